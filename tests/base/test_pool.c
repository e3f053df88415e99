/* The host thread pool (base/pool.h): every part of every job runs once,
 * with its own (k, n); the shares cover a range in order; the part count
 * is clamped; many short jobs in a row (the image scorer's pattern) lose
 * none; a bad thread count is refused. */
#include <stdatomic.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "base/pool.h"

typedef struct tally {
    atomic_int runs[RELIEF_POOL_MAX];
    atomic_int wrong_n;
    int expect_n;
    long sum[RELIEF_POOL_MAX];
} tally;

static void count_part(void *ctx, int k, int n)
{
    tally *t = ctx;
    atomic_fetch_add(&t->runs[k], 1);
    if (n != t->expect_n)
        atomic_fetch_add(&t->wrong_n, 1);
}

/* Part k sums its share of 0 .. 9999. */
static void sum_share(void *ctx, int k, int n)
{
    tally *t = ctx;
    size_t lo, hi;
    relief_pool_share(10000, k, n, &lo, &hi);
    t->sum[k] = 0;
    for (size_t i = lo; i < hi; ++i)
        t->sum[k] += (long)i;
}

int main(void)
{
    relief_error err = {0};
    relief_pool *p = NULL;
    static tally t;
    size_t prev = 0;
    long total = 0;

    CHECK(relief_pool_create(0, &p, &err) == RELIEF_E_RANGE && p == NULL, "0 threads accepted");
    CHECK(relief_pool_create(RELIEF_POOL_MAX + 1, &p, &err) == RELIEF_E_RANGE,
          "too many threads accepted");
    CHECK(relief_pool_default_threads() >= 1, "no default threads");
    CHECK(relief_pool_create(4, &p, &err) == RELIEF_OK, "%s", err.message);
    CHECK(relief_pool_threads(p) == 4, "threads %d", relief_pool_threads(p));

    /* 5000 jobs of 1 to 6 parts asked (clamped to 1 .. 4). */
    for (int j = 0; j < 5000; ++j) {
        int asked = 1 + j % 6, n = asked > 4 ? 4 : asked;
        t.expect_n = n;
        relief_pool_run(p, asked, count_part, &t);
    }
    {
        int want[4] = {5000, 0, 0, 0};
        for (int j = 0; j < 5000; ++j)
            for (int k = 1; k < (1 + j % 6 > 4 ? 4 : 1 + j % 6); ++k)
                ++want[k];
        for (int k = 0; k < 4; ++k)
            CHECK(atomic_load(&t.runs[k]) == want[k], "part %d ran %d times, expected %d", k,
                  atomic_load(&t.runs[k]), want[k]);
        CHECK(atomic_load(&t.wrong_n) == 0, "%d parts saw a wrong part count",
              atomic_load(&t.wrong_n));
    }

    /* The shares cover 0 .. 9999 in order, without gap or overlap. */
    for (int n = 1; n <= 4; ++n)
        for (int k = 0; k < n; ++k) {
            size_t lo, hi;
            relief_pool_share(10000, k, n, &lo, &hi);
            CHECK(lo == (k ? prev : 0) && hi >= lo, "share %d of %d: [%zu, %zu)", k, n, lo, hi);
            prev = hi;
            if (k == n - 1)
                CHECK(hi == 10000, "the last share ends at %zu", hi);
        }
    relief_pool_run(p, 4, sum_share, &t);
    for (int k = 0; k < 4; ++k)
        total += t.sum[k];
    CHECK(total == 10000L * 9999 / 2, "the shares summed %ld", total);
    relief_pool_destroy(p);
    relief_pool_destroy(NULL);
    printf("pool: 5000 jobs on 4 threads, every part once\n");
    return check_result();
}
