/* Plane, sphere and cylinder fitting with robust trimming and model choice.
 * The method, its constants and the units are described in fit.h. */
#include "smooth/fit.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/linalg.h"
#include "base/vec3.h"
#include "mesh/mesh.h"
#include "smooth/fit_robust.h"

/* ------------------------------------------------------------- geometry */

double relief_fit_distance(const relief_fit_primitive *prim, const double p[3])
{
    double w[3], d = NAN;

    for (int k = 0; k < 3; ++k)
        w[k] = p[k] - prim->point[k];
    switch (prim->model) {
    case RELIEF_FIT_PLANE:
        d = dot3(w, prim->dir);
        break;
    case RELIEF_FIT_SPHERE:
        d = sqrt(dot3(w, w)) - prim->radius;
        break;
    case RELIEF_FIT_CYLINDER: {
        double t = dot3(w, prim->dir);
        for (int k = 0; k < 3; ++k)
            w[k] -= t * prim->dir[k];
        d = sqrt(dot3(w, w)) - prim->radius;
        break;
    }
    case RELIEF_FIT_AUTO:
        break;
    }
    return d;
}

void relief_fit_normal(const relief_fit_primitive *prim, const double p[3],
                       double nrm[3])
{
    double w[3], u[3], v[3];

    for (int k = 0; k < 3; ++k)
        w[k] = p[k] - prim->point[k];
    switch (prim->model) {
    case RELIEF_FIT_PLANE:
        memcpy(w, prim->dir, sizeof w);
        break;
    case RELIEF_FIT_SPHERE:
        if (relief_normalize3(w) == 0.0) {
            w[0] = w[1] = 0.0;
            w[2] = 1.0;
        }
        break;
    case RELIEF_FIT_CYLINDER: {
        double t = dot3(w, prim->dir);
        for (int k = 0; k < 3; ++k)
            w[k] -= t * prim->dir[k];
        if (relief_normalize3(w) == 0.0) {
            relief_perp_basis(prim->dir, u, v);
            memcpy(w, u, sizeof w);
        }
        break;
    }
    case RELIEF_FIT_AUTO:
        w[0] = w[1] = w[2] = NAN;
        break;
    }
    memcpy(nrm, w, sizeof w);
}

void relief_fit_project(const relief_fit_primitive *prim, const double p[3],
                        double q[3])
{
    double nrm[3], d = relief_fit_distance(prim, p);

    relief_fit_normal(prim, p, nrm);
    for (int k = 0; k < 3; ++k)
        q[k] = p[k] - d * nrm[k];
}

/* ---------------------------------------------------------- the driver */

static size_t min_points(relief_fit_model model)
{
    return model == RELIEF_FIT_SPHERE ? 4 : model == RELIEF_FIT_CYLINDER ? 5 : 3;
}

static int n_params(relief_fit_model model)
{
    return model == RELIEF_FIT_SPHERE ? 4 : model == RELIEF_FIT_CYLINDER ? 5 : 3;
}

/* The auto-selection score of fit.h, lower is better: the RMS over all
 * points of the distances capped at sqrt(cap2), with k fitted parameters.
 * The cap is common to all models, so a point one model trims costs it as
 * much as a point far off any model (truncated least squares, the cost of
 * MSAC and of Torr's GRIC). */
static double model_score(const fit_work *w, const fit_candidate *c,
                          double cap2, int k)
{
    double sum = 0.0;
    double dof = w->n > (size_t)k ? (double)(w->n - (size_t)k) : 1.0;
    for (size_t i = 0; i < w->n; ++i) {
        double d = relief_fit_distance(&c->prim, w->q + 3 * i);
        sum += fmin(d * d, cap2);
    }
    return sqrt(sum / dof) * pow(1.0 + RELIEF_FIT_GAIN, k - 3);
}

static void append(char *buf, size_t cap, const char *fmt, ...)
    RELIEF_PRINTF(3, 4);

static void append(char *buf, size_t cap, const char *fmt, ...)
{
    size_t len = strlen(buf);
    va_list ap;
    if (len + 1 >= cap)
        return;
    va_start(ap, fmt);
    vsnprintf(buf + len, cap - len, fmt, ap);
    va_end(ap);
}

