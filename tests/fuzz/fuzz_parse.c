/*
** libFuzzer target over the lexer and parser: any byte string must end in
** an AST or diagnostics, never a crash, a leak or a hang. Diagnostics are
** counted, not printed, so the fuzzer's output stays readable.
*/
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../src/base/mem.h"
#include "../../src/lang/diag.h"
#include "../../src/lang/parse.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  static FILE *sink;
  if (!sink) sink = fopen("/dev/null", "w");
  char *text = xmalloc(size + 1);
  memcpy(text, data, size);
  text[size] = '\0';
  diag_init(DIAG_SILENT);
  int file = diag_add_file("fuzz.npr", text, size, -1, src_none());
  Arena arena;
  arena_init(&arena);
  AstNode *prog = parse_file(file, &arena);
  if (prog && sink) ast_print(prog, sink);
  arena_free(&arena);
  diag_shutdown();
  return 0;
}
