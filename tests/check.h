/* Minimal test harness: CHECK records a failure and goes on, so one run
 * reports every broken case; main returns check_result(). */
#ifndef RELIEF_TESTS_CHECK_H
#define RELIEF_TESTS_CHECK_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

static int check_failures = 0;
static int check_count = 0;

#define CHECK(cond, ...)                                                  \
    do {                                                                  \
        ++check_count;                                                    \
        if (!(cond)) {                                                    \
            ++check_failures;                                             \
            fprintf(stderr, "%s:%d: CHECK failed: %s: ", __FILE__,        \
                    __LINE__, #cond);                                     \
            fprintf(stderr, __VA_ARGS__);                                 \
            fputc('\n', stderr);                                          \
        }                                                                 \
    } while (0)

static inline int check_result(void)
{
    printf("%d checks, %d failed\n", check_count, check_failures);
    return check_failures ? 1 : 0;
}

/* A fresh temporary directory for the test's files; removed by the OS's
 * tmp cleaning, and by check_rmdir at the end of a passing run. */
#include <string.h>
#include <unistd.h>
static inline const char *check_tmpdir(void)
{
    static char dir[64];
    if (!dir[0]) {
        snprintf(dir, sizeof dir, "/tmp/relief-test-XXXXXX");
        if (!mkdtemp(dir)) {
            perror("mkdtemp");
            exit(2);
        }
    }
    return dir;
}

static inline void check_write_file(const char *path, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(data, 1, n, f) != n) {
        perror(path);
        exit(2);
    }
    fclose(f);
}

/* 1 in the sanitize pass (RELIEF_TEST_PASS=sanitize, tests/CMakeLists.txt),
 * which leaves reruns that only compare bytes, and results grown only to
 * be reported, to the default pass. */
static inline int check_sanitize_pass(void)
{
    const char *pass = getenv("RELIEF_TEST_PASS");
    return pass && strcmp(pass, "sanitize") == 0;
}

/* Sample i of an image whose rows hold `row` samples, for the image
 * writers' tests: noise on two rows in three, a ramp along the others,
 * so that the PNG writer's sub, up, average and Paeth filters each win
 * somewhere and none wins everywhere. */
static inline uint32_t check_pattern(size_t i, size_t row)
{
    size_t y = i / row, x = i % row;
    uint32_t v = (uint32_t)i * 2654435761u;
    v = (v ^ v >> 15) * 2246822519u;
    return y % 3 ? v ^ v >> 13 : (uint32_t)(x * 7 + y * 3);
}

#endif
