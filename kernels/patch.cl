/* Window scores of the image hole filler (host/image/patch_opencl.c; its
 * scalar twin is host/image/patch_scalar.c), for one query or a batch of
 * them. One work-item per candidate centre, the first dimension along x,
 * so that neighbouring work-items read neighbouring pixels. The level's
 * pixels stay on the device between launches; only the scores come back. */

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
