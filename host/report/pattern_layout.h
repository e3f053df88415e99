/* The pattern measures' layout figures (pattern.h, 3): the signed lean of
 * a part's orientation field about its dominant orientation, and whether
 * it changes across the ridges or along them. Internal to report/. */
#ifndef RELIEF_HOST_PATTERN_LAYOUT_H
#define RELIEF_HOST_PATTERN_LAYOUT_H

#include "report/pattern.h"
#include "report/pattern_grid.h"

/* The dominant orientation, lean RMS and lean-across share of one part
 * (pattern.h, 3), written into out->dominant, out->lean_rms and
 * out->lean_across (NaN where undefined); nothing else of out is touched.
 *
 * gr       the part's grid: only nx, ny and g are read.
 * z        2 nx ny values, row-major like the grid: at a node with a
 *          structure tensor, c (cos 2 theta, sin 2 theta) (c the coherence,
 *          theta the orientation, pattern.h, 2); NaN at the other nodes.
 * spacing  the part's ridge spacing, input units; not finite or not
 *          positive: the lean-across share is NaN. */
void pattern_layout(const part_grid *gr, const double *z, double spacing,
                    relief_pattern_part *out);

#endif
