/*
** The ukiyo-e colour layer (screentex.h): setting up each style's noise and
** pattern tiles, each object's mapping, and laying them over shaded
** samples.
*/
#include "screentex.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"
#include "../base/rng.h"
#include "../lang/diag.h"

/* Key of the generator stream that places each object's noise in its tile. */
#define SCREENTEX_PLACE_STREAM 0x5eed

/* ---- set-up ------------------------------------------------------------------ */

/* Read path into t; 0 after a diagnostic at loc naming what (noise, pattern). */
static int read_tile(NoiseTile *t, const char *path, SrcRange loc, const char *what) {
  Image *img = NULL;
  char err[600];
  if (!image_read(path, &img, err, sizeof err)) {
    diag_error(loc, "`image` in `%s`: %s", what, err);   /* err names the file and the reason */
    return 0;
  }
  if (img->width < 1 || img->height < 1) {
    diag_error(loc, "%s image: `%s` has no pixels", what, path);
    image_destroy(img);
    return 0;
  }
  noise_tile_from_image(t, img);
  image_destroy(img);
  return 1;
}

static int noise_init(ScreenTex *x, const SceneNoise *n) {
  if (n->image) {
    if (!read_tile(&x->noise, n->image, n->image_loc, "noise")) return 0;
  } else {
    NoiseFbm fbm;
    noise_fbm_init(&fbm, SCREENTEX_NOISE_CELLS, n->octaves, 0.5f, (uint64_t)n->seed);
    noise_tile_bake(&x->noise, &fbm, SCREENTEX_NOISE_SIZE);
    noise_fbm_free(&fbm);
  }
  x->has_noise = 1;
  x->noise_gain = (float)(2 * n->amount);
  /* scale: an image's width, or the procedural noise's coarsest cell */
  double tile = n->image ? n->scale : n->scale * SCREENTEX_NOISE_CELLS;
  x->noise_texel = (float)(tile / x->noise.w[0]);
  return 1;
}

static int pattern_init(ScreenTex *x, const ScenePattern *p) {
  if (!read_tile(&x->pattern, p->image, p->image_loc, "pattern")) return 0;
  x->has_pattern = 1;
  x->pattern_texel = (float)(p->scale / x->pattern.w[0]);
  x->opacity = (float)p->opacity;
  x->blend = p->blend;
  x->nramp = p->ncolors;   /* 0, or 2 .. SCENE_MAX_PATTERN_COLORS (checked) */
  for (int i = 0; i < x->nramp; i++) {
    x->ramp[i][0] = p->colors[i].r; x->ramp[i][1] = p->colors[i].g; x->ramp[i][2] = p->colors[i].b;
  }
  return 1;
}

/* The mapping of tile t (texel scene units) for object o: u = 0 (plus
** place) at the centre, k level-0 texels a sample. */
static ScreenTexMap map_of(const RenderFrame *f, const RenderObject *o, const NoiseTile *t, float texel,
                           float place_u, float place_v) {
  ScreenTexMap m;
  float N = (float)f->samples, s = o->centre.wpp / texel;   /* texels an output pixel */
  m.k = s / N;
  /* sample sx sits at output x = (sx + 0.5) / N */
  m.u0 = (0.5f / N - o->centre.px[0]) * s + place_u;
  m.v0 = (0.5f / N - o->centre.px[1]) * s + place_v;
  m.level = noise_tile_level(t, m.k);
  return m;
}

int screentex_prepare(RenderFrame *f) {
  int any = 0;
  for (int i = 0; i < f->nstyles; i++) any |= f->styles[i].src->noise.present || f->styles[i].src->pattern.present;
  if (!any) return 1;
  ScreenTexFrame *sf = f->screentex = xcalloc(1, sizeof *sf);
  sf->styles = xcalloc((size_t)f->nstyles, sizeof *sf->styles);
  sf->objects = xcalloc((size_t)f->nobjects + 1, sizeof *sf->objects);
  int ok = 1;
  for (int i = 0; i < f->nstyles; i++) {
    const SceneStyle *st = f->styles[i].src;
    ScreenTex *x = &sf->styles[i];
    if (st->pattern.present && !pattern_init(x, &st->pattern)) ok = 0;
    if (st->noise.present && !noise_init(x, &st->noise)) ok = 0;
    if (x->has_noise || x->has_pattern) f->styles[i].tex = x;
  }
  if (!ok) return 0;
  for (int i = 0; i < f->nobjects; i++) {
    RenderObject *o = &f->objects[i];
    const ScreenTex *x = o->style->tex;
    if (!x) continue;
    ScreenTexObject *to = &sf->objects[i];
    if (x->has_pattern)   /* the pattern's middle on the centre */
      to->pattern = map_of(f, o, &x->pattern, x->pattern_texel, 0.5f * x->pattern.w[0], 0.5f * x->pattern.h[0]);
    if (x->has_noise) {   /* each object's grain from its own place in the tile */
      Rng r;
      rng_seed_key(&r, (uint64_t)o->style->src->noise.seed, (uint32_t)i, SCREENTEX_PLACE_STREAM);
      float pu = (float)(rng_uniform(&r) * x->noise.w[0]), pv = (float)(rng_uniform(&r) * x->noise.h[0]);
      to->noise = map_of(f, o, &x->noise, x->noise_texel, pu, pv);
    }
    o->tex = to;
  }
  return 1;
}

