/*
** CLAHE (clahe.h): per-region clipped histograms and their mappings, then
** the bilinear blend of the four nearest mappings at every pixel.
*/
#include "clahe.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"

enum { BINS = 256 };

/* Index i of a side of n, mirrored at the ends without repeating the edge
** (OpenCV's BORDER_REFLECT_101). */
static int reflect101(int i, int n) {
  if (n == 1) return 0;
  int period = 2 * (n - 1);
  i %= period;
  if (i < 0) i += period;
  return i < n ? i : period - i;
}

/* The image the regions are cut from: src itself when the tiles divide it,
** else src padded on the right and bottom (as OpenCV pads it, by a whole
** tile's count of pixels even on a side the tiles divide). */
static const uint8_t *region_source(const uint8_t *src, int w, int h, int tx, int ty, int *pw,
                                    int *ph, uint8_t **owned) {
  *owned = NULL;
  *pw = w;
  *ph = h;
  if (w % tx == 0 && h % ty == 0) return src;
  *pw = w + tx - w % tx;
  *ph = h + ty - h % ty;
  uint8_t *p = xmalloc((size_t)*pw * *ph);
  for (int y = 0; y < *ph; y++) {
    const uint8_t *row = src + (size_t)reflect101(y, h) * w;
    uint8_t *out = p + (size_t)y * *pw;
    memcpy(out, row, (size_t)w);
    for (int x = w; x < *pw; x++) out[x] = row[reflect101(x, w)];
  }
  *owned = p;
  return p;
}

/* The mapping of one region: its histogram, clipped at limit (0: not) with
** the excess spread evenly and the remainder one count at a time over
** evenly stepped bins, summed and scaled to 0..255. */
static void region_lut(const uint8_t *img, int stride, int x0, int y0, int tw, int th, int limit,
                       float scale, uint8_t lut[BINS]) {
  int hist[BINS] = {0};
  for (int y = 0; y < th; y++) {
    const uint8_t *row = img + (size_t)(y0 + y) * stride + x0;
    for (int x = 0; x < tw; x++) hist[row[x]]++;
  }
  if (limit > 0) {
    int clipped = 0;
    for (int i = 0; i < BINS; i++) {   /* without branches: side by side */
      int excess = hist[i] - limit;
      excess = excess > 0 ? excess : 0;
      clipped += excess;
      hist[i] -= excess;
    }
    int batch = clipped / BINS, residual = clipped - batch * BINS;
    for (int i = 0; i < BINS; i++) hist[i] += batch;
    int step = residual ? (BINS / residual > 1 ? BINS / residual : 1) : 0;
    for (int i = 0; residual > 0 && i < BINS; i += step, residual--) hist[i]++;
  }
  int sum = 0;
  for (int i = 0; i < BINS; i++) {   /* the running sum, then its codes in a loop of their own */
    sum += hist[i];
    hist[i] = sum;
  }
  /* sum * scale <= 255 (sum <= the area, scale = 255 / area): no clamp.
  ** Adding and taking off 1.5 * 2^23 rounds to the nearest, ties to even
  ** (as lrintf and OpenCV's cvRound do) in SIMD lanes. */
  for (int i = 0; i < BINS; i++) {
    float v = (float)hist[i] * scale;
    lut[i] = (uint8_t)(int)((v + 0x1.8p23f) - 0x1.8p23f);
  }
}

/* A pixel's two nearer regions along one axis and its weight toward the
** second: the regions' centres lie at (k + 1/2) tile sides. */
static void axis_weights(int i, float inv_side, int tiles, int *k1, int *k2, float *a) {
  float f = (float)i * inv_side - 0.5f;
  int k = (int)floorf(f);
  *a = f - (float)k;
  *k1 = k > 0 ? k : 0;
  *k2 = k + 1 < tiles - 1 ? k + 1 : tiles - 1;
}

