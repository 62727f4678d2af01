/*
** The layer-order solver (src/geom/arrangement.c, layer_solve.c,
** origami_layers.c) on small crease patterns whose states can be counted
** by hand, and an independent check of every state it finds.
*/
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../../src/geom/origami.h"
#include "../../src/geom/origami_layers.h"
#include "../../src/io/crease.h"
#include "../../src/io/fold.h"
#include "../../src/render/origami.h"
#include "../../src/lang/diag.h"
#include "unit.h"

/* ---- crease patterns by hand (faces traced by origami_build) ----------- */

typedef struct Pattern {
  SceneOrigami o;
  Vec2 v[64];
  OrigamiCrease c[128];
} Pattern;

static void pattern_init(Pattern *p) {
  memset(p, 0, sizeof *p);
  p->o.verts = p->v;
  p->o.creases = p->c;
  p->o.transform = m4_identity();
  p->o.style = -1;
  p->o.loc = p->o.overlap_loc = p->o.state_loc = src_none();
  p->o.overlap_auto = 1;
}

static int vert(Pattern *p, double x, double y) {
  p->v[p->o.nverts] = (Vec2){x, y};
  return p->o.nverts++;
}

static void crease(Pattern *p, int a, int b, char asg) {
  p->c[p->o.ncreases++] = (OrigamiCrease){a, b, asg, src_none()};
}

/* A strip [0, n] x [0, 1] with creases at x = 1 .. n-1 given by asg. */
static void strip(Pattern *p, int n, const char *asg) {
  pattern_init(p);
  int lo[16], hi[16];
  for (int i = 0; i <= n; i++) lo[i] = vert(p, i, 0), hi[i] = vert(p, i, 1);
  for (int i = 0; i < n; i++) crease(p, lo[i], lo[i + 1], 'B'), crease(p, hi[i], hi[i + 1], 'B');
  crease(p, lo[0], hi[0], 'B');
  crease(p, lo[n], hi[n], 'B');
  for (int i = 1; i < n; i++) crease(p, lo[i], hi[i], asg[i - 1]);
}

/* The square [0, 1]^2 with its border as B creases; returns the corners. */
static void square(Pattern *p, int corner[4]) {
  pattern_init(p);
  corner[0] = vert(p, 0, 0), corner[1] = vert(p, 1, 0), corner[2] = vert(p, 1, 1), corner[3] = vert(p, 0, 1);
}

/* The classic square twist: a diamond of half-diagonal r at the centre,
** each corner sending a ray along x and one along y to the border. The
** diamond's sides are mountains; at each corner the ray that bounds the
** 45° sector is a valley (big-little-big needs it), the other a mountain;
** `wrong` swaps the two (then no state exists). */
static void square_twist(Pattern *p, int wrong) {
  int k[4];
  square(p, k);
  double r = 0.2;
  int d[4] = {vert(p, 0.5 + r, 0.5), vert(p, 0.5, 0.5 + r), vert(p, 0.5 - r, 0.5), vert(p, 0.5, 0.5 - r)};
  /* rays: d0 down and right, d1 right and up, d2 up and left, d3 left and down */
  int e[8] = {vert(p, 0.5 + r, 0), vert(p, 1, 0.5), vert(p, 1, 0.5 + r), vert(p, 0.5, 1),
              vert(p, 0.5 - r, 1), vert(p, 0, 0.5), vert(p, 0, 0.5 - r), vert(p, 0.5, 0)};
  int ring[12] = {k[0], e[7], e[0], k[1], e[1], e[2], k[2], e[3], e[4], k[3], e[5], e[6]};
  for (int i = 0; i < 12; i++) crease(p, ring[i], ring[(i + 1) % 12], 'B');
  for (int i = 0; i < 4; i++) {
    crease(p, d[i], d[(i + 1) % 4], 'M');
    crease(p, d[i], e[2 * i], wrong ? 'M' : 'V');           /* the first ray counter-clockwise */
    crease(p, d[i], e[2 * i + 1], wrong ? 'V' : 'M');
  }
}

