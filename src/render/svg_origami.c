/*
** Origami in the SVG writer (svg_origami.h): face polygons in layer order
** with fitted gradients, the blocks' lines as polygon strokes, and traced
** layers for what the gradients miss.
*/
#include "svg_origami.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"
#include "../geom/origami.h"
#include "../io/image.h"
#include "origami.h"

/* A face pixel whose colour is further than this (in codes, any channel)
** from the face's gradient is drawn again by a traced layer over it. */
#define SVG_RESIDUAL 16

typedef struct Block {
  const OrigamiModel *m;
  int w, h;
  int32_t *ids;                /* the face on top at each pixel (meshes ignored), -1 none */
  unsigned char *near_line;    /* pixels the block's lines cover (NULL: no lines) */
  double (*xy)[2];             /* screen position of each vertex */
  int from_below;
  OrigamiLines lines;
  int samples;                 /* the render's samples a pixel side */
} Block;

/* A face's colour as an affine function of the pixel centre, per channel
** (sRGB codes): v = a + gx (x - cx) + gy (y - cy). */
typedef struct Fit { double a[3], gx[3], gy[3], cx, cy; long n; } Fit;

static double fit_at(const Fit *t, int ch, double x, double y) {
  return t->a[ch] + t->gx[ch] * (x - t->cx) + t->gy[ch] * (y - t->cy);
}

/* (NaN, from a face whose fit has no pixels, is 0: casting it is undefined) */
static uint8_t code(double v) { return (uint8_t)(!(v > 0) ? 0 : v > 255 ? 255 : v + 0.5); }

static void hex(char out[8], const uint8_t *c) { snprintf(out, 8, "#%02x%02x%02x", c[0], c[1], c[2]); }

/* ---- the order of the faces ------------------------------------------------- */

/* Face i lies over face j for this viewer (where they overlap). */
static int lies_over(const Block *b, int i, int j) {
  return b->from_below ? origami_is_above(b->m, j, i) : origami_is_above(b->m, i, j);
}

/* Faces back to front: a face after every face it lies over where they
** overlap (Kahn's order, lowest id first). A cycle is broken at its face
** with the fewest faces left under it; a face that comes after one it lies
** under is marked in cyclic, to be clipped to the pixels it shows. */
static void face_order(const Block *b, int *order, unsigned char *cyclic) {
  int npairs, nf = b->m->nfaces;
  OrigamiOverlap *ov = origami_overlaps(b->m, &npairs);
  int *under = xcalloc((size_t)nf + 1, sizeof *under);   /* faces below each face not yet drawn */
  int *start = xcalloc((size_t)nf + 2, sizeof *start), *pairs = xmalloc((size_t)(2 * npairs + 1) * sizeof *pairs);
  for (int k = 0; k < npairs; k++) {
    start[ov[k].i + 1]++, start[ov[k].j + 1]++;
    if (lies_over(b, ov[k].i, ov[k].j)) under[ov[k].i]++;
    else if (lies_over(b, ov[k].j, ov[k].i)) under[ov[k].j]++;
  }
  for (int f = 0; f < nf; f++) start[f + 1] += start[f];
  int *fill = xmalloc((size_t)(nf + 1) * sizeof *fill);
  memcpy(fill, start, (size_t)nf * sizeof *fill);
  for (int k = 0; k < npairs; k++) pairs[fill[ov[k].i]++] = ov[k].j, pairs[fill[ov[k].j]++] = ov[k].i;
  unsigned char *done = xcalloc((size_t)nf + 1, 1);
  for (int placed = 0; placed < nf; placed++) {
    int pick = -1;
    for (int f = 0; f < nf; f++)
      if (!done[f] && (pick < 0 || under[f] < under[pick])) pick = f;
    done[pick] = 1;
    order[placed] = pick;
    for (int k = start[pick]; k < start[pick + 1]; k++)   /* the faces over it wait for one fewer */
      if (!done[pairs[k]] && lies_over(b, pairs[k], pick)) under[pairs[k]]--;
  }
  /* a face drawn after one it lies under would cover it: clip it to what it shows */
  int *pos = xmalloc((size_t)(nf + 1) * sizeof *pos);
  for (int k = 0; k < nf; k++) pos[order[k]] = k;
  for (int k = 0; k < npairs; k++) {
    int i = ov[k].i, j = ov[k].j;
    if (lies_over(b, i, j) && pos[i] < pos[j]) cyclic[j] = 1;
    if (lies_over(b, j, i) && pos[j] < pos[i]) cyclic[i] = 1;
  }
  free(pos);
  free(done);
  free(fill);
  free(pairs);
  free(start);
  free(under);
  free(ov);
}

