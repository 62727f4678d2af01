/*
** Texture coordinates of a surface and their screen-space rates of change,
** for the textured shading models (threshold textures, 002 section 3).
**
** Coordinates come from the mesh's own (u, v) (a patch's parameters, an
** imported mesh's UVs) or from a projection of the object-space surface
** point p = (x, y, z), in texture units of `scale` object units:
**   planar       (x, y)
**   box          the two axes across the triangle's largest normal axis
**                (x: (y, z), y: (x, z), z: (x, y))
**   cylindrical  (turns around z, z): u = atan2(y, x) / 2 pi
**   spherical    (turns around z, latitude): v = 1/2 + asin(z / |p|) / pi
** Each corner of a triangle is projected and the coordinates interpolated
** across it, as a mesh's UVs are: around the seam of the cylinder and the
** sphere a triangle's corners are unwrapped to one side, and a corner on
** the axis takes the angle of the others. So the coordinates are affine
** over each triangle, and their screen derivatives come from the
** triangle's own plane and gradients: at a surface point p seen along
** q = p - eye, one pixel step D of the view ray moves the point on the
** plane (normal n) by dp = (q.f) (D - q (D.n) / (q.n)) (perspective, f the
** forward axis and D at unit depth), or dp = D - f (D.n) / (f.n)
** (orthographic), and the coordinates by G dp, G their world gradient.
*/
#ifndef render_texcoord_h
#define render_texcoord_h

#include "../base/lanes.h"
#include "render.h"

/* The camera as the derivatives need it: one output pixel's step along x
** and along y (down) of the view ray at unit depth (perspective) or of the
** ray itself (orthographic). */
typedef struct TexView {
  int ortho;
  float eye[3], fwd[3];
  float dx[3], dy[3];
} TexView;

/* The view of camera c (the output's: derivatives are per output pixel). */
void texcoord_view(TexView *v, const Camera *c);

/* One triangle's coordinates: at corner 0 (t0) and along its two edges
** (t1 - t0, t2 - t0), so the coordinates at barycentrics (b1, b2) are
** t0 + b1 d1 + b2 d2; and the constants of its screen derivatives. */
struct TexTriangle {
  float t0[2], d1[2], d2[2];
  float gq[2];                 /* G q at corner 0 (q = w0 - eye), or G f (ortho) */
  float gx[2], gy[2];          /* G D for the two pixel steps */
  float nx, ny;                /* n.D */
  float inv_qn;                /* 1 / (q.n) at corner 0, or 1 / (f.n) (ortho); 0 edge-on */
};

/* Whether projection (TexProjection) can give o's triangles coordinates:
** PROJ_UV needs the mesh's own. */
int texcoord_available(const RenderObject *o, int projection);

/* Set up triangle face of object o for view v with projection (not
** PROJ_AUTO: texcoord_resolve) and scale (object units a texture unit). */
void texcoord_triangle(TexTriangle *tt, const RenderObject *o, int face, int projection,
                       float inv_scale, const TexView *v);

/* PROJ_AUTO made concrete for o: its own coordinates where it has them,
** else box. */
int texcoord_resolve(const RenderObject *o, int projection);

/* The coordinates of n samples of triangle tt at barycentrics bary[i] and
** world points (px, py, pz)[i] (on its plane) into (u, v)[i], and their
** derivatives per output pixel into ux = du/dx, uy = du/dy, vx, vy. One
** loop a camera kind, the triangle's constants held, so the samples run
** side by side. Near edge-on the derivatives are large but finite
** (texcoord_triangle bounds 1 / (q.n)); the layers cap what they take. */
static inline void texcoord_run(const TexTriangle *tt, const TexView *v, int n, const float (*bary)[2],
                                const float *restrict px, const float *restrict py,
                                const float *restrict pz, float *restrict u, float *restrict w,
                                float *restrict ux, float *restrict uy, float *restrict vx,
                                float *restrict vy) {
  float kx = tt->nx * tt->inv_qn, ky = tt->ny * tt->inv_qn;
  if (v->ortho) {   /* depth 1, and G q is the constant G f */
    float rx0 = tt->gx[0] - tt->gq[0] * kx, ry0 = tt->gy[0] - tt->gq[0] * ky;
    float rx1 = tt->gx[1] - tt->gq[1] * kx, ry1 = tt->gy[1] - tt->gq[1] * ky;
    for (int i = 0; i < n; i++) {
      float b1 = bary[i][0], b2 = bary[i][1];
      u[i] = tt->t0[0] + b1 * tt->d1[0] + b2 * tt->d2[0];
      w[i] = tt->t0[1] + b1 * tt->d1[1] + b2 * tt->d2[1];
      ux[i] = rx0; uy[i] = ry0;
      vx[i] = rx1; vy[i] = ry1;
    }
    return;
  }
  for (int i = 0; i < n; i++) {
    float b1 = bary[i][0], b2 = bary[i][1];
    float du = b1 * tt->d1[0] + b2 * tt->d2[0], dv = b1 * tt->d1[1] + b2 * tt->d2[1];
    u[i] = tt->t0[0] + du;
    w[i] = tt->t0[1] + dv;
    float gq0 = tt->gq[0] + du, gq1 = tt->gq[1] + dv;   /* G q at p: affine over the triangle */
    float depth = (px[i] - v->eye[0]) * v->fwd[0] + (py[i] - v->eye[1]) * v->fwd[1] +
                  (pz[i] - v->eye[2]) * v->fwd[2];
    ux[i] = depth * (tt->gx[0] - gq0 * kx);
    uy[i] = depth * (tt->gy[0] - gq0 * ky);
    vx[i] = depth * (tt->gx[1] - gq1 * kx);
    vy[i] = depth * (tt->gy[1] - gq1 * ky);
  }
}

