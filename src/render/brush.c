/*
** The Chinese brush (see brush.h): the width profile and pressure at the
** control points, the Catmull-Rom path resampled into steps, the dry-brush
** draws, then the deposits.
*/
#include "brush.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"

/* ---- control points ------------------------------------------------------- */

double brush_width_at(int i, int ncp, double width_step, double max_width) {
  int k = i < ncp - 1 - i ? i : ncp - 1 - i;
  double w = width_step * (k > 0 ? k : 0);
  return w < max_width ? w : max_width;
}

double brush_pressure_at(double included, double p) {
  double turn = 180 - included;   /* degrees off straight on */
  double f = turn <= 0 ? 0 : turn >= 90 ? 1 : turn / 90;
  return p + (1 - p) * f;
}

float brush_weight(float uy, float P) {
  float u = 0.5f * (1 - uy);   /* |b'_y - B| / 2B with b'_y = uy B */
  if (u >= P) return 0;
  return 1 - u * (1 - P) / P;
}

/* The included angle at c[i] between its edges to c[i - 1] and c[i + 1],
** degrees (180 at an end, or where an edge has no length). */
static double included_angle(const float *c, int n, int i) {
  if (i <= 0 || i >= n - 1) return 180;
  double ax = c[2 * i - 2] - c[2 * i], ay = c[2 * i - 1] - c[2 * i + 1];
  double bx = c[2 * i + 2] - c[2 * i], by = c[2 * i + 3] - c[2 * i + 1];
  double la = hypot(ax, ay), lb = hypot(bx, by);
  if (la <= 0 || lb <= 0) return 180;
  double cs = (ax * bx + ay * by) / (la * lb);
  return acos(cs < -1 ? -1 : cs > 1 ? 1 : cs) * 180 / M_PI;
}

/* ---- the spline path ------------------------------------------------------ */

/* A turn of more than this many degrees at a control point makes it a
** corner: the spline keeps the two edges into it straight, as through a
** sharp silhouette corner (a cube's) it would swing wide of both. */
#define BRUSH_CORNER_TURN 30

/* The control points of a stroke and what the spline through them needs. */
typedef struct Curve {
  int n;
  const float *c;          /* x, y pairs */
  const float *w;          /* half-widths */
  unsigned char *corner;   /* per point: a corner (ends count as corners) */
} Curve;

/* The four points, widths and knots of segment i (from control point i to
** i + 1) of the centripetal Catmull-Rom spline: the neighbours i - 1 and
** i + 2, or, past an end or a corner, the reflection of the other end
** (so the curve runs straight into it); knots spaced by the square roots
** of the points' distances, so unevenly spaced points (short edges beside
** long ones) make no loops or cusps. */
static void segment(const Curve *cv, int i, double x[4], double y[4], double w[4], double t[4]) {
  const float *c = cv->c;
  for (int k = 1; k <= 2; k++) {
    x[k] = c[2 * (i + k - 1)];
    y[k] = c[2 * (i + k - 1) + 1];
    w[k] = cv->w[i + k - 1];
  }
  if (cv->corner[i]) { x[0] = 2 * x[1] - x[2]; y[0] = 2 * y[1] - y[2]; w[0] = 2 * w[1] - w[2]; }
  else { x[0] = c[2 * i - 2]; y[0] = c[2 * i - 1]; w[0] = cv->w[i - 1]; }
  if (cv->corner[i + 1]) { x[3] = 2 * x[2] - x[1]; y[3] = 2 * y[2] - y[1]; w[3] = 2 * w[2] - w[1]; }
  else { x[3] = c[2 * i + 4]; y[3] = c[2 * i + 5]; w[3] = cv->w[i + 2]; }
  t[0] = 0;
  for (int k = 0; k < 3; k++) t[k + 1] = t[k] + sqrt(hypot(x[k + 1] - x[k], y[k + 1] - y[k]));
}

