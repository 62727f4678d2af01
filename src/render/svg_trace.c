/*
** Traced regions for the SVG writer (svg_trace.h): potrace over pixel
** masks, colour classes of an object's pixels, and the layers of the mesh
** objects.
*/
#include "svg_trace.h"

#include <limits.h>
#include <math.h>
#include <potracelib.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"

/* ---- potrace ------------------------------------------------------------ */

#define WORD_BITS ((int)(8 * sizeof(potrace_word)))

static void put_point(FILE *f, potrace_dpoint_t p, int x0, int y0) {
  fprintf(f, "%.2f %.2f", p.x + x0, p.y + y0);
}

/* One traced curve: from the end of its last segment, each segment a
** Bezier (CURVETO) or two straight lines through its corner (CORNER). */
static void put_curve(FILE *f, const potrace_curve_t *c, int x0, int y0) {
  fputc('M', f);
  put_point(f, c->c[c->n - 1][2], x0, y0);
  for (int i = 0; i < c->n; i++) {
    if (c->tag[i] == POTRACE_CURVETO) {
      fputc('C', f);
      put_point(f, c->c[i][0], x0, y0);
      fputc(' ', f);
      put_point(f, c->c[i][1], x0, y0);
    } else {
      fputc('L', f);
      put_point(f, c->c[i][1], x0, y0);
    }
    fputc(c->tag[i] == POTRACE_CURVETO ? ' ' : 'L', f);
    put_point(f, c->c[i][2], x0, y0);
  }
  fputc('Z', f);
}

int svg_trace(FILE *f, const unsigned char *mask, int w, SvgBox box, double alphamax) {
  int bw = box.x1 - box.x0 + 1, bh = box.y1 - box.y0 + 1;
  if (bw <= 0 || bh <= 0) return 0;
  potrace_bitmap_t bm = {bw, bh, (bw + WORD_BITS - 1) / WORD_BITS, NULL};
  bm.map = xcalloc((size_t)bm.dy * (size_t)bh, sizeof *bm.map);
  int any = 0;
  for (int y = 0; y < bh; y++) {   /* scanline y is pixel row box.y0 + y: the curves come out y down */
    const unsigned char *row = mask + (size_t)(box.y0 + y) * w + box.x0;
    potrace_word *out = bm.map + (size_t)y * bm.dy;
    for (int x = 0; x < bw; x++)
      if (row[x]) out[x / WORD_BITS] |= (potrace_word)1 << (WORD_BITS - 1 - x % WORD_BITS), any = 1;
  }
  int n = 0;
  potrace_param_t *param = any ? potrace_param_default() : NULL;
  if (param) {
    param->turdsize = 0;       /* every pixel is somebody's: no speck is dropped */
    param->alphamax = alphamax;
    potrace_state_t *st = potrace_trace(param, &bm);
    if (st && st->status == POTRACE_STATUS_OK)
      for (const potrace_path_t *p = st->plist; p; p = p->next, n++) put_curve(f, &p->curve, box.x0, box.y0);
    potrace_state_free(st);
    potrace_param_free(param);
  }
  free(bm.map);
  return n;
}

void svg_trace_fill(FILE *f, const unsigned char *mask, int w, SvgBox box, double alphamax,
                    const uint8_t rgb[3], const char *attrs) {
  int any = 0;
  for (int y = box.y0; y <= box.y1 && !any; y++)
    for (int x = box.x0; x <= box.x1 && !any; x++) any = mask[(size_t)y * w + x];
  if (!any) return;
  fprintf(f, "<path fill=\"#%02x%02x%02x\"%s d=\"", rgb[0], rgb[1], rgb[2], attrs);
  svg_trace(f, mask, w, box, alphamax);
  fprintf(f, "\"/>\n");
}

/* ---- colour classes ------------------------------------------------------ */

/* Colours are binned 16 codes a channel wide, 4096 bins. */
#define BIN_BITS 4
#define NBINS (1 << (3 * (8 - BIN_BITS)))

static int bin_of(const uint8_t *c) {
  return (c[0] >> BIN_BITS) << (2 * (8 - BIN_BITS)) | (c[1] >> BIN_BITS) << (8 - BIN_BITS) | c[2] >> BIN_BITS;
}

typedef struct Cand { int bin; long count; } Cand;

static int by_count(const void *a, const void *b) {
  const Cand *x = a, *y = b;
  return x->count != y->count ? (x->count < y->count) - (x->count > y->count) : x->bin - y->bin;
}

