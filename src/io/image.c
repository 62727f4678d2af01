/*
** Image buffers and image files. Pixels are converted here (sRGB encoding
** and decoding by exact tables, alpha association for EXR) and handed to
** libpng for PNG (png_file.h), or else to the OpenImageIO bridge, which
** this file loads with dlopen on first use (or early, on a thread, when
** image_bridge_prefetch says it will be needed):
** libsumi_oiio.so is looked for beside the running binary (an uninstalled
** build/), in PREFIX/lib/sumi/ for a binary in PREFIX/bin/, and one level up
** (test binaries in build/unit/). Writes go through a temporary file that
** is renamed into place (see image.h).
*/
#include "image.h"

#include "../base/mem.h"
#include "image_oiio.h"
#include "infile.h"
#include "tempfile.h"
#include "png_file.h"

#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define BRIDGE_NAME "libsumi_oiio.so"

/* Buckets of the linear -> sRGB 8-bit encoder, indexed by the top bits of
** a float (sign, exponent and SRGB_MANT_BITS mantissa bits): every
** float has one, so the encoder needs no range tests. Between
** 2^SRGB_MIN_EXP (below it every value is code 0: the first threshold is
** ~1.5e-4) and 1 each bucket is narrower than the gap between two code
** thresholds in its octave, so a bucket's first code is at most one below
** the answer (srgb_init checks this). */
#define SRGB_MANT_BITS 7
#define SRGB_MIN_EXP (-13)
#define SRGB_LO_BITS ((uint32_t)(127 + SRGB_MIN_EXP) << 23)   /* bits of 2^SRGB_MIN_EXP */
#define SRGB_ONE_BITS 0x3f800000u                               /* bits of 1.0f */
#define SRGB_NAN_BITS 0x7f800001u                               /* the smallest NaN's bits */
#define SRGB_SHIFT (23 - SRGB_MANT_BITS)                        /* bits -> bucket */

/* Attempts at a fresh temporary name before giving up (a name is taken
** only if a file of that name already exists). */
#define TMP_NAME_TRIES 100

/* ---- errors --------------------------------------------------------- */

static void set_err(char *err, size_t errlen, const char *fmt, ...)
  __attribute__((format(printf, 3, 4)));

static void set_err(char *err, size_t errlen, const char *fmt, ...) {
  if (!err || errlen == 0) return;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(err, errlen, fmt, ap);
  va_end(ap);
}

/* ---- sRGB tables ------------------------------------------------------ */

static pthread_once_t srgb_once = PTHREAD_ONCE_INIT;
static float srgb_decode[256];              /* code -> linear */
static double srgb_threshold[257];          /* smallest linear value of each code */
static float srgb_threshold_f[257];         /* the smallest float at or above each */
static uint8_t srgb_bucket[1u << (32 - SRGB_SHIFT)];   /* by a float's top bits: its bucket's first code */
static uint32_t srgb_next_bits[256];        /* by code: the bits where the next code starts */

static double srgb_to_linear_d(double s) {
  return s <= 0.04045 ? s / 12.92 : pow((s + 0.055) / 1.055, 2.4);
}

static double linear_to_srgb_d(double v) {
  return v <= 0.0031308 ? v * 12.92 : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}

static float float_of_bits(uint32_t u) {
  float f;
  memcpy(&f, &u, sizeof f);
  return f;
}

/* The code whose threshold interval holds v, by search from code k up. */
static int code_from(double v, int k) {
  while (v >= srgb_threshold[k + 1]) k++;
  return k;
}

static void srgb_init(void) {
  for (int k = 0; k < 256; k++) srgb_decode[k] = (float)srgb_to_linear_d(k / 255.0);
  srgb_threshold[0] = -INFINITY;
  for (int k = 1; k < 256; k++) srgb_threshold[k] = srgb_to_linear_d((k - 0.5) / 255.0);
  srgb_threshold[256] = INFINITY;
  /* float thresholds: for a float v, v >= srgb_threshold_f[k] exactly when
  ** (double)v >= srgb_threshold[k] */
  srgb_threshold_f[0] = -INFINITY;
  srgb_threshold_f[256] = INFINITY;
  for (int k = 1; k < 256; k++) {
    float f = (float)srgb_threshold[k];
    if ((double)f < srgb_threshold[k]) f = nextafterf(f, INFINITY);
    while ((double)nextafterf(f, -INFINITY) >= srgb_threshold[k]) f = nextafterf(f, -INFINITY);
    srgb_threshold_f[k] = f;
  }
  if (!(srgb_threshold_f[1] > float_of_bits(SRGB_LO_BITS)))
    sumi_fatal("srgb_init: code 1 starts below 2^%d", SRGB_MIN_EXP);
  int k = 0;   /* codes rise with the buckets: each search starts where the last ended */
  for (uint32_t b = SRGB_LO_BITS >> SRGB_SHIFT; b < SRGB_ONE_BITS >> SRGB_SHIFT; b++) {
    uint32_t lo = b << SRGB_SHIFT;
    k = code_from(float_of_bits(lo), k);
    int top = code_from(float_of_bits(lo + (1u << SRGB_SHIFT) - 1), k);
    if (top > k + 1) sumi_fatal("srgb_init: bucket %u spans codes %d..%d", (unsigned)b, k, top);
    srgb_bucket[b] = (uint8_t)k;
  }
  /* Below 2^SRGB_MIN_EXP: code 0 (its bits stay below code 1's). From 1.0
  ** up, and every negative float and NaN: 255, plus one (wrapping to 0)
  ** where the bits reach the smallest NaN's, which only +inf's do not. */
  for (uint32_t b = SRGB_ONE_BITS >> SRGB_SHIFT; b < 1u << (32 - SRGB_SHIFT); b++) srgb_bucket[b] = 255;
  for (int c = 0; c < 255; c++) memcpy(&srgb_next_bits[c], &srgb_threshold_f[c + 1], sizeof srgb_next_bits[c]);
  srgb_next_bits[255] = SRGB_NAN_BITS;
}

