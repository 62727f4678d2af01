/*
** The frames of an animation run (frames.h).
*/
#include "frames.h"

#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mem.h"

/* The decimal number at *p (moved past it), or -1 when there is none; a
** number past FRAMES_MAX is FRAMES_MAX + 1. */
static long frame_number(const char **p) {
  if (!isdigit((unsigned char)**p)) return -1;
  char *end;
  errno = 0;
  long n = strtol(*p, &end, 10);
  *p = end;
  return errno || n > FRAMES_MAX ? FRAMES_MAX + 1 : n;
}

/* frames = item { "," item }; item = N [ ":" N [ ":" STEP ] ]
** Marks the frames of text in on[] (FRAMES_MAX + 1 entries), and the
** lowest and highest numbers it names in *lo, *hi. */
static int parse_list(const char *opt, const char *text, unsigned char *on, int *lo, int *hi, char *err,
                      size_t errlen) {
  const char *p = text;
  *lo = FRAMES_MAX + 1, *hi = -1;
  for (;;) {
    long a = frame_number(&p), b = a, step = 1;
    if (a >= 0 && *p == ':') p++, b = frame_number(&p);
    if (b >= 0 && *p == ':') p++, step = frame_number(&p);
    if (a < 0 || b < 0 || step < 0 || (*p && *p != ',')) {
      snprintf(err, errlen, "%s takes A:B, A:B:STEP or a list of them (e.g. 0:119, 0:119:10 or 1,5,9:12), "
               "not `%s`", opt, text);
      return 0;
    }
    if (a > FRAMES_MAX || b > FRAMES_MAX) {
      snprintf(err, errlen, "%s %s: frame numbers run from 0 to %d", opt, text, FRAMES_MAX);
      return 0;
    }
    if (b < a) {
      snprintf(err, errlen, "%s %s: %ld:%ld runs backwards; a range goes from its first frame up to its last, as %ld:%ld does",
               opt, text, a, b, b, a);
      return 0;
    }
    if (step == 0) {
      snprintf(err, errlen, "%s %s: a step is 1 or more, not 0", opt, text);
      return 0;
    }
    for (long f = a; f <= b; f += step) on[f] = 1;
    if (a < *lo) *lo = (int)a;
    if (b > *hi) *hi = (int)b;
    if (!*p) return 1;
    p++;   /* skip ',' */
  }
}

int frames_parse(const char *spec, const char *only, FrameSet *fs, char *err, size_t errlen) {
  memset(fs, 0, sizeof *fs);
  unsigned char *on = xcalloc(FRAMES_MAX + 1, 1), *pick = NULL;
  int ok = parse_list("--frames", spec, on, &fs->first, &fs->last, err, errlen);
  if (ok && only) {
    int lo, hi;
    pick = xcalloc(FRAMES_MAX + 1, 1);
    ok = parse_list("--only", only, pick, &lo, &hi, err, errlen);
    for (int f = lo; ok && f <= hi; f++) {
      if (pick[f] && !on[f]) {
        snprintf(err, errlen, "--only %s: frame %d is not one of --frames %s", only, f, spec);
        ok = 0;
      }
    }
  }
  if (ok) {
    const unsigned char *use = pick ? pick : on;
    fs->frames = xmalloc(((size_t)fs->last - fs->first + 1) * sizeof *fs->frames);
    for (int f = fs->first; f <= fs->last; f++)
      if (use[f]) fs->frames[fs->count++] = f;
  }
  free(on);
  free(pick);
  return ok;
}

void frames_free(FrameSet *fs) {
  free(fs->frames);
  memset(fs, 0, sizeof *fs);
}

void frames_path(char *buf, size_t n, const char *pattern, int frame) {
  const char *hash = strchr(pattern, '#');
  if (hash) {
    size_t run = strspn(hash, "#");
    snprintf(buf, n, "%.*s%0*d%s", (int)(hash - pattern), pattern, (int)run, frame, hash + run);
    return;
  }
  const char *dot = strrchr(pattern, '.');
  const char *slash = strrchr(pattern, '/');
  if (!dot || (slash && dot < slash)) dot = pattern + strlen(pattern);
  snprintf(buf, n, "%.*s_%04d%s", (int)(dot - pattern), pattern, frame, dot);
}