/* ---- colour ------------------------------------------------------------------- */

/* Whether pixel p shows face f of the block (no mesh in front; unless
** lines_too, no line over it). */
static int shows(const Block *b, const SvgFrame *fr, size_t p, int f, int lines_too) {
  return b->ids[p] == f && fr->owner[p] == SVG_OWNER_ORIGAMI && (lines_too || !(b->near_line && b->near_line[p]));
}

/* Solve the 3 x 3 system s x = r (Cramer); 0 when it is singular. */
static int solve3(double s[3][3], const double r[3], double x[3]) {
  double det = s[0][0] * (s[1][1] * s[2][2] - s[1][2] * s[2][1]) - s[0][1] * (s[1][0] * s[2][2] - s[1][2] * s[2][0]) +
               s[0][2] * (s[1][0] * s[2][1] - s[1][1] * s[2][0]);
  if (fabs(det) < 1e-9) return 0;
  for (int k = 0; k < 3; k++) {
    double t[3][3];
    memcpy(t, s, sizeof t);
    for (int i = 0; i < 3; i++) t[i][k] = r[i];
    x[k] = (t[0][0] * (t[1][1] * t[2][2] - t[1][2] * t[2][1]) - t[0][1] * (t[1][0] * t[2][2] - t[1][2] * t[2][0]) +
            t[0][2] * (t[1][0] * t[2][1] - t[1][1] * t[2][0])) / det;
  }
  return 1;
}

/* The least-squares affine colour of face f over the pixels it shows in
** box (with lines_too, those under its lines as well). */
static Fit fit_face(const Block *b, const SvgFrame *fr, int f, SvgBox box, int lines_too) {
  Fit t;
  memset(&t, 0, sizeof t);
  double sx = 0, sy = 0;
  for (int y = box.y0; y <= box.y1; y++)
    for (int x = box.x0; x <= box.x1; x++)
      if (shows(b, fr, (size_t)y * b->w + x, f, lines_too)) sx += x + 0.5, sy += y + 0.5, t.n++;
  if (t.n == 0) return t;
  t.cx = sx / t.n, t.cy = sy / t.n;
  double s[3][3] = {{0}}, r[3][3] = {{0}};
  for (int y = box.y0; y <= box.y1; y++)
    for (int x = box.x0; x <= box.x1; x++) {
      size_t p = (size_t)y * b->w + x;
      if (!shows(b, fr, p, f, lines_too)) continue;
      double u[3] = {1, x + 0.5 - t.cx, y + 0.5 - t.cy};
      for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) s[i][j] += u[i] * u[j];
        for (int ch = 0; ch < 3; ch++) r[ch][i] += u[i] * fr->rgba[p * 4 + ch];
      }
    }
  for (int ch = 0; ch < 3; ch++) {
    double x[3];
    if (!solve3(s, r[ch], x)) x[0] = r[ch][0] / (double)t.n, x[1] = x[2] = 0;   /* too few pixels: flat */
    t.a[ch] = x[0], t.gx[ch] = x[1], t.gy[ch] = x[2];
  }
  return t;
}

/* The face's screen box (its polygon's), clipped to the frame; x1 < x0 when off screen. */
static SvgBox face_box(const Block *b, int f) {
  const OrigamiModel *m = b->m;
  double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  for (int k = m->face_start[f]; k < m->face_start[f + 1]; k++) {
    const double *q = b->xy[m->face_index[k]];
    x0 = fmin(x0, q[0]), y0 = fmin(y0, q[1]), x1 = fmax(x1, q[0]), y1 = fmax(y1, q[1]);
  }
  SvgBox r = {(int)fmax(0, floor(x0)), (int)fmax(0, floor(y0)), (int)fmin(b->w - 1, ceil(x1)),
              (int)fmin(b->h - 1, ceil(y1))};
  return r;
}