/* The code whose threshold interval holds v: round(255 * srgb(v)) exactly,
** 0 for negatives and NaN, 255 from 1 up. The bucket of v's top bits
** gives the code or the one below it; positive floats are ordered as their
** bits are, so one integer test against the next code's threshold settles
** it: no branch, no range test. */
static inline uint8_t encode8(float v) {
  uint32_t u;
  memcpy(&u, &v, sizeof u);
  unsigned k = srgb_bucket[u >> SRGB_SHIFT];
  return (uint8_t)(k + (u >= srgb_next_bits[k]));
}

static inline uint8_t alpha8(float a) {
  if (!(a > 0.0f)) return 0;
  if (a >= 1.0f) return 255;
  return (uint8_t)lrintf(a * 255.0f);
}

static uint16_t encode16(float v) {
  if (!(v > 0.0f)) return 0;
  if (v >= 1.0f) return 65535;
  return (uint16_t)lrint(linear_to_srgb_d(v) * 65535.0);
}

static inline uint16_t alpha16(float a) {
  if (!(a > 0.0f)) return 0;
  if (a >= 1.0f) return 65535;
  return (uint16_t)lrintf(a * 65535.0f);
}

uint8_t image_linear_to_srgb8(float v) {
  pthread_once(&srgb_once, srgb_init);
  return encode8(v);
}

float image_srgb8_to_linear(int code) {
  pthread_once(&srgb_once, srgb_init);
  return srgb_decode[code < 0 ? 0 : code > 255 ? 255 : code];
}

/* ---- Image ------------------------------------------------------------- */

/* An image with no pixels yet; bad sizes end the program (image.h). */
static Image *image_shell(int w, int h, int channels, int max_channels, const char *who) {
  if (w <= 0 || h <= 0 || channels < 1 || channels > max_channels)
    sumi_fatal("%s: bad size %dx%d with %d channels", who, w, h, channels);
  Image *img = xcalloc(1, sizeof *img);
  img->width = w;
  img->height = h;
  img->channels = channels;
  return img;
}

Image *image_create(int w, int h, int channels) {
  Image *img = image_shell(w, h, channels, IMAGE_MAX_CHANNELS, "image_create");
  img->data = xcalloc((size_t)w * (size_t)h * (size_t)channels, sizeof(float));
  return img;
}

Image *image_create_unset(int w, int h, int channels) {
  Image *img = image_shell(w, h, channels, IMAGE_MAX_CHANNELS, "image_create_unset");
  img->data = xmalloc_huge((size_t)w * (size_t)h * (size_t)channels * sizeof(float));
  return img;
}

Image *image_create8(int w, int h, int channels) {
  Image *img = image_shell(w, h, channels, 4, "image_create8");
  img->data8 = xcalloc((size_t)w * (size_t)h * (size_t)channels, 1);
  return img;
}

Image *image_create8_unset(int w, int h, int channels) {
  Image *img = image_shell(w, h, channels, 4, "image_create8_unset");
  img->data8 = xmalloc_huge((size_t)w * (size_t)h * (size_t)channels);   /* a few faults */
  return img;
}

void image_destroy(Image *img) {
  if (!img) return;
  free(img->data);
  free(img->data8);
  free(img);
}

int image_alpha_channel(const Image *img) {
  return img->channels == 2 || img->channels == 4 ? img->channels - 1 : -1;
}

static size_t image_values(const Image *img) {
  return (size_t)img->width * (size_t)img->height * (size_t)img->channels;
}

/* Do RGB pixels a and b hold the same bits? */
static inline int same_rgb(const float *a, const float *b) { return !memcmp(a, b, 3 * sizeof *a); }

static inline void encode_rgb8(const float *a, uint8_t *d) {
  d[0] = encode8(a[0]), d[1] = encode8(a[1]), d[2] = encode8(a[2]);
}

/* Encode npix pixels of nc channels (alpha at ac, or -1) to 8-bit codes.
** Flat regions are the rule in stylised images, so a pixel whose bits
** equal the one before it reuses its codes (equal bits, equal codes); in
** RGB a whole run of them is encoded once and copied in a few long stores
** (a 3-byte store a pixel costs more than the encoding); the pixels
** between runs (noise, gradients) are encoded as the scan passes them. */
static void encode_pixels8(const float *src, uint8_t *dst, size_t npix, int nc, int ac) {
  if (nc == 3 && ac < 0) {   /* opaque RGB, the common case */
    for (size_t p = 0, q, e; p < npix; p = e) {
      q = p;
      do encode_rgb8(src + 3 * q, dst + 3 * q);                /* p .. q - 1: each differs from its left */
      while (++q < npix && !same_rgb(src + 3 * q, src + 3 * q - 3));
      for (e = q; e < npix && same_rgb(src + 3 * e, src + 3 * q - 3); e++) {}
      uint8_t *d = dst + 3 * (q - 1);                           /* q .. e - 1 repeat q - 1 */
      for (size_t done = 1, left = e - q; left > 0;) {          /* copies double: few, long stores */
        size_t k = done < left ? done : left;
        memcpy(d + 3 * done, d, 3 * k);
        done += k;
        left -= k;
      }
    }
    return;
  }
  for (size_t p = 0; p < npix; p++, src += nc, dst += nc) {
    int same = p > 0;
    for (int c = 0; c < nc && same; c++) same = src[c] == src[c - nc];
    if (same) {
      for (int c = 0; c < nc; c++) dst[c] = dst[c - nc];
      continue;
    }
    for (int c = 0; c < nc; c++) dst[c] = c == ac ? alpha8(src[c]) : encode8(src[c]);
  }
}

void image_encode8(const float *src, uint8_t *dst, size_t npix, int nc) {
  pthread_once(&srgb_once, srgb_init);
  encode_pixels8(src, dst, npix, nc, nc == 2 || nc == 4 ? nc - 1 : -1);
}

