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

/* The index of edge (a, b) in m->edges, adding it when new; slot is the
** open-addressed table of edge indices + 1 (0 = empty). */
static int edge_find_or_add(Mesh *m, int *slot, size_t mask, int a, int b) {
  if (a > b) { int t = a; a = b; b = t; }
  uint64_t key = ((uint64_t)(uint32_t)a << 32) | (uint32_t)b;
  size_t h = (size_t)hash_u64(key) & mask;
  while (slot[h]) {
    MeshEdge *e = &m->edges[slot[h] - 1];
    if (e->v[0] == a && e->v[1] == b) return slot[h] - 1;
    h = (h + 1) & mask;
  }
  MeshEdge *e = &m->edges[m->nedges];
  e->v[0] = a; e->v[1] = b;
  e->f[0] = e->f[1] = -1;
  e->sharpness = 0;
  e->nonmanifold = 0;
  slot[h] = ++m->nedges;
  return m->nedges - 1;
}

/* Record triangle t on edge e. */
static void edge_add_face(MeshEdge *e, int t) {
  if (e->f[0] < 0) e->f[0] = t;
  else if (e->f[1] < 0) e->f[1] = t;
  else e->nonmanifold = 1;
}

/* A triangle side whose two corners are the same vertex gets edge -1. */
void mesh_build_edges(Mesh *m) {
  free(m->edges);
  free(m->tri_edges);
  size_t cap = (size_t)m->ntris * 3;
  m->edges = xmalloc((cap ? cap : 1) * sizeof *m->edges);
  m->tri_edges = xmalloc((m->ntris ? (size_t)m->ntris : 1) * sizeof *m->tri_edges);
  m->nedges = 0;
  size_t size = table_size(cap);
  int *slot = xcalloc(size, sizeof *slot);
  for (int t = 0; t < m->ntris; t++) {
    for (int k = 0; k < 3; k++) {
      int a = m->tri[t][k], b = m->tri[t][(k + 1) % 3];
      if (a == b) { m->tri_edges[t][k] = -1; continue; }
      int e = edge_find_or_add(m, slot, size - 1, a, b);
      edge_add_face(&m->edges[e], t);
      m->tri_edges[t][k] = e;
    }
  }
  free(slot);
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

/* ---- welding ---------------------------------------------------------- */

/* Integer cell of coordinate x for cell size 1 / inv, clamped so the cast
** is defined; inv = 0 asks for exact matching: the cell is x's bit pattern
** (with -0 as +0). */
static int64_t cell_of(double x, double inv) {
  if (inv == 0) {
    double z = x + 0.0;
    int64_t bits;
    memcpy(&bits, &z, sizeof bits);
    return bits;
  }
  double c = floor(x * inv);
  if (!(c > -4e18)) c = -4e18;   /* also NaN */
  if (c > 4e18) c = 4e18;
  return (int64_t)c;
}

static uint64_t cell_hash(int64_t x, int64_t y, int64_t z) {
  return hash_u64((uint64_t)x * 0x9E3779B97F4A7C15ULL ^ hash_u64((uint64_t)y + 0x632BE59BD9B4E019ULL) ^
                  hash_u64((uint64_t)z * 3 + 1));
}

typedef struct WeldGrid {
  size_t mask;
  int *head;          /* per slot: first representative + 1, 0 = none */
  int *next;          /* per vertex: next representative in the same slot + 1 */
  double inv;
} WeldGrid;

/* The earlier representative within eps of p, or -1. Candidates come from
** the 27 cells around p's; different cells may share a slot, which only
** costs a distance test. */
static int weld_lookup(const WeldGrid *g, const Vec3 *pos, Vec3 p, double eps2) {
  int64_t cx = cell_of(p.x, g->inv), cy = cell_of(p.y, g->inv), cz = cell_of(p.z, g->inv);
  int reach = g->inv == 0 ? 0 : 1;
  for (int dz = -reach; dz <= reach; dz++)
    for (int dy = -reach; dy <= reach; dy++)
      for (int dx = -reach; dx <= reach; dx++) {
        size_t h = (size_t)cell_hash(cx + dx, cy + dy, cz + dz) & g->mask;
        for (int r = g->head[h]; r; r = g->next[r - 1]) {
          Vec3 d = v3_sub(pos[r - 1], p);
          if (v3_dot(d, d) <= eps2) return r - 1;
        }
      }
  return -1;
}

static void weld_insert(WeldGrid *g, Vec3 p, int v) {
  size_t h = (size_t)cell_hash(cell_of(p.x, g->inv), cell_of(p.y, g->inv), cell_of(p.z, g->inv)) & g->mask;
  g->next[v] = g->head[h];
  g->head[h] = v + 1;
}

/* Vertex v merges into the first earlier vertex within eps (in index
** order); kept vertices keep their order, position, normal and uv.
** Triangles that lose a corner are dropped; topology, if built, is rebuilt. */
void mesh_weld(Mesh *m, double eps) {
  if (m->nverts == 0) return;
  if (!(eps > 0)) eps = 0;
  WeldGrid g;
  size_t size = table_size((size_t)m->nverts);
  g.mask = size - 1;
  g.head = xcalloc(size, sizeof *g.head);
  g.next = xcalloc((size_t)m->nverts, sizeof *g.next);
  g.inv = eps > 0 ? 1.0 / eps : 0;
  if (!isfinite(g.inv)) g.inv = 0;   /* eps so small it is exact */
  int *remap = xmalloc((size_t)m->nverts * sizeof *remap);
  int nkept = 0;
  for (int v = 0; v < m->nverts; v++) {
    int r = weld_lookup(&g, m->pos, m->pos[v], eps * eps);
    if (r >= 0) { remap[v] = remap[r]; continue; }
    weld_insert(&g, m->pos[v], v);
    remap[v] = nkept++;
  }
  /* compact: a kept vertex's new index is never above its old one */
  int seen = 0;
  for (int v = 0; v < m->nverts; v++) {
    if (remap[v] != seen) continue;
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
    nt++;
  }
  m->ntris = nt;
  free(g.head);
  free(g.next);
  free(remap);
  if (m->edges) mesh_build_edges(m);
}
