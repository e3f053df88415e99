/* relief_image_fill_params described for clients that set them by name and
 * for the documentation (relief_param, relief/core.h); the ranges are
 * relief_image_fill_params_validate's. */
#include <float.h>

#include "relief/relief.h"
#include "base/param_table.h"

#define T relief_image_fill_params

#define METHOD_NAME(code, name) name,
static const char *const methods[] = {RELIEF_IMAGE_FILL_METHOD_LIST(METHOD_NAME) NULL};
#undef METHOD_NAME

static const relief_param table[] = {
    RP_ENUM(T, method, "M", methods, "jain (default: paper 004's window-by-window "
            "copy-paste) or wexler (multi-scale patch voting, Wexler et al. 2007 with "
            "PatchMatch's search: every filled pixel a weighted vote of the patches that "
            "cover it)"),
    RP_INT(T, patch, "P", 3, 15, "wexler: the patch side, an odd number of pixels in 3..15 "
           "(default 7)"),
    RP_INT(T, em_steps, "N", 1, 50, "wexler: vote-and-search steps at the coarsest level, "
           "1..50 (default 10; finer levels fewer, at least 4)"),
    RP_INT(T, pm_steps, "N", 1, 20, "wexler: PatchMatch iterations per step, 1..20 "
           "(default 3)"),
    RP_INT(T, window, "W", 3, 1025, "jain: the starting window, an odd number of pixels in "
           "3..1025 (default 17; paper 004: 129 for texture atlases)"),
    RP_INT(T, min_window, "W", 3, 1025, "jain: the smallest window tried before the 3 x 3 "
           "fallback, odd, 3..window (default 5)"),
    RP_REAL(T, tau, "T", 0, HUGE_VAL, "jain: accept a match when its RMS difference is under tau, "
            "in sample units; 0 (default): 36 on 0..255, x 257 for 16-bit images"),
    RP_REAL(T, max_hole_fraction, "F", 0, 0.999999, "jain: a candidate window may hold this "
            "share of hole pixels at most, 0..1 (default 0.1)"),
    RP_INT(T, search_radius, "R", 0, 1000000, "jain: search the (2R+1)^2 region around each "
           "pixel, at least half a window; 0 (default): the whole image"),
    RP_FLAG(T, exhaustive, "jain: every window at full resolution (slow; the reference the "
            "pyramid is measured against); default: coarse to fine"),
    RP_FLAG(T, interp, "the 1-D interpolation pass along rows and columns over gaps no "
            "longer than the window whose ends agree and are no rougher than the image's "
            "median pixel, before copy-paste (default: on)"),
    RP_REAL(T, interp_diff, "D", -HUGE_VAL, HUGE_VAL, "1-D pass: a gap's two ends differ by "
            "at most D in every channel; < 0 (default): 16 on 0..255, scaled"),
    RP_REAL(T, interp_sd, "S", -HUGE_VAL, HUGE_VAL, "1-D pass: the 4 pixels beyond each end "
            "have a standard deviation of at most S; < 0 (default): 3 on 0..255, scaled"),
    RP_SEED(T, seed, "wexler: the random start and search; jain: the fallback's random choice (default 1)"),
    RP_BACKEND(T, "scalar (one thread, the reference), host (the host's threads), opencl, "
               "or auto (default: OpenCL on the device --device names, else the host's "
               "threads); outputs are identical"),
    RP_DEVICE(T),
    RP_MAX_MEMORY(T),
    RP_THREADS(T),
};

const relief_param *relief_image_fill_param_table(size_t *count)
{
    if (count)
        *count = sizeof table / sizeof table[0];
    return table;
}
