/* Nearest exemplar grids: FLANN's kd-tree, or brute force on the host or
 * an OpenCL device (grid_nn.h). */
#include "points/grid_nn.h"

#include <flann/flann.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/knn.h"
#include "base/parallel.h"
#include "device/device.h"
#include "kernels/grid_math.h"

#define GN_MAX_K 8
#define GN_CHUNK 64 /* queries per OpenCL launch: 64 x nz distances come back */

#ifdef RELIEF_HAVE_OPENCL
#include "device/cl_profile.h"
#include "device/ocl.h"
extern const char relief_kernel_grid_math_h[];
extern const char relief_kernel_grid_cl[];
#endif

struct relief_grid_nn {
    relief_grid_search search;
    relief_backend backend; /* brute: scalar or opencl */
    const float *z;
    size_t nz;
    int dims, threads;
    flann_index_t index;
    char name[320];
#ifdef RELIEF_HAVE_OPENCL
    cl_context ctx;
    cl_command_queue queue;
    relief_cl_profile *prof; /* RELIEF_OPENCL_PROFILE's record; NULL: off */
    cl_program prog;
    cl_kernel kernel;
    cl_mem zt, q, out; /* exemplars transposed; a chunk's queries; its distances */
    float *dist;       /* GN_CHUNK x nz on the host */
#endif
};

/* The k smallest (distance, index) of d[0..nz-1], nearest first. */
static void top_k(const float *d, size_t nz, int k, uint32_t *idx)
{
    float bd[GN_MAX_K];
    int m = 0;
    for (size_t e = 0; e < nz; ++e) {
        int j;
        if (m == k && !(d[e] < bd[k - 1]))
            continue;
        j = m < k ? m++ : k - 1;
        for (; j > 0 && d[e] < bd[j - 1]; --j)
            bd[j] = bd[j - 1], idx[j] = idx[j - 1];
        bd[j] = d[e], idx[j] = (uint32_t)e;
    }
}

/* A batch's queries, shared out by relief_parallel_ranges. */
typedef struct job {
    relief_grid_nn *nn;
    const float *q;
    int k;
    uint32_t *idx;
} job;

static int kdtree_range(void *ctx, size_t lo, size_t hi)
{
    const job *j = ctx;
    const relief_grid_nn *nn = j->nn;
    struct FLANNParameters fp = relief_knn_exact_params();
    int id[GN_MAX_K];
    float dist[GN_MAX_K];
    for (size_t i = lo; i < hi; ++i) {
        if (flann_find_nearest_neighbors_index_float(nn->index,
                                                     (float *)j->q + i * (size_t)nn->dims, 1, id,
                                                     dist, j->k, &fp) != 0)
            return 1;
        for (int c = 0; c < j->k; ++c)
            j->idx[i * (size_t)j->k + (size_t)c] = id[c] < 0 ? UINT32_MAX : (uint32_t)id[c];
    }
    return 0;
}

static int brute_range(void *ctx, size_t lo, size_t hi)
{
    const job *j = ctx;
    const relief_grid_nn *nn = j->nn;
    float *d = malloc((nn->nz + 1) * sizeof *d);
    if (!d)
        return 1;
    for (size_t i = lo; i < hi; ++i) {
        const float *q = j->q + i * (size_t)nn->dims;
        for (size_t e = 0; e < nn->nz; ++e)
            d[e] = gm_dist(q, nn->z + e * (size_t)nn->dims, nn->dims, 1);
        top_k(d, nn->nz, j->k, j->idx + i * (size_t)j->k);
    }
    free(d);
    return 0;
}

