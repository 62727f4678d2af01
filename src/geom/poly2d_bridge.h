/*
** The 2D polygon bridge: a plain C view of Clipper (Angus Johnson's
** polygon clipping library, Debian's libpolyclipping-dev) for booleans,
** fill rules and offsets of polygons with holes, and of CGAL's
** constrained Delaunay triangulation for triangulating them. The
** implementation is C++17 in poly2d_bridge.cpp; no exception crosses this
** header. Every function that can fail returns 1 on success and 0 on
** failure, with a one-line reason written into err (errlen bytes, always
** terminated).
**
** Clipper works on integers: each call scales its points by one power of
** two, chosen from their extent so that the largest coordinate becomes
** about 2^46, and scales the result back. Points therefore move by at most
** 2^-47 of the largest coordinate; powers of two and other short binary
** fractions (0.5, 1.25) come back exactly.
*/
#ifndef geom_poly2d_bridge_h
#define geom_poly2d_bridge_h

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Closed polygons: contour c is points start[c] .. start[c + 1] - 1 of
** xy (x, y pairs), the last point joined back to the first. */
typedef struct SumiP2dPolys {
  int ncontours;
  int *start;                  /* ncontours + 1 offsets */
  double *xy;                  /* 2 * start[ncontours] */
} SumiP2dPolys;

/* Releases what a bridge function filled into p (malloc'd arrays). */
void sumi_p2d_free(SumiP2dPolys *p);

typedef enum {
  SUMI_P2D_UNION,              /* everything any input covers */
  SUMI_P2D_DIFFERENCE,         /* the first input less all the others */
  SUMI_P2D_INTERSECTION        /* what every input covers */
} SumiP2dOp;

typedef enum {
  SUMI_P2D_EVEN_ODD,           /* inside where a ray crosses an odd number of edges */
  SUMI_P2D_NON_ZERO            /* inside where the winding number is not 0 */
} SumiP2dFill;

/* Combine n sets of polygons by op, each read with fill, into *out: outer
** contours counter-clockwise, holes clockwise, no two edges crossing
** (strictly simple: contours may touch only at a vertex they share), an
** outer contour before the holes inside it. n = 1 with SUMI_P2D_UNION
** cleans one set (a self-intersecting polygon, a glyph's overlapping
** strokes) into that form. */
int sumi_p2d_boolean(SumiP2dOp op, const SumiP2dPolys *in, int n, SumiP2dFill fill, SumiP2dPolys *out, char *err,
                     size_t errlen);

typedef enum {
  SUMI_P2D_JOIN_ROUND,         /* corners rounded (arcs within arc_tolerance) */
  SUMI_P2D_JOIN_MITER,         /* corners kept sharp (up to a miter limit of 2 delta, as OpenSCAD) */
  SUMI_P2D_JOIN_SQUARE         /* corners cut off (OpenSCAD's chamfer) */
} SumiP2dJoin;

/* Grow (delta > 0) or shrink (delta < 0) clean polygons in (the form
** sumi_p2d_boolean makes) by |delta| into *out, in that form. */
int sumi_p2d_offset(const SumiP2dPolys *in, double delta, SumiP2dJoin join, double arc_tolerance,
                    SumiP2dPolys *out, char *err, size_t errlen);

/* Triangulate the region clean polygons in bound (the form
** sumi_p2d_boolean makes). *pts gets the points the triangles index: the
** npts = in->start[in->ncontours] input points first, in order, then any
** the triangulation had to add; *tris gets 3 indices a triangle, counter-
** clockwise. Both are malloc'd; free them. A point that appears twice in
** in (where two contours touch) is one vertex: its first index. */
int sumi_p2d_triangulate(const SumiP2dPolys *in, double **pts, int *npts, int **tris, int *ntris, char *err,
                         size_t errlen);

#ifdef __cplusplus
}
#endif

#endif
