#include "report/render.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/compare.h"
#include "base/error.h"
#include "base/vec3.h"
#include "mesh/mesh.h"

#define DEG (RELIEF_PI / 180.0)

const float relief_render_label_rgb[2][3] = {{0.72f, 0.72f, 0.72f}, {0.96f, 0.52f, 0.10f}};
static const float uniform_rgb[3] = {0.72f, 0.72f, 0.72f};

const char *relief_colour_by_name(relief_colour_by c)
{
    switch (c) {
    case RELIEF_COLOUR_BY_AUTO: return "auto";
    case RELIEF_COLOUR_BY_LABEL: return "label";
    case RELIEF_COLOUR_BY_COLOUR: return "colour";
    case RELIEF_COLOUR_BY_DISPLACEMENT: return "displacement";
    case RELIEF_COLOUR_BY_NONE: return "none";
    }
    return "?";
}

relief_render_options relief_render_options_default(void)
{
    relief_render_options o;
    memset(&o, 0, sizeof o);
    o.width = RELIEF_RENDER_DEFAULT_WIDTH;
    o.height = RELIEF_RENDER_DEFAULT_HEIGHT;
    o.colour_by = RELIEF_COLOUR_BY_AUTO;
    return o;
}

void relief_rgb_image_free(relief_rgb_image *img)
{
    if (img) {
        free(img->rgb);
        img->rgb = NULL;
        img->width = img->height = 0;
    }
}

static double normalise3(double *a)
{
    double n = sqrt(dot3(a, a));
    if (n > 0.0) {
        a[0] /= n;
        a[1] /= n;
        a[2] /= n;
    }
    return n;
}

/* Twice the area times the unit normal of triangle t. */
static void face_normal(const relief_mesh *m, size_t t, double *n)
{
    const uint32_t *f = m->tri + 3 * t;
    double e1[3], e2[3];
    sub3(m->pos + 3 * (size_t)f[1], m->pos + 3 * (size_t)f[0], e1);
    sub3(m->pos + 3 * (size_t)f[2], m->pos + 3 * (size_t)f[0], e2);
    cross3(e1, e2, n);
}

void relief_render_default_view(const relief_mesh *m, double *azimuth, double *elevation)
{
    relief_render_part_view(m, RELIEF_LABEL_CAPTURED, azimuth, elevation);
}

void relief_render_part_view(const relief_mesh *m, int part, double *azimuth,
                             double *elevation)
{
    double sum[3] = {0.0, 0.0, 0.0}, mag = 0.0, n[3], len, az, el;
    if (!m->label)
        part = -1;
    if (m->nt > 0) {
        for (size_t t = 0; t < m->nt; ++t) {
            const uint32_t *f = m->tri + 3 * t;
            if (part >= 0 && (m->label[f[0]] != part || m->label[f[1]] != part ||
                              m->label[f[2]] != part))
                continue;
            face_normal(m, t, n);
            for (int k = 0; k < 3; ++k)
                sum[k] += n[k];
            mag += sqrt(dot3(n, n));
        }
    } else if (m->nrm) {
        for (size_t v = 0; v < m->nv; ++v) {
            if (part >= 0 && m->label[v] != part)
                continue;
            for (int k = 0; k < 3; ++k)
                sum[k] += m->nrm[3 * v + k];
            mag += sqrt(dot3(m->nrm + 3 * v, m->nrm + 3 * v));
        }
    }
    len = sqrt(dot3(sum, sum));
    /* A closed (or nearly closed) captured part has no side to look at. */
    if (!(mag > 0.0) || len < 0.05 * mag) {
        *azimuth = 30.0;
        *elevation = 20.0;
        return;
    }
    az = atan2(sum[1], sum[0]) / DEG;
    el = asin(fmax(-1.0, fmin(1.0, sum[2] / len))) / DEG;
    az += RELIEF_RENDER_TURN_AZ;
    el += el > 60.0 ? -RELIEF_RENDER_TURN_EL : RELIEF_RENDER_TURN_EL;
    if (az > 180.0)
        az -= 360.0;
    *azimuth = az;
    *elevation = el;
}

