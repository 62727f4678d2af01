/*
** The reference image: the tiles the edges cross, the meshes' depth in
** them, then every important edge drawn with its id (depth-tested against
** the surfaces with the offset rule of edgeref.h, depth-writing), in id
** order. Work is split into horizontal bands; each band sees every
** triangle and edge in the same order, so the image never depends on the
** number of workers.
*/
#include "edgeref.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"

/* ---- screen triangles ---------------------------------------------------- */

/* A triangle ready to rasterize: pixel positions, nearness, the offset its
** depth is pushed back by, and the object it belongs to. */
typedef struct ScreenTri {
  float x[3], y[3], n[3];
  float off;
  int obj, tri;              /* object index, mesh triangle */
  int ymin, ymax;            /* rows it may cover */
} ScreenTri;

typedef struct TriList { int n, cap; ScreenTri *t; } TriList;

/* A clip-space point to pixels and nearness (1 - depth). */
static void clip_to_screen(const double c[4], int w, int h, float *x, float *y, float *n) {
  double iw = 1.0 / c[3];
  *x = (float)((c[0] * iw + 1) * 0.5 * w);
  *y = (float)((1 - c[1] * iw) * 0.5 * h);
  *n = (float)((1 - c[2] * iw) * 0.5);
}

/* Which tiles get depth: the summed-area table (tw + 1) x (th + 1) of the
** tiles with storage; NULL keeps every triangle. */
typedef struct TileSat {
  int tw, th;
  const int *sat;
  const int *tile;   /* tw * th: the tile's storage block, -1 = none (LineRef.tile) */
} TileSat;

/* Does any tile in columns [tx0, tx1] and rows [ty0, ty1] have storage? */
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

/* Append the triangle p (x0 y0 n0 x1 y1 n1 x2 y2 n2: pixels and
** nearness), whose rows span [ymin, ymax], if it has area. */
static void append_tri(TriList *l, const float *p, double ymin, double ymax, int obj, int tri,
                       double factor, int h) {
  double ax = p[3] - p[0], ay = p[4] - p[1], bx = p[6] - p[0], by = p[7] - p[1];
  double det = ax * by - ay * bx;
  if (!(fabs(det) > 1e-12)) return;
  double an = p[5] - p[2], bn = p[8] - p[2];
  double dndx = (an * by - bn * ay) / det, dndy = (bn * ax - an * bx) / det;
  if (l->n == l->cap) l->t = xgrow(l->t, &l->cap, l->n + 1, sizeof *l->t);
  ScreenTri *t = &l->t[l->n++];
  for (int k = 0; k < 3; k++) { t->x[k] = p[3 * k]; t->y[k] = p[3 * k + 1]; t->n[k] = p[3 * k + 2]; }
  /* polygon offset: factor times the depth slope, plus a few ulps */
  t->off = (float)(factor * (fabs(dndx) + fabs(dndy))) + LINE_DEPTH_EPS;
  t->obj = obj;
  t->tri = tri;
  /* (int)fmax(0, floor(ymin)) and (int)fmin(h - 1, ceil(ymax)) without the
  ** calls: the callers have ymin <= h and ymax >= 0 (or NaN) */
  t->ymin = ymin > 0 ? (int)ymin : 0;
  t->ymax = h - 1;
  if (ymax < h - 1) {
    t->ymax = (int)ymax;
    if (t->ymax < ymax) t->ymax++;
  }
}

/* Append the triangle p (as append_tri) if it has area and reaches a tile
** with storage (any tile when m is NULL). */
static void push_tri(TriList *l, const float *p, int obj, int tri, double factor, int w, int h,
                     const TileSat *m) {
  double ymin = fmin(p[1], fmin(p[4], p[7])), ymax = fmax(p[1], fmax(p[4], p[7]));
  double xmin = fmin(p[0], fmin(p[3], p[6])), xmax = fmax(p[0], fmax(p[3], p[6]));
  if (ymax < 0 || ymin > h || xmax < 0 || xmin > w) return;
  if (m && !sat_any(m, (int)fmax(0, xmin) >> LINE_REF_TILE_BITS, (int)fmax(0, ymin) >> LINE_REF_TILE_BITS,
                    (int)fmin(w - 1, xmax) >> LINE_REF_TILE_BITS, (int)fmin(h - 1, ymax) >> LINE_REF_TILE_BITS))
    return;   /* no edge near it: nothing will read its depth */
  append_tri(l, p, ymin, ymax, obj, tri, factor, h);
}

