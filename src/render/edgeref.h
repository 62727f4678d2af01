/*
** The reference image (001 §2.1.2): every important edge depth-tested
** against all meshes. The paper draws each edge in its own colour into an
** image over the meshes and reads the colours back; sumi tests each edge
** where the paper's tracing would look, at the points of its walk (one a
** pixel along its dominant axis), and keeps the result step by step
** (LineRef.vis), which is what tracing reads.
**
** Two things differ from drawing into pixels, both so that outlines hold:
**  - the points lie on the edge's exact projected line, not at the centres
**    of the pixels the line crosses: a pixel centre beside a silhouette can
**    fall on a surface that does not cover the edge (a face seen edge-on
**    next to it, a part of the model just inside the outline) and hide it;
**  - edges do not compete for pixels: where edges meet or cross, each
**    keeps its own record, so an edge shorter than a pixel, and a run of
**    them (a silhouette through a finely tessellated pole), is not lost to
**    its neighbours (the paper bridges such losses with link depth, a few
**    at a time).
**
** At each point the nearest surface covering it is pushed away from the
** camera by a slope-scaled offset, as a polygon offset
** (LINE_DEPTH_OFFSET_BASE + depth_offset reference pixels of that
** surface's depth slope), when the surface is turned the same way (toward
** or away from the viewer) as one of the edge's faces, and by only
** LINE_DEPTH_EPS when it is turned the other way. So an edge never loses
** to the faces it lies on (no stitching), and an edge on the far side of
** an object does not leak out from behind a silhouette or a corner, as
** one global offset lets it. The set of edges with a visible point is
** recorded as they are tested, so nothing scans an image.
**
** Depth here is "nearness", 1 - depth of camera.h (1 at the near plane,
** 0 at the far plane).
*/
#ifndef render_edgeref_h
#define render_edgeref_h

#include <stdint.h>

#include "edges.h"

/* The polygon-offset factor, in reference pixels of a surface's depth
** slope, before the style's depth_offset (default 0) is added to it: the
** faces around an edge's ends meet it at a point, and float rounding of
** the projection moves a point by a fraction of a pixel. */
#define LINE_DEPTH_OFFSET_BASE 1.5
/* Constant part of the mesh offset, in nearness units (a few float ulps at
** depth 1). */
#define LINE_DEPTH_EPS 1e-6f

/* An important edge's line in the reference image: its projected ends,
** clipped to the near plane and the image, ordered from the mesh edge's
** v[0] to v[1]. Its walk has nsteps points, evenly spaced from one end to
** the other, one a pixel along the dominant axis. */
typedef struct LineSpan {
  float x0, y0, x1, y1;        /* reference pixels */
  float n0, n1;                /* nearness at the ends */
  int px0, py0, px1, py1;      /* the pixels of the ends */
  int nsteps;                  /* points of the walk; 0 = off screen */
  unsigned char real0, real1;  /* the end is the vertex itself, not a clip point */
} LineSpan;

typedef struct LineRef {
  int width, height;           /* the reference image */
  int nids;                    /* important edges (ids 1..nids) */
  LineSpan *span;              /* per id - 1 */
  size_t *step0;               /* nids + 1: where each id's steps start in vis */
  unsigned char *vis;          /* per step of each walk: 1 where the edge is visible */
  int *count;                  /* per id - 1: its visible steps */
  int nvisible;
  int *visible;                /* the ids with a visible step, ascending */
} LineRef;

/* Most points the walks of a frame's edges may have: the test keeps 20
** bytes for each and 16 more a worker (2.4 GB at the limit on one). */
#define LINE_MAX_STEPS (1LL << 26)

/* Build the reference image of edges (whose vertices are already projected
** into a width x height image) over the meshes of objs, using threads
** workers (>= 1). Returns 1, or 0 (no edge visible) when the walks come
** to more than LINE_MAX_STEPS points: ref->step0[ref->nids] says how many.
** Free with line_ref_free either way. */
int line_ref_build(LineRef *ref, const LineEdges *edges, const LineObject *objs, int width,
                   int height, int threads);
void line_ref_free(LineRef *ref);

/* The visibility record of id's walk in ref: entry i is step i. */
static inline const unsigned char *line_ref_vis(const LineRef *ref, int id) {
  return ref->vis + ref->step0[id - 1];
}

#endif
