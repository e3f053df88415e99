/* The OpenCL matcher: kernels/score.cl, running relief_math.h's scoring,
 * the scalar reference's arithmetic: on a CPU device score_lanes (runs of
 * candidates in lock-step lanes, rm_score_range), elsewhere score (one
 * work-item per (sample, rotation), rm_score_candidate).
 *
 * The surface goes to the device once; textured targets update their
 * positions, colours and matchable flags there just before the next
 * launch; per target only the neighbourhood travels. With pruning, the
 * host first scores 512 evenly spread candidates itself to bound the
 * minimum, and the launch prunes above just over 1.1 x that bound, which
 * can never drop a best-set member; a large pruned launch goes in chunks,
 * each under the minimum of those before it. Queries too small to pay for a
 * launch are scored on the host's cores (score_pool.h) instead.
 * Kernel sources are embedded at build time; RELIEF_KERNEL_DIR names a
 * folder to read relief_math.h and score.cl from instead (development). */
#include <ctype.h>
#include <errno.h>
#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "match/matcher_opencl.h"
#include "match/matcher_scalar.h"
#include "device/cl_profile.h"
#include "device/ocl.h"
#include "match/score_pool.h"

#define RM_REAL float
#define RM_WITH_SCORING
#include "kernels/relief_math.h" /* RM_VALID */

#define WG_SIZE 64
/* Candidates the host scores to bound the minimum before a pruned launch.
 * Measured on the bark with PoCL on one thread: 64 probes left the bound
 * loose enough that the kernel spent twice the scalar reference's time per
 * candidate; 512 bring it to the exhaustive kernel's efficiency (about 1 %
 * of the bark's candidates, a millisecond on the host); 2048 gain little. */
#define PROBES 512
/* Launches of at most this many candidates are scored on the host instead
 * (relief_score_pool_run); RELIEF_OPENCL_HOST_MAX overrides it.
 * A CPU device runs on the very cores the pool would use, and its launch
 * first pays the 512 probes there: up to 4096 candidates they are at least
 * an eighth of the work. Measured with PoCL on 2 cores (medians of 3 to
 * 5): bands 2000's level 1 (1005 launches of 2548) 1.31 s as launches,
 * 0.93 s on the pool; paper 001's mono-scale run (2900 each) 0.71 and
 * 0.54 s. The pool kept ahead above that too (14484: 13 %), so the kernel
 * keeps the large launches, where it is closest, and a GPU every launch
 * from 1024 up. On an H100 with 16 host threads, paper 001's growth took
 * 0.189, 0.184, 0.178 and 0.150 s with 0, 256, 1024 and 4096 (medians of
 * 5, one run each): close, and the best value depends on the host's cores
 * too, so 1024 stays. */
#define HOST_MAX_CPU 4096
/* The lanes of score_lanes on a CPU device (RELIEF_OPENCL_LANES overrides
 * it; 1 picks the score kernel), and the candidates each of its
 * work-items takes. */
#define LANES_CPU 16
#define LANES_MAX 64
#define PER_ITEM 256
#define HOST_MAX_OTHER 1024
#define HOST_MAX_LIMIT 1000000000

extern const char relief_kernel_relief_math_h[];
extern const char relief_kernel_score_cl[];

typedef struct ocl {
    cl_context ctx;
    cl_command_queue queue;
    relief_cl_profile *prof; /* RELIEF_OPENCL_PROFILE's record; NULL: off */
    cl_program prog;
    cl_kernel kernel;
    cl_mem proj, pos, col, matchable, tri, vt_start, vt, cell_start, cell_items, lslot, litems;
    cl_mem s_proj, s_frame, cos_r, sin_r, ssd, flag, subset;
    cl_mem qp, q, g, qcol;
    size_t qcap; /* neighbours the query buffers hold */
    relief_score_pool *pool; /* scores the launches too small to pay */
    size_t host_max;          /* launches up to this many candidates go there */
    int lanes;                /* score_lanes' RM_LANES; 1: the score kernel */
    /* Vertices textured since the device's copy was last brought up to
     * date: ids dirty_lo..dirty_hi (none when dirty_lo > dirty_hi). */
    uint32_t dirty_lo, dirty_hi;
} ocl;

