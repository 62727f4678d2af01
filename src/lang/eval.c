/*
** The evaluator's run time: expressions, calls, comprehensions, statements
** and blocks over the ENodes that eval_compile.c made. Errors are reported
** where they happen and yield V_ERR, which every consumer passes on without
** a second message (no longjmp: the C stack unwinds normally). A limit
** (recursion, iterations, list length, memory) also sets Eval.stop so the
** whole run winds down at once.
*/
#include "eval.h"

#include <pthread.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "../geom/shapes.h"
#include "builtins.h"
#include "eval_int.h"
#include "habits.h"
#include "schema.h"

/* The evaluator runs on a thread with a stack this large, so deep
** recursion reaches the recursion limit (a diagnostic) long before the
** C stack's end; the guard below catches what the limit does not. */
#define EVAL_C_STACK (512u << 20)
#define EVAL_C_STACK_MARGIN (1u << 20)

/* Value-stack slots for Envs that no closure captures (16 bytes each). */
#define EVAL_VALUE_STACK (1 << 22)

#define LIKELY(x) __builtin_expect(!!(x), 1)
#define UNLIKELY(x) __builtin_expect(!!(x), 0)

/* Frames of the call stack shown under an error (the rest is elided). */
#define EVAL_NOTE_INNER 3
#define EVAL_NOTE_OUTER 2

/* ---- memory and values ------------------------------------------------ */

