/*
** Chinese ink interiors (Yeh ch. 5.2) and the xuan sheet (ch. 6): the
** quantisation table, the diffusion's rules and invariants, the box
** filter and why it goes last, the high-contrast Gouraud image, the
** paper, and whole frames (determinism, composition).
*/
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../../src/base/rng.h"
#include "../../src/render/canvas.h"
#include "../../src/render/ink.h"
#include "../../src/render/paper.h"
#include "../../src/render/render.h"
#include "render_scenes.h"
#include "unit.h"

/* ---- helpers ------------------------------------------------------------------------ */

/* The thesis's defaults at diffusion strength st. */
static InkStyle ink_style(int st) {
  SceneShade sh = scene_default_style().shade;
  sh.kind = SHADE_INK;
  sh.ink = scene_default_ink();
  sh.ink.diffusion = st;
  sh.toon.ambient = 0.05;
  sh.toon.specular = 0.5;
  sh.toon.shininess = 10;
  InkStyle k;
  ink_style_init(&k, &sh);
  return k;
}

/* A quantised image of every level and every pairing of them: the grey
** is a smooth wave over the canvas, quantised by k; its dark parts touch
** paper directly in places. Every pixel is ink of style 0. */
static void wave_canvas(InkCanvas *c, const InkStyle *k, int w, int h) {
  ink_canvas_init(c, w, h, k, 1);
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      float g = 0.5f + 0.3f * sinf(x * 0.11f) + 0.25f * cosf(y * 0.07f + x * 0.03f) + 0.2f * sinf(y * 0.23f);
      size_t p = (size_t)y * w + x;
      c->level[p] = (uint8_t)ink_label(k, g);
      c->style[p] = 0;
      c->ink[p] = k->ink[c->level[p]];
    }
  ink_canvas_wet(c);
}

/* Blocks of random levels (2 x 2 pixels, seeded), some off the canvas:
** every level touches every other, the paper among them. */
static void random_canvas(InkCanvas *c, const InkStyle *k, int w, int h) {
  ink_canvas_init(c, w, h, k, 1);
  Rng r;
  rng_seed(&r, 7, 1);
  for (int by = 0; by < h; by += 2)
    for (int bx = 0; bx < w; bx += 2) {
      int l = (int)(rng_uniform(&r) * 4.2);   /* 4: off the canvas, now and then */
      for (int y = by; y < by + 2 && y < h; y++)
        for (int x = bx; x < bx + 2 && x < w; x++) {
          size_t p = (size_t)y * w + x;
          c->level[p] = l > 3 ? INK_OFF : (uint8_t)l;
          c->style[p] = l > 0 && l < 4 ? 0 : INK_NO_STYLE;
          c->ink[p] = l < 4 ? k->ink[l] : 0;
        }
    }
  ink_canvas_wet(c);
}

/* A disc of levels on bare paper: dark core, then medium, then light. */
static void disc_canvas(InkCanvas *c, const InkStyle *k, int w, int h) {
  ink_canvas_init(c, w, h, k, 1);
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      float r = hypotf(x - w / 2.0f, y - h / 2.0f);
      int l = r < 10 ? 3 : r < 18 ? 2 : r < 26 ? 1 : 0;
      size_t p = (size_t)y * w + x;
      c->level[p] = (uint8_t)l;
      c->style[p] = l ? 0 : INK_NO_STYLE;
      c->ink[p] = k->ink[l];
    }
  ink_canvas_wet(c);
}

static float *copy_plane(const float *a, size_t n) {
  float *b = malloc(n * sizeof *b);
  memcpy(b, a, n * sizeof *b);
  return b;
}

static double total(const float *a, size_t n) {
  double s = 0;
  for (size_t i = 0; i < n; i++) s += a[i];
  return s;
}

/* ---- quantisation (Fig. 5.4) ----------------------------------------------------------- */

