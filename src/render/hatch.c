/*
** Procedural threshold textures (hatch.h): the dyadic scale, the uniform
** multi-scale sawtooth with its box-filtered coverage, stipple dots, and
** value noise.
*/
#include "hatch.h"

#include <math.h>
#include <pthread.h>

#include "../base/lanes.h"

/* ---- lines ---------------------------------------------------------------- */

/* F(f, t) of eq. 8 on one period f in [0, 1): (1 + t) f, less t past 1/2. */
static inline float blend_sawtooth(float f, float t) {
  return (1 + t) * f - (f < 0.5f ? 0 : t);
}

/* The cumulative distribution of F(., t) at z: density c = 1 / (1 + t) below
** a = (1 - t) / 2 and from b = (1 + t) / 2 on, 2c in between. */
static inline float blend_cdf(float z, float t) {
  float c = 1 / (1 + t), a = 0.5f - 0.5f * t, b = 0.5f + 0.5f * t;
  if (z < a) return c * z;
  if (z < b) return c * (a + 2 * (z - a));
  return c * (a + 2 * t + (z - b));
}

float hatch_value(float x, float t) {
  float f = x - floorf(x);
  float q = blend_cdf(blend_sawtooth(f, t), t);
  return q < 1 ? q : 0.99999994f;
}

/* The bright length of [0, X) (hatch_bright_i) in lanes. */
static inline F4 bright_i4(F4 X, F4 y, F4 lo, F4 hi) {
  F4 k = f4_floor(X), f = f4_sub(X, k), g = f4_min(f, hi);
  /* g > 1/2 ? g - 1/2 : 0 is max(g - 1/2, 0): g - 1/2 is exact there (g <= 1) */
  return f4_add(f4_add(f4_mul(k, y), f4_min(f, lo)), f4_max(f4_sub(g, f4_set(0.5f)), f4_set(0)));
}

/* hatch_coverage_c in lanes, operation for operation (the same bits);
** with `boxed` every lane's footprint is known to be over 1e-6 (the
** filtered case), so the step at x alone is not worked out. */
static inline F4 coverage4(F4 x, F4 fw, F4 t, F4 c, F4 y, int boxed) {
  F4 zero = f4_set(0), half = f4_set(0.5f), one = f4_set(1);
  y = f4_min(f4_max(y, zero), one);
  F4 a = f4_sub(half, f4_mul(half, t)), yc = f4_mul(y, f4_add(one, t));
  F4 mid = f4_add(a, f4_mul(f4_sub(yc, a), half)), top = f4_sub(yc, t);
  F4 z = f4_select(f4_lt(yc, a), yc, mid);
  z = f4_select(f4_lt(yc, f4_add(a, f4_mul(f4_set(2), t))), z, top);
  F4 lo = f4_min(f4_max(f4_mul(z, c), zero), half);
  F4 hi = f4_min(f4_max(f4_mul(f4_add(z, t), c), half), one);
  F4 h = f4_mul(half, fw);
  F4 len = f4_sub(bright_i4(f4_add(x, h), y, lo, hi), bright_i4(f4_sub(x, h), y, lo, hi));
  if (boxed) return f4_min(f4_max(f4_div(len, fw), zero), one);
  M4 in = m4_or(f4_le(x, lo), m4_and(f4_le(half, x), f4_le(x, hi)));
  M4 wide = f4_lt(f4_set(1e-6f), fw);
  F4 r = f4_select(wide, f4_div(len, f4_select(wide, fw, one)), f4_keep(in, one));
  return f4_min(f4_max(r, zero), one);
}

void hatch_coverage_run(const float *x, const float *fw, const float *t, const float *c, const float *y,
                        float lo, float inv, float *bright, int j0, int j1) {
  F4 flo = f4_set(lo), finv = f4_set(inv);
  int j = j0;
  for (; j + 4 <= j1; j += 4) {
    F4 yl = f4_mul(f4_sub(f4_load(y + j), flo), finv), w = f4_load(fw + j);
    F4 r = m4_bits(f4_lt(f4_set(1e-6f), w)) == 15 ? coverage4(f4_load(x + j), w, f4_load(t + j), f4_load(c + j), yl, 1)
                                                 : coverage4(f4_load(x + j), w, f4_load(t + j), f4_load(c + j), yl, 0);
    f4_store(bright + j, f4_mul(f4_load(bright + j), r));
  }
  for (; j < j1; j++) bright[j] *= hatch_coverage_c(x[j], fw[j], t[j], c[j], (y[j] - lo) * inv);
}

/* ---- stipple dots ------------------------------------------------------------ */

