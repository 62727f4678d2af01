/*
** Small vector and matrix math shared by every stage (double precision).
** Matrices are row-major and act on column vectors: p' = M p.
*/
#ifndef base_vec_h
#define base_vec_h

#include <math.h>

typedef struct Vec2 { double x, y; } Vec2;
typedef struct Vec3 { double x, y, z; } Vec3;
typedef struct Mat4 { double m[4][4]; } Mat4;

static inline Vec3 v3(double x, double y, double z) { Vec3 r = {x, y, z}; return r; }
static inline Vec3 v3_add(Vec3 a, Vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline Vec3 v3_sub(Vec3 a, Vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline Vec3 v3_mul(Vec3 a, double s) { return v3(a.x * s, a.y * s, a.z * s); }
static inline Vec3 v3_hadamard(Vec3 a, Vec3 b) { return v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static inline double v3_dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline Vec3 v3_cross(Vec3 a, Vec3 b) {
  return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline double v3_len(Vec3 a) { return sqrt(v3_dot(a, a)); }
/* Unit vector along a; the zero vector stays zero (never NaN). */
static inline Vec3 v3_norm(Vec3 a) {
  double l = v3_len(a);
  return l > 0 ? v3_mul(a, 1.0 / l) : v3(0, 0, 0);
}
static inline Vec3 v3_lerp(Vec3 a, Vec3 b, double t) { return v3_add(a, v3_mul(v3_sub(b, a), t)); }

static inline Mat4 m4_identity(void) {
  Mat4 r = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};
  return r;
}
static inline Mat4 m4_mul(Mat4 a, Mat4 b) {  /* a * b: applies b first */
  Mat4 r;
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++)
      r.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j] +
                  a.m[i][3] * b.m[3][j];
  return r;
}
static inline Vec3 m4_point(Mat4 a, Vec3 p) {  /* affine point transform (w = 1) */
  return v3(a.m[0][0] * p.x + a.m[0][1] * p.y + a.m[0][2] * p.z + a.m[0][3],
            a.m[1][0] * p.x + a.m[1][1] * p.y + a.m[1][2] * p.z + a.m[1][3],
            a.m[2][0] * p.x + a.m[2][1] * p.y + a.m[2][2] * p.z + a.m[2][3]);
}
static inline Vec3 m4_dir(Mat4 a, Vec3 d) {  /* direction transform (w = 0) */
  return v3(a.m[0][0] * d.x + a.m[0][1] * d.y + a.m[0][2] * d.z,
            a.m[1][0] * d.x + a.m[1][1] * d.y + a.m[1][2] * d.z,
            a.m[2][0] * d.x + a.m[2][1] * d.y + a.m[2][2] * d.z);
}

Mat4 m4_translate(Vec3 t);
Mat4 m4_scale(Vec3 s);
Mat4 m4_rotate_xyz(Vec3 degrees);   /* about x, then y, then z (OpenSCAD order) */
Mat4 m4_rotate_axis(double degrees, Vec3 axis);   /* right-handed about axis (unit or not) */
Mat4 m4_mirror(Vec3 normal);       /* reflection in the plane through the origin across normal */
Mat4 m4_inverse(Mat4 a, int *ok);   /* *ok = 0 when singular */
Mat4 m4_transpose(Mat4 a);

#endif
