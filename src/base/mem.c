/*
** Allocation that aborts on failure, and the arena used by the AST and scene.
*/
#include "mem.h"

#include <malloc.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

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

#if defined(MADV_HUGEPAGE) || defined(MADV_POPULATE_WRITE)
/* madvise(advice) on the whole pages of size page inside [p, p + n). */
static void advise_inside(void *p, size_t n, uintptr_t page, int advice) {
  uintptr_t lo = ((uintptr_t)p + page - 1) & ~(page - 1), hi = ((uintptr_t)p + n) & ~(page - 1);
  if (hi > lo) madvise((void *)lo, hi - lo, advice);   /* a hint: failure only costs speed */
}
#endif

void mem_advise_huge(void *p, size_t n) {
#ifdef MADV_HUGEPAGE
  advise_inside(p, n, (uintptr_t)2 << 20, MADV_HUGEPAGE);
#else
  (void)p;
  (void)n;
#endif
}

void mem_populate(void *p, size_t n) {
#ifdef MADV_POPULATE_WRITE
  advise_inside(p, n, 4096, MADV_POPULATE_WRITE);
#else
  (void)p;
  (void)n;
#endif
}

void mem_heap_setup(int frames) {
  mallopt(M_ARENA_MAX, 1);
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
#ifdef MADV_HUGEPAGE
  if (!frames) return;
  mallopt(M_TOP_PAD, 64 << 20);              /* the heap grows 64 MB at a time */
  char *lo = sbrk(0);
  void *volatile p = malloc(1 << 20);        /* ... once now (volatile: the call must stay) */
  char *hi = sbrk(0);
  if (hi > lo) mem_advise_huge(lo, (size_t)(hi - lo));   /* malloc's heap did grow */
  free(p);
#else
  (void)frames;
#endif
}

void mem_heap_release(void) {
  malloc_trim(0);
}

void *xmalloc_huge(size_t n) {
  const size_t huge = (size_t)2 << 20;
  if (n < huge) return xmalloc(n);
  n = (n + huge - 1) & ~(huge - 1);   /* aligned_alloc wants a multiple */
  void *p = aligned_alloc(huge, n);
  if (!p) sumi_fatal("out of memory (asked for %zu bytes)", n);
  mem_advise_huge(p, n);
  return p;
}

void *xcalloc_huge(size_t n) {
  return memset(xmalloc_huge(n), 0, n);
}

/* A mapping of n bytes: whole huge pages, so that the kernel places it on
** a huge page's boundary. */
static size_t zeroed_size(size_t n) {
  const size_t huge = (size_t)2 << 20;
  return (n + huge - 1) & ~(huge - 1);
}

void *mem_zeroed(size_t n) {
  if (n < ((size_t)2 << 20)) return xcalloc(1, n);
  void *p = mmap(NULL, zeroed_size(n), PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) sumi_fatal("out of memory (asked for %zu bytes)", n);
  mem_advise_huge(p, zeroed_size(n));
  return p;
}

void mem_zeroed_free(void *p, size_t n) {
  if (!p) return;
  if (n < ((size_t)2 << 20)) free(p);
  else munmap(p, zeroed_size(n));
}

/* ---- arena ---------------------------------------------------------- */

struct ArenaChunk {
  ArenaChunk *next;
  size_t size;   /* bytes of data */
  _Alignas(16) unsigned char data[];
};

/* Chunks come from mmap, so they arrive zeroed and arena_alloc need not
** clear anything. Each chunk is twice the last (up to ARENA_CHUNK_MAX), and
** large ones ask for transparent huge pages: a 10 MB script's syntax tree
** then costs a few hundred page faults instead of tens of thousands. */
#define ARENA_CHUNK_MIN ((size_t)1 << 20)
#define ARENA_CHUNK_MAX ((size_t)64 << 20)
#define ARENA_HUGE_PAGE ((size_t)2 << 20)

static ArenaChunk *chunk_map(size_t bytes) {
  void *p = mmap(NULL, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) sumi_fatal("out of memory (arena chunk of %zu bytes)", bytes);
#ifdef MADV_HUGEPAGE
  if (bytes >= ARENA_HUGE_PAGE) madvise(p, bytes, MADV_HUGEPAGE);
#endif
  return p;
}

void arena_init(Arena *a) {
  a->head = NULL;
  a->next = a->limit = NULL;
  a->used_total = 0;
}

void *arena_alloc_new_chunk(Arena *a, size_t n) {
  size_t size = a->head ? (a->head->size + sizeof(ArenaChunk)) * 2 : ARENA_CHUNK_MIN;
  if (size > ARENA_CHUNK_MAX) size = ARENA_CHUNK_MAX;
  if (size < n + sizeof(ArenaChunk)) size = n + sizeof(ArenaChunk);
  ArenaChunk *c = chunk_map(size);
  c->size = size - sizeof(ArenaChunk);
  c->next = a->head;
  a->head = c;
  a->next = c->data + n;   /* data is 16-aligned */
  a->limit = c->data + c->size;
  a->used_total += n;
  return c->data;
}

void *arena_alloc(Arena *a, size_t n) {
  n = (n + 15) & ~(size_t)15;
  unsigned char *p = (unsigned char *)(((uintptr_t)a->next + 15) & ~(uintptr_t)15);
  if (!a->next || p > a->limit || (size_t)(a->limit - p) < n) return arena_alloc_new_chunk(a, n);
  a->next = p + n;
  a->used_total += n;
  return p;
}

char *arena_strndup(Arena *a, const char *s, size_t n) {
  char *p = arena_alloc_small(a, n + 1);
  memcpy(p, s, n);
  p[n] = '\0';
  return p;
}

void arena_free(Arena *a) {
  ArenaChunk *c = a->head;
  while (c) {
    ArenaChunk *next = c->next;
    munmap(c, c->size + sizeof(ArenaChunk));
    c = next;
  }
  a->head = NULL;
  a->next = a->limit = NULL;
  a->used_total = 0;
}
