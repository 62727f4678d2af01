/*
** Subdivision surfaces through OpenSubdiv: SceneGeometry -> bridge
** topology -> uniform refinement -> triangle Mesh with limit positions,
** limit normals and crease tags (see subdiv.h).
*/
#include "subdiv.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"
#include "../base/tasks.h"

/* Threads a refinement may use (subdiv_threads). */
static int threads = 1;

void subdiv_threads(int n) {
  threads = n > 0 ? n : 1;
}

/* ---- names and counts -------------------------------------------------- */

int subdiv_scheme_parse(const char *name, SumiOsdScheme *out) {
  if (!name || !strcmp(name, "catmark")) *out = SUMI_OSD_CATMARK;
  else if (!strcmp(name, "loop")) *out = SUMI_OSD_LOOP;
  else if (!strcmp(name, "bilinear")) *out = SUMI_OSD_BILINEAR;
  else return 0;
  return 1;
}

int subdiv_boundary_parse(const char *name, SumiOsdBoundary *out) {
  if (!name || !strcmp(name, "edge_and_corner")) *out = SUMI_OSD_BOUNDARY_EDGE_AND_CORNER;
  else if (!strcmp(name, "edge_only")) *out = SUMI_OSD_BOUNDARY_EDGE_ONLY;
  else if (!strcmp(name, "none")) *out = SUMI_OSD_BOUNDARY_NONE;
  else return 0;
  return 1;
}

/* Level 1 splits an n-gon into n quads (catmark, bilinear) or a triangle
** into 4 (loop); every later level multiplies by 4. */
long subdiv_face_count(const SceneGeometry *g) {
  SumiOsdScheme scheme = SUMI_OSD_CATMARK;
  subdiv_scheme_parse(g->subdiv_scheme, &scheme);
  long n = 0;
  for (int f = 0; f < g->nfaces; f++) {
    int size = g->face_start[f + 1] - g->face_start[f];
    n += scheme == SUMI_OSD_LOOP ? 4 : (size == 4 ? 4 : size);
    if (n > INT_MAX) return INT_MAX;
  }
  for (int l = 1; l < g->subdiv_level; l++) {
    n *= 4;
    if (n > INT_MAX) return INT_MAX;
  }
  return n;
}

/* ---- topology ---------------------------------------------------------- */

int subdiv_topology(const SceneGeometry *g, SumiOsdBoundary boundary, SubdivTopology *st,
                    char *err, size_t errlen) {
  memset(st, 0, sizeof *st);
  SumiOsdTopology *t = &st->topo;
  if (!subdiv_scheme_parse(g->subdiv_scheme, &t->scheme)) {
    snprintf(err, errlen, "unknown subdivision scheme \"%s\" (use catmark, loop or bilinear)",
             g->subdiv_scheme);
    return 0;
  }
  t->boundary = boundary;
  t->nverts = g->nverts;
  t->nfaces = g->nfaces;
  st->face_size = xmalloc(sizeof(int) * (size_t)(g->nfaces > 0 ? g->nfaces : 1));
  for (int f = 0; f < g->nfaces; f++) st->face_size[f] = g->face_start[f + 1] - g->face_start[f];
  t->face_size = st->face_size;
  t->face_index = g->face_index;
  int nc = g->ncreases, nk = g->ncorners;
  st->crease_verts = xmalloc(sizeof(int) * (size_t)(2 * nc + 1));
  st->crease_sharpness = xmalloc(sizeof(float) * (size_t)(nc + 1));
  for (int c = 0; c < nc; c++) {
    st->crease_verts[2 * c] = g->creases[c].a;
    st->crease_verts[2 * c + 1] = g->creases[c].b;
    st->crease_sharpness[c] = (float)g->creases[c].sharpness;
  }
  st->corner_verts = xmalloc(sizeof(int) * (size_t)(nk + 1));
  st->corner_sharpness = xmalloc(sizeof(float) * (size_t)(nk + 1));
  for (int c = 0; c < nk; c++) {
    st->corner_verts[c] = g->corners[c].v;
    st->corner_sharpness[c] = (float)g->corners[c].sharpness;
  }
  t->ncreases = nc;
  t->crease_verts = st->crease_verts;
  t->crease_sharpness = st->crease_sharpness;
  t->ncorners = nk;
  t->corner_verts = st->corner_verts;
  t->corner_sharpness = st->corner_sharpness;
  return 1;
}

