/* The scalar backend: the reference every other backend is compared with,
 * and the one-candidate scoring and probes the host pool (score_pool.h)
 * builds on. */
#ifndef RELIEF_HOST_MATCHER_SCALAR_H
#define RELIEF_HOST_MATCHER_SCALAR_H

#include <stddef.h>
#include <stdint.h>

#include "match/backend.h"

/* The scalar reference: plain C, one thread, obviously correct. */
relief_status relief_matcher_scalar_create(const relief_match_data *d, relief_matcher **out,
                                           relief_error *err);

/* The update and rebind of a backend that scores the host's arrays
 * directly (scalar, host): nothing to do. */
relief_status relief_host_arrays_update(void *ctx, const relief_match_data *d, uint32_t v,
                                        relief_error *err);
relief_status relief_host_arrays_rebind(void *ctx, const relief_match_data *d,
                                        relief_error *err);

/* Score one candidate, sample index si (into d->sample) at rotation r,
 * against the query with the given cutoff: rm_score_candidate on the
 * host's arrays. Returns its RM_VALID / RM_PRUNED / RM_INVALID flag. */
int relief_score_host_one(const relief_match_data *d, const relief_match_query *q,
                          uint32_t si, int r, float cutoff, float *ssd);

/* The scalar reference's loop over the query's centres begin .. end - 1
 * (all their rotations, in order) on this thread, each candidate under
 * *cutoff, which a valid score lowers when q->running. */
void relief_score_host_centres(const relief_match_data *d, const relief_match_query *q,
                               uint32_t begin, uint32_t end, float *cutoff, float *ssd,
                               uint8_t *flag);
/* The scalar reference's loop: score the query's candidates in order on
 * this thread, lowering a running cutoff when q->running. */
void relief_score_host(const relief_match_data *d, const relief_match_query *q, float *ssd,
                       uint8_t *flag);
/* The lowest valid SSD among the probes first, first + step, ... of
 * `probes` candidates spread evenly over the query's (probe i: candidate
 * i * ncand / probes), FLT_MAX when none is valid. Each probe is scored
 * with the best so far as its cutoff, so the result is the exact minimum
 * over those probes, however they are split between threads. */
float relief_score_host_probe(const relief_match_data *d, const relief_match_query *q,
                              size_t probes, uint32_t first, uint32_t step);

#endif
