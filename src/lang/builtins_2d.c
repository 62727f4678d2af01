/*
** The 2D builtins, with OpenSCAD's parameters: circle, square, polygon
** and text make 2D shapes (drawn flat, facing +z, as statements); offset,
** linear_extrude and rotate_extrude take the 2D shapes their children
** make (or a shape or a list of them as the first argument) and return a
** shape. Geometry is in src/geom/shape2d.c, extrude.c and text.c. One
** table row each, at the end.
*/
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../geom/extrude.h"
#include "../geom/shape2d.h"
#include "../geom/text.h"
#include "builtins.h"

/* ---- argument helpers ------------------------------------------------- */

static int given(const Value *v) { return v->kind != V_UNSET && v->kind != V_UNDEF; }

/* Where parameter k of call stands in the source: a named argument by its
** name; a positional one by its place, except in the builtins whose call
** statement's children come first (the place depends on the form there);
** else the whole call. */
static SrcRange at(const ENode *call, int k) {
  int b = call->what ? builtin_index(call->what) : -1, nb;
  if (b < 0) return call->range;
  const Builtin *bi = &builtin_table(&nb)[b];
  const char *p = bi->params;
  for (int j = 0; j < k && p; j++) p = strchr(p, ',') ? strchr(p, ',') + 1 : NULL;
  size_t len = p ? strcspn(p, ",") : 0;
  for (int i = 0, pos = 0; i < call->n; i++) {
    if (call->names[i] && p && strlen(call->names[i]) == len && !strncmp(call->names[i], p, len))
      return call->kids[i]->range;
    if (!call->names[i] && pos++ == k && bi->kind == BI_FUNCTION) return call->kids[i]->range;
  }
  return call->range;
}
static Arena *arena(Eval *ev) { return &ev->scene->arena; }

static Value geom(SceneGeometry *g, const ENode *call) {
  g->loc = call->range;
  return val_ptr(V_GEOM, g);
}

/* A geometry the bridge could not make: its reason, at the call. */
static Value failed(Eval *ev, const ENode *call, const char *err) {
  ev_error(ev, call->range, "`%s`: %s", bi_name(call), err);
  return val_err();
}

static int positive(Eval *ev, const ENode *call, int i, const char *what, double x) {
  if (isfinite(x) && x > 0) return 0;
  ev_error(ev, at(call, i), "`%s` needs a %s greater than 0; found %g", bi_name(call), what, x);
  return -1;
}

static int is_finite(Eval *ev, const ENode *call, int i, const char *what, double x) {
  if (isfinite(x)) return 0;
  ev_error(ev, at(call, i), "`%s`: the %s is not finite (%g)", bi_name(call), what, x);
  return -1;
}

static int flag(Eval *ev, Value *a, int i, const ENode *call, int *out) {
  *out = 0;
  if (!given(&a[i])) return 0;
  if (a[i].kind != V_BOOL) return bi_type_error(ev, call, i, "true or false", &a[i]);
  *out = a[i].u.n != 0;
  return 0;
}

/* A number or [x, y] (both components the number when one is given). */
static int num_or_pair(Eval *ev, Value *a, int i, const ENode *call, Vec2 def, Vec2 *out) {
  *out = def;
  if (!given(&a[i])) return 0;
  if (a[i].kind == V_NUM) { out->x = out->y = a[i].u.n; return 0; }
  const List *l = a[i].kind == V_LIST ? a[i].u.l : NULL;
  if (!l || l->n != 2 || l->v[0].kind != V_NUM || l->v[1].kind != V_NUM)
    return bi_type_error(ev, call, i, "a number or [x, y]", &a[i]);
  *out = (Vec2){l->v[0].u.n, l->v[1].u.n};
  return 0;
}

