/*
** Matrix constructors and inversion for the transforms of the language.
*/
#include "vec.h"

Mat4 m4_translate(Vec3 t) {
  Mat4 r = m4_identity();
  r.m[0][3] = t.x;
  r.m[1][3] = t.y;
  r.m[2][3] = t.z;
  return r;
}

Mat4 m4_scale(Vec3 s) {
  Mat4 r = m4_identity();
  r.m[0][0] = s.x;
  r.m[1][1] = s.y;
  r.m[2][2] = s.z;
  return r;
}

/* Exact values at multiples of 90 degrees keep axis-aligned scenes exact. */
static void sincos_deg(double deg, double *s, double *c) {
  double q = fmod(deg, 360.0);
  if (q < 0) q += 360.0;
  if (q == 0) { *s = 0; *c = 1; }
  else if (q == 90) { *s = 1; *c = 0; }
  else if (q == 180) { *s = 0; *c = -1; }
  else if (q == 270) { *s = -1; *c = 0; }
  else { double r = deg * M_PI / 180.0; *s = sin(r); *c = cos(r); }
}

Mat4 m4_rotate_xyz(Vec3 d) {
  double s, c;
  Mat4 rx = m4_identity(), ry = m4_identity(), rz = m4_identity();
  sincos_deg(d.x, &s, &c);
  rx.m[1][1] = c; rx.m[1][2] = -s; rx.m[2][1] = s; rx.m[2][2] = c;
  sincos_deg(d.y, &s, &c);
  ry.m[0][0] = c; ry.m[0][2] = s; ry.m[2][0] = -s; ry.m[2][2] = c;
  sincos_deg(d.z, &s, &c);
  rz.m[0][0] = c; rz.m[0][1] = -s; rz.m[1][0] = s; rz.m[1][1] = c;
  return m4_mul(rz, m4_mul(ry, rx));   /* x first, then y, then z */
}

Mat4 m4_rotate_axis(double deg, Vec3 axis) {
  Vec3 u = v3_norm(axis);
  double s, c;
  sincos_deg(deg, &s, &c);
  double t = 1 - c;
  Mat4 r = m4_identity();   /* Rodrigues' rotation matrix */
  r.m[0][0] = c + u.x * u.x * t;       r.m[0][1] = u.x * u.y * t - u.z * s; r.m[0][2] = u.x * u.z * t + u.y * s;
  r.m[1][0] = u.y * u.x * t + u.z * s; r.m[1][1] = c + u.y * u.y * t;       r.m[1][2] = u.y * u.z * t - u.x * s;
  r.m[2][0] = u.z * u.x * t - u.y * s; r.m[2][1] = u.z * u.y * t + u.x * s; r.m[2][2] = c + u.z * u.z * t;
  return r;
}

Mat4 m4_mirror(Vec3 n) {
  Vec3 u = v3_norm(n);
  Mat4 r = m4_identity();   /* I - 2 u u^T */
  double d[3] = {u.x, u.y, u.z};
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) r.m[i][j] -= 2 * d[i] * d[j];
  return r;
}

Mat4 m4_transpose(Mat4 a) {
  Mat4 r;
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) r.m[i][j] = a.m[j][i];
  return r;
}

/* Gauss-Jordan elimination with partial pivoting. */
Mat4 m4_inverse(Mat4 a, int *ok) {
  Mat4 inv = m4_identity();
  for (int col = 0; col < 4; col++) {
    int piv = col;
    for (int r = col + 1; r < 4; r++)
      if (fabs(a.m[r][col]) > fabs(a.m[piv][col])) piv = r;
    if (fabs(a.m[piv][col]) < 1e-300) { *ok = 0; return m4_identity(); }
    for (int j = 0; j < 4; j++) {
      double t = a.m[col][j]; a.m[col][j] = a.m[piv][j]; a.m[piv][j] = t;
      t = inv.m[col][j]; inv.m[col][j] = inv.m[piv][j]; inv.m[piv][j] = t;
    }
    double d = a.m[col][col];
    for (int j = 0; j < 4; j++) { a.m[col][j] /= d; inv.m[col][j] /= d; }
    for (int r = 0; r < 4; r++) {
      if (r == col) continue;
      double f = a.m[r][col];
      for (int j = 0; j < 4; j++) { a.m[r][j] -= f * a.m[col][j]; inv.m[r][j] -= f * inv.m[col][j]; }
    }
  }
  *ok = 1;
  return inv;
}
