/*
** The canvas (canvas.h): paper, ink, and the tile pass's image over them.
**
** Bottom-up: the frame's ink styles, the ink of each pixel from the tile
** pass's samples (handed over tile by tile as they are drawn, or read from
** a whole G-buffer when one is kept anyway), the stages (diffusion, box
** filter), and the composite. The
** work is kept to where it matters: the diffusion starts from the ink's
** bounding box, the box filter runs over that box grown by the ink's reach,
** and the composite reads the tile pass's image only when something other
** than ink was drawn in it.
*/
#include "canvas.h"

#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"
#include "../lang/diag.h"
#include "display.h"
#include "ink.h"
#include "paper.h"
#include "raster.h"
#include "stats.h"

/* ---- the frame's ink styles ---------------------------------------------------- */

/* The ink styles of a frame as the canvas numbers them. */
typedef struct InkSet {
  int n;
  InkStyle *styles;      /* copies of the RenderStyles' ink */
  int *of_object;        /* per object: its style's index here, or -1 (not ink) */
  int uniform;           /* every ink style has the same colour */
  int box;               /* the frame's box side: the largest a filtered style asks for */
  int reach;             /* the most pixels ink can run: the largest bound on passes */
} InkSet;

static void ink_set(const RenderFrame *f, InkSet *set) {
  memset(set, 0, sizeof *set);
  set->styles = xcalloc((size_t)f->nstyles + 1, sizeof *set->styles);
  int *of_style = xmalloc(((size_t)f->nstyles + 1) * sizeof *of_style);
  set->uniform = 1;
  set->box = 1;
  for (int i = 0; i < f->nstyles; i++) {
    of_style[i] = -1;
    const InkStyle *k = f->styles[i].ink;
    if (!k || set->n >= INK_NO_STYLE) continue;
    of_style[i] = set->n;
    set->styles[set->n] = *k;
    if (set->n > 0 && memcmp(k->color, set->styles[0].color, sizeof k->color) != 0) set->uniform = 0;
    if (k->stage == INK_STAGE_FILTERED && k->box > set->box) set->box = k->box;
    if (k->stage >= INK_STAGE_DIFFUSED && k->passes > set->reach) set->reach = k->passes;
    set->n++;
  }
  set->of_object = xmalloc(((size_t)f->nobjects + 1) * sizeof *set->of_object);
  for (int i = 0; i < f->nobjects; i++)
    set->of_object[i] = f->objects[i].vink ? of_style[f->objects[i].style - f->styles] : -1;
  free(of_style);
}

static void ink_set_free(InkSet *set) {
  free(set->styles);
  free(set->of_object);
}

int canvas_margin(const RenderFrame *f) {
  int passes = 0, box = 0;
  for (int i = 0; i < f->nstyles; i++) {
    const InkStyle *k = f->styles[i].ink;
    if (!k) continue;
    if (k->stage >= INK_STAGE_DIFFUSED && k->passes > passes) passes = k->passes;
    if (k->stage == INK_STAGE_FILTERED && k->box > box) box = k->box;
  }
  /* a pass moves ink one pixel; the box reads side / 2 pixels around */
  return (passes < INK_MAX_PASSES ? passes : INK_MAX_PASSES) + box / 2 + 1;
}

int canvas_wanted(const Scene *s, const RenderFrame *f) {
  if (s->output.sheet.texture || s->output.nstops >= 2 || s->output.backdrop) return 1;
  for (int i = 0; i < f->nobjects; i++)
    if (f->objects[i].style->ink) return 1;
  return 0;
}

int canvas_reads_layer(const Scene *s, const RenderFrame *f) {
  if (s->norigami > 0) return 1;
  for (int i = 0; i < f->nobjects; i++)
    if (!f->objects[i].style->ink) return 1;   /* others drew */
  return 0;
}

/* ---- the ink of each pixel -------------------------------------------------------- */

/* Where the canvas holds ink, and whether other objects cover some of it. */
typedef struct InkArea {
  int x0, y0, x1, y1;    /* the ink's bounding box (empty: x0 >= x1) */
  int any_off;           /* some pixel is off the canvas */
} InkArea;

