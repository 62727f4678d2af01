/*
** The sheet (paper.h): procedural xuan paper, an image sheet, or a flat
** colour.
**
** Xuan paper is made of bark fibres in a pulp: the sheet is mottled where
** the pulp lies thicker, has a fine tooth, and shows fibres, thin curved
** strands a few pixels to a hundred long, some a little lighter than the
** sheet and some darker. Fibres and thick pulp hold more water, so ink
** lands darker on them (absorbency above 1) and washes show the grain.
** Everything is built on a tile that wraps (lattices with whole periods,
** fibres drawn modulo the tile), from the seeded generator and the noise
** module's periodic gradient noise (noise.h).
*/
#include "paper.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"
#include "../base/rng.h"
#include "../io/image.h"
#include "../lang/diag.h"
#include "display.h"
#include "imagemap.h"
#include "noise.h"

/* ---- fibres ---------------------------------------------------------------------- */

/* Fibres on a 384-pixel tile at density 1. */
#define FIBRES_PER_TILE 520

/* Coverage planes of the fibres: light and dark ones. */
typedef struct Fibres { int t; float *light, *dark; } Fibres;

/* v modulo t, in [0, t): a fibre strays less than a tile from it, so a
** step back or on does, with no division. */
static inline int wrap(int v, int t) {
  while (v < 0) v += t;
  while (v >= t) v -= t;
  return v;
}

/* Cover a disc of radius r around (px, py) with strength s, wrapping;
** coverage keeps its largest value, so a fibre's own overlapping steps
** and crossing fibres do not pile up. */
/* Cover reaches pixels whose centres lie within r + 0.5 of (px, py): a
** column (row) past ceil(px + r) lies at least r + 1.5 away. */
static void fibre_dab(Fibres *fb, float *plane, float px, float py, float r, float s) {
  int t = fb->t, x0 = (int)floorf(px - r - 1), x1 = (int)ceilf(px + r);
  int y0 = (int)floorf(py - r - 1), y1 = (int)ceilf(py + r);
  for (int y = y0; y <= y1; y++) {
    float *row = &plane[(size_t)wrap(y, t) * t];
    for (int x = x0; x <= x1; x++) {
      float dx = (float)x + 0.5f - px, dy = (float)y + 0.5f - py;
      float cover = r + 0.5f - sqrtf(dx * dx + dy * dy);   /* antialiased edge */
      if (cover <= 0) continue;
      cover = (cover < 1 ? cover : 1) * s;
      float *q = &row[wrap(x, t)];
      if (cover > *q) *q = cover;
    }
  }
}

/* One fibre: a strand that bends a little at each half-pixel step. */
static void draw_fibre(Fibres *fb, Rng *r, float scale) {
  float u = (float)rng_uniform(r);
  float len = (10 + 80 * u * u * u) * scale;           /* many short, a few long */
  float width = (0.35f + 0.8f * (float)rng_uniform(r)) * scale;
  float strength = 0.35f + 0.65f * (float)rng_uniform(r);
  float *plane = rng_uniform(r) < 0.6 ? fb->light : fb->dark;
  float x = (float)(rng_uniform(r) * fb->t), y = (float)(rng_uniform(r) * fb->t);
  float angle = (float)(rng_uniform(r) * 2 * M_PI);
  float bend = (float)(rng_uniform(r) - 0.5) * 0.006f / scale;   /* gently curved */
  for (float d = 0; d < len; d += 0.5f) {
    fibre_dab(fb, plane, x, y, width / 2, strength);
    angle += bend + (float)(rng_uniform(r) - 0.5) * 0.03f;
    x += 0.5f * cosf(angle);
    y += 0.5f * sinf(angle);
  }
}

/* ---- enlarging ----------------------------------------------------------------- */

/* The s x s tile src enlarged to t x t into dst, bilinearly between texel
** centres, wrapping at the edges (so it still tiles). */
static void enlarge(const float *src, int s, float *dst, int t) {
  int *i0 = xmalloc((size_t)t * sizeof *i0), *i1 = xmalloc((size_t)t * sizeof *i1);
  float *w = xmalloc((size_t)t * sizeof *w);
  for (int x = 0; x < t; x++) {   /* the same for rows and columns */
    float u = ((float)x + 0.5f) * s / t - 0.5f;
    int a = (int)floorf(u);
    w[x] = u - (float)a;
    i0[x] = ((a % s) + s) % s;
    i1[x] = (i0[x] + 1) % s;
  }
  float *across = xmalloc((size_t)s * t * sizeof *across);   /* each source row enlarged along it */
  for (int y = 0; y < s; y++) {
    const float *r = src + (size_t)y * s;
    for (int x = 0; x < t; x++) across[(size_t)y * t + x] = r[i0[x]] + (r[i1[x]] - r[i0[x]]) * w[x];
  }
  for (int y = 0; y < t; y++) {   /* then between two of them, a row in lanes */
    const float *top = across + (size_t)i0[y] * t, *bottom = across + (size_t)i1[y] * t;
    float *d = dst + (size_t)y * t, wy = w[y];
    for (int x = 0; x < t; x++) d[x] = top[x] + (bottom[x] - top[x]) * wy;
  }
  free(across);
  free(i0);
  free(i1);
  free(w);
}

