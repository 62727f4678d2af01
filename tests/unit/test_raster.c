/*
** Rasterizer and frame pipeline facts: the top-left fill rule covers every
** sample of a shared-edge mesh exactly once, barycentrics are perspective
** correct (through near-plane clipping too), the depth test keeps the
** nearest surface, automatic framing keeps the scene in view, and the
** rendered image is byte-identical at 1, 2 and 8 threads.
*/
#include <stdlib.h>
#include <string.h>

#include "../../src/base/mem.h"
#include "../../src/render/camera.h"
#include "../../src/render/gbuffer.h"
#include "../../src/render/raster.h"
#include "../../src/render/render.h"
#include "render_scenes.h"
#include "unit.h"

/* ---- helpers ---------------------------------------------------------------- */

enum { W = 64, H = 48 };

/* Planes for a W x H target and a fragment counter. */
typedef struct Target {
  float depth[W * H];
  int32_t object[W * H], face[W * H];
  float bary[W * H][2];
  uint16_t count[W * H];
  RastTarget rt;
} Target;

static void target_init(Target *t) {
  for (int i = 0; i < W * H; i++) {
    t->depth[i] = GBUF_NO_DEPTH;
    t->object[i] = t->face[i] = -1;
    t->bary[i][0] = t->bary[i][1] = 0;
    t->count[i] = 0;
  }
  t->rt = (RastTarget){0, 0, W, H, 0, 0, W, t->depth, t->object, t->face, t->bary, t->count};
}

/* A vertex at pixel position (x, y) and depth z for the W x H target,
** through clip space with w = 1 (an orthographic projection). */
static void pixel_clip(double clip[4], double x, double y, double z) {
  clip[0] = 2 * x / W - 1, clip[1] = 1 - 2 * y / H, clip[2] = 2 * z - 1, clip[3] = 1;
}

static void pixel_vertex(RastVert *v, double x, double y, double z) {
  double clip[4];
  pixel_clip(clip, x, y, z);
  rast_vertex(v, clip, W, H);
}

/* Draw triangle (a, b, c) of vs into t, as the pipeline does; clip holds
** the vertices' clip coordinates (NULL: none of them needs clipping). */
static void draw_clip(Target *t, const RastVert *vs, const double (*clip)[4], int a, int b, int c, int face) {
  RastTriList list = {0};
  const RastVert *tv[3] = {&vs[a], &vs[b], &vs[c]};
  const double *const h[3] = {clip ? clip[a] : NULL, clip ? clip[b] : NULL, clip ? clip[c] : NULL};
  CHECK(clip || !rast_needs_clip(tv));
  rast_emit(&list, tv, h, 0, face, W, H);
  for (int i = 0; i < list.n; i++) rast_triangle(&list.tris[i], &t->rt);
  rast_list_free(&list);
}

static void draw(Target *t, const RastVert *vs, int a, int b, int c, int face) {
  draw_clip(t, vs, NULL, a, b, c, face);
}

/* A deterministic value in [0, 1) from an integer (no global state). */
static double hash01(unsigned k) {
  k ^= k >> 16; k *= 0x7feb352dU; k ^= k >> 15; k *= 0x846ca68bU; k ^= k >> 16;
  return (k & 0xffffff) / (double)0x1000000;
}

/* ---- fill rule -------------------------------------------------------------- */

/* A grid of quads over [x0, x1] x [y0, y1], each split along a diagonal
** that alternates, interior vertices jittered (or snapped to sample
** centres and pixel corners, where ties happen), triangles drawn in both
** windings. Every sample whose centre is strictly inside the outline is
** covered exactly once; no sample outside is covered. */
static void check_grid(int jitter_kind) {
  enum { NX = 9, NY = 7 };
  const double x0 = 3.3, x1 = 60.7, y0 = 2.6, y1 = 45.2;
  RastVert vs[(NX + 1) * (NY + 1)];
  for (int j = 0; j <= NY; j++)
    for (int i = 0; i <= NX; i++) {
      double x = x0 + (x1 - x0) * i / NX, y = y0 + (y1 - y0) * j / NY;
      int interior = i > 0 && i < NX && j > 0 && j < NY;
      if (interior && jitter_kind == 1) {   /* random jitter, up to +-2 px */
        x += 4 * hash01(j * 131 + i) - 2;
        y += 4 * hash01(j * 977 + i + 7) - 2;
      } else if (interior && jitter_kind == 2) {   /* on sample centres: edges pass through them */
        x = floor(x) + 0.5;
        y = floor(y) + 0.5;
      } else if (interior && jitter_kind == 3) {   /* on pixel corners */
        x = floor(x);
        y = floor(y);
      }
      pixel_vertex(&vs[j * (NX + 1) + i], x, y, 0.25 + 0.5 * hash01(i * 31 + j));
    }
  Target *t = xmalloc(sizeof *t);
  target_init(t);
  int face = 0;
  for (int j = 0; j < NY; j++)
    for (int i = 0; i < NX; i++) {
      int a = j * (NX + 1) + i, b = a + 1, c = a + NX + 1, d = c + 1;
      int flip = (i + j) & 1;   /* alternate the diagonal and the winding */
      if (flip) { draw(t, vs, a, b, d, face++); draw(t, vs, a, c, d, face++); }
      else { draw(t, vs, a, b, c, face++); draw(t, vs, b, d, c, face++); }
    }
  int bad_inside = 0, bad_outside = 0, twice = 0;
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      double cx = x + 0.5, cy = y + 0.5;
      int inside = cx > x0 && cx < x1 && cy > y0 && cy < y1;
      int n = t->count[y * W + x];
      if (n > 1) twice++;
      if (inside && n != 1) bad_inside++;
      if (!inside && n != 0) bad_outside++;
    }
  CHECK_EQ_INT(twice, 0);
  CHECK_EQ_INT(bad_inside, 0);
  CHECK_EQ_INT(bad_outside, 0);
  free(t);
}

