/* Holes cut where the truth is known: a region taken out of a whole mesh
 * (a real scan, usually) gives a capture to complete and the truth to
 * measure the completion against, as relief_synth does for the synthetic
 * surfaces. `relief cut` and the real-scan tests use it. */
#ifndef RELIEF_HOST_CUT_H
#define RELIEF_HOST_CUT_H

#include "relief/relief.h"

typedef enum relief_cut_shape {
    RELIEF_CUT_BALL, /* the vertices within `radius` of `point` */
    RELIEF_CUT_SLAB  /* the vertices within `radius` of the plane through
                      * `point` with unit normal `normal`: a band across a
                      * cylinder when the normal is its axis */
} relief_cut_shape;

/* The region cut out, in the mesh's units. */
typedef struct relief_cut_region {
    relief_cut_shape shape;
    double point[3];
    double normal[3]; /* RELIEF_CUT_SLAB only; normalised by the cut */
    double radius;    /* > 0: the ball's radius, or the slab's half width */
    int crop;         /* 0: cut the region out; 1: keep only the region (a
                       * patch of a larger scan: `relief cut --crop`) */
} relief_cut_region;

/* Cut `region` out of m (with region->crop, everything but the region).
 * *captured: m without the region's vertices, the
 * triangles that touch them, and the vertices left in no triangle (m's
 * colours and normals kept, its labels dropped). *truth: a copy of m whose
 * label is RELIEF_LABEL_COMPLETED (1) on every vertex the capture lacks and
 * RELIEF_LABEL_CAPTURED (0) elsewhere. *n_cut (may be NULL): the vertices
 * the capture lacks. RELIEF_E_RANGE when the region is not finite or its
 * radius is not > 0, or when it cuts no vertex (nothing to fill) or
 * leaves no triangle (nothing captured); RELIEF_E_MESH when m has no
 * triangles. */
relief_status relief_mesh_cut(const relief_mesh *m, const relief_cut_region *region,
                              relief_mesh **captured, relief_mesh **truth, size_t *n_cut,
                              relief_error *err);

#endif
