/*
** Image threshold textures (texture.h): grey, pyramid, CLAHE per level, the
** process-wide cache, and sampling.
*/
#include "texture.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "../base/mem.h"
#include "../io/image.h"
#include "clahe.h"

/* ---- building ----------------------------------------------------------------- */

/* The 2 x 2 means of a w x h grey level: a level of half its sides
** (rounded down, at least 1), where an odd side's last texel joins the pair
** before it. */
static uint8_t *reduce(const uint8_t *src, int w, int h, int *nw, int *nh) {
  *nw = w > 1 ? w / 2 : 1;
  *nh = h > 1 ? h / 2 : 1;
  uint8_t *dst = xmalloc((size_t)*nw * *nh);
  for (int y = 0; y < *nh; y++) {
    int y0 = h > 1 ? 2 * y : 0, y1 = y == *nh - 1 ? h : y0 + 2;   /* rows [y0, y1) */
    int fast = y1 - y0 == 2 ? *nw - (w & 1) : 0;   /* 2 x 2 blocks: the common case */
    const uint8_t *a = src + (size_t)y0 * w, *b = a + w;
    uint8_t *d = dst + (size_t)y * *nw;
    for (int x = 0; x < fast; x++)
      d[x] = (uint8_t)((a[2 * x] + a[2 * x + 1] + b[2 * x] + b[2 * x + 1] + 2) >> 2);
    for (int x = fast; x < *nw; x++) {   /* an odd side's last block, or a side of 1 */
      int x0 = w > 1 ? 2 * x : 0, x1 = x == *nw - 1 ? w : x0 + 2;
      unsigned sum = 0, n = 0;
      for (int j = y0; j < y1; j++)
        for (int i = x0; i < x1; i++, n++) sum += src[(size_t)j * w + i];
      d[x] = (uint8_t)((sum + n / 2) / n);
    }
  }
  return dst;
}

/* Regions a side for a side of n texels and a window of w texels. */
static int regions(int n, double w) {
  long k = lround(n / w);
  return k < 1 ? 1 : k > n ? n : (int)k;
}

/* Rank the n values v (0 to 255) as a whole, ties in index order, into
** thresholds: the rank's place in [0, 1), in 65536ths. A counting sort on
** the values to 1/256 of a code, or coarser for a small level (about four
** keys a value: a level of a few texels costs no table of 65536). */
static void rank_thresholds(const float *v, size_t n, uint16_t *out) {
  int bits = 8;
  while (bits < 16 && ((size_t)1 << bits) < 4 * n) bits++;
  uint32_t keys = 1u << bits;
  float scale = (float)keys / 256;
  uint32_t *start = xcalloc(keys + 1, sizeof *start);
  uint16_t *key = xmalloc(n * sizeof *key);
  for (size_t i = 0; i < n; i++) {
    long k = lrintf(v[i] * scale);
    key[i] = (uint16_t)(k < 0 ? 0 : k >= (long)keys ? keys - 1 : k);
    start[key[i] + 1]++;
  }
  for (uint32_t k = 0; k < keys; k++) start[k + 1] += start[k];   /* the first rank of each key */
  for (size_t i = 0; i < n; i++) {
    uint32_t rank = start[key[i]]++;
    out[i] = (uint16_t)(((uint64_t)rank * 65536 + 32768) / n);   /* (rank + 1/2) / n */
  }
  free(key);
  free(start);
}

void texture_equalize_level(const uint8_t *grey, int w, int h, double window, double clip,
                            uint16_t *out) {
  float *v = xmalloc((size_t)w * h * sizeof *v);
  clahe_apply_float(grey, w, h, regions(w, window), regions(h, window), clip, v);
  rank_thresholds(v, (size_t)w * h, out);
  free(v);
}

ThresholdTexture *texture_build(const uint8_t *grey, int w, int h, double window, double clip) {
  ThresholdTexture *t = xcalloc(1, sizeof *t);
  uint8_t *cur = xmalloc((size_t)w * h);
  memcpy(cur, grey, (size_t)w * h);
  for (int k = 0; k < TEXTURE_MAX_LEVELS; k++) {
    TextureLevel *l = &t->level[k];
    l->w = w;
    l->h = h;
    l->texels = xmalloc((size_t)w * h * sizeof *l->texels);
    texture_equalize_level(cur, w, h, window, clip, l->texels);
    t->nlevels = k + 1;
    if (w == 1 && h == 1) break;
    uint8_t *next = reduce(cur, w, h, &w, &h);
    free(cur);
    cur = next;
  }
  free(cur);
  return t;
}

void texture_free(ThresholdTexture *t) {
  if (!t) return;
  for (int k = 0; k < t->nlevels; k++) free(t->level[k].texels);
  free(t);
}

