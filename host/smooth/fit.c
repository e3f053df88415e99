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
#include "base/numtext.h"
#include "base/pool.h"
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
    relief_vsnprintf_c(buf + len, cap - len, fmt, ap);
    va_end(ap);
}

/* The models auto tries, fewest parameters first (a tie keeps the first). */
static const relief_fit_model fit_models[3] = {RELIEF_FIT_PLANE, RELIEF_FIT_SPHERE,
                                               RELIEF_FIT_CYLINDER};

/* One relief_fit call's state, shared by its stages: the points normalised
 * (w.q, n x 3: centred on c0 and divided by scale), the subset that chooses
 * the model (sel: w itself when small), the cylinder's start axes and each
 * model's candidate. */
typedef struct fit_run {
    const double *pts, *normals; /* n x 3 each; normals may be NULL */
    size_t n;
    relief_fit_model model, best;
    fit_work w, sel;
    double *q, *q_sel; /* n x 3; sel.n x 3 or NULL */
    double c0[3], scale;
    double axes[AXES_IN_PLANE + 2][3];
    int n_axes, coplanar;
    fit_candidate cand[4]; /* by model */
    int have[4];           /* cand[m] was fitted */
} fit_run;

/* The arguments and the points: NULL pointers, an unknown model, too few
 * points, a non-finite coordinate, too many to allocate for. */
static relief_status fit_check_input(const double *pts, const relief_fit_result *out, size_t n,
                                     relief_fit_model model, relief_error *err)
{
    if (!pts || !out)
        return relief_fail(err, RELIEF_E_USAGE, "relief_fit: %s is NULL",
                           pts ? "out" : "pts");
    if ((int)model < (int)RELIEF_FIT_AUTO || (int)model > (int)RELIEF_FIT_CYLINDER)
        return relief_fail(err, RELIEF_E_USAGE,
                           "relief_fit: unknown model %d; expected auto, plane, "
                           "sphere or cylinder", (int)model);
    if (n < min_points(model))
        return relief_fail(err, RELIEF_E_MESH,
                           "%s fit needs at least %zu points; got %zu",
                           relief_fit_model_name(model), min_points(model), n);
    for (size_t i = 0; i < n; ++i) {
        const double *p = pts + 3 * i;
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
            return relief_fail(err, RELIEF_E_MESH,
                               "point %zu has a non-finite coordinate (%g, %g, %g)",
                               i, p[0], p[1], p[2]);
    }
    if (n > SIZE_MAX / (3 * sizeof(double)))
        return relief_fail(err, RELIEF_E_NOMEM, "cannot fit %zu points: too many", n);
    return RELIEF_OK;
}

/* The work space, and the points centred and scaled to unit RMS radius:
 * every tolerance below is then relative, whatever the input's units. */
static relief_status fit_normalise(fit_run *f, relief_error *err)
{
    const size_t n = f->n;
    const double *pts = f->pts;
    double cmax = 0.0;
    f->q = malloc(n * 3 * sizeof *f->q);
    f->w.r = malloc(n * sizeof *f->w.r);
    f->w.tmp = malloc(n * sizeof *f->w.tmp);
    f->w.mask = malloc(n);
    if (!f->q || !f->w.r || !f->w.tmp || !f->w.mask)
        return relief_fail(err, RELIEF_E_NOMEM,
                           "cannot allocate the work space to fit %zu points", n);
    f->w.n = n;
    f->w.q = f->q;
    for (size_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k)
            f->c0[k] += pts[3 * i + k] / (double)n;
    for (size_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) {
            double d = pts[3 * i + k] - f->c0[k];
            f->scale += d * d;
        }
    f->scale = sqrt(f->scale / (double)n);
    for (int k = 0; k < 3; ++k)
        cmax = fmax(cmax, fabs(f->c0[k]));
    /* Identical points still scatter by rounding of the centroid. */
    if (!(f->scale > 1e-12 * cmax) || f->scale == 0.0)
        return relief_fail(err, RELIEF_E_MESH,
                           "all %zu points coincide at (%g, %g, %g); no %s is "
                           "determined", n, f->c0[0], f->c0[1], f->c0[2],
                           f->model == RELIEF_FIT_AUTO ? "primitive"
                                                       : relief_fit_model_name(f->model));
    for (size_t i = 0; i < 3 * n; ++i)
        f->q[i] = (f->pts[i] - f->c0[i % 3]) / f->scale;
    return RELIEF_OK;
}