/* [0, 0.4) -> 0.4, [0.4, 0.6) -> 0.6, [0.6, 0.9) -> 0.9, [0.9, 1] -> 1, and
** the inks 255 (1 - colour): 153, 102, 25.5 and 0, exactly. */
TEST(quantisation_table) {
  InkStyle k = ink_style(INK_MEDIUM);
  static const float in[] = {0, 0.1f, 0.39999f, 0.4f, 0.5f, 0.59999f, 0.6f, 0.75f, 0.89999f, 0.9f, 0.95f, 1};
  static const float out[] = {0.4f, 0.4f, 0.4f, 0.6f, 0.6f, 0.6f, 0.9f, 0.9f, 0.9f, 1, 1, 1};
  for (int i = 0; i < (int)(sizeof in / sizeof in[0]); i++) CHECK(ink_quantise(&k, in[i]) == out[i]);
  CHECK_EQ_INT(k.ntones, 4);
  CHECK(k.ink[3] == 153.0f);   /* dark level */
  CHECK(k.ink[2] == 102.0f);   /* medium */
  CHECK(k.ink[1] == 25.5f);    /* light */
  CHECK(k.ink[0] == 0.0f);     /* paper */
  CHECK_EQ_INT(ink_label(&k, 0.2f), 3);
  CHECK_EQ_INT(ink_label(&k, 0.95f), 0);
  CHECK_EQ_INT(ink_label(&k, NAN), 0);   /* not a number: the lightest, no ink */
}

/* Levels and tones are parameters: two ranges with their own tones. */
TEST(quantisation_parameters) {
  SceneShade sh = scene_default_style().shade;
  sh.ink = scene_default_ink();
  sh.ink.nlevels = 1;
  sh.ink.levels[0] = 0.5;
  sh.ink.ntones = 2;
  sh.ink.tones[0] = 0.2;
  sh.ink.tones[1] = 0.8;
  InkStyle k;
  ink_style_init(&k, &sh);
  CHECK(ink_quantise(&k, 0.49f) == 0.2f);
  CHECK(ink_quantise(&k, 0.5f) == 0.8f);
  CHECK_NEAR(k.ink[1], 204, 1e-4);
  CHECK_NEAR(k.ink[0], 51, 1e-4);
}

/* ---- diffusion (ch. 5.2) ---------------------------------------------------------------- */

/* One level everywhere: nothing is darker than anything, nothing moves. */
TEST(constant_image_unchanged) {
  InkStyle k = ink_style(INK_LARGE);
  for (int l = 0; l < 4; l++) {
    InkCanvas c;
    ink_canvas_init(&c, 40, 30, &k, 1);
    for (int p = 0; p < 40 * 30; p++) { c.level[p] = (uint8_t)l; c.style[p] = 0; c.ink[p] = k.ink[l]; }
    ink_canvas_wet(&c);
    float *before = copy_plane(c.ink, 40 * 30);
    InkDiffuseStats st;
    ink_diffuse(&c, -1, &st);
    CHECK_EQ_INT(st.transfers, 0);
    CHECK(!memcmp(before, c.ink, 40 * 30 * sizeof *before));
    free(before);
    ink_canvas_free(&c);
  }
}

/* Every pixel whose ink changed took a darker level than it had (ink went
** from darker to lighter), and none lost ink or water. */
TEST(ink_moves_darker_to_lighter) {
  InkStyle k = ink_style(INK_LARGE);
  InkCanvas c;
  wave_canvas(&c, &k, 160, 120);
  size_t n = 160 * 120;
  float *ink0 = copy_plane(c.ink, n), *water0 = copy_plane(c.water, n);
  uint8_t *level0 = malloc(n);
  memcpy(level0, c.level, n);
  InkDiffuseStats st;
  ink_diffuse(&c, -1, &st);
  CHECK(st.transfers > 500);
  int changed = 0, bad_level = 0, lost = 0;
  for (size_t p = 0; p < n; p++) {
    if (c.ink[p] < ink0[p] || c.water[p] < water0[p]) lost++;
    if (c.ink[p] == ink0[p]) continue;
    changed++;
    if (!(c.level[p] > level0[p])) bad_level++;
  }
  CHECK(changed > 500);
  CHECK_EQ_INT(bad_level, 0);
  CHECK_EQ_INT(lost, 0);
  free(ink0);
  free(water0);
  free(level0);
  ink_canvas_free(&c);
}

