/*
** Lexical analyser for .npr scripts. It walks UTF-8 text one character at
** a time, keeping line and column (in characters), and hands out tokens.
** Errors are reported at once and the lexer skips past them, so the parser
** never sees a broken token: a bad number becomes 0, a bad colour black, an
** unterminated string what was read of it.
*/
#include "lex.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../base/utf8.h"
#include "habits.h"

#define TOKEN_NAME(name, text) text,
static const char *const token_names[] = {TOKEN_LIST(TOKEN_NAME)};
#undef TOKEN_NAME

const char *token_name(TokenKind k) { return k < TK_COUNT ? token_names[k] : "?"; }

/* Longest string literal after decoding, a named limit (style.md §14). */
#define LEX_MAX_STRING (16 * 1024 * 1024)

/* ---- interned names ---------------------------------------------------- */

/* Every identifier is stored once per parse: an open-addressing hash table
** (linear probing, at most 3/4 full) maps its bytes to the arena copy. The
** keywords are entered first with their token kind, so one probe both
** classifies a word and finds its copy. */
typedef struct LexName {
  const char *text;    /* NUL-terminated, in the arena */
  uint32_t hash;
  uint16_t len;        /* longer names are not interned */
  uint16_t kind;       /* TK_IDENT or a keyword's kind */
} LexName;

/* Slots of recently seen names, picked by hash: the few names a script
** repeats most (keywords, parameters, property words) stay in the first
** level of the cache, where the big table would cost a miss each. */
#define LEX_RECENT 256

struct LexNames {
  LexName *slots;
  uint32_t mask;       /* capacity - 1; capacity is a power of two */
  uint32_t count;
  LexName recent[LEX_RECENT];   /* copies of table entries; text NULL when empty */
};

/* Longest identifier kept in the table; a longer one gets its own copy. */
#define LEX_MAX_INTERNED 0xFFFF

static uint32_t name_hash(const char *s, size_t len) {
  uint32_t h = 2166136261u;   /* FNV-1a */
  for (size_t i = 0; i < len; i++) h = (h ^ (unsigned char)s[i]) * 16777619u;
  return h;
}

static void names_grow(LexNames *t) {
  uint32_t cap = (t->mask + 1) * 2;
  LexName *slots = xcalloc_huge(cap * sizeof *slots);
  for (uint32_t i = 0; i <= t->mask; i++) {
    if (!t->slots[i].text) continue;
    uint32_t j = t->slots[i].hash & (cap - 1);
    while (slots[j].text) j = (j + 1) & (cap - 1);
    slots[j] = t->slots[i];
  }
  free(t->slots);
  t->slots = slots;
  t->mask = cap - 1;
}

/* The table entry for s[0..len) (hash h), added (as TK_IDENT) if new, and
** copied into its recent slot. */
static const LexName *names_find(Lexer *lx, const char *s, size_t len, uint32_t h) {
  LexNames *t = lx->names;
  LexName *r = &t->recent[h % LEX_RECENT];
  uint32_t i = h & t->mask;
  for (; t->slots[i].text; i = (i + 1) & t->mask) {
    const LexName *e = &t->slots[i];
    if (e->hash == h && e->len == len && memcmp(e->text, s, len) == 0) {
      *r = *e;
      return r;
    }
  }
  if ((t->count + 1) * 4 > (t->mask + 1) * 3) {
    names_grow(t);
    for (i = h & t->mask; t->slots[i].text; i = (i + 1) & t->mask) {}
  }
  LexName *e = &t->slots[i];
  e->text = arena_strndup(lx->arena, s, len);
  e->hash = h;
  e->len = (uint16_t)len;
  e->kind = TK_IDENT;
  t->count++;
  *r = *e;
  return e;
}

/* names_find, answered from the recent slots when the name is there. */
static inline const LexName *names_lookup(Lexer *lx, const char *s, size_t len, uint32_t h) {
  const LexName *r = &lx->names->recent[h % LEX_RECENT];
  if (r->text && r->hash == h && r->len == len && memcmp(r->text, s, len) == 0) return r;
  return names_find(lx, s, len, h);
}

static const struct { const char *word; TokenKind kind; } keywords[] = {
  {"include", TK_INCLUDE}, {"use", TK_USE}, {"as", TK_AS}, {"let", TK_LET},
  {"fn", TK_FN}, {"module", TK_MODULE}, {"for", TK_FOR}, {"if", TK_IF},
  {"else", TK_ELSE}, {"each", TK_EACH}, {"true", TK_TRUE}, {"false", TK_FALSE},
  {"undef", TK_UNDEF},
};

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
  lx->prev = TK_EOF;
  lx->names = xcalloc(1, sizeof *lx->names);
  lx->names->mask = 255;
  lx->names->slots = xcalloc(lx->names->mask + 1, sizeof(LexName));
  for (size_t i = 0; i < sizeof keywords / sizeof keywords[0]; i++) {
    size_t len = strlen(keywords[i].word);
    uint32_t h = name_hash(keywords[i].word, len);
    LexName *e = (LexName *)names_lookup(lx, keywords[i].word, len, h);
    e->kind = (uint16_t)keywords[i].kind;
    lx->names->recent[h % LEX_RECENT] = *e;
  }
}