/* The regions' mappings (tiles_x * tiles_y rows of BINS) and the tile
** size, for clahe_apply and clahe_apply_float. Free the result. */
static uint8_t *region_luts(const uint8_t *src, int w, int h, int tiles_x, int tiles_y, double clip,
                            int *tw, int *th) {
  int pw, ph;
  uint8_t *owned;
  const uint8_t *img = region_source(src, w, h, tiles_x, tiles_y, &pw, &ph, &owned);
  *tw = pw / tiles_x;
  *th = ph / tiles_y;
  int area = *tw * *th;
  float scale = (float)(BINS - 1) / (float)area;
  int limit = 0;
  if (clip > 0) {
    limit = (int)(clip * area / BINS);
    if (limit < 1) limit = 1;
  }
  uint8_t *lut = xmalloc((size_t)tiles_x * tiles_y * BINS);
  for (int ty = 0; ty < tiles_y; ty++)
    for (int tx = 0; tx < tiles_x; tx++)
      region_lut(img, pw, tx * *tw, ty * *th, *tw, *th, limit, scale,
                 lut + ((size_t)ty * tiles_x + tx) * BINS);
  free(owned);
  return lut;
}

/* The blend of the four nearest mappings at every pixel, rounded to a code
** (dst8) or not (dstf): one of the two is NULL. Inlined into both callers,
** so each loop has one kind of store. */
static inline __attribute__((always_inline)) void interpolate(const uint8_t *src, int w, int h,
                                                              int tiles_x, int tiles_y, double clip,
                                                              uint8_t *dst8, float *dstf) {
  int tw, th;
  uint8_t *lut = region_luts(src, w, h, tiles_x, tiles_y, clip, &tw, &th);
  /* per column: its two regions' mappings (offsets into a row of them) and weights */
  int *off1 = xmalloc((size_t)w * sizeof *off1), *off2 = xmalloc((size_t)w * sizeof *off2);
  float *xa = xmalloc((size_t)w * sizeof *xa), *xa1 = xmalloc((size_t)w * sizeof *xa1);
  for (int x = 0; x < w; x++) {
    int k1, k2;
    axis_weights(x, 1.0f / (float)tw, tiles_x, &k1, &k2, &xa[x]);
    xa1[x] = 1.0f - xa[x];
    off1[x] = k1 * BINS;
    off2[x] = k2 * BINS;
  }
  /* a row's four mapped values per pixel, gathered first, so the blend and
  ** the rounding after it run in SIMD lanes */
  float *g = xmalloc(4 * (size_t)w * sizeof *g), *g11 = g, *g12 = g + w, *g21 = g + 2 * w, *g22 = g + 3 * w;
  for (int y = 0; y < h; y++) {
    int k1, k2;
    float ya;
    axis_weights(y, 1.0f / (float)th, tiles_y, &k1, &k2, &ya);
    float ya1 = 1.0f - ya;
    const uint8_t *l1 = lut + (size_t)k1 * tiles_x * BINS, *l2 = lut + (size_t)k2 * tiles_x * BINS;
    const uint8_t *s = src + (size_t)y * w;
    for (int x = 0; x < w; x++) {
      int v = s[x], i1 = off1[x] + v, i2 = off2[x] + v;
      g11[x] = l1[i1]; g12[x] = l1[i2]; g21[x] = l2[i1]; g22[x] = l2[i2];
    }
    if (dstf) {
      float *d = dstf + (size_t)y * w;
      for (int x = 0; x < w; x++)
        d[x] = (g11[x] * xa1[x] + g12[x] * xa[x]) * ya1 + (g21[x] * xa1[x] + g22[x] * xa[x]) * ya;
    } else {
      uint8_t *d = dst8 + (size_t)y * w;
      for (int x = 0; x < w; x++) {   /* in [0, 255]: to nearest, ties to even, as in region_lut */
        float r = (g11[x] * xa1[x] + g12[x] * xa[x]) * ya1 + (g21[x] * xa1[x] + g22[x] * xa[x]) * ya;
        d[x] = (uint8_t)(int)((r + 0x1.8p23f) - 0x1.8p23f);
      }
    }
  }
  free(g);
  free(off1);
  free(off2);
  free(xa);
  free(xa1);
  free(lut);
}

void clahe_apply(const uint8_t *src, int w, int h, int tiles_x, int tiles_y, double clip,
                 uint8_t *dst) {
  interpolate(src, w, h, tiles_x, tiles_y, clip, dst, NULL);
}

void clahe_apply_float(const uint8_t *src, int w, int h, int tiles_x, int tiles_y, double clip,
                       float *dst) {
  interpolate(src, w, h, tiles_x, tiles_y, clip, NULL, dst);
}
