/*
** The builtin functions and statement modules of the language (math in
** degrees, vectors, lists, strings, rands, transforms, colours, geometry
** constructors, fold_file, echo/assert/children). One table row each.
*/
#ifndef lang_builtins_h
#define lang_builtins_h

#include "eval_int.h"

typedef Value (*BuiltinFn)(Eval *ev, Value *args, int nargs, const ENode *call);

/* What a builtin is (Builtin.kind). A function's call statement with
** children (`difference() { ... }`, `linear_extrude(2) circle(1);`) runs
** them and hands the builtin the shapes they make, moved to the world. */
enum {
  BI_FUNCTION,               /* a function */
  BI_STATEMENT,              /* echo, assert, children: statements only */
  BI_CHILDREN_ARGS,          /* a function whose call statement's children are its arguments */
  BI_CHILDREN_FIRST,         /* ... whose children, as a list, are its first argument */
};

struct Builtin {
  const char *name;
  BuiltinFn fn;
  const char *params;        /* "a,b,c": the names named arguments match */
  int min_args, max_args;    /* max_args -1: any number, positional only */
  int kind;                  /* BI_FUNCTION ... */
};

/* Every builtin: this file's table, builtins_model.c's and builtins_2d.c's. */
const Builtin *builtin_table(int *n);
/* The modelling builtins (shapes, CSG, 2D, extrusion, text, transforms of
** builtins_model.c), which builtin_table adds to the rest. */
const Builtin *builtin_model_table(int *n);
/* The 2D builtins (circle, square, polygon, text, offset, the extrusions)
** of builtins_2d.c. */
const Builtin *builtin_2d_table(int *n);
int builtin_index(const char *name);          /* -1 when not a builtin */
int builtin_param(const Builtin *bi, const char *name);   /* -1 when unknown */
/* Nonzero for a builtin that reads no element of its arguments (len, is_*):
** the others' work counts toward the iteration limit. */
int builtin_constant_time(const Builtin *bi);

/* Argument helpers the builtin files share. Each reports its error at
** argument i of call (the call itself when the argument is missing) and
** returns -1; 0 on success. */
SrcRange bi_arg_loc(const ENode *call, int i);
const char *bi_name(const ENode *call);
int bi_type_error(Eval *ev, const ENode *call, int i, const char *want, const Value *v);
int bi_num(Eval *ev, Value *a, int i, const ENode *call, double *out);
int bi_opt_num(Eval *ev, Value *a, int i, const ENode *call, double def, double *out);
int bi_list(Eval *ev, Value *a, int i, const ENode *call, List **out);
int bi_vec3(Eval *ev, Value *a, int i, const ENode *call, Vec3 *out);
/* A list of finite points [x, y, z] into scene memory. */
int bi_points(Eval *ev, Value *a, int i, const ENode *call, Vec3 **out, int *n);
/* A geometry value in the scene's arena, located at the call. */
SceneGeometry *bi_geom_new(Eval *ev, GeomKind kind, const ENode *call);
/* Faces (lists of 3 or more indices into nverts points) into g. */
int bi_faces(Eval *ev, List *faces, int nverts, const ENode *call, int arg, SceneGeometry *g);

#endif
