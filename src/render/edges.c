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

/* A triangle's plane in world space: its unit normal and d = n . p0, p0
** its first corner; all NaN for a degenerate face (no normal), so that
** every test of it below fails (no crease, no silhouette, not a front).
** Which side of it the viewer is on, one dot product a frame, says whether
** the face is turned toward the viewer; an edge is a silhouette where its
** two faces disagree. */
typedef struct FacePlane { double x, y, z, d; } FacePlane;

static inline FacePlane face_plane(const Vec3 *world, const int c[3]) {
  const Vec3 *a = &world[c[0]], *b = &world[c[1]], *e = &world[c[2]];
  /* v3_norm(v3_cross(b - a, e - a)), written out */
  double ux = b->x - a->x, uy = b->y - a->y, uz = b->z - a->z;
  double vx = e->x - a->x, vy = e->y - a->y, vz = e->z - a->z;
  double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
  double l = sqrt(nx * nx + ny * ny + nz * nz);
  if (!(l > 0)) return (FacePlane){NAN, NAN, NAN, NAN};
  double il = 1.0 / l;
  nx *= il;
  ny *= il;
  nz *= il;
  return (FacePlane){nx, ny, nz, nx * a->x + ny * a->y + nz * a->z};
}

/* The viewer's side of plane p: > 0 in front of it (the face is turned
** toward the viewer), < 0 behind, 0 edge-on. A perspective viewer is at
** eye; an orthographic one looks along forward. */
static inline double plane_side(FacePlane p, int ortho, Vec3 forward, Vec3 eye) {
  if (ortho) return -(p.x * forward.x + p.y * forward.y + p.z * forward.z);
  return p.x * eye.x + p.y * eye.y + p.z * eye.z - p.d;
}

/* Which side of its face's plane the viewer is on, as bits: SIDE_FRONT
** where plane_side >= 0, SIDE_BACK where <= 0 (both edge-on). An edge is
** a silhouette where its faces' bits together are both: one face looks at
** the viewer and the other away, or either is edge-on. */
#define SIDE_FRONT 1u
#define SIDE_BACK 2u

static inline unsigned side_bits(double s) {
  return (unsigned)(s >= 0) | (unsigned)(s <= 0) << 1;
}

/* What the view-independent half of classifying an object's edges needs
** besides the edge: its triangles' source faces and planes, the kinds
** wanted, and the crease test as n0 . n1 <= crease_cos. */
typedef struct EdgeTest {
  const int *tri_face;
  const FacePlane *plane;
  unsigned want;
  double crease_cos;
} EdgeTest;

/* The crease test's bound on n0 . n1 for crease(angle): faces meeting at
** less than LINE_COPLANAR_DEG are coplanar, so crease(0) marks every edge
** whose faces are not (a flat polygon's diagonals never, however rounding
** tilts their normals), the same on every edge. */
static double crease_cos(double angle) {
  return cos((angle > LINE_COPLANAR_DEG ? angle : LINE_COPLANAR_DEG) * M_PI / 180.0);
}

/* Set on an edge's view-independent kinds where the silhouette test
** applies: silhouettes are wanted and the edge has two faces, neither
** degenerate. */
#define EDGE_TRY_SILHOUETTE 0x80u