/* Release the surface's buffers (upload_data's; the program, queue and
 * query buffers stay), once the queue has finished. */
static void release_data(ocl *o)
{
    cl_mem *mems[] = {&o->proj, &o->pos, &o->col, &o->matchable, &o->tri, &o->vt_start,
                      &o->vt, &o->cell_start, &o->cell_items, &o->lslot, &o->litems,
                      &o->s_proj, &o->s_frame, &o->cos_r, &o->sin_r, &o->ssd, &o->flag,
                      &o->subset};
    if (o->queue)
        clFinish(o->queue);
    for (size_t i = sizeof mems / sizeof mems[0]; i-- > 0;)
        if (*mems[i]) {
            clReleaseMemObject(*mems[i]);
            *mems[i] = NULL;
        }
}

/* Free o; `created`: its creation succeeded (the profile is written). */
static void ocl_free(ocl *o, int created)
{
    if (!o)
        return;
    release_data(o); /* waits for pending writes, which read the host's arrays */
    relief_cl_profile_close(o->prof, created);
    relief_score_pool_destroy(o->pool);
    {
        cl_mem query[] = {o->qp, o->q, o->g, o->qcol};
        for (size_t i = 0; i < sizeof query / sizeof query[0]; ++i)
            if (query[i])
                clReleaseMemObject(query[i]);
    }
    if (o->kernel)
        clReleaseKernel(o->kernel);
    if (o->prog)
        clReleaseProgram(o->prog);
    if (o->queue)
        clReleaseCommandQueue(o->queue);
    if (o->ctx)
        clReleaseContext(o->ctx);
    free(o);
}

/* Read a whole file into a NUL-terminated buffer. */
static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    char *buf = NULL;
    long n;
    if (!f)
        return NULL;
    if (fseek(f, 0, SEEK_END) == 0 && (n = ftell(f)) >= 0 && fseek(f, 0, SEEK_SET) == 0) {
        buf = malloc((size_t)n + 1);
        if (buf && fread(buf, 1, (size_t)n, f) != (size_t)n) {
            free(buf);
            buf = NULL;
        } else if (buf) {
            buf[n] = '\0';
        }
    }
    fclose(f);
    return buf;
}

/* Environment variable `name` as a plain decimal number in lo..hi: *set 0
 * when unset or empty (out untouched), else its value in *out;
 * RELIEF_E_RANGE naming it and `expected` otherwise. */
static relief_status env_number(const char *name, unsigned long long lo, unsigned long long hi,
                                const char *expected, unsigned long long *out, int *set,
                                relief_error *err)
{
    const char *env = getenv(name);
    char *end = NULL;
    unsigned long long v;
    *set = env && *env;
    if (!*set)
        return RELIEF_OK;
    errno = 0;
    v = strtoull(env, &end, 10);
    if (!isdigit((unsigned char)env[0]) || errno || *end || v < lo || v > hi)
        return relief_fail(err, RELIEF_E_RANGE, "%s='%.40s': expected %s", name, env,
                           expected);
    *out = v;
    return RELIEF_OK;
}

relief_status relief_opencl_host_max_env(size_t *out, int *set, relief_error *err)
{
    unsigned long long v = 0;
    char expected[64];
    relief_status st;
    snprintf(expected, sizeof expected, "a number of candidates, 0..%d", HOST_MAX_LIMIT);
    st = env_number("RELIEF_OPENCL_HOST_MAX", 0, HOST_MAX_LIMIT, expected, &v, set, err);
    if (st == RELIEF_OK && *set)
        *out = (size_t)v;
    return st;
}

