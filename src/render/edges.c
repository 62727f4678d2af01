/*
** Important edge detection (001 §2.1.1, Algorithm 1) and the per-object
** data the reference image, tracing and linking read: projected vertices
** and the vertex -> edge graph.
*/
#include "edges.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"

/* ---- classification ---------------------------------------------------- */

/* What classifying one object's edges needs besides the edge: its
** triangles' source faces, world positions and unit face normals (and
** which normals are zero, when known), the kinds wanted, the crease test
** as n0 . n1 <= crease_cos, and the view vector: forward (ortho) or from
** eye to the edge's v[0]. */
typedef struct EdgeTest {
  const int *tri_face;
  const Vec3 *world, *fn;
  const unsigned char *zero;   /* per triangle: fn . fn == 0 (a degenerate face), or NULL */
  unsigned want;
  double crease_cos;
  int ortho;
  Vec3 forward, eye;
} EdgeTest;

/* The crease test's bound on n0 . n1 for crease(angle): faces meeting at
** less than LINE_COPLANAR_DEG are coplanar, so crease(0) marks every edge
** whose faces are not (a flat polygon's diagonals never, however rounding
** tilts their normals), the same on every edge. */
static double crease_cos(double angle) {
  return cos((angle > LINE_COPLANAR_DEG ? angle : LINE_COPLANAR_DEG) * M_PI / 180.0);
}

/* Kinds of edge me (inlined in each loop over the edges). */
static inline __attribute__((always_inline)) unsigned edge_kind_at(const MeshEdge *me,
                                                                   const EdgeTest *et) {
  const int *tri_face = et->tri_face;
  const Vec3 *fn = et->fn;
  unsigned want = et->want;
  unsigned kind = 0;
  int f0 = me->f[0], f1 = me->f[1];
  if (f0 < 0 || f1 < 0) {                          /* fewer than two faces */
    if (want & EDGE_BOUNDARY) kind |= EDGE_BOUNDARY;
    if (want & EDGE_FACE) kind |= EDGE_FACE;       /* a mesh border is a polygon edge too */
    return kind;
  }
  if ((want & EDGE_FACE) && (!tri_face || tri_face[f0] != tri_face[f1]))
    kind |= EDGE_FACE;
  Vec3 n0 = fn[f0], n1 = fn[f1];
  int degenerate = et->zero ? et->zero[f0] | et->zero[f1] : v3_dot(n0, n0) == 0 || v3_dot(n1, n1) == 0;
  if (want & EDGE_CREASE) {
    if (me->sharpness > 0) kind |= EDGE_CREASE;   /* tagged by subdivision */
    /* angle(n0, n1) >= threshold  <=>  n0 . n1 <= cos(threshold) */
    else if (!degenerate && v3_dot(n0, n1) <= et->crease_cos)
      kind |= EDGE_CREASE;
  }
  if ((want & EDGE_SILHOUETTE) && !degenerate) {
    /* view vector from the camera to an end point; the product of the two
    ** dot products is <= 0 when one face looks at the viewer and the other
    ** away (or either is edge-on) */
    Vec3 v = et->ortho ? et->forward : v3_sub(et->world[me->v[0]], et->eye);
    if (v3_dot(v, n0) * v3_dot(v, n1) <= 0) kind |= EDGE_SILHOUETTE;
  }
  return kind;
}

unsigned line_edge_kind(const Mesh *m, int e, const Vec3 *world, const Vec3 *fn,
                        const SceneLines *ls, const Camera *cam) {
  EdgeTest et = {m->tri_face, world, fn, NULL, ls->kinds, crease_cos(ls->crease_angle),
                 cam->kind == CAMERA_ORTHO, cam->forward, cam->eye};
  return edge_kind_at(&m->edges[e], &et);
}

/* ---- per object --------------------------------------------------------- */

