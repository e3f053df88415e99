/* What depth-image repair does to a frame around the repair itself
 * (depth/depth_fill.h): which pixels are missing (the frame's own, and a
 * mask's), the pinhole camera of an organised cloud, the points of its
 * filled pixels, and the repaired points as a PLY. */
#ifndef RELIEF_HOST_DEPTH_FRAME_H
#define RELIEF_HOST_DEPTH_FRAME_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"
#include "base/output.h"

/* Check `mask` (relief/image.h) as a mask of a width x height frame: data
 * set, 1 to 4 channels of 8 or 16 bits, a stride that holds a row, and the
 * frame's size. RELIEF_E_USAGE naming the field (both sizes when they
 * differ), RELIEF_E_RANGE for a value out of range. */
relief_status relief_depth_mask_check(const relief_image *mask, int width, int height,
                                      relief_error *err);

/* bits[i] (width x height) = 1 where `mask` (checked) is non-zero in any
 * channel but alpha, else 0. */
void relief_depth_mask_bits(const relief_image *mask, uint8_t *bits);

/* missing[i] (width x height) = 1 where f's z is not finite or 0, or where
 * `mask` (may be NULL; checked) is non-zero in any channel but alpha.
 * *in_input gets the pixels missing in f, *by_mask those known in f but
 * masked. */
void relief_depth_missing(const relief_depth_image *f, const relief_image *mask,
                          uint8_t *missing, size_t *in_input, size_t *by_mask);

/* The camera of an organised cloud, x / z = cam[0] u + cam[1] and y / z =
 * cam[2] v + cam[3] (a pinhole; u, v pixels), fitted by least squares to
 * f->xyz's points of finite, non-zero z. 0 when there are too few distinct
 * columns or rows (or no xyz). */
int relief_depth_fit_camera(const relief_depth_image *f, double cam[4]);

/* Give the pixels where missing != 0 their points through `cam` (NULL: no
 * camera, NaN points) at their depth f->z (NaN stays NaN), and, when f has
 * rgb, the colour of source[i] (the captured pixel their texture came from;
 * black where -1). f->xyz must be set. */
void relief_depth_cloud_fill(relief_depth_image *f, const uint8_t *missing,
                             const int64_t *source, const double *cam);

/* Write f's points (those whose xyz z is finite) as a binary
 * little-endian PLY (x y z float, red green blue uchar when f has rgb,
 * then label uchar = label[i]), atomically. f->xyz must be set.
 * RELIEF_E_IO naming the path. */
relief_status relief_depth_points_write(const char *path, const relief_depth_image *f,
                                        const uint8_t *label, relief_error *err);

/* The same into the sink s (base/output.h), for a caller that stages the
 * file itself. */
relief_status relief_depth_points_write_to(relief_sink *s, const relief_depth_image *f,
                                           const uint8_t *label, relief_error *err);

#endif
