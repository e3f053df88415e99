/* The surface `relief complete --base smooth` grows on (issue 21): paper
 * 002's smoothed, hole-filled base under a capture that no primitive fits,
 * in the form the paper 000/001 growth reads (smooth/surface.h).
 *
 * The capture's vertices are the samples, at their captured positions;
 * their projection p' is their base point (the curvature flow of
 * points/flow.h), their displacement p - p', their normal the base's. The
 * targets are the new base points the hierarchical RBF lays across the
 * holes (points/rbf.h), on the base exactly. The triangulation is the
 * capture's own with the holes' patches (points/patch_mesh.h); a point in
 * no triangle (a crack between patches) is left out, since the growth
 * could not reach it. Frames
 * follow paper 000's rule on the normal. `fit` holds the primitive the
 * capture fits best (the caller's `fitted` when given, else
 * relief_fit_mesh's), for the report and the measures only: nothing of the
 * growth depends on it. `free_form` is set: the hierarchy (--levels)
 * coarsens this triangulation by collapses rather than re-triangulating
 * in a parameter domain the base does not have. */
#ifndef RELIEF_HOST_POINTS_BASE_SURFACE_H
#define RELIEF_HOST_POINTS_BASE_SURFACE_H

#include "relief/relief.h"
#include "points/complete_points.h"
#include "smooth/surface.h"

/* capture: a mesh (triangles required: RELIEF_E_RANGE otherwise). p: the
 * point-set parameters (relief_points_params_default(); the texture ones
 * unused). fitted (may be NULL): the capture's primitive, already fitted
 * by the caller with RELIEF_FIT_AUTO, so it is not fitted twice. rep (may
 * be NULL): what the base's construction found.
 * RELIEF_E_RANGE as relief_points_complete (no hole, too few points, ...);
 * RELIEF_E_NOMEM. *out only on success. */
relief_status relief_points_base_surface(const relief_mesh *capture,
                                         const relief_points_params *p,
                                         const relief_fit_result *fitted, relief_surface **out,
                                         relief_points_report *rep, relief_error *err);

#endif
