/*
** Block schemas and the filling of the Scene from checked blocks.
**
** Each block kind has a table of rows (name, type, range, default, field,
** flags). check_block() runs every property of a finished block against its
** table: unknown names get the closest known one as a suggestion, a value of
** the wrong type or out of range names what was expected and what was found,
** a property given twice (unless repeatable) points at both, and a missing
** required property names the block. Written bottom-up: value converters,
** custom converters, the tables, then the checker and the emitters.
*/
#include "schema.h"

#include "habits.h"
#include "../io/infile.h"

#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef enum {
  T_NUM, T_INT, T_BOOL, T_STRING, T_COLOR, T_VEC3, T_SYMBOL, T_TRANSFORM,
  T_GEOMETRY, T_STYLE, T_COLORS, T_PARAM, T_CUSTOM
} PropType;

enum {
  R_REPEAT = 1,    /* may be given more than once */
  R_REQUIRED = 2,  /* the block needs it */
  R_MANY = 4,      /* takes several values (a custom converter reads them) */
  R_SYM = 8,       /* bare words in it are symbols, not names to look up */
  R_FIRST = 16,    /* converted before the others (it replaces the whole target) */
  R_FILE = 32,     /* a string naming a file (it has a `.` or a `/`) must exist */
  R_POSITIVE = 64  /* a number greater than 0 (the row's lo is then not used) */
};

/* The block being checked: where params go, and its name for messages. */
typedef struct Ctx {
  Eval *ev;
  SceneStyle *style;     /* for T_PARAM rows */
  const char *pass;      /* "shade", "noise", "pattern" */
  char what[64];         /* "lines", "shade toon" */
  int folded_n;          /* points in `folded`, checked against the paper */
} Ctx;

typedef struct Row Row;
typedef int (*Custom)(Ctx *c, const Prop *p, const Row *r, void *target);

struct Row {
  const char *name;
  PropType type;
  double lo, hi;         /* allowed range of numbers */
  double def;            /* default of numbers (NAN: none) */
  size_t off;            /* field in the target struct */
  unsigned flags;
  const char *symbols;   /* the words it knows, "a|b|c" (T_SYMBOL: stored as the index) */
  Custom custom;
};

#define NOFIELD ((size_t)-1)
#define NUM(n, S, f, lo, hi, def) {n, T_NUM, lo, hi, def, offsetof(S, f), 0, NULL, NULL}
#define INT(n, S, f, lo, hi, def) {n, T_INT, lo, hi, def, offsetof(S, f), 0, NULL, NULL}
#define TYPED(n, t, S, f) {n, t, 0, 0, NAN, offsetof(S, f), 0, NULL, NULL}
#define SYM(n, S, f, syms) {n, T_SYMBOL, 0, 0, NAN, offsetof(S, f), R_SYM, syms, NULL}
#define CUSTOM(n, fn, flags) {n, T_CUSTOM, 0, 0, NAN, NOFIELD, flags, NULL, fn}
#define CUSTOM_SYM(n, fn, flags, syms) {n, T_CUSTOM, 0, 0, NAN, NOFIELD, (flags) | R_SYM, syms, fn}
#define PARAM(n, flags) {n, T_PARAM, -INFINITY, INFINITY, NAN, NOFIELD, flags, NULL, NULL}
#define POSITIVE(n, S, f, def) {n, T_NUM, 0, 1e12, def, offsetof(S, f), R_POSITIVE, NULL, NULL}
#define BOOL(n, S, f) {n, T_BOOL, 0, 0, NAN, offsetof(S, f), 0, NULL, NULL}

/* ---- messages ---------------------------------------------------------- */

/* The property's name alone (for the caret under it). */
static SrcRange name_range(const Prop *p) {
  SrcRange r = p->loc;
  r.end_line = r.line;
  r.end_col = r.col + (int)strlen(p->name);
  return r;
}

static const char *a_type(const Value *v) {
  static char buf[4][48];
  static int k;
  const char *t = val_type_name(v);
  char *b = buf[k++ & 3];
  snprintf(b, sizeof buf[0], "%s %s", strchr("aeiou", t[0]) ? "an" : "a", t);
  return b;
}

static int expect(Ctx *c, const Prop *p, int i, const char *want) {
  const Value *v = i < p->n ? &p->v[i] : NULL;
  SrcRange at = i < p->n ? p->vloc[i] : name_range(p);
  if (!v) ev_error(c->ev, at, "`%s` in `%s` expects %s; found nothing", p->name, c->what, want);
  else ev_error(c->ev, at, "`%s` in `%s` expects %s; found %s", p->name, c->what, want, a_type(v));
  return -1;
}

/* A nan or inf reaching the scene would draw a silently wrong image. */
static int not_finite(Ctx *c, const Prop *p, int i, const char *what) {
  ev_error(c->ev, i < p->n ? p->vloc[i] : name_range(p), "`%s` in `%s` needs a finite %s (found nan or inf)",
           p->name, c->what, what);
  return -1;
}

static char *scene_str(Ctx *c, const char *s) {
  return arena_strndup(&c->ev->scene->arena, s, strlen(s));
}

/* Grow a scene array held in the scene arena (doubling at powers of two). */
static void *grow(Ctx *c, void *items, int n, size_t elem) {
  if (n & (n - 1) && n) return items;
  void *bigger = arena_alloc(&c->ev->scene->arena, (size_t)(n ? n * 2 : 4) * elem);
  if (n) memcpy(bigger, items, (size_t)n * elem);
  return bigger;
}

/* ---- value converters --------------------------------------------------- */

static int to_number(Ctx *c, const Prop *p, int i, const Row *r, double *out) {
  if (p->v[i].kind != V_NUM) return expect(c, p, i, r->type == T_INT ? "a whole number" : "a number");
  double x = p->v[i].u.n;
  if (r->type == T_INT && x != floor(x)) {
    char got[32];
    val_format_number(got, sizeof got, x);
    ev_error(c->ev, p->vloc[i], "`%s` in `%s` must be a whole number; found %s", p->name, c->what, got);
    return -1;
  }
  if ((r->flags & R_POSITIVE) && !(x > 0 && x <= r->hi)) {
    char got[32];
    val_format_number(got, sizeof got, x);
    ev_error(c->ev, p->vloc[i], "`%s` in `%s` must be greater than 0; found %s", p->name, c->what, got);
    return -1;
  }
  if (x < r->lo || x > r->hi || isnan(x)) {
    char lo[32], hi[32], got[32];
    val_format_number(lo, sizeof lo, r->lo);
    val_format_number(hi, sizeof hi, r->hi);
    val_format_number(got, sizeof got, x);
    if (isinf(r->hi)) ev_error(c->ev, p->vloc[i], "`%s` in `%s` must be at least %s; found %s", p->name, c->what, lo, got);
    else ev_error(c->ev, p->vloc[i], "`%s` in `%s` must be from %s to %s; found %s", p->name, c->what, lo, hi, got);
    return -1;
  }
  *out = x;
  return 0;
}

static int to_color(Ctx *c, const Prop *p, int i, Color *out) {
  const Value *v = &p->v[i];
  if (v->kind == V_COLOR) {
    *out = *v->u.c;
    if (!isfinite(out->r) || !isfinite(out->g) || !isfinite(out->b) || !isfinite(out->a))
      return not_finite(c, p, i, "colour");
    return 0;
  }
  if (v->kind == V_LIST && (v->u.l->n == 3 || v->u.l->n == 4)) {   /* linear [r, g, b(, a)] */
    float ch[4] = {0, 0, 0, 1};
    for (int k = 0; k < v->u.l->n; k++) {
      if (v->u.l->v[k].kind != V_NUM) return expect(c, p, i, "a colour (#rrggbb or [r, g, b])");
      ch[k] = (float)v->u.l->v[k].u.n;
    }
    *out = (Color){ch[0], ch[1], ch[2], ch[3]};
    if (!isfinite(out->r) || !isfinite(out->g) || !isfinite(out->b) || !isfinite(out->a))
      return not_finite(c, p, i, "colour");
    return 0;
  }
  return expect(c, p, i, "a colour (#rrggbb or [r, g, b])");
}

static int to_vec3(Ctx *c, const Prop *p, int i, Vec3 *out) {
  const Value *v = &p->v[i];
  if (v->kind == V_LIST && (v->u.l->n == 2 || v->u.l->n == 3)) {
    double x[3] = {0, 0, 0};
    int k;
    for (k = 0; k < v->u.l->n && v->u.l->v[k].kind == V_NUM; k++) x[k] = v->u.l->v[k].u.n;
    if (k == v->u.l->n) {
      *out = v3(x[0], x[1], x[2]);
      if (!isfinite(x[0]) || !isfinite(x[1]) || !isfinite(x[2])) return not_finite(c, p, i, "point");
      return 0;
    }
  }
  return expect(c, p, i, "a point [x, y, z]");
}

/* A symbol (or a string) naming one of "a|b|c": its index. */
static int to_symbol(Ctx *c, const Prop *p, int i, const char *choices, int *out) {
  const Value *v = &p->v[i];
  const char *name = v->kind == V_SYMBOL ? v->u.sym->name : v->kind == V_STR ? v->u.s->s : NULL;
  const char *opts[16];
  int n = 0;
  char buf[256];
  snprintf(buf, sizeof buf, "%s", choices);
  for (char *tok = strtok(buf, "|"); tok && n < 16; tok = strtok(NULL, "|")) opts[n++] = tok;
  for (int k = 0; name && k < n; k++)
    if (strcmp(name, opts[k]) == 0) { *out = k; return 0; }
  char list[300] = "";
  for (int k = 0; k < n; k++) {
    strcat(list, k == 0 ? "`" : k == n - 1 ? " or `" : ", `");
    strcat(list, opts[k]);
    strcat(list, "`");
  }
  if (!name) return expect(c, p, i, list);
  const char *s = suggest_name(name, opts, n);
  if (s) ev_error(c->ev, p->vloc[i], "`%s` in `%s` expects %s; found `%s`; did you mean `%s`?", p->name, c->what, list, name, s);
  else ev_error(c->ev, p->vloc[i], "`%s` in `%s` expects %s; found `%s`", p->name, c->what, list, name);
  return -1;
}

static int to_colors(Ctx *c, const Prop *p, Color **out, int *n) {
  const Value *v = &p->v[0];
  if (v->kind != V_LIST || v->u.l->n == 0) return expect(c, p, 0, "a list of colours");
  *n = v->u.l->n;
  *out = arena_alloc(&c->ev->scene->arena, (size_t)*n * sizeof **out);
  for (int k = 0; k < *n; k++) {
    if (v->u.l->v[k].kind != V_COLOR) return expect(c, p, 0, "a list of colours");
    (*out)[k] = *v->u.l->v[k].u.c;
  }
  return 0;
}

/* A T_PARAM property: numbers, a vector, a colour, a string or a symbol. */
static int to_param(Ctx *c, const Prop *p, const Row *r) {
  SceneStyle *st = c->style;
  st->params = grow(c, st->params, st->nparams, sizeof *st->params);
  SceneParam *sp = &st->params[st->nparams];
  memset(sp, 0, sizeof *sp);
  sp->pass = c->pass;
  sp->name = r->name;
  sp->loc = p->loc;
  const Value *v = &p->v[0];
  List *nums = NULL;
  switch (v->kind) {
  case V_NUM: case V_BOOL: sp->n = 1; sp->num = arena_alloc(&c->ev->scene->arena, sizeof(double)); sp->num[0] = v->u.n; break;
  case V_COLOR:
    sp->n = 4;
    sp->num = arena_alloc(&c->ev->scene->arena, 4 * sizeof(double));
    sp->num[0] = v->u.c->r; sp->num[1] = v->u.c->g; sp->num[2] = v->u.c->b; sp->num[3] = v->u.c->a;
    break;
  case V_STR: sp->str = scene_str(c, v->u.s->s); break;
  case V_SYMBOL: sp->str = scene_str(c, v->u.sym->name); nums = v->u.sym->args; break;
  case V_LIST: nums = v->u.l; break;
  default: return expect(c, p, 0, "a number, a vector, a colour, a string or a word");
  }
  if (nums) {
    sp->n = nums->n;
    sp->num = arena_alloc(&c->ev->scene->arena, (size_t)(nums->n + 1) * sizeof(double));
    for (int k = 0; k < nums->n; k++) {
      if (nums->v[k].kind != V_NUM) return expect(c, p, 0, "numbers");
      sp->num[k] = nums->v[k].u.n;
    }
  }
  st->nparams++;
  return 0;
}

