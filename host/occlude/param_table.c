/* relief_occluder_params described for clients that set them by name and
 * for the documentation (relief_param, relief/core.h); the ranges are
 * relief_occluder_params_validate's. */
#include <float.h>

#include "relief/relief.h"
#include "base/param_table.h"

#define T relief_occluder_params

static const char *const backgrounds[] = {"planes", "plane", "mesh", NULL};
static const char *const seedings[] = {"margin", "hysteresis", NULL};
static const char *const noise_models[] = {"plane", "frame", NULL};

static const relief_param table[] = {
    RP_ENUM(T, background, "B", backgrounds, "planes (default: up to max_planes planes by "
            "RANSAC, a corner or a floor too), plane (the dominant one), or mesh (a surface "
            "given in the frame's camera coordinates)"),
    RP_INT(T, max_planes, "N", 1, 8, "planes: at most N background planes, 1..8 (default 4)"),
    RP_REAL(T, min_support, "F", 1e-6, 1, "a background plane holds at least this share of "
            "the captured points, 1e-6..1 (default 0.03)"),
    RP_REAL(T, margin, "M", -HUGE_VAL, 1e9, "seeds lie more than M (depth units: metres) in "
            "front of the background; <= 0 (default): 4 sigma(z), the noise measured on it as "
            "sigma(z) = a z^2 (a structured-light camera's)"),
    RP_ENUM(T, seeding, "S", seedings, "margin (default, paper 004's: the points beyond the "
            "margin) or hysteresis (also those over 3/4 of it in front connected to them: "
            "legs, a chair's base; it can spread into walls that are not quite plane)"),
    RP_ENUM(T, noise_model, "N", noise_models, "whose noise the margin is measured in: "
            "plane (default: each background plane's own sigma_k(z) = a_k z^2, from its "
            "inliers, at least half the first plane's; a point is judged against the plane "
            "it is fewest sigmas in front of) or frame (the first plane's for every plane)"),
    RP_INT(T, window, "W", 3, 1025, "the growth's square around each seed, odd pixels "
           "(default 61, the paper's)"),
    RP_REAL(T, colour_distance, "D", 0, 200, "the growth's step: neighbours whose colours "
            "differ by at most D (CIELAB delta E 1976) join, 0..200 (default 12)"),
    RP_REAL(T, front_sigmas, "K", 0, 64, "growth also enters captured points over K sigmas "
            "above their plane's local level (the mean of its points in a 31-pixel square; "
            "sigma: their noise about it): thin things on a floor, a chair's runners; 0: never, "
            "paper 004's growth, 0..64 (default 3)"),
    RP_INT(T, edge, "N", 0, 64, "growth onto background depth within N pixels of a seed "
           "(a depth camera's misregistered rim), 0..64 (default 3)"),
    RP_INT(T, min_area, "N", 1, 100000000, "seed groups under N pixels are noise (default "
           "50)"),
    RP_INT(T, dilate, "N", 0, 64, "the mask grown by N pixels: background marked as "
           "foreground rather than the reverse, 0..64 (default 1)"),
    RP_INT(T, iterations, "N", 10, 1000000, "RANSAC hypotheses per plane (default 500)"),
    RP_REALS(T, intrinsics, "FX,FY,CX,CY", 4, 4, has_intrinsics, 1, "the depth image's "
             "pinhole camera, pixels (default: a cloud's camera fitted to its points; for a "
             "depth image fx = fy = 525 x width / 640 and the centre)"),
    RP_REAL(T, parallax, "P", 0.1, 64, "with neighbouring views: a correspondence error "
            "(eq. 2.1) over P pixels is foreground, 0.1..64 (default 2)"),
    RP_INT(T, view_radius, "R", 1, 32, "with neighbouring views: the colour search's reach "
           "behind where the background says, and its least reach in front (it goes on to "
           "where the ray's point at half the depth projects, up to 64), pixels (default 6)"),
    RP_SEED(T, seed, "RANSAC's seed (default 1)"),
    RP_BACKEND(T, "remove-occluders: the colour's and the depth's fills, auto (default), "
               "scalar, host or opencl; outputs are identical"),
    RP_DEVICE(T),
    RP_MAX_MEMORY(T),
    RP_THREADS(T),
};

const relief_param *relief_occluder_param_table(size_t *count)
{
    if (count)
        *count = sizeof table / sizeof table[0];
    return table;
}
