/*
** The SVG writer (see svg.h): the document, the strokes, and the frame the
** regions (svg_trace.h) and the origami (svg_origami.h) are drawn from.
*/
#include "svg.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../base/mem.h"
#include "../io/tempfile.h"
#include "stats.h"
#include "stroke.h"
#include "svg_origami.h"
#include "svg_trace.h"

static void hex_color(char out[8], Color c) {
  snprintf(out, 8, "#%02x%02x%02x", image_linear_to_srgb8(c.r), image_linear_to_srgb8(c.g),
           image_linear_to_srgb8(c.b));
}

/* ---- strokes -------------------------------------------------------------- */

static void write_stroke(FILE *f, const Stroke *st) {
  char col[8];
  hex_color(col, st->color);
  if (st->kind == STROKE_PLAIN) {
    fprintf(f, "<path fill=\"none\" stroke=\"%s\" stroke-width=\"%.2f\" stroke-linecap=\"round\" "
            "stroke-linejoin=\"round\"", col, st->width);
    if (st->opacity < 1) fprintf(f, " stroke-opacity=\"%.3f\"", st->opacity);
    fprintf(f, " d=\"");
    for (int i = 0; i < st->npts; i++)
      fprintf(f, "%s%.2f %.2f", i ? " L" : "M", st->pts[2 * i], st->pts[2 * i + 1]);
  } else {
    fprintf(f, "<path fill=\"%s\"", col);
    if (st->opacity < 1) fprintf(f, " fill-opacity=\"%.3f\"", st->opacity);
    fprintf(f, " d=\"");
    for (int i = 0; i < st->npts; i++)
      fprintf(f, "%s%.2f %.2f", i ? " L" : "M", st->left[2 * i], st->left[2 * i + 1]);
    for (int i = st->npts - 1; i >= 0; i--) fprintf(f, " L%.2f %.2f", st->right[2 * i], st->right[2 * i + 1]);
  }
  fprintf(f, "%s\"/>\n", st->closed || st->kind != STROKE_PLAIN ? " Z" : "");
}

/* ---- the document --------------------------------------------------------- */

/* Background pixels this close to origami are its margin (svg_trace.h):
** its Sobel lines reach off the paper, and its faces' strokes draw them. */
#define ORIGAMI_MARGIN 3

static void origami_margin(SvgFrame *fr) {
  size_t np = (size_t)fr->w * fr->h;
  unsigned char *near = xcalloc(np, 1);
  int r = ORIGAMI_MARGIN;
  for (size_t p = 0; p < np; p++) {
    if (fr->owner[p] != SVG_OWNER_ORIGAMI) continue;
    int x = (int)(p % fr->w), y = (int)(p / fr->w);
    for (int yy = y - r < 0 ? 0 : y - r; yy <= y + r && yy < fr->h; yy++)
      for (int xx = x - r < 0 ? 0 : x - r; xx <= x + r && xx < fr->w; xx++) near[(size_t)yy * fr->w + xx] = 1;
  }
  for (size_t p = 0; p < np; p++)
    if (near[p] && fr->owner[p] == -1) fr->owner[p] = SVG_OWNER_MARGIN;
  free(near);
}

/* The frame as the tracer sees it: out's colour as sRGB codes with alpha,
** and each output pixel's owner and depth from the sample at its centre. */
static SvgFrame frame_of(const Image *out, const GBuffer *g, int nobjects) {
  SvgFrame fr = {out->width, out->height, NULL, NULL, NULL, nobjects, g->samples};
  size_t np = (size_t)fr.w * fr.h;
  int nc = out->channels, N = g->samples;
  uint8_t *codes = xmalloc(np * (size_t)nc), *rgba = xmalloc(np * 4);
  image_to_srgb8(out, codes);
  fr.owner = xmalloc(np * sizeof *fr.owner);
  fr.depth = xmalloc(np * sizeof *fr.depth);
  for (size_t p = 0; p < np; p++) {
    for (int c = 0; c < 3; c++) rgba[p * 4 + c] = codes[p * nc + (nc >= 3 ? c : 0)];
    rgba[p * 4 + 3] = nc == 4 ? codes[p * nc + 3] : 255;
    size_t x = p % fr.w, y = p / fr.w;
    size_t q = (y * N + N / 2) * (size_t)g->width + x * N + N / 2;
    int o = g->object[q];
    fr.owner[p] = o == nobjects ? SVG_OWNER_ORIGAMI : o;
    fr.depth[p] = g->depth[q];
  }
  fr.rgba = rgba;
  free(codes);
  origami_margin(&fr);
  return fr;
}

static void frame_free(SvgFrame *fr) {
  free((void *)fr->rgba);
  free(fr->owner);
  free(fr->depth);
}

/* Write the document for frame fr of s (camera world_to_clip, strokes sl)
** into the open file f. Returns 0 when an origami block failed. */
static int write_document(FILE *f, const SvgFrame *fr, const Scene *s, const Mat4 *world_to_clip,
                          const StrokeList *sl) {
  fprintf(f, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
  fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\">\n",
          fr->w, fr->h, fr->w, fr->h);
  Color bg = s->output.background;
  if (bg.a > 0) {
    char col[8];
    hex_color(col, bg);
    fprintf(f, "<rect width=\"%d\" height=\"%d\" fill=\"%s\"", fr->w, fr->h, col);
    if (bg.a < 1) fprintf(f, " fill-opacity=\"%.3f\"", bg.a);
    fprintf(f, "/>\n");
  }
  fprintf(f, "<g id=\"regions\">\n");
  svg_write_regions(f, fr);
  fprintf(f, "</g>\n");
  int ok = svg_write_origami(f, fr, s, world_to_clip);
  fprintf(f, "<g id=\"strokes\">\n");
  for (int i = 0; sl && i < sl->n; i++) write_stroke(f, &sl->s[i]);
  fprintf(f, "</g>\n</svg>\n");
  return ok;
}

int svg_render_scene(const Scene *s, const RenderOptions *o, const char *path) {
  RenderOptions ro = *o;
  StrokeList *sl = NULL;
  ro.strokes = &sl;
  ro.out8 = 0;
  ro.rows = NULL;
  ro.aliased = 1;   /* regions are traced from the colours: hard edges, the SVG renderer smooths them */
  Image *img = NULL;
  GBuffer *g = NULL;
  if (render_scene(s, &ro, &img, &g) != 0) return 1;
  double t0 = stats_now();
  SvgFrame fr = frame_of(img, g, s->nobjects);
  size_t n = strlen(path) + 32;
  char *tmp = xmalloc(n);
  snprintf(tmp, n, "%s.tmp-%ld", path, (long)getpid());
  FILE *f = fopen(tmp, "w");
  int status = 1;
  if (f) {
    tempfile_add(tmp);   /* removed if a signal ends the program first */
    int ok = write_document(f, &fr, s, &g->camera.world_to_clip, sl);
    int bad = ferror(f);
    if (fclose(f) != 0) bad = 1;
    if (ok && !bad && rename(tmp, path) == 0) status = 0, tempfile_forget(tmp);
    else if (ok) fprintf(stderr, "sumi: cannot write '%s': %s\n", path, strerror(errno));
    if (status) tempfile_discard(tmp);
  } else {
    fprintf(stderr, "sumi: cannot write '%s': %s\n", path, strerror(errno));
  }
  stats_record("write", stats_now() - t0);
  free(tmp);
  frame_free(&fr);
  stroke_list_free(sl);
  gbuf_destroy(g);
  image_destroy(img);
  return status;
}
