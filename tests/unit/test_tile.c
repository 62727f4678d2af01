/*
** Tiles: the split covers a frame exactly once; tile files keep their
** place (the format's own fields and sumi's description) and `assemble`
** stitches them bit for bit or refuses; the box filter's value at a pixel
** depends on its window alone; and every render test scene, rendered in
** windows of a 2 x 2 split (whole at once, and band by band through a
** rows taker), gives exactly the whole frame's pixels there.
*/
#include <dirent.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "../../src/base/mem.h"
#include "../../src/base/rng.h"
#include "../../src/base/split.h"
#include "../../src/io/assemble.h"
#include "../../src/io/image.h"
#include "../../src/lang/diag.h"
#include "../../src/lang/eval.h"
#include "../../src/lang/parse.h"
#include "../../src/render/ink.h"
#include "../../src/render/render.h"
#include "../../src/render/tile.h"
#include "unit.h"

static char tmp_dir[64];

static const char *tmp_path(const char *name) {
  static char buf[8][256];
  static int k;
  char *b = buf[k++ % 8];
  snprintf(b, 256, "%s/%s", tmp_dir, name);
  return b;
}

/* ---- the split --------------------------------------------------------------- */

/* Every pixel of a w x h frame lies in exactly one tile of a cols x rows
** split, and tiles across differ in size by at most a pixel. */
static int split_covers(int w, int h, int cols, int rows) {
  unsigned char *hit = xcalloc((size_t)w * h, 1);
  int ok = 1, minw = w, maxw = 0;
  for (int i = 1; i <= cols * rows && ok; i++) {
    TileSpec t = {i, cols, rows};
    int x0, y0, x1, y1;
    char err[256];
    ok = tile_split_rect(&t, w, h, &x0, &y0, &x1, &y1, err, sizeof err) && x1 > x0 && y1 > y0;
    for (int y = y0; ok && y < y1; y++)
      for (int x = x0; x < x1; x++) hit[(size_t)y * w + x]++;
    minw = x1 - x0 < minw ? x1 - x0 : minw;
    maxw = x1 - x0 > maxw ? x1 - x0 : maxw;
  }
  for (size_t p = 0; ok && p < (size_t)w * h; p++) ok = hit[p] == 1;
  free(hit);
  return ok && maxw - minw <= 1;
}

TEST(split_covers_the_frame_once) {
  static const int cases[][4] = {{640, 480, 1, 8}, {640, 480, 3, 2}, {7, 5, 7, 5}, {100, 37, 3, 7},
                                 {1, 1, 1, 1}, {1000, 3, 9, 3}, {33, 65, 2, 2}};
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++)
    CHECK(split_covers(cases[k][0], cases[k][1], cases[k][2], cases[k][3]));
}

TEST(split_parse) {
  TileSpec t;
  char err[256];
  CHECK(tile_parse("3/8", &t, err, sizeof err) && t.index == 3 && t.cols == 1 && t.rows == 8);
  CHECK(tile_parse("6/3x2", &t, err, sizeof err) && t.index == 6 && t.cols == 3 && t.rows == 2);
  static const char *const bad[] = {"5/4", "0/0", "0/4", "7/3x2", "1/0", "1/0x3", "a/2", "1/", "/4", "1/2x",
                                    "-1/4", " 1/4", "1/4 ", "1/4x2x2", "1/99999999999", "1/300x300"};
  for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
    err[0] = 0;
    CHECK(!tile_parse(bad[k], &t, err, sizeof err) && strstr(err, "--tile"));
  }
  int x0, y0, x1, y1;
  TileSpec four = {1, 1, 4};
  CHECK(!tile_split_rect(&four, 10, 3, &x0, &y0, &x1, &y1, err, sizeof err));
  CHECK(strstr(err, "3 rows cannot make 4 rows of tiles") != NULL);
}

/* ---- tile files ------------------------------------------------------------------ */

/* A w x h RGB test image of 8-bit codes (x, y and a mix). */
static Image *test_image(int w, int h) {
  Image *img = image_create8(w, h, 3);
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      uint8_t *p = img->data8 + ((size_t)y * w + x) * 3;
      p[0] = (uint8_t)(x * 7), p[1] = (uint8_t)(y * 13), p[2] = (uint8_t)(x ^ y);
    }
  return img;
}

