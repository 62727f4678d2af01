/*
** Strokes: building (scaling, filtering, ribs) and drawing (coverage per
** stroke, then "over" compositing) of the polylines of the line stage.
*/
#include "stroke.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"
#include "../base/rng.h"

static float clampf(float x, float lo, float hi) { return x < lo ? lo : x > hi ? hi : x; }

/* ---- procedural ink -------------------------------------------------------- */

/* A lattice value in [0, 1) for integer i (integer hash, lowbias32). */
static float lattice(int32_t i) {
  uint32_t x = (uint32_t)i;
  x ^= x >> 16; x *= 0x7feb352dU;
  x ^= x >> 15; x *= 0x846ca68bU;
  x ^= x >> 16;
  return (float)(x >> 8) * (1.0f / 16777216.0f);
}

/* fminf and fmaxf without the call: the smaller (larger), or the one that
** is not NaN. */
static float minf(float a, float b) { return a < b || b != b ? a : b; }
static float maxf(float a, float b) { return a > b || b != b ? a : b; }

/* (int)floorf(x) and (int)ceilf(x) without the rounding sequence, for
** |x| < 2^31, where the conversion is defined. */
static int floor_int(float x) {
  int i = (int)x;
  if ((float)i > x) i--;   /* x < 0, not whole */
  return i;
}

static int ceil_int(float x) {
  int i = (int)x;
  if ((float)i < x) i++;   /* x > 0, not whole */
  return i;
}

/* A channel of smooth 1D value noise in [0, 1). It keeps its last
** lattice cell: along a stroke the next pixel is mostly in the same one. */
typedef struct Noise { int32_t i; float l0, l1; } Noise;

static void noise_init(Noise *n) {
  n->i = 0;
  n->l0 = lattice(0);
  n->l1 = lattice(1);
}

/* The noise at x. */
static inline float vnoise(Noise *n, float x) {
  int32_t i = floor_int(x);
  float fl = (float)i, f = x - fl;
  float t = f * f * (3 - 2 * f);
  if (i != n->i) { n->i = i; n->l0 = lattice(i); n->l1 = lattice(i + 1); }
  return n->l0 + t * (n->l1 - n->l0);
}

/* The procedural ink of one stroke: its phases, length len, width W (at
** least 1) and noise channels (dry, streak, ragged). */
typedef struct Ink { const float *phase; float len, W; Noise n[3]; } Ink;

static void ink_init(Ink *k, const float phase[4], float len, float w) {
  k->phase = phase;
  k->len = len;
  k->W = w > 1 ? w : 1;
  for (int j = 0; j < 3; j++) noise_init(&k->n[j]);
}

/* The factors of the ink that depend on the arc length s alone (a join,
** at one s, works them out once). */
typedef struct InkAlong { float s, along, drift, ends; } InkAlong;

static inline void ink_along(Ink *k, float s, InkAlong *a) {
  float W = k->W;
  a->s = s;
  /* mostly full ink (composited in linear light, 90 % ink already reads
  ** grey), with rare thin patches where the brush ran dry and streaks */
  float dry = vnoise(&k->n[0], s / (8 * W) + k->phase[0]);
  a->along = 1 - 0.25f * dry * dry * dry * dry;
  a->drift = s / (40 * W);
  /* softer ends; m >= W makes m / W >= 1, which the clamp takes to 1 */
  float m = minf(s, k->len - s);
  a->ends = 0.6f + 0.4f * (m >= W ? 1 : clampf(m / W, 0, 1));
}

/* The ink at across position v. It is at most a->along * a->ends: every
** other factor is in [0, 1]. */
static inline float ink_across(Ink *k, const InkAlong *a, float v) {
  float streak = vnoise(&k->n[1], v * 6 + k->phase[1] + a->drift);
  float fibre = 1 - 0.08f * streak * streak;
  float edge = fabsf(2 * v - 1);                                             /* 1 at the sides */
  float ragged = edge > 0.85f
                     ? 1 - (edge - 0.85f) / 0.15f * 0.5f * vnoise(&k->n[2], a->s / (1.5f * k->W) + k->phase[2])
                     : 1;
  return clampf(a->along * fibre * ragged * a->ends, 0, 1);
}

float stroke_ink(const float phase[4], float s, float len, float v, float w) {
  Ink k;
  ink_init(&k, phase, len, w);
  InkAlong a;
  ink_along(&k, s, &a);
  return ink_across(&k, &a, v);
}

/* The ink of an image texture at arc length s and across position v. */
static float image_ink(const Image *img, float s, float v, float w) {
  int tw = img->width, th = img->height, ch = img->channels;
  float aspect = (float)tw / (float)th;
  float x = s / (w * aspect) * (float)tw - 0.5f, y = (1 - v) * (float)(th - 1);
  float fx = floorf(x), fy = floorf(y);
  float ax = x - fx, ay = y - fy;
  int x0 = ((int)fx % tw + tw) % tw, x1 = (x0 + 1) % tw;
  int y0 = (int)clampf(fy, 0, (float)(th - 1)), y1 = y0 + 1 < th ? y0 + 1 : th - 1;
  int alpha = image_alpha_channel(img);
  float acc = 0;
  for (int k = 0; k < 4; k++) {
    int xx = k & 1 ? x1 : x0, yy = k & 2 ? y1 : y0;
    float wt = (k & 1 ? ax : 1 - ax) * (k & 2 ? ay : 1 - ay);
    const float *p = img->data + ((size_t)yy * tw + xx) * ch;
    float ink;
    if (alpha >= 0) ink = p[alpha];
    else if (ch >= 3) ink = 1 - (0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2]);
    else ink = 1 - p[0];
    acc += wt * ink;
  }
  return clampf(acc, 0, 1);
}

