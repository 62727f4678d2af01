/*
** The object-space line pipeline (Brown & Arandjelovic, 001 §2.1), run by
** render_scene after shading:
**
**   important edges (edges.c) -> reference image (edgeref.c)
**     -> segments (trace.c) -> polylines (link.c) -> strokes (stroke.c)
**
** or, for the objects whose lines ask for it (`visibility endpoints`, the
** default of brush strokes), the front end of 003 (silhouette.c):
**
**   important edges -> their visibility tested (edgeref.c) -> endpoint
**     culling -> 2-pixel linking -> strokes (stroke.c; brush strokes in brush.c)
**
** Every object occludes, and so does every origami sheet (its folded
** faces, from either side); objects whose style has lines { } draw strokes.
** One reference image serves all objects, at the largest ref_scale any of
** them asks for; the other lines parameters are per object.
*/
#ifndef render_lines_h
#define render_lines_h

#include <stddef.h>
#include <stdio.h>

#include "camera.h"
#include "edges.h"
#include "render.h"
#include "stroke.h"

/* Largest reference image: 8192 x 8192 pixels (8 bytes each: 512 MiB). */
#define LINE_MAX_REF_PIXELS (8192LL * 8192LL)

typedef struct LineStats {
  int objects;             /* objects drawing lines */
  int important, visible;  /* important edges; those traced into segments */
  int segments, polylines, strokes;
  long long brush_steps;   /* positions of the brush, a pixel apart, over all brush strokes */
  int tested, whole, cut, dropped;   /* endpoint test (003): edges tested, kept whole,
                                        bisected, hidden */
  int ref_width, ref_height;
  /* seconds per stage */
  double t_edges, t_ref, t_trace, t_link, t_build, t_draw;
  double t_cull, t_chain;              /* endpoint front end */
} LineStats;

/* Find, trace, link and draw the lines of objs[0..nobj) seen by cam (the
** output camera: cam->width x cam->height pixels). Strokes are composited
** over target (may be NULL); with strokes_out, the stroke list is handed
** to the caller (stroke_list_free) for the SVG writer. threads >= 1. stats
** may be NULL. Returns 1, or 0 with a reason in err (a stroke texture that
** cannot be read, a reference image over LINE_MAX_REF_PIXELS). */
int line_render(const LineObject *objs, int nobj, const Camera *cam, Image *target, int threads,
                LineStats *stats, StrokeList **strokes_out, char *err, size_t errlen);

/* The objects of a prepared frame as the line stage sees them (meshes in
** object space, each style's lines, fill = the style's base colour), in
** frame order: *out is malloc'ed (free it); returns the count. */
int line_frame_objects(const RenderFrame *f, LineObject **out);

/* Does any object of f draw lines (line_render_frame changes its image)? */
int line_frame_draws(const RenderFrame *f);

/* line_render for a prepared frame (render_scene calls it after shading,
** with the frame's camera and threads workers). Records its stages in the
** --stats table (stats.h). A failure is reported as a diagnostic at the
** style's lines block; returns 0 then. */
int line_render_frame(const RenderFrame *f, int threads, Image *target, StrokeList **strokes_out,
                      LineStats *stats);

/* The reference image size line_render uses for objs and cam. */
void line_ref_size(const LineObject *objs, int nobj, const Camera *cam, int *w, int *h);

/* Print the --stats lines of the line stage. */
void line_stats_print(FILE *f, const LineStats *s);

#endif
