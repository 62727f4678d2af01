/*
** The SVG writer's origami (svg.h): each block's faces as their polygons,
** back to front in the order of the overlap relation (for this viewer),
** each filled with a linear gradient fitted to the colours the frame
** shows on it (Mitani's illustration brightness runs across a face) and
** stroked with the block's Sobel lines where it draws them, then the
** parts of faces the gradient misses (the shaded mode's occlusion, a
** paper texture) as traced layers (svg_trace.h). Faces the relation
** orders in a cycle (twist folds) are clipped to the pixels they show.
** Where a mesh stands in front of the paper, the origami is clipped to
** leave it out.
*/
#ifndef render_svg_origami_h
#define render_svg_origami_h

#include <stdio.h>

#include "../scene/scene.h"
#include "svg_trace.h"

/* Write every origami block of s seen through world_to_clip (fr's size)
** to f, as <g> elements; the definitions they use (gradients, clip paths)
** go inline. Returns 1, or 0 when a block cannot be built (diagnostics
** reported). */
int svg_write_origami(FILE *f, const SvgFrame *fr, const Scene *s, const Mat4 *world_to_clip);

#endif
