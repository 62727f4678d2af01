/*
** Subdivision surfaces: a GEOM_MESH SceneGeometry with subdiv_level > 0
** becomes a triangle Mesh refined by OpenSubdiv (through osd_bridge.h).
** The mesh's vertices are the level's points pushed to the limit surface,
** its normals the limit normals, and every edge that descends from a
** tagged crease carries that crease's sharpness in MeshEdge.sharpness, so
** the line stages draw it as a crease line.
*/
#ifndef geom_subdiv_h
#define geom_subdiv_h

#include <stddef.h>

#include "../scene/scene.h"
#include "mesh.h"
#include "osd_bridge.h"

/* Highest level subdiv() accepts: each level multiplies the faces by 4. */
#define SUBDIV_MAX_LEVEL 10
/* Most refined faces (quads or triangles) one object may reach: 4 M quads
** are 8 M triangles, about 1.5 GB through OpenSubdiv's full topology at
** the last level plus our mesh. */
#define SUBDIV_MAX_FACES (1 << 22)

/* Parse a scheme name ("catmark", "loop", "bilinear"; NULL = catmark).
** Returns 1, or 0 for an unknown name. */
int subdiv_scheme_parse(const char *name, SumiOsdScheme *out);
/* Parse a boundary name ("edge_and_corner", "edge_only", "none"; NULL =
** edge_and_corner). Returns 1, or 0 for an unknown name. */
int subdiv_boundary_parse(const char *name, SumiOsdBoundary *out);

/* How many faces refining g to its level gives (an estimate from the base
** faces, exact for quads and triangles), saturating at INT_MAX. */
long subdiv_face_count(const SceneGeometry *g);

/* Check g's subdivision settings (level, scheme, faces, creases, corners,
** the face limit) without refining: 1 when fine, else 0 and a reason in
** err. The evaluator can call this to report errors at the script. */
int subdiv_check(const SceneGeometry *g, SumiOsdBoundary boundary, char *err, size_t errlen);

/* Refine g (GEOM_MESH, subdiv_level >= 1) and triangulate the result.
** tri_face is the base polygon each triangle lies in; uv is NULL. The
** caller owns the result (mesh_destroy). NULL and a reason in err on
** failure. With subdiv_cache_keep, the cache's refinement of the same
** inputs (every one compared exactly) is handed over instead, the same
** mesh bit for bit; give it back with subdiv_mesh_done. */
Mesh *subdiv_mesh(const SceneGeometry *g, SumiOsdBoundary boundary, char *err, size_t errlen);

/* Worker threads each later refinement may use (1 at start); the result
** is the same at any count. */
void subdiv_threads(int n);

/* Across the frames of an animation: keep the refinements of the last
** `entries` inputs subdiv_mesh was asked for (each with a copy of its
** inputs), so a mesh that does not change is refined once. 0 keeps none,
** as at start. subdiv_cache_clear frees them. */
void subdiv_cache_keep(int entries);
void subdiv_cache_clear(void);
/* How many times, in this process, subdiv_mesh handed over a kept mesh. */
long subdiv_cache_hits(void);
/* Refinements `sumi render --frames` keeps (a scene's subdivided objects
** beyond that are refined again each frame). */
#define SUBDIV_CACHE_FRAMES 8
/* The caller is done with m, subdiv_mesh(g, boundary)'s result, unchanged:
** the cache keeps it for the next frame (with no cache, it is destroyed). */
void subdiv_mesh_done(const SceneGeometry *g, SumiOsdBoundary boundary, Mesh *m);

/* The same, also handing back the bridge's refinement (positions at the
** level, faces, tags) into *refined when it is not NULL; the caller frees
** it with sumi_osd_refined_free(). */
Mesh *subdiv_mesh_ex(const SceneGeometry *g, SumiOsdBoundary boundary, SumiOsdRefined *refined,
                     char *err, size_t errlen);

/* Build the bridge topology of g (arrays in scratch, freed by the caller
** with subdiv_topology_free) and the handle; 1 on success. */
typedef struct SubdivTopology {
  SumiOsdTopology topo;
  int *face_size, *crease_verts, *corner_verts;
  float *crease_sharpness, *corner_sharpness;
} SubdivTopology;
int subdiv_topology(const SceneGeometry *g, SumiOsdBoundary boundary, SubdivTopology *st,
                    char *err, size_t errlen);
void subdiv_topology_free(SubdivTopology *st);

#endif
