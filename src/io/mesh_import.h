/*
** Mesh import through Assimp's C API: OBJ, PLY, STL, glTF and the other
** formats the installed library reads, into a GEOM_MESH SceneGeometry
** (polygons kept as they are, not triangulated). Every mesh of the file is
** placed by its node transforms and merged into one; vertices at exactly
** the same position are shared, so the result is connected for
** subdivision and edge detection. Coordinates are taken as the file
** gives them (no axis conversion: a y-up model needs a rotate).
**
** Vertex numbers (for creases and corners): an OBJ file's vertices keep
** the order of its `v` lines (those no face uses are left out); other
** formats get Assimp's order, which is the order the faces first use them.
*/
#ifndef io_mesh_import_h
#define io_mesh_import_h

#include <stddef.h>

#include "../base/mem.h"
#include "../scene/scene.h"

/* Most vertices and faces one imported file may have (16 M each): far
** beyond what one frame can show, and still well inside int indices. */
#define MESH_IMPORT_MAX_VERTS (1 << 24)
#define MESH_IMPORT_MAX_FACES (1 << 24)

/* Assimp reads each file in a child process (it crashes or loops on some
** malformed files): the child gets MESH_IMPORT_TIMEOUT seconds of wall
** time and, outside sanitizer builds, MESH_IMPORT_MAX_MEMORY bytes of
** address space; a crash, a runaway or a failed allocation there is an
** error here. (fork: call it before starting threads.) */
#define MESH_IMPORT_TIMEOUT 120
#define MESH_IMPORT_MAX_MEMORY (8LL << 30)

/* Read the mesh in the file at path into *out (kind GEOM_MESH; verts,
** face_start and face_index allocated in arena, and face_uv when the file
** has texture coordinates (its first UV channel, per face corner); every
** other field zero).
** Returns 0 on success; nonzero with a one-line reason in err (errlen
** bytes; it does not repeat the path, the caller names the file) for a
** missing, unreadable or malformed file, or one without polygons.
** On success err is "" or a one-line note for a warning: faces the file
** has (for OBJ, its `f` lines) that were not imported (an empty face, or
** one with fewer than 3 distinct corners).
** (0 = success, as the evaluator's caller expects.) */
int mesh_import_file(const char *path, SceneGeometry *out, Arena *arena, char *err,
                     size_t errlen);

/* The same with the child's time limit in seconds (tests use a short one). */
int mesh_import_file_limited(const char *path, SceneGeometry *out, Arena *arena, char *err,
                             size_t errlen, int timeout_s);

/* The same read in this process, without the child: for the fuzzer, which
** must see the reader's coverage. */
int mesh_import_file_in_process(const char *path, SceneGeometry *out, Arena *arena, char *err,
                                size_t errlen);

/* Across the frames of one run: with mesh_import_cache_keep(N), the last N
** files read are kept, each with its path, identity (device, inode),
** modification time and size, and a file read again unchanged is copied
** from there instead of read by Assimp again (the same geometry and the
** same note). mesh_import_cache_clear drops them and stops keeping;
** mesh_import_cache_hits counts the reads the cache answered. */
void mesh_import_cache_keep(int entries);
void mesh_import_cache_clear(void);
long mesh_import_cache_hits(void);

#endif
