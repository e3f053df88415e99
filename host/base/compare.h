/* Ascending qsort comparators for the plain types relief sorts (header
 * only: each file gets its own copy to pass as a function pointer). */
#ifndef RELIEF_HOST_COMPARE_H
#define RELIEF_HOST_COMPARE_H

#include <stddef.h>
#include <stdint.h>

static inline int relief_cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static inline int relief_cmp_size(const void *a, const void *b)
{
    size_t x = *(const size_t *)a, y = *(const size_t *)b;
    return (x > y) - (x < y);
}

static inline int relief_cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

static inline int relief_cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

#endif
