/*
** The render camera: automatic framing, view and projection matrices, and
** the small conversions between world, clip and pixel space (camera.h).
*/
#include "camera.h"

#include <float.h>

/* ---- orientation ------------------------------------------------------ */

/* Fill the view basis from a forward direction and a wished-for up. When up
** is (nearly) parallel to forward, +y and then +x stand in for it. */
static void set_basis(Camera *c, Vec3 forward, Vec3 up) {
  c->forward = v3_norm(forward);
  Vec3 candidates[3] = {up, v3(0, 1, 0), v3(1, 0, 0)};
  for (int i = 0; i < 3; i++) {
    Vec3 r = v3_cross(c->forward, v3_norm(candidates[i]));
    if (v3_len(r) > 1e-6) { c->right = v3_norm(r); break; }
  }
  c->up = v3_cross(c->right, c->forward);
}

/* world -> view: rows are the basis, so view x = right . (p - eye), and
** the camera looks down -z. */
static Mat4 view_matrix(const Camera *c) {
  Mat4 m = m4_identity();
  Vec3 rows[3] = {c->right, c->up, v3_mul(c->forward, -1)};
  for (int i = 0; i < 3; i++) {
    m.m[i][0] = rows[i].x;
    m.m[i][1] = rows[i].y;
    m.m[i][2] = rows[i].z;
    m.m[i][3] = -v3_dot(rows[i], c->eye);
  }
  return m;
}

/* view -> clip, OpenGL style: z_ndc = -1 at the near plane, +1 at far. */
static Mat4 proj_matrix(const Camera *c) {
  Mat4 m = {{{0}}};
  double aspect = (double)c->width / c->height, n = c->znear, f = c->zfar;
  if (c->kind == CAMERA_PERSPECTIVE) {
    double t = 1.0 / tan(c->fov * M_PI / 360.0);   /* cot(fov / 2) */
    m.m[0][0] = t / aspect;
    m.m[1][1] = t;
    m.m[2][2] = (f + n) / (n - f);
    m.m[2][3] = 2 * f * n / (n - f);
    m.m[3][2] = -1;                                 /* w = distance in front */
  } else {
    double half_h = c->ortho_height / 2, half_w = half_h * aspect;
    m.m[0][0] = 1 / half_w;
    m.m[1][1] = 1 / half_h;
    m.m[2][2] = -2 / (f - n);
    m.m[2][3] = -(f + n) / (f - n);
    m.m[3][3] = 1;
  }
  return m;
}

/* ---- framing ----------------------------------------------------------- */

static void box_corner(Vec3 lo, Vec3 hi, int i, Vec3 *q) {
  *q = v3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
}

/* Near and far planes around the box: the nearest and farthest corner
** depths, with a little room. A perspective near plane never reaches 0
** (depth precision): when the eye is inside the box it sits at far / 1e4. */
static void set_depth_range(Camera *c, Vec3 lo, Vec3 hi) {
  double zmin = DBL_MAX, zmax = -DBL_MAX;
  for (int i = 0; i < 8; i++) {
    Vec3 q;
    box_corner(lo, hi, i, &q);
    double z = v3_dot(v3_sub(q, c->eye), c->forward);
    zmin = fmin(zmin, z);
    zmax = fmax(zmax, z);
  }
  double pad = 0.01 * (zmax - zmin) + 1e-9 * fmax(1, fabs(zmax));
  if (zmax <= 0) { c->znear = 0.1; c->zfar = 1; return; }   /* all behind: nothing shows */
  c->zfar = zmax + pad;
  if (c->kind == CAMERA_PERSPECTIVE)
    c->znear = zmin - pad > c->zfar * 1e-4 ? zmin - pad : c->zfar * 1e-4;
  else
    c->znear = zmin - pad > 0 ? zmin - pad : 0;
}

