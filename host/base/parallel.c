/* Contiguous shares of a range over threads (parallel.h). */
#include "base/parallel.h"

#include <pthread.h>

typedef struct share {
    int (*fn)(void *ctx, size_t lo, size_t hi);
    void *ctx;
    size_t lo, hi;
    int failed;
} share;

static void *run_share(void *arg)
{
    share *s = arg;
    s->failed = s->fn(s->ctx, s->lo, s->hi) != 0;
    return NULL;
}

int relief_parallel_ranges(size_t n, int threads, int (*fn)(void *ctx, size_t lo, size_t hi),
                           void *ctx)
{
    share s[RELIEF_PARALLEL_MAX_THREADS];
    pthread_t tid[RELIEF_PARALLEL_MAX_THREADS];
    int started[RELIEF_PARALLEL_MAX_THREADS] = {0}, failed = 0, t;
    if (threads < 1)
        threads = 1;
    if (threads > RELIEF_PARALLEL_MAX_THREADS)
        threads = RELIEF_PARALLEL_MAX_THREADS;
    t = (size_t)threads > n ? (int)n : threads;
    for (int i = 0; i < t; ++i) {
        s[i] = (share){fn, ctx, n * (size_t)i / (size_t)t, n * (size_t)(i + 1) / (size_t)t, 0};
        if (i > 0)
            started[i] = pthread_create(&tid[i], NULL, run_share, &s[i]) == 0;
    }
    if (t > 0)
        run_share(&s[0]);
    for (int i = 1; i < t; ++i) {
        if (started[i])
            pthread_join(tid[i], NULL);
        else
            run_share(&s[i]); /* no thread to be had: its share here */
    }
    for (int i = 0; i < t; ++i)
        failed |= s[i].failed;
    return failed;
}
