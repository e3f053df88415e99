/* Where relief_surface_build lays its targets: the points of the fitted primitive
 * the capture does not cover, and which of them to complete.
 *
 * The uncovered points split into connected regions. A region is a hole
 * when the capture's outline encloses it; it is outside the outline when
 * it reaches the lattice's border (plane: any side of the region laid;
 * cylinder: the first or last row along the axis) or, on a sphere, when it
 * is larger than the capture's own cover. The region completed
 * (relief_fill):
 *   HOLES  the holes only, as a plane without --extent has always been;
 *   WHOLE  every uncovered point: the back of a one-sided scan;
 *   AUTO   a plane: HOLES, or WHOLE inside an --extent; a cylinder with
 *          --extent: WHOLE; otherwise HOLES when the capture has holes and
 *          covers less than RELIEF_ONE_SIDED_COVER of the primitive (a patch
 *          of a larger object with a gap in it: the rest of the sphere is
 *          not what was lost), else WHOLE (a one-sided scan, whose hidden
 *          side is the hole). */
#ifndef RELIEF_HOST_TARGETS_H
#define RELIEF_HOST_TARGETS_H

#include <stddef.h>

#include "base/error.h"
#include "base/params.h"
#include "mesh/mesh.h"
#include "smooth/param.h"
#include "smooth/surface.h"

/* Points on the primitive, n x 3 (input units), owned by the caller:
 * free(p). */
typedef struct relief_target_list {
    double *p;
    size_t n, cap;
} relief_target_list;

/* Lay a triangular lattice of edge `spacing` (plane, cylinder; a Fibonacci
 * lattice of the same density on a sphere) over the region params gives
 * (cylinder: the full turn over the capture's axial extent or
 * params->extent z0,z1; plane: the capture's bounding rectangle plus one
 * spacing, or params->extent u0,v0,u1,v1; sphere: all of it), keep the
 * points no projected capture triangle covers within half a spacing, and of
 * those the region opts->fill selects (above; auto: the holes only when the
 * capture goes all round its cylinder or sphere), the enclosed regions
 * through opts->holes' filter when only holes are filled; an enclosed region
 * that `scanned` (the capture as given, before relief dropped its folded
 * triangles or spikes; NULL or `capture` when nothing was dropped) covers
 * is relief's own hole, completed whatever the filter says. The points go to *out in
 * lattice order; *stats says what was found and chosen. RELIEF_E_USAGE for
 * an extent of the wrong length, RELIEF_E_RANGE for a lattice over 50
 * million points, RELIEF_E_NOMEM. */
relief_status relief_targets_lay(const relief_mesh *capture, const relief_mesh *scanned,
                                 const relief_domain *param, double spacing,
                                 const relief_params *params,
                                 const relief_smooth_options *opts,
                                 relief_target_list *out, relief_fill_stats *stats,
                                 relief_error *err);

#endif
