/*
** The modelling builtins: OpenSCAD's primitives with OpenSCAD's parameters
** (sphere, cube, cylinder, polyhedron, and cone, torus, plane), its
** transforms (mirror, multmatrix; translate, rotate and scale are in
** builtins.c). Each returns a value (a geometry or a transform); as a call
** statement, a geometry is drawn and a transform moves the statement's
** children (eval.c). One table row each, at the end.
*/
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../geom/csg.h"
#include "../geom/shape2d.h"
#include "../geom/shapes.h"
#include "builtins.h"

/* ---- argument helpers ------------------------------------------------- */

static int given(const Value *v) { return v->kind != V_UNSET && v->kind != V_UNDEF; }

/* A size: a positive finite number, reported at argument i. */
static int positive(Eval *ev, const ENode *call, int i, const char *what, double x) {
  if (isfinite(x) && x > 0) return 0;
  ev_error(ev, bi_arg_loc(call, i), "`%s` needs a %s greater than 0; found %g", bi_name(call), what, x);
  return -1;
}

static int not_negative(Eval *ev, const ENode *call, int i, const char *what, double x) {
  if (isfinite(x) && x >= 0) return 0;
  ev_error(ev, bi_arg_loc(call, i), "`%s` needs a %s of 0 or more; found %g", bi_name(call), what, x);
  return -1;
}

/* OpenSCAD's radius lookup: the diameter argument d (when given) wins
** over the radius r, then the fallback. */
static int radius(Eval *ev, Value *a, int r, int d, const ENode *call, double fallback, double *out) {
  if (given(&a[d])) {
    if (bi_num(ev, a, d, call, out)) return -1;
    *out /= 2;
    return 0;
  }
  return bi_opt_num(ev, a, r, call, fallback, out);
}

static int flag(Eval *ev, Value *a, int i, const ENode *call, int *out) {
  *out = 0;
  if (!given(&a[i])) return 0;
  if (a[i].kind != V_BOOL) return bi_type_error(ev, call, i, "true or false", &a[i]);
  *out = a[i].u.n != 0;
  return 0;
}

static Value geom(SceneGeometry *g, const ENode *call) {
  g->loc = call->range;
  return val_ptr(V_GEOM, g);
}

static Arena *arena(Eval *ev) { return &ev->scene->arena; }

/* ---- primitives ---------------------------------------------------------- */

/* sphere(r = 1, d) */
static Value bi_sphere(Eval *ev, Value *a, int n, const ENode *call) {
  double r;
  if (radius(ev, a, 0, 1, call, 1, &r) || positive(ev, call, given(&a[1]) ? 1 : 0, "radius", r)) return val_err();
  return geom(shape_sphere(arena(ev), r), call);
}

/* cube(size = 1, center = false): size a number or [x, y, z] */
static Value bi_cube(Eval *ev, Value *a, int n, const ENode *call) {
  Vec3 s = v3(1, 1, 1);
  int center;
  if (a[0].kind == V_NUM) s = v3(a[0].u.n, a[0].u.n, a[0].u.n);
  else if (given(&a[0]) && (a[0].kind != V_LIST || a[0].u.l->n != 3 || !val_to_point(&a[0], &s)))
    return bi_type_error(ev, call, 0, "a number or [x, y, z]", &a[0]), val_err();
  if (flag(ev, a, 1, call, &center) || positive(ev, call, 0, "size", fmin(s.x, fmin(s.y, s.z)))) return val_err();
  return geom(shape_cube(arena(ev), s, center), call);
}

/* cylinder(h = 1, r1, r2, center = false, r, d, d1, d2): radius r1 at
** the bottom and r2 at the top, each from its own argument, else r (d),
** else 1. */
static Value bi_cylinder(Eval *ev, Value *a, int n, const ENode *call) {
  double h, r, r1, r2;
  int center;
  if (bi_opt_num(ev, a, 0, call, 1, &h) || radius(ev, a, 4, 5, call, 1, &r) || radius(ev, a, 1, 6, call, r, &r1) ||
      radius(ev, a, 2, 7, call, r, &r2) || flag(ev, a, 3, call, &center))
    return val_err();
  if (positive(ev, call, 0, "height", h) || not_negative(ev, call, 1, "radius", r1) ||
      not_negative(ev, call, 2, "radius", r2))
    return val_err();
  if (r1 == 0 && r2 == 0) {
    ev_error(ev, call->range, "`cylinder` needs a radius greater than 0 at one end at least");
    return val_err();
  }
  return geom(shape_cylinder(arena(ev), h, r1, r2, center), call);
}

