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

/* w x h planes of zeros, bare paper (the style plane INK_NO_STYLE), with
** or without a water plane and a style plane. */
static void canvas_planes(InkCanvas *c, int w, int h, const InkStyle *styles, int nstyles, int water, int style) {
  memset(c, 0, sizeof *c);
  size_t n = (size_t)w * h + 1;
  c->width = w;
  c->height = h;
  c->ink = mem_zeroed(n * sizeof *c->ink);   /* big planes: their pages are faulted as written */
  c->water = water ? mem_zeroed(n * sizeof *c->water) : NULL;
  c->level = mem_zeroed(n);
  c->style = style ? xmalloc_huge(n * sizeof *c->style) : NULL;
  if (style) memset(c->style, 0xff, n * sizeof *c->style);   /* INK_NO_STYLE */
  c->styles = styles;
  c->nstyles = nstyles;
}

void ink_canvas_init(InkCanvas *c, int w, int h, const InkStyle *styles, int nstyles) {
  canvas_planes(c, w, h, styles, nstyles, 1, 1);
}

void ink_canvas_init_lean(InkCanvas *c, int w, int h, const InkStyle *styles, int nstyles) {
  canvas_planes(c, w, h, styles, nstyles, 0, nstyles > 1);
}

void ink_canvas_free(InkCanvas *c) {
  size_t n = (size_t)c->width * c->height + 1;
  mem_zeroed_free(c->ink, n * sizeof *c->ink);
  mem_zeroed_free(c->water, n * sizeof *c->water);
  mem_zeroed_free(c->level, n);
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

/* ---- the cells ------------------------------------------------------------------- */

/* A pixel's diffusion state beyond its planes. Most pixels never take
** ink: they keep what they started with (a zero cell), their water the
** canvas's. */
typedef struct InkCell {
  float water;       /* with ready set: the pixel's water */
  uint32_t at;       /* a receiver in this pass: its offer's index + 1; else 0 */
  uint16_t ready;    /* the pass after which it can give (0: from the first, its water the canvas's) */
  uint8_t noise;     /* the resistance noise where computed, 1..255 (0: not yet) */
} InkCell;

/* The cells, in blocks of CELL_BLOCK pixels in a row (running on into the
** next), made as the diffusion first changes one of their pixels: the
** fronts of a 1080p frame reach a fifth of the blocks, and the pool's
** pages are cleared as they fill, so the state costs what it holds. */
#define CELL_BLOCK_BITS 6
#define CELL_BLOCK (1 << CELL_BLOCK_BITS)

typedef struct InkCells {
  uint32_t *block;   /* per block: its first cell in the pool; 0: not made (the pool's first
                        block, zeros, stands for them all and is never written) */
  InkCell *pool;
  uint32_t made;     /* blocks in the pool, the zero block among them */
  size_t blocks;
} InkCells;

static void cells_init(InkCanvas *c, InkCells *t) {
  t->blocks = ((size_t)c->width * c->height >> CELL_BLOCK_BITS) + 2;
  t->block = xcalloc(t->blocks, sizeof *t->block);
  t->pool = mem_zeroed(t->blocks * CELL_BLOCK * sizeof *t->pool);
  t->made = 1;
  c->cells = t;
}

static void cells_free(InkCanvas *c) {
  InkCells *t = c->cells;
  free(t->block);
  mem_zeroed_free(t->pool, t->blocks * CELL_BLOCK * sizeof *t->pool);
  c->cells = NULL;
}

/* Pixel p's cell, to read. */
static inline const InkCell *cell_at(const InkCanvas *c, size_t p) {
  return &c->cells->pool[c->cells->block[p >> CELL_BLOCK_BITS] + (p & (CELL_BLOCK - 1))];
}

/* Pixel p's cell, to change: its block made if need be. */
static inline InkCell *cell_of(const InkCanvas *c, size_t p) {
  InkCells *t = c->cells;
  uint32_t *b = &t->block[p >> CELL_BLOCK_BITS];
  if (!*b) *b = t->made++ << CELL_BLOCK_BITS;
  return &t->pool[*b + (p & (CELL_BLOCK - 1))];
}

/* ---- the paper's resistance --------------------------------------------------- */

/* The smooth part of the resistance: gradient noise of cells RESIST_CELL
** pixels, repeating every RESIST_PERIOD cells (far beyond what a front
** sees), in [0, 1]. */
#define RESIST_CELL 6
#define RESIST_PERIOD 64

/* The noise's lattice, and where each column and row of the canvas lie
** on it. */
typedef struct InkResist {
  NoiseFbm fbm;
  NoiseAxis *col, *row;
} InkResist;

/* The lattice of the canvas's frame pixels ((x + 0.5) / span across the unit
** square), for c->resist (freed by resist_free). */
static void resist_init(InkCanvas *c, InkResist *r) {
  const float span = RESIST_CELL * RESIST_PERIOD;
  noise_fbm_init(&r->fbm, RESIST_PERIOD, 1, 0.5f, c->seed);
  r->col = xmalloc((size_t)c->width * sizeof *r->col + 1);
  r->row = xmalloc((size_t)c->height * sizeof *r->row + 1);
  for (int x = 0; x < c->width; x++) noise_axis(&r->fbm, ((float)(x + c->ox) + 0.5f) / span, &r->col[x]);
  for (int y = 0; y < c->height; y++) noise_axis(&r->fbm, ((float)(y + c->oy) + 0.5f) / span, &r->row[y]);
  c->resist = r;
}

static void resist_free(InkCanvas *c, InkResist *r) {
  noise_fbm_free(&r->fbm);
  free(r->col);
  free(r->row);
  c->resist = NULL;
}

static float resist_noise(const InkCanvas *c, int x, int y) {
  const InkResist *r = c->resist;
  float v = 0.5f + 0.5f * noise_fbm_axes(&r->fbm, &r->col[x], &r->row[y]);
  return v < 0 ? 0 : v > 1 ? 1 : v;
}

/* The paper's absorbency under canvas pixel (x, y). */
static float absorb_at(const InkCanvas *c, int x, int y) {
  return c->absorb[c->absorb_row[y] + (size_t)c->absorb_col[x]];
}

/* The tables absorb_at reads (ink_diffuse's: freed by absorb_free). */
static void absorb_tables(InkCanvas *c) {
  if (!c->absorb) return;
  c->absorb_row = xmalloc((size_t)c->height * sizeof *c->absorb_row + 1);
  c->absorb_col = xmalloc((size_t)c->width * sizeof *c->absorb_col + 1);
  for (int y = 0; y < c->height; y++) c->absorb_row[y] = (size_t)((y + c->oy) % c->absorb_h) * c->absorb_w;
  for (int x = 0; x < c->width; x++) c->absorb_col[x] = (x + c->ox) % c->absorb_w;
}

static void absorb_free(InkCanvas *c) {
  free(c->absorb_row);
  free(c->absorb_col);
  c->absorb_row = NULL;
  c->absorb_col = NULL;
}

/* Pixel p's column and row, without a division: the quotient by a
** reciprocal, corrected to the exact one. */
static inline void pixel_xy(uint32_t p, uint32_t w, double inv_w, int *x, int *y) {
  uint32_t q = (uint32_t)((double)p * inv_w);
  if (q * w > p) q--;
  else if ((q + 1) * w <= p) q++;
  *x = (int)(p - q * w);
  *y = (int)q;
}

/* The paper's resistance to ink at pixel (x, y) for roughness rho: 1 +
** rho (2 n - 1) over the absorbency, n the smooth noise (cached in the
** pixel's state e): it scales a hop's loss and water cost. */
static float ink_resistance(const InkCanvas *c, InkCell *e, int x, int y, float rho) {
  if (!e->noise)   /* not yet: only pixels the diffusion reaches need it */
    e->noise = (uint8_t)(1 + resist_noise(c, x, y) * 254 + 0.5f);   /* 1..255: 0 says not yet */
  float n = (float)(e->noise - 1) * (1.0f / 254);
  float r = 1 + rho * (2 * n - 1);
  if (c->absorb) r /= absorb_at(c, x, y);
  return r > 0.1f ? r : 0.1f;
}

/* The passes before a pixel that took ink can pass it on: INK_DELAY times
** the same with the pixel's own random value (so growth from one point is
** irregular and roundish, not a diamond of four-neighbour steps). */
static int ink_delay(const InkCanvas *c, int x, int y, float rho) {
  Rng g;   /* the pixel's own random value */
  rng_seed_key(&g, c->seed, (uint32_t)(x + c->ox), (uint32_t)(y + c->oy));
  float r = 1 + rho * (2 * (float)rng_uniform(&g) - 1);
  if (c->absorb) r /= absorb_at(c, x, y);
  int d = (int)ceilf(INK_DELAY * r);
  return d < 1 ? 1 : d > INK_MAX_DELAY ? INK_MAX_DELAY : d;
}

/* ---- the pixels' state -------------------------------------------------------- */

/* Does style index s take part in the diffusion? */
static inline int diffuses(const InkCanvas *c, int s) {
  return s == INK_NO_STYLE || c->styles[s].stage >= INK_STAGE_DIFFUSED;
}

/* Does pixel p take part: not off the canvas, and its style diffuses?
** (With one style that does, its style need not be looked up: the
** planes are big and each one read is a cache miss at a front.) */
static inline int takes_part(const InkCanvas *c, size_t p) {
  return c->level[p] != INK_OFF && (c->one || diffuses(c, c->style[p]));
}

/* The style of ink pixel q. */
static inline const InkStyle *style_of(const InkCanvas *c, size_t q) {
  return c->one ? c->one : &c->styles[c->style[q]];
}

/* The water pixel p started with. */
static inline float water_at_start(const InkCanvas *c, size_t p) {
  if (c->water) return c->water[p];
  int l = c->level[p];   /* the washes are wet; the paper level (bare paper, highlights) is dry */
  return l != INK_OFF && l > 0 ? style_of(c, p)->water : 0;
}

/* Pixel p's water. */
static inline float water_of(const InkCanvas *c, size_t p) {
  const InkCell *e = cell_at(c, p);
  return e->ready ? e->water : water_at_start(c, p);
}

/* ---- diffusion ---------------------------------------------------------------- */

typedef struct Offer {
  uint32_t pixel, from;       /* the receiver and its giver */
  uint16_t style;
  uint8_t level, delay;
  float ink, water;
} Offer;

/* The rules split by what they read. Rule 2 and the paper's: does q's
** level run onto p's (darker to lighter; onto paper only from the light
** level)? */
static inline int level_runs(const InkCanvas *c, size_t q, size_t p) {
  int lq = c->level[q], lp = c->level[p];
  return lq > lp && (lp != 0 || lq == 1);
}

/* Giver q's style when q can give in pass `pass` at all (on the canvas,
** its water come through, its style diffusing, and rule 1: enough
** water); else NULL. */
static inline const InkStyle *giver_style(const InkCanvas *c, size_t q, int pass) {
  const InkCell *g = cell_at(c, q);
  if (c->level[q] == INK_OFF || g->ready >= pass) return NULL;
  const InkStyle *k = style_of(c, q);
  if (k->stage < INK_STAGE_DIFFUSED) return NULL;
  float water = g->ready ? g->water : water_at_start(c, q);
  return water > k->water_threshold ? k : NULL;
}

/* Rule 3, for giver q of style k: a large enough difference of ink. */
static inline int ink_runs(const InkCanvas *c, const InkStyle *k, size_t q, size_t p) {
  return c->ink[q] - c->ink[p] > k->ink_threshold;
}

/* May giver q give to receiver p in pass `pass` under the three rules? */
static inline int may_give(const InkCanvas *c, size_t q, size_t p, int pass) {
  if (!level_runs(c, q, p)) return 0;   /* the cheap test first: most neighbours fail it */
  const InkStyle *k = giver_style(c, q, pass);
  return k && ink_runs(c, k, q, p);
}

/* Does giver a come before giver b: darker (level, then ink, then water),
** and at a tie the one earlier in the image (so the order givers are
** looked at in does not matter)? */
static inline int darker(const InkCanvas *c, size_t a, size_t b) {
  if (c->level[a] != c->level[b]) return c->level[a] > c->level[b];
  if (c->ink[a] != c->ink[b]) return c->ink[a] > c->ink[b];
  float wa = water_of(c, a), wb = water_of(c, b);
  if (wa != wb) return wa > wb;
  return a < b;
}

/* What giver q gives pixel p (x, y): a little less ink than q has, its
** water less a step's cost, through the paper's resistance there. */
static void offer_from(const InkCanvas *c, size_t q, size_t p, int x, int y, Offer *o) {
  const InkStyle *k = style_of(c, q);
  InkCell *e = cell_of(c, p);
  float r = ink_resistance(c, e, x, y, k->roughness);
  float cost = r * (c->level[p] == 0 ? k->paper_cost : 1);
  float loss = k->ink_loss * cost;
  loss = loss < 0.95f ? loss : 0.95f;
  float water = water_of(c, q) - cost, ink = c->ink[p], own = water_of(c, p);
  o->pixel = (uint32_t)p;
  o->from = (uint32_t)q;
  o->style = c->one ? 0 : c->style[q];
  o->level = c->level[q];
  o->delay = (uint8_t)ink_delay(c, x, y, k->roughness);
  o->ink = ink + (1 - loss) * (c->ink[q] - ink);      /* its own plus (1 - loss) of the difference */
  o->water = water > own ? water : own;               /* nobody loses water */
}

/* The giver pixel (x, y) takes from in pass `pass`, into *giver: its
** darkest neighbour that may give; 0 if none may. */
static int best_giver(const InkCanvas *c, int x, int y, int pass, size_t *giver) {
  int w = c->width;
  size_t p = (size_t)y * w + x;
  if (!takes_part(c, p)) return 0;
  size_t nb[4];
  int n = 0, found = 0;
  if (x > 0) nb[n++] = p - 1;
  if (x + 1 < w) nb[n++] = p + 1;
  if (y > 0) nb[n++] = p - (size_t)w;
  if (y + 1 < c->height) nb[n++] = p + (size_t)w;
  for (int i = 0; i < n; i++)
    if (may_give(c, nb[i], p, pass) && (!found || darker(c, nb[i], *giver))) { *giver = nb[i]; found = 1; }
  return found;
}

/* The offer pixel (x, y) takes in pass `pass`; 0 if none. */
static int best_offer(const InkCanvas *c, int x, int y, int pass, Offer *best) {
  size_t giver;
  if (!best_giver(c, x, y, pass, &giver)) return 0;
  offer_from(c, giver, (size_t)y * c->width + x, x, y, best);
  return 1;
}

typedef struct Updates { Offer *v; int n, cap; } Updates;

static inline void updates_add(Updates *u, const Offer *o) {
  if (u->n == u->cap) u->v = xgrow(u->v, &u->cap, u->n + 1, sizeof *u->v);   /* full: twice the room */
  u->v[u->n++] = *o;
}

/* Pixels by the pass after which they can give: a ring of lists, one per
** pass ahead (a delay is at most INK_MAX_DELAY). */
typedef struct Ready { Updates at[INK_MAX_DELAY + 1]; } Ready;

/* Apply the pass's offers; each receiver can give from pass + delay on. */
/* The lists visit pixels scattered along the fronts, over planes far
** bigger than the caches: a pixel's state is fetched a few list entries
** ahead (a hint only; it changes nothing). */
#define INK_AHEAD 8

static inline void fetch_ahead(const InkCanvas *c, const Offer *v, int i, int n) {
  if (i + INK_AHEAD >= n) return;
  size_t p = v[i + INK_AHEAD].pixel, w = (size_t)c->width;
  __builtin_prefetch(cell_at(c, p));
  __builtin_prefetch(&c->ink[p]);
  __builtin_prefetch(&c->level[p]);
  if (p >= w) __builtin_prefetch(&c->ink[p - w]), __builtin_prefetch(&c->level[p - w]);
  if (p + w < w * (size_t)c->height) __builtin_prefetch(&c->ink[p + w]), __builtin_prefetch(&c->level[p + w]);
}

static void apply(InkCanvas *c, const Updates *u, int pass, Ready *rd) {
  for (int i = 0; i < u->n; i++) {
    const Offer *o = &u->v[i];
    fetch_ahead(c, u->v, i, u->n);
    InkCell *e = cell_of(c, o->pixel);
    c->level[o->pixel] = o->level;
    if (c->style) c->style[o->pixel] = o->style;
    c->ink[o->pixel] = o->ink;
    e->water = o->water;
    if (c->water) c->water[o->pixel] = o->water;   /* the planes the canvas keeps */
    int ready = pass + o->delay - 1;
    e->ready = (uint16_t)ready;
    e->at = 0;   /* no longer this pass's receiver */
    updates_add(&rd->at[ready % (INK_MAX_DELAY + 1)], o);
  }
}

/* Row y's pixels that have a darker neighbour (levels; off the canvas
** counts as nothing), flagged in near (w bytes): the cheap test before
** best_offer, several pixels at a time. Levels go up by one so that off
** (255) becomes 0. */
static void darker_row(const InkCanvas *c, int y, uint8_t *restrict near) {
  int w = c->width;
  const uint8_t *row = c->level + (size_t)y * w;
  const uint8_t *up = y > 0 ? row - w : row, *down = y + 1 < c->height ? row + w : row;   /* itself: not darker */
  near[0] = near[w - 1] = 1;   /* the ends: best_offer looks */
  for (int x = 1; x + 1 < w; x++) {
    uint8_t me = (uint8_t)(row[x] + 1), m = (uint8_t)(row[x - 1] + 1), v;
    v = (uint8_t)(row[x + 1] + 1); m = v > m ? v : m;
    v = (uint8_t)(up[x] + 1); m = v > m ? v : m;
    v = (uint8_t)(down[x] + 1); m = v > m ? v : m;
    near[x] = (uint8_t)((m > me) & (me != 0));
  }
}

/* The first pass: every pixel of the canvas with a darker neighbour. */
static void first_pass(const InkCanvas *c, Updates *u) {
  uint8_t *near = xmalloc((size_t)c->width + 2);
  for (int y = 0; y < c->height; y++) {
    darker_row(c, y, near);
    for (const uint8_t *at = near, *end = near + c->width; (at = memchr(at, 1, (size_t)(end - at))); at++) {
      Offer o;   /* the flagged pixels, skipping the runs of others at once */
      if (best_offer(c, (int)(at - near), y, 1, &o)) updates_add(u, &o);
    }
  }
  free(near);
}

/* Receiver p (x, y) with the offer from giver q: the
** first offer it gets this pass, or a darker giver's instead of the one it
** has (its state holds the offer's index). */
/* The offer itself is worked out once the pass's givers are known
** (offers_of), from the state before the pass, as it would be now. */
static void take(const InkCanvas *c, size_t q, size_t p, Updates *u) {
  InkCell *e = cell_of(c, p);
  if (e->at) {
    Offer *o = &u->v[e->at - 1];
    if (darker(c, q, o->from)) o->from = (uint32_t)q;
    return;
  }
  e->at = (uint32_t)u->n + 1;
  Offer o;
  o.pixel = (uint32_t)p;
  o.from = (uint32_t)q;
  updates_add(u, &o);
}

/* The offers of the receivers in u, each from its giver. */
static void offers_of(const InkCanvas *c, Updates *u) {
  uint32_t w = (uint32_t)c->width;
  double inv_w = 1.0 / w;
  for (int i = 0; i < u->n; i++) {
    Offer *o = &u->v[i];
    int x, y;
    fetch_ahead(c, u->v, i, u->n);
    pixel_xy(o->pixel, w, inv_w, &x, &y);
    offer_from(c, o->from, o->pixel, x, y, o);
  }
}

/* Giver q, of style k and able to give, offers to its neighbour p when
** the rules let it: may_give's tests, q's own made once for its four. */
static inline void offer_to(const InkCanvas *c, const InkStyle *k, size_t q, size_t p, Updates *u) {
  if (level_runs(c, q, p) && takes_part(c, p) && ink_runs(c, k, q, p)) take(c, q, p, u);
}

/* A later pass. A pixel's best offer can change only when it or a
** neighbour changed: so the pixels that took ink in the last pass (last)
** look at all their neighbours again, and the pixels that can give from
** this pass on (now) offer to theirs; a neighbour that could give before
** made its offers then and, the receiver unchanged, a refusal stands. */
static void next_pass(const InkCanvas *c, const Updates *last, const Updates *now, int pass, Updates *u) {
  int w = c->width, h = c->height;
  double inv_w = 1.0 / w;
  for (int i = 0; i < last->n; i++) {
    uint32_t p = last->v[i].pixel;
    fetch_ahead(c, last->v, i, last->n);
    int x, y;
    pixel_xy(p, (uint32_t)w, inv_w, &x, &y);
    size_t q;
    if (!cell_at(c, p)->at && best_giver(c, x, y, pass, &q)) take(c, q, p, u);
  }
  for (int i = 0; i < now->n; i++) {
    uint32_t q = now->v[i].pixel;
    fetch_ahead(c, now->v, i, now->n);
    if (cell_at(c, q)->ready != pass - 1) continue;   /* it took a darker offer since: listed again */
    const InkStyle *k = giver_style(c, q, pass);
    if (!k) continue;
    int x0, y0;
    pixel_xy(q, (uint32_t)w, inv_w, &x0, &y0);
    if (x0 > 0) offer_to(c, k, q, q - 1, u);   /* left, right, up, down */
    if (x0 + 1 < w) offer_to(c, k, q, q + 1, u);
    if (y0 > 0) offer_to(c, k, q, q - (size_t)w, u);
    if (y0 + 1 < h) offer_to(c, k, q, q + (size_t)w, u);
  }
  offers_of(c, u);
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

/* The passes to run: the styles' bound, max_passes if it is lower. */
static int pass_bound(const InkCanvas *c, int max_passes) {
  int passes = style_passes(c);
  if (max_passes >= 0 && max_passes < passes) passes = max_passes;
  return passes > INK_MAX_PASSES ? INK_MAX_PASSES : passes;
}

void ink_diffuse_every_pixel(InkCanvas *c, int max_passes, InkDiffuseStats *st) {
  int passes = pass_bound(c, max_passes);
  InkResist resist;
  resist_init(c, &resist);
  absorb_tables(c);
  c->one = c->nstyles == 1 && diffuses(c, 0) ? &c->styles[0] : NULL;
  InkCells cells;
  cells_init(c, &cells);
  Updates u = {0};
  Ready rd;
  memset(&rd, 0, sizeof rd);
  InkDiffuseStats s = {0, 0};
  for (int pass = 1; pass <= passes; pass++) {
    u.n = 0;
    for (int y = 0; y < c->height; y++)
      for (int x = 0; x < c->width; x++) {
        Offer o;
        if (best_offer(c, x, y, pass, &o)) updates_add(&u, &o);
      }
    for (int i = 0; i <= INK_MAX_DELAY; i++) rd.at[i].n = 0;   /* no lists needed: every pixel looks */
    apply(c, &u, pass, &rd);
    s.transfers += u.n;
    if (u.n) s.passes = pass;
  }
  free(u.v);
  for (int i = 0; i <= INK_MAX_DELAY; i++) free(rd.at[i].v);
  cells_free(c);
  resist_free(c, &resist);
  c->one = NULL;
  absorb_free(c);
  if (st) *st = s;
}

void ink_diffuse(InkCanvas *c, int max_passes, InkDiffuseStats *st) {
  int passes = pass_bound(c, max_passes);
  InkDiffuseStats s = {0, 0};
  if (passes <= 0) { if (st) *st = s; return; }
  InkResist resist;
  resist_init(c, &resist);
  absorb_tables(c);
  c->one = c->nstyles == 1 && diffuses(c, 0) ? &c->styles[0] : NULL;
  InkCells cells;
  cells_init(c, &cells);
  Updates u = {0}, last = {0};
  Ready rd;
  memset(&rd, 0, sizeof rd);
  for (int pass = 1; pass <= passes; pass++) {
    u.n = 0;
    Updates *now = &rd.at[(pass - 1) % (INK_MAX_DELAY + 1)];
    if (pass == 1) first_pass(c, &u);
    else next_pass(c, &last, now, pass, &u);
    now->n = 0;
    apply(c, &u, pass, &rd);
    s.transfers += u.n;
    if (u.n) s.passes = pass;
    Updates t = last; last = u; u = t;   /* this pass's receivers look again in the next */
    if (ring_empty(&rd) && last.n == 0) break;   /* settled before the bound */
  }
  free(u.v);
  free(last.v);
  for (int i = 0; i <= INK_MAX_DELAY; i++) free(rd.at[i].v);
  cells_free(c);
  resist_free(c, &resist);
  c->one = NULL;
  absorb_free(c);
  if (st) *st = s;
}

/* ---- the box filter ---------------------------------------------------------------- */

/* The box sums below add each window's values afresh, left to right (top
** to bottom), not as running sums: a pixel's result then depends on its
** window alone, not on where the filtered rectangle begins, so a tile's
** canvas (a window of the frame, its ink elsewhere in it) gets the bits
** the whole frame gets. Each sum starts from 0.0 and adds in double, in
** that order, however the loops below are arranged: the loops run across
** the outputs (SIMD lanes), each output's own additions in order. */

/* Window sums along row src (w values) for outputs x0..x1-1 into dst:
** each sums src over [x - r, x + r] clipped to the row; acc is scratch
** for x1 - x0 doubles. */
static void row_sums(const float *src, int w, int x0, int x1, int r, double *restrict acc,
                     float *restrict dst) {
  int i0 = x0 > r ? x0 : r, i1 = x1 < w - r ? x1 : w - r;   /* the windows wholly inside the row */
  if (i1 < i0) i1 = i0;
  for (int x = x0; x < x1; x++) {   /* the clipped ones */
    if (x >= i0 && x < i1) { x = i1 - 1; continue; }
    int a = x - r > 0 ? x - r : 0, e = x + r < w - 1 ? x + r : w - 1;
    double s = 0;
    for (int j = a; j <= e; j++) s += src[j];
    dst[x - x0] = (float)s;
  }
  float *restrict d = dst + (i0 - x0);
  const float *s = src + i0 - r;
  int n = i1 - i0;
  if (r == 2) {   /* the 5 x 5 box, the default */
    for (int i = 0; i < n; i++) {
      double v = 0.0 + s[i];
      v += s[i + 1];
      v += s[i + 2];
      v += s[i + 3];
      v += s[i + 4];
      d[i] = (float)v;
    }
    return;
  }
  for (int i = 0; i < n; i++) acc[i] = 0.0 + s[i];
  for (int j = 1; j <= 2 * r; j++)
    for (int i = 0; i < n; i++) acc[i] += s[i + j];
  for (int i = 0; i < n; i++) d[i] = (float)acc[i];
}

/* Column sums of the n rows rows[0..n-1] (m values each), top down, into acc. */
static void column_sums(const float *const *rows, int n, size_t m, double *restrict acc) {
  if (n == 5) {
    const float *r0 = rows[0], *r1 = rows[1], *r2 = rows[2], *r3 = rows[3], *r4 = rows[4];
    for (size_t i = 0; i < m; i++) {
      double v = 0.0 + r0[i];
      v += r1[i];
      v += r2[i];
      v += r3[i];
      v += r4[i];
      acc[i] = v;
    }
    return;
  }
  for (size_t i = 0; i < m; i++) acc[i] = 0.0 + rows[0][i];
  for (int k = 1; k < n; k++) {
    const float *row = rows[k];
    for (size_t i = 0; i < m; i++) acc[i] += row[i];
  }
}

/* The columns [*lo, *hi) of [m0, m1) holding the row's nonzero values of
** any of the nplanes rows src[k] (empty: lo = hi). */
static void nonzero_span(const float *const *src, int nplanes, int m0, int m1, int *lo, int *hi) {
  int a = m1, e = m0;
  for (int k = 0; k < nplanes; k++) {
    a = ink_first_nonzero(src[k], m0, a);
    e = ink_nonzero_end(src[k], e, m1);
  }
  *lo = a < e ? a : 0;
  *hi = a < e ? e : 0;
}

/* Horizontal sums of row y of every plane (and of the weights, as the
** last, when weighted) into dst: nq rows of rw floats. Only the columns
** the windows read, [rx0 - r, rx1 + r), are masked. Where a window holds
** only zeros its sum is +0 (0.0 plus zeros): the data planes' sums are
** worked out only around the row's nonzero values, the rest set to 0, and
** the outputs that may be nonzero, [*x0, *x1) of 0 .. rw, returned. */
static void hsum_row(float **planes, int nplanes, const uint8_t *weight, int w, int y, int rx0, int rx1, int r,
                     float *masked, double *acc, float *dst, int *x0, int *x1) {
  int rw = rx1 - rx0, m0 = rx0 - r > 0 ? rx0 - r : 0, m1 = rx1 + r < w ? rx1 + r : w;
  const uint8_t *wt = weight ? weight + (size_t)y * w : NULL;
  const float *rows[4];
  for (int k = 0; k < nplanes && k < 4; k++) rows[k] = planes[k] + (size_t)y * w;
  int lo = m0, hi = m1;   /* more than four planes: every column */
  if (nplanes <= 4) nonzero_span(rows, nplanes, m0, m1, &lo, &hi);
  int a = lo - r - rx0, e = hi + r - rx0;   /* the outputs whose windows reach them */
  a = a > 0 ? a : 0;
  e = e < rw ? e : rw;
  if (a >= e) a = e = 0;
  *x0 = a;
  *x1 = e;
  for (int k = 0; k < nplanes + (weight != NULL); k++) {
    const float *src = k < nplanes ? planes[k] + (size_t)y * w : NULL;
    float *d = dst + (size_t)k * rw;
    int ka = k < nplanes ? a : 0, ke = k < nplanes ? e : rw;   /* the weights' sums: everywhere */
    if (wt) {   /* the weighted pixels only; the last plane sums the weights */
      if (src)
        for (int x = m0; x < m1; x++) masked[x] = wt[x] ? src[x] : 0;
      else
        for (int x = m0; x < m1; x++) masked[x] = wt[x] ? 1 : 0;
      src = masked;
    }
    for (int x = 0; x < ka; x++) d[x] = 0;
    for (int x = ke; x < rw; x++) d[x] = 0;
    if (ka < ke) row_sums(src, w, rx0 + ka, rx0 + ke, r, acc, d + ka);
  }
}

void ink_box_filter_rect(float **planes, int nplanes, const uint8_t *weight, int w, int h, int side,
                         int rx0, int ry0, int rx1, int ry1) {
  int r = side / 2;
  if (r <= 0 || nplanes <= 0 || rx0 >= rx1 || ry0 >= ry1) return;
  int hy0 = ry0 - r > 0 ? ry0 - r : 0, hy1 = ry1 + r < h ? ry1 + r : h;   /* rows the windows read */
  int rw = rx1 - rx0, nq = nplanes + (weight != NULL), ring = side + 1;
  size_t m = (size_t)nq * rw;
  /* the horizontal sums of the last side + 1 rows: a row is read by the
  ** boxes of the side rows around it, and overwritten only after that */
  float *hs = xmalloc((size_t)ring * m * sizeof *hs + 1);
  int *span = xmalloc((size_t)ring * 2 * sizeof *span);             /* each ring row's nonzero outputs */
  float *masked = xmalloc((size_t)w * sizeof *masked + 1);          /* a row times its weight */
  double *acc = xmalloc(m * sizeof *acc + 1);                       /* the column sums */
  double *racc = xmalloc((size_t)rw * sizeof *racc + 1);            /* a row's window sums */
  float *cols = xmalloc((size_t)rw * sizeof *cols + 1), *inv = xmalloc((size_t)rw * sizeof *inv + 1);
  const float **rows = xmalloc((size_t)side * sizeof *rows);
  for (int x = 0; x < rw; x++) {   /* a box's columns inside the image */
    int cx = rx0 + x;
    cols[x] = (float)((cx + r < w ? cx + r : w - 1) - (cx - r > 0 ? cx - r : 0) + 1);
  }
  float inv_rows = -1;   /* the rows inv was worked out for (unweighted) */
  int next = hy0;   /* the next row whose horizontal sums go into the ring */
  for (int y = ry0; y < ry1; y++) {
    for (; next <= y + r && next < hy1; next++) {   /* rows in: their sums from the planes as they were */
      int slot = (next - hy0) % ring;
      hsum_row(planes, nplanes, weight, w, next, rx0, rx1, r, masked, racc, hs + (size_t)slot * m,
               &span[2 * slot], &span[2 * slot + 1]);
    }
    int a = y - r > hy0 ? y - r : hy0, e = y + r < hy1 - 1 ? y + r : hy1 - 1;
    int ua = rw, ub = 0;   /* the outputs some row of the box has nonzero sums at */
    for (int yy = a; yy <= e; yy++) {
      int slot = (yy - hy0) % ring;
      if (span[2 * slot] < span[2 * slot + 1]) {
        ua = span[2 * slot] < ua ? span[2 * slot] : ua;
        ub = span[2 * slot + 1] > ub ? span[2 * slot + 1] : ub;
      }
    }
    if (ua >= ub) ua = ub = 0;
    for (int k = 0; k < nq; k++) {   /* the column sums of the box's rows, top down */
      int ka = k < nplanes ? ua : 0, ke = k < nplanes ? ub : rw;
      for (int yy = a; yy <= e; yy++) rows[yy - a] = hs + (size_t)((yy - hy0) % ring) * m + (size_t)k * rw + ka;
      if (ka < ke) column_sums(rows, e - a + 1, (size_t)(ke - ka), acc + (size_t)k * rw + ka);
    }
    float nrows = (float)((y + r < h ? y + r : h - 1) - (y - r > 0 ? y - r : 0) + 1);
    if (weight) {   /* the box's pixels: weighted ones */
      const double *cnt = acc + (size_t)nplanes * rw;
      for (int x = ua; x < ub; x++) inv[x] = cnt[x] > 0.5 ? (float)(1 / cnt[x]) : 0;
    } else if (nrows != inv_rows) {   /* those inside the image */
      for (int x = 0; x < rw; x++) inv[x] = 1 / (nrows * cols[x]);
      inv_rows = nrows;
    }
    for (int k = 0; k < nplanes; k++) {   /* row y's own sums are in the ring: it may change now */
      float *restrict dst = planes[k] + (size_t)y * w + rx0;
      const double *sum = acc + (size_t)k * rw;
      /* outside [ua, ub) the windows hold only zeros, row y's own values
      ** among them (its sums' span covers every value of it that is not
      ** zero): they are zeros already, and are left so */
      for (int x = ua; x < ub; x++) dst[x] = (float)sum[x] * inv[x];
    }
  }
  free(rows);
  free(cols);
  free(inv);
  free(racc);
  free(acc);
  free(masked);
  free(span);
  free(hs);
}

void ink_box_filter(float **planes, int nplanes, const uint8_t *weight, int w, int h, int side) {
  ink_box_filter_rect(planes, nplanes, weight, w, h, side, 0, 0, w, h);
}
