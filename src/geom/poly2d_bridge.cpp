/*
** The 2D polygon bridge (C++17 behind poly2d_bridge.h): Clipper for
** booleans, fill rules and offsets, CGAL's constrained Delaunay
** triangulation for triangles. Every entry point catches every exception
** and turns it into a 0 result and a message.
*/
#include "poly2d_bridge.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Random.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <clipper.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <list>
#include <new>
#include <vector>

namespace CL = ClipperLib;

namespace {

// Scaling to Clipper's integers -------------------------------------------

// The largest coordinate becomes about 2^46: far inside Clipper's 2^62
// range (offsets of up to 2^15 times the extent stay inside it too), and
// 2^-47 of the extent is the most a point moves.
const int SCALE_BITS = 46;

struct Scale {
  double to_int, to_real;
};

// One power of two for every point of in[0 .. n-1] (and margin more).
Scale scale_for(const SumiP2dPolys *in, int n, double margin) {
  double m = std::fabs(margin);
  for (int s = 0; s < n; s++)
    for (int i = 0; i < 2 * in[s].start[in[s].ncontours]; i++) m = std::max(m, std::fabs(in[s].xy[i]));
  int e = 0;
  if (m > 0) std::frexp(m, &e);   // m < 2^e
  Scale sc;
  sc.to_int = std::ldexp(1.0, SCALE_BITS - e);
  sc.to_real = std::ldexp(1.0, e - SCALE_BITS);
  return sc;
}

CL::Paths to_paths(const SumiP2dPolys &p, const Scale &sc) {
  CL::Paths out(p.ncontours);
  for (int c = 0; c < p.ncontours; c++)
    for (int i = p.start[c]; i < p.start[c + 1]; i++)
      out[c].push_back(CL::IntPoint((CL::cInt)std::llround(p.xy[2 * i] * sc.to_int),
                                    (CL::cInt)std::llround(p.xy[2 * i + 1] * sc.to_int)));
  return out;
}

// The tree's contours in order: each outer contour (counter-clockwise),
// then its holes (clockwise), then the islands inside those holes.
void collect(const CL::PolyNode *node, const Scale &sc, std::vector<int> &start, std::vector<double> &xy) {
  for (const CL::PolyNode *k : node->Childs) {
    CL::Path path = k->Contour;
    if (path.size() >= 3) {
      if (CL::Orientation(path) == k->IsHole()) std::reverse(path.begin(), path.end());
      for (const CL::IntPoint &q : path) {
        xy.push_back((double)q.X * sc.to_real);
        xy.push_back((double)q.Y * sc.to_real);
      }
      start.push_back((int)(xy.size() / 2));
    }
  }
  for (const CL::PolyNode *k : node->Childs) collect(k, sc, start, xy);
}

// Fills out from tree (malloc'd arrays).
void tree_out(const CL::PolyTree &tree, const Scale &sc, SumiP2dPolys *out) {
  std::vector<int> start(1, 0);
  std::vector<double> xy;
  collect(&tree, sc, start, xy);
  out->ncontours = (int)start.size() - 1;
  out->start = (int *)std::malloc(start.size() * sizeof(int));
  out->xy = (double *)std::malloc(std::max<size_t>(xy.size(), 1) * sizeof(double));
  if (!out->start || !out->xy) throw std::bad_alloc();
  std::memcpy(out->start, start.data(), start.size() * sizeof(int));
  if (!xy.empty()) std::memcpy(out->xy, xy.data(), xy.size() * sizeof(double));
}

void fail(char *err, size_t errlen, const char *what) {
  if (errlen) std::snprintf(err, errlen, "%s", what);
}

// Triangulation -------------------------------------------------------------

struct VertexInfo {
  int index = -1;     // the input point it is (its first occurrence), or -1
};

struct FaceInfo {
  int nesting = -1;   // how many constraints a path from outside crosses to reach it
};

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, K> Vb;
typedef CGAL::Constrained_triangulation_face_base_2<K> Cfb;
typedef CGAL::Triangulation_face_base_with_info_2<FaceInfo, K, Cfb> Fb;
typedef CGAL::Triangulation_data_structure_2<Vb, Fb> Tds;
typedef CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag> Cdt;

// Give every face its nesting level: flood from the outside, one level
// deeper each time a constrained edge is crossed. Faces of odd level lie
// inside the polygons.
void mark_nesting(Cdt &cdt) {
  std::list<Cdt::Edge> border;   // constrained edges seen, to cross later
  std::vector<Cdt::Face_handle> queue;
  auto flood = [&](Cdt::Face_handle start, int level) {
    if (start->info().nesting != -1) return;
    queue.assign(1, start);
    while (!queue.empty()) {
      Cdt::Face_handle f = queue.back();
      queue.pop_back();
      if (f->info().nesting != -1) continue;
      f->info().nesting = level;
      for (int i = 0; i < 3; i++) {
        Cdt::Face_handle g = f->neighbor(i);
        if (g->info().nesting != -1) continue;
        if (cdt.is_constrained(Cdt::Edge(f, i))) border.push_back(Cdt::Edge(f, i));
        else queue.push_back(g);
      }
    }
  };
  flood(cdt.infinite_face(), 0);
  while (!border.empty()) {
    Cdt::Edge e = border.front();
    border.pop_front();
    Cdt::Face_handle g = e.first->neighbor(e.second);
    if (g->info().nesting == -1) flood(g, e.first->info().nesting + 1);
  }
}

void triangulate(const SumiP2dPolys *in, std::vector<double> &pts, std::vector<int> &tris) {
  // the triangulation's insertion order shuffles with CGAL's default
  // random source, seeded from the clock; points on one circle (a regular
  // polygon) have many Delaunay triangulations, so a fixed seed at every
  // call makes the same shape give the same triangles in every run
  CGAL::get_default_random() = CGAL::Random(0);
  Cdt cdt;
  int n = in->start[in->ncontours];
  pts.assign(in->xy, in->xy + 2 * n);
  for (int c = 0; c < in->ncontours; c++) {
    std::vector<Cdt::Vertex_handle> vh;
    for (int i = in->start[c]; i < in->start[c + 1]; i++) {
      Cdt::Vertex_handle v = cdt.insert(K::Point_2(in->xy[2 * i], in->xy[2 * i + 1]));
      if (v->info().index < 0) v->info().index = i;
      vh.push_back(v);
    }
    for (size_t i = 0; i < vh.size(); i++) {
      Cdt::Vertex_handle a = vh[i], b = vh[(i + 1) % vh.size()];
      if (a != b) cdt.insert_constraint(a, b);
    }
  }
  // a vertex the triangulation added where constraints crossed
  for (Cdt::Finite_vertices_iterator v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v)
    if (v->info().index < 0) {
      v->info().index = (int)(pts.size() / 2);
      pts.push_back(v->point().x());
      pts.push_back(v->point().y());
    }
  mark_nesting(cdt);
  for (Cdt::Finite_faces_iterator f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
    if (f->info().nesting % 2 == 1)
      for (int k = 0; k < 3; k++) tris.push_back(f->vertex(k)->info().index);
}

}  // namespace

extern "C" {

void sumi_p2d_free(SumiP2dPolys *p) {
  std::free(p->start);
  std::free(p->xy);
  p->start = nullptr;
  p->xy = nullptr;
  p->ncontours = 0;
}

int sumi_p2d_boolean(SumiP2dOp op, const SumiP2dPolys *in, int n, SumiP2dFill fill, SumiP2dPolys *out, char *err,
                     size_t errlen) {
  *out = SumiP2dPolys{0, nullptr, nullptr};
  try {
    Scale sc = scale_for(in, n, 0);
    CL::PolyFillType ft = fill == SUMI_P2D_EVEN_ODD ? CL::pftEvenOdd : CL::pftNonZero;
    CL::PolyTree tree;
    CL::Clipper c;
    c.StrictlySimple(true);
    if (op == SUMI_P2D_INTERSECTION && n > 1) {
      // fold left: what the first covers, cut by each of the others
      CL::Paths acc = to_paths(in[0], sc);
      for (int s = 1; s < n; s++) {
        CL::Clipper k;
        k.AddPaths(acc, CL::ptSubject, true);
        k.AddPaths(to_paths(in[s], sc), CL::ptClip, true);
        acc.clear();
        k.Execute(CL::ctIntersection, acc, ft, ft);
      }
      c.AddPaths(acc, CL::ptSubject, true);
      c.Execute(CL::ctUnion, tree, CL::pftNonZero, CL::pftNonZero);
    } else {
      for (int s = 0; s < n; s++)
        c.AddPaths(to_paths(in[s], sc), op == SUMI_P2D_DIFFERENCE && s > 0 ? CL::ptClip : CL::ptSubject, true);
      c.Execute(op == SUMI_P2D_DIFFERENCE ? CL::ctDifference : CL::ctUnion, tree, ft, ft);
    }
    tree_out(tree, sc, out);
    return 1;
  } catch (const std::exception &e) {
    sumi_p2d_free(out);
    fail(err, errlen, e.what());
  } catch (...) {
    sumi_p2d_free(out);
    fail(err, errlen, "unknown failure in Clipper");
  }
  return 0;
}

int sumi_p2d_offset(const SumiP2dPolys *in, double delta, SumiP2dJoin join, double arc_tolerance,
                    SumiP2dPolys *out, char *err, size_t errlen) {
  *out = SumiP2dPolys{0, nullptr, nullptr};
  try {
    Scale sc = scale_for(in, 1, delta);
    CL::JoinType jt = join == SUMI_P2D_JOIN_ROUND ? CL::jtRound : join == SUMI_P2D_JOIN_MITER ? CL::jtMiter : CL::jtSquare;
    CL::ClipperOffset co(2.0, std::max(arc_tolerance * sc.to_int, 0.25));
    co.AddPaths(to_paths(*in, sc), jt, CL::etClosedPolygon);
    CL::Paths grown;
    co.Execute(grown, delta * sc.to_int);
    CL::Clipper c;   // into the tree form, strictly simple
    c.StrictlySimple(true);
    c.AddPaths(grown, CL::ptSubject, true);
    CL::PolyTree tree;
    c.Execute(CL::ctUnion, tree, CL::pftNonZero, CL::pftNonZero);
    tree_out(tree, sc, out);
    return 1;
  } catch (const std::exception &e) {
    sumi_p2d_free(out);
    fail(err, errlen, e.what());
  } catch (...) {
    sumi_p2d_free(out);
    fail(err, errlen, "unknown failure in Clipper");
  }
  return 0;
}

int sumi_p2d_triangulate(const SumiP2dPolys *in, double **pts_out, int *npts, int **tris_out, int *ntris, char *err,
                         size_t errlen) {
  *pts_out = nullptr;
  *tris_out = nullptr;
  *npts = *ntris = 0;
  try {
    std::vector<double> pts;
    std::vector<int> tris;
    triangulate(in, pts, tris);
    *pts_out = (double *)std::malloc(std::max<size_t>(pts.size(), 1) * sizeof(double));
    *tris_out = (int *)std::malloc(std::max<size_t>(tris.size(), 1) * sizeof(int));
    if (!*pts_out || !*tris_out) throw std::bad_alloc();
    if (!pts.empty()) std::memcpy(*pts_out, pts.data(), pts.size() * sizeof(double));
    if (!tris.empty()) std::memcpy(*tris_out, tris.data(), tris.size() * sizeof(int));
    *npts = (int)(pts.size() / 2);
    *ntris = (int)(tris.size() / 3);
    return 1;
  } catch (const std::exception &e) {
    fail(err, errlen, e.what());
  } catch (...) {
    fail(err, errlen, "unknown failure in the triangulation");
  }
  std::free(*pts_out);
  std::free(*tris_out);
  *pts_out = nullptr;
  *tris_out = nullptr;
  return 0;
}

}  // extern "C"