/* Clip the triangle c[3] against the near plane (z >= -w) and append the
** pieces. */
static void add_clipped(TriList *l, const double *c[3], int obj, int tri, double factor, int w, int h,
                        const TileSat *m) {
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
    clip_to_screen(poly[k], w, h, &s[k][0], &s[k][1], &s[k][2]);
  }
  for (int k = 1; k + 1 < np; k++) {
    float p[9] = {s[0][0], s[0][1], s[0][2], s[k][0], s[k][1], s[k][2],
                  s[k + 1][0], s[k + 1][1], s[k + 1][2]};
    push_tri(l, p, obj, tri, factor, w, h, m);
  }
}

/* A vertex in front of the near plane (z >= -w, w > 0) as clip_to_screen
** puts it; in = 0 marks one the triangles around must clip. tile is the
** index of the tile it lies in, -1 when it is off the image. */
typedef struct ScreenVert { float x, y, n; int in, tile; } ScreenVert;

/* Triangle t of object obj whose corners are all in front of the near
** plane: what add_clipped does for it (the polygon is the triangle
** itself), with the cheap rejections (off the image, no tile with
** storage) before the slope arithmetic of append_tri. */
static void add_front(TriList *l, const ScreenVert *a, const ScreenVert *b, const ScreenVert *c,
                      int obj, int tri, double factor, int w, int h, const TileSat *m) {
  /* all three corners in one tile (most small triangles): so is the box,
  ** and one look at that tile decides */
  if (a->tile >= 0 && a->tile == b->tile && a->tile == c->tile && m->tile[a->tile] < 0) return;
  /* the corners are finite (ScreenVert.in), so plain comparisons give
  ** what fmin and fmax give */
  float ymin = a->y < b->y ? a->y : b->y, ymax = a->y < b->y ? b->y : a->y;
  float xmin = a->x < b->x ? a->x : b->x, xmax = a->x < b->x ? b->x : a->x;
  if (c->y < ymin) ymin = c->y;
  if (c->y > ymax) ymax = c->y;
  if (c->x < xmin) xmin = c->x;
  if (c->x > xmax) xmax = c->x;
  if (ymax < 0 || ymin > h || xmax < 0 || xmin > w) return;
  if (m && !sat_any(m, (int)(xmin > 0 ? xmin : 0) >> LINE_REF_TILE_BITS,
                    (int)(ymin > 0 ? ymin : 0) >> LINE_REF_TILE_BITS,
                    (int)(xmax < w - 1 ? xmax : (float)(w - 1)) >> LINE_REF_TILE_BITS,
                    (int)(ymax < h - 1 ? ymax : (float)(h - 1)) >> LINE_REF_TILE_BITS))
    return;
  float p[9] = {a->x, a->y, a->n, b->x, b->y, b->n, c->x, c->y, c->n};
  append_tri(l, p, ymin, ymax, obj, tri, factor, h);   /* box and tiles checked */
}

