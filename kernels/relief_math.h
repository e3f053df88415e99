/* Math shared by the host (C11) and the OpenCL kernels (OpenCL C 1.2).
 *
 * Everything here compiles as both, so the scalar reference and the kernels
 * cannot drift apart: the scalar matcher and the OpenCL kernel both score a
 * candidate with rm_score_candidate below. RM_REAL is the scalar type: the
 * host includes this file with RM_REAL double for geometry set-up, or float
 * where it must agree with a kernel bit for bit; OpenCL C gets float.
 * Vectors are plain arrays of 3 RM_REAL (x, y, z); a frame is 9 values, the
 * rows u, v, n (so R = [u v n] as columns, and R^T a = (u.a, v.a, n.a)).
 * Only +, -, *, / and comparisons are used on the scoring path, in a fixed
 * order, with floating-point contraction off on both sides.
 */
#ifndef RELIEF_MATH_H
#define RELIEF_MATH_H

#ifndef RM_REAL
#ifdef __OPENCL_C_VERSION__
#define RM_REAL float
#else
#define RM_REAL double
#endif
#endif

#ifdef __OPENCL_C_VERSION__
#pragma OPENCL FP_CONTRACT OFF /* no fused multiply-add: match the host */
#define RM_FN static inline
#define RM_GLOBAL __global
#define RM_UINT uint
#define RM_UCHAR uchar
#else
#include <float.h>
#include <math.h>
#include <stdint.h>
#define RM_FN static inline
#define RM_GLOBAL
#define RM_UINT uint32_t
#define RM_UCHAR uint8_t
#endif

RM_FN RM_REAL rm_dot(const RM_REAL a[3], const RM_REAL b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

RM_FN void rm_cross(const RM_REAL a[3], const RM_REAL b[3], RM_REAL out[3])
{
    RM_REAL x = a[1] * b[2] - a[2] * b[1];
    RM_REAL y = a[2] * b[0] - a[0] * b[2];
    RM_REAL z = a[0] * b[1] - a[1] * b[0];
    out[0] = x;
    out[1] = y;
    out[2] = z;
}

/* Scale a to unit length; a zero vector is left as it is. */
RM_FN void rm_normalise(RM_REAL a[3])
{
    RM_REAL l = sqrt(rm_dot(a, a));
    if (l > (RM_REAL)0) {
        a[0] /= l;
        a[1] /= l;
        a[2] /= l;
    }
}

/* The local frame of paper 000 section 3 for unit normal n = (x, y, z):
 * u is perpendicular to n in the plane of the two largest components,
 *   |x| smallest: u = (0, -z, y); |y| smallest: u = (z, 0, -x);
 *   |z| smallest: u = (-y, x, 0)  (ties go to the earlier axis),
 * normalised, and v = n x u, so [u v n] is a right-handed orthonormal
 * frame. Deterministic: the same normal always gives the same frame. */
RM_FN void rm_frame_from_normal(const RM_REAL n[3], RM_REAL u[3], RM_REAL v[3])
{
    RM_REAL ax = fabs(n[0]), ay = fabs(n[1]), az = fabs(n[2]);
    if (ax <= ay && ax <= az) {
        u[0] = 0;
        u[1] = -n[2];
        u[2] = n[1];
    } else if (ay <= az) {
        u[0] = n[2];
        u[1] = 0;
        u[2] = -n[0];
    } else {
        u[0] = -n[1];
        u[1] = n[0];
        u[2] = 0;
    }
    rm_normalise(u);
    rm_cross(n, u, v);
}

/* Squared distance from p to the triangle (a, b, c), by the closest-point
 * regions of Ericson, Real-Time Collision Detection, section 5.1.5. */
RM_FN RM_REAL rm_point_triangle_d2(const RM_REAL p[3], const RM_REAL a[3],
                                   const RM_REAL b[3], const RM_REAL c[3])
{
    RM_REAL ab[3], ac[3], ap[3], bp[3], cp[3], q[3];
    RM_REAL d1, d2, d3, d4, d5, d6, va, vb, vc, v, w, den;
    int k;
    for (k = 0; k < 3; ++k) {
        ab[k] = b[k] - a[k];
        ac[k] = c[k] - a[k];
        ap[k] = p[k] - a[k];
        bp[k] = p[k] - b[k];
        cp[k] = p[k] - c[k];
    }
    d1 = rm_dot(ab, ap);
    d2 = rm_dot(ac, ap);
    d3 = rm_dot(ab, bp);
    d4 = rm_dot(ac, bp);
    d5 = rm_dot(ab, cp);
    d6 = rm_dot(ac, cp);
    vc = d1 * d4 - d3 * d2;
    vb = d5 * d2 - d1 * d6;
    va = d3 * d6 - d5 * d4;
    if (d1 <= 0 && d2 <= 0) { /* vertex region a */
        for (k = 0; k < 3; ++k)
            q[k] = ap[k];
    } else if (d3 >= 0 && d4 <= d3) { /* vertex region b */
        for (k = 0; k < 3; ++k)
            q[k] = bp[k];
    } else if (vc <= 0 && d1 >= 0 && d3 <= 0) { /* edge ab */
        v = d1 / (d1 - d3);
        for (k = 0; k < 3; ++k)
            q[k] = ap[k] - v * ab[k];
    } else if (d6 >= 0 && d5 <= d6) { /* vertex region c */
        for (k = 0; k < 3; ++k)
            q[k] = cp[k];
    } else if (vb <= 0 && d2 >= 0 && d6 <= 0) { /* edge ac */
        w = d2 / (d2 - d6);
        for (k = 0; k < 3; ++k)
            q[k] = ap[k] - w * ac[k];
    } else if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) { /* edge bc */
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (k = 0; k < 3; ++k)
            q[k] = bp[k] - w * (c[k] - b[k]);
    } else { /* inside the face */
        den = 1 / (va + vb + vc);
        v = vb * den;
        w = vc * den;
        for (k = 0; k < 3; ++k)
            q[k] = ap[k] - ab[k] * v - ac[k] * w;
    }
    return rm_dot(q, q);
}

