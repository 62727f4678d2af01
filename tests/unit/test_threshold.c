/*
** Threshold textures (002 sections 3-4): procedural lines and dots keep a
** uniform distribution of thresholds at every scale (a constant shade x
** stays bright over x of the area), the dyadic scale keeps the on-screen
** spacing within a factor 2 of the one asked for, and the box-filtered
** coverage is the mean of the thresholded result over the footprint.
*/
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../../src/io/image.h"
#include "../../src/render/clahe.h"
#include "../../src/render/hatch.h"
#include "../../src/render/render.h"
#include "../../src/render/texcoord.h"
#include "../../src/render/texture.h"
#include "unit.h"

/* skimage's photographs, when python3-skimage is installed (else the tests
** that need them are skipped). */
#define SKIMAGE_DATA "/usr/lib/python3/dist-packages/skimage/data/"
static int skipped;

static int have_file(const char *path) {
  FILE *f = fopen(path, "rb");
  if (f) fclose(f);
  return f != NULL;
}

/* ---- procedural textures ------------------------------------------------------ */

/* The bright fraction of n evenly spread points of one period for shade y. */
static double line_bright(float t, float y, int n) {
  int bright = 0;
  for (int i = 0; i < n; i++) bright += hatch_value((i + 0.5f) / n, t) <= y;
  return (double)bright / n;
}

TEST(hatch_uniform_at_every_scale) {
  for (int it = 0; it < 16; it++)
    for (int iy = 1; iy < 20; iy++) {
      float t = it / 16.0f, y = iy / 20.0f;
      CHECK_NEAR(line_bright(t, y, 20000), y, 0.002);
    }
}

/* The paper's blend without the map through its distribution is not
** uniform: this is what the map mends (t = 1/2, y = 1/4: 1/6 is bright). */
TEST(hatch_eq8_blend_alone_is_not_uniform) {
  int bright = 0, n = 20000;
  for (int i = 0; i < n; i++) {
    float f = (i + 0.5f) / n, t = 0.5f;
    float F = (1 - t) * f + t * (2 * f - floorf(2 * f));   /* eq. 8 with eq. 7 */
    bright += F <= 0.25f;
  }
  CHECK_NEAR((double)bright / n, 0.25 / 1.5, 0.002);
}

TEST(hatch_scales_meet) {
  /* at t = 0 the texture is the sawtooth; as t -> 1 it becomes the
  ** sawtooth at twice the frequency, the next octave's t = 0 */
  for (int i = 0; i < 100; i++) {
    float x = i / 100.0f + 0.003f;
    CHECK_NEAR(hatch_value(x, 0), x - floorf(x), 1e-6);
    CHECK_NEAR(hatch_value(x, 0.99999f), 2 * x - floorf(2 * x), 1e-4);
  }
}

TEST(hatch_coverage_is_box_filtered_threshold) {
  float ts[] = {0, 0.3f, 0.7f}, fws[] = {0.05f, 0.3f, 1, 2.5f};
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 4; b++)
      for (int iy = 1; iy < 10; iy++)
        for (int ix = 0; ix < 7; ix++) {
          float t = ts[a], fw = fws[b], y = iy / 10.0f, x = ix * 0.137f;
          int n = 4000, bright = 0;
          for (int i = 0; i < n; i++) bright += hatch_value(x - fw / 2 + fw * (i + 0.5f) / n, t) <= y;
          CHECK_NEAR(hatch_coverage(x, fw, t, y), (double)bright / n, 0.003);
        }
  /* a whole period (or several) covers exactly y */
  CHECK_NEAR(hatch_coverage(0.4f, 1, 0.25f, 0.3f), 0.3, 1e-5);
  CHECK_NEAR(hatch_coverage(0.1f, 3, 0.8f, 0.65f), 0.65, 1e-5);
  CHECK(hatch_coverage(0.2f, 0, 0, 0.1f) == 0.0f);   /* unfiltered: a step */
  CHECK(hatch_coverage(0.2f, 0, 0, 0.3f) == 1.0f);
}

