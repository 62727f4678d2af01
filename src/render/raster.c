/*
** Triangle rasterizer (raster.h): clipping in homogeneous coordinates,
** fixed-point triangle setup with the top-left fill rule, and the one loop
** that scan-converts a triangle into G-buffer planes.
*/
#include "raster.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"

#define SUB (1 << RAST_SUBPIXEL_BITS)   /* fixed-point units a pixel */

/* A clip-space vertex with the source barycentrics it carries. */
typedef struct ClipVert {
  double h[4];    /* x, y, z, w */
  double b[2];    /* b1, b2 in the source triangle */
} ClipVert;

/* ---- clipping ------------------------------------------------------------ */

/* The six planes a vertex must be on the inside of, as signed distances:
** near z >= -w, far z <= w, and the guard band |x| <= gx w, |y| <= gy w. */
enum { NPLANES = 6, MAXPOLY = 3 + NPLANES };

static double plane_dist(const ClipVert *v, int plane, double gx, double gy) {
  const double *h = v->h;
  switch (plane) {
  case 0: return h[2] + h[3];
  case 1: return h[3] - h[2];
  case 2: return gx * h[3] + h[0];
  case 3: return gx * h[3] - h[0];
  case 4: return gy * h[3] + h[1];
  default: return gy * h[3] - h[1];
  }
}

/* Bit p set when v is outside plane p (plane_dist, unrolled). */
static inline unsigned outcode(const ClipVert *v, double gx, double gy) {
  const double *h = v->h;
  return (unsigned)(h[2] + h[3] < 0) | (unsigned)(h[3] - h[2] < 0) << 1 |
         (unsigned)(gx * h[3] + h[0] < 0) << 2 | (unsigned)(gx * h[3] - h[0] < 0) << 3 |
         (unsigned)(gy * h[3] + h[1] < 0) << 4 | (unsigned)(gy * h[3] - h[1] < 0) << 5;
}

/* The point where the edge from inside vertex a (distance da >= 0) to
** outside vertex b (db < 0) crosses the plane. Always computed from the
** inside end, so two triangles sharing the edge get bit-identical points. */
static ClipVert crossing(const ClipVert *in, double din, const ClipVert *out, double dout) {
  double t = din / (din - dout);
  ClipVert r;
  for (int k = 0; k < 4; k++) r.h[k] = in->h[k] + t * (out->h[k] - in->h[k]);
  for (int k = 0; k < 2; k++) r.b[k] = in->b[k] + t * (out->b[k] - in->b[k]);
  return r;
}

/* Sutherland-Hodgman against each plane the polygon crosses; returns the
** vertex count of the clipped polygon (0 when nothing is left). */
static int clip_polygon(ClipVert *poly, int n, unsigned planes, double gx, double gy) {
  ClipVert tmp[MAXPOLY];
  for (int p = 0; p < NPLANES && n > 0; p++) {
    if (!(planes & (1u << p))) continue;
    int m = 0;
    for (int i = 0; i < n; i++) {
      const ClipVert *a = &poly[i], *b = &poly[(i + 1) % n];
      double da = plane_dist(a, p, gx, gy), db = plane_dist(b, p, gx, gy);
      if (da >= 0) tmp[m++] = *a;
      if (da >= 0 && db < 0) tmp[m++] = crossing(a, da, b, db);
      else if (da < 0 && db >= 0) tmp[m++] = crossing(b, db, a, da);
    }
    for (int i = 0; i < m; i++) poly[i] = tmp[i];
    n = m;
  }
  return n;
}

/* ---- setup --------------------------------------------------------------- */

/* Round to the nearest integer, halves away from zero (inline, exact). */
static inline int64_t snap(double v) {
  return v >= 0 ? (int64_t)(v + 0.5) : -(int64_t)(0.5 - v);
}

/* Pixel position on the grid, depth and 1 / w of clip (w > 0), into v. */
static inline void project(RastVert *v, const double clip[4], int width, int height) {
  double inv = 1.0 / clip[3];
  v->X = (int32_t)snap((clip[0] * inv + 1) * 0.5 * width * SUB);   /* NDC -> pixel, on the grid */
  v->Y = (int32_t)snap((1 - clip[1] * inv) * 0.5 * height * SUB);
  v->z = (float)((clip[2] * inv + 1) * 0.5);
  v->iw = (float)inv;
}

