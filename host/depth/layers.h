/* Depth layers of a frame's holes (issue 63). A hole between a near and a
 * far surface (a depth camera's shadow beside an object, a stereo
 * occlusion) has a rim in two or more pieces at depths a step apart. Each
 * hole pixel is given to one of those pieces, and the repair fills each
 * layer from its own rim only (depth_fill.c, one pass per rank), so the
 * background continues behind and the foreground's silhouette stays where
 * it was captured, where an interpolation across the hole would draw a
 * ramp (a skirt in the points) from one surface to the other.
 *
 * A step is a difference over `step` times the frame's own noise at that
 * depth, measured on the frame: the median of the non-zero |second
 * differences| along rows and columns, over z^2 for depths (a structured-
 * light or stereo camera's error grows as z^2) and as it is for
 * disparities (a stereo match's error is a fraction of a pixel's
 * disparity, whatever the depth).
 *
 * The rim of each hole is cut into pieces (8-neighbours joined unless a
 * step apart). A piece is in front of another where the two meet on the
 * rim across a step; a piece meeting none (an island) is in front when it
 * is nearer than every piece behind by a step. Rank 0 is a piece in front
 * of none; a piece in front of rank r is rank r + 1 (at most
 * RELIEF_LAYERS_MAX - 1). Pieces of fewer than 3 pixels (flying pixels on
 * a silhouette, noise) bound no layer. A hole pixel takes the rank whose
 * rim is nearest by its path through the hole, the paths to a nearer
 * layer counted `near_weight` times longer (the background is preferred:
 * a hole beside an edge is mostly the camera's shadow on it). With a
 * colour guide a step along the path costs more where the colour changes,
 * so that the layers part at the silhouette seen in colour. */
#ifndef RELIEF_HOST_DEPTH_LAYERS_H
#define RELIEF_HOST_DEPTH_LAYERS_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"

#define RELIEF_LAYERS_MAX 4      /* ranks, so passes of the repair, at most */
#define RELIEF_LAYER_NONE 0xFF   /* a pixel of no stepped hole nor its rim */
#define RELIEF_LAYER_IGNORED 0xFE /* a rim piece too small to bound a layer */

typedef struct relief_layer_params {
    int far_sign;        /* +1: larger values are farther (depths); -1:
                            nearer (disparities) */
    double step;         /* a step is over this many noise units; 8 */
    double near_weight;  /* a nearer layer's paths count this many times
                            longer; 8 without a guide (a shadow's
                            pixels stay behind unless 8 times nearer the
                            front), 1.5 with one */
    const uint8_t *rgb;  /* width x height x 3 colour registered to the
                            depths, or NULL */
} relief_layer_params;

relief_layer_params relief_layer_params_default(void);

typedef struct relief_layers {
    uint8_t *rank;       /* width x height: the rank of each pixel of a
                            stepped hole and of its rim's pieces;
                            RELIEF_LAYER_NONE elsewhere, RELIEF_LAYER_IGNORED
                            on a small piece (owned) */
    int ranks;           /* 1 + the highest rank; 1 when no hole is stepped */
    size_t stepped_holes;
    size_t front_pixels; /* hole pixels given a rank over 0 */
    double noise;        /* the noise unit: z^2's factor, or a disparity */
} relief_layers;

/* Find the layers of the holes `inside` (missing pixels to be filled; the
 * rest of `missing` is neither rim nor hole) of z (width x height, NaN or
 * anything where missing). RELIEF_E_NOMEM. Free with relief_layers_free. */
relief_status relief_layers_find(const float *z, const uint8_t *missing, const uint8_t *inside,
                                 int width, int height, const relief_layer_params *p,
                                 relief_layers *out, relief_error *err);

void relief_layers_free(relief_layers *l);

#endif
