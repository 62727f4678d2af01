/*
** The primitive shapes as geometry values (see shapes.h).
*/
#include "shapes.h"

#include <string.h>

/* The four quarter arcs of the unit circle, counter-clockwise from +x,
** each as 4 control points. Written out (not rotated with sin and cos) so
** neighbouring arcs share their end points exactly. */
static const double K = SHAPE_ARC_K;
static const Vec2 ARCS[4][4] = {
  {{1, 0}, {1, SHAPE_ARC_K}, {SHAPE_ARC_K, 1}, {0, 1}},
  {{0, 1}, {-SHAPE_ARC_K, 1}, {-1, SHAPE_ARC_K}, {-1, 0}},
  {{-1, 0}, {-1, -SHAPE_ARC_K}, {-SHAPE_ARC_K, -1}, {0, -1}},
  {{0, -1}, {SHAPE_ARC_K, -1}, {1, -SHAPE_ARC_K}, {1, 0}},
};

static SceneGeometry *geom_new(Arena *a, GeomKind kind) {
  SceneGeometry *g = arena_alloc(a, sizeof *g);
  g->kind = kind;
  return g;
}

SceneGeometry *shape_revolve(Arena *a, const ShapeProfile *profiles, int n) {
  SceneGeometry *g = geom_new(a, GEOM_PATCHES);
  g->npatches = 4 * n;
  g->patches = arena_alloc(a, (size_t)(4 * n > 0 ? 4 * n : 1) * sizeof *g->patches);
  for (int s = 0; s < n; s++)
    for (int q = 0; q < 4; q++) {
      ScenePatch *p = &g->patches[4 * s + q];
      for (int j = 0; j < 4; j++)        /* rows along v: the profile */
        for (int i = 0; i < 4; i++) {    /* columns along u: the arc */
          Vec2 r = profiles[s].p[j], c = ARCS[q][i];
          p->cp[4 * j + i] = v3(r.x * c.x, r.x * c.y, r.y);
        }
    }
  return g;
}

static ShapeProfile profile(double r0, double z0, double r1, double z1, double r2, double z2, double r3, double z3) {
  ShapeProfile p = {{{r0, z0}, {r1, z1}, {r2, z2}, {r3, z3}}};
  return p;
}

SceneGeometry *shape_sphere(Arena *a, double r) {
  double k = K * r;
  ShapeProfile pr[2] = {
    profile(0, -r, k, -r, r, -k, r, 0),   /* south pole up to the equator */
    profile(r, 0, r, k, k, r, 0, r),      /* equator up to the north pole */
  };
  return shape_revolve(a, pr, 2);
}

SceneGeometry *shape_cylinder(Arena *a, double h, double r1, double r2, int center) {
  double z0 = center ? -h / 2 : 0, z1 = z0 + h;
  ShapeProfile pr[3];
  int n = 0;
  if (r1 > 0) pr[n++] = profile(0, z0, r1 / 3, z0, 2 * r1 / 3, z0, r1, z0);        /* bottom cap, centre out */
  pr[n++] = profile(r1, z0, r1 + (r2 - r1) / 3, z0 + h / 3, r1 + 2 * (r2 - r1) / 3, z0 + 2 * h / 3, r2, z1);
  if (r2 > 0) pr[n++] = profile(r2, z1, 2 * r2 / 3, z1, r2 / 3, z1, 0, z1);        /* top cap, rim in */
  return shape_revolve(a, pr, n);
}

SceneGeometry *shape_torus(Arena *a, double R, double r) {
  double k = K * r;
  ShapeProfile pr[4] = {
    profile(R + r, 0, R + r, k, R + k, r, R, r),
    profile(R, r, R - k, r, R - r, k, R - r, 0),
    profile(R - r, 0, R - r, -k, R - k, -r, R, -r),
    profile(R, -r, R + k, -r, R + r, -k, R + r, 0),
  };
  return shape_revolve(a, pr, 4);
}

