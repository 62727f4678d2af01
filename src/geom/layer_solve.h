/*
** The layer-order solver: the valid stackings of a flat-folded crease
** pattern's faces, from the folded positions and the crease assignments
** alone (finding one is NP-complete in general; Flat-Folder's model).
**
**   - One variable per pair of faces whose folded images overlap (share a
**     cell of the arrangement, arrangement.h): which of the two lies over
**     the other, seen from +z.
**   - Constraints: taco-taco (two folded creases along one line must nest
**     or stand apart, never interleave), taco-tortilla and the like (the
**     two faces of a crease lie on one side of a face the crease crosses),
**     tortilla-tortilla (two flat creases along one line: the sheets keep
**     their order across it), transitivity (three faces over one place
**     form no cycle; those a chain of taco-tortilla constraints already
**     implies are left out).
**   - The orders M/V creases force are fixed first and propagated; what is
**     left splits into independent components, each searched (depth
**     first, with the same propagation) and counted up to a limit.
** States are numbered in the order the search finds them: a component's
** state 0 prefers, at each choice, the lower-numbered face on top.
*/
#ifndef geom_layer_solve_h
#define geom_layer_solve_h

#include <stddef.h>

#include "../base/vec.h"

/* A folded crease pattern, as plain arrays (nothing is copied: they must
** outlive the solver). */
typedef struct LayerInput {
  int nverts;
  const Vec2 *folded;                 /* folded vertex positions */
  int nfaces;
  const unsigned char *flipped;       /* 1: the face shows its back to +z */
  int nedges;
  const int (*edge_verts)[2];
  const int (*edge_faces)[2];         /* face on the right of v0 -> v1 (paper, CCW faces), left; -1 none */
  const char *assign;                 /* 'M', 'V', 'U' (folds either way), 'F', 'B' */
} LayerInput;

enum { LAYER_TACO_TACO, LAYER_TACO_TORTILLA, LAYER_TORTILLA_TORTILLA, LAYER_TRANSITIVITY };

/* Why there is no state: the kind of the constraint that failed (or -1:
** two creases force opposite orders on one pair; -2: a component has no
** state), the faces of that constraint, and the faces and creases whose
** forced orders led to it (ascending). */
typedef struct LayerConflict {
  int kind;
  int nfaces, faces[4];
  int nchain_faces, *chain_faces;
  int nchain_edges, *chain_edges;
} LayerConflict;

typedef struct LayerStats {
  int points, segments, cells, eps_log2;
  long variables;
  long taco_taco, taco_tortilla, tortilla_tortilla, transitivity;
  long fixed;                         /* variables the creases decide */
} LayerStats;

typedef struct LayerSolver LayerSolver;

/* Build the arrangement, the variables and constraints, fix what the
** creases force, and split the rest into components. Returns NULL with a
** reason in err when the arrangement cannot be built; a solver whose
** layer_conflict() is not NULL when the creases alone leave no state. */
LayerSolver *layer_new(const LayerInput *in, char *err, size_t errlen);
void layer_free(LayerSolver *s);

const LayerConflict *layer_conflict(const LayerSolver *s);
LayerStats layer_stats(const LayerSolver *s);

/* Components left after the forced orders (each independent of the others). */
int layer_ncomponents(const LayerSolver *s);
int layer_component_vars(const LayerSolver *s, int c);
/* The faces in component c's variables, ascending, into faces (room for
** nfaces); returns the count. */
int layer_component_faces(const LayerSolver *s, int c, int *faces);

/* The number of states of component c, counting up to limit (so limit
** means "at least limit"). 0: none, and then layer_conflict() says where. */
long layer_count(LayerSolver *s, int c, long limit);

/* Set component c to its state k (0-based, in search order): returns 1, or
** 0 when it has k states or fewer. */
int layer_pick(LayerSolver *s, int c, long k);

/* The order of every overlapping pair, after picking a state of every
** component (0 is picked for a component not yet picked): calls
** out(user, upper, lower) once per pair. Returns 0 when some component has
** no state. */
int layer_orders(LayerSolver *s, void (*out)(void *user, int upper, int lower), void *user);

/* Whether faces i and j overlap in the folded state. */
int layer_overlap(const LayerSolver *s, int i, int j);

/* Check a relation against every constraint: above(user, i, j) says
** whether i lies over j (a pair with neither may go either way: a
** constraint breaks only when no way of its open pairs satisfies it).
** Returns the number of orders and constraints it breaks; the first
** broken one's faces go to *conflict (kind as above; -3: a pair ordered
** both ways). */
long layer_check(const LayerSolver *s, int (*above)(void *user, int i, int j), void *user,
                 LayerConflict *conflict);

#endif
