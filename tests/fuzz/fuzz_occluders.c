/* libFuzzer harness for relief_find_occluders and relief_remove_occluders
 * (relief/occluders.h) through their buffer interface: the input's first
 * bytes choose the frame (width and height 1..24, with or without xyz,
 * colour or not, intrinsics or not), the parameters (background planes or
 * plane, max_planes, min_support, margin, window, colour_distance, edge,
 * min_area, dilate, iterations, seed) and whether the removal is given a
 * mask; the rest supplies the depths (a byte's value as decimetres, 0 and
 * 255 as missing), the colours and the mask, cycled when short.
 *
 * Besides the sanitizers it checks what the API promises: a status of bad
 * input or out of memory with a message, never an internal error; a
 * refused call leaves the frame's bytes as they were and writes no mask; a
 * removal keeps every pixel outside its mask. A broken promise aborts. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "relief/relief.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define HEADER 12
#define MAX_SIDE 24

static void fail(const char *what, const char *detail)
{
    fprintf(stderr, "fuzz_occluders: %s: %s\n", what, detail);
    abort();
}

typedef struct stream {
    const uint8_t *d;
    size_t n, at;
} stream;

static uint8_t next(stream *s)
{
    if (s->n <= HEADER)
        return 0;
    if (s->at >= s->n)
        s->at = HEADER;
    return s->d[s->at++];
}

static void choose(const uint8_t *h, int *w, int *hh, int *flags, relief_occluder_params *p)
{
    *w = 1 + h[0] % MAX_SIDE;
    *hh = 1 + h[1] % MAX_SIDE;
    *flags = h[2];
    p->background = (h[3] & 1) ? RELIEF_BACKGROUND_PLANE : RELIEF_BACKGROUND_PLANES;
    p->max_planes = (h[3] >> 1) % 10;                  /* 0 and 9 refused */
    p->min_support = h[4] == 255 ? NAN : h[4] / 200.0; /* 0 and > 1 refused */
    p->margin = h[5] == 255 ? NAN : h[5] < 128 ? 0.0 : (h[5] - 128) / 100.0;
    p->window = 1 + (h[6] % 16);                        /* evens and 1 refused */
    p->colour_distance = h[7] == 255 ? -1.0 : h[7] / 2.0;
    p->edge = h[8] % 70 - 2;
    p->min_area = h[9] % 12;
    p->dilate = h[10] % 4;
    p->iterations = 8 + h[11] % 40;
    p->seed = h[11];
    if ((*flags & 8) && !(*flags & 1)) {
        p->has_intrinsics = 1;
        p->intrinsics[0] = p->intrinsics[1] = (*flags & 16) ? 0.0 : 20.0;
        p->intrinsics[2] = *w / 2.0, p->intrinsics[3] = *hh / 2.0;
    }
}

static void check_status(relief_status st, const relief_error *err, const char *call)
{
    if (st != RELIEF_OK && st != RELIEF_E_USAGE && st != RELIEF_E_RANGE &&
        st != RELIEF_E_NOMEM)
        fail(call, err->message);
    if (st != RELIEF_OK && !err->message[0])
        fail(call, "a failure without a message");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint8_t head[HEADER] = {0};
    relief_occluder_params p = relief_occluder_params_default();
    relief_remove_params rp = relief_remove_params_default();
    relief_error err = {0};
    relief_image mask = {0, 0, 0, 0, 0, NULL}, given;
    stream s = {data, size, HEADER};
    int w, h, flags;
    size_t n;
    float *z, *xyz, *z0;
    uint8_t *rgb, *m;
    relief_depth_image f;
    relief_status st;
    memcpy(head, data, size < HEADER ? size : HEADER);
    choose(head, &w, &h, &flags, &p);
    n = (size_t)w * h;
    z = malloc(n * sizeof *z), z0 = malloc(n * sizeof *z0);
    xyz = malloc(n * 3 * sizeof *xyz), rgb = malloc(n * 3), m = malloc(n);
    if (!z || !z0 || !xyz || !rgb || !m)
        fail("malloc", "");
    for (size_t i = 0; i < n; ++i) {
        uint8_t b = next(&s);
        z[i] = b == 0 || b == 255 ? NAN : b / 10.0f;
        xyz[3 * i] = ((int)(i % w) - w / 2.0f) / 20.0f * z[i];
        xyz[3 * i + 1] = ((int)(i / w) - h / 2.0f) / 20.0f * z[i];
        xyz[3 * i + 2] = z[i];
    }
    for (size_t i = 0; i < 3 * n; ++i)
        rgb[i] = next(&s);
    for (size_t i = 0; i < n; ++i)
        m[i] = next(&s) & 1;
    memcpy(z0, z, n * sizeof *z);
    f = (relief_depth_image){w, h, z, (flags & 1) ? xyz : NULL, (flags & 2) ? NULL : rgb,
                             RELIEF_DEPTH_PCD_BINARY};
    st = relief_find_occluders(&f, &p, &mask, NULL, &err);
    check_status(st, &err, "relief_find_occluders");
    if (st != RELIEF_OK && mask.data)
        fail("a refused finding wrote a mask", err.message);
    if (memcmp(z, z0, n * sizeof *z) != 0)
        fail("the finding wrote to the frame", "");
    relief_image_free(&mask);
    /* The removal, on a small scalar run. */
    rp.find = p;
    rp.colour.run.backend = rp.depth.run.backend = RELIEF_BACKEND_SCALAR;
    rp.colour.window = rp.depth.window = 3;
    rp.colour.min_window = 3;
    given = (relief_image){w, h, 1, 8, 0, m};
    st = relief_remove_occluders(&f, (flags & 4) ? &given : NULL, &rp, NULL, &err);
    check_status(st, &err, "relief_remove_occluders");
    for (size_t i = 0; i < n; ++i) {
        int changed = memcmp(&z[i], &z0[i], sizeof *z) != 0;
        if (changed && (st != RELIEF_OK || ((flags & 4) && !m[i])))
            fail("a depth outside the removal's mask changed", "");
    }
    free(z), free(z0), free(xyz), free(rgb), free(m);
    return 0;
}
