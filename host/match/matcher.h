/* Neighbourhood matching: one interface, a scalar reference and an OpenCL
 * backend with identical semantics (DESIGN.md, "Matching backends").
 *
 * The host builds a float copy of the surface once (relief_match_data),
 * updates it as targets become textured, and for each target asks the
 * matcher to score every candidate (sample s, rotation r): candidate index
 * c = s * R + r, over the samples in relief_match_data.sample order, or
 * over a subset of them (the hierarchy's sample pyramids): c = i * R + r for
 * the i-th sample of relief_match_query.subset. */
#ifndef RELIEF_HOST_MATCHER_H
#define RELIEF_HOST_MATCHER_H

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
    uint32_t *sample;     /* ns vertex ids of the samples */
    float *s_proj;        /* ns x 3 s' */
    float *s_frame;       /* ns x 9 R_s as rows u, v, n */
    int rotations;        /* R */
    float *cos_r, *sin_r; /* R: cos and sin of 2 pi r / R */
    float mu;             /* shape weight */
    float inv_b2;         /* 1 / B_shape^2 */
    double b_shape;       /* the shape bound B_shape (input units) */
} relief_match_data;

/* Build the match data of a surface: R rotations, shape weight mu.
 * B_shape (paper 000 section 6) is read here as the range of the samples'
 * signed displacement along the normal, max(D.n) - min(D.n): the largest
 * difference between two samples' displacements, on either side of the
 * fit; a flat capture (range 0) uses the target spacing instead. */
relief_status relief_match_data_build(const relief_surface *s, int rotations, double mu,
                                      relief_match_data **out, relief_error *err);
void relief_match_data_destroy(relief_match_data *d);

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

/* Per-candidate results: flag RM_VALID, RM_INVALID or RM_PRUNED (see
 * relief_math.h) and the SSD (valid) or partial SSD (pruned). */
typedef struct relief_matcher relief_matcher;

typedef struct relief_matcher_ops {
    const char *name;
    /* Score the query's candidates (relief_match_query_candidates) into
     * ssd[] and flag[]. */
    relief_status (*score)(void *ctx, const relief_match_data *d, const relief_match_query *q,
                           float *ssd, uint8_t *flag, relief_error *err);
    /* Vertex v's position, colour or matchable flag changed in d. */
    relief_status (*update)(void *ctx, const relief_match_data *d, uint32_t v,
                            relief_error *err);
    /* From now on score against d, another surface (the next level of a
     * hierarchy); what does not depend on the surface is kept. */
    relief_status (*rebind)(void *ctx, const relief_match_data *d, relief_error *err);
    void (*destroy)(void *ctx);
} relief_matcher_ops;

struct relief_matcher {
    const relief_matcher_ops *ops;
    void *ctx;
    relief_backend backend;  /* the one actually used */
    int device_index;        /* the OpenCL device asked for (-1: first) */
    char device[256];        /* "scalar (1 thread)" or the OpenCL device */
    double kernel_seconds;   /* time spent scoring */
    /* Set by relief_matcher_create for auto: when the device fails during
     * a run (out of resources, lost), switch to the scalar reference, which
     * reads the host's arrays, and go on from the same target; the reason
     * is then in fallback_note (else ""). */
    int fallback;
    char fallback_note[RELIEF_ERROR_MESSAGE_MAX + 128];
    /* Test hook (NULL: none): called before each score; a failure it
     * returns is taken as the backend's own. */
    relief_status (*inject)(void *ctx, relief_error *err);
    void *inject_ctx;
};

/* The scalar reference: plain C, one thread, obviously correct. */
relief_status relief_matcher_scalar_create(const relief_match_data *d, relief_matcher **out,
                                           relief_error *err);

/* The scalar reference's loop: score the query's candidates in order on
 * this thread, lowering a running cutoff when q->running. The OpenCL
 * matcher also runs it for launches too small to pay for themselves. */
void relief_score_host(const relief_match_data *d, const relief_match_query *q, float *ssd,
                       uint8_t *flag);

/* The same loop over the query's centres first, first + step, ... only
 * (their candidates' entries of ssd[] and flag[]), with a running cutoff
 * of its own starting from q->cutoff: what each of the step threads of a
 * score_pool.h pool runs. */
void relief_score_host_strided(const relief_match_data *d, const relief_match_query *q,
                               uint32_t first, uint32_t step, float *ssd, uint8_t *flag);

/* The lowest valid SSD among the probes first, first + step, ... of
 * `probes` candidates spread evenly over the query's (probe i: candidate
 * i * ncand / probes), FLT_MAX when none is valid. Each probe is scored
 * with the best so far as its cutoff, so the result is the exact minimum
 * over those probes, however they are split between threads. */
float relief_score_host_probe(const relief_match_data *d, const relief_match_query *q,
                              size_t probes, uint32_t first, uint32_t step);

/* The OpenCL matcher sends a running query's launch in chunks: the first
 * of RELIEF_OPENCL_CHUNK_FIRST candidates, each next one twice the last,
 * each pruning under just over 1.1 x the minimum of everything scored
 * before it. With only the probes' bound, a launch of 226 000 candidates
 * (a 32 000-vertex bark) took 0.102 s per target against 0.066 s so;
 * below 16384 a second launch cost more than it saved (the bands'
 * mono-scale run, launches of 14 484: 6.88 s in one, 7.09 s in two of
 * 8192 and 6292). Here so that the tests can place candidates past the
 * first chunk. */
#define RELIEF_OPENCL_CHUNK_FIRST 16384

/* The OpenCL matcher on device `device` (relief_devices order; -1: the
 * first). RELIEF_E_DEVICE naming the reason (no platform, the build log of
 * a failed kernel build, out of device memory); RELIEF_E_NOT_BUILT in a
 * build without OpenCL. */
relief_status relief_matcher_opencl_create(const relief_match_data *d, int device,
                                           relief_matcher **out, relief_error *err);

/* The matcher for `backend`: scalar, OpenCL, or for auto OpenCL when it can
 * run, else scalar with the reason written to `note` (may be NULL). OpenCL
 * is refused (RELIEF_E_NOMEM, naming the need and the device's memory) when
 * the surface does not fit on the device (device_memory.h). */
relief_status relief_matcher_create(relief_backend backend, int device,
                                    const relief_match_data *d, relief_matcher **out,
                                    char *note, size_t note_size, relief_error *err);

/* Score through the matcher, timing it. */
relief_status relief_matcher_score(relief_matcher *m, const relief_match_data *d,
                                   const relief_match_query *q, float *ssd, uint8_t *flag,
                                   relief_error *err);
relief_status relief_matcher_update(relief_matcher *m, const relief_match_data *d, uint32_t v,
                                    relief_error *err);
/* Score against another surface d from now on, keeping the backend's
 * set-up (for OpenCL the context and the built program): the levels of a
 * hierarchy. The surface is checked against the device's memory again;
 * under auto a device that cannot take it falls back to the scalar
 * reference (fallback_note says why). */
relief_status relief_matcher_rebind(relief_matcher *m, const relief_match_data *d,
                                    relief_error *err);
void relief_matcher_destroy(relief_matcher *m);

#endif
