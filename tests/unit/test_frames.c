/*
** Animation frames (sumi render --frames SPEC [--only LIST] [--loop]): the
** clock each frame sees. Without --loop it runs 0..1 from the first frame
** to the last; with it, a loop of n frames takes clock k / n, so the last
** frame is not the first again and frame n would be (clock 1 = clock 0 of
** the next turn). Lists and steps keep the animation's span (the clock),
** --only picks among them, the output pattern takes the number; and for
** --resume, a file cut short at any byte is never taken for a whole one,
** in every format a render writes, while the whole file always is.
*/
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "../../src/base/frames.h"
#include "../../src/io/image.h"
#include "../../src/io/outfile.h"
#include "../../src/scene/scene.h"
#include "unit.h"

static char tmp_dir[64];

static const char *tmp_path(const char *name) {
  static char buf[4][256];
  static int k;
  char *b = buf[k++ % 4];
  snprintf(b, 256, "%s/%s", tmp_dir, name);
  return b;
}

/* ---- the clock --------------------------------------------------------------- */

TEST(frames_run_from_0_to_1) {
  CHECK_NEAR(scene_frame_clock(0, 11, 0, 0), 0, 0);
  CHECK_NEAR(scene_frame_clock(0, 11, 11, 0), 1, 0);
  CHECK_NEAR(scene_frame_clock(0, 11, 3, 0), 3.0 / 11, 1e-15);
  CHECK_NEAR(scene_frame_clock(5, 9, 7, 0), 0.5, 1e-15);
  CHECK_NEAR(scene_frame_clock(4, 4, 4, 0), 0, 0);   /* one frame */
}

TEST(loop_stays_below_1) {
  /* 12 frames, 0..11: clock k / 12, the last 11 / 12, and the turn's
  ** 13th frame would be clock 1, where the loop starts over */
  for (int k = 0; k < 12; k++) CHECK_NEAR(scene_frame_clock(0, 11, k, 1), k / 12.0, 1e-15);
  CHECK(scene_frame_clock(0, 11, 11, 1) < 1);
  CHECK_NEAR(scene_frame_clock(0, 11, 12, 1), 1, 0);
  CHECK_NEAR(scene_frame_clock(10, 13, 12, 1), 0.5, 1e-15);   /* 4 frames from 10 */
  CHECK_NEAR(scene_frame_clock(4, 4, 4, 1), 0, 0);            /* one frame: still 0 */
}

/* ---- frame sets ------------------------------------------------------------- */

/* spec (and only) parse to exactly the frames of want (n of them, ending
** in -1) over the animation first..last. */
static int frames_are(const char *spec, const char *only, int first, int last, const int *want) {
  FrameSet fs;
  char err[256];
  if (!frames_parse(spec, only, &fs, err, sizeof err)) {
    fprintf(stderr, "  %s: %s\n", spec, err);
    return 0;
  }
  int n = 0;
  while (want[n] >= 0) n++;
  int ok = fs.first == first && fs.last == last && fs.count == n;
  for (int i = 0; ok && i < n; i++) ok = fs.frames[i] == want[i];
  if (!ok) fprintf(stderr, "  %s: %d frames over %d..%d\n", spec, fs.count, fs.first, fs.last);
  frames_free(&fs);
  return ok;
}

/* spec (and only) are refused with exactly the message msg. */
static int frames_refused(const char *spec, const char *only, const char *msg) {
  FrameSet fs;
  char err[256] = "";
  int ok = !frames_parse(spec, only, &fs, err, sizeof err) && !strcmp(err, msg);
  if (!ok) fprintf(stderr, "  %s: got `%s`\n", spec, err);
  return ok;
}

TEST(frames_steps_and_lists) {
  CHECK(frames_are("0:4", NULL, 0, 4, (int[]){0, 1, 2, 3, 4, -1}));
  CHECK(frames_are("7", NULL, 7, 7, (int[]){7, -1}));
  CHECK(frames_are("0:10:5", NULL, 0, 10, (int[]){0, 5, 10, -1}));
  /* a step that passes the end by: the animation still ends at 119 */
  CHECK(frames_are("0:119:50", NULL, 0, 119, (int[]){0, 50, 100, -1}));
  /* a list: ascending, each frame once, the span from lowest to highest */
  CHECK(frames_are("9,1,5:6,5", NULL, 1, 9, (int[]){1, 5, 6, 9, -1}));
  CHECK(frames_are("0:100:50,0:100:25", NULL, 0, 100, (int[]){0, 25, 50, 75, 100, -1}));
  /* --only: a job's share, the clock still the whole animation's */
  CHECK(frames_are("0:119", "17", 0, 119, (int[]){17, -1}));
  CHECK(frames_are("0:119:10", "20:40:10,110", 0, 119, (int[]){20, 30, 40, 110, -1}));
  CHECK(frames_are("0:1000000", "1000000", 0, 1000000, (int[]){1000000, -1}));
}

