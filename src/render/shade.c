/*
** Shading: the model table, lights, the smooth diffuse and specular terms,
** and the flat, gouraud, phong and unlit models (shade.h).
*/
#include "shade.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"
#include "../lang/diag.h"
#include "imagemap.h"
#include "shadow.h"
#include "texcoord.h"

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
  /* SHADE_THRESHOLD */ shade_threshold,
  /* SHADE_BOKASHI */   shade_bokashi,
  /* SHADE_INK */       shade_ink,
  /* SHADE_ORIGAMI */   shade_phong,   /* paper is origami.c's; an object gets a warning (main.c) */
};

ShadeFn shade_model(ShadeKind kind) {
  if ((unsigned)kind < sizeof models / sizeof models[0]) return models[kind];
  return shade_phong;
}

ShadeSpanFn shade_span_model(ShadeKind kind) {
  if (kind == SHADE_TOON) return shade_toon_span;
  if (kind == SHADE_BOKASHI) return shade_bokashi_span;
  if (kind == SHADE_THRESHOLD) return shade_threshold_span;
  if (kind == SHADE_INK) return shade_ink_span;
  return shade_span_generic;
}

void shade_span_one(const ShadeSample *s, ShadeSpanFn span, float rgb[3]) {
  float p[3] = {s->p[0], s->p[1], s->p[2]}, n[3] = {s->n[0], s->n[1], s->n[2]};
  float v[3] = {s->v[0], s->v[1], s->v[2]}, uv[2] = {s->uv[0], s->uv[1]};
  float bary[1][2] = {{s->b1, s->b2}}, b[3] = {s->base[0], s->base[1], s->base[2]};
  int32_t face = s->face;
  ShadeRow r = {s->frame, &face, (const float(*)[2])bary, &p[0], &p[1], &p[2],
                &n[0], &n[1], &n[2], &v[0], &v[1], &v[2], &uv[0], &uv[1], &b[0], &b[1], &b[2],
                s->sx, s->sy, .step_key = NULL};
  span(&r, s->obj, 0, 1, rgb, 3);
}

void shade_span_generic(const ShadeRow *r, const RenderObject *o, int k0, int k1, float *rgb,
                        int stride) {
  ShadeFn fn = shade_model(o->style->kind);
  ShadeSample s;
  for (int k = k0; k < k1; k++) {
    shade_row_sample(r, o, k, &s);
    fn(&s, rgb + (size_t)k * stride);
  }
}

int shade_reads_uv(ShadeKind kind) {
  /* the models in this file, shade_toon.c and shade_threshold.c (which
  ** makes its own coordinates) do not; textured ones will */
  return kind == SHADE_ORIGAMI;
}

/* ---- image maps ------------------------------------------------------------ */

/* A style's image map and the camera its coordinates' steps are taken for. */
typedef struct ImageStyle {
  ImageMap *map;
  TexView view;                /* the frame's, set when its objects are prepared */
} ImageStyle;

/* Read st's texture into rs->image; 0 after a diagnostic. */
static int image_style_init(RenderStyle *rs, const SceneStyle *st) {
  rs->image = NULL;
  if (!st->texture) return 1;
  char err[600];
  ImageMap *m = imagemap_load(st->texture, err, sizeof err);
  if (!m) {
    diag_error(st->texture_loc, "`texture` in `style`: %s", err);   /* err names the file and the reason */
    return 0;
  }
  rs->image = xcalloc(1, sizeof *rs->image);
  rs->image->map = m;
  return 1;
}

/* An image-mapped object's triangles' coordinates for f's camera: its
** own (u, v) where its geometry has them, else a box projection of
** object space, one unit a copy of the image; times texture_repeat. */
static void image_prepare(const RenderFrame *f, RenderObject *o) {
  ImageStyle *is = o->style->image;
  texcoord_view(&is->view, &f->camera);   /* the same for every object of the frame */
  int projection = texcoord_resolve(o, PROJ_AUTO), n = o->mesh->ntris;
  o->imgcoords = xmalloc(((size_t)n + 1) * sizeof *o->imgcoords);
  for (int t = 0; t < n; t++)   /* a back face the rasterizer skips is never shaded */
    if (!(o->cull_back && o->backfacing[t]))
      texcoord_triangle(&o->imgcoords[t], o, t, projection, (float)o->style->src->texture_repeat, &is->view);
}

