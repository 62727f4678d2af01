/*
** Image maps: the pyramid averages in linear light (a black-and-white
** checker becomes the grey that is half the light, sRGB code 188, not
** code 128), a texel's centre reads the texel, bilinear weights between
** centres, the footprint picks the level (trilinear between two), the
** image repeats and its first row is at v = 1, alpha lays it over the
** base, and a mid-grey texel renders as its own code.
*/
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../src/io/image.h"
#include "../../src/render/imagemap.h"
#include "../../src/render/render.h"
#include "render_scenes.h"
#include "unit.h"

/* A w x h checker of 1-texel squares, black and white (linear 0 and 1). */
static ImageMap *checker(int w, int h) {
  float *t = malloc((size_t)w * h * 4 * sizeof *t);
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      float v = (float)((x + y) % 2);
      float *p = &t[((size_t)y * w + x) * 4];
      p[0] = p[1] = p[2] = v;
      p[3] = 1;
    }
  ImageMap *m = imagemap_from_rgba(t, w, h);
  free(t);
  return m;
}

TEST(pyramid_levels_and_linear_means) {
  ImageMap *m = checker(8, 4);
  CHECK_EQ_INT(m->nlevels, 4);   /* 8x4, 4x2, 2x1, 1x1 */
  CHECK_EQ_INT(m->level[1].w, 4);
  CHECK_EQ_INT(m->level[1].h, 2);
  CHECK_EQ_INT(m->level[3].w, 1);
  CHECK_EQ_INT(m->level[3].h, 1);
  for (int k = 1; k < m->nlevels; k++) CHECK_NEAR(m->level[k].rgba[0], 0.5, 1e-6);
  /* half the light shows as code 188, where a mean of codes would be 128 */
  CHECK_EQ_INT(image_linear_to_srgb8(m->level[1].rgba[0]), 188);
  imagemap_free(m);
}

TEST(bilinear_centres_and_between) {
  float t[2 * 2 * 4] = {0, 0, 0, 1,   1, 1, 1, 1,     /* top row: black, white */
                        0.5f, 0.5f, 0.5f, 1,   0.25f, 0.25f, 0.25f, 1};
  ImageMap *m = imagemap_from_rgba(t, 2, 2);
  float c[4];
  imagemap_bilinear(m, 0, 0.25f, 0.75f, c);   /* the top-left texel's centre: v = 1 is the first row */
  CHECK_NEAR(c[0], 0, 1e-6);
  imagemap_bilinear(m, 0, 0.75f, 0.75f, c);   /* top right */
  CHECK_NEAR(c[0], 1, 1e-6);
  imagemap_bilinear(m, 0, 0.25f, 0.25f, c);   /* bottom left */
  CHECK_NEAR(c[0], 0.5, 1e-6);
  imagemap_bilinear(m, 0, 0.5f, 0.75f, c);    /* half way along the top row */
  CHECK_NEAR(c[0], 0.5, 1e-6);
  imagemap_bilinear(m, 0, 0.5f, 0.5f, c);     /* the middle: the four's mean */
  CHECK_NEAR(c[0], (0 + 1 + 0.5 + 0.25) / 4, 1e-6);
  imagemap_bilinear(m, 0, 1.25f, -0.75f, c);  /* a period on: the bottom-left texel again */
  CHECK_NEAR(c[0], 0.5, 1e-6);
  imagemap_bilinear(m, 0, 0.0f, 0.75f, c);    /* the left edge wraps to the right texel */
  CHECK_NEAR(c[0], 0.5, 1e-6);
  imagemap_free(m);
}

