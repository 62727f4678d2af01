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

#include "shadow.h"

static inline float dot3(const float a[3], const float b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* The ramp colour for a value x in [0, 1]: the ramp's n colours split
** [0, 1] into n equal steps (a 1D texture read with nearest filtering). */
static const Color *ramp_at(const Color *ramp, int n, float x) {
  int i = x > 0 ? (x < 1 ? (int)(x * n) : n - 1) : 0;   /* NaN reads the first colour */
  return &ramp[i < 0 ? 0 : i >= n ? n - 1 : i];
}

/* Light i's weight in the ramps' sums at point p (normal n, on triangle
** face of o) lit from l with colour col: its mean intensity, times the
** share of it reaching p when it casts shadows. */
static float ramp_weight(const RenderFrame *f, int i, const RenderObject *o, int face, const float p[3],
                         const float n[3], const float l[3], const float col[3]) {
  float w = (col[0] + col[1] + col[2]) / 3;
  if (!f->lights[i].shadow || !o->wfnrm) return w;
  return dot3(n, l) > 0 ? w * shade_reach(f, i, o, face, p) : 0;
}

/* Colour ramps: the diffuse (and specular) values of all lights, weighted
** by each light's mean intensity (and the share of it a shadow lets
** through), index the ramps. */
static void toon_ramps(const ShadeSample *s, const RenderStyle *st, const ShadeToon *t,
                       float rgb[3]) {
  float d = 0, sp = 0;
  for (int i = 0; i < s->frame->nlights; i++) {
    float l[3], col[3];
    shade_light(s->frame, i, s->p, l, col);
    float w = ramp_weight(s->frame, i, s->obj, s->face, s->p, s->n, l, col);
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

/* T_m(f_s) of one sample whose n.h and h.h (h = l + v, unnormalised)
** passed the style's cut: below it the step is surely 0, and the bands
** loop skips the pow() (most samples). */
static float banded_specular_tail(const RenderStyle *st, float nh, float hh) {
  nh /= sqrtf(hh);
  return shade_step_inv(powf(nh, st->shininess), st->spec_threshold, st->spec_n, st->inv_spec_n);
}

/* The same for a light of which only the share vis arrives: T_m(f_s vis). */
static float banded_specular_shadowed(const RenderStyle *st, float nh, float hh, float vis) {
  nh /= sqrtf(hh);
  return shade_step_inv(powf(nh, st->shininess) * vis, st->spec_threshold, st->spec_n, st->inv_spec_n);
}

/* Samples a block of the bands loop works on: its temporaries live on the
** stack. */
#define TOON_BLOCK 64

/* Unit vectors toward light lt from samples k0..k0+n-1 of r into l*, and
** the falloff factor into fall (shade_light, several samples at a time). */
static void light_block(const RenderLight *lt, const ShadeRow *r, int k0, int n, float *restrict lx,
                        float *restrict ly, float *restrict lz, float *restrict fall) {
  if (lt->directional) {
    for (int j = 0; j < n; j++) {
      lx[j] = lt->dir[0]; ly[j] = lt->dir[1]; lz[j] = lt->dir[2]; fall[j] = 1;
    }
    return;
  }
  const float *px = r->px + k0, *py = r->py + k0, *pz = r->pz + k0;
  for (int j = 0; j < n; j++) fall[j] = shade_point_light(lt, px[j], py[j], pz[j], &lx[j], &ly[j], &lz[j]);
  if (lt->spot)   /* its own loop: a point light's stays as it was */
    for (int j = 0; j < n; j++) fall[j] *= shade_spot(lt, lx[j], ly[j], lz[j]);
}

/* The specular term T_m(f_s) times the style's strength, for samples
** k0..k0+n-1 of r lit by directions l* with n.l in nl, into ts: 0 for the
** samples whose n.h / |h| does not pass the cut (tested without a square
** root, most samples) and the power only for the few that do. */
static void highlight_block(const ShadeRow *r, const RenderStyle *st, int k0, int n,
                            const float *lx, const float *ly, const float *lz, const float *nl,
                            const float *vis, float *restrict ts) {
  const float *nx = r->nx + k0, *ny = r->ny + k0, *nz = r->nz + k0;
  const float *vx = r->vx + k0, *vy = r->vy + k0, *vz = r->vz + k0;
  float cut2 = st->spec_cut * st->spec_cut, nhs[TOON_BLOCK], hhs[TOON_BLOCK];
  int lit[TOON_BLOCK], any = 0;
  for (int j = 0; j < n; j++) {
    float hx = lx[j] + vx[j], hy = ly[j] + vy[j], hz = lz[j] + vz[j];   /* unnormalised half vector */
    float nh = nx[j] * hx + ny[j] * hy + nz[j] * hz, hh = hx * hx + hy * hy + hz * hz;
    lit[j] = !(nl[j] <= 0) & !(nh <= 0) & !(nh * nh <= cut2 * hh);
    nhs[j] = nh;
    hhs[j] = hh;
    any |= lit[j];
    ts[j] = 0;
  }
  if (any && vis)   /* a light that casts shadows: what arrives of it */
    for (int j = 0; j < n; j++)
      if (lit[j] && vis[j] > 0) ts[j] = st->specular * banded_specular_shadowed(st, nhs[j], hhs[j], vis[j]);
  if (any && !vis)
    for (int j = 0; j < n; j++)
      if (lit[j]) ts[j] = st->specular * banded_specular_tail(st, nhs[j], hhs[j]);
}

/* Whether some sample k0..k0+n-1 of r, lit from direction l, passes
** highlight_block's cut (so its specular term may not be 0). */
static int any_highlight(const ShadeRow *r, const RenderStyle *st, const float l[3], int k0,
                         int n) {
  const float *nx = r->nx + k0, *ny = r->ny + k0, *nz = r->nz + k0;
  const float *vx = r->vx + k0, *vy = r->vy + k0, *vz = r->vz + k0;
  float cut2 = st->spec_cut * st->spec_cut;
  int any = 0;
  for (int j = 0; j < n; j++) {
    float d = nx[j] * l[0] + ny[j] * l[1] + nz[j] * l[2];
    float hx = l[0] + vx[j], hy = l[1] + vy[j], hz = l[2] + vz[j];
    float nh = nx[j] * hx + ny[j] * hy + nz[j] * hz, hh = hx * hx + hy * hy + hz * hz;
    any |= !(d <= 0) & !(nh <= 0) & !(nh * nh <= cut2 * hh);
  }
  return any;
}

/* Antialiased, the bands record the level each of their steps is on
** (ShadeRow.step_key) for antialias.h: term 0 the n.v edge (if any), then
** per light its diffuse step and (with a specular) its highlight's, as
** many as SHADE_STEP_TERMS hold; shade_step_value gives their values.
** The term of light i's diffuse step (its highlight's is the next): */
static int diffuse_term(const RenderStyle *st, int i) {
  return (st->edge > 0) + i * (1 + (st->specular > 0));
}

/* Levels of light i's terms at samples k0..k0+n-1 of r from their steps'
** values T_n(f_d) in td and, when given, T_m(f_s) times the specular
** strength in ts (NULL: none passes the cut, level -1): a T value is
** (level + 1) / n. */
static void light_levels(const ShadeRow *r, const RenderStyle *st, int i, int k0, int n,
                         const float *restrict td, const float *restrict ts) {
  int t = diffuse_term(st, i);
  if (t >= SHADE_STEP_TERMS) return;
  uint32_t *restrict key = r->step_key + k0;   /* zeroed by the tile pass */
  float bn = (float)st->bands_n;
  for (int j = 0; j < n; j++) key[j] |= ((uint32_t)((int)(td[j] * bn + 0.5f) - 1) & 0xffu) << (8 * t);
  if (++t >= SHADE_STEP_TERMS || !(st->specular > 0)) return;
  if (!ts) {
    for (int j = 0; j < n; j++) key[j] |= 0xffu << (8 * t);
    return;
  }
  float m = (float)st->spec_n / st->specular;
  for (int j = 0; j < n; j++) key[j] |= ((uint32_t)((int)(ts[j] * m + 0.5f) - 1) & 0xffu) << (8 * t);
}

float shade_step_value(const RenderFrame *f, const RenderObject *o, int face, int t, const float p[3],
                       const float n[3], const float v[3]) {
  const RenderStyle *st = o->style;
  if (st->kind != SHADE_TOON) return NAN;
  if (st->edge > 0 && t-- == 0) return dot3(n, v) - st->edge;
  const ShadeToon *tn = &st->src->shade.toon;
  if (tn->nramp > 0) {   /* the ramps' indices: d (then s) times the colours' count */
    float d = 0, sp = 0;
    for (int i = 0; i < f->nlights; i++) {
      float l[3], col[3];
      shade_light(f, i, p, l, col);
      float w = ramp_weight(f, i, o, face, p, n, l, col);
      d += shade_diffuse(n, l) * w;
      if (st->specular > 0) sp += shade_specular(n, l, v, st->shininess) * w;
    }
    if (t == 0) return d * tn->nramp;
    if (t != 1 || !(st->specular > 0)) return NAN;
    return tn->nspecular_ramp > 0 ? sp * tn->nspecular_ramp : sp * st->spec_n - st->spec_threshold;
  }
  int per = 1 + (st->specular > 0), i = t / per;
  if (i >= f->nlights) return NAN;
  float l[3], col[3];
  shade_light(f, i, p, l, col);
  float nl = dot3(n, l), vis = 1;
  if (f->lights[i].shadow && o->wfnrm) vis = nl > 0 ? shade_reach(f, i, o, face, p) : 0;
  if (t % per == 0)   /* not clamped: its true distance (in shadow, the light that arrives) */
    return (nl > 0 ? nl * vis : nl) * st->bands_n - st->threshold;
  return shade_specular(n, l, v, st->shininess) * vis * st->spec_n - st->spec_threshold;
}

/* Light i, which casts shadows, on samples k0..k0+n-1 of r (object o):
** its terms scaled by the share of it reaching each sample before the
** steps, T_n(f_d vis) and T_m(f_s vis), so a shadow is a band of its own
** with the bands' crisp edges (the cel-shading look), added to R, G, B. */
static void toon_shadowed_light(const ShadeRow *r, const RenderObject *o, int i, int k0, int n,
                                const float *bR, const float *bG, const float *bB,
                                float *restrict R, float *restrict G, float *restrict B) {
  const RenderStyle *st = o->style;
  const RenderLight *lt = &r->frame->lights[i];
  const float *nx = r->nx + k0, *ny = r->ny + k0, *nz = r->nz + k0;
  float lx[TOON_BLOCK], ly[TOON_BLOCK], lz[TOON_BLOCK], fall[TOON_BLOCK];
  float nl[TOON_BLOCK], vis[TOON_BLOCK], td[TOON_BLOCK], ts[TOON_BLOCK];
  light_block(lt, r, k0, n, lx, ly, lz, fall);
  for (int j = 0; j < n; j++) nl[j] = nx[j] * lx[j] + ny[j] * ly[j] + nz[j] * lz[j];
  /* the map is read only where the light that arrives can show: where
  ** n.l reaches the first band's step (below it T_n is 0 however much
  ** arrives) or the highlight may pass its cut; elsewhere vis is 0, the
  ** same colour */
  float need[TOON_BLOCK], first = st->threshold * st->inv_bands_n;
  for (int j = 0; j < n; j++) need[j] = nl[j] >= first ? nl[j] : 0;
  if (st->specular > 0) {
    const float *vx = r->vx + k0, *vy = r->vy + k0, *vz = r->vz + k0;
    float cut2 = st->spec_cut * st->spec_cut;
    for (int j = 0; j < n; j++) {
      float hx = lx[j] + vx[j], hy = ly[j] + vy[j], hz = lz[j] + vz[j];
      float nh = nx[j] * hx + ny[j] * hy + nz[j] * hz, hh = hx * hx + hy * hy + hz * hz;
      need[j] = nh > 0 && nh * nh > cut2 * hh ? nl[j] : need[j];
    }
  }
  shadow_run(lt->shadow, o, n, r->face + k0, r->px + k0, r->py + k0, r->pz + k0, need, vis);
  for (int j = 0; j < n; j++) {
    td[j] = shade_step_inv(nl[j] > 0 ? nl[j] * vis[j] : 0, st->threshold, st->bands_n, st->inv_bands_n);
    ts[j] = 0;
  }
  if (st->specular > 0) highlight_block(r, st, k0, n, lx, ly, lz, nl, vis, ts);
  if (r->step_key) light_levels(r, st, i, k0, n, td, ts);
  for (int j = 0; j < n; j++) {
    float c0 = lt->color[0] * fall[j], c1 = lt->color[1] * fall[j], c2 = lt->color[2] * fall[j];
    R[j] += (bR[j] * td[j] + ts[j]) * c0;
    G[j] += (bG[j] * td[j] + ts[j]) * c1;
    B[j] += (bB[j] * td[j] + ts[j]) * c2;
  }
}

/* Bands for samples k0..k0+n-1 (n <= TOON_BLOCK): T_n on each light's
** diffuse term, T_m on its specular term, the sums per channel in planes.
** Each sample's arithmetic is the same, in the same order, whether it is
** shaded alone (shade_toon) or in a block; the loops run several samples
** at a time, all but the power of the few samples whose highlight passes
** the cut. */
static void toon_bands_block(const ShadeRow *r, const RenderObject *o, int k0, int n,
                             float *restrict R, float *restrict G, float *restrict B) {
  const RenderStyle *st = o->style;
  const float *nx = r->nx + k0, *ny = r->ny + k0, *nz = r->nz + k0;
  const float *vx = r->vx + k0, *vy = r->vy + k0, *vz = r->vz + k0;
  float bR[TOON_BLOCK], bG[TOON_BLOCK], bB[TOON_BLOCK];   /* the base colour, per sample */
  shade_base_block(r, o, k0, n, bR, bG, bB);
  float lx[TOON_BLOCK], ly[TOON_BLOCK], lz[TOON_BLOCK], fall[TOON_BLOCK];
  float nl[TOON_BLOCK], td[TOON_BLOCK], ts[TOON_BLOCK];
  for (int j = 0; j < n; j++) {
    R[j] = bR[j] * st->ambient; G[j] = bG[j] * st->ambient; B[j] = bB[j] * st->ambient;
    ts[j] = 0;   /* no specular: stays 0 */
  }
  for (int i = 0; i < r->frame->nlights; i++) {
    const RenderLight *lt = &r->frame->lights[i];
    if (lt->shadow && o->wfnrm) {
      toon_shadowed_light(r, o, i, k0, n, bR, bG, bB, R, G, B);
      continue;
    }
    if (lt->directional && !(st->specular > 0 && any_highlight(r, st, lt->dir, k0, n))) {
      /* the common case: a sun and no highlight in the block, one loop */
      float dx = lt->dir[0], dy = lt->dir[1], dz = lt->dir[2];
      float c0 = lt->color[0], c1 = lt->color[1], c2 = lt->color[2];   /* falloff 1: c * 1 is c */
      for (int j = 0; j < n; j++) {
        float d = nx[j] * dx + ny[j] * dy + nz[j] * dz;
        float t = shade_step_inv(d > 0 ? d : 0, st->threshold, st->bands_n, st->inv_bands_n);
        td[j] = t;
        R[j] += (bR[j] * t + 0.0f) * c0;   /* + 0: the specular term, as below */
        G[j] += (bG[j] * t + 0.0f) * c1;
        B[j] += (bB[j] * t + 0.0f) * c2;
      }
      if (r->step_key) light_levels(r, st, i, k0, n, td, NULL);
      continue;
    }
    light_block(lt, r, k0, n, lx, ly, lz, fall);
    for (int j = 0; j < n; j++) {
      float d = nx[j] * lx[j] + ny[j] * ly[j] + nz[j] * lz[j];
      nl[j] = d;
      td[j] = shade_step_inv(d > 0 ? d : 0, st->threshold, st->bands_n, st->inv_bands_n);
    }
    if (st->specular > 0) highlight_block(r, st, k0, n, lx, ly, lz, nl, NULL, ts);
    if (r->step_key) light_levels(r, st, i, k0, n, td, ts);
    for (int j = 0; j < n; j++) {
      float c0 = lt->color[0] * fall[j], c1 = lt->color[1] * fall[j], c2 = lt->color[2] * fall[j];
      R[j] += (bR[j] * td[j] + ts[j]) * c0;
      G[j] += (bG[j] * td[j] + ts[j]) * c1;
      B[j] += (bB[j] * td[j] + ts[j]) * c2;
    }
  }
  if (!(st->edge > 0)) return;
  int lv[TOON_BLOCK];
  for (int j = 0; j < n; j++) {   /* edge = max(0, n.v) below the cutoff: the edge colour */
    int edge = nx[j] * vx[j] + ny[j] * vy[j] + nz[j] * vz[j] < st->edge;
    R[j] = edge ? st->edge_color[0] : R[j];
    G[j] = edge ? st->edge_color[1] : G[j];
    B[j] = edge ? st->edge_color[2] : B[j];
    lv[j] = edge;
  }
  if (!r->step_key) return;
  uint32_t *restrict key = r->step_key + k0;
  for (int j = 0; j < n; j++) key[j] |= (uint32_t)-lv[j] & 0xffu;   /* level -1 below the cutoff */
}

/* The levels of the ramps' terms at sample k of r (as light_levels):
** the edge, the diffuse ramp's index, the specular ramp's index or step. */
static void toon_ramp_levels(const ShadeRow *r, const ShadeSample *s, const RenderStyle *st, int k) {
  const ShadeToon *tn = &st->src->shade.toon;
  int t = st->edge > 0, lv[2];
  uint32_t key = st->edge > 0 && dot3(s->n, s->v) < st->edge ? 0xffu : 0;
  float d = 0, sp = 0;
  for (int i = 0; i < s->frame->nlights; i++) {
    float l[3], col[3];
    shade_light(s->frame, i, s->p, l, col);
    float w = ramp_weight(s->frame, i, s->obj, s->face, s->p, s->n, l, col);
    d += shade_diffuse(s->n, l) * w;
    if (st->specular > 0) sp += shade_specular(s->n, l, s->v, st->shininess) * w;
  }
  lv[0] = (int)(ramp_at(tn->ramp, tn->nramp, d) - tn->ramp);
  if (tn->nspecular_ramp > 0) lv[1] = (int)(ramp_at(tn->specular_ramp, tn->nspecular_ramp, sp) - tn->specular_ramp);
  else lv[1] = (int)(shade_step_inv(sp, st->spec_threshold, st->spec_n, st->inv_spec_n) * st->spec_n + 0.5f) - 1;
  for (int j = 0; j < 1 + (st->specular > 0); j++) key |= ((uint32_t)lv[j] & 0xffu) << (8 * (t + j));
  r->step_key[k] = key;
}

/* The ramps model for one sample, with the silhouette edge first. */
static void toon_ramp_sample(const ShadeSample *s, const RenderStyle *st, float rgb[3]) {
  if (st->edge > 0 && dot3(s->n, s->v) < st->edge) {   /* edge = max(0, n.v) below the cutoff */
    rgb[0] = st->edge_color[0]; rgb[1] = st->edge_color[1]; rgb[2] = st->edge_color[2];
    return;
  }
  const ShadeToon *t = &st->src->shade.toon;
  toon_ramps(s, st, t, rgb);
}

void shade_toon_span(const ShadeRow *r, const RenderObject *o, int k0, int k1, float *rgb,
                     int stride) {
  const RenderStyle *st = o->style;
  if (st->src->shade.toon.nramp > 0) {   /* ramps: one sample at a time */
    ShadeSample s;
    for (int k = k0; k < k1; k++) {
      shade_row_sample(r, o, k, &s);
      toon_ramp_sample(&s, st, rgb + (size_t)k * stride);
      if (r->step_key) toon_ramp_levels(r, &s, st, k);
    }
    return;
  }
  float R[TOON_BLOCK], G[TOON_BLOCK], B[TOON_BLOCK];
  for (int k = k0; k < k1; k += TOON_BLOCK) {
    int n = k1 - k < TOON_BLOCK ? k1 - k : TOON_BLOCK;
    toon_bands_block(r, o, k, n, R, G, B);
    float *out = rgb + (size_t)k * stride;
    for (int j = 0; j < n; j++, out += stride) {
      out[0] = R[j]; out[1] = G[j]; out[2] = B[j];
    }
  }
}

/* One sample as a row of one. */
void shade_toon(const ShadeSample *s, float rgb[3]) {
  shade_span_one(s, shade_toon_span, rgb);
}
