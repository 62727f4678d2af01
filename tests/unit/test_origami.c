/*
** Flat origami: faces, folding, the overlap relation and its checks
** (src/geom/origami.c), and the face-ID buffer and shadings
** (src/render/origami.c), against facts from Mitani's paper.
*/
#include <stdlib.h>
#include <string.h>

#include "../../src/base/rng.h"
#include "../../src/geom/origami.h"
#include "../../src/io/fold.h"
#include "../../src/render/origami.h"
#include "unit.h"

/* ---- building blocks by hand ------------------------------------------- */

typedef struct Paper {
  SceneOrigami o;
  Vec2 v[64];
  Vec3 folded[64];
  OrigamiCrease c[128];
  int fs[33], fi[256];
  OrigamiAbove ab[32];
} Paper;

static void paper_init(Paper *p) {
  memset(p, 0, sizeof *p);
  p->o.verts = p->v;
  p->o.creases = p->c;
  p->o.face_start = p->fs;
  p->o.face_index = p->fi;
  p->o.above = p->ab;
  p->o.folded = p->folded;
  p->o.transform = m4_identity();
  p->o.style = -1;
  p->o.loc = p->o.overlap_loc = src_none();
}

static int vert(Paper *p, double x, double y) {
  p->v[p->o.nverts] = (Vec2){x, y};
  p->folded[p->o.nverts] = v3(x, y, 0);
  return p->o.nverts++;
}

static void crease(Paper *p, int a, int b, char asg) {
  p->c[p->o.ncreases++] = (OrigamiCrease){a, b, asg, src_none()};
}

static void face(Paper *p, int n, const int *v) {
  int k = p->fs[p->o.nfaces];
  for (int i = 0; i < n; i++) p->fi[k + i] = v[i];
  p->fs[++p->o.nfaces] = k + n;
}

/* A piece of paper given as its own polygon (boundary creases), folded to
** the polygon `at` (same vertex count): pieces need not touch. */
static int piece(Paper *p, int n, const double (*on_paper)[2], const double (*at)[2]) {
  int v[16];
  for (int i = 0; i < n; i++) {
    v[i] = vert(p, on_paper[i][0], on_paper[i][1]);
    p->folded[v[i]] = v3(at[i][0], at[i][1], 0);
  }
  for (int i = 0; i < n; i++) crease(p, v[i], v[(i + 1) % n], 'B');
  face(p, n, v);
  p->o.has_folded = 1;
  return p->o.nfaces - 1;
}

static void above(Paper *p, int i, int j) {
  p->ab[p->o.nabove++] = (OrigamiAbove){i, j, src_none()};
}

/* A strip [0,3] x [0,1] with a valley at x = 1 and a mountain at x = 2:
** faces are traced (left to right: 0, 1, 2), folding gives a Z. */
static void zfold(Paper *p) {
  paper_init(p);
  for (int i = 0; i <= 3; i++) vert(p, i, 0);
  for (int i = 3; i >= 0; i--) vert(p, i, 1);                /* 4:(3,1) 5:(2,1) 6:(1,1) 7:(0,1) */
  int ring[8] = {0, 1, 2, 3, 4, 5, 6, 7};
  for (int i = 0; i < 8; i++) crease(p, ring[i], ring[(i + 1) % 8], 'B');
  crease(p, 1, 6, 'V');
  crease(p, 2, 5, 'M');
}

/* An orthographic view of [x0, x1] x [y0, y1] filling a w x h buffer (+y up). */
static Mat4 view_box(double x0, double y0, double x1, double y1) {
  Mat4 m = m4_identity();
  m.m[0][0] = 2 / (x1 - x0), m.m[0][3] = -(x0 + x1) / (x1 - x0);
  m.m[1][1] = 2 / (y1 - y0), m.m[1][3] = -(y0 + y1) / (y1 - y0);
  m.m[2][2] = -0.1;
  return m;
}

static int errors_of(Paper *p, int check, OrigamiModel **out) {
  int e0 = diag_error_count();
  OrigamiModel *m = origami_build(&p->o, check);
  if (out) *out = m;
  else origami_free(m);
  return diag_error_count() - e0;
}

/* ---- faces and folding -------------------------------------------------- */

TEST(zfold_faces_and_fold) {
  Paper p;
  zfold(&p);
  above(&p, 2, 0);
  OrigamiModel *m;
  CHECK_EQ_INT(errors_of(&p, 1, &m), 0);
  if (!m) return;
  CHECK_EQ_INT(m->nfaces, 3);
  int want[3][4] = {{0, 1, 6, 7}, {1, 2, 5, 6}, {2, 3, 4, 5}};
  for (int f = 0; f < 3; f++)
    for (int k = 0; k < 4; k++) CHECK_EQ_INT(m->face_index[m->face_start[f] + k], want[f][k]);
  /* everything lands on [0,1] x [0,1]; the middle face shows its back */
  CHECK_NEAR(m->folded[2].x, 0, 1e-12);
  CHECK_NEAR(m->folded[3].x, 1, 1e-12);
  CHECK_EQ_INT(m->flipped[0], 0);
  CHECK_EQ_INT(m->flipped[1], 1);
  CHECK_EQ_INT(m->flipped[2], 0);
  origami_free(m);
}

