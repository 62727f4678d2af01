/*
** Images in memory and on disk. An Image is linear float, row-major, top
** row first, channels interleaved; with 2 or 4 channels the last one is
** alpha, unassociated (colour not multiplied by alpha). An 8-bit Image
** (image_create8) holds the codes an 8-bit file stores instead: sRGB colour
** and linear alpha, as image_encode8 makes them; a frame bound for an
** 8-bit file is kept that way, a quarter of the memory of float.
**
** PNG goes through libpng (png_file.h); the other formats through
** OpenImageIO, behind a bridge library loaded on first use (image_oiio.h),
** so that a process that touches only PNG never loads OIIO's ~260 shared
** libraries. The format comes from the extension (a file read is taken as
** PNG by its signature):
**   png, tif/tiff, jpg/jpeg  sRGB-encoded from linear, 8-bit (png and tif
**                            may be 16-bit); alpha stays linear; no dither
**   exr                      linear float (or half); alpha associated, as
**                            EXR defines it: colour is multiplied by alpha
**                            on write and divided on read
** Every write goes to a temporary file beside the target, named after it
** with the extension kept ("out.png" -> "out.tmp-PID-SEQ.png", so OIIO
** still picks the format), and is renamed over it only when complete: a
** failed write removes it, and no write leaves a partial image under the
** real name. TIFF and EXR carry a fixed DateTime, so the same image gives
** the same bytes on every run.
**
** Functions that can fail return 1 on success and 0 on failure, with a
** one-line reason naming the file in err (errlen bytes, may be 0).
*/
#ifndef io_image_h
#define io_image_h

#include <stddef.h>
#include <stdint.h>

/* Channels an image may carry: colour images use 1-4; AOV EXRs carry a few
** more (depth, normal, uv, ids). Bounds a file's header before allocation. */
#define IMAGE_MAX_CHANNELS 16
/* Largest image image_read accepts: 8192 x 8192 pixels, 16384 on a side
** (a reader's buffers grow with a row), and 8192 x 8192 x 4 values, so its
** float copy stays at 1 GiB (an image of more channels has fewer pixels);
** a header asking for more is refused before allocation. */
#define IMAGE_READ_MAX_PIXELS (8192LL * 8192LL)
#define IMAGE_READ_MAX_SIDE   16384
#define IMAGE_READ_MAX_VALUES (IMAGE_READ_MAX_PIXELS * 4)

typedef struct Image {
  int width, height, channels;
  float *data;                /* width * height * channels floats, or NULL */
  uint8_t *data8;             /* an 8-bit image's codes (data is NULL), or NULL */
} Image;

/* A zeroed w x h image of channels channels (1..IMAGE_MAX_CHANNELS). Sizes
** are checked by the caller against its limits first; bad sizes or running
** out of memory end the program with a message. Free with image_destroy. */
Image *image_create(int w, int h, int channels);
/* The same with its values unset, for a caller that writes every one. */
Image *image_create_unset(int w, int h, int channels);
void image_destroy(Image *img);                /* NULL is fine */
/* A w x h 8-bit image (channels 1..4), every code 0. */
Image *image_create8(int w, int h, int channels);
/* The same with its codes unset, for a caller that writes every one. */
Image *image_create8_unset(int w, int h, int channels);

/* npix pixels of nc channels (1..4; the last is alpha when nc is 2 or 4)
** from linear float to 8-bit codes, exactly as image_write encodes them,
** and back (a code's linear value). */
void image_encode8(const float *src, uint8_t *dst, size_t npix, int nc);
void image_decode8(const uint8_t *src, float *dst, size_t npix, int nc);

/* Index of the alpha channel of img (the last of 2 or 4), or -1. */
int image_alpha_channel(const Image *img);

