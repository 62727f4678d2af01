/*
** AST nodes and the stable text form of a tree (the parser snapshots of
** tests/parse/). One node a line, two spaces of indent a level:
**
**   kind [detail] @line:col-line:col
**
** where the range's end is exclusive. Lists that need a name to be read
** unambiguously (bodies, branches) get a "then:", "else:" or "body:" line.
*/
#include "ast.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

#define AST_NAME(name, text) text,
static const char *const ast_kind_names[] = {AST_LIST_KINDS(AST_NAME)};
#undef AST_NAME

const char *ast_kind_name(AstKind k) { return k < AST_KIND_COUNT ? ast_kind_names[k] : "?"; }

/* Bytes of a node of kind k: up to the last field the table in ast.h gives
** that kind, so no node pays for fields it never uses (a number in a long
** point list costs 32 bytes, a list 72). Readers must keep to the table. */
static size_t node_size(AstKind k) {
  switch (k) {
    case AST_NUMBER: case AST_STRING: case AST_COLOR: case AST_BOOL: case AST_UNDEF:
    case AST_IDENT: case AST_INCLUDE:
      return offsetof(AstNode, a);
    case AST_UNARY: case AST_ARG: case AST_MEMBER: case AST_BINDING: case AST_PARAM:
    case AST_COMP_EACH: case AST_USE: case AST_LET:
      return offsetof(AstNode, b);
    case AST_BINARY: case AST_INDEX:
      return offsetof(AstNode, c);
    case AST_RANGE: case AST_TERNARY: case AST_COMP_IF:
      return offsetof(AstNode, list);
    case AST_PROGRAM: case AST_LIST: case AST_CALL: case AST_LET_EXPR: case AST_FN_EXPR:
    case AST_COMP_FOR: case AST_COMP_LET: case AST_FN_DEF: case AST_PROPERTY:
      return offsetof(AstNode, list2);
    default:   /* AST_MODULE_DEF, AST_CALL_STMT, AST_FOR, AST_IF, AST_BLOCK */
      return sizeof(AstNode);
  }
}

AstNode *ast_new(Arena *arena, AstKind kind, SrcRange range) {
  AstNode *n = arena_alloc_small(arena, node_size(kind));
  n->kind = (unsigned char)kind;
  n->range = range;
  return n;
}

/* The shortest %g form that reads back as the same double. */
static void print_number(double v, FILE *out) {
  char buf[40];
  if (v == floor(v) && fabs(v) < 1e15) { fprintf(out, "%.0f", v == 0 ? 0.0 : v); return; }
  for (int prec = 1; prec <= 17; prec++) {
    snprintf(buf, sizeof buf, "%.*g", prec, v);
    if (strtod(buf, NULL) == v) break;
  }
  fputs(buf, out);
}

static void print_string(const char *s, FILE *out) {
  if (!s) { fputs("(missing)", out); return; }   /* a partial tree after an error */
  fputc('"', out);
  for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
    if (*p == '"' || *p == '\\') fprintf(out, "\\%c", *p);
    else if (*p == '\n') fputs("\\n", out);
    else if (*p == '\t') fputs("\\t", out);
    else if (*p < 0x20 || *p == 0x7F) fprintf(out, "\\u{%x}", *p);
    else fputc(*p, out);
  }
  fputc('"', out);
}

static const char *op_text(TokenKind op) {
  switch (op) {
    case TK_PLUS: return "+"; case TK_MINUS: return "-"; case TK_STAR: return "*";
    case TK_SLASH: return "/"; case TK_PERCENT: return "%"; case TK_CARET: return "^";
    case TK_NOT: return "!"; case TK_AND: return "&&"; case TK_OR: return "||";
    case TK_EQ: return "=="; case TK_NE: return "!="; case TK_LT: return "<";
    case TK_LE: return "<="; case TK_GT: return ">"; case TK_GE: return ">=";
    default: return "?";
  }
}