/* cone(h = 1, r = 1, center = false): base radius r, apex at the top */
static Value bi_cone(Eval *ev, Value *a, int n, const ENode *call) {
  double h, r;
  int center;
  if (bi_opt_num(ev, a, 0, call, 1, &h) || radius(ev, a, 1, 3, call, 1, &r) || flag(ev, a, 2, call, &center) ||
      positive(ev, call, 0, "height", h) || positive(ev, call, 1, "radius", r))
    return val_err();
  return geom(shape_cylinder(arena(ev), h, r, 0, center), call);
}

/* torus(R = 1, r = 0.25) */
static Value bi_torus(Eval *ev, Value *a, int n, const ENode *call) {
  double R, r;
  if (bi_opt_num(ev, a, 0, call, 1, &R) || bi_opt_num(ev, a, 1, call, 0.25, &r) ||
      positive(ev, call, 0, "radius", R) || positive(ev, call, 1, "tube radius", r))
    return val_err();
  return geom(shape_torus(arena(ev), R, r), call);
}

/* plane(size = 10) */
static Value bi_plane(Eval *ev, Value *a, int n, const ENode *call) {
  double size;
  if (bi_opt_num(ev, a, 0, call, 10, &size) || positive(ev, call, 0, "size", size)) return val_err();
  return geom(shape_plane(arena(ev), size), call);
}

/* polyhedron(points, faces, convexity): OpenSCAD's faces run clockwise
** seen from outside, so each is reversed to sumi's counter-clockwise. */
static Value bi_polyhedron(Eval *ev, Value *a, int n, const ENode *call) {
  SceneGeometry *g = bi_geom_new(ev, GEOM_MESH, call);
  List *faces;
  if (bi_points(ev, a, 0, call, &g->verts, &g->nverts) || bi_list(ev, a, 1, call, &faces) ||
      bi_faces(ev, faces, g->nverts, call, 1, g))
    return val_err();
  for (int f = 0; f < g->nfaces; f++)
    for (int i = g->face_start[f], j = g->face_start[f + 1] - 1; i < j; i++, j--) {
      int t = g->face_index[i];
      g->face_index[i] = g->face_index[j];
      g->face_index[j] = t;
    }
  return geom(g, call);
}

/* ---- transforms ------------------------------------------------------- */

/* mirror(v): the reflection in the plane through the origin across v */
static Value bi_mirror(Eval *ev, Value *a, int n, const ENode *call) {
  Vec3 v;
  if (bi_vec3(ev, a, 0, call, &v)) return val_err();
  if (v3_len(v) == 0) {
    ev_error(ev, bi_arg_loc(call, 0), "`mirror`: the normal [0, 0, 0] has no direction");
    return val_err();
  }
  return ev_xform(ev, m4_mirror(v));
}

/* multmatrix(m): 4 rows of 4, or 3 (the last row is 0 0 0 1), as OpenSCAD */
static Value bi_multmatrix(Eval *ev, Value *a, int n, const ENode *call) {
  List *rows;
  if (bi_list(ev, a, 0, call, &rows)) return val_err();
  Mat4 m = m4_identity();
  int ok = rows->n == 3 || rows->n == 4;
  for (int i = 0; ok && i < rows->n; i++) {
    const Value *r = &rows->v[i];
    ok = r->kind == V_LIST && r->u.l->n == 4;
    for (int j = 0; ok && j < 4; j++) {
      ok = r->u.l->v[j].kind == V_NUM && isfinite(r->u.l->v[j].u.n);
      if (ok) m.m[i][j] = r->u.l->v[j].u.n;
    }
  }
  if (!ok) return bi_type_error(ev, call, 0, "3 or 4 rows of 4 finite numbers", &a[0]), val_err();
  return ev_xform(ev, m);
}

/* ---- CSG ------------------------------------------------------------- */

/* Where operand i of n of a CSG call stands: its argument, or (a call
** statement's child) the statement that made it. */
static SrcRange operand_loc(const ENode *call, int n, int i, const SceneGeometry *g) {
  return n == call->n ? bi_arg_loc(call, i) : g->loc;
}

