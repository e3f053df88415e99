/* MT19937 (Matsumoto and Nishimura 1998), the random source of the papers.
 * Each user owns its generator: there is no global random state. */
#ifndef RELIEF_HOST_RNG_H
#define RELIEF_HOST_RNG_H

#include <stddef.h>
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

/* relief_rng_below in two steps, for a caller that knows n only to lie in
 * 1..n_max when it draws: x = relief_rng_next(rng) is the draw's first
 * output. relief_rng_below_one(x, n_max) is 1 when x ends the draw for every
 * such n (as it nearly always does), so that the draw took one output;
 * otherwise relief_rng_below_from(rng, x, n) finishes it for the true n,
 * taking what further outputs relief_rng_below would. Either way the
 * generator ends where relief_rng_below(rng, n) leaves it, and
 * relief_rng_below_from returns its value. */
int relief_rng_below_one(uint32_t x, uint32_t n_max);
uint32_t relief_rng_below_from(relief_rng *rng, uint32_t x, uint32_t n);

/* Standard normal deviate (Box-Muller, two uniforms per call). */
double relief_rng_normal(relief_rng *rng);

/* A deterministic random subset: pick[0..m-1] = m distinct indices of
 * 0..n-1 in ascending order, drawn without replacement by a partial
 * Fisher-Yates shuffle from an MT19937 seeded with `seed` (all of them when
 * m >= n). pick has room for n; pick[m..n-1] is scratch. n < 2^32. */
void relief_rng_subset(size_t *pick, size_t n, size_t m, uint32_t seed);

#endif
