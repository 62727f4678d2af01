/*
** The CSG bridge (C++17 behind csg_bridge.h): builds CGAL Surface_meshes
** from plain arrays, checks them for self-intersections, and folds them
** with corefinement booleans, tracking through a corefinement visitor
** which input triangle each result triangle was cut from. The kernel has
** exact predicates and inexact (double) constructions: every decision
** (which side, which order, coplanar or not) is exact, so coincident faces
** are handled; the new points on intersection curves are rounded to
** doubles. Every entry point catches every exception and turns it into a
** 0 result and a message.
*/
#include "csg_bridge.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Random.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iterator>
#include <new>
#include <string>
#include <vector>

namespace PMP = CGAL::Polygon_mesh_processing;

namespace {

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef K::Point_3 Point;
typedef CGAL::Surface_mesh<Point> SM;

}  // namespace

// The boxes corefinement finds crossings with (one mesh's faces against
// the other's edges, CGAL 5.5's intersection_impl.h) are named by their
// addresses (ID_FROM_BOX_ADDRESS), and box_intersection_d breaks ties
// between boxes with equal coordinates by name: which of the two boxes'
// vectors malloc placed lower decided the order crossings were found in,
// hence the nodes' order and how a face cut along points on a circle was
// triangulated. Whatever ran before (fontconfig loading a font) moved the
// heap, so a scene's triangles changed from run to run. This box, for the
// Surface_mesh halfedges corefinement uses, is named by a counter instead
// (ID_EXPLICIT): the faces' boxes are made before the edges', so the ties
// go as when the faces' vector lay lower, in every run.
namespace CGAL {
namespace Box_intersection_d {
template <>
class Box_with_info_d<double, 3, SM::Halfedge_index, ID_FROM_BOX_ADDRESS> : public Box_d<double, 3, ID_EXPLICIT> {
  SM::Halfedge_index m_info;

public:
  typedef Box_d<double, 3, ID_EXPLICIT> Base;
  typedef double NT;
  typedef SM::Halfedge_index Info;
  Box_with_info_d() {}
  Box_with_info_d(const Bbox_3 &b, Info h) : Base(b), m_info(h) {}
  Info info() const { return m_info; }
};
}  // namespace Box_intersection_d
}  // namespace CGAL

