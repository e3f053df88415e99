/* Host threads scoring one query side by side (score_pool.h). */
#include "match/matcher_scalar.h"
#include "match/score_pool.h"
#include "match/score_lanes.h"

#include <float.h>
#include <stdlib.h>

#include "base/error.h"
#include "base/pool.h"

/* A query takes one thread per this many centres (or probes), at most the
 * pool's: fewer per thread and the hand-over costs more than it saves. */
#define MIN_PER_THREAD 16

struct relief_score_pool {
    relief_pool *threads; /* base/pool.h: started once */
    int lanes;            /* 1: score in lock-step (this processor has AVX2) */
    /* The query in progress: scores (probes == 0) or a probe. */
    const relief_match_data *d;
    const relief_match_query *q;
    float *ssd;
    uint8_t *flag;
    size_t probes;
    float best[RELIEF_SCORE_POOL_MAX]; /* each thread's probe minimum */
};

int relief_host_lanes_supported(void)
{
#if defined(RELIEF_HOST_LANES_AVX2) && defined(__GNUC__)
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") != 0;
#else
    return 0;
#endif
}

void relief_score_host_blocks(const relief_match_data *d, const relief_match_query *q,
                              uint32_t first, uint32_t step, int lanes, float *ssd,
                              uint8_t *flag)
{
    const uint32_t centres = q->subset ? q->n_subset : d->ns;
    float cutoff = q->cutoff;
#ifdef RELIEF_HOST_LANES_AVX2
    if (lanes) {
        relief_score_host_lanes(d, q, first, step, ssd, flag);
        return;
    }
#else
    (void)lanes;
#endif
    /* The scalar reference's loop over the same blocks. */
    for (uint32_t b = first; (size_t)b * RELIEF_HOST_LANE_BLOCK < centres; b += step) {
        const uint32_t begin = b * RELIEF_HOST_LANE_BLOCK;
        const uint32_t end = centres - begin < RELIEF_HOST_LANE_BLOCK
                                 ? centres
                                 : begin + RELIEF_HOST_LANE_BLOCK;
        relief_score_host_centres(d, q, begin, end, &cutoff, ssd, flag);
        if (b > UINT32_MAX - step)
            break;
    }
}

/* Thread k's share of the query, the first `active` threads taking part
 * (a relief_pool job). */
static void run_part(void *ctx, int k, int active)
{
    relief_score_pool *p = ctx;
    if (p->probes)
        p->best[k] = relief_score_host_probe(p->d, p->q, p->probes, (uint32_t)k,
                                             (uint32_t)active);
    else
        relief_score_host_blocks(p->d, p->q, (uint32_t)k, (uint32_t)active, p->lanes, p->ssd,
                                 p->flag);
}

/* The threads that take `items` centres or probes: at most one per
 * MIN_PER_THREAD of them. */
static int threads_for(const relief_score_pool *p, size_t items)
{
    size_t n = items / MIN_PER_THREAD;
    int threads = relief_pool_threads(p->threads);
    return n < 1 ? 1 : n < (size_t)threads ? (int)n : threads;
}

int relief_score_pool_default_threads(void)
{
    int n = relief_pool_default_threads();
    return n > RELIEF_SCORE_POOL_MAX ? RELIEF_SCORE_POOL_MAX : n;
}

int relief_score_pool_threads_for(int threads)
{
    const int n = relief_pool_threads_for(threads);
    return n > RELIEF_SCORE_POOL_MAX ? RELIEF_SCORE_POOL_MAX : n;
}

relief_status relief_score_pool_create(int threads, relief_score_pool **out,
                                       relief_error *err)
{
    relief_score_pool *p;
    relief_status st;
    if (!out)
        return relief_fail(err, RELIEF_E_USAGE, "relief_score_pool_create: out is NULL");
    *out = NULL;
    if (threads < 1 || threads > RELIEF_SCORE_POOL_MAX)
        return relief_fail(err, RELIEF_E_RANGE, "host scoring threads %d out of range: "
                           "expected 1..%d", threads, RELIEF_SCORE_POOL_MAX);
    p = calloc(1, sizeof *p);
    if (!p)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the host scoring threads");
    st = relief_pool_create(threads, &p->threads, err);
    if (st != RELIEF_OK) {
        free(p);
        return st;
    }
    p->lanes = relief_host_lanes_supported();
    *out = p;
    return RELIEF_OK;
}

void relief_score_pool_run(relief_score_pool *p, const relief_match_data *d,
                           const relief_match_query *q, float *ssd, uint8_t *flag)
{
    const uint32_t centres = q->subset ? q->n_subset : d->ns;
    const int use = threads_for(p, centres);
    if (use == 1) {
        relief_score_host_blocks(d, q, 0, 1, p->lanes, ssd, flag);
        return;
    }
    p->d = d, p->q = q, p->ssd = ssd, p->flag = flag, p->probes = 0;
    relief_pool_run(p->threads, use, run_part, p);
}

float relief_score_pool_probe(relief_score_pool *p, const relief_match_data *d,
                              const relief_match_query *q, size_t probes)
{
    float best = FLT_MAX;
    const int use = threads_for(p, probes);
    if (use == 1)
        return relief_score_host_probe(d, q, probes, 0, 1);
    p->d = d, p->q = q, p->probes = probes;
    relief_pool_run(p->threads, use, run_part, p);
    for (int k = 0; k < use; ++k)
        best = p->best[k] < best ? p->best[k] : best;
    return best;
}

void relief_score_pool_destroy(relief_score_pool *p)
{
    if (!p)
        return;
    relief_pool_destroy(p->threads);
    free(p);
}
