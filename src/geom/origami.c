/*
** Flat origami geometry: faces from the crease pattern, the folded state by
** reflection, the overlap relation (Mitani §4, the OR matrix), and the
** checks `sumi check` runs on them (antisymmetry, overlapping faces with
** no order, orders for faces that do not overlap, Kawasaki and Maekawa).
**
** Written bottom-up: plane maps, the edge table, the planar graph, faces,
** folding, the relation, overlaps, checks, and last the public entries.
*/
#include "origami.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"
#include "origami_layers.h"

#define PI 3.14159265358979323846

/* Real crease patterns (drawn in ORIPA and the like, for the solver) are
** off by up to ~1e-4 rad at a vertex; a pattern written out by hand or by a
** script is exact. */
#define KAWASAKI_TOL 1e-6
#define KAWASAKI_TOL_SOLVER 1e-2

/* ---- plane maps -------------------------------------------------------- */

static OrigamiXf xf_identity(void) {
  OrigamiXf r = {{1, 0, 0, 0, 1, 0}};
  return r;
}

static Vec2 xf_apply(const OrigamiXf *t, Vec2 p) {
  Vec2 r = {t->a[0] * p.x + t->a[1] * p.y + t->a[2], t->a[3] * p.x + t->a[4] * p.y + t->a[5]};
  return r;
}

/* a * b: applies b first. */
static OrigamiXf xf_mul(const OrigamiXf *a, const OrigamiXf *b) {
  OrigamiXf r;
  r.a[0] = a->a[0] * b->a[0] + a->a[1] * b->a[3];
  r.a[1] = a->a[0] * b->a[1] + a->a[1] * b->a[4];
  r.a[2] = a->a[0] * b->a[2] + a->a[1] * b->a[5] + a->a[2];
  r.a[3] = a->a[3] * b->a[0] + a->a[4] * b->a[3];
  r.a[4] = a->a[3] * b->a[1] + a->a[4] * b->a[4];
  r.a[5] = a->a[3] * b->a[2] + a->a[4] * b->a[5] + a->a[5];
  return r;
}

static double xf_det(const OrigamiXf *t) { return t->a[0] * t->a[4] - t->a[1] * t->a[3]; }

/* Reflection across the line through p and q (p != q). */
static OrigamiXf xf_reflect(Vec2 p, Vec2 q) {
  double dx = q.x - p.x, dy = q.y - p.y, l2 = dx * dx + dy * dy;
  double c = (dx * dx - dy * dy) / l2, s = 2 * dx * dy / l2;   /* cos 2θ, sin 2θ */
  OrigamiXf r = {{c, s, 0, s, -c, 0}};
  /* fix p: x' = R (x - p) + p */
  r.a[2] = p.x - (c * p.x + s * p.y);
  r.a[5] = p.y - (s * p.x - c * p.y);
  return r;
}