/* The spline of values v at u in [0, 1] of a segment with knots t: Barry
** and Goldman's pyramid of blends. It passes through the segment's ends. */
static double blend(const double v[4], const double t[4], double u) {
  double s = t[1] + u * (t[2] - t[1]);
  double a1 = ((t[1] - s) * v[0] + (s - t[0]) * v[1]) / (t[1] - t[0]);
  double a2 = ((t[2] - s) * v[1] + (s - t[1]) * v[2]) / (t[2] - t[1]);
  double a3 = ((t[3] - s) * v[2] + (s - t[2]) * v[3]) / (t[3] - t[2]);
  double b1 = ((t[2] - s) * a1 + (s - t[0]) * a2) / (t[2] - t[0]);
  double b2 = ((t[3] - s) * a2 + (s - t[1]) * a3) / (t[3] - t[1]);
  return ((t[2] - s) * b1 + (s - t[1]) * b2) / (t[2] - t[1]);
}

/* The tangent direction of the curve at control point i: the spline's
** tangent there, (p1 - p0) / (t1 - t0) - (p2 - p0) / (t2 - t0) + (p2 -
** p1) / (t2 - t1) over the points i - 1, i, i + 1, which at a corner (its
** two edges straight) is the bisector of the edges. */
static double tangent_angle(const Curve *cv, int i) {
  const float *c = cv->c;
  int n = cv->n, a = i > 0 ? i - 1 : i, b = i < n - 1 ? i + 1 : i;
  double p[3][2];
  for (int k = 0; k < 2; k++) {
    p[1][k] = c[2 * i + k];
    p[0][k] = a < i ? c[2 * a + k] : 2 * p[1][k] - c[2 * b + k];   /* an end: reflected */
    p[2][k] = b > i ? c[2 * b + k] : 2 * p[1][k] - c[2 * a + k];
  }
  double t1 = sqrt(hypot(p[1][0] - p[0][0], p[1][1] - p[0][1]));
  double t2 = t1 + sqrt(hypot(p[2][0] - p[1][0], p[2][1] - p[1][1]));
  double d[2];
  for (int k = 0; k < 2; k++)
    d[k] = (p[1][k] - p[0][k]) / t1 - (p[2][k] - p[0][k]) / t2 + (p[2][k] - p[1][k]) / (t2 - t1);
  return atan2(d[1], d[0]);
}

/* A point of the finely sampled spline: arc length, segment and parameter. */
typedef struct Fine { double s, x, y; int seg; double t; } Fine;

/* Samples a segment of chord `chord` pixels gets: at most a pixel apart
** (and never fewer than 4), so the arc length is true to a small fraction
** of a pixel and a straight line between samples is off the curve by
** much less. */
static int segment_samples(double chord) { return (int)ceil(chord) + 4; }

/* The spline of cv sampled segment by segment. */
static Fine *fine_samples(const Curve *cv, int *nfine) {
  const float *c = cv->c;
  int cap = 1;
  for (int i = 0; i + 1 < cv->n; i++)
    cap += segment_samples(hypot(c[2 * i + 2] - c[2 * i], c[2 * i + 3] - c[2 * i + 1]));
  Fine *f = xmalloc((size_t)cap * sizeof *f);
  int m = 0;
  f[m++] = (Fine){0, c[0], c[1], 0, 0};
  for (int i = 0; i + 1 < cv->n; i++) {
    int k = segment_samples(hypot(c[2 * i + 2] - c[2 * i], c[2 * i + 3] - c[2 * i + 1]));
    double x[4], y[4], w[4], t[4];
    segment(cv, i, x, y, w, t);
    for (int j = 1; j <= k; j++) {
      double u = (double)j / k, px = blend(x, t, u), py = blend(y, t, u);
      Fine *p = &f[m - 1];
      f[m++] = (Fine){p->s + hypot(px - p->x, py - p->y), px, py, i, u};
    }
  }
  *nfine = m;
  return f;
}

/* Angle a1 moved to within pi of a0, so a linear blend turns the short way. */
static double near_angle(double a0, double a1) {
  while (a1 - a0 > M_PI) a1 -= 2 * M_PI;
  while (a1 - a0 < -M_PI) a1 += 2 * M_PI;
  return a1;
}

