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


/* ------------------------------------------------ scoring in lock-step
 *
 * rm_score_range scores a run of candidates with the very arithmetic of
 * rm_score_candidate, RM_LANES of them side by side: each lane holds one
 * candidate, and one step takes every lane's next neighbour through the
 * same straight-line code (where the neighbour lands, its closest vertex,
 * the colour term, the distances to that vertex's triangles, the pruning
 * test), so a compiler can give each lane a SIMD lane: the host's
 * (score_lanes.c) and PoCL's through auto-vectorisation of the loops over
 * the lanes. A lane whose candidate ends (pruned, invalid or scored) takes
 * the next candidate of the run at once, so pruning does not leave lanes
 * idle. Per lane the operations and their order are rm_score_candidate's,
 * so every score and flag is bit for bit the reference's. */

#ifndef RM_LANES
#define RM_LANES 8
#endif
/* Put before each loop over the lanes that is meant to become SIMD code:
 * the host defines it as an OpenMP simd pragma (score_lanes.c). */
#ifndef RM_SIMD
#define RM_SIMD
#endif
#define RM_NONE 0xffffffffu /* a lane without a candidate */
#define RM_ROUNDS 3         /* rounds of new candidates before the triangles */
#define RM_FIND_NONE 0  /* an idle lane */
#define RM_FIND_PROBE 1 /* looking for its cell in the lists' hash table */
#define RM_FIND_LIST 2  /* found it: the cell's list answers */
#define RM_FIND_RINGS 3 /* not listed: rm_closest_vertex answers */

/* rm_point_triangle_d2 without branches, on separate coordinates: the
 * region of Ericson's test is found first, then one expression
 *   q = base - e1 * s - e2 * t
 * gives the closest point's offset for every region (base ap, bp or cp;
 * e1 ab or bc; e2 ac; s and t from the region's single division). Each
 * region's q is the reference's to the last bit, up to the sign of a zero
 * (x - 0 * e), which squaring removes, so the result is identical. */
RM_FN float rm_point_triangle_d2_flat(float px, float py, float pz, float ax, float ay,
                                      float az, float bx, float by, float bz, float cx,
                                      float cy, float cz)
{
    float abx = bx - ax, aby = by - ay, abz = bz - az;
    float acx = cx - ax, acy = cy - ay, acz = cz - az;
    float apx = px - ax, apy = py - ay, apz = pz - az;
    float bpx = px - bx, bpy = py - by, bpz = pz - bz;
    float cpx = px - cx, cpy = py - cy, cpz = pz - cz;
    float d1 = abx * apx + aby * apy + abz * apz;
    float d2 = acx * apx + acy * apy + acz * apz;
    float d3 = abx * bpx + aby * bpy + abz * bpz;
    float d4 = acx * bpx + acy * bpy + acz * bpz;
    float d5 = abx * cpx + aby * cpy + abz * cpz;
    float d6 = acx * cpx + acy * cpy + acz * cpz;
    float vc = d1 * d4 - d3 * d2;
    float vb = d5 * d2 - d1 * d6;
    float va = d3 * d6 - d5 * d4;
    float e43 = d4 - d3, e56 = d5 - d6;
    /* The reference's regions in its order: the first that holds wins. */
    const int in_a = (d1 <= 0) & (d2 <= 0);
    const int in_b = !in_a & (d3 >= 0) & (d4 <= d3);
    const int on_ab = !in_a & !in_b & (vc <= 0) & (d1 >= 0) & (d3 <= 0);
    const int in_c = !in_a & !in_b & !on_ab & (d6 >= 0) & (d5 <= d6);
    const int on_ac = !in_a & !in_b & !on_ab & !in_c & (vb <= 0) & (d2 >= 0) & (d6 <= 0);
    const int on_bc = !in_a & !in_b & !on_ab & !in_c & !on_ac & (va <= 0) & (e43 >= 0) & (e56 >= 0);
    const int in_face = !in_a & !in_b & !on_ab & !in_c & !on_ac & !on_bc;
    {
        /* Every operand is computed whatever the region and only chosen
         * here: selects, not branches. */
        const float den_ab = d1 - d3, den_ac = d2 - d6, den_bc = e43 + e56;
        const float den_face = va + vb + vc;
        const float bcx = cx - bx, bcy = cy - by, bcz = cz - bz;
        float num = 0.0f, den = 1.0f, quot, vq, wq, s, t, bx0, by0, bz0, e1x, e1y, e1z, qx, qy, qz;
        num = on_ab ? d1 : num;
        den = on_ab ? den_ab : den;
        num = on_ac ? d2 : num;
        den = on_ac ? den_ac : den;
        num = on_bc ? e43 : num;
        den = on_bc ? den_bc : den;
        num = in_face ? 1.0f : num;
        den = in_face ? den_face : den;
        quot = num / den;
        vq = vb * quot;
        wq = vc * quot;
        s = (on_ab | on_bc) ? quot : 0.0f;
        s = in_face ? vq : s;
        t = on_ac ? quot : 0.0f;
        t = in_face ? wq : t;
        bx0 = (in_b | on_bc) ? bpx : in_c ? cpx : apx;
        by0 = (in_b | on_bc) ? bpy : in_c ? cpy : apy;
        bz0 = (in_b | on_bc) ? bpz : in_c ? cpz : apz;
        e1x = on_bc ? bcx : abx;
        e1y = on_bc ? bcy : aby;
        e1z = on_bc ? bcz : abz;
        qx = bx0 - e1x * s - acx * t;
        qy = by0 - e1y * s - acy * t;
        qz = bz0 - e1z * s - acz * t;
        return qx * qx + qy * qy + qz * qz;
    }
}

