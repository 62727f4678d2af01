/*
** The reference image: every important edge sampled at points of its
** exact projected line, one a step of its walk; the samples binned into
** tiles; every triangle of every mesh tested at the samples of the tiles
** it reaches as it is met (the nearest wins, the first of equals); then
** each sample found visible or hidden by the offset rule of edgeref.h.
** Work is split into runs of triangles; each worker keeps its own nearest
** surfaces, and they are merged by nearness and then triangle order, so
** the result never depends on the number of workers.
*/
#include "edgeref.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"

/* Samples are binned in tiles of 2^bits x 2^bits pixels: a triangle is
** tested only at the samples of the tiles its box reaches, so the work
** follows the length of the lines, not the resolution. Small tiles test
** fewer samples a triangle, but the passes over the tile tables grow with
** their number, so a tile is about as wide as the edges are long on
** screen, from 2 to 16 pixels (mean span: Wuson subdivided at 1080p 2.5
** px, 2x2 tiles; a CAD engine 7 px, 4x4; the bench teapot 14 px, 8x8, 31M
** instructions where 2x2 took 67M; that teapot at 7680x4320, 16x16), and
** there are at most LINE_REF_MAX_TILES. Which triangle a sample finds does
** not depend on the tiles (every triangle reaching a sample is tested
** there, in order). */
#define LINE_REF_TILE_BITS 1
#define LINE_REF_MAX_TILES (1 << 20)

static int tile_bits(int w, int h, double mean_span) {
  int bits = LINE_REF_TILE_BITS;
  while (bits < 4 && (double)(2 << bits) <= mean_span) bits++;
  while (bits < 8 && (double)((w >> bits) + 1) * ((h >> bits) + 1) > LINE_REF_MAX_TILES) bits++;
  return bits;
}


/* ---- edge spans ---------------------------------------------------------- */

/* Clip the segment p0 -> p1 (t in [*t0, *t1]) to the box [0, w) x [0, h). */
static int clip_box(double x0, double y0, double x1, double y1, double w, double h, double *t0,
                    double *t1) {
  double dx = x1 - x0, dy = y1 - y0;
  double p[4] = {-dx, dx, -dy, dy}, q[4] = {x0, w - x0, y0, h - y0};
  for (int k = 0; k < 4; k++) {
    if (p[k] == 0) {
      if (q[k] < 0) return 0;
    } else {
      double r = q[k] / p[k];
      if (p[k] < 0) { if (r > *t1) return 0; if (r > *t0) *t0 = r; }
      else { if (r < *t0) return 0; if (r < *t1) *t1 = r; }
    }
  }
  return 1;
}

/* The span of mesh edge (a, b): clipped to the near plane in clip space,
** projected, clipped to the image. */
static void make_span(LineSpan *s, const LineVert *a, const LineVert *b, int w, int h) {
  memset(s, 0, sizeof *s);
  double ca[4], cb[4];
  memcpy(ca, a->clip, sizeof ca);
  memcpy(cb, b->clip, sizeof cb);
  double da = ca[2] + ca[3], db = cb[2] + cb[3];
  if (da < 0 && db < 0) return;
  s->real0 = da >= 0;
  s->real1 = db >= 0;
  if (da < 0 || db < 0) {   /* one end behind the near plane: move it onto it */
    double t = da / (da - db);
    double *m = da < 0 ? ca : cb;
    for (int j = 0; j < 4; j++) m[j] = a->clip[j] + t * (b->clip[j] - a->clip[j]);
  }
  if (!(ca[3] > 0) || !(cb[3] > 0)) return;
  float x0, y0, n0, x1, y1, n1;
  line_clip_to_screen(ca, w, h, &x0, &y0, &n0);
  line_clip_to_screen(cb, w, h, &x1, &y1, &n1);
  double t0 = 0, t1 = 1, lim_w = w - 1e-3, lim_h = h - 1e-3;
  if (!clip_box(x0, y0, x1, y1, lim_w, lim_h, &t0, &t1)) return;
  if (t0 > 0) s->real0 = 0;
  if (t1 < 1) s->real1 = 0;
  s->x0 = (float)(x0 + t0 * (x1 - x0)); s->y0 = (float)(y0 + t0 * (y1 - y0));
  s->x1 = (float)(x0 + t1 * (x1 - x0)); s->y1 = (float)(y0 + t1 * (y1 - y0));
  s->n0 = (float)(n0 + t0 * (n1 - n0)); s->n1 = (float)(n0 + t1 * (n1 - n0));
  s->px0 = (int)floor(fmax(0, s->x0)); s->py0 = (int)floor(fmax(0, s->y0));
  s->px1 = (int)floor(fmax(0, s->x1)); s->py1 = (int)floor(fmax(0, s->y1));
  if (s->px0 > w - 1) s->px0 = w - 1;
  if (s->px1 > w - 1) s->px1 = w - 1;
  if (s->py0 > h - 1) s->py0 = h - 1;
  if (s->py1 > h - 1) s->py1 = h - 1;
  int ax = abs(s->px1 - s->px0), ay = abs(s->py1 - s->py0);
  s->nsteps = (ax > ay ? ax : ay) + 1;
}


/* ---- samples ------------------------------------------------------------- */

