/*
** The OpenSubdiv bridge (C++17 behind osd_bridge.h): builds Far topology
** refiners from plain arrays, refines them uniformly (positions and limit
** positions in double precision), and evaluates exact limit surfaces of
** single faces with Bfr. Every entry point catches every exception and
** turns it into a 0 result and a message; OpenSubdiv's own error and
** warning callbacks are captured into the same message.
*/
#include "osd_bridge.h"

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/far/error.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefiner.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <mutex>
#include <new>
#include <string>
#include <vector>

extern "C" {
#include "../base/tasks.h"
}

using namespace OpenSubdiv;

namespace {

// Errors ------------------------------------------------------------------

// What OpenSubdiv reported through its callbacks during the current call.
thread_local std::string osd_message;

void on_osd_error(Far::ErrorType, const char *message) {
  if (osd_message.empty()) osd_message = message ? message : "unknown OpenSubdiv error";
}

void on_osd_warning(const char *message) {
  if (osd_message.empty() && message) osd_message = message;
}

// Install the callbacks once (whichever thread comes first); clear what an
// earlier call on this thread left.
void begin_call() {
  static std::once_flag installed;
  std::call_once(installed, [] {
    Far::SetErrorCallback(on_osd_error);
    Far::SetWarningCallback(on_osd_warning);
  });
  osd_message.clear();
}

int fail(char *err, size_t errlen, const char *fmt, ...) {
  if (err && errlen > 0) {
    va_list ap;
    va_start(ap, fmt);
    std::vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
  }
  return 0;
}

// An entry point's body, with every exception turned into 0 and a message
// (none may cross into C). oom names what ran out of memory.
template <class Body> int guarded(Body body, char *err, size_t errlen, const char *oom) {
  try {
    begin_call();
    return body();
  } catch (std::bad_alloc const &) {
    return fail(err, errlen, "%s", oom);
  } catch (std::exception const &e) {
    return fail(err, errlen, "OpenSubdiv: %s", e.what());
  } catch (...) {
    return fail(err, errlen, "OpenSubdiv: unknown exception");
  }
}

// Points as Far's primvar templates want them -------------------------------

// (No initialiser: Far clears each point before it adds to it, so large
// arrays of them need not be zeroed first.)
struct Point {
  double p[3];
  Point() {}
  Point(double x, double y, double z) : p{x, y, z} {}
  void Clear(void * = nullptr) { p[0] = p[1] = p[2] = 0; }
  void AddWithWeight(Point const &src, double w) {
    p[0] += w * src.p[0];
    p[1] += w * src.p[1];
    p[2] += w * src.p[2];
  }
};

// Views a packed double array (3 a point) as Points, for read access.
struct PointView {
  const double *data;
  Point const &operator[](int i) const { return *reinterpret_cast<Point const *>(data + 3 * i); }
};

static_assert(sizeof(Point) == 3 * sizeof(double), "Point must be three packed doubles");

// Points written straight into a malloc'd array of 3 * n doubles.
struct PointOut {
  double *data;
  Point &operator[](int i) { return *reinterpret_cast<Point *>(data + 3 * i); }
  Point const &operator[](int i) const { return *reinterpret_cast<Point const *>(data + 3 * i); }
};

double *alloc_points(size_t n) {
  double *p = static_cast<double *>(std::malloc(n ? 3 * n * sizeof(double) : 1));
  if (!p) throw std::bad_alloc();
  return p;
}

Sdc::SchemeType scheme_type(SumiOsdScheme s) {
  switch (s) {
    case SUMI_OSD_LOOP: return Sdc::SCHEME_LOOP;
    case SUMI_OSD_BILINEAR: return Sdc::SCHEME_BILINEAR;
    default: return Sdc::SCHEME_CATMARK;
  }
}

Sdc::Options::VtxBoundaryInterpolation boundary_type(SumiOsdBoundary b) {
  switch (b) {
    case SUMI_OSD_BOUNDARY_NONE: return Sdc::Options::VTX_BOUNDARY_NONE;
    case SUMI_OSD_BOUNDARY_EDGE_ONLY: return Sdc::Options::VTX_BOUNDARY_EDGE_ONLY;
    default: return Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER;
  }
}

}  // namespace

// The handle ----------------------------------------------------------------

struct SumiOsdMesh {
  // Copies of the caller's topology (the descriptor points into these).
  std::vector<int> face_size, face_index, crease_verts, corner_verts;
  std::vector<float> crease_sharpness, corner_sharpness;
  int nverts = 0;
  SumiOsdScheme scheme = SUMI_OSD_CATMARK;
  SumiOsdBoundary boundary = SUMI_OSD_BOUNDARY_EDGE_AND_CORNER;
  std::unique_ptr<Far::TopologyRefiner> base;                  // never refined
  std::unique_ptr<Bfr::RefinerSurfaceFactory<>> factory;       // over base
};

