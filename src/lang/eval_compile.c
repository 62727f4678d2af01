/*
** The compile pass of the evaluator: turns the AST into ENodes with every
** identifier resolved to (hops, slot), splices included files in, builds
** `use` namespaces, and reports static errors (unknown names, a let
** defined twice in one scope, a module used as a value). Written bottom-up:
** scopes and names first, then expressions, then statements.
*/
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "builtins.h"
#include "eval_int.h"
#include "habits.h"
#include "schema.h"
#include "parse.h"

typedef struct Compiler {
  Eval *ev;
  Scope *scope;
  int file;                   /* the file being compiled (includes search beside it) */
  const char *block_kind;     /* innermost literal block, for symbol-valued properties */
  const char *block_word;
  struct IncludeChain *chain; /* files being included, for cycle reports */
} Compiler;

/* Deepest chain of nested includes (a chain this long is surely a mistake,
** and each level costs C stack in the compiler). */
#define EVAL_MAX_INCLUDE_DEPTH 64

typedef struct IncludeChain {
  int files[EVAL_MAX_INCLUDE_DEPTH + 2];
  int n;
} IncludeChain;

static ENode *compile_expr(Compiler *c, AstNode *a);
static Body *compile_items(Compiler *c, AstList *items, Scope *scope, int force_scope);

/* ---- names ---------------------------------------------------------- */

/* Levenshtein distance, capped (names are short). */
static int edit_distance(const char *a, const char *b) {
  int la = (int)strlen(a), lb = (int)strlen(b);
  if (la > 40 || lb > 40) return 99;
  int d[41][41];
  for (int i = 0; i <= la; i++) d[i][0] = i;
  for (int j = 0; j <= lb; j++) d[0][j] = j;
  for (int i = 1; i <= la; i++)
    for (int j = 1; j <= lb; j++) {
      int best = d[i - 1][j - 1] + (a[i - 1] != b[j - 1]);
      if (d[i - 1][j] + 1 < best) best = d[i - 1][j] + 1;
      if (d[i][j - 1] + 1 < best) best = d[i][j - 1] + 1;
      d[i][j] = best;
    }
  return d[la][lb];
}

/* The candidate closest to name, or NULL when none is close enough to be
** a plausible typo (at most a third of the letters wrong). */
const char *suggest_name(const char *name, const char *const *cands, int n) {
  const char *best = NULL;
  int bestd = INT_MAX;
  int len = (int)strlen(name);
  int limit = len <= 3 ? 1 : len / 3 + 1;
  for (int i = 0; i < n; i++) {
    if (!cands[i] || strcmp(cands[i], name) == 0) continue;
    int d = edit_distance(name, cands[i]);
    if (d < bestd) { bestd = d; best = cands[i]; }
  }
  return bestd <= limit ? best : NULL;
}

/* Room for one more element in an arena array of n: doubles at powers of
** two (the old copy stays in the arena, freed with it). */
static void *arena_grow(Arena *a, void *items, int n, size_t elem) {
  if (n & (n - 1) || (n && n < 4)) return items;
  void *bigger = arena_alloc(a, (size_t)(n < 4 ? 4 : n * 2) * elem);
  if (n) memcpy(bigger, items, (size_t)n * elem);
  return bigger;
}

static Scope *scope_new(Compiler *c, Scope *parent) {
  Scope *s = arena_alloc(c->ev->ast_arena, sizeof *s);
  s->parent = parent;
  s->warn_unused = c->file == c->ev->main_file;
  return s;
}

static int scope_find(const Scope *s, const char *name) {
  for (int i = s->n - 1; i >= 0; i--)
    if (s->b[i].name == name) return i;
  return -1;
}

/* Add a binding; a second one of the same name in one scope is an error
** pointing at both. Returns the slot. */
static int scope_add(Compiler *c, Scope *s, const char *name, BindKind kind, SrcRange loc) {
  int old = scope_find(s, name);
  if (old >= 0 && (kind <= B_STYLE || kind == B_NAMESPACE)) {
    diag_error(loc, "`%s` is already defined in this scope", name);
    diag_note(s->b[old].loc, "`%s` was first defined here", name);
  }
  s->b = arena_grow(c->ev->ast_arena, s->b, s->n, sizeof *s->b);
  Binding *b = &s->b[s->n];
  memset(b, 0, sizeof *b);
  b->name = name;
  b->kind = kind;
  b->loc = loc;
  if (old >= 0) b->used = s->b[old].used = 1;   /* one message is enough */
  return s->n++;
}

/* Mark every scope from s outwards: a closure made here captures them. */
static void scope_mark_heap(Scope *s) {
  for (; s; s = s->parent) s->heap = 1;
}

static void collect_names(const Scope *s, const char ***out, int *n, int *cap) {
  for (; s; s = s->parent)
    for (int i = 0; i < s->n; i++) {
      *out = xgrow(*out, cap, *n + 1, sizeof **out);
      (*out)[(*n)++] = s->b[i].name;
    }
}

