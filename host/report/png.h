/* PNG output, the one PNG writer of relief (renders, reports, and
 * image/image_io.h's images): relief's own encoder around zlib, which
 * filters and deflates a large image on every core (png.c says how; the
 * bytes do not depend on the number of threads). Files are written atomically
 * (atomic.h): they appear whole or not at all. */
#ifndef RELIEF_HOST_PNG_H
#define RELIEF_HOST_PNG_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"
#include "base/output.h"

/* Largest width or height accepted (pixels). */
#define RELIEF_PNG_MAX_SIDE 16384

/* Write `rgb` (height rows of width x 3 bytes, top row first) to `path`.
 * Errors: RELIEF_E_USAGE for a NULL argument or a side outside
 * 1..RELIEF_PNG_MAX_SIDE; RELIEF_E_IO or RELIEF_E_SYSTEM naming the path
 * and the system's reason; RELIEF_E_NOMEM;
 * RELIEF_E_INTERNAL when zlib fails. */
relief_status relief_png_write(const char *path, const uint8_t *rgb, int width, int height,
                               relief_error *err);

/* The same into a sink (base/output.h), for a caller that stages the file
 * itself, or as a new file `path` inside a folder being staged, its
 * messages naming `shown`. */
relief_status relief_png_write_to(relief_sink *s, const uint8_t *rgb, int width, int height,
                                  relief_error *err);
relief_status relief_png_write_plain(const char *path, const char *shown, const uint8_t *rgb,
                                     int width, int height, relief_error *err);

/* The PNG bytes of `pixels`: height rows of width x channels samples
 * (1 grey, 2 grey + alpha, 3 RGB, 4 RGBA), of 8 bits, or of 16 bits big
 * endian (2 bytes each, as PNG stores them), top row first. *out is
 * malloc'ed (the caller frees it). Errors: RELIEF_E_USAGE for a NULL
 * argument or a shape out of range, RELIEF_E_NOMEM, RELIEF_E_INTERNAL
 * when zlib fails. */
relief_status relief_png_encode_pixels(const uint8_t *pixels, int width, int height,
                                       int channels, int bit_depth, uint8_t **out, size_t *n,
                                       relief_error *err);

/* The same on `threads` threads (clamped to 1..RELIEF_PARALLEL_MAX_THREADS;
 * relief_png_encode_pixels takes every core): the bytes do not depend on
 * it, which the tests check. */
relief_status relief_png_encode_threads(const uint8_t *pixels, int width, int height,
                                        int channels, int bit_depth, int threads, uint8_t **out,
                                        size_t *n, relief_error *err);

/* The PNG bytes of the same image in memory: *out (malloc'ed, the caller
 * frees it) and *n its length. Same errors, without RELIEF_E_IO. */
relief_status relief_png_encode(const uint8_t *rgb, int width, int height, uint8_t **out,
                                size_t *n, relief_error *err);

#endif
