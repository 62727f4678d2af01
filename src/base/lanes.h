/*
** Four float lanes side by side, for the inner loops the compiler cannot
** turn into SIMD code well by itself: a loop of clamps and selects, with
** x86-64's baseline SSE2 (no blend instruction), becomes compares and
** masks, four or five instructions a select where a minimum or maximum
** is one. Here `f4_min(a, b)` is exactly `a < b ? a : b` and `f4_max(a,
** b)` exactly `a > b ? a : b` (SSE's MINPS and MAXPS are defined so; a NaN
** gives b), so code written with these gives the same bits as the scalar
** code it mirrors, operation for operation, on any target: where SSE2 is
** missing the lanes are a struct of four floats done one at a time.
*/
#ifndef base_lanes_h
#define base_lanes_h

#include <stdint.h>

#if defined(__SSE2__)
#include <emmintrin.h>

typedef __m128 F4;   /* four floats */
typedef __m128 M4;   /* four lanes' conditions: all bits set or clear */

static inline F4 f4_load(const float *p) { return _mm_loadu_ps(p); }
static inline void f4_store(float *p, F4 a) { _mm_storeu_ps(p, a); }
/* r, g, b interleaved: p[0..11] = r0 g0 b0 r1 g1 b1 ... */
static inline void f4_store_rgb(float *p, F4 r, F4 g, F4 b) {
  __m128 rg_lo = _mm_unpacklo_ps(r, g), rg_hi = _mm_unpackhi_ps(r, g);   /* r0 g0 r1 g1, r2 g2 r3 g3 */
  __m128 b_lo = _mm_shuffle_ps(b, b, _MM_SHUFFLE(1, 1, 0, 0)), b_hi = _mm_shuffle_ps(b, b, _MM_SHUFFLE(3, 3, 2, 2));
  _mm_storeu_ps(p, _mm_shuffle_ps(rg_lo, b_lo, _MM_SHUFFLE(0, 0, 1, 0)));       /* r0 g0 b0 b0 */
  _mm_storeu_ps(p + 3, _mm_shuffle_ps(rg_lo, b_lo, _MM_SHUFFLE(2, 2, 3, 2)));   /* r1 g1 b1 b1 */
  _mm_storeu_ps(p + 6, _mm_shuffle_ps(rg_hi, b_hi, _MM_SHUFFLE(0, 0, 1, 0)));   /* r2 g2 b2 b2 */
  float last[4];
  _mm_storeu_ps(last, _mm_shuffle_ps(rg_hi, b_hi, _MM_SHUFFLE(2, 2, 3, 2)));    /* r3 g3 b3 */
  p[9] = last[0]; p[10] = last[1]; p[11] = last[2];
}
/* four pairs p[0..7] apart: *a = p[0], p[2], p[4], p[6], *b = p[1], p[3], ... */
static inline void f4_load_pairs(const float *p, F4 *a, F4 *b) {
  __m128 lo = _mm_loadu_ps(p), hi = _mm_loadu_ps(p + 4);
  *a = _mm_shuffle_ps(lo, hi, _MM_SHUFFLE(2, 0, 2, 0));
  *b = _mm_shuffle_ps(lo, hi, _MM_SHUFFLE(3, 1, 3, 1));
}
static inline F4 f4_set(float x) { return _mm_set1_ps(x); }
static inline F4 f4_add(F4 a, F4 b) { return _mm_add_ps(a, b); }
static inline F4 f4_sub(F4 a, F4 b) { return _mm_sub_ps(a, b); }
static inline F4 f4_mul(F4 a, F4 b) { return _mm_mul_ps(a, b); }
static inline F4 f4_div(F4 a, F4 b) { return _mm_div_ps(a, b); }
static inline F4 f4_min(F4 a, F4 b) { return _mm_min_ps(a, b); }   /* a < b ? a : b */
static inline F4 f4_max(F4 a, F4 b) { return _mm_max_ps(a, b); }   /* a > b ? a : b */
static inline M4 f4_lt(F4 a, F4 b) { return _mm_cmplt_ps(a, b); }
static inline M4 f4_le(F4 a, F4 b) { return _mm_cmple_ps(a, b); }
static inline M4 m4_and(M4 a, M4 b) { return _mm_and_ps(a, b); }
static inline M4 m4_or(M4 a, M4 b) { return _mm_or_ps(a, b); }
static inline M4 m4_andnot(M4 a, M4 b) { return _mm_andnot_ps(a, b); }   /* !a & b */
static inline M4 m4_all(void) { return _mm_castsi128_ps(_mm_set1_epi32(-1)); }
static inline M4 m4_none(void) { return _mm_setzero_ps(); }
static inline int m4_bits(M4 m) { return _mm_movemask_ps(m); }   /* lane i's condition: bit i */
/* m ? a : b, lane by lane */
static inline F4 f4_select(M4 m, F4 a, F4 b) { return _mm_or_ps(_mm_and_ps(m, a), _mm_andnot_ps(m, b)); }
/* m ? a : 0 */
static inline F4 f4_keep(M4 m, F4 a) { return _mm_and_ps(m, a); }
/* (float)(int)a: toward zero, for |a| < 2^31 */
static inline F4 f4_trunc(F4 a) { return _mm_cvtepi32_ps(_mm_cvttps_epi32(a)); }
static inline F4 f4_sqrt(F4 a) { return _mm_sqrt_ps(a); }
/* (float)((bits of a >> 23) - 127): the exponent of a positive float */
static inline F4 f4_exponent(F4 a) {
  return _mm_cvtepi32_ps(_mm_sub_epi32(_mm_srli_epi32(_mm_castps_si128(a), 23), _mm_set1_epi32(127)));
}
/* 2^i for whole i in [-126, 127] */
static inline F4 f4_pow2i(F4 i) {
  return _mm_castsi128_ps(_mm_slli_epi32(_mm_add_epi32(_mm_cvttps_epi32(i), _mm_set1_epi32(127)), 23));
}
/* the bits of a and mask, or mask */
static inline F4 f4_and_bits(F4 a, uint32_t mask) {
  return _mm_and_ps(a, _mm_castsi128_ps(_mm_set1_epi32((int32_t)mask)));
}
static inline F4 f4_or_bits(F4 a, uint32_t mask) {
  return _mm_or_ps(a, _mm_castsi128_ps(_mm_set1_epi32((int32_t)mask)));
}

