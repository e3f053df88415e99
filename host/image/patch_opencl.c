/* The OpenCL scorer of the image hole filler: kernels/patch.cl, which runs
 * kernels/patch_math.h's pm_score, the scalar twin's arithmetic. The
 * pyramid's levels go to the device once; the rows pastes changed travel
 * before the next launch, and only the scores come back. A single query
 * is a batch of one (patch_score_rects, patch_score_pairs). */
#include "image/patch.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"

#ifdef RELIEF_HAVE_OPENCL
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

typedef struct patch_cl {
    cl_context ctx;
    cl_command_queue queue;
    cl_program prog;
    cl_kernel rects_kernel, pairs_kernel;
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
    int dirty_lo[MAX_LEVELS], dirty_hi[MAX_LEVELS]; /* rows changed on the host and not
                                                       yet on the device (lo > hi: none) */
} patch_cl;

static void patch_cl_free(patch_cl *p)
{
    if (!p)
        return;
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
        rc = clEnqueueWriteBuffer(p->queue, p->v[level], CL_FALSE,
                                  first * l->channels * sizeof(float),
                                  count * l->channels * sizeof(float),
                                  l->v + first * l->channels, 0, NULL, NULL);
        if (rc == CL_SUCCESS)
            rc = clEnqueueWriteBuffer(p->queue, p->known[level], CL_FALSE, first, count,
                                      l->known + first, 0, NULL, NULL);
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
                              NULL);
    if (rc == CL_SUCCESS) {
        memcpy(p->g_host, g, (size_t)len * sizeof *g);
        p->g_len = len;
    }
    return rc;
}

/* Read `count` scores back (blocking: the queue is in order); wsum may
 * be NULL. */
static cl_int read_scores(patch_cl *p, size_t count, float *ssd, float *wsum, int *n)
{
    cl_int rc = clEnqueueReadBuffer(p->queue, p->ssd, CL_FALSE, 0, count * sizeof(float), ssd,
                                    0, NULL, NULL);
    if (rc == CL_SUCCESS && wsum)
        rc = clEnqueueReadBuffer(p->queue, p->wsum, CL_FALSE, 0, count * sizeof(float), wsum, 0,
                                 NULL, NULL);
    if (rc == CL_SUCCESS)
        rc = clEnqueueReadBuffer(p->queue, p->n, CL_TRUE, 0, count * sizeof(int), n, 0, NULL,
                                 NULL);
    return rc;
}

/* `ints` ints onto the device's batch buffer (grown as needed). */
static relief_status put_batch(patch_cl *p, const int *data, size_t ints, relief_error *err)
{
    cl_int rc;
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
    /* Blocking: the caller's array may go as soon as this call fails. */
    rc = clEnqueueWriteBuffer(p->queue, p->batch, CL_TRUE, 0, ints * sizeof(int), data, 0,
                              NULL, NULL);
    if (rc != CL_SUCCESS)
        return relief_fail(err, RELIEF_E_DEVICE, "sending a batch of windows to the device: %s",
                           relief_cl_error_name(rc));
    return RELIEF_OK;
}

/* A launch that failed on the way: what was queued (the levels' rows read
 * from the host) is waited for before the caller may free anything. */
static relief_status launch_failed(patch_cl *p, cl_int rc, const char *what,
                                   relief_error *err)
{
    clFinish(p->queue);
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
 * set, the kernel run and `scores` scores read back. */
typedef struct launch_shape {
    cl_kernel kernel;
    cl_uint dims;
    size_t global[3], local[3];
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
                                    NULL, NULL);
    if (rc == CL_SUCCESS)
        rc = read_scores(p, scores, ssd, wsum, n);
    if (rc != CL_SUCCESS)
        return launch_failed(p, rc, k->what, err);
    return RELIEF_OK;
}

static relief_status patch_cl_score_rects(void *ctx, int level, int radius, int max_holes,
                                          const float *g, const int *rects, int count,
                                          size_t total, float *ssd, float *wsum, int *n,
                                          relief_error *err)
{
    patch_cl *p = ctx;
    launch_shape k = {p->rects_kernel, 3, {0, 0, (size_t)count}, {WG_X, WG_Y, 1},
                      "scoring a batch of windows on the device"};
    if (count <= 0)
        return RELIEF_OK;
    for (int q = 0; q < count; ++q) {
        size_t nx = ((size_t)rects[7 * q + 4] + WG_X - 1) / WG_X * WG_X;
        size_t ny = ((size_t)rects[7 * q + 5] + WG_Y - 1) / WG_Y * WG_Y;
        k.global[0] = nx > k.global[0] ? nx : k.global[0];
        k.global[1] = ny > k.global[1] ? ny : k.global[1];
    }
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
                      {local, 1, 1}, "scoring a batch of refinements on the device"};
    if (count <= 0)
        return RELIEF_OK;
    return launch(p, &k, level, radius, max_holes, g, pairs, 4 * (size_t)count, count,
                  (size_t)count, ssd, wsum, n, err);
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

static void patch_cl_destroy(void *ctx) { patch_cl_free(ctx); }

static const relief_patch_ops patch_cl_ops = {patch_cl_bind, patch_cl_update,
                                              patch_cl_score_rect, patch_cl_score_list,
                                              patch_cl_destroy, patch_cl_score_rects,
                                              patch_cl_score_pairs};

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
    p->ctx = clCreateContext(NULL, 1, &dev, NULL, NULL, &rc);
    if (rc == CL_SUCCESS)
        p->queue = clCreateCommandQueue(p->ctx, dev, 0, &rc);
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
        static const char *names[2] = {"patch_score_rects", "patch_score_pairs"};
        cl_kernel *kernels[2] = {&p->rects_kernel, &p->pairs_kernel};
        for (int k = 0; k < 2; ++k) {
            *kernels[k] = clCreateKernel(p->prog, names[k], &rc);
            if (rc != CL_SUCCESS) {
                st = relief_fail(err, RELIEF_E_DEVICE, "clCreateKernel(%s): %s", names[k],
                                 relief_cl_error_name(rc));
                goto fail;
            }
        }
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
    patch_cl_free(p);
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
