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

Mesh *mesh_alloc(int nverts, int ntris) {
  Mesh *m = xcalloc(1, sizeof *m);
  m->nverts = nverts;
  m->ntris = ntris;
  m->pos = xmalloc((size_t)(nverts > 0 ? nverts : 1) * sizeof *m->pos);
  m->nrm = xmalloc((size_t)(nverts > 0 ? nverts : 1) * sizeof *m->nrm);
  m->tri = xmalloc((size_t)(ntris > 0 ? ntris : 1) * sizeof *m->tri);
  m->tri_face = xmalloc((size_t)(ntris > 0 ? ntris : 1) * sizeof *m->tri_face);
  return m;
}

void *mesh_derived(const Mesh *m, const void *tag) {
  for (const MeshDerived *d = m->derived; d; d = d->next)
    if (d->tag == tag) return d->data;
  return NULL;
}

int mesh_derived_set(Mesh *m, const void *tag, void *data, void (*free_data)(void *data)) {
  if (!m->keeps_derived) return 0;
  for (MeshDerived *d = m->derived; d; d = d->next)
    if (d->tag == tag) {
      d->free_data(d->data);
      d->data = data;
      d->free_data = free_data;
      return 1;
    }
  MeshDerived *d = xmalloc(sizeof *d);
  *d = (MeshDerived){tag, data, free_data, m->derived};
  m->derived = d;
  return 1;
}

void mesh_derived_clear(Mesh *m) {
  while (m->derived) {
    MeshDerived *d = m->derived;
    m->derived = d->next;
    d->free_data(d->data);
    free(d);
  }
}

