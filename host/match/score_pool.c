/* Host threads scoring one query side by side (score_pool.h). */
#include "match/matcher_scalar.h"
#include "match/score_pool.h"
#include "match/score_lanes.h"

#include <float.h>
#include <pthread.h>
#include <stdlib.h>
#include <unistd.h>

#include "base/error.h"

/* A query takes one thread per this many centres (or probes), at most the
 * pool's: fewer per thread and the hand-over costs more than it saves. */
#define MIN_PER_THREAD 16

typedef struct worker {
    relief_score_pool *pool;
    int index;
    pthread_t thread;
} worker;

struct relief_score_pool {
    int threads, started;
    int lanes; /* 1: score in lock-step (this processor has AVX2) */
    int active; /* threads taking part in the query in progress; written
                   and read under mu, with the generation */
    worker *w;
    pthread_mutex_t mu;
    pthread_cond_t go, done;
    unsigned long generation; /* bumped once per query */
    int pending;              /* workers still scoring this query */
    int quit;
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

/* Thread k's share of the query, the first `active` threads taking part. */
static void run_part(relief_score_pool *p, int k, int active)
{
    if (p->probes)
        p->best[k] = relief_score_host_probe(p->d, p->q, p->probes, (uint32_t)k,
                                             (uint32_t)active);
    else
        relief_score_host_blocks(p->d, p->q, (uint32_t)k, (uint32_t)active, p->lanes, p->ssd,
                                 p->flag);
}

/* Run the job set in p on its first `active` threads and wait for them.
 * Every worker wakes and reads the generation and `active` together; only
 * the first active - 1 take part and report back, so the caller waits for
 * no idle thread. */
static void run_all(relief_score_pool *p, int active)
{
    pthread_mutex_lock(&p->mu);
    p->active = active;
    p->pending = active - 1;
    ++p->generation;
    pthread_cond_broadcast(&p->go);
    pthread_mutex_unlock(&p->mu);
    run_part(p, 0, active);
    pthread_mutex_lock(&p->mu);
    while (p->pending > 0)
        pthread_cond_wait(&p->done, &p->mu);
    pthread_mutex_unlock(&p->mu);
}

static void *worker_main(void *arg)
{
    worker *w = arg;
    relief_score_pool *p = w->pool;
    unsigned long seen = 0;
    int active;
    for (;;) {
        pthread_mutex_lock(&p->mu);
        while (p->generation == seen && !p->quit)
            pthread_cond_wait(&p->go, &p->mu);
        if (p->quit) {
            pthread_mutex_unlock(&p->mu);
            return NULL;
        }
        seen = p->generation;
        active = p->active;
        pthread_mutex_unlock(&p->mu);
        if (w->index >= active)
            continue; /* not needed for this query */
        run_part(p, w->index, active);
        pthread_mutex_lock(&p->mu);
        if (--p->pending == 0)
            pthread_cond_signal(&p->done);
        pthread_mutex_unlock(&p->mu);
    }
}

/* The threads that take `items` centres or probes: at most one per
 * MIN_PER_THREAD of them. */
static int threads_for(const relief_score_pool *p, size_t items)
{
    size_t n = items / MIN_PER_THREAD;
    return n < 1 ? 1 : n < (size_t)p->threads ? (int)n : p->threads;
}

int relief_score_pool_default_threads(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > RELIEF_SCORE_POOL_MAX ? RELIEF_SCORE_POOL_MAX : (int)n;
}

relief_status relief_score_pool_create(int threads, relief_score_pool **out,
                                       relief_error *err)
{
    relief_score_pool *p;
    if (!out)
        return relief_fail(err, RELIEF_E_USAGE, "relief_score_pool_create: out is NULL");
    *out = NULL;
    if (threads < 1 || threads > RELIEF_SCORE_POOL_MAX)
        return relief_fail(err, RELIEF_E_RANGE, "host scoring threads %d out of range: "
                           "expected 1..%d", threads, RELIEF_SCORE_POOL_MAX);
    p = calloc(1, sizeof *p);
    if (!p || !(p->w = calloc((size_t)threads, sizeof *p->w))) {
        free(p);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the host scoring threads");
    }
    p->threads = threads;
    p->lanes = relief_host_lanes_supported();
    pthread_mutex_init(&p->mu, NULL);
    pthread_cond_init(&p->go, NULL);
    pthread_cond_init(&p->done, NULL);
    for (int k = 1; k < threads; ++k) {
        p->w[k].pool = p;
        p->w[k].index = k;
        if (pthread_create(&p->w[k].thread, NULL, worker_main, &p->w[k]) != 0) {
            relief_score_pool_destroy(p);
            return relief_fail(err, RELIEF_E_NOMEM, "cannot start host scoring thread %d of "
                               "%d", k + 1, threads);
        }
        p->started = k;
    }
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
    run_all(p, use);
}

float relief_score_pool_probe(relief_score_pool *p, const relief_match_data *d,
                              const relief_match_query *q, size_t probes)
{
    float best = FLT_MAX;
    const int use = threads_for(p, probes);
    if (use == 1)
        return relief_score_host_probe(d, q, probes, 0, 1);
    p->d = d, p->q = q, p->probes = probes;
    run_all(p, use);
    for (int k = 0; k < use; ++k)
        best = p->best[k] < best ? p->best[k] : best;
    return best;
}

void relief_score_pool_destroy(relief_score_pool *p)
{
    if (!p)
        return;
    pthread_mutex_lock(&p->mu);
    p->quit = 1;
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
