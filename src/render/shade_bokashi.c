/*
** Bokashi, the ukiyo-e gradation of colour (001 section 2.2.3; its
** coherence in 3.3.3 and 3.3.4), between the style's two colours (lit and
** unlit), both around the object's centre c (RenderCentre):
**
** Bokashi 2, `shade bokashi sphere`: shaded as if the object were a sphere
** around c. The normal is n = normalise(p - c) and each light's vector d
** runs from c to the light, so
**   f = clamp(sum_i (n.d_i / |d_i|) s_i / |d_i|^2, 0, 1)
** with the lights added before the clamp (a sun: its unit direction and s_i
** alone). The sum is n . K with K one vector per object. Per vertex
** (Gouraud: f at each vertex into its colour, interpolated) or per pixel
** (Phong: f at each sample's surface point; on a sphere about c that is the
** paper's interpolated vertex normals' direction).
**
** Bokashi 1, `shade bokashi linear`: a straight gradation in screen space.
** The gradation point g = c + d^ (s / |d|^2 s_mod + o), d the ray from the
** strongest light at c to c, is taken to the screen by the camera's local
** scale at c, then moved along the ray's screen direction D by the view
** modifier m = (v^.l^) m_base (v from the eye to c, l from the light to c):
** m < 0 when the object stands between the viewer and the light, and the
** boundary then moves toward the light. The line through g across D is the
** border: toward the light the colour is lit; away from it the colour runs
** to unlit over 1 / rate scene units at c's depth. Rate and m are in scene
** units, so in pixels the rate grows and m shrinks with depth (3.3.3).
*/
#include "shade.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"

/* ---- lights at the centre ------------------------------------------------- */

/* Light i as the bokashi formulas see it from c: the unit vector from c to
** the light into d, and s / |d|^2 (a sun: s) returned; s is the mean of the
** light's colour times strength. */
static float light_at_centre(const RenderFrame *f, int i, const float c[3], float d[3]) {
  const RenderLight *lt = &f->lights[i];
  float s = (lt->color[0] + lt->color[1] + lt->color[2]) / 3;
  if (lt->directional) {
    d[0] = lt->dir[0]; d[1] = lt->dir[1]; d[2] = lt->dir[2];
    return s;
  }
  float x = lt->pos[0] - c[0], y = lt->pos[1] - c[1], z = lt->pos[2] - c[2];
  float d2 = x * x + y * y + z * z, inv = d2 > 0 ? 1 / sqrtf(d2) : 0;
  d[0] = x * inv; d[1] = y * inv; d[2] = z * inv;
  if (lt->spot) s *= shade_spot(lt, d[0], d[1], d[2]);   /* c outside its cone: no light */
  return d2 > 0 ? s / d2 : 0;
}

static float mixc(float a, float b, float t) { return a + t * (b - a); }

static float clamp01(float x) { return x > 0 ? (x < 1 ? x : 1) : 0; }   /* NaN to 0 */

/* The gradation's two ends at sample k of r (object o): the style's, or
** with an image map and no colour given, the map's colour as the base
** (lit = base, unlit = base times BOKASHI_UNLIT_DEFAULT). */
static void ends_at(const ShadeRow *r, const RenderObject *o, int k, float lit[3], float unlit[3]) {
  const RenderStyle *st = o->style;
  const ShadeBokashi *b = &st->src->shade.bokashi;
  memcpy(lit, st->lit_color, 3 * sizeof *lit);
  memcpy(unlit, st->unlit_color, 3 * sizeof *unlit);
  if (!st->image) return;
  float base[3] = {r->br[k], r->bg[k], r->bb[k]};
  for (int c = 0; c < 3; c++) {
    if (!b->has_lit) lit[c] = base[c];
    if (!b->has_unlit) unlit[c] = base[c] * BOKASHI_UNLIT_DEFAULT;
  }
}

/* ---- bokashi 2: the sphere ------------------------------------------------- */

/* The unit vector from c to vertex v of o's world positions into n (0 at c). */
static void from_centre(const RenderObject *o, int v, const float c[3], float n[3]) {
  n[0] = o->wpos[v][0] - c[0]; n[1] = o->wpos[v][1] - c[1]; n[2] = o->wpos[v][2] - c[2];
  float l = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), il = l > 0 ? 1 / l : 0;
  n[0] *= il; n[1] *= il; n[2] *= il;
}

