/*
** Ukiyo-e colour (001 section 2.2): the tileable noise module, flat unlit
** colour, and the screen-space noise and pattern layer that follows each
** object's centre: translation on screen keeps the texel under the centre
** (no shower door), doubling the centre's depth halves the on-screen
** period, and the frame is the same at any thread count.
*/
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../../src/render/noise.h"
#include "../../src/render/render.h"
#include "../../src/render/screentex.h"
#include "render_scenes.h"
#include "unit.h"

static char dir[64];

static const char *tmp_path(const char *name) {
  static char buf[256];
  snprintf(buf, sizeof buf, "%s/%s", dir, name);
  return buf;
}

/* ---- the noise module -------------------------------------------------------- */

/* The fractal noise repeats over the unit square, and a seed fixes it. */
TEST(fbm_periodic_and_seeded) {
  NoiseFbm a, b, c;
  noise_fbm_init(&a, 4, 4, 0.5f, 7);
  noise_fbm_init(&b, 4, 4, 0.5f, 7);
  noise_fbm_init(&c, 4, 4, 0.5f, 8);
  int same = 1, differs = 0;
  for (int i = 0; i < 200; i++) {
    float x = (float)(i * 0.0137), y = (float)(i * 0.0291 - 1.3);
    float v = noise_fbm_eval(&a, x, y);
    CHECK_NEAR(noise_fbm_eval(&a, x + 1, y), v, 1e-5);
    CHECK_NEAR(noise_fbm_eval(&a, x, y - 2), v, 1e-5);
    CHECK(v >= -1 && v <= 1);
    same &= noise_fbm_eval(&b, x, y) == v;
    differs |= fabsf(noise_fbm_eval(&c, x, y) - v) > 1e-3f;
  }
  CHECK(same);
  CHECK(differs);
  noise_fbm_free(&a);
  noise_fbm_free(&b);
  noise_fbm_free(&c);
}

/* One octave at a grid's points from their columns' and rows' axes is
** noise_fbm_eval there to the bit, on a lattice of a power of two cells
** and on one of another size, negative coordinates among the points. */
TEST(fbm_axes_equal_eval) {
  static const int cells[] = {64, 6};
  for (int k = 0; k < 2; k++) {
    NoiseFbm n;
    noise_fbm_init(&n, cells[k], 1, 0.5f, 11);
    int same = 1;
    for (int i = 0; i < 300; i++) {
      float x = ((float)(i - 40) + 0.5f) / 384, y = ((float)(i * 7 % 300 - 90) + 0.5f) / 384;
      NoiseAxis ax, ay;
      noise_axis(&n, x, &ax);
      noise_axis(&n, y, &ay);
      float a = noise_fbm_axes(&n, &ax, &ay), e = noise_fbm_eval(&n, x, y);
      same &= !memcmp(&a, &e, sizeof a);
    }
    CHECK(same);
    noise_fbm_free(&n);
  }
}

/* A baked tile fills [0, 1] around 0.5, its reads wrap, and its coarser
** levels keep the mean. */
TEST(tile_range_wrap_levels) {
  NoiseFbm n;
  noise_fbm_init(&n, 8, 4, 0.5f, 3);
  NoiseTile t;
  noise_tile_bake(&t, &n, 64);
  float lo = 1, hi = 0;
  for (int i = 0; i < 64 * 64; i++) { lo = fminf(lo, t.texel[0][i]); hi = fmaxf(hi, t.texel[0][i]); }
  CHECK(lo >= 0 && hi <= 1);
  CHECK(lo < 0.02f || hi > 0.98f);   /* the widest deviation reaches an end */
  CHECK_NEAR(t.mean[0], 0.5, 1e-4);
  CHECK_EQ_INT(t.levels, 7);         /* 64, 32, ..., 1 */
  float a, b;
  for (int i = 0; i < 50; i++) {
    float u = i * 1.37f, v = i * 0.61f;
    noise_tile_sample(&t, 0, u, v, &a);
    noise_tile_sample(&t, 0, u + 64, v - 128, &b);
    CHECK_NEAR(a, b, 1e-4);
  }
  noise_tile_sample(&t, 0, 10.5f, 20.5f, &a);   /* a texel centre reads the texel */
  CHECK_NEAR(a, t.texel[0][20 * 64 + 10], 1e-6);
  noise_tile_sample(&t, 6, 3, 3, &a);           /* the 1 x 1 level is the mean */
  CHECK_NEAR(a, 0.5, 1e-4);
  CHECK_EQ_INT(noise_tile_level(&t, 0.5f), 0);
  CHECK_EQ_INT(noise_tile_level(&t, 4.5f), 2);  /* 4 texels a sample: the level of 4-texel texels */
  noise_tile_free(&t);
  noise_fbm_free(&n);
}