/* ------------------------------------------------------------ scoring */

/* The scoring path is float on both sides: define RM_WITH_SCORING (and
 * RM_REAL float) to get it. */
#ifdef RM_WITH_SCORING

/* |x| in float on both sides (C's fabs would compute in double). */
#define RM_ABSF(x) ((x) < 0 ? -(x) : (x))

/* Outcome of scoring one candidate. */
#define RM_VALID 0   /* scored; the SSD is exact */
#define RM_INVALID 1 /* some neighbour maps onto a vertex that is not matchable */
#define RM_PRUNED 2  /* stopped once the partial SSD exceeded the cutoff */

/* The surface as the matcher sees it (float, device-friendly). All arrays
 * are indexed by vertex id unless said otherwise.
 *   proj       nv x 3  projected positions v' on the primitive
 *   pos        nv x 3  real positions v (targets move as they are textured)
 *   col        nv x 3  colours in [0, 1] (read only when mu < 1)
 *   matchable  nv      1 where a neighbour may land (samples; with
 *                      --bootstrap also textured targets)
 *   tri        nt x 3  triangles
 *   vt_start   nv + 1  CSR offsets into vt of each vertex's triangles
 *   vt                 incident triangle ids
 *   cell_start ncell+1 CSR offsets into cell_items of each grid cell
 *   cell_items nv      vertex ids sorted by cell, then id
 *   lgrid, ldims, lmask, lslot, litems: the closest-vertex lists (see
 *              rm_closest_vertex_listed)
 * The uniform grid over the projected positions has its origin at
 * grid[0..2], cell size grid[3], and dims[0..2] cells per axis. */

/* Index of the vertex whose projected position is closest to x (ties: the
 * lowest id), by rings of grid cells around x's cell until no closer
 * vertex can remain. Exact. */
RM_FN RM_UINT rm_closest_vertex(const float x[3], RM_GLOBAL const float *proj,
                                RM_GLOBAL const RM_UINT *cell_start,
                                RM_GLOBAL const RM_UINT *cell_items, const float grid[4],
                                const RM_UINT dims[3])
{
    int c[3], ring, maxring = 0, k;
    float best = FLT_MAX;
    RM_UINT best_id = 0xffffffffu;
    for (k = 0; k < 3; ++k) {
        float f = (x[k] - grid[k]) / grid[3];
        int i = f < 0 ? 0 : (f >= (float)dims[k] ? (int)dims[k] - 1 : (int)f);
        c[k] = i;
        if ((int)dims[k] > maxring)
            maxring = (int)dims[k];
    }
    for (ring = 0; ring <= maxring; ++ring) {
        int i, j, l;
        for (i = c[0] - ring; i <= c[0] + ring; ++i) {
            if (i < 0 || i >= (int)dims[0])
                continue;
            for (j = c[1] - ring; j <= c[1] + ring; ++j) {
                if (j < 0 || j >= (int)dims[1])
                    continue;
                for (l = c[2] - ring; l <= c[2] + ring; ++l) {
                    RM_UINT cell, it, end;
                    int di = i - c[0], dj = j - c[1], dl = l - c[2];
                    if (l < 0 || l >= (int)dims[2])
                        continue;
                    di = di < 0 ? -di : di;
                    dj = dj < 0 ? -dj : dj;
                    dl = dl < 0 ? -dl : dl;
                    if (di != ring && dj != ring && dl != ring)
                        continue; /* inside: visited in an earlier ring */
                    cell = ((RM_UINT)l * dims[1] + (RM_UINT)j) * dims[0] + (RM_UINT)i;
                    end = cell_start[cell + 1];
                    for (it = cell_start[cell]; it < end; ++it) {
                        RM_UINT id = cell_items[it];
                        float dx = proj[3 * id] - x[0], dy = proj[3 * id + 1] - x[1];
                        float dz = proj[3 * id + 2] - x[2];
                        float d2 = dx * dx + dy * dy + dz * dz;
                        if (d2 < best || (d2 == best && id < best_id)) {
                            best = d2;
                            best_id = id;
                        }
                    }
                }
            }
        }
        /* Every vertex in ring + 1 or beyond is at least ring cells away. */
        if (best_id != 0xffffffffu) {
            float reach = (float)ring * grid[3];
            if (best <= reach * reach)
                break;
        }
    }
    return best_id;
}

