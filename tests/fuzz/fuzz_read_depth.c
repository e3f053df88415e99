/* libFuzzer harness for the depth readers (depth/depth_io.c): the input's
 * bytes go to relief_depth_decode, which tells a PCD (ascii, binary,
 * binary_compressed through liblzf) from a PFM by the first bytes.
 *
 * Besides the sanitizers, it checks what the API promises: a decode that
 * succeeds gives a frame of at least one pixel whose z is NaN or finite
 * and equals its point's z; one that fails names the input, with a status
 * of bad input (exit 1) or out of memory, never an internal error, and
 * leaves no frame. A broken promise aborts. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "depth/depth_io.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void fail(const char *what, const char *detail)
{
    fprintf(stderr, "fuzz_read_depth: %s: %s\n", what, detail);
    abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    relief_error err = {RELIEF_OK, ""};
    relief_depth_frame f;
    /* 16 M pixels at most: a header may claim 65535 x 65535. */
    relief_status st = relief_depth_decode(data, size, "input", 1u << 24, &f, &err);

    if (st != RELIEF_OK) {
        if (f.z || f.xyz || f.rgb)
            fail("a failed decode left a frame", err.message);
        if (relief_status_exit_code(st) != 1 && st != RELIEF_E_NOMEM)
            fail("an internal error for bad input", err.message);
        if (strncmp(err.message, "input", 5) != 0)
            fail("the message does not name the input", err.message);
        return 0;
    }
    if (f.width < 1 || f.height < 1 || !f.z)
        fail("a decoded frame out of shape", "");
    for (size_t i = 0; i < (size_t)f.width * f.height; ++i) {
        if (!isnan(f.z[i]) && !isfinite(f.z[i]))
            fail("an infinite depth", "");
        if (f.xyz && !(isnan(f.z[i]) ? isnan(f.xyz[i * 3 + 2]) : f.z[i] == f.xyz[i * 3 + 2]))
            fail("z differs from its point's z", "");
    }
    relief_depth_frame_free(&f);
    return 0;
}
