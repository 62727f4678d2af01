/*
** Solids from 2D shapes (see extrude.h).
*/
#include "extrude.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "shape2d.h"
#include "shapes.h"

/* ---- a mesh under construction ------------------------------------------ */

/* A mesh of nverts vertices with room for nfaces faces of ncorners
** corners in all. */
static SceneGeometry *mesh_new(Arena *a, int nverts, int nfaces, int ncorners) {
  SceneGeometry *g = arena_alloc(a, sizeof *g);
  g->kind = GEOM_MESH;
  g->nverts = nverts;
  g->verts = arena_alloc(a, (size_t)(nverts ? nverts : 1) * sizeof *g->verts);
  g->face_start = arena_alloc(a, (size_t)(nfaces + 1) * sizeof *g->face_start);
  g->face_index = arena_alloc(a, (size_t)(ncorners ? ncorners : 1) * sizeof *g->face_index);
  return g;
}

static void face3(SceneGeometry *g, int a, int b, int c) {
  int *f = g->face_index + g->face_start[g->nfaces];
  f[0] = a, f[1] = b, f[2] = c;
  g->nfaces++;
  g->face_start[g->nfaces] = g->face_start[g->nfaces - 1] + 3;
}

static void face4(SceneGeometry *g, int a, int b, int c, int d) {
  int *f = g->face_index + g->face_start[g->nfaces];
  f[0] = a, f[1] = b, f[2] = c, f[3] = d;
  g->nfaces++;
  g->face_start[g->nfaces] = g->face_start[g->nfaces - 1] + 4;
}

/* ---- the shape's points -------------------------------------------------- */

typedef struct Keyed { double x, y; int i; } Keyed;

static int by_position(const void *pa, const void *pb) {
  const Keyed *a = pa, *b = pb;
  if (a->x != b->x) return a->x < b->x ? -1 : 1;
  if (a->y != b->y) return a->y < b->y ? -1 : 1;
  return a->i - b->i;
}

/* same[i]: the next of pts[0 .. n-1] at pts[i]'s position, round in a
** ring (same[i] == i for a point no other shares: contours touch there). */
static void same_points(const Vec2 *pts, int n, int *same) {
  Keyed *k = xmalloc((size_t)(n ? n : 1) * sizeof *k);
  for (int i = 0; i < n; i++) k[i] = (Keyed){pts[i].x, pts[i].y, i};
  qsort(k, (size_t)n, sizeof *k, by_position);
  for (int i = 0, first = 0; i < n; i++) {
    if (i == 0 || k[i].x != k[i - 1].x || k[i].y != k[i - 1].y) first = i;
    int last = i + 1 == n || k[i + 1].x != k[i].x || k[i + 1].y != k[i].y;
    same[k[i].i] = last ? k[first].i : k[i + 1].i;
  }
  free(k);
}

/* The point of contour c after i, and before it. */
static int next_in(const SceneGeometry *s, int c, int i) { return i + 1 < s->contour_start[c + 1] ? i + 1 : s->contour_start[c]; }
static int prev_in(const SceneGeometry *s, int c, int i) { return i > s->contour_start[c] ? i - 1 : s->contour_start[c + 1] - 1; }

/* The angle from direction a to b, counter-clockwise, in [0, 2 pi). */
static double turn(Vec2 a, Vec2 b) {
  double t = atan2(a.x * b.y - a.y * b.x, a.x * b.x + a.y * b.y);
  return t < 0 ? t + 2 * M_PI : t;
}

/* Which of the points at pts[i]'s position a triangle with its centroid
** at m has its corner at: the one whose contour's inside (to the left of
** its edges) holds m, between the edge out and the edge in. */
static int corner_owner(const SceneGeometry *s, const int *contour_of, const int *same, int i, Vec2 m) {
  const Vec2 *p = s->contour_pts;
  for (int k = i;; k = same[k]) {
    int c = contour_of[k];
    Vec2 q = p[k], out = p[next_in(s, c, k)], in = p[prev_in(s, c, k)];
    Vec2 d_out = {out.x - q.x, out.y - q.y}, d_in = {in.x - q.x, in.y - q.y}, d = {m.x - q.x, m.y - q.y};
    if (turn(d_out, d) < turn(d_out, d_in)) return k;
    if (same[k] == i) return i;
  }
}

/* The shape's cap: its triangulation (tri indices; indices from n on are
** points the triangulation added, in extra). Where contours touch, each
** triangle's corner is the point of the contour it lies inside, so the
** solid's pieces that meet there share no vertex and stay manifold. */
typedef struct Cap {
  int n, ntris, nextra;
  int *tris;
  Vec2 *extra;
  double *pts;
} Cap;

