/*
** The arrangement of a folded state's edges (arrangement.h): merged points,
** the lines the edges lie on, the segments between consecutive points on
** each line, the cells those segments bound, and the faces covering each
** cell.
**
** Written bottom-up: the point grid, lines, segments, cells, face sets,
** and last the search for eps and the public entries.
*/
#include "arrangement.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"

#define PI 3.14159265358979323846
#define EPS_FIRST 3             /* eps = shortest edge / 2^3 .. */
#define EPS_LAST 27             /* .. / 2^27 */
#define EPS_STABLE 3            /* steps in a row with the same counts */

/* ---- point grid: merge points closer than eps ------------------------- */

/* Points hashed by their eps-sized grid cell; a query looks at the 3 x 3
** cells around it, so any point within eps (in x and in y) is found. */
typedef struct PointGrid {
  double eps;
  int n, cap;
  Vec2 *p;
  int *next;                    /* next point in the same grid cell */
  int slots;                    /* power of two */
  int64_t (*key)[2];
  int *head;                    /* -1: empty slot */
} PointGrid;

static uint64_t cell_hash(int64_t x, int64_t y) {
  uint64_t h = (uint64_t)x * 0x9E3779B97F4A7C15u ^ ((uint64_t)y + 0x632BE59BD9B4E019u) * 0xC2B2AE3D27D4EB4Fu;
  return h ^ (h >> 29);
}

static int *grid_slot(PointGrid *g, int64_t x, int64_t y, int insert) {
  size_t mask = (size_t)g->slots - 1, i = cell_hash(x, y) & mask;
  while (g->head[i] >= 0) {
    if (g->key[i][0] == x && g->key[i][1] == y) return &g->head[i];
    i = (i + 1) & mask;
  }
  if (!insert) return NULL;
  g->key[i][0] = x, g->key[i][1] = y;
  return &g->head[i];
}

static void grid_alloc(PointGrid *g, int slots) {
  g->slots = slots;
  g->key = xmalloc((size_t)slots * sizeof *g->key);
  g->head = xmalloc((size_t)slots * sizeof *g->head);
  memset(g->head, 0xff, (size_t)slots * sizeof *g->head);
}

static int64_t grid_coord(const PointGrid *g, double v) { return (int64_t)floor(v / g->eps); }

static void grid_link(PointGrid *g, int id) {
  int *h = grid_slot(g, grid_coord(g, g->p[id].x), grid_coord(g, g->p[id].y), 1);
  g->next[id] = *h;
  *h = id;
}

static void grid_rehash(PointGrid *g) {
  free(g->key);
  free(g->head);
  grid_alloc(g, g->slots * 2);
  for (int id = 0; id < g->n; id++) grid_link(g, id);
}

/* The lowest-numbered point within eps of p, or -1. */
static int grid_find(PointGrid *g, Vec2 p) {
  int64_t cx = grid_coord(g, p.x), cy = grid_coord(g, p.y);
  int best = -1;
  for (int dy = -1; dy <= 1; dy++)
    for (int dx = -1; dx <= 1; dx++) {
      int *h = grid_slot(g, cx + dx, cy + dy, 0);
      for (int id = h ? *h : -1; id >= 0; id = g->next[id])
        if (fabs(g->p[id].x - p.x) <= g->eps && fabs(g->p[id].y - p.y) <= g->eps &&
            (best < 0 || id < best))
          best = id;
    }
  return best;
}

/* The point within eps of p, added when there is none. */
static int grid_point(PointGrid *g, Vec2 p) {
  int id = grid_find(g, p);
  if (id >= 0) return id;
  g->p = xgrow(g->p, &g->cap, g->n + 1, sizeof *g->p);
  g->next = xrealloc(g->next, (size_t)g->cap * sizeof *g->next);
  id = g->n++;
  g->p[id] = p;
  if (2 * g->n > g->slots) grid_rehash(g);
  else grid_link(g, id);
  return id;
}

static void grid_init(PointGrid *g, double eps, int expect) {
  memset(g, 0, sizeof *g);
  g->eps = eps;
  int slots = 64;
  while (slots < 2 * expect) slots *= 2;
  grid_alloc(g, slots);
}

static void grid_free(PointGrid *g) {
  free(g->p);
  free(g->next);
  free(g->key);
  free(g->head);
}

/* ---- lines: edges within eps of one line share it ----------------------- */

