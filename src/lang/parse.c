/*
** Recursive-descent parser for .npr scripts. Each parse function begins
** with the rule of grammar/npr.ebnf it implements (same names).
**
** Errors are reported and parsing goes on: the item being parsed is
** abandoned and the parser resynchronises at the next `;` or `}` of its
** nesting level, so one run reports several independent mistakes. Nesting
** deeper than PARSE_MAX_DEPTH stops the parse with one diagnostic, which
** keeps the C stack safe on any input.
**
** Written bottom-up: token handling, then expressions, then items.
*/
#include "parse.h"

#include "habits.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct Parser {
  Lexer lx;
  Token cur;          /* the token being looked at */
  Token next;         /* one token of lookahead, valid when has_next */
  int has_next;
  SrcRange prev_end;  /* end of the last consumed token (for "expected `;`") */
  uint32_t prev_end_at;   /* the same as a byte offset, where nodes end */
  int prev_bad;       /* the last consumed token had a lexical error */
  Arena *arena;
  int depth;
  int stop;           /* nesting limit hit or too many errors: unwind */
  int panic;          /* an error in the current item: skip to a sync point */
  int errors;
  AstNode **scratch;  /* children of the lists being built, innermost on top */
  int nscratch, capscratch;
  AstNumber *nums;    /* the numbers of a list while they are all lone ones (parse_list) */
  int nnums, capnums;
} Parser;

/* ---- tokens ------------------------------------------------------------ */

/* Byte offset of a token in the source. */
static uint32_t offset_of(const Parser *p, const Token *t) { return (uint32_t)(t->start - p->lx.src); }

static void next_token(Parser *p) {
  p->prev_end = p->cur.range;
  p->prev_end_at = offset_of(p, &p->cur) + (uint32_t)p->cur.len;
  p->prev_end.line = p->cur.range.end_line;
  p->prev_end.col = p->cur.range.end_col;
  p->prev_end.end_col = p->prev_end.col + 1;
  p->prev_bad = p->cur.bad;
  if (p->has_next) { p->cur = p->next; p->has_next = 0; }
  else lex_next(&p->lx, &p->cur);
  if (diag_too_many()) p->stop = 1;
}

static Token *peek(Parser *p) {
  if (!p->has_next) { lex_next(&p->lx, &p->next); p->has_next = 1; }
  return &p->next;
}

static int check(Parser *p, TokenKind k) { return p->cur.kind == k; }

static int accept(Parser *p, TokenKind k) {
  if (!check(p, k)) return 0;
  next_token(p);
  return 1;
}

/* Text of the current token for messages: `name`, `12`, or its kind. */
static const char *found(Parser *p) {
  static char buf[80];
  const Token *t = &p->cur;
  if (t->kind == TK_EOF) return "end of file";
  if (t->kind == TK_STRING) return "a string";
  int n = t->len > 40 ? 40 : t->len;
  snprintf(buf, sizeof buf, "`%.*s%s`", n, t->start, t->len > 40 ? "…" : "");
  return buf;
}

