/*
** The layer-order solver (layer_solve.h): variables from the arrangement's
** cells, the four kinds of constraint, propagation, the forced orders,
** components, and the search that finds and counts states.
**
** A constraint is a predicate on up to six literals, "face x lies over
** face y", kept as the 64-bit set of its valid truth assignments; so
** propagation is the same few mask operations for every kind: a partial
** assignment leaves the valid assignments that match it, none of them is
** a conflict, and a literal that is the same in all of them is implied.
**
** Written bottom-up: variables, literals and propagation, constraints,
** transitivity, the forced orders, components, the search, and last the
** public entries.
*/
#include "layer_solve.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"
#include "../base/sort.h"
#include "arrangement.h"

/* Constraints as stored: kind, literals (2 * variable + 1 when the pair
** is read the other way round), and the faces, for diagnostics. */
typedef struct Cons {
  unsigned char kind, n, taco;       /* taco: the first two faces overlap (a taco-tortilla) */
  int lit[6];
  int face[4];
} Cons;

enum { WHY_NONE, WHY_CREASE, WHY_CONS, WHY_TRANS };
typedef struct Why { int kind, a, b; } Why;   /* crease a; constraint a; variable a with third face b */

typedef struct Frame { int var, trail, pos, second; } Frame;

/* A per-face value valid only where gen matches (cleared by a new gen). */
typedef struct Dense { int *gen, *val; } Dense;

struct LayerSolver {
  LayerInput in;
  Arrangement arr;
  int nvars;
  uint64_t *key;                     /* (f1 << 32) | f2, f1 < f2, ascending */
  int *row;                          /* nfaces + 1: the variables whose f1 is f */
  signed char *val;                  /* 0 unknown, +1 f1 over f2, -1 f2 over f1 */
  int ncons, conscap;
  Cons *cons;
  int *vc_start, *vc;                /* variable -> constraints */
  int *cc_start, *cc_face, *cc_comp; /* per face: the faces joined by taco-tortillas it is the tortilla of */
  int *stamp, *third, nthird;        /* scratch for transitivity */
  int (*third_lit)[2];               /* with each third face: "f2 over f3", "f3 over f1" */
  int (*adj)[2], *adj_start;         /* per face: (other face, variable), both ways, by face */
  int (*cct)[2], *cct_start;         /* per face: (tortilla, group) where a taco-tortilla joins it */
  Dense near1, near2, group1, group2, joined;   /* per-variable scatter of the above */
  int gen;
  long trans_all, trans_reduced;     /* third faces found, before and after leaving out implied ones */
  int *tc_start, (*tc)[2];           /* cached transitivity of component variables: the other two literals */
  int cached;
  Why *why;
  int *trail, ntrail;
  int recording;                     /* propagation records a conflict (the forced orders) */
  int ncomp;
  int *comp_start, *comp_var;
  long *count, *count_limit;         /* per component: states found (-1 not counted), up to limit */
  signed char *picked;               /* per variable: the picked state's value */
  unsigned char *comp_picked;
  LayerConflict conflict;
  int has_conflict;
  LayerStats stats;
};

/* ---- variables and literals -------------------------------------------- */

static int cmp_int_asc(const void *a, const void *b) {
  int x = *(const int *)a, y = *(const int *)b;
  return (x > y) - (x < y);
}

/* Index of f in the ascending list l[0..n), or -1. */
static int cc_local(const int *l, int n, int f) {
  int lo = 0, hi = n;
  while (lo < hi) {
    int mid = (lo + hi) / 2;
    if (l[mid] < f) lo = mid + 1;
    else hi = mid;
  }
  return lo < n && l[lo] == f ? lo : -1;
}

static int var_find(const LayerSolver *s, int f, int g) {
  if (f > g) { int t = f; f = g; g = t; }
  if (f == g || f < 0 || g >= s->in.nfaces) return -1;
  uint64_t k = ((uint64_t)f << 32) | (uint32_t)g;
  int lo = s->row[f], hi = s->row[f + 1];
  while (lo < hi) {
    int mid = (lo + hi) / 2;
    if (s->key[mid] < k) lo = mid + 1;
    else hi = mid;
  }
  return lo < s->row[f + 1] && s->key[lo] == k ? lo : -1;
}

static int var_f1(const LayerSolver *s, int v) { return (int)(s->key[v] >> 32); }
static int var_f2(const LayerSolver *s, int v) { return (int)(uint32_t)s->key[v]; }

/* The literal "x lies over y", or -1 when they do not overlap. */
static int lit_of(const LayerSolver *s, int x, int y) {
  int v = var_find(s, x, y);
  return v < 0 ? -1 : 2 * v + (x > y);
}

/* 1 true, 0 false, -1 unknown. */
static int lit_value(const LayerSolver *s, int lit) {
  int v = s->val[lit >> 1];
  return v == 0 ? -1 : ((v > 0) ^ (lit & 1));
}

static void assign(LayerSolver *s, int lit, int value, Why why) {
  int v = lit >> 1;
  s->val[v] = (value ^ (lit & 1)) ? 1 : -1;
  s->why[v] = why;
  s->trail[s->ntrail++] = v;
}

static void undo_to(LayerSolver *s, int mark) {
  while (s->ntrail > mark) s->val[s->trail[--s->ntrail]] = 0;
}

/* ---- masks: constraints as sets of valid assignments ------------------- */

static const uint64_t POS[6] = {0xAAAAAAAAAAAAAAAAull, 0xCCCCCCCCCCCCCCCCull, 0xF0F0F0F0F0F0F0F0ull,
                                0xFF00FF00FF00FF00ull, 0xFFFF0000FFFF0000ull, 0xFFFFFFFF00000000ull};

static uint64_t all_of(int n) { return n == 6 ? ~0ull : ((1ull << (1 << n)) - 1); }

