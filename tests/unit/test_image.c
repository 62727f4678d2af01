/*
** Unit tests of image I/O (src/io/image.c, libpng for PNG and the
** OpenImageIO bridge): exact sRGB coding, round trips through every
** format, unassociated alpha, the temporary-file rule, AOV and id outputs,
** PNG without the bridge, and bad files that must give an error rather
** than a crash. Files go under a fresh build/ directory.
*/
#include "../../src/io/image.h"
#include "unit.h"

#include <png.h>
#include <dirent.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

static char dir[64];

/* dir/name into a static buffer (one live result at a time per slot). */
static const char *tmp_path(const char *name) {
  static char bufs[4][256];
  static int slot;
  char *b = bufs[slot++ & 3];
  snprintf(b, 256, "%s/%s", dir, name);
  return b;
}

/* Entries in directory d other than . and .., or -1 if it cannot be read. */
static int count_entries(const char *d) {
  DIR *dp = opendir(d);
  if (!dp) return -1;
  int n = 0;
  struct dirent *e;
  while ((e = readdir(dp)))
    if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) n++;
  closedir(dp);
  return n;
}

/* Remove every plain file in d, then d (directories one level deep). */
static void remove_tree(const char *d) {
  DIR *dp = opendir(d);
  if (!dp) return;
  struct dirent *e;
  char p[512];
  while ((e = readdir(dp))) {
    if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
    snprintf(p, sizeof p, "%s/%s", d, e->d_name);
    struct stat st;
    if (lstat(p, &st) == 0 && S_ISDIR(st.st_mode)) {
      chmod(p, 0755);
      remove_tree(p);
    } else {
      unlink(p);
    }
  }
  closedir(dp);
  rmdir(d);
}

/* An image whose colour values are exact 8-bit sRGB codes (so a round trip
** through an 8-bit file is exact), alpha exact k/255. */
static Image *coded_image(int w, int h, int ch, unsigned seed) {
  Image *img = image_create(w, h, ch);
  int ac = image_alpha_channel(img);
  size_t n = (size_t)w * h * ch;
  for (size_t i = 0; i < n; i++) {
    seed = seed * 1103515245u + 12345u;
    int k = (int)((seed >> 16) & 255);
    img->data[i] = (int)(i % ch) == ac ? k / 255.0f : image_srgb8_to_linear(k);
  }
  return img;
}

static int same_pixels(const Image *a, const Image *b) {
  if (a->width != b->width || a->height != b->height || a->channels != b->channels) return 0;
  size_t n = (size_t)a->width * a->height * a->channels;
  return memcmp(a->data, b->data, n * sizeof(float)) == 0;
}

static int file_bytes_equal(const char *p, const char *q) {
  FILE *f = fopen(p, "rb"), *g = fopen(q, "rb");
  int same = f && g;
  while (same) {
    int a = fgetc(f), b = fgetc(g);
    if (a != b) same = 0;
    if (a == EOF) break;
  }
  if (f) fclose(f);
  if (g) fclose(g);
  return same;
}

/* ---- sRGB coding ------------------------------------------------------ */

TEST(srgb_known_values) {
  CHECK_EQ_INT(image_linear_to_srgb8(0.5f), 188);
  CHECK_EQ_INT(image_linear_to_srgb8(0.0f), 0);
  CHECK_EQ_INT(image_linear_to_srgb8(1.0f), 255);
  CHECK_EQ_INT(image_linear_to_srgb8(0.18f), 118);        /* middle grey */
  CHECK_EQ_INT(image_linear_to_srgb8(0.0031308f), 10);    /* end of the linear segment */
  CHECK_EQ_INT(image_linear_to_srgb8(-1.0f), 0);
  CHECK_EQ_INT(image_linear_to_srgb8(7.0f), 255);
  CHECK_EQ_INT(image_linear_to_srgb8(NAN), 0);
  CHECK_NEAR(image_srgb8_to_linear(188), 0.50289, 1e-5);
  CHECK_NEAR(image_srgb8_to_linear(128), 0.21586, 1e-5);
  CHECK_NEAR(image_srgb8_to_linear(10), 10 / 255.0 / 12.92, 1e-9);
  CHECK(image_srgb8_to_linear(0) == 0.0f);
  CHECK(image_srgb8_to_linear(255) == 1.0f);
}

/* Every code decodes to a value that encodes back to the same code, and
** decoding is strictly increasing. */
TEST(srgb_codes_round_trip) {
  for (int k = 0; k < 256; k++) {
    CHECK_EQ_INT(image_linear_to_srgb8(image_srgb8_to_linear(k)), k);
    if (k > 0) CHECK(image_srgb8_to_linear(k) > image_srgb8_to_linear(k - 1));
  }
}

/* The table-driven encoder equals round(255 * srgb(v)) computed directly,
** away from the half-code boundaries where double rounding could tie. */
TEST(srgb_encoder_matches_formula) {
  unsigned seed = 1;
  int checked = 0;
  for (int i = 0; i < 200000; i++) {
    seed = seed * 1664525u + 1013904223u;
    float v = (float)((seed >> 8) / 16777216.0);
    if (i & 1) v = v * v * v;                       /* many dark values too */
    double s = v <= 0.0031308 ? v * 12.92 : 1.055 * pow(v, 1 / 2.4) - 0.055;
    double x = s * 255.0;
    if (fabs(x - floor(x) - 0.5) < 1e-6) continue;
    CHECK_EQ_INT(image_linear_to_srgb8(v), (int)floor(x + 0.5));
    checked++;
  }
  CHECK(checked > 199000);
}

/* Code k's threshold srgb^-1((k - 0.5) / 255), k = 1..255, in double. */
static double srgb_threshold_ref(int k) {
  double s = (k - 0.5) / 255.0;
  return s <= 0.04045 ? s / 12.92 : pow((s + 0.055) / 1.055, 2.4);
}

