/*
** Tessellation of patch and polygon geometry into triangle meshes (see
** tessellate.h).
**
** Every patch is cut the same way: its four border curves are sampled by
** counts decided from each border's own four control points, evaluated in a
** canonical direction, so two patches that share a border produce the same
** points bit for bit and the weld joins them (no cracks, no T-junctions).
** Inside, a regular grid of nu x nv cells; where the border counts differ
** from the grid's, the outermost ring of cells is replaced by four strips
** that zip each border polyline to the first inner grid line.
*/
#include "tessellate.h"

#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"
#include "patch.h"

/* Segments for a border that has a control point at or behind the eye
** (its projection is meaningless); the rasterizer clips these anyway. */
#define TESS_BEHIND_SEGMENTS 16
/* The tolerance used when the one given is not positive: pixels, or a
** fraction of the control net's size in object units. (Small ones are
** safe: TESS_MAX_SEGMENTS bounds the work.) */
#define TESS_DEFAULT_PX 0.5
#define TESS_DEFAULT_REL 1e-3
/* Polygon faces meeting at more than this (degrees) shade flat on either
** side of their edge (a cube's faces); below it they shade smooth. */
#define TESS_SMOOTH_ANGLE 45.0
/* Vertices closer than this times the control net's size are welded. */
#define TESS_WELD_REL 1e-9

/* ---- growing output ---------------------------------------------------- */

typedef struct TessBuf {
  int nv, capv;
  Vec3 *pos, *nrm;
  Vec2 *uv;
  unsigned char *border;   /* 1 on a patch border: only these are welded */
  int nt, capt;
  int (*tri)[3];
  int *face;
} TessBuf;

/* Sizes the buffers for nv vertices and nt triangles in one go when the
** counts are known: growing by doubling copies the arrays again and again
** and faults in fresh pages for every copy. They will be filled whole, so
** their pages are faulted in at once. Counts too large are left to the
** growing (and its limit). */
static void buf_reserve(TessBuf *b, long long nv, long long nt) {
  if (nv > b->capv && nv <= (1 << 29)) {
    b->capv = (int)nv;
    b->pos = xrealloc(b->pos, (size_t)nv * sizeof *b->pos);
    b->nrm = xrealloc(b->nrm, (size_t)nv * sizeof *b->nrm);
    b->uv = xrealloc(b->uv, (size_t)nv * sizeof *b->uv);
    b->border = xrealloc(b->border, (size_t)nv);
    mem_populate(b->pos, (size_t)nv * sizeof *b->pos);
    mem_populate(b->nrm, (size_t)nv * sizeof *b->nrm);
    mem_populate(b->uv, (size_t)nv * sizeof *b->uv);
  }
  if (nt > b->capt && nt <= (1 << 29)) {
    b->capt = (int)nt;
    b->tri = xrealloc(b->tri, (size_t)nt * sizeof *b->tri);
    b->face = xrealloc(b->face, (size_t)nt * sizeof *b->face);
    mem_populate(b->tri, (size_t)nt * sizeof *b->tri);
    mem_populate(b->face, (size_t)nt * sizeof *b->face);
  }
}

/* Room for need_v vertices and need_t triangles in all: the slow path of
** buf_vertex and buf_tri, kept apart so theirs stays small and inline. */
static void buf_grow(TessBuf *b, int need_v, int need_t) {
  if (need_v > b->capv) {
    int cap = b->capv;
    b->pos = xgrow(b->pos, &cap, need_v, sizeof *b->pos);
    b->nrm = xrealloc(b->nrm, (size_t)cap * sizeof *b->nrm);
    b->uv = xrealloc(b->uv, (size_t)cap * sizeof *b->uv);
    b->border = xrealloc(b->border, (size_t)cap);
    b->capv = cap;
  }
  if (need_t > b->capt) {
    int cap = b->capt;
    b->tri = xgrow(b->tri, &cap, need_t, sizeof *b->tri);
    b->face = xrealloc(b->face, (size_t)cap * sizeof *b->face);
    b->capt = cap;
  }
}

static int buf_vertex(TessBuf *b, Vec3 p, Vec3 n, double u, double v, int border) {
  if (b->nv == b->capv) buf_grow(b, b->nv + 1, 0);
  b->pos[b->nv] = p;
  b->nrm[b->nv] = n;
  b->uv[b->nv].x = u;
  b->uv[b->nv].y = v;
  b->border[b->nv] = (unsigned char)border;
  return b->nv++;
}

static void buf_tri(TessBuf *b, int a, int c1, int c2, int face) {
  if (b->nt == b->capt) buf_grow(b, 0, b->nt + 1);
  b->tri[b->nt][0] = a;
  b->tri[b->nt][1] = c1;
  b->tri[b->nt][2] = c2;
  b->face[b->nt] = face;
  b->nt++;
}

