/* What the three steps of mesh/hole_fill.h share: one polygon's patch in
 * local indices (the rim's vertices 0..n_rim-1 in the patch's order: the
 * mesh's, then an arc's chord points; then the new ones), and the mesh's
 * vertex adjacency. */
#ifndef RELIEF_HOST_MESH_HOLE_FILL_INTERNAL_H
#define RELIEF_HOST_MESH_HOLE_FILL_INTERNAL_H

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "relief/relief.h"
#include "mesh/mesh.h"


typedef struct hole_patch {
    size_t n_rim;      /* the polygon's vertices, local 0..n_rim-1, fixed */
    size_t n_mesh;     /* of which the mesh's, 0..n_mesh-1; n_mesh..n_rim-1
                          are new, on an arc's chord */
    size_t n_first;    /* the first loop's: n_mesh, or where a tube's second
                          loop begins */
    const uint32_t *gid; /* n_mesh: their indices in the mesh */
    int closed;        /* 1: a whole loop; 0: an arc, its chord (n_mesh-1,
                          n_mesh, .., n_rim-1, 0) open */
    double *x;         /* nx x 3: the rim's positions, then the new vertices' */
    double *sigma;     /* nx: the edge length wanted about each vertex */
    size_t nx, cap_x;
    uint32_t *t;       /* nt x 3, local, oriented as the mesh */
    size_t nt, cap_t;
    /* the mesh's edges between two rim vertices that are not neighbours
     * along the polygon (a neck the hole wraps round): never made edges
     * of the patch. Pairs of local indices, a < b. */
    uint32_t *blocked;
    size_t n_blocked;
    size_t max_new;    /* 0: no limit */
} hole_patch;

/* Grow the arrays *a (elements of asz bytes) and, when b is not NULL, *b
 * (bsz bytes) together to hold `need` elements (capacity *cap, doubled
 * past need). 0 on allocation failure (what was reallocated is kept). */
static inline int hole_grow(void **a, size_t asz, void **b, size_t bsz, size_t *cap,
                            size_t need)
{
    size_t c = need * 2 + 16;
    void *na, *nb;
    if (need <= *cap)
        return 1;
    if (!(na = realloc(*a, c * asz)))
        return 0;
    *a = na;
    if (b) {
        if (!(nb = realloc(*b, c * bsz)))
            return 0;
        *b = nb;
    }
    *cap = c;
    return 1;
}

/* Make room for n more vertices / triangles. 0 on allocation failure. */
int hole_patch_reserve(hole_patch *p, size_t more_x, size_t more_t);

/* Step 1: triangulate the polygon x[0..n_rim) into p->t. opp: n_rim x 3,
 * for the rim edge (i, i+1) of the patch the mesh's vertex opposite it
 * across that edge (its position), NaN for the open chord of an arc.
 * *by_ears set when the polygon was cut by ears. 0 on allocation
 * failure. */
int hole_triangulate(hole_patch *p, const double *opp, int *by_ears);

/* Step 2: refine (Liepa's density rule) and flip to Delaunay.
 * RELIEF_E_NOMEM; RELIEF_E_RANGE past max_new. */
relief_status hole_refine(hole_patch *p, relief_error *err);

/* Step 3: fair the new vertices (continuity 1 or 2), the mesh's pos and
 * adjacency giving the rim vertices' other neighbours. RELIEF_E_NOMEM. */
relief_status hole_fair(hole_patch *p, int continuity, const double *pos,
                        const relief_adjacency *adj, relief_error *err);

/* A loop of the mesh's boundary as hole_loops_face sees it. */
typedef struct hole_loop_shape {
    size_t n;         /* its vertices */
    double centre[3]; /* their centroid */
    double dir[3];    /* the mean over its edges (weighted by length) of the
                         unit direction from the mesh into the hole, across
                         the edge in the mesh's triangle there: |dir| near 1
                         where the hole runs on one way (a tube's end), near
                         0 about a round hole in a gently curved surface */
    double across;    /* twice the farthest vertex's distance from centre */
} hole_loop_shape;

/* The shape of a loop (n vertices in the patch's order; pos the mesh's;
 * opp[g]: the mesh's vertex across the boundary edge that starts, in the
 * boundary's order, at g). */
void hole_loop_facing(const double *pos, const uint32_t *opp, const uint32_t *loop, size_t n,
                      hole_loop_shape *f);

/* 1 when loops a and b bound one hole between them (a band cut all round
 * a tube): each of RELIEF_TUBE_MIN_LOOP vertices or more, running on one
 * way (|dir| over RELIEF_TUBE_FACING) toward the other's centre within 37
 * degrees, the two ways opposed within 37 degrees, of widths within a
 * factor 2 and their centres apart by at most 1.5 times the wider. */
int hole_loops_face(const hole_loop_shape *a, const hole_loop_shape *b);

/* Step 1 for a tube: the strip between p's two loops (0..n_first-1 and
 * n_first..n_mesh-1, in the patch's order) into p->t. 1 done; 0 no
 * memory; -1 too large for the search (RELIEF_TUBE_DP_MAX). */
int hole_bridge(hole_patch *p);

/* The patch's triangles that cross another of the patch or one of the
 * mesh's (pos, tri: nt x 3) elsewhere than where they are joined
 * (mesh/mesh_check.h's test, over the mesh's triangles near the patch):
 * *count, and where[3] the mean of their corners (zero when none).
 * RELIEF_E_NOMEM. */
relief_status hole_patch_crossings(const hole_patch *p, const double *pos, const uint32_t *tri,
                                   size_t nt, size_t *count, double where[3],
                                   relief_error *err);

#endif