namespace {

// The handle's copies seen as the topology they were made from.
SumiOsdTopology topology_of(SumiOsdMesh const &m) {
  SumiOsdTopology t;
  t.nverts = m.nverts;
  t.nfaces = (int)m.face_size.size();
  t.face_size = m.face_size.data();
  t.face_index = m.face_index.data();
  t.ncreases = (int)m.crease_sharpness.size();
  t.crease_verts = m.crease_verts.data();
  t.crease_sharpness = m.crease_sharpness.data();
  t.ncorners = (int)m.corner_sharpness.size();
  t.corner_verts = m.corner_verts.data();
  t.corner_sharpness = m.corner_sharpness.data();
  t.scheme = m.scheme;
  t.boundary = m.boundary;
  return t;
}

Far::TopologyRefiner *make_refiner(SumiOsdTopology const &t) {
  Far::TopologyDescriptor d;
  d.numVertices = t.nverts;
  d.numFaces = t.nfaces;
  d.numVertsPerFace = t.face_size;
  d.vertIndicesPerFace = t.face_index;
  d.numCreases = t.ncreases;
  d.creaseVertexIndexPairs = t.crease_verts;
  d.creaseWeights = t.crease_sharpness;
  d.numCorners = t.ncorners;
  d.cornerVertexIndices = t.corner_verts;
  d.cornerWeights = t.corner_sharpness;
  Sdc::Options sdc;
  sdc.SetVtxBoundaryInterpolation(boundary_type(t.boundary));
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  return Factory::Create(d, Factory::Options(scheme_type(t.scheme), sdc));
}

// The checks OpenSubdiv does not make itself (an index out of range would
// be read out of bounds there).
int check_topology(const SumiOsdTopology *t, char *err, size_t errlen) {
  if (t->nverts < 1 || t->nfaces < 1)
    return fail(err, errlen, "mesh has %d vertices and %d faces; it needs at least one face",
                t->nverts, t->nfaces);
  long k = 0;
  for (int f = 0; f < t->nfaces; f++) {
    int n = t->face_size[f];
    if (n < 3) return fail(err, errlen, "face %d has %d vertices; a face needs at least 3", f, n);
    if (t->scheme == SUMI_OSD_LOOP && n != 3)
      return fail(err, errlen, "face %d has %d vertices; the loop scheme takes triangles only", f, n);
    for (int i = 0; i < n; i++, k++) {
      int v = t->face_index[k];
      if (v < 0 || v >= t->nverts)
        return fail(err, errlen, "face %d refers to vertex %d; the mesh has %d vertices", f, v,
                    t->nverts);
    }
  }
  for (int c = 0; c < t->ncreases; c++) {
    int a = t->crease_verts[2 * c], b = t->crease_verts[2 * c + 1];
    float s = t->crease_sharpness[c];
    if (a < 0 || a >= t->nverts || b < 0 || b >= t->nverts || a == b)
      return fail(err, errlen, "crease %d: [%d, %d] is not an edge of a mesh with %d vertices", c,
                  a, b, t->nverts);
    if (!(s >= 0) || !std::isfinite(s))
      return fail(err, errlen, "crease %d: sharpness must be a number >= 0", c);
  }
  for (int c = 0; c < t->ncorners; c++) {
    int v = t->corner_verts[c];
    float s = t->corner_sharpness[c];
    if (v < 0 || v >= t->nverts)
      return fail(err, errlen, "corner %d: vertex %d is not in a mesh with %d vertices", c, v,
                  t->nverts);
    if (!(s >= 0) || !std::isfinite(s))
      return fail(err, errlen, "corner %d: sharpness must be a number >= 0", c);
  }
  return 1;
}

// Creases name vertex pairs; each must be an edge of the base mesh.
int check_creases(SumiOsdTopology const &t, Far::TopologyRefiner const &r, char *err,
                  size_t errlen) {
  Far::TopologyLevel const &l0 = r.GetLevel(0);
  for (int c = 0; c < t.ncreases; c++) {
    int a = t.crease_verts[2 * c], b = t.crease_verts[2 * c + 1];
    if (l0.FindEdge(a, b) == Far::INDEX_INVALID)
      return fail(err, errlen, "crease %d: vertices %d and %d share no edge of the mesh", c, a, b);
  }
  return 1;
}

// The base refiner of t after every check (NULL and a reason in err).
Far::TopologyRefiner *checked_refiner(const SumiOsdTopology *t, char *err, size_t errlen) {
  if (!check_topology(t, err, errlen)) return nullptr;
  std::unique_ptr<Far::TopologyRefiner> r(make_refiner(*t));
  if (!r) {
    fail(err, errlen, "OpenSubdiv rejected the mesh: %s",
         osd_message.empty() ? "invalid topology" : osd_message.c_str());
    return nullptr;
  }
  if (!check_creases(*t, *r, err, errlen)) return nullptr;
  return r.release();
}

int create(const SumiOsdTopology *t, SumiOsdMesh **out, char *err, size_t errlen) {
  std::unique_ptr<Far::TopologyRefiner> base(checked_refiner(t, err, errlen));
  if (!base) return 0;
  std::unique_ptr<SumiOsdMesh> m(new SumiOsdMesh);
  long nidx = 0;
  for (int f = 0; f < t->nfaces; f++) nidx += t->face_size[f];
  m->nverts = t->nverts;
  m->scheme = t->scheme;
  m->boundary = t->boundary;
  m->face_size.assign(t->face_size, t->face_size + t->nfaces);
  m->face_index.assign(t->face_index, t->face_index + nidx);
  m->crease_verts.assign(t->crease_verts, t->crease_verts + 2 * t->ncreases);
  m->crease_sharpness.assign(t->crease_sharpness, t->crease_sharpness + t->ncreases);
  m->corner_verts.assign(t->corner_verts, t->corner_verts + t->ncorners);
  m->corner_sharpness.assign(t->corner_sharpness, t->corner_sharpness + t->ncorners);
  m->base = std::move(base);   // made from t, the same arrays as the copies
  m->factory.reset(new Bfr::RefinerSurfaceFactory<>(*m->base));
  *out = m.release();
  return 1;
}

// Refinement ----------------------------------------------------------------

template <class T>
T *copy_out(std::vector<T> const &v) {
  T *p = static_cast<T *>(std::malloc(v.empty() ? 1 : v.size() * sizeof(T)));
  if (!p) throw std::bad_alloc();
  if (!v.empty()) std::memcpy(p, v.data(), v.size() * sizeof(T));
  return p;
}

// Base crease tag of every edge of the last level: each user crease marks
// its base edge, and each edge passes its tag to its two children.
std::vector<float> tagged_edges(SumiOsdTopology const &t, Far::TopologyRefiner const &r) {
  Far::TopologyLevel const &l0 = r.GetLevel(0);
  std::vector<float> tag(l0.GetNumEdges(), 0.0f);
  for (int c = 0; c < t.ncreases; c++) {
    Far::Index e = l0.FindEdge(t.crease_verts[2 * c], t.crease_verts[2 * c + 1]);
    if (e != Far::INDEX_INVALID) tag[e] = std::max(tag[e], t.crease_sharpness[c]);
  }
  for (int l = 1; l <= r.GetMaxLevel(); l++) {
    Far::TopologyLevel const &parent = r.GetLevel(l - 1);
    std::vector<float> child(r.GetLevel(l).GetNumEdges(), 0.0f);
    for (int e = 0; e < parent.GetNumEdges(); e++) {
      if (tag[e] <= 0) continue;
      Far::ConstIndexArray kids = parent.GetEdgeChildEdges(e);
      for (int k = 0; k < kids.size(); k++)
        if (kids[k] != Far::INDEX_INVALID) child[kids[k]] = tag[e];
    }
    tag.swap(child);
  }
  return tag;
}

// The task pool ------------------------------------------------------------------

// Components (vertices, edges, faces) one task takes.
constexpr int CHUNK = 16384;

// fn(first, end) over [0, n) in chunks of `chunk`, on the pool.
template <class Fn>
struct PoolRun {
  Fn const *fn;
  int n, chunk;
  std::mutex lock;
  std::exception_ptr error;
};

template <class Fn>
void pool_task(void *ctx, int k) {
  PoolRun<Fn> *run = static_cast<PoolRun<Fn> *>(ctx);
  try {
    (*run->fn)(k * run->chunk, std::min(run->n, (k + 1) * run->chunk));
  } catch (...) {   // none may cross tasks.c's C frames: thrown again by on_pool
    std::lock_guard<std::mutex> hold(run->lock);
    if (!run->error) run->error = std::current_exception();
  }
}

// fn(first, end) for the chunks of [0, n) on up to `threads` threads; an
// exception in one (out of memory) is thrown here once all are done.
template <class Fn>
void on_pool(int n, int threads, Fn const &fn, int chunk = CHUNK) {
  PoolRun<Fn> run;
  run.fn = &fn;
  run.n = n;
  run.chunk = chunk;
  tasks_run((n + chunk - 1) / chunk, threads, pool_task<Fn>, &run);
  if (run.error) std::rethrow_exception(run.error);
}

// Limit masks ------------------------------------------------------------------

// The unit normal a x b into n (0 when it has no length); n may be a.
void unit_normal(double const *a, double const *b, double *n) {
  double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  double len = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
  int ok = len > 0 && std::isfinite(len);
  for (int k = 0; k < 3; k++) n[k] = ok ? c[k] / len : 0;
}

// One vertex of a level as Sdc's limit mask queries read it.
struct Hood {
  Far::TopologyLevel const *level;
  Far::Index v;
  int ne, nf;
  const Far::Index *edges;   // ne: v's edges, in order
  int GetNumEdges() const { return ne; }
  int GetNumFaces() const { return nf; }
  float GetSharpness() const { return level->GetVertexSharpness(v); }
  float *GetSharpnessPerEdge(float s[]) const {
    for (int i = 0; i < ne; i++) s[i] = level->GetEdgeSharpness(edges[i]);
    return s;
  }
};

// The last level's neighbourhoods made from its parent level, in Far's
// order, for a refinement made without the last level's full topology
// (Catmull-Clark from level 2: the parent's faces are quads, its edges
// have one or two faces). Level L's vertices are the children of L-1's
// vertices, faces and edges; its edges the children of L-1's faces (one
// from the face's point to each edge's point) and edges (two, from the
// edge's point to each end's point).
struct Rings {
  Vtr::internal::Refinement const *ref;
  Vtr::internal::Level const *parent, *child;

