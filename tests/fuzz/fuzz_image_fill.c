/* libFuzzer harness for relief_image_fill through its buffer interface
 * (relief/image.h): the input's first bytes choose the image's shape
 * (width and height 1..32, channels 0..5, bit depth 8, 16 or 12, the
 * padding after each row), the mask's (NULL: the image's alpha; its own
 * channels and bit depth), a few parameters (window, min_window, tau,
 * max_hole_fraction, search_radius, interp, exhaustive, seed; the method,
 * and wexler's patch and steps) and when the
 * progress callback cancels; the rest supplies the pixels, then the mask
 * (cycled when short). tests/fuzz/image_fill_seeds.py writes the seeds.
 *
 * Besides the sanitizers, it checks what the API promises: a status of
 * bad input, out of memory or cancelled with a message, never an internal
 * error; a refused or cancelled call leaves every byte of the buffer as it
 * was; a fill keeps every pixel outside the hole and the padding, and
 * makes every filled pixel opaque. A broken promise aborts. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "relief/relief.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define HEADER 14

static void fail(const char *what, const char *detail)
{
    fprintf(stderr, "fuzz_image_fill: %s: %s\n", what, detail);
    abort();
}

/* The input's bytes from `at` on, cycled (zeros when there are none). */
typedef struct stream {
    const uint8_t *d;
    size_t n, at;
} stream;

static uint8_t next(stream *s)
{
    if (s->n == 0)
        return 0;
    if (s->at >= s->n)
        s->at = HEADER < s->n ? HEADER : 0;
    return s->d[s->at++];
}

typedef struct cancel {
    int after, calls;
} cancel;

static int on_progress(void *ctx, double fraction)
{
    cancel *c = ctx;
    if (!(fraction >= 0.0 && fraction <= 1.0))
        fail("a progress fraction out of 0..1", "");
    return c->after > 0 && ++c->calls >= c->after;
}

/* The image's shape and the parameters from the header's bytes. */
static void choose(const uint8_t *h, relief_image *img, relief_image *mask, int *with_mask,
                   relief_image_fill_params *p, cancel *c)
{
    static const int depths[4] = {8, 16, 8, 12};
    img->width = 1 + h[0] % 32;
    img->height = 1 + h[1] % 32;
    img->channels = h[2] % 6;
    img->bit_depth = depths[h[3] & 3];
    img->stride = (size_t)img->width * img->channels * (img->bit_depth / 8) + (h[4] & 7);
    *with_mask = !(h[4] & 0x80);
    mask->width = img->width - ((h[4] & 0x40) && img->width > 1);
    mask->height = img->height;
    mask->channels = 1 + ((h[4] >> 3) & 3);
    mask->bit_depth = (h[3] & 4) ? 16 : 8;
    mask->stride = 0;
    /* Windows up to 13 and sides up to 32: a whole exhaustive fill stays
     * under a second or two with the sanitizers. */
    p->window = 3 + 2 * (h[5] % 6) + ((h[5] & 0x80) != 0);
    p->min_window = 3 + 2 * (h[6] % 6);
    p->tau = h[7] == 255 ? NAN : (double)h[7] * (img->bit_depth == 16 ? 257 : 1) / 4.0;
    p->interp = h[8] & 1;
    p->exhaustive = (h[8] >> 1) & 1;
    p->search_radius = (h[8] & 4) ? (h[8] >> 3) : 0;
    p->seed = (uint32_t)h[9] | (uint32_t)h[10] << 8;
    p->max_hole_fraction = (h[11] % 100) / 100.0;
    p->interp_diff = h[12] == 255 ? INFINITY : h[12] < 128 ? -1.0 : h[12] - 128.0;
    p->run.backend = RELIEF_BACKEND_SCALAR;
    /* The method (issue 62): bit 4 of the last byte; wexler's patch from
     * its top bits, its steps from the seed's bytes. */
    p->method = (h[13] & 0x10) ? RELIEF_IMAGE_FILL_JAIN : RELIEF_IMAGE_FILL_WEXLER;
    p->patch = 3 + 2 * ((h[13] >> 5) % 7);
    p->em_steps = 1 + h[9] % 5;
    p->pm_steps = 1 + h[10] % 4;
    c->after = h[13] % 16;
    c->calls = 0;
}

