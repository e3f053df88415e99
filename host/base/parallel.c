/* Contiguous shares of a range over threads (parallel.h). */
#define _GNU_SOURCE /* sched_getaffinity, CPU_COUNT_S: this file only */
#include "base/parallel.h"

#include <errno.h>
#include <limits.h>
#include <pthread.h>
#include <sched.h>
#include <unistd.h>

/* The affinity's count, or 0 when it cannot be read. The mask starts at
 * 1024 CPUs and doubles while the kernel's is larger (EINVAL). */
static int affinity_count(void)
{
#if defined(__linux__) && defined(CPU_ALLOC)
    for (int cpus = 1024; cpus <= (1 << 20); cpus *= 2) {
        cpu_set_t *set = CPU_ALLOC(cpus);
        const size_t size = CPU_ALLOC_SIZE(cpus);
        int count = 0, again = 0;
        if (!set)
            return 0;
        CPU_ZERO_S(size, set);
        if (sched_getaffinity(0, size, set) == 0)
            count = CPU_COUNT_S(size, set);
        else
            again = errno == EINVAL;
        CPU_FREE(set);
        if (!again)
            return count;
    }
#endif
    return 0;
}

int relief_cpus_available(void)
{
    const int n = affinity_count();
    long online;
    if (n > 0)
        return n;
    online = sysconf(_SC_NPROCESSORS_ONLN);
    return online < 1 ? 1 : online > INT_MAX ? INT_MAX : (int)online;
}

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
