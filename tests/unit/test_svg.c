/*
** Unit tests of the SVG writer's tracing (src/render/svg_trace.c): potrace
** outlines enclose the pixels they trace (a disc, a ring, a square as a
** polygon), colour classes find toon bands, absorb specks and posterise a
** gradient within a step, and a layer reaches under the later layers it
** meets so no gap opens between them. The whole writer is checked against
** the PNG by the render suite (tests/render/svg_*.npr, through rsvg-convert).
*/
#include "../../src/render/svg_trace.h"
#include "unit.h"

#include <stdlib.h>
#include <string.h>

/* Area enclosed by path data d (M, L, C and Z commands, as svg_trace
** writes them; Beziers flattened into 32 chords), even-odd: the signed
** areas of potrace's outer curves and holes, which turn opposite ways. */
static double path_area(const char *d) {
  double area = 0, x = 0, y = 0, sx = 0, sy = 0;
  char *p = (char *)d;
  while (*p && *p != '"') {
    char c = *p++;
    if (c == 'M') {
      sx = x = strtod(p, &p);
      sy = y = strtod(p, &p);
    } else if (c == 'L' || c == 'Z') {
      double nx = c == 'Z' ? sx : strtod(p, &p), ny = c == 'Z' ? sy : strtod(p, &p);
      area += x * ny - nx * y;
      x = nx, y = ny;
    } else if (c == 'C') {
      double q[6];
      for (int k = 0; k < 6; k++) q[k] = strtod(p, &p);
      double px = x, py = y;
      for (int i = 1; i <= 32; i++) {
        double t = i / 32.0, u = 1 - t;
        double nx = u * u * u * x + 3 * u * u * t * q[0] + 3 * u * t * t * q[2] + t * t * t * q[4];
        double ny = u * u * u * y + 3 * u * u * t * q[1] + 3 * u * t * t * q[3] + t * t * t * q[5];
        area += px * ny - nx * py;
        px = nx, py = ny;
      }
      x = q[4], y = q[5];
    }
  }
  return fabs(area / 2);
}

/* What f holds from the start, NUL-ended (malloc'ed). */
static char *slurp(FILE *f) {
  long n = ftell(f);
  char *t = malloc((size_t)n + 1);
  rewind(f);
  size_t got = fread(t, 1, (size_t)n, f);
  t[got] = 0;
  return t;
}

/* Trace mask (w x h, whole frame) into a string. */
static char *traced(const unsigned char *mask, int w, int h, double alphamax, int *curves) {
  FILE *f = tmpfile();
  SvgBox box = {0, 0, w - 1, h - 1};
  *curves = svg_trace(f, mask, w, box, alphamax);
  char *t = slurp(f);
  fclose(f);
  return t;
}

static int count_char(const char *s, char c) {
  int n = 0;
  for (; *s; s++) n += *s == c;
  return n;
}

/* A disc's smooth outline encloses its pixels' area within 3%; a ring is
** two curves (the hole turns the other way) enclosing the ring's pixels. */
TEST(trace_disc_and_ring) {
  enum { W = 64 };
  static unsigned char disc[W * W], ring[W * W];
  long nd = 0, nr = 0;
  for (int y = 0; y < W; y++)
    for (int x = 0; x < W; x++) {
      double r = hypot(x + 0.5 - 32, y + 0.5 - 32);
      nd += disc[y * W + x] = r < 20;
      nr += ring[y * W + x] = r < 20 && r >= 9;
    }
  int n;
  char *t = traced(disc, W, W, 1.0, &n);
  CHECK_EQ_INT(n, 1);
  CHECK(strchr(t, 'C') != NULL);                      /* curves, not a staircase */
  CHECK_NEAR(path_area(t), (double)nd, 0.03 * nd);   /* the curves cut the staircase's corners */
  free(t);
  t = traced(ring, W, W, 1.0, &n);
  CHECK_EQ_INT(n, 2);
  CHECK_NEAR(path_area(t), (double)nr, 0.03 * nr);
  free(t);
}

/* With alphamax 0 a square traces as a polygon through its corners: area exact. */
TEST(trace_square_polygon) {
  enum { W = 32 };
  static unsigned char sq[W * W];
  for (int y = 5; y < 15; y++)
    for (int x = 8; x < 20; x++) sq[y * W + x] = 1;
  int n;
  char *t = traced(sq, W, W, 0.0, &n);
  CHECK_EQ_INT(n, 1);
  CHECK(strchr(t, 'C') == NULL);
  CHECK_NEAR(path_area(t), 120.0, 1e-9);
  CHECK(strstr(t, "8.00 5.00") != NULL && strstr(t, "20.00 15.00") != NULL);
  free(t);
}

/* A frame w x h (w * h <= MAXPIX) of one object (owner 0) at one depth,
** in static buffers; its colours to be put. */
enum { MAXPIX = 2048 };
static uint8_t rgba[MAXPIX * 4];
static int32_t owner[MAXPIX];
static float depth[MAXPIX];

static SvgFrame frame(int w, int h) {
  SvgFrame fr = {w, h, rgba, owner, depth, 1, 1};
  for (int p = 0; p < w * h; p++) owner[p] = 0, depth[p] = 0.5f, rgba[4 * p + 3] = 255;
  return fr;
}

