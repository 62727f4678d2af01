/*
** Tessellation: grid counts, welding across patch borders, orientation,
** and the crack-free property of adaptive tessellation on the teapot at
** several tolerances (topological watertightness: every edge of the welded
** mesh has two faces except on patch borders no other patch shares, and
** the two faces traverse it in opposite directions); flatness against the
** true surface; polygon triangulation.
*/
#include <stdlib.h>
#include <string.h>

#include "../../src/geom/patch.h"
#include "../../src/geom/tessellate.h"
#include "../../src/render/render.h"
#include "render_scenes.h"
#include "teapot_npr.h"
#include "unit.h"

/* ---- helpers ----------------------------------------------------------- */

static ScenePatch patch_from(Vec3 (*f)(double, double)) {
  ScenePatch p = {0};
  for (int j = 0; j < 4; j++)
    for (int i = 0; i < 4; i++) p.cp[4 * j + i] = f(i / 3.0, j / 3.0);
  return p;
}

/* Patch A over [0,1]^2 and patch B over [1,2] x [0,1], sharing the curved
** border x = 1; B's parameters run so its border is its v = 0 row, in the
** opposite direction to A's u = 1 column. Both face +z (roughly). */
static double bump(double y) { return y == 0 ? 0 : y < 0.4 ? 0.5 : y < 0.7 ? -0.3 : 0.2; }
static Vec3 net_a(double s, double t) { return v3(s, t, s == 1 ? bump(t) : 0.1 * s * t); }
static Vec3 net_b(double s, double t) { return v3(1 + t, 1 - s, t == 0 ? bump(1 - s) : -0.2 * t * s); }

static SceneGeometry two_patches(ScenePatch *store) {
  SceneGeometry g;
  memset(&g, 0, sizeof g);
  store[0] = patch_from(net_a);
  store[1] = patch_from(net_b);
  g.kind = GEOM_PATCHES;
  g.npatches = 2;
  g.patches = store;
  return g;
}

static Vec3 tri_normal(const Mesh *m, int t) {
  Vec3 a = m->pos[m->tri[t][0]], b = m->pos[m->tri[t][1]], c = m->pos[m->tri[t][2]];
  return v3_cross(v3_sub(b, a), v3_sub(c, a));
}

/* Whether every vertex normal is a finite unit vector. */
static int normals_ok(const Mesh *m) {
  for (int i = 0; i < m->nverts; i++) {
    Vec3 n = m->nrm[i];
    if (!isfinite(n.x) || !isfinite(n.y) || !isfinite(n.z) || fabs(v3_len(n) - 1) > 1e-9) return 0;
  }
  return 1;
}

/* Whether the two faces of every interior edge run it in opposite
** directions (a consistently oriented surface). */
static int oriented(const Mesh *m) {
  for (int e = 0; e < m->nedges; e++) {
    const MeshEdge *d = &m->edges[e];
    if (d->f[1] < 0) continue;
    int dir[2];
    for (int s = 0; s < 2; s++) {
      const int *t = m->tri[d->f[s]];
      dir[s] = 0;
      for (int k = 0; k < 3; k++)
        if (t[k] == d->v[0] && t[(k + 1) % 3] == d->v[1]) dir[s] = 1;
        else if (t[k] == d->v[1] && t[(k + 1) % 3] == d->v[0]) dir[s] = -1;
    }
    if (dir[0] * dir[1] != -1) return 0;
  }
  return 1;
}

static int count_nonmanifold(const Mesh *m) {
  int n = 0;
  for (int e = 0; e < m->nedges; e++) n += m->edges[e].nonmanifold;
  return n;
}

/* The border curves of g that no other patch shares (same four control
** points, either way round) and that do not collapse to a point. */
typedef struct Border { Vec3 c[4]; } Border;

static void border_of(const ScenePatch *p, int k, Vec3 c[4]) {
  for (int i = 0; i < 4; i++)
    c[i] = k == 0 ? p->cp[i] : k == 1 ? p->cp[4 * i + 3] : k == 2 ? p->cp[12 + i] : p->cp[4 * i];
}

static int same_border(const Vec3 a[4], const Vec3 b[4]) {
  int fwd = 1, rev = 1;
  for (int i = 0; i < 4; i++) {
    if (v3_len(v3_sub(a[i], b[i])) > 1e-12) fwd = 0;
    if (v3_len(v3_sub(a[i], b[3 - i])) > 1e-12) rev = 0;
  }
  return fwd || rev;
}