/* The grey codes of an image read by image.h: its colour channels back to
** 8-bit sRGB codes (exactly the file's for an 8-bit file), then luma in
** OpenCV's fixed point. */
static uint8_t *grey_codes(const Image *img) {
  size_t n = (size_t)img->width * img->height;
  int nc = img->channels, colour = nc >= 3;
  uint8_t *g = xmalloc(n);
  for (size_t i = 0; i < n; i++) {
    const float *p = img->data + i * nc;
    if (!colour) { g[i] = image_linear_to_srgb8(p[0]); continue; }
    unsigned r = image_linear_to_srgb8(p[0]), gr = image_linear_to_srgb8(p[1]), b = image_linear_to_srgb8(p[2]);
    g[i] = (uint8_t)((r * 4899 + gr * 9617 + b * 1868 + 8192) >> 14);
  }
  return g;
}

/* ---- the cache ------------------------------------------------------------------ */

typedef struct CacheEntry {
  struct CacheEntry *next;
  char *path;
  double window, clip;
  long long size, mtime_ns;
  ThresholdTexture *tex;
} CacheEntry;

static CacheEntry *cache;
static pthread_mutex_t cache_lock = PTHREAD_MUTEX_INITIALIZER;

const ThresholdTexture *texture_threshold(const char *path, double window, double clip, char *err,
                                          size_t errlen) {
  struct stat st;
  if (stat(path, &st) != 0) {
    snprintf(err, errlen, "%s: no such file", path);
    return NULL;
  }
  long long mtime = (long long)st.st_mtim.tv_sec * 1000000000LL + st.st_mtim.tv_nsec;
  pthread_mutex_lock(&cache_lock);
  for (CacheEntry *e = cache; e; e = e->next)
    if (!strcmp(e->path, path) && e->window == window && e->clip == clip && e->size == st.st_size &&
        e->mtime_ns == mtime) {
      pthread_mutex_unlock(&cache_lock);
      return e->tex;
    }
  Image *img = NULL;
  ThresholdTexture *tex = NULL;
  if (image_read(path, &img, err, errlen)) {
    uint8_t *g = grey_codes(img);
    tex = texture_build(g, img->width, img->height, window, clip);
    free(g);
    image_destroy(img);
    CacheEntry *e = xcalloc(1, sizeof *e);
    *e = (CacheEntry){cache, xstrdup(path), window, clip, st.st_size, mtime, tex};
    cache = e;
  }
  pthread_mutex_unlock(&cache_lock);
  return tex;
}

void texture_cache_clear(void) {
  pthread_mutex_lock(&cache_lock);
  while (cache) {
    CacheEntry *e = cache;
    cache = e->next;
    texture_free(e->tex);
    free(e->path);
    free(e);
  }
  pthread_mutex_unlock(&cache_lock);
}

/* ---- sampling ------------------------------------------------------------------- */

/* i mod n, for any i. */
static inline int wrap(int i, int n) {
  int r = i % n;
  return r < 0 ? r + n : r;
}

/* Level k's texel coordinates of (u, v): the texel grid's x and y (texel
** centres at half-integers become integers). */
static inline void texel_coords(const TextureLevel *l, float u, float v, float *x, float *y) {
  float fu = u - floorf(u), fv = v - floorf(v);
  *x = fu * (float)l->w - 0.5f;
  *y = (1 - fv) * (float)l->h - 0.5f;   /* the first row at the top */
}

void texture_level_taps(const ThresholdTexture *t, int k, float u, float v, float q[4], float w[4]) {
  const TextureLevel *l = &t->level[k];
  float x, y;
  texel_coords(l, u, v, &x, &y);
  float fx = floorf(x), fy = floorf(y), ax = x - fx, ay = y - fy;
  int x0 = wrap((int)fx, l->w), x1 = wrap((int)fx + 1, l->w);
  int y0 = wrap((int)fy, l->h), y1 = wrap((int)fy + 1, l->h);
  const uint16_t *r0 = l->texels + (size_t)y0 * l->w, *r1 = l->texels + (size_t)y1 * l->w;
  const float k16 = 1.0f / 65536;
  q[0] = r0[x0] * k16; w[0] = (1 - ax) * (1 - ay);
  q[1] = r0[x1] * k16; w[1] = ax * (1 - ay);
  q[2] = r1[x0] * k16; w[2] = (1 - ax) * ay;
  q[3] = r1[x1] * k16; w[3] = ax * ay;
}

float texture_level_nearest(const ThresholdTexture *t, int k, float u, float v) {
  const TextureLevel *l = &t->level[k];
  float x, y;
  texel_coords(l, u, v, &x, &y);
  int xi = wrap((int)floorf(x + 0.5f), l->w), yi = wrap((int)floorf(y + 0.5f), l->h);
  return l->texels[(size_t)yi * l->w + xi] * (1.0f / 65536);
}

void texture_lod(const ThresholdTexture *t, float rate, int *k0, int *k1, float *w1) {
  float lod = rate > 1 ? log2f(rate) : 0;
  float top = (float)(t->nlevels - 1);
  if (!(lod < top)) lod = top;   /* also NaN */
  int k = (int)lod;
  *k0 = k;
  *k1 = k + 1 < t->nlevels ? k + 1 : k;
  *w1 = lod - (float)k;
}