typedef struct Line {
  Vec2 u;                       /* unit direction, angle in [-atol, pi - atol) */
  double d;                     /* offset: cross(u, p) for p on the line */
  int group;                    /* lines of one group are parallel */
  Vec2 lo, hi;                  /* bounding box of its edges, grown by eps */
  int ncover;                   /* merged t-intervals its edges cover */
  double (*cover)[2];
} Line;

typedef struct Entry { double t; int point; } Entry;   /* a point on a line */

typedef struct Build {
  double eps;
  int nedges;
  const int (*ev)[2];
  const int (*ef)[2];
  int nfaces;
  PointGrid grid;
  int *edge_pa, *edge_pb;       /* edge endpoints as points */
  int *edge_line;
  int nlines;
  Line *line;
  Entry **entry;                /* per line */
  int *nentry, *entry_cap;
} Build;

typedef struct Keyed { double k; int i; } Keyed;

static int cmp_keyed(const void *a, const void *b) {
  const Keyed *x = a, *y = b;
  if (x->k != y->k) return x->k < y->k ? -1 : 1;
  return x->i - y->i;
}

static double edge_angle(const Build *b, int e, double atol) {
  Vec2 p = b->grid.p[b->edge_pa[e]], q = b->grid.p[b->edge_pb[e]];
  double th = atan2(q.y - p.y, q.x - p.x);
  if (th < 0) th += PI;
  if (th >= PI) th -= PI;
  if (th >= PI - atol) th -= PI;            /* near-horizontal lines meet near 0 */
  return th;
}

static double edge_len2(const Build *b, int e) {
  Vec2 p = b->grid.p[b->edge_pa[e]], q = b->grid.p[b->edge_pb[e]];
  return (q.x - p.x) * (q.x - p.x) + (q.y - p.y) * (q.y - p.y);
}

static double cross_u(Vec2 u, Vec2 p) { return u.x * p.y - u.y * p.x; }
static double dot_u(Vec2 u, Vec2 p) { return u.x * p.x + u.y * p.y; }

static int cmp_interval(const void *a, const void *b) {
  const double *x = a, *y = b;
  return x[0] < y[0] ? -1 : x[0] > y[0];
}

/* One line's bounding box and its covered t-intervals, merged. */
static void line_finish(Build *b, Line *l, const int *edges, int n) {
  l->lo = (Vec2){INFINITY, INFINITY};
  l->hi = (Vec2){-INFINITY, -INFINITY};
  l->cover = xmalloc((size_t)n * sizeof *l->cover);
  for (int k = 0; k < n; k++) {
    Vec2 p = b->grid.p[b->edge_pa[edges[k]]], q = b->grid.p[b->edge_pb[edges[k]]];
    double t0 = dot_u(l->u, p), t1 = dot_u(l->u, q);
    l->cover[k][0] = fmin(t0, t1);
    l->cover[k][1] = fmax(t0, t1);
    l->lo.x = fmin(l->lo.x, fmin(p.x, q.x) - b->eps), l->lo.y = fmin(l->lo.y, fmin(p.y, q.y) - b->eps);
    l->hi.x = fmax(l->hi.x, fmax(p.x, q.x) + b->eps), l->hi.y = fmax(l->hi.y, fmax(p.y, q.y) + b->eps);
  }
  qsort(l->cover, (size_t)n, sizeof *l->cover, cmp_interval);
  int m = 0;
  for (int k = 0; k < n; k++) {
    if (m > 0 && l->cover[k][0] <= l->cover[m - 1][1] + b->eps)
      l->cover[m - 1][1] = fmax(l->cover[m - 1][1], l->cover[k][1]);
    else {
      l->cover[m][0] = l->cover[k][0];
      l->cover[m][1] = l->cover[k][1];
      m++;
    }
  }
  l->ncover = m;
}

