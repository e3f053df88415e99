/* What the API tests share: they see relief as a user does, through the
 * public headers (<relief/...>) and the shared library, nothing of host/.
 * CHECK(cond, fmt, ...) counts a failure with its line; API_TEST_END
 * returns the exit status (0 all passed, 1 some failed). */
#ifndef RELIEF_TESTS_API_TEST_H
#define RELIEF_TESTS_API_TEST_H

#include <locale.h>
#include <stdio.h>
#include <stdlib.h>
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

/* Are the numbers of a JSON document (or of `relief eval`'s text) written
 * with '.'? Outside its strings a comma only separates ("1, 2", ",\n"), so a
 * comma between two digits there is a decimal comma. */
static inline int api_json_numbers_use_dots(const char *text)
{
    int in_string = 0;
    for (const char *s = text; *s; ++s) {
        if (in_string && *s == '\\' && s[1])
            ++s;
        else if (*s == '"')
            in_string = !in_string;
        else if (!in_string && *s == ',' && s > text && s[-1] >= '0' && s[-1] <= '9' &&
                 s[1] >= '0' && s[1] <= '9')
            return 0;
    }
    return 1;
}

/* Under tests/comma_locale.sh (RELIEF_TEST_LOCALE set), the whole test runs
 * in that comma-decimal locale, as a GTK host or Python after setlocale may
 * call relief (issue 60); relief must read and write "0.5" all the same. 0
 * when the locale is asked for but cannot be had or does not write "0,5"
 * (the test would then prove nothing). Call it first in main. */
static inline int api_test_locale(void)
{
    const char *name = getenv("RELIEF_TEST_LOCALE");
    char half[16];
    if (!name || !name[0])
        return 1;
    if (!setlocale(LC_ALL, name)) {
        fprintf(stderr, "cannot set the locale %s (LOCPATH %s)\n", name,
                getenv("LOCPATH") ? getenv("LOCPATH") : "unset");
        return 0;
    }
    snprintf(half, sizeof half, "%.1f", 0.5);
    if (strcmp(half, "0,5") != 0) {
        fprintf(stderr, "the locale %s writes a half as %s, not 0,5\n", name, half);
        return 0;
    }
    printf("in the locale %s, where a half is written 0,5\n", name);
    return 1;
}

#define API_TEST_END()                                                       \
    do {                                                                     \
        if (api_failures)                                                    \
            fprintf(stderr, "%d check(s) failed\n", api_failures);           \
        else                                                                 \
            printf("all checks passed\n");                                   \
        return api_failures ? 1 : 0;                                         \
    } while (0)

#endif
