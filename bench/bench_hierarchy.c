/* Mono-scale against hierarchical completion (issue 7; paper 001 table 1):
 * the same capture completed with --levels 1 and --levels M on one
 * backend, alternating within each repetition so a noisy machine slows
 * both alike; medians, the mono / hierarchical time ratio, and the MSI
 * difference of each result (deterministic for the seed).
 *
 *   usage: bench_hierarchy --case NAME [--kind KIND] [--vertices N] [--colour]
 *          [--noise SIGMA] [--spacing S] [--window W] [--rotations R]
 *          [--levels M] [--seed N] [--backend scalar|opencl] [--prune 0|1]
 *          [--reps N] [--csv FILE]
 *
 * --prune 0 scores every candidate in full in both runs (the papers'
 * exhaustive search, which their timings are of); the default prunes.
 *
 * Times are seconds of wall clock from the smooth completion to the grown
 * surface (the hierarchy's construction included). CSV columns: case, cpu,
 * cores, device, backend, kind, vertices, samples, targets, W, R, levels,
 * reps, median, min, max, candidates, msi_diff_percent, truth_rms,
 * peak_rss_kib. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_util.h"
#include "base/params.h"
#include "base/clock.h"
#include "grow/grow.h"
#include "grow/hierarchy.h"
#include "match/matcher.h"
#include "mesh/mesh.h"
#include "report/measures.h"
#include "smooth/surface.h"

#define MAX_REPS 32

typedef struct config {
    const char *name, *csv;
    relief_synth_params sp;
    relief_params p;
    relief_backend backend;
    int levels, reps, prune;
} config;

typedef struct result {
    double t[MAX_REPS];
    size_t samples, targets, candidates;
    relief_measures me;
    char device[256];
} result;

/* One completion of cap with `levels` (1: mono-scale) into *r at rep i. */
static relief_status run(const config *c, const relief_mesh *cap, const relief_mesh *truth,
                         int levels, int i, result *r, relief_error *err)
{
    relief_surface *s = NULL;
    relief_match_data *d = NULL;
    relief_matcher *m = NULL;
    relief_hierarchy *h = NULL;
    relief_grow_options go = relief_grow_options_default();
    relief_grow_stats gs;
    relief_params p = c->p;
    double t0 = relief_seconds();
    go.prune = c->prune;
    relief_status st = relief_surface_build(cap, &p, NULL, &s, err);
    p.levels = levels;
    if (st == RELIEF_OK && levels == 1) {
        st = relief_match_data_build(s, p.rotations,
                                     relief_grow_mu(&p, cap->col != NULL), &d,
                                     err);
        if (st == RELIEF_OK)
            st = relief_matcher_create(c->backend, -1, 0, 0.0, d, &m, NULL, 0, NULL, err);
        if (st == RELIEF_OK)
            st = relief_grow(s, d, m, &p, &go, &gs, err);
        if (st == RELIEF_OK)
            snprintf(r->device, sizeof r->device, "%s", m->device);
    } else if (st == RELIEF_OK) {
        relief_hierarchy_options ho = relief_hierarchy_options_default();
        relief_hierarchy_stats hs;
        relief_backend used;
        ho.backend = c->backend;
        st = relief_hierarchy_build(s, levels, &h, err);
        if (st == RELIEF_OK)
            st = relief_hierarchy_grow(h, s, &p, &go, &ho, &hs, &gs, &used, r->device,
                                       sizeof r->device, NULL, 0, err);
    }
    r->t[i] = relief_seconds() - t0;
    if (st == RELIEF_OK) {
        r->samples = s->n_samples;
        r->targets = s->n_targets;
        r->candidates = gs.candidates;
        st = relief_measure(s->mesh, truth, &s->fit.prim, &r->me, err);
    }
    relief_hierarchy_destroy(h);
    relief_matcher_destroy(m);
    relief_match_data_destroy(d);
    relief_surface_destroy(s);
    return st;
}

static int usage(void)
{
    fprintf(stderr,
            "usage: bench_hierarchy --case NAME [--kind KIND] [--vertices N] [--colour]\n"
            "       [--noise SIGMA] [--spacing S] [--window W] [--rotations R] [--levels M]\n"
            "       [--seed N] [--backend scalar|opencl] [--prune 0|1] [--reps N] [--csv FILE]\n");
    return 1;
}

