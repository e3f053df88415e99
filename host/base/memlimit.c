/* Memory estimates and limits (memlimit.h). */
#include "base/memlimit.h"
#include "base/params.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <strings.h>
#include <sys/resource.h>
#include <unistd.h>

#include "base/error.h"
#include "base/numtext.h"

uint64_t relief_physical_memory(void)
{
    long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || size <= 0)
        return 0;
    return (uint64_t)pages * (uint64_t)size;
}

uint64_t relief_default_memory_limit(void)
{
    uint64_t phys = relief_physical_memory(), limit = UINT64_MAX;
    struct rlimit rl;
    if (phys)
        limit = phys / 10 * 8;
    if (getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY &&
        (uint64_t)rl.rlim_cur / 10 * 8 < limit)
        limit = (uint64_t)rl.rlim_cur / 10 * 8;
    return limit;
}

uint64_t relief_memory_limit(const relief_params *params)
{
    return params->max_memory ? params->max_memory : relief_default_memory_limit();
}

relief_status relief_parse_size(const char *text, uint64_t *out, relief_error *err)
{
    static const char *const units[] = {"", "k", "m", "g", "t"};
    char *end;
    double v;
    int shift = -1;
    errno = 0;
    v = relief_strtod(text, &end);
    if (end == text || errno != 0 || !isfinite(v) || !(v > 0.0))
        return relief_fail(err, RELIEF_E_USAGE,
                           "'%s' is not a size: expected a positive number of bytes with an "
                           "optional K, M, G or T (e.g. 512M, 4G)", text);
    for (int i = 0; i < 5 && shift < 0; ++i) {
        const size_t n = i == 0 ? 0 : 1;
        if (strncasecmp(end, units[i], n) != 0)
            continue;
        if (end[n] == '\0' || strcasecmp(end + n, "b") == 0 ||
            (i > 0 && strcasecmp(end + n, "ib") == 0))
            shift = 10 * i;
    }
    if (shift < 0)
        return relief_fail(err, RELIEF_E_USAGE,
                           "'%s' is not a size: unknown unit '%s' (expected K, M, G or T)",
                           text, end);
    v = ldexp(v, shift);
    if (v < 1.0 || v >= 18446744073709551615.0)
        return relief_fail(err, RELIEF_E_USAGE, "'%s' is out of range: expected 1 byte to "
                           "16 EiB", text);
    *out = (uint64_t)v;
    return RELIEF_OK;
}

void relief_format_size(uint64_t bytes, char *buf, size_t cap)
{
    static const char *const units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    double v = (double)bytes;
    int u = 0;
    while (v >= 1024.0 && u < 6) {
        v /= 1024.0;
        ++u;
    }
    if (u == 0)
        snprintf(buf, cap, "%llu B", (unsigned long long)bytes);
    else
        relief_snprintf_c(buf, cap, "%.*f %s", v < 10.0 ? 2 : v < 100.0 ? 1 : 0, v, units[u]);
}

/* a * b + c, saturating instead of wrapping. */
static uint64_t mul_add(uint64_t a, uint64_t b, uint64_t c)
{
    if (b && a > (UINT64_MAX - c) / b)
        return UINT64_MAX;
    return a * b + c;
}

uint64_t relief_estimate_read(uint64_t file_bytes)
{
    return mul_add(file_bytes, RELIEF_MEM_READ_PER_FILE_BYTE, 0);
}

uint64_t relief_estimate_smooth(size_t vertices)
{
    return mul_add(vertices, RELIEF_MEM_SMOOTH_PER_VERTEX, 0);
}

uint64_t relief_estimate_growth(size_t nv, size_t nt, size_t ns, int rotations)
{
    uint64_t b = 0;
    b = mul_add(nv, RELIEF_MEM_SURFACE_PER_VERTEX + RELIEF_MEM_MATCH_PER_VERTEX +
                        RELIEF_MEM_GROW_PER_VERTEX, b);
    b = mul_add(nt, RELIEF_MEM_SURFACE_PER_TRIANGLE + RELIEF_MEM_MATCH_PER_TRIANGLE +
                        RELIEF_MEM_GROW_PER_TRIANGLE, b);
    b = mul_add(ns, RELIEF_MEM_MATCH_PER_SAMPLE, b);
    b = mul_add(mul_add(ns, (uint64_t)(rotations > 0 ? rotations : 1), 0),
                RELIEF_MEM_GROW_PER_CANDIDATE, b);
    return b;
}

relief_status relief_memory_check(const char *what, uint64_t need, uint64_t limit,
                                  const char *hint, relief_error *err)
{
    char a[32], b[32];
    if (need <= limit)
        return RELIEF_OK;
    relief_format_size(need, a, sizeof a);
    relief_format_size(limit, b, sizeof b);
    return relief_fail(err, RELIEF_E_NOMEM,
                       "%s needs about %s of memory, over the limit of %s (max_memory; the "
                       "default is 80%% of physical memory)%s",
                       what, a, b, hint);
}
