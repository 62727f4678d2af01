/*
** libFuzzer target over mesh import (OBJ through Assimp, then sumi's
** welding, face copying and OBJ vertex order), in this process so the
** fuzzer sees the coverage: any bytes must end in a mesh or a message,
** never a crash, a leak or a hang.
*/
#include "../../src/io/mesh_import.h"
#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const char *path = fuzz_file(data, size, "obj");
  Arena arena;
  arena_init(&arena);
  SceneGeometry g;
  char err[512];
  mesh_import_file_in_process(path, &g, &arena, err, sizeof err);
  arena_free(&arena);
  return 0;
}