/* The canvas starts as bare paper: only the pixels that are not are
** written, ink pixels and those off the canvas. */

/* Pixel p of style index si takes grey's ink (its quantised tone's, or at
** the Gouraud stage the grey's own) and its level; its water follows from
** them. */
static void put_ink(InkCanvas *c, const InkSet *set, size_t p, int si, float grey, InkArea *a, int x,
                    int y) {
  const InkStyle *k = &set->styles[si];
  int label = ink_label(k, grey);
  c->level[p] = (uint8_t)label;
  if (c->style) c->style[p] = (uint16_t)si;
  c->ink[p] = k->stage == INK_STAGE_GOURAUD ? 255 * (1 - grey) : k->ink[label];
  if (x < a->x0) a->x0 = x;
  if (x >= a->x1) a->x1 = x + 1;
  if (y < a->y0) a->y0 = y;
  if (y >= a->y1) a->y1 = y + 1;
}

/* Pixel p off the canvas (another object shows there). */
static void put_off(InkCanvas *c, size_t p, InkArea *a) {
  c->level[p] = INK_OFF;
  a->any_off = 1;
}

/* Pixels p0..p1-1 of one ink object (style index si), all of triangle
** face: their greys quantised. */
/* face and bary are the samples of pixel p0 on. */
static void ink_run(InkCanvas *c, const InkSet *set, const RenderFrame *f, const float (*bary)[2], int obj,
                    int si, int face, size_t p0, size_t p1) {
  const InkStyle *k = &set->styles[si];
  const RenderObject *o = &f->objects[obj];
  float v[3];
  int plain = shade_ink_corners(f, o, face, v), gouraud = k->stage == INK_STAGE_GOURAUD;
  if (c->style)
    for (size_t p = p0; p < p1; p++) c->style[p] = (uint16_t)si;
  if (plain && !gouraud && k->ntones == 4) {   /* the common case, its tests out of the loop */
    const float l0 = k->levels[0], l1 = k->levels[1], l2 = k->levels[2];
    const float *inks = k->ink;
    for (size_t p = p0; p < p1; p++) {
      float grey = shade_ink_lerp(v, bary[p - p0]);
      int label = 3 - (!(grey < l0) + !(grey < l1) + !(grey < l2));   /* ink_label's */
      c->level[p] = (uint8_t)label;
      c->ink[p] = inks[label];
    }
    return;
  }
  for (size_t p = p0; p < p1; p++) {
    float grey = plain ? shade_ink_lerp(v, bary[p - p0]) : shade_ink_grey(f, o, face, bary[p - p0]);
    int label = ink_label(k, grey);
    c->level[p] = (uint8_t)label;
    c->ink[p] = gouraud ? 255 * (1 - grey) : k->ink[label];
  }
}

/* One sample a pixel: the sample is the pixel. Every pixel of rt's
** rectangle is looked at once: a run of background left bare paper, of
** one triangle of an ink object written from its greys, and a pixel of
** another object off the canvas. */
static void ink_pixels_1(InkCanvas *c, const InkSet *set, const RenderFrame *f, const RastTarget *rt,
                         InkArea *a) {
  int x0 = rt->x0 - f->win.x0, n = rt->x1 - rt->x0;   /* the canvas's columns */
  for (int sy = rt->y0; sy < rt->y1; sy++) {
    int y = sy - f->win.y0;
    size_t i = (size_t)(sy - rt->oy) * rt->stride + (size_t)(rt->x0 - rt->ox);
    const int32_t *obj = rt->object + i, *face = rt->face + i;
    const float(*bary)[2] = (const float(*)[2])rt->bary + i;
    size_t row = (size_t)y * c->width + x0;
    int first = -1, last = -1;   /* the row's ink pixels */
    for (int x = 0, e; x < n; x = e) {
      e = x + 1;
      if (obj[x] < 0) {   /* a run of background: bare paper */
        while (e + 4 <= n && (obj[e] & obj[e + 1] & obj[e + 2] & obj[e + 3]) < 0) e += 4;   /* all four < 0 */
        while (e < n && obj[e] < 0) e++;
        continue;
      }
      int si = obj[x] < f->nobjects ? set->of_object[obj[x]] : -1;   /* else an origami sheet */
      if (si < 0) { put_off(c, row + x, a); continue; }
      while (e < n && obj[e] == obj[x] && face[e] == face[x]) e++;
      ink_run(c, set, f, bary + x, obj[x], si, face[x], row + x, row + e);
      if (first < 0) first = x0 + x;
      last = x0 + e - 1;
    }
    if (first < 0) continue;
    if (first < a->x0) a->x0 = first;
    if (last >= a->x1) a->x1 = last + 1;
    if (y < a->y0) a->y0 = y;
    a->y1 = y + 1;
  }
}

