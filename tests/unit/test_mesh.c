/*
** Mesh topology and welding: edge counts and adjacency, the non-manifold
** flag, area-weighted normals, and deterministic welding.
*/
#include <stdlib.h>

#include "../../src/geom/mesh.h"
#include "unit.h"

static Mesh *make_mesh(int nv, const Vec3 *pos, int nt, const int (*tri)[3]) {
  Mesh *m = mesh_create(nv, nt);
  for (int i = 0; i < nv; i++) m->pos[i] = pos[i];
  for (int t = 0; t < nt; t++) {
    for (int k = 0; k < 3; k++) m->tri[t][k] = tri[t][k];
    m->tri_face[t] = t;
  }
  return m;
}

/* The edge between a and b, or -1. */
static int find_edge(const Mesh *m, int a, int b) {
  for (int e = 0; e < m->nedges; e++)
    if ((m->edges[e].v[0] == a && m->edges[e].v[1] == b) || (m->edges[e].v[0] == b && m->edges[e].v[1] == a))
      return e;
  return -1;
}

TEST(create_and_destroy) {
  Mesh *m = mesh_create(3, 1);
  CHECK_EQ_INT(m->nverts, 3);
  CHECK_EQ_INT(m->ntris, 1);
  CHECK(m->uv == NULL);
  CHECK(m->edges == NULL);
  mesh_destroy(m);
  mesh_destroy(NULL);
}

TEST(two_triangles) {
  /* a unit square split along 0-2 */
  Vec3 p[] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  int t[][3] = {{0, 1, 2}, {0, 2, 3}};
  Mesh *m = make_mesh(4, p, 2, t);
  mesh_build_edges(m);
  CHECK_EQ_INT(m->nedges, 5);
  int d = find_edge(m, 0, 2);
  CHECK(d >= 0);
  if (d >= 0) {
    CHECK_EQ_INT(m->edges[d].v[0], 0);
    CHECK_EQ_INT(m->edges[d].v[1], 2);
    CHECK_EQ_INT(m->edges[d].f[0], 0);
    CHECK_EQ_INT(m->edges[d].f[1], 1);
  }
  int boundary = 0;
  for (int e = 0; e < m->nedges; e++) {
    CHECK(m->edges[e].v[0] < m->edges[e].v[1]);
    CHECK(!m->edges[e].nonmanifold);
    if (m->edges[e].f[1] < 0) boundary++;
  }
  CHECK_EQ_INT(boundary, 4);
  /* tri_edges name the sides v0v1, v1v2, v2v0 */
  for (int i = 0; i < 2; i++)
    for (int k = 0; k < 3; k++)
      CHECK_EQ_INT(m->tri_edges[i][k], find_edge(m, t[i][k], t[i][(k + 1) % 3]));
  /* rebuilding replaces, never appends */
  mesh_build_edges(m);
  CHECK_EQ_INT(m->nedges, 5);
  mesh_destroy(m);
}