static int cap_make(const SceneGeometry *shape, Cap *c, char *err, size_t errlen) {
  SumiP2dPolys p = shape2d_polys(shape);
  int npts;
  memset(c, 0, sizeof *c);
  c->n = p.start[p.ncontours];
  if (!sumi_p2d_triangulate(&p, &c->pts, &npts, &c->tris, &c->ntris, err, errlen)) return -1;
  c->nextra = npts - c->n;
  c->extra = (Vec2 *)c->pts + c->n;
  int *same = xmalloc((size_t)c->n * sizeof *same), *contour_of = xmalloc((size_t)c->n * sizeof *contour_of);
  same_points(shape->contour_pts, c->n, same);
  for (int k = 0; k < shape->ncontours; k++)
    for (int i = shape->contour_start[k]; i < shape->contour_start[k + 1]; i++) contour_of[i] = k;
  const Vec2 *q = (const Vec2 *)c->pts;
  for (int t = 0; t < c->ntris; t++) {
    int *v = c->tris + 3 * t;
    Vec2 m = {(q[v[0]].x + q[v[1]].x + q[v[2]].x) / 3, (q[v[0]].y + q[v[1]].y + q[v[2]].y) / 3};
    for (int k = 0; k < 3; k++)
      if (v[k] < c->n && same[v[k]] != v[k]) v[k] = corner_owner(shape, contour_of, same, v[k], m);
  }
  free(same);
  free(contour_of);
  return 0;
}

static void cap_free(Cap *c) {
  free(c->pts);
  free(c->tris);
}


static int too_many(double nverts, char *err, size_t errlen) {
  if (nverts <= EXTRUDE_MAX_VERTS) return 0;
  snprintf(err, errlen, "it would make %.0f vertices (at most %d: fewer slices or segments)", nverts,
           EXTRUDE_MAX_VERTS);
  return 1;
}

/* ---- linear_extrude --------------------------------------------------------- */

/* cos and sin of d degrees, exact at multiples of 90 (a quarter turn
** lands on the axis, not 6e-17 beside it). */
static void cos_sin_deg(double d, double *c, double *s) {
  double q = d / 90;
  if (q == floor(q) && fabs(q) < 1e15) {
    static const double C[4] = {1, 0, -1, 0}, S[4] = {0, 1, 0, -1};
    long long k = ((long long)q % 4 + 4) % 4;
    *c = C[k], *s = S[k];
    return;
  }
  *c = cos(d * M_PI / 180), *s = sin(d * M_PI / 180);
}

/* Where point q of the shape lands at height fraction t. */
static Vec2 slice_point(const ExtrudeLinear *p, Vec2 q, double t) {
  double c, s;
  cos_sin_deg(-p->twist * t, &c, &s);
  double sx = 1 + (p->scale.x - 1) * t, sy = 1 + (p->scale.y - 1) * t;
  return (Vec2){sx * (c * q.x - s * q.y), sy * (s * q.x + c * q.y)};
}

/* Whether contour c of s is a hole (runs clockwise). */
static int is_hole(const SceneGeometry *s, int c) {
  double area = 0;
  for (int i = s->contour_start[c]; i < s->contour_start[c + 1]; i++) {
    Vec2 p = s->contour_pts[i], q = s->contour_pts[next_in(s, c, i)];
    area += p.x * q.y - q.x * p.y;
  }
  return area < 0;
}

/* A twisted side folds where its quads split, by about twist x edge /
** height (radians), whatever the slices: so edges are cut into pieces of
** at most this fold, 10 degrees. */
#define EXTRUDE_TWIST_FOLD 0.1745

/* shape with each contour edge longer than len cut into equal pieces (a
** contours-only copy; NULL when none is that long). */
static SceneGeometry *refined(Arena *a, const SceneGeometry *shape, double len, char *err, size_t errlen) {
  int n = shape->contour_start[shape->ncontours];
  double total = 0;
  for (int c = 0; c < shape->ncontours; c++)
    for (int i = shape->contour_start[c]; i < shape->contour_start[c + 1]; i++) {
      Vec2 p = shape->contour_pts[i], q = shape->contour_pts[next_in(shape, c, i)];
      total += ceil(hypot(q.x - p.x, q.y - p.y) / len);
    }
  if (total == n) return NULL;
  if (too_many(total, err, errlen)) return (SceneGeometry *)shape;   /* reported */
  SceneGeometry *g = arena_alloc(a, sizeof *g);
  *g = *shape;
  g->contour_start = arena_alloc(a, (size_t)(shape->ncontours + 1) * sizeof *g->contour_start);
  g->contour_pts = arena_alloc(a, (size_t)total * sizeof *g->contour_pts);
  int m = 0;
  for (int c = 0; c < shape->ncontours; c++) {
    g->contour_start[c] = m;
    for (int i = shape->contour_start[c]; i < shape->contour_start[c + 1]; i++) {
      Vec2 p = shape->contour_pts[i], q = shape->contour_pts[next_in(shape, c, i)];
      int k = (int)ceil(hypot(q.x - p.x, q.y - p.y) / len);
      for (int j = 0; j < k; j++) g->contour_pts[m++] = (Vec2){p.x + (q.x - p.x) * j / k, p.y + (q.y - p.y) * j / k};
    }
  }
  g->contour_start[shape->ncontours] = m;
  return g;
}

