/*
** What the file-reading fuzz targets share: the input written to a file
** of this process's own, since the readers under test take a path.
*/
#ifndef tests_fuzz_common_h
#define tests_fuzz_common_h

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* data written to /tmp/sumi-fuzz-PID.EXT (the same name every run); the path. */
static const char *fuzz_file(const uint8_t *data, size_t size, const char *ext) {
  static char path[64];
  snprintf(path, sizeof path, "/tmp/sumi-fuzz-%d.%s", (int)getpid(), ext);
  FILE *f = fopen(path, "wb");
  if (!f) abort();
  if (size && fwrite(data, 1, size, f) != size) abort();
  fclose(f);
  return path;
}

#endif
