/* Robust fitting of one model (fit_robust.h): starting values,
 * Levenberg-Marquardt refinement, trimming. */
#include "smooth/fit_robust.h"

#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "base/linalg.h"
#include "base/parallel.h"
#include "base/vec3.h"

/* ------------------------------------------------------ starting values */

/* Algebraic sphere through the points: |p|^2 = 2 c.p + d is linear in
 * (c, d), and r^2 = d + |c|^2. Biased on a small cap, which is why the
 * geometric refinement follows. Returns 0 when the points are (nearly)
 * coplanar and no sphere is determined. */
static int sphere_start(const fit_work *w, relief_fit_primitive *out)
{
    double ata[16] = {0}, atb[4] = {0}, x[4], r2;
    int ok;

    for (size_t i = 0; i < w->n; ++i) {
        const double *p = w->q + 3 * i;
        double row[4] = {p[0], p[1], p[2], 1.0}, b = dot3(p, p);
        for (int r = 0; r < 4; ++r) {
            for (int c = 0; c < 4; ++c)
                ata[4 * r + c] += row[r] * row[c];
            atb[r] += row[r] * b;
        }
    }
    ok = relief_solve_dense(4, ata, atb, x);
    if (ok) {
        memset(out, 0, sizeof *out);
        out->model = RELIEF_FIT_SPHERE;
        for (int k = 0; k < 3; ++k)
            out->point[k] = 0.5 * x[k];
        r2 = x[3] + dot3(out->point, out->point);
        ok = r2 > 0.0 && isfinite(r2);
        out->radius = ok ? sqrt(r2) : 0.0;
    }
    return ok;
}

/* Cylinder with the given unit axis direction: an algebraic (Kasa) circle
 * fit x^2 + y^2 = A x + B y + C to the points projected on the plane
 * orthogonal to the axis. The axis point is the circle's centre in that
 * plane, hence the axis point nearest the origin (the input centroid).
 * Returns 0 when the projection is a line (the axis lies in the points'
 * plane) and no circle is determined. */
static int cylinder_start(const fit_work *w, const double axis[3],
                          relief_fit_primitive *out)
{
    double u[3], v[3], ata[9] = {0}, atb[3] = {0}, x[3], r2;
    int ok;

    relief_perp_basis(axis, u, v);
    for (size_t i = 0; i < w->n; ++i) {
        const double *p = w->q + 3 * i;
        double a = dot3(p, u), b = dot3(p, v);
        double row[3] = {a, b, 1.0}, rhs = a * a + b * b;
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c)
                ata[3 * r + c] += row[r] * row[c];
            atb[r] += row[r] * rhs;
        }
    }
    ok = relief_solve_dense(3, ata, atb, x);
    if (ok) {
        memset(out, 0, sizeof *out);
        out->model = RELIEF_FIT_CYLINDER;
        memcpy(out->dir, axis, sizeof out->dir);
        for (int k = 0; k < 3; ++k)
            out->point[k] = 0.5 * (x[0] * u[k] + x[1] * v[k]);
        r2 = x[2] + 0.25 * (x[0] * x[0] + x[1] * x[1]);
        ok = r2 > 0.0 && isfinite(r2);
        out->radius = ok ? sqrt(r2) : 0.0;
    }
    return ok;
}

/* ------------------------------------------- Levenberg-Marquardt refining */

/* Move a cylinder's axis point to the axis point nearest the origin. The
 * axis point slides freely along the axis; pinning it near the data keeps
 * the rotation update of the direction from swinging the axis about a
 * far-away point. */
void fit_recentre_axis(relief_fit_primitive *c)
{
    double t = dot3(c->point, c->dir);
    for (int k = 0; k < 3; ++k)
        c->point[k] -= t * c->dir[k];
}

/* Signed distance of p to a sphere or cylinder and its derivatives J with
 * respect to the local parameters that lm_apply adds:
 * sphere (dc_x, dc_y, dc_z, dr); cylinder (point moves along u and v,
 * direction tilts towards u and v, dr), where (u, v, dir) = perp_basis. */