/* ------------------------------------------------------------ colours */

/* The primitive displacement colours are measured from: fitted to the
 * captured part as relief_measure does, so `relief render --colour-by
 * displacement` and `relief eval` agree on the heights. */
static relief_status fit_captured(const relief_mesh *m, relief_fit_primitive *prim,
                                  relief_error *err)
{
    relief_fit_result fr;
    relief_mesh *sub = NULL;
    const relief_mesh *src = m;
    relief_status st = RELIEF_OK;
    size_t n0 = 0;
    if (m->label) {
        for (size_t v = 0; v < m->nv; ++v)
            n0 += m->label[v] == RELIEF_LABEL_CAPTURED;
        if (n0 > 0 && n0 < m->nv) {
            uint8_t *keep = malloc(m->nv);
            if (!keep)
                return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate %zu labels", m->nv);
            for (size_t v = 0; v < m->nv; ++v)
                keep[v] = m->label[v] == RELIEF_LABEL_CAPTURED;
            st = relief_mesh_subset(m, keep, &sub, NULL, err);
            free(keep);
            src = sub;
        }
    }
    if (st == RELIEF_OK)
        st = relief_fit_mesh(src, RELIEF_FIT_AUTO, &fr, err);
    if (st == RELIEF_OK)
        *prim = fr.prim;
    else if (st == RELIEF_E_MESH && err) {
        char why[RELIEF_ERROR_MESSAGE_MAX];
        snprintf(why, sizeof why, "%s", err->message);
        st = relief_fail(err, RELIEF_E_MESH, "cannot colour by displacement: %s", why);
    }
    relief_mesh_destroy(sub);
    return st;
}

/* Blue - light grey - red, t in [-1, 1] (after Moreland's cool-warm map). */
static void diverging(double t, float *rgb)
{
    static const float lo[3] = {0.23f, 0.30f, 0.75f}, mid[3] = {0.87f, 0.87f, 0.87f},
                       hi[3] = {0.71f, 0.02f, 0.15f};
    const float *end = t < 0.0 ? lo : hi;
    float a = (float)fmin(1.0, fabs(t));
    for (int k = 0; k < 3; ++k)
        rgb[k] = mid[k] + a * (end[k] - mid[k]);
}