/* The code of v by its definition: 0 for NaN and v <= 0, else the number
** of code thresholds at or below v (so 255 from 1 up). */
static int srgb_code_reference(float v) {
  static double t[256];
  if (t[1] == 0)
    for (int k = 1; k < 256; k++) t[k] = srgb_threshold_ref(k);
  if (!(v > 0)) return 0;
  int lo = 0, hi = 255;   /* t[lo] <= v (t[0] as -inf), t[hi + 1] > v (t[256] as +inf) */
  while (lo < hi) {
    int mid = (lo + hi + 1) / 2;
    if ((double)v >= t[mid]) lo = mid;
    else hi = mid - 1;
  }
  return lo;
}

static float float_bits(uint32_t u) {
  float f;
  memcpy(&f, &u, sizeof f);
  return f;
}

/* The encoder takes a bucket by a float's top 16 bits and one test of its
** bits against a threshold: every class of float pattern gives its
** defined code through the one-value and the row encoder. Tested: both
** ends and the middle of every top-16-bit bucket (all signs, exponents,
** denormals, infinities and NaN payloads), a few ulps on each side of every
** code threshold, and a stride through all 2^32 patterns. */
TEST(srgb_encoder_every_float_class) {
  enum { MAX = 3 * 65536 + 9 * 255 + 65556 + 16 };   /* the patterns below */
  uint32_t *bits = malloc(MAX * sizeof *bits);
  int n = 0;
  for (uint32_t b = 0; b < 1u << 16; b++) {
    bits[n++] = b << 16;
    bits[n++] = b << 16 | 0x8000u;
    bits[n++] = b << 16 | 0xffffu;
  }
  for (int k = 1; k < 256; k++) {   /* the float nearest each threshold, +-4 ulps */
    float f = (float)srgb_threshold_ref(k);
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    for (int d = -4; d <= 4; d++) bits[n++] = u + (uint32_t)d;
  }
  for (uint64_t u = 0; u < 1ull << 32; u += 65521) bits[n++] = (uint32_t)u;
  uint32_t special[] = {0x7f800000u, 0x7f800001u, 0x7fc00000u, 0x7fffffffu, 0xff800000u,
                        0xff800001u, 0xffffffffu, 0x80000000u, 0x00000001u, 0x3f7fffffu};
  for (size_t i = 0; i < sizeof special / sizeof *special; i++) bits[n++] = special[i];
  float *px = malloc((size_t)n * 3 * sizeof *px);
  uint8_t *out = malloc((size_t)n * 3);
  int bad = 0;
  for (int i = 0; i < n; i++) {
    float v = float_bits(bits[i]);
    int want = srgb_code_reference(v);
    if (image_linear_to_srgb8(v) != want && bad++ < 5)
      fprintf(stderr, "  bits %08x: %d, expected %d\n", (unsigned)bits[i], image_linear_to_srgb8(v), want);
    for (int c = 0; c < 3; c++) px[3 * i + c] = float_bits(bits[(i + c * (i & 1)) % n]);   /* some pixels grey */
  }
  for (int i = 0; i + 1 < n; i += 7) memcpy(px + 3 * (i + 1), px + 3 * i, 3 * sizeof *px);   /* runs of two */
  image_encode8(px, out, (size_t)n, 3);
  for (int i = 0; i < 3 * n; i++) bad += out[i] != srgb_code_reference(px[i]);
  CHECK_EQ_INT(bad, 0);
  CHECK(n <= MAX);
  free(out);
  free(px);
  free(bits);
}

/* ---- round trips ------------------------------------------------------ */

static void round_trip_exact(const char *name, int ch) {
  char err[512] = "";
  Image *img = coded_image(37, 23, ch, (unsigned)ch * 7u), *back = NULL;
  const char *p = tmp_path(name);
  CHECK(image_write(p, img, err, sizeof err));
  CHECK(image_read(p, &back, err, sizeof err));
  if (err[0]) fprintf(stderr, "  %s: %s\n", name, err);
  CHECK(back && same_pixels(img, back));
  image_destroy(img);
  image_destroy(back);
}

/* The row encoder (runs of equal pixels encoded once, then copied) gives
** each pixel the code of the one-value encoder, for RGB and RGBA, over
** runs of every length from 1 to 40 and values on both sides of codes. */
TEST(row_encoder_matches_one_value_encoder) {
  enum { NPIX = 820 };
  float px[NPIX * 4];
  uint8_t out[NPIX * 4];
  for (int nc = 3; nc <= 4; nc++) {
    int p = 0;
    for (int run = 1; p < NPIX; run = run % 40 + 1)
      for (int r = 0; r < run && p < NPIX; r++, p++)
        for (int c = 0; c < nc; c++) px[p * nc + c] = (float)((run * 7 + c * 13) % 256) / 255.0f + (run % 3 - 1) * 1e-4f;
    image_encode8(px, out, NPIX, nc);
    int bad = 0;
    for (int i = 0; i < NPIX * nc; i++) {
      int want = nc == 4 && i % 4 == 3 ? (int)lrintf(fminf(fmaxf(px[i], 0), 1) * 255) : image_linear_to_srgb8(px[i]);
      bad += out[i] != want;
    }
    CHECK_EQ_INT(bad, 0);
  }
}

TEST(png_round_trip_exact) {
  round_trip_exact("grey.png", 1);
  round_trip_exact("grey_alpha.png", 2);
  round_trip_exact("rgb.png", 3);
  round_trip_exact("rgba.png", 4);
}

TEST(tiff_round_trip_exact) {
  round_trip_exact("rgb.tif", 3);
  round_trip_exact("rgba.tiff", 4);
  round_trip_exact("UPPER.TIF", 3);
}

TEST(png16_round_trip) {
  char err[512] = "";
  Image *img = image_create(16, 8, 3), *back = NULL;
  for (int i = 0; i < 16 * 8 * 3; i++) img->data[i] = (float)i / (16 * 8 * 3);
  ImageWriteOptions opt = { .bits = 16 };
  CHECK(image_write_opts(tmp_path("deep.png"), img, &opt, err, sizeof err));
  CHECK(image_read(tmp_path("deep.png"), &back, err, sizeof err));
  for (int i = 0; back && i < 16 * 8 * 3; i++) CHECK_NEAR(back->data[i], img->data[i], 2e-5);
  image_destroy(img);
  image_destroy(back);
}

