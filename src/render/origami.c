/*
** Rendering flat origami (Mitani §5): the face-ID buffer by scanline, and
** the line, illustration and shaded modes over it. See origami.h.
*/
#include "origami.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"
#include "display.h"

/* Sub-pixel bits of the rasterizer's fixed-point coordinates, and the
** largest |coordinate| in pixels kept exact (products stay in int64). */
#define SUBPIX_BITS 8
#define SUBPIX (1 << SUBPIX_BITS)
#define MAX_COORD 1048576.0

/* ---- projection -------------------------------------------------------- */

/* A folded vertex on the screen: pixel position (y down), window depth,
** 1/w, and whether it lies in front of the camera. */
typedef struct ScreenVert { double x, y, depth, invw; int ok; } ScreenVert;

static ScreenVert project(const Mat4 *c, Vec2 p, int width, int height) {
  const double(*m)[4] = c->m;
  double cx = m[0][0] * p.x + m[0][1] * p.y + m[0][3];
  double cy = m[1][0] * p.x + m[1][1] * p.y + m[1][3];
  double cz = m[2][0] * p.x + m[2][1] * p.y + m[2][3];
  double cw = m[3][0] * p.x + m[3][1] * p.y + m[3][3];
  ScreenVert s = {0, 0, 0, 0, cw > 1e-12};
  if (!s.ok) return s;
  s.invw = 1 / cw;
  s.x = (cx * s.invw + 1) * 0.5 * width;                     /* camera.h: pixel x */
  s.y = (1 - cy * s.invw) * 0.5 * height;                    /* y runs down */
  s.depth = (cz * s.invw + 1) * 0.5;
  return s;
}

/* Whether the camera sees the block's -z side: the block's x and y axes
** turn the other way on the screen (whose y runs down). */
static int seen_from_below(const Mat4 *c, Vec2 centre, int width, int height) {
  ScreenVert o = project(c, centre, width, height);
  ScreenVert ex = project(c, (Vec2){centre.x + 1, centre.y}, width, height);
  ScreenVert ey = project(c, (Vec2){centre.x, centre.y + 1}, width, height);
  double area = (ex.x - o.x) * (ey.y - o.y) - (ex.y - o.y) * (ey.x - o.x);
  return area > 0;                                           /* +z toward us gives area < 0 */
}

typedef struct Ctx {
  const OrigamiModel *m;
  int width, height;         /* the planes: a window of the frame */
  int ox, oy, fw, fh;        /* the frame pixel of the planes' first; the frame's size */
  ScreenVert *sv;            /* per vertex */
  int from_below;
  int32_t *fid, *tid;        /* face and triangle at each pixel, -1 empty */
} Ctx;

static void ctx_project(Ctx *c, const Mat4 *object_to_clip) {
  const OrigamiModel *m = c->m;
  c->sv = xmalloc((size_t)(m->nverts ? m->nverts : 1) * sizeof *c->sv);
  if (c->fw <= 0) c->fw = c->width, c->fh = c->height;
  for (int v = 0; v < m->nverts; v++) c->sv[v] = project(object_to_clip, m->folded[v], c->fw, c->fh);
  Vec2 centre = {(m->fold_min.x + m->fold_max.x) / 2, (m->fold_min.y + m->fold_max.y) / 2};
  c->from_below = seen_from_below(object_to_clip, centre, c->fw, c->fh);
}

/* The frame position of the centre of window pixel (x, y). */
#define PX(c, x) ((float)((x) + (c)->ox) + 0.5f)
#define PY(c, y) ((float)((y) + (c)->oy) + 0.5f)

/* Face i lies over face j for this viewer. */
static int over(const Ctx *c, int i, int j) {
  return c->from_below ? origami_is_above(c->m, j, i) : origami_is_above(c->m, i, j);
}

/* ---- the face-ID buffer: scanline with exact fixed-point edges ---------- */

static int64_t fixed(double v) {
  if (v > MAX_COORD) v = MAX_COORD;
  if (v < -MAX_COORD) v = -MAX_COORD;
  return (int64_t)llround(v * SUBPIX);
}

static int64_t floor_div(int64_t a, int64_t b) {             /* b > 0 */
  int64_t q = a / b;
  return (a % b != 0 && a < 0) ? q - 1 : q;
}