/* Samples the image run works on at once (its coordinates on the stack). */
#define IMAGE_BLOCK 64

void shade_image_run(ShadeRow *r, const RenderObject *o, int face, int k0, int k1) {
  const ImageStyle *is = o->style->image;
  const float *base = o->style->base;
  float u[IMAGE_BLOCK], v[IMAGE_BLOCK], ux[IMAGE_BLOCK], uy[IMAGE_BLOCK], vx[IMAGE_BLOCK], vy[IMAGE_BLOCK];
  for (int k = k0; k < k1; k += IMAGE_BLOCK) {
    int n = k1 - k < IMAGE_BLOCK ? k1 - k : IMAGE_BLOCK;
    texcoord_run(&o->imgcoords[face], &is->view, n, r->bary + k, r->px + k, r->py + k, r->pz + k, u, v, ux, uy,
                 vx, vy);
    for (int j = 0; j < n; j++) {
      float t[4];   /* colour times alpha */
      imagemap_sample(is->map, u[j], v[j], ux[j], vx[j], uy[j], vy[j], t);
      float keep = 1 - t[3];   /* the base shows through what the image leaves */
      r->br[k + j] = base[0] * keep + t[0];
      r->bg[k + j] = base[1] * keep + t[1];
      r->bb[k + j] = base[2] * keep + t[2];
    }
  }
}

void shade_base_block(const ShadeRow *r, const RenderObject *o, int k0, int n, float *R, float *G, float *B) {
  if (o->style->image) {
    memcpy(R, r->br + k0, (size_t)n * sizeof *R);
    memcpy(G, r->bg + k0, (size_t)n * sizeof *G);
    memcpy(B, r->bb + k0, (size_t)n * sizeof *B);
    return;
  }
  const float *base = o->style->base;
  for (int j = 0; j < n; j++) { R[j] = base[0]; G[j] = base[1]; B[j] = base[2]; }
}

int shade_style_init(RenderStyle *rs, const SceneStyle *st) {
  const ShadeToon *t = &st->shade.toon;
  rs->src = st;
  rs->kind = st->shade.kind;
  rs->base[0] = st->base.r;
  rs->base[1] = st->base.g;
  rs->base[2] = st->base.b;
  rs->ambient = (float)t->ambient;
  rs->specular = (float)t->specular;
  rs->shininess = t->shininess > 0 ? (float)t->shininess : 32.0f;
  rs->bands_n = (t->bands >= 2 ? t->bands : st->shade.kind == SHADE_THRESHOLD ? 2 : 3) - 1;
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
  rs->lit = st->shade.kind != SHADE_FLAT || st->shade.lit;
  const ShadeBokashi *b = &st->shade.bokashi;   /* unlit by default: the base at a quarter of its light */
  Color lit = b->has_lit ? b->lit : st->base, unlit = b->has_unlit ? b->unlit : st->base;
  float dim = b->has_unlit ? 1 : BOKASHI_UNLIT_DEFAULT;
  rs->lit_color[0] = lit.r; rs->lit_color[1] = lit.g; rs->lit_color[2] = lit.b;
  rs->unlit_color[0] = unlit.r * dim; rs->unlit_color[1] = unlit.g * dim; rs->unlit_color[2] = unlit.b * dim;
  /* an SVG region's flat colour: the base, or a bokashi's lit end */
  for (int c = 0; c < 3; c++) rs->fill[c] = rs->kind == SHADE_BOKASHI ? rs->lit_color[c] : rs->base[c];
  rs->alpha = st->shade.kind == SHADE_INK ? 0.0f : 1.0f;   /* ink: painted on the canvas later */
  rs->ink = NULL;                                          /* shade_ink_prepare */
  rs->layers = NULL;
  int ok = image_style_init(rs, st);
  return (rs->kind == SHADE_THRESHOLD ? shade_threshold_init(rs, st) : 1) && ok;
}