/* The classes of every pixel of fr into cls. */
static int classes_of_all(const SvgFrame *fr, int *cls, uint8_t *rgb) {
  static int sel[MAXPIX];
  int ncls;
  for (int p = 0; p < fr->w * fr->h; p++) sel[p] = p;
  svg_classes(fr, sel, fr->w * fr->h, cls, &ncls, rgb);
  return ncls;
}

static void put(int p, int r, int g, int b) {
  rgba[4 * p] = (uint8_t)r, rgba[4 * p + 1] = (uint8_t)g, rgba[4 * p + 2] = (uint8_t)b;
}

/* Three toon bands with an antialiased row between two of them (blends of
** the two changing from pixel to pixel, as a sloped edge's do) and a
** two-pixel speck of another colour: three classes, dark to light, the
** blends joined to a band next to them, the speck to the band around it. */
TEST(classes_find_bands) {
  enum { W = 40, H = 30 };
  SvgFrame fr = frame(W, H);
  static const int band[3][3] = {{200, 220, 240}, {20, 40, 90}, {90, 120, 170}};
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      const int *c = band[y / 10];
      put(y * W + x, c[0], c[1], c[2]);
      int k = x % 3 + 1;   /* 1/4, 2/4 or 3/4 of band 0 over band 2 */
      if (y == 10) put(y * W + x, (k * 200 + (4 - k) * 90) / 4, (k * 220 + (4 - k) * 120) / 4, (k * 240 + (4 - k) * 170) / 4);
    }
  put(25 * W + 7, 250, 10, 10);
  put(25 * W + 8, 250, 10, 10);
  static int cls[W * H];
  uint8_t rgb[SVG_MAX_CLASSES * 3];
  int ncls = classes_of_all(&fr, cls, rgb);
  CHECK_EQ_INT(ncls, 3);
  CHECK(rgb[0] < rgb[3] && rgb[3] < rgb[6]);          /* dark to light */
  CHECK(rgb[1] == 40 && rgb[4] == 120 && rgb[7] == 220);
  CHECK_EQ_INT(cls[5 * W], 2);                          /* band 0 (light) */
  CHECK_EQ_INT(cls[15 * W], 0);                         /* band 1 (dark) */
  CHECK_EQ_INT(cls[25 * W + 7], 1);                     /* the speck, in band 2 */
  CHECK(cls[10 * W + 3] == 1 || cls[10 * W + 3] == 2);  /* the blend, to a band beside it */
}

/* A grey ramp posterises into steps: every pixel within 2 steps of its
** class colour, the classes in order along the ramp. */
TEST(classes_posterise_a_gradient) {
  enum { W = 256, H = 4 };
  SvgFrame fr = frame(W, H);
  for (int p = 0; p < W * H; p++) put(p, p % W, p % W, p % W);
  static int cls[W * H];
  uint8_t rgb[SVG_MAX_CLASSES * 3];
  int ncls = classes_of_all(&fr, cls, rgb);
  CHECK(ncls >= 256 / (2 * SVG_CLASS_STEP + 16) && ncls <= SVG_MAX_CLASSES);
  int worst = 0, ordered = 1;
  for (int x = 0; x < W; x++) {
    int d = abs(rgb[3 * cls[x]] - x);
    if (d > worst) worst = d;
    if (x && cls[x] < cls[x - 1]) ordered = 0;
  }
  CHECK(worst <= 2 * SVG_CLASS_STEP);
  CHECK(ordered);
}

/* Two objects side by side, the nearer painted last: the farther one's
** path reaches SVG_UNDERLAP pixels under it, the nearer one's encloses just
** its own pixels. */
TEST(layers_reach_under_later_ones) {
  enum { W = 48, H = 24 };
  SvgFrame fr = frame(W, H);
  fr.nobjects = 2;
  for (int p = 0; p < W * H; p++) {
    int x = p % W, near = x >= 24;
    owner[p] = x < 4 || x >= 44 ? -1 : near;
    depth[p] = near ? 0.3f : 0.6f;
    if (owner[p] < 0) put(p, 255, 255, 255);   /* a flat background: the rectangle, no layer */
    else if (near) put(p, 200, 50, 40);
    else put(p, 40, 80, 160);
  }
  FILE *f = tmpfile();
  svg_write_regions(f, &fr);
  char *t = slurp(f);
  fclose(f);
  CHECK_EQ_INT(count_char(t, '<'), 2);
  const char *first = strstr(t, "#2850a0"), *second = strstr(t, "#c83228");
  CHECK(first && second && first < second);             /* far (blue) first */
  if (first && second) {
    double far = path_area(strstr(first, "d=\"") + 3);
    CHECK(far >= 21.0 * H);                              /* at least a pixel under the nearer one */
    CHECK_NEAR(far, 20.0 * H + SVG_UNDERLAP * H, 0.02 * 20 * H);
    CHECK_NEAR(path_area(strstr(second, "d=\"") + 3), 20.0 * H, 0.02 * 20 * H);
  }
  free(t);
}

int main(void) {
  RUN(trace_disc_and_ring);
  RUN(trace_square_polygon);
  RUN(classes_find_bands);
  RUN(classes_posterise_a_gradient);
  RUN(layers_reach_under_later_ones);
  return unit_done();
}
