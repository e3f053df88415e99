#include "report/png.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "base/output.h"
#include "base/error.h"
#include "base/parallel.h"
#include "base/pool.h"

/* The encoder is relief's own, around zlib, so that it can use every core.
 * The rows are cut into stripes of about STRIPE_BYTES, and each stripe is
 * one task: its rows filtered and deflated, primed with the 32 KiB of
 * filtered rows before it (refiltered there: a filter reads only the raw
 * rows), and ended on a byte boundary (Z_SYNC_FLUSH), as pigz does, so
 * that the stripes join into one zlib stream; each becomes an IDAT chunk.
 * The stripes are cut by the image's size alone: the bytes do not depend
 * on the number of threads. The memory is twice the file's (the stripes,
 * then the file they are joined into) and, a thread, a stripe's. Each row takes the filter that minimises the sum of its bytes
 * read as signed, the heuristic of the PNG specification and of libpng;
 * zlib runs at its default level with the Z_FILTERED strategy, as libpng
 * does. */
#define STRIPE_BYTES ((size_t)1 << 18)
#define WINDOW_BYTES ((size_t)1 << 15)

/* One stripe's deflated bytes, the adler32 of its filtered rows, and how
 * its task ended: 0, ENCODE_ZLIB or ENCODE_MEMORY (each task writes only
 * its own stripes). */
typedef struct stripe {
    uint8_t *data;
    size_t n, cap;
    uLong adler;
    int status;
} stripe;

enum { ENCODE_ZLIB = 1, ENCODE_MEMORY = 2 };

