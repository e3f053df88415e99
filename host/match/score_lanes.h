/* Scoring on the host in lock-step: RELIEF_HOST_LANES candidates side by
 * side through rm_score_range (relief_math.h), as AVX2 code. Built only on
 * x86-64 (RELIEF_HOST_LANES_AVX2 defined), and to be called only where the
 * processor has AVX2 (score_pool.h checks). The scores and flags are the
 * scalar reference's bit for bit (for a running query, those of the
 * candidates it does not prune). */
#ifndef RELIEF_HOST_SCORE_LANES_H
#define RELIEF_HOST_SCORE_LANES_H
#include <stdint.h>

#include "match/match_data.h"

/* Lanes side by side: two AVX2 registers of floats. */
#define RELIEF_HOST_LANES 16
/* A query's centres go out to threads in blocks of this many (a block's
 * candidates: those centres' rotations, consecutive). */
#define RELIEF_HOST_LANE_BLOCK 16

#ifdef RELIEF_HOST_LANES_AVX2
/* Score blocks first, first + step, first + 2 step, ... (first < step) of
 * the query's candidates (block b: centres 16 b to 16 b + 15, all
 * rotations), with a running cutoff of its own that starts from
 * q->cutoff: thread `first` of `step` of a score_pool.h pool. */
void relief_score_host_lanes(const relief_match_data *d, const relief_match_query *q,
                             uint32_t first, uint32_t step, float *ssd, uint8_t *flag);
#endif
#endif
