/* Primitive fitting: the smooth base shape (plane, sphere or cylinder) that
 * the completion continues, and the geometry the later stages need from it
 * (signed distance, projection, outward normal).
 *
 * Method. Every model starts from a closed-form estimate and is then refined
 * on the orthogonal (Euclidean) distances:
 * - plane: principal component analysis (3 x 3 Jacobi eigen-solver). The
 *   plane through the centroid normal to the direction of least spread IS the
 *   orthogonal least-squares plane, so there is nothing left to refine.
 * - sphere: algebraic linear least squares (|p|^2 = 2 c.p + d), then
 *   Levenberg-Marquardt on |p - c| - r.
 * - cylinder: for each start axis (6 directions 30 degrees apart in the
 *   plane of the two larger principal axes, the smallest principal axis,
 *   and the direction most orthogonal to the normals when normals are
 *   given), an algebraic circle fit in the plane orthogonal to the axis, then
 *   Levenberg-Marquardt on the 5 parameters (axis point 2, axis direction 2,
 *   radius 1); the direction is updated by a local rotation about the two
 *   axes orthogonal to it, so no parameterisation singularity exists. The
 *   start axes are ranked by the median |distance| after a short
 *   refinement; the best one is then fitted in full.
 * All of this runs on points centred on their centroid and scaled to unit
 * RMS radius, so the tolerances are scale-free (a drill bit in metres and a
 * building in millimetres behave alike).
 *
 * Robustness. After the first fit on all points, points with |distance| >
 * RELIEF_FIT_TRIM_K * s, s = 1.4826 * median |distance| (the MAD scale of a
 * zero-centred residual), are dropped and the model refitted, until the
 * inlier set stops changing (at most RELIEF_FIT_TRIM_PASSES passes). The
 * threshold never drops more than half the points. Relief that is not
 * noise (a drill's flutes) is partly trimmed too, which pulls a radius
 * slightly towards the majority of the surface; rms_all reports the
 * residual over every point.
 *
 * Model choice (RELIEF_FIT_AUTO). Each model (k = 3, 4, 5 parameters) is
 * scored over ALL n points by
 *     sqrt(sum_i min(d_i^2, T^2) / (n - k)) * (1 + RELIEF_FIT_GAIN)^(k - 3)
 * with T the trimming threshold of the model whose threshold is smallest.
 * The common cap makes a point that one model trims cost it as much as a
 * gross outlier costs every model, so no model wins by discarding points
 * (truncated least squares, as in MSAC or Torr's GRIC); n - k is the usual
 * degrees-of-freedom correction. The lowest score wins, so every extra
 * parameter must cut the residual by RELIEF_FIT_GAIN (10%): a sphere or
 * cylinder fitted to a plane always reaches a slightly lower residual, and
 * this keeps the plane. The reason string quotes each model's inlier rms.
 * On more than 20000 points the choice (and the ranking of the cylinder's
 * start axes) is made on an evenly strided subset of 20000, and the chosen
 * model is then refitted on all points; model_rms of the models not chosen
 * are then those of the subset.
 *
 * Units. Positions, distances, radii and rms are in the input's units; the
 * fitted primitive is in the input's coordinate frame. Arrays are row-major:
 * "n x 3" means n consecutive (x, y, z) triples.
 */
#ifndef RELIEF_HOST_FIT_H
#define RELIEF_HOST_FIT_H

#include <stddef.h>

#include "relief/relief.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Robust trimming: inlier when |distance| <= K * 1.4826 * median|distance|. */
#define RELIEF_FIT_TRIM_K 3.0
/* Most refit-and-trim passes after the first fit. */
#define RELIEF_FIT_TRIM_PASSES 10
/* Fraction by which each extra parameter must cut the residual (auto). */
#define RELIEF_FIT_GAIN 0.10
/* relief_fit_primitive, relief_fit_result, relief_fit, relief_fit_mesh
 * and relief_fit_distance are public: relief/complete.h. */

/* relief_fit and relief_fit_mesh (which run on one thread) with the
 * cylinder's start axes ranked on `threads` host threads (0: the default,
 * relief_pool_threads_for): the same result for any count. */
relief_status relief_fit_threads(const double *pts, const double *normals, size_t n,
                                 relief_fit_model model, int threads, relief_fit_result *out,
                                 relief_error *err);
relief_status relief_fit_mesh_threads(const relief_mesh *mesh, relief_fit_model model,
                                      int threads, relief_fit_result *out, relief_error *err);

/* Unit outward normal of the primitive at the foot of p, written to
 * nrm[3]: the plane's dir; (p - centre) / |p - centre| for a sphere; the
 * radial direction from the axis for a cylinder. At a sphere's centre or on
 * a cylinder's axis, where it is undefined, a fixed unit vector (orthogonal
 * to the axis for a cylinder) is returned. */
void relief_fit_normal(const relief_fit_primitive *prim, const double p[3],
                       double nrm[3]);

/* Orthogonal projection q[3] of p[3] onto the primitive, the closest point
 * of the (infinite) surface: q = p - distance(p) * normal(p). The
 * displacement of p from the primitive is D = p - q. q may alias p. */
void relief_fit_project(const relief_fit_primitive *prim, const double p[3],
                        double q[3]);

#ifdef __cplusplus
}
#endif

#endif
