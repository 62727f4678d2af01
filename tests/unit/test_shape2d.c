/*
** 2D shapes and extrusions: areas of circles, polygons with holes and
** booleans against their formulas; extrusions closed and consistently
** oriented, with the volumes geometry says (a prism A h, a frustum
** A h (1 + s + s^2) / 3, a pyramid A h / 3, a twisted prism tending to
** A h, a torus swept in n steps n sin(2 pi / n) R A).
*/
#include <stdlib.h>
#include <string.h>

#include "../../src/geom/extrude.h"
#include "../../src/geom/shape2d.h"
#include "../../src/geom/shapes.h"
#include "unit.h"

static Arena arena;
static char err[512];

/* ---- helpers ----------------------------------------------------------- */

typedef struct Edge { int a, b; } Edge;

static int edge_cmp(const void *pa, const void *pb) {
  const Edge *x = pa, *y = pb;
  return x->a != y->a ? x->a - y->a : x->b - y->b;
}

/* Whether every directed edge of g's faces appears once and its reverse
** once: closed, manifold and consistently oriented. */
static int closed_oriented(const SceneGeometry *g) {
  int n = g->face_start[g->nfaces], k = 0;
  Edge *e = malloc((size_t)(n ? n : 1) * sizeof *e);
  for (int f = 0; f < g->nfaces; f++)
    for (int i = g->face_start[f]; i < g->face_start[f + 1]; i++) {
      int j = i + 1 < g->face_start[f + 1] ? i + 1 : g->face_start[f];
      e[k++] = (Edge){g->face_index[i], g->face_index[j]};
    }
  qsort(e, (size_t)k, sizeof *e, edge_cmp);
  int ok = k > 0;
  for (int i = 0; i < k && ok; i++) {
    if (i + 1 < k && !edge_cmp(&e[i], &e[i + 1])) ok = 0;   /* a directed edge twice */
    Edge r = {e[i].b, e[i].a};
    if (!bsearch(&r, e, (size_t)k, sizeof *e, edge_cmp)) ok = 0;
    if (e[i].a == e[i].b) ok = 0;
  }
  free(e);
  return ok;
}

/* The area of g's flat triangulation (its faces, in the xy-plane). */
static double mesh_area(const SceneGeometry *g) {
  double s = 0;
  for (int f = 0; f < g->nfaces; f++) {
    const int *t = g->face_index + g->face_start[f];
    Vec3 a = g->verts[t[0]], b = g->verts[t[1]], c = g->verts[t[2]];
    s += ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y)) / 2;
  }
  return s;
}

static SceneGeometry *square(double side, int center) {
  SceneGeometry *g = shape2d_square(&arena, (Vec2){side, side}, center, err, sizeof err);
  if (!g) fprintf(stderr, "square: %s\n", err);
  return g;
}

static SceneGeometry *moved(SceneGeometry *g, double dx, double dy) {
  return shape_transformed(&arena, g, m4_translate(v3(dx, dy, 0)));
}

/* ---- 2D shapes ------------------------------------------------------------ */

TEST(circle_is_a_regular_polygon) {
  for (int n = 3; n <= 96; n += 31) {
    SceneGeometry *g = shape2d_circle(&arena, 2, n, err, sizeof err);
    CHECK(g && g->ncontours == 1);
    CHECK_EQ_INT(g->contour_start[1], n);
    double want = n / 2.0 * 4 * sin(2 * M_PI / n);
    CHECK_NEAR(shape2d_area(g), want, 1e-9);
    CHECK_NEAR(mesh_area(g), want, 1e-9);   /* the triangles cover it once */
    CHECK_EQ_INT(g->nfaces, n - 2);
  }
}

TEST(fragments_follow_openscad) {
  CHECK_EQ_INT(shape2d_fragments(1, 0, 12, 2), 5);      /* the small circle's pentagon */
  CHECK_EQ_INT(shape2d_fragments(10, 0, 12, 2), 30);    /* 360 / fa */
  CHECK_EQ_INT(shape2d_fragments(5, 0, 12, 2), 16);     /* 2 pi r / fs, rounded up */
  CHECK_EQ_INT(shape2d_fragments(5, 7, 12, 2), 7);
  CHECK_EQ_INT(shape2d_fragments(5, 2, 12, 2), 3);
  CHECK_EQ_INT(shape2d_fragments(5, 2e6, 12, 2), -1);      /* past SHAPE2D_MAX_POINTS */
}