/* Where an image lies in a larger one: a tile of a frame (render/tile.h).
** A file keeps it as its format allows, for other programs (PNG: an oFFs
** chunk; TIFF: XPosition, YPosition and the full size; EXR: the data and
** display windows), and all of it in its description (PNG's "Description"
** text, TIFF's and EXR's ImageDescription), as image_tile_format writes
** it: "sumi tile 3/8 of 640x480 at 0,120 render 9f3a0c5e12b4d7a1". */
typedef struct ImageTile {
  int x, y;                   /* its first pixel's place in the frame */
  int full_width, full_height;   /* the frame's size */
  char name[32];              /* the tile: "I/N" or "I/CxR" */
  char render[32];            /* the render it is a part of: the same for all its tiles */
} ImageTile;

/* t as its description says it, into buf (n bytes); and back: 1 when text
** is such a description (*t filled), else 0. */
void image_tile_format(const ImageTile *t, char *buf, size_t n);
int image_tile_parse(const char *text, ImageTile *t);

/* Does path's format keep a tile's pixels exactly and its place (png,
** tif, exr; not jpg, which loses both)? */
int image_keeps_tiles(const char *path);

/* Options for image_write_opts; all-zero means the defaults. */
typedef struct ImageWriteOptions {
  int bits;                   /* png, tif: 8 (default) or 16 per channel */
  int exr_half;               /* exr: 16-bit half instead of 32-bit float */
  int jpeg_quality;           /* jpg: 1..100, 0 for the default (95) */
  const ImageTile *tile;      /* the image is this tile of a frame, or NULL */
} ImageWriteOptions;

/* Does image_write (default options) store path's format as 8-bit codes?
** True for png, tif and jpg: a frame bound for one may be made 8-bit. */
int image_write_is_8bit(const char *path);

/* Write img to path in the format its extension names. */
int image_write(const char *path, const Image *img, char *err, size_t errlen);
int image_write_opts(const char *path, const Image *img, const ImageWriteOptions *opt,
                     char *err, size_t errlen);

/* Writing an 8-bit image a band of rows at a time, as a renderer finishes
** them: the file image_write makes of the whole image, byte for byte,
** through the same temporary name, renamed into place by
** image_stream_close. For the formats and channel counts whose 8-bit codes
** image_write stores unchanged: png and tif with 1-4 channels, jpg
** without alpha (image_stream_fits). */
typedef struct ImageStream ImageStream;
int image_stream_fits(const char *path, int nc);
/* Load the bridge and create the file for a w x h image of nc channels;
** NULL with the reason in err when that fails. */
ImageStream *image_stream_open(const char *path, int w, int h, int nc, char *err, size_t errlen);
/* The same for an image that is tile of a frame (NULL: none). */
ImageStream *image_stream_open_tile(const char *path, int w, int h, int nc, const ImageTile *tile, char *err,
                                    size_t errlen);
/* The next rows, y0..y1-1 (top to bottom, no gaps), as 8-bit codes. A
** failure is kept for image_stream_close to report; later rows are dropped. */
void image_stream_rows(ImageStream *s, int y0, int y1, const uint8_t *codes);
/* Finish the file and rename it into place, or remove it after any failure
** (returned as 0 with the reason in err); frees s. */
int image_stream_close(ImageStream *s, char *err, size_t errlen);
/* Give the file up: remove it and free s. */
void image_stream_discard(ImageStream *s);

/* Read path into a new Image (*out; free with image_destroy): integer
** formats are sRGB-decoded to linear (alpha linearly), float formats kept
** as stored. Errors say whether the file is missing, not an image, or
** corrupt. On failure *out is NULL. */
int image_read(const char *path, Image **out, char *err, size_t errlen);

/* Does every row of the image file at path read, with no complaint from
** its reader? PNG (by the extension) through libpng to its IEND chunk,
** other formats through the bridge; a band of rows at a time, so any size
** costs a band of memory (io/outfile.h checks the rest of a file). */
int image_file_reads_whole(const char *path);