TEST(frames_clock_follows_the_animation) {
  FrameSet all, step, only;
  char err[256];
  CHECK(frames_parse("0:12", NULL, &all, err, sizeof err));
  CHECK(frames_parse("0:12:4", NULL, &step, err, sizeof err));
  CHECK(frames_parse("0:12", "8", &only, err, sizeof err));
  /* frame 8 has one clock whichever way the run is cut */
  double c = scene_frame_clock(all.first, all.last, 8, 0);
  CHECK_NEAR(c, 8.0 / 12, 1e-15);
  CHECK(scene_frame_clock(step.first, step.last, 8, 0) == c);
  CHECK(scene_frame_clock(only.first, only.last, 8, 0) == c);
  CHECK(scene_frame_clock(only.first, only.last, 8, 1) == 8.0 / 13);
  frames_free(&all), frames_free(&step), frames_free(&only);
}

TEST(frames_errors) {
  CHECK(frames_refused("5:2", NULL, "--frames 5:2: 5:2 runs backwards; a range goes from its first frame up "
                                    "to its last, as 2:5 does"));
  CHECK(frames_refused("0:10,9:3", NULL, "--frames 0:10,9:3: 9:3 runs backwards; a range goes from its first "
                                         "frame up to its last, as 3:9 does"));
  CHECK(frames_refused("0:10:0", NULL, "--frames 0:10:0: a step is 1 or more, not 0"));
  const char *bad[] = {"", "x", "1:", ":3", "1,,2", "1,", "-1:3", "1:2:3:4", "1:2:-1", "0x10", "1 ", NULL};
  for (int i = 0; bad[i]; i++) {
    char msg[256];
    snprintf(msg, sizeof msg, "--frames takes A:B, A:B:STEP or a list of them (e.g. 0:119, 0:119:10 or 1,5,9:12), "
             "not `%s`", bad[i]);
    CHECK(frames_refused(bad[i], NULL, msg));
  }
  CHECK(frames_refused("0:1000001", NULL, "--frames 0:1000001: frame numbers run from 0 to 1000000"));
  CHECK(frames_refused("99999999999999999999", NULL,
                       "--frames 99999999999999999999: frame numbers run from 0 to 1000000"));
  CHECK(frames_refused("0:119:10", "5", "--only 5: frame 5 is not one of --frames 0:119:10"));
  CHECK(frames_refused("0:119", "100:130", "--only 100:130: frame 120 is not one of --frames 0:119"));
  CHECK(frames_refused("0:119", "9:3", "--only 9:3: 9:3 runs backwards; a range goes from its first frame up "
                                       "to its last, as 3:9 does"));
}

TEST(frames_output_pattern) {
  char buf[256];
  frames_path(buf, sizeof buf, "out/f_####.png", 17);
  CHECK(!strcmp(buf, "out/f_0017.png"));
  frames_path(buf, sizeof buf, "f_##.t3.png", 7);
  CHECK(!strcmp(buf, "f_07.t3.png"));
  frames_path(buf, sizeof buf, "f_##.png", 1234);   /* a number wider than the run keeps its digits */
  CHECK(!strcmp(buf, "f_1234.png"));
  frames_path(buf, sizeof buf, "shot.v2/frame.png", 3);
  CHECK(!strcmp(buf, "shot.v2/frame_0003.png"));
  frames_path(buf, sizeof buf, "shot.v2/frame", 3);
  CHECK(!strcmp(buf, "shot.v2/frame_0003"));
}

/* ---- whole files ------------------------------------------------------------ */

/* Copy the first n bytes of file from into file to. */
static void copy_head(const char *from, const char *to, long n) {
  FILE *in = fopen(from, "rb"), *out = fopen(to, "wb");
  for (long i = 0; in && out && i < n; i++) {
    int c = fgetc(in);
    if (c == EOF) break;
    fputc(c, out);
  }
  if (in) fclose(in);
  if (out) fclose(out);
}

