/*
** Procedural threshold textures (002 section 3.2): hatching lines and
** stipple dots whose thresholds are uniformly distributed at every scale,
** so that thresholding a constant shade x over them inks 1 - x of the area,
** and whose on-screen spacing stays within a factor 2 of the one asked for
** while the surface zooms; plus the smooth value noise that displaces any
** threshold texture.
**
** Lines are a function of one texture coordinate h (they run along the
** iso-lines of h). With d the screen distance between the iso-lines h and
** h + 1 and w the wanted spacing, the dyadic scale is s = log2(d / w)
** (eq. 5); the texture is read at x = 2^floor(s) h (eq. 6), where the base
** function f(x) = frac(x), a sawtooth, gives F(x, 0) and the next scale
** F(x, 1) = F(2x, 0) or F(2x - 1, 0) (eq. 7), blended as
** F(x, t) = (1 - t) F(x, 0) + t F(x, 1) with t = frac(s) (eq. 8).
**
** The blend of eq. 8 is not uniform: its density is 2 / (1 + t) over
** [(1 - t) / 2, (1 + t) / 2) and 1 / (1 + t) elsewhere, so a constant shade
** would change tone as the scale moves between powers of two (by up to
** 0.08 of the range at t = 1/2). sumi maps F(x, t) through its own
** cumulative distribution, piecewise linear and known in closed form: the
** result is exactly uniform at every t, and, the map being increasing,
** keeps F's order, so the minima and maxima of consecutive scales still
** match. The same is done for stipple dots, whose distribution is
** tabulated once.
**
** A threshold q is met (the sample stays bright) where the shade y >= q;
** hatch_coverage gives the fraction of a box footprint that is bright,
** the analytic percentage-closer filter of section 4.
*/
#ifndef render_hatch_h
#define render_hatch_h

#include <stdint.h>

/* floor(x) for |x| < 2^31, without a library call (so loops of it run
** side by side in SIMD lanes). */
static inline float hatch_floor(float x) {
  float t = (float)(int)x;   /* toward zero */
  return t > x ? t - 1 : t;
}

/* The dyadic scale of a texture coordinate whose screen gradient has
** length g (per pixel) for a spacing of w pixels: *m = 2^floor(s) (the
** lines per unit of the coordinate at the coarse scale) and the blend
** *t in [0, 1), s = log2(1 / (g w)) (eq. 5). floor(s) comes exactly from
** the exponent of 1 / (g w); t is frac(s) to within 0.0015 (a cubic in
** the mantissa), continuous and increasing in s, 0 at the powers of two.
** s is kept within [-HATCH_MAX_OCTAVES, HATCH_MAX_OCTAVES]. */
#define HATCH_MAX_OCTAVES 30
static inline void hatch_scale(float g, float w, float *m, float *t) {
  float d = 1 / (g * w);   /* the iso-lines' spacing in units of w */
  d = d > 0x1p-30f ? (d < 0x1p30f ? d : 0x1p30f) : 0x1p-30f;   /* g = 0: d = inf; NaN: 2^-30 */
  union { float f; int32_t i; } b = {d}, e;
  e.i = b.i & 0x7f800000;               /* 2^floor(log2 d) */
  b.i = (b.i & 0x007fffff) | 0x3f800000;  /* the mantissa, in [1, 2) */
  float f = b.f - 1;
  *m = e.f;
  *t = f + f * (1 - f) * (0.42086f - 0.15639f * f);   /* log2(1 + f) */
}

/* The uniform multi-scale line threshold at x (= 2^floor(s) h) and blend
** t in [0, 1): eq. 6-8 mapped to the uniform distribution. In [0, 1). */
float hatch_value(float x, float t);

/* The bright part of a period for shade y in [0, 1] and blend t (c = 1 /
** (1 + t)): where F(x, t) <= z, z the point where F's distribution reaches
** y, that is [0, lo] and [1/2, hi] with lo + hi - 1/2 = y. With yc = y (1 +
** t): z = yc below a = (1 - t) / 2, a + (yc - a) / 2 up to a + 2t, yc - t
** past it (the density there is back to c, and b - a - 2t = -t). */
static inline void hatch_bright_ends(float t, float c, float y, float *lo, float *hi) {
  float a = 0.5f - 0.5f * t, yc = y * (1 + t);
  float mid = a + (yc - a) * 0.5f, top = yc - t;
  float z = yc < a ? yc : mid;
  z = yc < a + 2 * t ? z : top;
  float l = z * c, h = (z + t) * c;
  l = l > 0 ? l : 0;
  h = h > 0.5f ? h : 0.5f;
  *lo = l < 0.5f ? l : 0.5f;
  *hi = h < 1 ? h : 1;
}

/* The bright length of [0, x): floor(x) y plus the last period's part. */
static inline float hatch_bright_i(float x, float y, float lo, float hi) {
  float k = hatch_floor(x), f = x - k;
  float g = f < hi ? f : hi;
  return k * y + (f < lo ? f : lo) + (g > 0.5f ? g - 0.5f : 0);
}

/* The fraction of the footprint [x - fw / 2, x + fw / 2] that is bright
** for shade y over the lines at x (in [0, 1), the position in the period)
** and blend t (c = 1 / (1 + t)): the threshold box-filtered exactly, a
** difference of two bright lengths; the value at x alone when fw is under
** 1e-6. y outside [0, 1] counts as its end. A footprint past 16 periods is
** the caller's to cap (whole periods give y; the lengths lose precision).
** Selects of one level only, no calls: loops of it run in SIMD lanes. */
static inline float hatch_coverage_c(float x, float fw, float t, float c, float y) {
  y = y > 0 ? y : 0;
  y = y < 1 ? y : 1;
  float lo, hi;
  hatch_bright_ends(t, c, y, &lo, &hi);
  float step = (x <= lo) | ((x >= 0.5f) & (x <= hi)) ? 1.0f : 0.0f;
  float h = 0.5f * fw, wide = fw > 1e-6f;
  float box = (hatch_bright_i(x + h, y, lo, hi) - hatch_bright_i(x - h, y, lo, hi)) / (wide ? fw : 1);
  float r = wide ? box : step;
  r = r > 0 ? r : 0;
  return r < 1 ? r : 1;
}

/* bright[j] *= hatch_coverage_c(x[j], fw[j], t[j], c[j], (y[j] - lo) * inv)
** for j in [j0, j1): four lanes at a time (the rest one by one), the
** same bits. */
void hatch_coverage_run(const float *x, const float *fw, const float *t, const float *c, const float *y,
                        float lo, float inv, float *bright, int j0, int j1);

static inline float hatch_coverage(float x, float fw, float t, float y) {
  return hatch_coverage_c(x, fw < 16 ? fw : 16, t, 1 / (1 + t), y);
}

/* The uniform multi-scale dot threshold at cell coordinates (a, b)
** (= 2^floor(s) times the texture coordinates): round dots centred in the
** unit cells, high at the centres (ink gathers there first), the next
** scale's dots in the four quarter cells, blended by t as eq. 8 blends
** lines. In [0, 1). */
float stipple_value(float a, float b, float t);

/* Smooth value noise in [0, 1) at (u, v): a lattice of hashed values
** (one per unit cell corner, from seed) blended with a C1 smoothstep. */
float hatch_noise(float u, float v, uint32_t seed);

#endif