void image_decode8(const uint8_t *src, float *dst, size_t npix, int nc) {
  pthread_once(&srgb_once, srgb_init);
  int ac = nc == 2 || nc == 4 ? nc - 1 : -1;
  for (size_t i = 0; i < npix * (size_t)nc; i++)
    dst[i] = (int)(i % (size_t)nc) == ac ? src[i] / 255.0f : srgb_decode[src[i]];
}

void image_to_srgb8(const Image *img, uint8_t *out) {
  pthread_once(&srgb_once, srgb_init);
  size_t npix = (size_t)img->width * (size_t)img->height;
  if (img->data8) {
    memcpy(out, img->data8, npix * (size_t)img->channels);
    return;
  }
  encode_pixels8(img->data, out, npix, img->channels, image_alpha_channel(img));
}

/* ---- the bridge library ---------------------------------------------- */

static pthread_once_t bridge_once = PTHREAD_ONCE_INIT;
static const SumiOiioApi *bridge;
static char bridge_error[1024];
static double bridge_seconds;

static double now_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* Directory of the running binary into dir (no trailing slash); 0 if
** /proc/self/exe cannot be read. */
static int exe_dir(char *dir, size_t size) {
  ssize_t n = readlink("/proc/self/exe", dir, size - 1);
  if (n <= 0 || (size_t)n >= size - 1) return 0;
  dir[n] = '\0';
  char *slash = strrchr(dir, '/');
  if (!slash) return 0;
  *slash = '\0';
  return 1;
}

/* dlopen path and fetch its table; 0 with bridge_error set on failure. */
static int bridge_open(const char *path) {
  void *lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
  if (!lib) {
    set_err(bridge_error, sizeof bridge_error, "cannot load the image library: %s", dlerror());
    return 0;
  }
  SumiOiioApiFn fn;
  *(void **)&fn = dlsym(lib, SUMI_OIIO_API_SYMBOL);
  const SumiOiioApi *api = fn ? fn() : NULL;
  if (!api || api->version != SUMI_OIIO_API_VERSION) {
    set_err(bridge_error, sizeof bridge_error,
            "image library %s is from another build (interface version %d, want %d); rebuild "
            "with make", path, api ? api->version : -1, SUMI_OIIO_API_VERSION);
    dlclose(lib);
    return 0;
  }
  bridge = api;                /* never dlclose'd: OIIO keeps threads and state */
  return 1;
}

static void bridge_init(void) {
  char dir[PATH_MAX], path[PATH_MAX + 64];
  if (!exe_dir(dir, sizeof dir)) {
    set_err(bridge_error, sizeof bridge_error,
            "cannot find the image library: /proc/self/exe is unreadable");
    return;
  }
  static const char *const places[] = { "/", "/../lib/sumi/", "/../" };
  double t0 = now_seconds();
  for (size_t i = 0; i < sizeof places / sizeof places[0]; i++) {
    snprintf(path, sizeof path, "%s%s" BRIDGE_NAME, dir, places[i]);
    if (access(path, F_OK) != 0) continue;
    if (bridge_open(path)) bridge_seconds = now_seconds() - t0;
    return;
  }
  set_err(bridge_error, sizeof bridge_error,
          "cannot find the image library " BRIDGE_NAME " beside %s or in its ../lib/sumi/ "
          "(build it with make)", dir);
}

static double bridge_waited;     /* seconds callers spent blocked in image_bridge_load */
static pthread_mutex_t waited_lock = PTHREAD_MUTEX_INITIALIZER;

int image_bridge_load(char *err, size_t errlen) {
  double t0 = now_seconds();
  pthread_once(&bridge_once, bridge_init);
  pthread_mutex_lock(&waited_lock);
  bridge_waited += now_seconds() - t0;
  pthread_mutex_unlock(&waited_lock);
  if (!bridge) set_err(err, errlen, "%s", bridge_error);
  return bridge != NULL;
}

double image_bridge_load_seconds(void) {
  return bridge_seconds;
}

double image_bridge_wait_seconds(void) {
  pthread_mutex_lock(&waited_lock);
  double w = bridge_waited;
  pthread_mutex_unlock(&waited_lock);
  return w;
}

static pthread_mutex_t prefetch_lock = PTHREAD_MUTEX_INITIALIZER;
static pthread_t prefetch_thread;
static int prefetch_state;   /* 0 none, 1 running, 2 joined */

static void *prefetch_main(void *arg) {
  (void)arg;
  pthread_once(&bridge_once, bridge_init);   /* not image_bridge_load: no caller waits here */
  return NULL;
}

void image_bridge_prefetch(void) {
  pthread_mutex_lock(&prefetch_lock);
  if (prefetch_state == 0 && pthread_create(&prefetch_thread, NULL, prefetch_main, NULL) == 0)
    prefetch_state = 1;   /* if the thread cannot start, the first use loads it */
  pthread_mutex_unlock(&prefetch_lock);
}

void image_bridge_join(void) {
  pthread_mutex_lock(&prefetch_lock);
  if (prefetch_state == 1) {
    pthread_join(prefetch_thread, NULL);
    prefetch_state = 2;
  }
  pthread_mutex_unlock(&prefetch_lock);
}

/* ---- writing ------------------------------------------------------------ */

/* Formats by extension. */
typedef enum { FMT_NONE, FMT_PNG, FMT_TIFF, FMT_JPEG, FMT_EXR } ImageFormat;

/* The extension of path's last component (after its last dot), or NULL. */
static const char *path_extension(const char *path) {
  const char *slash = strrchr(path, '/');
  const char *base = slash ? slash + 1 : path;
  const char *dot = strrchr(base, '.');
  return dot && dot != base ? dot + 1 : NULL;
}

static ImageFormat format_of(const char *path) {
  const char *ext = path_extension(path);
  if (!ext) return FMT_NONE;
  if (!strcasecmp(ext, "png")) return FMT_PNG;
  if (!strcasecmp(ext, "tif") || !strcasecmp(ext, "tiff")) return FMT_TIFF;
  if (!strcasecmp(ext, "jpg") || !strcasecmp(ext, "jpeg")) return FMT_JPEG;
  if (!strcasecmp(ext, "exr")) return FMT_EXR;
  return FMT_NONE;
}