/* Convert a one-valued property by its row's type into target + off. */
static int convert(Ctx *c, const Prop *p, const Row *r, void *target) {
  char *f = (char *)target + (r->off == NOFIELD ? 0 : r->off);
  const Value *v = &p->v[0];
  double x;
  int k;
  switch (r->type) {
  case T_NUM: if (to_number(c, p, 0, r, &x)) return -1; *(double *)f = x; return 0;
  case T_INT: if (to_number(c, p, 0, r, &x)) return -1; *(int *)f = (int)x; return 0;
  case T_BOOL:
    if (v->kind != V_BOOL) return expect(c, p, 0, "`true` or `false`");
    *(int *)f = v->u.n != 0;
    return 0;
  case T_STRING:
    if (v->kind != V_STR) return expect(c, p, 0, "a string");
    *(const char **)f = scene_str(c, v->u.s->s);
    return 0;
  case T_COLOR: return to_color(c, p, 0, (Color *)f);
  case T_VEC3: return to_vec3(c, p, 0, (Vec3 *)f);
  case T_SYMBOL: if (to_symbol(c, p, 0, r->symbols, &k)) return -1; *(int *)f = k; return 0;
  case T_TRANSFORM:
    if (v->kind != V_XFORM) return expect(c, p, 0, "a transform (translate, rotate, scale, matrix)");
    *(Mat4 *)f = *v->u.m;
    for (int q = 0; q < 16; q++)
      if (!isfinite(v->u.m->m[q / 4][q % 4])) return not_finite(c, p, 0, "transform");
    return 0;
  case T_GEOMETRY:
    if (v->kind != V_GEOM) return expect(c, p, 0, "a geometry (bezier, mesh, teapot(), ...)");
    *(SceneGeometry **)f = v->u.g;
    return 0;
  case T_STYLE:
    if (v->kind != V_STYLE) return expect(c, p, 0, "a style");
    *(int *)f = v->aux;
    return 0;
  case T_COLORS: {
    Color **list = (Color **)f;
    int *n = (int *)(f + sizeof(Color *));   /* the count follows the pointer */
    return to_colors(c, p, list, n);
  }
  case T_PARAM: return to_param(c, p, r);
  case T_CUSTOM: return r->custom(c, p, r, target);
  }
  return -1;
}

/* ---- custom converters ------------------------------------------------ */

static int cv_size(Ctx *c, const Prop *p, const Row *r, void *t) {
  SceneOutput *o = t;
  const Value *v = &p->v[0];
  if (v->kind != V_LIST || v->u.l->n != 2) return expect(c, p, 0, "[width, height]");
  int wh[2];
  for (int k = 0; k < 2; k++) {
    const Value *x = &v->u.l->v[k];
    if (x->kind != V_NUM || x->u.n != floor(x->u.n) || x->u.n < 1 || x->u.n > SCHEMA_MAX_IMAGE_SIDE) {
      ev_error(c->ev, p->vloc[0], "`size` in `output` needs whole numbers from 1 to %d (the limit)",
               SCHEMA_MAX_IMAGE_SIDE);
      return -1;
    }
    wh[k] = (int)x->u.n;
  }
  o->width = wh[0];
  o->height = wh[1];
  return 0;
}

static int cv_ortho(Ctx *c, const Prop *p, const Row *r, void *t) {
  SceneCamera *cam = t;
  Row num = {"ortho", T_NUM, 1e-9, INFINITY, NAN, 0, 0, NULL, NULL};
  if (to_number(c, p, 0, &num, &cam->ortho_height)) return -1;
  cam->kind = CAMERA_ORTHO;
  return 0;
}

static int cv_light_position(Ctx *c, const Prop *p, const Row *r, void *t) {
  SceneLight *l = t;   /* a point light (the default kind), or a spot's place */
  return to_vec3(c, p, 0, &l->position);
}

static int cv_light_direction(Ctx *c, const Prop *p, const Row *r, void *t) {
  SceneLight *l = t;
  if (to_vec3(c, p, 0, &l->direction)) return -1;
  if (v3_len(l->direction) == 0) {
    ev_error(c->ev, p->vloc[0], "`direction` in `light` cannot be [0, 0, 0]");
    return -1;
  }
  l->kind = LIGHT_DIRECTIONAL;
  return 0;
}

/* point_at [x, y, z]; makes the light a spot aimed there. */
static int cv_light_point_at(Ctx *c, const Prop *p, const Row *r, void *t) {
  SceneLight *l = t;
  if (to_vec3(c, p, 0, &l->point_at)) return -1;
  l->kind = LIGHT_SPOT;
  return 0;
}

/* kinds silhouette, crease(40), boundary, face_edges; */
static int cv_kinds(Ctx *c, const Prop *p, const Row *r, void *t) {
  SceneLines *l = t;
  static const char *names[] = {"silhouette", "crease", "boundary", "face_edges"};
  static const unsigned bits[] = {EDGE_SILHOUETTE, EDGE_CREASE, EDGE_BOUNDARY, EDGE_FACE};
  l->kinds = 0;
  for (int i = 0; i < p->n; i++) {
    const Value *v = &p->v[i];
    const char *name = v->kind == V_SYMBOL ? v->u.sym->name : v->kind == V_STR ? v->u.s->s : NULL;
    int k = 0;
    while (name && k < 4 && strcmp(name, names[k]) != 0) k++;
    if (!name || k == 4) {
      const char *s = name ? suggest_name(name, names, 4) : NULL;
      if (s) ev_error(c->ev, p->vloc[i], "unknown edge kind `%s`; did you mean `%s`?", name, s);
      else if (name) ev_error(c->ev, p->vloc[i], "unknown edge kind `%s` (silhouette, crease(angle), boundary, face_edges)", name);
      else expect(c, p, i, "edge kinds (silhouette, crease(angle), boundary, face_edges)");
      return -1;
    }
    List *args = v->kind == V_SYMBOL ? v->u.sym->args : NULL;
    if (bits[k] == EDGE_CREASE && args && args->n == 1 && args->v[0].kind == V_NUM &&
        args->v[0].u.n >= 0 && args->v[0].u.n <= 180)
      l->crease_angle = args->v[0].u.n;
    else if (args && (bits[k] != EDGE_CREASE || args->n > 0)) {
      ev_error(c->ev, p->vloc[i], bits[k] == EDGE_CREASE ? "`crease(angle)` needs one angle from 0 to 180 degrees"
                                                        : "`%s` takes no arguments", names[k]);
      return -1;
    }
    l->kinds |= bits[k];
  }
  return 0;
}

/* tessellate N; or tessellate adaptive(pixels); */
static int cv_tessellate(Ctx *c, const Prop *p, const Row *r, void *t) {
  SceneObject *o = t;
  const Value *v = &p->v[0];
  if (v->kind == V_NUM) {
    Row num = {"tessellate", T_INT, 1, SCHEMA_MAX_TESSELLATE, NAN, 0, 0, NULL, NULL};
    double n;
    if (to_number(c, p, 0, &num, &n)) return -1;
    o->tess_kind = TESS_UNIFORM;
    o->tess_n = (int)n;
    return 0;
  }
  if (v->kind == V_SYMBOL && strcmp(v->u.sym->name, "adaptive") == 0 && v->u.sym->args &&
      v->u.sym->args->n == 1 && v->u.sym->args->v[0].kind == V_NUM && v->u.sym->args->v[0].u.n > 0) {
    o->tess_kind = TESS_ADAPTIVE;
    o->tess_px = v->u.sym->args->v[0].u.n;
    return 0;
  }
  return expect(c, p, 0, "a number of segments or adaptive(pixels > 0)");
}

static int cv_weights(Ctx *c, const Prop *p, const Row *r, void *t) {
  SceneShade *s = t;
  const Value *v = &p->v[0];
  if (v->kind != V_LIST || v->u.l->n != 3) return expect(c, p, 0, "[wa, wb, wc]");
  for (int k = 0; k < 3; k++) {
    if (v->u.l->v[k].kind != V_NUM) return expect(c, p, 0, "[wa, wb, wc]");
    s->origami_weights[k] = v->u.l->v[k].u.n;
  }
  return 0;
}

/* ---- shade ink and the sheet ---------------------------------------------- */

/* A list of 1..max numbers in [0, 1], each above the one before it (the
** quantisation's ranges and tones run from dark to light), into out. */
static int ink_rising(Ctx *c, const Prop *p, int max, double *out, int *n) {
  const Value *v = &p->v[0];
  if (v->kind != V_LIST || v->u.l->n < 1) return expect(c, p, 0, "a list of numbers from 0 to 1");
  if (v->u.l->n > max) {
    ev_error(c->ev, p->vloc[0], "`%s` in `%s` takes at most %d values; found %d", p->name, c->what, max,
             v->u.l->n);
    return -1;
  }
  for (int k = 0; k < v->u.l->n; k++) {
    const Value *x = &v->u.l->v[k];
    if (x->kind != V_NUM) return expect(c, p, 0, "a list of numbers from 0 to 1");
    char got[32], prev[32];
    val_format_number(got, sizeof got, x->u.n);
    if (!(x->u.n >= 0 && x->u.n <= 1)) {
      ev_error(c->ev, p->vloc[0], "`%s` in `%s`: value %d is %s, outside 0 to 1", p->name, c->what, k + 1, got);
      return -1;
    }
    if (k > 0 && !(x->u.n > out[k - 1])) {
      val_format_number(prev, sizeof prev, out[k - 1]);
      ev_error(c->ev, p->vloc[0], "`%s` in `%s` are out of order: value %d (%s) is not above value %d (%s); "
               "they rise from dark to light", p->name, c->what, k + 1, got, k, prev);
      return -1;
    }
    out[k] = x->u.n;
  }
  *n = v->u.l->n;
  return 0;
}

/* levels [0.4, 0.6, 0.9]: the thresholds of the quantisation. */
static int cv_ink_levels(Ctx *c, const Prop *p, const Row *r, void *t) {
  ShadeInk *k = &((SceneShade *)t)->ink;
  k->levels_loc = p->vloc[0];
  if (ink_rising(c, p, INK_MAX_TONES - 1, k->levels, &k->nlevels)) return -1;
  if (k->levels[0] > 0) return 0;
  ev_error(c->ev, p->vloc[0], "`levels` in `%s`: the first threshold must be above 0 (the darkest range "
           "[0, t) would be empty)", c->what);
  return -1;
}

/* tones [0.4, 0.6, 0.9, 1]: the value each range becomes. */
static int cv_ink_tones(Ctx *c, const Prop *p, const Row *r, void *t) {
  ShadeInk *k = &((SceneShade *)t)->ink;
  k->tones_loc = p->vloc[0];
  return ink_rising(c, p, INK_MAX_TONES, k->tones, &k->ntones);
}

