/* Small dense linear algebra (linalg.h). */
#include "base/linalg.h"

#include <math.h>
#include <string.h>

#include "base/vec3.h"

/* Scale a to unit length; returns its former length (0 leaves a as is). */
double relief_normalize3(double a[3])
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
void relief_perp_basis(const double a[3], double u[3], double v[3])
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
    relief_normalize3(u);
    cross3(a, u, v);
}

/* Make the largest-magnitude component of d positive: a direction that is
 * only defined up to sign gets one reproducible sign. */
void relief_canonical_sign(double d[3])
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

/* Cyclic Jacobi rotations (linalg.h); for n = 3 rather than the closed-form
 * cubic because it stays accurate for the nearly repeated eigenvalues of
 * discs and sphere caps. */
void relief_sym_eigen(int n, const double *a_in, double *eval, double *evec, double *work)
{
    double *a = work, *v = work + (size_t)n * (size_t)n;
    int order[RELIEF_SYM_EIGEN_MAX];
    memcpy(a, a_in, (size_t)n * (size_t)n * sizeof *a);
    memset(v, 0, (size_t)n * (size_t)n * sizeof *v);
    for (int i = 0; i < n; ++i) {
        v[n * i + i] = 1.0;
        order[i] = i;
    }
    for (int sweep = 0; sweep < 64; ++sweep) {
        double off = 0.0, diag = 0.0;
        for (int p = 0; p < n; ++p)
            for (int q = p + 1; q < n; ++q)
                off += a[n * p + q] * a[n * p + q];
        for (int p = 0; p < n; ++p)
            diag += a[n * p + p] * a[n * p + p];
        if (off == 0.0 || off <= 1e-32 * diag)
            break;
        for (int p = 0; p < n - 1; ++p) {
            for (int q = p + 1; q < n; ++q) {
                double apq = a[n * p + q], theta, t, c, s;
                if (apq == 0.0)
                    continue;
                /* Numerical Recipes' rotation: the smaller angle, which
                 * keeps the sweep convergent. */
                theta = (a[n * q + q] - a[n * p + p]) / (2.0 * apq);
                if (fabs(theta) > 1e150)
                    t = 0.5 / theta;
                else
                    t = (theta >= 0.0 ? 1.0 : -1.0) /
                        (fabs(theta) + sqrt(theta * theta + 1.0));
                c = 1.0 / sqrt(t * t + 1.0);
                s = t * c;
                for (int k = 0; k < n; ++k) {
                    double akp = a[n * k + p], akq = a[n * k + q];
                    a[n * k + p] = c * akp - s * akq;
                    a[n * k + q] = s * akp + c * akq;
                }
                for (int k = 0; k < n; ++k) {
                    double apk = a[n * p + k], aqk = a[n * q + k];
                    a[n * p + k] = c * apk - s * aqk;
                    a[n * q + k] = s * apk + c * aqk;
                }
                for (int k = 0; k < n; ++k) {
                    double vkp = v[n * k + p], vkq = v[n * k + q];
                    v[n * k + p] = c * vkp - s * vkq;
                    v[n * k + q] = s * vkp + c * vkq;
                }
            }
        }
    }
    for (int i = 0; i < n - 1; ++i)
        for (int j = i + 1; j < n; ++j)
            if (a[(n + 1) * order[j]] > a[(n + 1) * order[i]]) {
                int t = order[i];
                order[i] = order[j];
                order[j] = t;
            }
    for (int j = 0; j < n; ++j) {
        eval[j] = a[(n + 1) * order[j]];
        for (int i = 0; i < n; ++i)
            evec[n * i + j] = v[n * i + order[j]];
    }
}

void relief_sym3_eigen(const double a_in[9], double eval[3], double evec[9])
{
    double work[18];
    relief_sym_eigen(3, a_in, eval, evec, work);
}

/* Centroid m[3] and principal axes of the points q (n x 3) with mask[i] != 0
 * (all points when mask is NULL): eigenvalues of the covariance, largest
 * first, and the axes as the columns of evec. Returns the point count. */
size_t relief_pca3(const double *q, size_t n, const uint8_t *mask, double m[3],
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
    relief_sym3_eigen(cov, eval, evec);
    return cnt;
}

/* Solve the k x k system a x = b (row-major) by Gaussian elimination with
 * partial pivoting; a and b are destroyed. Returns 0 when a is singular to
 * working precision or the solution is not finite. */
int relief_solve_dense(int k, double *a, double *b, double *x)
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
double relief_select_median(double *a, size_t n)
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