/* The waterbomb base: both diagonals valleys, the horizontal midline a
** mountain, all meeting at the centre. */
static void waterbomb(Pattern *p) {
  int k[4];
  square(p, k);
  int c = vert(p, 0.5, 0.5), l = vert(p, 0, 0.5), r = vert(p, 1, 0.5);
  int ring[6] = {k[0], k[1], r, k[2], k[3], l};
  for (int i = 0; i < 6; i++) crease(p, ring[i], ring[(i + 1) % 6], 'B');
  for (int i = 0; i < 4; i++) crease(p, c, k[i], 'V');
  crease(p, c, l, 'M');
  crease(p, c, r, 'M');
}

/* ---- solving ------------------------------------------------------------- */

typedef struct Solved {
  OrigamiModel *m;
  OrigamiLayers l;
  LayerSolver *s;
} Solved;

static int solve(Pattern *p, Solved *out) {
  memset(out, 0, sizeof *out);
  out->m = origami_build_folded(&p->o);
  if (!out->m) return 0;
  origami_layers_init(out->m, &out->l);
  char err[256];
  out->s = layer_new(&out->l.in, err, sizeof err);
  return out->s != NULL;
}

static void solved_free(Solved *x) {
  layer_free(x->s);
  if (x->m) origami_layers_free(&x->l);
  origami_free(x->m);
}

/* The number of states (product over the components, each up to limit). */
static long count_states(Pattern *p, long limit) {
  Solved x;
  long total = -1;
  if (solve(p, &x) && !layer_conflict(x.s)) {
    total = 1;
    for (int c = 0; c < layer_ncomponents(x.s); c++) total *= layer_count(x.s, c, limit);
  }
  solved_free(&x);
  return total;
}

/* A Z fold: the valley puts face 1 over face 0, the mountain face 2 over
** face 1, so face 2 over face 0. A letter fold (two valleys) puts face 1
** over both others, and face 2 may lie inside (between 1 and 0) or
** outside (under 0): each crease lies on the other end face's paper edge. */
TEST(strip_in_three_has_one_state) {
  Pattern p;
  strip(&p, 3, "VM");
  CHECK_EQ_INT(count_states(&p, 100), 1);
  strip(&p, 3, "VV");
  CHECK_EQ_INT(count_states(&p, 100), 2);
}

TEST(single_valley_fold) {
  Pattern p;
  int k[4];
  square(&p, k);
  for (int i = 0; i < 4; i++) crease(&p, k[i], k[(i + 1) % 4], 'B');
  crease(&p, k[0], k[2], 'V');
  CHECK_EQ_INT(count_states(&p, 100), 1);
}

/* Unassigned creases fold either way: a strip of three folds to one
** square, and any of the 3! stackings works (each crease lies on the other
** face's paper edge, so nothing blocks it); a strip of four has two creases
** on one line, whose tacos must not interleave: 16 of the 24 stackings. */
TEST(unassigned_strips) {
  Pattern p;
  strip(&p, 2, "U");
  CHECK_EQ_INT(count_states(&p, 100), 2);
  strip(&p, 3, "UU");
  CHECK_EQ_INT(count_states(&p, 100), 6);
  strip(&p, 4, "UUU");
  CHECK_EQ_INT(count_states(&p, 100), 16);
  CHECK_EQ_INT(count_states(&p, 10), 10);                  /* the limit caps the count */
}

/* Waterbomb base: the two side flaps (each a pair of small triangles held
** by the mountain midline) fold between the two big triangles, one into
** each half, and never meet: every order is forced. */
TEST(waterbomb_base) {
  Pattern p;
  waterbomb(&p);
  CHECK_EQ_INT(count_states(&p, 100), 1);
}

TEST(square_twist) {
  Pattern p;
  square_twist(&p, 0);
  CHECK_EQ_INT(count_states(&p, 100), 1);
}

/* ---- an independent check of a state ------------------------------------ */

