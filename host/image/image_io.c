/* libpng and libjpeg report errors by longjmp from a callback: every
 * decoder keeps what it allocates in a struct that outlives the jump, so
 * nothing is leaked and no local modified after setjmp is read after it. */
#include "image/image_io.h"

#include <errno.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <jpeglib.h> /* after stdio.h, which it needs and does not include */
#include <png.h>

#include "base/output.h"
#include "base/error.h"
#include "base/file.h"
#include "base/memlimit.h"
#include "image/pnm.h"
#include "report/png.h"

relief_image_format relief_image_format_of_name(const char *path)
{
    const char *dot = strrchr(path, '.');
    if (!dot || strchr(dot, '/'))
        return RELIEF_IMAGE_UNKNOWN;
    if (strcasecmp(dot, ".png") == 0)
        return RELIEF_IMAGE_PNG;
    if (strcasecmp(dot, ".jpg") == 0 || strcasecmp(dot, ".jpeg") == 0)
        return RELIEF_IMAGE_JPEG;
    return RELIEF_IMAGE_UNKNOWN;
}

/* Refuse a width x height x channels image the limit cannot take, before
 * its pixels are decoded. */
static relief_status check_size(const char *name, uint32_t w, uint32_t h, int channels,
                                int depth, const relief_image_limit *lim, int samples,
                                relief_error *err)
{
    uint64_t bytes, sample_bytes;
    double need;
    char what[512];
    if (w == 0 || h == 0)
        return relief_fail(err, RELIEF_E_FORMAT, "%s: the image has %u x %u pixels: nothing "
                           "to read", name, w, h);
    if (w > RELIEF_RASTER_MAX_SIDE || h > RELIEF_RASTER_MAX_SIDE)
        return relief_fail(err, RELIEF_E_RANGE, "%s: the image has %u x %u pixels: each side "
                           "must be at most %d", name, w, h, RELIEF_RASTER_MAX_SIDE);
    if (!lim || lim->limit == 0)
        return RELIEF_OK;
    snprintf(what, sizeof what, "%s (%u x %u pixels, %d channel%s)%s%s", name, w, h,
             channels, channels == 1 ? "" : "s", lim->what ? ": " : "",
             lim->what ? lim->what : "");
    bytes = relief_raster_bytes((int)w, (int)h, channels);
    sample_bytes = bytes / sizeof(float) * (uint64_t)(depth / 8);
    /* A raster is converted from the samples, both held a while. */
    need = samples ? (double)sample_bytes
                   : (double)bytes * (lim->factor > 1.0 ? lim->factor : 1.0) +
                         (double)sample_bytes;
    return relief_memory_check(what, (uint64_t)need, lim->limit, "", err);
}

/* ---------------------------------------------------------------- PNG */

typedef struct png_job {
    jmp_buf jump;
    char msg[256];
    const uint8_t *data;
    size_t n, at;
    png_bytep pixels;  /* the decoded image, rows packed */
    png_bytepp rows;
} png_job;

static void png_on_error(png_structp png, png_const_charp msg)
{
    png_job *job = png_get_error_ptr(png);
    snprintf(job->msg, sizeof job->msg, "%s", msg);
    longjmp(job->jump, 1);
}

static void png_on_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg; /* warnings (an unknown ancillary chunk, say) do not stop a read */
}

static void png_read_memory(png_structp png, png_bytep out, size_t len)
{
    png_job *job = png_get_io_ptr(png);
    if (len > job->n - job->at)
        png_error(png, "the file ends early (truncated)");
    memcpy(out, job->data + job->at, len);
    job->at += len;
}

static uint32_t be32(const uint8_t *b)
{
    return (uint32_t)b[0] << 24 | (uint32_t)b[1] << 16 | (uint32_t)b[2] << 8 | b[3];
}

/* libpng refuses a bad IHDR with "Invalid IHDR data" alone; its CRC
 * matched by then, so the fields are read here again to say which one
 * is wrong and its value. Returns 1 (the size over relief's limit) or 0. */