relief_status relief_opencl_lanes_env(int *out, int *set, relief_error *err)
{
    unsigned long long v = 0;
    char expected[64];
    relief_status st;
    snprintf(expected, sizeof expected, "1..%d (1: one candidate per work-item)", LANES_MAX);
    st = env_number("RELIEF_OPENCL_LANES", 1, LANES_MAX, expected, &v, set, err);
    if (st == RELIEF_OK && *set)
        *out = (int)v;
    return st;
}

/* What this device gets unless the environment says otherwise: on a CPU
 * device, the largest launch the host scores itself is HOST_MAX_CPU and
 * score_lanes runs LANES_CPU lanes, whose loops its compiler vectorises;
 * elsewhere HOST_MAX_OTHER and the score kernel, one candidate per
 * work-item (lanes 1). RELIEF_OPENCL_HOST_MAX and RELIEF_OPENCL_LANES
 * override them. */
static relief_status tune_for(cl_device_id dev, ocl *o, relief_error *err)
{
    cl_device_type type = 0;
    int host_max_set = 0, lanes_set = 0, cpu;
    relief_status st = relief_opencl_host_max_env(&o->host_max, &host_max_set, err);
    if (st == RELIEF_OK)
        st = relief_opencl_lanes_env(&o->lanes, &lanes_set, err);
    if (st != RELIEF_OK)
        return st;
    if (clGetDeviceInfo(dev, CL_DEVICE_TYPE, sizeof type, &type, NULL) != CL_SUCCESS)
        type = 0;
    cpu = (type & CL_DEVICE_TYPE_CPU) != 0;
    if (!host_max_set)
        o->host_max = cpu ? HOST_MAX_CPU : HOST_MAX_OTHER;
    if (!lanes_set)
        o->lanes = cpu ? LANES_CPU : 1;
    return RELIEF_OK;
}

static relief_status build_program(ocl *o, cl_device_id dev, relief_error *err)
{
    const char *kernel = o->lanes > 1 ? "score_lanes" : "score";
    char lanes[64] = "";
    const char *dir = getenv("RELIEF_KERNEL_DIR");
    char *files[2] = {NULL, NULL}, options[256];
    const char *src[3];
    cl_device_fp_config fp = 0;
    cl_int rc;
    relief_status st = RELIEF_OK;

    src[0] = "#define RM_WITH_SCORING 1\n";
    src[1] = relief_kernel_relief_math_h;
    src[2] = relief_kernel_score_cl;
    if (dir && *dir) {
        char path[4096];
        snprintf(path, sizeof path, "%s/relief_math.h", dir);
        files[0] = slurp(path);
        snprintf(path, sizeof path, "%s/score.cl", dir);
        files[1] = slurp(path);
        if (!files[0] || !files[1]) {
            st = relief_fail(err, RELIEF_E_DEVICE,
                             "RELIEF_KERNEL_DIR=%s: cannot read relief_math.h and score.cl "
                             "there: %s",
                             dir, strerror(errno));
            goto done;
        }
        src[1] = files[0];
        src[2] = files[1];
    }
    /* Division must round as the host's does for the scores to agree bit
     * for bit; ask for it where the device offers it. */
    clGetDeviceInfo(dev, CL_DEVICE_SINGLE_FP_CONFIG, sizeof fp, &fp, NULL);
    if (o->lanes > 1)
        snprintf(lanes, sizeof lanes, " -DRELIEF_LANES_KERNEL -DRM_LANES=%d", o->lanes);
    snprintf(options, sizeof options, "-cl-std=CL1.2 -DRELIEF_WG_SIZE=%d%s%s", WG_SIZE, lanes,
             (fp & CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT)
                 ? " -cl-fp32-correctly-rounded-divide-sqrt"
                 : "");
    st = relief_cl_build(o->ctx, dev, src, 3, options,
                         dir && *dir ? ", sources from RELIEF_KERNEL_DIR" : "", &o->prog, err);
    if (st != RELIEF_OK)
        goto done;
    o->kernel = clCreateKernel(o->prog, kernel, &rc);
    if (rc != CL_SUCCESS)
        st = relief_fail(err, RELIEF_E_DEVICE, "clCreateKernel(%s): %s", kernel,
                         relief_cl_error_name(rc));
done:
    free(files[0]);
    free(files[1]);
    return st;
}