/* The sample points of every walk, grouped by tile: sample k lies on the
** line of edge id[k] at x[k], y[k] with nearness nr[k], and decides step
** step[k] of that edge's walk. */
typedef struct Samples {
  int tw, th, bits;    /* tiles of 2^bits pixels (tile_bits) */
  int *first;          /* tw * th + 1: tile t holds samples [first[t], first[t + 1]) */
  int *tile;           /* tw * th: first[t], or -1 for a tile without samples (TileSat.tile) */
  int *row_start;      /* th + 1: tile row ty's tiles with samples are row_tx[row_start[ty] ..
                          row_start[ty + 1]), columns in order */
  int *row_tx;
  int n;               /* at most LINE_MAX_STEPS */
  float *x, *y, *nr;
  int *id, *step;      /* the edge, and the step of its walk */
} Samples;

/* Point i of span s's walk: on the exact line, at i / (nsteps - 1) of the
** way, with its nearness (affine in screen space, as depth over w is). */
static void span_point(const LineSpan *s, int i, float *x, float *y, float *n) {
  float t = s->nsteps > 1 ? (float)i / (float)(s->nsteps - 1) : 0;
  *x = s->x0 + t * (s->x1 - s->x0);
  *y = s->y0 + t * (s->y1 - s->y0);
  *n = s->n0 + t * (s->n1 - s->n0);
}

/* The tile of point (x, y) of a tw-tile-wide grid of 2^bits-pixel tiles
** over a w x h image. */
static int tile_of(float x, float y, int tw, int bits, int w, int h) {
  int px = (int)x, py = (int)y;   /* spans are clipped to [0, w) x [0, h) */
  px = px < 0 ? 0 : px >= w ? w - 1 : px;
  py = py < 0 ? 0 : py >= h ? h - 1 : py;
  return (py >> bits) * tw + (px >> bits);
}

/* Sample every step of every span of ref into *sm (counted, then placed
** tile by tile in id and step order), with the summed-area table of the
** tiles that hold samples in *sat. */
static void make_samples(Samples *sm, const LineRef *ref, int **sat) {
  int w = ref->width, h = ref->height;
  sm->bits = tile_bits(w, h, (double)ref->step0[ref->nids] / (ref->nids ? ref->nids : 1));
  sm->tw = (w + (1 << sm->bits) - 1) >> sm->bits;
  sm->th = (h + (1 << sm->bits) - 1) >> sm->bits;
  size_t nt = (size_t)sm->tw * sm->th;
  sm->first = xcalloc(nt + 1, sizeof *sm->first);
  sm->tile = xmalloc((nt ? nt : 1) * sizeof *sm->tile);
  sm->n = (int)ref->step0[ref->nids];
  for (int i = 0; i < ref->nids; i++)
    for (int k = 0; k < ref->span[i].nsteps; k++) {
      float x, y, n;
      span_point(&ref->span[i], k, &x, &y, &n);
      sm->first[tile_of(x, y, sm->tw, sm->bits, w, h) + 1]++;
    }
  int W = sm->tw + 1;
  *sat = xcalloc((size_t)W * (sm->th + 1), sizeof **sat);
  for (int ty = 0; ty < sm->th; ty++) {
    int run = 0;   /* tiles with samples in this row so far */
    for (int tx = 0; tx < sm->tw; tx++) {
      int t = ty * sm->tw + tx, on = sm->first[t + 1] > 0;
      run += on;
      (*sat)[(ty + 1) * W + tx + 1] = (*sat)[ty * W + tx + 1] + run;
    }
  }
  for (size_t t = 0; t < nt; t++) sm->first[t + 1] += sm->first[t];
  for (size_t t = 0; t < nt; t++) sm->tile[t] = sm->first[t + 1] > sm->first[t] ? sm->first[t] : -1;
  sm->row_start = xmalloc(((size_t)sm->th + 1) * sizeof *sm->row_start);
  sm->row_tx = xmalloc((nt ? nt : 1) * sizeof *sm->row_tx);
  int nrow = 0;
  for (int ty = 0; ty < sm->th; ty++) {
    sm->row_start[ty] = nrow;
    for (int tx = 0; tx < sm->tw; tx++)
      if (sm->tile[ty * sm->tw + tx] >= 0) sm->row_tx[nrow++] = tx;
  }
  sm->row_start[sm->th] = nrow;
  size_t n = (size_t)sm->n + 1;
  sm->x = xmalloc(n * sizeof *sm->x);
  sm->y = xmalloc(n * sizeof *sm->y);
  sm->nr = xmalloc(n * sizeof *sm->nr);
  sm->id = xmalloc(n * sizeof *sm->id);
  sm->step = xmalloc(n * sizeof *sm->step);
  int *at = xmalloc((nt ? nt : 1) * sizeof *at);   /* the next free slot of each tile */
  memcpy(at, sm->first, nt * sizeof *at);
  for (int i = 0; i < ref->nids; i++)
    for (int k = 0; k < ref->span[i].nsteps; k++) {
      float x, y, nr;
      span_point(&ref->span[i], k, &x, &y, &nr);
      int s = at[tile_of(x, y, sm->tw, sm->bits, w, h)]++;
      sm->x[s] = x;
      sm->y[s] = y;
      sm->nr[s] = nr;
      sm->id[s] = i + 1;
      sm->step[s] = k;
    }
  free(at);
}

static void samples_free(Samples *sm) {
  free(sm->first); free(sm->tile); free(sm->row_start); free(sm->row_tx);
  free(sm->x); free(sm->y); free(sm->nr); free(sm->id); free(sm->step);
}

/* Which tiles hold samples: the summed-area table (tw + 1) x (th + 1) of
** them. */
typedef struct TileSat {
  int tw, th, bits;
  const int *sat;
  const int *tile;   /* tw * th: the tile's first sample, -1 = none */
  const unsigned char *block;   /* tw * th: which of tiles (tx, ty), (tx + 1, ty), (tx, ty + 1)
                                   and (tx + 1, ty + 1) hold samples, bits 0 to 3 */
} TileSat;

