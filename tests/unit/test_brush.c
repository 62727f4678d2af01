/*
** Unit tests of the Chinese-painting lines (Yeh, 003 ch. 2-4): endpoint
** culling and its bisection, 2-pixel linking and stroke direction, the
** width profile, the B-spline path, the brush's pressure, weights, dry
** brush and deposits, and determinism at any thread count.
*/
#include <stdlib.h>
#include <string.h>

#include "../../src/base/mem.h"
#include "../../src/render/brush.h"
#include "../../src/render/edgeref.h"
#include "../../src/render/lines.h"
#include "../../src/render/silhouette.h"
#include "unit.h"

/* ---- fixtures -------------------------------------------------------------- */

static Camera camera_at(Vec3 eye, Vec3 at, Vec3 up, int ortho, double fov_or_h, int w, int h) {
  SceneCamera sc;
  memset(&sc, 0, sizeof sc);
  sc.present = 1;
  sc.kind = ortho ? CAMERA_ORTHO : CAMERA_PERSPECTIVE;
  sc.position = eye;
  sc.look_at = at;
  sc.up = up;
  sc.fov = fov_or_h;
  sc.ortho_height = fov_or_h;
  Camera c;
  const char *why = NULL;
  if (!camera_setup(&c, &sc, w, h, v3(-1, -1, -1), v3(1, 1, 1), 0, &why)) {
    fprintf(stderr, "camera: %s\n", why);
    abort();
  }
  return c;
}

/* Lines as a style with `stroke brush` gets them (the schema's defaults). */
static SceneLines brush_lines(unsigned kinds) {
  SceneLines l = scene_default_style().lines;
  l.kinds = kinds;
  l.stroke = STROKE_BRUSH;
  l.min_length = 0;
  return l;
}

static LineObject object_of(Mesh *m, const SceneLines *ls, int id) {
  LineObject o;
  memset(&o, 0, sizeof o);
  o.mesh = m;
  o.object_to_world = m4_identity();
  o.lines = ls;
  o.id = id;
  return o;
}

/* A quad p0 p1 p2 p3 (counter-clockwise) as two triangles. */
static Mesh *make_quad(Vec3 p0, Vec3 p1, Vec3 p2, Vec3 p3) {
  Mesh *m = mesh_create(4, 2);
  m->pos[0] = p0; m->pos[1] = p1; m->pos[2] = p2; m->pos[3] = p3;
  int t0[3] = {0, 1, 2}, t1[3] = {0, 2, 3};
  memcpy(m->tri[0], t0, sizeof t0);
  memcpy(m->tri[1], t1, sizeof t1);
  mesh_compute_normals(m);
  mesh_build_edges(m);
  return m;
}

/* A UV sphere of radius r about the origin, nu around, nv pole to pole. */
static Mesh *make_sphere(double r, int nu, int nv) {
  int south = nu * (nv - 1) + 1;
  Mesh *m = mesh_create(south + 1, 2 * nu * (nv - 1));
  int v = 0, t = 0;
  m->pos[v++] = v3(0, 0, r);
  for (int j = 1; j < nv; j++)
    for (int i = 0; i < nu; i++) {
      double th = M_PI * j / nv, ph = 2 * M_PI * i / nu;
      m->pos[v++] = v3(r * sin(th) * cos(ph), r * sin(th) * sin(ph), r * cos(th));
    }
  m->pos[south] = v3(0, 0, -r);
  for (int i = 0; i < nu; i++) {
    int i1 = (i + 1) % nu;
    m->tri[t][0] = 0; m->tri[t][1] = 1 + i; m->tri[t][2] = 1 + i1; t++;
    for (int j = 1; j + 1 < nv; j++) {
      int a = 1 + (j - 1) * nu + i, b = 1 + (j - 1) * nu + i1, c = a + nu, d = b + nu;
      m->tri[t][0] = a; m->tri[t][1] = c; m->tri[t][2] = d; t++;
      m->tri[t][0] = a; m->tri[t][1] = d; m->tri[t][2] = b; t++;
    }
    int a = 1 + (nv - 2) * nu + i, b = 1 + (nv - 2) * nu + i1;
    m->tri[t][0] = a; m->tri[t][1] = south; m->tri[t][2] = b; t++;
  }
  mesh_compute_normals(m);
  mesh_build_edges(m);
  return m;
}

