/* Multi-scale patch voting's per-target and per-pixel work (issue 62),
 * shared by the host (C11, host/image/vote_fill.c) and the OpenCL kernels
 * (kernels/vote.cl), so that one thread, many and a device compute every
 * target's search and every pixel's vote alike. Integer arithmetic only:
 * the same bits everywhere, whatever the compiler contracts or reorders.
 *
 * A level is `v`, h x w x C samples (ushort, row-major). Its
 * targets (the centres of the P x P patches, P = 2 r + 1, that hold a hole
 * pixel) are listed in `tgt` (y * w + x) and mapped by `tmap`, bw x bh
 * ints over the box at (bx, by): a target's index, or -1. A source is a
 * patch centre inside the level at least r from its sides and no target.
 * The field `nnf` gives each target's source (y * w + x), `dist` its
 * distance. */
#ifndef VOTE_MATH_H
#define VOTE_MATH_H

#ifdef __OPENCL_C_VERSION__
#define VM_FN static inline
#define VM_G __global
#define VM_U8 uchar
#define VM_U16 ushort
#define VM_U32 uint
#define VM_I32 int
#define VM_U64 ulong
#define VM_I64 long
#define VM_U64_MAX ((ulong)0xffffffffffffffffUL)
#else
#include <stdint.h>
#define VM_FN static inline
#define VM_G
#define VM_U8 uint8_t
#define VM_U16 uint16_t
#define VM_U32 uint32_t
#define VM_I32 int32_t
#define VM_U64 uint64_t
#define VM_I64 int64_t
#define VM_U64_MAX UINT64_MAX
#endif

/* Channels a level may hold: 3 colours and 2 texture features. */
#define VM_MAX_CHANNELS 6

/* The level as the per-item functions read it. */
typedef struct vm_level {
    int w, h, C, r;
    int bx, by, bw, bh;
} vm_level;

VM_FN int vm_target_at(VM_G const VM_I32 *tmap, const vm_level *L, int x, int y)
{
    x -= L->bx, y -= L->by;
    if (x < 0 || y < 0 || x >= L->bw || y >= L->bh)
        return -1;
    return tmap[y * L->bw + x];
}

VM_FN int vm_source_ok(VM_G const VM_I32 *tmap, const vm_level *L, int x, int y)
{
    return x >= L->r && y >= L->r && x < L->w - L->r && y < L->h - L->r &&
           vm_target_at(tmap, L, x, y) < 0;
}

/* The sum of squared differences between the target patch at
 * (tx, ty), clipped to the level, and the source patch at (sx, sy), every
 * channel, rows top to bottom; it stops once it reaches `bound` (then only
 * known to be >= bound). */
VM_FN VM_U64 vm_dist(VM_G const VM_U16 *v, const vm_level *L, int tx, int ty, int sx, int sy,
                     VM_U64 bound)
{
    const int r = L->r, C = L->C;
    const int x0 = tx - r < 0 ? -tx : -r, x1 = tx + r >= L->w ? L->w - 1 - tx : r;
    VM_U64 d = 0;
    for (int dy = -r; dy <= r; ++dy) {
        const int y = ty + dy;
        VM_U64 row = 0;
        if (y < 0 || y >= L->h)
            continue;
        for (int i = 0; i <= x1 - x0; ++i) {
            const long a = ((long)y * L->w + tx + x0 + i) * C;
            const long b = ((long)(sy + dy) * L->w + sx + x0 + i) * C;
            VM_U64 e2 = 0;
            for (int c = 0; c < C; ++c) {
                const VM_I64 e = (VM_I64)v[a + c] - (VM_I64)v[b + c];
                e2 += (VM_U64)(e * e);
            }
            row += e2;
        }
        d += row;
        if (d >= bound)
            return d;
    }
    return d;
}

/* splitmix64's finaliser. */
VM_FN VM_U64 vm_mix64(VM_U64 x)
{
    x ^= x >> 30;
    x *= (VM_U64)0xbf58476d1ce4e5b9UL;
    x ^= x >> 27;
    x *= (VM_U64)0x94d049bb133111ebUL;
    return x ^ (x >> 31);
}

/* The k-th draw of pixel `pix` at (level, step): independent of the order
 * in which pixels are visited. */
VM_FN VM_U64 vm_draw(VM_U32 seed, int level, int step, VM_U32 pix, int k)
{
    VM_U64 x = vm_mix64((VM_U64)seed * (VM_U64)0x9e3779b97f4a7c15UL +
                        (VM_U64)(VM_I64)(level * 1024 + step));
    return vm_mix64(x ^ ((VM_U64)pix << 8 | (VM_U64)k));
}

