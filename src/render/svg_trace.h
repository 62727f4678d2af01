/*
** The SVG writer's raster side (svg.h): pixel regions of the rendered
** frame traced into smooth closed paths with potrace (Debian's
** libpotrace), and the frame as those tracings see it.
**
** A region is drawn as a layer: one filled path. Layers are painted in
** order, and a layer's traced mask is its own pixels plus the pixels
** within SVG_UNDERLAP of them that a later layer owns, so that where two
** regions meet the later one's curve is drawn over the earlier one, never
** over a gap (potrace's curves stay within about a pixel of the mask's
** outline). Each pixel then shows the last layer that owns it.
*/
#ifndef render_svg_trace_h
#define render_svg_trace_h

#include <stdint.h>
#include <stdio.h>

/* Pixels a layer reaches under the layers painted after it. */
#define SVG_UNDERLAP 2
/* Colour classes of one object at most (the most common ones). */
#define SVG_MAX_CLASSES 64
/* Codes (any channel) a colour may be from its class's first colour
** before it starts a class of its own: a smooth shading's steps. */
#define SVG_CLASS_STEP 16
/* A region of one class smaller than this many pixels joins the class
** around it (anti-aliased edges and specks are not regions of their own). */
#define SVG_MIN_REGION 4

/* A pixel box, inclusive. */
typedef struct SvgBox { int x0, y0, x1, y1; } SvgBox;

/* The frame the regions are traced from, at output resolution. */
typedef struct SvgFrame {
  int w, h;
  const uint8_t *rgba;   /* w * h * 4: sRGB colour codes and alpha, before strokes */
  int32_t *owner;        /* per pixel: object index, SVG_OWNER_ORIGAMI, SVG_OWNER_MARGIN, or -1
                            (background) */
  float *depth;          /* per pixel window depth (camera.h), for the painting order */
  int nobjects;
  int samples;           /* the render's N of `samples N` (origami line widths depend on it) */
} SvgFrame;

#define SVG_OWNER_ORIGAMI INT32_MAX
/* Background just off an origami sheet, where its lines reach: in no
** region (the sheet's strokes draw what is there). */
#define SVG_OWNER_MARGIN (INT32_MAX - 1)

/* Write the path data of the outline of the pixels of box where mask
** (frame width w, 1 = inside) is set to f: "M… C… L… Z" per closed curve,
** coordinates in pixels (y down). alphamax is potrace's corner threshold
** (0: polygons; 1: its default, smooth curves). Returns the number of
** curves written (0 when there are none). */
int svg_trace(FILE *f, const unsigned char *mask, int w, SvgBox box, double alphamax);

/* Write a filled path of mask's outline in colour rgb (sRGB codes) to f,
** with the given extra attributes ("" for none); nothing when the mask is
** empty in box. */
void svg_trace_fill(FILE *f, const unsigned char *mask, int w, SvgBox box, double alphamax,
                    const uint8_t rgb[3], const char *attrs);

/* The mesh objects' regions of fr, one layer per object and colour class:
** objects far to near (by their pixels' mean depth), each one's classes
** (the colours its pixels cluster into: toon bands, specular spots,
** posterised gradients) dark to light. A background of more than one
** colour (a paper sheet) is traced the same way, first. Pixels of
** SVG_OWNER_ORIGAMI count as painted later (the origami goes over the
** meshes, svg_origami.h). */
void svg_write_regions(FILE *f, const SvgFrame *fr);

/* The colour classes of a set of pixels: sel holds n pixel indices of
** fr; cls[k] receives the class of pixel sel[k], one of *ncls (at most
** SVG_MAX_CLASSES), whose mean colours go to rgb (3 sRGB codes a class).
** Classes are sorted dark to light; a connected region of one class
** under SVG_MIN_REGION pixels joins the class around it. */
void svg_classes(const SvgFrame *fr, const int *sel, int n, int *cls, int *ncls, uint8_t *rgb);

#endif