/* Does any tile in columns [tx0, tx1] and rows [ty0, ty1] hold samples? */
static inline int sat_any(const TileSat *m, int tx0, int ty0, int tx1, int ty1) {
  if (tx0 < 0) tx0 = 0;
  if (ty0 < 0) ty0 = 0;
  if (tx1 >= m->tw) tx1 = m->tw - 1;
  if (ty1 >= m->th) ty1 = m->th - 1;
  if (tx0 > tx1 || ty0 > ty1) return 0;
  int W = m->tw + 1;
  return m->sat[(ty1 + 1) * W + tx1 + 1] - m->sat[ty0 * W + tx1 + 1] - m->sat[(ty1 + 1) * W + tx0] +
         m->sat[ty0 * W + tx0] > 0;
}

/* ---- the test ------------------------------------------------------------- */

/* The nearest surface one worker found so far at each sample: its
** nearness there, its offset (ScreenTri.off) and its key (the order of
** the triangles met: object << 32 | mesh triangle << 1 | piece, the
** piece of a triangle cut by the near plane), or NO_PIECE. The nearness
** starts at the sample's own: a surface no nearer than the sample cannot
** hide it, whichever is nearest, and is passed over. */
typedef struct Nearest {
  float *near, *off;
  uint64_t *key;
  float *floor;      /* per tile: the least near of its samples (INFINITY without) */
} Nearest;

#define NO_PIECE UINT64_MAX

/* A triangle (or a piece of one cut by the near plane) ready to test:
** pixel positions, nearness, the offset its depth is pushed back by. */
typedef struct ScreenTri {
  float x[3], y[3], n[3];
  float off;
  float nmax;                /* no point it covers is nearer (its corners' greatest
                                nearness and the rounding of the sample test) */
  int ymin, ymax;            /* rows it may cover */
} ScreenTri;

/* A triangle as the sample test wants it: three sides e with
** a[e] x + b[e] y + c[e] >= 0 inside (in either winding), and its
** nearness n(x, y) = na x + nb y + nc. */
typedef struct TriTest { double a[3], b[3], c[3], na, nb, nc; } TriTest;

static void tri_test(const ScreenTri *t, TriTest *q) {
  double x0 = t->x[0], y0 = t->y[0];
  double ax = t->x[1] - x0, ay = t->y[1] - y0, bx = t->x[2] - x0, by = t->y[2] - y0;
  double det = ax * by - ay * bx, sgn = det > 0 ? 1 : -1;
  double an = t->n[1] - t->n[0], bn = t->n[2] - t->n[0];
  q->na = (an * by - bn * ay) / det;
  q->nb = (bn * ax - an * bx) / det;
  q->nc = t->n[0] - q->na * x0 - q->nb * y0;
  for (int e = 0; e < 3; e++) {
    int e1 = e == 2 ? 0 : e + 1;
    double ex = t->x[e1] - t->x[e], ey = t->y[e1] - t->y[e];
    q->a[e] = -sgn * ey;
    q->b[e] = sgn * ex;
    q->c[e] = sgn * (ey * t->x[e] - ex * t->y[e]);
  }
}

/* Pixels a sample beyond a triangle's exact extent may lie and still
** pass the side tests (their rounding); only tiles so far off are
** skipped, so the result is that of testing every sample of the box. */
#define LINE_REF_SLACK 1.0f

/* Boxes at least this many tiles wide go row by row: each row visits only
** its tiles with samples that the triangle's extent over it reaches. */
#define LINE_REF_WIDE 4

/* The x extent [*lo, *hi] of triangle t over the rows y in [ya, yb]: its
** corners there and where its sides cross y = ya and y = yb. l and h are
** never NaN, so `x < l ? x : l` is fminf(l, x) without the call (a NaN x
** leaves l) but for the sign of a zero, which the callers' sums and
** comparisons do not see. */
static void slab_extent(const ScreenTri *t, float ya, float yb, float *lo, float *hi) {
  float l = INFINITY, h = -INFINITY;
  for (int e = 0; e < 3; e++) {
    int e1 = e == 2 ? 0 : e + 1;
    float x0 = t->x[e], y0 = t->y[e], x1 = t->x[e1], y1 = t->y[e1];
    if (y0 >= ya && y0 <= yb) {
      l = x0 < l ? x0 : l;
      h = x0 > h ? x0 : h;
    }
    for (int k = 0; k < 2; k++) {
      float y = k ? yb : ya;
      if ((y0 - y) * (y1 - y) < 0) {   /* the side crosses the row's edge */
        float x = x0 + (x1 - x0) * ((y - y0) / (y1 - y0));
        l = x < l ? x : l;
        h = x > h ? x : h;
      }
    }
  }
  *lo = l;
  *hi = h;
}

/* Nearest.floor of tile: the least near of its samples (a NaN never
** is: no nearness is nearer than it). */
static float tile_floor(const Samples *sm, const float *near, int tile) {
  float m = INFINITY;
  for (int s = sm->first[tile]; s < sm->first[tile + 1]; s++)
    if (near[s] < m) m = near[s];
  return m;
}

