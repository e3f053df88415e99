#include "base/error.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "base/numtext.h"

const char *relief_strerror(relief_status status)
{
    switch (status) {
#define RELIEF_X_CASE(code, value, name, msg, exit_code) \
    case code:                                           \
        return msg;
        RELIEF_STATUS_LIST(RELIEF_X_CASE)
#undef RELIEF_X_CASE
    }
    return "unknown status";
}

const char *relief_status_name(relief_status status)
{
    switch (status) {
#define RELIEF_X_CASE(code, value, name, msg, exit_code) \
    case code:                                           \
        return name;
        RELIEF_STATUS_LIST(RELIEF_X_CASE)
#undef RELIEF_X_CASE
    }
    return "unknown";
}

int relief_status_exit_code(relief_status status)
{
    switch (status) {
#define RELIEF_X_CASE(code, value, name, msg, exit_code) \
    case code:                                           \
        return exit_code;
        RELIEF_STATUS_LIST(RELIEF_X_CASE)
#undef RELIEF_X_CASE
    }
    return 2;
}

const char *relief_reason_name(relief_reason reason)
{
    switch (reason) {
#define RELIEF_X_CASE(code, value, name, desc) \
    case code:                                 \
        return name;
        RELIEF_REASON_LIST(RELIEF_X_CASE)
#undef RELIEF_X_CASE
    }
    return "unknown";
}

/* Status, reason and message; the other fields cleared. */
static relief_status vfail(relief_error *err, relief_status status, relief_reason reason,
                           const char *fmt, va_list ap)
{
    if (err) {
        relief_error_clear(err);
        err->status = status;
        err->reason = reason;
        relief_vsnprintf_c(err->message, sizeof err->message, fmt, ap);
    }
    return status;
}

relief_status relief_fail(relief_error *err, relief_status status,
                          const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vfail(err, status, RELIEF_REASON_NONE, fmt, ap);
    va_end(ap);
    return status;
}

relief_status relief_fail_reason(relief_error *err, relief_status status, relief_reason reason,
                                 const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vfail(err, status, reason, fmt, ap);
    va_end(ap);
    return status;
}

relief_status relief_fail_param(relief_error *err, relief_status status, const char *param,
                                const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vfail(err, status, RELIEF_REASON_PARAMETER, fmt, ap);
    va_end(ap);
    if (err)
        snprintf(err->param, sizeof err->param, "%s", param);
    return status;
}

relief_status relief_errno_status(int e)
{
    switch (e) {
    case ENOSPC:
    case EDQUOT:
    case EFBIG:
    case EIO:
    case EROFS:
    case EMFILE:
    case ENFILE:
        return RELIEF_E_SYSTEM;
    case ENOMEM:
        return RELIEF_E_NOMEM;
    default:
        return RELIEF_E_IO;
    }
}

static relief_reason errno_reason(int e)
{
    switch (e) {
    case ENOSPC:
    case EDQUOT:
    case EFBIG:
        return RELIEF_REASON_NO_SPACE;
    case EROFS:
        return RELIEF_REASON_READ_ONLY;
    case EACCES:
    case EPERM:
        return RELIEF_REASON_NO_PERMISSION;
    default:
        return RELIEF_REASON_NONE;
    }
}

relief_status relief_fail_errno(relief_error *err, int e, const char *path, const char *what)
{
    relief_status st = relief_errno_status(e);
    relief_fail_reason(err, st, errno_reason(e), "%s: %s: %s", path, what, strerror(e));
    if (err)
        err->sys_errno = e;
    return st;
}

void relief_error_clear(relief_error *err)
{
    if (err) {
        err->status = RELIEF_OK;
        err->message[0] = '\0';
        err->reason = RELIEF_REASON_NONE;
        err->sys_errno = 0;
        err->param[0] = '\0';
    }
}

void relief_fail_prefix(relief_error *err, const char *fmt, ...)
{
    char head[RELIEF_ERROR_MESSAGE_MAX / 4], msg[RELIEF_ERROR_MESSAGE_MAX];
    size_t n;
    va_list ap;
    if (!err)
        return;
    va_start(ap, fmt);
    relief_vsnprintf_c(head, sizeof head, fmt, ap);
    va_end(ap);
    memcpy(msg, err->message, sizeof msg);
    msg[sizeof msg - 1] = '\0';
    /* Truncating the message, never the context, when it is too long. */
    n = strlen(head);
    memcpy(err->message, head, n);
    memcpy(err->message + n, ": ", 2);
    n += 2;
    memcpy(err->message + n, msg, strnlen(msg, sizeof err->message - n - 1));
    err->message[n + strnlen(msg, sizeof err->message - n - 1)] = '\0';
}

const char *relief_escape(const char *text, size_t max, char *out, size_t cap)
{
    size_t at = 0, k = 0;
    if (cap == 0)
        return out;
    for (; text[k] && k < max; ++k) {
        unsigned char c = (unsigned char)text[k];
        char piece[5];
        size_t len;
        if (c == '\\')
            len = (size_t)snprintf(piece, sizeof piece, "\\\\");
        else if (c >= 0x20 && c < 0x7f)
            len = (size_t)snprintf(piece, sizeof piece, "%c", c);
        else
            len = (size_t)snprintf(piece, sizeof piece, "\\x%02x", c);
        if (at + len + 4 > cap)
            break;
        memcpy(out + at, piece, len);
        at += len;
    }
    if (text[k] && at + 4 <= cap) {
        memcpy(out + at, "...", 3);
        at += 3;
    }
    out[at] = '\0';
    return out;
}
