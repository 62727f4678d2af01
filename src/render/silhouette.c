/*
** Endpoint culling and 2-pixel linking of 003 ch. 2.5 and 3.3 (see
** silhouette.h): written bottom-up, the depth test, the bisection, the
** pieces, then the endpoint index and the linker.
*/
#include "silhouette.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"

/* ---- culling --------------------------------------------------------------- */

/* Does the point at t in [0, 1] along edge id's span pass the depth test?
** It is read at the nearest point of the edge's walk, which the reference
** test (edgeref.h) decided on the exact line: a point a pixel apart along
** the dominant axis, so the answer is the test's own within half a pixel. */
static int passes(const LineRef *ref, int id, float t) {
  const LineSpan *s = &ref->span[id - 1];
  int i = (int)lroundf(t * (float)(s->nsteps - 1));
  return line_ref_vis(ref, id)[i];
}

int sil_cull_span(const LineRef *ref, int id, int steps, float *t0, float *t1) {
  const LineSpan *s = &ref->span[id - 1];
  if (s->nsteps <= 0) return 0;
  int a = passes(ref, id, 0), b = passes(ref, id, 1);
  *t0 = 0;
  *t1 = 1;
  if (a && b) return 1;
  if (!a && !b) return 0;
  if (steps <= 0) return 0;
  /* the boundary lies between the visible end v and the hidden end h */
  float v = a ? 0.0f : 1.0f, h = 1 - v;
  float len = hypotf(s->x1 - s->x0, s->y1 - s->y0);
  for (int k = 0; k < steps && fabsf(h - v) * len > 0.5f; k++) {
    float m = 0.5f * (v + h);
    if (passes(ref, id, m)) v = m;
    else h = m;
  }
  *t0 = a ? 0.0f : 1.0f;
  *t1 = v;
  return 2;
}

/* Is there a face that puts edge e (mesh edge me, projected vertices vert)
** on a side, and which: +1 when it lies left of v[0] -> v[1] as seen on
** the screen (y down), -1 right, 0 none. It is the front face of a
** silhouette or the one face of a boundary. */
static int edge_side(const MeshEdge *me, const Mesh *m, const LineObjEdges *oe) {
  int f = -1;
  if (me->f[1] < 0) f = me->f[0];
  else if (oe->front[me->f[0]] != oe->front[me->f[1]]) f = oe->front[me->f[0]] ? me->f[0] : me->f[1];
  if (f < 0) return 0;
  int c = m->tri[f][0] + m->tri[f][1] + m->tri[f][2] - me->v[0] - me->v[1];   /* the third corner */
  const LineVert *a = &oe->vert[me->v[0]], *b = &oe->vert[me->v[1]], *p = &oe->vert[c];
  if (!(a->clip[3] > 0 && b->clip[3] > 0 && p->clip[3] > 0)) return 0;
  /* left of d as seen, with y down, is (d.y, -d.x) */
  double dx = b->x - a->x, dy = b->y - a->y;
  double side = (p->x - a->x) * dy - (p->y - a->y) * dx;
  return side > 0 ? 1 : side < 0 ? -1 : 0;
}

static void add_piece(SilPieces *out, const LineSpan *s, float t0, float t1, int obj, int side) {
  float x0 = s->x0 + t0 * (s->x1 - s->x0), y0 = s->y0 + t0 * (s->y1 - s->y0);
  float x1 = s->x0 + t1 * (s->x1 - s->x0), y1 = s->y0 + t1 * (s->y1 - s->y0);
  if (side < 0) {   /* turn it so that its face is on the left */
    float tx = x0, ty = y0;
    x0 = x1; y0 = y1; x1 = tx; y1 = ty;
  }
  out->p = xgrow(out->p, &out->cap, out->n + 1, sizeof *out->p);
  out->p[out->n++] = (SilPiece){x0, y0, x1, y1, obj, side != 0};
}

