/* The scalar twin of kernels/patch.cl: the same pm_score, one candidate
 * after another, in the rectangle's row-major order. */
#include "image/patch.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "kernels/patch_math.h"

typedef struct scalar_ctx {
    const relief_patch_level *levels;
    int n_levels;
} scalar_ctx;

static relief_status scalar_bind(void *ctx, const relief_patch_level *levels, int n_levels,
                                 relief_error *err)
{
    scalar_ctx *s = ctx;
    (void)err;
    s->levels = levels;
    s->n_levels = n_levels;
    return RELIEF_OK;
}

static relief_status scalar_update(void *ctx, int level, int y0, int y1, relief_error *err)
{
    (void)ctx, (void)level, (void)y0, (void)y1, (void)err;
    return RELIEF_OK; /* it reads the filler's own arrays */
}

static relief_status scalar_score_rect(void *ctx, int level, int qx, int qy, int radius,
                                       int max_holes, const float *g, int x0, int y0, int nx,
                                       int ny, float *ssd, float *wsum, int *n,
                                       relief_error *err)
{
    const relief_patch_level *l = &((scalar_ctx *)ctx)->levels[level];
    float ws;
    (void)err;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            size_t k = (size_t)j * nx + i;
            pm_score(l->v, l->known, l->width, l->height, l->channels, qx, qy, x0 + i, y0 + j,
                     radius, max_holes, g, g != NULL, &ssd[k], &ws, &n[k]);
            if (wsum)
                wsum[k] = ws;
        }
    return RELIEF_OK;
}

static relief_status scalar_score_list(void *ctx, int level, int qx, int qy, int radius,
                                       int max_holes, const float *g, const int *xy, int count,
                                       float *ssd, float *wsum, int *n, relief_error *err)
{
    const relief_patch_level *l = &((scalar_ctx *)ctx)->levels[level];
    float ws;
    (void)err;
    for (int i = 0; i < count; ++i) {
        pm_score(l->v, l->known, l->width, l->height, l->channels, qx, qy, xy[2 * i],
                 xy[2 * i + 1], radius, max_holes, g, g != NULL, &ssd[i], &ws, &n[i]);
        if (wsum)
            wsum[i] = ws;
    }
    return RELIEF_OK;
}

static void scalar_destroy(void *ctx) { free(ctx); }

static const relief_patch_ops scalar_ops = {scalar_bind, scalar_update, scalar_score_rect,
                                            scalar_score_list, scalar_destroy, NULL, NULL,
                                            NULL};

relief_status relief_patch_scalar_create(relief_patch_scorer **out, relief_error *err)
{
    relief_patch_scorer *s = calloc(1, sizeof *s);
    scalar_ctx *c = calloc(1, sizeof *c);
    if (!s || !c) {
        free(s);
        free(c);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the scalar scorer");
    }
    s->ops = &scalar_ops;
    s->ctx = c;
    s->backend = RELIEF_BACKEND_SCALAR;
    s->threads = 1;
    snprintf(s->device, sizeof s->device, "host (1 thread, scalar reference)");
    *out = s;
    return RELIEF_OK;
}

void relief_patch_scorer_destroy(relief_patch_scorer *s)
{
    if (s) {
        s->ops->destroy(s->ctx);
        free(s);
    }
}

relief_status relief_patch_scorer_create(relief_backend backend, int device, int threads,
                                         relief_patch_scorer **out, char *note,
                                         size_t note_size, relief_reason *why_code,
                                         relief_error *err)
{
    relief_error why = {0};
    relief_status st;
    if (note && note_size)
        note[0] = '\0';
    if (why_code)
        *why_code = RELIEF_REASON_NONE;
    if (backend == RELIEF_BACKEND_SCALAR)
        return relief_patch_scalar_create(out, err);
    if (backend == RELIEF_BACKEND_HOST)
        return relief_patch_host_create(threads, out, err);
    if (backend == RELIEF_BACKEND_OPENCL)
        return relief_patch_opencl_create(device, out, err);
    /* auto: OpenCL on the device named; else the host's threads, with or
     * without a GPU. The filler asks one query at a time (a window
     * search per pasted patch or synthesised pixel), and a launch and its
     * read-back per query cost more than the host's lanes and threads
     * spend on it: on an NVIDIA H100 with a 16-core host (bench/gpu.sh,
     * 27 November 2026, README) the host's threads filled the astronaut in
     * 0.79 s against the GPU's 1.55, the 2048 x 2048 grass in 4.66 against
     * 5.27, the atlas in 1.61 against 2.77, and repaired office1 in 0.94 s
     * against 12.19; on a CPU device the kernel runs on the same cores. */
    if (device < 0) {
        /* No device is enumerated to word this: that would start the
         * OpenCL platforms on every run that will not use them. */
        if (note && note_size)
            snprintf(note, note_size, "backend auto: the host's threads (a launch per window "
                     "search measured slower than them on a GPU, and no faster on a CPU; "
                     "backend opencl to use it)");
        return relief_patch_host_create(threads, out, err);
    }
    st = relief_patch_opencl_create(device, out, &why);
    if (st == RELIEF_OK) {
        if (note && note_size)
            snprintf(note, note_size, "backend auto: OpenCL on %s", (*out)->device);
        return RELIEF_OK;
    }
    if (st == RELIEF_E_RANGE) /* a --device there is none of is the user's mistake */
        return relief_fail(err, st, "%s", why.message);
    if (note && note_size)
        snprintf(note, note_size, "OpenCL unavailable (%s); backend auto: the host's "
                 "threads", why.message);
    if (why_code)
        *why_code = RELIEF_REASON_DEVICE_FELL_BACK;
    return relief_patch_host_create(threads, out, err);
}
