/* The patch voting's OpenCL device (issue 62): kernels/vote.cl runs
 * kernels/vote_math.h's per-target search and per-pixel vote over every
 * target or hole pixel of a level at once, as the host's threads run
 * them (vote_fill.c): the same bytes. A level is sent once; within it
 * only the distances travel back after each search (the vote's weights
 * are the host's) and the weights forward; the field and, at full
 * resolution, the pixels come back at the level's end.
 *
 * Without OpenCL (RELIEF_HAVE_OPENCL unset) relief_vote_cl_create answers
 * RELIEF_E_NOT_BUILT and nothing else is called. */
#ifndef RELIEF_HOST_IMAGE_VOTE_CL_H
#define RELIEF_HOST_IMAGE_VOTE_CL_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"
#include "kernels/vote_math.h"

typedef struct relief_vote_cl relief_vote_cl;

/* The device numbered as relief_devices numbers them (-1: the first GPU or
 * accelerator, else the first). RELIEF_E_NOT_BUILT, RELIEF_E_DEVICE,
 * RELIEF_E_RANGE as relief_patch_opencl_create. */
relief_status relief_vote_cl_create(int device, relief_vote_cl **out, relief_error *err);
void relief_vote_cl_destroy(relief_vote_cl *d);
/* Its name, for reports. */
const char *relief_vote_cl_name(const relief_vote_cl *d);

/* Send a level: its samples v (h x w x C), hole (h x w: 1 thick, 2 thin),
 * the targets' tmap (bw x bh) and list tgt (nt), and the field nnf (nt). */
relief_status relief_vote_cl_level(relief_vote_cl *d, const vm_level *L, const uint16_t *v,
                                   const uint8_t *hole, const int32_t *tmap,
                                   const uint32_t *tgt, size_t nt, const uint32_t *nnf,
                                   relief_error *err);
/* Every target's distance to its source, then one PatchMatch iteration
 * (vm_pm_target), then the distances read back into dist (nt). */
relief_status relief_vote_cl_dist(relief_vote_cl *d, relief_error *err);
relief_status relief_vote_cl_pm(relief_vote_cl *d, uint32_t seed, int level, int step,
                                int jump, relief_error *err);
relief_status relief_vote_cl_read_dist(relief_vote_cl *d, uint64_t *dist, relief_error *err);
/* Every hole pixel's vote (vm_vote_pixel) with the weights wt (nt). */
relief_status relief_vote_cl_vote(relief_vote_cl *d, const uint32_t *wt, int best,
                                  relief_error *err);
/* The level's field into nnf (nt), its samples into v unless NULL, and
 * the distances its searches evaluated added to *distances. */
relief_status relief_vote_cl_read(relief_vote_cl *d, uint32_t *nnf, uint16_t *v,
                                  uint64_t *distances, relief_error *err);

#endif