void subdiv_topology_free(SubdivTopology *st) {
  free(st->face_size);
  free(st->crease_verts);
  free(st->crease_sharpness);
  free(st->corner_verts);
  free(st->corner_sharpness);
  memset(st, 0, sizeof *st);
}

/* The checks before OpenSubdiv sees the mesh: kind, level, face count. */
static int check_size(const SceneGeometry *g, char *err, size_t errlen) {
  if (g->kind != GEOM_MESH) {
    snprintf(err, errlen, "subdivision needs a polygon mesh");
    return 0;
  }
  if (g->subdiv_level < 1 || g->subdiv_level > SUBDIV_MAX_LEVEL) {
    snprintf(err, errlen, "subdivision level %d is outside 1..%d (SUBDIV_MAX_LEVEL)",
             g->subdiv_level, SUBDIV_MAX_LEVEL);
    return 0;
  }
  long n = subdiv_face_count(g);
  if (n > SUBDIV_MAX_FACES) {
    snprintf(err, errlen,
             "subdivision to level %d gives %ld faces; the limit is %d (SUBDIV_MAX_FACES)",
             g->subdiv_level, n, SUBDIV_MAX_FACES);
    return 0;
  }
  return 1;
}

int subdiv_check(const SceneGeometry *g, SumiOsdBoundary boundary, char *err, size_t errlen) {
  if (!check_size(g, err, errlen)) return 0;
  SubdivTopology st;
  int ok = subdiv_topology(g, boundary, &st, err, errlen) && sumi_osd_check(&st.topo, err, errlen);
  subdiv_topology_free(&st);
  return ok;
}

/* ---- the mesh ---------------------------------------------------------- */

/* Edge slot for one more triangle side. */
static void edge_add_face(MeshEdge *e, int t) {
  if (e->f[0] < 0) e->f[0] = t;
  else if (e->f[1] < 0) e->f[1] = t;
  else e->nonmanifold = 1;
}

/* Side k of triangle t gets edge e when e joins the side's two corners. */
static inline int set_side(Mesh *m, int t, int k, int e) {
  int a = m->tri[t][k], b = m->tri[t][(k + 1) % 3];
  MeshEdge *ed = &m->edges[e];
  if (!((ed->v[0] == a && ed->v[1] == b) || (ed->v[0] == b && ed->v[1] == a))) return 0;
  m->tri_edges[t][k] = e;
  edge_add_face(ed, t);
  return 1;
}

/* The mesh's edges straight from OpenSubdiv's: the level's edges (with
** their crease tags), then one diagonal for each quad, in the order
** fill_triangles made the triangles. Returns 0 when the level's topology
** does not match the triangles (a degenerate face), so the caller falls
** back to mesh_build_edges(). */
static int edges_from_level(Mesh *m, const SumiOsdRefined *r) {
  int nquads = 0;
  for (int f = 0; f < r->nfaces; f++) nquads += r->face_start[f + 1] - r->face_start[f] == 4;
  m->nedges = r->nedges + nquads;
  m->edges = xmalloc(sizeof *m->edges * (size_t)(m->nedges > 0 ? m->nedges : 1));
  m->tri_edges = xmalloc(sizeof *m->tri_edges * (size_t)(m->ntris > 0 ? m->ntris : 1));
  for (int e = 0; e < r->nedges; e++) {
    int a = r->edge_verts[2 * e], b = r->edge_verts[2 * e + 1];
    m->edges[e] = (MeshEdge){{a < b ? a : b, a < b ? b : a}, {-1, -1}, r->edge_tag[e], 0};
  }
  int t = 0, diag = r->nedges;
  for (int f = 0; f < r->nfaces; f++) {
    const int *fe = r->face_edges + r->face_start[f];
    int n = r->face_start[f + 1] - r->face_start[f];
    if (n == 3) {
      /* fill_triangles keeps a triangle's corner order */
      for (int k = 0; k < 3; k++)
        if (!set_side(m, t, k, fe[k])) return 0;
      t++;
      continue;
    }
    /* quad split at corner k0 = tri[t][0]: sides k0, k0+1, diagonal; diagonal, k0+2, k0+3 */
    const int *v = r->face_index + r->face_start[f];
    int k0 = v[0] == m->tri[t][0] ? 0 : 1;
    int a = m->tri[t][0], b = m->tri[t][2];
    m->edges[diag] = (MeshEdge){{a < b ? a : b, a < b ? b : a}, {-1, -1}, 0, 0};
    if (!set_side(m, t, 0, fe[k0]) || !set_side(m, t, 1, fe[(k0 + 1) % 4]) ||
        !set_side(m, t, 2, diag) || !set_side(m, t + 1, 0, diag) ||
        !set_side(m, t + 1, 1, fe[(k0 + 2) % 4]) || !set_side(m, t + 1, 2, fe[(k0 + 3) % 4]))
      return 0;
    t += 2;
    diag++;
  }
  return t == m->ntris;
}