/* N x N samples a pixel: ink when ink objects show at least as many
** samples as other objects and as the background, its grey the mean of
** theirs; off the canvas when other objects show more than the
** background; else bare paper. (x, y) is a canvas pixel of rt's. */
static void ink_pixel_n(InkCanvas *c, const InkSet *set, const RenderFrame *f, const RastTarget *rt, int x,
                        int y, InkArea *a) {
  int N = f->samples, n_ink = 0, n_other = 0, n_bare = 0, si = -1;
  float grey = 0;
  for (int sy = 0; sy < N; sy++)
    for (int sx = 0; sx < N; sx++) {
      size_t i = (size_t)((y + f->win.y0) * N + sy - rt->oy) * rt->stride + (size_t)((x + f->win.x0) * N + sx - rt->ox);
      int obj = rt->object[i];
      if (obj < 0) { n_bare++; continue; }
      int s = obj < f->nobjects ? set->of_object[obj] : -1;
      if (s < 0) { n_other++; continue; }
      n_ink++;
      grey += shade_ink_grey(f, &f->objects[obj], rt->face[i], rt->bary[i]);
      if (si < 0) si = s;
    }
  size_t p = (size_t)y * c->width + x;
  if (n_ink == 0 || n_ink < n_other || n_ink < n_bare) {
    if (n_other > n_bare) put_off(c, p, a);
    return;
  }
  put_ink(c, set, p, si, grey / (float)n_ink, a, x, y);
}

/* The ink of the pixels of rt's rectangle of samples (whole pixels) into
** c; their ink's box and whether some are off the canvas into a. */
static void ink_rect(InkCanvas *c, const InkSet *set, const RenderFrame *f, const RastTarget *rt, InkArea *a) {
  int N = f->samples;
  if (N == 1) { ink_pixels_1(c, set, f, rt, a); return; }
  for (int y = rt->y0 / N - f->win.y0; y < rt->y1 / N - f->win.y0; y++)
    for (int x = rt->x0 / N - f->win.x0; x < rt->x1 / N - f->win.x0; x++) ink_pixel_n(c, set, f, rt, x, y, a);
}

/* Does any ink style run the stage st? */
static int any_stage(const InkSet *set, int st) {
  for (int i = 0; i < set->n; i++)
    if (set->styles[i].stage >= st) return 1;
  return 0;
}

/* ---- the box filter ------------------------------------------------------------------ */

/* Ink colour planes (premultiplied by ink), when the styles' colours differ. */
typedef struct InkColour { float *k[3]; } InkColour;

static void colour_planes(const InkCanvas *c, const InkSet *set, InkColour *col) {
  size_t n = (size_t)c->width * c->height;
  for (int ch = 0; ch < 3; ch++) col->k[ch] = set->uniform ? NULL : xmalloc(n * sizeof(float) + 1);
  if (set->uniform) return;
  for (size_t p = 0; p < n; p++)
    for (int ch = 0; ch < 3; ch++)
      col->k[ch][p] = c->style[p] == INK_NO_STYLE ? 0 : c->ink[p] * set->styles[c->style[p]].color[ch];
}

