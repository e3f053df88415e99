/* Distances between texture grids (paper 002's exemplar search, issue 21),
 * shared by the host (C11) and the OpenCL kernel grid.cl (OpenCL C 1.2),
 * so that the scalar twin (host/points/grid_nn.c) and the kernel give the
 * same bits.
 *
 * A grid is `dims` floats (n x n nodes x channels, node-major). The
 * distance of query q to exemplar e is the sum over d = 0, 1, ..., dims - 1
 * of (q[d] - e[d])^2 in float, in that order, with - and * and + only and
 * contraction off. The exemplars lie either row-major (e at z + e * dims,
 * stride 1) or transposed (dimension d of e at z[d * stride + e]): the
 * kernel reads them transposed, so that neighbouring work-items read
 * neighbouring floats, and the order of the sum is the same. */
#ifndef GRID_MATH_H
#define GRID_MATH_H

#ifdef __OPENCL_C_VERSION__
#pragma OPENCL FP_CONTRACT OFF /* no fused multiply-add: match the host */
#define GM_FN static inline
#define GM_GLOBAL __global
#else
#define GM_FN static inline
#define GM_GLOBAL
#endif

/* Squared distance of q (dims floats, contiguous) to the exemplar whose
 * dimension d is e[d * step]. */
GM_FN float gm_dist(GM_GLOBAL const float *q, GM_GLOBAL const float *e, int dims, int step)
{
    float s = 0.0f;
    for (int d = 0; d < dims; ++d) {
        const float t = q[d] - e[d * step];
        s += t * t;
    }
    return s;
}

#endif