static uint64_t VALID_TACO_TACO;                  /* built once from the 24 stackings */
static const uint64_t VALID_EQUAL = 0x9;          /* two literals alike: 00 or 11 */
static const uint64_t VALID_TRANS = 0x7E;         /* three literals around a cycle: not 000, not 111 */

/* The pairs of a taco-taco (A B C D: creases A-B and C-D along one line),
** as face positions. */
static const int TT_PAIRS[6][2] = {{0, 1}, {2, 3}, {2, 1}, {0, 3}, {0, 2}, {1, 3}};

/* Valid: the four faces stacked so that neither taco's pair has exactly
** one face of the other between them. */
static uint64_t taco_taco_mask(void) {
  uint64_t m = 0;
  for (int p = 0; p < 256; p++) {
    int h[4] = {p & 3, (p >> 2) & 3, (p >> 4) & 3, (p >> 6) & 3};
    if (h[0] == h[1] || h[0] == h[2] || h[0] == h[3] || h[1] == h[2] || h[1] == h[3] || h[2] == h[3])
      continue;                                       /* not a stacking of four */
    int lo = h[0] < h[1] ? h[0] : h[1], hi = h[0] ^ h[1] ^ lo;
    int c_in = h[2] > lo && h[2] < hi, d_in = h[3] > lo && h[3] < hi;
    if (c_in != d_in) continue;                       /* interleaved */
    int t = 0;
    for (int i = 0; i < 6; i++) t |= (h[TT_PAIRS[i][0]] > h[TT_PAIRS[i][1]]) << i;
    m |= 1ull << t;
  }
  return m;
}

static uint64_t cons_mask(int kind, int n) {
  if (kind == LAYER_TACO_TACO) return VALID_TACO_TACO;
  return n == 3 ? VALID_TRANS : VALID_EQUAL;
}

/* Match the literals against the assignment: -1 conflict, else the number
** of implied literals written to imp (as lit * 2 + value); *dead when every
** completion is valid. */
static int gac(const LayerSolver *s, const int *lit, int n, uint64_t valid, int *imp, int *dead) {
  uint64_t match = all_of(n);
  int unknown = 0;
  for (int i = 0; i < n; i++) {
    int lv = lit_value(s, lit[i]);
    if (lv < 0) unknown |= 1 << i;
    else match &= lv ? POS[i] : ~POS[i];
  }
  uint64_t ok = match & valid;
  if (!ok) return -1;
  *dead = ok == match;
  int k = 0;
  for (int i = 0; i < n; i++) {
    if (!(unknown >> i & 1)) continue;
    if (!(ok & POS[i])) imp[k++] = lit[i] * 2;
    else if (!(ok & ~POS[i])) imp[k++] = lit[i] * 2 + 1;
  }
  return k;
}

/* ---- constraints ------------------------------------------------------ */

static void cons_add(LayerSolver *s, int kind, int taco, const int (*pairs)[2], int n, const int *faces,
                     int nf) {
  Cons c = {.kind = (unsigned char)kind, .n = (unsigned char)n, .taco = (unsigned char)taco};
  for (int i = 0; i < n; i++)
    if ((c.lit[i] = lit_of(s, pairs[i][0], pairs[i][1])) < 0) return;   /* not a real overlap */
  for (int i = 0; i < 4; i++) c.face[i] = i < nf ? faces[i] : -1;
  s->cons = xgrow(s->cons, &s->conscap, s->ncons + 1, sizeof *s->cons);
  s->cons[s->ncons++] = c;
}

/* a and b (the faces of a crease) lie on one side of c. */
static void add_same_side(LayerSolver *s, int a, int b, int c, int taco, int kind) {
  int pairs[2][2] = {{a, c}, {b, c}}, faces[3] = {a, b, c};
  cons_add(s, kind, taco, pairs, 2, faces, 3);
}

/* Two edges along one segment of the folded state. */
static void edge_pair(LayerSolver *s, int e1, int e2) {
  const int *p = s->in.edge_faces[e1], *q = s->in.edge_faces[e2];
  if (p[0] < 0 || p[1] < 0 || q[0] < 0 || q[1] < 0) return;
  int f1 = p[0], f2 = p[1], f3 = q[0], f4 = q[1];
  if (f1 == f3 || f1 == f4 || f2 == f3 || f2 == f4 || f1 == f2 || f3 == f4) return;
  int o12 = var_find(s, f1, f2) >= 0, o13 = var_find(s, f1, f3) >= 0, o14 = var_find(s, f1, f4) >= 0;
  switch (o12 << 2 | o13 << 1 | o14) {
  case 0: add_same_side(s, f3, f4, f2, 1, LAYER_TACO_TORTILLA); break;
  case 1: case 2: {                                     /* two flat creases: the sheets keep their order */
    int g = o14 ? f4 : f3, h = o14 ? f3 : f4;
    int pairs[2][2] = {{f1, g}, {f2, h}}, faces[4] = {f1, f2, g, h};
    cons_add(s, LAYER_TORTILLA_TORTILLA, 0, pairs, 2, faces, 4);
    break;
  }
  case 3: add_same_side(s, f3, f4, f1, 1, LAYER_TACO_TORTILLA); break;
  case 4: break;                                        /* f1-f2 folded, f3 f4 elsewhere */
  case 5: add_same_side(s, f1, f2, f4, 1, LAYER_TACO_TORTILLA); break;
  case 6: add_same_side(s, f1, f2, f3, 1, LAYER_TACO_TORTILLA); break;
  default: {
    int faces[4] = {f1, f2, f3, f4}, pairs[6][2];
    for (int i = 0; i < 6; i++) pairs[i][0] = faces[TT_PAIRS[i][0]], pairs[i][1] = faces[TT_PAIRS[i][1]];
    cons_add(s, LAYER_TACO_TACO, 0, pairs, 6, faces, 4);
  }
  }
}

