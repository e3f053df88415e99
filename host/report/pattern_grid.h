/* The pattern measures' first step (pattern.h, "Why a grid"): a part's
 * points in (u, v) with their fields, and the part resampled onto a
 * regular grid and tapered at its outline. Internal to report/. */
#ifndef RELIEF_HOST_PATTERN_GRID_H
#define RELIEF_HOST_PATTERN_GRID_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"
#include "base/knn.h"
#include "smooth/param.h"

/* Fields per part: height, luminance. */
#define RELIEF_PATTERN_FIELDS 2

/* One part's points in (u, v), the fields over them and a kd-tree. */
typedef struct part_points {
    size_t n;
    double *uv;   /* n x 2 */
    double *f[RELIEF_PATTERN_FIELDS]; /* n heights; n luminances or NULL */
    double lo[2], hi[2];
    double spacing; /* median nearest-neighbour distance */
    flann_index_t index;
    struct FLANNParameters fp;
} part_points;

/* One part resampled onto the grid: node (i, j) at org + g (i, j),
 * row-major j nx + i. */
typedef struct part_grid {
    size_t nx, ny, n_inside;
    double org[2], g;
    uint8_t *inside;
    double *val[RELIEF_PATTERN_FIELDS];
} part_grid;

void pattern_points_free(part_points *pp);

/* The vertices of m labelled `want`: (u, v), heights, luminance when
 * `colour`; a kd-tree and the spacing when there are enough to measure. */
relief_status pattern_points_load(const relief_domain *pm, const relief_mesh *m, int want,
                                  int colour, part_points *pp, relief_error *err);

int pattern_points_measurable(const part_points *pp);

double pattern_points_long_side(const part_points *pp);

double pattern_points_short_side(const part_points *pp);

/* Is field f of the part constant (RMS about its mean at most
 * RELIEF_PATTERN_FLAT times `scale`)? */
int pattern_points_flat(const part_points *pp, int f, double scale);

void pattern_grid_free(part_grid *gr);

/* Resample the part's fields onto nodes of step g over its bounding box
 * (see the header: inside test, local weighted plane). */
relief_status pattern_grid_resample(const part_points *pp, double g, part_grid *gr,
                                    relief_error *err);

/* Taper weights (see the header), 0 outside the part. */
void pattern_grid_taper(const part_grid *gr, double *w);

#endif