static void report_unknown(Compiler *c, const char *name, SrcRange at, const char *what) {
  const char **cands = NULL;
  int n = 0, cap = 0, nb;
  collect_names(c->scope, &cands, &n, &cap);
  const Builtin *bt = builtin_table(&nb);
  for (int i = 0; i < nb; i++) {
    cands = xgrow(cands, &cap, n + 1, sizeof *cands);
    cands[n++] = bt[i].name;
  }
  const char *s = suggest_name(name, cands, n);
  char hint[600];
  if (habit_hint(strcmp(what, "module") ? HABIT_NAME : HABIT_MODULE, name, c->ev->opt->stdlib_dir, hint,
                 sizeof hint))
    diag_error(at, "unknown %s `%s`%s", what, name, hint);
  else if (s) diag_error(at, "unknown %s `%s`; did you mean `%s`?", what, name, s);
  else diag_error(at, "unknown %s `%s`", what, name);
  free(cands);
}

/* ---- expressions ---------------------------------------------------- */

static ENode *enode(Compiler *c, EOp op, SrcRange r) {
  ENode *e = arena_alloc(c->ev->ast_arena, sizeof *e);
  e->op = op;
  e->range = r;
  return e;
}

static ENode *const_node(Compiler *c, Value v, SrcRange r) {
  ENode *e = enode(c, E_CONST, r);
  e->k = v;
  return e;
}

static ENode **kids_of(Compiler *c, int n) {
  return arena_alloc(c->ev->ast_arena, (size_t)(n ? n : 1) * sizeof(ENode *));
}

/* Constants that are not functions: PI and the animation clock. */
static int constant_value(Compiler *c, const char *name, Value *out) {
  if (strcmp(name, "PI") == 0) { *out = val_num(M_PI); return 1; }
  if (strcmp(name, "clock") == 0) { *out = val_num(c->ev->opt->clock); return 1; }
  if (strcmp(name, "frame") == 0) { *out = val_num(c->ev->opt->frame); return 1; }
  return 0;
}

/* Resolve a name: scopes inside out, then builtins and constants. */
static ENode *compile_ident(Compiler *c, const char *raw, SrcRange r, int want_module) {
  const char *name = ev_intern(c->ev, raw);
  int hops = 0;
  for (Scope *s = c->scope; s; s = s->parent, hops++) {
    int i = scope_find(s, name);
    if (i < 0) continue;
    Binding *b = &s->b[i];
    b->used = 1;
    if (b->kind == B_NAMESPACE) {
      diag_error(r, "`%s` is a namespace (from `use`), not a value; write `%s.name`", name, name);
      return const_node(c, val_err(), r);
    }
    if (b->kind == B_MODULE && !want_module) {
      diag_error(r, "`%s` is a module, not a value: call it as a statement", name);
      return const_node(c, val_err(), r);
    }
    ENode *e = enode(c, E_LOCAL, r);
    e->hops = hops;
    e->slot = i;
    e->name = name;
    return e;
  }
  int bi = builtin_index(name);
  if (bi >= 0) return const_node(c, val_ptr(V_FUNC, &c->ev->bi_closures[bi]), r);
  Value k;
  if (constant_value(c, name, &k)) return const_node(c, k, r);
  report_unknown(c, name, r, want_module ? "module" : "name");
  return const_node(c, val_err(), r);
}

static ENode *compile_member(Compiler *c, AstNode *a) {
  AstNode *base = a->a;
  if (base && base->kind == AST_IDENT) {
    const char *name = ev_intern(c->ev, base->name);
    for (Scope *s = c->scope; s; s = s->parent) {
      int i = scope_find(s, name);
      if (i < 0) continue;
      if (s->b[i].kind != B_NAMESPACE) break;
      s->b[i].used = 1;
      Namespace *ns = s->b[i].ns;
      const char *m = ev_intern(c->ev, a->name);
      int slot = ns ? scope_find(ns->scope, m) : -1;
      if (!ns) return const_node(c, val_err(), ast_range(a));
      if (slot < 0) {
        const char **cands = NULL;
        int n = 0, cap = 0;
        collect_names(ns->scope, &cands, &n, &cap);
        const char *sug = suggest_name(m, cands, n);
        if (sug) diag_error(ast_range(a), "`%s` has no `%s`; did you mean `%s`?", name, m, sug);
        else diag_error(ast_range(a), "`%s` has no `%s`", name, m);
        free(cands);
        return const_node(c, val_err(), ast_range(a));
      }
      ENode *e = enode(c, E_NSREF, ast_range(a));
      e->ns = ns;
      e->slot = slot;
      e->name = m;
      return e;
    }
  }
  ENode *e = enode(c, E_MEMBER, ast_range(a));
  e->a = compile_expr(c, base);
  e->name = ev_intern(c->ev, a->name);
  return e;
}