/* The fill of a face: a linear gradient along the direction its
** brightness changes (defined here as id "g<uid>"), or one colour when it
** changes by less than a code across the face. Writes the attribute into fill. */
static void face_fill(FILE *f, const Block *b, int face, const Fit *t, int uid, char *fill, size_t n) {
  static const double luma[3] = {0.2126, 0.7152, 0.0722};
  double dx = 0, dy = 0;
  for (int ch = 0; ch < 3; ch++) dx += luma[ch] * t->gx[ch], dy += luma[ch] * t->gy[ch];
  double len = hypot(dx, dy), tmin = INFINITY, tmax = -INFINITY;
  if (len > 0) dx /= len, dy /= len;
  const OrigamiModel *m = b->m;
  for (int k = m->face_start[face]; k < m->face_start[face + 1] && len > 0; k++) {
    const double *q = b->xy[m->face_index[k]];
    double s = (q[0] - t->cx) * dx + (q[1] - t->cy) * dy;
    tmin = fmin(tmin, s), tmax = fmax(tmax, s);
  }
  uint8_t c0[3], c1[3];
  for (int ch = 0; ch < 3; ch++) {
    c0[ch] = code(fit_at(t, ch, t->cx + dx * tmin, t->cy + dy * tmin));
    c1[ch] = code(fit_at(t, ch, t->cx + dx * tmax, t->cy + dy * tmax));
  }
  char h0[8], h1[8];
  if (len == 0 || !memcmp(c0, c1, 3)) {
    uint8_t mid[3] = {code(t->a[0]), code(t->a[1]), code(t->a[2])};
    hex(h0, mid);
    snprintf(fill, n, "%s", h0);
    return;
  }
  hex(h0, c0);
  hex(h1, c1);
  fprintf(f, "<defs><linearGradient id=\"g%d\" gradientUnits=\"userSpaceOnUse\" x1=\"%.2f\" y1=\"%.2f\" "
          "x2=\"%.2f\" y2=\"%.2f\"><stop offset=\"0\" stop-color=\"%s\"/><stop offset=\"1\" stop-color=\"%s\"/>"
          "</linearGradient></defs>\n", uid, t->cx + dx * tmin, t->cy + dy * tmin, t->cx + dx * tmax,
          t->cy + dy * tmax, h0, h1);
  snprintf(fill, n, "url(#g%d)", uid);
}

/* ---- one block --------------------------------------------------------------- */

/* The width in output pixels of the block's Sobel lines: they mark both
** sides of a change of face (2 samples), grown by round((width - 2) / 2)
** samples a side for wider lines. */
static double line_width(const Block *b) {
  int N = b->samples;
  long grow = lround((b->lines.width * N - 2) / 2);
  return (2 + 2 * (grow > 0 ? grow : 0)) / (double)N;
}

/* The pixels the block's lines cover: both sides of every change of face,
** grown to the line width. */
static unsigned char *line_pixels(const Block *b) {
  int w = b->w, h = b->h, r = (int)ceil(line_width(b) / 2);
  unsigned char *edge = xcalloc((size_t)w * h, 1), *near = xcalloc((size_t)w * h, 1);
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      size_t p = (size_t)y * w + x;
      if (x + 1 < w && b->ids[p] != b->ids[p + 1]) edge[p] = edge[p + 1] = 1;
      if (y + 1 < h && b->ids[p] != b->ids[p + w]) edge[p] = edge[p + w] = 1;
    }
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++)
      if (edge[(size_t)y * w + x])
        for (int yy = y - r < 0 ? 0 : y - r; yy <= y + r && yy < h; yy++)
          memset(near + (size_t)yy * w + (x - r < 0 ? 0 : x - r), 1,
                 (size_t)((x + r < w ? x + r : w - 1) - (x - r < 0 ? 0 : x - r) + 1));
  free(edge);
  return near;
}

/* The stroke attributes of the block's lines into out ("" without lines). */
static void stroke_attrs(const Block *b, char *out, size_t n) {
  out[0] = 0;
  if (!b->lines.draw) return;
  uint8_t c[3] = {image_linear_to_srgb8(b->lines.color[0]), image_linear_to_srgb8(b->lines.color[1]),
                  image_linear_to_srgb8(b->lines.color[2])};
  char h[8];
  hex(h, c);
  int k = snprintf(out, n, " stroke=\"%s\" stroke-width=\"%.2f\" stroke-linejoin=\"round\"", h, line_width(b));
  if (b->lines.opacity < 1 && k > 0 && (size_t)k < n)
    snprintf(out + k, n - (size_t)k, " stroke-opacity=\"%.3f\"", b->lines.opacity);
}