#ifdef RELIEF_HAVE_OPENCL
static relief_status cl_start(relief_grid_nn *nn, cl_device_id dev,
                              const relief_device_info *info, relief_error *err)
{
    cl_int rc;
    const char *src[2] = {relief_kernel_grid_math_h, relief_kernel_grid_cl};
    size_t bytes = nn->nz * (size_t)nn->dims * sizeof(float);
    relief_status st;
    float *zt;
    st = relief_cl_profile_open("point grids' search", info->name, &nn->prof, err);
    if (st != RELIEF_OK)
        return st;
    nn->ctx = clCreateContext(NULL, 1, &dev, NULL, NULL, &rc);
    if (rc == CL_SUCCESS)
        nn->queue = clCreateCommandQueue(nn->ctx, dev, relief_cl_profile_queue_flags(nn->prof),
                                         &rc);
    if (rc != CL_SUCCESS)
        return relief_fail(err, RELIEF_E_DEVICE, "starting OpenCL on %s: %s", info->name,
                           relief_cl_error_name(rc));
    st = relief_cl_build(nn->ctx, dev, src, 2, "-cl-std=CL1.2", "", &nn->prog, err);
    if (st != RELIEF_OK)
        return st;
    nn->kernel = clCreateKernel(nn->prog, "grid_dist", &rc);
    if (rc != CL_SUCCESS)
        return relief_fail(err, RELIEF_E_DEVICE, "clCreateKernel(grid_dist): %s",
                           relief_cl_error_name(rc));
    zt = malloc(bytes + 1);
    nn->dist = malloc(GN_CHUNK * nn->nz * sizeof *nn->dist + 1);
    if (!zt || !nn->dist) {
        free(zt);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate %zu exemplar grids for the "
                           "device", nn->nz);
    }
    for (size_t e = 0; e < nn->nz; ++e)
        for (int d = 0; d < nn->dims; ++d)
            zt[(size_t)d * nn->nz + e] = nn->z[e * (size_t)nn->dims + (size_t)d];
    nn->zt = clCreateBuffer(nn->ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes, zt, &rc);
    free(zt);
    if (rc == CL_SUCCESS)
        nn->q = clCreateBuffer(nn->ctx, CL_MEM_READ_ONLY,
                               GN_CHUNK * (size_t)nn->dims * sizeof(float), NULL, &rc);
    if (rc == CL_SUCCESS)
        nn->out = clCreateBuffer(nn->ctx, CL_MEM_WRITE_ONLY, GN_CHUNK * nn->nz * sizeof(float),
                                 NULL, &rc);
    if (rc != CL_SUCCESS)
        return relief_fail(err, RELIEF_E_DEVICE, "cannot allocate %zu bytes of device memory "
                           "for the exemplar grids: %s", bytes, relief_cl_error_name(rc));
    snprintf(nn->name, sizeof nn->name, "brute force, OpenCL on %.96s (%s, %u compute units)",
             info->name, info->type, info->compute_units);
    return RELIEF_OK;
}

/* Release the device's side; `created`: cl_start had succeeded (the
 * profile is written). */
static void cl_stop(relief_grid_nn *nn, int created)
{
    relief_cl_profile_close(nn->prof, created);
    nn->prof = NULL;
    if (nn->zt)
        clReleaseMemObject(nn->zt);
    if (nn->q)
        clReleaseMemObject(nn->q);
    if (nn->out)
        clReleaseMemObject(nn->out);
    if (nn->kernel)
        clReleaseKernel(nn->kernel);
    if (nn->prog)
        clReleaseProgram(nn->prog);
    if (nn->queue)
        clReleaseCommandQueue(nn->queue);
    if (nn->ctx)
        clReleaseContext(nn->ctx);
    free(nn->dist);
    nn->zt = nn->q = nn->out = NULL, nn->kernel = NULL, nn->prog = NULL, nn->queue = NULL;
    nn->ctx = NULL, nn->dist = NULL;
}

static relief_status cl_query(relief_grid_nn *nn, const float *q, size_t nq, int k,
                              uint32_t *idx, relief_error *err)
{
    const int nz = (int)nn->nz, stride = (int)nn->nz;
    const size_t local = 64, global = (nn->nz + local - 1) / local * local;
    for (size_t c0 = 0; c0 < nq; c0 += GN_CHUNK) {
        const int nc = (int)(nq - c0 < GN_CHUNK ? nq - c0 : GN_CHUNK);
        int a = 0;
        const size_t qbytes = (size_t)nc * nn->dims * sizeof(float);
        const size_t dbytes = (size_t)nc * nn->nz * sizeof(float);
        cl_int rc = clEnqueueWriteBuffer(nn->queue, nn->q, CL_FALSE, 0, qbytes,
                                         q + c0 * (size_t)nn->dims, 0, NULL,
                                         relief_cl_profile_event(nn->prof, "write", qbytes));
#define ARG(x) (rc |= clSetKernelArg(nn->kernel, a++, sizeof(x), &(x)))
        ARG(nn->zt);
        ARG(nz);
        ARG(stride);
        ARG(nn->dims);
        ARG(nn->q);
        ARG(nc);
        ARG(nn->out);
#undef ARG
        if (rc == CL_SUCCESS)
            rc = clEnqueueNDRangeKernel(nn->queue, nn->kernel, 1, NULL, &global, &local, 0, NULL,
                                        relief_cl_profile_event(nn->prof, "grid_dist", 0));
        if (rc == CL_SUCCESS)
            rc = clEnqueueReadBuffer(nn->queue, nn->out, CL_TRUE, 0, dbytes, nn->dist, 0, NULL,
                                     relief_cl_profile_event(nn->prof, "read", dbytes));
        if (rc != CL_SUCCESS) {
            clFinish(nn->queue); /* the write may still read the caller's queries */
            return relief_fail(err, RELIEF_E_DEVICE, "grid distances on the device: %s",
                               relief_cl_error_name(rc));
        }
        for (int i = 0; i < nc; ++i)
            top_k(nn->dist + (size_t)i * nn->nz, nn->nz, k, idx + (c0 + (size_t)i) * (size_t)k);
    }
    return RELIEF_OK;
}
#endif