static size_t bytes_of(const relief_image *img)
{
    size_t row = (size_t)img->width * img->channels * (img->bit_depth == 16 ? 2 : 1);
    return (img->stride ? img->stride : row) * (size_t)img->height;
}

static unsigned sample(const relief_image *img, int x, int y, int c)
{
    size_t row = (size_t)img->width * img->channels * (img->bit_depth / 8);
    const uint8_t *r = (const uint8_t *)img->data + (size_t)y * (img->stride ? img->stride : row);
    uint16_t v;
    if (img->bit_depth == 8)
        return r[(size_t)x * img->channels + c];
    memcpy(&v, r + 2 * ((size_t)x * img->channels + c), 2);
    return v;
}

/* Is pixel (x, y) to fill: the mask's colours non-zero, or alpha 0? */
static int is_hole(const relief_image *img, const relief_image *mask, int x, int y)
{
    int h = 0, colours;
    if (!mask)
        return sample(img, x, y, img->channels - 1) == 0;
    colours = mask->channels == 2 || mask->channels == 4 ? mask->channels - 1 : mask->channels;
    for (int c = 0; c < colours; ++c)
        h |= sample(mask, x, y, c) != 0;
    return h;
}

/* After a fill: outside the hole and between rows, every byte as before;
 * inside, opaque where there is alpha. */
static void check_fill(const relief_image *img, const uint8_t *before, const relief_image *mask)
{
    relief_image old = *img;
    size_t row = (size_t)img->width * img->channels * (img->bit_depth / 8);
    unsigned opaque = img->bit_depth == 16 ? 65535u : 255u;
    old.data = (void *)before;
    for (int y = 0; y < img->height; ++y) {
        const uint8_t *a = (const uint8_t *)img->data + (size_t)y * img->stride;
        if (memcmp(a + row, before + (size_t)y * img->stride + row, img->stride - row) != 0)
            fail("a fill wrote between rows", "");
        for (int x = 0; x < img->width; ++x) {
            int alpha = img->channels == 2 || img->channels == 4;
            if (!is_hole(&old, mask, x, y)) {
                for (int c = 0; c < img->channels; ++c)
                    if (sample(img, x, y, c) != sample(&old, x, y, c))
                        fail("a pixel outside the hole changed", "");
            } else if (alpha && sample(img, x, y, img->channels - 1) != opaque) {
                fail("a filled pixel is not opaque", "");
            }
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    relief_image img, mask;
    relief_image_fill_params p = relief_image_fill_params_default();
    relief_image_fill_report rep;
    relief_error err = {0};
    cancel c;
    stream s = {data, size, HEADER};
    uint8_t head[HEADER] = {0}, *pix, *before, *mpix;
    size_t n, mn;
    int with_mask;
    relief_status st, pst;

    memcpy(head, data, size < HEADER ? size : HEADER);
    choose(head, &img, &mask, &with_mask, &p, &c);
    p.run.progress = on_progress;
    p.run.progress_ctx = &c;
    n = bytes_of(&img);
    mn = bytes_of(&mask);
    pix = malloc(n ? n : 1);
    before = malloc(n ? n : 1);
    mpix = malloc(mn);
    if (!pix || !before || !mpix)
        fail("out of memory", "");
    for (size_t i = 0; i < n; ++i)
        pix[i] = next(&s);
    for (size_t i = 0; i < mn; ++i)
        mpix[i] = next(&s);
    memcpy(before, pix, n);
    img.data = pix;
    mask.data = mpix;

    pst = relief_image_fill_params_validate(&p, &err);
    st = relief_image_fill(&img, with_mask ? &mask : NULL, &p, &rep, &err);
    if (pst != RELIEF_OK && st != pst)
        fail("the fill took parameters its validation refused", err.message);
    if (st == RELIEF_OK) {
        check_fill(&img, before, with_mask ? &mask : NULL);
        if (!rep.json || rep.hole_pixels > (size_t)img.width * img.height)
            fail("a report without JSON or with too many holes", "");
        relief_image_fill_report_free(&rep);
    } else {
        if (st != RELIEF_E_CANCELLED && st != RELIEF_E_NOMEM && relief_status_exit_code(st) != 1)
            fail("an internal error or an unexpected status", err.message);
        if (!err.message[0])
            fail("a failure without a message", relief_status_name(st));
        if (memcmp(pix, before, n) != 0)
            fail("a failed call changed the buffer", err.message);
    }
    free(pix);
    free(before);
    free(mpix);
    return 0;
}