/* Scan-convert triangle t of face f: pixel centres inside (top-left rule
** on shared edges, so no pixel is drawn twice by one face). */
static void raster_tri(Ctx *c, int t, int f) {
  const int *vi = c->m->tri[t];
  ScreenVert s0 = c->sv[vi[0]], s1 = c->sv[vi[1]], s2 = c->sv[vi[2]];
  if (!s0.ok || !s1.ok || !s2.ok) return;                    /* behind the camera: not drawn */
  int64_t x[3] = {fixed(s0.x), fixed(s1.x), fixed(s2.x)}, y[3] = {fixed(s0.y), fixed(s1.y), fixed(s2.y)};
  int64_t area = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
  if (area == 0) return;
  if (area < 0) {                                            /* make it positive */
    int64_t tx = x[1], ty = y[1];
    x[1] = x[2], y[1] = y[2], x[2] = tx, y[2] = ty;
  }
  int64_t ymin = y[0], ymax = y[0];
  for (int k = 1; k < 3; k++) ymin = ymin < y[k] ? ymin : y[k], ymax = ymax > y[k] ? ymax : y[k];
  int row0 = (int)floor_div(ymin, SUBPIX), row1 = (int)floor_div(ymax, SUBPIX);
  if (row0 < c->oy) row0 = c->oy;                            /* frame rows, cut to the window */
  if (row1 > c->oy + c->height - 1) row1 = c->oy + c->height - 1;
  for (int row = row0; row <= row1; row++) {
    int64_t py = (int64_t)row * SUBPIX + SUBPIX / 2;
    int64_t lo = c->ox, hi = c->ox + c->width - 1;
    for (int e = 0; e < 3 && lo <= hi; e++) {
      int a = e, b = (e + 1) % 3;
      int64_t dx = x[b] - x[a], dy = y[b] - y[a];
      /* inside: E = dx (py - ya) - dy (px - xa) >= 0, or > 0 off a top-left edge */
      int64_t bias = (dy > 0 || (dy == 0 && dx < 0)) ? 0 : -1;
      int64_t alpha = -dy * SUBPIX;                          /* E per pixel step in x */
      int64_t beta = dx * (py - y[a]) - dy * (SUBPIX / 2 - x[a]) + bias;   /* E at x = 0, biased */
      if (alpha > 0) {                                       /* x >= -beta / alpha */
        int64_t xm = -floor_div(beta, alpha);
        if (xm > lo) lo = xm;
      } else if (alpha < 0) {                                /* x <= beta / -alpha */
        int64_t xm = floor_div(beta, -alpha);
        if (xm < hi) hi = xm;
      } else if (beta < 0) lo = hi + 1;
    }
    int32_t *fr = c->fid + (size_t)(row - c->oy) * c->width, *tr = c->tid + (size_t)(row - c->oy) * c->width;
    for (int64_t px = lo; px <= hi; px++) {
      int64_t i = px - c->ox;                                /* frame column to window column */
      int32_t cur = fr[i];
      if (cur >= 0 && (cur == f || !over(c, f, cur))) continue;   /* §5.1: only over a lower face */
      fr[i] = f;
      tr[i] = t;
    }
  }
}

static void raster_ids(Ctx *c, const int *order) {
  const OrigamiModel *m = c->m;
  size_t n = (size_t)c->width * (size_t)c->height;
  for (size_t p = 0; p < n; p++) c->fid[p] = c->tid[p] = -1;
  int *first = xcalloc((size_t)m->nfaces + 1, sizeof *first);   /* triangles by face */
  for (int t = 0; t < m->ntris; t++) first[m->tri_face[t] + 1]++;
  for (int f = 0; f < m->nfaces; f++) first[f + 1] += first[f];
  for (int k = 0; k < m->nfaces; k++) {
    int f = order ? order[k] : k;
    for (int t = first[f]; t < first[f + 1]; t++) raster_tri(c, t, f);   /* tri_face is sorted */
  }
  free(first);
}

void origami_render_ids(const OrigamiModel *m, const Mat4 *object_to_clip, int width, int height,
                        const int *order, int32_t *ids) {
  Ctx c = {.m = m, .width = width, .height = height, .fid = ids};
  c.tid = xmalloc((size_t)width * (size_t)height * sizeof *c.tid);
  ctx_project(&c, object_to_clip);
  raster_ids(&c, order);
  free(c.tid);
  free(c.sv);
}

/* ---- illustration: brightness at face corners --------------------------- */

double origami_corner_brightness(const OrigamiModel *m, int f, int k, int from_below) {
  int s = m->face_start[f], n = m->face_start[f + 1] - s;
  int ce[2] = {m->face_crease[s + (k + n - 1) % n], m->face_crease[s + k]};   /* edges into and out of k */
  int nm = 0, nv = 0;
  for (int e = 0; e < 2; e++) {
    char a = ce[e] >= 0 ? m->creases[ce[e]].assignment : 0;
    nm += a == 'M', nv += a == 'V';
  }
  if (m->flipped[f] != from_below) {                         /* the back side: M and V swap */
    int tmp = nm;
    nm = nv;
    nv = tmp;
  }
  return (nm - nv + 2) / 4.0;
}

typedef struct Shading {
  int mode;                  /* 0 line, 1 illustration, 2 shaded */
  float color[3];            /* display values */
  double w[3];
  double radius;             /* buffer pixels */
  int lines;                 /* draw Sobel lines */
  float line_color[3];       /* linear */
  float line_opacity;
  double line_width;         /* buffer pixels */
} Shading;

/* Linear -> sRGB display value, in [0, 1]. */
static float display_value(float linear) {
  double v = linear <= 0 ? 0 : linear >= 1 ? 1 : linear;
  return (float)(v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1 / 2.4) - 0.055);
}

