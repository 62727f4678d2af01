/*
** Threshold textures (002 sections 2-5): toon's lighting equation with the
** multi-band step T_n applied to the diffuse and the specular terms, where
** the threshold t of T_n varies over the surface, read from layers of
** threshold textures:
**   I = m_a l_a + sum_i m_d T_n(f_d, t_d) l_i + sum_i m_s T_m(f_s, t_s) l_i.
** A layer is procedural lines (hatch.h: the dyadic rescaling of eq. 5-8),
** stipple dots, or an image equalized by CLAHE at every mip level
** (texture.h), each over texture coordinates with screen derivatives from
** the triangle's own gradients (texcoord.h).
**
** Filtering (section 4) is percentage-closer: the smooth shade is
** thresholded against several thresholds of the sample's footprint and the
** results averaged, not the thresholds: exactly (the box-filtered sawtooth)
** for lines, over four taps of the footprint for dots, over the two mip
** levels for images. A layer's result is the bright fraction of the
** footprint for shade y, C(y) = P(t <= y).
**
** Composition: a layer is active over its tone range [lo, hi] (the band's
** shade y maps to (y - lo) / (hi - lo): solid ink below lo, none above hi),
** and the layers of a term ink wherever any of them does, so the bright
** fraction is the product of theirs (cross-hatching: a second layer at
** another angle over the darker half). A term no layer names thresholds at
** the style's constant (toon's `threshold`, `specular_threshold`).
**
** Strength (section 5): the thresholded value blends back toward the
** smooth one, T' = x + s (T - x), with s = strength times the `facing`
** curve at n.v times the `light` curve at the smooth term x.
*/
#include "shade.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../base/lanes.h"
#include "../base/mem.h"
#include "../base/rng.h"
#include "../lang/diag.h"
#include "hatch.h"
#include "shadow.h"
#include "texcoord.h"
#include "texture.h"

/* ---- the style, resolved once a frame ----------------------------------------- */

enum { TERM_DIFFUSE_BIT = 1, TERM_SPECULAR_BIT = 2 };

/* One layer as the model reads it. */
typedef struct Layer {
  ThresholdLayerKind kind;
  unsigned terms;              /* TERM_*_BIT */
  float lo, inv_span;          /* the tone range: y -> (y - lo) / (hi - lo) */
  float cs, sn;                /* the angle's cosine and sine */
  float spacing;               /* pixels (hatch, stipple) */
  float noise, inv_noise_scale;
  uint32_t seed;               /* the noise lattice's */
  const ThresholdTexture *tex; /* image */
  float inv_scale;             /* image: copies a texture unit */
} Layer;

struct ThresholdStyle {
  float inv_scale;             /* texture units an object unit */
  int filter;
  float strength;
  const double *facing, *light;
  int nfacing, nlight;
  int nlayers;
  Layer *layers;
  TexView view;                /* the frame's camera, set when its objects are prepared */
  float spec_cut2;             /* (n.h / |h|)^2 below which f_s < 2^-12 */
};

/* A layer when the block gives none: the default hatch. */
static ThresholdLayer default_layer(void) {
  ThresholdLayer l;
  memset(&l, 0, sizeof l);
  l.kind = LAYER_HATCH;
  l.range[1] = 1;
  l.angle = 45;
  l.spacing = 6;
  l.noise_scale = 0.1;
  l.loc = l.file_loc = src_none();
  return l;
}

static int layer_init(Layer *L, const ThresholdLayer *src, int index) {
  L->kind = src->kind;
  L->terms = src->term == TERM_DIFFUSE ? TERM_DIFFUSE_BIT
             : src->term == TERM_SPECULAR ? TERM_SPECULAR_BIT
                                          : TERM_DIFFUSE_BIT | TERM_SPECULAR_BIT;
  L->lo = (float)src->range[0];
  L->inv_span = (float)(1 / (src->range[1] - src->range[0]));
  L->cs = (float)cos(src->angle * M_PI / 180);
  L->sn = (float)sin(src->angle * M_PI / 180);
  L->spacing = (float)src->spacing;
  L->noise = (float)src->noise;
  L->inv_noise_scale = (float)(1 / src->noise_scale);
  Rng r;
  rng_seed_key(&r, 0x5eed, 0, (uint32_t)index);   /* the lattice of layer index */
  L->seed = rng_next(&r);
  L->inv_scale = src->scale > 0 ? (float)(1 / src->scale) : 1;
  L->tex = NULL;
  if (src->kind != LAYER_IMAGE) return 1;
  char err[512];
  L->tex = texture_threshold(src->file, src->window, src->clip, err, sizeof err);
  if (L->tex) return 1;
  diag_error(src->file_loc.file >= 0 ? src->file_loc : src->loc, "%s", err);   /* it names the file */
  return 0;
}

