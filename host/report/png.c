#include "report/png.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "base/atomic.h"
#include "base/error.h"

static void put_be32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v >> 24);
    p[1] = (uint8_t)(v >> 16);
    p[2] = (uint8_t)(v >> 8);
    p[3] = (uint8_t)v;
}

/* One chunk at *p: length, type, data, CRC over type and data. */
static uint8_t *put_chunk(uint8_t *p, const char type[4], const uint8_t *data, uint32_t n)
{
    uLong crc;
    put_be32(p, n);
    memcpy(p + 4, type, 4);
    if (n)
        memcpy(p + 8, data, n);
    crc = crc32(0L, p + 4, n + 4);
    put_be32(p + 8 + n, (uint32_t)crc);
    return p + 12 + n;
}

static uint8_t paeth(int a, int b, int c)
{
    int p = a + b - c, pa = abs(p - a), pb = abs(p - b), pc = abs(p - c);
    return (uint8_t)(pa <= pb && pa <= pc ? a : pb <= pc ? b : c);
}

/* Filter one row with each of the five PNG filters and keep the one whose
 * bytes, read as signed, have the smallest absolute sum (the heuristic the
 * PNG specification recommends); rendered images with flat backgrounds and
 * smooth shading then compress several times better than unfiltered. */
static void filter_row(const uint8_t *row, const uint8_t *prev, size_t n, uint8_t *out,
                       uint8_t *scratch)
{
    unsigned long best_sum = (unsigned long)-1;
    for (int f = 0; f < 5; ++f) {
        unsigned long sum = 0;
        for (size_t i = 0; i < n; ++i) {
            int a = i >= 3 ? row[i - 3] : 0, b = prev ? prev[i] : 0,
                c = prev && i >= 3 ? prev[i - 3] : 0, x = row[i];
            uint8_t v;
            switch (f) {
            case 0: v = (uint8_t)x; break;
            case 1: v = (uint8_t)(x - a); break;
            case 2: v = (uint8_t)(x - b); break;
            case 3: v = (uint8_t)(x - ((a + b) >> 1)); break;
            default: v = (uint8_t)(x - paeth(a, b, c)); break;
            }
            scratch[i] = v;
            sum += v < 128 ? v : 256u - v;
        }
        if (sum < best_sum) {
            best_sum = sum;
            out[0] = (uint8_t)f;
            memcpy(out + 1, scratch, n);
        }
    }
}

relief_status relief_png_encode(const uint8_t *rgb, int width, int height, uint8_t **out,
                                size_t *n, relief_error *err)
{
    static const uint8_t signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    uint8_t ihdr[13], *raw = NULL, *z = NULL, *png = NULL, *scratch = NULL, *p;
    size_t stride, raw_n;
    uLongf z_n;
    relief_status st = RELIEF_OK;

    if (!rgb || !out || !n)
        return relief_fail(err, RELIEF_E_USAGE, "relief_png_encode: NULL argument");
    if (width < 1 || height < 1 || width > RELIEF_PNG_MAX_SIDE || height > RELIEF_PNG_MAX_SIDE)
        return relief_fail(err, RELIEF_E_USAGE,
                           "image size %dx%d is out of range: expected 1..%d per side", width,
                           height, RELIEF_PNG_MAX_SIDE);
    stride = (size_t)width * 3;
    raw_n = (stride + 1) * (size_t)height;
    raw = malloc(raw_n);
    scratch = malloc(stride);
    z_n = compressBound((uLong)raw_n);
    z = malloc(z_n);
    if (!raw || !scratch || !z) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a %dx%d PNG", width, height);
        goto done;
    }
    for (int y = 0; y < height; ++y)
        filter_row(rgb + (size_t)y * stride, y ? rgb + (size_t)(y - 1) * stride : NULL, stride,
                   raw + (size_t)y * (stride + 1), scratch);
    if (compress2(z, &z_n, raw, (uLong)raw_n, 6) != Z_OK) {
        st = relief_fail(err, RELIEF_E_INTERNAL, "zlib could not compress a %dx%d image",
                         width, height);
        goto done;
    }
    /* signature, IHDR (13), IDAT, IEND: three chunks of 12 bytes' framing */
    png = malloc(8 + 3 * 12 + 13 + (size_t)z_n);
    if (!png) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a %dx%d PNG", width, height);
        goto done;
    }
    put_be32(ihdr, (uint32_t)width);
    put_be32(ihdr + 4, (uint32_t)height);
    ihdr[8] = 8;  /* bit depth */
    ihdr[9] = 2;  /* colour type: RGB */
    ihdr[10] = 0; /* deflate */
    ihdr[11] = 0; /* adaptive filtering */
    ihdr[12] = 0; /* no interlace */
    memcpy(png, signature, 8);
    p = put_chunk(png + 8, "IHDR", ihdr, 13);
    p = put_chunk(p, "IDAT", z, (uint32_t)z_n);
    p = put_chunk(p, "IEND", NULL, 0);
    *out = png;
    *n = (size_t)(p - png);
    png = NULL;
done:
    free(png);
    free(z);
    free(scratch);
    free(raw);
    return st;
}

relief_status relief_png_write(const char *path, const uint8_t *rgb, int width, int height,
                               relief_error *err)
{
    uint8_t *png = NULL;
    size_t n = 0;
    char *tmp = NULL;
    FILE *f;
    relief_status st;

    if (!path)
        return relief_fail(err, RELIEF_E_USAGE, "relief_png_write: NULL path");
    st = relief_png_encode(rgb, width, height, &png, &n, err);
    if (st == RELIEF_OK)
        st = relief_atomic_create(path, &tmp, err);
    if (st == RELIEF_OK) {
        int ok;
        f = fopen(tmp, "wb");
        ok = f != NULL;
        if (f) {
            ok = fwrite(png, 1, n, f) == n;
            ok = fclose(f) == 0 && ok;
        }
        if (!ok) {
            st = relief_fail(err, RELIEF_E_IO, "%s: cannot write the image", path);
            relief_atomic_abort(tmp);
        } else {
            st = relief_atomic_commit(tmp, path, err);
        }
    }
    free(png);
    return st;
}