/* Cylinder start axes. A patch of a cylinder has its axis in the plane of
 * its two larger principal axes (an arc under 180 degrees) or along one
 * principal axis (symmetric or closed coverage); when the two larger
 * spreads are alike the principal axes are an arbitrary pair in that
 * plane, so directions every 30 degrees in it are tried. evec: the
 * principal axes, columns by decreasing spread. */
static void fit_start_axes(fit_run *f, const double evec[9])
{
    for (int a = 0; a < AXES_IN_PLANE; ++a) {
        double t = RELIEF_PI * (double)a / AXES_IN_PLANE;
        for (int k = 0; k < 3; ++k)
            f->axes[a][k] = cos(t) * evec[3 * k] + sin(t) * evec[3 * k + 1];
    }
    for (int k = 0; k < 3; ++k)
        f->axes[AXES_IN_PLANE][k] = evec[3 * k + 2];
    f->n_axes = AXES_IN_PLANE + 1;
    if (f->normals) {
        /* A cylinder's normals are all orthogonal to its axis: the axis is
         * the direction of least spread of the normals. */
        double nn[9] = {0}, nev[3], nvec[9];
        for (size_t i = 0; i < f->n; ++i)
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c)
                    nn[3 * r + c] += f->normals[3 * i + r] * f->normals[3 * i + c];
        if (nn[0] + nn[4] + nn[8] > 0.0 && isfinite(nn[0] + nn[4] + nn[8])) {
            relief_sym3_eigen(nn, nev, nvec);
            for (int k = 0; k < 3; ++k)
                f->axes[f->n_axes][k] = nvec[3 * k + 2];
            ++f->n_axes;
        }
    }
}

/* The points' spread: collinear points determine nothing, coplanar ones no
 * sphere; then the cylinder's start axes from the principal axes. */
static relief_status fit_shape(fit_run *f, relief_error *err)
{
    const size_t n = f->n;
    double m[3], eval[3], evec[9];
    relief_pca3(f->q, n, NULL, m, eval, evec);
    if (eval[1] <= FLAT_EIGEN * eval[0])
        return relief_fail(err, RELIEF_E_MESH,
                           "the %zu points are collinear (spread across the line "
                           "%.3g of that along it); no %s is determined", n,
                           sqrt(fmax(eval[1], 0.0) / eval[0]),
                           f->model == RELIEF_FIT_AUTO ? "primitive"
                                                       : relief_fit_model_name(f->model));
    f->coplanar = eval[2] <= FLAT_EIGEN * eval[0];
    if (f->model == RELIEF_FIT_SPHERE && f->coplanar)
        return relief_fail(err, RELIEF_E_MESH,
                           "the %zu points are coplanar; a sphere through them is "
                           "not determined (fit a plane)", n);
    fit_start_axes(f, evec);
    return RELIEF_OK;
}

/* Choosing a model and ranking the cylinder's start axes need far fewer
 * points than a big scan has: do both on an evenly strided subset (sel),
 * then refit the chosen model on every point from there. */
static relief_status fit_subset(fit_run *f, relief_error *err)
{
    const size_t n = f->n;
    size_t stride;
    f->sel = f->w;
    if (!(n > SELECT_POINTS &&
          (f->model == RELIEF_FIT_AUTO || f->model == RELIEF_FIT_CYLINDER)))
        return RELIEF_OK;
    stride = (n + SELECT_POINTS - 1) / SELECT_POINTS;
    f->sel.n = (n + stride - 1) / stride;
    f->q_sel = malloc(f->sel.n * 3 * sizeof *f->q_sel);
    if (!f->q_sel)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a subset of %zu points",
                           f->sel.n);
    for (size_t j = 0; j < f->sel.n; ++j)
        memcpy(f->q_sel + 3 * j, f->q + 3 * j * stride, 3 * sizeof *f->q);
    f->sel.q = f->q_sel;
    return RELIEF_OK;
}

/* Auto's choice among the fitted models: the lowest score over all points
 * with the distances capped at the tightest model's trimming threshold, so
 * that what it calls an outlier weighs the same on every model. */