/* Build "dir/stem.tmp-PID-SEQ.ext" for path into tmp and create it
** exclusively (so it is ours). Returns 1, or 0 with errno set. */
static int make_temp(const char *path, char *tmp, size_t size) {
  static unsigned seq;  /* distinguishes concurrent writes to one path */
  const char *ext = path_extension(path);
  size_t stem = ext ? (size_t)(ext - 1 - path) : strlen(path);
  for (int tries = 0; tries < TMP_NAME_TRIES; tries++) {
    unsigned n = __atomic_fetch_add(&seq, 1, __ATOMIC_RELAXED);
    int len = snprintf(tmp, size, "%.*s.tmp-%ld-%u%s%s", (int)stem, path, (long)getpid(), n,
                       ext ? "." : "", ext ? ext : "");
    if (len < 0 || (size_t)len >= size) {
      errno = ENAMETOOLONG;
      return 0;
    }
    int fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      close(fd);
      tempfile_add(tmp);   /* removed if a signal ends the program before the rename */
      return 1;
    }
    if (errno != EEXIST) return 0;
  }
  return 0;
}

/* Load the bridge (unless the file is a PNG, which libpng writes) and
** create the temporary file for path in tmp (size bytes). Returns 1, or 0
** with the reason in err. */
static int begin_write(const char *path, char *tmp, size_t size, char *err, size_t errlen) {
  char why[768];
  if (format_of(path) != FMT_PNG && !image_bridge_load(why, sizeof why)) {
    set_err(err, errlen, "cannot write '%s': %s", path, why);
    return 0;
  }
  if (!make_temp(path, tmp, size)) {
    set_err(err, errlen, "cannot write '%s': %s", path, strerror(errno));
    return 0;
  }
  return 1;
}

/* Rename the written tmp to path; on failure remove it. */
static int end_write(const char *path, const char *tmp, char *err, size_t errlen) {
  if (rename(tmp, path) == 0) {
    tempfile_forget(tmp);
    return 1;
  }
  int e = errno;
  tempfile_discard(tmp);
  set_err(err, errlen, "cannot write '%s': %s", path, strerror(e));
  return 0;
}

/* Open the temporary file tmp as a PNG of px's size (8- or 16-bit codes);
** NULL with the reason in err, the file left for the caller to remove. */
static PngOut *png_begin(const char *path, const char *tmp, const SumiOiioPixels *px, const ImageTile *tile,
                         FILE **f, char *err, size_t errlen) {
  char why[512], text[256];
  PngPlace place = {0, 0, "Description", text};
  if (tile) {
    place.x = tile->x, place.y = tile->y;
    image_tile_format(tile, text, sizeof text);
  }
  *f = fopen(tmp, "wb");
  PngOut *p = *f ? png_out_open(*f, px->width, px->height, px->channels, px->type == SUMI_OIIO_UINT16 ? 16 : 8,
                                tile ? &place : NULL, why, sizeof why) : NULL;
  if (p) return p;
  set_err(err, errlen, "cannot write '%s': %s", path, *f ? why : strerror(errno));
  if (*f) fclose(*f);
  *f = NULL;
  return NULL;
}

/* Finish the PNG p on f, closing both; ok says whether every step so far
** worked. Returns 1, or 0, with the reason of a failure in this step in
** why (n bytes; an earlier one is left there). */
static int png_end(PngOut *p, FILE *f, int ok, char *why, size_t n) {
  if (!png_out_close(p, why, ok ? n : 0)) ok = 0;
  int bad = ferror(f);
  if ((fclose(f) != 0 || bad) && ok) {
    set_err(why, n, "%s", strerror(errno ? errno : EIO));
    ok = 0;
  }
  return ok;
}

/* Write px as a PNG through libpng into tmp. */
static int write_png(const char *path, const char *tmp, const SumiOiioPixels *px, const ImageTile *tile,
                     char *err, size_t errlen) {
  FILE *f;
  PngOut *p = png_begin(path, tmp, px, tile, &f, err, errlen);
  if (!p) return 0;
  char why[512] = "";
  int ok = png_out_rows(p, px->data, px->height, why, sizeof why);
  if (png_end(p, f, ok, why, sizeof why)) return 1;
  set_err(err, errlen, "cannot write '%s': %s", path, why);
  return 0;
}

/* w with tile's place in it (text: room for its description). */
static SumiOiioWrite placed(const SumiOiioWrite *w, const ImageTile *tile, char *text, size_t n) {
  SumiOiioWrite out = *w;
  if (!tile) return out;
  out.x = tile->x, out.y = tile->y;
  out.full_width = tile->full_width, out.full_height = tile->full_height;
  image_tile_format(tile, text, n);
  out.description = text;
  return out;
}

/* Write px through libpng (a PNG) or the bridge to a temporary file, then
** rename it to path, placed as tile says (NULL: not a tile). On any
** failure the temporary file is removed. */
static int write_atomic(const char *path, const SumiOiioPixels *px, const SumiOiioWrite *w,
                        const ImageTile *tile, char *err, size_t errlen) {
  char tmp[PATH_MAX + 64], why[768], text[256];
  if (!begin_write(path, tmp, sizeof tmp, err, errlen)) return 0;
  if (format_of(path) == FMT_PNG) {
    if (!write_png(path, tmp, px, tile, err, errlen)) {
      tempfile_discard(tmp);
      return 0;
    }
    return end_write(path, tmp, err, errlen);
  }
  SumiOiioWrite how = placed(w, tile, text, sizeof text);
  if (!bridge->write(tmp, px, &how, why, sizeof why)) {
    tempfile_discard(tmp);
    set_err(err, errlen, "cannot write '%s': %s", path, why);
    return 0;
  }
  return end_write(path, tmp, err, errlen);
}

