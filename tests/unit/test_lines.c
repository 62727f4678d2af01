/*
** Unit tests of the line pipeline (001 §2.1): important edges, the
** reference image, tracing, linking, ribbons and stroke drawing, on meshes
** built here with known answers.
*/
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../../src/base/mem.h"
#include "../../src/render/edgeref.h"
#include "../../src/render/lines.h"
#include "../../src/render/link.h"
#include "../../src/render/trace.h"
#include "unit.h"

/* ---- fixtures -------------------------------------------------------------- */

static Camera make_camera(Vec3 eye, Vec3 at, int ortho, double fov_or_h, int w, int h, Vec3 lo, Vec3 hi) {
  SceneCamera sc;
  memset(&sc, 0, sizeof sc);
  sc.present = 1;
  sc.kind = ortho ? CAMERA_ORTHO : CAMERA_PERSPECTIVE;
  sc.position = eye;
  sc.look_at = at;
  sc.up = v3(0, 0, 1);
  if (fabs(eye.x - at.x) < 1e-9 && fabs(eye.y - at.y) < 1e-9) sc.up = v3(0, 1, 0);
  sc.fov = fov_or_h;
  sc.ortho_height = fov_or_h;
  Camera c;
  const char *why = NULL;
  if (!camera_setup(&c, &sc, w, h, lo, hi, 0, &why)) { fprintf(stderr, "camera: %s\n", why); abort(); }
  return c;
}

static SceneLines lines_of(unsigned kinds) {
  SceneLines l;
  memset(&l, 0, sizeof l);
  l.present = 1;
  l.kinds = kinds;
  l.crease_angle = 40;
  l.stroke = STROKE_PLAIN;
  l.width = 2;
  l.color = (Color){0, 0, 0, 1};
  l.opacity = 1;
  l.ref_scale = 1;
  l.search_width = 2;
  l.max_misses = 2;
  l.link_depth = 3;
  l.link_angle = 40;
  l.miter_limit = 4;
  l.min_length = 0;
  l.depth_offset = 0;
  return l;
}

static LineObject object_of(Mesh *m, const SceneLines *ls, int id) {
  LineObject o;
  memset(&o, 0, sizeof o);
  o.mesh = m;
  o.object_to_world = m4_identity();
  o.lines = ls;
  o.id = id;
  o.fill = (Color){0.8f, 0.7f, 0.5f, 1};
  return o;
}

/* The cube [-1, 1]^3: 12 triangles, two per face, tri_face = face. */
static Mesh *make_cube(void) {
  static const int quads[6][4] = {
    {1, 3, 7, 5},  /* +x */ {0, 4, 6, 2},  /* -x */ {2, 6, 7, 3},  /* +y */
    {0, 1, 5, 4},  /* -y */ {4, 5, 7, 6},  /* +z */ {0, 2, 3, 1},  /* -z */
  };
  Mesh *m = mesh_create(8, 12);
  for (int i = 0; i < 8; i++) m->pos[i] = v3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
  for (int f = 0; f < 6; f++) {
    const int *q = quads[f];
    int t0[3] = {q[0], q[1], q[2]}, t1[3] = {q[0], q[2], q[3]};
    memcpy(m->tri[2 * f], t0, sizeof t0);
    memcpy(m->tri[2 * f + 1], t1, sizeof t1);
    m->tri_face[2 * f] = m->tri_face[2 * f + 1] = f;
  }
  mesh_compute_normals(m);
  mesh_build_edges(m);
  return m;
}

/* A quad p0 p1 p2 p3 (counter-clockwise) as two triangles of one face. */
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

/* A UV sphere of radius r about c: nu segments around, nv from pole to pole. */
static Mesh *make_sphere(Vec3 c, double r, int nu, int nv) {
  Mesh *m = mesh_create(nu * (nv - 1) + 2, 2 * nu * (nv - 1));
  int v = 0, t = 0;
  m->pos[v++] = v3_add(c, v3(0, 0, r));
  for (int j = 1; j < nv; j++) {
    double th = M_PI * j / nv;
    for (int i = 0; i < nu; i++) {
      double ph = 2 * M_PI * i / nu;
      m->pos[v++] = v3_add(c, v3(r * sin(th) * cos(ph), r * sin(th) * sin(ph), r * cos(th)));
    }
  }
  m->pos[v++] = v3_add(c, v3(0, 0, -r));
  for (int i = 0; i < nu; i++) {
    int i1 = (i + 1) % nu;
    m->tri[t][0] = 0; m->tri[t][1] = 1 + i; m->tri[t][2] = 1 + i1; t++;
    for (int j = 1; j + 1 < nv; j++) {
      int a = 1 + (j - 1) * nu + i, b = 1 + (j - 1) * nu + i1, cc = a + nu, d = b + nu;
      m->tri[t][0] = a; m->tri[t][1] = cc; m->tri[t][2] = d; t++;
      m->tri[t][0] = a; m->tri[t][1] = d; m->tri[t][2] = b; t++;
    }
    int last = 1 + (nv - 2) * nu;
    m->tri[t][0] = last + i; m->tri[t][1] = v - 1; m->tri[t][2] = last + i1; t++;
  }
  m->ntris = t;
  for (int k = 0; k < t; k++) m->tri_face[k] = k;
  mesh_compute_normals(m);
  mesh_build_edges(m);
  return m;
}