/* Slot of a cell id in the closest-vertex lists' hash table (before the
 * mask): the 32-bit finaliser of MurmurHash3, the same in C and OpenCL C. */
RM_FN RM_UINT rm_cell_hash(RM_UINT k)
{
    k ^= k >> 16;
    k *= 0x85ebca6bu;
    k ^= k >> 13;
    k *= 0xc2b2ae35u;
    k ^= k >> 16;
    return k;
}

#define RM_EMPTY 0xffffffffu /* an empty slot of the lists' hash table */

/* The same vertex as rm_closest_vertex (the closest by projected position,
 * ties: the lowest id), from the cell's precomputed list when x falls in a
 * listed cell of the fine sparse grid: one short scan, the same work for
 * most queries, instead of rings of cells. The lists hold every vertex
 * that can be the closest to any point of their (slightly enlarged) cell,
 * so the answer is exact; anywhere else the rings answer.
 *   lgrid      origin x, y, z and cell size of the fine grid
 *   ldims      its cells per axis; cell id (l * ldims[1] + j) * ldims[0] + i
 *   lmask      hash table slots - 1 (a power of two - 1)
 *   lslot      (lmask + 1) x 3: cell id or RM_EMPTY, offset, count
 *   litems     the lists' vertex ids, ascending within a list */
RM_FN RM_UINT rm_closest_vertex_listed(
    const float x[3], RM_GLOBAL const float *proj, RM_GLOBAL const RM_UINT *cell_start,
    RM_GLOBAL const RM_UINT *cell_items, const float grid[4], const RM_UINT dims[3],
    const float lgrid[4], const RM_UINT ldims[3], RM_UINT lmask,
    RM_GLOBAL const RM_UINT *lslot, RM_GLOBAL const RM_UINT *litems)
{
    RM_UINT c[3], cell, h, probe;
    int k;
    for (k = 0; k < 3; ++k) {
        float f = (x[k] - lgrid[k]) / lgrid[3];
        if (!(f >= 0) || f >= (float)ldims[k]) /* outside (or NaN) */
            return rm_closest_vertex(x, proj, cell_start, cell_items, grid, dims);
        c[k] = (RM_UINT)f;
    }
    cell = (c[2] * ldims[1] + c[1]) * ldims[0] + c[0];
    h = rm_cell_hash(cell) & lmask;
    for (probe = 0; probe <= lmask; ++probe) {
        RM_UINT key = lslot[3 * h];
        if (key == cell) {
            RM_UINT it = lslot[3 * h + 1], end = it + lslot[3 * h + 2];
            RM_UINT best_id = 0xffffffffu;
            float best = FLT_MAX;
            for (; it < end; ++it) {
                RM_UINT id = litems[it];
                float dx = proj[3 * id] - x[0], dy = proj[3 * id + 1] - x[1];
                float dz = proj[3 * id + 2] - x[2];
                float d2 = dx * dx + dy * dy + dz * dz;
                if (d2 < best) { /* ascending ids: the first of equals stays */
                    best = d2;
                    best_id = id;
                }
            }
            return best_id;
        }
        if (key == RM_EMPTY)
            break;
        h = (h + 1) & lmask;
    }
    return rm_closest_vertex(x, proj, cell_start, cell_items, grid, dims);
}

