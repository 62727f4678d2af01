/*
** Lexical analyser for .npr scripts. It walks UTF-8 text one character at
** a time, keeping line and column (in characters), and hands out tokens.
** Errors are reported at once and the lexer skips past them, so the parser
** never sees a broken token: a bad number becomes 0, a bad colour black, an
** unterminated string what was read of it.
*/
#include "lex.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../base/utf8.h"

#define TOKEN_NAME(name, text) text,
static const char *const token_names[] = {TOKEN_LIST(TOKEN_NAME)};
#undef TOKEN_NAME

const char *token_name(TokenKind k) { return k < TK_COUNT ? token_names[k] : "?"; }

/* Longest string literal after decoding, a named limit (style.md §14). */
#define LEX_MAX_STRING (16 * 1024 * 1024)

void lex_init(Lexer *lx, int file, Arena *arena) {
  const SrcFile *f = diag_file(file);
  lx->file = file;
  lx->src = f->text;
  lx->end = f->text + f->len;
  lx->p = lx->src;
  lx->line = 1;
  lx->col = 1;
  lx->arena = arena;
  lx->quiet = 0;
  lx->errors = 0;
}

/* ---- characters ------------------------------------------------------ */

static int at_end(const Lexer *lx) { return lx->p >= lx->end; }
static int peekc(const Lexer *lx) { return at_end(lx) ? -1 : (unsigned char)*lx->p; }
static int peekc2(const Lexer *lx) { return lx->p + 1 < lx->end ? (unsigned char)lx->p[1] : -1; }

/* Advance one character (one code point, or one invalid byte). */
static inline void advance(Lexer *lx) {
  if ((unsigned char)*lx->p < 0x80) {   /* ASCII: the common case */
    if (*lx->p == '\n') { lx->line++; lx->col = 1; }
    else lx->col++;
    lx->p++;
    return;
  }
  uint32_t cp;
  int n = utf8_decode((const unsigned char *)lx->p, (const unsigned char *)lx->end, &cp);
  if (n == 0) n = 1;
  if (*lx->p == '\n') { lx->line++; lx->col = 1; }
  else lx->col++;
  lx->p += n;
}

static SrcRange here(const Lexer *lx) {
  SrcRange r = {lx->file, lx->line, lx->col, lx->line, lx->col + 1};
  return r;
}

static SrcRange from(const Lexer *lx, int line, int col) {
  SrcRange r = {lx->file, line, col, lx->line, lx->col};
  return r;
}

static void lex_error(Lexer *lx, SrcRange at, const char *msg) {
  lx->errors++;
  if (!lx->quiet) diag_error(at, "%s", msg);
}