#else
#include <math.h>

typedef struct { float f[4]; } F4;
typedef struct { uint32_t m[4]; } M4;

#define LANES_MAP(expr) F4 r; for (int i = 0; i < 4; i++) r.f[i] = (expr); return r
#define LANES_TEST(expr) M4 r; for (int i = 0; i < 4; i++) r.m[i] = (expr) ? 0xffffffffu : 0; return r

static inline F4 f4_load(const float *p) { LANES_MAP(p[i]); }
static inline void f4_store(float *p, F4 a) { for (int i = 0; i < 4; i++) p[i] = a.f[i]; }
static inline void f4_store_rgb(float *p, F4 r, F4 g, F4 b) {
  for (int i = 0; i < 4; i++) { p[3 * i] = r.f[i]; p[3 * i + 1] = g.f[i]; p[3 * i + 2] = b.f[i]; }
}
static inline void f4_load_pairs(const float *p, F4 *a, F4 *b) {
  for (int i = 0; i < 4; i++) { a->f[i] = p[2 * i]; b->f[i] = p[2 * i + 1]; }
}
static inline F4 f4_set(float x) { LANES_MAP(x); }
static inline F4 f4_add(F4 a, F4 b) { LANES_MAP(a.f[i] + b.f[i]); }
static inline F4 f4_sub(F4 a, F4 b) { LANES_MAP(a.f[i] - b.f[i]); }
static inline F4 f4_mul(F4 a, F4 b) { LANES_MAP(a.f[i] * b.f[i]); }
static inline F4 f4_div(F4 a, F4 b) { LANES_MAP(a.f[i] / b.f[i]); }
static inline F4 f4_min(F4 a, F4 b) { LANES_MAP(a.f[i] < b.f[i] ? a.f[i] : b.f[i]); }
static inline F4 f4_max(F4 a, F4 b) { LANES_MAP(a.f[i] > b.f[i] ? a.f[i] : b.f[i]); }
static inline M4 f4_lt(F4 a, F4 b) { LANES_TEST(a.f[i] < b.f[i]); }
static inline M4 f4_le(F4 a, F4 b) { LANES_TEST(a.f[i] <= b.f[i]); }
static inline M4 m4_and(M4 a, M4 b) { LANES_TEST(a.m[i] & b.m[i]); }
static inline M4 m4_or(M4 a, M4 b) { LANES_TEST(a.m[i] | b.m[i]); }
static inline M4 m4_andnot(M4 a, M4 b) { LANES_TEST(~a.m[i] & b.m[i]); }
static inline M4 m4_all(void) { LANES_TEST(1); }
static inline M4 m4_none(void) { LANES_TEST(0); }
static inline int m4_bits(M4 m) {
  int r = 0;
  for (int i = 0; i < 4; i++) r |= (m.m[i] != 0) << i;
  return r;
}
static inline F4 f4_select(M4 m, F4 a, F4 b) { LANES_MAP(m.m[i] ? a.f[i] : b.f[i]); }
static inline F4 f4_keep(M4 m, F4 a) { LANES_MAP(m.m[i] ? a.f[i] : 0.0f); }
static inline F4 f4_trunc(F4 a) { LANES_MAP((float)(int)a.f[i]); }
static inline F4 f4_sqrt(F4 a) { LANES_MAP(sqrtf(a.f[i])); }
static inline float lanes_exponent(float x) {
  union { float f; uint32_t u; } b = {x};
  return (float)((int32_t)(b.u >> 23) - 127);
}
static inline float lanes_pow2i(float x) {
  union { float f; uint32_t u; } b;
  b.u = (uint32_t)((int32_t)x + 127) << 23;
  return b.f;
}
static inline F4 f4_exponent(F4 a) { LANES_MAP(lanes_exponent(a.f[i])); }
static inline F4 f4_pow2i(F4 a) { LANES_MAP(lanes_pow2i(a.f[i])); }
static inline float lanes_bits(float x, uint32_t and_mask, uint32_t or_mask) {
  union { float f; uint32_t u; } b = {x};
  b.u = (b.u & and_mask) | or_mask;
  return b.f;
}
static inline F4 f4_and_bits(F4 a, uint32_t mask) { LANES_MAP(lanes_bits(a.f[i], mask, 0)); }
static inline F4 f4_or_bits(F4 a, uint32_t mask) { LANES_MAP(lanes_bits(a.f[i], 0xffffffffu, mask)); }

#undef LANES_MAP
#undef LANES_TEST
#endif

static inline F4 f4_abs(F4 a) { return f4_and_bits(a, 0x7fffffffu); }

/* floor(a) for |a| < 2^31, as hatch_floor: the truncation, less one where
** it rounded up. */
static inline F4 f4_floor(F4 a) {
  F4 t = f4_trunc(a);
  return f4_sub(t, f4_keep(f4_lt(a, t), f4_set(1)));
}

#endif