static long dist2(const uint8_t *c, const double *m) {
  double d = 0;
  for (int k = 0; k < 3; k++) d += (c[k] - m[k]) * (c[k] - m[k]);
  return (long)d;
}

/* Each pixel of sel to its nearest mean; then the means of what each got. */
static void assign(const SvgFrame *fr, const int *sel, int n, int *cls, double (*mean)[3], int ncls) {
  long *cnt = xcalloc((size_t)ncls, sizeof *cnt);
  double (*sum)[3] = xcalloc((size_t)ncls, sizeof *sum);
  for (int k = 0; k < n; k++) {
    const uint8_t *c = fr->rgba + (size_t)sel[k] * 4;
    int best = 0;
    long bd = LONG_MAX;
    for (int j = 0; j < ncls; j++) {
      long d = dist2(c, mean[j]);
      if (d < bd) bd = d, best = j;
    }
    cls[k] = best;
    cnt[best]++;
    for (int q = 0; q < 3; q++) sum[best][q] += c[q];
  }
  for (int j = 0; j < ncls; j++)
    if (cnt[j])
      for (int q = 0; q < 3; q++) mean[j][q] = sum[j][q] / (double)cnt[j];
  free(cnt);
  free(sum);
}

/* The first means: bins taken fullest first, each one whose mean is
** further than SVG_CLASS_STEP (any channel) from every mean taken so far,
** so that every colour of the set has a class near it (until
** SVG_MAX_CLASSES). Returns their count. */
static int seed_means(const SvgFrame *fr, const int *sel, int n, double (*mean)[3]) {
  Cand *cand = xcalloc(NBINS, sizeof *cand);
  double (*sum)[3] = xcalloc(NBINS, sizeof *sum);
  for (int b = 0; b < NBINS; b++) cand[b].bin = b;
  for (int k = 0; k < n; k++) {
    const uint8_t *c = fr->rgba + (size_t)sel[k] * 4;
    int b = bin_of(c);
    cand[b].count++;
    for (int q = 0; q < 3; q++) sum[b][q] += c[q];
  }
  qsort(cand, NBINS, sizeof *cand, by_count);
  int m = 0;
  for (int i = 0; i < NBINS && m < SVG_MAX_CLASSES && cand[i].count > 0; i++) {
    double c[3];
    for (int q = 0; q < 3; q++) c[q] = sum[cand[i].bin][q] / (double)cand[i].count;
    int near = 0;
    for (int j = 0; j < m && !near; j++)
      near = fabs(c[0] - mean[j][0]) <= SVG_CLASS_STEP && fabs(c[1] - mean[j][1]) <= SVG_CLASS_STEP &&
             fabs(c[2] - mean[j][2]) <= SVG_CLASS_STEP;
    if (!near) memcpy(mean[m++], c, sizeof c);
  }
  free(cand);
  free(sum);
  return m;
}

/* Regions of one class under SVG_MIN_REGION pixels join the class most of
** their neighbours in the set have. lab: a w x h map of classes (-1: not
** in the set). */
static void merge_specks(int w, int h, int *lab) {
  size_t np = (size_t)w * h;
  unsigned char *seen = xcalloc(np, 1);
  int *comp = xmalloc(np * sizeof *comp);
  for (size_t s = 0; s < np; s++) {
    if (lab[s] < 0 || seen[s]) continue;
    int n = 0, c = lab[s];
    comp[n++] = (int)s;
    seen[s] = 1;
    for (int i = 0; i < n; i++) {   /* flood the 4-connected region of class c */
      int p = comp[i], x = p % w, y = p / w;
      int nb[4] = {x > 0 ? p - 1 : -1, x + 1 < w ? p + 1 : -1, y > 0 ? p - w : -1, y + 1 < h ? p + w : -1};
      for (int k = 0; k < 4; k++)
        if (nb[k] >= 0 && !seen[nb[k]] && lab[nb[k]] == c) seen[nb[k]] = 1, comp[n++] = nb[k];
    }
    if (n >= SVG_MIN_REGION) continue;
    int votes[SVG_MAX_CLASSES] = {0}, best = -1;
    for (int i = 0; i < n; i++) {
      int p = comp[i], x = p % w, y = p / w;
      int nb[4] = {x > 0 ? p - 1 : -1, x + 1 < w ? p + 1 : -1, y > 0 ? p - w : -1, y + 1 < h ? p + w : -1};
      for (int k = 0; k < 4; k++)
        if (nb[k] >= 0 && lab[nb[k]] >= 0 && lab[nb[k]] != c) votes[lab[nb[k]]]++;
    }
    for (int j = 0; j < SVG_MAX_CLASSES; j++)
      if (votes[j] && (best < 0 || votes[j] > votes[best])) best = j;
    for (int i = 0; best >= 0 && i < n; i++) lab[comp[i]] = best;
  }
  free(comp);
  free(seen);
}