/* Pairs of edges sharing a segment, each pair once. */
static void edge_edge(LayerSolver *s) {
  const Arrangement *a = &s->arr;
  size_t n = 0, cap = 16;
  uint64_t *k = xmalloc(cap * sizeof *k);
  for (int g = 0; g < a->nsegs; g++)
    for (int i = a->seg_edge_start[g]; i < a->seg_edge_start[g + 1]; i++)
      for (int j = i + 1; j < a->seg_edge_start[g + 1]; j++) {
        int e1 = a->seg_edge[i], e2 = a->seg_edge[j];
        if (e1 > e2) { int t = e1; e1 = e2; e2 = t; }
        if (n == cap) k = xrealloc(k, (cap *= 2) * sizeof *k);
        k[n++] = ((uint64_t)e1 << 32) | (uint32_t)e2;
      }
  n = sort_unique_u64(k, n);
  for (size_t i = 0; i < n; i++) edge_pair(s, (int)(k[i] >> 32), (int)(uint32_t)k[i]);
  free(k);
}

/* An edge along a segment that runs through the inside of face f (f
** covers the cells on both sides): the edge's faces lie on one side of f. */
static void edge_face(LayerSolver *s) {
  const Arrangement *a = &s->arr;
  size_t n = 0, cap = 16;
  uint64_t *k = xmalloc(cap * sizeof *k);
  for (int g = 0; g < a->nsegs; g++) {
    int c0 = a->seg_cell[g][0], c1 = a->seg_cell[g][1];
    if (c0 < 0 || c1 < 0 || c0 == c1) continue;
    const int *x = a->cell_face + a->cell_face_start[c0], *xe = a->cell_face + a->cell_face_start[c0 + 1];
    const int *y = a->cell_face + a->cell_face_start[c1], *ye = a->cell_face + a->cell_face_start[c1 + 1];
    while (x < xe && y < ye) {
      if (*x < *y) x++;
      else if (*y < *x) y++;
      else {
        for (int i = a->seg_edge_start[g]; i < a->seg_edge_start[g + 1]; i++) {
          if (n == cap) k = xrealloc(k, (cap *= 2) * sizeof *k);
          k[n++] = ((uint64_t)a->seg_edge[i] << 32) | (uint32_t)*x;
        }
        x++, y++;
      }
    }
  }
  n = sort_unique_u64(k, n);
  for (size_t i = 0; i < n; i++) {
    int e = (int)(k[i] >> 32), f3 = (int)(uint32_t)k[i];
    int f1 = s->in.edge_faces[e][0], f2 = s->in.edge_faces[e][1];
    if (f1 < 0 || f2 < 0 || f1 == f3 || f2 == f3 || f1 == f2) continue;
    int taco = var_find(s, f1, f2) >= 0;
    add_same_side(s, f1, f2, f3, taco, taco ? LAYER_TACO_TORTILLA : LAYER_TORTILLA_TORTILLA);
  }
  free(k);
}

static void var_cons_index(LayerSolver *s) {
  s->vc_start = xcalloc((size_t)s->nvars + 1, sizeof *s->vc_start);
  for (int c = 0; c < s->ncons; c++)
    for (int i = 0; i < s->cons[c].n; i++) s->vc_start[(s->cons[c].lit[i] >> 1) + 1]++;
  for (int v = 0; v < s->nvars; v++) s->vc_start[v + 1] += s->vc_start[v];
  int *fill = xcalloc((size_t)s->nvars + 1, sizeof *fill);
  s->vc = xmalloc((size_t)(s->vc_start[s->nvars] + 1) * sizeof *s->vc);
  for (int c = 0; c < s->ncons; c++)
    for (int i = 0; i < s->cons[c].n; i++) {
      int v = s->cons[c].lit[i] >> 1;
      s->vc[s->vc_start[v] + fill[v]++] = c;
    }
  free(fill);
  for (int c = 0; c < s->ncons; c++) {
    const Cons *k = &s->cons[c];
    if (k->kind == LAYER_TACO_TACO) s->stats.taco_taco++;
    else if (k->kind == LAYER_TACO_TORTILLA) s->stats.taco_tortilla++;
    else s->stats.tortilla_tortilla++;
  }
}

/* ---- variables from the cells ------------------------------------------ */

/* Every pair of faces sharing a cell: in each cell, the faces it gained
** over the cell its set came from, paired with all of its faces. */
static void make_variables(LayerSolver *s) {
  const Arrangement *a = &s->arr;
  size_t n = 0, cap = 16;
  uint64_t *k = xmalloc(cap * sizeof *k);
  for (int c = 0; c < a->ncells; c++) {
    const int *cf = a->cell_face + a->cell_face_start[c];
    int nc = a->cell_face_start[c + 1] - a->cell_face_start[c], p = a->cell_parent[c];
    const int *pf = p >= 0 ? a->cell_face + a->cell_face_start[p] : NULL;
    int np = p >= 0 ? a->cell_face_start[p + 1] - a->cell_face_start[p] : 0, j = 0;
    for (int i = 0; i < nc; i++) {
      while (j < np && pf[j] < cf[i]) j++;
      if (j < np && pf[j] == cf[i]) continue;         /* not new here */
      for (int m = 0; m < nc; m++) {
        if (m == i) continue;
        int f = cf[i] < cf[m] ? cf[i] : cf[m], g = cf[i] ^ cf[m] ^ f;
        if (n == cap) k = xrealloc(k, (cap *= 2) * sizeof *k);
        k[n++] = ((uint64_t)f << 32) | (uint32_t)g;
      }
    }
  }
  n = sort_unique_u64(k, n);
  s->nvars = (int)n;
  s->key = k;
  s->row = xcalloc((size_t)s->in.nfaces + 1, sizeof *s->row);
  for (size_t i = 0; i < n; i++) s->row[(k[i] >> 32) + 1]++;
  for (int f = 0; f < s->in.nfaces; f++) s->row[f + 1] += s->row[f];
}

/* ---- transitivity -------------------------------------------------------- */