/* Every triangle of every object that reaches a tile of sat, with the
** offset its object's edges get from it, but for the back faces an
** object's own front hides (LineObject.hidden). Each vertex is projected
** once; only triangles with a corner behind the near plane go through
** add_clipped. */
static void collect_tris(TriList *l, const LineEdges *edges, const LineObject *objs, int w, int h,
                         const TileSat *sat) {
  for (int i = 0; i < edges->nobj; i++) {
    const Mesh *m = objs[i].mesh;
    const LineVert *v = edges->obj[i].vert;
    const SceneLines *ls = objs[i].lines;
    double factor = LINE_DEPTH_OFFSET_BASE + (ls && ls->present ? ls->depth_offset : 0);
    if (!(factor > 0)) factor = 0;
    ScreenVert *sv = xmalloc(((size_t)m->nverts + 1) * sizeof *sv);   /* every entry written below */
    for (int k = 0; k < m->nverts; k++) {
      const double *c = v[k].clip;
      ScreenVert s = {0, 0, 0, 0, -1};   /* in = 0: behind the near plane */
      if (c[2] + c[3] >= 0 && c[3] > 0) {
        clip_to_screen(c, w, h, &s.x, &s.y, &s.n);
        s.in = isfinite(s.x) && isfinite(s.y) && isfinite(s.n);   /* else the general path */
        if (s.in && s.x >= 0 && s.x < w && s.y >= 0 && s.y < h && sat)
          s.tile = ((int)s.y >> LINE_REF_TILE_BITS) * sat->tw + ((int)s.x >> LINE_REF_TILE_BITS);
      }
      sv[k] = s;
    }
    const unsigned char *hidden = objs[i].hidden;
    for (int t = 0; t < m->ntris; t++) {
      if (hidden && hidden[t]) continue;   /* behind the object's own front */
      const int *tv = m->tri[t];
      const ScreenVert *a = &sv[tv[0]], *b = &sv[tv[1]], *c = &sv[tv[2]];
      if (a->in & b->in & c->in) {
        add_front(l, a, b, c, i, t, factor, w, h, sat);
      } else {
        const double *cc[3] = {v[tv[0]].clip, v[tv[1]].clip, v[tv[2]].clip};
        add_clipped(l, cc, i, t, factor, w, h, sat);
      }
    }
    free(sv);
  }
}

/* Where the raster writes: the tiled buffers of a LineRef, and optionally
** a dense row-major image of object indices (line_object_ids). */
typedef struct RefTarget {
  const LineRef *ref;
  int32_t *ids;
  const uint8_t *walk;   /* NULL, or per row of each block (block * LINE_REF_TILE + (y & 7)):
                            bit x & 7 set where some edge's walk steps, the only pixels
                            whose depth is read (edgeref.h); the rest are left empty */
} RefTarget;

_Static_assert(LINE_REF_TILE == 8, "a row of a tile's walk mask is a byte, a tile's eight a word");

/* The pixels of [xa, xb] (in one tile) of row y of block b that the
** raster must write: bit x & (LINE_REF_TILE - 1). */
static unsigned run_pixels(const RefTarget *rt, int b, int y, int xa, int xb) {
  unsigned bits = (0xFFu << (xa & (LINE_REF_TILE - 1))) & (0xFFu >> (LINE_REF_TILE - 1 - (xb & (LINE_REF_TILE - 1))));
  if (rt->walk) bits &= rt->walk[(size_t)b * LINE_REF_TILE + (y & (LINE_REF_TILE - 1))];
  return bits;
}

/* Pixels of row y from xa on, all in tile block b, take t's nearness (n0
** at xa, dndx a pixel) where it is nearer; only those of bits (run_pixels). */
static void raster_run(const ScreenTri *t, uint32_t k, const RefTarget *rt, int b, int y, int xa,
                       unsigned bits, double n0, double dndx) {
  const LineRef *ref = rt->ref;
  size_t base = (size_t)b * LINE_REF_TILE_PX + ((size_t)(y & (LINE_REF_TILE - 1)) << LINE_REF_TILE_BITS);
  int x = xa;   /* up to the last pixel of bits */
  for (unsigned m = bits >> (xa & (LINE_REF_TILE - 1)); m; m >>= 1, x++) {
    if (!(m & 1)) continue;
    float nf = (float)(n0 + dndx * (x - xa));
    size_t i = base + (x & (LINE_REF_TILE - 1));
    if (nf > ref->near[i]) {
      ref->near[i] = nf;
      ref->id[i] = LINE_REF_TRI | k;
      if (rt->ids) rt->ids[(size_t)y * ref->width + x] = t->obj;
    }
  }
}

