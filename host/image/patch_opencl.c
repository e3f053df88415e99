/* The OpenCL scorer of the image hole filler: kernels/patch.cl, which runs
 * kernels/patch_math.h's pm_score, the scalar twin's arithmetic. The
 * pyramid's levels go to the device once; the rows pastes changed travel
 * before the next launch, and only the scores come back. A single query
 * is a batch of one (patch_score_rects, patch_score_pairs). */
#include "image/patch.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "kernels/patch_math.h" /* PM_BLOCK */

#ifdef RELIEF_HAVE_OPENCL
#include "device/cl_profile.h"
#include "device/ocl.h"

extern const char relief_kernel_patch_math_h[];
extern const char relief_kernel_patch_cl[];

#define MAX_LEVELS 8
/* One work-group shape for every launch: rows of 32 neighbouring candidates
 * (their reads of the level fall side by side), 2 rows. Left to the
 * implementation, PoCL picked a shape per rectangle size and compiled the
 * kernel again for each: 29 ms a launch on grass.png against 5 ms of
 * work. */
#define WG_X 32
#define WG_Y 2
/* Weights of a radius up to 512 (windows up to 1025, fill.h's bound). */
#define G_MAX 513
/* The selection's margin over the float msd the device ranks blocks by:
 * far above its division's 2.5 ulp (3e-7) and a flushed subnormal. */
#define SELECT_REL 1e-5
#define SELECT_ABS 1e-30

typedef struct patch_cl {
    cl_context ctx;
    cl_command_queue queue;
    relief_cl_profile *prof; /* RELIEF_OPENCL_PROFILE's record; NULL: off */
    cl_program prog;
    cl_kernel rects_kernel, pairs_kernel, bmin_kernel, gather_kernel;
    const relief_patch_level *levels;
    int n_levels;
    cl_mem v[MAX_LEVELS], known[MAX_LEVELS];
    cl_mem ssd, wsum, n; /* the scores of the last rectangle or list */
    size_t cap;          /* candidates they hold */
    cl_mem g;            /* the weights of the last weighted call (G_MAX floats) */
    float g_host[G_MAX]; /* what g holds, so that it travels only when it changes */
    int g_len;           /* entries of g_host in use; 0 none yet */
    cl_mem batch;     /* the last batch's rectangles or pairs */
    size_t batch_cap; /* ints batch holds */
    int *batch_host;  /* what batch was sent from (the scorer's copy) */
    size_t batch_host_cap;
    int batch_in_flight; /* batch_host's write may not be done: no blocking
                            read or clFinish since it was queued */
    int dirty_lo[MAX_LEVELS], dirty_hi[MAX_LEVELS]; /* rows changed on the host and not
                                                       yet on the device (lo > hi: none) */
    /* select_rects: each rectangle's first block (bstart, count + 1 ints),
     * the blocks' least msd (bmin), the blocks chosen (sel: first score,
     * length) and their scores gathered (out_*), on the device and here;
     * runs, what select_rects returns. */
    int can_select;     /* patch_block_min runs PM_BLOCK work-items a group */
    size_t select_from; /* batches of fewer scores are read back whole */
    cl_mem bstart, bmin, sel, out_ssd, out_wsum, out_n;
    size_t bstart_cap, bmin_cap, sel_cap, out_cap; /* elements each holds */
    int *bstart_host, *sel_host, *runs;
    float *bmin_host;
    size_t bstart_host_cap, sel_host_cap, runs_cap, bmin_host_cap;
} patch_cl;

/* Free p; `created`: its creation succeeded (the profile is written). */
static void patch_cl_free(patch_cl *p, int created)
{
    if (!p)
        return;
    if (p->queue && p->batch_in_flight) /* not met: every path ends waiting */
        clFinish(p->queue);
    relief_cl_profile_close(p->prof, created);
    for (int l = 0; l < MAX_LEVELS; ++l) {
        if (p->v[l])
            clReleaseMemObject(p->v[l]);
        if (p->known[l])
            clReleaseMemObject(p->known[l]);
    }
    if (p->ssd)
        clReleaseMemObject(p->ssd);
    if (p->wsum)
        clReleaseMemObject(p->wsum);
    if (p->n)
        clReleaseMemObject(p->n);
    if (p->g)
        clReleaseMemObject(p->g);
    if (p->batch)
        clReleaseMemObject(p->batch);
    {
        cl_mem sel_mems[6] = {p->bstart, p->bmin, p->sel, p->out_ssd, p->out_wsum, p->out_n};
        for (int i = 0; i < 6; ++i)
            if (sel_mems[i])
                clReleaseMemObject(sel_mems[i]);
    }
    if (p->bmin_kernel)
        clReleaseKernel(p->bmin_kernel);
    if (p->gather_kernel)
        clReleaseKernel(p->gather_kernel);
    free(p->batch_host);
    free(p->bstart_host);
    free(p->sel_host);
    free(p->runs);
    free(p->bmin_host);
    if (p->rects_kernel)
        clReleaseKernel(p->rects_kernel);
    if (p->pairs_kernel)
        clReleaseKernel(p->pairs_kernel);
    if (p->prog)
        clReleaseProgram(p->prog);
    if (p->queue)
        clReleaseCommandQueue(p->queue);
    if (p->ctx)
        clReleaseContext(p->ctx);
    free(p);
}

