#include "base/error.h"

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

relief_status relief_fail(relief_error *err, relief_status status,
                          const char *fmt, ...)
{
    if (err) {
        va_list ap;
        err->status = status;
        va_start(ap, fmt);
        relief_vsnprintf_c(err->message, sizeof err->message, fmt, ap);
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
    return err->status;
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
