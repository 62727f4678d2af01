/*
** Tiles (tile.h): the split, the window each tile's stages draw, and the
** two ways a tile is rendered: band by band into its file, or its window
** at once and the tile cut out of it.
*/
#include "tile.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"
#include "canvas.h"
#include "lines.h"
#include "origami.h"
#include "stats.h"
#include "stroke.h"

int tile_rect(const TileSpec *t, int w, int h, RenderWindow *r, char *err, size_t errlen) {
  return tile_split_rect(t, w, h, &r->x0, &r->y0, &r->x1, &r->y1, err, errlen);
}

/* ---- the window ---------------------------------------------------------------- */

/* w widened to whole screen tiles across (the tile pass shades a screen
** tile's rows as one, and a row's runs must be the whole frame's). */
static RenderWindow tile_columns(RenderWindow w, int width) {
  w.x0 = w.x0 / RENDER_TILE * RENDER_TILE;
  w.x1 = (w.x1 + RENDER_TILE - 1) / RENDER_TILE * RENDER_TILE;
  if (w.x1 > width) w.x1 = width;
  return w;
}

/* The window the stages draw for tile pixels want: the margin the origami
** and the canvas need around them, within the frame, in whole screen
** tiles across. */
static RenderWindow work_window(const Scene *s, const RenderFrame *f, int canvas, RenderWindow want) {
  int N = f->samples, m = 0;
  if (s->norigami > 0) m = (origami_margin(s, N) + N - 1) / N;
  if (canvas) {
    int c = canvas_margin(f);
    m = c > m ? c : m;
  }
  RenderWindow w = {want.x0 - m, want.y0 - m, want.x1 + m, want.y1 + m};
  if (w.x0 < 0) w.x0 = 0;
  if (w.y0 < 0) w.y0 = 0;
  if (w.x1 > f->width) w.x1 = f->width;
  if (w.y1 > f->height) w.y1 = f->height;
  return tile_columns(w, f->width);
}

/* ---- cutting a tile out ------------------------------------------------------- */

/* The part of img (whose first pixel is frame pixel (ox, oy)) under frame
** rectangle r: a new image. */
static Image *crop_image(const Image *img, int ox, int oy, RenderWindow r) {
  int w = r.x1 - r.x0, h = r.y1 - r.y0, nc = img->channels;
  Image *out = img->data8 ? image_create8_unset(w, h, nc) : image_create(w, h, nc);
  size_t esize = img->data8 ? 1 : sizeof(float), row = (size_t)w * nc * esize;
  const char *src = img->data8 ? (const char *)img->data8 : (const char *)img->data;
  char *dst = img->data8 ? (char *)out->data8 : (char *)out->data;
  for (int y = 0; y < h; y++)
    memcpy(dst + (size_t)y * row,
           src + (((size_t)(y + r.y0 - oy) * img->width + (size_t)(r.x0 - ox)) * nc) * esize, row);
  return out;
}

/* Copy the rows of plane src (sw samples wide, elem bytes a sample) under
** sample rectangle [x0, x0 + w) x [y0, y0 + h) into a new plane. */
static void *crop_plane(const void *src, size_t elem, int sw, int x0, int y0, int w, int h) {
  if (!src) return NULL;
  char *dst = xmalloc((size_t)w * h * elem + 1);
  for (int y = 0; y < h; y++)
    memcpy(dst + (size_t)y * w * elem, (const char *)src + ((size_t)(y + y0) * sw + x0) * elem, (size_t)w * elem);
  return dst;
}

/* The samples of g (a window whose first pixel is frame pixel (ox, oy))
** under frame rectangle r: a new G-buffer. */
static GBuffer *crop_gbuf(const GBuffer *g, int ox, int oy, RenderWindow r) {
  int N = g->samples, x0 = (r.x0 - ox) * N, y0 = (r.y0 - oy) * N, w = (r.x1 - r.x0) * N, h = (r.y1 - r.y0) * N;
  GBuffer *c = xcalloc(1, sizeof *c);
  c->width = w;
  c->height = h;
  c->samples = N;
  c->camera = g->camera;
  c->depth = crop_plane(g->depth, sizeof *g->depth, g->width, x0, y0, w, h);
  c->object = crop_plane(g->object, sizeof *g->object, g->width, x0, y0, w, h);
  c->face = crop_plane(g->face, sizeof *g->face, g->width, x0, y0, w, h);
  c->bary = crop_plane(g->bary, sizeof *g->bary, g->width, x0, y0, w, h);
  c->normal = crop_plane(g->normal, sizeof *g->normal, g->width, x0, y0, w, h);
  c->uv = crop_plane(g->uv, sizeof *g->uv, g->width, x0, y0, w, h);
  c->position = crop_plane(g->position, sizeof *g->position, g->width, x0, y0, w, h);
  return c;
}

