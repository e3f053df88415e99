/* A smooth implicit surface through an oriented point set, and new points
 * sampled on it across a hole (paper 002, section 6.1: the base's holes are
 * filled by compactly supported radial basis functions, hierarchical as in
 * Ohtake, Belyaev and Seidel 2003, "A multi-scale approach to 3D scattered
 * data interpolation with compactly supported basis functions").
 *
 * f(x) = sum over levels l of sum over centres c of level l of
 *        (g_c(x) + lambda_c) phi(|x - c| / rho_l),
 * phi the Wendland function (1 - r)^4_+ (4 r + 1), rho_l halving from level
 * to level. A level's centres are the points clustered in cells of
 * max(rho_l / 2, spacing / 2) (per occupied cell, the point nearest the
 * cell's centroid, with the cell's mean normal). g_c is a local quadratic
 * approximation of the signed distance at c, as Ohtake's: the height over
 * c's tangent plane fitted by weighted least squares to the points within
 * max(rho_l, 3 spacing) whose normals agree with c's (the tangent plane
 * where too few do), divided by the overlap sum_j phi(|c - c_j| / rho_l)
 * at c and by the number of levels, so that the levels together
 * approximate the signed distance. lambda_c is solved (conjugate gradients
 * on the sparse, positive definite Wendland system) so that the levels so
 * far interpolate f = 0 at the level's centres. f < 0 inside, > 0 outside
 * (along the normals); near the points |grad f| is about 1 (0.77 to 1 on a
 * sphere), less over a hole, where only the coarse levels reach; f = 0
 * beyond every support (farther than rho_0 from the coarsest centres).
 * Evaluation visits, per level, the centres within rho_l through a hash of
 * cells rho_l wide.
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
    int threads;          /* host threads of the fit, 0..64 (default 0: the CPUs
                             this thread may run on); the bytes do not depend on it */
} relief_rbf_params;

/* Defaults as stated above (spacing must then be set by the caller). */
relief_rbf_params relief_rbf_params_default(void);

/* Fit f to n points pos (n x 3) with outward normals nrm (n x 3; unit, or
 * normalised here). RELIEF_E_RANGE for n < 4, a coordinate or normal that
 * is not finite, a zero normal, points that all coincide, a bad parameter,
 * or a spacing (or finest support) so small against the points' extent
 * that the cells would number more than 2^18 across; RELIEF_E_NOMEM; *out
 * NULL on failure. */
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
 * In detail: the step direction is the tangent-plane part of p minus the
 * centroid of p's neighbours within 2 spacings (given and new points; p is
 * skipped when that is zero), and from each front point 5 steps are tried,
 * along it and turned by +-45 and +-90 degrees about p's normal, so that
 * the front also spreads sideways and closes up between its steps. A step
 * is projected by relief_rbf_project (10 Newton steps, |f| <= 1e-3
 * spacing) and dropped when that fails or moves it more than 2 spacings.
 * A step is also dropped when the given point nearest to it (within 2
 * spacings) is on no rim: in a hole the nearest captured point is on the
 * hole's rim, so such a step has turned back over the capture (between the
 * sparse vertices of a decimated mesh, say). Every kept point joins the
 * front (first in, first out).
 *   pos, nrm: n x 3 points and unit normals (the base surface);
 *   rim: n entries, 0 for a point on no hole's rim, k >= 1 for a point on
 *        the rim of hole k (holes numbered 1..n_holes);
 *   spacing: > 0, in the points' unit;
 *   max_new: refuse (RELIEF_E_NOMEM naming the count) beyond it;
 *   out_pos, out_nrm: malloc'ed n_new x 3 (normals: f's normalised
 *        gradient, turned to agree with the nearest rim point's normal),
 *        out_hole: malloc'ed n_new hole ids; all NULL when 0, and on
 *        failure (n_new 0 then).
 * RELIEF_E_RANGE for n < 4, spacing <= 0 (or too small for the points'
 * extent, as for the fit), a rim mark above n_holes or a point that is not
 * finite. No rim point: RELIEF_OK with no new point.
 * Deterministic (no randomness; the front is processed in index order). */
relief_status relief_rbf_fill_holes(const relief_rbf *f, const double *pos,
                                    const double *nrm, size_t n, const uint32_t *rim,
                                    uint32_t n_holes, double spacing, size_t max_new,
                                    double **out_pos, double **out_nrm,
                                    uint32_t **out_hole, size_t *n_new,
                                    relief_error *err);

#endif