int shade_threshold_init(RenderStyle *rs, const SceneStyle *st) {
  const ShadeThreshold *th = &st->shade.threshold;
  ThresholdStyle *ts = xcalloc(1, sizeof *ts);
  rs->layers = ts;
  ts->inv_scale = th->scale > 0 ? (float)(1 / th->scale) : 1;
  float cut = powf(0x1p-12f, 1 / rs->shininess);
  ts->spec_cut2 = cut * cut;
  ts->filter = th->filter;
  ts->strength = (float)th->strength;
  ts->facing = th->facing;
  ts->nfacing = th->nfacing;
  ts->light = th->light;
  ts->nlight = th->nlight;
  ThresholdLayer fallback = default_layer();
  ts->nlayers = th->nlayers > 0 ? th->nlayers : 1;
  ts->layers = xcalloc((size_t)ts->nlayers, sizeof *ts->layers);
  int ok = 1;
  for (int i = 0; i < ts->nlayers; i++)
    ok &= layer_init(&ts->layers[i], th->nlayers > 0 ? &th->layers[i] : &fallback, i);
  return ok;
}

void shade_threshold_free(RenderStyle *rs) {
  if (!rs->layers) return;
  free(rs->layers->layers);
  free(rs->layers);
  rs->layers = NULL;
}

int shade_threshold_prepare(const RenderFrame *f, RenderObject *o) {
  const SceneShade *sh = &o->style->src->shade;
  if (!texcoord_available(o, sh->threshold.projection)) {
    diag_error(sh->threshold.projection_loc.file >= 0 ? sh->threshold.projection_loc : sh->loc,
               "`projection uv` needs texture coordinates, and this object's geometry has none "
               "(a mesh without UVs, or a subdivision surface); use planar, box, cylindrical or spherical");
    diag_note(o->src->loc, "the object");
    return 0;
  }
  int projection = texcoord_resolve(o, sh->threshold.projection);
  TexView view;
  texcoord_view(&view, &f->camera);
  o->style->layers->view = view;   /* the same for every object of the frame */
  int n = o->mesh->ntris;
  o->texcoords = xmalloc(((size_t)n + 1) * sizeof *o->texcoords);
  for (int t = 0; t < n; t++)   /* a back face the rasterizer skips is never shaded */
    if (!(o->cull_back && o->backfacing[t]))
      texcoord_triangle(&o->texcoords[t], o, t, projection, o->style->layers->inv_scale, &view);
  return 1;
}

/* ---- a block of samples -------------------------------------------------------- */

#ifndef FOOTPRINT
#define FOOTPRINT 1.0f
#endif

/* Samples shaded together: their planes live on the stack. */
#define BLOCK 64

/* Most thresholds a layer reads at a sample (an image's trilinear taps). */
#define MAX_TAPS 8
/* Where a stipple layer keeps its taps' span (the row after its 4 weights). */
#define STIPPLE_SPAN (MAX_TAPS + 4)

/* A block's samples: texture coordinates and derivatives, n.v, and what
** each layer found (a[0..3] for lines: position in the period, footprint,
** blend t, 1 / (1 + t); else thresholds a[0..nq-1] and their weights a[MAX_TAPS..]). */
typedef struct Block {
  int n;                       /* samples */
  int n4;                      /* n rounded up to SIMD lanes: the side-by-side loops run to it
                                  over copies of the last sample, with no scalar tail */
  float u[BLOCK + 4], v[BLOCK + 4], ux[BLOCK + 4], uy[BLOCK + 4], vx[BLOCK + 4], vy[BLOCK + 4];
                               /* 4 spare: a run's last lane group writes past its end */
  float nv[BLOCK];
  float a[SCENE_MAX_LAYERS][2 * MAX_TAPS][BLOCK];
  int nq[SCENE_MAX_LAYERS];
  unsigned filled;             /* bit i: layer i's a[i] and nq[i] are set (layer_fill) */
  float inv_n;                 /* a sample's share of a pixel side */
} Block;

/* The coordinates of samples k0..k0+n-1 of r (object o) into b, a run of
** one triangle at a time (its constants held while the run's samples go
** side by side, four lanes at a time). A run's last lane group reads past
** the run: inside the block that is the block's next samples, but past
** the block's end it may be past the row, so that group reads a padded
** copy. */
static void block_coords(Block *b, const ShadeRow *r, const RenderObject *o, const TexView *view,
                         int k0, int n) {
  for (int j = 0, e; j < n; j = e) {
    int face = r->face[k0 + j];
    for (e = j + 1; e < n && r->face[k0 + e] == face; e++) {}
    int k = k0 + j, m = e - j;
    const TexTriangle *tt = &o->texcoords[face];
    int inside = j + ((m + 3) & ~3) <= n ? m : m & ~3;   /* samples whose lane groups stay in the block */
    texcoord_run_lanes(tt, view, inside, r->bary + k, r->px + k, r->py + k, r->pz + k,
                       b->u + j, b->v + j, b->ux + j, b->uy + j, b->vx + j, b->vy + j);
    if (inside == m) continue;
    float bary[4][2] = {{0}}, px[4] = {0}, py[4] = {0}, pz[4] = {0};
    for (int i = 0; i < m - inside; i++) {
      int q = k + inside + i;
      bary[i][0] = r->bary[q][0]; bary[i][1] = r->bary[q][1];
      px[i] = r->px[q]; py[i] = r->py[q]; pz[i] = r->pz[q];
    }
    int at = j + inside;
    texcoord_run_lanes(tt, view, 4, bary, px, py, pz, b->u + at, b->v + at, b->ux + at, b->uy + at,
                       b->vx + at, b->vy + at);
  }
  b->n4 = (n + 3) & ~3;
  for (int j = n; j < b->n4; j++) {   /* the padding lanes: copies of the last sample */
    b->u[j] = b->u[n - 1]; b->v[j] = b->v[n - 1];
    b->ux[j] = b->ux[n - 1]; b->uy[j] = b->uy[n - 1]; b->vx[j] = b->vx[n - 1]; b->vy[j] = b->vy[n - 1];
  }
  /* the row's planes hold SHADE_LANES spare samples past any run */
  const float *nx = r->nx + k0, *ny = r->ny + k0, *nz = r->nz + k0;
  const float *vx = r->vx + k0, *vy = r->vy + k0, *vz = r->vz + k0;
  for (int j = 0; j < b->n4; j++) {
    float nv = nx[j] * vx[j] + ny[j] * vy[j] + nz[j] * vz[j];
    b->nv[j] = nv > 0 ? nv : 0;
  }
}

