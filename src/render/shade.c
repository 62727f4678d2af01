/*
** Shading: the model table, lights, the smooth diffuse and specular terms,
** and the flat, gouraud, phong and unlit models (shade.h).
*/
#include "shade.h"

#include <math.h>

#include "../base/mem.h"

/* ---- small float vector helpers ------------------------------------------ */

static inline float dot3(const float a[3], const float b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void norm3(float a[3]) {
  float l = sqrtf(dot3(a, a));
  if (l > 0) { a[0] /= l; a[1] /= l; a[2] /= l; }
}

/* ---- the table ------------------------------------------------------------ */

/* One row per shade kind (ORDER ShadeKind in scene.h). Kinds implemented
** by other stages replace their phong row when they land. */
static const ShadeFn models[] = {
  /* SHADE_NONE */      shade_unlit,
  /* SHADE_FLAT */      shade_flat,
  /* SHADE_GOURAUD */   shade_gouraud,
  /* SHADE_PHONG */     shade_phong,
  /* SHADE_TOON */      shade_toon,
  /* SHADE_THRESHOLD */ shade_phong,
  /* SHADE_BOKASHI */   shade_phong,
  /* SHADE_INK */       shade_phong,
  /* SHADE_ORIGAMI */   shade_phong,
};

ShadeFn shade_model(ShadeKind kind) {
  if ((unsigned)kind < sizeof models / sizeof models[0]) return models[kind];
  return shade_phong;
}

ShadeSpanFn shade_span_model(ShadeKind kind) {
  return kind == SHADE_TOON ? shade_toon_span : shade_span_generic;
}

void shade_span_generic(const ShadeSample *s, int n, float *rgb, int stride) {
  if (n <= 0) return;
  ShadeFn fn = shade_model(s->obj->style->kind);
  for (int k = 0; k < n; k++, rgb += stride) fn(&s[k], rgb);
}

int shade_reads_uv(ShadeKind kind) {
  /* the models in this file and shade_toon.c do not; textured ones will */
  return kind == SHADE_THRESHOLD || kind == SHADE_BOKASHI || kind == SHADE_INK ||
         kind == SHADE_ORIGAMI;
}

void shade_style_init(RenderStyle *rs, const SceneStyle *st) {
  const ShadeToon *t = &st->shade.toon;
  rs->src = st;
  rs->kind = st->shade.kind;
  rs->base[0] = st->base.r;
  rs->base[1] = st->base.g;
  rs->base[2] = st->base.b;
  rs->ambient = (float)t->ambient;
  rs->specular = (float)t->specular;
  rs->shininess = t->shininess > 0 ? (float)t->shininess : 32.0f;
  rs->bands_n = (t->bands >= 2 ? t->bands : 3) - 1;
  rs->threshold = (float)t->threshold;
  rs->spec_n = (t->specular_bands >= 2 ? t->specular_bands : 2) - 1;
  rs->spec_threshold = (float)t->specular_threshold;
  rs->inv_bands_n = 1.0f / rs->bands_n;
  rs->inv_spec_n = 1.0f / rs->spec_n;
  /* T_n(x, t) is 0 for x < t / n, and f_s = (n.h)^s is below that while
  ** n.h < (t / n)^(1 / s): the toon model skips its pow() there. */
  rs->spec_cut = rs->spec_threshold > 0
                     ? powf(rs->spec_threshold / rs->spec_n, 1.0f / rs->shininess)
                     : 0.0f;
  rs->edge = (float)t->edge;
  rs->edge_color[0] = t->edge_color.r;
  rs->edge_color[1] = t->edge_color.g;
  rs->edge_color[2] = t->edge_color.b;
}

/* ---- lights and terms ----------------------------------------------------- */

float shade_specular(const float n[3], const float l[3], const float v[3], float shininess) {
  if (dot3(n, l) <= 0) return 0;                    /* light behind the surface */
  float h[3] = {l[0] + v[0], l[1] + v[1], l[2] + v[2]};
  norm3(h);
  float nh = dot3(n, h);
  return nh > 0 ? powf(nh, shininess) : 0;
}

/* ---- models -------------------------------------------------------------- */

void shade_unlit(const ShadeSample *s, float rgb[3]) {
  const float *base = s->obj->style->base;
  rgb[0] = base[0]; rgb[1] = base[1]; rgb[2] = base[2];
}

/* The smooth lighting equation (T = identity) with normal n. */
static void phong_terms(const RenderFrame *f, const RenderStyle *st, const float p[3],
                        const float n[3], const float v[3], float rgb[3]) {
  for (int c = 0; c < 3; c++) rgb[c] = st->base[c] * st->ambient;
  for (int i = 0; i < f->nlights; i++) {
    float l[3], col[3];
    shade_light(f, i, p, l, col);
    float fd = shade_diffuse(n, l);
    float fs = st->specular > 0 ? st->specular * shade_specular(n, l, v, st->shininess) : 0;
    for (int c = 0; c < 3; c++) rgb[c] += (st->base[c] * fd + fs) * col[c];
  }
}

void shade_phong(const ShadeSample *s, float rgb[3]) {
  phong_terms(s->frame, s->obj->style, s->p, s->n, s->v, rgb);
}

/* Flat: the lighting of the triangle's own plane, its normal turned toward
** the viewer like the shading normal. */
void shade_flat(const ShadeSample *s, float rgb[3]) {
  const RenderObject *o = s->obj;
  const int *t = o->mesh->tri[s->face];
  const float *a = o->wpos[t[0]], *b = o->wpos[t[1]], *c = o->wpos[t[2]];
  float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  float e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  float ng[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                 e1[0] * e2[1] - e1[1] * e2[0]};
  norm3(ng);
  if (o->backfacing[s->face]) { ng[0] = -ng[0]; ng[1] = -ng[1]; ng[2] = -ng[2]; }
  phong_terms(s->frame, o->style, s->p, ng, s->v, rgb);
}

/* Gouraud: the vertex colours, interpolated. */
void shade_gouraud(const ShadeSample *s, float rgb[3]) {
  const RenderObject *o = s->obj;
  const int *t = o->mesh->tri[s->face];
  float b0 = 1 - s->b1 - s->b2;
  for (int c = 0; c < 3; c++)
    rgb[c] = b0 * o->vcolor[t[0]][c] + s->b1 * o->vcolor[t[1]][c] + s->b2 * o->vcolor[t[2]][c];
}

void shade_vertex_colors(const RenderFrame *f, RenderObject *o) {
  int nv = o->mesh->nverts;
  o->vcolor = xmalloc((size_t)nv * sizeof *o->vcolor);
  for (int i = 0; i < nv; i++) {
    const float *p = o->wpos[i];
    Vec3 vd = camera_view_dir(&f->camera, v3(p[0], p[1], p[2]));
    float v[3] = {(float)vd.x, (float)vd.y, (float)vd.z};
    float n[3] = {o->wnrm[i][0], o->wnrm[i][1], o->wnrm[i][2]};
    if (dot3(n, v) < 0) { n[0] = -n[0]; n[1] = -n[1]; n[2] = -n[2]; }
    phong_terms(f, o->style, p, n, v, o->vcolor[i]);
  }
}
