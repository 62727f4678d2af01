/*
** Toon shading facts (004; 002 section 2): T_n gives n + 1 levels, the
** bands apply to diffuse and specular separately, ramps replace the
** bands, and the n.v silhouette takes exactly the samples whose n.v is
** below the cutoff.
*/
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../../src/base/rng.h"
#include "../../src/render/render.h"
#include "../../src/render/shade.h"
#include "render_scenes.h"
#include "unit.h"

/* ---- the step function --------------------------------------------------------- */

/* Distinct values of T_n(x, t) over a fine sweep of x in [-0.5, 1.5]. */
static int levels(int n, float t, float out[16]) {
  int k = 0;
  for (int i = 0; i <= 20000; i++) {
    float v = shade_step(-0.5f + 2.0f * i / 20000, t, n);
    int seen = 0;
    for (int j = 0; j < k; j++) seen |= out[j] == v;
    if (!seen && k < 16) out[k++] = v;
  }
  return k;
}

TEST(step_levels) {
  float v[16];
  CHECK_EQ_INT(levels(2, 0.5f, v), 3);   /* n = 2: three colours */
  CHECK(v[0] == 0.0f && v[1] == 0.5f && v[2] == 1.0f);
  CHECK_EQ_INT(levels(1, 0.5f, v), 2);
  CHECK_EQ_INT(levels(4, 0.3f, v), 5);
  CHECK_EQ_INT(levels(7, 0.9f, v), 8);
}

TEST(step_threshold) {
  /* T_2(x, t) = (floor(2x) + T(frac(2x), t)) / 2 */
  CHECK(shade_step(0.20f, 0.5f, 2) == 0.0f);    /* 2x = 0.4: frac below t */
  CHECK(shade_step(0.30f, 0.5f, 2) == 0.5f);    /* 2x = 0.6: frac reaches t */
  CHECK(shade_step(0.30f, 0.7f, 2) == 0.0f);    /* a higher threshold keeps it dark */
  CHECK(shade_step(0.60f, 0.5f, 2) == 0.5f);    /* 2x = 1.2: one whole step */
  CHECK(shade_step(0.80f, 0.5f, 2) == 1.0f);
  CHECK(shade_step(1.00f, 0.5f, 2) == 1.0f);
  CHECK(shade_step(7.00f, 0.5f, 2) == 1.0f);    /* clamped */
  CHECK(shade_step(-1.0f, 0.0f, 2) == 0.5f);    /* t = 0: T(0, 0) = 1 */
  CHECK(shade_step(0.49f, 0.5f, 1) == 0.0f);    /* n = 1: the plain step T(x, t) */
  CHECK(shade_step(0.50f, 0.5f, 1) == 1.0f);
}

/* ---- rendered ------------------------------------------------------------------- */

/* One sphere, toon, lit by a sun from the viewer's side; samples 1 so
** pixels are samples. */
static void toon_scene(Scene *s) {
  memset(s, 0, sizeof *s);
  arena_init(&s->arena);
  s->output.width = s->output.height = 160;
  s->output.samples = 1;
  s->output.background = (Color){1, 1, 1, 1};
  s->nstyles = 1;
  s->styles = arena_alloc(&s->arena, sizeof *s->styles);
  s->styles[0].base = (Color){0.2f, 0.4f, 0.8f, 1};
  s->styles[0].shade.kind = SHADE_TOON;
  s->styles[0].shade.toon = (ShadeToon){.bands = 3, .threshold = 0.5, .shininess = 24, .specular_bands = 2,
                                        .specular_threshold = 0.5, .ambient = 0.1,
                                        .edge_color = {0, 0, 0, 1}};
  s->camera = (SceneCamera){.present = 1, .kind = CAMERA_PERSPECTIVE, .position = v3(0, -8, 0),
                            .look_at = v3(0, 0, 0), .up = v3(0, 0, 1), .fov = 20};
  s->nlights = 1;
  s->lights = arena_alloc(&s->arena, sizeof *s->lights);
  s->lights[0] = (SceneLight){.kind = LIGHT_DIRECTIONAL, .direction = v3(-0.3, 1, -0.4),
                              .color = {1, 1, 1, 1}, .strength = 1};
  s->nobjects = 1;
  s->objects = arena_alloc(&s->arena, sizeof *s->objects);
  s->objects[0].geometry = sphere_geometry(&s->arena, v3(0, 0, 0), 1, 64, 32);
  s->objects[0].transform = m4_identity();
  s->objects[0].style = 0;
}

