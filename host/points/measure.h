/* A point-set completion measured against its truth (issue 21's bench and
 * tests): the completion's points labelled 1 (added) against the truth's
 * points labelled 1 (the hole cut out of it, as `relief cut --truth`
 * writes).
 *
 *   accuracy: each added point's distance to the truth's surface (its
 *             triangles, or its nearest point when it has none; RMS, max);
 *   completeness: each truth-hole point's distance to the nearest point of
 *             the completion (RMS, max); Hausdorff the larger max;
 *   colour: each truth-hole point's colour against its nearest added
 *             point's, RMS over the channels (colours in [0, 1]);
 *   roughness: the mean over a region's points of the RMS distance of the
 *             point and its k = 16 neighbours from their least-squares
 *             plane, a texture statistic that rewards detail over blur (a
 *             smooth fill scores near 0); for the added points, the truth's
 *             hole and the truth's captured part;
 *   colour detail: the same with the standard deviation of the luminance
 *             over the neighbourhood.
 * Lengths in the meshes' unit. */
#ifndef RELIEF_HOST_POINTS_MEASURE_H
#define RELIEF_HOST_POINTS_MEASURE_H

#include <stddef.h>

#include "relief/relief.h"

typedef struct relief_points_measures {
    size_t added, truth_hole;
    double acc_rms, acc_max, comp_rms, comp_max, hausdorff;
    double colour_rms;                 /* NaN without colour on both */
    double rough_added, rough_truth_hole, rough_truth_captured;
    double cdetail_added, cdetail_truth_hole; /* NaN without colour */
} relief_points_measures;

/* `region` (4: a ball X, Y, Z, R, or NULL for everywhere): only the added
 * points inside it count, so that holes the scan had before the cut (and
 * the completion filled, where the truth has nothing) are not measured.
 * RELIEF_E_RANGE when either has no `label`, no point labelled 1 (in the
 * region), or fewer than 17 points. */
relief_status relief_points_measure(const relief_mesh *completed, const relief_mesh *truth,
                                    const double *region, relief_points_measures *m,
                                    relief_error *err);

#endif