/* The ink of st's texture at (s, v); ink is st's procedural ink. */
static inline float texture_at(const Stroke *st, Ink *ink, float s, float v) {
  if (st->solid) return 1;
  if (st->texture) return image_ink(st->texture, s, v, st->width);
  InkAlong a;
  ink_along(ink, s, &a);
  return ink_across(ink, &a, v);
}

/* ---- building ---------------------------------------------------------------- */

/* The image texture named name, read once per list. */
static const Image *texture_get(StrokeList *sl, const char *name, char *err, size_t errlen) {
  for (int i = 0; i < sl->ntex; i++)
    if (strcmp(sl->tex_name[i], name) == 0) return sl->tex[i];
  Image *img = NULL;
  if (!image_read(name, &img, err, errlen)) return NULL;
  if (img->width < 1 || img->height < 1) {
    snprintf(err, errlen, "%s: stroke texture has no pixels", name);
    image_destroy(img);
    return NULL;
  }
  int cap = sl->cap_tex;
  sl->tex = xgrow(sl->tex, &cap, sl->ntex + 1, sizeof *sl->tex);
  sl->tex_name = xgrow(sl->tex_name, &sl->cap_tex, sl->ntex + 1, sizeof *sl->tex_name);
  sl->tex[sl->ntex] = img;
  sl->tex_name[sl->ntex] = xstrdup(name);
  sl->ntex++;
  return img;
}

/* Ribs of a ribbon: left/right ends at each point (001 §2.1.6). */
static void build_ribs(Stroke *st, double miter_limit) {
  int n = st->npts;
  const float *p = st->pts;
  st->left = xmalloc((size_t)n * 2 * sizeof *st->left);
  st->right = xmalloc((size_t)n * 2 * sizeof *st->right);
  for (int i = 0; i < n; i++) {
    int prev = i > 0 ? i - 1 : (st->closed ? n - 2 : i);
    int next = i < n - 1 ? i + 1 : (st->closed ? 1 : i);
    double dx = p[2 * next] - p[2 * prev], dy = p[2 * next + 1] - p[2 * prev + 1];
    double len = sqrt(dx * dx + dy * dy);
    if (len < 1e-9) { dx = 1; dy = 0; len = 1; }
    double rx = -dy / len, ry = dx / len;   /* rib: perpendicular to v[i+1] - v[i-1] */
    double f = 1;
    if (prev != i && next != i) {
      /* miter factor |r| / (r . n), n the unit normal of v[i+1] - v[i] */
      double ex = p[2 * next] - p[2 * i], ey = p[2 * next + 1] - p[2 * i + 1];
      double el = sqrt(ex * ex + ey * ey);
      double c = el > 1e-9 ? (rx * -ey + ry * ex) / el : 1;
      f = c * miter_limit > 1 ? 1 / c : miter_limit;
      if (f < 1) f = 1;
    }
    double hw = 0.5 * st->width * f;
    st->left[2 * i] = (float)(p[2 * i] + rx * hw);
    st->left[2 * i + 1] = (float)(p[2 * i + 1] + ry * hw);
    st->right[2 * i] = (float)(p[2 * i] - rx * hw);
    st->right[2 * i + 1] = (float)(p[2 * i + 1] - ry * hw);
  }
}

static void stroke_box(Stroke *st) {
  float pad = st->width + 2;
  if (st->left) {   /* miters reach further than the width */
    for (int i = 0; i < 2 * st->npts; i++) {
      pad = fmaxf(pad, fabsf(st->left[i] - st->pts[i]) + 2);
    }
  }
  st->box[0] = st->box[2] = st->pts[0];
  st->box[1] = st->box[3] = st->pts[1];
  for (int i = 1; i < st->npts; i++) {
    st->box[0] = fminf(st->box[0], st->pts[2 * i]);
    st->box[2] = fmaxf(st->box[2], st->pts[2 * i]);
    st->box[1] = fminf(st->box[1], st->pts[2 * i + 1]);
    st->box[3] = fmaxf(st->box[3], st->pts[2 * i + 1]);
  }
  st->box[0] -= pad; st->box[1] -= pad; st->box[2] += pad; st->box[3] += pad;
}

static void stroke_free(Stroke *st) {
  free(st->pts); free(st->s); free(st->left); free(st->right);
  brush_path_free(st->brush);
  free(st->brush);
}

/* A ribbon's points are at least its width / STROKE_POINTS_PER_WIDTH
** apart (and 0.25 px). Each point's join and quad cover about width^2
** pixels, so this bounds a stroke's work by some 16 times its own area,
** however wide: a `width 1000` silhouette of ~900 points at 800 x 600
** took 10.6G instructions to draw solid ink. Below 4 px wide it is the
** 0.25 px rule alone. */
#define STROKE_POINTS_PER_WIDTH 16