static int describe_ihdr(const uint8_t *d, size_t n, char *out, size_t cap)
{
    static const char *const names[] = {"grey", "", "RGB", "palette", "grey + alpha", "",
                                        "RGBA"};
    static const char *const depths[] = {"1, 2, 4, 8 or 16", "", "8 or 16", "1, 2, 4 or 8",
                                         "8 or 16", "", "8 or 16"};
    uint32_t side[2];
    int depth, ctype;
    if (n < 29 || memcmp(d + 12, "IHDR", 4) != 0) {
        snprintf(out, cap, "Invalid IHDR data");
        return 0;
    }
    side[0] = be32(d + 16);
    side[1] = be32(d + 20);
    depth = d[24];
    ctype = d[25];
    for (int k = 0; k < 2; ++k) {
        if (side[k] == 0 || side[k] > 0x7fffffffu) {
            snprintf(out, cap, "IHDR %s %u: expected 1..2^31 - 1 pixels", k ? "height" : "width",
                     side[k]);
            return 0;
        }
        if (side[k] > RELIEF_RASTER_MAX_SIDE) {
            snprintf(out, cap, "PNG IHDR %s %u: each side must be at most %d pixels",
                     k ? "height" : "width", side[k], RELIEF_RASTER_MAX_SIDE);
            return 1;
        }
    }
    if (ctype > 6 || !names[ctype][0])
        snprintf(out, cap, "IHDR colour type %d: expected 0 (grey), 2 (RGB), 3 (palette), "
                 "4 (grey + alpha) or 6 (RGBA)", ctype);
    else if (depth < 1 || depth > 16 || (depth & (depth - 1)) ||
             (ctype != 0 && ctype != 3 && depth < 8) || (ctype == 3 && depth == 16))
        snprintf(out, cap, "IHDR bit depth %d for colour type %d (%s): expected %s", depth,
                 ctype, names[ctype], depths[ctype]);
    else if (d[26] != 0)
        snprintf(out, cap, "IHDR compression method %d: expected 0", d[26]);
    else if (d[27] != 0)
        snprintf(out, cap, "IHDR filter method %d: expected 0", d[27]);
    else if (d[28] > 1)
        snprintf(out, cap, "IHDR interlace method %d: expected 0 (none) or 1 (Adam7)", d[28]);
    else
        snprintf(out, cap, "Invalid IHDR data (%u x %u pixels, bit depth %d, colour type %d)",
                 side[0], side[1], depth, ctype);
    return 0;
}

/* A palette image's PLTE and tRNS (colours NULL: not one). */
typedef struct png_palette {
    png_colorp colours;
    int entries;
    png_bytep alpha; /* NULL: opaque */
    int n_alpha;     /* entries past it are opaque */
} png_palette;

/* The decoded palette indexes (a byte each, job->rows) looked up into
 * *out: 8-bit samples, 3 or 4 channels; an index past the palette is
 * refused naming it. */
static relief_status expand_palette(const png_job *job, png_uint_32 w, png_uint_32 h,
                                    int channels, const png_palette *pal, const char *name,
                                    relief_image *out, relief_error *err)
{
    uint8_t *px = malloc((size_t)w * h * channels), *o = px;
    if (!px)
        return relief_fail(err, RELIEF_E_NOMEM, "%s: cannot allocate %u x %u pixels", name, w,
                           h);
    for (png_uint_32 y = 0; y < h; ++y)
        for (png_uint_32 x = 0; x < w; ++x, o += channels) {
            int k = job->rows[y][x];
            if (k >= pal->entries) {
                free(px);
                return relief_fail(err, RELIEF_E_PARSE, "%s: malformed PNG: a pixel has "
                                   "palette index %d, past the palette of %d entries", name,
                                   k, pal->entries);
            }
            o[0] = pal->colours[k].red;
            o[1] = pal->colours[k].green;
            o[2] = pal->colours[k].blue;
            if (channels == 4)
                o[3] = k < pal->n_alpha ? pal->alpha[k] : 255;
        }
    *out = (relief_image){(int)w, (int)h, channels, 8, (size_t)w * channels, px};
    return RELIEF_OK;
}