/* ---- streamed writing ------------------------------------------------- */

struct ImageStream {
  SumiOiioStream *out;        /* through the bridge, or */
  PngOut *png;                /* a PNG through libpng, on */
  FILE *file;
  int width, height, channels;
  int next;                   /* the first row not yet written */
  int failed;                 /* why holds the first failure */
  char why[768];
  char path[PATH_MAX], tmp[PATH_MAX + 64];
};

int image_stream_fits(const char *path, int nc) {
  ImageFormat fmt = format_of(path);
  return nc >= 1 && nc <= 4 && (fmt == FMT_PNG || fmt == FMT_TIFF || (fmt == FMT_JPEG && nc % 2));
}

ImageStream *image_stream_open(const char *path, int w, int h, int nc, char *err, size_t errlen) {
  return image_stream_open_tile(path, w, h, nc, NULL, err, errlen);
}

ImageStream *image_stream_open_tile(const char *path, int w, int h, int nc, const ImageTile *tile, char *err,
                                    size_t errlen) {
  if (!image_stream_fits(path, nc) || strlen(path) >= PATH_MAX) {
    set_err(err, errlen, "cannot write '%s': not an 8-bit image file for %d channels", path, nc);
    return NULL;
  }
  ImageStream *s = xcalloc(1, sizeof *s);
  if (!begin_write(path, s->tmp, sizeof s->tmp, err, errlen)) {
    free(s);
    return NULL;
  }
  snprintf(s->path, sizeof s->path, "%s", path);
  s->width = w;
  s->height = h;
  s->channels = nc;
  int ac = nc == 2 || nc == 4 ? nc - 1 : -1;
  SumiOiioPixels px = {w, h, nc, SUMI_OIIO_UINT8, ac, NULL, "", 0, 0, 0, 0, ""};
  SumiOiioWrite plain = {0, NULL, "sRGB", 0, 0, 0, 0, 0, NULL};   /* what write_encoded gives an 8-bit image */
  char text[256];
  SumiOiioWrite how = placed(&plain, tile, text, sizeof text);
  if (format_of(path) == FMT_PNG) {
    if ((s->png = png_begin(path, s->tmp, &px, tile, &s->file, err, errlen))) return s;
    tempfile_discard(s->tmp);
    free(s);
    return NULL;
  }
  s->out = bridge->stream_open(s->tmp, &px, &how, s->why, sizeof s->why);
  if (!s->out) {
    tempfile_discard(s->tmp);
    set_err(err, errlen, "cannot write '%s': %s", path, s->why);
    free(s);
    return NULL;
  }
  return s;
}

void image_stream_rows(ImageStream *s, int y0, int y1, const uint8_t *codes) {
  if (!s->failed && !(s->png ? png_out_rows(s->png, codes, y1 - y0, s->why, sizeof s->why)
                             : bridge->stream_rows(s->out, y0, y1, codes, s->why, sizeof s->why)))
    s->failed = 1;
  s->next = y1;
}

/* Close s's file: 0 with the reason in s->why (unless one is there) when that fails. */
static int stream_finish(ImageStream *s) {
  if (s->png) return png_end(s->png, s->file, !s->failed, s->why, sizeof s->why);
  char why[768];
  if (bridge->stream_close(s->out, why, sizeof why)) return 1;
  if (!s->failed) memcpy(s->why, why, sizeof why);
  return 0;
}

void image_stream_discard(ImageStream *s) {
  /* blank rows to the end first: a format library closing a short image
  ** complains on standard error */
  uint8_t *blank = xcalloc((size_t)s->width * (size_t)s->channels, 1);
  while (s->next < s->height) image_stream_rows(s, s->next, s->next + 1, blank);
  free(blank);
  stream_finish(s);
  tempfile_discard(s->tmp);
  free(s);
}

int image_stream_close(ImageStream *s, char *err, size_t errlen) {
  if (!stream_finish(s)) s->failed = 1;
  int ok = 0;
  if (s->failed) {
    tempfile_discard(s->tmp);
    set_err(err, errlen, "cannot write '%s': %s", s->path, s->why);
  } else {
    ok = end_write(s->path, s->tmp, err, errlen);
  }
  free(s);
  return ok;
}

/* Colour channels of img in file order as 8- or 16-bit codes, dropping
** alpha (always the last channel) when keep_alpha is 0, for JPEG. Returns
** malloc'ed data, *nch set. */
static void *encode_integer(const Image *img, int bits, int keep_alpha, int *nch) {
  pthread_once(&srgb_once, srgb_init);
  int ac = image_alpha_channel(img), in_ch = img->channels;
  int out_ch = (ac >= 0 && !keep_alpha) ? in_ch - 1 : in_ch;
  size_t npix = (size_t)img->width * (size_t)img->height;
  void *out = xmalloc(npix * (size_t)in_ch * (bits == 16 ? 2 : 1));
  if (bits == 16) {
    uint16_t *o16 = out;
    for (size_t i = 0; i < npix * (size_t)in_ch; i++)
      o16[i] = (int)(i % (size_t)in_ch) == ac ? alpha16(img->data[i]) : encode16(img->data[i]);
  } else if (img->data8) {
    memcpy(out, img->data8, npix * (size_t)in_ch);
  } else {
    encode_pixels8(img->data, out, npix, in_ch, ac);
  }
  if (out_ch < in_ch) {                 /* squeeze out alpha, in place, 8-bit only */
    uint8_t *o8 = out;
    for (size_t p = 0; p < npix; p++)
      memmove(o8 + p * (size_t)out_ch, o8 + p * (size_t)in_ch, (size_t)out_ch);
  }
  *nch = out_ch;
  return out;
}

/* A copy of img with colour multiplied by alpha (EXR's convention). */
static float *associate_alpha(const Image *img) {
  int nc = img->channels, ac = image_alpha_channel(img);
  size_t npix = (size_t)img->width * (size_t)img->height;
  float *out = xmalloc(image_values(img) * sizeof(float));
  memcpy(out, img->data, image_values(img) * sizeof(float));
  for (size_t p = 0; p < npix; p++) {
    float *px = out + p * (size_t)nc;
    for (int c = 0; c < nc; c++)
      if (c != ac) px[c] *= px[ac];
  }
  return out;
}