/* path is whole, and every copy of it cut short (at each byte) is not. */
static int whole_only_when_whole(const char *path) {
  struct stat st;
  if (stat(path, &st) != 0 || !outfile_complete(path)) {
    fprintf(stderr, "  %s: the whole file is not taken as whole\n", path);
    return 0;
  }
  const char *ext = strrchr(path, '.');
  char cut[300];
  snprintf(cut, sizeof cut, "%s.cut%s", path, ext);
  for (long n = 0; n < st.st_size; n++) {
    copy_head(path, cut, n);
    if (outfile_complete(cut)) {
      fprintf(stderr, "  %s cut to %ld of %ld bytes is taken as whole\n", path, n, (long)st.st_size);
      return 0;
    }
  }
  return 1;
}

/* A w x h test image of nc channels, 8-bit codes or floats. */
static Image *test_image(int w, int h, int nc, int codes) {
  Image *img = codes ? image_create8(w, h, nc) : image_create(w, h, nc);
  for (int i = 0; i < w * h * nc; i++) {
    if (codes) img->data8[i] = (uint8_t)(i * 37 % 251);
    else img->data[i] = (float)(i * 37 % 251) / 250;
  }
  return img;
}

TEST(a_file_cut_short_is_not_whole) {
  char err[512];
  ImageTile tile = {12, 0, 24, 18, "2/2x3", "0123456789abcdef"};
  const char *names[] = {"a.png", "a.tif", "a.exr", "a.jpg", "tile.png", "tile.tif", "tile.exr", NULL};
  for (int i = 0; names[i]; i++) {
    int is_exr = strstr(names[i], ".exr") != NULL, is_jpg = strstr(names[i], ".jpg") != NULL;
    Image *img = test_image(12, 6, is_jpg ? 3 : 4, !is_exr);
    ImageWriteOptions wo = {0, 0, 0, names[i][0] == 't' ? &tile : NULL};
    CHECK(image_write_opts(tmp_path(names[i]), img, &wo, err, sizeof err));
    CHECK(whole_only_when_whole(tmp_path(names[i])));
    image_destroy(img);
  }
  Image *img = test_image(12, 6, 3, 0);
  ImageWriteOptions deep = {16, 0, 0, NULL};
  CHECK(image_write_opts(tmp_path("deep.png"), img, &deep, err, sizeof err));
  CHECK(whole_only_when_whole(tmp_path("deep.png")));
  CHECK(image_write_opts(tmp_path("deep.tif"), img, &deep, err, sizeof err));
  CHECK(whole_only_when_whole(tmp_path("deep.tif")));
  image_destroy(img);
  FILE *f = fopen(tmp_path("a.svg"), "w");
  if (f) fputs("<svg xmlns=\"http://www.w3.org/2000/svg\">\n<g>\n</g>\n</svg>\n", f), fclose(f);
  CHECK(whole_only_when_whole(tmp_path("a.svg")));
}

TEST(not_whole_files) {
  CHECK(!outfile_complete(tmp_path("missing.png")));
  CHECK(!outfile_complete(tmp_dir));   /* a folder */
  FILE *f = fopen(tmp_path("text.png"), "w");
  if (f) fputs("not an image\n", f), fclose(f);
  CHECK(!outfile_complete(tmp_path("text.png")));
  char err[512];
  Image *img = test_image(8, 8, 3, 1);
  CHECK(image_write(tmp_path("really_a.png"), img, err, sizeof err));
  CHECK(rename(tmp_path("really_a.png"), tmp_path("named.tif")) == 0);   /* another format under the name */
  CHECK(!outfile_complete(tmp_path("named.tif")));
  image_destroy(img);
}

int main(void) {
  snprintf(tmp_dir, sizeof tmp_dir, "/tmp/sumi-test-frames-%d", (int)getpid());
  mkdir(tmp_dir, 0755);
  RUN(frames_run_from_0_to_1);
  RUN(loop_stays_below_1);
  RUN(frames_steps_and_lists);
  RUN(frames_clock_follows_the_animation);
  RUN(frames_errors);
  RUN(frames_output_pattern);
  RUN(a_file_cut_short_is_not_whole);
  RUN(not_whole_files);
  char cmd[128];
  snprintf(cmd, sizeof cmd, "rm -rf %s", tmp_dir);
  if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmp_dir);
  image_bridge_join();
  return unit_done();
}