TEST(fill_rule_regular_grid) { check_grid(0); }
TEST(fill_rule_jittered_grid) { check_grid(1); }
TEST(fill_rule_vertices_on_sample_centres) { check_grid(2); }
TEST(fill_rule_vertices_on_pixel_corners) { check_grid(3); }

/* A fan of 24 thin triangles around a vertex on a sample centre: the
** centre sample belongs to exactly one of them, and so does every sample
** the fan covers. */
TEST(fill_rule_fan_around_sample_centre) {
  enum { NF = 24 };
  RastVert vs[NF + 1];
  double cx = 32.5, cy = 24.5, r = 20;
  pixel_vertex(&vs[0], cx, cy, 0.5);
  for (int k = 0; k < NF; k++) {
    double a = 2 * M_PI * k / NF;
    pixel_vertex(&vs[k + 1], cx + r * cos(a), cy + r * sin(a), 0.5);
  }
  Target *t = xmalloc(sizeof *t);
  target_init(t);
  for (int k = 0; k < NF; k++) draw(t, vs, 0, 1 + k, 1 + (k + 1) % NF, k);
  CHECK_EQ_INT(t->count[24 * W + 32], 1);
  int twice = 0, covered = 0;
  for (int i = 0; i < W * H; i++) {
    twice += t->count[i] > 1;
    covered += t->count[i] == 1;
  }
  CHECK_EQ_INT(twice, 0);
  /* the 24-gon's area, give or take its perimeter in samples */
  double area = 0.5 * NF * r * r * sin(2 * M_PI / NF);
  CHECK(fabs(covered - area) < 2 * M_PI * r);
  free(t);
}

/* A quad reaching a million pixels past the image (clipped against the
** guard band), split by a diagonal that crosses the image: every sample
** is covered exactly once, by the triangle on its side of the diagonal. */
TEST(fill_rule_through_guard_band_clipping) {
  RastVert vs[4];
  double big = 1e6, clip[4][4];
  pixel_clip(clip[0], -big, -big * 0.7, 0.5);
  pixel_clip(clip[1], big, -big, 0.5);
  pixel_clip(clip[2], big * 0.9, big, 0.5);
  pixel_clip(clip[3], -big, big, 0.5);
  for (int i = 0; i < 4; i++) rast_vertex(&vs[i], clip[i], W, H);
  CHECK(vs[0].outcode && vs[2].outcode);
  Target *t = xmalloc(sizeof *t);
  target_init(t);
  draw_clip(t, vs, (const double(*)[4])clip, 0, 1, 2, 0);
  draw_clip(t, vs, (const double(*)[4])clip, 0, 2, 3, 1);
  int once = 0, side_ok = 0;
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      int i = y * W + x;
      once += t->count[i] == 1;
      /* the side of the diagonal v0 -> v2 the sample centre is on */
      double ex = big * 0.9 + big, ey = big + big * 0.7;
      double side = ex * (y + 0.5 + big * 0.7) - ey * (x + 0.5 + big);
      side_ok += (side < 0) == (t->face[i] == 0) || fabs(side) < 1e-3 * big;
    }
  CHECK_EQ_INT(once, W * H);
  CHECK_EQ_INT(side_ok, W * H);
  free(t);
}

/* ---- depth and barycentrics --------------------------------------------------- */