static double cross2(Vec2 o, Vec2 a, Vec2 b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

static double dist2(Vec2 a, Vec2 b) { return (a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y); }

double origami_poly_area2(const Vec2 *p, const int *idx, int n) {
  double a = 0;
  for (int k = 0; k < n; k++) {
    Vec2 u = p[idx[k]], v = p[idx[(k + 1) % n]];
    a += u.x * v.y - v.x * u.y;
  }
  return a;
}

/* qsort that accepts an empty (possibly NULL) array. */
static void sort_n(void *base, size_t n, size_t size, int (*cmp)(const void *, const void *)) {
  if (n > 1) qsort(base, n, size, cmp);
}

/* ---- edge table: undirected edge (u, v) -> a value -------------------- */

typedef struct EdgeKey { uint64_t key; int val; } EdgeKey;

static uint64_t edge_key(int u, int v) {
  unsigned lo = (unsigned)(u < v ? u : v), hi = (unsigned)(u < v ? v : u);
  return ((uint64_t)lo << 32) | hi;
}

static int cmp_edgekey(const void *a, const void *b) {
  const EdgeKey *x = a, *y = b;
  if (x->key != y->key) return x->key < y->key ? -1 : 1;
  return x->val - y->val;
}

/* First entry with this key, or -1. */
static int edge_find(const EdgeKey *t, int n, uint64_t key) {
  int lo = 0, hi = n;
  while (lo < hi) {
    int mid = (lo + hi) / 2;
    if (t[mid].key < key) lo = mid + 1;
    else hi = mid;
  }
  return lo < n && t[lo].key == key ? lo : -1;
}

/* ---- build context ------------------------------------------------------ */

typedef struct Build {
  const SceneOrigami *src;
  OrigamiModel *m;
  double eps;              /* length tolerance: 1e-9 of the paper's size */
  double size;             /* paper bounding-box diagonal */
  int vcap, ccap;
  EdgeKey *face_edges;     /* every face edge (u, v) -> face * 2^20... see face_edge_table */
  int nface_edges;
  /* explicit orders, kept to report conflicts and non-overlapping pairs */
  struct Order { int upper, lower; SrcRange loc; int from_matrix; } *orders;
  int norders, ordercap;
  /* vertices made by splitting creases: on original crease a-b at t */
  struct SplitOrigin { int a, b; double t; } *split_origin;
  int nsplit_origin, split_origin_cap;
} Build;

/* A location to report: the part's own, or the block's when it has none. */
static SrcRange at(const Build *b, SrcRange r) { return r.file >= 0 ? r : b->src->loc; }

static SrcRange vert_at(const Build *b, int v) {
  return at(b, b->m->vert_loc ? b->m->vert_loc[v] : src_none());
}

static SrcRange face_at(const Build *b, int f) {
  return at(b, b->m->face_loc ? b->m->face_loc[f] : src_none());
}


static int add_vertex(Build *b, Vec2 p, SrcRange loc) {
  OrigamiModel *m = b->m;
  m->paper = xgrow(m->paper, &b->vcap, m->nverts + 1, sizeof *m->paper);
  m->vert_loc = xrealloc(m->vert_loc, (size_t)b->vcap * sizeof *m->vert_loc);
  m->paper[m->nverts] = p;
  m->vert_loc[m->nverts] = loc;
  return m->nverts++;
}

/* ---- planar graph: split crossing creases ------------------------------ */

typedef struct Split { double t; int v; } Split;
typedef struct SplitList { Split *s; int n, cap; } SplitList;

static void split_add(SplitList *l, double t, int v) {
  for (int k = 0; k < l->n; k++)
    if (l->s[k].v == v) return;
  l->s = xgrow(l->s, &l->cap, l->n + 1, sizeof *l->s);
  l->s[l->n].t = t;
  l->s[l->n].v = v;
  l->n++;
}

static int cmp_split(const void *a, const void *b) {
  const Split *x = a, *y = b;
  return x->t < y->t ? -1 : x->t > y->t;
}

typedef struct XIdx { double x; int i; } XIdx;

static int cmp_xidx(const void *a, const void *b) {
  const XIdx *p = a, *q = b;
  if (p->x != q->x) return p->x < q->x ? -1 : 1;
  return p->i - q->i;
}

/* Parameter of p's projection on segment a-b when p lies on it strictly
** inside (within eps), else -1. */
static double on_segment(Vec2 a, Vec2 b, Vec2 p, double eps) {
  double len2 = dist2(a, b);
  double d = cross2(a, b, p);
  if (d * d > eps * eps * len2) return -1;
  double t = ((p.x - a.x) * (b.x - a.x) + (p.y - a.y) * (b.y - a.y)) / len2;
  double len = sqrt(len2);
  if (t * len <= eps || (1 - t) * len <= eps) return -1;
  return t;
}

/* The vertex at p: an existing one among those added since `first`, or a new one. */
static int crossing_vertex(Build *b, int first, Vec2 p, const OrigamiCrease *c, double t) {
  for (int v = first; v < b->m->nverts; v++)
    if (dist2(b->m->paper[v], p) <= b->eps * b->eps) return v;
  b->split_origin = xgrow(b->split_origin, &b->split_origin_cap, b->nsplit_origin + 1,
                          sizeof *b->split_origin);
  b->split_origin[b->nsplit_origin++] = (struct SplitOrigin){c->a, c->b, t};
  return add_vertex(b, p, c->loc);
}

/* Record where creases i and j cross each other strictly inside both.
** Collinear overlapping creases are an error. */
static void cross_pair(Build *b, int i, int j, SplitList *sp, int first_new) {
  OrigamiModel *m = b->m;
  OrigamiCrease *ci = &m->creases[i], *cj = &m->creases[j];
  Vec2 a = m->paper[ci->a], c = m->paper[ci->b], p = m->paper[cj->a], q = m->paper[cj->b];
  double d1 = cross2(a, c, p), d2 = cross2(a, c, q);
  double d3 = cross2(p, q, a), d4 = cross2(p, q, c);
  double li = sqrt(dist2(a, c)), lj = sqrt(dist2(p, q));
  double tol_i = b->eps * li, tol_j = b->eps * lj;
  if (fabs(d1) <= tol_i && fabs(d2) <= tol_i) {          /* collinear */
    double t0 = on_segment(a, c, p, b->eps), t1 = on_segment(a, c, q, b->eps);
    double s0 = on_segment(p, q, a, b->eps), s1 = on_segment(p, q, c, b->eps);
    int same = (ci->a == cj->a && ci->b == cj->b) || (ci->a == cj->b && ci->b == cj->a);
    if (t0 >= 0 || t1 >= 0 || s0 >= 0 || s1 >= 0 || same) {
      diag_error(at(b, cj->loc), "crease %d (%d-%d) overlaps crease %d (%d-%d) along a line",
                 j, cj->a, cj->b, i, ci->a, ci->b);
      diag_note(at(b, ci->loc), "crease %d is here", i);
    }
    return;
  }
  if (!((d1 > tol_i && d2 < -tol_i) || (d1 < -tol_i && d2 > tol_i))) return;
  if (!((d3 > tol_j && d4 < -tol_j) || (d3 < -tol_j && d4 > tol_j))) return;
  double t = d3 / (d3 - d4);                               /* along a-c */
  Vec2 x = {a.x + t * (c.x - a.x), a.y + t * (c.y - a.y)};
  int v = crossing_vertex(b, first_new, x, ci, t);
  split_add(&sp[i], t, v);
  double s = d1 / (d1 - d2);                               /* along p-q */
  split_add(&sp[j], s, v);
}

/* Split every crease where another crosses it or a vertex lies on it. */
static void split_creases(Build *b) {
  OrigamiModel *m = b->m;
  int nc = m->ncreases, nv0 = m->nverts;
  SplitList *sp = xcalloc((size_t)nc, sizeof *sp);
  XIdx *cx = xmalloc((size_t)nc * sizeof *cx), *vx = xmalloc((size_t)nv0 * sizeof *vx);
  for (int i = 0; i < nc; i++) {
    Vec2 a = m->paper[m->creases[i].a], c = m->paper[m->creases[i].b];
    cx[i].x = fmin(a.x, c.x);
    cx[i].i = i;
  }
  for (int v = 0; v < nv0; v++) vx[v].x = m->paper[v].x, vx[v].i = v;
  sort_n(cx, (size_t)nc, sizeof *cx, cmp_xidx);
  sort_n(vx, (size_t)nv0, sizeof *vx, cmp_xidx);
  for (int k = 0; k < nc; k++) {                            /* crease pairs, swept along x */
    int i = cx[k].i;
    Vec2 a = m->paper[m->creases[i].a], c = m->paper[m->creases[i].b];
    double maxx = fmax(a.x, c.x) + b->eps;
    double ylo = fmin(a.y, c.y) - b->eps, yhi = fmax(a.y, c.y) + b->eps;
    for (int l = k + 1; l < nc && cx[l].x <= maxx; l++) {
      int j = cx[l].i;
      Vec2 p = m->paper[m->creases[j].a], q = m->paper[m->creases[j].b];
      if (fmax(p.y, q.y) < ylo || fmin(p.y, q.y) > yhi) continue;
      cross_pair(b, i < j ? i : j, i < j ? j : i, sp, nv0);
    }
    int lo = 0, hi = nv0;                                   /* vertices lying on crease i */
    while (lo < hi) {
      int mid = (lo + hi) / 2;
      if (vx[mid].x < cx[k].x - b->eps) lo = mid + 1;
      else hi = mid;
    }
    for (int l = lo; l < nv0 && vx[l].x <= maxx; l++) {
      int v = vx[l].i;
      if (v == m->creases[i].a || v == m->creases[i].b) continue;
      double t = on_segment(a, c, m->paper[v], b->eps);
      if (t >= 0) split_add(&sp[i], t, v);
    }
  }
  /* Replace each split crease by its pieces. */
  int ncap = nc, n = nc;
  for (int i = 0; i < nc; i++) {
    if (sp[i].n == 0) continue;
    sort_n(sp[i].s, (size_t)sp[i].n, sizeof *sp[i].s, cmp_split);
    OrigamiCrease whole = m->creases[i];
    int prev = whole.a;
    for (int k = 0; k <= sp[i].n; k++) {
      int next = k < sp[i].n ? sp[i].s[k].v : whole.b;
      OrigamiCrease piece = whole;
      piece.a = prev;
      piece.b = next;
      if (k == 0) m->creases[i] = piece;
      else {
        m->creases = xgrow(m->creases, &ncap, n + 1, sizeof *m->creases);
        m->creases[n++] = piece;
      }
      prev = next;
    }
    free(sp[i].s);
  }
  m->ncreases = n;
  b->ccap = ncap;
  free(sp);
  free(cx);
  free(vx);
}

/* ---- planar graph: trace faces ------------------------------------------ */

typedef struct HalfEdge { int from, to, crease; double angle; } HalfEdge;

static int cmp_halfedge(const void *a, const void *b) {
  const HalfEdge *x = a, *y = b;
  if (x->from != y->from) return x->from - y->from;
  if (x->angle != y->angle) return x->angle < y->angle ? -1 : 1;
  return x->to - y->to;
}

typedef struct Cycle { int *v; int n; } Cycle;

static int cmp_cycle(const void *a, const void *b) {
  const Cycle *x = a, *y = b;
  for (int k = 0; k < x->n && k < y->n; k++)
    if (x->v[k] != y->v[k]) return x->v[k] - y->v[k];
  return x->n - y->n;
}

/* Drop creases given twice; a crease given twice with different
** assignments is an error. */
static void dedupe_creases(Build *b) {
  OrigamiModel *m = b->m;
  EdgeKey *t = xmalloc((size_t)m->ncreases * sizeof *t);
  for (int i = 0; i < m->ncreases; i++) t[i].key = edge_key(m->creases[i].a, m->creases[i].b), t[i].val = i;
  sort_n(t, (size_t)m->ncreases, sizeof *t, cmp_edgekey);
  unsigned char *drop = xcalloc((size_t)m->ncreases, 1);
  for (int k = 1; k < m->ncreases; k++) {
    if (t[k].key != t[k - 1].key) continue;
    int first = t[k - 1].val, i = t[k].val;
    drop[i] = 1;
    if (m->creases[i].assignment != m->creases[first].assignment) {
      diag_error(at(b, m->creases[i].loc), "crease %d-%d is given twice, as '%c' and as '%c'",
                 m->creases[i].a, m->creases[i].b, m->creases[first].assignment,
                 m->creases[i].assignment);
      diag_note(at(b, m->creases[first].loc), "first given here");
    }
  }
  int n = 0;
  for (int i = 0; i < m->ncreases; i++)
    if (!drop[i]) m->creases[n++] = m->creases[i];
  m->ncreases = n;
  free(drop);
  free(t);
}

/* Rotate a cycle so it starts at its smallest vertex. */
static void cycle_canonical(int *v, int n) {
  int k0 = 0;
  for (int k = 1; k < n; k++)
    if (v[k] < v[k0]) k0 = k;
  int *tmp = xmalloc((size_t)n * sizeof *tmp);
  for (int k = 0; k < n; k++) tmp[k] = v[(k0 + k) % n];
  memcpy(v, tmp, (size_t)n * sizeof *v);
  free(tmp);
}

/* Half-edges sorted around each vertex by angle, with their twins. */
typedef struct Graph {
  HalfEdge *h;
  int nh;
  int *first;        /* first[v] .. first[v + 1]: half-edges leaving v */
  EdgeKey *dir;      /* directed (from, to) -> half-edge */
} Graph;

static Graph graph_build(const OrigamiModel *m) {
  Graph g;
  g.nh = 2 * m->ncreases;
  g.h = xmalloc((size_t)(g.nh ? g.nh : 1) * sizeof *g.h);
  for (int i = 0; i < m->ncreases; i++) {
    int u = m->creases[i].a, v = m->creases[i].b;
    Vec2 pu = m->paper[u], pv = m->paper[v];
    g.h[2 * i] = (HalfEdge){u, v, i, atan2(pv.y - pu.y, pv.x - pu.x)};
    g.h[2 * i + 1] = (HalfEdge){v, u, i, atan2(pu.y - pv.y, pu.x - pv.x)};
  }
  sort_n(g.h, (size_t)g.nh, sizeof *g.h, cmp_halfedge);
  g.first = xmalloc((size_t)(m->nverts + 1) * sizeof *g.first);
  for (int v = 0, k = 0; v <= m->nverts; v++) {
    while (k < g.nh && g.h[k].from < v) k++;
    g.first[v] = k;
  }
  g.dir = xmalloc((size_t)(g.nh ? g.nh : 1) * sizeof *g.dir);
  for (int k = 0; k < g.nh; k++)
    g.dir[k].key = ((uint64_t)(unsigned)g.h[k].from << 32) | (unsigned)g.h[k].to, g.dir[k].val = k;
  sort_n(g.dir, (size_t)g.nh, sizeof *g.dir, cmp_edgekey);
  return g;
}

static void graph_free(Graph *g) {
  free(g->h);
  free(g->first);
  free(g->dir);
}

/* The half-edge after e along the face on e's left: at e's head, the one
** just clockwise from e's twin. */
static int graph_next(const Graph *g, int e) {
  int v = g->h[e].to;
  uint64_t tk = ((uint64_t)(unsigned)v << 32) | (unsigned)g->h[e].from;
  int twin = g->dir[edge_find(g->dir, g->nh, tk)].val;
  int deg = g->first[v + 1] - g->first[v];
  return g->first[v] + (twin - g->first[v] + deg - 1) % deg;
}

/* Move the traced cycles into the model's face arrays, in canonical order. */
static void store_faces(OrigamiModel *m, Cycle *cyc, int ncyc) {
  sort_n(cyc, (size_t)ncyc, sizeof *cyc, cmp_cycle);
  int total = 0;
  for (int f = 0; f < ncyc; f++) total += cyc[f].n;
  m->nfaces = ncyc;
  m->face_start = xmalloc((size_t)(ncyc + 1) * sizeof(int));
  m->face_index = xmalloc((size_t)(total ? total : 1) * sizeof(int));
  m->face_loc = xmalloc((size_t)(ncyc ? ncyc : 1) * sizeof(SrcRange));
  for (int f = 0, k = 0; f < ncyc; f++) {
    m->face_start[f] = k;
    memcpy(m->face_index + k, cyc[f].v, (size_t)cyc[f].n * sizeof(int));
    k += cyc[f].n;
    free(cyc[f].v);
  }
  m->face_start[ncyc] = total;
}

/* Faces of the planar graph of the creases: each bounded cycle traced with
** the face on its left (cycles winding clockwise are outer boundaries).
** Returns 0 after an error. */
static int trace_faces(Build *b) {
  OrigamiModel *m = b->m;
  Graph g = graph_build(m);
  unsigned char *used = xcalloc((size_t)g.nh + 1, 1);
  int *buf = xmalloc((size_t)(g.nh + 1) * sizeof *buf);
  Cycle *cyc = NULL;
  int ncyc = 0, cyccap = 0, ok = 1;
  for (int s = 0; s < g.nh; s++) {
    int n = 0, dangling = -1;
    for (int e = s; !used[e]; e = graph_next(&g, e)) {
      used[e] = 1;
      buf[n++] = g.h[e].from;
      if (g.first[g.h[e].to + 1] - g.first[g.h[e].to] == 1) dangling = g.h[e].crease;
    }
    if (n == 0 || origami_poly_area2(m->paper, buf, n) <= 0) continue;   /* an outer boundary */
    if (dangling >= 0) {
      OrigamiCrease *c = &m->creases[dangling];
      diag_error(at(b, c->loc), "crease %d-%d ends inside a face (every crease must reach another "
                 "crease or the paper's edge)", c->a, c->b);
      ok = 0;
      continue;
    }
    cyc = xgrow(cyc, &cyccap, ncyc + 1, sizeof *cyc);
    cyc[ncyc].v = xmalloc((size_t)n * sizeof(int));
    memcpy(cyc[ncyc].v, buf, (size_t)n * sizeof(int));
    cyc[ncyc].n = n;
    cycle_canonical(cyc[ncyc].v, n);
    ncyc++;
  }
  store_faces(m, cyc, ncyc);
  free(cyc);
  free(buf);
  free(used);
  graph_free(&g);
  if (ok && ncyc == 0) {
    diag_error(b->src->loc, "the creases enclose no face (the paper needs a closed boundary)");
    ok = 0;
  }
  return ok;
}

/* ---- faces ---------------------------------------------------------------- */

/* Copy faces given in the block; reverse clockwise ones. */
static int copy_faces(Build *b) {
  const SceneOrigami *s = b->src;
  OrigamiModel *m = b->m;
  int ok = 1;
  m->nfaces = s->nfaces;
  m->face_start = xmalloc((size_t)(s->nfaces + 1) * sizeof(int));
  memcpy(m->face_start, s->face_start, (size_t)(s->nfaces + 1) * sizeof(int));
  int total = s->face_start[s->nfaces];
  m->face_index = xmalloc((size_t)(total ? total : 1) * sizeof(int));
  memcpy(m->face_index, s->face_index, (size_t)total * sizeof(int));
  m->face_loc = xmalloc((size_t)s->nfaces * sizeof(SrcRange));
  for (int f = 0; f < s->nfaces; f++) {
    m->face_loc[f] = s->face_loc ? s->face_loc[f] : src_none();
    int *v = m->face_index + m->face_start[f], n = m->face_start[f + 1] - m->face_start[f];
    if (n < 3) {
      diag_error(face_at(b, f), "face %d has %d vertices; a face needs at least 3", f, n);
      ok = 0;
      continue;
    }
    int bad = 0;
    for (int k = 0; k < n; k++) {
      if (v[k] < 0 || v[k] >= s->nverts) {
        diag_error(face_at(b, f), "face %d: vertex %d does not exist (the paper has %d)", f, v[k],
                   s->nverts);
        bad = 1;
      } else if (v[k] == v[(k + 1) % n]) {
        diag_error(face_at(b, f), "face %d repeats vertex %d", f, v[k]);
        bad = 1;
      }
    }
    if (bad) { ok = 0; continue; }
    double a2 = origami_poly_area2(m->paper, v, n);
    /* the solver's real patterns hold slivers of 1e-11 of the paper */
    double no_area = b->src->overlap_auto ? b->eps * b->eps : b->eps * b->size;
    if (fabs(a2) <= no_area) {
      diag_error(face_at(b, f), "face %d has no area on the paper", f);
      ok = 0;
    } else if (a2 < 0) {
      for (int k = 0; k < n / 2; k++) {
        int t = v[k];
        v[k] = v[n - 1 - k];
        v[n - 1 - k] = t;
      }
    }
  }
  return ok;
}

/* Face edges (u, v) -> face * 65536 + corner... kept as two ints: val =
** index into face_index (the corner whose edge leaves it). */
static void face_edge_table(Build *b) {
  OrigamiModel *m = b->m;
  int total = m->face_start[m->nfaces];
  b->face_edges = xmalloc((size_t)(total ? total : 1) * sizeof *b->face_edges);
  for (int f = 0; f < m->nfaces; f++)
    for (int k = m->face_start[f]; k < m->face_start[f + 1]; k++) {
      int next = k + 1 < m->face_start[f + 1] ? k + 1 : m->face_start[f];
      b->face_edges[k].key = edge_key(m->face_index[k], m->face_index[next]);
      b->face_edges[k].val = k;
    }
  b->nface_edges = total;
  sort_n(b->face_edges, (size_t)total, sizeof *b->face_edges, cmp_edgekey);
}

static int corner_face(const OrigamiModel *m, int k) {
  int lo = 0, hi = m->nfaces - 1;
  while (lo < hi) {
    int mid = (lo + hi + 1) / 2;
    if (m->face_start[mid] <= k) lo = mid;
    else hi = mid - 1;
  }
  return lo;
}

static int corner_next(const OrigamiModel *m, int k) {
  int f = corner_face(m, k);
  return k + 1 < m->face_start[f + 1] ? k + 1 : m->face_start[f];
}

/* Neighbour corner across the edge leaving corner k, or -1. */
static int corner_twin(const Build *b, int k) {
  const OrigamiModel *m = b->m;
  uint64_t key = edge_key(m->face_index[k], m->face_index[corner_next(m, k)]);
  int e = edge_find(b->face_edges, b->nface_edges, key);
  for (; e >= 0 && e < b->nface_edges && b->face_edges[e].key == key; e++)
    if (b->face_edges[e].val != k) return b->face_edges[e].val;
  return -1;
}

/* Assign each face edge its crease; check the faces tile the paper
** consistently (an edge has at most two faces, running opposite ways). */
static int link_faces(Build *b) {
  OrigamiModel *m = b->m;
  int ok = 1, total = m->face_start[m->nfaces];
  EdgeKey *ct = xmalloc((size_t)(m->ncreases ? m->ncreases : 1) * sizeof *ct);
  for (int i = 0; i < m->ncreases; i++) ct[i].key = edge_key(m->creases[i].a, m->creases[i].b), ct[i].val = i;
  sort_n(ct, (size_t)m->ncreases, sizeof *ct, cmp_edgekey);
  m->face_crease = xmalloc((size_t)(total ? total : 1) * sizeof(int));
  for (int e = 0; e < b->nface_edges;) {
    int e2 = e;
    while (e2 < b->nface_edges && b->face_edges[e2].key == b->face_edges[e].key) e2++;
    int k0 = b->face_edges[e].val;
    int f0 = corner_face(m, k0), u = m->face_index[k0], v = m->face_index[corner_next(m, k0)];
    int c = edge_find(ct, m->ncreases, b->face_edges[e].key);
    if (e2 - e > 2) {
      int f2 = corner_face(m, b->face_edges[e + 2].val);
      diag_error(face_at(b, f2), "edge %d-%d belongs to more than two faces (%d, %d, %d, ...)", u, v,
                 f0, corner_face(m, b->face_edges[e + 1].val), f2);
      ok = 0;
    } else if (e2 - e == 2) {
      int k1 = b->face_edges[e + 1].val, f1 = corner_face(m, k1);
      if (m->face_index[k1] == u) {
        diag_error(face_at(b, f1), "faces %d and %d overlap on the paper (both run along edge %d-%d "
                   "the same way)", f0, f1, u, v);
        ok = 0;
      } else if (c < 0) {
        diag_error(face_at(b, f1), "edge %d-%d between faces %d and %d is not a crease; add it to "
                   "`creases` with M, V or F", u, v, f0, f1);
        ok = 0;
      }
    }
    for (int k = e; k < e2; k++) m->face_crease[b->face_edges[k].val] = c >= 0 ? ct[c].val : -1;
    e = e2;
  }
  free(ct);
  return ok;
}

/* Ear-clipping triangulation of every face (paper CCW). */
static void triangulate(OrigamiModel *m) {
  int cap = 0;
  m->ntris = 0;
  for (int f = 0; f < m->nfaces; f++) {
    int n = m->face_start[f + 1] - m->face_start[f];
    int *v = xmalloc((size_t)n * sizeof *v);
    memcpy(v, m->face_index + m->face_start[f], (size_t)n * sizeof *v);
    while (n >= 3) {
      int ear = -1;
      for (int k = 0; k < n && ear < 0; k++) {
        Vec2 a = m->paper[v[(k + n - 1) % n]], c = m->paper[v[k]], d = m->paper[v[(k + 1) % n]];
        if (cross2(a, c, d) <= 0) continue;                  /* reflex or flat corner */
        int inside = 0;
        for (int l = 0; l < n && !inside; l++) {
          if (l == k || l == (k + 1) % n || l == (k + n - 1) % n) continue;
          Vec2 p = m->paper[v[l]];
          inside = cross2(a, c, p) > 0 && cross2(c, d, p) > 0 && cross2(d, a, p) > 0;
        }
        if (!inside) ear = k;
      }
      if (ear < 0) ear = 1 % n;                              /* degenerate: cut any corner */
      m->tri = xgrow(m->tri, &cap, m->ntris + 1, sizeof *m->tri);
      m->tri_face = xrealloc(m->tri_face, (size_t)cap * sizeof *m->tri_face);
      m->tri[m->ntris][0] = v[(ear + n - 1) % n];
      m->tri[m->ntris][1] = v[ear];
      m->tri[m->ntris][2] = v[(ear + 1) % n];
      m->tri_face[m->ntris++] = f;
      memmove(v + ear, v + ear + 1, (size_t)(n - ear - 1) * sizeof *v);
      n--;
    }
    free(v);
  }
}

/* ---- folding ---------------------------------------------------------- */

/* A face to reach across the edge u-v from face `from`, longest edges first. */
typedef struct Reach { double len2; int face, from, u, v; } Reach;

static int reach_before(const Reach *a, const Reach *b) {
  if (a->len2 != b->len2) return a->len2 > b->len2;
  return a->face < b->face;
}

static void reach_push(Reach *h, int *n, Reach r) {
  int i = (*n)++;
  for (; i > 0 && reach_before(&r, &h[(i - 1) / 2]); i = (i - 1) / 2) h[i] = h[(i - 1) / 2];
  h[i] = r;
}

static Reach reach_pop(Reach *h, int *n) {
  Reach top = h[0], last = h[--*n];
  int i = 0;
  for (;;) {
    int c = 2 * i + 1;
    if (c >= *n) break;
    if (c + 1 < *n && reach_before(&h[c + 1], &h[c])) c++;
    if (!reach_before(&h[c], &last)) break;
    h[i] = h[c];
    i = c;
  }
  if (*n > 0) h[i] = last;
  return top;
}

/* Faces are reached across their longest edges first (a maximum spanning
** tree by length): on a drawn crease pattern, whose angles are a little
** off, a long edge carries the least error into the next face. */
int origami_reflect(int nverts, const Vec2 *from, int nfaces, const int *face_start,
                    const int *face_index, int root,
                    int (*fold_edge)(void *user, int fa, int fb, int u, int v), void *user,
                    double tol, Vec2 *to, OrigamiXf *xf_out, int *bad_vertex) {
  int total = face_start[nfaces];
  EdgeKey *t = xmalloc((size_t)(total ? total : 1) * sizeof *t);
  int *cf = xmalloc((size_t)(total ? total : 1) * sizeof *cf);
  for (int f = 0; f < nfaces; f++)
    for (int k = face_start[f]; k < face_start[f + 1]; k++) {
      int next = k + 1 < face_start[f + 1] ? k + 1 : face_start[f];
      t[k].key = edge_key(face_index[k], face_index[next]);
      t[k].val = k;
      cf[k] = f;
    }
  sort_n(t, (size_t)total, sizeof *t, cmp_edgekey);
  OrigamiXf *xf = xmalloc((size_t)(nfaces ? nfaces : 1) * sizeof *xf);
  unsigned char *seen = xcalloc((size_t)(nfaces ? nfaces : 1), 1);
  unsigned char *placed = xcalloc((size_t)(nverts ? nverts : 1), 1);
  Reach *heap = xmalloc((size_t)(total + 2) * sizeof *heap);
  int nheap = 0, nbad = 0;
  for (int v = 0; v < nverts; v++) to[v] = from[v];
  if (bad_vertex) *bad_vertex = -1;
  if (root >= 0 && root < nfaces) reach_push(heap, &nheap, (Reach){INFINITY, root, -1, 0, 0});
  while (nheap > 0) {
    Reach r = reach_pop(heap, &nheap);
    int f = r.face;
    if (seen[f]) continue;
    seen[f] = 1;
    xf[f] = r.from < 0 ? xf_identity() : xf[r.from];
    if (r.from >= 0 && fold_edge(user, r.from, f, r.u, r.v)) {
      OrigamiXf m = xf_reflect(from[r.u], from[r.v]);
      xf[f] = xf_mul(&xf[r.from], &m);
    }
    for (int k = face_start[f]; k < face_start[f + 1]; k++) {    /* place f's vertices */
      int v = face_index[k];
      Vec2 p = xf_apply(&xf[f], from[v]);
      if (!placed[v]) { to[v] = p; placed[v] = 1; }
      else if (dist2(to[v], p) > tol * tol) {
        if (bad_vertex && nbad == 0) *bad_vertex = v;
        nbad++;
      }
    }
    for (int k = face_start[f]; k < face_start[f + 1]; k++) {    /* reach the neighbours */
      int next = k + 1 < face_start[f + 1] ? k + 1 : face_start[f];
      int u = face_index[k], v = face_index[next];
      for (int e = edge_find(t, total, edge_key(u, v)); e >= 0 && e < total && t[e].key == edge_key(u, v); e++) {
        int g = cf[t[e].val];
        if (!seen[g]) reach_push(heap, &nheap, (Reach){dist2(from[u], from[v]), g, f, u, v});
      }
    }
  }
  for (int f = 0; f < nfaces; f++)
    if (!seen[f]) xf[f] = xf_identity();
  if (xf_out) memcpy(xf_out, xf, (size_t)nfaces * sizeof *xf);
  free(heap);
  free(placed);
  free(seen);
  free(xf);
  free(cf);
  free(t);
  return nbad;
}

typedef struct FoldUser { const OrigamiModel *m; const EdgeKey *ct; int nct, fold_u; } FoldUser;

static int fold_by_crease(void *user, int fa, int fb, int u, int v) {
  const FoldUser *fu = user;
  int e = edge_find(fu->ct, fu->nct, edge_key(u, v));
  if (e < 0) return 0;
  char a = fu->m->creases[fu->ct[e].val].assignment;
  return a == 'M' || a == 'V' || (a == 'U' && fu->fold_u);
}

/* Fit the affine map taking face f's paper corners to its folded ones;
** returns the largest corner misfit. */
static double fit_face(const OrigamiModel *m, int f, OrigamiXf *out) {
  const int *v = m->face_index + m->face_start[f];
  int n = m->face_start[f + 1] - m->face_start[f];
  int i1 = 1, i2 = 2;
  double best = 0;
  for (int k = 1; k < n; k++)                               /* the widest triangle from corner 0 */
    for (int l = k + 1; l < n; l++) {
      double a = fabs(cross2(m->paper[v[0]], m->paper[v[k]], m->paper[v[l]]));
      if (a > best) best = a, i1 = k, i2 = l;
    }
  Vec2 p0 = m->paper[v[0]], p1 = m->paper[v[i1]], p2 = m->paper[v[i2]];
  Vec2 q0 = m->folded[v[0]], q1 = m->folded[v[i1]], q2 = m->folded[v[i2]];
  double ux = p1.x - p0.x, uy = p1.y - p0.y, wx = p2.x - p0.x, wy = p2.y - p0.y;
  double det = ux * wy - uy * wx;
  if (det == 0) { *out = xf_identity(); return INFINITY; }
  /* solve [a b; c d] [u w] = [q1-q0 q2-q0] */
  double ax = q1.x - q0.x, ay = q1.y - q0.y, bx = q2.x - q0.x, by = q2.y - q0.y;
  OrigamiXf t;
  t.a[0] = (ax * wy - bx * uy) / det;
  t.a[1] = (bx * ux - ax * wx) / det;
  t.a[3] = (ay * wy - by * uy) / det;
  t.a[4] = (by * ux - ay * wx) / det;
  t.a[2] = q0.x - t.a[0] * p0.x - t.a[1] * p0.y;
  t.a[5] = q0.y - t.a[3] * p0.x - t.a[4] * p0.y;
  *out = t;
  double worst = 0;
  for (int k = 0; k < n; k++) worst = fmax(worst, sqrt(dist2(xf_apply(&t, m->paper[v[k]]), m->folded[v[k]])));
  return worst;
}

/* The scale of a folded state (1 unless a FOLD writer normalised it): that
** of the widest face's map. */
static double common_scale(OrigamiModel *m) {
  double scale = 0, widest = -1;
  for (int f = 0; f < m->nfaces; f++) {
    double miss = fit_face(m, f, &m->face_xf[f]);
    double a = fabs(origami_poly_area2(m->paper, m->face_index + m->face_start[f],
                                       m->face_start[f + 1] - m->face_start[f]));
    if (isfinite(miss) && a > widest) widest = a, scale = sqrt(fabs(xf_det(&m->face_xf[f])));
  }
  return scale > 0 ? scale : 1;
}

/* Whether face f's map (already fitted, misfit miss) moves and mirrors it
** at the given scale, within 1 %. */
static int keeps_shape(const OrigamiModel *m, int f, double miss, double scale) {
  const OrigamiXf *t = &m->face_xf[f];
  double sx = hypot(t->a[0], t->a[3]) / scale, sy = hypot(t->a[1], t->a[4]) / scale;
  double shear = (t->a[0] * t->a[1] + t->a[3] * t->a[4]) / (scale * scale);
  double diam = 0;
  Vec2 p0 = m->paper[m->face_index[m->face_start[f]]];
  for (int k = m->face_start[f] + 1; k < m->face_start[f + 1]; k++)
    diam = fmax(diam, sqrt(dist2(m->paper[m->face_index[k]], p0)));
  return miss <= 1e-2 * scale * diam && fabs(sx - 1) <= 1e-2 && fabs(sy - 1) <= 1e-2 &&
         fabs(shear) <= 1e-2;
}

/* The folded state as given. FOLD writers may scale it as a whole
** (rabbit-ear's crane), and solvers leave ~1e-4 of noise (flat-folder): a
** face must keep its shape up to the common scale, within 1 %. A FOLD
** file's folded state is taken as it is: when it holds only that state,
** its crease pattern was unfolded from it and carries the noise along. */
static int fold_given(Build *b) {
  const SceneOrigami *s = b->src;
  OrigamiModel *m = b->m;
  int ok = 1;
  for (int v = 0; v < s->nverts; v++) m->folded[v] = (Vec2){s->folded[v].x, s->folded[v].y};
  for (int v = s->nverts; v < m->nverts; v++) {              /* vertices made by splitting */
    const struct SplitOrigin *o = &b->split_origin[v - s->nverts];
    Vec2 p = m->folded[o->a], q = m->folded[o->b];
    m->folded[v] = (Vec2){p.x + o->t * (q.x - p.x), p.y + o->t * (q.y - p.y)};
  }
  double scale = common_scale(m);
  for (int f = 0; f < m->nfaces; f++) {
    double miss = fit_face(m, f, &m->face_xf[f]);
    if (!s->fold_file && !keeps_shape(m, f, miss, scale)) {
      diag_error(face_at(b, f), "the folded positions change the shape of face %d (a flat fold "
                 "only moves and mirrors faces)", f);
      ok = 0;
    }
    m->flipped[f] = xf_det(&m->face_xf[f]) < 0;
  }
  return ok;
}

/* The folded state by reflecting faces across their M and V creases from
** the fixed face. */
static int fold_reflect(Build *b) {
  OrigamiModel *m = b->m;
  int ok = 1;
  for (int i = 0; i < m->ncreases && !b->src->overlap_auto; i++)
    if (m->creases[i].assignment == 'U') {
      diag_error(at(b, m->creases[i].loc), "crease %d-%d is unassigned (U): give M, V or F, or "
                 "the folded positions", m->creases[i].a, m->creases[i].b);
      ok = 0;
    }
  if (!ok) return 0;
  EdgeKey *ct = xmalloc((size_t)(m->ncreases ? m->ncreases : 1) * sizeof *ct);
  for (int i = 0; i < m->ncreases; i++) ct[i].key = edge_key(m->creases[i].a, m->creases[i].b), ct[i].val = i;
  sort_n(ct, (size_t)m->ncreases, sizeof *ct, cmp_edgekey);
  FoldUser fu = {m, ct, m->ncreases, b->src->overlap_auto};
  int bad = -1;
  int nbad = origami_reflect(m->nverts, m->paper, m->nfaces, m->face_start, m->face_index, b->src->fixed,
                             fold_by_crease, &fu, (b->src->overlap_auto ? 1e-3 : 1e-7) * b->size,
                             m->folded, m->face_xf, &bad);
  free(ct);
  if (nbad > 0) {
    diag_error(vert_at(b, bad), "the crease pattern does not fold flat: reflecting faces across "
               "their creases puts vertex %d in %d different places", bad, nbad + 1);
    ok = 0;
  }
  for (int f = 0; f < m->nfaces; f++) m->flipped[f] = xf_det(&m->face_xf[f]) < 0;
  return ok;
}

/* The folded state: given, or by reflection from the fixed face. */
static int fold(Build *b) {
  const SceneOrigami *s = b->src;
  OrigamiModel *m = b->m;
  m->folded = xmalloc((size_t)m->nverts * sizeof *m->folded);
  m->face_xf = xmalloc((size_t)m->nfaces * sizeof *m->face_xf);
  m->flipped = xcalloc((size_t)m->nfaces, 1);
  if (s->fixed < 0 || s->fixed >= m->nfaces) {
    diag_error(s->loc, "fixed face %d does not exist (there are %d faces)", s->fixed, m->nfaces);
    return 0;
  }
  return s->has_folded ? fold_given(b) : fold_reflect(b);
}

/* ---- overlaps --------------------------------------------------------- */

/* Clip convex polygon in[n] (CCW) by CCW triangle c into out (room for
** n + 3 points); returns the new count. Sutherland-Hodgman. */
static int clip_by_tri(const Vec2 *in, int n, const Vec2 c[3], Vec2 *out, Vec2 *tmp) {
  const Vec2 *src = in;
  Vec2 *dst = out;
  Vec2 *bufs[2] = {out, tmp};
  for (int e = 0; e < 3 && n > 0; e++) {
    Vec2 p = c[e], q = c[(e + 1) % 3];
    dst = bufs[e % 2];
    int m = 0;
    for (int k = 0; k < n; k++) {
      Vec2 a = src[k], b = src[(k + 1) % n];
      double da = cross2(p, q, a), db = cross2(p, q, b);
      if (da >= 0) dst[m++] = a;
      if ((da >= 0) != (db >= 0)) {
        double u = da / (da - db);
        dst[m++] = (Vec2){a.x + u * (b.x - a.x), a.y + u * (b.y - a.y)};
      }
    }
    src = dst;
    n = m;
  }
  if (src != out) memcpy(out, src, (size_t)n * sizeof *out);
  return n;
}

static double poly_area(const Vec2 *p, int n) {
  double a2 = 0;
  for (int k = 0; k < n; k++) a2 += p[k].x * p[(k + 1) % n].y - p[(k + 1) % n].x * p[k].y;
  return a2 > 0 ? a2 / 2 : 0;
}

/* Area of the intersection of two CCW triangles. */
static double tri_overlap(const Vec2 a[3], const Vec2 c[3]) {
  Vec2 out[9], tmp[9];
  return poly_area(out, clip_by_tri(a, 3, c, out, tmp));
}

/* Area of the intersection of three CCW triangles. */
static double tri_overlap3(const Vec2 a[3], const Vec2 b[3], const Vec2 c[3]) {
  Vec2 one[9], two[12], tmp[12];
  int n = clip_by_tri(a, 3, b, one, tmp);
  return n ? poly_area(two, clip_by_tri(one, n, c, two, tmp)) : 0;
}

/* Folded triangles of every face, CCW, and each face's run of them. */
typedef struct FoldTris { Vec2 (*ft)[3]; int *start, *idx; } FoldTris;

static FoldTris fold_tris(const OrigamiModel *m) {
  FoldTris r;
  int n = m->nfaces, nt = m->ntris ? m->ntris : 1;
  r.ft = xmalloc((size_t)nt * sizeof *r.ft);
  r.start = xcalloc((size_t)n + 1, sizeof *r.start);
  r.idx = xmalloc((size_t)nt * sizeof *r.idx);
  int *fill = xcalloc((size_t)n + 1, sizeof *fill);
  for (int t = 0; t < m->ntris; t++) r.start[m->tri_face[t] + 1]++;
  for (int f = 0; f < n; f++) r.start[f + 1] += r.start[f];
  for (int t = 0; t < m->ntris; t++) {
    int f = m->tri_face[t];
    r.idx[r.start[f] + fill[f]++] = t;
    for (int k = 0; k < 3; k++) r.ft[t][k] = m->folded[m->tri[t][k]];
    if (cross2(r.ft[t][0], r.ft[t][1], r.ft[t][2]) < 0) {
      Vec2 tmp = r.ft[t][1];
      r.ft[t][1] = r.ft[t][2];
      r.ft[t][2] = tmp;
    }
  }
  free(fill);
  return r;
}

static void fold_tris_free(FoldTris *r) {
  free(r->ft);
  free(r->start);
  free(r->idx);
}

typedef struct FaceBox { double x0, y0, x1, y1; int f; } FaceBox;

static int cmp_facebox(const void *a, const void *b) {
  const FaceBox *p = a, *q = b;
  if (p->x0 != q->x0) return p->x0 < q->x0 ? -1 : 1;
  return p->f - q->f;
}

static int cmp_overlap(const void *a, const void *b) {
  const OrigamiOverlap *p = a, *q = b;
  if (p->i != q->i) return p->i - q->i;
  return p->j - q->j;
}

OrigamiOverlap *origami_overlaps(const OrigamiModel *m, int *count) {
  int n = m->nfaces;
  FoldTris tr = fold_tris(m);
  Vec2 (*ft)[3] = tr.ft;
  int *tstart = tr.start, *tidx = tr.idx;
  FaceBox *box = xmalloc((size_t)(n ? n : 1) * sizeof *box);
  for (int f = 0; f < n; f++) {
    FaceBox bx = {INFINITY, INFINITY, -INFINITY, -INFINITY, f};
    for (int k = m->face_start[f]; k < m->face_start[f + 1]; k++) {
      Vec2 p = m->folded[m->face_index[k]];
      bx.x0 = fmin(bx.x0, p.x), bx.y0 = fmin(bx.y0, p.y), bx.x1 = fmax(bx.x1, p.x), bx.y1 = fmax(bx.y1, p.y);
    }
    box[f] = bx;
  }
  sort_n(box, (size_t)n, sizeof *box, cmp_facebox);
  double dx = m->fold_max.x - m->fold_min.x, dy = m->fold_max.y - m->fold_min.y;
  double min_area = 1e-8 * (dx * dx + dy * dy);
  double gap = 1e-9 * sqrt(dx * dx + dy * dy);
  OrigamiOverlap *res = NULL;
  int nres = 0, cap = 0;
  for (int a = 0; a < n; a++)
    for (int c = a + 1; c < n && box[c].x0 < box[a].x1 - gap; c++) {
      if (box[c].y0 >= box[a].y1 - gap || box[a].y0 >= box[c].y1 - gap) continue;
      int f = box[a].f, g = box[c].f;
      double area = 0;
      for (int s = tstart[f]; s < tstart[f + 1]; s++)
        for (int t = tstart[g]; t < tstart[g + 1]; t++) area += tri_overlap(ft[tidx[s]], ft[tidx[t]]);
      if (area <= min_area) continue;
      res = xgrow(res, &cap, nres + 1, sizeof *res);
      res[nres++] = (OrigamiOverlap){f < g ? f : g, f < g ? g : f, area};
    }
  sort_n(res, (size_t)nres, sizeof *res, cmp_overlap);
  free(box);
  fold_tris_free(&tr);
  *count = nres;
  return res;
}

static int overlap_find(const OrigamiOverlap *ov, int n, int i, int j) {
  OrigamiOverlap key = {i < j ? i : j, i < j ? j : i, 0};
  return n > 0 && bsearch(&key, ov, (size_t)n, sizeof *ov, cmp_overlap) != NULL;
}

/* ---- the overlap relation ------------------------------------------ */

static void set_above(OrigamiModel *m, int i, int j) {
  m->above[(size_t)i * (size_t)m->row_words + ((unsigned)j >> 6)] |= (uint64_t)1 << (j & 63);
}

static void order_add(Build *b, int upper, int lower, SrcRange loc, int from_matrix) {
  b->orders = xgrow(b->orders, &b->ordercap, b->norders + 1, sizeof *b->orders);
  b->orders[b->norders++] = (struct Order){upper, lower, loc, from_matrix};
}

/* The explicit orders: `above` pairs and the matrix rows. */
static int read_orders(Build *b) {
  const SceneOrigami *s = b->src;
  int n = b->m->nfaces, ok = 1;
  for (int k = 0; k < s->nabove; k++) {
    const OrigamiAbove *a = &s->above[k];
    if (a->upper < 0 || a->upper >= n || a->lower < 0 || a->lower >= n) {
      diag_error(at(b, a->loc), "above [%d, %d]: face %d does not exist (there are %d faces)",
                 a->upper, a->lower, (a->upper < 0 || a->upper >= n) ? a->upper : a->lower, n);
      ok = 0;
    } else if (a->upper == a->lower) {
      diag_error(at(b, a->loc), "above [%d, %d]: a face cannot lie over itself", a->upper, a->lower);
      ok = 0;
    } else order_add(b, a->upper, a->lower, a->loc, 0);
  }
  if (s->noverlap == 0) return ok;
  SrcRange ol = at(b, s->overlap_loc);
  if (s->noverlap != n) {
    diag_error(ol, "the overlap matrix has %d rows but there are %d faces", s->noverlap, n);
    return 0;
  }
  for (int i = 0; i < n; i++) {
    const char *row = s->overlap[i];
    int len = (int)strlen(row);
    if (len != n) {
      diag_error(ol, "overlap row %d has %d entries; it needs one per face (%d)", i, len, n);
      ok = 0;
      continue;
    }
    for (int j = 0; j < n; j++) {
      char c = row[j];
      if (c != 'U' && c != 'L' && c != '-') {
        diag_error(ol, "overlap row %d, column %d: '%c' is not U, L or -", i, j, c);
        ok = 0;
      } else if (i == j && c != '-') {
        diag_error(ol, "overlap row %d, column %d: a face cannot lie over or under itself "
                   "(use '-')", i, j);
        ok = 0;
      } else if (c == 'U') order_add(b, i, j, s->overlap_loc, 1);
      else if (c == 'L') order_add(b, j, i, s->overlap_loc, 1);
      if (j > i && (int)strlen(s->overlap[j]) == n) {      /* antisymmetry */
        char d = s->overlap[j][i];
        char want = c == 'U' ? 'L' : c == 'L' ? 'U' : '-';
        if ((c == 'U' || c == 'L' || c == '-') && d != want) {
          diag_error(ol, "the overlap matrix is not antisymmetric: row %d column %d is '%c' but "
                     "row %d column %d is '%c' (should be '%c')", i, j, c, j, i, d, want);
          ok = 0;
        }
      }
    }
  }
  return ok;
}

static int cmp_order(const void *a, const void *b) {
  const struct Order *x = a, *y = b;
  int xl = x->upper < x->lower ? x->upper : x->lower, yl = y->upper < y->lower ? y->upper : y->lower;
  int xh = x->upper ^ x->lower ^ xl, yh = y->upper ^ y->lower ^ yl;
  if (xl != yl) return xl - yl;
  if (xh != yh) return xh - yh;
  return x->from_matrix - y->from_matrix;
}

/* The order an M/V crease implies for the faces on its two sides, as a
** "face i over face j" pair, or 0 when the edge is not a fold. A valley
** puts each face on the side its neighbour's paper normal points to; seen
** from +z, f lies over g when s * orient(g) > 0 (s = +1 valley, -1
** mountain; orient = -1 for a face showing its back). */
static int crease_order(const Build *b, int k, int *upper, int *lower) {
  const OrigamiModel *m = b->m;
  int c = m->face_crease[k];
  if (c < 0) return 0;
  char a = m->creases[c].assignment;
  if (a != 'M' && a != 'V') return 0;
  int t = corner_twin(b, k);
  if (t < 0) return 0;
  int f = corner_face(m, k), g = corner_face(m, t);
  int s = a == 'V' ? 1 : -1, og = m->flipped[g] ? -1 : 1;
  if (m->flipped[f] == m->flipped[g]) return 0;    /* not folded against each other */
  *upper = s * og > 0 ? f : g;
  *lower = *upper == f ? g : f;
  return 1;
}

static double triple_area(const FoldTris *tr, int i, int j, int k, double enough) {
  double area = 0;
  for (int p = tr->start[i]; p < tr->start[i + 1] && area <= enough; p++)
    for (int q = tr->start[j]; q < tr->start[j + 1] && area <= enough; q++)
      for (int r = tr->start[k]; r < tr->start[k + 1] && area <= enough; r++)
        area += tri_overlap3(tr->ft[tr->idx[p]], tr->ft[tr->idx[q]], tr->ft[tr->idx[r]]);
  return area;
}

/* Orders implied through a third face: where faces i and j overlap with no
** order, and some face k lies between them (i over k over j) at a place all
** three cover, i lies over j there, hence everywhere (a pleat's outer
** layers). Repeated until nothing changes. */
static void infer_orders(OrigamiModel *m) {
  int nov;
  OrigamiOverlap *ov = origami_overlaps(m, &nov);
  int n = m->nfaces, open = 0;
  for (int k = 0; k < nov; k++) open += !origami_is_above(m, ov[k].i, ov[k].j) && !origami_is_above(m, ov[k].j, ov[k].i);
  if (open == 0) { free(ov); return; }
  int *deg = xcalloc((size_t)n + 1, sizeof *deg), *adj = xmalloc((size_t)(2 * nov + 1) * sizeof *adj);
  int *fill = xcalloc((size_t)n + 1, sizeof *fill), *mark = xmalloc((size_t)(n ? n : 1) * sizeof *mark);
  for (int k = 0; k < nov; k++) deg[ov[k].i + 1]++, deg[ov[k].j + 1]++;
  for (int f = 0; f < n; f++) deg[f + 1] += deg[f], mark[f] = -1;
  for (int k = 0; k < nov; k++) {
    adj[deg[ov[k].i] + fill[ov[k].i]++] = ov[k].j;
    adj[deg[ov[k].j] + fill[ov[k].j]++] = ov[k].i;
  }
  FoldTris tr = fold_tris(m);
  double dx = m->fold_max.x - m->fold_min.x, dy = m->fold_max.y - m->fold_min.y;
  double min_area = 1e-8 * (dx * dx + dy * dy);
  for (int changed = 1, round = 0; changed && round < 64; round++) {
    changed = 0;
    for (int e = 0; e < nov; e++) {
      int i = ov[e].i, j = ov[e].j;
      if (origami_is_above(m, i, j) || origami_is_above(m, j, i)) continue;
      for (int a = deg[i]; a < deg[i + 1]; a++) mark[adj[a]] = e;
      for (int a = deg[j]; a < deg[j + 1]; a++) {
        int k = adj[a], up = -1;
        if (mark[k] != e) continue;
        if (origami_is_above(m, i, k) && origami_is_above(m, k, j)) up = i;
        else if (origami_is_above(m, j, k) && origami_is_above(m, k, i)) up = j;
        if (up < 0 || triple_area(&tr, i, j, k, min_area) <= min_area) continue;
        set_above(m, up, up == i ? j : i);
        changed = 1;
        break;
      }
    }
  }
  fold_tris_free(&tr);
  free(mark);
  free(fill);
  free(adj);
  free(deg);
  free(ov);
}

/* `overlap auto`: the relation of the solver's state K (layer_solve.h). */
static int solve_relation(Build *b) {
  OrigamiModel *m = b->m;
  OrigamiLayers l;
  origami_layers_init(m, &l);
  char err[256];
  LayerSolver *s = layer_new(&l.in, err, sizeof err);
  int ok = s != NULL;
  if (!s) diag_error(b->src->loc, "no layer order: %s", err);
  else if (layer_conflict(s)) {
    origami_layers_report(m, &l, layer_conflict(s));
    ok = 0;
  } else {
    double total;
    long k = b->src->state;
    if (!origami_layers_pick(s, k, ORIGAMI_STATE_LIMIT, &total)) {
      if (layer_conflict(s)) origami_layers_report(m, &l, layer_conflict(s));
      else diag_error(at(b, b->src->state_loc), "state %ld does not exist: the crease pattern has %.0f "
                      "valid states (each component counted up to %d)", k, total, ORIGAMI_STATE_LIMIT);
      ok = 0;
    } else ok = origami_layers_apply(m, &l, s);
  }
  layer_free(s);
  origami_layers_free(&l);
  return ok;
}

static int build_relation(Build *b) {
  OrigamiModel *m = b->m;
  int n = m->nfaces, ok = 1;
  m->row_words = (n + 63) / 64;
  m->above = xcalloc((size_t)n * (size_t)m->row_words, sizeof *m->above);
  if (b->src->overlap_auto) return solve_relation(b);
  if (!read_orders(b)) ok = 0;
  sort_n(b->orders, (size_t)b->norders, sizeof *b->orders, cmp_order);
  for (int k = 0; k < b->norders; k++) {                     /* contradictions among them */
    struct Order *o = &b->orders[k], *p = k > 0 ? &b->orders[k - 1] : NULL;
    int same_pair = p && (o->upper ^ o->lower) == (p->upper ^ p->lower) &&
                    (o->upper == p->upper || o->upper == p->lower);
    if (same_pair && o->upper != p->upper && !(o->from_matrix && p->from_matrix)) {
      /* the matrix sorts after the pairs: report at the `above` line */
      struct Order *pair = p->from_matrix ? o : p, *other = pair == p ? o : p;
      diag_error(at(b, pair->loc), "above [%d, %d] contradicts %s", pair->upper, pair->lower,
                 other->from_matrix ? "the overlap matrix" : "another order for the same faces");
      if (!other->from_matrix) diag_note(at(b, other->loc), "the other order is here");
      ok = 0;
    }
    set_above(m, o->upper, o->lower);
  }
  int total = m->face_start[n];
  for (int k = 0; k < total; k++) {                          /* orders the creases imply */
    int up, lo;
    if (!crease_order(b, k, &up, &lo) || up != corner_face(m, k)) continue;
    if (origami_is_above(m, lo, up)) {
      char a = m->creases[m->face_crease[k]].assignment;
      int bad = -1;
      for (int o = 0; o < b->norders && bad < 0; o++)
        if (b->orders[o].upper == lo && b->orders[o].lower == up) bad = o;
      diag_error(bad >= 0 ? at(b, b->orders[bad].loc) : face_at(b, lo),
                 "the order puts face %d over face %d, but the %s crease %d-%d between them puts "
                 "%d over %d", lo, up, a == 'V' ? "valley" : "mountain",
                 m->creases[m->face_crease[k]].a, m->creases[m->face_crease[k]].b, up, lo);
      ok = 0;
    }
    set_above(m, up, lo);
  }
  for (int i = 0; i < n && ok; i++)                          /* both ways: antisymmetry */
    for (int j = i + 1; j < n; j++)
      if (origami_is_above(m, i, j) && origami_is_above(m, j, i)) {
        diag_error(face_at(b, i), "faces %d and %d are each given as lying over the other", i, j);
        ok = 0;
        break;
      }
  if (ok) infer_orders(m);
  return ok;
}

/* ---- checks ------------------------------------------------------------ */

static int above_of(void *user, int i, int j) { return origami_is_above(user, i, j); }

static const char *constraint_name(int kind) {
  static const char *names[] = {"taco-taco", "taco-tortilla", "tortilla-tortilla", "transitivity"};
  return kind >= 0 && kind < 4 ? names[kind] : kind == -1 ? "crease" : "antisymmetry";
}

/* A given relation (`above`, the matrix, faceOrders) against the layer
** solver's constraints: where it cannot be a valid stacking, say which
** constraint it breaks. A state the arrangement cannot be built for
** (noisy imported positions) is left to the other checks. */
static void check_with_solver(Build *b) {
  OrigamiModel *m = b->m;
  OrigamiLayers l;
  origami_layers_init(m, &l);
  char err[256];
  LayerSolver *s = layer_new(&l.in, err, sizeof err);
  LayerConflict c;
  long n = s ? layer_check(s, above_of, m, &c) : 0;
  if (n > 0) {
    char faces[64] = "";
    for (int i = 0, at = 0; i < c.nfaces && at < 48; i++)
      at += snprintf(faces + at, sizeof faces - (size_t)at, "%s%d", i ? ", " : "", c.faces[i]);
    SrcRange where = b->src->nabove ? at(b, b->src->above[0].loc) : at(b, b->src->overlap_loc);
    diag_error(where, "the overlap relation is not a valid stacking: it breaks the %s constraint on "
               "faces %s%s", constraint_name(c.kind), faces, n > 1 ? " (and more)" : "");
  }
  layer_free(s);
  origami_layers_free(&l);
}

/* The order written for `upper` over `lower` (an `above` line or the
** matrix), or NULL when a crease or inference made it. */
static const struct Order *written_order(const Build *b, int upper, int lower) {
  for (int k = 0; k < b->norders; k++)
    if (b->orders[k].upper == upper && b->orders[k].lower == lower) return &b->orders[k];
  return NULL;
}

/* The M/V crease between faces upper and lower that puts upper over lower,
** or -1. */
static int crease_putting(const Build *b, int upper, int lower) {
  const OrigamiModel *m = b->m;
  for (int k = m->face_start[upper]; k < m->face_start[upper + 1]; k++) {
    int up, lo;
    if (crease_order(b, k, &up, &lo) && up == upper && lo == lower) return m->face_crease[k];
  }
  return -1;
}

/* Faces i over j over k over i in one place: the error at the first of the
** three orders that was written (an `above` line), a note at each other
** one; at the face when creases and inference made them all. */
static void report_cycle(Build *b, int i, int j, int k) {
  int f[4] = {i, j, k, i};
  const struct Order *w[3];
  int first = -1;
  for (int e = 0; e < 3; e++) {
    w[e] = written_order(b, f[e], f[e + 1]);
    if (w[e] && first < 0) first = e;
  }
  diag_error(first >= 0 ? at(b, w[first]->loc) : face_at(b, i),
             "faces %d, %d and %d all cover one place, where the orders form a cycle (%d over %d "
             "over %d over %d): no folding stacks them so", i, j, k, i, j, k, i);
  for (int e = 0; e < 3; e++) {
    if (e == first) continue;
    int c = w[e] || first < 0 ? -1 : crease_putting(b, f[e], f[e + 1]);
    if (w[e]) diag_note(at(b, w[e]->loc), "%d over %d, part of the cycle, is written here", f[e], f[e + 1]);
    else if (c >= 0)
      diag_note(at(b, b->m->creases[c].loc), "%d over %d, part of the cycle: the %s crease %d-%d "
                "between them", f[e], f[e + 1], b->m->creases[c].assignment == 'V' ? "valley" : "mountain",
                b->m->creases[c].a, b->m->creases[c].b);
    else if (first >= 0)
      diag_note(face_at(b, f[e]), "%d over %d, part of the cycle, follows from the other orders",
                f[e], f[e + 1]);
  }
}

/* Three faces covering a common place must be ordered without a cycle
** there (cycles are fine between faces that never meet all at once: a
** twist's pleats). */
static void check_cycles(Build *b, const OrigamiOverlap *ov, int nov) {
  OrigamiModel *m = b->m;
  int n = m->nfaces;
  int *deg = xcalloc((size_t)n + 1, sizeof *deg), *adj = xmalloc((size_t)(2 * nov + 1) * sizeof *adj);
  for (int k = 0; k < nov; k++) deg[ov[k].i + 1]++, deg[ov[k].j + 1]++;
  for (int f = 0; f < n; f++) deg[f + 1] += deg[f];
  int *fill = xcalloc((size_t)n + 1, sizeof *fill);
  for (int k = 0; k < nov; k++) {
    adj[deg[ov[k].i] + fill[ov[k].i]++] = ov[k].j;
    adj[deg[ov[k].j] + fill[ov[k].j]++] = ov[k].i;
  }
  FoldTris tr = fold_tris(m);
  double dx = m->fold_max.x - m->fold_min.x, dy = m->fold_max.y - m->fold_min.y;
  double min_area = 1e-8 * (dx * dx + dy * dy);
  for (int i = 0; i < n && !diag_too_many(); i++)
    for (int a = deg[i]; a < deg[i + 1]; a++) {
      int j = adj[a];
      if (j < i || !origami_is_above(m, i, j)) continue;   /* i over j, i the smallest */
      for (int c = deg[j]; c < deg[j + 1]; c++) {
        int k = adj[c];
        if (k < i || !origami_is_above(m, j, k) || !origami_is_above(m, k, i)) continue;
        if (triple_area(&tr, i, j, k, min_area) > min_area) report_cycle(b, i, j, k);
      }
    }
  fold_tris_free(&tr);
  free(fill);
  free(adj);
  free(deg);
}

static void check_orders(Build *b) {
  OrigamiModel *m = b->m;
  int nov;
  OrigamiOverlap *ov = origami_overlaps(m, &nov);
  for (int k = 0; k < nov && !diag_too_many(); k++) {
    int i = ov[k].i, j = ov[k].j;
    if (origami_is_above(m, i, j) || origami_is_above(m, j, i)) continue;
    diag_error(face_at(b, i), "faces %d and %d overlap when folded (area %g) but no order is given: "
               "add `above [%d, %d];` or `above [%d, %d];`", i, j, ov[k].area, i, j, j, i);
  }
  check_cycles(b, ov, nov);
  int matrix_warned = 0;
  for (int k = 0; k < b->norders; k++) {
    struct Order *o = &b->orders[k];
    if (overlap_find(ov, nov, o->upper, o->lower)) continue;
    if (!o->from_matrix)
      diag_warning(at(b, o->loc), "above [%d, %d]: faces %d and %d do not overlap when folded",
                   o->upper, o->lower, o->upper, o->lower);
    else if (k == 0 || cmp_order(o, &b->orders[k - 1]) != 0) {   /* once per pair */
      if (matrix_warned++ < 8)
        diag_warning(at(b, o->loc), "the overlap matrix orders faces %d and %d, which do not "
                     "overlap when folded", o->upper, o->lower);
    }
  }
  if (matrix_warned > 8)
    diag_note(at(b, b->src->overlap_loc), "%d more ordered pairs of the matrix do not overlap",
              matrix_warned - 8);
  free(ov);
}

typedef struct Spoke { double angle; char a; } Spoke;

static int cmp_spoke(const void *x, const void *y) {
  const Spoke *p = x, *q = y;
  return p->angle < q->angle ? -1 : p->angle > q->angle;
}

/* Vertices on the paper's edge: on a face edge with no face across, or a
** B crease. Kawasaki and Maekawa hold only inside. */
static unsigned char *boundary_vertices(const Build *b) {
  const OrigamiModel *m = b->m;
  unsigned char *boundary = xcalloc((size_t)m->nverts, 1);
  int total = m->face_start[m->nfaces];
  for (int k = 0; k < total; k++) {
    int c = m->face_crease[k];
    if (corner_twin(b, k) < 0 || (c >= 0 && m->creases[c].assignment == 'B')) {
      boundary[m->face_index[k]] = 1;
      boundary[m->face_index[corner_next(m, k)]] = 1;
    }
  }
  return boundary;
}

static void report_maekawa(const Build *b, int v, int nm, int nv) {
  Vec2 p = b->m->paper[v];
  diag_error(vert_at(b, v), "vertex %d at [%g, %g] does not fold flat (Maekawa): %d mountain and "
             "%d valley creases meet there; they must differ by 2", v, p.x, p.y, nm, nv);
}

static void report_kawasaki(const Build *b, int v, double even, double odd) {
  Vec2 p = b->m->paper[v];
  diag_error(vert_at(b, v), "vertex %d at [%g, %g] does not fold flat (Kawasaki): alternate "
             "angles around it sum to %g° and %g°; both must be 180°", v, p.x, p.y,
             even * 180 / PI, odd * 180 / PI);
}

static double kawasaki_tol(const Build *b) {
  return b->src->overlap_auto ? KAWASAKI_TOL_SOLVER : KAWASAKI_TOL;
}

/* Kawasaki (alternate angles sum to 180°) and Maekawa (|M - V| = 2) at
** every interior vertex with folds, from the crease directions on the
** paper. Run before folding from the paper, which needs both. */
static void check_vertices_paper(Build *b) {
  OrigamiModel *m = b->m;
  unsigned char *boundary = boundary_vertices(b);
  int *deg = xcalloc((size_t)m->nverts + 1, sizeof *deg);
  for (int i = 0; i < m->ncreases; i++) deg[m->creases[i].a + 1]++, deg[m->creases[i].b + 1]++;
  for (int v = 0; v < m->nverts; v++) deg[v + 1] += deg[v];
  Spoke *sp = xmalloc((size_t)(2 * m->ncreases + 1) * sizeof *sp);
  int *fill = xcalloc((size_t)m->nverts, sizeof *fill);
  for (int i = 0; i < m->ncreases; i++) {
    OrigamiCrease *c = &m->creases[i];
    for (int e = 0; e < 2; e++) {
      int v = e ? c->b : c->a, w = e ? c->a : c->b;
      Vec2 p = m->paper[v], q = m->paper[w];
      sp[deg[v] + fill[v]++] = (Spoke){atan2(q.y - p.y, q.x - p.x), c->assignment};
    }
  }
  for (int v = 0; v < m->nverts && !diag_too_many(); v++) {
    if (boundary[v]) continue;
    Spoke *s = sp + deg[v];
    int n = 0, nm = 0, nv = 0, nu = 0;
    for (int k = 0; k < deg[v + 1] - deg[v]; k++) {
      if (s[k].a == 'M' || s[k].a == 'V' || s[k].a == 'U') s[n++] = s[k];
      nm += s[k].a == 'M', nv += s[k].a == 'V', nu += s[k].a == 'U';
    }
    if (n == 0) continue;
    if (nu == 0 && abs(nm - nv) != 2) report_maekawa(b, v, nm, nv);
    if (n % 2) continue;                                     /* Maekawa said it */
    sort_n(s, (size_t)n, sizeof *s, cmp_spoke);
    double even = 0, odd = 0;
    for (int k = 0; k < n; k++) {
      double sector = (k + 1 < n ? s[k + 1].angle : s[0].angle + 2 * PI) - s[k].angle;
      if (k % 2) odd += sector;
      else even += sector;
    }
    if (fabs(even - odd) > kawasaki_tol(b)) report_kawasaki(b, v, even, odd);
  }
  free(fill);
  free(sp);
  free(deg);
  free(boundary);
}

/* The same two theorems for a given folded state, from each face's corner
** angle in its folded position (intrinsic, so a crease pattern unfolded
** from noisy data does not add its own noise): faces around an interior
** vertex alternate between front and back up, so the corners of each kind
** sum to the same (180° on a flat paper). Solver output carries ~1e-4 of
** noise (the egg tessellation's corners sum to 359.7° at some vertices),
** hence a tolerance of 0.1° on the difference only. */
static void check_vertices_folded(Build *b) {
  OrigamiModel *m = b->m;
  unsigned char *boundary = boundary_vertices(b);
  double *front = xcalloc((size_t)m->nverts, sizeof *front), *back = xcalloc((size_t)m->nverts, sizeof *back);
  int *nm = xcalloc((size_t)m->nverts, sizeof *nm), *nv = xcalloc((size_t)m->nverts, sizeof *nv);
  for (int f = 0; f < m->nfaces; f++) {
    int s = m->face_start[f], n = m->face_start[f + 1] - s;
    for (int k = 0; k < n; k++) {
      Vec2 p = m->folded[m->face_index[s + (k + n - 1) % n]], c = m->folded[m->face_index[s + k]];
      Vec2 q = m->folded[m->face_index[s + (k + 1) % n]];
      double ex = q.x - c.x, ey = q.y - c.y, fx = p.x - c.x, fy = p.y - c.y;
      double cr = (ex * fy - ey * fx) * (m->flipped[f] ? -1 : 1), dt = ex * fx + ey * fy;
      double ang = atan2(cr, dt);
      if (ang < 0) ang += 2 * PI;
      if (m->flipped[f]) back[m->face_index[s + k]] += ang;
      else front[m->face_index[s + k]] += ang;
    }
  }
  for (int i = 0; i < m->ncreases; i++) {
    OrigamiCrease *c = &m->creases[i];
    nm[c->a] += c->assignment == 'M', nm[c->b] += c->assignment == 'M';
    nv[c->a] += c->assignment == 'V', nv[c->b] += c->assignment == 'V';
  }
  for (int v = 0; v < m->nverts && !diag_too_many(); v++) {
    if (boundary[v] || (nm[v] == 0 && nv[v] == 0)) continue;
    if (abs(nm[v] - nv[v]) != 2) report_maekawa(b, v, nm[v], nv[v]);
    if (fabs(front[v] - back[v]) > 2e-3) report_kawasaki(b, v, front[v], back[v]);
  }
  free(nv);
  free(nm);
  free(back);
  free(front);
  free(boundary);
}

/* ---- public entries -------------------------------------------------- */

static int copy_paper(Build *b) {
  const SceneOrigami *s = b->src;
  OrigamiModel *m = b->m;
  if (s->nverts > ORIGAMI_MAX_VERTS || s->ncreases > ORIGAMI_MAX_CREASES ||
      s->nfaces > ORIGAMI_MAX_FACES) {
    diag_error(s->loc, "origami too large: %d vertices, %d creases, %d faces (limits are "
               "ORIGAMI_MAX_VERTS %d, ORIGAMI_MAX_CREASES %d, ORIGAMI_MAX_FACES %d)",
               s->nverts, s->ncreases, s->nfaces, ORIGAMI_MAX_VERTS, ORIGAMI_MAX_CREASES,
               ORIGAMI_MAX_FACES);
    return 0;
  }
  for (int v = 0; v < s->nverts; v++)
    add_vertex(b, s->verts[v], s->vert_loc ? s->vert_loc[v] : src_none());
  Vec2 lo = {INFINITY, INFINITY}, hi = {-INFINITY, -INFINITY};
  for (int v = 0; v < s->nverts; v++) {
    Vec2 p = s->verts[v];
    if (!isfinite(p.x) || !isfinite(p.y)) {
      diag_error(vert_at(b, v), "vertex %d is not a finite point", v);
      return 0;
    }
    lo.x = fmin(lo.x, p.x), lo.y = fmin(lo.y, p.y), hi.x = fmax(hi.x, p.x), hi.y = fmax(hi.y, p.y);
  }
  b->size = s->nverts ? sqrt(dist2(lo, hi)) : 1;
  if (b->size == 0) b->size = 1;
  b->eps = 1e-9 * b->size;
  int ok = 1;
  m->creases = xmalloc((size_t)(s->ncreases ? s->ncreases : 1) * sizeof *m->creases);
  b->ccap = s->ncreases;
  for (int i = 0; i < s->ncreases; i++) {
    OrigamiCrease c = s->creases[i];
    if (c.a < 0 || c.a >= s->nverts || c.b < 0 || c.b >= s->nverts) {
      diag_error(at(b, c.loc), "crease %d: vertex %d does not exist (the paper has %d)", i,
                 (c.a < 0 || c.a >= s->nverts) ? c.a : c.b, s->nverts);
      ok = 0;
    } else if (dist2(s->verts[c.a], s->verts[c.b]) <= b->eps * b->eps) {
      diag_error(at(b, c.loc), "crease %d joins vertex %d to %s", i, c.a,
                 c.a == c.b ? "itself" : "a vertex at the same place");
      ok = 0;
    } else if (!strchr("MVBFU", c.assignment) || !c.assignment) {
      diag_error(at(b, c.loc), "crease %d: assignment '%c' is not M, V, B, F or U", i, c.assignment);
      ok = 0;
    } else m->creases[m->ncreases++] = c;
  }
  return ok;
}

static void fold_bounds(OrigamiModel *m) {
  m->fold_min = (Vec2){INFINITY, INFINITY};
  m->fold_max = (Vec2){-INFINITY, -INFINITY};
  for (int f = 0; f < m->nfaces; f++)
    for (int k = m->face_start[f]; k < m->face_start[f + 1]; k++) {
      Vec2 p = m->folded[m->face_index[k]];
      m->fold_min.x = fmin(m->fold_min.x, p.x), m->fold_min.y = fmin(m->fold_min.y, p.y);
      m->fold_max.x = fmax(m->fold_max.x, p.x), m->fold_max.y = fmax(m->fold_max.y, p.y);
    }
  if (m->nfaces == 0) m->fold_min = m->fold_max = (Vec2){0, 0};
}

/* The model up to its folded state; with relation, also the overlap relation. */
static OrigamiModel *build(const SceneOrigami *src, int check, int relation) {
  int errors0 = diag_error_count();
  OrigamiModel *m = xcalloc(1, sizeof *m);
  Build b = {.src = src, .m = m};
  m->name = src->name ? xstrdup(src->name) : NULL;
  m->loc = src->loc;
  int ok = copy_paper(&b);
  if (ok && src->nfaces == 0) {
    split_creases(&b);
    dedupe_creases(&b);
    ok = diag_error_count() == errors0 && trace_faces(&b);
    if (ok && m->nfaces > ORIGAMI_MAX_FACES) {
      diag_error(src->loc, "origami too large: %d faces (limit ORIGAMI_MAX_FACES %d)", m->nfaces,
                 ORIGAMI_MAX_FACES);
      ok = 0;
    }
    if (ok)
      for (int f = 0; f < m->nfaces; f++) {                  /* a derived face points at a crease of it */
        int k = m->face_start[f];
        m->face_loc[f] = m->vert_loc[m->face_index[k]];
      }
  } else if (ok) {
    ok = copy_faces(&b);
    if (ok) dedupe_creases(&b);
  }
  if (ok) {
    face_edge_table(&b);
    ok = link_faces(&b);
  }
  if (ok) {
    if (src->nfaces == 0)                                   /* point derived faces at a crease */
      for (int f = 0; f < m->nfaces; f++) {
        int c = m->face_crease[m->face_start[f]];
        if (c >= 0 && m->creases[c].loc.file >= 0) m->face_loc[f] = m->creases[c].loc;
      }
    triangulate(m);
    if (!src->has_folded) {                                 /* folding needs both theorems */
      int before = diag_error_count();
      check_vertices_paper(&b);
      ok = diag_error_count() == before;
    }
  }
  if (ok) ok = fold(&b);
  if (ok) {
    fold_bounds(m);
    if (relation) ok = build_relation(&b);
    else {
      m->row_words = (m->nfaces + 63) / 64;
      m->above = xcalloc((size_t)m->nfaces * (size_t)m->row_words, sizeof *m->above);
    }
  }
  if (ok && check) {
    check_orders(&b);
    if (!src->overlap_auto && diag_error_count() == errors0) check_with_solver(&b);
    if (src->has_folded) check_vertices_folded(&b);
  }
  free(b.face_edges);
  free(b.orders);
  free(b.split_origin);
  if (!ok || diag_error_count() > errors0) {
    origami_free(m);
    return NULL;
  }
  return m;
}

OrigamiModel *origami_build(const SceneOrigami *src, int check) { return build(src, check, 1); }

OrigamiModel *origami_build_folded(const SceneOrigami *src) { return build(src, 0, 0); }

void origami_free(OrigamiModel *m) {
  if (!m) return;
  free(m->name);
  free(m->paper);
  free(m->folded);
  free(m->vert_loc);
  free(m->creases);
  free(m->face_start);
  free(m->face_index);
  free(m->face_crease);
  free(m->face_loc);
  free(m->face_xf);
  free(m->flipped);
  free(m->tri);
  free(m->tri_face);
  free(m->above);
  free(m);
}

static Vec2 face_centroid(const OrigamiModel *m, int f, const Vec2 *p) {
  /* area centroid of the polygon */
  double a2 = 0, cx = 0, cy = 0;
  int n = m->face_start[f + 1] - m->face_start[f];
  const int *v = m->face_index + m->face_start[f];
  for (int k = 0; k < n; k++) {
    Vec2 s = p[v[k]], t = p[v[(k + 1) % n]];
    double w = s.x * t.y - t.x * s.y;
    a2 += w, cx += (s.x + t.x) * w, cy += (s.y + t.y) * w;
  }
  Vec2 c = {cx / (3 * a2), cy / (3 * a2)};
  return c;
}

static void print_list(FILE *out, const char *label, const int *ids, int n) {
  fprintf(out, " %s [", label);
  for (int k = 0; k < n; k++) fprintf(out, "%s%d", k ? ", " : "", ids[k]);
  fputc(']', out);
}

void origami_list_faces(const OrigamiModel *m, FILE *out) {
  int nov;
  OrigamiOverlap *ov = origami_overlaps(m, &nov);
  int *over = xmalloc((size_t)(m->nfaces + 1) * sizeof *over);
  int *under = xmalloc((size_t)(m->nfaces + 1) * sizeof *under);
  int *none = xmalloc((size_t)(m->nfaces + 1) * sizeof *none);
  fprintf(out, "origami %s: %d faces, %d vertices\n", m->name ? m->name : "(unnamed)", m->nfaces,
          m->nverts);
  for (int f = 0; f < m->nfaces; f++) {
    fprintf(out, "face %d: vertices [", f);
    for (int k = m->face_start[f]; k < m->face_start[f + 1]; k++)
      fprintf(out, "%s%d", k > m->face_start[f] ? ", " : "", m->face_index[k]);
    Vec2 cp = face_centroid(m, f, m->paper), cf = face_centroid(m, f, m->folded);
    fprintf(out, "]; paper [%g, %g]; folded [%g, %g]%s;", cp.x, cp.y, cf.x, cf.y,
            m->flipped[f] ? " (back up)" : "");
    int no = 0, nu = 0, nn = 0;
    for (int k = 0; k < nov; k++) {
      int g = ov[k].i == f ? ov[k].j : ov[k].j == f ? ov[k].i : -1;
      if (g < 0) continue;
      if (origami_is_above(m, f, g)) over[no++] = g;
      else if (origami_is_above(m, g, f)) under[nu++] = g;
      else none[nn++] = g;
    }
    print_list(out, "over", over, no);
    print_list(out, "under", under, nu);
    if (nn) print_list(out, "unordered", none, nn);
    fputc('\n', out);
  }
  free(none);
  free(under);
  free(over);
  free(ov);
}

int origami_check_scene(const Scene *s) {
  int failed = 0;
  for (int i = 0; i < s->norigami && !diag_too_many(); i++) {
    OrigamiModel *m = origami_build(&s->origami[i], 1);
    failed += m == NULL;
    origami_free(m);
  }
  return failed;
}

int origami_list_scene(const Scene *s, FILE *out) {
  int status = 0;
  for (int i = 0; i < s->norigami; i++) {
    OrigamiModel *m = origami_build(&s->origami[i], 0);
    if (!m) { status = 1; continue; }
    if (i > 0) fputc('\n', out);
    origami_list_faces(m, out);
    origami_free(m);
  }
  return status;
}
