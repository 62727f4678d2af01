/*
** Texture coordinates and their screen derivatives (texcoord.h).
*/
#include "texcoord.h"

#include <math.h>

static inline double dot3d(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void set3(float d[3], Vec3 v, double k) {
  d[0] = (float)(v.x * k); d[1] = (float)(v.y * k); d[2] = (float)(v.z * k);
}

void texcoord_view(TexView *v, const Camera *c) {
  v->ortho = c->kind == CAMERA_ORTHO;
  double k = v->ortho ? c->ortho_height / c->height   /* world units a pixel */
                      : 2 * tan(c->fov * M_PI / 360.0) / c->height;   /* at unit depth */
  set3(v->eye, c->eye, 1);
  set3(v->fwd, c->forward, 1);
  set3(v->dx, c->right, k);
  set3(v->dy, c->up, -k);   /* pixel rows run down */
}

int texcoord_available(const RenderObject *o, int projection) {
  return projection != PROJ_UV || o->mesh->uv != NULL;
}

int texcoord_resolve(const RenderObject *o, int projection) {
  if (projection != PROJ_AUTO) return projection;
  return o->mesh->uv ? PROJ_UV : PROJ_BOX;
}

/* ---- projections ---------------------------------------------------------- */

/* The angle around z of (x, y) in turns, in [-1/2, 1/2]. */
static double turns(Vec3 p) { return atan2(p.y, p.x) / (2 * M_PI); }

/* Corner angles a[3] unwrapped to lie within half a turn of each other;
** corners on the axis (on[k] = 0) take the mean of the others. */
static void unwrap(double a[3], const int on[3]) {
  int first = on[0] ? 0 : on[1] ? 1 : on[2] ? 2 : -1;
  if (first < 0) { a[0] = a[1] = a[2] = 0; return; }
  double sum = 0;
  int n = 0;
  for (int k = 0; k < 3; k++) {
    if (!on[k]) continue;
    a[k] -= floor(a[k] - a[first] + 0.5);   /* nearest to the first corner */
    sum += a[k];
    n++;
  }
  for (int k = 0; k < 3; k++)
    if (!on[k]) a[k] = sum / n;
}

/* The texture coordinates of the corners of triangle face of o. */
static void corner_coords(const RenderObject *o, int face, int projection, double inv_scale,
                          double t[3][2]) {
  const Mesh *m = o->mesh;
  Vec3 p[3];
  for (int k = 0; k < 3; k++) p[k] = m->pos[m->tri[face][k]];
  if (projection == PROJ_UV) {
    for (int k = 0; k < 3; k++) {
      Vec2 uv = mesh_corner_uv(m, face, k);
      t[k][0] = uv.x * inv_scale;
      t[k][1] = uv.y * inv_scale;
    }
    return;
  }
  if (projection == PROJ_CYLINDRICAL || projection == PROJ_SPHERICAL) {
    double a[3], ext = 0;
    int on[3];
    for (int k = 0; k < 3; k++) ext = fmax(ext, v3_len(p[k]));
    for (int k = 0; k < 3; k++) {
      a[k] = turns(p[k]);
      on[k] = hypot(p[k].x, p[k].y) > 1e-9 * ext;   /* off the axis: has an angle */
    }
    unwrap(a, on);
    for (int k = 0; k < 3; k++) {
      double r = v3_len(p[k]);
      t[k][0] = a[k];
      t[k][1] = projection == PROJ_CYLINDRICAL ? p[k].z * inv_scale
                                               : (r > 0 ? 0.5 + asin(fmax(-1, fmin(1, p[k].z / r))) / M_PI : 0.5);
    }
    return;
  }
  int axis = 2;   /* planar: along z */
  if (projection == PROJ_BOX) {
    Vec3 n = v3_cross(v3_sub(p[1], p[0]), v3_sub(p[2], p[0]));
    double ax = fabs(n.x), ay = fabs(n.y), az = fabs(n.z);
    axis = ax >= ay && ax >= az ? 0 : ay >= az ? 1 : 2;
  }
  for (int k = 0; k < 3; k++) {
    double c[3] = {p[k].x, p[k].y, p[k].z};
    t[k][0] = c[axis == 0 ? 1 : 0] * inv_scale;
    t[k][1] = c[axis == 2 ? 1 : 2] * inv_scale;
  }
}

/* ---- gradients ------------------------------------------------------------- */

void texcoord_triangle(TexTriangle *tt, const RenderObject *o, int face, int projection,
                       float inv_scale, const TexView *v) {
  double t[3][2];
  corner_coords(o, face, projection, inv_scale, t);
  const int *tri = o->mesh->tri[face];
  const float *w0 = o->wpos[tri[0]], *w1 = o->wpos[tri[1]], *w2 = o->wpos[tri[2]];
  double e1[3] = {w1[0] - w0[0], w1[1] - w0[1], w1[2] - w0[2]};
  double e2[3] = {w2[0] - w0[0], w2[1] - w0[1], w2[2] - w0[2]};
  for (int c = 0; c < 2; c++) {
    tt->t0[c] = (float)t[0][c];
    tt->d1[c] = (float)(t[1][c] - t[0][c]);
    tt->d2[c] = (float)(t[2][c] - t[0][c]);
  }
  /* G: the gradient in the plane with G e1 = d1 and G e2 = d2 */
  double a = dot3d(e1, e1), b = dot3d(e1, e2), c = dot3d(e2, e2), det = a * c - b * b;
  double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
  double nl = sqrt(dot3d(n, n));
  double G[2][3] = {{0, 0, 0}, {0, 0, 0}};
  if (det > 1e-30 * a * c && nl > 0) {
    for (int k = 0; k < 2; k++) {
      double d1 = t[1][k] - t[0][k], d2 = t[2][k] - t[0][k];
      double s1 = (c * d1 - b * d2) / det, s2 = (a * d2 - b * d1) / det;
      for (int i = 0; i < 3; i++) G[k][i] = s1 * e1[i] + s2 * e2[i];
    }
    for (int i = 0; i < 3; i++) n[i] /= nl;
  }
  double dx[3] = {v->dx[0], v->dx[1], v->dx[2]}, dy[3] = {v->dy[0], v->dy[1], v->dy[2]};
  double f[3] = {v->fwd[0], v->fwd[1], v->fwd[2]};
  double q[3] = {w0[0] - v->eye[0], w0[1] - v->eye[1], w0[2] - v->eye[2]};
  const double *ref = v->ortho ? f : q;   /* the ray direction the plane is met along */
  double rn = dot3d(ref, n);
  for (int k = 0; k < 2; k++) {
    tt->gq[k] = (float)dot3d(G[k], ref);
    tt->gx[k] = (float)dot3d(G[k], dx);
    tt->gy[k] = (float)dot3d(G[k], dy);
  }
  tt->nx = (float)dot3d(n, dx);
  tt->ny = (float)dot3d(n, dy);
  tt->inv_qn = fabs(rn) > 1e-12 * sqrt(dot3d(ref, ref)) ? (float)(1 / rn) : 0;
}
