/*
** Bokashi (001 section 2.2.3): bokashi 2 on a sphere centred at c is
** Phong's and Gouraud's diffuse shading of that sphere, it keeps a surface
** point's colour under a camera orbit, and its lights add before the
** clamp; bokashi 1's gradation point moves toward the light as the view
** crosses to the far side of the object (the sign of the view modifier),
** and its rate follows the centre's depth; the same bytes at 1, 2, 8
** threads.
*/
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../../src/render/render.h"
#include "../../src/render/shade.h"
#include "render_scenes.h"
#include "unit.h"

/* A sphere of radius 1 at c, style 0 bokashi sphere (lit white, unlit
** black), one sun along dir; 160 x 160, one sample a pixel. */
static void sphere_scene(Scene *s, Vec3 c, Vec3 dir) {
  memset(s, 0, sizeof *s);
  arena_init(&s->arena);
  s->output.width = s->output.height = 160;
  s->output.samples = 1;
  s->output.background = (Color){0, 0, 1, 1};
  s->nstyles = 1;
  s->styles = arena_alloc(&s->arena, sizeof *s->styles);
  SceneStyle *st = &s->styles[0];
  *st = scene_default_style();
  st->lines.present = 0;
  st->shade.kind = SHADE_BOKASHI;
  st->shade.bokashi.lit = (Color){1, 1, 1, 1};
  st->shade.bokashi.unlit = (Color){0, 0, 0, 1};
  st->shade.bokashi.has_lit = st->shade.bokashi.has_unlit = 1;
  s->camera = (SceneCamera){.present = 1, .kind = CAMERA_PERSPECTIVE, .position = v3_add(c, v3(0, -8, 1)),
                            .look_at = c, .up = v3(0, 0, 1), .fov = 20};
  s->nlights = 1;
  s->lights = arena_alloc(&s->arena, 2 * sizeof *s->lights);
  s->lights[0] = (SceneLight){.kind = LIGHT_DIRECTIONAL, .direction = dir, .color = {1, 1, 1, 1}, .strength = 1};
  s->nobjects = 1;
  s->objects = arena_alloc(&s->arena, sizeof *s->objects);
  s->objects[0].geometry = sphere_geometry(&s->arena, c, 1, 96, 48);
  s->objects[0].transform = m4_identity();
  s->objects[0].centre = c;
  s->objects[0].has_centre = 1;
}

static Image *render_n(const Scene *s, int threads, GBuffer **g) {
  RenderOptions o = {.threads = threads};
  Image *img = NULL;
  CHECK_EQ_INT(render_scene(s, &o, &img, g), 0);
  return img;
}

/* n.v at G-buffer sample i: away from the outline where it is large. */
static double facing(const GBuffer *g, int i) {
  Vec3 p = v3(g->position[i][0], g->position[i][1], g->position[i][2]);
  Vec3 v = camera_view_dir(&g->camera, p);
  return v.x * g->normal[i][0] + v.y * g->normal[i][1] + v.z * g->normal[i][2];
}

/* The largest difference, over the samples facing the viewer by more than
** 0.2, between the grey of a and the red of b. */
static double max_difference(const Image *a, const Image *b, const GBuffer *g, int *compared) {
  double worst = 0;
  *compared = 0;
  for (int i = 0; i < a->width * a->height; i++) {
    if (g->object[i] != 0 || facing(g, i) < 0.2) continue;
    (*compared)++;
    worst = fmax(worst, fabs(a->data[i * 3] - b->data[i * 3]));
  }
  return worst;
}

/* Bokashi 2 on a sphere centred at c equals the sphere's diffuse shading
** (white, no ambient, no specular) per pixel (Phong) and per vertex
** (Gouraud), within 1/255. */
TEST(sphere_equals_diffuse) {
  Scene s;
  Vec3 c = v3(0.3, 0.2, -0.4);
  sphere_scene(&s, c, v3(-0.6, 0.7, -0.4));
  for (int per_pixel = 1; per_pixel >= 0; per_pixel--) {
    s.styles[0].shade.kind = SHADE_BOKASHI;
    s.styles[0].shade.bokashi.per_pixel = per_pixel;
    GBuffer *g;
    Image *bk = render_n(&s, 2, &g);
    s.styles[0].shade.kind = per_pixel ? SHADE_PHONG : SHADE_GOURAUD;
    s.styles[0].base = (Color){1, 1, 1, 1};
    s.styles[0].shade.toon.ambient = 0;
    s.styles[0].shade.toon.specular = 0;
    Image *ph = render_n(&s, 2, NULL);
    int n;
    double d = max_difference(bk, ph, g, &n);
    CHECK(n > 4000);
    CHECK(d <= 1.0 / 255);
    if (d > 1.0 / 255) fprintf(stderr, "per_pixel %d: max difference %g\n", per_pixel, d);
    image_destroy(bk);
    image_destroy(ph);
    gbuf_destroy(g);
  }
  arena_free(&s.arena);
}

