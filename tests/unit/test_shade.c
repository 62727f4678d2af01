/*
** The classic models (shade flat, gouraud, phong): where a mesh has hard
** edges (a cube's faces meet at 90 degrees, so each face shades with its
** own normal), gouraud honours them as phong does, so under a sun and
** without a highlight the three give the same faces.
*/
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "../../src/render/render.h"
#include "render_scenes.h"
#include "unit.h"

/* A cube and a cylinder (a smooth side with hard rims) in the given
** model, under a sun, no specular, aliased so that only the shading is
** compared. */
static Image *render_model(const char *model, GBuffer **g) {
  char text[2048];
  snprintf(text, sizeof text,
           "include \"shapes.npr\";\n"
           "output { background #000000; antialias false; }\n"
           "camera { position [4, -5, 3.5]; look_at [0, 0, 0.4]; fov 30; }\n"
           "light { direction [-0.4, 0.9, -0.7]; }\n"
           "style s { base #c08040; shade %s { ambient 0.1; } }\n"
           "object { geometry cube(1.4); style s; }\n"
           "object { geometry cylinder(0.5, 1.2); style s; transform translate([0, 1.6, 0]); }\n",
           model);
  Scene s;
  Arena ast;
  Image *img = NULL;
  *g = NULL;
  if (scene_from_text(&s, &ast, text)) {
    RenderOptions o = {.width = 120, .height = 90, .threads = 1};
    if (render_scene(&s, &o, &img, g) != 0) img = NULL;
  }
  scene_free(&s);
  arena_free(&ast);
  return img;
}

/* The largest channel difference between a and b over the cube (object
** 0) and the mean over the whole frame. */
static void compare(const Image *a, const Image *b, const GBuffer *g, double *cube_max, double *mean) {
  int n = a->width * a->height;
  *cube_max = 0;
  *mean = 0;
  for (int i = 0; i < n; i++) {
    double d = 0;
    for (int k = 0; k < 3; k++) d = fmax(d, fabs(a->data[i * a->channels + k] - b->data[i * b->channels + k]));
    *mean += d / n;
    if (g->object[i] == 0) *cube_max = fmax(*cube_max, d);
  }
}

TEST(gouraud_honours_hard_edges) {
  GBuffer *gg, *gp, *gf;
  Image *gouraud = render_model("gouraud", &gg), *phong = render_model("phong", &gp);
  Image *flat = render_model("flat", &gf);
  CHECK(gouraud && phong && flat);
  if (gouraud && phong && flat) {
    double cube, mean, cube_f, mean_f;
    compare(gouraud, phong, gp, &cube, &mean);
    compare(flat, phong, gp, &cube_f, &mean_f);
    /* a cube's faces are flat: one normal a face in all three */
    CHECK(cube < 1e-4);
    CHECK(cube_f < 1e-4);
    /* the cylinder's side is round: gouraud interpolates colours, phong
    ** normals, a little apart; far less than a face's colour across the
    ** rims */
    CHECK(mean < 2e-3);
    if (!(cube < 1e-4 && mean < 2e-3)) fprintf(stderr, "  gouraud vs phong: cube %g, mean %g\n", cube, mean);
  }
  image_destroy(gouraud);
  image_destroy(phong);
  image_destroy(flat);
  gbuf_destroy(gg);
  gbuf_destroy(gp);
  gbuf_destroy(gf);
}

int main(void) {
  RUN(gouraud_honours_hard_edges);
  return unit_done();
}
