/* Triangles over the holes a point-set completion filled (`relief
 * complete-points --mesh`): each hole's rim points and new points projected
 * on their mean tangent plane (centroid, mean normal) and triangulated
 * there (Delaunay, qhull), keeping the triangles that reach a new point and
 * whose circumradius is at most 3 spacings (the convex hull's slivers across
 * a concave rim go), each turned to agree with its vertices' normals, and
 * then, smallest circumradius first, each whose directed edges are all
 * still free (of the mesh's triangles and the patches kept), so that every
 * edge has at most one triangle a side; patches are dropped around a vertex
 * left with two fans. They are laid in the order a front from the rim
 * would lay them, each sharing an edge with what is there and reaching a
 * vertex that has triangles only through an edge, then the ones that
 * close the cracks where fronts from two sides meet; of those, the ones
 * OpenMesh can store in that order are kept (the mesh writer, OpenMesh,
 * adds faces one by one and cannot always relink a vertex whose fans a
 * corner split), so that the result can be written. Last, the cracks
 * where fronts met, boundary loops of at most 12 edges through a new
 * point, are closed by ears (relief_points_close_gaps). With
 * the input mesh's own triangles this makes the completed surface. A hole
 * whose points do not project one-to-one on a plane (a deep pocket) gets
 * folded triangles: the patch is a height field over its plane.
 * Arrays row-major; lengths in the points' unit. */
#ifndef RELIEF_HOST_POINTS_PATCH_MESH_H
#define RELIEF_HOST_POINTS_PATCH_MESH_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"

/* pos, nrm: N x 3, the input's n_in points first, then the new ones;
 * rim: n_in hole ids of the input points (0: on no rim); hole: N - n_in
 * hole ids of the new points (1..n_holes); tri_in: the input mesh's nt_in
 * triangles (indices < n_in). *tri (malloc'ed, nt x 3
 * indices into pos) and *nt receive the patches' triangles (NULL and 0
 * when none). RELIEF_E_NOMEM; a hole qhull cannot triangulate (too few or
 * collinear points) is skipped, counted in *skipped. */
/* A candidate triangle: laid lower rank first, then smaller r (its
 * circumradius), then by its vertices; v oriented as it is to be laid. */
typedef struct relief_cand_tri {
    double r;
    uint32_t rank;
    uint32_t v[3];
} relief_cand_tri;

/* The circumradius of triangle a, b, c (3 each); INFINITY when degenerate. */
double relief_circumradius(const double *a, const double *b, const double *c);

/* Which of ncand candidate triangles over N vertices pos (N x 3) join a
 * mesh's own nt_in triangles tri_in so that the whole is an oriented
 * manifold that OpenMesh can store, and in which order: greedily in
 * cand_tri order, each whose directed edges are all free; then dropped
 * around a vertex left with two fans; then laid as a front from tri_in
 * would lay them (with seed_islands, a front also starts from each part
 * no front reaches, at its first triangle in that order; without, such
 * parts stay out), then the cracks where fronts met; then those OpenMesh
 * accepts in that order. cand is sorted in place. *tri (malloc'ed, nt x 3,
 * in laying order; NULL when none) and *nt receive them. RELIEF_E_NOMEM. */
relief_status relief_points_lay_triangles(const double *pos, size_t N, const uint32_t *tri_in,
                                          size_t nt_in, relief_cand_tri *cand, size_t ncand,
                                          int seed_islands, uint32_t **tri, size_t *nt,
                                          relief_error *err);

relief_status relief_points_patch_mesh(const double *pos, const double *nrm, size_t n_in,
                                       size_t N, const uint32_t *rim, const uint32_t *hole,
                                       uint32_t n_holes, double spacing,
                                       const uint32_t *tri_in, size_t nt_in, uint32_t **tri,
                                       size_t *nt, size_t *skipped, relief_error *err);

/* What is left open about the filled holes of a completed surface (nt x 3
 * triangles over N points, the input's n_in first, rim their hole ids as
 * for relief_points_patch_mesh): *loops, the boundary loops all of whose
 * vertices are new or on a filled hole's rim, and *edges, their edges. A
 * loop through a capture vertex off every filled rim is an opening the
 * hole model leaves (a border, a mouth; the chord that closes a notch
 * joins its border's loop) and is not counted. Issue 40: a completion said
 * to fill a hole must close it; these say where it did not.
 * RELIEF_E_NOMEM. */
relief_status relief_points_open_loops(const uint32_t *tri, size_t nt, size_t N, size_t n_in,
                                       const uint32_t *rim, size_t *edges, size_t *loops,
                                       relief_error *err);

#endif
