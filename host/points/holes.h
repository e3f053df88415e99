/* Where a point set has holes (issue 21): the rims of the holes, numbered.
 *
 * A mesh's holes are its boundary loops (edges of one triangle). A bare
 * point set's rim points are those whose neighbourhood is one-sided: the
 * k neighbours projected on the point's tangent plane leave an angular gap
 * wider than `gap` (radians; relief uses pi/2, Bendels et al. 2006's
 * angle criterion); rim points joined through the k-NN graph form one hole.
 *
 * Not every rim is a hole: the outer border of an open scan is one too.
 * A rim is taken for an outer border, and left open, when the ball about
 * its centroid through its farthest rim point holds more than half of the
 * points of its connected piece (through the triangles, or the k-NN graph;
 * a hole's ball holds few; a border's holds its piece, a stray fragment's
 * included). Rims
 * of fewer than 3 points (a mesh's) or k points (a point set's: an
 * irregular sampling, a laser scan's or a random one, leaves one-sided
 * gaps of a few points everywhere; a hole with fewer than k rim points is
 * under about 2.5 spacings across) are dropped as noise.
 *
 * Output: rim[i] = 0 off any rim, h in 1..n_holes on hole h's rim. */
#ifndef RELIEF_HOST_POINTS_HOLES_H
#define RELIEF_HOST_POINTS_HOLES_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"
#include "points/analysis.h"

typedef struct relief_hole_info {
    uint32_t n_holes;   /* holes kept */
    uint32_t n_borders; /* rims taken for an outer border and left open */
    uint32_t n_dropped; /* rims too small */
} relief_hole_info;

/* From a mesh's triangles (nt x 3 indices into n vertices). */
relief_status relief_holes_mesh(const double *pos, size_t n, const uint32_t *tri, size_t nt,
                                uint32_t *rim, relief_hole_info *info, relief_error *err);

/* From a bare point set with oriented normals and its k-NN graph. */
relief_status relief_holes_points(const double *pos, const double *nrm,
                                  const relief_knn_graph *g, double gap, uint32_t *rim,
                                  relief_hole_info *info, relief_error *err);

/* For each of nq query points (nq x 3; pos itself when query is NULL, nq
 * then ignored and n used), the distance dist (nq) to the nearest of the n
 * points with rim[i] != 0 and, when `nearest` (nq) is not NULL, that
 * point's index. INFINITY and UINT32_MAX when no point is on a rim. */
relief_status relief_rim_distance(const double *pos, size_t n, const uint32_t *rim,
                                  const double *query, size_t nq, double *dist,
                                  uint32_t *nearest, relief_error *err);

#endif
