/* A PNG decoder of the tests' own, apart from libpng, for what relief's
 * writer (host/report/png.c) writes: non-interlaced grey, grey + alpha,
 * RGB or RGBA of 8 or 16 bits. Every chunk's CRC is checked, the IDATs
 * are joined and inflated by zlib in one call (so the stream's adler32 is
 * checked too, which libpng only warns about), and the five filters are
 * undone. */
#ifndef RELIEF_TESTS_PNG_DECODE_H
#define RELIEF_TESTS_PNG_DECODE_H

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

typedef struct png_decoded {
    int width, height, channels, depth;
    size_t idat_chunks;
    uint8_t *samples; /* rows packed, 16 bits big endian, as the file has them */
} png_decoded;

static uint32_t png_be32(const uint8_t *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

static int png_paeth(int a, int b, int c)
{
    int p = a + b - c, pa = abs(p - a), pb = abs(p - b), pc = abs(p - c);
    return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

/* The header's shape into *d; NULL, or what is wrong. */
static const char *png_ihdr(const uint8_t *data, uint32_t len, png_decoded *d)
{
    static const int channels[7] = {1, 0, 3, 0, 2, 0, 4}; /* by colour type */
    if (len != 13 || (data[8] != 8 && data[8] != 16) || data[9] > 6 || !channels[data[9]] ||
        data[10] || data[11] || data[12])
        return "IHDR is not 8 or 16 bits of grey, grey + alpha, RGB or RGBA, deflate, not "
               "interlaced";
    d->width = (int)png_be32(data);
    d->height = (int)png_be32(data + 4);
    d->depth = data[8];
    d->channels = channels[data[9]];
    return NULL;
}

/* The rows of `raw` (filter byte, then stride bytes each) unfiltered into
 * d->samples; NULL, or what is wrong. */
static const char *png_unfilter(const uint8_t *raw, size_t stride, size_t bpp, png_decoded *d)
{
    for (int y = 0; y < d->height; ++y) {
        const uint8_t *in = raw + (size_t)y * (stride + 1);
        uint8_t *row = d->samples + (size_t)y * stride, *prev = y ? row - stride : NULL;
        for (size_t i = 0; i < stride; ++i) {
            int a = i >= bpp ? row[i - bpp] : 0, b = prev ? prev[i] : 0,
                c = prev && i >= bpp ? prev[i - bpp] : 0, x = in[1 + i];
            switch (in[0]) {
            case 0: row[i] = (uint8_t)x; break;
            case 1: row[i] = (uint8_t)(x + a); break;
            case 2: row[i] = (uint8_t)(x + b); break;
            case 3: row[i] = (uint8_t)(x + ((a + b) >> 1)); break;
            case 4: row[i] = (uint8_t)(x + png_paeth(a, b, c)); break;
            default: return "unknown filter type";
            }
        }
    }
    return NULL;
}

/* Decode the n bytes of png into *d (d->samples malloc'ed). Returns NULL
 * on success, else what is wrong (and d->samples NULL). */
static const char *png_decode_all(const uint8_t *png, size_t n, png_decoded *d)
{
    static const uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    uint8_t *z = NULL, *raw = NULL;
    size_t zn = 0, pos = 8, stride = 0, bpp = 0;
    uLongf raw_n = 0;
    int seen_iend = 0;
    const char *why = NULL;

    memset(d, 0, sizeof *d);
    if (n < 8 || memcmp(png, sig, 8) != 0)
        return "bad signature";
    while (!why && pos + 12 <= n && !seen_iend) {
        uint32_t len = png_be32(png + pos);
        const uint8_t *type = png + pos + 4, *data = png + pos + 8;
        if (pos + 12 + (size_t)len > n)
            why = "chunk runs past the end";
        else if ((uint32_t)crc32(0L, type, len + 4) != png_be32(data + len))
            why = "chunk CRC mismatch";
        else if (memcmp(type, "IHDR", 4) == 0)
            why = png_ihdr(data, len, d);
        else if (memcmp(type, "IDAT", 4) == 0) {
            uint8_t *grown = realloc(z, zn + len + 1);
            if (!grown)
                why = "out of memory";
            else {
                z = grown;
                memcpy(z + zn, data, len);
                zn += len;
                ++d->idat_chunks;
            }
        } else if (memcmp(type, "IEND", 4) == 0)
            seen_iend = 1;
        pos += 12 + (size_t)len;
    }
    if (!why && (!d->channels || !seen_iend || !z || d->width < 1 || d->height < 1))
        why = "missing IHDR, IDAT or IEND";
    if (!why) {
        bpp = (size_t)d->channels * (size_t)d->depth / 8;
        stride = (size_t)d->width * bpp;
        raw_n = (uLongf)((stride + 1) * (size_t)d->height);
        raw = malloc(raw_n);
        d->samples = malloc(stride * (size_t)d->height);
        if (!raw || !d->samples)
            why = "out of memory";
        else if (uncompress(raw, &raw_n, z, (uLong)zn) != Z_OK ||
                 raw_n != (stride + 1) * (size_t)d->height)
            why = "the IDATs do not inflate (adler32 checked) to the image's size";
    }
    if (!why)
        why = png_unfilter(raw, stride, bpp, d);
    free(z);
    free(raw);
    if (why) {
        free(d->samples);
        d->samples = NULL;
    }
    return why;
}

#endif