/* Moves the buffers into a new Mesh (uv kept when with_uv). */
static Mesh *buf_to_mesh(TessBuf *b, int with_uv) {
  Mesh *m = xcalloc(1, sizeof *m);
  m->nverts = b->nv;
  m->pos = b->pos ? b->pos : xmalloc(sizeof *m->pos);
  m->nrm = b->nrm ? b->nrm : xmalloc(sizeof *m->nrm);
  if (with_uv) m->uv = b->uv ? b->uv : xmalloc(sizeof *m->uv);
  else free(b->uv);
  m->ntris = b->nt;
  m->tri = b->tri ? b->tri : xmalloc(sizeof *m->tri);
  m->tri_face = b->face ? b->face : xmalloc(sizeof *m->tri_face);
  free(b->border);
  memset(b, 0, sizeof *b);
  return m;
}

/* ---- border curves ----------------------------------------------------- */

/* The control points of border k of cubic patch p, in the patch's own
** parameter direction: 0 is v = 0 and 2 is v = 1 (along u); 1 is u = 1 and
** 3 is u = 0 (along v). */
static void border_points(const ScenePatch *p, int k, Vec3 out[4]) {
  for (int i = 0; i < 4; i++) {
    switch (k) {
      case 0: out[i] = p->cp[i]; break;
      case 1: out[i] = p->cp[4 * i + 3]; break;
      case 2: out[i] = p->cp[12 + i]; break;
      default: out[i] = p->cp[4 * i]; break;
    }
  }
}

/* -1, 0 or 1 as a sorts before, equal to or after b (x, then y, then z). */
static int vec_order(Vec3 a, Vec3 b) {
  if (a.x != b.x) return a.x < b.x ? -1 : 1;
  if (a.y != b.y) return a.y < b.y ? -1 : 1;
  if (a.z != b.z) return a.z < b.z ? -1 : 1;
  return 0;
}

/* Puts the border's control points into the canonical direction (the
** smaller end first; for a closed border the smaller inner point first) and
** returns 1 when that reversed them. Both patches of a shared border agree
** on it. */
static int canonical_border(Vec3 c[4]) {
  int o = vec_order(c[0], c[3]);
  if (o == 0) o = vec_order(c[1], c[2]);
  if (o <= 0) return 0;
  Vec3 t = c[0]; c[0] = c[3]; c[3] = t;
  t = c[1]; c[1] = c[2]; c[2] = t;
  return 1;
}

static Vec3 cubic_point(const Vec3 c[4], double t) {
  double s = 1.0 - t;
  double b0 = s * s * s, b1 = 3 * t * s * s, b2 = 3 * t * t * s, b3 = t * t * t;
  return v3(b0 * c[0].x + b1 * c[1].x + b2 * c[2].x + b3 * c[3].x,
            b0 * c[0].y + b1 * c[1].y + b2 * c[2].y + b3 * c[3].y,
            b0 * c[0].z + b1 * c[1].z + b2 * c[2].z + b3 * c[3].z);
}

/* ---- segment counts ---------------------------------------------------- */

/* Where counts are measured: pixels through a projection, or object units. */
typedef struct Measure {
  const Mat4 *clip;
  double half_w, half_h;
  double tol;
} Measure;

/* The image position of p (pixels); 0 when p is at or behind the eye. */
static int project(const Measure *ms, Vec3 p, Vec3 *out) {
  if (!ms->clip) { *out = p; return 1; }
  const double (*m)[4] = ms->clip->m;
  double w = m[3][0] * p.x + m[3][1] * p.y + m[3][2] * p.z + m[3][3];
  if (!(w > 1e-12)) return 0;
  double x = m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3];
  double y = m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3];
  *out = v3(x / w * ms->half_w, y / w * ms->half_h, 0);
  return 1;
}

/* Whether points c[0..n-1] all lie beyond one side of the view (left,
** right, bottom, top, or behind the eye): then so does every surface they
** control (convex hull), and one segment is enough. */
static int outside_view(const Measure *ms, const Vec3 *c, int n) {
  if (!ms->clip) return 0;
  const double (*m)[4] = ms->clip->m;
  int out[5] = {1, 1, 1, 1, 1};
  for (int i = 0; i < n; i++) {
    Vec3 p = c[i];
    double x = m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3];
    double y = m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3];
    double w = m[3][0] * p.x + m[3][1] * p.y + m[3][2] * p.z + m[3][3];
    out[0] &= x < -w; out[1] &= x > w; out[2] &= y < -w; out[3] &= y > w; out[4] &= w <= 0;
  }
  return out[0] || out[1] || out[2] || out[3] || out[4];
}

