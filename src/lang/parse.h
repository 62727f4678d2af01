/*
** The parser: hand-written recursive descent over the grammar in
** grammar/npr.ebnf. Each parse function begins with the rule it implements.
*/
#ifndef lang_parse_h
#define lang_parse_h

#include "ast.h"

/* Deepest nesting of expressions and blocks before a diagnostic (keeps the
** recursive descent far from the C stack's end on any input). */
#define PARSE_MAX_DEPTH 512

/* Parse the source registered as diag file `file` into an AST allocated in
** arena. Always returns a program node (possibly partial); errors were
** reported through diag. */
AstNode *parse_file(int file, Arena *arena);

/* Parse a whole source as one expression (for -D name=value). NULL after
** reporting an error. */
AstNode *parse_expression_file(int file, Arena *arena);

#endif
