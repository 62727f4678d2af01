/*
** The builtin functions and statement modules of the language (math in
** degrees, vectors, lists, strings, rands, transforms, colours, geometry
** constructors, fold_file, echo/assert/children). One table row each.
*/
#ifndef lang_builtins_h
#define lang_builtins_h

#include "eval_int.h"

typedef Value (*BuiltinFn)(Eval *ev, Value *args, int nargs, const ENode *call);

struct Builtin {
  const char *name;
  BuiltinFn fn;
  const char *params;        /* "a,b,c": the names named arguments match */
  int min_args, max_args;    /* max_args -1: any number, positional only */
  int is_module;             /* echo, assert, children: statements */
};

const Builtin *builtin_table(int *n);
int builtin_index(const char *name);          /* -1 when not a builtin */
int builtin_param(const Builtin *bi, const char *name);   /* -1 when unknown */

#endif