/* texcoord_run four samples at a time, the same bits: for n rounded up to
** a multiple of 4, so it reads bary and (px, py, pz) and writes the six
** outputs up to 3 samples past n (the caller's to have them). */
static inline void texcoord_run_lanes(const TexTriangle *tt, const TexView *v, int n, const float (*bary)[2],
                                      const float *restrict px, const float *restrict py,
                                      const float *restrict pz, float *restrict u, float *restrict w,
                                      float *restrict ux, float *restrict uy, float *restrict vx,
                                      float *restrict vy) {
  float kx = tt->nx * tt->inv_qn, ky = tt->ny * tt->inv_qn;
  F4 t00 = f4_set(tt->t0[0]), t01 = f4_set(tt->t0[1]), d10 = f4_set(tt->d1[0]), d11 = f4_set(tt->d1[1]);
  F4 d20 = f4_set(tt->d2[0]), d21 = f4_set(tt->d2[1]);
  if (v->ortho) {   /* depth 1, and G q is the constant G f */
    F4 rx0 = f4_set(tt->gx[0] - tt->gq[0] * kx), ry0 = f4_set(tt->gy[0] - tt->gq[0] * ky);
    F4 rx1 = f4_set(tt->gx[1] - tt->gq[1] * kx), ry1 = f4_set(tt->gy[1] - tt->gq[1] * ky);
    for (int i = 0; i < n; i += 4) {
      F4 b1, b2;
      f4_load_pairs(bary[i], &b1, &b2);
      f4_store(u + i, f4_add(f4_add(t00, f4_mul(b1, d10)), f4_mul(b2, d20)));
      f4_store(w + i, f4_add(f4_add(t01, f4_mul(b1, d11)), f4_mul(b2, d21)));
      f4_store(ux + i, rx0); f4_store(uy + i, ry0);
      f4_store(vx + i, rx1); f4_store(vy + i, ry1);
    }
    return;
  }
  F4 gq0 = f4_set(tt->gq[0]), gq1 = f4_set(tt->gq[1]), fkx = f4_set(kx), fky = f4_set(ky);
  F4 gx0 = f4_set(tt->gx[0]), gy0 = f4_set(tt->gy[0]), gx1 = f4_set(tt->gx[1]), gy1 = f4_set(tt->gy[1]);
  F4 e0 = f4_set(v->eye[0]), e1 = f4_set(v->eye[1]), e2 = f4_set(v->eye[2]);
  F4 f0 = f4_set(v->fwd[0]), f1 = f4_set(v->fwd[1]), f2 = f4_set(v->fwd[2]);
  for (int i = 0; i < n; i += 4) {
    F4 b1, b2;
    f4_load_pairs(bary[i], &b1, &b2);
    F4 du = f4_add(f4_mul(b1, d10), f4_mul(b2, d20)), dv = f4_add(f4_mul(b1, d11), f4_mul(b2, d21));
    f4_store(u + i, f4_add(t00, du));
    f4_store(w + i, f4_add(t01, dv));
    F4 q0 = f4_add(gq0, du), q1 = f4_add(gq1, dv);   /* G q at p: affine over the triangle */
    F4 depth = f4_add(f4_add(f4_mul(f4_sub(f4_load(px + i), e0), f0), f4_mul(f4_sub(f4_load(py + i), e1), f1)),
                      f4_mul(f4_sub(f4_load(pz + i), e2), f2));
    f4_store(ux + i, f4_mul(depth, f4_sub(gx0, f4_mul(q0, fkx))));
    f4_store(uy + i, f4_mul(depth, f4_sub(gy0, f4_mul(q0, fky))));
    f4_store(vx + i, f4_mul(depth, f4_sub(gx1, f4_mul(q1, fkx))));
    f4_store(vy + i, f4_mul(depth, f4_sub(gy1, f4_mul(q1, fky))));
  }
}

#endif