static int open_borders(const SceneGeometry *g, Border *out) {
  int n = 0;
  for (int p = 0; p < g->npatches; p++)
    for (int k = 0; k < 4; k++) {
      Vec3 c[4];
      border_of(&g->patches[p], k, c);
      if (v3_len(v3_sub(c[0], c[3])) < 1e-12 && v3_len(v3_sub(c[1], c[0])) < 1e-12) continue;
      int shared = 0;
      for (int q = 0; q < g->npatches && !shared; q++)
        for (int l = 0; l < 4 && !shared; l++) {
          Vec3 d[4];
          if (q == p && l == k) continue;
          border_of(&g->patches[q], l, d);
          shared = same_border(c, d);
        }
      if (!shared) memcpy(out[n++].c, c, sizeof c);
    }
  return n;
}

/* Distance from x to segment ab. */
static double segment_distance(Vec3 a, Vec3 b, Vec3 x) {
  Vec3 d = v3_sub(b, a);
  double l2 = v3_dot(d, d), t = l2 > 0 ? v3_dot(v3_sub(x, a), d) / l2 : 0;
  t = t < 0 ? 0 : t > 1 ? 1 : t;
  return v3_len(v3_sub(v3_add(a, v3_mul(d, t)), x));
}

/* Distance from x to the cubic with control points c (to a 2000-segment
** polyline of it: off by about 1e-7 of its curvature). */
static double curve_distance(const Vec3 c[4], Vec3 x) {
  double best = INFINITY;
  ScenePatch p = {0};
  for (int i = 0; i < 4; i++) p.cp[i] = p.cp[4 + i] = p.cp[8 + i] = p.cp[12 + i] = c[i];
  Vec3 prev = c[0];
  for (int s = 1; s <= 2000; s++) {
    Vec3 next = patch_eval(&p, s / 2000.0, 0, NULL, NULL);
    double d = segment_distance(prev, next, x);
    if (d < best) best = d;
    prev = next;
  }
  return best;
}

/* How many boundary edges of m have an end off every open border of g: a
** crack or a T-junction shows up as such an edge. */
static int stray_boundary_edges(const Mesh *m, const SceneGeometry *g) {
  Border *open = malloc((size_t)(4 * g->npatches) * sizeof *open);
  int nopen = open_borders(g, open), stray = 0;
  char *checked = calloc((size_t)m->nverts, 1);   /* 1 on a border, 2 off */
  for (int e = 0; e < m->nedges; e++) {
    if (m->edges[e].f[1] >= 0) continue;
    for (int s = 0; s < 2; s++) {
      int v = m->edges[e].v[s];
      if (!checked[v]) {
        checked[v] = 2;
        for (int b = 0; b < nopen && checked[v] == 2; b++)
          if (curve_distance(open[b].c, m->pos[v]) < 1e-5) checked[v] = 1;
      }
      if (checked[v] == 2) { stray++; break; }
    }
  }
  free(checked);
  free(open);
  return stray;
}

/* A perspective camera at eye looking at target, z up, fov 30 degrees:
** object -> clip (OpenGL-style, w = distance in front of the eye). */
static Mat4 camera(Vec3 eye, Vec3 target, double aspect) {
  Vec3 f = v3_norm(v3_sub(target, eye)), r = v3_norm(v3_cross(f, v3(0, 0, 1))), u = v3_cross(r, f);
  Mat4 view = {{{r.x, r.y, r.z, -v3_dot(r, eye)},
                {u.x, u.y, u.z, -v3_dot(u, eye)},
                {-f.x, -f.y, -f.z, v3_dot(f, eye)},
                {0, 0, 0, 1}}};
  double t = 1 / tan(15 * M_PI / 180), n = 0.1, fa = 100;
  Mat4 proj = {{{t / aspect, 0, 0, 0},
                {0, t, 0, 0},
                {0, 0, -(fa + n) / (fa - n), -2 * fa * n / (fa - n)},
                {0, 0, -1, 0}}};
  return m4_mul(proj, view);
}

/* ---- uniform ------------------------------------------------------------ */

static Vec3 net_flat(double s, double t) { return v3(2 * s, t, 0); }

