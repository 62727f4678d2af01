/*
** Segment identification: the walk along each visible edge's line in the
** reference image, with misses (001 §2.1.4).
*/
#include "trace.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"

/* The point of step i on the span's exact line (not the pixel centre). */
static void step_point(const LineSpan *s, int i, float *x, float *y) {
  float t = s->nsteps > 1 ? (float)i / (float)(s->nsteps - 1) : 0;
  *x = s->x0 + t * (s->x1 - s->x0);
  *y = s->y0 + t * (s->y1 - s->y0);
}

/* Close the run of steps [a, b] into out; returns 1 if it is kept. */
static int close_run(const LineSpan *s, int a, int b, int max_misses, LineSeg *out) {
  int n = s->nsteps;
  int touch0 = a <= max_misses, touch1 = n - 1 - b <= max_misses;
  if (touch0) a = 0;
  if (touch1) b = n - 1;
  if (a == b && n > 1) return 0;   /* one pixel cannot define a segment */
  if (touch0) { out->x0 = s->x0; out->y0 = s->y0; } else step_point(s, a, &out->x0, &out->y0);
  if (touch1) { out->x1 = s->x1; out->y1 = s->y1; } else step_point(s, b, &out->x1, &out->y1);
  out->at0 = (unsigned char)(touch0 && s->real0);
  out->at1 = (unsigned char)(touch1 && s->real1);
  return 1;
}

int line_trace_span(const LineSpan *s, const unsigned char *vis, int max_misses, LineSeg *out) {
  int n = s->nsteps, nout = 0;
  if (n <= 0) return 0;
  if (max_misses < 0) max_misses = 0;
  int in_run = 0, start = 0, last = 0, misses = 0;
  for (int i = 0; i < n; i++) {
    if (vis[i]) {
      if (!in_run) { in_run = 1; start = i; }
      last = i;
      misses = 0;
    } else if (in_run && ++misses > max_misses) {
      nout += close_run(s, start, last, max_misses, &out[nout]);
      in_run = 0;
    }
  }
  if (in_run) nout += close_run(s, start, last, max_misses, &out[nout]);
  return nout;
}

int line_trace_misses(int max_misses, double ref_per_px) {
  double m = (max_misses > 0 ? max_misses : 0) * ref_per_px;
  return m < 64 * 8 ? (int)floor(m + 0.5) : 64 * 8;   /* the property's cap at the largest ref_scale */
}

/* ---- all visible edges --------------------------------------------------- */

#define TRACE_CHUNK 64   /* visible edges a task */

typedef struct TraceJob {
  const LineRef *ref;
  const LineEdges *edges;
  double ref_per_px;   /* reference pixels to an output pixel */
  LineSeg **seg;       /* per task: its segments */
  int *nseg;           /* per task */
  int *count;          /* per id - 1: segments */
} TraceJob;

static void trace_task(void *ctx, int task, int worker) {
  TraceJob *j = ctx;
  const LineRef *ref = j->ref;
  int lo = task * TRACE_CHUNK, hi = lo + TRACE_CHUNK;
  if (hi > ref->nvisible) hi = ref->nvisible;
  int cap = 0, n = 0;
  LineSeg *seg = NULL;
  for (int k = lo; k < hi; k++) {
    int id = ref->visible[k];
    const LineSpan *s = &ref->span[id - 1];
    const SceneLines *ls = j->edges->obj[j->edges->obj_of[id - 1]].lines;
    seg = xgrow(seg, &cap, n + s->nsteps / 2 + 1, sizeof *seg);
    int got = line_trace_span(s, line_ref_vis(ref, id), line_trace_misses(ls->max_misses, j->ref_per_px),
                              seg + n);
    j->count[id - 1] = got;
    n += got;
  }
  j->seg[task] = seg;
  j->nseg[task] = n;
}

void line_trace_build(LineTrace *tr, const LineRef *ref, const LineEdges *edges, double ref_per_px,
                      int threads) {
  memset(tr, 0, sizeof *tr);
  tr->nids = ref->nids;
  int ntasks = (ref->nvisible + TRACE_CHUNK - 1) / TRACE_CHUNK;
  TraceJob job = {ref, edges, ref_per_px, xcalloc((size_t)ntasks + 1, sizeof(LineSeg *)),
                  xcalloc((size_t)ntasks + 1, sizeof(int)),
                  xcalloc((size_t)ref->nids + 1, sizeof(int))};
  line_parallel(ntasks, threads, trace_task, &job);
  for (int t = 0; t < ntasks; t++) tr->nseg += job.nseg[t];
  tr->seg = xmalloc(((size_t)tr->nseg + 1) * sizeof *tr->seg);
  int at = 0;
  for (int t = 0; t < ntasks; t++) {   /* tasks hold visible ids in ascending order */
    if (job.nseg[t]) memcpy(tr->seg + at, job.seg[t], (size_t)job.nseg[t] * sizeof *tr->seg);
    at += job.nseg[t];
    free(job.seg[t]);
  }
  tr->first = xmalloc(((size_t)ref->nids + 1) * sizeof *tr->first);
  at = 0;
  for (int i = 0; i < ref->nids; i++) {
    tr->first[i] = at;
    at += job.count[i];
    tr->nvisible += job.count[i] > 0;
  }
  tr->first[ref->nids] = at;
  free(job.seg);
  free(job.nseg);
  free(job.count);
}

void line_trace_free(LineTrace *tr) {
  free(tr->first);
  free(tr->seg);
  memset(tr, 0, sizeof *tr);
}