/* The lanes give the scalar coverage's bits: over footprints from none
** to 16 periods, blends, shades in and past [0, 1] and NaN, and a count
** that leaves a tail. */
TEST(hatch_coverage_run_is_the_scalar_one) {
  enum { N = 4099 };
  static float x[N], fw[N], t[N], c[N], y[N], lanes[N], scalar[N];
  unsigned h = 12345;
  for (int i = 0; i < N; i++) {
    float r[5];
    for (int k = 0; k < 5; k++) {
      h = h * 1664525u + 1013904223u;
      r[k] = (float)(h >> 8) / 16777216.0f;
    }
    x[i] = r[0];
    fw[i] = i % 7 == 0 ? 0 : i % 11 == 0 ? 16 : r[1] * r[1] * 4;
    t[i] = r[2];
    c[i] = 1 / (1 + t[i]);
    y[i] = i % 13 == 0 ? NAN : r[3] * 1.4f - 0.2f;
    lanes[i] = scalar[i] = 0.25f + r[4];
  }
  hatch_coverage_run(x, fw, t, c, y, 0.1f, 1.25f, lanes, 1, N);
  for (int i = 1; i < N; i++) scalar[i] *= hatch_coverage_c(x[i], fw[i], t[i], c[i], (y[i] - 0.1f) * 1.25f);
  CHECK(!memcmp(lanes, scalar, sizeof lanes));
}

TEST(hatch_scale_keeps_spacing) {
  /* the coarse lines lie d / m = w 2^frac(s) apart on screen: within
  ** [w, 2w); the blend t follows frac(s) closely and never turns back */
  float last_s = -1e9f, last_t = 0;
  for (int i = 0; i < 400; i++) {
    float d = 0.5f * powf(1.025f, (float)i), w = 6, m, t;   /* iso-lines d pixels apart */
    hatch_scale(1 / d, w, &m, &t);
    float s = log2f(d / w);
    CHECK(t >= 0 && t < 1);
    CHECK(d / m >= w * 0.9999f && d / m < 2 * w * 1.0001f);
    CHECK_NEAR(t, s - floorf(s), 0.0015);
    if (floorf(s) == floorf(last_s)) CHECK(t >= last_t);
    last_s = s;
    last_t = t;
  }
  float m, t;
  hatch_scale(0, 6, &m, &t);   /* a coordinate that does not change on screen */
  CHECK(m == 0x1p30f);
}

TEST(stipple_uniform_at_every_scale) {
  for (int it = 0; it <= 8; it++)
    for (int iy = 1; iy < 10; iy++) {
      float t = it / 8.0f * 0.999f, y = iy / 10.0f;
      int n = 300, bright = 0;
      for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) bright += stipple_value(i * 1.0f / n + 0.0013f, j * 1.0f / n + 0.0017f, t) <= y;
      CHECK_NEAR((double)bright / (n * n), y, 0.01);
    }
}

TEST(stipple_dots_ink_centres_first) {
  /* a dark shade inks the cell centres; a light one only those */
  CHECK(stipple_value(0.5f, 0.5f, 0) > 0.95f);
  CHECK(stipple_value(0.02f, 0.03f, 0) < 0.05f);
  CHECK(stipple_value(2.5f, -3.5f, 0) > 0.95f);   /* every cell alike */
}

TEST(noise_smooth_and_bounded) {
  float prev = hatch_noise(0, 0.3f, 7);
  for (int i = 1; i < 4000; i++) {
    float u = i * 0.001f, n = hatch_noise(u, 0.3f, 7);
    CHECK(n >= 0 && n < 1);
    CHECK(fabsf(n - prev) < 0.01f);   /* continuous */
    prev = n;
  }
  CHECK(hatch_noise(3.2f, 1.1f, 7) == hatch_noise(3.2f, 1.1f, 7));
  CHECK(hatch_noise(3.2f, 1.1f, 7) != hatch_noise(3.2f, 1.1f, 8));
}

/* ---- CLAHE ------------------------------------------------------------------- */

/* The grey codes of an image file, as the threshold textures read it. */
static uint8_t *read_grey(const char *path, int *w, int *h) {
  Image *img;
  char err[256];
  if (!image_read(path, &img, err, sizeof err)) return NULL;
  *w = img->width;
  *h = img->height;
  uint8_t *g = malloc((size_t)*w * *h);
  for (int i = 0; i < *w * *h; i++) g[i] = image_linear_to_srgb8(img->data[i * img->channels]);
  image_destroy(img);
  return g;
}

/* The fraction of n codes in each of 16 equal bins. */
static void histogram16(const uint8_t *c, int n, double out[16]) {
  for (int b = 0; b < 16; b++) out[b] = 0;
  for (int i = 0; i < n; i++) out[c[i] >> 4] += 1.0 / n;
}

