/*
** The abstract syntax tree. Nodes live in the parser's arena and each keeps
** its source range as byte offsets (ast_range gives lines and columns). One
** node struct serves every kind; the table below says which fields each kind
** uses (unused fields are zero/NULL).
**
**   kind            fields
**   --------------  ---------------------------------------------------------
**   AST_PROGRAM     list: statements / items
**   AST_NUMBER      number
**   AST_STRING      name: decoded text (NUL-terminated; escapes resolved)
**   AST_COLOR       color[0..3]: sRGB components in [0, 1] (alpha 1 unless given)
**   AST_BOOL        number: 1 or 0
**   AST_UNDEF       -
**   AST_IDENT       name
**   AST_LIST        list: elements (expressions or AST_COMP_* items)
**   AST_NUMBERS     count: a list of count plain numbers ([1, -2.5, 3]), the
**                   bulk of point data, kept as its source text: ast_numbers
**                   reads the numbers back. Printed as a list of numbers.
**   AST_RANGE       a: start, b: step (NULL if absent), c: end
**   AST_UNARY       op (TK_MINUS, TK_PLUS, TK_NOT), a
**   AST_BINARY      op (TK_PLUS … TK_GE, TK_AND, TK_OR), a, b
**   AST_TERNARY     a ? b : c
**   AST_CALL        a: callee expression, list: AST_ARG
**   AST_ARG         name: argument name or NULL (positional), a: value
**   AST_INDEX       a[b]
**   AST_MEMBER      a.name
**   AST_LET_EXPR    list: AST_BINDING, a: body
**   AST_FN_EXPR     list: AST_PARAM, a: body       (fn (x, y = 1) = x + y)
**   AST_BINDING     name = a                       (let, for, comprehension)
**   AST_PARAM       name [= a default]
**   AST_COMP_FOR    list: AST_BINDING (generators), a: element
**   AST_COMP_IF     a: condition, b: element, c: else-element or NULL
**   AST_COMP_EACH   a: expression spliced into the list
**   AST_COMP_LET    list: AST_BINDING, a: element
**   AST_INCLUDE     name: path string
**   AST_USE         name: path string, a: AST_IDENT prefix (the `as` name)
**   AST_LET         name = a;                      (statement)
**   AST_FN_DEF      name, list: AST_PARAM, a: body expression
**   AST_MODULE_DEF  name, list: AST_PARAM, list2: body items
**   AST_CALL_STMT   a: AST_CALL; list2: children items, has_body = 1 when
**                   written with `{ … }`   (echo(x); row(3); frame() { … })
**   AST_FOR         list: AST_BINDING, list2: body items
**   AST_IF          a: condition, list: then-items, list2: else-items,
**                   has_else = 1 when an else branch was written
**   AST_BLOCK       name: kind word; list2: AST_IDENT words after the kind
**                   (a name and/or sub-kinds); list: items
**   AST_PROPERTY    name, list: value expressions (possibly empty)
**
** Operators are stored as their TokenKind (lex.h).
*/
#ifndef lang_ast_h
#define lang_ast_h

#include <stdint.h>
#include <stdio.h>

#include "../base/mem.h"
#include "diag.h"
#include "lex.h"

/* ORDER AST: ast.c's ast_kind_names[] follows this list, and the kinds
** an expression can be come before AST_COMP_FOR (parse_list relies on it). */
#define AST_LIST_KINDS(X) \
  X(AST_PROGRAM, "program") X(AST_NUMBER, "number") X(AST_STRING, "string") \
  X(AST_COLOR, "color") X(AST_BOOL, "bool") X(AST_UNDEF, "undef") X(AST_IDENT, "ident") \
  X(AST_LIST, "list") X(AST_NUMBERS, "list") X(AST_RANGE, "range") X(AST_UNARY, "unary") \
  X(AST_BINARY, "binary") X(AST_TERNARY, "ternary") X(AST_CALL, "call") X(AST_ARG, "arg") \
  X(AST_INDEX, "index") X(AST_MEMBER, "member") X(AST_LET_EXPR, "let-expr") \
  X(AST_FN_EXPR, "fn-expr") X(AST_BINDING, "binding") X(AST_PARAM, "param") \
  X(AST_COMP_FOR, "comp-for") X(AST_COMP_IF, "comp-if") X(AST_COMP_EACH, "comp-each") \
  X(AST_COMP_LET, "comp-let") X(AST_INCLUDE, "include") X(AST_USE, "use") X(AST_LET, "let") \
  X(AST_FN_DEF, "fn") X(AST_MODULE_DEF, "module") X(AST_CALL_STMT, "call-stmt") \
  X(AST_FOR, "for") X(AST_IF, "if") X(AST_BLOCK, "block") X(AST_PROPERTY, "property")

#define AST_ENUM(name, text) name,
typedef enum { AST_LIST_KINDS(AST_ENUM) AST_KIND_COUNT } AstKind;
#undef AST_ENUM

typedef struct AstNode AstNode;

typedef struct AstList {
  AstNode **items;
  int count;
} AstList;

/* Each node is allocated only up to the last field its kind uses (ast.c's
** node_size), so a number costs 24 bytes, a list 48 and a list of numbers
** 24 in all (see make bench-parse). Read only the fields the table above
** gives for a node's kind: the others may lie past the node's end, and b, c
** share their place with list (no kind uses both). */
struct AstNode {
  unsigned char kind;           /* AstKind */
  unsigned char op;             /* TokenKind of an operator */
  unsigned char has_body, has_else;
  int file;                     /* diag file index */
  uint32_t start, end;          /* the source range as byte offsets */
  union {                       /* which one: the table above */
    const char *name;
    double number;
    const float *color;         /* 4 floats in the arena */
    int count;                  /* AST_NUMBERS */
  };
  /* interior nodes only */
  AstNode *a;
  union {
    struct { AstNode *b, *c; };
    AstList list;
  };
  AstList list2;
};

AstNode *ast_new(Arena *arena, AstKind kind, int file, uint32_t start, uint32_t end);
/* The node's source range in lines and columns. */
static inline SrcRange ast_range(const AstNode *n) { return diag_range(n->file, n->start, n->end); }

/* One number of an AST_NUMBERS list: its value and source range. */
typedef struct AstNumber {
  double value;
  uint32_t start, end;
} AstNumber;

/* Read the numbers of an AST_NUMBERS node back from its source into
** out[0 .. n->count). */
void ast_numbers(const AstNode *n, AstNumber *out);

const char *ast_kind_name(AstKind k);
/* Print the tree as stable, indented text (the parser snapshot format). */
void ast_print(const AstNode *node, FILE *out);

#endif