/* The samples of tile (whose first sample is at index tile's) that t (as
** q) covers, sides included, nearer than what f found there: t (key,
** offset off) is their surface now. */
static void test_tile(const TriTest *q, float off, uint64_t key, const Samples *sm, Nearest *f,
                      int tile) {
  int won = 0;
  for (int s = sm->first[tile]; s < sm->first[tile + 1]; s++) {
    double x = sm->x[s], y = sm->y[s];
    float n = (float)(q->na * x + q->nb * y + q->nc);
    if (!(n > f->near[s])) continue;   /* no nearer there (cheaper than the sides) */
    if (q->a[0] * x + q->b[0] * y + q->c[0] < 0 || q->a[1] * x + q->b[1] * y + q->c[1] < 0 ||
        q->a[2] * x + q->b[2] * y + q->c[2] < 0)
      continue;
    f->near[s] = n;
    f->off[s] = off;
    f->key[s] = key;
    won = 1;
  }
  if (won) f->floor[tile] = tile_floor(sm, f->near, tile);
}

/* May a triangle no point of which is nearer than nmax be the nearest
** surface found at a sample of tile? Only where what f found so far is
** less near at some sample: elsewhere test_tile would change nothing, and
** the triangle's set-up (tri_test) is not needed. */
static inline int tile_may_win(const Nearest *f, int tile, float nmax) {
  return f->floor[tile] < nmax;
}

/* The first index in row_tx[a, b) whose column is at least tx. */
static int first_column(const int *row_tx, int a, int b, int tx) {
  while (a < b) {
    int m = a + (b - a) / 2;
    if (row_tx[m] < tx) a = m + 1;
    else b = m;
  }
  return a;
}

/* Triangle t (key) at the samples of its box, columns from its least and
** greatest x: where it covers a sample (its sides included) nearer than
** what f found there, it is the sample's surface. A wide box goes row by
** row (LINE_REF_WIDE), visiting the tiles with samples that the
** triangle's extent over the row reaches (LINE_REF_SLACK wider). */
static void test_tri(const ScreenTri *t, uint64_t key, float xmin, float xmax, const Samples *sm,
                     Nearest *f, int w) {
  int bits = sm->bits;
  /* (int)fmaxf(0, xmin) and (int)fminf(w - 1, xmax), NaN as they take it */
  int tx0 = (int)(xmin > 0 ? xmin : 0) >> bits, tx1 = (int)(xmax < w - 1 ? xmax : (float)(w - 1)) >> bits;
  int ra = t->ymin >> bits, rb = t->ymax >> bits;
  if (rb >= sm->th) rb = sm->th - 1;
  if (tx0 > tx1 || ra > rb) return;
  TriTest q;
  int set = 0;   /* most triangles of a box reach no sample: set up on the first */
  if (tx1 - tx0 < LINE_REF_WIDE) {   /* a small box: look at each of its tiles */
    for (int ty = ra; ty <= rb; ty++)
      for (int tx = tx0; tx <= tx1; tx++) {
        int tile = ty * sm->tw + tx;
        if (!tile_may_win(f, tile, t->nmax)) continue;   /* also a tile without samples */
        if (!set) { tri_test(t, &q); set = 1; }
        test_tile(&q, t->off, key, sm, f, tile);
      }
    return;
  }
  for (int ty = ra; ty <= rb; ty++) {
    int a = sm->row_start[ty], b = sm->row_start[ty + 1];
    if (a == b) continue;
    int c0 = tx0, c1 = tx1;
    float lo, hi;
    slab_extent(t, (float)(ty << bits) - LINE_REF_SLACK, (float)((ty + 1) << bits) + LINE_REF_SLACK,
                &lo, &hi);
    lo -= LINE_REF_SLACK;
    hi += LINE_REF_SLACK;
    if (lo > hi) continue;   /* the row is beyond the triangle (NaN: keep the box) */
    if (lo > (float)(c0 << bits)) c0 = (int)lo >> bits;
    if (hi < (float)((c1 + 1) << bits)) c1 = hi < 0 ? -1 : (int)hi >> bits;
    for (int i = first_column(sm->row_tx, a, b, c0); i < b && sm->row_tx[i] <= c1; i++) {
      int tile = ty * sm->tw + sm->row_tx[i];
      if (!tile_may_win(f, tile, t->nmax)) continue;
      if (!set) { tri_test(t, &q); set = 1; }
      test_tile(&q, t->off, key, sm, f, tile);
    }
  }
}

/* ---- triangles ------------------------------------------------------------ */

/* One worker's pass over some triangles of an object: the samples, the
** tiles holding them, what it found so far, and the offset factor of the
** object's edges. */
typedef struct Tester {
  const Samples *sm;
  const TileSat *m;
  Nearest *f;
  int w, h;
  double factor;
} Tester;

