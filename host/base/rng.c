#include "base/rng.h"

#include <math.h>
#include <stdlib.h>

#include "base/compare.h"

void relief_rng_seed(relief_rng *rng, uint32_t seed)
{
    rng->mt[0] = seed;
    for (int i = 1; i < 624; ++i)
        rng->mt[i] = 1812433253u * (rng->mt[i - 1] ^ (rng->mt[i - 1] >> 30)) + (uint32_t)i;
    rng->index = 624;
}

uint32_t relief_rng_next(relief_rng *rng)
{
    uint32_t y;
    if (rng->index >= 624) {
        for (int i = 0; i < 624; ++i) {
            y = (rng->mt[i] & 0x80000000u) | (rng->mt[(i + 1) % 624] & 0x7fffffffu);
            rng->mt[i] = rng->mt[(i + 397) % 624] ^ (y >> 1) ^ ((y & 1u) ? 0x9908b0dfu : 0u);
        }
        rng->index = 0;
    }
    y = rng->mt[rng->index++];
    y ^= y >> 11;
    y ^= (y << 7) & 0x9d2c5680u;
    y ^= (y << 15) & 0xefc60000u;
    y ^= y >> 18;
    return y;
}

double relief_rng_uniform(relief_rng *rng)
{
    uint32_t a = relief_rng_next(rng) >> 5, b = relief_rng_next(rng) >> 6;
    return (a * 67108864.0 + b) * (1.0 / 9007199254740992.0);
}

uint32_t relief_rng_below(relief_rng *rng, uint32_t n)
{
    return relief_rng_below_from(rng, relief_rng_next(rng), n);
}

/* The limit below is at least UINT32_MAX - (n - 1) > UINT32_MAX - n_max. */
int relief_rng_below_one(uint32_t x, uint32_t n_max) { return x <= UINT32_MAX - n_max; }

uint32_t relief_rng_below_from(relief_rng *rng, uint32_t x, uint32_t n)
{
    /* Reject the top partial copy of [0, n) so every value is equally likely. */
    const uint32_t limit = UINT32_MAX - UINT32_MAX % n;
    while (x >= limit)
        x = relief_rng_next(rng);
    return x % n;
}

double relief_rng_normal(relief_rng *rng)
{
    double u1 = relief_rng_uniform(rng), u2 = relief_rng_uniform(rng);
    if (u1 < 1e-300)
        u1 = 1e-300;
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

void relief_rng_subset(size_t *pick, size_t n, size_t m, uint32_t seed)
{
    for (size_t i = 0; i < n; ++i)
        pick[i] = i;
    if (m >= n)
        return;
    relief_rng rng;
    relief_rng_seed(&rng, seed);
    for (size_t i = 0; i < m; ++i) {
        size_t j = i + (size_t)relief_rng_below(&rng, (uint32_t)(n - i)), t = pick[i];
        pick[i] = pick[j];
        pick[j] = t;
    }
    qsort(pick, m, sizeof *pick, relief_cmp_size);
}