/* The bokashi 2 factor of world point p for a frame's lights (the paper's
** formula: the lights' n^.d^ s / |d|^2 summed, then clamped). */
static double factor_at(const Scene *s, Vec3 c, Vec3 p) {
  Vec3 n = v3_norm(v3_sub(p, c));
  double f = 0;
  for (int i = 0; i < s->nlights; i++) {
    const SceneLight *l = &s->lights[i];
    if (l->kind == LIGHT_DIRECTIONAL) f += v3_dot(n, v3_norm(v3_mul(l->direction, -1))) * l->strength;
    else {
      Vec3 d = v3_sub(l->position, c);
      f += v3_dot(n, v3_norm(d)) * l->strength / v3_dot(d, d);
    }
  }
  return f < 0 ? 0 : f > 1 ? 1 : f;
}

/* Worst difference between a render's samples and factor_at their points. */
static double worst_against_formula(const Scene *s, Vec3 c, int *n) {
  GBuffer *g;
  Image *img = render_n(s, 2, &g);
  double worst = 0;
  *n = 0;
  for (int i = 0; i < img->width * img->height; i++) {
    if (g->object[i] != 0) continue;
    (*n)++;
    Vec3 p = v3(g->position[i][0], g->position[i][1], g->position[i][2]);
    worst = fmax(worst, fabs(img->data[i * 3] - factor_at(s, c, p)));
  }
  image_destroy(img);
  gbuf_destroy(g);
  return worst;
}

/* A camera orbit with a fixed light: every sample's colour is the factor
** of its surface point alone, in every view. */
TEST(sphere_orbit_keeps_colour) {
  Scene s;
  Vec3 c = v3(0, 0, 0);
  sphere_scene(&s, c, v3(-1, 0.5, -0.5));
  s.lights[0] = (SceneLight){.kind = LIGHT_POINT, .position = v3(3, -2, 4), .color = {1, 1, 1, 1},
                             .strength = 25};
  for (int k = 0; k < 4; k++) {
    double a = k * M_PI / 2.5;
    s.camera.position = v3(8 * sin(a), -8 * cos(a), 2 - k);
    int n;
    double w = worst_against_formula(&s, c, &n);
    CHECK(n > 4000);
    CHECK(w <= 2.0 / 255);
    if (w > 2.0 / 255) fprintf(stderr, "view %d: worst %g\n", k, w);
  }
  arena_free(&s.arena);
}

/* Two lights add before the clamp: where one light's term is negative it
** takes from the other's (a per-light max(0, .) would not), and where the
** sum passes 1 it is clamped. */
TEST(sphere_lights_add_before_clamp) {
  Scene s;
  Vec3 c = v3(0, 0, 0);
  sphere_scene(&s, c, v3(-1, 0, 0));   /* a sun from +x, s = 1 */
  s.nlights = 2;
  s.lights[1] = (SceneLight){.kind = LIGHT_DIRECTIONAL, .direction = v3(0, 0, -1), .color = {1, 1, 1, 1},
                             .strength = 0.5};   /* and one from +z, s = 0.5 */
  int n;
  CHECK(worst_against_formula(&s, c, &n) <= 2.0 / 255);
  /* at n = (1, -1, -0.5) / 1.5: 0.667 - 0.5 * 0.333 = 0.5, not 0.667 */
  GBuffer *g;
  Image *img = render_n(&s, 2, &g);
  Vec3 want = v3_norm(v3(1, -1, -0.5));
  double best = -1, got = -1;
  int clamped = 0;
  for (int i = 0; i < img->width * img->height; i++) {
    if (g->object[i] != 0) continue;
    Vec3 p = v3_norm(v3(g->position[i][0], g->position[i][1], g->position[i][2]));
    if (v3_dot(p, want) > best) { best = v3_dot(p, want); got = img->data[i * 3]; }
    clamped += p.x + 0.5 * p.z > 1.02 && img->data[i * 3] == 1.0f;
  }
  CHECK(best > 0.999);
  CHECK_NEAR(got, 0.5, 0.01);
  CHECK(clamped > 50);
  image_destroy(img);
  gbuf_destroy(g);
  arena_free(&s.arena);
}

/* Bokashi 1 lit by a sun whose rays travel +x (the light is at -x), seen
** from a camera at angle a (degrees) around the object from the light's
** side: a = 0 beside the light, 180 behind the object. */
static void linear_scene(Scene *s, double a) {
  sphere_scene(s, v3(0, 0, 0), v3(1, 0, 0));   /* rays travel +x: the light is at -x */
  s->styles[0].shade.bokashi.sphere = 0;
  s->styles[0].shade.bokashi.strength_mod = 0;   /* g off c by the view modifier alone */
  s->styles[0].shade.bokashi.offset = 0;
  s->styles[0].shade.bokashi.view_mod = 0.6;
  s->styles[0].shade.bokashi.rate = 4;
  double r = a * M_PI / 180;
  s->camera.position = v3(-8 * cos(r), -8 * sin(r), 0);   /* a = 0: beside the light */
}