/* A device buffer holding `bytes` from `host` (at least 1 byte). */
static relief_status upload(ocl *o, cl_mem *mem, const void *host, size_t bytes,
                            cl_mem_flags flags, const char *what, relief_error *err)
{
    cl_int rc;
    *mem = clCreateBuffer(o->ctx, flags | (host && bytes ? CL_MEM_COPY_HOST_PTR : 0),
                          bytes ? bytes : 1, bytes ? (void *)host : NULL, &rc);
    if (rc != CL_SUCCESS)
        return relief_fail(err, RELIEF_E_DEVICE, "cannot allocate %zu bytes of device memory "
                           "for %s: %s", bytes, what, relief_cl_error_name(rc));
    return RELIEF_OK;
}

/* The surface's buffers for match data d (device-resident for the run). */
static relief_status upload_data(ocl *o, const relief_match_data *d, relief_error *err)
{
    const size_t ncand = (size_t)d->ns * (size_t)d->rotations;
    relief_status st;
    o->dirty_lo = UINT32_MAX, o->dirty_hi = 0; /* the whole surface goes now */
#define UP(mem, ptr, bytes, what)                                                         \
    if ((st = upload(o, &o->mem, ptr, bytes, CL_MEM_READ_ONLY, what, err)) != RELIEF_OK) \
        return st;
    UP(proj, d->proj, (size_t)d->nv * 3 * sizeof(float), "projected positions");
    UP(pos, d->pos, (size_t)d->nv * 3 * sizeof(float), "positions");
    UP(col, d->col, (size_t)d->nv * 3 * sizeof(float), "colours");
    UP(matchable, d->matchable, d->nv, "labels");
    UP(tri, d->tri, (size_t)d->nt * 3 * sizeof(uint32_t), "triangles");
    UP(vt_start, d->vt_start, ((size_t)d->nv + 1) * sizeof(uint32_t), "vertex-triangle lists");
    UP(vt, d->vt, (size_t)d->vt_start[d->nv] * sizeof(uint32_t), "vertex-triangle lists");
    UP(cell_start, d->cell_start,
       ((size_t)d->dims[0] * d->dims[1] * d->dims[2] + 1) * sizeof(uint32_t), "the grid");
    UP(cell_items, d->cell_items, (size_t)d->nv * sizeof(uint32_t), "the grid");
    UP(lslot, d->lslot, ((size_t)d->lmask + 1) * 3 * sizeof(uint32_t), "the closest-vertex lists");
    UP(litems, d->litems, (d->n_litems ? d->n_litems : 1) * sizeof(uint32_t),
       "the closest-vertex lists");
    UP(s_proj, d->s_proj, (size_t)d->ns * 3 * sizeof(float), "sample positions");
    UP(s_frame, d->s_frame, (size_t)d->ns * 9 * sizeof(float), "sample frames");
    UP(cos_r, d->cos_r, (size_t)d->rotations * sizeof(float), "rotations");
    UP(sin_r, d->sin_r, (size_t)d->rotations * sizeof(float), "rotations");
#undef UP
    if ((st = upload(o, &o->subset, NULL, (size_t)d->ns * sizeof(cl_uint), CL_MEM_READ_ONLY,
                     "the sample subset", err)) != RELIEF_OK ||
        (st = upload(o, &o->ssd, NULL, ncand * sizeof(float), CL_MEM_WRITE_ONLY, "scores",
                     err)) != RELIEF_OK ||
        (st = upload(o, &o->flag, NULL, ncand, CL_MEM_WRITE_ONLY, "scores", err)) != RELIEF_OK)
        return st;
    return RELIEF_OK;
}

