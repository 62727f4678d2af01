/*
** Strokes along polylines (001 §2.1.6-2.1.7): polylines scaled from the
** reference image to the output, filtered by min_length, then drawn as
**   plain   constant-width antialiased lines with round joins and caps;
**   ribbon  polygon strips: a rib at each vertex perpendicular to
**           v[i+1] - v[i-1] (at an end, to its one segment), scaled at
**           corners by the miter factor 1 / (r . n) capped by miter_limit,
**           with a stroke texture mapped along the strip (u: arc length,
**           v: across, 0 on the right side, 1 on the left);
**   brush   the Chinese brush of 003 (brush.h): the polyline's points are
**           its control points; the stroke's points are the brush's steps
**           and its outline the width profile (for the SVG).
** Textures: "ink" (the default, procedural: ink density drifting along the
** stroke, fibre streaks across it, softened ends), "solid", or an image file
** (its alpha where it has one, else 1 - luminance, is the ink; it repeats
** along the stroke at the stroke's width). Every random choice comes from
** rng_seed_key(LINE_STROKE_SEED, object id, stroke number in the object).
** Strokes are composited in order over the target; the work is split in
** row bands, so the image does not depend on the number of workers.
*/
#ifndef render_stroke_h
#define render_stroke_h

#include <stddef.h>

#include "../io/image.h"
#include "brush.h"
#include "link.h"

#define LINE_STROKE_SEED 0x53554D49ULL   /* "SUMI" */
/* Length of a polyline kept whatever min_length says: a dot would not read
** as a stroke. */
#define STROKE_MIN_PIXELS 0.5

typedef struct Stroke {
  int obj;                 /* index into the LineObject array */
  int object_id;           /* LineObject.id */
  StrokeKind kind;
  int npts;
  float *pts;              /* x, y pairs, output pixels */
  float *left, *right;     /* ribbon: rib ends (x, y pairs); brush: its outline; NULL for plain */
  float *s;                /* arc length at each point */
  int closed;              /* last point = first: ribs wrap around */
  float width;             /* output pixels */
  Color color;             /* linear */
  float opacity;
  const Image *texture;    /* image texture, NULL = procedural */
  int solid;               /* texture "solid" */
  float phase[4];          /* random phases of the procedural texture */
  float box[4];            /* x0, y0, x1, y1 covered (output pixels) */
  BrushPath *brush;        /* brush: the brush's steps (pts are their centres), else NULL */
} Stroke;

typedef struct StrokeList {
  int n, cap;
  Stroke *s;
  int ntex, cap_tex;
  Image **tex;             /* image textures, owned */
  char **tex_name;         /* their file names, owned */
  int nbrushes, cap_brushes;
  BrushBristles **brushes; /* the bristles of each brush size brush strokes use, owned */
} StrokeList;

/* Strokes from polys (reference pixels; sx, sy scale them to the output)
** for objs. Image textures are read with image_read; a texture that
** cannot be read fails the build with a reason in err (returns 0, *out
** NULL). On success *out is a new list (stroke_list_free). */
int stroke_build(StrokeList **out, const LinePolys *polys, const LineObject *objs, double sx,
                 double sy, char *err, size_t errlen);
void stroke_list_free(StrokeList *sl);

/* Composite every stroke over target (3 or 4 channels, linear). */
void stroke_render(const StrokeList *sl, Image *target, int threads);
/* The same over a target that is a window of a larger frame, its first
** pixel at the frame's (ox, oy) (the strokes are in the frame's pixels):
** each of its pixels gets the bits the whole frame's has. */
void stroke_render_at(const StrokeList *sl, Image *target, int ox, int oy, int threads);

/* The procedural ink texture at arc length s (of length len) and across
** position v for a stroke of width w: ink in [0, 1]. Exposed for tests. */
float stroke_ink(const float phase[4], float s, float len, float v, float w);

#endif