static relief_fit_model fit_auto_best(fit_run *f)
{
    relief_fit_model best = RELIEF_FIT_AUTO;
    double best_score = INFINITY, cap = INFINITY;
    for (int i = 0; i < 3; ++i)
        if (f->have[fit_models[i]])
            cap = fmin(cap, RELIEF_FIT_TRIM_K * MAD_TO_SIGMA * f->cand[fit_models[i]].med_abs);
    cap = fmax(cap, TRIM_FLOOR);
    for (int i = 0; i < 3; ++i) {
        relief_fit_model mm = fit_models[i];
        double sc;
        if (!f->have[mm])
            continue;
        sc = model_score(&f->sel, &f->cand[mm], cap * cap, n_params(mm));
        /* Strictly lower: on a tie the model with fewer parameters, tried
         * first, stays. */
        if (sc < best_score) {
            best_score = sc;
            best = mm;
        }
    }
    return best;
}

/* Fit the models asked for (auto: all that the points determine) on the
 * subset, choose one (f->best), and refit it on every point when the
 * subset was smaller. */
static relief_status fit_choose(fit_run *f, relief_error *err)
{
    const size_t n = f->n;
    relief_fit_model models[3];
    size_t need[3];
    fit_candidate cand[3];
    int ok[3], m = 0;
    for (int i = 0; i < 3; ++i) {
        relief_fit_model mm = fit_models[i];
        if (f->model != RELIEF_FIT_AUTO && f->model != mm)
            continue;
        if (n < min_points(mm) || (mm == RELIEF_FIT_SPHERE && f->coplanar))
            continue;
        models[m] = mm, need[m++] = min_points(mm);
    }
    fit_each_model(&f->sel, m, models, need, (const double(*)[3])f->axes, f->n_axes, cand,
                   ok);
    for (int i = 0; i < m; ++i) {
        f->have[models[i]] = ok[i];
        if (ok[i])
            f->cand[models[i]] = cand[i];
    }
    if (f->model != RELIEF_FIT_AUTO) {
        if (!f->have[f->model])
            return relief_fail(err, RELIEF_E_MESH,
                               "cannot fit a %s to the %zu points: they are too "
                               "flat (its radius diverges)",
                               relief_fit_model_name(f->model), n);
        f->best = f->model;
    } else {
        f->best = fit_auto_best(f);
        if (f->best == RELIEF_FIT_AUTO)
            return relief_fail(err, RELIEF_E_INTERNAL,
                               "no primitive could be fitted to the %zu points", n);
    }
    if (f->sel.q != f->w.q) {
        relief_fit_primitive start = f->cand[f->best].prim;
        if (!fit_robust(&f->w, &start, min_points(f->best), &f->cand[f->best]))
            return relief_fail(err, RELIEF_E_MESH,
                               "cannot fit a %s to the %zu points: they are too "
                               "flat (its radius diverges)",
                               relief_fit_model_name(f->best), n);
    }
    return RELIEF_OK;
}

/* The chosen candidate in the input's units, its direction's sign made
 * definite (a plane's along most normals), and its figures. */
