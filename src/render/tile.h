/*
** Tiles: one part of a frame rendered on its own (`sumi render --tile
** I/N` or `--tile I/CxR`), so that independent jobs share a frame too big
** or too slow for one, and `sumi assemble` (io/assemble.h) stitches their
** files into the frame, byte for byte what one render writes.
**
** A tile's pixels are exactly the whole frame's there. Every stage that
** looks across pixels gets what it needs:
**   tile pass   its triangles are set up in the whole frame's sample grid
**               (the same fixed-point positions and planes) and only the
**               screen tiles over the window are drawn; shading is per row,
**               so a window's rows can start anywhere, but its columns keep
**               the screen tiles' (RENDER_TILE) boundaries;
**   lines       the strokes are found in the whole view (reference image,
**               tracing, linking, brush paths) and drawn into the window;
**   origami     its window reaches the disk radius and the lines' width
**               beyond the tile (origami_margin);
**   canvas      the ink diffusion's passes and the box filter's half side
**               (canvas_margin); paper, noise and random values follow the
**               frame's pixel coordinates.
** The stages draw that window and the tile is cut out of it. A tile that
** needs no margin (no origami, no canvas) and goes to an 8-bit file is
** drawn and written TILE_BAND_ROWS rows at a time, so a job holds a band,
** not its whole tile.
*/
#ifndef render_tile_h
#define render_tile_h

#include <stddef.h>

#include "../base/split.h"
#include "render.h"

/* Rows a tile job draws and writes at a time (a multiple of RENDER_TILE). */
#define TILE_BAND_ROWS 64
/* The pixels of tile t (base/split.h) in a w x h frame, as a window; 0
** with the reason in err when the frame is smaller than the split. */
int tile_rect(const TileSpec *t, int w, int h, RenderWindow *r, char *err, size_t errlen);

/* render_scene for a window of the frame (o->window): prepared f (its
** background made transparent when canvas), into *out (the window's
** pixels, or, when o->rows took the tile band by band, an image with no
** pixels) and *gbuf_out (the window's samples). Returns 1, or 0 after a
** diagnostic. */
int tile_render(const Scene *s, const RenderOptions *o, RenderFrame *f, int canvas, Image **out,
                GBuffer **gbuf_out);

#endif