relief_status relief_fit(const double *pts, const double *normals, size_t n,
                         relief_fit_model model, relief_fit_result *out,
                         relief_error *err)
{
    static const relief_fit_model models[3] = {
        RELIEF_FIT_PLANE, RELIEF_FIT_SPHERE, RELIEF_FIT_CYLINDER};
    relief_status st = RELIEF_OK;
    fit_work w, sel;
    double *q = NULL, *q_sel = NULL, c0[3] = {0}, scale = 0.0, cmax = 0.0;
    double m[3], eval[3], evec[9], axes[AXES_IN_PLANE + 2][3];
    fit_candidate cand[4];
    int have[4] = {0}, n_axes, coplanar;
    relief_fit_model best = RELIEF_FIT_AUTO;
    relief_fit_result res;

    memset(&w, 0, sizeof w);
    memset(&res, 0, sizeof res);
    if (!pts || !out) {
        st = relief_fail(err, RELIEF_E_USAGE, "relief_fit: %s is NULL",
                         pts ? "out" : "pts");
        goto done;
    }
    if ((int)model < (int)RELIEF_FIT_AUTO || (int)model > (int)RELIEF_FIT_CYLINDER) {
        st = relief_fail(err, RELIEF_E_USAGE,
                         "relief_fit: unknown model %d; expected auto, plane, "
                         "sphere or cylinder", (int)model);
        goto done;
    }
    if (n < min_points(model)) {
        st = relief_fail(err, RELIEF_E_MESH,
                         "%s fit needs at least %zu points; got %zu",
                         relief_fit_model_name(model), min_points(model), n);
        goto done;
    }
    for (size_t i = 0; i < n; ++i) {
        const double *p = pts + 3 * i;
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) {
            st = relief_fail(err, RELIEF_E_MESH,
                             "point %zu has a non-finite coordinate (%g, %g, %g)",
                             i, p[0], p[1], p[2]);
            goto done;
        }
    }
    if (n > SIZE_MAX / (3 * sizeof(double))) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot fit %zu points: too many", n);
        goto done;
    }
    q = malloc(n * 3 * sizeof *q);
    w.r = malloc(n * sizeof *w.r);
    w.tmp = malloc(n * sizeof *w.tmp);
    w.mask = malloc(n);
    if (!q || !w.r || !w.tmp || !w.mask) {
        st = relief_fail(err, RELIEF_E_NOMEM,
                         "cannot allocate the work space to fit %zu points", n);
        goto done;
    }
    w.n = n;
    w.q = q;

    /* Centre and scale to unit RMS radius: every tolerance below is then
     * relative, whatever the input's units. */
    for (size_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k)
            c0[k] += pts[3 * i + k] / (double)n;
    for (size_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) {
            double d = pts[3 * i + k] - c0[k];
            scale += d * d;
        }
    scale = sqrt(scale / (double)n);
    for (int k = 0; k < 3; ++k)
        cmax = fmax(cmax, fabs(c0[k]));
    /* Identical points still scatter by rounding of the centroid. */
    if (!(scale > 1e-12 * cmax) || scale == 0.0) {
        st = relief_fail(err, RELIEF_E_MESH,
                         "all %zu points coincide at (%g, %g, %g); no %s is "
                         "determined", n, c0[0], c0[1], c0[2],
                         model == RELIEF_FIT_AUTO ? "primitive"
                                                  : relief_fit_model_name(model));
        goto done;
    }
    for (size_t i = 0; i < 3 * n; ++i)
        q[i] = (pts[i] - c0[i % 3]) / scale;

    relief_pca3(q, n, NULL, m, eval, evec);
    if (eval[1] <= FLAT_EIGEN * eval[0]) {
        st = relief_fail(err, RELIEF_E_MESH,
                         "the %zu points are collinear (spread across the line "
                         "%.3g of that along it); no %s is determined", n,
                         sqrt(fmax(eval[1], 0.0) / eval[0]),
                         model == RELIEF_FIT_AUTO ? "primitive"
                                                  : relief_fit_model_name(model));
        goto done;
    }
    coplanar = eval[2] <= FLAT_EIGEN * eval[0];
    if (model == RELIEF_FIT_SPHERE && coplanar) {
        st = relief_fail(err, RELIEF_E_MESH,
                         "the %zu points are coplanar; a sphere through them is "
                         "not determined (fit a plane)", n);
        goto done;
    }

    /* Cylinder start axes. A patch of a cylinder has its axis in the plane
     * of its two larger principal axes (an arc under 180 degrees) or along
     * one principal axis (symmetric or closed coverage); when the two larger
     * spreads are alike the principal axes are an arbitrary pair in that
     * plane, so directions every 30 degrees in it are tried. */
    for (int a = 0; a < AXES_IN_PLANE; ++a) {
        double t = RELIEF_PI * (double)a / AXES_IN_PLANE;
        for (int k = 0; k < 3; ++k)
            axes[a][k] = cos(t) * evec[3 * k] + sin(t) * evec[3 * k + 1];
    }
    for (int k = 0; k < 3; ++k)
        axes[AXES_IN_PLANE][k] = evec[3 * k + 2];
    n_axes = AXES_IN_PLANE + 1;
    if (normals) {
        /* A cylinder's normals are all orthogonal to its axis: the axis is
         * the direction of least spread of the normals. */
        double nn[9] = {0}, nev[3], nvec[9];
        for (size_t i = 0; i < n; ++i)
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c)
                    nn[3 * r + c] += normals[3 * i + r] * normals[3 * i + c];
        if (nn[0] + nn[4] + nn[8] > 0.0 && isfinite(nn[0] + nn[4] + nn[8])) {
            relief_sym3_eigen(nn, nev, nvec);
            for (int k = 0; k < 3; ++k)
                axes[n_axes][k] = nvec[3 * k + 2];
            ++n_axes;
        }
    }

    /* Choosing a model and ranking the cylinder's start axes need far fewer
     * points than a big scan has: do both on an evenly strided subset, then
     * refit the chosen model on every point from there. */
    sel = w;
    if (n > SELECT_POINTS &&
        (model == RELIEF_FIT_AUTO || model == RELIEF_FIT_CYLINDER)) {
        size_t stride = (n + SELECT_POINTS - 1) / SELECT_POINTS;
        sel.n = (n + stride - 1) / stride;
        q_sel = malloc(sel.n * 3 * sizeof *q_sel);
        if (!q_sel) {
            st = relief_fail(err, RELIEF_E_NOMEM,
                             "cannot allocate a subset of %zu points", sel.n);
            goto done;
        }
        for (size_t j = 0; j < sel.n; ++j)
            memcpy(q_sel + 3 * j, q + 3 * j * stride, 3 * sizeof *q);
        sel.q = q_sel;
    }
    for (int i = 0; i < 3; ++i) {
        relief_fit_model mm = models[i];
        if (model != RELIEF_FIT_AUTO && model != mm)
            continue;
        if (n < min_points(mm) || (mm == RELIEF_FIT_SPHERE && coplanar))
            continue;
        have[mm] = fit_one_model(&sel, mm, min_points(mm),
                                 (const double(*)[3])axes, n_axes, &cand[mm]);
    }
    if (model != RELIEF_FIT_AUTO) {
        if (!have[model]) {
            st = relief_fail(err, RELIEF_E_MESH,
                             "cannot fit a %s to the %zu points: they are too "
                             "flat (its radius diverges)",
                             relief_fit_model_name(model), n);
            goto done;
        }
        best = model;
    } else {
        double best_score = INFINITY, cap = INFINITY;
        /* The cap: the trimming threshold of the tightest model, so that
         * what it calls an outlier weighs the same on every model. */
        for (int i = 0; i < 3; ++i)
            if (have[models[i]])
                cap = fmin(cap, RELIEF_FIT_TRIM_K * MAD_TO_SIGMA *
                                    cand[models[i]].med_abs);
        cap = fmax(cap, TRIM_FLOOR);
        for (int i = 0; i < 3; ++i) {
            relief_fit_model mm = models[i];
            double sc;
            if (!have[mm])
                continue;
            sc = model_score(&sel, &cand[mm], cap * cap, n_params(mm));
            /* Strictly lower: on a tie the model with fewer parameters,
             * tried first, stays. */
            if (sc < best_score) {
                best_score = sc;
                best = mm;
            }
        }
        if (best == RELIEF_FIT_AUTO) {
            st = relief_fail(err, RELIEF_E_INTERNAL,
                             "no primitive could be fitted to the %zu points", n);
            goto done;
        }
    }
    if (sel.q != w.q) {
        relief_fit_primitive start = cand[best].prim;
        if (!fit_robust(&w, &start, min_points(best), &cand[best])) {
            st = relief_fail(err, RELIEF_E_MESH,
                             "cannot fit a %s to the %zu points: they are too "
                             "flat (its radius diverges)",
                             relief_fit_model_name(best), n);
            goto done;
        }
    }

    {
        const fit_candidate *c = &cand[best];
        relief_fit_primitive *p = &res.prim;
        double thr = fmax(3.0 * c->rms, TRIM_FLOOR);
        size_t within = 0;

        for (size_t i = 0; i < n; ++i)
            within += fabs(relief_fit_distance(&c->prim, q + 3 * i)) <= thr;
        *p = c->prim;
        if (p->model == RELIEF_FIT_PLANE) {
            double s = 0.0;
            if (normals)
                for (size_t i = 0; i < n; ++i)
                    s += dot3(normals + 3 * i, p->dir);
            if (s < 0.0)
                for (int k = 0; k < 3; ++k)
                    p->dir[k] = -p->dir[k];
            else if (!(s > 0.0)) /* no normals, or no majority among them */
                relief_canonical_sign(p->dir);
        } else if (p->model == RELIEF_FIT_CYLINDER) {
            fit_recentre_axis(p);
            relief_canonical_sign(p->dir);
        }
        for (int k = 0; k < 3; ++k)
            p->point[k] = c0[k] + scale * p->point[k];
        p->radius *= scale;
        res.rms = scale * c->rms;
        res.rms_all = scale * c->rms_all;
        res.inlier_fraction = (double)within / (double)n;
        res.n_points = n;
        res.n_inliers = c->n_in;
        res.size = scale * c->size;
        res.poor_fit = res.rms > RELIEF_FIT_POOR * res.size;
        for (int i = 0; i < 4; ++i)
            res.model_rms[i] = have[i] ? scale * cand[i].rms : -1.0;
    }

    if (model == RELIEF_FIT_AUTO) {
        /* A model with a lower inlier rms than the chosen one lost on the
         * score: say why, or the sentence reads as a contradiction. */
        relief_fit_model lower = RELIEF_FIT_AUTO;
        append(res.reason, sizeof res.reason, "%s: rms %.4g vs",
               relief_fit_model_name(best), res.rms);
        for (int i = 0, first = 1; i < 3; ++i) {
            relief_fit_model mm = models[i];
            if (mm == best)
                continue;
            if (have[mm])
                append(res.reason, sizeof res.reason, "%s %s %.4g",
                       first ? "" : ",", relief_fit_model_name(mm),
                       res.model_rms[mm]);
            else
                append(res.reason, sizeof res.reason, "%s %s n/a",
                       first ? "" : ",", relief_fit_model_name(mm));
            first = 0;
            if (have[mm] && res.model_rms[mm] < res.rms &&
                (lower == RELIEF_FIT_AUTO || res.model_rms[mm] < res.model_rms[lower]))
                lower = mm;
        }
        if (lower != RELIEF_FIT_AUTO && n_params(lower) > n_params(best))
            append(res.reason, sizeof res.reason,
                   " (%s not chosen: over all points, outliers capped, it does not "
                   "cut the residual by %.0f%% per extra parameter)",
                   relief_fit_model_name(lower), 100.0 * RELIEF_FIT_GAIN);
        else if (lower != RELIEF_FIT_AUTO)
            append(res.reason, sizeof res.reason,
                   " (%s not chosen: its rms leaves out more points; over all "
                   "points, outliers capped, its residual is higher)",
                   relief_fit_model_name(lower));
    } else {
        append(res.reason, sizeof res.reason,
               "%s (requested): rms %.4g over %zu of %zu points",
               relief_fit_model_name(best), res.rms, res.n_inliers, n);
    }
    if (res.poor_fit)
        append(res.reason, sizeof res.reason, "; poor fit: rms is %.1f%% of the %s",
               100.0 * res.rms / res.size,
               best == RELIEF_FIT_PLANE ? "points' extent" : "radius");
    *out = res;