/* ---- scenes ------------------------------------------------------------------ */

/* A sphere in an unlit flat style, seen from -y; samples 1 so pixels are
** samples; ortho h (0: perspective, fov 30). */
static void flat_scene(Scene *s, double ortho) {
  memset(s, 0, sizeof *s);
  arena_init(&s->arena);
  s->output.width = s->output.height = 128;
  s->output.samples = 1;
  s->output.background = (Color){1, 1, 1, 1};
  s->nstyles = 1;
  s->styles = arena_alloc(&s->arena, sizeof *s->styles);
  s->styles[0] = scene_default_style();
  s->styles[0].lines.present = 0;
  s->styles[0].base = (Color){0.2f, 0.4f, 0.6f, 1};
  s->styles[0].shade.kind = SHADE_FLAT;
  s->styles[0].shade.lit = 0;
  s->camera = (SceneCamera){.present = 1, .kind = ortho > 0 ? CAMERA_ORTHO : CAMERA_PERSPECTIVE,
                            .position = v3(0, -10, 0), .look_at = v3(0, 0, 0), .up = v3(0, 0, 1),
                            .fov = 30, .ortho_height = ortho};
  s->nlights = 1;
  s->lights = arena_alloc(&s->arena, sizeof *s->lights);
  s->lights[0] = (SceneLight){.kind = LIGHT_DIRECTIONAL, .direction = v3(-0.3, 1, -0.4),
                              .color = {1, 1, 1, 1}, .strength = 1};
  s->nobjects = 1;
  s->objects = arena_alloc(&s->arena, sizeof *s->objects);
  s->objects[0].geometry = sphere_geometry(&s->arena, v3(0, 0, 0), 1, 48, 24);
  s->objects[0].transform = m4_identity();
  s->objects[0].style = 0;
}

static void add_noise(Scene *s, double amount, double scale) {
  SceneNoise *n = &s->styles[0].noise;
  *n = (SceneNoise){.present = 1, .amount = amount, .scale = scale, .seed = 5, .octaves = 4};
}

static Image *render_threads(const Scene *s, int threads, GBuffer **g) {
  RenderOptions o = {.threads = threads};
  Image *img = NULL;
  CHECK_EQ_INT(render_scene(s, &o, &img, g), 0);
  return img;
}

static const float *px(const Image *img, int x, int y) {
  return &img->data[((size_t)y * img->width + x) * img->channels];
}

/* Flat colour with lit false: the base colour on every face; lit flat
** colour with ambient 1 still differs from face to face. */
TEST(flat_unlit_one_colour) {
  Scene s;
  flat_scene(&s, 3);
  GBuffer *g;
  Image *img = render_threads(&s, 2, &g);
  int covered = 0, off = 0;
  for (int i = 0; i < img->width * img->height; i++) {
    if (g->object[i] < 0) continue;
    covered++;
    const float *c = &img->data[i * 3];
    off += c[0] != 0.2f || c[1] != 0.4f || c[2] != 0.6f;
  }
  CHECK(covered > 3000);
  CHECK_EQ_INT(off, 0);
  image_destroy(img);
  gbuf_destroy(g);
  s.styles[0].shade.lit = 1;
  s.styles[0].shade.toon.ambient = 1;
  img = render_threads(&s, 2, &g);
  off = 0;
  for (int i = 0; i < img->width * img->height; i++)
    if (g->object[i] >= 0) off += img->data[i * 3] != 0.2f;
  CHECK(off > covered / 2);
  image_destroy(img);
  gbuf_destroy(g);
  arena_free(&s.arena);
}