static Shading shading_of(const SceneStyle *style, double pixel_scale) {
  Shading s = {1, {1.0f, 1.0f, 0.95f}, {0.675, 0.225, 0.15}, ORIGAMI_DEFAULT_RADIUS, 0,
               {0.0078f, 0.0078f, 0.0078f}, 1, 2};         /* ink #141414, 2 px */
  if (style && style->shade.kind == SHADE_ORIGAMI) {
    const SceneShade *sh = &style->shade;
    s.mode = sh->origami_mode;
    /* The scene holds linear colour; the paper's formula multiplies display
    ** values (its (1, 1, 0.95) is one), so encode to sRGB first. */
    Color c = sh->origami_color;
    if (c.r != 0 || c.g != 0 || c.b != 0)
      s.color[0] = display_value(c.r), s.color[1] = display_value(c.g), s.color[2] = display_value(c.b);
    if (sh->origami_weights[0] != 0 || sh->origami_weights[1] != 0 || sh->origami_weights[2] != 0)
      memcpy(s.w, sh->origami_weights, sizeof s.w);
    if (sh->origami_radius > 0) s.radius = sh->origami_radius;
  }
  if (style && style->lines.present) {
    s.lines = style->lines.kinds != 0;   /* flat: every visible face edge outlines a layer */
    s.line_color[0] = style->lines.color.r, s.line_color[1] = style->lines.color.g;
    s.line_color[2] = style->lines.color.b;
    s.line_opacity = (float)style->lines.opacity;
    if (style->lines.width > 0) s.line_width = style->lines.width;
  }
  if (s.mode == 0) s.lines = 1;
  s.radius *= pixel_scale > 0 ? pixel_scale : 1;
  s.line_width *= pixel_scale > 0 ? pixel_scale : 1;
  if (s.radius > ORIGAMI_MAX_RADIUS) s.radius = ORIGAMI_MAX_RADIUS;
  return s;
}

/* B' at every face corner (bp, indexed like face_index) and triangle
** corner (bt): B' = min(1, wa B + wb R + wc), R from the face's screen
** bounding box (upper-left corner, y down). */
static float (*corner_values(const Ctx *c, const Shading *s, double **corners))[3] {
  const OrigamiModel *m = c->m;
  float (*bt)[3] = xmalloc((size_t)(m->ntris ? m->ntris : 1) * sizeof *bt);
  double *bp = xmalloc((size_t)(m->face_start[m->nfaces] + 1) * sizeof *bp);
  for (int f = 0; f < m->nfaces; f++) {
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (int k = m->face_start[f]; k < m->face_start[f + 1]; k++) {
      ScreenVert v = c->sv[m->face_index[k]];
      x0 = fmin(x0, v.x), y0 = fmin(y0, v.y), x1 = fmax(x1, v.x), y1 = fmax(y1, v.y);
    }
    double diag = hypot(x1 - x0, y1 - y0);
    for (int k = m->face_start[f]; k < m->face_start[f + 1]; k++) {
      ScreenVert v = c->sv[m->face_index[k]];
      double r = diag > 0 ? hypot(v.x - x0, v.y - y0) / diag : 0;
      double b = origami_corner_brightness(m, f, k - m->face_start[f], c->from_below);
      bp[k] = fmin(1.0, s->w[0] * b + s->w[1] * r + s->w[2]);
    }
  }
  for (int t = 0; t < m->ntris; t++) {
    int f = m->tri_face[t];
    for (int i = 0; i < 3; i++) {
      bt[t][i] = 1;
      for (int k = m->face_start[f]; k < m->face_start[f + 1]; k++)
        if (m->face_index[k] == m->tri[t][i]) { bt[t][i] = (float)bp[k]; break; }
    }
  }
  *corners = bp;
  return bt;
}

/* The value at paper point x of face f of m whose corners carry val
** (indexed like face_index), interpolated by mean value coordinates
** (Floater 2003): w_i = (tan(a_(i-1) / 2) + tan(a_i / 2)) / |v_i - x|,
** a_i the angle at x between corners i and i + 1. They depend on the
** polygon alone, not on how it is cut into triangles (a fan's colours
** would depend on the corner it starts at), are the barycentrics on a
** triangle, and are linear along each edge. */
static double mean_value(const OrigamiModel *m, int f, Vec2 x, const double *val) {
  int s = m->face_start[f], n = m->face_start[f + 1] - s;
  double sum = 0, wsum = 0, t_first = 0, t_prev = 0, r_first = 0;
  Vec2 v = m->paper[m->face_index[s]];
  double ax = v.x - x.x, ay = v.y - x.y, ar = hypot(ax, ay);
  for (int i = 0; i < n; i++) {   /* corner i (a) and i + 1 (b): the edge between them */
    if (ar < 1e-12) return val[s + i];   /* on a corner */
    int j = (i + 1) % n;
    Vec2 u = m->paper[m->face_index[s + j]];
    double bx = u.x - x.x, by = u.y - x.y, br = hypot(bx, by);
    double cr = ax * by - ay * bx, d = ax * bx + ay * by;
    if (br >= 1e-12 && fabs(cr) < 1e-12 * ar * br && d < 0)   /* on the edge: along it */
      return (br * val[s + i] + ar * val[s + j]) / (ar + br);
    double t = br < 1e-12 ? 0 : (ar * br - d) / cr;   /* tan(a_i / 2) */
    if (i == 0) { t_first = t; r_first = ar; }
    else {
      double w = (t_prev + t) / ar;
      sum += w * val[s + i];
      wsum += w;
    }
    t_prev = t;
    ax = bx, ay = by, ar = br;
  }
  double w = (t_prev + t_first) / r_first;   /* corner 0 closes the loop */
  sum += w * val[s];
  wsum += w;
  return wsum != 0 ? sum / wsum : val[s];
}

