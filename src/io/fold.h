/*
** FOLD import (spec 1.0-1.2, edemaine/fold doc/spec.md): a crease pattern
** and its flat-folded state read into a SceneOrigami.
**
** Read: vertices_coords, edges_vertices, edges_assignment, faces_vertices,
** file_frames (frame i + 1, with frame_inherit / frame_parent) and
** faceOrders. Everything else is ignored, malformed or not.
**   - The folded state is the first frame whose frame_classes hold
**     "foldedForm". A file with one frame is taken as folded when its faces
**     wind both ways (frame_classes are only hints); the crease pattern is
**     then recovered by unfolding across the folded creases.
**   - 3D coordinates are accepted when they lie in one plane (Origami
**     Simulator writes crease patterns in the XZ plane); a folded frame
**     that is not flat is refused.
**   - faceOrders [f, g, s] become `above` pairs: seen from +z, f lies over
**     g exactly when s * sign(signed area of g folded) > 0.
**   - faces_vertices may be missing (origami_build traces the faces from
**     the edges; face ids are then its own) or wind clockwise. When given,
**     face ids are the faces_vertices indices.
*/
#ifndef io_fold_h
#define io_fold_h

#include <stddef.h>

#include "../base/mem.h"
#include "../scene/scene.h"

/* Read the FOLD file at path into *out; every array is allocated from
** arena, and every location is src_none() (the caller sets out->loc, name,
** transform and style: they come from the script). Returns 0 on success
** (as mesh_import does); nonzero on failure with a message naming the file
** and the offending key in err (at most errlen bytes), e.g.
**   "x.fold: edges_vertices[3]: vertex 12 does not exist (4 vertices)". */
int fold_read(const char *path, SceneOrigami *out, Arena *arena, char *err, size_t errlen);

/* A flat-folded state as FOLD 1.1 (what Flat-Folder's "state" export
** holds): vertices_coords are the folded positions, frame_classes
** ["foldedForm"], and faceOrders [f, g, s] for each overlapping pair with
** f over g seen from +z (s = +1 when g shows its front to +z, else -1).
** Written to a temporary name and renamed. Returns 0, or nonzero with a
** message in err. */
typedef struct FoldState {
  const char *title;
  int nverts;
  const Vec2 *coords;
  int nedges;
  const int (*edge_verts)[2];
  const char *assign;
  int nfaces;
  const int *face_start, *face_index;
  const unsigned char *flipped;
  long norders;
  const int (*orders)[2];        /* [upper, lower] */
} FoldState;

int fold_write_state(const char *path, const FoldState *st, char *err, size_t errlen);

#endif