/* Two overlapping triangles: the nearer wins whatever the drawing order,
** and equal depths keep the first drawn. */
TEST(depth_test_keeps_nearest) {
  RastVert vs[6];
  pixel_vertex(&vs[0], 2, 2, 0.7); pixel_vertex(&vs[1], 60, 2, 0.7); pixel_vertex(&vs[2], 2, 46, 0.7);
  pixel_vertex(&vs[3], 2, 2, 0.3); pixel_vertex(&vs[4], 60, 2, 0.3); pixel_vertex(&vs[5], 2, 46, 0.3);
  Target *t = xmalloc(sizeof *t);
  for (int order = 0; order < 2; order++) {
    target_init(t);
    if (order == 0) { draw(t, vs, 0, 1, 2, 1); draw(t, vs, 3, 4, 5, 2); }
    else { draw(t, vs, 3, 4, 5, 2); draw(t, vs, 0, 1, 2, 1); }
    CHECK_EQ_INT(t->face[10 * W + 10], 2);
    CHECK_NEAR(t->depth[10 * W + 10], 0.3, 1e-6);
  }
  target_init(t);
  draw(t, vs, 0, 1, 2, 7);
  draw(t, vs, 0, 1, 2, 8);   /* same depth: the first stays */
  CHECK_EQ_INT(t->face[10 * W + 10], 7);
  free(t);
}

/* A quad tilted steeply away from a perspective camera: every sample's
** barycentrics rebuild a 3D point that projects back onto the sample
** centre. Screen-linear (affine) interpolation misses by pixels here. */
static void check_perspective_quad(double near_cut) {
  Camera cam;
  const char *why = NULL;
  SceneCamera sc = {0};
  sc.present = 1;
  sc.kind = CAMERA_PERSPECTIVE;
  sc.position = v3(0, -1, 1);
  sc.look_at = v3(0, 6, 0);
  sc.fov = 60;
  CHECK(camera_setup(&cam, &sc, W, H, v3(-3, -0.5 + near_cut, 0), v3(3, 20, 0.1), 0, &why));
  /* the quad: z = 0, x in [-3, 3], y from -0.5 + near_cut (close, or
  ** behind the camera at y = -1) to 20 (far) */
  double yn = -0.5 + near_cut;
  Vec3 q[4] = {v3(-3, yn, 0), v3(3, yn, 0), v3(-3, 20, 0), v3(3, 20, 0)};
  int tris[2][3] = {{0, 1, 3}, {0, 3, 2}};
  RastVert vs[4];
  double clip[4][4];
  for (int i = 0; i < 4; i++) {
    camera_to_clip(&cam, q[i], clip[i]);
    rast_vertex(&vs[i], clip[i], W, H);
  }
  Target *t = xmalloc(sizeof *t);
  target_init(t);
  for (int k = 0; k < 2; k++) draw_clip(t, vs, (const double(*)[4])clip, tris[k][0], tris[k][1], tris[k][2], k);
  int covered = 0, off = 0, affine_off = 0;
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      int i = y * W + x;
      if (t->face[i] < 0) continue;
      covered++;
      const int *tr = tris[t->face[i]];
      double b1 = t->bary[i][0], b2 = t->bary[i][1], b0 = 1 - b1 - b2;
      Vec3 p = v3_add(v3_add(v3_mul(q[tr[0]], b0), v3_mul(q[tr[1]], b1)), v3_mul(q[tr[2]], b2));
      double px, py, depth;
      CHECK(camera_to_pixel(&cam, p, &px, &py, &depth));
      if (fabs(px - (x + 0.5)) > 0.01 || fabs(py - (y + 0.5)) > 0.01) off++;
      CHECK_NEAR(depth, t->depth[i], 1e-4);
      if (near_cut != 0) continue;
      /* the same point by screen-linear weights would sit elsewhere */
      double sx[3], sy[3], sd;
      for (int k = 0; k < 3; k++) camera_to_pixel(&cam, q[tr[k]], &sx[k], &sy[k], &sd);
      double det = (sx[1] - sx[0]) * (sy[2] - sy[0]) - (sx[2] - sx[0]) * (sy[1] - sy[0]);
      double l1 = ((x + 0.5 - sx[0]) * (sy[2] - sy[0]) - (sx[2] - sx[0]) * (y + 0.5 - sy[0])) / det;
      if (fabs(l1 - b1) > 0.05) affine_off++;
    }
  CHECK(covered > W * H / 4);
  CHECK_EQ_INT(off, 0);
  if (near_cut == 0) CHECK(affine_off > covered / 10);   /* the test can tell the two apart */
  free(t);
}

TEST(perspective_correct_barycentrics) { check_perspective_quad(0); }

/* The same quad reaching behind the camera: it is clipped at the near
** plane, and the samples still carry the source triangle's barycentrics. */
TEST(near_plane_clipping_keeps_barycentrics) { check_perspective_quad(-5); }

/* ---- camera ------------------------------------------------------------------- */

