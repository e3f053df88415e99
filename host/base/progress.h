/* An engine's progress, passed on to the caller's relief_progress_fn
 * (relief/relief.h): the call's stages take consecutive shares of [0, 1],
 * the fraction reported never decreases, and once the callback answers
 * non-zero the call is cancelled for good (every later step says so), so
 * that the engine can stop at its next step and return RELIEF_E_CANCELLED
 * with the caller's outputs untouched. */
#ifndef RELIEF_HOST_BASE_PROGRESS_H
#define RELIEF_HOST_BASE_PROGRESS_H

#include "relief/relief.h"

typedef struct relief_progress {
    relief_progress_fn fn; /* NULL: nothing is reported, nothing cancels */
    void *ctx;
    double lo, hi;         /* the current stage's share of the call */
    double last;           /* the last fraction reported */
    int cancelled;         /* 1 once the callback asked */
} relief_progress;

/* Start at 0 with one stage covering [0, 1]. */
void relief_progress_init(relief_progress *p, relief_progress_fn fn, void *ctx);

/* The next stage takes [lo, hi] of the call (0 <= lo <= hi <= 1). */
void relief_progress_stage(relief_progress *p, double lo, double hi);

/* `done` (0..1) of the current stage is done: report it (the call's
 * fraction is lo + done x (hi - lo), never below the last one). Returns 1
 * when the call is cancelled (now or earlier), else 0. NULL p: 0. */
int relief_progress_step(relief_progress *p, double done);

/* The same with a count: done of total (total 0: the stage is done). */
int relief_progress_count(relief_progress *p, size_t done, size_t total);

#endif
