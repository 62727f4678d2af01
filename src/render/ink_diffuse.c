/*
** The ink canvas (ink.h): ink diffusion under the three rules of Yeh's
** ch. 5.2 and the box filter that follows it.
**
** The diffusion is synchronous: a pass reads the state the previous pass
** left and writes the changes after, so its result does not depend on the
** order pixels are visited (nor on tiles or threads). Only a pixel next to
** one that changed can change in the next pass: a giver's offer depends on
** its own state and its receiver's, the receiver only gets darker (level
** and ink rise), which the rules make harder to give to, and a pixel takes
** the darkest offer there is. So the first pass scans the canvas and each
** later pass looks only at the neighbours of the last pass's changes.
*/
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"
#include "../base/rng.h"
#include "ink.h"
#include "noise.h"

/* ---- the canvas ----------------------------------------------------------- */

void ink_canvas_init(InkCanvas *c, int w, int h, const InkStyle *styles, int nstyles) {
  memset(c, 0, sizeof *c);
  size_t n = (size_t)w * h;
  c->width = w;
  c->height = h;
  c->ink = xcalloc(n + 1, sizeof *c->ink);
  c->water = xcalloc(n + 1, sizeof *c->water);
  c->level = xcalloc(n + 1, sizeof *c->level);
  c->style = xmalloc((n + 1) * sizeof *c->style);
  memset(c->style, 0xff, (n + 1) * sizeof *c->style);   /* INK_NO_STYLE */
  c->styles = styles;
  c->nstyles = nstyles;
}

void ink_canvas_free(InkCanvas *c) {
  free(c->noise);
  free(c->ink);
  free(c->water);
  free(c->level);
  free(c->style);
  memset(c, 0, sizeof *c);
}

void ink_canvas_wet(InkCanvas *c) {
  size_t n = (size_t)c->width * c->height;
  for (size_t p = 0; p < n; p++) {
    int l = c->level[p];
    /* the washes are wet; the paper level (bare paper, highlights) is dry */
    c->water[p] = l != INK_OFF && l > 0 && c->style[p] != INK_NO_STYLE ? c->styles[c->style[p]].water : 0;
  }
}

/* ---- the paper's resistance --------------------------------------------------- */

/* The smooth part of the resistance: gradient noise of cells RESIST_CELL
** pixels, repeating every RESIST_PERIOD cells (far beyond what a front
** sees), in [0, 1]. */
#define RESIST_CELL 6
#define RESIST_PERIOD 64

static float resist_noise(const InkCanvas *c, int x, int y) {
  const float span = RESIST_CELL * RESIST_PERIOD;
  float v = 0.5f + 0.5f * noise_fbm_eval(c->fbm, ((float)x + 0.5f) / span, ((float)y + 0.5f) / span);
  return v < 0 ? 0 : v > 1 ? 1 : v;
}

/* The paper's resistance to ink at pixel (x, y) for roughness rho: 1 +
** rho (2 n - 1) over the absorbency, n the smooth noise (cached): it scales
** a hop's loss and water cost. */
static float ink_resistance(const InkCanvas *c, int x, int y, float rho) {
  size_t p = (size_t)y * c->width + x;
  float n = c->noise ? c->noise[p] : -1;
  if (n < 0) {   /* not yet computed: only pixels the diffusion reaches need it */
    n = resist_noise(c, x, y);
    if (c->noise) c->noise[p] = n;
  }
  float r = 1 + rho * (2 * n - 1);
  if (c->absorb) r /= c->absorb[(size_t)(y % c->absorb_h) * c->absorb_w + (size_t)(x % c->absorb_w)];
  return r > 0.1f ? r : 0.1f;
}

/* The passes before a pixel that took ink can pass it on: INK_DELAY times
** the same with the pixel's own random value (so growth from one point is
** irregular and roundish, not a diamond of four-neighbour steps). */
static int ink_delay(const InkCanvas *c, int x, int y, float rho) {
  Rng g;   /* the pixel's own random value */
  rng_seed_key(&g, c->seed, (uint32_t)x, (uint32_t)y);
  float r = 1 + rho * (2 * (float)rng_uniform(&g) - 1);
  if (c->absorb) r /= c->absorb[(size_t)(y % c->absorb_h) * c->absorb_w + (size_t)(x % c->absorb_w)];
  int d = (int)ceilf(INK_DELAY * r);
  return d < 1 ? 1 : d > INK_MAX_DELAY ? INK_MAX_DELAY : d;
}

