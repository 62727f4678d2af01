/*
** Bezier patch evaluation (see patch.h for the parameterisation): the
** tensor-product Bernstein sums for the point and its derivatives, and a
** normal that stays finite on collapsed edges.
*/
#include "patch.h"

/* Cubic Bernstein weights at t, and their first derivatives. */
static void bernstein3(double t, double b[4], double d[4]) {
  double s = 1.0 - t;
  b[0] = s * s * s;
  b[1] = 3.0 * t * s * s;
  b[2] = 3.0 * t * t * s;
  b[3] = t * t * t;
  d[0] = -3.0 * s * s;
  d[1] = 3.0 * s * s - 6.0 * t * s;
  d[2] = 6.0 * t * s - 3.0 * t * t;
  d[3] = 3.0 * t * t;
}

/* Linear weights at t, and their derivatives, padded to four. */
static void bernstein1(double t, double b[4], double d[4]) {
  b[0] = 1.0 - t; b[1] = t; b[2] = 0; b[3] = 0;
  d[0] = -1.0; d[1] = 1.0; d[2] = 0; d[3] = 0;
}

void patch_rows(const ScenePatch *p, double u, PatchRows *rows) {
  double bu[4], wu[4];
  int n = p->bilinear ? 2 : 4;
  if (p->bilinear) bernstein1(u, bu, wu);
  else bernstein3(u, bu, wu);
  rows->n = n;
  for (int j = 0; j < n; j++) {
    const Vec3 *c = &p->cp[n * j];
    Vec3 r = {0, 0, 0}, ru = {0, 0, 0};   /* row j at u, and its u-derivative */
    for (int i = 0; i < n; i++) {
      r.x += bu[i] * c[i].x; r.y += bu[i] * c[i].y; r.z += bu[i] * c[i].z;
      ru.x += wu[i] * c[i].x; ru.y += wu[i] * c[i].y; ru.z += wu[i] * c[i].z;
    }
    rows->r[j] = r;
    rows->ru[j] = ru;
  }
}

/* P, dP/du, dP/dv and d2P/dudv at v from the rows at some u; any output
** but P may be NULL. The rows combine both ways in v. */
static Vec3 eval_rows(const PatchRows *rows, double v, Vec3 *du, Vec3 *dv, Vec3 *duv) {
  double bv[4], wv[4];
  if (rows->n == 2) bernstein1(v, bv, wv);
  else bernstein3(v, bv, wv);
  Vec3 x = {0, 0, 0}, xu = {0, 0, 0}, xv = {0, 0, 0}, xuv = {0, 0, 0};
  for (int j = 0; j < rows->n; j++) {
    Vec3 r = rows->r[j], ru = rows->ru[j];
    x = v3_add(x, v3_mul(r, bv[j]));
    xu = v3_add(xu, v3_mul(ru, bv[j]));
    xv = v3_add(xv, v3_mul(r, wv[j]));
    xuv = v3_add(xuv, v3_mul(ru, wv[j]));
  }
  if (du) *du = xu;
  if (dv) *dv = xv;
  if (duv) *duv = xuv;
  return x;
}

/* P, dP/du, dP/dv and d2P/dudv at (u, v); any output but P may be NULL.
** Each row is summed once with the point weights and once with the
** derivative weights; the rows then combine both ways in v. */
static Vec3 eval_full(const ScenePatch *p, double u, double v, Vec3 *du, Vec3 *dv, Vec3 *duv) {
  PatchRows rows;
  patch_rows(p, u, &rows);
  return eval_rows(&rows, v, du, dv, duv);
}

Vec3 patch_eval(const ScenePatch *p, double u, double v, Vec3 *du, Vec3 *dv) {
  return eval_full(p, u, v, du, dv, NULL);
}

/* True when the cross product n of tangents a and b is too small against
** the tangents themselves to give a direction (a tangent vanished or the
** two are parallel). */
static int degenerate_cross(Vec3 n, Vec3 a, Vec3 b) {
  double la = v3_len(a), lb = v3_len(b), ln = v3_len(n);
  double big = la > lb ? la : lb;
  return !(ln > 1e-10 * big * big) || !isfinite(ln);
}

/* The normal's limit where one tangent vanishes: if dP/du = 0 along
** v = v0, then near it dP/du ~ (v - v0) d2P/dudv, so the normal points
** along sign(v - v0) d2P/dudv x dP/dv, the sign taken toward the inside. */
static Vec3 limit_normal(const ScenePatch *p, double u, double v, Vec3 du, Vec3 dv) {
  Vec3 duv;
  eval_full(p, u, v, NULL, NULL, &duv);
  Vec3 n;
  if (v3_len(du) < v3_len(dv)) n = v3_mul(v3_cross(duv, dv), v < 0.5 ? 1.0 : -1.0);
  else n = v3_mul(v3_cross(du, duv), u < 0.5 ? 1.0 : -1.0);
  return n;
}

/* The normal from tangents du, dv already evaluated at (u, v). */
static Vec3 normal_from(const ScenePatch *p, double u, double v, Vec3 du, Vec3 dv) {
  Vec3 n = v3_cross(du, dv);
  if (!degenerate_cross(n, du, dv)) return v3_norm(n);
  n = limit_normal(p, u, v, du, dv);
  if (v3_len(n) > 0 && isfinite(v3_len(n))) return v3_norm(n);
  /* Both tangents vanish (a collapsed corner) or the patch folds: step
  ** toward the centre until the tangents span a plane again. */
  for (double step = 1e-6; step <= 0.5; step *= 10) {
    double su = u + (0.5 - u) * step * 2, sv = v + (0.5 - v) * step * 2;
    eval_full(p, su, sv, &du, &dv, NULL);
    n = v3_cross(du, dv);
    if (!degenerate_cross(n, du, dv)) return v3_norm(n);
  }
  return v3(0, 0, 1);
}

Vec3 patch_normal(const ScenePatch *p, double u, double v) {
  Vec3 du, dv;
  eval_full(p, u, v, &du, &dv, NULL);
  return normal_from(p, u, v, du, dv);
}

Vec3 patch_eval_normal(const ScenePatch *p, double u, double v, Vec3 *normal) {
  Vec3 du, dv;
  Vec3 x = eval_full(p, u, v, &du, &dv, NULL);
  *normal = normal_from(p, u, v, du, dv);
  return x;
}

Vec3 patch_eval_normal_rows(const ScenePatch *p, const PatchRows *rows, double u, double v,
                            Vec3 *normal) {
  Vec3 du, dv;
  Vec3 x = eval_rows(rows, v, &du, &dv, NULL);
  *normal = normal_from(p, u, v, du, dv);
  return x;
}

void patch_bilinear(ScenePatch *out, Vec3 p00, Vec3 p10, Vec3 p01, Vec3 p11) {
  for (int k = 0; k < 16; k++) out->cp[k] = v3(0, 0, 0);
  out->bilinear = 1;
  out->cp[0] = p00;
  out->cp[1] = p10;
  out->cp[2] = p01;
  out->cp[3] = p11;
}

void patch_elevate_bilinear(const ScenePatch *p, ScenePatch *out) {
  ScenePatch r;
  r.bilinear = 0;
  for (int j = 0; j < 4; j++) {
    double v = j / 3.0;
    Vec3 a = v3_lerp(p->cp[0], p->cp[2], v), b = v3_lerp(p->cp[1], p->cp[3], v);
    for (int i = 0; i < 4; i++) r.cp[4 * j + i] = v3_lerp(a, b, i / 3.0);
  }
  *out = r;
}