/* Another surface on the same device: keeps the context, queue and built
 * program (the hierarchy's levels), replaces the surface's buffers. */
static relief_status ocl_rebind(void *ctx, const relief_match_data *d, relief_error *err)
{
    ocl *o = ctx;
    release_data(o);
    return upload_data(o, d, err);
}

/* Bring the device's positions, colours and matchable flags up to date
 * with the textured vertices' (ocl_update), in one write per array over
 * the range of ids they span: vertices in between rewrite the values the
 * device already has. Called only before a launch; no wait here, since the
 * in-order queue runs the writes before the launch, and the launch ends in
 * a blocking read (or, after a failure, a clFinish), so the host's bytes
 * stay as they are until the writes are done. */
static relief_status flush_updates(ocl *o, const relief_match_data *d, relief_error *err)
{
    const size_t lo = o->dirty_lo, n = lo <= o->dirty_hi ? o->dirty_hi - lo + 1 : 0;
    cl_int rc = CL_SUCCESS;
    if (n == 0)
        return RELIEF_OK;
    rc |= clEnqueueWriteBuffer(o->queue, o->pos, CL_FALSE, lo * 3 * sizeof(float),
                               n * 3 * sizeof(float), d->pos + 3 * lo, 0, NULL,
                               relief_cl_profile_event(o->prof, "write", n * 3 * sizeof(float)));
    rc |= clEnqueueWriteBuffer(o->queue, o->col, CL_FALSE, lo * 3 * sizeof(float),
                               n * 3 * sizeof(float), d->col + 3 * lo, 0, NULL,
                               relief_cl_profile_event(o->prof, "write", n * 3 * sizeof(float)));
    rc |= clEnqueueWriteBuffer(o->queue, o->matchable, CL_FALSE, lo, n, d->matchable + lo, 0,
                               NULL, relief_cl_profile_event(o->prof, "write", n));
    if (rc != CL_SUCCESS)
        return relief_fail(err, RELIEF_E_DEVICE, "updating vertices %zu to %zu on the device: "
                           "%s", lo, lo + n - 1, relief_cl_error_name(rc));
    o->dirty_lo = UINT32_MAX, o->dirty_hi = 0;
    return RELIEF_OK;
}

/* Room on the device for a neighbourhood of n vertices (twice that, so
 * that the buffers grow seldom). */
static relief_status reserve_query(ocl *o, size_t n, relief_error *err)
{
    const size_t cap = n * 2;
    cl_mem *qb[4] = {&o->qp, &o->q, &o->g, &o->qcol};
    size_t per[4] = {3, 3, 1, 3};
    if (n <= o->qcap)
        return RELIEF_OK;
    for (int i = 0; i < 4; ++i) {
        relief_status st;
        if (*qb[i])
            clReleaseMemObject(*qb[i]);
        *qb[i] = NULL;
        st = upload(o, qb[i], NULL, cap * per[i] * sizeof(float), CL_MEM_READ_ONLY,
                    "the neighbourhood", err);
        if (st != RELIEF_OK)
            return st;
    }
    o->qcap = cap;
    return RELIEF_OK;
}

/* The query's neighbourhood, and its subset of samples when it has one,
 * queued for the device (not waited for). */