static ENode *compile_call(Compiler *c, AstNode *a, int want_module) {
  ENode *e = enode(c, E_CALL, ast_range(a));
  if (a->a && a->a->kind == AST_IDENT) e->a = compile_ident(c, a->a->name, ast_range(a->a), want_module);
  else e->a = compile_expr(c, a->a);
  e->n = a->list.count;
  e->kids = kids_of(c, e->n);
  e->names = arena_alloc(c->ev->ast_arena, (size_t)(e->n + 1) * sizeof *e->names);
  e->simple = 1;
  e->argloc = arena_alloc(c->ev->ast_arena, (size_t)(e->n + 1) * sizeof *e->argloc);
  for (int i = 0; i < e->n; i++) {
    AstNode *arg = a->list.items[i];
    e->argloc[i] = ast_range(arg);
    e->kids[i] = compile_expr(c, arg->kind == AST_ARG ? arg->a : arg);
    e->names[i] = arg->kind == AST_ARG && arg->name ? ev_intern(c->ev, arg->name) : NULL;
    if (e->names[i]) e->simple = 0;
  }
  if (a->a && a->a->kind == AST_IDENT) e->what = ev_intern(c->ev, a->a->name);
  return e;
}

/* Bindings of let/for/comprehensions: each sees the ones before it. */
static void compile_bindings(Compiler *c, AstList *l, ENode *e, BindKind kind) {
  e->n = l->count;
  e->kids = kids_of(c, e->n);
  for (int i = 0; i < l->count; i++) {
    AstNode *b = l->items[i];
    e->kids[i] = compile_expr(c, b->a);
    scope_add(c, c->scope, ev_intern(c->ev, b->name), kind, ast_range(b));
  }
}

static ENode *compile_scoped(Compiler *c, AstNode *a, EOp op, BindKind kind) {
  ENode *e = enode(c, op, ast_range(a));
  Scope *saved = c->scope;
  c->scope = e->scope = scope_new(c, saved);
  compile_bindings(c, &a->list, e, kind);
  e->a = compile_expr(c, a->a);
  c->scope = saved;
  if (op == E_COMP_FOR) e->what = "comprehension";
  return e;
}

static FnDef *fn_new(Compiler *c, const char *name, AstList *params, SrcRange loc) {
  FnDef *d = arena_alloc(c->ev->ast_arena, sizeof *d);
  d->name = name ? ev_intern(c->ev, name) : NULL;
  d->nparams = params->count;
  d->pnames = arena_alloc(c->ev->ast_arena, (size_t)(d->nparams + 1) * sizeof *d->pnames);
  d->defaults = kids_of(c, d->nparams);
  d->loc = loc;
  return d;
}

/* Parameters go first in the function's scope; a default sees the
** parameters before it. */
static void compile_params(Compiler *c, FnDef *d, AstList *params) {
  for (int i = 0; i < params->count; i++) {
    AstNode *p = params->items[i];
    d->pnames[i] = ev_intern(c->ev, p->name);
    d->defaults[i] = p->a ? compile_expr(c, p->a) : NULL;
    scope_add(c, d->scope, d->pnames[i], B_PARAM, ast_range(p));
    d->scope->b[i].used = 1;   /* unused parameters are not worth a warning */
  }
}

static void compile_fn_body(Compiler *c, FnDef *d, AstNode *a) {
  Scope *saved = c->scope;
  c->scope = d->scope = scope_new(c, saved);
  compile_params(c, d, &a->list);
  if (a->kind == AST_MODULE_DEF) {
    const char *bk = c->block_kind;
    c->block_kind = NULL;
    d->mbody = compile_items(c, &a->list2, d->scope, 0);
    c->block_kind = bk;
  } else d->body = compile_expr(c, a->a);
  c->scope = saved;
}

static ENode *compile_list(Compiler *c, AstNode *a) {
  ENode *e = enode(c, E_LIST, ast_range(a));
  e->n = a->list.count;
  e->kids = kids_of(c, e->n);
  for (int i = 0; i < e->n; i++) e->kids[i] = compile_expr(c, a->list.items[i]);
  return e;
}

/* A list of plain numbers, read back from its source (ast.h's AST_NUMBERS):
** the same E_LIST of constants as compile_list makes of number nodes. */
static ENode *compile_numbers(Compiler *c, AstNode *a) {
  ENode *e = enode(c, E_LIST, ast_range(a));
  e->n = a->count;
  e->kids = kids_of(c, e->n);
  AstNumber *nums = xmalloc((size_t)e->n * sizeof *nums);
  ast_numbers(a, nums);
  for (int i = 0; i < e->n; i++)
    e->kids[i] = const_node(c, val_num(nums[i].value), diag_range(a->file, nums[i].start, nums[i].end));
  free(nums);
  return e;
}

static const EOp binary_ops[TK_COUNT] = {
  [TK_PLUS] = E_ADD, [TK_MINUS] = E_SUB, [TK_STAR] = E_MUL, [TK_SLASH] = E_DIV,
  [TK_PERCENT] = E_MOD, [TK_CARET] = E_POW, [TK_EQ] = E_EQ, [TK_NE] = E_NE,
  [TK_LT] = E_LT, [TK_LE] = E_LE, [TK_GT] = E_GT, [TK_GE] = E_GE,
  [TK_AND] = E_AND, [TK_OR] = E_OR,
};

