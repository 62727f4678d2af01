/*
** PNG writing and reading through libpng (see png_file.h). libpng reports
** errors by longjmp to the setjmp of the call that was running: every
** function here that calls into libpng sets one, and the message handler
** keeps libpng's reason for our one-line error instead of printing it.
*/
#include "png_file.h"

#include <png.h>
#include <setjmp.h>
#include <stdlib.h>
#include <string.h>

#include "../base/mem.h"

/* libpng's messages go here (the error pointer of each struct), not to stderr. */
typedef struct PngMsg { char text[256]; } PngMsg;

static void on_error(png_structp png, png_const_charp msg) {
  PngMsg *m = png_get_error_ptr(png);
  if (m) snprintf(m->text, sizeof m->text, "%s", msg);
  png_longjmp(png, 1);
}

static void on_warning(png_structp png, png_const_charp msg) { (void)png, (void)msg; }

static int host_little_endian(void) {
  const uint16_t one = 1;
  return *(const uint8_t *)&one == 1;
}

static void put_err(char *err, size_t errlen, const char *what, const PngMsg *m) {
  if (err && errlen) snprintf(err, errlen, "%s%s%s", what, m->text[0] ? ": " : "", m->text);
}

/* ---- writing ---------------------------------------------------------------- */

struct PngOut {
  png_structp png;
  png_infop info;
  int w, nc, bits;
  int failed;
  PngMsg msg;
};

static void out_free(PngOut *p) {
  png_destroy_write_struct(&p->png, &p->info);
  free(p);
}

PngOut *png_out_open(FILE *f, int w, int h, int nc, int bits, const PngPlace *place, char *err,
                     size_t errlen) {
  static const int color_type[5] = {0, PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA,
                                    PNG_COLOR_TYPE_RGB, PNG_COLOR_TYPE_RGB_ALPHA};
  PngOut *p = xcalloc(1, sizeof *p);
  p->w = w, p->nc = nc, p->bits = bits;
  p->png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &p->msg, on_error, on_warning);
  p->info = p->png ? png_create_info_struct(p->png) : NULL;
  if (!p->info) {
    snprintf(p->msg.text, sizeof p->msg.text, "out of memory");
    put_err(err, errlen, "libpng", &p->msg);
    out_free(p);
    return NULL;
  }
  if (setjmp(png_jmpbuf(p->png))) {
    put_err(err, errlen, "libpng", &p->msg);
    out_free(p);
    return NULL;
  }
  png_init_io(p->png, f);
  png_set_IHDR(p->png, p->info, (png_uint_32)w, (png_uint_32)h, bits, color_type[nc], PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_sRGB_gAMA_and_cHRM(p->png, p->info, PNG_sRGB_INTENT_PERCEPTUAL);
  if (place) {   /* a tile: its offset (oFFs, in pixels) and the text that places it */
    png_set_oFFs(p->png, p->info, place->x, place->y, PNG_OFFSET_PIXEL);
    png_text t;
    memset(&t, 0, sizeof t);
    t.compression = PNG_TEXT_COMPRESSION_NONE;
    t.key = (png_charp)place->key;
    t.text = (png_charp)place->text;
    png_set_text(p->png, p->info, &t, 1);
  }
  png_set_filter(p->png, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE);
  png_set_compression_level(p->png, PNG_LEVEL);
  png_write_info(p->png, p->info);
  if (bits == 16 && host_little_endian()) png_set_swap(p->png);   /* PNG stores 16 bits big-endian */
  return p;
}

int png_out_rows(PngOut *p, const void *codes, int n, char *err, size_t errlen) {
  if (p->failed) return 0;
  if (setjmp(png_jmpbuf(p->png))) {
    p->failed = 1;
    put_err(err, errlen, "libpng", &p->msg);
    return 0;
  }
  size_t row = (size_t)p->w * (size_t)p->nc * (size_t)(p->bits / 8);
  for (int i = 0; i < n; i++) png_write_row(p->png, (png_const_bytep)codes + (size_t)i * row);
  return 1;
}

int png_out_close(PngOut *p, char *err, size_t errlen) {
  if (p->failed) {
    out_free(p);
    return 0;
  }
  if (setjmp(png_jmpbuf(p->png))) {
    put_err(err, errlen, "libpng", &p->msg);
    out_free(p);
    return 0;
  }
  png_write_end(p->png, NULL);
  out_free(p);
  return 1;
}

/* ---- reading ---------------------------------------------------------------- */

int png_is_png_file(const char *path) {
  unsigned char sig[8];
  FILE *f = fopen(path, "rb");
  if (!f) return 0;
  size_t n = fread(sig, 1, sizeof sig, f);
  fclose(f);
  return n == sizeof sig && png_sig_cmp(sig, 0, sizeof sig) == 0;
}

/* What a read holds, freed on every way out (volatile: set between setjmp
** and a longjmp). */
typedef struct PngIn {
  png_structp png;
  png_infop info;
  FILE *f;
  unsigned char *volatile data;
  png_bytep *volatile rows;
  PngMsg msg;
} PngIn;

static void in_free(PngIn *r) {
  png_destroy_read_struct(&r->png, r->info ? &r->info : NULL, NULL);
  if (r->f) fclose(r->f);
  free(r->rows);
}

