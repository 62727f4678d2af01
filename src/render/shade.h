/*
** Shading models: the colour of one G-buffer sample from its surface point,
** normal and view vector, by its object's style. One function per model
** behind a table (shade_model), one file per model family:
**   shade.c       lights, the shared terms, flat, gouraud, phong, unlit
**   shade_toon.c  toon: T_n bands on the diffuse and specular terms
**                 separately, or 1D colour ramps, and the n.v silhouette
**                 edge (004; 002 section 2)
** The tile pass shades a row of samples in two steps: it rebuilds each
** sample's surface from its triangle's corners (shade_tri_sample_raw, with
** ShadeTri set up once per run of samples of one triangle, then
** shade_unit_lengths and shade_sample_unit for the whole row), and the
** model's span shader (shade_span_model) colours each run of samples of
** one object.
** The lighting equation every lit model shares (002 eq. 1):
**   I = m_a l_a + sum_i m_d T(f_d) l_i + sum_i m_s T(f_s) l_i
** with m_a = m_d = the style's base colour, l_a = ambient (white),
** m_s = specular (white), f_d = max(0, n.l), f_s = max(0, n.h)^shininess
** (Blinn's half vector, 0 where n.l <= 0), and T the identity except in
** toon. All colours are linear.
*/
#ifndef render_shade_h
#define render_shade_h

#include <math.h>

#include "render.h"

/* What a shading model sees of one sample. */
typedef struct ShadeSample {
  const RenderFrame *frame;
  const RenderObject *obj;
  int face;            /* triangle of obj->mesh */
  float b1, b2;        /* barycentrics in it (gbuffer.h) */
  float p[3];          /* world point */
  float n[3];          /* unit shading normal, turned toward the viewer */
  float v[3];          /* unit vector toward the viewer */
  float uv[2];
} ShadeSample;

/* A shading model: the linear colour of s into rgb. */
typedef void (*ShadeFn)(const ShadeSample *s, float rgb[3]);

/* The model for a shade kind. Kinds whose own model is not in this table
** (their stages add it) shade as phong. */
ShadeFn shade_model(ShadeKind kind);

/* One triangle's constants, hoisted out of the loop over a run of its
** samples (neighbouring samples mostly show the same triangle). */
typedef struct ShadeTri {
  const RenderFrame *frame;
  const RenderObject *obj;
  int face;                      /* triangle of obj->mesh */
  const int *vert;               /* its vertex indices, obj->mesh->tri[face] */
  const float *p[3], *n[3];      /* corner world positions and normals */
  int back;                      /* it shows its back: normals turn around */
  int ortho;                     /* view vector: back[] (ortho) or toward eye[] */
  float eye[3], view[3];
  int want_uv;                   /* interpolate ShadeSample.uv (else 0) */
} ShadeTri;

/* Shade n samples of one object, s[0..n-1] (rebuilt as above),
** into rgb: sample k's colour at rgb[k * stride + 0..2]. */
typedef void (*ShadeSpanFn)(const ShadeSample *s, int n, float *rgb, int stride);

/* The span shader for a shade kind: a model's own loop where it has one
** (toon), else shade_span_generic, which calls the kind's ShadeFn per
** sample. Both give the colours the ShadeFn gives, bit for bit. */
ShadeSpanFn shade_span_model(ShadeKind kind);
void shade_span_generic(const ShadeSample *s, int n, float *rgb, int stride);
void shade_toon_span(const ShadeSample *s, int n, float *rgb, int stride);

/* The sample of t at barycentrics (b1, b2) in two steps, so that a row's
** square roots and divisions can run side by side (shade_unit_lengths):
** shade_tri_sample_raw rebuilds the surface point, the uv, and the shading
** normal and view vector before their normalisation, with their squared
** lengths in *nn and *vv (*nn negated on a back face, whose normal turns
** toward the viewer); shade_sample_unit then scales them by the factors
** shade_unit_lengths made of those. */
static inline void shade_tri_sample_raw(const ShadeTri *t, float b1, float b2, ShadeSample *s,
                                        float *nn, float *vv) {
  const float *p0 = t->p[0], *p1 = t->p[1], *p2 = t->p[2];
  const float *n0 = t->n[0], *n1 = t->n[1], *n2 = t->n[2];
  float b0 = 1 - b1 - b2;
  s->frame = t->frame;
  s->obj = t->obj;
  s->face = t->face;
  s->b1 = b1;
  s->b2 = b2;
  float px = b0 * p0[0] + b1 * p1[0] + b2 * p2[0];
  float py = b0 * p0[1] + b1 * p1[1] + b2 * p2[1];
  float pz = b0 * p0[2] + b1 * p1[2] + b2 * p2[2];
  float nx = b0 * n0[0] + b1 * n1[0] + b2 * n2[0];
  float ny = b0 * n0[1] + b1 * n1[1] + b2 * n2[1];
  float nz = b0 * n0[2] + b1 * n1[2] + b2 * n2[2];
  *nn = nx * nx + ny * ny + nz * nz;
  if (t->back) *nn = -*nn;
  float vx = t->view[0], vy = t->view[1], vz = t->view[2];
  *vv = 1;                                  /* ortho: already unit */
  if (!t->ortho) {                          /* toward the eye */
    vx = t->eye[0] - px; vy = t->eye[1] - py; vz = t->eye[2] - pz;
    *vv = vx * vx + vy * vy + vz * vz;
  }
  s->p[0] = px; s->p[1] = py; s->p[2] = pz;
  s->n[0] = nx; s->n[1] = ny; s->n[2] = nz;
  s->v[0] = vx; s->v[1] = vy; s->v[2] = vz;
  s->uv[0] = s->uv[1] = 0;
  if (t->want_uv && t->obj->mesh->uv) {
    const Vec2 *uv = t->obj->mesh->uv;
    const int *v = t->vert;
    s->uv[0] = (float)(b0 * uv[v[0]].x + b1 * uv[v[1]].x + b2 * uv[v[2]].x);
    s->uv[1] = (float)(b0 * uv[v[0]].y + b1 * uv[v[1]].y + b2 * uv[v[2]].y);
  }
}