/* union, difference, intersection: of 2D shapes through Clipper
** (shape2d.h), of 3D shapes through CGAL's corefinement (csg.h); the empty
** shape goes with either. */
static Value csg(Eval *ev, Value *a, int n, const ENode *call, SumiCsgOp op) {
  const SceneGeometry **g = xmalloc((size_t)(n ? n : 1) * sizeof *g);
  int first2d = -1, first3d = -1;
  Value r = val_err();
  for (int i = 0; i < n; i++) {
    if (a[i].kind != V_GEOM) {
      bi_type_error(ev, call, i, "a shape", &a[i]);
      goto out;
    }
    g[i] = a[i].u.g;
    if (shape2d_is_empty(g[i])) continue;
    if (shape2d_is_2d(g[i])) { if (first2d < 0) first2d = i; }
    else if (first3d < 0) first3d = i;
  }
  if (first2d >= 0 && first3d >= 0) {
    int late = first2d > first3d ? first2d : first3d;
    ev_error(ev, operand_loc(call, n, late, g[late]), "`%s` combines 2D shapes or 3D shapes, not both; this one is %s "
             "and an earlier one %s (linear_extrude the 2D ones first)", bi_name(call), late == first2d ? "2D" : "3D",
             late == first2d ? "3D" : "2D");
    goto out;
  }
  char err[400];
  int bad = -1;
  SceneGeometry *res;
  if (first2d >= 0) {
    SumiP2dOp op2 = op == SUMI_CSG_UNION ? SUMI_P2D_UNION : op == SUMI_CSG_DIFFERENCE ? SUMI_P2D_DIFFERENCE
                                                                                       : SUMI_P2D_INTERSECTION;
    res = shape2d_boolean(arena(ev), op2, g, n, err, sizeof err);
  } else res = csg_boolean(arena(ev), op, g, n, &bad, err, sizeof err);
  if (!res) {
    if (bad >= 0) ev_error(ev, operand_loc(call, n, bad, g[bad]), "`%s`: this shape %s", bi_name(call), err);
    else ev_error(ev, call->range, "`%s`: %s", bi_name(call), err);
    goto out;
  }
  r = val_ptr(V_GEOM, res);
  int same = 0;   /* one operand left: the result is that shape, where it was made */
  for (int i = 0; i < n; i++) same |= res == g[i];
  if (!same) res->loc = call->range;
out:
  free(g);
  return r;
}

/* union() { ... } or union(a, b, ...): everything the shapes enclose */
static Value bi_union(Eval *ev, Value *a, int n, const ENode *call) { return csg(ev, a, n, call, SUMI_CSG_UNION); }

/* difference() { ... }: the first shape less all the others */
static Value bi_difference(Eval *ev, Value *a, int n, const ENode *call) {
  return csg(ev, a, n, call, SUMI_CSG_DIFFERENCE);
}

/* intersection() { ... }: what every shape encloses */
static Value bi_intersection(Eval *ev, Value *a, int n, const ENode *call) {
  return csg(ev, a, n, call, SUMI_CSG_INTERSECTION);
}

/* ---- the table ---------------------------------------------------------- */

/* The round shapes are exact surfaces: OpenSCAD's `$fn`, `$fa`, `$fs` are
** taken and change nothing (an object's `tessellate` sets the triangles). */
static const Builtin model_builtins[] = {
  {"sphere", bi_sphere, "r,d,$fn,$fa,$fs", 0, 5, BI_FUNCTION},
  {"cube", bi_cube, "size,center", 0, 2, BI_FUNCTION},
  {"cylinder", bi_cylinder, "h,r1,r2,center,r,d,d1,d2,$fn,$fa,$fs", 0, 11, BI_FUNCTION},
  {"cone", bi_cone, "h,r,center,d,$fn,$fa,$fs", 0, 7, BI_FUNCTION},
  {"torus", bi_torus, "R,r,$fn,$fa,$fs", 0, 5, BI_FUNCTION},
  {"plane", bi_plane, "size", 0, 1, BI_FUNCTION},
  {"polyhedron", bi_polyhedron, "points,faces,convexity", 2, 3, BI_FUNCTION},
  {"mirror", bi_mirror, "v", 1, 1, BI_FUNCTION},
  {"multmatrix", bi_multmatrix, "m", 1, 1, BI_FUNCTION},
  {"union", bi_union, "", 0, -1, BI_CHILDREN_ARGS},
  {"difference", bi_difference, "", 0, -1, BI_CHILDREN_ARGS},
  {"intersection", bi_intersection, "", 0, -1, BI_CHILDREN_ARGS},
};

const Builtin *builtin_model_table(int *n) {
  *n = (int)(sizeof model_builtins / sizeof model_builtins[0]);
  return model_builtins;
}
