/* Exact hole filling of a triangle mesh (issue 61): each chosen boundary
 * loop, or each chosen arc of one, is closed by a patch whose rim is that
 * loop's own edges, so the result has no open edge there, no edge of more
 * than two triangles and the patch meets the rim edge to edge.
 *
 * The method is Liepa's (2003, "Filling holes in meshes"), the one CGAL's
 * triangulate_refine_and_fair_hole follows:
 *
 *  1. Triangulate the rim polygon by dynamic programming (Barequet and
 *     Sharir), minimising first the largest dihedral angle between
 *     adjacent triangles (the capture's across the rim included) and then
 *     the area; a diagonal that is already an edge of the mesh is never
 *     used. A polygon of more than RELIEF_HOLE_DP_MAX vertices, where the
 *     O(n^3) search would take seconds, is cut by ears instead, smallest
 *     angle first, over the rim's mean plane.
 *  2. Refine: a triangle whose centroid lies farther than sigma / 1.7
 *     from each of its corners (sigma: the mean edge length about a rim
 *     vertex, interpolated inward; Liepa's factor is sqrt 2, which leaves
 *     the patch at 60 % of the capture's vertex density, where relief's
 *     growth wants a target for each sample the capture would have had)
 *     is split at the centroid, and the
 *     patch's edges are flipped until every one is Delaunay (opposite
 *     angles summing to at most pi), until nothing splits: the patch takes
 *     the capture's own density.
 *  3. Fair: the new vertices minimise the squared scale-dependent umbrella
 *     Laplacian (weights 1 / edge length) over themselves and, for C1
 *     continuity, over the rim vertices, whose 1-rings hold the capture's
 *     vertices: a bi-Laplacian surface that continues the rim's position
 *     and tangent plane (RELIEF_FAIR_C1; RELIEF_FAIR_C0 keeps only the
 *     position, a membrane). Solved by conjugate gradients on the normal
 *     equations, in a fixed order: the bytes do not depend on threads.
 *
 * An arc of a loop (a notch of a border chosen by a ball: some of the
 * loop's vertices chosen, the rest not) is closed as a polygon by the
 * chord between its ends, cut into new vertices at the ends' edge length;
 * the chord is left open, the border it belongs to being open by design.
 * An arc's patch that crosses itself or the mesh near a chord's end (the
 * arc runs on along the chord there) is made again with that end
 * trimmed (RELIEF_NOTCH_TRIMS).
 *
 * Arrays row-major; lengths in the mesh's units. The mesh must be an
 * oriented manifold about the chosen rims (relief's readers repair one on
 * reading); a rim vertex with two boundary edges leaving it is a pinch,
 * and its loop is skipped and counted. */
#ifndef RELIEF_HOST_MESH_HOLE_FILL_H
#define RELIEF_HOST_MESH_HOLE_FILL_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"

/* An arc's patch that crosses the capture near an end of its chord is
 * made again with that end trimmed, at most this many times. */
#define RELIEF_NOTCH_TRIMS 16

/* Two loops bound one hole (a tube) when each runs on one way this much
 * (hole_loop_facing's |dir|, 1 at a cylinder's band) toward the other. */
#define RELIEF_TUBE_FACING 0.7
/* and has at least this many vertices */
#define RELIEF_TUBE_MIN_LOOP 8
/* A tube's strip is searched over (n_a + 1) (n_b + 1) cells, at most. */
#define RELIEF_TUBE_DP_MAX (1u << 24)

/* Larger polygons are cut by ears (1 above). */
#define RELIEF_HOLE_DP_MAX 400

/* The continuity the fairing keeps at the rim. */
typedef enum relief_fair_continuity {
    RELIEF_FAIR_NONE = 0, /* refined, not faired: the new vertices where refinement put them */
    RELIEF_FAIR_C0 = 1,   /* membrane: position */
    RELIEF_FAIR_C1 = 2    /* thin plate: position and tangent plane (the default) */
} relief_fair_continuity;

typedef struct relief_hole_fill_options {
    int refine;                  /* 1 (default): refine to the capture's density */
    relief_fair_continuity fair; /* default RELIEF_FAIR_C1 */
    size_t max_new;              /* refuse (RELIEF_E_RANGE) a fill adding more new
                                    vertices; 0: no limit */
} relief_hole_fill_options;

void relief_hole_fill_options_default(relief_hole_fill_options *o);

/* The patches, in the input's indices: the mesh's nv vertices, then the
 * new ones. */
typedef struct relief_hole_patches {
    size_t nv_new;     /* new vertices */
    double *pos;       /* nv_new x 3 (owned) */
    uint32_t *hole;    /* nv_new: the rim label each one fills (owned) */
    size_t nt_new;     /* new triangles */
    uint32_t *tri;     /* nt_new x 3 into [0, nv + nv_new), oriented as the mesh (owned) */
    uint32_t *tri_hole; /* nt_new: the rim label of each (owned) */
    size_t polygons;   /* polygons closed (whole loops and arcs) */
    size_t arcs;       /* of which arcs, each leaving its chord open */
    size_t skipped;    /* chosen polygons not closed: a pinched rim, or
                          fewer than 3 vertices in an arc */
    size_t by_ears;    /* polygons over RELIEF_HOLE_DP_MAX, cut by ears */
} relief_hole_patches;

void relief_hole_patches_free(relief_hole_patches *p);

/* Close the rims of the mesh (pos: nv x 3, tri: nt x 3) whose vertices
 * carry a non-zero label in rim (nv; the hole model's labels,
 * mesh/holes.h): a boundary loop all of whose vertices carry one label is
 * closed whole; the runs of labelled vertices along a loop otherwise, each
 * of 3 or more, as arcs. Each patch's vertices and triangles carry its
 * label. o NULL: the defaults. RELIEF_E_NOMEM; RELIEF_E_RANGE past
 * max_new. */
relief_status relief_fill_rims(const double *pos, size_t nv, const uint32_t *tri, size_t nt,
                               const uint32_t *rim, const relief_hole_fill_options *o,
                               relief_hole_patches *out, relief_error *err);

/* The arcs relief_fill_rims closes (a notch a selection takes of a
 * border's loop): each one's label, its first and last vertex (the
 * chord's ends) and its vertices' mean position; *arcs malloc'ed (NULL
 * when none). RELIEF_E_NOMEM. */
typedef struct relief_rim_arc {
    uint32_t label, first, last;
    double mean[3];
} relief_rim_arc;

relief_status relief_rim_arcs(const double *pos, size_t nv, const uint32_t *tri, size_t nt,
                              const uint32_t *rim, relief_rim_arc **arcs, size_t *n_arcs,
                              relief_error *err);

#endif
