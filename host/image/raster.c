#include "image/raster.h"

#include <stdlib.h>

#include "base/error.h"

uint64_t relief_raster_bytes(int width, int height, int channels)
{
    return (uint64_t)width * (uint64_t)height * (uint64_t)channels * sizeof(float);
}

relief_status relief_raster_create(int width, int height, int channels, int bit_depth,
                                   relief_raster *out, relief_error *err)
{
    out->v = NULL;
    if (width < 1 || height < 1 || width > RELIEF_RASTER_MAX_SIDE ||
        height > RELIEF_RASTER_MAX_SIDE)
        return relief_fail(err, RELIEF_E_RANGE,
                           "image of %d x %d pixels: each side must be 1..%d", width, height,
                           RELIEF_RASTER_MAX_SIDE);
    if (channels < 1 || channels > 4)
        return relief_fail(err, RELIEF_E_RANGE, "image with %d channels: expected 1..4",
                           channels);
    out->width = width;
    out->height = height;
    out->channels = channels;
    out->bit_depth = bit_depth;
    out->v = calloc((size_t)width * (size_t)height * (size_t)channels, sizeof(float));
    if (!out->v)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate an image of %d x %d x %d",
                           width, height, channels);
    return RELIEF_OK;
}

void relief_raster_free(relief_raster *r)
{
    if (r) {
        free(r->v);
        r->v = NULL;
    }
}

int relief_raster_has_alpha(const relief_raster *r)
{
    return r->channels == 2 || r->channels == 4;
}

float relief_raster_max_value(const relief_raster *r)
{
    return r->bit_depth == 16 ? 65535.0f : r->bit_depth == 8 ? 255.0f : 0.0f;
}