/* The box filter over the ink of filtered styles' pixels (the others keep
** theirs), averaged over the canvas (pixels other objects cover are off
** it), within rectangle a (the ink's box grown by its reach and the box). */
static void box_stage(InkCanvas *c, const InkSet *set, InkColour *col, const InkArea *a, int any_off) {
  size_t n = (size_t)c->width * c->height;
  int np = set->uniform ? 1 : 4, all_filtered = !any_stage(set, INK_STAGE_FILTERED + 1);
  for (int i = 0; i < set->n && all_filtered; i++) all_filtered = set->styles[i].stage == INK_STAGE_FILTERED;
  float *planes[4] = {all_filtered ? c->ink : xmalloc(n * sizeof(float) + 1), NULL, NULL, NULL};
  for (int ch = 0; ch < 3 && np == 4; ch++) planes[1 + ch] = all_filtered ? col->k[ch] : xmalloc(n * sizeof(float) + 1);
  if (!all_filtered)   /* the filtered styles' ink apart; the rest keep theirs */
    for (size_t p = 0; p < n; p++) {
      int filtered = c->style[p] == INK_NO_STYLE || set->styles[c->style[p]].stage == INK_STAGE_FILTERED;
      planes[0][p] = filtered ? c->ink[p] : 0;
      if (filtered) c->ink[p] = 0;
      for (int ch = 0; ch < 3 && np == 4; ch++) {
        planes[1 + ch][p] = filtered ? col->k[ch][p] : 0;
        if (filtered) col->k[ch][p] = 0;
      }
    }
  uint8_t *on = NULL;   /* pixels on the canvas, when some are off it */
  if (any_off) {
    on = xmalloc(n + 1);
    for (size_t p = 0; p < n; p++) on[p] = c->level[p] != INK_OFF;
  }
  ink_box_filter_rect(planes, np, on, c->width, c->height, set->box, a->x0, a->y0, a->x1, a->y1);
  free(on);
  if (all_filtered) return;
  for (size_t p = 0; p < n; p++) {
    c->ink[p] += planes[0][p];
    for (int ch = 0; ch < 3 && np == 4; ch++) col->k[ch][p] += planes[1 + ch][p];
  }
  for (int k = 0; k < np; k++) free(planes[k]);
}

/* ---- the composite ------------------------------------------------------------------ */

/* What the composite reads. */
typedef struct Paint {
  const Paper *pp;
  const InkCanvas *c;          /* NULL: no ink */
  const InkArea *area;         /* with c */
  const InkColour *col;
  float ink_color[3];          /* the one colour, when uniform */
  const Image *layer;          /* the tile pass's image */
  int read_layer;              /* 0: it is transparent everywhere (only ink was drawn) */
  uint8_t *mix[3];             /* one ink colour: per channel, paper code p and density d
                                  (1/256ths) mix to mix[p * 257 + d]; else NULL */
  int ox, oy;                  /* the frame pixel the layer's first is (a tile's window) */
} Paint;

/* The mixing tables of one ink colour k (display values): paper code p
** under ink of density d / 256 shows p + (k - p) d / 256, rounded. */
static void mix_tables(Paint *pt, const float k[3]) {
  for (int ch = 0; ch < 3; ch++) {
    int K = (int)(k[ch] * 255 + 0.5f);
    uint8_t *t = pt->mix[ch] = xmalloc(256 * 257);
    for (int p = 0; p < 256; p++)
      for (int d = 0; d <= 256; d++) t[p * 257 + d] = (uint8_t)(p + (((K - p) * d + 128) >> 8));
  }
}

/* The ink's colour at pixel p (display values). */
static void ink_colour(const Paint *pt, size_t p, float ink, float kc[3]) {
  for (int ch = 0; ch < 3; ch++)
    kc[ch] = pt->col->k[0] && ink > 0 ? pt->col->k[ch][p] / ink : pt->ink_color[ch];
}

/* One pixel, in general: ink of density d (times the absorbency) on the
** paper texel t, in display values, then the layer pixel lay (linear,
** unassociated alpha) over it, into out (nc linear channels). */
static void composite_pixel(const Paint *pt, size_t p, size_t t, const float *lay, float *out, int nc) {
  const Paper *pp = pt->pp;
  float ink = pt->c ? pt->c->ink[p] : 0, kc[3];
  ink_colour(pt, p, ink, kc);
  float d = ink * (1.0f / 255) * (pp->absorb ? pp->absorb[t] : 1);
  d = d < 1 ? (d > 0 ? d : 0) : 1;
  float pa = pp->alpha, a = d + pa * (1 - d);   /* ink over the paper's alpha */
  float base[3];
  for (int ch = 0; ch < 3; ch++)
    base[ch] = d == 0 ? pp->linear[3 * t + ch]
                      : display_to_linear((kc[ch] * d + pp->display[3 * t + ch] * pa * (1 - d)) / a);
  float la = lay[3], oa = la + a * (1 - la);
  for (int ch = 0; ch < 3; ch++) out[ch] = oa > 0 ? (lay[ch] * la + base[ch] * a * (1 - la)) / oa : 0;
  if (nc == 4) out[3] = oa;
}