/* On real photographs of textures CLAHE gives a near-uniform histogram:
** each of 16 bins within 25 % of 1/16 (64-pixel windows, without and with
** clipping), where the photograph itself is far from it. */
TEST(clahe_flattens_a_photograph) {
  const char *names[] = {"gravel.png", "grass.png"};
  double clips[] = {0, 4};
  for (int i = 0; i < 2; i++) {
    char path[256];
    snprintf(path, sizeof path, SKIMAGE_DATA "%s", names[i]);
    int w, h;
    uint8_t *g = have_file(path) ? read_grey(path, &w, &h) : NULL;
    if (!g) { skipped++; continue; }
    uint8_t *out = malloc((size_t)w * h);
    double before[16], worst_before = 0;
    histogram16(g, w * h, before);
    for (int b = 0; b < 16; b++) worst_before = fmax(worst_before, fabs(before[b] - 1.0 / 16));
    CHECK(worst_before > 0.25 / 16);   /* the test means something */
    for (int c = 0; c < 2; c++) {
      clahe_apply(g, w, h, w / 64, h / 64, clips[c], out);
      double after[16];
      histogram16(out, w * h, after);
      for (int b = 0; b < 16; b++) CHECK_NEAR(after[b], 1.0 / 16, 0.25 / 16);
    }
    free(g);
    free(out);
  }
}

/* The fraction of n thresholds (65536ths) in each of 16 bins. */
static void histogram16_16(const uint16_t *c, int n, double out[16]) {
  for (int b = 0; b < 16; b++) out[b] = 0;
  for (int i = 0; i < n; i++) out[c[i] >> 12] += 1.0 / n;
}

/* Every level of a threshold texture is equalized (CLAHE, then ranked):
** flat to within 1 % a bin on every photograph, even a dark one of few
** grey levels (brick) and a scene (camera), with the paper's 16-texel
** window and with clipping; a level made by averaging alone would have
** lost its contrast (the paper's Figure 3). */
TEST(threshold_texture_levels_uniform) {
  const char *names[] = {"brick.png", "gravel.png", "grass.png", "camera.png"};
  for (int i = 0; i < 4; i++) {
    char path[256];
    snprintf(path, sizeof path, SKIMAGE_DATA "%s", names[i]);
    int w, h;
    uint8_t *g = have_file(path) ? read_grey(path, &w, &h) : NULL;
    if (!g) { skipped++; continue; }
    ThresholdTexture *t = texture_build(g, w, h, 16, i & 1 ? 4 : 0);
    CHECK_EQ_INT(t->nlevels, 10);   /* 512 .. 1 */
    for (int k = 0; k < 7; k++) {   /* down to 8 x 8 */
      const TextureLevel *l = &t->level[k];
      CHECK_EQ_INT(l->w, w >> k);
      double hist[16];
      histogram16_16(l->texels, l->w * l->h, hist);
      for (int b = 0; b < 16; b++) CHECK_NEAR(hist[b], 1.0 / 16, 0.01 / 16 + 1.0 / (l->w * l->h));
    }
    texture_free(t);
    free(g);
  }
}

/* Equalizing keeps CLAHE's local order: the ranked level is an increasing
** function of the unrounded CLAHE values. */
TEST(threshold_texture_keeps_clahe_order) {
  char path[] = SKIMAGE_DATA "gravel.png";
  int w, h;
  uint8_t *g = have_file(path) ? read_grey(path, &w, &h) : NULL;
  if (!g) { skipped++; return; }
  ThresholdTexture *t = texture_build(g, w, h, 16, 4);
  float *v = malloc((size_t)w * h * sizeof *v);
  clahe_apply_float(g, w, h, w / 16, h / 16, 4, v);
  int bad = 0;
  for (int i = 1; i < w * h; i++)
    if ((v[i] < v[i - 1] - 1.0f / 256) != (t->level[0].texels[i] < t->level[0].texels[i - 1]) &&
        fabsf(v[i] - v[i - 1]) > 1.0f / 256)
      bad++;
  CHECK_EQ_INT(bad, 0);
  free(v);
  texture_free(t);
  free(g);
}

/* ---- texture coordinates' screen rates ------------------------------------------ */