TEST(uniform_grid_counts) {
  ScenePatch p = patch_from(net_flat);
  SceneGeometry g;
  memset(&g, 0, sizeof g);
  g.kind = GEOM_PATCHES; g.npatches = 1; g.patches = &p;
  Mesh *m = tess_uniform(&g, 4);
  CHECK_EQ_INT(m->nverts, 25);
  CHECK_EQ_INT(m->ntris, 32);
  CHECK_EQ_INT(m->nedges, 2 * 4 * 5 + 16);
  int boundary = 0;
  for (int e = 0; e < m->nedges; e++) boundary += m->edges[e].f[1] < 0;
  CHECK_EQ_INT(boundary, 16);
  CHECK(m->uv != NULL);
  for (int i = 0; i < m->nverts; i++) {
    /* uv are the patch parameters of the position */
    Vec3 x = patch_eval(&p, m->uv[i].x, m->uv[i].y, NULL, NULL);
    CHECK(v3_len(v3_sub(x, m->pos[i])) < 1e-12);
    CHECK_NEAR(m->nrm[i].z, 1, 1e-15);
    double gu = m->uv[i].x * 4, gv = m->uv[i].y * 4;
    CHECK_NEAR(gu, floor(gu + 0.5), 1e-12);
    CHECK_NEAR(gv, floor(gv + 0.5), 1e-12);
  }
  for (int t = 0; t < m->ntris; t++) {
    CHECK(tri_normal(m, t).z > 0);   /* counter-clockwise seen from +z */
    CHECK_EQ_INT(m->tri_face[t], 0);
  }
  mesh_destroy(m);
  /* n = 1 is two triangles; n is clamped to [1, TESS_MAX_SEGMENTS] */
  m = tess_uniform(&g, 0);
  CHECK_EQ_INT(m->ntris, 2);
  mesh_destroy(m);
}

TEST(uniform_welds_shared_border) {
  ScenePatch store[2];
  SceneGeometry g = two_patches(store);
  Mesh *m = tess_uniform(&g, 5);
  CHECK_EQ_INT(m->nverts, 2 * 36 - 6);
  CHECK_EQ_INT(m->ntris, 100);
  int across = 0;
  for (int e = 0; e < m->nedges; e++)
    if (m->edges[e].f[1] >= 0 && m->tri_face[m->edges[e].f[0]] != m->tri_face[m->edges[e].f[1]]) across++;
  CHECK_EQ_INT(across, 5);
  CHECK(oriented(m));
  CHECK(normals_ok(m));
  CHECK_EQ_INT(stray_boundary_edges(m, &g), 0);
  for (int t = 0; t < m->ntris; t++) CHECK(v3_dot(tri_normal(m, t), m->nrm[m->tri[t][0]]) > 0);
  mesh_destroy(m);
}

TEST(uniform_teapot) {
  SceneGeometry g;
  if (!teapot_load(&g)) { CHECK(!"cannot read " TEAPOT_NPR); return; }
  Mesh *m = tess_uniform(&g, 8);
  /* 8 patches lose the 8 triangles on their collapsed row */
  CHECK_EQ_INT(m->ntris, 32 * 128 - 8 * 8);
  CHECK(normals_ok(m));
  CHECK(oriented(m));
  CHECK_EQ_INT(count_nonmanifold(m), 0);
  CHECK_EQ_INT(stray_boundary_edges(m, &g), 0);
  /* triangles agree with the smooth normals (counter-clockwise outside) */
  int against = 0;
  for (int t = 0; t < m->ntris; t++) {
    Vec3 n = tri_normal(m, t);
    double s = 0;
    for (int k = 0; k < 3; k++) s += v3_dot(n, m->nrm[m->tri[t][k]]);
    if (s <= 0) against++;
  }
  CHECK_EQ_INT(against, 0);
  /* the joins are smooth except where the handle touches the body at one
  ** point, (-2, 0, 0.9): only corners there keep their own normals */
  CHECK(m->corner_nrm != NULL);
  int differ = 0;
  for (int t = 0; m->corner_nrm && t < m->ntris; t++)
    for (int k = 0; k < 3; k++) {
      if (v3_dot(m->corner_nrm[t][k], m->nrm[m->tri[t][k]]) > 1 - 1e-9) continue;
      differ++;
      CHECK(v3_len(v3_sub(m->pos[m->tri[t][k]], v3(-2, 0, 0.9))) < 1e-12);
      CHECK(m->tri_face[t] == 14 || m->tri_face[t] == 15);
    }
  CHECK(differ > 0);
  mesh_destroy(m);
  free(g.patches);
}

/* A cylinder as patches, as stdlib/shapes.npr builds it: quarter arcs
** around z times a profile (bottom cap centre out, side, top cap rim in). */
static SceneGeometry cylinder_patches(ScenePatch *store) {
  static const double k = 0.5522847498;
  double arcs[4][4][2] = {{{1, 0}, {1, k}, {k, 1}, {0, 1}}, {{0, 1}, {-k, 1}, {-1, k}, {-1, 0}},
                          {{-1, 0}, {-1, -k}, {-k, -1}, {0, -1}}, {{0, -1}, {k, -1}, {1, -k}, {1, 0}}};
  double prof[3][4][2] = {{{0, 0}, {1 / 3.0, 0}, {2 / 3.0, 0}, {1, 0}},
                          {{1, 0}, {1, 1 / 3.0}, {1, 2 / 3.0}, {1, 1}},
                          {{1, 1}, {2 / 3.0, 1}, {1 / 3.0, 1}, {0, 1}}};
  int n = 0;
  for (int s = 0; s < 3; s++)
    for (int q = 0; q < 4; q++, n++)
      for (int j = 0; j < 4; j++)
        for (int i = 0; i < 4; i++)
          store[n].cp[4 * j + i] = v3(prof[s][j][0] * arcs[q][i][0], prof[s][j][0] * arcs[q][i][1], prof[s][j][1]);
  SceneGeometry g;
  memset(&g, 0, sizeof g);
  g.kind = GEOM_PATCHES; g.npatches = 12; g.patches = store;
  return g;
}