  explicit Rings(Far::TopologyRefiner const &r)
      : ref(&r.getRefinement(r.GetMaxLevel() - 1)), parent(&ref->parent()), child(&ref->child()) {}

  int max_valence() const { return std::max(parent->getMaxValence(), 4); }

  // The ends of child edge k of parent face f, and of child edge j of parent edge e.
  void face_edge_ends(int f, int k, int *ends) const {
    ends[0] = ref->getFaceChildVertex(f);
    ends[1] = ref->getEdgeChildVertex(parent->getFaceEdges(f)[k]);
  }
  void edge_edge_ends(int e, int j, int *ends) const {
    ends[0] = ref->getEdgeChildVertex(e);
    ends[1] = ref->getVertexChildVertex(parent->getEdgeVertices(e)[j]);
  }

  // The ends of every child edge, into ends (2 a child edge).
  void all_edge_ends(int *ends) const {
    for (int f = 0; f < parent->getNumFaces(); f++)
      for (int k = 0; k < 4; k++) face_edge_ends(f, k, ends + 2 * ref->getFaceChildEdges(f)[k]);
    for (int e = 0; e < parent->getNumEdges(); e++)
      for (int j = 0; j < 2; j++) edge_edge_ends(e, j, ends + 2 * ref->getEdgeChildEdges(e)[j]);
  }

  // The child edge of parent edge e at its end v.
  int edge_child_at(int e, int v, int *ends) const {
    int j = parent->getEdgeVertices(e)[0] == v ? 0 : 1;
    edge_edge_ends(e, j, ends);
    return ref->getEdgeChildEdges(e)[j];
  }

  // The edges of child face l of parent face f, edge k from its corner k to
  // k + 1: of the four edges at the parent's corner l (the child edges of
  // the face's edges l and l - 1 there, the face's child edges l and l - 1),
  // the one joining those corners.
  void child_face_edges(int f, int l, int *out) const {
    Far::ConstIndexArray fe = parent->getFaceEdges(f), fv = parent->getFaceVertices(f),
                         ce = ref->getFaceChildEdges(f);
    int cand[4], ends[4][2];
    cand[0] = edge_child_at(fe[l], fv[l], ends[0]);
    cand[1] = edge_child_at(fe[(l + 3) % 4], fv[l], ends[1]);
    cand[2] = ce[l];
    face_edge_ends(f, l, ends[2]);
    cand[3] = ce[(l + 3) % 4];
    face_edge_ends(f, (l + 3) % 4, ends[3]);
    Far::ConstIndexArray cv = child->getFaceVertices(ref->getFaceChildFaces(f)[l]);
    for (int k = 0; k < 4; k++) {
      int a = cv[k], b = cv[(k + 1) % 4], i = 0;
      while (i < 3 && !((ends[i][0] == a && ends[i][1] == b) ||
                        (ends[i][0] == b && ends[i][1] == a)))
        i++;
      out[k] = cand[i];
    }
  }

