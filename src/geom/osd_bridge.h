/*
** The OpenSubdiv bridge: a plain C view of the parts of OpenSubdiv sumi
** uses (Far: topology, uniform refinement, limit positions; Bfr: exact
** limit-surface evaluation of one face). The implementation is C++17 in
** osd_bridge.cpp; no exception crosses this header. Every function that
** can fail returns 1 on success and 0 on failure, with a one-line reason
** written into err (errlen bytes, always terminated).
**
** Points are packed doubles, 3 a point (x, y, z).
*/
#ifndef geom_osd_bridge_h
#define geom_osd_bridge_h

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
  SUMI_OSD_CATMARK,   /* Catmull-Clark: any polygons, quads after one level */
  SUMI_OSD_LOOP,      /* Loop: triangles only */
  SUMI_OSD_BILINEAR   /* bilinear: splits faces, no smoothing */
} SumiOsdScheme;

typedef enum {
  SUMI_OSD_BOUNDARY_NONE,            /* boundary faces have no limit surface */
  SUMI_OSD_BOUNDARY_EDGE_ONLY,       /* boundary edges sharp, corners smooth */
  SUMI_OSD_BOUNDARY_EDGE_AND_CORNER  /* boundary edges sharp, valence-2 corners sharp */
} SumiOsdBoundary;

/* A polygon mesh's topology and tags, as OpenSubdiv's TopologyDescriptor
** takes it. The arrays are the caller's and are copied by create. */
typedef struct SumiOsdTopology {
  int nverts, nfaces;
  const int *face_size;        /* nfaces: vertices of each face (>= 3) */
  const int *face_index;       /* sum of face_size: vertex indices, counter-clockwise */
  int ncreases;
  const int *crease_verts;     /* 2 * ncreases: the edge's two vertices */
  const float *crease_sharpness;
  int ncorners;
  const int *corner_verts;     /* ncorners */
  const float *corner_sharpness;
  SumiOsdScheme scheme;
  SumiOsdBoundary boundary;
} SumiOsdTopology;

/* An opaque handle: one base mesh, ready for refinement and evaluation. */
typedef struct SumiOsdMesh SumiOsdMesh;

/* Build a handle from topo into *out (NULL on failure). Checks indices,
** face sizes, Loop's triangles and crease/corner references first, then
** lets OpenSubdiv validate the rest. */
int sumi_osd_create(const SumiOsdTopology *topo, SumiOsdMesh **out, char *err, size_t errlen);
void sumi_osd_destroy(SumiOsdMesh *m);

/* The result of a uniform refinement. Every array is malloc'd by the bridge
** and released by sumi_osd_refined_free(). */
typedef struct SumiOsdRefined {
  int level;
  int nverts;
  double *ctrl;                /* 3 * nverts: the level's control points (or NULL, see below) */
  double *limit;               /* 3 * nverts: those points pushed to the limit surface */
  double *normal;              /* 3 * nverts: unit limit normals (0 where undefined) */
  float *vert_sharpness;       /* nverts: vertex (corner) sharpness at this level */
  int nfaces;
  int *face_start;             /* nfaces + 1 offsets into face_index */
  int *face_index;             /* quads (catmark, bilinear) or triangles (loop) */
  int *face_base;              /* nfaces: the base face each refined face lies in */
  int nedges;                  /* edges of the level */
  int *edge_verts;             /* 2 * nedges */
  float *edge_tag;             /* nedges: the base crease each descends from, 0 = none */
  int *face_edges;             /* like face_index: edge k runs from corner k to k + 1 */
  int nsharp;                  /* edges with edge_tag > 0 */
  int *sharp_verts;            /* 2 * nsharp: edges descending from a tagged base crease */
  float *sharp;                /* nsharp: the base crease's sharpness, as tagged */
  float *sharp_now;            /* nsharp: the sharpness left at this level (decayed) */
} SumiOsdRefined;

/* Refine m uniformly to level (>= 1) with base positions pos (3 * nverts of
** the base mesh). Fills *out (zeroed on failure). */
int sumi_osd_refine(const SumiOsdMesh *m, int level, const double *pos, SumiOsdRefined *out,
                    char *err, size_t errlen);
void sumi_osd_refined_free(SumiOsdRefined *r);

/* The checks sumi_osd_create makes, without keeping a handle. */
int sumi_osd_check(const SumiOsdTopology *topo, char *err, size_t errlen);

/* sumi_osd_create's checks, then sumi_osd_refine, in one refiner made for
** the call (no handle, no limit evaluator: a third of the base meshes
** made). With keep_ctrl 0, out->ctrl is NULL. The points of each level
** and their limit are made on up to `threads` threads (the same bits at
** any count). */
int sumi_osd_refine_topology(const SumiOsdTopology *topo, int level, const double *pos,
                             int keep_ctrl, int threads, SumiOsdRefined *out, char *err,
                             size_t errlen);

/* The same (with out->ctrl) on one thread, the points of each level and
** their limit by OpenSubdiv's own Far::PrimvarRefiner (Interpolate, Limit)
** rather than the bridge's ranges: the reference the tests hold the
** bridge's to, bit for bit. */
int sumi_osd_refine_far(const SumiOsdTopology *topo, int level, const double *pos,
                        SumiOsdRefined *out, char *err, size_t errlen);

/* 1 if base face `face` of m has a limit surface (0 for holes and for
** boundary faces under SUMI_OSD_BOUNDARY_NONE). */
int sumi_osd_face_has_limit(const SumiOsdMesh *m, int face);

/* Evaluate the exact limit surface of base face `face` (Bfr) at npts
** parameter pairs uv (2 * npts; a quad's corners k = 0..3 sit at (0,0),
** (1,0), (1,1), (0,1)). P, du, dv receive 3 * npts doubles; du and dv may
** be NULL. *regular (may be NULL) is set to 1 when the face is a regular
** B-spline patch. Returns 0 when the face has no limit surface. */
int sumi_osd_eval_face(const SumiOsdMesh *m, const double *pos, int face, int npts,
                       const double *uv, double *P, double *du, double *dv, int *regular,
                       char *err, size_t errlen);

#ifdef __cplusplus
}
#endif

#endif