static relief_status buffer(patch_cl *p, cl_mem *mem, const void *host, size_t bytes,
                            const char *what, relief_error *err)
{
    cl_int rc;
    *mem = clCreateBuffer(p->ctx, host ? CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR
                                       : CL_MEM_WRITE_ONLY,
                          bytes, (void *)host, &rc);
    if (rc != CL_SUCCESS)
        return relief_fail(err, RELIEF_E_DEVICE, "cannot allocate %zu bytes of device memory "
                           "for %s: %s", bytes, what, relief_cl_error_name(rc));
    return RELIEF_OK;
}

static relief_status patch_cl_bind(void *ctx, const relief_patch_level *levels, int n_levels,
                                   relief_error *err)
{
    patch_cl *p = ctx;
    relief_status st = RELIEF_OK;
    if (n_levels > MAX_LEVELS)
        return relief_fail(err, RELIEF_E_INTERNAL, "%d pyramid levels; the OpenCL scorer "
                           "holds %d", n_levels, MAX_LEVELS);
    /* A scorer serves one fill after another: the last fill's levels go. */
    for (int l = 0; l < MAX_LEVELS; ++l) {
        if (p->v[l])
            clReleaseMemObject(p->v[l]);
        if (p->known[l])
            clReleaseMemObject(p->known[l]);
        p->v[l] = p->known[l] = NULL;
    }
    p->levels = levels;
    p->n_levels = n_levels;
    for (int l = 0; l < MAX_LEVELS; ++l)
        p->dirty_lo[l] = 1, p->dirty_hi[l] = 0;
    for (int l = 0; l < n_levels && st == RELIEF_OK; ++l) {
        size_t px = (size_t)levels[l].width * levels[l].height;
        st = buffer(p, &p->v[l], levels[l].v, px * levels[l].channels * sizeof(float),
                    "an image level", err);
        if (st == RELIEF_OK)
            st = buffer(p, &p->known[l], levels[l].known, px, "a level's known pixels", err);
    }
    return st;
}

/* Rows y0..y1 of a level changed: noted, and sent before the next launch
 * (flush), so that a batch's many pastes cost one write per level rather
 * than a round trip each. */
static relief_status patch_cl_update(void *ctx, int level, int y0, int y1, relief_error *err)
{
    patch_cl *p = ctx;
    (void)err;
    if (p->dirty_lo[level] > p->dirty_hi[level]) {
        p->dirty_lo[level] = y0, p->dirty_hi[level] = y1;
    } else {
        p->dirty_lo[level] = y0 < p->dirty_lo[level] ? y0 : p->dirty_lo[level];
        p->dirty_hi[level] = y1 > p->dirty_hi[level] ? y1 : p->dirty_hi[level];
    }
    return RELIEF_OK;
}

/* The rows changed since the last launch, onto the device (in order
 * before the launch; the host changes them again only after the launch's
 * scores are read back). */
static cl_int flush(patch_cl *p)
{
    cl_int rc = CL_SUCCESS;
    for (int level = 0; level < p->n_levels && rc == CL_SUCCESS; ++level) {
        const relief_patch_level *l = &p->levels[level];
        size_t row = (size_t)l->width, first, count;
        if (p->dirty_lo[level] > p->dirty_hi[level])
            continue;
        first = (size_t)p->dirty_lo[level] * row;
        count = (size_t)(p->dirty_hi[level] - p->dirty_lo[level] + 1) * row;
        size_t bytes = count * l->channels * sizeof(float);
        rc = clEnqueueWriteBuffer(p->queue, p->v[level], CL_FALSE,
                                  first * l->channels * sizeof(float), bytes,
                                  l->v + first * l->channels, 0, NULL,
                                  relief_cl_profile_event(p->prof, "write", bytes));
        if (rc == CL_SUCCESS)
            rc = clEnqueueWriteBuffer(p->queue, p->known[level], CL_FALSE, first, count,
                                      l->known + first, 0, NULL,
                                      relief_cl_profile_event(p->prof, "write", count));
        p->dirty_lo[level] = 1, p->dirty_hi[level] = 0;
    }
    return rc;
}

