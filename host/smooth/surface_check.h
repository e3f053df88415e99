/* Geometry the method cannot handle, refused with the place named instead
 * of a wrong answer (issue 8).
 *
 * The capture must be a single-layer height field over its primitive:
 * relief projects it onto the primitive and triangulates it there, so an
 * edge shared by three or more triangles (a fin, or a second layer) or a
 * part folded back over another (two layers over one spot of the
 * primitive) would be woven into one layer: a large fold is refused, a
 * fringe of a few folded triangles dropped with its vertices. A vertex where two fans of
 * triangles touch, common in range scans, is harmless for the same reason
 * and accepted. The growth needs every target
 * joined to the capture and at least one sample whose window lies wholly
 * in the capture. */
#ifndef RELIEF_HOST_SURFACE_CHECK_H
#define RELIEF_HOST_SURFACE_CHECK_H

#include "relief/relief.h"
#include "smooth/fit.h"
#include "smooth/surface.h"

/* Fraction of the capture's area that may face away from the primitive
 * (the fringes a depth camera leaves at depth edges: 1.4 to 2.9 % on
 * Kinect-class meshes) before the capture counts as folded and is refused;
 * below it the folded triangles are dropped. */
#define RELIEF_FOLD_AREA_MAX 0.1

/* A triangle faces away when its normal makes more than this angle's
 * cosine with the primitive's normal (120 degrees). */
#define RELIEF_FOLD_COS -0.5

/* How the refusal of a capture that folds over its primitive by more than
 * RELIEF_FOLD_AREA_MAX begins (complete's base auto answers it with the
 * smoothed base). */
#define RELIEF_FOLD_REFUSAL "the capture overlaps itself over the fitted"


/* Check the capture against its fitted primitive. RELIEF_E_MESH naming
 * the place: an edge shared by more than two triangles (its vertex ids,
 * midpoint and triangles), or triangles folded back over the primitive on
 * more than RELIEF_FOLD_AREA_MAX of its area (how many, their share of the
 * area, the largest one's id, vertices and position). Fewer folded
 * triangles are dropped with every vertex they touch, leaving a hole the
 * completion fills: *unfolded (the caller's to destroy) is the capture
 * without them, NULL when nothing folds. *folds (may be NULL) counts them. */
relief_status relief_capture_check(const relief_mesh *capture,
                                   const relief_fit_primitive *prim, relief_mesh **unfolded,
                                   relief_fold_stats *folds, relief_error *err);

/* Scanner spikes, flying pixels and rim fringes are not relief. For each
 * capture vertex v with 3 or more neighbours (h: the signed distance to the
 * primitive), its excess is how far h(v) lies outside [min, max] of its
 * neighbours' h (0 inside: a band's edge or a dimple's rim is not a
 * spike); the scale is 1.4826 x the median of |h(v) - the median of its
 * neighbours' h| over those vertices (the standard deviation for Gaussian
 * roughness), and at least 1e-6 of the capture's bounding-box diagonal
 * (a float file's precision); a vertex whose excess is over k x scale is
 * a spike. *despiked (the
 * caller's) is the capture without the spikes and their triangles, NULL
 * when there is none; *sp counts them. RELIEF_E_MESH when nothing would be
 * left. */
relief_status relief_capture_spikes(const relief_mesh *capture,
                                    const relief_fit_primitive *prim, double k,
                                    relief_mesh **despiked, relief_spike_stats *sp,
                                    relief_error *err);

/* Check a surface can be grown with windows of `window` edge hops.
 * RELIEF_E_MESH when targets have no path to a sample in the triangulation
 * (how many, and one of them with its position), when no sample has a
 * complete neighbourhood (every sample is next to a target), or when no
 * sample has its whole `window`-hop neighbourhood among the samples (the
 * capture is smaller than the window; the message gives the largest window
 * that would fit). */
relief_status relief_surface_check_growth(const relief_surface *s, int window,
                                          relief_error *err);

#endif
