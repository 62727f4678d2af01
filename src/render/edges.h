/*
** Important edges (Brown & Arandjelovic, 001 §2.1.1): per object, which
** mesh edges are silhouettes, creases, boundaries or polygon (face) edges
** for the current view, each given a global id for the reference image.
** Also the per-object data the later line stages share: vertices projected
** into the reference image and the vertex -> edge graph used for linking.
*/
#ifndef render_edges_h
#define render_edges_h

#include "../geom/mesh.h"
#include "../scene/scene.h"
#include "camera.h"

/* Faces meeting at less than this angle (degrees) are coplanar for the
** crease test. Rounding float vertices tilts the triangles of a flat
** polygon by about 6e-8 radians times its distance from the origin over
** its size (under this angle up to a ratio of ~3000); the faces of a
** tessellated curve meet at degrees. */
#define LINE_COPLANAR_DEG 0.01

/* One object as the line stages see it. lines NULL (or !present) makes it
** an occluder only. */
typedef struct LineObject {
  const Mesh *mesh;
  Mat4 object_to_world;
  const SceneLines *lines;
  int id;                  /* object id: keys the random streams, names SVG groups */
  Color fill;              /* linear; the SVG fills the object's visible region with it */
  const unsigned char *hidden;   /* per triangle: a back face the object's own front hides
                                    (a closed mesh seen from outside, as the rasterizer skips
                                    them), left out of the reference image; or NULL */
} LineObject;

/* A vertex in the reference image: clip coordinates and, when in front of
** the camera (w > 0), its pixel position and nearness (line_clip_to_screen). */
typedef struct LineVert {
  double clip[4];
  float x, y, n;           /* reference-image pixels, nearness (meaningless when clip[3] <= 0) */
  int in;                  /* in front of the near plane (z >= -w, w > 0) and x, y, n finite:
                              a triangle of such corners needs no clipping */
} LineVert;

/* A clip-space point to reference pixels (w x h) and nearness (1 - depth):
** the one projection the line stages use, so a vertex projected once and
** a clip point projected later agree. */
static inline void line_clip_to_screen(const double c[4], int w, int h, float *x, float *y,
                                       float *n) {
  double iw = 1.0 / c[3];
  *x = (float)((c[0] * iw + 1) * 0.5 * w);
  *y = (float)((1 - c[1] * iw) * 0.5 * h);
  *n = (float)((1 - c[2] * iw) * 0.5);
}

/* The triangles of a mesh in runs of this many (the last may be short),
** each with a bound on its pixels in the reference image: a run none of
** whose pixels is near an edge is passed over as a whole. */
#define LINE_CLUSTER_TRIS 64

/* Per-object edge data, built by line_edges_build. */
typedef struct LineObjEdges {
  const Mesh *mesh;
  const SceneLines *lines; /* NULL when the object draws no lines */
  LineVert *vert;          /* mesh->nverts projected vertices */
  int *id;                 /* per mesh edge: global id (1-based), 0 = not important */
  int *adj_start;          /* nverts + 1 offsets into adj: the vertex -> edge graph
                              of the important edges (the only ones linking walks) */
  int *adj;                /* incident important mesh edges of each vertex, in edge order */
  unsigned char *front;    /* per triangle: its front faces the viewer */
  float (*cluster)[4];     /* per run of LINE_CLUSTER_TRIS triangles: x0, y0, x1, y1, a box in
                              reference pixels holding every pixel of its triangles (infinite
                              where part of the run is behind the near plane); NULL when not
                              made (an object without lines, or a mesh not kept across
                              frames) */
} LineObjEdges;

/* Every important edge of every object; id i + 1 is entry i. */
typedef struct LineEdges {
  int nobj;
  LineObjEdges *obj;
  int n;                   /* important edges */
  int *obj_of;             /* object index of id i + 1 */
  int *edge_of;            /* mesh edge of id i + 1 */
  unsigned char *kind;     /* EdgeKindBits that made it important */
} LineEdges;

/* Classify the edges of objs[0..nobj) seen by cam (the reference camera:
** vertices are projected into its pixels) into *out, on up to threads
** workers (the same result on any number). Objects without lines get no
** ids but are projected (they still occlude). Every mesh must have its
** topology built (mesh_build_edges). Free with line_edges_free. */
void line_edges_build(LineEdges *out, const LineObject *objs, int nobj, const Camera *cam,
                      int threads);
void line_edges_free(LineEdges *e);

/* Run fn(ctx, task, worker) for task 0..ntasks-1 on up to threads workers
** (the caller is one of them); tasks are handed out in order, so results
** that depend only on the task, never on the worker, are deterministic. */
void line_parallel(int ntasks, int threads, void (*fn)(void *ctx, int task, int worker), void *ctx);

#endif