/* The rates texcoord_run gives (from the triangle's own plane and
** gradients, item 2) are those of the coordinates on screen: moving a
** surface point so that its pixel (camera_to_pixel) steps by one along x
** or y changes (u, v) by (ux, vx) or (uy, vy). The step is found from the
** projection's own Jacobian over the plane, by finite differences, for a
** tilted triangle under a perspective and an orthographic camera. */
static void check_rates(CameraKind kind) {
  Vec3 pos[3] = {v3(-1.2, -0.8, 0.1), v3(1.1, -0.5, 0.6), v3(0.2, 1.3, -0.4)};
  int tri[1][3] = {{0, 1, 2}};
  Mesh m = {.nverts = 3, .pos = pos, .ntris = 1, .tri = tri};
  float wpos[3][3];
  for (int k = 0; k < 3; k++) { wpos[k][0] = (float)pos[k].x; wpos[k][1] = (float)pos[k].y; wpos[k][2] = (float)pos[k].z; }
  RenderObject o = {.mesh = &m, .wpos = wpos};
  SceneCamera sc = {.present = 1, .kind = kind, .position = v3(0.9, -3.2, 2.4), .look_at = v3(0, 0, 0),
                    .up = v3(0, 0, 1), .fov = 40, .ortho_height = 3, .loc = src_none()};
  Camera cam;
  const char *why = NULL;
  CHECK(camera_setup(&cam, &sc, 320, 240, v3(-2, -2, -2), v3(2, 2, 2), 0, &why));
  TexView view;
  texcoord_view(&view, &cam);
  TexTriangle tt;
  texcoord_triangle(&tt, &o, 0, PROJ_PLANAR, 0.5f, &view);   /* (u, v) = (x, y) / 2 */
  Vec3 e1 = v3_sub(pos[1], pos[0]), e2 = v3_sub(pos[2], pos[0]);
  double bs[3][2] = {{0.2, 0.3}, {0.6, 0.1}, {0.25, 0.5}};
  for (int i = 0; i < 3; i++) {
    Vec3 p = v3_add(pos[0], v3_add(v3_mul(e1, bs[i][0]), v3_mul(e2, bs[i][1])));
    /* the pixel's Jacobian over the plane's (a, b) = (e1, e2) coordinates */
    double x0, y0, d, xa, ya, xb, yb, h = 1e-6;
    CHECK(camera_to_pixel(&cam, p, &x0, &y0, &d));
    camera_to_pixel(&cam, v3_add(p, v3_mul(e1, h)), &xa, &ya, &d);
    camera_to_pixel(&cam, v3_add(p, v3_mul(e2, h)), &xb, &yb, &d);
    double J[2][2] = {{(xa - x0) / h, (xb - x0) / h}, {(ya - y0) / h, (yb - y0) / h}};
    double det = J[0][0] * J[1][1] - J[0][1] * J[1][0];
    /* (a, b) per pixel step along x and along y: the inverse's columns */
    double ax = J[1][1] / det, bx = -J[1][0] / det, ay = -J[0][1] / det, by = J[0][0] / det;
    Vec3 dpx = v3_add(v3_mul(e1, ax), v3_mul(e2, bx)), dpy = v3_add(v3_mul(e1, ay), v3_mul(e2, by));
    float bary[4][2] = {{(float)bs[i][0], (float)bs[i][1]}};
    float px[4] = {(float)p.x}, py[4] = {(float)p.y}, pz[4] = {(float)p.z};
    float u[4], v[4], ux[4], uy[4], vx[4], vy[4];
    texcoord_run(&tt, &view, 1, bary, px, py, pz, u, v, ux, uy, vx, vy);
    CHECK_NEAR(u[0], p.x / 2, 1e-5);
    CHECK_NEAR(v[0], p.y / 2, 1e-5);
    double scale = fabs(dpx.x) + fabs(dpx.y) + fabs(dpy.x) + fabs(dpy.y);
    CHECK_NEAR(ux[0], dpx.x / 2, 1e-3 * scale);
    CHECK_NEAR(vx[0], dpx.y / 2, 1e-3 * scale);
    CHECK_NEAR(uy[0], dpy.x / 2, 1e-3 * scale);
    CHECK_NEAR(vy[0], dpy.y / 2, 1e-3 * scale);
    float lu[4], lv[4], lux[4], luy[4], lvx[4], lvy[4];   /* the lanes: the same bits */
    texcoord_run_lanes(&tt, &view, 4, bary, px, py, pz, lu, lv, lux, luy, lvx, lvy);
    CHECK(lu[0] == u[0] && lv[0] == v[0] && lux[0] == ux[0] && luy[0] == uy[0] && lvx[0] == vx[0] && lvy[0] == vy[0]);
  }
}

TEST(texcoord_rates_are_the_screen_rates) {
  check_rates(CAMERA_PERSPECTIVE);
  check_rates(CAMERA_ORTHO);
}

