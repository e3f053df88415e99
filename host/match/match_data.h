/* What every matcher reads: the surface as float arrays (relief_match_data)
 * and one target's query (relief_match_query). For each target the
 * matcher scores every candidate (sample s, rotation r): candidate index
 * c = s * R + r, over the samples in relief_match_data.sample order, or
 * over a subset of them (the hierarchy's sample pyramids): c = i * R + r for
 * the i-th sample of relief_match_query.subset. */
#ifndef RELIEF_HOST_MATCH_DATA_H
#define RELIEF_HOST_MATCH_DATA_H

#include <float.h>
#include <math.h>
#include <stdint.h>

#include "relief/relief.h"
#include "smooth/surface.h"

/* The surface as the matcher reads it; the layouts are those documented in
 * kernels/relief_math.h. Owned by the host; backends keep their own copies
 * (device buffers) in step through relief_matcher_update. */
typedef struct relief_match_data {
    uint32_t nv, nt, ns;  /* vertices, triangles, samples (candidate centres) */
    float *proj;          /* nv x 3 projected positions v' */
    float *pos;           /* nv x 3 real positions v */
    float *col;           /* nv x 3 colours in [0, 1]; grey when uncoloured */
    uint8_t *matchable;   /* nv */
    uint32_t *tri;        /* nt x 3 */
    uint32_t *vt_start;   /* nv + 1 */
    uint32_t *vt;         /* vt_start[nv] incident triangle ids */
    float grid[4];        /* grid origin x, y, z and cell size */
    uint32_t dims[3];     /* cells per axis */
    uint32_t *cell_start; /* dims[0] * dims[1] * dims[2] + 1 */
    uint32_t *cell_items; /* nv vertex ids by cell, then id */
    /* Closest-vertex lists (relief_math.h, rm_closest_vertex_listed): a
     * sparse grid finer than the one above, cells of size lgrid[3] from the
     * origin lgrid[0..2], ldims[0..2] cells per axis; a hash table of
     * lmask + 1 slots (a power of two), 3 values per slot: cell id or
     * RM_EMPTY, offset and count into litems; each listed cell's items are
     * every vertex that can be the closest to a point of the cell, in
     * ascending id. Cells without a list use the grid above. */
    float lgrid[4];
    uint32_t ldims[3];
    uint32_t lmask;
    uint32_t *lslot;      /* (lmask + 1) x 3 */
    uint32_t *litems;     /* n_litems vertex ids */
    size_t n_litems;
    uint32_t *sample;     /* ns vertex ids of the samples, ascending */
    uint32_t *sample_of;  /* nv: vertex v's index into sample, or UINT32_MAX
                             (a target, or a sample left out of the pool);
                             NULL while every sample is a centre
                             (sample[i] == i): relief_match_sample_of */
    float *s_proj;        /* ns x 3 s' */
    float *s_frame;       /* ns x 9 R_s as rows u, v, n */
    int rotations;        /* R */
    float *cos_r, *sin_r; /* R: cos and sin of 2 pi r / R */
    float mu;             /* shape weight */
    float inv_b2;         /* 1 / B_shape^2 */
    double b_shape;       /* the shape bound B_shape (input units) */
} relief_match_data;

/* Build the match data of a surface: R rotations (1..64, or 0 for
 * relief_params_rotations' default on s's primitive), shape weight mu.
 * B_shape (paper 000 section 6) is read here as the range of the samples'
 * signed displacement along the normal, max(D.n) - min(D.n): the largest
 * difference between two samples' displacements, on either side of the
 * fit; a flat capture (range 0) uses the target spacing instead. */
relief_status relief_match_data_build(const relief_surface *s, int rotations, double mu,
                                      relief_match_data **out, relief_error *err);
void relief_match_data_destroy(relief_match_data *d);

/* relief_match_data_build for a told hole: the candidate centres are only
 * the n_keep samples nearest the targets in edge hops over the surface (a
 * breadth-first search from every target at once, ties in the order
 * found), in ascending vertex order, and the closest-vertex lists cover
 * only the vertices within `margin` hops more (elsewhere the rings answer
 * the same). Every sample stays matchable: a neighbour may land on it. The
 * hole is matched against the capture around it, and its search costs
 * what the hole does, not the capture (issue 61). Every sample is a centre
 * when n_keep >= ns, or when the search reaches fewer (a hole on a piece
 * of its own). The closest-vertex lists are built on `threads` host
 * threads (0: the default, relief_pool_threads_for), the same bytes for
 * any count; relief_match_data_build builds them on one. */
relief_status relief_match_data_build_near(const relief_surface *s, int rotations, double mu,
                                           size_t n_keep, int margin, int threads,
                                           relief_match_data **out, relief_error *err);

/* The pool of relief_match_data_build_near, on d's samples: compacts them
 * and sets *near (nv flags, the caller's to free; NULL when every sample
 * stays a centre). */
relief_status relief_match_pool(relief_match_data *d, size_t n_keep, int margin,
                                uint8_t **near, relief_error *err);

/* The sample index of vertex v, or UINT32_MAX when v is no candidate
 * centre. */
static inline uint32_t relief_match_sample_of(const relief_match_data *d, uint32_t v)
{
    if (!d->sample_of)
        return v < d->ns ? v : UINT32_MAX;
    return v < d->nv ? d->sample_of[v] : UINT32_MAX;
}

/* One target's textured neighbourhood, transformed into its frame. */
typedef struct relief_match_query {
    uint32_t n;        /* neighbours */
    const float *qp;   /* n x 3 projected offsets R_t^T (v' - t) */
    const float *q;    /* n x 3 real offsets R_t^T (v - t) */
    const float *g;    /* n Gaussian weights */
    const float *qcol; /* n x 3 colours */
    float inv_wsum;    /* 1 / sum of g */
    float cutoff;      /* prune a candidate once its partial SSD exceeds
                          this (FLT_MAX: never) */
    int running;       /* 1: the backend may lower the cutoff to just above
                          1.1 x the best SSD found so far, which never drops
                          a member of the best set */
    const uint32_t *subset; /* NULL: every sample is a candidate centre;
                               else n_subset distinct indices into
                               d->sample (any order), and the candidates are those samples'
                               rotations */
    uint32_t n_subset;
} relief_match_query;

/* The cutoff a running query may drop to once a candidate scores `ssd`
 * (valid): just above 1.1 x ssd, so no member of the best set (SSD at
 * most 1.1 x the final minimum, itself at most ssd) is ever pruned. */
static inline float relief_match_cutoff_after(float ssd)
{
    return nextafterf((float)(1.1 * (double)ssd), FLT_MAX);
}

/* Candidates the query asks for: ns x R, or n_subset x R. */
size_t relief_match_query_candidates(const relief_match_data *d, const relief_match_query *q);

/* The sample index (into d->sample) of the i-th candidate centre. */
static inline uint32_t relief_match_query_sample(const relief_match_query *q, uint32_t i)
{
    return q->subset ? q->subset[i] : i;
}

#endif
