#include "report/png.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "base/atomic.h"
#include "base/error.h"
#include "base/parallel.h"
#include "base/pool.h"

/* The encoder is relief's own, around zlib, so that it can use every core:
 * the rows are filtered in parallel, then deflated in stripes of about
 * STRIPE_BYTES, each primed with the 32 KiB of filtered bytes before it
 * and ended on a byte boundary (Z_SYNC_FLUSH), as pigz does, so that the
 * stripes join into one zlib stream. The stripes are cut by the image's
 * size alone: the bytes do not depend on the number of threads. Each row
 * takes the filter that minimises the sum of its bytes read as signed,
 * the heuristic of the PNG specification and of libpng; zlib runs at its
 * default level with the Z_FILTERED strategy, as libpng does. */
#define STRIPE_BYTES ((size_t)1 << 18)
#define WINDOW_BYTES ((size_t)1 << 15)
#define IDAT_BYTES ((size_t)1 << 20)

/* One stripe's deflated bytes and the adler32 of its filtered rows. */
typedef struct stripe {
    uint8_t *data;
    size_t n;
    uLong adler;
} stripe;

typedef struct encode_job {
    const uint8_t *pixels;
    size_t stride; /* bytes of a row of samples */
    size_t bpp;    /* bytes of a pixel (at least 1) */
    size_t rows;   /* rows of the image */
    uint8_t *filtered; /* rows x (1 + stride): each row's filter type, then its bytes */
    size_t stripe_rows;
    size_t n_stripes;
    stripe *stripes;
    int out_of_memory;
} encode_job;

static inline uint8_t paeth(int a, int b, int c)
{
    int pa = abs(b - c), pb = abs(a - c), pc = abs(a + b - 2 * c);
    return (uint8_t)(pa <= pb && pa <= pc ? a : pb <= pc ? b : c);
}

/* Row `cur` (above it `up`, zeros for the first row) filtered by `type`
 * (1 sub, 2 up, 3 average, 4 Paeth) into `out`. */
static void filter_row(int type, const uint8_t *cur, const uint8_t *up, size_t len,
                       size_t bpp, uint8_t *out)
{
    size_t i;
    for (i = 0; i < bpp; ++i) /* no left neighbour */
        out[i] = (uint8_t)(cur[i] - (type == 2 || type == 4 ? up[i] : type == 3 ? up[i] / 2 : 0));
    switch (type) {
    case 1:
        for (; i < len; ++i)
            out[i] = (uint8_t)(cur[i] - cur[i - bpp]);
        break;
    case 2:
        for (; i < len; ++i)
            out[i] = (uint8_t)(cur[i] - up[i]);
        break;
    case 3:
        for (; i < len; ++i)
            out[i] = (uint8_t)(cur[i] - (uint8_t)(((unsigned)cur[i - bpp] + up[i]) >> 1));
        break;
    default:
        for (; i < len; ++i)
            out[i] = (uint8_t)(cur[i] - paeth(cur[i - bpp], up[i], up[i - bpp]));
        break;
    }
}

/* The sum of the bytes read as signed: the PNG specification's measure
 * of how well a filter predicted a row. */
static unsigned long signed_sum(const uint8_t *b, size_t len)
{
    unsigned long sum = 0;
    for (size_t i = 0; i < len; ++i)
        sum += (unsigned)abs((int8_t)b[i]);
    return sum;
}

/* Rows [lo, hi), each with its best filter, for relief_parallel_ranges. */
static int filter_rows(void *ctx, size_t lo, size_t hi)
{
    encode_job *j = ctx;
    uint8_t *trial = malloc(j->stride), *zeros = calloc(j->stride, 1);
    if (!trial || !zeros) {
        free(trial), free(zeros);
        j->out_of_memory = 1;
        return 1;
    }
    for (size_t y = lo; y < hi; ++y) {
        const uint8_t *cur = j->pixels + y * j->stride, *up = y ? cur - j->stride : zeros;
        uint8_t *out = j->filtered + y * (j->stride + 1);
        unsigned long best = signed_sum(cur, j->stride);
        out[0] = 0;
        memcpy(out + 1, cur, j->stride);
        for (int type = 1; type <= 4 && best > 0; ++type) {
            unsigned long sum;
            filter_row(type, cur, up, j->stride, j->bpp, trial);
            sum = signed_sum(trial, j->stride);
            if (sum < best) {
                best = sum;
                out[0] = (uint8_t)type;
                memcpy(out + 1, trial, j->stride);
            }
        }
    }
    free(trial), free(zeros);
    return 0;
}