typedef struct encode_job {
    const uint8_t *pixels;
    size_t stride;      /* bytes of a row of samples */
    size_t bpp;         /* bytes of a pixel (at least 1) */
    size_t rows;        /* rows of the image */
    size_t stripe_rows; /* rows of a stripe (the last may have fewer) */
    size_t prime_rows;  /* rows above a stripe that hold its 32 KiB of priming */
    size_t n_stripes;
    stripe *stripes;
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

/* Rows [lo, hi), each with its best filter, into out: (hi - lo) rows of
 * the filter type and stride bytes. trial: stride bytes of scratch;
 * zeros: stride zero bytes, the row above the first. */
static void filter_rows(const encode_job *j, size_t lo, size_t hi, uint8_t *out,
                        uint8_t *trial, const uint8_t *zeros)
{
    for (size_t y = lo; y < hi; ++y, out += j->stride + 1) {
        const uint8_t *cur = j->pixels + y * j->stride, *up = y ? cur - j->stride : zeros;
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
}

/* deflate with `flush` until it is done, into s's buffer (first of
 * deflateBound's size, doubled should that fall short): 0, ENCODE_ZLIB
 * or ENCODE_MEMORY. */
static int deflate_into(z_stream *z, stripe *s, int flush)
{
    size_t first = deflateBound(z, z->avail_in) + 64; /* a sync flush's few bytes too */
    for (;;) {
        int rc;
        if (s->n == s->cap) {
            size_t cap = s->cap ? 2 * s->cap : first;
            uint8_t *grown = realloc(s->data, cap);
            if (!grown)
                return ENCODE_MEMORY;
            s->data = grown, s->cap = cap;
        }
        z->next_out = s->data + s->n;
        z->avail_out = (uInt)(s->cap - s->n);
        rc = deflate(z, flush);
        s->n = s->cap - z->avail_out;
        if (flush == Z_FINISH ? rc == Z_STREAM_END : rc == Z_OK && z->avail_out > 0)
            return 0;
        if ((rc != Z_OK && rc != Z_BUF_ERROR) || z->avail_out > 0) /* no progress */
            return ENCODE_ZLIB;
    }
}

/* Stripe k filtered (buf: its rows and the priming rows above) and
 * deflated into j->stripes[k], its status set; 0, or 1 when it failed. */
static int encode_stripe(encode_job *j, size_t k, uint8_t *buf, uint8_t *trial,
                         const uint8_t *zeros)
{
    size_t row = j->stride + 1, lo = k * j->stripe_rows;
    size_t hi = lo + j->stripe_rows > j->rows ? j->rows : lo + j->stripe_rows;
    size_t pre = lo < j->prime_rows ? lo : j->prime_rows, len = (hi - lo) * row;
    size_t dict = pre * row < WINDOW_BYTES ? pre * row : WINDOW_BYTES;
    const uint8_t *in = buf + pre * row;
    stripe *s = &j->stripes[k];
    z_stream z;
    int rc;

    filter_rows(j, lo - pre, hi, buf, trial, zeros);
    s->adler = adler32(1L, in, (uInt)len);
    memset(&z, 0, sizeof z);
    rc = deflateInit2(&z, Z_DEFAULT_COMPRESSION, Z_DEFLATED, -15, 8, Z_FILTERED);
    if (rc != Z_OK) {
        s->status = rc == Z_MEM_ERROR ? ENCODE_MEMORY : ENCODE_ZLIB;
        return 1;
    }
    rc = dict ? deflateSetDictionary(&z, in - dict, (uInt)dict) : Z_OK;
    z.next_in = (uint8_t *)in;
    z.avail_in = (uInt)len;
    s->status = rc != Z_OK ? ENCODE_ZLIB
                           : deflate_into(&z, s, k + 1 == j->n_stripes ? Z_FINISH : Z_SYNC_FLUSH);
    deflateEnd(&z);
    if (s->status == 0 && s->n < s->cap) { /* give back what deflateBound kept */
        uint8_t *fit = realloc(s->data, s->n);
        s->data = fit ? fit : s->data;
    }
    return s->status != 0;
}

/* Stripes [lo, hi), for relief_parallel_ranges. */
static int encode_stripes(void *ctx, size_t lo, size_t hi)
{
    encode_job *j = ctx;
    uint8_t *buf = malloc((j->prime_rows + j->stripe_rows) * (j->stride + 1));
    uint8_t *trial = malloc(j->stride), *zeros = calloc(j->stride, 1);
    int failed = !buf || !trial || !zeros;
    if (failed)
        j->stripes[lo].status = ENCODE_MEMORY;
    for (size_t k = lo; k < hi && !failed; ++k)
        failed = encode_stripe(j, k, buf, trial, zeros);
    free(buf), free(trial), free(zeros);
    return failed;
}

static void put32(uint8_t *b, uint32_t v)
{
    b[0] = (uint8_t)(v >> 24), b[1] = (uint8_t)(v >> 16), b[2] = (uint8_t)(v >> 8);
    b[3] = (uint8_t)v;
}

/* The chunk begun at `start` (its data written from start + 8 to `end`):
 * its length, its type and, after the data, its CRC; returns the byte
 * after it. */
static uint8_t *end_chunk(uint8_t *start, const char *type, uint8_t *end)
{
    size_t len = (size_t)(end - start) - 8;
    put32(start, (uint32_t)len);
    memcpy(start + 4, type, 4);
    put32(end, (uint32_t)crc32(crc32(0L, Z_NULL, 0), start + 4, (uInt)(len + 4)));
    return end + 4;
}

/* The file: signature, IHDR, an IDAT a stripe (the first led by the zlib
 * header, the last followed by the adler32 of all filtered bytes), IEND. */
static uint8_t *assemble(const encode_job *j, const uint8_t ihdr[13], size_t *n)
{
    static const uint8_t signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    size_t total = 8 + 25 + 2 + 4 + 12;
    uLong adler = 1L;
    uint8_t *file, *o;
    for (size_t k = 0; k < j->n_stripes; ++k) {
        size_t rows = (k + 1 == j->n_stripes ? j->rows : (k + 1) * j->stripe_rows) -
                      k * j->stripe_rows;
        total += 12 + j->stripes[k].n;
        adler = k ? adler32_combine(adler, j->stripes[k].adler,
                                    (z_off_t)(rows * (j->stride + 1)))
                  : j->stripes[k].adler;
    }
    if (!(file = malloc(total)))
        return NULL;
    memcpy(file, signature, 8);
    memcpy(file + 16, ihdr, 13);
    o = end_chunk(file + 8, "IHDR", file + 16 + 13);
    for (size_t k = 0; k < j->n_stripes; ++k) {
        uint8_t *start = o, *d = o + 8;
        if (k == 0)
            *d++ = 0x78, *d++ = 0x9c; /* deflate, 32 KiB window, default level */
        memcpy(d, j->stripes[k].data, j->stripes[k].n);
        d += j->stripes[k].n;
        if (k + 1 == j->n_stripes)
            put32(d, (uint32_t)adler), d += 4;
        o = end_chunk(start, "IDAT", d);
    }
    o = end_chunk(o, "IEND", o + 8);
    *n = (size_t)(o - file);
    return file;
}

static relief_status encode(encode_job *j, const uint8_t ihdr[13], int threads, uint8_t **out,
                            size_t *n, relief_error *err)
{
    size_t row = j->stride + 1;
    uint8_t *file = NULL;
    int status = 0;
    j->stripe_rows = STRIPE_BYTES / row ? STRIPE_BYTES / row : 1;
    j->prime_rows = (WINDOW_BYTES + row - 1) / row;
    j->n_stripes = (j->rows + j->stripe_rows - 1) / j->stripe_rows;
    j->stripes = calloc(j->n_stripes, sizeof *j->stripes);
    if (!j->stripes)
        status = ENCODE_MEMORY;
    else if (relief_parallel_ranges(j->n_stripes, threads, encode_stripes, j))
        for (size_t k = 0; k < j->n_stripes; ++k)
            status = status ? status : j->stripes[k].status;
    if (status == 0 && !(file = assemble(j, ihdr, n)))
        status = ENCODE_MEMORY;
    for (size_t k = 0; j->stripes && k < j->n_stripes; ++k)
        free(j->stripes[k].data);
    free(j->stripes);
    if (status == 0) {
        *out = file;
        return RELIEF_OK;
    }
    if (status == ENCODE_MEMORY)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a %zu x %zu PNG",
                           j->stride / j->bpp, j->rows);
    return relief_fail(err, RELIEF_E_INTERNAL, "zlib could not compress a %zu x %zu image",
                       j->stride / j->bpp, j->rows);
}

relief_status relief_png_encode_pixels(const uint8_t *pixels, int width, int height,
                                       int channels, int bit_depth, uint8_t **out, size_t *n,
                                       relief_error *err)
{
    return relief_png_encode_threads(pixels, width, height, channels, bit_depth,
                                     relief_pool_default_threads(), out, n, err);
}

relief_status relief_png_encode_threads(const uint8_t *pixels, int width, int height,
                                        int channels, int bit_depth, int threads, uint8_t **out,
                                        size_t *n, relief_error *err)
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
    return encode(&j, ihdr, threads, out, n, err);
}

