/* relief's PNG writer (host/report/png.c): every shape it takes, from one
 * pixel to rows of the largest side at 16 bits (wider than the 32 KiB a
 * stripe is primed with) and images of many stripes, encoded on 1, 2 and
 * 3 threads to the same bytes, and decoded by the tests' own decoder
 * (png_decode.h: every CRC, the one zlib stream and its adler32, the five
 * filters) back to the samples; and the arguments it refuses. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "png_decode.h"
#include "report/png.h"

/* check_pattern's samples, as the bytes PNG stores. */
static uint8_t *pattern(int w, int h, int c, int depth)
{
    size_t row = (size_t)w * c * (depth / 8), n = row * (size_t)h;
    uint8_t *px = malloc(n);
    for (size_t i = 0; px && i < n; ++i)
        px[i] = (uint8_t)check_pattern(i, row);
    return px;
}

static void shape(int w, int h, int c, int depth)
{
    relief_error err = {0};
    uint8_t *px = pattern(w, h, c, depth), *png[3] = {NULL, NULL, NULL};
    size_t n[3] = {0, 0, 0};
    png_decoded d;
    const char *why;
    CHECK(px != NULL, "%d x %d: out of memory", w, h);
    for (int t = 0; px && t < 3; ++t)
        CHECK(relief_png_encode_threads(px, w, h, c, depth, t + 1, &png[t], &n[t], &err) ==
                  RELIEF_OK,
              "%d x %d x %d, %d bits, %d threads: %s", w, h, c, depth, t + 1, err.message);
    if (!png[0] || !png[1] || !png[2])
        goto done;
    CHECK(n[0] == n[1] && n[0] == n[2] && memcmp(png[0], png[1], n[0]) == 0 &&
              memcmp(png[0], png[2], n[0]) == 0,
          "%d x %d x %d, %d bits: other bytes on other thread counts", w, h, c, depth);
    why = png_decode_all(png[1], n[1], &d);
    CHECK(why == NULL, "%d x %d x %d, %d bits: %s", w, h, c, depth, why);
    if (!why) {
        CHECK(d.width == w && d.height == h && d.channels == c && d.depth == depth,
              "%d x %d x %d, %d bits: decoded %d x %d x %d, %d bits", w, h, c, depth, d.width,
              d.height, d.channels, d.depth);
        CHECK(memcmp(d.samples, px, (size_t)w * h * c * (depth / 8)) == 0,
              "%d x %d x %d, %d bits: other samples", w, h, c, depth);
        printf("%5d x %-5d x %d, %2d bits: %8zu bytes, %3zu IDAT\n", w, h, c, depth, n[1],
               d.idat_chunks);
    }
    free(d.samples);
done:
    for (int t = 0; t < 3; ++t)
        free(png[t]);
    free(px);
}

static void refused(const uint8_t *px, int w, int h, int c, int depth, const char *what)
{
    relief_error err = {0};
    uint8_t *png = NULL;
    size_t n = 0;
    CHECK(relief_png_encode_pixels(px, w, h, c, depth, &png, &n, &err) == RELIEF_E_USAGE &&
              png == NULL && err.message[0],
          "%s: not refused (%s)", what, err.message);
}

int main(void)
{
    static const uint8_t one[8] = {0};
    shape(1, 1, 1, 8);
    for (int c = 1; c <= 4; ++c) {
        shape(37, 23, c, 8);
        shape(37, 23, c, 16);
    }
    shape(600, 700, 3, 8);   /* 5 stripes of 145 rows, 19 priming rows */
    shape(1500, 300, 4, 16); /* 15 stripes of 21 rows, 3 priming rows */
    shape(12000, 40, 3, 8);  /* 6 stripes of 7 rows, the priming inside a row */
    shape(16384, 9, 4, 16);  /* the widest row: 9 stripes of 1 row */
    refused(NULL, 1, 1, 1, 8, "NULL pixels");
    refused(one, 0, 1, 1, 8, "width 0");
    refused(one, 1, RELIEF_PNG_MAX_SIDE + 1, 1, 8, "height past the maximum");
    refused(one, 1, 1, 5, 8, "5 channels");
    refused(one, 1, 1, 3, 12, "12 bits");
    return check_result();
}
