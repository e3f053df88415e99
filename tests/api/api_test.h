/* What the API tests share: they see relief as a user does, through the
 * public headers (<relief/...>) and the shared library, nothing of host/.
 * CHECK(cond, fmt, ...) counts a failure with its line; API_TEST_END
 * returns the exit status (0 all passed, 1 some failed). */
#ifndef RELIEF_TESTS_API_TEST_H
#define RELIEF_TESTS_API_TEST_H

#include <stdio.h>
#include <string.h>

#include <relief/relief.h>

static int api_failures = 0;

/* Does `message` hold `needle` (NULL: any non-empty message)? */
static inline int api_names(const char *message, const char *needle)
{
    return message[0] && (!needle || strstr(message, needle));
}

#define CHECK(cond, ...)                                                     \
    do {                                                                     \
        if (!(cond)) {                                                       \
            fprintf(stderr, "%s:%d: FAIL: ", __FILE__, __LINE__);            \
            fprintf(stderr, __VA_ARGS__);                                    \
            fputc('\n', stderr);                                             \
            ++api_failures;                                                  \
        }                                                                    \
    } while (0)

/* A call's status must be `want`, and the message in `err` (a relief_error)
 * must hold `needle` (NULL: any message, but one there is). */
#define CHECK_STATUS(st, want, err, needle)                                  \
    do {                                                                     \
        relief_status st_ = (st);                                            \
        CHECK(st_ == (want), "status %s, expected %s (%s)",                  \
              relief_status_name(st_), relief_status_name(want),             \
              (err).message);                                                \
        if ((want) != RELIEF_OK)                                             \
            CHECK(api_names((err).message, (needle)),                        \
                  "message '%s' does not name '%s'", (err).message,          \
                  (needle) ? (needle) : "anything");                         \
    } while (0)

#define API_TEST_END()                                                       \
    do {                                                                     \
        if (api_failures)                                                    \
            fprintf(stderr, "%d check(s) failed\n", api_failures);           \
        else                                                                 \
            printf("all checks passed\n");                                   \
        return api_failures ? 1 : 0;                                         \
    } while (0)

#endif
