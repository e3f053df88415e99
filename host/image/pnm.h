/* Binary Netpbm images (P5 grey, P6 RGB; maxval 1..65535, two big-endian
 * bytes a sample above 255): NYU Depth's colour and raw depth, and what
 * many tools write without a library. The header and the samples are read
 * apart, so that a caller checks the size against its memory limit before
 * anything is allocated. */
#ifndef RELIEF_HOST_IMAGE_PNM_H
#define RELIEF_HOST_IMAGE_PNM_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"

typedef struct relief_pnm {
    int width, height;  /* pixels, 1..RELIEF_RASTER_MAX_SIDE */
    int channels;       /* 1 (P5) or 3 (P6) */
    unsigned maxval;    /* 1..65535 */
    size_t offset;      /* where the samples start */
} relief_pnm;

/* Whether `n` bytes start as a PNM of any kind ("P1" to "P7"): the
 * readers then say what is wrong with it rather than "not an image". */
int relief_pnm_sniff(const uint8_t *d, size_t n);

/* The header of a binary PNM: magic, width, height, maxval ('#' comments
 * allowed between them), then exactly one whitespace byte. RELIEF_E_FORMAT
 * for a PNM kind other than P5 / P6 (ascii, bitmap, PAM), RELIEF_E_PARSE
 * naming the field for a malformed one, RELIEF_E_RANGE for a side over
 * RELIEF_RASTER_MAX_SIDE. Messages start with `name`. */
relief_status relief_pnm_header(const uint8_t *d, size_t n, const char *name, relief_pnm *h,
                                relief_error *err);

/* The samples after header h into *out (packed rows, 8 bits when maxval <
 * 256, else 16 bits in the host's byte order; the caller frees
 * out->data). full_range: scaled so that maxval reads as 255 or 65535 (a
 * picture's intensities); 0: the values as stored (a depth camera's
 * counts). RELIEF_E_PARSE for a truncated file (the bytes needed and
 * found) or a sample over maxval (its pixel); RELIEF_E_NOMEM. */
relief_status relief_pnm_samples(const uint8_t *d, size_t n, const char *name,
                                 const relief_pnm *h, int full_range, relief_image *out,
                                 relief_error *err);

#endif