static int write_exr(const char *path, const Image *img, const ImageWriteOptions *opt,
                     char *err, size_t errlen) {
  int ac = image_alpha_channel(img);
  float *assoc = ac >= 0 ? associate_alpha(img) : NULL;
  SumiOiioPixels px = { img->width, img->height, img->channels, SUMI_OIIO_FLOAT, ac,
                        assoc ? assoc : img->data, "", 0, 0, 0, 0, "" };
  SumiOiioWrite w = { opt->exr_half ? SUMI_OIIO_HALF : SUMI_OIIO_FLOAT, NULL, "Linear", 0, 0, 0, 0, 0, NULL };
  int ok = write_atomic(path, &px, &w, opt->tile, err, errlen);
  free(assoc);
  return ok;
}

static int write_encoded(const char *path, ImageFormat fmt, const Image *img,
                         const ImageWriteOptions *opt, char *err, size_t errlen) {
  int bits = fmt == FMT_JPEG ? 8 : opt->bits ? opt->bits : 8;
  if (bits != 8 && bits != 16) {
    set_err(err, errlen, "cannot write '%s': %d bits per channel (use 8 or 16)", path, bits);
    return 0;
  }
  int keep_alpha = fmt != FMT_JPEG, nch = img->channels;
  int as_is = img->data8 && bits == 8 && (keep_alpha || image_alpha_channel(img) < 0);
  void *codes = as_is ? img->data8 : encode_integer(img, bits, keep_alpha, &nch);
  int ac = keep_alpha ? image_alpha_channel(img) : -1;
  SumiOiioPixels px = { img->width, img->height, nch, bits == 16 ? SUMI_OIIO_UINT16 : SUMI_OIIO_UINT8,
                        ac, codes, "", 0, 0, 0, 0, "" };
  SumiOiioWrite w = { 0, NULL, "sRGB", opt->jpeg_quality, 0, 0, 0, 0, NULL };
  int ok = write_atomic(path, &px, &w, opt->tile, err, errlen);
  if (!as_is) free(codes);
  return ok;
}

int image_write_opts(const char *path, const Image *img, const ImageWriteOptions *opt,
                     char *err, size_t errlen) {
  static const ImageWriteOptions defaults;
  if (!opt) opt = &defaults;
  ImageFormat fmt = format_of(path);
  if (fmt == FMT_NONE) {
    const char *ext = path_extension(path);
    set_err(err, errlen, "cannot write '%s': %s '%s%s' (use .png, .tif, .jpg or .exr)", path,
            ext ? "unknown image format" : "no image format extension", ext ? "." : "",
            ext ? ext : "");
    return 0;
  }
  if (!img || img->width <= 0 || img->height <= 0 || img->channels < 1 ||
      (fmt != FMT_EXR && img->channels > 4) || img->channels > IMAGE_MAX_CHANNELS) {
    set_err(err, errlen, "cannot write '%s': %d channels do not make a colour image", path,
            img ? img->channels : 0);
    return 0;
  }
  if (img->data8 && (fmt == FMT_EXR || (opt->bits && opt->bits != 8))) {
    /* more precision than the image has: write its codes' values */
    Image *f = image_create(img->width, img->height, img->channels);
    image_decode8(img->data8, f->data, (size_t)img->width * img->height, img->channels);
    int ok = image_write_opts(path, f, opt, err, errlen);
    image_destroy(f);
    return ok;
  }
  if (fmt == FMT_EXR) return write_exr(path, img, opt, err, errlen);
  return write_encoded(path, fmt, img, opt, err, errlen);
}

int image_write_needs_bridge(const char *path) {
  return format_of(path) != FMT_PNG;
}

int image_read_needs_bridge(const char *name) {
  const char *ext = path_extension(name);
  return ext && strcasecmp(ext, "png") != 0;
}

int image_keeps_tiles(const char *path) {
  ImageFormat fmt = format_of(path);
  return fmt == FMT_PNG || fmt == FMT_TIFF || fmt == FMT_EXR;
}

int image_write_is_8bit(const char *path) {
  ImageFormat fmt = format_of(path);
  return fmt == FMT_PNG || fmt == FMT_TIFF || fmt == FMT_JPEG;
}

int image_write(const char *path, const Image *img, char *err, size_t errlen) {
  return image_write_opts(path, img, NULL, err, errlen);
}

/* 0 with a message unless names holds nch distinct, non-empty names. */
static int check_channel_names(const char *path, int nch, const char **names, char *err,
                               size_t errlen) {
  for (int c = 0; c < nch; c++) {
    if (!names || !names[c] || !names[c][0]) {
      set_err(err, errlen, "cannot write '%s': channel %d has no name", path, c);
      return 0;
    }
    for (int d = 0; d < c; d++)
      if (!strcmp(names[c], names[d])) {
        set_err(err, errlen, "cannot write '%s': channel name '%s' appears twice", path,
                names[c]);
        return 0;
      }
  }
  return 1;
}

int image_write_aov_exr(const char *path, int w, int h, int nch, const char **channel_names,
                        const float *data, char *err, size_t errlen) {
  if (format_of(path) != FMT_EXR) {
    set_err(err, errlen, "cannot write '%s': AOVs are written as .exr", path);
    return 0;
  }
  if (w <= 0 || h <= 0 || nch < 1 || nch > IMAGE_MAX_CHANNELS) {
    set_err(err, errlen, "cannot write '%s': bad AOV size %dx%d with %d channels (at most %d)",
            path, w, h, nch, IMAGE_MAX_CHANNELS);
    return 0;
  }
  if (!check_channel_names(path, nch, channel_names, err, errlen)) return 0;
  int ac = -1;
  for (int c = 0; c < nch; c++)
    if (!strcmp(channel_names[c], "A")) ac = c;
  SumiOiioPixels px = { w, h, nch, SUMI_OIIO_FLOAT, ac, (void *)data, "", 0, 0, 0, 0, "" };
  SumiOiioWrite wr = { SUMI_OIIO_FLOAT, (const char *const *)channel_names, NULL, 0, 0, 0, 0, 0, NULL };
  return write_atomic(path, &px, &wr, NULL, err, errlen);
}

