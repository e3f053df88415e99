/* Plane, sphere and cylinder fitting with robust trimming and model choice.
 * The method, its constants and the units are described in fit.h. */
#include "smooth/fit.h"

#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/vec3.h"
#include "mesh/mesh.h"

/* 1 / Phi^-1(3/4): turns the median |residual| of Gaussian noise into its
 * standard deviation. */
#define MAD_TO_SIGMA 1.4826

/* Everything below works on points scaled to unit RMS radius about their
 * centroid, so these are relative tolerances. */
#define FLAT_EIGEN 1e-16      /* eigenvalue ratio taken as exactly zero spread */
#define TRIM_FLOOR 1e-12      /* trimming threshold for exact (noise-free) data */
#define RADIUS_DIVERGED 1e6   /* radius that means "this is really a plane" */
/* Levenberg-Marquardt iteration caps: a fit from an algebraic start, a
 * refit after trimming (warm start: the inliers changed a little), and the
 * quick refinement that ranks the cylinder's start axes. Well-posed fits
 * converge in well under 30 iterations; the caps bound the time spent on a
 * sphere or cylinder crawling towards infinite radius on flat data. */
#define LM_ITERATIONS_COLD 100
#define LM_ITERATIONS_WARM 30
#define LM_ITERATIONS_SCREEN 40
#define LM_LAMBDA_MAX 1e12
/* Points enough to choose a model and rank the cylinder's start axes. */
#define SELECT_POINTS 20000

#define PI_ 3.14159265358979323846

enum {
    MAX_PARAMS = 5,
    AXES_IN_PLANE = 6 /* cylinder start axes tried in the principal plane */
};

/* Scratch shared by all candidate fits of one relief_fit call. */
typedef struct fit_work {
    size_t n;
    const double *q;     /* n x 3 normalised points */
    double *r;           /* n signed distances to the current primitive */
    double *tmp;         /* n scratch for medians */
    uint8_t *mask;       /* n, 1 = inlier of the current primitive */
} fit_work;

/* One model's robust fit, in normalised coordinates. */
typedef struct fit_candidate {
    relief_fit_primitive prim;
    double rms;     /* over the inliers */
    double rms_all; /* over all points */
    size_t n_in;    /* inlier count */
    double med_abs; /* median |distance| over all points */
    double size;    /* radius, or the plane inliers' in-plane RMS radius */
} fit_candidate;

/* ------------------------------------------------------------ small math */

/* Scale a to unit length; returns its former length (0 leaves a as is). */
static double normalize3(double a[3])
{
    double len = sqrt(dot3(a, a));
    if (len > 0.0) {
        a[0] /= len;
        a[1] /= len;
        a[2] /= len;
    }
    return len;
}

/* Unit u, v with (u, v, a) a right-handed orthonormal frame, a unit. A
 * function of a alone, so that the Levenberg-Marquardt Jacobian and the step
 * that applies it agree on the frame. */
static void perp_basis(const double a[3], double u[3], double v[3])
{
    int k = 0;
    double e[3] = {0.0, 0.0, 0.0};
    if (fabs(a[1]) < fabs(a[k]))
        k = 1;
    if (fabs(a[2]) < fabs(a[k]))
        k = 2;
    e[k] = 1.0;
    for (int i = 0; i < 3; ++i)
        u[i] = e[i] - a[k] * a[i];
    normalize3(u);
    cross3(a, u, v);
}

/* Make the largest-magnitude component of d positive: a direction that is
 * only defined up to sign gets one reproducible sign. */
static void canonical_sign(double d[3])
{
    int k = 0;
    if (fabs(d[1]) > fabs(d[k]))
        k = 1;
    if (fabs(d[2]) > fabs(d[k]))
        k = 2;
    if (d[k] < 0.0)
        for (int i = 0; i < 3; ++i)
            d[i] = -d[i];
}

/* Eigen-decomposition of the symmetric 3 x 3 row-major matrix a_in by cyclic
 * Jacobi rotations. eval[0] >= eval[1] >= eval[2]; column j of evec
 * (evec[3 * i + j]) is the unit eigenvector of eval[j]. Jacobi rather than
 * the closed-form cubic because it stays accurate for the nearly repeated
 * eigenvalues of discs and sphere caps. */