static double luma(const double *m) { return 0.2126 * m[0] + 0.7152 * m[1] + 0.0722 * m[2]; }

void svg_classes(const SvgFrame *fr, const int *sel, int n, int *cls, int *ncls, uint8_t *rgb) {
  double mean[SVG_MAX_CLASSES][3];
  int m = seed_means(fr, sel, n, mean);
  assign(fr, sel, n, cls, mean, m);
  assign(fr, sel, n, cls, mean, m);   /* a second round with the means the first gave */
  /* the classes on a map of the set's box, for its regions */
  int x0 = fr->w, y0 = fr->h, x1 = -1, y1 = -1;
  for (int k = 0; k < n; k++) {
    int x = sel[k] % fr->w, y = sel[k] / fr->w;
    x0 = x < x0 ? x : x0, y0 = y < y0 ? y : y0, x1 = x > x1 ? x : x1, y1 = y > y1 ? y : y1;
  }
  int bw = x1 - x0 + 1, bh = y1 - y0 + 1;
  int *lab = xmalloc(((size_t)(n ? bw * bh : 0) + 1) * sizeof *lab);
  for (size_t p = 0; n && p < (size_t)bw * bh; p++) lab[p] = -1;
#define AT(k) ((size_t)(sel[k] / fr->w - y0) * bw + (size_t)(sel[k] % fr->w - x0))
  for (int k = 0; k < n; k++) lab[AT(k)] = cls[k];
  if (n) merge_specks(bw, bh, lab);
  /* the classes left, dark to light */
  long cnt[SVG_MAX_CLASSES] = {0};
  for (int k = 0; k < n; k++) cnt[cls[k] = lab[AT(k)]]++;
#undef AT
  int order[SVG_MAX_CLASSES], used = 0, rank[SVG_MAX_CLASSES];
  for (int j = 0; j < m; j++)
    if (cnt[j]) order[used++] = j;
  for (int i = 1; i < used; i++)   /* insertion sort by brightness, then index */
    for (int j = i; j > 0 && luma(mean[order[j]]) < luma(mean[order[j - 1]]); j--) {
      int t = order[j];
      order[j] = order[j - 1];
      order[j - 1] = t;
    }
  for (int i = 0; i < used; i++) {
    rank[order[i]] = i;
    for (int q = 0; q < 3; q++) rgb[3 * i + q] = (uint8_t)(mean[order[i]][q] + 0.5);
  }
  for (int k = 0; k < n; k++) cls[k] = rank[cls[k]];
  *ncls = used;
  free(lab);
}

/* ---- the mesh objects' layers ---------------------------------------------- */

typedef struct ObjOrder { int obj; double depth; } ObjOrder;

static int far_first(const void *a, const void *b) {
  const ObjOrder *x = a, *y = b;
  if (x->depth != y->depth) return x->depth < y->depth ? 1 : -1;
  return x->obj - y->obj;
}

/* Paint layer L: its pixels (own, n of them) and those within
** SVG_UNDERLAP of them whose layer (rank) comes later. */
static void paint_layer(FILE *f, const SvgFrame *fr, const int32_t *rank, int L, const int *own, int n,
                        const uint8_t rgb[3], unsigned char *mask) {
  int w = fr->w, h = fr->h, r = SVG_UNDERLAP;
  SvgBox b = {w, h, -1, -1};
  for (int k = 0; k < n; k++) {
    int x = own[k] % w, y = own[k] / w;
    if (x < b.x0) b.x0 = x;
    if (y < b.y0) b.y0 = y;
    if (x > b.x1) b.x1 = x;
    if (y > b.y1) b.y1 = y;
  }
  b.x0 = b.x0 - r < 0 ? 0 : b.x0 - r, b.y0 = b.y0 - r < 0 ? 0 : b.y0 - r;
  b.x1 = b.x1 + r >= w ? w - 1 : b.x1 + r, b.y1 = b.y1 + r >= h ? h - 1 : b.y1 + r;
  for (int y = b.y0; y <= b.y1; y++) memset(mask + (size_t)y * w + b.x0, 0, (size_t)(b.x1 - b.x0 + 1));
  for (int k = 0; k < n; k++) {
    int x = own[k] % w, y = own[k] / w;
    mask[own[k]] = 1;
    for (int dy = -r; dy <= r; dy++)
      for (int dx = -r; dx <= r; dx++) {
        int xx = x + dx, yy = y + dy;
        if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
        size_t q = (size_t)yy * w + xx;
        if (rank[q] > L) mask[q] = 1;
      }
  }
  svg_trace_fill(f, mask, w, b, 1.0, rgb, "");
}

