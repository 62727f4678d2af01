/*
** The progress line of a render on a terminal: on standard error, redrawn
** in place as the frame's screen tiles are shaded,
**
**   sumi: frame 3 of 12, 45% of tiles, 0:12 elapsed, ~0:31 left
**
** (without "frame k of n" for one image). It shows once a run has taken
** PROGRESS_DELAY seconds, so quick renders show nothing, and it is taken
** off the terminal before any other output (progress_clear: diagnostics
** call it through diag_before_output) and at the end. Off with --quiet,
** and whenever standard error is not a terminal: logs and tests see
** exactly what they saw without it.
*/
#ifndef io_progress_h
#define io_progress_h

#include "../render/render.h"

/* Seconds a run goes before its line shows, and at least between redraws. */
#define PROGRESS_DELAY 0.3
#define PROGRESS_PERIOD 0.1

/* Start a run of nframes frames (1: one image); the line is on when
** standard error is a terminal and quiet is 0. */
void progress_begin(int nframes, int quiet);
/* Frame k (1 .. nframes) of the run begins. */
void progress_frame(int k);
/* The hook for RenderOptions.progress, or NULL when the line is off. */
const RenderProgress *progress_hook(void);
/* Take the line off the terminal (the next tile draws it again). */
void progress_clear(void);
/* The run is over: the line goes for good. */
void progress_end(void);

#endif
