/*
** Scenes built directly in C for the render unit tests (no parser needed):
** a latitude-longitude sphere mesh and small helpers.
*/
#ifndef tests_render_scenes_h
#define tests_render_scenes_h

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../../src/base/mem.h"
#include "../../src/lang/diag.h"
#include "../../src/lang/eval.h"
#include "../../src/lang/parse.h"
#include "../../src/scene/scene.h"

/* A closed polygon mesh: an n x m latitude-longitude sphere of radius r
** at c (quads, triangles at the poles). */
static inline SceneGeometry *sphere_geometry(Arena *a, Vec3 c, double r, int n, int m) {
  SceneGeometry *g = arena_alloc(a, sizeof *g);
  g->kind = GEOM_MESH;
  g->nverts = 2 + n * (m - 1);
  g->verts = arena_alloc(a, sizeof *g->verts * g->nverts);
  g->verts[0] = v3(c.x, c.y, c.z - r);
  g->verts[1] = v3(c.x, c.y, c.z + r);
  for (int j = 1; j < m; j++)
    for (int i = 0; i < n; i++) {
      double th = M_PI * j / m - M_PI / 2, ph = 2 * M_PI * i / n;
      g->verts[2 + (j - 1) * n + i] = v3(c.x + r * cos(th) * cos(ph), c.y + r * cos(th) * sin(ph), c.z + r * sin(th));
    }
  g->nfaces = n * m;
  g->face_start = arena_alloc(a, sizeof *g->face_start * (g->nfaces + 1));
  g->face_index = arena_alloc(a, sizeof *g->face_index * 4 * g->nfaces);
  int k = 0, f = 0;
#define RING(j, i) (2 + ((j) - 1) * n + ((i) % n))
  for (int i = 0; i < n; i++) {   /* bottom cap, counter-clockwise seen from outside */
    g->face_start[f++] = k;
    g->face_index[k++] = 0; g->face_index[k++] = RING(1, i + 1); g->face_index[k++] = RING(1, i);
  }
  for (int j = 1; j < m - 1; j++)
    for (int i = 0; i < n; i++) {
      g->face_start[f++] = k;
      g->face_index[k++] = RING(j, i); g->face_index[k++] = RING(j, i + 1);
      g->face_index[k++] = RING(j + 1, i + 1); g->face_index[k++] = RING(j + 1, i);
    }
  for (int i = 0; i < n; i++) {
    g->face_start[f++] = k;
    g->face_index[k++] = 1; g->face_index[k++] = RING(m - 1, i); g->face_index[k++] = RING(m - 1, i + 1);
  }
#undef RING
  g->nfaces = f;
  g->face_start[f] = k;
  return g;
}

/* Evaluate scene text (the language's own defaults apply; stdlib/ is
** found from the repository root, where the unit tests run) into *s,
** scene_init'ed here; ast holds the syntax tree. Returns 1, or 0 after
** the diagnostics were printed. */
static inline int scene_from_text(Scene *s, Arena *ast, const char *text) {
  static int diag_ready;
  if (!diag_ready) { diag_init(DIAG_TEXT); diag_ready = 1; }
  size_t n = strlen(text);
  char *copy = malloc(n + 1);
  memcpy(copy, text, n + 1);
  int file = diag_add_file("test.npr", copy, n, -1, src_none());
  arena_init(ast);
  scene_init(s);
  int errors = diag_error_count();
  AstNode *prog = parse_file(file, ast);
  if (!prog || diag_error_count() > errors) return 0;
  EvalOptions eo;
  eval_options_init(&eo);
  eo.stdlib_dir = "stdlib";
  return eval_program(prog, file, ast, &eo, s) == 0;
}

#endif
