/*
** Flat origami geometry (Mitani, "Rendering method for flat origami", §4):
** faces of a crease pattern, the flat-folded state, and the overlap
** relation between faces (the OR matrix), with the checks `sumi check`
** runs on them.
**
** origami_build() turns an origami block as written (SceneOrigami) into an
** OrigamiModel:
**   - faces: given, or traced from the planar graph of the creases (crossing
**     creases and vertices lying on a crease are split first); every face is
**     counter-clockwise in paper coordinates (clockwise input is reversed);
**   - folded vertex positions: given, or computed by reflecting each face
**     across the M/V creases it shares with its neighbours, from the fixed
**     face outwards;
**   - the relation "face i lies over face j (toward +z)": from `above` pairs
**     or the N x N U/L/- matrix, plus the order every M/V crease implies for
**     the two faces it joins (a valley puts the neighbour on the side of a
**     face's paper normal, a mountain on the other side), plus the orders
**     implied through a third face: i over k over j at a place all three
**     cover puts i over j (a pleat's outer layers; repeated to a fixpoint).
** Diagnostics point at the source of the offending face, crease or vertex
** (the SrcRange fields of SceneOrigami; the block's own location when a
** part has none, as for FOLD imports).
*/
#ifndef geom_origami_h
#define geom_origami_h

#include <stdint.h>
#include <stdio.h>

#include "../scene/scene.h"

/* Limits: the relation is a dense N x N bit matrix (32 MB at the face
** limit), and the checks compare face pairs. */
#define ORIGAMI_MAX_FACES 16384
#define ORIGAMI_MAX_VERTS 65536
#define ORIGAMI_MAX_CREASES 200000
/* `state K` counts each component's states up to this many to find state K. */
#define ORIGAMI_STATE_LIMIT 10000

/* An affine map of the plane: x' = a[0] x + a[1] y + a[2],
**                             y' = a[3] x + a[4] y + a[5]. */
typedef struct OrigamiXf { double a[6]; } OrigamiXf;

typedef struct OrigamiModel {
  char *name;                 /* the block's name, or NULL */
  int nverts;                 /* may exceed the source's: split creases add vertices */
  Vec2 *paper;                /* paper coordinates */
  Vec2 *folded;               /* flat-folded positions (xy-plane of the block) */
  SrcRange *vert_loc;         /* where each vertex was written (or its crease) */
  int ncreases;
  OrigamiCrease *creases;     /* after splitting */
  int nfaces;
  int *face_start;            /* nfaces + 1 offsets into face_index */
  int *face_index;            /* vertex cycles, counter-clockwise on the paper */
  int *face_crease;           /* per corner k: crease of edge (k, k+1), -1 if none */
  SrcRange *face_loc;
  OrigamiXf *face_xf;         /* paper -> folded, per face */
  unsigned char *flipped;     /* 1: the face shows its back (paper's -z side) to +z */
  int ntris;
  int (*tri)[3];              /* faces triangulated (paper CCW), for raster and overlap */
  int *tri_face;
  uint64_t *above;            /* bit j of row i: face i lies over face j (seen from +z) */
  int row_words;              /* uint64 words a row of `above` */
  Vec2 fold_min, fold_max;    /* bounding box of the folded state */
  SrcRange loc;               /* the origami block */
} OrigamiModel;

/* Face i lies over face j where they overlap, seen from +z. */
static inline int origami_is_above(const OrigamiModel *m, int i, int j) {
  return (int)((m->above[(size_t)i * (size_t)m->row_words + ((unsigned)j >> 6)] >> (j & 63)) & 1u);
}

/* Build the model of one origami block. Always checked: indices, faces
** tiling the paper, folded positions that keep each face's shape, an
** antisymmetric relation that agrees with the creases, and (when folding
** from the paper) Kawasaki and Maekawa at interior vertices. With
** check != 0 also: overlapping faces with no order, orders for faces that
** do not overlap (a warning), cycles among three faces covering one place,
** and Kawasaki and Maekawa on a given folded state. Errors and warnings go to diag_report.
** Returns a malloc'd model (free with origami_free), or NULL after at
** least one error. */
OrigamiModel *origami_build(const SceneOrigami *src, int check);
void origami_free(OrigamiModel *m);

/* The same up to the folded state, with an empty relation (for the layer
** solver to fill: origami_layers.h); U creases fold. */
OrigamiModel *origami_build_folded(const SceneOrigami *src);

/* One pair of faces whose folded images overlap with positive area. */
typedef struct OrigamiOverlap { int i, j; double area; } OrigamiOverlap;

/* Every overlapping face pair (i < j), sorted by (i, j); *count is set.
** Areas are in folded units. The result is malloc'd (caller frees). */
OrigamiOverlap *origami_overlaps(const OrigamiModel *m, int *count);

/* Print every face: id, vertex cycle, centroid on the paper and folded,
** and the faces it overlaps (split into those it lies over, under, and
** any left unordered). For `sumi faces`. */
void origami_list_faces(const OrigamiModel *m, FILE *out);

/* Build every origami block of a scene with the checks on (`sumi check`):
** returns the number of blocks that failed. */
int origami_check_scene(const Scene *s);

/* `sumi faces`: build every block and list its faces (origami_list_faces),
** blocks separated by a blank line. Returns 0, or 1 when a block failed
** to build (its diagnostics are reported). */
int origami_list_scene(const Scene *s, FILE *out);

/* Reflect faces across their shared edges from face `root`, mapping
** positions `from` (one state) to `to` (the other: paper -> folded, or
** folded -> paper). Two faces sharing an edge are folded against each
** other when fold_edge says so: fold_edge(user, face_a, face_b, u, v)
** returns 1 to reflect across u-v, 0 to keep (a flat crease). Vertices of
** faces not reached keep their `from` position. xf_out (nfaces, may be
** NULL) receives each face's map. Returns the number of vertices whose
** positions disagreed between two faces by more than tol (0 when the
** pattern folds consistently); *bad_vertex is set to the first one. */
int origami_reflect(int nverts, const Vec2 *from, int nfaces, const int *face_start,
                    const int *face_index, int root,
                    int (*fold_edge)(void *user, int fa, int fb, int u, int v), void *user,
                    double tol, Vec2 *to, OrigamiXf *xf_out, int *bad_vertex);

/* Twice the signed area of polygon `idx` (n vertices) over points p. */
double origami_poly_area2(const Vec2 *p, const int *idx, int n);

#endif