static ENode *compile_unary(Compiler *c, AstNode *a) {
  ENode *inner = compile_expr(c, a->a);
  if (a->op == TK_PLUS) return inner;
  ENode *e = enode(c, a->op == TK_NOT ? E_NOT : E_NEG, ast_range(a));
  e->a = inner;
  /* fold -literal, so negative constants cost nothing */
  if (e->op == E_NEG && inner->op == E_CONST && inner->k.kind == V_NUM)
    return const_node(c, val_num(-inner->k.u.n), ast_range(a));
  return e;
}

static ENode *compile_expr(Compiler *c, AstNode *a) {
  if (!a) return const_node(c, val_err(), src_none());
  ENode *e;
  switch (a->kind) {
  case AST_NUMBER: return const_node(c, val_num(a->number), ast_range(a));
  case AST_BOOL: return const_node(c, val_bool(a->number != 0), ast_range(a));
  case AST_UNDEF: return const_node(c, val_undef(), ast_range(a));
  case AST_STRING: return const_node(c, ev_str(c->ev, a->name, (int)strlen(a->name)), ast_range(a));
  case AST_COLOR:
    return const_node(c, ev_color(c->ev, val_srgb_to_linear(a->color[0]), val_srgb_to_linear(a->color[1]),
                                  val_srgb_to_linear(a->color[2]), a->color[3]), ast_range(a));
  case AST_IDENT: return compile_ident(c, a->name, ast_range(a), 0);
  case AST_LIST: return compile_list(c, a);
  case AST_NUMBERS: return compile_numbers(c, a);
  case AST_RANGE:
    e = enode(c, E_RANGE, ast_range(a));
    e->a = compile_expr(c, a->a);
    e->b = a->b ? compile_expr(c, a->b) : NULL;
    e->c = compile_expr(c, a->c);
    return e;
  case AST_UNARY: return compile_unary(c, a);
  case AST_BINARY:
    e = enode(c, binary_ops[a->op], ast_range(a));
    e->a = compile_expr(c, a->a);
    e->b = compile_expr(c, a->b);
    return e;
  case AST_TERNARY: case AST_COMP_IF:
    e = enode(c, a->kind == AST_TERNARY ? E_TERNARY : E_COMP_IF, ast_range(a));
    e->a = compile_expr(c, a->a);
    e->b = compile_expr(c, a->b);
    e->c = a->c ? compile_expr(c, a->c) : NULL;
    return e;
  case AST_CALL: return compile_call(c, a, 0);
  case AST_INDEX:
    e = enode(c, E_INDEX, ast_range(a));
    e->a = compile_expr(c, a->a);
    e->b = compile_expr(c, a->b);
    return e;
  case AST_MEMBER: return compile_member(c, a);
  case AST_LET_EXPR: return compile_scoped(c, a, E_LET, B_LET);
  case AST_COMP_FOR: return compile_scoped(c, a, E_COMP_FOR, B_LOOP);
  case AST_COMP_LET: return compile_scoped(c, a, E_COMP_LET, B_LET);
  case AST_COMP_EACH:
    e = enode(c, E_COMP_EACH, ast_range(a));
    e->a = compile_expr(c, a->a);
    return e;
  case AST_FN_EXPR:
    e = enode(c, E_FN, ast_range(a));
    scope_mark_heap(c->scope);
    e->def = fn_new(c, NULL, &a->list, ast_range(a));
    compile_fn_body(c, e->def, a);
    return e;
  default:
    diag_error(ast_range(a), "a %s cannot be used as a value", ast_kind_name(a->kind));
    return const_node(c, val_err(), ast_range(a));
  }
}

/* ---- includes and use ----------------------------------------------- */

/* Anything at path ends the search: what is not a file readable as a
** scene is then reported as what it is (diag_load_file checks it). */
static int is_file(const char *path) {
  struct stat st;
  return stat(path, &st) == 0;
}

/* The folder part of path ("" for a bare name), with a trailing slash. */
static void dir_of(const char *path, char *out, size_t n) {
  const char *slash = strrchr(path, '/');
  size_t len = slash ? (size_t)(slash - path + 1) : 0;
  if (len >= n) len = n - 1;
  memcpy(out, path, len);
  out[len] = 0;
}

static int try_dir(const char *dir, const char *name, char *out, size_t n) {
  if (!dir || !*dir) snprintf(out, n, "%s", name);
  else snprintf(out, n, "%s%s%s", dir, dir[strlen(dir) - 1] == '/' ? "" : "/", name);
  return is_file(out);
}