relief_status relief_png_encode(const uint8_t *rgb, int width, int height, uint8_t **out,
                                size_t *n, relief_error *err)
{
    return relief_png_encode_pixels(rgb, width, height, 3, 8, out, n, err);
}

/* Encode, then write into a sink (to), a file inside a staged folder
 * (plain: shown names it) or a file on its own. */
static relief_status png_out(const char *path, relief_sink *to, const char *shown,
                             const uint8_t *rgb, int width, int height, relief_error *err)
{
    relief_bytes b = {NULL, 0};
    uint8_t *png = NULL;
    relief_status st = relief_png_encode(rgb, width, height, &png, &b.n, err);
    b.data = png;
    if (st == RELIEF_OK)
        st = to ? relief_sink_bytes(to, &b, err)
             : shown ? relief_output_plain(path, shown, relief_sink_bytes, &b, err)
                     : relief_output_file(path, relief_sink_bytes, &b, err);
    free(png);
    return st;
}

relief_status relief_png_write(const char *path, const uint8_t *rgb, int width, int height,
                               relief_error *err)
{
    if (!path)
        return relief_fail(err, RELIEF_E_USAGE, "relief_png_write: NULL path");
    return png_out(path, NULL, NULL, rgb, width, height, err);
}

relief_status relief_png_write_to(relief_sink *s, const uint8_t *rgb, int width, int height,
                                  relief_error *err)
{
    return png_out(NULL, s, NULL, rgb, width, height, err);
}

relief_status relief_png_write_plain(const char *path, const char *shown, const uint8_t *rgb,
                                     int width, int height, relief_error *err)
{
    return png_out(path, NULL, shown, rgb, width, height, err);
}