/* ---- sheets ---------------------------------------------------------------------- */

static void paper_alloc(Paper *p, int w, int h) {
  size_t n = (size_t)w * h;
  p->width = w;
  p->height = h;
  p->display = xmalloc(n * 3 * sizeof *p->display);
  p->linear = NULL;   /* paper_fill_linear, when the composite reads them */
  p->absorb = xmalloc(n * sizeof *p->absorb);
  p->alpha = 1;
}

/* Absorbency raw values a (mean m) to 1 + grain (a - m), kept positive. */
static void normalise_absorb(Paper *p, double grain) {
  size_t n = (size_t)p->width * p->height;
  double sum = 0;
  for (size_t i = 0; i < n; i++) sum += p->absorb[i];
  float mean = (float)(sum / (double)n);
  for (size_t i = 0; i < n; i++) {
    float a = 1 + (float)grain * (p->absorb[i] - mean);
    p->absorb[i] = a > 0.2f ? a : 0.2f;
  }
}

/* The codes of the display values. */
static void fill_codes(Paper *p) {
  size_t n = (size_t)p->width * p->height * 3;
  uint8_t *restrict code = p->code = xmalloc(n + 1);   /* apart from the floats: a loop in lanes */
  const float *restrict d = p->display;
  for (size_t i = 0; i < n; i++) code[i] = (uint8_t)(int)(d[i] * 255 + 0.5f);   /* in [0, 255.5] */
}

/* The linear values of the display values (p->linear allocated). */
static void linear_values(Paper *p) {
  size_t n = (size_t)p->width * p->height * 3;
  for (size_t i = 0; i < n; i++) p->linear[i] = display_to_linear(p->display[i]);
}

/* The linear values and the codes of the display values. */
static void fill_linear(Paper *p) {
  fill_codes(p);
  linear_values(p);
}

void paper_fill_linear(Paper *p) {
  if (p->linear) return;
  p->linear = xmalloc((size_t)p->width * p->height * 3 * sizeof *p->linear);
  linear_values(p);
}

/* Procedural xuan paper. */
static int xuan(const SceneSheet *sh, Paper *p, char *err, size_t errlen) {
  int t = (int)lround(PAPER_TILE * sh->scale);
  t = t < 32 ? 32 : t;
  if ((long long)t * t > PAPER_MAX_TEXELS) {
    snprintf(err, errlen, "a sheet of scale %g needs a %d x %d tile, more than %lld texels (PAPER_MAX_TEXELS)",
             sh->scale, t, t, PAPER_MAX_TEXELS);
    return 0;
  }
  paper_alloc(p, t, t);
  size_t n = (size_t)t * t;
  Fibres fb = {t, xcalloc(n, sizeof(float)), xcalloc(n, sizeof(float))};
  int count = (int)lround(sh->fibres * FIBRES_PER_TILE * (double)t * t / ((double)PAPER_TILE * PAPER_TILE));
  for (int i = 0; i < count; i++) {
    Rng r;
    rng_seed_key(&r, (uint64_t)sh->seed, 0x78756eu /* "xun" */, (uint32_t)i);
    draw_fibre(&fb, &r, (float)sh->scale);
  }
  float tint[3] = {display_from_linear(sh->color.r), display_from_linear(sh->color.g),
                   display_from_linear(sh->color.b)};
  /* thick and thin pulp over the tile, and a tooth of two-pixel cells: each
  ** baked at the scale of its cells (a quarter and a half of the tile's
  ** side) and enlarged bilinearly, wrapping */
  NoiseFbm pulp_fbm, tooth_fbm;
  NoiseTile pulp_tile, tooth_tile;
  int tq = t / 4 > 1 ? t / 4 : 1, th = t / 2 > 1 ? t / 2 : 1;
  noise_fbm_init(&pulp_fbm, 6, 3, 0.5f, (uint64_t)sh->seed * 2 + 1);
  noise_fbm_init(&tooth_fbm, th, 1, 0.5f, (uint64_t)sh->seed * 2 + 2);
  noise_tile_bake(&pulp_tile, &pulp_fbm, tq);
  noise_tile_bake(&tooth_tile, &tooth_fbm, th);
  float *pulp_plane = xmalloc(n * sizeof(float)), *tooth_plane = xmalloc(n * sizeof(float));
  enlarge(pulp_tile.texel[0], tq, pulp_plane, t);
  enlarge(tooth_tile.texel[0], th, tooth_plane, t);
  for (int y = 0; y < t; y++)
    for (int x = 0; x < t; x++) {
      size_t i = (size_t)y * t + x;
      float pulp = pulp_plane[i] - 0.5f, tooth = tooth_plane[i] - 0.5f;
      float light = fb.light[i], dark = fb.dark[i];
      float k = 1 + 0.035f * pulp + 0.02f * tooth + 0.045f * light - 0.05f * dark;
      for (int c = 0; c < 3; c++) {
        float v = tint[c] * k;
        p->display[3 * i + c] = v < 1 ? (v > 0 ? v : 0) : 1;
      }
      p->absorb[i] = 0.6f * pulp + 0.3f * tooth + 0.5f * light + 0.4f * dark;
    }
  free(fb.light);
  free(fb.dark);
  free(pulp_plane);
  free(tooth_plane);
  noise_tile_free(&pulp_tile);
  noise_tile_free(&tooth_tile);
  noise_fbm_free(&pulp_fbm);
  noise_fbm_free(&tooth_fbm);
  normalise_absorb(p, sh->grain);
  fill_codes(p);
  return 1;
}