/* The vertex -> edge graph of m's important edges (oe->id[e] != 0) as
** offsets (nverts + 1) and edge lists, each vertex's edges in edge order.
** Linking only ever walks important edges, so the rest are left out. */
static void build_adjacency(LineObjEdges *oe, const Mesh *m, const int *imp, int nimp) {
  oe->adj_start = xcalloc((size_t)m->nverts + 1, sizeof *oe->adj_start);
  oe->adj = xmalloc(((size_t)nimp * 2 + 1) * sizeof *oe->adj);
  for (int i = 0; i < nimp; i++) {
    oe->adj_start[m->edges[imp[i]].v[0] + 1]++;
    oe->adj_start[m->edges[imp[i]].v[1] + 1]++;
  }
  for (int v = 0; v < m->nverts; v++) oe->adj_start[v + 1] += oe->adj_start[v];
  for (int i = 0; i < nimp; i++) {   /* adj_start[v] counts up as v's edges go in */
    oe->adj[oe->adj_start[m->edges[imp[i]].v[0]]++] = imp[i];
    oe->adj[oe->adj_start[m->edges[imp[i]].v[1]]++] = imp[i];
  }
  for (int v = m->nverts; v > 0; v--) oe->adj_start[v] = oe->adj_start[v - 1];   /* back to starts */
  oe->adj_start[0] = 0;
}

/* World positions, clip coordinates and reference pixels of m's vertices. */
static void project_vertices(LineObjEdges *oe, Vec3 *world, const Mesh *m, Mat4 to_world,
                             const Camera *cam) {
  oe->vert = xmalloc(((size_t)m->nverts + 1) * sizeof *oe->vert);   /* every entry written below */
  const double(*M)[4] = cam->world_to_clip.m;
  for (int v = 0; v < m->nverts; v++) {
    LineVert *lv = &oe->vert[v];
    Vec3 p = m4_point(to_world, m->pos[v]);
    world[v] = p;
    for (int r = 0; r < 4; r++)   /* clip = world_to_clip * (p, 1) */
      lv->clip[r] = M[r][0] * p.x + M[r][1] * p.y + M[r][2] * p.z + M[r][3];
    double w = lv->clip[3];
    lv->x = lv->y = lv->n = 0;   /* behind the eye */
    lv->in = 0;
    if (w > 0) {
      line_clip_to_screen(lv->clip, cam->width, cam->height, &lv->x, &lv->y, &lv->n);
      lv->in = lv->clip[2] + w >= 0 && isfinite(lv->x) && isfinite(lv->y) && isfinite(lv->n);
    }
  }
}

/* Is every vertex outside one and the same clip plane (nothing of the
** object can show)? */
static int outside_view(const LineObjEdges *oe, int nverts) {
  unsigned all = 63;
  for (int v = 0; v < nverts && all; v++) {
    const double *c = oe->vert[v].clip;
    unsigned code = (unsigned)(c[0] < -c[3]) | (unsigned)(c[0] > c[3]) << 1 |
                    (unsigned)(c[1] < -c[3]) << 2 | (unsigned)(c[1] > c[3]) << 3 |
                    (unsigned)(c[2] < -c[3]) << 4 | (unsigned)(c[2] > c[3]) << 5;
    all &= code;
  }
  return nverts > 0 && all != 0;
}

/* How many edges ahead the classification loop prefetches what it
** gathers. */
#define EDGE_AHEAD 32

/* Unit world normals of m's triangles (zero for a degenerate one), which
** of them are zero (so classifying an edge need not test both of its
** faces' normals again), and which of them the viewer sees the front of
** (v . n < 0), in one pass. */
static void face_normals(Vec3 *fn, unsigned char *zero, unsigned char *front, const Mesh *m,
                         const Vec3 *world, const Camera *cam) {
  int ortho = cam->kind == CAMERA_ORTHO;
  Vec3 fwd = cam->forward, eye = cam->eye;
  for (int t = 0; t < m->ntris; t++) {
    const int *c = m->tri[t];
    Vec3 p0 = world[c[0]];
    Vec3 n = v3_norm(v3_cross(v3_sub(world[c[1]], p0), v3_sub(world[c[2]], p0)));
    fn[t] = n;
    zero[t] = v3_dot(n, n) == 0;
    Vec3 v = ortho ? fwd : v3_sub(p0, eye);
    front[t] = v3_dot(v, n) < 0;
  }
}