/* With shadows: each light's part of k, and for the per-vertex sphere
** n.k_i at each vertex. */
static void sphere_prepare_shadowed(const RenderFrame *f, RenderObject *o, BokashiObject *b, float smod) {
  const float *c = o->centre.world;
  int nl = f->nlights;
  b->kl = xcalloc((size_t)nl + 1, sizeof *b->kl);
  for (int i = 0; i < nl; i++) {
    float d[3], s = light_at_centre(f, i, c, d) * smod;
    for (int k = 0; k < 3; k++) b->kl[i][k] = d[k] * s;
  }
  if (o->style->src->shade.bokashi.per_pixel) return;
  b->vk = xmalloc((size_t)o->mesh->nverts * nl * sizeof *b->vk + 1);
  for (int v = 0; v < o->mesh->nverts; v++) {
    float n[3];
    from_centre(o, v, c, n);
    for (int i = 0; i < nl; i++) b->vk[(size_t)v * nl + i] = n[0] * b->kl[i][0] + n[1] * b->kl[i][1] + n[2] * b->kl[i][2];
  }
}

static void sphere_prepare(const RenderFrame *f, RenderObject *o, BokashiObject *b) {
  const float *c = o->centre.world;
  float smod = (float)o->style->src->shade.bokashi.strength_mod;
  for (int i = 0; i < f->nlights; i++) {
    float d[3], s = light_at_centre(f, i, c, d) * smod;
    for (int k = 0; k < 3; k++) b->k[k] += d[k] * s;
  }
  if (o->wfnrm) {
    sphere_prepare_shadowed(f, o, b, smod);
    return;
  }
  if (o->style->src->shade.bokashi.per_pixel) return;
  const RenderStyle *st = o->style;   /* Gouraud: the colour at each vertex, n = normalise(p - c) */
  int nv = o->mesh->nverts;
  o->vcolor = xmalloc((size_t)nv * sizeof *o->vcolor + 1);
  for (int v = 0; v < nv; v++) {
    float n[3] = {o->wpos[v][0] - c[0], o->wpos[v][1] - c[1], o->wpos[v][2] - c[2]};
    float l = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);   /* a vertex at c: f = 0 */
    float t = clamp01((n[0] * b->k[0] + n[1] * b->k[1] + n[2] * b->k[2]) * (l > 0 ? 1 / l : 0));
    for (int k = 0; k < 3; k++)   /* with an image map, t itself: the ends are the sample's */
      o->vcolor[v][k] = st->image ? t : mixc(st->unlit_color[k], st->lit_color[k], t);
  }
}

