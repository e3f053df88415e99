/* A triangulated surface through a bare point set (`relief complete-points
 * --mesh` on a point set, paper 002's input without triangles): each
 * point's local Delaunay umbrella, kept where its neighbours agree.
 *
 * For every point p with unit normal n, its k nearest neighbours are
 * projected on p's tangent plane (neighbours whose normal faces away from
 * n, or that lie more than 45 degrees off the plane, belong to another
 * sheet and are left out), and p's Voronoi cell among them is cut from a
 * 16-gon of radius 3 spacings about p (so no triangle's circumcircle
 * reaches past about 3 spacings: wider gaps stay open, as a hole patch's
 * do). Each pair of consecutive cell edges cut by neighbours a, b gives
 * the triangle (p, a, b), counter-clockwise about n. A triangle proposed
 * by all three of its corners ranks before one proposed by two; one
 * proposed by a single corner is dropped (Gopi, Krishnan and Silva 2000's
 * consistency test, in spirit). The candidates are then laid as
 * relief_points_lay_triangles lays them, fronts started in every part, so
 * that the result is an oriented manifold OpenMesh can write. Gaps remain
 * where neighbours disagree: the surface is the points' own, not a
 * watertight reconstruction (Poisson's is). Lengths in the points' unit. */
#ifndef RELIEF_HOST_POINTS_SURFACE_MESH_H
#define RELIEF_HOST_POINTS_SURFACE_MESH_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"

typedef struct relief_surface_mesh_info {
    size_t candidates;      /* triangles proposed by at least two corners */
    size_t triangles;       /* laid */
    size_t boundary_edges;  /* edges with a triangle on one side only */
    size_t bare_points;     /* points in no triangle */
} relief_surface_mesh_info;

/* pos, nrm: N x 3 (nrm unit, consistently oriented); spacing > 0 (the
 * median nearest-neighbour distance); k: neighbours per umbrella, 6..64
 * and N > k. *tri (malloc'ed, nt x 3 indices into pos; NULL when none)
 * and *nt receive the surface; info (may be NULL) its counts.
 * RELIEF_E_RANGE for k or N out of range, RELIEF_E_NOMEM. */
relief_status relief_points_surface_mesh(const double *pos, const double *nrm, size_t N,
                                         double spacing, int k, uint32_t **tri, size_t *nt,
                                         relief_surface_mesh_info *info, relief_error *err);

/* Close the small gaps of a surface (nt x 3 triangles *tri over the N
 * points pos, N x 3): each boundary loop of at most max_loop edges, through
 * vertices on one loop only and with at least one vertex >= first_new or
 * on a filled hole's rim (rim, first_new entries, non-zero; or NULL), cut
 * into ears, the shortest diagonal first (none longer than max_diag, and
 * given rim, none with a captured vertex on no filled rim: a border left
 * open stays as it was), then
 * those of the new triangles OpenMesh accepts after *tri's. *tri grows
 * (realloc'ed), *nt with it. RELIEF_E_NOMEM. */
relief_status relief_points_close_gaps(const double *pos, size_t N, size_t first_new,
                                       const uint32_t *rim, double max_diag, int max_loop,
                                       uint32_t **tri, size_t *nt, relief_error *err);

#endif
