/*
** Lexical analyser: turns UTF-8 .npr text into tokens. Every token carries
** its source range (columns count characters). Bad input (invalid UTF-8, a
** NUL byte, a stray character, an unterminated string or comment, a bad
** number or colour) is reported through diag and yields TK_ERROR, so the
** parser can carry on.
*/
#ifndef lang_lex_h
#define lang_lex_h

#include <stdint.h>

#include "../base/mem.h"
#include "diag.h"

/* ORDER TOKEN: lex.c's token_names[] follows this list. */
#define TOKEN_LIST(X) \
  X(TK_EOF, "end of file") X(TK_ERROR, "invalid token") \
  X(TK_NUMBER, "number") X(TK_STRING, "string") X(TK_COLOR, "colour") X(TK_IDENT, "identifier") \
  X(TK_INCLUDE, "`include`") X(TK_USE, "`use`") X(TK_AS, "`as`") X(TK_LET, "`let`") \
  X(TK_FN, "`fn`") X(TK_MODULE, "`module`") X(TK_FOR, "`for`") X(TK_IF, "`if`") \
  X(TK_ELSE, "`else`") X(TK_EACH, "`each`") X(TK_TRUE, "`true`") X(TK_FALSE, "`false`") \
  X(TK_UNDEF, "`undef`") \
  X(TK_LPAREN, "`(`") X(TK_RPAREN, "`)`") X(TK_LBRACKET, "`[`") X(TK_RBRACKET, "`]`") \
  X(TK_LBRACE, "`{`") X(TK_RBRACE, "`}`") X(TK_COMMA, "`,`") X(TK_SEMI, "`;`") \
  X(TK_COLON, "`:`") X(TK_DOT, "`.`") X(TK_QUESTION, "`?`") X(TK_ASSIGN, "`=`") \
  X(TK_PLUS, "`+`") X(TK_MINUS, "`-`") X(TK_STAR, "`*`") X(TK_SLASH, "`/`") \
  X(TK_PERCENT, "`%`") X(TK_CARET, "`^`") X(TK_NOT, "`!`") X(TK_AND, "`&&`") \
  X(TK_OR, "`||`") X(TK_EQ, "`==`") X(TK_NE, "`!=`") X(TK_LT, "`<`") X(TK_LE, "`<=`") \
  X(TK_GT, "`>`") X(TK_GE, "`>=`")

#define TOKEN_ENUM(name, text) name,
typedef enum { TOKEN_LIST(TOKEN_ENUM) TK_COUNT } TokenKind;
#undef TOKEN_ENUM

typedef struct Token {
  TokenKind kind;
  int len;             /* byte length */
  int bad;             /* the lexer reported an error inside this token */
  SrcRange range;
  const char *start;   /* the token's bytes in the source */
  /* NULL for other kinds: the parser's error paths may read it from any token */
  char *string;        /* TK_STRING (decoded, arena) and TK_IDENT (interned, arena) */
  union {              /* which one: kind */
    double number;     /* TK_NUMBER */
    float color[4];    /* TK_COLOR: sRGB components in [0, 1] */
  };
} Token;

typedef struct LexNames LexNames;

typedef struct Lexer {
  int file;            /* diag file index */
  const char *src, *end, *p;
  int line, col;       /* of p */
  Arena *arena;
  LexNames *names;     /* interned identifiers, shared by copies of the lexer */
  int quiet;           /* lookahead: report nothing */
  int errors;          /* errors reported so far */
  TokenKind prev;      /* the last token scanned (TK_EOF at the start) */
} Lexer;

/* The source must end in a NUL byte (diag_add_file's contract): the lexer
** reads one byte past a character without checking for the end. */
void lex_init(Lexer *lx, int file, Arena *arena);
/* A quiet lexer from byte offset `at` of the file, with no arena and no
** name table: only for reading back tokens known to be numbers and
** punctuation (ast.c's ast_numbers). Its lines and columns mean nothing. */
void lex_init_at(Lexer *lx, int file, uint32_t at);
/* Free the name table; the names themselves live in the arena. */
void lex_free(Lexer *lx);
/* Scan the next token into *t. Errors are reported and give TK_ERROR. */
void lex_next(Lexer *lx, Token *t);
const char *token_name(TokenKind k);

#endif