/* Room for `count` scores on the device. */
static relief_status grow_scores(patch_cl *p, size_t count, relief_error *err)
{
    relief_status st;
    if (count <= p->cap)
        return RELIEF_OK;
    if (p->ssd)
        clReleaseMemObject(p->ssd);
    if (p->wsum)
        clReleaseMemObject(p->wsum);
    if (p->n)
        clReleaseMemObject(p->n);
    p->ssd = p->wsum = p->n = NULL;
    p->cap = 0;
    st = buffer(p, &p->ssd, NULL, count * sizeof(float), "window scores", err);
    if (st == RELIEF_OK)
        st = buffer(p, &p->wsum, NULL, count * sizeof(float), "window scores", err);
    if (st == RELIEF_OK)
        st = buffer(p, &p->n, NULL, count * sizeof(int), "window scores", err);
    if (st == RELIEF_OK)
        p->cap = count;
    return st;
}

/* The weights `g` (radius + 1 of them) on the device, unless they are
 * there already; NULL (unweighted) leaves the buffer as it is. */
static cl_int put_weights(patch_cl *p, const float *g, int radius)
{
    int len = radius + 1;
    cl_int rc;
    if (!g || (len == p->g_len && memcmp(g, p->g_host, (size_t)len * sizeof *g) == 0))
        return CL_SUCCESS;
    if (len > G_MAX)
        return CL_INVALID_VALUE;
    rc = clEnqueueWriteBuffer(p->queue, p->g, CL_TRUE, 0, (size_t)len * sizeof *g, g, 0, NULL,
                              relief_cl_profile_event(p->prof, "write", (size_t)len * sizeof *g));
    if (rc == CL_SUCCESS) {
        memcpy(p->g_host, g, (size_t)len * sizeof *g);
        p->g_len = len;
        p->batch_in_flight = 0;
    }
    return rc;
}

/* Read `count` scores back from the device's ssd, wsum and n (blocking:
 * the queue is in order); wsum may be NULL. */
static cl_int read_scores(patch_cl *p, const cl_mem from[3], size_t count, float *ssd,
                          float *wsum, int *n)
{
    size_t bytes = count * sizeof(float);
    cl_int rc = clEnqueueReadBuffer(p->queue, from[0], CL_FALSE, 0, bytes, ssd, 0, NULL,
                                    relief_cl_profile_event(p->prof, "read", bytes));
    if (rc == CL_SUCCESS && wsum)
        rc = clEnqueueReadBuffer(p->queue, from[1], CL_FALSE, 0, bytes, wsum, 0, NULL,
                                 relief_cl_profile_event(p->prof, "read", bytes));
    if (rc == CL_SUCCESS)
        rc = clEnqueueReadBuffer(p->queue, from[2], CL_TRUE, 0, count * sizeof(int), n, 0, NULL,
                                 relief_cl_profile_event(p->prof, "read", count * sizeof(int)));
    if (rc == CL_SUCCESS)
        p->batch_in_flight = 0;
    return rc;
}

/* Host array `ptr` with room for `need` elements of `size` bytes (*cap
 * updated), or `ptr` as it was with *ok 0. */
static void *grown(void *ptr, size_t *cap, size_t need, size_t size, int *ok)
{
    void *b;
    if (need <= *cap)
        return ptr;
    b = realloc(ptr, need * size);
    if (!b) {
        *ok = 0;
        return ptr;
    }
    *cap = need;
    return b;
}
#define GROW_HOST(ptr, cap, need, ok) ((ptr) = grown((ptr), &(cap), (need), sizeof *(ptr), &(ok)))

/* `ints` ints onto the device's batch buffer (grown as needed), queued
 * without waiting: they go from the scorer's own copy, which stays until
 * the launch's blocking read, so a launch costs one wait for the device,
 * not two (PoCL, office1's plain depth repair: 8.3-8.9 s to 6.6-7.5 s). */
static relief_status put_batch(patch_cl *p, const int *data, size_t ints, relief_error *err)
{
    cl_int rc;
    int ok = 1;
    if (p->batch_in_flight) /* not met in the scorer's paths: each launch reads back */
        clFinish(p->queue);
    p->batch_in_flight = 0;
    GROW_HOST(p->batch_host, p->batch_host_cap, ints, ok);
    if (!ok)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a batch of %zu ints", ints);
    if (ints > p->batch_cap) {
        relief_status st;
        if (p->batch)
            clReleaseMemObject(p->batch);
        p->batch = NULL;
        p->batch_cap = 0;
        st = buffer(p, &p->batch, NULL, ints * sizeof(int), "a batch of windows", err);
        if (st != RELIEF_OK)
            return st;
        p->batch_cap = ints;
    }
    memcpy(p->batch_host, data, ints * sizeof(int));
    rc = clEnqueueWriteBuffer(p->queue, p->batch, CL_FALSE, 0, ints * sizeof(int),
                              p->batch_host, 0, NULL,
                              relief_cl_profile_event(p->prof, "write", ints * sizeof(int)));
    if (rc != CL_SUCCESS)
        return relief_fail(err, RELIEF_E_DEVICE, "sending a batch of windows to the device: %s",
                           relief_cl_error_name(rc));
    p->batch_in_flight = 1;
    return RELIEF_OK;
}