/* ---- diffusion ---------------------------------------------------------------- */

typedef struct Offer {
  uint32_t pixel;
  uint16_t style;
  uint8_t level, delay;
  float ink, water;
} Offer;

/* Is offer a better than b (darker level, then more ink, then more water)? */
static int better(const Offer *a, const Offer *b) {
  if (a->level != b->level) return a->level > b->level;
  if (a->ink != b->ink) return a->ink > b->ink;
  return a->water > b->water;
}

/* Does style index s take part in the diffusion? */
static int diffuses(const InkCanvas *c, int s) {
  return s == INK_NO_STYLE || c->styles[s].stage >= INK_STAGE_DIFFUSED;
}

/* What giver q offers pixel p (x, y) in pass `pass` under the three rules;
** 0 if nothing. */
static int offer_from(const InkCanvas *c, size_t q, size_t p, int x, int y, int pass, Offer *o) {
  int lq = c->level[q], lp = c->level[p];
  if (lq == INK_OFF || lq <= lp) return 0;                   /* rule 2: darker to lighter */
  if (lp == 0 && lq != 1) return 0;                          /* onto paper only from the light level */
  if (c->ready[q] >= pass) return 0;                         /* its water has not come through yet */
  const InkStyle *k = &c->styles[c->style[q]];
  if (k->stage < INK_STAGE_DIFFUSED) return 0;
  if (!(c->water[q] > k->water_threshold)) return 0;         /* rule 1: enough water */
  float diff = c->ink[q] - c->ink[p];
  if (!(diff > k->ink_threshold)) return 0;                  /* rule 3: a large enough difference */
  float r = ink_resistance(c, x, y, k->roughness);
  float cost = r * (lp == 0 ? k->paper_cost : 1);
  float loss = k->ink_loss * cost;
  loss = loss < 0.95f ? loss : 0.95f;
  float water = c->water[q] - cost;
  o->pixel = (uint32_t)p;
  o->style = c->style[q];
  o->level = (uint8_t)lq;
  o->delay = (uint8_t)ink_delay(c, x, y, k->roughness);
  o->ink = c->ink[p] + (1 - loss) * diff;                    /* a little less than the giver has */
  o->water = water > c->water[p] ? water : c->water[p];      /* nobody loses water */
  return 1;
}

/* The best offer pixel (x, y)'s four neighbours make it in pass `pass`; 0
** if none. */
static int best_offer(const InkCanvas *c, int x, int y, int pass, Offer *best) {
  int w = c->width;
  size_t p = (size_t)y * w + x;
  if (c->level[p] == INK_OFF || !diffuses(c, c->style[p])) return 0;
  size_t nb[4];
  int n = 0;
  if (x > 0) nb[n++] = p - 1;
  if (x + 1 < w) nb[n++] = p + 1;
  if (y > 0) nb[n++] = p - (size_t)w;
  if (y + 1 < c->height) nb[n++] = p + (size_t)w;
  int found = 0;
  for (int i = 0; i < n; i++) {
    Offer o;
    if (offer_from(c, nb[i], p, x, y, pass, &o) && (!found || better(&o, best))) { *best = o; found = 1; }
  }
  return found;
}

/* Could some neighbour of p be darker (the cheap test before best_offer)? */
static int darker_beside(const InkCanvas *c, int x, int y) {
  size_t p = (size_t)y * c->width + x;
  unsigned lp = c->level[p];
  const uint8_t *L = c->level;
  if (lp == INK_OFF) return 0;
  return (x > 0 && L[p - 1] > lp && L[p - 1] != INK_OFF) ||
         (x + 1 < c->width && L[p + 1] > lp && L[p + 1] != INK_OFF) ||
         (y > 0 && L[p - c->width] > lp && L[p - c->width] != INK_OFF) ||
         (y + 1 < c->height && L[p + c->width] > lp && L[p + c->width] != INK_OFF);
}

typedef struct Updates { Offer *v; int n, cap; } Updates;

