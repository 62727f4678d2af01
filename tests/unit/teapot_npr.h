/*
** Test helper: the Utah teapot read straight from stdlib/teapot.npr (the
** numbers between `let TEAPOT_POINTS` and `let TEAPOT_PATCHES`, then those up
** to `fn teapot`), so the geometry tests need no evaluator and no data from
** outside the repository. Unit tests run from the repository root.
*/
#ifndef tests_teapot_npr_h
#define tests_teapot_npr_h

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../src/scene/scene.h"

#define TEAPOT_NPR "stdlib/teapot.npr"

/* The numbers in s[0..n), comments (// to end of line) skipped, into out
** (at most max); returns how many. */
static inline int teapot_numbers(const char *s, size_t n, double *out, int max) {
  int count = 0;
  for (size_t i = 0; i < n && count < max;) {
    if (s[i] == '/' && i + 1 < n && s[i + 1] == '/') {
      while (i < n && s[i] != '\n') i++;
    } else if ((s[i] >= '0' && s[i] <= '9') || s[i] == '-' || s[i] == '.') {
      char *end;
      out[count++] = strtod(s + i, &end);
      i = (size_t)(end - s) > i ? (size_t)(end - s) : i + 1;
    } else {
      i++;
    }
  }
  return count;
}

/* Fills *g with the 32 teapot patches (patches malloc'd: free g->patches);
** returns 0 when the file is missing or malformed. */
static inline int teapot_load(SceneGeometry *g) {
  memset(g, 0, sizeof *g);
  FILE *f = fopen(TEAPOT_NPR, "rb");
  if (!f) return 0;
  static char text[1 << 16];
  size_t len = fread(text, 1, sizeof text - 1, f);
  fclose(f);
  text[len] = 0;
  const char *pts = strstr(text, "let TEAPOT_POINTS"), *pat = strstr(text, "let TEAPOT_PATCHES");
  const char *fn = strstr(text, "fn teapot");
  if (!pts || !pat || !fn || pat < pts || fn < pat) return 0;
  pts += strlen("let TEAPOT_POINTS");
  pat += strlen("let TEAPOT_PATCHES");
  static double v[306 * 3], idx[32 * 16];
  if (teapot_numbers(pts, (size_t)(pat - pts), v, 306 * 3) != 306 * 3) return 0;
  if (teapot_numbers(pat, (size_t)(fn - pat), idx, 32 * 16) != 32 * 16) return 0;
  g->kind = GEOM_PATCHES;
  g->npatches = 32;
  g->patches = calloc(32, sizeof *g->patches);
  for (int p = 0; p < 32; p++)
    for (int k = 0; k < 16; k++) {
      int i = (int)idx[16 * p + k];
      if (i < 0 || i >= 306) { free(g->patches); return 0; }
      g->patches[p].cp[k] = v3(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
    }
  return 1;
}

/* A copy of g holding only patches first..last (inclusive) of it, appended
** to *out (out->patches realloc'd). */
static inline void teapot_take(SceneGeometry *out, const SceneGeometry *g, int first, int last) {
  out->kind = GEOM_PATCHES;
  out->patches = realloc(out->patches, (size_t)(out->npatches + last - first + 1) * sizeof *out->patches);
  for (int p = first; p <= last; p++) out->patches[out->npatches++] = g->patches[p];
}

#endif
