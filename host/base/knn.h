/* FLANN set up for exact, deterministic nearest-neighbour search. */
#ifndef RELIEF_HOST_KNN_H
#define RELIEF_HOST_KNN_H

#include <flann/flann.h>

/* A single kd-tree with eps 0 is an exact search and builds without
 * randomness (median splits), so results do not depend on a seed.
 * random_seed stays 0 on purpose: FLANN reseeds the process-wide rand()
 * (srand) on every call when it is > 0, and a library must not touch its
 * caller's global state. Log level none: failures come back as status. */
static inline struct FLANNParameters relief_knn_exact_params(void)
{
    struct FLANNParameters fp = DEFAULT_FLANN_PARAMETERS;
    fp.algorithm = FLANN_INDEX_KDTREE_SINGLE;
    fp.checks = FLANN_CHECKS_UNLIMITED;
    fp.eps = 0.0f;
    fp.cores = 1;
    fp.trees = 1;
    fp.leaf_max_size = 10;
    fp.log_level = FLANN_LOG_NONE;
    fp.random_seed = 0;
    return fp;
}

#endif
