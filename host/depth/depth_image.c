/* The public depth image's files (relief/depth.h): PCD and PFM through
 * depth_io.h, a 16-bit grey PNG or PGM through the image readers (as the
 * RGB-D datasets encode it: relief_depth_encoding) and the PNG writer. */
#include "relief/relief.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/file.h"
#include "depth/depth_io.h"
#include "image/image_io.h"
#include "image/pnm.h"

/* A PNG's scale: 0 the default; NaN, negative or absurd values refused. */
static relief_status png_scale_of(double png_scale, double *scale, relief_error *err)
{
    if (png_scale == 0.0) {
        *scale = RELIEF_DEPTH_PNG_SCALE;
        return RELIEF_OK;
    }
    if (!(png_scale > 0.0 && png_scale <= 1e9))
        return relief_fail_param(err, RELIEF_E_RANGE, "png_scale", "png_scale %g out of range: expected "
                           "values per metre in (0, 1e9], or 0 for the default %g", png_scale,
                           RELIEF_DEPTH_PNG_SCALE);
    *scale = png_scale;
    return RELIEF_OK;
}

/* How one sample becomes a depth: the encoding and its scale. */
typedef struct depth_code {
    relief_depth_encoding encoding;
    double scale;       /* values per metre (png, pgm, sun) */
} depth_code;

/* Sample v (as the file's reader gives it: PGM's big-endian bytes already
 * in the host's order) as metres; NaN where missing. */
static float depth_of(const depth_code *c, unsigned v)
{
    if (c->encoding == RELIEF_DEPTH_ENCODING_NYU) {
        /* Stored little-endian, read big-endian: swap back. The Kinect's
         * disparity-to-depth fit of NYU's toolbox (depth_rel2depth_abs). */
        unsigned d = (v >> 8 | v << 8) & 0xffffu;
        double z = 351.3 / (1092.5 - d);
        return d < 2047 && z > 0.0 ? (float)z : NAN;
    }
    if (c->encoding == RELIEF_DEPTH_ENCODING_SUN)
        v = (v >> 3 | v << 13) & 0xffffu; /* SUN RGB-D's rotated bits */
    return v > 0 ? (float)(v / c->scale) : NAN;
}

/* The depth image's samples: one channel, 16 bits (8 allowed for a plain
 * PGM: a coarse depth, but a depth). */
static relief_status check_samples(const relief_image *img, const char *name, const char *kind,
                                   int narrow_ok, relief_error *err)
{
    if (img->channels == 1 && (img->bit_depth == 16 || (narrow_ok && img->bit_depth == 8)))
        return RELIEF_OK;
    return relief_fail(err, RELIEF_E_FORMAT, "%s: a %s depth image has one 16-bit grey "
                       "channel; this one has %d channel(s) of %d bits", name, kind,
                       img->channels, img->bit_depth);
}

/* A PGM's samples as they are stored (no scaling to the full range: they
 * are counts), bounded as the other readers are. */
static relief_status pgm_samples(const uint8_t *d, size_t n, const char *name,
                                 uint64_t max_pixels, relief_image *img, relief_error *err)
{
    relief_pnm h;
    relief_status st = relief_pnm_header(d, n, name, &h, err);
    if (st == RELIEF_OK && max_pixels && (uint64_t)h.width * h.height > max_pixels)
        st = relief_fail(err, RELIEF_E_NOMEM, "%s: %d x %d pixels: over the %llu the call "
                         "may take", name, h.width, h.height, (unsigned long long)max_pixels);
    return st == RELIEF_OK ? relief_pnm_samples(d, n, name, &h, 0, img, err) : st;
}

/* A PNG's samples; max_pixels bounds it as the other readers do: the
 * image reader's limit is in bytes of its samples, 2 a depth pixel. */
static relief_status png_samples(const uint8_t *d, size_t n, const char *name,
                                 uint64_t max_pixels, relief_image *img, relief_error *err)
{
    uint64_t bytes = max_pixels > UINT64_MAX / 2 ? UINT64_MAX : max_pixels * 2;
    return relief_image_file_decode(d, n, name, bytes, img, err);
}

