/*
** A frame split into tiles: "I/N" (tile I of N rows of tiles) or "I/CxR"
** (of C columns and R rows), numbered from 1, row by row from the top
** left. The arithmetic both the renderer (render/tile.h) and the stitcher
** (io/assemble.h) use, so they agree on every tile's pixels.
*/
#ifndef base_split_h
#define base_split_h

#include <stddef.h>

/* Most tiles a split may have (columns times rows). */
#define SPLIT_MAX_TILES 65536

/* Tile `index` (1 .. cols * rows) of a split into cols x rows tiles. */
typedef struct TileSpec {
  int index, cols, rows;
} TileSpec;

/* Parse "I/N" or "I/CxR" into *t: 1 on success, else 0 with the reason in
** err (not a tile, a split of no tiles or more than SPLIT_MAX_TILES, a tile
** the split does not have). The reason names the option --tile. */
int tile_parse(const char *spec, TileSpec *t, char *err, size_t errlen);

/* "I/N" or "I/CxR" for t, into buf. */
void tile_format(const TileSpec *t, char *buf, size_t n);

/* The pixels [*x0, *x1) x [*y0, *y1) of tile t in a w x h frame: columns
** and rows split as evenly as whole pixels allow (tile column c spans
** [c w / C, (c + 1) w / C)). 1, or 0 with the reason in err when the frame
** has fewer columns or rows than the split. */
int tile_split_rect(const TileSpec *t, int w, int h, int *x0, int *y0, int *x1, int *y1, char *err,
                    size_t errlen);

#endif
