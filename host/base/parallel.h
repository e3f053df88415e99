/* A range of work shared out over threads, each share contiguous, so that
 * a job that writes only its own rows gives the same result however many
 * threads run it. */
#ifndef RELIEF_HOST_BASE_PARALLEL_H
#define RELIEF_HOST_BASE_PARALLEL_H

#include <stddef.h>

#define RELIEF_PARALLEL_MAX_THREADS 64

/* The CPUs the calling thread may run on: its affinity mask's count
 * (sched_getaffinity, any mask size), which taskset, a container's cpuset
 * or a scheduler's one-core worker narrow; the online processors where the
 * mask cannot be read (not Linux). At least 1. */
int relief_cpus_available(void);

/* Run fn(ctx, lo, hi) over [0, n) cut into min(threads, n) contiguous
 * shares (threads clamped to 1..RELIEF_PARALLEL_MAX_THREADS), the first on
 * the calling thread and each other on a thread of its own, or on the
 * calling thread when none can be started. Returns 0, or 1 when any call
 * returned non-zero. */
int relief_parallel_ranges(size_t n, int threads, int (*fn)(void *ctx, size_t lo, size_t hi),
                           void *ctx);

#endif