/* The kinds of edge me that do not depend on the view, with
** EDGE_TRY_SILHOUETTE. A degenerate face's NaN plane fails the crease
** test and makes n0 . n1 NaN. */
static inline unsigned static_kind(const MeshEdge *me, const EdgeTest *et) {
  unsigned want = et->want;
  int f0 = me->f[0], f1 = me->f[1];
  if ((f0 | f1) < 0)   /* fewer than two faces: a mesh border is a polygon edge too */
    return want & (EDGE_BOUNDARY | EDGE_FACE);
  const FacePlane *n0 = &et->plane[f0], *n1 = &et->plane[f1];
  double dot = n0->x * n1->x + n0->y * n1->y + n0->z * n1->z;
  unsigned kind = dot == dot && (want & EDGE_SILHOUETTE) ? EDGE_TRY_SILHOUETTE : 0;
  /* tagged by subdivision, or angle(n0, n1) >= threshold  <=>  n0 . n1 <= cos(threshold) */
  if (me->sharpness > 0 || dot <= et->crease_cos) kind |= want & EDGE_CREASE;
  if ((want & EDGE_FACE) && (!et->tri_face || et->tri_face[f0] != et->tri_face[f1]))
    kind |= EDGE_FACE;
  return kind;
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

/* Clip coordinates and reference pixels of m's vertices [v0, v1) into
** vert, and their world positions into world (unless NULL: nothing needs
** them). */
static void project_vertices(LineVert *vert, Vec3 *world, const Mesh *m, Mat4 to_world,
                             const Camera *cam, int v0, int v1) {
  Mat4 M = cam->world_to_clip;   /* a copy, which the stores below cannot change */
  int width = cam->width, height = cam->height;
  for (int v = v0; v < v1; v++) {
    LineVert *lv = &vert[v];
    Vec3 p = m4_point(to_world, m->pos[v]);
    if (world) world[v] = p;
    double c[4] = {   /* clip = world_to_clip * (p, 1), row by row */
        M.m[0][0] * p.x + M.m[0][1] * p.y + M.m[0][2] * p.z + M.m[0][3],
        M.m[1][0] * p.x + M.m[1][1] * p.y + M.m[1][2] * p.z + M.m[1][3],
        M.m[2][0] * p.x + M.m[2][1] * p.y + M.m[2][2] * p.z + M.m[2][3],
        M.m[3][0] * p.x + M.m[3][1] * p.y + M.m[3][2] * p.z + M.m[3][3]};
    memcpy(lv->clip, c, sizeof c);
    float x = 0, y = 0, n = 0;   /* behind the eye */
    lv->in = 0;
    if (c[3] > 0) {
      line_clip_to_screen(c, width, height, &x, &y, &n);
      lv->in = c[2] + c[3] >= 0 && isfinite(x) && isfinite(y) && isfinite(n);
    }
    lv->x = x, lv->y = y, lv->n = n;
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

/* The side_bits of the triangles [t0, t1) of planes plane into side, and
** which of them the viewer sees the front of (plane_side > 0: SIDE_FRONT
** alone) into front. */
static void face_sides(unsigned char *front, unsigned char *side, const FacePlane *plane, int t0,
                       int t1, const Camera *cam) {
  Vec3 fwd = cam->forward, eye = cam->eye;
  if (cam->kind == CAMERA_ORTHO) {   /* two loops: no test of the camera in either */
    for (int t = t0; t < t1; t++) side[t] = (unsigned char)side_bits(plane_side(plane[t], 1, fwd, eye));
  } else {
    for (int t = t0; t < t1; t++) side[t] = (unsigned char)side_bits(plane_side(plane[t], 0, fwd, eye));
  }
  for (int t = t0; t < t1; t++) front[t] = side[t] == SIDE_FRONT;
}

/* The same for an object without lines (it only occludes): the front
** faces of its triangles [t0, t1), from planes made as they are needed. */
static void occluder_fronts(unsigned char *front, const Mesh *m, const Vec3 *world,
                            const Camera *cam, int t0, int t1) {
  int ortho = cam->kind == CAMERA_ORTHO;
  Vec3 fwd = cam->forward, eye = cam->eye;
  for (int t = t0; t < t1; t++)
    front[t] = plane_side(face_plane(world, m->tri[t]), ortho, fwd, eye) > 0;
}

/* ---- what the mesh decides, kept with it --------------------------------- */

/* The half of classifying an object's edges that does not depend on the
** view: its triangles' world planes and, per edge, its kinds but
** silhouette (static_kind). Kept with a mesh kept for later frames
** (mesh_derived), made for one transform, set of kinds and crease angle
** (compared exactly); for any other mesh, made for the frame and freed. */
typedef struct EdgeCache {
  Mat4 to_world;
  unsigned want;
  double crease_cos;
  FacePlane *plane;
  unsigned char *kind;     /* NULL in a cache made for one frame */
  double (*box)[6];        /* per run of LINE_CLUSTER_TRIS triangles: the least and greatest
                              x, y, z of their corners (world); NULL in a cache made for
                              one frame */
  int ready;               /* plane, kind and box are filled (the first frame may stop short) */
} EdgeCache;

static const char edge_cache_tag;

static void edge_cache_free(void *p) {
  EdgeCache *c = p;
  free(c->plane);
  free(c->kind);
  free(c->box);
  free(c);
}

static int nclusters(const Mesh *m) {
  return (m->ntris + LINE_CLUSTER_TRIS - 1) / LINE_CLUSTER_TRIS;
}

/* The planes of m's triangles [t0, t1) into c, from m's world positions. */
static void edge_cache_planes(EdgeCache *c, const Mesh *m, const Vec3 *world, int t0, int t1) {
  for (int t = t0; t < t1; t++) c->plane[t] = face_plane(world, m->tri[t]);
}

/* The kept kinds of m's edges [e0, e1) into c, from its planes. */
static void edge_cache_kinds(EdgeCache *c, const Mesh *m, int e0, int e1) {
  EdgeTest et = {m->tri_face, c->plane, c->want, c->crease_cos};
  for (int e = e0; e < e1; e++) c->kind[e] = (unsigned char)static_kind(&m->edges[e], &et);
}

/* The boxes of c's runs of m's triangles, from m's world positions. */
static void edge_cache_boxes(EdgeCache *c, const Mesh *m, const Vec3 *world) {
  for (int k = 0, t0 = 0; t0 < m->ntris; k++, t0 += LINE_CLUSTER_TRIS) {
    const int *v = m->tri[t0], *end = m->tri[t0 + LINE_CLUSTER_TRIS < m->ntris ? t0 + LINE_CLUSTER_TRIS : m->ntris];
    double x0 = world[*v].x, y0 = world[*v].y, z0 = world[*v].z, x1 = x0, y1 = y0, z1 = z0;
    for (; v < end; v++) {   /* every corner of the run's triangles */
      Vec3 p = world[*v];
      x0 = p.x < x0 ? p.x : x0;
      y0 = p.y < y0 ? p.y : y0;
      z0 = p.z < z0 ? p.z : z0;
      x1 = p.x > x1 ? p.x : x1;
      y1 = p.y > y1 ? p.y : y1;
      z1 = p.z > z1 ? p.z : z1;
    }
    double *b = c->box[k];
    b[0] = x0, b[1] = y0, b[2] = z0, b[3] = x1, b[4] = y1, b[5] = z1;
  }
}

/* A box in reference pixels holding the projection of world box b (its
** corners' pixels, a pixel wider on each side for the rounding of the
** vertices' own projection), or an infinite one when some of b is behind
** the near plane or the eye (or not finite). Every point of b is in front
** of the near plane when its corners are, and then projects inside the
** hull of theirs. */
static void cluster_rect(float r[4], const double b[6], const Camera *cam) {
  const double(*M)[4] = cam->world_to_clip.m;
  double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  int ahead = 1;
  for (int k = 0; k < 8; k++) {
    double p[3] = {b[k & 1 ? 3 : 0], b[k & 2 ? 4 : 1], b[k & 4 ? 5 : 2]}, q[4];
    for (int j = 0; j < 4; j++) q[j] = M[j][0] * p[0] + M[j][1] * p[1] + M[j][2] * p[2] + M[j][3];
    ahead &= q[3] > 0 && q[2] + q[3] >= 0;
    double x = (q[0] / q[3] + 1) * 0.5 * cam->width, y = (1 - q[1] / q[3]) * 0.5 * cam->height;
    x0 = x < x0 ? x : x0;
    y0 = y < y0 ? y : y0;
    x1 = x > x1 ? x : x1;
    y1 = y > y1 ? y : y1;
  }
  if (!(ahead && isfinite(x0) && isfinite(y0) && isfinite(x1) && isfinite(y1))) {
    r[0] = r[1] = -INFINITY;
    r[2] = r[3] = INFINITY;
    return;
  }
  r[0] = (float)(x0 - 1);
  r[1] = (float)(y0 - 1);
  r[2] = (float)(x1 + 1);
  r[3] = (float)(y1 + 1);
}

/* The cache kept with m for this transform, kinds and crease angle, or a
** new one (not ready), kept with m in place of any other when m
** keeps_derived; else *scratch is set and it is the caller's to free. The
** mesh is the caller's to keep or free: the cache is an addition to it,
** not a change. */
static EdgeCache *edge_cache(const Mesh *m, Mat4 to_world, const SceneLines *ls, int *scratch) {
  double ccos = crease_cos(ls->crease_angle);
  EdgeCache *c = mesh_derived(m, &edge_cache_tag);
  *scratch = 0;
  if (c && !memcmp(&c->to_world, &to_world, sizeof to_world) && c->want == ls->kinds &&
      c->crease_cos == ccos)
    return c;
  c = xmalloc(sizeof *c);
  *c = (EdgeCache){to_world, ls->kinds, ccos, xmalloc(((size_t)m->ntris + 1) * sizeof *c->plane),
                   NULL, NULL, 0};
  if (!mesh_derived_set((Mesh *)m, &edge_cache_tag, c, edge_cache_free)) *scratch = 1;
  /* For one frame the kinds are worked out as the edges are classified.
  ** Making the boxes costs more than they spare the reference image in
  ** one frame (most triangles of a large mesh lie near some edge's
  ** samples): they are made once for a mesh kept across frames. */
  if (!*scratch) {
    c->kind = xmalloc((size_t)m->nedges + 1);
    c->box = xmalloc(((size_t)nclusters(m) + 1) * sizeof *c->box);
  }
  return c;
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

/* The kinds of m's edges [e0, e1) into kind: their view-independent
** kinds (ck, or static_kind from et where ck is NULL), and a silhouette
** where the edge's faces' side bits are both. */
static inline __attribute__((always_inline)) void kinds_from(
    int *kind, const Mesh *m, const unsigned char *ck, const EdgeTest *et, const unsigned char *side,
    int e0, int e1) {
  const MeshEdge *me = m->edges;
  for (int e = e0; e < e1; e++) {
    unsigned k = ck ? ck[e] : static_kind(&me[e], et);
    if (k & EDGE_TRY_SILHOUETTE) {
      if ((side[me[e].f[0]] | side[me[e].f[1]]) == (SIDE_FRONT | SIDE_BACK)) k |= EDGE_SILHOUETTE;
      k &= ~EDGE_TRY_SILHOUETTE;
    }
    kind[e] = (int)k;
  }
}

/* The same from c: its kept kinds, or for a cache made for one frame
** (no kinds kept) worked out in the same pass. */
static void edge_kinds(int *kind, const Mesh *m, const EdgeCache *c, const unsigned char *side,
                       int e0, int e1) {
  EdgeTest et = {m->tri_face, c->plane, c->want, c->crease_cos};
  if (c->kind) kinds_from(kind, m, c->kind, &et, side, e0, e1);
  else kinds_from(kind, m, NULL, &et, side, e0, e1);
}

/* Append object obj's important edges (a kind in oe->id, which each
** becomes its id). */
static void add_edges(LineEdges *out, int *cap, int obj, LineObjEdges *oe, const Mesh *m) {
  for (int e = 0; e < m->nedges; e++) {
    if (!oe->id[e]) continue;
    add_edge(out, cap, obj, e, (unsigned)oe->id[e]);
    oe->id[e] = out->n;
  }
}

/* ---- an object's stages, on workers ---------------------------------------- */

/* Vertices, triangles or edges a task of those stages takes. */
#define LINE_EDGE_CHUNK 65536

/* What the stages of one object read and write; each task writes only
** the entries of its range. */
typedef struct ObjJob {
  LineObjEdges *oe;
  const Mesh *m;
  Mat4 to_world;
  const Camera *cam;
  Vec3 *world;
  EdgeCache *c;
  unsigned char *side;
} ObjJob;

/* Run task(job, a, b) over [0, n) in ranges of LINE_EDGE_CHUNK on up to
** threads workers. */
typedef void (*RangeTask)(ObjJob *j, int a, int b);
typedef struct RangeJob { ObjJob *job; RangeTask task; int n; } RangeJob;

static void range_task(void *ctx, int k, int worker) {
  RangeJob *r = ctx;
  int a = k * LINE_EDGE_CHUNK, b = a + LINE_EDGE_CHUNK < r->n ? a + LINE_EDGE_CHUNK : r->n;
  r->task(r->job, a, b);
}

static void over_ranges(ObjJob *j, RangeTask task, int n, int threads) {
  RangeJob r = {j, task, n};
  line_parallel((n + LINE_EDGE_CHUNK - 1) / LINE_EDGE_CHUNK, threads, range_task, &r);
}

static void project_range(ObjJob *j, int a, int b) {
  project_vertices(j->oe->vert, j->world, j->m, j->to_world, j->cam, a, b);
}
static void occluder_range(ObjJob *j, int a, int b) {
  occluder_fronts(j->oe->front, j->m, j->world, j->cam, a, b);
}
static void plane_range(ObjJob *j, int a, int b) { edge_cache_planes(j->c, j->m, j->world, a, b); }
static void kept_kind_range(ObjJob *j, int a, int b) { edge_cache_kinds(j->c, j->m, a, b); }
static void side_range(ObjJob *j, int a, int b) {
  face_sides(j->oe->front, j->side, j->c->plane, a, b, j->cam);
}
static void kind_range(ObjJob *j, int a, int b) { edge_kinds(j->oe->id, j->m, j->c, j->side, a, b); }

void line_edges_build(LineEdges *out, const LineObject *objs, int nobj, const Camera *cam,
                      int threads) {
  memset(out, 0, sizeof *out);
  out->nobj = nobj;
  out->obj = xcalloc((size_t)(nobj > 0 ? nobj : 1), sizeof *out->obj);
  int cap = 0;
  for (int i = 0; i < nobj; i++) {
    const Mesh *m = objs[i].mesh;
    LineObjEdges *oe = &out->obj[i];
    oe->mesh = m;
    oe->lines = objs[i].lines && objs[i].lines->present && objs[i].lines->kinds ? objs[i].lines : NULL;
    /* World positions are scratch (from the heap, which keeps the earlier
    ** stages' freed, already mapped memory for reuse), needed only where
    ** no kept cache has the planes. */
    int scratch = 0;
    EdgeCache *c = oe->lines ? edge_cache(m, objs[i].object_to_world, oe->lines, &scratch) : NULL;
    Vec3 *world = c && c->ready ? NULL : xmalloc(((size_t)m->nverts + 1) * sizeof *world);
    ObjJob j = {oe, m, objs[i].object_to_world, cam, world, c, NULL};
    oe->vert = xmalloc(((size_t)m->nverts + 1) * sizeof *oe->vert);   /* every entry written */
    over_ranges(&j, project_range, m->nverts, threads);
    oe->front = xcalloc((size_t)m->ntris + 1, 1);
    if (outside_view(oe, m->nverts)) {   /* nothing of it can show or occlude */
      oe->lines = NULL;
    } else if (!oe->lines) {
      over_ranges(&j, occluder_range, m->ntris, threads);
    }
    if (!oe->lines) {
      oe->id = xcalloc((size_t)m->nedges + 1, sizeof *oe->id);
    } else {
      if (!c->ready) {
        over_ranges(&j, plane_range, m->ntris, threads);
        if (c->box) edge_cache_boxes(c, m, world);
        if (c->kind) over_ranges(&j, kept_kind_range, m->nedges, threads);
        c->ready = 1;
      }
      j.side = xmalloc((size_t)m->ntris + 1);
      over_ranges(&j, side_range, m->ntris, threads);
      oe->id = xmalloc(((size_t)m->nedges + 1) * sizeof *oe->id);   /* every entry written */
      over_ranges(&j, kind_range, m->nedges, threads);
      free(j.side);
      int first = out->n;
      add_edges(out, &cap, i, oe, m);
      build_adjacency(oe, m, out->edge_of + first, out->n - first);
      if (c->box) {
        oe->cluster = xmalloc(((size_t)nclusters(m) + 1) * sizeof *oe->cluster);
        for (int k = 0; k < nclusters(m); k++) cluster_rect(oe->cluster[k], c->box[k], cam);
      }
    }
    if (scratch) edge_cache_free(c);
    free(world);
  }
}

void line_edges_free(LineEdges *e) {
  for (int i = 0; i < e->nobj; i++) {
    free(e->obj[i].vert);
    free(e->obj[i].id);
    free(e->obj[i].adj_start);
    free(e->obj[i].adj);
    free(e->obj[i].front);
    free(e->obj[i].cluster);
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