/* An image sheet: each texel is scale pixels; darker than the sheet's mean
** absorbs more. */
static int image_sheet(const SceneSheet *sh, Paper *p, char *err, size_t errlen) {
  char path[4096], why[1024];
  const char *file = diag_path_beside(sh->loc, sh->texture, path, sizeof path);
  Image *img = NULL;
  if (!image_read(file, &img, why, sizeof why)) {
    snprintf(err, errlen, "cannot read the sheet image `%s`: %s", sh->texture, why);
    return 0;
  }
  int w = (int)lround(img->width * sh->scale), h = (int)lround(img->height * sh->scale);
  w = w < 1 ? 1 : w;
  h = h < 1 ? 1 : h;
  if ((long long)w * h > PAPER_MAX_TEXELS) {
    snprintf(err, errlen, "the sheet image `%s` at scale %g is %d x %d pixels, more than %lld (PAPER_MAX_TEXELS)",
             sh->texture, sh->scale, w, h, PAPER_MAX_TEXELS);
    image_destroy(img);
    return 0;
  }
  paper_alloc(p, w, h);
  int nc = img->channels, colour = nc >= 3;
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {   /* nearest texel */
      int sx = (int)((x + 0.5) / sh->scale), sy = (int)((y + 0.5) / sh->scale);
      sx = sx < img->width ? sx : img->width - 1;
      sy = sy < img->height ? sy : img->height - 1;
      const float *q = img->data + ((size_t)sy * img->width + sx) * nc;
      size_t i = (size_t)y * w + x;
      float lum = 0;
      for (int c = 0; c < 3; c++) {
        float d = display_from_linear(q[colour ? c : 0]);
        p->display[3 * i + c] = d;
        lum += (c == 0 ? 0.2126f : c == 1 ? 0.7152f : 0.0722f) * d;
      }
      p->absorb[i] = -2 * lum;   /* darker: more absorbent */
    }
  image_destroy(img);
  normalise_absorb(p, sh->grain);
  fill_codes(p);
  return 1;
}

int paper_create(const SceneSheet *sh, Color background, Paper *p, char *err, size_t errlen) {
  memset(p, 0, sizeof *p);
  if (sh && sh->texture) return strcmp(sh->texture, "xuan") ? image_sheet(sh, p, err, errlen) : xuan(sh, p, err, errlen);
  p->width = PAPER_FLAT_RUN;   /* the flat background: a row of one colour, so runs are long */
  p->height = 1;
  p->display = xmalloc(3 * PAPER_FLAT_RUN * sizeof *p->display);
  p->linear = xmalloc(3 * PAPER_FLAT_RUN * sizeof *p->linear);
  float bg[3] = {display_from_linear(background.r), display_from_linear(background.g),
                 display_from_linear(background.b)};
  for (int i = 0; i < PAPER_FLAT_RUN; i++)
    for (int c = 0; c < 3; c++) p->display[3 * i + c] = bg[c];
  fill_linear(p);
  for (int i = 0; i < PAPER_FLAT_RUN; i++) {   /* the background's own linear values, not their round trip */
    p->linear[3 * i] = background.r; p->linear[3 * i + 1] = background.g; p->linear[3 * i + 2] = background.b;
  }
  p->alpha = background.a;
  return 1;
}

