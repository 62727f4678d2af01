/*
** The canvas (canvas.h): paper, ink, and the tile pass's image over them.
**
** Bottom-up: the frame's ink styles, the ink of each pixel from the
** G-buffer, the stages (diffusion, box filter), and the composite.
*/
#include "canvas.h"

#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"
#include "../lang/diag.h"
#include "display.h"
#include "ink.h"
#include "paper.h"
#include "stats.h"

/* ---- the frame's ink styles ---------------------------------------------------- */

/* The ink styles of a frame as the canvas numbers them. */
typedef struct InkSet {
  int n;
  InkStyle *styles;      /* copies of the RenderStyles' ink */
  int *of_style;         /* per RenderStyle: its index here, or -1 */
  int uniform;           /* every ink style has the same colour */
  int box;               /* the frame's box side: the largest a filtered style asks for */
} InkSet;

static void ink_set(const RenderFrame *f, InkSet *set) {
  memset(set, 0, sizeof *set);
  set->styles = xcalloc((size_t)f->nstyles + 1, sizeof *set->styles);
  set->of_style = xmalloc(((size_t)f->nstyles + 1) * sizeof *set->of_style);
  set->uniform = 1;
  set->box = 1;
  for (int i = 0; i < f->nstyles; i++) {
    set->of_style[i] = -1;
    const InkStyle *k = f->styles[i].ink;
    if (!k || set->n >= INK_NO_STYLE) continue;
    set->of_style[i] = set->n;
    set->styles[set->n] = *k;
    if (set->n > 0 && memcmp(k->color, set->styles[0].color, sizeof k->color) != 0) set->uniform = 0;
    if (k->stage == INK_STAGE_FILTERED && k->box > set->box) set->box = k->box;
    set->n++;
  }
}

static void ink_set_free(InkSet *set) {
  free(set->styles);
  free(set->of_style);
}

int canvas_wanted(const Scene *s, const RenderFrame *f) {
  if (s->output.sheet.texture) return 1;
  for (int i = 0; i < f->nobjects; i++)
    if (f->objects[i].style->ink) return 1;
  return 0;
}

/* ---- the ink of each pixel -------------------------------------------------------- */

/* The Gouraud grey of object o at a sample of triangle face, barycentrics b. */
static float sample_grey(const RenderObject *o, int face, const float b[2]) {
  float b1 = b[0], b2 = b[1], b0 = 1 - b1 - b2;
  if (o->wcnrm) {   /* a grey per corner */
    const float *v = o->vink + 3 * (size_t)face;
    return b0 * v[0] + b1 * v[1] + b2 * v[2];
  }
  const int *t = o->mesh->tri[face];
  return b0 * o->vink[t[0]] + b1 * o->vink[t[1]] + b2 * o->vink[t[2]];
}

/* Pixel p (x, y) of the canvas from its N x N samples: ink when ink
** objects show at least as many samples as other objects and as the
** background, its grey the mean of theirs; off the canvas when other
** objects show more than the background; else bare paper. */
static void ink_pixel(InkCanvas *c, const InkSet *set, const RenderFrame *f, const GBuffer *g, int x,
                      int y) {
  int N = f->samples, n_ink = 0, n_other = 0, n_bare = 0, style = -1;
  float grey = 0;
  for (int sy = 0; sy < N; sy++)
    for (int sx = 0; sx < N; sx++) {
      size_t i = (size_t)(y * N + sy) * g->width + (size_t)(x * N + sx);
      int obj = g->object[i];
      if (obj < 0) { n_bare++; continue; }
      const RenderObject *o = obj < f->nobjects ? &f->objects[obj] : NULL;   /* else an origami sheet */
      if (!o || !o->vink) { n_other++; continue; }
      n_ink++;
      grey += sample_grey(o, g->face[i], g->bary[i]);
      if (style < 0) style = set->of_style[o->style - f->styles];
    }
  size_t p = (size_t)y * c->width + x;
  if (n_ink == 0 || n_ink < n_other || n_ink < n_bare) {
    if (n_other > n_bare) c->level[p] = INK_OFF;
    return;   /* else bare paper, as initialised */
  }
  const InkStyle *k = &set->styles[style];
  grey /= (float)n_ink;
  int label = ink_label(k, grey);
  c->level[p] = (uint8_t)label;
  c->style[p] = (uint16_t)style;
  c->ink[p] = k->stage == INK_STAGE_GOURAUD ? 255 * (1 - grey) : k->ink[label];
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
** it). */
static void box_stage(InkCanvas *c, const InkSet *set, InkColour *col) {
  size_t n = (size_t)c->width * c->height;
  float *planes[4] = {xmalloc(n * sizeof(float) + 1), NULL, NULL, NULL};
  uint8_t *on = xmalloc(n + 1);
  int np = set->uniform ? 1 : 4;
  for (int ch = 0; ch < 3 && np == 4; ch++) planes[1 + ch] = xmalloc(n * sizeof(float) + 1);
  for (size_t p = 0; p < n; p++) {
    int filtered = c->style[p] == INK_NO_STYLE || set->styles[c->style[p]].stage == INK_STAGE_FILTERED;
    on[p] = c->level[p] != INK_OFF;
    planes[0][p] = filtered ? c->ink[p] : 0;
    if (filtered) c->ink[p] = 0;
    for (int ch = 0; ch < 3 && np == 4; ch++) {
      planes[1 + ch][p] = filtered ? col->k[ch][p] : 0;
      if (filtered) col->k[ch][p] = 0;
    }
  }
  ink_box_filter(planes, np, on, c->width, c->height, set->box);
  for (size_t p = 0; p < n; p++) {
    c->ink[p] += planes[0][p];
    for (int ch = 0; ch < 3 && np == 4; ch++) col->k[ch][p] += planes[1 + ch][p];
  }
  for (int k = 0; k < np; k++) free(planes[k]);
  free(on);
}