done:
    free(q_sel);
    free(w.mask);
    free(w.tmp);
    free(w.r);
    free(q);
    return st;
}

relief_status relief_fit_mesh(const relief_mesh *mesh, relief_fit_model model,
                              relief_fit_result *out, relief_error *err)
{
    relief_status st = RELIEF_OK;
    double *nrm = NULL;
    const double *use = NULL;

    if (!mesh) {
        st = relief_fail(err, RELIEF_E_USAGE, "relief_fit_mesh: mesh is NULL");
        goto done;
    }
    if (mesh->nrm) {
        use = mesh->nrm;
    } else if (mesh->nt > 0 && mesh->nv > 0) {
        nrm = calloc(mesh->nv, 3 * sizeof *nrm);
        if (!nrm) {
            st = relief_fail(err, RELIEF_E_NOMEM,
                             "cannot allocate normals for %zu vertices", mesh->nv);
            goto done;
        }
        /* The unnormalised cross product weights each face by its area. */
        for (size_t t = 0; t < mesh->nt; ++t) {
            const uint32_t *f = mesh->tri + 3 * t;
            double e1[3], e2[3], fn[3];
            if (f[0] >= mesh->nv || f[1] >= mesh->nv || f[2] >= mesh->nv)
                continue;
            for (int k = 0; k < 3; ++k) {
                e1[k] = mesh->pos[3 * (size_t)f[1] + k] - mesh->pos[3 * (size_t)f[0] + k];
                e2[k] = mesh->pos[3 * (size_t)f[2] + k] - mesh->pos[3 * (size_t)f[0] + k];
            }
            cross3(e1, e2, fn);
            for (int c = 0; c < 3; ++c)
                for (int k = 0; k < 3; ++k)
                    nrm[3 * (size_t)f[c] + k] += fn[k];
        }
        for (size_t v = 0; v < mesh->nv; ++v)
            relief_normalize3(nrm + 3 * v);
        use = nrm;
    }
    st = relief_fit(mesh->pos, use, mesh->nv, model, out, err);

done:
    free(nrm);
    return st;
}
