/*
** Tileable noise and wrapping texture tiles (noise.h): the seeded gradient
** lattices, fractal sums, baking into a tile, the chain of levels, and
** bilinear reads with wrap-around.
*/
#include "noise.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"
#include "../base/rng.h"

/* ---- fractal gradient noise ------------------------------------------------ */

void noise_fbm_init(NoiseFbm *n, int cells, int octaves, float gain, uint64_t seed) {
  memset(n, 0, sizeof *n);
  n->cells = cells < 1 ? 1 : cells;
  n->octaves = octaves < 1 ? 1 : octaves > NOISE_MAX_OCTAVES ? NOISE_MAX_OCTAVES : octaves;
  n->gain = gain;
  for (int k = 0; k < n->octaves; k++) {
    size_t p = (size_t)n->cells << k, count = p * p;
    float *g = n->grad[k] = xmalloc(2 * count * sizeof *g);
    Rng r;
    rng_seed_key(&r, seed, (uint32_t)k, 0);   /* one stream per octave */
    for (size_t i = 0; i < count; i++) {
      double a = 2 * M_PI * rng_uniform(&r);
      g[2 * i] = (float)cos(a);
      g[2 * i + 1] = (float)sin(a);
    }
  }
}

void noise_fbm_free(NoiseFbm *n) {
  for (int k = 0; k < NOISE_MAX_OCTAVES; k++) free(n->grad[k]);
  memset(n, 0, sizeof *n);
}

/* Perlin's quintic fade: 6t^5 - 15t^4 + 10t^3 (zero slope and curvature at 0 and 1). */
static inline float fade(float t) { return t * t * t * (t * (t * 6 - 15) + 10); }

/* floorf(v), to the bit, without the library call where v fits an int
** (an integral v, -0 too, is its own floor). */
static inline float floor_of(float v) {
  if (!(v > -2147483648.0f && v < 2147483648.0f)) return floorf(v);
  float t = (float)(int)v;
  return t > v ? t - 1 : t == v ? v : t;
}

/* Coordinate V (in cells) on a periodic lattice of p cells a side. */
static void axis_of(int p, float V, NoiseAxis *a) {
  float f = floor_of(V);
  int i0, m = p - 1;
  if ((p & m) == 0) {   /* a power of two (the usual lattices): the remainder is a mask */
    i0 = (int)f & m;
  } else {
    i0 = (int)f % p;
    if (i0 < 0) i0 += p;
  }
  a->i0 = i0;
  a->i1 = i0 + 1 == p ? 0 : i0 + 1;
  a->t = V - f;
  a->fade = fade(a->t);
}

/* One octave: gradient noise over a periodic p x p lattice at the point of axes ax and ay. */
static float noise_at(const float *grad, int p, const NoiseAxis *ax, const NoiseAxis *ay) {
  float x = ax->t, y = ay->t;
  const float *g00 = grad + 2 * (ay->i0 * p + ax->i0), *g10 = grad + 2 * (ay->i0 * p + ax->i1);
  const float *g01 = grad + 2 * (ay->i1 * p + ax->i0), *g11 = grad + 2 * (ay->i1 * p + ax->i1);
  float d00 = g00[0] * x + g00[1] * y, d10 = g10[0] * (x - 1) + g10[1] * y;
  float d01 = g01[0] * x + g01[1] * (y - 1), d11 = g11[0] * (x - 1) + g11[1] * (y - 1);
  float u = ax->fade, v = ay->fade;
  float a = d00 + u * (d10 - d00), b = d01 + u * (d11 - d01);
  return (a + v * (b - a)) * 1.41421356f;   /* 2D gradient noise spans +-1/sqrt(2) */
}

/* The same at (X, Y) in cells. */
static float gradient_noise(const float *grad, int p, float X, float Y) {
  NoiseAxis ax, ay;
  axis_of(p, X, &ax);
  axis_of(p, Y, &ay);
  return noise_at(grad, p, &ax, &ay);
}

