/*
** Constructive solid geometry of closed shapes (see csg.h): operands to
** checked triangle meshes, the bridge's booleans, and the result's
** surface attributes carried over from the operands.
*/
#include "csg.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "shapes.h"
#include "subdiv.h"
#include "tessellate.h"

/* The bridge reads Vec3 arrays as packed doubles and triangles as ints. */
_Static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 is three doubles");
_Static_assert(sizeof(int[3]) == 3 * sizeof(int), "a triangle is three ints");

/* Faces of different operands meeting at less than this angle (degrees)
** are one flat surface (coincident faces of a union), not an
** intersection curve. */
#define CSG_FLAT_DEGREES 0.5

/* ---- operands ------------------------------------------------------------ */

/* Drop m's triangles that name one vertex twice (a polygon with a point
** repeated, as a profile's point on the axis of a rotate_extrude makes):
** they have no area, and their neighbours meet across them. */
static void drop_repeated(Mesh *m) {
  int n = 0;
  for (int t = 0; t < m->ntris; t++) {
    const int *c = m->tri[t];
    if (c[0] == c[1] || c[1] == c[2] || c[2] == c[0]) continue;
    memmove(m->tri[n], c, sizeof m->tri[n]);
    m->tri_face[n] = m->tri_face[t];
    if (m->corner_nrm) memmove(m->corner_nrm[n], m->corner_nrm[t], sizeof m->corner_nrm[n]);
    if (m->corner_uv) memmove(m->corner_uv[n], m->corner_uv[t], sizeof m->corner_uv[n]);
    n++;
  }
  if (n == m->ntris) return;
  m->ntris = n;
  mesh_build_edges(m);
}

Mesh *csg_operand_mesh(const SceneGeometry *g, char *err, size_t errlen) {
  Mesh *m;
  if (g->kind == GEOM_PATCHES) m = tess_uniform(g, g->tess_n > 0 ? g->tess_n : CSG_SEGMENTS);
  else if (g->subdiv_level > 0) {
    SumiOsdBoundary boundary;
    subdiv_boundary_parse(g->subdiv_boundary, &boundary);   /* checked by the evaluator */
    m = subdiv_mesh(g, boundary, err, errlen);
  } else m = tess_polygons(g);
  if (!m) return NULL;
  drop_repeated(m);
  if (!m->edges) mesh_build_edges(m);
  return m;
}

double csg_mesh_volume(const Mesh *m) {
  double v = 0;
  for (int t = 0; t < m->ntris; t++) {
    Vec3 a = m->pos[m->tri[t][0]], b = m->pos[m->tri[t][1]], c = m->pos[m->tri[t][2]];
    v += v3_dot(a, v3_cross(b, c));
  }
  return v / 6;
}

static Vec3 edge_mid(const Mesh *m, int e) {
  return v3_mul(v3_add(m->pos[m->edges[e].v[0]], m->pos[m->edges[e].v[1]]), 0.5);
}

int csg_check_solid(const Mesh *m, char *err, size_t errlen) {
  int open = 0, first_open = -1, bad_turn = -1;
  for (int e = 0; e < m->nedges; e++) {
    const MeshEdge *me = &m->edges[e];
    if (me->nonmanifold) {
      Vec3 p = edge_mid(m, e);
      snprintf(err, errlen, "is not a manifold: an edge near [%g, %g, %g] is shared by more than two faces", p.x,
               p.y, p.z);
      return 0;
    }
    if (me->f[1] < 0) {
      if (!open++) first_open = e;
      continue;
    }
    /* the two faces run along the edge in opposite directions */
    int dir[2];
    for (int s = 0; s < 2; s++) {
      const int *t = m->tri[me->f[s]];
      dir[s] = 0;
      for (int k = 0; k < 3; k++)
        if (t[k] == me->v[0] && t[(k + 1) % 3] == me->v[1]) dir[s] = 1;
        else if (t[k] == me->v[1] && t[(k + 1) % 3] == me->v[0]) dir[s] = -1;
    }
    if (dir[0] == dir[1] && bad_turn < 0) bad_turn = e;
  }
  if (open) {
    Vec3 p = edge_mid(m, first_open);
    snprintf(err, errlen, "is not closed: %d edge%s border%s one face only (one near [%g, %g, %g])", open,
             open == 1 ? "" : "s", open == 1 ? "s" : "", p.x, p.y, p.z);
    return 0;
  }
  if (bad_turn >= 0) {
    Vec3 p = edge_mid(m, bad_turn);
    snprintf(err, errlen, "is not consistently oriented: two faces meeting near [%g, %g, %g] face opposite ways",
             p.x, p.y, p.z);
    return 0;
  }
  if (!(csg_mesh_volume(m) > 0)) {
    snprintf(err, errlen, "encloses no volume (its faces point inward, or it is flat)");
    return 0;
  }
  return 1;
}

/* ---- the result's surface attributes ------------------------------------- */