/* The mesh edge of m joining vertices a and b, or -1. */
static int find_edge(const Mesh *m, int a, int b) {
  for (int e = 0; e < m->nedges; e++)
    if ((m->edges[e].v[0] == a && m->edges[e].v[1] == b) || (m->edges[e].v[0] == b && m->edges[e].v[1] == a))
      return e;
  return -1;
}

/* ---- important edges ------------------------------------------------------- */

/* Bit (axis, sign) of cube corner i: +1 or -1 along x (0), y (1), z (2). */
static int corner_coord(int i, int axis) { return i >> axis & 1 ? 1 : -1; }

/* Seen from the corner (3, 3, 3), the faces +x +y +z face the viewer and
** -x -y -z face away: the silhouette is the six cube edges where one
** coordinate is +1 and another -1 (the hexagon); every cube edge is a 90°
** crease and a polygon edge; the six face diagonals are none of these. */
TEST(cube_corner_edges) {
  Mesh *m = make_cube();
  Vec3 lo = v3(-1, -1, -1), hi = v3(1, 1, 1);
  for (int ortho = 0; ortho <= 1; ortho++) {
    Camera cam = make_camera(v3(3, 3, 3), v3(0, 0, 0), ortho, ortho ? 4 : 50, 128, 128, lo, hi);
    SceneLines sil = lines_of(EDGE_SILHOUETTE), cre = lines_of(EDGE_CREASE),
               face = lines_of(EDGE_FACE | EDGE_BOUNDARY);
    const SceneLines *ls[3] = {&sil, &cre, &face};
    int counts[3] = {0, 0, 0};
    for (int k = 0; k < 3; k++) {
      LineObject o = object_of(m, ls[k], 0);
      LineEdges ed;
      line_edges_build(&ed, &o, 1, &cam, 1);
      counts[k] = ed.n;
      for (int e = 0; e < m->nedges; e++) {
        int a = m->edges[e].v[0], b = m->edges[e].v[1], same = 0, plus = 0, minus = 0;
        for (int ax = 0; ax < 3; ax++) {
          if (corner_coord(a, ax) == corner_coord(b, ax)) {
            same++;
            plus += corner_coord(a, ax) > 0;
            minus += corner_coord(a, ax) < 0;
          }
        }
        int cube_edge = same == 2;   /* diagonals share one coordinate */
        int want = k == 0 ? cube_edge && plus == 1 && minus == 1 : cube_edge;
        CHECK_EQ_INT(ed.obj[0].id[e] != 0, want);
      }
      line_edges_free(&ed);
    }
    CHECK_EQ_INT(m->nedges, 18);
    CHECK_EQ_INT(counts[0], 6);
    CHECK_EQ_INT(counts[1], 12);
    CHECK_EQ_INT(counts[2], 12);
  }
  mesh_destroy(m);
}