static void sym3_eigen(const double a_in[9], double eval[3], double evec[9])
{
    double a[9], v[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    int order[3] = {0, 1, 2};

    memcpy(a, a_in, sizeof a);
    for (int sweep = 0; sweep < 64; ++sweep) {
        double off = a[1] * a[1] + a[2] * a[2] + a[5] * a[5];
        double diag = a[0] * a[0] + a[4] * a[4] + a[8] * a[8];
        if (off == 0.0 || off <= 1e-32 * diag)
            break;
        for (int p = 0; p < 2; ++p) {
            for (int q = p + 1; q < 3; ++q) {
                double apq = a[3 * p + q], theta, t, c, s;
                if (apq == 0.0)
                    continue;
                /* Numerical Recipes' rotation: the smaller angle, which
                 * keeps the sweep convergent. */
                theta = (a[3 * q + q] - a[3 * p + p]) / (2.0 * apq);
                if (fabs(theta) > 1e150)
                    t = 0.5 / theta;
                else
                    t = (theta >= 0.0 ? 1.0 : -1.0) /
                        (fabs(theta) + sqrt(theta * theta + 1.0));
                c = 1.0 / sqrt(t * t + 1.0);
                s = t * c;
                for (int k = 0; k < 3; ++k) {
                    double akp = a[3 * k + p], akq = a[3 * k + q];
                    a[3 * k + p] = c * akp - s * akq;
                    a[3 * k + q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; ++k) {
                    double apk = a[3 * p + k], aqk = a[3 * q + k];
                    a[3 * p + k] = c * apk - s * aqk;
                    a[3 * q + k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; ++k) {
                    double vkp = v[3 * k + p], vkq = v[3 * k + q];
                    v[3 * k + p] = c * vkp - s * vkq;
                    v[3 * k + q] = s * vkp + c * vkq;
                }
            }
        }
    }
    for (int i = 0; i < 2; ++i)
        for (int j = i + 1; j < 3; ++j)
            if (a[4 * order[j]] > a[4 * order[i]]) {
                int t = order[i];
                order[i] = order[j];
                order[j] = t;
            }
    for (int j = 0; j < 3; ++j) {
        eval[j] = a[4 * order[j]];
        for (int i = 0; i < 3; ++i)
            evec[3 * i + j] = v[3 * i + order[j]];
    }
}

/* Centroid m[3] and principal axes of the points q (n x 3) with mask[i] != 0
 * (all points when mask is NULL): eigenvalues of the covariance, largest
 * first, and the axes as the columns of evec. Returns the point count. */
static size_t pca(const double *q, size_t n, const uint8_t *mask, double m[3],
                  double eval[3], double evec[9])
{
    double cov[9] = {0};
    size_t cnt = 0;

    m[0] = m[1] = m[2] = 0.0;
    for (size_t i = 0; i < n; ++i) {
        if (mask && !mask[i])
            continue;
        for (int k = 0; k < 3; ++k)
            m[k] += q[3 * i + k];
        ++cnt;
    }
    if (cnt > 0)
        for (int k = 0; k < 3; ++k)
            m[k] /= (double)cnt;
    /* Second pass about the centroid: no cancellation for far-off data. */
    for (size_t i = 0; i < n; ++i) {
        double d[3];
        if (mask && !mask[i])
            continue;
        for (int k = 0; k < 3; ++k)
            d[k] = q[3 * i + k] - m[k];
        for (int r = 0; r < 3; ++r)
            for (int c = r; c < 3; ++c)
                cov[3 * r + c] += d[r] * d[c];
    }
    for (int r = 0; r < 3; ++r)
        for (int c = r; c < 3; ++c) {
            cov[3 * r + c] /= cnt > 0 ? (double)cnt : 1.0;
            cov[3 * c + r] = cov[3 * r + c];
        }
    sym3_eigen(cov, eval, evec);
    return cnt;
}

/* Solve the k x k system a x = b (row-major, k <= MAX_PARAMS) by Gaussian
 * elimination with partial pivoting; a and b are destroyed. Returns 0 when a
 * is singular to working precision or the solution is not finite. */
static int solve_dense(int k, double *a, double *b, double *x)
{
    double amax = 0.0;
    int ok = 1;

    for (int i = 0; i < k * k; ++i)
        if (fabs(a[i]) > amax)
            amax = fabs(a[i]);
    if (!(amax > 0.0) || !isfinite(amax))
        ok = 0;
    for (int c = 0; ok && c < k; ++c) {
        int piv = c;
        for (int r = c + 1; r < k; ++r)
            if (fabs(a[r * k + c]) > fabs(a[piv * k + c]))
                piv = r;
        if (fabs(a[piv * k + c]) <= 1e-14 * amax) {
            ok = 0;
            break;
        }
        if (piv != c) {
            for (int j = 0; j < k; ++j) {
                double t = a[c * k + j];
                a[c * k + j] = a[piv * k + j];
                a[piv * k + j] = t;
            }
            double t = b[c];
            b[c] = b[piv];
            b[piv] = t;
        }
        for (int r = c + 1; r < k; ++r) {
            double f = a[r * k + c] / a[c * k + c];
            for (int j = c; j < k; ++j)
                a[r * k + j] -= f * a[c * k + j];
            b[r] -= f * b[c];
        }
    }
    for (int r = k - 1; ok && r >= 0; --r) {
        double s = b[r];
        for (int j = r + 1; j < k; ++j)
            s -= a[r * k + j] * x[j];
        x[r] = s / a[r * k + r];
        if (!isfinite(x[r]))
            ok = 0;
    }
    return ok;
}

/* The lower median of a[0..n-1], n >= 1, by Hoare's selection (expected
 * linear time; a is reordered). */
static double select_median(double *a, size_t n)
{
    size_t k = (n - 1) / 2, lo = 0, hi = n - 1;

    while (lo < hi) {
        double pivot = a[lo + (hi - lo) / 2];
        size_t i = lo, j = hi;
        while (i <= j) {
            while (a[i] < pivot)
                ++i;
            while (a[j] > pivot)
                --j;
            if (i <= j) {
                double t = a[i];
                a[i] = a[j];
                a[j] = t;
                ++i;
                if (j == 0)
                    break;
                --j;
            }
        }
        if (k <= j)
            hi = j;
        else if (k >= i)
            lo = i;
        else
            break; /* a[j+1 .. i-1] all equal the pivot */
    }
    return a[k];
}

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
        if (normalize3(w) == 0.0) {
            w[0] = w[1] = 0.0;
            w[2] = 1.0;
        }
        break;
    case RELIEF_FIT_CYLINDER: {
        double t = dot3(w, prim->dir);
        for (int k = 0; k < 3; ++k)
            w[k] -= t * prim->dir[k];
        if (normalize3(w) == 0.0) {
            perp_basis(prim->dir, u, v);
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
    ok = solve_dense(4, ata, atb, x);
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

    perp_basis(axis, u, v);
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
    ok = solve_dense(3, ata, atb, x);
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
static void recentre_axis(relief_fit_primitive *c)
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
        normalize3(out->dir);
        out->radius += delta[4];
        recentre_axis(out);
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
            perp_basis(s->dir, u, v);
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
            if (solve_dense(np, A, b, delta) && lm_apply(s, u, v, delta, &trial)) {
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
        ok = pca(w->q, w->n, mask, m, eval, evec) >= 3;
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
    thr = RELIEF_FIT_TRIM_K * MAD_TO_SIGMA * select_median(w->tmp, w->n);
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
static int robust_fit(fit_work *w, const relief_fit_primitive *start,
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
        out->med_abs = select_median(w->tmp, w->n);
        out->size = s.radius;
        if (s.model == RELIEF_FIT_PLANE) {
            double m[3], eval[3], evec[9];
            pca(w->q, w->n, w->mask, m, eval, evec);
            out->size = sqrt(fmax(eval[0] + eval[1], 0.0));
        }
    }
    return ok;
}

/* Fit one model robustly. The cylinder's start axes (n_axes x 3, unit) are
 * ranked by a short refinement on all points, scored by the median
 * |distance| (which outliers cannot sway); only the best is fitted robustly.
 * Returns 0 when nothing could be fitted. */
static int fit_model(fit_work *w, relief_fit_model model, size_t need,
                     const double (*axes)[3], int n_axes, fit_candidate *out)
{
    relief_fit_primitive start, trial;
    double best_med = INFINITY;
    int ok = 0;

    memset(&start, 0, sizeof start);
    start.model = model;
    if (model == RELIEF_FIT_PLANE) {
        ok = robust_fit(w, &start, need, out);
    } else if (model == RELIEF_FIT_SPHERE) {
        ok = sphere_start(w, &start) && robust_fit(w, &start, need, out);
    } else {
        memset(w->mask, 1, w->n);
        for (int a = 0; a < n_axes; ++a) {
            double med;
            if (!cylinder_start(w, axes[a], &trial) ||
                !refine(w, w->mask, LM_ITERATIONS_SCREEN, &trial))
                continue;
            for (size_t i = 0; i < w->n; ++i)
                w->tmp[i] = fabs(relief_fit_distance(&trial, w->q + 3 * i));
            med = select_median(w->tmp, w->n);
            if (med < best_med) {
                best_med = med;
                start = trial;
                ok = 1;
            }
        }
        ok = ok && robust_fit(w, &start, need, out);
    }
    return ok;
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

    pca(q, n, NULL, m, eval, evec);
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
        double t = PI_ * (double)a / AXES_IN_PLANE;
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
            sym3_eigen(nn, nev, nvec);
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
        have[mm] = fit_model(&sel, mm, min_points(mm),
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
        if (!robust_fit(&w, &start, min_points(best), &cand[best])) {
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
                canonical_sign(p->dir);
        } else if (p->model == RELIEF_FIT_CYLINDER) {
            recentre_axis(p);
            canonical_sign(p->dir);
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
            normalize3(nrm + 3 * v);
        use = nrm;
    }
    st = relief_fit(mesh->pos, use, mesh->nv, model, out, err);

done:
    free(nrm);
    return st;
}
