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

/* Grow *items (of elem bytes each) so it holds at least need; *cap tracks it. */
void *xgrow(void *items, int *cap, int need, size_t elem);

/* An arena hands out memory that is freed all at once by arena_free. */
typedef struct ArenaChunk ArenaChunk;
typedef struct Arena {
  ArenaChunk *head;
  size_t used_total;   /* bytes handed out, for --stats */
} Arena;

void arena_init(Arena *a);
void *arena_alloc(Arena *a, size_t n);          /* zeroed, 16-byte aligned */
char *arena_strndup(Arena *a, const char *s, size_t n);
void arena_free(Arena *a);

#endif
