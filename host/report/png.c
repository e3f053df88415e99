#include "report/png.h"

#include <png.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/atomic.h"
#include "base/error.h"

/* libpng writes into a growing buffer; its errors come back by longjmp
 * into encode(), with what it allocated kept here. */
typedef struct png_buffer {
    jmp_buf jump;
    char msg[256];
    uint8_t *data;
    size_t n, cap;
    int out_of_memory;
} png_buffer;

static void on_error(png_structp png, png_const_charp msg)
{
    png_buffer *b = png_get_error_ptr(png);
    snprintf(b->msg, sizeof b->msg, "%s", msg);
    longjmp(b->jump, 1);
}

static void on_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg;
}

static void on_write(png_structp png, png_bytep data, size_t len)
{
    png_buffer *b = png_get_io_ptr(png);
    if (len > b->cap - b->n) {
        size_t cap = b->cap ? b->cap : 1 << 16;
        uint8_t *grown;
        while (cap - b->n < len)
            cap *= 2;
        grown = realloc(b->data, cap);
        if (!grown) {
            b->out_of_memory = 1;
            png_error(png, "out of memory");
        }
        b->data = grown;
        b->cap = cap;
    }
    memcpy(b->data + b->n, data, len);
    b->n += len;
}

static void on_flush(png_structp png) { (void)png; }

relief_status relief_png_encode_pixels(const uint8_t *pixels, int width, int height,
                                       int channels, int bit_depth, uint8_t **out, size_t *n,
                                       relief_error *err)
{
    static const int types[5] = {0, PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA,
                                 PNG_COLOR_TYPE_RGB, PNG_COLOR_TYPE_RGB_ALPHA};
    png_buffer b;
    png_structp png;
    png_infop info;
    size_t stride = (size_t)width * channels * (bit_depth == 16 ? 2 : 1);

    if (!pixels || !out || !n)
        return relief_fail(err, RELIEF_E_USAGE, "relief_png_encode: NULL argument");
    if (width < 1 || height < 1 || width > RELIEF_PNG_MAX_SIDE || height > RELIEF_PNG_MAX_SIDE)
        return relief_fail(err, RELIEF_E_USAGE,
                           "image size %dx%d is out of range: expected 1..%d per side", width,
                           height, RELIEF_PNG_MAX_SIDE);
    if (channels < 1 || channels > 4 || (bit_depth != 8 && bit_depth != 16))
        return relief_fail(err, RELIEF_E_USAGE, "a PNG of %d channels of %d bits: expected "
                           "1..4 channels of 8 or 16", channels, bit_depth);
    memset(&b, 0, sizeof b);
    png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &b, on_error, on_warning);
    info = png ? png_create_info_struct(png) : NULL;
    if (!png || !info) {
        png_destroy_write_struct(png ? &png : NULL, NULL);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot start libpng");
    }
    if (setjmp(b.jump)) {
        png_destroy_write_struct(&png, &info);
        free(b.data);
        if (b.out_of_memory)
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a %dx%d PNG", width,
                               height);
        return relief_fail(err, RELIEF_E_INTERNAL, "libpng could not encode a %dx%d image: %s",
                           width, height, b.msg);
    }
    png_set_write_fn(png, &b, on_write, on_flush);
    png_set_IHDR(png, info, (png_uint_32)width, (png_uint_32)height, bit_depth,
                 types[channels], PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = 0; y < height; ++y)
        png_write_row(png, pixels + (size_t)y * stride);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    *out = b.data;
    *n = b.n;
    return RELIEF_OK;
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
