/* Meshes through six depth images (paper 003, section 2): the orthographic
 * z-buffers of a mesh's bounding box, a front/back pair along each axis,
 * and the way back: voxels between the front and back depths, their
 * surface extracted. All lengths are in the mesh's units.
 *
 * The grid: cubic voxels of side h, n[0] x n[1] x n[2] of them, voxel
 * (i, j, k) centred at origin + (i + 1/2, j + 1/2, k + 1/2) h. The longest
 * side of the bounding box spans `resolution` voxels; a margin of 1/32
 * of that side (at least 2 voxels) on every face keeps the surface, and a
 * repaired cap rising past the holed mesh's box, inside. */
#ifndef RELIEF_HOST_DEPTH_VOLUME_H
#define RELIEF_HOST_DEPTH_VOLUME_H

#include <stddef.h>
#include <stdint.h>

#include <flann/flann.h>

#include "relief/relief.h"

typedef struct relief_grid {
    double origin[3];
    double h;
    int n[3];
} relief_grid;

/* The grid of `m`'s bounding box (grown by 1/32 of its longest side on
 * each face, at least 2 voxels) at `resolution` (8..1024) voxels along its
 * longest side. RELIEF_E_RANGE for a flat or empty box. */
relief_status relief_grid_of_mesh(relief_mesh *m, int resolution, relief_grid *g,
                                  relief_error *err);

/* Bytes the z-buffers, the voxel values and the surface extraction need
 * for a grid (for the memory check before the work starts). */
uint64_t relief_volume_estimate(const relief_grid *g);

/* Pixel states of a depth image. */
enum { RELIEF_Z_EMPTY = 0, RELIEF_Z_SURFACE = 1, RELIEF_Z_HOLE = 2 };

/* The depth images along axis a (0 x, 1 y, 2 z): over the other two axes
 * b = (a + 1) % 3 (columns, n[b]) and c = (a + 2) % 3 (rows, n[c]), the ray
 * through each pixel centre along +a. front: the coordinate along a of the
 * first surface the ray enters (a triangle facing -a); back: of the last
 * it leaves (facing +a). state: EMPTY where the ray meets nothing, HOLE
 * where it meets the mesh the wrong way first (front: it sees a triangle's
 * inside through a hole) or last (back), SURFACE otherwise; depths are NaN
 * where not SURFACE. Triangles must be counter-clockwise seen from outside
 * (relief_mesh's convention). */
typedef struct relief_zbuffers {
    relief_grid g;
    int width[3], height[3]; /* n[b], n[c] per axis */
    float *front[3], *back[3];
    uint8_t *front_state[3], *back_state[3];
} relief_zbuffers;

relief_status relief_zbuffers_make(relief_mesh *m, const relief_grid *g, relief_zbuffers *z,
                                   relief_error *err);
void relief_zbuffers_free(relief_zbuffers *z);

/* The voxel values: for each voxel centre and each axis whose pixel has a
 * front and a back depth (SURFACE or filled), the distance inside along
 * that axis, min(t - front, back - t), times the nearer side's slope factor
 * 1 / sqrt(1 + |grad depth|^2) (the distance along the surface's normal,
 * so that the axes agree); the value is the smallest over the axes (> 0
 * inside). An EMPTY pixel on an axis puts the voxel outside (-h), unless a
 * repaired pixel (HOLE, filled since) of another axis puts it inside: the
 * hole that took part of the surface took part of the other views'
 * silhouettes too. A pixel still missing on an axis
 * is ignored there. `values`: n[0] x n[1] x n[2] floats, x fastest. */
relief_status relief_zbuffers_voxels(const relief_zbuffers *z, float *values,
                                     relief_error *err);

/* The surface where `values` crosses 0, by marching tetrahedra (six per
 * cube of eight voxel centres), vertices shared, triangles oriented
 * outwards: a closed mesh. RELIEF_E_RANGE when no voxel is inside. */
relief_status relief_isosurface(const relief_grid *g, const float *values, relief_mesh **out,
                                relief_error *err);

/* The distance from a point to a surface: exact over the NEAR triangles
 * (16, or all when fewer) whose centroids are nearest the point, through a
 * kd-tree over the centroids. Build, query, free. */
typedef struct relief_triangle_index {
    const double *pos;
    const uint32_t *tri;
    double *centroid;       /* nt x 3 */
    flann_index_t index;
    struct FLANNParameters fp;
    int k;
} relief_triangle_index;

relief_status relief_triangle_index_build(relief_triangle_index *t, const double *pos,
                                          const uint32_t *tri, size_t nt, relief_error *err);
double relief_triangle_index_d2(const relief_triangle_index *t, const double p[3]);
void relief_triangle_index_free(relief_triangle_index *t);

/* Distances between two surfaces, one way: each vertex of `a` to the
 * nearest triangle of `b` (exact over b's 16 triangles with the nearest
 * centroids). mean and max over a's vertices. */
relief_status relief_surface_distance(relief_mesh *a, relief_mesh *b, double *mean, double *max,
                                      relief_error *err);

#endif
