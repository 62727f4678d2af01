/*
** Evaluator internals shared by eval.c (running), eval_compile.c
** (resolving names to slots), builtins.c and schema.c. Nothing outside
** src/lang/eval*.c, builtins.c and schema.c includes this.
**
** Model: the compile pass turns the AST into ENodes. Every scope that
** declares names (a function's parameters, a let-expression, a loop, a
** block with lets) becomes a Scope with numbered slots; at run time each
** Scope has one Env (an array of slots and a link to the enclosing Env),
** and an identifier is (hops up, slot). Envs live on a value stack unless
** a closure can be made inside the scope (Scope.heap), then in the arena.
*/
#ifndef lang_eval_int_h
#define lang_eval_int_h

#include "ast.h"
#include "eval.h"
#include "value.h"

typedef struct ENode ENode;
typedef struct Scope Scope;
typedef struct FnDef FnDef;
typedef struct Eval Eval;
typedef struct Namespace Namespace;
typedef struct Builtin Builtin;

typedef struct Env {
  struct Env *up;
  Value *v;
} Env;

typedef enum { B_LET, B_FN, B_MODULE, B_STYLE, B_PARAM, B_LOOP, B_NAMESPACE } BindKind;

typedef struct Binding {
  const char *name;     /* interned */
  BindKind kind;
  SrcRange loc;
  int used;
  FnDef *def;           /* B_FN, B_MODULE */
  Namespace *ns;        /* B_NAMESPACE */
  ENode *let;           /* B_LET at top level: the statement (for -D) */
} Binding;

struct Scope {
  Scope *parent;
  Binding *b;
  int n;
  int heap;             /* a closure may capture this scope's Env */
  int is_global;
  int warn_unused;      /* declared in the main file: warn for unused lets */
  FnDef **defs;         /* hoisted fn/module definitions, made at Env entry */
  int *def_slot;
  int ndefs;
};

struct FnDef {
  const char *name;     /* NULL for a function literal */
  int is_module;
  int nparams;
  const char **pnames;  /* interned */
  ENode **defaults;     /* NULL entry: no default (undef) */
  Scope *scope;         /* parameters first, then (modules) the body's names */
  ENode *body;          /* function */
  struct Body *mbody;   /* module */
  SrcRange loc;
};

/* A list of statements, with its own Scope when it declares names. */
typedef struct Body {
  Scope *scope;
  ENode **items;
  int n;
} Body;

struct Closure {
  FnDef *def;           /* NULL for a builtin */
  Env *env;
  const Builtin *bi;
};

/* ORDER EOP: eval.c's switch handles each. */
typedef enum {
  E_CONST, E_LOCAL, E_NSREF, E_LIST, E_RANGE, E_NEG, E_NOT,
  E_ADD, E_SUB, E_MUL, E_DIV, E_MOD, E_POW, E_EQ, E_NE, E_LT, E_LE, E_GT, E_GE,
  E_AND, E_OR, E_TERNARY, E_CALL, E_INDEX, E_MEMBER, E_LET, E_FN, E_SYMCALL,
  E_COMP_FOR, E_COMP_IF, E_COMP_EACH, E_COMP_LET,
  S_LET, S_CALL, S_FOR, S_IF, S_BLOCK, S_PROP, S_USE, S_NOP
} EOp;

struct ENode {
  EOp op;
  int hops, slot, n;
  SrcRange range;
  Value k;                    /* E_CONST */
  ENode *a, *b, *c;
  ENode **kids;               /* elements, arguments, generators, values */
  const char **names;         /* E_CALL: argument names (NULL = positional) */
  const char *name;           /* member, property, block kind, let name */
  Scope *scope;               /* E_LET, E_COMP_FOR, E_COMP_LET, S_FOR */
  FnDef *def;                 /* E_FN */
  Body *body, *body2;         /* S_CALL children; S_FOR/S_IF/S_BLOCK bodies */
  Namespace *ns;              /* E_NSREF, S_USE */
  const char **words;         /* S_BLOCK: words after the kind */
  SrcRange *wordloc;
  int nwords;
  const char *what;           /* what a loop or call is, for limit messages */
  int simple;                 /* E_CALL: positional arguments only */
  SrcRange *argloc;           /* E_CALL: each argument as written (`name = value`) */
};