static void updates_add(Updates *u, const Offer *o) {
  u->v = xgrow(u->v, &u->cap, u->n + 1, sizeof *u->v);
  u->v[u->n++] = *o;
}

/* Pixels by the pass after which they can give: a ring of lists, one per
** pass ahead (a delay is at most INK_MAX_DELAY). */
typedef struct Ready { Updates at[INK_MAX_DELAY + 1]; } Ready;

/* Apply the pass's offers; each receiver can give from pass + delay on. */
static void apply(InkCanvas *c, const Updates *u, int pass, Ready *rd) {
  for (int i = 0; i < u->n; i++) {
    const Offer *o = &u->v[i];
    c->level[o->pixel] = o->level;
    c->style[o->pixel] = o->style;
    c->ink[o->pixel] = o->ink;
    c->water[o->pixel] = o->water;
    int ready = pass + o->delay - 1;
    c->ready[o->pixel] = (uint16_t)ready;
    updates_add(&rd->at[ready % (INK_MAX_DELAY + 1)], o);
  }
}

/* The first pass: every pixel of the canvas. */
static void first_pass(const InkCanvas *c, Updates *u) {
  for (int y = 0; y < c->height; y++)
    for (int x = 0; x < c->width; x++) {
      Offer o;
      if (darker_beside(c, x, y) && best_offer(c, x, y, 1, &o)) updates_add(u, &o);
    }
}

/* A later pass: the neighbours of the pixels that can give from this pass
** on (now), each once (seen holds the pass that looked at a pixel last). */
static void next_pass(const InkCanvas *c, const Updates *now, uint16_t *seen, int pass, Updates *u) {
  int w = c->width, h = c->height;
  static const int dx[4] = {-1, 1, 0, 0}, dy[4] = {0, 0, -1, 1};
  for (int i = 0; i < now->n; i++) {
    uint32_t g = now->v[i].pixel;
    if (c->ready[g] != pass - 1) continue;   /* it took a darker offer since: listed again */
    int x0 = (int)(g % (uint32_t)w), y0 = (int)(g / (uint32_t)w);
    for (int d = 0; d < 4; d++) {
      int x = x0 + dx[d], y = y0 + dy[d];
      if (x < 0 || y < 0 || x >= w || y >= h) continue;
      size_t p = (size_t)y * w + x;
      if (seen[p] == pass) continue;
      seen[p] = (uint16_t)pass;
      Offer o;
      if (best_offer(c, x, y, pass, &o)) updates_add(u, &o);
    }
  }
}

/* The most passes any style of the canvas allows. */
static int style_passes(const InkCanvas *c) {
  int most = 0;
  for (int i = 0; i < c->nstyles; i++)
    if (c->styles[i].stage >= INK_STAGE_DIFFUSED && c->styles[i].passes > most) most = c->styles[i].passes;
  return most;
}

static int ring_empty(const Ready *rd) {
  for (int i = 0; i <= INK_MAX_DELAY; i++)
    if (rd->at[i].n) return 0;
  return 1;
}

void ink_diffuse(InkCanvas *c, int max_passes, InkDiffuseStats *st) {
  int passes = style_passes(c);
  if (max_passes >= 0 && max_passes < passes) passes = max_passes;
  if (passes > INK_MAX_PASSES) passes = INK_MAX_PASSES;
  InkDiffuseStats s = {0, 0};
  if (passes <= 0) { if (st) *st = s; return; }
  size_t n = (size_t)c->width * c->height;
  NoiseFbm fbm;
  noise_fbm_init(&fbm, RESIST_PERIOD, 1, 0.5f, c->seed);
  c->fbm = &fbm;
  if (!c->noise) {
    c->noise = xmalloc((n + 1) * sizeof *c->noise);
    for (size_t i = 0; i < n; i++) c->noise[i] = -1;
  }
  c->ready = xcalloc(n + 1, sizeof *c->ready);   /* the first ink can give in pass 1 */
  uint16_t *seen = xcalloc(n + 1, sizeof *seen);
  Updates u = {0};
  Ready rd;
  memset(&rd, 0, sizeof rd);
  for (int pass = 1; pass <= passes; pass++) {
    u.n = 0;
    Updates *now = &rd.at[(pass - 1) % (INK_MAX_DELAY + 1)];
    if (pass == 1) first_pass(c, &u);
    else next_pass(c, now, seen, pass, &u);
    now->n = 0;
    apply(c, &u, pass, &rd);
    s.transfers += u.n;
    if (u.n) s.passes = pass;
    if (ring_empty(&rd)) break;   /* settled before the bound */
  }
  free(u.v);
  for (int i = 0; i <= INK_MAX_DELAY; i++) free(rd.at[i].v);
  free(seen);
  free(c->ready);
  c->ready = NULL;
  noise_fbm_free(&fbm);
  c->fbm = NULL;
  if (st) *st = s;
}