/* ---- the composite ------------------------------------------------------------------ */

/* One pixel: ink of density d (times the absorbency) and colour ink_col on
** the paper texel t, in display values, then the layer pixel lay (linear,
** unassociated alpha; NULL: nothing) over it, into out (nc channels). */
static void composite_pixel(const Paper *pp, size_t t, float ink, const float ink_col[3], const float *lay,
                            float *out, int nc) {
  float d = ink * (1.0f / 255) * (pp->absorb ? pp->absorb[t] : 1);
  d = d < 1 ? (d > 0 ? d : 0) : 1;
  float pa = pp->alpha, a = d + pa * (1 - d);   /* ink over the paper's alpha */
  float base[3];
  for (int ch = 0; ch < 3; ch++) {
    if (d == 0) { base[ch] = pp->linear[3 * t + ch]; continue; }
    float disp = (ink_col[ch] * d + pp->display[3 * t + ch] * pa * (1 - d)) / a;
    base[ch] = display_to_linear(disp);
  }
  float la = lay ? lay[3] : 0, oa = la + a * (1 - la);
  for (int ch = 0; ch < 3; ch++)
    out[ch] = oa > 0 ? ((lay ? lay[ch] * la : 0) + base[ch] * a * (1 - la)) / oa : 0;
  if (nc == 4) out[3] = oa;
}

/* The painted image: the layer over the inked paper. */
static Image *composite(const Paper *pp, const InkCanvas *c, const InkSet *set, const InkColour *col,
                        const Image *layer) {
  int w = layer->width, h = layer->height;
  int nc = pp->alpha >= 1 ? 3 : 4;
  Image *out = image_create(w, h, nc);
  mem_advise_huge(out->data, (size_t)w * h * nc * sizeof(float));
  const float *uni = set->n ? set->styles[0].color : (const float[3]){0, 0, 0};
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      size_t p = (size_t)y * w + x;
      float ink = c ? c->ink[p] : 0, kc[3] = {uni[0], uni[1], uni[2]};
      if (col && col->k[0] && ink > 0)
        for (int ch = 0; ch < 3; ch++) kc[ch] = col->k[ch][p] / ink;
      const float *lay = layer->data + p * layer->channels;
      composite_pixel(pp, paper_texel(pp, x, y), ink, kc, lay[3] > 0 ? lay : NULL, out->data + p * nc, nc);
    }
  return out;
}

/* ---- the whole step ------------------------------------------------------------------- */

/* The ink of the frame on c, through every stage its styles ask for. */
static void paint_ink(InkCanvas *c, const InkSet *set, const RenderFrame *f, const GBuffer *g,
                      InkColour *col) {
  double t0 = stats_now();
  for (int y = 0; y < c->height; y++)
    for (int x = 0; x < c->width; x++) ink_pixel(c, set, f, g, x, y);
  double t1 = stats_now();
  stats_record("ink quantise", t1 - t0);
  if (any_stage(set, INK_STAGE_DIFFUSED)) {
    InkDiffuseStats ds;
    ink_canvas_wet(c);
    ink_diffuse(c, -1, &ds);
    double t2 = stats_now();
    stats_record("ink diffuse", t2 - t1);
    stats_record_count("ink diffuse", "transfers", ds.transfers);
    t1 = t2;
  }
  colour_planes(c, set, col);
  if (set->box > 1) {
    box_stage(c, set, col);
    stats_record("ink box", stats_now() - t1);
  }
}

int canvas_paint(const Scene *s, const RenderFrame *f, const GBuffer *g, Image **img) {
  double t0 = stats_now();
  Paper pp;
  char err[1400];
  const SceneSheet *sh = &s->output.sheet;
  if (!paper_create(sh, s->output.background, &pp, err, sizeof err)) {
    diag_error(sh->loc, "%s", err);
    return 0;
  }
  stats_record("paper", stats_now() - t0);
  InkSet set;
  ink_set(f, &set);
  InkCanvas c, *cp = NULL;
  InkColour col = {{NULL, NULL, NULL}};
  if (set.n > 0) {
    ink_canvas_init(&c, f->width, f->height, set.styles, set.n);
    c.absorb = pp.absorb;
    c.absorb_w = pp.width;
    c.absorb_h = pp.height;
    c.seed = (uint32_t)sh->seed;
    paint_ink(&c, &set, f, g, &col);
    cp = &c;
  }
  double t1 = stats_now();
  Image *out = composite(&pp, cp, &set, &col, *img);
  stats_record("canvas", stats_now() - t1);
  image_destroy(*img);
  *img = out;
  for (int ch = 0; ch < 3; ch++) free(col.k[ch]);
  if (cp) ink_canvas_free(cp);
  ink_set_free(&set);
  paper_free(&pp);
  return 1;
}
