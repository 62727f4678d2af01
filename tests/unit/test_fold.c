/*
** FOLD import (src/io/fold.c): small files written for these tests under
** tests/data/fold/ (run from the repository root), and the real files of
** SUMI_SHARED/data/fold when present.
*/
#include <stdlib.h>
#include <string.h>

#include "../../src/geom/origami.h"
#include "../../src/io/fold.h"
#include "unit.h"

#define DATA "tests/data/fold/"

static Arena arena;
static char err[512];

static int read_fold(const char *name, SceneOrigami *o) {
  err[0] = 0;
  return fold_read(name, o, &arena, err, sizeof err) == 0;
}

static int has(const char *s, const char *part) { return strstr(s, part) != NULL; }

static int is_above(const SceneOrigami *o, int i, int j) {
  for (int k = 0; k < o->nabove; k++)
    if (o->above[k].upper == i && o->above[k].lower == j) return 1;
  return 0;
}

/* A crease pattern with its folded frame: faceOrders follow the sign rule
** (f over g from +z when s * sign(area of g folded) > 0). */
TEST(zfold_with_frame) {
  SceneOrigami o;
  CHECK(read_fold(DATA "zfold.fold", &o));
  CHECK_EQ_INT(o.nverts, 8);
  CHECK_EQ_INT(o.ncreases, 10);
  CHECK_EQ_INT(o.nfaces, 3);
  CHECK_EQ_INT(o.has_folded, 1);
  CHECK_EQ_INT(o.creases[8].assignment, 'V');
  CHECK_NEAR(o.verts[3].x, 3, 0);
  CHECK_NEAR(o.folded[3].x, 1, 0);
  CHECK_EQ_INT(o.nabove, 3);
  CHECK(is_above(&o, 1, 0));   /* [1, 0, +1], face 0 front up */
  CHECK(is_above(&o, 2, 0));   /* [2, 0, +1] */
  CHECK(is_above(&o, 2, 1));   /* [2, 1, -1], face 1 back up */
  CHECK(o.fold_file && has(o.fold_file, "zfold.fold"));
  int e0 = diag_error_count();
  OrigamiModel *m = origami_build(&o, 1);
  CHECK(m != NULL);
  CHECK_EQ_INT(diag_error_count(), e0);
  origami_free(m);
}

/* Only the folded state: the faces wind both ways, so the crease pattern
** is unfolded from it. */
TEST(folded_state_only) {
  SceneOrigami o;
  CHECK(read_fold(DATA "folded_only.fold", &o));
  CHECK_EQ_INT(o.has_folded, 1);
  CHECK_NEAR(o.verts[3].x, 3, 1e-12);      /* the strip unfolds to [0, 3] */
  CHECK_NEAR(o.verts[3].y, 0, 1e-12);
  CHECK_NEAR(o.verts[5].x, 2, 1e-12);
  CHECK_NEAR(o.folded[3].x, 1, 0);
  CHECK(is_above(&o, 2, 1));
  OrigamiModel *m = origami_build(&o, 1);
  CHECK(m != NULL);
  if (m) CHECK_EQ_INT(m->flipped[1], 1);
  origami_free(m);
}

/* faceOrders with no folded frame: read against the state folded from the
** crease pattern (face 1 shows its back there). */
TEST(orders_without_frame) {
  SceneOrigami o;
  CHECK(read_fold(DATA "orders_no_frame.fold", &o));
  CHECK_EQ_INT(o.has_folded, 0);
  CHECK(is_above(&o, 1, 0));
  CHECK(is_above(&o, 2, 0));
  CHECK(is_above(&o, 2, 1));
  OrigamiModel *m = origami_build(&o, 1);
  CHECK(m != NULL);
  origami_free(m);
}

/* A frame that inherits from itself: the lookup stops (FOLD_MAX_INHERIT)
** and the folded coordinates are reported missing. */
TEST(inherit_loop) {
  SceneOrigami o;
  CHECK(!read_fold(DATA "inherit_loop.fold", &o));
  CHECK(has(err, "file_frames[0].vertices_coords is missing"));
}

TEST(faces_from_edges) {
  SceneOrigami o;
  CHECK(read_fold(DATA "edges_only.fold", &o));
  CHECK_EQ_INT(o.nfaces, 0);
  OrigamiModel *m = origami_build(&o, 1);
  CHECK(m != NULL);
  if (m) CHECK_EQ_INT(m->nfaces, 4);
  origami_free(m);
}