static int clamp_segments(double n) {
  if (!(n < TESS_MAX_SEGMENTS)) return TESS_MAX_SEGMENTS;   /* also NaN */
  return n < 1 ? 1 : (int)n;
}

/* Segments for a border with projected control points q. Its chord
** error alone would need n^2 = 6 D / (8 tol) (the error is at most
** h^2 max|C''| / 8, |C''| <= 6 D, D the largest second difference); the
** strip triangles along it also span the inside, so it takes the inner
** grid's rule without the twist term, n^2 = 6 D / (2 tol): where a patch
** has no twist its borders then match its grid and it is cut as one. */
static int curve_segments(const Measure *ms, const Vec3 q[4]) {
  double d = 0;
  for (int i = 0; i < 2; i++) {
    double l = v3_len(v3_add(v3_sub(q[i], v3_mul(q[i + 1], 2)), q[i + 2]));
    if (l > d) d = l;
  }
  return clamp_segments(ceil(sqrt(3 * d / ms->tol)));
}

/* Border k's count, from its own control points only, canonically ordered
** so both sides compute the same number. */
static int border_segments(const Measure *ms, const ScenePatch *p, int k) {
  Vec3 c[4], q[4];
  border_points(p, k, c);
  canonical_border(c);
  if (outside_view(ms, c, 4)) return 1;
  for (int i = 0; i < 4; i++)
    if (!project(ms, c[i], &q[i])) return TESS_BEHIND_SEGMENTS;
  return curve_segments(ms, q);
}

/* Grid counts for the inside: the error of a triangulated grid is at most
** (6 Du hu^2 + 18 Duv hu hv + 6 Dv hv^2) / 8 (D: largest second and mixed
** differences of the net); n^2 = (6 D + 9 Duv) / (2 tol) a direction keeps
** it under tol. */
static void inner_segments(const Measure *ms, const ScenePatch *p, int *nu, int *nv) {
  Vec3 q[16];
  if (outside_view(ms, p->cp, 16)) { *nu = *nv = 1; return; }
  for (int k = 0; k < 16; k++)
    if (!project(ms, p->cp[k], &q[k])) { *nu = *nv = TESS_BEHIND_SEGMENTS; return; }
  double du = 0, dv = 0, duv = 0;
  for (int a = 0; a < 4; a++)
    for (int b = 0; b < 2; b++) {
      double lu = v3_len(v3_add(v3_sub(q[4 * a + b], v3_mul(q[4 * a + b + 1], 2)), q[4 * a + b + 2]));
      double lv = v3_len(v3_add(v3_sub(q[4 * b + a], v3_mul(q[4 * (b + 1) + a], 2)), q[4 * (b + 2) + a]));
      if (lu > du) du = lu;
      if (lv > dv) dv = lv;
    }
  for (int j = 0; j < 3; j++)
    for (int i = 0; i < 3; i++) {
      Vec3 t = v3_sub(v3_add(q[4 * j + i], q[4 * (j + 1) + i + 1]),
                      v3_add(q[4 * j + i + 1], q[4 * (j + 1) + i]));
      if (v3_len(t) > duv) duv = v3_len(t);
    }
  *nu = clamp_segments(ceil(sqrt((6 * du + 9 * duv) / (2 * ms->tol))));
  *nv = clamp_segments(ceil(sqrt((6 * dv + 9 * duv) / (2 * ms->tol))));
}

/* ---- one patch ----------------------------------------------------------- */

/* What one patch is cut into: border counts e[k] (see border_points) and
** the inner grid's nu x nv. */
typedef struct PatchCut {
  int e[4];
  int nu, nv;
} PatchCut;

/* A patch being cut. Its columns' rows and its grid lines' weights are
** evaluated once (patch.h): the inner points and the border normals at the
** grid's parameters share them. */
typedef struct PatchWork {
  TessBuf *b;
  const ScenePatch *p;
  int face;
  int *border[4];     /* vertex indices along each border, patch direction */
  int *grid;          /* (nu + 1) x (nv + 1), only where used */
  PatchRows *rows;    /* at u = i / nu, i = 0..nu */
  PatchWeights *wts;  /* at v = j / nv, j = 0..nv */
} PatchWork;

/* A vertex on the border at (u, v), its position pos from the curve and its
** normal from rows at u and weights at v. */
static int border_vertex(PatchWork *w, Vec3 pos, const PatchRows *rows, const PatchWeights *wts,
                         double u, double v) {
  Vec3 n;
  patch_eval_normal_rows(w->p, rows, wts, u, v, &n);
  return buf_vertex(w->b, pos, n, u, v, 1);
}