/* ---- shaded: pseudo ambient occlusion ------------------------------------- */

typedef struct FaceBox { int x0, y0, x1, y1; } FaceBox;

/* The box of the pixels each face shows at (x1 < 0: it shows nowhere). */
static FaceBox *visible_boxes(const Ctx *c) {
  int w = c->width, h = c->height;
  FaceBox *box = xmalloc((size_t)(c->m->nfaces ? c->m->nfaces : 1) * sizeof *box);
  for (int f = 0; f < c->m->nfaces; f++) box[f] = (FaceBox){w, h, -1, -1};
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      int f = c->fid[(size_t)y * w + x];
      if (f < 0) continue;
      FaceBox *b = &box[f];
      if (x < b->x0) b->x0 = x;
      if (x > b->x1) b->x1 = x;
      if (y < b->y0) b->y0 = y;
      if (y > b->y1) b->y1 = y;
    }
  return box;
}

/* A summed-area table over box (w x h pixels from (x0, y0)) of "the face
** shown here lies over f": sat[(y + 1) * (w + 1) + x + 1] counts those in
** [x0, x0 + x] x [y0, y0 + y]. Returns the total. */
static int32_t cover_table(const Ctx *c, int f, FaceBox box, int32_t *sat) {
  int bw = box.x1 - box.x0 + 1, bh = box.y1 - box.y0 + 1, sw = bw + 1;
  memset(sat, 0, (size_t)sw * sizeof *sat);
  for (int y = 0; y < bh; y++) {
    const int32_t *row = c->fid + (size_t)(box.y0 + y) * c->width + box.x0;
    int32_t *s = sat + (size_t)(y + 1) * sw, *up = s - sw, acc = 0;
    s[0] = 0;
    for (int x = 0; x < bw; x++) {
      int g = row[x];
      acc += g >= 0 && g != f && over(c, g, f);
      s[x + 1] = up[x + 1] + acc;
    }
  }
  return sat[(size_t)bh * sw + bw];
}

/* The disk of radius r (row half-widths hw[dy + r]) around table point
** (lx, ly): covered pixels, O(r) with one row segment a disk row, after an
** O(1) test of the disk's bounding square. */
static long disk_sum(const int32_t *sat, int bw, int bh, int lx, int ly, int r, const int *hw) {
  int sw = bw + 1;
  int qx0 = lx - r < 0 ? 0 : lx - r, qx1 = lx + r >= bw ? bw - 1 : lx + r;
  int qy0 = ly - r < 0 ? 0 : ly - r, qy1 = ly + r >= bh ? bh - 1 : ly + r;
  int32_t sq = sat[(size_t)(qy1 + 1) * sw + qx1 + 1] - sat[(size_t)qy0 * sw + qx1 + 1] -
               sat[(size_t)(qy1 + 1) * sw + qx0] + sat[(size_t)qy0 * sw + qx0];
  if (sq == 0) return 0;                                     /* the square is clear */
  long s = 0;
  for (int yy = qy0; yy <= qy1; yy++) {
    int half = hw[yy - ly + r];
    int a = lx - half < 0 ? 0 : lx - half, e = lx + half >= bw ? bw - 1 : lx + half;
    const int32_t *lo = sat + (size_t)yy * sw, *hi = lo + sw;
    s += (hi[e + 1] - lo[e + 1]) - (hi[a] - lo[a]);
  }
  return s;
}

/* I = 1 - s/S at every pixel of the origami (1 elsewhere), into occ: per
** visible face, a table of "covered by a face above me" over its box grown
** by the radius, then the disk sums at its pixels. */
static void occlusion(const Ctx *c, double radius, float *occ) {
  int w = c->width, h = c->height, r = (int)lround(radius);
  for (size_t p = 0; p < (size_t)w * (size_t)h; p++) occ[p] = 1;
  if (r < 1) return;
  int *hw = xmalloc((size_t)(2 * r + 1) * sizeof *hw);       /* disk half-widths by row */
  long disk = 0;
  for (int dy = -r; dy <= r; dy++) {
    hw[dy + r] = (int)floor(sqrt(radius * radius - (double)dy * dy) + 1e-9);
    disk += 2 * hw[dy + r] + 1;
  }
  FaceBox *box = visible_boxes(c);
  int32_t *sat = NULL;
  size_t satcap = 0;
  for (int f = 0; f < c->m->nfaces; f++) {
    FaceBox b = box[f];
    if (b.x1 < 0) continue;
    FaceBox g = {b.x0 - r < 0 ? 0 : b.x0 - r, b.y0 - r < 0 ? 0 : b.y0 - r,
                 b.x1 + r >= w ? w - 1 : b.x1 + r, b.y1 + r >= h ? h - 1 : b.y1 + r};
    int bw = g.x1 - g.x0 + 1, bh = g.y1 - g.y0 + 1;
    size_t need = (size_t)(bw + 1) * (size_t)(bh + 1);
    if (need > satcap) sat = xrealloc(sat, (satcap = need) * sizeof *sat);
    if (cover_table(c, f, g, sat) == 0) continue;           /* nothing above f nearby */
    for (int y = b.y0; y <= b.y1; y++)
      for (int x = b.x0; x <= b.x1; x++) {
        size_t p = (size_t)y * w + x;
        if (c->fid[p] != f) continue;
        long s = disk_sum(sat, bw, bh, x - g.x0, y - g.y0, r, hw);
        if (s) occ[p] = 1.0f - (float)s / (float)disk;
      }
  }
  free(sat);
  free(box);
  free(hw);
}