/* In place, for n samples: nn[k] becomes the factor that makes the normal
** unit (negative on a back face, 0 for a zero normal), vv[k] the one for
** the view vector. A plain loop over floats, which the compiler runs
** several lanes at a time (IEEE square root and division, so the results
** are those of one at a time). */
static inline void shade_unit_lengths(float *restrict nn, float *restrict vv, int n) {
  for (int k = 0; k < n; k++) {   /* no branches (1 / 0 is inf, not a trap), so it runs in lanes */
    float a = fabsf(nn[k]), b = vv[k];
    float ia = 1 / sqrtf(a), ib = 1 / sqrtf(b);
    nn[k] = copysignf(a > 0 ? ia : 0, nn[k]);
    vv[k] = b > 0 ? ib : 0;
  }
}

static inline void shade_sample_unit(ShadeSample *s, float fn, float fv) {
  s->n[0] *= fn; s->n[1] *= fn; s->n[2] *= fn;
  s->v[0] *= fv; s->v[1] *= fv; s->v[2] *= fv;
}

/* Whether the model for kind reads ShadeSample.uv (else it is left 0). */
int shade_reads_uv(ShadeKind kind);

/* Resolve a style's shading constants (defaults for unset values: bands
** 0 -> 3, specular_bands 0 -> 2, shininess 0 -> 32). */
void shade_style_init(RenderStyle *rs, const SceneStyle *st);

/* Unit vector toward light i from world point p into l, and the light's
** colour arriving there (with falloff) into col. */
static inline void shade_light(const RenderFrame *f, int i, const float p[3], float l[3], float col[3]) {
  const RenderLight *lt = &f->lights[i];
  float k = 1;
  if (lt->directional) {
    l[0] = lt->dir[0]; l[1] = lt->dir[1]; l[2] = lt->dir[2];
  } else {
    l[0] = lt->pos[0] - p[0]; l[1] = lt->pos[1] - p[1]; l[2] = lt->pos[2] - p[2];
    float d2 = l[0] * l[0] + l[1] * l[1] + l[2] * l[2];
    float inv = d2 > 0 ? 1 / sqrtf(d2) : 0;
    l[0] *= inv; l[1] *= inv; l[2] *= inv;
    if (lt->inverse_square && d2 > 0) k = 1 / d2;
  }
  col[0] = lt->color[0] * k;
  col[1] = lt->color[1] * k;
  col[2] = lt->color[2] * k;
}

/* The smooth diffuse term f_d = max(0, n.l). */
static inline float shade_diffuse(const float n[3], const float l[3]) {
  float d = n[0] * l[0] + n[1] * l[1] + n[2] * l[2];
  return d > 0 ? d : 0;
}

/* The smooth specular term f_s = max(0, n.h)^shininess with h the unit
** half vector of l and v; 0 where the light is behind the surface. */
float shade_specular(const float n[3], const float l[3], const float v[3], float shininess);

/* The multi-band step T_n(x, t) = (floor(x n) + T(frac(x n), t)) / n with
** T(y, t) = 0 if y < t else 1; x is clamped to [0, 1] first (NaN to 0).
** n >= 1; gives the n + 1 levels 0, 1/n, ..., 1 (002 eq. 4). inv_n is
** 1 / n, passed in so the shading loop does not divide. */
static inline float shade_step_inv(float x, float t, int n, float inv_n) {
  x = x > 0 ? (x < 1 ? x : 1) : 0;                  /* NaN too goes to 0 */
  float xn = x * n;
  float whole = (float)(int)xn;                      /* floor: xn >= 0 */
  float frac = xn - whole;
  return (whole + (frac < t ? 0.0f : 1.0f)) * inv_n; /* T(frac(xn), t) adds the last step */
}

static inline float shade_step(float x, float t, int n) { return shade_step_inv(x, t, n, 1.0f / n); }

/* Per-vertex colours of a gouraud object (o->vcolor, allocated here):
** the phong terms at each vertex with its normal turned toward the
** viewer. */
void shade_vertex_colors(const RenderFrame *f, RenderObject *o);

/* Models (shade_model's table). */
void shade_unlit(const ShadeSample *s, float rgb[3]);
void shade_flat(const ShadeSample *s, float rgb[3]);
void shade_gouraud(const ShadeSample *s, float rgb[3]);
void shade_phong(const ShadeSample *s, float rgb[3]);
void shade_toon(const ShadeSample *s, float rgb[3]);

#endif