/* Pixel p of the layer (linear, unassociated alpha) into lay; 0 where it
** is transparent. */
static int layer_pixel(const Image *L, size_t p, float lay[4]) {
  if (L->data8) {   /* an 8-bit layer: its codes */
    if (L->data8[4 * p + 3] == 0) return 0;
    image_decode8(L->data8 + 4 * p, lay, 1, 4);
    return 1;
  }
  memcpy(lay, L->data + 4 * p, 4 * sizeof *lay);
  return lay[3] > 0;
}

/* Ink of quantity ink on paper of absorbency a: its density in 1/256ths
** of full ink, 0..256. */
static inline int density(float ink, float a) {
  float v = ink * (256.0f / 255) * a + 0.5f;
  v = v < 256 ? v : 256;   /* a NaN too */
  v = v > 0 ? v : 0;       /* clamped as selects, so a loop of them runs in lanes */
  return (int)v;
}

/* The densities of n pixels of ink I on paper of absorbency A (NULL: 1)
** into D: a loop of lanes, apart from the lookups that use them. */
static void densities(const float *restrict I, const float *restrict A, int *restrict D, int n) {
  if (A)
    for (int i = 0; i < n; i++) D[i] = density(I[i], A[i]);
  else
    for (int i = 0; i < n; i++) D[i] = density(I[i], 1);
}

/* n pixels of one ink (densities D) on paper codes P into codes o,
** through the mixing tables m0, m1, m2; no ink (density 0) leaves the
** paper's codes. */
static void mix_run(const uint8_t *restrict m0, const uint8_t *restrict m1, const uint8_t *restrict m2,
                    const int *restrict D, const uint8_t *restrict P, uint8_t *restrict o, int n) {
  for (int i = 0; i < n; i++, o += 3, P += 3) {
    int d = D[i];
    if (d == 0) { o[0] = P[0]; o[1] = P[1]; o[2] = P[2]; continue; }
    o[0] = m0[P[0] * 257 + d];
    o[1] = m1[P[1] * 257 + d];
    o[2] = m2[P[2] * 257 + d];
  }
}

/* The same on paper of one colour: its three tables' rows packed, a
** pixel's codes in the low three bytes of t[d]. */
static void mix_flat(const uint32_t *restrict t, const int *restrict D, uint8_t *restrict o, int n) {
  int i = 0;
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
  for (; i + 1 < n; i++, o += 3) memcpy(o, &t[D[i]], 4);   /* the 4th byte: the next pixel's, written next */
#endif
  for (; i < n; i++, o += 3) {
    uint32_t v = t[D[i]];
    o[0] = (uint8_t)v;
    o[1] = (uint8_t)(v >> 8);
    o[2] = (uint8_t)(v >> 16);
  }
}

/* Row y into an 8-bit image. Where only ink and paper show, the display
** mix goes straight to its codes, a run of texels at a time; where the
** layer shows, the general pixel, encoded. */
/* One ink's mixes with paper codes P, packed as mix_flat reads them, into
** f (kept while the codes stay the same: flat paper has one). */
typedef struct FlatMix { uint32_t t[257]; int code; } FlatMix;

static const uint32_t *flat_mix(const Paint *pt, const uint8_t *P, FlatMix *f) {
  int code = P[0] | P[1] << 8 | P[2] << 16;
  if (f->code == code) return f->t;
  for (int d = 0; d <= 256; d++)
    f->t[d] = pt->mix[0][P[0] * 257 + d] | (uint32_t)pt->mix[1][P[1] * 257 + d] << 8 |
              (uint32_t)pt->mix[2][P[2] * 257 + d] << 16;
  f->code = code;
  return f->t;
}