void sil_cull(SilPieces *out, const LineRef *ref, const LineEdges *edges) {
  memset(out, 0, sizeof *out);
  for (int i = 0; i < edges->n; i++) {
    const LineObjEdges *oe = &edges->obj[edges->obj_of[i]];
    const LineSpan *s = &ref->span[i];
    float t0, t1;
    int r = sil_cull_span(ref, i + 1, oe->lines->cull_steps, &t0, &t1);
    out->tested++;
    if (r == 0) { out->dropped++; continue; }
    if (r == 1) out->whole++;
    else out->cut++;
    if (r == 2 && fabsf(t1 - t0) * hypotf(s->x1 - s->x0, s->y1 - s->y0) < 1e-3f) continue;   /* nothing left */
    const MeshEdge *me = &oe->mesh->edges[edges->edge_of[i]];
    add_piece(out, s, t0, t1, edges->obj_of[i], edge_side(me, oe->mesh, oe));
  }
}

void sil_pieces_free(SilPieces *p) {
  free(p->p);
  memset(p, 0, sizeof *p);
}

/* ---- endpoint index -------------------------------------------------------- */

/* The ends of every piece on a grid of cells `cell` pixels square, sorted
** by cell (row-major), so the ends near a point are a few runs. End k is
** end k & 1 of piece k >> 1. */
typedef struct EndKey { long long key; int end; } EndKey;

typedef struct EndIndex {
  float cell;
  int gw;                  /* cells a row */
  EndKey *e;               /* sorted by cell, then end */
  int n;
} EndIndex;

static int cmp_end(const void *a, const void *b) {
  const EndKey *p = a, *q = b;
  if (p->key != q->key) return p->key < q->key ? -1 : 1;
  return p->end - q->end;
}

static void end_xy(const SilPieces *ps, int k, float *x, float *y) {
  const SilPiece *p = &ps->p[k >> 1];
  *x = k & 1 ? p->x1 : p->x0;
  *y = k & 1 ? p->y1 : p->y0;
}

static long long cell_key(const EndIndex *ix, int cx, int cy) { return (long long)cy * ix->gw + cx; }

static void index_build(EndIndex *ix, const SilPieces *ps, float cell) {
  ix->cell = cell;
  ix->n = 2 * ps->n;
  float xmax = 1;
  for (int k = 0; k < ix->n; k++) {
    float x, y;
    end_xy(ps, k, &x, &y);
    if (x > xmax) xmax = x;
  }
  ix->gw = (int)(xmax / cell) + 2;   /* column cx + 1 of any end is still in its row */
  ix->e = xmalloc(((size_t)ix->n + 1) * sizeof *ix->e);
  for (int k = 0; k < ix->n; k++) {
    float x, y;
    end_xy(ps, k, &x, &y);
    ix->e[k] = (EndKey){cell_key(ix, (int)floorf(x / cell), (int)floorf(y / cell)), k};
  }
  qsort(ix->e, (size_t)ix->n, sizeof *ix->e, cmp_end);
}

