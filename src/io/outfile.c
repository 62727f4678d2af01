/*
** Whether an output file is whole (outfile.h).
*/
#include "outfile.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "image.h"

/* Directories a TIFF walk follows at most (the chain and the Exif ones):
** a loop of offsets ends there. */
#define TIFF_MAX_IFDS 64

/* Does the file f (size bytes) end with the text tail? */
static int ends_with(FILE *f, long long size, const char *tail) {
  char buf[64];
  size_t n = strlen(tail);
  return (long long)n <= size && n < sizeof buf && fseek(f, -(long)n, SEEK_END) == 0 &&
         fread(buf, 1, n, f) == n && memcmp(buf, tail, n) == 0;
}

/* A classic TIFF being walked: its byte order and size. */
typedef struct Tiff {
  FILE *f;
  int big_endian;
  long long size;
} Tiff;

/* The n-byte (2 or 4) unsigned number at offset at, or -1 past the end. */
static long long tiff_uint(const Tiff *t, long long at, int n) {
  unsigned char b[4];
  if (at < 0 || at + n > t->size || fseek(t->f, (long)at, SEEK_SET) != 0 || fread(b, 1, (size_t)n, t->f) != (size_t)n)
    return -1;
  uint32_t v = 0;
  for (int i = 0; i < n; i++) v |= (uint32_t)b[t->big_endian ? i : n - 1 - i] << (8 * (n - 1 - i));
  return v;
}

/* Bytes of one value of TIFF field type `type` (0 for an unknown type). */
static int tiff_type_size(long long type) {
  static const int size[] = {0, 1, 1, 2, 4, 8, 1, 1, 2, 4, 8, 4, 8, 4};   /* BYTE .. IFD */
  return type >= 0 && type < (long long)(sizeof size / sizeof size[0]) ? size[type] : 0;
}

/* Do the count strips (or tiles) whose offsets (on bytes each) are at
** offs_at and lengths (ln bytes each) at lens_at all end inside the file? */
static int tiff_spans_ok(const Tiff *t, long long offs_at, int on, long long lens_at, int ln, long long count) {
  for (long long i = 0; i < count; i++) {
    long long off = tiff_uint(t, offs_at + i * on, on), len = tiff_uint(t, lens_at + i * ln, ln);
    if (off < 0 || len < 0 || off + len > t->size) return 0;
  }
  return 1;
}

/* Walk the directory at ifd and those it leads to (the next one, an Exif
** one): every entry's values and every strip or tile must lie inside the
** file. *left counts the directories the walk may still visit. */
static int tiff_ifd_ok(const Tiff *t, long long ifd, int *left) {
  while (ifd) {
    long long n = tiff_uint(t, ifd, 2);
    if (n < 0 || --*left < 0) return 0;
    long long offs[2] = {-1, -1}, lens[2] = {-1, -1}, count[2] = {0, 0};
    int osize[2] = {0, 0}, lsize[2] = {0, 0};
    for (long long e = 0; e < n; e++) {
      long long at = ifd + 2 + 12 * e;
      long long tag = tiff_uint(t, at, 2), type = tiff_uint(t, at + 2, 2), cnt = tiff_uint(t, at + 4, 4);
      int sz = tiff_type_size(type);
      if (tag < 0 || cnt < 0 || !sz) return 0;
      long long where = cnt * sz > 4 ? tiff_uint(t, at + 8, 4) : at + 8;   /* the values, or in the entry */
      if (where < 0 || where + cnt * sz > t->size) return 0;
      int k = tag == 273 || tag == 279 ? 0 : tag == 324 || tag == 325 ? 1 : -1;   /* strips, tiles */
      if (k >= 0 && (tag == 273 || tag == 324)) offs[k] = where, osize[k] = sz, count[k] = cnt;
      if (k >= 0 && (tag == 279 || tag == 325)) lens[k] = where, lsize[k] = sz;
      if (tag == 34665 && !tiff_ifd_ok(t, tiff_uint(t, where, 4), left)) return 0;   /* the Exif directory */
    }
    for (int k = 0; k < 2; k++)
      if (offs[k] >= 0 && (lens[k] < 0 || !tiff_spans_ok(t, offs[k], osize[k], lens[k], lsize[k], count[k])))
        return 0;
    ifd = tiff_uint(t, ifd + 2 + 12 * n, 4);   /* the next directory, 0 at the end */
    if (ifd < 0) return 0;
  }
  return 1;
}

/* Does every byte a classic TIFF's directories point to lie in the file? */
static int tiff_whole(FILE *f, long long size) {
  unsigned char head[4];
  if (fread(head, 1, 4, f) != 4 || head[0] != head[1] || (head[0] != 'I' && head[0] != 'M')) return 0;
  Tiff t = {f, head[0] == 'M', size};
  int left = TIFF_MAX_IFDS;
  return tiff_uint(&t, 2, 2) == 42 && tiff_ifd_ok(&t, tiff_uint(&t, 4, 4), &left);
}

int outfile_complete(const char *path) {
  struct stat st;
  if (stat(path, &st) != 0 || !S_ISREG(st.st_mode)) return 0;
  const char *ext = strrchr(path, '.');
  ext = ext ? ext + 1 : "";
  FILE *f = fopen(path, "rb");
  if (!f) return 0;
  int ok = 1;
  if (!strcasecmp(ext, "svg")) ok = ends_with(f, st.st_size, "</svg>\n");
  else if (!strcasecmp(ext, "tif") || !strcasecmp(ext, "tiff")) ok = tiff_whole(f, st.st_size);
  fclose(f);
  return ok && (!strcasecmp(ext, "svg") || image_file_reads_whole(path));
}