/* Noise displacement in [-1/2, 1/2) times the layer's amount at sample j. */
static inline float noise_shift(const Layer *L, const Block *b, int j, uint32_t salt) {
  return L->noise * (hatch_noise(b->u[j] * L->inv_noise_scale, b->v[j] * L->inv_noise_scale, L->seed ^ salt) - 0.5f);
}

/* Lines along the iso-lines of h = -sin(a) u + cos(a) v: the position in
** the period at the dyadic scale, the footprint (FOOTPRINT times
** |dh/dx| + |dh/dy| of a sample, in periods) and the blend. Noise moves h by a fraction of the
** spacing on screen, so it stays put across scales. */
static void hatch_block(const Layer *L, Block *b, float inv_n, int filter, float a[2 * MAX_TAPS][BLOCK]) {
  float cs = L->cs, sn = L->sn, w = L->spacing, k = filter ? inv_n * FOOTPRINT : 0;
  float shift[BLOCK];   /* noise: a fraction of the spacing, in pixels */
  int noise = L->noise > 0;
  if (noise)
    for (int j = 0; j < b->n4; j++) shift[j] = noise_shift(L, b, j, 0) * w;
  /* four lanes at a time: the clamps are minima and maxima (base/lanes.h) */
  F4 nsn = f4_set(-sn), fcs = f4_set(cs), fw = f4_set(w), fk = f4_set(k), one = f4_set(1);
  for (int j = 0; j < b->n4; j += 4) {
    F4 h = f4_add(f4_mul(nsn, f4_load(b->u + j)), f4_mul(fcs, f4_load(b->v + j)));
    F4 hx = f4_add(f4_mul(nsn, f4_load(b->ux + j)), f4_mul(fcs, f4_load(b->vx + j)));
    F4 hy = f4_add(f4_mul(nsn, f4_load(b->uy + j)), f4_mul(fcs, f4_load(b->vy + j)));
    F4 g = f4_sqrt(f4_add(f4_mul(hx, hx), f4_mul(hy, hy)));
    /* hatch_scale: d = 1 / (g w) kept in [2^-30, 2^30] (NaN: 2^-30), m =
    ** 2^floor(log2 d), t = log2 of the mantissa by its cubic */
    F4 d = f4_min(f4_max(f4_div(one, f4_mul(g, fw)), f4_set(0x1p-30f)), f4_set(0x1p30f));
    F4 m = f4_and_bits(d, 0x7f800000u);
    F4 f = f4_sub(f4_or_bits(f4_and_bits(d, 0x007fffffu), 0x3f800000u), one);
    F4 t = f4_add(f, f4_mul(f4_mul(f, f4_sub(one, f)), f4_sub(f4_set(0.42086f), f4_mul(f4_set(0.15639f), f))));
    F4 x = f4_mul(m, noise ? f4_add(h, f4_mul(f4_load(shift + j), g)) : h);
    x = f4_keep(f4_lt(f4_abs(x), f4_set(0x1p23f)), f4_sub(x, f4_floor(x)));   /* past 2^23 a float has no fraction */
    F4 fp = f4_mul(f4_mul(m, f4_add(f4_abs(hx), f4_abs(hy))), fk);
    f4_store(a[0] + j, x);
    f4_store(a[1] + j, f4_min(fp, f4_set(16)));   /* 16 whole periods are the mean already */
    f4_store(a[2] + j, t);
    f4_store(a[3] + j, f4_div(one, f4_add(one, t)));
  }
}