/* Arbitrary floats, negative and above 1 included, come back bit for bit. */
TEST(exr_round_trip_exact_float) {
  char err[512] = "";
  Image *img = image_create(19, 11, 3), *back = NULL;
  unsigned seed = 3;
  for (int i = 0; i < 19 * 11 * 3; i++) {
    seed = seed * 1664525u + 1013904223u;
    img->data[i] = ((int)(seed >> 8) - (1 << 23)) / 1234567.0f;
  }
  CHECK(image_write(tmp_path("f.exr"), img, err, sizeof err));
  CHECK(image_read(tmp_path("f.exr"), &back, err, sizeof err));
  CHECK(back && same_pixels(img, back));
  image_destroy(back);

  ImageWriteOptions half = { .exr_half = 1 };
  CHECK(image_write_opts(tmp_path("h.exr"), img, &half, err, sizeof err));
  CHECK(image_read(tmp_path("h.exr"), &back, err, sizeof err));
  for (int i = 0; back && i < 19 * 11 * 3; i++)
    CHECK_NEAR(back->data[i], img->data[i], fabs(img->data[i]) * 1e-3 + 1e-7);
  image_destroy(back);
  image_destroy(img);
}

/* JPEG is lossy: a smooth image comes back within a few codes. */
TEST(jpeg_round_trip_close) {
  char err[512] = "";
  Image *img = image_create(64, 48, 3), *back = NULL;
  for (int y = 0; y < 48; y++)
    for (int x = 0; x < 64; x++) {
      float *p = img->data + (y * 64 + x) * 3;
      p[0] = image_srgb8_to_linear(x * 4);
      p[1] = image_srgb8_to_linear(y * 5);
      p[2] = image_srgb8_to_linear(128);
    }
  CHECK(image_write(tmp_path("smooth.jpg"), img, err, sizeof err));
  CHECK(image_read(tmp_path("smooth.jpeg.jpg"), &back, err, sizeof err) == 0);
  CHECK(image_read(tmp_path("smooth.jpg"), &back, err, sizeof err));
  CHECK(back && back->channels == 3);
  int maxd = 0;
  for (int i = 0; back && i < 64 * 48 * 3; i++) {
    int d = abs(image_linear_to_srgb8(back->data[i]) - image_linear_to_srgb8(img->data[i]));
    if (d > maxd) maxd = d;
  }
  CHECK(maxd <= 6);
  image_destroy(back);

  /* alpha is dropped, not an error */
  Image *rgba = coded_image(8, 8, 4, 5);
  CHECK(image_write(tmp_path("rgba.jpg"), rgba, err, sizeof err));
  CHECK(image_read(tmp_path("rgba.jpg"), &back, err, sizeof err));
  CHECK(back && back->channels == 3);
  image_destroy(back);
  image_destroy(rgba);
  image_destroy(img);
}

/* ---- alpha ------------------------------------------------------------- */

/* White at alpha 0.5 stays white: nothing premultiplies or divides it. */
static void check_unassociated(const char *name) {
  char err[512] = "";
  Image *img = image_create(2, 1, 4), *back = NULL;
  float px[8] = { 1.0f, 1.0f, 1.0f, 0.5f, 0.25f, 0.5f, 1.0f, 0.0f };
  memcpy(img->data, px, sizeof px);
  CHECK(image_write(tmp_path(name), img, err, sizeof err));
  CHECK(image_read(tmp_path(name), &back, err, sizeof err));
  if (!back) { image_destroy(img); return; }
  CHECK(back->channels == 4);
  CHECK_NEAR(back->data[0], 1.0, 1e-6);
  CHECK_NEAR(back->data[2], 1.0, 1e-6);
  CHECK_NEAR(back->data[3], 0.5, 0.5 / 255 + 1e-6);
  if (strstr(name, ".exr")) {
    CHECK(back->data[4] == 0.0f);              /* at alpha 0 EXR keeps no colour */
  } else {
    CHECK_EQ_INT(image_linear_to_srgb8(back->data[4]), image_linear_to_srgb8(0.25f));
    CHECK_EQ_INT(image_linear_to_srgb8(back->data[6]), 255);   /* colour kept at alpha 0 */
  }
  CHECK(back->data[7] == 0.0f);
  image_destroy(back);
  image_destroy(img);
}

TEST(alpha_unassociated) {
  check_unassociated("alpha.png");
  check_unassociated("alpha.tif");
  check_unassociated("alpha.exr");
}

/* ---- the temporary-file rule ----------------------------------------- */

TEST(write_missing_dir_fails_cleanly) {
  char err[512] = "";
  Image *img = coded_image(4, 4, 3, 1);
  CHECK(image_write(tmp_path("nope/out.png"), img, err, sizeof err) == 0);
  CHECK(strstr(err, "nope/out.png") != NULL);
  CHECK(strstr(err, "No such file") != NULL);
  CHECK(access(tmp_path("nope"), F_OK) != 0);
  image_destroy(img);
}

/* A parent that is a file, a target that is a directory, and (when not
** root) a read-only directory: each fails and leaves no file behind. */
TEST(write_unwritable_fails_cleanly) {
  char err[512] = "";
  Image *img = coded_image(4, 4, 3, 1);
  mkdir(tmp_path("box"), 0755);
  FILE *f = fopen(tmp_path("box/plain"), "w");
  if (f) fclose(f);
  CHECK(image_write(tmp_path("box/plain/out.png"), img, err, sizeof err) == 0);
  CHECK(strstr(err, "Not a directory") != NULL);
  mkdir(tmp_path("box/taken.png"), 0755);
  err[0] = '\0';
  CHECK(image_write(tmp_path("box/taken.png"), img, err, sizeof err) == 0);
  CHECK(strstr(err, "taken.png") != NULL);
  CHECK_EQ_INT(count_entries(tmp_path("box")), 2);      /* plain, taken.png: no temp */
  CHECK_EQ_INT(count_entries(tmp_path("box/taken.png")), 0);
  if (geteuid() != 0) {
    mkdir(tmp_path("ro"), 0555);
    CHECK(image_write(tmp_path("ro/out.png"), img, err, sizeof err) == 0);
    CHECK(strstr(err, "Permission denied") != NULL);
    CHECK_EQ_INT(count_entries(tmp_path("ro")), 0);
  }
  image_destroy(img);
}

