/* Local analysis of a point set (paper 002, section 3.1): k nearest
 * neighbours, covariance normals consistently oriented, the surface
 * variation sigma_n, and the sampling spacing.
 *
 * Arrays are row-major: "n x 3" is n consecutive (x, y, z). Lengths are in
 * the points' own unit. */
#ifndef RELIEF_HOST_POINTS_ANALYSIS_H
#define RELIEF_HOST_POINTS_ANALYSIS_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"

/* The k nearest neighbours of every point, itself excluded, nearest first:
 * nbr[i * k + j] and its squared distance d2[i * k + j]. */
typedef struct relief_knn_graph {
    size_t n;
    int k;
    uint32_t *nbr; /* n x k */
    double *d2;    /* n x k */
} relief_knn_graph;

/* Exact k-NN (FLANN, single kd-tree, deterministic) of n points pos, the
 * queries on `threads` of FLANN's (1: the calling thread; the same graph
 * whatever their number). k in 3..64 and n > k, else RELIEF_E_RANGE naming
 * both; RELIEF_E_NOMEM. */
relief_status relief_knn_graph_build(const double *pos, size_t n, int k, int threads,
                                     relief_knn_graph *g, relief_error *err);
void relief_knn_graph_free(relief_knn_graph *g);

/* The median over the points of the distance to the nearest neighbour. */
double relief_knn_spacing(const relief_knn_graph *g);

/* Covariance analysis of point i's neighbourhood in pos (itself and its k
 * neighbours of g): the centroid (3, may be NULL), the unit eigenvector of
 * the least eigenvalue lambda0 (3, its sign as the eigen-solver gives it)
 * and, returned, the surface variation lambda0 / (lambda0 + lambda1 +
 * lambda2) (0 for coincident points). */
double relief_points_covariance(const double *pos, const relief_knn_graph *g, size_t i,
                                double centroid[3], double normal[3]);

/* Covariance analysis of each point's neighbourhood (itself and its k
 * neighbours): nrm (n x 3) the eigenvector of the least eigenvalue lambda0,
 * sigma (n, may be NULL) the surface variation lambda0 / (lambda0 + lambda1
 * + lambda2), in 0..1/3. Orientation:
 *   - with `hint` (n x 3, e.g. a mesh's or a scanner's normals; zero rows
 *     allowed), each normal agrees in sign with its hint where the hint is
 *     non-zero;
 *   - the rest by Hoppe et al. 1992: propagated over a minimum spanning tree
 *     of the k-NN graph weighted 1 - |n_i . n_j|, each connected component
 *     started at its point of largest `view` projection (the point farthest
 *     along `view`, normal made to point along `view`). With `viewpoint`
 *     (3, may be NULL; a depth camera's centre) every normal instead faces
 *     the viewpoint, as for a one-sided capture.
 * The covariances are shared out over `threads` (1: the calling thread
 * alone), each point alone, so the bytes do not depend on it.
 * RELIEF_E_NOMEM. */
relief_status relief_points_normals(const double *pos, const relief_knn_graph *g,
                                    const double *hint, const double *viewpoint, int threads,
                                    double *nrm, double *sigma, relief_error *err);

/* Are the points spread in 2 dimensions at least? 0 when they are all on a
 * line (the second principal extent below 1e-6 of the first) or all at one
 * place, else 1; *why names which. */
int relief_points_spread(const double *pos, size_t n, const char **why);

#endif