relief_status relief_grid_nn_create(relief_grid_search search, relief_backend backend,
                                    int device, const float *z, size_t nz, int dims, int threads,
                                    relief_grid_nn **out, char *note, size_t note_size,
                                    relief_reason *why, relief_error *err)
{
    relief_grid_nn *nn;
    (void)device; /* read only when built with OpenCL */
    *out = NULL;
    if (why)
        *why = RELIEF_REASON_NONE;
    if (!nz || dims < 1 || nz > INT32_MAX / (size_t)dims)
        return relief_fail(err, RELIEF_E_RANGE, "%zu exemplar grids of %d floats", nz, dims);
    nn = calloc(1, sizeof *nn);
    if (!nn)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the grid search");
    nn->search = search, nn->z = z, nn->nz = nz, nn->dims = dims;
    nn->threads = threads;
    nn->backend = RELIEF_BACKEND_SCALAR;
    if (search == RELIEF_GRID_SEARCH_KDTREE) {
        struct FLANNParameters fp = relief_knn_exact_params();
        float speedup;
        nn->index = flann_build_index_float((float *)z, (int)nz, dims, &speedup, &fp);
        if (!nn->index) {
            free(nn);
            return relief_fail(err, RELIEF_E_NOMEM, "FLANN could not index %zu exemplar grids",
                               nz);
        }
        snprintf(nn->name, sizeof nn->name, "kd-tree (FLANN, exact)");
    } else {
        snprintf(nn->name, sizeof nn->name, "brute force, scalar");
#ifdef RELIEF_HAVE_OPENCL
        if (backend == RELIEF_BACKEND_OPENCL || backend == RELIEF_BACKEND_AUTO) {
            relief_error cerr;
            relief_device_info info;
            cl_device_id dev;
            int profile;
            relief_status st = relief_cl_profile_env(&profile, err);
            if (st != RELIEF_OK) { /* refused, not a reason to run elsewhere */
                free(nn);
                return st;
            }
            st = relief_cl_device(device, &dev, &info, &cerr);
            /* auto takes a GPU or accelerator, or a device named by number */
            const int gpu = backend == RELIEF_BACKEND_OPENCL ||
                            (st == RELIEF_OK &&
                             (device >= 0 || relief_device_is_accelerator(&info)));
            if (gpu && st == RELIEF_OK)
                st = cl_start(nn, dev, &info, &cerr);
            if (gpu && st == RELIEF_OK)
                nn->backend = RELIEF_BACKEND_OPENCL;
            else if (gpu) {
                cl_stop(nn, 0);
                snprintf(nn->name, sizeof nn->name, "brute force, scalar");
                if (backend == RELIEF_BACKEND_OPENCL) {
                    *err = cerr;
                    free(nn);
                    return st;
                }
                if (note)
                    snprintf(note, note_size, "OpenCL unavailable for the grid search (%s): "
                             "the scalar twin runs", cerr.message);
                if (why)
                    *why = RELIEF_REASON_DEVICE_FELL_BACK;
                note = NULL;
            }
        }
#else
        if (backend == RELIEF_BACKEND_OPENCL) {
            free(nn);
            return relief_fail(err, RELIEF_E_NOT_BUILT,
                               "relief was built without OpenCL (RELIEF_WITH_OPENCL=OFF)");
        }
#endif
    }
    if (note)
        snprintf(note, note_size, "grid search: %s", nn->name);
    *out = nn;
    return RELIEF_OK;
}

relief_status relief_grid_nn_query(relief_grid_nn *nn, const float *q, size_t nq, int k,
                                   uint32_t *idx, relief_error *err)
{
    if (k < 1 || k > GN_MAX_K || (size_t)k > nn->nz)
        return relief_fail(err, RELIEF_E_RANGE, "%d nearest of %zu grids", k, nn->nz);
#ifdef RELIEF_HAVE_OPENCL
    if (nn->backend == RELIEF_BACKEND_OPENCL)
        return cl_query(nn, q, nq, k, idx, err);
#endif
    {
        job j = {nn, q, k, idx};
        if (relief_parallel_ranges(nq, nn->threads, nn->search == RELIEF_GRID_SEARCH_KDTREE
                                                        ? kdtree_range : brute_range, &j))
            return relief_fail(err, RELIEF_E_NOMEM, "the grid search ran out of memory");
    }
    return RELIEF_OK;
}

const char *relief_grid_nn_name(const relief_grid_nn *nn) { return nn->name; }

void relief_grid_nn_destroy(relief_grid_nn *nn)
{
    if (!nn)
        return;
    if (nn->index) {
        struct FLANNParameters fp = relief_knn_exact_params();
        flann_free_index_float(nn->index, &fp);
    }
#ifdef RELIEF_HAVE_OPENCL
    cl_stop(nn, 1);
#endif
    free(nn);
}