/* A write replaces the old file whole and leaves nothing else. */
TEST(write_replaces_atomically) {
  char err[512] = "";
  mkdir(tmp_path("atomic"), 0755);
  Image *a = coded_image(8, 8, 3, 11), *b = coded_image(9, 5, 3, 12), *back = NULL;
  CHECK(image_write(tmp_path("atomic/x.png"), a, err, sizeof err));
  CHECK(image_write(tmp_path("atomic/x.png"), b, err, sizeof err));
  CHECK_EQ_INT(count_entries(tmp_path("atomic")), 1);
  CHECK(image_read(tmp_path("atomic/x.png"), &back, err, sizeof err));
  CHECK(back && same_pixels(b, back));
  image_destroy(back);
  image_destroy(a);
  image_destroy(b);
}

TEST(write_bad_format_names_it) {
  char err[512] = "";
  Image *img = coded_image(4, 4, 3, 1);
  CHECK(image_write(tmp_path("x.bmp"), img, err, sizeof err) == 0);
  CHECK(strstr(err, "unknown image format '.bmp'") != NULL);
  CHECK(image_write(tmp_path("noext"), img, err, sizeof err) == 0);
  CHECK(strstr(err, "no image format extension") != NULL);
  CHECK(access(tmp_path("x.bmp"), F_OK) != 0);
  image_destroy(img);
}

/* ---- AOVs and ids ------------------------------------------------------ */

TEST(aov_exr_channels) {
  char err[512] = "";
  enum { W = 7, H = 5 };
  float normal[W * H * 3];
  for (int i = 0; i < W * H * 3; i++) normal[i] = (float)sin(i * 0.37);
  const char *names[] = { "N.x", "N.y", "N.z" };
  CHECK(image_write_aov_exr(tmp_path("n.exr"), W, H, 3, names, normal, err, sizeof err));
  Image *back = NULL;
  CHECK(image_read(tmp_path("n.exr"), &back, err, sizeof err));
  CHECK(back && back->channels == 3 && memcmp(back->data, normal, sizeof normal) == 0);
  image_destroy(back);

  float depth[W * H];
  for (int i = 0; i < W * H; i++) depth[i] = i * 1.5f + 0.125f;
  const char *z[] = { "Z" };
  CHECK(image_write_aov_exr(tmp_path("z.exr"), W, H, 1, z, depth, err, sizeof err));
  CHECK(image_read(tmp_path("z.exr"), &back, err, sizeof err));
  CHECK(back && back->channels == 1 && memcmp(back->data, depth, sizeof depth) == 0);
  image_destroy(back);

  const char *twice[] = { "Z", "Z" };
  CHECK(image_write_aov_exr(tmp_path("zz.exr"), W, H, 2, twice, normal, err, sizeof err) == 0);
  CHECK(strstr(err, "appears twice") != NULL);
  CHECK(access(tmp_path("zz.exr"), F_OK) != 0);
}

TEST(ids_tiff_exact) {
  char err[512] = "";
  enum { W = 9, H = 4 };
  int32_t ids[W * H];
  for (int i = 0; i < W * H; i++) ids[i] = i * 99991 - 7;
  ids[0] = -1;
  ids[1] = 0x7fffffff;
  ids[2] = (1 << 24) + 1;                       /* not representable as float */
  CHECK(image_write_ids_tiff(tmp_path("ids.tif"), W, H, ids, err, sizeof err));
  int w = 0, h = 0;
  int32_t *back = NULL;
  CHECK(image_read_ids(tmp_path("ids.tif"), &w, &h, &back, err, sizeof err));
  CHECK(w == W && h == H);
  CHECK(back && memcmp(back, ids, sizeof ids) == 0);
  free(back);
}

/* ---- determinism --------------------------------------------------------- */

/* The file holds no trace of today's date (TIFF and EXR writers stamp the
** time unless told otherwise). */
static int file_mentions_today(const char *p) {
  char today[16], buf[1 << 14];
  time_t t = time(NULL);
  strftime(today, sizeof today, "%Y:%m:%d", gmtime(&t));
  FILE *f = fopen(p, "rb");
  size_t n = f ? fread(buf, 1, sizeof buf, f) : 0;
  if (f) fclose(f);
  for (size_t i = 0; i + 10 <= n; i++)
    if (!memcmp(buf + i, today, 10)) return 1;
  return 0;
}

TEST(same_image_same_bytes) {
  char err[512] = "";
  Image *img = coded_image(33, 17, 4, 9);
  const char *ext[] = { "png", "tif", "exr", "jpg" };
  for (int i = 0; i < 4; i++) {
    char a[32], b[32];
    snprintf(a, sizeof a, "det_a.%s", ext[i]);
    snprintf(b, sizeof b, "det_b.%s", ext[i]);
    CHECK(image_write(tmp_path(a), img, err, sizeof err));
    CHECK(image_write(tmp_path(b), img, err, sizeof err));
    CHECK(file_bytes_equal(tmp_path(a), tmp_path(b)));
    CHECK(!file_mentions_today(tmp_path(a)));
  }
  image_destroy(img);
}

/* ---- streamed writing ------------------------------------------------------ */

/* An 8-bit image of pseudo-random codes (what a renderer hands the stream). */
static Image *codes_image(int w, int h, int ch, unsigned seed) {
  Image *img = image_create8(w, h, ch);
  for (size_t i = 0; i < (size_t)w * h * ch; i++) {
    seed = seed * 1103515245u + 12345u;
    img->data8[i] = (uint8_t)(seed >> 16);
  }
  return img;
}

