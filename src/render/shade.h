/*
** Shading models: the colour of one G-buffer sample from its surface point,
** normal and view vector, by its object's style. One function per model
** behind a table (shade_model), one file per model family:
**   shade.c       lights, the shared terms, flat, gouraud, phong, unlit
**   shade_toon.c  toon: T_n bands on the diffuse and specular terms
**                 separately, or 1D colour ramps, and the n.v silhouette
**                 edge (004; 002 section 2)
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