/* crease(0) marks every edge whose faces are not coplanar: the cube's 12
** edges and none of its 6 face diagonals, however it is turned, moved or
** scaled (rounding tilts the diagonals' normals either way), and the
** diagonal of a twisted quad; crease(91) marks none of the cube's; a
** subdivision sharpness makes a crease anyway. */
TEST(crease_threshold_and_sharpness) {
  Mesh *m = make_cube();
  Camera cam = make_camera(v3(3, 3, 3), v3(0, 0, 0), 0, 50, 64, 64, v3(-1, -1, -1), v3(1, 1, 1));
  SceneLines l = lines_of(EDGE_CREASE);
  l.crease_angle = 0;
  LineObject o = object_of(m, &l, 0);
  LineEdges ed;
  for (int k = 0; k < 24; k++) {
    o.object_to_world = m4_mul(m4_translate(v3(0.1 * k, -0.03 * k, 0.07 * k)),
                               m4_mul(m4_rotate_xyz(v3(7.3 * k, 11.1 * k, 13.7 * k)), m4_scale(v3(1 + 0.1 * k, 1, 1))));
    line_edges_build(&ed, &o, 1, &cam, 1);
    CHECK_EQ_INT(ed.n, 12);
    line_edges_free(&ed);
  }
  o.object_to_world = m4_identity();
  l.crease_angle = 91;
  line_edges_build(&ed, &o, 1, &cam, 1);
  CHECK_EQ_INT(ed.n, 0);
  line_edges_free(&ed);
  int diag = find_edge(m, 0, 3);   /* a diagonal of the -z face */
  CHECK(diag >= 0);
  m->edges[diag].sharpness = 2;
  line_edges_build(&ed, &o, 1, &cam, 1);
  CHECK_EQ_INT(ed.n, 1);
  CHECK_EQ_INT(ed.edge_of[0], diag);
  line_edges_free(&ed);
  mesh_destroy(m);
  Mesh *q = make_quad(v3(-1, -1, 0), v3(1, -1, 0), v3(1, 1, 0.01), v3(-1, 1, 0));   /* twisted */
  l.crease_angle = 0;
  LineObject oq = object_of(q, &l, 0);
  line_edges_build(&ed, &oq, 1, &cam, 1);
  CHECK_EQ_INT(ed.n, 1);
  if (ed.n == 1) CHECK_EQ_INT(ed.edge_of[0], find_edge(q, 0, 2));
  line_edges_free(&ed);
  mesh_destroy(q);
}

/* A lone quad: four boundary edges; with face_edges the diagonal (inside
** one polygon) is not a polygon edge. */
TEST(boundary_and_face_edges) {
  Mesh *m = make_quad(v3(-1, -1, 0), v3(1, -1, 0), v3(1, 1, 0), v3(-1, 1, 0));
  Camera cam = make_camera(v3(0, 0, 5), v3(0, 0, 0), 0, 40, 64, 64, v3(-1, -1, 0), v3(1, 1, 0));
  SceneLines l = lines_of(EDGE_BOUNDARY);
  LineObject o = object_of(m, &l, 0);
  LineEdges ed;
  line_edges_build(&ed, &o, 1, &cam, 1);
  CHECK_EQ_INT(ed.n, 4);
  CHECK_EQ_INT(ed.obj[0].id[find_edge(m, 0, 2)], 0);
  line_edges_free(&ed);
  l.kinds = EDGE_FACE;
  line_edges_build(&ed, &o, 1, &cam, 1);
  CHECK_EQ_INT(ed.n, 4);
  line_edges_free(&ed);
  mesh_destroy(m);
}

/* ---- reference image and tracing ------------------------------------------- */

/* Scene: a triangle in z = 0 whose top edge runs from (-1, 0) to (1, 0),
** seen from +z, with an occluding quad at z = 0.5 over x in [x0, x1]. */
typedef struct EdgeScene {
  Mesh *tri, *occ;
  SceneLines l, occ_l;
  LineObject o[2];
  Camera cam;
  int edge;   /* mesh edge (-1,0)-(1,0) */
} EdgeScene;

static void edge_scene(EdgeScene *s, double x0, double x1) {
  s->tri = mesh_create(3, 1);
  s->tri->pos[0] = v3(-1, 0, 0); s->tri->pos[1] = v3(0, -0.6, 0); s->tri->pos[2] = v3(1, 0, 0);
  s->tri->tri[0][0] = 0; s->tri->tri[0][1] = 1; s->tri->tri[0][2] = 2;
  mesh_compute_normals(s->tri);
  mesh_build_edges(s->tri);
  s->edge = find_edge(s->tri, 0, 2);
  s->occ = make_quad(v3(x0, -1, 0.5), v3(x1, -1, 0.5), v3(x1, 1, 0.5), v3(x0, 1, 0.5));
  s->l = lines_of(EDGE_BOUNDARY);
  s->o[0] = object_of(s->tri, &s->l, 0);
  s->o[1] = object_of(s->occ, NULL, 1);
  s->cam = make_camera(v3(0, 0, 4), v3(0, 0, 0), 1, 2.5, 200, 200, v3(-1.2, -1, 0), v3(1.2, 1, 0.5));
}

static void edge_scene_free(EdgeScene *s) { mesh_destroy(s->tri); mesh_destroy(s->occ); }