/* Write tile t of img (a frame) to path; 1 on success. */
static int write_tile(const Image *img, const TileSpec *t, const char *render, const char *path) {
  int x0, y0, x1, y1;
  char err[512];
  if (!tile_split_rect(t, img->width, img->height, &x0, &y0, &x1, &y1, err, sizeof err)) return 0;
  Image *part = image_create8(x1 - x0, y1 - y0, 3);
  for (int y = y0; y < y1; y++)
    memcpy(part->data8 + (size_t)(y - y0) * (x1 - x0) * 3, img->data8 + ((size_t)y * img->width + x0) * 3,
           (size_t)(x1 - x0) * 3);
  ImageTile it = {x0, y0, img->width, img->height, "", ""};
  tile_format(t, it.name, sizeof it.name);
  snprintf(it.render, sizeof it.render, "%s", render);
  ImageWriteOptions wo = {0, 0, 0, &it};
  int ok = image_write_opts(path, part, &wo, err, sizeof err);
  if (!ok) fprintf(stderr, "%s\n", err);
  image_destroy(part);
  return ok;
}

TEST(tile_files_keep_their_place) {
  Image *img = test_image(70, 45);
  static const char *const ext[] = {"png", "tif", "exr"};
  for (int k = 0; k < 3; k++) {
    char name[32];
    snprintf(name, sizeof name, "place.%s", ext[k]);
    TileSpec t = {5, 3, 2};   /* the middle of the bottom row: x 23, y 22, 23 x 23 */
    CHECK(write_tile(img, &t, "00ff00ff00ff00ff", tmp_path(name)));
    ImageRaw raw;
    char err[512];
    CHECK(image_read_raw(tmp_path(name), &raw, err, sizeof err));
    CHECK(raw.has_tile && !strcmp(raw.tile.name, "5/3x2") && !strcmp(raw.tile.render, "00ff00ff00ff00ff"));
    CHECK(raw.tile.x == 23 && raw.tile.y == 22 && raw.tile.full_width == 70 && raw.tile.full_height == 45);
    CHECK(raw.width == 23 && raw.height == 23);
    CHECK(raw.x == 23 && raw.y == 22);   /* PNG oFFs, TIFF position, EXR data window */
    if (k > 0) CHECK(raw.full_width == 70 && raw.full_height == 45);   /* TIFF and EXR keep the frame's size */
    image_raw_free(&raw);
  }
  image_destroy(img);
}

TEST(tile_description) {
  ImageTile t = {16, 120, 640, 480, "3/2x4", "9f3a0c5e12b4d7a1"}, u;
  char text[256];
  image_tile_format(&t, text, sizeof text);
  CHECK(!strcmp(text, "sumi tile 3/2x4 of 640x480 at 16,120 render 9f3a0c5e12b4d7a1"));
  CHECK(image_tile_parse(text, &u) && !memcmp(&t, &u, sizeof t));
  CHECK(!image_tile_parse("sumi tile 3/2x4 of 640x480 at 16,120", &u));
  CHECK(!image_tile_parse("a photograph", &u));
}

/* Assemble the given tile files of a 3 x 2 split into out; 1 on success. */
static int assemble6(const char *const *names, int n, const char *out, char *err, size_t errlen) {
  const char *paths[8];
  for (int i = 0; i < n; i++) paths[i] = tmp_path(names[i]);
  return assemble_tiles(paths, n, tmp_path(out), err, errlen);
}

TEST(assemble_stitches_or_refuses) {
  Image *img = test_image(70, 45);
  static const char *const names[] = {"a1.png", "a2.png", "a3.png", "a4.png", "a5.png", "a6.png"};
  for (int i = 0; i < 6; i++) {
    TileSpec t = {i + 1, 3, 2};
    CHECK(write_tile(img, &t, "1111111111111111", tmp_path(names[i])));
  }
  char err[1200];
  const char *shuffled[] = {names[4], names[1], names[5], names[0], names[3], names[2]};
  CHECK(assemble6(shuffled, 6, "whole.png", err, sizeof err));
  char ref[256];
  snprintf(ref, sizeof ref, "%s", tmp_path("ref.png"));
  CHECK(image_write(ref, img, err, sizeof err));
  ImageRaw a, b;
  CHECK(image_read_raw(tmp_path("whole.png"), &a, err, sizeof err) && image_read_raw(ref, &b, err, sizeof err));
  CHECK(a.width == 70 && a.height == 45 && !a.has_tile && !memcmp(a.data, b.data, 70 * 45 * 3));
  image_raw_free(&a);
  image_raw_free(&b);

  CHECK(!assemble6(names, 5, "x.png", err, sizeof err) && strstr(err, "tile 6/3x2 is missing"));
  const char *twice[] = {names[0], names[1], names[2], names[3], names[4], names[4]};
  CHECK(!assemble6(twice, 6, "x.png", err, sizeof err) && strstr(err, "tile 5/3x2 is given twice"));
  TileSpec other = {6, 3, 2};   /* another render's tile 6 */
  CHECK(write_tile(img, &other, "2222222222222222", tmp_path("b6.png")));
  const char *mixed[] = {names[0], names[1], names[2], names[3], names[4], "b6.png"};
  CHECK(!assemble6(mixed, 6, "x.png", err, sizeof err) && strstr(err, "a different render"));
  TileSpec rows = {2, 1, 6};   /* the same render split otherwise */
  CHECK(write_tile(img, &rows, "1111111111111111", tmp_path("r2.png")));
  const char *split[] = {names[0], "r2.png"};
  CHECK(!assemble6(split, 2, "x.png", err, sizeof err) && strstr(err, "a different split"));
  CHECK(image_write(tmp_path("plain.png"), img, err, sizeof err));
  const char *plain[] = {"plain.png"};
  CHECK(!assemble6(plain, 1, "x.png", err, sizeof err) && strstr(err, "is not a tile"));
  const char *floats[] = {names[0]};
  CHECK(!assemble6(floats, 1, "x.exr", err, sizeof err));
  struct stat st;
  CHECK(stat(tmp_path("x.png"), &st) != 0 && stat(tmp_path("x.exr"), &st) != 0);   /* nothing written */
  image_destroy(img);
}