/* Fallback: hash the triangles' sides, then copy the tags across. */
static void edges_by_hash(Mesh *m, const SumiOsdRefined *r) {
  free(m->edges);
  free(m->tri_edges);
  m->edges = NULL;
  m->tri_edges = NULL;
  mesh_build_edges(m);
  int *first = xmalloc(sizeof(int) * (size_t)(m->nverts > 0 ? m->nverts : 1));
  int *next = xmalloc(sizeof(int) * (size_t)(m->nedges > 0 ? m->nedges : 1));
  for (int v = 0; v < m->nverts; v++) first[v] = -1;
  for (int e = 0; e < m->nedges; e++) {   /* edges listed by their lower vertex */
    next[e] = first[m->edges[e].v[0]];
    first[m->edges[e].v[0]] = e;
  }
  for (int i = 0; i < r->nsharp; i++) {
    int a = r->sharp_verts[2 * i], b = r->sharp_verts[2 * i + 1];
    if (a > b) { int x = a; a = b; b = x; }
    for (int e = first[a]; e >= 0; e = next[e])
      if (m->edges[e].v[1] == b) m->edges[e].sharpness = r->sharp[i];
  }
  free(first);
  free(next);
}

static double dist2(const double *p, const double *q) {
  double x = p[0] - q[0], y = p[1] - q[1], z = p[2] - q[2];
  return x * x + y * y + z * z;
}

/* Triangles of the refined faces: quads split along their shorter
** diagonal, triangles as they are. */
static int triangle_count(const SumiOsdRefined *r) {
  int n = 0;
  for (int f = 0; f < r->nfaces; f++) n += r->face_start[f + 1] - r->face_start[f] - 2;
  return n;
}

/* Faces one fill task triangulates. */
#define FILL_CHUNK 8192

typedef struct FillJob {
  Mesh *m;
  const SumiOsdRefined *r;
} FillJob;

/* Faces [FILL_CHUNK * k, ...) of the refinement; face f's triangles start
** at face_start[f] - 2 f (an n-gon makes n - 2), so chunks write apart. */
static void fill_task(void *ctx, int k) {
  const FillJob *job = ctx;
  Mesh *m = job->m;
  const SumiOsdRefined *r = job->r;
  int f0 = k * FILL_CHUNK, f1 = f0 + FILL_CHUNK < r->nfaces ? f0 + FILL_CHUNK : r->nfaces;
  for (int f = f0; f < f1; f++) {
    const int *v = r->face_index + r->face_start[f];
    int n = r->face_start[f + 1] - r->face_start[f], t = r->face_start[f] - 2 * f;
    int k0 = 0;  /* fan origin: for a quad, the end of the shorter diagonal */
    if (n == 4 && dist2(r->limit + 3 * v[1], r->limit + 3 * v[3]) <
                      dist2(r->limit + 3 * v[0], r->limit + 3 * v[2]))
      k0 = 1;
    for (int i = 1; i + 1 < n; i++) {
      m->tri[t][0] = v[k0];
      m->tri[t][1] = v[(k0 + i) % n];
      m->tri[t][2] = v[(k0 + i + 1) % n];
      m->tri_face[t++] = r->face_base[f];
    }
  }
}

static void fill_triangles(Mesh *m, const SumiOsdRefined *r) {
  FillJob job = {m, r};
  tasks_run((r->nfaces + FILL_CHUNK - 1) / FILL_CHUNK, threads, fill_task, &job);
}

/* Limit normals, turned to agree with the area-weighted face normals; a
** vertex whose limit normal is undefined keeps the face-based one. */
static void fill_normals(Mesh *m, const SumiOsdRefined *r) {
  mesh_compute_normals(m);
  for (int i = 0; i < m->nverts; i++) {
    Vec3 n = v3(r->normal[3 * i], r->normal[3 * i + 1], r->normal[3 * i + 2]);
    if (!(v3_len(n) > 0.5)) continue;
    m->nrm[i] = v3_dot(n, m->nrm[i]) < 0 ? v3_mul(n, -1) : n;
  }
}

