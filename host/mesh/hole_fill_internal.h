/* What the three steps of mesh/hole_fill.h share: one polygon's patch in
 * local indices (the rim's vertices 0..n_rim-1 in the patch's order, then
 * the new ones), and the mesh's vertex adjacency. */
#ifndef RELIEF_HOST_MESH_HOLE_FILL_INTERNAL_H
#define RELIEF_HOST_MESH_HOLE_FILL_INTERNAL_H

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "relief/relief.h"
#include "mesh/mesh.h"


typedef struct hole_patch {
    size_t n_rim;      /* the polygon's vertices, local 0..n_rim-1 */
    const uint32_t *gid; /* n_rim: their indices in the mesh */
    int closed;        /* 1: a whole loop; 0: an arc, its chord (n_rim-1, 0) open */
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

#endif
