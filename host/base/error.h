/* Internal helpers to fill a relief_error. */
#ifndef RELIEF_HOST_ERROR_H
#define RELIEF_HOST_ERROR_H

#include <stddef.h>

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

/* The bytes of `text` (up to a NUL) as a message may quote them from a
 * file: printable ASCII kept (a backslash doubled), every other byte as
 * \xNN, at most `max` bytes of it shown, then "..." when it went on. `out`
 * (cap bytes, 4 * max + 4 is always enough) is returned, so that a call
 * can be an argument of relief_fail: a garbled header never prints raw
 * bytes on a terminal. */
#define RELIEF_ESCAPE_MAX 32
const char *relief_escape(const char *text, size_t max, char *out, size_t cap);

/* Clear `err` to RELIEF_OK with an empty message (NULL accepted). */
void relief_error_clear(relief_error *err);

#ifdef __cplusplus
}
#endif

#endif