namespace {
typedef SM::Face_index Face;
typedef SM::Property_map<Face, int> SrcMap;

const char *const SRC = "f:sumi_src";   // the face property: the input triangle

int fail(char *err, size_t errlen, const char *fmt, ...) {
  if (err && errlen) {
    va_list ap;
    va_start(ap, fmt);
    std::vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
  }
  return 0;
}

SrcMap src_map(const SM &m) { return m.property_map<Face, int>(SRC).first; }

// Carries each face's source through the splits and copies corefinement
// makes: a face cut into subfaces gives them its source; a face copied
// from one mesh into another keeps it.
struct SourceVisitor : PMP::Corefinement::Default_visitor<SM> {
  int cur = -1;
  void before_subface_creations(Face f, SM &tm) { cur = src_map(tm)[f]; }
  void after_subface_created(Face f, SM &tm) { src_map(tm)[f] = cur; }
  void after_face_copy(Face f_old, const SM &from, Face f_new, SM &to) { src_map(to)[f_new] = src_map(from)[f_old]; }
};

// Input m as a Surface_mesh whose faces' sources are first, first + 1, ...
void build(const SumiCsgMesh &m, int first, SM &out) {
  std::vector<Point> pts;
  std::vector<std::vector<std::size_t>> polys;
  std::vector<std::size_t> id((size_t)m.nverts, SIZE_MAX);   // only the points a triangle uses:
  polys.reserve((size_t)m.ntris);                             // a mesh has no lone vertices
  for (int t = 0; t < m.ntris; t++) {
    std::vector<std::size_t> f(3);
    for (int k = 0; k < 3; k++) {
      int v = m.tri[3 * t + k];
      if (id[(size_t)v] == SIZE_MAX) {
        id[(size_t)v] = pts.size();
        pts.emplace_back(m.xyz[3 * v], m.xyz[3 * v + 1], m.xyz[3 * v + 2]);
      }
      f[(size_t)k] = id[(size_t)v];
    }
    polys.push_back(f);
  }
  if (!PMP::is_polygon_soup_a_polygon_mesh(polys)) throw std::runtime_error("is not a manifold surface");
  PMP::polygon_soup_to_polygon_mesh(pts, polys, out);
  SrcMap s = out.add_property_map<Face, int>(SRC, -1).first;
  // polygon_soup_to_polygon_mesh adds the faces in the soup's order
  int t = first;
  for (Face f : out.faces()) s[f] = t++;
  PMP::remove_degenerate_faces(out);   // slivers of a tessellation or of an earlier boolean
}

// Where input m first intersects itself: the centre of one triangle of
// the first pair found, written into at; 0 when it does not.
int self_intersection(const SM &m, double at[3]) {
  if (!PMP::does_self_intersect(m)) return 0;
  std::vector<std::pair<Face, Face>> pairs;
  PMP::self_intersections(m, std::back_inserter(pairs));
  at[0] = at[1] = at[2] = 0;
  if (pairs.empty()) return 1;
  int k = 0;
  for (auto v : m.vertices_around_face(m.halfedge(pairs[0].first))) {
    const Point &p = m.point(v);
    at[0] += p.x(), at[1] += p.y(), at[2] += p.z();
    k++;
  }
  for (int i = 0; i < 3 && k; i++) at[i] /= k;
  return 1;
}

bool apply(SumiCsgOp op, SM &acc, SM &b) {
  SourceVisitor vis;
  auto np = CGAL::parameters::visitor(vis);
  bool ok;
  switch (op) {
  case SUMI_CSG_UNION: ok = PMP::corefine_and_compute_union(acc, b, acc, np); break;
  case SUMI_CSG_DIFFERENCE: ok = PMP::corefine_and_compute_difference(acc, b, acc, np); break;
  default: ok = PMP::corefine_and_compute_intersection(acc, b, acc, np); break;
  }
  // new points on the curves, rounded, can leave zero-area triangles
  // (three points on one line): the result is cleaner without them, and
  // a boolean of it would count them as the surface meeting itself
  if (ok) PMP::remove_degenerate_faces(acc);
  return ok;
}

void result(const SM &m, SumiCsgResult *out) {
  std::vector<int> id(m.number_of_vertices() + m.number_of_removed_vertices(), -1);
  int nv = 0;
  for (auto v : m.vertices()) id[v] = nv++;
  int nt = (int)m.number_of_faces();
  out->xyz = (double *)std::malloc(sizeof(double) * 3 * (size_t)std::max(nv, 1));
  out->tri = (int *)std::malloc(sizeof(int) * 3 * (size_t)std::max(nt, 1));
  out->src = (int *)std::malloc(sizeof(int) * (size_t)std::max(nt, 1));
  if (!out->xyz || !out->tri || !out->src) throw std::bad_alloc();
  for (auto v : m.vertices()) {
    const Point &p = m.point(v);
    double *q = out->xyz + 3 * id[v];
    q[0] = p.x(), q[1] = p.y(), q[2] = p.z();
  }
  SrcMap s = src_map(m);
  int t = 0;
  for (Face f : m.faces()) {
    int k = 0;
    for (auto v : m.vertices_around_face(m.halfedge(f)))
      if (k < 3) out->tri[3 * t + k++] = id[v];
    if (k != 3) throw std::runtime_error("the result has a face that is not a triangle");
    if (s[f] < 0) throw std::runtime_error("a face of the result lost track of its source");
    out->src[t++] = s[f];
  }
  out->nverts = nv;
  out->ntris = nt;
}

}  // namespace

extern "C" {

void sumi_csg_free(SumiCsgResult *r) {
  if (!r) return;
  std::free(r->xyz);
  std::free(r->tri);
  std::free(r->src);
  *r = SumiCsgResult{0, nullptr, 0, nullptr, nullptr};
}

int sumi_csg_run(SumiCsgOp op, const SumiCsgMesh *in, int n, SumiCsgResult *out, int *bad, char *err,
                 size_t errlen) {
  *out = SumiCsgResult{0, nullptr, 0, nullptr, nullptr};
  int dummy;
  if (!bad) bad = &dummy;
  *bad = -1;
  try {
    // CGAL's default random source (the box intersections' choices) is
    // seeded from the clock: from a fixed seed at every call, the same
    // scene gives the same triangles in every run, whatever came before
    CGAL::get_default_random() = CGAL::Random(0);
    std::vector<SM> m((size_t)n);
    int first = 0;
    for (int k = 0; k < n; k++) {
      *bad = k;
      build(in[k], first, m[(size_t)k]);
      first += in[k].ntris;
      double at[3];
      if (self_intersection(m[(size_t)k], at))
        return fail(err, errlen, "intersects itself (near [%g, %g, %g])", at[0], at[1], at[2]);
    }
    *bad = -1;
    for (int k = 1; k < n; k++)
      if (!apply(op, m[0], m[(size_t)k]))
        return fail(err, errlen, "the result would not be a manifold solid (shapes that touch only along an edge "
                                 "or at a point); move one a little");
    result(m[0], out);
    return 1;
  } catch (const CGAL::Failure_exception &e) {   // a precondition of CGAL's, in one line
    sumi_csg_free(out);
    fail(err, errlen, "is not a mesh CGAL can take (%s)", e.expression().c_str());
  } catch (const std::exception &e) {
    sumi_csg_free(out);
    fail(err, errlen, "%s", e.what());
  } catch (...) {
    sumi_csg_free(out);
    fail(err, errlen, "unknown failure in CGAL");
  }
  return 0;
}

}  // extern "C"
