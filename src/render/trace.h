/*
** Reference image analysis (001 §2.1.3-2.1.4): for every visible edge,
** walk its projected line with the Bresenham steps it was tested with and
** cut it into segments, the runs where it is visible. max_misses lets a
** run bridge that many missed steps in a row; it counts output pixels (so
** a reference image at ref_scale 4 bridges four times as many of its
** steps), as a gap is seen in the output. A segment that reaches an end
** of the walk (its first hit within max_misses of the start, or at most
** max_misses misses after its last hit before the end) takes the edge's
** real end point and is linkable there. One-step segments are dropped
** unless the whole walk is one pixel.
*/
#ifndef render_trace_h
#define render_trace_h

#include "edgeref.h"

/* A visible piece of an edge, ordered like the edge's span (v[0] -> v[1]). */
typedef struct LineSeg {
  float x0, y0, x1, y1;        /* reference pixels */
  unsigned char at0, at1;      /* touches the v[0] (v[1]) end and may link there */
} LineSeg;

typedef struct LineTrace {
  int nids;
  int *first;                  /* per id - 1: index of its first segment; nids + 1 entries */
  LineSeg *seg;                /* segments of id i + 1 are seg[first[i] .. first[i + 1]) */
  int nseg;
  int nvisible;                /* ids with a segment */
} LineTrace;

/* Trace every visible edge of ref; max_misses comes from each edge's
** object (edges->obj[..].lines), in output pixels, ref_per_px reference
** pixels each. Uses threads workers. Free with line_trace_free. */
void line_trace_build(LineTrace *tr, const LineRef *ref, const LineEdges *edges, double ref_per_px,
                      int threads);
void line_trace_free(LineTrace *tr);

/* Segments of one span whose steps are visible where vis[i] != 0, with
** max_misses reference steps, into out (room for at least span->nsteps /
** 2 + 1); returns how many. Exposed for tests. */
int line_trace_span(const LineSpan *span, const unsigned char *vis, int max_misses, LineSeg *out);

/* max_misses output pixels in reference steps, ref_per_px of them a pixel. */
int line_trace_misses(int max_misses, double ref_per_px);

#endif