void screentex_free(RenderFrame *f) {
  ScreenTexFrame *sf = f->screentex;
  if (!sf) return;
  for (int i = 0; i < f->nstyles; i++) {
    noise_tile_free(&sf->styles[i].noise);
    noise_tile_free(&sf->styles[i].pattern);
  }
  free(sf->styles);
  free(sf->objects);
  free(sf);
  f->screentex = NULL;
}

/* ---- laying it over ------------------------------------------------------------ */

/* The ramp's colour at grey g: equally spaced stops, linear between them. */
static void ramp_at(const ScreenTex *x, float g, float out[3]) {
  float t = (g > 0 ? (g < 1 ? g : 1) : 0) * (float)(x->nramp - 1);   /* NaN reads the first */
  int i = (int)t;
  if (i >= x->nramp - 1) i = x->nramp - 2;
  float a = t - (float)i;
  for (int c = 0; c < 3; c++) out[c] = x->ramp[i][c] + a * (x->ramp[i + 1][c] - x->ramp[i][c]);
}

/* The pattern's texel p (channels, then alpha) over rgb. */
static void lay_pattern(const ScreenTex *x, const float *p, float rgb[3]) {
  const NoiseTile *t = &x->pattern;
  float col[3];
  if (x->nramp >= 2) {
    float g = t->channels == 3 ? 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2] : p[0];
    ramp_at(x, g, col);
  } else if (t->channels == 3) {
    col[0] = p[0]; col[1] = p[1]; col[2] = p[2];
  } else {
    col[0] = col[1] = col[2] = p[0];
  }
  float a = x->opacity * (t->has_alpha ? p[t->channels] : 1);
  for (int c = 0; c < 3; c++)
    rgb[c] = x->blend == PATTERN_MULTIPLY ? rgb[c] * (1 + (col[c] - 1) * a) : rgb[c] + (col[c] - rgb[c]) * a;
}

/* The noise's texel n added to rgb in the square root of linear light. */
static void lay_noise(const ScreenTex *x, const float *n, float rgb[3]) {
  const NoiseTile *t = &x->noise;
  for (int c = 0; c < 3; c++) {
    int ch = t->channels == 3 ? c : 0;
    float d = sqrtf(rgb[c] > 0 ? rgb[c] : 0) + x->noise_gain * (n[ch] - t->mean[ch]);
    rgb[c] = d > 0 ? d * d : 0;
  }
}

/* Grey grain: g (row[j] - mean) for each of sample j's three channels,
** in dn. Four samples at a time fill three whole vectors (stores of three
** floats a sample cost twice as much). */
static void grain_rgb(const float *row, int n, float g, float mean, float *dn) {
  int j = 0;
  for (; j + 4 <= n; j += 4) {
    float a = g * (row[j] - mean), b = g * (row[j + 1] - mean), c = g * (row[j + 2] - mean);
    float d = g * (row[j + 3] - mean), *o = dn + 3 * j;
    o[0] = a, o[1] = a, o[2] = a, o[3] = b, o[4] = b, o[5] = b;
    o[6] = c, o[7] = c, o[8] = c, o[9] = d, o[10] = d, o[11] = d;
  }
  for (; j < n; j++) dn[3 * j] = dn[3 * j + 1] = dn[3 * j + 2] = g * (row[j] - mean);
}

/* Samples the span works on at a time (its noise row lives on the stack). */
#define SCREENTEX_BLOCK 128

void screentex_span(const ShadeRow *r, const RenderObject *o, int k0, int k1, float *rgb, int stride) {
  const ScreenTex *x = o->style->tex;
  float texel[4], row[SCREENTEX_BLOCK];
  if (x->has_pattern) {
    const ScreenTexMap *m = &o->tex->pattern;
    float v = m->v0 + m->k * (float)r->sy;
    for (int k = k0; k < k1; k++) {
      noise_tile_sample(&x->pattern, m->level, m->u0 + m->k * (float)(r->sx0 + k), v, texel);
      lay_pattern(x, texel, rgb + (size_t)k * stride);
    }
  }
  if (!x->has_noise) return;
  const ScreenTexMap *m = &o->tex->noise;
  if (x->noise.channels != 1 || x->noise.has_alpha) {   /* a colour image: one sample at a time */
    for (int k = k0; k < k1; k++) {
      noise_tile_sample(&x->noise, m->level, m->u0 + m->k * (float)(r->sx0 + k), m->v0 + m->k * (float)r->sy,
                        texel);
      lay_noise(x, texel, rgb + (size_t)k * stride);
    }
    return;
  }
  float g = x->noise_gain, mean = x->noise.mean[0], v = m->v0 + m->k * (float)r->sy;
  float dn[3 * SCREENTEX_BLOCK];
  for (int k = k0; k < k1; k += SCREENTEX_BLOCK) {
    int n = k1 - k < SCREENTEX_BLOCK ? k1 - k : SCREENTEX_BLOCK;
    noise_tile_row(&x->noise, m->level, m->u0 + m->k * (float)(r->sx0 + k), m->k, v, n, row);
    grain_rgb(row, n, g, mean, dn);
    float *c = rgb + (size_t)k * stride;
    if (stride == 3) {   /* the channels side by side: one flat loop the compiler runs in lanes */
      for (int q = 0; q < 3 * n; q++) {
        float d = sqrtf(c[q] > 0 ? c[q] : 0) + dn[q];
        c[q] = d > 0 ? d * d : 0;
      }
      continue;
    }
    for (int j = 0; j < n; j++, c += stride)
      for (int q = 0; q < 3; q++) {
        float d = sqrtf(c[q] > 0 ? c[q] : 0) + dn[3 * j + q];
        c[q] = d > 0 ? d * d : 0;
      }
  }
}
