/* MT19937 (base/rng.h): std::mt19937's outputs, and relief_rng_below in
 * two steps (relief_rng_below_one, relief_rng_below_from) leaving the
 * generator where relief_rng_below leaves it, with the same value, for n
 * where a first output is nearly always kept and for n where it is
 * rejected about half the time. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "base/rng.h"

/* The C++ standard's check: the 10000th output of a default-constructed
 * std::mt19937 (seed 5489) is 4123659995. */
static void check_mt19937(void)
{
    relief_rng rng;
    uint32_t x = 0;
    relief_rng_seed(&rng, 5489u);
    for (int i = 0; i < 10000; ++i)
        x = relief_rng_next(&rng);
    CHECK(x == 4123659995u, "10000th output %u, not 4123659995", x);
}

/* n_max bounds n: one stream draws with relief_rng_below, the other in two
 * steps; both must give the same values and stay in step. Returns how many
 * draws took the second step. */
static size_t check_two_steps(uint32_t n, uint32_t n_max, int draws)
{
    relief_rng a, b;
    size_t second = 0;
    relief_rng_seed(&a, 7u + n);
    relief_rng_seed(&b, 7u + n);
    for (int i = 0; i < draws; ++i) {
        const uint32_t va = relief_rng_below(&a, n), x = relief_rng_next(&b);
        uint32_t vb = x % n;
        if (!relief_rng_below_one(x, n_max)) {
            vb = relief_rng_below_from(&b, x, n);
            ++second;
        }
        if (va != vb || va >= n) {
            CHECK(0, "n %u, n_max %u, draw %d: %u against %u", n, n_max, i, va, vb);
            return second;
        }
    }
    CHECK(relief_rng_next(&a) == relief_rng_next(&b), "n %u, n_max %u: the streams parted",
          n, n_max);
    return second;
}

int main(void)
{
    static const uint32_t ns[] = {1, 2, 3, 7, 1000, 65536, 1u << 31, (1u << 31) + 1,
                                  3000000000u, UINT32_MAX};
    check_mt19937();
    for (size_t i = 0; i < sizeof ns / sizeof *ns; ++i) {
        check_two_steps(ns[i], ns[i], 20000);
        check_two_steps(ns[i], UINT32_MAX, 2000);
    }
    /* n = 2^31 + 1 rejects every output from 2^31 + 1 up: about half. */
    CHECK(check_two_steps((1u << 31) + 1, (1u << 31) + 1, 20000) > 5000,
          "the second step was hardly taken");
    /* A first output kept for every n up to n_max needs no second step. */
    CHECK(relief_rng_below_one(UINT32_MAX - 10, 10) && !relief_rng_below_one(UINT32_MAX - 9, 10),
          "the one-output bound is not UINT32_MAX - n_max");
    return check_result();
}