/* lights key, rim;: names of the scene's lights (checked when rendering:
** a light may be written after the style). */
static int cv_ink_lights(Ctx *c, const Prop *p, const Row *r, void *t) {
  ShadeInk *k = &((SceneShade *)t)->ink;
  k->lights = arena_alloc(&c->ev->scene->arena, (size_t)(p->n + 1) * sizeof *k->lights);
  for (int i = 0; i < p->n; i++) {
    const Value *v = &p->v[i];
    const char *name = v->kind == V_SYMBOL && !v->u.sym->args ? v->u.sym->name : v->kind == V_STR ? v->u.s->s : NULL;
    if (!name) return expect(c, p, i, "the name of a light");
    k->lights[i] = scene_str(c, name);
  }
  k->nlights = p->n;
  k->lights_loc = p->loc;
  return 0;
}

/* After a shade ink block: the tones must match the ranges, the box be odd. */
static int check_ink(Ctx *c, const ShadeInk *k) {
  if (k->ntones && k->ntones != k->nlevels + 1) {
    ev_error(c->ev, k->tones_loc, "`tones` in `%s` needs %d values, one for each range the %d `levels` make; "
             "found %d", c->what, k->nlevels + 1, k->nlevels, k->ntones);
    return -1;
  }
  return 0;
}

static int cv_box_filter(Ctx *c, const Prop *p, const Row *r, void *t) {
  const Value *v = &p->v[0];
  if (v->kind != V_NUM || v->u.n != floor(v->u.n) || v->u.n < 1 || v->u.n > INK_MAX_BOX || fmod(v->u.n, 2) != 1) {
    char got[32] = "";
    if (v->kind == V_NUM) val_format_number(got, sizeof got, v->u.n);
    ev_error(c->ev, p->vloc[0], "`box_filter` in `%s` is the box's side: an odd whole number from 1 (none) to %d; "
             "found %s", c->what, INK_MAX_BOX, v->kind == V_NUM ? got : a_type(v));
    return -1;
  }
  ((SceneShade *)t)->ink.box_filter = (int)v->u.n;
  return 0;
}

/* background #c; background #top, ..., #bottom; background "sky.png";
** in output: a colour, a vertical gradient through the colours (evenly
** spaced, top to bottom), or an image file scaled to the frame (resolved
** against the folder of the file that wrote it; R_FILE has checked it can
** be read). A gradient or an image is opaque. */
static int cv_background(Ctx *c, const Prop *p, const Row *r, void *t) {
  SceneOutput *o = t;
  o->background_loc = p->vloc[0];
  const Value *v = &p->v[0];
  if (p->n == 1 && v->kind == V_STR) {
    if (!strpbrk(v->u.s->s, "./")) {
      ev_error(c->ev, p->vloc[0], "`background` in `output` is a colour, colours or an image file (a path "
               "with a `.` or a `/`); `%s` is none of them", v->u.s->s);
      return -1;
    }
    const SrcFile *f = p->loc.file >= 0 ? diag_file(p->loc.file) : NULL;
    const char *slash = f ? strrchr(f->name, '/') : NULL;
    char full[4096];
    if (v->u.s->s[0] == '/' || !slash) snprintf(full, sizeof full, "%s", v->u.s->s);
    else snprintf(full, sizeof full, "%.*s/%s", (int)(slash - f->name), f->name, v->u.s->s);
    o->backdrop = scene_str(c, full);
    o->backdrop_name = scene_str(c, v->u.s->s);
    o->background = (Color){0, 0, 0, 1};
    return 0;
  }
  if (p->n > SCENE_MAX_BACKGROUND_STOPS) {
    ev_error(c->ev, p->vloc[SCENE_MAX_BACKGROUND_STOPS], "`background` in `output` takes at most %d colours "
             "(SCENE_MAX_BACKGROUND_STOPS)", SCENE_MAX_BACKGROUND_STOPS);
    return -1;
  }
  Color stops[SCENE_MAX_BACKGROUND_STOPS] = {{0, 0, 0, 1}};
  for (int i = 0; i < p->n; i++)
    if (to_color(c, p, i, &stops[i])) return -1;
  o->background = stops[0];
  if (p->n == 1) return 0;
  o->nstops = p->n;
  o->stops = arena_alloc(&c->ev->scene->arena, (size_t)p->n * sizeof *o->stops);
  for (int i = 0; i < p->n; i++) { o->stops[i] = stops[i]; o->stops[i].a = 1; }
  o->background.a = 1;
  return 0;
}

/* sheet "xuan"; or sheet "paper.png"; in output: the paper, with the
** defaults of a `sheet { }` block. */
static int cv_sheet(Ctx *c, const Prop *p, const Row *r, void *t) {
  SceneOutput *o = t;
  if (p->v[0].kind != V_STR) return expect(c, p, 0, "a string: \"xuan\" or an image file");
  if (o->sheet.texture) {
    ev_error(c->ev, name_range(p), "the sheet is given twice in `output`");
    diag_note(o->sheet.loc, "first given here");
    return -1;
  }
  o->sheet = scene_default_sheet();
  o->sheet.texture = scene_str(c, p->v[0].u.s->s);
  o->sheet.loc = p->vloc[0];
  return 0;
}

/* An index from 0 to n-1 in a value. */
static int get_index(const Value *v, int n, int *out) {
  if (v->kind != V_NUM || v->u.n != floor(v->u.n) || v->u.n < 0 || v->u.n >= n) return 0;
  *out = (int)v->u.n;
  return 1;
}

static int cv_vertices(Ctx *c, const Prop *p, const Row *r, void *t) {
  SceneOrigami *o = t;
  const Value *v = &p->v[0];
  if (v->kind != V_LIST) return expect(c, p, 0, "a list of points [x, y]");
  o->nverts = v->u.l->n;
  o->verts = arena_alloc(&c->ev->scene->arena, (size_t)(o->nverts + 1) * sizeof *o->verts);
  o->vert_loc = arena_alloc(&c->ev->scene->arena, (size_t)(o->nverts + 1) * sizeof *o->vert_loc);
  int warned = 0;
  for (int k = 0; k < o->nverts; k++) {
    const Value *q = &v->u.l->v[k];
    if (q->kind != V_LIST || q->u.l->n < 2 || q->u.l->n > 3 || q->u.l->v[0].kind != V_NUM ||
        q->u.l->v[1].kind != V_NUM || (q->u.l->n == 3 && q->u.l->v[2].kind != V_NUM)) {
      ev_error(c->ev, p->vloc[0], "`vertices` in `paper`: vertex %d is not a point [x, y]", k);
      return -1;
    }
    /* [x, y, 0] is a flat point too; another z would be a folded state */
    if (q->u.l->n == 3 && q->u.l->v[2].u.n != 0 && !warned++)
      diag_warning(p->vloc[0], "`vertices` in `paper`: vertex %d has z = %g, which is ignored: the "
                   "paper lies flat in the xy-plane (its creases fold it)", k,
                   q->u.l->v[2].u.n);
    o->verts[k] = (Vec2){q->u.l->v[0].u.n, q->u.l->v[1].u.n};
    o->vert_loc[k] = p->vloc[0];
  }
  return 0;
}

static int cv_creases(Ctx *c, const Prop *p, const Row *r, void *t) {
  SceneOrigami *o = t;
  const Value *v = &p->v[0];
  if (v->kind != V_LIST) return expect(c, p, 0, "a list of creases [a, b, \"M\"]");
  o->ncreases = v->u.l->n;
  o->creases = arena_alloc(&c->ev->scene->arena, (size_t)(o->ncreases + 1) * sizeof *o->creases);
  for (int k = 0; k < o->ncreases; k++) {
    const Value *q = &v->u.l->v[k];
    OrigamiCrease *cr = &o->creases[k];
    const Value *as = q->kind == V_LIST && q->u.l->n == 3 ? &q->u.l->v[2] : NULL;
    if (!as || !get_index(&q->u.l->v[0], o->nverts, &cr->a) || !get_index(&q->u.l->v[1], o->nverts, &cr->b) ||
        as->kind != V_STR || as->u.s->len != 1 || !strchr("MVBFU", as->u.s->s[0])) {
      ev_error(c->ev, p->vloc[0],
               "`creases` in `paper`: crease %d must be [a, b, \"M\"|\"V\"|\"B\"|\"F\"|\"U\"] with vertices 0 to %d", k,
               o->nverts - 1);
      return -1;
    }
    cr->assignment = as->u.s->s[0];
    cr->loc = p->vloc[0];
  }
  return 0;
}

static int cv_faces(Ctx *c, const Prop *p, const Row *r, void *t) {
  SceneOrigami *o = t;
  const Value *v = &p->v[0];
  if (v->kind != V_LIST) return expect(c, p, 0, "a list of faces (lists of vertex indices)");
  int total = 0;
  for (int k = 0; k < v->u.l->n; k++) {
    const Value *f = &v->u.l->v[k];
    if (f->kind != V_LIST || f->u.l->n < 3) {
      ev_error(c->ev, p->vloc[0], "`faces` in `paper`: face %d needs 3 or more vertex indices", k);
      return -1;
    }
    total += f->u.l->n;
  }
  o->nfaces = v->u.l->n;
  o->face_start = arena_alloc(&c->ev->scene->arena, (size_t)(o->nfaces + 1) * sizeof(int));
  o->face_index = arena_alloc(&c->ev->scene->arena, (size_t)(total + 1) * sizeof(int));
  o->face_loc = arena_alloc(&c->ev->scene->arena, (size_t)(o->nfaces + 1) * sizeof *o->face_loc);
  int n = 0;
  for (int k = 0; k < o->nfaces; k++) {
    const List *f = v->u.l->v[k].u.l;
    o->face_start[k] = n;
    o->face_loc[k] = p->vloc[0];
    for (int j = 0; j < f->n; j++)
      if (!get_index(&f->v[j], o->nverts, &o->face_index[n++])) {
        ev_error(c->ev, p->vloc[0], "`faces` in `paper`: face %d, entry %d is not a vertex index (0 to %d)", k, j,
                 o->nverts - 1);
        return -1;
      }
  }
  o->face_start[o->nfaces] = n;
  return 0;
}

/* paper fold_file("x.fold"); — the crease pattern of a FOLD file. */
static int cv_paper(Ctx *c, const Prop *p, const Row *r, void *t) {
  SceneOrigami *o = t;
  if (p->v[0].kind != V_PAPER) return expect(c, p, 0, "a crease pattern (a `paper { ... }` block or fold_file(\"x.fold\"))");
  const SceneOrigami *src = p->v[0].u.paper;
  const char *name = o->name;
  Mat4 m = o->transform;
  int style = o->style;
  SrcRange loc = o->loc;
  *o = *src;
  o->state_loc = src_none();      /* `overlap` and `state` come after `paper` */
  o->name = name;
  o->transform = m;
  o->style = style;
  o->loc = loc;
  return 0;
}

static int cv_folded(Ctx *c, const Prop *p, const Row *r, void *t) {
  SceneOrigami *o = t;
  const Value *v = &p->v[0];
  if (v->kind != V_LIST) return expect(c, p, 0, "a list of folded points [x, y]");
  o->folded = arena_alloc(&c->ev->scene->arena, (size_t)(v->u.l->n + 1) * sizeof *o->folded);
  for (int k = 0; k < v->u.l->n; k++) {
    const Value *q = &v->u.l->v[k];
    double x[3] = {0, 0, 0};
    int ok = q->kind == V_LIST && q->u.l->n >= 2 && q->u.l->n <= 3;
    for (int j = 0; ok && j < q->u.l->n; j++) {
      ok = q->u.l->v[j].kind == V_NUM;
      if (ok) x[j] = q->u.l->v[j].u.n;
    }
    if (!ok) {
      ev_error(c->ev, p->vloc[0], "`folded` in `origami`: point %d is not [x, y]", k);
      return -1;
    }
    o->folded[k] = v3(x[0], x[1], x[2]);
  }
  o->has_folded = 1;
  c->folded_n = v->u.l->n;   /* checked against nverts when the block ends */
  return 0;
}

