/* libFuzzer harness for relief_depth_fill (relief/depth.h) through its
 * buffer interface: the input's first bytes choose the frame (width and
 * height 1..24, a colour guide or not, a mask or not, a PFM's disparities
 * or depths) and the parameters (variant, window, edges, edge_step,
 * values, seam, tileable, levels, seed); the rest supplies the depths (a
 * byte's value as decimetres, 0 and 255 missing), the colours and the
 * mask, cycled when short.
 *
 * Besides the sanitizers it checks what the API promises: a status of bad
 * input or out of memory with a message, never an internal error; a
 * refused call leaves the frame's bytes as they were; a repair keeps every
 * captured, unmasked pixel's bits and writes no infinity. A broken promise
 * aborts. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "relief/relief.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define HEADER 8
#define MAX_SIDE 24

static void fail(const char *what, const char *detail)
{
    fprintf(stderr, "fuzz_depth_fill: %s: %s\n", what, detail);
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

static void choose(const uint8_t *h, int *w, int *hh, int *flags, relief_depth_fill_params *p)
{
    *w = 1 + h[0] % MAX_SIDE;
    *hh = 1 + h[1] % MAX_SIDE;
    *flags = h[2];
    p->variant = (relief_depth_variant)(h[3] % 3);
    p->window = 3 + 2 * ((h[3] >> 2) % 3) - ((h[3] >> 4) & 1); /* evens refused */
    p->edges = (h[4] & 0xC0) == 0xC0 ? (relief_depth_edges)3 /* refused */
               : (h[4] & 1)         ? RELIEF_DEPTH_EDGES_ACROSS
               : (h[4] & 0x40)      ? RELIEF_DEPTH_EDGES_AUTO
                                    : RELIEF_DEPTH_EDGES_LAYERS;
    p->edge_step = h[5] == 255 ? NAN : h[5] == 0 ? 0.5 : h[5] / 8.0; /* 0.5 and NaN refused */
    p->values = (relief_depth_values)((h[4] >> 1) % 4);             /* 3 refused */
    p->seam = (h[4] >> 3) & 1;
    p->tileable = ((h[4] >> 4) & 3) == 3;
    p->levels = 1 + h[6] % 3;
    p->seed = h[7];
    p->search_radius = 4 + h[7] % 8;
    p->run.backend = RELIEF_BACKEND_SCALAR;
}

static void check_status(relief_status st, const relief_error *err)
{
    if (st != RELIEF_OK && st != RELIEF_E_USAGE && st != RELIEF_E_RANGE &&
        st != RELIEF_E_NOMEM)
        fail("relief_depth_fill", err->message);
    if (st != RELIEF_OK && !err->message[0])
        fail("relief_depth_fill", "a failure without a message");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint8_t head[HEADER] = {0};
    relief_depth_fill_params p = relief_depth_fill_params_default();
    relief_error err = {0};
    stream s = {data, size, HEADER};
    int w, h, flags;
    size_t n;
    float *z, *z0;
    uint8_t *rgb, *m;
    relief_image mask;
    relief_depth_image f;
    relief_status st;
    memcpy(head, data, size < HEADER ? size : HEADER);
    choose(head, &w, &h, &flags, &p);
    n = (size_t)w * h;
    z = malloc(n * sizeof *z), z0 = malloc(n * sizeof *z0), rgb = malloc(n * 3), m = malloc(n);
    if (!z || !z0 || !rgb || !m)
        fail("malloc", "");
    for (size_t i = 0; i < n; ++i) {
        uint8_t b = next(&s);
        z[i] = b == 0 || b == 255 ? NAN : b / 10.0f;
    }
    for (size_t i = 0; i < 3 * n; ++i)
        rgb[i] = next(&s);
    for (size_t i = 0; i < n; ++i)
        m[i] = next(&s) % 7 == 0;
    memcpy(z0, z, n * sizeof *z);
    f = (relief_depth_image){w, h, z, NULL, (flags & 1) ? rgb : NULL,
                             (flags & 2) ? RELIEF_DEPTH_PFM : RELIEF_DEPTH_PNG16};
    mask = (relief_image){w, h, 1, 8, 0, m};
    st = relief_depth_fill(&f, (flags & 4) ? &mask : NULL, &p, NULL, &err);
    check_status(st, &err);
    for (size_t i = 0; i < n; ++i) {
        int changed = memcmp(&z[i], &z0[i], sizeof *z) != 0;
        int kept = !isnan(z0[i]) && !((flags & 4) && m[i]);
        if (changed && (st != RELIEF_OK || kept))
            fail("a depth changed that the call promised to keep", err.message);
        if (isinf(z[i]))
            fail("an infinite depth written", "");
    }
    free(z), free(z0), free(rgb), free(m);
    return 0;
}