/* The Z fold's OR matrix is unique: the valley puts 1 over 0, the mountain
** 2 over 1, and 2 over 0 is the only order that fits. */
TEST(zfold_unique_matrix) {
  Paper p;
  zfold(&p);
  const char *rows[3] = {"-LL", "U-L", "UU-"};
  p.o.overlap = rows;
  p.o.noverlap = 3;
  OrigamiModel *m;
  CHECK_EQ_INT(errors_of(&p, 1, &m), 0);
  if (!m) return;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      char c = origami_is_above(m, i, j) ? 'U' : origami_is_above(m, j, i) ? 'L' : '-';
      CHECK_EQ_INT(c, rows[i][j]);
    }
  origami_free(m);
  /* the other order for 0 and 2 contradicts the creases through face 1? no:
  ** it is the creases' own pairs that pin it; flipping 1 over 0 must fail */
  const char *bad[3] = {"-UL", "L-L", "UU-"};
  p.o.overlap = bad;
  CHECK(errors_of(&p, 1, NULL) > 0);
}

/* With the creases' orders alone, 2 over 0 follows: face 1 lies between
** them at a place all three cover. The same matrix results. */
TEST(zfold_order_inferred) {
  Paper p;
  zfold(&p);
  OrigamiModel *m;
  CHECK_EQ_INT(errors_of(&p, 1, &m), 0);
  if (!m) return;
  CHECK(origami_is_above(m, 2, 0));
  CHECK(!origami_is_above(m, 0, 2));
  origami_free(m);
}

/* Two loose pieces that overlap, with nothing to order them. */
TEST(missing_order_is_reported) {
  Paper p;
  paper_init(&p);
  const double a[4][2] = {{0, 0}, {2, 0}, {2, 2}, {0, 2}}, b[4][2] = {{1, 1}, {3, 1}, {3, 3}, {1, 3}};
  double pb[4][2];
  for (int i = 0; i < 4; i++) pb[i][0] = b[i][0] + 10, pb[i][1] = b[i][1];
  piece(&p, 4, a, a);
  piece(&p, 4, pb, b);
  CHECK_EQ_INT(errors_of(&p, 1, NULL), 1);
  CHECK_EQ_INT(errors_of(&p, 0, NULL), 0);                   /* render builds skip the check */
  above(&p, 1, 0);
  CHECK_EQ_INT(errors_of(&p, 1, NULL), 0);
}

/* 0 over 2 closes a cycle with the creases' 2 over 1 over 0, at a place
** all three cover: reported by the check. */
TEST(cycle_at_one_place) {
  Paper p;
  zfold(&p);
  above(&p, 0, 2);
  CHECK_EQ_INT(errors_of(&p, 1, NULL), 1);
}

TEST(matrix_not_antisymmetric) {
  Paper p;
  zfold(&p);
  const char *rows[3] = {"-LL", "U-L", "UL-"};               /* 2 over 0 but also 0 over... */
  p.o.overlap = rows;
  p.o.noverlap = 3;
  CHECK(errors_of(&p, 0, NULL) >= 1);
  const char *short_rows[2] = {"-L", "U-"};
  p.o.overlap = short_rows;
  p.o.noverlap = 2;
  CHECK_EQ_INT(errors_of(&p, 0, NULL), 1);
}

TEST(above_contradiction_and_range) {
  Paper p;
  zfold(&p);
  above(&p, 2, 0);
  above(&p, 0, 2);
  CHECK(errors_of(&p, 0, NULL) >= 1);
  zfold(&p);
  above(&p, 2, 7);
  CHECK_EQ_INT(errors_of(&p, 0, NULL), 1);
  zfold(&p);
  above(&p, 0, 1);                                           /* the valley says 1 over 0 */
  above(&p, 2, 0);
  CHECK_EQ_INT(errors_of(&p, 0, NULL), 1);
}

