/* The OpenCL scorer of the image hole filler: kernels/patch.cl, which runs
 * kernels/patch_math.h's pm_score, the scalar twin's arithmetic. The
 * pyramid's levels go to the device once; after each paste only the rows
 * it changed travel, and per query only the scores come back. */
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
    cl_kernel kernel, list_kernel;
    const relief_patch_level *levels;
    int n_levels;
    cl_mem v[MAX_LEVELS], known[MAX_LEVELS];
    cl_mem ssd, wsum, n; /* the scores of the last rectangle or list */
    size_t cap;          /* candidates they hold */
    cl_mem g;            /* the weights of the last weighted call (G_MAX floats) */
    float g_host[G_MAX]; /* what g holds, so that it travels only when it changes */
    int g_len;           /* entries of g_host in use; 0 none yet */
    cl_mem xy;     /* the last list's centres */
    size_t xy_cap; /* centres xy holds */
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
    if (p->xy)
        clReleaseMemObject(p->xy);
    if (p->kernel)
        clReleaseKernel(p->kernel);
    if (p->list_kernel)
        clReleaseKernel(p->list_kernel);
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
    for (int l = 0; l < n_levels && st == RELIEF_OK; ++l) {
        size_t px = (size_t)levels[l].width * levels[l].height;
        st = buffer(p, &p->v[l], levels[l].v, px * levels[l].channels * sizeof(float),
                    "an image level", err);
        if (st == RELIEF_OK)
            st = buffer(p, &p->known[l], levels[l].known, px, "a level's known pixels", err);
    }
    return st;
}

static relief_status patch_cl_update(void *ctx, int level, int y0, int y1, relief_error *err)
{
    patch_cl *p = ctx;
    const relief_patch_level *l = &p->levels[level];
    size_t row = (size_t)l->width, first = (size_t)y0 * row, count = (size_t)(y1 - y0 + 1) * row;
    cl_int rc = clEnqueueWriteBuffer(p->queue, p->v[level], CL_TRUE,
                                     first * l->channels * sizeof(float),
                                     count * l->channels * sizeof(float),
                                     l->v + first * l->channels, 0, NULL, NULL);
    if (rc == CL_SUCCESS)
        rc = clEnqueueWriteBuffer(p->queue, p->known[level], CL_TRUE, first, count,
                                  l->known + first, 0, NULL, NULL);
    if (rc != CL_SUCCESS)
        return relief_fail(err, RELIEF_E_DEVICE, "updating an image level on the device: %s",
                           relief_cl_error_name(rc));
    return RELIEF_OK;
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

static relief_status patch_cl_score_rect(void *ctx, int level, int qx, int qy, int radius,
                                         int max_holes, const float *g, int x0, int y0, int nx,
                                         int ny, float *ssd, float *wsum, int *n,
                                         relief_error *err)
{
    patch_cl *p = ctx;
    const relief_patch_level *l = &p->levels[level];
    size_t count = (size_t)nx * ny, local[2] = {WG_X, WG_Y};
    size_t global[2] = {((size_t)nx + WG_X - 1) / WG_X * WG_X,
                        ((size_t)ny + WG_Y - 1) / WG_Y * WG_Y};
    cl_int rc;
    int a = 0, weighted = g != NULL;
    relief_status st;

    st = grow_scores(p, count, err);
    if (st != RELIEF_OK)
        return st;
    rc = put_weights(p, g, radius);
#define ARG(x) (rc |= clSetKernelArg(p->kernel, a++, sizeof(x), &(x)))
    ARG(p->v[level]);
    ARG(p->known[level]);
    ARG(l->width);
    ARG(l->height);
    ARG(l->channels);
    ARG(qx);
    ARG(qy);
    ARG(radius);
    ARG(max_holes);
    ARG(p->g);
    ARG(weighted);
    ARG(x0);
    ARG(y0);
    ARG(nx);
    ARG(ny);
    ARG(p->ssd);
    ARG(p->wsum);
    ARG(p->n);
#undef ARG
    if (rc == CL_SUCCESS)
        rc = clEnqueueNDRangeKernel(p->queue, p->kernel, 2, NULL, global, local, 0, NULL,
                                    NULL);
    if (rc == CL_SUCCESS)
        rc = read_scores(p, count, ssd, wsum, n);
    if (rc != CL_SUCCESS)
        return relief_fail(err, RELIEF_E_DEVICE, "scoring windows on the device: %s",
                           relief_cl_error_name(rc));
    return RELIEF_OK;
}

static relief_status patch_cl_score_list(void *ctx, int level, int qx, int qy, int radius,
                                         int max_holes, const float *g, const int *xy,
                                         int count, float *ssd, float *wsum, int *n,
                                         relief_error *err)
{
    patch_cl *p = ctx;
    const relief_patch_level *l = &p->levels[level];
    size_t local = WG_X * WG_Y, global = ((size_t)count + local - 1) / local * local;
    cl_int rc = CL_SUCCESS;
    int a = 0, weighted = g != NULL;
    relief_status st;

    if (count <= 0)
        return RELIEF_OK;
    st = grow_scores(p, (size_t)count, err);
    if (st == RELIEF_OK && (size_t)count > p->xy_cap) {
        if (p->xy)
            clReleaseMemObject(p->xy);
        p->xy = NULL;
        p->xy_cap = 0;
        st = buffer(p, &p->xy, NULL, 2 * (size_t)count * sizeof(int), "window centres", err);
        if (st == RELIEF_OK)
            p->xy_cap = (size_t)count;
    }
    if (st != RELIEF_OK)
        return st;
    rc = clEnqueueWriteBuffer(p->queue, p->xy, CL_TRUE, 0, 2 * (size_t)count * sizeof(int), xy,
                              0, NULL, NULL);
    if (rc == CL_SUCCESS)
        rc = put_weights(p, g, radius);
#define ARG(x) (rc |= clSetKernelArg(p->list_kernel, a++, sizeof(x), &(x)))
    ARG(p->v[level]);
    ARG(p->known[level]);
    ARG(l->width);
    ARG(l->height);
    ARG(l->channels);
    ARG(qx);
    ARG(qy);
    ARG(radius);
    ARG(max_holes);
    ARG(p->g);
    ARG(weighted);
    ARG(p->xy);
    ARG(count);
    ARG(p->ssd);
    ARG(p->wsum);
    ARG(p->n);
#undef ARG
    if (rc == CL_SUCCESS)
        rc = clEnqueueNDRangeKernel(p->queue, p->list_kernel, 1, NULL, &global, &local, 0, NULL,
                                    NULL);
    if (rc == CL_SUCCESS)
        rc = read_scores(p, (size_t)count, ssd, wsum, n);
    if (rc != CL_SUCCESS)
        return relief_fail(err, RELIEF_E_DEVICE, "scoring a list of windows on the device: %s",
                           relief_cl_error_name(rc));
    return RELIEF_OK;
}

static void patch_cl_destroy(void *ctx) { patch_cl_free(ctx); }

static const relief_patch_ops patch_cl_ops = {patch_cl_bind, patch_cl_update,
                                              patch_cl_score_rect, patch_cl_score_list,
                                              patch_cl_destroy};

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
    p->kernel = clCreateKernel(p->prog, "patch_score", &rc);
    if (rc == CL_SUCCESS)
        p->list_kernel = clCreateKernel(p->prog, "patch_score_list", &rc);
    if (rc != CL_SUCCESS) {
        st = relief_fail(err, RELIEF_E_DEVICE, "clCreateKernel(patch_score%s): %s",
                         p->kernel ? "_list" : "", relief_cl_error_name(rc));
        goto fail;
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