/* The segments of the scene's top edge, traced with its lines settings
** (reference image at the output's size). */
static int trace_top(EdgeScene *s, LineSeg *seg, int *visible_ids_match) {
  LineEdges ed;
  LineRef ref;
  line_edges_build(&ed, s->o, 2, &s->cam, 1);
  line_ref_build(&ref, &ed, s->o, 200, 200, 1);
  int id = ed.obj[0].id[s->edge];
  int n = line_trace_span(&ref.span[id - 1], line_ref_vis(&ref, id), s->l.max_misses, seg);
  /* the recorded visible set and counts are the ids with visible steps */
  int k = 0, match = 1;
  for (int i = 0; i < ed.n; i++) {
    int steps = 0;
    for (int j = 0; j < ref.span[i].nsteps; j++) steps += line_ref_vis(&ref, i + 1)[j];
    match &= steps == ref.count[i];
    if (steps) match &= k < ref.nvisible && ref.visible[k++] == i + 1;
  }
  match &= k == ref.nvisible;
  if (visible_ids_match) *visible_ids_match = match;
  line_ref_free(&ref);
  line_edges_free(&ed);
  return n;
}

/* An edge half hidden behind a plane: one segment, linkable at its visible
** end only, ending where the plane begins (x = 0 is pixel 100). */
TEST(half_hidden_edge) {
  EdgeScene s;
  edge_scene(&s, 0, 2);
  LineSeg seg[64];
  int match = 0;
  int n = trace_top(&s, seg, &match);
  CHECK(match);
  CHECK_EQ_INT(n, 1);
  if (n == 1) {
    /* v[0] of the edge is vertex 0, at (-1, 0): the visible end */
    CHECK_EQ_INT(seg[0].at0, 1);
    CHECK_EQ_INT(seg[0].at1, 0);
    CHECK_NEAR(seg[0].x0, 20, 0.01);   /* the real end point: (-1 + 1.25) / 2.5 * 200 */
    CHECK_NEAR(seg[0].x1, 100, 2.5);
  }
  edge_scene_free(&s);
}

/* A plane strip 8 px wide across the middle of an edge: two misses do not
** bridge it, thirty do (001 §3.3.1, Figure 17). */
TEST(max_misses_bridges_hidden_parts) {
  EdgeScene s;
  edge_scene(&s, -0.05, 0.05);
  LineSeg seg[64];
  int n = trace_top(&s, seg, NULL);
  CHECK_EQ_INT(n, 2);
  if (n == 2) {
    CHECK(seg[0].at0 && !seg[0].at1);
    CHECK(!seg[1].at0 && seg[1].at1);
  }
  s.l.max_misses = 30;
  n = trace_top(&s, seg, NULL);
  CHECK_EQ_INT(n, 1);
  if (n == 1) CHECK(seg[0].at0 && seg[0].at1);
  s.l.max_misses = 0;   /* exact: the misses only come from the strip */
  n = trace_top(&s, seg, NULL);
  CHECK_EQ_INT(n, 2);
  edge_scene_free(&s);
}

/* An edge fully visible gives one segment touching both ends; the hidden
** edge of a fully covered object is not in the visible set. */
TEST(visible_and_hidden) {
  EdgeScene s;
  edge_scene(&s, 3, 4);   /* occluder off to the side */
  LineSeg seg[64];
  int n = trace_top(&s, seg, NULL);
  CHECK_EQ_INT(n, 1);
  if (n == 1) CHECK(seg[0].at0 && seg[0].at1);
  edge_scene_free(&s);
  edge_scene(&s, -2, 2);  /* everything behind the plane */
  LineEdges ed;
  LineRef ref;
  line_edges_build(&ed, s.o, 2, &s.cam, 1);
  line_ref_build(&ref, &ed, s.o, 200, 200, 1);
  CHECK_EQ_INT(ed.n, 3);
  CHECK_EQ_INT(ref.nvisible, 0);
  line_ref_free(&ref);
  line_edges_free(&ed);
  edge_scene_free(&s);
}

/* One-pixel runs are dropped, unless the whole walk is one pixel. */
TEST(one_pixel_segments) {
  LineSpan s;
  memset(&s, 0, sizeof s);
  s.x0 = 2.5f; s.y0 = 5.5f; s.x1 = 12.5f; s.y1 = 5.5f;
  s.px0 = 2; s.py0 = 5; s.px1 = 12; s.py1 = 5; s.nsteps = 11;
  s.real0 = s.real1 = 1;
  unsigned char vis[11] = {0};
  vis[5] = 1;   /* a lone step in the middle */
  LineSeg seg[8];
  CHECK_EQ_INT(line_trace_span(&s, vis, 0, seg), 0);
  vis[6] = 1;   /* two steps: a segment */
  CHECK_EQ_INT(line_trace_span(&s, vis, 0, seg), 1);
  LineSpan dot = s;
  dot.x1 = 2.9f; dot.px1 = 2; dot.nsteps = 1;
  unsigned char one = 1;
  CHECK_EQ_INT(line_trace_span(&dot, &one, 0, seg), 1);
  CHECK(seg[0].at0 && seg[0].at1);
  CHECK_NEAR(seg[0].x1, 2.9, 1e-6);
}