TEST(cylinder_closed_with_creases) {
  ScenePatch store[12] = {{0}};
  SceneGeometry g = cylinder_patches(store);
  Mesh *m = tess_uniform(&g, 6);
  /* closed: a sphere's topology, every edge two faces, oriented outward */
  CHECK_EQ_INT(m->nverts - m->nedges + m->ntris, 2);
  for (int e = 0; e < m->nedges; e++) CHECK(m->edges[e].f[1] >= 0 && !m->edges[e].nonmanifold);
  CHECK(oriented(m));
  for (int t = 0; t < m->ntris; t++) {
    Vec3 c = v3_add(v3_add(m->pos[m->tri[t][0]], m->pos[m->tri[t][1]]), m->pos[m->tri[t][2]]);
    c = v3_sub(v3_mul(c, 1 / 3.0), v3(0, 0, 0.5));
    CHECK(v3_dot(tri_normal(m, t), c) > 0);
  }
  /* the rims are creases: cap corners face up or down, side corners out */
  CHECK(m->corner_nrm != NULL);
  for (int t = 0; m->corner_nrm && t < m->ntris; t++)
    for (int k = 0; k < 3; k++) {
      Vec3 n = m->corner_nrm[t][k];
      if (m->tri_face[t] < 4) CHECK_NEAR(n.z, -1, 1e-12);
      else if (m->tri_face[t] >= 8) CHECK_NEAR(n.z, 1, 1e-12);
      else CHECK_NEAR(n.z, 0, 1e-12);
    }
  mesh_destroy(m);
}

/* ---- adaptive ----------------------------------------------------------- */

/* The body: rim, upper and lower body and bottom, a disc (closed except
** the rim's inner edge at z = 2.4): V - E + F = 1, every boundary edge on
** that circle. */
static void check_body(const SceneGeometry *tea, const Mat4 *clip, double tol) {
  SceneGeometry body;
  memset(&body, 0, sizeof body);
  teapot_take(&body, tea, 0, 11);
  teapot_take(&body, tea, 28, 31);
  Mesh *m = tess_adaptive(&body, clip, 640, 480, tol);
  CHECK_EQ_INT(m->nverts - m->nedges + m->ntris, 1);
  int boundary = 0, off = 0;
  for (int e = 0; e < m->nedges; e++) {
    if (m->edges[e].f[1] >= 0) continue;
    boundary++;
    for (int s = 0; s < 2; s++) {
      Vec3 x = m->pos[m->edges[e].v[s]];
      if (fabs(x.z - 2.4) > 1e-12 || hypot(x.x, x.y) > 1.41) off++;
    }
  }
  CHECK(boundary >= 4);
  CHECK_EQ_INT(off, 0);
  CHECK(oriented(m));
  CHECK_EQ_INT(count_nonmanifold(m), 0);
  mesh_destroy(m);
  free(body.patches);
}

