/*
** Polylines from segments: each visible edge not yet used seeds polylines
** from its segments; segments touching an end grow through links found by
** a breadth-first search of the mesh graph (001 §2.1.5).
*/
#include "link.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"

typedef struct PtBuf { int n, cap; float *p; } PtBuf;   /* n points, x y pairs */

/* A polyline waiting to grow from vertex v past edge e (mesh edge). */
typedef struct Pending { PtBuf pts; int obj, v, e; } Pending;

typedef struct Linker {
  const LineRef *ref;
  const LineTrace *tr;
  const LineEdges *edges;
  unsigned char *used;     /* per id - 1 */
  int **stamp;             /* per object, per mesh edge: last search that visited it */
  int cur;                 /* the current search */
  int *frontier, *next;    /* vertex lists of the search */
  int cap_front, cap_next;
  Pending *queue;
  int nqueue, cap_queue, qhead;
  LineSeg *tmp;            /* oriented segments of one edge */
  int cap_tmp;
  LinePolys *out;
} Linker;

static void pt_push(PtBuf *b, float x, float y) {
  if (b->n > 0 && fabsf(b->p[2 * b->n - 2] - x) < 1e-3f && fabsf(b->p[2 * b->n - 1] - y) < 1e-3f)
    return;   /* the shared end of two linked segments */
  int cap2 = b->cap * 2;
  b->p = xgrow(b->p, &cap2, 2 * b->n + 2, sizeof *b->p);
  b->cap = cap2 / 2;
  b->p[2 * b->n] = x;
  b->p[2 * b->n + 1] = y;
  b->n++;
}

void line_polys_append(LinePolys *o, const float *p, int n, int obj) {
  if (n < 2) return;
  o->pts = xgrow(o->pts, &o->cap_pts, 2 * (o->npts + n), sizeof *o->pts);
  memcpy(o->pts + 2 * o->npts, p, (size_t)n * 2 * sizeof *p);
  o->start = xgrow(o->start, &o->cap_start, o->n + 2, sizeof *o->start);
  o->obj = xgrow(o->obj, &o->cap, o->n + 1, sizeof *o->obj);
  o->start[o->n] = o->npts;
  o->obj[o->n] = obj;
  o->n++;
  o->npts += n;
  o->start[o->n] = o->npts;
}

/* Append points [0, n) of p as one polyline of obj. */
static void emit(Linker *L, const float *p, int n, int obj) { line_polys_append(L->out, p, n, obj); }

static void emit_seg(Linker *L, const LineSeg *s, int obj) {
  float p[4] = {s->x0, s->y0, s->x1, s->y1};
  emit(L, p, 2, obj);
}

/* Did tracing find any of id visible (a lone visible step is none)? */
static int has_segments(const Linker *L, int id) { return L->tr->first[id] > L->tr->first[id - 1]; }

/* The screen direction of id's span leaving vertex v (unit, or zero when
** the span has no length). */
static void span_dir(const Linker *L, int id, int v, float *dx, float *dy) {
  const LineSpan *s = &L->ref->span[id - 1];
  const MeshEdge *me = &L->edges->obj[L->edges->obj_of[id - 1]].mesh->edges[L->edges->edge_of[id - 1]];
  float x = s->x1 - s->x0, y = s->y1 - s->y0;
  if (me->v[0] != v) { x = -x; y = -y; }
  float len = sqrtf(x * x + y * y);
  *dx = len > 1e-6f ? x / len : 0;
  *dy = len > 1e-6f ? y / len : 0;
}