/* Copy polyline k of polys scaled to the output into st (points closer
** than gap merged); returns its length. */
static double scaled_points(Stroke *st, const LinePolys *polys, int k, double sx, double sy,
                            float gap) {
  int a = polys->start[k], n = polys->start[k + 1] - a;
  st->pts = xmalloc((size_t)n * 2 * sizeof *st->pts);
  st->s = xmalloc((size_t)n * sizeof *st->s);
  int m = 0;
  for (int i = 0; i < n; i++) {
    float x = (float)(polys->pts[2 * (a + i)] * sx), y = (float)(polys->pts[2 * (a + i) + 1] * sy);
    if (m > 0 && hypotf(x - st->pts[2 * m - 2], y - st->pts[2 * m - 1]) < gap) {
      if (i < n - 1) continue;   /* too close to its neighbour to shape a rib */
      if (m > 1) m--;            /* the end point replaces the close one */
    }
    st->pts[2 * m] = x;
    st->pts[2 * m + 1] = y;
    st->s[m] = m > 0 ? st->s[m - 1] + hypotf(x - st->pts[2 * m - 2], y - st->pts[2 * m - 1]) : 0;
    m++;
  }
  /* drop inner points where the line doubles back (turns by more than
  ** 120°): a rib there has no direction and its miter would spike */
  int kept = 0;
  for (int i = 0; i < m; i++) {
    if (kept >= 1 && i + 1 < m) {
      float ax = st->pts[2 * i] - st->pts[2 * kept - 2], ay = st->pts[2 * i + 1] - st->pts[2 * kept - 1];
      float bx = st->pts[2 * i + 2] - st->pts[2 * i], by = st->pts[2 * i + 3] - st->pts[2 * i + 1];
      if (ax * bx + ay * by < -0.5f * hypotf(ax, ay) * hypotf(bx, by)) continue;
    }
    st->pts[2 * kept] = st->pts[2 * i];
    st->pts[2 * kept + 1] = st->pts[2 * i + 1];
    st->s[kept] = kept > 0 ? st->s[kept - 1] + hypotf(st->pts[2 * kept] - st->pts[2 * kept - 2],
                                             st->pts[2 * kept + 1] - st->pts[2 * kept - 1]) : 0;
    kept++;
  }
  m = kept;
  double len = m > 0 ? st->s[m - 1] : 0;
  st->npts = m;
  return len;
}

/* The brush stroke along polyline k of polys, scaled to the output (003,
** brush.h): the brush's steps become the points and its width profile the
** outline. Returns the length of the control polyline, 0 when it has
** none. */
static double build_brush(Stroke *st, const LinePolys *polys, int k, double sx, double sy,
                          const SceneBrush *b, const BrushBristles *br, Rng *r) {
  int a = polys->start[k], n = polys->start[k + 1] - a;
  float *c = xmalloc((size_t)n * 2 * sizeof *c);
  double len = 0;
  for (int i = 0; i < n; i++) {
    c[2 * i] = (float)(polys->pts[2 * (a + i)] * sx);
    c[2 * i + 1] = (float)(polys->pts[2 * (a + i) + 1] * sy);
    if (i > 0) len += hypotf(c[2 * i] - c[2 * i - 2], c[2 * i + 1] - c[2 * i - 1]);
  }
  BrushPath *bp = xcalloc(1, sizeof *bp);
  if (!brush_path_build(bp, c, n, b, br, r)) len = 0;
  free(c);
  if (len <= 0) { free(bp); return 0; }
  st->brush = bp;
  st->npts = bp->nsteps;
  st->pts = xmalloc((size_t)bp->nsteps * 2 * sizeof *st->pts);
  st->s = xmalloc((size_t)bp->nsteps * sizeof *st->s);
  for (int i = 0; i < bp->nsteps; i++) {
    st->pts[2 * i] = bp->x[i];
    st->pts[2 * i + 1] = bp->y[i];
    st->s[i] = bp->s[i];
  }
  st->left = xmalloc((size_t)bp->nsteps * 2 * sizeof *st->left);
  st->right = xmalloc((size_t)bp->nsteps * 2 * sizeof *st->right);
  brush_outline(bp, st->left, st->right);
  st->width = (float)(2 * b->max_width);
  return len;
}

/* The bristles of a brush of b's size, made once per list. */
static const BrushBristles *bristles_get(StrokeList *sl, const SceneBrush *b) {
  for (int i = 0; i < sl->nbrushes; i++)
    if (sl->brushes[i]->sectors == b->sectors && sl->brushes[i]->bristles == b->bristles) return sl->brushes[i];
  BrushBristles *bb = xmalloc(sizeof *bb);
  brush_bristles_make(bb, b->sectors, b->bristles);
  sl->brushes = xgrow(sl->brushes, &sl->cap_brushes, sl->nbrushes + 1, sizeof *sl->brushes);
  sl->brushes[sl->nbrushes++] = bb;
  return bb;
}