/* OpenSCAD's $fn, $fa, $fs at arguments i, i + 1, i + 2: the segments of
** a full circle of radius r. With none given, SHAPE2D_SEGMENTS. */
static int fragments(Eval *ev, Value *a, int i, const ENode *call, double r, int *out) {
  double fn, fa, fs;
  *out = SHAPE2D_SEGMENTS;
  if (!given(&a[i]) && !given(&a[i + 1]) && !given(&a[i + 2])) return 0;
  if (bi_opt_num(ev, a, i, call, 0, &fn) || bi_opt_num(ev, a, i + 1, call, 12, &fa) ||
      bi_opt_num(ev, a, i + 2, call, 2, &fs))
    return -1;
  if (!(isfinite(fn) && fn >= 0)) {
    ev_error(ev, at(call, i), "`%s`: `$fn` must be 0 or more; found %g", bi_name(call), fn);
    return -1;
  }
  if (positive(ev, call, i + 1, "`$fa`", fa) || positive(ev, call, i + 2, "`$fs`", fs)) return -1;
  *out = shape2d_fragments(r, fn, fa, fs);
  if (*out > 0) return 0;
  ev_error(ev, call->range, "`%s`: `$fn`, `$fa` and `$fs` ask for more than %d segments a circle", bi_name(call),
           SHAPE2D_MAX_POINTS);
  return -1;
}

/* The 2D shapes of argument i (a shape or a list of them: a call
** statement's children), joined into one. */
static SceneGeometry *shapes_2d(Eval *ev, Value *a, int i, const ENode *call) {
  const Value *one = &a[i];
  int n = a[i].kind == V_LIST ? a[i].u.l->n : 1;
  const Value *v = a[i].kind == V_LIST ? a[i].u.l->v : one;
  const SceneGeometry **g = xmalloc((size_t)(n ? n : 1) * sizeof *g);
  SceneGeometry *r = NULL;
  for (int k = 0; k < n; k++) {
    if (v[k].kind != V_GEOM) {
      bi_type_error(ev, call, i, "a 2D shape or a list of them", &v[k]);
      goto out;
    }
    g[k] = v[k].u.g;
    if (!shape2d_is_2d(g[k]) && !shape2d_is_empty(g[k])) {
      ev_error(ev, a[i].kind == V_LIST ? g[k]->loc : at(call, i),
               "`%s` takes 2D shapes (circle, square, polygon, text, and their booleans); this is a 3D one%s",
               bi_name(call), g[k]->kind == GEOM_MESH && g[k]->nfaces ? " (or a 2D one tilted out of the xy-plane)" : "");
      goto out;
    }
  }
  char err[512];
  r = n == 1 ? (SceneGeometry *)g[0] : shape2d_boolean(arena(ev), SUMI_P2D_UNION, g, n, err, sizeof err);
  if (!r) failed(ev, call, err);
out:
  free(g);
  return r;
}

/* ---- shapes ---------------------------------------------------------------- */

/* circle(r = 1, d, $fn, $fa, $fs) */
static Value bi_circle(Eval *ev, Value *a, int n, const ENode *call) {
  double r;
  int segs;
  if (given(&a[1])) {
    if (bi_num(ev, a, 1, call, &r)) return val_err();
    r /= 2;
  } else if (bi_opt_num(ev, a, 0, call, 1, &r)) return val_err();
  if (positive(ev, call, given(&a[1]) ? 1 : 0, "radius", r) || fragments(ev, a, 2, call, r, &segs)) return val_err();
  char err[512];
  SceneGeometry *g = shape2d_circle(arena(ev), r, segs, err, sizeof err);
  return g ? geom(g, call) : failed(ev, call, err);
}

/* square(size = 1, center = false): size a number or [x, y] */
static Value bi_square(Eval *ev, Value *a, int n, const ENode *call) {
  Vec2 s;
  int center;
  if (num_or_pair(ev, a, 0, call, (Vec2){1, 1}, &s) || flag(ev, a, 1, call, &center) ||
      positive(ev, call, 0, "size", fmin(s.x, s.y)))
    return val_err();
  char err[512];
  SceneGeometry *g = shape2d_square(arena(ev), s, center, err, sizeof err);
  return g ? geom(g, call) : failed(ev, call, err);
}

/* The points of polygon's argument 0: [x, y] each, finite. */
static Vec2 *polygon_points(Eval *ev, Value *a, const ENode *call, int *n) {
  List *l;
  if (bi_list(ev, a, 0, call, &l)) return NULL;
  if (l->n > SHAPE2D_MAX_POINTS) {
    ev_error(ev, at(call, 0), "`polygon` takes at most %d points; found %d", SHAPE2D_MAX_POINTS, l->n);
    return NULL;
  }
  Vec2 *p = xmalloc((size_t)(l->n ? l->n : 1) * sizeof *p);
  for (int k = 0; k < l->n; k++) {
    const Value *q = &l->v[k];
    if (q->kind != V_LIST || q->u.l->n != 2 || q->u.l->v[0].kind != V_NUM || q->u.l->v[1].kind != V_NUM) {
      ev_error(ev, at(call, 0), "`polygon` expects points [x, y]; element %d is not one", k);
      free(p);
      return NULL;
    }
    p[k] = (Vec2){q->u.l->v[0].u.n, q->u.l->v[1].u.n};
    if (!isfinite(p[k].x) || !isfinite(p[k].y)) {
      ev_error(ev, at(call, 0), "`polygon`: point %d is not finite (it has a nan or inf coordinate)", k);
      free(p);
      return NULL;
    }
  }
  *n = l->n;
  return p;
}