typedef struct Triple { int tortilla, a, b; } Triple;

static int cmp_triple(const void *x, const void *y) {
  const Triple *p = x, *q = y;
  if (p->tortilla != q->tortilla) return p->tortilla - q->tortilla;
  if (p->a != q->a) return p->a - q->a;
  return p->b - q->b;
}

static int uf_root(int *up, int x) {
  while (up[x] != x) x = up[x] = up[up[x]];
  return x;
}

/* For each face t, the faces that taco-tortilla constraints with t as the
** tortilla join into groups: two faces of one group lie on one side of t. */
static void tortilla_groups(LayerSolver *s) {
  int nf = s->in.nfaces, n = 0;
  Triple *t = xmalloc((size_t)(s->ncons + 1) * sizeof *t);
  for (int c = 0; c < s->ncons; c++)
    if (s->cons[c].kind == LAYER_TACO_TORTILLA && s->cons[c].taco)
      t[n++] = (Triple){s->cons[c].face[2], s->cons[c].face[0], s->cons[c].face[1]};
  qsort(t, (size_t)n, sizeof *t, cmp_triple);
  s->cc_start = xcalloc((size_t)nf + 1, sizeof *s->cc_start);
  s->cc_face = xmalloc((size_t)(2 * n + 1) * sizeof *s->cc_face);
  s->cc_comp = xmalloc((size_t)(2 * n + 1) * sizeof *s->cc_comp);
  int *up = xmalloc((size_t)(2 * n + 1) * sizeof *up), total = 0;
  for (int i = 0; i < n;) {
    int j = i, base = total;
    while (j < n && t[j].tortilla == t[i].tortilla) {
      s->cc_face[total++] = t[j].a;
      s->cc_face[total++] = t[j].b;
      j++;
    }
    qsort(s->cc_face + base, (size_t)(total - base), sizeof(int), cmp_int_asc);
    int m = base;
    for (int k = base; k < total; k++)
      if (m == base || s->cc_face[m - 1] != s->cc_face[k]) s->cc_face[m++] = s->cc_face[k];
    total = m;
    for (int k = base; k < total; k++) up[k] = k;
    for (int k = i; k < j; k++) {
      int x = cc_local(s->cc_face + base, total - base, t[k].a) + base;
      int y = cc_local(s->cc_face + base, total - base, t[k].b) + base;
      up[uf_root(up, x)] = uf_root(up, y);
    }
    for (int k = base; k < total; k++) s->cc_comp[k] = uf_root(up, k);
    s->cc_start[t[i].tortilla + 1] = total - base;
    i = j;
  }
  for (int f = 0; f < nf; f++) s->cc_start[f + 1] += s->cc_start[f];
  free(up);
  free(t);
}

static void dense_init(Dense *d, int n) {
  d->gen = xcalloc((size_t)n + 1, sizeof *d->gen);
  d->val = xmalloc((size_t)(n + 1) * sizeof *d->val);
}

static void dense_free(Dense *d) {
  free(d->gen);
  free(d->val);
}

static int dense_get(const Dense *d, int f, int gen) { return d->gen[f] == gen ? d->val[f] : -1; }

static void scatter(Dense *d, const int (*pairs)[2], int from, int to, int gen) {
  for (int k = from; k < to; k++) d->gen[pairs[k][0]] = gen, d->val[pairs[k][0]] = pairs[k][1];
}

/* Each face's overlapping faces with their variables, both ways round. */
static void face_adjacency(LayerSolver *s) {
  int nf = s->in.nfaces;
  s->adj_start = xcalloc((size_t)nf + 1, sizeof *s->adj_start);
  for (int v = 0; v < s->nvars; v++) s->adj_start[var_f1(s, v) + 1]++, s->adj_start[var_f2(s, v) + 1]++;
  for (int f = 0; f < nf; f++) s->adj_start[f + 1] += s->adj_start[f];
  int *fill = xcalloc((size_t)nf + 1, sizeof *fill);
  s->adj = xmalloc((size_t)(2 * s->nvars + 1) * sizeof *s->adj);
  for (int v = 0; v < s->nvars; v++) {                      /* ascending v: rows come out by face */
    int f = var_f1(s, v), g = var_f2(s, v);
    s->adj[s->adj_start[g] + fill[g]][0] = f, s->adj[s->adj_start[g] + fill[g]++][1] = v;
  }
  for (int v = 0; v < s->nvars; v++) {
    int f = var_f1(s, v), g = var_f2(s, v);
    s->adj[s->adj_start[f] + fill[f]][0] = g, s->adj[s->adj_start[f] + fill[f]++][1] = v;
  }
  free(fill);
}

/* The tortilla groups turned around: for each face, the tortillas whose
** taco-tortillas join it, with its group there (ascending tortilla). */
static void tortilla_index(LayerSolver *s) {
  int nf = s->in.nfaces, total = s->cc_start[nf];
  s->cct_start = xcalloc((size_t)nf + 1, sizeof *s->cct_start);
  for (int k = 0; k < total; k++) s->cct_start[s->cc_face[k] + 1]++;
  for (int f = 0; f < nf; f++) s->cct_start[f + 1] += s->cct_start[f];
  int *fill = xcalloc((size_t)nf + 1, sizeof *fill);
  s->cct = xmalloc((size_t)(total + 1) * sizeof *s->cct);
  for (int t = 0; t < nf; t++)
    for (int k = s->cc_start[t]; k < s->cc_start[t + 1]; k++) {
      int f = s->cc_face[k];
      s->cct[s->cct_start[f] + fill[f]][0] = t;
      s->cct[s->cct_start[f] + fill[f]++][1] = s->cc_comp[k];
    }
  free(fill);
}

