/* The k nearest exemplar grids of a batch of query grids (the texture
 * optimisation's M-step, paper 002 section 4), by one of:
 *   - kdtree: FLANN's exact single kd-tree (the default: on a CPU it prunes
 *     most of the exemplars);
 *   - brute, scalar: every exemplar, gm_dist of kernels/grid_math.h, the
 *     queries shared out over threads;
 *   - brute, opencl: the same distances by kernels/grid.cl on an OpenCL
 *     device (a GPU's way), the same bits as the scalar twin.
 * Brute force ranks by (distance, index), so its two backends give the
 * same neighbours; the kd-tree's own float sums may order two grids at a
 * near tie the other way, so kdtree and brute may differ there.
 *
 * Grids are `dims` floats each; the exemplars z (nz x dims, row-major) stay
 * the caller's until destroy. */
#ifndef RELIEF_HOST_POINTS_GRID_NN_H
#define RELIEF_HOST_POINTS_GRID_NN_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"

typedef struct relief_grid_nn relief_grid_nn;

/* A searcher over z. brute's backend: scalar, opencl (on `device`, -1 the
 * first GPU or accelerator, else the first device), or auto (OpenCL on a
 * GPU or accelerator when there is one, else scalar); host is scalar.
 * threads: the scalar twin's and the kd-tree's workers (>= 1). `note`
 * (may be NULL) says what runs, and *why (may be NULL) is
 * RELIEF_REASON_DEVICE_FELL_BACK when auto's OpenCL failed to start (a
 * warning), else RELIEF_REASON_NONE. RELIEF_E_NOMEM; RELIEF_E_DEVICE,
 * RELIEF_E_NOT_BUILT, RELIEF_E_RANGE from OpenCL when asked for by name. */
relief_status relief_grid_nn_create(relief_grid_search search, relief_backend backend,
                                    int device, const float *z, size_t nz, int dims, int threads,
                                    relief_grid_nn **out, char *note, size_t note_size,
                                    relief_reason *why, relief_error *err);

/* For each of nq queries q (nq x dims), its k (1..8, at most nz) nearest
 * exemplars, nearest first: idx[i * k + j]. RELIEF_E_NOMEM, RELIEF_E_DEVICE. */
relief_status relief_grid_nn_query(relief_grid_nn *nn, const float *q, size_t nq, int k,
                                   uint32_t *idx, relief_error *err);

/* "kd-tree", "brute force, scalar", "brute force, OpenCL on <device>". */
const char *relief_grid_nn_name(const relief_grid_nn *nn);

void relief_grid_nn_destroy(relief_grid_nn *nn);

#endif