/* rast_vertex with the guard band's gx, gy worked out. */
static inline void vertex_in(RastVert *v, const double clip[4], double gx, double gy, int width, int height) {
  /* x - x is 0 for a finite x, NaN for a NaN or an infinity */
  if (!((clip[0] - clip[0]) + (clip[1] - clip[1]) + (clip[2] - clip[2]) + (clip[3] - clip[3]) == 0)) {
    v->outcode = RAST_INVALID;   /* NaN or infinite: its triangles are dropped */
    v->X = v->Y = 0; v->z = v->iw = 0;
    return;
  }
  ClipVert cv = {{clip[0], clip[1], clip[2], clip[3]}, {0, 0}};
  v->outcode = outcode(&cv, gx, gy);
  if (v->outcode) { v->X = v->Y = 0; v->z = v->iw = 0; return; }
  project(v, clip, width, height);
}

/* rast_clip_point, inline for rast_vertices' loop. */
static inline void clip_point(double clip[4], const double m[4][4], const float pos[3]) {
  double x = pos[0], y = pos[1], z = pos[2];
  for (int i = 0; i < 4; i++) clip[i] = m[i][0] * x + m[i][1] * y + m[i][2] * z + m[i][3];
}

void rast_vertex(RastVert *v, const double clip[4], int width, int height) {
  /* guard band: |x/w| <= gx puts pixel x within RAST_GUARD_PX of the image */
  double gx = 1 + 2.0 * RAST_GUARD_PX / width, gy = 1 + 2.0 * RAST_GUARD_PX / height;
  vertex_in(v, clip, gx, gy, width, height);
}

void rast_clip_point(double clip[4], const double m[4][4], const float pos[3]) { clip_point(clip, m, pos); }

void rast_vertices(RastVert *out, const float (*pos)[3], int n, const double m[4][4], int width, int height) {
  double gx = 1 + 2.0 * RAST_GUARD_PX / width, gy = 1 + 2.0 * RAST_GUARD_PX / height;
  double mm[4][4];   /* in a local: a store to out could alias m */
  memcpy(mm, m, sizeof mm);
  for (int v = 0; v < n; v++) {
    double clip[4];
    clip_point(clip, (const double(*)[4])mm, pos[v]);
    vertex_in(&out[v], clip, gx, gy, width, height);
  }
}

/* Plane of an attribute with values f[0..2] at pixel positions (x, y):
** p[0] = f0, p[1] = df/dx, p[2] = df/dy, solved from
** f1 - f0 = p1 ex1 + p2 ey1 and f2 - f0 = p1 ex2 + p2 ey2 (inv_det is
** 1 / (ex1 ey2 - ex2 ey1)). In double: thin triangles near the camera
** cancel too much in float. */
static void plane(float p[3], const double f[3], double ex1, double ey1, double ex2, double ey2,
                  double inv_det) {
  double d1 = f[1] - f[0], d2 = f[2] - f[0];
  p[0] = (float)f[0];
  p[1] = (float)((d1 * ey2 - d2 * ey1) * inv_det);
  p[2] = (float)((d2 * ex1 - d1 * ex2) * inv_det);
}

/* The pixels whose centre (i + 1/2) lies in the bounding box of in[0..2]:
** ceil(min - 1/2) .. floor(max - 1/2), clamped to the target, into
** box[0..3] (x0, y0, x1, y1), and twice the signed area on the grid.
** Returns 0 when the triangle has no area or its box holds no sample
** centre: most triangles of a fine mesh that are dropped are dropped here. */
static inline int cover_box(const RastVert *const in[3], int width, int height, int box[4], int64_t *area) {
  int64_t xmin = in[0]->X, xmax = in[0]->X, ymin = in[0]->Y, ymax = in[0]->Y;
  for (int i = 1; i < 3; i++) {
    xmin = in[i]->X < xmin ? in[i]->X : xmin; xmax = in[i]->X > xmax ? in[i]->X : xmax;
    ymin = in[i]->Y < ymin ? in[i]->Y : ymin; ymax = in[i]->Y > ymax ? in[i]->Y : ymax;
  }
  /* floor(a / SUB) is an arithmetic shift */
  int64_t bx0 = -((SUB / 2 - xmin) >> RAST_SUBPIXEL_BITS), bx1 = ((xmax - SUB / 2) >> RAST_SUBPIXEL_BITS) + 1;
  int64_t by0 = -((SUB / 2 - ymin) >> RAST_SUBPIXEL_BITS), by1 = ((ymax - SUB / 2) >> RAST_SUBPIXEL_BITS) + 1;
  box[0] = (int)(bx0 > 0 ? bx0 : 0);
  box[1] = (int)(by0 > 0 ? by0 : 0);
  box[2] = (int)(bx1 < width ? bx1 : width);
  box[3] = (int)(by1 < height ? by1 : height);
  if (box[0] >= box[2] || box[1] >= box[3]) return 0;
  int64_t ex1 = in[1]->X - in[0]->X, ey1 = in[1]->Y - in[0]->Y;   /* < 2^25: no overflow in 32 bits */
  int64_t ex2 = in[2]->X - in[0]->X, ey2 = in[2]->Y - in[0]->Y;
  *area = ex1 * ey2 - ex2 * ey1;
  return *area != 0;
}

