/* The base surface and the detail over it (paper 002, section 5).
 *
 * Base: the point curvature flow of eq. 5, du_i/dt = -k_i n_i with
 * k_i = sign_i sigma_n(i), integrated by explicit Euler; the sign is eq. 4's
 * Gaussian-weighted side test, sign of sum_u G(|p_i - u|) n_i . (p_i - u)
 * over the k neighbours (G's sigma the mean neighbour distance), so a point
 * above its neighbours moves down. Each step recomputes the covariance
 * normal and sigma_n over the same neighbours (indices from the input's
 * k-NN graph: points move along their normals by a fraction of the spacing
 * per step, so the neighbourhoods stay), each normal's sign following the
 * previous step's as the paper does. sigma_n falls with the square of a
 * point's offset from its neighbours, so the time step has to be long
 * (relief's default is 10 spacings) to move small offsets at all; a step
 * never carries a point past its neighbourhood's least-squares plane, which
 * keeps that long step stable where offsets are large.
 *
 * Shape stays in the base: a point's base point never lies farther than
 * max_disp from the point (a step that would carry it farther is cut back
 * along the whole displacement). Without it a part only a few spacings
 * thick, an arm of fertility at its 2.4-unit spacing, is flattened into a
 * blade by the flow, and its "detail" is then the arm's own shape (RMS 1.7
 * spacings there), which the base's hole patch and the synthesis cannot
 * carry.
 *
 * Detail: c_i = sign((p_i - p'_i) . n'_i) |p_i - p'_i|, the signed distance
 * of the input point from its base point along the base normal, so that
 * p'_i + c_i n'_i reconstructs p_i up to the tangential part of p_i - p'_i.
 *
 * Arrays n x 3 row-major, lengths in the points' unit. */
#ifndef RELIEF_HOST_POINTS_FLOW_H
#define RELIEF_HOST_POINTS_FLOW_H

#include <stddef.h>

#include "relief/relief.h"
#include "points/analysis.h"

/* `steps` (0..10000) Euler steps of time step dt (> 0, a length, since
 * sigma_n has no unit) from pos
 * (with its oriented normals nrm) into base (n x 3) and base_nrm (n x 3),
 * no base point farther than max_disp (a length; 0: unbounded) from its
 * point. Each step's points are shared out over `threads` (1: the calling
 * thread alone); every point is computed alone, so the bytes do not depend
 * on it. RELIEF_E_RANGE for steps, dt or max_disp out of range. */
relief_status relief_curvature_flow(const double *pos, const double *nrm,
                                    const relief_knn_graph *g, int steps, double dt,
                                    double max_disp, int threads, double *base,
                                    double *base_nrm, relief_error *err);

/* The signed detail c (n) of pos over base/base_nrm, and the RMS of
 * |base + c base_nrm - pos| over the points (the reconstruction's error),
 * returned. */
double relief_detail_encode(const double *pos, const double *base, const double *base_nrm,
                            size_t n, float *c);

#endif