static relief_status upload_query(ocl *o, const relief_match_query *qr, cl_uint centres,
                                  relief_error *err)
{
    const cl_uint n = qr->n;
    const size_t v3 = n * 3 * sizeof(float);
    cl_int rc = CL_SUCCESS;
    rc |= clEnqueueWriteBuffer(o->queue, o->qp, CL_FALSE, 0, v3, qr->qp, 0, NULL,
                               relief_cl_profile_event(o->prof, "write", v3));
    rc |= clEnqueueWriteBuffer(o->queue, o->q, CL_FALSE, 0, v3, qr->q, 0, NULL,
                               relief_cl_profile_event(o->prof, "write", v3));
    rc |= clEnqueueWriteBuffer(o->queue, o->g, CL_FALSE, 0, n * sizeof(float), qr->g, 0, NULL,
                               relief_cl_profile_event(o->prof, "write", n * sizeof(float)));
    rc |= clEnqueueWriteBuffer(o->queue, o->qcol, CL_FALSE, 0, v3, qr->qcol, 0, NULL,
                               relief_cl_profile_event(o->prof, "write", v3));
    if (qr->subset && centres > 0)
        rc |= clEnqueueWriteBuffer(o->queue, o->subset, CL_FALSE, 0, centres * sizeof(cl_uint),
                                   qr->subset, 0, NULL,
                                   relief_cl_profile_event(o->prof, "write",
                                                           centres * sizeof(cl_uint)));
    if (rc != CL_SUCCESS)
        return relief_fail(err, RELIEF_E_DEVICE, "uploading the neighbourhood failed");
    return RELIEF_OK;
}

/* The score kernel's arguments; *cutoff_arg and *range_arg get the
 * indices of the cutoff and of the candidate range, set again per
 * launch. */
static relief_status set_score_args(ocl *o, const relief_match_data *d,
                                    const relief_match_query *qr, float cutoff,
                                    cl_uint per_item, cl_uint *cutoff_arg, cl_uint *range_arg,
                                    relief_error *err)
{
    cl_float4 grid, lgrid;
    cl_uint4 dims, ldims;
    cl_uint use_subset = qr->subset != NULL;
    cl_uint cfirst = 0, cend = 0;
    cl_uint rot = (cl_uint)d->rotations, n = qr->n;
    cl_int rc = CL_SUCCESS;
    cl_uint a = 0;
    grid.s[0] = d->grid[0], grid.s[1] = d->grid[1], grid.s[2] = d->grid[2],
    grid.s[3] = d->grid[3];
    dims.s[0] = d->dims[0], dims.s[1] = d->dims[1], dims.s[2] = d->dims[2], dims.s[3] = 0;
    for (int k = 0; k < 4; ++k)
        lgrid.s[k] = d->lgrid[k];
    for (int k = 0; k < 3; ++k)
        ldims.s[k] = d->ldims[k];
    ldims.s[3] = d->lmask; /* the kernel reads the mask from .w */
#define ARG(v) rc |= clSetKernelArg(o->kernel, a++, sizeof(v), &(v))
    ARG(o->proj); ARG(o->pos); ARG(o->col); ARG(o->matchable); ARG(o->tri);
    ARG(o->vt_start); ARG(o->vt); ARG(o->cell_start); ARG(o->cell_items); ARG(grid);
    ARG(dims); ARG(lgrid); ARG(ldims); ARG(o->lslot); ARG(o->litems); ARG(o->s_proj); ARG(o->s_frame); ARG(o->cos_r); ARG(o->sin_r);
    ARG(o->subset); ARG(use_subset); ARG(rot); ARG(n); ARG(o->qp); ARG(o->q); ARG(o->g); ARG(o->qcol); ARG(d->mu);
    ARG(d->inv_b2); ARG(qr->inv_wsum); *cutoff_arg = a; ARG(cutoff); ARG(o->ssd); ARG(o->flag);
    *range_arg = a; ARG(cfirst); ARG(cend); ARG(per_item);
#undef ARG
    if (rc != CL_SUCCESS)
        return relief_fail(err, RELIEF_E_DEVICE, "clSetKernelArg failed");
    return RELIEF_OK;
}

