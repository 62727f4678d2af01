/*
** `-o out.svg`: the frame as vector paths, for print and plotters. The
** document is the output size in pixels (1 unit = 1 pixel), painted in
** this order:
**   - a rectangle of the background colour (left out when transparent);
**   - the mesh objects' regions (svg_trace.h): the frame is rendered as for
**     a PNG, and each object's pixels are split into the colour classes
**     they cluster into (toon bands, specular spots, a smooth shading's
**     posterised steps), each class traced by potrace into smooth closed
**     curves; objects far to near, classes dark to light, each layer
**     reaching a little under the later ones so nothing shows between;
**   - the origami blocks (svg_origami.h): face polygons back to front in
**     the overlap relation's order, with gradient fills and their lines;
**   - the strokes, in the order they are composited into the PNG: plain
**     strokes as stroked paths (round caps and joins, stroke-width = the
**     width), ribbons as filled outlines (left rib ends forward, right rib
**     ends back). Stroke textures are not carried over.
** Colours are written as sRGB hex. Numbers have two decimals. Written to
** a temporary file and renamed.
*/
#ifndef render_svg_h
#define render_svg_h

#include "render.h"

/* `sumi render scene.npr -o out.svg`: render s (sizes and threads as in
** o), trace the frame, write path. Returns 0 on success, 1 when the scene
** cannot be rendered (diagnostics reported) or the file cannot be written
** (a "sumi: ..." line on standard error). */
int svg_render_scene(const Scene *s, const RenderOptions *o, const char *path);

#endif
