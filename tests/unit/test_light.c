/*
** Lights: a spot's cone lands where its angle says, and its penumbra
** fades as the smoothstep the docs give.
*/
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../src/render/render.h"
#include "../../src/render/shade.h"
#include "render_scenes.h"
#include "unit.h"

/* Render scene text at its own size on threads workers into a float
** image (NULL after a failure). */
static Image *render_text(const char *text, int threads) {
  Scene s;
  Arena ast;
  Image *img = NULL;
  if (scene_from_text(&s, &ast, text)) {
    RenderOptions o = {.threads = threads};
    if (render_scene(&s, &o, &img, NULL) != 0) img = NULL;
  }
  scene_free(&s);
  arena_free(&ast);
  return img;
}

static float red_at(const Image *img, int x, int y) {
  return img->data[((size_t)y * img->width + x) * img->channels];
}

/* ---- spot lights ------------------------------------------------------------ */

/* A plane seen from straight above (ortho, 8 units across 256 pixels: 32
** pixels a unit), lit only by a spot at height h aiming straight down. */
static Image *spot_on_plane(double h, double cone, double penumbra) {
  char text[1024];
  snprintf(text, sizeof text,
           "include \"shapes.npr\";\n"
           "output { size [256, 256]; background #000000; }\n"
           "camera { position [0, 0, 10]; look_at [0, 0, 0]; up [0, 1, 0]; ortho 8; }\n"
           "light { position [0, 0, %g]; point_at [0, 0, 0]; cone %g; penumbra %g; }\n"
           "style s { base [1, 1, 1]; shade phong { ambient 0; } }\n"
           "object { geometry plane(20); style s; }\n",
           h, cone, penumbra);
  return render_text(text, 2);
}

/* The lit disc's radius along the centre row: pixels from the centre to
** the first dark one, as a distance in scene units of the pixel edge. */
static double lit_radius(const Image *img) {
  int cy = img->height / 2, cx = img->width / 2, x = cx;
  while (x < img->width && red_at(img, x, cy) > 0) x++;
  return (x - cx) / 32.0;   /* pixel x starts at (x - 128) / 32 units */
}

TEST(spot_cone_edge) {
  /* h tan(cone): 2 tan(30) = 1.1547 units, 36.9 pixels */
  for (int k = 0; k < 3; k++) {
    double h = 2 + k, cone = 20 + 10 * k;
    Image *img = spot_on_plane(h, cone, 0);
    CHECK(img != NULL);
    if (!img) return;
    CHECK_NEAR(lit_radius(img), h * tan(cone * M_PI / 180), 1.0 / 32);   /* within a pixel */
    /* the middle is lit by n.l = 1 */
    CHECK_NEAR(red_at(img, 128, 128), 1.0, 1e-3);
    image_destroy(img);
  }
}

TEST(spot_penumbra_smoothstep) {
  double h = 3, cone = 30, pen = 10;
  Image *img = spot_on_plane(h, cone, pen);
  CHECK(img != NULL);
  if (!img) return;
  double ce = cos(cone * M_PI / 180), ci = cos((cone - pen) * M_PI / 180);
  int checked = 0;
  for (int x = 128; x < 256; x++) {
    double r = (x + 0.5 - 128) / 32, d = sqrt(r * r + h * h);
    double c = h / d, t = (c - ce) / (ci - ce);   /* cos off the axis, n.l is c too */
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    double want = c * t * t * (3 - 2 * t);
    CHECK_NEAR(red_at(img, x, 128), want, 2e-3);
    checked += t > 0 && t < 1;
  }
  CHECK(checked > 10);   /* the fade spans pixels */
  image_destroy(img);
}

int main(void) {
  RUN(spot_cone_edge);
  RUN(spot_penumbra_smoothstep);
  return unit_done();
}