static relief_status ocl_score(void *ctx, const relief_match_data *d,
                               const relief_match_query *qr, float *ssd, uint8_t *flag,
                               relief_error *err)
{
    ocl *o = ctx;
    const size_t ncand = relief_match_query_candidates(d, qr);
    const size_t local = o->lanes > 1 ? 1 : WG_SIZE;
    const cl_uint per_item = o->lanes > 1 ? PER_ITEM : 1;
    float cutoff = qr->cutoff;
    cl_uint centres = qr->subset ? qr->n_subset : d->ns;
    cl_uint cfirst = 0, cend = 0;
    cl_int rc = CL_SUCCESS;
    cl_uint cutoff_arg = 0, range_arg = 0;
    relief_status st;

    if (ncand <= o->host_max) { /* also every empty query */
        /* A small query (a sample pyramid's box, a coarse level) takes
         * less time here, on the host's cores, than a launch and its
         * probes; the same function scores it, so the best set is the
         * same. */
        double t0 = relief_cl_profile_now(o->prof);
        relief_score_pool_run(o->pool, d, qr, ssd, flag);
        relief_cl_profile_host(o->prof, "queries too small to launch", t0);
        return RELIEF_OK;
    }
    /* From here on a failure goes to `fail`, which waits for the queue:
     * writes and reads not waited for still use the caller's buffers
     * (the query, ssd, flag), which it may free once this returns. */
    st = flush_updates(o, d, err);
    if (st == RELIEF_OK)
        st = reserve_query(o, qr->n, err);
    if (st != RELIEF_OK)
        goto fail;
    if (qr->running) {
        /* Bound the minimum from a spread of candidates scored here. */
        const size_t probes = ncand < PROBES ? ncand : PROBES;
        double t0 = relief_cl_profile_now(o->prof);
        const float best = relief_score_pool_probe(o->pool, d, qr, probes);
        relief_cl_profile_host(o->prof, "probes before a pruned launch", t0);
        if (best < FLT_MAX) {
            float c11 = relief_match_cutoff_after(best);
            if (c11 < cutoff)
                cutoff = c11;
        }
    }
    st = upload_query(o, qr, centres, err);
    if (st == RELIEF_OK)
        st = set_score_args(o, d, qr, cutoff, per_item, &cutoff_arg, &range_arg, err);
    if (st != RELIEF_OK)
        goto fail;
    for (size_t first = 0, chunk = qr->running ? RELIEF_OPENCL_CHUNK_FIRST : ncand;
         first < ncand; first += chunk, chunk *= 2) {
        size_t global;
        if (chunk > ncand - first)
            chunk = ncand - first;
        /* Work-items: one per candidate (score) or per PER_ITEM of them
         * (score_lanes), in whole work-groups. */
        global = (chunk + per_item - 1) / per_item;
        global = (global + local - 1) / local * local;
        cfirst = (cl_uint)first;
        cend = (cl_uint)(first + chunk);
        rc = clSetKernelArg(o->kernel, cutoff_arg, sizeof cutoff, &cutoff);
        rc |= clSetKernelArg(o->kernel, range_arg, sizeof cfirst, &cfirst);
        rc |= clSetKernelArg(o->kernel, range_arg + 1, sizeof cend, &cend);
        if (rc == CL_SUCCESS)
            rc = clEnqueueNDRangeKernel(o->queue, o->kernel, 1, NULL, &global, &local, 0,
                                        NULL,
                                        relief_cl_profile_event(o->prof, o->lanes > 1
                                                                             ? "score_lanes"
                                                                             : "score",
                                                                0));
        if (rc != CL_SUCCESS) {
            st = relief_fail(err, RELIEF_E_DEVICE, "launching the score kernel: %s",
                             relief_cl_error_name(rc));
            goto fail;
        }
        rc = clEnqueueReadBuffer(o->queue, o->ssd, CL_FALSE, first * sizeof(float),
                                 chunk * sizeof(float), ssd + first, 0, NULL,
                                 relief_cl_profile_event(o->prof, "read", chunk * sizeof(float)));
        if (rc == CL_SUCCESS)
            rc = clEnqueueReadBuffer(o->queue, o->flag, CL_TRUE, first, chunk, flag + first, 0,
                                     NULL, relief_cl_profile_event(o->prof, "read", chunk));
        if (rc != CL_SUCCESS) {
            st = relief_fail(err, RELIEF_E_DEVICE, "reading the scores back: %s",
                             relief_cl_error_name(rc));
            goto fail;
        }
        if (qr->running)
            for (size_t c = first; c < first + chunk; ++c)
                if (flag[c] == RM_VALID) {
                    float c11 = relief_match_cutoff_after(ssd[c]);
                    if (c11 < cutoff)
                        cutoff = c11;
                }
    }
    return RELIEF_OK;
fail:
    clFinish(o->queue);
    return st;
}