static int is_ident_start(int c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
static int is_digit(int c) { return c >= '0' && c <= '9'; }
static int is_ident_char(int c) { return is_ident_start(c) || is_digit(c); }
static int hex_value(int c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

/* ---- whitespace and comments ----------------------------------------- */

static void skip_space(Lexer *lx) {
  for (;;) {
    int c = peekc(lx);
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v') advance(lx);
    else if (c == '/' && peekc2(lx) == '/') {
      while (!at_end(lx) && *lx->p != '\n') advance(lx);
    } else if (c == '/' && peekc2(lx) == '*') {
      int line = lx->line, col = lx->col;
      advance(lx);
      advance(lx);
      while (!at_end(lx) && !(*lx->p == '*' && peekc2(lx) == '/')) advance(lx);
      if (at_end(lx)) {
        SrcRange r = {lx->file, line, col, line, col + 2};
        lex_error(lx, r, "unterminated comment: `/*` has no closing `*/`");
        return;
      }
      advance(lx);
      advance(lx);
    } else return;
  }
}

/* ---- tokens ------------------------------------------------------------ */

/* number := digits ['.' digits] [exp] | '.' digits [exp];  exp := ('e'|'E') ['+'|'-'] digits */
static void lex_number(Lexer *lx, Token *t) {
  const char *start = lx->p;
  int ok = 1;
  while (is_digit(peekc(lx))) advance(lx);
  if (peekc(lx) == '.') {
    advance(lx);
    while (is_digit(peekc(lx))) advance(lx);
  }
  if (peekc(lx) == 'e' || peekc(lx) == 'E') {
    advance(lx);
    if (peekc(lx) == '+' || peekc(lx) == '-') advance(lx);
    if (!is_digit(peekc(lx))) ok = 0;
    while (is_digit(peekc(lx))) advance(lx);
  }
  /* "1.2.3", "12abc", "1e": glue the rest on so the error names it whole */
  while (is_ident_char(peekc(lx)) || (peekc(lx) == '.' && is_digit(peekc2(lx)))) { ok = 0; advance(lx); }
  t->kind = TK_NUMBER;
  t->range = from(lx, t->range.line, t->range.col);
  int len = (int)(lx->p - start);
  if (!ok) {
    lx->errors++;
    if (!lx->quiet) diag_error(t->range, "invalid number `%.*s`", len, start);
    t->number = 0;
    return;
  }
  /* The token is a complete, valid number and the source ends in a NUL, so
  ** strtod stops exactly at its end: no copy needed. */
  t->number = strtod(start, NULL);
  if (!isfinite(t->number)) {
    lx->errors++;
    if (!lx->quiet) diag_error(t->range, "number `%.*s` is too large", len, start);
    t->number = 0;
  }
}

/* Decode \u{…} at p (just after "\u"); returns the code point or -1. */
static long lex_unicode_escape(Lexer *lx) {
  if (peekc(lx) != '{') return -1;
  advance(lx);
  long v = 0;
  int n = 0;
  while (hex_value(peekc(lx)) >= 0) {
    if (n < 7) v = v * 16 + hex_value(peekc(lx));
    n++;
    advance(lx);
  }
  if (peekc(lx) != '}' || n == 0 || n > 6) return -1;
  advance(lx);
  if (v == 0 || v > 0x10FFFF || (v >= 0xD800 && v <= 0xDFFF)) return -1;
  return v;
}

/* string := '"' { char | '\' ('"' | '\' | 'n' | 't' | 'u{' hex+ '}') } '"' */
static void lex_string(Lexer *lx, Token *t) {
  size_t cap = 64, n = 0;
  char *buf = xmalloc(cap);
  advance(lx);  /* opening quote */
  for (;;) {
    int c = peekc(lx);
    if (c < 0 || c == '\n') {
      SrcRange r = from(lx, t->range.line, t->range.col);
      lex_error(lx, r, "unterminated string: missing closing `\"`");
      break;
    }
    if (cap - n < 8) {
      if (cap >= LEX_MAX_STRING) sumi_fatal("string literal longer than %d bytes", LEX_MAX_STRING);
      cap *= 2;
      buf = xrealloc(buf, cap);
    }
    if (c == '"') { advance(lx); break; }
    if (c == '\\') {
      int line = lx->line, col = lx->col;
      advance(lx);
      int e = peekc(lx);
      if (e == '"' || e == '\\') { buf[n++] = (char)e; advance(lx); }
      else if (e == 'n') { buf[n++] = '\n'; advance(lx); }
      else if (e == 't') { buf[n++] = '\t'; advance(lx); }
      else if (e == 'u') {
        advance(lx);
        long cp = lex_unicode_escape(lx);
        if (cp < 0) lex_error(lx, from(lx, line, col), "invalid unicode escape: expected `\\u{…}` with 1 to 6 hex digits naming a character (not U+0000 or a surrogate)");
        else n += (size_t)utf8_encode((uint32_t)cp, buf + n);
      } else if (e < 0 || e == '\n') {
        continue;  /* reported as unterminated above */
      } else {
        char msg[96];
        advance(lx);
        snprintf(msg, sizeof msg, "unknown escape `\\%c` in string (known: \\\" \\\\ \\n \\t \\u{…})",
                 e >= 0x20 && e < 0x7F ? e : '?');
        lex_error(lx, from(lx, line, col), msg);
      }
      continue;
    }
    const char *p0 = lx->p;
    uint32_t cp;
    int len = utf8_decode((const unsigned char *)lx->p, (const unsigned char *)lx->end, &cp);
    if (len == 0 || cp == 0) {
      char what[48];
      if (len == 0) snprintf(what, sizeof what, "invalid UTF-8 byte 0x%02x in string", (unsigned char)*lx->p);
      else snprintf(what, sizeof what, "NUL byte in string");
      lex_error(lx, here(lx), what);
      advance(lx);
      continue;
    }
    memcpy(buf + n, p0, (size_t)len);
    n += (size_t)len;
    advance(lx);
  }
  t->kind = TK_STRING;
  t->range = from(lx, t->range.line, t->range.col);
  t->string = arena_strndup(lx->arena, buf, n);
  free(buf);
}

/* color := '#' hex{3} | '#' hex{6} | '#' hex{8} */
static void lex_color(Lexer *lx, Token *t) {
  const char *start = lx->p;
  advance(lx);
  while (is_ident_char(peekc(lx))) advance(lx);
  int n = (int)(lx->p - start) - 1;
  t->kind = TK_COLOR;
  t->range = from(lx, t->range.line, t->range.col);
  t->color[0] = t->color[1] = t->color[2] = 0;
  t->color[3] = 1;
  int ok = n == 3 || n == 6 || n == 8;
  for (int i = 1; i <= n && ok; i++) ok = hex_value((unsigned char)start[i]) >= 0;
  if (!ok) {
    char *text = arena_strndup(lx->arena, start, (size_t)n + 1);
    lx->errors++;
    if (!lx->quiet) diag_error(t->range, "invalid colour `%s`: expected #rgb, #rrggbb or #rrggbbaa", text);
    return;
  }
  for (int k = 0; k < (n == 3 ? 3 : n / 2); k++) {
    int v = n == 3 ? hex_value(start[1 + k]) * 17
                   : hex_value(start[1 + 2 * k]) * 16 + hex_value(start[2 + 2 * k]);
    t->color[k] = (float)v / 255.0f;
  }
}

static const struct { const char *word; int len; TokenKind kind; } keywords[] = {
  {"include", 7, TK_INCLUDE}, {"use", 3, TK_USE}, {"as", 2, TK_AS}, {"let", 3, TK_LET},
  {"fn", 2, TK_FN}, {"module", 6, TK_MODULE}, {"for", 3, TK_FOR}, {"if", 2, TK_IF},
  {"else", 4, TK_ELSE}, {"each", 4, TK_EACH}, {"true", 4, TK_TRUE}, {"false", 5, TK_FALSE},
  {"undef", 5, TK_UNDEF},
};

static void lex_ident(Lexer *lx, Token *t) {
  const char *start = lx->p;
  /* identifiers are ASCII: step bytes directly */
  while (lx->p < lx->end && is_ident_char((unsigned char)*lx->p)) lx->p++;
  int len = (int)(lx->p - start);
  lx->col += len;
  t->range = from(lx, t->range.line, t->range.col);
  t->kind = TK_IDENT;
  if (len <= 7) {
    for (size_t i = 0; i < sizeof keywords / sizeof keywords[0]; i++) {
      if (keywords[i].len == len && keywords[i].word[0] == start[0] &&
          memcmp(keywords[i].word, start, (size_t)len) == 0) {
        t->kind = keywords[i].kind;
        return;
      }
    }
  }
  t->string = arena_strndup(lx->arena, start, (size_t)len);
}

/* Report the character at p as unexpected and step over it. */
static void lex_stray(Lexer *lx) {
  SrcRange r = here(lx);
  uint32_t cp;
  int n = utf8_decode((const unsigned char *)lx->p, (const unsigned char *)lx->end, &cp);
  char what[64];
  if (n == 0) snprintf(what, sizeof what, "invalid UTF-8 byte 0x%02x", (unsigned char)*lx->p);
  else if (cp == 0) snprintf(what, sizeof what, "NUL byte");
  else if (cp < 0x20 || cp == 0x7F) snprintf(what, sizeof what, "unexpected control character U+%04X", (unsigned)cp);
  else if (cp == '`') snprintf(what, sizeof what, "unexpected backtick (U+0060)");
  else snprintf(what, sizeof what, "unexpected character `%.*s` (U+%04X)", n, lx->p, (unsigned)cp);
  lex_error(lx, r, what);
  advance(lx);
}

/* One- and two-character operators. Returns 0 when c starts none. */
static int lex_operator(Lexer *lx, Token *t) {
  int c = peekc(lx), d = peekc2(lx);
  TokenKind k;
  int two = 0;
  switch (c) {
    case '(': k = TK_LPAREN; break;
    case ')': k = TK_RPAREN; break;
    case '[': k = TK_LBRACKET; break;
    case ']': k = TK_RBRACKET; break;
    case '{': k = TK_LBRACE; break;
    case '}': k = TK_RBRACE; break;
    case ',': k = TK_COMMA; break;
    case ';': k = TK_SEMI; break;
    case ':': k = TK_COLON; break;
    case '.': k = TK_DOT; break;
    case '?': k = TK_QUESTION; break;
    case '+': k = TK_PLUS; break;
    case '-': k = TK_MINUS; break;
    case '*': k = TK_STAR; break;
    case '/': k = TK_SLASH; break;
    case '%': k = TK_PERCENT; break;
    case '^': k = TK_CARET; break;
    case '=': two = d == '='; k = two ? TK_EQ : TK_ASSIGN; break;
    case '!': two = d == '='; k = two ? TK_NE : TK_NOT; break;
    case '<': two = d == '='; k = two ? TK_LE : TK_LT; break;
    case '>': two = d == '='; k = two ? TK_GE : TK_GT; break;
    case '&': if (d != '&') return 0; two = 1; k = TK_AND; break;
    case '|': if (d != '|') return 0; two = 1; k = TK_OR; break;
    default: return 0;
  }
  advance(lx);
  if (two) advance(lx);
  t->kind = k;
  t->range = from(lx, t->range.line, t->range.col);
  return 1;
}

Token lex_next(Lexer *lx) {
  Token t;
  int errors_before = lx->errors;   /* a stray character before it counts too */
  for (;;) {
    skip_space(lx);
    memset(&t, 0, sizeof t);
    t.range = here(lx);
    t.start = lx->p;
    int c = peekc(lx);
    if (c < 0) {
      t.kind = TK_EOF;
      t.range.end_col = t.range.col;
      return t;
    }
    if (is_digit(c) || (c == '.' && is_digit(peekc2(lx)))) lex_number(lx, &t);
    else if (is_ident_start(c)) lex_ident(lx, &t);
    else if (c == '"') lex_string(lx, &t);
    else if (c == '#') lex_color(lx, &t);
    else if (!lex_operator(lx, &t)) { lex_stray(lx); continue; }
    t.len = (int)(lx->p - t.start);
    t.bad = lx->errors > errors_before;
    return t;
  }
}
