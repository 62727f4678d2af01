/*
** An origami model as the layer solver's input (origami_layers.h).
*/
#include "origami_layers.h"

#include <stdlib.h>

#include "../base/mem.h"
#include "../base/sort.h"

void origami_layers_init(const OrigamiModel *m, OrigamiLayers *out) {
  int total = m->face_start[m->nfaces], n = m->ncreases;
  /* edges: the creases, then face edges without one */
  uint64_t *extra = xmalloc((size_t)(total + 1) * sizeof *extra);
  int nextra = 0;
  for (int f = 0; f < m->nfaces; f++)
    for (int k = m->face_start[f]; k < m->face_start[f + 1]; k++) {
      if (m->face_crease[k] >= 0) continue;
      int u = m->face_index[k], v = m->face_index[k + 1 < m->face_start[f + 1] ? k + 1 : m->face_start[f]];
      int a = u < v ? u : v, b = u ^ v ^ a;
      extra[nextra++] = ((uint64_t)a << 32) | (uint32_t)b;
    }
  nextra = (int)sort_unique_u64(extra, (size_t)nextra);
  int ne = n + nextra;
  out->edge_verts = xmalloc((size_t)(ne + 1) * sizeof *out->edge_verts);
  out->edge_faces = xmalloc((size_t)(ne + 1) * sizeof *out->edge_faces);
  out->assign = xmalloc((size_t)ne + 1);
  out->edge_crease = xmalloc((size_t)(ne + 1) * sizeof *out->edge_crease);
  for (int e = 0; e < ne; e++) {
    int a, b;
    if (e < n) a = m->creases[e].a, b = m->creases[e].b;
    else a = (int)(extra[e - n] >> 32), b = (int)(uint32_t)extra[e - n];
    out->edge_verts[e][0] = a < b ? a : b;
    out->edge_verts[e][1] = a < b ? b : a;
    out->edge_faces[e][0] = out->edge_faces[e][1] = -1;
    out->assign[e] = e < n ? m->creases[e].assignment : 'B';
    out->edge_crease[e] = e < n ? e : -1;
  }
  for (int f = 0; f < m->nfaces; f++)
    for (int k = m->face_start[f]; k < m->face_start[f + 1]; k++) {
      int u = m->face_index[k], v = m->face_index[k + 1 < m->face_start[f + 1] ? k + 1 : m->face_start[f]];
      int e = m->face_crease[k];
      if (e < 0) {                                          /* find it among the extra edges */
        uint64_t key = ((uint64_t)(u < v ? u : v) << 32) | (uint32_t)(u < v ? v : u);
        int lo = 0, hi = nextra;
        while (lo < hi) {
          int mid = (lo + hi) / 2;
          if (extra[mid] < key) lo = mid + 1;
          else hi = mid;
        }
        e = n + lo;
      }
      out->edge_faces[e][u < v ? 1 : 0] = f;               /* CCW face: on the left of u -> v */
    }
  free(extra);
  out->in = (LayerInput){m->nverts, m->folded, m->nfaces, m->flipped, ne,
                         (const int (*)[2])out->edge_verts, (const int (*)[2])out->edge_faces, out->assign};
}

void origami_layers_free(OrigamiLayers *l) {
  free(l->edge_verts);
  free(l->edge_faces);
  free(l->assign);
  free(l->edge_crease);
}

static const char *conflict_name(int kind) {
  switch (kind) {
  case LAYER_TACO_TACO: return "taco-taco";
  case LAYER_TACO_TORTILLA: return "taco-tortilla";
  case LAYER_TORTILLA_TORTILLA: return "tortilla-tortilla";
  case LAYER_TRANSITIVITY: return "transitivity";
  default: return "crease";
  }
}

static void list_ints(char *buf, size_t len, const int *v, int n, int cap) {
  size_t at = 0;
  buf[0] = 0;
  for (int i = 0; i < n && i < cap && at + 16 < len; i++)
    at += (size_t)snprintf(buf + at, len - at, "%s%d", i ? ", " : "", v[i]);
  if (n > cap && at + 8 < len) snprintf(buf + at, len - at, ", ...");
}

#define REPORT_CREASES 6      /* notes at most at this many creases of a conflict */

void origami_layers_report(const OrigamiModel *m, const OrigamiLayers *l, const LayerConflict *c) {
  char faces[256], chain[512];
  list_ints(faces, sizeof faces, c->faces, c->nfaces, 4);
  list_ints(chain, sizeof chain, c->chain_faces, c->nchain_faces, 40);
  if (c->kind == -2)
    diag_error(m->loc, "no valid layer order: faces %s cannot be stacked without breaking a "
               "constraint (every order of that component fails)", chain);
  else if (c->kind == -1)
    diag_error(m->loc, "no valid layer order: two creases force opposite orders on faces %s", faces);
  else
    diag_error(m->loc, "no valid layer order: the %s constraint on faces %s cannot hold with the "
               "orders the creases force (faces involved: %s)", conflict_name(c->kind), faces, chain);
  for (int i = 0; i < c->nchain_edges && i < REPORT_CREASES; i++) {
    int e = c->chain_edges[i], k = l->edge_crease[e];
    const int *v = l->edge_verts[e];
    SrcRange at = k >= 0 && m->creases[k].loc.file >= 0 ? m->creases[k].loc : m->loc;
    diag_note(at, "the %s crease %d-%d (between faces %d and %d) forces part of it",
              l->assign[e] == 'V' ? "valley" : "mountain", v[0], v[1], l->edge_faces[e][0],
              l->edge_faces[e][1]);
  }
  if (c->nchain_edges > REPORT_CREASES)
    diag_note(m->loc, "and %d more creases", c->nchain_edges - REPORT_CREASES);
}