static int cv_above(Ctx *c, const Prop *p, const Row *r, void *t) {
  SceneOrigami *o = t;
  const Value *v = &p->v[0];
  if (v->kind != V_LIST || v->u.l->n != 2 || v->u.l->v[0].kind != V_NUM || v->u.l->v[1].kind != V_NUM ||
      v->u.l->v[0].u.n < 0 || v->u.l->v[1].u.n < 0 || v->u.l->v[0].u.n != floor(v->u.l->v[0].u.n) ||
      v->u.l->v[1].u.n != floor(v->u.l->v[1].u.n))
    return expect(c, p, 0, "[upper face, lower face]");
  o->above = grow(c, o->above, o->nabove, sizeof *o->above);
  OrigamiAbove *a = &o->above[o->nabove++];
  a->upper = (int)v->u.l->v[0].u.n;
  a->lower = (int)v->u.l->v[1].u.n;
  a->loc = p->loc;
  return 0;
}

/* overlap auto; | overlap ["-UL", ...]; */
static int cv_overlap(Ctx *c, const Prop *p, const Row *r, void *t) {
  SceneOrigami *o = t;
  const Value *v = &p->v[0];
  if (v->kind == V_SYMBOL && strcmp(v->u.sym->name, "auto") == 0 && !v->u.sym->args) {
    o->overlap_auto = 1;
    o->overlap_loc = p->loc;
    return 0;
  }
  if (v->kind != V_LIST) return expect(c, p, 0, "`auto` or a list of strings of `-`, `U` and `L`");
  int n = v->u.l->n;
  o->overlap = arena_alloc(&c->ev->scene->arena, (size_t)(n + 1) * sizeof *o->overlap);
  for (int k = 0; k < n; k++) {
    const Value *row = &v->u.l->v[k];
    if (row->kind != V_STR || row->u.s->len != n || strspn(row->u.s->s, "-UL") != (size_t)n) {
      ev_error(c->ev, p->vloc[0], "`overlap` row %d must be a string of %d characters `-`, `U` or `L`", k, n);
      return -1;
    }
    o->overlap[k] = scene_str(c, row->u.s->s);
  }
  o->noverlap = n;
  o->overlap_loc = p->loc;
  return 0;
}

/* state K; — which of the solver's states `overlap auto` renders. */
static int cv_state(Ctx *c, const Prop *p, const Row *r, void *t) {
  SceneOrigami *o = t;
  Row num = {"state", T_INT, 0, 2e9, NAN, 0, 0, NULL, NULL};
  double n;
  if (to_number(c, p, 0, &num, &n)) return -1;
  o->state = (long)n;
  o->state_loc = p->loc;
  return 0;
}

/* lit / unlit in shade bokashi: a colour, marked as given (the defaults
** follow the style's base colour). */
static int cv_bokashi_color(Ctx *c, const Prop *p, const Row *r, void *t) {
  ShadeBokashi *b = &((SceneShade *)t)->bokashi;
  int lit = strcmp(r->name, "lit") == 0;
  if (to_color(c, p, 0, lit ? &b->lit : &b->unlit)) return -1;
  if (lit) b->has_lit = 1;
  else b->has_unlit = 1;
  return 0;
}

/* colors [c0, c1, ...]; in pattern: the ramp the image's grey value indexes. */
static int cv_pattern_colors(Ctx *c, const Prop *p, const Row *r, void *t) {
  ScenePattern *pt = &((SceneStyle *)t)->pattern;
  if (to_colors(c, p, &pt->colors, &pt->ncolors)) return -1;
  if (pt->ncolors >= 2 && pt->ncolors <= SCENE_MAX_PATTERN_COLORS) return 0;
  ev_error(c->ev, p->vloc[0], "`colors` in `pattern` takes 2 to %d colours; found %d", SCENE_MAX_PATTERN_COLORS,
           pt->ncolors);
  return -1;
}

/* centre [x, y, z]; in object space. */
static int cv_centre(Ctx *c, const Prop *p, const Row *r, void *t) {
  SceneObject *o = t;
  if (to_vec3(c, p, 0, &o->centre)) return -1;
  o->has_centre = 1;
  return 0;
}

/* image "file.png"; in noise or pattern: the path resolved against the
** folder of the file that wrote it, read when the frame is prepared. */
static int cv_image(Ctx *c, const Prop *p, const Row *r, void *t) {
  const Value *v = &p->v[0];
  if (v->kind != V_STR || v->u.s->len == 0) return expect(c, p, 0, "an image file name (a string)");
  const SrcFile *f = p->loc.file >= 0 ? diag_file(p->loc.file) : NULL;
  const char *slash = f ? strrchr(f->name, '/') : NULL;
  char full[4096];
  if (v->u.s->s[0] == '/' || !slash) snprintf(full, sizeof full, "%s", v->u.s->s);
  else snprintf(full, sizeof full, "%.*s/%s", (int)(slash - f->name), f->name, v->u.s->s);
  const char *path = scene_str(c, full), *name = scene_str(c, v->u.s->s);
  if (strcmp(c->what, "noise") == 0) {
    SceneNoise *n = &((SceneStyle *)t)->noise;
    n->image = path; n->image_name = name; n->image_loc = p->vloc[0];
  } else {
    ScenePattern *pt = &((SceneStyle *)t)->pattern;
    pt->image = path; pt->image_name = name; pt->image_loc = p->vloc[0];
  }
  return 0;
}

/* texture "wood.png"; in a style: an image file on the object's (u, v),
** resolved against the folder of the file that wrote it (R_FILE has
** checked it can be read); whether it decodes is found when the frame is
** prepared. */
static int cv_style_texture(Ctx *c, const Prop *p, const Row *r, void *t) {
  const Value *v = &p->v[0];
  if (v->kind != V_STR || v->u.s->len == 0) return expect(c, p, 0, "an image file name (a string)");
  if (!strpbrk(v->u.s->s, "./")) {
    ev_error(c->ev, p->vloc[0], "`texture` in `style` names an image file (a path with a `.` or a `/`); "
             "`%s` is not one", v->u.s->s);
    return -1;
  }
  const SrcFile *f = p->loc.file >= 0 ? diag_file(p->loc.file) : NULL;
  const char *slash = f ? strrchr(f->name, '/') : NULL;
  char full[4096];
  if (v->u.s->s[0] == '/' || !slash) snprintf(full, sizeof full, "%s", v->u.s->s);
  else snprintf(full, sizeof full, "%.*s/%s", (int)(slash - f->name), f->name, v->u.s->s);
  SceneStyle *st = t;
  st->texture = scene_str(c, full);
  st->texture_name = scene_str(c, v->u.s->s);
  st->texture_loc = p->vloc[0];
  return 0;
}

/* range [lo, hi]; — a layer's tone range, 0 <= lo < hi <= 1. */
static int cv_range(Ctx *c, const Prop *p, const Row *r, void *t) {
  ThresholdLayer *l = t;
  const Value *v = &p->v[0];
  if (v->kind != V_LIST || v->u.l->n != 2 || v->u.l->v[0].kind != V_NUM || v->u.l->v[1].kind != V_NUM)
    return expect(c, p, 0, "a tone range [low, high]");
  double lo = v->u.l->v[0].u.n, hi = v->u.l->v[1].u.n;
  if (!(lo >= 0 && lo < hi && hi <= 1)) {
    ev_error(c->ev, p->vloc[0], "`range` in `%s` needs 0 <= low < high <= 1", c->what);
    return -1;
  }
  l->range[0] = lo;
  l->range[1] = hi;
  return 0;
}

/* A strength curve: values from 0 to 1 spread evenly over [0, 1]; the
** pointer's count follows it in the target (as T_COLORS). */
static int cv_curve(Ctx *c, const Prop *p, const Row *r, void *t) {
  double **curve = (double **)((char *)t + r->off);
  int *n = (int *)((char *)curve + sizeof(double *));
  const Value *v = &p->v[0];
  int k = v->kind == V_NUM ? 1 : v->kind == V_LIST ? v->u.l->n : 0;
  if (k < 1 || k > SCHEMA_MAX_CURVE)
    return expect(c, p, 0, "a number or a list of 1 to 64 numbers from 0 to 1");
  *curve = arena_alloc(&c->ev->scene->arena, (size_t)k * sizeof **curve);
  for (int i = 0; i < k; i++) {
    const Value *x = v->kind == V_NUM ? v : &v->u.l->v[i];
    if (x->kind != V_NUM || !(x->u.n >= 0 && x->u.n <= 1)) {
      ev_error(c->ev, p->vloc[0], "`%s` in `%s` needs numbers from 0 to 1 (entry %d is not)", p->name,
               c->what, i);
      return -1;
    }
    (*curve)[i] = x->u.n;
  }
  *n = k;
  return 0;
}

/* file "paper.png"; — a threshold image, read relative to the folder of
** the scene file that names it (as mesh("file") is; R_FILE has checked it
** can be read). Whether it decodes is found when the frame is prepared. */
static int cv_image_file(Ctx *c, const Prop *p, const Row *r, void *t) {
  ThresholdLayer *l = t;
  if (p->v[0].kind != V_STR || p->v[0].u.s->len == 0) return expect(c, p, 0, "an image file name (a string)");
  const char *name = p->v[0].u.s->s;
  const SrcFile *f = p->loc.file >= 0 ? diag_file(p->loc.file) : NULL;
  const char *slash = f ? strrchr(f->name, '/') : NULL;
  char full[4096];
  if (name[0] == '/' || !slash) snprintf(full, sizeof full, "%s", name);
  else snprintf(full, sizeof full, "%.*s/%s", (int)(slash - f->name), f->name, name);
  l->file = scene_str(c, full);
  l->file_loc = p->vloc[0];
  return 0;
}

/* ---- tables ------------------------------------------------------------- */

static const Row output_rows[] = {
  CUSTOM("size", cv_size, 0),
  CUSTOM("background", cv_background, R_MANY | R_FILE),
  INT("samples", SceneOutput, samples, 1, SCHEMA_MAX_SAMPLES, 1),
  {"antialias", T_BOOL, 0, 0, 1, offsetof(SceneOutput, antialias), 0, NULL, NULL},
  CUSTOM("sheet", cv_sheet, R_FILE),
};

static const Row sheet_rows[] = {
  {"texture", T_STRING, 0, 0, NAN, offsetof(SceneSheet, texture), R_FILE, NULL, NULL},
  TYPED("color", T_COLOR, SceneSheet, color),
  INT("seed", SceneSheet, seed, 0, 2147483647, 0),
  NUM("scale", SceneSheet, scale, 0.05, 64, 1),
  NUM("fibres", SceneSheet, fibres, 0, 16, 1),
  NUM("grain", SceneSheet, grain, 0, 1, 0.5),
};

static const Row camera_rows[] = {
  TYPED("position", T_VEC3, SceneCamera, position),
  TYPED("look_at", T_VEC3, SceneCamera, look_at),
  TYPED("up", T_VEC3, SceneCamera, up),
  NUM("fov", SceneCamera, fov, 0.01, 179, 30),
  CUSTOM("ortho", cv_ortho, 0),
};

static const Row light_rows[] = {
  CUSTOM("position", cv_light_position, 0),
  CUSTOM("direction", cv_light_direction, 0),
  TYPED("color", T_COLOR, SceneLight, color),
  NUM("strength", SceneLight, strength, 0, INFINITY, 1),
  SYM("falloff", SceneLight, falloff, "none|inverse_square"),
  CUSTOM("point_at", cv_light_point_at, 0),
  NUM("cone", SceneLight, cone, 0.1, 89, 30),
  NUM("penumbra", SceneLight, penumbra, 0, 89, 5),
  BOOL("shadow", SceneLight, shadow),
  INT("shadow_resolution", SceneLight, shadow_resolution, 16, SCHEMA_MAX_SHADOW_RESOLUTION, 1024),
  NUM("shadow_bias", SceneLight, shadow_bias, 0, 64, 1),
  NUM("shadow_filter", SceneLight, shadow_filter, 1, 32, 2),
};