/* Dots on the grid of a = cos(a) u + sin(a) v, b = -sin(a) u + cos(a) v,
** spaced by the denser of the two directions; filtered over four taps at
** (+-1/4, +-1/4) of the sample's footprint, each standing for its quarter
** of it: the threshold's change across a quarter, from the taps'
** differences, is kept (a[STIPPLE_SPAN]) so each tap's result is the box
** filter of a linear ramp over its quarter, not a step. */
static void stipple_block(const Layer *L, Block *b, float inv_n, int filter, float a[2 * MAX_TAPS][BLOCK],
                          int *nq) {
  static const float tap[4][2] = {{-0.25f, -0.25f}, {0.25f, -0.25f}, {-0.25f, 0.25f}, {0.25f, 0.25f}};
  float cs = L->cs, sn = L->sn;
  *nq = filter ? 4 : 1;
  for (int j = 0; j < b->n; j++) {
    float s = cs * b->u[j] + sn * b->v[j], t = -sn * b->u[j] + cs * b->v[j];
    float sx = cs * b->ux[j] + sn * b->vx[j], sy = cs * b->uy[j] + sn * b->vy[j];
    float tx = -sn * b->ux[j] + cs * b->vx[j], ty = -sn * b->uy[j] + cs * b->vy[j];
    float g = fmaxf(sqrtf(sx * sx + sy * sy), sqrtf(tx * tx + ty * ty)), m, blend;
    hatch_scale(g, L->spacing, &m, &blend);
    if (L->noise > 0) {
      s += noise_shift(L, b, j, 0) * L->spacing * g;
      t += noise_shift(L, b, j, 0x9e3779b9u) * L->spacing * g;
    }
    s *= m;
    t *= m;
    s -= hatch_floor(s);
    t -= hatch_floor(t);
    if (!filter) {
      a[0][j] = stipple_value(s, t, blend);
      a[MAX_TAPS][j] = 1;
      continue;
    }
    float k = m * inv_n;
    for (int i = 0; i < 4; i++) {
      float ox = tap[i][0] * k, oy = tap[i][1] * k;
      a[i][j] = stipple_value(s + sx * ox + sy * oy, t + tx * ox + ty * oy, blend);
      a[MAX_TAPS + i][j] = 0.25f;
    }
    /* taps are half a footprint apart: the mean differences along x and y */
    float dx = 0.5f * (a[1][j] - a[0][j] + a[3][j] - a[2][j]);
    float dy = 0.5f * (a[2][j] - a[0][j] + a[3][j] - a[1][j]);
    a[STIPPLE_SPAN][j] = fabsf(dx) + fabsf(dy);
  }
}

/* The image, turned by the angle and repeating every `scale` texture
** units, at the footprint's level of detail: the trilinear filter's eight
** texels and weights (filtered) or the nearest texel of the nearest level
** (texture.h says why not interpolated values). Noise moves the
** coordinates by a fraction of the noise's cell. */
static void image_block(const Layer *L, Block *b, float inv_n, int filter, float a[2 * MAX_TAPS][BLOCK],
                        int *nq) {
  const ThresholdTexture *tex = L->tex;
  float k = L->inv_scale, cs = L->cs * k, sn = L->sn * k, cell = 1 / L->inv_noise_scale;
  float W = (float)tex->level[0].w, H = (float)tex->level[0].h;
  *nq = filter ? 8 : 1;
  for (int j = 0; j < b->n; j++) {
    float s = cs * b->u[j] + sn * b->v[j], t = -sn * b->u[j] + cs * b->v[j];
    float sx = cs * b->ux[j] + sn * b->vx[j], sy = cs * b->uy[j] + sn * b->vy[j];
    float tx = -sn * b->ux[j] + cs * b->vx[j], ty = -sn * b->uy[j] + cs * b->vy[j];
    if (L->noise > 0) {
      s += noise_shift(L, b, j, 0) * cell * k;
      t += noise_shift(L, b, j, 0x9e3779b9u) * cell * k;
    }
    float rx = sqrtf(sx * sx * W * W + tx * tx * H * H), ry = sqrtf(sy * sy * W * W + ty * ty * H * H);
    int k0, k1;
    float w1;
    texture_lod(tex, fmaxf(rx, ry) * inv_n, &k0, &k1, &w1);
    if (!filter) {
      a[0][j] = texture_level_nearest(tex, w1 < 0.5f ? k0 : k1, s, t);
      a[MAX_TAPS][j] = 1;
      continue;
    }
    float q[8], w[8];
    texture_level_taps(tex, k0, s, t, q, w);
    texture_level_taps(tex, k1, s, t, q + 4, w + 4);
    for (int i = 0; i < 8; i++) {
      a[i][j] = q[i];
      a[MAX_TAPS + i][j] = w[i] * (i < 4 ? 1 - w1 : w1);
    }
  }
}

/* Layer i's thresholds for the block, the first time a term reads them (a
** layer whose range no sample of the block reaches is never filled). */
static void layer_fill(const ThresholdStyle *ts, Block *b, int i) {
  if (b->filled & (1u << i)) return;
  b->filled |= 1u << i;
  const Layer *L = &ts->layers[i];
  b->nq[i] = 0;
  switch (L->kind) {
  case LAYER_HATCH: hatch_block(L, b, b->inv_n, ts->filter, b->a[i]); break;
  case LAYER_STIPPLE: stipple_block(L, b, b->inv_n, ts->filter, b->a[i], &b->nq[i]); break;
  case LAYER_IMAGE: image_block(L, b, b->inv_n, ts->filter, b->a[i], &b->nq[i]); break;
  }
}

/* ---- the step and the strength ------------------------------------------------------ */

/* A strength curve at x in [0, 1]: n values spread evenly, linear between. */
static float curve_at(const double *c, int n, float x) {
  if (n <= 0) return 1;
  if (n == 1) return (float)c[0];
  x = x > 0 ? (x < 1 ? x : 1) : 0;
  float p = x * (float)(n - 1);
  int i = (int)p;
  if (i >= n - 1) return (float)c[n - 1];
  return (float)(c[i] + (p - (float)i) * (c[i + 1] - c[i]));
}

