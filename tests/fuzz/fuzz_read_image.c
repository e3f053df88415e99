/* libFuzzer harness for the image readers (image/image_io.c): the input's
 * bytes go to relief_raster_decode, the path every image command's reading
 * takes after the file's bytes are in memory (PNG through libpng, JPEG
 * through libjpeg, binary PNM by relief's own reader, told apart by the
 * first bytes), and to the public relief_image_decode, which returns the
 * samples without a raster. A PNM goes also to the depth readers' entry,
 * its samples as stored (relief_pnm_samples without scaling).
 *
 * Besides the sanitizers, it checks what the API promises: a decode that
 * succeeds gives 1 to 4 channels of 8 or 16 bits, every value an integer
 * in range; one that fails names the input, with a status of bad input
 * (exit 1) or out of memory, never an internal error, and leaves no
 * raster; the public decode agrees, sample for sample, and leaves *out as
 * it was when it fails. A broken promise aborts. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image/image_io.h"
#include "image/pnm.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void fail(const char *what, const char *detail)
{
    fprintf(stderr, "fuzz_read_image: %s: %s\n", what, detail);
    abort();
}

/* relief_image_decode of the same bytes against the raster's outcome
 * (st, r). */
static void check_public(const uint8_t *data, size_t size, relief_status st,
                         const relief_raster *r)
{
    relief_error err = {0};
    relief_image img, untouched;
    relief_status pst;
    memset(&img, 0xab, sizeof img);
    untouched = img;
    /* Its limit is on the samples (a quarter of an 8-bit raster's bytes, a
     * half of a 16-bit one's): only the memory checks may disagree. */
    pst = relief_image_decode(data, size, "input", 16u << 20, &img, &err);
    if (pst != st && pst != RELIEF_E_NOMEM && st != RELIEF_E_NOMEM)
        fail("relief_image_decode and relief_raster_decode disagree", err.message);
    if (pst != RELIEF_OK) {
        if (memcmp(&img, &untouched, sizeof img) != 0)
            fail("a failed relief_image_decode wrote *out", err.message);
        return;
    }
    if (st != RELIEF_OK) {
        relief_image_free(&img);
        return;
    }
    if (img.width != r->width || img.height != r->height || img.channels != r->channels ||
        img.bit_depth != r->bit_depth)
        fail("relief_image_decode's shape differs", "");
    for (size_t i = 0; i < (size_t)r->width * r->height * r->channels; ++i) {
        float v = img.bit_depth == 16 ? (float)((const uint16_t *)img.data)[i]
                                      : (float)((const uint8_t *)img.data)[i];
        if (v != r->v[i])
            fail("relief_image_decode's samples differ", "");
    }
    relief_image_free(&img);
}

/* A PNM's samples as stored: they decode exactly when the scaled ones
 * do (the memory limit aside), in the same shape, none over maxval. */
static void check_pnm_raw(const uint8_t *data, size_t size, relief_status st,
                          const relief_raster *r)
{
    relief_error err = {0};
    relief_pnm h;
    relief_image img = {0, 0, 0, 0, 0, NULL};
    relief_status pst = relief_pnm_header(data, size, "input", &h, &err);
    if (!relief_pnm_sniff(data, size))
        return;
    if (pst == RELIEF_OK && (uint64_t)h.width * h.height * h.channels > (16u << 20))
        return; /* the raster's limit refused it: not decoded here either */
    if (pst == RELIEF_OK)
        pst = relief_pnm_samples(data, size, "input", &h, 0, &img, &err);
    if (pst != RELIEF_OK) {
        if (img.data)
            fail("a failed PNM decode left samples", err.message);
        if (st == RELIEF_OK)
            fail("the raw PNM decode refused what the raster read", err.message);
        return;
    }
    if (st == RELIEF_OK && (img.width != r->width || img.height != r->height ||
                            img.channels != r->channels || img.bit_depth != r->bit_depth))
        fail("the raw PNM decode's shape differs", "");
    for (size_t i = 0; i < (size_t)img.width * img.height * img.channels; ++i) {
        unsigned v = img.bit_depth == 16 ? ((const uint16_t *)img.data)[i]
                                         : ((const uint8_t *)img.data)[i];
        if (v > h.maxval)
            fail("a raw PNM sample over maxval", "");
    }
    relief_image_free(&img);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* 64 MiB of raster at most: a header may claim 65535 x 65535 pixels. */
    relief_image_limit lim = {64u << 20, 1.0, "fuzzing"};
    relief_error err = {0};
    relief_raster r;
    relief_status st = relief_raster_decode(data, size, "input", &lim, &r, &err);

    check_public(data, size, st, &r);
    check_pnm_raw(data, size, st, &r);

    if (st != RELIEF_OK) {
        if (r.v)
            fail("a failed decode left a raster", err.message);
        if (relief_status_exit_code(st) != 1 && st != RELIEF_E_NOMEM)
            fail("an internal error for bad input", err.message);
        if (strncmp(err.message, "input", 5) != 0)
            fail("the message does not name the input", err.message);
        return 0;
    }
    if (r.width < 1 || r.height < 1 || r.channels < 1 || r.channels > 4 ||
        (r.bit_depth != 8 && r.bit_depth != 16))
        fail("a decoded raster out of shape", "");
    for (size_t i = 0; i < (size_t)r.width * r.height * r.channels; ++i) {
        float v = r.v[i];
        if (!(v >= 0.0f && v <= relief_raster_max_value(&r)) || v != floorf(v))
            fail("a value out of range", "");
    }
    relief_raster_free(&r);
    return 0;
}
