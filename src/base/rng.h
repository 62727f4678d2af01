/*
** PCG32 (O'Neill, pcg-random.org, "XSH RR" output): the one documented
** generator behind rands() and every random choice of the renderer, so
** results never change between machines or versions.
*/
#ifndef base_rng_h
#define base_rng_h

#include <stdint.h>

typedef struct Rng { uint64_t state, inc; } Rng;

void rng_seed(Rng *r, uint64_t seed, uint64_t stream);

/* The next 32 bits (inline: the brush draws one per bristle and pixel). */
static inline uint32_t rng_next(Rng *r) {
  uint64_t old = r->state;
  r->state = old * 6364136223846793005ULL + r->inc;
  uint32_t xorshifted = (uint32_t)(((old >> 18u) ^ old) >> 27u);
  uint32_t rot = (uint32_t)(old >> 59u);
  return (xorshifted >> rot) | (xorshifted << ((-rot) & 31));
}

double rng_uniform(Rng *r);                 /* in [0, 1) with 32 random bits */
/* A stream keyed by (object, stroke) so parallel work stays deterministic. */
void rng_seed_key(Rng *r, uint64_t seed, uint32_t object, uint32_t stroke);

#endif