void shade_centre_init(const RenderFrame *f, RenderObject *o) {
  const Camera *c = &f->camera;
  Vec3 w = m4_point(o->object_to_world, o->src->has_centre ? o->src->centre : v3(0, 0, 0));
  RenderCentre *rc = &o->centre;
  rc->world[0] = (float)w.x; rc->world[1] = (float)w.y; rc->world[2] = (float)w.z;
  double clip[4];
  camera_to_clip(c, w, clip);
  double iw = clip[3] > 1e-12 ? 1 / clip[3] : 1e12;   /* behind the eye: far off screen */
  rc->px[0] = (float)((clip[0] * iw + 1) * 0.5 * c->width);
  rc->px[1] = (float)((1 - clip[1] * iw) * 0.5 * c->height);
  if (c->kind == CAMERA_ORTHO) {
    rc->wpp = (float)(c->ortho_height / c->height);
  } else {   /* depth along forward over the focal length in pixels; at least the near plane's */
    double z = fmax(v3_dot(v3_sub(w, c->eye), c->forward), c->znear);
    rc->wpp = (float)(z * 2 * tan(c->fov * M_PI / 360) / c->height);
  }
}

void shade_style_free(RenderStyle *rs) {
  shade_threshold_free(rs);
  if (rs->image) imagemap_free(rs->image->map);
  free(rs->image);
  rs->image = NULL;
}

int shade_prepare_object(const RenderFrame *f, RenderObject *o) {
  if (o->style->image) image_prepare(f, o);
  if (o->style->kind == SHADE_GOURAUD) shade_vertex_colors(f, o);
  if (o->style->kind == SHADE_BOKASHI) shade_bokashi_prepare(f, o);
  return o->style->kind == SHADE_THRESHOLD ? shade_threshold_prepare(f, o) : 1;
}

/* ---- rows of samples ---------------------------------------------------- */

void shade_view_init(ShadeView *view, const Camera *c, int samples) {
  double t = c->kind == CAMERA_PERSPECTIVE ? tan(c->fov * M_PI / 360) : 0, aspect = (double)c->width / c->height;
  *view = (ShadeView){.ortho = c->kind == CAMERA_ORTHO};
  const Vec3 *axes[3] = {&c->forward, &c->right, &c->up};
  float *to[3] = {view->fwd, view->right, view->up};
  for (int a = 0; a < 3; a++) {
    to[a][0] = (float)axes[a]->x; to[a][1] = (float)axes[a]->y; to[a][2] = (float)axes[a]->z;
  }
  for (int i = 0; i < 3; i++) view->back[i] = -view->fwd[i];
  view->cx = (float)(t * aspect);                              /* ndc x = 1 at the right edge */
  view->kx = (float)(2 * t * aspect / ((double)c->width * samples));
  view->cy = (float)t;
  view->ky = (float)(2 * t / ((double)c->height * samples));
}

void shade_row_alloc(ShadeRow *r, const RenderFrame *f, int n) {
  int m = n + SHADE_LANES;   /* spare lanes: shade_row_rebuild writes up to 3 past a run */
  float *pl = xcalloc(14 * (size_t)m, sizeof *pl);   /* p, n, v, uv, base: one block, px first */
  *r = (ShadeRow){.frame = f, .px = pl, .py = pl + m, .pz = pl + 2 * m,
                  .nx = pl + 3 * m, .ny = pl + 4 * m, .nz = pl + 5 * m,
                  .vx = pl + 6 * m, .vy = pl + 7 * m, .vz = pl + 8 * m,
                  .u = pl + 9 * m, .v = pl + 10 * m,
                  .br = pl + 11 * m, .bg = pl + 12 * m, .bb = pl + 13 * m};
}

void shade_row_free(ShadeRow *r) { free(r->px); }

/* One group: samples k..k+SHADE_LANES-1 of a row from corners c (p0, p1,
** p2, n0, n1, n2) and their (b1, b2) pairs in b12: the planes get the
** surface, the unit normal (times sign: -1 on a back face) and the unit
** view vector. A fixed number of lanes and restrict planes, so the compiler
** runs the group side by side (SSE); each lane's arithmetic is that of one
** sample alone, in the same order. */
/* A row's view rays: sample sx's is base + ((sx + 0.5) kx - cx) right. */
typedef struct RayRow { float base[3], right[3], kx, cx; int sx0; } RayRow;

/* Row sy's part of its view rays, along fwd and up. */
static void ray_base(const ShadeView *view, int sy, float base[3]) {
  float ay = view->cy - ((float)sy + 0.5f) * view->ky;
  for (int c = 0; c < 3; c++) base[c] = view->fwd[c] + ay * view->up[c];
}