/* A 16-bit PNG or a PGM (is_pgm) decoded by c into f. */
static relief_status decode_image_depth(const uint8_t *d, size_t n, const char *name,
                                        int is_pgm, const depth_code *c, uint64_t max_pixels,
                                        relief_depth_image *f, relief_error *err)
{
    static const char *const kinds[] = {"", "PNG", "PGM", "NYU (PGM)", "SUN (PNG)"};
    relief_image img = {0, 0, 0, 0, 0, NULL};
    relief_status st = is_pgm ? pgm_samples(d, n, name, max_pixels, &img, err)
                              : png_samples(d, n, name, max_pixels, &img, err);
    size_t px;
    if (st == RELIEF_OK)
        st = check_samples(&img, name, kinds[c->encoding], c->encoding == RELIEF_DEPTH_ENCODING_PGM,
                           err);
    px = (size_t)img.width * img.height;
    if (st == RELIEF_OK && !(f->z = malloc(px * sizeof *f->z)))
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the depths");
    for (size_t i = 0; st == RELIEF_OK && i < px; ++i) {
        const uint8_t *row = (const uint8_t *)img.data + (i / (size_t)img.width) * img.stride;
        size_t x = i % (size_t)img.width;
        unsigned v = img.bit_depth == 16 ? ((const uint16_t *)row)[x] : row[x];
        f->z[i] = depth_of(c, v);
    }
    if (st == RELIEF_OK) {
        f->width = img.width, f->height = img.height;
        f->format = RELIEF_DEPTH_PNG16;
    }
    relief_image_free(&img);
    return st;
}

static int is_png(const uint8_t *d, size_t n)
{
    return n >= 8 && memcmp(d, "\x89PNG\r\n\x1a\n", 8) == 0;
}

static int is_depth_frame(const uint8_t *d, size_t n)
{
    return (n >= 2 && d[0] == 'P' && (d[1] == 'f' || d[1] == 'F')) ||
           (n >= 6 && memcmp(d, "# .PCD", 6) == 0) || (n >= 7 && memcmp(d, "VERSION", 7) == 0);
}

/* The file's bytes as `c` says (auto: by the first bytes). */
static relief_status decode_as(const uint8_t *d, size_t n, const char *path, depth_code c,
                               uint64_t max_pixels, relief_depth_image *out, relief_error *err)
{
    int png = is_png(d, n), pgm = !png && relief_pnm_sniff(d, n);
    if (c.encoding == RELIEF_DEPTH_ENCODING_AUTO) {
        if (is_depth_frame(d, n))
            return relief_depth_frame_decode(d, n, path, max_pixels, out, err);
        if (!png && !pgm)
            return relief_fail(err, RELIEF_E_FORMAT, "%s: neither a PCD, a PFM, a PNG nor a "
                               "PGM file (by its first bytes)", path);
        c.encoding = png ? RELIEF_DEPTH_ENCODING_PNG : RELIEF_DEPTH_ENCODING_PGM;
    }
    if (c.encoding == RELIEF_DEPTH_ENCODING_PNG || c.encoding == RELIEF_DEPTH_ENCODING_SUN) {
        if (!png)
            return relief_fail(err, RELIEF_E_FORMAT, "%s: depth format %s expects a 16-bit PNG; "
                               "the file is none (by its first bytes)", path,
                               relief_depth_encoding_name(c.encoding));
    } else if (!pgm) {
        return relief_fail(err, RELIEF_E_FORMAT, "%s: depth format %s expects a binary PGM (P5); "
                           "the file is none (by its first bytes)", path,
                           relief_depth_encoding_name(c.encoding));
    }
    return decode_image_depth(d, n, path, pgm, &c, max_pixels, out, err);
}

relief_status relief_depth_read_as(const char *path, relief_depth_encoding encoding,
                                   double scale, uint64_t max_pixels, relief_depth_image *out,
                                   relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    uint8_t *d = NULL;
    size_t n = 0;
    depth_code c = {encoding, RELIEF_DEPTH_PNG_SCALE};
    relief_status st;
    if (!out)
        return relief_fail(err, RELIEF_E_USAGE, "out: NULL");
    memset(out, 0, sizeof *out);
    if (!path)
        return relief_fail(err, RELIEF_E_USAGE, "path: NULL");
    if ((unsigned)encoding > RELIEF_DEPTH_ENCODING_SUN)
        return relief_fail_param(err, RELIEF_E_RANGE, "encoding", "depth encoding %d out of "
                                 "range: expected auto, png, pgm, nyu or sun", (int)encoding);
    st = png_scale_of(scale, &c.scale, err);
    if (encoding == RELIEF_DEPTH_ENCODING_SUN && scale == 0.0)
        c.scale = 1000.0; /* SUN RGB-D's millimetres */
    if (st == RELIEF_OK)
        st = relief_read_file(path, &d, &n, err);
    if (st != RELIEF_OK)
        return st;
    st = decode_as(d, n, path, c, max_pixels, out, err);
    free(d);
    if (st != RELIEF_OK)
        relief_depth_image_free(out);
    return st;
}

relief_status relief_depth_read(const char *path, double png_scale, uint64_t max_pixels,
                                relief_depth_image *out, relief_error *err)
{
    return relief_depth_read_as(path, RELIEF_DEPTH_ENCODING_AUTO, png_scale, max_pixels, out,
                                err);
}