/* Polyline k of polys as a brush stroke of object o into sl (nothing when
** it is too short). */
static void add_brush(StrokeList *sl, const LinePolys *polys, int k, double sx, double sy,
                      const LineObject *o, int number) {
  const SceneLines *ls = o->lines;
  Stroke st;
  memset(&st, 0, sizeof st);
  Rng r;
  rng_seed_key(&r, LINE_STROKE_SEED, (uint32_t)o->id, (uint32_t)number);
  double len = build_brush(&st, polys, k, sx, sy, &ls->brush, bristles_get(sl, &ls->brush), &r);
  if (len <= 0 || len < ls->min_length || len < STROKE_MIN_PIXELS) {
    stroke_free(&st);
    return;
  }
  st.obj = polys->obj[k];
  st.object_id = o->id;
  st.kind = STROKE_BRUSH;
  st.color = ls->color;
  st.opacity = (float)clampf((float)ls->opacity, 0, 1);
  stroke_box(&st);
  sl->s = xgrow(sl->s, &sl->cap, sl->n + 1, sizeof *sl->s);
  sl->s[sl->n++] = st;
}

int stroke_build(StrokeList **out, const LinePolys *polys, const LineObject *objs, double sx,
                 double sy, char *err, size_t errlen) {
  StrokeList *sl = xcalloc(1, sizeof *sl);
  *out = NULL;
  int maxobj = 0;
  for (int k = 0; k < polys->n; k++) if (polys->obj[k] + 1 > maxobj) maxobj = polys->obj[k] + 1;
  int *made = xcalloc((size_t)maxobj + 1, sizeof *made);   /* strokes so far per object */
  for (int k = 0; k < polys->n; k++) {
    int o = polys->obj[k];
    const SceneLines *ls = objs[o].lines;
    if (ls->stroke == STROKE_BRUSH) {
      add_brush(sl, polys, k, sx, sy, &objs[o], made[o]++);
      continue;
    }
    Stroke st;
    memset(&st, 0, sizeof st);
    float width = (float)(ls->width > 0 ? ls->width : 0);
    double len = scaled_points(&st, polys, k, sx, sy, fmaxf(0.25f, width / STROKE_POINTS_PER_WIDTH));
    if (st.npts < 2 || len < ls->min_length || len < STROKE_MIN_PIXELS) {
      free(st.pts); free(st.s);
      continue;
    }
    float dx = st.pts[0] - st.pts[2 * st.npts - 2], dy = st.pts[1] - st.pts[2 * st.npts - 1];
    if (st.npts >= 4 && dx * dx + dy * dy < 0.25f) {   /* a loop: ribs wrap around */
      st.closed = 1;
      st.pts[2 * st.npts - 2] = st.pts[0];
      st.pts[2 * st.npts - 1] = st.pts[1];
    }
    st.obj = o;
    st.object_id = objs[o].id;
    st.kind = ls->stroke == STROKE_PLAIN ? STROKE_PLAIN : STROKE_RIBBON;
    st.width = width;
    st.color = ls->color;
    st.opacity = (float)clampf((float)ls->opacity, 0, 1);
    const char *tex = ls->texture;
    if (tex && strcmp(tex, "solid") == 0) st.solid = 1;
    else if (tex && strcmp(tex, "ink") != 0 && st.kind == STROKE_RIBBON) {
      st.texture = texture_get(sl, tex, err, errlen);
      if (!st.texture) {
        free(st.pts); free(st.s); free(made);
        stroke_list_free(sl);
        return 0;
      }
    }
    Rng r;
    rng_seed_key(&r, LINE_STROKE_SEED, (uint32_t)objs[o].id, (uint32_t)made[o]++);
    for (int j = 0; j < 4; j++) st.phase[j] = (float)(rng_uniform(&r) * 1024.0);
    if (st.kind == STROKE_RIBBON) build_ribs(&st, ls->miter_limit);
    stroke_box(&st);
    sl->s = xgrow(sl->s, &sl->cap, sl->n + 1, sizeof *sl->s);
    sl->s[sl->n++] = st;
  }
  free(made);
  *out = sl;
  return 1;
}

void stroke_list_free(StrokeList *sl) {
  if (!sl) return;
  for (int i = 0; i < sl->n; i++) stroke_free(&sl->s[i]);
  for (int i = 0; i < sl->ntex; i++) { image_destroy(sl->tex[i]); free(sl->tex_name[i]); }
  for (int i = 0; i < sl->nbrushes; i++) { brush_bristles_free(sl->brushes[i]); free(sl->brushes[i]); }
  free(sl->brushes);
  free(sl->s);
  free(sl->tex);
  free(sl->tex_name);
  free(sl);
}

/* ---- coverage ---------------------------------------------------------------- */

/* A band of rows [y0, y1) and columns [x0, x0 + w) of the frame (the
** target's, or a window's of a larger frame: columns and rows here are the
** frame's) and the coverage of the stroke being drawn (max-combined, so
** overlapping pieces do not darken). */
typedef struct Band {
  int x0, w, y0, y1;
  float *cov;   /* w * (y1 - y0), 0 but for the stroke being drawn */
  int *lo, *hi; /* per row: the columns the stroke touched (lo > hi: none) */
  int *flo, *fhi; /* per row: columns a plain stroke has covered fully (flo > fhi: none) */
  float *run;   /* w * 4: an 8-bit target's pixels being composited, linear */
} Band;

/* Pixel rows/columns of the box [x0, x1] x [y0, y1] inside the band. */
static int band_clip(const Band *b, float x0, float y0, float x1, float y1, int *xa, int *ya,
                     int *xb, int *yb) {
  *xa = floor_int(maxf((float)b->x0, x0));   /* = fmaxf(b->x0, floorf(x0)): the bound is an integer */
  *xb = ceil_int(minf((float)(b->x0 + b->w - 1), x1));
  *ya = floor_int(maxf((float)b->y0, y0));
  *yb = ceil_int(minf((float)(b->y1 - 1), y1));
  return *xa <= *xb && *ya <= *yb;
}