int image_write_ids_tiff(const char *path, int w, int h, const int32_t *ids, char *err,
                         size_t errlen) {
  if (format_of(path) != FMT_TIFF) {
    set_err(err, errlen, "cannot write '%s': id images are written as .tif", path);
    return 0;
  }
  if (w <= 0 || h <= 0) {
    set_err(err, errlen, "cannot write '%s': bad size %dx%d", path, w, h);
    return 0;
  }
  static const char *const names[] = { "id" };
  SumiOiioPixels px = { w, h, 1, SUMI_OIIO_INT32, -1, (void *)ids, "", 0, 0, 0, 0, "" };
  SumiOiioWrite wr = { SUMI_OIIO_INT32, names, NULL, 0, 0, 0, 0, 0, NULL };
  return write_atomic(path, &px, &wr, NULL, err, errlen);
}

/* ---- reading ------------------------------------------------------------ */

static void too_large(const char *path, const SumiOiioPixels *px, char *err, size_t errlen) {
  set_err(err, errlen,
          "cannot read '%s': image too large: %dx%d with %d channels (limits: %lld pixels, "
          "IMAGE_READ_MAX_PIXELS; %d on a side, IMAGE_READ_MAX_SIDE; %d channels, "
          "IMAGE_MAX_CHANNELS; %lld values, IMAGE_READ_MAX_VALUES)", path, px->width,
          px->height, px->channels, IMAGE_READ_MAX_PIXELS, IMAGE_READ_MAX_SIDE,
          IMAGE_MAX_CHANNELS, IMAGE_READ_MAX_VALUES);
}

/* A PNG through libpng, as the bridge would hand it over. */
static int read_png(const char *path, SumiOiioPixels *px, char *err, size_t errlen) {
  char why[512];
  int bits, big;
  memset(px, 0, sizeof *px);
  if (!png_read_file(path, IMAGE_READ_MAX_PIXELS, &px->width, &px->height, &px->channels, &bits,
                     &px->data, &big, why, sizeof why)) {
    if (big) too_large(path, px, err, errlen);
    else set_err(err, errlen, "cannot read '%s': corrupt or truncated image (%s)", path, why);
    return 0;
  }
  px->type = bits == 16 ? SUMI_OIIO_UINT16 : SUMI_OIIO_UINT8;
  px->alpha_channel = px->channels == 2 || px->channels == 4 ? px->channels - 1 : -1;
  snprintf(px->format, sizeof px->format, "png");
  return 1;
}

/* Read path through libpng (a PNG, by its signature) or the bridge as
** want (0: the file's own class). Checks that path names a regular file
** first, for a clear message. */
static int read_pixels(const char *path, int want, SumiOiioPixels *px, char *err,
                       size_t errlen) {
  char why[768];
  if (!infile_check(path, INFILE_MAX_IMAGE, "an image", why, sizeof why)) {
    set_err(err, errlen, "cannot read '%s': %s", path, why);
    return 0;
  }
  if (want == 0 && png_is_png_file(path)) return read_png(path, px, err, errlen);
  if (!image_bridge_load(why, sizeof why)) {
    set_err(err, errlen, "cannot read '%s': %s", path, why);
    return 0;
  }
  static const SumiOiioLimits limits = { IMAGE_READ_MAX_PIXELS, IMAGE_READ_MAX_SIDE,
                                         IMAGE_MAX_CHANNELS, IMAGE_READ_MAX_VALUES };
  int r = bridge->read(path, want, &limits, px, why, sizeof why);
  if (r == SUMI_OIIO_OK) return 1;
  if (r == SUMI_OIIO_TOO_LARGE) too_large(path, px, err, errlen);
  else
    set_err(err, errlen, "cannot read '%s': %s (%s)", path,
            r == SUMI_OIIO_NOT_IMAGE ? "not an image sumi can read" : "corrupt or truncated image",
            why);
  return 0;
}

int image_file_reads_whole(const char *path) {
  if (format_of(path) == FMT_PNG) return png_file_complete(path);
  char why[512];
  return image_bridge_load(why, sizeof why) && bridge->complete(path, why, sizeof why);
}

/* Fill img from integer codes: sRGB-decoded colour, linear alpha. */
static void decode_integer(Image *img, const SumiOiioPixels *px) {
  pthread_once(&srgb_once, srgb_init);
  int nc = img->channels, ac = px->alpha_channel;
  size_t npix = (size_t)img->width * (size_t)img->height;
  const uint8_t *in8 = px->data;
  const uint16_t *in16 = px->data;
  for (size_t p = 0; p < npix; p++) {
    float *dst = img->data + p * (size_t)nc;
    for (int c = 0; c < nc; c++) {
      size_t i = p * (size_t)nc + (size_t)c;
      if (px->type == SUMI_OIIO_UINT8)
        dst[c] = c == ac ? in8[i] / 255.0f : srgb_decode[in8[i]];
      else
        dst[c] = c == ac ? in16[i] / 65535.0f : (float)srgb_to_linear_d(in16[i] / 65535.0);
    }
  }
}

/* Divide colour by alpha where alpha is not 0 (EXR stores it multiplied). */
static void dissociate_alpha(Image *img) {
  int nc = img->channels, ac = image_alpha_channel(img);
  size_t npix = (size_t)img->width * (size_t)img->height;
  for (size_t p = 0; p < npix; p++) {
    float *q = img->data + p * (size_t)nc;
    if (q[ac] == 0.0f) continue;
    for (int c = 0; c < nc; c++)
      if (c != ac) q[c] /= q[ac];
  }
}