/* Stripe k deflated into j->stripes[k]; 0, or 1 when zlib failed. */
static int deflate_stripe(encode_job *j, size_t k)
{
    size_t row = j->stride + 1, lo = k * j->stripe_rows * row;
    size_t hi = (k + 1) * j->stripe_rows * row, all = j->rows * row;
    size_t dict = lo < WINDOW_BYTES ? lo : WINDOW_BYTES, cap;
    stripe *s = &j->stripes[k];
    z_stream z;
    int last = k + 1 == j->n_stripes, rc;

    hi = hi > all ? all : hi;
    memset(&z, 0, sizeof z);
    if (deflateInit2(&z, Z_DEFAULT_COMPRESSION, Z_DEFLATED, -15, 8, Z_FILTERED) != Z_OK) {
        j->out_of_memory = 1;
        return 1;
    }
    rc = dict ? deflateSetDictionary(&z, j->filtered + lo - dict, (uInt)dict) : Z_OK;
    cap = deflateBound(&z, (uLong)(hi - lo)) + 16;
    s->data = rc == Z_OK ? malloc(cap) : NULL;
    if (!s->data) {
        deflateEnd(&z);
        j->out_of_memory = rc == Z_OK;
        return 1;
    }
    z.next_in = j->filtered + lo;
    z.avail_in = (uInt)(hi - lo);
    z.next_out = s->data;
    z.avail_out = (uInt)cap;
    rc = deflate(&z, last ? Z_FINISH : Z_SYNC_FLUSH);
    s->n = cap - z.avail_out;
    s->adler = adler32(1L, j->filtered + lo, (uInt)(hi - lo));
    deflateEnd(&z);
    return (last ? rc != Z_STREAM_END : rc != Z_OK || z.avail_out == 0) || z.avail_in != 0;
}

static int deflate_stripes(void *ctx, size_t lo, size_t hi)
{
    int failed = 0;
    for (size_t k = lo; k < hi && !failed; ++k)
        failed = deflate_stripe(ctx, k);
    return failed;
}

static void put32(uint8_t *b, uint32_t v)
{
    b[0] = (uint8_t)(v >> 24), b[1] = (uint8_t)(v >> 16), b[2] = (uint8_t)(v >> 8);
    b[3] = (uint8_t)v;
}

/* A chunk of `type` holding `len` bytes (from `data`, or already at
 * o + 8 when data is NULL) written at o; returns the bytes after it. */
static uint8_t *put_chunk(uint8_t *o, const char *type, const uint8_t *data, size_t len)
{
    put32(o, (uint32_t)len);
    memcpy(o + 4, type, 4);
    if (data && len)
        memcpy(o + 8, data, len);
    put32(o + 8 + len, (uint32_t)crc32(crc32(0L, Z_NULL, 0), o + 4, (uInt)(len + 4)));
    return o + 12 + len;
}

/* The file: signature, IHDR, the zlib stream (2-byte header, the stripes,
 * the adler32 of all filtered bytes) in IDAT chunks of at most IDAT_BYTES,
 * IEND. */
static uint8_t *assemble(const encode_job *j, const uint8_t ihdr[13], size_t *n)
{
    static const uint8_t signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    size_t zn = 6, at = 0, total;
    uint8_t *zs, *file, *o;
    uLong adler = 1L;
    for (size_t k = 0; k < j->n_stripes; ++k)
        zn += j->stripes[k].n;
    zs = malloc(zn);
    total = 8 + 25 + zn + 12 * (zn / IDAT_BYTES + 1) + 12;
    file = zs ? malloc(total) : NULL;
    if (!file) {
        free(zs);
        return NULL;
    }
    zs[at++] = 0x78, zs[at++] = 0x9c; /* deflate, 32 KiB window, default level */
    for (size_t k = 0; k < j->n_stripes; ++k) {
        size_t len = (k + 1 == j->n_stripes ? j->rows : (k + 1) * j->stripe_rows) -
                     k * j->stripe_rows;
        memcpy(zs + at, j->stripes[k].data, j->stripes[k].n);
        at += j->stripes[k].n;
        adler = k ? adler32_combine(adler, j->stripes[k].adler, (z_off_t)(len * (j->stride + 1)))
                  : j->stripes[k].adler;
    }
    put32(zs + at, (uint32_t)adler);
    memcpy(file, signature, 8);
    o = put_chunk(file + 8, "IHDR", ihdr, 13);
    for (size_t off = 0; off < zn; off += IDAT_BYTES)
        o = put_chunk(o, "IDAT", zs + off, zn - off < IDAT_BYTES ? zn - off : IDAT_BYTES);
    o = put_chunk(o, "IEND", NULL, 0);
    free(zs);
    *n = (size_t)(o - file);
    return file;
}

