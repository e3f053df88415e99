#include "base/error.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

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

relief_status relief_fail(relief_error *err, relief_status status,
                          const char *fmt, ...)
{
    if (err) {
        va_list ap;
        err->status = status;
        va_start(ap, fmt);
        vsnprintf(err->message, sizeof err->message, fmt, ap);
        va_end(ap);
    }
    return status;
}

void relief_error_clear(relief_error *err)
{
    if (err) {
        err->status = RELIEF_OK;
        err->message[0] = '\0';
    }
}

relief_status relief_fail_prefix(relief_error *err, const char *fmt, ...)
{
    char head[RELIEF_ERROR_MESSAGE_MAX / 4], msg[RELIEF_ERROR_MESSAGE_MAX];
    size_t n;
    va_list ap;
    if (!err)
        return RELIEF_E_INTERNAL;
    va_start(ap, fmt);
    vsnprintf(head, sizeof head, fmt, ap);
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
    return err->status;
}