/* The state of the lanes: structure of arrays, one entry per lane. */
typedef struct rm_lanes {
    RM_UINT cand[RM_LANES];  /* candidate index, RM_NONE when idle */
    RM_UINT at[RM_LANES];    /* the neighbour this step scores */
    RM_UINT v2[RM_LANES];    /* its closest vertex (0, a valid id, in idle lanes) */
    RM_UINT ready[RM_LANES]; /* 1: at the triangles of neighbour at */
    RM_UINT fresh[RM_LANES]; /* 1: became ready in this round */
    RM_UINT vnew[RM_LANES];  /* the closest vertex the lists found */
    RM_UINT tfirst[RM_LANES], tcount[RM_LANES]; /* v2's triangles in vt */
    RM_UINT tlast[RM_LANES];                     /* tcount - 1, or 0 */
    /* The closest-vertex search: the lane's cell of the lists' grid, its
     * slot in their hash table, where the search stands (RM_FIND_*), the
     * cell's list in litems (first, last = count - 1, count) and the
     * nearest distance so far. */
    RM_UINT cell[RM_LANES], slot[RM_LANES], find[RM_LANES];
    RM_UINT lfirst[RM_LANES], llast[RM_LANES], lcount[RM_LANES];
    float nearest[RM_LANES];
    float shape[RM_LANES], colour[RM_LANES], ssd[RM_LANES], best[RM_LANES];
    float cr[RM_LANES], sr[RM_LANES];
    float sp[3][RM_LANES], sf[9][RM_LANES]; /* s' and R_s (rows u, v, n) */
    float xp[3][RM_LANES], x[3][RM_LANES];  /* the neighbour's x' and x */
} rm_lanes;

/* Score the candidates c0, c0 + 1, ... (c = centre * rotations + r, the
 * centre's sample subset[centre], or the centre itself when subset is
 * null) in blocks of `block` consecutive ones, `stride` apart (stride >=
 * block; block == stride: every candidate), up to c1 (excluded), writing
 * ssd_out[c] and flag_out[c] as rm_score_candidate would with the cutoff
 * *cutoff. With `running` (host only, where RM_LOWER_CUTOFF(cut, ssd) is
 * defined), a valid score lowers *cutoff for the candidates after it. The
 * other arguments are rm_score_candidate's, and s_proj, s_frame, cos_r and
 * sin_r the samples' positions and frames and the rotations' cos and sin. */
