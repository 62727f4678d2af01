/*
** The triangle rasterizer: half-space (edge function) scan conversion into
** G-buffer planes, with a top-left fill rule on a fixed-point grid, so a
** mesh whose triangles share edges covers each sample of its silhouette
** exactly once (no cracks, no double coverage), perspective-correct
** barycentrics and a depth test.
**
** Two steps. rast_emit() takes a triangle in clip coordinates (camera.h),
** clips it against the near and far planes and a guard band around the
** image when it must, and appends one or more RastTri to a list: the
** per-triangle setup (edge functions, attribute planes). rast_triangle()
** then draws one RastTri into a RastTarget, a rectangle of G-buffer planes
** (a whole G-buffer or one screen tile of it). Drawing is deterministic:
** equal depths keep the sample drawn first, so the result depends only on
** the order triangles are drawn in, never on how the image is tiled
** between threads.
**
** Sample positions are pixel centres (x + 0.5, y + 0.5) of the target grid.
*/
#ifndef render_raster_h
#define render_raster_h

#include <stdint.h>

/* Vertex positions are snapped to 1/256 pixel: edge functions are exact
** integers, so neighbouring triangles agree on every sample. */
#define RAST_SUBPIXEL_BITS 8
/* Triangles reaching further than this many pixels outside the image are
** clipped there (keeps the fixed-point products inside 64 bits). */
#define RAST_GUARD_PX 8192
/* Largest target side in samples the fixed-point grid supports. */
#define RAST_MAX_DIM 32768

/* A triangle ready to draw. The edge function of edge i (the edge opposite
** vertex i) at the fixed-point sample position (X, Y) is
** e[i] = a[i] X + b[i] Y + c[i], positive inside; c[i] carries the fill
** rule's bias, so "covered" is e[0], e[1], e[2] >= 0. Attributes are planes
** in pixel space: value = p[0] + p[1] (x - x0) + p[2] (y - y0). */
typedef struct RastTri {
  int32_t a[3], b[3];
  int64_t c[3];
  int x0, y0, x1, y1;      /* covered pixels lie in [x0, x1) x [y0, y1) */
  float ox, oy;            /* plane origin: pixel position of vertex 0 */
  float z[3];              /* window depth, linear in screen space */
  float iw[3];             /* 1 / w */
  float b1w[3], b2w[3];    /* source barycentrics b1 / w, b2 / w */
  int32_t object, face;
} RastTri;

/* A growing list of set-up triangles (rast_emit appends). */
typedef struct RastTriList {
  RastTri *tris;
  int n, cap;
} RastTriList;

/* Where rast_triangle draws: a clip rectangle of pixels, and planes in
** which pixel (x, y) lives at index (y - oy) * stride + (x - ox). count,
** when not NULL, is incremented for every covered sample before the depth
** test (the fill-rule tests use it). */
typedef struct RastTarget {
  int x0, y0, x1, y1;       /* drawable rectangle, end exclusive */
  int ox, oy, stride;
  float *depth;
  int32_t *object, *face;
  float (*bary)[2];
  uint16_t *count;
} RastTarget;

/* A vertex projected for a width x height target: rast_vertex() once per
** mesh vertex, then rast_emit() per triangle (shared vertices are projected
** once, and neighbours see bit-identical positions). Twenty bytes: its clip
** coordinates are not kept, only the few triangles that need clipping read
** them, and their callers work them out again (rast_clip_point). */
/* RastVert.outcode bit of a vertex with a NaN or infinite coordinate. */
#define RAST_INVALID (1u << 6)

typedef struct RastVert {
  int32_t X, Y;            /* fixed-point pixel position (when outcode is 0): inside the guard
                              band, |X|, |Y| < (RAST_MAX_DIM + 2 RAST_GUARD_PX) 2^RAST_SUBPIXEL_BITS */
  float z, iw;             /* window depth and 1 / w (when outcode is 0) */
  uint32_t outcode;        /* planes (near, far, guard band) it is outside of; RAST_INVALID */
} RastVert;

void rast_vertex(RastVert *v, const double clip[4], int width, int height);
/* Clip coordinates of world point pos under m (camera.h's world_to_clip,
** as camera_to_clip does it): the arithmetic rast_vertices does, so a
** caller working them out again gets the same bits. */
void rast_clip_point(double clip[4], const double m[4][4], const float pos[3]);
/* rast_vertex for n points pos (world space) taken to clip coordinates by
** m (rast_clip_point), into out. */
void rast_vertices(RastVert *out, const float (*pos)[3], int n, const double m[4][4], int width, int height);

/* Set up triangle (v[0], v[1], v[2]) for a width x height target and
** append it to list, clipped against the near and far planes and the guard
** band when it crosses them. clip[i] are the clip coordinates v[i] was
** projected from: read only when the triangle needs clipping (some outcode
** is set but not one plane's in all three), so NULL will do when none of
** the outcodes is set. Its samples record object and face; the
** barycentrics they record are those of this triangle (b1 for v[1], b2 for
** v[2]), through any clipping. Returns the number of RastTri appended (0:
** outside or degenerate). */
int rast_emit(RastTriList *list, const RastVert *const v[3], const double *const clip[3], int32_t object,
              int32_t face, int width, int height);
/* Does triangle v need clipping coordinates for rast_emit: some vertex is
** outside a plane, but the triangle is not wholly outside one plane and no
** vertex is invalid? */
static inline int rast_needs_clip(const RastVert *const v[3]) {
  unsigned any = v[0]->outcode | v[1]->outcode | v[2]->outcode;
  return any && !(v[0]->outcode & v[1]->outcode & v[2]->outcode) && !(any & RAST_INVALID);
}

/* The same setup for a triangle none of whose vertices is outside a plane
** (outcodes 0): what rast_emit appends for it, into t. Returns 0 when it
** has no area or covers no sample centre. */
int rast_setup(RastTri *t, const RastVert *const v[3], int32_t object, int32_t face, int width, int height);

/* What a setup would cover without doing it, for such a triangle: its
** pixel box (x0, y0, x1, y1, as RastTri's) and a depth no sample it draws
** is nearer than, below the least of its depth plane over the box's sample
** centres by a margin wider than the rounding of setup's float planes.
** Returns 0 when rast_setup would. */
int rast_bounds(const RastVert *const v[3], int width, int height, int box[4], float *zmin);

/* Draw t into rt: every covered sample inside rt's rectangle whose depth is
** less than the stored depth gets depth, object, face and barycentrics. */
void rast_triangle(const RastTri *t, const RastTarget *rt);

void rast_list_free(RastTriList *list);

#endif