/* Control points with those closer than 1/100 pixel to the one before
** dropped (the last one kept): a copy the caller frees. */
static float *distinct_points(const float *ctrl, int n, int *out_n) {
  float *c = xmalloc((size_t)(n > 0 ? n : 1) * 2 * sizeof *c);
  int m = 0;
  for (int i = 0; i < n; i++) {
    if (m > 0 && hypotf(ctrl[2 * i] - c[2 * m - 2], ctrl[2 * i + 1] - c[2 * m - 1]) < 0.01f) {
      if (i == n - 1 && m > 1) m--;
      else continue;
    }
    c[2 * m] = ctrl[2 * i];
    c[2 * m + 1] = ctrl[2 * i + 1];
    m++;
  }
  *out_n = m;
  return c;
}

/* Per control point of cv (its c and n set): half-width, pressure,
** corner flag and tangent angle. */
static void knot_values(Curve *cv, const SceneBrush *b, float *w, float *press, double *ang) {
  int n = cv->n;
  for (int i = 0; i < n; i++) {
    double included = included_angle(cv->c, n, i);
    w[i] = (float)brush_width_at(i, n, b->width_step, b->max_width);
    press[i] = (float)brush_pressure_at(included, b->pressure);
    cv->corner[i] = i == 0 || i == n - 1 || 180 - included > BRUSH_CORNER_TURN;
  }
  cv->w = w;
  for (int i = 0; i < n; i++) {
    ang[i] = tangent_angle(cv, i);
    if (i > 0) ang[i] = near_angle(ang[i - 1], ang[i]);
  }
}

static void path_alloc(BrushPath *bp, int nsteps) {
  bp->nsteps = nsteps;
  bp->x = xmalloc((size_t)nsteps * sizeof *bp->x);
  bp->y = xmalloc((size_t)nsteps * sizeof *bp->y);
  bp->s = xmalloc((size_t)nsteps * sizeof *bp->s);
  bp->b = xmalloc((size_t)nsteps * sizeof *bp->b);
  bp->ang = xmalloc((size_t)nsteps * sizeof *bp->ang);
  bp->press = xmalloc((size_t)nsteps * sizeof *bp->press);
}

/* Where along the fine samples f[0..m) the brush stands at each step:
** one pixel along the dominant axis of the way it is going apart (the
** thesis's "one pixel at a time"; 1 to 1.41 pixels of arc), and at the
** end. Returns the count; *out is malloc'ed. */
static int step_positions(const Fine *f, int m, double **out) {
  double len = f[m - 1].s;
  int n = 0, cap = (int)len + 2;
  double *s = xmalloc((size_t)cap * sizeof *s);
  int j = 0;
  for (double at = 0; at < len - 1e-6;) {
    s = xgrow(s, &cap, n + 2, sizeof *s);
    s[n++] = at;
    while (j + 2 < m && f[j + 1].s <= at) j++;
    double dx = fabs(f[j + 1].x - f[j].x), dy = fabs(f[j + 1].y - f[j].y), d = f[j + 1].s - f[j].s;
    double major = d > 0 ? (dx > dy ? dx : dy) / d : 1;   /* in [0.71, 1] */
    at += 1 / (major > 0.7 ? major : 0.7);
  }
  s[n++] = len;
  *out = s;
  return n;
}

/* The steps of bp along the fine samples f[0..m) (step_positions), with
** the control points' values interpolated: the half-width along the
** spline (clamped to [0, max_width], as it may overshoot a little),
** pressure and angle linearly. */
static void resample(BrushPath *bp, const Fine *f, int m, const Curve *cv, const float *press,
                     const double *ang, double max_width) {
  double *pos;
  int n = cv->n, nsteps = step_positions(f, m, &pos);
  path_alloc(bp, nsteps);
  int j = 0, kseg = -1;
  double sx[4], sy[4], sw[4], st[4];
  for (int i = 0; i < nsteps; i++) {
    double s = pos[i];
    while (j + 2 < m && f[j + 1].s < s) j++;
    const Fine *a = &f[j], *b = &f[j + 1 < m ? j + 1 : j];
    double u = b->s > a->s ? (s - a->s) / (b->s - a->s) : 0;
    u = u < 0 ? 0 : u > 1 ? 1 : u;
    /* segment and parameter: b's, with t measured back when a is in the segment before */
    int seg = b->seg, next = seg + 1 < n ? seg + 1 : seg;
    double ta = a->seg == seg ? a->t : 0, t = ta + u * (b->t - ta);
    bp->x[i] = (float)(a->x + u * (b->x - a->x));
    bp->y[i] = (float)(a->y + u * (b->y - a->y));
    bp->s[i] = (float)s;
    if (seg != kseg) { segment(cv, seg, sx, sy, sw, st); kseg = seg; }
    double bw = blend(sw, st, t);
    bp->b[i] = (float)(bw < 0 ? 0 : bw > max_width ? max_width : bw);
    bp->press[i] = (float)(press[seg] + t * (press[next] - press[seg]));
    bp->ang[i] = (float)(ang[seg] + t * (ang[next] - ang[seg]));
  }
  free(pos);
}

