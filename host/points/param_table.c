/* relief_complete_points_params described for clients that set them by
 * name and for the documentation (relief_param, relief/core.h); the
 * ranges are relief_complete_points_params_validate's. The masks given as
 * arrays (hole_mask, sample_mask) and the clone are for callers in C. */
#include <float.h>

#include "relief/relief.h"
#include "base/param_table.h"

#define T relief_complete_points_params

static const char *const whats[] = {"all", "colour", "geometry", NULL};
static const char *const searches[] = {"kdtree", "brute", NULL};

static const relief_param table[] = {
    RP_ENUM(T, what, "W", whats, "all (default: new points with detail, and colour when "
            "the input has it), colour (the colour of the hole mask's points only) or "
            "geometry (new points and their detail; colour from the rim)"),
    RP_FLAG(T, smooth_only, "the smooth fill alone: no detail, colour from the rim (the "
            "baseline of paper 002's Fig. 9g)"),
    RP_FLAG(T, detail_histogram, "the new points' detail takes the distribution of the "
            "capture about the hole, by histogram matching: as rough as the scan's own "
            "(default: on; off leaves it as the texture optimisation averaged it; a mesh's "
            "faired patches never take it)"),
    RP_FLAG(T, mesh, "the output also gets triangles: a mesh's own and patches over the "
            "filled holes; for a point set, local Delaunay umbrellas through all the "
            "points"),
    RP_INT(T, k, "N", 6, 64, "neighbours of the local analysis, 6..64 (default 16)"),
    RP_INT(T, smooth_steps, "N", 0, 10000, "curvature-flow steps of the base, 0..10000 "
           "(default 20)"),
    RP_REAL(T, max_detail, "S", 0, 100, "the base keeps within S spacings of every point, so "
            "that thin parts stay shape, not detail, 0..100 (default 1; 0: no bound)"),
    RP_REAL(T, band, "S", 0, 1e6, "exemplars keep S spacings from a rim (default 2)"),
    RP_REAL(T, max_hole, "L", 0, 1e30, "holes whose rims are wider than L (the input's "
            "units) are taken for openings by design (a vase's mouth) and left open; 0 "
            "(default): a quarter of the bounding box's diagonal; a hole mask selects "
            "instead"),
    RP_INT(T, grid, "N", 3, 33, "the texture grid's side, odd, 3..33 (default 23)"),
    RP_INT(T, cluster_size, "N", 16, 100000, "points per cluster before overlap, "
           "16..100000 (default 300)"),
    RP_INT(T, iterations, "N", 1, 1000, "texture optimisation iterations, 1..1000 (default "
           "50)"),
    RP_SEED(T, seed, "which exemplar grids the texture searches when there are over 20 000 "
            "to choose from (default 1)"),
    RP_ENUM(T, grid_search, "S", searches, "the texture's nearest exemplar grids: kdtree "
            "(FLANN's exact kd-tree, default) or brute (every grid; on the backend)"),
    RP_FLAG(T, hole_labels, "fill the holes whose rims the input's PLY labels 1 touch, and "
            "synthesise those points again"),
    RP_REALS(T, hole_ball, "X,Y,Z,R", 4, 4, has_hole_ball, 1, "fill the holes whose rims "
             "reach within R of (X, Y, Z), R > 0, and synthesise those points again"),
    RP_FLAG(T, sample_labels, "exemplars only on the points the input's PLY labels 1"),
    RP_REALS(T, sample_box, "X0,Y0,Z0,X1,Y1,Z1", 6, 6, has_sample_box, 1, "exemplars only "
             "inside the box (the input's units; X0 < X1, Y0 < Y1, Z0 < Z1)"),
    RP_REALS(T, viewpoint, "X,Y,Z", 3, 3, has_viewpoint, 1, "the normals face this point (a "
             "PCD's sensor)"),
    RP_BACKEND(T, "scalar: every stage on one thread (the reference); host: every stage on "
               "the host's threads; auto (default): host, and grid_search brute on OpenCL on "
               "a GPU or accelerator; opencl: grid_search brute on OpenCL; the same bytes "
               "each way"),
    RP_DEVICE(T),
    RP_MAX_MEMORY(T),
    RP_THREADS(T),
};

const relief_param *relief_complete_points_param_table(size_t *count)
{
    if (count)
        *count = sizeof table / sizeof table[0];
    return table;
}