static int parse_args(int argc, char **argv, config *c)
{
    memset(c, 0, sizeof *c);
    c->name = "hierarchy";
    c->sp = relief_synth_params_default();
    c->sp.kind = RELIEF_SYNTH_CYLINDER_BANDS;
    c->p = relief_params_default();
    c->p.search = RELIEF_SEARCH_EXHAUSTIVE; /* what its figures have always been of */
    c->backend = RELIEF_BACKEND_AUTO;
    c->levels = 3;
    c->reps = 3;
    c->prune = 1;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(a, "--colour") == 0) {
            c->sp.colour = 1;
            continue;
        }
        if (!v)
            return usage();
        ++i;
        if (strcmp(a, "--case") == 0)
            c->name = v;
        else if (strcmp(a, "--kind") == 0) {
            if (relief_synth_kind_parse(v, &c->sp.kind, NULL) != RELIEF_OK)
                return usage();
        } else if (strcmp(a, "--vertices") == 0)
            c->sp.vertices = (size_t)atol(v);
        else if (strcmp(a, "--noise") == 0)
            c->sp.noise = atof(v);
        else if (strcmp(a, "--spacing") == 0)
            c->p.spacing = atof(v);
        else if (strcmp(a, "--window") == 0)
            c->p.window = atoi(v);
        else if (strcmp(a, "--rotations") == 0)
            c->p.rotations = atoi(v);
        else if (strcmp(a, "--levels") == 0)
            c->levels = atoi(v);
        else if (strcmp(a, "--seed") == 0)
            c->p.seed = c->sp.seed = (uint32_t)atol(v);
        else if (strcmp(a, "--backend") == 0) {
            if (strcmp(v, "scalar") == 0)
                c->backend = RELIEF_BACKEND_SCALAR;
            else if (strcmp(v, "opencl") == 0)
                c->backend = RELIEF_BACKEND_OPENCL;
            else
                return usage();
        } else if (strcmp(a, "--prune") == 0) {
            if (strcmp(v, "0") != 0 && strcmp(v, "1") != 0)
                return usage();
            c->prune = v[0] == '1';
        } else if (strcmp(a, "--reps") == 0)
            c->reps = atoi(v);
        else if (strcmp(a, "--csv") == 0)
            c->csv = v;
        else
            return usage();
    }
    if (c->reps < 1 || c->reps > MAX_REPS || c->levels < 2 || c->levels > RELIEF_MAX_LEVELS)
        return usage();
    return 0;
}

int main(int argc, char **argv)
{
    config c;
    bench_machine mc;
    result *res = calloc(2, sizeof *res);
    relief_mesh *cap = NULL, *truth = NULL;
    relief_error err = {0};
    FILE *out = NULL;
    double med[2], lo[2], hi[2];
    int rc = parse_args(argc, argv, &c);
    if (rc != 0 || !res) {
        free(res);
        return rc ? rc : 2;
    }
    bench_read_machine(&mc);
    c.p.rotations = bench_rotations(&c.p, c.sp.kind);
    if (relief_synth(&c.sp, &cap, &truth, &err) != RELIEF_OK)
        goto fail;
    for (int i = 0; i < c.reps; ++i)
        for (int k = 0; k < 2; ++k) {
            if (run(&c, cap, truth, k ? c.levels : 1, i, &res[k], &err) != RELIEF_OK)
                goto fail;
            fprintf(stderr, "bench_hierarchy %s: levels %d rep %d/%d: %.3f s\n", c.name,
                    k ? c.levels : 1, i + 1, c.reps, res[k].t[i]);
        }
    printf("%s: %s %zu vertices, W %d, R %d; %s (%ld cores); %s\n", c.name,
           relief_synth_kind_name(c.sp.kind), c.sp.vertices, c.p.window, c.p.rotations, mc.cpu,
           mc.cores, res[0].device);
    if (c.csv) {
        out = bench_csv_append(c.csv,
                               "case,cpu,cores,device,backend,kind,vertices,samples,targets,W,"
                               "R,levels,reps,median,min,max,candidates,msi_diff_percent,"
                               "truth_rms,peak_rss_kib\n");
        if (!out)
            goto fail;
    }
    for (int k = 0; k < 2; ++k) {
        const result *r = &res[k];
        char dev[256];
        snprintf(dev, sizeof dev, "%s", r->device);
        for (char *p = dev; *p; ++p)
            if (*p == ',')
                *p = ';';
        bench_stats3(r->t, c.reps, &med[k], &lo[k], &hi[k]);
        printf("  levels %d: %zu samples, %zu targets: median %.3f s (min %.3f, max %.3f, "
               "%d reps), %zu candidates scored, MSI difference %.2f %%, truth RMS %.4g\n",
               k ? c.levels : 1, r->samples, r->targets, med[k], lo[k], hi[k], c.reps,
               r->candidates, r->me.msi_diff_percent, r->me.truth_rms);
        if (out)
            fprintf(out, "%s,%s,%ld,%s,%s,%s,%zu,%zu,%zu,%d,%d,%d,%d,%.6g,%.6g,%.6g,%zu,%.4f,"
                         "%.6g,%ld\n",
                    c.name, mc.cpu, mc.cores, dev,
                    strstr(r->device, "scalar") ? "scalar" : "opencl",
                    relief_synth_kind_name(c.sp.kind), c.sp.vertices, r->samples, r->targets,
                    c.p.window, c.p.rotations, k ? c.levels : 1, c.reps, med[k], lo[k], hi[k],
                    r->candidates, r->me.msi_diff_percent, r->me.truth_rms,
                    bench_peak_rss_kib());
    }
    printf("  mono / hierarchical median time = %.2f\n", med[0] / med[1]);
    if (out)
        fclose(out);
    relief_mesh_destroy(truth);
    relief_mesh_destroy(cap);
    free(res);
    return 0;
fail:
    fprintf(stderr, "bench_hierarchy %s: %s\n", c.name, err.message);
    if (out)
        fclose(out);
    relief_mesh_destroy(truth);
    relief_mesh_destroy(cap);
    free(res);
    return 2;
}