SceneGeometry *extrude_linear(Arena *a, const SceneGeometry *shape, const ExtrudeLinear *p, char *err, size_t errlen) {
  if (shape2d_is_empty(shape)) return mesh_new(a, 0, 0, 0);
  if (p->twist != 0) {
    SceneGeometry *r = refined(a, shape, EXTRUDE_TWIST_FOLD * p->height / fabs(p->twist * M_PI / 180), err, errlen);
    if (r == shape) return NULL;
    if (r) shape = r;
  }
  Cap cap;
  int n = shape->contour_start[shape->ncontours], S = p->slices;
  if (too_many((double)(S + 1) * n, err, errlen) || cap_make(shape, &cap, err, errlen)) return NULL;
  int point_top = p->scale.x == 0 || p->scale.y == 0;   /* the top is a line or a point: no cap */
  int flat = p->twist == 0 && p->scale.x == p->scale.y;  /* sides are plane quads */
  double z0 = p->center ? -p->height / 2 : 0;
  int nv = (S + 1) * n + 2 * cap.nextra;
  SceneGeometry *g = mesh_new(a, nv, 2 * cap.ntris + 2 * S * n, 6 * cap.ntris + 6 * S * n);
  for (int k = 0; k <= S; k++)
    for (int i = 0; i < n; i++) {
      Vec2 q = slice_point(p, shape->contour_pts[i], (double)k / S);
      g->verts[k * n + i] = v3(q.x, q.y, z0 + p->height * k / S);
    }
  for (int e = 0; e < cap.nextra; e++) {
    Vec2 q = slice_point(p, cap.extra[e], 1);
    g->verts[(S + 1) * n + e] = v3(cap.extra[e].x, cap.extra[e].y, z0);
    g->verts[(S + 1) * n + cap.nextra + e] = v3(q.x, q.y, z0 + p->height);
  }
  /* the top ring's vertex for each point: where the scale made points
  ** meet (at a line or a point), the first of them */
  int *top = xmalloc((size_t)n * sizeof *top);
  for (int i = 0; i < n; i++) top[i] = S * n + i;
  if (point_top) {
    Vec2 *tp = xmalloc((size_t)n * sizeof *tp);
    int *same = xmalloc((size_t)n * sizeof *same);
    for (int i = 0; i < n; i++) tp[i] = (Vec2){g->verts[S * n + i].x, g->verts[S * n + i].y};
    same_points(tp, n, same);
    for (int i = 0; i < n; i++)
      for (int k = same[i]; k != i; k = same[k])
        if (k < top[i] - S * n) top[i] = S * n + k;
    free(tp);
    free(same);
  }
  /* caps: the bottom faces -z (its triangles turned), the top +z */
  for (int t = 0; t < cap.ntris; t++) {
    const int *c = cap.tris + 3 * t;
    int b[3], u[3];
    for (int k = 0; k < 3; k++) {
      b[k] = c[k] < n ? c[k] : (S + 1) * n + (c[k] - n);
      u[k] = c[k] < n ? S * n + c[k] : (S + 1) * n + cap.nextra + (c[k] - n);
    }
    face3(g, b[0], b[2], b[1]);
    if (!point_top) face3(g, u[0], u[1], u[2]);
  }
  /* sides: each contour edge i -> j, each slice k. A bent quad is split
  ** along the diagonal OpenSCAD 2021 takes (the one that bulges out, so
  ** the solid is a little larger than the smooth one): from the bottom of
  ** i to the top of j where the twist turns clockwise on an outer contour
  ** (or the other way on a hole), else from the top of i to the bottom of
  ** j. */
  for (int c = 0; c < shape->ncontours; c++) {
    int down = (p->twist < 0) != is_hole(shape, c);
    for (int i = shape->contour_start[c]; i < shape->contour_start[c + 1]; i++) {
      int j = next_in(shape, c, i);
      for (int k = 0; k < S; k++) {
        int b0 = k * n + i, b1 = k * n + j;
        int t0 = k + 1 == S ? top[i] : (k + 1) * n + i, t1 = k + 1 == S ? top[j] : (k + 1) * n + j;
        if (t0 == t1) face3(g, b0, b1, t0);
        else if (flat) face4(g, b0, b1, t1, t0);
        else if (down) face3(g, b0, b1, t0), face3(g, b1, t1, t0);
        else face3(g, b0, b1, t1), face3(g, b0, t1, t0);
      }
    }
  }
  free(top);
  cap_free(&cap);
  return g;
}