void noise_axis(const NoiseFbm *n, float v, NoiseAxis *a) {
  axis_of(n->cells, v * (float)n->cells, a);
}

float noise_fbm_axes(const NoiseFbm *n, const NoiseAxis *ax, const NoiseAxis *ay) {
  return 0.0f + noise_at(n->grad[0], n->cells, ax, ay);   /* noise_fbm_eval's sum of one */
}

float noise_fbm_eval(const NoiseFbm *n, float x, float y) {
  if (n->octaves == 1)   /* the sum below, to the bit: 0 + 1 g, over 1 */
    return 0.0f + gradient_noise(n->grad[0], n->cells, x * (float)n->cells, y * (float)n->cells);
  float sum = 0, amp = 1, total = 0;
  for (int k = 0; k < n->octaves; k++) {
    int p = n->cells << k;
    sum += amp * gradient_noise(n->grad[k], p, x * p, y * p);
    total += amp;
    amp *= n->gain;
  }
  return sum / total;
}

/* ---- tiles ------------------------------------------------------------------ */

static int stride_of(const NoiseTile *t) { return t->channels + t->has_alpha; }

/* Level k + 1 from level k: each texel the mean of a 2 x 2 block (wrapping
** where a side is odd), down to 1 x 1 or NOISE_MAX_LEVELS levels. */
static void build_levels(NoiseTile *t) {
  int s = stride_of(t);
  while (t->levels < NOISE_MAX_LEVELS && (t->w[t->levels - 1] > 1 || t->h[t->levels - 1] > 1)) {
    int k = t->levels, pw = t->w[k - 1], ph = t->h[k - 1];
    int w = pw > 1 ? pw / 2 : 1, h = ph > 1 ? ph / 2 : 1;
    const float *src = t->texel[k - 1];
    float *dst = t->texel[k] = xmalloc((size_t)w * h * s * sizeof *dst);
    for (int j = 0; j < h; j++)
      for (int i = 0; i < w; i++) {
        int x0 = (2 * i) % pw, x1 = (2 * i + 1) % pw, y0 = (2 * j) % ph, y1 = (2 * j + 1) % ph;
        for (int c = 0; c < s; c++)
          dst[((size_t)j * w + i) * s + c] =
              0.25f * (src[((size_t)y0 * pw + x0) * s + c] + src[((size_t)y0 * pw + x1) * s + c] +
                       src[((size_t)y1 * pw + x0) * s + c] + src[((size_t)y1 * pw + x1) * s + c]);
      }
    t->w[k] = w;
    t->h[k] = h;
    t->levels++;
  }
}

static void set_mean(NoiseTile *t) {
  int s = stride_of(t);
  size_t n = (size_t)t->w[0] * t->h[0];
  for (int c = 0; c < s; c++) {
    double sum = 0;
    for (size_t i = 0; i < n; i++) sum += t->texel[0][i * s + c];
    t->mean[c] = (float)(sum / (double)(n ? n : 1));
  }
}

/* One row's texels q0 .. q1 - 1 in one cell, whose corner gradients give
** the coefficients c (ax, ay, bx, by, cx, cy, ex, ey: ay .. ey scaled by
** the row's place y in the cell), fv the row's fade: adds amp times the
** noise to out. */
static void add_cell_run(float *restrict out, const float *restrict frac, const float *restrict fd, int q0,
                         int q1, const float c[8], float fv, float amp) {
  float ax = c[0], ay = c[1], bx = c[2], by = c[3], cx = c[4], cy = c[5], ex = c[6], ey = c[7];
  for (int q = q0; q < q1; q++) {
    float x = frac[q];
    float d00 = ax * x + ay, d10 = bx * (x - 1) + by, d01 = cx * x + cy, d11 = ex * (x - 1) + ey;
    float a = d00 + fd[q] * (d10 - d00), b = d01 + fd[q] * (d11 - d01);
    out[q] += amp * ((a + fv * (b - a)) * 1.41421356f);
  }
}

