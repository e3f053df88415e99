/* The host backend: the scalar reference's scoring function on every core
 * of the host (score_pool.h), one query's candidates split between the
 * threads. It gives the scalar reference's best sets, hence its bytes; it
 * is what --backend auto runs on a machine whose only OpenCL device is its
 * own CPU, where the kernel would run on the very same cores. */
#ifndef RELIEF_HOST_MATCHER_HOST_H
#define RELIEF_HOST_MATCHER_HOST_H

#include "match/backend.h"

/* A host matcher on `threads` threads (1..RELIEF_SCORE_POOL_MAX; 0: the
 * online processors, relief_score_pool_default_threads). */
relief_status relief_matcher_host_create(const relief_match_data *d, int threads,
                                         relief_matcher **out, relief_error *err);

#endif
