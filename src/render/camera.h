/*
** The render camera: a SceneCamera (or the automatic framing of
** language.md § Conventions) turned into the matrices every render stage
** shares. A plain struct: the line stages read it as they read the G-buffer.
**
** Spaces, in the order a point goes through them:
**   world   right-handed, z up (the scene's units)
**   view    camera at the origin looking down -z, +x right, +y up
**   clip    OpenGL convention: visible where -w <= x, y, z <= w
**   NDC     clip / w, each in [-1, 1]
**   pixel   x = (ndc.x + 1) / 2 * width, y = (1 - ndc.y) / 2 * height:
**           y runs down, pixel (i, j) covers [i, i+1) x [j, j+1), its centre
**           is (i + 0.5, j + 0.5); depth = (ndc.z + 1) / 2 in [0, 1],
**           0 at the near plane, 1 at the far plane (not linear in distance
**           for a perspective camera: see camera_view_depth).
** width and height are those of the image the camera was set up for; the
** G-buffer's camera is set up at the sample resolution (output size times
** the samples per side), so its pixels are samples.
*/
#ifndef render_camera_h
#define render_camera_h

#include "../base/vec.h"
#include "../scene/scene.h"

typedef struct Camera {
  CameraKind kind;
  int width, height;       /* pixels of the target image */
  Vec3 eye;                /* world position */
  Vec3 forward, right, up; /* world unit vectors: view -z, +x, +y */
  double fov;              /* vertical field of view, degrees (perspective) */
  double ortho_height;     /* world units shown vertically (ortho) */
  double znear, zfar;      /* distances along forward to the clip planes */
  Mat4 view;               /* world -> view */
  Mat4 proj;               /* view -> clip */
  Mat4 world_to_clip;      /* proj * view */
} Camera;

/* Default vertical field of view of an automatically framed camera. */
#define CAMERA_AUTO_FOV 30.0
/* Framing margin of an automatic camera: the scene's box fills the view up
** to this fraction of its height or width. */
#define CAMERA_AUTO_FILL 0.92

/* Set up *c for a width x height image. sc is the scene's camera (present
** = 0 frames the world box [bmin, bmax] automatically: perspective, fov 30,
** from direction (1, -2, 1); with origami_only, orthographic from +z with +y
** up). The near and far planes enclose the box. Returns 1, or 0 with a
** reason in *why when the camera is unusable (position equal to look_at,
** zero fov or ortho height). */
int camera_setup(Camera *c, const SceneCamera *sc, int width, int height, Vec3 bmin, Vec3 bmax,
                 int origami_only, const char **why);

/* Refitting an automatic perspective camera to the points it must show
** (the tessellated surfaces rather than their control boxes): keeps the
** orientation and fov, moves the eye to the nearest place that shows every
** point within CAMERA_AUTO_FILL of the view, centred, and sets the depth
** range around them.
**   CameraFit fit; camera_fit_init(&fit, c);
**   for each point q: camera_fit_add(&fit, c, q);
**   camera_fit_apply(c, &fit);    (no points: the camera is unchanged) */
typedef struct CameraFit {
  double tx, ty, a, b, c, d;
  Vec3 lo, hi;
  long n;
} CameraFit;
void camera_fit_init(CameraFit *fit, const Camera *c);
void camera_fit_add(CameraFit *fit, const Camera *c, Vec3 q);
void camera_fit_apply(Camera *c, const CameraFit *fit);

/* The same camera for an image scale times as large on each side (the
** G-buffer of a supersampled frame, a reference image at ref_scale). */
Camera camera_scaled(const Camera *c, int width, int height);

/* Clip coordinates (x, y, z, w) of a world point into out[4]. */
void camera_to_clip(const Camera *c, Vec3 p, double out[4]);

/* Pixel position and depth of a world point (see above); returns 0 (and
** leaves *x, *y, *depth untouched) when the point is not in front of the
** camera (w <= 0). */
int camera_to_pixel(const Camera *c, Vec3 p, double *x, double *y, double *depth);

/* The distance along forward (view-space -z) of a G-buffer depth. */
double camera_view_depth(const Camera *c, double depth);

/* The world point seen at pixel position (x, y) with G-buffer depth. */
Vec3 camera_unproject(const Camera *c, double x, double y, double depth);

/* Unit vector from world point p toward the viewer: toward the eye for a
** perspective camera, -forward for an orthographic one. */
Vec3 camera_view_dir(const Camera *c, Vec3 p);

#endif