/* polygon(points, paths, convexity): each path a list of point indices
** (3 or more); without paths, the points in order. Filled even-odd, as
** OpenSCAD: a path inside another is a hole. */
static Value bi_polygon(Eval *ev, Value *a, int n, const ENode *call) {
  int np = 0;
  Vec2 *pts = polygon_points(ev, a, call, &np);
  if (!pts) return val_err();
  List *paths = NULL;
  if (given(&a[1]) && bi_list(ev, a, 1, call, &paths)) { free(pts); return val_err(); }
  int npaths = paths ? paths->n : 1, total = 0;
  for (int k = 0; k < npaths; k++) {
    const Value *path = paths ? &paths->v[k] : NULL;
    int len = path ? (path->kind == V_LIST ? path->u.l->n : 0) : np;
    if (len < 3) {
      if (paths) ev_error(ev, at(call, 1), "`polygon`: path %d needs a list of 3 or more point indices", k);
      else ev_error(ev, at(call, 0), "`polygon` needs 3 or more points; found %d", np);
      free(pts);
      return val_err();
    }
    total += len;
  }
  Vec2 *ring = xmalloc((size_t)total * sizeof *ring);
  int *start = xmalloc((size_t)(npaths + 1) * sizeof *start), m = 0;
  for (int k = 0; k < npaths; k++) {
    start[k] = m;
    const List *path = paths ? paths->v[k].u.l : NULL;
    for (int j = 0; j < (path ? path->n : np); j++) {
      const Value *ix = path ? &path->v[j] : NULL;
      if (ix && (ix->kind != V_NUM || ix->u.n != floor(ix->u.n) || ix->u.n < 0 || ix->u.n >= np)) {
        ev_error(ev, at(call, 1), "`polygon`: path %d, index %d is not a point index (0 to %d)", k, j, np - 1);
        free(pts), free(ring), free(start);
        return val_err();
      }
      ring[m++] = pts[ix ? (int)ix->u.n : j];
    }
  }
  start[npaths] = m;
  char err[512];
  SceneGeometry *g = shape2d_from_contours(arena(ev), ring, start, npaths, SUMI_P2D_EVEN_ODD, err, sizeof err);
  free(pts), free(ring), free(start);
  return g ? geom(g, call) : failed(ev, call, err);
}

/* ---- text ----------------------------------------------------------------- */

/* Which of words ("a|b|c") string argument i is; def when not given. */
static int word(Eval *ev, Value *a, int i, const ENode *call, const char *what, const char *const *words, int n,
                int def, int *out) {
  *out = def;
  if (!given(&a[i])) return 0;
  if (a[i].kind != V_STR) return bi_type_error(ev, call, i, "a string", &a[i]);
  for (int k = 0; k < n; k++)
    if (!strcmp(a[i].u.s->s, words[k])) { *out = k; return 0; }
  const char *near = suggest_name(a[i].u.s->s, words, n);
  char list[200] = "";
  for (int k = 0; k < n; k++)
    snprintf(list + strlen(list), sizeof list - strlen(list), "%s\"%s\"", k ? (k + 1 == n ? " or " : ", ") : "", words[k]);
  if (near) ev_error(ev, at(call, i), "`%s`: unknown %s \"%s\"; did you mean \"%s\"?", bi_name(call), what,
                     a[i].u.s->s, near);
  else ev_error(ev, at(call, i), "`%s`: unknown %s \"%s\" (it is %s)", bi_name(call), what, a[i].u.s->s, list);
  return -1;
}

static int opt_string(Eval *ev, Value *a, int i, const ENode *call, const char **out) {
  *out = NULL;
  if (!given(&a[i])) return 0;
  if (a[i].kind != V_STR) return bi_type_error(ev, call, i, "a string", &a[i]);
  *out = a[i].u.s->s;
  return 0;
}