static RayRow ray_row(const ShadeView *view, int sx0, const float base[3]) {
  RayRow rr = {.kx = view->kx, .cx = view->cx, .sx0 = sx0};
  for (int c = 0; c < 3; c++) {
    rr.base[c] = base[c];
    rr.right[c] = view->right[c];
  }
  return rr;
}

void shade_row_start(ShadeRow *r, const ShadeView *view, int sx0, int sy) {
  r->sx0 = sx0;
  r->sy = sy;
  ray_base(view, sy, r->ray_base);
}

static inline __attribute__((always_inline)) void rebuild_group(
    const float *const c[6], const RayRow *rr, float sign, int k, const float *restrict b12,
    float *restrict px, float *restrict py, float *restrict pz, float *restrict nx,
    float *restrict ny, float *restrict nz, float *restrict vx, float *restrict vy,
    float *restrict vz) {
  const float *p0 = c[0], *p1 = c[1], *p2 = c[2], *n0 = c[3], *n1 = c[4], *n2 = c[5];
  for (int j = 0; j < SHADE_LANES; j++) {
    float b1 = b12[2 * j], b2 = b12[2 * j + 1], b0 = 1 - b1 - b2;
    float x = b0 * p0[0] + b1 * p1[0] + b2 * p2[0];
    float y = b0 * p0[1] + b1 * p1[1] + b2 * p2[1];
    float z = b0 * p0[2] + b1 * p1[2] + b2 * p2[2];
    float a = b0 * n0[0] + b1 * n1[0] + b2 * n2[0];
    float b = b0 * n0[1] + b1 * n1[1] + b2 * n2[1];
    float d = b0 * n0[2] + b1 * n1[2] + b2 * n2[2];
    float nn = a * a + b * b + d * d;
    float sn = (nn > 0 ? 1 / sqrtf(nn) : 0) * sign;   /* a zero normal stays zero */
    float ax = ((float)(rr->sx0 + k + j) + 0.5f) * rr->kx - rr->cx;   /* the ray, reversed */
    float ex = rr->base[0] + ax * rr->right[0], ey = rr->base[1] + ax * rr->right[1],
          ez = rr->base[2] + ax * rr->right[2];
    float vv = ex * ex + ey * ey + ez * ez;
    float sv = vv > 0 ? -1 / sqrtf(vv) : 0;
    px[k + j] = x; py[k + j] = y; pz[k + j] = z;
    nx[k + j] = a * sn; ny[k + j] = b * sn; nz[k + j] = d * sn;
    vx[k + j] = ex * sv; vy[k + j] = ey * sv; vz[k + j] = ez * sv;
  }
}

/* Samples k0..k1-1 of a row, group by group; the last group's lanes past
** k1 read (0, 0) and write the planes' spare samples past the run. */
static inline void rebuild_run(const float *const c[6], const RayRow *rr, float sign, int k0,
                               int k1, const float *restrict bary, float *restrict px,
                               float *restrict py, float *restrict pz, float *restrict nx,
                               float *restrict ny, float *restrict nz, float *restrict vx,
                               float *restrict vy, float *restrict vz) {
  int k = k0;
  for (; k + SHADE_LANES <= k1; k += SHADE_LANES)
    rebuild_group(c, rr, sign, k, bary + 2 * k, px, py, pz, nx, ny, nz, vx, vy, vz);
  if (k == k1) return;
  float tail[2 * SHADE_LANES] = {0};
  for (int j = 0; j < SHADE_LANES; j++)   /* a fixed count: no call to memcpy for a sample or two */
    if (k + j < k1) tail[2 * j] = bary[2 * (k + j)], tail[2 * j + 1] = bary[2 * (k + j) + 1];
  rebuild_group(c, rr, sign, k, tail, px, py, pz, nx, ny, nz, vx, vy, vz);
}