/* The distinct colours of the object's samples (up to max) into out. */
static int object_colours(const Image *img, const GBuffer *g, float out[][3], int max) {
  int k = 0;
  for (int i = 0; i < img->width * img->height; i++) {
    if (g->object[i] < 0) continue;
    const float *p = &img->data[i * img->channels];
    int seen = 0;
    for (int j = 0; j < k && !seen; j++) seen = !memcmp(out[j], p, sizeof out[j]);
    if (!seen && k < max) memcpy(out[k++], p, sizeof out[0]);
    if (!seen && k == max) return max + 1;
  }
  return k;
}

static void render(const Scene *s, Image **img, GBuffer **g) {
  RenderOptions o = {.threads = 2};
  CHECK_EQ_INT(render_scene(s, &o, img, g), 0);
}

/* bands 3 without specular: exactly three colours on the sphere, the
** ambient-only one among them. */
TEST(three_bands_three_colours) {
  Scene s;
  toon_scene(&s);
  Image *img;
  GBuffer *g;
  render(&s, &img, &g);
  float c[8][3];
  CHECK_EQ_INT(object_colours(img, g, c, 8), 3);
  int has_ambient = 0;
  for (int k = 0; k < 3; k++) has_ambient |= fabsf(c[k][2] - 0.8f * 0.1f) < 1e-6f;
  CHECK(has_ambient);
  image_destroy(img);
  gbuf_destroy(g);
  arena_free(&s.arena);
}

/* A banded specular adds its own step: one more colour, the top band
** plus the specular strength. */
TEST(specular_banded_separately) {
  Scene s;
  toon_scene(&s);
  s.styles[0].shade.toon.specular = 0.5;
  Image *img;
  GBuffer *g;
  render(&s, &img, &g);
  float c[8][3];
  CHECK_EQ_INT(object_colours(img, g, c, 8), 4);
  int highlight = 0;
  for (int k = 0; k < 4; k++)   /* top band 0.1 + 1 of base, plus 0.5 white */
    highlight |= fabsf(c[k][0] - (0.2f * 1.1f + 0.5f)) < 1e-5f && fabsf(c[k][2] - (0.8f * 1.1f + 0.5f)) < 1e-5f;
  CHECK(highlight);
  image_destroy(img);
  gbuf_destroy(g);
  arena_free(&s.arena);
}

/* A ramp replaces the bands: every sample takes one of its colours, and
** with a light from the viewer's side all of them show. */
TEST(ramp_colours) {
  Scene s;
  toon_scene(&s);
  Color ramp[4] = {{0.1f, 0, 0, 1}, {0.3f, 0.1f, 0, 1}, {0.6f, 0.3f, 0.1f, 1}, {0.9f, 0.8f, 0.5f, 1}};
  s.styles[0].shade.toon.ramp = ramp;
  s.styles[0].shade.toon.nramp = 4;
  s.lights[0].direction = v3(0, 1, 0);
  Image *img;
  GBuffer *g;
  render(&s, &img, &g);
  float c[8][3];
  int n = object_colours(img, g, c, 8);
  CHECK_EQ_INT(n, 4);
  for (int k = 0; k < n && k < 8; k++) {
    int in_ramp = 0;
    for (int r = 0; r < 4; r++) in_ramp |= c[k][0] == ramp[r].r && c[k][1] == ramp[r].g && c[k][2] == ramp[r].b;
    CHECK(in_ramp);
  }
  image_destroy(img);
  gbuf_destroy(g);
  arena_free(&s.arena);
}

/* The silhouette: samples with n.v below the cutoff take the edge colour,
** the others never do; the band is a ring around the outline. */
TEST(edge_by_n_dot_v) {
  Scene s;
  toon_scene(&s);
  s.styles[0].shade.toon.edge = 0.3;
  s.styles[0].shade.toon.edge_color = (Color){1, 0, 1, 1};   /* no band gives magenta */
  Image *img;
  GBuffer *g;
  render(&s, &img, &g);
  int edge = 0, wrong = 0;
  for (int i = 0; i < img->width * img->height; i++) {
    if (g->object[i] < 0) continue;
    Vec3 p = v3(g->position[i][0], g->position[i][1], g->position[i][2]);
    Vec3 v = camera_view_dir(&g->camera, p);
    double nv = v.x * g->normal[i][0] + v.y * g->normal[i][1] + v.z * g->normal[i][2];
    const float *c = &img->data[i * img->channels];
    int is_edge = c[0] == 1 && c[1] == 0 && c[2] == 1;
    edge += is_edge;
    if (nv < 0.299 && !is_edge) wrong++;
    if (nv > 0.301 && is_edge) wrong++;
  }
  CHECK_EQ_INT(wrong, 0);
  /* n.v < 0.3 is the outer ring r > sqrt(1 - 0.09) of the disc: ~9% of it */
  int covered = 0;
  for (int i = 0; i < img->width * img->height; i++) covered += g->object[i] >= 0;
  CHECK_NEAR((double)edge / covered, 0.09, 0.03);
  image_destroy(img);
  gbuf_destroy(g);
  arena_free(&s.arena);
}