static relief_status vertex_colours(const relief_mesh *m, const relief_render_options *o,
                                    float *rgb, relief_render_info *info, relief_error *err)
{
    relief_colour_by by = o->colour_by;
    if (by == RELIEF_COLOUR_BY_AUTO)
        by = m->col ? RELIEF_COLOUR_BY_COLOUR
                    : m->label ? RELIEF_COLOUR_BY_LABEL : RELIEF_COLOUR_BY_NONE;
    info->colour_by = by;
    info->displacement_range = 0.0;
    switch (by) {
    case RELIEF_COLOUR_BY_COLOUR:
        if (!m->col)
            return relief_fail(err, RELIEF_E_MESH, "the mesh has no per-vertex colour to "
                               "render; try colour_by label or displacement");
        memcpy(rgb, m->col, m->nv * 3 * sizeof *rgb);
        return RELIEF_OK;
    case RELIEF_COLOUR_BY_LABEL:
        if (!m->label)
            return relief_fail(err, RELIEF_E_MESH, "the mesh has no label property "
                               "(0 captured, 1 completed) to colour by");
        for (size_t v = 0; v < m->nv; ++v) {
            if (m->label[v] > RELIEF_LABEL_COMPLETED)
                return relief_fail(err, RELIEF_E_MESH, "vertex %zu has label %u; expected "
                                   "0 (captured) or 1 (completed)", v, m->label[v]);
            memcpy(rgb + 3 * v, relief_render_label_rgb[m->label[v]], 3 * sizeof *rgb);
        }
        return RELIEF_OK;
    case RELIEF_COLOUR_BY_DISPLACEMENT: {
        relief_fit_primitive prim;
        double *h, range = o->displacement_range;
        relief_status st = RELIEF_OK;
        if (o->prim)
            prim = *o->prim;
        else
            st = fit_captured(m, &prim, err);
        if (st != RELIEF_OK)
            return st;
        h = malloc(m->nv * 2 * sizeof *h);
        if (!h)
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate %zu heights", m->nv);
        for (size_t v = 0; v < m->nv; ++v) {
            h[v] = relief_fit_distance(&prim, m->pos + 3 * v);
            h[m->nv + v] = fabs(h[v]);
        }
        if (!(range > 0.0)) {
            /* A robust range: a few spikes must not wash the map out. */
            qsort(h + m->nv, m->nv, sizeof *h, relief_cmp_double);
            range = h[m->nv + (size_t)(0.99 * (double)(m->nv - 1))];
            if (!(range > 0.0))
                range = 1.0; /* every height 0: all mid grey */
        }
        for (size_t v = 0; v < m->nv; ++v)
            diverging(h[v] / range, rgb + 3 * v);
        free(h);
        info->displacement_range = range;
        return RELIEF_OK;
    }
    case RELIEF_COLOUR_BY_NONE:
    case RELIEF_COLOUR_BY_AUTO:
        for (size_t v = 0; v < m->nv; ++v)
            memcpy(rgb + 3 * v, uniform_rgb, sizeof uniform_rgb);
        return RELIEF_OK;
    }
    return relief_fail(err, RELIEF_E_USAGE, "unknown colouring %d", (int)by);
}

/* ------------------------------------------------------------- raster */

typedef struct camera {
    double centre[3], dir[3], right[3], up[3], light[3], half[3];
    double scale;      /* supersampled pixels per input unit */
    double off[2];     /* screen coordinates of the image centre */
    int w, h;          /* supersampled size */
} camera;

static void camera_setup(camera *c, double az, double el)
{
    double up_w[3] = {0.0, 0.0, 1.0};
    c->dir[0] = cos(el * DEG) * cos(az * DEG);
    c->dir[1] = cos(el * DEG) * sin(az * DEG);
    c->dir[2] = sin(el * DEG);
    if (fabs(c->dir[2]) > 0.9999985) { /* within 0.1 degree of the z axis */
        up_w[1] = 1.0;
        up_w[2] = 0.0;
    }
    cross3(up_w, c->dir, c->right);
    normalise3(c->right);
    cross3(c->dir, c->right, c->up);
    for (int k = 0; k < 3; ++k)
        c->light[k] = c->dir[k] + 0.6 * c->up[k] - 0.45 * c->right[k];
    normalise3(c->light);
    for (int k = 0; k < 3; ++k)
        c->half[k] = c->light[k] + c->dir[k];
    normalise3(c->half);
}

/* Screen x, y (supersampled pixels, y down) and depth (towards the camera). */
static void project(const camera *c, const double *p, double *s)
{
    double q[3];
    sub3(p, c->centre, q);
    s[0] = 0.5 * c->w + (dot3(q, c->right) - c->off[0]) * c->scale;
    s[1] = 0.5 * c->h - (dot3(q, c->up) - c->off[1]) * c->scale;
    s[2] = dot3(q, c->dir);
}