  // Vertex c's edges (edges, and the far end of each in ei) and faces (the
  // corner opposite c in each in fi), as Far orders them; their counts.
  // Child face l of a parent quad has at its corners l to l + 3 the points
  // of the quad's vertex l, edge l, the quad itself and edge l - 1, so each
  // opposite corner is a child point of the parent's.
  void ring(int c, int &ne, int &nf, Far::Index *edges, Far::Index *ei, Far::Index *fi) const {
    int p = ref->getChildVertexParentIndex(c);
    if (c >= ref->getFirstChildVertexFromVertices() &&
        c < ref->getFirstChildVertexFromVertices() + ref->getNumChildVerticesFromVertices()) {
      Far::ConstIndexArray pe = parent->getVertexEdges(p), pf = parent->getVertexFaces(p);
      Far::ConstLocalIndexArray el = parent->getVertexEdgeLocalIndices(p);
      ne = pe.size();
      nf = pf.size();
      for (int i = 0; i < ne; i++) {
        edges[i] = ref->getEdgeChildEdges(pe[i])[el[i]];
        ei[i] = ref->getEdgeChildVertex(pe[i]);
      }
      for (int i = 0; i < nf; i++) fi[i] = ref->getFaceChildVertex(pf[i]);
    } else if (c >= ref->getFirstChildVertexFromFaces() &&
               c < ref->getFirstChildVertexFromFaces() + ref->getNumChildVerticesFromFaces()) {
      Far::ConstIndexArray fe = parent->getFaceEdges(p), fv = parent->getFaceVertices(p),
                           ce = ref->getFaceChildEdges(p);
      ne = nf = 4;
      for (int i = 0; i < 4; i++) {
        edges[i] = ce[(i + 3) % 4];
        ei[i] = ref->getEdgeChildVertex(fe[(i + 3) % 4]);
        fi[i] = ref->getVertexChildVertex(fv[i]);
      }
    } else {
      Far::ConstIndexArray ef = parent->getEdgeFaces(p), ev = parent->getEdgeVertices(p),
                           ce = ref->getEdgeChildEdges(p);
      Far::ConstLocalIndexArray efl = parent->getEdgeFaceLocalIndices(p);
      int first = ev[0] == parent->getFaceVertices(ef[0])[efl[0]] ? 1 : 0;
      ne = nf = 0;
      for (int i = 0; i < ef.size(); i++) {   // one or two faces
        int l = efl[i], end = i ? 1 - first : first;
        Far::ConstIndexArray fe = parent->getFaceEdges(ef[i]);
        edges[ne] = ce[end];
        ei[ne++] = ref->getVertexChildVertex(ev[end]);
        edges[ne] = ref->getFaceChildEdges(ef[i])[l];
        ei[ne++] = ref->getFaceChildVertex(ef[i]);
        fi[nf++] = ref->getEdgeChildVertex(fe[(l + 1) % 4]);   // in child face l + 1
        fi[nf++] = ref->getEdgeChildVertex(fe[(l + 3) % 4]);   // in child face l
      }
      if (ef.size() == 1) {   // a boundary edge: its other child edge ends the ring
        edges[ne] = ce[1 - first];
        ei[ne++] = ref->getVertexChildVertex(ev[1 - first]);
      }
    }
  }
};

// One mask (vertex, edge and face weights) in Sdc's generic MASK interface.
struct Weights {
  typedef double Weight;
  double *vw = nullptr, *ew = nullptr, *fw = nullptr;
  int nv = 0, ne = 0, nf = 0;
  int GetNumVertexWeights() const { return nv; }
  int GetNumEdgeWeights() const { return ne; }
  int GetNumFaceWeights() const { return nf; }
  void SetNumVertexWeights(int n) { nv = n; }
  void SetNumEdgeWeights(int n) { ne = n; }
  void SetNumFaceWeights(int n) { nf = n; }
  double &VertexWeight(int i) { return vw[i]; }
  double &EdgeWeight(int i) { return ew[i]; }
  double &FaceWeight(int i) { return fw[i]; }
  double VertexWeight(int i) const { return vw[i]; }
  double EdgeWeight(int i) const { return ew[i]; }
  double FaceWeight(int i) const { return fw[i]; }
  bool centres = false;   // face weights for the faces' child points, not their corners
  bool AreFaceWeightsForFaceCenters() const { return centres; }
  void SetFaceWeightsForFaceCenters(bool on) { centres = on; }
};

// A vertex's limit masks (position and the two tangents) for up to maxv
// edges and faces, laid out as Far's Limit lays them out; `extra` weights
// past the end for a non-manifold vertex with more (whose weights then run
// on into the next mask's, as in Far).
struct LimitMasks {
  std::vector<double> buf;
  Weights pos, tan1, tan2;
  explicit LimitMasks(int maxv, int extra = 0) : buf(3 * (1 + 2 * (size_t)maxv) + extra) {
    Weights *m[3] = {&pos, &tan1, &tan2};
    for (int k = 0; k < 3; k++) {
      double *b = buf.data() + k * (1 + 2 * (size_t)maxv);
      m[k]->vw = b;
      m[k]->ew = b + 1;
      m[k]->fw = b + 1 + maxv;
    }
  }
};

// Valences whose smooth masks are made once for the whole level.
constexpr int SMOOTH_KEPT = 16;

// The limit of the last level of r: positions (lim) and unit normals (nrm,
// zero where the tangents give none) of points src, 3 doubles a point, for
// vertices [v0, v1). The same arithmetic as Far::PrimvarRefiner::Limit
// (the same Sdc masks, applied in the same order, faces first), so the same
// bits, but over a range of vertices: ranges run on the task pool. A smooth
// vertex's masks depend on its valence alone: those up to SMOOTH_KEPT are
// made once, in smooth[valence].
template <Sdc::SchemeType SCHEME>
struct LimitJob {
  Far::TopologyLevel const *level;
  Rings const *rings;   // the neighbourhoods, when the level has no full topology
  Sdc::Scheme<SCHEME> scheme;
  int maxv;
  std::vector<LimitMasks> smooth;
  bool regular4;   // smooth[4] is R4_POS, R4_TAN1, R4_TAN2
  const Point *src;
  double *lim, *nrm;

  LimitJob(Far::TopologyRefiner const &r, Rings const *g, const Point *p, double *l, double *n)
      : level(&r.GetLevel(r.GetMaxLevel())), rings(g), scheme(r.GetSchemeOptions()),
        maxv(g ? g->max_valence() : r.getLevel(r.GetMaxLevel()).getMaxValence()), src(p), lim(l),
        nrm(n) {
    smooth.emplace_back(0);   // valence 0 is never kept (its masks read outside their weights)
    for (int k = 1; k <= std::min(maxv, SMOOTH_KEPT); k++) {
      smooth.emplace_back(k);
      Hood h{level, 0, k, k, nullptr};   // smooth masks read no sharpness
      LimitMasks &m = smooth.back();
      scheme.ComputeVertexLimitMask(h, m.pos, m.tan1, m.tan2, Sdc::Crease::RULE_SMOOTH);
    }
    regular4 = SCHEME == Sdc::SCHEME_CATMARK && maxv >= 4 && is_regular4(smooth[4]);
  }

  // Catmull-Clark's regular vertex (smooth, 4 edges, 4 faces), most of a
  // refined mesh: its masks as Sdc makes them, written out.
  static constexpr double R4_POS[9] = {1.0 / 36, 1.0 / 36, 1.0 / 36, 1.0 / 36,  // faces
                                       1.0 / 9,  1.0 / 9,  1.0 / 9,  1.0 / 9,   // edges
                                       4.0 / 9};                                // vertex
  static constexpr double R4_TAN1[9] = {1, -1, -1, 1, 4, 0, -4, 0, 0};
  static constexpr double R4_TAN2[9] = {1, 1, -1, -1, 0, 4, 0, -4, 0};

  static bool same_mask(Weights const &w, const double *want) {
    if (w.nf != 4 || w.ne != 4 || w.nv != 1) return false;
    for (int i = 0; i < 4; i++)
      if (w.fw[i] != want[i] || w.ew[i] != want[4 + i]) return false;
    return w.vw[0] == want[8];
  }

  static bool is_regular4(LimitMasks const &m) {
    return same_mask(m.pos, R4_POS) && same_mask(m.tan1, R4_TAN1) && same_mask(m.tan2, R4_TAN2);
  }

