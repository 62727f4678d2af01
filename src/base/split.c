/*
** Splitting a frame into tiles (split.h).
*/
#include "split.h"

#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The decimal number at *p, which must end at a character of stop or at
** the end of the text (*p then moves past it); -1 when there is none. */
static long tile_number(const char **p, const char *stop) {
  if (!isdigit((unsigned char)**p)) return -1;
  char *end;
  errno = 0;
  long n = strtol(*p, &end, 10);
  if (errno || n > 1000000000L || (*end && !strchr(stop, *end))) return -1;
  *p = end;
  return n;
}

int tile_parse(const char *spec, TileSpec *t, char *err, size_t errlen) {
  const char *p = spec;
  long i = tile_number(&p, "/"), c = 1, r = -1;
  if (i >= 0 && *p == '/') {
    p++;
    r = tile_number(&p, "x");
    if (r >= 0 && *p == 'x') {
      p++;
      c = r;
      r = tile_number(&p, "");
    }
  }
  if (i < 0 || r < 0 || *p) {
    snprintf(err, errlen, "--tile takes I/N (tile I of N rows of tiles) or I/CxR (of C columns and R rows), "
             "not `%s`", spec);
    return 0;
  }
  if (c < 1 || r < 1 || c * r > SPLIT_MAX_TILES) {
    snprintf(err, errlen, "--tile %s: a split needs 1 to %d tiles", spec, SPLIT_MAX_TILES);
    return 0;
  }
  if (i < 1 || i > c * r) {
    snprintf(err, errlen, "--tile %s: there is no tile %ld of %ld (tiles are numbered 1 to %ld)", spec, i,
             c * r, c * r);
    return 0;
  }
  t->index = (int)i;
  t->cols = (int)c;
  t->rows = (int)r;
  return 1;
}

void tile_format(const TileSpec *t, char *buf, size_t n) {
  if (t->cols == 1) snprintf(buf, n, "%d/%d", t->index, t->rows);
  else snprintf(buf, n, "%d/%dx%d", t->index, t->cols, t->rows);
}

int tile_split_rect(const TileSpec *t, int w, int h, int *x0, int *y0, int *x1, int *y1, char *err,
                    size_t errlen) {
  char name[64];
  tile_format(t, name, sizeof name);
  if (w < t->cols || h < t->rows) {
    int cols = w < t->cols;
    snprintf(err, errlen, "--tile %s: the frame is %d x %d pixels: %d %s cannot make %d %s of tiles", name, w, h,
             cols ? w : h, cols ? "columns" : "rows", cols ? t->cols : t->rows, cols ? "columns" : "rows");
    return 0;
  }
  int c = (t->index - 1) % t->cols, k = (t->index - 1) / t->cols;
  *x0 = (int)((long long)c * w / t->cols);
  *x1 = (int)((long long)(c + 1) * w / t->cols);
  *y0 = (int)((long long)k * h / t->rows);
  *y1 = (int)((long long)(k + 1) * h / t->rows);
  return 1;
}

