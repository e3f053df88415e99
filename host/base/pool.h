/* A pool of host threads started once and handed one job after another:
 * for work cut into many short jobs (a window search per synthesised
 * pixel, an iteration of a solver), where starting threads per job would
 * cost more than the job. The caller's thread is one of the pool's.
 *
 * A job is fn(ctx, k, n) for k = 0 .. n - 1, k = 0 on the calling thread;
 * relief_pool_run returns when every part has returned. What each part
 * does with k and n is the caller's: a share fixed by (k, n) alone gives
 * the same result however the threads are scheduled. A pool serves one
 * caller thread at a time. */
#ifndef RELIEF_HOST_BASE_POOL_H
#define RELIEF_HOST_BASE_POOL_H

#include <stddef.h>

#include "relief/relief.h"

#define RELIEF_POOL_MAX 64

typedef struct relief_pool relief_pool;

/* The CPUs this thread may run on (relief_cpus_available, base/parallel.h:
 * its affinity), 1 .. RELIEF_POOL_MAX. */
int relief_pool_default_threads(void);

/* The threads a call asked for (relief_run_options.threads): `threads`
 * itself, at most RELIEF_POOL_MAX, or for 0 the default above. */
int relief_pool_threads_for(int threads);

/* A pool of `threads` (1 .. RELIEF_POOL_MAX; threads - 1 are started).
 * RELIEF_E_RANGE out of range, RELIEF_E_NOMEM when a thread cannot start. */
relief_status relief_pool_create(int threads, relief_pool **out, relief_error *err);

int relief_pool_threads(const relief_pool *p);

/* Run fn(ctx, k, n) on n = clamp(parts, 1, threads) threads and wait for
 * all of them. */
void relief_pool_run(relief_pool *p, int parts, void (*fn)(void *ctx, int k, int n), void *ctx);

/* The share [lo, hi) of `count` items that part k of n takes: contiguous,
 * in order, sizes differing by one at most. */
void relief_pool_share(size_t count, int k, int n, size_t *lo, size_t *hi);

void relief_pool_destroy(relief_pool *p);

#endif
