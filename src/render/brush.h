/*
** The Chinese brush (Yeh, 003 ch. 3.4-4.6) that `stroke brush` paints a
** polyline with:
**
**   width     at control point i of ncp, the half-width
**             min(max_width, width_step * min(i, ncp - 1 - i)): thin at both
**             ends (our symmetric reading of ch. 3.4's equations);
**   smoothing positions and widths follow a centripetal Catmull-Rom spline
**             through the control points (knots spaced by the square roots of
**             their distances: no loops where short edges meet long ones;
**             ends extended by reflection; a turn over 30 degrees is a
**             corner, its edges kept straight), resampled a pixel apart along
**             the dominant axis of the way: the brush's steps;
**   pressure  P at a control point grows from `pressure` on a straight run
**             to 1 at a turn of 90 degrees or more (the included angle of
**             its two edges), linear between control points (ch. 4.6.2);
**   brush     an ellipse, long semi-axis B = the half-width across the
**             stroke, short semi-axis A = aspect * B along it, holding
**             sectors x bristles bristles at polar positions (r, theta) =
**             (k / bristles, j * 360 / sectors) (ch. 4.3); turned to the
**             curve's tangent at each control point, the angle interpolated
**             between them (ch. 4.4-4.5);
**   weight    W_p of formula 6: with u = |b'_y - B| / 2B (0 on the brush's
**             right side, 1 on its left), W_p = 1 - u (1 - P) / P when u <
**             P, else 0: a light brush touches with its right side only;
**   dry brush each bristle keeps a gap counter (ch. 4.6.1): at zero, a draw
**             starts a gap of 0..dry_max_gap steps with probability
**             dry_probability; else it counts down; a bristle deposits only
**             at a step its counter is zero. Draws come from the stroke's
**             seeded stream.
** Each deposit is ink_load * W_p, antialiased as Wu draws a line (the
** nearest pixel along the step's major axis, the two around the bristle
** across it, by distance) and accumulated as a = a + d (1 - a).
*/
#ifndef render_brush_h
#define render_brush_h

#include <stdint.h>

#include "../base/rng.h"
#include "../scene/scene.h"

/* The bristles of a brush in the unit disc: polar (k / bristles, j * 360 /
** sectors), sorted by across position, right side first (so those a
** pressure lets touch are a prefix). */
typedef struct BrushBristles {
  int sectors, bristles, n;
  float *ux, *uy;        /* along, across (+1 on the right as seen) */
} BrushBristles;

void brush_bristles_make(BrushBristles *bb, int sectors, int bristles);
void brush_bristles_free(BrushBristles *bb);

/* A brush stroke ready to draw: the brush at each step. */
typedef struct BrushPath {
  int nsteps;
  float *x, *y;          /* centre, output pixels */
  float *s;              /* arc length */
  float *b;              /* long semi-axis B (the half-width) */
  float *ang;            /* direction of travel, radians (y down) */
  float *press;          /* pressure P */
  const BrushBristles *br;   /* not owned */
  uint32_t *dry;         /* nsteps x words bits: bit k set where bristle k deposits at step i */
  int words;             /* 32-bit words a step */
  float aspect, ink;
} BrushPath;

/* The half-width at control point i of ncp (ch. 3.4, as read above). */
double brush_width_at(int i, int ncp, double width_step, double max_width);

/* The pressure at a turn whose edges meet at included angle `included`
** degrees (180 = straight on) for base pressure p. */
double brush_pressure_at(double included, double p);

/* W_p (formula 6) of a bristle at unit across position uy for pressure P. */
float brush_weight(float uy, float P);

/* The brush path along control points ctrl (n x, y pairs, output
** pixels) for brush b with bristles br (b's sectors and bristles, kept by
** the caller while bp lives); dry-brush draws come from r. Returns 0
** (nothing made) when the points span no length. Free with
** brush_path_free. */
int brush_path_build(BrushPath *bp, const float *ctrl, int n, const SceneBrush *b,
                     const BrushBristles *br, Rng *r);
void brush_path_free(BrushPath *bp);

/* Does bristle k deposit at step i? */
static inline int brush_deposits(const BrushPath *bp, int i, int k) {
  return (bp->dry[(size_t)i * bp->words + (k >> 5)] >> (k & 31)) & 1;
}

/* The outline of bp's width profile: left and right ends of each step's
** rib (x, y pairs, nsteps each), left as seen on the screen. */
void brush_outline(const BrushPath *bp, float *left, float *right);

/* Accumulate bp's ink into rows [y0, y1) and columns [x0, x0 + w) of cov
** (pixel (x, y) at cov[(y - y0) * w + x - x0]); lo[r] and hi[r] widen to
** the columns row y0 + r was written in. */
void brush_cover(const BrushPath *bp, float *cov, int x0, int w, int y0, int y1, int *lo, int *hi);

#endif