/* ---- the box filter: a pixel's window alone ------------------------------------ */

TEST(box_filter_depends_on_the_window_alone) {
  int w = 61, h = 47, side = 5, r = side / 2;
  Rng g;
  rng_seed_key(&g, 7, 1, 2);
  float *whole = xmalloc((size_t)w * h * sizeof *whole);
  uint8_t *wt = xmalloc((size_t)w * h);
  for (int i = 0; i < w * h; i++) {   /* ink with tiny amounts beside large ones, as diffusion leaves */
    whole[i] = (float)(rng_uniform(&g) < 0.5 ? 255 * rng_uniform(&g) : 1e-4 * rng_uniform(&g));
    wt[i] = rng_uniform(&g) < 0.8;
  }
  int x0 = 13, y0 = 9, x1 = 40, y1 = 31, ww = x1 - x0 + 2 * r, wh = y1 - y0 + 2 * r;
  float *part = xmalloc((size_t)ww * wh * sizeof *part);
  uint8_t *pwt = xmalloc((size_t)ww * wh);
  for (int y = 0; y < wh; y++)
    for (int x = 0; x < ww; x++) {
      part[y * ww + x] = whole[(y + y0 - r) * w + x + x0 - r];
      pwt[y * ww + x] = wt[(y + y0 - r) * w + x + x0 - r];
    }
  float *pw[1] = {whole}, *pp[1] = {part};
  ink_box_filter(pw, 1, wt, w, h, side);
  ink_box_filter(pp, 1, pwt, ww, wh, side);
  int same = 1;
  for (int y = y0; y < y1; y++)
    for (int x = x0; x < x1; x++) same &= !memcmp(&whole[y * w + x], &part[(y - y0 + r) * ww + x - x0 + r], sizeof(float));
  CHECK(same);
  free(whole);
  free(wt);
  free(part);
  free(pwt);
}

/* ---- every render test scene in windows ---------------------------------------- */

/* A rows taker that keeps the rows it is handed. */
typedef struct Collect {
  Image *img;
  int next;     /* the next row it expects */
  int ordered;  /* every band came in order */
} Collect;

static int collect_begin(void *ctx, const Image *img) {
  Collect *c = ctx;
  c->img = image_create8(img->width, img->height, img->channels);
  return 1;
}

static void collect_rows(void *ctx, const Image *band, int y0, int y1) {
  Collect *c = ctx;
  c->ordered &= y0 == c->next && band->width == c->img->width;
  memcpy(c->img->data8 + (size_t)y0 * c->img->width * c->img->channels, band->data8,
         (size_t)(y1 - y0) * band->width * band->channels);
  c->next = y1;
}

/* Do the pixels of part equal those of whole under r? */
static int same_pixels(const Image *whole, const Image *part, RenderWindow r) {
  if (!part || part->width != r.x1 - r.x0 || part->height != r.y1 - r.y0 || part->channels != whole->channels ||
      !part->data8 != !whole->data8)
    return 0;
  size_t es = whole->data8 ? 1 : sizeof(float), row = (size_t)part->width * part->channels * es;
  const char *a = whole->data8 ? (const char *)whole->data8 : (const char *)whole->data;
  const char *b = part->data8 ? (const char *)part->data8 : (const char *)part->data;
  for (int y = 0; y < part->height; y++)
    if (memcmp(a + (((size_t)(y + r.y0) * whole->width + r.x0) * whole->channels) * es, b + (size_t)y * row, row))
      return 0;
  return 1;
}

