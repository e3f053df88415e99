/* Host threads that score one query's candidates side by side: the OpenCL
 * matcher's path for launches too small to pay for themselves (a sample
 * pyramid's box, a coarse level), which would otherwise leave all but one
 * core idle.
 *
 * A query of c centres takes n = min(threads, c / 16) of the threads (one
 * when that is below 2: a hand-over costs more than 16 centres save).
 * The centres go out in blocks of 16: thread k of n scores blocks k,
 * k + n, k + 2 n, ... in that order (relief_score_host_blocks) with its
 * own running cutoff: dealt out so, each thread meets the candidates a
 * caller put first (the nearest to a pyramid's parent match) first, and
 * its cutoff drops as early as one thread's would. On a processor with
 * AVX2 each thread scores 16 candidates in lock-step (score_lanes.h).
 * Pruning is exact, so every candidate within 1.1 x the minimum comes out
 * VALID with the same SSD as from the scalar reference; only which of the
 * others are cut short (RM_PRUNED, and their partial sums) depends on the
 * split, which is fixed for a given pool size and query. */
#ifndef RELIEF_SCORE_POOL_H
#define RELIEF_SCORE_POOL_H

#include "match/match_data.h"

typedef struct relief_score_pool relief_score_pool;

/* A pool of `threads` (1..RELIEF_SCORE_POOL_MAX; the caller's thread is one
 * of them, so threads - 1 are started). */
#define RELIEF_SCORE_POOL_MAX 16
relief_status relief_score_pool_create(int threads, relief_score_pool **out,
                                       relief_error *err);

/* The threads to use here: the CPUs this thread may run on (its
 * affinity), at most RELIEF_SCORE_POOL_MAX. */
int relief_score_pool_default_threads(void);

/* The threads a call asked for (relief_run_options.threads; 0: the
 * default above), at most RELIEF_SCORE_POOL_MAX. */
int relief_score_pool_threads_for(int threads);

/* 1 when this build and processor score in lock-step (score_lanes.h: an
 * x86-64 build on a processor with AVX2), else 0. */
int relief_host_lanes_supported(void);
/* Score blocks first, first + step, ... (first < step) of the query's
 * candidates, block b being centres 16 b to 16 b + 15 with all their
 * rotations, with a running cutoff of its own starting from q->cutoff: in
 * lock-step when `lanes` is set (only where relief_host_lanes_supported()),
 * else by the scalar reference's loop. Thread `first` of a pool of `step`
 * runs this. */
void relief_score_host_blocks(const relief_match_data *d, const relief_match_query *q,
                              uint32_t first, uint32_t step, int lanes, float *ssd,
                              uint8_t *flag);
/* Score the query as relief_score_host does, split over the pool. */
void relief_score_pool_run(relief_score_pool *p, const relief_match_data *d,
                           const relief_match_query *q, float *ssd, uint8_t *flag);

/* relief_score_host_probe over the pool: the same minimum. */
float relief_score_pool_probe(relief_score_pool *p, const relief_match_data *d,
                              const relief_match_query *q, size_t probes);

void relief_score_pool_destroy(relief_score_pool *p);

#endif
