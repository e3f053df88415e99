/* Whether a surface is closed where it should be (issue 61: every filled
 * hole is closed, with no open edge, no non-manifold edge and no
 * self-intersection where the patch meets the rim): its edges' census and
 * the triangles that cross others.
 *
 * An edge is an unordered pair of vertex indices; how many triangles have
 * it says what it is: 1 a boundary (open) edge, 2 an inner edge, 3 or more
 * a non-manifold one. Two triangles that have an edge the same way round
 * (an orientation flip) still make an inner edge here. Boundary loops are
 * the boundary's vertices joined through boundary edges, as
 * relief_boundary_loops (holes.h) numbers them: two loops that touch at a
 * vertex are one. */
#ifndef RELIEF_HOST_MESH_CHECK_H
#define RELIEF_HOST_MESH_CHECK_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"

/* The undirected edges of nt triangles (nt x 3 indices) as keys
 * (lo << 32 | hi), sorted, one per triangle side: 3 nt keys, an edge of k
 * triangles k times in a row. NULL when out of memory; the caller frees. */
uint64_t *relief_edge_keys(const uint32_t *tri, size_t nt);

typedef struct relief_edge_census_result {
    size_t boundary_edges;     /* edges of one triangle */
    size_t boundary_loops;     /* their loops */
    size_t nonmanifold_edges;  /* edges of three triangles or more */
    size_t focus_boundary_edges;    /* boundary edges with an end in the focus */
    size_t focus_boundary_loops;    /* loops with a vertex in the focus */
    size_t focus_nonmanifold_edges; /* non-manifold edges with an end in it */
} relief_edge_census_result;

/* The census of nt triangles (nt x 3 indices) over nv vertices; the focus
 * is the vertices with vfocus[v] != 0 (nv entries; NULL: all of them, the
 * focus_ counts then equal the others). RELIEF_E_MESH naming the first
 * triangle with an index >= nv; RELIEF_E_NOMEM. */
relief_status relief_edge_census(const uint32_t *tri, size_t nt, size_t nv,
                                 const uint8_t *vfocus, relief_edge_census_result *out,
                                 relief_error *err);

/* The triangles that cross or touch another one elsewhere than where the
 * two are joined. pos: nv x 3; tri: nt x 3 indices. Only the triangles
 * with focus[t] != 0 (nt entries; NULL: all) are reported, each tested
 * against every triangle. hit (nt entries, may be NULL) gets 1 for each
 * reported triangle, 0 for the others; *count their number.
 *
 * Two triangles share a vertex where they have the same index or the same
 * position, exactly (the reader's bow-tie split leaves copies at one
 * place). Sharing none, they are reported when their closed sets meet,
 * touching included. Sharing one vertex, when they meet anywhere else
 * (their sets then meet beyond it exactly when the edge opposite it in one
 * meets the other triangle). Sharing an edge, when they are coplanar and
 * fold onto each other (the third vertices on one side of the edge).
 * Sharing all three (a duplicate face), always. Triangles of no area (three
 * collinear corners) are skipped, neither tested nor reported: they have no
 * side to cross, and a reader's repair drops them.
 *
 * The tests use exact orientation predicates (base/predicates.h): coplanar
 * and touching cases are decided exactly for the (finite) coordinates
 * given. A uniform grid over the triangles' bounding boxes, hashed, pairs
 * only the triangles whose boxes meet: one thread, 0.08 s for the Stanford
 * bunny's 69 451 triangles, 1.4 s for the 508 916 of a scan subdivided
 * once, whose flat neighbours take the exact path (bench/bench_mesh_check,
 * a 2-core EPYC). hit is
 * written only on success. RELIEF_E_MESH naming the first triangle with an
 * index >= nv; RELIEF_E_NOMEM. */
relief_status relief_self_intersections(const double *pos, size_t nv, const uint32_t *tri,
                                        size_t nt, const uint8_t *focus, uint8_t *hit,
                                        size_t *count, relief_error *err);

/* What a completion left open or crossing where it completed. */
typedef struct relief_closure {
    size_t open_loops;         /* boundary loops near the completed part */
    size_t open_edges;         /* boundary edges near it */
    size_t nonmanifold_edges;  /* non-manifold edges near it */
    size_t self_intersections; /* triangles with a completed vertex that
                                  cross another (relief_self_intersections) */
} relief_closure;

/* The closure of a completed surface (pos: nv x 3, tri: nt x 3) where
 * completed[v] != 0 (nv entries; the mesh's labels). "Near" is a completed
 * vertex or a neighbour of one through a triangle: where a patch meets its
 * rim, a gap left between them runs along rim vertices that are not
 * completed themselves. A capture's own border or non-manifold edge
 * farther away is not counted; a rim filled in part (holes.h) stays open
 * beside its patch and is. RELIEF_E_MESH, RELIEF_E_NOMEM. */
relief_status relief_closure_check(const double *pos, size_t nv, const uint32_t *tri, size_t nt,
                                   const uint8_t *completed, relief_closure *c,
                                   relief_error *err);

#endif
