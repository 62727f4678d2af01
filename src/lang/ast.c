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
** that kind, so no node pays for fields it never uses (a number costs 24
** bytes, a list 48). Readers must keep to the table. */
static size_t node_size(AstKind k) {
  switch (k) {
    case AST_NUMBER: case AST_STRING: case AST_COLOR: case AST_BOOL: case AST_UNDEF:
    case AST_IDENT: case AST_INCLUDE: case AST_NUMBERS:
      return offsetof(AstNode, a);
    case AST_UNARY: case AST_ARG: case AST_MEMBER: case AST_BINDING: case AST_PARAM:
    case AST_COMP_EACH: case AST_USE: case AST_LET:
      return offsetof(AstNode, b);
    case AST_BINARY: case AST_INDEX:
      return offsetof(AstNode, c);
    case AST_RANGE: case AST_TERNARY: case AST_COMP_IF:   /* b, c */
    case AST_PROGRAM: case AST_LIST: case AST_CALL: case AST_LET_EXPR: case AST_FN_EXPR:
    case AST_COMP_FOR: case AST_COMP_LET: case AST_FN_DEF: case AST_PROPERTY:   /* list */
      return offsetof(AstNode, list2);
    default:   /* AST_MODULE_DEF, AST_CALL_STMT, AST_FOR, AST_IF, AST_BLOCK */
      return sizeof(AstNode);
  }
}

AstNode *ast_new(Arena *arena, AstKind kind, int file, uint32_t start, uint32_t end) {
  AstNode *n = arena_alloc_small(arena, node_size(kind));
  n->kind = (unsigned char)kind;
  n->file = file;
  n->start = start;
  n->end = end;
  return n;
}

/* The parser checked these tokens when it packed the list: `[`, then the
** numbers, each a NUMBER or '-' NUMBER, with commas between. */
void ast_numbers(const AstNode *n, AstNumber *out) {
  Lexer lx;
  Token t;
  lex_init_at(&lx, n->file, n->start);
  lex_next(&lx, &t);   /* [ */
  for (int i = 0; i < n->count; i++) {
    if (i > 0) lex_next(&lx, &t);   /* , */
    lex_next(&lx, &t);
    int neg = t.kind == TK_MINUS;
    out[i].start = (uint32_t)(t.start - lx.src);
    if (neg) lex_next(&lx, &t);
    out[i].value = neg ? -t.number : t.number;
    out[i].end = (uint32_t)(t.start - lx.src) + (uint32_t)t.len;
  }
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

static void print_range(int file, uint32_t start, uint32_t end, FILE *out) {
  SrcRange r = diag_range(file, start, end);
  fprintf(out, " @%d:%d-%d:%d\n", r.line, r.col, r.end_line, r.end_col);
}

/* An AST_NUMBERS list, printed as the list of number nodes it stands for. */
static void print_numbers(const AstNode *n, int depth, FILE *out) {
  AstNumber *nums = xmalloc((size_t)n->count * sizeof *nums);
  ast_numbers(n, nums);
  for (int i = 0; i < n->count; i++) {
    fprintf(out, "%*snumber ", depth * 2, "");
    print_number(nums[i].value, out);
    print_range(n->file, nums[i].start, nums[i].end, out);
  }
  free(nums);
}

static void print_node(const AstNode *n, int depth, FILE *out) {
  if (!n) { fprintf(out, "%*s(missing)\n", depth * 2, ""); return; }
  fprintf(out, "%*s%s", depth * 2, "", ast_kind_name(n->kind));
  print_detail(n, out);
  print_range(n->file, n->start, n->end, out);
  switch (n->kind) {   /* read no field past the node's end (node_size) */
    case AST_NUMBER: case AST_STRING: case AST_COLOR: case AST_BOOL: case AST_UNDEF:
    case AST_IDENT: case AST_INCLUDE:
      return;
    case AST_NUMBERS:
      print_numbers(n, depth + 1, out);
      return;
    case AST_RANGE:   /* start, [step,] end in source order */
      print_node(n->a, depth + 1, out);
      if (n->b) print_node(n->b, depth + 1, out);
      print_node(n->c, depth + 1, out);
      return;
    case AST_USE:
      if (n->a) fprintf(out, "%*sas %s\n", (depth + 1) * 2, "", n->a->name);
      return;
    case AST_UNARY: case AST_ARG: case AST_MEMBER: case AST_BINDING: case AST_PARAM:
    case AST_COMP_EACH: case AST_LET:
      if (n->a) print_node(n->a, depth + 1, out);
      return;
    case AST_BINARY: case AST_INDEX:
      if (n->a) print_node(n->a, depth + 1, out);
      if (n->b) print_node(n->b, depth + 1, out);
      return;
    case AST_TERNARY: case AST_COMP_IF:
      if (n->a) print_node(n->a, depth + 1, out);
      if (n->b) print_node(n->b, depth + 1, out);
      if (n->c) print_node(n->c, depth + 1, out);
      return;
    /* definitions and scopes: their parameters or bindings come first */
    case AST_FN_DEF: case AST_FN_EXPR: case AST_LET_EXPR: case AST_COMP_FOR: case AST_COMP_LET:
      print_list(&n->list, depth + 1, out);
      if (n->a) print_node(n->a, depth + 1, out);
      return;
    case AST_IF:
      if (n->a) print_node(n->a, depth + 1, out);
      print_section("then", &n->list, depth + 1, out);
      if (n->has_else) print_section("else", &n->list2, depth + 1, out);
      return;
    case AST_FOR: case AST_MODULE_DEF:
      print_list(&n->list, depth + 1, out);
      print_section("body", &n->list2, depth + 1, out);
      return;
    case AST_CALL_STMT:
      if (n->a) print_node(n->a, depth + 1, out);
      if (n->has_body) print_section("body", &n->list2, depth + 1, out);
      return;
    case AST_BLOCK:   /* list2 holds the words, printed on the header line */
      print_list(&n->list, depth + 1, out);
      return;
    default:   /* AST_PROGRAM, AST_LIST, AST_CALL, AST_PROPERTY */
      if (n->kind == AST_CALL && n->a) print_node(n->a, depth + 1, out);
      print_list(&n->list, depth + 1, out);
      return;
  }
}

void ast_print(const AstNode *node, FILE *out) { print_node(node, 0, out); }