/* Points along a polyline of n control points from (x0, y0), dx apart. */
static float *line_points(int n, float x0, float y0, float dx, float dy) {
  float *p = xmalloc((size_t)n * 2 * sizeof *p);
  for (int i = 0; i < n; i++) { p[2 * i] = x0 + dx * i; p[2 * i + 1] = y0 + dy * i; }
  return p;
}

/* ---- width profile (ch. 3.4) ---------------------------------------------- */

/* Fig. 3.5: 9 control points, width_step 2, MAX_WIDTH 7. */
TEST(width_table_nine_points) {
  static const double want[9] = {0, 2, 4, 6, 7, 6, 4, 2, 0};
  for (int i = 0; i < 9; i++) CHECK_NEAR(brush_width_at(i, 9, 2, 7), want[i], 0);
  static const double even[8] = {0, 2, 4, 6, 6, 4, 2, 0};   /* symmetric for an even count too */
  for (int i = 0; i < 8; i++) CHECK_NEAR(brush_width_at(i, 8, 2, 7), even[i], 0);
  CHECK_NEAR(brush_width_at(0, 2, 2, 7), 0, 0);
  CHECK_NEAR(brush_width_at(50, 101, 3, 7), 7, 0);   /* the cap holds over a long stroke */
}

/* ---- culling (ch. 2.5) ----------------------------------------------------- */

/* A strip at z = 0 (its long boundary edges run from x = -1 to 1) under an
** occluder at z = 0.5 over x >= 0, seen from above, 50 pixels a unit: x = 0
** is pixel 100. Returns the pieces of the strip's long edges. */
static int strip_pieces(int cull_steps, SilPiece *out, int *whole, int *cut) {
  Mesh *strip = make_quad(v3(-1, -0.2, 0), v3(1, -0.2, 0), v3(1, 0.2, 0), v3(-1, 0.2, 0));
  Mesh *occ = make_quad(v3(0, -1, 0.5), v3(3, -1, 0.5), v3(3, 1, 0.5), v3(0, 1, 0.5));
  SceneLines ls = brush_lines(EDGE_BOUNDARY);
  ls.cull_steps = cull_steps;
  LineObject o[2] = {object_of(strip, &ls, 0), object_of(occ, NULL, 1)};
  Camera cam = camera_at(v3(0, 0, 10), v3(0, 0, 0), v3(0, 1, 0), 1, 2, 200, 100);
  LineEdges e;
  line_edges_build(&e, o, 2, &cam, 1);
  LineRef ref;
  CHECK(line_ref_build(&ref, &e, o, 200, 100, 1));
  SilPieces ps;
  sil_cull(&ps, &ref, &e);
  int n = 0;
  for (int i = 0; i < ps.n; i++) {
    const SilPiece *p = &ps.p[i];
    if (fabsf(p->y0 - p->y1) < 0.5f && fabsf(p->x0 - p->x1) > 1) out[n++] = *p;   /* the long ones */
  }
  *whole = ps.whole;
  *cut = ps.cut;
  sil_pieces_free(&ps);
  line_ref_free(&ref);
  line_edges_free(&e);
  mesh_destroy(strip);
  mesh_destroy(occ);
  return n;
}

TEST(bisection_keeps_the_visible_half) {
  SilPiece p[8];
  int whole, cut;
  int n = strip_pieces(10, p, &whole, &cut);
  CHECK_EQ_INT(n, 2);
  CHECK_EQ_INT(cut, 2);      /* the two long edges */
  CHECK_EQ_INT(whole, 1);    /* the short one at x = -1 (the one at x = 1 is hidden) */
  for (int i = 0; i < n; i++) {
    float lo = fminf(p[i].x0, p[i].x1), hi = fmaxf(p[i].x0, p[i].x1);
    CHECK_NEAR(lo, 50, 1e-3);   /* from the visible end, x = -1 */
    CHECK_NEAR(hi, 100, 1);     /* to where the occluder begins, x = 0 */
  }
}