/* Whether p lies inside face f's folded polygon, at least margin from its edges. */
static int inside_face(const OrigamiModel *m, int f, Vec2 p, double margin) {
  int s = m->face_start[f], n = m->face_start[f + 1] - s, wind = 0;
  for (int k = 0; k < n; k++) {
    Vec2 a = m->folded[m->face_index[s + k]], b = m->folded[m->face_index[s + (k + 1) % n]];
    double dx = b.x - a.x, dy = b.y - a.y, len = sqrt(dx * dx + dy * dy);
    double t = ((p.x - a.x) * dx + (p.y - a.y) * dy) / (len * len);
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    if (hypot(a.x + t * dx - p.x, a.y + t * dy - p.y) < margin) return 0;
    if ((a.y <= p.y) != (b.y <= p.y)) {
      double x = a.x + (p.y - a.y) / (b.y - a.y) * dx;
      if (x > p.x) wind++;
    }
  }
  return wind & 1;
}

/* The faces covering p, into out; returns the count. */
static int covering(const OrigamiModel *m, Vec2 p, double margin, int *out) {
  int n = 0;
  for (int f = 0; f < m->nfaces; f++)
    if (inside_face(m, f, p, margin)) out[n++] = f;
  return n;
}

/* The faces on the two sides of the crease of corner k, or -1. */
static int crease_faces(const OrigamiModel *m, int c, int *f, int *g) {
  *f = *g = -1;
  for (int x = 0; x < m->nfaces; x++)
    for (int l = m->face_start[x]; l < m->face_start[x + 1]; l++)
      if (m->face_crease[l] == c) {
        if (*f < 0) *f = x;
        else if (*f != x) *g = x;
      }
  return *g >= 0;
}

/* Two folded creases through the point q, with all four faces over the
** point q1 beside it: one crease's faces may not have exactly one of the
** other's between them (the tacos interleave). */
static int crossing_tacos(const OrigamiModel *m, int f, int g, Vec2 q, Vec2 q1, double margin) {
  int bad = 0;
  for (int c = 0; c < m->ncreases; c++) {
    int x, y;
    if (!crease_faces(m, c, &x, &y) || x == f || x == g || y == f || y == g) continue;
    Vec2 a = m->folded[m->creases[c].a], b = m->folded[m->creases[c].b];
    double dx = b.x - a.x, dy = b.y - a.y, len = hypot(dx, dy);
    double t = ((q.x - a.x) * dx + (q.y - a.y) * dy) / (len * len);
    if (t <= 0 || t >= 1 || fabs((q.x - a.x) * dy - (q.y - a.y) * dx) / len > margin) continue;
    int cover[4] = {f, g, x, y}, all = 1;
    for (int i = 0; i < 4; i++) all &= inside_face(m, cover[i], q1, margin);
    if (!all) continue;
    int lo = origami_is_above(m, f, g) ? g : f, hi = lo == f ? g : f;
    int x_in = origami_is_above(m, x, lo) && origami_is_above(m, hi, x);
    int y_in = origami_is_above(m, y, lo) && origami_is_above(m, hi, y);
    bad += x_in != y_in;
  }
  return bad;
}

