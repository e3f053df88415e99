/* Window matching of the image hole filler (paper 004, section 3.2),
 * shared by the host (C11) and the OpenCL kernel patch.cl (OpenCL C 1.2),
 * so that the scalar twin and the kernel score every window alike.
 *
 * An image level is `v`, height x width x channels floats (row-major, top
 * row first), with `known`, height x width bytes (1 known, 0 hole). The
 * query is the window of radius `radius` ((2 radius + 1)^2 pixels) centred
 * at (qx, qy) in the same level; a candidate is the window centred at
 * (cx, cy), wholly inside the image. pm_score sums the squared differences
 * of every channel over the offsets where the query pixel is inside the
 * image and known and the candidate pixel is known, in row-major order of
 * the offsets and channel order, with +, - and * only and contraction off:
 * both sides get the same bits. The candidate is refused (n = -1) when its
 * centre is a hole, when more than `max_holes` of its pixels are holes, or
 * when no pixel is known in both.
 *
 * Unweighted (`weighted` 0), the caller ranks by ssd / n (paper 004). With
 * `weighted` 1, each offset's squared differences are multiplied by the
 * separable weight g[|dx|] * g[|dy|] (g: radius + 1 floats, the Gaussian
 * of paper 003's weighted mean square distance) and *wsum is the sum of the
 * weights over the pixels known in both; the caller ranks by ssd / wsum.
 * Unweighted, *wsum = n and ssd has the same bits as without weights.
 */
#ifndef PATCH_MATH_H
#define PATCH_MATH_H

/* Scores a device selects in (patch.cl's patch_block_min, patch_gather):
 * each rectangle's scores in row-major runs of PM_BLOCK, the last shorter. */
#define PM_BLOCK 256

#ifdef __OPENCL_C_VERSION__
#pragma OPENCL FP_CONTRACT OFF /* no fused multiply-add: match the host */
#define PM_FN static inline
#define PM_GLOBAL __global
#define PM_UCHAR uchar
#else
#include <stdint.h>
#define PM_FN static inline
#define PM_GLOBAL
#define PM_UCHAR uint8_t
#endif

/* Score one candidate: *ssd, *wsum and *n (pixels known in both; -1
 * refused). */
PM_FN void pm_score(PM_GLOBAL const float *v, PM_GLOBAL const PM_UCHAR *known, int width,
                    int height, int channels, int qx, int qy, int cx, int cy, int radius,
                    int max_holes, PM_GLOBAL const float *g, int weighted, float *ssd,
                    float *wsum, int *n)
{
    float s = 0.0f, ws = 0.0f;
    int both = 0, holes = 0;
    *ssd = 0.0f;
    *wsum = 0.0f;
    *n = -1;
    if (!known[cy * width + cx])
        return;
    for (int dy = -radius; dy <= radius; ++dy) {
        int y = qy + dy, inside_y = y >= 0 && y < height;
        int crow = (cy + dy) * width;
        for (int dx = -radius; dx <= radius; ++dx) {
            int x = qx + dx, c_at = crow + cx + dx;
            if (!known[c_at]) {
                ++holes;
                continue;
            }
            if (!inside_y || x < 0 || x >= width || !known[y * width + x])
                continue;
            {
                PM_GLOBAL const float *a = v + (y * width + x) * channels;
                PM_GLOBAL const float *b = v + c_at * channels;
                if (weighted) {
                    float wt = g[dy < 0 ? -dy : dy] * g[dx < 0 ? -dx : dx];
                    for (int c = 0; c < channels; ++c) {
                        float d = a[c] - b[c];
                        s = s + wt * (d * d);
                    }
                    ws = ws + wt;
                } else {
                    for (int c = 0; c < channels; ++c) {
                        float d = a[c] - b[c];
                        s = s + d * d;
                    }
                    ws = ws + 1.0f;
                }
            }
            ++both;
        }
    }
    if (holes > max_holes || both == 0)
        return;
    *ssd = s;
    *wsum = ws;
    *n = both;
}

#endif