static int little_endian(void)
{
    const uint16_t one = 1;
    return *(const uint8_t *)&one == 1;
}

static relief_status decode_png(const uint8_t *data, size_t n, const char *name,
                                const relief_image_limit *lim, int samples, relief_image *out,
                                relief_error *err)
{
    png_job job;
    png_structp png;
    png_infop info;
    png_uint_32 w, h;
    int depth, ctype, interlace, channels;
    size_t rowbytes;
    png_palette pal;
    relief_status st = RELIEF_OK;

    memset(&job, 0, sizeof job);
    memset(&pal, 0, sizeof pal);
    job.data = data;
    job.n = n;
    png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &job, png_on_error, png_on_warning);
    info = png ? png_create_info_struct(png) : NULL;
    if (!png || !info) {
        png_destroy_read_struct(png ? &png : NULL, NULL, NULL);
        return relief_fail(err, RELIEF_E_NOMEM, "%s: cannot start libpng", name);
    }
    if (setjmp(job.jump)) {
        int over = 0;
        if (strcmp(job.msg, "Invalid IHDR data") == 0)
            over = describe_ihdr(data, n, job.msg, sizeof job.msg);
        st = over ? relief_fail(err, RELIEF_E_RANGE, "%s: %s", name, job.msg)
                  : relief_fail(err, RELIEF_E_PARSE, "%s: malformed PNG: %s", name, job.msg);
        goto done;
    }
    png_set_read_fn(png, &job, png_read_memory);
    png_set_user_limits(png, RELIEF_RASTER_MAX_SIDE, RELIEF_RASTER_MAX_SIDE);
    png_read_info(png, info);
    png_get_IHDR(png, info, &w, &h, &depth, &ctype, &interlace, NULL, NULL);
    if (ctype == PNG_COLOR_TYPE_PALETTE) {
        /* Expanded here, not by libpng, which pads a short palette with
         * black and reads a pixel past it so, silently. */
        png_get_PLTE(png, info, &pal.colours, &pal.entries);
        if (png_get_valid(png, info, PNG_INFO_tRNS))
            png_get_tRNS(png, info, &pal.alpha, &pal.n_alpha, NULL);
        png_set_packing(png); /* 1, 2, 4-bit indexes to a byte each */
    } else {
        if (ctype == PNG_COLOR_TYPE_GRAY && depth < 8)
            png_set_expand_gray_1_2_4_to_8(png);
        if (png_get_valid(png, info, PNG_INFO_tRNS))
            png_set_tRNS_to_alpha(png);
        if (depth == 16 && little_endian())
            png_set_swap(png); /* 16-bit samples in the host's order */
    }
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    channels = pal.colours ? (pal.alpha ? 4 : 3) : png_get_channels(png, info);
    depth = png_get_bit_depth(png, info);
    if ((depth != 8 && depth != 16) || channels < 1 || channels > 4) {
        st = relief_fail(err, RELIEF_E_FORMAT, "%s: PNG of %d channels of %d bits: not "
                         "supported", name, channels, depth);
        goto done;
    }
    st = check_size(name, w, h, channels, depth, lim, samples, err);
    if (st != RELIEF_OK)
        goto done;
    rowbytes = png_get_rowbytes(png, info);
    job.pixels = malloc(rowbytes * h);
    job.rows = malloc(sizeof *job.rows * h);
    if (!job.pixels || !job.rows) {
        st = relief_fail(err, RELIEF_E_NOMEM, "%s: cannot allocate %u x %u pixels", name, w, h);
        goto done;
    }
    for (png_uint_32 y = 0; y < h; ++y)
        job.rows[y] = job.pixels + y * rowbytes;
    png_read_image(png, job.rows);
    png_read_end(png, NULL);
    if (pal.colours) {
        st = expand_palette(&job, w, h, channels, &pal, name, out, err);
    } else { /* libpng's rows are the samples, packed */
        *out = (relief_image){(int)w, (int)h, channels, depth, rowbytes, job.pixels};
        job.pixels = NULL;
    }
