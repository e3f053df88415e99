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

/* The first statement of every public entry point: a caller's NULL `err`
 * (which the API allows) becomes one local to the call, so the code below
 * always has an error to fill and decide on. */
#define RELIEF_ENTRY_ERR(err)                                                  \
    relief_error err##_entry_local_;                                           \
    if (!(err)) {                                                              \
        (err) = &err##_entry_local_;                                           \
        relief_error_clear(err);                                               \
    }

/* Record `status` and a printf-formatted message in `err` (may be NULL) and
 * return `status`, so callers can write `return relief_fail(err, ...)`. */
relief_status relief_fail(relief_error *err, relief_status status,
                          const char *fmt, ...) RELIEF_PRINTF(3, 4);

/* relief_fail with a reason (relief_reason) a caller may act on. */
relief_status relief_fail_reason(relief_error *err, relief_status status, relief_reason reason,
                                 const char *fmt, ...) RELIEF_PRINTF(4, 5);

/* relief_fail naming the parameter `param` ("min_window"): err->param,
 * reason RELIEF_REASON_PARAMETER. */
relief_status relief_fail_param(relief_error *err, relief_status status, const char *param,
                                const char *fmt, ...) RELIEF_PRINTF(4, 5);

/* The status of a system failure with errno `e`: RELIEF_E_SYSTEM for what
 * the user cannot mend by naming another path (no space, a quota, a file
 * size limit, an I/O error, a read-only file system, too many open files),
 * RELIEF_E_NOMEM, else RELIEF_E_IO (no such file, no permission, a folder
 * where a file was named). */
relief_status relief_errno_status(int e);

/* Fail with errno `e` on `path` (the user's name, never a temporary's):
 * "PATH: WHAT: <the system's reason>", the status relief_errno_status
 * gives, err->sys_errno = e and the reason (no space, read-only, no
 * permission) where there is one. */
relief_status relief_fail_errno(relief_error *err, int e, const char *path, const char *what);

/* Put a printf-formatted context in front of err's message (err may be
 * NULL: nothing to do): "level 2 of 3: <message>". It returns nothing: a
 * NULL err holds no status to return, so a caller returns the status it
 * already has. */
void relief_fail_prefix(relief_error *err, const char *fmt, ...) RELIEF_PRINTF(2, 3);

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
