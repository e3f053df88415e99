/* Nearest exemplar grids: FLANN's kd-tree, or brute force on the host or
 * an OpenCL device (grid_nn.h). */
#include "points/grid_nn.h"

#include <flann/flann.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/knn.h"
#include "kernels/grid_math.h"

#define GN_MAX_K 8
#define GN_MAX_THREADS 64
#define GN_CHUNK 64 /* queries per OpenCL launch: 64 x nz distances come back */

#ifdef RELIEF_HAVE_OPENCL
#include "match/ocl.h"
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

typedef struct job {
    relief_grid_nn *nn;
    const float *q;
    size_t lo, hi;
    int k;
    uint32_t *idx;
    int failed;
} job;

static void *run_job(void *arg)
{
    job *j = arg;
    relief_grid_nn *nn = j->nn;
    if (nn->search == RELIEF_GRID_KDTREE) {
        struct FLANNParameters fp = relief_knn_exact_params();
        int id[GN_MAX_K];
        float dist[GN_MAX_K];
        for (size_t i = j->lo; i < j->hi && !j->failed; ++i) {
            if (flann_find_nearest_neighbors_index_float(nn->index, (float *)j->q +
                                                                        i * (size_t)nn->dims,
                                                         1, id, dist, j->k, &fp) != 0)
                j->failed = 1;
            for (int c = 0; c < j->k; ++c)
                j->idx[i * (size_t)j->k + (size_t)c] = id[c] < 0 ? UINT32_MAX : (uint32_t)id[c];
        }
        return NULL;
    }
    {
        float *d = malloc((nn->nz + 1) * sizeof *d);
        if (!d) {
            j->failed = 1;
            return NULL;
        }
        for (size_t i = j->lo; i < j->hi; ++i) {
            const float *q = j->q + i * (size_t)nn->dims;
            for (size_t e = 0; e < nn->nz; ++e)
                d[e] = gm_dist(q, nn->z + e * (size_t)nn->dims, nn->dims, 1);
            top_k(d, nn->nz, j->k, j->idx + i * (size_t)j->k);
        }
        free(d);
    }
    return NULL;
}

static int run_threads(relief_grid_nn *nn, const float *q, size_t nq, int k, uint32_t *idx)
{
    job w[GN_MAX_THREADS];
    pthread_t tid[GN_MAX_THREADS];
    int started[GN_MAX_THREADS] = {0}, failed = 0;
    const int t = (size_t)nn->threads > nq ? (int)nq : nn->threads;
    for (int i = 0; i < t; ++i) {
        w[i] = (job){nn, q, nq * (size_t)i / (size_t)t, nq * (size_t)(i + 1) / (size_t)t, k, idx,
                     0};
        if (i > 0)
            started[i] = pthread_create(&tid[i], NULL, run_job, &w[i]) == 0;
    }
    if (t > 0)
        run_job(&w[0]);
    for (int i = 1; i < t; ++i) {
        if (started[i])
            pthread_join(tid[i], NULL);
        else
            run_job(&w[i]); /* no thread to be had: its share here */
    }
    for (int i = 0; i < t; ++i)
        failed |= w[i].failed;
    return failed;
}

#ifdef RELIEF_HAVE_OPENCL
static relief_status cl_start(relief_grid_nn *nn, int device, relief_error *err)
{
    relief_device_info info;
    cl_device_id dev;
    cl_int rc;
    const char *src[2] = {relief_kernel_grid_math_h, relief_kernel_grid_cl};
    relief_status st = relief_cl_device(device, &dev, &info, err);
    size_t bytes = nn->nz * (size_t)nn->dims * sizeof(float);
    float *zt;
    if (st != RELIEF_OK)
        return st;
    nn->ctx = clCreateContext(NULL, 1, &dev, NULL, NULL, &rc);
    if (rc == CL_SUCCESS)
        nn->queue = clCreateCommandQueue(nn->ctx, dev, 0, &rc);
    if (rc != CL_SUCCESS)
        return relief_fail(err, RELIEF_E_DEVICE, "starting OpenCL on %s: %s", info.name,
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
             info.name, info.type, info.compute_units);
    return RELIEF_OK;
}

static void cl_stop(relief_grid_nn *nn)
{
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
        cl_int rc = clEnqueueWriteBuffer(nn->queue, nn->q, CL_FALSE, 0,
                                         (size_t)nc * nn->dims * sizeof(float),
                                         q + c0 * (size_t)nn->dims, 0, NULL, NULL);
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
                                        NULL);
        if (rc == CL_SUCCESS)
            rc = clEnqueueReadBuffer(nn->queue, nn->out, CL_TRUE, 0,
                                     (size_t)nc * nn->nz * sizeof(float), nn->dist, 0, NULL,
                                     NULL);
        if (rc != CL_SUCCESS)
            return relief_fail(err, RELIEF_E_DEVICE, "grid distances on the device: %s",
                               relief_cl_error_name(rc));
        for (int i = 0; i < nc; ++i)
            top_k(nn->dist + (size_t)i * nn->nz, nn->nz, k, idx + (c0 + (size_t)i) * (size_t)k);
    }
    return RELIEF_OK;
}
#endif

relief_status relief_grid_nn_create(relief_grid_search search, relief_backend backend,
                                    int device, const float *z, size_t nz, int dims, int threads,
                                    relief_grid_nn **out, char *note, size_t note_size,
                                    relief_error *err)
{
    relief_grid_nn *nn;
    *out = NULL;
    if (!nz || dims < 1 || nz > INT32_MAX / (size_t)dims)
        return relief_fail(err, RELIEF_E_RANGE, "%zu exemplar grids of %d floats", nz, dims);
    nn = calloc(1, sizeof *nn);
    if (!nn)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the grid search");
    nn->search = search, nn->z = z, nn->nz = nz, nn->dims = dims;
    nn->threads = threads < 1 ? 1 : threads > GN_MAX_THREADS ? GN_MAX_THREADS : threads;
    nn->backend = RELIEF_BACKEND_SCALAR;
    if (search == RELIEF_GRID_KDTREE) {
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
            int gpu = backend == RELIEF_BACKEND_OPENCL ||
                      (relief_cl_device(device, &dev, &info, &cerr) == RELIEF_OK &&
                       (device >= 0 || strcmp(info.type, "cpu") != 0));
            relief_status st = gpu ? cl_start(nn, device, &cerr) : RELIEF_OK;
            if (gpu && st == RELIEF_OK)
                nn->backend = RELIEF_BACKEND_OPENCL;
            else if (gpu) {
                cl_stop(nn);
                snprintf(nn->name, sizeof nn->name, "brute force, scalar");
                if (backend == RELIEF_BACKEND_OPENCL) {
                    *err = cerr;
                    free(nn);
                    return st;
                }
                if (note)
                    snprintf(note, note_size, "OpenCL unavailable for the grid search (%s): "
                             "the scalar twin runs", cerr.message);
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
    if (run_threads(nn, q, nq, k, idx))
        return relief_fail(err, RELIEF_E_NOMEM, "the grid search ran out of memory");
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
    cl_stop(nn);
#endif
    free(nn);
}