/* The same for a layer of nq weighted thresholds a[0..nq-1] (weights
** a[MAX_TAPS..]): the weights of those met, or with span (stipple's
** a[STIPPLE_SPAN]) the part of each tap's ramp, y - q over its span from
** -1/2 to 1/2, that is met. */
static void taps_bright(const float (*a)[BLOCK], int nq, const float *span, const float *y, float lo,
                        float inv, float *bright, int j0, int j1) {
  for (int j = j0; j < j1; j++) {
    float yl = (y[j] - lo) * inv, c = 0;
    if (span && span[j] > 1e-6f) {
      float k = 1 / span[j];
      for (int q = 0; q < nq; q++) {
        float r = (yl - a[q][j]) * k + 0.5f;
        r = r > 0 ? r : 0;
        c += a[MAX_TAPS + q][j] * (r < 1 ? r : 1);
      }
    } else {
      for (int q = 0; q < nq; q++) c += a[q][j] <= yl ? a[MAX_TAPS + q][j] : 0;
    }
    c = yl > 0 ? c : 0;   /* below the range: solid */
    bright[j] *= yl < 1 ? c : 1;
  }
}

/* Multiply bright[j0..j1) by layer i's bright fraction for the band
** positions y (P(t <= y') over the footprint, y' = y in the layer's range),
** unless every sample is above its range (no ink) or below it (solid). */
static void layer_bright(const ThresholdStyle *ts, Block *b, int i, const float *y,
                         float *bright, int j0, int j1) {
  const Layer *L = &ts->layers[i];
  float lo = L->lo, inv = L->inv_span;
  /* every sample past the range (no ink), or none above its start (solid)?
  ** Lanes: a NaN is neither */
  F4 flo = f4_set(lo), finv = f4_set(inv), zero = f4_set(0), one = f4_set(1);
  M4 past = m4_all(), above = m4_none();
  int j = j0;
  for (; j + 4 <= j1; j += 4) {
    F4 yl = f4_mul(f4_sub(f4_load(y + j), flo), finv);
    M4 up = f4_lt(zero, yl);
    above = m4_or(above, up);
    past = m4_and(past, m4_andnot(f4_lt(yl, one), up));
  }
  int all_past = m4_bits(past) == 15, any_above = m4_bits(above) != 0;
  for (; j < j1; j++) {
    float yl = (y[j] - lo) * inv;
    any_above |= yl > 0;
    all_past &= yl > 0 && !(yl < 1);
  }
  if (all_past) return;   /* every sample past the range: no ink */
  if (!any_above) {       /* none above its start: solid */
    for (j = j0; j < j1; j++) bright[j] = 0;
    return;
  }
  layer_fill(ts, b, i);
  const float(*a)[BLOCK] = b->a[i];
  if (L->kind == LAYER_HATCH) hatch_coverage_run(a[0], a[1], a[2], a[3], y, lo, inv, bright, j0, j1);
  else taps_bright(a, b->nq[i], L->kind == LAYER_STIPPLE && b->nq[i] == 4 ? a[STIPPLE_SPAN] : NULL, y, lo,
                   inv, bright, j0, j1 < b->n ? j1 : b->n);   /* taps: n filled */
}

/* The smooth terms x_in[j0..j1) clamped to [0, 1] (NaN: 0) into x, and
** x n split into its whole part and fraction; bright[j] = 1. */
static void step_split(const float *x_in, int n, float *x, float *whole, float *frac, float *bright, int j0,
                       int j1) {
  F4 fn = f4_set((float)n), zero = f4_set(0), one = f4_set(1);
  int j = j0;
  for (; j + 4 <= j1; j += 4) {
    F4 xc = f4_min(f4_max(f4_load(x_in + j), zero), one), xn = f4_mul(xc, fn), w = f4_trunc(xn);
    f4_store(x + j, xc);
    f4_store(whole + j, w);
    f4_store(frac + j, f4_sub(xn, w));
    f4_store(bright + j, one);
  }
  for (; j < j1; j++) {
    float xc = x_in[j] > 0 ? (x_in[j] < 1 ? x_in[j] : 1) : 0;
    float xn = xc * (float)n, w = (float)(int)xn;
    x[j] = xc;
    whole[j] = w;
    frac[j] = xn - w;
    bright[j] = 1;
  }
}

/* T[j] = (whole[j] + bright[j]) / n, at most 1 (whole = n only at x = 1,
** where T is 1), for j in [j0, j1). */
static void step_join(const float *whole, const float *bright, float inv_n, float *T, int j0, int j1) {
  F4 finv = f4_set(inv_n), one = f4_set(1);
  int j = j0;
  for (; j + 4 <= j1; j += 4)
    f4_store(T + j, f4_min(f4_mul(f4_add(f4_load(whole + j), f4_load(bright + j)), finv), one));
  for (; j < j1; j++) {
    float t = (whole[j] + bright[j]) * inv_n;
    T[j] = t < 1 ? t : 1;
  }
}

