/*
** Sorting 64-bit keys: a least-significant-digit radix sort (stable, linear
** in the keys), for the millions of packed pairs the layer solver dedupes,
** where qsort's comparator calls would dominate.
*/
#ifndef base_sort_h
#define base_sort_h

#include <stddef.h>
#include <stdint.h>

/* Sort keys[0..n) ascending in place (a scratch buffer of n keys is
** allocated and freed). Only the bytes that differ between keys are passed
** over. */
void sort_u64(uint64_t *keys, size_t n);

/* Sort and drop repeats; returns the number of distinct keys left at the front. */
size_t sort_unique_u64(uint64_t *keys, size_t n);

#endif