/* Background pixels enclosed by the mesh's picture: m seen along dir
** (orthographic, n x n pixels over its bounds), every triangle but skip
** filled at the pixel centres it covers (edges inclusive, within 1e-12, so
** only a real gap leaves a pixel uncovered), then the background flooded
** from the image border; what the flood does not reach but no triangle
** covers shows through a crack. */
static int enclosed_background(const Mesh *m, Vec3 dir, int n, int skip) {
  Vec3 e1 = v3_norm(v3_cross(dir, fabs(dir.z) < 0.9 ? v3(0, 0, 1) : v3(1, 0, 0))), e2 = v3_cross(v3_norm(dir), e1);
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  Vec2 *q = malloc((size_t)m->nverts * sizeof *q);
  for (int i = 0; i < m->nverts; i++) {
    q[i].x = v3_dot(m->pos[i], e1);
    q[i].y = v3_dot(m->pos[i], e2);
    lo[0] = fmin(lo[0], q[i].x); hi[0] = fmax(hi[0], q[i].x);
    lo[1] = fmin(lo[1], q[i].y); hi[1] = fmax(hi[1], q[i].y);
  }
  double scale = (n - 4) / fmax(hi[0] - lo[0], hi[1] - lo[1]);
  for (int i = 0; i < m->nverts; i++) {
    q[i].x = (q[i].x - lo[0]) * scale + 2;
    q[i].y = (q[i].y - lo[1]) * scale + 2;
  }
  unsigned char *px = calloc((size_t)n * n, 1);   /* 1 covered, 2 background reached */
  for (int t = 0; t < m->ntris; t++) {
    if (t == skip) continue;
    Vec2 a = q[m->tri[t][0]], b = q[m->tri[t][1]], c = q[m->tri[t][2]];
    double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (area == 0) continue;
    double sgn = area > 0 ? 1 : -1;
    int x0 = (int)floor(fmin(a.x, fmin(b.x, c.x))), x1 = (int)ceil(fmax(a.x, fmax(b.x, c.x)));
    int y0 = (int)floor(fmin(a.y, fmin(b.y, c.y))), y1 = (int)ceil(fmax(a.y, fmax(b.y, c.y)));
    for (int y = y0; y <= y1 && y < n; y++)
      for (int x = x0; x <= x1 && x < n; x++) {
        double cx = x + 0.5, cy = y + 0.5;
        double w0 = sgn * ((b.x - a.x) * (cy - a.y) - (b.y - a.y) * (cx - a.x));
        double w1 = sgn * ((c.x - b.x) * (cy - b.y) - (c.y - b.y) * (cx - b.x));
        double w2 = sgn * ((a.x - c.x) * (cy - c.y) - (a.y - c.y) * (cx - c.x));
        if (x >= 0 && y >= 0 && w0 >= -1e-12 && w1 >= -1e-12 && w2 >= -1e-12) px[y * n + x] = 1;
      }
  }
  int *stack = malloc((size_t)n * n * sizeof *stack), top = 0;
  for (int i = 0; i < n; i++) {
    int border[4] = {i, (n - 1) * n + i, i * n, i * n + n - 1};
    for (int k = 0; k < 4; k++)
      if (!px[border[k]]) { px[border[k]] = 2; stack[top++] = border[k]; }
  }
  while (top > 0) {
    int p = stack[--top], x = p % n, y = p / n;
    int next[4] = {x > 0 ? p - 1 : -1, x + 1 < n ? p + 1 : -1, y > 0 ? p - n : -1, y + 1 < n ? p + n : -1};
    for (int k = 0; k < 4; k++)
      if (next[k] >= 0 && !px[next[k]]) { px[next[k]] = 2; stack[top++] = next[k]; }
  }
  int holes = 0;
  for (int i = 0; i < n * n; i++) holes += px[i] == 0;
  free(stack);
  free(px);
  free(q);
  return holes;
}

TEST(no_background_through_body) {
  /* the body (rim, body, bottom) is closed but for the rim's opening:
  ** seen from any side, nothing behind it shows through */
  SceneGeometry g, body;
  if (!teapot_load(&g)) { CHECK(!"cannot read " TEAPOT_NPR); return; }
  memset(&body, 0, sizeof body);
  teapot_take(&body, &g, 0, 11);
  teapot_take(&body, &g, 28, 31);
  Mat4 clip = camera(v3(8, -12, 6), v3(0, 0, 1.5), 640.0 / 480.0);
  Vec3 dirs[] = {{0, 0, 1}, {1, 0.3, 0.1}, {-0.4, 1, -0.6}, {0.3, -0.2, -1}};
  double tols[] = {16, 4, 1, 0.25};
  for (int i = 0; i < 4; i++) {
    Mesh *m = tess_adaptive(&body, &clip, 640, 480, tols[i]);
    for (int d = 0; d < 4; d++) CHECK_EQ_INT(enclosed_background(m, dirs[d], 300, -1), 0);
    if (i == 0) {
      /* the check sees a real hole: take out the triangle nearest the
      ** bottom's centre and look up through it and the opening */
      int near = 0;
      double best = INFINITY;
      for (int t = 0; t < m->ntris; t++) {
        Vec3 c = v3_add(v3_add(m->pos[m->tri[t][0]], m->pos[m->tri[t][1]]), m->pos[m->tri[t][2]]);
        if (v3_len(c) < best) { best = v3_len(c); near = t; }
      }
      CHECK(enclosed_background(m, v3(0, 0, 1), 300, near) > 0);
    }
    mesh_destroy(m);
  }
  free(body.patches);
  free(g.patches);
}