static void face_path(FILE *f, const Block *b, int face) {
  const OrigamiModel *m = b->m;
  for (int k = m->face_start[face]; k < m->face_start[face + 1]; k++) {
    const double *q = b->xy[m->face_index[k]];
    fprintf(f, "%s%.2f %.2f", k == m->face_start[face] ? "M" : "L", q[0], q[1]);
  }
  fputc('Z', f);
}

/* Is the edge from corner k of face on a flat ("F") crease? It folds
** nothing, so it is no line (the PNG's Sobel lines skip it too). */
static int flat_edge(const OrigamiModel *m, int k) {
  int c = m->face_crease[k];
  return c >= 0 && m->creases[c].assignment == 'F';
}

static int has_flat_edge(const OrigamiModel *m, int face) {
  for (int k = m->face_start[face]; k < m->face_start[face + 1]; k++)
    if (flat_edge(m, k)) return 1;
  return 0;
}

/* The face's outline as lines: face_path, less its flat edges. */
static void face_lines(FILE *f, const Block *b, int face) {
  const OrigamiModel *m = b->m;
  int s = m->face_start[face], n = m->face_start[face + 1] - s;
  if (!has_flat_edge(m, face)) { face_path(f, b, face); return; }
  int k0 = 0;
  while (!flat_edge(m, s + k0)) k0++;   /* start after a flat edge: each run is one open path */
  int pen = 0;
  for (int i = 1; i <= n; i++) {
    int k = (k0 + i) % n;   /* corner k; the edge from k - 1 to k */
    const double *q = b->xy[m->face_index[s + k]];
    if (flat_edge(m, s + (k + n - 1) % n)) { pen = 0; continue; }
    if (!pen) {
      const double *p0 = b->xy[m->face_index[s + (k + n - 1) % n]];
      fprintf(f, "M%.2f %.2f", p0[0], p0[1]);
      pen = 1;
    }
    fprintf(f, "L%.2f %.2f", q[0], q[1]);
  }
}

/* A clip path "c<uid>" of the pixels face shows, grown by grow pixels, as
** polygons; writes its attribute into attr. */
static void face_clip(FILE *f, const Block *b, int face, int grow, int uid, unsigned char *mask, char *attr,
                      size_t n) {
  SvgBox box = face_box(b, face);
  box.x0 = box.x0 - grow < 0 ? 0 : box.x0 - grow, box.y0 = box.y0 - grow < 0 ? 0 : box.y0 - grow;
  box.x1 = box.x1 + grow >= b->w ? b->w - 1 : box.x1 + grow, box.y1 = box.y1 + grow >= b->h ? b->h - 1 : box.y1 + grow;
  for (int y = box.y0; y <= box.y1; y++)
    for (int x = box.x0; x <= box.x1; x++) {
      int in = 0;
      for (int yy = y - grow; yy <= y + grow && !in; yy++)
        for (int xx = x - grow; xx <= x + grow && !in; xx++)
          in = xx >= 0 && yy >= 0 && xx < b->w && yy < b->h && b->ids[(size_t)yy * b->w + xx] == face;
      mask[(size_t)y * b->w + x] = (unsigned char)in;
    }
  fprintf(f, "<clipPath id=\"c%d\"><path d=\"", uid);
  svg_trace(f, mask, b->w, box, 0);
  fprintf(f, "\"/></clipPath>\n");
  snprintf(attr, n, " clip-path=\"url(#c%d)\"", uid);
}

/* A face's fill, and (with_line) its outline in the same element; a face
** drawn after one it lies under (cyclic) is clipped to the pixels it shows. */
static void write_fill(FILE *f, const Block *b, int face, int cyclic, int with_line, const Fit *t, int *uid,
                       unsigned char *mask) {
  char fill[32], stroke[160] = "", clip[48] = "";
  face_fill(f, b, face, t, (*uid)++, fill, sizeof fill);
  int apart = with_line && has_flat_edge(b->m, face);   /* the outline less its flat edges */
  if (with_line) stroke_attrs(b, stroke, sizeof stroke);
  if (cyclic) face_clip(f, b, face, 0, (*uid)++, mask, clip, sizeof clip);
  fprintf(f, "<path fill=\"%s\"%s%s d=\"", fill, apart ? "" : stroke, clip);
  face_path(f, b, face);
  fprintf(f, "\"/>\n");
  if (apart) {
    fprintf(f, "<path fill=\"none\"%s%s d=\"", stroke, clip);
    face_lines(f, b, face);
    fprintf(f, "\"/>\n");
  }
}

