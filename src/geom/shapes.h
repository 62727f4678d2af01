/*
** The primitive shapes as geometry values (the builtins sphere, cube,
** cylinder, cone, torus, plane, polyhedron), and geometry moved by a
** transform. Everything is allocated in the given arena (the scene's).
**
** Round shapes are bicubic Bezier patches, so they shade with exact
** normals, keep their patch parameters as (u, v) and take `tessellate`: a
** circle is four cubic quarter arcs (off the true radius by at most
** 0.027%), and a surface of revolution is the tensor product of an arc
** around z with its profile. Flat-sided shapes are polygon meshes. Every
** surface is oriented outward (patches: dP/du x dP/dv; faces counter-
** clockwise seen from outside).
*/
#ifndef geom_shapes_h
#define geom_shapes_h

#include "../scene/scene.h"

/* The inner control points of a cubic quarter circle sit this far along
** the tangents: 4/3 (sqrt(2) - 1). */
#define SHAPE_ARC_K 0.5522847498

/* A profile segment of a surface of revolution: 4 control points
** [radius, z], swept around z in four quarter-turn patches. */
typedef struct ShapeProfile { Vec2 p[4]; } ShapeProfile;

/* The surface sweeping each profile around z (4 patches a profile).
** Normals point outward when the profile runs counter-clockwise around
** the region it bounds, drawn with radius to the right and z up. */
SceneGeometry *shape_revolve(Arena *a, const ShapeProfile *profiles, int n);
/* A sphere of radius r around the origin: 8 patches with a pole each. */
SceneGeometry *shape_sphere(Arena *a, double r);
/* OpenSCAD's cylinder: radius r1 at the bottom, r2 at the top, from z = 0
** to h (or centred on the origin), flat caps (none where a radius is 0). */
SceneGeometry *shape_cylinder(Arena *a, double h, double r1, double r2, int center);
/* A torus around z: the tube of radius r about the circle of radius R. */
SceneGeometry *shape_torus(Arena *a, double R, double r);
/* A box from the origin to size, or centred on the origin: 6 quads. */
SceneGeometry *shape_cube(Arena *a, Vec3 size, int center);
/* A square of side size in the xy-plane, centred, facing +z. */
SceneGeometry *shape_plane(Arena *a, double size);
/* The empty shape: a mesh of no faces (what a boolean leaves of nothing). */
SceneGeometry *shape_empty(Arena *a);

/* g moved by m into a copy (patches, vertices, per-corner normals; faces
** and patches turned when m mirrors, so they still face outward). A 2D
** shape's contours move by m's xy part; tilted out of the xy-plane it is
** no longer a 2D shape, only a flat mesh. */
SceneGeometry *shape_transformed(Arena *a, const SceneGeometry *g, Mat4 m);

#endif