/* Coverage row y: frame column x at [x - b->x0]. */
static float *band_row(const Band *b, int y) { return &b->cov[(size_t)(y - b->y0) * b->w]; }

/* Row y's columns [xa, xb] were written (none when xa > xb). */
static void band_touch(const Band *b, int y, int xa, int xb) {
  int r = y - b->y0;
  if (xa > xb) return;
  if (xa < b->lo[r]) b->lo[r] = xa;
  if (xb > b->hi[r]) b->hi[r] = xb;
}

/* A half-plane nx * px + ny * py + d >= 0. */
typedef struct HalfPlane { float nx, ny, d; } HalfPlane;

/* The half-plane of points at least -margin from the line through (ax, ay)
** with unit normal (nx, ny), on its positive side. */
static HalfPlane half_plane(float ax, float ay, float nx, float ny, float margin) {
  HalfPlane h = {nx, ny, -(ax * nx + ay * ny) + margin};
  return h;
}

/* Columns [*xa, *xb] of row y whose pixel centres lie in every half-plane
** of hp, within [xa0, xb0]; 0 when none. Keeps the per-pixel
** loops of long, thin pieces to the pixels near them, not their boxes.
** (A bound that is NaN is no bound, as with fmaxf and fminf.) */
static int row_span(const HalfPlane *hp, int n, int y, int xa0, int xb0, int *xa, int *xb) {
  float py = y + 0.5f, lo = (float)xa0 + 0.5f, hi = (float)xb0 + 0.5f;
  for (int k = 0; k < n; k++) {
    float r = hp[k].ny * py + hp[k].d;   /* nx * px + r >= 0 */
    if (hp[k].nx > 1e-6f) { float q = -r / hp[k].nx; if (q > lo) lo = q; }
    else if (hp[k].nx < -1e-6f) { float q = -r / hp[k].nx; if (q < hi) hi = q; }
    else if (r < 0) return 0;
  }
  if (lo > hi) return 0;
  *xa = ceil_int(lo - 0.5f);
  *xb = floor_int(hi - 0.5f);
  if (*xa < xa0) *xa = xa0;
  if (*xb > xb0) *xb = xb0;
  return *xa <= *xb;
}

/* Plain: the union of capsules of radius width / 2 around the segments. */
static void cover_plain(const Band *b, const Stroke *st) {
  float hw = st->width * 0.5f;
  for (int i = 0; i + 1 < st->npts; i++) {
    float ax = st->pts[2 * i], ay = st->pts[2 * i + 1], bx = st->pts[2 * i + 2], by = st->pts[2 * i + 3];
    int xa, ya, xb, yb;
    float pad = hw + 1.5f;
    if (!band_clip(b, minf(ax, bx) - pad, minf(ay, by) - pad, maxf(ax, bx) + pad, maxf(ay, by) + pad,
                   &xa, &ya, &xb, &yb))
      continue;
    float ex = bx - ax, ey = by - ay, ee = ex * ex + ey * ey, el = sqrtf(ee);
    float ux = el > 0 ? ex / el : 1, uy = el > 0 ? ey / el : 0;
    HalfPlane hp[4] = {half_plane(ax, ay, ux, uy, pad), half_plane(bx, by, -ux, -uy, pad),
                       half_plane(ax, ay, -uy, ux, pad), half_plane(ax, ay, uy, -ux, pad)};
    for (int y = ya; y <= yb; y++) {
      int x0, x1, wa = b->x0 + b->w, wb = -1, r = y - b->y0;
      if (!row_span(hp, 4, y, xa, xb, &x0, &x1)) continue;
      float *c = band_row(b, y);
      int fa = b->flo[r], fb = b->fhi[r], na = x1 + 1, nb = x0 - 1;   /* n: this capsule's full run */
      for (int x = x0; x <= x1; x++) {
        if (x >= fa && x <= fb) {   /* covered fully already: no capsule raises it */
          x = fb;
          continue;
        }
        float px = x + 0.5f - ax, py = y + 0.5f - ay;
        float t = ee > 0 ? clampf((px * ex + py * ey) / ee, 0, 1) : 0;
        float qx = px - t * ex, qy = py - t * ey, d = sqrtf(qx * qx + qy * qy);
        float a = st->width >= 1 ? clampf(hw + 0.5f - d, 0, 1) : st->width * clampf(1 - d, 0, 1);
        if (a <= 0) continue;
        if (a >= 1) { if (x < na) na = x; nb = x; }
        if (a > c[x - b->x0]) c[x - b->x0] = a;
        if (x < wa) wa = x;
        wb = x;
      }
      band_touch(b, y, wa, wb);
      /* a capsule is convex, so its full pixels in a row are one run: joined
      ** to the row's known run where they meet, else the longer one kept
      ** (the skipped columns inside [na, nb] are full too) */
      if (na > nb) continue;
      if (fa <= fb && na <= fb + 1 && nb >= fa - 1) {
        b->flo[r] = na < fa ? na : fa;
        b->fhi[r] = nb > fb ? nb : fb;
      } else if (fa > fb || nb - na > fb - fa) {
        b->flo[r] = na;
        b->fhi[r] = nb;
      }
    }
  }
}

