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
/* The smallest tolerance tess_adaptive honours, pixels (or units). */
#define TESS_MIN_TOLERANCE 0.01
/* Vertices closer than this times the control net's size are welded. */
#define TESS_WELD_REL 1e-9

/* ---- growing output ---------------------------------------------------- */

typedef struct TessBuf {
  int nv, capv;
  Vec3 *pos, *nrm;
  Vec2 *uv;
  int nt, capt;
  int (*tri)[3];
  int *face;
} TessBuf;

static int buf_vertex(TessBuf *b, Vec3 p, Vec3 n, double u, double v) {
  if (b->nv == b->capv) {
    int cap = b->capv;
    b->pos = xgrow(b->pos, &cap, b->nv + 1, sizeof *b->pos);
    cap = b->capv;
    b->nrm = xgrow(b->nrm, &cap, b->nv + 1, sizeof *b->nrm);
    b->uv = xgrow(b->uv, &b->capv, b->nv + 1, sizeof *b->uv);
  }
  b->pos[b->nv] = p;
  b->nrm[b->nv] = n;
  b->uv[b->nv].x = u;
  b->uv[b->nv].y = v;
  return b->nv++;
}

static void buf_tri(TessBuf *b, int a, int c1, int c2, int face) {
  if (b->nt == b->capt) {
    int cap = b->capt;
    b->tri = xgrow(b->tri, &cap, b->nt + 1, sizeof *b->tri);
    b->face = xgrow(b->face, &b->capt, b->nt + 1, sizeof *b->face);
  }
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

static int clamp_segments(double n) {
  if (!(n < TESS_MAX_SEGMENTS)) return TESS_MAX_SEGMENTS;   /* also NaN */
  return n < 1 ? 1 : (int)n;
}

/* Segments so the polyline of a cubic with projected control points q
** stays within tol of it: the chord error of a curve is at most
** h^2 max|C''| / 8 and |C''| <= 6 max|second difference|. */
static int curve_segments(const Measure *ms, const Vec3 q[4]) {
  double d = 0;
  for (int i = 0; i < 2; i++) {
    double l = v3_len(v3_add(v3_sub(q[i], v3_mul(q[i + 1], 2)), q[i + 2]));
    if (l > d) d = l;
  }
  return clamp_segments(ceil(sqrt(0.75 * d / ms->tol)));
}

/* Border k's count, from its own control points only, canonically ordered
** so both sides compute the same number. */
static int border_segments(const Measure *ms, const ScenePatch *p, int k) {
  Vec3 c[4], q[4];
  border_points(p, k, c);
  canonical_border(c);
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

typedef struct PatchWork {
  TessBuf *b;
  const ScenePatch *p;
  int face;
  int *border[4];     /* vertex indices along each border, patch direction */
  int *grid;          /* (nu + 1) x (nv + 1), only where used */
} PatchWork;

static int patch_vertex(PatchWork *w, Vec3 pos, double u, double v) {
  return buf_vertex(w->b, pos, patch_normal(w->p, u, v), u, v);
}

/* The e + 1 vertices of border k, corners included, the inner points from
** the canonical curve so a neighbour makes the same ones. */
static void make_border(PatchWork *w, int k, int e, const int corner[4]) {
  static const int first[4] = {0, 1, 3, 0}, last[4] = {1, 2, 2, 3};  /* corners 00 10 11 01 */
  Vec3 c[4];
  border_points(w->p, k, c);
  int rev = canonical_border(c);
  int *idx = xmalloc((size_t)(e + 1) * sizeof *idx);
  idx[0] = corner[first[k]];
  idx[e] = corner[last[k]];
  for (int s = 1; s < e; s++) {
    double t = (double)s / e;            /* patch direction */
    Vec3 pos = cubic_point(c, rev ? (double)(e - s) / e : t);
    double u = k == 1 ? 1 : k == 3 ? 0 : t, v = k == 0 ? 0 : k == 2 ? 1 : t;
    idx[s] = patch_vertex(w, pos, u, v);
  }
  w->border[k] = idx;
}

/* Grid vertex (i, j) of an nu x nv grid: the border's where it lies on one
** (only when that border's count matches), else evaluated. */
static int grid_index(const PatchCut *c, int i, int j) { return j * (c->nu + 1) + i; }

static void make_grid(PatchWork *w, const PatchCut *c, int full) {
  int lo = full ? 0 : 1, hiu = full ? c->nu : c->nu - 1, hiv = full ? c->nv : c->nv - 1;
  w->grid = xmalloc((size_t)(c->nu + 1) * (size_t)(c->nv + 1) * sizeof *w->grid);
  for (int j = lo; j <= hiv; j++)
    for (int i = lo; i <= hiu; i++) {
      int *g = &w->grid[grid_index(c, i, j)];
      if (j == 0) *g = w->border[0][i];
      else if (j == c->nv) *g = w->border[2][i];
      else if (i == 0) *g = w->border[3][j];
      else if (i == c->nu) *g = w->border[1][j];
      else {
        double u = (double)i / c->nu, v = (double)j / c->nv;
        *g = patch_vertex(w, patch_eval(w->p, u, v, NULL, NULL), u, v);
      }
    }
}

/* Two triangles per cell over cells [i0, i1) x [j0, j1), counter-clockwise
** in (u, v). */
static void emit_cells(PatchWork *w, const PatchCut *c, int i0, int i1, int j0, int j1) {
  for (int j = j0; j < j1; j++)
    for (int i = i0; i < i1; i++) {
      int a = w->grid[grid_index(c, i, j)], b = w->grid[grid_index(c, i + 1, j)];
      int d = w->grid[grid_index(c, i, j + 1)], e = w->grid[grid_index(c, i + 1, j + 1)];
      buf_tri(w->b, a, b, e, w->face);
      buf_tri(w->b, a, e, d, w->face);
    }
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

/* Cuts patch p (cubic) as c says into b. */
static void cut_patch(TessBuf *b, const ScenePatch *p, int face, PatchCut c) {
  PatchWork w = {b, p, face, {NULL, NULL, NULL, NULL}, NULL};
  int corner[4] = {
    patch_vertex(&w, p->cp[0], 0, 0), patch_vertex(&w, p->cp[3], 1, 0),
    patch_vertex(&w, p->cp[15], 1, 1), patch_vertex(&w, p->cp[12], 0, 1),
  };
  for (int k = 0; k < 4; k++) make_border(&w, k, c.e[k], corner);
  if (c.e[0] == c.nu && c.e[2] == c.nu && c.e[1] == c.nv && c.e[3] == c.nv) {
    make_grid(&w, &c, 1);
    emit_cells(&w, &c, 0, c.nu, 0, c.nv);
  } else {
    if (c.nu < 2) c.nu = 2;
    if (c.nv < 2) c.nv = 2;
    make_grid(&w, &c, 0);
    emit_cells(&w, &c, 1, c.nu - 1, 1, c.nv - 1);
    for (int k = 0; k < 4; k++) stitch_border(&w, &c, k);
  }
  for (int k = 0; k < 4; k++) free(w.border[k]);
  free(w.grid);
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
  Mesh *m = buf_to_mesh(b, 1);
  if (g->npatches > 0) mesh_weld(m, TESS_WELD_REL * control_extent(g));
  mesh_build_edges(m);
  return m;
}

Mesh *tess_uniform(const SceneGeometry *g, int n) {
  TessBuf b = {0};
  if (n < 1) n = 1;
  if (n > TESS_MAX_SEGMENTS) n = TESS_MAX_SEGMENTS;
  PatchCut c = {{n, n, n, n}, n, n};
  for (int i = 0; g->kind == GEOM_PATCHES && i < g->npatches; i++) {
    ScenePatch p = cubic_patch(g, i);
    cut_patch(&b, &p, i, c);
  }
  return finish_patches(g, &b);
}

Mesh *tess_adaptive(const SceneGeometry *g, const Mat4 *object_to_clip, int width, int height,
                    double tolerance_px) {
  TessBuf b = {0};
  Measure ms = {object_to_clip, 0.5 * (width > 0 ? width : 1), 0.5 * (height > 0 ? height : 1),
                tolerance_px > TESS_MIN_TOLERANCE ? tolerance_px : TESS_MIN_TOLERANCE};
  for (int i = 0; g->kind == GEOM_PATCHES && i < g->npatches; i++) {
    ScenePatch p = cubic_patch(g, i);
    PatchCut c;
    for (int k = 0; k < 4; k++) c.e[k] = border_segments(&ms, &p, k);
    inner_segments(&ms, &p, &c.nu, &c.nv);
    /* the inside at least as fine as its borders, so strips stay narrow */
    c.nu = c.nu > c.e[0] ? c.nu : c.e[0];
    c.nu = c.nu > c.e[2] ? c.nu : c.e[2];
    c.nv = c.nv > c.e[1] ? c.nv : c.e[1];
    c.nv = c.nv > c.e[3] ? c.nv : c.e[3];
    cut_patch(&b, &p, i, c);
  }
  return finish_patches(g, &b);
}