/* Automatic framing: the 8 corners of the box land inside the image, and
** the box is not lost in it (it spans most of one side). */
TEST(auto_camera_frames_box) {
  Camera c;
  const char *why = NULL;
  SceneCamera none = {0};
  Vec3 lo = v3(-1, -2, 0), hi = v3(3, 1, 2.5);
  CHECK(camera_setup(&c, &none, 320, 200, lo, hi, 0, &why));
  double xmin = 1e9, xmax = -1e9, ymin = 1e9, ymax = -1e9;
  for (int i = 0; i < 8; i++) {
    Vec3 q = v3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
    double x, y, d;
    CHECK(camera_to_pixel(&c, q, &x, &y, &d));
    CHECK(d > 0 && d < 1);
    xmin = fmin(xmin, x); xmax = fmax(xmax, x); ymin = fmin(ymin, y); ymax = fmax(ymax, y);
  }
  CHECK(xmin >= 0 && xmax <= 320 && ymin >= 0 && ymax <= 200);
  CHECK(xmax - xmin > 0.85 * 320 || ymax - ymin > 0.85 * 200);
  /* seen from (1, -2, 1): the camera looks the opposite way */
  CHECK_NEAR(v3_dot(c.forward, v3_norm(v3(-1, 2, -1))), 1, 1e-12);
  /* and the box is centred (exactly along the side it fills) */
  CHECK_NEAR((xmin + xmax) / 2, 160, 4);
  CHECK_NEAR((ymin + ymax) / 2, 100, 4);
  /* origami alone: from +z, orthographic, +y up */
  CHECK(camera_setup(&c, &none, 100, 100, v3(0, 0, 0), v3(2, 1, 0), 1, &why));
  CHECK(c.kind == CAMERA_ORTHO);
  CHECK_NEAR(c.up.y, 1, 1e-12);
  CHECK_NEAR(c.forward.z, -1, 1e-12);
}

TEST(unproject_inverts_projection) {
  Camera c;
  const char *why = NULL;
  SceneCamera sc = {0};
  sc.present = 1;
  sc.position = v3(4, -6, 3);
  sc.look_at = v3(0, 0, 1);
  sc.up = v3(0, 0, 1);
  sc.fov = 35;
  CHECK(camera_setup(&c, &sc, 200, 100, v3(-1, -1, 0), v3(1, 1, 2), 0, &why));
  Vec3 p = v3(0.3, -0.2, 1.4);
  double x, y, d;
  CHECK(camera_to_pixel(&c, p, &x, &y, &d));
  Vec3 r = camera_unproject(&c, x, y, d);
  CHECK_NEAR(r.x, p.x, 1e-6);
  CHECK_NEAR(r.y, p.y, 1e-6);
  CHECK_NEAR(r.z, p.z, 1e-6);
  sc.position = sc.look_at;
  CHECK(!camera_setup(&c, &sc, 200, 100, v3(-1, -1, 0), v3(1, 1, 2), 0, &why));
}

/* ---- the pipeline --------------------------------------------------------------- */

/* Three overlapping spheres, each in its own style, one light. */
static void build_scene(Scene *s, ShadeKind kind) {
  memset(s, 0, sizeof *s);
  arena_init(&s->arena);
  s->output.width = 160;
  s->output.height = 96;
  s->output.samples = 2;
  s->output.background = (Color){0.9f, 0.85f, 0.7f, 1};
  s->nstyles = 3;
  s->styles = arena_alloc(&s->arena, sizeof *s->styles * 3);
  for (int i = 0; i < 3; i++) {
    SceneStyle *st = &s->styles[i];
    st->base = (Color){0.2f + 0.3f * i, 0.5f, 0.8f - 0.3f * i, 1};
    st->shade.kind = kind;
    st->shade.toon = (ShadeToon){.bands = 3, .threshold = 0.5, .specular = 0.5, .shininess = 20,
                                 .specular_bands = 2, .specular_threshold = 0.5, .ambient = 0.1,
                                 .edge = 0.25, .edge_color = {0, 0, 0, 1}};
  }
  s->nlights = 1;
  s->lights = arena_alloc(&s->arena, sizeof *s->lights);
  s->lights[0] = (SceneLight){.kind = LIGHT_POINT, .position = v3(5, -8, 9), .color = {1, 1, 1, 1},
                              .strength = 1};
  s->nobjects = 3;
  s->objects = arena_alloc(&s->arena, sizeof *s->objects * 3);
  for (int i = 0; i < 3; i++) {
    SceneObject *o = &s->objects[i];
    o->geometry = sphere_geometry(&s->arena, v3(1.2 * i, 0.4 * i, 0), 1, 24, 12);
    o->transform = i == 2 ? m4_scale(v3(-1, 1, 1)) : m4_identity();   /* one mirrored */
    o->style = i;
  }
}