/* T_n(x, t) of samples j0..j1 for the term (TERM_*_BIT) with t from its
** layers (eq. 4; the filtered bright fraction in place of T(frac(xn), t)),
** blended toward x by the strength, into T. */
static void textured_step(const ThresholdStyle *ts, Block *b, unsigned term, const float *x_in,
                          int n, float inv_n, float t_const, float *T, int j0, int j1) {
  float x[BLOCK], whole[BLOCK], frac[BLOCK], bright[BLOCK];
  step_split(x_in, n, x, whole, frac, bright, j0, j1);
  int any = 0;
  for (int i = 0; i < ts->nlayers; i++)
    if (ts->layers[i].terms & term) {
      layer_bright(ts, b, i, frac, bright, j0, j1);
      any = 1;
    }
  if (!any)
    for (int j = j0; j < j1; j++) bright[j] = frac[j] < t_const ? 0.0f : 1.0f;
  step_join(whole, bright, inv_n, T, j0, j1);
  if (!ts->nfacing && !ts->nlight) {   /* a constant strength */
    float s = ts->strength;
    if (s < 1)
      for (int j = j0; j < j1; j++) T[j] = x[j] + s * (T[j] - x[j]);
    return;
  }
  for (int j = j0; j < j1; j++) {
    float s = ts->strength * curve_at(ts->facing, ts->nfacing, b->nv[j]) * curve_at(ts->light, ts->nlight, x[j]);
    T[j] = x[j] + s * (T[j] - x[j]);
  }
}

/* ---- colours ---------------------------------------------------------------------- */

/* The ramp's colour at position p in [0, n - 1], linear between entries
** (a filtered step lands between two). */
static void ramp_mix(const Color *ramp, int n, float p, float rgb[3]) {
  int i = p > 0 ? (int)p : 0;
  if (i >= n - 1) i = n > 1 ? n - 2 : 0;
  float f = n > 1 ? fminf(fmaxf(p - (float)i, 0), 1) : 0;
  const Color *a = &ramp[i], *c = &ramp[n > 1 ? i + 1 : i];
  rgb[0] = a->r + f * (c->r - a->r);
  rgb[1] = a->g + f * (c->g - a->g);
  rgb[2] = a->b + f * (c->b - a->b);
}

/* Ramps for sample j of the block (sample s): the light-weighted diffuse
** (and specular) values, thresholded with as many bands as the ramp has
** steps, pick the colour. */
static void ramp_sample(const ShadeSample *s, const RenderStyle *st, Block *b, int j,
                        float rgb[3]) {
  const ShadeToon *t = &st->src->shade.toon;
  const ThresholdStyle *ts = st->layers;
  float d[BLOCK], sp[BLOCK], T[BLOCK];
  d[j] = sp[j] = 0;
  for (int i = 0; i < s->frame->nlights; i++) {
    float l[3], col[3];
    shade_light(s->frame, i, s->p, l, col);
    float w = (col[0] + col[1] + col[2]) / 3;
    if (s->frame->lights[i].shadow && s->obj->wfnrm)   /* the share of it a shadow lets through */
      w *= shade_diffuse(s->n, l) > 0 ? shade_reach(s->frame, i, s->obj, s->face, s->p) : 0;
    d[j] += shade_diffuse(s->n, l) * w;
    if (st->specular > 0) sp[j] += shade_specular(s->n, l, s->v, st->shininess) * w;
  }
  int n = t->nramp - 1;
  T[j] = 0;
  if (n > 0) textured_step(ts, b, TERM_DIFFUSE_BIT, d, n, 1.0f / n, st->threshold, T, j, j + 1);
  ramp_mix(t->ramp, t->nramp, T[j] * n, rgb);
  if (st->specular <= 0) return;
  int m = t->nspecular_ramp > 0 ? t->nspecular_ramp - 1 : st->spec_n;
  T[j] = 0;
  if (m > 0) textured_step(ts, b, TERM_SPECULAR_BIT, sp, m, 1.0f / m, st->spec_threshold, T, j, j + 1);
  if (t->nspecular_ramp > 0) {
    float c[3];
    ramp_mix(t->specular_ramp, t->nspecular_ramp, T[j] * m, c);
    rgb[0] += c[0]; rgb[1] += c[1]; rgb[2] += c[2];
  } else {
    float k = st->specular * T[j];
    rgb[0] += k; rgb[1] += k; rgb[2] += k;
  }
}

/* x^s for x in [2^-12, 1] and the power s >= 0 as exp2(s log2 x), four
** lanes at a time: log2 of the mantissa by the atanh series to z^9 (z =
** (m - 1) / (m + 1) < 1/3: within 2e-6), 2^f by its Taylor series to f^7
** (within 2e-6 relative), so within 1e-4 of powf relative for s up to 100
** (1.3e-3 at s = 1000). A smooth term about to be thresholded: that close
** is as good as powf, at a fraction of its cost. */
static inline F4 pow_unit4(F4 x, F4 s) {
  F4 one = f4_set(1), e = f4_exponent(x);
  F4 m = f4_or_bits(f4_and_bits(x, 0x007fffffu), 0x3f800000u);   /* the mantissa in [1, 2) */
  F4 z = f4_div(f4_sub(m, one), f4_add(m, one)), z2 = f4_mul(z, z);
  F4 poly = f4_add(f4_set(1.0f / 7), f4_mul(z2, f4_set(1.0f / 9)));
  poly = f4_add(f4_set(0.2f), f4_mul(z2, poly));
  poly = f4_add(f4_set(1.0f / 3), f4_mul(z2, poly));
  poly = f4_add(one, f4_mul(z2, poly));
  F4 lg = f4_add(e, f4_mul(f4_mul(f4_set(2.8853900817779268f), z), poly));
  F4 y = f4_max(f4_mul(s, lg), f4_set(-126));   /* <= 0 */
  F4 i = f4_floor(y), f = f4_mul(f4_sub(y, i), f4_set(0.69314718f));
  static const float c[7] = {1.0f / 5040, 1.0f / 720, 1.0f / 120, 1.0f / 24, 1.0f / 6, 0.5f, 1};
  F4 p = f4_set(c[0]);
  for (int k = 1; k < 7; k++) p = f4_add(f4_set(c[k]), f4_mul(f, p));
  p = f4_add(one, f4_mul(f, p));
  return f4_mul(p, f4_pow2i(i));   /* p 2^i */
}