/* The inward unit normal of the side a -> b of a strip whose other side is
** at c. */
static void inward(float ax, float ay, float bx, float by, float cx, float cy, float *nx, float *ny) {
  float ex = bx - ax, ey = by - ay, l = sqrtf(ex * ex + ey * ey);
  if (l < 1e-9f) { ex = cx - ax; ey = cy - ay; l = sqrtf(ex * ex + ey * ey); *nx = ex / l; *ny = ey / l; return; }
  *nx = -ey / l; *ny = ex / l;
  if ((cx - ax) * *nx + (cy - ay) * *ny < 0) { *nx = -*nx; *ny = -*ny; }
}

/* Ribbon quad i: between rib i and rib i + 1 (hard edges there, so
** neighbours share them exactly), antialiased along its two sides and at
** the strip's open ends. Texture ink is at most 1, so a pixel whose
** coverage is already at least the quad's there needs no texture lookup:
** the quad cannot raise it. */
static void cover_quad(const Band *b, const Stroke *st, Ink *ink, int i) {
  const float *L = st->left, *R = st->right, *P = st->pts;
  int last = st->npts - 2;
  int cap0 = i == 0 && !st->closed, cap1 = i == last && !st->closed;
  float d0x, d0y, d1x, d1y;   /* tangents at the ribs: perpendicular to them */
  float rx = L[2 * i] - R[2 * i], ry = L[2 * i + 1] - R[2 * i + 1], rl = sqrtf(rx * rx + ry * ry);
  if (rl < 1e-9f) return;
  d0x = ry / rl; d0y = -rx / rl;
  rx = L[2 * i + 2] - R[2 * i + 2]; ry = L[2 * i + 3] - R[2 * i + 3]; rl = sqrtf(rx * rx + ry * ry);
  if (rl < 1e-9f) return;
  d1x = ry / rl; d1y = -rx / rl;
  float nlx, nly, nrx, nry;
  inward(L[2 * i], L[2 * i + 1], L[2 * i + 2], L[2 * i + 3], R[2 * i], R[2 * i + 1], &nlx, &nly);
  inward(R[2 * i], R[2 * i + 1], R[2 * i + 2], R[2 * i + 3], L[2 * i], L[2 * i + 1], &nrx, &nry);
  float x0 = minf(minf(L[2 * i], L[2 * i + 2]), minf(R[2 * i], R[2 * i + 2])) - 1;
  float x1 = maxf(maxf(L[2 * i], L[2 * i + 2]), maxf(R[2 * i], R[2 * i + 2])) + 1;
  float y0 = minf(minf(L[2 * i + 1], L[2 * i + 3]), minf(R[2 * i + 1], R[2 * i + 3])) - 1;
  float y1 = maxf(maxf(L[2 * i + 1], L[2 * i + 3]), maxf(R[2 * i + 1], R[2 * i + 3])) + 1;
  int xa, ya, xb, yb;
  if (!band_clip(b, x0, y0, x1, y1, &xa, &ya, &xb, &yb)) return;
  float s0 = st->s[i], s1 = st->s[i + 1];
  /* the pixels the tests below can accept, and a 1/32 pixel more for
  ** rounding: sides at -0.5, ends at 0 (-0.5 at a cap) */
  float m = 1.0f / 32;
  HalfPlane hp[4] = {half_plane(P[2 * i], P[2 * i + 1], d0x, d0y, (cap0 ? 0.5f : 0) + m),
                     half_plane(P[2 * i + 2], P[2 * i + 3], -d1x, -d1y, (cap1 ? 0.5f : 0) + m),
                     half_plane(L[2 * i], L[2 * i + 1], nlx, nly, 0.5f + m),
                     half_plane(R[2 * i], R[2 * i + 1], nrx, nry, 0.5f + m)};
  for (int y = ya; y <= yb; y++) {
    int ra, rb, wa = b->x0 + b->w, wb = -1;
    if (!row_span(hp, 4, y, xa, xb, &ra, &rb)) continue;
    float *c = band_row(b, y);
    /* signed distances (p - a) . n from the four sides, their row terms
    ** (py - ay) * ny taken out of the loop */
    float py = y + 0.5f;
    float fa_y = (py - P[2 * i + 1]) * d0y, fb_y = (py - P[2 * i + 3]) * d1y;
    float dl_y = (py - L[2 * i + 1]) * nly, dr_y = (py - R[2 * i + 1]) * nry;
    for (int x = ra; x <= rb; x++) {
      float px = x + 0.5f, capcov = 1;
      float fa = (px - P[2 * i]) * d0x + fa_y;
      float fb = (px - P[2 * i + 2]) * d1x + fb_y;
      if (cap0) { if (fa < -0.5f) continue; capcov *= clampf(fa + 0.5f, 0, 1); }
      else if (fa < 0) continue;
      if (cap1) { if (fb > 0.5f) continue; capcov *= clampf(0.5f - fb, 0, 1); }
      else if (fb > 0) continue;
      float dl = (px - L[2 * i]) * nlx + dl_y;
      float dr = (px - R[2 * i]) * nrx + dr_y;
      if (dl < -0.5f || dr < -0.5f) continue;
      float cov = clampf(dl + 0.5f, 0, 1) * clampf(dr + 0.5f, 0, 1) * capcov;
      if (cov <= c[x - b->x0]) continue;
      float t = fa - fb > 1e-6f ? clampf(fa / (fa - fb), 0, 1) : 0;
      float v = dl + dr > 1e-6f ? clampf(dr / (dl + dr), 0, 1) : 0.5f;
      float a = cov * texture_at(st, ink, s0 + t * (s1 - s0), v);
      if (a <= 0) continue;
      if (a > c[x - b->x0]) c[x - b->x0] = a;
      if (x < wa) wa = x;
      wb = x;
    }
    band_touch(b, y, wa, wb);
  }
}

