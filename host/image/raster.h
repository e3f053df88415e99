/* A raster image as the hole filler works on it: values in the file's own
 * units (0..255 or 0..65535 for images, metres or disparities for depth),
 * as floats so that every integer sample is held exactly and the depth
 * images of issue 20 use the same engine. */
#ifndef RELIEF_HOST_IMAGE_RASTER_H
#define RELIEF_HOST_IMAGE_RASTER_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"

/* Largest width or height accepted (pixels): a paper-sized atlas is 8192. */
#define RELIEF_RASTER_MAX_SIDE 65535

typedef struct relief_raster {
    int width, height; /* pixels, each >= 1 */
    int channels;      /* 1 grey, 2 grey + alpha, 3 RGB, 4 RGBA */
    int bit_depth;     /* 8 or 16: values are integers in 0 .. 2^bit_depth - 1;
                          0 for real-valued data (depth) */
    float *v;          /* height x width x channels, row-major, top row first */
} relief_raster;

/* Allocate `out` (values zero). RELIEF_E_RANGE for a side outside
 * 1..RELIEF_RASTER_MAX_SIDE or channels outside 1..4; RELIEF_E_NOMEM. */
relief_status relief_raster_create(int width, int height, int channels, int bit_depth,
                                   relief_raster *out, relief_error *err);
void relief_raster_free(relief_raster *r);

/* Bytes a width x height x channels raster holds. */
uint64_t relief_raster_bytes(int width, int height, int channels);

/* Does the raster carry alpha (2 or 4 channels)? The colour channels are
 * the first (channels - 1) then. */
int relief_raster_has_alpha(const relief_raster *r);

/* Largest value of a channel: 255, 65535, or 0 for real-valued data. */
float relief_raster_max_value(const relief_raster *r);

/* A value as the integer sample written for it: rounded to the nearest,
 * clamped to 0..max (NaN: 0). Inline: it runs once a sample on every
 * image read, filled and written; v + 0.5f is positive here, so the
 * conversion's truncation is floorf's rounding. */
static inline unsigned relief_raster_quantise(float v, float max)
{
    if (!(v > 0.0f)) /* NaN too */
        return 0;
    if (v >= max)
        return (unsigned)max;
    return (unsigned)(float)(v + 0.5f); /* the cast: float's rounding where sums are wider */
}

#endif
