/*
** Triangle meshes: creation, edge-face adjacency, normals and vertex
** welding (see mesh.h). Every hash here is open-addressed and walked in
** input order, so results never depend on addresses or timing.
*/
#include "mesh.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"

Mesh *mesh_create(int nverts, int ntris) {
  Mesh *m = xcalloc(1, sizeof *m);
  m->nverts = nverts;
  m->ntris = ntris;
  m->pos = xcalloc((size_t)(nverts > 0 ? nverts : 1), sizeof *m->pos);
  m->nrm = xcalloc((size_t)(nverts > 0 ? nverts : 1), sizeof *m->nrm);
  m->tri = xcalloc((size_t)(ntris > 0 ? ntris : 1), sizeof *m->tri);
  m->tri_face = xcalloc((size_t)(ntris > 0 ? ntris : 1), sizeof *m->tri_face);
  return m;
}

void mesh_destroy(Mesh *m) {
  if (!m) return;
  free(m->pos);
  free(m->nrm);
  free(m->uv);
  free(m->tri);
  free(m->tri_face);
  free(m->corner_nrm);
  free(m->edges);
  free(m->tri_edges);
  free(m);
}

/* ---- edges ------------------------------------------------------------ */

static uint64_t hash_u64(uint64_t x) {  /* splitmix64 finaliser */
  x ^= x >> 30; x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27; x *= 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/* A power of two at least twice n (and at least 16). */
static size_t table_size(size_t n) {
  size_t s = 16;
  while (s < 2 * n) s <<= 1;
  return s;
}

/* Record triangle t on edge e. */
static void edge_add_face(MeshEdge *e, int t) {
  if (e->f[0] < 0) e->f[0] = t;
  else if (e->f[1] < 0) e->f[1] = t;
  else e->nonmanifold = 1;
}

/* Edges are found through lists by their lower vertex: the edges (a, b)
** met so far, a handful for each a on a mesh, chained newest first
** through the edges themselves, so the only extra memory is a link per
** edge and a head per vertex. Edges are numbered in the order the
** triangles first name them. */
void mesh_build_edges(Mesh *m) {
  free(m->edges);
  free(m->tri_edges);
  size_t cap = (size_t)m->ntris * 3;
  m->edges = xmalloc((cap ? cap : 1) * sizeof *m->edges);
  m->tri_edges = xmalloc((m->ntris ? (size_t)m->ntris : 1) * sizeof *m->tri_edges);
  mem_populate(m->tri_edges, (size_t)m->ntris * sizeof *m->tri_edges);
  mem_populate(m->edges, cap / 2 * sizeof *m->edges);   /* what a closed mesh uses */
  m->nedges = 0;
  int *first = xcalloc((size_t)m->nverts + 1, sizeof *first);   /* newest edge from a, + 1 */
  int *next = xmalloc((cap ? cap : 1) * sizeof *next);          /* the one before it, + 1 */
  for (int t = 0; t < m->ntris; t++) {
    for (int k = 0; k < 3; k++) {
      int a = m->tri[t][k], b = m->tri[t][k < 2 ? k + 1 : 0];
      if (a == b) { m->tri_edges[t][k] = -1; continue; }
      if (a > b) { int x = a; a = b; b = x; }
      int e = first[a] - 1;
      while (e >= 0 && m->edges[e].v[1] != b) e = next[e] - 1;
      if (e < 0) {
        e = m->nedges++;
        MeshEdge *me = &m->edges[e];
        me->v[0] = a; me->v[1] = b;
        me->f[0] = me->f[1] = -1;
        me->sharpness = 0;
        me->nonmanifold = 0;
        next[e] = first[a];
        first[a] = e + 1;
      }
      edge_add_face(&m->edges[e], t);
      m->tri_edges[t][k] = e;
    }
  }
  free(first);
  free(next);
  if (m->nedges > 0) m->edges = xrealloc(m->edges, (size_t)m->nedges * sizeof *m->edges);
}

/* ---- normals ---------------------------------------------------------- */

void mesh_compute_normals(Mesh *m) {
  for (int i = 0; i < m->nverts; i++) m->nrm[i] = v3(0, 0, 0);
  for (int t = 0; t < m->ntris; t++) {
    const int *c = m->tri[t];
    Vec3 e1 = v3_sub(m->pos[c[1]], m->pos[c[0]]), e2 = v3_sub(m->pos[c[2]], m->pos[c[0]]);
    Vec3 n = v3_cross(e1, e2);   /* length = twice the area: the weight */
    for (int k = 0; k < 3; k++) m->nrm[c[k]] = v3_add(m->nrm[c[k]], n);
  }
  for (int i = 0; i < m->nverts; i++) {
    Vec3 n = v3_norm(m->nrm[i]);
    if (!(v3_len(n) > 0.5)) n = v3(0, 0, 1);   /* unused, or its faces cancel: any unit vector */
    m->nrm[i] = n;
  }
}

/* Whether any corner normal differs from its vertex normal by more than
** about 0.1 degree. */
static int corners_differ(const Mesh *m) {
  for (int t = 0; t < m->ntris; t++)
    for (int k = 0; k < 3; k++)
      if (v3_dot(m->corner_nrm[t][k], m->nrm[m->tri[t][k]]) < 1 - 1e-6) return 1;
  return 0;
}

/* Drops corner_nrm when it says nothing the vertex normals do not. */
static void corners_prune(Mesh *m) {
  if (m->corner_nrm && !corners_differ(m)) {
    free(m->corner_nrm);
    m->corner_nrm = NULL;
  }
}

void mesh_smooth_corners(Mesh *m, double max_angle) {
  free(m->corner_nrm);
  m->corner_nrm = NULL;
  if (m->ntris == 0) return;
  double cos_max = cos(max_angle * M_PI / 180);
  /* triangles around each vertex, as offsets into one array */
  int *start = xcalloc((size_t)m->nverts + 1, sizeof *start), *around = xmalloc((size_t)m->ntris * 3 * sizeof *around);
  Vec3 *fn = xmalloc((size_t)m->ntris * sizeof *fn);   /* area-weighted face normals */
  for (int t = 0; t < m->ntris; t++) {
    const int *c = m->tri[t];
    fn[t] = v3_cross(v3_sub(m->pos[c[1]], m->pos[c[0]]), v3_sub(m->pos[c[2]], m->pos[c[0]]));
    for (int k = 0; k < 3; k++) start[c[k] + 1]++;
  }
  for (int v = 0; v < m->nverts; v++) start[v + 1] += start[v];
  int *fill = xmalloc((size_t)m->nverts * sizeof *fill);
  memcpy(fill, start, (size_t)m->nverts * sizeof *fill);
  for (int t = 0; t < m->ntris; t++)
    for (int k = 0; k < 3; k++) around[fill[m->tri[t][k]]++] = t;
  m->corner_nrm = xmalloc((size_t)m->ntris * sizeof *m->corner_nrm);
  for (int t = 0; t < m->ntris; t++) {
    Vec3 own = v3_norm(fn[t]);
    for (int k = 0; k < 3; k++) {
      int v = m->tri[t][k];
      Vec3 sum = {0, 0, 0};
      for (int i = start[v]; i < start[v + 1]; i++)
        if (v3_dot(v3_norm(fn[around[i]]), own) >= cos_max) sum = v3_add(sum, fn[around[i]]);
      Vec3 n = v3_norm(sum);
      m->corner_nrm[t][k] = v3_len(n) > 0.5 ? n : m->nrm[v];
    }
  }
  free(start);
  free(around);
  free(fn);
  free(fill);
  corners_prune(m);
}

/* ---- welding ---------------------------------------------------------- */

/* Welding hashes positions into cubic cells of side 2 eps: every point
** within eps of p then lies in one of 8 cells, p's own and its neighbours
** toward the nearer face on each axis. eps = 0 matches exact positions
** (one cell per bit pattern, -0 as +0). */
typedef struct WeldGrid {
  size_t mask;
  int *head;          /* per slot: first representative + 1, 0 = none */
  int *next;          /* per vertex: next representative in the same slot + 1 */
  double inv;         /* 1 / cell side; 0 = exact */
} WeldGrid;

/* Cell of coordinate x, clamped so the cast is defined; *side is the
** neighbour toward the nearer cell face (-1 or +1). */
static int64_t cell_of(const WeldGrid *g, double x, int *side) {
  if (g->inv == 0) {
    double z = x + 0.0;
    int64_t bits;
    memcpy(&bits, &z, sizeof bits);
    *side = 0;
    return bits;
  }
  double f = x * g->inv, c = floor(f);
  *side = f - c < 0.5 ? -1 : 1;
  if (!(c > -4e18)) c = -4e18;   /* also NaN */
  if (c > 4e18) c = 4e18;
  return (int64_t)c;
}

static size_t cell_slot(const WeldGrid *g, int64_t x, int64_t y, int64_t z) {
  uint64_t h = (uint64_t)x * 0x9E3779B97F4A7C15ULL ^ (uint64_t)y * 0xC2B2AE3D27D4EB4FULL ^
               (uint64_t)z * 0x165667B19E3779F9ULL;
  return (size_t)hash_u64(h) & g->mask;
}

/* The earlier representative within eps of p, or -1. Different cells may
** share a slot, which only costs a distance test. */
static int weld_lookup(const WeldGrid *g, const Vec3 *pos, Vec3 p, double eps2) {
  int sx, sy, sz;
  int64_t cx = cell_of(g, p.x, &sx), cy = cell_of(g, p.y, &sy), cz = cell_of(g, p.z, &sz);
  size_t seen[8];
  int nseen = 0;
  for (int k = 0; k < 8; k++) {
    if (((k & 1) && !sx) || ((k & 2) && !sy) || ((k & 4) && !sz)) continue;
    size_t h = cell_slot(g, cx + (k & 1 ? sx : 0), cy + (k & 2 ? sy : 0), cz + (k & 4 ? sz : 0));
    int dup = 0;
    for (int i = 0; i < nseen; i++) dup |= seen[i] == h;
    if (dup) continue;
    seen[nseen++] = h;
    for (int r = g->head[h]; r; r = g->next[r - 1]) {
      Vec3 d = v3_sub(pos[r - 1], p);
      if (v3_dot(d, d) <= eps2) return r - 1;
    }
  }
  return -1;
}

static void weld_insert(WeldGrid *g, Vec3 p, int v) {
  int s;
  size_t h = cell_slot(g, cell_of(g, p.x, &s), cell_of(g, p.y, &s), cell_of(g, p.z, &s));
  g->next[v] = g->head[h];
  g->head[h] = v + 1;
}

/* Drops the vertices remap sends elsewhere (kept ones keep their order and
** attributes) and the triangles that lose a corner. */
static void weld_compact(Mesh *m, const int *remap, int nkept) {
  int seen = 0;
  for (int v = 0; v < m->nverts; v++) {
    if (remap[v] != seen) continue;   /* kept vertices number 0, 1, 2, ... in order */
    m->pos[seen] = m->pos[v];
    m->nrm[seen] = m->nrm[v];
    if (m->uv) m->uv[seen] = m->uv[v];
    seen++;
  }
  m->nverts = nkept;
  int nt = 0;
  for (int t = 0; t < m->ntris; t++) {
    int a = remap[m->tri[t][0]], b = remap[m->tri[t][1]], c = remap[m->tri[t][2]];
    if (a == b || b == c || c == a) continue;
    m->tri[nt][0] = a; m->tri[nt][1] = b; m->tri[nt][2] = c;
    m->tri_face[nt] = m->tri_face[t];
    if (m->corner_nrm && nt != t)   /* nt < t: apart, so a copy (inlined) will do */
      memcpy(m->corner_nrm[nt], m->corner_nrm[t], sizeof m->corner_nrm[t]);
    nt++;
  }
  m->ntris = nt;
}

void mesh_weld_marked(Mesh *m, double eps, const unsigned char *mark) {
  if (m->nverts == 0) return;
  if (!(eps > 0)) eps = 0;
  WeldGrid g;
  size_t size = table_size((size_t)m->nverts);
  g.mask = size - 1;
  g.head = xcalloc(size, sizeof *g.head);
  g.next = xcalloc((size_t)m->nverts, sizeof *g.next);
  g.inv = eps > 0 ? 0.5 / eps : 0;
  if (!isfinite(g.inv)) g.inv = 0;   /* eps so small it is exact */
  int *remap = xmalloc((size_t)m->nverts * sizeof *remap);
  int nkept = 0;
  for (int v = 0; v < m->nverts; v++) {
    if (!mark || mark[v]) {
      int r = weld_lookup(&g, m->pos, m->pos[v], eps * eps);
      if (r >= 0) { remap[v] = remap[r]; continue; }
      weld_insert(&g, m->pos[v], v);
    }
    remap[v] = nkept++;
  }
  weld_compact(m, remap, nkept);
  corners_prune(m);
  free(g.head);
  free(g.next);
  free(remap);
  if (m->edges) mesh_build_edges(m);
}

void mesh_weld(Mesh *m, double eps) { mesh_weld_marked(m, eps, NULL); }