done:
    png_destroy_read_struct(&png, &info, NULL);
    free(job.pixels);
    free(job.rows);
    return st;
}

/* ---------------------------------------------------------------- JPEG */

typedef struct jpeg_job {
    struct jpeg_error_mgr pub; /* first: libjpeg hands back a pointer to it */
    jmp_buf jump;
    char msg[JMSG_LENGTH_MAX];
    int warned;
    JSAMPLE *row;
} jpeg_job;

static void jpeg_on_error(j_common_ptr cinfo)
{
    jpeg_job *job = (jpeg_job *)cinfo->err;
    (*cinfo->err->format_message)(cinfo, job->msg);
    longjmp(job->jump, 1);
}

/* libjpeg only warns about corrupt or truncated data and fills the rest
 * grey; relief refuses such a file instead, so keep the first warning. */
static void jpeg_on_message(j_common_ptr cinfo, int level)
{
    jpeg_job *job = (jpeg_job *)cinfo->err;
    if (level < 0 && !job->warned) {
        (*cinfo->err->format_message)(cinfo, job->msg);
        job->warned = 1;
    }
}

static relief_status decode_jpeg(const uint8_t *data, size_t n, const char *name,
                                 const relief_image_limit *lim, int samples, relief_image *out,
                                 relief_error *err)
{
    struct jpeg_decompress_struct cinfo;
    jpeg_job job;
    relief_status st = RELIEF_OK;
    int channels;
    size_t row;

    memset(&job, 0, sizeof job);
    cinfo.err = jpeg_std_error(&job.pub);
    job.pub.error_exit = jpeg_on_error;
    job.pub.emit_message = jpeg_on_message;
    if (setjmp(job.jump)) {
        st = relief_fail(err, RELIEF_E_PARSE, "%s: malformed JPEG: %s", name, job.msg);
        goto done;
    }
    jpeg_create_decompress(&cinfo);
    jpeg_mem_src(&cinfo, data, (unsigned long)n);
    jpeg_read_header(&cinfo, TRUE);
    if (cinfo.jpeg_color_space == JCS_CMYK || cinfo.jpeg_color_space == JCS_YCCK) {
        st = relief_fail(err, RELIEF_E_FORMAT, "%s: a CMYK JPEG: not supported (convert it to "
                         "RGB first)", name);
        goto done;
    }
    channels = cinfo.num_components == 1 ? 1 : 3;
    cinfo.out_color_space = channels == 1 ? JCS_GRAYSCALE : JCS_RGB;
    st = check_size(name, cinfo.image_width, cinfo.image_height, channels, 8, lim, samples,
                    err);
    if (st != RELIEF_OK)
        goto done;
    jpeg_start_decompress(&cinfo);
    row = (size_t)cinfo.output_width * channels;
    if (!(job.row = malloc(row * cinfo.output_height))) {
        st = relief_fail(err, RELIEF_E_NOMEM, "%s: cannot allocate %u x %u pixels", name,
                         cinfo.output_width, cinfo.output_height);
        jpeg_abort_decompress(&cinfo);
        goto done;
    }
    while (cinfo.output_scanline < cinfo.output_height && !job.warned) {
        JSAMPROW rows[1] = {job.row + (size_t)cinfo.output_scanline * row};
        jpeg_read_scanlines(&cinfo, rows, 1);
    }
    if (!job.warned)
        jpeg_finish_decompress(&cinfo);
    if (job.warned) {
        st = relief_fail(err, RELIEF_E_PARSE, "%s: corrupt or truncated JPEG: %s", name,
                         job.msg);
    } else {
        *out = (relief_image){(int)cinfo.output_width, (int)cinfo.output_height, channels, 8,
                              row, job.row};
        job.row = NULL;
    }
done:
    jpeg_destroy_decompress(&cinfo);
    free(job.row);
    return st;
}

