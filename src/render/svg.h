/*
** `-o out.svg`: the line stage's strokes as vector paths, for print and
** plotters. The document is the output size in pixels (1 unit = 1 pixel):
**   - a rectangle of the background colour (left out when transparent);
**   - the visible region of each object filled with its fill colour: one
**     path per object, the exact pixel outline of the region the object
**     wins in a depth raster at the output resolution (even-odd rule), so
**     regions never overlap and need no drawing order;
**   - the strokes, in the order they are composited into the PNG: plain
**     strokes as stroked paths (round caps and joins, stroke-width = the
**     width), ribbons as filled outlines (left rib ends forward, right rib
**     ends back). Stroke textures are not carried over.
** Colours are written as sRGB hex. Numbers have two decimals, so the text
** is stable for snapshot tests. Written to a temporary file and renamed.
*/
#ifndef render_svg_h
#define render_svg_h

#include <stddef.h>

#include "lines.h"

/* Write the SVG for objs seen by cam (its width x height) to path.
** Returns 1, or 0 with a reason naming the file in err. */
int svg_write(const char *path, const LineObject *objs, int nobj, const Camera *cam, Color background,
              const StrokeList *sl, int threads, char *err, size_t errlen);

/* The same for a prepared frame (its objects, camera and background). */
int svg_write_frame(const char *path, const RenderFrame *f, const StrokeList *sl, int threads,
                    char *err, size_t errlen);

/* `sumi render scene.npr -o out.svg`: prepare the frame of s (sizes and
** threads as in o), run the line stage, write path. Returns 0 on success,
** 1 when the scene cannot be rendered (diagnostics reported) or the file
** cannot be written (a "sumi: ..." line on standard error). */
int svg_render_scene(const Scene *s, const RenderOptions *o, const char *path);

#endif
