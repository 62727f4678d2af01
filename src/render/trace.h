/*
** Reference image analysis (001 §2.1.3-2.1.4): for every visible edge,
** walk its projected line with the Bresenham steps it was drawn with and
** cut it into segments, the runs where its id is found. search_width also
** looks that many pixels to either side across the dominant axis;
** max_misses lets a run bridge that many missed steps in a row. A segment
** that reaches an end of the walk (its first hit within max_misses steps of
** the start, or at most max_misses misses after its last hit before the
** end) takes the edge's real end point and is linkable there. One-step
** segments are dropped unless the whole walk is one pixel.
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
} LineTrace;

/* Trace every visible edge of ref; search_width and max_misses come from
** each edge's object (edges->obj[..].lines). Uses threads workers. Free
** with line_trace_free. */
void line_trace_build(LineTrace *tr, const LineRef *ref, const LineEdges *edges, int threads);
void line_trace_free(LineTrace *tr);

/* Segments of one span (id) in ref, into out (room for at least
** span->nsteps / 2 + 1); returns how many. Exposed for tests. */
int line_trace_span(const LineRef *ref, const LineSpan *span, uint32_t id, int search_width,
                    int max_misses, LineSeg *out);

#endif