/* max_misses counts output pixels: at ref_scale 4 a gap of 8 reference
** steps (2 output pixels) is bridged, at 0.5 a gap of one step. */
TEST(misses_in_output_pixels) {
  CHECK_EQ_INT(line_trace_misses(2, 1), 2);
  CHECK_EQ_INT(line_trace_misses(2, 4), 8);
  CHECK_EQ_INT(line_trace_misses(2, 0.5), 1);
  CHECK_EQ_INT(line_trace_misses(0, 4), 0);
  LineSpan s;
  memset(&s, 0, sizeof s);
  s.x0 = 0.5f; s.y0 = 0.5f; s.x1 = 40.5f; s.y1 = 0.5f;
  s.px1 = 40; s.nsteps = 41;
  s.real0 = s.real1 = 1;
  unsigned char vis[41];
  memset(vis, 1, sizeof vis);
  memset(vis + 16, 0, 8);   /* 8 hidden steps */
  LineSeg seg[8];
  CHECK_EQ_INT(line_trace_span(&s, vis, line_trace_misses(2, 4), seg), 1);
  CHECK_EQ_INT(line_trace_span(&s, vis, line_trace_misses(2, 2), seg), 2);
}

/* An outline with a nearer part of the model just inside it (a spider's
** thigh inside its shin, a face seen edge-on beside a silhouette): the
** top edge of a quad lies at image row 100.2, and a nearer quad covers the
** rows from 100.45 down. The centres of the pixels the edge crosses (row
** 100.5) fall on the nearer quad; the edge's own line does not. Tested on
** its line, the whole edge shows. */
TEST(outline_beside_nearer_part) {
  /* ortho, 80 px a unit: image row r is world y = 1.25 - r / 80 */
  double top = 1.25 - 100.2 / 80, inner = 1.25 - 100.45 / 80;
  Mesh *a = make_quad(v3(-1, -1, 0), v3(1, -1, 0), v3(1, top, 0), v3(-1, top, 0));
  Mesh *b = make_quad(v3(-0.8, -1, 0.5), v3(0.8, -1, 0.5), v3(0.8, inner, 0.5), v3(-0.8, inner, 0.5));
  SceneLines l = lines_of(EDGE_BOUNDARY);
  LineObject o[2] = {object_of(a, &l, 0), object_of(b, NULL, 1)};
  Camera cam = make_camera(v3(0, 0, 4), v3(0, 0, 0), 1, 2.5, 200, 200, v3(-1.2, -1, 0), v3(1.2, 1, 0.5));
  LineEdges ed;
  LineRef ref;
  line_edges_build(&ed, o, 2, &cam, 1);
  line_ref_build(&ref, &ed, o, 200, 200, 1);
  int id = ed.obj[0].id[find_edge(a, 2, 3)];
  CHECK(id > 0);
  if (id > 0) {
    const LineSpan *sp = &ref.span[id - 1];
    CHECK_NEAR(sp->y0, 100.2, 1e-3);
    CHECK(sp->nsteps > 150);
    int shown = 0;
    for (int k = 0; k < sp->nsteps; k++) shown += line_ref_vis(&ref, id)[k];
    CHECK_EQ_INT(shown, sp->nsteps);
  }
  line_ref_free(&ref);
  line_edges_free(&ed);
  mesh_destroy(a);
  mesh_destroy(b);
}

/* ---- linking ---------------------------------------------------------------- */

/* Polylines of the silhouette of a sphere of 96 x 48 faces drawn small
** (radius ~10 px), where many silhouette edges are shorter than a pixel.
** Drawn as ids into pixels (the paper) most of them lose every pixel to a
** neighbour, and direct links break the outline into pieces; tested each
** on its own line, none is lost, and direct links hold the outline. */
static int sphere_polylines(int link_depth, int ref_w, LineStats *st) {
  Mesh *m = make_sphere(v3(0, 0, 0), 1, 96, 48);
  SceneLines l = lines_of(EDGE_SILHOUETTE);
  l.link_depth = link_depth;
  l.link_angle = 60;
  LineObject o = object_of(m, &l, 0);
  Camera cam = make_camera(v3(0, -30, 8), v3(0, 0, 0), 0, 8, ref_w, ref_w, v3(-1, -1, -1), v3(1, 1, 1));
  char err[128];
  int ok = line_render(&o, 1, &cam, NULL, 1, st, NULL, err, sizeof err);
  CHECK(ok);
  mesh_destroy(m);
  return st->polylines;
}