/* The e + 1 vertices of border k, corners included, the inner points from
** the canonical curve so a neighbour makes the same ones. Where e is the
** grid's count along the border, its points sit on the grid's lines and
** take their rows or weights; elsewhere they are evaluated here. */
static void make_border(PatchWork *w, const PatchCut *c, int k, const int corner[4]) {
  static const int first[4] = {0, 1, 3, 0}, last[4] = {1, 2, 2, 3};  /* corners 00 10 11 01 */
  int e = c->e[k], along_u = k == 0 || k == 2;
  int on_grid = e == (along_u ? c->nu : c->nv);
  /* what the border's points share: the rows at u = 0 or 1, or the
  ** weights at v = 0 or 1 */
  const PatchRows *side_rows = &w->rows[k == 1 ? c->nu : 0];
  const PatchWeights *side_wts = &w->wts[k == 2 ? c->nv : 0];
  Vec3 cp[4];
  border_points(w->p, k, cp);
  int rev = canonical_border(cp);
  int *idx = xmalloc((size_t)(e + 1) * sizeof *idx);
  idx[0] = corner[first[k]];
  idx[e] = corner[last[k]];
  for (int s = 1; s < e; s++) {
    double t = (double)s / e;            /* patch direction */
    Vec3 pos = cubic_point(cp, rev ? (double)(e - s) / e : t);
    if (along_u) {
      PatchRows own;
      if (!on_grid) patch_rows(w->p, t, &own);
      idx[s] = border_vertex(w, pos, on_grid ? &w->rows[s] : &own, side_wts, t, k == 0 ? 0 : 1);
    } else {
      PatchWeights own;
      if (!on_grid) patch_weights(w->p, t, &own);
      idx[s] = border_vertex(w, pos, side_rows, on_grid ? &w->wts[s] : &own, k == 1 ? 1 : 0, t);
    }
  }
  w->border[k] = idx;
}

/* Where grid vertex (i, j) of an nu x nv grid is kept in PatchWork.grid. */
static int grid_index(const PatchCut *c, int i, int j) { return j * (c->nu + 1) + i; }

/* The grid's vertices: the inner ones, (1..nu-1) x (1..nv-1), evaluated
** row by row, and when full (the borders' counts match the grid) the outer
** ring too, which is the borders' vertices. */
static void make_grid(PatchWork *w, const PatchCut *c, int full) {
  int nu = c->nu, nv = c->nv;
  w->grid = xmalloc((size_t)(nu + 1) * (size_t)(nv + 1) * sizeof *w->grid);
  for (int j = 1; j < nv; j++) {
    double v = (double)j / nv;
    int *g = &w->grid[grid_index(c, 0, j)];
    for (int i = 1; i < nu; i++) {
      double u = (double)i / nu;
      Vec3 n, pos = patch_eval_normal_rows(w->p, &w->rows[i], &w->wts[j], u, v, &n);
      g[i] = buf_vertex(w->b, pos, n, u, v, 0);
    }
  }
  if (!full) return;
  for (int i = 0; i <= nu; i++) {
    w->grid[grid_index(c, i, 0)] = w->border[0][i];
    w->grid[grid_index(c, i, nv)] = w->border[2][i];
  }
  for (int j = 1; j < nv; j++) {
    w->grid[grid_index(c, 0, j)] = w->border[3][j];
    w->grid[grid_index(c, nu, j)] = w->border[1][j];
  }
}

/* Two triangles per cell over cells [i0, i1) x [j0, j1), counter-clockwise
** in (u, v). */
static void emit_cells(PatchWork *w, const PatchCut *c, int i0, int i1, int j0, int j1) {
  TessBuf *b = w->b;
  buf_grow(b, 0, b->nt + 2 * (i1 - i0) * (j1 - j0));   /* then written straight */
  int (*t)[3] = &b->tri[b->nt], *f = &b->face[b->nt];
  for (int j = j0; j < j1; j++) {
    const int *g0 = &w->grid[grid_index(c, 0, j)], *g1 = &w->grid[grid_index(c, 0, j + 1)];
    for (int i = i0; i < i1; i++) {
      int a = g0[i], e = g1[i + 1];
      t[0][0] = a; t[0][1] = g0[i + 1]; t[0][2] = e;
      t[1][0] = a; t[1][1] = e; t[1][2] = g1[i];
      f[0] = f[1] = w->face;
      t += 2;
      f += 2;
    }
  }
  b->nt = (int)(t - b->tri);
}

/* Zips an outer polyline o (params so, no + 1 points) to an inner one q
** (params sq, nq + 1 points) running the same way, advancing whichever
** side's next point comes first. Triangles are (o, o', q) and (o, q', q):
** counter-clockwise when the inner line lies to the left of the outer
** one's direction; flip reverses them for the other two borders. */
static void zip(PatchWork *w, const int *o, const double *so, int no, const int *q,
                const double *sq, int nq, int flip) {
  int k = 0, i = 0;
  while (k < no || i < nq) {
    int outer = i == nq || (k < no && so[k + 1] <= sq[i + 1]);
    int a = o[k], b = outer ? o[k + 1] : q[i + 1], c = q[i];
    if (flip) buf_tri(w->b, a, c, b, w->face);
    else buf_tri(w->b, a, b, c, w->face);
    if (outer) k++;
    else i++;
  }
}