static void fit_result(const fit_run *f, relief_fit_result *res)
{
    const fit_candidate *c = &f->cand[f->best];
    relief_fit_primitive *p = &res->prim;
    const size_t n = f->n;
    const double scale = f->scale;
    double thr = fmax(3.0 * c->rms, TRIM_FLOOR);
    size_t within = 0;

    for (size_t i = 0; i < n; ++i)
        within += fabs(relief_fit_distance(&c->prim, f->q + 3 * i)) <= thr;
    *p = c->prim;
    if (p->model == RELIEF_FIT_PLANE) {
        double s = 0.0;
        if (f->normals)
            for (size_t i = 0; i < n; ++i)
                s += dot3(f->normals + 3 * i, p->dir);
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
        p->point[k] = f->c0[k] + scale * p->point[k];
    p->radius *= scale;
    res->rms = scale * c->rms;
    res->rms_all = scale * c->rms_all;
    res->inlier_fraction = (double)within / (double)n;
    res->n_points = n;
    res->n_inliers = c->n_in;
    res->size = scale * c->size;
    res->poor_fit = res->rms > RELIEF_FIT_POOR * res->size;
    for (int i = 0; i < 4; ++i)
        res->model_rms[i] = f->have[i] ? scale * f->cand[i].rms : -1.0;
}

/* The sentence that says why the model was chosen (res->reason). */
static void fit_reason(const fit_run *f, relief_fit_result *res)
{
    const relief_fit_model best = f->best;
    if (f->model == RELIEF_FIT_AUTO) {
        /* A model with a lower inlier rms than the chosen one lost on the
         * score: say why, or the sentence reads as a contradiction. */
        relief_fit_model lower = RELIEF_FIT_AUTO;
        append(res->reason, sizeof res->reason, "%s: rms %.4g vs",
               relief_fit_model_name(best), res->rms);
        for (int i = 0, first = 1; i < 3; ++i) {
            relief_fit_model mm = fit_models[i];
            if (mm == best)
                continue;
            if (f->have[mm])
                append(res->reason, sizeof res->reason, "%s %s %.4g",
                       first ? "" : ",", relief_fit_model_name(mm), res->model_rms[mm]);
            else
                append(res->reason, sizeof res->reason, "%s %s n/a",
                       first ? "" : ",", relief_fit_model_name(mm));
            first = 0;
            if (f->have[mm] && res->model_rms[mm] < res->rms &&
                (lower == RELIEF_FIT_AUTO || res->model_rms[mm] < res->model_rms[lower]))
                lower = mm;
        }
        if (lower != RELIEF_FIT_AUTO && n_params(lower) > n_params(best))
            append(res->reason, sizeof res->reason,
                   " (%s not chosen: over all points, outliers capped, it does not "
                   "cut the residual by %.0f%% per extra parameter)",
                   relief_fit_model_name(lower), 100.0 * RELIEF_FIT_GAIN);
        else if (lower != RELIEF_FIT_AUTO)
            append(res->reason, sizeof res->reason,
                   " (%s not chosen: its rms leaves out more points; over all "
                   "points, outliers capped, its residual is higher)",
                   relief_fit_model_name(lower));
    } else {
        append(res->reason, sizeof res->reason,
               "%s (requested): rms %.4g over %zu of %zu points",
               relief_fit_model_name(best), res->rms, res->n_inliers, f->n);
    }
    if (res->poor_fit)
        append(res->reason, sizeof res->reason, "; poor fit: rms is %.1f%% of the %s",
               100.0 * res->rms / res->size,
               best == RELIEF_FIT_PLANE ? "points' extent" : "radius");
}

relief_status relief_fit(const double *pts, const double *normals, size_t n,
                         relief_fit_model model, relief_fit_result *out,
                         relief_error *err)
{
    return relief_fit_threads(pts, normals, n, model, 1, out, err);
}

relief_status relief_fit_threads(const double *pts, const double *normals, size_t n,
                                 relief_fit_model model, int threads, relief_fit_result *out,
                                 relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    relief_status st;
    fit_run f;
    relief_fit_result res;

    memset(&f, 0, sizeof f);
    memset(&res, 0, sizeof res);
    f.pts = pts;
    f.normals = normals;
    f.n = n;
    f.model = model;
    f.best = RELIEF_FIT_AUTO;
    st = fit_check_input(pts, out, n, model, err);
    if (st == RELIEF_OK)
        st = fit_normalise(&f, err);
    f.w.threads = relief_pool_threads_for(threads);
    if (st == RELIEF_OK)
        st = fit_shape(&f, err);
    if (st == RELIEF_OK)
        st = fit_subset(&f, err);
    if (st == RELIEF_OK)
        st = fit_choose(&f, err);
    if (st == RELIEF_OK) {
        fit_result(&f, &res);
        fit_reason(&f, &res);
        *out = res;
    }
    free(f.q_sel);
    free(f.w.mask);
    free(f.w.tmp);
    free(f.w.r);
    free(f.q);
    return st;
}

relief_status relief_fit_mesh(const relief_mesh *mesh, relief_fit_model model,
                              relief_fit_result *out, relief_error *err)
{
    return relief_fit_mesh_threads(mesh, model, 1, out, err);
}

relief_status relief_fit_mesh_threads(const relief_mesh *mesh, relief_fit_model model,
                                      int threads, relief_fit_result *out, relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
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
    st = relief_fit_threads(mesh->pos, use, mesh->nv, model, threads, out, err);

done:
    free(nrm);
    return st;
}
