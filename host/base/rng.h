/* MT19937 (Matsumoto and Nishimura 1998), the random source of the papers.
 * Each user owns its generator: there is no global random state. */
#ifndef RELIEF_HOST_RNG_H
#define RELIEF_HOST_RNG_H

#include <stdint.h>

typedef struct relief_rng {
    uint32_t mt[624];
    int index;
} relief_rng;

/* Seed as std::mt19937(seed) does: the same sequence as the C++ library. */
void relief_rng_seed(relief_rng *rng, uint32_t seed);

/* Next 32-bit output. */
uint32_t relief_rng_next(relief_rng *rng);

/* Uniform double in [0, 1) with 53 random bits (two draws). */
double relief_rng_uniform(relief_rng *rng);

/* Uniform integer in [0, n) without modulo bias; n >= 1. */
uint32_t relief_rng_below(relief_rng *rng, uint32_t n);

/* Standard normal deviate (Box-Muller, two uniforms per call). */
double relief_rng_normal(relief_rng *rng);

#endif