/* The edge functions of triangle v[0..2] (counter-clockwise on the grid:
** positive area) into a, b, c, as RastTri holds them, fill rule included. */
static inline void edge_functions(const RastVert *const v[3], int32_t a[3], int32_t b[3], int64_t c[3]) {
  static const int next[3] = {1, 2, 0}, prev[3] = {2, 0, 1};
  for (int i = 0; i < 3; i++) {
    /* edge i runs from vertex i+1 to i+2; with d = end - start,
    ** e(P) = dx (P.y - start.y) - dy (P.x - start.x) */
    const RastVert *s = v[next[i]], *e = v[prev[i]];
    int64_t dx = e->X - s->X, dy = e->Y - s->Y;
    a[i] = (int32_t)-dy;   /* |dx|, |dy| < 2^25 inside the guard band */
    b[i] = (int32_t)dx;
    c[i] = dy * s->X - dx * s->Y;
    /* Top-left rule (y down): a top edge is horizontal with the interior
    ** below (dx > 0), a left edge has the interior to its right (dy < 0).
    ** Samples exactly on any other edge belong to the neighbour: e > 0. */
    int top_left = dy < 0 || (dy == 0 && dx > 0);
    if (!top_left) c[i] -= 1;
  }
}

/* Boxes of at most this many sample centres are tested one by one before
** the rest of the setup: most triangles of a fine mesh that hold no
** sample have such a box (Wuson L4 at 1080p: 128 k of 134 k). */
enum { SMALL_BOX = 4 };

/* Does the triangle of edge functions a, b, c cover a sample centre of
** box (x0, y0, x1, y1)? The test rast_triangle makes, sample by sample,
** for a small box; a bigger one is taken to cover some. */
static inline int covers_sample(const int32_t a[3], const int32_t b[3], const int64_t c[3], const int box[4]) {
  int nx = box[2] - box[0], ny = box[3] - box[1];
  if (nx * ny > SMALL_BOX) return 1;
  int64_t X = (int64_t)box[0] * SUB + SUB / 2, Y = (int64_t)box[1] * SUB + SUB / 2;
  int64_t r0 = a[0] * X + b[0] * Y + c[0], r1 = a[1] * X + b[1] * Y + c[1], r2 = a[2] * X + b[2] * Y + c[2];
  for (int y = 0; y < ny; y++) {
    int64_t e0 = r0, e1 = r1, e2 = r2;
    for (int x = 0; x < nx; x++) {
      if ((e0 | e1 | e2) >= 0) return 1;   /* no edge function negative: inside */
      e0 += (int64_t)a[0] * SUB, e1 += (int64_t)a[1] * SUB, e2 += (int64_t)a[2] * SUB;
    }
    r0 += (int64_t)b[0] * SUB, r1 += (int64_t)b[1] * SUB, r2 += (int64_t)b[2] * SUB;
  }
  return 0;
}