TEST(link_depth_on_distant_mesh) {
  LineStats d1, d3;
  int p1 = sphere_polylines(1, 160, &d1), p3 = sphere_polylines(3, 160, &d3);
  CHECK_EQ_INT(d1.visible, d1.important);   /* no silhouette edge is lost */
  CHECK_EQ_INT(d1.visible, d3.visible);
  CHECK(p1 <= 4);
  CHECK(p3 <= p1);
  LineStats c1;
  int pc = sphere_polylines(1, 320, &c1);
  CHECK_EQ_INT(c1.visible, c1.important);
  CHECK(pc <= 4);
}

/* Links never cross objects: two quads touching along x = 0 give separate
** polylines though their boundary edges meet end to end in the image. */
TEST(links_stay_in_object) {
  Mesh *a = make_quad(v3(-1, -0.5, 0), v3(0, -0.5, 0), v3(0, 0.5, 0), v3(-1, 0.5, 0));
  Mesh *b = make_quad(v3(0, -0.5, 0), v3(1, -0.5, 0), v3(1, 0.5, 0), v3(0, 0.5, 0));
  SceneLines l = lines_of(EDGE_BOUNDARY);
  l.link_angle = 10;
  LineObject o[2] = {object_of(a, &l, 0), object_of(b, &l, 1)};
  Camera cam = make_camera(v3(0, 0, 4), v3(0, 0, 0), 1, 2.5, 200, 200, v3(-1, -1, 0), v3(1, 1, 0));
  LineEdges ed;
  LineRef ref;
  LineTrace tr;
  LinePolys p;
  line_edges_build(&ed, o, 2, &cam, 1);
  line_ref_build(&ref, &ed, o, 200, 200, 1);
  line_trace_build(&tr, &ref, &ed, 1, 1);
  line_link_build(&p, &ref, &tr, &ed);
  for (int k = 0; k < p.n; k++) {
    float xmin = 1e9f, xmax = -1e9f;
    for (int i = p.start[k]; i < p.start[k + 1]; i++) {
      xmin = fminf(xmin, p.pts[2 * i]);
      xmax = fmaxf(xmax, p.pts[2 * i]);
    }
    if (p.obj[k] == 0) CHECK(xmax <= 100.5f);
    else CHECK(xmin >= 99.5f);
  }
  /* the square outlines: 90° corners are refused at link_angle 10, so each
  ** side stands alone; with 100° each outline links around the corners */
  CHECK(p.n >= 6);
  line_polys_free(&p);
  l.link_angle = 100;
  line_link_build(&p, &ref, &tr, &ed);
  CHECK(p.n <= 4);
  line_polys_free(&p);
  line_trace_free(&tr);
  line_ref_free(&ref);
  line_edges_free(&ed);
  mesh_destroy(a);
  mesh_destroy(b);
}

/* ---- strokes ----------------------------------------------------------------- */

static LinePolys one_poly(const float *pts, int n) {
  LinePolys p;
  memset(&p, 0, sizeof p);
  p.n = 1;
  p.start = xmalloc(2 * sizeof *p.start);
  p.start[0] = 0; p.start[1] = n;
  p.pts = xmalloc((size_t)n * 2 * sizeof *p.pts);
  memcpy(p.pts, pts, (size_t)n * 2 * sizeof *p.pts);
  p.obj = xcalloc(1, sizeof *p.obj);
  p.npts = n;
  return p;
}

/* Ribs are perpendicular to v[i+1] - v[i-1] and, at a right angle, widen
** by the miter factor sqrt(2), unless miter_limit caps it. */
TEST(ribbon_ribs_and_miter) {
  float pts[6] = {10, 10, 30, 10, 30, 30};
  LinePolys p = one_poly(pts, 3);
  SceneLines l = lines_of(EDGE_SILHOUETTE);
  l.stroke = STROKE_RIBBON;
  l.width = 4;
  LineObject o = object_of(NULL, &l, 7);
  StrokeList *sl;
  char err[128];
  CHECK(stroke_build(&sl, &p, &o, 1, 1, err, sizeof err));
  CHECK_EQ_INT(sl->n, 1);
  const Stroke *st = &sl->s[0];
  /* end ribs: perpendicular to their one segment, half width 2 */
  CHECK_NEAR(fabs(st->left[1] - st->right[1]), 4, 1e-5);
  CHECK_NEAR(st->left[0], st->right[0], 1e-5);
  /* corner rib: along (1, -1) / sqrt 2, half length 2 sqrt 2 */
  double rx = st->left[2] - st->right[2], ry = st->left[3] - st->right[3];
  CHECK_NEAR(sqrt(rx * rx + ry * ry), 4 * sqrt(2), 1e-4);
  CHECK_NEAR(rx + ry, 0, 1e-4);
  stroke_list_free(sl);
  l.miter_limit = 1.2;
  CHECK(stroke_build(&sl, &p, &o, 1, 1, err, sizeof err));
  rx = sl->s[0].left[2] - sl->s[0].right[2]; ry = sl->s[0].left[3] - sl->s[0].right[3];
  CHECK_NEAR(sqrt(rx * rx + ry * ry), 4 * 1.2, 1e-4);
  stroke_list_free(sl);
  /* min_length drops short polylines (length 40 here) */
  l.min_length = 41;
  CHECK(stroke_build(&sl, &p, &o, 1, 1, err, sizeof err));
  CHECK_EQ_INT(sl->n, 0);
  stroke_list_free(sl);
  line_polys_free(&p);
}

