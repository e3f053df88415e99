/* Welding a split vertex's copies back together where a fill joined them.
 *
 * The reader splits a bow-tie vertex (two fans meeting at one point) into
 * copies at one position, one per fan (repair.h). A hole that passes such a
 * point twice is closed by ears (points/surface_mesh.c) that can join the
 * copies with a triangle of no area: the copies stay apart, the triangle
 * marks where they touch, and a reader that welds coincident vertices
 * (MeshLab, trimesh) drops it again and finds the bow-tie back.
 *
 * relief_weld_copies merges two coincident vertices that a triangle joins
 * when, with every triangle that joins them dropped, the merged vertex's
 * triangles form one fan (a disc, or a half-disc at a border, consistently
 * oriented) and no neighbour's fan that was one fan becomes two: the fill
 * closed the pinch, and the vertex is one again. Otherwise the copies and
 * their triangle stay as they are. */
#ifndef RELIEF_HOST_MESH_WELD_H
#define RELIEF_HOST_MESH_WELD_H

#include <stddef.h>
#include <stdint.h>

#include "base/error.h"

/* pos: nv x 3; tri: *nt x 3 indices, rewritten in place: welded copies
 * take the lower index, the triangles that joined them are dropped and *nt
 * shrinks. A welded copy's index stays in pos, used by no triangle.
 * *welded: pairs merged. RELIEF_E_NOMEM when memory runs out (tri is then
 * unchanged). */
relief_status relief_weld_copies(const double *pos, size_t nv, uint32_t *tri, size_t *nt,
                                 size_t *welded, relief_error *err);

#endif