void shade_row_rebuild(ShadeRow *r, const ShadeView *view, const RenderObject *o, int face,
                       int k0, int k1) {
  const int *t = o->mesh->tri[face];
  const float *c[6] = {o->wpos[t[0]], o->wpos[t[1]], o->wpos[t[2]],   /* then the normals: */
                       o->wnrm[t[0]], o->wnrm[t[1]], o->wnrm[t[2]]};
  if (o->wcnrm) {   /* hard edges: the triangle's own corner normals */
    c[3] = o->wcnrm[face][0]; c[4] = o->wcnrm[face][1]; c[5] = o->wcnrm[face][2];
  }
  float sign = o->backfacing[face] ? -1.0f : 1.0f;   /* a back face's normal turns around */
  const float *bary = r->bary[0];   /* (b1, b2) pairs, read flat */
  RayRow rr = ray_row(view, r->sx0, r->ray_base);   /* its base made once a row */
  rebuild_run(c, &rr, sign, k0, k1, bary, r->px, r->py, r->pz, r->nx, r->ny, r->nz, r->vx,
              r->vy, r->vz);
  if (view->ortho)   /* the one unit view vector */
    for (int j = k0; j < k1; j++) {
      r->vx[j] = view->back[0]; r->vy[j] = view->back[1]; r->vz[j] = view->back[2];
    }
  if (!view->want_uv) return;   /* no style reads uv: its planes stay 0 */
  const Vec2 *uv = o->mesh->uv;
  for (int j = k0; j < k1; j++) r->u[j] = r->v[j] = 0;
  if (!uv) return;
  for (int j = k0; j < k1; j++) {
    float b1 = bary[2 * j], b2 = bary[2 * j + 1], b0 = 1 - b1 - b2;
    r->u[j] = (float)(b0 * uv[t[0]].x + b1 * uv[t[1]].x + b2 * uv[t[2]].x);
    r->v[j] = (float)(b0 * uv[t[0]].y + b1 * uv[t[1]].y + b2 * uv[t[2]].y);
  }
}

void shade_surface_at(const ShadeView *view, const RenderObject *o, int face, float b1, float b2,
                      int sx, int sy, float p[3], float n[3], float v[3]) {
  const int *t = o->mesh->tri[face];
  const float *p0 = o->wpos[t[0]], *p1 = o->wpos[t[1]], *p2 = o->wpos[t[2]];
  const float *n0 = o->wnrm[t[0]], *n1 = o->wnrm[t[1]], *n2 = o->wnrm[t[2]];
  if (o->wcnrm) { n0 = o->wcnrm[face][0]; n1 = o->wcnrm[face][1]; n2 = o->wcnrm[face][2]; }
  float b0 = 1 - b1 - b2;
  p[0] = b0 * p0[0] + b1 * p1[0] + b2 * p2[0];
  p[1] = b0 * p0[1] + b1 * p1[1] + b2 * p2[1];
  p[2] = b0 * p0[2] + b1 * p1[2] + b2 * p2[2];
  n[0] = b0 * n0[0] + b1 * n1[0] + b2 * n2[0];
  n[1] = b0 * n0[1] + b1 * n1[1] + b2 * n2[1];
  n[2] = b0 * n0[2] + b1 * n1[2] + b2 * n2[2];
  float nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
  float sn = (nn > 0 ? 1 / sqrtf(nn) : 0) * (o->backfacing[face] ? -1.0f : 1.0f);
  n[0] *= sn; n[1] *= sn; n[2] *= sn;
  if (view->ortho) { v[0] = view->back[0]; v[1] = view->back[1]; v[2] = view->back[2]; return; }
  float base[3];
  ray_base(view, sy, base);
  RayRow rr = ray_row(view, sx, base);   /* as rebuild_group makes it */
  float ax = ((float)sx + 0.5f) * rr.kx - rr.cx;
  for (int c = 0; c < 3; c++) v[c] = rr.base[c] + ax * rr.right[c];
  float vv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2], sv = vv > 0 ? -1 / sqrtf(vv) : 0;
  v[0] *= sv; v[1] *= sv; v[2] *= sv;
}

void shade_row_sample(const ShadeRow *r, const RenderObject *o, int k, ShadeSample *s) {
  s->frame = r->frame;
  s->obj = o;
  s->face = r->face[k];
  s->b1 = r->bary[k][0];
  s->b2 = r->bary[k][1];
  s->p[0] = r->px[k]; s->p[1] = r->py[k]; s->p[2] = r->pz[k];
  s->n[0] = r->nx[k]; s->n[1] = r->ny[k]; s->n[2] = r->nz[k];
  s->v[0] = r->vx[k]; s->v[1] = r->vy[k]; s->v[2] = r->vz[k];
  s->uv[0] = r->u[k];
  s->uv[1] = r->v[k];
  if (o->style->image) { s->base[0] = r->br[k]; s->base[1] = r->bg[k]; s->base[2] = r->bb[k]; }
  else memcpy(s->base, o->style->base, sizeof s->base);
  s->sx = r->sx0 + k;
  s->sy = r->sy;
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
  rgb[0] = s->base[0]; rgb[1] = s->base[1]; rgb[2] = s->base[2];
}

