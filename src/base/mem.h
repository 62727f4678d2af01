/*
** Memory helpers: allocation that never returns NULL (it ends the program
** with a message instead, as cmark's xcalloc does), and a bump arena.
*/
#ifndef base_mem_h
#define base_mem_h

#include <stddef.h>

/* Print "sumi: fatal: <msg>" to stderr and exit with status 1. */
_Noreturn void sumi_fatal(const char *fmt, ...);

void *xmalloc(size_t n);
void *xcalloc(size_t count, size_t size);
void *xrealloc(void *p, size_t n);
char *xstrdup(const char *s);

/* Ask for transparent huge pages on the whole 2 MB pages inside the block
** [p, p + n): a big buffer then costs a few page faults instead of one per
** 4 KB. A hint only; small blocks are left alone. */
void mem_advise_huge(void *p, size_t n);
/* Fault in the pages of [p, p + n) now, in one call, rather than one
** fault at a time as they are first written: for a fresh buffer about to
** be filled whole. A hint: without kernel support nothing happens. */
void mem_populate(void *p, size_t n);

/* n bytes for a big buffer, freed with free(). From 2 MB up the block is
** aligned to 2 MB and asks for huge pages, as mem_advise_huge. */
void *xmalloc_huge(size_t n);
/* The same, zeroed: a big table. */
void *xcalloc_huge(size_t n);
/* n zero bytes straight from the system, freed with mem_zeroed_free(p, n)
** (the same n): its pages are cleared only as they are first written, so
** a big plane of which a frame writes only a part costs only that part.
** From 2 MB up it asks for huge pages, as mem_advise_huge. */
void *mem_zeroed(size_t n);
void mem_zeroed_free(void *p, size_t n);

/* Set malloc up for a program whose stages allocate and free big buffers
** one after the other: freed memory stays in the heap for the next stage
** (no per-block mmap, no trimming). With frames set (a command that
** renders), the heap's first 64 MB are also backed by transparent huge
** pages, so a frame's buffers fault in 2 MB at a time instead of 4 KB
** (about 2,000 fewer faults, ~1.5 ms, in a 1080p frame); the other
** commands keep 4 KB pages, whose memory follows what they use more
** closely. Call once before any big allocation, and (sumi render does,
** once it knows a frame is big) again with frames set. Hints only: under
** another allocator (sanitizers, valgrind) or without huge pages the
** pages stay as they are. All threads share the one heap (M_ARENA_MAX 1):
** a worker's own arena would keep what the worker freed away from the
** stages after it, which then grow the main heap instead. */
void mem_heap_setup(int frames);
/* Give the heap's free pages back to the system (malloc_trim): after a
** stage whose peak left far more free memory in the heap than the next
** stages will use, in pieces too small or scattered for their big
** buffers, which would otherwise fault in fresh pages on top of it. */
void mem_heap_release(void);

/* Grow *items (of elem bytes each) so it holds at least need; *cap tracks it. */
void *xgrow(void *items, int *cap, int need, size_t elem);

/* An arena hands out memory that is freed all at once by arena_free. */
typedef struct ArenaChunk ArenaChunk;
typedef struct Arena {
  ArenaChunk *head;
  unsigned char *next, *limit;   /* the free part of the head chunk */
  size_t used_total;             /* bytes handed out, for --stats */
} Arena;

void arena_init(Arena *a);
void *arena_alloc(Arena *a, size_t n);          /* zeroed, 16-byte aligned */
char *arena_strndup(Arena *a, const char *s, size_t n);
void arena_free(Arena *a);
/* n bytes (a multiple of 8) at the start of a new chunk: the slow path. */
void *arena_alloc_new_chunk(Arena *a, size_t n);

/* Zeroed and only 8-byte aligned: for the many small objects of a syntax
** tree (nodes, child arrays, names), where rounding each up to 16 bytes
** would cost a fifth of the tree. Inline, as a parse makes millions. */
static inline void *arena_alloc_small(Arena *a, size_t n) {
  n = (n + 7) & ~(size_t)7;   /* next and the chunk's data stay 8-aligned */
  if ((size_t)(a->limit - a->next) < n) return arena_alloc_new_chunk(a, n);
  void *p = a->next;
  a->next += n;
  a->used_total += n;
  return p;
}

#endif
