/*
** libFuzzer target over the evaluator: parse, evaluate and check the
** origami of any text under small limits. Every input must end in a scene
** or diagnostics, never a crash, a leak, a hang or memory past the limits.
*/
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../../src/base/mem.h"
#include "../../src/geom/origami.h"
#include "../../src/lang/diag.h"
#include "../../src/lang/eval.h"
#include "../../src/lang/parse.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  char *text = xmalloc(size + 1);
  memcpy(text, data, size);
  text[size] = '\0';
  diag_init(DIAG_SILENT);
  int file = diag_add_file("fuzz.npr", text, size, -1, src_none());
  Arena arena;
  arena_init(&arena);
  AstNode *prog = parse_file(file, &arena);
  if (prog && !diag_error_count()) {
    EvalOptions eo;
    eval_options_init(&eo);
    eo.max_recursion = 200;
    eo.max_iterations = 200000;
    eo.max_list = 100000;
    eo.max_memory = 64LL << 20;
    Scene scene;
    scene_init(&scene);
    if (eval_program(prog, file, &arena, &eo, &scene) == 0) origami_check_scene(&scene);
    scene_free(&scene);
  }
  arena_free(&arena);
  diag_shutdown();
  return 0;
}
