/*
** Bezier patch evaluation: values and derivatives against hand-computed
** ones, order independence (the lecture's de Casteljau in u then v equals v
** then u), normal orientation, and finite normals on the teapot's collapsed
** lid and bottom patches.
*/
#include "../../src/geom/patch.h"
#include "teapot_npr.h"
#include "unit.h"

#define CHECK_VEC(a, b, eps) \
  do { Vec3 a__ = (a), b__ = (b); CHECK_NEAR(a__.x, b__.x, eps); CHECK_NEAR(a__.y, b__.y, eps); \
       CHECK_NEAR(a__.z, b__.z, eps); } while (0)

/* A small deterministic generator for test patches. */
static unsigned rng_state = 12345u;
static double rnd(void) {
  rng_state = rng_state * 1664525u + 1013904223u;
  return (rng_state >> 8) / 16777216.0 * 2.0 - 1.0;
}

static ScenePatch random_patch(void) {
  ScenePatch p = {0};
  for (int k = 0; k < 16; k++) p.cp[k] = v3(rnd(), rnd(), rnd());
  return p;
}

/* cp(i, j) = (i/3, j/3, f(i, j)). */
static ScenePatch graph_patch(double (*f)(int, int)) {
  ScenePatch p = {0};
  for (int j = 0; j < 4; j++)
    for (int i = 0; i < 4; i++) p.cp[4 * j + i] = v3(i / 3.0, j / 3.0, f(i, j));
  return p;
}

static double f_product(int i, int j) { return (i / 3.0) * (j / 3.0); }
static double f_square(int i, int j) { (void)j; return (i / 3.0) * (i / 3.0); }
static double f_bump(int i, int j) { return i == 1 && j == 1 ? 1.0 : 0.0; }

/* The lecture's two-step construction: de Casteljau on each row (u), then
** on the resulting column (v) — or columns first when v_first. */
static Vec3 casteljau(const Vec3 c[4], double t) {
  Vec3 a = v3_lerp(c[0], c[1], t), b = v3_lerp(c[1], c[2], t), d = v3_lerp(c[2], c[3], t);
  Vec3 e = v3_lerp(a, b, t), f = v3_lerp(b, d, t);
  return v3_lerp(e, f, t);
}

static Vec3 two_step(const ScenePatch *p, double u, double v, int v_first) {
  Vec3 q[4], c[4];
  for (int a = 0; a < 4; a++) {
    for (int b = 0; b < 4; b++) c[b] = v_first ? p->cp[4 * b + a] : p->cp[4 * a + b];
    q[a] = casteljau(c, v_first ? v : u);
  }
  return casteljau(q, v_first ? u : v);
}

TEST(linear_precision) {
  /* x and y are linear in i, j, so P = (u, v, ...) exactly; z = ij/9 gives uv */
  ScenePatch p = graph_patch(f_product);
  Vec3 du, dv;
  Vec3 x = patch_eval(&p, 0.3, 0.7, &du, &dv);
  CHECK_VEC(x, v3(0.3, 0.7, 0.21), 1e-14);
  CHECK_VEC(du, v3(1, 0, 0.7), 1e-14);
  CHECK_VEC(dv, v3(0, 1, 0.3), 1e-14);
}

TEST(quadratic_values) {
  /* sum_i B_i(u) (i/3)^2 = u^2 + u(1 - u)/3: 1/3 at u = 1/2 */
  ScenePatch p = graph_patch(f_square);
  Vec3 du;
  CHECK_NEAR(patch_eval(&p, 0.5, 0.2, &du, NULL).z, 1.0 / 3.0, 1e-14);
  CHECK_NEAR(du.z, 1.0, 1e-14);   /* 2u + (1 - 2u)/3 at 1/2 */
  CHECK_NEAR(patch_eval(&p, 0.25, 0.9, &du, NULL).z, 0.0625 + 0.0625, 1e-14);
  CHECK_NEAR(du.z, 0.5 + 0.5 / 3.0, 1e-14);
}

TEST(single_control_point) {
  /* only cp(1, 1) = 1: z = B1(u) B1(v), B1(t) = 3t(1-t)^2 */
  ScenePatch p = graph_patch(f_bump);
  Vec3 du, dv;
  CHECK_NEAR(patch_eval(&p, 0.5, 0.5, &du, &dv).z, 0.140625, 1e-15);
  CHECK_NEAR(du.z, -0.28125, 1e-15);   /* B1'(1/2) = -3/4, times B1(1/2) = 3/8 */
  CHECK_NEAR(dv.z, -0.28125, 1e-15);
  CHECK_NEAR(patch_eval(&p, 0.25, 0.5, &du, &dv).z, 0.158203125, 1e-15);
  CHECK_NEAR(du.z, 0.5625 * 0.375, 1e-15);   /* B1'(1/4) = 3(9/16) - 6(3/16) */
}

