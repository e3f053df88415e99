/* Multi-scale patch voting on a device (host/image/vote_opencl.c; its
 * host twin is host/image/vote_fill.c): kernels/vote_math.h's per-target
 * search and per-pixel vote, one work-item each. Every launch reads the
 * field of the step before and writes another buffer, so the work-items'
 * order never matters. The level's geometry: w, h, C, r, bx, by, bw, bh
 * (vote_math.h's vm_level). */

#define VM_LEVEL_ARGS int w, int h, int C, int r, int bx, int by, int bw, int bh
#define VM_LEVEL_INIT {w, h, C, r, bx, by, bw, bh}

/* dist[i]: target i's distance to its source nnf[i]. */
__kernel void vote_dist(__global const ushort *v, __global const uint *tgt, __global const uint *nnf,
                        __global ulong *dist, int nt, VM_LEVEL_ARGS)
{
    const int i = get_global_id(0);
    const vm_level L = VM_LEVEL_INIT;
    if (i >= nt)
        return;
    dist[i] = vm_dist(v, &L, (int)(tgt[i] % (uint)w), (int)(tgt[i] / (uint)w),
                      (int)(nnf[i] % (uint)w), (int)(nnf[i] / (uint)w), VM_U64_MAX);
}

/* One PatchMatch iteration of target i into nnf2, dist2; cnt[i] counts the
 * distances it evaluated. */
__kernel void vote_pm(__global const ushort *v, __global const int *tmap, __global const uint *tgt,
                      __global const uint *nnf, __global const ulong *dist,
                      __global uint *nnf2, __global ulong *dist2, __global uint *cnt, int nt,
                      uint seed, int level, int step, int jump, VM_LEVEL_ARGS)
{
    const int i = get_global_id(0);
    const vm_level L = VM_LEVEL_INIT;
    if (i >= nt)
        return;
    cnt[i] += vm_pm_target(v, tmap, tgt, nnf, dist, nnf2, dist2, &L, i, seed, level, step,
                           jump);
}

/* The vote of the hole pixel at (bx + x, by + y), for every (x, y) of the
 * box: with `best`, the best patch's pixel where the hole is thick (hole
 * 1), the mean where it is thin (2). */
__kernel void vote_vote(__global ushort *v, __global const uchar *hole,
                        __global const int *tmap, __global const uint *nnf,
                        __global const ulong *dist, __global const uint *wt, int best,
                        VM_LEVEL_ARGS)
{
    const int x = bx + (int)get_global_id(0), y = by + (int)get_global_id(1);
    const vm_level L = VM_LEVEL_INIT;
    if (x >= bx + bw || y >= by + bh || !hole[y * w + x])
        return;
    vm_vote_pixel(v, tmap, nnf, dist, wt, &L, x, y, best && hole[y * w + x] == 1);
}