TEST(order_for_faces_apart_is_a_warning) {
  Paper p;
  paper_init(&p);
  const double a[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, b[4][2] = {{5, 0}, {6, 0}, {6, 1}, {5, 1}};
  piece(&p, 4, a, a);
  piece(&p, 4, b, b);
  above(&p, 0, 1);
  int w0 = diag_warning_count();
  CHECK_EQ_INT(errors_of(&p, 1, NULL), 0);
  CHECK_EQ_INT(diag_warning_count() - w0, 1);
}

/* Two diagonals of a square cross: split at the centre into 4 faces. */
TEST(crossing_creases_are_split) {
  Paper p;
  paper_init(&p);
  int v0 = vert(&p, 0, 0), v1 = vert(&p, 2, 0), v2 = vert(&p, 2, 2), v3_ = vert(&p, 0, 2);
  crease(&p, v0, v1, 'B'), crease(&p, v1, v2, 'B'), crease(&p, v2, v3_, 'B'), crease(&p, v3_, v0, 'B');
  crease(&p, v0, v2, 'F');
  crease(&p, v1, v3_, 'F');
  OrigamiModel *m;
  CHECK_EQ_INT(errors_of(&p, 1, &m), 0);
  if (!m) return;
  CHECK_EQ_INT(m->nverts, 5);
  CHECK_NEAR(m->paper[4].x, 1, 1e-12);
  CHECK_NEAR(m->paper[4].y, 1, 1e-12);
  CHECK_EQ_INT(m->nfaces, 4);
  CHECK_EQ_INT(m->ncreases, 8);
  origami_free(m);
}

/* A waterbomb-like vertex that breaks Kawasaki, and one that breaks Maekawa. */
TEST(kawasaki_and_maekawa) {
  Paper p;
  paper_init(&p);
  int c = vert(&p, 0, 0);
  double ang[4] = {0, 80, 180, 270};                         /* sectors 80, 100, 90, 90 */
  int r[4];
  for (int i = 0; i < 4; i++) r[i] = vert(&p, cos(ang[i] * M_PI / 180), sin(ang[i] * M_PI / 180));
  for (int i = 0; i < 4; i++) crease(&p, r[i], r[(i + 1) % 4], 'B');
  crease(&p, c, r[0], 'M'), crease(&p, c, r[1], 'M'), crease(&p, c, r[2], 'M'), crease(&p, c, r[3], 'V');
  CHECK_EQ_INT(errors_of(&p, 1, NULL), 1);                   /* Kawasaki: 80 + 180 vs 100 + 90 */
  p.c[p.o.ncreases - 1].assignment = 'M';                    /* all M: Maekawa too */
  CHECK_EQ_INT(errors_of(&p, 1, NULL), 2);
  /* a flat-foldable vertex: sectors 90 each, 3 M + 1 V */
  paper_init(&p);
  c = vert(&p, 0, 0);
  for (int i = 0; i < 4; i++) r[i] = vert(&p, cos(i * M_PI / 2), sin(i * M_PI / 2));
  for (int i = 0; i < 4; i++) crease(&p, r[i], r[(i + 1) % 4], 'B');
  crease(&p, c, r[0], 'M'), crease(&p, c, r[1], 'M'), crease(&p, c, r[2], 'M'), crease(&p, c, r[3], 'V');
  OrigamiModel *m;
  errors_of(&p, 0, &m);
  CHECK(m != NULL);
  origami_free(m);
}

/* ORIGAMI_MAX_VERTS: one vertex more is an error naming the limit. */
TEST(vertex_limit) {
  Paper p;
  zfold(&p);
  Vec2 *many = xcalloc((size_t)ORIGAMI_MAX_VERTS + 1, sizeof *many);
  memcpy(many, p.v, 8 * sizeof *many);
  p.o.verts = many;
  p.o.nverts = ORIGAMI_MAX_VERTS + 1;
  CHECK_EQ_INT(errors_of(&p, 0, NULL), 1);
  free(many);
}

TEST(folded_shape_is_checked) {
  Paper p;
  paper_init(&p);
  const double a[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, b[4][2] = {{0, 0}, {2, 0}, {2, 1}, {0, 1}};
  piece(&p, 4, a, b);                                        /* stretched: not a fold */
  CHECK_EQ_INT(errors_of(&p, 0, NULL), 1);
}

/* ---- face-ID buffer ----------------------------------------------------- */

/* Three strips overlapping in a cycle (no point covered by all three):
** A bottom, B right, C an L on the left and top. */
static void three_cycle(Paper *p) {
  paper_init(p);
  const double A[4][2] = {{0, 0}, {3, 0}, {3, 1}, {0, 1}};
  const double B[4][2] = {{2, 0}, {3, 0}, {3, 3}, {2, 3}};
  const double C[6][2] = {{0, 0}, {1, 0}, {1, 2}, {3, 2}, {3, 3}, {0, 3}};
  double pa[6][2];
  for (int i = 0; i < 4; i++) pa[i][0] = A[i][0], pa[i][1] = A[i][1];
  piece(p, 4, pa, A);
  for (int i = 0; i < 4; i++) pa[i][0] = B[i][0] + 10, pa[i][1] = B[i][1];
  piece(p, 4, pa, B);
  for (int i = 0; i < 6; i++) pa[i][0] = C[i][0] + 20, pa[i][1] = C[i][1];
  piece(p, 6, pa, C);
  above(p, 0, 1);
  above(p, 1, 2);
  above(p, 2, 0);
}

static int32_t id_at(const int32_t *ids, int w, int h, double x, double y) {
  int px = (int)(x / 3 * w), py = (int)((1 - y / 3) * h);
  return ids[py * w + px];
}

TEST(three_face_cycle) {
  Paper p;
  three_cycle(&p);
  OrigamiModel *m;
  CHECK_EQ_INT(errors_of(&p, 1, &m), 0);
  if (!m) return;
  int w = 60, h = 60;
  int32_t *ids = xmalloc((size_t)w * h * sizeof *ids);
  Mat4 c = view_box(0, 0, 3, 3);
  origami_render_ids(m, &c, w, h, NULL, ids);
  CHECK_EQ_INT(id_at(ids, w, h, 2.5, 0.5), 0);               /* A over B */
  CHECK_EQ_INT(id_at(ids, w, h, 2.5, 2.5), 1);               /* B over C */
  CHECK_EQ_INT(id_at(ids, w, h, 0.5, 0.5), 2);               /* C over A */
  CHECK_EQ_INT(id_at(ids, w, h, 1.5, 0.5), 0);
  CHECK_EQ_INT(id_at(ids, w, h, 1.5, 1.5), -1);              /* the hole in the middle */
  int order[3] = {2, 1, 0};                                  /* reversed drawing order */
  int32_t *ids2 = xmalloc((size_t)w * h * sizeof *ids2);
  origami_render_ids(m, &c, w, h, order, ids2);
  CHECK(memcmp(ids, ids2, (size_t)w * h * sizeof *ids) == 0);
  /* seen from below, every overlap turns the other way */
  Mat4 flip = m4_mul(c, m4_scale(v3(-1, 1, -1)));
  Mat4 back = m4_mul(flip, m4_translate(v3(-3, 0, 0)));
  origami_render_ids(m, &back, w, h, NULL, ids2);
  CHECK_EQ_INT(ids2[(int)(0.5 * h) * w + (int)(0.5 / 3 * w)], 1);   /* (2.5, 2.5) mirrored */
  free(ids2);
  free(ids);
  origami_free(m);
}

/* Any drawing order gives the same buffer (§5.1). */
static void check_shuffles(const OrigamiModel *m, int w, int h) {
  Mat4 c = view_box(m->fold_min.x - 0.05, m->fold_min.y - 0.05, m->fold_max.x + 0.05, m->fold_max.y + 0.05);
  int32_t *ref = xmalloc((size_t)w * h * sizeof *ref), *ids = xmalloc((size_t)w * h * sizeof *ids);
  int *order = xmalloc((size_t)m->nfaces * sizeof *order);
  origami_render_ids(m, &c, w, h, NULL, ref);
  Rng rng;
  rng_seed(&rng, 7, 1);
  for (int round = 0; round < 12; round++) {
    for (int i = 0; i < m->nfaces; i++) order[i] = i;
    for (int i = m->nfaces - 1; i > 0; i--) {
      int j = (int)(rng_next(&rng) % (uint32_t)(i + 1)), t = order[i];
      order[i] = order[j], order[j] = t;
    }
    origami_render_ids(m, &c, w, h, order, ids);
    long diff = 0;
    for (long k = 0; k < (long)w * h; k++) diff += ids[k] != ref[k];
    CHECK_EQ_INT(diff, 0);
  }
  free(order);
  free(ids);
  free(ref);
}

TEST(shuffle_order_independent) {
  Paper p;
  zfold(&p);
  above(&p, 2, 0);
  OrigamiModel *m;
  errors_of(&p, 0, &m);
  CHECK(m != NULL);
  if (m) check_shuffles(m, 64, 64), origami_free(m);
  three_cycle(&p);
  errors_of(&p, 0, &m);
  CHECK(m != NULL);
  if (m) check_shuffles(m, 64, 64), origami_free(m);
  /* real data when it is there: the egg tessellation (cyclic) and the crane */
  const char *shared = getenv("SUMI_SHARED");
  const char *names[2] = {"egg13-3_tessellation_state.fold", "crane.fold"};
  for (int k = 0; k < 2; k++) {
    char path[1024];
    snprintf(path, sizeof path, "%s/data/fold/%s", shared ? shared : "../shared", names[k]);
    FILE *f = fopen(path, "r");
    if (!f) { fprintf(stderr, "skip: %s absent\n", path); continue; }
    fclose(f);
    Arena a;
    arena_init(&a);
    SceneOrigami o;
    char err[256];
    CHECK(fold_read(path, &o, &a, err, sizeof err) == 0);
    m = origami_build(&o, 1);
    CHECK(m != NULL);
    if (m) check_shuffles(m, 200, 200), origami_free(m);
    arena_free(&a);
  }
}

/* ---- shadings ------------------------------------------------------------ */

static float to_display(float v) { return v <= 0.0031308f ? v * 12.92f : 1.055f * powf(v, 1 / 2.4f) - 0.055f; }

/* B = (M - V + 2) / 4 per face corner, M and V from that face's contour,
** swapped on a face showing its back. */
TEST(illustration_corner_brightness) {
  Paper p;
  zfold(&p);
  above(&p, 2, 0);
  OrigamiModel *m;
  errors_of(&p, 0, &m);
  if (!m) { CHECK(m != NULL); return; }
  /* face 0 [0 1 6 7]: corner 1 touches the valley: B = (0 - 1 + 2) / 4 */
  CHECK_NEAR(origami_corner_brightness(m, 0, 1, 0), 0.25, 1e-12);
  CHECK_NEAR(origami_corner_brightness(m, 0, 0, 0), 0.5, 1e-12);
  /* face 1 [1 2 5 6] shows its back: its valley reads as a mountain, its
  ** mountain as a valley */
  CHECK_NEAR(origami_corner_brightness(m, 1, 0, 0), 0.75, 1e-12);   /* vertex 1: V -> M */
  CHECK_NEAR(origami_corner_brightness(m, 1, 1, 0), 0.25, 1e-12);   /* vertex 2: M -> V */
  CHECK_NEAR(origami_corner_brightness(m, 1, 0, 1), 0.25, 1e-12);   /* seen from below */
  /* the rendered colour at face 0's corner (1, 0)... covered; at (0, 0),
  ** the upper-left corner's opposite: B' = min(1, wa B + wb R + wc) with R
  ** = 1 at the lower-left? The box's upper-left is (0, 1): R(0,0) = 1/sqrt2.
  ** Face 0 is hidden there by 2 and 1; face 2 [2 3 4 5] folds onto it
  ** unflipped: its corner 2 (at (0, 0) folded) has the mountain: B = 0.75. */
  int w = 200, h = 200;
  float *rgba = xcalloc((size_t)w * h * 4, sizeof *rgba);
  SceneStyle st;
  memset(&st, 0, sizeof st);
  st.shade.kind = SHADE_ORIGAMI;
  st.shade.origami_mode = 1;
  Mat4 c = view_box(0, 0, 1, 1);
  OrigamiTarget t = {.width = w, .height = h, .rgba = rgba, .face_id = NULL, .depth = NULL, .pixel_scale = 1};
  CHECK_EQ_INT(origami_render(m, &st, &c, NULL, &t), w * h);
  float *px = rgba + ((size_t)(h - 1) * w + 0) * 4;         /* pixel at (0, 0) */
  double want = fmin(1, 0.675 * 0.75 + 0.225 * (1 / sqrt(2.0)) + 0.15);
  CHECK_NEAR(to_display(px[0]), want, 0.01);
  CHECK_NEAR(to_display(px[2]), want * 0.95, 0.01);
  free(rgba);
  origami_free(m);
}

/* The illustration colour of a face of one piece of paper (a pentagon,
** boundary creases), its corners listed from corner `start` on, rendered
** at 96 x 96 into rgba. */
static void render_piece(int start, float *rgba) {
  static const double pent[5][2] = {{0, 0}, {2, 0}, {2.4, 1.2}, {1, 2}, {-0.3, 1.4}};
  double ring[5][2];
  for (int i = 0; i < 5; i++) {
    ring[i][0] = pent[(start + i) % 5][0];
    ring[i][1] = pent[(start + i) % 5][1];
  }
  Paper p;
  paper_init(&p);
  piece(&p, 5, (const double(*)[2])ring, (const double(*)[2])ring);
  OrigamiModel *m;
  errors_of(&p, 0, &m);
  if (!m) { CHECK(m != NULL); return; }
  SceneStyle st;
  memset(&st, 0, sizeof st);
  st.shade.kind = SHADE_ORIGAMI;
  st.shade.origami_mode = 1;
  Mat4 c = view_box(-0.5, -0.2, 2.6, 2.2);
  OrigamiTarget t = {.width = 96, .height = 96, .rgba = rgba, .face_id = NULL, .depth = NULL, .pixel_scale = 1};
  origami_render(m, &st, &c, NULL, &t);
  origami_free(m);
}

/* The colour interpolated across a face does not depend on the corner
** its list starts at (a fan of triangles from the first corner made it
** depend: up to 11/255 on a square): mean value coordinates over the
** polygon. */
TEST(illustration_independent_of_first_corner) {
  float *a = xcalloc(96 * 96 * 4, sizeof *a), *b = xcalloc(96 * 96 * 4, sizeof *b);
  render_piece(0, a);
  double worst = 0;
  int covered = 0;
  for (int start = 1; start < 5; start++) {
    memset(b, 0, 96 * 96 * 4 * sizeof *b);
    render_piece(start, b);
    for (int i = 0; i < 96 * 96; i++) {
      covered += start == 1 && a[i * 4 + 3] > 0;
      for (int k = 0; k < 3; k++) worst = fmax(worst, fabs(to_display(a[i * 4 + k]) - to_display(b[i * 4 + k])));
    }
  }
  CHECK(covered > 96 * 96 / 3);   /* the face is there */
  CHECK(worst < 0.5 / 255);
  if (!(worst < 0.5 / 255)) fprintf(stderr, "  largest difference %.2f / 255\n", worst * 255);
  free(a);
  free(b);
}

/* I = 1 - s/S: 1 on the uncovered top face, and on the lower face far from
** the upper one; below 1 near the upper face's edge, as the disk count. */
TEST(pseudo_shading) {
  Paper p;
  paper_init(&p);
  const double A[4][2] = {{0, 0}, {4, 0}, {4, 4}, {0, 4}}, B[4][2] = {{1, 1}, {2, 1}, {2, 2}, {1, 2}};
  double pb[4][2];
  piece(&p, 4, A, A);
  for (int i = 0; i < 4; i++) pb[i][0] = B[i][0] + 10, pb[i][1] = B[i][1];
  piece(&p, 4, pb, B);
  above(&p, 1, 0);
  OrigamiModel *m;
  errors_of(&p, 1, &m);
  if (!m) { CHECK(m != NULL); return; }
  int w = 80, h = 80;
  float *ill = xcalloc((size_t)w * h * 4, sizeof *ill), *sh = xcalloc((size_t)w * h * 4, sizeof *sh);
  int32_t *ids = xmalloc((size_t)w * h * sizeof *ids);
  SceneStyle st;
  memset(&st, 0, sizeof st);
  st.shade.kind = SHADE_ORIGAMI;
  st.shade.origami_mode = 1;
  st.shade.origami_radius = 6;
  Mat4 c = view_box(0, 0, 4, 4);
  OrigamiTarget t = {.width = w, .height = h, .rgba = ill, .face_id = ids, .depth = NULL, .pixel_scale = 1};
  origami_render(m, &st, &c, NULL, &t);
  st.shade.origami_mode = 2;
  t.rgba = sh;
  origami_render(m, &st, &c, NULL, &t);
  int disk = 0;
  for (int dy = -6; dy <= 6; dy++) disk += 2 * (int)floor(sqrt(36.0 - dy * dy) + 1e-9) + 1;
  int checked_dark = 0;
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      size_t q = (size_t)y * w + x;
      double ratio = to_display(sh[q * 4 + 1]) / to_display(ill[q * 4 + 1]);
      if (ids[q] == 1) { CHECK_NEAR(ratio, 1, 1e-3); continue; }   /* the top face */
      int s = 0;                                             /* brute force: O(r^2) */
      for (int dy = -6; dy <= 6; dy++)
        for (int dx = -6; dx <= 6; dx++) {
          if (dx * dx + dy * dy > 36 || x + dx < 0 || x + dx >= w || y + dy < 0 || y + dy >= h) continue;
          s += ids[(size_t)(y + dy) * w + x + dx] == 1;
        }
      CHECK_NEAR(ratio, 1 - (double)s / disk, 2e-3);
      if (s > disk / 4) checked_dark++;
    }
  CHECK(checked_dark > 0);
  free(ids);
  free(sh);
  free(ill);
  origami_free(m);
}

/* m drawn in line mode into a new w x h RGBA buffer viewed by c (free it). */
static float *line_mode(const OrigamiModel *m, Mat4 c, int w, int h) {
  float *rgba = xcalloc((size_t)w * h * 4, sizeof *rgba);
  SceneStyle st;
  memset(&st, 0, sizeof st);
  st.shade.kind = SHADE_ORIGAMI;
  st.shade.origami_mode = 0;
  OrigamiTarget t = {.width = w, .height = h, .rgba = rgba, .face_id = NULL, .depth = NULL, .pixel_scale = 1};
  origami_render(m, &st, &c, NULL, &t);
  return rgba;
}

TEST(line_mode_marks_face_changes) {
  Paper p;
  three_cycle(&p);
  OrigamiModel *m;
  errors_of(&p, 0, &m);
  if (!m) { CHECK(m != NULL); return; }
  int w = 60, h = 60;
  float *rgba = line_mode(m, view_box(0, 0, 3, 3), w, h);
  /* x = 2 (A over B, A's edge at y = 1 ... B's left edge at x = 2) */
  float *edge = rgba + ((size_t)(h * 5 / 6) * w + w * 2 / 3) * 4;   /* (2, 0.5): B's left edge under A? no: A on top */
  float *inside = rgba + ((size_t)(h * 5 / 6) * w + w / 2) * 4;     /* (1.5, 0.5): inside A */
  float *boundary = rgba + ((size_t)(h * 5 / 6) * w + w / 3) * 4;   /* (1, 0.5): C's edge, C on top */
  CHECK(inside[0] > 0.8f);
  CHECK(edge[0] > 0.8f);                                     /* hidden edge: no line */
  CHECK(boundary[0] < 0.1f || boundary[-4] < 0.1f);          /* visible edge: a line */
  free(rgba);
  origami_free(m);
}

/* A flat ("F") crease folds nothing, so the line mode does not draw it: a
** 2 x 2 square folded in half along a mountain at y = 1 (two layers) and
** split at x = 1 by an F crease through both shows its outline (the right
** edge, x = 2, is drawn) but no line at x = 1. */
TEST(flat_crease_is_no_fold) {
  Paper p;
  paper_init(&p);
  int v[8] = {vert(&p, 0, 0), vert(&p, 1, 0), vert(&p, 2, 0), vert(&p, 2, 1), vert(&p, 2, 2),
              vert(&p, 1, 2), vert(&p, 0, 2), vert(&p, 0, 1)};
  for (int i = 0; i < 8; i++) crease(&p, v[i], v[(i + 1) % 8], 'B');
  crease(&p, v[1], v[5], 'F');   /* x = 1 */
  crease(&p, v[7], v[3], 'M');   /* y = 1 */
  OrigamiModel *m;
  errors_of(&p, 0, &m);
  if (!m) { CHECK(m != NULL); return; }
  int w = 80, h = 80;
  float *rgba = line_mode(m, view_box(-0.5, -0.5, 2.5, 2.5), w, h);   /* x = 1 at column 40, 2 at 66.7 */
  int mid = 0, right = 0;   /* dark pixels about x = 1 and x = 2, rows inside the folded half */
  for (int y = h * 2 / 3 + 3; y < h * 5 / 6 - 3; y++)
    for (int dx = -3; dx <= 3; dx++) {
      const float *a = rgba + ((size_t)y * w + 40 + dx) * 4, *b = rgba + ((size_t)y * w + 66 + dx) * 4;
      mid += a[3] > 0.5f && a[0] < 0.1f;
      right += b[3] > 0.5f && b[0] < 0.1f;
    }
  CHECK_EQ_INT(mid, 0);
  CHECK(right > 10);
  free(rgba);
  origami_free(m);
}

/* Ink samples of row y in [x0, x1) of a w-wide RGBA buffer (opaque, dark). */
static int ink_in_row(const float *rgba, int w, int y, int x0, int x1) {
  int n = 0;
  for (int x = x0; x < x1; x++) {
    const float *o = rgba + ((size_t)y * w + x) * 4;
    n += o[3] > 0.99f && o[0] < 0.1f;
  }
  return n;
}

/* A line is as wide on the paper's outline as between two faces, at any
** sample scale and line width, when a depth buffer is given (a frame with
** or without meshes behind the paper): two squares side by side, [0, 1]
** and [1, 2], drawn with lines at pixel_scale N. The line's outer half, off
** the paper, is shown where the paper it outlines is in front of what lies
** there, however far the widened line reaches (it once looked one sample
** around only, so the outer half shrank to one sample). With a mesh in
** front of everything, no line shows at all. */
TEST(outline_as_wide_as_inner_lines) {
  Paper p;
  paper_init(&p);
  double a[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, b[4][2] = {{1, 0}, {2, 0}, {2, 1}, {1, 1}};
  piece(&p, 4, a, a);
  piece(&p, 4, b, b);
  OrigamiModel *m;
  errors_of(&p, 0, &m);
  if (!m) { CHECK(m != NULL); return; }
  SceneStyle st;
  memset(&st, 0, sizeof st);
  st.shade.kind = SHADE_ORIGAMI;
  st.shade.origami_mode = 0;                                 /* line mode: paper colour and lines */
  st.lines.present = 1, st.lines.kinds = 1, st.lines.opacity = 1;
  Mat4 c = view_box(-1, -1, 3, 2);                           /* 4 x 3 units, 10 pixels a unit */
  for (int N = 1; N <= 4; N++)
    for (int lw = 1; lw <= 3; lw++) {
      int w = 40 * N, h = 30 * N, y = h / 2, unit = 10 * N;
      float behind[3] = {INFINITY, 0.9f, 0.1f};              /* nothing, a mesh behind, one in front */
      for (int k = 0; k < 3; k++) {
        float *rgba = xcalloc((size_t)w * h * 4, sizeof *rgba), *depth = xmalloc((size_t)w * h * sizeof *depth);
        for (int i = 0; i < w * h; i++) depth[i] = behind[k];
        st.lines.width = lw;
        OrigamiTarget t = {.width = w, .height = h, .rgba = rgba, .face_id = NULL, .depth = depth, .pixel_scale = N};
        origami_render(m, &st, &c, NULL, &t);
        int outer = ink_in_row(rgba, w, y, unit / 2, unit * 3 / 2);        /* about x = 0 */
        int inner = ink_in_row(rgba, w, y, unit * 3 / 2, unit * 5 / 2);    /* about x = 1 */
        int right = ink_in_row(rgba, w, y, unit * 5 / 2, unit * 7 / 2);    /* about x = 2 */
        if (k < 2) {
          CHECK(inner >= lw * N);
          CHECK_EQ_INT(outer, inner);
          CHECK_EQ_INT(right, inner);
        } else {
          CHECK_EQ_INT(outer + inner + right, 0);
        }
        free(depth);
        free(rgba);
      }
    }
  origami_free(m);
}

/* The texture shows on faces with the paper's front up, mapped over the
** paper's box: the Z fold's top face (2, front up) takes the right third
** of a two-colour image, a face showing its back keeps the plain colour. */
TEST(texture_on_the_front) {
  Paper p;
  zfold(&p);
  OrigamiModel *m;
  errors_of(&p, 0, &m);
  if (!m) { CHECK(m != NULL); return; }
  Image *tex = image_create(3, 1, 3);                        /* left third blue, the rest red */
  float px[9] = {0, 0, 1, 1, 0, 0, 1, 0, 0};
  memcpy(tex->data, px, sizeof px);
  int w = 20, h = 20;
  float *rgba = xcalloc((size_t)w * h * 4, sizeof *rgba);
  SceneStyle st;
  memset(&st, 0, sizeof st);
  st.shade.kind = SHADE_ORIGAMI;
  st.shade.origami_mode = 0;                                 /* flat colour: the texture alone */
  Mat4 c = view_box(0, 0, 1, 1);
  OrigamiTarget t = {.width = w, .height = h, .rgba = rgba, .face_id = NULL, .depth = NULL, .pixel_scale = 1};
  origami_render(m, &st, &c, tex, &t);
  float *mid = rgba + ((size_t)(h / 2) * w + w / 2) * 4;
  CHECK(mid[0] > 0.9f && mid[2] < 0.1f);                     /* red: face 2 on top */
  /* seen from below, face 0 (front up, so its back shows) is on top: plain */
  Mat4 below = m4_mul(m4_mul(c, m4_scale(v3(-1, 1, -1))), m4_translate(v3(-1, 0, 0)));
  origami_render(m, &st, &below, tex, &t);
  CHECK(mid[0] > 0.9f && mid[2] > 0.8f && mid[2] < 0.95f);   /* (1, 1, 0.95) display */
  free(rgba);
  image_destroy(tex);
  origami_free(m);
}

/* The renderer's entry: every block of a scene, its own transform and
** style; a texture that cannot be read is reported, the block still drawn. */
TEST(draw_scene) {
  Paper p;
  zfold(&p);
  p.o.transform = m4_translate(v3(1, 0, 0));                /* the fold lands on [1, 2] x [0, 1] */
  Scene sc;
  scene_init(&sc);
  SceneStyle st = scene_default_style();
  st.shade.kind = SHADE_ORIGAMI;
  st.shade.origami_mode = 0;
  sc.norigami = 1;
  sc.origami = &p.o;
  sc.nstyles = 1;
  sc.styles = &st;
  p.o.style = 0;
  int w = 40, h = 20;
  float *rgba = xcalloc((size_t)w * h * 4, sizeof *rgba);
  int32_t *ids = xmalloc((size_t)w * h * sizeof *ids);
  for (int k = 0; k < w * h; k++) ids[k] = -1;
  Mat4 c = view_box(0, 0, 2, 1);
  OrigamiTarget t = {.width = w, .height = h, .rgba = rgba, .face_id = ids, .depth = NULL, .pixel_scale = 1};
  CHECK_EQ_INT(origami_draw_scene(&sc, &c, &t), 1);
  CHECK_EQ_INT(ids[10 * w + 5], -1);                         /* x = 0.25: empty */
  CHECK_EQ_INT(ids[10 * w + 30], 2);                         /* x = 1.5: the top face */
  CHECK(rgba[(10 * w + 5) * 4 + 3] == 0);
  st.shade.origami_texture = "no-such-texture.png";
  int e0 = diag_error_count();
  CHECK_EQ_INT(origami_draw_scene(&sc, &c, &t), 0);
  CHECK_EQ_INT(diag_error_count() - e0, 1);
  sc.norigami = 0, sc.nstyles = 0, sc.origami = NULL, sc.styles = NULL;
  scene_free(&sc);
  free(ids);
  free(rgba);
}

/* The face-ID buffer's overwrite rule (§5.1), against an oracle that never
** draws: at each pixel centre well inside the faces that cover it, the
** buffer holds the one face over all the others there (for this viewer),
** whatever order the faces are drawn in. */
static int covers(const OrigamiModel *m, int f, double x, double y, int *edge) {
  for (int t = 0; t < m->ntris; t++) {
    if (m->tri_face[t] != f) continue;
    Vec2 a = m->folded[m->tri[t][0]], b = m->folded[m->tri[t][1]], c = m->folded[m->tri[t][2]];
    double d = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (d == 0) continue;
    double u = ((b.x - x) * (c.y - y) - (b.y - y) * (c.x - x)) / d;
    double v = ((c.x - x) * (a.y - y) - (c.y - y) * (a.x - x)) / d;
    double w = 1 - u - v, lo = fmin(u, fmin(v, w));
    if (fabs(lo) < 1e-3) *edge = 1;                          /* too near an edge to judge */
    if (lo > 0) return 1;
  }
  return 0;
}

static void check_overwrite_rule(const OrigamiModel *m, int from_below) {
  int w = 48, h = 48;
  double x0 = m->fold_min.x - 0.1, y0 = m->fold_min.y - 0.1, x1 = m->fold_max.x + 0.1, y1 = m->fold_max.y + 0.1;
  Mat4 c = view_box(x0, y0, x1, y1);
  if (from_below) c = m4_mul(m4_mul(c, m4_scale(v3(-1, 1, -1))), m4_translate(v3(-(x0 + x1), 0, 0)));
  int32_t *ids = xmalloc((size_t)w * h * sizeof *ids);
  int *order = xmalloc((size_t)m->nfaces * sizeof *order);
  long judged = 0;
  for (int round = 0; round < 2; round++) {                  /* drawn first to last, then last to first */
    for (int i = 0; i < m->nfaces; i++) order[i] = round ? m->nfaces - 1 - i : i;
    origami_render_ids(m, &c, w, h, order, ids);
    for (int py = 0; py < h; py++)
      for (int px = 0; px < w; px++) {
        double x = x0 + (px + 0.5) / w * (x1 - x0), y = y1 - (py + 0.5) / h * (y1 - y0);
        if (from_below) x = x0 + x1 - x;
        int edge = 0, want = -1, n = 0;
        for (int f = 0; f < m->nfaces; f++)
          if (covers(m, f, x, y, &edge)) {
            n++;
            int top = 1;
            for (int g = 0; g < m->nfaces && top; g++)
              if (g != f && covers(m, g, x, y, &edge))
                top = from_below ? origami_is_above(m, g, f) : origami_is_above(m, f, g);
            if (top) want = f;
          }
        if (edge || (n > 0 && want < 0)) continue;
        judged++;
        CHECK_EQ_INT(ids[py * w + px], want);
      }
  }
  CHECK(judged > w * h / 2);
  free(order);
  free(ids);
}

TEST(face_id_overwrite_rule) {
  Paper p;
  zfold(&p);
  above(&p, 2, 0);
  OrigamiModel *m;
  errors_of(&p, 0, &m);
  if (!m) { CHECK(m != NULL); return; }
  check_overwrite_rule(m, 0);
  check_overwrite_rule(m, 1);
  origami_free(m);
  three_cycle(&p);
  errors_of(&p, 0, &m);
  if (!m) { CHECK(m != NULL); return; }
  check_overwrite_rule(m, 0);
  origami_free(m);
}

/* Colour reaches the picture through sRGB, not a 2.2 gamma: a mid-grey
** `color` (sRGB code 128) and a mid-grey texel both come out as code 128. */
TEST(mid_grey_stays_mid_grey) {
  Paper p;
  zfold(&p);
  OrigamiModel *m;
  errors_of(&p, 0, &m);
  if (!m) { CHECK(m != NULL); return; }
  float grey = image_srgb8_to_linear(128);
  int w = 20, h = 20;
  float *rgba = xcalloc((size_t)w * h * 4, sizeof *rgba);
  SceneStyle st;
  memset(&st, 0, sizeof st);
  st.shade.kind = SHADE_ORIGAMI;
  st.shade.origami_mode = 0;                                 /* line mode: the colour alone */
  st.shade.origami_color = (Color){grey, grey, grey, 1};
  Mat4 c = view_box(0, 0, 1, 1);
  OrigamiTarget t = {.width = w, .height = h, .rgba = rgba, .face_id = NULL, .depth = NULL, .pixel_scale = 1};
  origami_render(m, &st, &c, NULL, &t);
  float *mid = rgba + ((size_t)(h / 2) * w + w / 2 + 2) * 4;
  CHECK_NEAR(mid[0], grey, 1e-5);
  CHECK_EQ_INT(image_linear_to_srgb8(mid[1]), 128);
  Image *tex = image_create(1, 1, 3);                        /* a mid-grey texel */
  tex->data[0] = tex->data[1] = tex->data[2] = grey;
  origami_render(m, &st, &c, tex, &t);
  CHECK_NEAR(mid[0], grey, 1e-5);
  CHECK_EQ_INT(image_linear_to_srgb8(mid[2]), 128);
  image_destroy(tex);
  free(rgba);
  origami_free(m);
}

int main(void) {
  diag_init(DIAG_TEXT);
  RUN(zfold_faces_and_fold);
  RUN(zfold_unique_matrix);
  RUN(zfold_order_inferred);
  RUN(missing_order_is_reported);
  RUN(cycle_at_one_place);
  RUN(matrix_not_antisymmetric);
  RUN(above_contradiction_and_range);
  RUN(order_for_faces_apart_is_a_warning);
  RUN(crossing_creases_are_split);
  RUN(kawasaki_and_maekawa);
  RUN(vertex_limit);
  RUN(folded_shape_is_checked);
  RUN(three_face_cycle);
  RUN(shuffle_order_independent);
  RUN(illustration_corner_brightness);
  RUN(illustration_independent_of_first_corner);
  RUN(pseudo_shading);
  RUN(line_mode_marks_face_changes);
  RUN(flat_crease_is_no_fold);
  RUN(outline_as_wide_as_inner_lines);
  RUN(texture_on_the_front);
  RUN(draw_scene);
  RUN(face_id_overwrite_rule);
  RUN(mid_grey_stays_mid_grey);
  return unit_done();
}