static void limit_error(Eval *ev, SrcRange at, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

void *ev_alloc(Eval *ev, size_t n) {
  ev->mem_used += (long long)n;
  if (ev->mem_used > ev->opt->max_memory && !ev->stop)
    limit_error(ev, ev->where,
                "the program used more than %lld MB of memory (the limit; raise it with --max-memory-mb N)",
                ev->opt->max_memory >> 20);
  return arena_alloc(ev->arena, n);
}

Value ev_str(Eval *ev, const char *s, int len) {
  Str *st = ev_alloc(ev, sizeof(Str) + (size_t)len + 1);
  st->len = len;
  memcpy(st->s, s, (size_t)len);
  st->s[len] = 0;
  return val_ptr(V_STR, st);
}

List *ev_list(Eval *ev, int n) {
  List *l = ev_alloc(ev, sizeof(List) + (size_t)n * sizeof(Value));
  l->n = n;
  l->v = (Value *)(l + 1);
  return l;
}

Value ev_color(Eval *ev, double r, double g, double b, double a) {
  Color *c = ev_alloc(ev, sizeof *c);
  c->r = (float)r; c->g = (float)g; c->b = (float)b; c->a = (float)a;
  return val_ptr(V_COLOR, c);
}

Value ev_xform(Eval *ev, Mat4 m) {
  Mat4 *p = ev_alloc(ev, sizeof *p);
  *p = m;
  return val_ptr(V_XFORM, p);
}

/* Interned names compare by pointer; an open-addressing table. */
static unsigned hash_str(const char *s) {
  unsigned h = 2166136261u;
  while (*s) h = (h ^ (unsigned char)*s++) * 16777619u;
  return h;
}

const char *ev_intern(Eval *ev, const char *s) {
  if (ev->nintern * 2 >= ev->capintern) {
    int cap = ev->capintern ? ev->capintern * 2 : 256;
    const char **t = xcalloc((size_t)cap, sizeof *t);
    for (int i = 0; i < ev->capintern; i++)
      if (ev->intern[i]) {
        unsigned h = hash_str(ev->intern[i]) & (unsigned)(cap - 1);
        while (t[h]) h = (h + 1) & (unsigned)(cap - 1);
        t[h] = ev->intern[i];
      }
    free(ev->intern);
    ev->intern = t;
    ev->capintern = cap;
  }
  unsigned h = hash_str(s) & (unsigned)(ev->capintern - 1);
  while (ev->intern[h]) {
    if (strcmp(ev->intern[h], s) == 0) return ev->intern[h];
    h = (h + 1) & (unsigned)(ev->capintern - 1);
  }
  ev->nintern++;
  return ev->intern[h] = arena_strndup(ev->ast_arena, s, strlen(s));
}

/* ---- diagnostics ----------------------------------------------------- */

static void call_note(const CallRec *c) {
  if (c->name) diag_note(c->site, "in %s `%s`, called from here", c->is_module ? "module" : "function", c->name);
  else diag_note(c->site, "in a function literal, called from here");
}

/* The call stack under an error: the innermost few frames and the
** outermost few, with the middle elided. */
static void call_notes(Eval *ev) {
  int d = ev->depth;
  for (int i = d - 1; i >= 0; i--) {
    if (d > EVAL_NOTE_INNER + EVAL_NOTE_OUTER + 1 && i == d - 1 - EVAL_NOTE_INNER) {
      int skip = d - EVAL_NOTE_INNER - EVAL_NOTE_OUTER;
      diag_note(src_none(), "... %d more call%s ...", skip, skip == 1 ? "" : "s");
      i = EVAL_NOTE_OUTER;
      continue;
    }
    call_note(&ev->calls[i]);
  }
}

static void ev_verror(Eval *ev, SrcRange at, const char *fmt, va_list ap) {
  char msg[1024];
  vsnprintf(msg, sizeof msg, fmt, ap);
  diag_error(at, "%s", msg);
  call_notes(ev);
}

void ev_error(Eval *ev, SrcRange at, const char *fmt, ...) {
  if (ev->stop) return;
  va_list ap;
  va_start(ap, fmt);
  ev_verror(ev, at, fmt, ap);
  va_end(ap);
}

static void limit_error(Eval *ev, SrcRange at, const char *fmt, ...) {
  if (ev->stop) return;
  va_list ap;
  va_start(ap, fmt);
  ev_verror(ev, at, fmt, ap);
  va_end(ap);
  ev->stop = 1;
}

/* "a number", "an undef": the article for a type name in messages. */
static const char *a_type(const Value *v) {
  static char buf[4][40];
  static int k;
  const char *t = val_type_name(v);
  char *b = buf[k++ & 3];
  snprintf(b, sizeof buf[0], "%s %s", strchr("aeiou", t[0]) ? "an" : "a", t);
  return b;
}

/* Count one loop iteration or call against the limit. */
static inline int count_step(Eval *ev, SrcRange at, const char *what) {
  if (LIKELY(++ev->iterations <= ev->opt->max_iterations)) return 0;
  limit_error(ev, at, "%s ran past the limit of %lld loop iterations and calls (raise it with --max-iterations N)",
              what, ev->opt->max_iterations);
  return 1;
}

int ev_steps(Eval *ev, double n, SrcRange at, const char *what) {
  if (LIKELY(n <= (double)(ev->opt->max_iterations - ev->iterations))) { ev->iterations += (long long)n; return 0; }
  limit_error(ev, at, "%s ran past the limit of %lld loop iterations and calls (its work on each element counts; "
              "raise it with --max-iterations N)", what, ev->opt->max_iterations);
  return 1;
}

int ev_list_limit(Eval *ev, double n, SrcRange at) {
  if (n <= (double)ev->opt->max_list) return 0;
  limit_error(ev, at, "a list grew past the limit of %lld elements (raise it with --max-list N)", ev->opt->max_list);
  return 1;
}

StrBuf ev_text_buf(Eval *ev) {
  StrBuf b = {.max = ev_text_room(ev), .max_work = ev->opt->max_iterations - ev->iterations};
  if (b.max_work < 1) b.max_work = 1;
  return b;
}

size_t ev_text_room(Eval *ev) {
  long long left = ev->opt->max_memory - ev->mem_used;
  if (left < 2) return 1;
  return left / 2 < EVAL_MAX_STRING ? (size_t)(left / 2) : EVAL_MAX_STRING;
}

static void memory_error(Eval *ev, SrcRange at, const char *what, const char *made) {
  limit_error(ev, at, "%s made %s past the memory limit of %lld MB (raise it with --max-memory-mb N)", what, made,
              ev->opt->max_memory >> 20);
}

int ev_buffer_limit(Eval *ev, double n, SrcRange at, const char *what) {
  if (n <= (double)(ev->opt->max_memory - ev->mem_used)) return 0;
  memory_error(ev, at, what, "a buffer");
  return 1;
}

int ev_text_over(Eval *ev, const StrBuf *b, SrcRange at, const char *what) {
  if (b->work > 0) ev->iterations += b->work < ev->opt->max_iterations ? b->work : ev->opt->max_iterations;
  if (!b->over) return 0;
  if (b->over == SB_OVER_WORK) ev_steps(ev, (double)ev->opt->max_iterations + 1, at, what);
  else if (b->max >= EVAL_MAX_STRING)
    limit_error(ev, at, "%s made a string longer than %d bytes (the longest a string can be)", what, EVAL_MAX_STRING);
  else memory_error(ev, at, what, "a string");
  return 1;
}

/* ---- environments ---------------------------------------------------- */

static Env *env_open(Eval *ev, const Scope *sc, Env *up, Env *local, int *mark, SrcRange at) {
  *mark = ev->sp;
  Env *e;
  int n = sc->n;
  if (sc->heap) {
    e = ev_alloc(ev, sizeof *e);
    e->v = ev_alloc(ev, (size_t)(n ? n : 1) * sizeof(Value));
  } else {
    if (ev->sp + n > ev->stack_cap) {
      limit_error(ev, at, "recursion too deep: the evaluator's value stack is full (lower the recursion)");
      return NULL;
    }
    e = local;
    e->v = ev->stack + ev->sp;
    ev->sp += n;
  }
  e->up = up;
  for (int i = 0; i < n; i++) e->v[i] = val_unset();
  for (int i = 0; i < sc->ndefs; i++) {
    Closure *c = ev_alloc(ev, sizeof *c);
    c->def = sc->defs[i];
    c->env = e;
    e->v[sc->def_slot[i]] = val_ptr(sc->defs[i]->is_module ? V_MODULE : V_FUNC, c);
  }
  return e;
}

static inline void env_close(Eval *ev, int mark) { ev->sp = mark; }

/* ---- scratch (lists under construction) ------------------------------- */

static int scratch_push(Eval *ev, Value v, long long base, SrcRange at) {
  if (ev->nscratch == ev->capscratch) {
    long long cap = ev->capscratch ? ev->capscratch * 2 : 1024;
    ev->mem_used += (cap - ev->capscratch) * (long long)sizeof(Value);
    if (ev->mem_used > ev->opt->max_memory) {
      limit_error(ev, at, "the program used more than %lld MB of memory (the limit; raise it with --max-memory-mb N)",
                  ev->opt->max_memory >> 20);
      return -1;
    }
    ev->scratch = xrealloc(ev->scratch, (size_t)cap * sizeof(Value));
    ev->capscratch = cap;
  }
  ev->scratch[ev->nscratch++] = v;
  if (ev->nscratch - base > ev->opt->max_list) return ev_list_limit(ev, ev->nscratch - base, at) ? -1 : 0;
  return 0;
}

/* Lists longer than this, built from an empty scratch, take the scratch
** buffer itself instead of copying it (a 10M-element list is 160 MB). */
#define EVAL_STEAL_LIST (1 << 16)

static Value scratch_take(Eval *ev, long long base) {
  int n = (int)(ev->nscratch - base);
  if (base == 0 && n >= EVAL_STEAL_LIST) {
    List *l = ev_alloc(ev, sizeof(List));
    l->n = n;
    l->v = ev->scratch;
    ev->owned = xgrow(ev->owned, &ev->capowned, ev->nowned + 1, sizeof *ev->owned);
    ev->owned[ev->nowned++] = ev->scratch;
    ev->scratch = NULL;
    ev->nscratch = ev->capscratch = 0;
    return val_ptr(V_LIST, l);
  }
  List *l = ev_list(ev, n);
  if (n) memcpy(l->v, ev->scratch + base, (size_t)n * sizeof(Value));
  ev->nscratch = base;
  return val_ptr(V_LIST, l);
}

/* ---- iteration ------------------------------------------------------- */

typedef struct Iter {
  Value src;
  long long n;
} Iter;

/* The characters of a string as a list of one-character strings. */
static Value string_chars(Eval *ev, const Str *s) {
  int n = 0;
  for (int i = 0; i < s->len; i++) n += ((unsigned char)s->s[i] & 0xC0) != 0x80;
  List *l = ev_list(ev, n);
  int k = 0;
  for (int i = 0; i < s->len;) {
    int j = i + 1;
    while (j < s->len && ((unsigned char)s->s[j] & 0xC0) == 0x80) j++;
    l->v[k++] = ev_str(ev, s->s + i, j - i);
    i = j;
  }
  return val_ptr(V_LIST, l);
}

/* The element count of a range, checked before it becomes an integer: a
** loop (what names it) over more elements than the iterations left, or
** an `each` (what NULL) past the list limit, is that limit's error now,
** not a count cast beyond long long or a loop that runs for hours. */
static int range_count(Eval *ev, const Range *r, long long *n, SrcRange at, const char *what) {
  double count = val_range_count(r);
  long long room = what ? ev->opt->max_iterations - ev->iterations : ev->opt->max_list;
  if (count <= (double)room) { *n = (long long)count; return 0; }
  if (!what) return ev_list_limit(ev, room + 1, at) ? -1 : 0;
  char num[32] = "no end";
  if (!isinf(count)) val_format_number(num, sizeof num, count);
  limit_error(ev, at, "this range has %s%s: %s over it would run past the limit of %lld loop iterations and "
              "calls (raise it with --max-iterations N)", num, isinf(count) ? "" : " elements", what,
              ev->opt->max_iterations);
  return -1;
}

static int iter_init(Eval *ev, Value v, Iter *it, SrcRange at, const char *what) {
  if (v.kind == V_ERR) return -1;
  if (v.kind == V_STR) v = string_chars(ev, v.u.s);
  it->src = v;
  switch (v.kind) {
  case V_LIST: it->n = v.u.l->n; return 0;
  case V_RANGE: return range_count(ev, v.u.r, &it->n, at, what);
  case V_NUM: case V_BOOL: it->n = 1; return 0;
  default:
    ev_error(ev, at, "a loop needs a list, a range or a string; found %s", a_type(&v));
    return -1;
  }
}

static inline Value iter_get(const Iter *it, long long i) {
  switch (it->src.kind) {
  case V_LIST: return it->src.u.l->v[i];
  case V_RANGE: return val_num(it->src.u.r->start + (double)i * it->src.u.r->step);
  default: return it->src;
  }
}

/* ---- arithmetic ------------------------------------------------------- */

static const char *op_text(EOp op) {
  switch (op) {
  case E_ADD: return "+"; case E_SUB: return "-"; case E_MUL: return "*"; case E_DIV: return "/";
  case E_MOD: return "%"; case E_POW: return "^"; case E_LT: return "<"; case E_LE: return "<=";
  case E_GT: return ">"; case E_GE: return ">="; default: return "?";
  }
}

static double num_op(EOp op, double a, double b) {
  switch (op) {
  case E_ADD: return a + b;
  case E_SUB: return a - b;
  case E_MUL: return a * b;
  case E_DIV: return a / b;
  case E_MOD: return fmod(a, b);
  default: return pow(a, b);
  }
}

static Value arith(Eval *ev, EOp op, Value a, Value b, const ENode *e);

static Value broadcast(Eval *ev, EOp op, Value a, Value b, const ENode *e) {
  int la = a.kind == V_LIST ? a.u.l->n : -1, lb = b.kind == V_LIST ? b.u.l->n : -1;
  if (la >= 0 && lb >= 0 && la != lb) {
    ev_error(ev, e->range, "`%s` on lists of different lengths (%d and %d)", op_text(op), la, lb);
    return val_err();
  }
  int n = la >= 0 ? la : lb;
  List *l = ev_list(ev, n);
  for (int i = 0; i < n; i++) {
    l->v[i] = arith(ev, op, la >= 0 ? a.u.l->v[i] : a, lb >= 0 ? b.u.l->v[i] : b, e);
    if (l->v[i].kind == V_ERR) return val_err();
  }
  return val_ptr(V_LIST, l);
}

static Value color_op(Eval *ev, EOp op, Value a, Value b, const ENode *e) {
  float ca[4], cb[4];
  for (int k = 0; k < 2; k++) {
    Value v = k ? b : a;
    float *d = k ? cb : ca;
    if (v.kind == V_COLOR) { d[0] = v.u.c->r; d[1] = v.u.c->g; d[2] = v.u.c->b; d[3] = v.u.c->a; }
    else if (v.kind == V_NUM) d[0] = d[1] = d[2] = d[3] = (float)v.u.n;
    else goto bad;
  }
  if (op == E_MOD || op == E_POW) goto bad;
  double r[4];
  for (int i = 0; i < 4; i++) r[i] = num_op(op, ca[i], cb[i]);
  /* alpha of colour op number keeps the colour's alpha */
  if (a.kind != V_COLOR) r[3] = cb[3];
  else if (b.kind != V_COLOR) r[3] = ca[3];
  return ev_color(ev, r[0], r[1], r[2], r[3]);
bad:
  ev_error(ev, e->range, "`%s` cannot combine %s and %s", op_text(op), a_type(&a), a_type(&b));
  return val_err();
}

static Value xform_op(Eval *ev, EOp op, Value a, Value b, const ENode *e) {
  Vec3 p;
  if (op == E_MUL && a.kind == V_XFORM && b.kind == V_XFORM) return ev_xform(ev, m4_mul(*a.u.m, *b.u.m));
  if (op == E_MUL && a.kind == V_XFORM && b.kind == V_GEOM) {   /* the shape moved: translate(v) * cube(1) */
    SceneGeometry *g = shape_transformed(&ev->scene->arena, b.u.g, *a.u.m);
    g->loc = e->range;
    return val_ptr(V_GEOM, g);
  }
  if (op == E_MUL && a.kind == V_XFORM && val_to_point(&b, &p)) {
    Vec3 q = m4_point(*a.u.m, p);
    List *l = ev_list(ev, 3);
    l->v[0] = val_num(q.x); l->v[1] = val_num(q.y); l->v[2] = val_num(q.z);
    return val_ptr(V_LIST, l);
  }
  if (op == E_MUL)
    ev_error(ev, e->range, "`*` with a transform needs a transform, a point or a shape on the right; found %s",
             a_type(&b));
  else ev_error(ev, e->range, "transforms only compose with `*`; found `%s`", op_text(op));
  return val_err();
}

static Value arith(Eval *ev, EOp op, Value a, Value b, const ENode *e) {
  if (a.kind == V_NUM && b.kind == V_NUM) return val_num(num_op(op, a.u.n, b.u.n));
  if (a.kind == V_ERR || b.kind == V_ERR) return val_err();
  if (a.kind == V_XFORM) return xform_op(ev, op, a, b, e);
  if (a.kind == V_COLOR || b.kind == V_COLOR) return color_op(ev, op, a, b, e);
  if ((a.kind == V_LIST || a.kind == V_NUM) && (b.kind == V_LIST || b.kind == V_NUM))
    return broadcast(ev, op, a, b, e);
  ev_error(ev, e->range, "`%s` expects numbers, vectors or colours; found %s and %s", op_text(op), a_type(&a),
           a_type(&b));
  return val_err();
}

static Value compare(Eval *ev, EOp op, Value a, Value b, const ENode *e) {
  int c;
  if ((a.kind == V_NUM || a.kind == V_BOOL) && (b.kind == V_NUM || b.kind == V_BOOL))
    c = a.u.n < b.u.n ? -1 : a.u.n > b.u.n ? 1 : a.u.n == b.u.n ? 0 : 2;
  else if (a.kind == V_STR && b.kind == V_STR) {
    int n = a.u.s->len < b.u.s->len ? a.u.s->len : b.u.s->len;
    c = memcmp(a.u.s->s, b.u.s->s, (size_t)n);
    if (c == 0) c = a.u.s->len - b.u.s->len;
  } else {
    if (a.kind == V_ERR || b.kind == V_ERR) return val_err();
    ev_error(ev, e->range, "`%s` needs two numbers or two strings; found %s and %s", op_text(op), a_type(&a),
             a_type(&b));
    return val_err();
  }
  if (c == 2) return val_bool(0);   /* NaN compares false */
  switch (op) {
  case E_LT: return val_bool(c < 0);
  case E_LE: return val_bool(c <= 0);
  case E_GT: return val_bool(c > 0);
  default: return val_bool(c >= 0);
  }
}

static Value negate(Eval *ev, Value a, const ENode *e) {
  if (a.kind == V_NUM) return val_num(-a.u.n);
  return arith(ev, E_MUL, a, val_num(-1), e);
}

/* ---- indexing and members -------------------------------------------- */

static Value index_value(Eval *ev, Value a, Value i, const ENode *e) {
  if (a.kind == V_ERR || i.kind == V_ERR) return val_err();
  if (i.kind != V_NUM) {
    ev_error(ev, e->b->range, "an index must be a number; found %s", a_type(&i));
    return val_err();
  }
  double k = floor(i.u.n);
  switch (a.kind) {
  case V_LIST: return k >= 0 && k < a.u.l->n ? a.u.l->v[(int)k] : val_undef();
  case V_STR: {
    Value chars = string_chars(ev, a.u.s);
    return k >= 0 && k < chars.u.l->n ? chars.u.l->v[(int)k] : val_undef();
  }
  case V_RANGE:
    return k >= 0 && k < val_range_count(a.u.r) ? val_num(a.u.r->start + k * a.u.r->step) : val_undef();
  case V_UNDEF: return val_undef();
  default:
    ev_error(ev, e->range, "only lists, strings and ranges can be indexed; found %s", a_type(&a));
    return val_err();
  }
}

static Value member_value(Eval *ev, Value a, const ENode *e) {
  const char *m = e->name;
  if (a.kind == V_ERR) return val_err();
  if (a.kind == V_LIST && (m == ev->sym_x || m == ev->sym_y || m == ev->sym_z || m == ev->sym_w)) {
    int k = m == ev->sym_x ? 0 : m == ev->sym_y ? 1 : m == ev->sym_z ? 2 : 3;
    return k < a.u.l->n ? a.u.l->v[k] : val_undef();
  }
  if (a.kind == V_COLOR && (m == ev->sym_r || m == ev->sym_g || m == ev->sym_b || m == ev->sym_a)) {
    const Color *c = a.u.c;
    return val_num(m == ev->sym_r ? c->r : m == ev->sym_g ? c->g : m == ev->sym_b ? c->b : c->a);
  }
  if (a.kind == V_LIST)
    ev_error(ev, e->range, "a vector has `.x`, `.y`, `.z` and `.w`; found `.%s`", m);
  else if (a.kind == V_COLOR)
    ev_error(ev, e->range, "a colour has `.r`, `.g`, `.b` and `.a`; found `.%s`", m);
  else
    ev_error(ev, e->range, "`.%s` needs a vector or a colour; found %s", m, a_type(&a));
  return val_err();
}

/* ---- calls ------------------------------------------------------------ */

static inline int guard_depth(Eval *ev, const char *name, int is_module, SrcRange site) {
  char here;
  if (UNLIKELY(ev->stop)) return -1;
  if (UNLIKELY(ev->depth >= ev->opt->max_recursion ||
               (size_t)(ev->cstack_base - &here) > ev->cstack_size - EVAL_C_STACK_MARGIN)) {
    if (ev->depth >= ev->opt->max_recursion)
      limit_error(ev, site, "recursion in %s `%s` went deeper than %d calls (the limit; raise it with --max-recursion N)",
                  is_module ? "module" : "function", name ? name : "literal", ev->opt->max_recursion);
    else
      limit_error(ev, site, "recursion in %s `%s` exhausted the evaluator's stack at depth %d",
                  is_module ? "module" : "function", name ? name : "literal", ev->depth);
    return -1;
  }
  if (ev->depth >= ev->ncalls_cap) ev->calls = xgrow(ev->calls, &ev->ncalls_cap, ev->depth + 1, sizeof *ev->calls);
  CallRec *r = &ev->calls[ev->depth++];
  r->name = name;
  r->is_module = is_module;
  r->site = site;
  return 0;
}

/* "function `f`", "module `m`": how limit messages name a callee. */
static const char *fn_what(const FnDef *d) {
  static char buf[160];
  if (!d->name) return "a function literal";
  snprintf(buf, sizeof buf, "%s `%s`", d->is_module ? "module" : "function", d->name);
  return buf;
}

/* count_step for a call; the callee's name is only formatted on failure. */
static inline int count_call(Eval *ev, SrcRange at, const FnDef *d) {
  if (LIKELY(ev->iterations + 1 <= ev->opt->max_iterations)) { ev->iterations++; return 0; }
  return count_step(ev, at, fn_what(d));
}

static int param_index(const FnDef *d, const char *name) {
  for (int i = 0; i < d->nparams; i++)
    if (d->pnames[i] == name) return i;
  return -1;
}

/* "`f`", or "a function literal" for one without a name. */
static const char *callee(const FnDef *d) {
  static char buf[160];
  if (!d->name) return "a function literal";
  snprintf(buf, sizeof buf, "`%s`", d->name);
  return buf;
}

static void unknown_arg(Eval *ev, const FnDef *d, const char *name, SrcRange at) {
  const char *s = suggest_name(name, d->pnames, d->nparams);
  if (s) ev_error(ev, at, "%s has no parameter `%s`; did you mean `%s`?", callee(d), name, s);
  else ev_error(ev, at, "%s has no parameter `%s`", callee(d), name);
}

/* Evaluate the call's arguments (in the caller's env) into the frame's
** parameter slots. */
static int bind_args(Eval *ev, const FnDef *d, const ENode *call, Env *caller, Env *fe) {
  int pos = 0;
  for (int i = 0; i < call->n; i++) {
    int k;
    if (!call->names[i]) {
      k = pos++;
      if (k >= d->nparams) {
        ev_error(ev, call->argloc[i], "too many arguments to %s (it takes %d)", callee(d), d->nparams);
        return -1;
      }
    } else if ((k = param_index(d, call->names[i])) < 0) {
      unknown_arg(ev, d, call->names[i], call->argloc[i]);
      return -1;
    } else if (fe->v[k].kind != V_UNSET) {
      ev_error(ev, call->argloc[i], "argument `%s` is given twice", call->names[i]);
      return -1;
    }
    fe->v[k] = ev_expr(ev, call->kids[i], caller);
    if (fe->v[k].kind == V_ERR) return -1;
  }
  return 0;
}

/* Defaults of the parameters not given, in the frame, left to right (the
** call is on the call stack by now, so their errors show it). */
static int bind_defaults(Eval *ev, const FnDef *d, Env *fe) {
  for (int k = 0; k < d->nparams; k++)
    if (fe->v[k].kind == V_UNSET) {
      fe->v[k] = d->defaults[k] ? ev_expr(ev, d->defaults[k], fe) : val_undef();
      if (fe->v[k].kind == V_ERR) return -1;
    }
  return 0;
}

/* The common call: positional arguments, one for each parameter, and a
** frame no closure captures. */
static Value call_simple(Eval *ev, const Closure *f, const ENode *call, Env *caller) {
  const FnDef *d = f->def;
  int n = d->nparams, mark = ev->sp;
  if (UNLIKELY(ev->sp + n > ev->stack_cap)) {
    limit_error(ev, call->range, "recursion too deep: the evaluator's value stack is full (lower the recursion)");
    return val_err();
  }
  Env fe = {f->env, ev->stack + ev->sp};
  ev->sp += n;
  Value r = val_err();
  for (int i = 0; i < n; i++)
    if (UNLIKELY((fe.v[i] = ev_expr(ev, call->kids[i], caller)).kind == V_ERR)) goto out;
  if (guard_depth(ev, d->name, 0, call->range)) goto out;
  if (count_call(ev, call->range, d)) { ev->depth--; goto out; }
  r = ev_expr(ev, d->body, &fe);
  ev->depth--;
out:
  ev->sp = mark;
  return r;
}

static Value call_closure(Eval *ev, const Closure *f, const ENode *call, Env *caller) {
  const FnDef *d = f->def;
  if (LIKELY(call->simple && d->nparams == call->n && !d->scope->heap)) return call_simple(ev, f, call, caller);
  Env local;
  int mark;
  Env *fe = env_open(ev, d->scope, f->env, &local, &mark, call->range);
  Value r = val_err();
  if (fe && bind_args(ev, d, call, caller, fe) == 0 && guard_depth(ev, d->name, 0, call->range) == 0) {
    if (!count_call(ev, call->range, d) && bind_defaults(ev, d, fe) == 0)
      r = ev_expr(ev, d->body, fe);
    ev->depth--;
  }
  env_close(ev, mark);
  return r;
}

/* A builtin's work on its arguments counts toward the iteration limit:
** one step per element of each list and per 16 bytes of each string. */
static int builtin_steps(Eval *ev, const Builtin *bi, const Value *args, int n, const ENode *call) {
  double w = 0;
  for (int i = 0; i < n; i++)
    w += args[i].kind == V_LIST ? args[i].u.l->n : args[i].kind == V_STR ? args[i].u.s->len / 16 : 0;
  if (w < 1) return 0;
  char what[80];
  snprintf(what, sizeof what, "`%s`", bi->name);
  return ev_steps(ev, w, call->range, what);
}

/* Builtin arguments: positional in order, named ones matched against the
** builtin's parameter names; missing ones are V_UNSET. A call statement's
** children (kids, the shapes they made) come first: as the arguments
** themselves (BI_CHILDREN_ARGS) or as a list, the first argument
** (BI_CHILDREN_FIRST); kids is NULL for a plain call. */
static Value call_builtin(Eval *ev, const Builtin *bi, const ENode *call, Env *env, const Value *kids, int nkids) {
  int nk = kids && bi->kind == BI_CHILDREN_ARGS ? nkids : 0;
  int first = kids && bi->kind == BI_CHILDREN_FIRST;
  int n = bi->max_args < 0 ? call->n + nk : bi->max_args;
  if (ev->sp + n > ev->stack_cap) {
    limit_error(ev, call->range, "recursion too deep: the evaluator's value stack is full");
    return val_err();
  }
  Value *args = ev->stack + ev->sp;
  int mark = ev->sp;
  ev->where = call->range;
  ev->sp += n;
  for (int i = 0; i < n; i++) args[i] = val_unset();
  for (int i = 0; i < nk; i++) args[i] = kids[i];
  if (first) {
    List *l = ev_list(ev, nkids);
    if (nkids) memcpy(l->v, kids, (size_t)nkids * sizeof *kids);
    args[0] = val_ptr(V_LIST, l);
  }
  int pos = nk + first, given = nk + first;
  Value r = val_err();
  char hint[600];
  for (int i = 0; i < call->n; i++) {
    int k = pos;
    if (call->names[i] && bi->max_args >= 0) {
      k = builtin_param(bi, call->names[i]);
      if (k < 0) {
        habit_hint(HABIT_ARGS, bi->name, NULL, hint, sizeof hint);
        ev_error(ev, call->argloc[i], "`%s` has no parameter `%s`%s", bi->name, call->names[i], hint);
        goto out;
      }
    } else pos++;
    if (k >= n) {
      habit_hint(HABIT_ARGS, bi->name, NULL, hint, sizeof hint);
      ev_error(ev, call->argloc[i], "too many arguments to `%s` (it takes %d)%s", bi->name, n, hint);
      goto out;
    }
    args[k] = ev_expr(ev, call->kids[i], env);
    if (args[k].kind == V_ERR) goto out;
    given++;
  }
  for (int k = 0; k < bi->min_args && k < n; k++)
    if (args[k].kind == V_UNSET) {
      ev_error(ev, call->range, "`%s` needs at least %d argument%s; found %d", bi->name, bi->min_args,
               bi->min_args == 1 ? "" : "s", given);
      goto out;
    }
  if (!builtin_constant_time(bi) && builtin_steps(ev, bi, args, n, call)) goto out;
  r = bi->fn(ev, args, n, call);
out:
  ev->sp = mark;
  return r;
}

static Value call_value(Eval *ev, Value f, const ENode *call, Env *env) {
  if (f.kind == V_FUNC) {
    if (f.u.f->def) return call_closure(ev, f.u.f, call, env);
    if (f.u.f->bi->kind != BI_STATEMENT) return call_builtin(ev, f.u.f->bi, call, env, NULL, 0);
    ev_error(ev, call->range, "`%s` is a statement, not a function: write `%s(...);` on its own", f.u.f->bi->name,
             f.u.f->bi->name);
    return val_err();
  }
  if (f.kind == V_ERR) return f;
  ev_error(ev, call->a->range, "only functions can be called; this is %s", a_type(&f));
  return val_err();
}

/* ---- comprehensions -------------------------------------------------- */

static int comp_emit(Eval *ev, const ENode *e, Env *env, long long base);

/* A copy of an Env, so a closure made in this iteration keeps its values. */
static Env *env_clone(Eval *ev, const Env *src, int n) {
  Env *e = ev_alloc(ev, sizeof *e);
  e->up = src->up;
  e->v = ev_alloc(ev, (size_t)(n ? n : 1) * sizeof(Value));
  memcpy(e->v, src->v, (size_t)n * sizeof(Value));
  return e;
}

static int comp_for(Eval *ev, const ENode *e, Env *fe, int k, long long base) {
  if (k == e->n) return comp_emit(ev, e->a, e->scope->heap ? env_clone(ev, fe, e->scope->n) : fe, base);
  Iter it;
  if (iter_init(ev, ev_expr(ev, e->kids[k], fe), &it, e->kids[k]->range, "a list comprehension")) return -1;
  for (long long i = 0; i < it.n; i++) {
    if (count_step(ev, e->range, "this list comprehension")) return -1;
    fe->v[k] = iter_get(&it, i);
    if (comp_for(ev, e, fe, k + 1, base)) return -1;
  }
  return 0;
}

static int comp_each(Eval *ev, const ENode *e, Env *env, long long base) {
  Value v = ev_expr(ev, e->a, env);
  if (v.kind == V_ERR) return -1;
  if (v.kind != V_LIST && v.kind != V_RANGE && v.kind != V_STR) return scratch_push(ev, v, base, e->range);
  Iter it;
  if (iter_init(ev, v, &it, e->range, NULL)) return -1;
  for (long long i = 0; i < it.n; i++)
    if (scratch_push(ev, iter_get(&it, i), base, e->range)) return -1;
  return 0;
}

static int comp_emit(Eval *ev, const ENode *e, Env *env, long long base) {
  Env local;
  int mark, r;
  switch (e->op) {
  case E_COMP_FOR: {
    Env *fe = env_open(ev, e->scope, env, &local, &mark, e->range);
    r = fe ? comp_for(ev, e, fe, 0, base) : -1;
    env_close(ev, mark);
    return r;
  }
  case E_COMP_IF: {
    Value c = ev_expr(ev, e->a, env);
    if (c.kind == V_ERR) return -1;
    if (val_truthy(&c)) return comp_emit(ev, e->b, env, base);
    return e->c ? comp_emit(ev, e->c, env, base) : 0;
  }
  case E_COMP_EACH: return comp_each(ev, e, env, base);
  case E_COMP_LET: {
    Env *le = env_open(ev, e->scope, env, &local, &mark, e->range);
    r = -1;
    if (le) {
      int k;
      for (k = 0; k < e->n; k++)
        if ((le->v[k] = ev_expr(ev, e->kids[k], le)).kind == V_ERR) break;
      if (k == e->n) r = comp_emit(ev, e->a, le, base);
    }
    env_close(ev, mark);
    return r;
  }
  default: {
    Value v = ev_expr(ev, e, env);
    if (v.kind == V_ERR) return -1;
    return scratch_push(ev, v, base, e->range);
  }
  }
}

static Value list_value(Eval *ev, const ENode *e, Env *env) {
  long long base = ev->nscratch;
  ev->where = e->range;
  for (int i = 0; i < e->n; i++)
    if (comp_emit(ev, e->kids[i], env, base)) {
      ev->nscratch = base;
      return val_err();
    }
  return scratch_take(ev, base);
}

/* ---- expressions ------------------------------------------------------ */

static Value range_value(Eval *ev, const ENode *e, Env *env) {
  Value a = ev_expr(ev, e->a, env);
  Value s = e->b ? ev_expr(ev, e->b, env) : val_num(1);
  Value b = ev_expr(ev, e->c, env);
  const Value *parts[3] = {&a, &s, &b};
  for (int i = 0; i < 3; i++) {
    if (parts[i]->kind == V_ERR) return val_err();
    if (parts[i]->kind != V_NUM) {
      ev_error(ev, e->range, "a range needs numbers; found %s", a_type(parts[i]));
      return val_err();
    }
  }
  for (int i = 0; i < 3; i++)
    if (isnan(parts[i]->u.n)) {
      ev_error(ev, e->range, "a range needs numbers; its %s is nan", i == 0 ? "start" : i == 1 ? "step" : "end");
      return val_err();
    }
  if (s.u.n == 0) {
    ev_error(ev, e->range, "a range's step cannot be 0");
    return val_err();
  }
  Range *r = ev_alloc(ev, sizeof *r);
  r->start = a.u.n;
  r->step = s.u.n;
  r->end = b.u.n;
  return val_ptr(V_RANGE, r);
}

static Value let_value(Eval *ev, const ENode *e, Env *env) {
  Env local;
  int mark;
  Env *le = env_open(ev, e->scope, env, &local, &mark, e->range);
  Value r = val_err();
  if (le) {
    int k;
    for (k = 0; k < e->n; k++)
      if ((le->v[k] = ev_expr(ev, e->kids[k], le)).kind == V_ERR) break;
    if (k == e->n) r = ev_expr(ev, e->a, le);
  }
  env_close(ev, mark);
  return r;
}

static Value symcall_value(Eval *ev, const ENode *e, Env *env) {
  List *args = ev_list(ev, e->n);
  for (int i = 0; i < e->n; i++)
    if ((args->v[i] = ev_expr(ev, e->kids[i], env)).kind == V_ERR) return val_err();
  Symbol *s = ev_alloc(ev, sizeof *s);
  s->name = e->name;
  s->args = args;
  return val_ptr(V_SYMBOL, s);
}

static Value read_slot(Eval *ev, const ENode *e, Value v) {
  if (v.kind == V_UNSET) {
    ev_error(ev, e->range, "`%s` is used before its definition", e->name);
    return val_err();
  }
  return v;
}

Value ev_expr(Eval *ev, const ENode *e, Env *env) {
  Value a, b;
  switch (e->op) {
  case E_CONST: return e->k;
  case E_LOCAL: {
    Env *x = env;
    for (int h = e->hops; h > 0; h--) x = x->up;
    a = x->v[e->slot];
    return a.kind < V_UNSET ? a : read_slot(ev, e, a);
  }
  case E_NSREF:
    a = e->ns->env->v ? e->ns->env->v[e->slot] : val_unset();
    return a.kind < V_UNSET ? a : read_slot(ev, e, a);
  case E_LIST: return list_value(ev, e, env);
  case E_RANGE: return range_value(ev, e, env);
  case E_NEG: a = ev_expr(ev, e->a, env); return a.kind == V_ERR ? a : negate(ev, a, e);
  case E_NOT: a = ev_expr(ev, e->a, env); return a.kind == V_ERR ? a : val_bool(!val_truthy(&a));
/* numbers first, inline: this is the hot path of every numeric script */
#define ARITH(OP, EXPR) \
  case OP: \
    a = ev_expr(ev, e->a, env); \
    b = ev_expr(ev, e->b, env); \
    if (LIKELY(a.kind == V_NUM && b.kind == V_NUM)) return val_num(EXPR); \
    return arith(ev, OP, a, b, e);
  ARITH(E_ADD, a.u.n + b.u.n)
  ARITH(E_SUB, a.u.n - b.u.n)
  ARITH(E_MUL, a.u.n * b.u.n)
  ARITH(E_DIV, a.u.n / b.u.n)
  ARITH(E_MOD, fmod(a.u.n, b.u.n))
  ARITH(E_POW, pow(a.u.n, b.u.n))
#undef ARITH
#define COMPARE(OP, EXPR) \
  case OP: \
    a = ev_expr(ev, e->a, env); \
    b = ev_expr(ev, e->b, env); \
    if (LIKELY(a.kind == V_NUM && b.kind == V_NUM)) return val_bool(EXPR); \
    return compare(ev, OP, a, b, e);
  COMPARE(E_LT, a.u.n < b.u.n)
  COMPARE(E_LE, a.u.n <= b.u.n)
  COMPARE(E_GT, a.u.n > b.u.n)
  COMPARE(E_GE, a.u.n >= b.u.n)
#undef COMPARE
  case E_EQ: case E_NE:
    a = ev_expr(ev, e->a, env);
    b = ev_expr(ev, e->b, env);
    if (a.kind == V_ERR || b.kind == V_ERR) return val_err();
    if (a.kind == V_LIST && b.kind == V_LIST && a.u.l->n == b.u.l->n &&
        ev_steps(ev, a.u.l->n, e->range, "comparing lists with `==`"))
      return val_err();
    return val_bool(val_equal(&a, &b) == (e->op == E_EQ));
  case E_AND: case E_OR:
    a = ev_expr(ev, e->a, env);
    if (a.kind == V_ERR) return a;
    if (val_truthy(&a) == (e->op == E_OR)) return val_bool(e->op == E_OR);
    b = ev_expr(ev, e->b, env);
    return b.kind == V_ERR ? b : val_bool(val_truthy(&b));
  case E_TERNARY:
    a = ev_expr(ev, e->a, env);
    if (a.kind == V_ERR) return a;
    return ev_expr(ev, val_truthy(&a) ? e->b : e->c, env);
  case E_CALL: return call_value(ev, ev_expr(ev, e->a, env), e, env);
  case E_INDEX: return index_value(ev, ev_expr(ev, e->a, env), ev_expr(ev, e->b, env), e);
  case E_MEMBER: return member_value(ev, ev_expr(ev, e->a, env), e);
  case E_LET: return let_value(ev, e, env);
  case E_FN: {
    Closure *c = ev_alloc(ev, sizeof *c);
    c->def = e->def;
    c->env = env;
    return val_ptr(V_FUNC, c);
  }
  case E_SYMCALL: return symcall_value(ev, e, env);
  case E_COMP_FOR: case E_COMP_IF: case E_COMP_EACH: case E_COMP_LET:
    ev_error(ev, e->range, "`for`, `if`, `each` and `let` of this kind belong inside a list `[...]`");
    return val_err();
  default:
    ev_error(ev, e->range, "a statement cannot be used as a value");
    return val_err();
  }
}

/* ---- statements ------------------------------------------------------- */

static int exec(Eval *ev, const ENode *e, Env *env);

static void blockval_free(BlockVal *b) {
  for (int i = 0; i < b->nsubs; i++) blockval_free(b->subs[i]);
  free(b->subs);
  free(b->props);
  free(b);
}

static void col_add_prop(BlockVal *col, const char *name, int n, Value *v, SrcRange *vloc, SrcRange loc) {
  col->props = xgrow(col->props, &col->capprops, col->nprops + 1, sizeof *col->props);
  Prop *p = &col->props[col->nprops++];
  p->name = name;
  p->n = n;
  p->v = v;
  p->vloc = vloc;
  p->loc = loc;
}

static int exec_prop(Eval *ev, const ENode *e, Env *env) {
  if (!ev->col) {
    ev_error(ev, e->range, "`%s` is not a statement here; properties belong inside a block", e->name);
    return -1;
  }
  Value *v = ev_alloc(ev, (size_t)(e->n + 1) * sizeof *v);
  SrcRange *loc = ev_alloc(ev, (size_t)(e->n + 1) * sizeof *loc);
  for (int i = 0; i < e->n; i++) {
    v[i] = ev_expr(ev, e->kids[i], env);
    loc[i] = e->kids[i]->range;
    if (v[i].kind == V_ERR) return -1;
  }
  col_add_prop(ev->col, e->name, e->n, v, loc, e->range);
  return 0;
}

static int exec_block(Eval *ev, const ENode *e, Env *env) {
  BlockVal *b = xcalloc(1, sizeof *b);
  b->kind = e->name;
  b->nwords = e->nwords;
  b->words = e->words;
  b->wordloc = e->wordloc;
  b->loc = e->range;
  BlockVal *outer = ev->col;
  ev->col = b;
  int r = ev_body(ev, e->body, env);
  ev->col = outer;
  /* a style is made at once (even inside an object), so it can be named */
  if (!outer || strcmp(b->kind, "style") == 0) {
    int idx = r == 0 ? schema_emit(ev, b) : -1;
    blockval_free(b);
    Value sv = val_err();
    if (idx >= 0) { sv.kind = V_STYLE; sv.aux = idx; }
    if (e->slot >= 0) env->v[e->slot] = sv;
    if (outer && idx >= 0 && e->slot < 0) {   /* object { style { ... } }: as `style <it>;` */
      Value *v = ev_alloc(ev, sizeof *v);
      SrcRange *loc = ev_alloc(ev, sizeof *loc);
      *v = sv;
      *loc = e->range;
      col_add_prop(outer, ev_intern(ev, "style"), 1, v, loc, e->range);
    }
    return r;
  }
  outer->subs = xgrow(outer->subs, &outer->capsubs, outer->nsubs + 1, sizeof *outer->subs);
  outer->subs[outer->nsubs++] = b;
  return r;
}

static int exec_for(Eval *ev, const ENode *e, Env *fe, int k, Env *env) {
  if (k == e->n) {
    Env local;
    int mark;
    Env *be = env_open(ev, e->scope, env, &local, &mark, e->range);
    if (!be) return -1;
    memcpy(be->v, fe->v, (size_t)e->n * sizeof(Value));
    int r = ev_body(ev, e->body, be);
    env_close(ev, mark);
    return r;
  }
  Iter it;
  if (iter_init(ev, ev_expr(ev, e->kids[k], fe), &it, e->kids[k]->range, "a `for` loop")) return -1;
  int r = 0;
  for (long long i = 0; i < it.n; i++) {
    if (count_step(ev, e->range, "this `for` loop")) return -1;
    fe->v[k] = iter_get(&it, i);
    r |= exec_for(ev, e, fe, k + 1, env);
    if (ev->stop) return -1;
  }
  return r;
}

static int exec_for_stmt(Eval *ev, const ENode *e, Env *env) {
  Env local;
  int mark;
  Env *fe = env_open(ev, e->scope, env, &local, &mark, e->range);
  int r = fe ? exec_for(ev, e, fe, 0, env) : -1;
  env_close(ev, mark);
  return r;
}

static int call_module(Eval *ev, const Closure *m, const ENode *s, Env *env) {
  const FnDef *d = m->def;
  const ENode *call = s->a;
  Env local;
  int mark;
  Env *fe = env_open(ev, d->scope, m->env, &local, &mark, call->range);
  int r = -1;
  if (fe && bind_args(ev, d, call, env, fe) == 0 && guard_depth(ev, d->name, 1, call->range) == 0) {
    if (!count_call(ev, call->range, d) && bind_defaults(ev, d, fe) == 0) {
      ChildCtx ctx = {s->body, env, ev->children, call->range};
      const ChildCtx *saved = ev->children;
      ev->children = &ctx;
      r = ev_body(ev, d->mbody, fe);
      ev->children = saved;
    }
    ev->depth--;
  }
  env_close(ev, mark);
  return r;
}

/* ---- statements that make shapes ---------------------------------------- */

/* The name a call statement calls, for messages. */
static const char *call_name(const ENode *s) { return s->a->what ? s->a->what : "this"; }

/* A statement that makes a shape (`cube(1);`, a CSG block) belongs where
** objects are made, not inside another block. */
static int shape_here(Eval *ev, const ENode *s) {
  if (!ev->col) return 1;
  ev_error(ev, s->a->range, "`%s` makes an object of its own, so it cannot stand inside `%s`; "
           "write it outside, or `geometry %s(…);` inside an object", call_name(s), ev->col->kind, call_name(s));
  return 0;
}

/* Run a call statement's children with m added to the enclosing transforms
** (`translate(v) cube(1);`). */
static int exec_transformed(Eval *ev, Mat4 m, const ENode *s, Env *env) {
  Mat4 saved = ev->xform;
  ev->xform = m4_mul(saved, m);
  int r = ev_body(ev, s->body, env);
  ev->xform = saved;
  return r;
}

/* Run a call statement's children in its own frame and take back the
** objects they made, in order (a malloc'd copy in *out). */
static int collect_objects(Eval *ev, const ENode *s, Env *env, SceneObject **out, int *n) {
  Scene *sc = ev->scene;
  int mark = sc->nobjects, omark = sc->norigami;
  Mat4 saved = ev->xform;
  ev->xform = m4_identity();
  int r = ev_body(ev, s->body, env);
  ev->xform = saved;
  *n = sc->nobjects - mark;
  *out = xmalloc((size_t)(*n ? *n : 1) * sizeof **out);
  if (*n) memcpy(*out, sc->objects + mark, (size_t)*n * sizeof **out);
  sc->nobjects = mark;
  if (sc->norigami > omark) {
    ev_error(ev, sc->origami[omark].loc, "`%s` combines shapes; an origami cannot be one of them", call_name(s));
    sc->norigami = omark;
    r = -1;
  }
  return r;
}

/* A builtin whose call statement takes the shapes its children make
** (`difference() { ... }`): each child's geometry moved by its transform,
** the builtin's result made an object with the first child's style. */
static int exec_shape_children(Eval *ev, const Builtin *bi, const ENode *s, Env *env) {
  SceneObject *kids;
  int nk;
  if (collect_objects(ev, s, env, &kids, &nk)) { free(kids); return -1; }
  Value *geoms = xmalloc((size_t)(nk ? nk : 1) * sizeof *geoms);
  for (int i = 0; i < nk; i++) {
    SceneGeometry *g = shape_transformed(&ev->scene->arena, kids[i].geometry, kids[i].transform);
    g->loc = kids[i].loc;
    g->tess_n = kids[i].tess_kind == TESS_UNIFORM ? kids[i].tess_n : 0;
    geoms[i] = val_ptr(V_GEOM, g);
  }
  Value r = call_builtin(ev, bi, s->a, env, geoms, nk);
  free(geoms);
  if (r.kind == V_GEOM) {
    SceneObject like = nk ? kids[0] : (SceneObject){0};
    if (nk && like.has_centre) like.centre = m4_point(kids[0].transform, like.centre);
    schema_emit_object(ev, nk ? &like : NULL, r.u.g, ev->xform, s->range);
  }
  free(kids);
  return r.kind == V_ERR ? -1 : 0;
}

/* A function's call statement: a shape is drawn (`cube(1);`), a transform
** moves the children (`translate(v) { ... }`). */
static int exec_function_call(Eval *ev, Value f, const ENode *s, Env *env) {
  const Builtin *bi = f.u.f->def ? NULL : f.u.f->bi;
  if (bi && s->body && (bi->kind == BI_CHILDREN_ARGS || bi->kind == BI_CHILDREN_FIRST))
    return shape_here(ev, s) ? exec_shape_children(ev, bi, s, env) : -1;
  Value r = call_value(ev, f, s->a, env);
  if (r.kind == V_ERR) return -1;
  if (r.kind == V_XFORM && s->body) return exec_transformed(ev, *r.u.m, s, env);
  if (r.kind == V_GEOM && !s->body) {
    if (!shape_here(ev, s)) return -1;
    schema_emit_object(ev, NULL, r.u.g, ev->xform, s->range);
    return 0;
  }
  if (r.kind == V_GEOM)
    ev_error(ev, s->body->n ? s->body->items[0]->range : s->a->range,
             "`%s` makes a shape, which takes no children; end it with `;`", call_name(s));
  else if (r.kind == V_XFORM)
    ev_error(ev, s->a->range, "`%s` makes a transform; as a statement it moves what follows it: `%s(…) cube(1);`",
             call_name(s), call_name(s));
  else {
    char hint[600];
    habit_hint(HABIT_MODULE, s->a->what, NULL, hint, sizeof hint);
    ev_error(ev, s->a->range, "a statement calls a module, or a function that makes a shape or a transform; "
             "`%s` gives %s%s", call_name(s), a_type(&r), hint);
  }
  return -1;
}

static int exec_call(Eval *ev, const ENode *s, Env *env) {
  Value f = ev_expr(ev, s->a->a, env);
  if (f.kind == V_ERR) return -1;
  if (f.kind == V_MODULE) return call_module(ev, f.u.f, s, env);
  if (f.kind == V_FUNC && !f.u.f->def && f.u.f->bi->kind == BI_STATEMENT) {
    Value r = call_builtin(ev, f.u.f->bi, s->a, env, NULL, 0);
    return r.kind == V_ERR ? -1 : 0;
  }
  if (f.kind == V_FUNC) return exec_function_call(ev, f, s, env);
  char hint[600];
  habit_hint(HABIT_MODULE, s->a->what, NULL, hint, sizeof hint);
  ev_error(ev, s->a->range, "a statement can only call a module; `%s` is %s%s", call_name(s), a_type(&f), hint);
  return -1;
}

/* Run the children of the module call being executed (children();), or
** only child i. Each child runs in the caller's environment. Outside any
** module call (at top level, or in a top-level call's own children) there
** are none: a warning at `at`, once, since it draws nothing. */
int ev_children(Eval *ev, int only, SrcRange at) {
  const ChildCtx *ctx = ev->children;
  if (!ctx && !ev->warned_children++)
    diag_warning(at, "`children()` is not inside a module's body: there are no children to run, so it does nothing");
  if (!ctx || !ctx->body) return 0;
  const ChildCtx *saved = ev->children;
  ev->children = ctx->outer;
  int r;
  if (only < 0) r = ev_body(ev, ctx->body, ctx->env);
  else {
    Body one = *ctx->body;
    int k = 0;
    r = 0;
    for (int i = 0; i < ctx->body->n; i++) {
      EOp op = ctx->body->items[i]->op;
      if (op == S_LET || op == S_NOP || op == S_USE) continue;
      if (k++ == only) {
        one.items = &ctx->body->items[i];
        one.n = 1;
        r = ev_body(ev, &one, ctx->env);
      }
    }
  }
  ev->children = saved;
  return r;
}

static int exec(Eval *ev, const ENode *e, Env *env) {
  switch (e->op) {
  case S_LET:
    env->v[e->slot] = ev_expr(ev, e->a, env);
    return env->v[e->slot].kind == V_ERR ? -1 : 0;
  case S_CALL: return exec_call(ev, e, env);
  case S_FOR: return exec_for_stmt(ev, e, env);
  case S_IF: {
    Value c = ev_expr(ev, e->a, env);
    if (c.kind == V_ERR) return -1;
    if (val_truthy(&c)) return ev_body(ev, e->body, env);
    return e->body2 ? ev_body(ev, e->body2, env) : 0;
  }
  case S_BLOCK: return exec_block(ev, e, env);
  case S_PROP: return exec_prop(ev, e, env);
  default: return 0;
  }
}

/* Run a statement list; the first error does not stop the rest (their own
** errors are worth seeing), but a limit does. */
int ev_body(Eval *ev, const Body *b, Env *env) {
  Env local;
  int mark = ev->sp;
  Env *be = env;
  if (b->scope) {
    be = env_open(ev, b->scope, env, &local, &mark, b->n ? b->items[0]->range : src_none());
    if (!be) return -1;
  }
  int r = 0;
  for (int i = 0; i < b->n && !ev->stop && !diag_too_many(); i++)
    if (exec(ev, b->items[i], be)) r = -1;
  if (b->scope) env_close(ev, mark);
  return ev->stop ? -1 : r;
}

/* A used file runs its definitions only: lets, functions, styles. */
static void run_namespace(Eval *ev, Namespace *ns) {
  Env local;
  int mark;
  ns->scope->heap = 1;   /* the namespace's Env outlives this call */
  ns->env = env_open(ev, ns->scope, NULL, &local, &mark, src_none());
  for (int i = 0; i < ns->body->n && !ev->stop; i++) {
    const ENode *s = ns->body->items[i];
    if (s->op == S_LET || (s->op == S_BLOCK && s->slot >= 0)) exec(ev, s, ns->env);
  }
}

/* ---- the program ------------------------------------------------------ */

void eval_options_init(EvalOptions *opt) {
  memset(opt, 0, sizeof *opt);
  opt->max_recursion = EVAL_MAX_RECURSION;
  opt->max_iterations = EVAL_MAX_ITERATIONS;
  opt->max_list = EVAL_MAX_LIST;
  opt->max_memory = EVAL_MAX_MEMORY;
}

static void init_eval(Eval *ev, Arena *values, Arena *ast_arena, const EvalOptions *opt, Scene *out, int file) {
  memset(ev, 0, sizeof *ev);
  ev->arena = values;
  ev->ast_arena = ast_arena;
  ev->opt = opt;
  ev->scene = out;
  ev->main_file = file;
  ev->stack_cap = EVAL_VALUE_STACK;
  ev->stack = xmalloc((size_t)ev->stack_cap * sizeof(Value));
  int nb;
  const Builtin *bt = builtin_table(&nb);
  ev->bi_closures = xcalloc((size_t)nb, sizeof *ev->bi_closures);
  for (int i = 0; i < nb; i++) ev->bi_closures[i].bi = &bt[i];
  ev->sym_x = ev_intern(ev, "x"); ev->sym_y = ev_intern(ev, "y");
  ev->sym_z = ev_intern(ev, "z"); ev->sym_w = ev_intern(ev, "w");
  ev->sym_r = ev_intern(ev, "r"); ev->sym_g = ev_intern(ev, "g");
  ev->sym_b = ev_intern(ev, "b"); ev->sym_a = ev_intern(ev, "a");
  ev->xform = m4_identity();
}

static void free_eval(Eval *ev) {
  free(ev->stack);
  free(ev->scratch);
  for (int i = 0; i < ev->nowned; i++) free(ev->owned[i]);
  free(ev->owned);
  free(ev->calls);
  free(ev->intern);
  free(ev->bi_closures);
  for (int i = 0; i < ev->nincluded; i++) free(ev->included[i]);
  free(ev->included);
  free(ev->nss);
}

typedef struct EvalJob {
  AstNode *program;
  int file;
  Arena *ast_arena;
  const EvalOptions *opt;
  Scene *out;
  int result;
} EvalJob;

static void run_program(EvalJob *job, char *stack_base, size_t stack_size) {
  Arena values;
  arena_init(&values);
  Eval ev;
  init_eval(&ev, &values, job->ast_arena, job->opt, job->out, job->file);
  ev.cstack_base = stack_base;
  ev.cstack_size = stack_size;
  int before = diag_error_count();
  Body *b = compile_program(&ev, job->program, job->file);
  for (int i = 0; i < job->opt->ndefines; i++) compile_define(&ev, job->opt->defines[i], i);
  for (int i = 0; i < ev.nnss && !ev.stop; i++) run_namespace(&ev, ev.nss[i]);
  Env local;
  int mark;
  ev.genv = env_open(&ev, ev.global, NULL, &local, &mark, src_none());
  if (ev.genv && !diag_too_many()) ev_body(&ev, b, ev.genv);
  if (!ev.stop) schema_finish(&ev);
  job->out->clock = job->opt->clock;
  job->out->frame = job->opt->frame;
  job->result = diag_error_count() > before;
  free_eval(&ev);
  arena_free(&values);
}

static void *eval_thread(void *p) {
  char base;
  run_program(p, &base, EVAL_C_STACK);
  return NULL;
}

int eval_program(AstNode *program, int file, Arena *ast_arena, const EvalOptions *opt, Scene *out) {
  EvalJob job = {program, file, ast_arena, opt, out, 1};
  pthread_attr_t attr;
  pthread_t th;
  pthread_attr_init(&attr);
  pthread_attr_setstacksize(&attr, EVAL_C_STACK);
  if (pthread_create(&th, &attr, eval_thread, &job) != 0) {
    /* no thread (a tight ulimit): run here with a conservative stack guess */
    char base;
    EvalOptions small = *opt;
    if (small.max_recursion > 1000) small.max_recursion = 1000;
    job.opt = &small;
    run_program(&job, &base, 4u << 20);
  } else pthread_join(th, NULL);
  pthread_attr_destroy(&attr);
  return job.result;
}
