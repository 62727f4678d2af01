/*
** The progress line of a render on a terminal (progress.h).
*/
#include "progress.h"

#include <pthread.h>
#include <stdio.h>
#include <time.h>
#include <unistd.h>

/* One line for the process: there is one standard error. Workers call
** on_tiles at once; whoever holds the lock draws, the others skip. */
static struct {
  int on;
  pthread_mutex_t lock;
  int nframes, frame;          /* frame k of n, from 1 */
  double start, frame_start;   /* of the run, of this frame */
  int done, total;             /* this frame's tiles */
  int shown;                   /* the line is on the terminal */
  double drawn;                /* when it was last drawn */
} P = {0, PTHREAD_MUTEX_INITIALIZER, 0, 0, 0, 0, 0, 0, 0, 0};

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* s seconds as m:ss, or h:mm:ss from an hour, into buf. */
static const char *clock_text(double s, char *buf, size_t n) {
  long t = (long)(s + 0.5);
  if (t >= 3600) snprintf(buf, n, "%ld:%02ld:%02ld", t / 3600, t / 60 % 60, t % 60);
  else snprintf(buf, n, "%ld:%02ld", t / 60, t % 60);
  return buf;
}

/* Seconds the run still needs, estimated: the frames done give the time
** a frame takes (this one's tiles say how much of it is left); before the
** first is done, this frame's tiles and time so far do. -1 when there is
** nothing to go on yet. */
static double seconds_left(double t) {
  double in_frame = t - P.frame_start, f = P.total > 0 ? (double)P.done / P.total : 0;
  int frames_done = P.frame - 1;
  if (frames_done > 0) {
    double per = (P.frame_start - P.start) / frames_done;
    return per * (1 - f) + per * (P.nframes - P.frame);
  }
  if (f < 0.02) return -1;
  double per = in_frame / f;
  return per - in_frame + per * (P.nframes - P.frame);
}

/* Draw the line (the lock held). */
static void draw(double t) {
  char line[160], el[32], left[32];
  int n = 0;
  n += snprintf(line + n, sizeof line - (size_t)n, "sumi: ");
  if (P.nframes > 1) n += snprintf(line + n, sizeof line - (size_t)n, "frame %d of %d, ", P.frame, P.nframes);
  double eta = seconds_left(t);
  snprintf(line + n, sizeof line - (size_t)n, "%d%% of tiles, %s elapsed%s%s%s",
           P.total > 0 ? (int)(100.0 * P.done / P.total) : 0, clock_text(t - P.start, el, sizeof el),
           eta >= 0 ? ", ~" : "", eta >= 0 ? clock_text(eta, left, sizeof left) : "", eta >= 0 ? " left" : "");
  fprintf(stderr, "\r%s\033[K", line);
  fflush(stderr);
  P.shown = 1;
  P.drawn = t;
}

static void on_tiles(void *ctx, int done, int total) {
  (void)ctx;
  if (pthread_mutex_trylock(&P.lock) != 0) return;   /* another worker is drawing */
  if (done > P.done || total != P.total) P.done = done, P.total = total;
  double t = now();
  if (t - P.start >= PROGRESS_DELAY && (t - P.drawn >= PROGRESS_PERIOD || done == total)) draw(t);
  pthread_mutex_unlock(&P.lock);
}

static const RenderProgress hook = {NULL, on_tiles};

void progress_begin(int nframes, int quiet) {
  P.on = !quiet && isatty(STDERR_FILENO);
  P.nframes = nframes;
  P.frame = 0;
  P.start = P.frame_start = now();
  P.shown = 0;
}

void progress_frame(int k) {
  if (!P.on) return;
  pthread_mutex_lock(&P.lock);
  P.frame = k;
  P.frame_start = now();
  P.done = P.total = 0;
  pthread_mutex_unlock(&P.lock);
}

const RenderProgress *progress_hook(void) { return P.on ? &hook : NULL; }

void progress_clear(void) {
  if (!P.on) return;
  pthread_mutex_lock(&P.lock);
  if (P.shown) fputs("\r\033[K", stderr), fflush(stderr);
  P.shown = 0;
  P.drawn = 0;   /* the next tile draws it again at once */
  pthread_mutex_unlock(&P.lock);
}

void progress_end(void) {
  progress_clear();
  P.on = 0;
}