/* The ring between border k and the inner grid line next to it. */
static void stitch_border(PatchWork *w, const PatchCut *c, int k) {
  int along_u = k == 0 || k == 2;
  int no = c->e[k], nq = (along_u ? c->nu : c->nv) - 2;
  int n = along_u ? c->nu : c->nv;
  double *so = xmalloc((size_t)(no + 1 + nq + 1) * sizeof *so), *sq = so + no + 1;
  int *q = xmalloc((size_t)(nq + 1) * sizeof *q);
  for (int s = 0; s <= no; s++) so[s] = (double)s / no;
  for (int s = 0; s <= nq; s++) {
    int t = s + 1;   /* grid index along the border */
    sq[s] = (double)t / n;
    q[s] = k == 0 ? w->grid[grid_index(c, t, 1)]
         : k == 2 ? w->grid[grid_index(c, t, c->nv - 1)]
         : k == 1 ? w->grid[grid_index(c, c->nu - 1, t)]
                  : w->grid[grid_index(c, 1, t)];
  }
  zip(w, w->border[k], so, no, q, sq, nq, k >= 2);
  free(so);
  free(q);
}

/* Whether the borders' counts match the grid's: then the patch is one
** grid, with no strips. */
static int cut_is_grid(const PatchCut *c) {
  return c->e[0] == c->nu && c->e[2] == c->nu && c->e[1] == c->nv && c->e[3] == c->nv;
}

/* A cut that is not a grid stitches a strip along each border to an inner
** grid, which then needs at least two segments each way. */
static PatchCut cut_with_strips(PatchCut c) {
  if (c.nu < 2) c.nu = 2;
  if (c.nv < 2) c.nv = 2;
  return c;
}

/* Adds the vertices and triangles cut_patch makes for c to *nv and *nt. */
static void cut_size(PatchCut c, long long *nv, long long *nt) {
  long long verts = 4;   /* the corners, then each border's inner points */
  for (int k = 0; k < 4; k++) verts += c.e[k] - 1;
  if (cut_is_grid(&c)) {
    *nv += verts + (long long)(c.nu - 1) * (c.nv - 1);
    *nt += 2LL * c.nu * c.nv;
    return;
  }
  c = cut_with_strips(c);
  *nv += verts + (long long)(c.nu - 1) * (c.nv - 1);
  /* the inner cells, then each strip: one triangle per segment of either side */
  *nt += 2LL * (c.nu - 2) * (c.nv - 2) + c.e[0] + c.e[1] + c.e[2] + c.e[3] + 2LL * (c.nu - 2) +
         2LL * (c.nv - 2);
}

/* Cuts patch p (cubic) as c says into b. */
static void cut_patch(TessBuf *b, const ScenePatch *p, int face, PatchCut c) {
  int full = cut_is_grid(&c);
  if (!full) c = cut_with_strips(c);
  PatchWork w = {b, p, face, {NULL, NULL, NULL, NULL}, NULL, NULL, NULL};
  w.rows = xmalloc((size_t)(c.nu + 1) * sizeof *w.rows);
  w.wts = xmalloc((size_t)(c.nv + 1) * sizeof *w.wts);
  for (int i = 0; i <= c.nu; i++) patch_rows(p, (double)i / c.nu, &w.rows[i]);
  for (int j = 0; j <= c.nv; j++) patch_weights(p, (double)j / c.nv, &w.wts[j]);
  const PatchRows *r0 = &w.rows[0], *r1 = &w.rows[c.nu];
  const PatchWeights *w0 = &w.wts[0], *w1 = &w.wts[c.nv];
  int corner[4];   /* one statement each: made in this order */
  corner[0] = border_vertex(&w, p->cp[0], r0, w0, 0, 0);
  corner[1] = border_vertex(&w, p->cp[3], r1, w0, 1, 0);
  corner[2] = border_vertex(&w, p->cp[15], r1, w1, 1, 1);
  corner[3] = border_vertex(&w, p->cp[12], r0, w1, 0, 1);
  for (int k = 0; k < 4; k++) make_border(&w, &c, k, corner);
  make_grid(&w, &c, full);
  if (full) {
    emit_cells(&w, &c, 0, c.nu, 0, c.nv);
  } else {
    emit_cells(&w, &c, 1, c.nu - 1, 1, c.nv - 1);
    for (int k = 0; k < 4; k++) stitch_border(&w, &c, k);
  }
  for (int k = 0; k < 4; k++) free(w.border[k]);
  free(w.grid);
  free(w.rows);
  free(w.wts);
}

