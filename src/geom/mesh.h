/*
** Triangle meshes with shared vertices and edge-face adjacency: the form
** every geometry takes after the prepare stage (tessellated patches,
** imported and subdivided meshes), and what the rasterizer and the line
** stages read.
*/
#ifndef geom_mesh_h
#define geom_mesh_h

#include "../base/vec.h"

/* An undirected edge between two vertices, with the (at most two) faces
** on either side; f[1] = -1 on a boundary. An edge shared by more than two
** triangles (non-manifold) keeps the first two and sets nonmanifold. */
typedef struct MeshEdge {
  int v[2];          /* v[0] < v[1] */
  int f[2];          /* adjacent triangles, -1 if none */
  float sharpness;   /* crease sharpness tagged by the source (subdiv), 0 = none */
  unsigned char nonmanifold;
} MeshEdge;

typedef struct Mesh {
  int nverts;
  Vec3 *pos;          /* object space */
  Vec3 *nrm;          /* unit vertex normals (never NaN) */
  Vec2 *uv;           /* patch parameters or texture coordinates; may be NULL */
  int ntris;
  int (*tri)[3];      /* counter-clockwise seen from the side the normal points to */
  int *tri_face;      /* per triangle: the source face (patch index, polygon index) */
  /* Per-corner normals where a vertex sits on a crease (a cube's corner, a
  ** cylinder's rim, where two patches meet at an angle): corner k of
  ** triangle t shades with corner_nrm[t][k] instead of nrm[tri[t][k]].
  ** NULL when every corner may use its vertex normal. Unit, never NaN. */
  Vec3 (*corner_nrm)[3];
  /* Per-corner texture coordinates where a welded vertex joins faces whose
  ** parameters differ there (the shared border of two patches, a UV seam):
  ** corner k of triangle t reads corner_uv[t][k] instead of uv[tri[t][k]].
  ** NULL when every corner may use its vertex's uv. */
  Vec2 (*corner_uv)[3];
  /* topology, filled by mesh_build_edges() */
  int nedges;
  MeshEdge *edges;
  int (*tri_edges)[3];   /* edge index of tri edge (v0v1, v1v2, v2v0) */
  /* What later stages work out from the mesh alone and keep with it, so
  ** that a mesh kept across frames (a refinement the subdivision cache
  ** lends each frame) is not worked over again: freed with the mesh, and
  ** dropped when its topology is rebuilt. */
  struct MeshDerived *derived;
  unsigned char keeps_derived;   /* set by whoever keeps the mesh for later frames: without
                                    it, nothing is kept with it (peak memory) */
} Mesh;

/* One stage's data kept with a mesh, found by the stage's tag (the
** address of a static of its own). */
typedef struct MeshDerived {
  const void *tag;
  void *data;
  void (*free_data)(void *data);
  struct MeshDerived *next;
} MeshDerived;

Mesh *mesh_create(int nverts, int ntris);      /* arrays allocated, uv and corner_nrm NULL */
/* The same with pos, nrm, tri and tri_face not zeroed, for a caller that
** fills every entry (a million-triangle mesh's clearing is 2 % of its
** subdivision). */
Mesh *mesh_alloc(int nverts, int ntris);
void mesh_destroy(Mesh *m);
/* Build edges and tri_edges from tri (replaces any earlier topology). */
void mesh_build_edges(Mesh *m);
/* The data kept with m under tag, or NULL. */
void *mesh_derived(const Mesh *m, const void *tag);
/* Keep data with m under tag (replacing and freeing any there), freed by
** free_data with the mesh, when m keeps_derived: returns 1. Otherwise
** returns 0 and data stays the caller's. */
int mesh_derived_set(Mesh *m, const void *tag, void *data, void (*free_data)(void *data));
/* Free everything kept with m. */
void mesh_derived_clear(Mesh *m);
/* Area-weighted vertex normals from the triangles (for meshes without any). */
void mesh_compute_normals(Mesh *m);
/* The texture coordinates of corner k of triangle t (m->uv not NULL). */
static inline Vec2 mesh_corner_uv(const Mesh *m, int t, int k) {
  return m->corner_uv ? m->corner_uv[t][k] : m->uv[m->tri[t][k]];
}
/* The normal corner k of triangle t shades with: corner_nrm when there is
** one, else the vertex normal. */
static inline Vec3 mesh_corner_normal(const Mesh *m, int t, int k) {
  return m->corner_nrm ? m->corner_nrm[t][k] : m->nrm[m->tri[t][k]];
}
/* Smoothing groups for a polygon mesh: each corner's normal averages (by
** area) only the triangles around its vertex that meet the corner's own
** triangle at less than max_angle degrees, so faces meeting at a sharper
** angle shade flat. Fills corner_nrm (freed again when no corner differs
** from its vertex normal); nrm stays the plain area-weighted normal. */
void mesh_smooth_corners(Mesh *m, double max_angle);
/* Merge vertices closer than eps (positions), remapping triangles. Each
** vertex merges into the first earlier one within eps (so the result does
** not depend on anything but the order); kept vertices keep their order,
** normal and uv. Triangles left with a repeated corner are dropped, and
** topology, if it was built, is rebuilt. corner_nrm, if there is one,
** follows the triangles, and is freed (NULL) when no corner differs from
** its vertex normal any more. eps = 0 merges equal positions. So: set
** corner_nrm to each corner's own normal before welding to keep creases. */
void mesh_weld(Mesh *m, double eps);
/* The same, but only vertices with mark[v] != 0 take part (the rest are
** never merged), e.g. the border vertices of tessellated patches. */
void mesh_weld_marked(Mesh *m, double eps, const unsigned char *mark);
/* mesh_weld_marked keeping creases: the same as setting corner_nrm to
** each corner's own normal and then welding (any corner_nrm m has is
** dropped first), only cheaper, as the per-corner array is made only when
** some corner's own normal differs from its vertex's after the weld. */
void mesh_weld_creased(Mesh *m, double eps, const unsigned char *mark);

#endif