static double lm_row(const relief_fit_primitive *s, const double u[3],
                     const double v[3], const double p[3],
                     double J[MAX_PARAMS])
{
    double w[3], rho;

    for (int k = 0; k < 3; ++k)
        w[k] = p[k] - s->point[k];
    if (s->model == RELIEF_FIT_SPHERE) {
        rho = sqrt(dot3(w, w));
        for (int k = 0; k < 3; ++k)
            J[k] = rho > 0.0 ? -w[k] / rho : 0.0;
        J[3] = -1.0;
    } else {
        /* rho = |w - (w.a) a|: moving the point by e u changes w by -e u;
         * tilting a by e u changes the radial vector by -(w.u) a - t e u,
         * whose first term is orthogonal to it. */
        double t = dot3(w, s->dir), eu = 0.0, ev = 0.0;
        for (int k = 0; k < 3; ++k)
            w[k] -= t * s->dir[k];
        rho = sqrt(dot3(w, w));
        if (rho > 0.0) {
            eu = dot3(w, u) / rho;
            ev = dot3(w, v) / rho;
        }
        J[0] = -eu;
        J[1] = -ev;
        J[2] = -t * eu;
        J[3] = -t * ev;
        J[4] = -1.0;
    }
    return rho - s->radius;
}

/* out = s moved by the local step delta (see lm_row). Returns 0 when the
 * step leaves a non-positive or non-finite radius: such a step is refused. */
static int lm_apply(const relief_fit_primitive *s, const double u[3],
                    const double v[3], const double *delta,
                    relief_fit_primitive *out)
{
    *out = *s;
    if (s->model == RELIEF_FIT_SPHERE) {
        for (int k = 0; k < 3; ++k)
            out->point[k] += delta[k];
        out->radius += delta[3];
    } else {
        for (int k = 0; k < 3; ++k) {
            out->point[k] += delta[0] * u[k] + delta[1] * v[k];
            out->dir[k] += delta[2] * u[k] + delta[3] * v[k];
        }
        relief_normalize3(out->dir);
        out->radius += delta[4];
        fit_recentre_axis(out);
    }
    return isfinite(out->radius) && out->radius > 0.0 &&
           isfinite(dot3(out->point, out->point)) &&
           isfinite(dot3(out->dir, out->dir));
}

/* Sum of squared distances over the inliers. */
static double lm_cost(const fit_work *w, const uint8_t *mask,
                      const relief_fit_primitive *s)
{
    double sum = 0.0;
    for (size_t i = 0; i < w->n; ++i)
        if (mask[i]) {
            double d = relief_fit_distance(s, w->q + 3 * i);
            sum += d * d;
        }
    return sum;
}

/* Minimise the squared orthogonal distances of the inliers to a sphere or
 * cylinder, from *s, by at most max_iter steps of Levenberg-Marquardt with Marquardt's scaling of the
 * damping by the diagonal of J^T J (so the radius and the angles, which have
 * different units, are damped alike). */