RM_FN void rm_score_range(
    RM_GLOBAL const float *proj, RM_GLOBAL const float *pos, RM_GLOBAL const float *col,
    RM_GLOBAL const RM_UCHAR *matchable, RM_GLOBAL const RM_UINT *tri,
    RM_GLOBAL const RM_UINT *vt_start, RM_GLOBAL const RM_UINT *vt,
    RM_GLOBAL const RM_UINT *cell_start, RM_GLOBAL const RM_UINT *cell_items,
    const float grid[4], const RM_UINT dims[3], const float lgrid[4], const RM_UINT ldims[3],
    RM_UINT lmask, RM_GLOBAL const RM_UINT *lslot, RM_GLOBAL const RM_UINT *litems,
    RM_GLOBAL const float *s_proj, RM_GLOBAL const float *s_frame,
    RM_GLOBAL const float *cos_r, RM_GLOBAL const float *sin_r,
    RM_GLOBAL const RM_UINT *subset, RM_UINT rotations, RM_UINT c0, RM_UINT c1,
    RM_UINT block, RM_UINT stride, RM_UINT n, RM_GLOBAL const float *qp,
    RM_GLOBAL const float *q, RM_GLOBAL const float *g, RM_GLOBAL const float *qcol,
    float mu, float inv_b2, float inv_wsum, float *cutoff, int running,
    RM_GLOBAL float *ssd_out, RM_GLOBAL RM_UCHAR *flag_out)
{
    rm_lanes L;
    RM_UINT next = c0, left = block, busy = 0, l, t, maxc;
    RM_UINT nc = c0 / rotations, nr = c0 % rotations;
    int round;
    int k;
    (void)running;
    if (n == 0) { /* nothing to step through: the reference's answer */
        for (; next < c1; ++next, --left) {
            RM_UINT si, r;
            float s, sp[3], sf[9];
            if (left == 0) {
                next += stride - block;
                left = block;
                if (next >= c1)
                    break;
            }
            si = subset ? subset[next / rotations] : next / rotations;
            r = next % rotations;
            for (k = 0; k < 3; ++k)
                sp[k] = s_proj[3 * si + k];
            for (k = 0; k < 9; ++k)
                sf[k] = s_frame[9 * si + k];
            flag_out[next] = (RM_UCHAR)rm_score_candidate(
                proj, pos, col, matchable, tri, vt_start, vt, cell_start, cell_items, grid,
                dims, lgrid, ldims, lmask, lslot, litems, sp, sf, cos_r[r], sin_r[r], n, qp,
                q, g, qcol, mu, inv_b2, inv_wsum, *cutoff, &s);
            ssd_out[next] = s;
        }
        return;
    }
    for (l = 0; l < RM_LANES; ++l) {
        L.cand[l] = RM_NONE;
        L.at[l] = 0;
        L.v2[l] = 0;
        L.ready[l] = L.fresh[l] = 0;
        L.shape[l] = L.colour[l] = L.ssd[l] = L.best[l] = 0;
        L.cr[l] = 1;
        L.sr[l] = 0;
        for (k = 0; k < 3; ++k)
            L.sp[k][l] = L.xp[k][l] = L.x[k][l] = 0;
        for (k = 0; k < 9; ++k)
            L.sf[k][l] = 0;
    }
    for (;;) {
        for (round = 0;; ++round) {
            /* Idle lanes take the run's next candidates (next is centre nc,
             * rotation nr: no division but at a block's start). */
            for (l = 0; l < RM_LANES; ++l) {
                RM_UINT si;
                if (L.cand[l] != RM_NONE || next >= c1)
                    continue;
    #ifdef RM_LOWER_CUTOFF
                /* A running query without a cutoff yet scores one candidate at
                 * a time until one is valid: the lanes then start under its
                 * cutoff, as the scalar loop's second candidate does. */
                if (running && *cutoff == FLT_MAX && busy > 0)
                    break;
    #endif
                si = subset ? subset[nc] : nc;
                L.cand[l] = next;
                ++busy;
                L.at[l] = 0;
                L.ready[l] = 0;
                L.shape[l] = L.colour[l] = 0;
                L.cr[l] = cos_r[nr];
                L.sr[l] = sin_r[nr];
                for (k = 0; k < 3; ++k)
                    L.sp[k][l] = s_proj[3 * si + k];
                for (k = 0; k < 9; ++k)
                    L.sf[k][l] = s_frame[9 * si + k];
                ++next;
                if (--left == 0) {
                    next += stride - block;
                    left = block;
                    nc = next / rotations;
                    nr = next % rotations;
                } else if (++nr == rotations) {
                    nr = 0;
                    ++nc;
                }
            }
            if (busy == 0)
                return;
            /* x' = s' + R_s Rz(theta) q' for each lane's neighbour (computed in
             * every lane, used in those not yet ready for the triangles). */
            RM_SIMD
            for (l = 0; l < RM_LANES; ++l) {
                const int i = (int)L.at[l]; /* int indices: the compilers' gathers */
                const float a = L.cr[l] * qp[3 * i] - L.sr[l] * qp[3 * i + 1];
                const float b = L.sr[l] * qp[3 * i] + L.cr[l] * qp[3 * i + 1];
                const float z = qp[3 * i + 2];
                for (k = 0; k < 3; ++k)
                    L.xp[k][l] =
                        L.sp[k][l] + a * L.sf[k][l] + b * L.sf[3 + k][l] + z * L.sf[6 + k][l];
            }
            /* Its closest vertex, as rm_closest_vertex_listed finds it, in
             * lock-step: the lane's cell of the fine grid, its slot in the
             * lists' hash table, then the cell's list; lanes outside every
             * listed cell take the rings one by one. */
            RM_SIMD
            for (l = 0; l < RM_LANES; ++l) {
                const float fx = (L.xp[0][l] - lgrid[0]) / lgrid[3];
                const float fy = (L.xp[1][l] - lgrid[1]) / lgrid[3];
                const float fz = (L.xp[2][l] - lgrid[2]) / lgrid[3];
                const RM_UINT inside = (fx >= 0) & (fx < (float)ldims[0]) & (fy >= 0) &
                                       (fy < (float)ldims[1]) & (fz >= 0) & (fz < (float)ldims[2]);
                /* (converted only when in range: no undefined conversion) */
                const RM_UINT cx = (RM_UINT)(inside ? fx : 0.0f);
                const RM_UINT cy = (RM_UINT)(inside ? fy : 0.0f);
                const RM_UINT cz = (RM_UINT)(inside ? fz : 0.0f);
                L.cell[l] = (cz * ldims[1] + cy) * ldims[0] + cx;
                L.slot[l] = rm_cell_hash(L.cell[l]) & lmask;
                L.find[l] = (L.cand[l] == RM_NONE) | L.ready[l] ? RM_FIND_NONE
                            : inside                             ? RM_FIND_PROBE
                                                                 : RM_FIND_RINGS;
            }
            for (t = 0; t <= lmask; ++t) { /* linear probing, all lanes at once */
                RM_UINT probing = 0;
                RM_SIMD
                for (l = 0; l < RM_LANES; ++l) {
                    const RM_UINT h = L.slot[l], key = lslot[3 * h];
                    const RM_UINT here = (L.find[l] == RM_FIND_PROBE) & (key == L.cell[l]);
                    const RM_UINT count = lslot[3 * h + 2], first = lslot[3 * h + 1];
                    L.lfirst[l] = here ? (count ? first : 0) : L.lfirst[l];
                    L.llast[l] = here ? (count ? count - 1 : 0) : L.llast[l];
                    L.lcount[l] = here ? count : L.lcount[l];
                    const RM_UINT gone = (L.find[l] == RM_FIND_PROBE) & (key == RM_EMPTY);
                    L.find[l] = here ? RM_FIND_LIST : gone ? RM_FIND_RINGS : L.find[l];
                    L.slot[l] = (h + 1) & lmask;
                }
                for (l = 0; l < RM_LANES; ++l)
                    probing |= L.find[l] == RM_FIND_PROBE;
                if (!probing)
                    break;
            }
            maxc = 0;
            for (l = 0; l < RM_LANES; ++l) {
                if (L.find[l] == RM_FIND_PROBE) /* a full table without the cell */
                    L.find[l] = RM_FIND_RINGS;
                if (L.find[l] != RM_FIND_LIST)
                    L.lfirst[l] = L.llast[l] = L.lcount[l] = 0;
                maxc = L.lcount[l] > maxc ? L.lcount[l] : maxc;
                L.nearest[l] = FLT_MAX;
                L.vnew[l] = RM_NONE;
            }
            /* The lists: ascending ids, so the first of equals stays. Shorter
             * lists read their last item again, and ignore it. */
            for (t = 0; t < maxc; ++t) {
                RM_SIMD
                for (l = 0; l < RM_LANES; ++l) {
                    const RM_UINT has = t < L.lcount[l];
                    const int id =
                        (int)litems[(int)L.lfirst[l] + (int)(t < L.llast[l] ? t : L.llast[l])];
                    const float dx = proj[3 * id] - L.xp[0][l], dy = proj[3 * id + 1] - L.xp[1][l];
                    const float dz = proj[3 * id + 2] - L.xp[2][l];
                    const float d2 = dx * dx + dy * dy + dz * dz;
                    const RM_UINT closer = has & (d2 < L.nearest[l]);
                    L.nearest[l] = closer ? d2 : L.nearest[l];
                    L.vnew[l] = closer ? (RM_UINT)id : L.vnew[l];
                }
            }
            /* The rest take the rings; a lane that meets an unmatchable vertex
             * ends. */
            for (l = 0; l < RM_LANES; ++l) {
                RM_UINT v = L.vnew[l];
                L.fresh[l] = 0;
                if (L.find[l] == RM_FIND_NONE)
                    continue;
                if (L.find[l] == RM_FIND_RINGS) {
                    float p[3];
                    p[0] = L.xp[0][l];
                    p[1] = L.xp[1][l];
                    p[2] = L.xp[2][l];
                    v = rm_closest_vertex(p, proj, cell_start, cell_items, grid, dims);
                }
                if (v == RM_NONE || !matchable[v]) {
                    ssd_out[L.cand[l]] = FLT_MAX;
                    flag_out[L.cand[l]] = (RM_UCHAR)RM_INVALID;
                    L.cand[l] = RM_NONE;
                    L.at[l] = 0;
                    L.v2[l] = 0;
                    --busy;
                    continue;
                }
                L.v2[l] = v;
                L.fresh[l] = L.ready[l] = 1;
            }
            if (mu < 1) { /* the colour term, and pruning before the triangles */
                RM_SIMD
                for (l = 0; l < RM_LANES; ++l) {
                    const int i = (int)L.at[l], v = (int)L.v2[l];
                    const float e0 = qcol[3 * i] - col[3 * v];
                    const float e1 = qcol[3 * i + 1] - col[3 * v + 1];
                    const float e2 = qcol[3 * i + 2] - col[3 * v + 2];
                    const float term = (RM_ABSF(e0) + RM_ABSF(e1) + RM_ABSF(e2)) / 3;
                    const float colour = L.colour[l] + g[i] * term;
                    const float ssd = (mu * L.shape[l] * inv_b2 + (1 - mu) * colour) * inv_wsum;
                    L.colour[l] = L.fresh[l] ? colour : L.colour[l];
                    L.ssd[l] = L.fresh[l] ? ssd : L.ssd[l];
                }
                for (l = 0; l < RM_LANES; ++l)
                    if (L.fresh[l] && L.ssd[l] > *cutoff) {
                        ssd_out[L.cand[l]] = L.ssd[l];
                        flag_out[L.cand[l]] = (RM_UCHAR)RM_PRUNED;
                        L.cand[l] = RM_NONE;
                        L.at[l] = 0;
                        L.v2[l] = 0;
                        L.ready[l] = 0;
                        --busy;
                    }
            }
            /* Lanes the colour pruned take new candidates through the steps
             * above before the triangles, a few rounds at most, so that the
             * costly part runs with most lanes busy. */
            if (mu >= 1 || next >= c1 || round == RM_ROUNDS - 1)
                break;
            for (k = 0, l = 0; l < RM_LANES; ++l)
                k += (int)L.ready[l];
            if (4 * k >= 3 * RM_LANES)
                break;
        }

        /* x = s' + R_s Rz(theta) q, and the closest vertex's triangles. */
        RM_SIMD
        for (l = 0; l < RM_LANES; ++l) {
            const int i = (int)L.at[l], v = (int)L.v2[l];
            const float a = L.cr[l] * q[3 * i] - L.sr[l] * q[3 * i + 1];
            const float b = L.sr[l] * q[3 * i] + L.cr[l] * q[3 * i + 1];
            const float z = q[3 * i + 2];
            for (k = 0; k < 3; ++k)
                L.x[k][l] = L.sp[k][l] + a * L.sf[k][l] + b * L.sf[3 + k][l] + z * L.sf[6 + k][l];
            L.tcount[l] = L.ready[l] ? vt_start[v + 1] - vt_start[v] : 0;
            L.tfirst[l] = L.tcount[l] ? vt_start[v] : 0;
            L.tlast[l] = L.tcount[l] ? L.tcount[l] - 1 : 0;
            L.best[l] = FLT_MAX;
        }
        maxc = 0;
        for (l = 0; l < RM_LANES; ++l)
            maxc = L.tcount[l] > maxc ? L.tcount[l] : maxc;
        /* Lanes with fewer triangles read their last one again (vt has
         * one: t < maxc), and ignore it. */
        for (t = 0; t < maxc; ++t) {
            RM_SIMD
            for (l = 0; l < RM_LANES; ++l) {
                const RM_UINT has = t < L.tcount[l];
                const int f = (int)vt[(int)L.tfirst[l] + (int)(t < L.tlast[l] ? t : L.tlast[l])];
                const int ia = 3 * (int)tri[3 * f], ib = 3 * (int)tri[3 * f + 1];
                const int ic = 3 * (int)tri[3 * f + 2];
                const float d2 = rm_point_triangle_d2_flat(
                    L.x[0][l], L.x[1][l], L.x[2][l], pos[ia], pos[ia + 1], pos[ia + 2], pos[ib],
                    pos[ib + 1], pos[ib + 2], pos[ic], pos[ic + 1], pos[ic + 2]);
                L.best[l] = (has & (d2 < L.best[l])) ? d2 : L.best[l];
            }
        }
        RM_SIMD
        for (l = 0; l < RM_LANES; ++l) {
            L.shape[l] += g[L.at[l]] * L.best[l];
            L.ssd[l] = (mu * L.shape[l] * inv_b2 + (1 - mu) * L.colour[l]) * inv_wsum;
        }
        /* Lanes past the cutoff or at their last neighbour end; the others
         * go on to their next neighbour. */
        for (l = 0; l < RM_LANES; ++l) {
            if (!L.ready[l])
                continue;
            L.ready[l] = 0;
            if (L.ssd[l] > *cutoff) {
                flag_out[L.cand[l]] = (RM_UCHAR)RM_PRUNED;
            } else if (++L.at[l] == n) {
                flag_out[L.cand[l]] = (RM_UCHAR)RM_VALID;
#ifdef RM_LOWER_CUTOFF
                if (running)
                    *cutoff = RM_LOWER_CUTOFF(*cutoff, L.ssd[l]);
#endif
            } else {
                continue;
            }
            ssd_out[L.cand[l]] = L.ssd[l];
            L.cand[l] = RM_NONE;
            L.at[l] = 0; /* idle lanes read neighbour 0 of vertex 0 */
            L.v2[l] = 0;
            --busy;
        }
    }
}

#endif /* RM_WITH_SCORING */

#endif
