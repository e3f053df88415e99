/* A frame around its repair (frame.h). */
#include "depth/frame.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "base/output.h"
#include "base/error.h"

relief_status relief_depth_mask_check(const relief_image *mask, int width, int height,
                                      relief_error *err)
{
    size_t row;
    if (!mask->data)
        return relief_fail(err, RELIEF_E_USAGE, "mask data: NULL");
    if (mask->channels < 1 || mask->channels > 4)
        return relief_fail(err, RELIEF_E_RANGE, "mask channels %d out of range: expected 1..4",
                           mask->channels);
    if (mask->bit_depth != 8 && mask->bit_depth != 16)
        return relief_fail(err, RELIEF_E_RANGE, "mask bit_depth %d: expected 8 or 16",
                           mask->bit_depth);
    if (mask->width != width || mask->height != height)
        return relief_fail(err, RELIEF_E_USAGE, "the mask is %d x %d pixels, the frame %d x "
                           "%d: they must be the same size", mask->width, mask->height, width,
                           height);
    row = (size_t)width * (size_t)mask->channels * (size_t)(mask->bit_depth / 8);
    if (mask->stride && mask->stride < row)
        return relief_fail(err, RELIEF_E_USAGE, "mask stride %zu: a row takes %zu bytes",
                           mask->stride, row);
    return RELIEF_OK;
}

/* Is pixel (x, y) of the mask non-zero in a channel other than alpha? */
static int masked(const relief_image *m, int x, int y)
{
    int bytes = m->bit_depth / 8, colours = m->channels == 2 || m->channels == 4
                                                ? m->channels - 1
                                                : m->channels;
    size_t stride = m->stride ? m->stride : (size_t)m->width * m->channels * bytes;
    const uint8_t *p = (const uint8_t *)m->data + (size_t)y * stride +
                       (size_t)x * m->channels * bytes;
    for (int k = 0; k < colours; ++k) {
        if (bytes == 1 && p[k])
            return 1;
        if (bytes == 2) {
            uint16_t v;
            memcpy(&v, p + 2 * k, 2);
            if (v)
                return 1;
        }
    }
    return 0;
}

void relief_depth_mask_bits(const relief_image *mask, uint8_t *bits)
{
    for (int y = 0; y < mask->height; ++y)
        for (int x = 0; x < mask->width; ++x)
            bits[(size_t)y * mask->width + x] = (uint8_t)masked(mask, x, y);
}

void relief_depth_missing(const relief_depth_image *f, const relief_image *mask,
                          uint8_t *missing, size_t *in_input, size_t *by_mask)
{
    *in_input = *by_mask = 0;
    for (int y = 0; y < f->height; ++y)
        for (int x = 0; x < f->width; ++x) {
            size_t i = (size_t)y * f->width + x;
            int bad = !isfinite(f->z[i]) || f->z[i] == 0.0f;
            int m = mask && masked(mask, x, y);
            missing[i] = (uint8_t)(bad || m);
            *in_input += (size_t)bad;
            *by_mask += (size_t)(m && !bad);
        }
}

int relief_depth_fit_camera(const relief_depth_image *f, double cam[4])
{
    double su = 0, suu = 0, sx = 0, sux = 0, sv = 0, svv = 0, sy = 0, svy = 0, du, dv;
    size_t m = 0;
    if (!f->xyz)
        return 0;
    for (int v = 0; v < f->height; ++v)
        for (int u = 0; u < f->width; ++u) {
            const float *q = f->xyz + 3 * ((size_t)v * f->width + u);
            double x, y;
            if (!isfinite(q[2]) || q[2] == 0.0f)
                continue;
            x = q[0] / q[2];
            y = q[1] / q[2];
            su += u, suu += (double)u * u, sx += x, sux += u * x;
            sv += v, svv += (double)v * v, sy += y, svy += v * y;
            ++m;
        }
    if (m < 3)
        return 0;
    du = m * suu - su * su;
    dv = m * svv - sv * sv;
    if (!(du > 0) || !(dv > 0))
        return 0;
    cam[0] = (m * sux - su * sx) / du;
    cam[1] = (sx - cam[0] * su) / m;
    cam[2] = (m * svy - sv * sy) / dv;
    cam[3] = (sy - cam[2] * sv) / m;
    return 1;
}

void relief_depth_cloud_fill(relief_depth_image *f, const uint8_t *missing,
                             const int64_t *source, const double *cam)
{
    size_t n = (size_t)f->width * f->height;
    for (size_t i = 0; i < n; ++i) {
        int u = (int)(i % (size_t)f->width), v = (int)(i / (size_t)f->width);
        float *q = f->xyz + 3 * i;
        if (!missing[i])
            continue;
        q[0] = cam ? (float)((cam[0] * u + cam[1]) * f->z[i]) : NAN;
        q[1] = cam ? (float)((cam[2] * v + cam[3]) * f->z[i]) : NAN;
        q[2] = cam ? f->z[i] : NAN;
        if (f->rgb) {
            /* The source is a captured pixel: never one written here. */
            if (source[i] >= 0)
                memcpy(f->rgb + 3 * i, f->rgb + 3 * (size_t)source[i], 3);
            else
                memset(f->rgb + 3 * i, 0, 3);
        }
    }
}

typedef struct points_ctx {
    const relief_depth_image *f;
    const uint8_t *label;
} points_ctx;

static relief_status write_points(relief_sink *s, void *ctx, relief_error *err)
{
    FILE *fp = s->f;
    const points_ctx *c = ctx;
    const relief_depth_image *f = c->f;
    size_t n = (size_t)f->width * f->height, m = 0;
    for (size_t i = 0; i < n; ++i)
        m += isfinite(f->xyz[3 * i + 2]);
    fprintf(fp, "ply\nformat binary_little_endian 1.0\ncomment relief depth-fill\n"
            "element vertex %zu\nproperty float x\nproperty float y\nproperty float z\n%s"
            "property uchar label\nend_header\n", m,
            f->rgb ? "property uchar red\nproperty uchar green\nproperty uchar blue\n" : "");
    for (size_t i = 0; i < n; ++i) {
        uint8_t rec[16];
        size_t k = 12;
        if (!isfinite(f->xyz[3 * i + 2]))
            continue;
        memcpy(rec, f->xyz + 3 * i, 12); /* little-endian hosts only (as the PLY writer) */
        if (f->rgb) {
            memcpy(rec + 12, f->rgb + 3 * i, 3);
            k = 15;
        }
        rec[k++] = c->label[i];
        if (fwrite(rec, 1, k, fp) != k)
            return relief_fail_errno(err, errno ? errno : EIO, s->path, "cannot write");
    }
    return RELIEF_OK;
}

relief_status relief_depth_points_write_to(relief_sink *s, const relief_depth_image *f,
                                           const uint8_t *label, relief_error *err)
{
    points_ctx c = {f, label};
    return write_points(s, &c, err);
}

relief_status relief_depth_points_write(const char *path, const relief_depth_image *f,
                                        const uint8_t *label, relief_error *err)
{
    points_ctx c = {f, label};
    return relief_output_file(path, write_points, &c, err);
}