/* Set up triangle v[0..2] (all inside the planes) carrying barycentrics
** b[0..2]. Returns 0 when it has no area or covers no sample centre (its
** box holds none, or it is small and none lies inside it). */
static int setup(RastTri *t, const RastVert *const in[3], const double b[3][2], int32_t object,
                 int32_t face, int width, int height) {
  int box[4];
  int64_t area;
  if (!cover_box(in, width, height, box, &area)) return 0;
  /* a negative area swaps vertices 1 and 2 so the interior is where all
  ** three edge functions are positive */
  int ord[3] = {0, 1, 2};
  if (area < 0) { ord[1] = 2; ord[2] = 1; }
  const RastVert *v[3] = {in[ord[0]], in[ord[1]], in[ord[2]]};
  edge_functions(v, t->a, t->b, t->c);
  if (!covers_sample(t->a, t->b, t->c, box)) return 0;
  t->x0 = box[0], t->y0 = box[1], t->x1 = box[2], t->y1 = box[3];
  /* attribute planes, in pixels relative to vertex 0 */
  const double inv_sub = 1.0 / SUB;
  double ex1 = (double)(v[1]->X - v[0]->X) * inv_sub, ey1 = (double)(v[1]->Y - v[0]->Y) * inv_sub;
  double ex2 = (double)(v[2]->X - v[0]->X) * inv_sub, ey2 = (double)(v[2]->Y - v[0]->Y) * inv_sub;
  double inv_det = (double)SUB * SUB / (double)(area < 0 ? -area : area);
  double z[3], iw[3], b1w[3], b2w[3];
  for (int i = 0; i < 3; i++) {
    z[i] = v[i]->z;
    iw[i] = v[i]->iw;
    b1w[i] = b[ord[i]][0] * v[i]->iw;   /* b / w is affine in screen space */
    b2w[i] = b[ord[i]][1] * v[i]->iw;
  }
  t->ox = (float)((double)v[0]->X * inv_sub);
  t->oy = (float)((double)v[0]->Y * inv_sub);
  plane(t->z, z, ex1, ey1, ex2, ey2, inv_det);
  plane(t->iw, iw, ex1, ey1, ex2, ey2, inv_det);
  plane(t->b1w, b1w, ex1, ey1, ex2, ey2, inv_det);
  plane(t->b2w, b2w, ex1, ey1, ex2, ey2, inv_det);
  t->object = object;
  t->face = face;
  return 1;
}

static RastTri *list_push(RastTriList *list) {
  if (list->n == list->cap) list->tris = xgrow(list->tris, &list->cap, list->n + 1, sizeof *list->tris);
  return &list->tris[list->n];
}

/* A triangle crossing some plane: clip it as a polygon, project the new
** vertices, and fan it out into triangles. */
static int emit_clipped(RastTriList *list, const double *const clip[3], unsigned planes,
                        int32_t object, int32_t face, int width, int height) {
  static const double corner_bary[3][2] = {{0, 0}, {1, 0}, {0, 1}};
  double gx = 1 + 2.0 * RAST_GUARD_PX / width, gy = 1 + 2.0 * RAST_GUARD_PX / height;
  ClipVert poly[MAXPOLY];
  for (int i = 0; i < 3; i++) {
    for (int k = 0; k < 4; k++) poly[i].h[k] = clip[i][k];
    poly[i].b[0] = corner_bary[i][0];
    poly[i].b[1] = corner_bary[i][1];
  }
  int n = clip_polygon(poly, 3, planes, gx, gy);
  RastVert pv[MAXPOLY];
  for (int i = 0; i < n; i++) {
    pv[i].outcode = 0;   /* on the planes up to rounding: inside */
    project(&pv[i], poly[i].h, width, height);
  }
  int emitted = 0;
  for (int i = 1; i + 1 < n; i++) {   /* fan around vertex 0 */
    const RastVert *tv[3] = {&pv[0], &pv[i], &pv[i + 1]};
    double b[3][2] = {{poly[0].b[0], poly[0].b[1]}, {poly[i].b[0], poly[i].b[1]},
                      {poly[i + 1].b[0], poly[i + 1].b[1]}};
    if (setup(list_push(list), tv, b, object, face, width, height)) {
      list->n++;
      emitted++;
    }
  }
  return emitted;
}

int rast_emit(RastTriList *list, const RastVert *const v[3], const double *const clip[3], int32_t object,
              int32_t face, int width, int height) {
  static const double corner_bary[3][2] = {{0, 0}, {1, 0}, {0, 1}};
  unsigned all = v[0]->outcode & v[1]->outcode & v[2]->outcode;
  unsigned any = v[0]->outcode | v[1]->outcode | v[2]->outcode;
  if (all || (any & RAST_INVALID)) return 0;   /* wholly outside one plane, or not a number */
  if (any) return emit_clipped(list, clip, any, object, face, width, height);
  if (!setup(list_push(list), v, corner_bary, object, face, width, height)) return 0;
  list->n++;
  return 1;
}