/* Per triangle: screen barycentrics l1, l2 = C (p - a), and the corners'
** 1/w and depths, for perspective-correct attributes. */
typedef struct TriSetup { float ax, ay, c[4], invw[3], depth[3]; } TriSetup;

static TriSetup *tri_setup(const Ctx *c) {
  const OrigamiModel *m = c->m;
  TriSetup *ts = xmalloc((size_t)(m->ntris ? m->ntris : 1) * sizeof *ts);
  for (int t = 0; t < m->ntris; t++) {
    ScreenVert a = c->sv[m->tri[t][0]], b = c->sv[m->tri[t][1]], d = c->sv[m->tri[t][2]];
    double den = (b.x - a.x) * (d.y - a.y) - (b.y - a.y) * (d.x - a.x), k = den ? 1 / den : 0;
    TriSetup *s = &ts[t];
    s->ax = (float)a.x, s->ay = (float)a.y;
    s->c[0] = (float)((d.y - a.y) * k), s->c[1] = (float)(-(d.x - a.x) * k);   /* l1 */
    s->c[2] = (float)(-(b.y - a.y) * k), s->c[3] = (float)((b.x - a.x) * k);   /* l2 */
    s->invw[0] = (float)a.invw, s->invw[1] = (float)b.invw, s->invw[2] = (float)d.invw;
    s->depth[0] = (float)a.depth, s->depth[1] = (float)b.depth, s->depth[2] = (float)d.depth;
  }
  return ts;
}

/* Perspective-correct barycentrics of pixel centre (px, py) in triangle s,
** and the screen-linear depth. */
static void tri_bary(const TriSetup *s, float px, float py, float b[3], float *depth) {
  float dx = px - s->ax, dy = py - s->ay;
  float l1 = s->c[0] * dx + s->c[1] * dy, l2 = s->c[2] * dx + s->c[3] * dy, l0 = 1 - l1 - l2;
  *depth = l0 * s->depth[0] + l1 * s->depth[1] + l2 * s->depth[2];
  float w0 = l0 * s->invw[0], w1 = l1 * s->invw[1], w2 = l2 * s->invw[2], sum = w0 + w1 + w2;
  if (sum == 0) sum = 1;
  b[0] = w0 / sum, b[1] = w1 / sum, b[2] = w2 / sum;
}

/* Screen-linear depth of triangle s at pixel centre (px, py). */
static float tri_depth_at(const TriSetup *s, float px, float py) {
  float dx = px - s->ax, dy = py - s->ay;
  float l1 = s->c[0] * dx + s->c[1] * dy, l2 = s->c[2] * dx + s->c[3] * dy;
  return (1 - l1 - l2) * s->depth[0] + l1 * s->depth[1] + l2 * s->depth[2];
}

/* Where a mesh drawn before (depth, or NULL for none) hides the paper:
** shown[p] = 1 where the face-ID buffer has a face whose depth at the
** pixel centre is nearer than the mesh's. */
static unsigned char *shown_pixels(const Ctx *c, const TriSetup *ts, const float *depth) {
  int w = c->width, h = c->height;
  unsigned char *shown = xmalloc((size_t)w * (size_t)h + 1);
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      size_t p = (size_t)y * w + x;
      shown[p] = c->fid[p] >= 0;
      if (shown[p] && depth) shown[p] = tri_depth_at(&ts[c->tid[p]], PX(c, x), PY(c, y)) < depth[p];
    }
  return shown;
}

/* Is the line at pixel p in front of the mesh there? On the paper where
** the paper shows; off it (the outer side of the outline) where paper
** within reach (the line's half-width beyond the Sobel pixel next to the
** paper, reach = grow + 1) is nearer than the mesh at p. */
static int line_shown(const Ctx *c, const TriSetup *ts, const unsigned char *shown, const float *depth,
                      size_t p, int reach) {
  if (c->fid[p] >= 0) return shown[p];
  if (!depth) return 1;
  int w = c->width, h = c->height, x = (int)(p % (size_t)w), y = (int)(p / (size_t)w);
  for (int v = y - reach < 0 ? 0 : y - reach; v <= y + reach && v < h; v++)
    for (int u = x - reach < 0 ? 0 : x - reach; u <= x + reach && u < w; u++) {
      size_t q = (size_t)v * w + u;
      if (c->fid[q] >= 0 && tri_depth_at(&ts[c->tid[q]], PX(c, u), PY(c, v)) < depth[p]) return 1;
    }
  return 0;
}

