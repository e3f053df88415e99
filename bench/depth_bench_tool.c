/* The depth bench's chores (bench/depth_fill.sh), so that the peers'
 * outputs are converted and measured by relief's own code:
 *   depth_bench_tool pfm IN OUT.pfm
 *       any depth file relief reads (organised PCD of every DATA kind, PFM)
 *       to a PFM of its depths (missing as +inf);
 *   depth_bench_tool rgb IN.pcd OUT.png
 *       an organised PCD's colour as a picture (the occluders' figures);
 *   depth_bench_tool measure FILLED.pfm TRUTH.pfm MASK.pfm
 *       relief_depth_measure over MASK's finite non-zero pixels (the holes
 *       cut), printed as JSON: compared, rms, rim_jump, capture_jump,
 *       slope_jump, truth_rim_jump, truth_slope_jump (the truth's own jump at
 *       the same rim: the floor a fill is judged by), and the roughness ratio (mean |second
 *       difference| of FILLED over TRUTH's, both inside the holes). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "depth/depth_fill.h"
#include "depth/depth_io.h"

static relief_depth_frame load(const char *path)
{
    relief_depth_frame f;
    relief_error err = {0};
    if (relief_depth_frame_read(path, 0, &f, &err) != RELIEF_OK) {
        fprintf(stderr, "depth_bench_tool: %s\n", err.message);
        exit(1);
    }
    return f;
}

/* Mean |second difference| along rows and columns over triples wholly in
 * the holes. */
static double roughness(const float *z, const uint8_t *hole, int W, int H)
{
    double s = 0.0;
    size_t n = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int dir = 0; dir < 2; ++dir) {
                size_t i = (size_t)y * W + x, st = dir ? (size_t)W : 1;
                if (dir ? y + 2 >= H : x + 2 >= W)
                    continue;
                if (!hole[i] || !hole[i + st] || !hole[i + 2 * st] || !isfinite(z[i]) ||
                    !isfinite(z[i + st]) || !isfinite(z[i + 2 * st]))
                    continue;
                s += fabs((double)z[i] - 2.0 * z[i + st] + z[i + 2 * st]);
                ++n;
            }
    return n ? s / (double)n : NAN;
}

int main(int argc, char **argv)
{
    if (argc == 4 && argv[1][0] == 'p') {
        relief_depth_frame f = load(argv[2]);
        relief_error err = {0};
        int rc = relief_depth_frame_write(argv[3], &f, RELIEF_DEPTH_PFM, &err) != RELIEF_OK;
        if (rc)
            fprintf(stderr, "depth_bench_tool: %s\n", err.message);
        relief_depth_frame_free(&f);
        return rc;
    }
    if (argc == 5 && argv[1][0] == 'm') {
        relief_depth_frame a = load(argv[2]), t = load(argv[3]), m = load(argv[4]);
        size_t n = (size_t)a.width * a.height;
        uint8_t *hole = malloc(n);
        relief_depth_measures r;
        if (t.width != a.width || m.width != a.width || t.height != a.height ||
            m.height != a.height || !hole) {
            fprintf(stderr, "depth_bench_tool: the three images differ in size\n");
            return 1;
        }
        /* Pixels the truth lacks (the frame's own holes, which relief
         * fills and OpenCV may not) are left out of every method's
         * measures alike, so that all are judged on the same rims. */
        for (size_t i = 0; i < n; ++i) {
            hole[i] = isfinite(m.z[i]) && m.z[i] != 0.0f && isfinite(t.z[i]);
            if (!isfinite(t.z[i]))
                a.z[i] = NAN;
        }
        relief_depth_measure(a.z, t.z, hole, a.width, a.height, &r);
        printf("{\"compared\": %zu, \"rms\": %.9g, \"rim_jump\": %.9g, \"capture_jump\": %.9g, "
               "\"slope_jump\": %.9g, \"truth_rim_jump\": %.9g, \"truth_slope_jump\": %.9g, "
               "\"roughness_ratio\": %.9g}\n",
               r.compared, r.rms, r.rim_jump, r.capture_jump, r.rim_jump / r.capture_jump,
               r.truth_jump, r.truth_jump / r.capture_jump,
               roughness(a.z, hole, a.width, a.height) / roughness(t.z, hole, a.width, a.height));
        free(hole);
        relief_depth_frame_free(&a);
        relief_depth_frame_free(&t);
        relief_depth_frame_free(&m);
        return 0;
    }
    if (argc == 4 && strcmp(argv[1], "rgb") == 0) {
        relief_depth_frame f = load(argv[2]);
        relief_error err = {0};
        int bad = !f.rgb || relief_image_write(&(relief_image){f.width, f.height, 3, 8, 0, f.rgb},
                                               argv[3], &err) != RELIEF_OK;
        if (bad)
            fprintf(stderr, "depth_bench_tool: %s\n", f.rgb ? err.message : "no colour");
        relief_depth_frame_free(&f);
        return bad;
    }
    fprintf(stderr, "usage: depth_bench_tool pfm IN OUT.pfm | rgb IN.pcd OUT.png | measure "
            "FILLED TRUTH MASK\n");
    return 2;
}
