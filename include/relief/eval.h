/* relief/eval.h: the measures of a completion (`relief eval`), taken on
 * its per-vertex label (0 captured, 1 completed) over a primitive fitted
 * to the captured part: the mean surface integral of each part (paper
 * 001's MSI, mean |D.n|) and their difference, histogram distances, the
 * seam, dominant frequencies, pattern distances between the parts' height
 * spectra, against a truth the RMS relief error, and whether the
 * completed part is closed (no open or non-manifold edge, no crossing
 * triangle there). */
#ifndef RELIEF_EVAL_H
#define RELIEF_EVAL_H

#include "relief/core.h"
#include "relief/complete.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The headline figures; every measure is in `json`. */
typedef struct relief_eval_result {
    relief_fit_primitive prim;  /* the primitive the heights are taken over */
    size_t captured, completed; /* label-0 and label-1 vertices */
    double msi_captured;        /* mean |h| over the captured part, input units */
    double msi_completed;       /* the same over the completed part */
    double msi_diff_percent;    /* their difference, % of the captured; NaN when
                                   undefined */
    double hist_distance_displacement; /* total variation of the parts' height
                                   histograms, [0, 1] */
    double hist_distance_colour; /* the same for RGB, mean of the channels; NaN
                                   without colour */
    double seam_ratio;          /* mean height jump across captured-completed
                                   edges over the same inside the capture */
    double pattern_spectrum_distance; /* total variation between the parts' height
                                   power spectra by orientation and scale, 0 same
                                   to 1 disjoint */
    int has_truth;              /* 1 when a truth was given: */
    double truth_rms;           /* RMS of h - h_truth over the completed vertices
                                   on the truth, input units */
    char *json;                 /* every measure as one JSON object, as `relief
                                   eval --json` prints them without the file names
                                   (owned) */
    char *text;                 /* the same as lines of "name: value", as `relief
                                   eval` prints them (owned) */
    /* Whether the completion closed what it filled (issue 61), on the
       completed surface near its completed part: a completed vertex (label
       != 0) or a neighbour of one through a triangle, where a patch meets
       its rim. All 0 for a hole closed well. */
    size_t open_loops_completed;  /* boundary loops with a vertex near it */
    size_t open_edges_completed;  /* boundary edges (of one triangle) with an
                                     end near it */
    size_t nonmanifold_edges_completed; /* edges of three triangles or more
                                     with an end near it */
    size_t self_intersections_completed; /* triangles with a completed vertex
                                     that cross or touch another elsewhere
                                     than where the two are joined */
} relief_eval_result;

/* Free what the result owns and zero it. NULL accepted. */
RELIEF_API void relief_eval_result_free(relief_eval_result *r);

/* Measure `completed` (with its `label` property), against `truth` when
 * not NULL (the whole surface in the same coordinates, label 1 on the part
 * the capture lacked, as relief_synth and `relief cut --truth` write it).
 * RELIEF_E_MESH naming what is missing (no labels, an empty part);
 * RELIEF_E_NOMEM. */
RELIEF_API relief_status relief_eval(const relief_mesh *completed, const relief_mesh *truth,
                                     relief_eval_result *out, relief_error *err);

#ifdef __cplusplus
}
#endif

#endif /* RELIEF_EVAL_H */