/* Group the edges into lines: by angle (a chain of angles each within atol
** of the last), then within a group by offset (within eps). */
static void make_lines(Build *b, double atol) {
  int ne = b->nedges;
  Keyed *byang = xmalloc((size_t)(ne ? ne : 1) * sizeof *byang);
  for (int e = 0; e < ne; e++) byang[e] = (Keyed){edge_angle(b, e, atol), e};
  qsort(byang, (size_t)ne, sizeof *byang, cmp_keyed);
  Keyed *byoff = xmalloc((size_t)(ne ? ne : 1) * sizeof *byoff);
  int *members = xmalloc((size_t)(ne ? ne : 1) * sizeof *members);
  int cap = 0, group = 0;
  b->edge_line = xmalloc((size_t)(ne ? ne : 1) * sizeof *b->edge_line);
  for (int g0 = 0; g0 < ne; group++) {
    int g1 = g0 + 1, longest = byang[g0].i;
    while (g1 < ne && byang[g1].k - byang[g1 - 1].k <= atol) g1++;
    for (int k = g0; k < g1; k++)
      if (edge_len2(b, byang[k].i) > edge_len2(b, longest)) longest = byang[k].i;
    double th = edge_angle(b, longest, atol);
    Vec2 u = {cos(th), sin(th)};
    for (int k = g0; k < g1; k++) {
      int e = byang[k].i;
      Vec2 p = b->grid.p[b->edge_pa[e]], q = b->grid.p[b->edge_pb[e]];
      byoff[k - g0] = (Keyed){0.5 * (cross_u(u, p) + cross_u(u, q)), e};
    }
    qsort(byoff, (size_t)(g1 - g0), sizeof *byoff, cmp_keyed);
    for (int a = 0; a < g1 - g0;) {
      int c = a + 1;
      double sum = byoff[a].k;
      while (c < g1 - g0 && byoff[c].k - byoff[c - 1].k <= b->eps) sum += byoff[c++].k;
      b->line = xgrow(b->line, &cap, b->nlines + 1, sizeof *b->line);
      Line *l = &b->line[b->nlines];
      memset(l, 0, sizeof *l);
      l->u = u;
      l->d = sum / (c - a);
      l->group = group;
      for (int k = a; k < c; k++) members[k - a] = byoff[k].i, b->edge_line[byoff[k].i] = b->nlines;
      line_finish(b, l, members, c - a);
      b->nlines++;
      a = c;
    }
    g0 = g1;
  }
  free(members);
  free(byoff);
  free(byang);
}

static void entry_add(Build *b, int l, int point) {
  b->entry[l] = xgrow(b->entry[l], &b->entry_cap[l], b->nentry[l] + 1, sizeof **b->entry);
  b->entry[l][b->nentry[l]++] = (Entry){dot_u(b->line[l].u, b->grid.p[point]), point};
}

/* Whether t lies within eps of the part of line l its edges cover. */
static int line_covers(const Line *l, double t, double eps) {
  int lo = 0, hi = l->ncover;
  while (lo < hi) {                               /* first interval ending at or after t - eps */
    int mid = (lo + hi) / 2;
    if (l->cover[mid][1] < t - eps) lo = mid + 1;
    else hi = mid;
  }
  return lo < l->ncover && l->cover[lo][0] <= t + eps;
}

static void cross_lines(Build *b, int i, int j) {
  const Line *p = &b->line[i], *q = &b->line[j];
  double det = cross_u(p->u, q->u);              /* a1 b2 - a2 b1 with a = -u.y, b = u.x */
  if (p->group == q->group || det == 0) return;
  Vec2 x = {(p->d * q->u.x - q->d * p->u.x) / det, (p->d * q->u.y - q->d * p->u.y) / det};
  if (!line_covers(p, dot_u(p->u, x), b->eps) || !line_covers(q, dot_u(q->u, x), b->eps)) return;
  int id = grid_point(&b->grid, x);
  entry_add(b, i, id);
  entry_add(b, j, id);
}

/* Every crossing of two lines where both are covered, swept along x. */
static void cross_all(Build *b) {
  Keyed *order = xmalloc((size_t)(b->nlines ? b->nlines : 1) * sizeof *order);
  for (int l = 0; l < b->nlines; l++) order[l] = (Keyed){b->line[l].lo.x, l};
  qsort(order, (size_t)b->nlines, sizeof *order, cmp_keyed);
  for (int k = 0; k < b->nlines; k++) {
    const Line *p = &b->line[order[k].i];
    for (int m = k + 1; m < b->nlines && order[m].k <= p->hi.x; m++) {
      const Line *q = &b->line[order[m].i];
      if (q->lo.y > p->hi.y || q->hi.y < p->lo.y) continue;
      int i = order[k].i, j = order[m].i;
      cross_lines(b, i < j ? i : j, i < j ? j : i);
    }
  }
  free(order);
}

/* ---- segments: consecutive points on a line that its edges cover ------ */