/* After png_read_info: the transforms that give 8- or 16-bit grey, grey +
** alpha, RGB or RGBA; the row layout is checked against them. */
static int read_layout(PngIn *r, int w, int *nc, int *bits) {
  png_set_expand(r->png);                 /* palette -> RGB, tRNS -> alpha, 1-4 bit grey -> 8 */
  png_set_interlace_handling(r->png);
  if (png_get_bit_depth(r->png, r->info) == 16 && host_little_endian()) png_set_swap(r->png);
  png_read_update_info(r->png, r->info);
  *nc = png_get_channels(r->png, r->info);
  *bits = png_get_bit_depth(r->png, r->info);
  return *nc >= 1 && *nc <= 4 && (*bits == 8 || *bits == 16) &&
         png_get_rowbytes(r->png, r->info) == (size_t)w * (size_t)*nc * (size_t)(*bits / 8);
}

int png_read_place(const char *path, const char *key, char *out, size_t n, int *x, int *y) {
  PngIn r;
  memset(&r, 0, sizeof r);
  volatile int found = 0;   /* set between setjmp and a longjmp */
  if (n) out[0] = 0;
  if (!(r.f = fopen(path, "rb"))) return 0;
  r.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &r.msg, on_error, on_warning);
  r.info = r.png ? png_create_info_struct(r.png) : NULL;
  if (!r.info || setjmp(png_jmpbuf(r.png))) {
    in_free(&r);
    return 0;
  }
  png_init_io(r.png, r.f);
  png_read_info(r.png, r.info);   /* the chunks before the image data */
  png_int_32 ox = 0, oy = 0;
  int unit = 0;
  *x = *y = 0;
  if (png_get_oFFs(r.png, r.info, &ox, &oy, &unit) && unit == PNG_OFFSET_PIXEL) *x = ox, *y = oy;
  png_textp text;
  int count = 0;
  png_get_text(r.png, r.info, &text, &count);
  for (int i = 0; i < count && !found; i++)
    if (!strcmp(text[i].key, key)) {
      snprintf(out, n, "%s", text[i].text ? text[i].text : "");
      found = 1;
    }
  in_free(&r);
  return found;
}

int png_file_complete(const char *path) {
  PngIn r;
  memset(&r, 0, sizeof r);
  unsigned char *volatile row = NULL;   /* set between setjmp and a longjmp */
  if (!png_is_png_file(path) || !(r.f = fopen(path, "rb"))) return 0;
  r.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &r.msg, on_error, on_warning);
  r.info = r.png ? png_create_info_struct(r.png) : NULL;
  if (!r.info || setjmp(png_jmpbuf(r.png))) {
    free(row);
    in_free(&r);
    return 0;
  }
  png_init_io(r.png, r.f);
  png_read_info(r.png, r.info);
  int passes = png_set_interlace_handling(r.png);
  png_read_update_info(r.png, r.info);
  row = xmalloc(png_get_rowbytes(r.png, r.info));
  int h = (int)png_get_image_height(r.png, r.info);
  for (int pass = 0; pass < passes; pass++)
    for (int y = 0; y < h; y++) png_read_row(r.png, row, NULL);
  png_read_end(r.png, NULL);   /* the chunks after the data, to IEND */
  free(row);
  in_free(&r);
  return 1;
}

int png_read_file(const char *path, long long max_pixels, int *w, int *h, int *nc, int *bits,
                  void **codes, int *too_large, char *err, size_t errlen) {
  PngIn r;
  memset(&r, 0, sizeof r);
  *codes = NULL;
  *too_large = 0;
  *w = *h = *nc = *bits = 0;
  if (!(r.f = fopen(path, "rb"))) {
    snprintf(r.msg.text, sizeof r.msg.text, "cannot open");
    put_err(err, errlen, "libpng", &r.msg);
    return 0;
  }
  r.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &r.msg, on_error, on_warning);
  r.info = r.png ? png_create_info_struct(r.png) : NULL;
  if (!r.info) snprintf(r.msg.text, sizeof r.msg.text, "out of memory");
  if (!r.info || setjmp(png_jmpbuf(r.png))) {
    put_err(err, errlen, "libpng", &r.msg);
    free(r.data);
    in_free(&r);
    return 0;
  }
  png_init_io(r.png, r.f);
  png_read_info(r.png, r.info);
  *w = (int)png_get_image_width(r.png, r.info);
  *h = (int)png_get_image_height(r.png, r.info);
  if ((long long)*w * *h > max_pixels) {
    *too_large = 1;
    *nc = png_get_channels(r.png, r.info);
    in_free(&r);
    return 0;
  }
  if (!read_layout(&r, *w, nc, bits)) png_error(r.png, "unexpected row layout");
  size_t row = png_get_rowbytes(r.png, r.info);
  r.data = xmalloc(row * (size_t)*h);
  r.rows = xmalloc((size_t)*h * sizeof *r.rows);
  for (int y = 0; y < *h; y++) r.rows[y] = r.data + (size_t)y * row;
  png_read_image(r.png, r.rows);
  png_read_end(r.png, NULL);
  *codes = r.data;
  in_free(&r);
  return 1;
}
