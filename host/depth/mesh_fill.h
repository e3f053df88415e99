/* Mesh repair through six depth images (paper 003): the mesh's z-buffers
 * (depth/volume.h), each image's holes repaired by depth-image repair
 * (depth/depth_fill.h: the same variants, the same scorer), the voxels
 * between the repaired front and back depths, and their surface. Where
 * the mesh was complete the result matches it within about a voxel. */
#ifndef RELIEF_HOST_DEPTH_MESH_FILL_H
#define RELIEF_HOST_DEPTH_MESH_FILL_H

#include <stddef.h>

#include "relief/relief.h"
#include "depth/depth_fill.h"
#include "depth/volume.h"
#include "image/patch.h"

typedef struct relief_mesh_fill_params {
    int resolution;                 /* voxels along the box's longest side, 8..1024; 256 */
    relief_depth_repair_params depth; /* each image's repair */
} relief_mesh_fill_params;

relief_mesh_fill_params relief_mesh_fill_params_default(void);

typedef struct relief_mesh_fill_report {
    relief_grid grid;
    size_t hole_pixels[6];  /* per image (x front, x back, y front, ...): seen through a hole */
    size_t filled[6];       /* of them, repaired */
    size_t surface_pixels;  /* all images: depths seen on the surface */
    size_t by_synthesis, by_fallback, by_membrane, unreached; /* summed over the images */
    size_t inside_voxels;
    double seconds_zbuffers, seconds_repair, seconds_surface;
} relief_mesh_fill_report;

/* Repair `in` (triangles counter-clockwise seen from outside) into a new
 * closed mesh *out. RELIEF_E_RANGE for a bad resolution or a mesh with no
 * triangles; depth-image repair's errors otherwise. p->depth.progress (may
 * be NULL) gets the call's progress within its current stage (the six
 * images' repairs from 5 to 95 %) and can cancel it between two images or
 * two pixels of one: RELIEF_E_CANCELLED, *out untouched. */
relief_status relief_mesh_depth_fill(relief_mesh *in, const relief_mesh_fill_params *p,
                                     relief_patch_scorer *scorer, relief_mesh **out,
                                     relief_mesh_fill_report *rep, relief_error *err);

/* Measures of a repaired mesh against the complete one: the symmetric
 * surface distances (mean and Hausdorff, relief_surface_distance both
 * ways) and the voxel IoU of their volumes on the grid `g` (both through
 * their z-buffers, unrepaired: the truth is complete). */
typedef struct relief_mesh_measures {
    double mean, hausdorff; /* mesh units */
    double iou;             /* inside voxels of both over inside voxels of either */
} relief_mesh_measures;

relief_status relief_mesh_measure(relief_mesh *repaired, relief_mesh *truth,
                                  const relief_grid *g, relief_mesh_measures *m,
                                  relief_error *err);

#endif