/* Total ink never decreases, pass after pass. */
TEST(total_ink_never_decreases) {
  InkStyle k = ink_style(INK_MEDIUM);
  double last = -1;
  for (int passes = 0; passes <= k.passes; passes += 3) {
    InkCanvas c;
    wave_canvas(&c, &k, 120, 90);
    ink_diffuse(&c, passes, NULL);
    double t = total(c.ink, 120 * 90);
    CHECK(t >= last);
    if (passes > 0) CHECK(t > last);   /* and the early passes add some */
    last = t;
    ink_canvas_free(&c);
    if (passes >= 9) break;
  }
}

/* The fast diffusion (looking only where something can change) gives what
** looking at every pixel in every pass gives, bit for bit: on smooth
** levels (the paper level inside), on the disc, and on random blocks where
** every level touches every other and the paper. */
TEST(frontier_equals_every_pixel) {
  for (int st = 0; st < 3; st++) {
    InkStyle k = ink_style(st);
    InkCanvas a, b;
    wave_canvas(&a, &k, 120, 90);
    wave_canvas(&b, &k, 120, 90);
    InkDiffuseStats sa, sb;
    ink_diffuse(&a, -1, &sa);
    ink_diffuse_every_pixel(&b, -1, &sb);
    CHECK(sa.transfers > 100);
    CHECK_EQ_INT(sa.transfers, sb.transfers);
    size_t n = 120 * 90;
    CHECK(!memcmp(a.ink, b.ink, n * sizeof *a.ink));
    CHECK(!memcmp(a.level, b.level, n));
    CHECK(!memcmp(a.water, b.water, n * sizeof *a.water));
    ink_canvas_free(&a);
    ink_canvas_free(&b);
    for (int shape = 0; shape < 2; shape++) {
      if (shape) { random_canvas(&a, &k, 80, 80); random_canvas(&b, &k, 80, 80); }
      else { disc_canvas(&a, &k, 80, 80); disc_canvas(&b, &k, 80, 80); }
      ink_diffuse(&a, -1, &sa);
      ink_diffuse_every_pixel(&b, -1, &sb);
      CHECK(sa.transfers > 100);
      CHECK_EQ_INT(sa.transfers, sb.transfers);
      CHECK(!memcmp(a.ink, b.ink, 80 * 80 * sizeof *a.ink));
      CHECK(!memcmp(a.level, b.level, 80 * 80));
      ink_canvas_free(&a);
      ink_canvas_free(&b);
    }
  }
}

/* Pixels at level l or darker: a level's area. */
static int area(const InkCanvas *c, int l) {
  int a = 0;
  for (int p = 0; p < c->width * c->height; p++) a += c->level[p] != INK_OFF && c->level[p] >= l;
  return a;
}

/* small < medium < large: each level's area grows more (the light level's
** onto the paper, the others into the lighter levels). */
TEST(larger_strength_grows_more) {
  int a[3][4];
  for (int st = 0; st < 3; st++) {
    InkStyle k = ink_style(st);
    InkCanvas c;
    disc_canvas(&c, &k, 96, 96);
    int before[4];
    for (int l = 1; l < 4; l++) before[l] = area(&c, l);
    ink_diffuse(&c, -1, NULL);
    for (int l = 1; l < 4; l++) {
      a[st][l] = area(&c, l);
      CHECK(a[st][l] > before[l]);
    }
    ink_canvas_free(&c);
  }
  for (int l = 1; l < 4; l++) {
    CHECK(a[INK_SMALL][l] < a[INK_MEDIUM][l]);
    CHECK(a[INK_MEDIUM][l] < a[INK_LARGE][l]);
  }
}

/* Rule 1: with a water threshold above every pixel's water, nothing
** moves; rule 3: with an ink threshold above every difference, nothing
** moves; the dark level never runs onto paper directly. */
TEST(the_three_rules) {
  InkStyle k = ink_style(INK_MEDIUM);
  InkCanvas c;
  InkDiffuseStats st;
  k.water_threshold = k.water;
  wave_canvas(&c, &k, 80, 60);
  ink_diffuse(&c, -1, &st);
  CHECK_EQ_INT(st.transfers, 0);
  ink_canvas_free(&c);
  k = ink_style(INK_MEDIUM);
  k.ink_threshold = 153;
  wave_canvas(&c, &k, 80, 60);
  ink_diffuse(&c, -1, &st);
  CHECK_EQ_INT(st.transfers, 0);
  ink_canvas_free(&c);
  k = ink_style(INK_LARGE);   /* a dark square on bare paper: no way onto it */
  ink_canvas_init(&c, 40, 40, &k, 1);
  for (int y = 10; y < 30; y++)
    for (int x = 10; x < 30; x++) { c.level[y * 40 + x] = 3; c.style[y * 40 + x] = 0; c.ink[y * 40 + x] = 153; }
  ink_canvas_wet(&c);
  ink_diffuse(&c, -1, &st);
  CHECK_EQ_INT(st.transfers, 0);
  ink_canvas_free(&c);
}