/* The sides of a triangle as bounds on the pixel centres px of the row at
** py. Side e (vertex e to e + 1) is a * px + b * py + c >= 0 inside; it
** bounds px from below (a > 0) or above (a < 0) at m * py + q, and a
** horizontal side (a = 0, or NaN) empties the rows where b * py + c < 0.
** The sign of a is that of y[e] - y[e + 1] (times sgn), and the three
** differences of a cycle cannot all have one sign, so at most two sides
** bound from below and at most two from above. Those lists, in side order,
** are padded with a bound that never binds (0 * py -/+ infinity), so a row
** takes the max and min over two of each with no branch on the kinds. */
typedef struct TriSides {
  double lm[2], lq[2];   /* lower bounds: px >= lm * py + lq */
  double um[2], uq[2];   /* upper bounds: px <= um * py + uq */
  double hm[3], hq[3];   /* horizontal: the row is empty if hm * py + hq < 0 */
  int nflat;             /* horizontal sides */
} TriSides;

static void tri_sides(const ScreenTri *t, double sgn, TriSides *s) {
  int nl = 0, nu = 0, nh = 0;
  for (int e = 0; e < 3; e++) {
    int e1 = e == 2 ? 0 : e + 1;
    double ex = t->x[e1] - t->x[e], ey = t->y[e1] - t->y[e];
    double a = -sgn * ey, b = sgn * ex, c = sgn * (ey * t->x[e] - ex * t->y[e]);
    if (a > 0) { s->lm[nl] = -b / a; s->lq[nl++] = -c / a; }
    else if (a < 0) { s->um[nu] = -b / a; s->uq[nu++] = -c / a; }
    else { s->hm[nh] = b; s->hq[nh++] = c; }
  }
  for (; nl < 2; nl++) { s->lm[nl] = 0; s->lq[nl] = -INFINITY; }
  for (; nu < 2; nu++) { s->um[nu] = 0; s->uq[nu] = INFINITY; }
  s->nflat = nh;
}

/* Narrow [*lo, *hi] to the pixel centres of the row at py inside the
** triangle; 0 when none are. */
static inline int tri_row(const TriSides *s, double py, double *lo, double *hi) {
  double l = *lo, h = *hi;
  for (int e = 0; e < 2; e++) {
    double le = s->lm[e] * py + s->lq[e], he = s->um[e] * py + s->uq[e];
    l = le > l ? le : l;
    h = he < h ? he : h;
  }
  *lo = l;
  *hi = h;
  for (int e = 0; e < s->nflat; e++)
    if (s->hm[e] * py + s->hq[e] < 0) return 0;
  return l <= h;
}

/* The pixel columns xa..xb (clamped to 0..xhi) whose centres x + 0.5 lie
** in [lo, hi] (lo >= 0.5); 0 when there are none. */
static int centre_columns(double lo, double hi, int xhi, int *xa, int *xb) {
  double a0 = lo - 0.5, b0 = hi - 0.5;   /* a0 >= 0, so truncation floors */
  *xa = (int)a0;
  *xb = (int)b0;
  if (*xa < a0) (*xa)++;
  if (*xb > xhi) *xb = xhi;
  return *xa <= *xb;
}

/* Which rows of [ra, rb], all in one tile row, need the row raster of
** sides s: byte y & (LINE_REF_TILE - 1) of the result nonzero; 0 when none
** do. Rounding is monotone, so over those rows each side's bound lies
** between its values at the first and the last row (a side that is NaN at
** either end may be anything between; it bounds nothing here). That gives
** the columns any of the rows can reach; a row needs the raster only when
** it has a pixel to write (run_pixels) in a tile of those columns. */
static uint64_t reach_rows(const TriSides *s, const RefTarget *rt, int ra, int rb) {
  const LineRef *ref = rt->ref;
  int xhi = ref->width - 1;
  double pa = ra + 0.5, pb = rb + 0.5, lo = 0.5, hi = xhi + 0.5;
  for (int e = 0; e < 2; e++) {
    double la = s->lm[e] * pa + s->lq[e], lb = s->lm[e] * pb + s->lq[e];
    double ua = s->um[e] * pa + s->uq[e], ub = s->um[e] * pb + s->uq[e];
    if (!isnan(la) && !isnan(lb)) {
      double l = la < lb ? la : lb;
      lo = l > lo ? l : lo;
    }
    if (!isnan(ua) && !isnan(ub)) {
      double u = ua > ub ? ua : ub;
      hi = u < hi ? u : hi;
    }
  }
  int xa, xb;
  if (!(lo <= hi) || !centre_columns(lo, hi, xhi, &xa, &xb)) return 0;
  uint64_t any = 0;   /* the eight row masks of the blocks, or-ed */
  const int *tiles = ref->tile + (size_t)(ra >> LINE_REF_TILE_BITS) * ref->tw;
  for (int tx = xa >> LINE_REF_TILE_BITS; tx <= xb >> LINE_REF_TILE_BITS; tx++) {
    int b = tiles[tx];
    if (b < 0) continue;
    uint64_t m = ~(uint64_t)0;
    if (rt->walk) memcpy(&m, rt->walk + (size_t)b * LINE_REF_TILE, sizeof m);
    /* only the columns [xa, xb]: the same byte mask in every row */
    int ca = tx == xa >> LINE_REF_TILE_BITS ? xa & (LINE_REF_TILE - 1) : 0;
    int cb = tx == xb >> LINE_REF_TILE_BITS ? xb & (LINE_REF_TILE - 1) : LINE_REF_TILE - 1;
    uint64_t cols = (0xFFu << ca) & (0xFFu >> (LINE_REF_TILE - 1 - cb));
    any |= m & cols * 0x0101010101010101u;
  }
  return any;
}

