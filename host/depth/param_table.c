/* relief_depth_fill_params described for clients that set them by name and
 * for the documentation (relief_param, relief/core.h); the ranges are
 * relief_depth_fill_params_validate's. */
#include <float.h>

#include "relief/relief.h"
#include "base/param_table.h"

#define T relief_depth_fill_params

static const char *const variants[] = {"plain", "haar", "decompose", NULL};
static const char *const orders[] = {"both", "horizontal", "vertical", NULL};
static const char *const membranes[] = {"auto", "harmonic", "thin-plate", NULL};
static const char *const edges[] = {"auto", "layers", "across", NULL};
static const char *const values[] = {"auto", "depth", "disparity", NULL};

static const relief_param table[] = {
    RP_ENUM(T, variant, "V", variants, "plain: synthesis on the depths; haar: the coarsest "
            "LL interpolated, the Haar detail bands synthesised; decompose (default): ROF's "
            "structure u interpolated, the texture v synthesised"),
    RP_INT(T, window, "W", 3, 1025, "the synthesis window, an odd number of pixels in "
           "3..1025 (default 9)"),
    RP_REAL(T, sigma, "S", -HUGE_VAL, 1e6, "the window's Gaussian weights, 0.5..1e6 pixels; "
            "<= 0 (default): window / 6.4 (Efros and Leung)"),
    RP_REAL(T, epsilon, "E", 0, 10, "the draw takes a window within (1 + epsilon) of the "
            "best, 0..10 (default 0.1)"),
    RP_INT(T, search_radius, "R", 0, 1000000, "the symmetric search distance, pixels "
           "(default 32); 0: the whole image"),
    RP_FLAG(T, exhaustive, "every window at full resolution, no pyramid (default: off)"),
    RP_INT(T, batch, "N", 1, 256, "1 (default): a pixel at a time, Efros and Leung's order; "
           "2..256: waves of up to N pixels, none inside an earlier one's window, searched "
           "together (a device launch per wave; the same bytes on every backend; not with "
           "tileable)"),
    RP_ENUM(T, order, "O", orders, "both (default: keep the better of the two), horizontal "
            "or vertical"),
    RP_FLAG(T, tileable, "the image is a torus (paper 003's tileable constraint): windows "
            "see across the borders, the result repeats without seams, and holes at a "
            "border are filled (default: off)"),
    RP_INT(T, levels, "L", 1, 6, "haar: transform steps, 1..6 (default 2)"),
    RP_REAL(T, lambda, "L", -HUGE_VAL, 1e12, "decompose: ROF's lambda, depth units x pixels, "
            "up to 1e12; <= 0 (default): 8 x the capture's robust step between neighbours"),
    RP_ENUM(T, membrane, "M", membranes, "the smooth fill of haar's LL and decompose's u: "
            "auto (default: harmonic for images, thin-plate for meshes), harmonic, or "
            "thin-plate (carries the rim's slope and curvature in; can overshoot at depth "
            "edges)"),
    RP_FLAG(T, seam, "blend each hole's rim in the gradient domain, so that the fill "
            "continues the capture's slope (default: on; off leaves the rims as "
            "synthesised)"),
    RP_ENUM(T, edges, "E", edges, "images: a hole across a depth step filled by layers "
            "(each pixel from the rim of the surface it belongs to, so the background "
            "continues behind and the foreground's silhouette stays) or across (paper 003: "
            "from the whole rim, a ramp between the surfaces); auto (default): layers for "
            "depths, across for disparities (a noise-free disparity map has no noise to "
            "tell its slopes from steps)"),
    RP_REAL(T, edge_step, "K", 1, 1000, "images, edges layers: a step between surfaces is "
            "a difference over K times the frame's measured noise, 1..1000 (default 8)"),
    RP_ENUM(T, values, "V", values, "images, edges layers: what the values are, so which "
            "surface is in front: auto (default: a PFM's disparities, larger nearer; any "
            "other frame depths), depth or disparity"),
    RP_INT(T, resolution, "N", 8, 1024, "meshes: voxels along the box's longest side, "
           "8..1024 (default 256)"),
    RP_FLAG(T, solid, "meshes: return the whole repaired solid, every opening capped and "
            "the inside filled (paper 003; default: the capture with only its holes "
            "filled, the hole model's: its mouths and borders stay open)"),
    RP_FLAG(T, skin, "meshes: close each hole with the repaired solid's skin zipped to its "
            "rim (paper 003's surface; default: a faired patch from the rim's own edges, "
            "given the solid's relief where it lies within 3 voxels)"),
    RP_REAL(T, max_hole, "L", 0, 1e30, "meshes: holes whose rims are wider than L (mesh "
            "units) are openings by design (a vessel's mouth) and stay open; 0 (default): "
            "a quarter of the bounding box's diagonal"),
    RP_SEED(T, seed, "the near-minimum draw's seed (default 1)"),
    RP_BACKEND(T, "scalar (one thread, the reference), host (the host's threads), opencl, "
               "or auto (default: OpenCL on the device --device names, else the host's "
               "threads); outputs are identical"),
    RP_DEVICE(T),
    RP_MAX_MEMORY(T),
    RP_THREADS(T),
};

const relief_param *relief_depth_fill_param_table(size_t *count)
{
    if (count)
        *count = sizeof table / sizeof table[0];
    return table;
}