/* A pass moves ink one pixel at most: after one pass, only pixels beside
** a darker one changed, and the paper level took only the light level's
** ink (no other level runs onto paper). */
TEST(one_pass_one_pixel) {
  InkStyle k = ink_style(INK_LARGE);
  InkCanvas c;
  disc_canvas(&c, &k, 64, 64);
  uint8_t level0[64 * 64];
  memcpy(level0, c.level, sizeof level0);
  InkDiffuseStats st;
  ink_diffuse(&c, 1, &st);
  CHECK_EQ_INT(st.passes, 1);
  CHECK(st.transfers > 0);
  int far = 0, paper_from_dark = 0;
  for (int y = 0; y < 64; y++)
    for (int x = 0; x < 64; x++) {
      int p = y * 64 + x;
      if (c.level[p] == level0[p]) continue;
      paper_from_dark += level0[p] == 0 && c.level[p] != 1;
      int beside = (x > 0 && level0[p - 1] == c.level[p]) || (x < 63 && level0[p + 1] == c.level[p]) ||
                   (y > 0 && level0[p - 64] == c.level[p]) || (y < 63 && level0[p + 64] == c.level[p]);
      far += !beside;
    }
  CHECK_EQ_INT(far, 0);
  CHECK_EQ_INT(paper_from_dark, 0);
  ink_canvas_free(&c);
}

/* Pixels off the canvas (another object covers them) neither take nor
** pass on ink: a wall of them keeps the paper beyond it bare. */
TEST(covered_pixels_block) {
  InkStyle k = ink_style(INK_LARGE);
  InkCanvas c;
  ink_canvas_init(&c, 60, 20, &k, 1);
  for (int y = 0; y < 20; y++)
    for (int x = 0; x < 60; x++) {
      int p = y * 60 + x;
      if (x < 20) { c.level[p] = 1; c.style[p] = 0; c.ink[p] = 25.5f; }
      else if (x == 22) c.level[p] = INK_OFF;
    }
  ink_canvas_wet(&c);
  ink_diffuse(&c, -1, NULL);
  int reached_21 = 0, beyond = 0;
  for (int y = 0; y < 20; y++) {
    reached_21 += c.ink[y * 60 + 21] > 0;
    for (int x = 23; x < 60; x++) beyond += c.ink[y * 60 + x] > 0;
  }
  CHECK(reached_21 > 0);
  CHECK_EQ_INT(beyond, 0);
  ink_canvas_free(&c);
}

/* ---- the box filter ------------------------------------------------------------------------ */

/* One pixel of ink spreads evenly over a 5 x 5 box, the sum kept; at the
** image's corner the box is clipped and averaged over what is inside. */
TEST(box_filter_five) {
  float *a = calloc(20 * 20, sizeof *a);
  a[10 * 20 + 10] = 250;
  float *planes[1] = {a};
  ink_box_filter(planes, 1, NULL, 20, 20, 5);
  int inside = 0;
  for (int y = 0; y < 20; y++)
    for (int x = 0; x < 20; x++) {
      int in = abs(x - 10) <= 2 && abs(y - 10) <= 2;
      inside += in;
      CHECK_NEAR(a[y * 20 + x], in ? 10 : 0, 1e-4);
    }
  CHECK_EQ_INT(inside, 25);
  for (int i = 0; i < 400; i++) a[i] = 0;
  a[0] = 90;   /* the corner's box holds 3 x 3 pixels */
  ink_box_filter(planes, 1, NULL, 20, 20, 5);
  CHECK_NEAR(a[0], 10, 1e-4);
  CHECK_NEAR(a[2 * 20 + 2], 90.0 / 25, 1e-4);
  /* weighted: pixels of weight 0 are left out of every average */
  uint8_t *wt = malloc(400);
  for (int i = 0; i < 400; i++) { a[i] = i % 20 < 10 ? 100 : 0; wt[i] = i % 20 < 10; }
  ink_box_filter(planes, 1, wt, 20, 20, 5);
  CHECK_NEAR(a[5 * 20 + 9], 100, 1e-4);   /* the edge of the weighted part stays full */
  free(wt);
  free(a);
}