/* The third faces of variable v's transitivity constraints into s->third
** (with their literals in s->third_lit): every face over a cell both of
** v's faces cover, less those a tortilla's taco-tortillas already keep
** from a cycle (one of the three faces joins the other two on one side). */
static int third_faces(LayerSolver *s, int v) {
  const Arrangement *a = &s->arr;
  int f1 = var_f1(s, v), f2 = var_f2(s, v), gen = ++s->gen;
  scatter(&s->near1, (const int (*)[2])s->adj, s->adj_start[f1], s->adj_start[f1 + 1], gen);
  scatter(&s->near2, (const int (*)[2])s->adj, s->adj_start[f2], s->adj_start[f2 + 1], gen);
  for (int k = s->cc_start[f1]; k < s->cc_start[f1 + 1]; k++)
    s->group1.gen[s->cc_face[k]] = gen, s->group1.val[s->cc_face[k]] = s->cc_comp[k];
  for (int k = s->cc_start[f2]; k < s->cc_start[f2 + 1]; k++)
    s->group2.gen[s->cc_face[k]] = gen, s->group2.val[s->cc_face[k]] = s->cc_comp[k];
  for (int i = s->cct_start[f1], j = s->cct_start[f2]; i < s->cct_start[f1 + 1] && j < s->cct_start[f2 + 1];) {
    if (s->cct[i][0] < s->cct[j][0]) i++;                  /* tortillas joining f1 and f2 */
    else if (s->cct[j][0] < s->cct[i][0]) j++;
    else {
      if (s->cct[i][1] == s->cct[j][1]) s->joined.gen[s->cct[i][0]] = gen;
      i++, j++;
    }
  }
  int c12 = dense_get(&s->group1, f2, gen), c21 = dense_get(&s->group2, f1, gen);
  const int *x = a->face_cell + a->face_cell_start[f1], *xe = a->face_cell + a->face_cell_start[f1 + 1];
  const int *y = a->face_cell + a->face_cell_start[f2], *ye = a->face_cell + a->face_cell_start[f2 + 1];
  int n = 0, m = 0;
  s->stamp[f1] = s->stamp[f2] = gen;
  while (x < xe && y < ye) {
    if (*x < *y) x++;
    else if (*y < *x) y++;
    else {
      for (int k = a->cell_face_start[*x]; k < a->cell_face_start[*x + 1]; k++) {
        int f3 = a->cell_face[k];
        if (s->stamp[f3] == gen) continue;
        s->stamp[f3] = gen;
        n++;
        if ((c12 >= 0 && dense_get(&s->group1, f3, gen) == c12) ||
            (c21 >= 0 && dense_get(&s->group2, f3, gen) == c21) || s->joined.gen[f3] == gen)
          continue;
        s->third[m] = f3;
        s->third_lit[m][0] = 2 * s->near2.val[f3] + (f2 > f3);
        s->third_lit[m][1] = 2 * s->near1.val[f3] + (f3 > f1);
        m++;
      }
      x++, y++;
    }
  }
  s->trans_all += n;
  s->trans_reduced += m;
  return s->nthird = m;
}

/* ---- propagation ------------------------------------------------------ */

static int crease_lit(const LayerSolver *s, int e);

static void chain_add(int **list, int *n, int *cap, int x) {
  *list = xgrow(*list, cap, *n + 1, sizeof **list);
  (*list)[(*n)++] = x;
}

static int unique_ints(int *l, int n) {
  qsort(l, (size_t)n, sizeof *l, cmp_int_asc);
  int m = 0;
  for (int i = 0; i < n; i++)
    if (m == 0 || l[m - 1] != l[i]) l[m++] = l[i];
  return m;
}

/* The variables a reason rests on, into out (room for 6). */
static int why_vars(const LayerSolver *s, Why w, int *out) {
  if (w.kind == WHY_CONS) {
    const Cons *c = &s->cons[w.a];
    for (int i = 0; i < c->n; i++) out[i] = c->lit[i] >> 1;
    return c->n;
  }
  if (w.kind == WHY_CREASE) {
    out[0] = crease_lit(s, w.a) >> 1;
    return 1;
  }
  if (w.kind == WHY_TRANS) {
    int f1 = var_f1(s, w.a), f2 = var_f2(s, w.a);
    out[0] = w.a, out[1] = var_find(s, f2, w.b), out[2] = var_find(s, w.b, f1);
    return 3;
  }
  return 0;
}

/* Record why the forced orders fail at constraint `why` (faces[nf] its
** faces): follow each variable's reason back to the creases. */
static void record_conflict(LayerSolver *s, int kind, const int *faces, int nf, Why why) {
  LayerConflict *c = &s->conflict;
  if (s->has_conflict || !s->recording) return;
  s->has_conflict = 1;
  c->kind = kind;
  c->nfaces = nf;
  for (int i = 0; i < nf; i++) c->faces[i] = faces[i];
  int n = 0, cap = 0, fcap = 0, ecap = 0, *stack = NULL, vars[6];
  unsigned char *seen = xcalloc((size_t)s->nvars + 1, 1);
  int nv = why_vars(s, why, vars);
  for (int i = 0; i < nv; i++) chain_add(&stack, &n, &cap, vars[i]);
  if (why.kind == WHY_CREASE) chain_add(&c->chain_edges, &c->nchain_edges, &ecap, why.a);
  while (n > 0) {
    int v = stack[--n];
    if (v < 0 || seen[v]) continue;
    seen[v] = 1;
    chain_add(&c->chain_faces, &c->nchain_faces, &fcap, var_f1(s, v));
    chain_add(&c->chain_faces, &c->nchain_faces, &fcap, var_f2(s, v));
    if (s->val[v] == 0) continue;
    if (s->why[v].kind == WHY_CREASE) chain_add(&c->chain_edges, &c->nchain_edges, &ecap, s->why[v].a);
    nv = why_vars(s, s->why[v], vars);
    for (int i = 0; i < nv; i++) chain_add(&stack, &n, &cap, vars[i]);
  }
  c->nchain_faces = unique_ints(c->chain_faces, c->nchain_faces);
  c->nchain_edges = unique_ints(c->chain_edges, c->nchain_edges);
  free(seen);
  free(stack);
}