/* ---------------------------------------------------------------- PNM */

/* A binary PNM's intensities, scaled to 8 or 16 bits whatever its maxval:
 * a picture's 0..maxval means black to white. */
static relief_status decode_pnm(const uint8_t *data, size_t n, const char *name,
                                const relief_image_limit *lim, int samples, relief_image *out,
                                relief_error *err)
{
    relief_pnm h;
    relief_status st = relief_pnm_header(data, n, name, &h, err);
    if (st == RELIEF_OK)
        st = check_size(name, (uint32_t)h.width, (uint32_t)h.height, h.channels,
                        h.maxval > 255 ? 16 : 8, lim, samples, err);
    return st == RELIEF_OK ? relief_pnm_samples(data, n, name, &h, 1, out, err) : st;
}

/* PNG, JPEG or PNM by the first bytes, into *out (out->data NULL on failure);
 * samples: lim bounds the samples at the file's bit depth, not the raster
 * (check_size). */
static relief_status decode(const uint8_t *data, size_t n, const char *name,
                            const relief_image_limit *lim, int samples, relief_image *out,
                            relief_error *err)
{
    static const uint8_t png_sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    memset(out, 0, sizeof *out);
    if (n >= 8 && memcmp(data, png_sig, 8) == 0)
        return decode_png(data, n, name, lim, samples, out, err);
    if (n >= 3 && data[0] == 0xff && data[1] == 0xd8 && data[2] == 0xff)
        return decode_jpeg(data, n, name, lim, samples, out, err);
    if (relief_pnm_sniff(data, n))
        return decode_pnm(data, n, name, lim, samples, out, err);
    if (n == 0)
        return relief_fail(err, RELIEF_E_FORMAT, "%s: the file is empty", name);
    return relief_fail(err, RELIEF_E_FORMAT, "%s: not a PNG, JPEG or binary PNM image (by "
                       "its first bytes)", name);
}

relief_status relief_raster_decode(const uint8_t *data, size_t n, const char *name,
                                  const relief_image_limit *lim, relief_raster *out,
                                  relief_error *err)
{
    relief_image img;
    relief_status st = decode(data, n, name, lim, 0, &img, err);
    size_t vals = (size_t)img.width * img.height * img.channels;
    out->v = NULL;
    if (st == RELIEF_OK)
        st = relief_raster_create(img.width, img.height, img.channels, img.bit_depth, out, err);
    for (size_t i = 0; st == RELIEF_OK && i < vals; ++i)
        out->v[i] = img.bit_depth == 16 ? (float)((const uint16_t *)img.data)[i]
                                        : (float)((const uint8_t *)img.data)[i];
    free(img.data);
    return st;
}

relief_status relief_image_file_decode(const uint8_t *data, size_t n, const char *name,
                                       uint64_t max_bytes, relief_image *out, relief_error *err)
{
    relief_image_limit lim = {max_bytes, 1.0, NULL};
    relief_image img;
    relief_status st = decode(data, n, name, &lim, 1, &img, err);
    if (st == RELIEF_OK) /* *out is not touched on failure */
        *out = img;
    return st;
}

relief_status relief_raster_read(const char *path, const relief_image_limit *lim,
                                relief_raster *out, relief_error *err)
{
    uint8_t *data;
    size_t n;
    relief_status st = relief_read_file(path, &data, &n, err);
    out->v = NULL;
    if (st != RELIEF_OK)
        return st;
    st = relief_raster_decode(data, n, path, lim, out, err);
    free(data);
    return st;
}

/* ---------------------------------------------------------------- writing */

static size_t packed_row(const relief_image *img)
{
    return (size_t)img->width * img->channels * (img->bit_depth / 8);
}