/* ---- bristles and the dry brush ------------------------------------------ */

typedef struct Bristle { float ux, uy; int k; } Bristle;

/* By across position, right side first (ties: by place in the polar grid). */
static int cmp_bristle(const void *a, const void *b) {
  const Bristle *p = a, *q = b;
  if (p->uy != q->uy) return p->uy > q->uy ? -1 : 1;
  return p->k - q->k;
}

void brush_bristles_make(BrushBristles *bb, int sectors, int bristles) {
  int n = sectors * bristles;
  Bristle *br = xmalloc((size_t)n * sizeof *br);
  for (int j = 0; j < sectors; j++) {
    double th = 2 * M_PI * j / sectors;
    for (int k = 0; k < bristles; k++) {
      double r = (double)(k + 1) / bristles;
      br[j * bristles + k] = (Bristle){(float)(r * cos(th)), (float)(r * sin(th)), j * bristles + k};
    }
  }
  qsort(br, (size_t)n, sizeof *br, cmp_bristle);
  bb->sectors = sectors;
  bb->bristles = bristles;
  bb->n = n;
  bb->ux = xmalloc((size_t)n * sizeof *bb->ux);
  bb->uy = xmalloc((size_t)n * sizeof *bb->uy);
  for (int k = 0; k < n; k++) { bb->ux[k] = br[k].ux; bb->uy[k] = br[k].uy; }
  free(br);
}

void brush_bristles_free(BrushBristles *bb) {
  free(bb->ux);
  free(bb->uy);
  memset(bb, 0, sizeof *bb);
}

/* The 0/1 bytes f[0 .. 32 words) as bits, bit j of word w from f[32 w + j].
** Eight bytes at a time: read as a number (byte j at bit 8 j, whatever the
** machine's byte order), one multiply gathers their low bits into the top
** byte (byte j's bit lands at 56 + j, and no two products meet). */
static void pack_bits(const unsigned char *f, int words, uint32_t *out) {
  for (int w = 0; w < words; w++) {
    uint32_t v = 0;
    for (int q = 0; q < 4; q++) {
      const unsigned char *b = f + 32 * w + 8 * q;
      uint64_t x = (uint64_t)b[0] | (uint64_t)b[1] << 8 | (uint64_t)b[2] << 16 | (uint64_t)b[3] << 24 |
                   (uint64_t)b[4] << 32 | (uint64_t)b[5] << 40 | (uint64_t)b[6] << 48 | (uint64_t)b[7] << 56;
      v |= (uint32_t)((x * 0x0102040810204080ULL) >> 56) << (8 * q);
    }
    out[w] = v;
  }
}