/* Score candidate (s, r) for one target's neighbourhood (DESIGN.md,
 * "Scoring one candidate").
 *   s_proj    s', the sample's projected position (3)
 *   s_frame   R_s as rows u, v, n (9)
 *   cr, sr    cos and sin of the rotation 2 pi r / R
 *   n         neighbourhood size; qp, q: n x 3 projected and real offsets
 *             in the target's frame; g: n Gaussian weights; qcol: n x 3
 *             colours; the neighbours come in the order the host chose
 *             (decreasing weight), which fixes the order of the sums
 *   mu        shape weight; inv_b2 = 1 / B_shape^2; inv_wsum = 1 / sum g
 *   cutoff    stop and report RM_PRUNED once the partial SSD exceeds it
 * Returns RM_VALID, RM_INVALID or RM_PRUNED; *ssd gets the SSD (valid) or
 * the partial SSD when pruning (pruned). */
RM_FN int rm_score_candidate(
    RM_GLOBAL const float *proj, RM_GLOBAL const float *pos, RM_GLOBAL const float *col,
    RM_GLOBAL const RM_UCHAR *matchable, RM_GLOBAL const RM_UINT *tri,
    RM_GLOBAL const RM_UINT *vt_start, RM_GLOBAL const RM_UINT *vt,
    RM_GLOBAL const RM_UINT *cell_start, RM_GLOBAL const RM_UINT *cell_items,
    const float grid[4], const RM_UINT dims[3], const float lgrid[4], const RM_UINT ldims[3],
    RM_UINT lmask, RM_GLOBAL const RM_UINT *lslot, RM_GLOBAL const RM_UINT *litems,
    const float s_proj[3],
    const float s_frame[9], float cr, float sr, RM_UINT n, RM_GLOBAL const float *qp,
    RM_GLOBAL const float *q, RM_GLOBAL const float *g, RM_GLOBAL const float *qcol,
    float mu, float inv_b2, float inv_wsum, float cutoff, float *ssd)
{
    float shape = 0, colour = 0;
    RM_UINT i;
    for (i = 0; i < n; ++i) {
        float a, b, xp[3], x[3], best = FLT_MAX, term;
        RM_UINT v2, t, tend;
        int k;
        /* x' = s' + R_s Rz(theta) q'  (Rz turns about the frame's n). */
        a = cr * qp[3 * i] - sr * qp[3 * i + 1];
        b = sr * qp[3 * i] + cr * qp[3 * i + 1];
        for (k = 0; k < 3; ++k)
            xp[k] = s_proj[k] + a * s_frame[k] + b * s_frame[3 + k] +
                    qp[3 * i + 2] * s_frame[6 + k];
        v2 = rm_closest_vertex_listed(xp, proj, cell_start, cell_items, grid, dims, lgrid,
                                      ldims, lmask, lslot, litems);
        if (v2 == 0xffffffffu || !matchable[v2]) {
            *ssd = FLT_MAX;
            return RM_INVALID;
        }
        if (mu < 1) {
            float c0 = qcol[3 * i] - col[3 * v2], c1 = qcol[3 * i + 1] - col[3 * v2 + 1];
            float c2 = qcol[3 * i + 2] - col[3 * v2 + 2];
            term = (RM_ABSF(c0) + RM_ABSF(c1) + RM_ABSF(c2)) / 3;
            colour += g[i] * term;
            /* The partial SSD without this neighbour's shape term bounds
             * the one with it from below (every term >= 0, and rounding is
             * monotonic), so stopping here prunes exactly the candidates
             * the check below would, only before the triangles are read. */
            *ssd = (mu * shape * inv_b2 + (1 - mu) * colour) * inv_wsum;
            if (*ssd > cutoff)
                return RM_PRUNED;
        }
        a = cr * q[3 * i] - sr * q[3 * i + 1];
        b = sr * q[3 * i] + cr * q[3 * i + 1];
        for (k = 0; k < 3; ++k)
            x[k] = s_proj[k] + a * s_frame[k] + b * s_frame[3 + k] +
                   q[3 * i + 2] * s_frame[6 + k];
        tend = vt_start[v2 + 1];
        for (t = vt_start[v2]; t < tend; ++t) {
            RM_UINT f = vt[t];
            float pa[3], pb[3], pc[3], d2;
            for (k = 0; k < 3; ++k) {
                pa[k] = pos[3 * tri[3 * f] + k];
                pb[k] = pos[3 * tri[3 * f + 1] + k];
                pc[k] = pos[3 * tri[3 * f + 2] + k];
            }
            d2 = rm_point_triangle_d2(x, pa, pb, pc);
            if (d2 < best)
                best = d2;
        }
        shape += g[i] * best;
        *ssd = (mu * shape * inv_b2 + (1 - mu) * colour) * inv_wsum;
        if (*ssd > cutoff)
            return RM_PRUNED;
    }
    *ssd = (mu * shape * inv_b2 + (1 - mu) * colour) * inv_wsum;
    return RM_VALID;
}

#endif /* RM_WITH_SCORING */

#endif
