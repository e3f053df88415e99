/* What a matching backend implements: a table of functions over one
 * opaque context, behind the relief_matcher handle that the front
 * (matcher.h) hands out. Each backend has a creation function in its own
 * header (matcher_scalar.h, matcher_host.h, matcher_opencl.h) and includes
 * this one, never the front, which is what chooses between them. */
#ifndef RELIEF_HOST_MATCH_BACKEND_H
#define RELIEF_HOST_MATCH_BACKEND_H

#include <stdint.h>

#include "relief/relief.h"
#include "match/match_data.h"

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
    int threads;             /* the host threads asked for (0: the default):
                                auto's fallback to the host matcher takes them */
    char device[256];        /* "scalar reference (1 thread)", "host (N
                                threads[, 16 lanes AVX2])" or the OpenCL
                                device [with its lanes] */
    double kernel_seconds;   /* time spent scoring */
    /* Set by relief_matcher_create for auto: when the device fails during
     * a run (out of resources, lost), switch to the host matcher, which
     * reads the host's arrays, and go on from the same target; the reason
     * is then in fallback_note (else ""). */
    int fallback;
    char fallback_note[RELIEF_ERROR_MESSAGE_MAX + 192];
    /* Test hook (NULL: none): called before each score; a failure it
     * returns is taken as the backend's own. */
    relief_status (*inject)(void *ctx, relief_error *err);
    void *inject_ctx;
};

#endif