/* The edges and the normals of the triangulated mesh: neither reads what
** the other writes. */
static void finish_task(void *ctx, int k) {
  const FillJob *job = ctx;
  if (k == 1) fill_normals(job->m, job->r);
  else if (!edges_from_level(job->m, job->r)) edges_by_hash(job->m, job->r);
}

Mesh *subdiv_mesh_ex(const SceneGeometry *g, SumiOsdBoundary boundary, SumiOsdRefined *refined,
                     char *err, size_t errlen) {
  /* subdiv_check's checks, the OpenSubdiv ones made by the one refiner */
  if (!check_size(g, err, errlen)) return NULL;
  SubdivTopology st;
  if (!subdiv_topology(g, boundary, &st, err, errlen)) return NULL;
  SumiOsdRefined r;
  int ok = sumi_osd_refine_topology(&st.topo, g->subdiv_level, (const double *)g->verts,
                                    refined != NULL, threads, &r, err, errlen);
  subdiv_topology_free(&st);
  if (!ok) return NULL;
  Mesh *m = mesh_alloc(r.nverts, triangle_count(&r));   /* every entry filled below */
  memcpy(m->pos, r.limit, sizeof(Vec3) * (size_t)r.nverts);
  fill_triangles(m, &r);
  FillJob job = {m, &r};
  tasks_run(2, threads, finish_task, &job);
  if (refined) *refined = r;
  else sumi_osd_refined_free(&r);
  return m;
}

/* ---- the cache across frames ------------------------------------------- */

/* One refined mesh (NULL while lent to a frame) and a copy of everything
** it was made from. */
typedef struct CacheEntry {
  int level, boundary;
  char *scheme;                /* NULL: catmark */
  int nverts, nfaces, nindex, ncreases, ncorners;
  Vec3 *verts;
  int *face_start, *face_index;
  int *crease_v;               /* a, b per crease */
  double *crease_s;
  int *corner_v;
  double *corner_s;
  Mesh *mesh;
} CacheEntry;

static struct {
  long hits;                   /* refinements the cache gave */
  int max;                     /* entries kept; 0: no cache */
  int n, next;                 /* entries held; the one replaced next when full */
  CacheEntry *e;
} cache;

static void *copy_of(const void *p, size_t bytes) {
  void *q = xmalloc(bytes + 1);
  if (bytes) memcpy(q, p, bytes);
  return q;
}

static int same_bytes(const void *a, const void *b, size_t bytes) {
  return bytes == 0 || memcmp(a, b, bytes) == 0;
}

/* Is e the refinement of g with boundary? Every input compared exactly. */
static int entry_matches(const CacheEntry *e, const SceneGeometry *g, SumiOsdBoundary boundary) {
  if (e->level != g->subdiv_level || e->boundary != (int)boundary || e->nverts != g->nverts ||
      e->nfaces != g->nfaces || e->ncreases != g->ncreases || e->ncorners != g->ncorners)
    return 0;
  if ((e->scheme == NULL) != (g->subdiv_scheme == NULL) ||
      (e->scheme && strcmp(e->scheme, g->subdiv_scheme)))
    return 0;
  int nindex = g->nfaces > 0 ? g->face_start[g->nfaces] : 0;
  if (e->nindex != nindex || !same_bytes(e->verts, g->verts, sizeof(Vec3) * (size_t)g->nverts) ||
      !same_bytes(e->face_start, g->face_start, sizeof(int) * (size_t)(g->nfaces + 1)) ||
      !same_bytes(e->face_index, g->face_index, sizeof(int) * (size_t)nindex))
    return 0;
  for (int c = 0; c < g->ncreases; c++)
    if (e->crease_v[2 * c] != g->creases[c].a || e->crease_v[2 * c + 1] != g->creases[c].b ||
        memcmp(&e->crease_s[c], &g->creases[c].sharpness, sizeof(double)))
      return 0;
  for (int c = 0; c < g->ncorners; c++)
    if (e->corner_v[c] != g->corners[c].v || memcmp(&e->corner_s[c], &g->corners[c].sharpness, sizeof(double)))
      return 0;
  return 1;
}

