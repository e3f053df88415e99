/* Matching throughput, scalar against OpenCL and the host's threads in one
 * process: candidates
 * (sample x rotation) scored per second for W = 2, 3, 4 and R = 1, 4, 8,
 * exhaustive and pruned, on the queries the growth builds for targets on
 * the first boundary of a synthetic capture (relief_query_build). Each
 * cell is the median of several repetitions; the OpenCL / scalar and host /
 * scalar ratios are of the medians. The host backend (matcher_host.h) runs
 * on every online core; the scalar reference on one.
 *   usage: bench_score [--vertices N] [--targets K] [--reps N] [--csv FILE]
 * Prints a table and writes CSV rows: machine, device, backend, W, R,
 * prune, reps, median, min, max (candidates per second). */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/clock.h"
#include "base/params.h"
#include "base/rng.h"
#include "grow/grow.h"
#include "match/matcher.h"
#include "match/matcher_host.h"
#include "match/matcher_opencl.h"
#include "match/matcher_scalar.h"
#include "mesh/mesh.h"
#include "smooth/surface.h"

#include "bench_util.h"

#define MAX_NB 512

typedef struct query_set {
    size_t n;
    relief_match_query q[64];
    float *buf; /* qp, q, g, qcol of all queries */
} query_set;

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The growth's own queries (window w) for up to `k` targets next to the
 * capture, copied out of the builder so they can be replayed. */
static void make_queries(const relief_surface *s, const relief_match_data *d, int w, size_t k,
                         query_set *qs)
{
    relief_query_builder *qb = NULL;
    relief_error err;
    relief_rng rng;
    uint8_t *textured = calloc(d->nv, 1);
    float *b;
    qs->n = 0;
    qs->buf = malloc(k * MAX_NB * 10 * sizeof(float));
    b = qs->buf;
    if (!textured || !qs->buf || relief_query_builder_create(s, d, &qb, &err) != RELIEF_OK) {
        free(textured);
        return;
    }
    for (size_t v = 0; v < s->n_samples; ++v)
        textured[v] = 1; /* the first pass: only the samples are textured */
    relief_rng_seed(&rng, 5);
    for (size_t tries = 0; qs->n < k && tries < 100 * k; ++tries) {
        uint32_t t = (uint32_t)(s->n_samples + relief_rng_below(&rng, (uint32_t)s->n_targets));
        relief_match_query q;
        relief_query_build(qb, textured, t, w, &q);
        if (q.n < 3 || q.n > MAX_NB)
            continue; /* not on the boundary yet */
        memcpy(b, q.qp, 3 * q.n * sizeof(float));
        memcpy(b + 3 * MAX_NB, q.q, 3 * q.n * sizeof(float));
        memcpy(b + 6 * MAX_NB, q.g, q.n * sizeof(float));
        memcpy(b + 7 * MAX_NB, q.qcol, 3 * q.n * sizeof(float));
        q.qp = b, q.q = b + 3 * MAX_NB, q.g = b + 6 * MAX_NB, q.qcol = b + 7 * MAX_NB;
        qs->q[qs->n++] = q;
        b += 10 * MAX_NB;
    }
    relief_query_builder_destroy(qb);
    free(textured);
}

