/* Query-to-exemplar distances of the texture optimisation's grid search
 * (host/points/grid_nn.c; its scalar twin is in the same file). One
 * work-item per exemplar; the exemplars lie transposed (dimension d of
 * exemplar e at z[d * stride + e]) so that a work-group's reads of one
 * dimension are side by side, and each work-item runs GN_BLOCK queries at
 * once (each query's sum in dimension order, as gm_dist: the same bits),
 * so that an exemplar's floats are read once per block. */
#define GN_BLOCK 8

__kernel void grid_dist(__global const float *z, int nz, int stride, int dims,
                        __global const float *q, int nq, __global float *out)
{
    const int e = get_global_id(0);
    if (e >= nz)
        return;
    for (int q0 = 0; q0 < nq; q0 += GN_BLOCK) {
        float s[GN_BLOCK];
        const int nb = nq - q0 < GN_BLOCK ? nq - q0 : GN_BLOCK;
        for (int b = 0; b < GN_BLOCK; ++b)
            s[b] = 0.0f;
        for (int d = 0; d < dims; ++d) {
            const float zd = z[d * stride + e];
            for (int b = 0; b < GN_BLOCK; ++b)
                if (b < nb) {
                    const float t = q[(q0 + b) * dims + d] - zd;
                    s[b] += t * t;
                }
        }
        for (int b = 0; b < nb; ++b)
            out[(q0 + b) * nz + e] = s[b];
    }
}