static void print_detail(const AstNode *n, FILE *out) {
  switch ((AstKind)n->kind) {
    case AST_NUMBER: fputc(' ', out); print_number(n->number, out); break;
    case AST_STRING: case AST_INCLUDE: case AST_USE: fputc(' ', out); print_string(n->name, out); break;
    case AST_COLOR:
      fprintf(out, " #%02x%02x%02x%02x", (int)lround(n->color[0] * 255), (int)lround(n->color[1] * 255),
              (int)lround(n->color[2] * 255), (int)lround(n->color[3] * 255));
      break;
    case AST_BOOL: fputs(n->number ? " true" : " false", out); break;
    case AST_UNARY: case AST_BINARY: fprintf(out, " %s", op_text(n->op)); break;
    case AST_MEMBER: fprintf(out, " .%s", n->name); break;
    case AST_ARG: if (n->name) fprintf(out, " %s=", n->name); break;
    case AST_BLOCK:
      fprintf(out, " %s", n->name);
      for (int i = 0; i < n->list2.count; i++) fprintf(out, " %s", n->list2.items[i]->name);
      break;
    case AST_RANGE: if (n->b) fputs(" stepped", out); break;
    case AST_IDENT: case AST_PROGRAM: case AST_LET: case AST_FN_DEF: case AST_MODULE_DEF:
    case AST_PARAM: case AST_BINDING: case AST_PROPERTY:
      if (n->name) fprintf(out, " %s", n->name);
      break;
    default:
      break;
  }
}

static void print_node(const AstNode *n, int depth, FILE *out);

static void print_list(const AstList *l, int depth, FILE *out) {
  for (int i = 0; i < l->count; i++) print_node(l->items[i], depth, out);
}

static void print_section(const char *label, const AstList *l, int depth, FILE *out) {
  fprintf(out, "%*s%s:\n", depth * 2, "", label);
  print_list(l, depth + 1, out);
}

static void print_node(const AstNode *n, int depth, FILE *out) {
  if (!n) { fprintf(out, "%*s(missing)\n", depth * 2, ""); return; }
  fprintf(out, "%*s%s", depth * 2, "", ast_kind_name(n->kind));
  print_detail(n, out);
  fprintf(out, " @%d:%d-%d:%d\n", n->range.line, n->range.col, n->range.end_line, n->range.end_col);
  size_t size = node_size(n->kind);   /* read no field past it */
  if (size <= offsetof(AstNode, a)) return;
  if (n->kind == AST_RANGE) {   /* start, [step,] end in source order */
    print_node(n->a, depth + 1, out);
    if (n->b) print_node(n->b, depth + 1, out);
    print_node(n->c, depth + 1, out);
    return;
  }
  /* definitions and scopes: their parameters or bindings come first */
  int list_first = n->kind == AST_FN_DEF || n->kind == AST_FN_EXPR || n->kind == AST_LET_EXPR ||
                   n->kind == AST_COMP_FOR || n->kind == AST_COMP_LET;
  if (list_first) print_list(&n->list, depth + 1, out);
  if (n->kind != AST_USE) { if (n->a) print_node(n->a, depth + 1, out); }
  else if (n->a) fprintf(out, "%*sas %s\n", (depth + 1) * 2, "", n->a->name);
  if (size > offsetof(AstNode, b) && n->b) print_node(n->b, depth + 1, out);
  if (size > offsetof(AstNode, c) && n->c) print_node(n->c, depth + 1, out);
  if (size <= offsetof(AstNode, list)) return;
  switch (n->kind) {
    case AST_IF:
      print_section("then", &n->list, depth + 1, out);
      if (n->has_else) print_section("else", &n->list2, depth + 1, out);
      break;
    case AST_FOR: case AST_MODULE_DEF:
      print_list(&n->list, depth + 1, out);
      print_section("body", &n->list2, depth + 1, out);
      break;
    case AST_CALL_STMT:
      if (n->has_body) print_section("body", &n->list2, depth + 1, out);
      break;
    case AST_BLOCK:   /* list2 holds the words, printed on the header line */
      print_list(&n->list, depth + 1, out);
      break;
    default:
      if (!list_first) print_list(&n->list, depth + 1, out);
      if (size > offsetof(AstNode, list2)) print_list(&n->list2, depth + 1, out);
  }
}

void ast_print(const AstNode *node, FILE *out) { print_node(node, 0, out); }