/* Render f's work window for tile pixels want, then cut them out. */
static int render_window(const Scene *s, const RenderOptions *o, RenderFrame *f, int canvas, RenderWindow want,
                         Image **out, GBuffer **gbuf_out) {
  f->win = work_window(s, f, canvas, want);
  RenderOptions ro = *o;
  ro.rows = NULL;   /* the window is not the file's rows: written once cut */
  if (!render_stages(s, &ro, f, canvas, out, gbuf_out)) return 0;
  RenderWindow w = f->win;
  if (w.x0 == want.x0 && w.y0 == want.y0 && w.x1 == want.x1 && w.y1 == want.y1) return 1;
  double t0 = stats_now();
  Image *cut = crop_image(*out, w.x0, w.y0, want);
  image_destroy(*out);
  *out = cut;
  if (gbuf_out && *gbuf_out) {
    GBuffer *g = crop_gbuf(*gbuf_out, w.x0, w.y0, want);
    gbuf_destroy(*gbuf_out);
    *gbuf_out = g;
  }
  stats_record("tile crop", stats_now() - t0);
  return 1;
}

/* ---- band by band ---------------------------------------------------------- */

/* Draw tile pixels want of f (no origami, no canvas; 8-bit) and hand them
** to o->rows TILE_BAND_ROWS rows at a time, each band shaded, stroked with
** the whole view's strokes (sl, or NULL) and cut to the tile's columns. */
static void render_bands(const RenderOptions *o, RenderFrame *f, const StrokeList *sl, int nc, RenderWindow want) {
  f->win = tile_columns(want, f->width);
  int ww = f->win.x1 - f->win.x0, tw = want.x1 - want.x0;
  RenderPass *p = render_pass_begin(f, o);
  Image *band = image_create8_unset(ww, TILE_BAND_ROWS, nc);
  Image *cut = tw < ww ? image_create8_unset(tw, TILE_BAND_ROWS, nc) : NULL;
  for (int y0 = want.y0, y1; y0 < want.y1; y0 = y1) {
    y1 = (y0 / TILE_BAND_ROWS + 1) * TILE_BAND_ROWS;   /* bands on the frame's grid of rows */
    if (y1 > want.y1) y1 = want.y1;
    Image b = {ww, y1 - y0, nc, NULL, band->data8};
    render_pass_run(p, y0, y1, NULL, &b, NULL);
    if (sl) {
      double t0 = stats_now();
      stroke_render_at(sl, &b, f->win.x0, y0, render_thread_count(o));
      stats_record("lines draw", stats_now() - t0);
    }
    Image c = {tw, y1 - y0, nc, NULL, cut ? cut->data8 : band->data8};
    for (int y = 0; cut && y < y1 - y0; y++)
      memcpy(c.data8 + (size_t)y * tw * nc, b.data8 + ((size_t)y * ww + (size_t)(want.x0 - f->win.x0)) * nc,
             (size_t)tw * nc);
    double t1 = stats_now();
    o->rows->rows(o->rows->ctx, &c, y0 - want.y0, y1 - want.y0);
    stats_record("write", stats_now() - t1);
  }
  image_destroy(cut);
  image_destroy(band);
  render_pass_end(p);
}

/* ---- the entry point --------------------------------------------------------- */

int tile_render(const Scene *s, const RenderOptions *o, RenderFrame *f, int canvas, Image **out,
                GBuffer **gbuf_out) {
  RenderWindow want = o->window;
  if (want.x0 < 0) want.x0 = 0;
  if (want.y0 < 0) want.y0 = 0;
  if (want.x1 > f->width) want.x1 = f->width;
  if (want.y1 > f->height) want.y1 = f->height;
  int nc = f->background.a >= 1 ? 3 : 4;
  int banded = o->rows && o->out8 && s->norigami == 0 && !canvas && !gbuf_out && !o->strokes;
  if (!banded) return render_window(s, o, f, canvas, want, out, gbuf_out);
  /* the strokes of the whole view first: each band draws its part of them */
  StrokeList *sl = NULL;
  if (line_frame_draws(f) && !line_render_frame(f, render_thread_count(o), NULL, &sl, NULL)) return 0;
  Image *img = xcalloc(1, sizeof *img);   /* the tile's size; its pixels go to the file */
  img->width = want.x1 - want.x0;
  img->height = want.y1 - want.y0;
  img->channels = nc;
  if (!o->rows->begin(o->rows->ctx, img)) {   /* the file wants the image whole */
    image_destroy(img);
    stroke_list_free(sl);
    return render_window(s, o, f, canvas, want, out, gbuf_out);
  }
  render_bands(o, f, sl, nc, want);
  stroke_list_free(sl);
  *out = img;
  return 1;
}