TEST(corners_interpolate) {
  ScenePatch p = random_patch();
  CHECK_VEC(patch_eval(&p, 0, 0, NULL, NULL), p.cp[0], 1e-15);
  CHECK_VEC(patch_eval(&p, 1, 0, NULL, NULL), p.cp[3], 1e-15);
  CHECK_VEC(patch_eval(&p, 0, 1, NULL, NULL), p.cp[12], 1e-15);
  CHECK_VEC(patch_eval(&p, 1, 1, NULL, NULL), p.cp[15], 1e-15);
  /* corner tangents: 3 (cp1 - cp0) along u, 3 (cp4 - cp0) along v */
  Vec3 du, dv;
  patch_eval(&p, 0, 0, &du, &dv);
  CHECK_VEC(du, v3_mul(v3_sub(p.cp[1], p.cp[0]), 3), 1e-14);
  CHECK_VEC(dv, v3_mul(v3_sub(p.cp[4], p.cp[0]), 3), 1e-14);
}

TEST(order_independence) {
  for (int n = 0; n < 20; n++) {
    ScenePatch p = random_patch();
    double u = (rnd() + 1) / 2, v = (rnd() + 1) / 2;
    Vec3 a = two_step(&p, u, v, 0), b = two_step(&p, u, v, 1);
    CHECK_VEC(a, b, 1e-14);
    CHECK_VEC(patch_eval(&p, u, v, NULL, NULL), a, 1e-14);
  }
}

TEST(derivatives_match_differences) {
  for (int n = 0; n < 10; n++) {
    ScenePatch p = random_patch();
    double u = 0.1 + 0.8 * (rnd() + 1) / 2, v = 0.1 + 0.8 * (rnd() + 1) / 2, h = 1e-6;
    Vec3 du, dv;
    patch_eval(&p, u, v, &du, &dv);
    Vec3 fu = v3_mul(v3_sub(patch_eval(&p, u + h, v, NULL, NULL), patch_eval(&p, u - h, v, NULL, NULL)), 0.5 / h);
    Vec3 fv = v3_mul(v3_sub(patch_eval(&p, u, v + h, NULL, NULL), patch_eval(&p, u, v - h, NULL, NULL)), 0.5 / h);
    CHECK_VEC(du, fu, 1e-7);
    CHECK_VEC(dv, fv, 1e-7);
  }
}

TEST(eval_normal_agrees) {
  /* the one-pass point and normal equal the separate calls, and so does
  ** the tessellator's pass from rows at u and weights at v made once */
  for (int n = 0; n < 10; n++) {
    ScenePatch p = random_patch();
    double u = (rnd() + 1) / 2, v = (rnd() + 1) / 2;
    Vec3 nrm, x = patch_eval_normal(&p, u, v, &nrm);
    CHECK_VEC(x, patch_eval(&p, u, v, NULL, NULL), 0);
    CHECK_VEC(nrm, patch_normal(&p, u, v), 0);
    PatchRows rows;
    PatchWeights w;
    patch_rows(&p, u, &rows);
    patch_weights(&p, v, &w);
    Vec3 nr, xr = patch_eval_normal_rows(&p, &rows, &w, u, v, &nr);
    CHECK_VEC(xr, x, 0);
    CHECK_VEC(nr, nrm, 0);
  }
}

TEST(flat_patch_faces_plus_z) {
  ScenePatch p = graph_patch(f_bump);
  for (int k = 0; k < 16; k++) p.cp[k].z = 0;
  CHECK_VEC(patch_normal(&p, 0.3, 0.6), v3(0, 0, 1), 1e-15);
  /* swapping u and v (transposing the net) turns it over */
  ScenePatch t = p;
  for (int j = 0; j < 4; j++)
    for (int i = 0; i < 4; i++) t.cp[4 * j + i] = p.cp[4 * i + j];
  CHECK_VEC(patch_normal(&t, 0.3, 0.6), v3(0, 0, -1), 1e-15);
}

TEST(bilinear_lecture_formula) {
  Vec3 p0 = v3(0, 0, 0), p1 = v3(2, 0, 1), p2 = v3(0, 3, -1), p3 = v3(2, 3, 4);
  ScenePatch b;
  patch_bilinear(&b, p0, p1, p2, p3);
  CHECK(b.bilinear);
  double u = 0.3, v = 0.8;
  /* x(u, v) = (p0 - p1 - p2 + p3) uv + (p1 - p0) u + (p2 - p0) v + p0 */
  Vec3 twist = v3_add(v3_sub(v3_sub(p0, p1), p2), p3);
  Vec3 want = v3_add(v3_add(v3_mul(twist, u * v), v3_mul(v3_sub(p1, p0), u)),
                     v3_add(v3_mul(v3_sub(p2, p0), v), p0));
  Vec3 du, dv;
  CHECK_VEC(patch_eval(&b, u, v, &du, &dv), want, 1e-14);
  CHECK_VEC(du, v3_add(v3_mul(twist, v), v3_sub(p1, p0)), 1e-14);
  CHECK_VEC(dv, v3_add(v3_mul(twist, u), v3_sub(p2, p0)), 1e-14);
  /* Lerp(v, Lerp(u, p0, p1), Lerp(u, p2, p3)) = Lerp(u, Lerp(v, p0, p2), Lerp(v, p1, p3)) */
  CHECK_VEC(v3_lerp(v3_lerp(p0, p1, u), v3_lerp(p2, p3, u), v),
            v3_lerp(v3_lerp(p0, p2, v), v3_lerp(p1, p3, v), u), 1e-14);
  /* the elevated bicubic is the same surface */
  ScenePatch c;
  patch_elevate_bilinear(&b, &c);
  CHECK(!c.bilinear);
  CHECK_VEC(patch_eval(&c, u, v, NULL, NULL), want, 1e-14);
  CHECK_VEC(patch_normal(&c, u, v), patch_normal(&b, u, v), 1e-12);
  /* p0 p1 along +x and p2 above along +y: a unit square faces +z */
  patch_bilinear(&b, v3(0, 0, 0), v3(1, 0, 0), v3(0, 1, 0), v3(1, 1, 0));
  CHECK_VEC(patch_normal(&b, 0.5, 0.5), v3(0, 0, 1), 1e-15);
}

