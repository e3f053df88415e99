/* relief_complete_params described for clients that set them by name and
 * for the documentation (relief_param, relief/core.h). The smooth
 * completion's fields come first: relief_smooth takes those, the memory
 * limit and the threads. The ranges are relief_complete_params_validate's. */
#include "complete/engine.h"

#include <float.h>

#include "base/param_table.h"

#define T relief_complete_params

static const char *const fits[] = {"auto", "plane", "sphere", "cylinder", NULL};
static const char *const bases[] = {"auto", "primitive", "smooth", NULL};
static const char *const fills[] = {"auto", "holes", "whole", NULL};
static const char *const frames[] = {"paper", "primitive", NULL};
static const char *const schemes[] = {"midpoint", "butterfly", NULL};
static const char *const searches[] = {"auto", "exhaustive", "coherent", NULL};

/* What relief_smooth takes: SMOOTH_COUNT entries. */
#define SMOOTH_COUNT 13

static const relief_param table[] = {
    RP_ENUM(T, fit, "MODEL", fits, "the primitive fitted to the capture: auto (default: "
            "the one whose residual each extra parameter cuts by 10 %), plane, sphere or "
            "cylinder"),
    RP_INT(T, oversample, "N", 0, 4, "1-to-4 subdivision passes of the capture, 0..4 "
           "(default 1)"),
    RP_ENUM(T, oversample_scheme, "S", schemes, "where a new sample goes: butterfly "
            "(default: on the smooth surface through the capture) or midpoint (the "
            "papers' coplanar edge midpoints)"),
    RP_REAL1(T, spacing, "S", DBL_MIN, HUGE_VAL, 0, "target vertex spacing, in the "
             "input's units, > 0; 0 (default): the 10th percentile of the capture's edge "
             "lengths"),
    RP_REALS(T, extent, "A,B[,C,D]", 2, 4, n_extent, 0, "the region to complete: a "
             "cylinder's z0,z1 along the fitted axis from its axis point, or a plane's "
             "u0,v0,u1,v1 in its (e1, e2) frame from its fitted point (both in the "
             "report); default: from the capture"),
    RP_ENUM(T, fill, "REGION", fills, "what to complete of the uncovered primitive: auto "
            "(default: a plane's holes; a cylinder's or sphere's whole, as a one-sided "
            "scan's hidden side, unless the capture has holes and goes all round it (no "
            "direction over 45 degrees from a captured one) or covers under 20 % of it), "
            "holes (inside the capture's outline, chosen by max_hole and --hole-mask) or "
            "whole"),
    RP_ENUM(T, frames, "RULE", frames, "the local frames relief is copied in: paper "
            "(default, paper 000's rule) or primitive (along its parameterisation)"),
    RP_REAL(T, max_growth, "R", 0, HUGE_VAL, "refuse more than R targets per captured "
            "vertex, the sign of a primitive that does not suit the capture (default "
            "100; 0: no limit)"),
    RP_FLAG(T, accept_poor_fit, "go on, with a warning, when the fit's rms is over 10 % "
            "of the primitive's size (default: refuse)"),
    RP_FLAG(T, keep_spikes, "keep the capture's spikes as relief (default: a vertex over "
            "8 robust roughness scales outside its neighbours' heights is a scanner spike, "
            "left out and completed)"),
    RP_REAL(T, max_hole, "L", 0, 1e30, "the hole model: holes whose rims are wider than "
            "L (the capture's units) are openings by design (a vase's mouth or base) and "
            "stay open, on the smooth base and when a cylinder's or sphere's holes are "
            "filled (a plane's too when L is given); 0 (default): a quarter of the bounding "
            "box's diagonal"),
    RP_MAX_MEMORY(T),
    RP_THREADS(T),
    /* the growth: relief_complete only */
    RP_ENUM(T, base, "B", bases, "what the relief grows over: primitive (the fitted one), "
            "smooth (paper 002's smoothed, hole-filled base, for a mesh no primitive fits: "
            "a head, a statue; levels coarsen it by collapses) or auto (default: smooth "
            "when no primitive fits well and neither fit, extent nor accept_poor_fit is "
            "set)"),
    RP_INT(T, window, "W", 1, 16, "neighbourhood radius in edge hops, 1..16 (default 3)"),
    RP_INT1(T, rotations, "R", 1, 64, 0, "rotations tried per sample, 1..64; 0 (default): "
            "1 on a plane, whose frames are all alike, 4 otherwise"),
    RP_REAL(T, error, "E", DBL_MIN, 1e6, "the acceptance threshold e, > 0 and at most 1e6 "
            "(default 0.1)"),
    RP_REAL1(T, mu, "MU", 0, 1, -1, "the shape's weight against the colour's, 0..1; -1 "
             "(default): 1 without colour, 0.5 with"),
    RP_SEED(T, seed, "the draw's seed (default 1)"),
    RP_REAL1(T, coherence, "K", 1, 100, 0, "copy patches: take the best candidate that "
             "continues a neighbour's source when its score is within K x the best, 1..100; "
             "0 (default): off, the paper's draw alone"),
    RP_ENUM(T, search, "S", searches, "auto (default), exhaustive or coherent: score every "
            "sample for each target (paper 000), or only those that continue its "
            "neighbours' patches and their K most similar (k-coherence: sub-quadratic); "
            "auto is coherent above 2.5e7 samples x R x targets (2.5e6 when --hole-mask tells the holes)"),
    RP_INT(T, search_k, "K", 1, 64, "similar samples per patch for the coherent search, "
           "1..64 (default 8)"),
    RP_INT(T, levels, "M", 1, 8, "hierarchy levels, 1..8 (default 1: mono-scale)"),
    RP_FLAG(T, bootstrap, "completed targets become matchable too (default: off)"),
    RP_FLAG(T, prune, "stop a candidate's score once it cannot win: the same result, "
            "faster (default: on; off scores every candidate in full, the paper's "
            "exhaustive search)"),
    RP_PATH(T, checkpoint, "FILE", "save the growth's state to FILE when the call is "
            "cancelled (SIGINT), on a device failure and every checkpoint_every seconds; "
            "removed when the run completes"),
    RP_REAL(T, checkpoint_every, "S", 0, HUGE_VAL, "seconds between saves; 0: only on a "
            "cancel or a failure (default 300)"),
    RP_PATH(T, resume, "FILE", "continue a run saved by checkpoint (the same input and "
            "parameters, any backend): the same output as a run never stopped"),
    RP_PATH(T, report_dir, "DIR", "write report.json, renders, histograms and index.html "
            "(open it in a browser) into the folder DIR"),
    RP_FLAG(T, measure, "put the completion's measures in the report (default: on)"),
    RP_BACKEND(T, "who scores the candidates, all with the same output: scalar (the "
               "reference, one thread), opencl (the kernel on the device), host (the "
               "reference on every core), auto (default: OpenCL on a GPU or accelerator, or "
               "on the device named, else host)"),
    RP_DEVICE(T),
};

const relief_param *relief_complete_param_table(size_t *count)
{
    if (count)
        *count = sizeof table / sizeof table[0];
    return table;
}

const relief_param *relief_smooth_param_table(size_t *count)
{
    if (count)
        *count = SMOOTH_COUNT;
    return table;
}