static void composite_row8(const Paint *pt, int y, uint8_t *out, int *D, FlatMix *fm) {
  const Paper *pp = pt->pp;
  int w = pt->layer->width, tw = pp->width, ox = pt->ox;
  size_t row = (size_t)y * w, row_t = paper_texel(pp, 0, y + pt->oy);   /* the frame's rows and columns */
  const float *ink = pt->c ? pt->c->ink + row : NULL;
  int lo = 0, hi = 0;   /* the row's pixels from its first ink to its last */
  if (ink) {
    lo = ink_first_nonzero(ink, 0, w);
    hi = ink_nonzero_end(ink, lo, w);
  }
  for (int x0 = 0, tx = ox % tw; x0 < w; x0 += tw - tx, tx = 0) {   /* runs of the tile's row */
    int n = w - x0 < tw - tx ? w - x0 : tw - tx;
    const uint8_t *P = pp->code + 3 * (row_t + (size_t)tx);
    const float *A = pp->absorb ? pp->absorb + row_t + tx : NULL;
    uint8_t *o = out + 3 * (size_t)x0;
    /* no ink (density 0, the absorbency finite) shows the paper's codes */
    int a = lo - x0 > 0 ? (lo - x0 < n ? lo - x0 : n) : 0, e = hi - x0 < n ? hi - x0 : n;
    if (e < a) e = a;
    memcpy(o, P, 3 * (size_t)a);
    memcpy(o + 3 * (size_t)e, P + 3 * (size_t)e, 3 * (size_t)(n - e));
    if (a == e) continue;
    int xs = x0 + a;   /* the ink's part of the run */
    P += 3 * (size_t)a, o += 3 * (size_t)a, A = A ? A + a : NULL, n = e - a;
    const float *I = ink + xs;
    if (pt->mix[0] && !A && pp->height == 1) {   /* one ink on one colour: a table each channel */
      densities(I, NULL, D, n);
      mix_flat(flat_mix(pt, P, fm), D, o, n);
      continue;
    }
    if (pt->mix[0]) {   /* one ink: its mixes with every paper code, from the tables */
      densities(I, A, D, n);
      mix_run(pt->mix[0], pt->mix[1], pt->mix[2], D, P, o, n);
      continue;
    }
    for (int i = 0; i < n; i++, o += 3, P += 3) {   /* inks of several colours */
      int d = density(I[i], A ? A[i] : 1);
      float kc[3];
      ink_colour(pt, row + (size_t)(xs + i), I[i], kc);
      for (int ch = 0; ch < 3; ch++) {
        int K = (int)(kc[ch] * 255 + 0.5f);
        o[ch] = (uint8_t)(P[ch] + (((K - P[ch]) * d + 128) >> 8));
      }
    }
  }
  if (!pt->read_layer) return;
  for (int x = 0; x < w; x++) {
    size_t p = row + (size_t)x;
    float lay[4], lin[3];
    if (!layer_pixel(pt->layer, p, lay)) continue;
    composite_pixel(pt, p, paper_texel(pp, x + ox, y + pt->oy), lay, lin, 3);   /* another object shows here */
    image_encode8(lin, out + 3 * x, 1, 3);
  }
}

/* The painted image: the layer over the inked paper; 8-bit codes when
** out8 asks and the paper is opaque, else float. */
static Image *composite(const Paint *pt, int out8) {
  const Image *layer = pt->layer;
  int w = layer->width, h = layer->height, nc = pt->pp->alpha >= 1 ? 3 : 4;
  if (out8 && nc == 3) {
    Image *out = image_create8_unset(w, h, 3);
    int *D = xmalloc((size_t)w * sizeof *D);   /* a row's densities */
    FlatMix *fm = xmalloc(sizeof *fm);
    fm->code = -1;   /* none yet */
    for (int y = 0; y < h; y++) composite_row8(pt, y, out->data8 + (size_t)y * w * 3, D, fm);
    free(fm);
    free(D);
    return out;
  }
  Image *out = image_create(w, h, nc);
  mem_advise_huge(out->data, (size_t)w * h * nc * sizeof(float));
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      size_t p = (size_t)y * w + x;
      float lay[4] = {0, 0, 0, 0};
      if (pt->read_layer) layer_pixel(layer, p, lay);
      composite_pixel(pt, p, paper_texel(pt->pp, x + pt->ox, y + pt->oy), lay, out->data + p * nc, nc);
    }
  return out;
}

