/* The patch voting's OpenCL device (vote_cl.h). */
#include "image/vote_cl.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"

#ifdef RELIEF_HAVE_OPENCL
#include "device/ocl.h"

extern const char relief_kernel_vote_math_h[];
extern const char relief_kernel_vote_cl[];

/* Work-items a group: rows of 64 targets, or 16 x 4 pixels of the box. */
#define WG_1D 64
#define WG_X 16
#define WG_Y 4

struct relief_vote_cl {
    cl_context ctx;
    cl_command_queue queue;
    cl_program prog;
    cl_kernel k_dist, k_pm, k_vote;
    char name[256];
    vm_level L;
    size_t nt;
    cl_mem v, hole, tmap, tgt, nnf, nnf2, dist, dist2, cnt, wt;
};

static relief_status cl_fail(relief_error *err, const char *what, cl_int rc)
{
    return relief_fail(err, rc == CL_MEM_OBJECT_ALLOCATION_FAILURE ||
                                    rc == CL_OUT_OF_RESOURCES || rc == CL_OUT_OF_HOST_MEMORY
                                ? RELIEF_E_NOMEM
                                : RELIEF_E_DEVICE,
                       "the patch voting on the device: %s: %s", what,
                       relief_cl_error_name(rc));
}

static void release_level(relief_vote_cl *d)
{
    cl_mem *m[] = {&d->v, &d->hole, &d->tmap, &d->tgt, &d->nnf, &d->nnf2, &d->dist, &d->dist2, &d->cnt, &d->wt};
    for (size_t i = 0; i < sizeof m / sizeof m[0]; ++i) {
        if (*m[i])
            clReleaseMemObject(*m[i]);
        *m[i] = NULL;
    }
}

void relief_vote_cl_destroy(relief_vote_cl *d)
{
    if (!d)
        return;
    release_level(d);
    if (d->k_dist)
        clReleaseKernel(d->k_dist);
    if (d->k_pm)
        clReleaseKernel(d->k_pm);
    if (d->k_vote)
        clReleaseKernel(d->k_vote);
    if (d->prog)
        clReleaseProgram(d->prog);
    if (d->queue)
        clReleaseCommandQueue(d->queue);
    if (d->ctx)
        clReleaseContext(d->ctx);
    free(d);
}

const char *relief_vote_cl_name(const relief_vote_cl *d)
{
    return d->name;
}

relief_status relief_vote_cl_create(int device, relief_vote_cl **out, relief_error *err)
{
    relief_device_info info;
    cl_device_id dev;
    cl_int rc;
    const char *src[2] = {relief_kernel_vote_math_h, relief_kernel_vote_cl};
    relief_vote_cl *d;
    relief_status st = relief_cl_device(device, &dev, &info, err);
    *out = NULL;
    if (st != RELIEF_OK)
        return st;
    d = calloc(1, sizeof *d);
    if (!d)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the patch voting's device");
    snprintf(d->name, sizeof d->name, "%s", info.name);
    d->ctx = clCreateContext(NULL, 1, &dev, NULL, NULL, &rc);
    if (rc == CL_SUCCESS)
        d->queue = clCreateCommandQueue(d->ctx, dev, 0, &rc);
    if (rc != CL_SUCCESS) {
        st = cl_fail(err, "starting OpenCL", rc);
        goto fail;
    }
    st = relief_cl_build(d->ctx, dev, src, 2, "-cl-std=CL1.2", "", &d->prog, err);
    if (st != RELIEF_OK)
        goto fail;
    d->k_dist = clCreateKernel(d->prog, "vote_dist", &rc);
    if (rc == CL_SUCCESS)
        d->k_pm = clCreateKernel(d->prog, "vote_pm", &rc);
    if (rc == CL_SUCCESS)
        d->k_vote = clCreateKernel(d->prog, "vote_vote", &rc);
    if (rc != CL_SUCCESS) {
        st = cl_fail(err, "clCreateKernel", rc);
        goto fail;
    }
    *out = d;
    return RELIEF_OK;
fail:
    relief_vote_cl_destroy(d);
    return st;
}

