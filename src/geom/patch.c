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

void patch_weights(const ScenePatch *p, double v, PatchWeights *w) {
  if (p->bilinear) bernstein1(v, w->b, w->d);
  else bernstein3(v, w->b, w->d);
}

/* r[0] w[0] + r[1] w[1] + r[2] w[2] + r[3] w[3] added in that order to
** zero (as a loop would: the first add turns -0 into +0). Written out, the
** x and y lanes go together. */
static inline Vec3 sum4(const Vec3 r[4], const double w[4]) {
  Vec3 x = v3_add(v3(0, 0, 0), v3_mul(r[0], w[0]));
  x = v3_add(x, v3_mul(r[1], w[1]));
  x = v3_add(x, v3_mul(r[2], w[2]));
  return v3_add(x, v3_mul(r[3], w[3]));
}

/* P, dP/du and dP/dv at v from the rows at some u and the weights at v:
** the rows combine both ways in v. */
static Vec3 eval_rows(const PatchRows *rows, const PatchWeights *w, Vec3 *du, Vec3 *dv) {
  if (rows->n == 4) {
    *du = sum4(rows->ru, w->b);
    *dv = sum4(rows->r, w->d);
    return sum4(rows->r, w->b);
  }
  Vec3 x = {0, 0, 0}, xu = {0, 0, 0}, xv = {0, 0, 0};
  for (int j = 0; j < rows->n; j++) {
    Vec3 r = rows->r[j], ru = rows->ru[j];
    x = v3_add(x, v3_mul(r, w->b[j]));
    xu = v3_add(xu, v3_mul(ru, w->b[j]));
    xv = v3_add(xv, v3_mul(r, w->d[j]));
  }
  *du = xu;
  *dv = xv;
  return x;
}

/* P, dP/du and dP/dv at (u, v). Each row is summed once with the point
** weights and once with the derivative weights; the rows then combine
** both ways in v. */
static Vec3 eval_full(const ScenePatch *p, double u, double v, Vec3 *du, Vec3 *dv) {
  PatchRows rows;
  PatchWeights w;
  patch_rows(p, u, &rows);
  patch_weights(p, v, &w);
  return eval_rows(&rows, &w, du, dv);
}

/* d2P/dudv at (u, v), the same way. */
static Vec3 eval_twist(const ScenePatch *p, double u, double v) {
  PatchRows rows;
  PatchWeights w;
  patch_rows(p, u, &rows);
  patch_weights(p, v, &w);
  Vec3 xuv = {0, 0, 0};
  for (int j = 0; j < rows.n; j++) xuv = v3_add(xuv, v3_mul(rows.ru[j], w.d[j]));
  return xuv;
}

Vec3 patch_eval(const ScenePatch *p, double u, double v, Vec3 *du, Vec3 *dv) {
  Vec3 xu, xv, x = eval_full(p, u, v, &xu, &xv);
  if (du) *du = xu;
  if (dv) *dv = xv;
  return x;
}

/* True when the cross product of tangents a and b, of length ln, is too
** small against the tangents themselves to give a direction (a tangent
** vanished or the two are parallel). */
static int degenerate_cross(double ln, Vec3 a, Vec3 b) {
  double la = v3_len(a), lb = v3_len(b);
  double big = la > lb ? la : lb;
  return !(ln > 1e-10 * big * big) || !isfinite(ln);
}

/* The normal's limit where one tangent vanishes: if dP/du = 0 along
** v = v0, then near it dP/du ~ (v - v0) d2P/dudv, so the normal points
** along sign(v - v0) d2P/dudv x dP/dv, the sign taken toward the inside. */
static Vec3 limit_normal(const ScenePatch *p, double u, double v, Vec3 du, Vec3 dv) {
  Vec3 duv = eval_twist(p, u, v);
  Vec3 n;
  if (v3_len(du) < v3_len(dv)) n = v3_mul(v3_cross(duv, dv), v < 0.5 ? 1.0 : -1.0);
  else n = v3_mul(v3_cross(du, duv), u < 0.5 ? 1.0 : -1.0);
  return n;
}

/* The normal from tangents du, dv already evaluated at (u, v). Not
** degenerate, the cross product's length ln is positive, so n / ln is
** v3_norm(n) without a second square root. */
static Vec3 normal_from(const ScenePatch *p, double u, double v, Vec3 du, Vec3 dv) {
  Vec3 n = v3_cross(du, dv);
  double ln = v3_len(n);
  if (!degenerate_cross(ln, du, dv)) return v3_mul(n, 1.0 / ln);
  n = limit_normal(p, u, v, du, dv);
  if (v3_len(n) > 0 && isfinite(v3_len(n))) return v3_norm(n);
  /* Both tangents vanish (a collapsed corner) or the patch folds: step
  ** toward the centre until the tangents span a plane again. */
  for (double step = 1e-6; step <= 0.5; step *= 10) {
    double su = u + (0.5 - u) * step * 2, sv = v + (0.5 - v) * step * 2;
    eval_full(p, su, sv, &du, &dv);
    n = v3_cross(du, dv);
    ln = v3_len(n);
    if (!degenerate_cross(ln, du, dv)) return v3_mul(n, 1.0 / ln);
  }
  return v3(0, 0, 1);
}

Vec3 patch_normal(const ScenePatch *p, double u, double v) {
  Vec3 du, dv;
  eval_full(p, u, v, &du, &dv);
  return normal_from(p, u, v, du, dv);
}

Vec3 patch_eval_normal(const ScenePatch *p, double u, double v, Vec3 *normal) {
  Vec3 du, dv;
  Vec3 x = eval_full(p, u, v, &du, &dv);
  *normal = normal_from(p, u, v, du, dv);
  return x;
}

Vec3 patch_eval_normal_rows(const ScenePatch *p, const PatchRows *rows, const PatchWeights *w,
                            double u, double v, Vec3 *normal) {
  Vec3 du, dv;
  Vec3 x = eval_rows(rows, w, &du, &dv);
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