static relief_status ocl_update(void *ctx, const relief_match_data *d, uint32_t v,
                                relief_error *err)
{
    /* Only noted here: the host scores most small launches itself, so the
     * device's copy is written just before the next launch that reads it
     * (flush_updates), not once per textured vertex. */
    ocl *o = ctx;
    (void)d;
    (void)err;
    if (v < o->dirty_lo)
        o->dirty_lo = v;
    if (v > o->dirty_hi)
        o->dirty_hi = v;
    return RELIEF_OK;
}

static void ocl_destroy(void *ctx) { ocl_free(ctx, 1); }

static const relief_matcher_ops ocl_ops = {"opencl", ocl_score, ocl_update, ocl_rebind,
                                           ocl_destroy};

relief_status relief_matcher_opencl_create(const relief_match_data *d, int device,
                                           int threads, relief_matcher **out,
                                           relief_error *err)
{
    relief_device_info info;
    cl_device_id dev = NULL;
    cl_int rc;
    ocl *o = NULL;
    relief_matcher *m = NULL;
    relief_status st;

    st = relief_cl_device(device < 0 ? 0 : device, &dev, &info, err);
    if (st != RELIEF_OK)
        return st;

    o = calloc(1, sizeof *o);
    m = calloc(1, sizeof *m);
    if (!o || !m) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the OpenCL matcher");
        goto fail;
    }
    st = tune_for(dev, o, err);
    if (st == RELIEF_OK)
        st = relief_cl_profile_open("mesh matcher", info.name, &o->prof, err);
    if (st != RELIEF_OK)
        goto fail;
    o->ctx = clCreateContext(NULL, 1, &dev, NULL, NULL, &rc);
    if (rc != CL_SUCCESS) {
        st = relief_fail(err, RELIEF_E_DEVICE, "clCreateContext: %s", relief_cl_error_name(rc));
        goto fail;
    }
    o->queue = clCreateCommandQueue(o->ctx, dev, relief_cl_profile_queue_flags(o->prof), &rc);
    if (rc != CL_SUCCESS) {
        st = relief_fail(err, RELIEF_E_DEVICE, "clCreateCommandQueue: %s",
                         relief_cl_error_name(rc));
        goto fail;
    }
    st = build_program(o, dev, err);
    if (st == RELIEF_OK)
        st = relief_score_pool_create(relief_score_pool_threads_for(threads), &o->pool, err);
    if (st != RELIEF_OK)
        goto fail;
    st = upload_data(o, d, err);
    if (st != RELIEF_OK)
        goto fail;
    m->ops = &ocl_ops;
    m->ctx = o;
    m->backend = RELIEF_BACKEND_OPENCL;
    if (o->lanes > 1)
        snprintf(m->device, sizeof m->device, "%.96s (%s, %u compute units, %d lanes) on %.96s",
                 info.name, info.type, info.compute_units, o->lanes,
                 info.platform);
    else
        snprintf(m->device, sizeof m->device, "%.96s (%s, %u compute units) on %.96s",
                 info.name, info.type, info.compute_units,
                 info.platform);
    *out = m;
    return RELIEF_OK;
fail:
    ocl_free(o, 0);
    free(m);
    return st;
}