/* Fit the projection of `f`'s vertices into the image. */
static void camera_frame(camera *c, const relief_mesh *f, double margin)
{
    double lo[2] = {DBL_MAX, DBL_MAX}, hi[2] = {-DBL_MAX, -DBL_MAX}, ext[2], q[3], sx, sy;
    double box_lo[3] = {DBL_MAX, DBL_MAX, DBL_MAX}, box_hi[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX};
    for (size_t v = 0; v < f->nv; ++v)
        for (int k = 0; k < 3; ++k) {
            box_lo[k] = fmin(box_lo[k], f->pos[3 * v + k]);
            box_hi[k] = fmax(box_hi[k], f->pos[3 * v + k]);
        }
    for (int k = 0; k < 3; ++k)
        c->centre[k] = 0.5 * (box_lo[k] + box_hi[k]);
    for (size_t v = 0; v < f->nv; ++v) {
        double s[2];
        sub3(f->pos + 3 * v, c->centre, q);
        s[0] = dot3(q, c->right);
        s[1] = dot3(q, c->up);
        for (int k = 0; k < 2; ++k) {
            lo[k] = fmin(lo[k], s[k]);
            hi[k] = fmax(hi[k], s[k]);
        }
    }
    for (int k = 0; k < 2; ++k) {
        ext[k] = hi[k] - lo[k];
        c->off[k] = 0.5 * (lo[k] + hi[k]);
    }
    sx = ext[0] > 0.0 ? c->w * (1.0 - 2.0 * margin) / ext[0] : DBL_MAX;
    sy = ext[1] > 0.0 ? c->h * (1.0 - 2.0 * margin) / ext[1] : DBL_MAX;
    c->scale = fmin(sx, sy);
    if (c->scale == DBL_MAX) /* a single point */
        c->scale = 1.0;
}

static void shade(const camera *c, const double *n_in, int back, const float *alb, float *out)
{
    double n[3] = {n_in[0], n_in[1], n_in[2]}, diff, spec;
    normalise3(n);
    diff = fmax(0.0, dot3(n, c->light));
    spec = pow(fmax(0.0, dot3(n, c->half)), 40.0);
    for (int k = 0; k < 3; ++k) {
        double v = alb[k] * (0.28 + 0.72 * diff) + 0.12 * spec;
        out[k] = (float)(back ? RELIEF_RENDER_BACK * v : v);
    }
}

static void draw_triangle(const camera *c, const relief_mesh *m, size_t t, const double *scr,
                          const double *vn, const float *alb, float *zbuf, float *img)
{
    const uint32_t *f = m->tri + 3 * t;
    const double *a = scr + 3 * (size_t)f[0], *b = scr + 3 * (size_t)f[1],
                 *d = scr + 3 * (size_t)f[2];
    double area = (b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]), fn[3];
    int x0, x1, y0, y1, back;
    if (!(fabs(area) > 1e-12))
        return; /* seen edge-on */
    face_normal(m, t, fn);
    back = dot3(fn, c->dir) < 0.0;
    x0 = (int)fmax(0.0, floor(fmin(a[0], fmin(b[0], d[0]))));
    x1 = (int)fmin(c->w - 1.0, ceil(fmax(a[0], fmax(b[0], d[0]))));
    y0 = (int)fmax(0.0, floor(fmin(a[1], fmin(b[1], d[1]))));
    y1 = (int)fmin(c->h - 1.0, ceil(fmax(a[1], fmax(b[1], d[1]))));
    for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
            double px = x + 0.5, py = y + 0.5, w[3], z, n[3];
            float col[3];
            size_t i = (size_t)y * (size_t)c->w + (size_t)x;
            w[0] = ((b[0] - px) * (d[1] - py) - (b[1] - py) * (d[0] - px)) / area;
            w[1] = ((d[0] - px) * (a[1] - py) - (d[1] - py) * (a[0] - px)) / area;
            w[2] = 1.0 - w[0] - w[1];
            if (w[0] < 0.0 || w[1] < 0.0 || w[2] < 0.0)
                continue;
            z = w[0] * a[2] + w[1] * b[2] + w[2] * d[2];
            if (!(z > zbuf[i]))
                continue;
            zbuf[i] = (float)z;
            for (int k = 0; k < 3; ++k) {
                n[k] = 0.0;
                col[k] = 0.0f;
                for (int j = 0; j < 3; ++j) {
                    n[k] += w[j] * vn[3 * (size_t)f[j] + k];
                    col[k] += (float)w[j] * alb[3 * (size_t)f[j] + k];
                }
                if (back)
                    n[k] = -n[k];
            }
            shade(c, n, back, col, img + 3 * i);
        }
}