/* Apply the implied literals imp[n]; 0 on a clash among them. */
static int apply(LayerSolver *s, const int *imp, int n, Why why) {
  for (int i = 0; i < n; i++) {
    int lit = imp[i] >> 1, value = imp[i] & 1, now = lit_value(s, lit);
    if (now < 0) assign(s, lit, value, why);
    else if (now != value) return 0;
  }
  return 1;
}

static int check_cons(LayerSolver *s, int c) {
  const Cons *k = &s->cons[c];
  int imp[6], dead, r = gac(s, k->lit, k->n, cons_mask(k->kind, k->n), imp, &dead);
  Why why = {WHY_CONS, c, 0};
  if (r < 0 || !apply(s, imp, r, why)) {
    record_conflict(s, k->kind, k->face, k->kind == LAYER_TACO_TACO || k->face[3] >= 0 ? 4 : 3, why);
    return 0;
  }
  return 1;
}

static int check_triple(LayerSolver *s, int v, int f3, const int lit[3]) {
  int imp[3], dead, r = gac(s, lit, 3, VALID_TRANS, imp, &dead);
  Why why = {WHY_TRANS, v, f3};
  if (r < 0 || !apply(s, imp, r, why)) {
    int faces[3] = {var_f1(s, v), var_f2(s, v), f3};
    record_conflict(s, LAYER_TRANSITIVITY, faces, 3, why);
    return 0;
  }
  return 1;
}

static void triple_lits(const LayerSolver *s, int v, int k, int lit[3]) {
  lit[0] = 2 * v;
  lit[1] = s->third_lit[k][0];
  lit[2] = s->third_lit[k][1];
}

/* Every constraint of variable v, just assigned. */
static int visit(LayerSolver *s, int v) {
  for (int k = s->vc_start[v]; k < s->vc_start[v + 1]; k++)
    if (!check_cons(s, s->vc[k])) return 0;
  int lit[3];
  if (s->cached) {
    for (int k = s->tc_start[v]; k < s->tc_start[v + 1]; k++) {
      lit[0] = 2 * v, lit[1] = s->tc[k][0], lit[2] = s->tc[k][1];
      if (!check_triple(s, v, -1, lit)) return 0;
    }
    return 1;
  }
  int n = third_faces(s, v);
  for (int k = 0; k < n; k++) {
    triple_lits(s, v, k, lit);
    if (!check_triple(s, v, s->third[k], lit)) return 0;
  }
  return 1;
}

/* Propagate the assignments on the trail from position head on. */
static int propagate(LayerSolver *s, int head) {
  while (head < s->ntrail)
    if (!visit(s, s->trail[head++])) return 0;
  return 1;
}

/* ---- the orders the creases force -------------------------------------- */

/* The order an M/V crease puts on its two faces: a valley puts each face
** on the side its neighbour's paper normal points to. Returns the literal
** "upper over lower", or -1. */
static int crease_lit(const LayerSolver *s, int e) {
  char as = s->in.assign[e];
  int f = s->in.edge_faces[e][0], g = s->in.edge_faces[e][1];
  if ((as != 'M' && as != 'V') || f < 0 || g < 0 || s->in.flipped[f] == s->in.flipped[g]) return -1;
  int sgn = as == 'V' ? 1 : -1, og = s->in.flipped[g] ? -1 : 1;
  int up = sgn * og > 0 ? f : g;
  return lit_of(s, up, up == f ? g : f);
}

static int presolve(LayerSolver *s) {
  s->recording = 1;
  for (int e = 0; e < s->in.nedges; e++) {
    int lit = crease_lit(s, e);
    if (lit < 0) continue;
    int now = lit_value(s, lit);
    Why why = {WHY_CREASE, e, 0};
    if (now < 0) assign(s, lit, 1, why);
    else if (now == 0) {
      int v = lit >> 1, faces[2] = {var_f1(s, v), var_f2(s, v)};
      record_conflict(s, -1, faces, 2, why);     /* the chain reaches the other crease through v */
      return 0;
    }
  }
  s->stats.fixed = s->ntrail;
  int ok = propagate(s, 0);
  s->stats.fixed = s->ntrail;
  s->recording = 0;
  return ok;
}

/* ---- components ---------------------------------------------------------- */

static void union_vars(LayerSolver *s, int *up, int v, const int *lit, int n) {
  for (int i = 0; i < n; i++) {
    int w = lit[i] >> 1;
    if (s->val[w] == 0) up[uf_root(up, w)] = uf_root(up, v);
  }
}