/* A round join of radius width / 2 at inner point i: fills the inside of
** sharp turns where neighbouring quads' ribs cross. Inside, the quads
** have mostly inked the pixels already; the most ink the texture gives at
** the join (top) skips the pixels it cannot raise. */
static void cover_join(const Band *b, const Stroke *st, Ink *ink, int i) {
  float hw = st->width * 0.5f, cx = st->pts[2 * i], cy = st->pts[2 * i + 1];
  float rx = st->left[2 * i] - cx, ry = st->left[2 * i + 1] - cy, rl = sqrtf(rx * rx + ry * ry);
  if (hw <= 0 || rl < 1e-9f) return;
  rx /= rl; ry /= rl;
  int xa, ya, xb, yb;
  if (!band_clip(b, cx - hw - 1, cy - hw - 1, cx + hw + 1, cy + hw + 1, &xa, &ya, &xb, &yb)) return;
  float s = st->s[i], top = 1;
  int proc = !st->solid && !st->texture;   /* procedural: its factors along s are the join's */
  InkAlong along = {0, 0, 0, 0};
  if (proc) {
    ink_along(ink, s, &along);
    top = along.along * along.ends;
  }
  float rr = hw + 0.5f + 1.0f / 32;   /* cov > 0 needs d < hw + 0.5; 1/32 for rounding */
  for (int y = ya; y <= yb; y++) {
    float dy = y + 0.5f - cy;
    if (dy * dy >= rr * rr) continue;
    float h = sqrtf(rr * rr - dy * dy);   /* the columns of the disc in this row */
    int x0 = ceil_int(cx - h - 0.5f), x1 = floor_int(cx + h - 0.5f);
    if (x0 < xa) x0 = xa;
    if (x1 > xb) x1 = xb;
    if (x0 > x1) continue;
    float *c = band_row(b, y);
    int wa = b->x0 + b->w, wb = -1;
    for (int x = x0; x <= x1; x++) {
      float px = x + 0.5f - cx, py = y + 0.5f - cy, d = sqrtf(px * px + py * py);
      float cov = clampf(hw + 0.5f - d, 0, 1);
      if (cov <= 0 || cov * top <= c[x - b->x0]) continue;
      float v = clampf(0.5f + 0.5f * (px * rx + py * ry) / hw, 0, 1);
      float a = cov * (proc ? ink_across(ink, &along, v) : texture_at(st, ink, s, v));
      if (a > c[x - b->x0]) c[x - b->x0] = a;
      if (x < wa) wa = x;
      wb = x;
    }
    band_touch(b, y, wa, wb);
  }
}

/* Ink of colour col and coverage a over pixel p (linear; its alpha channel
** at alpha, or -1; ncol colour channels). */
static inline void composite_pixel(float *p, int alpha, int ncol, const float col[3], float a) {
  if (alpha < 0) {
    for (int k = 0; k < ncol; k++) p[k] = p[k] * (1 - a) + col[k] * a;
    return;
  }
  /* "over" with unassociated alpha: what shows through is weighted by
  ** its own alpha, so ink on a transparent pixel keeps its colour */
  float under = p[alpha] * (1 - a), out = a + under;
  for (int k = 0; k < ncol; k++) p[k] = out > 0 ? (col[k] * a + p[k] * under) / out : col[k];
  p[alpha] = out;
}

