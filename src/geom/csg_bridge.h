/*
** The CSG bridge: a plain C view of CGAL's corefinement booleans
** (Polygon_mesh_processing::corefine_and_compute_union, _difference,
** _intersection on a Surface_mesh with exact predicates) for closed
** triangle meshes. The implementation is C++17 in csg_bridge.cpp; no
** exception crosses this header. Every function that can fail returns 1
** on success and 0 on failure, with a one-line reason written into err
** (errlen bytes, always terminated).
**
** The caller checks that each input is closed, manifold and outward
** (csg.c does, with located messages); the bridge checks what needs CGAL:
** that no input intersects itself, and that the result is a manifold.
*/
#ifndef geom_csg_bridge_h
#define geom_csg_bridge_h

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
  SUMI_CSG_UNION,              /* everything any input encloses */
  SUMI_CSG_DIFFERENCE,         /* the first input less all the others */
  SUMI_CSG_INTERSECTION        /* what every input encloses */
} SumiCsgOp;

/* A closed triangle mesh: points packed as doubles (x, y, z), triangles
** as 3 indices each, counter-clockwise seen from outside. The arrays are
** the caller's. */
typedef struct SumiCsgMesh {
  int nverts;
  const double *xyz;           /* 3 * nverts */
  int ntris;
  const int *tri;              /* 3 * ntris */
} SumiCsgMesh;

/* A result: arrays malloc'd by the bridge, released by sumi_csg_free. */
typedef struct SumiCsgResult {
  int nverts;
  double *xyz;                 /* 3 * nverts */
  int ntris;
  int *tri;                    /* 3 * ntris, counter-clockwise seen from outside */
  int *src;                    /* ntris: the input triangle each was cut from, numbered
                                  through the inputs in order (input k's triangle t is
                                  t plus the triangles of the inputs before k) */
} SumiCsgResult;

void sumi_csg_free(SumiCsgResult *r);

/* in[0] op in[1] op ... op in[n - 1] (n >= 1), folded left, into *out
** (zeroed on failure). *bad (may be NULL) gets the input a failure is
** about (one that intersects itself), or -1 when it is about the
** operation (a result that would not be a manifold: shapes that touch
** along an edge or at a point). */
int sumi_csg_run(SumiCsgOp op, const SumiCsgMesh *in, int n, SumiCsgResult *out, int *bad, char *err,
                 size_t errlen);

#ifdef __cplusplus
}
#endif

#endif