/* Which of m's triangles the viewer sees the front of, from their unit
** normals fn: face_normals' front alone. */
static void face_fronts(unsigned char *front, const Mesh *m, const Vec3 *world, const Vec3 *fn,
                        const Camera *cam) {
  int ortho = cam->kind == CAMERA_ORTHO;
  Vec3 fwd = cam->forward, eye = cam->eye;
  for (int t = 0; t < m->ntris; t++) {
    Vec3 v = ortho ? fwd : v3_sub(world[m->tri[t][0]], eye);
    front[t] = v3_dot(v, fn[t]) < 0;
  }
}

/* ---- what the mesh decides, kept with it --------------------------------- */

/* The half of classifying an object's edges that does not depend on the
** view, kept with its mesh (mesh_derived) for the next frames: its unit
** world face normals and their zero flags, and per edge its kinds
** but silhouette, with EDGE_TRY_SILHOUETTE where the silhouette test
** applies (two faces, neither degenerate). Made for one transform, set of
** kinds and crease angle (compared exactly). */
typedef struct EdgeCache {
  Mat4 to_world;
  unsigned want;
  double crease_cos;
  Vec3 *fn;
  unsigned char *zero, *kind;
  int ready;               /* fn, zero and kind are filled (the first frame may stop short) */
} EdgeCache;

#define EDGE_TRY_SILHOUETTE 0x80u

static const char edge_cache_tag;

static void edge_cache_free(void *p) {
  EdgeCache *c = p;
  free(c->fn);
  free(c->zero);
  free(c->kind);
  free(c);
}

/* The view-independent kinds of m's edges into c->kind (c->fn, c->zero set). */
static void static_kinds(EdgeCache *c, const Mesh *m, const Vec3 *world) {
  EdgeTest et = {m->tri_face, world, c->fn, c->zero, c->want & ~(unsigned)EDGE_SILHOUETTE,
                 c->crease_cos, 0, v3(0, 0, 0), v3(0, 0, 0)};
  for (int e = 0; e < m->nedges; e++) {
    const MeshEdge *me = &m->edges[e];
    unsigned kind = edge_kind_at(me, &et);
    if (me->f[0] >= 0 && me->f[1] >= 0 && !(c->zero[me->f[0]] | c->zero[me->f[1]]))
      kind |= EDGE_TRY_SILHOUETTE;
    c->kind[e] = (unsigned char)kind;
  }
}

/* The cache kept with m (which keeps_derived) for this transform, kinds
** and crease angle, or a new one (not ready) kept with m in place of any
** other. The mesh is the caller's to keep or free: the cache is an
** addition to it, not a change. */
static EdgeCache *edge_cache(const Mesh *m, Mat4 to_world, const SceneLines *ls) {
  double ccos = crease_cos(ls->crease_angle);
  EdgeCache *c = mesh_derived(m, &edge_cache_tag);
  if (c && !memcmp(&c->to_world, &to_world, sizeof to_world) && c->want == ls->kinds &&
      c->crease_cos == ccos)
    return c;
  c = xmalloc(sizeof *c);
  *c = (EdgeCache){to_world, ls->kinds, ccos, xmalloc(((size_t)m->ntris + 1) * sizeof *c->fn),
                   xmalloc((size_t)m->ntris + 1), xmalloc((size_t)m->nedges + 1), 0};
  mesh_derived_set((Mesh *)m, &edge_cache_tag, c, edge_cache_free);
  return c;
}

/* The silhouette test of edge me (edge_kind_at's): one face looks at the
** viewer and the other away (or either is edge-on). */
static inline int silhouette_at(const MeshEdge *me, const Vec3 *world, const Vec3 *fn, int ortho,
                                Vec3 forward, Vec3 eye) {
  Vec3 v = ortho ? forward : v3_sub(world[me->v[0]], eye);
  return v3_dot(v, fn[me->f[0]]) * v3_dot(v, fn[me->f[1]]) <= 0;
}