float shade_reach(const RenderFrame *f, int i, const RenderObject *o, int face, const float p[3]) {
  const RenderLight *lt = &f->lights[i];
  return lt->shadow && o->wfnrm ? shadow_visibility(lt->shadow, p, o->wfnrm[face]) : 1;
}

/* Light i's diffuse and specular terms with normal n, times its colour
** and k, added to rgb. */
static void phong_light(const RenderFrame *f, const RenderStyle *st, const float base[3], int i,
                        const float p[3], const float n[3], const float v[3], float k, float rgb[3]) {
  float l[3], col[3];
  shade_light(f, i, p, l, col);
  float fd = shade_diffuse(n, l);
  float fs = st->specular > 0 ? st->specular * shade_specular(n, l, v, st->shininess) : 0;
  for (int c = 0; c < 3; c++) rgb[c] += (base[c] * fd + fs) * (col[c] * k);
}

/* The smooth lighting equation (T = identity) with normal n; a light
** that casts shadows reaches p on triangle face of o as far as its map
** lets it (face < 0: every light wholly). */
static void phong_terms(const RenderFrame *f, const RenderObject *o, int face, const float base[3],
                        const float p[3], const float n[3], const float v[3], float rgb[3]) {
  const RenderStyle *st = o->style;
  for (int c = 0; c < 3; c++) rgb[c] = base[c] * st->ambient;
  for (int i = 0; i < f->nlights; i++) {
    if (face >= 0 && f->lights[i].shadow) {
      float l[3], col[3];
      shade_light(f, i, p, l, col);
      float k = shade_diffuse(n, l) > 0 ? shade_reach(f, i, o, face, p) : 0;
      if (k > 0) phong_light(f, st, base, i, p, n, v, k, rgb);
      continue;
    }
    phong_light(f, st, base, i, p, n, v, 1, rgb);
  }
}

void shade_phong(const ShadeSample *s, float rgb[3]) {
  phong_terms(s->frame, s->obj, s->face, s->base, s->p, s->n, s->v, rgb);
}

/* Flat: the lighting of the triangle's own plane, its normal turned toward
** the viewer like the shading normal; unlit (lit false), the base colour. */
void shade_flat(const ShadeSample *s, float rgb[3]) {
  const RenderObject *o = s->obj;
  if (!o->style->lit) { shade_unlit(s, rgb); return; }   /* lit false: one colour on every face */
  const int *t = o->mesh->tri[s->face];
  const float *a = o->wpos[t[0]], *b = o->wpos[t[1]], *c = o->wpos[t[2]];
  float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  float e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  float ng[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                 e1[0] * e2[1] - e1[1] * e2[0]};
  norm3(ng);
  if (o->backfacing[s->face]) { ng[0] = -ng[0]; ng[1] = -ng[1]; ng[2] = -ng[2]; }
  phong_terms(s->frame, o, s->face, s->base, s->p, ng, s->v, rgb);
}

