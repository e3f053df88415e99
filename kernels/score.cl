/* Score every candidate (sample s, rotation r) of one target's neighbourhood:
 * one work-item per candidate c = i * R + r, i the i-th candidate centre:
 * sample i, or sample subset[i] when use_subset is set (sample pyramids). The scoring itself is
 * rm_score_candidate in relief_math.h, the very function the scalar
 * reference runs; the host puts relief_math.h (with RM_WITH_SCORING
 * defined) before this file when it builds the program.
 * Tunables (-D at build time): RELIEF_WG_SIZE, the work-group size. */

#ifndef RELIEF_WG_SIZE
#define RELIEF_WG_SIZE 64
#endif

__kernel __attribute__((reqd_work_group_size(RELIEF_WG_SIZE, 1, 1)))
void score(__global const float *proj, __global const float *pos,
           __global const float *col, __global const uchar *matchable,
           __global const uint *tri, __global const uint *vt_start,
           __global const uint *vt, __global const uint *cell_start,
           __global const uint *cell_items, float4 grid4, uint4 dims4,
           float4 lgrid4, uint4 ldims4, __global const uint *lslot,
           __global const uint *litems,
           __global const float *s_proj, __global const float *s_frame,
           __global const float *cos_r, __global const float *sin_r, uint centres,
           __global const uint *subset, uint use_subset, uint rotations, uint n, __global const float *qp,
           __global const float *q, __global const float *g,
           __global const float *qcol, float mu, float inv_b2, float inv_wsum,
           float cutoff, __global float *ssd_out, __global uchar *flag_out)
{
    const uint c = (uint)get_global_id(0);
    float grid[4], lgrid[4], sp[3], sf[9], ssd;
    uint dims[3], ldims[3], si, r;
    int k, f;
    if (c >= centres * rotations)
        return;
    si = use_subset ? subset[c / rotations] : c / rotations;
    r = c % rotations;
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