/* Append id entries for obj's important edges (kinds computed by the caller). */
static void add_edge(LineEdges *out, int *cap, int obj, int e, unsigned kind) {
  if (out->n == *cap) {
    int ncap = *cap ? *cap * 2 : 1024;
    out->obj_of = xrealloc(out->obj_of, (size_t)ncap * sizeof *out->obj_of);
    out->edge_of = xrealloc(out->edge_of, (size_t)ncap * sizeof *out->edge_of);
    out->kind = xrealloc(out->kind, (size_t)ncap);
    *cap = ncap;
  }
  out->obj_of[out->n] = obj;
  out->edge_of[out->n] = e;
  out->kind[out->n] = (unsigned char)kind;
  out->n++;
}

/* Classify m's edges (object obj) in one pass, appending the important
** ones. */
static inline __attribute__((always_inline)) void classify(LineEdges *out, int *cap, int obj,
                                                            LineObjEdges *oe, const Mesh *m,
                                                            const EdgeTest *test) {
  const EdgeTest et = *test;   /* a local copy: the appends below cannot change it */
  const MeshEdge *me = m->edges;
  for (int e = 0; e < m->nedges; e++) {
#ifdef __GNUC__
    if (e + EDGE_AHEAD < m->nedges) {   /* the gathers of a later edge, ahead of time */
      const MeshEdge *ahead = &me[e + EDGE_AHEAD];
      if (ahead->f[0] >= 0) __builtin_prefetch(&et.fn[ahead->f[0]]);
      if (ahead->f[1] >= 0) __builtin_prefetch(&et.fn[ahead->f[1]]);
      __builtin_prefetch(&et.world[ahead->v[0]]);
    }
#endif
    unsigned kind = edge_kind_at(&me[e], &et);
    if (!kind) continue;
    add_edge(out, cap, obj, e, kind);
    oe->id[e] = out->n;
  }
}

/* The same from c's kinds: only the silhouette test is made again. */
static void classify_kept(LineEdges *out, int *cap, int obj, LineObjEdges *oe, const Mesh *m,
                          const EdgeCache *c, const Vec3 *world, const Camera *cam) {
  int ortho = cam->kind == CAMERA_ORTHO, sil = (c->want & EDGE_SILHOUETTE) != 0;
  const MeshEdge *me = m->edges;
  const unsigned char *ck = c->kind;
  const Vec3 *fn = c->fn;
  for (int e = 0; e < m->nedges; e++) {
    unsigned kind = ck[e] & ~EDGE_TRY_SILHOUETTE;
    if (sil && (ck[e] & EDGE_TRY_SILHOUETTE)) {
#ifdef __GNUC__
      if (e + EDGE_AHEAD < m->nedges) {   /* the gathers of a later edge, ahead of time */
        const MeshEdge *ahead = &me[e + EDGE_AHEAD];
        __builtin_prefetch(&fn[ahead->f[0] > 0 ? ahead->f[0] : 0]);
        __builtin_prefetch(&fn[ahead->f[1] > 0 ? ahead->f[1] : 0]);
      }
#endif
      if (silhouette_at(&me[e], world, fn, ortho, cam->forward, cam->eye)) kind |= EDGE_SILHOUETTE;
    }
    if (!kind) continue;
    add_edge(out, cap, obj, e, kind);
    oe->id[e] = out->n;
  }
}