/* The thesis's gap counters (Fig. 4.4), one per bristle, run over every
** step. Each 32-bit draw of the stream decides for two bristles, 16 bits
** each: a bristle whose counter is zero starts a gap when the top 10 bits
** fall under dry_probability * 1024, of (low 6 bits) * (dry_max_gap + 1)
** / 64 steps; else its counter counts down. It deposits at a step its
** counter is (then) zero. Every bristle draws at every step, used or not,
** so the loop has no branch to mispredict. */
static void dry_brush(BrushPath *bp, const SceneBrush *b, Rng *r) {
  int n = bp->br->n;
  bp->words = (n + 31) / 32;
  bp->dry = xmalloc((size_t)bp->nsteps * bp->words * sizeof *bp->dry);
  size_t nb = (size_t)bp->words * 32;   /* whole words: the spare bristles never deposit */
  uint16_t *gap = xcalloc(nb, sizeof *gap), *half = xcalloc(nb, sizeof *half);
  unsigned char *dep = xcalloc(nb, 1);
  uint16_t cut = (uint16_t)(b->dry_probability >= 1 ? 1024 : b->dry_probability * 1024.0 + 0.5);
  uint16_t span = (uint16_t)(b->dry_max_gap + 1);
  for (int i = 0; i < bp->nsteps; i++) {
    for (int k = 0; k < n; k += 2) {
      uint32_t u = rng_next(r);
      half[k] = (uint16_t)(u & 0xFFFFu);
      half[k + 1] = (uint16_t)(u >> 16);
    }
    for (int k = 0; k < n; k++) {
      uint16_t h = half[k], g = gap[k];
      uint16_t start = (uint16_t)((h >> 6) < cut ? ((h & 63) * span) >> 6 : 0);
      g = (uint16_t)(g ? g - 1 : start);
      gap[k] = g;
      dep[k] = g == 0;
    }
    pack_bits(dep, bp->words, &bp->dry[(size_t)i * bp->words]);
  }
  free(dep);
  free(half);
  free(gap);
}

int brush_path_build(BrushPath *bp, const float *ctrl, int n, const SceneBrush *b,
                     const BrushBristles *br, Rng *r) {
  memset(bp, 0, sizeof *bp);
  int m;
  float *c = distinct_points(ctrl, n, &m);
  if (m < 2) { free(c); return 0; }
  float *w = xmalloc((size_t)m * sizeof *w), *press = xmalloc((size_t)m * sizeof *press);
  double *ang = xmalloc((size_t)m * sizeof *ang);
  Curve cv = {m, c, w, xmalloc((size_t)m)};
  knot_values(&cv, b, w, press, ang);
  int nfine;
  Fine *f = fine_samples(&cv, &nfine);
  int ok = f[nfine - 1].s > 0;
  if (ok) {
    resample(bp, f, nfine, &cv, press, ang, b->max_width);
    bp->br = br;
    bp->aspect = (float)b->aspect;
    bp->ink = (float)b->ink_load;
    dry_brush(bp, b, r);
  }
  free(f);
  free(cv.corner);
  free(ang);
  free(press);
  free(w);
  free(c);
  return ok;
}

void brush_path_free(BrushPath *bp) {
  if (!bp) return;
  free(bp->x); free(bp->y); free(bp->s); free(bp->b); free(bp->ang); free(bp->press);
  free(bp->dry);
  memset(bp, 0, sizeof *bp);
}

void brush_outline(const BrushPath *bp, float *left, float *right) {
  for (int i = 0; i < bp->nsteps; i++) {
    float c = cosf(bp->ang[i]), s = sinf(bp->ang[i]), h = bp->b[i];
    /* right as seen (y down) is (-sin, cos) */
    right[2 * i] = bp->x[i] - s * h;
    right[2 * i + 1] = bp->y[i] + c * h;
    left[2 * i] = bp->x[i] + s * h;
    left[2 * i + 1] = bp->y[i] - c * h;
  }
}

/* ---- deposits ------------------------------------------------------------- */

/* Deposits are placed in coordinates shifted by BRUSH_SHIFT pixels (and
** by the half pixel to the pixel centres), where every point a brush can
** reach in an image is positive, so truncation is floor. */
#define BRUSH_SHIFT 1024
_Static_assert(BRUSH_SHIFT > 500 + 2, "max_width (500) and the splat's reach stay positive");

/* floor(x) as an int, for |x| < 2^31. */
static inline int floor_int(float x) {
  int i = (int)x;
  return i - ((float)i > x);
}

/* Index of the lowest set bit of v (v != 0). */
static inline int lowest_bit(uint32_t v) {
#ifdef __GNUC__
  return __builtin_ctz(v);
#else
  int i = 0;
  for (; !(v & 1); v >>= 1) i++;
  return i;
#endif
}