/* ---- line: Sobel on the face IDs ------------------------------------------ */

/* A face id spread over 20 bits, so that Sobel's weighted sums of
** different ids do not cancel (any id change is an edge). */
static int32_t id_code(int32_t id) { return (int32_t)(((uint32_t)(id + 2) * 2654435761u) >> 12); }

/* The face each face is one piece of paper with: faces joined by flat
** ("F") creases, which fold nothing, share the lowest face number among
** them, so the Sobel lines do not draw those creases as folds. */
static int *flat_pieces(const OrigamiModel *m) {
  int *piece = xmalloc((size_t)(m->nfaces ? m->nfaces : 1) * sizeof *piece);
  int *owner = xmalloc((size_t)(m->ncreases ? m->ncreases : 1) * sizeof *owner);   /* a face on it */
  for (int f = 0; f < m->nfaces; f++) piece[f] = f;
  for (int i = 0; i < m->ncreases; i++) owner[i] = -1;
  for (int f = 0; f < m->nfaces; f++)
    for (int k = m->face_start[f]; k < m->face_start[f + 1]; k++) {
      int cr = m->face_crease[k];
      if (cr < 0 || m->creases[cr].assignment != 'F') continue;
      if (owner[cr] < 0) { owner[cr] = f; continue; }
      int a = owner[cr], b = f;   /* join the two pieces: union by the lower root */
      while (piece[a] != a) a = piece[a];
      while (piece[b] != b) b = piece[b];
      if (a < b) piece[b] = a;
      else piece[a] = b;
    }
  for (int f = 0; f < m->nfaces; f++) {
    int r = f;
    while (piece[r] != r) r = piece[r];
    piece[f] = r;
  }
  free(owner);
  return piece;
}

/* Grow the marked pixels of mask by r in x, then in y (a square of side
** 2r + 1), with running counts: O(1) a pixel. */
static void dilate(unsigned char *mask, int w, int h, int r) {
  unsigned char *tmp = xmalloc((size_t)w * (size_t)h);
  for (int pass = 0; pass < 2; pass++) {
    int len = pass ? h : w, lines = pass ? w : h;
    size_t step = pass ? (size_t)w : 1, next = pass ? 1 : (size_t)w;
    unsigned char *src = pass ? tmp : mask, *dst = pass ? mask : tmp;
    for (int l = 0; l < lines; l++) {
      const unsigned char *in = src + (size_t)l * next;
      unsigned char *out = dst + (size_t)l * next;
      int count = 0;
      for (int i = 0; i < r && i < len; i++) count += in[(size_t)i * step];
      for (int i = 0; i < len; i++) {
        if (i + r < len) count += in[(size_t)(i + r) * step];
        if (i - r - 1 >= 0) count -= in[(size_t)(i - r - 1) * step];
        out[(size_t)i * step] = count > 0;
      }
    }
  }
  free(tmp);
}

/* Draw the Sobel edges of the face-ID buffer (both sides of each change
** of piece, flat_pieces: about 2 pixels; wider lines grow them). The buffer holds every face,
** hidden or not, so a mesh in front of the paper neither adds edges along
** its outline nor lets the creases behind it show: a line pixel is drawn
** only where line_shown says the line is in front. */
static void sobel_lines(const Ctx *c, const Shading *s, const TriSetup *ts, const unsigned char *shown,
                        const float *depth, float *rgba) {
  int w = c->width, h = c->height;
  int32_t *code = xmalloc((size_t)(w + 2) * (size_t)(h + 2) * sizeof *code);   /* clamped border */
  unsigned char *mask = xmalloc((size_t)w * (size_t)h);
  int cw = w + 2;
  int *piece = flat_pieces(c->m);
  for (int y = -1; y <= h; y++) {
    int yy = y < 0 ? 0 : y >= h ? h - 1 : y;
    for (int x = -1; x <= w; x++) {
      int xx = x < 0 ? 0 : x >= w ? w - 1 : x;
      int32_t f = c->fid[(size_t)yy * w + xx];
      code[(size_t)(y + 1) * cw + (x + 1)] = id_code(f >= 0 ? piece[f] : f);
    }
  }
  for (int y = 0; y < h; y++) {
    const int32_t *r0 = code + (size_t)y * cw, *r1 = r0 + cw, *r2 = r1 + cw;
    unsigned char *mr = mask + (size_t)y * w;
    for (int x = 0; x < w; x++) {
      int64_t gx = (int64_t)r0[x + 2] + 2 * (int64_t)r1[x + 2] + r2[x + 2] - r0[x] - 2 * (int64_t)r1[x] - r2[x];
      int64_t gy = (int64_t)r2[x] + 2 * (int64_t)r2[x + 1] + r2[x + 2] - r0[x] - 2 * (int64_t)r0[x + 1] - r0[x + 2];
      mr[x] = gx != 0 || gy != 0;
    }
  }
  int grow = (int)lround((s->line_width - 2) / 2);
  if (grow < 0) grow = 0;
  if (grow > 0) dilate(mask, w, h, grow);
  float a = s->line_opacity;
  for (size_t p = 0; p < (size_t)w * (size_t)h; p++) {
    if (!mask[p] || !line_shown(c, ts, shown, depth, p, grow + 1)) continue;
    float *o = rgba + p * 4;
    for (int ch = 0; ch < 3; ch++) o[ch] = o[ch] * (1 - a) + s->line_color[ch] * a;
    o[3] = o[3] * (1 - a) + a;
  }
  free(piece);
  free(mask);
  free(code);
}