/* Row y of t (number k in its list, sides s, nearness slopes dndx, dndy):
** pixel centres inside (edges included) in tiles with storage take its
** nearness when it is nearer than what is there, and LINE_REF_TRI | k as
** their id. */
static void raster_row(const ScreenTri *t, uint32_t k, const RefTarget *rt, const TriSides *s,
                       double dndx, double dndy, int y) {
  const LineRef *ref = rt->ref;
  int xhi = ref->width - 1;
  double py = y + 0.5, lo = 0.5, hi = xhi + 0.5;
  int xa, xb;
  if (!tri_row(s, py, &lo, &hi) || !centre_columns(lo, hi, xhi, &xa, &xb)) return;
  double n0 = 0;
  int have_n0 = 0;   /* most rows write nothing: their nearness is never needed */
  const int *tiles = ref->tile + (size_t)(y >> LINE_REF_TILE_BITS) * ref->tw;
  for (int tx = xa >> LINE_REF_TILE_BITS; tx <= xb >> LINE_REF_TILE_BITS; tx++) {
    int b = tiles[tx];
    if (b < 0) continue;
    int ta = tx << LINE_REF_TILE_BITS, tb = ta + LINE_REF_TILE - 1;
    if (ta < xa) ta = xa;
    if (tb > xb) tb = xb;
    unsigned bits = run_pixels(rt, b, y, ta, tb);
    if (!bits) continue;
    if (!have_n0) {
      n0 = t->n[0] + dndx * (xa + 0.5 - (double)t->x[0]) + dndy * (py - (double)t->y[0]);
      have_n0 = 1;
    }
    raster_run(t, k, rt, b, y, ta, bits, n0 + dndx * (ta - xa), dndx);
  }
}

