/*
** Constructive solid geometry (OpenSCAD's union, difference and
** intersection) of closed 3D shapes: patches (tessellated), polygon
** meshes, subdivision surfaces (refined) and imported meshes, each made a
** closed triangle mesh, checked, and combined by CGAL's corefinement
** (csg_bridge.h). The result is a triangle mesh that remembers, per
** corner, the shading normal and texture coordinates of the operand
** surface it was cut from, per face the source face, and as creases the
** intersection curves where one operand's surface meets another's (the
** edges `lines` draws as creases).
*/
#ifndef geom_csg_h
#define geom_csg_h

#include "../scene/scene.h"
#include "csg_bridge.h"
#include "mesh.h"

/* Segments a patch side of a CSG operand gets without `tessellate N`:
** a sphere's volume then comes out within 0.05 %, a cube less a sphere
** within 0.2 %. (Uniform, not adaptive: the adaptive cut stitches its
** borders with triangles that lie flat along a straight border, which
** CGAL counts as the surface intersecting itself.) */
#define CSG_SEGMENTS 32

/* The closed triangle mesh operand g (a 3D shape, already in the frame
** the operation works in) stands for: patches tessellated (g->tess_n
** segments a side, else CSG_SEGMENTS), subdivision surfaces
** refined, polygons triangulated; with topology. NULL with a reason in
** err (a subdivision failure). The caller owns the mesh. */
Mesh *csg_operand_mesh(const SceneGeometry *g, char *err, size_t errlen);

/* Whether m bounds a solid: closed (every edge between two faces),
** manifold, consistently oriented and outward (positive volume). 0 with
** the first reason in err, naming a point where it fails. */
int csg_check_solid(const Mesh *m, char *err, size_t errlen);

/* g[0] op g[1] op ... op g[n - 1] (n >= 1, 3D shapes or the empty shape,
** folded left) as a triangle mesh in a. NULL with a reason in err on
** failure; *bad (may be NULL) then gets the operand the reason is about,
** or -1 when it is about the operation. */
SceneGeometry *csg_boolean(Arena *a, SumiCsgOp op, const SceneGeometry *const *g, int n, int *bad, char *err,
                           size_t errlen);

/* The signed volume a closed, outward mesh encloses. */
double csg_mesh_volume(const Mesh *m);

#endif
