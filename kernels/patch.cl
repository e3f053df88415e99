/* Window scores of the image hole filler (host/image/patch_opencl.c; its
 * scalar twin is host/image/patch_scalar.c), for one query or a batch of
 * them. One work-item per candidate centre, the first dimension along x,
 * so that neighbouring work-items read neighbouring pixels. The level's
 * pixels stay on the device between launches; only the scores come back,
 * and of a large batch only the blocks that may hold each query's best
 * (patch_block_min, patch_gather). */

/* Queries' rectangles (one, or a depth synthesis's batch):
 * rectangle q is rects[7 q ..] = qx, qy, x0, y0, nx, ny, offset, its
 * scores at offset + j * nx + i. The third dimension is the query; the
 * first two span the largest rectangle, and the work-items past a smaller
 * one return. */
__kernel void patch_score_rects(__global const float *v, __global const uchar *known, int width,
                                int height, int channels, int radius, int max_holes,
                                __global const float *g, int weighted,
                                __global const int *rects, int count, __global float *ssd,
                                __global float *wsum, __global int *n)
{
    int i = get_global_id(0), j = get_global_id(1), q = get_global_id(2), at;
    __global const int *r = rects + 7 * q;
    float s, ws;
    int k;
    if (q >= count || i >= r[4] || j >= r[5])
        return;
    pm_score(v, known, width, height, channels, r[0], r[1], r[2] + i, r[3] + j, radius,
             max_holes, g, weighted, &s, &ws, &k);
    at = r[6] + j * r[4] + i;
    ssd[at] = s;
    wsum[at] = ws;
    n[at] = k;
}

/* Queries' candidate centres (one query's refinement list, or a batch's):
 * pair i is pairs[4 i ..] = qx, qy, cx, cy. */
__kernel void patch_score_pairs(__global const float *v, __global const uchar *known, int width,
                                int height, int channels, int radius, int max_holes,
                                __global const float *g, int weighted,
                                __global const int *pairs, int count, __global float *ssd,
                                __global float *wsum, __global int *n)
{
    int i = get_global_id(0);
    __global const int *p = pairs + 4 * i;
    float s, ws;
    int k;
    if (i >= count)
        return;
    pm_score(v, known, width, height, channels, p[0], p[1], p[2], p[3], radius, max_holes, g,
             weighted, &s, &ws, &k);
    ssd[i] = s;
    wsum[i] = ws;
    n[i] = k;
}

/* The least msd in each block of PM_BLOCK consecutive scores of a batch's
 * rectangles (rectangle q's blocks numbered from bstart[q], its scores from
 * its offset r[6]), so that the host reads back only the blocks that may
 * hold a query's best few (patch_opencl.c, select_rects). msd is ssd / wsum
 * (weighted) or ssd / n, in float: the host ranks in double and selects
 * with a margin far above the difference. A block with no candidate gives
 * NaN; a non-finite msd (an overflow in float) counts as -infinity, so that
 * its block is always read. One
 * work-group per block, the block's scores read side by side. */
__kernel __attribute__((reqd_work_group_size(PM_BLOCK, 1, 1))) void
patch_block_min(__global const float *ssd, __global const float *wsum, __global const int *n,
                int weighted, __global const int *rects, __global const int *bstart, int count,
                __global float *bmin)
{
    __local float m[PM_BLOCK];
    int b = get_group_id(0), t = get_local_id(0), lo = 0, hi = count - 1;
    float key = NAN;
    while (lo < hi) { /* the rectangle of block b: the last q with bstart[q] <= b */
        int mid = (lo + hi + 1) / 2;
        if (bstart[mid] <= b)
            lo = mid;
        else
            hi = mid - 1;
    }
    {
        __global const int *r = rects + 7 * lo;
        int k = (b - bstart[lo]) * PM_BLOCK + t;
        if (k < r[4] * r[5]) {
            int at = r[6] + k, nk = n[at];
            float div = weighted ? wsum[at] : (float)nk;
            if (nk > 0 && div > 0.0f) {
                key = ssd[at] / div;
                key = isfinite(key) ? key : -INFINITY;
            }
        }
    }
    m[t] = key;
    barrier(CLK_LOCAL_MEM_FENCE);
    for (int s = PM_BLOCK / 2; s > 0; s >>= 1) {
        if (t < s) {
            float a = m[t], c = m[t + s];
            m[t] = isnan(a) || c < a ? c : a;
        }
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    if (t == 0)
        bmin[b] = m[0];
}

/* The selected blocks' scores side by side: block j is runs[2 j] (its
 * first score's index), runs[2 j + 1] (its length, up to PM_BLOCK), copied
 * to j * PM_BLOCK of the outputs. */
__kernel void patch_gather(__global const float *ssd, __global const float *wsum,
                           __global const int *n, __global const int *runs, int blocks,
                           __global float *out_ssd, __global float *out_wsum,
                           __global int *out_n)
{
    int i = get_global_id(0), j = i / PM_BLOCK, k = i % PM_BLOCK, from;
    if (j >= blocks || k >= runs[2 * j + 1])
        return;
    from = runs[2 * j] + k;
    out_ssd[i] = ssd[from];
    out_wsum[i] = wsum[from];
    out_n[i] = n[from];
}