/* Whether n is a finite unit vector. */
static int unit_vector(Vec3 n) {
  double l = v3_len(n);
  return isfinite(n.x) && isfinite(n.y) && isfinite(n.z) && fabs(l - 1) < 1e-9;
}

TEST(degenerate_normals_finite) {
  /* a patch shrunk to one point, and one squashed onto a line */
  ScenePatch p = {0};
  for (int k = 0; k < 16; k++) p.cp[k] = v3(1, 2, 3);
  CHECK(unit_vector(patch_normal(&p, 0, 0)));
  CHECK(unit_vector(patch_normal(&p, 0.5, 0.5)));
  for (int k = 0; k < 16; k++) p.cp[k] = v3(k, 0, 0);
  CHECK(unit_vector(patch_normal(&p, 0.2, 0.7)));
  /* a cone: the v = 0 row collapsed to an apex above a unit circle-ish
  ** square; the apex normal is the limit from inside (pointing up-out) */
  ScenePatch c = graph_patch(f_product);
  for (int i = 0; i < 4; i++) c.cp[i] = v3(0.5, 0, 1);
  Vec3 n0 = patch_normal(&c, 0.4, 0), n1 = patch_normal(&c, 0.4, 1e-5);
  CHECK(unit_vector(n0));
  CHECK(v3_dot(n0, n1) > 0.9999);
  /* the u = 1 column collapsed instead (dP/dv vanishes there) */
  ScenePatch d = graph_patch(f_product);
  for (int j = 0; j < 4; j++) d.cp[4 * j + 3] = v3(1, 0.5, 0);
  n0 = patch_normal(&d, 1, 0.3);
  n1 = patch_normal(&d, 1 - 1e-5, 0.3);
  CHECK(unit_vector(n0));
  CHECK(v3_dot(n0, n1) > 0.9999);
}

TEST(teapot_normals) {
  SceneGeometry g;
  if (!teapot_load(&g)) { CHECK(!"cannot read " TEAPOT_NPR); return; }
  int bad = 0;
  for (int p = 0; p < g.npatches; p++)
    for (int j = 0; j <= 16; j++)
      for (int i = 0; i <= 16; i++)
        if (!unit_vector(patch_normal(&g.patches[p], i / 16.0, j / 16.0))) bad++;
  CHECK_EQ_INT(bad, 0);
  /* the collapsed rows: the lid's apex faces up, the bottom's centre down,
  ** whatever u, and the limit agrees with the normal just inside */
  for (int p = 20; p < 24; p++)
    for (int i = 0; i <= 8; i++) {
      CHECK_VEC(patch_normal(&g.patches[p], i / 8.0, 0), v3(0, 0, 1), 1e-9);
      CHECK(v3_dot(patch_normal(&g.patches[p], i / 8.0, 1e-4), v3(0, 0, 1)) > 0.999);
    }
  for (int p = 28; p < 32; p++)
    for (int i = 0; i <= 8; i++) CHECK_VEC(patch_normal(&g.patches[p], i / 8.0, 0), v3(0, 0, -1), 1e-9);
  /* the body (patches 4-11) faces away from the axis */
  for (int p = 4; p < 12; p++)
    for (int k = 1; k < 8; k++) {
      double u = k / 8.0, v = (8 - k) / 8.0;
      Vec3 x = patch_eval(&g.patches[p], u, v, NULL, NULL), n = patch_normal(&g.patches[p], u, v);
      CHECK(n.x * x.x + n.y * x.y > 0);
    }
  /* it stands on z = 0 with its apex at 3.15 */
  CHECK_NEAR(patch_eval(&g.patches[28], 0.5, 0, NULL, NULL).z, 0, 0);
  CHECK_NEAR(patch_eval(&g.patches[20], 0.5, 0, NULL, NULL).z, 3.15, 1e-12);
  free(g.patches);
}

int main(void) {
  RUN(linear_precision);
  RUN(quadratic_values);
  RUN(single_control_point);
  RUN(corners_interpolate);
  RUN(order_independence);
  RUN(derivatives_match_differences);
  RUN(eval_normal_agrees);
  RUN(flat_patch_faces_plus_z);
  RUN(bilinear_lecture_formula);
  RUN(degenerate_normals_finite);
  RUN(teapot_normals);
  return unit_done();
}