/* A face's outline, clipped to the pixels it shows grown by the line's
** reach: it shows where the face does, not where faces over it hide it. */
static void write_outline(FILE *f, const Block *b, int face, int *uid, unsigned char *mask) {
  char stroke[160], clip[48];
  stroke_attrs(b, stroke, sizeof stroke);
  face_clip(f, b, face, (int)ceil(line_width(b) / 2) + 1, (*uid)++, mask, clip, sizeof clip);
  fprintf(f, "<path fill=\"none\"%s%s d=\"", stroke, clip);
  face_lines(f, b, face);
  fprintf(f, "\"/>\n");
}

/* What the gradients miss: pixels further than SVG_RESIDUAL from their
** face's fit, in colour classes, traced over the faces. */
static void write_residual(FILE *f, const Block *b, const SvgFrame *fr, const Fit *fits, unsigned char *mask) {
  size_t np = (size_t)b->w * b->h;
  int *sel = xmalloc((np + 1) * sizeof *sel), n = 0;
  for (size_t p = 0; p < np; p++) {
    int face = b->ids[p];
    if (face < 0 || !shows(b, fr, p, face, 0) || fits[face].n == 0) continue;
    double x = (double)(p % b->w) + 0.5, y = (double)(p / b->w) + 0.5;
    int off = 0;
    for (int ch = 0; ch < 3; ch++) off |= fabs(fit_at(&fits[face], ch, x, y) - fr->rgba[p * 4 + ch]) > SVG_RESIDUAL;
    if (off) sel[n++] = (int)p;
  }
  if (n > 0) {
    int *cls = xmalloc((size_t)n * sizeof *cls), ncls;
    uint8_t rgb[SVG_MAX_CLASSES * 3];
    svg_classes(fr, sel, n, cls, &ncls, rgb);
    SvgBox box = {0, 0, b->w - 1, b->h - 1};
    for (int c = 0; c < ncls; c++) {
      memset(mask, 0, np);
      for (int k = 0; k < n; k++) mask[sel[k]] = cls[k] == c;
      svg_trace_fill(f, mask, b->w, box, 1.0, rgb + 3 * c, "");
    }
    free(cls);
  }
  free(sel);
}

/* A block: its faces back to front. Without cycles each face's outline
** is stroked with its fill, and a face over it covers what it hides. With
** them, fills go first (a face after one it lies under clipped to what it
** shows), then every outline clipped to where its face shows. */
static void write_block(FILE *f, const Block *b, const SvgFrame *fr, int *uid) {
  int nf = b->m->nfaces, any_cycle = 0;
  int *order = xmalloc((size_t)(nf + 1) * sizeof *order);
  unsigned char *cyclic = xcalloc((size_t)nf + 1, 1), *mask = xmalloc((size_t)b->w * b->h);
  unsigned char *shown = xcalloc((size_t)nf + 1, 1);
  Fit *fits = xcalloc((size_t)nf + 1, sizeof *fits);
  face_order(b, order, cyclic);
  for (int k = 0; k < nf; k++) any_cycle |= cyclic[k];
  fprintf(f, "<g>\n");
  for (int k = 0; k < nf; k++) {
    int face = order[k];
    SvgBox box = face_box(b, face);
    if (box.x1 < box.x0 || box.y1 < box.y0) continue;
    fits[face] = fit_face(b, fr, face, box, 0);
    Fit all = fits[face].n ? fits[face] : fit_face(b, fr, face, box, 1);   /* a face narrower than its lines */
    if (all.n == 0) continue;                                              /* it shows nowhere */
    shown[face] = 1;
    write_fill(f, b, face, cyclic[face], b->lines.draw && !any_cycle, &all, uid, mask);
  }
  write_residual(f, b, fr, fits, mask);
  for (int k = 0; any_cycle && b->lines.draw && k < nf; k++)
    if (shown[order[k]]) write_outline(f, b, order[k], uid, mask);
  fprintf(f, "</g>\n");
  free(fits);
  free(shown);
  free(mask);
  free(cyclic);
  free(order);
}

