/* Internal helpers to fill a relief_error. */
#ifndef RELIEF_HOST_ERROR_H
#define RELIEF_HOST_ERROR_H

#include "relief/relief.h"

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__GNUC__)
#define RELIEF_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define RELIEF_PRINTF(a, b)
#endif

/* Record `status` and a printf-formatted message in `err` (may be NULL) and
 * return `status`, so callers can write `return relief_fail(err, ...)`. */
relief_status relief_fail(relief_error *err, relief_status status,
                          const char *fmt, ...) RELIEF_PRINTF(3, 4);

/* Put a printf-formatted context in front of err's message (err may be
 * NULL) and return its status: "level 2 of 3: <message>". */
relief_status relief_fail_prefix(relief_error *err, const char *fmt, ...) RELIEF_PRINTF(2, 3);

/* Clear `err` to RELIEF_OK with an empty message (NULL accepted). */
void relief_error_clear(relief_error *err);

#ifdef __cplusplus
}
#endif

#endif
