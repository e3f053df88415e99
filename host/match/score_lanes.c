/* The host's lock-step scoring (score_lanes.h): rm_score_range of
 * relief_math.h on the host's arrays. This file is compiled for AVX2 (and
 * tuned so that GCC uses its gathers); score_pool.c calls it only on a
 * processor that has AVX2. */
#include "match/score_lanes.h"

#include "match/match_data.h"

/* A valid score lowers a running query's cutoff as the scalar loop's
 * does. */
static inline float lower_cutoff(float cutoff, float ssd)
{
    const float c11 = relief_match_cutoff_after(ssd);
    return c11 < cutoff ? c11 : cutoff;
}

#define RM_REAL float
#define RM_WITH_SCORING
#define RM_LANES RELIEF_HOST_LANES
#define RM_LOWER_CUTOFF(cut, ssd) lower_cutoff(cut, ssd)
#define RM_SIMD _Pragma("omp simd")
#include "kernels/relief_math.h"

void relief_score_host_lanes(const relief_match_data *d, const relief_match_query *q,
                             uint32_t first, uint32_t step, float *ssd, uint8_t *flag)
{
    const uint32_t centres = q->subset ? q->n_subset : d->ns;
    const uint32_t rot = (uint32_t)d->rotations;
    const uint32_t block = RELIEF_HOST_LANE_BLOCK * rot;
    float cutoff = q->cutoff;
    /* (the run's last jump must not wrap) */
    if (centres == 0 || first >= step ||
        (uint64_t)centres * rot + (uint64_t)step * block > UINT32_MAX)
        return;
    rm_score_range(d->proj, d->pos, d->col, d->matchable, d->tri, d->vt_start, d->vt,
                   d->cell_start, d->cell_items, d->grid, d->dims, d->lgrid, d->ldims,
                   d->lmask, d->lslot, d->litems, d->s_proj, d->s_frame, d->cos_r, d->sin_r,
                   q->subset, rot, first * block, centres * rot, block, step * block, q->n,
                   q->qp, q->q, q->g, q->qcol, d->mu, d->inv_b2, q->inv_wsum, &cutoff,
                   q->running, ssd, flag);
}
