/*
** bench/clahe.sh's driver: sumi's CLAHE (src/render/clahe.c) on an 8-bit
** grey image, timed over RUNS runs on this one thread, its output written
** raw for the comparison with OpenCV; then one threshold-texture level
** (CLAHE unrounded, then ranked: texture_equalize_level) and the whole
** pyramid (texture_build) at the same window, timed in turn.
**
**   clahe_bench IMAGE TILES_X TILES_Y CLIP OUT.raw
** prints: clahe_ms level_ms pyramid_ms (medians)
*/
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "../src/io/image.h"
#include "../src/render/clahe.h"
#include "../src/render/texture.h"

#ifndef RUNS
#define RUNS 21
#endif

static double now_ms(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec * 1e3 + t.tv_nsec / 1e6;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y;
}

static double median(double *t) {
  qsort(t, RUNS, sizeof *t, cmp_double);
  return t[RUNS / 2];
}

int main(int argc, char **argv) {
  if (argc < 6) {
    fprintf(stderr, "usage: clahe_bench IMAGE TILES_X TILES_Y CLIP OUT.raw\n");
    return 2;
  }
  int tx = atoi(argv[2]), ty = atoi(argv[3]);
  double clip = atof(argv[4]);
  Image *img;
  char err[512];
  if (!image_read(argv[1], &img, err, sizeof err)) {
    fprintf(stderr, "%s\n", err);
    return 1;
  }
  int w = img->width, h = img->height;
  uint8_t *grey = malloc((size_t)w * h), *out = malloc((size_t)w * h);
  uint16_t *level = malloc((size_t)w * h * sizeof *level);
  for (int i = 0; i < w * h; i++) grey[i] = image_linear_to_srgb8(img->data[i * img->channels]);
  double t[RUNS], c, l, p;
  for (int r = 0; r < RUNS; r++) {
    double t0 = now_ms();
    clahe_apply(grey, w, h, tx, ty, clip, out);
    t[r] = now_ms() - t0;
  }
  c = median(t);
  double window = (double)w / tx;   /* the window these tiles make */
  double tp[RUNS];
  for (int r = 0; r < RUNS; r++) {   /* one level and the pyramid in turn: a busy spell hits both */
    double t0 = now_ms();
    texture_equalize_level(grey, w, h, window, clip, level);
    double t1 = now_ms();
    ThresholdTexture *tex = texture_build(grey, w, h, window, clip);
    tp[r] = now_ms() - t1;
    t[r] = t1 - t0;
    texture_free(tex);
  }
  l = median(t);
  p = median(tp);
  FILE *f = fopen(argv[5], "wb");
  if (!f || fwrite(out, 1, (size_t)w * h, f) != (size_t)w * h) {
    fprintf(stderr, "cannot write %s\n", argv[5]);
    return 1;
  }
  fclose(f);
  printf("%.3f %.3f %.3f\n", c, l, p);
  image_destroy(img);
  free(grey);
  free(out);
  free(level);
  return 0;
}
