/* Small dense linear algebra on doubles: 3-vectors, the symmetric 3 x 3
 * eigenproblem, principal axes of a point set, a k x k solve and a median.
 * Shared by the fit and by what needs covariance frames. */
#ifndef RELIEF_HOST_LINALG_H
#define RELIEF_HOST_LINALG_H

#include <stddef.h>
#include <stdint.h>

/* Scale a to unit length; returns its former length (0 leaves a as is). */
double relief_normalize3(double a[3]);

/* Unit u, v with (u, v, a) a right-handed orthonormal frame, a unit. A
 * function of a alone, so that the Levenberg-Marquardt Jacobian and the step
 * that applies it agree on the frame. */
void relief_perp_basis(const double a[3], double u[3], double v[3]);

/* Make the largest-magnitude component of d positive: a direction that is
 * only defined up to sign gets one reproducible sign. */
void relief_canonical_sign(double d[3]);

/* Eigen-decomposition of the symmetric 3 x 3 row-major matrix a_in by cyclic
 * Jacobi rotations. eval[0] >= eval[1] >= eval[2]; column j of evec
 * (evec[3 * i + j]) is the unit eigenvector of eval[j]. Jacobi rather than
 * the closed-form cubic because it stays accurate for the nearly repeated
 * eigenvalues of discs and sphere caps. */
void relief_sym3_eigen(const double a_in[9], double eval[3], double evec[9]);

/* The same for a symmetric n x n row-major matrix, 1 <= n <=
 * RELIEF_SYM_EIGEN_MAX: eval[n], evec[n x n] (column j the eigenvector of
 * eval[j], eigenvalues largest first); work holds 2 n^2 doubles. Cyclic
 * Jacobi: O(n^3) per sweep, meant for small n (descriptor covariances). */
#define RELIEF_SYM_EIGEN_MAX 64
void relief_sym_eigen(int n, const double *a_in, double *eval, double *evec, double *work);

/* Centroid m[3] and principal axes of the points q (n x 3) with mask[i] != 0
 * (all points when mask is NULL): eigenvalues of the covariance, largest
 * first, and the axes as the columns of evec. Returns the point count. */
size_t relief_pca3(const double *q, size_t n, const uint8_t *mask, double m[3],
                   double eval[3], double evec[9]);

/* Solve the k x k system a x = b (row-major) by Gaussian elimination with
 * partial pivoting; a and b are destroyed. Returns 0 when a is singular to
 * working precision or the solution is not finite. */
int relief_solve_dense(int k, double *a, double *b, double *x);

/* The lower median of a[0..n-1], n >= 1, by Hoare's selection (expected
 * linear time; a is reordered). */
double relief_select_median(double *a, size_t n);

#endif