int rast_setup(RastTri *t, const RastVert *const v[3], int32_t object, int32_t face, int width, int height) {
  static const double corner_bary[3][2] = {{0, 0}, {1, 0}, {0, 1}};
  return setup(t, v, corner_bary, object, face, width, height);
}

int rast_bounds(const RastVert *const v[3], int width, int height, int box[4], float *zmin) {
  int64_t area;
  if (!cover_box(v, width, height, box, &area)) return 0;
  if ((box[2] - box[0]) * (box[3] - box[1]) <= SMALL_BOX) {   /* as setup would find it */
    const RastVert *o[3] = {v[0], area < 0 ? v[2] : v[1], area < 0 ? v[1] : v[2]};
    int32_t ea[3], eb[3];
    int64_t ec[3];
    edge_functions(o, ea, eb, ec);
    if (!covers_sample(ea, eb, ec, box)) return 0;
  }
  /* the depth plane through the three vertices, in double, relative to
  ** vertex 0 (the plane origin setup takes: its position is exact in
  ** float, and so are the offsets of sample centres from it) */
  const double inv_sub = 1.0 / SUB;
  double ex1 = (double)(v[1]->X - v[0]->X) * inv_sub, ey1 = (double)(v[1]->Y - v[0]->Y) * inv_sub;
  double ex2 = (double)(v[2]->X - v[0]->X) * inv_sub, ey2 = (double)(v[2]->Y - v[0]->Y) * inv_sub;
  double inv_det = (double)SUB * SUB / (double)area;   /* signed: the vertices in their own order */
  double d1 = (double)v[1]->z - v[0]->z, d2 = (double)v[2]->z - v[0]->z;
  double gx = (d1 * ey2 - d2 * ey1) * inv_det, gy = (d2 * ex1 - d1 * ex2) * inv_det;
  double ox = (double)v[0]->X * inv_sub, oy = (double)v[0]->Y * inv_sub;
  double fx0 = box[0] + 0.5 - ox, fx1 = box[2] - 0.5 - ox, fy0 = box[1] + 0.5 - oy, fy1 = box[3] - 0.5 - oy;
  double zx = gx * fx0 < gx * fx1 ? gx * fx0 : gx * fx1, zy = gy * fy0 < gy * fy1 ? gy * fy0 : gy * fy1;
  /* the float sums the setup's bound and the drawing make round within
  ** 2^-24 of their terms' sizes: the margin is far wider */
  double size = fabs(v[0]->z) + fabs(gx) * (fabs(fx0) + fabs(fx1)) + fabs(gy) * (fabs(fy0) + fabs(fy1));
  *zmin = (float)(v[0]->z + zx + zy - 2e-5 - 1e-6 * size);
  return 1;
}

void rast_list_free(RastTriList *list) {
  free(list->tris);
  *list = (RastTriList){0};
}

/* ---- scan conversion ----------------------------------------------------- */

/* A row's span: of the n samples k = 0 .. n - 1 where edge i has the
** value e[i] + k step[i], those inside all three (every value >= 0): the
** triangle is convex, so they are one run [*k0, *k1) (empty: k0 = k1).
** Worked out in integers from where each edge crosses zero, exactly the
** samples a walk testing each one would find. */
static void row_span(const int64_t e[3], const int64_t step[3], int n, int *k0, int *k1) {
  int64_t lo = 0, hi = n;
  for (int i = 0; i < 3; i++) {
    if (step[i] > 0) {          /* rising: inside from its first k with e + k step >= 0 on */
      if (e[i] < 0) {
        int64_t k = (-e[i] + step[i] - 1) / step[i];
        if (k > lo) lo = k;
      }
    } else if (step[i] < 0) {   /* falling: inside up to its last such k */
      int64_t k = e[i] < 0 ? 0 : e[i] / -step[i] + 1;
      if (k < hi) hi = k;
    } else if (e[i] < 0) {      /* level and outside: no sample */
      hi = 0;
    }
  }
  if (lo > n) lo = n;
  if (hi < lo) hi = lo;
  *k0 = (int)lo;
  *k1 = (int)hi;
}

