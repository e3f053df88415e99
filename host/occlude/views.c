/* The second cue of paper 004's section 2.1 (eq. 2.1): a pixel's
 * correspondence error against registered neighbouring views. The pixel's
 * background point is projected into each view and its window's lightness
 * searched for around there; a background pixel is found where its point
 * says, a foreground one, nearer the camera, is displaced by its parallax.
 * The search runs along the epipolar line: a displacement towards where
 * the ray's nearer points project is a point in front of the background.
 * The error is the larger displacement over the views. */
#include "occlude/occlude.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"

/* The window compared: (2 HALF + 1)^2 pixels of L*. */
#define HALF 2
/* A match is trusted when its SSD is under this share of the search's
 * mean SSD (a peak, not noise on a flat colour) ... */
#define PEAK 0.4
/* ... and the zero displacement is kept when within this factor of the
 * best (the sensor's noise between two views). */
#define ZERO_SLACK 1.25
/* The farthest a search goes along the epipolar line, pixels. */
#define MAX_REACH 64

/* View k's camera: its own intrinsics, or the frame's (x / z = cam[0] u +
 * cam[1] inverted: u = x / z / cam[0] - cam[1] / cam[0]). */
static relief_status view_camera(const occ_scene *s, const relief_occluder_view *w, int k,
                                 occ_view_camera *c, relief_error *err)
{
    const double *in = w->intrinsics;
    int own = in[0] != 0.0 || in[1] != 0.0 || in[2] != 0.0 || in[3] != 0.0;
    if (!w->rgb)
        return relief_fail(err, RELIEF_E_USAGE, "view %d: rgb: NULL", k);
    if (!own && (w->width != s->width || w->height != s->height))
        return relief_fail(err, RELIEF_E_USAGE, "view %d is %d x %d pixels, the frame %d x %d: "
                           "a view through the frame's camera is of its size (give the view's "
                           "intrinsics)", k, w->width, w->height, s->width, s->height);
    if (w->width < 2 * HALF + 1 || w->height < 2 * HALF + 1)
        return relief_fail(err, RELIEF_E_RANGE, "view %d is %d x %d pixels: expected at least "
                           "%d x %d", k, w->width, w->height, 2 * HALF + 1, 2 * HALF + 1);
    c->width = w->width, c->height = w->height;
    if (own)
        c->fx = in[0], c->fy = in[1], c->cx = in[2], c->cy = in[3];
    else
        c->fx = 1.0 / s->cam[0], c->cx = -s->cam[1] / s->cam[0],
        c->fy = 1.0 / s->cam[2], c->cy = -s->cam[3] / s->cam[2];
    return RELIEF_OK;
}

/* Each view's L*, one after the other in v->lum. */
static relief_status view_lightness(occ_views *v, size_t total, relief_error *err)
{
    size_t at = 0, most = 0;
    float *tmp;
    for (int k = 0; k < v->p->n_views; ++k)
        if ((size_t)v->cam[k].width * v->cam[k].height > most)
            most = (size_t)v->cam[k].width * v->cam[k].height;
    v->lum = malloc(total * sizeof *v->lum);
    tmp = malloc(most * 3 * sizeof *tmp);
    if (!v->lum || !tmp) {
        free(tmp);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the views' %zu pixels", total);
    }
    for (int k = 0; k < v->p->n_views; ++k) {
        size_t m = (size_t)v->cam[k].width * v->cam[k].height;
        occ_lab(v->p->views[k].rgb, m, tmp);
        for (size_t i = 0; i < m; ++i)
            v->lum[at + i] = tmp[3 * i];
        v->cam[k].lum = v->lum + at;
        at += m;
    }
    free(tmp);
    return RELIEF_OK;
}

relief_status occ_views_init(occ_views *v, const occ_scene *s, const float *lab,
                             const relief_occluder_params *p, relief_error *err)
{
    size_t n = (size_t)s->width * s->height, total = 0;
    relief_status st;
    memset(v, 0, sizeof *v);
    v->s = s, v->p = p, v->lab = lab;
    if (p->n_views == 0)
        return RELIEF_OK;
    for (int k = 0; k < p->n_views; ++k) {
        if ((st = view_camera(s, &p->views[k], k, &v->cam[k], err)) != RELIEF_OK)
            return st;
        total += (size_t)v->cam[k].width * v->cam[k].height;
    }
    if ((st = view_lightness(v, total, err)) != RELIEF_OK) {
        occ_views_free(v);
        return st;
    }
    if (!(v->cue = malloc(n))) {
        occ_views_free(v);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the views' verdicts");
    }
    memset(v->cue, OCC_CUE_UNSEEN, n);
    return RELIEF_OK;
}

void occ_views_free(occ_views *v)
{
    free(v->lum);
    free(v->cue);
    v->lum = NULL, v->cue = NULL;
}

/* SSD of the frame's window at (u, y0) against view c's at (x, y); -1
 * when the view's window leaves the view. */
static double ssd(const occ_views *v, const occ_view_camera *c, int u, int y0, int x, int y)
{
    const occ_scene *s = v->s;
    double sum = 0.0;
    if (x < HALF || y < HALF || x + HALF >= c->width || y + HALF >= c->height)
        return -1.0;
    for (int dy = -HALF; dy <= HALF; ++dy)
        for (int dx = -HALF; dx <= HALF; ++dx) {
            double d = v->lab[3 * ((size_t)(y0 + dy) * s->width + (u + dx))] -
                       c->lum[(size_t)(y + dy) * c->width + (x + dx)];
            sum += d * d;
        }
    return sum;
}