/* The group pixel p is painted in: its object, nobjects for the
** background, -1 for origami (painted by svg_origami.h). */
static int group_of(const SvgFrame *fr, size_t p) {
  int o = fr->owner[p];
  return o >= 0 && o < fr->nobjects ? o : o == -1 ? fr->nobjects : -1;
}

/* Whether the background group (pixels sel, n of them, in ncls classes)
** needs layers: not when it is one colour (the background rectangle is)
** or transparent. */
static int background_drawn(const SvgFrame *fr, const int *sel, int n, int ncls) {
  long alpha = 0;
  for (int k = 0; k < n; k++) alpha += fr->rgba[(size_t)sel[k] * 4 + 3];
  return ncls > 1 && alpha >= 128L * n;
}

void svg_write_regions(FILE *f, const SvgFrame *fr) {
  int w = fr->w, h = fr->h, no = fr->nobjects, ng = no + 1;   /* groups: the objects, then the background */
  size_t np = (size_t)w * h;
  /* each group's pixels, gathered by a counting sort */
  int *start = xcalloc((size_t)ng + 1, sizeof *start), *pix = xmalloc((np + 1) * sizeof *pix);
  ObjOrder *ord = xcalloc((size_t)ng, sizeof *ord);
  for (size_t p = 0; p < np; p++) {
    int g = group_of(fr, p);
    if (g >= 0) start[g + 1]++, ord[g].depth += fr->depth[p];
  }
  for (int g = 0; g < ng; g++) {
    ord[g].obj = g;
    ord[g].depth = g == no ? INFINITY : start[g + 1] ? ord[g].depth / start[g + 1] : 0;   /* the background first */
    start[g + 1] += start[g];
  }
  int *fill = xmalloc((size_t)ng * sizeof *fill);
  memcpy(fill, start, (size_t)ng * sizeof *fill);
  for (size_t p = 0; p < np; p++) {
    int g = group_of(fr, p);
    if (g >= 0) pix[fill[g]++] = (int)p;
  }
  qsort(ord, (size_t)ng, sizeof *ord, far_first);
  /* every pixel's layer: groups in painting order, each one's classes dark to light */
  int32_t *rank = xmalloc(np * sizeof *rank);
  for (size_t p = 0; p < np; p++) rank[p] = fr->owner[p] == SVG_OWNER_ORIGAMI ? INT32_MAX : -1;
  int *cls = xmalloc((np + 1) * sizeof *cls);
  uint8_t (*rgb)[SVG_MAX_CLASSES * 3] = xmalloc((size_t)ng * sizeof *rgb);
  int *ncls = xcalloc((size_t)ng, sizeof *ncls), *base = xcalloc((size_t)ng, sizeof *base);
  int layers = 0;
  for (int i = 0; i < ng; i++) {
    int g = ord[i].obj, n = start[g + 1] - start[g];
    if (n == 0) continue;
    svg_classes(fr, pix + start[g], n, cls + start[g], &ncls[g], rgb[g]);
    if (g == no && !background_drawn(fr, pix + start[g], n, ncls[g])) { ncls[g] = 0; continue; }
    base[g] = layers;
    for (int k = 0; k < n; k++) rank[pix[start[g] + k]] = layers + cls[start[g] + k];
    layers += ncls[g];
  }
  /* paint them: each class's pixels, in a list of its own */
  unsigned char *mask = xcalloc(np, 1);
  int *own = xmalloc((np + 1) * sizeof *own);
  for (int i = 0; i < ng; i++) {
    int g = ord[i].obj, n = start[g + 1] - start[g];
    for (int c = 0; c < ncls[g]; c++) {
      int m = 0;
      for (int k = 0; k < n; k++)
        if (cls[start[g] + k] == c) own[m++] = pix[start[g] + k];
      paint_layer(f, fr, rank, base[g] + c, own, m, rgb[g] + 3 * c, mask);
    }
  }
  free(own);
  free(mask);
  free(base);
  free(ncls);
  free(rgb);
  free(cls);
  free(rank);
  free(fill);
  free(ord);
  free(pix);
  free(start);
}