/* Fitting a perspective camera of fixed orientation to points q. With
** x = q.right, y = q.up, z = q.forward and the eye at (ex, ey, ez) in the
** same basis, q is in view when |x - ex| <= tx (z - ez) and likewise for
** y; both are linear in the eye, so the nearest eye that sees every point
** is ez = min((b - a) / 2tx, (d - c) / 2ty), ex = (a + b) / 2,
** ey = (c + d) / 2, where a = max(x - tx z), b = min(x + tx z), and c, d
** the same with y and ty: the points end up centred in the view. */
void camera_fit_init(CameraFit *fit, const Camera *c) {
  fit->ty = tan(c->fov * M_PI / 360.0) * CAMERA_AUTO_FILL;
  fit->tx = fit->ty * c->width / c->height;
  fit->a = fit->c = -DBL_MAX;
  fit->b = fit->d = DBL_MAX;
  fit->n = 0;
}

void camera_fit_add(CameraFit *fit, const Camera *c, Vec3 q) {
  if (!(isfinite(q.x) && isfinite(q.y) && isfinite(q.z))) return;   /* shows nowhere */
  double x = v3_dot(q, c->right), y = v3_dot(q, c->up), z = v3_dot(q, c->forward);
  fit->a = fmax(fit->a, x - fit->tx * z);
  fit->b = fmin(fit->b, x + fit->tx * z);
  fit->c = fmax(fit->c, y - fit->ty * z);
  fit->d = fmin(fit->d, y + fit->ty * z);
  if (fit->n == 0) { fit->lo = fit->hi = q; }
  else {
    fit->lo = v3(fmin(fit->lo.x, q.x), fmin(fit->lo.y, q.y), fmin(fit->lo.z, q.z));
    fit->hi = v3(fmax(fit->hi.x, q.x), fmax(fit->hi.y, q.y), fmax(fit->hi.z, q.z));
  }
  fit->n++;
}

void camera_fit_apply(Camera *c, const CameraFit *fit) {
  if (fit->n == 0) return;
  double ez = fmin((fit->b - fit->a) / (2 * fit->tx), (fit->d - fit->c) / (2 * fit->ty));
  double ex = (fit->a + fit->b) / 2, ey = (fit->c + fit->d) / 2;
  /* a single point (or a flat one seen edge-on) needs some distance */
  double size = v3_len(v3_sub(fit->hi, fit->lo));
  Vec3 centre = v3_mul(v3_add(fit->lo, fit->hi), 0.5);
  if (!(size > 0)) size = 1;
  double zc = v3_dot(centre, c->forward);
  if (zc - ez < 0.5 * size) ez = zc - 0.5 * size;
  c->eye = v3_add(v3_add(v3_mul(c->right, ex), v3_mul(c->up, ey)), v3_mul(c->forward, ez));
  set_depth_range(c, fit->lo, fit->hi);
  c->view = view_matrix(c);
  c->proj = proj_matrix(c);
  c->world_to_clip = m4_mul(c->proj, c->view);
}

/* Perspective along -dir (forward), fitted to the box's corners. */
static void frame_perspective(Camera *c, Vec3 lo, Vec3 hi, Vec3 dir) {
  c->kind = CAMERA_PERSPECTIVE;
  c->fov = CAMERA_AUTO_FOV;
  set_basis(c, v3_mul(v3_norm(dir), -1), v3(0, 0, 1));
  CameraFit fit;
  camera_fit_init(&fit, c);
  for (int i = 0; i < 8; i++) {
    Vec3 q;
    box_corner(lo, hi, i, &q);
    camera_fit_add(&fit, c, q);
  }
  camera_fit_apply(c, &fit);
}

/* Orthographic from +z, +y up, showing the whole box. */
static void frame_ortho_top(Camera *c, Vec3 lo, Vec3 hi) {
  Vec3 centre = v3_mul(v3_add(lo, hi), 0.5);
  double aspect = (double)c->width / c->height;
  c->kind = CAMERA_ORTHO;
  set_basis(c, v3(0, 0, -1), v3(0, 1, 0));
  c->ortho_height = fmax(hi.y - lo.y, (hi.x - lo.x) / aspect) / CAMERA_AUTO_FILL;
  if (c->ortho_height <= 0) c->ortho_height = 1;
  c->eye = v3(centre.x, centre.y, hi.z + c->ortho_height);
}