/* First sorted position whose key is >= key. */
static int lower_bound(const EndIndex *ix, long long key) {
  int lo = 0, hi = ix->n;
  while (lo < hi) {
    int mid = (lo + hi) / 2;
    if (ix->e[mid].key < key) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

/* ---- linking --------------------------------------------------------------- */

typedef struct PtList { int n, cap; float *p; } PtList;

static void pt_add(PtList *l, float x, float y) {
  int cap2 = l->cap * 2;
  l->p = xgrow(l->p, &cap2, 2 * l->n + 2, sizeof *l->p);
  l->cap = cap2 / 2;
  l->p[2 * l->n] = x;
  l->p[2 * l->n + 1] = y;
  l->n++;
}

typedef struct Linker {
  const SilPieces *ps;
  EndIndex ix;
  int *stroke;             /* per piece: the stroke (from 1) it went into, 0 = unused */
  int cur;                 /* the stroke being grown */
  int *mine, nmine, cap_mine;   /* its pieces */
} Linker;

/* A stroke whose pieces all end within this many reference pixels of the
** ends of earlier strokes' pieces retraces an outline already painted
** (edges that coincide on the screen, like a sphere's rings near a pole
** on its outline, all visible at their ends) and is left out. */
#define SIL_RETRACE_PX 1.0f

static void take(Linker *L, int piece) {
  L->stroke[piece] = L->cur;
  L->mine = xgrow(L->mine, &L->cap_mine, L->nmine + 1, sizeof *L->mine);
  L->mine[L->nmine++] = piece;
}

/* Is a piece end of an earlier stroke within SIL_RETRACE_PX of (x, y)? */
static int earlier_end_near(const Linker *L, float x, float y) {
  const EndIndex *ix = &L->ix;
  int cx = (int)floorf(x / ix->cell), cy = (int)floorf(y / ix->cell);
  for (int gy = cy - 1; gy <= cy + 1; gy++) {
    int k = lower_bound(ix, cell_key(ix, cx - 1, gy));
    long long last = cell_key(ix, cx + 1, gy);
    for (; k < ix->n && ix->e[k].key <= last; k++) {
      int e = ix->e[k].end, s = L->stroke[e >> 1];
      if (s <= 0 || s >= L->cur) continue;
      float ex, ey;
      end_xy(L->ps, e, &ex, &ey);
      if ((ex - x) * (ex - x) + (ey - y) * (ey - y) <= SIL_RETRACE_PX * SIL_RETRACE_PX) return 1;
    }
  }
  return 0;
}

/* Does the stroke being grown retrace earlier ones all along? */
static int retraces(const Linker *L) {
  for (int j = 0; j < L->nmine; j++) {
    const SilPiece *p = &L->ps->p[L->mine[j]];
    if (!earlier_end_near(L, p->x0, p->y0) || !earlier_end_near(L, p->x1, p->y1)) return 0;
  }
  return 1;
}

/* A brush stroke does not double back: a piece that would turn it by more
** than this (the cosine of 150 degrees) is left for another stroke. Edges
** that coincide on the screen (a sphere's rings near a pole on its
** outline, both visible at their ends) would otherwise retrace the outline
** backwards, the brush pressing on its inner side. */
#define SIL_MAX_TURN_COS (-0.866f)

/* The next piece for a stroke of object obj whose end is (x, y), heading
** (dx, dy) (unit, or zero): of the unused piece ends within r of it that
** do not double the stroke back, the one whose piece turns it least
** (ties: the nearer, then the lower piece, then its start), or -1. Where
** a fan of silhouette edges meets (a pole, a cusp) the stroke so keeps to
** its course. */
static int next_end(const Linker *L, int obj, float x, float y, float dx, float dy, float r) {
  const EndIndex *ix = &L->ix;
  int cx = (int)floorf(x / ix->cell), cy = (int)floorf(y / ix->cell);
  int best = -1;
  float bd = 0, bc = -2;
  for (int gy = cy - 1; gy <= cy + 1; gy++) {
    int k = lower_bound(ix, cell_key(ix, cx - 1, gy));
    long long last = cell_key(ix, cx + 1, gy);
    for (; k < ix->n && ix->e[k].key <= last; k++) {
      int e = ix->e[k].end;
      if (L->stroke[e >> 1] || L->ps->p[e >> 1].obj != obj) continue;
      float ex, ey, fx, fy;
      end_xy(L->ps, e, &ex, &ey);
      float d = (ex - x) * (ex - x) + (ey - y) * (ey - y);
      if (d > r * r) continue;
      end_xy(L->ps, e ^ 1, &fx, &fy);   /* where the piece takes the stroke */
      float len = hypotf(fx - ex, fy - ey);
      float c = len > 0 ? ((fx - ex) * dx + (fy - ey) * dy) / len : 0;
      if ((dx != 0 || dy != 0) && c < SIL_MAX_TURN_COS) continue;
      if (best < 0 || c > bc || (c == bc && (d < bd || (d == bd && e < best)))) {
        best = e;
        bc = c;
        bd = d;
      }
    }
  }
  return best;
}

/* The unit direction from (ax, ay) to (bx, by), or zero. */
static void heading(float ax, float ay, float bx, float by, float *dx, float *dy) {
  float l = hypotf(bx - ax, by - ay);
  *dx = l > 0 ? (bx - ax) / l : 0;
  *dy = l > 0 ? (by - ay) / l : 0;
}

/* Grow one end of a stroke from (x, y), heading (dx, dy): append the far
** end of each piece linked there to l; *agree gains the length of the
** sided pieces that run along the stroke (at_end: growing at the stroke's
** end, so a piece met at its start runs along) and loses that of those
** that run against it. */
static void grow(Linker *L, int obj, float x, float y, float dx, float dy, float r, int at_end, PtList *l,
                 double *agree) {
  for (;;) {
    int e = next_end(L, obj, x, y, dx, dy, r);
    if (e < 0) return;
    const SilPiece *p = &L->ps->p[e >> 1];
    take(L, e >> 1);
    float ex, ey;
    end_xy(L->ps, e, &ex, &ey);
    end_xy(L->ps, e ^ 1, &x, &y);
    heading(ex, ey, x, y, &dx, &dy);
    pt_add(l, x, y);
    if (p->side) {
      double len = hypot(p->x1 - p->x0, p->y1 - p->y0);
      int along = at_end ? (e & 1) == 0 : (e & 1) == 1;
      *agree += along ? len : -len;
    }
  }
}

/* The stroke seeded by piece i: its points into out, reversed when its
** sided pieces mostly run against it; nothing when it retraces earlier
** strokes. */
static void link_from(Linker *L, int i, float r, PtList *back, PtList *front, LinePolys *out) {
  const SilPiece *p = &L->ps->p[i];
  L->cur++;
  L->nmine = 0;
  take(L, i);
  back->n = front->n = 0;
  double agree = p->side ? hypot(p->x1 - p->x0, p->y1 - p->y0) : 0;
  float dx, dy;
  heading(p->x0, p->y0, p->x1, p->y1, &dx, &dy);
  grow(L, p->obj, p->x1, p->y1, dx, dy, r, 1, back, &agree);
  grow(L, p->obj, p->x0, p->y0, -dx, -dy, r, 0, front, &agree);
  if (retraces(L)) return;
  int n = front->n + 2 + back->n;
  float *pts = xmalloc((size_t)n * 2 * sizeof *pts);
  int k = 0;
  for (int j = front->n - 1; j >= 0; j--, k++) { pts[2 * k] = front->p[2 * j]; pts[2 * k + 1] = front->p[2 * j + 1]; }
  pts[2 * k] = p->x0; pts[2 * k + 1] = p->y0; k++;
  pts[2 * k] = p->x1; pts[2 * k + 1] = p->y1; k++;
  for (int j = 0; j < back->n; j++, k++) { pts[2 * k] = back->p[2 * j]; pts[2 * k + 1] = back->p[2 * j + 1]; }
  if (agree < 0)
    for (int a = 0, b = n - 1; a < b; a++, b--) {
      float tx = pts[2 * a], ty = pts[2 * a + 1];
      pts[2 * a] = pts[2 * b]; pts[2 * a + 1] = pts[2 * b + 1];
      pts[2 * b] = tx; pts[2 * b + 1] = ty;
    }
  line_polys_append(out, pts, n, p->obj);
  free(pts);
}

void sil_link(LinePolys *out, const SilPieces *pieces, const LineEdges *edges, double px_scale) {
  if (pieces->n == 0) return;
  Linker L = {pieces, {0, 0, NULL, 0}, xcalloc((size_t)pieces->n, sizeof(int)), 0, NULL, 0, 0};
  float cell = 1;   /* a cell at least as wide as any object's link distance */
  for (int o = 0; o < edges->nobj; o++)
    if (edges->obj[o].lines && edges->obj[o].lines->link_distance * px_scale > cell)
      cell = (float)(edges->obj[o].lines->link_distance * px_scale);
  index_build(&L.ix, pieces, cell);
  PtList back = {0, 0, NULL}, front = {0, 0, NULL};
  for (int i = 0; i < pieces->n; i++) {
    if (L.stroke[i]) continue;
    float r = (float)(edges->obj[pieces->p[i].obj].lines->link_distance * px_scale);
    link_from(&L, i, r, &back, &front, out);
  }
  free(back.p);
  free(front.p);
  free(L.stroke);
  free(L.mine);
  free(L.ix.e);
}
