/*
** Rendering flat origami (Mitani §5): the face-ID buffer, then one of three
** shadings of it.
**
**   face-ID buffer  every face triangle scan-converted; a face overwrites a
**                   pixel only where it is empty or holds a face the
**                   relation puts below it (§5.1). At a point of a valid
**                   flat fold the faces are totally ordered, so the result
**                   does not depend on the drawing order.
**   line            Sobel filter on the face IDs (§5.2): any ID change is
**                   an edge, the paper's colour elsewhere.
**   illustration    B = (M - V + 2) / 4 at each face corner, M and V
**                   counting the creases of that face's contour meeting
**                   there (swapped for a face showing its back);
**                   B' = min(1, wa B + wb R + wc), R the corner's distance
**                   to the face's upper-left bounding-box corner over the
**                   box diagonal; colour B' (r, g, b) interpolated (§5.3).
**   shaded          the illustration colour times I = 1 - s / S, S the
**                   pixel count of a disk of `radius` pixels, s the part of
**                   it covered by faces above the pixel's face (§5.4).
**                   Per face: a summed-area table of "covered by a face
**                   above me" over the face's visible box, then per pixel
**                   an O(1) test of the disk's bounding square and, where
**                   it is not empty, one row segment per disk row: O(r)
**                   a pixel, not O(r^2).
** Colour: Mitani's (r, g, b) = (1, 1, 0.95) and the brightness B' are
** display values, so B' (r, g, b), the texture's colour and I are
** multiplied in display (sRGB) space and converted to linear once at the
** end (see the style reference).
*/
#ifndef render_origami_h
#define render_origami_h

#include <stdint.h>

#include "../geom/origami.h"
#include "../io/image.h"
#include "../scene/scene.h"

/* The shaded mode's disk when the style gives none, in output pixels. */
#define ORIGAMI_DEFAULT_RADIUS 10.0
/* Largest disk radius, in buffer pixels (the per-row table is this long). */
#define ORIGAMI_MAX_RADIUS 1024

/* Where origami_render draws. Planes are row-major, top row first
** (index y * width + x), in the conventions of camera.h. */
typedef struct OrigamiTarget {
  int width, height;
  float *rgba;          /* width * height * 4, linear RGBA; written where the origami shows
                           (alpha 1) and under its lines */
  int32_t *face_id;     /* optional: the face drawn at each pixel (FOLD files: the
                           faces_vertices index); untouched elsewhere */
  float *depth;         /* optional: window depth in [0, 1] (camera.h), +INFINITY for
                           empty; the origami draws only where it is nearer, and
                           writes its own depth there */
  double pixel_scale;   /* buffer pixels per output pixel (the N of `samples N`):
                           scales the disk radius; 0 means 1 */
  int x0, y0;           /* a window of a larger frame (a tile): the frame pixel the
                           planes' first pixel is; 0, 0 for the whole frame */
  int full_width, full_height;   /* that frame's size (0: width x height) */
} OrigamiTarget;

/* Draw one origami block. object_to_clip = world_to_clip * the block's
** transform (the folded state lies in the block's xy-plane, z = 0).
** style: its `shade origami` gives the mode and parameters (another shade
** kind, or NULL, draws the illustration mode with the paper's values);
** its `lines` (any kind: on a flat fold every visible edge between faces
** outlines a layer, so face_edges, silhouette, crease and boundary all
** name it) adds the Sobel lines to the illustration and shaded modes, in
** its colour, opacity and width (line mode always draws them). texture:
** an image on the paper's front (NULL: none), mapped over the paper's
** bounding box, +y up. A camera below the paper (seeing -z) sees the
** relation reversed and the faces' other sides.
** A window (t->x0, t->y0, t->full_width) draws what the whole frame has
** at its pixels, but for those within the disk radius and a line's width
** (plus 2 pixels) of a window edge that is not the frame's: the caller
** gives the window that margin and keeps the inside (origami_margin).
** Returns the number of pixels the origami covers. */
long origami_render(const OrigamiModel *m, const SceneStyle *style, const Mat4 *object_to_clip,
                    const Image *texture, OrigamiTarget *t);

/* Every origami block of scene s drawn into t, in scene order, as seen by
** world_to_clip (the render camera's, at t's resolution): each block is
** built (origami_build, no pair checks), its style looked up (the default
** style when it has none), its `shade origami { texture ... }` read with
** image_read, and drawn with origami_render (depth-tested when t->depth is
** set, so it composes with meshes drawn before). Returns 1, or 0 when a
** block or a texture failed (its diagnostics reported at the block). */
int origami_draw_scene(const Scene *s, const Mat4 *world_to_clip, OrigamiTarget *t);

/* The margin in buffer pixels a window of scene s needs around the pixels
** it keeps (see origami_render): the largest disk radius and line growth
** of its origami blocks' styles at pixel_scale, plus 3. */
int origami_margin(const Scene *s, double pixel_scale);

/* Only the face-ID buffer: ids[width * height] (set to -1 first), faces
** drawn in the given order (order: nfaces face ids; NULL = 0, 1, 2 ...).
** For tests (order independence) and the `face` AOV. */
void origami_render_ids(const OrigamiModel *m, const Mat4 *object_to_clip, int width, int height,
                        const int *order, int32_t *ids);

/* Screen positions (pixels, y down) of m's folded vertices seen through
** object_to_clip on a width x height image, into xy (m->nverts pairs);
** returns whether the camera sees the block from below (the relation
** reversed). For the SVG writer's face polygons. */
int origami_screen_points(const OrigamiModel *m, const Mat4 *object_to_clip, int width, int height,
                          double (*xy)[2]);

/* The Sobel lines origami_render draws for style (NULL: the defaults):
** whether it draws them, their linear colour, opacity, and width in
** output pixels. */
typedef struct OrigamiLines { int draw; float color[3]; float opacity; double width; } OrigamiLines;
OrigamiLines origami_lines_of(const SceneStyle *style);

/* The folded state's box in world space (z = 0 plane of the block moved by
** transform), for framing a camera. */
void origami_world_bounds(const OrigamiModel *m, const Mat4 *transform, Vec3 *bmin, Vec3 *bmax);

/* Brightness B = (M - V + 2) / 4 of face f at its k-th corner (M, V the
** creases of f's contour meeting there; swapped when the face shows its
** back, or when seen from below: from_below). */
double origami_corner_brightness(const OrigamiModel *m, int f, int k, int from_below);

#endif