void lex_init_at(Lexer *lx, int file, uint32_t at) {
  const SrcFile *f = diag_file(file);
  memset(lx, 0, sizeof *lx);
  lx->file = file;
  lx->src = f->text;
  lx->end = f->text + f->len;
  lx->p = lx->src + at;
  lx->line = lx->col = 1;
  lx->quiet = 1;
}

void lex_free(Lexer *lx) {
  if (!lx->names) return;
  free(lx->names->slots);
  free(lx->names);
  lx->names = NULL;
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

/* Character classes of the ASCII bytes (all others are 0). */
enum { CC_SPACE = 1, CC_DIGIT = 2, CC_ALPHA = 4, CC_IDENT = CC_DIGIT | CC_ALPHA };
static const unsigned char char_class[256] = {
  0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 1, 1, 1, 0, 0,   /* \t \v \f \r; \n is handled apart */
  0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
  1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,   /* space */
  2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 0, 0, 0, 0, 0, 0,   /* 0-9 */
  0, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4,   /* A-Z */
  4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 0, 0, 0, 0, 4,   /* _ */
  0, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4,   /* a-z */
  4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 0, 0, 0, 0, 0,
};

/* c is a byte, or -1 at the end (which is in no class) */
static int is_ident_start(int c) { return c >= 0 && (char_class[c] & CC_ALPHA); }
static int is_digit(int c) { return c >= 0 && (char_class[c] & CC_DIGIT); }
static int is_ident_char(int c) { return c >= 0 && (char_class[c] & CC_IDENT); }
static int hex_value(int c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

/* ---- whitespace and comments ----------------------------------------- */

static void skip_space(Lexer *lx) {
  for (;;) {
    unsigned char c = (unsigned char)*lx->p;   /* the NUL at the end is no space */
    if (c == '\n') { lx->line++; lx->col = 1; lx->p++; }
    else if (char_class[c] & CC_SPACE) { lx->col++; lx->p++; }
    else if (c == '/' && peekc2(lx) == '/') {
      /* Columns inside the comment matter to nobody: jump to its newline,
      ** which resets them. Only a comment that ends the file is walked. */
      const char *nl = memchr(lx->p, '\n', (size_t)(lx->end - lx->p));
      if (nl) lx->p = nl;
      else while (!at_end(lx)) advance(lx);
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

/* Exact powers of ten as doubles (10^22 is the last one a double holds). */
static const double pow10_exact[] = {
  1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11,
  1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
};

/* The value of a decimal with significand digits m (ndigits of them) and
** exponent e, when one IEEE operation gives it exactly rounded: m and 10^|e|
** are then both exact, so m * 10^e or m / 10^-e is the double nearest the
** decimal, just as strtod's. Returns 0 when it cannot say (then strtod). */
static int decimal_fast(uint64_t m, int ndigits, int e, double *out) {
#if FLT_EVAL_METHOD == 0   /* no excess precision, so no double rounding */
  if (ndigits > 19 || m > ((uint64_t)1 << 53) || e < -22 || e > 22) return 0;
  *out = e < 0 ? (double)m / pow10_exact[-e] : (double)m * pow10_exact[e];
  return 1;
#else
  (void)m; (void)ndigits; (void)e; (void)out;
  return 0;
#endif
}

/* number := digits ['.' digits] [exp] | '.' digits [exp];  exp := ('e'|'E') ['+'|'-'] digits
** Numbers are ASCII, so this steps bytes and adds their count to the column. */
static void lex_number(Lexer *lx, Token *t) {
  const char *start = lx->p, *s = start;
  uint64_t m = 0;
  int ndigits = 0, e = 0, ok = 1;
  for (; char_class[(unsigned char)*s] & CC_DIGIT; s++, ndigits++) m = m * 10 + (uint64_t)(*s - '0');
  if (*s == '.') {
    for (s++; char_class[(unsigned char)*s] & CC_DIGIT; s++, ndigits++, e--) m = m * 10 + (uint64_t)(*s - '0');
  }
  if (*s == 'e' || *s == 'E') {
    s++;
    int neg = *s == '-', x = 0;
    if (*s == '+' || *s == '-') s++;
    if (!(char_class[(unsigned char)*s] & CC_DIGIT)) ok = 0;
    for (; char_class[(unsigned char)*s] & CC_DIGIT; s++) if (x < 100000) x = x * 10 + (*s - '0');
    e += neg ? -x : x;
  }
  /* "1.2.3", "12abc", "1e": glue the rest on so the error names it whole */
  while ((char_class[(unsigned char)*s] & CC_IDENT) ||
         (*s == '.' && (char_class[(unsigned char)s[1]] & CC_DIGIT))) {
    ok = 0;
    s++;
  }
  int len = (int)(s - start);
  lx->p = s;
  lx->col += len;
  t->kind = TK_NUMBER;
  t->range = from(lx, t->range.line, t->range.col);
  if (!ok) {
    lx->errors++;
    if (!lx->quiet) diag_error(t->range, "invalid number `%.*s`", len, start);
    t->number = 0;
    return;
  }
  if (decimal_fast(m, ndigits, e, &t->number)) return;
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
    char *text = arena_strndup(lx->arena, start, (size_t)n + 1), hint[600];
    lx->errors++;
    if (lx->quiet) return;
    if (habit_hint(HABIT_TOKEN, text, NULL, hint, sizeof hint)) diag_error(t->range, "unexpected `%s`%s", text, hint);
    else diag_error(t->range, "invalid colour `%s`: expected #rgb, #rrggbb or #rrggbbaa", text);
    return;
  }
  for (int k = 0; k < (n == 3 ? 3 : n / 2); k++) {
    int v = n == 3 ? hex_value(start[1 + k]) * 17
                   : hex_value(start[1 + 2 * k]) * 16 + hex_value(start[2 + 2 * k]);
    t->color[k] = (float)v / 255.0f;
  }
}

/* IDENT = letter { letter | digit } | '$' letter { letter | digit } */
static void lex_ident(Lexer *lx, Token *t) {
  const char *start = lx->p, *s = start;
  uint32_t h = 2166136261u;   /* name_hash, computed while scanning */
  if (*s == '$') h = (h ^ (unsigned char)*s++) * 16777619u;
  /* identifiers are ASCII: step bytes directly */
  for (; char_class[(unsigned char)*s] & CC_IDENT; s++) h = (h ^ (unsigned char)*s) * 16777619u;
  size_t len = (size_t)(s - start);
  lx->p = s;
  lx->col += (int)len;
  t->range = from(lx, t->range.line, t->range.col);
  if (len > LEX_MAX_INTERNED) {
    t->kind = TK_IDENT;
    t->string = arena_strndup(lx->arena, start, len);
    return;
  }
  const LexName *name = names_lookup(lx, start, len, h);
  t->kind = (TokenKind)name->kind;
  if (t->kind == TK_IDENT) t->string = (char *)name->text;
}

/* OpenSCAD's special variables (`$fn`) are names only where a named
** argument stands: after `(` or `,` and before a lone `=`. Elsewhere the
** `$` is a stray character with a hint. */
static int special_name_here(const Lexer *lx) {
  const char *s = lx->p + 1;
  if ((lx->prev != TK_LPAREN && lx->prev != TK_COMMA) || !is_ident_start((unsigned char)*s)) return 0;
  while (is_ident_char((unsigned char)*s)) s++;
  while (*s == ' ' || *s == '\t') s++;   /* the source ends in a NUL */
  return s[0] == '=' && s[1] != '=';
}

/* Report the character at p as unexpected and step over it. */
static void lex_stray(Lexer *lx) {
  SrcRange r = here(lx);
  uint32_t cp = 0;
  int n = utf8_decode((const unsigned char *)lx->p, (const unsigned char *)lx->end, &cp);
  char what[700], word[32], hint[600];
  int w = 1;   /* `$fn`: the word after a `$` */
  while (cp == '$' && w < 31 && lx->p + w < lx->end && is_ident_char((unsigned char)lx->p[w])) w++;
  snprintf(word, sizeof word, "%.*s", w, lx->p);
  if (n == 0) snprintf(what, sizeof what, "invalid UTF-8 byte 0x%02x", (unsigned char)*lx->p);
  else if (cp == 0) snprintf(what, sizeof what, "NUL byte");
  else if (cp < 0x20 || cp == 0x7F) snprintf(what, sizeof what, "unexpected control character U+%04X", (unsigned)cp);
  else if (cp == '`') snprintf(what, sizeof what, "unexpected backtick (U+0060)");
  else if (cp == '$' && habit_hint(HABIT_TOKEN, word, NULL, hint, sizeof hint))
    snprintf(what, sizeof what, "unexpected `%s`%s", word, hint);
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
  lx->p += 1 + two;   /* operators are ASCII */
  lx->col += 1 + two;
  t->kind = k;
  t->range = from(lx, t->range.line, t->range.col);
  return 1;
}

void lex_next(Lexer *lx, Token *t) {
  int errors_before = lx->errors;   /* a stray character before it counts too */
  for (;;) {
    skip_space(lx);
    t->kind = TK_EOF;
    t->range = here(lx);
    t->start = lx->p;
    t->string = NULL;
    memset(t->color, 0, sizeof t->color);   /* clears the whole union */
    int c = peekc(lx);
    if (c < 0) {
      t->range.end_col = t->range.col;
      t->len = 0;
      t->bad = 0;
      return;
    }
    if (is_digit(c) || (c == '.' && is_digit(peekc2(lx)))) lex_number(lx, t);
    else if (is_ident_start(c) || (c == '$' && special_name_here(lx))) lex_ident(lx, t);
    else if (c == '"') lex_string(lx, t);
    else if (c == '#') lex_color(lx, t);
    else if (!lex_operator(lx, t)) { lex_stray(lx); continue; }
    t->len = (int)(lx->p - t->start);
    t->bad = lx->errors > errors_before;
    lx->prev = t->kind;
    return;
  }
}