/* A plain horizontal stroke of width 3 covers a column with ink summing to
** 3 pixels, full in the middle, none 3 pixels away; a ribbon of the same
** width with the solid texture does the same. */
TEST(stroke_coverage) {
  float pts[4] = {5, 16, 27, 16};
  LinePolys p = one_poly(pts, 2);
  for (int ribbon = 0; ribbon <= 1; ribbon++) {
    SceneLines l = lines_of(EDGE_SILHOUETTE);
    l.stroke = ribbon ? STROKE_RIBBON : STROKE_PLAIN;
    l.width = 3;
    l.texture = "solid";
    l.color = (Color){0, 0, 0, 1};
    LineObject o = object_of(NULL, &l, 0);
    StrokeList *sl;
    char err[128];
    CHECK(stroke_build(&sl, &p, &o, 1, 1, err, sizeof err));
    Image *img = image_create(32, 32, 4);
    for (int i = 0; i < 32 * 32 * 4; i++) img->data[i] = 1;
    stroke_render(sl, img, 1);
    double ink = 0;
    for (int y = 0; y < 32; y++) ink += 1 - img->data[(y * 32 + 16) * 4];
    CHECK_NEAR(ink, 3, 0.05);
    CHECK_NEAR(img->data[(16 * 32 + 16) * 4], 0, 1e-6);
    CHECK_NEAR(img->data[(19 * 32 + 16) * 4], 1, 1e-6);
    CHECK_NEAR(img->data[(16 * 32 + 16) * 4 + 3], 1, 1e-6);   /* alpha stays opaque */
    /* over a transparent pixel (unassociated alpha) ink keeps its colour
    ** and the coverage becomes the alpha */
    for (int i = 0; i < 32 * 32; i++) {
      img->data[4 * i] = 1; img->data[4 * i + 1] = img->data[4 * i + 2] = 0.5f; img->data[4 * i + 3] = 0;
    }
    stroke_render(sl, img, 1);
    int partial = 0;
    for (int y = 0; y < 32; y++) {
      const float *q = &img->data[(y * 32 + 16) * 4];
      if (q[3] > 0) CHECK_NEAR(q[0], 0, 1e-6);
      partial += q[3] > 0.01f && q[3] < 0.99f;
    }
    CHECK(partial >= 1);
    CHECK_NEAR(img->data[(16 * 32 + 16) * 4 + 3], 1, 1e-6);
    image_destroy(img);
    stroke_list_free(sl);
  }
  line_polys_free(&p);
}

/* The procedural ink stays in [0, 1], varies along a stroke and is keyed
** by its phases only. */
TEST(procedural_ink) {
  float ph[4] = {1.5f, 7.25f, 3.0f, 0};
  float lo = 1, hi = 0;
  for (int i = 0; i <= 200; i++) {
    float a = stroke_ink(ph, i * 0.5f, 100, 0.5f, 3);
    lo = fminf(lo, a); hi = fmaxf(hi, a);
    CHECK(a >= 0 && a <= 1);
  }
  CHECK(hi - lo > 0.1f);
  CHECK(stroke_ink(ph, 50, 100, 0.5f, 3) == stroke_ink(ph, 50, 100, 0.5f, 3));
}

/* ---- whole stage -------------------------------------------------------------- */

static unsigned long long image_hash(const Image *img) {
  unsigned long long h = 1469598103934665603ULL;
  const unsigned char *b = (const unsigned char *)img->data;
  size_t n = (size_t)img->width * img->height * img->channels * sizeof(float);
  for (size_t i = 0; i < n; i++) h = (h ^ b[i]) * 1099511628211ULL;
  return h;
}