/* With shadows, samples k0..k1-1 of r: f = clamp(sum_i vis_i n.k_i), each
** light's part times the share of it reaching the sample's point (per
** pixel: n = normalise(p - c); per vertex: n.k_i interpolated). */
static void sphere_span_shadowed(const ShadeRow *r, const RenderObject *o, int k0, int k1, float *rgb,
                                 int stride) {
  const RenderFrame *f = r->frame;
  const BokashiObject *b = o->bokashi;
  const float *c = o->centre.world;
  int nl = f->nlights;
  for (int k = k0; k < k1; k++) {
    float p[3] = {r->px[k], r->py[k], r->pz[k]}, n[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
    float dd = n[0] * n[0] + n[1] * n[1] + n[2] * n[2], in = dd > 0 ? 1 / sqrtf(dd) : 0;
    const int *t = o->mesh->tri[r->face[k]];
    float b1 = r->bary[k][0], b2 = r->bary[k][1], b0 = 1 - b1 - b2, sum = 0;
    for (int i = 0; i < nl; i++) {
      float part = b->vk ? b0 * b->vk[(size_t)t[0] * nl + i] + b1 * b->vk[(size_t)t[1] * nl + i] +
                               b2 * b->vk[(size_t)t[2] * nl + i]
                         : (n[0] * b->kl[i][0] + n[1] * b->kl[i][1] + n[2] * b->kl[i][2]) * in;
      if (part > 0 && f->lights[i].shadow) part *= shade_reach(f, i, o, r->face[k], p);
      sum += part;
    }
    float *out = rgb + (size_t)k * stride, w = clamp01(sum), l[3], u[3];
    ends_at(r, o, k, l, u);
    for (int q = 0; q < 3; q++) out[q] = mixc(u[q], l[q], w);
  }
}

/* Samples sphere_span works on at a time (its factors live on the stack). */
#define BOKASHI_BLOCK 64

/* Phong: f at each sample's own surface point, n = normalise(p - c): the
** rebuilt point planes, several samples side by side. */
static void sphere_span(const ShadeRow *r, const RenderObject *o, int k0, int k1, float *rgb, int stride) {
  const BokashiObject *b = o->bokashi;
  const float *lit = o->style->lit_color, *unlit = o->style->unlit_color, *c = o->centre.world;
  float kx = b->k[0], ky = b->k[1], kz = b->k[2], f[BOKASHI_BLOCK];
  for (int k = k0; k < k1; k += BOKASHI_BLOCK) {
    int n = k1 - k < BOKASHI_BLOCK ? k1 - k : BOKASHI_BLOCK;
    const float *px = r->px + k, *py = r->py + k, *pz = r->pz + k;
    for (int j = 0; j < n; j++) {
      float x = px[j] - c[0], y = py[j] - c[1], z = pz[j] - c[2], dd = x * x + y * y + z * z;
      float t = (x * kx + y * ky + z * kz) * (dd > 0 ? 1 / sqrtf(dd) : 0);   /* at c: 0 */
      f[j] = t > 0 ? (t < 1 ? t : 1) : 0;
    }
    float *out = rgb + (size_t)k * stride;
    if (o->style->image) {
      for (int j = 0; j < n; j++, out += stride) {
        float l[3], u[3];
        ends_at(r, o, k + j, l, u);
        for (int q = 0; q < 3; q++) out[q] = mixc(u[q], l[q], f[j]);
      }
      continue;
    }
    for (int j = 0; j < n; j++, out += stride)
      for (int q = 0; q < 3; q++) out[q] = mixc(unlit[q], lit[q], f[j]);
  }
}

/* Gouraud: the vertex colours, interpolated. */
static void vertex_span(const ShadeRow *r, const RenderObject *o, int k0, int k1, float *rgb, int stride) {
  for (int k = k0; k < k1; k++) {
    const int *t = o->mesh->tri[r->face[k]];
    float b1 = r->bary[k][0], b2 = r->bary[k][1], b0 = 1 - b1 - b2;
    float *out = rgb + (size_t)k * stride;
    for (int c = 0; c < 3; c++)
      out[c] = b0 * o->vcolor[t[0]][c] + b1 * o->vcolor[t[1]][c] + b2 * o->vcolor[t[2]][c];
    if (o->style->image) {   /* the colours held t: the ends are the sample's */
      float l[3], u[3];
      ends_at(r, o, k, l, u);
      for (int c = 0; c < 3; c++) out[c] = mixc(u[c], l[c], out[c]);
    }
  }
}

/* ---- bokashi 1: the linear gradation ---------------------------------------- */

/* Screen position (output pixels) of world point p, and whether it is in
** front of the camera. */
static int to_screen(const Camera *cam, Vec3 p, double out[2]) {
  double clip[4];
  camera_to_clip(cam, p, clip);
  if (!(clip[3] > 1e-12)) return 0;
  out[0] = (clip[0] / clip[3] + 1) * 0.5 * cam->width;
  out[1] = (1 - clip[1] / clip[3]) * 0.5 * cam->height;
  return 1;
}

static void linear_prepare(const RenderFrame *f, RenderObject *o, BokashiObject *b) {
  const ShadeBokashi *sb = &o->style->src->shade.bokashi;
  const RenderCentre *rc = &o->centre;
  const Camera *cam = &f->camera;
  Vec3 c = v3(rc->world[0], rc->world[1], rc->world[2]);
  float best = -1, ray[3] = {0, 0, -1};   /* the strongest light at c (the first of equals) */
  b->light = -1;
  for (int i = 0; i < f->nlights; i++) {
    float d[3], s = light_at_centre(f, i, rc->world, d);
    if (s > best) { best = s; ray[0] = -d[0]; ray[1] = -d[1]; ray[2] = -d[2]; b->light = i; }
  }
  float S = best > 0 ? best : 0;
  /* the ray's screen direction at c: pixels a scene unit along it */
  double eps = rc->wpp, a[2], e[2], D[2] = {0, 0};
  if (to_screen(cam, c, a) && to_screen(cam, v3_add(c, v3_mul(v3(ray[0], ray[1], ray[2]), eps)), e)) {
    D[0] = (e[0] - a[0]) / eps;
    D[1] = (e[1] - a[1]) / eps;
  }
  double len = sqrt(D[0] * D[0] + D[1] * D[1]);
  double ux = len > 1e-9 ? D[0] / len : 0, uy = len > 1e-9 ? D[1] / len : -1;   /* along the view: up */
  Vec3 v = cam->kind == CAMERA_ORTHO ? cam->forward : v3_norm(v3_sub(c, cam->eye));
  double m = (v.x * ray[0] + v.y * ray[1] + v.z * ray[2]) * sb->view_mod;   /* (v^.l^) m_base */
  double shift = S * sb->strength_mod + sb->offset;                          /* scene units along d^ */
  b->g[0] = (float)(rc->px[0] + D[0] * shift + ux * m / rc->wpp);
  b->g[1] = (float)(rc->px[1] + D[1] * shift + uy * m / rc->wpp);
  b->dir[0] = (float)ux;
  b->dir[1] = (float)uy;
  b->rate = (float)(sb->rate * rc->wpp);
}

static void linear_span(const ShadeRow *r, const RenderObject *o, int k0, int k1, float *rgb, int stride) {
  const BokashiObject *b = o->bokashi;
  const float *lit = o->style->lit_color, *unlit = o->style->unlit_color;
  float inv_n = 1.0f / (float)r->frame->samples;
  float y = ((float)r->sy + 0.5f) * inv_n - b->g[1];
  int shadowed = o->wfnrm && b->light >= 0 && r->frame->lights[b->light].shadow;
  for (int k = k0; k < k1; k++) {
    float x = ((float)(r->sx0 + k) + 0.5f) * inv_n - b->g[0];
    float t = clamp01((x * b->dir[0] + y * b->dir[1]) * b->rate);   /* 0 on the lit side */
    if (shadowed) {   /* in the strongest light's shadow, toward unlit */
      float p[3] = {r->px[k], r->py[k], r->pz[k]};
      t = 1 - (1 - t) * shade_reach(r->frame, b->light, o, r->face[k], p);
    }
    float *out = rgb + (size_t)k * stride;
    if (o->style->image) {
      float l[3], u[3];
      ends_at(r, o, k, l, u);
      for (int c = 0; c < 3; c++) out[c] = mixc(l[c], u[c], t);
      continue;
    }
    for (int c = 0; c < 3; c++) out[c] = mixc(lit[c], unlit[c], t);
  }
}

/* ---- entry points ------------------------------------------------------------ */

void shade_bokashi_prepare(const RenderFrame *f, RenderObject *o) {
  BokashiObject *b = o->bokashi = xcalloc(1, sizeof *b);
  if (o->style->src->shade.bokashi.sphere) sphere_prepare(f, o, b);
  else linear_prepare(f, o, b);
}

void shade_bokashi_free(RenderObject *o) {
  if (!o->bokashi) return;
  free(o->bokashi->kl);
  free(o->bokashi->vk);
  free(o->bokashi);
  o->bokashi = NULL;
}

void shade_bokashi_span(const ShadeRow *r, const RenderObject *o, int k0, int k1, float *rgb, int stride) {
  const ShadeBokashi *sb = &o->style->src->shade.bokashi;
  if (!sb->sphere) linear_span(r, o, k0, k1, rgb, stride);
  else if (o->bokashi->kl) sphere_span_shadowed(r, o, k0, k1, rgb, stride);
  else if (sb->per_pixel) sphere_span(r, o, k0, k1, rgb, stride);
  else vertex_span(r, o, k0, k1, rgb, stride);
}

/* One sample as a row of one. */
void shade_bokashi(const ShadeSample *s, float rgb[3]) {
  shade_span_one(s, shade_bokashi_span, rgb);
}