  // apply() for the regular vertex with those weights as constants: a
  // weight of 0 adds +0 or -0 (the points are finite) to a sum that is
  // never -0 (it starts at +0), so leaving its term out changes no bit;
  // and x * 1 is x.
  void apply_regular4(int v, Far::Index const *ei, Far::Index const *fi, Point &p, Point &t1,
                      Point &t2) const {
    for (int i = 0; i < 4; i++) p.AddWithWeight(src[fi[i]], R4_POS[i]);
    for (int i = 0; i < 4; i++) p.AddWithWeight(src[ei[i]], R4_POS[4 + i]);
    p.AddWithWeight(src[v], R4_POS[8]);
    t1.AddWithWeight(src[fi[0]], 1.0);
    t1.AddWithWeight(src[fi[1]], -1.0);
    t1.AddWithWeight(src[fi[2]], -1.0);
    t1.AddWithWeight(src[fi[3]], 1.0);
    t1.AddWithWeight(src[ei[0]], 4.0);
    t1.AddWithWeight(src[ei[2]], -4.0);
    t2.AddWithWeight(src[fi[0]], 1.0);
    t2.AddWithWeight(src[fi[1]], 1.0);
    t2.AddWithWeight(src[fi[2]], -1.0);
    t2.AddWithWeight(src[fi[3]], -1.0);
    t2.AddWithWeight(src[ei[1]], 4.0);
    t2.AddWithWeight(src[ei[3]], -4.0);
  }

  // The masks of vertex v (ne edges, nf faces): kept ones, or made in own
  // (or in wide, for a vertex with more edges or faces than maxv).
  LimitMasks const *masks_of(int v, int ne, int nf, const Far::Index *edges, LimitMasks &own,
                             std::unique_ptr<LimitMasks> &wide) const {
    Sdc::Crease::Rule rule = level->GetVertexRule(v);
    if ((rule == Sdc::Crease::RULE_SMOOTH || rule == Sdc::Crease::RULE_DART) && ne == nf &&
        nf >= 1 && nf <= SMOOTH_KEPT)
      return &smooth[nf];
    LimitMasks *into = &own;
    if (ne > maxv || nf > maxv) {
      wide.reset(new LimitMasks(maxv, ne + nf));
      into = wide.get();
    }
    Hood h{level, v, ne, nf, edges};
    scheme.ComputeVertexLimitMask(h, into->pos, into->tan1, into->tan2, rule);
    return into;
  }

  // The points the masks weigh: the far end of each edge (ei), the corner
  // opposite v in each face (fi, when a mask has face weights).
  void neighbours(int v, LimitMasks const &m, Far::Index *ei, Far::Index *fi) const {
    Far::ConstIndexArray ve = level->GetVertexEdges(v);
    for (int i = 0; i < ve.size(); i++) {
      Far::ConstIndexArray ev = level->GetEdgeVertices(ve[i]);
      ei[i] = ev[0] == v ? ev[1] : ev[0];
    }
    if (!m.pos.nf && !m.tan1.nf) return;
    Far::ConstIndexArray vf = level->GetVertexFaces(v);
    Far::ConstLocalIndexArray in = level->GetVertexFaceLocalIndices(v);
    for (int i = 0; i < vf.size(); i++) {
      Far::ConstIndexArray fv = level->GetFaceVertices(vf[i]);
      int opp = in[i] + 2;
      if (opp >= fv.size()) opp -= fv.size();
      fi[i] = fv[opp];
    }
  }

  // Far's order: face weights, then edge weights, then the vertex's.
  void apply(int v, LimitMasks const &m, Far::Index const *ei, Far::Index const *fi, Point &p,
             Point &t1, Point &t2) const {
    for (int i = 0; i < m.pos.nf; i++) p.AddWithWeight(src[fi[i]], m.pos.fw[i]);
    for (int i = 0; i < m.pos.ne; i++) p.AddWithWeight(src[ei[i]], m.pos.ew[i]);
    p.AddWithWeight(src[v], m.pos.vw[0]);
    for (int i = 0; i < m.tan1.nf; i++) {
      t1.AddWithWeight(src[fi[i]], m.tan1.fw[i]);
      t2.AddWithWeight(src[fi[i]], m.tan2.fw[i]);
    }
    for (int i = 0; i < m.tan1.ne; i++) {
      t1.AddWithWeight(src[ei[i]], m.tan1.ew[i]);
      t2.AddWithWeight(src[ei[i]], m.tan2.ew[i]);
    }
    t1.AddWithWeight(src[v], m.tan1.vw[0]);
    t2.AddWithWeight(src[v], m.tan2.vw[0]);
  }

  void run(int v0, int v1) const {
    LimitMasks own(maxv);
    std::unique_ptr<LimitMasks> wide;
    std::vector<Far::Index> edges(maxv + 1), ei(maxv + 1), fi(maxv + 1);
    for (int v = v0; v < v1; v++) {
      int ne, nf;
      const Far::Index *ve = edges.data();
      if (rings) {
        rings->ring(v, ne, nf, edges.data(), ei.data(), fi.data());
      } else {
        ne = level->GetVertexEdges(v).size();
        nf = level->GetVertexFaces(v).size();
        if (ne > 0) ve = &level->GetVertexEdges(v)[0];
        if (ei.size() < (size_t)ne) ei.resize(ne);
        if (fi.size() < (size_t)nf) fi.resize(nf);
      }
      Point p, t1, t2;
      p.Clear();
      t1.Clear();
      t2.Clear();
      if (ne == 0) {   // no neighbourhood: the point as it is, no normal
        p.AddWithWeight(src[v], 1.0);
      } else {
        LimitMasks const *m = masks_of(v, ne, nf, ve, own, wide);
        if (!rings) neighbours(v, *m, ei.data(), fi.data());
        if (regular4 && m == &smooth[4]) apply_regular4(v, ei.data(), fi.data(), p, t1, t2);
        else apply(v, *m, ei.data(), fi.data(), p, t1, t2);
      }
      store(v, p, t1, t2);
    }
  }

