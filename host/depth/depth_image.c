/* The public depth image's files (relief/depth.h): PCD and PFM through
 * depth_io.h, a 16-bit grey PNG through the image reader and writer. */
#include "relief/relief.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/file.h"
#include "depth/depth_io.h"
#include "image/image_io.h"

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

/* A 16-bit grey PNG's values as depths: value / scale, 0 missing (NaN).
 * max_pixels bounds it as the other readers do: the raster reader's limit
 * is in bytes of its float raster (4 a pixel) times the work after it. */
static relief_status decode_png16(const uint8_t *d, size_t n, const char *name, double scale,
                                  uint64_t max_pixels, relief_depth_image *f, relief_error *err)
{
    uint64_t bytes = max_pixels > UINT64_MAX / 64 ? UINT64_MAX : max_pixels * 64;
    relief_image_limit lim = {bytes, 16.0, "repairing it"};
    relief_raster r = {0, 0, 0, 0, NULL};
    relief_status st = relief_raster_decode(d, n, name, &lim, &r, err);
    size_t px;
    if (st != RELIEF_OK)
        return st;
    if (r.channels != 1 || r.bit_depth != 16) {
        relief_raster_free(&r);
        return relief_fail(err, RELIEF_E_FORMAT, "%s: a PNG depth image has one 16-bit grey "
                           "channel; this one has %d channel(s) of %d bits", name, r.channels,
                           r.bit_depth);
    }
    px = (size_t)r.width * r.height;
    f->z = malloc(px * sizeof *f->z);
    if (!f->z) {
        relief_raster_free(&r);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the depths");
    }
    f->width = r.width;
    f->height = r.height;
    f->format = RELIEF_DEPTH_PNG16;
    for (size_t i = 0; i < px; ++i)
        f->z[i] = r.v[i] > 0.0f ? (float)(r.v[i] / scale) : NAN;
    relief_raster_free(&r);
    return RELIEF_OK;
}

static int is_png(const uint8_t *d, size_t n)
{
    return n >= 8 && memcmp(d, "\x89PNG\r\n\x1a\n", 8) == 0;
}

relief_status relief_depth_read(const char *path, double png_scale, uint64_t max_pixels,
                                relief_depth_image *out, relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    uint8_t *d = NULL;
    size_t n = 0;
    double scale = RELIEF_DEPTH_PNG_SCALE;
    relief_status st;
    if (!out)
        return relief_fail(err, RELIEF_E_USAGE, "out: NULL");
    memset(out, 0, sizeof *out);
    if (!path)
        return relief_fail(err, RELIEF_E_USAGE, "path: NULL");
    st = png_scale_of(png_scale, &scale, err);
    if (st == RELIEF_OK)
        st = relief_read_file(path, &d, &n, err);
    if (st != RELIEF_OK)
        return st;
    if (is_png(d, n))
        st = decode_png16(d, n, path, scale, max_pixels, out, err);
    else if ((n >= 2 && d[0] == 'P' && (d[1] == 'f' || d[1] == 'F')) ||
             (n >= 6 && memcmp(d, "# .PCD", 6) == 0) || (n >= 7 && memcmp(d, "VERSION", 7) == 0))
        st = relief_depth_frame_decode(d, n, path, max_pixels, out, err);
    else
        st = relief_fail(err, RELIEF_E_FORMAT, "%s: neither a PCD, a PFM nor a PNG file (by "
                         "its first bytes)", path);
    free(d);
    if (st != RELIEF_OK)
        relief_depth_image_free(out);
    return st;
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
