/*
** OpenSubdiv bridge, Bezier -> B-spline conversion and subdivision:
** the converted net's limit surface is our Bezier patch (random patches and
** the teapot), the bridge reports bad topology instead of crashing, and a
** cube with a sharp crease ring keeps a hard edge while the smooth ring
** beside it rounds off.
*/
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../src/base/mem.h"
#include "../../src/base/rng.h"
#include "../../src/geom/bspline.h"
#include "../../src/geom/osd_bridge.h"
#include "../../src/geom/patch.h"
#include "../../src/geom/refine.h"
#include "../../src/geom/subdiv.h"
#include "../../src/geom/tessellate.h"
#include "unit.h"

/* ---- helpers ------------------------------------------------------------ */

static double dist(Vec3 a, Vec3 b) { return v3_len(v3_sub(a, b)); }

/* A (n+1) x (n+1) grid of parameters in [0, 1]^2. */
static int uv_grid(int n, double *uv) {
  int k = 0;
  for (int j = 0; j <= n; j++)
    for (int i = 0; i <= n; i++) {
      uv[2 * k] = (double)i / n;
      uv[2 * k + 1] = (double)j / n;
      k++;
    }
  return k;
}

/* Largest distance between our evaluation of p and OpenSubdiv's limit of
** its converted net over a grid, for points and both derivatives
** (derivatives relative to the patch size). -1 if the bridge failed. */
static double patch_vs_osd(const ScenePatch *p, double *dmax_deriv) {
  enum { N = 8 };
  double uv[2 * (N + 1) * (N + 1)];
  Vec3 P[(N + 1) * (N + 1)], du[(N + 1) * (N + 1)], dv[(N + 1) * (N + 1)];
  int n = uv_grid(N, uv);
  BsplineRef ref;
  char err[256];
  if (!bspline_ref_init(&ref, p, err, sizeof err)) {
    fprintf(stderr, "bspline_ref_init: %s\n", err);
    return -1;
  }
  if (!bspline_ref_eval(&ref, n, uv, P, du, dv, err, sizeof err)) {
    fprintf(stderr, "bspline_ref_eval: %s\n", err);
    bspline_ref_free(&ref);
    return -1;
  }
  double dp = 0, dd = 0;
  for (int k = 0; k < n; k++) {
    Vec3 qu, qv, q = patch_eval(p, uv[2 * k], uv[2 * k + 1], &qu, &qv);
    dp = fmax(dp, dist(q, P[k]));
    dd = fmax(dd, fmax(dist(qu, du[k]), dist(qv, dv[k])));
  }
  bspline_ref_free(&ref);
  if (dmax_deriv) *dmax_deriv = dd;
  return dp;
}

/* An edge of the patch's boundary collapsed to one point (as on the teapot
** lid and bottom). */
static int patch_degenerate(const ScenePatch *p) {
  static const int edges[4][4] = {{0, 1, 2, 3}, {12, 13, 14, 15}, {0, 4, 8, 12}, {3, 7, 11, 15}};
  for (int e = 0; e < 4; e++) {
    int same = 1;
    for (int k = 1; k < 4; k++) same &= dist(p->cp[edges[e][k]], p->cp[edges[e][0]]) == 0;
    if (same) return 1;
  }
  return 0;
}

/* ---- conversion ----------------------------------------------------------- */

TEST(conversion_identity_on_bspline_basis) {
  /* Linear precision: the Bezier net of p(u, v) = (u, v, 0) (points at
  ** thirds) has the B-spline net at the integer knots i - 1, j - 1. */
  Vec3 bez[16], bsp[16];
  for (int j = 0; j < 4; j++)
    for (int i = 0; i < 4; i++) bez[4 * j + i] = v3(i / 3.0, j / 3.0, 0);
  bspline_from_bezier(bez, bsp);
  for (int j = 0; j < 4; j++)
    for (int i = 0; i < 4; i++) {
      CHECK_NEAR(bsp[4 * j + i].x, i - 1, 1e-12);
      CHECK_NEAR(bsp[4 * j + i].y, j - 1, 1e-12);
      CHECK_NEAR(bsp[4 * j + i].z, 0, 1e-12);
    }
}

TEST(conversion_random_patches) {
  Rng rng;
  rng_seed(&rng, 12345, 0);
  for (int t = 0; t < 200; t++) {
    ScenePatch p = {0};
    for (int k = 0; k < 16; k++)
      p.cp[k] = v3(2 * rng_uniform(&rng) - 1, 2 * rng_uniform(&rng) - 1, 2 * rng_uniform(&rng) - 1);
    double dd = 0, dp = patch_vs_osd(&p, &dd);
    CHECK(dp >= 0);
    CHECK_NEAR(dp, 0, 1e-9);
    CHECK_NEAR(dd, 0, 1e-8);
  }
}

TEST(conversion_bilinear_patch) {
  ScenePatch p;
  patch_bilinear(&p, v3(0, 0, 0), v3(2, 0, 1), v3(0, 1, 0), v3(2, 1.5, -1));
  double dp = patch_vs_osd(&p, NULL);
  CHECK(dp >= 0);
  CHECK_NEAR(dp, 0, 1e-9);
}

TEST(bridge_regular_centre_face) {
  ScenePatch p = {0};
  for (int k = 0; k < 16; k++) p.cp[k] = v3(k % 4, k / 4, (k * 7 % 5) * 0.1);
  BsplineRef ref;
  char err[256];
  double uv[2] = {0.5, 0.5};
  Vec3 P;
  CHECK(bspline_ref_init(&ref, &p, err, sizeof err));
  CHECK(bspline_ref_eval(&ref, 1, uv, &P, NULL, NULL, err, sizeof err));
  CHECK_EQ_INT(ref.regular, 1);
  bspline_ref_free(&ref);
}

