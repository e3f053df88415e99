/* Score the candidates (sample s, rotation r) of one target's
 * neighbourhood, candidate c = i * R + r for the i-th candidate centre:
 * sample i, or sample subset[i] when use_subset is set (sample pyramids).
 * A launch scores candidates cfirst .. cend - 1. The scoring itself is
 * relief_math.h's, the very code the scalar reference runs; the host puts
 * relief_math.h (with RM_WITH_SCORING defined) before this file when it
 * builds the program. Two kernels, the same arguments:
 *   score        one work-item per candidate (rm_score_candidate): a GPU's
 *                many threads;
 *   score_lanes  one work-item per `per_item` consecutive candidates, in
 *                RM_LANES lanes side by side (rm_score_range): a CPU
 *                device, whose compiler turns the lanes into SIMD code.
 * Tunables (-D at build time): RELIEF_WG_SIZE, score's work-group size;
 * RM_LANES, the lanes (score_lanes is built only when it is defined). */

#ifndef RELIEF_WG_SIZE
#define RELIEF_WG_SIZE 64
#endif

/* The grids' vector arguments as the arrays relief_math.h takes. */
static void unpack_grids(float4 grid4, uint4 dims4, float4 lgrid4, uint4 ldims4, float grid[4],
                         uint dims[3], float lgrid[4], uint ldims[3])
{
    grid[0] = grid4.x;
    grid[1] = grid4.y;
    grid[2] = grid4.z;
    grid[3] = grid4.w;
    dims[0] = dims4.x;
    dims[1] = dims4.y;
    dims[2] = dims4.z;
    lgrid[0] = lgrid4.x;
    lgrid[1] = lgrid4.y;
    lgrid[2] = lgrid4.z;
    lgrid[3] = lgrid4.w;
    ldims[0] = ldims4.x;
    ldims[1] = ldims4.y;
    ldims[2] = ldims4.z;
}

__kernel __attribute__((reqd_work_group_size(RELIEF_WG_SIZE, 1, 1)))
void score(__global const float *proj, __global const float *pos,
           __global const float *col, __global const uchar *matchable,
           __global const uint *tri, __global const uint *vt_start,
           __global const uint *vt, __global const uint *cell_start,
           __global const uint *cell_items, float4 grid4, uint4 dims4,
           float4 lgrid4, uint4 ldims4, __global const uint *lslot,
           __global const uint *litems,
           __global const float *s_proj, __global const float *s_frame,
           __global const float *cos_r, __global const float *sin_r,
           __global const uint *subset, uint use_subset, uint rotations, uint n,
           __global const float *qp, __global const float *q, __global const float *g,
           __global const float *qcol, float mu, float inv_b2, float inv_wsum,
           float cutoff, __global float *ssd_out, __global uchar *flag_out,
           uint cfirst, uint cend, uint per_item)
{
    const uint c = cfirst + (uint)get_global_id(0);
    float grid[4], lgrid[4], sp[3], sf[9], ssd;
    uint dims[3], ldims[3], si, r;
    int k, f;
    (void)per_item;
    if (c >= cend)
        return;
    si = use_subset ? subset[c / rotations] : c / rotations;
    r = c % rotations;
    unpack_grids(grid4, dims4, lgrid4, ldims4, grid, dims, lgrid, ldims);
    for (k = 0; k < 3; ++k)
        sp[k] = s_proj[3 * si + k];
    for (k = 0; k < 9; ++k)
        sf[k] = s_frame[9 * si + k];
    f = rm_score_candidate(proj, pos, col, matchable, tri, vt_start, vt, cell_start,
                           cell_items, grid, dims, lgrid, ldims, ldims4.w, lslot, litems,
                           sp, sf, cos_r[r], sin_r[r], n, qp,
                           q, g, qcol, mu, inv_b2, inv_wsum, cutoff, &ssd);
    ssd_out[c] = ssd;
    flag_out[c] = (uchar)f;
}

#ifdef RELIEF_LANES_KERNEL
__kernel __attribute__((reqd_work_group_size(1, 1, 1)))
void score_lanes(__global const float *proj, __global const float *pos,
                 __global const float *col, __global const uchar *matchable,
                 __global const uint *tri, __global const uint *vt_start,
                 __global const uint *vt, __global const uint *cell_start,
                 __global const uint *cell_items, float4 grid4, uint4 dims4,
                 float4 lgrid4, uint4 ldims4, __global const uint *lslot,
                 __global const uint *litems,
                 __global const float *s_proj, __global const float *s_frame,
                 __global const float *cos_r, __global const float *sin_r,
                 __global const uint *subset, uint use_subset, uint rotations, uint n,
                 __global const float *qp, __global const float *q, __global const float *g,
                 __global const float *qcol, float mu, float inv_b2, float inv_wsum,
                 float cutoff, __global float *ssd_out, __global uchar *flag_out,
                 uint cfirst, uint cend, uint per_item)
{
    const uint c0 = cfirst + (uint)get_global_id(0) * per_item;
    float grid[4], lgrid[4], cut = cutoff;
    uint dims[3], ldims[3];
    if (c0 >= cend)
        return;
    unpack_grids(grid4, dims4, lgrid4, ldims4, grid, dims, lgrid, ldims);
    rm_score_range(proj, pos, col, matchable, tri, vt_start, vt, cell_start, cell_items,
                   grid, dims, lgrid, ldims, ldims4.w, lslot, litems, s_proj, s_frame,
                   cos_r, sin_r, use_subset ? subset : 0, rotations, c0,
                   cend - c0 < per_item ? cend : c0 + per_item, per_item, per_item, n, qp,
                   q, g, qcol, mu, inv_b2, inv_wsum, &cut, 0, ssd_out, flag_out);
}
#endif