int main(int argc, char **argv)
{
    size_t vertices = 2000, ntargets = 8;
    int reps = 5;
    const char *csv = "bench-out/bench_score.csv";
    relief_synth_params sp = relief_synth_params_default();
    relief_params p = relief_params_default();
    relief_mesh *cap = NULL;
    relief_surface *s = NULL;
    relief_error err = {0};
    relief_device_info dev[8];
    size_t ndev = 0;
    char machine[256], devname[200] = "none";
    FILE *out;
    long cores = sysconf(_SC_NPROCESSORS_ONLN);

    for (int i = 1; i + 1 < argc; i += 2) {
        if (strcmp(argv[i], "--vertices") == 0)
            vertices = (size_t)atol(argv[i + 1]);
        else if (strcmp(argv[i], "--targets") == 0)
            ntargets = (size_t)atol(argv[i + 1]);
        else if (strcmp(argv[i], "--reps") == 0)
            reps = atoi(argv[i + 1]);
        else if (strcmp(argv[i], "--csv") == 0)
            csv = argv[i + 1];
    }
    if (ntargets > 64)
        ntargets = 64;
    if (reps < 1)
        reps = 1;
    if (relief_devices(dev, 8, &ndev, &err) == RELIEF_OK && ndev > 0)
        snprintf(devname, sizeof devname, "%s", dev[0].name);
    {
        /* CPU model and cores; no commas (CSV). */
        FILE *f = fopen("/proc/cpuinfo", "r");
        char line[512], cpu[160] = "unknown CPU";
        while (f && fgets(line, sizeof line, f))
            if (strncmp(line, "model name", 10) == 0 && strchr(line, ':')) {
                char *c = strchr(line, ':') + 1;
                c += *c == ' ';
                c[strcspn(c, "\n")] = '\0';
                snprintf(cpu, sizeof cpu, "%s", c);
                break;
            }
        if (f)
            fclose(f);
        snprintf(machine, sizeof machine, "%s; %ld cores", cpu, cores);
        for (char *c = machine; *c; ++c)
            *c = *c == ',' ? ';' : *c;
        for (char *c = devname; *c; ++c)
            *c = *c == ',' ? ';' : *c;
    }

    sp.kind = RELIEF_SYNTH_CYLINDER_BARK;
    sp.vertices = vertices;
    sp.colour = 1;
    if (relief_synth(&sp, &cap, NULL, &err) != RELIEF_OK ||
        relief_surface_build(cap, &p, NULL, &s, &err) != RELIEF_OK) {
        fprintf(stderr, "bench_score: %s\n", err.message);
        return 2;
    }
    out = fopen(csv, "w");
    if (!out) {
        perror(csv);
        return 2;
    }
    fprintf(out, "machine,device,backend,W,R,prune,reps,targets,samples,median_cps,min_cps,"
                 "max_cps\n");
    printf("bench_score: cylinder-bark %zu vertices: %zu samples, %zu targets; %zu "
           "neighbourhoods per cell, %d repetitions; %s; OpenCL device: %s\n",
           vertices, s->n_samples, s->n_targets, ntargets, reps, machine, devname);
    printf("%2s %2s %-6s %14s %14s %14s %8s %8s\n", "W", "R", "prune", "scalar c/s",
           "opencl c/s", "host c/s", "opencl/s", "host/s");
    for (int w = 2; w <= 4; ++w)
        for (int rr = 0; rr < 3; ++rr) {
            const int R = rr == 0 ? 1 : rr == 1 ? 4 : 8;
            relief_match_data *d = NULL;
            relief_matcher *m[3] = {NULL, NULL, NULL};
            query_set qs;
            if (relief_match_data_build(s, R, 0.5, &d, &err) != RELIEF_OK) {
                fprintf(stderr, "bench_score: %s\n", err.message);
                return 2;
            }
            make_queries(s, d, w, ntargets, &qs);
            relief_matcher_scalar_create(d, &m[0], &err);
            if (relief_matcher_opencl_create(d, -1, 0, &m[1], &err) != RELIEF_OK)
                m[1] = NULL;
            if (relief_matcher_host_create(d, 0, &m[2], &err) != RELIEF_OK)
                m[2] = NULL;
            for (int prune = 0; prune < 2; ++prune) {
                double med[3] = {NAN, NAN, NAN};
                char field[256];
                static const char *const names[3] = {"scalar", "opencl", "host"};
                size_t nc = (size_t)d->ns * (size_t)R;
                float *ssd = malloc(nc * sizeof *ssd);
                uint8_t *flag = malloc(nc);
                for (int b = 0; b < 3; ++b) {
                    double rate[64];
                    if (!m[b])
                        continue;
                    /* A warm-up pass, then the timed repetitions. */
                    for (int r = -1; r < reps; ++r) {
                        double t0 = relief_seconds();
                        for (size_t i = 0; i < qs.n; ++i) {
                            qs.q[i].running = prune;
                            relief_matcher_score(m[b], d, &qs.q[i], ssd, flag, &err);
                        }
                        if (r >= 0)
                            rate[r] = (double)(nc * qs.n) / (relief_seconds() - t0);
                    }
                    qsort(rate, (size_t)reps, sizeof rate[0], cmp_double);
                    med[b] = rate[reps / 2];
                    fprintf(out, "%s,%s,%s,%d,%d,%d,%d,%zu,%zu,%.6g,%.6g,%.6g\n", machine,
                            bench_csv_field(b == 1 ? devname : m[b]->device, field,
                                            sizeof field),
                            names[b], w, R,
                            prune, reps, qs.n, s->n_samples, med[b], rate[0], rate[reps - 1]);
                }
                printf("%2d %2d %-6s %14.4g %14.4g %14.4g %8.2f %8.2f\n", w, R,
                       prune ? "yes" : "no", med[0], med[1], med[2], med[1] / med[0],
                       med[2] / med[0]);
                free(ssd);
                free(flag);
            }
            free(qs.buf);
            relief_matcher_destroy(m[2]);
            relief_matcher_destroy(m[1]);
            relief_matcher_destroy(m[0]);
            relief_match_data_destroy(d);
        }
    fclose(out);
    printf("CSV: %s\n", csv);
    relief_surface_destroy(s);
    relief_mesh_destroy(cap);
    return 0;
}