SceneGeometry *shape_cube(Arena *a, Vec3 s, int center) {
  static const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  SceneGeometry *g = geom_new(a, GEOM_MESH);
  Vec3 o = center ? v3(-s.x / 2, -s.y / 2, -s.z / 2) : v3(0, 0, 0);
  g->nverts = 8;
  g->verts = arena_alloc(a, 8 * sizeof *g->verts);
  for (int i = 0; i < 8; i++)
    g->verts[i] = v3(o.x + (i % 2) * s.x, o.y + (i / 2 % 2) * s.y, o.z + (i / 4) * s.z);
  g->nfaces = 6;
  g->face_start = arena_alloc(a, 7 * sizeof *g->face_start);
  g->face_index = arena_alloc(a, 24 * sizeof *g->face_index);
  for (int f = 0; f < 6; f++) {
    g->face_start[f] = 4 * f;
    memcpy(&g->face_index[4 * f], quads[f], sizeof quads[f]);
  }
  g->face_start[6] = 24;
  /* each face carries the whole unit square as its (u, v), upright seen
  ** from outside (v up the sides; the top with x right and y up, the
  ** bottom with x right and y down) */
  static const double uv[6][4][2] = {
    {{0, 1}, {0, 0}, {1, 0}, {1, 1}},   /* bottom, z = 0 */
    {{0, 0}, {1, 0}, {1, 1}, {0, 1}},   /* top */
    {{0, 0}, {1, 0}, {1, 1}, {0, 1}},   /* y = 0 */
    {{1, 0}, {1, 1}, {0, 1}, {0, 0}},   /* y = size */
    {{1, 0}, {1, 1}, {0, 1}, {0, 0}},   /* x = 0 */
    {{0, 0}, {1, 0}, {1, 1}, {0, 1}},   /* x = size */
  };
  g->face_uv = arena_alloc(a, 24 * sizeof *g->face_uv);
  for (int f = 0; f < 6; f++)
    for (int k = 0; k < 4; k++) g->face_uv[4 * f + k] = (Vec2){uv[f][k][0], uv[f][k][1]};
  return g;
}

SceneGeometry *shape_plane(Arena *a, double size) {
  SceneGeometry *g = geom_new(a, GEOM_PATCHES);
  double h = size / 2;
  g->npatches = 1;
  g->patches = arena_alloc(a, sizeof *g->patches);
  g->patches[0].bilinear = 1;
  g->patches[0].cp[0] = v3(-h, -h, 0);
  g->patches[0].cp[1] = v3(h, -h, 0);
  g->patches[0].cp[2] = v3(-h, h, 0);
  g->patches[0].cp[3] = v3(h, h, 0);
  return g;
}

/* ---- moving geometry ---------------------------------------------------- */

static void *copy(Arena *a, const void *src, size_t n) {
  if (!src) return NULL;
  void *d = arena_alloc(a, n ? n : 1);
  memcpy(d, src, n);
  return d;
}

/* The 3x3 determinant of m's linear part (< 0: m mirrors). */
static double det3(Mat4 m) {
  return m.m[0][0] * (m.m[1][1] * m.m[2][2] - m.m[1][2] * m.m[2][1]) -
         m.m[0][1] * (m.m[1][0] * m.m[2][2] - m.m[1][2] * m.m[2][0]) +
         m.m[0][2] * (m.m[1][0] * m.m[2][1] - m.m[1][1] * m.m[2][0]);
}

/* Reverse each face's corners (and what runs parallel to them), so a
** mirrored mesh still faces outward. */
static void reverse_faces(SceneGeometry *g) {
  for (int f = 0; f < g->nfaces; f++)
    for (int i = g->face_start[f], j = g->face_start[f + 1] - 1; i < j; i++, j--) {
      int t = g->face_index[i]; g->face_index[i] = g->face_index[j]; g->face_index[j] = t;
      if (g->face_uv) { Vec2 u = g->face_uv[i]; g->face_uv[i] = g->face_uv[j]; g->face_uv[j] = u; }
      if (g->face_nrm) { Vec3 n = g->face_nrm[i]; g->face_nrm[i] = g->face_nrm[j]; g->face_nrm[j] = n; }
    }
}

