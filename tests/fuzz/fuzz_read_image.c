/* libFuzzer harness for the image readers (image/image_io.c): the input's
 * bytes go to relief_raster_decode, the path every image command's reading
 * takes after the file's bytes are in memory (PNG through libpng, JPEG
 * through libjpeg, told apart by the first bytes).
 *
 * Besides the sanitizers, it checks what the API promises: a decode that
 * succeeds gives 1 to 4 channels of 8 or 16 bits, every value an integer
 * in range; one that fails names the input, with a status of bad input
 * (exit 1) or out of memory, never an internal error, and leaves no
 * raster. A broken promise aborts. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image/image_io.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void fail(const char *what, const char *detail)
{
    fprintf(stderr, "fuzz_read_image: %s: %s\n", what, detail);
    abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* 64 MiB of raster at most: a header may claim 65535 x 65535 pixels. */
    relief_image_limit lim = {64u << 20, 1.0, "fuzzing"};
    relief_error err = {RELIEF_OK, ""};
    relief_raster r;
    relief_status st = relief_raster_decode(data, size, "input", &lim, &r, &err);

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