/* Fewer steps stop further from the boundary (at most len / 2^steps), and
** none drop the half-hidden edge. */
TEST(bisection_steps_bound_it) {
  SilPiece p[8];
  int whole, cut;
  int n = strip_pieces(3, p, &whole, &cut);
  CHECK_EQ_INT(n, 2);
  for (int i = 0; i < n; i++) {
    float hi = fmaxf(p[i].x0, p[i].x1);
    CHECK(hi < 99);
    CHECK(hi >= 100 - 100.0f / 8 - 1e-3f);
  }
  n = strip_pieces(0, p, &whole, &cut);
  CHECK_EQ_INT(n, 0);
}

/* ---- linking (ch. 3.3) ----------------------------------------------------- */

/* Link pieces p[0..n) of one object whose lines are ls. */
static void link_pieces(LinePolys *out, const SilPiece *p, int n, const SceneLines *ls) {
  SilPieces ps;
  memset(&ps, 0, sizeof ps);
  ps.p = (SilPiece *)p;
  ps.n = n;
  LineObjEdges oe;
  memset(&oe, 0, sizeof oe);
  oe.lines = ls;
  LineEdges e;
  memset(&e, 0, sizeof e);
  e.nobj = 1;
  e.obj = &oe;
  memset(out, 0, sizeof *out);
  sil_link(out, &ps, &e, 1);
}

TEST(link_within_two_pixels) {
  SceneLines ls = brush_lines(EDGE_SILHOUETTE);
  SilPiece near[2] = {{0, 0, 10, 0, 0, 1}, {11.5f, 0, 20, 0, 0, 1}};
  LinePolys out;
  link_pieces(&out, near, 2, &ls);
  CHECK_EQ_INT(out.n, 1);
  CHECK_EQ_INT(out.start[1], 3);   /* 0,0 -> 10,0 -> 20,0: only the far end of the second joins */
  line_polys_free(&out);
  SilPiece far[2] = {{0, 0, 10, 0, 0, 1}, {13, 0, 20, 0, 0, 1}};
  link_pieces(&out, far, 2, &ls);
  CHECK_EQ_INT(out.n, 2);
  line_polys_free(&out);
  ls.link_distance = 3;   /* the distance is the parameter's */
  link_pieces(&out, far, 2, &ls);
  CHECK_EQ_INT(out.n, 1);
  line_polys_free(&out);
}

/* At a fork the piece that turns the stroke least links (here the later
** one); each piece is used once. */
TEST(link_uses_each_piece_once) {
  SceneLines ls = brush_lines(EDGE_SILHOUETTE);
  SilPiece fork[3] = {{0, 0, 10, 0, 0, 1}, {10, 0, 10, 10, 0, 1}, {10, 0, 20, 0, 0, 1}};
  LinePolys out;
  link_pieces(&out, fork, 3, &ls);
  CHECK_EQ_INT(out.n, 2);
  CHECK_EQ_INT(out.start[1], 3);     /* 0,0 -> 10,0 -> 20,0 */
  CHECK_EQ_INT(out.start[2], 5);     /* then the branch alone */
  CHECK_NEAR(out.pts[2 * 2], 20, 0);
  CHECK_NEAR(out.pts[2 * 4 + 1], 10, 0);
  line_polys_free(&out);
}

/* A stroke does not double back (a turn of more than 150 degrees), and a
** stroke that only retraces one already made (ends within a pixel) is
** left out. */
TEST(link_never_doubles_back) {
  SceneLines ls = brush_lines(EDGE_SILHOUETTE);
  SilPiece back[2] = {{0, 0, 10, 0, 0, 1}, {10, 0, 3, 3, 0, 1}};   /* turns by 157 degrees */
  LinePolys out;
  link_pieces(&out, back, 2, &ls);
  CHECK_EQ_INT(out.n, 2);
  line_polys_free(&out);
  SilPiece retrace[2] = {{0, 0, 10, 0, 0, 1}, {10, 0.5f, 0.5f, 0.5f, 0, 1}};   /* the same line again */
  link_pieces(&out, retrace, 2, &ls);
  CHECK_EQ_INT(out.n, 1);
  CHECK_EQ_INT(out.start[1], 2);
  line_polys_free(&out);
}

