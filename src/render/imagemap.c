/*
** Image maps (imagemap.h): reading into linear RGBA with colour times
** alpha (so the pyramid's means and the filter's blends weigh each texel
** by its cover), the pyramid, and the trilinear read.
*/
#include "imagemap.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"
#include "../io/image.h"

/* ---- the pyramid ---------------------------------------------------------- */

/* Level k + 1 of m from level k: each texel the mean of the (up to) 2 x 2
** texels under it. */
static void reduce(ImageMap *m, int k) {
  const ImageMapLevel *a = &m->level[k];
  ImageMapLevel *b = &m->level[k + 1];
  b->w = a->w > 1 ? (a->w + 1) / 2 : 1;
  b->h = a->h > 1 ? (a->h + 1) / 2 : 1;
  b->rgba = xmalloc((size_t)b->w * b->h * 4 * sizeof *b->rgba);
  for (int y = 0; y < b->h; y++)
    for (int x = 0; x < b->w; x++) {
      float sum[4] = {0, 0, 0, 0};
      int n = 0;
      for (int dy = 0; dy < 2; dy++)
        for (int dx = 0; dx < 2; dx++) {
          int sx = 2 * x + dx, sy = 2 * y + dy;
          if (sx >= a->w || sy >= a->h) continue;
          const float *t = &a->rgba[((size_t)sy * a->w + sx) * 4];
          for (int c = 0; c < 4; c++) sum[c] += t[c];
          n++;
        }
      float *o = &b->rgba[((size_t)y * b->w + x) * 4];
      for (int c = 0; c < 4; c++) o[c] = sum[c] / (float)n;
    }
}

/* The pyramid over m's level 0. */
static void build(ImageMap *m) {
  m->nlevels = 1;
  while (m->nlevels < IMAGEMAP_MAX_LEVELS &&
         (m->level[m->nlevels - 1].w > 1 || m->level[m->nlevels - 1].h > 1)) {
    reduce(m, m->nlevels - 1);
    m->nlevels++;
  }
}

ImageMap *imagemap_from_rgba(const float *rgba, int w, int h) {
  ImageMap *m = xcalloc(1, sizeof *m);
  m->level[0].w = w;
  m->level[0].h = h;
  m->level[0].rgba = xmalloc((size_t)w * h * 4 * sizeof *rgba);
  for (size_t i = 0; i < (size_t)w * h; i++) {   /* colour times alpha */
    const float *t = &rgba[4 * i];
    float *o = &m->level[0].rgba[4 * i];
    for (int c = 0; c < 3; c++) o[c] = t[c] * t[3];
    o[3] = t[3];
  }
  build(m);
  return m;
}

ImageMap *imagemap_load(const char *path, char *err, size_t errlen) {
  Image *img = NULL;
  if (!image_read(path, &img, err, errlen)) return NULL;
  int w = img->width, h = img->height, nc = img->channels;
  float *rgba = xmalloc((size_t)w * h * 4 * sizeof *rgba + 1);
  for (size_t i = 0; i < (size_t)w * h; i++) {
    const float *t = &img->data[i * nc];
    float *o = &rgba[4 * i];
    if (nc >= 3) { o[0] = t[0]; o[1] = t[1]; o[2] = t[2]; }
    else o[0] = o[1] = o[2] = t[0];                    /* grey */
    o[3] = nc == 2 ? t[1] : nc >= 4 ? t[3] : 1;         /* no alpha: opaque */
  }
  image_destroy(img);
  ImageMap *m = imagemap_from_rgba(rgba, w, h);
  free(rgba);
  return m;
}

void imagemap_free(ImageMap *m) {
  if (!m) return;
  for (int k = 0; k < m->nlevels; k++) free(m->level[k].rgba);
  free(m);
}

/* ---- reading -------------------------------------------------------------- */

/* x modulo n into [0, n). */
static inline int wrap(int x, int n) {
  int r = x % n;
  return r < 0 ? r + n : r;
}

/* floor for the texel positions (bounded by the caller), without a call. */
static inline float floor_of(float x) {
  float t = (float)(long long)x;
  return t > x ? t - 1 : t;
}

void imagemap_bilinear(const ImageMap *m, int k, float u, float v, float rgba[4]) {
  const ImageMapLevel *l = &m->level[k];
  /* one period of u and v is enough: the image repeats */
  u -= floor_of(u);
  v -= floor_of(v);
  float x = u * (float)l->w - 0.5f, y = (1 - v) * (float)l->h - 0.5f;   /* texel centres at i + 0.5 */
  float fx = floor_of(x), fy = floor_of(y), ax = x - fx, ay = y - fy;
  int x0 = wrap((int)fx, l->w), x1 = wrap((int)fx + 1, l->w);
  int y0 = wrap((int)fy, l->h), y1 = wrap((int)fy + 1, l->h);
  const float *t00 = &l->rgba[((size_t)y0 * l->w + x0) * 4], *t10 = &l->rgba[((size_t)y0 * l->w + x1) * 4];
  const float *t01 = &l->rgba[((size_t)y1 * l->w + x0) * 4], *t11 = &l->rgba[((size_t)y1 * l->w + x1) * 4];
  for (int c = 0; c < 4; c++) {
    float top = t00[c] + ax * (t10[c] - t00[c]), bottom = t01[c] + ax * (t11[c] - t01[c]);
    rgba[c] = top + ay * (bottom - top);
  }
}

void imagemap_sample(const ImageMap *m, float u, float v, float dudx, float dvdx, float dudy, float dvdy,
                     float rgba[4]) {
  if (!(fabsf(u) < 1e6f && fabsf(v) < 1e6f)) u = v = 0;   /* NaN or far off: any texel will do */
  float W = (float)m->level[0].w, H = (float)m->level[0].h;
  float ax = dudx * W, ay = dvdx * H, bx = dudy * W, by = dvdy * H;
  float rate = sqrtf(fmaxf(ax * ax + ay * ay, bx * bx + by * by));   /* level-0 texels a pixel */
  float lod = rate > 1 ? log2f(rate) : 0;
  float top = (float)(m->nlevels - 1);
  if (!(lod < top)) lod = top;   /* NaN: the coarsest */
  int k0 = (int)lod, k1 = k0 + 1 < m->nlevels ? k0 + 1 : k0;
  float w1 = lod - (float)k0;
  imagemap_bilinear(m, k0, u, v, rgba);
  if (w1 <= 0 || k1 == k0) return;
  float b[4];
  imagemap_bilinear(m, k1, u, v, b);
  for (int c = 0; c < 4; c++) rgba[c] += w1 * (b[c] - rgba[c]);
}