/* The object moved by (dx, dy) whole pixels: its pixels well inside both
** outlines are those of the first render moved by as much (same texels),
** and the pixel under the centre is unchanged. Returns how many interior
** pixels differ by more than tol. */
static int shifted_differences(Scene *s, int dx, int dz, double wpp, float tol) {
  GBuffer *g0, *g1;
  Image *a = render_threads(s, 2, &g0);
  s->objects[0].transform = m4_translate(v3(dx * wpp, 0, dz * wpp));   /* +x right, +z up the screen */
  Image *b = render_threads(s, 2, &g1);
  s->objects[0].transform = m4_identity();
  int bad = 0, compared = 0;
  for (int y = 2; y < 126; y++)
    for (int x = 2; x < 126; x++) {
      int x1 = x + dx, y1 = y - dz, inside = 1;
      if (x1 < 2 || x1 >= 126 || y1 < 2 || y1 >= 126) continue;
      for (int j = -1; j <= 1; j++)   /* away from both outlines */
        for (int i = -1; i <= 1; i++)
          inside &= g0->object[(y + j) * 128 + x + i] == 0 && g1->object[(y1 + j) * 128 + x1 + i] == 0;
      if (!inside) continue;
      compared++;
      for (int c = 0; c < 3; c++) bad += fabsf(px(a, x, y)[c] - px(b, x1, y1)[c]) > tol;
    }
  CHECK(compared > 1000);
  image_destroy(a);
  image_destroy(b);
  gbuf_destroy(g0);
  gbuf_destroy(g1);
  return bad;
}

/* No shower door (001 section 2.2.1): translating the object by whole
** pixels on screen carries its noise with it, orthographic and in
** perspective (a move across the view keeps the centre's depth). */
TEST(noise_follows_centre) {
  Scene s;
  flat_scene(&s, 4);
  add_noise(&s, 0.2, 0.1);
  CHECK_EQ_INT(shifted_differences(&s, 5, 3, 4.0 / 128, 2e-4f), 0);
  CHECK_EQ_INT(shifted_differences(&s, -7, 0, 4.0 / 128, 2e-4f), 0);
  arena_free(&s.arena);
  flat_scene(&s, 0);
  add_noise(&s, 0.2, 0.1);
  double wpp = 10 * 2 * tan(15 * M_PI / 180) / 128;   /* at the centre's depth, 10 */
  CHECK_EQ_INT(shifted_differences(&s, 6, -4, wpp, 2e-4f), 0);
  arena_free(&s.arena);
}

/* The noise's texel under the centre: the same wherever the object is. */
TEST(noise_texel_under_centre) {
  Scene s;
  flat_scene(&s, 4);
  add_noise(&s, 0.2, 0.1);
  RenderOptions o = {.threads = 1, .width = 128, .height = 128};
  float u[2], v[2];
  for (int k = 0; k < 2; k++) {
    s.objects[0].transform = m4_translate(v3(k * 0.73, 0, k * -0.41));
    RenderFrame f;
    CHECK(render_prepare(&s, &o, &f));
    const RenderObject *ob = &f.objects[0];
    const ScreenTexMap *m = &ob->tex->noise;
    /* sample position of the centre: sx + 0.5 = px */
    u[k] = m->u0 + m->k * (ob->centre.px[0] - 0.5f);
    v[k] = m->v0 + m->k * (ob->centre.px[1] - 0.5f);
    render_frame_free(&f);
  }
  CHECK_NEAR(u[0], u[1], 1e-3);
  CHECK_NEAR(v[0], v[1], 1e-3);
  arena_free(&s.arena);
}

/* A grey image of vertical stripes, period texels across, written to path. */
static void write_stripes(const char *path, int w, int period) {
  Image *img = image_create(w, 4, 1);
  for (int y = 0; y < 4; y++)
    for (int x = 0; x < w; x++) img->data[y * w + x] = 0.5f + 0.4f * sinf(2 * (float)M_PI * x / period);
  char err[256];
  CHECK(image_write(path, img, err, sizeof err));
  image_destroy(img);
}

/* The on-screen period of the stripes along the image's middle row: the
** lag (pixels) that best matches the row with itself, over the object. */
static int stripe_period(const Image *img, const GBuffer *g) {
  int y = img->height / 2, x0 = -1, x1 = -1;
  for (int x = 0; x < img->width; x++)
    if (g->object[y * img->width + x] == 0) { if (x0 < 0) x0 = x; x1 = x; }
  int best = 0;
  double best_err = 1e30;
  for (int lag = 3; lag < (x1 - x0) / 2; lag++) {
    double e = 0;
    for (int x = x0 + 2; x + lag < x1 - 2; x++) e += fabs(px(img, x, y)[0] - px(img, x + lag, y)[0]);
    e /= (x1 - x0 - 4 - lag);
    if (e < best_err * 0.98) { best_err = e; best = lag; }
  }
  return best;
}