static int cmp_entry(const void *a, const void *b) {
  const Entry *x = a, *y = b;
  if (x->t != y->t) return x->t < y->t ? -1 : 1;
  return x->point - y->point;
}

static int entry_find(const Entry *en, int n, int point, double t) {
  int lo = 0, hi = n;
  while (lo < hi) {
    int mid = (lo + hi) / 2;
    if (cmp_entry(&en[mid], &(Entry){t, point}) < 0) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

typedef struct SegList {
  int n, cap, ecap, nedge;
  int (*pt)[2];
  int *line;
  int *edge_start, *edge;
} SegList;

/* Cut line l at its points and keep the pieces its edges cover, with the
** edges covering each. */
static void line_segments(Build *b, int l, const int *edges, int nedges, SegList *s, int *cover) {
  Entry *en = b->entry[l];
  int n = b->nentry[l], m = 0;
  qsort(en, (size_t)n, sizeof *en, cmp_entry);
  for (int k = 0; k < n; k++)
    if (m == 0 || en[m - 1].point != en[k].point) en[m++] = en[k];
  n = b->nentry[l] = m;
  memset(cover, 0, (size_t)n * sizeof *cover);
  int *span = xmalloc((size_t)(2 * nedges + 1) * sizeof *span);
  for (int k = 0; k < nedges; k++) {
    int pa = b->edge_pa[edges[k]], pb = b->edge_pb[edges[k]];
    int ia = entry_find(en, n, pa, dot_u(b->line[l].u, b->grid.p[pa]));
    int ib = entry_find(en, n, pb, dot_u(b->line[l].u, b->grid.p[pb]));
    span[2 * k] = ia < ib ? ia : ib;
    span[2 * k + 1] = ia < ib ? ib : ia;
    for (int i = span[2 * k]; i < span[2 * k + 1]; i++) cover[i]++;
  }
  int first = s->n;
  s->edge_start = xrealloc(s->edge_start, (size_t)(s->cap + 1) * sizeof *s->edge_start);
  for (int i = 0; i + 1 < n; i++) {
    if (cover[i] == 0) { cover[i] = -1; continue; }
    s->pt = xgrow(s->pt, &s->cap, s->n + 1, sizeof *s->pt);
    s->line = xrealloc(s->line, (size_t)s->cap * sizeof *s->line);
    s->edge_start = xrealloc(s->edge_start, (size_t)(s->cap + 1) * sizeof *s->edge_start);
    s->pt[s->n][0] = en[i].point;
    s->pt[s->n][1] = en[i + 1].point;
    s->line[s->n] = l;
    s->edge_start[s->n] = s->nedge;
    s->nedge += cover[i];
    cover[i] = s->n++;
  }
  s->edge_start[s->n] = s->nedge;
  s->edge = xgrow(s->edge, &s->ecap, s->nedge, sizeof *s->edge);
  int *fill = xcalloc((size_t)(s->n - first + 1), sizeof *fill);
  for (int k = 0; k < nedges; k++)
    for (int i = span[2 * k]; i < span[2 * k + 1]; i++) {
      int sg = cover[i];
      s->edge[s->edge_start[sg] + fill[sg - first]++] = edges[k];
    }
  free(fill);
  free(span);
}

static void make_segments(Build *b, SegList *s) {
  int *start = xcalloc((size_t)b->nlines + 1, sizeof *start), *byline = xmalloc((size_t)(b->nedges + 1) * sizeof *byline);
  for (int e = 0; e < b->nedges; e++) start[b->edge_line[e] + 1]++;
  for (int l = 0; l < b->nlines; l++) start[l + 1] += start[l];
  int *fill = xcalloc((size_t)b->nlines + 1, sizeof *fill);
  for (int e = 0; e < b->nedges; e++) byline[start[b->edge_line[e]] + fill[b->edge_line[e]]++] = e;
  int maxn = 1;
  for (int l = 0; l < b->nlines; l++) maxn = b->nentry[l] > maxn ? b->nentry[l] : maxn;
  int *cover = xmalloc((size_t)maxn * sizeof *cover);
  for (int l = 0; l < b->nlines; l++)
    line_segments(b, l, byline + start[l], start[l + 1] - start[l], s, cover);
  free(cover);
  free(fill);
  free(byline);
  free(start);
}

/* ---- cells: the faces of the planar graph of segments ---------------- */

typedef struct HalfKey { double angle; int h; } HalfKey;

static int cmp_halfkey(const void *a, const void *b) {
  const HalfKey *x = a, *y = b;
  if (x->angle != y->angle) return x->angle < y->angle ? -1 : 1;
  return x->h - y->h;
}

/* The cell to the left of every half-edge (2s: point 0 -> 1, 2s + 1 back);
** returns the number of cycles, with the outer one (negative area) last,
** or -1 when there is not exactly one. */
static int trace_cells(const Build *b, const SegList *s, int *hcell, int **first_half) {
  int np = b->grid.n, nh = 2 * s->n;
  int *deg = xcalloc((size_t)np + 1, sizeof *deg);
  for (int g = 0; g < s->n; g++) deg[s->pt[g][0] + 1]++, deg[s->pt[g][1] + 1]++;
  for (int p = 0; p < np; p++) deg[p + 1] += deg[p];
  HalfKey *out = xmalloc((size_t)(nh ? nh : 1) * sizeof *out);
  int *fill = xcalloc((size_t)np, sizeof *fill), *pos = xmalloc((size_t)(nh ? nh : 1) * sizeof *pos);
  for (int h = 0; h < nh; h++) {
    int g = h / 2, from = s->pt[g][h & 1], to = s->pt[g][!(h & 1)];
    Vec2 u = b->line[s->line[g]].u;
    double tf = dot_u(u, b->grid.p[from]), tt = dot_u(u, b->grid.p[to]);
    double ang = tt > tf ? atan2(u.y, u.x) : atan2(-u.y, -u.x);
    out[deg[from] + fill[from]++] = (HalfKey){ang, h};
  }
  for (int p = 0; p < np; p++) {
    qsort(out + deg[p], (size_t)(deg[p + 1] - deg[p]), sizeof *out, cmp_halfkey);
    for (int k = deg[p]; k < deg[p + 1]; k++) pos[out[k].h] = k;
  }
  for (int h = 0; h < nh; h++) hcell[h] = -1;
  int ncyc = 0, outer = -1, nouter = 0, cap = 0;
  *first_half = NULL;
  double *area = NULL;
  int acap = 0;
  for (int h0 = 0; h0 < nh; h0++) {
    if (hcell[h0] >= 0) continue;
    double a2 = 0;
    for (int h = h0; hcell[h] < 0;) {
      hcell[h] = ncyc;
      Vec2 p = b->grid.p[s->pt[h / 2][h & 1]], q = b->grid.p[s->pt[h / 2][!(h & 1)]];
      a2 += p.x * q.y - q.x * p.y;
      int to = s->pt[h / 2][!(h & 1)], k = pos[h ^ 1], d = deg[to + 1] - deg[to];
      h = out[deg[to] + (k - deg[to] + d - 1) % d].h;     /* turn right past the twin */
    }
    *first_half = xgrow(*first_half, &cap, ncyc + 1, sizeof **first_half);
    area = xgrow(area, &acap, ncyc + 1, sizeof *area);
    (*first_half)[ncyc] = h0;
    area[ncyc] = a2;
    if (a2 < 0) outer = ncyc, nouter++;
    ncyc++;
  }
  free(area);
  free(pos);
  free(fill);
  free(out);
  free(deg);
  if (nouter != 1) return -1;
  if (outer != ncyc - 1) {                                  /* renumber: outer last */
    for (int h = 0; h < nh; h++)
      hcell[h] = hcell[h] == outer ? ncyc - 1 : hcell[h] == ncyc - 1 ? outer : hcell[h];
    int t = (*first_half)[outer];
    (*first_half)[outer] = (*first_half)[ncyc - 1];
    (*first_half)[ncyc - 1] = t;
  }
  return ncyc;
}

/* ---- face sets: crossing a segment toggles the faces of its edges ------ */

static int cmp_int(const void *a, const void *b) {
  int x = *(const int *)a, y = *(const int *)b;
  return (x > y) - (x < y);
}

/* The faces along segment g, ascending, into buf; returns the count. */
static int seg_faces(const Build *b, const SegList *s, int g, int *buf) {
  int n = 0;
  for (int k = s->edge_start[g]; k < s->edge_start[g + 1]; k++)
    for (int side = 0; side < 2; side++)
      if (b->ef[s->edge[k]][side] >= 0) buf[n++] = b->ef[s->edge[k]][side];
  qsort(buf, (size_t)n, sizeof *buf, cmp_int);
  int m = 0;                                   /* a face on both sides of an edge does not change */
  for (int i = 0; i < n; i++) {
    if (i + 1 < n && buf[i] == buf[i + 1]) { i++; continue; }
    buf[m++] = buf[i];
  }
  return m;
}

/* out = a xor b (both ascending); returns the count. */
static int sym_diff(const int *a, int na, const int *b, int nb, int *out) {
  int i = 0, j = 0, n = 0;
  while (i < na || j < nb) {
    if (j == nb || (i < na && a[i] < b[j])) out[n++] = a[i++];
    else if (i == na || b[j] < a[i]) out[n++] = b[j++];
    else i++, j++;
  }
  return n;
}

typedef struct FaceSets { int *start, *face, n, cap; } FaceSets;

/* Each cell's faces, by a breadth-first walk from the outside (no faces). */
static int face_sets(const Build *b, const SegList *s, const int *hcell, const int *first_half,
                     int ncells, Arrangement *a) {
  int maxseg = 2, *next_h = xmalloc((size_t)(2 * s->n + 1) * sizeof *next_h);
  for (int g = 0; g < s->n; g++) {
    int n = 2 * (s->edge_start[g + 1] - s->edge_start[g]);
    maxseg = n > maxseg ? n : maxseg;
  }
  /* half-edges of each cell, as lists */
  int *cell_h = xmalloc((size_t)(ncells + 2) * sizeof *cell_h);
  for (int c = 0; c <= ncells; c++) cell_h[c] = -1;
  for (int h = 2 * s->n - 1; h >= 0; h--) {
    int c = hcell[h] == ncells ? ncells : hcell[h];
    next_h[h] = cell_h[c];
    cell_h[c] = h;
  }
  (void)first_half;
  int *start = xmalloc((size_t)(ncells + 2) * sizeof *start), *parent = xmalloc((size_t)(ncells + 1) * sizeof *parent);
  int *len = xcalloc((size_t)(ncells + 1), sizeof *len), *queue = xmalloc((size_t)(ncells + 1) * sizeof *queue);
  unsigned char *seen = xcalloc((size_t)ncells + 1, 1);
  int *sf = xmalloc((size_t)maxseg * sizeof *sf);
  FaceSets fs = {0};
  fs.face = xgrow(NULL, &fs.cap, 64, sizeof *fs.face);
  int qh = 0, qt = 0;
  queue[qt++] = ncells;                                     /* the outside */
  seen[ncells] = 1;
  start[ncells] = 0;
  parent[ncells] = -1;
  while (qh < qt) {
    int c = queue[qh++];
    for (int h = cell_h[c]; h >= 0; h = next_h[h]) {
      int d = hcell[h ^ 1];
      if (seen[d]) continue;
      seen[d] = 1;
      int nsf = seg_faces(b, s, h / 2, sf);
      fs.face = xgrow(fs.face, &fs.cap, fs.n + len[c] + nsf, sizeof *fs.face);
      start[d] = fs.n;
      len[d] = sym_diff(fs.face + start[c], len[c], sf, nsf, fs.face + fs.n);
      fs.n += len[d];
      parent[d] = c == ncells ? -1 : c;
      queue[qt++] = d;
    }
  }
  int ok = qt == ncells + 1;
  for (int g = 0; g < s->n && ok; g++) {                    /* every crossing must agree */
    int c0 = hcell[2 * g], c1 = hcell[2 * g + 1];
    if (c0 == c1) continue;
    int nsf = seg_faces(b, s, g, sf);
    int *tmp = xmalloc((size_t)(len[c0] + len[c1] + 1) * sizeof *tmp);
    int n = sym_diff(fs.face + start[c0], len[c0], fs.face + start[c1], len[c1], tmp);
    ok = n == nsf && memcmp(tmp, sf, (size_t)n * sizeof *tmp) == 0;
    free(tmp);
  }
  a->ncells = ncells;
  a->cell_face_start = xmalloc((size_t)(ncells + 1) * sizeof(int));
  a->cell_parent = parent;
  int total = 0;
  for (int c = 0; c < ncells; c++) total += len[c];
  a->cell_face = xmalloc((size_t)(total + 1) * sizeof(int));
  total = 0;
  for (int c = 0; c < ncells; c++) {
    a->cell_face_start[c] = total;
    memcpy(a->cell_face + total, fs.face + start[c], (size_t)len[c] * sizeof(int));
    total += len[c];
  }
  a->cell_face_start[ncells] = total;
  free(fs.face);
  free(sf);
  free(seen);
  free(queue);
  free(len);
  free(start);
  free(cell_h);
  free(next_h);
  return ok;
}

static void face_cells(Arrangement *a, int nfaces) {
  int *start = xcalloc((size_t)nfaces + 1, sizeof *start);
  for (int k = 0; k < a->cell_face_start[a->ncells]; k++) start[a->cell_face[k] + 1]++;
  for (int f = 0; f < nfaces; f++) start[f + 1] += start[f];
  int *fill = xcalloc((size_t)nfaces + 1, sizeof *fill);
  a->face_cell = xmalloc((size_t)(start[nfaces] + 1) * sizeof *a->face_cell);
  for (int c = 0; c < a->ncells; c++)
    for (int k = a->cell_face_start[c]; k < a->cell_face_start[c + 1]; k++) {
      int f = a->cell_face[k];
      a->face_cell[start[f] + fill[f]++] = c;
    }
  a->face_cell_start = start;
  free(fill);
}

/* ---- one build at a given eps ----------------------------------------- */

static void build_free(Build *b) {
  for (int l = 0; l < b->nlines; l++) free(b->line[l].cover), free(b->entry[l]);
  free(b->line);
  free(b->entry);
  free(b->nentry);
  free(b->entry_cap);
  free(b->edge_line);
  free(b->edge_pa);
  free(b->edge_pb);
  grid_free(&b->grid);
}

static void seglist_free(SegList *s) {
  free(s->pt);
  free(s->line);
  free(s->edge_start);
  free(s->edge);
}

/* Points and lines at eps; 0 when an edge collapses to a point. */
static int build_lines(Build *b, int nverts, const Vec2 *pos, double atol) {
  grid_init(&b->grid, b->eps, nverts);
  int *vp = xmalloc((size_t)(nverts ? nverts : 1) * sizeof *vp);
  for (int v = 0; v < nverts; v++) vp[v] = -1;
  b->edge_pa = xmalloc((size_t)(b->nedges + 1) * sizeof(int));
  b->edge_pb = xmalloc((size_t)(b->nedges + 1) * sizeof(int));
  int ok = 1;
  for (int e = 0; e < b->nedges; e++) {
    for (int k = 0; k < 2; k++) {
      int v = b->ev[e][k];
      if (vp[v] < 0) vp[v] = grid_point(&b->grid, pos[v]);
    }
    b->edge_pa[e] = vp[b->ev[e][0]];
    b->edge_pb[e] = vp[b->ev[e][1]];
    if (b->edge_pa[e] == b->edge_pb[e]) ok = 0;
  }
  free(vp);
  if (!ok) return 0;
  make_lines(b, atol);
  b->entry = xcalloc((size_t)b->nlines + 1, sizeof *b->entry);
  b->nentry = xcalloc((size_t)b->nlines + 1, sizeof *b->nentry);
  b->entry_cap = xcalloc((size_t)b->nlines + 1, sizeof *b->entry_cap);
  for (int e = 0; e < b->nedges; e++) {
    entry_add(b, b->edge_line[e], b->edge_pa[e]);
    entry_add(b, b->edge_line[e], b->edge_pb[e]);
  }
  return 1;
}

/* The whole arrangement at eps into a (when a is not NULL), or only its
** point and segment counts. Returns 0 when it is not consistent. */
static int build_at(double eps, int nverts, const Vec2 *pos, int nedges, const int (*ev)[2],
                    const int (*ef)[2], int nfaces, double scale, Arrangement *a, int *npoints,
                    int *nsegs) {
  Build b = {.eps = eps, .nedges = nedges, .ev = ev, .ef = ef, .nfaces = nfaces};
  SegList s = {0};
  int ok = build_lines(&b, nverts, pos, eps / scale);
  if (ok) {
    cross_all(&b);
    make_segments(&b, &s);
    *npoints = b.grid.n;
    *nsegs = s.n;
  }
  if (ok && a) {
    int *hcell = xmalloc((size_t)(2 * s.n + 1) * sizeof *hcell), *first_half = NULL;
    int ncyc = trace_cells(&b, &s, hcell, &first_half);
    ok = ncyc > 0 && face_sets(&b, &s, hcell, first_half, ncyc - 1, a);
    if (ok) {
      a->npoints = b.grid.n;
      a->point = xmalloc((size_t)(b.grid.n + 1) * sizeof *a->point);
      memcpy(a->point, b.grid.p, (size_t)b.grid.n * sizeof *a->point);
      a->vert_point = xmalloc((size_t)(nverts + 1) * sizeof *a->vert_point);
      for (int v = 0; v < nverts; v++) a->vert_point[v] = -1;
      for (int e = 0; e < nedges; e++)
        a->vert_point[ev[e][0]] = b.edge_pa[e], a->vert_point[ev[e][1]] = b.edge_pb[e];
      a->nsegs = s.n;
      a->seg_point = s.pt, s.pt = NULL;
      a->seg_edge_start = s.edge_start, s.edge_start = NULL;
      a->seg_edge = s.edge, s.edge = NULL;
      a->seg_cell = xmalloc((size_t)(s.n + 1) * sizeof *a->seg_cell);
      for (int g = 0; g < s.n; g++)
        for (int k = 0; k < 2; k++)
          a->seg_cell[g][k] = hcell[2 * g + k] == ncyc - 1 ? -1 : hcell[2 * g + k];
      face_cells(a, nfaces);
    }
    free(first_half);
    free(hcell);
  }
  seglist_free(&s);
  build_free(&b);
  return ok;
}

/* ---- public entries --------------------------------------------------- */

int arrangement_build(int nverts, const Vec2 *pos, int nedges, const int (*edge_verts)[2],
                      const int (*edge_faces)[2], int nfaces, Arrangement *out, char *err,
                      size_t errlen) {
  memset(out, 0, sizeof *out);
  double shortest = INFINITY;
  Vec2 lo = {INFINITY, INFINITY}, hi = {-INFINITY, -INFINITY};
  for (int e = 0; e < nedges; e++) {
    Vec2 p = pos[edge_verts[e][0]], q = pos[edge_verts[e][1]];
    shortest = fmin(shortest, hypot(q.x - p.x, q.y - p.y));
    lo.x = fmin(lo.x, fmin(p.x, q.x)), lo.y = fmin(lo.y, fmin(p.y, q.y));
    hi.x = fmax(hi.x, fmax(p.x, q.x)), hi.y = fmax(hi.y, fmax(p.y, q.y));
  }
  double scale = fmax(hi.x - lo.x, hi.y - lo.y);
  if (nedges == 0 || !(shortest > 0) || !isfinite(scale) || scale <= 0) {
    snprintf(err, errlen, "the folded state has no edge of positive length");
    return 1;
  }
  /* the coarsest eps whose counts hold for EPS_STABLE steps, as the
  ** stable count is the one the file means */
  int run = 0, best_run = 0, best_i = -1, np0 = -1, ns0 = -1;
  for (int i = EPS_FIRST; i <= EPS_LAST; i++) {
    double eps = shortest / ldexp(1, i);
    if (eps < 1e-15 * scale) break;
    int np = 0, ns = 0;
    if (!build_at(eps, nverts, pos, nedges, edge_verts, edge_faces, nfaces, scale, NULL, &np, &ns)) {
      run = 0, np0 = ns0 = -1;
      continue;
    }
    run = (np == np0 && ns == ns0) ? run + 1 : 1;
    np0 = np, ns0 = ns;
    if (run > best_run) best_run = run, best_i = i - run + 1;
    if (run == EPS_STABLE) break;
  }
  if (best_i < 0) {
    snprintf(err, errlen, "the folded state's edges do not make a consistent arrangement at any "
             "merge distance");
    return 1;
  }
  for (int i = best_i; i <= EPS_LAST; i++) {                /* the first consistent one from there */
    double eps = shortest / ldexp(1, i);
    int np, ns;
    if (build_at(eps, nverts, pos, nedges, edge_verts, edge_faces, nfaces, scale, out, &np, &ns)) {
      out->eps = eps;
      out->eps_log2 = i;
      return 0;
    }
    arrangement_free(out);
  }
  snprintf(err, errlen, "the folded state's edges do not make a consistent arrangement: the "
           "faces on the two sides of some folded edge disagree at every merge distance");
  return 1;
}

void arrangement_free(Arrangement *a) {
  free(a->point);
  free(a->vert_point);
  free(a->seg_point);
  free(a->seg_edge_start);
  free(a->seg_edge);
  free(a->seg_cell);
  free(a->cell_face_start);
  free(a->cell_face);
  free(a->cell_parent);
  free(a->face_cell_start);
  free(a->face_cell);
  memset(a, 0, sizeof *a);
}