/* text(text, size = 10, font, halign = "left", valign = "baseline",
** spacing = 1, direction, language, script, $fn, $fa, $fs) */
static Value bi_text(Eval *ev, Value *a, int n, const ENode *call) {
  static const char *const halign[] = {"left", "center", "right"};
  static const char *const valign[] = {"baseline", "top", "center", "bottom"};
  static const char *const dirs[] = {"ltr", "rtl", "ttb"};
  TextLayout t = {0};
  int h, v, d = -1;
  if (a[0].kind != V_STR) return bi_type_error(ev, call, 0, "a string", &a[0]), val_err();
  t.text = a[0].u.s->s;
  t.len = a[0].u.s->len;
  if (bi_opt_num(ev, a, 1, call, 10, &t.size) || positive(ev, call, 1, "size", t.size) ||
      opt_string(ev, a, 2, call, &t.font) || word(ev, a, 3, call, "halign", halign, 3, 0, &h) ||
      word(ev, a, 4, call, "valign", valign, 4, 0, &v) || bi_opt_num(ev, a, 5, call, 1, &t.spacing) ||
      positive(ev, call, 5, "spacing", t.spacing) || word(ev, a, 6, call, "direction", dirs, 3, -1, &d) ||
      opt_string(ev, a, 7, call, &t.language) || opt_string(ev, a, 8, call, &t.script))
    return val_err();
  t.halign = (TextHAlign)h;
  t.valign = (TextVAlign)v;
  t.direction = d < 0 ? TEXT_AUTO : (TextDirection)(d + 1);
  TextOutline o;
  char err[512];
  if (text_outline(&t, SHAPE2D_MAX_POINTS, &o, err, sizeof err)) return failed(ev, call, err);
  if (o.substituted)
    diag_warning(at(call, 2), "font \"%s\" is not installed; `text` draws in \"%s\"", t.font, o.family);
  else if (o.fallback && t.font)
    diag_warning(at(call, 2), "font \"%s\" has no glyphs for some of the text; `text` draws it in \"%s\"",
                 t.font, o.family);
  SceneGeometry *g = shape2d_from_contours(arena(ev), o.pts, o.start, o.ncontours, SUMI_P2D_NON_ZERO, err, sizeof err);
  text_outline_free(&o);
  return g ? geom(g, call) : failed(ev, call, err);
}

/* ---- operations on 2D shapes ------------------------------------------- */

/* offset(shapes, r, delta, chamfer = false, $fn, $fa, $fs): grown by r
** with round corners, or by delta with sharp ones (cut off with chamfer);
** negative values shrink. Neither given: delta 1. */
static Value bi_offset(Eval *ev, Value *a, int n, const ENode *call) {
  SceneGeometry *s = shapes_2d(ev, a, 0, call);
  double d;
  int chamfer, segs = 0, round = given(&a[1]);
  if (!s || flag(ev, a, 3, call, &chamfer)) return val_err();
  if (round && given(&a[2])) {
    ev_error(ev, at(call, 2), "`offset` takes `r` or `delta`, not both");
    return val_err();
  }
  if (round ? bi_num(ev, a, 1, call, &d) : bi_opt_num(ev, a, 2, call, 1, &d)) return val_err();
  if (is_finite(ev, call, round ? 1 : 2, "offset", d) || fragments(ev, a, 4, call, fabs(d), &segs)) return val_err();
  SumiP2dJoin join = round ? SUMI_P2D_JOIN_ROUND : chamfer ? SUMI_P2D_JOIN_SQUARE : SUMI_P2D_JOIN_MITER;
  char err[512];
  SceneGeometry *g = shape2d_offset(arena(ev), s, d, join, segs, err, sizeof err);
  return g ? geom(g, call) : failed(ev, call, err);
}

/* The largest distance of s's points from the origin, and from the axis. */
static void reach(const SceneGeometry *s, double *r, double *x) {
  *r = *x = 0;
  for (int i = 0; s->ncontours && i < s->contour_start[s->ncontours]; i++) {
    Vec2 p = s->contour_pts[i];
    *r = fmax(*r, hypot(p.x, p.y));
    *x = fmax(*x, fabs(p.x));
  }
}