/* A buffer of n bytes, copied from src when not NULL. */
static relief_status buffer(relief_vote_cl *d, cl_mem *m, size_t n, const void *src,
                            relief_error *err)
{
    cl_int rc;
    *m = clCreateBuffer(d->ctx, CL_MEM_READ_WRITE | (src ? CL_MEM_COPY_HOST_PTR : 0),
                        n ? n : 1, (void *)src, &rc);
    return rc == CL_SUCCESS ? RELIEF_OK : cl_fail(err, "clCreateBuffer", rc);
}

relief_status relief_vote_cl_level(relief_vote_cl *d, const vm_level *L, const uint16_t *v,
                                   const uint8_t *hole, const int32_t *tmap,
                                   const uint32_t *tgt, size_t nt, const uint32_t *nnf,
                                   relief_error *err)
{
    const size_t px = (size_t)L->w * (size_t)L->h;
    relief_status st;
    release_level(d);
    d->L = *L;
    d->nt = nt;
    st = buffer(d, &d->v, px * (size_t)L->C * sizeof *v, v, err);
    if (st == RELIEF_OK)
        st = buffer(d, &d->hole, px, hole, err);
    if (st == RELIEF_OK)
        st = buffer(d, &d->tmap, (size_t)L->bw * (size_t)L->bh * sizeof *tmap, tmap, err);
    if (st == RELIEF_OK)
        st = buffer(d, &d->tgt, nt * sizeof *tgt, tgt, err);
    if (st == RELIEF_OK)
        st = buffer(d, &d->nnf, nt * sizeof *nnf, nnf, err);
    if (st == RELIEF_OK)
        st = buffer(d, &d->nnf2, nt * sizeof *nnf, NULL, err);
    if (st == RELIEF_OK)
        st = buffer(d, &d->dist, nt * sizeof(uint64_t), NULL, err);
    if (st == RELIEF_OK)
        st = buffer(d, &d->dist2, nt * sizeof(uint64_t), NULL, err);
    if (st == RELIEF_OK)
        st = buffer(d, &d->wt, nt * sizeof(uint32_t), NULL, err);
    if (st == RELIEF_OK) {
        const cl_uint zero = 0;
        cl_int rc;
        st = buffer(d, &d->cnt, nt * sizeof(cl_uint), NULL, err);
        rc = st == RELIEF_OK && nt ? clEnqueueFillBuffer(d->queue, d->cnt, &zero, sizeof zero, 0,
                                                         nt * sizeof zero, 0, NULL, NULL)
                                   : CL_SUCCESS;
        if (st == RELIEF_OK && rc != CL_SUCCESS)
            st = cl_fail(err, "clEnqueueFillBuffer", rc);
    }
    return st;
}

/* The level's geometry as the kernels' last eight arguments, from `at`. */
static cl_int set_level(cl_kernel k, cl_uint at, const vm_level *L)
{
    const int g[8] = {L->w, L->h, L->C, L->r, L->bx, L->by, L->bw, L->bh};
    cl_int rc = CL_SUCCESS;
    for (cl_uint i = 0; i < 8 && rc == CL_SUCCESS; ++i)
        rc = clSetKernelArg(k, at + i, sizeof(int), &g[i]);
    return rc;
}

static cl_int set_mems(cl_kernel k, cl_uint n, cl_mem *const *m)
{
    cl_int rc = CL_SUCCESS;
    for (cl_uint i = 0; i < n && rc == CL_SUCCESS; ++i)
        rc = clSetKernelArg(k, i, sizeof(cl_mem), m[i]);
    return rc;
}

static cl_int run_1d(relief_vote_cl *d, cl_kernel k)
{
    const size_t local = WG_1D, global = (d->nt + WG_1D - 1) / WG_1D * WG_1D;
    return d->nt ? clEnqueueNDRangeKernel(d->queue, k, 1, NULL, &global, &local, 0, NULL, NULL)
                 : CL_SUCCESS;
}