TEST(tetrahedron_closed) {
  Vec3 p[] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  int t[][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  Mesh *m = make_mesh(4, p, 4, t);
  mesh_build_edges(m);
  CHECK_EQ_INT(m->nedges, 6);
  for (int e = 0; e < m->nedges; e++) CHECK(m->edges[e].f[0] >= 0 && m->edges[e].f[1] >= 0);
  /* V - E + F = 2 */
  CHECK_EQ_INT(m->nverts - m->nedges + m->ntris, 2);
  mesh_compute_normals(m);
  /* outward: every vertex normal points away from the centroid */
  Vec3 c = v3(0.25, 0.25, 0.25);
  for (int i = 0; i < 4; i++) {
    CHECK_NEAR(v3_len(m->nrm[i]), 1, 1e-12);
    CHECK(v3_dot(m->nrm[i], v3_sub(m->pos[i], c)) > 0);
  }
  /* vertex 0 touches three faces of area 1/2 with normals -x, -y, -z */
  double s = 1 / sqrt(3.0);
  CHECK_NEAR(m->nrm[0].x, -s, 1e-12);
  CHECK_NEAR(m->nrm[0].y, -s, 1e-12);
  CHECK_NEAR(m->nrm[0].z, -s, 1e-12);
  mesh_destroy(m);
}

TEST(area_weighting) {
  /* vertex 0 shared by a big triangle facing +z and a small one facing +x */
  Vec3 p[] = {{0, 0, 0}, {3, 0, 0}, {0, 3, 0}, {0, 0, -1}, {0, 1, 0}};
  int t[][3] = {{0, 1, 2}, {0, 3, 4}};
  Mesh *m = make_mesh(5, p, 2, t);
  mesh_compute_normals(m);
  /* weights 9 (+z) and 1 (+x): normalize(1, 0, 9) */
  double l = sqrt(82.0);
  CHECK_NEAR(m->nrm[0].x, 1 / l, 1e-12);
  CHECK_NEAR(m->nrm[0].z, 9 / l, 1e-12);
  mesh_destroy(m);
}

TEST(nonmanifold_flag) {
  /* three triangles on edge 0-1 */
  Vec3 p[] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  int t[][3] = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  Mesh *m = make_mesh(5, p, 3, t);
  mesh_build_edges(m);
  int e = find_edge(m, 0, 1);
  CHECK(e >= 0);
  if (e >= 0) {
    CHECK(m->edges[e].nonmanifold);
    CHECK_EQ_INT(m->edges[e].f[0], 0);
    CHECK_EQ_INT(m->edges[e].f[1], 1);
  }
  CHECK_EQ_INT(m->nedges, 7);
  mesh_destroy(m);
}

TEST(weld) {
  /* two separate triangles whose shared side was written twice, one copy
  ** off by 1e-9; plus a far vertex that must stay */
  Vec3 p[] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 1e-9}, {1, 1, 0}, {0, 1, 0}, {5, 5, 5}};
  int t[][3] = {{0, 1, 2}, {3, 4, 5}};
  Mesh *m = make_mesh(7, p, 2, t);
  mesh_build_edges(m);
  CHECK_EQ_INT(m->nedges, 6);
  mesh_weld(m, 1e-6);
  CHECK_EQ_INT(m->nverts, 5);
  CHECK_EQ_INT(m->ntris, 2);
  /* kept vertices keep their order: 0 1 2 4 6 */
  CHECK_NEAR(m->pos[3].x, 1, 0);
  CHECK_NEAR(m->pos[3].y, 1, 0);
  CHECK_NEAR(m->pos[4].x, 5, 0);
  CHECK_EQ_INT(m->tri[1][0], 1);
  CHECK_EQ_INT(m->tri[1][1], 3);
  CHECK_EQ_INT(m->tri[1][2], 2);
  /* topology was rebuilt: the diagonal is now shared */
  CHECK_EQ_INT(m->nedges, 5);
  int e = find_edge(m, 1, 2);
  CHECK(e >= 0 && m->edges[e].f[1] == 1);
  mesh_destroy(m);
}

TEST(weld_drops_collapsed_triangles) {
  /* a sliver whose two corners coincide after welding */
  Vec3 p[] = {{0, 0, 0}, {1, 0, 0}, {1, 1e-12, 0}, {0, 1, 0}};
  int t[][3] = {{0, 1, 2}, {0, 2, 3}};
  Mesh *m = make_mesh(4, p, 2, t);
  mesh_weld(m, 1e-9);
  CHECK_EQ_INT(m->nverts, 3);
  CHECK_EQ_INT(m->ntris, 1);
  CHECK_EQ_INT(m->tri_face[0], 1);
  mesh_destroy(m);
}

TEST(weld_exact_and_far) {
  /* eps 0 merges only identical positions (and -0 with +0) */
  Vec3 p[] = {{0, 0, 0}, {-0.0, 0, 0}, {1e-300, 0, 0}, {1e9, 1e9, 1e9}, {1e9, 1e9, 1e9}};
  int t[][3] = {{0, 2, 3}};
  Mesh *m = make_mesh(5, p, 1, t);
  mesh_weld(m, 0);
  CHECK_EQ_INT(m->nverts, 3);
  mesh_destroy(m);
  /* points on both sides of a cell border still meet */
  Vec3 q[] = {{0.999999, 0, 0}, {1.000001, 0, 0}, {-0.0000004, 0, 0}, {0.0000004, 0, 0}};
  int s[][3] = {{0, 1, 2}};
  m = make_mesh(4, q, 1, s);
  mesh_weld(m, 1e-5);
  CHECK_EQ_INT(m->nverts, 2);
  CHECK_EQ_INT(m->ntris, 0);
  mesh_destroy(m);
}

TEST(grid_counts) {
  /* an n x n grid of quads, two triangles each: V = (n+1)^2, F = 2n^2,
  ** E = 2n(n+1) + n^2, 4n on the boundary */
  enum { N = 7 };
  Mesh *m = mesh_create((N + 1) * (N + 1), 2 * N * N);
  for (int j = 0; j <= N; j++)
    for (int i = 0; i <= N; i++) m->pos[j * (N + 1) + i] = v3(i, j, 0);
  int t = 0;
  for (int j = 0; j < N; j++)
    for (int i = 0; i < N; i++) {
      int a = j * (N + 1) + i;
      m->tri[t][0] = a; m->tri[t][1] = a + 1; m->tri[t][2] = a + N + 2; t++;
      m->tri[t][0] = a; m->tri[t][1] = a + N + 2; m->tri[t][2] = a + N + 1; t++;
    }
  mesh_build_edges(m);
  CHECK_EQ_INT(m->nedges, 2 * N * (N + 1) + N * N);
  int boundary = 0;
  for (int e = 0; e < m->nedges; e++) boundary += m->edges[e].f[1] < 0;
  CHECK_EQ_INT(boundary, 4 * N);
  mesh_compute_normals(m);
  for (int i = 0; i < m->nverts; i++) CHECK_NEAR(m->nrm[i].z, 1, 1e-15);
  mesh_destroy(m);
}

