/*
** The OpenImageIO bridge: a plain C view of the few OIIO calls sumi needs
** (write one image, whole or a band of rows at a time; read one image). It
** is built on its own as libsumi_oiio.so and loaded by image.c with dlopen
** on first use, so a
** command that touches no image never pays OIIO's start-up. image.c finds
** everything through the single exported symbol sumi_oiio_api().
**
** The bridge moves pixels, it does not convert colour: callers hand it
** pixels already in the file's type (8-bit sRGB codes, half/float linear,
** int32 ids) and get back pixels in the file's own type class. Alpha is
** always unassociated ("oiio:UnassociatedAlpha" = 1), on write and on read.
** No C++ exception crosses this boundary: every entry point returns an int
** and writes a message into err.
*/
#ifndef io_image_oiio_h
#define io_image_oiio_h

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Bumped whenever SumiOiioApi or the structs below change shape, so a stale
** libsumi_oiio.so from an older build is refused instead of misused. */
#define SUMI_OIIO_API_VERSION 5

/* Pixel types crossing the bridge. */
enum {
  SUMI_OIIO_UINT8 = 1,
  SUMI_OIIO_UINT16,
  SUMI_OIIO_HALF,     /* 16-bit IEEE half, stored as uint16_t */
  SUMI_OIIO_FLOAT,
  SUMI_OIIO_INT32
};

/* Results of read: success, the file is no image OIIO can open (missing,
** unknown format, bad header), the pixels could not be read (corrupt or
** truncated data), or the header asks for more than the caller's limits
** (px->width, height and channels then say how much). */
enum { SUMI_OIIO_OK = 1, SUMI_OIIO_NOT_IMAGE = 0, SUMI_OIIO_CORRUPT = -1, SUMI_OIIO_TOO_LARGE = -2 };

/* A described block of interleaved, row-major pixels, top row first. */
typedef struct SumiOiioPixels {
  int width, height, channels;
  int type;                          /* SUMI_OIIO_* */
  int alpha_channel;                 /* index of the alpha channel, or -1 */
  void *data;
  char format[16];                   /* read only: OIIO's format name ("png", "openexr") */
  /* read only: where the pixels lie in a larger image (a tile: the data
  ** window's corner and the display window's size; 0, 0 and the image's
  ** own size otherwise), and the ImageDescription ("" if none) */
  int x, y, full_width, full_height;
  char description[256];
} SumiOiioPixels;

/* How to write: the type stored in the file may differ from the pixels'
** (float pixels stored as half in EXR). */
typedef struct SumiOiioWrite {
  int file_type;                     /* SUMI_OIIO_*, 0: same as the pixels */
  const char *const *channel_names;  /* channels entries, or NULL: defaults */
  const char *colorspace;            /* "sRGB", "Linear" or NULL */
  int quality;                       /* JPEG quality 1..100, 0: default */
  /* a tile of a full_width x full_height image whose first pixel is (x,
  ** y) there (full_width 0: not a tile), and an ImageDescription (NULL:
  ** none): TIFF keeps them as XPosition, YPosition, the full size and its
  ** description tag, EXR as data and display windows and an attribute */
  int x, y, full_width, full_height;
  const char *description;
} SumiOiioWrite;

/* A file being written a band of rows at a time (stream_open). */
typedef struct SumiOiioStream SumiOiioStream;

/* What a file's header may ask for. */
typedef struct SumiOiioLimits {
  long long pixels; /* width * height */
  int side;         /* width, and height */
  int channels;
  long long values; /* width * height * channels */
} SumiOiioLimits;

typedef struct SumiOiioApi {
  int version;                       /* SUMI_OIIO_API_VERSION */
  const char *oiio_version;          /* OpenImageIO's own version string */
  /* Write px to path, the format chosen by path's extension (OIIO's
  ** rules). Returns 1 on success; 0 with a message in err otherwise. A
  ** failed write may leave a partial file at path: the caller writes to a
  ** temporary name and removes it. */
  int (*write)(const char *path, const SumiOiioPixels *px, const SumiOiioWrite *w,
               char *err, size_t errlen);
  /* Read the first subimage of path. want is the type to deliver: 0 for
  ** the file's own class (UINT8 or UINT16 for integer files of up to 16
  ** bits, INT32 for 32-bit integer files, FLOAT otherwise), or a SUMI_OIIO_*
  ** type to convert to. On SUMI_OIIO_OK px is filled and px->data was
  ** allocated with malloc: the caller frees it. Otherwise returns
  ** SUMI_OIIO_NOT_IMAGE, SUMI_OIIO_CORRUPT or SUMI_OIIO_TOO_LARGE with the
  ** reason in err.
  ** limits bounds the header: one asking for more is refused before any
  ** allocation, sumi's or OpenImageIO's (its limits:channels and
  ** limits:imagesize_MB are set from it). */
  int (*read)(const char *path, int want, const SumiOiioLimits *limits, SumiOiioPixels *px,
              char *err, size_t errlen);
  /* write, for pixels that arrive a band of rows at a time: open path
  ** for px's size and type (px->data is not read), hand stream_rows rows
  ** y0..y1-1 in order, top to bottom, then stream_close, which frees the
  ** stream whatever happened before. The file gets the bytes write gives
  ** for the whole image. Each returns 1, or 0 with a message in err (open
  ** returns NULL then); the file may be partial, as with write. */
  SumiOiioStream *(*stream_open)(const char *path, const SumiOiioPixels *px,
                                 const SumiOiioWrite *w, char *err, size_t errlen);
  int (*stream_rows)(SumiOiioStream *s, int y0, int y1, const void *rows, char *err, size_t errlen);
  int (*stream_close)(SumiOiioStream *s, char *err, size_t errlen);
  /* Whether path is a whole image: it opens, and every scanline (or
  ** tile) of its first subimage reads without error, a band at a time,
  ** so any size costs a band of memory. 1, or 0 with the reason in err. */
  int (*complete)(const char *path, char *err, size_t errlen);
} SumiOiioApi;

/* The one exported symbol: the bridge's function table. Never NULL. */
const SumiOiioApi *sumi_oiio_api(void);
typedef const SumiOiioApi *(*SumiOiioApiFn)(void);
#define SUMI_OIIO_API_SYMBOL "sumi_oiio_api"

#ifdef __cplusplus
}
#endif

#endif