/* Where deposits go: the band's rows [y0, y1) of cov, columns [x0, x0 + w). */
typedef struct Canvas {
  float *cov;
  int x0, w, y0, y1;
  size_t base;   /* (BRUSH_SHIFT + y0) w + BRUSH_SHIFT + x0: shifted pixel (x, y) is cov[y w + x - base] */
} Canvas;

/* A deposit is split the way Wu draws an antialiased line: the brush
** moves a pixel along the major axis a step, so along it each bristle
** takes the nearest pixel, and across it the two pixels around it share
** the ink by distance. Pixel centres are at whole shifted coordinates.
** Both paths below weigh alike, so a pixel's ink does not depend on which
** of them (which band) drew it. */
static inline void split_weights(float major, float minor, float d, int *im, int *in, float a[2]) {
  *im = (int)(major + 0.5f);
  *in = (int)minor;
  float f = minor - (float)*in;
  a[1] = d * f;
  a[0] = d - a[1];
}

/* Ink d of the bristle at shifted (sx, sy), x the major axis when xmajor;
** its two pixels inside the rows (the caller checked). */
static inline void deposit(const Canvas *cv, float sx, float sy, float d, int xmajor) {
  int im, in, w = cv->w;
  float a[2];
  if (xmajor) {
    split_weights(sx, sy, d, &im, &in, a);
    float *c = cv->cov + ((size_t)in * w + (size_t)im - cv->base);
    c[0] += a[0] * (1 - c[0]);
    c[w] += a[1] * (1 - c[w]);
  } else {
    split_weights(sy, sx, d, &im, &in, a);
    float *c = cv->cov + ((size_t)im * w + (size_t)in - cv->base);
    c[0] += a[0] * (1 - c[0]);
    c[1] += a[1] * (1 - c[1]);
  }
}

/* deposit for a bristle whose pixels may lie outside the rows or the
** image: those are left out. */
static void deposit_clipped(const Canvas *cv, float sx, float sy, float d, int xmajor) {
  int im, in;
  float a[2];
  split_weights(xmajor ? sx : sy, xmajor ? sy : sx, d, &im, &in, a);
  for (int q = 0; q < 2; q++) {
    int xx = (xmajor ? im : in + q) - BRUSH_SHIFT, yy = (xmajor ? in + q : im) - BRUSH_SHIFT;
    if (xx < cv->x0 || xx >= cv->x0 + cv->w || yy < cv->y0 || yy >= cv->y1) continue;
    float *c = &cv->cov[(size_t)(yy - cv->y0) * cv->w + (xx - cv->x0)];
    *c += a[q] * (1 - *c);
  }
}

/* A deposit of a step whose brush reaches past the rows or the image:
** most of its bristles are still inside (the whole path), the rest
** clipped. */
static inline void deposit_near_edge(const Canvas *cv, float sx, float sy, float d, int xmajor) {
  int ix = (int)(xmajor ? sx + 0.5f : sx) - BRUSH_SHIFT, iy = (int)(xmajor ? sy : sy + 0.5f) - BRUSH_SHIFT;
  int x1 = ix + !xmajor, y1 = iy + xmajor;   /* the second pixel */
  if (iy >= cv->y0 && y1 < cv->y1 && ix >= cv->x0 && x1 < cv->x0 + cv->w) deposit(cv, sx, sy, d, xmajor);
  else deposit_clipped(cv, sx, sy, d, xmajor);
}

/* The columns [xa, xb] of rows [ya, yb] (inside the band) were written. */
static void touch(int *lo, int *hi, int y0, int ya, int yb, int xa, int xb) {
  for (int y = ya; y <= yb; y++) {
    if (xa < lo[y - y0]) lo[y - y0] = xa;
    if (xb > hi[y - y0]) hi[y - y0] = xb;
  }
}