TEST(footprint_picks_the_level) {
  ImageMap *m = checker(16, 16);
  float c[4];
  /* one texel a pixel: level 0, a texel's own value at its centre */
  imagemap_sample(m, 0.5f / 16, 1 - 0.5f / 16, 1.0f / 16, 0, 0, 1.0f / 16, c);
  CHECK_NEAR(c[0], 0, 1e-6);
  /* two texels a pixel: level 1, the checker's mean */
  imagemap_sample(m, 0.5f / 16, 1 - 0.5f / 16, 2.0f / 16, 0, 0, 2.0f / 16, c);
  CHECK_NEAR(c[0], 0.5, 1e-6);
  /* 1.41 texels: half way between levels 0 and 1 */
  float r = sqrtf(2.0f) / 16;
  imagemap_sample(m, 0.5f / 16, 1 - 0.5f / 16, r, 0, 0, r, c);
  CHECK_NEAR(c[0], 0.25, 1e-4);
  /* the longer of the two steps sets it */
  imagemap_sample(m, 0.5f / 16, 1 - 0.5f / 16, 1.0f / 16, 0, 0, 4.0f / 16, c);
  CHECK_NEAR(c[0], 0.5, 1e-6);
  imagemap_free(m);
}

/* Render scene text at its own size into a float image. */
static Image *render_text(const char *text) {
  Scene s;
  Arena ast;
  Image *img = NULL;
  if (scene_from_text(&s, &ast, text)) {
    RenderOptions o = {.threads = 2};
    if (render_scene(&s, &o, &img, NULL) != 0) img = NULL;
  }
  scene_free(&s);
  arena_free(&ast);
  return img;
}

/* An image of one colour written as a PNG into build/, its path into path. */
static int write_flat(const char *path, int channels, const float *value) {
  Image *img = image_create(4, 4, channels);
  for (int i = 0; i < 16; i++)
    for (int c = 0; c < channels; c++) img->data[i * channels + c] = value[c];
  char err[256];
  int ok = image_write(path, img, err, sizeof err);
  if (!ok) fprintf(stderr, "%s\n", err);
  image_destroy(img);
  return ok;
}

TEST(srgb_and_alpha_on_a_plane) {
  /* a texel of code 128 on an unlit plane seen straight on is code 128 */
  float grey[3] = {image_srgb8_to_linear(128), image_srgb8_to_linear(128), image_srgb8_to_linear(128)};
  float half_red[4] = {1, 0, 0, 0.5f};
  CHECK(write_flat("build/test_imagemap_grey.png", 3, grey));
  CHECK(write_flat("build/test_imagemap_alpha.png", 4, half_red));
#define PLANE_SCENE "include \"shapes.npr\";\n" \
                    "output { size [32, 32]; background #000000; }\n" \
                    "camera { position [0, 0, 10]; look_at [0, 0, 0]; up [0, 1, 0]; ortho 2; }\n" \
                    "style s { base %s; texture \"%s\"; shade flat { lit false; } }\n" \
                    "object { geometry plane(4); style s; }\n"
  char text[1024];
  snprintf(text, sizeof text, PLANE_SCENE, "#ff0000", "build/test_imagemap_grey.png");
  Image *a = render_text(text);
  snprintf(text, sizeof text, PLANE_SCENE, "#0000ff", "build/test_imagemap_alpha.png");
  Image *b = render_text(text);
  CHECK(a && b);
  if (a) {
    CHECK_EQ_INT(image_linear_to_srgb8(a->data[(16 * 32 + 16) * a->channels]), 128);
    image_destroy(a);
  }
  if (b) {   /* half red over a blue base: (0.5, 0, 0.5) in linear light */
    const float *p = &b->data[(16 * 32 + 16) * b->channels];
    CHECK_NEAR(p[0], 0.5, 2e-3);
    CHECK_NEAR(p[1], 0, 1e-6);
    CHECK_NEAR(p[2], 0.5, 2e-3);
    image_destroy(b);
  }
}

int main(void) {
  RUN(pyramid_levels_and_linear_means);
  RUN(bilinear_centres_and_between);
  RUN(footprint_picks_the_level);
  RUN(srgb_and_alpha_on_a_plane);
  return unit_done();
}
