/* The host backend (matcher_host.h): a score_pool behind the matcher
 * table. */
#include "match/matcher_host.h"

#include <stdio.h>
#include <stdlib.h>

#include "base/error.h"
#include "match/matcher_scalar.h"
#include "match/score_lanes.h"
#include "match/score_pool.h"

static relief_status host_score(void *ctx, const relief_match_data *d,
                                const relief_match_query *q, float *ssd, uint8_t *flag,
                                relief_error *err)
{
    (void)err;
    relief_score_pool_run(ctx, d, q, ssd, flag);
    return RELIEF_OK;
}

static void host_destroy(void *ctx) { relief_score_pool_destroy(ctx); }

static const relief_matcher_ops host_ops = {"host", host_score, relief_host_arrays_update,
                                            relief_host_arrays_rebind, host_destroy};

relief_status relief_matcher_host_create(const relief_match_data *d, int threads,
                                         relief_matcher **out, relief_error *err)
{
    relief_score_pool *pool = NULL;
    relief_matcher *m;
    relief_status st;
    (void)d;
    if (threads == 0)
        threads = relief_score_pool_default_threads();
    st = relief_score_pool_create(threads, &pool, err);
    if (st != RELIEF_OK)
        return st;
    m = calloc(1, sizeof *m);
    if (!m) {
        relief_score_pool_destroy(pool);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a matcher");
    }
    m->ops = &host_ops;
    m->ctx = pool;
    m->backend = RELIEF_BACKEND_HOST;
    m->device_index = -1;
    if (relief_host_lanes_supported())
        snprintf(m->device, sizeof m->device, "host (%d thread%s, %d lanes AVX2)", threads,
                 threads == 1 ? "" : "s", RELIEF_HOST_LANES);
    else
        snprintf(m->device, sizeof m->device, "host (%d thread%s)", threads,
                 threads == 1 ? "" : "s");
    *out = m;
    return RELIEF_OK;
}