/* Search: the including file's folder, -I folders, SUMI_PATH, stdlib. */
static int find_include(Compiler *c, const char *name, char *out, size_t n) {
  if (name[0] == '/') { snprintf(out, n, "%s", name); return is_file(out); }
  char dir[4096];
  dir_of(diag_file(c->file)->name, dir, sizeof dir);
  if (try_dir(dir, name, out, n)) return 1;
  const EvalOptions *o = c->ev->opt;
  for (int i = 0; i < o->ninclude_dirs; i++)
    if (try_dir(o->include_dirs[i], name, out, n)) return 1;
  const char *sp = getenv("SUMI_PATH");
  while (sp && *sp) {
    const char *colon = strchr(sp, ':');
    size_t len = colon ? (size_t)(colon - sp) : strlen(sp);
    if (len && len < sizeof dir) {
      memcpy(dir, sp, len);
      dir[len] = 0;
      if (try_dir(dir, name, out, n)) return 1;
    }
    sp = colon ? colon + 1 : NULL;
  }
  return o->stdlib_dir && try_dir(o->stdlib_dir, name, out, n);
}

static int already_included(Eval *ev, const char *real) {
  for (int i = 0; i < ev->nincluded; i++)
    if (strcmp(ev->included[i], real) == 0) return 1;
  return 0;
}

/* An include that would re-enter a file on the current chain (the
** includers and the current file): report the chain. */
static int include_cycle(Compiler *c, const char *real, SrcRange at) {
  int chain[EVAL_MAX_INCLUDE_DEPTH + 3], n = c->chain->n;
  memcpy(chain, c->chain->files, (size_t)n * sizeof *chain);
  chain[n++] = c->file;
  for (int i = 0; i < n; i++) {
    char r2[PATH_MAX];
    if (!realpath(diag_file(chain[i])->name, r2) || strcmp(r2, real) != 0) continue;
    diag_error(at, "include cycle: `%s` is already being included", diag_file(chain[i])->name);
    for (int j = i; j < n; j++) {
      const SrcFile *f = diag_file(chain[j]);
      const char *next = j + 1 < n ? diag_file(chain[j + 1])->name : diag_file(chain[i])->name;
      diag_note(src_none(), "`%s` includes `%s`", f->name, next);
    }
    return 1;
  }
  return 0;
}

/* Load and parse an include/use target; -1 (reported) when it cannot be. */
static int load_source(Compiler *c, AstNode *a, char *real, AstNode **prog) {
  char path[4096];
  if (!find_include(c, a->name, path, sizeof path)) {
    diag_error(ast_range(a), "cannot find `%s` (searched beside the file, -I folders, SUMI_PATH and the stdlib)", a->name);
    return -1;
  }
  if (!realpath(path, real)) snprintf(real, PATH_MAX, "%s", path);
  if (include_cycle(c, real, ast_range(a))) return -1;
  if (a->kind == AST_INCLUDE && already_included(c->ev, real)) return -2;
  if (c->chain->n >= EVAL_MAX_INCLUDE_DEPTH) {
    diag_error(ast_range(a), "includes nested deeper than %d files", EVAL_MAX_INCLUDE_DEPTH);
    return -1;
  }
  const char *why = NULL;
  int f = diag_load_file(path, c->file, ast_range(a), &why);
  if (f < 0) {
    diag_error(ast_range(a), "cannot read `%s`: %s", path, why ? why : "unknown error");
    return -1;
  }
  *prog = parse_file(f, c->ev->ast_arena);
  return f;
}

static void remember_included(Eval *ev, const char *real) {
  ev->included = xgrow(ev->included, &ev->capincluded, ev->nincluded + 1, sizeof *ev->included);
  ev->included[ev->nincluded++] = xstrdup(real);
}

/* A `use`d file compiles in a global scope of its own; the same file used
** twice shares one namespace. */
static Namespace *compile_namespace(Compiler *c, AstNode *a) {
  char real[PATH_MAX];
  AstNode *prog = NULL;
  char path[4096];
  if (find_include(c, a->name, path, sizeof path) && realpath(path, real))
    for (int i = 0; i < c->ev->nnss; i++)
      if (strcmp(c->ev->nss[i]->path, real) == 0) return c->ev->nss[i];
  int f = load_source(c, a, real, &prog);
  if (f < 0) return NULL;
  Namespace *ns = arena_alloc(c->ev->ast_arena, sizeof *ns);
  ns->path = arena_strndup(c->ev->ast_arena, real, strlen(real));
  Compiler sub = *c;
  sub.file = f;
  sub.scope = NULL;
  sub.block_kind = NULL;
  c->chain->files[c->chain->n++] = c->file;
  ns->scope = scope_new(&sub, NULL);
  ns->scope->is_global = 1;
  ns->scope->warn_unused = 0;
  ns->body = compile_items(&sub, &prog->list, ns->scope, 1);
  c->chain->n--;
  ns->env = arena_alloc(c->ev->arena, sizeof *ns->env);
  c->ev->nss = xgrow(c->ev->nss, &c->ev->capnss, c->ev->nnss + 1, sizeof *c->ev->nss);
  c->ev->nss[c->ev->nnss++] = ns;
  return ns;
}

/* ---- statements ----------------------------------------------------- */

/* A statement list with its includes spliced in (in order), each item
** tagged with the file it came from. */
typedef struct Flat {
  AstNode **items;
  int *file;
  int n, cap;
} Flat;

