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
  /* topology, filled by mesh_build_edges() */
  int nedges;
  MeshEdge *edges;
  int (*tri_edges)[3];   /* edge index of tri edge (v0v1, v1v2, v2v0) */
} Mesh;

Mesh *mesh_create(int nverts, int ntris);      /* arrays allocated, uv NULL */
void mesh_destroy(Mesh *m);
/* Build edges and tri_edges from tri (replaces any earlier topology). */
void mesh_build_edges(Mesh *m);
/* Area-weighted vertex normals from the triangles (for meshes without any). */
void mesh_compute_normals(Mesh *m);
/* Merge vertices closer than eps (positions), remapping triangles. */
void mesh_weld(Mesh *m, double eps);

#endif