static void entry_free(CacheEntry *e) {
  free(e->scheme);
  free(e->verts);
  free(e->face_start);
  free(e->face_index);
  free(e->crease_v);
  free(e->crease_s);
  free(e->corner_v);
  free(e->corner_s);
  mesh_destroy(e->mesh);
  memset(e, 0, sizeof *e);
}

/* The entry holding g's refinement with boundary (lent out or not), or -1. */
static int entry_find(const SceneGeometry *g, SumiOsdBoundary boundary) {
  for (int i = 0; i < cache.n; i++)
    if (entry_matches(&cache.e[i], g, boundary)) return i;
  return -1;
}

/* Keep m as the refinement of g (the oldest entry goes when the cache is
** full); the cache owns m. */
static void entry_store(const SceneGeometry *g, SumiOsdBoundary boundary, Mesh *m) {
  CacheEntry *e;
  if (cache.n < cache.max) e = &cache.e[cache.n++];
  else {
    e = &cache.e[cache.next];
    cache.next = (cache.next + 1) % cache.max;
    entry_free(e);
  }
  int nindex = g->nfaces > 0 ? g->face_start[g->nfaces] : 0;
  e->level = g->subdiv_level;
  e->boundary = (int)boundary;
  e->scheme = g->subdiv_scheme ? copy_of(g->subdiv_scheme, strlen(g->subdiv_scheme) + 1) : NULL;
  e->nverts = g->nverts;
  e->nfaces = g->nfaces;
  e->nindex = nindex;
  e->ncreases = g->ncreases;
  e->ncorners = g->ncorners;
  e->verts = copy_of(g->verts, sizeof(Vec3) * (size_t)g->nverts);
  e->face_start = copy_of(g->face_start, sizeof(int) * (size_t)(g->nfaces + 1));
  e->face_index = copy_of(g->face_index, sizeof(int) * (size_t)nindex);
  e->crease_v = xmalloc(sizeof(int) * (size_t)(2 * g->ncreases + 1));
  e->crease_s = xmalloc(sizeof(double) * (size_t)(g->ncreases + 1));
  for (int c = 0; c < g->ncreases; c++) {
    e->crease_v[2 * c] = g->creases[c].a;
    e->crease_v[2 * c + 1] = g->creases[c].b;
    e->crease_s[c] = g->creases[c].sharpness;
  }
  e->corner_v = xmalloc(sizeof(int) * (size_t)(g->ncorners + 1));
  e->corner_s = xmalloc(sizeof(double) * (size_t)(g->ncorners + 1));
  for (int c = 0; c < g->ncorners; c++) {
    e->corner_v[c] = g->corners[c].v;
    e->corner_s[c] = g->corners[c].sharpness;
  }
  e->mesh = m;
}

void subdiv_cache_keep(int entries) {
  subdiv_cache_clear();
  cache.max = entries > 0 ? entries : 0;
  cache.e = cache.max ? xcalloc((size_t)cache.max, sizeof *cache.e) : NULL;
}

void subdiv_cache_clear(void) {
  long hits = cache.hits;
  for (int i = 0; i < cache.n; i++) entry_free(&cache.e[i]);
  free(cache.e);
  memset(&cache, 0, sizeof cache);
  cache.hits = hits;
}

long subdiv_cache_hits(void) {
  return cache.hits;
}

Mesh *subdiv_mesh(const SceneGeometry *g, SumiOsdBoundary boundary, char *err, size_t errlen) {
  int i = entry_find(g, boundary);
  if (i >= 0 && cache.e[i].mesh) {   /* lent out until subdiv_mesh_done */
    Mesh *m = cache.e[i].mesh;
    cache.e[i].mesh = NULL;
    cache.hits++;
    return m;
  }
  Mesh *m = subdiv_mesh_ex(g, boundary, NULL, err, errlen);
  if (m) m->keeps_derived = cache.max > 0;   /* the later stages' data goes into the cache too */
  return m;
}

void subdiv_mesh_done(const SceneGeometry *g, SumiOsdBoundary boundary, Mesh *m) {
  if (!cache.max) {
    mesh_destroy(m);
    return;
  }
  int i = entry_find(g, boundary);
  if (i < 0) entry_store(g, boundary, m);
  else if (cache.e[i].mesh) mesh_destroy(m);   /* a second object of the same inputs */
  else cache.e[i].mesh = m;
}