/* Add amp times octave k of n over a size x size grid of texel centres
** into v, cell by cell: a cell's four gradients hold over its texels, and
** each texel's place in its cell comes from its column and row alone. The
** same values as gradient_noise at ((i + 0.5) / size) p. */
static void add_octave(const NoiseFbm *n, int k, int size, float amp, float *v) {
  int p = n->cells << k;
  const float *grad = n->grad[k];
  int *cell = xmalloc((size_t)size * sizeof *cell), *run = xmalloc((size_t)(size + 1) * sizeof *run);
  float *frac = xmalloc((size_t)size * sizeof *frac), *fd = xmalloc((size_t)size * sizeof *fd);
  int runs = 0;   /* run[r] .. run[r + 1] - 1: the texels of one cell along a row */
  for (int i = 0; i < size; i++) {
    float X = (i + 0.5f) / size * p, f = floorf(X);
    cell[i] = (int)f % p;
    frac[i] = X - f;
    fd[i] = fade(frac[i]);
    if (i == 0 || cell[i] != cell[i - 1]) run[runs++] = i;
  }
  run[runs] = size;
  for (int j = 0; j < size; j++) {
    int j0 = cell[j], j1 = j0 + 1 == p ? 0 : j0 + 1;
    float y = frac[j], fv = fd[j];
    for (int r = 0; r < runs; r++) {
      int i0 = cell[run[r]], i1 = i0 + 1 == p ? 0 : i0 + 1;
      const float *g00 = grad + 2 * (j0 * p + i0), *g10 = grad + 2 * (j0 * p + i1);
      const float *g01 = grad + 2 * (j1 * p + i0), *g11 = grad + 2 * (j1 * p + i1);
      float c[8] = {g00[0], g00[1] * y, g10[0], g10[1] * y, g01[0], g01[1] * (y - 1), g11[0], g11[1] * (y - 1)};
      add_cell_run(v + (size_t)j * size, frac, fd, run[r], run[r + 1], c, fv, amp);
    }
  }
  free(run);
  free(cell);
  free(frac);
  free(fd);
}

void noise_tile_bake(NoiseTile *t, const NoiseFbm *n, int size) {
  memset(t, 0, sizeof *t);
  t->channels = 1;
  t->levels = 1;
  t->w[0] = t->h[0] = size;
  size_t count = (size_t)size * size;
  float *v = t->texel[0] = xcalloc(count, sizeof *v);
  float amp = 1, total = 0;
  for (int k = 0; k < n->octaves; k++, amp *= n->gain) {
    add_octave(n, k, size, amp, v);
    total += amp;
  }
  double sum = 0;
  for (size_t i = 0; i < count; i++) sum += v[i] /= total;
  float mean = (float)(sum / (double)count), dev = 0;
  for (size_t i = 0; i < count; i++) {
    float d = fabsf(v[i] - mean);
    dev = d > dev ? d : dev;   /* fmaxf would be a call a texel */
  }
  float k = dev > 0 ? 0.5f / dev : 0;   /* the widest deviation reaches 0 or 1 */
  for (size_t i = 0; i < count; i++) v[i] = 0.5f + (v[i] - mean) * k;
  set_mean(t);
  build_levels(t);
}

void noise_tile_from_image(NoiseTile *t, const Image *img) {
  memset(t, 0, sizeof *t);
  int nc = img->channels;
  t->channels = nc >= 3 ? 3 : 1;
  t->has_alpha = nc == 2 || nc == 4;
  t->levels = 1;
  t->w[0] = img->width;
  t->h[0] = img->height;
  size_t n = (size_t)img->width * img->height;
  int s = stride_of(t);
  float *dst = t->texel[0] = xmalloc(n * s * sizeof *dst);
  float *lin = NULL;
  const float *src = img->data;
  if (!src) {   /* an 8-bit image: its codes' linear values */
    lin = xmalloc(n * nc * sizeof *lin);
    image_decode8(img->data8, lin, n, nc);
    src = lin;
  }
  for (size_t i = 0; i < n; i++)
    for (int c = 0; c < s; c++) dst[i * s + c] = src[i * nc + (c < nc ? c : nc - 1)];
  free(lin);
  set_mean(t);
  build_levels(t);
}