int camera_setup(Camera *c, const SceneCamera *sc, int width, int height, Vec3 bmin, Vec3 bmax,
                 int origami_only, const char **why) {
  *c = (Camera){0};
  c->width = width;
  c->height = height;
  if (!(bmin.x <= bmax.x && bmin.y <= bmax.y && bmin.z <= bmax.z)) {   /* empty scene */
    bmin = v3(-1, -1, -1);
    bmax = v3(1, 1, 1);
  }
  if (!sc || !sc->present) {
    if (origami_only) frame_ortho_top(c, bmin, bmax);
    else frame_perspective(c, bmin, bmax, v3(1, -2, 1));
  } else {
    Vec3 fwd = v3_sub(sc->look_at, sc->position);
    if (v3_len(fwd) <= 0) { *why = "the camera's position and look_at are the same point"; return 0; }
    c->kind = sc->kind;
    c->eye = sc->position;
    c->fov = sc->fov;
    c->ortho_height = sc->ortho_height;
    if (c->kind == CAMERA_PERSPECTIVE && !(c->fov > 0 && c->fov < 180)) {
      *why = "the camera's fov must lie between 0 and 180 degrees";
      return 0;
    }
    if (c->kind == CAMERA_ORTHO && !(c->ortho_height > 0)) {
      *why = "the camera's ortho height must be positive";
      return 0;
    }
    set_basis(c, fwd, v3_len(sc->up) > 0 ? sc->up : v3(0, 0, 1));
  }
  set_depth_range(c, bmin, bmax);
  c->view = view_matrix(c);
  c->proj = proj_matrix(c);
  c->world_to_clip = m4_mul(c->proj, c->view);
  return 1;
}

Camera camera_scaled(const Camera *c, int width, int height) {
  Camera r = *c;   /* the projection depends only on the aspect ratio */
  r.width = width;
  r.height = height;
  return r;
}

/* ---- conversions ------------------------------------------------------- */

void camera_to_clip(const Camera *c, Vec3 p, double out[4]) {
  const double (*m)[4] = c->world_to_clip.m;
  for (int i = 0; i < 4; i++) out[i] = m[i][0] * p.x + m[i][1] * p.y + m[i][2] * p.z + m[i][3];
}

int camera_to_pixel(const Camera *c, Vec3 p, double *x, double *y, double *depth) {
  double h[4];
  camera_to_clip(c, p, h);
  if (h[3] <= 0) return 0;
  *x = (h[0] / h[3] + 1) * 0.5 * c->width;
  *y = (1 - h[1] / h[3]) * 0.5 * c->height;
  *depth = (h[2] / h[3] + 1) * 0.5;
  return 1;
}

double camera_view_depth(const Camera *c, double depth) {
  double n = c->znear, f = c->zfar, zn = 2 * depth - 1;
  if (c->kind == CAMERA_ORTHO) return n + depth * (f - n);
  return 2 * f * n / ((f + n) - zn * (f - n));   /* inverse of the projection's z row */
}

Vec3 camera_unproject(const Camera *c, double x, double y, double depth) {
  double nx = 2 * x / c->width - 1, ny = 1 - 2 * y / c->height;
  double d = camera_view_depth(c, depth);
  double aspect = (double)c->width / c->height;
  double half_h = c->kind == CAMERA_PERSPECTIVE ? d * tan(c->fov * M_PI / 360.0) : c->ortho_height / 2;
  Vec3 p = v3_add(c->eye, v3_mul(c->forward, d));
  p = v3_add(p, v3_mul(c->right, nx * half_h * aspect));
  return v3_add(p, v3_mul(c->up, ny * half_h));
}

Vec3 camera_view_dir(const Camera *c, Vec3 p) {
  if (c->kind == CAMERA_ORTHO) return v3_mul(c->forward, -1);
  return v3_norm(v3_sub(c->eye, p));
}