/* A stroke runs so that most of its length has its face on the left. */
TEST(link_direction_follows_the_faces) {
  SceneLines ls = brush_lines(EDGE_SILHOUETTE);
  SilPiece p[2] = {{0, 0, 10, 0, 0, 1}, {30, 0, 10, 0, 0, 1}};   /* the longer one runs right to left */
  LinePolys out;
  link_pieces(&out, p, 2, &ls);
  CHECK_EQ_INT(out.n, 1);
  CHECK_NEAR(out.pts[0], 30, 0);
  CHECK_NEAR(out.pts[2 * 2], 0, 0);
  line_polys_free(&out);
}

/* The silhouette of a sphere is drawn counter-clockwise as seen: its centre
** on the left of (nearly) every step. */
TEST(sphere_outline_counter_clockwise) {
  Mesh *sph = make_sphere(1, 48, 24);
  SceneLines ls = brush_lines(EDGE_SILHOUETTE);
  ls.stroke = STROKE_PLAIN;
  ls.visibility = LINE_VIS_ENDPOINTS;
  LineObject o = object_of(sph, &ls, 0);
  Camera cam = camera_at(v3(3, -5, 2), v3(0, 0, 0), v3(0, 0, 1), 0, 35, 128, 128);
  StrokeList *sl = NULL;
  LineStats st;
  char err[128];
  CHECK(line_render(&o, 1, &cam, NULL, 1, &st, &sl, err, sizeof err));
  CHECK(st.tested > 0 && st.polylines >= 1);
  int left = 0, right = 0;
  for (int k = 0; sl && k < sl->n; k++) {
    const Stroke *s = &sl->s[k];
    for (int i = 0; i + 1 < s->npts; i++) {
      float dx = s->pts[2 * i + 2] - s->pts[2 * i], dy = s->pts[2 * i + 3] - s->pts[2 * i + 1];
      float cx = 64 - s->pts[2 * i], cy = 64 - s->pts[2 * i + 1];
      if (cx * dy - cy * dx > 0) left++;   /* left as seen, y down: (dy, -dx) */
      else right++;
    }
  }
  CHECK(left > 20 * (right + 1));
  stroke_list_free(sl);
  mesh_destroy(sph);
}

/* ---- the path (ch. 3.4, our splines) ------------------------------------- */

static SceneBrush default_brush(void) { return scene_default_style().lines.brush; }

/* A brush path along control points c[0..n) with brush b, its bristles,
** and its dry brush drawn from the stream of (object 7, stroke). */
typedef struct TestPath { BrushBristles br; BrushPath bp; } TestPath;

static int test_path(TestPath *t, const float *c, int n, const SceneBrush *b, uint32_t stroke) {
  brush_bristles_make(&t->br, b->sectors, b->bristles);
  Rng r;
  rng_seed_key(&r, LINE_STROKE_SEED, 7, stroke);
  return brush_path_build(&t->bp, c, n, b, &t->br, &r);
}

static void test_path_free(TestPath *t) {
  brush_path_free(&t->bp);
  brush_bristles_free(&t->br);
}

/* A circle of radius 60 given by 16 control points comes out in steps a
** pixel apart along the way's dominant axis (the brush's "one pixel at a
** time") that turn smoothly: not a polygon even at 4x zoom. */
TEST(path_is_smooth) {
  float c[2 * 17];
  for (int i = 0; i <= 16; i++) {
    c[2 * i] = (float)(100 + 60 * cos(2 * M_PI * i / 16));
    c[2 * i + 1] = (float)(100 + 60 * sin(2 * M_PI * i / 16));
  }
  SceneBrush b = default_brush();
  TestPath t;
  CHECK(test_path(&t, c, 17, &b, 0));

  /* a circle is 8 R sin 45 = 339 pixels round along the dominant axes */
  CHECK(t.bp.nsteps > 330 && t.bp.nsteps < 350);
  double worst_turn = 0, most = 0, least = 2, worst_r = 0;
  for (int i = 1; i + 1 < t.bp.nsteps; i++) {
    double ax = t.bp.x[i] - t.bp.x[i - 1], ay = t.bp.y[i] - t.bp.y[i - 1];
    double bx = t.bp.x[i + 1] - t.bp.x[i], by = t.bp.y[i + 1] - t.bp.y[i];
    double turn = fabs(atan2(ax * by - ay * bx, ax * bx + ay * by)) * 180 / M_PI;
    if (turn > worst_turn) worst_turn = turn;
    double major = fmax(fabs(ax), fabs(ay));
    if (major > most) most = major;
    if (major < least) least = major;
    double rr = fabs(hypot(t.bp.x[i] - 100, t.bp.y[i] - 100) - 60);
    if (rr > worst_r) worst_r = rr;
  }
  CHECK(most <= 1.02 && least >= 0.98);   /* a pixel along the dominant axis a step */
  CHECK(worst_turn < 4);   /* 1 / 60 rad = 0.95 degrees a pixel of arc; 22.5 at a corner */
  CHECK(worst_r < 1);      /* through the control points, nearer the arcs than the chords' 1.15 */
  test_path_free(&t);
}

