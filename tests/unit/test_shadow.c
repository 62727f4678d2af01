/*
** Shadow maps: a square's shadow on a plane lands where the geometry puts
** it (within a pixel) under a sun, a spot and a point light (its cube map,
** across a face's border); lit surfaces do not shadow themselves; the
** filter widens the penumbra; the picture is the same at any thread count.
*/
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../src/render/render.h"
#include "../../src/render/shadow.h"
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

/* The frame: 320 x 320 pixels seen from straight above, orthographic,
** 10 units across (32 pixels a unit), centred on (cx, cy). */
#define PPU 32.0
#define SIDE 320

static double world_x(double cx, double px) { return cx + (px - SIDE / 2) / PPU; }
static double world_y(double cy, double py) { return cy - (py - SIDE / 2) / PPU; }

/* A square of side 2 centred over the origin at height h, over a floor
** plane, lit only by light (a light block's body), both shaded phong
** without ambient: lit floor = n.l, shadow = 0. */
static Image *square_scene(double cx, double cy, double h, const char *light, int threads) {
  char text[2048];
  snprintf(text, sizeof text,
           "include \"shapes.npr\";\n"
           "output { size [%d, %d]; background #000000; }\n"
           "camera { position [%g, %g, 20]; look_at [%g, %g, 0]; up [0, 1, 0]; ortho %g; }\n"
           "light { %s }\n"
           "style s { base [1, 1, 1]; shade phong { ambient 0; } }\n"
           "object { geometry plane(40); style s; }\n"
           "object { geometry plane(2); transform translate([0, 0, %g]); style s; }\n",
           SIDE, SIDE, cx, cy, cx, cy, SIDE / PPU, light, h);
  return render_text(text, threads);
}

/* Where along row y (or column x, when vertical) the picture crosses
** half of `lit` going from a to b (pixel indices, a < b or a > b): a
** world coordinate, linear between the pixel centres; NAN if it does not. */
static double crossing(const Image *img, int vertical, int line, int a, int b, double lit, double c0) {
  int step = b > a ? 1 : -1;
  for (int i = a; i != b; i += step) {
    float u = vertical ? red_at(img, line, i) : red_at(img, i, line);
    float v = vertical ? red_at(img, line, i + step) : red_at(img, i + step, line);
    double half = lit / 2;
    if ((u - half) * (v - half) <= 0 && u != v) {
      double t = (half - u) / (v - u), px = i + 0.5 + step * t;
      return vertical ? world_y(c0, px) : world_x(c0, px);
    }
  }
  return NAN;
}

/* ---- the sun ------------------------------------------------------------- */

/* A sun whose rays go (dx, dy, -1): the square at height h throws its
** shadow to [-1, 1] + h (dx, dy). */
static void check_sun(double dx, double dy, double h, int res, double filter) {
  char light[256];
  snprintf(light, sizeof light, "direction [%g, %g, -1]; shadow true; shadow_resolution %d; shadow_filter %g;",
           dx, dy, res, filter);
  double sx = h * dx, sy = h * dy;   /* the shadow's centre */
  Image *img = square_scene(sx, sy, h, light, 2);
  CHECK(img != NULL);
  if (!img) return;
  double lit = 1 / sqrt(dx * dx + dy * dy + 1);   /* n.l on the floor */
  int c = SIDE / 2;
  /* across the shadow's middle row, from outside in on both sides */
  double left = crossing(img, 0, c, 0, c, lit, sx), right = crossing(img, 0, c, SIDE - 1, c, lit, sx);
  double top = crossing(img, 1, c, 0, c, lit, sy), bottom = crossing(img, 1, c, SIDE - 1, c, lit, sy);
  CHECK_NEAR(left, sx - 1, 1 / PPU);
  CHECK_NEAR(right, sx + 1, 1 / PPU);
  CHECK_NEAR(top, sy + 1, 1 / PPU);
  CHECK_NEAR(bottom, sy - 1, 1 / PPU);
  /* the shadow's inside is dark, the floor outside it lit (no acne) past
  ** the filter's reach: a texel stretched on the floor (the map spans
  ** the 40-unit floor at most 57 units across, 1 / n.l) times half the
  ** filter and one more */
  double reach = (filter / 2 + 1) * 57.0 / res / lit;
  CHECK_NEAR(red_at(img, c, c), 0, 1e-6);
  int acne = 0;
  for (int y = 0; y < SIDE; y++)
    for (int x = 0; x < SIDE; x++) {
      double wx = world_x(sx, x + 0.5), wy = world_y(sy, y + 0.5);
      int near_shadow = fabs(wx - sx) < 1 + reach && fabs(wy - sy) < 1 + reach;
      int near_square = fabs(wx) < 1 + 2 / PPU && fabs(wy) < 1 + 2 / PPU;
      if (!near_shadow && !near_square) acne += fabs(red_at(img, x, y) - lit) > 1e-4;
    }
  CHECK_EQ_INT(acne, 0);
  image_destroy(img);
}

