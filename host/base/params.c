#include <math.h>
#include <stddef.h>

#include "base/error.h"
#include "base/params.h"

relief_params relief_params_default(void)
{
    relief_params p;
    p.fit = RELIEF_FIT_AUTO;
    p.window = 3;
    p.rotations = 0;
    p.error = 0.1;
    p.mu = -1.0;
    p.seed = 1;
    p.coherence = 0.0;
    p.search = RELIEF_SEARCH_AUTO;
    p.search_k = 8;
    p.levels = 1;
    p.backend = RELIEF_BACKEND_AUTO;
    p.device = -1;
    p.oversample = 1;
    p.spacing = 0.0;
    p.has_extent = 0;
    p.n_extent = 0;
    p.max_memory = 0;
    p.threads = 0;
    for (int i = 0; i < 4; ++i)
        p.extent[i] = 0.0;
    return p;
}

int relief_params_rotations(const relief_params *params, relief_fit_model model)
{
    if (params->rotations > 0)
        return params->rotations;
    return model == RELIEF_FIT_PLANE ? 1 : 4;
}

relief_search_mode relief_params_search(const relief_params *params, size_t ns, int rotations,
                                        size_t n_targets)
{
    if (params->search != RELIEF_SEARCH_AUTO)
        return params->search;
    return (double)ns * rotations * (double)n_targets >
                   (params->told_holes ? RELIEF_SEARCH_AUTO_WORK_TOLD : RELIEF_SEARCH_AUTO_WORK)
               ? RELIEF_SEARCH_COHERENT : RELIEF_SEARCH_EXHAUSTIVE;
}

/* The extent's values (the engine's "extent"), when given. */
static relief_status validate_extent(const relief_params *p, relief_error *err)
{
    if (p->n_extent != 2 && p->n_extent != 4)
        return relief_fail_param(err, RELIEF_E_RANGE, "extent",
                                 "extent has %d values: expected 2 (cylinder z0,z1) or "
                                 "4 (plane u0,v0,u1,v1)", p->n_extent);
    for (int i = 0; i < p->n_extent; ++i)
        if (!isfinite(p->extent[i]))
            return relief_fail_param(err, RELIEF_E_RANGE, "extent",
                                     "extent value %d is not finite", i + 1);
    if (p->extent[0] >= p->extent[p->n_extent / 2])
        return relief_fail_param(err, RELIEF_E_RANGE, "extent",
                                 "extent is empty: the lower bound %g is not below the "
                                 "upper bound %g", p->extent[0], p->extent[p->n_extent / 2]);
    if (p->n_extent == 4 && p->extent[1] >= p->extent[3])
        return relief_fail_param(err, RELIEF_E_RANGE, "extent",
                                 "extent is empty: v0 %g is not below v1 %g",
                                 p->extent[1], p->extent[3]);
    return RELIEF_OK;
}

/* The growth's fields; each refusal names its field (err->param). */
static relief_status validate_growth(const relief_params *p, relief_error *err)
{
    if (p->fit < RELIEF_FIT_AUTO || p->fit > RELIEF_FIT_CYLINDER)
        return relief_fail_param(err, RELIEF_E_RANGE, "fit", "fit model %d is not one of "
                                 "auto, plane, sphere, cylinder", (int)p->fit);
    if (p->window < 1 || p->window > 16)
        return relief_fail_param(err, RELIEF_E_RANGE, "window",
                                 "window %d out of range: expected 1..16 edge hops", p->window);
    if (p->rotations < 0 || p->rotations > 64)
        return relief_fail_param(err, RELIEF_E_RANGE, "rotations",
                                 "rotations %d out of range: expected 1..64 (0: the "
                                 "primitive's default)", p->rotations);
    if (!(p->error > 0.0 && p->error <= 1e6))
        return relief_fail_param(err, RELIEF_E_RANGE, "error",
                                 "error threshold %g out of range: expected 0 < e <= 1e6",
                                 p->error);
    if (!(p->coherence == 0.0 || (p->coherence >= 1.0 && p->coherence <= 100.0)))
        return relief_fail_param(err, RELIEF_E_RANGE, "coherence",
                                 "coherence %g out of range: expected 0 (off) or 1..100",
                                 p->coherence);
    if (!(p->mu < 0.0 && p->mu == -1.0) && !(p->mu >= 0.0 && p->mu <= 1.0))
        return relief_fail_param(err, RELIEF_E_RANGE, "mu",
                                 "mu %g out of range: expected 0 <= mu <= 1", p->mu);
    if (p->search < RELIEF_SEARCH_AUTO || p->search > RELIEF_SEARCH_COHERENT)
        return relief_fail_param(err, RELIEF_E_RANGE, "search", "search %d is not one of "
                                 "auto, exhaustive, coherent", (int)p->search);
    if (p->search_k < 1 || p->search_k > 64)
        return relief_fail_param(err, RELIEF_E_RANGE, "search_k",
                                 "search_k %d out of range: expected 1..64", p->search_k);
    if (p->levels < 1 || p->levels > 8)
        return relief_fail_param(err, RELIEF_E_RANGE, "levels",
                                 "levels %d out of range: expected 1..8", p->levels);
    return RELIEF_OK;
}

/* Where it runs, and the capture's sampling. */
static relief_status validate_run(const relief_params *p, relief_error *err)
{
    if (p->backend < RELIEF_BACKEND_AUTO || p->backend > RELIEF_BACKEND_HOST)
        return relief_fail_param(err, RELIEF_E_RANGE, "backend", "backend %d is not one of "
                                 "auto, scalar, opencl, host", (int)p->backend);
    if (p->device < -1 || p->device > 255)
        return relief_fail_param(err, RELIEF_E_RANGE, "device",
                                 "device %d out of range: expected 0..255", p->device);
    if (p->threads < 0 || p->threads > RELIEF_THREADS_MAX)
        return relief_fail_param(err, RELIEF_E_RANGE, "threads", "threads %d out of range: "
                                 "expected 1..%d (0: the CPUs this thread may run on)",
                                 p->threads, RELIEF_THREADS_MAX);
    if (p->oversample < 0 || p->oversample > 4)
        return relief_fail_param(err, RELIEF_E_RANGE, "oversample",
                                 "oversample %d out of range: expected 0..4", p->oversample);
    if (!(p->spacing == 0.0 || (p->spacing > 0.0 && isfinite(p->spacing))))
        return relief_fail_param(err, RELIEF_E_RANGE, "spacing",
                                 "spacing %g out of range: expected a finite value > 0 "
                                 "(or 0 for the capture's own)", p->spacing);
    return RELIEF_OK;
}

relief_status relief_params_validate(const relief_params *p, relief_error *err)
{
    relief_status st = validate_growth(p, err);
    if (st == RELIEF_OK)
        st = validate_run(p, err);
    if (st == RELIEF_OK && p->has_extent)
        st = validate_extent(p, err);
    return st;
}
