/* Backend choice and the calls every backend goes through. */
#include <stdio.h>
#include <stdlib.h>

#include "error.h"
#include "matcher.h"
#include "report.h"

#ifndef RELIEF_HAVE_OPENCL
relief_status relief_matcher_opencl_create(const relief_match_data *d, int device,
                                           relief_matcher **out, relief_error *err)
{
    (void)d;
    (void)device;
    (void)out;
    return relief_fail(err, RELIEF_E_NOT_BUILT,
                       "relief was built without OpenCL (RELIEF_WITH_OPENCL=OFF)");
}
#endif

relief_status relief_matcher_create(relief_backend backend, int device,
                                    const relief_match_data *d, relief_matcher **out,
                                    char *note, size_t note_size, relief_error *err)
{
    relief_status st;
    if (note && note_size)
        note[0] = '\0';
    if (backend == RELIEF_BACKEND_SCALAR)
        return relief_matcher_scalar_create(d, out, err);
    st = relief_matcher_opencl_create(d, device, out, err);
    if (st == RELIEF_OK || backend == RELIEF_BACKEND_OPENCL)
        return st;
    /* auto: say why, then fall back to the reference. */
    if (note && note_size)
        snprintf(note, note_size, "OpenCL unavailable (%s); using the scalar matcher",
                 err ? err->message : relief_strerror(st));
    return relief_matcher_scalar_create(d, out, err);
}

size_t relief_match_query_candidates(const relief_match_data *d, const relief_match_query *q)
{
    return (size_t)(q->subset ? q->n_subset : d->ns) * (size_t)d->rotations;
}

relief_status relief_matcher_score(relief_matcher *m, const relief_match_data *d,
                                   const relief_match_query *q, float *ssd, uint8_t *flag,
                                   relief_error *err)
{
    double t0 = relief_seconds();
    relief_status st = m->ops->score(m->ctx, d, q, ssd, flag, err);
    m->kernel_seconds += relief_seconds() - t0;
    return st;
}

relief_status relief_matcher_update(relief_matcher *m, const relief_match_data *d, uint32_t v,
                                    relief_error *err)
{
    return m->ops->update(m->ctx, d, v, err);
}

void relief_matcher_destroy(relief_matcher *m)
{
    if (!m)
        return;
    m->ops->destroy(m->ctx);
    free(m);
}