/* ---- pressure and weights (ch. 4.6.2) --------------------------------------- */

TEST(pressure_larger_at_a_turn) {
  CHECK(brush_pressure_at(90, 0.6) > brush_pressure_at(180, 0.6));
  CHECK_NEAR(brush_pressure_at(180, 0.6), 0.6, 1e-12);
  CHECK_NEAR(brush_pressure_at(90, 0.6), 1, 1e-12);
  CHECK(brush_pressure_at(135, 0.6) > 0.6 && brush_pressure_at(135, 0.6) < 1);
  /* along a path with a right angle at its middle control point */
  float c[2 * 11];
  for (int i = 0; i <= 10; i++) {
    c[2 * i] = (float)(i <= 5 ? 20 * i : 100);
    c[2 * i + 1] = (float)(i <= 5 ? 0 : 20 * (i - 5));
  }
  SceneBrush b = default_brush();
  TestPath t;
  CHECK(test_path(&t, c, 11, &b, 0));

  float at_turn = 0, straight = 2;
  for (int i = 0; i < t.bp.nsteps; i++) {
    float d = hypotf(t.bp.x[i] - 100, t.bp.y[i]);
    if (d < 3 && t.bp.press[i] > at_turn) at_turn = t.bp.press[i];
    if (t.bp.x[i] > 25 && t.bp.x[i] < 55 && t.bp.press[i] < straight) straight = t.bp.press[i];
  }
  CHECK(at_turn > 0.9f);
  CHECK_NEAR(straight, 0.6, 1e-5);
  test_path_free(&t);
}

/* Formula 6: 1 on the pressed (right) side, falling to P, 0 from u = P on. */
TEST(bristle_weight_formula) {
  CHECK_NEAR(brush_weight(1, 0.5f), 1, 1e-6);
  CHECK_NEAR(brush_weight(0.5f, 0.5f), 1 - 0.25 * 0.5 / 0.5, 1e-6);   /* u = 0.25 */
  CHECK_NEAR(brush_weight(0.01f, 0.5f), 0.505, 1e-3);                 /* just before u = P */
  CHECK_NEAR(brush_weight(0, 0.5f), 0, 0);                            /* u = P */
  CHECK_NEAR(brush_weight(-1, 0.99f), 0, 0);
  for (float uy = -0.875f; uy <= 1; uy += 0.125f) CHECK_NEAR(brush_weight(uy, 1), 1, 1e-6);
  CHECK_NEAR(brush_weight(-1, 1), 0, 0);   /* u = 1 >= P even at full pressure */
}

/* ---- dry brush (ch. 4.6.1) --------------------------------------------------- */

/* The fraction of (bristle, step) pairs that deposit along a long line. */
static double deposit_rate(double p, int max_gap) {
  float *c = line_points(101, 10, 50, 20, 0);
  SceneBrush b = default_brush();
  b.dry_probability = p;
  b.dry_max_gap = max_gap;
  TestPath t;
  int ok = test_path(&t, c, 101, &b, 0);
  free(c);
  if (!ok) { brush_bristles_free(&t.br); return -1; }
  long on = 0, all = (long)t.bp.nsteps * t.br.n;
  for (int i = 0; i < t.bp.nsteps; i++)
    for (int k = 0; k < t.br.n; k++) on += brush_deposits(&t.bp, i, k);
  test_path_free(&t);
  return (double)on / all;
}