/* Rasterize t (number k in its list) into rows [y0, y1), a tile row at a
** time, skipping the rows reach_rows rules out. */
static void raster_tri(const ScreenTri *t, uint32_t k, const RefTarget *rt, int y0, int y1) {
  int ya = t->ymin > y0 ? t->ymin : y0, yb = t->ymax < y1 - 1 ? t->ymax : y1 - 1;
  if (ya > yb) return;
  double x0 = t->x[0], y0d = t->y[0];
  double ax = t->x[1] - x0, ay = t->y[1] - y0d, bx = t->x[2] - x0, by = t->y[2] - y0d;
  double det = ax * by - ay * bx;
  double an = t->n[1] - t->n[0], bn = t->n[2] - t->n[0];
  double dndx = (an * by - bn * ay) / det, dndy = (bn * ax - an * bx) / det;
  TriSides sides;
  tri_sides(t, det > 0 ? 1 : -1, &sides);
  for (int ra = ya; ra <= yb; ra = (ra | (LINE_REF_TILE - 1)) + 1) {
    int rb = ra | (LINE_REF_TILE - 1);
    if (rb > yb) rb = yb;
    uint64_t rows = reach_rows(&sides, rt, ra, rb);
    for (int y = ra; y <= rb; y++) {
      uint64_t r = rows >> (y & (LINE_REF_TILE - 1)) * 8;   /* this row's byte and those below */
      if (!r) break;
      if (r & 0xFF) raster_row(t, k, rt, &sides, dndx, dndy, y);
    }
  }
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
  clip_to_screen(ca, w, h, &x0, &y0, &n0);
  clip_to_screen(cb, w, h, &x1, &y1, &n1);
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

/* ---- bands --------------------------------------------------------------- */

/* What the depth test of an edge needs to know about it. */
typedef struct EdgeInfo {
  int obj, f0, f1, v0, v1;
  unsigned char facing;     /* bit 0: a face of it looks at the viewer, bit 1: one looks away */
} EdgeInfo;

typedef struct RefJob {
  LineRef *ref;
  const TriList *tris;
  const LineEdges *edges;
  const EdgeInfo *info;     /* per id - 1 */
  RefTarget rt;
  int nbands;
  int **count;              /* per band: pixel counts per id - 1 */
} RefJob;

/* Rows of a band: whole tile rows, so bands never share a tile. */
static void band_rows(const RefJob *j, int band, int *y0, int *y1) {
  int th = j->ref->th;
  *y0 = (int)((long long)th * band / j->nbands) << LINE_REF_TILE_BITS;
  *y1 = (int)((long long)th * (band + 1) / j->nbands) << LINE_REF_TILE_BITS;
  if (*y1 > j->ref->height) *y1 = j->ref->height;
}

/* May triangle t push its depth back for edge e? When it faces the
** viewer as one of e's faces does (front or back). A face turned the other
** way occludes at its true depth, so an edge on the far side of an object
** does not leak out from behind a silhouette or a corner. */
static int lenient(const RefJob *j, const ScreenTri *t, const EdgeInfo *e) {
  return (e->facing & (j->edges->obj[t->obj].front[t->tri] ? 1 : 2)) != 0;
}

/* Draw span s (id) into rows [y0, y1): where it is not behind the nearest
** surface (pushed back by its offset when lenient) or an earlier edge, the
** pixel takes the id and the edge's nearness. */
static void draw_span(const RefJob *j, const LineSpan *s, uint32_t id, int *count, int y0, int y1) {
  int ymin = s->py0 < s->py1 ? s->py0 : s->py1, ymax = s->py0 < s->py1 ? s->py1 : s->py0;
  if (ymax < y0 || ymin >= y1) return;
  LineRef *ref = j->ref;
  const EdgeInfo *e = &j->info[id - 1];
  float dn = s->nsteps > 1 ? (s->n1 - s->n0) / (float)(s->nsteps - 1) : 0;
  LineSpanWalk w;
  line_span_walk_start(&w, s);
  for (int i = 0; i < s->nsteps; i++, line_span_walk_next(&w)) {
    int x = w.x, y = w.y;
    if (y < y0 || y >= y1) continue;
    long at = line_ref_at(ref, x, y);   /* always stored: the walk made the tile */
    if (at < 0) continue;
    float n = s->n0 + dn * (float)i, limit = ref->near[at];
    uint32_t old = ref->id[at];
    if (old & LINE_REF_TRI) {   /* a surface: pushed back when lenient */
      const ScreenTri *t = &j->tris->t[old & ~LINE_REF_TRI];
      limit -= lenient(j, t, e) ? t->off : LINE_DEPTH_EPS;
      old = 0;
    }
    if (n < limit || n <= 0) continue;   /* hidden (or beyond the far plane) */
    if (old == id) continue;
    /* against an earlier edge (ends meeting at a vertex): the nearer wins;
    ** at equal depth, an edge with a face toward the viewer beats one
    ** without, else the earlier stays */
    if (old && n <= limit + LINE_DEPTH_EPS && !((e->facing & 1) && !(j->info[old - 1].facing & 1)))
      continue;
    if (old) count[old - 1]--;
    count[id - 1]++;
    ref->id[at] = id;
    ref->near[at] = n;
  }
}

static void ref_band(void *ctx, int band, int worker) {
  RefJob *j = ctx;
  LineRef *ref = j->ref;
  int y0, y1;
  band_rows(j, band, &y0, &y1);
  for (int i = 0; i < j->tris->n; i++) {
    const ScreenTri *t = &j->tris->t[i];
    if (t->ymax >= y0 && t->ymin < y1) raster_tri(t, (uint32_t)i, &j->rt, y0, y1);
  }
  if (!j->info) return;   /* line_object_ids: surfaces only */
  for (int i = 0; i < ref->nids; i++)
    if (ref->span[i].nsteps) draw_span(j, &ref->span[i], (uint32_t)i + 1, j->count[band], y0, y1);
}

static int band_count(int threads, int tile_rows) {
  int n = threads > 1 ? threads * 4 : 1;
  return n > tile_rows ? (tile_rows > 0 ? tile_rows : 1) : n;
}

static EdgeInfo *edge_info(const LineEdges *edges) {
  EdgeInfo *info = xmalloc(((size_t)edges->n + 1) * sizeof *info);
  for (int i = 0; i < edges->n; i++) {
    const LineObjEdges *oe = &edges->obj[edges->obj_of[i]];
    const MeshEdge *me = &oe->mesh->edges[edges->edge_of[i]];
    EdgeInfo *e = &info[i];
    e->obj = edges->obj_of[i];
    e->f0 = me->f[0]; e->f1 = me->f[1];
    e->v0 = me->v[0]; e->v1 = me->v[1];
    e->facing = 0;
    for (int k = 0; k < 2; k++)
      if (me->f[k] >= 0) e->facing |= oe->front[me->f[k]] ? 1 : 2;
  }
  return info;
}

/* Give storage to the tiles the walks of ref's spans cross (blocks in
** tile order) and fill *sat with the summed-area table of those tiles. */
static void edge_tiles(LineRef *ref, int **sat) {
  int tw = ref->tw, th = ref->th;
  for (int i = 0; i < ref->nids; i++) {
    LineSpanWalk w;
    line_span_walk_start(&w, &ref->span[i]);
    for (int k = 0; k < ref->span[i].nsteps; k++, line_span_walk_next(&w))
      ref->tile[(w.y >> LINE_REF_TILE_BITS) * tw + (w.x >> LINE_REF_TILE_BITS)] = 0;
  }
  int W = tw + 1;
  *sat = xcalloc((size_t)W * (th + 1), sizeof **sat);
  for (int ty = 0; ty < th; ty++) {
    int run = 0;   /* tiles with storage in this row so far */
    for (int tx = 0; tx < tw; tx++) {
      int *t = &ref->tile[ty * tw + tx];
      int on = *t == 0;
      *t = on ? ref->nblocks++ : -1;
      run += on;
      (*sat)[(ty + 1) * W + tx + 1] = (*sat)[ty * W + tx + 1] + run;
    }
  }
}

/* Per row of each block of ref, the pixels the walks of its spans visit
** (RefTarget.walk). */
static uint8_t *walk_masks(const LineRef *ref) {
  uint8_t *walk = xcalloc((size_t)ref->nblocks * LINE_REF_TILE + 1, 1);
  for (int i = 0; i < ref->nids; i++) {
    LineSpanWalk w;
    line_span_walk_start(&w, &ref->span[i]);
    for (int k = 0; k < ref->span[i].nsteps; k++, line_span_walk_next(&w)) {
      int b = ref->tile[(w.y >> LINE_REF_TILE_BITS) * ref->tw + (w.x >> LINE_REF_TILE_BITS)];
      walk[(size_t)b * LINE_REF_TILE + (w.y & (LINE_REF_TILE - 1))] |= (uint8_t)(1u << (w.x & (LINE_REF_TILE - 1)));
    }
  }
  return walk;
}

/* The tile grid of a width x height image, every tile without storage. */
static void ref_init(LineRef *ref, int width, int height) {
  memset(ref, 0, sizeof *ref);
  ref->width = width;
  ref->height = height;
  ref->tw = (width + LINE_REF_TILE - 1) >> LINE_REF_TILE_BITS;
  ref->th = (height + LINE_REF_TILE - 1) >> LINE_REF_TILE_BITS;
  size_t nt = (size_t)ref->tw * ref->th;
  ref->tile = xmalloc((nt ? nt : 1) * sizeof *ref->tile);
  for (size_t i = 0; i < nt; i++) ref->tile[i] = -1;
}

static void ref_alloc_blocks(LineRef *ref) {
  size_t n = (size_t)ref->nblocks * LINE_REF_TILE_PX;
  ref->near = xcalloc(n ? n : 1, sizeof *ref->near);
  ref->id = xcalloc(n ? n : 1, sizeof *ref->id);
}

void line_ref_blank(LineRef *ref, int width, int height) {
  ref_init(ref, width, height);
  for (int i = 0; i < ref->tw * ref->th; i++) ref->tile[i] = ref->nblocks++;
  ref_alloc_blocks(ref);
  ref->span = xcalloc(1, sizeof *ref->span);
  ref->count = xcalloc(1, sizeof *ref->count);
  ref->visible = xcalloc(1, sizeof *ref->visible);
}

void line_ref_build(LineRef *ref, const LineEdges *edges, const LineObject *objs, int width,
                    int height, int threads) {
  ref_init(ref, width, height);
  ref->nids = edges->n;
  ref->span = xcalloc((size_t)edges->n + 1, sizeof *ref->span);
  for (int i = 0; i < edges->n; i++) {
    const LineObjEdges *oe = &edges->obj[edges->obj_of[i]];
    const MeshEdge *me = &oe->mesh->edges[edges->edge_of[i]];
    make_span(&ref->span[i], &oe->vert[me->v[0]], &oe->vert[me->v[1]], width, height);
  }
  int *sat;
  edge_tiles(ref, &sat);   /* storage only where edges are */
  ref_alloc_blocks(ref);
  TileSat ts = {ref->tw, ref->th, sat, ref->tile};
  TriList tris = {0, 0, NULL};
  if (ref->nblocks) collect_tris(&tris, edges, objs, width, height, &ts);
  uint8_t *walk = walk_masks(ref);
  RefJob job = {ref, &tris, edges, edge_info(edges), {ref, NULL, walk}, band_count(threads, ref->th),
                NULL};
  job.count = xmalloc((size_t)job.nbands * sizeof *job.count);
  for (int b = 0; b < job.nbands; b++) job.count[b] = xcalloc((size_t)edges->n + 1, sizeof(int));
  if (ref->nblocks) line_parallel(job.nbands, threads, ref_band, &job);
  ref->count = job.count[0];
  for (int b = 1; b < job.nbands; b++) {
    for (int i = 0; i < edges->n; i++) ref->count[i] += job.count[b][i];
    free(job.count[b]);
  }
  free(job.count);
  free((void *)job.info);
  free(walk);
  free(sat);
  free(tris.t);
  ref->visible = xmalloc(((size_t)edges->n + 1) * sizeof *ref->visible);
  for (int i = 0; i < edges->n; i++)
    if (ref->count[i] > 0) ref->visible[ref->nvisible++] = i + 1;
}

void line_ref_free(LineRef *ref) {
  free(ref->tile);
  free(ref->near);
  free(ref->id);
  free(ref->span);
  free(ref->count);
  free(ref->visible);
  memset(ref, 0, sizeof *ref);
}

int32_t *line_object_ids(const LineEdges *edges, const LineObject *objs, int width, int height,
                         int threads) {
  size_t npx = (size_t)width * height;
  int32_t *ids = xmalloc((npx ? npx : 1) * sizeof *ids);
  for (size_t i = 0; i < npx; i++) ids[i] = -1;
  LineRef ref;
  line_ref_blank(&ref, width, height);   /* every tile */
  TriList tris = {0, 0, NULL};
  collect_tris(&tris, edges, objs, width, height, NULL);
  RefJob job = {&ref, &tris, edges, NULL, {&ref, ids, NULL}, band_count(threads, ref.th), NULL};
  line_parallel(job.nbands, threads, ref_band, &job);
  free(tris.t);
  line_ref_free(&ref);
  return ids;
}