/* ---- rendered: a square under a constant shade ------------------------------- */

/* A 2 x 2 square in the xy-plane at the origin, seen from +z by an
** orthographic camera showing `view` units, lit by a sun at an angle whose
** n.l is x: every point's smooth diffuse term is x. White, no ambient, so a
** pixel is T(x) (bands 2) and its mean over the square the bright part. */
static void square_scene(Scene *s, double x, double view, int size) {
  memset(s, 0, sizeof *s);
  arena_init(&s->arena);
  s->output.width = s->output.height = size;
  s->output.samples = 1;
  s->output.background = (Color){0, 0, 0, 1};
  SceneGeometry *g = arena_alloc(&s->arena, sizeof *g);
  g->kind = GEOM_MESH;
  g->nverts = 4;
  g->verts = arena_alloc(&s->arena, 4 * sizeof *g->verts);
  g->verts[0] = v3(-1, -1, 0); g->verts[1] = v3(1, -1, 0); g->verts[2] = v3(1, 1, 0); g->verts[3] = v3(-1, 1, 0);
  g->nfaces = 1;
  g->face_start = arena_alloc(&s->arena, 2 * sizeof(int));
  g->face_index = arena_alloc(&s->arena, 4 * sizeof(int));
  g->face_start[1] = 4;
  for (int i = 0; i < 4; i++) g->face_index[i] = i;
  g->loc = src_none();
  s->nobjects = 1;
  s->objects = arena_alloc(&s->arena, sizeof *s->objects);
  s->objects[0] = (SceneObject){.geometry = g, .transform = m4_identity(), .style = 0, .loc = src_none()};
  s->camera = (SceneCamera){.present = 1, .kind = CAMERA_ORTHO, .position = v3(0, 0, 5), .look_at = v3(0, 0, 0),
                            .up = v3(0, 1, 0), .ortho_height = view, .loc = src_none()};
  s->nlights = 1;
  s->lights = arena_alloc(&s->arena, sizeof *s->lights);
  double th = acos(x);
  s->lights[0] = (SceneLight){.kind = LIGHT_DIRECTIONAL, .direction = v3(-sin(th), 0, -cos(th)),
                              .color = {1, 1, 1, 1}, .strength = 1, .loc = src_none()};
  s->nstyles = 1;
  s->styles = arena_alloc(&s->arena, sizeof *s->styles);
  SceneStyle *st = &s->styles[0];
  *st = scene_default_style();
  st->lines.present = 0;
  st->base = (Color){1, 1, 1, 1};
  st->shade.kind = SHADE_THRESHOLD;
  st->shade.toon.bands = 2;
  st->shade.toon.ambient = 0;
  st->shade.threshold = (ShadeThreshold){.projection = PROJ_PLANAR, .scale = 1, .filter = 1, .strength = 1,
                                         .projection_loc = src_none()};
}

/* Add a layer of kind to the scene's style. */
static ThresholdLayer *add_layer(Scene *s, ThresholdLayerKind kind) {
  ShadeThreshold *th = &s->styles[0].shade.threshold;
  ThresholdLayer *old = th->layers;
  th->layers = arena_alloc(&s->arena, (size_t)(th->nlayers + 1) * sizeof *th->layers);
  if (th->nlayers) memcpy(th->layers, old, (size_t)th->nlayers * sizeof *old);
  ThresholdLayer *l = &th->layers[th->nlayers++];
  *l = (ThresholdLayer){.kind = kind, .range = {0, 1}, .angle = 30, .spacing = 6, .window = 16, .scale = 1,
                        .noise_scale = 0.1, .loc = src_none(), .file_loc = src_none()};
  return l;
}

static Image *render_image(const Scene *s, int threads) {
  RenderOptions o = {.threads = threads};
  Image *img = NULL;
  CHECK_EQ_INT(render_scene(s, &o, &img, NULL), 0);
  return img;
}

/* The mean red of the image's middle (the square fills it). */
static double mean_red(const Image *img) {
  double sum = 0;
  int n = 0;
  for (int y = img->height / 8; y < img->height * 7 / 8; y++)
    for (int x = img->width / 8; x < img->width * 7 / 8; x++, n++) sum += img->data[(y * img->width + x) * img->channels];
  return sum / n;
}

