/*
** The SVG writer: object regions traced from an object-id raster, then the
** strokes (see svg.h).
*/
#include "svg.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../base/mem.h"
#include "edgeref.h"
#include "stats.h"

static void hex_color(char out[8], Color c) {
  snprintf(out, 8, "#%02x%02x%02x", image_linear_to_srgb8(c.r), image_linear_to_srgb8(c.g),
           image_linear_to_srgb8(c.b));
}

/* ---- regions -------------------------------------------------------------- */

enum { DIR_E = 1, DIR_S = 2, DIR_W = 4, DIR_N = 8 };

/* One path of the pixel outline of object obj in ids (w x h) within its
** box [x0, x1] x [y0, y1]: every side between a pixel of obj and one that
** is not becomes a directed edge (clockwise on screen), and the edges are
** chained into closed loops; with the even-odd rule any chaining fills the
** same area. */
static void write_region(FILE *f, const int32_t *ids, int w, int h, int obj, int x0, int y0, int x1,
                         int y1, Color fill) {
  int gw = x1 - x0 + 2, gh = y1 - y0 + 2;   /* corners of the box */
  unsigned char *out = xcalloc((size_t)gw * gh, 1);
#define IN(x, y) ((x) >= 0 && (y) >= 0 && (x) < w && (y) < h && ids[(size_t)(y) * w + (x)] == obj)
#define AT(x, y) out[(size_t)((y) - y0) * gw + ((x) - x0)]
  for (int y = y0; y <= y1; y++)
    for (int x = x0; x <= x1; x++) {
      if (!IN(x, y)) continue;
      if (!IN(x, y - 1)) AT(x, y) |= DIR_E;
      if (!IN(x + 1, y)) AT(x + 1, y) |= DIR_S;
      if (!IN(x, y + 1)) AT(x + 1, y + 1) |= DIR_W;
      if (!IN(x - 1, y)) AT(x, y + 1) |= DIR_N;
    }
  char col[8];
  hex_color(col, fill);
  fprintf(f, "<path fill=\"%s\" fill-rule=\"evenodd\" d=\"", col);
  static const int dx[9] = {0, 1, 0, 0, -1, 0, 0, 0, 0}, dy[9] = {0, 0, 1, 0, 0, 0, 0, 0, -1};
  for (int cy = y0; cy <= y1 + 1; cy++)
    for (int cx = x0; cx <= x1 + 1; cx++) {
      if (!AT(cx, cy)) continue;
      int x = cx, y = cy, prev = 0;
      fprintf(f, "M%d %d", x, y);
      do {
        unsigned char *b = &AT(x, y);
        int d = *b & prev ? prev : *b & -*b;   /* keep going straight where possible */
        *b &= (unsigned char)~d;
        if (d != prev && prev) fprintf(f, prev & (DIR_E | DIR_W) ? "H%d" : "V%d", prev & (DIR_E | DIR_W) ? x : y);
        x += dx[d];
        y += dy[d];
        prev = d;
      } while (x != cx || y != cy);
      fprintf(f, "Z");
    }
  fprintf(f, "\"/>\n");
#undef IN
#undef AT
  free(out);
}

static void write_regions(FILE *f, const LineObject *objs, int nobj, const Camera *cam, int threads) {
  if (nobj == 0) return;
  LineObject *occ = xmalloc((size_t)nobj * sizeof *occ);   /* projection only, no edges */
  for (int i = 0; i < nobj; i++) { occ[i] = objs[i]; occ[i].lines = NULL; }
  LineEdges ed;
  line_edges_build(&ed, occ, nobj, cam);
  int w = cam->width, h = cam->height;
  int32_t *ids = line_object_ids(&ed, occ, w, h, threads);
  int *box = xmalloc((size_t)nobj * 4 * sizeof *box);
  for (int i = 0; i < nobj; i++) { box[4 * i] = w; box[4 * i + 1] = h; box[4 * i + 2] = -1; box[4 * i + 3] = -1; }
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      int o = ids[(size_t)y * w + x];
      if (o < 0) continue;
      int *b = &box[4 * o];
      if (x < b[0]) b[0] = x;
      if (y < b[1]) b[1] = y;
      if (x > b[2]) b[2] = x;
      if (y > b[3]) b[3] = y;
    }
  for (int i = 0; i < nobj; i++)
    if (box[4 * i + 2] >= 0)
      write_region(f, ids, w, h, i, box[4 * i], box[4 * i + 1], box[4 * i + 2], box[4 * i + 3], objs[i].fill);
  free(box);
  free(ids);
  line_edges_free(&ed);
  free(occ);
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

int svg_write(const char *path, const LineObject *objs, int nobj, const Camera *cam, Color background,
              const StrokeList *sl, int threads, char *err, size_t errlen) {
  size_t n = strlen(path) + 8;
  char *tmp = xmalloc(n);
  snprintf(tmp, n, "%s.tmp", path);
  FILE *f = fopen(tmp, "w");
  if (!f) {
    snprintf(err, errlen, "%s: cannot write: %s", path, strerror(errno));
    free(tmp);
    return 0;
  }
  fprintf(f, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
  fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\">\n",
          cam->width, cam->height, cam->width, cam->height);
  if (background.a > 0) {
    char col[8];
    hex_color(col, background);
    fprintf(f, "<rect width=\"%d\" height=\"%d\" fill=\"%s\"", cam->width, cam->height, col);
    if (background.a < 1) fprintf(f, " fill-opacity=\"%.3f\"", background.a);
    fprintf(f, "/>\n");
  }
  fprintf(f, "<g id=\"regions\">\n");
  write_regions(f, objs, nobj, cam, threads);
  fprintf(f, "</g>\n<g id=\"strokes\">\n");
  for (int i = 0; sl && i < sl->n; i++) write_stroke(f, &sl->s[i]);
  fprintf(f, "</g>\n</svg>\n");
  int bad = ferror(f);
  if (fclose(f) != 0) bad = 1;
  if (bad || rename(tmp, path) != 0) {
    snprintf(err, errlen, "%s: cannot write: %s", path, strerror(errno));
    remove(tmp);
    free(tmp);
    return 0;
  }
  free(tmp);
  return 1;
}

int svg_write_frame(const char *path, const RenderFrame *f, const StrokeList *sl, int threads,
                    char *err, size_t errlen) {
  LineObject *objs;
  int n = line_frame_objects(f, &objs);
  int ok = svg_write(path, objs, n, &f->camera, f->background, sl, threads, err, errlen);
  free(objs);
  return ok;
}

int svg_render_scene(const Scene *s, const RenderOptions *o, const char *path) {
  RenderFrame f;
  if (!render_prepare(s, o, &f)) {
    render_frame_free(&f);
    return 1;
  }
  int threads = o->threads;
  if (threads < 1) {
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    threads = n > 0 ? (int)n : 1;
  }
  StrokeList *sl = NULL;
  int status = 1;
  if (line_render_frame(&f, threads, NULL, &sl, NULL)) {
    char err[512];
    double t0 = stats_now();
    status = svg_write_frame(path, &f, sl, threads, err, sizeof err) ? 0 : 1;
    if (status) fprintf(stderr, "sumi: %s\n", err);
    stats_record("write", stats_now() - t0);
  }
  stroke_list_free(sl);
  render_frame_free(&f);
  return status;
}