/* The box filter as its definition reads, one pixel at a time from a copy
** of the planes: each window's row sums in double, left to right, each
** rounded to float, then the box's rows of those summed top down, over
** the weighted (or the image's) pixels. */
static void box_reference(float **planes, int np, const uint8_t *wt, int w, int h, int side, int x0, int y0,
                          int x1, int y1) {
  int r = side / 2;
  size_t n = (size_t)w * h;
  float *copy = malloc((size_t)np * n * sizeof *copy);
  for (int k = 0; k < np; k++) memcpy(copy + k * n, planes[k], n * sizeof *copy);
  for (int y = y0; y < y1; y++)
    for (int x = x0; x < x1; x++) {
      double sum[4] = {0, 0, 0, 0}, cnt = 0;
      for (int yy = y - r; yy <= y + r; yy++) {
        if (yy < 0 || yy >= h) continue;
        double row[4] = {0, 0, 0, 0}, rc = 0;
        for (int xx = x - r; xx <= x + r; xx++) {
          if (xx < 0 || xx >= w) continue;
          size_t p = (size_t)yy * w + xx;
          int on = wt ? wt[p] != 0 : 1;
          for (int k = 0; k < np; k++) row[k] += on ? copy[k * n + p] : 0;
          rc += on;
        }
        for (int k = 0; k < np; k++) sum[k] += (float)row[k];
        cnt += (float)rc;
      }
      int rows = (y + r < h ? y + r : h - 1) - (y - r > 0 ? y - r : 0) + 1;
      int cols = (x + r < w ? x + r : w - 1) - (x - r > 0 ? x - r : 0) + 1;
      float inv = wt ? (cnt > 0.5 ? (float)(1 / cnt) : 0) : 1 / ((float)rows * (float)cols);
      for (int k = 0; k < np; k++) planes[k][(size_t)y * w + x] = (float)sum[k] * inv;
    }
  free(copy);
}

/* The filter gives the reference's bits exactly, for every side, with and
** without weights, over the whole image and over rectangles of it, on
** random values (zeros, small and large ones, a negative zero). */
TEST(box_filter_bits_of_definition) {
  int w = 37, h = 29;
  size_t n = (size_t)w * h;
  Rng g;
  rng_seed_key(&g, 7, 1, 2);
  for (int trial = 0; trial < 24; trial++) {
    int side = 3 + 2 * (trial % 4), np = trial % 3 == 2 ? 4 : 1, weighted = trial % 2;
    float *a[4], *b[4];
    uint8_t *wt = malloc(n);
    for (int k = 0; k < np; k++) {
      a[k] = malloc(n * sizeof *a[k]);
      b[k] = malloc(n * sizeof *b[k]);
      for (size_t p = 0; p < n; p++) {
        double u = rng_uniform(&g);
        a[k][p] = u < 0.3 ? 0 : u < 0.35 ? -0.0f : (float)(255 * rng_uniform(&g) * pow(10, -6 * rng_uniform(&g)));
        b[k][p] = a[k][p];
      }
    }
    for (size_t p = 0; p < n; p++) wt[p] = rng_uniform(&g) < 0.8;
    int x0 = trial < 8 ? 0 : 3 + trial % 5, y0 = trial < 8 ? 0 : 2 + trial % 7;
    int x1 = trial < 8 ? w : w - 1 - trial % 6, y1 = trial < 8 ? h : h - trial % 4;
    ink_box_filter_rect(a, np, weighted ? wt : NULL, w, h, side, x0, y0, x1, y1);
    box_reference(b, np, weighted ? wt : NULL, w, h, side, x0, y0, x1, y1);
    int same = 1;
    for (int k = 0; k < np; k++) same &= memcmp(a[k], b[k], n * sizeof *a[k]) == 0;
    CHECK(same);
    for (int k = 0; k < np; k++) free(a[k]), free(b[k]);
    free(wt);
  }
}

