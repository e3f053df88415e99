/* A bare point set's holes (issue 21): the mesh's hole model
 * (mesh/holes.h) on rims found from the points' neighbourhoods. */
#ifndef RELIEF_HOST_POINTS_HOLES_H
#define RELIEF_HOST_POINTS_HOLES_H

#include "mesh/holes.h"
#include "points/analysis.h"

/* From a bare point set with oriented normals and its k-NN graph; each
 * point's rim test on `threads` threads (the same result whatever their
 * number). */
relief_status relief_holes_points(const double *pos, const double *nrm,
                                  const relief_knn_graph *g, double gap,
                                  const relief_hole_rule *rule, int threads, uint32_t *rim,
                                  relief_hole_info *info, relief_error *err);

#endif
