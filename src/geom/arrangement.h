/*
** The planar arrangement of a flat-folded state's edges: the folded edges
** cut the plane into cells, and each cell is covered by the same set of
** faces everywhere inside it. The layer-order solver (layer_solve.h)
** builds its variables and constraints on this.
**
** Folded positions carry rounding (and real files carry drawing error), so
** points closer than eps merge, a point within eps of a line lies on it,
** and edges within eps of one line share it. eps is the shortest edge over
** a power of two, the coarsest of 2^3 .. 2^27 at which the number of
** merged points stays the same for three steps in a row (the count a file
** means is the one that does not change as eps shrinks).
*/
#ifndef geom_arrangement_h
#define geom_arrangement_h

#include <stddef.h>

#include "../base/vec.h"

typedef struct Arrangement {
  double eps;
  int eps_log2;               /* eps = shortest edge / 2^eps_log2 */
  int npoints;
  Vec2 *point;
  int *vert_point;            /* input vertex -> point */
  int nsegs;
  int (*seg_point)[2];
  int *seg_edge_start;        /* nsegs + 1 offsets into seg_edge */
  int *seg_edge;              /* input edges lying along each segment */
  int (*seg_cell)[2];         /* cell on the left of point 0 -> 1, on the right; -1 outside */
  int ncells;
  int *cell_face_start;       /* ncells + 1 offsets into cell_face */
  int *cell_face;             /* faces covering each cell, ascending */
  int *cell_parent;           /* the cell whose face set this one's was derived from, or -1 */
  int *face_cell_start;       /* nfaces + 1 offsets into face_cell */
  int *face_cell;             /* cells each face covers, ascending */
} Arrangement;

/* Build the arrangement of edges edge_verts (nedges pairs of vertex ids
** into pos) whose sides are the faces edge_faces (-1 where none), with
** nfaces faces in all. Returns 0, or 1 with a reason in err (a state that
** does not make one consistent arrangement at any eps). */
int arrangement_build(int nverts, const Vec2 *pos, int nedges, const int (*edge_verts)[2],
                      const int (*edge_faces)[2], int nfaces, Arrangement *out, char *err,
                      size_t errlen);
void arrangement_free(Arrangement *a);

#endif