/* How far the gradation point lies from the centre toward the light, in
** pixels, and the lit share of the object's samples. */
static void linear_measure(const Scene *s, double *toward, double *lit_share) {
  RenderOptions o = {.threads = 1, .width = 160, .height = 160};
  RenderFrame f;
  CHECK(render_prepare(s, &o, &f));
  const RenderObject *ob = &f.objects[0];
  const BokashiObject *b = ob->bokashi;
  /* dir runs with the rays, away from the light */
  *toward = -((b->g[0] - ob->centre.px[0]) * b->dir[0] + (b->g[1] - ob->centre.px[1]) * b->dir[1]);
  render_frame_free(&f);
  GBuffer *g;
  Image *img = render_n(s, 2, &g);
  int n = 0, lit = 0;
  for (int i = 0; i < img->width * img->height; i++) {
    if (g->object[i] != 0) continue;
    n++;
    lit += img->data[i * 3] == 1.0f;
  }
  *lit_share = n ? (double)lit / n : 0;
  image_destroy(img);
  gbuf_destroy(g);
}

/* The sign of m: with the viewer on the light's side (v.l > 0) the point
** moves away from the light and more of the object is lit; as the view
** crosses to the far side (the object between the viewer and the light,
** v.l < 0) it moves toward the light and less is lit. */
TEST(linear_view_modifier_sign) {
  Scene s;
  double near_side, far_side, lit_near, lit_far;
  linear_scene(&s, 60);    /* v.l = cos 60 > 0 */
  linear_measure(&s, &near_side, &lit_near);
  arena_free(&s.arena);
  linear_scene(&s, 120);   /* v.l = cos 120 < 0 */
  linear_measure(&s, &far_side, &lit_far);
  arena_free(&s.arena);
  CHECK(near_side < -2);
  CHECK(far_side > 2);
  CHECK(lit_near > lit_far + 0.1);
  /* m in scene units: at v.l = +-0.5, 0.3 units at depth 8 */
  double wpp = 8 * 2 * tan(10 * M_PI / 180) / 160;
  CHECK_NEAR(near_side, -0.3 / wpp, 0.5);
  CHECK_NEAR(far_side, 0.3 / wpp, 0.5);
}

/* Rate and view modifier scale with the centre's depth (3.3.3): twice as
** far, the rate a pixel doubles and the modifier's pixels halve. */
TEST(linear_depth_scaling) {
  Scene s;
  linear_scene(&s, 60);
  RenderOptions o = {.threads = 1, .width = 160, .height = 160};
  float rate[2], shift[2];
  for (int k = 0; k < 2; k++) {
    s.camera.position = v3_mul(v3(-cos(M_PI / 3), -sin(M_PI / 3), 0), 8.0 * (k + 1));
    RenderFrame f;
    CHECK(render_prepare(&s, &o, &f));
    const RenderObject *ob = &f.objects[0];
    rate[k] = ob->bokashi->rate;
    shift[k] = hypotf(ob->bokashi->g[0] - ob->centre.px[0], ob->bokashi->g[1] - ob->centre.px[1]);
    render_frame_free(&f);
  }
  CHECK_NEAR(rate[1] / rate[0], 2, 1e-4);
  CHECK_NEAR(shift[1] / shift[0], 0.5, 1e-3);
  arena_free(&s.arena);
}

/* Both bokashi, with noise, at samples 2: the same bytes at 1, 2 and 8 threads. */
TEST(bokashi_deterministic_threads) {
  Scene s;
  sphere_scene(&s, v3(0, 0, 0), v3(-1, 0.5, -0.5));
  s.output.samples = 2;
  s.styles[0].noise = (SceneNoise){.present = 1, .amount = 0.1, .scale = 0.2, .seed = 3, .octaves = 4};
  for (int linear = 0; linear < 2; linear++) {
    s.styles[0].shade.bokashi.sphere = !linear;
    Image *a = render_n(&s, 1, NULL), *b = render_n(&s, 2, NULL), *c = render_n(&s, 8, NULL);
    size_t n = (size_t)a->width * a->height * a->channels * sizeof *a->data;
    CHECK(memcmp(a->data, b->data, n) == 0);
    CHECK(memcmp(a->data, c->data, n) == 0);
    image_destroy(a);
    image_destroy(b);
    image_destroy(c);
  }
  arena_free(&s.arena);
}

int main(void) {
  RUN(sphere_equals_diffuse);
  RUN(sphere_orbit_keeps_colour);
  RUN(sphere_lights_add_before_clamp);
  RUN(linear_view_modifier_sign);
  RUN(linear_depth_scaling);
  RUN(bokashi_deterministic_threads);
  return unit_done();
}