/* A launch that failed on the way: what was queued (the levels' rows read
 * from the host) is waited for before the caller may free anything. */
static relief_status launch_failed(patch_cl *p, cl_int rc, const char *what,
                                   relief_error *err)
{
    clFinish(p->queue);
    p->batch_in_flight = 0;
    return relief_fail(err, RELIEF_E_DEVICE, "%s: %s", what, relief_cl_error_name(rc));
}

/* The arguments both batched kernels take, in their order. */
static cl_int batch_args(patch_cl *p, cl_kernel k, int level, int radius, int max_holes,
                         int weighted, int count)
{
    const relief_patch_level *l = &p->levels[level];
    cl_int rc = CL_SUCCESS;
    int a = 0;
#define ARG(x) (rc |= clSetKernelArg(k, a++, sizeof(x), &(x)))
    ARG(p->v[level]);
    ARG(p->known[level]);
    ARG(l->width);
    ARG(l->height);
    ARG(l->channels);
    ARG(radius);
    ARG(max_holes);
    ARG(p->g);
    ARG(weighted);
    ARG(p->batch);
    ARG(count);
    ARG(p->ssd);
    ARG(p->wsum);
    ARG(p->n);
#undef ARG
    return rc;
}

/* A batched kernel's launch over `dims` dimensions: the batch's ints
 * sent, the levels' pending rows and the weights flushed, the arguments
 * set, the kernel run and `scores` scores read back (none when ssd is
 * NULL: they stay on the device). */
typedef struct launch_shape {
    cl_kernel kernel;
    cl_uint dims;
    size_t global[3], local[3];
    const char *name; /* the kernel's, for a profile */
    const char *what; /* for the message when it fails */
} launch_shape;

static relief_status launch(patch_cl *p, const launch_shape *k, int level, int radius,
                            int max_holes, const float *g, const int *batch, size_t ints,
                            int count, size_t scores, float *ssd, float *wsum, int *n,
                            relief_error *err)
{
    relief_status st = grow_scores(p, scores, err);
    cl_int rc;
    if (st == RELIEF_OK)
        st = put_batch(p, batch, ints, err);
    if (st != RELIEF_OK)
        return st;
    rc = flush(p);
    if (rc == CL_SUCCESS)
        rc = put_weights(p, g, radius);
    if (rc == CL_SUCCESS)
        rc = batch_args(p, k->kernel, level, radius, max_holes, g != NULL, count);
    if (rc == CL_SUCCESS)
        rc = clEnqueueNDRangeKernel(p->queue, k->kernel, k->dims, NULL, k->global, k->local, 0,
                                    NULL, relief_cl_profile_event(p->prof, k->name, 0));
    if (rc == CL_SUCCESS && ssd) {
        const cl_mem from[3] = {p->ssd, p->wsum, p->n};
        rc = read_scores(p, from, scores, ssd, wsum, n);
    }
    if (rc != CL_SUCCESS)
        return launch_failed(p, rc, k->what, err);
    return RELIEF_OK;
}

/* The launch of patch_score_rects over a batch's rectangles: the largest
 * one's extent, rounded up to the work-group, by the queries. */
static launch_shape rects_shape(const patch_cl *p, const int *rects, int count)
{
    launch_shape k = {p->rects_kernel, 3, {0, 0, (size_t)count}, {WG_X, WG_Y, 1},
                      "patch_score_rects", "scoring a batch of windows on the device"};
    for (int q = 0; q < count; ++q) {
        size_t nx = ((size_t)rects[7 * q + 4] + WG_X - 1) / WG_X * WG_X;
        size_t ny = ((size_t)rects[7 * q + 5] + WG_Y - 1) / WG_Y * WG_Y;
        k.global[0] = nx > k.global[0] ? nx : k.global[0];
        k.global[1] = ny > k.global[1] ? ny : k.global[1];
    }
    return k;
}

