/*
** The refinement reference (`sumi refine scene.npr --compare`): how far
** our Bezier evaluation and our tessellations (uniform and adaptive) lie
** from OpenSubdiv's limit surface of the same patches (each converted to
** a B-spline net, bspline.h), and how far a subdivided mesh as we draw it
** lies from the limit surface of its control mesh. Deviations are
** measured by parameter: a point of a triangle against the limit surface
** at the same (u, v), interpolated from the triangle's corners.
*/
#ifndef geom_refine_h
#define geom_refine_h

#include <stdio.h>

#include "../render/camera.h"
#include "../scene/scene.h"
#include "mesh.h"
#include "osd_bridge.h"

/* Screen tolerance the adaptive comparison uses when an object sets none. */
#define REFINE_DEFAULT_TOLERANCE_PX 0.5
/* Refined faces of a subdivided object sampled at most (evenly strided). */
#define REFINE_MAX_SUBDIV_FACES 50000

/* Deviation statistics of one comparison. Pixel figures are 0 without a
** camera, and count only points in front of it. */
typedef struct RefineStats {
  long samples;
  double max_units, mean_units;
  double max_px, mean_px;
  int ntris;          /* triangles of the tessellation (0 for evaluation) */
  int nfaces, nfaces_sampled;   /* subdivision: refined faces, and those compared */
  double ms;          /* our side's time: tessellation or evaluation */
  double ref_ms;      /* OpenSubdiv's side: building and evaluating the reference */
} RefineStats;

/* Compare tessellation m of the patches of g (GEOM_PATCHES; m from
** tess_uniform or tess_adaptive: uv = patch parameters, tri_face = patch)
** with the limit surface. cam and object_to_world (both may be NULL) give
** the pixel figures. Returns 1, or 0 with a reason in err. */
int refine_patch_mesh(const SceneGeometry *g, const Mesh *m, const Mat4 *object_to_world,
                      const Camera *cam, RefineStats *st, char *err, size_t errlen);

/* Compare our Bezier evaluation (patch_eval) of every patch of g with the
** limit surface on an n x n grid of parameters; degenerate patches (a
** border collapsed to a point) are counted into st_degenerate, the rest
** into st. */
int refine_patch_eval(const SceneGeometry *g, int n, const Mat4 *object_to_world,
                      const Camera *cam, RefineStats *st, RefineStats *st_degenerate, char *err,
                      size_t errlen);

/* 1 when a border of p collapses to one point (the teapot's lid and bottom). */
int refine_patch_degenerate(const ScenePatch *p);

/* Subdivide g (GEOM_MESH, subdiv_level >= 1) as the renderer draws it and
** compare the triangles with the limit surface of the control mesh. */
int refine_subdiv(const SceneGeometry *g, SumiOsdBoundary boundary, const Mat4 *object_to_world,
                  const Camera *cam, RefineStats *st, char *err, size_t errlen);

/* The whole report for scene s seen through cam (may be NULL): one block
** per object with patches or subdivision, printed to out. Returns 0, or 1
** when a comparison failed (its reason printed in the report). */
int refine_compare(const Scene *s, const Camera *cam, FILE *out);

#endif
