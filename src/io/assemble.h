/*
** `sumi assemble tiles... -o out.png`: the files of `sumi render --tile`
** stitched into their frame. Each tile file says which tile of which split
** of which render it is (image.h, ImageTile); the stitcher checks that the
** tiles given are all the tiles of one split of one render, each where the
** split puts it, and writes the frame with the pixels exactly as stored:
** the same bytes as one `sumi render` of the frame to out writes (for the
** same format: 8-bit codes to png or tif, floats to exr).
*/
#ifndef io_assemble_h
#define io_assemble_h

#include <stddef.h>

/* Stitch the n tile files paths into out. Returns 1, or 0 with the reason
** in err (a file that cannot be read or is no tile, tiles of different
** renders, splits, sizes or kinds of pixel, a tile given twice or
** missing, or one whose place or size is not its tile's): nothing is
** written then. */
int assemble_tiles(const char *const *paths, int n, const char *out, char *err, size_t errlen);

#endif