static relief_status patch_cl_score_rects(void *ctx, int level, int radius, int max_holes,
                                          const float *g, const int *rects, int count,
                                          size_t total, float *ssd, float *wsum, int *n,
                                          relief_error *err)
{
    patch_cl *p = ctx;
    launch_shape k;
    if (count <= 0)
        return RELIEF_OK;
    k = rects_shape(p, rects, count);
    return launch(p, &k, level, radius, max_holes, g, rects, 7 * (size_t)count, count, total,
                  ssd, wsum, n, err);
}

static relief_status patch_cl_score_pairs(void *ctx, int level, int radius, int max_holes,
                                          const float *g, const int *pairs, int count,
                                          float *ssd, float *wsum, int *n, relief_error *err)
{
    patch_cl *p = ctx;
    size_t local = WG_X * WG_Y;
    launch_shape k = {p->pairs_kernel, 1, {((size_t)count + local - 1) / local * local, 1, 1},
                      {local, 1, 1}, "patch_score_pairs",
                      "scoring a batch of refinements on the device"};
    if (count <= 0)
        return RELIEF_OK;
    return launch(p, &k, level, radius, max_holes, g, pairs, 4 * (size_t)count, count,
                  (size_t)count, ssd, wsum, n, err);
}

/* Room for `need` elements of `size` bytes in a device buffer of
 * select_rects (its contents are not kept). */
static relief_status grow_mem(patch_cl *p, cl_mem *mem, size_t *cap, size_t need, size_t size,
                              relief_error *err)
{
    cl_int rc;
    if (need <= *cap)
        return RELIEF_OK;
    if (*mem)
        clReleaseMemObject(*mem);
    *cap = 0;
    *mem = clCreateBuffer(p->ctx, CL_MEM_READ_WRITE, need * size, NULL, &rc);
    if (rc != CL_SUCCESS) {
        *mem = NULL;
        return relief_fail(err, RELIEF_E_DEVICE, "cannot allocate %zu bytes of device memory "
                           "for selecting windows: %s", need * size, relief_cl_error_name(rc));
    }
    *cap = need;
    return RELIEF_OK;
}

/* select_rects' runs when every score came back: one a rectangle. */
static relief_status runs_whole(patch_cl *p, const int *rects, int count, const int **runs,
                                size_t *n_runs, relief_error *err)
{
    int ok = 1;
    GROW_HOST(p->runs, p->runs_cap, 4 * (size_t)count, ok);
    if (!ok)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate %d runs of scores", count);
    for (int q = 0; q < count; ++q) {
        const int *r = rects + 7 * q;
        int *run = p->runs + 4 * q;
        run[0] = q, run[1] = 0, run[2] = r[4] * r[5], run[3] = r[6];
    }
    *runs = p->runs;
    *n_runs = (size_t)count;
    return RELIEF_OK;
}

/* The most matches a query keeps that the selection bounds; a query that
 * keeps more reads every block that holds a candidate. */
#define SELECT_KEEP_MAX 64

/* Rectangle q's (r's) blocks b0 .. b1 - 1 that may hold its `keep` best:
 * those whose least msd is within the margin of the keep-th least block
 * minimum (keep blocks each hold a window that good, so the keep best are
 * at least that good, and a block whose every window is worse by more than
 * the rounding holds none of them). Appended to sel_host and runs from
 * entry `nsel`; the new count. A NaN minimum (no candidate) is never
 * taken, -infinity (a non-finite msd, which bounds nothing) always. */
static size_t choose_blocks(patch_cl *p, const int *r, int q, int keep, size_t b0, size_t b1,
                            size_t nsel)
{
    float kth[SELECT_KEEP_MAX];
    int have = 0, size = r[4] * r[5];
    double t = INFINITY;
    for (size_t b = b0; b < b1 && keep <= SELECT_KEEP_MAX; ++b) {
        float v = p->bmin_host[b];
        int i;
        if (!isfinite(v) || (have == keep && v >= kth[keep - 1]))
            continue;
        i = have < keep ? have++ : keep - 1;
        for (; i > 0 && v < kth[i - 1]; --i)
            kth[i] = kth[i - 1];
        kth[i] = v;
    }
    if (keep <= SELECT_KEEP_MAX && have == keep)
        t = (double)kth[keep - 1] * (1.0 + SELECT_REL) + SELECT_ABS;
    for (size_t b = b0; b < b1; ++b) {
        int first = (int)(b - b0) * PM_BLOCK, len = size - first < PM_BLOCK ? size - first
                                                                            : PM_BLOCK;
        int *run = p->runs + 4 * nsel;
        if (!((double)p->bmin_host[b] <= t))
            continue;
        p->sel_host[2 * nsel] = r[6] + first, p->sel_host[2 * nsel + 1] = len;
        run[0] = q, run[1] = first, run[2] = len, run[3] = (int)nsel * PM_BLOCK;
        ++nsel;
    }
    return nsel;
}