TEST(clockwise_faces) {
  SceneOrigami o;
  CHECK(read_fold(DATA "clockwise.fold", &o));
  OrigamiModel *m = origami_build(&o, 1);
  CHECK(m != NULL);
  if (!m) return;
  CHECK_EQ_INT(m->nfaces, 2);
  for (int f = 0; f < 2; f++)
    CHECK(origami_poly_area2(m->paper, m->face_index + m->face_start[f], 4) > 0);
  CHECK_EQ_INT(m->face_index[m->face_start[1] + 0] == 2 || m->face_index[m->face_start[1] + 3] == 2, 1);
  origami_free(m);
}

TEST(xz_plane_coordinates) {
  SceneOrigami o;
  CHECK(read_fold(DATA "xz_plane.fold", &o));
  CHECK_NEAR(o.verts[2].x, 1, 0);
  CHECK_NEAR(o.verts[2].y, 1, 0);          /* z became y */
  CHECK_EQ_INT(o.has_folded, 0);
}

/* Broken files: an error naming the file and the key, never a crash. */
TEST(broken_files) {
  SceneOrigami o;
  CHECK(!read_fold(DATA "bad_json.fold", &o));
  CHECK(has(err, "bad_json.fold") && has(err, "line 1") && has(err, "JSON"));
  CHECK(!read_fold(DATA "no_coords.fold", &o));
  CHECK(has(err, "vertices_coords is missing"));
  CHECK(!read_fold(DATA "bad_edge.fold", &o));
  CHECK(has(err, "edges_vertices[1]") && has(err, "vertex 9"));
  CHECK(!read_fold(DATA "bad_assignment.fold", &o));
  CHECK(has(err, "edges_assignment[2]"));
  CHECK(!read_fold(DATA "folded_3d.fold", &o));
  CHECK(has(err, "folded_3d.fold") && has(err, "not flat"));
  CHECK(!read_fold(DATA "bad_orders.fold", &o));
  CHECK(has(err, "faceOrders[0]") && has(err, "face 5"));
  CHECK(!read_fold(DATA "no_such_file.fold", &o));
  CHECK(has(err, "no_such_file.fold") && has(err, "No such file"));
}

/* The real files, when SUMI_SHARED holds them: the shapes in the data
** README, the checks pass, and a 3D state is refused. */
TEST(shared_files) {
  const char *shared = getenv("SUMI_SHARED");
  char path[1024];
  snprintf(path, sizeof path, "%s/data/fold/crane.fold", shared ? shared : "../shared");
  FILE *f = fopen(path, "r");
  if (!f) { fprintf(stderr, "skip: %s absent\n", path); return; }
  fclose(f);
  struct { const char *name; int nv, nf, ok; } files[] = {
    {"crane.fold", 56, 59, 1}, {"square-twist.fold", 16, 9, 1},
    {"egg13-3_tessellation_state.fold", 169, 157, 1}, {"diagonal-folded.fold", 4, 2, 1},
    {"simple.fold", 0, 0, 0}};
  for (int k = 0; k < 5; k++) {
    snprintf(path, sizeof path, "%s/data/fold/%s", shared ? shared : "../shared", files[k].name);
    SceneOrigami o;
    int ok = read_fold(path, &o);
    CHECK_EQ_INT(ok, files[k].ok);
    if (!ok) {
      CHECK(has(err, files[k].name) && has(err, "3D"));
      continue;
    }
    CHECK_EQ_INT(o.nverts, files[k].nv);
    CHECK_EQ_INT(o.nfaces, files[k].nf);
    int e0 = diag_error_count();
    OrigamiModel *m = origami_build(&o, 1);
    CHECK(m != NULL);
    CHECK_EQ_INT(diag_error_count() - e0, 0);
    origami_free(m);
  }
}

int main(void) {
  diag_init(DIAG_TEXT);
  arena_init(&arena);
  RUN(zfold_with_frame);
  RUN(folded_state_only);
  RUN(orders_without_frame);
  RUN(inherit_loop);
  RUN(faces_from_edges);
  RUN(clockwise_faces);
  RUN(xz_plane_coordinates);
  RUN(broken_files);
  RUN(shared_files);
  arena_free(&arena);
  return unit_done();
}