static void set_order(void *user, int upper, int lower) {
  OrigamiModel *m = user;
  m->above[(size_t)upper * (size_t)m->row_words + ((unsigned)lower >> 6)] |= (uint64_t)1 << (lower & 63);
}

int origami_layers_apply(OrigamiModel *m, const OrigamiLayers *l, LayerSolver *s) {
  if (!layer_orders(s, set_order, m)) {
    origami_layers_report(m, l, layer_conflict(s));
    return 0;
  }
  for (int e = 0; e < l->in.nedges; e++) {                 /* U creases take the order's fold */
    int f = l->edge_faces[e][0], g = l->edge_faces[e][1], k = l->edge_crease[e];
    if (k < 0 || l->assign[e] != 'U' || f < 0 || g < 0 || m->flipped[f] == m->flipped[g]) continue;
    int f_up = origami_is_above(m, f, g), og = m->flipped[g] ? -1 : 1;
    /* a valley puts f over g exactly when g faces up (origami.c, crease_order) */
    m->creases[k].assignment = (f_up ? og : -og) > 0 ? 'V' : 'M';
  }
  return 1;
}

int origami_layers_pick(LayerSolver *s, long k, long limit, double *total) {
  *total = 1;
  for (int c = 0; c < layer_ncomponents(s); c++) {
    long n = k > 0 ? layer_count(s, c, limit) : 1;
    *total *= (double)layer_count(s, c, k > 0 ? limit : 1);
    if (n == 0) return 0;
    if (!layer_pick(s, c, k % n)) return 0;
    k /= n;
  }
  return k == 0;
}

typedef struct OrderList { int (*o)[2]; long n, cap; } OrderList;

static void collect_order(void *user, int upper, int lower) {
  OrderList *l = user;
  if (l->n == l->cap) l->o = xrealloc(l->o, (size_t)(l->cap = l->cap ? 2 * l->cap : 64) * sizeof *l->o);
  l->o[l->n][0] = upper;
  l->o[l->n][1] = lower;
  l->n++;
}

int (*origami_layers_orders(LayerSolver *s, long *n))[2] {
  OrderList l = {0};
  layer_orders(s, collect_order, &l);
  *n = l.n;
  return l.o;
}

/* Decimal product of the counts, as text (it outgrows any integer). */
static void product_text(const long *v, int n, char *out, size_t len) {
  int digits[400] = {1}, nd = 1;                            /* little-endian decimal */
  for (int i = 0; i < n; i++) {
    long carry = 0;
    for (int d = 0; d < nd; d++) {
      long x = digits[d] * v[i] + carry;
      digits[d] = (int)(x % 10);
      carry = x / 10;
    }
    while (carry && nd < 400) digits[nd++] = (int)(carry % 10), carry /= 10;
  }
  size_t k = 0;
  for (int d = nd - 1; d >= 0 && k + 1 < len; d--) out[k++] = (char)('0' + digits[d]);
  out[k] = 0;
}

int origami_layers_print(FILE *out, const OrigamiModel *m, const OrigamiLayers *l, LayerSolver *s,
                         int count, long limit) {
  LayerStats st = layer_stats(s);
  fprintf(out, "crease pattern: %d vertices, %d edges, %d faces\n", m->nverts, l->in.nedges, m->nfaces);
  fprintf(out, "folded: %d points, %d segments, %d cells (merge distance: shortest edge / 2^%d)\n",
          st.points, st.segments, st.cells, st.eps_log2);
  fprintf(out, "variables: %ld, %ld fixed by the creases\n", st.variables, st.fixed);
  fprintf(out, "constraints: %ld taco-taco, %ld taco-tortilla, %ld tortilla-tortilla, %ld transitivity\n",
          st.taco_taco, st.taco_tortilla, st.tortilla_tortilla, st.transitivity);
  int nc = layer_ncomponents(s), *faces = xmalloc((size_t)(m->nfaces + 1) * sizeof *faces), capped = 0;
  long *counts = xmalloc((size_t)(nc + 1) * sizeof *counts);
  fprintf(out, "components: %d\n", nc);
  for (int c = 0; c < nc; c++) {
    long n = count ? layer_count(s, c, limit) : (layer_pick(s, c, 0) ? 1 : 0);
    if (n == 0) {
      free(counts);
      free(faces);
      origami_layers_report(m, l, layer_conflict(s));
      return 1;
    }
    counts[c] = n;
    capped |= count && n >= limit;
    int nf = layer_component_faces(s, c, faces);
    fprintf(out, "  component %d: %d variables, ", c + 1, layer_component_vars(s, c));
    if (count) fprintf(out, "%s%ld states, ", n >= limit ? "at least " : "", n);
    fprintf(out, "%d faces:", nf);
    for (int i = 0; i < nf; i++) fprintf(out, " %d", faces[i]);
    fputc('\n', out);
  }
  if (count) {
    char total[512];
    product_text(counts, nc, total, sizeof total);
    fprintf(out, "states: %s%s\n", capped ? "at least " : "", total);
  } else fprintf(out, "states: at least 1 (found; --count counts them)\n");
  free(counts);
  free(faces);
  return 0;
}