/* A gap of g steps follows a draw; a bristle deposits once per 1 + g steps
** of such a cycle, so its rate is 1 / (1 + p * max_gap / 2). */
TEST(dry_brush_rates) {
  CHECK_NEAR(deposit_rate(0, 4), 1, 0);
  double one = deposit_rate(1, 4), want = 1.0 / 3;
  CHECK(fabs(one - want) <= 0.1 * want);
  double thesis = deposit_rate(0.39, 4);
  want = 1 / (1 + 0.39 * 2);
  CHECK(fabs(thesis - want) <= 0.1 * want);
  CHECK_NEAR(deposit_rate(1, 0), 1, 0);   /* gaps of no length */
}

/* Coverage of a straight brush stroke of 21 control points, 20 pixels
** apart, along y = 50.5: rows [0, 100) of a 460-pixel-wide buffer. */
static float *line_coverage(const SceneBrush *b) {
  float *c = line_points(21, 20, 50.5f, 20, 0);
  TestPath t;
  test_path(&t, c, 21, b, 0);
  float *cov = xcalloc(460 * 100, sizeof *cov);
  int lo[100], hi[100];
  for (int y = 0; y < 100; y++) { lo[y] = 460; hi[y] = -1; }
  brush_cover(&t.bp, cov, 0, 460, 0, 100, lo, hi);
  test_path_free(&t);
  free(c);
  return cov;
}

/* Four sectors of two bristles, full pressure: tracks at 0, +-B/2, +-B
** across (B = 7 in the middle; +y is the right of a stroke running +x).
** Dry probability 0 paints every track all along; 1 leaves gaps in it.
** The left rim's bristle (u = 1) never touches: formula 6 needs u < P. */
TEST(dry_brush_tracks) {
  SceneBrush b = default_brush();
  b.sectors = 4;
  b.bristles = 2;
  b.pressure = 1;
  b.dry_probability = 0;
  float *wet = line_coverage(&b);
  b.dry_probability = 1;
  float *dry = line_coverage(&b);
  static const int rows[4] = {46, 50, 54, 57};   /* 50.5 + {-3.5, 0, 3.5, 7}: rows inked most */
  for (int k = 0; k < 4; k++) {
    float wmin = 1, dmin = 1;
    for (int x = 180; x < 280; x++) {   /* the middle, where B = 7 */
      wmin = fminf(wmin, wet[rows[k] * 460 + x]);
      dmin = fminf(dmin, dry[rows[k] * 460 + x]);
    }
    CHECK(wmin > 0.1f);
    CHECK(dmin < 0.5f * wmin);
  }
  for (int x = 0; x < 460; x++) CHECK(wet[43 * 460 + x] == 0);   /* the left rim's track */
  float between = wet[45 * 460 + 230];   /* halfway between two tracks 3.5 apart: little ink */
  CHECK(between < 0.5f * wet[47 * 460 + 230]);
  free(wet);
  free(dry);
}

/* A deposit is spread over the pixels around it: a one-bristle brush
** along y = 20.25 inks rows 19 and 20 unequally, neither fully. */
TEST(deposits_are_antialiased) {
  SceneBrush b = default_brush();
  b.sectors = 1;
  b.bristles = 1;
  b.dry_probability = 0;
  b.pressure = 1;
  b.ink_load = 0.2;
  float *c = line_points(21, 20, 20.25f, 20, 0);
  TestPath t;
  CHECK(test_path(&t, c, 21, &b, 0));
  CHECK_NEAR(t.br.uy[0], 0, 0);   /* at (r, theta) = (1, 0): on the centre line */
  float *cov = xcalloc(460 * 40, sizeof *cov);
  int lo[40], hi[40];
  for (int y = 0; y < 40; y++) { lo[y] = 460; hi[y] = -1; }
  brush_cover(&t.bp, cov, 0, 460, 0, 40, lo, hi);
  float r19 = cov[19 * 460 + 230], r20 = cov[20 * 460 + 230], r21 = cov[21 * 460 + 230];
  CHECK(r19 > 0.01f && r20 > r19 && r20 < 0.9f);
  CHECK_NEAR(r21, 0, 0);
  CHECK(lo[20] <= 230 && hi[20] >= 230);
  free(cov);
  test_path_free(&t);
  free(c);
}

