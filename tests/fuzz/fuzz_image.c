/*
** libFuzzer target over image reading (image_read: PNG through libpng, any
** other format through the OpenImageIO bridge): any bytes must end in an
** image or a message, never a crash, a leak or a hang.
*/
#include "../../src/io/image.h"
#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const char *path = fuzz_file(data, size, "img");
  Image *img = NULL;
  char err[512];
  if (image_read(path, &img, err, sizeof err)) image_destroy(img);
  return 0;
}
