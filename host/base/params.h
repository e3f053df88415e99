/* The growth's parameters as the engine's stages take them: what
 * relief_complete_params (relief/complete.h) becomes once the engine has
 * checked it (complete/params.c converts), plus the helpers that resolve
 * its defaults. Internal: tests and benchmarks set it directly. */
#ifndef RELIEF_HOST_BASE_PARAMS_H
#define RELIEF_HOST_BASE_PARAMS_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"

/* Candidate work (samples x R x targets) above which auto searches
 * coherently. An exhaustive candidate on a real capture's smoothed base
 * costs 0.9 to 1.4 us on 2 cores at the window of 3 (the ggg_sfm cuts:
 * 3.8e7 to 6.5e7 candidates took 34 to 77 s), so 2.5e7 keeps an
 * exhaustive growth to about half a minute; the demo and every synthetic
 * test (at most 1.9e7) stay exhaustive. */
#define RELIEF_SEARCH_AUTO_WORK 2.5e7

/* The same bound when a selection tells the holes (hole_ball,
 * hole_labels): a told hole is small against the capture, whose every
 * sample an exhaustive search scores for each target, and a user filling
 * one waits for it (issue 61: within 3 x CGAL's fairing). On a sphere cap
 * of 320 targets over 10 439 samples (1.3e7) the coherent search took
 * 0.25 s against 7.6 s and landed nearer the truth (RMS 0.0030 against
 * 0.0044). */
#define RELIEF_SEARCH_AUTO_WORK_TOLD 2.5e6

/* The samples a told hole's targets are matched against (the pool,
 * match_data.h's relief_match_data_build_near): the capture nearest the
 * hole, RELIEF_TOLD_POOL_PER_TARGET per target and never fewer than
 * RELIEF_TOLD_POOL_MIN, so a small hole in a large capture costs what the
 * hole does (issue 61: a told fill within 3 x CGAL's time). */
#define RELIEF_TOLD_POOL_MIN 1024
#define RELIEF_TOLD_POOL_PER_TARGET 16

/* The pool's size for n_targets targets (a count, or an estimate). */
static inline double relief_told_pool(double n_targets)
{
    const double n = RELIEF_TOLD_POOL_PER_TARGET * n_targets;
    return n > RELIEF_TOLD_POOL_MIN ? n : RELIEF_TOLD_POOL_MIN;
}

/* Parameters of `relief complete` and `relief smooth`. Lengths are in the
 * input's units; 0 for spacing means "derive from the capture". */
typedef struct relief_params {
    relief_fit_model fit;   /* default auto */
    int window;             /* W, neighbourhood radius in edge hops; 3, [1, 16] */
    int rotations;          /* R, rotations tried per sample; [1, 64], or
                               0 (default): relief_params_rotations */
    double error;           /* e, acceptance threshold; 0.1, (0, 1e6] */
    double mu;              /* shape weight; <0 means "1 without colour,
                               0.5 with"; else [0, 1] */
    uint32_t seed;          /* MT19937 seed; 1 */
    double coherence;       /* kappa: a target takes its best coherent
                               candidate (the sample that continues a
                               neighbour's source patch) when that one's SSD
                               is at most kappa x the minimum; 0 = off (paper
                               000's draw alone); 0, or [1, 100] */
    relief_search_mode search; /* default auto */
    int told_holes;         /* 1: a selection tells the holes: auto's bound is
                               RELIEF_SEARCH_AUTO_WORK_TOLD, and a mono-scale
                               growth matches against the pool
                               RELIEF_TOLD_POOL_* */
    int search_k;           /* similar pairs per pair in the coherent
                               search; 8, [1, 64] */
    int levels;             /* M hierarchy levels; 1 (mono-scale), [1, 8] */
    relief_backend backend; /* default auto */
    int device;             /* OpenCL device index; -1 = first usable */
    int oversample;         /* oversampling passes; 1, [0, 4] */
    double spacing;         /* target spacing; 0 = from capture, else > 0 */
    int has_extent;         /* 1 when extent[] is set */
    double extent[4];       /* cylinder: z0, z1 (2 values); plane: u0, v0,
                               u1, v1 (4 values), in primitive coordinates */
    int n_extent;           /* number of extent values given: 2 or 4 */
    uint64_t max_memory;    /* host memory limit in bytes; a run whose
                               estimate exceeds it is refused before it
                               allocates. 0 (default): 80% of physical
                               memory */
    int threads;            /* host threads (relief_run_options.threads):
                               0 (default) the CPUs this thread may run on,
                               else 1..RELIEF_THREADS_MAX; scalar runs on one */
} relief_params;

/* Defaults as documented in relief_params. */
relief_params relief_params_default(void);

/* Check every field against its range; names the first one out of range
 * with its allowed range, and in err->param (RELIEF_REASON_PARAMETER) by
 * its name in relief_complete_params ("window", "extent"). */
relief_status relief_params_validate(const relief_params *params,
                                     relief_error *err);

/* The rotations tried on a primitive: params->rotations, or for 0 (the
 * default) 1 on a plane, whose frames are all alike so that a rotation can
 * only turn a directional pattern (streaks, waves), and 4 on a cylinder or
 * a sphere, where frames turn with the surface. */
int relief_params_rotations(const relief_params *params, relief_fit_model model);

/* The search params->search asks for on ns samples, R rotations and
 * n_targets targets: exhaustive or coherent, auto resolved. */
relief_search_mode relief_params_search(const relief_params *params, size_t ns, int rotations,
                                        size_t n_targets);

#endif
