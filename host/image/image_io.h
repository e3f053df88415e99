/* Reading and writing images: PNG through libpng (1, 2, 4, 8 or 16 bits;
 * grey, grey + alpha, palette, RGB, RGBA; interlaced or not) and JPEG
 * through libjpeg (8-bit grey or colour; CMYK is refused). The format is
 * told by the file's first bytes, never by its name; a written file's by
 * its extension (.png, .jpg, .jpeg). Palettes and transparency chunks are
 * expanded: what is read is always 1 to 4 channels of 8 or 16 bits. */
#ifndef RELIEF_HOST_IMAGE_IMAGE_IO_H
#define RELIEF_HOST_IMAGE_IMAGE_IO_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"
#include "base/output.h"
#include "image/raster.h"

typedef enum relief_image_format {
    RELIEF_IMAGE_UNKNOWN = 0,
    RELIEF_IMAGE_PNG,
    RELIEF_IMAGE_JPEG
} relief_image_format;

/* The format of `path` by its extension (case-insensitive). */
relief_image_format relief_image_format_of_name(const char *path);

/* What a reader may take: the decoded image must fit in `limit` bytes
 * after multiplying its raster's size (relief_raster_bytes) by `factor`,
 * the work that will follow it; `what` names that work in the message.
 * limit 0: no limit. */
typedef struct relief_image_limit {
    uint64_t limit;
    double factor;
    const char *what;
} relief_image_limit;

/* Decode `n` bytes of a PNG or JPEG file into *out (caller frees with
 * relief_raster_free). `name` names the data in messages. Errors:
 * RELIEF_E_FORMAT (neither PNG nor JPEG, or a kind not supported: CMYK,
 * 0-pixel), RELIEF_E_PARSE (malformed or truncated, with libpng's or
 * libjpeg's words), RELIEF_E_RANGE (a side over RELIEF_RASTER_MAX_SIDE),
 * RELIEF_E_NOMEM (over the limit, or allocation failed). */
relief_status relief_raster_decode(const uint8_t *data, size_t n, const char *name,
                                  const relief_image_limit *lim, relief_raster *out,
                                  relief_error *err);

/* The file's samples themselves into *out (packed rows of 8-bit, or
 * 16-bit in the host's byte order, samples; the caller frees out->data),
 * without a raster between: what relief_image_read returns. `max_bytes`
 * (0: none) bounds those samples. Errors as relief_raster_decode's; *out
 * is written only on success. */
relief_status relief_image_file_decode(const uint8_t *data, size_t n, const char *name,
                                       uint64_t max_bytes, relief_image *out, relief_error *err);

/* Read the file at `path` (RELIEF_E_IO naming it when it cannot be read),
 * then as relief_raster_decode. */
relief_status relief_raster_read(const char *path, const relief_image_limit *lim,
                                relief_raster *out, relief_error *err);

/* Write `r` (bit_depth 8 or 16; values rounded and clamped to the range)
 * to `path`, PNG or JPEG by its extension, atomically (the file appears
 * whole or not at all). PNG keeps the channels and the bit depth; JPEG
 * (quality 95) takes 8 bits, and drops alpha. RELIEF_E_FORMAT for another
 * extension, or 16 bits to JPEG; RELIEF_E_IO naming the path. */
relief_status relief_raster_write(const char *path, const relief_raster *r, relief_error *err);

/* The same for `img`'s samples as they are (relief_image_check'ed: 8 or 16
 * bits, native endian, any stride), without a raster between: the
 * writer of relief_image_write. */
relief_status relief_image_file_write(const char *path, const relief_image *img,
                                      relief_error *err);

/* The two above into a sink (base/output.h), the format by s->path's
 * extension, for a caller that stages the file itself. */
relief_status relief_raster_write_to(relief_sink *s, const relief_raster *r, relief_error *err);
relief_status relief_image_write_to(relief_sink *s, const relief_image *img, relief_error *err);

#endif
