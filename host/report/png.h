/* PNG output of an 8-bit RGB image (colour type 2, bit depth 8, no
 * interlace), compressed with zlib. Written atomically (atomic.h): the
 * file appears whole or not at all. */
#ifndef RELIEF_HOST_PNG_H
#define RELIEF_HOST_PNG_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"

/* Largest width or height accepted (pixels). */
#define RELIEF_PNG_MAX_SIDE 16384

/* Write `rgb` (height rows of width x 3 bytes, top row first) to `path`.
 * Errors: RELIEF_E_USAGE for a NULL argument or a side outside
 * 1..RELIEF_PNG_MAX_SIDE; RELIEF_E_IO naming the path; RELIEF_E_NOMEM;
 * RELIEF_E_INTERNAL when zlib fails. */
relief_status relief_png_write(const char *path, const uint8_t *rgb, int width, int height,
                               relief_error *err);

/* The PNG bytes of the same image in memory: *out (malloc'ed, the caller
 * frees it) and *n its length. Same errors, without RELIEF_E_IO. */
relief_status relief_png_encode(const uint8_t *rgb, int width, int height, uint8_t **out,
                                size_t *n, relief_error *err);

#endif
