/*
** Chinese ink interiors (Yeh, thesis 003, ch. 5.2), in three files:
**   shade_ink.c    the high-contrast Gouraud image (a grey per vertex from
**                  strong diffuse and specular terms and a weak ambient one,
**                  with the style's own lights) and its quantisation to a
**                  few tones: [0, 0.4) -> 0.4, [0.4, 0.6) -> 0.6,
**                  [0.6, 0.9) -> 0.9, [0.9, 1] -> 1; ink = 255 (1 - tone)
**   ink_diffuse.c  the ink canvas: ink and water per pixel; ink runs from a
**                  darker level to a lighter one under the thesis's three
**                  rules, a bounded number of passes; then the box filter
**   canvas.c       runs them over the whole frame after the tile pass and
**                  lays the ink on the paper (paper.h)
** Ink objects draw nothing in the tile pass (their samples are left
** transparent); the canvas paints them from their samples, so the diffusion
** sees the whole frame at once, whatever the tiles and threads.
*/
#ifndef render_ink_h
#define render_ink_h

#include <stdint.h>
#include <string.h>

#include "render.h"

/* A style's ink parameters, resolved for a frame. Levels are labels: 0 is
** the paper level (the lightest tone, ink 0 when it is 1.0), 1 the light
** level, ... ntones - 1 the darkest. */
typedef struct InkStyle {
  float ambient, diffuse, specular, shininess;
  int ntones;                      /* ranges and tones: nlevels + 1 */
  float levels[INK_MAX_TONES - 1]; /* thresholds, rising */
  float tones[INK_MAX_TONES];      /* the tone of range i, rising */
  float ink[INK_MAX_TONES];        /* ink of label k: 255 (1 - tones[ntones - 1 - k]) */
  float ink_loss;                  /* of the difference a transfer loses, before roughness */
  float water;                     /* each ink pixel's water at the start */
  float paper_cost;                /* onto the paper level, a hop costs this of water and loss */
  float ink_threshold, water_threshold, roughness;
  int passes, box, stage;          /* stage: InkStage */
  float color[3];                  /* the ink, display values */
  int nlights;                     /* lights of the Gouraud image; 0 = all of the frame's */
  int *lights;                     /* indices into RenderFrame.lights */
} InkStyle;

/* What each strength sets (ch. 6: small, medium and large diffusion). */
typedef struct InkStrengthRow {
  const char *name;
  float ink_loss;                  /* per hop, of the ink difference */
  float water;                     /* hops of water onto dry paper */
  int passes;                      /* the bound on passes */
} InkStrengthRow;
extern const InkStrengthRow ink_strengths[3];   /* ORDER InkStrength */

/* The water cost and loss onto the paper level relative to other hops:
** the thesis's strong diffusion from the light level onto paper. */
#define INK_PAPER_COST 0.5f

/* ---- shade_ink.c -------------------------------------------------------- */

/* Resolve the ink parameters of every shade ink style of f (RenderStyle.ink,
** freed by shade_ink_free), with the lights the evaluator resolved.
** Returns 0 after a diagnostic (a light index the frame lacks). */
int shade_ink_prepare(RenderFrame *f);
void shade_ink_free(RenderFrame *f);

/* Resolve one style's numbers (no lights) into k. */
void ink_style_init(InkStyle *k, const SceneShade *sh);

/* The Gouraud grey of every vertex of o (o->vink), in [0, 1]: ambient +
** sum over the style's lights of luminance (diffuse max(0, n.l) +
** specular max(0, n.h)^shininess), with the normal turned toward the
** viewer; read as a display grey, as the thesis's frame buffer was. */
void shade_ink_vertex_values(const RenderFrame *f, RenderObject *o);

/* The Gouraud grey of ink object o at a sample of triangle face,
** barycentrics b: its vertex greys interpolated; with shadows, each
** light's part times the share of it reaching the sample's point, and
** the sum clamped to [0, 1]. */
float shade_ink_grey(const RenderFrame *f, const RenderObject *o, int face, const float b[2]);

/* The greys of face's corners when o's grey there is their interpolation
** alone (no light casts shadows on it): into v, returning 1; else 0, and
** shade_ink_grey is the way. */
int shade_ink_corners(const RenderFrame *f, const RenderObject *o, int face, float v[3]);

/* The grey at barycentrics b from corner greys v: shade_ink_grey's own
** interpolation, to the bit. */
static inline float shade_ink_lerp(const float v[3], const float b[2]) {
  float b1 = b[0], b2 = b[1], b0 = 1 - b1 - b2;
  return b0 * v[0] + b1 * v[1] + b2 * v[2];
}

/* The range (0 darkest .. ntones - 1) grey value v falls in: how many
** thresholds it reaches (a NaN reaches all: the lightest, no ink). */
static inline int ink_range(const InkStyle *k, float v) {
  if (k->ntones == 4)   /* the thesis's four tones */
    return !(v < k->levels[0]) + !(v < k->levels[1]) + !(v < k->levels[2]);
  int i = 0;
  for (int t = 0; t < k->ntones - 1; t++) i += !(v < k->levels[t]);
  return i;
}

/* The quantised tone of v, and its level label. */
static inline float ink_quantise(const InkStyle *k, float v) { return k->tones[ink_range(k, v)]; }
static inline int ink_label(const InkStyle *k, float v) { return k->ntones - 1 - ink_range(k, v); }

/* The rows of ink planes are mostly zeros around the ink: where it
** begins and ends, eight values a step (their bits but the signs, so -0
** is zero too). */
static inline int ink_zeros8(const float *v) {
  uint64_t b[4];
  memcpy(b, v, sizeof b);
  return ((b[0] | b[1] | b[2] | b[3]) & 0x7fffffff7fffffffull) == 0;
}

