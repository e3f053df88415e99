/* libFuzzer harness for the depth readers (depth/depth_io.c): the input's
 * bytes go to relief_depth_frame_decode, which tells a PCD (ascii, binary,
 * binary_compressed through liblzf) from a PFM by the first bytes, and,
 * when they start as a PCD, to relief_pcd_decode_cloud too, the point-set
 * reader's entry (issue 21), which also takes an unorganised cloud
 * (HEIGHT 1, up to 1e8 points).
 *
 * Besides the sanitizers, it checks what the API promises: a decode that
 * succeeds gives a frame of at least one pixel whose z is NaN or finite
 * and equals its point's z; one that fails names the input, with a status
 * of bad input (exit 1) or out of memory, never an internal error, and
 * leaves no frame. A PCD that decodes as a depth frame decodes as the
 * same cloud (the cloud reader accepts more, never less). A broken
 * promise aborts. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "depth/depth_io.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* 16 M pixels (points) at most: a header may claim 65535 x 65535, or a
 * cloud of 1e8 points. */
#define FUZZ_MAX_PIXELS (1u << 24)

static void fail(const char *what, const char *detail)
{
    fprintf(stderr, "fuzz_read_depth: %s: %s\n", what, detail);
    abort();
}

/* The promises of a decode that returned `st` into `f`. */
static void check(relief_status st, const relief_depth_frame *f, const relief_error *err,
                  const char *entry)
{
    if (st != RELIEF_OK) {
        if (f->z || f->xyz || f->rgb)
            fail(entry, "a failed decode left a frame");
        if (relief_status_exit_code(st) != 1 && st != RELIEF_E_NOMEM)
            fail(entry, "an internal error for bad input");
        if (strncmp(err->message, "input", 5) != 0)
            fail(entry, "the message does not name the input");
        return;
    }
    if (f->width < 1 || f->height < 1 || !f->z)
        fail(entry, "a decoded frame out of shape");
    for (size_t i = 0; i < (size_t)f->width * f->height; ++i) {
        if (!isnan(f->z[i]) && !isfinite(f->z[i]))
            fail(entry, "an infinite depth");
        if (f->xyz &&
            !(isnan(f->z[i]) ? isnan(f->xyz[i * 3 + 2]) : f->z[i] == f->xyz[i * 3 + 2]))
            fail(entry, "z differs from its point's z");
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    relief_error err = {0}, cerr = {0};
    relief_depth_frame f, c;
    relief_status st = relief_depth_frame_decode(data, size, "input", FUZZ_MAX_PIXELS, &f, &err), cst;

    check(st, &f, &err, "relief_depth_frame_decode");
    if ((size >= 6 && memcmp(data, "# .PCD", 6) == 0) ||
        (size >= 7 && memcmp(data, "VERSION", 7) == 0)) {
        cst = relief_pcd_decode_cloud(data, size, "input", FUZZ_MAX_PIXELS, &c, &cerr);
        check(cst, &c, &cerr, "relief_pcd_decode_cloud");
        if (cst == RELIEF_OK && (!c.xyz || c.format == RELIEF_DEPTH_PFM))
            fail("relief_pcd_decode_cloud", "a cloud without points");
        if (st == RELIEF_OK) {
            size_t px = (size_t)f.width * f.height;
            if (cst != RELIEF_OK)
                fail("relief_pcd_decode_cloud refused a depth frame", cerr.message);
            if (c.width != f.width || c.height != f.height || c.format != f.format ||
                !c.rgb != !f.rgb || memcmp(c.z, f.z, px * sizeof *f.z) ||
                memcmp(c.xyz, f.xyz, px * 3 * sizeof *f.xyz) ||
                (f.rgb && memcmp(c.rgb, f.rgb, px * 3)))
                fail("relief_pcd_decode_cloud", "a cloud differs from its depth frame");
        }
        if (cst == RELIEF_OK)
            relief_depth_frame_free(&c);
    }
    if (st == RELIEF_OK)
        relief_depth_frame_free(&f);
    return 0;
}