/* Each rectangle's least msd per block, on the device, into bmin_host:
 * the scores of the last launch, the blocks numbered by bstart_host. */
static cl_int block_minima(patch_cl *p, int weighted, int count, size_t blocks)
{
    size_t global = blocks * PM_BLOCK, local = PM_BLOCK;
    size_t bytes = ((size_t)count + 1) * sizeof(int);
    cl_int rc = clEnqueueWriteBuffer(p->queue, p->bstart, CL_FALSE, 0, bytes, p->bstart_host, 0,
                                     NULL, relief_cl_profile_event(p->prof, "write", bytes));
    int a = 0;
#define ARG(x) (rc |= clSetKernelArg(p->bmin_kernel, a++, sizeof(x), &(x)))
    ARG(p->ssd);
    ARG(p->wsum);
    ARG(p->n);
    ARG(weighted);
    ARG(p->batch);
    ARG(p->bstart);
    ARG(count);
    ARG(p->bmin);
#undef ARG
    if (rc == CL_SUCCESS)
        rc = clEnqueueNDRangeKernel(p->queue, p->bmin_kernel, 1, NULL, &global, &local, 0, NULL,
                                    relief_cl_profile_event(p->prof, "patch_block_min", 0));
    if (rc == CL_SUCCESS)
        rc = clEnqueueReadBuffer(p->queue, p->bmin, CL_TRUE, 0, blocks * sizeof(float),
                                 p->bmin_host, 0, NULL,
                                 relief_cl_profile_event(p->prof, "read", blocks * sizeof(float)));
    if (rc == CL_SUCCESS)
        p->batch_in_flight = 0;
    return rc;
}

/* The `nsel` blocks of sel_host gathered side by side on the device and
 * read back into ssd, wsum (may be NULL) and n. */
static cl_int gather(patch_cl *p, size_t nsel, float *ssd, float *wsum, int *n)
{
    size_t global = nsel * PM_BLOCK, local = PM_BLOCK;
    int blocks = (int)nsel, a = 0;
    cl_int rc = clEnqueueWriteBuffer(p->queue, p->sel, CL_FALSE, 0, 2 * nsel * sizeof(int),
                                     p->sel_host, 0, NULL,
                                     relief_cl_profile_event(p->prof, "write",
                                                             2 * nsel * sizeof(int)));
#define ARG(x) (rc |= clSetKernelArg(p->gather_kernel, a++, sizeof(x), &(x)))
    ARG(p->ssd);
    ARG(p->wsum);
    ARG(p->n);
    ARG(p->sel);
    ARG(blocks);
    ARG(p->out_ssd);
    ARG(p->out_wsum);
    ARG(p->out_n);
#undef ARG
    if (rc == CL_SUCCESS)
        rc = clEnqueueNDRangeKernel(p->queue, p->gather_kernel, 1, NULL, &global, &local, 0,
                                    NULL, relief_cl_profile_event(p->prof, "patch_gather", 0));
    if (rc == CL_SUCCESS) {
        const cl_mem from[3] = {p->out_ssd, p->out_wsum, p->out_n};
        rc = read_scores(p, from, global, ssd, wsum, n);
    }
    return rc;
}

/* Room for `need` gathered scores on the device (out_ssd, out_wsum and
 * out_n, grown together). */
static relief_status grow_out(patch_cl *p, size_t need, relief_error *err)
{
    size_t c0 = p->out_cap, c1 = p->out_cap, c2 = p->out_cap;
    relief_status st = grow_mem(p, &p->out_ssd, &c0, need, sizeof(float), err);
    if (st == RELIEF_OK)
        st = grow_mem(p, &p->out_wsum, &c1, need, sizeof(float), err);
    if (st == RELIEF_OK)
        st = grow_mem(p, &p->out_n, &c2, need, sizeof(int), err);
    p->out_cap = st == RELIEF_OK ? c0 : 0;
    return st;
}

/* The `count` rectangles' blocks numbered (bstart_host: rectangle q's
 * first, and bstart_host[count] their number), and room on the host and
 * the device for a selection over them. */