/* The first of v[a..e) that is not zero; e if none is. */
static inline int ink_first_nonzero(const float *v, int a, int e) {
  while (a + 8 <= e && ink_zeros8(v + a)) a += 8;
  while (a < e && v[a] == 0) a++;
  return a;
}

/* One past the last of v[a..e) that is not zero; a if none is. */
static inline int ink_nonzero_end(const float *v, int a, int e) {
  while (e - 8 >= a && ink_zeros8(v + e - 8)) e -= 8;
  while (e > a && v[e - 1] == 0) e--;
  return e;
}

/* ---- ink_diffuse.c ---------------------------------------------------------- */

#define INK_OFF 255         /* a level: not on the canvas (another object covers it) */
#define INK_NO_STYLE 0xffff /* a style: bare paper */

/* The ink canvas: per pixel, row-major. A frame's canvas starts as bare
** paper (zeros, ink_canvas_init_lean) and its writer writes only its ink
** pixels. */
typedef struct InkCanvas {
  int width, height;
  int ox, oy;               /* the frame pixel of the canvas's first (a tile's window: the
                               paper, the noise and each pixel's random value follow it) */
  float *ink;               /* 0..255 */
  float *water;             /* NULL: a pixel's water at the start is its style's at an ink level,
                               none at the paper level (and the diffusion keeps what changes) */
  uint8_t *level;           /* label, or INK_OFF */
  uint16_t *style;          /* index into styles (whose ink it holds), or INK_NO_STYLE; NULL
                               with one style (every pixel's is it; bare paper behaves as its
                               paper level) */
  const InkStyle *styles;
  int nstyles;
  /* the paper's absorbency (a tile that repeats; NULL: 1 everywhere) and
  ** the seed of the resistance noise */
  const float *absorb;
  int absorb_w, absorb_h;
  uint32_t seed;
  struct InkCells *cells;   /* during ink_diffuse: each pixel's state beyond the planes */
  const struct InkResist *resist;   /* during ink_diffuse: the resistance noise's lattice */
  size_t *absorb_row;       /* during ink_diffuse, with absorb: per row its texel row's first */
  int *absorb_col;          /* and per column its texel column (no divisions per lookup) */
  const InkStyle *one;      /* during ink_diffuse: the only style, when there is one and it
                               diffuses (the style plane need not be read); else NULL */
} InkCanvas;

/* A pixel that takes ink can pass it on INK_DELAY x its resistance passes
** later (at least 1, at most INK_MAX_DELAY): the water has to soak through
** the paper first. Uneven delays make the fronts irregular. */
#define INK_DELAY 2.0f
#define INK_MAX_DELAY 6

/* Allocate w x h planes: every pixel bare paper (level 0, no ink, no water). */
void ink_canvas_init(InkCanvas *c, int w, int h, const InkStyle *styles, int nstyles);
/* The same without a water plane, and without a style plane with one
** style: a frame's canvas, whose writer writes its ink pixels only. */
void ink_canvas_init_lean(InkCanvas *c, int w, int h, const InkStyle *styles, int nstyles);
void ink_canvas_free(InkCanvas *c);

/* Give every ink pixel (a style) its style's water, bare paper none (a
** canvas with planes only). */
void ink_canvas_wet(InkCanvas *c);

/* What ink_diffuse did. */
typedef struct InkDiffuseStats { int passes; long long transfers; } InkDiffuseStats;

/* Run up to max_passes passes of diffusion (max_passes < 0: the styles'
** bound; never more than INK_MAX_PASSES). In a pass ink moves at most one
** pixel: every pixel takes the best offer of its four neighbours, all from
** the state before the pass (so the result does not depend on the order
** pixels are visited). Neighbour q may give to p when q's water exceeds
** its style's water threshold (rule 1), q's level is darker than p's
** (rule 2; onto the paper level only from the light level), q's ink
** exceeds p's by more than the ink threshold (rule 3), and q's water has
** soaked through (INK_DELAY). p takes from the darkest of those (level,
** then ink, then water): q's level and style, and ink a little less than
** q's: its own plus (1 - loss) of the difference; its water becomes the
** greater of its own and q's less a hop's cost. A pixel never loses ink or
** water; the giver keeps all of its. Loss, cost and delay scale with the
** paper's resistance at p (roughness noise over absorbency); onto paper the
** loss and the cost are INK_PAPER_COST of that. */
void ink_diffuse(InkCanvas *c, int max_passes, InkDiffuseStats *st);

/* The same by its definition: every pixel looks at its neighbours in
** every pass (slow). ink_diffuse looks only where something can change and
** must give the same; the tests hold it to that. */
void ink_diffuse_every_pixel(InkCanvas *c, int max_passes, InkDiffuseStats *st);

/* A side x side box filter (side odd) of nplanes planes of w x h floats,
** in place, averaged over the pixels where weight is nonzero (NULL: every
** pixel; the image's edges clip the box either way); where no pixel of a
** box has weight, the planes become 0. */
void ink_box_filter(float **planes, int nplanes, const uint8_t *weight, int w, int h, int side);
/* The same for the pixels of rectangle [x0, x1) x [y0, y1) only (their
** boxes still read the pixels around it); the others are left as they are.
** Every pixel whose box holds ink must lie in it. */
void ink_box_filter_rect(float **planes, int nplanes, const uint8_t *weight, int w, int h, int side,
                         int x0, int y0, int x1, int y1);

#endif