/* Test the triangle p (x0 y0 n0 x1 y1 n1 x2 y2 n2: pixels and nearness),
** whose rows span [ymin, ymax] and columns [xmin, xmax], if it has area. */
static void test_piece(const Tester *ts, const float *p, double ymin, double ymax, float xmin,
                       float xmax, uint64_t key) {
  int w = ts->w, h = ts->h;
  double ax = p[3] - p[0], ay = p[4] - p[1], bx = p[6] - p[0], by = p[7] - p[1];
  double det = ax * by - ay * bx;
  if (!(fabs(det) > 1e-12)) return;
  double an = p[5] - p[2], bn = p[8] - p[2];
  double dndx = (an * by - bn * ay) / det, dndy = (bn * ax - an * bx) / det;
  ScreenTri st, *t = &st;
  for (int k = 0; k < 3; k++) { t->x[k] = p[3 * k]; t->y[k] = p[3 * k + 1]; t->n[k] = p[3 * k + 2]; }
  /* polygon offset: factor times the depth slope, plus a few ulps */
  t->off = (float)(ts->factor * (fabs(dndx) + fabs(dndy))) + LINE_DEPTH_EPS;
  /* n at a sample is the plane through the corners evaluated in doubles
  ** (tri_test, test_tile): within the corners' range but for rounding,
  ** which grows with the slope times the coordinates' size (generously
  ** bounded here: 1e-12 against double's 1e-16), and for the float
  ** rounding of the result (1e-6: ulps of nearness <= 1). Not finite
  ** (a huge triangle): no bound. */
  float nm = p[2] > p[5] ? p[2] : p[5];
  nm = p[8] > nm ? p[8] : nm;
  double reach = w + h + fabs(p[0]) + fabs(p[1]) + fabs(p[3]) + fabs(p[4]) + fabs(p[6]) + fabs(p[7]);
  double bound = nm + 1e-6 + 1e-12 * (fabs(dndx) + fabs(dndy) + 1) * reach;
  t->nmax = isfinite(bound) ? (float)bound : INFINITY;
  /* (int)fmax(0, floor(ymin)) and (int)fmin(h - 1, ceil(ymax)) without the
  ** calls: the callers have ymin <= h and ymax >= 0 (or NaN) */
  t->ymin = ymin > 0 ? (int)ymin : 0;
  t->ymax = h - 1;
  if (ymax < h - 1) {
    t->ymax = (int)ymax;
    if (t->ymax < ymax) t->ymax++;
  }
  test_tri(t, key, xmin, xmax, ts->sm, ts->f, w);
}

/* Test the triangle p (as test_piece) if it reaches a tile with samples. */
static void push_tri(const Tester *ts, const float *p, uint64_t key) {
  int w = ts->w, h = ts->h;
  const TileSat *m = ts->m;
  double ymin = fmin(p[1], fmin(p[4], p[7])), ymax = fmax(p[1], fmax(p[4], p[7]));
  double xmin = fmin(p[0], fmin(p[3], p[6])), xmax = fmax(p[0], fmax(p[3], p[6]));
  if (ymax < 0 || ymin > h || xmax < 0 || xmin > w) return;
  if (!sat_any(m, (int)fmax(0, xmin) >> m->bits, (int)fmax(0, ymin) >> m->bits,
               (int)fmin(w - 1, xmax) >> m->bits, (int)fmin(h - 1, ymax) >> m->bits))
    return;   /* no edge near it: nothing will test against it */
  test_piece(ts, p, ymin, ymax, (float)xmin, (float)xmax, key);
}

/* Clip the triangle c[3] (key) against the near plane (z >= -w) and test
** the pieces. */
static void add_clipped(const Tester *ts, const double *c[3], uint64_t key) {
  int w = ts->w, h = ts->h;
  double poly[4][4];
  int np = 0;
  for (int k = 0; k < 3; k++) {
    const double *a = c[k], *b = c[(k + 1) % 3];
    double da = a[2] + a[3], db = b[2] + b[3];   /* >= 0 in front of the near plane */
    if (da >= 0) memcpy(poly[np++], a, sizeof poly[0]);
    if ((da >= 0) != (db >= 0)) {
      double t = da / (da - db);
      for (int j = 0; j < 4; j++) poly[np][j] = a[j] + t * (b[j] - a[j]);
      np++;
    }
  }
  if (np < 3) return;
  float s[4][3];
  for (int k = 0; k < np; k++) {
    if (!(poly[k][3] > 0)) return;
    line_clip_to_screen(poly[k], w, h, &s[k][0], &s[k][1], &s[k][2]);
  }
  for (int k = 1; k + 1 < np; k++) {
    float p[9] = {s[0][0], s[0][1], s[0][2], s[k][0], s[k][1], s[k][2],
                  s[k + 1][0], s[k + 1][1], s[k + 1][2]};
    push_tri(ts, p, key | (uint64_t)(k - 1));
  }
}

/* A triangle (key) whose corners are all in front of the near plane
** (LineVert.in): what add_clipped does for it (the polygon is the
** triangle itself), with the cheap rejections (off the image, no tile
** with samples) before the slope arithmetic of test_piece. */
static void add_front(const Tester *ts, const LineVert *a, const LineVert *b, const LineVert *c,
                      uint64_t key) {
  int w = ts->w, h = ts->h;
  const TileSat *m = ts->m;
  /* the corners are finite (LineVert.in), so plain comparisons give
  ** what fmin and fmax give */
  float ymin = a->y < b->y ? a->y : b->y, ymax = a->y < b->y ? b->y : a->y;
  float xmin = a->x < b->x ? a->x : b->x, xmax = a->x < b->x ? b->x : a->x;
  if (c->y < ymin) ymin = c->y;
  if (c->y > ymax) ymax = c->y;
  if (c->x < xmin) xmin = c->x;
  if (c->x > xmax) xmax = c->x;
  if (ymax < 0 || ymin > h || xmax < 0 || xmin > w) return;
  if (!sat_any(m, (int)(xmin > 0 ? xmin : 0) >> m->bits, (int)(ymin > 0 ? ymin : 0) >> m->bits,
               (int)(xmax < w - 1 ? xmax : (float)(w - 1)) >> m->bits,
               (int)(ymax < h - 1 ? ymax : (float)(h - 1)) >> m->bits))
    return;
  float p[9] = {a->x, a->y, a->n, b->x, b->y, b->n, c->x, c->y, c->n};
  test_piece(ts, p, ymin, ymax, xmin, xmax, key);   /* box and tiles checked */
}

/* No tile: a vertex that is not LineVert.in (its triangles are clipped). */
#define NO_TILE 0xffffffffu