static void draw_points(const camera *c, const relief_mesh *m, const double *scr,
                        const float *alb, float *zbuf, float *img)
{
    /* Splats about one point spacing wide: the image area the points span
     * shared among them. */
    double lo[2] = {DBL_MAX, DBL_MAX}, hi[2] = {-DBL_MAX, -DBL_MAX}, r;
    for (size_t v = 0; v < m->nv; ++v)
        for (int k = 0; k < 2; ++k) {
            lo[k] = fmin(lo[k], scr[3 * v + k]);
            hi[k] = fmax(hi[k], scr[3 * v + k]);
        }
    r = 0.5 * sqrt((hi[0] - lo[0]) * (hi[1] - lo[1]) / (double)m->nv);
    r = fmax(1.0, fmin(r, 6.0 * RELIEF_RENDER_SUPERSAMPLE));
    for (size_t v = 0; v < m->nv; ++v) {
        const double *s = scr + 3 * v;
        float col[3];
        int back = 0;
        if (m->nrm) {
            double n[3] = {m->nrm[3 * v], m->nrm[3 * v + 1], m->nrm[3 * v + 2]};
            back = dot3(n, c->dir) < 0.0;
            if (back)
                for (int k = 0; k < 3; ++k)
                    n[k] = -n[k];
            shade(c, n, back, alb + 3 * v, col);
        } else {
            for (int k = 0; k < 3; ++k)
                col[k] = 0.85f * alb[3 * v + k];
        }
        for (int y = (int)fmax(0.0, floor(s[1] - r)); y <= (int)fmin(c->h - 1.0, s[1] + r); ++y)
            for (int x = (int)fmax(0.0, floor(s[0] - r)); x <= (int)fmin(c->w - 1.0, s[0] + r);
                 ++x) {
                size_t i = (size_t)y * (size_t)c->w + (size_t)x;
                if (s[2] > zbuf[i]) {
                    zbuf[i] = (float)s[2];
                    memcpy(img + 3 * i, col, sizeof col);
                }
            }
    }
}

/* The options' and mesh's checks before anything is allocated. */
static relief_status render_check(const relief_mesh *m, const relief_render_options *o,
                                  relief_error *err)
{
    if (o->width < 1 || o->height < 1 || o->width > RELIEF_RENDER_MAX_SIDE ||
        o->height > RELIEF_RENDER_MAX_SIDE)
        return relief_fail(err, RELIEF_E_RANGE, "image size %dx%d is out of range: expected "
                           "1..%d pixels per side", o->width, o->height,
                           RELIEF_RENDER_MAX_SIDE);
    if (o->has_view && (!isfinite(o->azimuth) || !(fabs(o->elevation) <= 90.0)))
        return relief_fail(err, RELIEF_E_RANGE, "view azimuth %g, elevation %g is out of "
                           "range: expected a finite azimuth and an elevation in -90..90 "
                           "degrees", o->azimuth, o->elevation);
    if (!(o->displacement_range >= 0.0) || !isfinite(o->displacement_range))
        return relief_fail(err, RELIEF_E_RANGE, "displacement range %g: expected a length "
                           ">= 0 (0: automatic)", o->displacement_range);
    if (m->nv == 0)
        return relief_fail(err, RELIEF_E_MESH, "the mesh has no vertices to render");
    return relief_mesh_validate(m, err);
}

/* Draw m into the supersampled c->w x c->h buffers: zbuf (depth towards
 * the camera) and img (3 floats a pixel, linear 0..1), cleared to the
 * background first. scr and vn: 3 nv scratch for the screen positions
 * and vertex normals; alb: 3 nv vertex colours. */