/* The squared distance to the nearest dot centre at the coarse scale,
** r0^2, and at the next, r1^2, blended by t: B in [0, 1/2]. */
static inline float dot_blend(float a, float b, float t) {
  float fa = a - floorf(a), fb = b - floorf(b);
  float ga = 2 * fa - floorf(2 * fa), gb = 2 * fb - floorf(2 * fb);   /* the quarter cells */
  float r0 = (fa - 0.5f) * (fa - 0.5f) + (fb - 0.5f) * (fb - 0.5f);
  float r1 = (ga - 0.5f) * (ga - 0.5f) + (gb - 0.5f) * (gb - 0.5f);
  return (1 - t) * r0 + t * r1;
}

/* The distribution of dot_blend over a cell, tabulated at STIP_T + 1 blends
** and STIP_V + 1 values in [0, 1/2], from a STIP_GRID^2 grid of points. */
enum { STIP_T = 16, STIP_V = 256, STIP_GRID = 256 };
static float stipple_cdf[STIP_T + 1][STIP_V + 1];
static pthread_once_t stipple_once = PTHREAD_ONCE_INIT;

static void stipple_table(void) {
  for (int i = 0; i <= STIP_T; i++) {
    static unsigned count[STIP_V + 1];
    for (int j = 0; j <= STIP_V; j++) count[j] = 0;
    float t = (float)i / STIP_T;
    for (int y = 0; y < STIP_GRID; y++)
      for (int x = 0; x < STIP_GRID; x++) {
        float v = dot_blend((x + 0.5f) / STIP_GRID, (y + 0.5f) / STIP_GRID, t);
        int j = (int)ceilf(v * (2 * STIP_V));   /* the first edge at or above v */
        count[j < STIP_V ? j : STIP_V]++;
      }
    unsigned run = 0;
    for (int j = 0; j <= STIP_V; j++) {
      run += count[j];
      stipple_cdf[i][j] = (float)run / (STIP_GRID * STIP_GRID);
    }
  }
}

/* The tabulated distribution at blend t and value v, bilinear. */
static float stipple_distribution(float v, float t) {
  float pv = v * (2 * STIP_V), pt = t * STIP_T;
  int j = (int)pv, i = (int)pt;
  j = j < 0 ? 0 : j >= STIP_V ? STIP_V - 1 : j;
  i = i < 0 ? 0 : i >= STIP_T ? STIP_T - 1 : i;
  float fv = fminf(fmaxf(pv - j, 0), 1), ft = fminf(fmaxf(pt - i, 0), 1);
  float c0 = stipple_cdf[i][j] + fv * (stipple_cdf[i][j + 1] - stipple_cdf[i][j]);
  float c1 = stipple_cdf[i + 1][j] + fv * (stipple_cdf[i + 1][j + 1] - stipple_cdf[i + 1][j]);
  return c0 + ft * (c1 - c0);
}

float stipple_value(float a, float b, float t) {
  pthread_once(&stipple_once, stipple_table);
  float q = 1 - stipple_distribution(dot_blend(a, b, t), t);
  return q < 1 ? (q > 0 ? q : 0) : 0.99999994f;
}

/* ---- noise ------------------------------------------------------------------ */

/* A lattice point's value in [0, 1): a murmur-style mix of its coordinates. */
static inline float lattice(int32_t x, int32_t y, uint32_t seed) {
  uint32_t h = (uint32_t)x * 0x8da6b343u ^ (uint32_t)y * 0xd8163841u ^ seed * 0xcb1ab31fu;
  h ^= h >> 16;
  h *= 0x85ebca6bu;
  h ^= h >> 13;
  h *= 0xc2b2ae35u;
  h ^= h >> 16;
  return (float)(h >> 8) * (1.0f / 16777216.0f);
}

float hatch_noise(float u, float v, uint32_t seed) {
  float fu = floorf(u), fv = floorf(v);
  if (!(fabsf(fu) < 1e9f && fabsf(fv) < 1e9f)) return 0.5f;   /* far off, or NaN */
  int32_t x = (int32_t)fu, y = (int32_t)fv;
  float du = u - fu, dv = v - fv;
  float su = du * du * (3 - 2 * du), sv = dv * dv * (3 - 2 * dv);   /* smoothstep: C1 */
  float a = lattice(x, y, seed), b = lattice(x + 1, y, seed);
  float c = lattice(x, y + 1, seed), d = lattice(x + 1, y + 1, seed);
  float top = a + su * (b - a), bottom = c + su * (d - c);
  return top + sv * (bottom - top);
}