static void lm_refine(const fit_work *w, const uint8_t *mask, int max_iter,
                      relief_fit_primitive *s)
{
    const int np = s->model == RELIEF_FIT_SPHERE ? 4 : 5;
    double lambda = 1e-3, cost = lm_cost(w, mask, s);

    for (int it = 0; it < max_iter && cost > 0.0; ++it) {
        double jtj[MAX_PARAMS * MAX_PARAMS] = {0}, g[MAX_PARAMS] = {0};
        double u[3] = {0}, v[3] = {0}, trace = 0.0, new_cost = cost;
        relief_fit_primitive trial;
        int improved = 0;

        if (s->model == RELIEF_FIT_CYLINDER)
            relief_perp_basis(s->dir, u, v);
        for (size_t i = 0; i < w->n; ++i) {
            double J[MAX_PARAMS], r;
            if (!mask[i])
                continue;
            r = lm_row(s, u, v, w->q + 3 * i, J);
            for (int a = 0; a < np; ++a) {
                g[a] += J[a] * r;
                for (int b = a; b < np; ++b)
                    jtj[a * np + b] += J[a] * J[b];
            }
        }
        for (int a = 0; a < np; ++a) {
            for (int b = 0; b < a; ++b)
                jtj[a * np + b] = jtj[b * np + a];
            trace += jtj[a * np + a];
        }
        while (!improved && lambda <= LM_LAMBDA_MAX) {
            double A[MAX_PARAMS * MAX_PARAMS], b[MAX_PARAMS], delta[MAX_PARAMS];
            memcpy(A, jtj, sizeof A);
            for (int a = 0; a < np; ++a) {
                /* The trace term keeps a zero diagonal (a parameter the
                 * inliers do not constrain) from making A singular. */
                A[a * np + a] += lambda * (jtj[a * np + a] + 1e-12 * trace);
                b[a] = -g[a];
            }
            if (relief_solve_dense(np, A, b, delta) && lm_apply(s, u, v, delta, &trial)) {
                new_cost = lm_cost(w, mask, &trial);
                improved = new_cost < cost;
            }
            if (!improved)
                lambda *= 10.0;
        }
        if (!improved)
            break; /* no downhill step at any damping: a minimum */
        *s = trial;
        lambda = fmax(0.1 * lambda, 1e-12);
        if (cost - new_cost <= 1e-14 * cost) {
            cost = new_cost;
            break;
        }
        cost = new_cost;
    }
}

/* ------------------------------------------------------ robust fitting */

/* Refit s on the inliers: the plane by PCA (exactly the orthogonal
 * least-squares plane), sphere and cylinder by Levenberg-Marquardt (at most
 * max_iter steps). Returns 0 when the result is not a usable primitive. */
static int refine(const fit_work *w, const uint8_t *mask, int max_iter,
                  relief_fit_primitive *s)
{
    int ok = 1;

    if (s->model == RELIEF_FIT_PLANE) {
        double m[3], eval[3], evec[9];
        ok = relief_pca3(w->q, w->n, mask, m, eval, evec) >= 3;
        for (int k = 0; k < 3; ++k)
            s->dir[k] = evec[3 * k + 2];
        /* The plane's point nearest the origin, as for the cylinder. */
        for (int k = 0; k < 3; ++k)
            s->point[k] = dot3(m, s->dir) * s->dir[k];
        s->radius = 0.0;
    } else {
        lm_refine(w, mask, max_iter, s);
        ok = isfinite(s->radius) && s->radius > 0.0 &&
             s->radius < RADIUS_DIVERGED;
    }
    return ok;
}

/* Recompute the inliers from w->r: |r| <= K * 1.4826 * median|r| (at least
 * half the points pass). The mask is left alone when fewer than `need`
 * points would remain. Returns 1 when the inlier set changed. */
static int retrim(fit_work *w, size_t need)
{
    double thr;
    size_t count = 0, changes = 0;

    for (size_t i = 0; i < w->n; ++i)
        w->tmp[i] = fabs(w->r[i]);
    thr = RELIEF_FIT_TRIM_K * MAD_TO_SIGMA * relief_select_median(w->tmp, w->n);
    if (thr < TRIM_FLOOR)
        thr = TRIM_FLOOR;
    for (size_t i = 0; i < w->n; ++i) {
        uint8_t in = fabs(w->r[i]) <= thr;
        count += in;
        changes += in != w->mask[i];
    }
    if (count < need)
        changes = 0;
    if (changes > 0)
        for (size_t i = 0; i < w->n; ++i)
            w->mask[i] = fabs(w->r[i]) <= thr;
    return changes > 0;
}

/* Fit from `start` on all points, then alternate trimming and refitting on
 * the inliers until the inlier set is stable. Returns 0 when no usable
 * primitive results. */