int image_read(const char *path, Image **out, char *err, size_t errlen) {
  *out = NULL;
  SumiOiioPixels px;
  if (!read_pixels(path, 0, &px, err, errlen)) return 0;
  Image *img = image_create(px.width, px.height, px.channels);
  size_t n = image_values(img);
  if (px.type == SUMI_OIIO_UINT8 || px.type == SUMI_OIIO_UINT16) {
    decode_integer(img, &px);
  } else if (px.type == SUMI_OIIO_INT32) {
    const int32_t *ids = px.data;
    for (size_t i = 0; i < n; i++) img->data[i] = (float)ids[i];
  } else {
    memcpy(img->data, px.data, n * sizeof(float));
    if (!strcmp(px.format, "openexr") && image_alpha_channel(img) >= 0 &&
        px.alpha_channel == image_alpha_channel(img))
      dissociate_alpha(img);
  }
  free(px.data);
  *out = img;
  return 1;
}

int image_read_ids(const char *path, int *w, int *h, int32_t **ids, char *err, size_t errlen) {
  *ids = NULL;
  SumiOiioPixels px;
  if (!read_pixels(path, SUMI_OIIO_INT32, &px, err, errlen)) return 0;
  if (px.channels != 1) {
    set_err(err, errlen, "cannot read '%s': an id image has 1 channel, this has %d", path,
            px.channels);
    free(px.data);
    return 0;
  }
  *w = px.width;
  *h = px.height;
  *ids = px.data;
  return 1;
}

/* ---- tiles: their description, and pixels as stored ----------------------- */

void image_tile_format(const ImageTile *t, char *buf, size_t n) {
  snprintf(buf, n, "sumi tile %s of %dx%d at %d,%d render %s", t->name, t->full_width, t->full_height, t->x,
           t->y, t->render);
}

int image_tile_parse(const char *text, ImageTile *t) {
  ImageTile u;
  memset(&u, 0, sizeof u);
  int end = 0;
  if (sscanf(text, "sumi tile %31s of %dx%d at %d,%d render %31s%n", u.name, &u.full_width, &u.full_height, &u.x,
             &u.y, u.render, &end) != 6 || text[end] != 0)
    return 0;
  if (u.full_width < 1 || u.full_height < 1 || u.x < 0 || u.y < 0) return 0;
  *t = u;
  return 1;
}

int image_read_raw(const char *path, ImageRaw *raw, char *err, size_t errlen) {
  memset(raw, 0, sizeof *raw);
  SumiOiioPixels px;
  if (!read_pixels(path, 0, &px, err, errlen)) return 0;
  raw->width = px.width;
  raw->height = px.height;
  raw->channels = px.channels;
  raw->type = px.type == SUMI_OIIO_UINT8 ? IMAGE_RAW_U8 : px.type == SUMI_OIIO_UINT16 ? IMAGE_RAW_U16
                                                                                      : IMAGE_RAW_FLOAT;
  raw->data = px.data;
  snprintf(raw->format, sizeof raw->format, "%s", px.format);
  if (px.type == SUMI_OIIO_INT32) {
    set_err(err, errlen, "cannot read '%s': an id image is not a colour image", path);
    image_raw_free(raw);
    return 0;
  }
  char text[256] = "";
  raw->x = px.x, raw->y = px.y, raw->full_width = px.full_width, raw->full_height = px.full_height;
  if (!strcmp(px.format, "png")) {
    png_read_place(path, "Description", text, sizeof text, &raw->x, &raw->y);
    raw->full_width = raw->full_height = 0;   /* PNG has no field for it */
  } else {
    snprintf(text, sizeof text, "%s", px.description);
  }
  if (raw->full_width <= 0) raw->full_width = px.width, raw->full_height = px.height;
  raw->has_tile = image_tile_parse(text, &raw->tile);
  return 1;
}

int image_write_raw(const char *path, const ImageRaw *raw, char *err, size_t errlen) {
  ImageFormat fmt = format_of(path);
  int ac = raw->channels == 2 || raw->channels == 4 ? raw->channels - 1 : -1;
  if (raw->type == IMAGE_RAW_FLOAT) {
    if (fmt != FMT_EXR) {
      set_err(err, errlen, "cannot write '%s': the pixels are floats (from an .exr): write an .exr", path);
      return 0;
    }
    SumiOiioPixels px = {raw->width, raw->height, raw->channels, SUMI_OIIO_FLOAT, ac, raw->data, "", 0, 0, 0, 0, ""};
    SumiOiioWrite w = {SUMI_OIIO_FLOAT, NULL, "Linear", 0, 0, 0, 0, 0, NULL};   /* as write_exr, the colour already multiplied */
    return write_atomic(path, &px, &w, NULL, err, errlen);
  }
  if (fmt == FMT_EXR || fmt == FMT_NONE || raw->channels > 4) {
    set_err(err, errlen, "cannot write '%s': the pixels are %d-bit codes: write a .png, .tif or .jpg", path,
            raw->type == IMAGE_RAW_U16 ? 16 : 8);
    return 0;
  }
  if (raw->type == IMAGE_RAW_U16 || (fmt == FMT_JPEG && ac >= 0)) {   /* as write_encoded gives them */
    if (fmt == FMT_JPEG) {
      set_err(err, errlen, "cannot write '%s': JPEG keeps 8 bits and no alpha", path);
      return 0;
    }
    SumiOiioPixels px = {raw->width, raw->height, raw->channels, SUMI_OIIO_UINT16, ac, raw->data, "", 0, 0, 0, 0, ""};
    SumiOiioWrite w = {0, NULL, "sRGB", 0, 0, 0, 0, 0, NULL};
    return write_atomic(path, &px, &w, NULL, err, errlen);
  }
  Image img = {raw->width, raw->height, raw->channels, NULL, raw->data};
  return image_write(path, &img, err, errlen);
}

void image_raw_free(ImageRaw *raw) {
  free(raw->data);
  memset(raw, 0, sizeof *raw);
}
