/*
** Linking segments into polylines through the mesh edge graph (001
** §2.1.3, §2.1.5). From a segment end that touches its edge's vertex, a
** breadth-first search over the object's edges (following only important
** edges not yet used, up to link_depth) looks for a visible (traced into
** segments), unused, important edge whose screen direction differs from
** the current one by less than link_angle; a depth where a candidate was
** refused for its angle is the last one searched. Links never cross
** objects. Each edge is used in at most one polyline.
*/
#ifndef render_link_h
#define render_link_h

#include "trace.h"

typedef struct LinePolys {
  int n;                   /* polylines */
  int *start;              /* n + 1 offsets into pts (in points) */
  float *pts;              /* x, y pairs, reference pixels */
  int *obj;                /* object index of each polyline */
  int npts, cap_pts, cap, cap_start;  /* storage */
} LinePolys;

/* Link the traced segments of every visible edge into *out, visiting the
** visible ids in ascending order (deterministic). Free with
** line_polys_free. */
void line_link_build(LinePolys *out, const LineRef *ref, const LineTrace *tr,
                     const LineEdges *edges);
void line_polys_free(LinePolys *p);

/* Append points [0, n) of p (x, y pairs) as one polyline of object obj;
** fewer than 2 points add nothing. */
void line_polys_append(LinePolys *out, const float *p, int n, int obj);

#endif