/* -W, -H and --threads of a render test's "// args:" line. */
static void scene_args(const char *path, RenderOptions *ro) {
  FILE *f = fopen(path, "r");
  char line[512];
  for (int k = 0; f && k < 3 && fgets(line, sizeof line, f); k++) {
    const char *a = strstr(line, "// args:");
    if (!a) continue;
    const char *w = strstr(a, "-W "), *h = strstr(a, "-H "), *t = strstr(a, "--threads ");
    if (w) ro->width = atoi(w + 3);
    if (h) ro->height = atoi(h + 3);
    if (t) ro->threads = atoi(t + 10);
  }
  if (f) fclose(f);
}

/* Render scene file path whole and as the 4 tiles of a 2 x 2 split, each
** at once and band by band; 1 when every tile has the whole's pixels. */
static int tiles_match(const char *path) {
  Arena arena;
  arena_init(&arena);
  Scene s;
  scene_init(&s);
  const char *why;
  int file = diag_load_file(path, -1, src_none(), &why), ok = 0;
  AstNode *prog = file >= 0 ? parse_file(file, &arena) : NULL;
  EvalOptions eo;
  eval_options_init(&eo);
  eo.stdlib_dir = "../../stdlib";   /* run from tests/render, as the render suite runs them */
  if (prog && !diag_error_count() && eval_program(prog, file, &arena, &eo, &s) == 0) {
    RenderOptions ro;
    memset(&ro, 0, sizeof ro);
    scene_args(path, &ro);
    render_resolve_size(&s, ro.width, ro.height, &ro.width, &ro.height);
    ro.threads = ro.threads ? ro.threads : 2;
    ro.out8 = 1;
    Image *whole = NULL;
    ok = render_scene(&s, &ro, &whole, NULL) == 0;
    for (int i = 1; ok && i <= 4; i++) {
      TileSpec t = {i, 2, 2};
      char err[256];
      ok = tile_rect(&t, ro.width, ro.height, &ro.window, err, sizeof err);
      Image *part = NULL;
      ok = ok && render_scene(&s, &ro, &part, NULL) == 0 && same_pixels(whole, part, ro.window);
      image_destroy(part);
      Collect c = {NULL, 0, 1};
      RenderRows rows = {&c, collect_begin, collect_rows};
      RenderOptions rb = ro;
      rb.rows = &rows;
      part = NULL;
      ok = ok && render_scene(&s, &rb, &part, NULL) == 0;
      const Image *got = c.img ? c.img : part;   /* band by band, or at once when it needs margins */
      ok = ok && c.ordered && same_pixels(whole, got, ro.window) && (!c.img || c.next == got->height);
      image_destroy(c.img);
      image_destroy(part);
      if (!ok) fprintf(stderr, "%s: tile %d/2x2 differs from the whole frame\n", path, i);
    }
    image_destroy(whole);
  }
  scene_free(&s);
  arena_free(&arena);
  diag_shutdown();
  diag_init(DIAG_TEXT);
  return ok;
}

/* Does scene file path say it needs a file that is absent (// needs:)? */
static int needs_absent(const char *path) {
  FILE *f = fopen(path, "r");
  char line[512];
  int absent = 0;
  for (int k = 0; f && k < 3 && fgets(line, sizeof line, f); k++) {
    char *n = strstr(line, "// needs:");
    if (!n) continue;
    n += 9;
    while (*n == ' ') n++;
    n[strcspn(n, "\r\n")] = 0;
    struct stat st;
    absent = stat(n, &st) != 0;
  }
  if (f) fclose(f);
  return absent;
}

TEST(render_scenes_tile_exactly) {
  /* from the suite's folder: a scene names some files (origami textures)
  ** relative to where it is run */
  CHECK(chdir("tests/render") == 0);
  DIR *d = opendir(".");
  CHECK(d != NULL);
  int scenes = 0;
  for (struct dirent *e; d && (e = readdir(d));) {
    size_t n = strlen(e->d_name);
    if (n < 5 || strcmp(e->d_name + n - 4, ".npr")) continue;
    char path[512];
    snprintf(path, sizeof path, "%s", e->d_name);
    if (needs_absent(path)) continue;
    CHECK(tiles_match(path));
    scenes++;
  }
  if (d) closedir(d);
  CHECK(scenes > 20);
  CHECK(chdir("../..") == 0);
}

int main(void) {
  snprintf(tmp_dir, sizeof tmp_dir, "/tmp/sumi-test-tile-%d", (int)getpid());
  mkdir(tmp_dir, 0755);
  diag_init(DIAG_TEXT);
  RUN(split_covers_the_frame_once);
  RUN(split_parse);
  RUN(tile_files_keep_their_place);
  RUN(tile_description);
  RUN(assemble_stitches_or_refuses);
  RUN(box_filter_depends_on_the_window_alone);
  RUN(render_scenes_tile_exactly);
  char cmd[128];
  snprintf(cmd, sizeof cmd, "rm -rf %s", tmp_dir);
  if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmp_dir);
  image_bridge_join();
  return unit_done();
}
