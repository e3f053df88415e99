/* A pool of host threads handed one job after another (pool.h). */
#include "base/pool.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <time.h>

#include "base/error.h"
#include "base/parallel.h"

/* How long a thread spins for the next job (a worker) or for the last
 * part to finish (the caller) before it sleeps: a sleeping thread takes
 * tens of microseconds to wake (more in a virtual machine), about a window
 * search's share of work. Short, because a spinning thread takes a core
 * from whatever else runs: 200 us filled the astronaut in 1.1 to 1.3 s on
 * 2 threads here, 20 us in 1.3 to 1.4, none in 1.5 to 1.8; with 200 us
 * the sanitized suite (two tests at a time, the mesh matcher's threads
 * on this pool too) took 925 s, against 649 s before the pool. */
#define SPIN_NS 20000L

/* A worker's own job slot: written by the caller only while the worker
 * is idle, then published by bumping its ticket; a worker reads nothing
 * of a job it takes no part in. */
typedef struct worker {
    relief_pool *pool;
    int index;
    pthread_t thread;
    atomic_ulong ticket; /* bumped once per job this worker takes part in */
    void (*fn)(void *ctx, int k, int n);
    void *ctx;
    int parts;
} worker;

struct relief_pool {
    int threads, started;
    worker *w;
    pthread_mutex_t mu;
    pthread_cond_t go, done;
    atomic_int pending;      /* parts still running */
    int sleepers;            /* workers waiting on go, under mu */
    atomic_int quit;
};

static long elapsed_ns(const struct timespec *t0)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (t.tv_sec - t0->tv_sec) * 1000000000L + (t.tv_nsec - t0->tv_nsec);
}

static inline void cpu_relax(void)
{
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
}

/* Spin until *flag differs from `from` (differs: 1) or SPIN_NS pass (0). */
static int spin_ulong(atomic_ulong *flag, unsigned long from, const atomic_int *quit)
{
    struct timespec t0;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (unsigned i = 1;; ++i) {
        if (atomic_load_explicit(flag, memory_order_acquire) != from ||
            atomic_load_explicit(quit, memory_order_relaxed))
            return 1;
        cpu_relax();
        if ((i & 255) == 0 && elapsed_ns(&t0) > SPIN_NS)
            return 0;
    }
}

int relief_pool_default_threads(void)
{
    const int n = relief_cpus_available();
    return n > RELIEF_POOL_MAX ? RELIEF_POOL_MAX : n;
}

int relief_pool_threads_for(int threads)
{
    if (threads <= 0)
        return relief_pool_default_threads();
    return threads > RELIEF_POOL_MAX ? RELIEF_POOL_MAX : threads;
}

int relief_pool_threads(const relief_pool *p) { return p ? p->threads : 1; }

void relief_pool_share(size_t count, int k, int n, size_t *lo, size_t *hi)
{
    *lo = count * (size_t)k / (size_t)n;
    *hi = count * (size_t)(k + 1) / (size_t)n;
}

/* A worker waits for its ticket to move (spinning a while, then asleep),
 * runs its part, and the last part to finish wakes the caller. */
static void *worker_main(void *arg)
{
    worker *w = arg;
    relief_pool *p = w->pool;
    unsigned long seen = 0;
    for (;;) {
        if (!spin_ulong(&w->ticket, seen, &p->quit)) {
            pthread_mutex_lock(&p->mu);
            ++p->sleepers;
            while (atomic_load(&w->ticket) == seen && !atomic_load(&p->quit))
                pthread_cond_wait(&p->go, &p->mu);
            --p->sleepers;
            pthread_mutex_unlock(&p->mu);
        }
        if (atomic_load(&p->quit))
            return NULL;
        seen = atomic_load_explicit(&w->ticket, memory_order_acquire);
        w->fn(w->ctx, w->index, w->parts);
        if (atomic_fetch_sub_explicit(&p->pending, 1, memory_order_acq_rel) == 1) {
            pthread_mutex_lock(&p->mu);
            pthread_cond_signal(&p->done);
            pthread_mutex_unlock(&p->mu);
        }
    }
}

relief_status relief_pool_create(int threads, relief_pool **out, relief_error *err)
{
    relief_pool *p;
    *out = NULL;
    if (threads < 1 || threads > RELIEF_POOL_MAX)
        return relief_fail(err, RELIEF_E_RANGE, "host threads %d out of range: expected 1..%d",
                           threads, RELIEF_POOL_MAX);
    p = calloc(1, sizeof *p);
    if (!p || !(p->w = calloc((size_t)threads, sizeof *p->w))) {
        free(p);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate %d host threads", threads);
    }
    p->threads = threads;
    pthread_mutex_init(&p->mu, NULL);
    pthread_cond_init(&p->go, NULL);
    pthread_cond_init(&p->done, NULL);
    for (int k = 1; k < threads; ++k) {
        p->w[k].pool = p;
        p->w[k].index = k;
        atomic_init(&p->w[k].ticket, 0);
        if (pthread_create(&p->w[k].thread, NULL, worker_main, &p->w[k]) != 0) {
            relief_pool_destroy(p);
            return relief_fail(err, RELIEF_E_NOMEM, "cannot start host thread %d of %d",
                               k + 1, threads);
        }
        p->started = k;
    }
    *out = p;
    return RELIEF_OK;
}

void relief_pool_run(relief_pool *p, int parts, void (*fn)(void *ctx, int k, int n), void *ctx)
{
    int n = parts < 1 ? 1 : parts > p->threads ? p->threads : parts;
    struct timespec t0;
    if (n == 1) {
        fn(ctx, 0, 1);
        return;
    }
    /* Each taking part gets its slot, then the ticket that publishes it
     * (the ticket under mu, so that a worker going to sleep sees it). */
    atomic_store(&p->pending, n - 1);
    pthread_mutex_lock(&p->mu);
    for (int k = 1; k < n; ++k) {
        p->w[k].fn = fn;
        p->w[k].ctx = ctx;
        p->w[k].parts = n;
        atomic_fetch_add_explicit(&p->w[k].ticket, 1, memory_order_release);
    }
    if (p->sleepers)
        pthread_cond_broadcast(&p->go);
    pthread_mutex_unlock(&p->mu);
    fn(ctx, 0, n);
    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (unsigned i = 1; atomic_load_explicit(&p->pending, memory_order_acquire) > 0; ++i) {
        cpu_relax();
        if ((i & 255) == 0 && elapsed_ns(&t0) > SPIN_NS) {
            pthread_mutex_lock(&p->mu);
            while (atomic_load(&p->pending) > 0)
                pthread_cond_wait(&p->done, &p->mu);
            pthread_mutex_unlock(&p->mu);
            break;
        }
    }
}

void relief_pool_destroy(relief_pool *p)
{
    if (!p)
        return;
    pthread_mutex_lock(&p->mu);
    atomic_store(&p->quit, 1);
    pthread_cond_broadcast(&p->go);
    pthread_mutex_unlock(&p->mu);
    for (int k = 1; k <= p->started; ++k)
        pthread_join(p->w[k].thread, NULL);
    pthread_cond_destroy(&p->done);
    pthread_cond_destroy(&p->go);
    pthread_mutex_destroy(&p->mu);
    free(p->w);
    free(p);
}
