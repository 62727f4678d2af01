/*
** Allocation that aborts on failure, and the arena used by the AST and scene.
*/
#include "mem.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

_Noreturn void sumi_fatal(const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  fputs("sumi: fatal: ", stderr);
  vfprintf(stderr, fmt, ap);
  fputc('\n', stderr);
  va_end(ap);
  exit(1);
}

void *xmalloc(size_t n) {
  void *p = malloc(n ? n : 1);
  if (!p) sumi_fatal("out of memory (asked for %zu bytes)", n);
  return p;
}

void *xcalloc(size_t count, size_t size) {
  void *p = calloc(count ? count : 1, size ? size : 1);
  if (!p) sumi_fatal("out of memory (asked for %zu x %zu bytes)", count, size);
  return p;
}

void *xrealloc(void *p, size_t n) {
  void *q = realloc(p, n ? n : 1);
  if (!q) sumi_fatal("out of memory (asked for %zu bytes)", n);
  return q;
}

char *xstrdup(const char *s) {
  size_t n = strlen(s) + 1;
  return memcpy(xmalloc(n), s, n);
}

void *xgrow(void *items, int *cap, int need, size_t elem) {
  if (need <= *cap) return items;
  int c = *cap ? *cap : 8;
  while (c < need) {
    if (c > (1 << 29)) sumi_fatal("array grew past 2^30 elements");
    c *= 2;
  }
  *cap = c;
  return xrealloc(items, (size_t)c * elem);
}

/* ---- arena ---------------------------------------------------------- */

struct ArenaChunk {
  ArenaChunk *next;
  size_t size, used;
  _Alignas(16) unsigned char data[];
};

/* Chunks are large enough to come from mmap, so calloc hands them out
** already zeroed and arena_alloc need not clear anything. */
#define ARENA_CHUNK_MIN (1024 * 1024)

void arena_init(Arena *a) {
  a->head = NULL;
  a->used_total = 0;
}

void *arena_alloc(Arena *a, size_t n) {
  n = (n + 15) & ~(size_t)15;
  ArenaChunk *c = a->head;
  if (!c || c->size - c->used < n) {
    size_t size = n > ARENA_CHUNK_MIN ? n : ARENA_CHUNK_MIN;
    c = xcalloc(1, sizeof(ArenaChunk) + size);
    c->size = size;
    c->used = 0;
    c->next = a->head;
    a->head = c;
  }
  void *p = c->data + c->used;
  c->used += n;
  a->used_total += n;
  return p;
}

char *arena_strndup(Arena *a, const char *s, size_t n) {
  char *p = arena_alloc(a, n + 1);
  memcpy(p, s, n);
  p[n] = '\0';
  return p;
}

void arena_free(Arena *a) {
  ArenaChunk *c = a->head;
  while (c) {
    ArenaChunk *next = c->next;
    free(c);
    c = next;
  }
  a->head = NULL;
  a->used_total = 0;
}