static const Row style_rows[] = {
  TYPED("base", T_COLOR, SceneStyle, base),
  CUSTOM("texture", cv_style_texture, R_FILE),
  NUM("texture_repeat", SceneStyle, texture_repeat, 1e-3, 1e4, 1),
};

/* Shared by every shading model: the lighting terms. */
#define LIGHTING_ROWS \
  NUM("specular", SceneShade, toon.specular, 0, INFINITY, 0), \
  NUM("shininess", SceneShade, toon.shininess, 0, 10000, 32), \
  NUM("ambient", SceneShade, toon.ambient, 0, 1, 0.1)

static const Row shade_basic_rows[] = {LIGHTING_ROWS};

static const Row shade_flat_rows[] = {
  LIGHTING_ROWS,
  BOOL("lit", SceneShade, lit),
};

/* Toon's bands, ramps and edge, shared with threshold (after `bands`). */
#define TOON_ROWS \
  NUM("threshold", SceneShade, toon.threshold, 0, 1, 0.5), \
  TYPED("ramp", T_COLORS, SceneShade, toon.ramp), \
  TYPED("specular_ramp", T_COLORS, SceneShade, toon.specular_ramp), \
  INT("specular_bands", SceneShade, toon.specular_bands, 2, 256, 2), \
  NUM("specular_threshold", SceneShade, toon.specular_threshold, 0, 1, 0.5), \
  NUM("edge", SceneShade, toon.edge, 0, 1, 0), \
  TYPED("edge_color", T_COLOR, SceneShade, toon.edge_color)

static const Row shade_toon_rows[] = {
  LIGHTING_ROWS,
  INT("bands", SceneShade, toon.bands, 2, 256, 3),
  TOON_ROWS,
};

static const Row shade_origami_rows[] = {
  SYM("mode", SceneShade, origami_mode, "line|illustration|shaded"),
  TYPED("color", T_COLOR, SceneShade, origami_color),
  CUSTOM("weights", cv_weights, 0),
  NUM("radius", SceneShade, origami_radius, 0, 1000, 8),
  {"texture", T_STRING, 0, 0, NAN, offsetof(SceneShade, origami_texture), R_FILE, NULL, NULL},
};

/* shade threshold: toon's rows (two tones by default: hatching's ink and
** paper), the texture space, filtering and strength; its layers are the
** hatch, stipple and image blocks inside it. */
#define CURVE(n, f) {n, T_CUSTOM, 0, 0, NAN, offsetof(SceneShade, f), 0, NULL, cv_curve}

static const Row shade_threshold_rows[] = {
  LIGHTING_ROWS,
  INT("bands", SceneShade, toon.bands, 2, 256, 2),
  TOON_ROWS,
  SYM("projection", SceneShade, threshold.projection, "auto|uv|planar|box|cylindrical|spherical"),
  NUM("scale", SceneShade, threshold.scale, 1e-9, INFINITY, 1),
  {"filter", T_BOOL, 0, 0, 1, offsetof(SceneShade, threshold.filter), 0, NULL, NULL},
  NUM("strength", SceneShade, threshold.strength, 0, 1, 1),
  CURVE("facing", threshold.facing),
  CURVE("light", threshold.light),
};

/* Rows every threshold layer has. */
#define LAYER_ROWS(angle0) \
  SYM("term", ThresholdLayer, term, "both|diffuse|specular"), \
  CUSTOM("range", cv_range, 0), \
  NUM("angle", ThresholdLayer, angle, -360, 360, angle0), \
  NUM("noise", ThresholdLayer, noise, 0, 16, 0), \
  NUM("noise_scale", ThresholdLayer, noise_scale, 1e-6, INFINITY, 0.1)

static const Row hatch_rows[] = {
  LAYER_ROWS(45),
  NUM("spacing", ThresholdLayer, spacing, 0.5, 4096, 6),
};

static const Row stipple_rows[] = {
  LAYER_ROWS(45),
  NUM("spacing", ThresholdLayer, spacing, 0.5, 4096, 5),
};

static const Row image_rows[] = {
  LAYER_ROWS(0),
  CUSTOM("file", cv_image_file, R_REQUIRED | R_FILE),
  NUM("window", ThresholdLayer, window, 2, 4096, 16),
  NUM("clip", ThresholdLayer, clip, 0, 1000, 4),
  NUM("scale", ThresholdLayer, scale, 1e-9, INFINITY, 1),
};

/* Passes whose parameters live in SceneStyle.params (scene_style_param). */
static const Row shade_bokashi_rows[] = {
  CUSTOM("lit", cv_bokashi_color, 0),
  CUSTOM("unlit", cv_bokashi_color, 0),
  NUM("strength_mod", SceneShade, bokashi.strength_mod, 0, INFINITY, 1),
  NUM("offset", SceneShade, bokashi.offset, -INFINITY, INFINITY, 0),
  NUM("view_mod", SceneShade, bokashi.view_mod, -INFINITY, INFINITY, 0.5),
  POSITIVE("rate", SceneShade, bokashi.rate, 1),
  BOOL("per_pixel", SceneShade, bokashi.per_pixel),
};

/* The thesis's intent for the Gouraud image: strong diffuse and specular,
** weak ambient (ch. 5.2, Fig. 5.3). */
static const Row shade_ink_rows[] = {
  NUM("ambient", SceneShade, toon.ambient, 0, 1, 0.05),
  NUM("diffuse", SceneShade, ink.diffuse, 0, 100, 0.9),
  NUM("specular", SceneShade, toon.specular, 0, INFINITY, 0.5),
  NUM("shininess", SceneShade, toon.shininess, 0, 10000, 10),
  CUSTOM("levels", cv_ink_levels, 0),
  CUSTOM("tones", cv_ink_tones, 0),
  {"diffusion", T_SYMBOL, 0, 0, INK_MEDIUM, offsetof(SceneShade, ink.diffusion), R_SYM, "small|medium|large", NULL},
  INT("passes", SceneShade, ink.passes, 0, INK_MAX_PASSES, 0),
  NUM("ink_threshold", SceneShade, ink.ink_threshold, 0, 255, 8),
  NUM("water_threshold", SceneShade, ink.water_threshold, 0, 1000, 0),
  NUM("roughness", SceneShade, ink.roughness, 0, 1, 0.35),
  CUSTOM("box_filter", cv_box_filter, 0),
  TYPED("color", T_COLOR, SceneShade, ink.color),
  {"stage", T_SYMBOL, 0, 0, INK_STAGE_FILTERED, offsetof(SceneShade, ink.stage), R_SYM,
   "gouraud|quantised|diffused|filtered", NULL},
  CUSTOM("lights", cv_ink_lights, R_MANY | R_SYM),
};

static const Row noise_rows[] = {
  NUM("amount", SceneStyle, noise.amount, 0, 1, 0.1),
  POSITIVE("scale", SceneStyle, noise.scale, 0.25),
  INT("seed", SceneStyle, noise.seed, 0, 2147483647, 0),
  INT("octaves", SceneStyle, noise.octaves, 1, SCENE_MAX_NOISE_OCTAVES, 4),
  CUSTOM("image", cv_image, R_FILE),
};

static const Row pattern_rows[] = {
  CUSTOM("image", cv_image, R_REQUIRED | R_FILE),
  POSITIVE("scale", SceneStyle, pattern.scale, 1),
  NUM("opacity", SceneStyle, pattern.opacity, 0, 1, 1),
  CUSTOM("colors", cv_pattern_colors, 0),
  SYM("blend", SceneStyle, pattern.blend, "over|multiply"),
};

static const Row lines_rows[] = {
  CUSTOM_SYM("kinds", cv_kinds, R_MANY, "silhouette|crease|boundary|face_edges"),
  SYM("stroke", SceneLines, stroke, "plain|ribbon|brush"),
  NUM("width", SceneLines, width, 0, 1000, 1.5),
  TYPED("color", T_COLOR, SceneLines, color),
  NUM("opacity", SceneLines, opacity, 0, 1, 1),
  {"texture", T_STRING, 0, 0, NAN, offsetof(SceneLines, texture), R_FILE, NULL, NULL},
  NUM("ref_scale", SceneLines, ref_scale, 0.05, 8, 1),
  INT("search_width", SceneLines, search_width, 0, 64, 2),
  INT("max_misses", SceneLines, max_misses, 0, 64, 2),
  INT("link_depth", SceneLines, link_depth, 0, 64, 3),
  NUM("link_angle", SceneLines, link_angle, 0, 180, 40),
  NUM("miter_limit", SceneLines, miter_limit, 1, 100, 4),
  NUM("min_length", SceneLines, min_length, 0, INFINITY, 4),
  NUM("depth_offset", SceneLines, depth_offset, -INFINITY, INFINITY, 0),
  SYM("visibility", SceneLines, visibility, "auto|reference|endpoints"),
  INT("cull_steps", SceneLines, cull_steps, 0, 32, 10),
  NUM("link_distance", SceneLines, link_distance, 0, 64, 2),
  NUM("width_step", SceneLines, brush.width_step, 0, 500, 2),
  NUM("max_width", SceneLines, brush.max_width, 0, 500, 7),
  INT("sectors", SceneLines, brush.sectors, 1, 360, 28),
  INT("bristles", SceneLines, brush.bristles, 1, 64, 7),
  NUM("brush_aspect", SceneLines, brush.aspect, 0.05, 1, 0.5),
  NUM("ink_load", SceneLines, brush.ink_load, 0, 1, 0.35),
  NUM("dry_probability", SceneLines, brush.dry_probability, 0, 1, 0.39),
  INT("dry_max_gap", SceneLines, brush.dry_max_gap, 0, 63, 4),
  NUM("pressure", SceneLines, brush.pressure, 0.01, 1, 0.6),
};

static const Row object_rows[] = {
  {"geometry", T_GEOMETRY, 0, 0, NAN, offsetof(SceneObject, geometry), R_REQUIRED, NULL, NULL},
  CUSTOM_SYM("tessellate", cv_tessellate, 0, "adaptive"),
  TYPED("style", T_STYLE, SceneObject, style),
  TYPED("transform", T_TRANSFORM, SceneObject, transform),
  CUSTOM("centre", cv_centre, 0),
};

static const Row origami_rows[] = {
  CUSTOM("paper", cv_paper, R_FIRST),
  CUSTOM("folded", cv_folded, 0),
  INT("fixed", SceneOrigami, fixed, 0, INFINITY, 0),
  CUSTOM("above", cv_above, R_REPEAT),
  CUSTOM("overlap", cv_overlap, R_SYM),
  CUSTOM("state", cv_state, 0),
  TYPED("style", T_STYLE, SceneOrigami, style),
  TYPED("transform", T_TRANSFORM, SceneOrigami, transform),
};

static const Row paper_rows[] = {
  CUSTOM("vertices", cv_vertices, R_REQUIRED),
  CUSTOM("creases", cv_creases, R_REQUIRED),
  CUSTOM("faces", cv_faces, 0),
};

enum { W_NONE, W_NAME, W_KIND };

typedef struct Schema {
  const char *kind;
  const char *word;          /* the sub-kind word (shade), or NULL */
  const Row *rows;
  int nrows;
  const char *subs;          /* block kinds allowed inside, "a|b" */
  int words;
  int top;                   /* allowed at the top level */
} Schema;

