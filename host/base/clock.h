/* Wall-clock time for stage timings and progress. */
#ifndef RELIEF_HOST_CLOCK_H
#define RELIEF_HOST_CLOCK_H

/* Seconds on a monotonic clock (CLOCK_MONOTONIC): only differences mean
 * anything. */
double relief_seconds(void);

#endif