/* ---- whole geometries ---------------------------------------------------- */

/* Patch i of g as a cubic patch (bilinear ones elevated exactly). */
static ScenePatch cubic_patch(const SceneGeometry *g, int i) {
  ScenePatch p;
  if (g->patches[i].bilinear) patch_elevate_bilinear(&g->patches[i], &p);
  else p = g->patches[i];
  return p;
}

/* The largest extent of g's control points (at least 1e-300). */
static double control_extent(const SceneGeometry *g) {
  Vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
  for (int i = 0; i < g->npatches; i++)
    for (int k = 0; k < (g->patches[i].bilinear ? 4 : 16); k++) {
      Vec3 c = g->patches[i].cp[k];
      lo = v3(fmin(lo.x, c.x), fmin(lo.y, c.y), fmin(lo.z, c.z));
      hi = v3(fmax(hi.x, c.x), fmax(hi.y, c.y), fmax(hi.z, c.z));
    }
  double e = fmax(hi.x - lo.x, fmax(hi.y - lo.y, hi.z - lo.z));
  return e > 1e-300 ? e : 1e-300;
}

/* Welds shared borders and builds topology. */
static Mesh *finish_patches(const SceneGeometry *g, TessBuf *b) {
  unsigned char *border = b->border;
  b->border = NULL;
  Mesh *m = buf_to_mesh(b, 1);
  /* each corner keeps its own patch's normal where a weld joins patches
  ** that meet at an angle (corner_nrm stays NULL if none do) */
  mesh_weld_creased(m, TESS_WELD_REL * control_extent(g), border);
  free(border);
  mesh_build_edges(m);
  return m;
}

Mesh *tess_uniform(const SceneGeometry *g, int n) {
  TessBuf b = {0};
  if (g->kind == GEOM_MESH) return tess_polygons(g);
  if (n < 1) n = 1;
  if (n > TESS_MAX_SEGMENTS) n = TESS_MAX_SEGMENTS;
  PatchCut c = {{n, n, n, n}, n, n};
  long long nv = 0, nt = 0;
  cut_size(c, &nv, &nt);
  if (g->kind == GEOM_PATCHES) buf_reserve(&b, nv * g->npatches, nt * g->npatches);
  for (int i = 0; g->kind == GEOM_PATCHES && i < g->npatches; i++) {
    ScenePatch p = cubic_patch(g, i);
    cut_patch(&b, &p, i, c);
  }
  return finish_patches(g, &b);
}

/* How patch p is cut for the measure ms. */
static PatchCut adaptive_cut(const Measure *ms, const ScenePatch *p) {
  PatchCut c;
  for (int k = 0; k < 4; k++) c.e[k] = border_segments(ms, p, k);
  inner_segments(ms, p, &c.nu, &c.nv);
  /* the inside at least as fine as its borders, so strips stay narrow */
  c.nu = c.nu > c.e[0] ? c.nu : c.e[0];
  c.nu = c.nu > c.e[2] ? c.nu : c.e[2];
  c.nv = c.nv > c.e[1] ? c.nv : c.e[1];
  c.nv = c.nv > c.e[3] ? c.nv : c.e[3];
  return c;
}

Mesh *tess_adaptive(const SceneGeometry *g, const Mat4 *object_to_clip, int width, int height,
                    double tolerance_px) {
  TessBuf b = {0};
  if (g->kind == GEOM_MESH) return tess_polygons(g);
  Measure ms = {object_to_clip, 0.5 * (width > 0 ? width : 1), 0.5 * (height > 0 ? height : 1),
                tolerance_px};
  if (!(ms.tol > 0)) ms.tol = object_to_clip ? TESS_DEFAULT_PX : TESS_DEFAULT_REL * control_extent(g);
  int np = g->kind == GEOM_PATCHES ? g->npatches : 0;
  PatchCut *cut = xmalloc((size_t)(np > 0 ? np : 1) * sizeof *cut);
  long long nv = 0, nt = 0;
  for (int i = 0; i < np; i++) {   /* every count first, to size the buffers once */
    ScenePatch p = cubic_patch(g, i);
    cut[i] = adaptive_cut(&ms, &p);
    cut_size(cut[i], &nv, &nt);
  }
  buf_reserve(&b, nv, nt);
  for (int i = 0; i < np; i++) {
    ScenePatch p = cubic_patch(g, i);
    cut_patch(&b, &p, i, cut[i]);
  }
  free(cut);
  return finish_patches(g, &b);
}

/* ---- polygons ------------------------------------------------------------ */