void line_edges_build(LineEdges *out, const LineObject *objs, int nobj, const Camera *cam) {
  memset(out, 0, sizeof *out);
  out->nobj = nobj;
  out->obj = xcalloc((size_t)(nobj > 0 ? nobj : 1), sizeof *out->obj);
  int cap = 0;
  for (int i = 0; i < nobj; i++) {
    const Mesh *m = objs[i].mesh;
    LineObjEdges *oe = &out->obj[i];
    oe->mesh = m;
    oe->lines = objs[i].lines && objs[i].lines->present && objs[i].lines->kinds ? objs[i].lines : NULL;
    /* An object that draws lines keeps its face normals and the kinds
    ** that do not depend on the view with a mesh kept for later frames
    ** (EdgeCache); the rest, and all of the others', are scratch, every
    ** entry written before it is read (from the heap, which keeps the
    ** earlier stages' freed, already mapped memory for reuse). */
    EdgeCache *c = oe->lines && m->keeps_derived ? edge_cache(m, objs[i].object_to_world, oe->lines) : NULL;
    Vec3 *world = xmalloc(((size_t)m->nverts + 1) * sizeof *world);
    Vec3 *fn = c ? c->fn : xmalloc(((size_t)m->ntris + 1) * sizeof *fn);
    unsigned char *zero = c ? c->zero : xmalloc((size_t)m->ntris + 1);
    project_vertices(oe, world, m, objs[i].object_to_world, cam);
    oe->id = xcalloc((size_t)m->nedges + 1, sizeof *oe->id);
    oe->front = xcalloc((size_t)m->ntris + 1, 1);
    if (outside_view(oe, m->nverts)) {   /* nothing of it can show or occlude */
      oe->lines = NULL;
    } else if (c && c->ready) {
      face_fronts(oe->front, m, world, fn, cam);
    } else {
      face_normals(fn, zero, oe->front, m, world, cam);
    }
    if (oe->lines) {
      int first = out->n;
      if (c) {
        if (!c->ready) {
          static_kinds(c, m, world);
          c->ready = 1;
        }
        classify_kept(out, &cap, i, oe, m, c, world, cam);
      } else {
        EdgeTest et = {m->tri_face, world, fn, zero, oe->lines->kinds,
                       crease_cos(oe->lines->crease_angle), cam->kind == CAMERA_ORTHO,
                       cam->forward, cam->eye};
        classify(out, &cap, i, oe, m, &et);
      }
      build_adjacency(oe, m, out->edge_of + first, out->n - first);
    }
    free(world);
    if (!c) {
      free(fn);
      free(zero);
    }
  }
}

void line_edges_free(LineEdges *e) {
  for (int i = 0; i < e->nobj; i++) {
    free(e->obj[i].vert);
    free(e->obj[i].id);
    free(e->obj[i].adj_start);
    free(e->obj[i].adj);
    free(e->obj[i].front);
  }
  free(e->obj);
  free(e->obj_of);
  free(e->edge_of);
  free(e->kind);
  memset(e, 0, sizeof *e);
}

/* ---- workers ------------------------------------------------------------ */

typedef struct ParallelJob {
  void (*fn)(void *ctx, int task, int worker);
  void *ctx;
  int ntasks;
  atomic_int next;
} ParallelJob;

typedef struct ParallelArg { ParallelJob *job; int worker; } ParallelArg;

static void *parallel_worker(void *p) {
  ParallelArg *a = p;
  for (;;) {
    int t = atomic_fetch_add(&a->job->next, 1);
    if (t >= a->job->ntasks) break;
    a->job->fn(a->job->ctx, t, a->worker);
  }
  return NULL;
}

void line_parallel(int ntasks, int threads, void (*fn)(void *ctx, int task, int worker), void *ctx) {
  if (threads > ntasks) threads = ntasks;
  if (threads <= 1) {
    for (int t = 0; t < ntasks; t++) fn(ctx, t, 0);
    return;
  }
  ParallelJob job = {fn, ctx, ntasks, 0};
  pthread_t *th = xmalloc((size_t)threads * sizeof *th);
  ParallelArg *arg = xmalloc((size_t)threads * sizeof *arg);
  int started = 1;
  for (int i = 0; i < threads; i++) { arg[i].job = &job; arg[i].worker = i; }
  for (int i = 1; i < threads; i++) {
    if (pthread_create(&th[i], NULL, parallel_worker, &arg[i]) != 0) break;
    started++;
  }
  parallel_worker(&arg[0]);   /* the caller works too; a failed start only costs speed */
  for (int i = 1; i < started; i++) pthread_join(th[i], NULL);
  free(th);
  free(arg);
}