/* Keep the live transitivity constraints of the open variables (the
** search visits them many times) and join the open variables that live
** constraints share into components. */
static void components(LayerSolver *s) {
  int nv = s->nvars, *up = xmalloc((size_t)(nv + 1) * sizeof *up), cap = 0, imp[6], dead;
  for (int v = 0; v < nv; v++) up[v] = v;
  s->tc_start = xcalloc((size_t)nv + 1, sizeof *s->tc_start);
  int ntc = 0;
  for (int v = 0; v < nv; v++) {
    s->tc_start[v] = ntc;
    if (s->val[v]) continue;
    for (int k = s->vc_start[v]; k < s->vc_start[v + 1]; k++) {
      const Cons *c = &s->cons[s->vc[k]];
      gac(s, c->lit, c->n, cons_mask(c->kind, c->n), imp, &dead);
      if (!dead) union_vars(s, up, v, c->lit, c->n);
    }
    int n = third_faces(s, v), lit[3];
    for (int k = 0; k < n; k++) {
      triple_lits(s, v, k, lit);
      gac(s, lit, 3, VALID_TRANS, imp, &dead);
      if (dead) continue;
      union_vars(s, up, v, lit, 3);
      s->tc = xgrow(s->tc, &cap, ntc + 1, sizeof *s->tc);
      s->tc[ntc][0] = lit[1], s->tc[ntc][1] = lit[2];
      ntc++;
    }
  }
  s->tc_start[nv] = ntc;
  s->cached = 1;
  /* components: open variables by root, ordered by size, then first variable */
  int *size = xcalloc((size_t)nv + 1, sizeof *size), *id = xmalloc((size_t)(nv + 1) * sizeof *id);
  for (int v = 0; v < nv; v++)
    if (!s->val[v]) size[uf_root(up, v)]++;
  Triple *order = xmalloc((size_t)(nv + 1) * sizeof *order);
  int nc = 0;
  for (int v = 0; v < nv; v++)
    if (!s->val[v] && uf_root(up, v) == v) order[nc++] = (Triple){size[v], v, 0};
  qsort(order, (size_t)nc, sizeof *order, cmp_triple);
  for (int c = 0; c < nc; c++) id[order[c].a] = c;
  s->ncomp = nc;
  s->comp_start = xcalloc((size_t)nc + 1, sizeof *s->comp_start);
  for (int c = 0; c < nc; c++) s->comp_start[c + 1] = s->comp_start[c] + order[c].tortilla;
  s->comp_var = xmalloc((size_t)(s->comp_start[nc] + 1) * sizeof *s->comp_var);
  int *fill = xcalloc((size_t)nc + 1, sizeof *fill);
  for (int v = 0; v < nv; v++)
    if (!s->val[v]) {
      int c = id[uf_root(up, v)];
      s->comp_var[s->comp_start[c] + fill[c]++] = v;
    }
  s->count = xmalloc((size_t)(nc + 1) * sizeof *s->count);
  s->count_limit = xcalloc((size_t)nc + 1, sizeof *s->count_limit);
  for (int c = 0; c < nc; c++) s->count[c] = -1;
  s->comp_picked = xcalloc((size_t)nc + 1, 1);
  free(fill);
  free(order);
  free(id);
  free(size);
  free(up);
}

/* ---- search ------------------------------------------------------------ */

/* Enumerate component c's states depth first (each choice: f1 over f2
** first) until limit are found; with target >= 0, stop at state target
** and leave it assigned on the trail. Returns the number found. */
static long search(LayerSolver *s, int c, long limit, long target) {
  const int *vars = s->comp_var + s->comp_start[c];
  int n = s->comp_start[c + 1] - s->comp_start[c], base = s->ntrail, nf = 0, cap = 0, pos = 0;
  Frame *st = NULL;
  long found = 0;
  for (;;) {
    while (pos < n && s->val[vars[pos]]) pos++;
    int ok = 1;
    if (pos == n) {
      if (found++ == target) break;                 /* keep this one */
      if (found >= limit) { undo_to(s, base); break; }
      ok = 0;
    } else {                                        /* choose: f1 over f2 */
      st = xgrow(st, &cap, nf + 1, sizeof *st);
      st[nf++] = (Frame){vars[pos], s->ntrail, pos, 0};
      assign(s, 2 * vars[pos], 1, (Why){WHY_NONE, 0, 0});
      ok = propagate(s, s->ntrail - 1);
    }
    while (!ok && nf > 0) {                         /* back to the last choice with a way left */
      Frame *f = &st[nf - 1];
      undo_to(s, f->trail);
      if (f->second) { nf--; continue; }
      f->second = 1;
      pos = f->pos;
      assign(s, 2 * f->var, 0, (Why){WHY_NONE, 0, 0});
      ok = propagate(s, s->ntrail - 1);
    }
    if (!ok) { undo_to(s, base); break; }
  }
  free(st);
  return found;
}

/* ---- public entries ---------------------------------------------------- */

LayerSolver *layer_new(const LayerInput *in, char *err, size_t errlen) {
  if (!VALID_TACO_TACO) VALID_TACO_TACO = taco_taco_mask();
  LayerSolver *s = xcalloc(1, sizeof *s);
  s->in = *in;
  if (arrangement_build(in->nverts, in->folded, in->nedges, in->edge_verts, in->edge_faces, in->nfaces,
                        &s->arr, err, errlen)) {
    free(s);
    return NULL;
  }
  make_variables(s);
  int nv = s->nvars, nf = in->nfaces;
  s->val = xcalloc((size_t)nv + 1, 1);
  s->picked = xcalloc((size_t)nv + 1, 1);
  s->why = xcalloc((size_t)nv + 1, sizeof *s->why);
  s->trail = xmalloc((size_t)(nv + 1) * sizeof *s->trail);
  s->stamp = xcalloc((size_t)nf + 1, sizeof *s->stamp);
  s->third = xmalloc((size_t)(nf + 1) * sizeof *s->third);
  s->third_lit = xmalloc((size_t)(nf + 1) * sizeof *s->third_lit);
  Dense *d[5] = {&s->near1, &s->near2, &s->group1, &s->group2, &s->joined};
  for (int i = 0; i < 5; i++) dense_init(d[i], nf);
  face_adjacency(s);
  edge_edge(s);
  edge_face(s);
  var_cons_index(s);
  tortilla_groups(s);
  tortilla_index(s);
  s->stats.points = s->arr.npoints;
  s->stats.segments = s->arr.nsegs;
  s->stats.cells = s->arr.ncells;
  s->stats.eps_log2 = s->arr.eps_log2;
  s->stats.variables = nv;
  if (presolve(s)) components(s);
  s->stats.transitivity = s->trans_all / 3;
  return s;
}