/* A constant shade x over any threshold texture is bright over ~x of the
** area (+-0.03), filtered or not. */
static void check_coverage(ThresholdLayerKind kind, const char *file) {
  for (int f = 0; f < 2; f++)
    for (int i = 1; i < 10; i += 2) {
      double x = i / 10.0;
      Scene s;
      square_scene(&s, x, 2.0, 192);
      s.styles[0].shade.threshold.filter = f;
      ThresholdLayer *l = add_layer(&s, kind);
      if (file) { l->file = file; l->scale = 2; l->clip = 0; }
      Image *img = render_image(&s, 2);
      CHECK_NEAR(mean_red(img), x, 0.03);
      image_destroy(img);
      arena_free(&s.arena);
    }
}

TEST(coverage_hatch) { check_coverage(LAYER_HATCH, NULL); }
TEST(coverage_stipple) { check_coverage(LAYER_STIPPLE, NULL); }
TEST(coverage_image) {
  static const char path[] = SKIMAGE_DATA "brick.png";
  if (!have_file(path)) { skipped++; return; }
  check_coverage(LAYER_IMAGE, path);
}

/* Strength (section 5): T' = x + s (T - x) pixel for pixel, with s =
** strength x facing(n.v) x light(x). The square faces the camera (n.v =
** 1) and its smooth term is x everywhere, so each pixel of a blended
** render is the plain one moved toward x by the factor the curves give. */
static void check_strength(double x, double strength, const double *facing, int nfacing,
                           const double *light, int nlight, double s) {
  Scene a, b;
  square_scene(&a, x, 2.0, 96);
  add_layer(&a, LAYER_HATCH);
  square_scene(&b, x, 2.0, 96);
  add_layer(&b, LAYER_HATCH);
  ShadeThreshold *th = &b.styles[0].shade.threshold;
  th->strength = strength;
  th->facing = (double *)facing; th->nfacing = nfacing;
  th->light = (double *)light; th->nlight = nlight;
  Image *ia = render_image(&a, 2), *ib = render_image(&b, 2);
  double worst = 0, spread = 0;
  for (int y = ia->height / 8; y < ia->height * 7 / 8; y++)
    for (int i = ia->width / 8; i < ia->width * 7 / 8; i++) {
      size_t k = ((size_t)y * ia->width + i) * ia->channels;
      worst = fmax(worst, fabs(ib->data[k] - (x + s * (ia->data[k] - x))));
      spread = fmax(spread, fabs(ia->data[k] - x));
    }
  CHECK(worst < 1e-4);
  CHECK(spread > 0.2);   /* the plain render is thresholded: far from x somewhere */
  image_destroy(ia);
  image_destroy(ib);
  arena_free(&a.arena);
  arena_free(&b.arena);
}

TEST(strength_blends_toward_the_smooth_shade) {
  static const double fig5_facing[] = {1, 0.2}, fig5_light[] = {0, 1, 1, 0};
  check_strength(0.6, 0.3, NULL, 0, NULL, 0, 0.3);                 /* a constant strength */
  check_strength(0.6, 1, fig5_facing, 2, NULL, 0, 0.2);            /* facing at n.v = 1: its last value */
  check_strength(0.6, 1, NULL, 0, fig5_light, 4, 1);               /* light at 0.6: between 1 and 1 */
  check_strength(0.9, 1, NULL, 0, fig5_light, 4, 0.3);             /* at 0.9: 1 + 0.7 (0 - 1) */
  check_strength(0.9, 0.5, fig5_facing, 2, fig5_light, 4, 0.03);   /* all three multiply */
}

/* Ramps work as in toon over textured thresholds: a ramp of K colours
** gives K - 1 bands, and a filtered step lands between two neighbouring
** colours. Shade 0.6 over [black, red, white] is the second band (ramp
** position 1 + bright fraction of the band's 0.2): red at least, white
** over ~0.2 of the area. */
TEST(ramp_over_thresholds) {
  Scene s;
  square_scene(&s, 0.6, 2.0, 128);
  add_layer(&s, LAYER_HATCH);
  static Color ramp[3] = {{0, 0, 0, 1}, {1, 0, 0, 1}, {1, 1, 1, 1}};
  s.styles[0].shade.toon.ramp = ramp;
  s.styles[0].shade.toon.nramp = 3;
  Image *img = render_image(&s, 2);
  double red = 0, green = 0, lo = 1;
  int n = 0;
  for (int y = img->height / 8; y < img->height * 7 / 8; y++)
    for (int x = img->width / 8; x < img->width * 7 / 8; x++, n++) {
      const float *p = img->data + ((size_t)y * img->width + x) * img->channels;
      red += p[0];
      green += p[1];
      lo = fmin(lo, p[0]);
      CHECK(fabsf(p[1] - p[2]) < 1e-6f);   /* on the red-white segment */
    }
  CHECK(lo > 0.999);
  CHECK_NEAR(red / n, 1, 1e-6);
  CHECK_NEAR(green / n, 0.2, 0.03);
  image_destroy(img);
  arena_free(&s.arena);
}