  void store(int v, Point const &p, Point const &t1, Point const &t2) const {
    for (int k = 0; k < 3; k++) lim[3 * v + k] = p.p[k];
    unit_normal(t1.p, t2.p, nrm + 3 * v);
  }
};

template <Sdc::SchemeType SCHEME>
void limit_on_pool(Far::TopologyRefiner const &r, Rings const *rings, const Point *src, int threads,
                   double *lim, double *nrm) {
  LimitJob<SCHEME> job(r, rings, src, lim, nrm);
  on_pool(job.level->GetNumVertices(), threads, [&](int v0, int v1) { job.run(v0, v1); });
}

// Limit positions (lim) and unit limit normals (nrm) of the last level's
// points, each 3 * n doubles, on up to `threads` threads.
void limit_points(Far::TopologyRefiner const &r, Rings const *rings, std::vector<Point> const &last,
                  SumiOsdScheme scheme, int threads, double *lim, double *nrm) {
  size_t n = last.size();
  if (scheme == SUMI_OSD_BILINEAR) {  // the bilinear limit is the mesh itself
    std::memset(nrm, 0, 3 * n * sizeof(double));
    if (n) std::memcpy(lim, last.data(), n * sizeof(Point));
    return;
  }
  if (scheme == SUMI_OSD_LOOP)
    limit_on_pool<Sdc::SCHEME_LOOP>(r, rings, last.data(), threads, lim, nrm);
  else limit_on_pool<Sdc::SCHEME_CATMARK>(r, rings, last.data(), threads, lim, nrm);
}

// OpenSubdiv's own limit of the same points (Far::PrimvarRefiner::Limit),
// the reference limit_points is held to in the tests.
void limit_points_far(Far::TopologyRefiner const &r, std::vector<Point> const &last,
                      SumiOsdScheme scheme, double *lim, double *nrm) {
  size_t n = last.size();
  if (scheme == SUMI_OSD_BILINEAR) {
    limit_points(r, nullptr, last, scheme, 1, lim, nrm);
    return;
  }
  std::vector<Point> t2(n);
  Far::PrimvarRefinerReal<double> pr(r);
  PointOut out{lim}, t1{nrm};
  pr.Limit(last, out, t1, t2);
  for (size_t i = 0; i < n; i++) unit_normal(nrm + 3 * i, t2[i].p, nrm + 3 * i);
}

// Interpolation ----------------------------------------------------------------

// One level's points (dst) from its parent's (src) over ranges on the task
// pool, with Far::PrimvarRefiner::Interpolate's arithmetic (the same Sdc
// masks, applied in the same order), so the same bits: the points of the
// parent's faces, then those of its edges and vertices, which read them.
template <Sdc::SchemeType SCHEME>
struct InterpJob {
  Vtr::internal::Refinement const *ref;
  Vtr::internal::Level const *parent, *child;
  Sdc::Scheme<SCHEME> scheme;
  const Point *src;
  Point *dst;

  InterpJob(Far::TopologyRefiner const &r, int level, const Point *s, Point *d)
      : ref(&r.getRefinement(level - 1)), parent(&ref->parent()), child(&ref->child()),
        scheme(r.GetSchemeOptions()), src(s), dst(d) {}

  void faces(int f0, int f1) const {
    std::vector<double> w(std::max(parent->getMaxValence(), 4));
    for (int f = f0; f < f1; f++) {
      Far::Index c = ref->getFaceChildVertex(f);
      if (!Vtr::IndexIsValid(c)) continue;
      Far::ConstIndexArray fv = parent->getFaceVertices(f);
      if ((size_t)fv.size() > w.size()) w.resize(fv.size());
      Weights m;
      m.vw = w.data();
      Vtr::internal::FaceInterface hood(fv.size());
      scheme.ComputeFaceVertexMask(hood, m);
      dst[c].Clear();
      for (int i = 0; i < fv.size(); i++) dst[c].AddWithWeight(src[fv[i]], w[i]);
    }
  }

  void edges(int e0, int e1) const {
    Vtr::internal::EdgeInterface hood(*parent);
    double vw[2];
    std::vector<double> fw(std::max(parent->getMaxEdgeFaces(), 2));
    for (int e = e0; e < e1; e++) {
      Far::Index c = ref->getEdgeChildVertex(e);
      if (!Vtr::IndexIsValid(c)) continue;
      Far::ConstIndexArray ev = parent->getEdgeVertices(e), ef = parent->getEdgeFaces(e);
      if ((size_t)ef.size() > fw.size()) fw.resize(ef.size());
      Weights m;
      m.vw = vw;
      m.fw = fw.data();
      hood.SetIndex(e);
      Sdc::Crease::Rule prule =
          parent->getEdgeSharpness(e) > 0.0f ? Sdc::Crease::RULE_CREASE : Sdc::Crease::RULE_SMOOTH;
      scheme.ComputeEdgeVertexMask(hood, m, prule, child->getVertexRule(c));
      dst[c].Clear();
      dst[c].AddWithWeight(src[ev[0]], vw[0]);
      dst[c].AddWithWeight(src[ev[1]], vw[1]);
      if (m.nf == 0) continue;
      for (int i = 0; i < ef.size(); i++) {
        if (m.centres) {
          dst[c].AddWithWeight(dst[ref->getFaceChildVertex(ef[i])], fw[i]);
          continue;
        }
        Far::ConstIndexArray fe = parent->getFaceEdges(ef[i]), fv = parent->getFaceVertices(ef[i]);
        int k = 0;
        while (fe[k] != e) k++;
        k += 2;
        if (k >= fv.size()) k -= fv.size();
        dst[c].AddWithWeight(src[fv[k]], fw[i]);
      }
    }
  }