/* img's samples as PNG stores them: rows packed, 16 bits big endian. The
 * caller's buffer itself when it is already so (8 bits, rows packed);
 * else a copy, in *copy (the caller frees it). */
static const uint8_t *png_samples(const relief_image *img, uint8_t **copy)
{
    size_t row = packed_row(img), stride = img->stride ? img->stride : row;
    *copy = NULL;
    if (img->bit_depth == 8 && stride == row)
        return img->data;
    *copy = malloc(row * (size_t)img->height);
    if (!*copy)
        return NULL;
    for (int y = 0; y < img->height; ++y) {
        const uint8_t *in = (const uint8_t *)img->data + (size_t)y * stride;
        uint8_t *out = *copy + (size_t)y * row;
        if (img->bit_depth == 8) {
            memcpy(out, in, row);
            continue;
        }
        for (size_t i = 0; i < row; i += 2) {
            uint16_t v;
            memcpy(&v, in + i, sizeof v); /* a caller's rows need not be aligned */
            out[i] = (uint8_t)(v >> 8), out[i + 1] = (uint8_t)v;
        }
    }
    return *copy;
}

static relief_status write_png(FILE *f, const relief_image *img, const char *path,
                               relief_error *err)
{
    uint8_t *copy, *png = NULL;
    const uint8_t *pixels = png_samples(img, &copy);
    size_t n = 0;
    relief_status st;

    if (!pixels)
        return relief_fail(err, RELIEF_E_NOMEM, "%s: cannot allocate the image's bytes", path);
    st = relief_png_encode_pixels(pixels, img->width, img->height, img->channels,
                                  img->bit_depth, &png, &n, err);
    free(copy);
    if (st != RELIEF_OK) {
        relief_fail_prefix(err, "%s", path);
        return st;
    }
    if (fwrite(png, 1, n, f) != n)
        st = relief_fail_errno(err, errno ? errno : EIO, path, "cannot write");
    free(png);
    return st;
}

/* 8-bit samples only (relief_image_file_write checks). */
static relief_status write_jpeg(FILE *f, const relief_image *img, const char *path,
                                relief_error *err)
{
    struct jpeg_compress_struct cinfo;
    jpeg_job job;
    int colours = img->channels >= 3 ? 3 : 1;

    memset(&job, 0, sizeof job);
    job.row = malloc((size_t)img->width * colours);
    if (!job.row)
        return relief_fail(err, RELIEF_E_NOMEM, "%s: cannot allocate a row", path);
    cinfo.err = jpeg_std_error(&job.pub);
    job.pub.error_exit = jpeg_on_error;
    errno = 0;
    if (setjmp(job.jump)) {
        int e = errno;
        jpeg_destroy_compress(&cinfo);
        free(job.row);
        if (e) /* the file's write failed (libjpeg: "Output file write error") */
            return relief_fail_errno(err, e, path, "cannot write");
        return relief_fail(err, RELIEF_E_INTERNAL, "%s: cannot encode the JPEG: %s", path,
                           job.msg);
    }
    jpeg_create_compress(&cinfo);
    jpeg_stdio_dest(&cinfo, f);
    cinfo.image_width = (JDIMENSION)img->width;
    cinfo.image_height = (JDIMENSION)img->height;
    cinfo.input_components = colours;
    cinfo.in_color_space = colours == 3 ? JCS_RGB : JCS_GRAYSCALE;
    jpeg_set_defaults(&cinfo);
    jpeg_set_quality(&cinfo, 95, TRUE);
    jpeg_start_compress(&cinfo, TRUE);
    while (cinfo.next_scanline < cinfo.image_height) {
        size_t stride = img->stride ? img->stride : packed_row(img);
        const uint8_t *v = (const uint8_t *)img->data + (size_t)cinfo.next_scanline * stride;
        JSAMPROW rows[1] = {job.row};
        for (int x = 0; x < img->width; ++x)
            for (int c = 0; c < colours; ++c)
                job.row[x * colours + c] = v[x * img->channels + c];
        jpeg_write_scanlines(&cinfo, rows, 1);
    }
    jpeg_finish_compress(&cinfo);
    jpeg_destroy_compress(&cinfo);
    free(job.row);
    return RELIEF_OK;
}