/* linear_extrude(shapes, height = 1, center = false, convexity, twist = 0,
** slices, scale = 1, $fn, $fa, $fs): slices default to 1 without a twist,
** else to the circle segments of the farthest point times the turns. */
static Value bi_linear_extrude(Eval *ev, Value *a, int n, const ENode *call) {
  SceneGeometry *s = shapes_2d(ev, a, 0, call);
  ExtrudeLinear p = {0};
  double conv, slices = 1, r, x;
  int segs;
  if (!s || bi_opt_num(ev, a, 1, call, 1, &p.height) || positive(ev, call, 1, "height", p.height) ||
      flag(ev, a, 2, call, &p.center) || bi_opt_num(ev, a, 3, call, 10, &conv) ||
      bi_opt_num(ev, a, 4, call, 0, &p.twist) || is_finite(ev, call, 4, "twist", p.twist) ||
      num_or_pair(ev, a, 6, call, (Vec2){1, 1}, &p.scale))
    return val_err();
  if (!(p.scale.x >= 0 && p.scale.y >= 0 && isfinite(p.scale.x) && isfinite(p.scale.y))) {
    ev_error(ev, at(call, 6), "`linear_extrude` needs a scale of 0 or more; found [%g, %g]", p.scale.x, p.scale.y);
    return val_err();
  }
  reach(s, &r, &x);
  if (fragments(ev, a, 7, call, r, &segs)) return val_err();
  if (given(&a[5])) {
    if (bi_num(ev, a, 5, call, &slices)) return val_err();
    if (!(slices >= 1 && slices == floor(slices) && slices <= EXTRUDE_MAX_VERTS)) {
      ev_error(ev, at(call, 5), "`linear_extrude` needs a whole number of slices, 1 or more; found %g", slices);
      return val_err();
    }
  } else if (p.twist != 0) slices = fmin(ceil(fmax(segs * fabs(p.twist) / 360, 1)), EXTRUDE_MAX_VERTS);
  p.slices = (int)slices;
  char err[512];
  SceneGeometry *g = extrude_linear(arena(ev), s, &p, err, sizeof err);
  return g ? geom(g, call) : failed(ev, call, err);
}

/* rotate_extrude(shapes, angle = 360, convexity, $fn, $fa, $fs) */
static Value bi_rotate_extrude(Eval *ev, Value *a, int n, const ENode *call) {
  SceneGeometry *s = shapes_2d(ev, a, 0, call);
  double angle, conv, r, x;
  int segs;
  if (!s || bi_opt_num(ev, a, 1, call, 360, &angle) || bi_opt_num(ev, a, 2, call, 2, &conv)) return val_err();
  if (!(fabs(angle) > 0 && fabs(angle) <= 360)) {
    ev_error(ev, at(call, 1), "`rotate_extrude` needs an angle from -360 to 360 degrees, not 0; found %g", angle);
    return val_err();
  }
  reach(s, &r, &x);
  if (fragments(ev, a, 3, call, x, &segs)) return val_err();
  segs = (int)fmin(ceil(fmax(segs * fabs(angle) / 360, 1)), EXTRUDE_MAX_VERTS);
  char err[512];
  SceneGeometry *g = extrude_rotate(arena(ev), s, angle, segs, err, sizeof err);
  return g ? geom(g, call) : failed(ev, call, err);
}

/* ---- the table ---------------------------------------------------------- */

static const Builtin builtins_2d[] = {
  {"circle", bi_circle, "r,d,$fn,$fa,$fs", 0, 5, BI_FUNCTION},
  {"square", bi_square, "size,center", 0, 2, BI_FUNCTION},
  {"polygon", bi_polygon, "points,paths,convexity", 1, 3, BI_FUNCTION},
  {"text", bi_text, "text,size,font,halign,valign,spacing,direction,language,script,$fn,$fa,$fs", 1, 12, BI_FUNCTION},
  {"offset", bi_offset, "shapes,r,delta,chamfer,$fn,$fa,$fs", 1, 7, BI_CHILDREN_FIRST},
  {"linear_extrude", bi_linear_extrude, "shapes,height,center,convexity,twist,slices,scale,$fn,$fa,$fs", 1, 10,
   BI_CHILDREN_FIRST},
  {"rotate_extrude", bi_rotate_extrude, "shapes,angle,convexity,$fn,$fa,$fs", 1, 6, BI_CHILDREN_FIRST},
};

const Builtin *builtin_2d_table(int *n) {
  *n = (int)(sizeof builtins_2d / sizeof builtins_2d[0]);
  return builtins_2d;
}