/* ---- shading ------------------------------------------------------------- */

static void sample_texture(const Image *img, double u, double v, float out[3]) {
  double fx = u * img->width - 0.5, fy = (1 - v) * img->height - 0.5;   /* paper +y is up */
  int x0 = (int)floor(fx), y0 = (int)floor(fy);
  double ax = fx - x0, ay = fy - y0;
  int nc = img->channels;
  for (int ch = 0; ch < 3; ch++) {
    double acc = 0;
    for (int j = 0; j < 2; j++)
      for (int i = 0; i < 2; i++) {
        int x = x0 + i < 0 ? 0 : x0 + i >= img->width ? img->width - 1 : x0 + i;
        int y = y0 + j < 0 ? 0 : y0 + j >= img->height ? img->height - 1 : y0 + j;
        const float *px = img->data + ((size_t)y * img->width + x) * nc;
        acc += (i ? ax : 1 - ax) * (j ? ay : 1 - ay) * px[nc >= 3 ? ch : 0];
      }
    out[ch] = (float)acc;
  }
}

/* What colouring a pixel needs, set up once a frame. */
typedef struct Paint {
  const Shading *s;
  float (*bt)[3];            /* B' at triangle corners (illustration, shaded) */
  double *bc;                /* and at face corners, for faces of more than three */
  const float *occ;          /* I per pixel (shaded) */
  TriSetup *ts;
  const Image *texture;
  double px0, py0, pw, ph;   /* the paper's box, for the texture */
  float flat[3];             /* line mode: one linear colour */
} Paint;

static void paint_setup(Paint *pt, const Ctx *c) {
  const OrigamiModel *m = c->m;
  double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  for (int v = 0; v < m->nverts; v++) {
    x0 = fmin(x0, m->paper[v].x), y0 = fmin(y0, m->paper[v].y);
    x1 = fmax(x1, m->paper[v].x), y1 = fmax(y1, m->paper[v].y);
  }
  pt->px0 = x0, pt->py0 = y0;
  pt->pw = x1 > x0 ? x1 - x0 : 1, pt->ph = y1 > y0 ? y1 - y0 : 1;
  pt->ts = tri_setup(c);
  for (int ch = 0; ch < 3; ch++) pt->flat[ch] = display_to_linear(pt->s->color[ch]);
}

/* Colour pixel (x, y), showing face f through triangle tri. */
static void paint_pixel(const Paint *pt, const Ctx *c, int x, int y, OrigamiTarget *t) {
  size_t p = (size_t)y * c->width + x;
  int f = c->fid[p], tri = c->tid[p];
  float *o = t->rgba + p * 4;
  o[3] = 1;
  if (t->face_id) t->face_id[p] = f;
  if (!pt->bt && !pt->texture && !t->depth) {
    o[0] = pt->flat[0], o[1] = pt->flat[1], o[2] = pt->flat[2];
    return;
  }
  float b[3], depth;
  tri_bary(&pt->ts[tri], PX(c, x), PY(c, y), b, &depth);
  if (t->depth) t->depth[p] = depth;
  const float *col = pt->s->color;
  float base[3] = {col[0], col[1], col[2]};                  /* display values */
  if (pt->texture && c->m->flipped[f] == c->from_below) {    /* the front shows: the texture */
    double u = 0, v = 0;
    for (int i = 0; i < 3; i++) {
      Vec2 q = c->m->paper[c->m->tri[tri][i]];
      u += b[i] * (q.x - pt->px0) / pt->pw, v += b[i] * (q.y - pt->py0) / pt->ph;
    }
    float tc[3];
    sample_texture(pt->texture, u, v, tc);
    for (int ch = 0; ch < 3; ch++) base[ch] = display_from_linear(tc[ch]);
  }
  float k = 1;                                               /* display-space brightness */
  const OrigamiModel *m = c->m;
  if (pt->bt && m->face_start[f + 1] - m->face_start[f] > 3) {   /* over the face, not its triangles */
    Vec2 q = {0, 0};
    for (int i = 0; i < 3; i++) {
      Vec2 v = m->paper[m->tri[tri][i]];
      q.x += b[i] * v.x, q.y += b[i] * v.y;
    }
    k = (float)mean_value(m, f, q, pt->bc);
  } else if (pt->bt) {
    k = b[0] * pt->bt[tri][0] + b[1] * pt->bt[tri][1] + b[2] * pt->bt[tri][2];
  }
  if (pt->occ) k *= pt->occ[p];
  for (int ch = 0; ch < 3; ch++) o[ch] = display_to_linear(k * base[ch]);
}