/* The teapot: SUMI_SHARED/data/teapot.txt, skipped when absent. */
static int load_teapot(ScenePatch **out) {
  const char *shared = getenv("SUMI_SHARED");
  char path[1024];
  snprintf(path, sizeof path, "%s/data/teapot.txt", shared ? shared : "../shared");
  FILE *f = fopen(path, "r");
  if (!f) return -1;
  char line[512];
  int np = 0, nv = 0, (*idx)[16] = NULL;
  Vec3 *v = NULL;
  while (fgets(line, sizeof line, f)) {
    if (line[0] == '#') continue;
    if (sscanf(line, "patches %d", &np) == 1) {
      idx = xcalloc((size_t)np, sizeof *idx);
      for (int p = 0; p < np && fgets(line, sizeof line, f); p++) {
        char *s = line;
        for (int k = 0; k < 16; k++) idx[p][k] = (int)strtol(s, &s, 10);
      }
    } else if (sscanf(line, "vertices %d", &nv) == 1) {
      v = xcalloc((size_t)nv, sizeof *v);
      for (int i = 0; i < nv && fgets(line, sizeof line, f); i++)
        sscanf(line, "%lf %lf %lf", &v[i].x, &v[i].y, &v[i].z);
    }
  }
  fclose(f);
  if (!idx || !v) { free(idx); free(v); return -1; }
  *out = xcalloc((size_t)np, sizeof **out);
  for (int p = 0; p < np; p++)
    for (int k = 0; k < 16; k++) (*out)[p].cp[k] = v[idx[p][k]];
  free(idx);
  free(v);
  return np;
}

TEST(conversion_teapot) {
  ScenePatch *pt = NULL;
  int np = load_teapot(&pt);
  if (np < 0) { printf("skip: conversion_teapot (no $SUMI_SHARED/data/teapot.txt)\n"); return; }
  CHECK_EQ_INT(np, 32);
  int ndegenerate = 0;
  for (int p = 0; p < np; p++) {
    double dd = 0, dp = patch_vs_osd(&pt[p], &dd);
    CHECK(dp >= 0);
    if (patch_degenerate(&pt[p])) { ndegenerate++; continue; }
    CHECK_NEAR(dp, 0, 1e-9);
    CHECK_NEAR(dd, 0, 1e-8);
  }
  CHECK_EQ_INT(ndegenerate, 8);
  free(pt);
}

/* ---- the bridge's errors ------------------------------------------------------ */

static const int QUAD_SIZE[1] = {4};
static const int QUAD_INDEX[4] = {0, 1, 2, 3};

static SumiOsdTopology quad_topology(void) {
  SumiOsdTopology t = {0};
  t.nverts = 4;
  t.nfaces = 1;
  t.face_size = QUAD_SIZE;
  t.face_index = QUAD_INDEX;
  t.scheme = SUMI_OSD_CATMARK;
  t.boundary = SUMI_OSD_BOUNDARY_EDGE_AND_CORNER;
  return t;
}

TEST(bridge_rejects_bad_topology) {
  char err[256];
  SumiOsdMesh *m = NULL;
  SumiOsdTopology t = quad_topology();
  int bad_index[4] = {0, 1, 2, 7};
  t.face_index = bad_index;
  CHECK(!sumi_osd_create(&t, &m, err, sizeof err));
  CHECK(m == NULL);
  CHECK(strstr(err, "vertex 7") != NULL);

  t = quad_topology();
  t.scheme = SUMI_OSD_LOOP;
  CHECK(!sumi_osd_create(&t, &m, err, sizeof err));
  CHECK(strstr(err, "triangles") != NULL);

  t = quad_topology();
  int pair[2] = {0, 2};   /* a diagonal, not an edge */
  float s = 2;
  t.ncreases = 1;
  t.crease_verts = pair;
  t.crease_sharpness = &s;
  CHECK(!sumi_osd_create(&t, &m, err, sizeof err));
  CHECK(strstr(err, "share no edge") != NULL);

  t = quad_topology();
  int two[1] = {2};
  t.face_size = two;
  CHECK(!sumi_osd_create(&t, &m, err, sizeof err));
  CHECK(strstr(err, "at least 3") != NULL);
}