TEST(adaptive_teapot_crack_free) {
  SceneGeometry g;
  if (!teapot_load(&g)) { CHECK(!"cannot read " TEAPOT_NPR); return; }
  Mat4 clip = camera(v3(8, -12, 6), v3(0, 0, 1.5), 640.0 / 480.0);
  double tols[] = {8, 2, 0.5, 0.1};
  int last = 0;
  for (int i = 0; i < 4; i++) {
    Mesh *m = tess_adaptive(&g, &clip, 640, 480, tols[i]);
    CHECK(m->ntris > last);   /* finer tolerance, more triangles */
    last = m->ntris;
    CHECK(normals_ok(m));
    CHECK(oriented(m));
    CHECK_EQ_INT(count_nonmanifold(m), 0);
    CHECK_EQ_INT(stray_boundary_edges(m, &g), 0);
    /* patches are cut differently, yet meet edge to edge */
    int per[32] = {0}, across = 0;
    for (int t = 0; t < m->ntris; t++) per[m->tri_face[t]]++;
    int lo = per[0], hi = per[0];
    for (int p = 1; p < 32; p++) { lo = per[p] < lo ? per[p] : lo; hi = per[p] > hi ? per[p] : hi; }
    CHECK(hi > 2 * lo);
    for (int e = 0; e < m->nedges; e++)
      if (m->edges[e].f[1] >= 0 && m->tri_face[m->edges[e].f[0]] != m->tri_face[m->edges[e].f[1]]) across++;
    CHECK(across > 0);
    mesh_destroy(m);
    check_body(&g, &clip, tols[i]);
  }
  /* a camera inside the pot: borders with a point behind the eye get a
  ** fixed count, and the surface still closes up */
  Mat4 inside = camera(v3(0.2, 0.1, 1.5), v3(3, 0, 1.5), 1);
  Mesh *mi = tess_adaptive(&g, &inside, 300, 300, 0.5);
  CHECK(normals_ok(mi));
  CHECK(oriented(mi));
  CHECK_EQ_INT(stray_boundary_edges(mi, &g), 0);
  CHECK(mi->ntris <= 32 * 2 * TESS_MAX_SEGMENTS * TESS_MAX_SEGMENTS);
  mesh_destroy(mi);
  /* looking away: nothing in view, every patch a single cell (2
  ** triangles, 1 where a border collapses) */
  Mat4 away = camera(v3(0, -10, 1.5), v3(0, -20, 1.5), 1);
  mi = tess_adaptive(&g, &away, 300, 300, 0.5);
  CHECK_EQ_INT(mi->ntris, 32 * 2 - 8);
  CHECK_EQ_INT(stray_boundary_edges(mi, &g), 0);
  mesh_destroy(mi);
  /* object-space tolerance (no projection) works the same way */
  Mesh *m = tess_adaptive(&g, NULL, 0, 0, 0.01);
  CHECK_EQ_INT(stray_boundary_edges(m, &g), 0);
  CHECK(oriented(m));
  mesh_destroy(m);
  free(g.patches);
}

/* Whether row v = 0 of p collapses to a point (the teapot's lid and bottom). */
static int first_row_collapsed(const ScenePatch *p) {
  for (int i = 1; i < 4; i++)
    if (v3_len(v3_sub(p->cp[i], p->cp[0])) > 0) return 0;
  return 1;
}

/* Largest distance between the surface and the mesh at triangle centroids
** and edge midpoints (single patch: every uv belongs to patch p). A corner
** on a collapsed row takes the u of the triangle's other corners: it is
** the same point for every u, and that is the u its triangle stands for. */
static double max_deviation(const Mesh *m, const ScenePatch *p, const Mat4 *clip, double hw, double hh) {
  double worst = 0;
  for (int t = 0; t < m->ntris; t++) {
    const int *c = m->tri[t];
    double w[4][3] = {{1 / 3.0, 1 / 3.0, 1 / 3.0}, {0.5, 0.5, 0}, {0, 0.5, 0.5}, {0.5, 0, 0.5}};
    for (int s = 0; s < 4; s++) {
      Vec3 x = v3(0, 0, 0);
      double u = 0, v = 0;
      for (int k = 0; k < 3; k++) {
        double cu = m->uv[c[k]].x;
        if (m->uv[c[k]].y == 0 && first_row_collapsed(p))
          cu = (m->uv[c[(k + 1) % 3]].x + m->uv[c[(k + 2) % 3]].x) / 2;
        x = v3_add(x, v3_mul(m->pos[c[k]], w[s][k]));
        u += w[s][k] * cu;
        v += w[s][k] * m->uv[c[k]].y;
      }
      Vec3 y = patch_eval(p, u, v, NULL, NULL);
      if (clip) {
        Vec3 a = m4_point(*clip, x), b = m4_point(*clip, y);
        double wa = clip->m[3][0] * x.x + clip->m[3][1] * x.y + clip->m[3][2] * x.z + clip->m[3][3];
        double wb = clip->m[3][0] * y.x + clip->m[3][1] * y.y + clip->m[3][2] * y.z + clip->m[3][3];
        x = v3(a.x / wa * hw, a.y / wa * hh, 0);
        y = v3(b.x / wb * hw, b.y / wb * hh, 0);
      }
      double d = v3_len(v3_sub(x, y));
      if (d > worst) worst = d;
    }
  }
  return worst;
}