/* The SVG outline is the width profile: each rib reaches B to either side. */
TEST(outline_is_the_width_profile) {
  float *c = line_points(9, 10, 10, 10, 5);
  SceneBrush b = default_brush();
  TestPath t;
  CHECK(test_path(&t, c, 9, &b, 0));

  float *left = xmalloc((size_t)t.bp.nsteps * 2 * sizeof *left), *right = xmalloc((size_t)t.bp.nsteps * 2 * sizeof *right);
  brush_outline(&t.bp, left, right);
  float widest = 0;
  for (int i = 0; i < t.bp.nsteps; i++) {
    CHECK_NEAR(hypotf(left[2 * i] - t.bp.x[i], left[2 * i + 1] - t.bp.y[i]), t.bp.b[i], 1e-3);
    CHECK_NEAR(hypotf(right[2 * i] - t.bp.x[i], right[2 * i + 1] - t.bp.y[i]), t.bp.b[i], 1e-3);
    widest = fmaxf(widest, t.bp.b[i]);
  }
  CHECK_NEAR(t.bp.b[0], 0, 1e-6);
  CHECK_NEAR(t.bp.b[t.bp.nsteps - 1], 0, 1e-6);
  CHECK(widest > 5 && widest <= 7);   /* the splined profile peaks a little under the table's 7 */
  /* left is left as seen: the path runs right and down, so left is up and right */
  int mid = t.bp.nsteps / 2;
  CHECK(left[2 * mid + 1] < t.bp.y[mid] && left[2 * mid] > t.bp.x[mid]);
  free(left);
  free(right);
  test_path_free(&t);
  free(c);
}

/* ---- the whole stage ----------------------------------------------------------- */

static unsigned long long image_hash(const Image *img) {
  unsigned long long h = 1469598103934665603ULL;
  const unsigned char *p = (const unsigned char *)img->data;
  for (size_t i = 0; i < (size_t)img->width * img->height * img->channels * sizeof(float); i++)
    h = (h ^ p[i]) * 1099511628211ULL;
  return h;
}

/* Brush strokes (endpoint method) beside ribbons (reference image) on
** another object: the same bytes at 1, 2 and 8 threads. */
TEST(deterministic_across_threads) {
  Mesh *sph = make_sphere(1, 40, 20);
  Mesh *quad = make_quad(v3(-2.5, -1.5, -1.2), v3(2.5, -1.5, -1.2), v3(2.5, 1.5, -1.2), v3(-2.5, 1.5, -1.2));
  SceneLines brush = brush_lines(EDGE_SILHOUETTE);
  SceneLines ribbon = brush_lines(EDGE_BOUNDARY);
  ribbon.stroke = STROKE_RIBBON;
  ribbon.width = 3;
  LineObject o[2] = {object_of(sph, &brush, 0), object_of(quad, &ribbon, 1)};
  Camera cam = camera_at(v3(2, -7, 3), v3(0, 0, 0), v3(0, 0, 1), 0, 40, 200, 150);
  unsigned long long h[3];
  int threads[3] = {1, 2, 8};
  LineStats st[3];
  for (int k = 0; k < 3; k++) {
    Image *img = image_create(200, 150, 3);
    for (int i = 0; i < 200 * 150 * 3; i++) img->data[i] = 1;
    char err[128];
    CHECK(line_render(o, 2, &cam, img, threads[k], &st[k], NULL, err, sizeof err));
    h[k] = image_hash(img);
    image_destroy(img);
  }
  CHECK(st[0].tested > 0 && st[0].segments > 0);   /* both front ends ran */
  CHECK(st[0].brush_steps > 100);
  CHECK(h[0] == h[1]);
  CHECK(h[0] == h[2]);
  mesh_destroy(sph);
  mesh_destroy(quad);
}

int main(void) {
  RUN(width_table_nine_points);
  RUN(bisection_keeps_the_visible_half);
  RUN(bisection_steps_bound_it);
  RUN(link_within_two_pixels);
  RUN(link_uses_each_piece_once);
  RUN(link_never_doubles_back);
  RUN(link_direction_follows_the_faces);
  RUN(sphere_outline_counter_clockwise);
  RUN(path_is_smooth);
  RUN(pressure_larger_at_a_turn);
  RUN(bristle_weight_formula);
  RUN(dry_brush_rates);
  RUN(dry_brush_tracks);
  RUN(deposits_are_antialiased);
  RUN(outline_is_the_width_profile);
  RUN(deterministic_across_threads);
  return unit_done();
}