/* Composite the band's coverage of st (rows ya..yb, the columns it
** touched) over the target, and clear it for the next stroke. An 8-bit
** target is decoded and encoded a run of inked neighbours at a time. */
static void composite(const Band *b, const Stroke *st, Image *target, int ox, int oy, int ya, int yb) {
  int ch = target->channels, alpha = image_alpha_channel(target), ncol = ch >= 3 ? 3 : 1;
  float col[3] = {st->color.r, st->color.g, st->color.b};
  if (ch < 3) col[0] = st->color.g;
  /* a pixel under full ink without alpha becomes col (p (1 - 1) + col 1):
  ** its code, encoded once */
  uint8_t solid[4] = {0, 0, 0, 0};
  if (target->data8 && alpha < 0) image_encode8(col, solid, 1, ch);
  for (int y = ya; y <= yb; y++) {
    int r = y - b->y0;
    float *c = &b->cov[(size_t)r * b->w];   /* frame column x at c[x - b->x0] */
    size_t row = (size_t)(y - oy) * target->width * ch;
    for (int x = b->lo[r], e; x <= b->hi[r]; x = e) {
      if (c[x - b->x0] * st->opacity <= 0) { c[x - b->x0] = 0; e = x + 1; continue; }
      /* an 8-bit image: mix in linear, encode again. It holds the fill as
      ** it shows (clamped to 1), so partial ink mixes with what is seen; a
      ** float image keeps fill above 1, which shows through partial ink */
      uint8_t *code = target->data8 ? target->data8 + row + (size_t)(x - ox) * ch : NULL;
      if (code && alpha < 0 && c[x - b->x0] * st->opacity >= 1) {   /* solid ink: its own code */
        for (e = x; e <= b->hi[r] && c[e - b->x0] * st->opacity >= 1; e++, code += ch) {
          for (int k = 0; k < ch; k++) code[k] = solid[k];
          c[e - b->x0] = 0;
        }
        continue;
      }
      for (e = x + 1; e <= b->hi[r] && !(c[e - b->x0] * st->opacity <= 0) &&
                      !(code && alpha < 0 && c[e - b->x0] * st->opacity >= 1); e++) {}
      float *p = code ? b->run : target->data + row + (size_t)(x - ox) * ch;
      if (code) image_decode8(code, p, (size_t)(e - x), ch);
      for (int k = x - b->x0; k < e - b->x0; k++, p += ch) {
        composite_pixel(p, alpha, ncol, col, c[k] * st->opacity);
        c[k] = 0;
      }
      if (code) image_encode8(b->run, code, (size_t)(e - x), ch);
    }
    b->lo[r] = b->x0 + b->w;
    b->hi[r] = -1;
    b->flo[r] = b->x0 + b->w;
    b->fhi[r] = -1;
  }
}

/* Most rows a band has: a worker's coverage buffer is this many rows of the
** target (16 MiB at 16384 pixels wide). */
#define STROKE_BAND_ROWS 256

typedef struct StrokeJob {
  const StrokeList *sl;
  Image *target;
  int ox, oy;       /* the frame pixel the target's first pixel is */
  int nbands;
  float **cov;      /* per worker: a band's coverage buffer */
  int **rows;       /* per worker: 4 * band_h column bounds */
  float **run;      /* per worker: Band.run */
  int band_h;
} StrokeJob;

static void stroke_band(void *ctx, int band, int worker) {
  StrokeJob *j = ctx;
  Band b = {j->ox, j->target->width, j->oy + band * j->band_h, j->oy + (band + 1) * j->band_h,
            j->cov[worker], j->rows[worker], j->rows[worker] + j->band_h,
            j->rows[worker] + 2 * j->band_h, j->rows[worker] + 3 * j->band_h, j->run[worker]};
  if (b.y1 > j->oy + j->target->height) b.y1 = j->oy + j->target->height;
  for (int r = 0; r < j->band_h; r++) {
    b.lo[r] = b.flo[r] = b.x0 + b.w;
    b.hi[r] = b.fhi[r] = -1;
  }
  for (int k = 0; k < j->sl->n; k++) {
    const Stroke *st = &j->sl->s[k];
    int xa, ya, xb, yb;
    if (!band_clip(&b, st->box[0], st->box[1], st->box[2], st->box[3], &xa, &ya, &xb, &yb)) continue;
    if (st->kind == STROKE_PLAIN) {
      cover_plain(&b, st);
    } else if (st->kind == STROKE_BRUSH) {
      brush_cover(st->brush, b.cov, b.x0, b.w, b.y0, b.y1, b.lo, b.hi);
    } else {
      Ink ink;
      ink_init(&ink, st->phase, st->s[st->npts - 1], st->width);
      for (int i = 0; i + 1 < st->npts; i++) cover_quad(&b, st, &ink, i);
      for (int i = 1; i + 1 < st->npts; i++) cover_join(&b, st, &ink, i);
      if (st->closed) cover_join(&b, st, &ink, 0);
    }
    composite(&b, st, j->target, j->ox, j->oy, ya, yb);
  }
}

void stroke_render(const StrokeList *sl, Image *target, int threads) {
  stroke_render_at(sl, target, 0, 0, threads);
}

void stroke_render_at(const StrokeList *sl, Image *target, int ox, int oy, int threads) {
  if (!sl || sl->n == 0 || target->width < 1 || target->height < 1) return;
  if (threads < 1) threads = 1;
  int nbands = threads > 1 ? threads * 4 : 1;
  if (nbands > target->height) nbands = target->height;
  int band_h = (target->height + nbands - 1) / nbands;
  if (band_h > STROKE_BAND_ROWS) band_h = STROKE_BAND_ROWS;   /* bounds each worker's buffer */
  nbands = (target->height + band_h - 1) / band_h;
  int nw = threads < nbands ? threads : nbands;
  StrokeJob job = {sl, target, ox, oy, nbands, xmalloc((size_t)nw * sizeof(float *)),
                   xmalloc((size_t)nw * sizeof(int *)), xmalloc((size_t)nw * sizeof(float *)), band_h};
  for (int w = 0; w < nw; w++) {
    job.cov[w] = xcalloc((size_t)target->width * band_h, sizeof(float));
    job.rows[w] = xmalloc((size_t)band_h * 4 * sizeof(int));
    job.run[w] = xmalloc((size_t)target->width * 4 * sizeof(float));
  }
  line_parallel(nbands, nw, stroke_band, &job);
  for (int w = 0; w < nw; w++) {
    free(job.cov[w]);
    free(job.rows[w]);
    free(job.run[w]);
  }
  free(job.cov);
  free(job.rows);
  free(job.run);
}