/* A vertical gradient through o's stops, evenly spaced from the top row
** to the bottom row, in linear light: each row one colour. */
static void gradient(const SceneOutput *o, int height, Paper *p) {
  p->width = PAPER_FLAT_RUN;   /* a row of one colour: long runs, as the flat background */
  p->height = height;
  size_t n = (size_t)p->width * height * 3;
  p->display = xmalloc(n * sizeof *p->display);
  p->linear = xmalloc(n * sizeof *p->linear);
  float *row = xmalloc(3 * (size_t)height * sizeof *row);
  for (int y = 0; y < height; y++) {
    double t = height > 1 ? (double)y / (height - 1) * (o->nstops - 1) : 0;   /* the stops' scale */
    int i = (int)t < o->nstops - 1 ? (int)t : o->nstops - 2;
    float f = (float)(t - i);
    const Color *a = &o->stops[i], *b = &o->stops[i + 1];
    row[3 * y] = a->r + f * (b->r - a->r);
    row[3 * y + 1] = a->g + f * (b->g - a->g);
    row[3 * y + 2] = a->b + f * (b->b - a->b);
  }
  for (int y = 0; y < height; y++)
    for (int x = 0; x < p->width; x++)
      for (int c = 0; c < 3; c++) p->display[((size_t)y * p->width + x) * 3 + c] = display_from_linear(row[3 * y + c]);
  fill_linear(p);
  for (int y = 0; y < height; y++)   /* the gradient's own linear values, not their round trip */
    for (int x = 0; x < p->width; x++) memcpy(&p->linear[((size_t)y * p->width + x) * 3], &row[3 * y], 3 * sizeof *row);
  free(row);
}

/* o's image scaled to width x height pixels: each pixel the image's
** filtered colour over its footprint (imagemap.h), over black. */
static int backdrop_image(const SceneOutput *o, int width, int height, Paper *p, char *err, size_t errlen) {
  if ((long long)width * height > PAPER_MAX_TEXELS) {
    snprintf(err, errlen, "a background image is scaled to the frame, and %d x %d pixels is more than %lld "
             "(PAPER_MAX_TEXELS); render it in tiles of a smaller frame, or use a colour", width, height,
             PAPER_MAX_TEXELS);
    return 0;
  }
  char why[1024];
  ImageMap *m = imagemap_load(o->backdrop, why, sizeof why);
  if (!m) {
    snprintf(err, errlen, "`background` in `output`: %s", why);
    return 0;
  }
  p->width = width;
  p->height = height;
  size_t n = (size_t)width * height * 3;
  p->display = xmalloc(n * sizeof *p->display);
  p->linear = xmalloc(n * sizeof *p->linear);
  float du = 1.0f / (float)width, dv = 1.0f / (float)height;
  for (int y = 0; y < height; y++)
    for (int x = 0; x < width; x++) {
      float t[4];   /* colour times alpha: over black */
      imagemap_sample(m, ((float)x + 0.5f) * du, 1 - ((float)y + 0.5f) * dv, du, 0, 0, dv, t);
      float *d = &p->linear[((size_t)y * width + x) * 3];
      for (int c = 0; c < 3; c++) d[c] = t[c];
    }
  imagemap_free(m);
  for (size_t i = 0; i < n; i++) p->display[i] = display_from_linear(p->linear[i]);
  float *lin = p->linear;   /* fill_linear makes the codes; the linear values stay exact */
  p->linear = xmalloc(n * sizeof *p->linear);
  fill_linear(p);
  free(p->linear);
  p->linear = lin;
  return 1;
}

int paper_backdrop(const SceneOutput *o, int width, int height, Paper *p, char *err, size_t errlen) {
  memset(p, 0, sizeof *p);
  p->alpha = 1;
  if (o->backdrop) return backdrop_image(o, width, height, p, err, errlen);
  gradient(o, height, p);
  return 1;
}

void paper_free(Paper *p) {
  free(p->display);
  free(p->linear);
  free(p->absorb);
  free(p->code);
  memset(p, 0, sizeof *p);
}
