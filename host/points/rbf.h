/* A smooth implicit surface through an oriented point set, and new points
 * sampled on it across a hole (paper 002, section 6.1: the base's holes are
 * filled by compactly supported radial basis functions, hierarchical as in
 * Ohtake, Belyaev and Seidel 2003, "A multi-scale approach to 3D scattered
 * data interpolation with compactly supported basis functions").
 *
 * f(x) = sum over levels l of sum over centres c of level l of
 *        (g_c(x) + lambda_c) phi(|x - c| / rho_l),
 * phi the Wendland function (1 - r)^4_+ (4 r + 1), rho_l halving from level
 * to level, g_c a local linear approximation of the signed distance at c
 * (from its normal) and lambda_c solved so that the levels so far
 * interpolate f = 0 at the level's centres (Ohtake's scheme). f < 0 inside,
 * > 0 outside (along the normals), |grad f| about 1 near the points.
 * Units: the points' own (any length unit); all lengths below are in it. */
#ifndef RELIEF_HOST_POINTS_RBF_H
#define RELIEF_HOST_POINTS_RBF_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"

typedef struct relief_rbf relief_rbf;

typedef struct relief_rbf_params {
    int levels;           /* number of levels, 1..16 (default 0: as many as it
                             takes for rho to reach 2 x spacing, at most 12) */
    double spacing;       /* the points' mean nearest-neighbour distance (> 0; required) */
    double base_support;  /* rho of the coarsest level (default 0: 0.75 x the
                             bounding box's diagonal, Ohtake's choice) */
} relief_rbf_params;

/* Defaults as stated above (spacing must then be set by the caller). */
relief_rbf_params relief_rbf_params_default(void);

/* Fit f to n points pos (n x 3) with unit outward normals nrm (n x 3).
 * RELIEF_E_RANGE for n < 4 or a bad parameter; RELIEF_E_NOMEM; *out NULL on
 * failure. */
relief_status relief_rbf_fit(const double *pos, const double *nrm, size_t n,
                             const relief_rbf_params *p, relief_rbf **out,
                             relief_error *err);
void relief_rbf_free(relief_rbf *f);

/* f(x) and, when grad is not NULL, its gradient (3). */
double relief_rbf_eval(const relief_rbf *f, const double x[3], double grad[3]);

/* Move x onto f = 0 by Newton steps along the gradient, at most max_iter
 * steps, until |f| <= tol. 1 when it converged, 0 when not (x is then the
 * last iterate). */
int relief_rbf_project(const relief_rbf *f, double x[3], int max_iter, double tol);

/* New points on f = 0 across the holes whose rims are marked, at about
 * `spacing` from each other and from the given points: an advancing front
 * that starts at the rim points, steps `spacing` away from each front
 * point's captured neighbours in its tangent plane, projects each step onto
 * f = 0 and keeps it when no point (given or new) lies within 0.75 x
 * spacing and it stays within the bounding sphere of its hole's rim (centre
 * the rim's centroid, radius its farthest rim point plus one spacing).
 *   pos, nrm: n x 3 points and unit normals (the base surface);
 *   rim: n entries, 0 for a point on no hole's rim, k >= 1 for a point on
 *        the rim of hole k (holes numbered 1..n_holes);
 *   max_new: refuse (RELIEF_E_NOMEM naming the count) beyond it;
 *   out_pos, out_nrm: malloc'ed n_new x 3 (normals: f's normalised
 *        gradient), out_hole: malloc'ed n_new hole ids; all NULL when 0.
 * Deterministic (no randomness; the front is processed in index order). */
relief_status relief_rbf_fill_holes(const relief_rbf *f, const double *pos,
                                    const double *nrm, size_t n, const uint32_t *rim,
                                    uint32_t n_holes, double spacing, size_t max_new,
                                    double **out_pos, double **out_nrm,
                                    uint32_t **out_hole, size_t *n_new,
                                    relief_error *err);

#endif
