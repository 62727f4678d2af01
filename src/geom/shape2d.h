/*
** Shapes in the plane (OpenSCAD's 2D subsystem): circle, square, polygon
** with holes, text's outlines, their booleans and offsets, as geometry
** values. A 2D shape is a SceneGeometry with ncontours > 0 (scene.h):
** closed contours in the xy-plane, outer boundaries counter-clockwise and
** holes clockwise, no two edges crossing, plus the triangulation of the
** region they bound as a mesh facing +z, so the shape draws flat. An empty
** mesh (no contours, no faces) is the empty shape, in 2D as in 3D.
**
** Booleans, fill rules and offsets go through Clipper, triangles through
** CGAL (poly2d_bridge.h). Everything is allocated in the given arena.
*/
#ifndef geom_shape2d_h
#define geom_shape2d_h

#include "../scene/scene.h"
#include "poly2d_bridge.h"

/* Segments of a full circle of radius r, as OpenSCAD counts them: fn when
** fn > 0 (at least 3); else from the largest angle fa (degrees) and the
** longest side fs a segment may have: ceil(max(min(360 / fa, 2 pi r /
** fs), 5)). The builtins pass OpenSCAD's fa = 12, fs = 2 when a call gives
** one of them and SHAPE2D_SEGMENTS when it gives neither. -1 when that
** is more than SHAPE2D_MAX_POINTS. */
#define SHAPE2D_SEGMENTS 64
int shape2d_fragments(double r, double fn, double fa, double fs);

/* Most points a 2D shape may have (its contours, before cleaning): a
** million, so a runaway `$fn` or polygon is an error, not minutes of
** triangulation. */
#define SHAPE2D_MAX_POINTS 1000000

/* Whether g is a 2D shape, or the empty shape. */
int shape2d_is_2d(const SceneGeometry *g);
int shape2d_is_empty(const SceneGeometry *g);

/* The 2D shape the contours (pts from start[c] to start[c + 1] - 1, each
** closed) bound under fill, cleaned by Clipper and triangulated; NULL
** with a reason in err on failure. */
SceneGeometry *shape2d_from_contours(Arena *a, const Vec2 *pts, const int *start, int ncontours, SumiP2dFill fill,
                                     char *err, size_t errlen);
/* A circle of radius r around the origin: n points from (r, 0) on,
** counter-clockwise, as OpenSCAD places them. */
SceneGeometry *shape2d_circle(Arena *a, double r, int n, char *err, size_t errlen);
/* A rectangle from the origin to size, or centred on it. (Each returns
** NULL with a reason in err when Clipper or CGAL fail, as below.) */
SceneGeometry *shape2d_square(Arena *a, Vec2 size, int center, char *err, size_t errlen);

/* g[0] op g[1] op ... op g[n-1] (each a 2D or the empty shape); NULL
** with a reason in err on failure. */
SceneGeometry *shape2d_boolean(Arena *a, SumiP2dOp op, const SceneGeometry *const *g, int n, char *err,
                               size_t errlen);
/* g grown by delta (shrunk when negative), corners joined by join (arcs
** of n segments a full turn when round). */
SceneGeometry *shape2d_offset(Arena *a, const SceneGeometry *g, double delta, SumiP2dJoin join, int n, char *err,
                              size_t errlen);

/* The contours of g as the bridge reads them (pointing into g). */
SumiP2dPolys shape2d_polys(const SceneGeometry *g);
/* The area g's contours bound (holes counted out). */
double shape2d_area(const SceneGeometry *g);
/* The smallest and largest coordinates of g's contours ([0, 0] twice
** for the empty shape). */
void shape2d_bounds(const SceneGeometry *g, Vec2 *lo, Vec2 *hi);

#endif