/* Within a pixel: an edge lands within half a texel (the map's texel
** centres) of its place, so a texel on the floor must be at most two
** pixels: 2048 texels over the floor seen from these suns. */
TEST(sun_shadow_edges) {
  check_sun(2, 0, 1.5, 2048, 2);      /* low sun along x: [2, 4] x [-1, 1] */
  check_sun(1.5, 1.2, 2, 2048, 2);    /* diagonal */
  check_sun(-2.5, 0.5, 1, 2048, 4);
  check_sun(0.6, 0.6, 4, 1024, 2);    /* higher sun, the default resolution */
}

/* ---- a spot and a point light ------------------------------------------- */

/* A light at (0, 0, H) over the square at height h: its shadow is the
** square scaled by H / (H - h) about the origin. */
static void check_point(const char *kind, double H, double h) {
  char light[256], bare[256];
  snprintf(light, sizeof light, "position [0, 0, %g]; %s shadow true; shadow_resolution 2048;", H, kind);
  snprintf(bare, sizeof bare, "position [0, 0, %g]; %s", H, kind);
  Image *img = square_scene(0, 0, h, light, 2), *lit_img = square_scene(0, 0, h, bare, 2);
  CHECK(img && lit_img);
  if (!img || !lit_img) {
    if (img) image_destroy(img);
    if (lit_img) image_destroy(lit_img);
    return;
  }
  double a = H / (H - h);   /* the shadow's half side */
  int c = SIDE / 2;
  /* n.l on the floor at (x, 0, 0): H / sqrt(x^2 + H^2); across the edge
  ** the lit side is the one outside */
  double lit = H / sqrt(a * a + H * H);
  double right = crossing(img, 0, c, SIDE - 1, c, lit, 0), left = crossing(img, 0, c, 0, c, lit, 0);
  double top = crossing(img, 1, c, 0, c, lit, 0);
  CHECK_NEAR(right, a, 1 / PPU);
  CHECK_NEAR(left, -a, 1 / PPU);
  CHECK_NEAR(top, a, 1 / PPU);
  CHECK_NEAR(red_at(img, c + (int)(0.5 * (a + 1) * PPU), c), 0, 1e-6);   /* between square and edge */
  /* off the shadow and its edge, the same light as without shadows: no
  ** acne, no seam between the cube's faces */
  int acne = 0;
  for (int y = 0; y < SIDE; y++)
    for (int x = 0; x < SIDE; x++) {
      double wx = world_x(0, x + 0.5), wy = world_y(0, y + 0.5);
      if (fabs(wx) < a + 3 / PPU && fabs(wy) < a + 3 / PPU) continue;
      acne += fabs(red_at(img, x, y) - red_at(lit_img, x, y)) > 1e-6;
    }
  CHECK_EQ_INT(acne, 0);
  image_destroy(img);
  image_destroy(lit_img);
}

TEST(spot_shadow_edges) { check_point("point_at [0, 0, 0]; cone 55; penumbra 0;", 4, 2); }

TEST(point_shadow_edges) {
  check_point("", 4, 2);     /* within the cube's -z face */
  check_point("", 3, 2);     /* the edges at 45 degrees: on the border of the -z and side faces */
}

/* ---- the filter and the threads ------------------------------------------ */

/* Pixels along the middle row whose value lies strictly between 10 % and
** 90 % of lit: the penumbra's width in pixels. */
static int penumbra_pixels(const Image *img, double lit) {
  int n = 0;
  for (int x = 0; x < SIDE; x++) {
    float v = red_at(img, x, SIDE / 2);
    n += v > 0.1 * lit && v < 0.9 * lit;
  }
  return n;
}

TEST(filter_widens_penumbra) {
  /* 256 texels over the 40-unit floor: a texel is ~5 pixels */
  Image *a = square_scene(3, 0, 1.5, "direction [2, 0, -1]; shadow true; shadow_resolution 256; shadow_filter 2;", 2);
  Image *b = square_scene(3, 0, 1.5, "direction [2, 0, -1]; shadow true; shadow_resolution 256; shadow_filter 8;", 2);
  CHECK(a && b);
  if (a && b) {
    double lit = 1 / sqrt(5.0);
    int na = penumbra_pixels(a, lit), nb = penumbra_pixels(b, lit);
    CHECK(na > 2);             /* two edges, each a filter's width of texels */
    CHECK(nb > 3 * na);        /* 8 texels against 2 */
    CHECK(nb < 5 * na);
  }
  if (a) image_destroy(a);
  if (b) image_destroy(b);
}

TEST(same_at_any_thread_count) {
  const char *light = "position [1, -1, 5]; point_at [0, 0, 0]; cone 40; shadow true; shadow_filter 3;";
  Image *one = square_scene(0, 0, 1.5, light, 1);
  CHECK(one != NULL);
  if (!one) return;
  for (int t = 2; t <= 5; t += 3) {
    Image *other = square_scene(0, 0, 1.5, light, t);
    CHECK(other != NULL);
    if (!other) continue;
    size_t n = (size_t)one->width * one->height * one->channels;
    CHECK(memcmp(one->data, other->data, n * sizeof *one->data) == 0);
    image_destroy(other);
  }
  image_destroy(one);
}

int main(void) {
  RUN(sun_shadow_edges);
  RUN(spot_shadow_edges);
  RUN(point_shadow_edges);
  RUN(filter_widens_penumbra);
  RUN(same_at_any_thread_count);
  return unit_done();
}