/* ---- the whole step ------------------------------------------------------------------- */

/* Grow a's box by m pixels within w x h. */
static void grow_area(InkArea *a, int m, int w, int h) {
  a->x0 = a->x0 - m > 0 ? a->x0 - m : 0;
  a->y0 = a->y0 - m > 0 ? a->y0 - m : 0;
  a->x1 = a->x1 + m < w ? a->x1 + m : w;
  a->y1 = a->y1 + m < h ? a->y1 + m : h;
}

/* The ink of the frame on c (quantised: every pixel written), through
** the other stages its styles ask for; a is the ink's box. */
static void paint_ink(InkCanvas *c, const InkSet *set, InkArea *a, InkColour *col) {
  if (a->x0 >= a->x1) return;   /* no ink pixel in view */
  double t1 = stats_now();
  if (any_stage(set, INK_STAGE_DIFFUSED)) {
    InkDiffuseStats ds;
    ink_diffuse(c, -1, &ds);
    double t2 = stats_now();
    stats_record("ink diffuse", t2 - t1);
    stats_record_count("ink diffuse", "transfers", ds.transfers);
    t1 = t2;
  }
  grow_area(a, set->reach + set->box / 2, c->width, c->height);   /* where ink can be, and its boxes */
  colour_planes(c, set, col);
  if (set->box > 1) {
    box_stage(c, set, col, a, a->any_off);
    stats_record("ink box", stats_now() - t1);
  }
}

/* A frame's canvas between canvas_begin and canvas_finish. */
struct Canvas {
  const Scene *s;
  const RenderFrame *f;
  Paper pp;
  InkSet set;
  InkCanvas c;                 /* with set.n > 0 */
  InkArea *areas;              /* per screen tile of the window: what canvas_tile found */
  double *quantise_s;          /* per screen tile: the time it took */
  int tx0, ty0, tiles_x;       /* the window's first screen tile, its tiles a row */
  RenderTileSink sink;
};

int canvas_begin(const Scene *s, const RenderFrame *f, Canvas **out) {
  double t0 = stats_now();
  Canvas *cv = xcalloc(1, sizeof *cv);
  char err[1400];
  const SceneSheet *sh = &s->output.sheet;
  int backdrop = !sh->texture && (s->output.nstops >= 2 || s->output.backdrop);   /* a sheet wins */
  if (backdrop ? !paper_backdrop(&s->output, f->width, f->height, &cv->pp, err, sizeof err)
               : !paper_create(sh, s->output.background, &cv->pp, err, sizeof err)) {
    diag_error(backdrop ? s->output.background_loc : sh->loc, "%s", err);
    free(cv);
    *out = NULL;
    return 0;
  }
  stats_record("paper", stats_now() - t0);
  cv->s = s;
  cv->f = f;
  ink_set(f, &cv->set);
  if (cv->set.n > 0) {
    InkCanvas *c = &cv->c;
    ink_canvas_init_lean(c, f->win.x1 - f->win.x0, f->win.y1 - f->win.y0, cv->set.styles, cv->set.n);   /* the
                                                                  tiles write its ink pixels */
    c->ox = f->win.x0;
    c->oy = f->win.y0;
    c->absorb = cv->pp.absorb;
    c->absorb_w = cv->pp.width;
    c->absorb_h = cv->pp.height;
    c->seed = (uint32_t)sh->seed;
  }
  cv->tx0 = f->win.x0 / RENDER_TILE;
  cv->ty0 = f->win.y0 / RENDER_TILE;
  cv->tiles_x = (f->win.x1 + RENDER_TILE - 1) / RENDER_TILE - cv->tx0;
  int ntiles = cv->tiles_x * ((f->win.y1 + RENDER_TILE - 1) / RENDER_TILE - cv->ty0);
  cv->areas = xmalloc((size_t)ntiles * sizeof *cv->areas + 1);
  cv->quantise_s = xcalloc((size_t)ntiles + 1, sizeof *cv->quantise_s);
  for (int i = 0; i < ntiles; i++) cv->areas[i] = (InkArea){cv->c.width, cv->c.height, 0, 0, 0};
  *out = cv;
  return 1;
}