static void rasterise(const camera *c, const relief_mesh *m, const float *alb, double *scr,
                      double *vn, float *zbuf, float *img)
{
    const float bg[3] = {RELIEF_RENDER_BACKGROUND_R / 255.0f,
                         RELIEF_RENDER_BACKGROUND_G / 255.0f,
                         RELIEF_RENDER_BACKGROUND_B / 255.0f};
    const size_t npx = (size_t)c->w * (size_t)c->h;
    for (size_t v = 0; v < m->nv; ++v)
        project(c, m->pos + 3 * v, scr + 3 * v);
    for (size_t i = 0; i < npx; ++i) {
        zbuf[i] = -FLT_MAX;
        memcpy(img + 3 * i, bg, sizeof bg);
    }
    if (m->nt > 0) {
        relief_mesh_vertex_normals(m, vn); /* not normalised; shade does */
        for (size_t t = 0; t < m->nt; ++t)
            draw_triangle(c, m, t, scr, vn, alb, zbuf, img);
    } else {
        draw_points(c, m, scr, alb, zbuf, img);
    }
}

/* Box filter img (supersampled by ss, row length w_ss pixels, 3 floats
 * a pixel) down to the width x height output, 3 bytes a pixel. */
static void downsample(const float *img, int w_ss, int ss, int width, int height, uint8_t *rgb)
{
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int k = 0; k < 3; ++k) {
                double s = 0.0;
                for (int j = 0; j < ss; ++j)
                    for (int i = 0; i < ss; ++i)
                        s += img[3 * ((size_t)(y * ss + j) * (size_t)w_ss + (size_t)(x * ss + i)) +
                                 k];
                s = fmin(1.0, fmax(0.0, s / (ss * ss)));
                rgb[3 * ((size_t)y * (size_t)width + (size_t)x) + k] = (uint8_t)lround(s * 255.0);
            }
}

relief_status relief_render(const relief_mesh *m, const relief_render_options *o,
                            relief_rgb_image *out, relief_render_info *info_out,
                            relief_error *err)
{
    const int ss = RELIEF_RENDER_SUPERSAMPLE;
    relief_render_info info;
    camera c;
    float *alb = NULL, *zbuf = NULL, *img = NULL;
    double *vn = NULL, *scr = NULL;
    uint8_t *rgb = NULL;
    size_t npx;
    relief_status st;

    if (!m || !o || !out)
        return relief_fail(err, RELIEF_E_USAGE, "relief_render: NULL argument");
    if ((st = render_check(m, o, err)) != RELIEF_OK)
        return st;

    memset(&info, 0, sizeof info);
    if (o->has_view) {
        info.azimuth = o->azimuth;
        info.elevation = o->elevation;
    } else {
        relief_render_default_view(m, &info.azimuth, &info.elevation);
    }
    c.w = o->width * ss;
    c.h = o->height * ss;
    npx = (size_t)c.w * (size_t)c.h;
    alb = malloc(m->nv * 3 * sizeof *alb);
    vn = malloc(m->nv * 3 * sizeof *vn);
    scr = malloc(m->nv * 3 * sizeof *scr);
    zbuf = malloc(npx * sizeof *zbuf);
    img = malloc(npx * 3 * sizeof *img);
    rgb = malloc((size_t)o->width * (size_t)o->height * 3);
    if (!alb || !vn || !scr || !zbuf || !img || !rgb) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a %dx%d render of %zu vertices",
                         o->width, o->height, m->nv);
        goto done;
    }
    st = vertex_colours(m, o, alb, &info, err);
    if (st != RELIEF_OK)
        goto done;

    camera_setup(&c, info.azimuth, info.elevation);
    camera_frame(&c, o->frame && o->frame->nv > 0 ? o->frame : m, RELIEF_RENDER_MARGIN);
    info.pixel_size = ss / c.scale;
    rasterise(&c, m, alb, scr, vn, zbuf, img);
    downsample(img, c.w, ss, o->width, o->height, rgb);
    out->width = o->width;
    out->height = o->height;
    out->rgb = rgb;
    rgb = NULL;
    if (info_out)
        *info_out = info;
done:
    free(rgb);
    free(img);
    free(zbuf);
    free(scr);
    free(vn);
    free(alb);
    return st;
}