int fit_robust(fit_work *w, const relief_fit_primitive *start,
               size_t need, fit_candidate *out)
{
    relief_fit_primitive s = *start;
    double sum = 0.0, sum_all = 0.0;
    size_t n_in = 0;
    int ok = 1;

    memset(w->mask, 1, w->n);
    for (int pass = 0; ok; ++pass) {
        ok = refine(w, w->mask, pass == 0 ? LM_ITERATIONS_COLD : LM_ITERATIONS_WARM,
                    &s);
        for (size_t i = 0; ok && i < w->n; ++i)
            w->r[i] = relief_fit_distance(&s, w->q + 3 * i);
        if (!ok || pass == RELIEF_FIT_TRIM_PASSES || !retrim(w, need))
            break;
    }
    if (ok) {
        for (size_t i = 0; i < w->n; ++i) {
            if (w->mask[i]) {
                sum += w->r[i] * w->r[i];
                ++n_in;
            }
            sum_all += w->r[i] * w->r[i];
            w->tmp[i] = fabs(w->r[i]);
        }
        out->prim = s;
        out->n_in = n_in;
        out->rms = sqrt(sum / (double)n_in);
        out->rms_all = sqrt(sum_all / (double)w->n);
        out->med_abs = relief_select_median(w->tmp, w->n);
        out->size = s.radius;
        if (s.model == RELIEF_FIT_PLANE) {
            double m[3], eval[3], evec[9];
            relief_pca3(w->q, w->n, w->mask, m, eval, evec);
            out->size = sqrt(fmax(eval[0] + eval[1], 0.0));
        }
    }
    return ok;
}

/* Screen one cylinder start axis: its short refinement on the points
 * mask sets, and its median |distance| over all of them (tmp: n
 * scratch); NAN when it gives no cylinder. */
static double screen_axis(const fit_work *w, const uint8_t *mask, const double axis[3],
                          double *tmp, relief_fit_primitive *prim)
{
    if (!cylinder_start(w, axis, prim) || !refine(w, mask, LM_ITERATIONS_SCREEN, prim))
        return NAN;
    for (size_t i = 0; i < w->n; ++i)
        tmp[i] = fabs(relief_fit_distance(prim, w->q + 3 * i));
    return relief_select_median(tmp, w->n);
}

/* The axis of the lowest median (the first on a tie; a NAN never), or -1. */
static int best_of(const double *med, int n_axes)
{
    double best_med = INFINITY;
    int best = -1;
    for (int a = 0; a < n_axes; ++a)
        if (med[a] < best_med) {
            best_med = med[a];
            best = a;
        }
    return best;
}

/* Fit one model robustly. The cylinder's start axes (n_axes x 3, unit) are
 * ranked by a short refinement on all points, scored by the median
 * |distance| (which outliers cannot sway); only the best is fitted robustly.
 * Returns 0 when nothing could be fitted. */
int fit_one_model(fit_work *w, relief_fit_model model, size_t need,
                  const double (*axes)[3], int n_axes, fit_candidate *out)
{
    relief_fit_primitive start, prim[AXES_IN_PLANE + 2];
    double med[AXES_IN_PLANE + 2];
    int best;

    memset(&start, 0, sizeof start);
    start.model = model;
    if (model == RELIEF_FIT_PLANE)
        return fit_robust(w, &start, need, out);
    if (model == RELIEF_FIT_SPHERE)
        return sphere_start(w, &start) && fit_robust(w, &start, need, out);
    memset(w->mask, 1, w->n);
    for (int a = 0; a < n_axes; ++a)
        med[a] = screen_axis(w, w->mask, axes[a], w->tmp, &prim[a]);
    best = best_of(med, n_axes);
    return best >= 0 && fit_robust(w, &prim[best], need, out);
}

