/* What the benchmark programs share: the machine a row was measured on,
 * medians of repetitions, peak resident memory. */
#ifndef RELIEF_BENCH_UTIL_H
#define RELIEF_BENCH_UTIL_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#include "relief/relief.h"
#include "base/params.h"

typedef struct bench_machine {
    char cpu[160], device[200]; /* no commas: they go into CSV fields */
    long cores;
} bench_machine;

static inline void bench_read_machine(bench_machine *m)
{
    FILE *f = fopen("/proc/cpuinfo", "r");
    char line[512];
    relief_device_info dev[8];
    size_t ndev = 0;
    relief_error err;
    snprintf(m->cpu, sizeof m->cpu, "unknown CPU");
    snprintf(m->device, sizeof m->device, "none");
    m->cores = sysconf(_SC_NPROCESSORS_ONLN);
    while (f && fgets(line, sizeof line, f))
        if (strncmp(line, "model name", 10) == 0) {
            char *c = strchr(line, ':');
            if (c) {
                c += 1 + (c[1] == ' ');
                c[strcspn(c, "\n")] = '\0';
                snprintf(m->cpu, sizeof m->cpu, "%s", c);
            }
            break;
        }
    if (f)
        fclose(f);
    if (relief_devices(dev, 8, &ndev, &err) == RELIEF_OK && ndev > 0)
        snprintf(m->device, sizeof m->device, "%s", dev[0].name);
    for (char *c = m->cpu; *c; ++c)
        if (*c == ',')
            *c = ';';
    for (char *c = m->device; *c; ++c)
        if (*c == ',')
            *c = ';';
}

/* s with its commas as semicolons, in buf (n bytes): a CSV field. */
static inline const char *bench_csv_field(const char *s, char *buf, size_t n)
{
    snprintf(buf, n, "%s", s);
    for (char *c = buf; *c; ++c)
        if (*c == ',')
            *c = ';';
    return buf;
}

/* The rotations a synthetic kind's completion tries (relief_params_rotations
 * on the primitive the kind is made on), so the figures name what ran. */
static inline int bench_rotations(const relief_params *p, relief_synth_kind kind)
{
    relief_fit_model model = RELIEF_FIT_SPHERE;
    if (kind == RELIEF_SYNTH_PLANE_WAVES || kind == RELIEF_SYNTH_PLANE_NOISE)
        model = RELIEF_FIT_PLANE;
    else if (kind == RELIEF_SYNTH_CYLINDER_BANDS || kind == RELIEF_SYNTH_CYLINDER_BARK)
        model = RELIEF_FIT_CYLINDER;
    return relief_params_rotations(p, model);
}

static inline int bench_cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median, min and max of v[0..n-1] (n >= 1; n <= 64). */
static inline void bench_stats3(const double *v, int n, double *med, double *lo, double *hi)
{
    double s[64];
    memcpy(s, v, (size_t)n * sizeof *s);
    qsort(s, (size_t)n, sizeof *s, bench_cmp_double);
    *lo = s[0];
    *hi = s[n - 1];
    *med = n % 2 ? s[n / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
}

/* `path` opened for appending rows; `header` is written first when the
 * file did not exist yet. NULL (with perror) when it cannot be opened. */
static inline FILE *bench_csv_append(const char *path, const char *header)
{
    FILE *probe = fopen(path, "r"), *out;
    const int fresh = !probe;
    if (probe)
        fclose(probe);
    out = fopen(path, "a");
    if (!out) {
        perror(path);
        return NULL;
    }
    if (fresh)
        fputs(header, out);
    return out;
}

/* The process's peak resident memory so far, KiB. */
static inline long bench_peak_rss_kib(void)
{
    struct rusage ru;
    return getrusage(RUSAGE_SELF, &ru) == 0 ? ru.ru_maxrss : -1;
}

#endif