/* Two lights each add their own banded term. */
TEST(lights_add) {
  Scene s;
  toon_scene(&s);
  Image *one, *two;
  GBuffer *g1, *g2;
  render(&s, &one, &g1);
  SceneLight *l = arena_alloc(&s.arena, 2 * sizeof *l);
  l[0] = s.lights[0];
  l[1] = l[0];
  l[1].direction = v3(0.3, 1, 0.4);
  l[1].color = (Color){0.5f, 0.5f, 0.5f, 1};
  s.lights = l;
  s.nlights = 2;
  render(&s, &two, &g2);
  CHECK_EQ_INT(one->channels, 3);   /* opaque background: RGB */
  int brighter = 0, darker = 0;
  for (int i = 0; i < one->width * one->height; i++) {
    if (g1->object[i] < 0) continue;
    brighter += two->data[i * 3 + 2] > one->data[i * 3 + 2];
    darker += two->data[i * 3 + 2] < one->data[i * 3 + 2];
  }
  CHECK(brighter > 100);
  CHECK_EQ_INT(darker, 0);
  image_destroy(one);
  image_destroy(two);
  gbuf_destroy(g1);
  gbuf_destroy(g2);
  arena_free(&s.arena);
}

/* The bands loop shades a span in blocks, several samples side by side:
** a span longer than a block, under a point light (falling off with
** distance) and a sun, with specular highlights and the silhouette edge,
** gives each sample the colour it gets when shaded alone. */
TEST(span_equals_samples_alone) {
  Scene s;
  toon_scene(&s);
  s.styles[0].shade.toon.specular = 0.5;
  s.styles[0].shade.toon.edge = 0.2;
  SceneLight *l = arena_alloc(&s.arena, 2 * sizeof *l);
  l[0] = s.lights[0];
  l[1] = (SceneLight){.kind = LIGHT_POINT, .position = v3(1, -3, 2), .color = {1, 0.9f, 0.8f, 1},
                      .strength = 4, .falloff = FALLOFF_INVERSE_SQUARE};
  s.lights = l;
  s.nlights = 2;
  RenderOptions o = {.width = 16, .height = 16, .threads = 1};
  RenderFrame f;
  CHECK_EQ_INT(render_prepare(&s, &o, &f), 1);
  enum { N = 150 };   /* more than two blocks */
  float planes[11][N], bary[N][2];
  int32_t face[N];
  Rng r;
  rng_seed(&r, 7, 0);
  for (int k = 0; k < N; k++) {
    float n[3], v[3];
    for (int c = 0; c < 3; c++) {
      planes[c][k] = (float)(2 * rng_uniform(&r) - 1);        /* p */
      n[c] = (float)(2 * rng_uniform(&r) - 1);
      v[c] = (float)(2 * rng_uniform(&r) - 1) + (c == 1 ? -2.0f : 0.0f);
    }
    float ln = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    float lv = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int c = 0; c < 3; c++) {
      planes[3 + c][k] = n[c] / ln;
      planes[6 + c][k] = v[c] / lv;
    }
    planes[9][k] = planes[10][k] = 0;
    face[k] = 0;
    bary[k][0] = bary[k][1] = 0;
  }
  ShadeRow row = {.frame = &f, .face = face, .bary = (const float(*)[2])bary, .px = planes[0], .py = planes[1],
                  .pz = planes[2], .nx = planes[3], .ny = planes[4], .nz = planes[5], .vx = planes[6],
                  .vy = planes[7], .vz = planes[8], .u = planes[9], .v = planes[10]};
  float span[N][3], alone[3];
  shade_toon_span(&row, &f.objects[0], 0, N, span[0], 3);
  int same = 0, highlit = 0, edged = 0;
  for (int k = 0; k < N; k++) {
    ShadeSample one;
    shade_row_sample(&row, &f.objects[0], k, &one);
    shade_toon(&one, alone);
    same += !memcmp(alone, span[k], sizeof alone);
    highlit += span[k][0] > f.styles[0].base[0] * 2;   /* a highlight's white on top */
    edged += span[k][0] == 0 && span[k][1] == 0 && span[k][2] == 0;
  }
  CHECK_EQ_INT(same, N);
  CHECK(highlit > 0);   /* the cases the test means to cover do occur */
  CHECK(edged > 0);
  render_frame_free(&f);
  arena_free(&s.arena);
}

int main(void) {
  diag_init(DIAG_TEXT);
  RUN(step_levels);
  RUN(step_threshold);
  RUN(three_bands_three_colours);
  RUN(specular_banded_separately);
  RUN(ramp_colours);
  RUN(edge_by_n_dot_v);
  RUN(lights_add);
  RUN(span_equals_samples_alone);
  return unit_done();
}