/* ---- rotate_extrude ------------------------------------------------------- */

SceneGeometry *extrude_rotate(Arena *a, const SceneGeometry *shape, double angle, int segments, char *err,
                              size_t errlen) {
  if (shape2d_is_empty(shape)) return mesh_new(a, 0, 0, 0);
  int n = shape->contour_start[shape->ncontours], full = fabs(angle) >= 360;
  Vec2 lo, hi;
  shape2d_bounds(shape, &lo, &hi);
  if (lo.x < 0 && hi.x > 0) {
    snprintf(err, errlen, "the shape crosses the axis: its x runs from %g to %g, and a profile keeps to one side "
             "of x = 0", lo.x, hi.x);
    return NULL;
  }
  const SceneGeometry *s = shape;
  if (hi.x <= 0) {   /* all on the left: mirrored onto the right, as OpenSCAD does */
    Mat4 m = m4_identity();
    m.m[0][0] = -1;
    s = shape_transformed(a, shape, m);
  }
  int rings = full ? segments : segments + 1;
  Cap cap;
  memset(&cap, 0, sizeof cap);
  if (too_many((double)rings * n, err, errlen) || (!full && cap_make(s, &cap, err, errlen))) return NULL;
  /* a point on the axis is one vertex for every ring: the first ring's */
  SceneGeometry *g = mesh_new(a, rings * n + 2 * cap.nextra, 2 * cap.ntris + segments * n,
                              6 * cap.ntris + 4 * segments * n);
  for (int r = 0; r < rings; r++) {
    double c, sn;
    cos_sin_deg(angle * r / segments, &c, &sn);
    for (int i = 0; i < n; i++) {
      Vec2 q = s->contour_pts[i];
      g->verts[r * n + i] = v3(q.x * c, q.x * sn, q.y);
    }
  }
  double c1, s1;
  cos_sin_deg(angle, &c1, &s1);
  for (int e = 0; e < cap.nextra; e++) {
    Vec2 q = cap.extra[e];
    g->verts[rings * n + e] = v3(q.x, 0, q.y);
    g->verts[rings * n + cap.nextra + e] = v3(q.x * c1, q.x * s1, q.y);
  }
  int flip = angle < 0;   /* sweeping clockwise turns every face */
#define VID(r, i) (s->contour_pts[i].x == 0 ? (i) : ((r) % rings) * n + (i))
  for (int t = 0; t < cap.ntris; t++) {   /* the start faces back along the sweep, the end along it */
    int v0[3], v1[3];
    for (int k = 0; k < 3; k++) {
      int i = cap.tris[3 * t + k];
      v0[k] = i < n ? VID(0, i) : rings * n + (i - n);
      v1[k] = i < n ? VID(segments, i) : rings * n + cap.nextra + (i - n);
    }
    if (flip) face3(g, v0[0], v0[2], v0[1]), face3(g, v1[0], v1[1], v1[2]);
    else face3(g, v0[0], v0[1], v0[2]), face3(g, v1[0], v1[2], v1[1]);
  }
  for (int c = 0; c < s->ncontours; c++)
    for (int i = s->contour_start[c]; i < s->contour_start[c + 1]; i++) {
      int j = next_in(s, c, i);
      int on_i = s->contour_pts[i].x == 0, on_j = s->contour_pts[j].x == 0;
      if (on_i && on_j) continue;   /* an edge along the axis sweeps nothing */
      for (int r = 0; r < segments; r++) {
        int a0 = VID(r, i), a1 = VID(r + 1, i), b0 = VID(r, j), b1 = VID(r + 1, j);
        if (flip) {
          int t0 = a0, t1 = b0;
          a0 = a1, a1 = t0, b0 = b1, b1 = t1;
        }
        if (on_i) face3(g, a0, b1, b0);
        else if (on_j) face3(g, a0, a1, b0);
        else face4(g, a0, a1, b1, b0);
      }
    }
#undef VID
  cap_free(&cap);
  return g;
}

/* ---- measures ---------------------------------------------------------- */

double extrude_mesh_volume(const SceneGeometry *g) {
  double v = 0;
  for (int f = 0; f < g->nfaces; f++) {
    const int *idx = g->face_index + g->face_start[f];
    int m = g->face_start[f + 1] - g->face_start[f];
    Vec3 p0 = g->verts[idx[0]];
    for (int k = 1; k + 1 < m; k++) v += v3_dot(p0, v3_cross(g->verts[idx[k]], g->verts[idx[k + 1]]));
  }
  return v / 6;
}