TEST(adaptive_flatness) {
  SceneGeometry g;
  if (!teapot_load(&g)) { CHECK(!"cannot read " TEAPOT_NPR); return; }
  Mat4 clip = camera(v3(8, -12, 6), v3(0, 0, 1.5), 640.0 / 480.0);
  int pick[] = {0, 4, 9, 13, 16, 18, 21, 26, 30};
  for (int i = 0; i < (int)(sizeof pick / sizeof pick[0]); i++) {
    SceneGeometry one;
    memset(&one, 0, sizeof one);
    teapot_take(&one, &g, pick[i], pick[i]);
    for (double tol = 2; tol >= 0.1; tol /= 4) {
      Mesh *m = tess_adaptive(&one, &clip, 640, 480, tol);
      double d1 = max_deviation(m, &one.patches[0], &clip, 320, 240);
      CHECK(d1 <= tol);
      mesh_destroy(m);
      m = tess_adaptive(&one, NULL, 0, 0, tol / 100);
      double d2 = max_deviation(m, &one.patches[0], NULL, 1, 1);
      CHECK(d2 <= tol / 100);
      if (getenv("VERBOSE")) printf("patch %d tol %g: %g px, %g / %g units\n", pick[i], tol, d1, d2, tol / 100);
      mesh_destroy(m);
    }
    free(one.patches);
  }
  free(g.patches);
}

TEST(adaptive_two_patches) {
  ScenePatch store[2];
  SceneGeometry g = two_patches(store);
  /* patch B's far side is flat, A's curved: they get different cuts */
  for (double tol = 0.1; tol >= 1e-4; tol /= 10) {
    Mesh *m = tess_adaptive(&g, NULL, 0, 0, tol);
    CHECK(oriented(m));
    CHECK(normals_ok(m));
    CHECK_EQ_INT(stray_boundary_edges(m, &g), 0);
    mesh_destroy(m);
  }
}

/* ---- polygons ----------------------------------------------------------- */

TEST(polygons_cube) {
  /* the unit cube around the origin, quads counter-clockwise from outside */
  Vec3 v[8];
  for (int i = 0; i < 8; i++) v[i] = v3(i & 1 ? 0.5 : -0.5, i & 2 ? 0.5 : -0.5, i & 4 ? 0.5 : -0.5);
  int idx[] = {0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5};
  int start[] = {0, 4, 8, 12, 16, 20, 24};
  SceneGeometry g;
  memset(&g, 0, sizeof g);
  g.kind = GEOM_MESH; g.nverts = 8; g.verts = v; g.nfaces = 6; g.face_start = start; g.face_index = idx;
  Mesh *m = tess_polygons(&g);
  CHECK_EQ_INT(m->nverts, 8);
  CHECK_EQ_INT(m->ntris, 12);
  CHECK_EQ_INT(m->nedges, 18);   /* 12 cube edges and 6 diagonals */
  for (int e = 0; e < m->nedges; e++) CHECK(m->edges[e].f[0] >= 0 && m->edges[e].f[1] >= 0);
  CHECK_EQ_INT(m->nverts - m->nedges + m->ntris, 2);
  CHECK(oriented(m));
  CHECK(normals_ok(m));
  for (int t = 0; t < m->ntris; t++) {
    Vec3 c = v3_add(v3_add(m->pos[m->tri[t][0]], m->pos[m->tri[t][1]]), m->pos[m->tri[t][2]]);
    CHECK(v3_dot(tri_normal(m, t), c) > 0);   /* outward */
    CHECK_EQ_INT(m->tri_face[t], t / 2);
  }
  for (int i = 0; i < 8; i++) CHECK(v3_dot(m->nrm[i], m->pos[i]) > 0);
  /* faces meet at 90 degrees: every corner shades with its face's normal */
  CHECK(m->corner_nrm != NULL);
  for (int t = 0; m->corner_nrm && t < m->ntris; t++)
    for (int k = 0; k < 3; k++) CHECK_NEAR(v3_dot(m->corner_nrm[t][k], v3_norm(tri_normal(m, t))), 1, 1e-12);
  mesh_destroy(m);
}