relief_status relief_vote_cl_dist(relief_vote_cl *d, relief_error *err)
{
    cl_mem *m[4] = {&d->v, &d->tgt, &d->nnf, &d->dist};
    const int nt = (int)d->nt;
    cl_int rc = set_mems(d->k_dist, 4, m);
    if (rc == CL_SUCCESS)
        rc = clSetKernelArg(d->k_dist, 4, sizeof nt, &nt);
    if (rc == CL_SUCCESS)
        rc = set_level(d->k_dist, 5, &d->L);
    if (rc == CL_SUCCESS)
        rc = run_1d(d, d->k_dist);
    return rc == CL_SUCCESS ? RELIEF_OK : cl_fail(err, "vote_dist", rc);
}

relief_status relief_vote_cl_pm(relief_vote_cl *d, uint32_t seed, int level, int step,
                                int jump, relief_error *err)
{
    cl_mem *m[8] = {&d->v, &d->tmap, &d->tgt, &d->nnf, &d->dist, &d->nnf2, &d->dist2, &d->cnt};
    const int nt = (int)d->nt;
    const cl_uint s = seed;
    cl_int rc = set_mems(d->k_pm, 8, m);
    if (rc == CL_SUCCESS)
        rc = clSetKernelArg(d->k_pm, 8, sizeof nt, &nt);
    if (rc == CL_SUCCESS)
        rc = clSetKernelArg(d->k_pm, 9, sizeof s, &s);
    if (rc == CL_SUCCESS)
        rc = clSetKernelArg(d->k_pm, 10, sizeof level, &level);
    if (rc == CL_SUCCESS)
        rc = clSetKernelArg(d->k_pm, 11, sizeof step, &step);
    if (rc == CL_SUCCESS)
        rc = clSetKernelArg(d->k_pm, 12, sizeof jump, &jump);
    if (rc == CL_SUCCESS)
        rc = set_level(d->k_pm, 13, &d->L);
    if (rc == CL_SUCCESS)
        rc = run_1d(d, d->k_pm);
    if (rc == CL_SUCCESS) { /* the step's field is the next one's to read */
        cl_mem t = d->nnf;
        d->nnf = d->nnf2, d->nnf2 = t;
        t = d->dist, d->dist = d->dist2, d->dist2 = t;
    }
    return rc == CL_SUCCESS ? RELIEF_OK : cl_fail(err, "vote_pm", rc);
}

relief_status relief_vote_cl_read_dist(relief_vote_cl *d, uint64_t *dist, relief_error *err)
{
    cl_int rc = d->nt ? clEnqueueReadBuffer(d->queue, d->dist, CL_TRUE, 0,
                                            d->nt * sizeof *dist, dist, 0, NULL, NULL)
                      : CL_SUCCESS;
    return rc == CL_SUCCESS ? RELIEF_OK : cl_fail(err, "reading the distances", rc);
}

relief_status relief_vote_cl_vote(relief_vote_cl *d, const uint32_t *wt, int best,
                                  relief_error *err)
{
    cl_mem *m[6] = {&d->v, &d->hole, &d->tmap, &d->nnf, &d->dist, &d->wt};
    const size_t local[2] = {WG_X, WG_Y};
    const size_t global[2] = {((size_t)d->L.bw + WG_X - 1) / WG_X * WG_X,
                              ((size_t)d->L.bh + WG_Y - 1) / WG_Y * WG_Y};
    cl_int rc = d->nt ? clEnqueueWriteBuffer(d->queue, d->wt, CL_FALSE, 0, d->nt * sizeof *wt,
                                             wt, 0, NULL, NULL)
                      : CL_SUCCESS;
    if (rc == CL_SUCCESS)
        rc = set_mems(d->k_vote, 6, m);
    if (rc == CL_SUCCESS)
        rc = clSetKernelArg(d->k_vote, 6, sizeof best, &best);
    if (rc == CL_SUCCESS)
        rc = set_level(d->k_vote, 7, &d->L);
    if (rc == CL_SUCCESS)
        rc = clEnqueueNDRangeKernel(d->queue, d->k_vote, 2, NULL, global, local, 0, NULL, NULL);
    /* wt is the caller's: its write must be done before the call returns */
    if (rc == CL_SUCCESS)
        rc = clFinish(d->queue);
    return rc == CL_SUCCESS ? RELIEF_OK : cl_fail(err, "vote_vote", rc);
}