static void flat_push(Flat *f, AstNode *a, int file) {
  int cap = f->cap;
  f->items = xgrow(f->items, &cap, f->n + 1, sizeof *f->items);
  f->file = xgrow(f->file, &f->cap, f->n + 1, sizeof *f->file);
  f->items[f->n] = a;
  f->file[f->n++] = file;
}

static void flatten(Compiler *c, AstList *items, Flat *out) {
  for (int i = 0; i < items->count; i++) {
    AstNode *a = items->items[i];
    if (!a) continue;
    if (a->kind != AST_INCLUDE) { flat_push(out, a, c->file); continue; }
    char real[PATH_MAX];
    AstNode *prog = NULL;
    int f = load_source(c, a, real, &prog);
    if (f < 0) continue;
    remember_included(c->ev, real);
    int saved = c->file;
    c->chain->files[c->chain->n++] = saved;
    c->file = f;
    flatten(c, &prog->list, out);
    c->file = saved;
    c->chain->n--;
  }
}

static int declares(const AstNode *a) {
  switch (a->kind) {
  case AST_LET: case AST_FN_DEF: case AST_MODULE_DEF: case AST_USE: return 1;
  case AST_BLOCK: return a->list2.count > 0 && strcmp(a->name, "style") == 0;
  default: return 0;
  }
}

static void add_def(Arena *a, Scope *s, FnDef *d, int slot) {
  s->defs = arena_grow(a, s->defs, s->ndefs, sizeof *s->defs);
  s->def_slot = arena_grow(a, s->def_slot, s->ndefs, sizeof *s->def_slot);
  s->defs[s->ndefs] = d;
  s->def_slot[s->ndefs++] = slot;
}

/* Declare what a statement defines (before any statement compiles, so
** functions and modules are visible throughout their scope). */
static void declare(Compiler *c, Scope *s, AstNode *a, ENode **slot_of, FnDef **def) {
  const char *name;
  int slot;
  switch (a->kind) {
  case AST_LET:
    slot = scope_add(c, s, ev_intern(c->ev, a->name), B_LET, ast_range(a));
    *slot_of = enode(c, S_LET, ast_range(a));
    (*slot_of)->slot = slot;
    (*slot_of)->name = s->b[slot].name;
    s->b[slot].let = *slot_of;
    break;
  case AST_FN_DEF: case AST_MODULE_DEF: {
    int is_mod = a->kind == AST_MODULE_DEF;
    name = ev_intern(c->ev, a->name);
    if (builtin_index(name) >= 0)
      diag_warning(ast_range(a), "%s `%s` shadows the builtin of the same name", is_mod ? "module" : "function", name);
    slot = scope_add(c, s, name, is_mod ? B_MODULE : B_FN, ast_range(a));
    FnDef *d = fn_new(c, a->name, &a->list, ast_range(a));
    d->is_module = is_mod;
    s->b[slot].def = d;
    *def = d;
    add_def(c->ev->ast_arena, s, d, slot);
    if (!s->is_global) scope_mark_heap(s);
    break;
  }
  case AST_USE:
    if (!a->a) break;
    slot = scope_add(c, s, ev_intern(c->ev, a->a->name), B_NAMESPACE, ast_range(a->a));
    s->b[slot].ns = compile_namespace(c, a);
    break;
  case AST_BLOCK:
    if (!declares(a)) break;
    slot = scope_add(c, s, ev_intern(c->ev, a->list2.items[0]->name), B_STYLE, ast_range(a->list2.items[0]));
    *slot_of = enode(c, S_BLOCK, ast_range(a));
    (*slot_of)->slot = slot;
    break;
  default: break;
  }
}

static ENode *compile_item(Compiler *c, AstNode *a, ENode *pre);

static Body *body_of(Compiler *c, AstList *items) {
  return compile_items(c, items, NULL, 0);
}

static ENode *compile_for(Compiler *c, AstNode *a) {
  ENode *e = enode(c, S_FOR, ast_range(a));
  Scope *saved = c->scope;
  c->scope = e->scope = scope_new(c, saved);
  compile_bindings(c, &a->list, e, B_LOOP);
  e->body = compile_items(c, &a->list2, e->scope, 1);
  c->scope = saved;
  e->what = "for loop";
  return e;
}

/* Whether name (interned) is, where c is, a value variable: a `let`, a
** parameter or a loop variable (not a function, module or style). */
static int is_variable(const Compiler *c, const char *name) {
  for (const Scope *s = c->scope; s; s = s->parent) {
    int i = scope_find(s, name);
    if (i >= 0) return s->b[i].kind == B_LET || s->b[i].kind == B_PARAM || s->b[i].kind == B_LOOP;
  }
  return 0;
}

/* A bare word in a property that takes words is a symbol, unless the
** property does not know the word and a variable has its name
** (schema_knows_word); word(args) is always a symbol. */
static int is_symbol_word(Compiler *c, const char *prop, const char *raw) {
  return schema_knows_word(c->block_kind, c->block_word, prop, raw) || !is_variable(c, ev_intern(c->ev, raw));
}