/* The tile column and row (16 bits each) of vertices [k0, k1) of v into
** code, clamped to the image: those of a triangle's box are the least and
** greatest of its corners'. */
static void vertex_tiles(uint32_t *code, const LineVert *v, int k0, int k1, int w, int h, int bits) {
  float xm = (float)(w - 1), ym = (float)(h - 1);
  for (int k = k0; k < k1; k++) {
    float x = v[k].x < 0 ? 0 : v[k].x > xm ? xm : v[k].x;
    float y = v[k].y < 0 ? 0 : v[k].y > ym ? ym : v[k].y;
    code[k] = v[k].in ? (uint32_t)((int)y >> bits) << 16 | (uint32_t)((int)x >> bits) : NO_TILE;
  }
}

/* Can a triangle with corner tiles a, b, c (vertex_tiles) be skipped
** without a look at its box? When its tiles lie in two columns and two
** rows at most and none of those holds samples: its box covers just
** those, so sat_any would find none either. */
static inline int far_from_samples(uint32_t a, uint32_t b, uint32_t c, const TileSat *m) {
  if ((a == NO_TILE) | (b == NO_TILE) | (c == NO_TILE)) return 0;
  uint32_t ax = a & 0xffff, bx = b & 0xffff, cx = c & 0xffff, ay = a >> 16, by = b >> 16, cy = c >> 16;
  uint32_t x0 = ax < bx ? ax : bx, x1 = ax < bx ? bx : ax, y0 = ay < by ? ay : by, y1 = ay < by ? by : ay;
  x0 = cx < x0 ? cx : x0;
  x1 = cx > x1 ? cx : x1;
  y0 = cy < y0 ? cy : y0;
  y1 = cy > y1 ? cy : y1;
  uint32_t dx = x1 - x0, dy = y1 - y0;
  if ((dx | dy) > 1) return 0;
  unsigned covered = 1u | dx << 1 | dy << 2 | (dx & dy) << 3;   /* the block's tiles the box covers */
  return !(m->block[y0 * (uint32_t)m->tw + x0] & covered);
}

/* Is the box r (LineObjEdges.cluster) of a run of triangles off the image
** or clear of every tile with samples? Then so is each of its triangles'
** boxes, and none of them is tested. */
static inline int far_cluster(const float r[4], int w, int h, const TileSat *m) {
  if (r[3] < 0 || r[1] > h || r[2] < 0 || r[0] > w) return 1;
  return !sat_any(m, (int)(r[0] > 0 ? r[0] : 0) >> m->bits, (int)(r[1] > 0 ? r[1] : 0) >> m->bits,
                  (int)(r[2] < w - 1 ? r[2] : (float)(w - 1)) >> m->bits,
                  (int)(r[3] < h - 1 ? r[3] : (float)(h - 1)) >> m->bits);
}


/* Triangles a task tests: a run of whole LINE_CLUSTER_TRIS runs. */
#define LINE_REF_TASK_TRIS (LINE_CLUSTER_TRIS * 256)

/* The triangles of every object, tested in tasks of LINE_REF_TASK_TRIS
** (in object and triangle order), each worker into its own Nearest. */
typedef struct TestJob {
  const LineEdges *edges;
  const LineObject *objs;
  const Samples *sm;
  const TileSat *m;
  uint32_t **code;          /* per object: vertex_tiles */
  int *task0;               /* nobj + 1: object i's tasks are [task0[i], task0[i + 1]) */
  Nearest *found;           /* per worker */
  int w, h;
} TestJob;

/* The polygon offset factor of obj's edges over the surfaces they lie on. */
static double offset_factor(const LineObject *obj) {
  const SceneLines *ls = obj->lines;
  double factor = LINE_DEPTH_OFFSET_BASE + (ls && ls->present ? ls->depth_offset : 0);
  return factor > 0 ? factor : 0;
}

/* Task k: its triangles that reach a tile with samples, but for the back
** faces an object's own front hides (LineObject.hidden). The vertices are
** the ones line_edges_build projected; only triangles with a corner
** behind the near plane go through add_clipped. Most triangles of a large
** mesh are far from every edge: the tiles of their corners say so
** (far_from_samples) before their box is made, or their run's box
** (LineObjEdges.cluster) does. */
static void test_task(void *ctx, int k, int worker) {
  TestJob *j = ctx;
  int i = 0;
  while (k >= j->task0[i + 1]) i++;
  const Mesh *m = j->objs[i].mesh;
  const LineVert *v = j->edges->obj[i].vert;
  const uint32_t *code = j->code[i];
  const unsigned char *hidden = j->objs[i].hidden;
  const float(*cl)[4] = j->edges->obj[i].cluster;
  Tester ts = {j->sm, j->m, &j->found[worker], j->w, j->h, offset_factor(&j->objs[i])};
  int first = (k - j->task0[i]) * LINE_REF_TASK_TRIS;
  int last = first + LINE_REF_TASK_TRIS < m->ntris ? first + LINE_REF_TASK_TRIS : m->ntris;
  for (int t0 = first; t0 < last; t0 += LINE_CLUSTER_TRIS) {
    if (cl && far_cluster(cl[t0 / LINE_CLUSTER_TRIS], j->w, j->h, j->m)) continue;   /* the whole run */
    int t1 = t0 + LINE_CLUSTER_TRIS < last ? t0 + LINE_CLUSTER_TRIS : last;
    for (int t = t0; t < t1; t++) {
      if (hidden && hidden[t]) continue;   /* behind the object's own front */
      const int *tv = m->tri[t];
      if (far_from_samples(code[tv[0]], code[tv[1]], code[tv[2]], j->m)) continue;
      const LineVert *a = &v[tv[0]], *b = &v[tv[1]], *c = &v[tv[2]];
      uint64_t key = (uint64_t)i << 32 | (uint64_t)t << 1;
      if (a->in & b->in & c->in) {
        add_front(&ts, a, b, c, key);
      } else {
        const double *cc[3] = {a->clip, b->clip, c->clip};
        add_clipped(&ts, cc, key);
      }
    }
  }
}