static relief_status select_room(patch_cl *p, const int *rects, int count, relief_error *err)
{
    relief_status st;
    size_t blocks = 0;
    int ok = 1;
    GROW_HOST(p->bstart_host, p->bstart_host_cap, (size_t)count + 1, ok);
    if (!ok)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a batch of %d searches", count);
    for (int q = 0; q < count; ++q) {
        p->bstart_host[q] = (int)blocks;
        blocks += ((size_t)rects[7 * q + 4] * rects[7 * q + 5] + PM_BLOCK - 1) / PM_BLOCK;
    }
    p->bstart_host[count] = (int)blocks;
    GROW_HOST(p->bmin_host, p->bmin_host_cap, blocks, ok);
    GROW_HOST(p->sel_host, p->sel_host_cap, 2 * blocks, ok);
    GROW_HOST(p->runs, p->runs_cap, 4 * blocks, ok);
    if (!ok)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the selection of %zu blocks "
                           "of windows", blocks);
    st = grow_mem(p, &p->bstart, &p->bstart_cap, (size_t)count + 1, sizeof(int), err);
    if (st == RELIEF_OK)
        st = grow_mem(p, &p->bmin, &p->bmin_cap, blocks, sizeof(float), err);
    return st;
}

static relief_status patch_cl_select_rects(void *ctx, int level, int radius, int max_holes,
                                           const float *g, const int *rects, const int *keep,
                                           int count, size_t total, float *ssd, float *wsum,
                                           int *n, const int **runs, size_t *n_runs,
                                           relief_error *err)
{
    patch_cl *p = ctx;
    size_t blocks = 0, nsel = 0;
    launch_shape k;
    relief_status st;
    cl_int rc;
    *runs = NULL;
    *n_runs = 0;
    if (count <= 0)
        return RELIEF_OK;
    k = rects_shape(p, rects, count);
    if (!p->can_select || total < p->select_from) {
        st = launch(p, &k, level, radius, max_holes, g, rects, 7 * (size_t)count, count, total,
                    ssd, wsum, n, err);
        return st == RELIEF_OK ? runs_whole(p, rects, count, runs, n_runs, err) : st;
    }
    if ((st = select_room(p, rects, count, err)) != RELIEF_OK)
        return st;
    blocks = (size_t)p->bstart_host[count];
    /* The scores stay on the device; their blocks' minima come back. */
    st = launch(p, &k, level, radius, max_holes, g, rects, 7 * (size_t)count, count, total,
                NULL, NULL, NULL, err);
    if (st != RELIEF_OK)
        return st;
    rc = block_minima(p, g != NULL, count, blocks);
    if (rc != CL_SUCCESS)
        return launch_failed(p, rc, "ranking a batch of windows on the device", err);
    for (int q = 0; q < count; ++q)
        nsel = choose_blocks(p, rects + 7 * q, q, keep[q], (size_t)p->bstart_host[q],
                             (size_t)p->bstart_host[q + 1], nsel);
    if (nsel * PM_BLOCK >= total / 2) { /* most of it: one read is cheaper */
        const cl_mem from[3] = {p->ssd, p->wsum, p->n};
        rc = read_scores(p, from, total, ssd, wsum, n);
        if (rc != CL_SUCCESS)
            return launch_failed(p, rc, "reading a batch of windows' scores", err);
        return runs_whole(p, rects, count, runs, n_runs, err);
    }
    st = grow_mem(p, &p->sel, &p->sel_cap, 2 * nsel, sizeof(int), err);
    if (st == RELIEF_OK)
        st = grow_out(p, nsel * PM_BLOCK, err);
    if (st != RELIEF_OK)
        return st;
    if (nsel && (rc = gather(p, nsel, ssd, wsum, n)) != CL_SUCCESS)
        return launch_failed(p, rc, "gathering a batch's best windows on the device", err);
    *runs = p->runs;
    *n_runs = nsel;
    return RELIEF_OK;
}

void relief_patch_opencl_select_from(relief_patch_scorer *s, size_t scores)
{
    if (s && s->backend == RELIEF_BACKEND_OPENCL)
        ((patch_cl *)s->ctx)->select_from = scores;
}

/* One query's rectangle: a batch of one. */
static relief_status patch_cl_score_rect(void *ctx, int level, int qx, int qy, int radius,
                                         int max_holes, const float *g, int x0, int y0, int nx,
                                         int ny, float *ssd, float *wsum, int *n,
                                         relief_error *err)
{
    const int rect[7] = {qx, qy, x0, y0, nx, ny, 0};
    return patch_cl_score_rects(ctx, level, radius, max_holes, g, rect, 1,
                                (size_t)nx * (size_t)ny, ssd, wsum, n, err);
}

/* One query's list of centres: pairs that share the query. */
static relief_status patch_cl_score_list(void *ctx, int level, int qx, int qy, int radius,
                                         int max_holes, const float *g, const int *xy,
                                         int count, float *ssd, float *wsum, int *n,
                                         relief_error *err)
{
    int *pairs;
    relief_status st;
    if (count <= 0)
        return RELIEF_OK;
    pairs = malloc(4 * (size_t)count * sizeof *pairs);
    if (!pairs)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate %d window centres", count);
    for (int i = 0; i < count; ++i) {
        pairs[4 * i] = qx, pairs[4 * i + 1] = qy;
        pairs[4 * i + 2] = xy[2 * i], pairs[4 * i + 3] = xy[2 * i + 1];
    }
    st = patch_cl_score_pairs(ctx, level, radius, max_holes, g, pairs, count, ssd, wsum, n,
                              err);
    free(pairs);
    return st;
}