void noise_tile_free(NoiseTile *t) {
  for (int k = 0; k < NOISE_MAX_LEVELS; k++) free(t->texel[k]);
  memset(t, 0, sizeof *t);
}

int noise_tile_level(const NoiseTile *t, float texels_per_sample) {
  int k = 0;   /* a texel of level k + 1 spans w[0] / w[k + 1] level-0 texels */
  while (k + 1 < t->levels &&
         fminf((float)t->w[0] / t->w[k + 1], (float)t->h[0] / t->h[k + 1]) <= texels_per_sample)
    k++;
  return k;
}

/* x wrapped into [0, n). */
static inline float wrapf(float x, int n) {
  x -= (float)n * floorf(x / (float)n);
  return x < (float)n ? x : 0;   /* rounding can land on n itself */
}

void noise_tile_sample(const NoiseTile *t, int level, float u, float v, float *out) {
  int w = t->w[level], h = t->h[level], s = stride_of(t);
  /* into level texels, centres at +0.5 */
  float x = wrapf(u * ((float)w / t->w[0]) - 0.5f, w), y = wrapf(v * ((float)h / t->h[0]) - 0.5f, h);
  int i0 = (int)x, j0 = (int)y;
  float a = x - (float)i0, b = y - (float)j0;
  int i1 = i0 + 1 == w ? 0 : i0 + 1, j1 = j0 + 1 == h ? 0 : j0 + 1;
  const float *T = t->texel[level];
  const float *p00 = T + ((size_t)j0 * w + i0) * s, *p10 = T + ((size_t)j0 * w + i1) * s;
  const float *p01 = T + ((size_t)j1 * w + i0) * s, *p11 = T + ((size_t)j1 * w + i1) * s;
  for (int c = 0; c < s; c++) {
    float top = p00[c] + a * (p10[c] - p00[c]), bottom = p01[c] + a * (p11[c] - p01[c]);
    out[c] = top + b * (bottom - top);
  }
}

void noise_tile_row(const NoiseTile *t, int level, float u0, float du, float v, int n, float *out) {
  int w = t->w[level], h = t->h[level];
  float sx = (float)w / t->w[0], sy = (float)h / t->h[0];
  float y = wrapf(v * sy - 0.5f, h), x0 = wrapf(u0 * sx - 0.5f, w), dx = du * sx;
  int j0 = (int)y, j1 = j0 + 1 == h ? 0 : j0 + 1;
  float b = y - (float)j0;
  const float *r0 = t->texel[level] + (size_t)j0 * w, *r1 = t->texel[level] + (size_t)j1 * w;
  int pow2 = (w & (w - 1)) == 0, mask = w - 1;
  int at = -1;                    /* the texel whose values and steps t0 .. d1 hold */
  float t0 = 0, d0 = 0, t1 = 0, d1 = 0;
  for (int k = 0; k < n; k++) {
    float x = x0 + (float)k * dx;   /* >= 0: its int part is its floor */
    int i = (int)x;
    float a = x - (float)i;
    if (i != at) {                /* a magnified tile: several samples a texel */
      int i0 = pow2 ? i & mask : i % w, i1 = pow2 ? (i + 1) & mask : (i + 1) % w;
      t0 = r0[i0], d0 = r0[i1] - r0[i0], t1 = r1[i0], d1 = r1[i1] - r1[i0];
      at = i;
    }
    float top = t0 + a * d0, bottom = t1 + a * d1;
    out[k] = top + b * (bottom - top);
  }
}