#define ROWS(r) r, (int)(sizeof r / sizeof r[0])
/* One row per block kind (and per shading model). */
static const Schema schemas[] = {
  {"output", NULL, ROWS(output_rows), "sheet", W_NONE, 1},
  {"camera", NULL, ROWS(camera_rows), "", W_NAME, 1},
  {"light", NULL, ROWS(light_rows), "", W_NAME, 1},
  {"style", NULL, ROWS(style_rows), "shade|lines|noise|pattern", W_NAME, 1},
  {"shade", "flat", ROWS(shade_flat_rows), "", W_KIND, 0},
  {"shade", "gouraud", ROWS(shade_basic_rows), "", W_KIND, 0},
  {"shade", "phong", ROWS(shade_basic_rows), "", W_KIND, 0},
  {"shade", "toon", ROWS(shade_toon_rows), "", W_KIND, 0},
  {"shade", "threshold", ROWS(shade_threshold_rows), "hatch|stipple|image", W_KIND, 0},
  {"shade", "bokashi", ROWS(shade_bokashi_rows), "", W_KIND, 0},
  {"shade", "ink", ROWS(shade_ink_rows), "", W_KIND, 0},
  {"shade", "origami", ROWS(shade_origami_rows), "", W_KIND, 0},
  {"lines", NULL, ROWS(lines_rows), "", W_NONE, 0},
  {"noise", NULL, ROWS(noise_rows), "", W_NONE, 0},
  {"pattern", NULL, ROWS(pattern_rows), "", W_NONE, 0},
  {"object", NULL, ROWS(object_rows), "", W_NAME, 1},
  {"origami", NULL, ROWS(origami_rows), "paper", W_NAME, 1},
  {"paper", NULL, ROWS(paper_rows), "", W_NONE, 0},
  {"sheet", NULL, ROWS(sheet_rows), "", W_NONE, 0},
  /* threshold layers, inside `shade threshold` (ORDER ThresholdLayerKind) */
  {"hatch", NULL, ROWS(hatch_rows), "", W_NONE, 0},
  {"stipple", NULL, ROWS(stipple_rows), "", W_NONE, 0},
  {"image", NULL, ROWS(image_rows), "", W_NONE, 0},
};
#define NSCHEMAS ((int)(sizeof schemas / sizeof schemas[0]))

/* ---- placeholders ------------------------------------------------------- */

/* What the renderer does not draw yet: each use warns, where it is written,
** what is drawn instead. One row per pass or property (word: the shading
** model, or the property of kind); a row goes when its stage lands. */
static const struct { const char *kind, *word, *instead; } placeholders[] = {
  /* not missing, but with nothing left to do (docs/styles.md, lines) */
  {"lines", "search_width", "`search_width` has no effect: each edge is tested on its own line, so "
                            "tracing has nothing beside it to search"},
};

/* Warn at `at` when kind (with word, or NULL) is a placeholder. */
static void placeholder(Ctx *c, const char *kind, const char *word, SrcRange at) {
  for (size_t i = 0; i < sizeof placeholders / sizeof placeholders[0]; i++)
    if (!strcmp(placeholders[i].kind, kind) &&
        (placeholders[i].word ? word && !strcmp(placeholders[i].word, word) : !word))
      diag_warning(at, "%s", placeholders[i].instead);
}

/* The kind word of block b (for a caret under it). */
static SrcRange kind_range(const BlockVal *b) {
  SrcRange r = b->loc;
  r.end_line = r.line;
  r.end_col = r.col + (int)strlen(b->kind);
  return r;
}

/* ---- lookup --------------------------------------------------------------- */

static const Schema *find_schema(const char *kind, const char *word) {
  const Schema *first = NULL;
  for (int i = 0; i < NSCHEMAS; i++) {
    if (strcmp(schemas[i].kind, kind) != 0) continue;
    if (!schemas[i].word) return &schemas[i];
    if (!first) first = &schemas[i];
    if (word && strcmp(schemas[i].word, word) == 0) return &schemas[i];
  }
  return word ? NULL : first;
}

static const Row *find_row(const Schema *s, const char *name) {
  for (int i = 0; i < s->nrows; i++)
    if (strcmp(s->rows[i].name, name) == 0) return &s->rows[i];
  return NULL;
}

int schema_known_kind(const char *kind) {
  return find_schema(kind, NULL) != NULL;
}

int schema_wants_symbol(const char *kind, const char *word, const char *prop) {
  const Schema *s = find_schema(kind, word);
  const Row *r = s ? find_row(s, prop) : NULL;
  return r && (r->flags & R_SYM);
}

int schema_knows_word(const char *kind, const char *word, const char *prop, const char *name) {
  const Schema *s = find_schema(kind, word);
  const Row *r = s ? find_row(s, prop) : NULL;
  if (!r || !r->symbols) return 0;
  size_t n = strlen(name);
  for (const char *w = r->symbols; w; w = strchr(w, '|'), w = w ? w + 1 : NULL)
    if (!strncmp(w, name, n) && (w[n] == '|' || w[n] == 0)) return 1;
  return 0;
}

/* ---- checking ----------------------------------------------------------- */

static void apply_defaults(const Schema *s, void *target) {
  for (int i = 0; i < s->nrows; i++) {
    const Row *r = &s->rows[i];
    if (isnan(r->def) || r->off == NOFIELD) continue;
    if (r->type == T_NUM) *(double *)((char *)target + r->off) = r->def;
    if (r->type == T_INT || r->type == T_SYMBOL || r->type == T_BOOL)
      *(int *)((char *)target + r->off) = (int)r->def;
  }
}

static void unknown_prop(Ctx *c, const Schema *s, const Prop *p) {
  const char *names[64];
  int n = 0;
  for (int i = 0; i < s->nrows && n < 64; i++) names[n++] = s->rows[i].name;
  const char *sug = suggest_name(p->name, names, n);
  char hint[600];
  if (habit_hint(HABIT_PROPERTY, p->name, NULL, hint, sizeof hint))
    ev_error(c->ev, name_range(p), "unknown property `%s` in `%s`%s", p->name, c->what, hint);
  else if (sug) ev_error(c->ev, name_range(p), "unknown property `%s` in `%s`; did you mean `%s`?", p->name, c->what, sug);
  else ev_error(c->ev, name_range(p), "unknown property `%s` in `%s`", p->name, c->what);
}

/* An R_FILE property's string that names a file (it has a `.` or a `/`;
** other words are built-in names), relative to the folder of the file
** that wrote it: it must exist. Nonzero when reported. */
static int missing_file(Ctx *c, const Prop *p) {
  const Value *v = &p->v[0];
  if (v->kind != V_STR || !strpbrk(v->u.s->s, "./")) return 0;
  const SrcFile *f = p->loc.file >= 0 ? diag_file(p->loc.file) : NULL;
  const char *slash = f ? strrchr(f->name, '/') : NULL;
  char path[4096];
  if (v->u.s->s[0] == '/' || !slash) snprintf(path, sizeof path, "%s", v->u.s->s);
  else snprintf(path, sizeof path, "%.*s/%s", (int)(slash - f->name), f->name, v->u.s->s);
  char why[256];
  if (infile_check(path, INFILE_MAX_IMAGE, "an image", why, sizeof why)) {
    if (access(path, R_OK) == 0) return 0;
    snprintf(why, sizeof why, "%s", strerror(errno));
  }
  ev_error(c->ev, p->vloc[0], "`%s` in `%s`: cannot read `%s`: %s", p->name, c->what, v->u.s->s, why);
  return 1;
}

/* One property: known, not repeated (unless it may be), one value (unless
** it takes several), then converted. Nonzero when reported. */
static int check_prop(Ctx *c, const Schema *s, const BlockVal *b, int i, const Row *r, void *target) {
  const Prop *p = &b->props[i];
  if (!r) { unknown_prop(c, s, p); return 1; }
  int first = -1;
  for (int j = 0; j < i && first < 0; j++)
    if (strcmp(b->props[j].name, p->name) == 0) first = j;
  if (first >= 0 && !(r->flags & R_REPEAT)) {
    ev_error(c->ev, name_range(p), "`%s` is given twice in `%s`", p->name, c->what);
    diag_note(name_range(&b->props[first]), "first given here");
    return 1;
  }
  if (p->n != 1 && !(r->flags & R_MANY)) {
    if (p->n == 0) expect(c, p, 0, "a value");
    else ev_error(c->ev, p->vloc[1], "`%s` in `%s` takes one value; found %d", p->name, c->what, p->n);
    return 1;
  }
  if ((r->flags & R_FILE) && missing_file(c, p)) return 1;
  if (convert(c, p, r, target) != 0) return 1;
  placeholder(c, c->what, p->name, name_range(p));
  return 0;
}

/* Check every property of b against s and convert it into target. */
static int check_props(Ctx *c, const Schema *s, const BlockVal *b, void *target) {
  int bad = 0;
  for (int pass = 0; pass < 2; pass++)
    for (int i = 0; i < b->nprops; i++) {
      const Row *r = find_row(s, b->props[i].name);
      if (r && (pass == 0) != ((r->flags & R_FIRST) != 0)) continue;
      if (!r && pass == 0) continue;
      bad |= check_prop(c, s, b, i, r, target);
    }
  for (int i = 0; i < s->nrows; i++) {
    if (!(s->rows[i].flags & R_REQUIRED)) continue;
    int found = 0;
    for (int j = 0; j < b->nprops && !found; j++) found = strcmp(b->props[j].name, s->rows[i].name) == 0;
    if (!found && !bad) {
      ev_error(c->ev, b->loc, "`%s` block needs `%s`", c->what, s->rows[i].name);
      bad = 1;
    }
  }
  return bad ? -1 : 0;
}

/* Words after the kind: a name (W_NAME: at most one), or a sub-kind. */
static int check_words(Ctx *c, const Schema *s, const BlockVal *b) {
  int max = s->words == W_NONE ? 0 : s->words == W_NAME ? 1 : 2;
  if (b->nwords <= max) return 0;
  ev_error(c->ev, b->wordloc[max], "`%s` takes %s; found `%s`", b->kind,
           max == 0 ? "no name" : max == 1 ? "at most one name" : "a kind and a variant", b->words[max]);
  return -1;
}

static void unknown_kind(Ctx *c, const BlockVal *b, const char *allowed, const char *where) {
  const char *names[NSCHEMAS];
  int n = 0;
  char buf[256];
  snprintf(buf, sizeof buf, "%s", allowed);
  for (char *tok = strtok(buf, "|"); tok; tok = strtok(NULL, "|")) names[n++] = tok;
  const char *sug = suggest_name(b->kind, names, n);
  char hint[600];
  if (habit_hint(HABIT_BLOCK, b->kind, NULL, hint, sizeof hint)) {
    ev_error(c->ev, b->loc, "unknown block `%s`%s%s", b->kind, where, hint);
  } else if (!schema_known_kind(b->kind)) {
    if (!sug) {
      n = 0;
      for (int i = 0; i < NSCHEMAS; i++) names[n++] = schemas[i].kind;
      sug = suggest_name(b->kind, names, n);
    }
    if (sug) ev_error(c->ev, b->loc, "unknown block `%s`%s; did you mean `%s`?", b->kind, where, sug);
    else ev_error(c->ev, b->loc, "unknown block `%s`%s", b->kind, where);
  } else ev_error(c->ev, b->loc, "a `%s` block cannot be%s", b->kind, where);
}