TEST(polygon_with_a_hole) {
  /* a 4 x 4 square with a 2 x 2 hole, the hole written either way round:
  ** even-odd makes it a hole both times */
  Vec2 p[8] = {{0, 0}, {4, 0}, {4, 4}, {0, 4}, {1, 1}, {3, 1}, {3, 3}, {1, 3}};
  int start[3] = {0, 4, 8};
  for (int turn = 0; turn < 2; turn++) {
    if (turn) { Vec2 t = p[5]; p[5] = p[7]; p[7] = t; }
    SceneGeometry *g = shape2d_from_contours(&arena, p, start, 2, SUMI_P2D_EVEN_ODD, err, sizeof err);
    CHECK(g != NULL);
    CHECK_EQ_INT(g->ncontours, 2);
    CHECK_NEAR(shape2d_area(g), 12, 1e-12);
    CHECK_NEAR(mesh_area(g), 12, 1e-12);
  }
}

TEST(bow_tie_is_cleaned) {
  /* a self-crossing quadrilateral: two triangles of area 1 each */
  Vec2 p[4] = {{0, 0}, {2, 2}, {2, 0}, {0, 2}};
  int start[2] = {0, 4};
  SceneGeometry *g = shape2d_from_contours(&arena, p, start, 1, SUMI_P2D_EVEN_ODD, err, sizeof err);
  CHECK(g != NULL);
  CHECK_EQ_INT(g->ncontours, 2);
  CHECK_NEAR(shape2d_area(g), 2, 1e-12);
}

TEST(boolean_areas) {
  /* two unit-overlapping 2 x 2 squares: union 7, intersection 1, difference 3 */
  const SceneGeometry *g[2] = {square(2, 0), moved(square(2, 0), 1, 1)};
  SceneGeometry *u = shape2d_boolean(&arena, SUMI_P2D_UNION, g, 2, err, sizeof err);
  SceneGeometry *i = shape2d_boolean(&arena, SUMI_P2D_INTERSECTION, g, 2, err, sizeof err);
  SceneGeometry *d = shape2d_boolean(&arena, SUMI_P2D_DIFFERENCE, g, 2, err, sizeof err);
  CHECK(u && i && d);
  CHECK_NEAR(shape2d_area(u), 7, 1e-12);
  CHECK_NEAR(shape2d_area(i), 1, 1e-12);
  CHECK_NEAR(shape2d_area(d), 3, 1e-12);
  CHECK_NEAR(mesh_area(d), 3, 1e-12);
  /* a hole: a disc less a smaller concentric one, as an annulus */
  const SceneGeometry *ring[2] = {shape2d_circle(&arena, 2, 64, err, sizeof err),
                                  shape2d_circle(&arena, 1, 64, err, sizeof err)};
  SceneGeometry *an = shape2d_boolean(&arena, SUMI_P2D_DIFFERENCE, ring, 2, err, sizeof err);
  CHECK(an && an->ncontours == 2);
  CHECK_NEAR(shape2d_area(an), 32 * sin(2 * M_PI / 64) * 3, 1e-9);
  CHECK_NEAR(mesh_area(an), 32 * sin(2 * M_PI / 64) * 3, 1e-9);
  /* disjoint intersection: the empty shape */
  const SceneGeometry *apart[2] = {square(1, 0), moved(square(1, 0), 5, 0)};
  SceneGeometry *none = shape2d_boolean(&arena, SUMI_P2D_INTERSECTION, apart, 2, err, sizeof err);
  CHECK(none && shape2d_is_empty(none));
}

TEST(offset_areas) {
  /* a 2 x 2 square grown by 1 with sharp corners is 4 x 4; rounded, it
  ** gains four quarter discs (a polygon of them, so a little less than pi) */
  SceneGeometry *s = square(2, 1);
  SceneGeometry *m = shape2d_offset(&arena, s, 1, SUMI_P2D_JOIN_MITER, 64, err, sizeof err);
  SceneGeometry *r = shape2d_offset(&arena, s, 1, SUMI_P2D_JOIN_ROUND, 64, err, sizeof err);
  SceneGeometry *in = shape2d_offset(&arena, s, -0.5, SUMI_P2D_JOIN_MITER, 64, err, sizeof err);
  CHECK(m && r && in);
  CHECK_NEAR(shape2d_area(m), 16, 1e-9);
  CHECK_NEAR(shape2d_area(in), 1, 1e-9);
  double want = 4 + 8 + M_PI;
  CHECK(shape2d_area(r) < want && shape2d_area(r) > want - 0.01);
}

/* ---- extrusions ---------------------------------------------------------- */