/* ---- the box filter ---------------------------------------------------------------- */

/* Sums of a side-wide window along one row of n values (src, stride 1),
** clipped at the ends, into dst; with wt, of src * wt. */
static void row_sums(const float *src, const uint8_t *wt, int n, int r, float *dst) {
  double acc = 0;
  for (int x = 0; x < r && x < n; x++) acc += wt ? (wt[x] ? src[x] : 0) : src[x];
  for (int x = 0; x < n; x++) {
    int in = x + r, out = x - r - 1;
    if (in < n) acc += wt ? (wt[in] ? src[in] : 0) : src[in];
    if (out >= 0) acc -= wt ? (wt[out] ? src[out] : 0) : src[out];
    dst[x] = (float)acc;
  }
}

/* Window counts along one row: weighted pixels, or the clipped width. */
static void row_counts(const uint8_t *wt, int n, int r, float *dst) {
  int acc = 0;
  for (int x = 0; x < r && x < n; x++) acc += wt ? wt[x] != 0 : 1;
  for (int x = 0; x < n; x++) {
    int in = x + r, out = x - r - 1;
    if (in < n) acc += wt ? wt[in] != 0 : 1;
    if (out >= 0) acc -= wt ? wt[out] != 0 : 1;
    dst[x] = (float)acc;
  }
}

/* The vertical half of the filter: column sums of the row sums rows
** (h rows of w), side-wide and clipped, divided by the same sums of counts. */
static void column_pass(float **rows, int nplanes, const float *counts, int w, int h, int r,
                        float **out) {
  double *acc = xcalloc((size_t)(nplanes + 1) * w, sizeof *acc);
  double *cnt = acc + (size_t)nplanes * w;
  for (int y = -r; y < h; y++) {
    int in = y + r, gone = y - r - 1;
    for (int k = 0; k <= nplanes; k++) {
      const float *src = k < nplanes ? rows[k] : counts;
      double *a = k < nplanes ? acc + (size_t)k * w : cnt;
      if (in < h) for (int x = 0; x < w; x++) a[x] += src[(size_t)in * w + x];
      if (gone >= 0) for (int x = 0; x < w; x++) a[x] -= src[(size_t)gone * w + x];
    }
    if (y < 0) continue;
    for (int k = 0; k < nplanes; k++)
      for (int x = 0; x < w; x++)
        out[k][(size_t)y * w + x] = cnt[x] > 0 ? (float)(acc[(size_t)k * w + x] / cnt[x]) : 0;
  }
  free(acc);
}

void ink_box_filter(float **planes, int nplanes, const uint8_t *weight, int w, int h, int side) {
  int r = side / 2;
  if (r <= 0 || nplanes <= 0) return;
  size_t n = (size_t)w * h;
  float *buf = xmalloc((size_t)(nplanes + 1) * n * sizeof *buf + 1);
  float *rows[16];
  if (nplanes > 16) nplanes = 16;
  for (int k = 0; k < nplanes; k++) rows[k] = buf + (size_t)k * n;
  float *counts = buf + (size_t)nplanes * n;
  for (int y = 0; y < h; y++) {
    const uint8_t *wt = weight ? weight + (size_t)y * w : NULL;
    for (int k = 0; k < nplanes; k++) row_sums(planes[k] + (size_t)y * w, wt, w, r, rows[k] + (size_t)y * w);
    row_counts(wt, w, r, counts + (size_t)y * w);
  }
  column_pass(rows, nplanes, counts, w, h, r, planes);
  free(buf);
}
