/*
** The frames of an animation run (`sumi render --frames SPEC [--only
** LIST]`), and the file name each frame goes to.
**
**   frames = item { "," item }
**   item   = N [ ":" N [ ":" STEP ] ]       N, A:B (A..B), A:B:STEP (A, A+STEP, ... <= B)
**
** The animation runs from the lowest frame SPEC names to the highest (a
** range's end counts even when its step passes it by): the clock is 0 at
** the one and 1 at the other. --only LIST (the same grammar) renders some
** of SPEC's frames with the animation's clock, as a job of a scheduler's
** array renders its share of the run. Frames are rendered in ascending
** order, each once.
*/
#ifndef base_frames_h
#define base_frames_h

#include <stddef.h>

/* Highest frame number: numbers run 0..FRAMES_MAX, so a run holds at most
** FRAMES_MAX + 1 frames (their list is 4 MB at most). */
#define FRAMES_MAX 1000000

typedef struct FrameSet {
  int first, last;            /* the animation: the clock's 0 and 1 */
  int *frames;                /* the frames to render, ascending (malloc'ed) */
  int count;
} FrameSet;

/* Parse --frames spec and, when only is not NULL, --only only into *fs
** (free with frames_free): 1, or 0 with the reason in err (a spec that is
** not the grammar above, a range that runs backwards, a step of 0, a
** number past FRAMES_MAX, a frame of only that spec does not have). The
** reason names the option. */
int frames_parse(const char *spec, const char *only, FrameSet *fs, char *err, size_t errlen);
void frames_free(FrameSet *fs);

/* The name frame's image goes to, into buf (n bytes): a run of '#' in
** pattern becomes the frame number padded to its length (as Blender
** does), else "_NNNN" goes before the extension. */
void frames_path(char *buf, size_t n, const char *pattern, int frame);

#endif
