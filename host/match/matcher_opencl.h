/* The OpenCL backend (kernels/score.cl). In a build without OpenCL its
 * creation function is an inline stub that says so. */
#ifndef RELIEF_HOST_MATCHER_OPENCL_H
#define RELIEF_HOST_MATCHER_OPENCL_H

#include "match/backend.h"

/* The OpenCL matcher sends a running query's launch in chunks: the first
 * of RELIEF_OPENCL_CHUNK_FIRST candidates, each next one twice the last,
 * each pruning under just over 1.1 x the minimum of everything scored
 * before it. With only the probes' bound, a launch of 226 000 candidates
 * (a 32 000-vertex bark) took 0.102 s per target against 0.066 s so;
 * below 16384 a second launch cost more than it saved (the bands'
 * mono-scale run, launches of 14 484: 6.88 s in one, 7.09 s in two of
 * 8192 and 6292). Here so that the tests can place candidates past the
 * first chunk. */
#define RELIEF_OPENCL_CHUNK_FIRST 16384

/* The OpenCL matcher on device `device` (relief_devices order; -1: the
 * first), its small launches scored on the host's `threads` (0: the
 * default; relief_score_pool_threads_for). RELIEF_E_RANGE for a device index there is none of;
 * RELIEF_E_DEVICE naming the reason (no platform, the build log of a failed
 * kernel build, out of device memory); RELIEF_E_NOT_BUILT in a build
 * without OpenCL. */
#ifdef RELIEF_HAVE_OPENCL
relief_status relief_matcher_opencl_create(const relief_match_data *d, int device,
                                           int threads, relief_matcher **out,
                                           relief_error *err);

/* RELIEF_OPENCL_HOST_MAX, the largest launch scored on the host instead:
 * *set 0 when unset (out untouched), else its value in *out;
 * RELIEF_E_RANGE naming it when it is not a number of candidates up to
 * 10^9. */
relief_status relief_opencl_host_max_env(size_t *out, int *set, relief_error *err);

/* RELIEF_OPENCL_LANES, the lanes of the score_lanes kernel (1: the score
 * kernel, one candidate per work-item): *set 0 when unset, else its value
 * in *out; RELIEF_E_RANGE naming it when it is not 1..64. Unset, a CPU
 * device gets 16 lanes and any other device 1. */
relief_status relief_opencl_lanes_env(int *out, int *set, relief_error *err);
#else
#include "base/error.h"
static inline relief_status relief_matcher_opencl_create(const relief_match_data *d,
                                                         int device, int threads,
                                                         relief_matcher **out,
                                                         relief_error *err)
{
    (void)d;
    (void)device;
    (void)threads;
    (void)out;
    return relief_fail(err, RELIEF_E_NOT_BUILT,
                       "relief was built without OpenCL (RELIEF_WITH_OPENCL=OFF)");
}
static inline relief_status relief_opencl_host_max_env(size_t *out, int *set,
                                                       relief_error *err)
{
    (void)out;
    (void)err;
    *set = 0; /* nothing reads it */
    return RELIEF_OK;
}
static inline relief_status relief_opencl_lanes_env(int *out, int *set, relief_error *err)
{
    (void)out;
    (void)err;
    *set = 0; /* nothing reads it */
    return RELIEF_OK;
}
#endif

#endif
