/*
** Shapes in the plane (see shape2d.h).
*/
#include "shape2d.h"
#include "shapes.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The bridge reads a Vec2 array as x, y pairs. */
_Static_assert(sizeof(Vec2) == 2 * sizeof(double), "Vec2 is two doubles");

int shape2d_fragments(double r, double fn, double fa, double fs) {
  double n = fn > 0 ? fmax(floor(fn), 3) : ceil(fmax(fmin(360.0 / fa, 2 * M_PI * r / fs), 5));
  return n > SHAPE2D_MAX_POINTS ? -1 : (int)n;
}

int shape2d_is_empty(const SceneGeometry *g) {
  return g->kind == GEOM_MESH && g->ncontours == 0 && g->nfaces == 0 && g->nverts == 0 && g->subdiv_level == 0;
}

int shape2d_is_2d(const SceneGeometry *g) { return g->ncontours > 0; }

SumiP2dPolys shape2d_polys(const SceneGeometry *g) {
  static int zero = 0;
  SumiP2dPolys p = {g->ncontours, g->ncontours ? g->contour_start : &zero, (double *)g->contour_pts};
  return p;
}

/* ---- making a shape from clean contours ------------------------------- */

static void *arena_copy(Arena *a, const void *src, size_t n) {
  void *d = arena_alloc(a, n ? n : 1);
  if (n) memcpy(d, src, n);
  return d;
}

/* The 2D shape of clean polygons p (the bridge's form): its contours and
** their triangulation; NULL with a reason on failure. */
static SceneGeometry *make(Arena *a, const SumiP2dPolys *p, char *err, size_t errlen) {
  double *pts;
  int *tris, npts, ntris;
  if (!sumi_p2d_triangulate(p, &pts, &npts, &tris, &ntris, err, errlen)) return NULL;
  SceneGeometry *g = arena_alloc(a, sizeof *g);
  g->kind = GEOM_MESH;
  int n = p->start[p->ncontours];
  g->ncontours = p->ncontours;
  g->contour_start = arena_copy(a, p->start, (size_t)(p->ncontours + 1) * sizeof *p->start);
  g->contour_pts = arena_copy(a, p->xy, (size_t)n * sizeof *g->contour_pts);
  g->nverts = npts;
  g->verts = arena_alloc(a, (size_t)(npts ? npts : 1) * sizeof *g->verts);
  for (int i = 0; i < npts; i++) g->verts[i] = v3(pts[2 * i], pts[2 * i + 1], 0);
  g->nfaces = ntris;
  g->face_start = arena_alloc(a, (size_t)(ntris + 1) * sizeof *g->face_start);
  g->face_index = arena_copy(a, tris, (size_t)ntris * 3 * sizeof *tris);
  for (int f = 0; f <= ntris; f++) g->face_start[f] = 3 * f;
  free(pts);
  free(tris);
  return g;
}


/* Clean polygons (a bridge result, freed here) into a shape. */
static SceneGeometry *make_owned(Arena *a, SumiP2dPolys *p, char *err, size_t errlen) {
  SceneGeometry *g = p->ncontours ? make(a, p, err, errlen) : shape_empty(a);
  sumi_p2d_free(p);
  return g;
}

SceneGeometry *shape2d_from_contours(Arena *a, const Vec2 *pts, const int *start, int ncontours, SumiP2dFill fill,
                                     char *err, size_t errlen) {
  SumiP2dPolys in = {ncontours, (int *)start, (double *)pts}, out;
  if (!sumi_p2d_boolean(SUMI_P2D_UNION, &in, 1, fill, &out, err, errlen)) return NULL;
  return make_owned(a, &out, err, errlen);
}

/* ---- primitives ----------------------------------------------------------- */

SceneGeometry *shape2d_circle(Arena *a, double r, int n, char *err, size_t errlen) {
  Vec2 *pts = xmalloc((size_t)n * sizeof *pts);
  for (int i = 0; i < n; i++) {
    double phi = 2 * M_PI * i / n;
    pts[i] = (Vec2){r * cos(phi), r * sin(phi)};
  }
  int start[2] = {0, n};
  SceneGeometry *g = shape2d_from_contours(a, pts, start, 1, SUMI_P2D_NON_ZERO, err, errlen);
  free(pts);
  return g;
}

SceneGeometry *shape2d_square(Arena *a, Vec2 s, int center, char *err, size_t errlen) {
  Vec2 o = center ? (Vec2){-s.x / 2, -s.y / 2} : (Vec2){0, 0};
  Vec2 pts[4] = {{o.x, o.y}, {o.x + s.x, o.y}, {o.x + s.x, o.y + s.y}, {o.x, o.y + s.y}};
  int start[2] = {0, 4};
  return shape2d_from_contours(a, pts, start, 1, SUMI_P2D_NON_ZERO, err, errlen);
}

/* ---- booleans and offsets ------------------------------------------------ */

SceneGeometry *shape2d_boolean(Arena *a, SumiP2dOp op, const SceneGeometry *const *g, int n, char *err,
                               size_t errlen) {
  SumiP2dPolys *in = xmalloc((size_t)(n ? n : 1) * sizeof *in), out;
  for (int i = 0; i < n; i++) in[i] = shape2d_polys(g[i]);
  int ok = sumi_p2d_boolean(op, in, n, SUMI_P2D_NON_ZERO, &out, err, errlen);
  free(in);
  return ok ? make_owned(a, &out, err, errlen) : NULL;
}

SceneGeometry *shape2d_offset(Arena *a, const SceneGeometry *g, double delta, SumiP2dJoin join, int n, char *err,
                              size_t errlen) {
  SumiP2dPolys in = shape2d_polys(g), out;
  /* a chord of an n-gon strays r (1 - cos(pi / n)) from its arc */
  double tol = fabs(delta) * (1 - cos(M_PI / (n > 2 ? n : 3)));
  if (!sumi_p2d_offset(&in, delta, join, tol, &out, err, errlen)) return NULL;
  return make_owned(a, &out, err, errlen);
}

/* ---- measures ---------------------------------------------------------- */

double shape2d_area(const SceneGeometry *g) {
  double s = 0;   /* the shoelace sum: outer contours count up, holes down */
  for (int c = 0; c < g->ncontours; c++)
    for (int i = g->contour_start[c], e = g->contour_start[c + 1]; i < e; i++) {
      Vec2 p = g->contour_pts[i], q = g->contour_pts[i + 1 < e ? i + 1 : g->contour_start[c]];
      s += p.x * q.y - q.x * p.y;
    }
  return s / 2;
}

void shape2d_bounds(const SceneGeometry *g, Vec2 *lo, Vec2 *hi) {
  int n = g->ncontours ? g->contour_start[g->ncontours] : 0;
  *lo = *hi = n ? g->contour_pts[0] : (Vec2){0, 0};
  for (int i = 1; i < n; i++) {
    Vec2 p = g->contour_pts[i];
    lo->x = fmin(lo->x, p.x), lo->y = fmin(lo->y, p.y);
    hi->x = fmax(hi->x, p.x), hi->y = fmax(hi->y, p.y);
  }
}