/* Box filter last (ch. 5.2): filtering before the diffusion mixes the
** levels at their borders, so rule 3 finds other differences there; the
** two orders give measurably different images. */
TEST(box_filter_order_matters) {
  InkStyle k = ink_style(INK_MEDIUM);
  InkCanvas a, b;
  wave_canvas(&a, &k, 120, 90);
  wave_canvas(&b, &k, 120, 90);
  float *pa[1] = {a.ink}, *pb[1] = {b.ink};
  InkDiffuseStats sa, sb;
  ink_diffuse(&a, -1, &sa);   /* the thesis's order */
  ink_box_filter(pa, 1, NULL, 120, 90, 5);
  ink_box_filter(pb, 1, NULL, 120, 90, 5);   /* box first */
  ink_diffuse(&b, -1, &sb);
  double diff = 0, most = 0;
  for (int p = 0; p < 120 * 90; p++) {
    double d = fabs(a.ink[p] - b.ink[p]);
    diff += d;
    most = d > most ? d : most;
  }
  CHECK(diff / (120 * 90) > 0.5);   /* half an ink unit a pixel on average */
  CHECK(most > 10);
  ink_canvas_free(&a);
  ink_canvas_free(&b);
}

/* ---- frames -------------------------------------------------------------------------------- */

/* A sphere in shade ink (style 0) beside a toon sphere (style 1), lit by a
** sun from the upper left, on the xuan sheet when sheet is set. */
static void ink_scene(Scene *s, int sheet) {
  scene_init(s);
  s->output.width = 120;
  s->output.height = 80;
  if (sheet) s->output.sheet.texture = "xuan";
  s->nstyles = 2;
  s->styles = arena_alloc(&s->arena, 2 * sizeof *s->styles);
  s->styles[0] = scene_default_style();
  s->styles[0].lines.present = 0;
  s->styles[0].shade.kind = SHADE_INK;
  s->styles[0].shade.toon.ambient = 0.05;
  s->styles[0].shade.toon.specular = 0.5;
  s->styles[0].shade.toon.shininess = 10;
  s->styles[1] = scene_default_style();
  s->styles[1].lines.present = 0;
  s->camera = (SceneCamera){.present = 1, .kind = CAMERA_PERSPECTIVE, .position = v3(0, -10, 0),
                            .look_at = v3(0, 0, 0), .up = v3(0, 0, 1), .fov = 20};
  s->nlights = 1;
  s->lights = arena_alloc(&s->arena, sizeof *s->lights);
  s->lights[0] = (SceneLight){.kind = LIGHT_DIRECTIONAL, .direction = v3(0.6, 1, -0.5), .color = {1, 1, 1, 1},
                              .strength = 1};
  s->nobjects = 2;
  s->objects = arena_alloc(&s->arena, 2 * sizeof *s->objects);
  for (int i = 0; i < 2; i++) {
    memset(&s->objects[i], 0, sizeof s->objects[i]);
    s->objects[i].geometry = sphere_geometry(&s->arena, v3(i ? 1.1 : -0.6, i ? -1 : 0, 0), i ? 0.35 : 1, 48, 24);
    s->objects[i].transform = m4_identity();
    s->objects[i].style = i;
  }
}

static Image *render_threads(const Scene *s, int threads) {
  RenderOptions o = {.threads = threads};
  Image *img = NULL;
  CHECK_EQ_INT(render_scene(s, &o, &img, NULL), 0);
  return img;
}

/* The diffusion runs over the whole frame after the tiles: the same image
** at 1, 2 and 8 threads (whatever order the tiles are drawn in). */
TEST(frame_same_at_any_thread_count) {
  Scene s;
  ink_scene(&s, 1);
  s.output.samples = 2;
  Image *a = render_threads(&s, 1), *b = render_threads(&s, 2), *c = render_threads(&s, 8);
  CHECK(a && b && c);
  if (a && b && c) {
    size_t n = (size_t)a->width * a->height * a->channels * sizeof(float);
    CHECK(!memcmp(a->data, b->data, n));
    CHECK(!memcmp(a->data, c->data, n));
  }
  image_destroy(a);
  image_destroy(b);
  image_destroy(c);
  scene_free(&s);
}