/* A tile of the pass: its pixels' ink. */
static void canvas_tile(void *ctx, const RastTarget *rt) {
  Canvas *cv = ctx;
  double t0 = stats_now();
  int px = rt->x0 / cv->f->samples, py = rt->y0 / cv->f->samples;
  int slot = (py / RENDER_TILE - cv->ty0) * cv->tiles_x + (px / RENDER_TILE - cv->tx0);
  ink_rect(&cv->c, &cv->set, cv->f, rt, &cv->areas[slot]);
  cv->quantise_s[slot] += stats_now() - t0;
}

const RenderTileSink *canvas_sink(Canvas *cv) {
  if (cv->set.n == 0) return NULL;   /* no ink: the paper reads no samples */
  cv->sink.ctx = cv;
  cv->sink.tile = canvas_tile;
  return &cv->sink;
}

int canvas_finish(Canvas *cv, Image **img, int out8) {
  const RenderFrame *f = cv->f;
  int ntiles = cv->tiles_x * ((f->win.y1 + RENDER_TILE - 1) / RENDER_TILE - cv->ty0);
  InkArea area = {cv->c.width, cv->c.height, 0, 0, 0};
  double quantise = 0;
  for (int i = 0; i < ntiles; i++) {   /* the tiles' boxes, in one */
    const InkArea *t = &cv->areas[i];
    quantise += cv->quantise_s[i];
    area.any_off |= t->any_off;
    if (t->x0 >= t->x1) continue;
    area.x0 = t->x0 < area.x0 ? t->x0 : area.x0;
    area.y0 = t->y0 < area.y0 ? t->y0 : area.y0;
    area.x1 = t->x1 > area.x1 ? t->x1 : area.x1;
    area.y1 = t->y1 > area.y1 ? t->y1 : area.y1;
  }
  const InkSet *set = &cv->set;
  InkColour col = {{NULL, NULL, NULL}};
  Paint pt = {&cv->pp, NULL, &area, &col, {0, 0, 0}, *img, canvas_reads_layer(cv->s, f), {NULL, NULL, NULL},
              f->win.x0, f->win.y0};
  if (set->n > 0) {
    stats_record_cpu("ink quantise", quantise);   /* in the tile pass, on its workers */
    memcpy(pt.ink_color, set->styles[0].color, sizeof pt.ink_color);
    paint_ink(&cv->c, set, &area, &col);
    pt.c = &cv->c;
    if (out8 && set->uniform) mix_tables(&pt, pt.ink_color);
  }
  if (!(out8 && cv->pp.alpha >= 1) || pt.read_layer) paper_fill_linear(&cv->pp);   /* composite_pixel reads them */
  double t1 = stats_now();
  Image *out = composite(&pt, out8);
  stats_record("canvas", stats_now() - t1);
  image_destroy(*img);
  *img = out;
  for (int ch = 0; ch < 3; ch++) free(col.k[ch]), free(pt.mix[ch]);
  if (set->n > 0) ink_canvas_free(&cv->c);
  ink_set_free(&cv->set);
  paper_free(&cv->pp);
  free(cv->areas);
  free(cv->quantise_s);
  free(cv);
  return 1;
}

int canvas_paint(const Scene *s, const RenderFrame *f, const GBuffer *g, Image **img, int out8) {
  Canvas *cv;
  if (!canvas_begin(s, f, &cv)) return 0;
  if (cv->set.n > 0) {   /* the whole window as one tile */
    int N = f->samples;
    RastTarget rt = {f->win.x0 * N, f->win.y0 * N, f->win.x1 * N, f->win.y1 * N, f->win.x0 * N, f->win.y0 * N,
                     g->width, g->depth, g->object, g->face, g->bary, NULL};
    double t0 = stats_now();
    ink_rect(&cv->c, &cv->set, f, &rt, &cv->areas[0]);
    cv->quantise_s[0] = stats_now() - t0;
  }
  return canvas_finish(cv, img, out8);
}