relief_status relief_depth_decode(const void *data, size_t n, const char *name,
                                  uint64_t max_pixels, relief_depth_image *out,
                                  relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    relief_status st;
    if (!out)
        return relief_fail(err, RELIEF_E_USAGE, "out: NULL");
    memset(out, 0, sizeof *out);
    if (!data && n)
        return relief_fail(err, RELIEF_E_USAGE, "data: NULL");
    st = relief_depth_frame_decode(data, n, name ? name : "the data", max_pixels, out, err);
    if (st != RELIEF_OK)
        relief_depth_image_free(out);
    return st;
}

/* z x scale, rounded, 0 where missing: a filled depth rounds to at least
 * 1 (0 would read as missing), and clamps at 65535. */
static relief_status write_png16(relief_sink *s, const relief_depth_image *f, double scale,
                                 relief_error *err)
{
    relief_raster r = {0, 0, 0, 0, NULL};
    size_t n = (size_t)f->width * f->height;
    relief_status st = relief_raster_create(f->width, f->height, 1, 16, &r, err);
    if (st != RELIEF_OK)
        return st;
    for (size_t i = 0; i < n; ++i) {
        double v = isfinite(f->z[i]) ? floor(f->z[i] * scale + 0.5) : 0.0;
        r.v[i] = (float)(v < 1.0 && isfinite(f->z[i]) ? 1.0 : v > 65535.0 ? 65535.0 : v);
    }
    st = relief_raster_write_to(s, &r, err);
    relief_raster_free(&r);
    return st;
}

/* Can f be written as `format` to `path`? */
static relief_status check_write(const relief_depth_image *f, const char *path,
                                 relief_depth_format format, relief_error *err)
{
    if (!f || !path)
        return relief_fail(err, RELIEF_E_USAGE, "%s: NULL", f ? "path" : "frame");
    if (!f->z)
        return relief_fail(err, RELIEF_E_USAGE, "frame z: NULL");
    if (f->width < 1 || f->width > RELIEF_DEPTH_MAX_SIDE || f->height < 1 ||
        f->height > RELIEF_DEPTH_MAX_SIDE)
        return relief_fail(err, RELIEF_E_RANGE, "frame width x height %d x %d out of range: "
                           "expected 1..%d each", f->width, f->height, RELIEF_DEPTH_MAX_SIDE);
    if (format < RELIEF_DEPTH_PFM || format > RELIEF_DEPTH_PNG16)
        return relief_fail_param(err, RELIEF_E_RANGE, "format", "format %d is not one of pfm, "
                                 "pcd-ascii, pcd-binary, pcd-compressed, png16", (int)format);
    if (format != RELIEF_DEPTH_PFM && format != RELIEF_DEPTH_PNG16 && !f->xyz)
        return relief_fail(err, RELIEF_E_USAGE, "%s: a PCD needs points (x y z), this frame "
                           "has depths only (xyz NULL)", path);
    return RELIEF_OK;
}

/* What depth_sink writes. */
typedef struct depth_job {
    const relief_depth_image *f;
    relief_depth_format format;
    double png_scale;
} depth_job;

relief_status relief_depth_write_to(relief_sink *s, const relief_depth_image *f,
                                    relief_depth_format format, double png_scale,
                                    relief_error *err)
{
    double scale = RELIEF_DEPTH_PNG_SCALE;
    relief_status st = check_write(f, s->path, format, err);
    if (st != RELIEF_OK)
        return st;
    if (format != RELIEF_DEPTH_PNG16)
        return relief_depth_frame_write_to(s, f, format, err);
    st = png_scale_of(png_scale, &scale, err);
    return st != RELIEF_OK ? st : write_png16(s, f, scale, err);
}

static relief_status depth_sink(relief_sink *s, void *ctx, relief_error *err)
{
    const depth_job *job = ctx;
    return relief_depth_write_to(s, job->f, job->format, job->png_scale, err);
}

relief_status relief_depth_write(const relief_depth_image *f, const char *path,
                                 relief_depth_format format, double png_scale,
                                 relief_error *err)
{
    depth_job job = {f, format, png_scale};
    double scale;
    RELIEF_ENTRY_ERR(err);
    if (check_write(f, path, format, err) != RELIEF_OK ||
        (format == RELIEF_DEPTH_PNG16 && png_scale_of(png_scale, &scale, err) != RELIEF_OK))
        return err->status;
    return relief_output_file(path, depth_sink, &job, err);
}

void relief_depth_image_free(relief_depth_image *f)
{
    if (!f)
        return;
    relief_depth_frame_free(f);
    memset(f, 0, sizeof *f);
}