/* Newell's normal of polygon idx[0..n-1] (length = twice the area). */
static Vec3 newell_normal(const Vec3 *v, const int *idx, int n) {
  Vec3 r = {0, 0, 0};
  for (int i = 0; i < n; i++) {
    Vec3 a = v[idx[i]], b = v[idx[(i + 1) % n]];
    r.x += (a.y - b.y) * (a.z + b.z);
    r.y += (a.z - b.z) * (a.x + b.x);
    r.z += (a.x - b.x) * (a.y + b.y);
  }
  return r;
}

/* Twice the signed area of 2D triangle abc (> 0: counter-clockwise). */
static double area2(Vec2 a, Vec2 b, Vec2 c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

/* Whether p lies inside or on triangle abc (counter-clockwise). */
static int in_triangle(Vec2 p, Vec2 a, Vec2 b, Vec2 c) {
  return area2(a, b, p) >= 0 && area2(b, c, p) >= 0 && area2(c, a, p) >= 0;
}

/* Whether ring[k] (of the n left, ring of indices into q) is an ear: convex,
** and no other remaining corner inside it. */
static int is_ear(const Vec2 *q, const int *ring, int n, int k) {
  int a = ring[(k + n - 1) % n], b = ring[k], c = ring[(k + 1) % n];
  if (area2(q[a], q[b], q[c]) <= 0) return 0;
  for (int i = 0; i < n; i++) {
    int r = ring[i];
    if (r == a || r == b || r == c) continue;
    if (in_triangle(q[r], q[a], q[b], q[c])) return 0;
  }
  return 1;
}

/* Ear clipping of polygon idx[0..n-1] projected on the plane across normal
** nrm, so it runs counter-clockwise; triangles keep the polygon's winding.
** A polygon with no ear left (self-intersecting) is finished as a fan. */
static void clip_ears(TessBuf *b, const Vec3 *v, const int *idx, int n, Vec3 nrm, int face) {
  Vec3 t1 = fabs(nrm.x) > 0.5 ? v3(0, 1, 0) : v3(1, 0, 0);
  t1 = v3_norm(v3_sub(t1, v3_mul(nrm, v3_dot(t1, nrm))));
  Vec3 t2 = v3_cross(nrm, t1);
  Vec2 *q = xmalloc((size_t)n * sizeof *q);
  int *ring = xmalloc((size_t)n * sizeof *ring);
  for (int i = 0; i < n; i++) {
    q[i].x = v3_dot(v[idx[i]], t1);
    q[i].y = v3_dot(v[idx[i]], t2);
    ring[i] = i;
  }
  int left = n, k = 0, misses = 0;
  while (left > 3 && misses < left) {
    if (is_ear(q, ring, left, k)) {
      buf_tri(b, idx[ring[(k + left - 1) % left]], idx[ring[k]], idx[ring[(k + 1) % left]], face);
      memmove(&ring[k], &ring[k + 1], (size_t)(left - k - 1) * sizeof *ring);
      left--;
      if (k >= left) k = 0;
      misses = 0;
    } else {
      k = (k + 1) % left;
      misses++;
    }
  }
  for (int i = 1; i + 1 < left; i++) buf_tri(b, idx[ring[0]], idx[ring[i]], idx[ring[i + 1]], face);
  free(q);
  free(ring);
}

/* Whether polygon idx is convex seen along nrm (fan-safe). */
static int is_convex(const Vec3 *v, const int *idx, int n, Vec3 nrm) {
  for (int i = 0; i < n; i++) {
    Vec3 a = v[idx[i]], b = v[idx[(i + 1) % n]], c = v[idx[(i + 2) % n]];
    if (v3_dot(v3_cross(v3_sub(b, a), v3_sub(c, b)), nrm) < 0) return 0;
  }
  return 1;
}

/* The valid corners of face f: indices in range, repeats in a row dropped. */
static int face_corners(const SceneGeometry *g, int f, int *out) {
  int n = 0;
  for (int k = g->face_start[f]; k < g->face_start[f + 1]; k++) {
    int i = g->face_index[k];
    if (i < 0 || i >= g->nverts) continue;
    if (n > 0 && out[n - 1] == i) continue;
    out[n++] = i;
  }
  while (n > 1 && out[n - 1] == out[0]) n--;
  return n;
}

/* An imported mesh's own texture coordinates on m's triangles: each
** corner reads its polygon's corner at the same vertex (a UV seam gives a
** vertex two coordinates, so they go per corner); m->uv holds one of each
** vertex's. */
static void polygon_corner_uvs(const SceneGeometry *g, Mesh *m) {
  m->uv = xcalloc((size_t)m->nverts + 1, sizeof *m->uv);
  m->corner_uv = xmalloc(((size_t)m->ntris + 1) * sizeof *m->corner_uv);
  for (int t = 0; t < m->ntris; t++) {
    int f = m->tri_face[t];
    for (int k = 0; k < 3; k++) {
      int v = m->tri[t][k], c = g->face_start[f];
      while (c < g->face_start[f + 1] - 1 && g->face_index[c] != v) c++;
      m->corner_uv[t][k] = m->uv[v] = g->face_uv[c];
    }
  }
}

/* The same for the per-corner normals a CSG result carries (face_nrm). */
static void polygon_corner_normals(const SceneGeometry *g, Mesh *m) {
  m->corner_nrm = xmalloc(((size_t)m->ntris + 1) * sizeof *m->corner_nrm);
  for (int t = 0; t < m->ntris; t++) {
    int f = m->tri_face[t];
    for (int k = 0; k < 3; k++) {
      int v = m->tri[t][k], c = g->face_start[f];
      while (c < g->face_start[f + 1] - 1 && g->face_index[c] != v) c++;
      m->corner_nrm[t][k] = g->face_nrm[c];
    }
  }
}

typedef struct EdgeKey2 { int a, b; } EdgeKey2;

static int cmp_key2(const void *pa, const void *pb) {
  const EdgeKey2 *x = pa, *y = pb;
  return x->a != y->a ? (x->a < y->a ? -1 : 1) : (x->b > y->b) - (x->b < y->b);
}

/* A mesh drawn as it is: its creases (a CSG result's intersection curves)
** tag their edges, so `lines` draws them as creases. */
static void tag_creases(const SceneGeometry *g, Mesh *m) {
  EdgeKey2 *k = xmalloc((size_t)g->ncreases * sizeof *k);
  for (int i = 0; i < g->ncreases; i++) {
    int a = g->creases[i].a, b = g->creases[i].b;
    k[i] = (EdgeKey2){a < b ? a : b, a < b ? b : a};
  }
  qsort(k, (size_t)g->ncreases, sizeof *k, cmp_key2);
  for (int e = 0; e < m->nedges; e++) {
    EdgeKey2 q = {m->edges[e].v[0], m->edges[e].v[1]};
    if (bsearch(&q, k, (size_t)g->ncreases, sizeof *k, cmp_key2)) m->edges[e].sharpness = 10;
  }
  free(k);
}

Mesh *tess_polygons(const SceneGeometry *g) {
  TessBuf b = {0};
  int maxn = 0;
  for (int f = 0; g->kind == GEOM_MESH && f < g->nfaces; f++) {
    int n = g->face_start[f + 1] - g->face_start[f];
    if (n > maxn) maxn = n;
  }
  int *idx = xmalloc((size_t)(maxn > 0 ? maxn : 1) * sizeof *idx);
  for (int f = 0; g->kind == GEOM_MESH && f < g->nfaces; f++) {
    int n = face_corners(g, f, idx);
    if (n < 3) continue;
    Vec3 nrm = v3_norm(newell_normal(g->verts, idx, n));
    if (n == 3 || v3_len(nrm) == 0 || is_convex(g->verts, idx, n, nrm))
      for (int i = 1; i + 1 < n; i++) buf_tri(&b, idx[0], idx[i], idx[i + 1], f);
    else clip_ears(&b, g->verts, idx, n, nrm, f);
  }
  free(idx);
  int nv = g->kind == GEOM_MESH ? g->nverts : 0;
  b.pos = xmalloc((size_t)(nv > 0 ? nv : 1) * sizeof *b.pos);
  b.nrm = xmalloc((size_t)(nv > 0 ? nv : 1) * sizeof *b.nrm);
  if (nv > 0) memcpy(b.pos, g->verts, (size_t)nv * sizeof *b.pos);
  b.nv = nv;
  Mesh *m = buf_to_mesh(&b, 0);
  if (g->kind == GEOM_MESH && g->face_uv) polygon_corner_uvs(g, m);
  mesh_compute_normals(m);
  if (g->kind == GEOM_MESH && g->face_nrm) polygon_corner_normals(g, m);
  else mesh_smooth_corners(m, TESS_SMOOTH_ANGLE);
  if (g->kind == GEOM_MESH && g->face_group)   /* the source faces a CSG result was cut from */
    for (int t = 0; t < m->ntris; t++) m->tri_face[t] = g->face_group[m->tri_face[t]];
  mesh_build_edges(m);
  if (g->kind == GEOM_MESH && g->ncreases > 0 && g->subdiv_level == 0) tag_creases(g, m);
  return m;
}

Mesh *tess_geometry(const SceneGeometry *g, TessKind kind, int n, double tolerance_px,
                    const Mat4 *object_to_clip, int width, int height) {
  if (g->kind == GEOM_MESH) return tess_polygons(g);
  if (kind == TESS_ADAPTIVE) return tess_adaptive(g, object_to_clip, width, height, tolerance_px);
  return tess_uniform(g, n);
}
