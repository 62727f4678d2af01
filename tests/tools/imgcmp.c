/*
** imgcmp: compare a rendered image with its golden, for the render tests.
**
**   imgcmp GOLDEN OUT DIFF.png [--max-diff 2] [--max-frac 0.001]
**   imgcmp --same A B
**
** Both images are read through image.h and compared as 8-bit values (sRGB
** for colour, linear for alpha), after widening each to RGBA (grey copies
** into R, G, B; a missing alpha is opaque). A pixel differs when any
** channel is off by more than --max-diff codes; the test passes when at
** most --max-frac of the pixels differ. On failure DIFF.png shows the
** differing pixels in red over a dimmed grey copy of the golden, and one
** line sums it up:
**   imgcmp: 123 of 65536 pixels differ (0.19%), max channel diff 45
** --same demands identity: byte-identical files pass at once (without
** loading the image library); otherwise every value must match exactly.
** Exit status: 0 pass, 1 fail (a size mismatch included), 2 error.
*/
#include "../../src/io/image.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* An image as 8-bit RGBA. */
typedef struct Rgba8 {
  int width, height;
  uint8_t *px;
} Rgba8;

static int usage(void) {
  fprintf(stderr, "usage: imgcmp GOLDEN OUT DIFF.png [--max-diff N] [--max-frac F]\n"
                  "       imgcmp --same A B\n");
  return 2;
}

/* Read path as 8-bit RGBA into *out; 0 with a message printed on error. */
static int load_rgba8(const char *path, Rgba8 *out) {
  char err[1024];
  Image *img = NULL;
  if (!image_read(path, &img, err, sizeof err)) {
    fprintf(stderr, "imgcmp: %s\n", err);
    return 0;
  }
  if (img->channels > 4) {
    fprintf(stderr, "imgcmp: %s: %d channels; only 1-4 compare\n", path, img->channels);
    image_destroy(img);
    return 0;
  }
  size_t npix = (size_t)img->width * (size_t)img->height;
  uint8_t *codes = malloc(npix * (size_t)img->channels);
  out->px = malloc(npix * 4);
  if (!codes || !out->px) {
    fprintf(stderr, "imgcmp: out of memory\n");
    exit(2);
  }
  image_to_srgb8(img, codes);
  int nc = img->channels;
  for (size_t p = 0; p < npix; p++) {
    const uint8_t *s = codes + p * (size_t)nc;
    uint8_t *d = out->px + p * 4;
    int grey = nc <= 2;
    d[0] = s[0];
    d[1] = grey ? s[0] : s[1];
    d[2] = grey ? s[0] : s[2];
    d[3] = nc == 2 ? s[1] : nc == 4 ? s[3] : 255;
  }
  out->width = img->width;
  out->height = img->height;
  free(codes);
  image_destroy(img);
  return 1;
}

/* Red where mask is set, elsewhere the golden's grey at a third. */
static int write_diff(const char *path, const Rgba8 *golden, const uint8_t *mask) {
  Image *img = image_create(golden->width, golden->height, 3);
  size_t npix = (size_t)golden->width * (size_t)golden->height;
  for (size_t p = 0; p < npix; p++) {
    const uint8_t *g = golden->px + p * 4;
    float *d = img->data + p * 3;
    if (mask[p]) {
      d[0] = 1.0f;
      d[1] = d[2] = 0.0f;
    } else {
      int luma = (54 * g[0] + 183 * g[1] + 19 * g[2]) / 256;    /* Rec. 709 weights */
      d[0] = d[1] = d[2] = image_srgb8_to_linear(luma / 3);
    }
  }
  char err[1024];
  int ok = image_write(path, img, err, sizeof err);
  if (!ok) fprintf(stderr, "imgcmp: %s\n", err);
  image_destroy(img);
  return ok;
}