/* Rows handed over in uneven bands make the file image_write makes of the
** whole image, byte for byte, in every format that streams. */
TEST(stream_matches_whole_write) {
  char err[512] = "";
  const char *ext[] = {"png", "tif", "jpg"};
  const int cut[] = {0, 5, 6, 30, 37};   /* band edges: 5, 1, 24 and 7 rows */
  for (int i = 0; i < 3; i++)
    for (int ch = 1; ch <= 4; ch++) {
      char a[32], b[32];
      snprintf(a, sizeof a, "whole%d.%s", ch, ext[i]);
      snprintf(b, sizeof b, "streamed%d.%s", ch, ext[i]);
      if (!image_stream_fits(tmp_path(b), ch)) {   /* jpg keeps no alpha */
        CHECK(i == 2 && ch % 2 == 0);
        continue;
      }
      Image *img = codes_image(29, 37, ch, (unsigned)(7 * i + ch));
      CHECK(image_write(tmp_path(a), img, err, sizeof err));
      ImageStream *s = image_stream_open(tmp_path(b), 29, 37, ch, err, sizeof err);
      CHECK(s != NULL);
      if (!s) { image_destroy(img); continue; }
      for (int k = 0; k + 1 < 5; k++)
        image_stream_rows(s, cut[k], cut[k + 1], img->data8 + (size_t)cut[k] * 29 * ch);
      CHECK(image_stream_close(s, err, sizeof err));
      CHECK(file_bytes_equal(tmp_path(a), tmp_path(b)));
      image_destroy(img);
    }
}

/* A stream into a missing folder fails as image_write does; a discarded
** stream and a closed one leave nothing but the finished file. */
TEST(stream_leaves_no_temporary) {
  char err[512] = "", werr[512] = "";
  Image *img = codes_image(8, 8, 3, 5);
  CHECK(image_stream_open(tmp_path("nowhere/out.png"), 8, 8, 3, err, sizeof err) == NULL);
  CHECK(image_write(tmp_path("nowhere/out.png"), img, werr, sizeof werr) == 0);
  CHECK(strcmp(err, werr) == 0);
  mkdir(tmp_path("streams"), 0755);
  ImageStream *s = image_stream_open(tmp_path("streams/gone.png"), 8, 8, 3, err, sizeof err);
  CHECK(s != NULL);
  if (s) {
    image_stream_rows(s, 0, 4, img->data8);
    image_stream_discard(s);
  }
  CHECK_EQ_INT(count_entries(tmp_path("streams")), 0);
  s = image_stream_open(tmp_path("streams/kept.png"), 8, 8, 3, err, sizeof err);
  CHECK(s != NULL);
  if (s) {
    image_stream_rows(s, 0, 8, img->data8);
    CHECK(image_stream_close(s, err, sizeof err));
  }
  CHECK_EQ_INT(count_entries(tmp_path("streams")), 1);
  Image *back = NULL;
  CHECK(image_read(tmp_path("streams/kept.png"), &back, err, sizeof err));
  CHECK(back && back->width == 8 && back->height == 8);
  image_destroy(back);
  image_destroy(img);
}

/* ---- bad files ------------------------------------------------------------ */

static void write_bytes(const char *p, const void *data, size_t n) {
  FILE *f = fopen(p, "wb");
  if (!f) return;
  fwrite(data, 1, n, f);
  fclose(f);
}

TEST(read_missing_file) {
  char err[512] = "";
  Image *img = (Image *)1;
  CHECK(image_read(tmp_path("absent.png"), &img, err, sizeof err) == 0);
  CHECK(img == NULL);
  CHECK(strstr(err, "absent.png") != NULL && strstr(err, "No such file") != NULL);
  CHECK(image_read(dir, &img, err, sizeof err) == 0);
  CHECK(strstr(err, "is a directory") != NULL);
}

TEST(read_not_an_image) {
  char err[512] = "";
  Image *img = NULL;
  const char text[] = "scene { camera {} }\n";
  write_bytes(tmp_path("text.png"), text, sizeof text - 1);
  CHECK(image_read(tmp_path("text.png"), &img, err, sizeof err) == 0);
  CHECK(strstr(err, "text.png") != NULL && strstr(err, "not an image") != NULL);
  write_bytes(tmp_path("empty.png"), "", 0);
  CHECK(image_read(tmp_path("empty.png"), &img, err, sizeof err) == 0);
  CHECK(img == NULL);
}

/* Point stderr at /dev/null (quiet=1) and back (quiet=0): libpng prints
** "libpng error: ..." itself before OIIO hands us the same reason. */
static void quiet_stderr(int quiet) {
  static int saved = -1;
  fflush(stderr);
  if (quiet) {
    int null = open("/dev/null", O_WRONLY);
    saved = dup(2);
    if (null >= 0) dup2(null, 2), close(null);
  } else if (saved >= 0) {
    dup2(saved, 2);
    close(saved);
    saved = -1;
  }
}

/* A PNG cut short, one with a damaged data chunk, and one cut inside its
** header: each is an error naming the file, never a crash. */
TEST(read_corrupt_png) {
  char err[3][512] = { "", "", "" };
  Image *src = coded_image(64, 64, 3, 4), *img[3] = { NULL, NULL, NULL };
  CHECK(image_write(tmp_path("good.png"), src, err[0], sizeof err[0]));
  image_destroy(src);
  FILE *f = fopen(tmp_path("good.png"), "rb");
  static unsigned char buf[1 << 16];
  size_t n = f ? fread(buf, 1, sizeof buf, f) : 0;
  if (f) fclose(f);
  CHECK(n > 200);
  write_bytes(tmp_path("cut.png"), buf, n / 2);
  write_bytes(tmp_path("head.png"), buf, 20);
  for (size_t i = n / 2; i < n / 2 + 64; i++) buf[i] ^= 0x5a;
  write_bytes(tmp_path("bad.png"), buf, n);

  const char *names[3] = { "cut.png", "bad.png", "head.png" };
  int ok[3];
  quiet_stderr(1);                       /* no CHECK until stderr is back */
  for (int i = 0; i < 3; i++) ok[i] = image_read(tmp_path(names[i]), &img[i], err[i], sizeof err[i]);
  quiet_stderr(0);
  for (int i = 0; i < 3; i++) {
    CHECK(ok[i] == 0 && img[i] == NULL);
    CHECK(strstr(err[i], names[i]) != NULL);
  }
  CHECK(strstr(err[0], "corrupt") != NULL);
  CHECK(strstr(err[1], "corrupt") != NULL);
}