/* Report an error unless this item already has one; enter panic mode. */
static void error_at(Parser *p, SrcRange at, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static void error_at(Parser *p, SrcRange at, const char *fmt, ...) {
  if (p->panic || p->stop) return;
  char msg[512];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  diag_error(at, "%s", msg);
  p->panic = 1;
  p->errors++;
}

/* "expected `;` after …": when the offending token is on a later line, point
** just past the previous token, where the `;` is missing. */
static void expected(Parser *p, TokenKind k, const char *context) {
  if (p->prev_bad || p->cur.bad) { p->panic = 1; return; }   /* the lexer already said what is wrong */
  SrcRange at = p->cur.range;
  if (p->cur.range.line > p->prev_end.line && p->prev_end.file >= 0) at = p->prev_end;
  error_at(p, at, "expected %s %s, found %s", token_name(k), context, found(p));
}

static int expect(Parser *p, TokenKind k, const char *context) {
  if (accept(p, k)) return 1;
  expected(p, k, context);
  return 0;
}

/* Expect the closer of a bracket opened at `open`; name the opening place. */
static int expect_close(Parser *p, TokenKind k, SrcRange open, const char *what) {
  if (accept(p, k)) return 1;
  if (p->panic || p->stop) return 0;
  SrcRange at = p->cur.range;
  if (p->cur.range.line > p->prev_end.line) at = p->prev_end;
  error_at(p, at, "expected %s to close the %s opened at line %d, found %s", token_name(k), what,
           open.line, found(p));
  diag_note(open, "the %s opened here", what);
  return 0;
}

static int enter(Parser *p, SrcRange at) {
  if (p->stop) return 0;
  if (++p->depth > PARSE_MAX_DEPTH) {
    diag_error(at, "expression or block nested too deeply (limit is %d levels)", PARSE_MAX_DEPTH);
    p->stop = 1;
    return 0;
  }
  return 1;
}

static void leave(Parser *p) { p->depth--; }

/* A node over the current token. */
static AstNode *node(Parser *p, AstKind k) {
  uint32_t at = offset_of(p, &p->cur);
  return ast_new(p->arena, k, p->lx.file, at, at + (uint32_t)p->cur.len);
}

/* A node from byte offset start to the end of the last token consumed. */
static AstNode *node_from(Parser *p, AstKind k, uint32_t start) {
  return ast_new(p->arena, k, p->lx.file, start, p->prev_end_at);
}

/* Lists are gathered on a scratch stack and copied into the arena at their
** exact size when complete: begin_list() marks the start, push() adds a
** child, end_list() stores them. Nested lists stack above their parent's. */
static int begin_list(Parser *p) { return p->nscratch; }

static void push(Parser *p, AstNode *n) {
  if (!n) return;
  p->scratch = xgrow(p->scratch, &p->capscratch, p->nscratch + 1, sizeof *p->scratch);
  p->scratch[p->nscratch++] = n;
}

static void end_list(Parser *p, int mark, AstList *out) {
  int n = p->nscratch - mark;
  if (n > 0) {
    AstNode **items = arena_alloc_small(p->arena, (size_t)n * sizeof *items);
    memcpy(items, p->scratch + mark, (size_t)n * sizeof *items);
    out->items = items;
    out->count = n;
  }
  p->nscratch = mark;
}

/* Stretch n to the end of the last token consumed. */
static void end_node(Parser *p, AstNode *n) { n->end = p->prev_end_at; }

/* ---- expressions ------------------------------------------------------ */

static AstNode *parse_expr(Parser *p);
static AstNode *parse_unary(Parser *p);
static AstNode *parse_list_elem(Parser *p);

/* A placeholder for an expression that failed to parse. */
static AstNode *bad_expr(Parser *p) { return node(p, AST_UNDEF); }

/* binding := IDENT '=' expr */
static AstNode *parse_binding(Parser *p) {
  AstNode *b = node(p, AST_BINDING);
  if (!check(p, TK_IDENT)) { expected(p, TK_IDENT, "(a name to bind)"); return NULL; }
  b->name = p->cur.string;
  next_token(p);
  expect(p, TK_ASSIGN, "after the name");
  b->a = parse_expr(p);
  end_node(p, b);
  return b;
}

/* bindings := binding { ',' binding } */
static void parse_bindings(Parser *p, AstList *out) {
  int mark = begin_list(p);
  do {
    if (check(p, TK_RPAREN)) break;   /* trailing comma */
    push(p, parse_binding(p));
  } while (!p->panic && !p->stop && accept(p, TK_COMMA));
  end_list(p, mark, out);
}

/* params := [ param { ',' param } [','] ];  param := IDENT [ '=' expr ] */
static void parse_params(Parser *p, AstList *out) {
  SrcRange open = p->cur.range;
  if (!expect(p, TK_LPAREN, "to start the parameter list")) return;
  int mark = begin_list(p);
  while (!check(p, TK_RPAREN) && !p->panic && !p->stop) {
    if (!check(p, TK_IDENT)) { expected(p, TK_IDENT, "(a parameter name)"); return; }
    AstNode *prm = node(p, AST_PARAM);
    prm->name = p->cur.string;
    next_token(p);
    if (accept(p, TK_ASSIGN)) prm->a = parse_expr(p);
    end_node(p, prm);
    push(p, prm);
    if (!accept(p, TK_COMMA)) break;
  }
  end_list(p, mark, out);
  expect_close(p, TK_RPAREN, open, "parameter list");
}

/* args := [ arg { ',' arg } [','] ];  arg := [ IDENT '=' ] expr */
static void parse_args(Parser *p, AstList *out, SrcRange open) {
  int mark = begin_list(p);
  while (!check(p, TK_RPAREN) && !p->panic && !p->stop) {
    AstNode *arg = node(p, AST_ARG);
    if (check(p, TK_IDENT) && peek(p)->kind == TK_ASSIGN) {
      arg->name = p->cur.string;
      next_token(p);
      next_token(p);
    }
    arg->a = parse_expr(p);
    end_node(p, arg);
    push(p, arg);
    if (!accept(p, TK_COMMA)) break;
  }
  end_list(p, mark, out);
  expect_close(p, TK_RPAREN, open, "argument list");
}

static int lone_number(Parser *p, AstNumber *out);

static AstNode *number_node(Parser *p, const AstNumber *num) {
  AstNode *n = ast_new(p->arena, AST_NUMBER, p->lx.file, num->start, num->end);
  n->number = num->value;
  return n;
}

/* Read a lone number (see lone_number) onto p->nums. 0, having consumed
** nothing, when the next element is something else. */
static int take_number(Parser *p) {
  AstNumber num;
  if (!lone_number(p, &num)) return 0;
  p->nums = xgrow(p->nums, &p->capnums, p->nnums + 1, sizeof *p->nums);
  p->nums[p->nnums++] = num;
  return 1;
}

/* Turn the numbers on p->nums into nodes on the scratch stack. */
static void flush_numbers(Parser *p) {
  for (int i = 0; i < p->nnums; i++) push(p, number_node(p, &p->nums[i]));
  p->nnums = 0;
}

/* list := '[' ']' | '[' expr ':' expr [ ':' expr ] ']'
**       | '[' list_elem { ',' list_elem } [','] ']'
** A list of lone numbers only, most of any point data, becomes one
** AST_NUMBERS node: the numbers wait on p->nums (empty when a list starts:
** a list takes nested elements only after flushing its own) and are
** dropped, as the node reads them back from the source when asked. */
static AstNode *parse_list(Parser *p) {
  SrcRange open = p->cur.range;
  uint32_t start = offset_of(p, &p->cur);
  next_token(p);
  if (accept(p, TK_RBRACKET)) return node_from(p, AST_LIST, start);
  int packed = take_number(p);   /* every element so far is on p->nums */
  AstNode *first = packed ? NULL : parse_list_elem(p);
  if (check(p, TK_COLON) && (packed || (first && first->kind < AST_COMP_FOR))) {
    if (packed) { first = number_node(p, &p->nums[0]); p->nnums = 0; }
    AstNode *r = node_from(p, AST_RANGE, start);
    next_token(p);
    r->a = first;
    r->c = parse_expr(p);
    if (accept(p, TK_COLON)) { r->b = r->c; r->c = parse_expr(p); }
    expect_close(p, TK_RBRACKET, open, "range");
    end_node(p, r);
    return r;
  }
  int mark = begin_list(p);
  push(p, first);
  while (accept(p, TK_COMMA) && !p->panic && !p->stop) {
    if (check(p, TK_RBRACKET)) break;
    if (packed && take_number(p)) continue;
    if (packed) { flush_numbers(p); packed = 0; }
    push(p, parse_list_elem(p));
  }
  AstNode *l = node_from(p, packed ? AST_NUMBERS : AST_LIST, start);
  if (packed) { l->count = p->nnums; p->nnums = 0; }
  else end_list(p, mark, &l->list);
  expect_close(p, TK_RBRACKET, open, "list");
  end_node(p, l);
  return l;
}

/* list_elem := 'for' '(' bindings ')' list_elem
**            | 'if' '(' expr ')' list_elem [ 'else' list_elem ]
**            | 'each' expr
**            | 'let' '(' bindings ')' list_elem
**            | expr */
static AstNode *parse_list_elem(Parser *p) {
  uint32_t start = offset_of(p, &p->cur);
  if (!enter(p, p->cur.range)) return bad_expr(p);
  AstNode *n;
  if (check(p, TK_FOR) || check(p, TK_LET)) {
    n = node(p, check(p, TK_FOR) ? AST_COMP_FOR : AST_COMP_LET);
    next_token(p);
    SrcRange open = p->cur.range;
    expect(p, TK_LPAREN, n->kind == AST_COMP_FOR ? "after `for`" : "after `let`");
    parse_bindings(p, &n->list);
    expect_close(p, TK_RPAREN, open, n->kind == AST_COMP_FOR ? "`for` bindings" : "`let` bindings");
    n->a = parse_list_elem(p);
  } else if (accept(p, TK_IF)) {
    n = node_from(p, AST_COMP_IF, start);
    SrcRange open = p->cur.range;
    expect(p, TK_LPAREN, "after `if`");
    n->a = parse_expr(p);
    expect_close(p, TK_RPAREN, open, "`if` condition");
    n->b = parse_list_elem(p);
    if (accept(p, TK_ELSE)) n->c = parse_list_elem(p);
  } else if (accept(p, TK_EACH)) {
    n = node_from(p, AST_COMP_EACH, start);
    n->a = parse_expr(p);
  } else {
    leave(p);
    return parse_expr(p);
  }
  end_node(p, n);
  leave(p);
  return n;
}

/* primary := NUMBER | STRING | COLOR | 'true' | 'false' | 'undef' | IDENT
**          | '(' expr ')' | list | let_expr | fn_expr
** let_expr := 'let' '(' bindings ')' expr
** fn_expr  := 'fn' params '=' expr */
static AstNode *parse_primary(Parser *p) {
  const Token *t = &p->cur;   /* read before next_token replaces it */
  SrcRange at = t->range;
  uint32_t start = offset_of(p, t);
  AstNode *n;
  switch (t->kind) {
    case TK_NUMBER: n = node(p, AST_NUMBER); n->number = t->number; next_token(p); return n;
    case TK_STRING: n = node(p, AST_STRING); n->name = t->string; next_token(p); return n;
    case TK_COLOR: {
      n = node(p, AST_COLOR);
      float *rgba = arena_alloc_small(p->arena, sizeof t->color);
      memcpy(rgba, t->color, sizeof t->color);
      n->color = rgba;
      next_token(p);
      return n;
    }
    case TK_TRUE: case TK_FALSE:
      n = node(p, AST_BOOL); n->number = t->kind == TK_TRUE; next_token(p); return n;
    case TK_UNDEF: n = node(p, AST_UNDEF); next_token(p); return n;
    case TK_IDENT: n = node(p, AST_IDENT); n->name = t->string; next_token(p); return n;
    case TK_LPAREN:
      next_token(p);
      n = parse_expr(p);
      expect_close(p, TK_RPAREN, at, "parenthesis");
      return n;
    case TK_LBRACKET: return parse_list(p);
    case TK_LET: {
      next_token(p);
      n = node_from(p, AST_LET_EXPR, start);
      SrcRange open = p->cur.range;
      expect(p, TK_LPAREN, "after `let` in an expression");
      parse_bindings(p, &n->list);
      expect_close(p, TK_RPAREN, open, "`let` bindings");
      n->a = parse_expr(p);
      end_node(p, n);
      return n;
    }
    case TK_FN:
      next_token(p);
      n = node_from(p, AST_FN_EXPR, start);
      parse_params(p, &n->list);
      expect(p, TK_ASSIGN, "before the body of a function literal");
      n->a = parse_expr(p);
      end_node(p, n);
      return n;
    default:
      if (t->bad) p->panic = 1;   /* the lexer already reported it */
      char hint[600] = "";
      if (t->kind == TK_LT) habit_hint(HABIT_TOKEN, "<", NULL, hint, sizeof hint);
      error_at(p, at, "expected an expression, found %s%s", found(p), hint);
      return bad_expr(p);
  }
}

/* postfix := primary { '(' args ')' | '[' expr ']' | '.' IDENT } */
static AstNode *parse_postfix(Parser *p) {
  uint32_t start = offset_of(p, &p->cur);
  AstNode *e = parse_primary(p);
  for (;;) {
    TokenKind k = p->cur.kind;
    if (p->panic || p->stop || (k != TK_LPAREN && k != TK_LBRACKET && k != TK_DOT)) return e;
    SrcRange at = p->cur.range;   /* of the bracket (read only then: most primaries stand alone) */
    if (accept(p, TK_LPAREN)) {
      AstNode *call = node_from(p, AST_CALL, start);
      call->a = e;
      if (!enter(p, at)) return e;
      parse_args(p, &call->list, at);
      leave(p);
      end_node(p, call);
      e = call;
    } else if (accept(p, TK_LBRACKET)) {
      AstNode *ix = node_from(p, AST_INDEX, start);
      ix->a = e;
      ix->b = parse_expr(p);
      expect_close(p, TK_RBRACKET, at, "index");
      end_node(p, ix);
      e = ix;
    } else if (accept(p, TK_DOT)) {
      AstNode *m = node_from(p, AST_MEMBER, start);
      m->a = e;
      if (!check(p, TK_IDENT)) { expected(p, TK_IDENT, "after `.`"); return e; }
      m->name = p->cur.string;
      next_token(p);
      end_node(p, m);
      e = m;
    } else return e;
  }
}

/* power := postfix [ '^' unary ]          (right-associative, above unary minus) */
static AstNode *parse_power(Parser *p) {
  uint32_t start = offset_of(p, &p->cur);
  AstNode *base = parse_postfix(p);
  if (!check(p, TK_CARET)) return base;
  AstNode *n = node_from(p, AST_BINARY, start);
  n->op = TK_CARET;
  next_token(p);
  n->a = base;
  n->b = parse_unary(p);
  end_node(p, n);
  return n;
}

/* unary := ( '-' | '+' | '!' ) unary | power */
static AstNode *parse_unary(Parser *p) {
  uint32_t start = offset_of(p, &p->cur);
  if (!enter(p, p->cur.range)) return bad_expr(p);
  AstNode *n;
  if (check(p, TK_MINUS) || check(p, TK_PLUS) || check(p, TK_NOT)) {
    TokenKind op = p->cur.kind;
    next_token(p);
    AstNode *operand = parse_unary(p);
    if (op == TK_MINUS && operand->kind == AST_NUMBER) {
      /* -NUMBER is folded into one literal: long point lists are full of
      ** them. (-2^2 is not: its operand is the power, so it is -(2^2).) */
      operand->number = -operand->number;
      operand->start = start;
      end_node(p, operand);
      n = operand;
    } else {
      n = node_from(p, AST_UNARY, start);
      n->op = (unsigned char)op;
      n->a = operand;
      end_node(p, n);
    }
  } else n = parse_power(p);
  leave(p);
  return n;
}

/* The binary levels, loosest first; each is left-associative:
**   or := and { '||' and }
**   and := equality { '&&' equality }
**   equality := comparison { ('==' | '!=') comparison }
**   comparison := additive { ('<' | '<=' | '>' | '>=') additive }
**   additive := multiplicative { ('+' | '-') multiplicative }
**   multiplicative := unary { ('*' | '/' | '%') unary }
** parse_binary implements them all by precedence climbing: binary_prec
** gives each operator its level (1 = or … 6 = multiplicative). */
static int binary_prec(TokenKind k) {
  switch (k) {
    case TK_OR: return 1;
    case TK_AND: return 2;
    case TK_EQ: case TK_NE: return 3;
    case TK_LT: case TK_LE: case TK_GT: case TK_GE: return 4;
    case TK_PLUS: case TK_MINUS: return 5;
    case TK_STAR: case TK_SLASH: case TK_PERCENT: return 6;
    default: return 0;
  }
}

/* Parse operators of level min_prec and tighter. */
static AstNode *parse_binary(Parser *p, int min_prec) {
  SrcRange at = p->cur.range;   /* for the depth limit's message */
  uint32_t start = offset_of(p, &p->cur);
  AstNode *left = parse_unary(p);
  for (;;) {
    int prec = binary_prec(p->cur.kind);
    if (prec < min_prec || prec == 0 || p->panic || p->stop) return left;
    AstNode *n = node_from(p, AST_BINARY, start);
    n->op = (unsigned char)p->cur.kind;
    next_token(p);
    n->a = left;
    if (!enter(p, at)) return left;
    n->b = parse_binary(p, prec + 1);
    leave(p);
    end_node(p, n);
    left = n;
  }
}

/* Tokens that end an expression: no operator, call, index or member
** continues one through them. */
static int ends_expr(TokenKind k) {
  return k == TK_COMMA || k == TK_RBRACKET || k == TK_RPAREN || k == TK_SEMI || k == TK_COLON ||
         k == TK_RBRACE;
}

/* A lone number, NUMBER or '-' NUMBER before a token that ends the
** expression, is most of a long point list: read it without descending
** through every precedence level, with the same value, range, diagnostics
** and depth limit as that descent. 0, having consumed nothing, otherwise. */
static int lone_number(Parser *p, AstNumber *out) {
  int neg = check(p, TK_MINUS);
  if ((!neg && !check(p, TK_NUMBER)) || p->panic || p->stop) return 0;
  if (p->depth + 2 + neg > PARSE_MAX_DEPTH) return 0;   /* let the descent report it */
  const Token *t = peek(p);
  if (neg) {
    /* the descent would stop after the `-` once errors hit the cap */
    if (t->kind != TK_NUMBER || diag_too_many()) return 0;
    Lexer scout = p->lx;   /* the token after the number, as starts_block looks */
    scout.quiet = 1;
    Token after;
    lex_next(&scout, &after);
    if (!ends_expr(after.kind)) return 0;
  } else if (!ends_expr(t->kind)) return 0;
  out->start = offset_of(p, &p->cur);   /* as parse_unary folds -NUMBER */
  if (neg) next_token(p);
  out->value = neg ? -p->cur.number : p->cur.number;
  next_token(p);
  out->end = p->prev_end_at;
  return 1;
}

/* expr := or [ '?' expr ':' expr ] */
static AstNode *parse_expr(Parser *p) {
  AstNumber lone;
  if (lone_number(p, &lone)) return number_node(p, &lone);
  uint32_t start = offset_of(p, &p->cur);
  if (!enter(p, p->cur.range)) return bad_expr(p);
  AstNode *cond = parse_binary(p, 1);
  if (check(p, TK_QUESTION) && !p->panic) {
    AstNode *n = node_from(p, AST_TERNARY, start);
    next_token(p);
    n->a = cond;
    n->b = parse_expr(p);
    expect(p, TK_COLON, "in a `? :` expression");
    n->c = parse_expr(p);
    end_node(p, n);
    cond = n;
  }
  leave(p);
  return cond;
}

/* ---- items ------------------------------------------------------------- */

static AstNode *parse_item(Parser *p);

/* Skip to a point where parsing can resume: past the next `;` or before the
** next `}` at this nesting level (brackets in between are balanced). */
static void synchronize(Parser *p) {
  int depth = 0;
  while (!check(p, TK_EOF) && !p->stop) {
    TokenKind k = p->cur.kind;
    if (depth == 0 && k == TK_RBRACE) break;
    if (k == TK_LPAREN || k == TK_LBRACKET || k == TK_LBRACE) depth++;
    else if ((k == TK_RPAREN || k == TK_RBRACKET || k == TK_RBRACE) && depth > 0) {
      depth--;
      if (depth == 0 && k == TK_RBRACE) { next_token(p); break; }
    } else if (k == TK_SEMI && depth == 0) { next_token(p); break; }
    next_token(p);
  }
  p->panic = 0;
}

/* items := { item }   — up to a closing `}` (not consumed) or end of file */
static void parse_items(Parser *p, AstList *out) {
  int mark = begin_list(p);
  while (!check(p, TK_RBRACE) && !check(p, TK_EOF) && !p->stop) {
    AstNode *it = parse_item(p);
    push(p, it);
    if (p->panic) synchronize(p);
  }
  end_list(p, mark, out);
}

/* braced := '{' items '}' */
static void parse_braced(Parser *p, AstList *out, const char *what) {
  SrcRange open = p->cur.range;
  if (!expect(p, TK_LBRACE, what)) return;
  if (!enter(p, open)) return;
  parse_items(p, out);
  leave(p);
  if (p->stop) return;
  p->panic = 0;
  expect_close(p, TK_RBRACE, open, "block");
}

/* body := braced | item */
static void parse_body(Parser *p, AstList *out) {
  if (check(p, TK_LBRACE)) { parse_braced(p, out, ""); return; }
  if (!enter(p, p->cur.range)) return;
  int mark = begin_list(p);
  push(p, parse_item(p));
  end_list(p, mark, out);
  leave(p);
}

static void end_statement(Parser *p, const char *what) {
  if (!p->panic) expect(p, TK_SEMI, what);
}

/* include := 'include' STRING ';' ;  use := 'use' STRING 'as' IDENT ';' */
static AstNode *parse_include(Parser *p) {
  int is_use = check(p, TK_USE);
  AstNode *n = node(p, is_use ? AST_USE : AST_INCLUDE);
  next_token(p);
  if (!check(p, TK_STRING)) {
    char hint[600];
    if (check(p, TK_LT) && habit_hint(HABIT_TOKEN, is_use ? "use <" : "include <", NULL, hint, sizeof hint))
      error_at(p, p->cur.range, "expected string (a file name) after `%s`, found `<`%s", is_use ? "use" : "include", hint);
    else expected(p, TK_STRING, is_use ? "(a file name) after `use`" : "(a file name) after `include`");
    return n;
  }
  n->name = p->cur.string;
  next_token(p);
  if (is_use) {
    expect(p, TK_AS, "after the file name (`use \"file.npr\" as name;`)");
    if (!p->panic && !check(p, TK_IDENT)) expected(p, TK_IDENT, "(the namespace name) after `as`");
    if (!p->panic) {
      n->a = node(p, AST_IDENT);
      n->a->name = p->cur.string;
      next_token(p);
    }
  }
  end_statement(p, is_use ? "after a `use` statement" : "after an `include` statement");
  end_node(p, n);
  return n;
}

/* let_stmt := 'let' IDENT '=' expr ';' */
static AstNode *parse_let(Parser *p) {
  AstNode *n = node(p, AST_LET);
  next_token(p);
  if (!check(p, TK_IDENT)) { expected(p, TK_IDENT, "(a name) after `let`"); return n; }
  n->name = p->cur.string;
  next_token(p);
  expect(p, TK_ASSIGN, "after the name in a `let`");
  if (!p->panic) n->a = parse_expr(p);
  end_statement(p, "after a `let` statement");
  end_node(p, n);
  return n;
}

/* fn_def := 'fn' IDENT params '=' expr ';' */
static AstNode *parse_fn_def(Parser *p) {
  AstNode *n = node(p, AST_FN_DEF);
  next_token(p);
  if (!check(p, TK_IDENT)) { expected(p, TK_IDENT, "(the function's name) after `fn`"); return n; }
  n->name = p->cur.string;
  next_token(p);
  parse_params(p, &n->list);
  if (!p->panic) expect(p, TK_ASSIGN, "before the function body");
  if (!p->panic) n->a = parse_expr(p);
  end_statement(p, "after a function definition");
  end_node(p, n);
  return n;
}

/* module_def := 'module' IDENT params braced */
static AstNode *parse_module_def(Parser *p) {
  AstNode *n = node(p, AST_MODULE_DEF);
  next_token(p);
  if (!check(p, TK_IDENT)) { expected(p, TK_IDENT, "(the module's name) after `module`"); return n; }
  n->name = p->cur.string;
  next_token(p);
  parse_params(p, &n->list);
  if (!p->panic) parse_braced(p, &n->list2, "to start the module body");
  end_node(p, n);
  return n;
}

/* for_stmt := 'for' '(' bindings ')' body */
static AstNode *parse_for(Parser *p) {
  AstNode *n = node(p, AST_FOR);
  next_token(p);
  SrcRange open = p->cur.range;
  expect(p, TK_LPAREN, "after `for`");
  if (!p->panic) parse_bindings(p, &n->list);
  if (!p->panic) expect_close(p, TK_RPAREN, open, "`for` bindings");
  if (!p->panic) parse_body(p, &n->list2);
  end_node(p, n);
  return n;
}

/* if_stmt := 'if' '(' expr ')' body [ 'else' body ] */
static AstNode *parse_if(Parser *p) {
  AstNode *n = node(p, AST_IF);
  next_token(p);
  SrcRange open = p->cur.range;
  expect(p, TK_LPAREN, "after `if`");
  if (!p->panic) n->a = parse_expr(p);
  if (!p->panic) expect_close(p, TK_RPAREN, open, "`if` condition");
  if (!p->panic) parse_body(p, &n->list);
  if (!p->panic && accept(p, TK_ELSE)) {
    n->has_else = 1;
    parse_body(p, &n->list2);
  }
  end_node(p, n);
  return n;
}

/* block := IDENT { IDENT } braced */
static AstNode *parse_block(Parser *p) {
  AstNode *n = node(p, AST_BLOCK);
  n->name = p->cur.string;
  next_token(p);
  int mark = begin_list(p);
  while (check(p, TK_IDENT)) {
    AstNode *w = node(p, AST_IDENT);
    w->name = p->cur.string;
    push(p, w);
    next_token(p);
  }
  end_list(p, mark, &n->list2);
  parse_braced(p, &n->list, "to open the block");
  end_node(p, n);
  return n;
}

/* call_stmt := postfix ( ';' | body )      (starts with IDENT '('; the body
** is the call's children, as OpenSCAD's `translate(v) cube(1);`) */
static AstNode *parse_call_stmt(Parser *p) {
  AstNode *n = node(p, AST_CALL_STMT);
  n->a = parse_postfix(p);
  TokenKind k = p->cur.kind;
  if (!p->panic && (k == TK_LBRACE || k == TK_IDENT || k == TK_FOR || k == TK_IF)) {
    n->has_body = 1;
    parse_body(p, &n->list2);
  } else end_statement(p, "after a call");
  end_node(p, n);
  return n;
}

/* property := IDENT [ expr { ',' expr } ] ';' */
static AstNode *parse_property(Parser *p) {
  AstNode *n = node(p, AST_PROPERTY);
  n->name = p->cur.string;
  SrcRange name_at = p->cur.range;
  next_token(p);
  if (check(p, TK_ASSIGN)) {
    error_at(p, p->cur.range, "unexpected `=` after `%s`: a definition needs `let` (`let %s = …;`)", n->name, n->name);
    return n;
  }
  char hint[600];
  if (habit_hint(HABIT_TOKEN, n->name, NULL, hint, sizeof hint)) {
    error_at(p, name_at, "unexpected `%s`%s", n->name, hint);
    return n;
  }
  if (!check(p, TK_SEMI)) {
    int mark = begin_list(p);
    do push(p, parse_expr(p));
    while (!p->panic && !p->stop && accept(p, TK_COMMA));
    end_list(p, mark, &n->list);
  }
  end_statement(p, "after a property");
  end_node(p, n);
  return n;
}

/* Does the identifier at cur start a block (IDENT { IDENT } '{')? Looks
** ahead with a quiet copy of the lexer, so nothing is consumed or reported. */
static int starts_block(Parser *p) {
  Token *t = peek(p);
  if (t->kind == TK_LBRACE) return 1;
  if (t->kind != TK_IDENT) return 0;
  Lexer scout = p->lx;
  scout.quiet = 1;
  for (;;) {
    Token u;
    lex_next(&scout, &u);
    if (u.kind == TK_LBRACE) return 1;
    if (u.kind != TK_IDENT) return 0;
  }
}

/* item := include | use | let_stmt | fn_def | module_def | for_stmt | if_stmt
**       | block | call_stmt | property | ';' */
static AstNode *parse_item(Parser *p) {
  switch (p->cur.kind) {
    case TK_INCLUDE: case TK_USE: return parse_include(p);
    case TK_LET: return parse_let(p);
    case TK_FN: return parse_fn_def(p);
    case TK_MODULE: return parse_module_def(p);
    case TK_FOR: return parse_for(p);
    case TK_IF: return parse_if(p);
    case TK_SEMI: next_token(p); return NULL;   /* an empty statement */
    case TK_IDENT:
      if (starts_block(p)) return parse_block(p);
      if (peek(p)->kind == TK_LPAREN) return parse_call_stmt(p);
      return parse_property(p);
    case TK_ELSE:
      error_at(p, p->cur.range, "`else` without a matching `if`");
      return NULL;
    default:
      if (p->cur.bad) p->panic = 1;
      char hint[600] = "";
      if (check(p, TK_LT)) habit_hint(HABIT_TOKEN, "<", NULL, hint, sizeof hint);
      error_at(p, p->cur.range, "expected a statement, a block or a property, found %s%s", found(p), hint);
      return NULL;
  }
}

/* program := items EOF */
AstNode *parse_file(int file, Arena *arena) {
  Parser p;
  memset(&p, 0, sizeof p);
  lex_init(&p.lx, file, arena);
  p.arena = arena;
  p.prev_end = src_none();
  lex_next(&p.lx, &p.cur);
  AstNode *prog = ast_new(arena, AST_PROGRAM, file, 0, 0);
  while (!check(&p, TK_EOF) && !p.stop) {
    parse_items(&p, &prog->list);
    if (check(&p, TK_RBRACE)) {
      error_at(&p, p.cur.range, "unexpected `}` with no block to close");
      next_token(&p);
      p.panic = 0;
    }
  }
  prog->end = offset_of(&p, &p.cur);
  free(p.scratch);
  free(p.nums);
  lex_free(&p.lx);
  return prog;
}

/* expr_source := expr EOF      (for -D name=value) */
AstNode *parse_expression_file(int file, Arena *arena) {
  Parser p;
  memset(&p, 0, sizeof p);
  lex_init(&p.lx, file, arena);
  p.arena = arena;
  p.prev_end = src_none();
  int errors_before = diag_error_count();
  lex_next(&p.lx, &p.cur);
  AstNode *e = parse_expr(&p);
  if (!p.panic && !p.stop && !check(&p, TK_EOF))
    error_at(&p, p.cur.range, "unexpected %s after the value", found(&p));
  free(p.scratch);
  free(p.nums);
  lex_free(&p.lx);
  return (p.errors || p.stop || diag_error_count() > errors_before) ? NULL : e;
}