/* Same scene, same bytes at 1, 2 and 8 workers, plain and ribbon. */
TEST(deterministic_across_threads) {
  Mesh *sph = make_sphere(v3(0.4, 0, 0), 1, 40, 20), *cube = make_cube();
  for (int ribbon = 0; ribbon <= 1; ribbon++) {
    SceneLines l = lines_of(EDGE_SILHOUETTE | EDGE_CREASE | EDGE_BOUNDARY);
    l.stroke = ribbon ? STROKE_RIBBON : STROKE_PLAIN;
    l.width = 3;
    LineObject o[2] = {object_of(sph, &l, 0), object_of(cube, &l, 1)};
    o[1].object_to_world = m4_mul(m4_translate(v3(-1, 0.5, 0)), m4_rotate_xyz(v3(10, 20, 30)));
    Camera cam = make_camera(v3(2, -7, 3), v3(0, 0, 0), 0, 40, 160, 120, v3(-2.5, -2, -2), v3(1.5, 2, 2));
    unsigned long long h[3];
    int threads[3] = {1, 2, 8};
    LineStats st[3];
    for (int k = 0; k < 3; k++) {
      Image *img = image_create(160, 120, 4);
      for (int i = 0; i < 160 * 120 * 4; i++) img->data[i] = 1;
      char err[128];
      CHECK(line_render(o, 2, &cam, img, threads[k], &st[k], NULL, err, sizeof err));
      h[k] = image_hash(img);
      image_destroy(img);
    }
    CHECK(st[0].strokes > 4);
    CHECK(h[0] == h[1]);
    CHECK(h[0] == h[2]);
    CHECK_EQ_INT(st[0].polylines, st[2].polylines);
  }
  mesh_destroy(sph);
  mesh_destroy(cube);
}

/* No object with lines: nothing is allocated or drawn. */
TEST(empty_scene) {
  Mesh *cube = make_cube();
  LineObject o = object_of(cube, NULL, 0);
  Camera cam = make_camera(v3(3, 3, 3), v3(0, 0, 0), 0, 50, 1920, 1080, v3(-1, -1, -1), v3(1, 1, 1));
  LineStats st;
  char err[128];
  CHECK(line_render(&o, 1, &cam, NULL, 1, &st, NULL, err, sizeof err));
  CHECK_EQ_INT(st.objects, 0);
  CHECK_EQ_INT(st.ref_width, 0);
  mesh_destroy(cube);
}

/* ref_scale 2 draws the same outline, in output pixels. */
TEST(reference_scale) {
  Mesh *cube = make_cube();
  SceneLines l = lines_of(EDGE_SILHOUETTE | EDGE_CREASE);
  LineObject o = object_of(cube, &l, 0);
  Camera cam = make_camera(v3(3, 3, 3), v3(0, 0, 0), 1, 4, 100, 100, v3(-1, -1, -1), v3(1, 1, 1));
  StrokeList *a, *b;
  LineStats sa, sb;
  char err[128];
  CHECK(line_render(&o, 1, &cam, NULL, 1, &sa, &a, err, sizeof err));
  l.ref_scale = 2;
  CHECK(line_render(&o, 1, &cam, NULL, 1, &sb, &b, err, sizeof err));
  CHECK_EQ_INT(sb.ref_width, 200);
  CHECK_EQ_INT(sa.visible, 9);   /* hexagon + the three front creases */
  CHECK_EQ_INT(sb.visible, 9);
  float ax0 = 1e9f, ax1 = -1e9f, bx0 = 1e9f, bx1 = -1e9f;
  for (int k = 0; k < a->n; k++)
    for (int i = 0; i < a->s[k].npts; i++) { ax0 = fminf(ax0, a->s[k].pts[2 * i]); ax1 = fmaxf(ax1, a->s[k].pts[2 * i]); }
  for (int k = 0; k < b->n; k++)
    for (int i = 0; i < b->s[k].npts; i++) { bx0 = fminf(bx0, b->s[k].pts[2 * i]); bx1 = fmaxf(bx1, b->s[k].pts[2 * i]); }
  CHECK_NEAR(ax0, bx0, 0.75);
  CHECK_NEAR(ax1, bx1, 0.75);
  stroke_list_free(a);
  stroke_list_free(b);
  mesh_destroy(cube);
}


int main(void) {
  RUN(cube_corner_edges);
  RUN(crease_threshold_and_sharpness);
  RUN(boundary_and_face_edges);
  RUN(half_hidden_edge);
  RUN(max_misses_bridges_hidden_parts);
  RUN(visible_and_hidden);
  RUN(one_pixel_segments);
  RUN(misses_in_output_pixels);
  RUN(outline_beside_nearer_part);
  RUN(link_depth_on_distant_mesh);
  RUN(links_stay_in_object);
  RUN(ribbon_ribs_and_miter);
  RUN(stroke_coverage);
  RUN(procedural_ink);
  RUN(deterministic_across_threads);
  RUN(empty_scene);
  RUN(reference_scale);
  return unit_done();
}
