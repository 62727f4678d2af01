/*
** The canvas: the post step that paints a frame on its paper, after the
** tile pass (and the origami sheets), before the lines.
**
**   paper     the sheet, or the flat background (paper.h)
**   ink       the pixels of shade ink objects (from the tile pass's samples, each
**             pixel's samples): quantised Gouraud ink (shade_ink.c), then
**             the diffusion and the box filter over the whole frame
**             (ink_diffuse.c), each style up to its `stage`
**   layer     the tile pass's image, transparent where nothing or ink was
**             drawn, composited over the inked paper
** Ink lies on the paper in display values, as the thesis's ink quantities
** are (ink = 255 (1 - colour)): a pixel of density d = ink / 255 times the
** paper's absorbency shows paper (1 - d) + ink colour d.
*/
#ifndef render_canvas_h
#define render_canvas_h

#include "gbuffer.h"
#include "render.h"

/* The margin in output pixels a window of f needs around the pixels it
** keeps for its canvas to give them the whole frame's values: the ink of a
** pixel depends on the ink of pixels as far as the diffusion's passes and
** the box filter reach. */
int canvas_margin(const RenderFrame *f);

/* Does the frame need the canvas: a sheet, a gradient or image
** background, or an object in shade ink? */
int canvas_wanted(const Scene *s, const RenderFrame *f);

/* Does the canvas read the tile pass's image: do origami sheets or
** objects in other styles than ink show in it? When not, the pass need
** only draw the G-buffer (its image's pixels are never read). */
int canvas_reads_layer(const Scene *s, const RenderFrame *f);

/* Paint the frame: *img is the tile pass's image (RGBA, background
** transparent; float, or 8-bit codes when out8) with its G-buffer g, both
** covering the frame's window (f->win; its pixels are read only when
** canvas_reads_layer says so); it is
** replaced by the painted image (RGB when the paper is opaque, else RGBA;
** 8-bit codes when out8 and opaque, else float). Returns 1, or 0 after a diagnostic (a sheet image
** that cannot be read); *img is kept then. */
int canvas_paint(const Scene *s, const RenderFrame *f, const GBuffer *g, Image **img, int out8);

/* The same with no G-buffer kept: canvas_begin makes the frame's paper
** (returning 0 after a diagnostic, as canvas_paint) and the ink canvas;
** the tile pass hands each tile's samples to canvas_sink's (NULL: the
** frame has no ink, no samples are needed), whose ink goes onto the canvas
** as they come (the ink quantise stage, on the pass's workers); then
** canvas_finish paints *img as canvas_paint does and frees the canvas.
** The same bytes as canvas_paint. */
typedef struct Canvas Canvas;
int canvas_begin(const Scene *s, const RenderFrame *f, Canvas **cv);
const RenderTileSink *canvas_sink(Canvas *cv);
int canvas_finish(Canvas *cv, Image **img, int out8);

#endif