/* ---- the blocks --------------------------------------------------------------- */

static int is_mesh(const SvgFrame *fr, size_t p) { return fr->owner[p] >= 0 && fr->owner[p] < fr->nobjects; }

/* A clip leaving out the mesh pixels in front of any origami: mesh pixels
** where a face is (covered[p]), and the mesh pixels within reach of them
** (reach: where the faces' outlines stroke past their edges); nothing
** when there are none. */
static void front_clip(FILE *f, const SvgFrame *fr, const unsigned char *covered, int reach, int *clip_id) {
  size_t np = (size_t)fr->w * fr->h;
  unsigned char *keep = xmalloc(np);
  int any = 0;
  for (size_t p = 0; p < np; p++) keep[p] = 1;
  for (size_t p = 0; p < np; p++) {
    if (!covered[p] || !is_mesh(fr, p)) continue;
    any = 1;
    int x = (int)(p % fr->w), y = (int)(p / fr->w);
    for (int yy = y - reach; yy <= y + reach; yy++)
      for (int xx = x - reach; xx <= x + reach; xx++) {
        size_t q = (size_t)yy * fr->w + xx;
        if (xx >= 0 && yy >= 0 && xx < fr->w && yy < fr->h && is_mesh(fr, q)) keep[q] = 0;
      }
  }
  *clip_id = -1;
  if (any) {
    SvgBox box = {0, 0, fr->w - 1, fr->h - 1};
    fprintf(f, "<clipPath id=\"front\"><path clip-rule=\"evenodd\" d=\"");
    svg_trace(f, keep, fr->w, box, 1.0);
    fprintf(f, "\"/></clipPath>\n");
    *clip_id = 0;
  }
  free(keep);
}

int svg_write_origami(FILE *f, const SvgFrame *fr, const Scene *s, const Mat4 *world_to_clip) {
  if (s->norigami == 0) return 1;
  size_t np = (size_t)fr->w * fr->h;
  Block *blocks = xcalloc((size_t)s->norigami, sizeof *blocks);
  unsigned char *covered = xcalloc(np, 1);
  SceneStyle fallback = scene_default_style();
  int ok = 1;
  for (int i = 0; i < s->norigami; i++) {
    const SceneOrigami *o = &s->origami[i];
    Block *b = &blocks[i];
    OrigamiModel *m = origami_build(o, 0);
    if (!m) { ok = 0; continue; }
    const SceneStyle *style = o->style >= 0 && o->style < s->nstyles ? &s->styles[o->style] : &fallback;
    Mat4 object_to_clip = m4_mul(*world_to_clip, o->transform);
    b->m = m, b->w = fr->w, b->h = fr->h;
    b->ids = xmalloc(np * sizeof *b->ids);
    origami_render_ids(m, &object_to_clip, fr->w, fr->h, NULL, b->ids);
    b->xy = xmalloc((size_t)(m->nverts + 1) * sizeof *b->xy);
    b->from_below = origami_screen_points(m, &object_to_clip, fr->w, fr->h, b->xy);
    b->lines = origami_lines_of(style);
    b->samples = fr->samples > 0 ? fr->samples : 1;
    b->near_line = b->lines.draw ? line_pixels(b) : NULL;
    for (size_t p = 0; p < np; p++) covered[p] |= b->ids[p] >= 0;
  }
  int clip, uid = 0, reach = 1;
  for (int i = 0; i < s->norigami; i++)
    if (blocks[i].m && blocks[i].lines.draw) reach = fmax(reach, ceil(line_width(&blocks[i]) / 2) + 1);
  front_clip(f, fr, covered, reach, &clip);
  fprintf(f, clip >= 0 ? "<g id=\"origami\" clip-path=\"url(#front)\">\n" : "<g id=\"origami\">\n");
  for (int i = 0; i < s->norigami; i++)
    if (blocks[i].m) write_block(f, &blocks[i], fr, &uid);
  fprintf(f, "</g>\n");
  for (int i = 0; i < s->norigami; i++) {
    origami_free((OrigamiModel *)blocks[i].m);
    free(blocks[i].ids);
    free(blocks[i].xy);
    free(blocks[i].near_line);
  }
  free(covered);
  free(blocks);
  return ok;
}