/* The frame at 1, 2 and 8 threads, with a whole G-buffer kept or per
** tile, float or 8-bit: the same bytes, antialiased (aa) or not. */
static void check_identical_bytes(int aa) {
  Scene s;
  build_scene(&s, SHADE_TOON);
  s.output.antialias = aa;
  Image *img[3];
  GBuffer *gb[3];
  int threads[3] = {1, 2, 8};
  for (int k = 0; k < 3; k++) {
    RenderOptions o = {.threads = threads[k]};
    CHECK_EQ_INT(render_scene(&s, &o, &img[k], &gb[k]), 0);
  }
  CHECK_EQ_INT(img[0]->channels, 3);   /* opaque background: RGB */
  size_t n = (size_t)img[0]->width * img[0]->height * img[0]->channels * sizeof(float);
  size_t ns = (size_t)gb[0]->width * gb[0]->height;
  for (int k = 1; k < 3; k++) {
    CHECK(memcmp(img[0]->data, img[k]->data, n) == 0);
    CHECK(memcmp(gb[0]->depth, gb[k]->depth, ns * sizeof(float)) == 0);
    CHECK(memcmp(gb[0]->face, gb[k]->face, ns * sizeof(int32_t)) == 0);
  }
  /* the scene is really there: all three objects show, and the background */
  int seen[4] = {0};
  for (size_t i = 0; i < ns; i++) seen[gb[0]->object[i] + 1] = 1;
  CHECK(seen[0] && seen[1] && seen[2] && seen[3]);
  /* the full G-buffer path and the per-tile path give the same image */
  Image *tiles;
  RenderOptions o = {.threads = 2};
  CHECK_EQ_INT(render_scene(&s, &o, &tiles, NULL), 0);
  CHECK(memcmp(img[0]->data, tiles->data, n) == 0);
  image_destroy(tiles);
  /* bound for an 8-bit file, at 1 and 2 threads: the codes image_write
  ** would have made of the float frame */
  size_t npix = (size_t)img[0]->width * img[0]->height;
  uint8_t *want = malloc(npix * 3);
  image_to_srgb8(img[0], want);
  for (int t = 1; t <= 2; t++) {
    Image *img8;
    RenderOptions o8 = {.threads = t, .out8 = 1};
    CHECK_EQ_INT(render_scene(&s, &o8, &img8, NULL), 0);
    CHECK(img8->data == NULL && img8->data8 != NULL);
    CHECK(memcmp(want, img8->data8, npix * 3) == 0);
    image_destroy(img8);
  }
  free(want);
  for (int k = 0; k < 3; k++) { image_destroy(img[k]); gbuf_destroy(gb[k]); }
  arena_free(&s.arena);
}

TEST(identical_bytes_at_1_2_8_threads) { check_identical_bytes(0); }
TEST(identical_bytes_at_1_2_8_threads_antialiased) { check_identical_bytes(1); }

/* One sample a pixel in a wide frame: the tiles beside the spheres hold no
** triangle and are written as background straight away (render.c). The
** image is the one the full G-buffer path makes, which clears and reads
** every tile, in float and in 8-bit codes, at 1 and 2 threads. */
TEST(empty_tiles_give_the_background) {
  Scene s;
  build_scene(&s, SHADE_TOON);
  s.output.samples = 1;
  s.output.width = 640;   /* the spheres in the middle, background tiles at the sides */
  Image *full;
  GBuffer *gb;
  RenderOptions o = {.threads = 1};
  CHECK_EQ_INT(render_scene(&s, &o, &full, &gb), 0);
  int empty_cols = 0;   /* leading columns with nothing drawn: at least one tile's width */
  for (int x = 0, clear = 1; x < gb->width && clear; x++) {
    for (int y = 0; y < gb->height; y++) clear &= gb->object[y * gb->width + x] < 0;
    empty_cols += clear;
  }
  CHECK(empty_cols >= 2 * RENDER_TILE);
  size_t npix = (size_t)full->width * full->height;
  uint8_t *want = malloc(npix * 3);
  image_to_srgb8(full, want);
  for (int t = 1; t <= 2; t++) {
    Image *tiles, *img8;
    RenderOptions of = {.threads = t}, o8 = {.threads = t, .out8 = 1};
    CHECK_EQ_INT(render_scene(&s, &of, &tiles, NULL), 0);
    CHECK(memcmp(full->data, tiles->data, npix * 3 * sizeof(float)) == 0);
    CHECK_EQ_INT(render_scene(&s, &o8, &img8, NULL), 0);
    CHECK(memcmp(want, img8->data8, npix * 3) == 0);
    image_destroy(tiles);
    image_destroy(img8);
  }
  free(want);
  image_destroy(full);
  gbuf_destroy(gb);
  arena_free(&s.arena);
}