void mesh_destroy(Mesh *m) {
  if (!m) return;
  mesh_derived_clear(m);
  free(m->pos);
  free(m->nrm);
  free(m->uv);
  free(m->tri);
  free(m->tri_face);
  free(m->corner_nrm);
  free(m->corner_uv);
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
** met so far, a handful for each a on a mesh, chained newest first, so the
** only extra memory is a link per edge and a head per vertex. A walk reads
** each edge's upper vertex and link side by side, not the edges
** themselves. Edges are numbered in the order the triangles first name
** them. */
typedef struct EdgeLists {
  int *first;        /* per vertex: newest edge from it, + 1 */
  int (*link)[2];    /* per edge: upper vertex, edge before it + 1 */
} EdgeLists;

/* The edge between a and b (-1 if a == b), made if new, with triangle t
** recorded on it. */
static inline int edge_of(Mesh *m, EdgeLists *l, int a, int b, int t) {
  if (a == b) return -1;
  if (a > b) { int x = a; a = b; b = x; }
  int e = l->first[a] - 1;
  while (e >= 0 && l->link[e][0] != b) e = l->link[e][1] - 1;
  if (e >= 0) {
    edge_add_face(&m->edges[e], t);
    return e;
  }
  e = m->nedges++;
  MeshEdge *me = &m->edges[e];
  me->v[0] = a; me->v[1] = b;
  me->f[0] = t;
  me->f[1] = -1;
  me->sharpness = 0;
  me->nonmanifold = 0;
  l->link[e][0] = b;
  l->link[e][1] = l->first[a];
  l->first[a] = e + 1;
  return e;
}

void mesh_build_edges(Mesh *m) {
  mesh_derived_clear(m);   /* made from the old topology */
  free(m->edges);
  free(m->tri_edges);
  size_t cap = (size_t)m->ntris * 3;
  m->edges = xmalloc((cap ? cap : 1) * sizeof *m->edges);
  m->tri_edges = xmalloc((m->ntris ? (size_t)m->ntris : 1) * sizeof *m->tri_edges);
  mem_populate(m->tri_edges, (size_t)m->ntris * sizeof *m->tri_edges);
  mem_populate(m->edges, cap / 2 * sizeof *m->edges);   /* what a closed mesh uses */
  m->nedges = 0;
  EdgeLists l;
  l.first = xcalloc((size_t)m->nverts + 1, sizeof *l.first);
  l.link = xmalloc((cap ? cap : 1) * sizeof *l.link);
  for (int t = 0; t < m->ntris; t++) {
    int a = m->tri[t][0], b = m->tri[t][1], c = m->tri[t][2];
    m->tri_edges[t][0] = edge_of(m, &l, a, b, t);
    m->tri_edges[t][1] = edge_of(m, &l, b, c, t);
    m->tri_edges[t][2] = edge_of(m, &l, c, a, t);
  }
  free(l.first);
  free(l.link);
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

/* The hash of a cell's coordinates is the xor of one product per axis. */
#define WELD_KX 0x9E3779B97F4A7C15ULL
#define WELD_KY 0xC2B2AE3D27D4EB4FULL
#define WELD_KZ 0x165667B19E3779F9ULL

static size_t cell_slot(const WeldGrid *g, int64_t x, int64_t y, int64_t z) {
  uint64_t h = (uint64_t)x * WELD_KX ^ (uint64_t)y * WELD_KY ^ (uint64_t)z * WELD_KZ;
  return (size_t)hash_u64(h) & g->mask;
}

/* The earlier representative within eps of p, or -1; p lies in cell
** (cx, cy, cz) and nearer to its neighbours on the sides sx, sy, sz (see
** cell_of). Different cells may share a slot, which only costs a distance
** test; a slot met twice is walked twice, to the same end. The axes'
** products for cell_slot are made once for the 8 cells. */
static int weld_lookup(const WeldGrid *g, const Vec3 *pos, Vec3 p, double eps2, int64_t cx,
                       int64_t cy, int64_t cz, int sx, int sy, int sz) {
  uint64_t hx[2] = {(uint64_t)cx * WELD_KX, (uint64_t)(cx + sx) * WELD_KX};
  uint64_t hy[2] = {(uint64_t)cy * WELD_KY, (uint64_t)(cy + sy) * WELD_KY};
  uint64_t hz[2] = {(uint64_t)cz * WELD_KZ, (uint64_t)(cz + sz) * WELD_KZ};
  for (int k = 0; k < 8; k++) {
    int kx = k & 1, ky = (k >> 1) & 1, kz = k >> 2;
    if ((kx && !sx) || (ky && !sy) || (kz && !sz)) continue;
    size_t h = (size_t)hash_u64(hx[kx] ^ hy[ky] ^ hz[kz]) & g->mask;
    for (int r = g->head[h]; r; r = g->next[r - 1]) {
      Vec3 d = v3_sub(pos[r - 1], p);
      if (v3_dot(d, d) <= eps2) return r - 1;
    }
  }
  return -1;
}

/* Drops the vertices remap sends elsewhere (kept ones keep their order and
** attributes) and the triangles that lose a corner. With fill, corner_nrm
** (allocated for every triangle) gets each kept corner's own normal from
** before the weld, and with fill_uv corner_uv its own uv. Triangles go
** first, while nrm and uv are still as they were. */
static void weld_compact(Mesh *m, const int *remap, int nkept, int fill, int fill_uv) {
  int nt = 0;
  for (int t = 0; t < m->ntris; t++) {
    int o0 = m->tri[t][0], o1 = m->tri[t][1], o2 = m->tri[t][2];
    int a = remap[o0], b = remap[o1], d = remap[o2];
    if (a == b || b == d || d == a) continue;
    if (fill) {
      Vec3 *cn = m->corner_nrm[nt];
      cn[0] = m->nrm[o0];
      cn[1] = m->nrm[o1];
      cn[2] = m->nrm[o2];
    } else if (m->corner_nrm && nt != t)   /* nt < t: apart, so a copy (inlined) will do */
      memcpy(m->corner_nrm[nt], m->corner_nrm[t], sizeof m->corner_nrm[t]);
    if (fill_uv) {
      Vec2 *cu = m->corner_uv[nt];
      cu[0] = m->uv[o0];
      cu[1] = m->uv[o1];
      cu[2] = m->uv[o2];
    } else if (m->corner_uv && nt != t) {
      memcpy(m->corner_uv[nt], m->corner_uv[t], sizeof m->corner_uv[t]);
    }
    m->tri[nt][0] = a; m->tri[nt][1] = b; m->tri[nt][2] = d;
    m->tri_face[nt] = m->tri_face[t];
    nt++;
  }
  m->ntris = nt;
  int seen = 0;
  for (int v = 0; v < m->nverts; v++) {
    if (remap[v] != seen) continue;   /* kept vertices number 0, 1, 2, ... in order */
    m->pos[seen] = m->pos[v];
    m->nrm[seen] = m->nrm[v];
    if (m->uv) m->uv[seen] = m->uv[v];
    seen++;
  }
  m->nverts = nkept;
}

/* The weld's first half: remap[v] is the vertex v becomes (kept ones
** number 0, 1, 2, ... in order) and rep[v], when rep is not NULL, that
** vertex's index before the weld; returns how many are kept. */
static int weld_find(const Mesh *m, double eps, const unsigned char *mark, int *remap, int *rep) {
  if (!(eps > 0)) eps = 0;
  WeldGrid g;
  size_t size = table_size((size_t)m->nverts);
  g.mask = size - 1;
  g.head = xcalloc(size, sizeof *g.head);
  g.next = xcalloc((size_t)m->nverts, sizeof *g.next);
  g.inv = eps > 0 ? 0.5 / eps : 0;
  if (!isfinite(g.inv)) g.inv = 0;   /* eps so small it is exact */
  int nkept = 0;
  for (int v = 0; v < m->nverts; v++) {
    int r = v;
    if (!mark || mark[v]) {
      Vec3 p = m->pos[v];
      int sx, sy, sz;
      int64_t cx = cell_of(&g, p.x, &sx), cy = cell_of(&g, p.y, &sy), cz = cell_of(&g, p.z, &sz);
      r = weld_lookup(&g, m->pos, p, eps * eps, cx, cy, cz, sx, sy, sz);
      if (r < 0) {   /* a new representative */
        size_t h = cell_slot(&g, cx, cy, cz);
        g.next[v] = g.head[h];
        g.head[h] = v + 1;
        r = v;
      }
    }
    remap[v] = r == v ? nkept++ : remap[r];
    if (rep) rep[v] = r;
  }
  free(g.head);
  free(g.next);
  return nkept;
}

void mesh_weld_marked(Mesh *m, double eps, const unsigned char *mark) {
  if (m->nverts == 0) return;
  int *remap = xmalloc((size_t)m->nverts * sizeof *remap);
  int nkept = weld_find(m, eps, mark, remap, NULL);
  weld_compact(m, remap, nkept, 0, 0);
  corners_prune(m);
  free(remap);
  if (m->edges) mesh_build_edges(m);
}

void mesh_weld(Mesh *m, double eps) { mesh_weld_marked(m, eps, NULL); }

/* A corner ends up with its vertex's normal only if that is its own: one
** test per vertex against its representative's normal (the test
** corners_differ makes per corner) tells whether any corner can differ,
** and usually none does, so the per-corner array is never made. */
void mesh_weld_creased(Mesh *m, double eps, const unsigned char *mark) {
  free(m->corner_nrm);
  m->corner_nrm = NULL;
  if (m->nverts == 0) return;
  int *remap = xmalloc((size_t)m->nverts * sizeof *remap);
  int *rep = xmalloc((size_t)m->nverts * sizeof *rep);
  int nkept = weld_find(m, eps, mark, remap, rep);
  unsigned char *differs = xmalloc((size_t)m->nverts);   /* bit 0: normal, bit 1: uv */
  int any = 0;
  for (int v = 0; v < m->nverts; v++) {
    int r = rep[v];
    differs[v] = (unsigned char)((v3_dot(m->nrm[v], m->nrm[r]) < 1 - 1e-6) |
                                 (m->uv && (m->uv[v].x != m->uv[r].x || m->uv[v].y != m->uv[r].y)) << 1);
    any |= differs[v];
  }
  /* only corners of triangles the weld keeps count */
  int need = 0;
  for (int t = 0; any && need != 3 && t < m->ntris; t++) {
    const int *c = m->tri[t];
    int a = remap[c[0]], b = remap[c[1]], d = remap[c[2]];
    if (a == b || b == d || d == a) continue;
    need |= differs[c[0]] | differs[c[1]] | differs[c[2]];
  }
  if (need & 1) {   /* filled whole */
    m->corner_nrm = xmalloc((size_t)m->ntris * sizeof *m->corner_nrm);
    mem_populate(m->corner_nrm, (size_t)m->ntris * sizeof *m->corner_nrm);
  }
  free(m->corner_uv);
  m->corner_uv = need & 2 ? xmalloc((size_t)m->ntris * sizeof *m->corner_uv) : NULL;
  weld_compact(m, remap, nkept, need & 1, need >> 1);
  free(differs);
  free(rep);
  free(remap);
  if (m->edges) mesh_build_edges(m);
}