/* One operand's mesh and where its faces and triangles start in the
** numbering the bridge and the result use. */
typedef struct Operand {
  Mesh *m;
  int tri0;                    /* its first triangle in the bridge's numbering */
  int group0;                  /* its first source face in the result's face_group */
} Operand;

/* Barycentric weights of p's projection onto triangle (a, b, c), clamped
** to the triangle. */
static void barycentric(Vec3 p, Vec3 a, Vec3 b, Vec3 c, double w[3]) {
  Vec3 n = v3_cross(v3_sub(b, a), v3_sub(c, a));
  double nn = v3_dot(n, n);
  if (!(nn > 0)) { w[0] = 1, w[1] = w[2] = 0; return; }
  w[0] = v3_dot(n, v3_cross(v3_sub(b, p), v3_sub(c, p))) / nn;
  w[1] = v3_dot(n, v3_cross(v3_sub(c, p), v3_sub(a, p))) / nn;
  w[0] = fmin(fmax(w[0], 0), 1), w[1] = fmin(fmax(w[1], 0), 1);
  w[2] = fmax(1 - w[0] - w[1], 0);
  double s = w[0] + w[1] + w[2];
  for (int k = 0; k < 3; k++) w[k] /= s;
}

static int operand_of(const Operand *op, int n, int tri) {
  int k = 0;
  while (k + 1 < n && tri >= op[k + 1].tri0) k++;
  return k;
}

static Vec3 tri_normal(const Vec3 *pos, const int *t) {
  return v3_cross(v3_sub(pos[t[1]], pos[t[0]]), v3_sub(pos[t[2]], pos[t[0]]));
}

/* Corner normals and texture coordinates of result triangle t, each from
** the operand triangle it was cut from (turned where the result shows
** the inside of a subtracted shape). */
static void corner_attributes(SceneGeometry *g, const SumiCsgResult *r, SumiCsgOp op_kind, const Operand *op, int n,
                              int t, int any_uv) {
  int k = operand_of(op, n, r->src[t]);
  const Mesh *m = op[k].m;
  int st = r->src[t] - op[k].tri0;
  const int *s = m->tri[st];
  Vec3 a = m->pos[s[0]], b = m->pos[s[1]], c = m->pos[s[2]];
  int flip = op_kind == SUMI_CSG_DIFFERENCE && k > 0;   /* the inside of a subtracted shape */
  g->face_group[t] = op[k].group0 + m->tri_face[st];
  for (int j = 0; j < 3; j++) {
    double w[3];
    barycentric(g->verts[r->tri[3 * t + j]], a, b, c, w);
    Vec3 nrm = v3(0, 0, 0);
    Vec2 uv = {0, 0};
    for (int q = 0; q < 3; q++) {
      nrm = v3_add(nrm, v3_mul(mesh_corner_normal(m, st, q), w[q]));
      if (m->uv) {
        Vec2 u = mesh_corner_uv(m, st, q);
        uv.x += w[q] * u.x, uv.y += w[q] * u.y;
      }
    }
    nrm = v3_norm(nrm);
    if (v3_len(nrm) == 0) nrm = v3_norm(tri_normal(m->pos, s));
    g->face_nrm[3 * t + j] = flip ? v3_mul(nrm, -1) : nrm;
    if (any_uv) g->face_uv[3 * t + j] = uv;
  }
}

typedef struct EdgeRef { int a, b, t; } EdgeRef;

static int cmp_edgeref(const void *pa, const void *pb) {
  const EdgeRef *x = pa, *y = pb;
  if (x->a != y->a) return x->a < y->a ? -1 : 1;
  if (x->b != y->b) return x->b < y->b ? -1 : 1;
  return x->t < y->t ? -1 : x->t > y->t;
}

/* The intersection curves: edges between triangles cut from different
** operands that meet at an angle, as creases of g. */
static void intersection_creases(Arena *ar, SceneGeometry *g, const SumiCsgResult *r, const Operand *op, int n) {
  EdgeRef *e = xmalloc((size_t)(3 * r->ntris + 1) * sizeof *e);
  for (int t = 0; t < r->ntris; t++)
    for (int k = 0; k < 3; k++) {
      int a = r->tri[3 * t + k], b = r->tri[3 * t + (k + 1) % 3];
      e[3 * t + k] = (EdgeRef){a < b ? a : b, a < b ? b : a, t};
    }
  int ne = 3 * r->ntris, nc = 0;
  qsort(e, (size_t)ne, sizeof *e, cmp_edgeref);
  g->creases = arena_alloc(ar, (size_t)(ne / 2 + 1) * sizeof *g->creases);
  double flat = cos(CSG_FLAT_DEGREES * M_PI / 180);
  for (int i = 0; i + 1 < ne; i++) {
    if (e[i].a != e[i + 1].a || e[i].b != e[i + 1].b) continue;
    int t0 = e[i].t, t1 = e[i + 1].t;
    i++;
    if (operand_of(op, n, r->src[t0]) == operand_of(op, n, r->src[t1])) continue;
    Vec3 n0 = v3_norm(tri_normal(g->verts, &r->tri[3 * t0])), n1 = v3_norm(tri_normal(g->verts, &r->tri[3 * t1]));
    if (v3_dot(n0, n1) > flat) continue;
    g->creases[nc].a = e[i].a, g->creases[nc].b = e[i].b, g->creases[nc].sharpness = 10;
    nc++;
  }
  g->ncreases = nc;
  free(e);
}