static void patch_cl_destroy(void *ctx) { patch_cl_free(ctx, 1); }

static const relief_patch_ops patch_cl_ops = {patch_cl_bind, patch_cl_update,
                                              patch_cl_score_rect, patch_cl_score_list,
                                              patch_cl_destroy, patch_cl_score_rects,
                                              patch_cl_score_pairs, patch_cl_select_rects};

relief_status relief_patch_opencl_create(int device, relief_patch_scorer **out,
                                         relief_error *err)
{
    relief_device_info info;
    cl_device_id dev;
    cl_int rc;
    relief_patch_scorer *s = NULL;
    patch_cl *p = NULL;
    const char *src[2] = {relief_kernel_patch_math_h, relief_kernel_patch_cl};
    relief_status st = relief_cl_device(device, &dev, &info, err);

    if (st != RELIEF_OK)
        return st;
    s = calloc(1, sizeof *s);
    p = calloc(1, sizeof *p);
    if (!s || !p) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the OpenCL scorer");
        goto fail;
    }
    st = relief_cl_profile_open("image and depth scorer", info.name, &p->prof, err);
    if (st != RELIEF_OK)
        goto fail;
    p->ctx = clCreateContext(NULL, 1, &dev, NULL, NULL, &rc);
    if (rc == CL_SUCCESS)
        p->queue = clCreateCommandQueue(p->ctx, dev, relief_cl_profile_queue_flags(p->prof),
                                        &rc);
    if (rc != CL_SUCCESS) {
        st = relief_fail(err, RELIEF_E_DEVICE, "starting OpenCL on %s: %s", info.name,
                         relief_cl_error_name(rc));
        goto fail;
    }
    st = relief_cl_build(p->ctx, dev, src, 2, "-cl-std=CL1.2", "", &p->prog, err);
    if (st != RELIEF_OK)
        goto fail;
    /* The weights' buffer exists from the start: unweighted launches pass
     * it unread. */
    p->g = clCreateBuffer(p->ctx, CL_MEM_READ_ONLY, G_MAX * sizeof(float), NULL, &rc);
    if (rc != CL_SUCCESS) {
        st = relief_fail(err, RELIEF_E_DEVICE, "cannot allocate the window weights on the "
                         "device: %s", relief_cl_error_name(rc));
        goto fail;
    }
    {
        static const char *names[4] = {"patch_score_rects", "patch_score_pairs",
                                       "patch_block_min", "patch_gather"};
        cl_kernel *kernels[4] = {&p->rects_kernel, &p->pairs_kernel, &p->bmin_kernel,
                                 &p->gather_kernel};
        size_t wg = 0;
        for (int k = 0; k < 4; ++k) {
            *kernels[k] = clCreateKernel(p->prog, names[k], &rc);
            if (rc != CL_SUCCESS) {
                st = relief_fail(err, RELIEF_E_DEVICE, "clCreateKernel(%s): %s", names[k],
                                 relief_cl_error_name(rc));
                goto fail;
            }
        }
        /* The block minima and the gathering take PM_BLOCK work-items a
         * group; a device that cannot run that many reads every score
         * back. */
        p->can_select = 1;
        for (int k = 2; k < 4; ++k) {
            rc = clGetKernelWorkGroupInfo(*kernels[k], dev, CL_KERNEL_WORK_GROUP_SIZE,
                                          sizeof wg, &wg, NULL);
            p->can_select &= rc == CL_SUCCESS && wg >= PM_BLOCK;
        }
        p->select_from = RELIEF_PATCH_SELECT_FROM;
    }
    s->ops = &patch_cl_ops;
    s->ctx = p;
    s->backend = RELIEF_BACKEND_OPENCL;
    s->threads = 1;
    snprintf(s->device, sizeof s->device, "%.96s (%s, %u compute units) on %.96s", info.name,
             info.type, info.compute_units, info.platform);
    *out = s;
    return RELIEF_OK;
fail:
    patch_cl_free(p, 0);
    free(s);
    return st;
}

#else /* !RELIEF_HAVE_OPENCL */

relief_status relief_patch_opencl_create(int device, relief_patch_scorer **out,
                                         relief_error *err)
{
    (void)device;
    (void)out;
    return relief_fail(err, RELIEF_E_NOT_BUILT,
                       "relief was built without OpenCL (RELIEF_WITH_OPENCL=OFF)");
}

#endif
