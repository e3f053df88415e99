/* The candidate centres of a told hole: the samples nearest its targets
 * (match_data.h, relief_match_data_build_near). */
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "match/match_data.h"
#include "mesh/mesh.h"

/* The pool as the search from the targets finds it: the first n_keep
 * samples reached. */
typedef struct pool_reach {
    uint32_t ns;
    size_t n_keep, found;
    uint8_t *keep;
} pool_reach;

static int take_sample(void *ctx, uint32_t v)
{
    pool_reach *p = ctx;
    if (v < p->ns && p->found < p->n_keep) {
        p->keep[v] = 1;
        ++p->found;
    }
    return p->found == p->n_keep;
}

/* Breadth-first from every target (vertices ns..nv-1; the samples are
 * 0..ns-1 while no pool is kept) over the triangles, a ring at a time:
 * the first n_keep samples reached are marked in `keep`, and every vertex
 * reached up to `margin` rings past the ring that completed them in
 * `near`. Returns how many samples were kept. queue: nv entries. */
static size_t reach_samples(const relief_match_data *d, size_t n_keep, int margin,
                            uint32_t *queue, uint8_t *near, uint8_t *keep)
{
    pool_reach p = {d->ns, n_keep, 0, keep};
    size_t n = 0;
    for (uint32_t v = d->ns; v < d->nv; ++v) {
        queue[n++] = v;
        near[v] = 1;
    }
    relief_mesh_rings(d->tri, d->vt_start, d->vt, queue, n, near, 0, margin, take_sample, &p);
    return p.found;
}

/* Compact the sample arrays to the kept samples, in vertex order, and map
 * every vertex to its new index. */
static void compact(relief_match_data *d, const uint8_t *keep, uint32_t *sample_of)
{
    uint32_t n = 0;
    for (uint32_t v = 0; v < d->nv; ++v)
        sample_of[v] = UINT32_MAX;
    for (uint32_t i = 0; i < d->ns; ++i) {
        if (!keep[i])
            continue;
        d->sample[n] = d->sample[i];
        memmove(d->s_proj + 3 * (size_t)n, d->s_proj + 3 * (size_t)i, 3 * sizeof(float));
        memmove(d->s_frame + 9 * (size_t)n, d->s_frame + 9 * (size_t)i, 9 * sizeof(float));
        sample_of[d->sample[n]] = n;
        ++n;
    }
    d->ns = n;
    d->sample_of = sample_of;
}

relief_status relief_match_pool(relief_match_data *d, size_t n_keep, int margin,
                                uint8_t **near, relief_error *err)
{
    uint32_t *queue, *sample_of;
    uint8_t *keep;
    *near = NULL;
    if (d->sample_of || n_keep >= d->ns || d->ns == d->nv)
        return RELIEF_OK; /* already kept, or nothing to leave out */
    queue = malloc((size_t)d->nv * sizeof *queue);
    sample_of = malloc((size_t)d->nv * sizeof *sample_of);
    *near = calloc(d->nv, 1);
    keep = calloc(d->ns, 1);
    if (!queue || !sample_of || !*near || !keep) {
        free(queue);
        free(sample_of);
        free(*near);
        *near = NULL;
        free(keep);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the samples' pool over %u "
                           "vertices", d->nv);
    }
    if (reach_samples(d, n_keep, margin, queue, *near, keep) == n_keep) {
        compact(d, keep, sample_of);
    } else { /* a hole on a piece of its own: every sample */
        free(sample_of);
        free(*near);
        *near = NULL;
    }
    free(queue);
    free(keep);
    return RELIEF_OK;
}
