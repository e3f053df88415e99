/* Neighbourhood matching: one interface, a scalar reference and an OpenCL
 * backend with identical semantics (DESIGN.md, "Matching backends").
 *
 * The host builds a float copy of the surface once (match_data.h), updates
 * it as targets become textured, and for each target asks the matcher to
 * score every candidate. This is the front the growth calls: it picks the
 * backend (matcher_scalar.h, matcher_host.h, matcher_opencl.h, each behind
 * backend.h's table), falls back from a failed device under auto, and
 * times the scoring. */
#ifndef RELIEF_HOST_MATCHER_H
#define RELIEF_HOST_MATCHER_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"
#include "match/backend.h"
#include "match/match_data.h"

/* The matcher for `backend`: scalar, host or OpenCL (on `device`, -1: the
 * first); the host's scoring on `threads` (relief_run_options.threads: 0
 * the default, at most RELIEF_SCORE_POOL_MAX), scalar on one. For auto:
 * OpenCL on `device` when one is named (>= 0), else on the first GPU or
 * accelerator; the host matcher when there is none, or when that device
 * cannot run, or, without asking OpenCL, when `work` (the candidate scores
 * the growth is expected to ask; 0: not known) is under
 * RELIEF_MATCHER_DEVICE_MIN_WORK per host thread; which one and why is
 * written to `note` (may be NULL),
 * and *why (may be NULL) is RELIEF_REASON_DEVICE_FELL_BACK when OpenCL
 * could not be used (no platform, or the device failed to start): a
 * warning, where the others (RELIEF_REASON_NONE) are a plain choice. OpenCL is refused
 * (RELIEF_E_NOMEM, naming the need and the device's memory) when the
 * surface does not fit on the device (device_memory.h). Under auto and
 * opencl alike, a bad RELIEF_OPENCL_HOST_MAX or a --device there is none
 * of is refused (RELIEF_E_RANGE). */
#define RELIEF_MATCHER_UNAVAILABLE "OpenCL unavailable"
relief_status relief_matcher_create(relief_backend backend, int device, int threads,
                                    double work, const relief_match_data *d,
                                    relief_matcher **out, char *note, size_t note_size,
                                    relief_reason *why, relief_error *err);

/* Candidate scores per host thread below which auto does not ask OpenCL
 * for a device (matcher.c says why). */
#define RELIEF_MATCHER_DEVICE_MIN_WORK 1e6

/* Score through the matcher, timing it. */
relief_status relief_matcher_score(relief_matcher *m, const relief_match_data *d,
                                   const relief_match_query *q, float *ssd, uint8_t *flag,
                                   relief_error *err);
relief_status relief_matcher_update(relief_matcher *m, const relief_match_data *d, uint32_t v,
                                    relief_error *err);
/* Score against another surface d from now on, keeping the backend's
 * set-up (for OpenCL the context and the built program): the levels of a
 * hierarchy. The surface is checked against the device's memory again;
 * under auto a device that cannot take it falls back to the host matcher
 * (fallback_note says why). */
relief_status relief_matcher_rebind(relief_matcher *m, const relief_match_data *d,
                                    relief_error *err);
void relief_matcher_destroy(relief_matcher *m);

#endif