/* Nearest records for the samples of sm, starting at their own nearness
** (whose Nearest.floor is floor). */
static void nearest_init(Nearest *f, const Samples *sm, const float *floor) {
  size_t n = (size_t)sm->n, nt = (size_t)sm->tw * sm->th;
  f->near = xmalloc((n + 1) * sizeof *f->near);
  f->off = xmalloc((n + 1) * sizeof *f->off);
  f->key = xmalloc((n + 1) * sizeof *f->key);
  f->floor = xmalloc((nt + 1) * sizeof *f->floor);
  memcpy(f->near, sm->nr, n * sizeof *f->near);
  for (size_t s = 0; s < n; s++) f->key[s] = NO_PIECE;
  memcpy(f->floor, floor, nt * sizeof *f->floor);
}

static void nearest_free(Nearest *f) {
  free(f->near);
  free(f->off);
  free(f->key);
  free(f->floor);
}

/* Into f[0] what the workers f[0..nw) found: per sample the nearest, of
** equals the first met (the least key), as one worker testing every
** triangle in order would have found. */
static void nearest_merge(Nearest *f, int nw, int n) {
  for (int w = 1; w < nw; w++)
    for (int s = 0; s < n; s++)
      if (f[w].near[s] > f[0].near[s] || (f[w].near[s] == f[0].near[s] && f[w].key[s] < f[0].key[s])) {
        f[0].near[s] = f[w].near[s];
        f[0].off[s] = f[w].off[s];
        f[0].key[s] = f[w].key[s];
      }
}

/* What a set-up task makes: the codes of this many vertices (vertex_tiles),
** or the tables of this many rows of tiles. */
#define LINE_REF_TASK_VERTS 65536
#define LINE_REF_TASK_ROWS 32

/* What the triangles' test reads, made in tasks: first the vertex codes
** of each object (task0[i] to task0[i + 1] for object i), then from task
** task0[nobj] on, rows of tiles: their TileSat.block and their floor
** (Nearest.floor at the samples' own nearness): the same whichever
** thread makes which. */
typedef struct SetupJob {
  const LineEdges *edges;
  const LineObject *objs;
  const Samples *sm;
  uint32_t **code;
  int *task0;               /* nobj + 1 */
  unsigned char *block;
  float *floor;
  int w, h;
} SetupJob;

static void setup_task(void *ctx, int k, int worker) {
  SetupJob *j = ctx;
  const Samples *sm = j->sm;
  int nobj = j->edges->nobj;
  if (k < j->task0[nobj]) {
    int i = 0;
    while (k >= j->task0[i + 1]) i++;
    int k0 = (k - j->task0[i]) * LINE_REF_TASK_VERTS, nv = j->objs[i].mesh->nverts;
    int k1 = k0 + LINE_REF_TASK_VERTS < nv ? k0 + LINE_REF_TASK_VERTS : nv;
    vertex_tiles(j->code[i], j->edges->obj[i].vert, k0, k1, j->w, j->h, sm->bits);
    return;
  }
  int tw = sm->tw, th = sm->th, ty0 = (k - j->task0[nobj]) * LINE_REF_TASK_ROWS;
  int ty1 = ty0 + LINE_REF_TASK_ROWS < th ? ty0 + LINE_REF_TASK_ROWS : th;
  for (int ty = ty0; ty < ty1; ty++) {
    unsigned char *b = j->block + (size_t)ty * tw;   /* zeroed */
    float *fl = j->floor + (size_t)ty * tw;
    for (int tx = 0; tx < tw; tx++) fl[tx] = INFINITY;
    for (int dy = 0; dy < 2 && ty + dy < th; dy++)   /* the tiles with samples in this row and the next */
      for (int r = sm->row_start[ty + dy]; r < sm->row_start[ty + dy + 1]; r++) {
        int tx = sm->row_tx[r];
        b[tx] |= (unsigned char)(1u << dy * 2);
        if (tx > 0) b[tx - 1] |= (unsigned char)(2u << dy * 2);
        if (dy == 0) fl[tx] = tile_floor(sm, sm->nr, ty * tw + tx);
      }
  }
}