/* Try source (sx, sy) for target (tx, ty) against the best so far. */
VM_FN void vm_try(VM_G const VM_U16 *v, VM_G const VM_I32 *tmap,
                  const vm_level *L, int tx, int ty, int sx, int sy, VM_U32 *best,
                  VM_U64 *bd, VM_U32 *count)
{
    const VM_U32 s = (VM_U32)(sy * L->w + sx);
    VM_U64 d;
    if (s == *best || !vm_source_ok(tmap, L, sx, sy))
        return;
    d = vm_dist(v, L, tx, ty, sx, sy, *bd);
    ++*count;
    if (d < *bd) {
        *best = s;
        *bd = d;
    }
}

/* One PatchMatch iteration of target i: the sources of its four
 * neighbours at 1 and at `jump` (when > 1), shifted back (propagation,
 * read from the field before the step: nnf), then a random search about
 * the best at halving radii from half the level's longer side. Writes
 * nnf2[i], dist2[i]; returns the distances evaluated. */
VM_FN VM_U32 vm_pm_target(VM_G const VM_U16 *v, VM_G const VM_I32 *tmap,
                          VM_G const VM_U32 *tgt, VM_G const VM_U32 *nnf,
                          VM_G const VM_U64 *dist, VM_G VM_U32 *nnf2, VM_G VM_U64 *dist2,
                          const vm_level *L, int i, VM_U32 seed, int level, int step,
                          int jump)
{
    const int tx = (int)(tgt[i] % (VM_U32)L->w), ty = (int)(tgt[i] / (VM_U32)L->w);
    VM_U32 best = nnf[i], count = 0;
    VM_U64 bd = dist[i];
    for (int j = 0; j < (jump > 1 ? 2 : 1); ++j)
        for (int k = 0; k < 4; ++k) {
            const int s = j ? jump : 1;
            const int dx = (k == 0 ? -s : k == 1 ? s : 0), dy = (k == 2 ? -s : k == 3 ? s : 0);
            const int n = vm_target_at(tmap, L, tx + dx, ty + dy);
            if (n < 0)
                continue;
            vm_try(v, tmap, L, tx, ty, (int)(nnf[n] % (VM_U32)L->w) - dx,
                   (int)(nnf[n] / (VM_U32)L->w) - dy, &best, &bd, &count);
        }
    for (int R = (L->w > L->h ? L->w : L->h) / 2, k = 0; R >= 1; R /= 2, ++k) {
        const VM_U64 u = vm_draw(seed, level, step, tgt[i], k);
        const VM_U32 span = (VM_U32)(2 * R + 1);
        int sx = (int)(best % (VM_U32)L->w) + (int)((VM_U32)(u & 0xffffffffUL) % span) - R;
        int sy = (int)(best / (VM_U32)L->w) + (int)((VM_U32)(u >> 32) % span) - R;
        sx = sx < L->r ? L->r : sx > L->w - 1 - L->r ? L->w - 1 - L->r : sx;
        sy = sy < L->r ? L->r : sy > L->h - 1 - L->r ? L->h - 1 - L->r : sy;
        vm_try(v, tmap, L, tx, ty, sx, sy, &best, &bd, &count);
    }
    nnf2[i] = best;
    dist2[i] = bd;
    return count;
}

/* The vote of hole pixel (x, y): over the targets whose patches cover it
 * (offsets row-major), the source's pixel at the same place, weighted by
 * wt (mean, rounded) or, with `best` (the caller's for the pixels of the
 * hole's thick parts), the one of the least distance (the first of
 * equals). Writes the pixel's C samples in v: only hole pixels
 * are written and sources hold none, so no vote reads what another
 * writes. */
VM_FN void vm_vote_pixel(VM_G VM_U16 *v, VM_G const VM_I32 *tmap, VM_G const VM_U32 *nnf,
                         VM_G const VM_U64 *dist, VM_G const VM_U32 *wt, const vm_level *L,
                         int x, int y, int best)
{
    const int r = L->r, C = L->C;
    VM_U64 acc[VM_MAX_CHANNELS] = {0}, den = 0, bd = VM_U64_MAX;
    for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
            const int t = vm_target_at(tmap, L, x - dx, y - dy);
            long s;
            if (t < 0)
                continue;
            s = ((long)(nnf[t] / (VM_U32)L->w + dy) * L->w + (long)(nnf[t] % (VM_U32)L->w) +
                 dx) * C;
            if (best) {
                if (dist[t] < bd) {
                    bd = dist[t];
                    for (int c = 0; c < C; ++c)
                        acc[c] = v[s + c];
                    den = 1;
                }
                continue;
            }
            for (int c = 0; c < C; ++c)
                acc[c] += (VM_U64)wt[t] * v[s + c];
            den += wt[t];
        }
    for (int c = 0; c < C; ++c)
        v[((long)y * L->w + x) * C + c] = (VM_U16)((acc[c] + den / 2) / den);
}

#endif