struct Namespace {
  const char *path;
  Scope *scope;
  Env *env;
  Body *body;
};

/* A property or block collected while a block's items run. */
typedef struct Prop {
  const char *name;
  int n;
  Value *v;
  SrcRange *vloc;
  SrcRange loc;
} Prop;

typedef struct BlockVal {
  const char *kind;
  int nwords;
  const char **words;
  SrcRange *wordloc;
  Prop *props;
  int nprops, capprops;
  struct BlockVal **subs;
  int nsubs, capsubs;
  SrcRange loc;
} BlockVal;

typedef struct CallRec { const char *name; int is_module; SrcRange site; } CallRec;

typedef struct ChildCtx {
  const Body *body;
  Env *env;
  const struct ChildCtx *outer;   /* the caller's own children */
  SrcRange site;
} ChildCtx;


struct Eval {
  Arena *arena;              /* values (the Scene's arena holds scene data) */
  Arena *ast_arena;
  Scene *scene;
  const EvalOptions *opt;
  int main_file;
  long long mem_used;
  Value *stack;              /* Envs that no closure captures */
  int sp, stack_cap;
  Value *scratch;            /* lists under construction */
  long long nscratch, capscratch;
  Value **owned;             /* scratch buffers that became lists; freed at the end */
  int nowned, capowned;
  long long iterations;
  int depth;
  CallRec *calls;
  int ncalls_cap;
  int stop;                  /* a limit was hit: unwind without more errors */
  SrcRange where;            /* the list or builtin call allocating, for the memory limit */
  const ChildCtx *children;
  int warned_children;       /* `children()` with no module call around it: said once */
  BlockVal *col;             /* the block collecting properties, NULL at top level */
  Mat4 xform;                /* what the enclosing transform statements do to the objects made
                                (`translate(v) object { ... }`); identity at the top */
  char *cstack_base;         /* for the C stack guard */
  size_t cstack_size;
  /* interned names */
  const char **intern;
  int nintern, capintern;
  /* included files (realpath) and namespaces */
  char **included;
  int nincluded, capincluded;
  Namespace **nss;
  int nnss, capnss;
  Closure *bi_closures;      /* one per builtin */
  Scope *global;
  Env *genv;
  const char *sym_x, *sym_y, *sym_z, *sym_r, *sym_g, *sym_b, *sym_a, *sym_w;
};

/* eval.c */
void *ev_alloc(Eval *ev, size_t n);          /* zeroed, counted against max_memory */
const char *ev_intern(Eval *ev, const char *s);
void ev_error(Eval *ev, SrcRange at, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
Value ev_str(Eval *ev, const char *s, int len);
List *ev_list(Eval *ev, int n);
Value ev_color(Eval *ev, double r, double g, double b, double a);
Value ev_xform(Eval *ev, Mat4 m);
int ev_list_limit(Eval *ev, double n, SrcRange at);
/* Count n steps of a builtin's inner loop (what: "`search`") against the
** iteration limit; nonzero (reported at `at`) when past it. */
int ev_steps(Eval *ev, double n, SrcRange at, const char *what);
/* Bytes a string or buffer made now may take: half the memory left (the
** buffer and the string it becomes), at most EVAL_MAX_STRING. */
size_t ev_text_room(Eval *ev);
/* Nonzero when n more bytes of a builtin's own buffer would pass the
** memory limit; then reported at `at` as what's (e.g. "`chr`"). */
int ev_buffer_limit(Eval *ev, double n, SrcRange at, const char *what);
/* An empty buffer for a builtin's text: at most ev_text_room bytes and
** the iterations left of work. */
StrBuf ev_text_buf(Eval *ev);
/* Count b's work toward the iteration limit; nonzero when b went past its
** room (b->over): reported at `at` as the iteration, memory or
** string-length limit, naming what (e.g. "`str`"). */
int ev_text_over(Eval *ev, const StrBuf *b, SrcRange at, const char *what);
Value ev_expr(Eval *ev, const ENode *e, Env *env);
int ev_body(Eval *ev, const Body *b, Env *env);

/* eval_compile.c */
Body *compile_program(Eval *ev, AstNode *program, int file);
ENode *compile_define(Eval *ev, const char *def, int index);
const char *suggest_name(const char *name, const char *const *cands, int n);

int ev_children(Eval *ev, int only, SrcRange at);

#endif