/* ---- rendered: zooms ------------------------------------------------------------ */

/* Lines per pixel along the middle column of img: the ink runs (red below
** 1/2) it crosses, over its length. */
static double column_spacing(const Image *img) {
  int runs = 0, ink = 0, x = img->width / 2, n = 0;
  for (int y = img->height / 8; y < img->height * 7 / 8; y++, n++) {
    int dark = img->data[(y * img->width + x) * img->channels] < 0.5f;
    runs += dark && !ink;
    ink = dark;
  }
  return runs ? (double)n / runs : 1e9;
}

/* On screen the lines stay within a factor 2 of `spacing` while the square
** zooms in 8 times (measured on the rendered frames), where lines fixed on
** the surface would have spread 8 times apart. */
TEST(spacing_holds_over_a_zoom) {
  double lo = 1e9, hi = 0;
  for (int i = 0; i <= 24; i++) {
    double view = 2.0 / pow(8, i / 24.0);   /* units shown: 2 .. 1/4 */
    Scene s;
    square_scene(&s, 0.5, view, 160);
    ThresholdLayer *l = add_layer(&s, LAYER_HATCH);
    l->angle = 0;   /* lines along x: the column crosses them */
    l->spacing = 6;
    Image *img = render_image(&s, 2);
    double d = column_spacing(img);
    CHECK(d >= 3 && d <= 12);
    lo = fmin(lo, d);
    hi = fmax(hi, d);
    image_destroy(img);
    arena_free(&s.arena);
  }
  CHECK(hi / lo < 2.5);
}

/* A perspective view of the square, the eye moving from (0, -d0, d0) to
** (0, -d1, d1) over frames: a slow zoom. */
static void zoom_camera(Scene *s, int frame, int frames, double d0, double d1) {
  double d = d0 + (d1 - d0) * frame / (frames - 1);
  s->camera = (SceneCamera){.present = 1, .kind = CAMERA_PERSPECTIVE, .position = v3(0.3, -d, d),
                            .look_at = v3(0, 0, 0), .up = v3(0, 0, 1), .fov = 30, .loc = src_none()};
}

/* Measured ratios, printed with UNIT_NOTES set. */
#define NOTE(...) (getenv("UNIT_NOTES") ? (void)fprintf(stderr, __VA_ARGS__), (void)fputc('\n', stderr) : (void)0)

/* Whether pixel i of img shows the square: its greys (white lit white)
** against the blue background. */
static int on_square(const Image *img, int i) {
  const float *p = img->data + (size_t)i * img->channels;
  return fabsf(p[2] - p[0]) < 0.5f;
}

/* The frame-to-frame change of a 60-frame zoom over a layer at shade x:
** per pair of frames the root mean square of the change of the written
** sRGB codes (in units of full scale) over the pixels that show the
** square in both, averaged over the 59 pairs. Flicker is pixels jumping
** between ink and paper, and the root mean square weighs such a jump
** above the small changes of an edge moving smoothly (a jump of a whole
** step counts as sixteen of a quarter step, where a plain mean counts it
** as four); the background, still in every frame, would only dilute the
** measure. */
static double zoom_flicker(ThresholdLayerKind kind, const char *file, int filter, double x, double spacing) {
  double total = 0;
  Image *prev = NULL;
  for (int fr = 0; fr < 60; fr++) {
    Scene s;
    square_scene(&s, x, 2, 96);
    s.output.background = (Color){0, 0, 1, 1};
    zoom_camera(&s, fr, 60, 3.0, 2.6);
    s.styles[0].shade.threshold.filter = filter;
    ThresholdLayer *l = add_layer(&s, kind);
    l->spacing = spacing;
    if (file) { l->file = file; l->scale = 1; l->clip = 4; }
    Image *img = render_image(&s, 2);
    if (prev) {
      double sum = 0;
      long n = 0;
      for (int i = 0; i < img->width * img->height; i++) {
        if (!on_square(img, i) || !on_square(prev, i)) continue;
        for (int c = 0; c < 3; c++, n++) {   /* as written: sRGB codes */
          int k = i * img->channels + c;
          double d = (image_linear_to_srgb8(img->data[k]) - image_linear_to_srgb8(prev->data[k])) / 255.0;
          sum += d * d;
        }
      }
      CHECK(n > 3 * img->width * img->height / 4);   /* the square fills most of the frame */
      total += n ? sqrt(sum / n) : 0;
    }
    image_destroy(prev);
    prev = img;
    arena_free(&s.arena);
  }
  image_destroy(prev);
  return total / 59;
}

