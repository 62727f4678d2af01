/*
** PNG files through libpng, the format's reference library, so the default
** output format (and PNG inputs) need no OpenImageIO: a process that only
** writes a PNG loads a handful of shared libraries instead of ~260.
**
** Written files: IHDR, the sRGB chunk (with the gAMA and cHRM chunks
** libpng pairs with it for older readers), for a tile its oFFs and tEXt
** chunks, the image rows unfiltered at zlib level PNG_LEVEL, IEND. The codes are stored as given (the caller
** has encoded colour as sRGB and alpha linearly, unassociated). Rows go in
** one band at a time, so a whole image and the same image streamed in
** bands give the same bytes.
**
** Functions that can fail return 1 on success, 0 on failure with a
** one-line reason in err (errlen bytes).
*/
#ifndef io_png_file_h
#define io_png_file_h

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* zlib level, with no row filter. A toon-like 1920x1080 RGB frame, measured
** through libpng: level 2 unfiltered ~8 ms, 46 KB; level 6 unfiltered
** ~17 ms, 20 KB; level 6 with adaptive filters ~39 ms, 15 KB. Speed wins:
** frames are written every render, and the files stay small. */
#define PNG_LEVEL 2

/* Whether the first bytes of the file at path are a PNG signature. */
int png_is_png_file(const char *path);

typedef struct PngOut PngOut;

/* Where a PNG lies in a larger image (a tile): an oFFs chunk of (x, y)
** pixels, and a tEXt chunk key = text saying the rest. */
typedef struct PngPlace {
  int x, y;
  const char *key, *text;
} PngPlace;

/* Begin a w x h PNG of nc channels (1-4: grey, grey+alpha, RGB, RGBA) of
** bits (8 or 16) per channel on f (opened for writing, still the
** caller's to close), placed as place says (NULL: no such chunks). */
PngOut *png_out_open(FILE *f, int w, int h, int nc, int bits, const PngPlace *place, char *err,
                     size_t errlen);
/* The next n rows: n * w * nc codes (uint8_t, or uint16_t in host order
** for 16 bits), top row first. */
int png_out_rows(PngOut *p, const void *codes, int n, char *err, size_t errlen);
/* Finish the file (every row written) and free p; 0 if any step failed. */
int png_out_close(PngOut *p, char *err, size_t errlen);

/* The text of the tEXt chunk named key among those before the image data,
** into out (n bytes), and the oFFs chunk's offset in pixels (0, 0 without
** one) into *x, *y; 0 when there is no such text or the file is no PNG. */
int png_read_place(const char *path, const char *key, char *out, size_t n, int *x, int *y);

/* Whether the file at path is a whole PNG: its signature, every row's
** data (read one row at a time, so any size costs a row of memory) and
** the chunks after it up to IEND, with their checksums. */
int png_file_complete(const char *path);

/* Read a PNG: palette images become RGB, transparency chunks alpha, grey
** of fewer than 8 bits 8-bit grey; *codes is malloc'ed (free it), *bits
** is 8 or 16 (uint16_t codes in host order). A header whose w * h exceeds
** max_pixels is refused before anything is allocated: *w and *h are set,
** and *too_large is 1. */
int png_read_file(const char *path, long long max_pixels, int *w, int *h, int *nc, int *bits,
                  void **codes, int *too_large, char *err, size_t errlen);

#endif