/* A closed sphere seen whole shows no background inside its outline, and
** its G-buffer normals face the viewer (two-sided shading never needed). */
TEST(closed_mesh_has_no_cracks) {
  Scene s;
  build_scene(&s, SHADE_PHONG);
  s.nobjects = 1;
  s.output.samples = 1;
  s.output.width = s.output.height = 200;
  Image *img;
  GBuffer *gb;
  RenderOptions o = {.threads = 2};
  CHECK_EQ_INT(render_scene(&s, &o, &img, &gb), 0);
  /* every background sample must be reachable from the image border */
  int w = gb->width, h = gb->height, holes = 0, covered = 0;
  double nv = 0;
  for (int y = 1; y < h - 1; y++)
    for (int x = 1; x < w - 1; x++) {
      int i = y * w + x;
      if (gb->object[i] >= 0) {
        Vec3 p = v3(gb->position[i][0], gb->position[i][1], gb->position[i][2]);
        Vec3 v = camera_view_dir(&gb->camera, p);
        nv += v.x * gb->normal[i][0] + v.y * gb->normal[i][1] + v.z * gb->normal[i][2];
        covered++;
        continue;
      }
      /* a background sample with object samples left and right and above
      ** and below, within the sphere's outline, is a crack */
      int l = 0, r = 0, u = 0, d = 0;
      for (int k = x - 1; k >= 0 && !l; k--) l = gb->object[y * w + k] >= 0;
      for (int k = x + 1; k < w && !r; k++) r = gb->object[y * w + k] >= 0;
      for (int k = y - 1; k >= 0 && !u; k--) u = gb->object[k * w + x] >= 0;
      for (int k = y + 1; k < h && !d; k++) d = gb->object[k * w + x] >= 0;
      holes += l && r && u && d;
    }
  CHECK_EQ_INT(holes, 0);
  /* normals face the viewer: n.v averages 2/3 over a sphere's disc */
  CHECK(covered > 1000);
  CHECK_NEAR(nv / covered, 2.0 / 3.0, 0.03);
  image_destroy(img);
  gbuf_destroy(gb);
  arena_free(&s.arena);
}

/* Drop the face of g whose centre lies farthest along dir (its indices
** removed: tess_polygons skips a face without corners). */
static void drop_face_toward(Scene *s, SceneGeometry *g, Vec3 dir) {
  int drop = 0;
  double best = -1e9;
  for (int k = 0; k < g->nfaces; k++) {
    Vec3 c = v3(0, 0, 0);
    int nk = g->face_start[k + 1] - g->face_start[k];
    for (int j = g->face_start[k]; j < g->face_start[k + 1]; j++) c = v3_add(c, v3_mul(g->verts[g->face_index[j]], 1.0 / nk));
    if (v3_dot(c, dir) > best) { best = v3_dot(c, dir); drop = k; }
  }
  int *saved = arena_alloc(&s->arena, sizeof *saved * g->face_start[g->nfaces]);
  memcpy(saved, g->face_index, sizeof *saved * g->face_start[g->nfaces]);
  int m = 0;
  for (int k = 0; k < g->nfaces; k++) {
    int a = g->face_start[k], b = g->face_start[k + 1];
    g->face_start[k] = m;
    if (k == drop) continue;
    for (int j = a; j < b; j++) g->face_index[m++] = saved[j];
  }
  g->face_start[g->nfaces] = m;
}

/* Back faces are skipped only where they cannot show: a closed, outward
** mesh seen from outside. Inside it, or turned inside out, or opened,
** every face is drawn. Skipping never changes a visible sample. */
TEST(back_face_culling_only_when_hidden) {
  Scene s;
  build_scene(&s, SHADE_PHONG);
  s.nobjects = 1;
  s.output.samples = 1;
  RenderOptions o = {.threads = 2};
  RenderFrame f;
  CHECK(render_prepare(&s, &o, &f));
  CHECK_EQ_INT(f.objects[0].cull_back, 1);
  Vec3 toward = v3_mul(f.camera.forward, -1);
  render_frame_free(&f);
  GBuffer *gc, *go;
  Image *closed, *open;
  CHECK_EQ_INT(render_scene(&s, &o, &closed, &gc), 0);
  /* opened: the face farthest from the camera dropped; every face is drawn
  ** then, and the picture is the same */
  drop_face_toward(&s, s.objects[0].geometry, v3_mul(toward, -1));
  CHECK(render_prepare(&s, &o, &f));
  CHECK_EQ_INT(f.objects[0].cull_back, 0);
  render_frame_free(&f);
  CHECK_EQ_INT(render_scene(&s, &o, &open, &go), 0);
  /* (triangle numbers shift with the dropped face: compare what shows) */
  int differ = 0;
  for (int i = 0; i < gc->width * gc->height; i++)
    differ += gc->object[i] != go->object[i] || memcmp(&closed->data[i * 3], &open->data[i * 3], 3 * sizeof(float)) != 0;
  CHECK(differ <= 2);   /* at most a sample on the outline */
  /* inside out (every face reversed): not culled */
  SceneGeometry *g = s.objects[0].geometry;
  for (int k = 0; k < g->nfaces; k++)
    for (int a = g->face_start[k], b = g->face_start[k + 1] - 1; a < b; a++, b--) {
      int t = g->face_index[a]; g->face_index[a] = g->face_index[b]; g->face_index[b] = t;
    }
  CHECK(render_prepare(&s, &o, &f));
  CHECK_EQ_INT(f.objects[0].cull_back, 0);
  render_frame_free(&f);
  /* from inside the sphere: not culled, and its inside fills the view */
  s.camera = (SceneCamera){.present = 1, .kind = CAMERA_PERSPECTIVE, .position = v3(0, 0, 0),
                           .look_at = v3(1, 0, 0), .up = v3(0, 0, 1), .fov = 60};
  CHECK(render_prepare(&s, &o, &f));
  CHECK_EQ_INT(f.objects[0].cull_back, 0);
  render_frame_free(&f);
  GBuffer *gi;
  Image *inside;
  CHECK_EQ_INT(render_scene(&s, &o, &inside, &gi), 0);
  int empty = 0;
  for (int i = 0; i < gi->width * gi->height; i++) empty += gi->object[i] < 0;
  CHECK_EQ_INT(empty, 0);
  image_destroy(closed);
  image_destroy(open);
  image_destroy(inside);
  gbuf_destroy(gc);
  gbuf_destroy(go);
  gbuf_destroy(gi);
  arena_free(&s.arena);
}

