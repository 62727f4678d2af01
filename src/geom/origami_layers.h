/*
** The layer-order solver (layer_solve.h) on an origami model: the model's
** face edges as the solver's edges, with the faces on their two sides, and
** the state it picks back into the model's overlap relation and crease
** assignments.
*/
#ifndef geom_origami_layers_h
#define geom_origami_layers_h

#include <stdio.h>

#include "layer_solve.h"
#include "origami.h"

/* The solver's input for a folded model: every face edge once (the creases
** in their order, then any paper edge with no crease), as (lower vertex,
** higher vertex) with the face on its right and on its left. */
typedef struct OrigamiLayers {
  LayerInput in;
  int (*edge_verts)[2];
  int (*edge_faces)[2];
  char *assign;
  int *edge_crease;           /* the model's crease of each edge, or -1 */
} OrigamiLayers;

void origami_layers_init(const OrigamiModel *m, OrigamiLayers *out);
void origami_layers_free(OrigamiLayers *l);

/* Report why there is no state (diag_error at the model's block, notes at
** the creases whose orders lead to it, at most a few), as "no valid layer
** order". */
void origami_layers_report(const OrigamiModel *m, const OrigamiLayers *l, const LayerConflict *c);

/* Put the solver's picked state into m: the `above` relation, and M or V
** for every U crease (from the order of its two faces). Returns 0 when
** some component has no state (reported). */
int origami_layers_apply(OrigamiModel *m, const OrigamiLayers *l, LayerSolver *s);

/* Pick state k of the whole pattern: k in mixed radix over the
** components' counts (component 0 the fastest digit), each counted up to
** limit. Returns 1, or 0 when there are k states or fewer (*total gets
** their number, capped per component at limit, or -1 when past LONG_MAX). */
int origami_layers_pick(LayerSolver *s, long k, long limit, double *total);

/* `sumi fold`: print the pattern's sizes and its components (faces,
** variables and, with count, states up to limit each) to out. Returns 0,
** or 1 when a component has no state (reported). */
int origami_layers_print(FILE *out, const OrigamiModel *m, const OrigamiLayers *l, LayerSolver *s,
                         int count, long limit);

/* The picked state's orders as [upper, lower] pairs (malloc'd, *n set). */
int (*origami_layers_orders(LayerSolver *s, long *n))[2];

#endif