static const Schema *shade_schema(Ctx *c, const BlockVal *b) {
  static const char *kinds[] = {"flat", "gouraud", "phong", "toon", "threshold", "bokashi", "ink", "origami"};
  if (b->nwords == 0) {
    ev_error(c->ev, b->loc, "`shade` needs a shading model: flat, gouraud, phong, toon, threshold, bokashi, ink or origami");
    return NULL;
  }
  const Schema *s = find_schema("shade", b->words[0]);
  if (s) return s;
  const char *sug = suggest_name(b->words[0], kinds, 8);
  if (sug) ev_error(c->ev, b->wordloc[0], "unknown shading model `%s`; did you mean `%s`?", b->words[0], sug);
  else ev_error(c->ev, b->wordloc[0], "unknown shading model `%s` (flat, gouraud, phong, toon, threshold, bokashi, ink, origami)", b->words[0]);
  return NULL;
}

/* ---- emitters --------------------------------------------------------- */

static int no_subs(Ctx *c, const BlockVal *b) {
  char where[80];
  snprintf(where, sizeof where, " inside `%s`", b->kind);
  for (int i = 0; i < b->nsubs; i++) unknown_kind(c, b->subs[i], "", where);
  return b->nsubs ? -1 : 0;
}

/* Whether word is one of the names in list ("a|b|c"). */
static int in_list(const char *list, const char *word) {
  size_t n = strlen(word);
  for (const char *p = list; *p; p += strcspn(p, "|"), p += *p == '|')
    if (strncmp(p, word, n) == 0 && (p[n] == '|' || p[n] == 0)) return 1;
  return 0;
}

/* A layer block inside a shade block (hatch, stipple, image: the kinds its
** schema's subs allow), appended to the pass's layers. */
static int fill_layer(Ctx *c, const Schema *s, SceneShade *sh, const BlockVal *sub) {
  char where[80];
  snprintf(where, sizeof where, " inside `%s`", c->what);
  const Schema *ls = find_schema(sub->kind, NULL);
  if (!ls || !*s->subs || !in_list(s->subs, sub->kind)) {
    unknown_kind(c, sub, s->subs, where);
    return -1;
  }
  Ctx lc = *c;
  snprintf(lc.what, sizeof lc.what, "%s", sub->kind);
  if (check_words(&lc, ls, sub)) return -1;
  ShadeThreshold *th = &sh->threshold;
  if (th->nlayers == SCENE_MAX_LAYERS) {
    ev_error(c->ev, sub->loc, "`%s` has at most %d layers (SCENE_MAX_LAYERS)", c->what, SCENE_MAX_LAYERS);
    return -1;
  }
  th->layers = grow(c, th->layers, th->nlayers, sizeof *th->layers);
  ThresholdLayer *l = &th->layers[th->nlayers++];
  memset(l, 0, sizeof *l);
  l->kind = (ThresholdLayerKind)(ls - find_schema("hatch", NULL));
  l->range[1] = 1;
  l->loc = sub->loc;
  l->file_loc = src_none();
  apply_defaults(ls, l);
  return check_props(&lc, ls, sub, l) || no_subs(&lc, sub) ? -1 : 0;
}

static int fill_shade(Ctx *c, SceneStyle *st, const BlockVal *b) {
  const Schema *s = shade_schema(c, b);
  if (!s) return -1;
  if (st->shade.kind != SHADE_NONE) {
    ev_error(c->ev, b->loc, "a style has one `shade` pass; this is the second");
    return -1;
  }
  static const ShadeKind kinds[] = {SHADE_FLAT, SHADE_GOURAUD, SHADE_PHONG, SHADE_TOON,
                                    SHADE_THRESHOLD, SHADE_BOKASHI, SHADE_INK, SHADE_ORIGAMI};
  SceneShade *sh = &st->shade;
  SceneShade def = scene_default_style().shade;
  *sh = def;
  sh->kind = kinds[s - find_schema("shade", "flat")];
  sh->subkind = b->nwords > 1 ? scene_str(c, b->words[1]) : NULL;
  if (sh->kind == SHADE_BOKASHI && sh->subkind && strcmp(sh->subkind, "linear") && strcmp(sh->subkind, "sphere")) {
    ev_error(c->ev, b->wordloc[1], "`shade bokashi` is `linear` or `sphere`; found `%s`", sh->subkind);
    return -1;
  }
  if (sh->kind != SHADE_BOKASHI && b->nwords > 1) {
    ev_error(c->ev, b->wordloc[1], "`shade %s` has no variant `%s`", b->words[0], b->words[1]);
    return -1;
  }
  if (b->nwords > 2) return check_words(c, s, b);
  sh->loc = b->loc;
  placeholder(c, "shade", b->words[0], b->wordloc[0]);
  sh->bokashi.sphere = !sh->subkind || strcmp(sh->subkind, "linear") != 0;   /* sphere unless linear */
  apply_defaults(s, sh);
  snprintf(c->what, sizeof c->what, "shade %s", b->words[0]);
  c->pass = "shade";
  sh->threshold.projection_loc = src_none();
  int bad = check_props(c, s, b, sh) != 0;
  for (int i = 0; i < b->nprops; i++)   /* where `projection` is, for the renderer's check */
    if (strcmp(b->props[i].name, "projection") == 0) sh->threshold.projection_loc = b->props[i].loc;
  for (int i = 0; i < b->nsubs; i++) bad |= fill_layer(c, s, sh, b->subs[i]) != 0;
  if (bad) return -1;
  return sh->kind == SHADE_INK ? check_ink(c, &sh->ink) : 0;
}

/* A brush's lines: its bristles together (sectors x bristles) against
** their limit, reported at whichever of the two came last; and `width`,
** which a brush stroke does not read (its half-width is max_width), warned
** about where it is written. */
static int check_brush(Ctx *c, const BlockVal *b, const SceneLines *ls) {
  const SceneBrush *br = &ls->brush;
  for (int i = 0; ls->stroke == STROKE_BRUSH && i < b->nprops; i++)
    if (!strcmp(b->props[i].name, "width"))
      diag_warning(name_range(&b->props[i]), "`width` does not apply to `stroke brush`: its strokes grow by "
                   "`width_step` a control point up to a half-width of `max_width` (%g)", br->max_width);
  long n = (long)br->sectors * br->bristles;
  if (n <= SCENE_BRUSH_MAX_BRISTLES) return 0;
  SrcRange at = b->loc;
  for (int i = 0; i < b->nprops; i++)
    if (!strcmp(b->props[i].name, "sectors") || !strcmp(b->props[i].name, "bristles")) at = b->props[i].loc;
  ev_error(c->ev, at, "a brush of %d sectors x %d bristles holds %ld; the most is %d (sectors x bristles)",
           br->sectors, br->bristles, n, SCENE_BRUSH_MAX_BRISTLES);
  return -1;
}

static int fill_sub(Ctx *c, SceneStyle *st, const BlockVal *sub) {
  Ctx sc = *c;
  sc.style = st;
  if (strcmp(sub->kind, "shade") == 0) return fill_shade(&sc, st, sub);
  const Schema *s = find_schema(sub->kind, NULL);
  if (!s || !strstr("lines|noise|pattern", sub->kind)) {
    unknown_kind(c, sub, "shade|lines|noise|pattern", " inside `style`");
    return -1;
  }
  if (check_words(&sc, s, sub)) return -1;
  snprintf(sc.what, sizeof sc.what, "%s", sub->kind);
  sc.pass = scene_str(c, sub->kind);
  if (strcmp(sub->kind, "lines") == 0) {
    if (st->lines.present == 2) {
      ev_error(c->ev, sub->loc, "a style has one `lines` pass; this is the second");
      return -1;
    }
    st->lines = scene_default_style().lines;
    apply_defaults(s, &st->lines);
    st->lines.present = 2;   /* set explicitly: 1 once checked */
    st->lines.loc = sub->loc;
    if (check_props(&sc, s, sub, &st->lines)) return -1;
    return check_brush(&sc, sub, &st->lines);
  }
  placeholder(c, sub->kind, NULL, kind_range(sub));
  int noise = strcmp(sub->kind, "noise") == 0;
  if (noise ? st->noise.present : st->pattern.present) {
    ev_error(c->ev, sub->loc, "a style has one `%s` pass; this is the second", sub->kind);
    return -1;
  }
  apply_defaults(s, st);
  if (noise) { st->noise.present = 1; st->noise.loc = sub->loc; }
  else { st->pattern.present = 1; st->pattern.loc = sub->loc; }
  return check_props(&sc, s, sub, st);
}

static int emit_style(Ctx *c, const BlockVal *b) {
  Scene *sc = c->ev->scene;
  SceneStyle st = scene_default_style();
  st.shade.kind = SHADE_NONE;
  st.lines.present = 0;
  st.name = b->nwords ? scene_str(c, b->words[0]) : NULL;
  st.loc = b->loc;
  c->style = &st;
  int bad = check_props(c, find_schema("style", NULL), b, &st);
  for (int i = 0; i < b->nsubs; i++) bad |= fill_sub(c, &st, b->subs[i]) != 0;
  if (st.shade.kind == SHADE_NONE) st.shade = scene_default_style().shade;
  if (st.lines.present) st.lines.present = 1;
  if (bad) return -1;
  sc->styles = grow(c, sc->styles, sc->nstyles, sizeof *sc->styles);
  sc->styles[sc->nstyles] = st;
  return sc->nstyles++;
}


/* Where property name is written in b (its value), or the block itself. */
static SrcRange prop_at(const BlockVal *b, const char *name) {
  for (int i = b->nprops - 1; i >= 0; i--)
    if (!strcmp(b->props[i].name, name) && b->props[i].n > 0) return b->props[i].vloc[0];
  return b->loc;
}

/* A geometry that can draw nothing: no faces, or patches without area. */
static const char *empty_geometry(const SceneGeometry *g) {
  if (g->kind == GEOM_MESH) return g->nverts == 0 || g->nfaces == 0 ? "has no faces" : NULL;
  for (int i = 0; i < g->npatches; i++) {   /* area unless its points lie on one line */
    const Vec3 *p = g->patches[i].cp;
    Vec3 d = v3(0, 0, 0);
    for (int k = 1; k < 16; k++) {
      Vec3 e = v3_sub(p[k], p[0]);
      if (v3_len(d) == 0) d = e;
      else if (v3_len(v3_cross(d, e)) > 0) return NULL;
    }
  }
  return g->npatches ? "has patches of no area (their points lie on one line)" : "has no patches";
}

/* Quiet wrong pictures an object can make: warned where they are written. */
static void check_object(const SceneObject *o, const BlockVal *b) {
  const Mat4 *m = &o->transform;
  double det = m->m[0][0] * (m->m[1][1] * m->m[2][2] - m->m[1][2] * m->m[2][1]) -
               m->m[0][1] * (m->m[1][0] * m->m[2][2] - m->m[1][2] * m->m[2][0]) +
               m->m[0][2] * (m->m[1][0] * m->m[2][1] - m->m[1][1] * m->m[2][0]);
  if (det == 0)
    diag_warning(prop_at(b, "transform"), "this `transform` flattens the object (its determinant is 0, "
                 "as scale(0) is): it draws as a plane, a line or nothing");
  const char *why = o->geometry ? empty_geometry(o->geometry) : NULL;
  if (why) diag_warning(prop_at(b, "geometry"), "this geometry %s: the object draws nothing", why);
}

static int emit_object(Ctx *c, const Schema *s, const BlockVal *b) {
  Scene *sc = c->ev->scene;
  SceneObject o;
  memset(&o, 0, sizeof o);
  o.name = b->nwords ? scene_str(c, b->words[0]) : NULL;
  o.transform = m4_identity();
  o.style = -1;
  o.tess_kind = TESS_ADAPTIVE;
  o.tess_px = SCENE_DEFAULT_TESS_PX;
  o.loc = b->loc;
  if (check_props(c, s, b, &o) || no_subs(c, b)) return -1;
  o.transform = m4_mul(c->ev->xform, o.transform);   /* inside `translate(v) object { ... }` */
  check_object(&o, b);
  sc->objects = grow(c, sc->objects, sc->nobjects, sizeof *sc->objects);
  sc->objects[sc->nobjects++] = o;
  return 0;
}

