/*
** Antialiasing by coverage (render/antialias.h, toon's steps): at one
** sample a pixel, the default frame comes close to the same frame
** supersampled 8 x 8 (the box filter the coverage stands for) at object
** outlines against the background and against other objects, at hard
** edges, where surfaces pass through each other, and at toon band,
** highlight and edge borders; without it, the error is several times as
** large. Same bytes at any thread count is in test_raster.
*/
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../src/render/render.h"
#include "render_scenes.h"
#include "unit.h"

/* Render scene text (with `let aa = ...; let n = ...;` prepended) at
** W x H; NULL when it does not evaluate or render. */
static Image *render_text(const char *scene, int aa, int samples, int w, int h) {
  char text[4096];
  snprintf(text, sizeof text, "let aa = %s;\nlet n = %d;\n%s", aa ? "true" : "false", samples, scene);
  Scene s;
  Arena ast;
  Image *img = NULL;
  if (scene_from_text(&s, &ast, text)) {
    RenderOptions o = {.width = w, .height = h, .threads = 2};
    if (render_scene(&s, &o, &img, NULL) != 0) img = NULL;
  }
  scene_free(&s);
  arena_free(&ast);
  return img;
}

/* Mean over the pixels of the largest channel difference, in sRGB
** (display) units, between a and b. */
static double mean_error(const Image *a, const Image *b) {
  double sum = 0;
  int n = a->width * a->height, c = a->channels;
  for (int i = 0; i < n; i++) {
    double worst = 0;
    for (int k = 0; k < 3; k++) {
      double d = fabs((double)image_linear_to_srgb8(a->data[i * c + k]) - image_linear_to_srgb8(b->data[i * c + k])) / 255;
      worst = d > worst ? d : worst;
    }
    sum += worst;
  }
  return sum / n;
}

/* The default frame and the aliased one against the supersampled: the
** antialiased error must be under `ratio` times the aliased one. */
static void check_against_supersampled(const char *scene, double ratio) {
  enum { W = 96, H = 72 };
  Image *ref = render_text(scene, 0, 8, W, H), *aa = render_text(scene, 1, 1, W, H);
  Image *hard = render_text(scene, 0, 1, W, H);
  CHECK(ref && aa && hard);
  if (ref && aa && hard) {
    double e_aa = mean_error(aa, ref), e_hard = mean_error(hard, ref);
    if (!(e_aa < ratio * e_hard))
      fprintf(stderr, "  error against 8x8 samples: antialiased %.5f, aliased %.5f\n", e_aa, e_hard);
    CHECK(e_hard > 0.002);   /* the scene has edges to smooth */
    CHECK(e_aa < ratio * e_hard);
  }
  image_destroy(ref);
  image_destroy(aa);
  image_destroy(hard);
}

/* A toon sphere on white: its outline against the background, and its
** diffuse bands, highlight and n.v edge, each a step inside the object. */
TEST(outline_and_bands) {
  check_against_supersampled(
      "include \"shapes.npr\";\n"
      "output { background #ffffff; antialias aa; samples n; }\n"
      "camera { position [0, -6, 1.5]; look_at [0, 0, 0]; fov 25; }\n"
      "light { direction [1, 1.2, -1.5]; }\n"
      "style s { base #3a6ea5; shade toon { bands 4; specular 0.6; shininess 30; edge 0.3; edge_color #101010; } }\n"
      "object { geometry sphere(1); style s; }\n",
      0.25);
}

/* Flat-shaded cubes, one in front of the other and turned: outlines
** against another object, and the hard edges between their faces. */
TEST(objects_and_hard_edges) {
  check_against_supersampled(
      "include \"shapes.npr\";\n"
      "output { background #202020; antialias aa; samples n; }\n"
      "camera { position [4, -6, 3]; look_at [0, 0, 0.3]; fov 30; }\n"
      "style a { base #d08040; shade flat { } }\n"
      "style b { base #40a0d0; shade flat { } }\n"
      "object { geometry cube(1.6); style a; transform rotate([0, 0, 20]); }\n"
      "object { geometry cube(1); style b; transform translate([0.6, -1.3, 0.4]) * rotate([10, 30, 40]); }\n",
      0.25);
}

/* Two planes crossing, their borders out of view: the only edge is the
** line where they pass through each other, which belongs to neither
** mesh's outline. */
TEST(surfaces_through_each_other) {
  check_against_supersampled(
      "include \"shapes.npr\";\n"
      "output { background #ffffff; antialias aa; samples n; }\n"
      "camera { position [2, -6, 3]; look_at [0, 0, 0]; fov 30; }\n"
      "style a { base #e0e0e0; shade flat { } }\n"
      "style b { base #c03030; shade flat { } }\n"
      "object { geometry plane(60); style a; }\n"
      "object { geometry plane(60); style b; transform rotate([50, 0, 25]); }\n",
      0.25);
}

int main(void) {
  RUN(outline_and_bands);
  RUN(objects_and_hard_edges);
  RUN(surfaces_through_each_other);
  return unit_done();
}