/* A file's pixels exactly as it stores them, for stitching tiles (io/
** assemble.h) without changing a bit: 8- or 16-bit codes, or floats (EXR:
** colour stays multiplied by alpha), with the file's tile description. */
enum { IMAGE_RAW_U8 = 1, IMAGE_RAW_U16, IMAGE_RAW_FLOAT };
typedef struct ImageRaw {
  int width, height, channels;
  int type;                   /* IMAGE_RAW_* */
  void *data;                 /* malloc'ed, interleaved, top row first */
  int has_tile;               /* the file describes itself as a tile: */
  ImageTile tile;
  int x, y;                   /* the format's own record of its place (PNG oFFs, TIFF */
  int full_width, full_height;   /* position and full size, EXR windows); else 0, 0, its size */
  char format[16];            /* "png", "tiff", "openexr", ... */
} ImageRaw;

/* Read path as stored into *raw (image_raw_free); 0 with the reason in err. */
int image_read_raw(const char *path, ImageRaw *raw, char *err, size_t errlen);
/* Write raw's pixels to path as they are (no tile description): an 8-bit
** image gives the bytes image_write gives the same codes, a float one the
** bytes image_write gives the image those floats were written from. The
** format comes from path's extension; it must store raw's type (codes in
** png, tif or jpg; floats in exr). */
int image_write_raw(const char *path, const ImageRaw *raw, char *err, size_t errlen);
void image_raw_free(ImageRaw *raw);

/* Arbitrary-output variables: a w x h float EXR of nch channels named by
** channel_names (e.g. "Z" or "N.x", "N.y", "N.z"), data interleaved, no
** colour transform. */
int image_write_aov_exr(const char *path, int w, int h, int nch, const char **channel_names,
                        const float *data, char *err, size_t errlen);

/* A single-channel 32-bit signed integer TIFF of ids (object or face). */
int image_write_ids_tiff(const char *path, int w, int h, const int32_t *ids, char *err,
                         size_t errlen);

/* Read a single-channel integer image written by image_write_ids_tiff:
** *ids is malloc'ed (free it), *w and *h set. */
int image_read_ids(const char *path, int *w, int *h, int32_t **ids, char *err, size_t errlen);

/* ---- colour encoding (exact, table-driven, deterministic) ------------- */

uint8_t image_linear_to_srgb8(float v);        /* clamps to [0, 1]; NaN -> 0 */
float image_srgb8_to_linear(int code);         /* code 0..255 */
/* Encode img as 8-bit: sRGB for colour channels, linear for alpha; out has
** width * height * channels bytes. */
void image_to_srgb8(const Image *img, uint8_t *out);

/* ---- the bridge library ------------------------------------------------ */

/* Load the OpenImageIO bridge now (every read and write does this on first
** use; a caller may do it early on another thread to hide the ~0.2 s).
** Thread-safe; later calls return the first call's result. */
int image_bridge_load(char *err, size_t errlen);
/* Seconds the load took (dlopen of the bridge and OIIO's libraries), or 0
** if it has not happened: reported apart from encode times in --stats. */
double image_bridge_load_seconds(void);
/* Seconds callers of image_bridge_load (the reads and writes) spent
** waiting for it: all of the load without a prefetch, less with one. */
double image_bridge_wait_seconds(void);
/* Start loading the bridge on a thread now, for a process that will need
** it (image_write_needs_bridge, image_read_needs_bridge): the load
** overlaps parsing and rendering, and the first read or write that needs
** it waits for the rest. Returns at once; later calls do nothing. */
void image_bridge_prefetch(void);
/* Wait for a prefetch to finish; call before the process exits, so that
** no library is half loaded while exit runs destructors. */
void image_bridge_join(void);
/* Whether writing path (by its extension; image_write's formats) or
** reading the image file named name (by its extension: a guess, for
** prefetching only; PNG goes through libpng) needs the bridge. */
int image_write_needs_bridge(const char *path);
int image_read_needs_bridge(const char *name);

#endif