/* The tile pass draws a tile's front faces first and skips a back face
** that is nowhere nearer than what they drew. Depth is a minimum, the same
** in any order, so the G-buffer's depth must equal that of every triangle
** drawn in mesh order, with nothing skipped. The scene makes it matter: a
** sphere opened toward the camera, its inside (back faces) seen through the
** hole in front of a larger sphere behind it, whose front faces the first
** pass drew there. */
TEST(skipping_hidden_back_faces_keeps_the_depth) {
  Scene s;
  build_scene(&s, SHADE_PHONG);
  s.output.samples = 1;
  s.nobjects = 2;
  s.objects[0].geometry = sphere_geometry(&s.arena, v3(0, 0, 0), 1, 24, 12);
  s.objects[1].geometry = sphere_geometry(&s.arena, v3(0, 4.02, 0), 3, 24, 12);   /* just behind */
  s.objects[0].transform = s.objects[1].transform = m4_identity();
  s.camera = (SceneCamera){.present = 1, .kind = CAMERA_PERSPECTIVE, .position = v3(0, -5, 0.3),
                           .look_at = v3(0, 0, 0), .up = v3(0, 0, 1), .fov = 40};
  for (int k = 0; k < 8; k++) drop_face_toward(&s, s.objects[0].geometry, s.camera.position);
  RenderOptions o = {.threads = 2};
  RenderFrame f;
  CHECK(render_prepare(&s, &o, &f));
  int w = f.width, h = f.height;
  size_t n = (size_t)w * h;
  float *depth = malloc(n * sizeof *depth);
  int32_t *object = malloc(n * sizeof *object), *face = malloc(n * sizeof *face);
  float(*bary)[2] = malloc(n * sizeof *bary);
  for (size_t i = 0; i < n; i++) depth[i] = GBUF_NO_DEPTH;
  RastTarget rt = {0, 0, w, h, 0, 0, w, depth, object, face, bary, NULL};
  for (int i = 0; i < f.nobjects; i++) {
    const RenderObject *ro = &f.objects[i];
    RastVert *rv = malloc(((size_t)ro->mesh->nverts + 1) * sizeof *rv);
    double(*clip)[4] = malloc(((size_t)ro->mesh->nverts + 1) * sizeof *clip);
    for (int v = 0; v < ro->mesh->nverts; v++) {
      camera_to_clip(&f.camera, v3(ro->wpos[v][0], ro->wpos[v][1], ro->wpos[v][2]), clip[v]);
      rast_vertex(&rv[v], clip[v], w, h);
    }
    for (int t = 0; t < ro->mesh->ntris; t++) {
      RastTriList list = {0};
      const int *c = ro->mesh->tri[t];
      const RastVert *tv[3] = {&rv[c[0]], &rv[c[1]], &rv[c[2]]};
      const double *const hv[3] = {clip[c[0]], clip[c[1]], clip[c[2]]};
      rast_emit(&list, tv, hv, i, t, w, h);
      for (int k = 0; k < list.n; k++) rast_triangle(&list.tris[k], &rt);
      rast_list_free(&list);
    }
    free(rv);
    free(clip);
  }
  Image *img;
  GBuffer *gb;
  CHECK_EQ_INT(render_scene(&s, &o, &img, &gb), 0);
  CHECK(gb->width == w && gb->height == h);
  CHECK(memcmp(depth, gb->depth, n * sizeof *depth) == 0);
  int inside = 0;   /* the test sees back faces: samples of the spheres' insides */
  for (size_t i = 0; i < n; i++)
    inside += gb->object[i] >= 0 && f.objects[gb->object[i]].backfacing[gb->face[i]];
  CHECK(inside > 20);
  render_frame_free(&f);
  image_destroy(img);
  gbuf_destroy(gb);
  free(depth);
  free(object);
  free(face);
  free(bary);
  arena_free(&s.arena);
}