/* Size follows depth: with the centre twice as far, the noise's texels a
** pixel double and its stripes' on-screen period halves. */
TEST(noise_period_halves_at_double_depth) {
  write_stripes(tmp_path("stripes.png"), 64, 16);
  Scene s;
  flat_scene(&s, 0);
  s.output.width = s.output.height = 256;
  s.styles[0].base = (Color){0.5f, 0.5f, 0.5f, 1};
  s.objects[0].geometry = sphere_geometry(&s.arena, v3(0, 0, 0), 2, 48, 24);
  add_noise(&s, 0.3, 2.0);   /* the 64-texel image spans 2 units: 16 texels = 0.5 units */
  s.styles[0].noise.image = s.styles[0].noise.image_name = tmp_path("stripes.png");
  int period[2];
  float k[2];
  for (int i = 0; i < 2; i++) {
    s.camera.position = v3(0, -10.0 * (i + 1), 0);   /* depth 10, then 20 */
    GBuffer *g;
    Image *img = render_threads(&s, 2, &g);
    period[i] = stripe_period(img, g);
    RenderOptions o = {.threads = 1, .width = 256, .height = 256};
    RenderFrame f;
    CHECK(render_prepare(&s, &o, &f));
    k[i] = f.objects[0].tex->noise.k;
    render_frame_free(&f);
    image_destroy(img);
    gbuf_destroy(g);
  }
  CHECK_NEAR(k[1] / k[0], 2.0, 1e-4);
  /* 0.5 units at depth 10 with fov 30 on 256 px: 0.5 / (10 * 2 tan 15 / 256) = 23.9 px */
  CHECK(abs(period[0] - 24) <= 1);
  CHECK(abs(period[1] - 12) <= 1);
  arena_free(&s.arena);
}

/* Same scene, same bytes at 1, 2 and 8 threads, with noise and a pattern. */
TEST(layer_deterministic_threads) {
  write_stripes(tmp_path("pattern.png"), 32, 8);
  Scene s;
  flat_scene(&s, 0);
  s.output.samples = 2;
  add_noise(&s, 0.15, 0.2);
  s.styles[0].pattern = (ScenePattern){.present = 1, .scale = 0.7, .opacity = 0.6,
                                       .blend = PATTERN_MULTIPLY};
  s.styles[0].pattern.image = s.styles[0].pattern.image_name = tmp_path("pattern.png");
  Image *a = render_threads(&s, 1, NULL), *b = render_threads(&s, 2, NULL), *c = render_threads(&s, 8, NULL);
  size_t n = (size_t)a->width * a->height * a->channels * sizeof *a->data;
  CHECK(memcmp(a->data, b->data, n) == 0);
  CHECK(memcmp(a->data, c->data, n) == 0);
  image_destroy(a);
  image_destroy(b);
  image_destroy(c);
  arena_free(&s.arena);
}

/* An image that cannot be read stops the frame with a diagnostic. */
TEST(unreadable_image_fails) {
  Scene s;
  flat_scene(&s, 0);
  add_noise(&s, 0.1, 1);
  s.styles[0].noise.image = s.styles[0].noise.image_name = tmp_path("missing.png");
  RenderOptions o = {.threads = 1};
  Image *img = NULL;
  CHECK_EQ_INT(render_scene(&s, &o, &img, NULL), 1);
  CHECK(img == NULL);
  arena_free(&s.arena);
}

int main(void) {
  snprintf(dir, sizeof dir, "/tmp/sumi-ukiyoe-XXXXXX");
  if (!mkdtemp(dir)) { perror("mkdtemp"); return 1; }
  RUN(fbm_periodic_and_seeded);
  RUN(fbm_axes_equal_eval);
  RUN(tile_range_wrap_levels);
  RUN(flat_unlit_one_colour);
  RUN(noise_follows_centre);
  RUN(noise_texel_under_centre);
  RUN(noise_period_halves_at_double_depth);
  RUN(layer_deterministic_threads);
  RUN(unreadable_image_fails);
  remove(tmp_path("stripes.png"));
  remove(tmp_path("pattern.png"));
  rmdir(dir);
  return unit_done();
}