/* On a white background with black ink, the quantised stage shows the
** tones themselves: every ink pixel is one of 0.4, 0.6, 0.9 and 1 (display
** values), and the dark and the paper levels both show. */
TEST(frame_quantised_stage_shows_tones) {
  Scene s;
  ink_scene(&s, 0);
  s.nobjects = 1;
  s.styles[0].shade.ink.stage = INK_STAGE_QUANTISED;
  Image *img = render_threads(&s, 2);
  int seen[256] = {0}, other = 0;
  for (int i = 0; img && i < img->width * img->height; i++) {
    int code = image_linear_to_srgb8(img->data[i * img->channels]);
    if (code == 102 || code == 153 || code == 230 || code == 255) seen[code]++;
    else other++;
  }
  CHECK_EQ_INT(other, 0);
  CHECK(seen[102] > 50 && seen[153] > 50 && seen[230] > 50 && seen[255] > 50);
  image_destroy(img);
  scene_free(&s);
}

/* The high-contrast Gouraud image (Fig. 5.3): with the thesis's intent
** (strong diffuse and specular, weak ambient) the greys over the object
** spread wider than with OpenGL's usual material (ambient 0.2, diffuse
** 0.8, no specular). */
static double grey_spread(double ambient, double diffuse, double specular) {
  Scene s;
  ink_scene(&s, 0);
  s.nobjects = 1;
  s.styles[0].shade.ink.stage = INK_STAGE_GOURAUD;
  s.styles[0].shade.toon.ambient = ambient;
  s.styles[0].shade.ink.diffuse = diffuse;
  s.styles[0].shade.toon.specular = specular;
  Image *img = render_threads(&s, 1);
  double sum = 0, sum2 = 0;
  int n = 0;
  for (int i = 0; img && i < img->width * img->height; i++) {
    int code = image_linear_to_srgb8(img->data[i * img->channels]);
    if (code == 255) continue;   /* bare paper, and paper-white highlights alike */
    sum += code;
    sum2 += (double)code * code;
    n++;
  }
  image_destroy(img);
  scene_free(&s);
  return n ? sqrt(sum2 / n - (sum / n) * (sum / n)) : 0;
}

TEST(gouraud_high_contrast) {
  double usual = grey_spread(0.2, 0.8, 0), thesis = grey_spread(0.05, 0.9, 0.5);
  CHECK(thesis > usual * 1.1);
}

/* `lights`: the Gouraud image sees only the lights named; a light from
** the other side changes nothing when it is left out. */
TEST(style_lights) {
  Scene s;
  ink_scene(&s, 0);
  s.nobjects = 1;
  Image *one = render_threads(&s, 1);
  SceneLight *l = arena_alloc(&s.arena, 2 * sizeof *l);
  l[0] = s.lights[0];
  l[1] = (SceneLight){.kind = LIGHT_DIRECTIONAL, .direction = v3(-1, 0.3, 0.2), .color = {1, 1, 1, 1},
                      .strength = 1};
  s.lights = l;
  s.nlights = 2;
  Image *both = render_threads(&s, 1);
  static const char *names[1] = {"key"};
  static int index[1] = {0};
  s.styles[0].shade.ink.nlights = 1;
  s.styles[0].shade.ink.lights = names;
  s.styles[0].shade.ink.light_index = index;
  Image *named = render_threads(&s, 1);
  size_t n = (size_t)one->width * one->height * one->channels * sizeof(float);
  CHECK(memcmp(one->data, both->data, n) != 0);
  CHECK(!memcmp(one->data, named->data, n));
  image_destroy(one);
  image_destroy(both);
  image_destroy(named);
  scene_free(&s);
}

/* ---- the sheet (ch. 6) ----------------------------------------------------------------------- */

