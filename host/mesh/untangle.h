/* Undo crossings a displacement made (issue 61: no completed triangle
 * crosses another where a patch meets its rim). The movable vertices
 * (index >= first) of triangles that cross another (mesh/mesh_check.h)
 * are drawn back toward their base positions, halfway, round after round
 * (RELIEF_UNTANGLE_ROUNDS), then moved to their neighbours' mean, round
 * after round, until none crosses or the rounds run out. A vertex once
 * moved goes on moving with those of later rounds (else one drawn back
 * early leaves a step to a neighbour drawn back late, which crosses in
 * turn). Deterministic:
 * the same input gives the same bytes. */
#ifndef RELIEF_HOST_MESH_UNTANGLE_H
#define RELIEF_HOST_MESH_UNTANGLE_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"

#define RELIEF_UNTANGLE_ROUNDS 6

/* pos: nv x 3, moved in place; base: nv x 3, where each movable vertex
 * would sit without its displacement (NULL: relax only); tri: nt x 3.
 * *moved: the vertices moved; *left: the triangles with a movable vertex
 * still crossing another. RELIEF_E_NOMEM. */
relief_status relief_untangle(double *pos, const double *base, size_t nv, size_t first,
                              const uint32_t *tri, size_t nt, size_t *moved, size_t *left,
                              relief_error *err);

#endif
