/* The scalar reference matcher: every candidate in order, one thread, the
 * shared rm_score_candidate. Every other backend is tested against it. */
#include <float.h>
#include <stdio.h>
#include <stdlib.h>

#include "base/error.h"
#include "match/matcher_scalar.h"

#define RM_REAL float
#define RM_WITH_SCORING
#include "kernels/relief_math.h"

int relief_score_host_one(const relief_match_data *d, const relief_match_query *q,
                          uint32_t si, int r, float cutoff, float *ssd)
{
    return rm_score_candidate(d->proj, d->pos, d->col, d->matchable, d->tri, d->vt_start, d->vt,
                              d->cell_start, d->cell_items, d->grid, d->dims, d->lgrid,
                              d->ldims, d->lmask, d->lslot, d->litems,
                              d->s_proj + 3 * (size_t)si, d->s_frame + 9 * (size_t)si,
                              d->cos_r[r], d->sin_r[r], q->n, q->qp, q->q, q->g, q->qcol,
                              d->mu, d->inv_b2, q->inv_wsum, cutoff, ssd);
}

void relief_score_host_centres(const relief_match_data *d, const relief_match_query *q,
                               uint32_t begin, uint32_t end, float *cutoff, float *ssd,
                               uint8_t *flag)
{
    for (uint32_t i = begin; i < end; ++i) {
        const uint32_t si = relief_match_query_sample(q, i);
        for (int r = 0; r < d->rotations; ++r) {
            const size_t c = (size_t)i * (size_t)d->rotations + (size_t)r;
            const int f = relief_score_host_one(d, q, si, r, *cutoff, &ssd[c]);
            flag[c] = (uint8_t)f;
            if (q->running && f == RM_VALID) {
                const float c11 = relief_match_cutoff_after(ssd[c]);
                if (c11 < *cutoff)
                    *cutoff = c11;
            }
        }
    }
}

void relief_score_host(const relief_match_data *d, const relief_match_query *q, float *ssd,
                       uint8_t *flag)
{
    float cutoff = q->cutoff;
    relief_score_host_centres(d, q, 0, q->subset ? q->n_subset : d->ns, &cutoff, ssd, flag);
}

float relief_score_host_probe(const relief_match_data *d, const relief_match_query *q,
                              size_t probes, uint32_t first, uint32_t step)
{
    const size_t ncand = relief_match_query_candidates(d, q);
    float best = FLT_MAX;
    for (size_t i = first; i < probes; i += step) {
        const size_t c = i * ncand / probes;
        const uint32_t si = relief_match_query_sample(q, (uint32_t)(c / (size_t)d->rotations));
        const int r = (int)(c % (size_t)d->rotations);
        float s;
        if (relief_score_host_one(d, q, si, r, best, &s) == RM_VALID &&
            s < best)
            best = s;
    }
    return best;
}

static relief_status scalar_score(void *ctx, const relief_match_data *d,
                                  const relief_match_query *q, float *ssd, uint8_t *flag,
                                  relief_error *err)
{
    (void)ctx;
    (void)err;
    relief_score_host(d, q, ssd, flag);
    return RELIEF_OK;
}

relief_status relief_host_arrays_update(void *ctx, const relief_match_data *d, uint32_t v,
                                        relief_error *err)
{
    /* The host's arrays are what is scored: nothing to bring up to date. */
    (void)ctx;
    (void)d;
    (void)v;
    (void)err;
    return RELIEF_OK;
}

relief_status relief_host_arrays_rebind(void *ctx, const relief_match_data *d,
                                        relief_error *err)
{
    /* Nothing kept per surface: each query names its own. */
    (void)ctx;
    (void)d;
    (void)err;
    return RELIEF_OK;
}

static void scalar_destroy(void *ctx) { (void)ctx; }

static const relief_matcher_ops scalar_ops = {"scalar", scalar_score, relief_host_arrays_update,
                                              relief_host_arrays_rebind, scalar_destroy};

relief_status relief_matcher_scalar_create(const relief_match_data *d, relief_matcher **out,
                                           relief_error *err)
{
    relief_matcher *m = calloc(1, sizeof *m);
    (void)d;
    if (!m)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a matcher");
    m->ops = &scalar_ops;
    m->backend = RELIEF_BACKEND_SCALAR;
    snprintf(m->device, sizeof m->device, "scalar reference (1 thread)");
    *out = m;
    return RELIEF_OK;
}