/* Test every triangle of objs at the samples of sm (summed-area table
** sat) on up to threads workers: what was found into *f (nearest_free
** it). */
static void test_triangles(Nearest *f, const LineEdges *edges, const LineObject *objs, int w, int h,
                           const Samples *sm, const int *sat, int threads) {
  size_t nt = (size_t)sm->tw * sm->th;
  TileSat m = {sm->tw, sm->th, sm->bits, sat, sm->tile, xcalloc(nt + 1, 1)};
  SetupJob sj = {edges, objs, sm, xcalloc((size_t)edges->nobj + 1, sizeof *sj.code),
                 xcalloc((size_t)edges->nobj + 1, sizeof *sj.task0), (unsigned char *)m.block,
                 xmalloc((nt + 1) * sizeof *sj.floor), w, h};
  TestJob j = {edges, objs, sm, &m, sj.code, xcalloc((size_t)edges->nobj + 1, sizeof *j.task0), NULL,
               w, h};
  for (int i = 0; i < edges->nobj; i++) {
    int nv = objs[i].mesh->nverts;
    sj.code[i] = xmalloc(((size_t)nv + 1) * sizeof *sj.code[i]);   /* every entry written by setup_task */
    sj.task0[i + 1] = sj.task0[i] + (nv + LINE_REF_TASK_VERTS - 1) / LINE_REF_TASK_VERTS;
    j.task0[i + 1] = j.task0[i] + (objs[i].mesh->ntris + LINE_REF_TASK_TRIS - 1) / LINE_REF_TASK_TRIS;
  }
  line_parallel(sj.task0[edges->nobj] + (sm->th + LINE_REF_TASK_ROWS - 1) / LINE_REF_TASK_ROWS, threads,
                setup_task, &sj);
  int ntasks = j.task0[edges->nobj];
  int nw = threads < ntasks ? threads : ntasks > 0 ? ntasks : 1;
  j.found = xmalloc((size_t)nw * sizeof *j.found);
  for (int k = 0; k < nw; k++) nearest_init(&j.found[k], sm, sj.floor);
  line_parallel(ntasks, nw, test_task, &j);
  nearest_merge(j.found, nw, sm->n);
  *f = j.found[0];
  for (int k = 1; k < nw; k++) nearest_free(&j.found[k]);
  for (int i = 0; i < edges->nobj; i++) free(j.code[i]);
  free(sj.code);
  free(sj.task0);
  free(sj.floor);
  free(sj.block);
  free(j.task0);
  free(j.found);
}

/* ---- visibility ------------------------------------------------------------ */

/* Which ways the faces of edge id i + 1 look: bit 0, one looks at the
** viewer; bit 1, one looks away. */
static unsigned char *edge_facing(const LineEdges *edges) {
  unsigned char *facing = xmalloc((size_t)edges->n + 1);
  for (int i = 0; i < edges->n; i++) {
    const LineObjEdges *oe = &edges->obj[edges->obj_of[i]];
    const MeshEdge *me = &oe->mesh->edges[edges->edge_of[i]];
    facing[i] = 0;
    for (int k = 0; k < 2; k++)
      if (me->f[k] >= 0) facing[i] |= oe->front[me->f[k]] ? 1 : 2;
  }
  return facing;
}

/* Decide every sample of sm from the nearest surface f found there:
** visible where that surface (pushed back by its offset when it faces the
** viewer as one of the edge's faces does: it may; a face turned the other
** way occludes at its true depth, so an edge on the far side of an object
** does not leak out from behind a silhouette or a corner) does not hide
** it. */
static void decide(LineRef *ref, const LineEdges *edges, const Samples *sm, const Nearest *f) {
  unsigned char *facing = edge_facing(edges);
  for (int s = 0; s < sm->n; s++) {
    float n = sm->nr[s], limit = f->near[s];
    if (n <= 0) continue;   /* beyond the far plane */
    int id = sm->id[s];
    if (f->key[s] != NO_PIECE) {
      int obj = (int)(f->key[s] >> 32), tri = (int)(f->key[s] >> 1 & 0x7fffffff);
      int lenient = (facing[id - 1] & (edges->obj[obj].front[tri] ? 1 : 2)) != 0;
      limit -= lenient ? f->off[s] : LINE_DEPTH_EPS;
    }
    if (n < limit) continue;   /* hidden */
    ref->vis[ref->step0[id - 1] + (size_t)sm->step[s]] = 1;
    ref->count[id - 1]++;
  }
  free(facing);
}

int line_ref_build(LineRef *ref, const LineEdges *edges, const LineObject *objs, int width,
                   int height, int threads) {
  memset(ref, 0, sizeof *ref);
  ref->width = width;
  ref->height = height;
  ref->nids = edges->n;
  ref->span = xcalloc((size_t)edges->n + 1, sizeof *ref->span);
  ref->step0 = xmalloc(((size_t)edges->n + 1) * sizeof *ref->step0);
  size_t nsteps = 0;
  for (int i = 0; i < edges->n; i++) {
    const LineObjEdges *oe = &edges->obj[edges->obj_of[i]];
    const MeshEdge *me = &oe->mesh->edges[edges->edge_of[i]];
    make_span(&ref->span[i], &oe->vert[me->v[0]], &oe->vert[me->v[1]], width, height);
    ref->step0[i] = nsteps;
    nsteps += (size_t)ref->span[i].nsteps;
  }
  ref->step0[edges->n] = nsteps;
  ref->count = xcalloc((size_t)edges->n + 1, sizeof *ref->count);
  ref->visible = xmalloc(((size_t)edges->n + 1) * sizeof *ref->visible);
  if (nsteps > LINE_MAX_STEPS) return 0;
  ref->vis = xcalloc(nsteps + 1, 1);
  Samples sm;
  int *sat;
  make_samples(&sm, ref, &sat);
  if (sm.n) {
    Nearest f;
    test_triangles(&f, edges, objs, width, height, &sm, sat, threads);
    decide(ref, edges, &sm, &f);
    nearest_free(&f);
  }
  free(sat);
  samples_free(&sm);
  for (int i = 0; i < edges->n; i++)
    if (ref->count[i] > 0) ref->visible[ref->nvisible++] = i + 1;
  return 1;
}

void line_ref_free(LineRef *ref) {
  free(ref->span);
  free(ref->step0);
  free(ref->vis);
  free(ref->count);
  free(ref->visible);
  memset(ref, 0, sizeof *ref);
}
