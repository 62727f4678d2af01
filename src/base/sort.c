/*
** Radix sort of 64-bit keys, 8 bits a pass, skipping passes on bytes that
** are the same in every key.
*/
#include "sort.h"

#include <stdlib.h>
#include <string.h>

#include "mem.h"

void sort_u64(uint64_t *keys, size_t n) {
  if (n < 2) return;
  uint64_t all_or = 0, all_and = ~(uint64_t)0;
  for (size_t i = 0; i < n; i++) all_or |= keys[i], all_and &= keys[i];
  uint64_t varying = all_or ^ all_and;                 /* bits not shared by every key */
  uint64_t *tmp = xmalloc(n * sizeof *tmp), *src = keys, *dst = tmp;
  for (int shift = 0; shift < 64; shift += 8) {
    if (((varying >> shift) & 0xff) == 0) continue;
    size_t count[256] = {0};
    for (size_t i = 0; i < n; i++) count[(src[i] >> shift) & 0xff]++;
    size_t pos = 0;
    for (int b = 0; b < 256; b++) {
      size_t c = count[b];
      count[b] = pos;
      pos += c;
    }
    for (size_t i = 0; i < n; i++) dst[count[(src[i] >> shift) & 0xff]++] = src[i];
    uint64_t *t = src;
    src = dst;
    dst = t;
  }
  if (src != keys) memcpy(keys, src, n * sizeof *keys);
  free(tmp);
}

size_t sort_unique_u64(uint64_t *keys, size_t n) {
  sort_u64(keys, n);
  size_t m = 0;
  for (size_t i = 0; i < n; i++)
    if (m == 0 || keys[m - 1] != keys[i]) keys[m++] = keys[i];
  return m;
}