void layer_free(LayerSolver *s) {
  if (!s) return;
  arrangement_free(&s->arr);
  free(s->key);
  free(s->row);
  free(s->val);
  free(s->picked);
  free(s->why);
  free(s->trail);
  free(s->stamp);
  free(s->third);
  free(s->third_lit);
  free(s->adj);
  free(s->adj_start);
  free(s->cct);
  free(s->cct_start);
  Dense *d[5] = {&s->near1, &s->near2, &s->group1, &s->group2, &s->joined};
  for (int i = 0; i < 5; i++) dense_free(d[i]);
  free(s->cons);
  free(s->vc_start);
  free(s->vc);
  free(s->cc_start);
  free(s->cc_face);
  free(s->cc_comp);
  free(s->tc_start);
  free(s->tc);
  free(s->comp_start);
  free(s->comp_var);
  free(s->count);
  free(s->count_limit);
  free(s->comp_picked);
  free(s->conflict.chain_faces);
  free(s->conflict.chain_edges);
  free(s);
}

const LayerConflict *layer_conflict(const LayerSolver *s) { return s->has_conflict ? &s->conflict : NULL; }

LayerStats layer_stats(const LayerSolver *s) { return s->stats; }

int layer_ncomponents(const LayerSolver *s) { return s->ncomp; }

int layer_component_vars(const LayerSolver *s, int c) { return s->comp_start[c + 1] - s->comp_start[c]; }

int layer_component_faces(const LayerSolver *s, int c, int *faces) {
  LayerSolver *w = (LayerSolver *)s;          /* only the scratch stamps change */
  int n = 0, gen = ++w->gen;
  for (int k = s->comp_start[c]; k < s->comp_start[c + 1]; k++) {
    int v = s->comp_var[k], f[2] = {var_f1(s, v), var_f2(s, v)};
    for (int i = 0; i < 2; i++)
      if (s->stamp[f[i]] != gen) s->stamp[f[i]] = gen, faces[n++] = f[i];
  }
  qsort(faces, (size_t)n, sizeof *faces, cmp_int_asc);
  return n;
}

static void component_conflict(LayerSolver *s, int c) {
  if (s->has_conflict) return;
  s->has_conflict = 1;
  s->conflict.kind = -2;
  s->conflict.chain_faces = xmalloc((size_t)(s->in.nfaces + 1) * sizeof(int));
  s->conflict.nchain_faces = layer_component_faces(s, c, s->conflict.chain_faces);
}

long layer_count(LayerSolver *s, int c, long limit) {
  /* counted before: reuse it unless it stopped at a lower limit */
  if (s->count[c] < 0 || (s->count[c] == s->count_limit[c] && s->count_limit[c] < limit)) {
    s->count[c] = search(s, c, limit, -1);
    s->count_limit[c] = limit;
    if (s->count[c] == 0) component_conflict(s, c);
  }
  return s->count[c] < limit ? s->count[c] : limit;
}

int layer_pick(LayerSolver *s, int c, long k) {
  int mark = s->ntrail;
  long found = search(s, c, k + 1, k);
  if (found <= k) {
    if (found == 0) component_conflict(s, c);
    return 0;
  }
  for (int i = mark; i < s->ntrail; i++) s->picked[s->trail[i]] = s->val[s->trail[i]];
  undo_to(s, mark);
  s->comp_picked[c] = 1;
  return 1;
}

int layer_orders(LayerSolver *s, void (*out)(void *user, int upper, int lower), void *user) {
  if (s->has_conflict && s->conflict.kind != -2) return 0;
  for (int c = 0; c < s->ncomp; c++)
    if (!s->comp_picked[c] && !layer_pick(s, c, 0)) return 0;
  for (int v = 0; v < s->nvars; v++) {
    int x = s->val[v] ? s->val[v] : s->picked[v], f1 = var_f1(s, v), f2 = var_f2(s, v);
    if (x > 0) out(user, f1, f2);
    else out(user, f2, f1);
  }
  return 1;
}

int layer_overlap(const LayerSolver *s, int i, int j) { return var_find(s, i, j) >= 0; }

long layer_check(const LayerSolver *s, int (*above)(void *user, int i, int j), void *user,
                 LayerConflict *conflict) {
  LayerSolver *w = (LayerSolver *)s;          /* values are put back before returning */
  signed char *saved = xmalloc((size_t)s->nvars + 1);
  memcpy(saved, s->val, (size_t)s->nvars);
  long broken = 0;
  int imp[6], dead;
  memset(conflict, 0, sizeof *conflict);
  for (int v = 0; v < s->nvars; v++) {
    int f1 = var_f1(s, v), f2 = var_f2(s, v), a = above(user, f1, f2), b = above(user, f2, f1);
    w->val[v] = (signed char)(a && !b ? 1 : b && !a ? -1 : 0);   /* an open pair may go either way */
    if (a && b && broken++ == 0) *conflict = (LayerConflict){.kind = -3, .nfaces = 2, .faces = {f1, f2}};
  }
  for (int e = 0; e < s->in.nedges; e++) {
    int lit = crease_lit(s, e);
    if (lit >= 0 && lit_value(s, lit) == 0 && broken++ == 0) {
      int v = lit >> 1;
      *conflict = (LayerConflict){.kind = -1, .nfaces = 2, .faces = {var_f1(s, v), var_f2(s, v)}};
    }
  }
  for (int c = 0; c < s->ncons; c++) {
    const Cons *k = &s->cons[c];
    if (gac(s, k->lit, k->n, cons_mask(k->kind, k->n), imp, &dead) < 0 && broken++ == 0) {
      *conflict = (LayerConflict){.kind = k->kind, .nfaces = k->face[3] >= 0 ? 4 : 3};
      memcpy(conflict->faces, k->face, sizeof k->face);
    }
  }
  for (int v = 0; v < s->nvars; v++) {
    int n = third_faces(w, v), lit[3];
    for (int k = 0; k < n; k++) {
      triple_lits(s, v, k, lit);
      if (gac(s, lit, 3, VALID_TRANS, imp, &dead) < 0 && broken++ == 0)
        *conflict = (LayerConflict){.kind = LAYER_TRANSITIVITY, .nfaces = 3,
                                    .faces = {var_f1(s, v), var_f2(s, v), s->third[k], -1}};
    }
  }
  memcpy(w->val, saved, (size_t)s->nvars);
  free(saved);
  return broken;
}