/* row_span for a short row (n <= SHORT_ROW), by testing sample after
** sample: the same run, without the divisions. */
enum { SHORT_ROW = 8 };

static inline void short_row_span(const int64_t e[3], const int64_t step[3], int n, int *k0, int *k1) {
  int64_t e0 = e[0], e1 = e[1], e2 = e[2];
  int k = 0;
  for (; k < n && (e0 | e1 | e2) < 0; k++) e0 += step[0], e1 += step[1], e2 += step[2];   /* outside */
  *k0 = k;
  for (; k < n && (e0 | e1 | e2) >= 0; k++) e0 += step[0], e1 += step[1], e2 += step[2];   /* inside */
  *k1 = k;
}

void rast_triangle(const RastTri *t, const RastTarget *rt) {
  /* the triangle's pixel box, cut to the target's rectangle */
  int x0 = t->x0 > rt->x0 ? t->x0 : rt->x0, x1 = t->x1 < rt->x1 ? t->x1 : rt->x1;
  int y0 = t->y0 > rt->y0 ? t->y0 : rt->y0, y1 = t->y1 < rt->y1 ? t->y1 : rt->y1;
  if (x0 >= x1 || y0 >= y1) return;
  /* edge functions at the centre of the box's first sample; a step of one
  ** pixel adds a * SUB (along x) or b * SUB (along y): integers, exact */
  int64_t cx = (int64_t)x0 * SUB + SUB / 2, cy = (int64_t)y0 * SUB + SUB / 2;
  int64_t row0 = t->a[0] * cx + t->b[0] * cy + t->c[0];
  int64_t row1 = t->a[1] * cx + t->b[1] * cy + t->c[1];
  int64_t row2 = t->a[2] * cx + t->b[2] * cy + t->c[2];
  int64_t step_x0 = (int64_t)t->a[0] * SUB, step_x1 = (int64_t)t->a[1] * SUB, step_x2 = (int64_t)t->a[2] * SUB;
  /* the attribute planes in locals: the plane stores below could alias t */
  const float z0 = t->z[0], z1 = t->z[1], z2 = t->z[2];
  const float iw0 = t->iw[0], iw1 = t->iw[1], iw2 = t->iw[2];
  const float u0 = t->b1w[0], u1 = t->b1w[1], u2 = t->b1w[2];
  const float v0 = t->b2w[0], v1 = t->b2w[1], v2 = t->b2w[2];
  const float ox = t->ox;
  const int32_t object = t->object, face = t->face;
  /* the target's planes in locals too: a store to one could alias rt */
  float *restrict depth = rt->depth;
  int32_t *restrict objects = rt->object, *restrict faces = rt->face;
  float(*restrict bary)[2] = rt->bary;
  uint16_t *restrict count = rt->count;
  const int64_t step[3] = {step_x0, step_x1, step_x2};
  for (int y = y0; y < y1; y++) {
    const int64_t e[3] = {row0, row1, row2};
    float fy = (float)y + 0.5f - t->oy;             /* sample y relative to the plane origin */
    int n = x1 - x0, x, xe;
    if (n <= SHORT_ROW) short_row_span(e, step, n, &x, &xe);   /* the samples inside all three edges */
    else row_span(e, step, n, &x, &xe);
    x += x0, xe += x0;
    int idx = (y - rt->oy) * rt->stride + (x - rt->ox);
    for (; x < xe; x++, idx++) {
      float fx = (float)x + 0.5f - ox;
      float z = z0 + z1 * fx + z2 * fy;             /* depth is affine in screen space */
      if (count) count[idx]++;
      if (z < depth[idx]) {                         /* nearer than what is there: keep it */
        /* b/w and 1/w are affine in screen space; their ratio is the
        ** perspective-correct barycentric */
        float iw = iw0 + iw1 * fx + iw2 * fy;
        float b1w = u0 + u1 * fx + u2 * fy;
        float b2w = v0 + v1 * fx + v2 * fy;
        float inv = 1.0f / iw;
        depth[idx] = z;
        objects[idx] = object;
        faces[idx] = face;
        bary[idx][0] = b1w * inv;
        bary[idx][1] = b2w * inv;
      }
    }
    row0 += (int64_t)t->b[0] * SUB;                 /* one pixel down */
    row1 += (int64_t)t->b[1] * SUB;
    row2 += (int64_t)t->b[2] * SUB;
  }
}