  void verts(int v0, int v1) const {
    Vtr::internal::VertexInterface hood(*parent, *child);
    std::vector<double> w(2 * (size_t)parent->getMaxValence() + 2);
    for (int v = v0; v < v1; v++) {
      Far::Index c = ref->getVertexChildVertex(v);
      if (!Vtr::IndexIsValid(c)) continue;
      Far::ConstIndexArray ve = parent->getVertexEdges(v), vf = parent->getVertexFaces(v);
      if (w.size() < (size_t)(ve.size() + vf.size())) w.resize(ve.size() + vf.size());
      double vw;
      Weights m;
      m.vw = &vw;
      m.ew = w.data();
      m.fw = w.data() + ve.size();
      hood.SetIndex(v, c);
      scheme.ComputeVertexVertexMask(hood, m, parent->getVertexRule(v), child->getVertexRule(c));
      dst[c].Clear();
      if (m.nf > 0)
        for (int i = 0; i < vf.size(); i++)
          dst[c].AddWithWeight(dst[ref->getFaceChildVertex(vf[i])], m.fw[i]);
      if (m.ne > 0)
        for (int i = 0; i < ve.size(); i++) {
          Far::ConstIndexArray ends = parent->getEdgeVertices(ve[i]);
          dst[c].AddWithWeight(src[ends[0] == v ? ends[1] : ends[0]], m.ew[i]);
        }
      dst[c].AddWithWeight(src[v], vw);
    }
  }
};

template <Sdc::SchemeType SCHEME>
void interpolate_level(Far::TopologyRefiner const &r, int level, const Point *src, Point *dst,
                       int threads) {
  InterpJob<SCHEME> job(r, level, src, dst);
  if (job.ref->getNumChildVerticesFromFaces() > 0)   // none in loop's split
    on_pool(job.parent->getNumFaces(), threads, [&](int a, int b) { job.faces(a, b); });
  on_pool(job.parent->getNumEdges(), threads, [&](int a, int b) { job.edges(a, b); });
  on_pool(job.parent->getNumVertices(), threads, [&](int a, int b) { job.verts(a, b); });
}

// The level's points from the base positions, level by level (double
// precision weights), on up to `threads` threads; with far, by
// Far::PrimvarRefiner::Interpolate itself (the tests' reference).
std::vector<Point> interpolate(Far::TopologyRefiner const &r, const double *pos, int nverts,
                               int threads, int far) {
  Far::PrimvarRefinerReal<double> pr(r);
  std::vector<Point> src(nverts), dst;
  for (size_t i = 0; i < src.size(); i++) src[i] = Point(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
  for (int l = 1; l <= r.GetMaxLevel(); l++) {
    dst.resize(r.GetLevel(l).GetNumVertices());
    if (far) pr.Interpolate(l, src, dst);
    else if (r.GetSchemeType() == Sdc::SCHEME_LOOP)
      interpolate_level<Sdc::SCHEME_LOOP>(r, l, src.data(), dst.data(), threads);
    else if (r.GetSchemeType() == Sdc::SCHEME_BILINEAR)
      interpolate_level<Sdc::SCHEME_BILINEAR>(r, l, src.data(), dst.data(), threads);
    else interpolate_level<Sdc::SCHEME_CATMARK>(r, l, src.data(), dst.data(), threads);
    src.swap(dst);
  }
  return src;
}

double *copy_points(std::vector<Point> const &v) {
  double *p = alloc_points(v.size());
  if (!v.empty()) std::memcpy(p, v.data(), v.size() * sizeof(Point));
  return p;
}

template <class T>
T *alloc_array(size_t n) {
  T *p = static_cast<T *>(std::malloc(n ? n * sizeof(T) : 1));
  if (!p) throw std::bad_alloc();
  return p;
}

// Faces of the last level: corners, edges (with rings, made afterwards
// from the level above) and the base face each lies in.
void collect_faces(Far::TopologyRefiner const &r, Rings const *rings, SumiOsdRefined *out) {
  int level = r.GetMaxLevel();
  Far::TopologyLevel const &last = r.GetLevel(level);
  int nfaces = last.GetNumFaces();
  // the base face of every face, level by level (as walking up each face's parents)
  std::vector<int> base(r.GetLevel(0).GetNumFaces()), up;
  for (size_t f = 0; f < base.size(); f++) base[f] = (int)f;
  for (int l = 1; l <= level; l++) {
    Far::TopologyLevel const &tl = r.GetLevel(l);
    up.resize(tl.GetNumFaces());
    for (int f = 0; f < tl.GetNumFaces(); f++) up[f] = base[tl.GetFaceParentFace(f)];
    base.swap(up);
  }
  size_t nidx = 0;
  for (int f = 0; f < nfaces; f++) nidx += last.GetFaceVertices(f).size();
  int *start = out->face_start = alloc_array<int>((size_t)nfaces + 1);
  int *index = out->face_index = alloc_array<int>(nidx);
  int *edges = out->face_edges = alloc_array<int>(nidx);
  out->face_base = copy_out(base);
  out->nfaces = nfaces;
  size_t k = 0;
  start[0] = 0;
  for (int f = 0; f < nfaces; f++) {
    Far::ConstIndexArray fv = last.GetFaceVertices(f);
    for (int i = 0; i < fv.size(); i++) {
      index[k + i] = fv[i];
      if (!rings) edges[k + i] = last.GetFaceEdges(f)[i];
    }
    k += fv.size();
    start[f + 1] = (int)k;
  }
}

// Edges of the last level with their crease tags, and vertex sharpness.
void collect_edges(SumiOsdTopology const &t, Far::TopologyRefiner const &r, Rings const *rings,
                   SumiOsdRefined *out) {
  Far::TopologyLevel const &last = r.GetLevel(r.GetMaxLevel());
  std::vector<float> tag = tagged_edges(t, r), sharp, sharp_now;
  std::vector<int> sharp_verts;
  int *everts = out->edge_verts = alloc_array<int>(2 * (size_t)last.GetNumEdges());
  if (rings) rings->all_edge_ends(everts);
  for (int e = 0; e < last.GetNumEdges(); e++) {
    if (!rings) {
      Far::ConstIndexArray ev = last.GetEdgeVertices(e);
      everts[2 * e] = ev[0];
      everts[2 * e + 1] = ev[1];
    }
    if (tag[e] <= 0) continue;
    sharp_verts.push_back(everts[2 * e]);
    sharp_verts.push_back(everts[2 * e + 1]);
    sharp.push_back(tag[e]);
    sharp_now.push_back(last.GetEdgeSharpness(e));
  }
  float *vsharp = out->vert_sharpness = alloc_array<float>((size_t)last.GetNumVertices());
  for (int v = 0; v < last.GetNumVertices(); v++) vsharp[v] = last.GetVertexSharpness(v);
  out->nedges = last.GetNumEdges();
  out->edge_tag = copy_out(tag);
  out->nsharp = (int)sharp.size();
  out->sharp_verts = copy_out(sharp_verts);
  out->sharp = copy_out(sharp);
  out->sharp_now = copy_out(sharp_now);
}

// No edge of the level has more than two faces.
bool manifold_edges(Far::TopologyLevel const &l) {
  for (int e = 0; e < l.GetNumEdges(); e++)
    if (l.IsEdgeNonManifold(e) || l.GetEdgeFaces(e).size() > 2) return false;
  return true;
}

// Refines r (t's base refiner) in place and fills *out (zeroed by the
// caller, who frees it if this throws midway); out->ctrl only with
// keep_ctrl. The points and their limit are OpenSubdiv's own
// Far::PrimvarRefiner's with far, else the bridge's on up to `threads`
// threads.
void refine_in(Far::TopologyRefiner &r, SumiOsdTopology const &t, int level, const double *pos,
               int keep_ctrl, int threads, int far, SumiOsdRefined *out) {
  Far::TopologyRefiner::UniformOptions uo(level);
  // The last level's full topology is over half of the refinement, all
  // serial; what the limit and the copies need of it is made from the
  // level above (Rings) when that is all quads with manifold edges.
  bool own = !far && t.scheme == SUMI_OSD_CATMARK && level >= 2 && manifold_edges(r.GetLevel(0));
  uo.fullTopologyInLastLevel = !own;
  r.RefineUniform(uo);
  std::unique_ptr<Rings> rings(own ? new Rings(r) : nullptr);
  std::vector<Point> ctrl = interpolate(r, pos, t.nverts, threads, far);
  out->level = level;
  out->nverts = (int)ctrl.size();
  out->limit = alloc_points(ctrl.size());
  out->normal = alloc_points(ctrl.size());
  if (far) limit_points_far(r, ctrl, t.scheme, out->limit, out->normal);
  else limit_points(r, rings.get(), ctrl, t.scheme, threads, out->limit, out->normal);
  if (keep_ctrl) out->ctrl = copy_points(ctrl);
  std::vector<Point>().swap(ctrl);   // gone before the topology is copied out (peak memory)
  on_pool(2, threads, [&](int k, int) {
    if (k) collect_edges(t, r, rings.get(), out);
    else collect_faces(r, rings.get(), out);
  }, 1);
  if (rings)   // the faces' edges, from the level above
    on_pool(rings->parent->getNumFaces(), threads, [&](int f0, int f1) {
      for (int f = f0; f < f1; f++)
        for (int l = 0; l < 4; l++) {
          int child = rings->ref->getFaceChildFaces(f)[l];
          rings->child_face_edges(f, l, out->face_edges + out->face_start[child]);
        }
    });
}

int refine(const SumiOsdMesh *m, int level, const double *pos, SumiOsdRefined *out, char *err,
           size_t errlen) {
  if (level < 1 || level > 15) return fail(err, errlen, "level %d is outside 1..15", level);
  SumiOsdTopology t = topology_of(*m);
  std::unique_ptr<Far::TopologyRefiner> r(make_refiner(t));
  if (!r) return fail(err, errlen, "OpenSubdiv rejected the mesh: %s", osd_message.c_str());
  refine_in(*r, t, level, pos, 1, 1, 0, out);
  return 1;
}

int refine_topology(const SumiOsdTopology *t, int level, const double *pos, int keep_ctrl,
                    int threads, int far, SumiOsdRefined *out, char *err, size_t errlen) {
  std::unique_ptr<Far::TopologyRefiner> r(checked_refiner(t, err, errlen));
  if (!r) return 0;
  if (level < 1 || level > 15) return fail(err, errlen, "level %d is outside 1..15", level);
  refine_in(*r, *t, level, pos, keep_ctrl, threads, far, out);
  return 1;
}

// Limit evaluation ------------------------------------------------------------

int eval_face(const SumiOsdMesh *m, const double *pos, int face, int npts, const double *uv,
              double *P, double *du, double *dv, int *regular, char *err, size_t errlen) {
  if (face < 0 || face >= (int)m->face_size.size())
    return fail(err, errlen, "face %d is not in the mesh", face);
  Bfr::Surface<double> s;
  if (!m->factory->InitVertexSurface<double>(face, &s) || !s.IsValid())
    return fail(err, errlen, "face %d has no limit surface", face);
  if (regular) *regular = s.IsRegular();
  Bfr::Surface<double>::PointDescriptor desc(3);
  std::vector<double> patch(3 * (size_t)s.GetNumPatchPoints());
  s.PreparePatchPoints(pos, desc, patch.data(), desc);
  double scratch_u[3], scratch_v[3];
  for (int i = 0; i < npts; i++) {
    double *pu = du ? du + 3 * i : scratch_u, *pv = dv ? dv + 3 * i : scratch_v;
    s.Evaluate(uv + 2 * i, patch.data(), desc, P + 3 * i, pu, pv);
  }
  return 1;
}

}  // namespace

// The C interface -------------------------------------------------------------

extern "C" int sumi_osd_create(const SumiOsdTopology *topo, SumiOsdMesh **out, char *err,
                               size_t errlen) {
  *out = nullptr;
  return guarded([&] { return create(topo, out, err, errlen); }, err, errlen,
                 "out of memory in OpenSubdiv");
}

extern "C" void sumi_osd_destroy(SumiOsdMesh *m) {
  try {
    delete m;
  } catch (...) {
  }
}

extern "C" int sumi_osd_refine(const SumiOsdMesh *m, int level, const double *pos,
                               SumiOsdRefined *out, char *err, size_t errlen) {
  std::memset(out, 0, sizeof *out);
  char oom[64];
  std::snprintf(oom, sizeof oom, "out of memory refining to level %d", level);
  int ok = guarded([&] { return refine(m, level, pos, out, err, errlen); }, err, errlen, oom);
  if (!ok) sumi_osd_refined_free(out);
  return ok;
}

extern "C" int sumi_osd_check(const SumiOsdTopology *topo, char *err, size_t errlen) {
  return guarded(
      [&] {
        std::unique_ptr<Far::TopologyRefiner> r(checked_refiner(topo, err, errlen));
        return r != nullptr;
      },
      err, errlen, "out of memory in OpenSubdiv");
}

// sumi_osd_refine_topology, with the bridge's interpolation and limit or
// (far) with Far's.
static int refine_topology_call(const SumiOsdTopology *topo, int level, const double *pos,
                                int keep_ctrl, int threads, int far, SumiOsdRefined *out,
                                char *err, size_t errlen) {
  std::memset(out, 0, sizeof *out);
  char oom[64];
  std::snprintf(oom, sizeof oom, "out of memory refining to level %d", level);
  int ok = guarded(
      [&] {
        return refine_topology(topo, level, pos, keep_ctrl, threads, far, out, err, errlen);
      },
      err, errlen, oom);
  if (!ok) sumi_osd_refined_free(out);
  return ok;
}

extern "C" int sumi_osd_refine_topology(const SumiOsdTopology *topo, int level, const double *pos,
                                        int keep_ctrl, int threads, SumiOsdRefined *out,
                                        char *err, size_t errlen) {
  return refine_topology_call(topo, level, pos, keep_ctrl, threads, 0, out, err, errlen);
}

extern "C" int sumi_osd_refine_far(const SumiOsdTopology *topo, int level, const double *pos,
                                   SumiOsdRefined *out, char *err, size_t errlen) {
  return refine_topology_call(topo, level, pos, 1, 1, 1, out, err, errlen);
}

extern "C" void sumi_osd_refined_free(SumiOsdRefined *r) {
  if (!r) return;
  std::free(r->ctrl);
  std::free(r->limit);
  std::free(r->normal);
  std::free(r->vert_sharpness);
  std::free(r->face_start);
  std::free(r->face_index);
  std::free(r->face_base);
  std::free(r->edge_verts);
  std::free(r->edge_tag);
  std::free(r->face_edges);
  std::free(r->sharp_verts);
  std::free(r->sharp);
  std::free(r->sharp_now);
  std::memset(r, 0, sizeof *r);
}

extern "C" int sumi_osd_face_has_limit(const SumiOsdMesh *m, int face) {
  try {
    begin_call();
    if (face < 0 || face >= (int)m->face_size.size()) return 0;
    return m->factory->FaceHasLimitSurface(face) ? 1 : 0;
  } catch (...) {
    return 0;
  }
}

extern "C" int sumi_osd_eval_face(const SumiOsdMesh *m, const double *pos, int face, int npts,
                                  const double *uv, double *P, double *du, double *dv,
                                  int *regular, char *err, size_t errlen) {
  char oom[64];
  std::snprintf(oom, sizeof oom, "out of memory evaluating face %d", face);
  return guarded([&] { return eval_face(m, pos, face, npts, uv, P, du, dv, regular, err, errlen); },
                 err, errlen, oom);
}