/* Gouraud: the vertex colours, interpolated; where the mesh has corner
** normals (hard edges), each corner's own colour. With shadows, layer 0
** of the colours holds the ambient and the lights that cast none, and
** each light that casts one adds its own layer, interpolated the same
** way and times the share of it reaching the sample's own point. With an
** image map, each layer is two: what multiplies the base colour (the
** ambient and diffuse terms of a white base) and the highlight, so the
** map's colour is taken per sample. */
void shade_gouraud(const ShadeSample *s, float rgb[3]) {
  const RenderObject *o = s->obj;
  const int *t = o->mesh->tri[s->face];
  size_t i0 = t[0], i1 = t[1], i2 = t[2], count = (size_t)o->mesh->nverts;
  if (o->wcnrm) {
    i0 = 3 * (size_t)s->face; i1 = i0 + 1; i2 = i0 + 2; count = 3 * (size_t)o->mesh->ntris;
  }
  float b0 = 1 - s->b1 - s->b2;
  const float (*vc)[3] = o->vcolor;
  int parts = o->style->image ? 2 : 1;
  const RenderFrame *f = s->frame;
  for (int c = 0; c < 3; c++) rgb[c] = 0;
  for (int i = -1; i < f->nlights; i++) {   /* -1: layer 0 */
    if (i >= 0 && !(f->lights[i].shadow && o->wfnrm)) continue;
    float k = i < 0 ? 1 : shade_reach(f, i, o, s->face, s->p);
    for (int c = 0; c < 3; c++) {
      float d = b0 * vc[i0][c] + s->b1 * vc[i1][c] + s->b2 * vc[i2][c];
      if (parts == 2) d = d * s->base[c] + (b0 * vc[count + i0][c] + s->b1 * vc[count + i1][c] + s->b2 * vc[count + i2][c]);
      rgb[c] = i < 0 ? d : rgb[c] + k * d;
    }
    vc += parts * count;   /* the next layer */
  }
}

/* What part of the phong terms a vertex keeps (lit_point). */
enum { PART_ALL, PART_BASE, PART_SPECULAR };

/* The phong terms at world point p with normal n turned toward the
** viewer into rgb: with layer < 0 every light's; else the ambient and the
** lights that cast no shadow (layer 0), or the layer-th light that casts
** one alone (layer >= 1). part: all of them, the factor of the base colour
** (a white base without the highlight) or the highlight alone. */
static void lit_point(const RenderFrame *f, const RenderObject *o, const float p[3], const float nrm[3],
                      int layer, int part, float rgb[3]) {
  Vec3 vd = camera_view_dir(&f->camera, v3(p[0], p[1], p[2]));
  float v[3] = {(float)vd.x, (float)vd.y, (float)vd.z};
  float n[3] = {nrm[0], nrm[1], nrm[2]};
  if (dot3(n, v) < 0) { n[0] = -n[0]; n[1] = -n[1]; n[2] = -n[2]; }
  RenderStyle st = *o->style;
  static const float white[3] = {1, 1, 1}, black[3] = {0, 0, 0};
  const float *base = part == PART_BASE ? white : part == PART_SPECULAR ? black : st.base;
  if (part == PART_BASE) st.specular = 0;
  if (layer < 0 && part == PART_ALL) { phong_terms(f, o, -1, base, p, n, v, rgb); return; }
  for (int c = 0; c < 3; c++) rgb[c] = layer <= 0 ? base[c] * st.ambient : 0;
  for (int i = 0, j = 0; i < f->nlights; i++) {
    int shadowed = f->lights[i].shadow != NULL && layer >= 0;
    j += shadowed;
    if (layer < 0 || (shadowed ? j == layer : layer == 0)) phong_light(f, &st, base, i, p, n, v, 1, rgb);
  }
}

void shade_vertex_colors(const RenderFrame *f, RenderObject *o) {
  const Mesh *m = o->mesh;
  int layers = 1, parts = o->style->image ? 2 : 1;
  for (int i = 0; i < f->nlights; i++) layers += f->lights[i].shadow != NULL;
  int split = layers > 1 && o->wfnrm;   /* shadows: a layer per light that casts them */
  if (!split) layers = 1;
  size_t count = o->wcnrm ? 3 * (size_t)m->ntris : (size_t)m->nverts;
  o->vcolor = xmalloc((size_t)layers * parts * count * sizeof *o->vcolor + 1);
  for (int layer = 0; layer < layers; layer++)
    for (int part = 0; part < parts; part++) {
      float (*vc)[3] = o->vcolor + (layer * parts + part) * count;
      int which = split ? layer : -1, what = parts == 1 ? PART_ALL : part == 0 ? PART_BASE : PART_SPECULAR;
      if (o->wcnrm) {   /* hard edges: a colour per corner, from the corner's own normal */
        for (int t = 0; t < m->ntris; t++)
          for (int k = 0; k < 3; k++)
            lit_point(f, o, o->wpos[m->tri[t][k]], o->wcnrm[t][k], which, what, vc[3 * t + k]);
      } else {
        for (int i = 0; i < m->nverts; i++) lit_point(f, o, o->wpos[i], o->wnrm[i], which, what, vc[i]);
      }
    }
}