/* The smooth specular term of samples k0..k0+n-1 of r (n a multiple of
** 4) lit from l*: f_s = (n.h / |h|)^shininess where n.l > 0 and it
** reaches 2^-12, else 0 (a term under 2^-12, thresholded or not, moves no
** colour by a tenth of an 8-bit step). The lane groups where it may not
** be 0 lie in [*j0, *j1) (multiples of 4; empty: none). */
static void specular_block(const ShadeRow *r, const RenderStyle *st, int k0, int n, const float *lx,
                           const float *ly, const float *lz, const float *nl, float *fs, int *j0,
                           int *j1) {
  const float *nx = r->nx + k0, *ny = r->ny + k0, *nz = r->nz + k0;
  const float *vx = r->vx + k0, *vy = r->vy + k0, *vz = r->vz + k0;
  F4 cut2 = f4_set(st->layers->spec_cut2), zero = f4_set(0);
  *j0 = n;
  *j1 = 0;
  for (int j = 0; j < n; j += 4) {
    F4 hx = f4_add(f4_load(lx + j), f4_load(vx + j));
    F4 hy = f4_add(f4_load(ly + j), f4_load(vy + j));
    F4 hz = f4_add(f4_load(lz + j), f4_load(vz + j));
    F4 nh = f4_add(f4_add(f4_mul(f4_load(nx + j), hx), f4_mul(f4_load(ny + j), hy)), f4_mul(f4_load(nz + j), hz));
    F4 hh = f4_add(f4_add(f4_mul(hx, hx), f4_mul(hy, hy)), f4_mul(hz, hz));
    /* lit: !(n.l <= 0) & !(n.h <= 0) & !((n.h)^2 <= cut^2 |h|^2) */
    M4 dark = m4_or(m4_or(f4_le(f4_load(nl + j), zero), f4_le(nh, zero)), f4_le(f4_mul(nh, nh), f4_mul(cut2, hh)));
    M4 lit = m4_andnot(dark, m4_all());
    f4_store(fs + j, f4_keep(lit, f4_div(nh, f4_sqrt(hh))));
    if (m4_bits(lit)) {
      if (*j0 > j) *j0 = j;
      *j1 = j + 4;
    }
  }
  F4 s = f4_set(st->shininess);
  for (int j = *j0; j < *j1; j += 4) {
    F4 x = f4_load(fs + j);
    f4_store(fs + j, f4_keep(f4_lt(zero, x), pow_unit4(x, s)));
  }
  if (*j0 > *j1) *j0 = *j1 = 0;
}

/* Unit vectors toward light lt from samples k0..k0+n-1 of r, and the
** falloff there (shade_point_light, a block at a time). */
static void light_block(const RenderLight *lt, const ShadeRow *r, int k0, int n, float *lx, float *ly,
                        float *lz, float *fall) {
  if (lt->directional) {
    for (int j = 0; j < n; j++) {
      lx[j] = lt->dir[0]; ly[j] = lt->dir[1]; lz[j] = lt->dir[2]; fall[j] = 1;
    }
    return;
  }
  const float *px = r->px + k0, *py = r->py + k0, *pz = r->pz + k0;
  for (int j = 0; j < n; j++) fall[j] = shade_point_light(lt, px[j], py[j], pz[j], &lx[j], &ly[j], &lz[j]);
  if (lt->spot)   /* its own loop: a point light's stays as it was */
    for (int j = 0; j < n; j++) fall[j] *= shade_spot(lt, lx[j], ly[j], lz[j]);
}

