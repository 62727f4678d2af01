/*
** libFuzzer target over FOLD import: any bytes must end in a crease
** pattern (then built and folded, as `sumi fold` does) or a message,
** never a crash, a leak or a hang.
*/
#include <string.h>

#include "../../src/geom/origami.h"
#include "../../src/io/fold.h"
#include "../../src/lang/diag.h"
#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const char *path = fuzz_file(data, size, "fold");
  diag_init(DIAG_SILENT);
  Arena arena;
  arena_init(&arena);
  SceneOrigami o;
  char err[512];
  memset(&o, 0, sizeof o);
  if (fold_read(path, &o, &arena, err, sizeof err) == 0) {
    o.loc = src_none();
    o.loc.file = diag_add_file("fuzz.fold", xstrdup(""), 0, -1, src_none());
    o.loc.line = o.loc.col = o.loc.end_line = 1, o.loc.end_col = 2;
    origami_free(origami_build(&o, 1));
    origami_free(origami_build_folded(&o));
  }
  arena_free(&arena);
  diag_shutdown();
  return 0;
}
