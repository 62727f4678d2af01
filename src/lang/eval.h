/*
** The evaluator: runs a parsed program and fills a Scene. Identifiers are
** resolved to frame slots in a compile pass (eval_compile.c), so a call
** costs no string lookups; values live in an arena counted against a
** memory limit; every runaway (recursion, loops, lists, memory) stops at a
** named limit with a diagnostic naming the user's function or loop.
*/
#ifndef lang_eval_h
#define lang_eval_h

#include <stdio.h>

#include "../base/mem.h"
#include "../scene/scene.h"
#include "ast.h"

/* Default limits; each is changeable on the command line. */
#define EVAL_MAX_RECURSION 10000          /* nested user function/module calls (--max-recursion) */
#define EVAL_MAX_ITERATIONS 200000000LL   /* loop iterations and calls, in all (--max-iterations) */
#define EVAL_MAX_LIST 50000000            /* elements of one list (--max-list) */
#define EVAL_MAX_MEMORY (4096LL << 20)    /* bytes of values, in all (--max-memory-mb) */
#define EVAL_MAX_STRING 0x7ffffffe        /* bytes of one string: its length is an int */

typedef struct EvalOptions {
  const char **defines;       /* "name=expr" from -D, in order */
  int ndefines;
  const char **include_dirs;  /* -I folders, in order */
  int ninclude_dirs;
  const char *stdlib_dir;     /* searched last; NULL = none */
  double clock;               /* 0..1 over --frames */
  int frame;
  int max_recursion;
  long long max_iterations;
  long long max_list;
  long long max_memory;       /* bytes */
} EvalOptions;

/* Fill *opt with no defines, no folders, clock 0, frame 0, default limits. */
void eval_options_init(EvalOptions *opt);

/* Evaluate program (diag file `file`, parsed into ast_arena; included
** files are parsed into the same arena) into *out, which the caller has
** scene_init'ed. Returns 0 when no error was reported, nonzero otherwise
** (the diagnostics were printed through diag). */
int eval_program(AstNode *program, int file, Arena *ast_arena, const EvalOptions *opt, Scene *out);

/* Print the scene as stable text, one property a line (`sumi eval --scene`). */
void scene_print(const Scene *s, FILE *out);

#endif