/* Can `img` go to `path`'s format? */
static relief_status check_format(const char *path, const relief_image *img,
                                  relief_image_format *fmt, relief_error *err)
{
    *fmt = relief_image_format_of_name(path);
    if (*fmt == RELIEF_IMAGE_UNKNOWN)
        return relief_fail(err, RELIEF_E_FORMAT, "%s: unknown image extension; relief writes "
                           ".png, .jpg and .jpeg", path);
    if (img->bit_depth != 8 && img->bit_depth != 16)
        return relief_fail(err, RELIEF_E_FORMAT, "%s: an image of %d bits cannot be written; "
                           "expected 8 or 16", path, img->bit_depth);
    if (*fmt == RELIEF_IMAGE_JPEG && img->bit_depth != 8)
        return relief_fail(err, RELIEF_E_FORMAT, "%s: JPEG holds 8 bits per channel, the image "
                           "has 16; write it as .png", path);
    return RELIEF_OK;
}

relief_status relief_image_write_to(relief_sink *s, const relief_image *img, relief_error *err)
{
    relief_image_format fmt;
    relief_status st = check_format(s->path, img, &fmt, err);
    if (st != RELIEF_OK)
        return st;
    return fmt == RELIEF_IMAGE_PNG ? write_png(s->f, img, s->path, err)
                                   : write_jpeg(s->f, img, s->path, err);
}

static relief_status image_sink(relief_sink *s, void *ctx, relief_error *err)
{
    return relief_image_write_to(s, ctx, err);
}

relief_status relief_image_file_write(const char *path, const relief_image *img,
                                      relief_error *err)
{
    relief_image_format fmt;
    relief_status st = check_format(path, img, &fmt, err);
    if (st != RELIEF_OK)
        return st;
    return relief_output_file(path, image_sink, (void *)img, err);
}

/* r's samples as an 8- or 16-bit image (img->data malloc'ed). */
static relief_status raster_image(const relief_raster *r, relief_image *img, const char *path,
                                  relief_error *err)
{
    size_t vals = (size_t)r->width * r->height * r->channels;
    float max = relief_raster_max_value(r);
    *img = (relief_image){r->width, r->height, r->channels, r->bit_depth, 0, NULL};
    if (r->bit_depth != 8 && r->bit_depth != 16)
        return relief_fail(err, RELIEF_E_FORMAT, "%s: an image of %d bits cannot be written; "
                           "expected 8 or 16", path, r->bit_depth);
    img->data = malloc(vals * (r->bit_depth / 8));
    if (!img->data)
        return relief_fail(err, RELIEF_E_NOMEM, "%s: cannot allocate the image's bytes", path);
    if (r->bit_depth == 8) {
        uint8_t *o = img->data;
        for (size_t i = 0; i < vals; ++i)
            o[i] = (uint8_t)relief_raster_quantise(r->v[i], max);
    } else {
        uint16_t *o = img->data;
        for (size_t i = 0; i < vals; ++i)
            o[i] = (uint16_t)relief_raster_quantise(r->v[i], max);
    }
    return RELIEF_OK;
}

relief_status relief_raster_write_to(relief_sink *s, const relief_raster *r, relief_error *err)
{
    relief_image img;
    relief_status st = raster_image(r, &img, s->path, err);
    if (st == RELIEF_OK)
        st = relief_image_write_to(s, &img, err);
    free(img.data);
    return st;
}

relief_status relief_raster_write(const char *path, const relief_raster *r, relief_error *err)
{
    relief_image img;
    relief_status st = raster_image(r, &img, path, err);
    if (st == RELIEF_OK)
        st = relief_image_file_write(path, &img, err);
    free(img.data);
    return st;
}