/* fit_each_model's jobs, each alone, taken in turn by whichever worker
 * is free (what a job computes does not depend on who runs it): the
 * cylinder's start axes first, a = 0 .. n_axes - 1, each screened into
 * prim[a], med[a]; the worker that screens the last of them then fits the
 * cylinder from the best (on w's own scratch) while the others take the
 * plain models, job n_axes + i fitting models[i] (a plane or a sphere) on
 * scratch of its own. */
typedef struct fit_jobs {
    fit_work *w;
    int n_plain, n_axes, cyl;
    const relief_fit_model *models;
    const size_t *need;
    fit_candidate *out;
    int *ok;
    const double (*axes)[3];
    relief_fit_primitive prim[AXES_IN_PLANE + 2];
    double med[AXES_IN_PLANE + 2];
    double *scratch;  /* 2 n a job */
    uint8_t *mask;    /* n a plain model, then n set: every point */
    atomic_int next;  /* the next job to take */
    atomic_int axes_done;
} fit_jobs;

static void cylinder_from_best(fit_jobs *j)
{
    const int best = best_of(j->med, j->n_axes);
    j->ok[j->cyl] =
        best >= 0 && fit_robust(j->w, &j->prim[best], j->need[j->cyl], &j->out[j->cyl]);
}

static void run_fit_job(fit_jobs *j, int k)
{
    const fit_work *w = j->w;
    double *r = j->scratch + 2 * (size_t)k * w->n;
    if (k < j->n_axes) {
        j->med[k] = screen_axis(w, j->mask + (size_t)j->n_plain * w->n, j->axes[k], r,
                                &j->prim[k]);
        if (atomic_fetch_add(&j->axes_done, 1) == j->n_axes - 1)
            cylinder_from_best(j);
    } else {
        const int i = k - j->n_axes;
        fit_work own = {w->n, w->q, r, r + w->n, j->mask + (size_t)i * w->n, 1};
        j->ok[i] = fit_one_model(&own, j->models[i], j->need[i], NULL, 0, &j->out[i]);
    }
}

/* One worker (relief_parallel_ranges over the workers): jobs until none
 * is left. */
static int fit_worker(void *ctx, size_t lo, size_t hi)
{
    fit_jobs *j = ctx;
    const int jobs = j->n_axes + j->n_plain;
    (void)lo, (void)hi;
    for (int k; (k = atomic_fetch_add(&j->next, 1)) < jobs;)
        run_fit_job(j, k);
    return 0;
}

void fit_each_model(fit_work *w, int n_models, const relief_fit_model *models,
                    const size_t *need, const double (*axes)[3], int n_axes, fit_candidate *out,
                    int *ok)
{
    fit_jobs j = {w, 0, 0, -1, models, need, out, ok, axes, {{0}}, {0}, NULL, NULL, 0, 0};
    int jobs;
    for (int i = 0; i < n_models; ++i)
        if (models[i] == RELIEF_FIT_CYLINDER)
            j.cyl = i;
    j.n_plain = j.cyl < 0 ? n_models : n_models - 1;
    j.n_axes = j.cyl < 0 ? 0 : n_axes;
    jobs = j.n_plain + j.n_axes;
    /* The cylinder last among the models, so the plain ones are models
     * 0 .. n_plain - 1 in their order. */
    if (w->threads > 1 && jobs > 1 && j.n_axes > 0 && j.cyl == n_models - 1) {
        j.scratch = malloc((size_t)jobs * 2 * w->n * sizeof *j.scratch);
        j.mask = malloc(((size_t)j.n_plain + 1) * w->n);
    }
    if (!j.scratch || !j.mask) {
        free(j.scratch);
        free(j.mask);
        for (int i = 0; i < n_models; ++i)
            ok[i] = fit_one_model(w, models[i], need[i], axes, n_axes, &out[i]);
        return;
    }
    memset(j.mask + (size_t)j.n_plain * w->n, 1, w->n);
    relief_parallel_ranges((size_t)(w->threads < jobs ? w->threads : jobs), w->threads,
                           fit_worker, &j);
    free(j.scratch);
    free(j.mask);
}