static ENode *compile_property(Compiler *c, AstNode *a) {
  ENode *e = enode(c, S_PROP, ast_range(a));
  e->name = ev_intern(c->ev, a->name);
  e->n = a->list.count;
  e->kids = kids_of(c, e->n);
  int sym = c->block_kind && schema_wants_symbol(c->block_kind, c->block_word, a->name);
  for (int i = 0; i < e->n; i++) {
    AstNode *v = a->list.items[i];
    if (sym && v->kind == AST_IDENT && is_symbol_word(c, a->name, v->name)) {
      Symbol *s = arena_alloc(c->ev->arena, sizeof *s);
      s->name = ev_intern(c->ev, v->name);
      e->kids[i] = const_node(c, val_ptr(V_SYMBOL, s), ast_range(v));
    } else if (sym && v->kind == AST_CALL && v->a && v->a->kind == AST_IDENT) {
      ENode *sc = enode(c, E_SYMCALL, ast_range(v));   /* crease(40): a symbol with arguments */
      sc->name = ev_intern(c->ev, v->a->name);
      sc->n = v->list.count;
      sc->kids = kids_of(c, sc->n);
      for (int j = 0; j < sc->n; j++) {
        AstNode *arg = v->list.items[j];
        sc->kids[j] = compile_expr(c, arg->kind == AST_ARG ? arg->a : arg);
      }
      e->kids[i] = sc;
    } else e->kids[i] = compile_expr(c, v);
  }
  return e;
}

static ENode *compile_block(Compiler *c, AstNode *a, ENode *pre) {
  ENode *e = pre ? pre : enode(c, S_BLOCK, ast_range(a));
  if (!pre) e->slot = -1;
  e->range = ast_range(a);
  e->name = ev_intern(c->ev, a->name);
  e->nwords = a->list2.count;
  e->words = arena_alloc(c->ev->ast_arena, (size_t)(e->nwords + 1) * sizeof *e->words);
  e->wordloc = arena_alloc(c->ev->ast_arena, (size_t)(e->nwords + 1) * sizeof *e->wordloc);
  for (int i = 0; i < e->nwords; i++) {
    e->words[i] = ev_intern(c->ev, a->list2.items[i]->name);
    e->wordloc[i] = ast_range(a->list2.items[i]);
  }
  const char *bk = c->block_kind, *bw = c->block_word;
  c->block_kind = e->name;
  c->block_word = e->nwords ? e->words[0] : NULL;
  e->body = body_of(c, &a->list);
  c->block_kind = bk;
  c->block_word = bw;
  return e;
}

static ENode *compile_call_stmt(Compiler *c, AstNode *a) {
  ENode *e = enode(c, S_CALL, ast_range(a));
  if (!a->a || a->a->kind != AST_CALL) {
    diag_error(ast_range(a), "expected a module call");
    return enode(c, S_NOP, ast_range(a));
  }
  e->a = compile_call(c, a->a, 1);
  e->body = a->has_body ? body_of(c, &a->list2) : NULL;
  return e;
}

static ENode *compile_item(Compiler *c, AstNode *a, ENode *pre) {
  ENode *e;
  switch (a->kind) {
  case AST_LET:
    pre->a = compile_expr(c, a->a);
    return pre;
  case AST_FN_DEF: case AST_MODULE_DEF: case AST_USE: {
    e = enode(c, a->kind == AST_USE ? S_USE : S_NOP, ast_range(a));
    if (a->kind == AST_USE) {
      int i = a->a ? scope_find(c->scope, ev_intern(c->ev, a->a->name)) : -1;
      e->ns = i >= 0 ? c->scope->b[i].ns : NULL;
    }
    return e;
  }
  case AST_FOR: return compile_for(c, a);
  case AST_IF:
    e = enode(c, S_IF, ast_range(a));
    e->a = compile_expr(c, a->a);
    e->body = body_of(c, &a->list);
    e->body2 = a->has_else ? body_of(c, &a->list2) : NULL;
    return e;
  case AST_BLOCK: return compile_block(c, a, pre);
  case AST_PROPERTY: return compile_property(c, a);
  case AST_CALL_STMT: return compile_call_stmt(c, a);
  default:
    diag_error(ast_range(a), "a %s cannot stand as a statement", ast_kind_name(a->kind));
    return enode(c, S_NOP, ast_range(a));
  }
}