static SceneGeometry *linear(const SceneGeometry *s, double h, double twist, int slices, double sx, double sy) {
  ExtrudeLinear p = {h, 0, twist, slices, {sx, sy}};
  SceneGeometry *g = extrude_linear(&arena, s, &p, err, sizeof err);
  if (!g) fprintf(stderr, "linear_extrude: %s\n", err);
  return g;
}

TEST(prism_volume) {
  SceneGeometry *ring[2] = {shape2d_circle(&arena, 2, 48, err, sizeof err), shape2d_circle(&arena, 1, 48, err, sizeof err)};
  SceneGeometry *an = shape2d_boolean(&arena, SUMI_P2D_DIFFERENCE, (const SceneGeometry *const *)ring, 2, err, sizeof err);
  SceneGeometry *g = linear(an, 3, 0, 1, 1, 1);
  CHECK(g && closed_oriented(g));
  CHECK_NEAR(extrude_mesh_volume(g), shape2d_area(an) * 3, 1e-9);
  SceneGeometry *c = linear(square(2, 0), 1.5, 0, 4, 1, 1);   /* slices of a prism change nothing */
  CHECK(c && closed_oriented(c));
  CHECK_NEAR(extrude_mesh_volume(c), 6, 1e-12);
}

TEST(frustum_and_pyramid_volume) {
  SceneGeometry *s = square(2, 1);
  for (double k = 0.25; k <= 2; k += 0.75) {
    SceneGeometry *g = linear(s, 3, 0, 1, k, k);
    CHECK(g && closed_oriented(g));
    CHECK_NEAR(extrude_mesh_volume(g), 4 * 3 * (1 + k + k * k) / 3, 1e-12);
  }
  SceneGeometry *py = linear(s, 3, 0, 1, 0, 0);   /* to a point */
  CHECK(py && closed_oriented(py));
  CHECK_NEAR(extrude_mesh_volume(py), 4, 1e-12);
  SceneGeometry *wedge = linear(s, 3, 0, 1, 0, 1);   /* to a line: half the prism */
  CHECK(wedge && closed_oriented(wedge));
  CHECK_NEAR(extrude_mesh_volume(wedge), 6, 1e-12);
}

/* The prismatoid formula: a solid whose vertices all lie in two parallel
** planes h apart has volume h (A0 + 4 Am + A1) / 6, Am the area halfway,
** whose corners are the midpoints of the side edges. For a slice of the
** twisted square p turned by -d degrees, split from the bottom of each
** corner to the top of the next, those run b_i t_i, b_i t_i+1, ... */
static double twisted_slice_volume(const Vec2 *p, int n, double d, double h) {
  double c = cos(-d * M_PI / 180), s = sin(-d * M_PI / 180), am = 0, a = 0;
  Vec2 *m = malloc(2 * (size_t)n * sizeof *m);
  for (int i = 0; i < n; i++) {
    Vec2 b = p[i], bn = p[(i + 1) % n];
    Vec2 t = {c * b.x - s * b.y, s * b.x + c * b.y}, tn = {c * bn.x - s * bn.y, s * bn.x + c * bn.y};
    m[2 * i] = (Vec2){(b.x + t.x) / 2, (b.y + t.y) / 2};
    m[2 * i + 1] = (Vec2){(b.x + tn.x) / 2, (b.y + tn.y) / 2};
    a += (b.x * bn.y - bn.x * b.y) / 2;
  }
  for (int i = 0; i < 2 * n; i++) am += (m[i].x * m[(i + 1) % (2 * n)].y - m[(i + 1) % (2 * n)].x * m[i].y) / 2;
  free(m);
  return h * (2 * a + 4 * am) / 6;
}

TEST(twisted_prism_volume) {
  /* each slice is a prismatoid, so the volume is exact (a twist small
  ** enough that no side is cut), and the error against A h falls with the
  ** slices */
  SceneGeometry *s = square(1, 1);
  Vec2 p[4] = {{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}};
  double prev = 1;
  for (int slices = 1; slices <= 64; slices *= 4) {
    SceneGeometry *g = linear(s, 2, 9, slices, 1, 1);
    CHECK(g && closed_oriented(g));
    CHECK_EQ_INT(g->nverts, 4 * (slices + 1));
    CHECK_NEAR(extrude_mesh_volume(g), slices * twisted_slice_volume(p, 4, 9.0 / slices, 2.0 / slices), 1e-12);
    double e = fabs(extrude_mesh_volume(g) - 2);
    CHECK(e < prev);
    prev = e;
  }
  /* a big twist cuts the sides (folds of 10 degrees at most), which also
  ** brings the volume close to A h: a 2 x 2 square turned 90 degrees over
  ** 2, within 0.1 % at 64 slices */
  SceneGeometry *g = linear(square(2, 1), 2, 90, 64, 1, 1);
  CHECK(g && closed_oriented(g));
  CHECK(g->nverts > 4 * 65);
  CHECK(fabs(extrude_mesh_volume(g) - 8) < 8e-3);
}

