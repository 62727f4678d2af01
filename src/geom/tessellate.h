/*
** Tessellation: turns a SceneGeometry into a triangle Mesh (see mesh.h)
** with topology (mesh_build_edges), unit normals and per-triangle source
** faces. Triangles are counter-clockwise seen from the side their normals
** point to.
**
** Patch meshes: vertices on shared patch borders are welded, so edges
** across patches carry adjacency; tri_face is the patch index and uv the
** patch parameters (at a welded vertex, those of the first patch that
** made it); normals come from patch_normal() (exact, not averaged). Where
** patches meet at an angle (a cylinder's rim, the teapot's handle touching
** its body), corner_nrm keeps each triangle's own patch normal; it is NULL
** when every welded vertex agrees.
*/
#ifndef geom_tessellate_h
#define geom_tessellate_h

#include "../scene/scene.h"
#include "mesh.h"

/* Most segments a patch side gets (uniform n and adaptive alike): 256 gives
** 66k vertices a patch, far beyond any screen's need. */
#define TESS_MAX_SEGMENTS 256

/* An (n+1) x (n+1) grid per patch, n clamped to [1, TESS_MAX_SEGMENTS].
** The caller owns the result (mesh_destroy). Both tess_uniform and
** tess_adaptive hand a GEOM_MESH to tess_polygons. */
Mesh *tess_uniform(const SceneGeometry *g, int n);

/* Adaptive: each patch edge gets a segment count from its own control
** points only (projected by object_to_clip into a width x height image),
** so two patches that share an edge sample it alike and the surface is
** crack-free (no T-junctions); the interior is filled to the flatness
** tolerance tolerance_px (pixels) and stitched to the edges; segment
** counts are capped at TESS_MAX_SEGMENTS; a border or patch whose control
** points all lie beyond one side of the view gets 1, and a border with a
** control point behind the eye (w <= 0), but not all, a fixed 16. A NULL object_to_clip measures
** in object units instead of pixels. tolerance_px <= 0 means 0.5 px (or
** 1/1000 of the control net's size). The caller owns the result. */
Mesh *tess_adaptive(const SceneGeometry *g, const Mat4 *object_to_clip, int width, int height,
                    double tolerance_px);

/* GEOM_MESH: each polygon triangulated (ear clipping in its best-fit
** plane; convex polygons as a fan), tri_face = polygon index, vertices
** shared as given, area-weighted vertex normals (mesh_compute_normals) and,
** where faces meet at more than 45 degrees, per-corner normals
** (mesh_smooth_corners) so a cube shades flat. Polygons with fewer than 3
** valid indices are skipped; uv is NULL unless the geometry carries its own
** (face_uv, imported), which corner_uv keeps per corner across seams.
** Subdivision (subdiv_level) is not
** applied here. The caller owns the result. */
Mesh *tess_polygons(const SceneGeometry *g);

/* Whichever of the above g and the object's settings ask for. */
Mesh *tess_geometry(const SceneGeometry *g, TessKind kind, int n, double tolerance_px,
                    const Mat4 *object_to_clip, int width, int height);

#endif