/* The bands for the block's samples (samples k0.. of r): each light's
** textured steps on the diffuse and specular terms, summed per channel. */
static void bands_block(const ShadeRow *r, const RenderObject *o, Block *b, int k0, float *R,
                        float *G, float *B) {
  const RenderStyle *st = o->style;
  const ThresholdStyle *ts = st->layers;
  const float *nx = r->nx + k0, *ny = r->ny + k0, *nz = r->nz + k0;
  int n = b->n4;   /* the padding lanes too: whole SIMD groups */
  float lx[BLOCK], ly[BLOCK], lz[BLOCK], fall[BLOCK], nl[BLOCK], td[BLOCK], fs[BLOCK], tsp[BLOCK];
  float vis[BLOCK], bR[BLOCK], bG[BLOCK], bB[BLOCK];   /* the base colour, per sample */
  shade_base_block(r, o, k0, b->n, bR, bG, bB);
  for (int j = b->n; j < n; j++) { bR[j] = bR[b->n - 1]; bG[j] = bG[b->n - 1]; bB[j] = bB[b->n - 1]; }
  for (int j = 0; j < n; j++) {
    R[j] = bR[j] * st->ambient; G[j] = bG[j] * st->ambient; B[j] = bB[j] * st->ambient;
  }
  for (int i = 0; i < r->frame->nlights; i++) {
    const RenderLight *lt = &r->frame->lights[i];
    int shadowed = lt->shadow && o->wfnrm;
    if (lt->directional && !(st->specular > 0) && !shadowed) {   /* a sun and no highlight: n.l alone */
      float dx = lt->dir[0], dy = lt->dir[1], dz = lt->dir[2];
      for (int j = 0; j < n; j++) {
        float d = nx[j] * dx + ny[j] * dy + nz[j] * dz;
        td[j] = d > 0 ? d : 0;
        fall[j] = 1;
      }
    } else {
      light_block(lt, r, k0, n, lx, ly, lz, fall);
      for (int j = 0; j < n; j++) {
        float d = nx[j] * lx[j] + ny[j] * ly[j] + nz[j] * lz[j];
        nl[j] = d;
        td[j] = d > 0 ? d : 0;
      }
    }
    if (shadowed) {   /* the terms of the light that arrives, before their steps */
      const int32_t *face = r->face + k0;
      int m = n < b->n ? n : b->n;   /* the padding lanes repeat the last sample */
      shadow_run(lt->shadow, o, m, face, r->px + k0, r->py + k0, r->pz + k0, nl, vis);
      for (int j = m; j < n; j++) vis[j] = m > 0 ? vis[m - 1] : 0;
      for (int j = 0; j < n; j++) td[j] *= vis[j];
    }
    textured_step(ts, b, TERM_DIFFUSE_BIT, td, st->bands_n, st->inv_bands_n, st->threshold, td, 0, n);
    int s0 = 0, s1 = 0;   /* the samples a highlight may reach, in whole SIMD groups */
    if (st->specular > 0) specular_block(r, st, k0, n, lx, ly, lz, nl, fs, &s0, &s1);
    if (shadowed && st->specular > 0)
      for (int j = s0; j < s1; j++) fs[j] *= vis[j];
    for (int j = 0; j < n; j++) tsp[j] = 0;
    if (s0 < s1) textured_step(ts, b, TERM_SPECULAR_BIT, fs, st->spec_n, st->inv_spec_n, st->spec_threshold, tsp, s0, s1);
    for (int j = 0; j < n; j++) {
      float spec = st->specular * tsp[j];
      float c0 = lt->color[0] * fall[j], c1 = lt->color[1] * fall[j], c2 = lt->color[2] * fall[j];
      R[j] += (bR[j] * td[j] + spec) * c0;
      G[j] += (bG[j] * td[j] + spec) * c1;
      B[j] += (bB[j] * td[j] + spec) * c2;
    }
  }
}

/* n samples' colours from the planes R, G, B into out, sample j at
** out[j * stride + 0..2]; rows of three (stride 3) four samples at a time. */
static void block_out(const float *R, const float *G, const float *B, int n, float *out, int stride) {
  int j = 0;
  if (stride == 3)
    for (; j + 4 <= n; j += 4) f4_store_rgb(out + 3 * j, f4_load(R + j), f4_load(G + j), f4_load(B + j));
  for (out += (size_t)j * stride; j < n; j++, out += stride) {
    out[0] = R[j]; out[1] = G[j]; out[2] = B[j];
  }
}

/* ---- spans --------------------------------------------------------------------------- */

void shade_threshold_span(const ShadeRow *r, const RenderObject *o, int k0, int k1, float *rgb,
                          int stride) {
  const RenderFrame *f = r->frame;
  const RenderStyle *st = o->style;
  const TexView *view = &st->layers->view;
  float inv_n = 1.0f / (float)f->samples;   /* a sample's share of a pixel side */
  int ramps = st->src->shade.toon.nramp > 0;
  Block b;
  float R[BLOCK], G[BLOCK], B[BLOCK];
  for (int k = k0; k < k1; k += BLOCK) {
    b.n = k1 - k < BLOCK ? k1 - k : BLOCK;
    block_coords(&b, r, o, view, k, b.n);
    b.filled = 0;
    b.inv_n = inv_n;
    if (ramps) {   /* one sample at a time */
      for (int j = 0; j < b.n4; j++) {
        ShadeSample s;
        float c[3];
        shade_row_sample(r, o, k + (j < b.n ? j : b.n - 1), &s);   /* the padding: the last again */
        ramp_sample(&s, st, &b, j < b.n ? j : b.n - 1, c);
        R[j] = c[0]; G[j] = c[1]; B[j] = c[2];
      }
    } else {
      bands_block(r, o, &b, k, R, G, B);
    }
    if (st->edge > 0)   /* edge = max(0, n.v) below the cutoff: the edge colour */
      for (int j = 0; j < b.n4; j += 4) {
        M4 edge = f4_lt(f4_load(b.nv + j), f4_set(st->edge));
        f4_store(R + j, f4_select(edge, f4_set(st->edge_color[0]), f4_load(R + j)));
        f4_store(G + j, f4_select(edge, f4_set(st->edge_color[1]), f4_load(G + j)));
        f4_store(B + j, f4_select(edge, f4_set(st->edge_color[2]), f4_load(B + j)));
      }
    block_out(R, G, B, b.n, rgb + (size_t)k * stride, stride);
  }
}

/* One sample as a span of one. */
void shade_threshold(const ShadeSample *s, float rgb[3]) {
  shade_span_one(s, shade_threshold_span, rgb);
}