/* Where view k sees the point p (frame camera coordinates): *px, *py;
 * 0 when behind the view. */
static int project(const occ_views *v, int k, const double p[3], double *px, double *py)
{
    const double *m = v->p->views[k].pose;
    const occ_view_camera *c = &v->cam[k];
    double y[3];
    for (int r = 0; r < 3; ++r)
        y[r] = m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] + m[4 * r + 3];
    if (!(y[2] > 0.0))
        return 0;
    *px = c->fx * y[0] / y[2] + c->cx;
    *py = c->fy * y[1] / y[2] + c->cy;
    return 1;
}

/* The displacement (pixels, signed) of pixel (u, y0)'s window in view k
 * along its epipolar line: 0 where its background point x (depth z)
 * projects, positive towards where nearer points of its ray project.
 * Searched from view_radius pixels behind to where the ray's point at half
 * the depth projects (at least view_radius). 0 and *ok = 0 when no
 * match is trusted (no texture, no parallax possible, out of the view). */
static double displacement(const occ_views *v, int k, int u, int y0, const double x[3],
                           int *ok)
{
    const occ_view_camera *c = &v->cam[k];
    double qx, qy, nx, ny, near[3] = {0.5 * x[0], 0.5 * x[1], 0.5 * x[2]}, len;
    double best = HUGE_VAL, total = 0.0, zero = -1.0;
    int r = v->p->view_radius, hi, bt = 0, n = 0;
    *ok = 0;
    if (!project(v, k, x, &qx, &qy) || !project(v, k, near, &nx, &ny))
        return 0.0;
    nx -= qx, ny -= qy;
    len = sqrt(nx * nx + ny * ny);
    if (!(len > 0.5))
        return 0.0; /* the views' baseline shows no parallax here */
    nx /= len, ny /= len;
    /* Forwards the search reaches where the ray's point at half the
     * background's depth projects (len pixels: an occluder anywhere in
     * the nearer half of the ray is found, whatever the baseline), and
     * view_radius at least; backwards view_radius. */
    hi = len > r ? (int)ceil(len) : r;
    if (hi > MAX_REACH)
        hi = MAX_REACH;
    for (int t = -r; t <= hi; ++t) {
        double e = ssd(v, c, u, y0, (int)lround(qx + t * nx), (int)lround(qy + t * ny));
        if (e < 0.0)
            continue;
        if (t == 0)
            zero = e;
        total += e, ++n;
        if (e < best)
            best = e, bt = t;
    }
    if (n < 3 || zero < 0.0 || !(best <= PEAK * total / n))
        return 0.0;
    *ok = 1;
    return zero <= ZERO_SLACK * best ? 0.0 : bt;
}

/* The displacements of pixel i over the views: *lo the smallest, *hi the
 * larger (eq. 2.1's correspondence error); returns how many views gave a
 * trusted one. */
static int displacements(const occ_views *v, size_t i, double *lo, double *hi)
{
    const occ_scene *s = v->s;
    int u = (int)(i % (size_t)s->width), y0 = (int)(i / (size_t)s->width), n = 0;
    double x[3], z = s->surface[i];
    if (!isfinite(z) || u < HALF || y0 < HALF || u + HALF >= s->width || y0 + HALF >= s->height)
        return 0;
    x[0] = (s->cam[0] * u + s->cam[1]) * z, x[1] = (s->cam[2] * y0 + s->cam[3]) * z, x[2] = z;
    *lo = HUGE_VAL, *hi = -HUGE_VAL;
    for (int k = 0; k < v->p->n_views; ++k) {
        int ok;
        double d = displacement(v, k, u, y0, x, &ok);
        if (ok)
            *lo = fmin(*lo, d), *hi = fmax(*hi, d), ++n;
    }
    return n;
}

/* Background when even the larger displacement (eq. 2.1's error) is at
 * most parallax: every view that matched sees the pixel where its
 * background point says. Foreground when every view matched and even the
 * smallest is over it: a view that sees behind an occluder's edge (a
 * background point hidden from the other view) does not make it
 * foreground. */
int occ_views_cue(occ_views *v, size_t i)
{
    double lo, hi;
    int n;
    if (!v->cue)
        return OCC_CUE_UNKNOWN;
    if (v->cue[i] != OCC_CUE_UNSEEN)
        return v->cue[i];
    n = displacements(v, i, &lo, &hi);
    if (n == 0)
        v->cue[i] = OCC_CUE_UNKNOWN;
    else if (fabs(lo) <= v->p->parallax && fabs(hi) <= v->p->parallax)
        v->cue[i] = OCC_CUE_BACKGROUND;
    else
        v->cue[i] = n == v->p->n_views && lo > v->p->parallax ? OCC_CUE_FOREGROUND
                                                               : OCC_CUE_UNKNOWN;
    ++*(v->cue[i] == OCC_CUE_UNKNOWN ? &v->unknown : v->cue[i] ? &v->fg : &v->bg);
    return v->cue[i];
}