/* CRC-32 as PNG chunks use it (ISO 3309, reflected 0xedb88320). */
static uint32_t crc32_png(const unsigned char *p, size_t n) {
  uint32_t c = 0xffffffffu;
  for (size_t i = 0; i < n; i++) {
    c ^= p[i];
    for (int k = 0; k < 8; k++) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  return c ^ 0xffffffffu;
}

static void put_be32(unsigned char *p, uint32_t v) {
  p[0] = (unsigned char)(v >> 24), p[1] = (unsigned char)(v >> 16);
  p[2] = (unsigned char)(v >> 8), p[3] = (unsigned char)v;
}

/* A valid PNG header claiming 20000 x 20000 pixels crosses
** IMAGE_READ_MAX_PIXELS and is refused before anything is allocated; an
** AOV of IMAGE_MAX_CHANNELS + 1 channels is refused on write. */
TEST(limits) {
  /* signature, IHDR, an empty IDAT (the reader stops at its header) */
  unsigned char png[8 + 25 + 12] = { 0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n' };
  unsigned char *ihdr = png + 8, *idat = png + 8 + 25;
  put_be32(ihdr, 13);
  memcpy(ihdr + 4, "IHDR", 4);
  put_be32(ihdr + 8, 20000);
  put_be32(ihdr + 12, 20000);
  ihdr[16] = 8, ihdr[17] = 2;                   /* 8-bit RGB, rest 0 */
  put_be32(ihdr + 21, crc32_png(ihdr + 4, 17));
  memcpy(idat + 4, "IDAT", 4);
  put_be32(idat + 8, crc32_png(idat + 4, 4));
  write_bytes(tmp_path("huge.png"), png, sizeof png);
  char err[512] = "";
  Image *img = NULL;
  CHECK(image_read(tmp_path("huge.png"), &img, err, sizeof err) == 0);
  CHECK(img == NULL);
  CHECK(strstr(err, "too large") && strstr(err, "20000x20000") &&
        strstr(err, "IMAGE_READ_MAX_PIXELS"));

  enum { N = IMAGE_MAX_CHANNELS + 1 };
  const char *names[N];
  char buf[N][16];
  float data[4 * N] = { 0 };
  for (int c = 0; c < N; c++) {
    snprintf(buf[c], sizeof buf[c], "c%d", c);
    names[c] = buf[c];
  }
  CHECK(image_write_aov_exr(tmp_path("wide.exr"), 2, 2, N, names, data, err, sizeof err) == 0);
  CHECK(strstr(err, "at most 16") != NULL);
  CHECK(access(tmp_path("wide.exr"), F_OK) != 0);
}

static void put_le(unsigned char *p, uint32_t v, int bytes) {
  for (int b = 0; b < bytes; b++) p[b] = (unsigned char)(v >> (8 * b));
}

/* Write a TIFF header of 8192 x 8192 pixels of n samples of bits each
** (float at 32 bits), with one tiny strip: no pixel data to speak of. */
static void write_huge_tiff(const char *path, int n, int bits) {
  enum { ENTRIES = 12, IFD = 8, ARRAYS = IFD + 2 + ENTRIES * 12 + 4 };
  unsigned char tif[ARRAYS + 3 * 2 * IMAGE_MAX_CHANNELS + 16] = { 'I', 'I', 42, 0 };
  put_le(tif + 4, IFD, 4);
  put_le(tif + IFD, ENTRIES, 2);
  uint32_t nb = (uint32_t)n, at_bits = ARRAYS, extra = ARRAYS + 2 * nb, format = ARRAYS + 4 * nb;
  uint32_t strip = ARRAYS + 6 * nb;
  /* tag, type (3 short, 4 long), count, value or offset; in tag order */
  const uint32_t e[ENTRIES][4] = {
    { 256, 4, 1, 8192 }, { 257, 4, 1, 8192 }, { 258, 3, nb, at_bits }, { 259, 3, 1, 1 },
    { 262, 3, 1, 1 }, { 273, 4, 1, strip }, { 277, 3, 1, nb }, { 278, 4, 1, 8192 },
    { 279, 4, 1, 16 }, { 284, 3, 1, 1 }, { 338, 3, nb - 1, extra }, { 339, 3, nb, format },
  };
  for (int k = 0; k < ENTRIES; k++) {
    unsigned char *d = tif + IFD + 2 + 12 * k;
    put_le(d, e[k][0], 2), put_le(d + 2, e[k][1], 2), put_le(d + 4, e[k][2], 4);
    put_le(d + 8, e[k][3], e[k][1] == 3 && e[k][2] == 1 ? 2 : 4);
  }
  for (int c = 0; c < n; c++) {
    put_le(tif + at_bits + 2 * c, (uint32_t)bits, 2);
    put_le(tif + format + 2 * c, bits == 32 ? 3 : 1, 2); /* IEEE float or unsigned */
  }                                                       /* extra samples: 0, unspecified */
  write_bytes(path, tif, sizeof tif);
}

/* Headers within the pixel and channel limits whose pixels would not fit
** in memory are refused before anything is allocated (a fuzzed header once
** made the reader ask for 4 GiB): 8 bytes a pixel as floats pass sumi's
** IMAGE_READ_MAX_VALUES; 16 floats a pixel pass even OpenImageIO's own
** limits:imagesize_MB, which the bridge sets, checked as the file opens. */
TEST(limit_values) {
  char err[512] = "";
  Image *img = NULL;
  write_huge_tiff(tmp_path("huge8.tif"), 8, 8);
  CHECK(image_read(tmp_path("huge8.tif"), &img, err, sizeof err) == 0 && img == NULL);
  CHECK(strstr(err, "too large") && strstr(err, "8192x8192 with 8 channels") &&
        strstr(err, "IMAGE_READ_MAX_VALUES"));
  write_huge_tiff(tmp_path("huge16.tif"), IMAGE_MAX_CHANNELS, 32);
  CHECK(image_read(tmp_path("huge16.tif"), &img, err, sizeof err) == 0 && img == NULL);
  CHECK(strstr(err, "exceeds \"limits:imagesize_MB\" = 2048") != NULL);
}

/* An EXR whose dataWindow is made 8388620 x 8: fewer pixels than 8192 x
** 8192, but OpenEXR's C++ reader sized its decompression buffers by a row
** as the file opened (1.6 GB here, found by fuzzing). Through the core
** library the header is read alone and IMAGE_READ_MAX_SIDE refuses it. */
TEST(limit_exr_row) {
  char err[512] = "";
  Image *img = coded_image(2, 2, 3, 5), *back = NULL;
  CHECK(image_write(tmp_path("row.exr"), img, err, sizeof err));
  image_destroy(img);
  FILE *f = fopen(tmp_path("row.exr"), "rb");
  unsigned char bytes[8192];
  size_t n = f ? fread(bytes, 1, sizeof bytes, f) : 0;
  if (f) fclose(f);
  static const char key[] = "dataWindow\0box2i";
  unsigned char *w = NULL;
  for (size_t i = 0; i + sizeof key + 20 <= n && !w; i++)
    if (!memcmp(bytes + i, key, sizeof key)) w = bytes + i + sizeof key + 4;
  CHECK(w != NULL);
  if (!w) return;
  put_le(w + 8, 8388619, 4); /* xmax; xmin, ymin 0 */
  put_le(w + 12, 7, 4);      /* ymax */
  write_bytes(tmp_path("row_wide.exr"), bytes, n);
  CHECK(image_read(tmp_path("row_wide.exr"), &back, err, sizeof err) == 0 && back == NULL);
  CHECK(strstr(err, "too large: 8388620x8 with 3 channels") &&
        strstr(err, "IMAGE_READ_MAX_SIDE"));
}

/* An EXR whose first attribute says it holds 2 GB: OpenEXR's C++ reader
** allocated that before reading it (found by fuzzing); the core library
** finds the file too short for it. */
TEST(limit_exr_attribute) {
  char err[512] = "";
  Image *img = coded_image(2, 2, 3, 7), *back = NULL;
  CHECK(image_write(tmp_path("attr.exr"), img, err, sizeof err));
  image_destroy(img);
  FILE *f = fopen(tmp_path("attr.exr"), "rb");
  unsigned char bytes[8192];
  size_t n = f ? fread(bytes, 1, sizeof bytes, f) : 0;
  if (f) fclose(f);
  /* magic, version, then the first attribute: name, type, size */
  size_t at = 8;
  for (int z = 0; z < 2 && at < n; at++) z += bytes[at] == 0;
  CHECK(at + 4 < n);
  put_le(bytes + at, 0x7fff0000u, 4);
  write_bytes(tmp_path("attr_huge.exr"), bytes, n);
  CHECK(image_read(tmp_path("attr_huge.exr"), &back, err, sizeof err) == 0 && back == NULL);
  CHECK(strstr(err, "Unable to read 'capDate'") != NULL);
}

/* ---- the bridge ------------------------------------------------------------ */

/* Whether a shared library whose path contains name is mapped in this process. */
static int library_mapped(const char *name) {
  FILE *f = fopen("/proc/self/maps", "r");
  char line[1024];
  int found = 0;
  while (f && !found && fgets(line, sizeof line, f)) found = strstr(line, name) != NULL;
  if (f) fclose(f);
  return found;
}

/* PNG (whole, streamed, 16-bit, read back) goes through libpng: the
** bridge and OpenImageIO's libraries are never loaded. Runs first. */
TEST(png_needs_no_bridge) {
  char err[512] = "";
  Image *img = coded_image(31, 9, 4, 21), *back = NULL;
  CHECK(image_write(tmp_path("plain.png"), img, err, sizeof err));
  CHECK(image_read(tmp_path("plain.png"), &back, err, sizeof err) && same_pixels(img, back));
  image_destroy(back);
  ImageWriteOptions o16 = { .bits = 16 };
  CHECK(image_write_opts(tmp_path("deep.png"), img, &o16, err, sizeof err));
  Image *codes = codes_image(8, 8, 3, 3);
  ImageStream *s = image_stream_open(tmp_path("band.png"), 8, 8, 3, err, sizeof err);
  CHECK(s != NULL);
  if (s) {
    image_stream_rows(s, 0, 8, codes->data8);
    CHECK(image_stream_close(s, err, sizeof err));
  }
  CHECK(!image_write_needs_bridge("a.png") && image_write_needs_bridge("a.exr"));
  CHECK(!image_read_needs_bridge("washi") && !image_read_needs_bridge("k.PNG") && image_read_needs_bridge("k.jpg"));
  CHECK(image_bridge_load_seconds() == 0);
  CHECK(!library_mapped("libOpenImageIO") && !library_mapped("libsumi_oiio"));
  image_destroy(codes);
  image_destroy(img);
}

/* A prefetch loads the bridge on its own thread: afterwards it is loaded,
** and no caller waited for it. Runs before anything else loads it. */
TEST(prefetch_loads_on_a_thread) {
  char err[512] = "";
  image_bridge_prefetch();
  image_bridge_prefetch();   /* a second call does nothing */
  image_bridge_join();
  CHECK(image_bridge_load_seconds() > 0);
  CHECK(library_mapped("libOpenImageIO"));
  CHECK(image_bridge_wait_seconds() < 0.001);
  CHECK(image_bridge_load(err, sizeof err));
  CHECK(image_bridge_wait_seconds() < 0.001);   /* already loaded: no wait */
}

/* Write a w x h PNG of the given libpng layout with raw rows (test input). */
static void write_png_raw(const char *path, int w, int h, int depth, int type, int interlace,
                          const png_color *palette, int npal, const png_byte *trans, int ntrans,
                          const unsigned char *rows, size_t rowbytes) {
  FILE *f = fopen(path, "wb");
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
  png_infop info = png_create_info_struct(png);
  if (!f || !png || !info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    if (f) fclose(f);
    return;
  }
  png_init_io(png, f);
  png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, depth, type, interlace, 0, 0);
  if (palette) png_set_PLTE(png, info, palette, npal);
  if (trans) png_set_tRNS(png, info, trans, ntrans, NULL);
  png_write_info(png, info);
  int passes = png_set_interlace_handling(png);
  for (int p = 0; p < passes; p++)
    for (int y = 0; y < h; y++) png_write_row(png, rows + (size_t)y * rowbytes);
  png_write_end(png, NULL);
  png_destroy_write_struct(&png, &info);
  fclose(f);
}

/* PNGs other writers make read as OpenImageIO reads them: a palette with
** transparency as RGBA, 2-bit grey as 8-bit grey (codes scaled by 85),
** 16-bit grey + alpha, and an interlaced RGB image row for row. */
TEST(png_reads_every_layout) {
  char err[512] = "";
  Image *img = NULL;
  png_color pal[2] = {{255, 0, 0}, {0, 0, 255}};
  png_byte trans[1] = {0};
  unsigned char idx[2] = {0x01, 0x10};   /* 8-bit indices: rows [0, 1], [1, 0] */
  write_png_raw(tmp_path("pal.png"), 2, 2, 4, PNG_COLOR_TYPE_PALETTE, PNG_INTERLACE_NONE, pal, 2, trans, 1, idx, 1);
  CHECK(image_read(tmp_path("pal.png"), &img, err, sizeof err));
  if (img) {
    CHECK(img->channels == 4 && img->width == 2);
    CHECK(img->data[3] == 0.0f && img->data[4 + 2] == 1.0f && img->data[4 + 3] == 1.0f);
  }
  image_destroy(img);
  img = NULL;
  unsigned char grey[1] = {0x1b};   /* 2-bit codes 0, 1, 2, 3 */
  write_png_raw(tmp_path("grey2.png"), 4, 1, 2, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, NULL, 0, NULL, 0, grey, 1);
  CHECK(image_read(tmp_path("grey2.png"), &img, err, sizeof err));
  if (img) {
    CHECK(img->channels == 1);
    for (int k = 0; k < 4; k++) CHECK(img->data[k] == image_srgb8_to_linear(85 * k));
  }
  image_destroy(img);
  img = NULL;
  unsigned char ga[4] = {0x12, 0x34, 0x80, 0x00};   /* big-endian grey 0x1234, alpha 0x8000 */
  write_png_raw(tmp_path("ga16.png"), 1, 1, 16, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_INTERLACE_NONE, NULL, 0, NULL, 0, ga, 4);
  CHECK(image_read(tmp_path("ga16.png"), &img, err, sizeof err));
  if (img) CHECK(img->channels == 2 && img->data[1] == 0x8000 / 65535.0f && img->data[0] > 0 && img->data[0] < 0.01f);
  image_destroy(img);
  img = NULL;
  Image *src = coded_image(13, 11, 3, 5);
  unsigned char *rgb = malloc(13 * 11 * 3);
  image_to_srgb8(src, rgb);
  write_png_raw(tmp_path("adam7.png"), 13, 11, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_ADAM7, NULL, 0, NULL, 0, rgb, 13 * 3);
  CHECK(image_read(tmp_path("adam7.png"), &img, err, sizeof err) && same_pixels(src, img));
  free(rgb);
  image_destroy(src);
  image_destroy(img);
}

TEST(bridge_loaded_once) {
  char err[512] = "";
  CHECK(image_bridge_load(err, sizeof err));
  double t = image_bridge_load_seconds();
  CHECK(t > 0.0);
  CHECK(image_bridge_load(err, sizeof err));
  CHECK(image_bridge_load_seconds() == t);
}

int main(void) {
  mkdir("build", 0755);
  snprintf(dir, sizeof dir, "build/test-image-XXXXXX");
  if (!mkdtemp(dir)) {
    perror("mkdtemp under build/");
    return 1;
  }
  RUN(png_needs_no_bridge);          /* these two first: nothing has loaded the bridge yet */
  RUN(prefetch_loads_on_a_thread);
  RUN(png_reads_every_layout);
  RUN(srgb_known_values);
  RUN(srgb_codes_round_trip);
  RUN(srgb_encoder_matches_formula);
  RUN(srgb_encoder_every_float_class);
  RUN(row_encoder_matches_one_value_encoder);
  RUN(png_round_trip_exact);
  RUN(tiff_round_trip_exact);
  RUN(png16_round_trip);
  RUN(exr_round_trip_exact_float);
  RUN(jpeg_round_trip_close);
  RUN(alpha_unassociated);
  RUN(write_missing_dir_fails_cleanly);
  RUN(write_unwritable_fails_cleanly);
  RUN(write_replaces_atomically);
  RUN(write_bad_format_names_it);
  RUN(aov_exr_channels);
  RUN(ids_tiff_exact);
  RUN(same_image_same_bytes);
  RUN(stream_matches_whole_write);
  RUN(stream_leaves_no_temporary);
  RUN(read_missing_file);
  RUN(read_not_an_image);
  RUN(read_corrupt_png);
  RUN(limits);
  RUN(limit_values);
  RUN(limit_exr_row);
  RUN(limit_exr_attribute);
  RUN(bridge_loaded_once);
  int status = unit_done();
  if (status == 0) remove_tree(dir);
  return status;
}