relief_status relief_vote_cl_read(relief_vote_cl *d, uint32_t *nnf, uint16_t *v,
                                  uint64_t *distances, relief_error *err)
{
    uint32_t *cnt = malloc((d->nt ? d->nt : 1) * sizeof *cnt);
    cl_int rc;
    if (!cnt)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the device's counts");
    rc = d->nt ? clEnqueueReadBuffer(d->queue, d->nnf, CL_TRUE, 0, d->nt * sizeof *nnf, nnf, 0,
                                     NULL, NULL)
               : CL_SUCCESS;
    if (rc == CL_SUCCESS && d->nt)
        rc = clEnqueueReadBuffer(d->queue, d->cnt, CL_TRUE, 0, d->nt * sizeof *cnt, cnt, 0, NULL,
                                 NULL);
    if (rc == CL_SUCCESS && v)
        rc = clEnqueueReadBuffer(d->queue, d->v, CL_TRUE, 0,
                                 (size_t)d->L.w * d->L.h * d->L.C * sizeof *v, v, 0, NULL, NULL);
    for (size_t i = 0; rc == CL_SUCCESS && i < d->nt; ++i)
        *distances += cnt[i];
    free(cnt);
    return rc == CL_SUCCESS ? RELIEF_OK : cl_fail(err, "reading the field", rc);
}

#else

relief_status relief_vote_cl_create(int device, relief_vote_cl **out, relief_error *err)
{
    (void)device;
    *out = NULL;
    return relief_fail(err, RELIEF_E_NOT_BUILT,
                       "relief was built without OpenCL (RELIEF_WITH_OPENCL=OFF)");
}

void relief_vote_cl_destroy(relief_vote_cl *d)
{
    (void)d;
}

const char *relief_vote_cl_name(const relief_vote_cl *d)
{
    (void)d;
    return "";
}

#define NOT_BUILT return relief_fail(err, RELIEF_E_NOT_BUILT, "relief was built without OpenCL")
relief_status relief_vote_cl_level(relief_vote_cl *d, const vm_level *L, const uint16_t *v,
                                   const uint8_t *hole, const int32_t *tmap,
                                   const uint32_t *tgt, size_t nt, const uint32_t *nnf,
                                   relief_error *err)
{
    (void)d, (void)L, (void)v, (void)hole, (void)tmap, (void)tgt, (void)nt, (void)nnf;
    NOT_BUILT;
}
relief_status relief_vote_cl_dist(relief_vote_cl *d, relief_error *err)
{
    (void)d;
    NOT_BUILT;
}
relief_status relief_vote_cl_pm(relief_vote_cl *d, uint32_t seed, int level, int step,
                                int jump, relief_error *err)
{
    (void)d, (void)seed, (void)level, (void)step, (void)jump;
    NOT_BUILT;
}
relief_status relief_vote_cl_read_dist(relief_vote_cl *d, uint64_t *dist, relief_error *err)
{
    (void)d, (void)dist;
    NOT_BUILT;
}
relief_status relief_vote_cl_vote(relief_vote_cl *d, const uint32_t *wt, int best,
                                  relief_error *err)
{
    (void)d, (void)wt, (void)best;
    NOT_BUILT;
}
relief_status relief_vote_cl_read(relief_vote_cl *d, uint32_t *nnf, uint16_t *v,
                                  uint64_t *distances, relief_error *err)
{
    (void)d, (void)nnf, (void)v, (void)distances;
    NOT_BUILT;
}

#endif
