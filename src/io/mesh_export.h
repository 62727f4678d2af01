/*
** Mesh export: the solids of an evaluated scene, each object as the
** closed triangle mesh CSG would combine (geom/csg.h) moved to the world,
** written as one binary STL file through Assimp's exporter (its C API).
*/
#ifndef io_mesh_export_h
#define io_mesh_export_h

#include "../scene/scene.h"

/* Write scene's 3D objects to path (through a temporary file renamed into
** place). 2D shapes and origami are left out, each with a warning at the
** object. Returns 1, or 0 after a diagnostic (a message on stderr when it
** is about the file, not the scene). */
int mesh_export_scene(const Scene *scene, const char *path);

#endif