/* A roof: two unit squares (two triangles each) meeting along the x axis,
** tilted by angle degrees from the xy-plane each, facing up. */
static Mesh *roof(double angle) {
  double c = cos(angle * M_PI / 180), z = sin(angle * M_PI / 180);
  Vec3 p[] = {{0, 0, 0}, {1, 0, 0}, {1, c, -z}, {0, c, -z}, {1, -c, -z}, {0, -c, -z}};
  int t[][3] = {{0, 2, 3}, {0, 1, 2}, {0, 4, 1}, {0, 5, 4}};
  Mesh *m = make_mesh(6, p, 4, t);
  mesh_compute_normals(m);
  return m;
}

TEST(smooth_corners) {
  /* a 45-degree slope each side: the faces meet at 90 degrees, so each
  ** corner on the ridge shades with its own face's normal */
  Mesh *m = roof(45);
  CHECK(m->nrm[0].z > 0.99);   /* the plain vertex normal bends over the ridge */
  mesh_smooth_corners(m, 45);
  CHECK(m->corner_nrm != NULL);
  if (m->corner_nrm)
    for (int t = 0; t < 4; t++)
      for (int k = 0; k < 3; k++) {
        Vec3 n = mesh_corner_normal(m, t, k), a = m->pos[m->tri[t][0]];
        Vec3 f = v3_norm(v3_cross(v3_sub(m->pos[m->tri[t][1]], a), v3_sub(m->pos[m->tri[t][2]], a)));
        CHECK_NEAR(v3_dot(n, f), 1, 1e-12);
      }
  mesh_destroy(m);
  /* a gentle ridge (faces 20 degrees apart) stays smooth: no corner normals */
  m = roof(10);
  mesh_smooth_corners(m, 45);
  CHECK(m->corner_nrm == NULL);
  CHECK_NEAR(mesh_corner_normal(m, 0, 0).z, 1, 1e-12);
  mesh_destroy(m);
}

TEST(weld_keeps_corner_normals) {
  /* the roof's ridge written twice (one copy per side), then welded: the
  ** corners keep their faces' normals, the weld keeps the topology */
  double c = cos(M_PI / 4), z = sin(M_PI / 4);
  Vec3 p[] = {{0, 0, 0}, {1, 0, 0}, {1, c, -z}, {0, c, -z}, {0, 0, 0}, {1, 0, 0}, {1, -c, -z}, {0, -c, -z}};
  int t[][3] = {{0, 2, 3}, {0, 1, 2}, {4, 6, 5}, {4, 7, 6}};
  Mesh *m = make_mesh(8, p, 4, t);
  mesh_compute_normals(m);
  m->corner_nrm = malloc(4 * sizeof *m->corner_nrm);
  for (int i = 0; i < 4; i++)
    for (int k = 0; k < 3; k++) m->corner_nrm[i][k] = m->nrm[m->tri[i][k]];
  mesh_weld(m, 1e-9);
  CHECK_EQ_INT(m->nverts, 6);
  CHECK(m->corner_nrm != NULL);
  if (m->corner_nrm) {
    CHECK_NEAR(m->corner_nrm[0][0].y, z, 1e-12);    /* the +y side's own normal */
    CHECK_NEAR(m->corner_nrm[2][0].y, -z, 1e-12);   /* the -y side's own normal */
  }
  mesh_build_edges(m);
  int e = find_edge(m, 0, 1);
  CHECK(e >= 0 && m->edges[e].f[1] >= 0);
  mesh_destroy(m);
  /* two copies of one flat square: the corner normals agree, and go */
  Vec3 q[] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  int s2[][3] = {{0, 1, 2}, {3, 4, 5}};
  m = make_mesh(6, q, 2, s2);
  mesh_compute_normals(m);
  m->corner_nrm = malloc(2 * sizeof *m->corner_nrm);
  for (int i = 0; i < 2; i++)
    for (int k = 0; k < 3; k++) m->corner_nrm[i][k] = m->nrm[m->tri[i][k]];
  mesh_weld(m, 0);
  CHECK_EQ_INT(m->nverts, 4);
  CHECK(m->corner_nrm == NULL);
  mesh_destroy(m);
}

int main(void) {
  RUN(create_and_destroy);
  RUN(two_triangles);
  RUN(tetrahedron_closed);
  RUN(area_weighting);
  RUN(nonmanifold_flag);
  RUN(weld);
  RUN(weld_drops_collapsed_triangles);
  RUN(weld_exact_and_far);
  RUN(grid_counts);
  RUN(smooth_corners);
  RUN(weld_keeps_corner_normals);
  return unit_done();
}
