/* Texture completion on a point set by global optimisation over
 * overlapping clusters (paper 002, sections 3.2 to 4; Kwatra et al. 2005's
 * texture optimisation carried to irregular points).
 *
 * A "texture" is `channels` floats per point: a colour (3 channels in
 * [0, 1]) or the signed detail c' of the geometry (1 channel, a length in
 * the points' unit). The points are clustered into about uniform clusters
 * (a binary space partition to about cluster_size points, evened out, then
 * grown so that neighbouring clusters overlap by a band of 0.5 d, d the mean
 * cluster radius). Each cluster gets a frame from a smooth direction field
 * over the clusters and its normal, and an n x n grid G_i of spacing h on
 * its tangent plane, the texture resampled on it. Exemplar neighbourhoods
 * Z are the same grids centred at exemplar points. The energy
 *   E = sum_i ||G_i - Z_i||^2 + lambda sum_{k in rim} (x(k) - x_c(k))^2
 * is minimised by alternating an exact nearest-neighbour search of each
 * G_i among the Z (FLANN, kd-tree, exact) and averaging the matched Z back
 * onto the points (each point reads a match at its place, averaged where
 * clusters overlap), until E changes by less than tol relatively or
 * max_iter. Only the unknown points' values change; the known ones are the
 * constraint. As computed (texopt.c), ||G_i - Z_i||^2 is taken at the
 * cluster's points (Z_i read at each member from the exemplar points about
 * its place, not interpolated from the grid's nodes, which would blur) and
 * the rim points, being known, enter with weight 1 + lambda, so that
 * neither step can raise E. Unknown values start grown inward from the
 * known part (texopt.c); at most 20 000 exemplar grids are searched (a
 * seeded subset beyond).
 * Deterministic for a given seed, whatever the number of threads. */
#ifndef RELIEF_HOST_POINTS_TEXOPT_H
#define RELIEF_HOST_POINTS_TEXOPT_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"
#include "base/progress.h"

typedef struct relief_texopt_params {
    int grid_n;          /* grid side n, odd, 3..33 (default 23: with the default step and
                            cluster size the nodes are about 0.9 spacings apart, so
                            resampling keeps the detail; 1.5 spacings apart it lost a
                            quarter of it) */
    int cluster_size;    /* points per cluster before overlap, 16..100000 (default 300,
                            about 680 once overlapped; the paper's ~300 overlapped,
                            133 before, was measured worse: texopt.c) */
    double overlap;      /* overlap band over the mean cluster radius, 0..2 (default 0.5) */
    double grid_step;    /* grid spacing h in the points' unit (default 0: the mean
                            cluster radius x 2 / grid_n, so a grid spans a cluster) */
    int max_iter;        /* 1..1000 (default 50, the paper's figure) */
    double tol;          /* relative change of E that stops it (default 1e-4) */
    double lambda;       /* weight of the rim term (default 1) */
    uint64_t seed;       /* the subset of exemplar grids searched when there are more
                            than 20 000 (default 1) */
    int threads;         /* worker threads, 0 = the CPUs this thread may run on
                            (its affinity; default 0) */
    unsigned histogram;  /* bit c set: channel c's unknown values end histogram-matched
                            to the exemplars' about them (those in the clusters
                            that hold unknown points; all exemplars when fewer than
                            64 are; texopt.c; default 0) */
    int brute;           /* 1: the M-step's nearest grids by brute force (grid_nn.h) on
                            `backend` and `device`; 0 (default): FLANN's exact kd-tree */
    relief_backend backend; /* brute's: scalar, opencl, auto (default: OpenCL on a GPU) */
    int device;          /* OpenCL device index, -1 the first GPU (default -1) */
    relief_progress *progress; /* NULL (default), or the caller's, in the stage it set:
                                  the start takes its first 15 %, the iterations the
                                  rest; a cancel stops at the next cluster of the start
                                  or the next iteration (RELIEF_E_CANCELLED) */
} relief_texopt_params;

relief_texopt_params relief_texopt_params_default(void);

typedef struct relief_texopt_result {
    size_t clusters;          /* clusters made */
    size_t active_clusters;   /* those holding an unknown point */
    size_t exemplars;         /* exemplar grids searched */
    int iterations;           /* iterations run */
    double *energy;           /* energy per iteration (iterations entries), malloc'ed */
    int converged;            /* 1 when tol stopped it */
    char search[336];         /* the grid search that ran, and any warning (grid_nn.h) */
    relief_reason search_reason; /* RELIEF_REASON_DEVICE_FELL_BACK: the warning */
    int grid_n, cluster_size; /* what ran: smaller than asked when no exemplar grid could be
                                 built at the size asked (halved clusters, grids 1/sqrt 2 the
                                 side, the same step, down to 7) */
} relief_texopt_result;

void relief_texopt_result_free(relief_texopt_result *r);

/* Complete value (n x channels) where unknown[i] != 0, from exemplar
 * neighbourhoods centred at points with exemplar[i] != 0 (which must be
 * known). pos, nrm: n x 3 positions and unit normals (consistently
 * oriented). rim (may be NULL): known points whose value is also a soft
 * constraint of the rim term (the paper's phi). channels 1..4.
 * RELIEF_E_RANGE when a parameter is out of range, nothing is unknown or
 * no exemplar grid can be built (naming which); RELIEF_E_NOMEM;
 * RELIEF_E_CANCELLED (p->progress). On failure
 * value and res are unchanged. p NULL: the defaults; res may be NULL. */
relief_status relief_texopt_complete(const double *pos, const double *nrm, size_t n,
                                     int channels, float *value, const uint8_t *unknown,
                                     const uint8_t *exemplar, const uint8_t *rim,
                                     const relief_texopt_params *p,
                                     relief_texopt_result *res, relief_error *err);

#endif