/* Compile a statement list into a Body. scope: use this scope (a module's
** or loop's); else a new one is made when the list declares names (or
** force_scope). */
static Body *compile_items(Compiler *c, AstList *items, Scope *scope, int force_scope) {
  Flat f = {0};
  flatten(c, items, &f);
  Body *b = arena_alloc(c->ev->ast_arena, sizeof *b);
  int need = force_scope;
  for (int i = 0; i < f.n && !need; i++) need = declares(f.items[i]);
  Scope *saved = c->scope;
  if (scope) b->scope = NULL;   /* the caller's scope: its Env already exists */
  else if (need) b->scope = scope_new(c, saved);
  Scope *s = scope ? scope : b->scope;
  if (s) c->scope = s;
  ENode **pre = xcalloc((size_t)f.n + 1, sizeof *pre);
  FnDef **defs = xcalloc((size_t)f.n + 1, sizeof *defs);
  int saved_file = c->file;
  for (int i = 0; i < f.n; i++) {
    c->file = f.file[i];
    if (s) declare(c, s, f.items[i], &pre[i], &defs[i]);
  }
  for (int i = 0; i < f.n; i++) {   /* definitions compile after every name is known */
    c->file = f.file[i];
    if (defs[i]) compile_fn_body(c, defs[i], f.items[i]);
  }
  b->items = arena_alloc(c->ev->ast_arena, (size_t)(f.n + 1) * sizeof *b->items);
  for (int i = 0; i < f.n; i++) {
    c->file = f.file[i];
    b->items[b->n++] = compile_item(c, f.items[i], pre[i]);
  }
  c->file = saved_file;
  c->scope = saved;
  free(pre);
  free(defs);
  free(f.items);
  free(f.file);
  return b;
}

/* Unused lets written in the main file (not in included ones, whose
** names are there to be used or not), innermost scopes first. */
static void warn_unused(const Scope *s, int main_file) {
  if (!s || !s->warn_unused) return;
  for (int i = 0; i < s->n; i++) {
    const Binding *b = &s->b[i];
    if (b->used || b->kind != B_LET || b->name[0] == '_' || b->loc.file != main_file) continue;
    diag_warning(b->loc, "`%s` is defined but never used", b->name);
  }
}

/* Walk every scope reachable from a body to warn once per scope. */
static void warn_body(const Body *b, int main_file);
static void warn_def(const FnDef *d, int main_file) {
  if (!d || !d->scope) return;
  warn_unused(d->scope, main_file);
  if (d->mbody) warn_body(d->mbody, main_file);
}

static void warn_node(const ENode *e, int main_file) {
  if (!e) return;
  warn_unused(e->scope, main_file);
  if (e->op == E_FN) warn_def(e->def, main_file);
  warn_node(e->a, main_file);
  warn_node(e->b, main_file);
  warn_node(e->c, main_file);
  if (e->op != E_CONST)
    for (int i = 0; i < e->n && e->kids; i++) warn_node(e->kids[i], main_file);
  if (e->body) warn_body(e->body, main_file);
  if (e->body2) warn_body(e->body2, main_file);
}

static void warn_scope_defs(const Scope *s, int main_file) {
  for (int i = 0; s && i < s->ndefs; i++) {
    warn_def(s->defs[i], main_file);
    if (s->defs[i]->scope) warn_node(s->defs[i]->body, main_file);
  }
}

static void warn_body(const Body *b, int main_file) {
  warn_unused(b->scope, main_file);
  warn_scope_defs(b->scope, main_file);
  for (int i = 0; i < b->n; i++) warn_node(b->items[i], main_file);
}

Body *compile_program(Eval *ev, AstNode *program, int file) {
  IncludeChain chain = {.n = 0};
  Compiler c = {0};
  c.ev = ev;
  c.file = file;
  c.chain = &chain;
  Scope *g = scope_new(&c, NULL);
  g->is_global = 1;
  ev->global = g;
  Body *b = compile_items(&c, &program->list, g, 1);
  warn_body(b, file);
  warn_unused(g, file);
  warn_scope_defs(g, file);
  return b;
}

/* -D name=expr: compile expr in the global scope and make it the let's
** initialiser. index: which -D (for its pseudo file name). */
ENode *compile_define(Eval *ev, const char *def, int index) {
  const char *eq = strchr(def, '=');
  char name[256];
  size_t len = eq ? (size_t)(eq - def) : strlen(def);
  if (!eq || len == 0 || len >= sizeof name) {
    diag_error(src_none(), "bad -D `%s`: expected name=value", def);
    return NULL;
  }
  memcpy(name, def, len);
  name[len] = 0;
  const char *sym = ev_intern(ev, name);
  int slot = scope_find(ev->global, sym);
  if (slot < 0 || ev->global->b[slot].kind != B_LET) {
    diag_warning(src_none(), "-D %s: the program has no top-level `let %s` to override", name, name);
    return NULL;
  }
  char fname[300];
  snprintf(fname, sizeof fname, "-D %s", name);
  size_t n = strlen(eq + 1);
  char *text = xmalloc(n + 1);
  memcpy(text, eq + 1, n + 1);
  int f = diag_add_file(fname, text, n, -1, src_none());
  AstNode *ex = parse_expression_file(f, ev->ast_arena);
  if (!ex) return NULL;
  IncludeChain chain = {.n = 0};
  Compiler c = {0};
  c.ev = ev;
  c.file = f;
  c.chain = &chain;
  c.scope = ev->global;
  ENode *e = compile_expr(&c, ex);
  ev->global->b[slot].let->a = e;
  return e;
}
