/* depth-fill on a mesh, the holes only (issue 40). Six depth images make a
 * closed solid of any mesh (mesh_fill.h): an open vessel comes back full,
 * its mouth capped. What the user asked for is the capture with its holes
 * filled: from the solid, the skin over each filled hole of the hole model
 * (mesh/holes.h) is taken (the solid's triangles within reach of the
 * hole's rim and more than 1.5 voxels off the capture, the largest piece
 * per hole), and the strip between it and the hole's rim is zipped closed
 * with triangles, the shorter diagonal first. The capture keeps its
 * vertices and triangles; what is added is labelled 1. */
#ifndef RELIEF_HOST_DEPTH_MESH_PATCH_H
#define RELIEF_HOST_DEPTH_MESH_PATCH_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"
#include "mesh/holes.h"

typedef struct relief_mesh_patch_report {
    size_t holes_patched;    /* filled holes given a patch and a strip */
    size_t holes_unpatched;  /* filled holes the solid gave no patch (left open) */
    size_t inner_loops_capped; /* loops inside a patch (a channel cut off), fanned */
    size_t inner_loops_open;   /* such loops touching another at a vertex: left open */
    size_t vertices_added;
    size_t patch_triangles, strip_triangles;
    size_t mended_triangles; /* dropped by the final relief_mesh_repair (an edge
                                the strips made non-manifold, ...) */
    size_t mended_vertices;  /* non-manifold vertices it split */
    size_t copies_welded;    /* faired patches: a split vertex's copies welded
                                where a patch closed the pinch (mesh/weld.h) */
    size_t untangled;        /* faired patches: vertices drawn back where they
                                crossed the capture (mesh/untangle.h) */
    size_t crossing_left;    /* triangles of the patches still crossing another */
} relief_mesh_patch_report;

/* `in` the capture, `solid` its repaired closed mesh on a grid of `voxel`
 * side, h and rim its hole model (relief_holes_mesh on `in`): *out the
 * capture with its filled holes patched. */
relief_status relief_mesh_patch_holes(const relief_mesh *in, const relief_mesh *solid,
                                      double voxel, const relief_hole_info *h,
                                      const uint32_t *rim, relief_mesh **out,
                                      relief_mesh_patch_report *rep, relief_error *err);

/* The default since issue 61: each hole the model fills (rim: in->nv
 * labels, as relief_holes_mesh gives them; a notch's arc closed by its
 * chord) closed by mesh/hole_fill.h's faired patch, edge to edge with its
 * rim; then, where the repaired solid (may be NULL: the faired patch as
 * it is) lies within 3 voxels of a patch vertex along its normal, the
 * vertex takes the solid's offset, smoothed over the patch (the voxels'
 * steps do not come through) and faded in over the three rings next to
 * the rim. `in`'s vertices and triangles come first, unchanged; what is
 * added is labelled 1 and coloured as its rim on average. The report's
 * patch and vertex counts are set (strip_triangles 0). */
relief_status relief_mesh_fair_holes(const relief_mesh *in, const relief_mesh *solid,
                                     double voxel, const uint32_t *rim, relief_mesh **out,
                                     relief_mesh_patch_report *rep, relief_error *err);

#endif
