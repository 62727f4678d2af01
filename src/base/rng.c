/*
** PCG32: 64-bit LCG state, permuted 32-bit output.
*/
#include "rng.h"

void rng_seed(Rng *r, uint64_t seed, uint64_t stream) {
  r->state = 0;
  r->inc = (stream << 1u) | 1u;
  rng_next(r);
  r->state += seed;
  rng_next(r);
}

double rng_uniform(Rng *r) { return rng_next(r) * (1.0 / 4294967296.0); }

void rng_seed_key(Rng *r, uint64_t seed, uint32_t object, uint32_t stroke) {
  rng_seed(r, seed, ((uint64_t)object << 32) | stroke);
}
