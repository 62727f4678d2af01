/*
** Solids from 2D shapes (shape2d.h), as OpenSCAD makes them:
** linear_extrude sweeps a shape up z (turning and scaling it on the way),
** rotate_extrude sweeps it around z. Each result is a closed, consistently
** oriented polygon mesh (faces counter-clockwise seen from outside), its
** caps the shape's triangulation, holes and all; sides are quads where
** they are flat, triangle pairs where a twist or an uneven scale bends
** them. Allocated in the given arena; NULL with a reason in err on
** failure.
*/
#ifndef geom_extrude_h
#define geom_extrude_h

#include "../scene/scene.h"

/* Most vertices an extrusion may make (slices or segments times the
** shape's points): ten million, so a runaway `slices` or `$fn` is an
** error, not gigabytes. */
#define EXTRUDE_MAX_VERTS 10000000

typedef struct ExtrudeLinear {
  double height;              /* > 0 */
  int center;                 /* from -height/2 to height/2, else from 0 to height */
  double twist;               /* degrees, clockwise seen from +z (OpenSCAD's sense) */
  int slices;                 /* >= 1: layers along z */
  Vec2 scale;                 /* the top's scale (each >= 0; 0 meets at a line or point) */
} ExtrudeLinear;

/* shape swept from z0 to z0 + height: at height fraction t the shape is
** turned by -twist t degrees about z, then scaled by 1 + (scale - 1) t. */
SceneGeometry *extrude_linear(Arena *a, const SceneGeometry *shape, const ExtrudeLinear *p, char *err, size_t errlen);

/* shape's (x, y) swept around z as the (radius, z) of a profile, through
** angle degrees (counter-clockwise seen from +z, from the +x axis; 360 a
** closed ring) in segments steps. Every x must be >= 0, or every x <= 0
** (then the shape is mirrored first, as OpenSCAD does). */
SceneGeometry *extrude_rotate(Arena *a, const SceneGeometry *shape, double angle, int segments, char *err,
                              size_t errlen);

/* The signed volume a closed, outward-oriented mesh encloses (the sum
** over its faces' fan triangles of p0 . (p1 x p2) / 6). */
double extrude_mesh_volume(const SceneGeometry *g);

#endif