/* Search object obj's graph from vertex v for a link past mesh edge e,
** along which the line arrives at v in direction (dx, dy): a candidate's
** direction leaving its near vertex must be within link_angle of it.
** Returns the mesh edge and its near vertex (*near), or -1. */
static int find_link(Linker *L, int obj, int v, int e, float dx, float dy, int *near) {
  const LineObjEdges *oe = &L->edges->obj[obj];
  const SceneLines *ls = oe->lines;
  const Mesh *m = oe->mesh;
  int *stamp = L->stamp[obj];
  double min_cos = cos(ls->link_angle * M_PI / 180.0);
  int cur = ++L->cur, nf = 1;
  stamp[e] = cur;
  L->frontier[0] = v;
  for (int depth = 1; depth <= ls->link_depth && nf > 0; depth++) {
    int best = -1, refused = 0, nn = 0;
    double best_cos = -2;
    for (int f = 0; f < nf; f++) {
      int x = L->frontier[f];
      for (int k = oe->adj_start[x]; k < oe->adj_start[x + 1]; k++) {
        int c = oe->adj[k], id = oe->id[c];
        if (stamp[c] == cur) continue;
        stamp[c] = cur;
        if (!id || L->used[id - 1]) continue;   /* only unused important edges */
        int other = m->edges[c].v[0] == x ? m->edges[c].v[1] : m->edges[c].v[0];
        if (has_segments(L, id)) {               /* visible: a candidate */
          float cx, cy;
          span_dir(L, id, x, &cx, &cy);
          double cs = (cx == 0 && cy == 0) || (dx == 0 && dy == 0) ? 1 : (double)(cx * dx + cy * dy);
          if (cs > min_cos) {
            if (cs > best_cos) { best_cos = cs; best = c; *near = x; }
          } else {
            refused = 1;
          }
        } else {                                 /* hidden or lost at this resolution: go past it */
          L->next = xgrow(L->next, &L->cap_next, nn + 1, sizeof *L->next);
          L->next[nn++] = other;
        }
      }
    }
    if (best >= 0) return best;
    if (refused) return -1;   /* never deeper than a refusal */
    int *t = L->frontier; L->frontier = L->next; L->next = t;
    int tc = L->cap_front; L->cap_front = L->cap_next; L->cap_next = tc;
    nf = nn;
  }
  return -1;
}

/* The segments of id ordered from vertex u into L->tmp; returns how many. */
static int oriented_segs(Linker *L, int id, int u) {
  const MeshEdge *me = &L->edges->obj[L->edges->obj_of[id - 1]].mesh->edges[L->edges->edge_of[id - 1]];
  int a = L->tr->first[id - 1], n = L->tr->first[id] - a;
  L->tmp = xgrow(L->tmp, &L->cap_tmp, n + 1, sizeof *L->tmp);
  for (int i = 0; i < n; i++) {
    LineSeg s = L->tr->seg[a + i];
    if (me->v[0] != u) {
      LineSeg r = {s.x1, s.y1, s.x0, s.y0, s.at1, s.at0};
      L->tmp[n - 1 - i] = r;
    } else {
      L->tmp[i] = s;
    }
  }
  return n;
}

static void enqueue(Linker *L, const LineSeg *s, int obj, int v, int e) {
  L->queue = xgrow(L->queue, &L->cap_queue, L->nqueue + 1, sizeof *L->queue);
  Pending *p = &L->queue[L->nqueue++];
  memset(&p->pts, 0, sizeof p->pts);
  pt_push(&p->pts, s->x0, s->y0);
  pt_push(&p->pts, s->x1, s->y1);
  p->obj = obj; p->v = v; p->e = e;
}

/* Grow b (outward) from vertex v, the far end of mesh edge e of obj. */
static void extend(Linker *L, PtBuf *b, int obj, int v, int e) {
  const Mesh *m = L->edges->obj[obj].mesh;
  const int *ids = L->edges->obj[obj].id;
  for (;;) {
    float dx, dy, ox, oy;
    span_dir(L, ids[e], v, &ox, &oy);   /* leaving v along e: reverse for the way in */
    dx = -ox; dy = -oy;
    int u, c = find_link(L, obj, v, e, dx, dy, &u);
    if (c < 0) return;
    int id = ids[c];
    L->used[id - 1] = 1;
    int w = m->edges[c].v[0] == u ? m->edges[c].v[1] : m->edges[c].v[0];
    int n = oriented_segs(L, id, u);
    int near_seg = n > 0 && L->tmp[0].at0 ? 0 : -1;
    int far_seg = n > 0 && L->tmp[n - 1].at1 ? n - 1 : -1;
    if (near_seg == 0) {
      pt_push(b, L->tmp[0].x0, L->tmp[0].y0);
      pt_push(b, L->tmp[0].x1, L->tmp[0].y1);
    }
    for (int i = 0; i < n; i++)   /* pieces touching neither end stand alone */
      if (i != near_seg && i != far_seg) emit_seg(L, &L->tmp[i], obj);
    if (near_seg == 0 && far_seg == 0) { v = w; e = c; continue; }   /* fully visible: go on */
    if (far_seg >= 0) enqueue(L, &L->tmp[far_seg], obj, w, c);      /* a new polyline from w */
    return;
  }
}