long origami_render(const OrigamiModel *m, const SceneStyle *style, const Mat4 *object_to_clip,
                    const Image *texture, OrigamiTarget *t) {
  int w = t->width, h = t->height;
  size_t n = (size_t)w * (size_t)h;
  Ctx c = {.m = m, .width = w, .height = h, .ox = t->x0, .oy = t->y0, .fw = t->full_width,
           .fh = t->full_height};
  c.fid = xmalloc(n * sizeof *c.fid);
  c.tid = xmalloc(n * sizeof *c.tid);
  ctx_project(&c, object_to_clip);
  raster_ids(&c, NULL);                                      /* §5.1 */
  Shading s = shading_of(style, t->pixel_scale);
  Paint pt = {.s = &s, .texture = texture};
  pt.bt = s.mode > 0 ? corner_values(&c, &s, &pt.bc) : NULL;   /* §5.3 */
  float *occ = NULL;
  if (s.mode == 2) {                                         /* §5.4 */
    occ = xmalloc(n * sizeof *occ);
    occlusion(&c, s.radius, occ);
  }
  pt.occ = occ;
  paint_setup(&pt, &c);
  unsigned char *shown = shown_pixels(&c, pt.ts, t->depth);  /* before the paper writes its depth */
  long covered = 0;
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++)
      if (shown[(size_t)y * w + x]) {
        paint_pixel(&pt, &c, x, y, t);
        covered++;
      }
  if (s.lines) sobel_lines(&c, &s, pt.ts, shown, t->depth, t->rgba);   /* §5.2 */
  free(shown);
  free(pt.ts);
  free(occ);
  free(pt.bt);
  free(pt.bc);
  free(c.sv);
  free(c.tid);
  free(c.fid);
  return covered;
}

void origami_world_bounds(const OrigamiModel *m, const Mat4 *transform, Vec3 *bmin, Vec3 *bmax) {
  *bmin = v3(INFINITY, INFINITY, INFINITY);
  *bmax = v3(-INFINITY, -INFINITY, -INFINITY);
  for (int k = 0; k < 4; k++) {
    Vec3 p = v3(k & 1 ? m->fold_max.x : m->fold_min.x, k & 2 ? m->fold_max.y : m->fold_min.y, 0);
    Vec3 q = m4_point(*transform, p);
    *bmin = v3(fmin(bmin->x, q.x), fmin(bmin->y, q.y), fmin(bmin->z, q.z));
    *bmax = v3(fmax(bmax->x, q.x), fmax(bmax->y, q.y), fmax(bmax->z, q.z));
  }
}

int origami_margin(const Scene *s, double pixel_scale) {
  SceneStyle fallback = scene_default_style();
  int most = 0;
  for (int i = 0; i < s->norigami; i++) {
    const SceneOrigami *o = &s->origami[i];
    Shading sh = shading_of(o->style >= 0 && o->style < s->nstyles ? &s->styles[o->style] : &fallback,
                            pixel_scale);
    /* a pixel's disk sum reads the face ids within the radius; its line, the
    ** Sobel filter's neighbours (1) of the pixels the line grows over, and
    ** the nearest paper beside it (1) */
    int grow = (int)lround((sh.line_width - 2) / 2), r = sh.mode == 2 ? (int)lround(sh.radius) : 0;
    int need = r + (grow > 0 ? grow : 0) + 3;
    if (need > most) most = need;
  }
  return most;
}

int origami_draw_scene(const Scene *s, const Mat4 *world_to_clip, OrigamiTarget *t) {
  int ok = 1;
  SceneStyle fallback = scene_default_style();
  for (int i = 0; i < s->norigami; i++) {
    const SceneOrigami *o = &s->origami[i];
    OrigamiModel *m = origami_build(o, 0);
    if (!m) { ok = 0; continue; }
    const SceneStyle *style = o->style >= 0 && o->style < s->nstyles ? &s->styles[o->style] : &fallback;
    Image *tex = NULL;
    const char *path = style->shade.kind == SHADE_ORIGAMI ? style->shade.origami_texture : NULL;
    if (path) {
      char err[512];
      if (!image_read(path, &tex, err, sizeof err)) {
        diag_error(style->shade.loc.file >= 0 ? style->shade.loc : o->loc,
                   "cannot read the paper texture `%s`: %s", path, err);
        ok = 0;
        tex = NULL;
      }
    }
    Mat4 object_to_clip = m4_mul(*world_to_clip, o->transform);
    origami_render(m, style, &object_to_clip, tex, t);
    image_destroy(tex);
    origami_free(m);
  }
  return ok;
}

int origami_screen_points(const OrigamiModel *m, const Mat4 *object_to_clip, int width, int height,
                          double (*xy)[2]) {
  Ctx c = {.m = m, .width = width, .height = height};
  ctx_project(&c, object_to_clip);
  for (int v = 0; v < m->nverts; v++) xy[v][0] = c.sv[v].x, xy[v][1] = c.sv[v].y;
  free(c.sv);
  return c.from_below;
}

OrigamiLines origami_lines_of(const SceneStyle *style) {
  Shading s = shading_of(style, 1);
  OrigamiLines l = {s.lines, {s.line_color[0], s.line_color[1], s.line_color[2]}, s.line_opacity, s.line_width};
  return l;
}