void schema_emit_object(Eval *ev, const SceneObject *like, SceneGeometry *g, Mat4 transform, SrcRange loc) {
  Ctx c;
  memset(&c, 0, sizeof c);
  c.ev = ev;
  Scene *sc = ev->scene;
  SceneObject o;
  memset(&o, 0, sizeof o);
  if (like) o = *like;
  else {
    o.style = -1;
    o.tess_kind = TESS_ADAPTIVE;
    o.tess_px = SCENE_DEFAULT_TESS_PX;
  }
  o.geometry = g;
  o.transform = transform;
  o.loc = loc;
  sc->objects = grow(&c, sc->objects, sc->nobjects, sizeof *sc->objects);
  sc->objects[sc->nobjects++] = o;
}

/* After an origami block: the folded state and relations must fit. */
static int check_origami(Ctx *c, SceneOrigami *o, const BlockVal *b) {
  if (o->nverts == 0 && !o->fold_file) {
    ev_error(c->ev, b->loc, "`origami` block needs a crease pattern: a `paper { ... }` block or `paper fold_file(...)`");
    return -1;
  }
  if (c->folded_n && c->folded_n != o->nverts) {
    ev_error(c->ev, b->loc, "`folded` has %d points but the paper has %d vertices", c->folded_n, o->nverts);
    return -1;
  }
  if (o->nfaces && o->fixed >= o->nfaces) {
    ev_error(c->ev, b->loc, "`fixed` face %d does not exist (the paper has %d faces)", o->fixed, o->nfaces);
    return -1;
  }
  if (o->state_loc.file >= 0 && !o->overlap_auto) {
    ev_error(c->ev, o->state_loc, "`state` picks one of the solver's states: it needs `overlap auto`");
    return -1;
  }
  if (o->overlap_auto && o->nabove) {
    ev_error(c->ev, o->above[0].loc, "`above` and `overlap auto` cannot be combined: the solver finds every order");
    return -1;
  }
  return 0;
}

static int emit_origami(Ctx *c, const Schema *s, const BlockVal *b) {
  Scene *sc = c->ev->scene;
  SceneOrigami o;
  memset(&o, 0, sizeof o);
  o.name = b->nwords ? scene_str(c, b->words[0]) : NULL;
  o.transform = m4_identity();
  o.style = -1;
  o.overlap_loc = o.state_loc = src_none();
  o.loc = b->loc;
  int bad = 0;
  for (int i = 0; i < b->nsubs; i++) {
    const BlockVal *sub = b->subs[i];
    if (strcmp(sub->kind, "paper") != 0) { unknown_kind(c, sub, "paper", " inside `origami`"); bad = 1; continue; }
    Ctx pc = *c;
    snprintf(pc.what, sizeof pc.what, "paper");
    bad |= check_words(&pc, find_schema("paper", NULL), sub) || check_props(&pc, find_schema("paper", NULL), sub, &o);
  }
  bad |= check_props(c, s, b, &o) != 0;
  if (bad || check_origami(c, &o, b)) return -1;
  o.transform = m4_mul(c->ev->xform, o.transform);
  sc->origami = grow(c, sc->origami, sc->norigami, sizeof *sc->origami);
  sc->origami[sc->norigami++] = o;
  return 0;
}

/* sheet { texture "xuan"; seed 3; ... } inside output. */
static int emit_sheet(Ctx *c, const BlockVal *b, SceneOutput *o) {
  if (strcmp(b->kind, "sheet") != 0) { unknown_kind(c, b, "sheet", " inside `output`"); return -1; }
  if (o->sheet.texture) {
    ev_error(c->ev, b->loc, "the sheet is given twice in `output`");
    diag_note(o->sheet.loc, "first given here");
    return -1;
  }
  const Schema *s = find_schema("sheet", NULL);
  Ctx sc = *c;
  snprintf(sc.what, sizeof sc.what, "sheet");
  SceneSheet sh = scene_default_sheet();
  apply_defaults(s, &sh);
  sh.texture = "xuan";
  sh.loc = b->loc;
  if (check_words(&sc, s, b) || check_props(&sc, s, b, &sh) || no_subs(&sc, b)) return -1;
  for (int i = 0; i < b->nprops; i++)   /* a diagnostic about the image points at its name */
    if (!strcmp(b->props[i].name, "texture")) sh.loc = b->props[i].vloc[0];
  o->sheet = sh;
  return 0;
}

/* The property named name in b, or NULL. */
static const Prop *prop_named(const BlockVal *b, const char *name) {
  for (int i = 0; i < b->nprops; i++)
    if (!strcmp(b->props[i].name, name)) return &b->props[i];
  return NULL;
}

/* A light is a point (position), a sun (direction) or a spot (position
** and point_at); a spot's cone properties need point_at, and its fade
** lies inside its cone. */
static int check_light(Ctx *c, const BlockVal *b, const SceneLight *l) {
  const Prop *pos = prop_named(b, "position"), *dir = prop_named(b, "direction");
  const Prop *at = prop_named(b, "point_at"), *cone = prop_named(b, "cone"), *pen = prop_named(b, "penumbra");
  if (!pos == !dir) {
    ev_error(c->ev, b->loc, pos ? "a `light` has `position` (a point light) or `direction` (a sun), not both"
                                : "`light` block needs `position` (a point light) or `direction` (a sun)");
    return -1;
  }
  if (at && dir) {
    ev_error(c->ev, name_range(at), "`point_at` makes a spot light, which needs `position`, not `direction`");
    return -1;
  }
  if (!at && (cone || pen)) {
    ev_error(c->ev, name_range(cone ? cone : pen), "`%s` is a spot light's: it needs `point_at` (where the spot aims)",
             cone ? "cone" : "penumbra");
    return -1;
  }
  if (at && v3_len(v3_sub(l->point_at, l->position)) == 0) {
    ev_error(c->ev, at->vloc[0], "`point_at` in `light` is its `position`: a spot needs a direction to aim");
    return -1;
  }
  if (pen && l->penumbra > l->cone) {
    char a[32], b2[32];
    val_format_number(a, sizeof a, l->penumbra);
    val_format_number(b2, sizeof b2, l->cone);
    ev_error(c->ev, pen->vloc[0], "`penumbra` in `light` is %s degrees, wider than its `cone` of %s: the fade lies "
             "inside the cone", a, b2);
    return -1;
  }
  return 0;
}

/* camera and output may appear once: a second points at the first. */
static int once(Ctx *c, const BlockVal *b, SrcRange first, int present) {
  if (!present) return 0;
  ev_error(c->ev, b->loc, "a second `%s` block", b->kind);
  diag_note(first, "the first is here");
  return -1;
}

static int emit_simple(Ctx *c, const Schema *s, const BlockVal *b) {
  Scene *sc = c->ev->scene;
  if (strcmp(b->kind, "output") == 0) {
    if (once(c, b, sc->output.loc, sc->output.loc.file >= 0)) return -1;
    apply_defaults(s, &sc->output);
    sc->output.loc = b->loc;
    int bad = check_props(c, s, b, &sc->output);
    for (int i = 0; i < b->nsubs; i++) bad |= emit_sheet(c, b->subs[i], &sc->output);
    return bad ? -1 : 0;
  }
  if (strcmp(b->kind, "camera") == 0) {
    if (once(c, b, sc->camera.loc, sc->camera.present)) return -1;
    SceneCamera cam = sc->camera;
    apply_defaults(s, &cam);
    cam.present = 1;
    cam.kind = CAMERA_PERSPECTIVE;
    cam.loc = b->loc;
    if (check_props(c, s, b, &cam) || no_subs(c, b)) return -1;
    /* `up` names the picture's top: without one across the view, none is */
    Vec3 fwd = v3_sub(cam.look_at, cam.position);
    if (v3_len(cam.up) == 0) {
      ev_error(c->ev, prop_at(b, "up"), "`up` cannot be [0, 0, 0]: it says which way the picture's top points");
      return -1;
    }
    if (v3_len(fwd) > 0 && v3_len(v3_cross(fwd, cam.up)) <= 1e-9 * v3_len(fwd) * v3_len(cam.up)) {
      ev_error(c->ev, prop_at(b, "up"), "`up` is parallel to the view (from `position` to `look_at`): the "
               "picture's top is undefined; give an `up` across the view");
      return -1;
    }
    sc->camera = cam;
    return 0;
  }
  SceneLight l;   /* light */
  memset(&l, 0, sizeof l);
  apply_defaults(s, &l);
  l.name = b->nwords ? scene_str(c, b->words[0]) : NULL;
  l.kind = LIGHT_POINT;
  l.position = v3(0, 0, 10);
  l.color = (Color){1, 1, 1, 1};
  l.loc = b->loc;
  if (check_props(c, s, b, &l) || no_subs(c, b) || check_light(c, b, &l)) return -1;
  sc->lights = grow(c, sc->lights, sc->nlights, sizeof *sc->lights);
  sc->lights[sc->nlights++] = l;
  return 0;
}

/* The lights a shade ink style names, as indices into the scene's. */
static void resolve_ink_lights(Ctx *c, ShadeInk *k) {
  Scene *sc = c->ev->scene;
  const char **names = arena_alloc(&sc->arena, ((size_t)sc->nlights + 1) * sizeof *names);
  int nnamed = 0;
  for (int i = 0; i < sc->nlights; i++)
    if (sc->lights[i].name) names[nnamed++] = sc->lights[i].name;
  k->light_index = arena_alloc(&sc->arena, (size_t)k->nlights * sizeof *k->light_index);
  for (int i = 0; i < k->nlights; i++) {
    k->light_index[i] = -1;
    for (int j = 0; j < sc->nlights && k->light_index[i] < 0; j++)
      if (sc->lights[j].name && !strcmp(sc->lights[j].name, k->lights[i])) k->light_index[i] = j;
    if (k->light_index[i] >= 0) continue;
    const char *sug = suggest_name(k->lights[i], names, nnamed);
    if (sug) ev_error(c->ev, k->lights_loc, "`lights` in `shade ink`: no light is named `%s`; did you mean `%s`?",
                      k->lights[i], sug);
    else ev_error(c->ev, k->lights_loc, "`lights` in `shade ink`: no light is named `%s` (name one: "
                  "`light %s { ... }`)", k->lights[i], k->lights[i]);
  }
}

void schema_finish(Eval *ev) {
  Ctx c;
  memset(&c, 0, sizeof c);
  c.ev = ev;
  Scene *sc = ev->scene;
  for (int i = 0; i < sc->nstyles; i++)
    if (sc->styles[i].shade.kind == SHADE_INK && sc->styles[i].shade.ink.nlights)
      resolve_ink_lights(&c, &sc->styles[i].shade.ink);
}

int schema_emit(Eval *ev, BlockVal *b) {
  Ctx c;
  memset(&c, 0, sizeof c);
  c.ev = ev;
  snprintf(c.what, sizeof c.what, "%s", b->kind);
  const Schema *s = find_schema(b->kind, NULL);
  if (!s || (!s->top && strcmp(b->kind, "style") != 0)) {
    unknown_kind(&c, b, "output|camera|light|style|object|origami", s ? " at the top level" : "");
    return -1;
  }
  if (check_words(&c, s, b)) return -1;
  if (strcmp(b->kind, "style") == 0) return emit_style(&c, b);
  /* the other kinds are not values: their result is only success */
  if (strcmp(b->kind, "object") == 0) emit_object(&c, s, b);
  else if (strcmp(b->kind, "origami") == 0) emit_origami(&c, s, b);
  else emit_simple(&c, s, b);
  return -1;
}