static int compare(const char *golden_path, const char *out_path, const char *diff_path,
                   int max_diff, double max_frac) {
  Rgba8 g, o;
  if (!load_rgba8(golden_path, &g)) return 2;
  if (!load_rgba8(out_path, &o)) {
    free(g.px);
    return 2;
  }
  if (g.width != o.width || g.height != o.height) {
    printf("imgcmp: size differs: golden %s is %dx%d, output %s is %dx%d\n", golden_path,
           g.width, g.height, out_path, o.width, o.height);
    free(g.px);
    free(o.px);
    return 1;
  }
  size_t npix = (size_t)g.width * (size_t)g.height, ndiff = 0;
  uint8_t *mask = calloc(npix, 1);
  int maxd = 0;
  for (size_t p = 0; p < npix && mask; p++) {
    for (int c = 0; c < 4; c++) {
      int d = abs(g.px[p * 4 + c] - o.px[p * 4 + c]);
      if (d > maxd) maxd = d;
      if (d > max_diff) mask[p] = 1;
    }
    ndiff += mask[p];
  }
  int status = 0;
  if (!mask) {
    fprintf(stderr, "imgcmp: out of memory\n");
    status = 2;
  } else if ((double)ndiff > max_frac * (double)npix) {
    printf("imgcmp: %zu of %zu pixels differ (%.2f%%), max channel diff %d\n", ndiff, npix,
           100.0 * (double)ndiff / (double)npix, maxd);
    status = write_diff(diff_path, &g, mask) ? 1 : 2;
  }
  free(mask);
  free(g.px);
  free(o.px);
  return status;
}

/* 1 if files a and b hold the same bytes, 0 if not, -1 if one is unreadable. */
static int same_bytes(const char *a, const char *b) {
  FILE *f = fopen(a, "rb"), *g = fopen(b, "rb");
  int r = f && g ? 1 : -1;
  char x[65536], y[65536];
  while (r == 1) {
    size_t n = fread(x, 1, sizeof x, f), m = fread(y, 1, sizeof y, g);
    if (n != m || memcmp(x, y, n) != 0) r = 0;
    if (n < sizeof x) break;
  }
  if (f) fclose(f);
  if (g) fclose(g);
  return r;
}

/* --same: identical bytes, or else identical pixel values. */
static int compare_same(const char *a, const char *b) {
  if (same_bytes(a, b) == 1) return 0;
  char err[1024];
  Image *p = NULL, *q = NULL;
  int status = 2;
  if (!image_read(a, &p, err, sizeof err) || !image_read(b, &q, err, sizeof err)) {
    fprintf(stderr, "imgcmp: %s\n", err);
  } else if (p->width != q->width || p->height != q->height || p->channels != q->channels) {
    printf("imgcmp: not the same: %s is %dx%dx%d, %s is %dx%dx%d\n", a, p->width, p->height,
           p->channels, b, q->width, q->height, q->channels);
    status = 1;
  } else {
    size_t n = (size_t)p->width * (size_t)p->height * (size_t)p->channels, nd = 0;
    for (size_t i = 0; i < n; i++) nd += memcmp(&p->data[i], &q->data[i], sizeof(float)) != 0;
    if (nd) printf("imgcmp: not the same: %zu of %zu values differ\n", nd, n);
    else printf("imgcmp: same pixels, different bytes (metadata or encoding)\n");
    status = nd ? 1 : 0;
  }
  image_destroy(p);
  image_destroy(q);
  return status;
}

/* Parse a number option's value; 0 if missing or malformed. */
static int parse_number(const char *s, double *v) {
  char *end;
  if (!s) return 0;
  *v = strtod(s, &end);
  return end != s && *end == '\0' && *v >= 0;
}

int main(int argc, char **argv) {
  if (argc == 4 && !strcmp(argv[1], "--same")) return compare_same(argv[2], argv[3]);
  const char *files[3];
  int nfiles = 0;
  double max_diff = 2, max_frac = 0.001;
  for (int i = 1; i < argc; i++) {
    int is_diff = !strcmp(argv[i], "--max-diff"), is_frac = !strcmp(argv[i], "--max-frac");
    if (is_diff || is_frac) {
      if (i + 1 >= argc || !parse_number(argv[++i], is_diff ? &max_diff : &max_frac))
        return usage();
    } else if (argv[i][0] == '-' && argv[i][1] == '-') {
      return usage();
    } else if (nfiles < 3) {
      files[nfiles++] = argv[i];
    } else {
      return usage();
    }
  }
  if (nfiles != 3) return usage();
  return compare(files[0], files[1], files[2], (int)max_diff, max_frac);
}