/* A state is valid when, at every sample point, the faces over it are
** totally ordered; every M/V crease puts its faces as its paper normals
** say; no face lies between the two faces of a crease that runs through
** its inside; and two creases along one line do not interleave. Returns
** the number of failures. */
static int check_state(const OrigamiModel *m) {
  int bad = 0, cov[64];
  double w = m->fold_max.x - m->fold_min.x, h = m->fold_max.y - m->fold_min.y, margin = 1e-6 * (w + h);
  for (int i = 0; i <= 60; i++)                        /* total orders over sample points */
    for (int j = 0; j <= 60; j++) {
      Vec2 p = {m->fold_min.x + w * (i + 0.37) / 61.0, m->fold_min.y + h * (j + 0.61) / 61.0};
      int n = covering(m, p, margin, cov);
      for (int a = 0; a < n; a++)
        for (int b = 0; b < n; b++) {
          if (a == b) continue;
          if (origami_is_above(m, cov[a], cov[b]) == origami_is_above(m, cov[b], cov[a])) bad++;
          for (int c = 0; c < n; c++)
            if (c != a && c != b && origami_is_above(m, cov[a], cov[b]) &&
                origami_is_above(m, cov[b], cov[c]) && origami_is_above(m, cov[c], cov[a]))
              bad++;
        }
    }
  for (int f = 0; f < m->nfaces; f++)                  /* creases */
    for (int k = m->face_start[f]; k < m->face_start[f + 1]; k++) {
      int c = m->face_crease[k];
      if (c < 0) continue;
      int u = m->face_index[k], v = m->face_index[k + 1 < m->face_start[f + 1] ? k + 1 : m->face_start[f]];
      int g = -1;
      for (int g2 = 0; g2 < m->nfaces && g < 0; g2++)
        for (int l = m->face_start[g2]; g2 != f && l < m->face_start[g2 + 1]; l++)
          if (m->face_crease[l] == c) g = g2;
      char as = m->creases[c].assignment;
      if (g < 0 || (as != 'M' && as != 'V')) continue;
      /* a valley puts g on the side f's normal points to: up when f shows its front */
      int g_up = (as == 'V') == !m->flipped[f];
      if (origami_is_above(m, g, f) != g_up) bad++;
      Vec2 a = m->folded[u], b = m->folded[v], nrm = {-(b.y - a.y), b.x - a.x};
      double len = hypot(nrm.x, nrm.y), d = 1e-4 * (w + h);
      for (double t = 0.2; t < 0.9; t += 0.3) {         /* faces the crease runs through */
        Vec2 q = {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
        Vec2 q1 = {q.x + d * nrm.x / len, q.y + d * nrm.y / len}, q2 = {q.x - d * nrm.x / len, q.y - d * nrm.y / len};
        for (int x = 0; x < m->nfaces; x++) {
          if (x == f || x == g || !inside_face(m, x, q1, margin) || !inside_face(m, x, q2, margin)) continue;
          if (origami_is_above(m, x, f) != origami_is_above(m, x, g)) bad++;
        }
        bad += crossing_tacos(m, f, g, q, inside_face(m, f, q1, margin) ? q1 : q2, margin);
      }
    }
  return bad;
}

static OrigamiModel *build_state(Pattern *p, long k) {
  p->o.state = k;
  OrigamiModel *m = origami_build(&p->o, 0);
  p->o.state = 0;
  return m;
}

static int same_relation(const OrigamiModel *a, const OrigamiModel *b) {
  return a->nfaces == b->nfaces &&
         !memcmp(a->above, b->above, (size_t)a->nfaces * (size_t)a->row_words * sizeof *a->above);
}

/* Every state of every pattern passes check_state, all are different, and
** building one twice gives the same bytes. */
static void check_all_states(Pattern *p) {
  long n = count_states(p, 1000);
  CHECK(n > 0);
  if (n <= 0) return;
  OrigamiModel **ms = calloc((size_t)n, sizeof *ms);
  for (long k = 0; k < n; k++) {
    ms[k] = build_state(p, k);
    CHECK(ms[k] != NULL);
    if (!ms[k]) continue;
    CHECK_EQ_INT(check_state(ms[k]), 0);
    for (long j = 0; j < k; j++)
      if (ms[j]) CHECK(!same_relation(ms[j], ms[k]));
  }
  OrigamiModel *again = build_state(p, n - 1);
  CHECK(again && ms[n - 1] && same_relation(again, ms[n - 1]));
  origami_free(again);
  CHECK(build_state(p, n) == NULL);                         /* one past the last */
  for (long k = 0; k < n; k++) origami_free(ms[k]);
  free(ms);
}

TEST(every_state_passes_an_independent_check) {
  Pattern p;
  strip(&p, 3, "VV");
  check_all_states(&p);
  strip(&p, 4, "UUU");
  check_all_states(&p);
  waterbomb(&p);
  check_all_states(&p);
  square_twist(&p, 0);
  check_all_states(&p);
}

/* A crease pattern with no state is refused, with the constraint and the
** creases behind it. */
TEST(unsatisfiable_twist_is_refused) {
  Pattern p;
  square_twist(&p, 1);
  Solved x;
  CHECK(solve(&p, &x));
  const LayerConflict *c = x.s ? layer_conflict(x.s) : NULL;
  CHECK(c != NULL);
  if (c) CHECK(c->nchain_edges >= 2 && c->nfaces >= 2);
  solved_free(&x);
  CHECK(build_state(&p, 0) == NULL);
}

/* ORIPA's two formats (src/io/crease.c) give the same crease pattern: the
** square twist above, drawn on ORIPA's 400-unit paper. */
static long count_file(const char *path, int *nfaces) {
  Arena arena;
  arena_init(&arena);
  Pattern p;
  pattern_init(&p);
  long n = -1;
  *nfaces = 0;
  if (crease_read(path, &p.o, &arena, (char[256]){0}, 256) == 0) {
    p.o.overlap_auto = 1;
    Solved x;
    if (solve(&p, &x) && !layer_conflict(x.s)) {
      n = 1;
      for (int c = 0; c < layer_ncomponents(x.s); c++) n *= layer_count(x.s, c, 100);
      *nfaces = x.m->nfaces;
    }
    solved_free(&x);
  }
  arena_free(&arena);
  return n;
}

TEST(oripa_files) {
  int f1, f2;
  CHECK_EQ_INT(count_file("tests/data/cp/square_twist.cp", &f1), 1);
  CHECK_EQ_INT(count_file("tests/data/cp/square_twist.opx", &f2), 1);
  CHECK_EQ_INT(f1, 9);
  CHECK_EQ_INT(f2, 9);
  CHECK_EQ_INT(count_file("tests/data/cp/square_twist_wrong.opx", &f1), -1);
}

/* ---- against Flat-Folder's own state ---------------------------------------- */

static OrigamiModel *read_model(const char *path, int solve_it, Arena *arena) {
  SceneOrigami o;
  char err[256];
  if (fold_read(path, &o, arena, err, sizeof err)) return NULL;
  o.loc = o.overlap_loc = o.state_loc = src_none();
  o.overlap_auto = solve_it;
  return origami_build(&o, 0);
}

/* Folded positions moved into the unit box (the states of two solvers differ
** by where they put the fixed face) and then by symmetry k of the square
** (k & 3 quarter turns, k & 4 a mirror). */
static void normalise(OrigamiModel *m, int k) {
  double ext = fmax(m->fold_max.x - m->fold_min.x, m->fold_max.y - m->fold_min.y);
  for (int v = 0; v < m->nverts; v++) {
    Vec2 p = {(m->folded[v].x - m->fold_min.x) / ext - 0.5, (m->folded[v].y - m->fold_min.y) / ext - 0.5};
    if (k & 4) p.x = -p.x;
    for (int r = 0; r < (k & 3); r++) p = (Vec2){-p.y, p.x};
    m->folded[v] = p;
  }
  if (k & 4)                                              /* a mirror turns the stack over */
    for (int f = 0; f < m->nfaces; f++) m->flipped[f] = !m->flipped[f];
}

static Vec2 folded_centroid(const OrigamiModel *m, int f) {
  Vec2 c = {0, 0};
  int n = m->face_start[f + 1] - m->face_start[f];
  for (int k = m->face_start[f]; k < m->face_start[f + 1]; k++)
    c.x += m->folded[m->face_index[k]].x / n, c.y += m->folded[m->face_index[k]].y / n;
  return c;
}

/* Each face of b as the face of a lying at the same place the same side up,
** or -1; returns the number unmatched. */
static int match_faces(const OrigamiModel *a, const OrigamiModel *b, int *map) {
  int unmatched = 0;
  for (int g = 0; g < b->nfaces; g++) {
    Vec2 cb = folded_centroid(b, g);
    map[g] = -1;
    for (int f = 0; f < a->nfaces; f++) {
      Vec2 ca = folded_centroid(a, f);
      if (hypot(ca.x - cb.x, ca.y - cb.y) < 1e-6 && a->flipped[f] == b->flipped[g]) map[g] = f;
    }
    unmatched += map[g] < 0;
  }
  return unmatched;
}

/* The square twist's crease pattern, solved by sumi, draws the same
** face-ID buffer as the state Flat-Folder's solver exported for it
** (tests/data/cp/square_twist_ff_state.fold, from the peer's driver; its
** face ids and placement are its own, so faces are matched by where they
** lie once both are moved into the unit box), seen from its other side. */
TEST(first_state_draws_as_flat_folders) {
  Arena arena;
  arena_init(&arena);
  OrigamiModel *a = read_model("tests/data/cp/square_twist.fold", 1, &arena);
  OrigamiModel *b = read_model("tests/data/cp/square_twist_ff_state.fold", 0, &arena);
  CHECK(a && b && a->nfaces == b->nfaces);
  if (a && b && a->nfaces == b->nfaces) {
    int *map = malloc((size_t)b->nfaces * sizeof *map), k = 0, mirrored = 0;
    normalise(a, 0);
    for (; k < 8; k++) {                                    /* the symmetry that lays b on a */
      OrigamiModel *t = read_model("tests/data/cp/square_twist_ff_state.fold", 0, &arena);
      normalise(t, k);
      int ok = match_faces(a, t, map) == 0;
      origami_free(t);
      if (ok) break;
    }
    CHECK(k < 8);
    normalise(b, k);
    mirrored = (k & 4) != 0;
    /* Flat-Folder's default side (+) reads a FOLD crease pattern with M and
    ** V swapped, the paper seen from its back: its state is sumi's turned
    ** over, every order reversed (and a mirror turns it back) */
    int am = 0, av = 0, bm = 0, bv = 0;
    for (int e = 0; e < a->ncreases; e++) am += a->creases[e].assignment == 'M', av += a->creases[e].assignment == 'V';
    for (int e = 0; e < b->ncreases; e++) bm += b->creases[e].assignment == 'M', bv += b->creases[e].assignment == 'V';
    CHECK(am == bv && av == bm && am != av);
    if (!mirrored) {                                        /* the stack turned over: every order reverses */
      uint64_t *t = calloc((size_t)b->nfaces * (size_t)b->row_words, sizeof *t);
      for (int i = 0; i < b->nfaces; i++)
        for (int j = 0; j < b->nfaces; j++)
          if (origami_is_above(b, j, i)) t[(size_t)i * (size_t)b->row_words + ((unsigned)j >> 6)] |= 1ull << (j & 63);
      memcpy(b->above, t, (size_t)b->nfaces * (size_t)b->row_words * sizeof *t);
      free(t);
    }
    Mat4 c = m4_identity();                                 /* the unit box fills the view */
    c.m[0][0] = c.m[1][1] = 1.8, c.m[2][2] = -0.1;
    int w = 96, h = 96, differ = 0, covered = 0;
    int32_t *ia = malloc((size_t)(w * h) * sizeof *ia), *ib = malloc((size_t)(w * h) * sizeof *ib);
    origami_render_ids(a, &c, w, h, NULL, ia);
    origami_render_ids(b, &c, w, h, NULL, ib);
    for (int k2 = 0; k2 < w * h; k2++) {
      int mapped = ib[k2] < 0 || map[ib[k2]] < 0 ? -1 : map[ib[k2]];
      differ += ia[k2] != mapped;
      covered += ia[k2] >= 0;
    }
    CHECK(covered > w * h / 4);
    CHECK_EQ_INT(differ, 0);
    free(ia);
    free(ib);
    free(map);
  }
  origami_free(a);
  origami_free(b);
  arena_free(&arena);
}

int main(void) {
  diag_init(DIAG_SILENT);
  RUN(strip_in_three_has_one_state);
  RUN(single_valley_fold);
  RUN(unassigned_strips);
  RUN(waterbomb_base);
  RUN(square_twist);
  RUN(every_state_passes_an_independent_check);
  RUN(unsatisfiable_twist_is_refused);
  RUN(oripa_files);
  RUN(first_state_draws_as_flat_folders);
  return unit_done();
}