/* The procedural xuan sheet: the same seed gives the same tile, another
** seed another; the absorbency averages 1 and varies; the colour keeps
** near its tint. */
TEST(xuan_sheet) {
  SceneSheet sh = scene_default_sheet();
  sh.texture = "xuan";
  Paper a, b, c;
  char err[256];
  CHECK(paper_create(&sh, (Color){1, 1, 1, 1}, &a, err, sizeof err));
  CHECK(paper_create(&sh, (Color){1, 1, 1, 1}, &b, err, sizeof err));
  sh.seed = 7;
  CHECK(paper_create(&sh, (Color){1, 1, 1, 1}, &c, err, sizeof err));
  size_t n = (size_t)a.width * a.height;
  CHECK_EQ_INT(a.width, PAPER_TILE);
  CHECK(!memcmp(a.display, b.display, n * 3 * sizeof(float)));
  CHECK(memcmp(a.display, c.display, n * 3 * sizeof(float)) != 0);
  double mean = 0, lo = 1e9, hi = 0, dmean = 0;
  for (size_t i = 0; i < n; i++) {
    mean += a.absorb[i];
    lo = fmin(lo, a.absorb[i]);
    hi = fmax(hi, a.absorb[i]);
    dmean += a.display[3 * i];
  }
  CHECK_NEAR(mean / n, 1, 0.02);
  CHECK(hi - lo > 0.2);
  CHECK_NEAR(dmean / n, 0xf0 / 255.0, 0.03);   /* the tint's red, #f0e8d9 */
  CHECK_EQ_INT(paper_texel(&a, 3 + PAPER_TILE, 5), paper_texel(&a, 3, 5 + 2 * PAPER_TILE));   /* it repeats */
  paper_free(&a);
  paper_free(&b);
  paper_free(&c);
}

/* The sheet tiles without a seam: across the tile's edge, neighbouring
** texels differ no more than neighbours inside do. */
TEST(xuan_tiles_without_seam) {
  SceneSheet sh = scene_default_sheet();
  sh.texture = "xuan";
  Paper p;
  char err[256];
  CHECK(paper_create(&sh, (Color){1, 1, 1, 1}, &p, err, sizeof err));
  int t = p.width;
  double edge = 0, inner = 0;
  for (int y = 0; y < t; y++) {
    edge += fabs(p.absorb[(size_t)y * t + t - 1] - p.absorb[(size_t)y * t]);
    inner += fabs(p.absorb[(size_t)y * t + t / 2 - 1] - p.absorb[(size_t)y * t + t / 2]);
  }
  CHECK(edge < inner * 1.5 + 1);
  paper_free(&p);
}

/* A sheet under any scene: with no ink at all, the background pixels show
** the paper (not the background colour) and the objects are unchanged. */
TEST(sheet_under_any_scene) {
  Scene s;
  ink_scene(&s, 1);
  s.objects[0].style = 1;   /* both toon */
  Image *img = render_threads(&s, 2);
  Scene t;
  ink_scene(&t, 0);
  t.objects[0].style = 1;
  Image *flat = render_threads(&t, 2);
  int corner_paper = image_linear_to_srgb8(img->data[0]) != 255;
  int w = img->width, centre = (img->height / 2) * w + w / 2 - 20;   /* on the big sphere */
  CHECK(corner_paper);
  CHECK(!memcmp(&img->data[centre * 3], &flat->data[centre * 3], 3 * sizeof(float)));
  image_destroy(img);
  image_destroy(flat);
  scene_free(&s);
  scene_free(&t);
}

int main(void) {
  RUN(quantisation_table);
  RUN(quantisation_parameters);
  RUN(constant_image_unchanged);
  RUN(ink_moves_darker_to_lighter);
  RUN(total_ink_never_decreases);
  RUN(frontier_equals_every_pixel);
  RUN(larger_strength_grows_more);
  RUN(the_three_rules);
  RUN(one_pass_one_pixel);
  RUN(covered_pixels_block);
  RUN(box_filter_five);
  RUN(box_filter_bits_of_definition);
  RUN(box_filter_order_matters);
  RUN(frame_same_at_any_thread_count);
  RUN(frame_quantised_stage_shows_tones);
  RUN(gouraud_high_contrast);
  RUN(style_lights);
  RUN(xuan_sheet);
  RUN(xuan_tiles_without_seam);
  RUN(sheet_under_any_scene);
  return unit_done();
}