/* Percentage-closer filtering holds a slow zoom still: the filtered
** frames change at most a third as much as unfiltered ones (item 9), for
** lines near the pixel's size (where thresholding aliases: a pixel is
** wholly ink or paper as a line's edge crosses its centre) at a dark, a
** middle and a light tone, for small dots, and for an image. */
TEST(filtered_zoom_does_not_flicker) {
  double tones[] = {0.5, 0.8, 0.9};
  for (int i = 0; i < 3; i++) {
    double f = zoom_flicker(LAYER_HATCH, NULL, 1, tones[i], 2), u = zoom_flicker(LAYER_HATCH, NULL, 0, tones[i], 2);
    NOTE("hatch at %.1f: filtered %.4f, unfiltered %.4f (%.2f)", tones[i], f, u, f / u);
    CHECK(f <= u / 3);
  }
  double f = zoom_flicker(LAYER_STIPPLE, NULL, 1, 0.9, 2), u = zoom_flicker(LAYER_STIPPLE, NULL, 0, 0.9, 2);
  NOTE("stipple at 0.9: filtered %.4f, unfiltered %.4f (%.2f)", f, u, f / u);
  CHECK(f <= u / 3);
  static const char path[] = SKIMAGE_DATA "gravel.png";
  if (!have_file(path)) { skipped++; return; }
  f = zoom_flicker(LAYER_IMAGE, path, 1, 0.8, 0);
  u = zoom_flicker(LAYER_IMAGE, path, 0, 0.8, 0);
  NOTE("image at 0.8: filtered %.4f, unfiltered %.4f (%.2f)", f, u, f / u);
  CHECK(f <= u / 3);
}

/* The same image at 1, 2 and 8 threads, every layer kind at once. */
TEST(same_image_at_any_thread_count) {
  static const char path[] = SKIMAGE_DATA "grass.png";
  Scene s;
  square_scene(&s, 0.6, 2, 128);
  zoom_camera(&s, 0, 2, 3, 3);
  add_layer(&s, LAYER_HATCH)->noise = 0.5;
  add_layer(&s, LAYER_STIPPLE)->range[1] = 0.5;
  if (have_file(path)) add_layer(&s, LAYER_IMAGE)->file = path;
  else skipped++;
  Image *a = render_image(&s, 1), *b = render_image(&s, 2), *c = render_image(&s, 8);
  size_t n = (size_t)a->width * a->height * a->channels * sizeof(float);
  CHECK(!memcmp(a->data, b->data, n));
  CHECK(!memcmp(a->data, c->data, n));
  image_destroy(a);
  image_destroy(b);
  image_destroy(c);
  arena_free(&s.arena);
}

int main(void) {
  RUN(hatch_uniform_at_every_scale);
  RUN(hatch_eq8_blend_alone_is_not_uniform);
  RUN(hatch_scales_meet);
  RUN(hatch_coverage_is_box_filtered_threshold);
  RUN(hatch_coverage_run_is_the_scalar_one);
  RUN(hatch_scale_keeps_spacing);
  RUN(texcoord_rates_are_the_screen_rates);
  RUN(stipple_uniform_at_every_scale);
  RUN(stipple_dots_ink_centres_first);
  RUN(noise_smooth_and_bounded);
  RUN(clahe_flattens_a_photograph);
  RUN(threshold_texture_levels_uniform);
  RUN(threshold_texture_keeps_clahe_order);
  RUN(coverage_hatch);
  RUN(coverage_stipple);
  RUN(coverage_image);
  RUN(strength_blends_toward_the_smooth_shade);
  RUN(ramp_over_thresholds);
  RUN(spacing_holds_over_a_zoom);
  RUN(filtered_zoom_does_not_flicker);
  RUN(same_image_at_any_thread_count);
  texture_cache_clear();
  int status = unit_done();
  if (skipped) printf("%d passed, %d failed, %d skipped\n", unit_passed, unit_failed, skipped);
  return status;
}