/* The result as a triangle mesh in ar. */
static SceneGeometry *result_geometry(Arena *ar, const SumiCsgResult *r, SumiCsgOp op_kind, const Operand *op, int n) {
  SceneGeometry *g = arena_alloc(ar, sizeof *g);
  g->kind = GEOM_MESH;
  g->nverts = r->nverts;
  g->verts = arena_alloc(ar, (size_t)(r->nverts + 1) * sizeof *g->verts);
  memcpy(g->verts, r->xyz, (size_t)r->nverts * sizeof *g->verts);
  g->nfaces = r->ntris;
  g->face_start = arena_alloc(ar, (size_t)(r->ntris + 1) * sizeof *g->face_start);
  g->face_index = arena_alloc(ar, (size_t)(3 * r->ntris + 1) * sizeof *g->face_index);
  memcpy(g->face_index, r->tri, (size_t)(3 * r->ntris) * sizeof *g->face_index);
  for (int f = 0; f <= r->ntris; f++) g->face_start[f] = 3 * f;
  int any_uv = 0;
  for (int k = 0; k < n; k++) any_uv |= op[k].m->uv != NULL;
  g->face_nrm = arena_alloc(ar, (size_t)(3 * r->ntris + 1) * sizeof *g->face_nrm);
  g->face_group = arena_alloc(ar, (size_t)(r->ntris + 1) * sizeof *g->face_group);
  if (any_uv) g->face_uv = arena_alloc(ar, (size_t)(3 * r->ntris + 1) * sizeof *g->face_uv);
  for (int t = 0; t < r->ntris; t++) corner_attributes(g, r, op_kind, op, n, t, any_uv);
  intersection_creases(ar, g, r, op, n);
  return g;
}

/* ---- the operation ------------------------------------------------------- */

static int is_empty(const SceneGeometry *g) {
  return g->kind == GEOM_MESH ? g->nfaces == 0 : g->npatches == 0;
}

SceneGeometry *csg_boolean(Arena *a, SumiCsgOp op, const SceneGeometry *const *g, int n, int *bad, char *err,
                           size_t errlen) {
  int dummy;
  if (!bad) bad = &dummy;
  *bad = -1;
  /* the empty shape: nothing to a union, everything to an intersection */
  int *use = xmalloc((size_t)(n + 1) * sizeof *use), nu = 0;
  for (int k = 0; k < n; k++) {
    if (!is_empty(g[k])) use[nu++] = k;
    else if (op == SUMI_CSG_INTERSECTION || (op == SUMI_CSG_DIFFERENCE && k == 0)) { nu = 0; break; }
  }
  if (nu == 0 || (op == SUMI_CSG_DIFFERENCE && use[0] != 0)) { free(use); return shape_empty(a); }
  if (nu == 1) {   /* one shape: itself */
    SceneGeometry *one = (SceneGeometry *)g[use[0]];
    free(use);
    return one;
  }
  Operand *opd = xcalloc((size_t)nu, sizeof *opd);
  SumiCsgMesh *in = xmalloc((size_t)nu * sizeof *in);
  SceneGeometry *out = NULL;
  int tri0 = 0, group0 = 0;
  for (int i = 0; i < nu; i++) {
    const SceneGeometry *gi = g[use[i]];
    *bad = use[i];
    Mesh *m = opd[i].m = csg_operand_mesh(gi, err, errlen);
    if (!m || !csg_check_solid(m, err, errlen)) goto done;
    opd[i].tri0 = tri0, opd[i].group0 = group0;
    tri0 += m->ntris;
    int faces = 0;
    for (int t = 0; t < m->ntris; t++) faces = m->tri_face[t] >= faces ? m->tri_face[t] + 1 : faces;
    group0 += faces;
    in[i] = (SumiCsgMesh){m->nverts, (const double *)m->pos, m->ntris, (const int *)m->tri};
  }
  SumiCsgResult r;
  int which;
  if (!sumi_csg_run(op, in, nu, &r, &which, err, errlen)) {
    *bad = which >= 0 ? use[which] : -1;
    goto done;
  }
  *bad = -1;
  out = result_geometry(a, &r, op, opd, nu);
  sumi_csg_free(&r);
done:
  for (int i = 0; i < nu; i++)
    if (opd[i].m) mesh_destroy(opd[i].m);
  free(opd);
  free(in);
  free(use);
  return out;
}