TEST(torus_by_rotate_extrude) {
  /* a 24-gon of radius 1 at x = 3, swept in 48 steps: exactly
  ** n sin(2 pi / n) R A (every cross-section is a ring of 48-gons), and
  ** short of the true torus 2 pi^2 R r^2 by the two polygons' shortfalls,
  ** e(n) = 1 - n sin(2 pi / n) / (2 pi) each */
  SceneGeometry *c = moved(shape2d_circle(&arena, 1, 24, err, sizeof err), 3, 0);
  SceneGeometry *g = extrude_rotate(&arena, c, 360, 48, err, sizeof err);
  CHECK(g && closed_oriented(g));
  double A = 12 * sin(2 * M_PI / 24);
  double want = 48 * sin(2 * M_PI / 48) * 3 * A;
  CHECK_NEAR(extrude_mesh_volume(g), want, 1e-9);
  double e24 = 1 - 24 * sin(2 * M_PI / 24) / (2 * M_PI), e48 = 1 - 48 * sin(2 * M_PI / 48) / (2 * M_PI);
  double rel = 1 - extrude_mesh_volume(g) / (2 * M_PI * M_PI * 3);
  CHECK(rel > 0 && rel <= e24 + e48);
}

TEST(rotate_extrude_partial_and_on_axis) {
  /* a square [0, 1] x [0, 1] against the axis, swept a quarter turn in 16
  ** steps: a quarter of a 64-gon prism, closed with its end caps */
  SceneGeometry *g = extrude_rotate(&arena, square(1, 0), 90, 16, err, sizeof err);
  CHECK(g && closed_oriented(g));
  CHECK_NEAR(extrude_mesh_volume(g), 16 * sin(2 * M_PI / 64) / 2, 1e-12);
  /* the other way round, and from the left side of the axis: the same */
  SceneGeometry *back = extrude_rotate(&arena, square(1, 0), -90, 16, err, sizeof err);
  SceneGeometry *left = extrude_rotate(&arena, moved(square(1, 0), -1, 0), 90, 16, err, sizeof err);
  CHECK(back && left && closed_oriented(back) && closed_oriented(left));
  CHECK_NEAR(extrude_mesh_volume(back), extrude_mesh_volume(g), 1e-12);
  CHECK_NEAR(extrude_mesh_volume(left), extrude_mesh_volume(g), 1e-12);
  /* a full turn of it: a 64-gon cylinder */
  SceneGeometry *cyl = extrude_rotate(&arena, square(1, 0), 360, 64, err, sizeof err);
  CHECK(cyl && closed_oriented(cyl));
  CHECK_NEAR(extrude_mesh_volume(cyl), 32 * sin(2 * M_PI / 64), 1e-12);
  /* straddling the axis is refused */
  CHECK(extrude_rotate(&arena, square(1, 1), 360, 16, err, sizeof err) == NULL);
}

TEST(touching_contours_stay_closed) {
  /* two squares meeting at one corner: one shape whose contours share a
  ** point; its prism is still closed */
  const SceneGeometry *g[2] = {square(1, 0), moved(square(1, 0), 1, 1)};
  SceneGeometry *u = shape2d_boolean(&arena, SUMI_P2D_UNION, g, 2, err, sizeof err);
  CHECK(u != NULL);
  CHECK_NEAR(shape2d_area(u), 2, 1e-12);
  SceneGeometry *p = linear(u, 1, 0, 1, 1, 1);
  CHECK(p && closed_oriented(p));
  CHECK_NEAR(extrude_mesh_volume(p), 2, 1e-12);
}

int main(void) {
  arena_init(&arena);
  RUN(circle_is_a_regular_polygon);
  RUN(fragments_follow_openscad);
  RUN(polygon_with_a_hole);
  RUN(bow_tie_is_cleaned);
  RUN(boolean_areas);
  RUN(offset_areas);
  RUN(prism_volume);
  RUN(frustum_and_pyramid_volume);
  RUN(twisted_prism_volume);
  RUN(torus_by_rotate_extrude);
  RUN(rotate_extrude_partial_and_on_axis);
  RUN(touching_contours_stay_closed);
  arena_free(&arena);
  return unit_done();
}