TEST(bridge_degenerate_face_is_not_a_crash) {
  /* A face that repeats a vertex: OpenSubdiv takes it as non-manifold. */
  static const int size[2] = {4, 3};
  static const int index[7] = {0, 1, 2, 3, 0, 0, 1};
  double pos[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  SumiOsdTopology t = quad_topology();
  t.nfaces = 2;
  t.face_size = size;
  t.face_index = index;
  char err[256] = "";
  SumiOsdMesh *m = NULL;
  SumiOsdRefined r;
  if (sumi_osd_create(&t, &m, err, sizeof err)) {
    int ok = sumi_osd_refine(m, 2, pos, &r, err, sizeof err);
    if (ok) sumi_osd_refined_free(&r);
    else CHECK(err[0] != 0);
    sumi_osd_destroy(m);
  } else {
    CHECK(err[0] != 0);
  }
}

TEST(subdiv_nonmanifold_fin) {
  /* Three quads on one edge (0-1): OpenSubdiv takes it as non-manifold and
  ** sharp; the mesh keeps two triangles on each of its pieces and flags it. */
  static Vec3 v[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                      {1, -1, 0}, {0, -1, 0}, {1, 0, 1}, {0, 0, 1}};
  static int start[4] = {0, 4, 8, 12};
  static int index[12] = {0, 1, 2, 3, 1, 0, 5, 4, 0, 1, 6, 7};
  SceneGeometry g;
  memset(&g, 0, sizeof g);
  g.kind = GEOM_MESH;
  g.nverts = 8; g.verts = v; g.nfaces = 3; g.face_start = start; g.face_index = index;
  g.subdiv_level = 2;
  char err[256];
  Mesh *m = subdiv_mesh(&g, SUMI_OSD_BOUNDARY_EDGE_AND_CORNER, err, sizeof err);
  if (!m) { CHECK(err[0] != 0); return; }
  CHECK_EQ_INT(m->ntris, 3 * 16 * 2);
  int nonmanifold = 0;
  for (int e = 0; e < m->nedges; e++) nonmanifold += m->edges[e].nonmanifold;
  CHECK_EQ_INT(nonmanifold, 4);
  for (int i = 0; i < m->nverts; i++) CHECK(isfinite(m->pos[i].x + m->pos[i].y + m->pos[i].z));
  mesh_destroy(m);
}

/* ---- subdivision ----------------------------------------------------------- */

/* The cube [-1, 1]^3 as 6 quads, outward and counter-clockwise. */
static Vec3 CUBE_V[8] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                         {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
static int CUBE_START[7] = {0, 4, 8, 12, 16, 20, 24};
static int CUBE_INDEX[24] = {0, 3, 2, 1,  4, 5, 6, 7,  0, 1, 5, 4,
                             1, 2, 6, 5,  2, 3, 7, 6,  3, 0, 4, 7};

static SceneGeometry cube(int level, void *creases, int ncreases) {
  SceneGeometry g;
  memset(&g, 0, sizeof g);
  g.kind = GEOM_MESH;
  g.nverts = 8;
  g.verts = CUBE_V;
  g.nfaces = 6;
  g.face_start = CUBE_START;
  g.face_index = CUBE_INDEX;
  g.subdiv_level = level;
  g.subdiv_scheme = "catmark";
  g.ncreases = ncreases;
  g.creases = creases;
  return g;
}

TEST(subdiv_cube_counts_and_closure) {
  char err[256];
  SceneGeometry g = cube(3, NULL, 0);
  Mesh *m = subdiv_mesh(&g, SUMI_OSD_BOUNDARY_EDGE_AND_CORNER, err, sizeof err);
  CHECK(m != NULL);
  if (!m) { fprintf(stderr, "%s\n", err); return; }
  CHECK_EQ_INT(m->ntris, 6 * 64 * 2);
  CHECK_EQ_INT(m->nverts, 6 * 64 + 2);        /* Euler: V - E + F = 2 with quads */
  int boundary = 0;
  for (int e = 0; e < m->nedges; e++) boundary += m->edges[e].f[1] < 0;
  CHECK_EQ_INT(boundary, 0);
  for (int t = 0; t < m->ntris; t++) CHECK(m->tri_face[t] >= 0 && m->tri_face[t] < 6);
  /* Smooth: every point inside the cube, rounded off (no point near a corner),
  ** normals pointing outward. */
  for (int i = 0; i < m->nverts; i++) {
    CHECK(v3_len(m->pos[i]) < sqrt(3.0) * 0.8);
    CHECK(v3_dot(m->nrm[i], m->pos[i]) > 0);
  }
  mesh_destroy(m);
}

/* Limit positions from Far agree with Bfr's limit at the base corners. */
TEST(subdiv_limit_matches_bfr) {
  char err[256];
  SceneGeometry g = cube(2, NULL, 0);
  SumiOsdRefined r;
  Mesh *m = subdiv_mesh_ex(&g, SUMI_OSD_BOUNDARY_EDGE_AND_CORNER, &r, err, sizeof err);
  CHECK(m != NULL);
  if (!m) return;
  SubdivTopology st;
  SumiOsdMesh *osd = NULL;
  CHECK(subdiv_topology(&g, SUMI_OSD_BOUNDARY_EDGE_AND_CORNER, &st, err, sizeof err));
  CHECK(sumi_osd_create(&st.topo, &osd, err, sizeof err));
  static const double corner_uv[8] = {0, 0, 1, 0, 1, 1, 0, 1};
  for (int f = 0; f < 6 && osd; f++) {
    double P[12];
    CHECK(sumi_osd_eval_face(osd, (const double *)CUBE_V, f, 4, corner_uv, P, NULL, NULL, NULL,
                             err, sizeof err));
    for (int k = 0; k < 4; k++) {
      int v = CUBE_INDEX[4 * f + k];   /* base vertices keep their index */
      CHECK_NEAR(dist(m->pos[v], v3(P[3 * k], P[3 * k + 1], P[3 * k + 2])), 0, 1e-9);
    }
  }
  sumi_osd_destroy(osd);
  subdiv_topology_free(&st);
  sumi_osd_refined_free(&r);
  mesh_destroy(m);
}

/* The largest angle (degrees) between the two triangles of a mesh edge,
** over the edges tagged (tagged = 1) or lying in the plane z = zplane. */
static double edge_angle(const Mesh *m, int e) {
  const MeshEdge *ed = &m->edges[e];
  if (ed->f[1] < 0) return 0;
  Vec3 n[2];
  for (int s = 0; s < 2; s++) {
    const int *t = m->tri[ed->f[s]];
    n[s] = v3_norm(v3_cross(v3_sub(m->pos[t[1]], m->pos[t[0]]), v3_sub(m->pos[t[2]], m->pos[t[0]])));
  }
  double c = v3_dot(n[0], n[1]);
  return acos(c > 1 ? 1 : c < -1 ? -1 : c) * 180 / M_PI;
}

TEST(subdiv_crease_ring_keeps_hard_edge) {
  /* Sharp ring around the top face; the bottom ring stays smooth. */
  struct { int a, b; double sharpness; } ring[4] = {{4, 5, 10}, {5, 6, 10}, {6, 7, 10}, {7, 4, 10}};
  char err[256];
  const int level = 4;
  SceneGeometry g = cube(level, ring, 4);
  Mesh *m = subdiv_mesh(&g, SUMI_OSD_BOUNDARY_EDGE_AND_CORNER, err, sizeof err);
  CHECK(m != NULL);
  if (!m) { fprintf(stderr, "%s\n", err); return; }
  int ntagged = 0;
  double top_angle = 180, bottom_angle = 0, zmax = -9, zmin = 9;
  for (int e = 0; e < m->nedges; e++) {
    const MeshEdge *ed = &m->edges[e];
    if (ed->sharpness > 0) {
      ntagged++;
      CHECK_NEAR(ed->sharpness, 10, 0);
      CHECK_NEAR(m->pos[ed->v[0]].z, 1, 1e-12);   /* the crease stays in the top plane */
      top_angle = fmin(top_angle, edge_angle(m, e));
    }
  }
  for (int i = 0; i < m->nverts; i++) {
    zmax = fmax(zmax, m->pos[i].z);
    zmin = fmin(zmin, m->pos[i].z);
  }
  /* The smooth ring: the bottom edges' images, found as the edges between
  ** the bottom face's and the side faces' triangles. */
  for (int e = 0; e < m->nedges; e++) {
    const MeshEdge *ed = &m->edges[e];
    if (ed->f[1] < 0) continue;
    int fa = m->tri_face[ed->f[0]], fb = m->tri_face[ed->f[1]];
    if ((fa == 0) != (fb == 0)) bottom_angle = fmax(bottom_angle, edge_angle(m, e));
  }
  CHECK_EQ_INT(ntagged, 4 << level);
  CHECK_NEAR(zmax, 1, 1e-12);        /* top face flat, in its plane */
  CHECK(zmin > -0.9);                /* bottom rounded off */
  CHECK(top_angle > 60);             /* a hard edge everywhere along the ring */
  CHECK(bottom_angle < 20);          /* smooth across the other ring */
  mesh_destroy(m);
}

/* The edges subdiv takes from OpenSubdiv's topology are those
** mesh_build_edges finds by hashing: same pairs, same triangles, and the
** tags on exactly the edges along the creases. */
static int edge_cmp(const void *x, const void *y) {
  const MeshEdge *a = x, *b = y;
  if (a->v[0] != b->v[0]) return a->v[0] < b->v[0] ? -1 : 1;
  return (a->v[1] > b->v[1]) - (a->v[1] < b->v[1]);
}

static void check_edges_like_hash(Mesh *m) {
  Mesh *h = mesh_create(m->nverts, m->ntris);
  memcpy(h->pos, m->pos, sizeof(Vec3) * (size_t)m->nverts);
  memcpy(h->tri, m->tri, sizeof(int[3]) * (size_t)m->ntris);
  mesh_build_edges(h);
  CHECK_EQ_INT(m->nedges, h->nedges);
  for (int t = 0; t < m->ntris; t++)
    for (int k = 0; k < 3; k++) {
      const MeshEdge *a = &m->edges[m->tri_edges[t][k]], *b = &h->edges[h->tri_edges[t][k]];
      CHECK(a->v[0] == b->v[0] && a->v[1] == b->v[1]);
      CHECK(a->v[0] < a->v[1]);
      CHECK((a->f[0] == b->f[0] && a->f[1] == b->f[1]) || (a->f[0] == b->f[1] && a->f[1] == b->f[0]));
      CHECK(a->f[0] == t || a->f[1] == t);
    }
  MeshEdge *sorted = xmalloc(sizeof *sorted * (size_t)m->nedges);
  memcpy(sorted, m->edges, sizeof *sorted * (size_t)m->nedges);
  qsort(sorted, (size_t)m->nedges, sizeof *sorted, edge_cmp);
  for (int e = 1; e < m->nedges; e++) CHECK(edge_cmp(&sorted[e - 1], &sorted[e]) < 0);
  free(sorted);
  mesh_destroy(h);
}

TEST(subdiv_edges_match_hashing) {
  struct { int a, b; double sharpness; } ring[4] = {{4, 5, 10}, {5, 6, 3}, {6, 7, 10}, {7, 4, 0.5}};
  char err[256];
  SceneGeometry g = cube(3, ring, 4);
  Mesh *m = subdiv_mesh(&g, SUMI_OSD_BOUNDARY_EDGE_AND_CORNER, err, sizeof err);
  CHECK(m != NULL);
  if (!m) return;
  check_edges_like_hash(m);
  /* 2^3 edges a base edge, each with its base crease's sharpness */
  int n10 = 0, n3 = 0, nhalf = 0, nother = 0;
  for (int e = 0; e < m->nedges; e++) {
    float sh = m->edges[e].sharpness;
    if (sh == 10) n10++;
    else if (sh == 3) n3++;
    else if (sh == 0.5f) nhalf++;
    else if (sh != 0) nother++;
  }
  CHECK_EQ_INT(n10, 16);
  CHECK_EQ_INT(n3, 8);
  CHECK_EQ_INT(nhalf, 8);
  CHECK_EQ_INT(nother, 0);
  mesh_destroy(m);

  /* A loop mesh (triangles as they come) and an open grid with a hole. */
  Vec3 v[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  int start[8] = {0, 3, 6, 9, 12, 15, 18, 21};
  int index[21] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5};
  SceneGeometry l;
  memset(&l, 0, sizeof l);
  l.kind = GEOM_MESH;
  l.nverts = 6; l.verts = v; l.nfaces = 7; l.face_start = start; l.face_index = index;
  l.subdiv_level = 2;
  l.subdiv_scheme = "loop";
  m = subdiv_mesh(&l, SUMI_OSD_BOUNDARY_EDGE_AND_CORNER, err, sizeof err);
  CHECK(m != NULL);
  if (m) {
    check_edges_like_hash(m);
    int boundary = 0;
    for (int e = 0; e < m->nedges; e++) boundary += m->edges[e].f[1] < 0;
    CHECK_EQ_INT(boundary, 3 * 4);
    mesh_destroy(m);
  }
}

TEST(subdiv_semi_sharp_is_between) {
  /* The bottom ring at sharpness 0, 1.5 and 10: how far the surface
  ** reaches toward the edge y = z = -1 (min of y + z) lies
  ** between smooth and infinitely sharp. */
  char err[256];
  double zmin[3];
  double sharp[3] = {0, 1.5, 10};
  for (int k = 0; k < 3; k++) {
    struct { int a, b; double sharpness; } ring[4] = {
        {0, 1, sharp[k]}, {1, 2, sharp[k]}, {2, 3, sharp[k]}, {3, 0, sharp[k]}};
    SceneGeometry g = cube(3, ring, 4);
    Mesh *m = subdiv_mesh(&g, SUMI_OSD_BOUNDARY_EDGE_AND_CORNER, err, sizeof err);
    CHECK(m != NULL);
    if (!m) return;
    zmin[k] = 9;
    for (int i = 0; i < m->nverts; i++) zmin[k] = fmin(zmin[k], m->pos[i].y + m->pos[i].z);
    mesh_destroy(m);
  }
  CHECK(zmin[0] > zmin[1] + 0.01);
  CHECK(zmin[1] > zmin[2] + 0.01);
  /* An infinitely sharp ring is the closed cubic B-spline of the square: at
  ** a side's middle, y = (P0 + 23 P1 + 23 P2 + P3) / 48 = -44 / 48. */
  CHECK_NEAR(zmin[2], -1 - 44.0 / 48, 1e-12);
}

TEST(subdiv_loop_and_bilinear) {
  /* An octahedron under loop; the cube under bilinear stays a cube. */
  Vec3 v[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  int start[9] = {0, 3, 6, 9, 12, 15, 18, 21, 24};
  int index[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  SceneGeometry g;
  memset(&g, 0, sizeof g);
  g.kind = GEOM_MESH;
  g.nverts = 6; g.verts = v; g.nfaces = 8; g.face_start = start; g.face_index = index;
  g.subdiv_level = 3;
  g.subdiv_scheme = "loop";
  char err[256];
  Mesh *m = subdiv_mesh(&g, SUMI_OSD_BOUNDARY_EDGE_AND_CORNER, err, sizeof err);
  CHECK(m != NULL);
  if (m) {
    CHECK_EQ_INT(m->ntris, 8 * 64);
    for (int i = 0; i < m->nverts; i++) CHECK(v3_len(m->pos[i]) < 1 && v3_len(m->pos[i]) > 0.4);
    mesh_destroy(m);
  }
  SceneGeometry c = cube(2, NULL, 0);
  c.subdiv_scheme = "bilinear";
  m = subdiv_mesh(&c, SUMI_OSD_BOUNDARY_EDGE_AND_CORNER, err, sizeof err);
  CHECK(m != NULL);
  if (m) {
    CHECK_EQ_INT(m->ntris, 6 * 16 * 2);
    for (int i = 0; i < m->nverts; i++)
      CHECK_NEAR(fmax(fabs(m->pos[i].x), fmax(fabs(m->pos[i].y), fabs(m->pos[i].z))), 1, 1e-12);
    mesh_destroy(m);
  }
}

TEST(subdiv_errors) {
  char err[256];
  SceneGeometry g = cube(SUBDIV_MAX_LEVEL + 1, NULL, 0);
  CHECK(subdiv_mesh(&g, SUMI_OSD_BOUNDARY_EDGE_AND_CORNER, err, sizeof err) == NULL);
  CHECK(strstr(err, "SUBDIV_MAX_LEVEL") != NULL);
  g = cube(SUBDIV_MAX_LEVEL, NULL, 0);   /* 6 * 4^10 faces */
  CHECK(subdiv_mesh(&g, SUMI_OSD_BOUNDARY_EDGE_AND_CORNER, err, sizeof err) == NULL);
  CHECK(strstr(err, "SUBDIV_MAX_FACES") != NULL);
  g = cube(2, NULL, 0);
  g.subdiv_scheme = "doo-sabin";
  CHECK(subdiv_mesh(&g, SUMI_OSD_BOUNDARY_EDGE_AND_CORNER, err, sizeof err) == NULL);
  CHECK(strstr(err, "doo-sabin") != NULL);
  struct { int a, b; double sharpness; } bad[1] = {{0, 6, 1}};
  g = cube(2, bad, 1);
  CHECK(subdiv_mesh(&g, SUMI_OSD_BOUNDARY_EDGE_AND_CORNER, err, sizeof err) == NULL);
  CHECK(strstr(err, "share no edge") != NULL);
  SumiOsdScheme s;
  SumiOsdBoundary b;
  CHECK(subdiv_scheme_parse("loop", &s) && s == SUMI_OSD_LOOP);
  CHECK(!subdiv_scheme_parse("catmull", &s));
  CHECK(subdiv_boundary_parse("edge_only", &b) && b == SUMI_OSD_BOUNDARY_EDGE_ONLY);
  CHECK(!subdiv_boundary_parse("sharp", &b));
}

/* The faces of a 3 x 3 grid of quads over 4 x 4 points, row by row. */
static void grid_quads(int start[10], int index[36]) {
  for (int f = 0; f < 9; f++) {
    int b = 4 * (f / 3) + f % 3;
    start[f] = 4 * f;
    index[4 * f] = b; index[4 * f + 1] = b + 1; index[4 * f + 2] = b + 5; index[4 * f + 3] = b + 4;
  }
  start[9] = 36;
}

TEST(subdiv_open_plane_boundary) {
  /* A 3 x 3 grid of quads, open: edge_and_corner keeps its corners fixed. */
  Vec3 v[16];
  int start[10], index[36];
  for (int j = 0; j < 4; j++)
    for (int i = 0; i < 4; i++) v[4 * j + i] = v3(i, j, (i == 1 || i == 2) && (j == 1 || j == 2));
  grid_quads(start, index);
  SceneGeometry g;
  memset(&g, 0, sizeof g);
  g.kind = GEOM_MESH;
  g.nverts = 16; g.verts = v; g.nfaces = 9; g.face_start = start; g.face_index = index;
  g.subdiv_level = 2;
  char err[256];
  Mesh *m = subdiv_mesh(&g, SUMI_OSD_BOUNDARY_EDGE_AND_CORNER, err, sizeof err);
  CHECK(m != NULL);
  if (!m) return;
  CHECK_NEAR(dist(m->pos[0], v[0]), 0, 1e-12);
  CHECK_NEAR(dist(m->pos[15], v[15]), 0, 1e-12);
  int boundary = 0;
  for (int e = 0; e < m->nedges; e++) boundary += m->edges[e].f[1] < 0;
  CHECK_EQ_INT(boundary, 12 * 4);
  mesh_destroy(m);
  m = subdiv_mesh(&g, SUMI_OSD_BOUNDARY_EDGE_ONLY, err, sizeof err);
  CHECK(m != NULL);
  if (m) {
    CHECK(dist(m->pos[0], v[0]) > 0.01);   /* corners smooth: pulled in */
    mesh_destroy(m);
  }
}

#define SAME(a, b, n) (!memcmp((a), (b), sizeof *(a) * (size_t)(n)))

/* Every array of two refinements the same. */
static int same_refinement(const SumiOsdRefined *a, const SumiOsdRefined *b) {
  if (a->nverts != b->nverts || a->nfaces != b->nfaces || a->nedges != b->nedges ||
      a->nsharp != b->nsharp)
    return 0;
  int nidx = b->face_start[b->nfaces];
  return SAME(a->ctrl, b->ctrl, 3 * b->nverts) && SAME(a->limit, b->limit, 3 * b->nverts) &&
         SAME(a->normal, b->normal, 3 * b->nverts) &&
         SAME(a->vert_sharpness, b->vert_sharpness, b->nverts) &&
         SAME(a->face_start, b->face_start, b->nfaces + 1) &&
         SAME(a->face_index, b->face_index, nidx) && SAME(a->face_edges, b->face_edges, nidx) &&
         SAME(a->face_base, b->face_base, b->nfaces) &&
         SAME(a->edge_verts, b->edge_verts, 2 * b->nedges) &&
         SAME(a->edge_tag, b->edge_tag, b->nedges) &&
         SAME(a->sharp_verts, b->sharp_verts, 2 * b->nsharp) &&
         SAME(a->sharp, b->sharp, b->nsharp) && SAME(a->sharp_now, b->sharp_now, b->nsharp);
}

/* The bridge's refinement on 1 and 3 threads (the last level's points,
** their limit positions and normals, its faces and edges, made from the
** level above where the bridge does not have OpenSubdiv make the last
** level's full topology) is Far's own (Interpolate, Limit, the full
** topology), bit for bit. */
static int points_are_far_points(const SceneGeometry *g, SumiOsdBoundary boundary) {
  char err[256];
  SubdivTopology st;
  if (!subdiv_topology(g, boundary, &st, err, sizeof err)) return 0;
  SumiOsdRefined far, ours[2];
  const double *pos = (const double *)g->verts;
  int ok = sumi_osd_refine_far(&st.topo, g->subdiv_level, pos, &far, err, sizeof err);
  for (int k = 0; k < 2; k++) {
    int threads = k ? 3 : 1;
    if (!sumi_osd_refine_topology(&st.topo, g->subdiv_level, pos, 1, threads, &ours[k], err,
                                  sizeof err)) {
      ok = 0;
      continue;
    }
    ok = ok && same_refinement(&ours[k], &far);
    sumi_osd_refined_free(&ours[k]);
  }
  if (!ok) fprintf(stderr, "points differ from Far's: %s\n", err);
  sumi_osd_refined_free(&far);
  subdiv_topology_free(&st);
  return ok;
}

TEST(subdiv_points_are_far_points) {
  /* The cube, moved off its round numbers, with a semi-sharp and a sharp
  ** crease and a corner; the open grid under each boundary rule; an
  ** octahedron and an open fan under loop; a cone of 20 triangles (a
  ** valence the masks are not kept for); a bow tie; the non-manifold fin. */
  Vec3 cv[8];
  for (int i = 0; i < 8; i++)
    cv[i] = v3_add(CUBE_V[i], v3(0.1 * sin(3.0 * i), 0.07 * cos(5.0 * i), 0.03 * i));
  struct { int a, b; double sharpness; } creases[3] = {{4, 5, 1.5}, {5, 6, 10}, {0, 1, 0.4}};
  struct { int v; double sharpness; } corner[1] = {{3, 2.5}};
  for (int level = 1; level <= 3; level++) {
    SceneGeometry g = cube(level, creases, 3);
    g.verts = cv;
    g.ncorners = 1;
    g.corners = (void *)corner;
    CHECK(points_are_far_points(&g, SUMI_OSD_BOUNDARY_EDGE_AND_CORNER));
  }
  Vec3 v[16];
  int start[10], index[36];
  for (int j = 0; j < 4; j++)
    for (int i = 0; i < 4; i++) v[4 * j + i] = v3(i + 0.1 * j, j, sin(i + 2.0 * j));
  grid_quads(start, index);
  SceneGeometry grid;
  memset(&grid, 0, sizeof grid);
  grid.kind = GEOM_MESH;
  grid.nverts = 16; grid.verts = v; grid.nfaces = 9;
  grid.face_start = start; grid.face_index = index;
  grid.subdiv_level = 3;
  CHECK(points_are_far_points(&grid, SUMI_OSD_BOUNDARY_EDGE_AND_CORNER));
  CHECK(points_are_far_points(&grid, SUMI_OSD_BOUNDARY_EDGE_ONLY));
  CHECK(points_are_far_points(&grid, SUMI_OSD_BOUNDARY_NONE));
  /* the grid as triangles, loop: an open mesh */
  int tstart[19], tindex[54];
  for (int f = 0; f < 9; f++) {
    const int *q = index + 4 * f;
    int t[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
    memcpy(tindex + 6 * f, t, sizeof t);
  }
  for (int t = 0; t <= 18; t++) tstart[t] = 3 * t;
  SceneGeometry fan = grid;
  fan.nfaces = 18; fan.face_start = tstart; fan.face_index = tindex;
  fan.subdiv_scheme = "loop";
  CHECK(points_are_far_points(&fan, SUMI_OSD_BOUNDARY_EDGE_AND_CORNER));
  Vec3 ov[6] = {{1, 0.1, 0}, {-1, 0, 0.2}, {0, 1, 0}, {0.3, -1, 0}, {0, 0, 1}, {0, 0.1, -1}};
  int ostart[9] = {0, 3, 6, 9, 12, 15, 18, 21, 24};
  int oindex[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  SceneGeometry oct;
  memset(&oct, 0, sizeof oct);
  oct.kind = GEOM_MESH;
  oct.nverts = 6; oct.verts = ov; oct.nfaces = 8; oct.face_start = ostart; oct.face_index = oindex;
  oct.subdiv_level = 3;
  oct.subdiv_scheme = "loop";
  CHECK(points_are_far_points(&oct, SUMI_OSD_BOUNDARY_EDGE_AND_CORNER));
  enum { N = 20 };
  Vec3 kv[N + 1];
  int kstart[N + 1], kindex[3 * N];
  kv[N] = v3(0, 0, 1);
  for (int i = 0; i < N; i++) {
    kv[i] = v3(cos(2 * M_PI * i / N), sin(2 * M_PI * i / N), 0.1 * (i % 3));
    kstart[i] = 3 * i;
    kindex[3 * i] = N; kindex[3 * i + 1] = i; kindex[3 * i + 2] = (i + 1) % N;
  }
  kstart[N] = 3 * N;
  SceneGeometry cone;
  memset(&cone, 0, sizeof cone);
  cone.kind = GEOM_MESH;
  cone.nverts = N + 1; cone.verts = kv; cone.nfaces = N;
  cone.face_start = kstart; cone.face_index = kindex;
  cone.subdiv_level = 2;
  CHECK(points_are_far_points(&cone, SUMI_OSD_BOUNDARY_EDGE_AND_CORNER));
  cone.subdiv_scheme = "loop";
  CHECK(points_are_far_points(&cone, SUMI_OSD_BOUNDARY_EDGE_ONLY));
  /* a bow tie: two quads meeting at a vertex (non-manifold there, its edges manifold) */
  static Vec3 bv[7] = {{0, 0, 0},   {1, 0, 0.2},  {1, 1, 0}, {0, 1, 0.1},
                       {-1, 0, 0.3}, {-1, -1, 0}, {0, -1, 0}};
  static int bstart[3] = {0, 4, 8};
  static int bindex[8] = {0, 1, 2, 3, 0, 4, 5, 6};
  SceneGeometry bow;
  memset(&bow, 0, sizeof bow);
  bow.kind = GEOM_MESH;
  bow.nverts = 7; bow.verts = bv; bow.nfaces = 2; bow.face_start = bstart; bow.face_index = bindex;
  bow.subdiv_level = 3;
  CHECK(points_are_far_points(&bow, SUMI_OSD_BOUNDARY_EDGE_AND_CORNER));
  CHECK(points_are_far_points(&bow, SUMI_OSD_BOUNDARY_EDGE_ONLY));
  static Vec3 fv[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                       {1, -1, 0}, {0, -1, 0}, {1, 0, 1}, {0, 0, 1}};
  static int fstart[4] = {0, 4, 8, 12};
  static int findex[12] = {0, 1, 2, 3, 1, 0, 5, 4, 0, 1, 6, 7};
  SceneGeometry fin;
  memset(&fin, 0, sizeof fin);
  fin.kind = GEOM_MESH;
  fin.nverts = 8; fin.verts = fv; fin.nfaces = 3; fin.face_start = fstart; fin.face_index = findex;
  fin.subdiv_level = 2;
  CHECK(points_are_far_points(&fin, SUMI_OSD_BOUNDARY_EDGE_AND_CORNER));
}

/* ---- the refinement reference -------------------------------------------------- */

/* Two bumpy patches side by side, sharing the border u = 1 / u = 0. */
static SceneGeometry two_patches(ScenePatch p[2]) {
  for (int j = 0; j < 4; j++)
    for (int i = 0; i < 4; i++) {
      double h = (i == 1 || i == 2) && (j == 1 || j == 2) ? 0.8 : 0.1 * i * j;
      p[0].cp[4 * j + i] = v3(i, j, h);
      p[1].cp[4 * j + i] = v3(3 + i, j, i == 0 ? 0.1 * 3 * j : h - 0.5 * i);
      p[0].bilinear = p[1].bilinear = 0;
    }
  SceneGeometry g;
  memset(&g, 0, sizeof g);
  g.kind = GEOM_PATCHES;
  g.npatches = 2;
  g.patches = p;
  return g;
}

TEST(refine_uniform_converges) {
  ScenePatch p[2];
  SceneGeometry g = two_patches(p);
  char err[256];
  double prev = INFINITY;
  for (int n = 4; n <= 32; n *= 2) {
    Mesh *m = tess_uniform(&g, n);
    RefineStats st;
    CHECK(refine_patch_mesh(&g, m, NULL, NULL, &st, err, sizeof err));
    CHECK_EQ_INT(st.ntris, 2 * 2 * n * n);
    CHECK(st.max_units < prev / 2.5);   /* chord error falls as 1 / n^2 */
    CHECK(st.max_units > 0);
    prev = st.max_units;
    mesh_destroy(m);
  }
  CHECK(prev < 2e-3);
}

TEST(refine_evaluation_exact) {
  ScenePatch p[2];
  SceneGeometry g = two_patches(p);
  char err[256];
  RefineStats st, sd;
  CHECK(refine_patch_eval(&g, 16, NULL, NULL, &st, &sd, err, sizeof err));
  CHECK_EQ_INT(st.samples, 2 * 17 * 17);
  CHECK_EQ_INT(sd.samples, 0);
  CHECK_NEAR(st.max_units, 0, 1e-12);
}

/* The adaptive tessellation stays within its stated screen tolerance of
** the limit surface, and is not wastefully fine either. */
static void check_adaptive(const SceneGeometry *g, const char *what) {
  char err[256];
  RefineStats st;
  Mesh *m;
  SceneCamera sc;
  memset(&sc, 0, sizeof sc);
  Camera cam;
  const char *why = NULL;
  Vec3 lo = g->patches[0].cp[0], hi = lo;
  for (int i = 0; i < g->npatches; i++)
    for (int k = 0; k < 16; k++) {
      Vec3 q = g->patches[i].cp[k];
      lo = v3(fmin(lo.x, q.x), fmin(lo.y, q.y), fmin(lo.z, q.z));
      hi = v3(fmax(hi.x, q.x), fmax(hi.y, q.y), fmax(hi.z, q.z));
    }
  CHECK(camera_setup(&cam, &sc, 320, 240, lo, hi, 0, &why));
  Mat4 id = m4_identity();
  for (double px = 0.25; px <= 2; px *= 2) {
    m = tess_adaptive(g, &cam.world_to_clip, cam.width, cam.height, px);
    CHECK(refine_patch_mesh(g, m, &id, &cam, &st, err, sizeof err));
    printf("%s: adaptive %g px: %d tris, max %.3g px mean %.3g px\n", what, px, st.ntris,
           st.max_px, st.mean_px);
    CHECK(st.max_px <= px);
    CHECK(st.max_px > px / 10);
    mesh_destroy(m);
  }
}

TEST(refine_adaptive_within_tolerance) {
  ScenePatch p[2];
  SceneGeometry g = two_patches(p);
  check_adaptive(&g, "two patches");
  ScenePatch *pt = NULL;
  int np = load_teapot(&pt);
  if (np < 0) { printf("skip: teapot part of refine_adaptive_within_tolerance\n"); return; }
  SceneGeometry t;
  memset(&t, 0, sizeof t);
  t.kind = GEOM_PATCHES;
  t.npatches = np;
  t.patches = pt;
  check_adaptive(&t, "teapot");
  free(pt);
}

TEST(refine_subdiv_drawn_vs_limit) {
  struct { int a, b; double sharpness; } ring[4] = {{4, 5, 10}, {5, 6, 10}, {6, 7, 10}, {7, 4, 2}};
  char err[256];
  double prev = INFINITY, prev_mean = INFINITY;
  for (int level = 2; level <= 5; level++) {
    SceneGeometry g = cube(level, ring, 4);
    RefineStats st;
    CHECK(refine_subdiv(&g, SUMI_OSD_BOUNDARY_EDGE_AND_CORNER, NULL, NULL, &st, err, sizeof err));
    CHECK_EQ_INT(st.ntris, 6 * 2 << (2 * level));
    CHECK_EQ_INT(st.samples, 15L * st.ntris);
    /* chords to the limit: the mean falls by 4 a level; the largest, near
    ** the extraordinary corners and the semi-sharp edge, by about 3 */
    CHECK(st.mean_units < prev_mean / 3.5);
    CHECK(st.max_units < prev / 2.5);
    prev = st.max_units;
    prev_mean = st.mean_units;
  }
  CHECK(prev < 5e-3);
}

int main(void) {
  RUN(conversion_identity_on_bspline_basis);
  RUN(conversion_random_patches);
  RUN(conversion_bilinear_patch);
  RUN(bridge_regular_centre_face);
  RUN(conversion_teapot);
  RUN(bridge_rejects_bad_topology);
  RUN(bridge_degenerate_face_is_not_a_crash);
  RUN(subdiv_nonmanifold_fin);
  RUN(subdiv_cube_counts_and_closure);
  RUN(subdiv_limit_matches_bfr);
  RUN(subdiv_crease_ring_keeps_hard_edge);
  RUN(subdiv_edges_match_hashing);
  RUN(subdiv_semi_sharp_is_between);
  RUN(subdiv_loop_and_bilinear);
  RUN(subdiv_errors);
  RUN(subdiv_open_plane_boundary);
  RUN(subdiv_points_are_far_points);
  RUN(refine_uniform_converges);
  RUN(refine_evaluation_exact);
  RUN(refine_adaptive_within_tolerance);
  RUN(refine_subdiv_drawn_vs_limit);
  return unit_done();
}