/* A mirrored patch runs u backwards, so dP/du x dP/dv turns outward again. */
static void reverse_patch(ScenePatch *p) {
  int rows = p->bilinear ? 2 : 4, cols = rows;
  for (int j = 0; j < rows; j++)
    for (int i = 0; i < cols / 2; i++) {
      Vec3 t = p->cp[cols * j + i];
      p->cp[cols * j + i] = p->cp[cols * j + cols - 1 - i];
      p->cp[cols * j + cols - 1 - i] = t;
    }
}

static void reverse_contours(SceneGeometry *g) {
  for (int c = 0; c < g->ncontours; c++)
    for (int i = g->contour_start[c], j = g->contour_start[c + 1] - 1; i < j; i++, j--) {
      Vec2 t = g->contour_pts[i]; g->contour_pts[i] = g->contour_pts[j]; g->contour_pts[j] = t;
    }
}

SceneGeometry *shape_transformed(Arena *a, const SceneGeometry *src, Mat4 m) {
  SceneGeometry *g = arena_alloc(a, sizeof *g);
  *g = *src;
  int mirror = det3(m) < 0;
  g->patches = copy(a, src->patches, (size_t)src->npatches * sizeof *src->patches);
  for (int i = 0; i < g->npatches; i++) {
    for (int k = 0; k < (g->patches[i].bilinear ? 4 : 16); k++) g->patches[i].cp[k] = m4_point(m, g->patches[i].cp[k]);
    if (mirror) reverse_patch(&g->patches[i]);
  }
  g->verts = copy(a, src->verts, (size_t)src->nverts * sizeof *src->verts);
  for (int i = 0; i < g->nverts; i++) g->verts[i] = m4_point(m, g->verts[i]);
  int ncorners = src->nfaces ? src->face_start[src->nfaces] : 0;
  g->face_index = copy(a, src->face_index, (size_t)ncorners * sizeof *src->face_index);
  g->face_uv = copy(a, src->face_uv, (size_t)ncorners * sizeof *src->face_uv);
  g->face_nrm = copy(a, src->face_nrm, (size_t)ncorners * sizeof *src->face_nrm);
  if (g->face_nrm) {   /* normals move by the inverse transpose */
    int ok;
    Mat4 nm = m4_transpose(m4_inverse(m, &ok));
    for (int i = 0; i < ncorners; i++) g->face_nrm[i] = v3_norm(m4_dir(nm, g->face_nrm[i]));
  }
  if (mirror) reverse_faces(g);
  int npts = src->ncontours ? src->contour_start[src->ncontours] : 0;
  g->contour_pts = copy(a, src->contour_pts, (size_t)npts * sizeof *src->contour_pts);
  for (int i = 0; i < npts; i++) {
    Vec3 p = m4_point(m, v3(g->contour_pts[i].x, g->contour_pts[i].y, 0));
    g->contour_pts[i].x = p.x;
    g->contour_pts[i].y = p.y;
  }
  /* a 2D shape stays one while m keeps the xy-plane level (a lift along z
  ** is dropped, as OpenSCAD does); tilted, it is a flat 3D mesh */
  if (m.m[2][0] != 0 || m.m[2][1] != 0) g->ncontours = 0;
  else if (m.m[0][0] * m.m[1][1] - m.m[0][1] * m.m[1][0] < 0) reverse_contours(g);
  return g;
}

SceneGeometry *shape_empty(Arena *a) {
  SceneGeometry *g = arena_alloc(a, sizeof *g);
  g->kind = GEOM_MESH;
  g->face_start = arena_alloc(a, sizeof *g->face_start);
  return g;
}
