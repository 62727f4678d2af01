/*
** Toon shading (004 "Toon shading"; 002 section 2): the lighting equation
** with the multi-band step T_n applied to the diffuse and the specular
** terms separately,
**   I = m_a l_a + sum_i m_d T_n(f_d, t) l_i + sum_i m_s T_m(f_s, t_s) l_i,
** or, when the style gives ramps, 1D colour ramps indexed by the diffuse
** and specular values (color = ramp_d(d) + ramp_s(s)); then the lecture's
** silhouette: where edge = max(0, n.v) falls below the style's cutoff the
** sample takes the edge colour.
*/
#include "shade.h"

#include <math.h>

static inline float dot3(const float a[3], const float b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* The ramp colour for a value x in [0, 1]: the ramp's n colours split
** [0, 1] into n equal steps (a 1D texture read with nearest filtering). */
static const Color *ramp_at(const Color *ramp, int n, float x) {
  int i = x > 0 ? (x < 1 ? (int)(x * n) : n - 1) : 0;   /* NaN reads the first colour */
  return &ramp[i < 0 ? 0 : i >= n ? n - 1 : i];
}

/* T_m(f_s) for light direction l, skipping pow() where n.h is below the
** style's cutoff (the step is surely 0 there). */
static float banded_specular(const RenderStyle *st, const float n[3], const float l[3],
                             const float v[3]) {
  if (dot3(n, l) <= 0) return 0;
  float h[3] = {l[0] + v[0], l[1] + v[1], l[2] + v[2]};   /* unnormalised half vector */
  float nh = dot3(n, h), hh = dot3(h, h);
  /* n.h / |h| <= cut, tested without the square root (most samples stop here) */
  if (nh <= 0 || nh * nh <= st->spec_cut * st->spec_cut * hh) return 0;
  nh /= sqrtf(hh);
  return shade_step_inv(powf(nh, st->shininess), st->spec_threshold, st->spec_n, st->inv_spec_n);
}

/* Colour ramps: the diffuse (and specular) values of all lights, weighted
** by each light's mean intensity, index the ramps. */
static void toon_ramps(const ShadeSample *s, const RenderStyle *st, const ShadeToon *t,
                       float rgb[3]) {
  float d = 0, sp = 0;
  for (int i = 0; i < s->frame->nlights; i++) {
    float l[3], col[3];
    shade_light(s->frame, i, s->p, l, col);
    float w = (col[0] + col[1] + col[2]) / 3;
    d += shade_diffuse(s->n, l) * w;
    if (st->specular > 0) sp += shade_specular(s->n, l, s->v, st->shininess) * w;
  }
  const Color *cd = ramp_at(t->ramp, t->nramp, d);
  rgb[0] = cd->r; rgb[1] = cd->g; rgb[2] = cd->b;
  if (st->specular <= 0) return;
  if (t->nspecular_ramp > 0) {
    const Color *cs = ramp_at(t->specular_ramp, t->nspecular_ramp, sp);
    rgb[0] += cs->r; rgb[1] += cs->g; rgb[2] += cs->b;
  } else {
    float k = st->specular * shade_step_inv(sp, st->spec_threshold, st->spec_n, st->inv_spec_n);
    rgb[0] += k; rgb[1] += k; rgb[2] += k;
  }
}

/* Bands: T_n on each light's diffuse term, T_m on its specular term.
** Spelled out per channel so the sums stay in registers (rgb may alias
** anything, and a loop over an array would keep them in memory). */
static inline void toon_bands(const ShadeSample *s, const RenderStyle *st, float rgb[3]) {
  const float *base = st->base;
  float r = base[0] * st->ambient, g = base[1] * st->ambient, b = base[2] * st->ambient;
  for (int i = 0; i < s->frame->nlights; i++) {
    float l[3], col[3];
    shade_light(s->frame, i, s->p, l, col);
    float td = shade_step_inv(shade_diffuse(s->n, l), st->threshold, st->bands_n, st->inv_bands_n);
    float ts = st->specular > 0 ? st->specular * banded_specular(st, s->n, l, s->v) : 0;
    r += (base[0] * td + ts) * col[0];
    g += (base[1] * td + ts) * col[1];
    b += (base[2] * td + ts) * col[2];
  }
  rgb[0] = r; rgb[1] = g; rgb[2] = b;
}

/* The model for one sample (inlined into the span loop, its only caller). */
static inline void toon(const ShadeSample *s, const RenderStyle *st, float rgb[3]) {
  if (st->edge > 0 && dot3(s->n, s->v) < st->edge) {   /* edge = max(0, n.v) below the cutoff */
    rgb[0] = st->edge_color[0]; rgb[1] = st->edge_color[1]; rgb[2] = st->edge_color[2];
    return;
  }
  const ShadeToon *t = &st->src->shade.toon;
  if (t->nramp > 0) toon_ramps(s, st, t, rgb);
  else toon_bands(s, st, rgb);
}

void shade_toon_span(const ShadeSample *s, int n, float *rgb, int stride) {
  if (n <= 0) return;
  const RenderStyle *st = s->obj->style;
  for (int k = 0; k < n; k++, rgb += stride) toon(&s[k], st, rgb);
}

void shade_toon(const ShadeSample *s, float rgb[3]) {
  shade_toon_span(s, 1, rgb, 3);
}