static relief_status encode(encode_job *j, const uint8_t ihdr[13], uint8_t **out, size_t *n,
                            relief_error *err)
{
    int threads = relief_pool_default_threads(), failed;
    j->stripe_rows = STRIPE_BYTES / (j->stride + 1);
    j->stripe_rows = j->stripe_rows ? j->stripe_rows : 1;
    j->n_stripes = (j->rows + j->stripe_rows - 1) / j->stripe_rows;
    j->filtered = malloc(j->rows * (j->stride + 1));
    j->stripes = calloc(j->n_stripes, sizeof *j->stripes);
    failed = !j->filtered || !j->stripes;
    j->out_of_memory = failed;
    if (!failed)
        failed = relief_parallel_ranges(j->rows, threads, filter_rows, j);
    if (!failed)
        failed = relief_parallel_ranges(j->n_stripes, threads, deflate_stripes, j);
    if (!failed) {
        *out = assemble(j, ihdr, n);
        failed = j->out_of_memory = *out == NULL;
    }
    for (size_t k = 0; j->stripes && k < j->n_stripes; ++k)
        free(j->stripes[k].data);
    free(j->stripes);
    free(j->filtered);
    if (!failed)
        return RELIEF_OK;
    if (j->out_of_memory)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a %zu x %zu PNG",
                           j->stride / j->bpp, j->rows);
    return relief_fail(err, RELIEF_E_INTERNAL, "zlib could not compress a %zu x %zu image",
                       j->stride / j->bpp, j->rows);
}

relief_status relief_png_encode_pixels(const uint8_t *pixels, int width, int height,
                                       int channels, int bit_depth, uint8_t **out, size_t *n,
                                       relief_error *err)
{
    static const uint8_t types[5] = {0, 0, 4, 2, 6}; /* grey, grey + alpha, RGB, RGBA */
    uint8_t ihdr[13];
    encode_job j;

    if (!pixels || !out || !n)
        return relief_fail(err, RELIEF_E_USAGE, "relief_png_encode: NULL argument");
    if (width < 1 || height < 1 || width > RELIEF_PNG_MAX_SIDE || height > RELIEF_PNG_MAX_SIDE)
        return relief_fail(err, RELIEF_E_USAGE,
                           "image size %dx%d is out of range: expected 1..%d per side", width,
                           height, RELIEF_PNG_MAX_SIDE);
    if (channels < 1 || channels > 4 || (bit_depth != 8 && bit_depth != 16))
        return relief_fail(err, RELIEF_E_USAGE, "a PNG of %d channels of %d bits: expected "
                           "1..4 channels of 8 or 16", channels, bit_depth);
    memset(&j, 0, sizeof j);
    j.pixels = pixels;
    j.bpp = (size_t)channels * (bit_depth / 8);
    j.stride = (size_t)width * j.bpp;
    j.rows = (size_t)height;
    put32(ihdr, (uint32_t)width);
    put32(ihdr + 4, (uint32_t)height);
    ihdr[8] = (uint8_t)bit_depth, ihdr[9] = types[channels];
    ihdr[10] = ihdr[11] = ihdr[12] = 0; /* deflate, adaptive filtering, not interlaced */
    return encode(&j, ihdr, out, n, err);
}

relief_status relief_png_encode(const uint8_t *rgb, int width, int height, uint8_t **out,
                                size_t *n, relief_error *err)
{
    return relief_png_encode_pixels(rgb, width, height, 3, 8, out, n, err);
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