/* How many of bp's bristles (sorted, right side first) touch at pressure P. */
static int touching(const BrushPath *bp, float P) {
  int lo = 0, hi = bp->br->n;   /* first with brush_weight 0: u >= P */
  while (lo < hi) {
    int mid = (lo + hi) / 2;
    if (0.5f * (1 - bp->br->uy[mid]) < P) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

/* Scratch for a step's bristles: shifted positions and ink. */
typedef struct StepPoints { float *x, *y, *d; } StepPoints;

/* Positions (x = ox + cA ux - sB uy, y = oy + sA ux + cB uy) and ink (d0 +
** d1 uy) of bristles [0, n), in a loop the compiler vectorises. */
static void bristle_points(int n, const float *restrict ux, const float *restrict uy, float ox, float oy,
                           float cA, float sA, float cB, float sB, float d0, float d1, float *restrict x,
                           float *restrict y, float *restrict d) {
  for (int k = 0; k < n; k++) {
    x[k] = ox + cA * ux[k] - sB * uy[k];
    y[k] = oy + sA * ux[k] + cB * uy[k];
    d[k] = d0 + d1 * uy[k];
  }
}

/* The deposits of step i: the positions and ink of the touching bristles
** first, then the splats of those not in a gap. */
static void cover_step(const BrushPath *bp, int i, const Canvas *cv, int clip, const StepPoints *sp) {
  float B = bp->b[i] > 0.5f ? bp->b[i] : 0.5f, A = bp->aspect * B;
  float c = cosf(bp->ang[i]), s = sinf(bp->ang[i]), P = bp->press[i];
  float cA = c * A, sA = s * A, cB = c * B, sB = s * B;
  float ox = bp->x[i] + (BRUSH_SHIFT - 0.5f), oy = bp->y[i] + (BRUSH_SHIFT - 0.5f);
  int xmajor = fabsf(c) >= fabsf(s);   /* the axis the brush steps along */
  /* ink_load * W_p = ink (1 - u q), u = (1 - uy) / 2, q = (1 - P) / P */
  float q = (1 - P) / P, d0 = bp->ink * (1 - 0.5f * q), d1 = bp->ink * 0.5f * q;
  const uint32_t *bits = &bp->dry[(size_t)i * bp->words];
  const float *X = sp->x, *Y = sp->y, *D = sp->d;
  int n = touching(bp, P);
  bristle_points(n, bp->br->ux, bp->br->uy, ox, oy, cA, sA, cB, sB, d0, d1, sp->x, sp->y, sp->d);
  for (int w = 0; w * 32 < n; w++) {   /* the bristles out of their gaps, a word at a time */
    uint32_t v = bits[w];
    if (n - w * 32 < 32) v &= (1u << (n - w * 32)) - 1;   /* the touching ones only */
    for (; v; v &= v - 1) {
      int k = w * 32 + lowest_bit(v);
      if (clip) deposit_near_edge(cv, X[k], Y[k], D[k], xmajor);
      else deposit(cv, X[k], Y[k], D[k], xmajor);
    }
  }
}

void brush_cover(const BrushPath *bp, float *cov, int x0, int w, int y0, int y1, int *lo, int *hi) {
  Canvas cv = {cov, x0, w, y0, y1, (size_t)(BRUSH_SHIFT + y0) * (size_t)w + BRUSH_SHIFT + (size_t)x0};
  int x1 = x0 + w;
  size_t n = (size_t)bp->br->n + 1;
  StepPoints sp = {xmalloc(n * sizeof(float)), xmalloc(n * sizeof(float)), xmalloc(n * sizeof(float))};
  for (int i = 0; i < bp->nsteps; i++) {
    float B = bp->b[i] > 0.5f ? bp->b[i] : 0.5f, reach = B + 1.5f;   /* A <= B */
    float ox = bp->x[i], oy = bp->y[i];
    int ya = floor_int(oy - reach), yb = floor_int(oy + reach) + 1;
    int xa = floor_int(ox - reach), xb = floor_int(ox + reach) + 1;
    if (yb < y0 || ya >= y1 || xb < x0 || xa >= x1) continue;   /* nothing in these rows */
    cover_step(bp, i, &cv, ya < y0 || yb >= y1 || xa < x0 || xb >= x1, &sp);
    touch(lo, hi, y0, ya > y0 ? ya : y0, yb < y1 - 1 ? yb : y1 - 1, xa > x0 ? xa : x0, xb < x1 - 1 ? xb : x1 - 1);
  }
  free(sp.x);
  free(sp.y);
  free(sp.d);
}
