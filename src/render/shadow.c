/*
** Shadow maps (shadow.h): the maps' frames for each kind of light, the
** triangles drawn into them in bands of rows on the workers, and the
** filtered reading.
*/
#include "shadow.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"
#include "../base/tasks.h"
#include "../lang/diag.h"
#include "stats.h"

/* Rows of a map one drawing task fills. */
#define SHADOW_BAND 128

static inline float dot3(const float a[3], const float b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void set3f(float d[3], double x, double y, double z) {
  d[0] = (float)x; d[1] = (float)y; d[2] = (float)z;
}

/* ---- the maps' frames ---------------------------------------------------- */

/* Texels kept around what a map must cover, so the filter's box at its
** border still reads inside it: half the box and two more. Never more
** than a quarter of the side. */
static int margin_texels(const ShadowMap *m) {
  int k = (int)ceilf(m->half) + 2;
  return k < m->n / 4 ? k : m->n / 4;
}

/* Unit axes a, b across the unit ray direction d (any right-handed pair). */
static void cross_axes(const float d[3], float a[3], float b[3]) {
  Vec3 dv = v3(d[0], d[1], d[2]);
  Vec3 up = fabs(dv.z) < 0.9 ? v3(0, 0, 1) : v3(1, 0, 0);
  Vec3 av = v3_norm(v3_cross(up, dv)), bv = v3_cross(dv, av);
  set3f(a, av.x, av.y, av.z);
  set3f(b, bv.x, bv.y, bv.z);
}

/* The sun's map: across its rays, over the box of every world vertex. */
static void frame_sun(ShadowMap *m, const RenderFrame *f, const RenderLight *lt) {
  ShadowFace *fc = &m->face[0];
  set3f(fc->d, -lt->dir[0], -lt->dir[1], -lt->dir[2]);   /* dir points toward the light */
  cross_axes(fc->d, fc->a, fc->b);
  double lo[3] = {DBL_MAX, DBL_MAX, DBL_MAX}, hi[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX};
  const float *ax[3] = {fc->a, fc->b, fc->d};
  for (int i = 0; i < f->nobjects; i++) {
    const RenderObject *o = &f->objects[i];
    for (int v = 0; v < o->mesh->nverts; v++)
      for (int k = 0; k < 3; k++) {
        double x = dot3(o->wpos[v], ax[k]);
        if (!isfinite(x)) continue;
        lo[k] = fmin(lo[k], x);
        hi[k] = fmax(hi[k], x);
      }
  }
  if (!(lo[0] <= hi[0])) for (int k = 0; k < 3; k++) lo[k] = hi[k] = 0;   /* nothing drawn */
  double extent = fmax(fmax(hi[0] - lo[0], hi[1] - lo[1]), 1e-6);
  int margin = margin_texels(m);
  double texel = extent / (m->n - 2 * margin);
  m->texel = (float)texel;
  double ca = 0.5 * (lo[0] + hi[0]) - texel * m->n / 2, cb = 0.5 * (lo[1] + hi[1]) - texel * m->n / 2;
  for (int k = 0; k < 3; k++)   /* the corner: s = 0, t = 0, depth 0 at the nearest vertex */
    fc->org[k] = (float)(ca * fc->a[k] + cb * fc->b[k] + lo[2] * fc->d[k]);
  for (int k = 0; k < 3; k++) {   /* s = (p - org) . a / texel, t likewise, w = -(p - org) . d */
    fc->rs[k] = (float)(fc->a[k] / texel); fc->rt[k] = (float)(fc->b[k] / texel); fc->rw[k] = -fc->d[k];
  }
  fc->rs[3] = (float)(-ca / texel - 0.0);
  fc->rt[3] = (float)(-cb / texel);
  fc->rw[3] = (float)lo[2];
}

/* A perspective map around axis d from the light at pos, over the tan
** range [-e, e] across it widened by the margin. */
static void frame_persp(ShadowMap *m, ShadowFace *fc, const float pos[3], Vec3 d, double e) {
  set3f(fc->d, d.x, d.y, d.z);
  cross_axes(fc->d, fc->a, fc->b);
  memcpy(fc->org, pos, sizeof fc->org);
  int margin = margin_texels(m);
  m->texel = (float)(2 * e / (m->n - 2 * margin));
  m->centre = 0.5f * (float)m->n;
}

/* The depth under which nothing is drawn into a perspective map: a
** millionth of the scene's reach from the light (at least 1e-6). */
static float near_depth(const RenderFrame *f, const float pos[3]) {
  double r = 0;
  for (int i = 0; i < f->nobjects; i++) {
    const RenderObject *o = &f->objects[i];
    for (int v = 0; v < o->mesh->nverts; v++) {
      const float *p = o->wpos[v];
      double dx = p[0] - pos[0], dy = p[1] - pos[1], dz = p[2] - pos[2], d = dx * dx + dy * dy + dz * dz;
      if (isfinite(d) && d > r) r = d;
    }
  }
  return (float)fmax(sqrt(r) * 1e-6, 1e-6);
}

static void frame_cube(ShadowMap *m, const RenderLight *lt) {
  static const double axes[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  m->persp = 1;
  m->nfaces = 6;
  for (int k = 0; k < 6; k++)
    frame_persp(m, &m->face[k], lt->pos, v3(axes[k][0], axes[k][1], axes[k][2]), 1.0);
}

/* ---- drawing ------------------------------------------------------------- */

/* The least and the greatest of three (NaN: whichever the comparisons give). */
static inline float min3f(float a, float b, float c) { float m = a < b ? a : b; return m < c ? m : c; }
static inline float max3f(float a, float b, float c) { float m = a > b ? a : b; return m > c ? m : c; }

/* A vertex in a face's frame: across (x, y) and along (z) from its
** origin, and in the map: column s, row t and w (shadow.h). */
typedef struct MapVert { float x, y, z, s, t, w; } MapVert;

static MapVert map_vert(const ShadowMap *m, const ShadowFace *fc, float x, float y, float z) {
  MapVert v = {x, y, z, 0, 0, 0};
  if (!m->persp) {
    v.s = x / m->texel; v.t = y / m->texel; v.w = -z;
  } else if (z > m->znear) {
    float iz = 1 / z;
    v.s = m->centre + x * iz / m->texel; v.t = m->centre + y * iz / m->texel; v.w = iz;
  }
  (void)fc;
  return v;
}

/* One face of one light being drawn: its vertices, per object, in its frame. */
typedef struct FaceJob {
  ShadowMap *m;
  ShadowFace *fc;
  MapVert **verts;             /* per object */
} FaceJob;

typedef struct ShadowJob {
  const RenderFrame *f;
  int nfaces;
  FaceJob *faces;
  int bands;                   /* per face: ceil(n / SHADOW_BAND) (the largest map's) */
} ShadowJob;

static void project_face(void *ctx, int k) {
  ShadowJob *job = ctx;
  FaceJob *fj = &job->faces[k];
  const ShadowFace *fc = fj->fc;
  for (int i = 0; i < job->f->nobjects; i++) {
    const RenderObject *o = &job->f->objects[i];
    MapVert *mv = fj->verts[i];
    for (int v = 0; v < o->mesh->nverts; v++) {
      const float *p = o->wpos[v];
      if (!fj->m->persp) {   /* as the reading places a point (ortho_at) */
        float s = fc->rs[0] * p[0] + fc->rs[1] * p[1] + fc->rs[2] * p[2] + fc->rs[3];
        float t = fc->rt[0] * p[0] + fc->rt[1] * p[1] + fc->rt[2] * p[2] + fc->rt[3];
        float w = fc->rw[0] * p[0] + fc->rw[1] * p[1] + fc->rw[2] * p[2] + fc->rw[3];
        mv[v] = (MapVert){0, 0, -w, s, t, w};
        continue;
      }
      float q[3] = {p[0] - fc->org[0], p[1] - fc->org[1], p[2] - fc->org[2]};
      mv[v] = map_vert(fj->m, fc, dot3(q, fc->a), dot3(q, fc->b), dot3(q, fc->d));
    }
  }
}

/* A triangle as the drawing sees it, as functions of a texel centre's
** column and row (s, t): its three edges, inside where e[k] + es[k] s +
** et[k] t >= 0 (each already less its tolerance), and its w there, w0 +
** ws s + wt t; the texels whose centres may be inside, [i0, i1] x [j0, j1]. */
typedef struct MapTri {
  double e[3], es[3], et[3];
  double w0, ws, wt;
  int i0, i1, j0, j1;
} MapTri;

/* Where edge k of tr crosses row t: es s = -(e + et t), as a + b t; the
** edge bounds the columns from below where es > 0, from above where < 0. */
typedef struct EdgeSpan { double a[3], b[3]; int side[3]; } EdgeSpan;

/* Fill the texels of rows j0..j1 whose centres lie inside tr: row by row,
** the run of columns all three edges let in, each texel keeping the
** larger of its w and the triangle's. A texel's value depends on the
** triangle and its row alone, never on the rows drawn together. */
static void fill_rows(const MapTri *tr, float *w, int n) {
  EdgeSpan sp;
  for (int k = 0; k < 3; k++) {
    double b = tr->es[k];
    sp.side[k] = b > 0 ? 1 : b < 0 ? -1 : 0;
    sp.a[k] = b != 0 ? -tr->e[k] / b : tr->e[k];   /* es = 0: the edge's sign alone */
    sp.b[k] = b != 0 ? -tr->et[k] / b : tr->et[k];
  }
  for (int j = tr->j0; j <= tr->j1; j++) {
    double t = j + 0.5, lo = tr->i0 + 0.5, hi = tr->i1 + 0.5;
    for (int k = 0; k < 3; k++) {
      double x = sp.a[k] + sp.b[k] * t;
      if (sp.side[k] > 0) lo = x > lo ? x : lo;
      else if (sp.side[k] < 0) hi = x < hi ? x : hi;
      else if (!(x >= 0)) hi = -1;   /* the row lies outside this edge */
    }
    if (!(lo <= hi)) continue;
    /* the centres i + 0.5 in [lo, hi], which lies in [0.5, n - 0.5]:
    ** ceil and floor of non-negative numbers by truncation */
    double a = lo - 0.5, b = hi - 0.5;
    int i0 = (int)a, i1 = (int)b;
    i0 += i0 < a;
    float wr = (float)(tr->w0 + tr->wt * t + tr->ws * 0.5), ws = (float)tr->ws;
    float *row = w + (size_t)j * n;
    for (int i = i0; i <= i1; i++) {   /* side by side: the plane in float across the run */
      float z = wr + ws * (float)i;
      row[i] = z > row[i] ? z : row[i];
    }
  }
}

/* The texels of [lo_s, hi_s] x [lo_t, hi_t] in rows y0..y1-1, a hair
** wider, into tr; 0 when none. */
static int tri_box(MapTri *tr, int n, float lo_s, float hi_s, float lo_t, float hi_t, int y0, int y1) {
  float i0f = ceilf(lo_s - 0.5f - 1e-3f), i1f = floorf(hi_s - 0.5f + 1e-3f);
  float j0f = ceilf(lo_t - 0.5f - 1e-3f), j1f = floorf(hi_t - 0.5f + 1e-3f);
  if (!(i1f >= 0 && j1f >= y0 && i0f < n && j0f < y1 && i0f <= i1f && j0f <= j1f)) return 0;
  tr->i0 = i0f > 0 ? (int)i0f : 0; tr->i1 = i1f < n - 1 ? (int)i1f : n - 1;
  tr->j0 = j0f > y0 ? (int)j0f : y0; tr->j1 = j1f < y1 - 1 ? (int)j1f : y1 - 1;
  return 1;
}

/* Fill rows y0..y1-1 of orthographic map m with the triangle (a, b, c):
** each texel whose centre lies inside (within a thousandth of a texel of
** its edges) keeps the larger of its w and the triangle's plane there. */
static void fill_triangle(const ShadowMap *m, float *w, const MapVert *a, const MapVert *b,
                          const MapVert *c, int y0, int y1) {
  double e1s = b->s - a->s, e1t = b->t - a->t, e2s = c->s - a->s, e2t = c->t - a->t;
  double area = e1s * e2t - e2s * e1t;
  if (!(fabs(area) > 1e-12)) return;   /* edge-on to the light (or NaN) */
  MapTri tr;
  if (!tri_box(&tr, m->n, min3f(a->s, b->s, c->s), max3f(a->s, b->s, c->s),
               min3f(a->t, b->t, c->t), max3f(a->t, b->t, c->t), y0, y1)) return;
  double sg = area > 0 ? 1 : -1;   /* counter-clockwise: inside on each edge's left */
  const MapVert *v[3] = {a, b, c};
  for (int k = 0; k < 3; k++) {   /* es (t - p.t) - et (s - p.s) for the edge p -> q */
    const MapVert *p = v[k], *q = v[(k + 1) % 3];
    double es = sg * (q->s - p->s), et = sg * (q->t - p->t);
    tr.es[k] = -et; tr.et[k] = es;
    tr.e[k] = et * p->s - es * p->t + 1e-3 * sqrt(es * es + et * et);
  }
  tr.ws = ((b->w - a->w) * e2t - (c->w - a->w) * e1t) / area;
  tr.wt = (e1s * (c->w - a->w) - e2s * (b->w - a->w)) / area;
  tr.w0 = a->w - a->s * tr.ws - a->t * tr.wt;
  fill_rows(&tr, w, m->n);
}

/* Fill rows y0..y1-1 of perspective map m with the triangle whose corners
** are v[k] (x, y, z in the face's frame, from the light), by the rays
** through the texel centres: ray (x, y, 1) with x = (s - centre) texel
** and y likewise meets the triangle, in front of the light, where its
** three edge planes through the light all have it on the triangle's side
** (ray . (v[k+1] x v[k+2]) of the sign of det(v0, v1, v2)), and there
** w = 1/z = (N . ray) / det with N the triangle's normal (v1 - v0) x
** (v2 - v0). So corners behind the light need no clipping, and no large
** numbers enter w. Texels are tested over the corners' image when all lie
** beyond the near plane, else over the whole rows. */
static void fill_persp(const ShadowMap *m, float *w, const MapVert *const v[3], int y0, int y1) {
  Vec3 V[3];
  for (int k = 0; k < 3; k++) V[k] = v3(v[k]->x, v[k]->y, v[k]->z);
  Vec3 N = v3_cross(v3_sub(V[1], V[0]), v3_sub(V[2], V[0]));
  double det = v3_dot(N, V[0]);
  if (!(fabs(det) > 1e-30)) return;   /* its plane passes through the light (or NaN) */
  MapTri tr = {.i0 = 0, .i1 = m->n - 1, .j0 = y0, .j1 = y1 - 1};
  if (v[0]->z > m->znear && v[1]->z > m->znear && v[2]->z > m->znear &&
      !tri_box(&tr, m->n, min3f(v[0]->s, v[1]->s, v[2]->s), max3f(v[0]->s, v[1]->s, v[2]->s),
               min3f(v[0]->t, v[1]->t, v[2]->t), max3f(v[0]->t, v[1]->t, v[2]->t), y0, y1))
    return;
  double sg = det > 0 ? 1 : -1, tau = m->texel, c = m->centre;
  for (int k = 0; k < 3; k++) {   /* C . ray, ray = ((s - c) tau, (t - c) tau, 1) */
    Vec3 C = v3_mul(v3_cross(V[(k + 1) % 3], V[(k + 2) % 3]), sg);
    tr.es[k] = C.x * tau; tr.et[k] = C.y * tau;
    tr.e[k] = C.z - (C.x + C.y) * tau * c + 1e-3 * tau * v3_len(C);
  }
  tr.ws = N.x * tau / det; tr.wt = N.y * tau / det;
  tr.w0 = N.z / det - (N.x + N.y) * tau * c / det;
  fill_rows(&tr, w, m->n);
}

static void draw_band(void *ctx, int task) {
  ShadowJob *job = ctx;
  FaceJob *fj = &job->faces[task / job->bands];
  const ShadowMap *m = fj->m;
  int y0 = (task % job->bands) * SHADOW_BAND, y1 = y0 + SHADOW_BAND < m->n ? y0 + SHADOW_BAND : m->n;
  if (y0 >= m->n) return;
  float *w = fj->fc->w;
  float empty = m->persp ? 0.0f : -INFINITY;   /* nothing there: every receiver is lit */
  for (size_t k = (size_t)y0 * m->n; k < (size_t)y1 * m->n; k++) w[k] = empty;
  for (int i = 0; i < job->f->nobjects; i++) {
    const RenderObject *o = &job->f->objects[i];
    const MapVert *mv = fj->verts[i];
    for (int t = 0; t < o->mesh->ntris; t++) {
      const int *c = o->mesh->tri[t];
      const MapVert *tv[3] = {&mv[c[0]], &mv[c[1]], &mv[c[2]]};
      int beyond = !m->persp || (tv[0]->z > m->znear && tv[1]->z > m->znear && tv[2]->z > m->znear);
      if (beyond && (max3f(tv[0]->t, tv[1]->t, tv[2]->t) < (float)y0 - 1 ||
                     min3f(tv[0]->t, tv[1]->t, tv[2]->t) > (float)y1 + 1 ||
                     max3f(tv[0]->s, tv[1]->s, tv[2]->s) < -1 ||
                     min3f(tv[0]->s, tv[1]->s, tv[2]->s) > (float)m->n + 1)) continue;   /* off the band */
      if (m->persp) {
        if (tv[0]->z <= 0 && tv[1]->z <= 0 && tv[2]->z <= 0) continue;   /* behind the light */
        fill_persp(m, w, tv, y0, y1);
        continue;
      }
      fill_triangle(m, w, tv[0], tv[1], tv[2], y0, y1);
    }
  }
}

/* ---- entry points --------------------------------------------------------- */

/* o's unit triangle normals in world space (zero for a degenerate one). */
static void face_normals(RenderObject *o) {
  const Mesh *m = o->mesh;
  o->wfnrm = xmalloc((size_t)m->ntris * sizeof *o->wfnrm + 1);
  for (int t = 0; t < m->ntris; t++) {
    const float *a = o->wpos[m->tri[t][0]], *b = o->wpos[m->tri[t][1]], *c = o->wpos[m->tri[t][2]];
    Vec3 n = v3_cross(v3(b[0] - a[0], b[1] - a[1], b[2] - a[2]), v3(c[0] - a[0], c[1] - a[1], c[2] - a[2]));
    double l = v3_len(n);
    n = l > 0 ? v3_mul(n, 1 / l) : v3(0, 0, 0);
    set3f(o->wfnrm[t], n.x, n.y, n.z);
  }
}

/* Set up light i's map frames (no texels yet). */
static ShadowMap *shadow_map_frame(const RenderFrame *f, const SceneLight *sl, const RenderLight *lt) {
  ShadowMap *m = xcalloc(1, sizeof *m);
  m->n = sl->shadow_resolution;
  m->bias = (float)sl->shadow_bias;
  m->half = (float)(0.5 * sl->shadow_filter);
  m->nfaces = 1;
  if (lt->directional) {
    frame_sun(m, f, lt);
  } else if (lt->spot && sl->cone <= SHADOW_SPOT_MAX_CONE) {
    m->persp = 1;
    frame_persp(m, &m->face[0], lt->pos, v3(lt->axis[0], lt->axis[1], lt->axis[2]),
                tan(sl->cone * M_PI / 180));
  } else {
    frame_cube(m, lt);
  }
  if (m->persp) m->znear = near_depth(f, lt->pos);
  return m;
}

int shadow_prepare(const Scene *s, RenderFrame *f, int nthreads) {
  if (s->nlights == 0) return 1;   /* the default key light casts none */
  long long texels = 0;
  for (int i = 0; i < s->nlights; i++) {
    const SceneLight *sl = &s->lights[i];
    if (!sl->shadow) continue;
    int faces = sl->kind == LIGHT_DIRECTIONAL || (sl->kind == LIGHT_SPOT && sl->cone <= SHADOW_SPOT_MAX_CONE) ? 1 : 6;
    texels += (long long)faces * sl->shadow_resolution * sl->shadow_resolution;
    if (texels > SHADOW_MAX_TEXELS) {
      diag_error(sl->loc, "the shadow maps would hold %lld texels by this light, more than %lld "
                 "(SHADOW_MAX_TEXELS); lower `shadow_resolution`", texels, SHADOW_MAX_TEXELS);
      return 0;
    }
  }
  if (texels == 0) return 1;
  double t0 = stats_now();
  for (int i = 0; i < f->nobjects; i++) face_normals(&f->objects[i]);
  ShadowJob job = {f, 0, NULL, 1};
  job.faces = xcalloc(6 * (size_t)s->nlights, sizeof *job.faces);
  for (int i = 0; i < s->nlights; i++) {
    if (!s->lights[i].shadow) continue;
    ShadowMap *m = shadow_map_frame(f, &s->lights[i], &f->lights[i]);
    f->lights[i].shadow = m;
    int bands = (m->n + SHADOW_BAND - 1) / SHADOW_BAND;
    if (bands > job.bands) job.bands = bands;
    for (int k = 0; k < m->nfaces; k++) {
      FaceJob *fj = &job.faces[job.nfaces++];
      fj->m = m;
      fj->fc = &m->face[k];
      fj->fc->w = xcalloc((size_t)m->n * m->n + 4, sizeof *fj->fc->w);   /* + 4: a filter's row read */
      fj->verts = xcalloc((size_t)f->nobjects + 1, sizeof *fj->verts);
      for (int o = 0; o < f->nobjects; o++)
        fj->verts[o] = xmalloc((size_t)f->objects[o].mesh->nverts * sizeof **fj->verts + 1);
    }
  }
  tasks_run(job.nfaces, nthreads, project_face, &job);
  tasks_run(job.nfaces * job.bands, nthreads, draw_band, &job);
  for (int k = 0; k < job.nfaces; k++) {
    for (int o = 0; o < f->nobjects; o++) free(job.faces[k].verts[o]);
    free(job.faces[k].verts);
  }
  free(job.faces);
  stats_record("shadows", stats_now() - t0);
  stats_record_count("shadows", "texels", texels);
  return 1;
}

void shadow_free_all(RenderFrame *f) {
  for (int i = 0; i < f->nlights; i++) {
    ShadowMap *m = f->lights[i].shadow;
    if (!m) continue;
    for (int k = 0; k < m->nfaces; k++) free(m->face[k].w);
    free(m);
    f->lights[i].shadow = NULL;
  }
}

/* ---- reading -------------------------------------------------------------- */

static inline float clamp_slope(float k) {
  if (k > SHADOW_MAX_SLOPE) return SHADOW_MAX_SLOPE;
  if (k < -SHADOW_MAX_SLOPE) return -SHADOW_MAX_SLOPE;
  return k == k ? k : 0;   /* NaN (a normal across the rays and along a, b at once): flat */
}

/* The cube face whose axis is nearest the direction q from the light. */
static inline int cube_face(const float q[3]) {
  float x = fabsf(q[0]), y = fabsf(q[1]), z = fabsf(q[2]);
  if (x >= y && x >= z) return q[0] >= 0 ? 0 : 1;
  if (y >= z) return q[1] >= 0 ? 2 : 3;
  return q[2] >= 0 ? 4 : 5;
}

/* floor(x) for |x| < 2^30 (the callers bound it), without a library call. */
static inline int ifloor(float x) {
  int k = (int)x;
  return k - (x < (float)k);
}

/* The filter's weights over texels i0..i0+count-1 of one axis for the box
** [lo, lo + 2 half]: the first and last texels by how much of them it
** covers, the ones between wholly. */
static inline int box_weights(float lo, float half, int *i0, float *wt, int cap) {
  float hi = lo + 2 * half;
  int a = ifloor(lo), b = ifloor(hi), count = b - a + 1;
  if (count > cap) count = cap;   /* shadow_filter <= 32: never */
  for (int k = 1; k < count - 1; k++) wt[k] = 1;
  wt[0] = (float)(a + 1) - lo;
  wt[count - 1] = count > 1 ? hi - (float)b : hi - lo;
  *i0 = a;
  return count;
}

/* Four lanes side by side (GCC's vector extension): a row of the default
** filter's texels at once. */
typedef float V4F __attribute__((vector_size(16)));
typedef int32_t V4I __attribute__((vector_size(16)));

/* Most texels the filter reads along an axis: shadow_filter 32 spans 33. */
#define SHADOW_MAX_TAPS 34

/* The receiver's plane across face fc of map m (shadow.h): its slopes
** ks, kt in texel depths a texel, from its unit normal n, for the ray
** direction r (orthographic: the face's d; perspective: q / z). */
static inline void plane_slopes(const ShadowFace *fc, const float n[3], const float r[3], float *ks, float *kt) {
  float inr = 1 / dot3(n, r);
  *ks = clamp_slope(dot3(n, fc->a) * inr);
  *kt = clamp_slope(dot3(n, fc->b) * inr);
}

/* The default filter (2 texels) at texel position (s0 + 1, t0 + 1) of
** face fc, inside the map: the 3 x 3 texels under the box, four a row
** side by side (the fourth weighs 0), the middle ones wholly under it;
** thr is the receiver's threshold at the first texel's centre and us, ut
** its steps a texel. */
static inline float filter_3x3(const ShadowMap *m, const ShadowFace *fc, float s0, float t0, int i0, int j0,
                               float thr, float us, float ut) {
  static const V4F lanes = {0, 1, 2, 3};
  float fx = (float)(i0 + 1) - s0, fy = (float)(j0 + 1) - t0;   /* the first's share */
  const float *row = fc->w + (size_t)j0 * m->n + i0;
  V4F wx = {fx, 1, 1 - fx, 0}, thr0 = lanes * us + thr, r0, r1, r2;
  memcpy(&r0, row, sizeof r0);
  memcpy(&r1, row + m->n, sizeof r1);
  memcpy(&r2, row + 2 * m->n, sizeof r2);
  V4I in0 = r0 <= thr0, in1 = r1 <= thr0 + ut, in2 = r2 <= thr0 + 2 * ut;   /* all bits where lit */
  V4F lit = (V4F)(in0 & (V4I)wx) * fy + (V4F)(in1 & (V4I)wx) + (V4F)(in2 & (V4I)wx) * (1 - fy);
  float v = (lit[0] + lit[1]) + (lit[2] + lit[3]);
  return v < 4 ? v * 0.25f : 1;   /* over the box's area, 4 */
}

/* The filtered comparison at texel position (s, t) of face fc for a
** receiver at w whose plane has slopes (ks, kt) and whose texel depth is
** unit: the box's share over texels the receiver is not behind. */
static inline float filter_at(const ShadowMap *m, const ShadowFace *fc, float s, float t, float w, float unit,
                              float ks, float kt) {
  /* w at texel centre (i + 0.5, j + 0.5) is w + unit (ks (i + 0.5 - s) +
  ** kt (j + 0.5 - t)); lit where the map's w is no nearer than that plus
  ** the bias */
  float base = w + unit * (m->bias + ks * (0.5f - s) + kt * (0.5f - t));
  float us = unit * ks, ut = unit * kt;
  float s0 = s - m->half, t0 = t - m->half;
  if (!(s0 > -1e6f && s0 < 1e6f && t0 > -1e6f && t0 < 1e6f)) return 1;   /* NaN or far off */
  int n = m->n, i0 = ifloor(s0), j0 = ifloor(t0);
  if (m->half == 1 && i0 >= 0 && j0 >= 0 && i0 + 3 <= n && j0 + 3 <= n)
    return filter_3x3(m, fc, s0, t0, i0, j0, base + us * (float)i0 + ut * (float)j0, us, ut);
  float wx[SHADOW_MAX_TAPS], wy[SHADOW_MAX_TAPS];
  int nx = box_weights(s0, m->half, &i0, wx, SHADOW_MAX_TAPS), ny = box_weights(t0, m->half, &j0, wy, SHADOW_MAX_TAPS);
  float lit = 0;
  for (int j = 0; j < ny; j++) {
    int jj = j0 + j, out_t = jj < 0 || jj >= n;
    const float *row = fc->w + (size_t)(jj < 0 ? 0 : jj >= n ? n - 1 : jj) * n;
    float sum = 0, thr = base + ut * (float)jj;
    for (int i = 0; i < nx; i++) {
      int ii = i0 + i, out = out_t || ii < 0 || ii >= n;
      /* off an orthographic map nothing was drawn: lit; a perspective
      ** face reads its border (its margin covers the filter) */
      int is_lit = (out && !m->persp) || row[ii < 0 ? 0 : ii >= n ? n - 1 : ii] <= thr + us * (float)ii;
      sum += is_lit ? wx[i] : 0;
    }
    lit += sum * wy[j];
  }
  float v = lit / (4 * m->half * m->half);
  return v < 1 ? v : 1;
}

/* An orthographic map's receiver slopes for unit normal nrm, times the
** texel (depth a texel step): its plane's steps. */
static inline void ortho_steps(const ShadowMap *m, const float nrm[3], float *us, float *ut) {
  float ks, kt;
  plane_slopes(&m->face[0], nrm, m->face[0].d, &ks, &kt);
  *us = m->texel * ks;
  *ut = m->texel * kt;
}

/* An orthographic map's filter at its position (s, t) for a receiver at
** w whose plane steps a texel are us, ut. */
static inline __attribute__((always_inline)) float ortho_filter(const ShadowMap *m, float s, float t, float w,
                                                                float us, float ut) {
  const ShadowFace *fc = &m->face[0];
  float s0 = s - 1, t0 = t - 1;
  int n = m->n;
  if (m->half == 1 && s0 >= 0 && t0 >= 0 && s0 < (float)(n - 3) && t0 < (float)(n - 3)) {   /* NaN fails */
    int i0 = (int)s0, j0 = (int)t0;   /* s0, t0 >= 0: truncation floors */
    float bias = m->bias * m->texel;
    float thr = w + bias + us * ((float)i0 + 0.5f - s) + ut * ((float)j0 + 0.5f - t);
    return filter_3x3(m, fc, s0, t0, i0, j0, thr, us, ut);
  }
  float it = 1 / m->texel;
  return filter_at(m, fc, s, t, w, m->texel, us * it, ut * it);
}

/* An orthographic map's reading at p whose plane steps a texel are us, ut. */
static inline float ortho_at(const ShadowMap *m, const float p[3], float us, float ut) {
  const ShadowFace *fc = &m->face[0];
  float s = fc->rs[0] * p[0] + fc->rs[1] * p[1] + fc->rs[2] * p[2] + fc->rs[3];
  float t = fc->rt[0] * p[0] + fc->rt[1] * p[1] + fc->rt[2] * p[2] + fc->rt[3];
  float w = fc->rw[0] * p[0] + fc->rw[1] * p[1] + fc->rw[2] * p[2] + fc->rw[3];
  return ortho_filter(m, s, t, w, us, ut);
}

/* A perspective map's reading at p with unit normal nrm. */
static inline float persp_at(const ShadowMap *m, const float p[3], const float nrm[3]) {
  float q[3] = {p[0] - m->face[0].org[0], p[1] - m->face[0].org[1], p[2] - m->face[0].org[2]};
  const ShadowFace *fc = &m->face[m->nfaces == 6 ? cube_face(q) : 0];   /* all faces share org */
  float x = dot3(q, fc->a), y = dot3(q, fc->b), z = dot3(q, fc->d);
  if (!(z > m->znear)) return 1;   /* at the light, or behind a spot's map: nothing between */
  float iz = 1 / z, k = iz / m->texel, r[3] = {q[0] * iz, q[1] * iz, q[2] * iz}, ks, kt;
  plane_slopes(fc, nrm, r, &ks, &kt);
  return filter_at(m, fc, m->centre + x * k, m->centre + y * k, iz, m->texel * iz, ks, kt);
}

float shadow_visibility(const ShadowMap *m, const float p[3], const float nrm[3]) {
  if (m->persp) return persp_at(m, p, nrm);
  float us, ut;
  ortho_steps(m, nrm, &us, &ut);
  return ortho_at(m, p, us, ut);
}

/* Samples the orthographic reading places at once (ortho_run). */
#define SHADOW_CHUNK 64

/* shadow_run on an orthographic map, n <= SHADOW_CHUNK samples: with
** the default filter, in passes over the chunk (the map positions, the
** planes' steps, the first texels and thresholds side by side, then each
** sample's 3 x 3 texels), with ortho_at's arithmetic sample by sample. */
static void ortho_run(const ShadowMap *m, const RenderObject *o, int n, const int32_t *face, const float *px,
                      const float *py, const float *pz, const float *nl, float *vis) {
  const ShadowFace *fc = &m->face[0];
  float S[SHADOW_CHUNK], T[SHADOW_CHUNK], W[SHADOW_CHUNK], US[SHADOW_CHUNK], UT[SHADOW_CHUNK];
  float THR[SHADOW_CHUNK];
  int32_t I0[SHADOW_CHUNK], J0[SHADOW_CHUNK], IN[SHADOW_CHUNK];
  for (int j = 0; j < n; j++) {
    S[j] = fc->rs[0] * px[j] + fc->rs[1] * py[j] + fc->rs[2] * pz[j] + fc->rs[3];
    T[j] = fc->rt[0] * px[j] + fc->rt[1] * py[j] + fc->rt[2] * pz[j] + fc->rt[3];
    W[j] = fc->rw[0] * px[j] + fc->rw[1] * py[j] + fc->rw[2] * pz[j] + fc->rw[3];
  }
  int last = -1;
  float us = 0, ut = 0;   /* the steps of the last triangle's plane */
  for (int j = 0; j < n; j++) {
    if (face[j] != last && (!nl || nl[j] > 0)) ortho_steps(m, o->wfnrm[last = face[j]], &us, &ut);
    US[j] = us; UT[j] = ut;
  }
  if (m->half != 1) {
    for (int j = 0; j < n; j++) vis[j] = nl && !(nl[j] > 0) ? 0 : ortho_filter(m, S[j], T[j], W[j], US[j], UT[j]);
    return;
  }
  float lim = (float)(m->n - 3), bias = m->bias * m->texel;
  for (int j = 0; j < n; j++) {   /* ortho_filter's first texel and threshold, side by side */
    float s0 = S[j] - 1, t0 = T[j] - 1;
    IN[j] = s0 >= 0 && t0 >= 0 && s0 < lim && t0 < lim;   /* NaN fails */
    int i0 = IN[j] ? (int)s0 : 0, j0 = IN[j] ? (int)t0 : 0;
    I0[j] = i0; J0[j] = j0;
    THR[j] = W[j] + bias + US[j] * ((float)i0 + 0.5f - S[j]) + UT[j] * ((float)j0 + 0.5f - T[j]);
  }
  for (int j = 0; j < n; j++) {
    if (nl && !(nl[j] > 0)) vis[j] = 0;
    else if (IN[j]) vis[j] = filter_3x3(m, fc, S[j] - 1, T[j] - 1, I0[j], J0[j], THR[j], US[j], UT[j]);
    else vis[j] = ortho_filter(m, S[j], T[j], W[j], US[j], UT[j]);
  }
}

void shadow_run(const ShadowMap *m, const RenderObject *o, int n, const int32_t *face, const float *px,
                const float *py, const float *pz, const float *nl, float *vis) {
  if (!m->persp) {
    for (int k = 0; k < n; k += SHADOW_CHUNK)
      ortho_run(m, o, n - k < SHADOW_CHUNK ? n - k : SHADOW_CHUNK, face + k, px + k, py + k, pz + k,
                nl ? nl + k : NULL, vis + k);
    return;
  }
  for (int j = 0; j < n; j++) {
    if (nl && !(nl[j] > 0)) { vis[j] = 0; continue; }
    float p[3] = {px[j], py[j], pz[j]};
    vis[j] = persp_at(m, p, o->wfnrm[face[j]]);
  }
}