/* Coordinates that are not numbers (a NaN or infinite transform) draw
** nothing of that object, and nothing breaks. */
TEST(non_finite_geometry_is_dropped) {
  Scene s;
  build_scene(&s, SHADE_TOON);
  s.objects[1].transform.m[0][0] = NAN;
  s.objects[2].transform.m[1][3] = INFINITY;
  Image *img;
  GBuffer *gb;
  RenderOptions o = {.threads = 2};
  CHECK_EQ_INT(render_scene(&s, &o, &img, &gb), 0);
  int seen[4] = {0};
  for (int i = 0; i < gb->width * gb->height; i++) seen[gb->object[i] + 1]++;
  CHECK(seen[1] > 1000);             /* the finite sphere shows */
  CHECK(seen[2] == 0 && seen[3] == 0);
  image_destroy(img);
  gbuf_destroy(gb);
  arena_free(&s.arena);
}

TEST(limits_are_diagnosed) {
  Scene s;
  build_scene(&s, SHADE_FLAT);
  Image *img;
  RenderOptions o = {.width = RENDER_MAX_SIZE + 1, .height = 10, .threads = 1};
  CHECK_EQ_INT(render_scene(&s, &o, &img, NULL), 1);
  CHECK(img == NULL);
  RenderOptions o2 = {.width = 100, .height = 100, .threads = 1, .samples = RENDER_MAX_SAMPLES + 1};
  CHECK_EQ_INT(render_scene(&s, &o2, &img, NULL), 1);
  RenderOptions o3 = {.width = 10000, .height = 10000, .threads = 1, .samples = 1};   /* each side fine, too many pixels */
  CHECK_EQ_INT(render_scene(&s, &o3, &img, NULL), 1);
  RenderOptions o4 = {.width = 4000, .height = 100, .threads = 1, .samples = 9};      /* 36000 samples wide */
  CHECK_EQ_INT(render_scene(&s, &o4, &img, NULL), 1);
  arena_free(&s.arena);
}

/* Nothing to draw: every pixel is the background, alpha included. */
TEST(empty_scene_is_background) {
  Scene s;
  memset(&s, 0, sizeof s);
  arena_init(&s.arena);
  s.output.width = 40;
  s.output.height = 30;
  s.output.samples = 2;
  s.output.background = (Color){0.25f, 0.5f, 0.75f, 0.5f};
  Image *img;
  RenderOptions o = {.threads = 3};
  CHECK_EQ_INT(render_scene(&s, &o, &img, NULL), 0);
  CHECK_EQ_INT(img->channels, 4);   /* a see-through background keeps alpha */
  int wrong = 0;
  for (int i = 0; i < 40 * 30; i++) {
    const float *p = &img->data[i * img->channels];
    wrong += p[0] != 0.25f || p[1] != 0.5f || p[2] != 0.75f || p[3] != 0.5f;
  }
  CHECK_EQ_INT(wrong, 0);
  image_destroy(img);
  arena_free(&s.arena);
}

TEST(resolve_size) {
  Scene s;
  memset(&s, 0, sizeof s);
  int w, h;
  render_resolve_size(&s, 0, 0, &w, &h);
  CHECK(w == RENDER_DEFAULT_WIDTH && h == RENDER_DEFAULT_HEIGHT);
  s.output.width = 1280;
  s.output.height = 720;
  render_resolve_size(&s, 640, 0, &w, &h);
  CHECK(w == 640 && h == 360);
  render_resolve_size(&s, 0, 180, &w, &h);
  CHECK(w == 320 && h == 180);
  render_resolve_size(&s, 10, 20, &w, &h);
  CHECK(w == 10 && h == 20);
}

int main(void) {
  diag_init(DIAG_TEXT);
  RUN(fill_rule_regular_grid);
  RUN(fill_rule_jittered_grid);
  RUN(fill_rule_vertices_on_sample_centres);
  RUN(fill_rule_vertices_on_pixel_corners);
  RUN(fill_rule_fan_around_sample_centre);
  RUN(fill_rule_through_guard_band_clipping);
  RUN(depth_test_keeps_nearest);
  RUN(perspective_correct_barycentrics);
  RUN(near_plane_clipping_keeps_barycentrics);
  RUN(auto_camera_frames_box);
  RUN(unproject_inverts_projection);
  RUN(identical_bytes_at_1_2_8_threads);
  RUN(identical_bytes_at_1_2_8_threads_antialiased);
  RUN(empty_tiles_give_the_background);
  RUN(closed_mesh_has_no_cracks);
  RUN(back_face_culling_only_when_hidden);
  RUN(skipping_hidden_back_faces_keeps_the_depth);
  RUN(non_finite_geometry_is_dropped);
  RUN(limits_are_diagnosed);
  RUN(empty_scene_is_background);
  RUN(resolve_size);
  return unit_done();
}