/* Polylines from the segments of one seed edge id. */
static void seed(Linker *L, int id) {
  int obj = L->edges->obj_of[id - 1], e = L->edges->edge_of[id - 1];
  const MeshEdge *me = &L->edges->obj[obj].mesh->edges[e];
  int a = L->tr->first[id - 1], n = L->tr->first[id] - a;
  L->used[id - 1] = 1;
  for (int i = 0; i < n; i++) {
    const LineSeg s = L->tr->seg[a + i];
    if (!s.at0 && !s.at1) { emit_seg(L, &s, obj); continue; }
    PtBuf fwd = {0, 0, NULL}, back = {0, 0, NULL};
    pt_push(&fwd, s.x0, s.y0);
    pt_push(&fwd, s.x1, s.y1);
    if (s.at1) extend(L, &fwd, obj, me->v[1], e);
    if (s.at0) {   /* grow backward from v[0], then join: reversed back, fwd */
      pt_push(&back, s.x0, s.y0);
      extend(L, &back, obj, me->v[0], e);
      PtBuf all = {0, 0, NULL};
      for (int k = back.n - 1; k >= 0; k--) pt_push(&all, back.p[2 * k], back.p[2 * k + 1]);
      for (int k = 1; k < fwd.n; k++) pt_push(&all, fwd.p[2 * k], fwd.p[2 * k + 1]);
      emit(L, all.p, all.n, obj);
      free(all.p);
    } else {
      emit(L, fwd.p, fwd.n, obj);
    }
    free(fwd.p);
    free(back.p);
  }
  while (L->qhead < L->nqueue) {   /* polylines started while linking */
    Pending p = L->queue[L->qhead++];
    extend(L, &p.pts, p.obj, p.v, p.e);
    emit(L, p.pts.p, p.pts.n, p.obj);
    free(p.pts.p);
  }
  L->nqueue = L->qhead = 0;
}

void line_link_build(LinePolys *out, const LineRef *ref, const LineTrace *tr,
                     const LineEdges *edges) {
  memset(out, 0, sizeof *out);
  Linker L;
  memset(&L, 0, sizeof L);
  L.ref = ref; L.tr = tr; L.edges = edges; L.out = out;
  L.used = xcalloc((size_t)ref->nids + 1, 1);
  L.stamp = xcalloc((size_t)edges->nobj + 1, sizeof *L.stamp);
  for (int i = 0; i < edges->nobj; i++)
    if (edges->obj[i].lines)
      L.stamp[i] = xcalloc((size_t)edges->obj[i].mesh->nedges + 1, sizeof **L.stamp);
  L.frontier = xgrow(NULL, &L.cap_front, 16, sizeof *L.frontier);
  L.next = xgrow(NULL, &L.cap_next, 16, sizeof *L.next);
  for (int k = 0; k < ref->nvisible; k++)
    if (!L.used[ref->visible[k] - 1] && has_segments(&L, ref->visible[k])) seed(&L, ref->visible[k]);
  for (int i = 0; i < edges->nobj; i++) free(L.stamp[i]);
  free(L.stamp);
  free(L.used);
  free(L.frontier);
  free(L.next);
  free(L.queue);
  free(L.tmp);
  if (!out->start) out->start = xgrow(NULL, &out->cap_start, 1, sizeof *out->start);
  out->start[out->n] = out->npts;
}

void line_polys_free(LinePolys *p) {
  free(p->start);
  free(p->pts);
  free(p->obj);
  memset(p, 0, sizeof *p);
}