TEST(polygons_concave_and_bad) {
  /* an L: 3 unit squares; the notch (1.5, 1.5) must stay empty. Then a face
  ** with an index out of range and a repeated one (a triangle is left), and
  ** one with only two usable corners (skipped). */
  Vec3 v[] = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
  int idx[] = {0, 1, 2, 3, 4, 5, 0, 1, 1, 99, 2, 3, 3, -1, 4};
  int start[] = {0, 6, 12, 15};
  SceneGeometry g;
  memset(&g, 0, sizeof g);
  g.kind = GEOM_MESH; g.nverts = 6; g.verts = v; g.nfaces = 3; g.face_start = start; g.face_index = idx;
  Mesh *m = tess_polygons(&g);
  CHECK_EQ_INT(m->ntris, 4 + 2);
  double area = 0;
  for (int t = 0; t < m->ntris; t++) {
    Vec3 n = tri_normal(m, t);
    CHECK(n.z > 0);
    if (m->tri_face[t] != 0) continue;
    area += n.z / 2;
    Vec3 c = v3_mul(v3_add(v3_add(m->pos[m->tri[t][0]], m->pos[m->tri[t][1]]), m->pos[m->tri[t][2]]), 1 / 3.0);
    CHECK(!(c.x > 1 && c.y > 1));
  }
  CHECK_NEAR(area, 3, 1e-12);
  CHECK(normals_ok(m));
  mesh_destroy(m);
}

TEST(geometry_dispatch) {
  ScenePatch store[2];
  SceneGeometry g = two_patches(store);
  Mesh *a = tess_geometry(&g, TESS_UNIFORM, 3, 0, NULL, 0, 0);
  CHECK_EQ_INT(a->ntris, 36);
  mesh_destroy(a);
  a = tess_geometry(&g, TESS_ADAPTIVE, 3, 0.05, NULL, 0, 0);
  CHECK(a->ntris > 2);
  mesh_destroy(a);
}

/* The largest distance, in pixels of a width x height frame, between the
** unit sphere and the mesh a sphere object without `tessellate` gets when
** it fills the frame's height (camera 4 units away, fov 30): its edge
** midpoints and triangle centroids, where a flat cell strays furthest
** from the surface, and the triangle count. */
static double default_sphere_error(int width, int height, int *ntris) {
  Scene s;
  Arena ast;
  double err = -1;
  *ntris = 0;
  if (!scene_from_text(&s, &ast, "include \"shapes.npr\";\n"
                                 "camera { position [0, -4, 0]; look_at [0, 0, 0]; fov 30; }\n"
                                 "object { geometry sphere(1); }\n"))
    return err;
  RenderOptions o = {.width = width, .height = height, .threads = 1};
  RenderFrame f;
  if (render_prepare(&s, &o, &f)) {
    const Mesh *m = f.objects[0].mesh;
    /* a world unit on the silhouette, sqrt(4^2 - 1) away, in pixels */
    double px = height / 2.0 / tan(15 * M_PI / 180) / sqrt(15);
    err = 0;
    for (int t = 0; t < m->ntris; t++) {
      Vec3 a = m->pos[m->tri[t][0]], b = m->pos[m->tri[t][1]], c = m->pos[m->tri[t][2]];
      Vec3 probe[4] = {v3_mul(v3_add(a, b), 0.5), v3_mul(v3_add(b, c), 0.5), v3_mul(v3_add(c, a), 0.5),
                       v3_mul(v3_add(v3_add(a, b), c), 1.0 / 3)};
      for (int k = 0; k < 4; k++) err = fmax(err, (1 - v3_len(probe[k])) * px);
    }
    *ntris = m->ntris;
  }
  render_frame_free(&f);
  scene_free(&s);
  arena_free(&ast);
  return err;
}

/* Without `tessellate`, a sphere filling the frame is cut to its size on
** screen: within half a pixel of the true surface (it was 8 segments a
** patch, ~2 px at 640 x 480), and more finely in a larger frame. */
TEST(default_follows_the_screen) {
  int small, large;
  double e_small = default_sphere_error(640, 480, &small);
  double e_large = default_sphere_error(1280, 960, &large);
  CHECK(e_small >= 0 && e_small < 0.5);
  CHECK(e_large >= 0 && e_large < 0.5);
  CHECK(large > small);
}

int main(void) {
  RUN(uniform_grid_counts);
  RUN(uniform_welds_shared_border);
  RUN(uniform_teapot);
  RUN(cylinder_closed_with_creases);
  RUN(adaptive_teapot_crack_free);
  RUN(no_background_through_body);
  RUN(adaptive_flatness);
  RUN(adaptive_two_patches);
  RUN(polygons_cube);
  RUN(polygons_concave_and_bad);
  RUN(geometry_dispatch);
  RUN(default_follows_the_screen);
  return unit_done();
}
