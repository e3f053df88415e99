/* Whole completions and their stages, per backend, on a synthetic surface:
 * the papers' problem sizes, pruned against exhaustive, and the scaling of
 * time and peak memory with the surface's size.
 *
 *   usage: bench_complete --case NAME [--kind KIND] [--vertices N] [--colour]
 *          [--spacing S] [--oversample N] [--window W] [--rotations R]
 *          [--error E] [--seed N] [--prune 0|1] [--backends scalar,opencl]
 *          [--reps N] [--scalar-reps N] [--smooth-reps N] [--mode full|setup]
 *          [--targets K] [--search exhaustive|coherent|auto] [--search-k K]
 *          [--csv FILE]
 *
 * --mode full (default): per repetition and backend, the whole completion
 * after the capture is made: smooth completion, match data, matcher
 * creation (for OpenCL: context, kernel build, upload), growth. The
 * backends alternate within a repetition so that a noisy machine slows
 * both alike; the outputs of the backends are compared (a checksum of the
 * completed positions and colours) and the row says whether they agree.
 *
 * --mode setup: the stages up to the growth (synth, smooth, match data,
 * matcher creation, the growth's query builder), then the matching time
 * per target on K targets of the first boundary (the query the growth
 * builds, scored as the growth scores it). For sizes whose whole growth
 * would take hours: the per-target time times the targets extrapolates it.
 * --smooth-reps N: synthesis and smooth completion only in the first N
 * repetitions (the rest reuse the surface).
 *
 * Every CSV row: case, machine (CPU model, cores), device, backend,
 * parameters, the surface's counts, stage, unit, repetitions, median, min,
 * max, and the process's peak resident memory so far (KiB, getrusage
 * ru_maxrss), the search and its fallbacks to every sample. Times are
 * seconds of wall clock. --search defaults to exhaustive, the method every
 * case measured before the k-coherence search existed. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_util.h"
#include "base/params.h"
#include "base/clock.h"
#include "base/error.h"
#include "base/rng.h"
#include "grow/grow.h"
#include "match/matcher.h"
#include "match/matcher_host.h"
#include "match/matcher_opencl.h"
#include "match/matcher_scalar.h"
#include "mesh/mesh.h"
#include "smooth/surface.h"

#define MAX_REPS 64
#define MAX_TARGETS 256

enum { B_SCALAR, B_OPENCL, B_HOST, NB };
static const char *const backend_name[NB] = {"scalar", "opencl", "host"};
enum {
    S_SYNTH,
    S_SMOOTH,
    S_MATCH_DATA,
    S_MATCHER,
    S_GROW,
    S_TOTAL,
    S_PER_TARGET,
    S_GROW_SETUP,
    NS
};
static const char *const stage_name[NS] = {
    "synth", "smooth", "match_data", "matcher_create", "grow", "completion", "per_target",
    "grow_setup"};

typedef struct config {
    const char *name, *csv;
    relief_synth_params sp;
    relief_params p;
    int prune, reps, scalar_reps, smooth_reps, setup, targets;
    int use[NB];
} config;

/* Measurements of one backend: t[stage][rep] (NAN: not taken). */
typedef struct series {
    double t[NS][MAX_REPS];
    int n[NS];
    size_t samples, targets, nv;
    relief_grow_stats stats; /* of the last full run */
    uint64_t checksum;       /* of the last full run */
    char device[256];
    double list_bytes; /* the closest-vertex lists: hash table and items */
} series;

/* FNV-1a over the completed positions (float) and colours: equal outputs
 * give equal sums. */
static uint64_t checksum(const relief_mesh *m)
{
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < 3 * m->nv; ++i) {
        float v[2] = {(float)m->pos[i], m->col ? m->col[i] : 0.0f};
        const unsigned char *b = (const unsigned char *)v;
        for (size_t k = 0; k < sizeof v; ++k)
            h = (h ^ b[k]) * 1099511628211ull;
    }
    return h;
}

static relief_status make_matcher(int b, const relief_match_data *d, relief_matcher **m,
                                  relief_error *err)
{
    return b == B_SCALAR   ? relief_matcher_scalar_create(d, m, err)
           : b == B_HOST ? relief_matcher_host_create(d, 0, m, err)
                         : relief_matcher_opencl_create(d, -1, 0, m, err);
}

/* One whole completion of `cap` with backend b; stage times into rep `r`. */
static relief_status run_full(const config *c, const relief_mesh *cap, int b, int r,
                              series *se, relief_error *err)
{
    relief_surface *s = NULL;
    relief_match_data *d = NULL;
    relief_matcher *m = NULL;
    relief_grow_options go = relief_grow_options_default();
    double t0 = relief_seconds(), t1, t2, t3, t4;
    relief_status st = relief_surface_build(cap, &c->p, NULL, &s, err);
    t1 = relief_seconds();
    if (st == RELIEF_OK)
        st = relief_match_data_build(s, c->p.rotations,
                                     relief_grow_mu(&c->p, cap->col != NULL),
                                     &d, err);
    t2 = relief_seconds();
    if (st == RELIEF_OK)
        st = make_matcher(b, d, &m, err);
    t3 = relief_seconds();
    go.prune = c->prune;
    if (st == RELIEF_OK)
        st = relief_grow(s, d, m, &c->p, &go, &se->stats, err);
    t4 = relief_seconds();
    if (st == RELIEF_OK) {
        se->t[S_SMOOTH][r] = t1 - t0;
        se->t[S_MATCH_DATA][r] = t2 - t1;
        se->t[S_MATCHER][r] = t3 - t2;
        se->t[S_GROW][r] = t4 - t3;
        se->t[S_TOTAL][r] = t4 - t0;
        for (int k = S_SMOOTH; k <= S_TOTAL; ++k)
            se->n[k] = r + 1;
        se->samples = s->n_samples;
        se->targets = s->n_targets;
        se->nv = s->mesh->nv;
        se->checksum = checksum(s->mesh);
        snprintf(se->device, sizeof se->device, "%s", m->device);
    }
    relief_matcher_destroy(m);
    relief_match_data_destroy(d);
    relief_surface_destroy(s);
    return st;
}

/* The capture and its smooth completion, for --mode setup. */
typedef struct prepared {
    relief_mesh *cap;
    relief_surface *s;
} prepared;

static void prepared_clear(prepared *pp)
{
    relief_surface_destroy(pp->s);
    relief_mesh_destroy(pp->cap);
    pp->s = NULL;
    pp->cap = NULL;
}

/* The stages before the growth, then the matching time per target on up to
 * c->targets targets of the first boundary (rep `r`). The synthesis and
 * smooth completion are redone for the first c->smooth_reps repetitions
 * only (they take minutes at a million vertices); later repetitions reuse
 * the surface, which the matching does not change. */
static relief_status run_setup(const config *c, int b, int r, prepared *pp, series *se,
                               relief_error *err)
{
    relief_match_data *d = NULL;
    relief_matcher *m = NULL;
    relief_query_builder *qb = NULL;
    uint8_t *textured = NULL, *flag = NULL;
    float *ssd = NULL;
    relief_rng rng;
    size_t ncand = 0, done = 0;
    double t0, t1, t2, t3, t4, t5, match = 0.0;
    relief_status st = RELIEF_OK;
    relief_surface *s;

    if (!pp->s || r < c->smooth_reps) {
        prepared_clear(pp);
        t0 = relief_seconds();
        st = relief_synth(&c->sp, &pp->cap, NULL, err);
        t1 = relief_seconds();
        if (st == RELIEF_OK)
            st = relief_surface_build(pp->cap, &c->p, NULL, &pp->s, err);
        t2 = relief_seconds();
        if (st != RELIEF_OK)
            return st;
        se->t[S_SYNTH][se->n[S_SYNTH]++] = t1 - t0;
        se->t[S_SMOOTH][se->n[S_SMOOTH]++] = t2 - t1;
    }
    s = pp->s;
    t2 = relief_seconds();
    st = relief_match_data_build(s, c->p.rotations,
                                 relief_grow_mu(&c->p, pp->cap->col != NULL), &d, err);
    t3 = relief_seconds();
    if (st == RELIEF_OK)
        st = make_matcher(b, d, &m, err);
    t4 = relief_seconds();
    if (st == RELIEF_OK)
        st = relief_query_builder_create(s, d, &qb, err);
    t5 = relief_seconds();
    if (st != RELIEF_OK)
        goto done;
    ncand = (size_t)d->ns * (size_t)d->rotations;
    textured = calloc(s->mesh->nv, 1);
    ssd = malloc(ncand * sizeof *ssd);
    flag = malloc(ncand);
    if (!textured || !ssd || !flag) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the scores of %zu candidates",
                         ncand);
        goto done;
    }
    memset(textured, 1, s->n_samples); /* the first pass: the samples */
    relief_rng_seed(&rng, 5);
    for (size_t tries = 0; done < (size_t)c->targets && tries < 100 * (size_t)c->targets;
         ++tries) {
        uint32_t t = (uint32_t)(s->n_samples + relief_rng_below(&rng, (uint32_t)s->n_targets));
        relief_match_query q;
        double q0;
        if (!relief_query_has_textured_neighbour(qb, textured, t))
            continue;
        relief_query_build(qb, textured, t, c->p.window, &q);
        if (q.n < 3)
            continue;
        q.running = c->prune;
        q0 = relief_seconds();
        st = relief_matcher_score(m, d, &q, ssd, flag, err);
        match += relief_seconds() - q0;
        if (st != RELIEF_OK)
            goto done;
        ++done;
    }
    se->list_bytes = ((double)d->lmask + 1.0) * 12.0 + (double)d->n_litems * 4.0;
    se->t[S_MATCH_DATA][r] = t3 - t2;
    se->t[S_MATCHER][r] = t4 - t3;
    se->t[S_GROW_SETUP][r] = t5 - t4; /* the growth's adjacency, walker */
    se->t[S_PER_TARGET][r] = done ? match / (double)done : NAN;
    se->n[S_MATCH_DATA] = se->n[S_MATCHER] = se->n[S_GROW_SETUP] = r + 1;
    se->n[S_PER_TARGET] = done ? r + 1 : 0;
    se->samples = s->n_samples;
    se->targets = s->n_targets;
    se->nv = s->mesh->nv;
    snprintf(se->device, sizeof se->device, "%s", m->device);
done:
    free(flag);
    free(ssd);
    free(textured);
    relief_query_builder_destroy(qb);
    relief_matcher_destroy(m);
    relief_match_data_destroy(d);
    return st;
}

static int parse_backends(const char *s, int use[NB])
{
    use[B_SCALAR] = strstr(s, "scalar") != NULL;
    use[B_OPENCL] = strstr(s, "opencl") != NULL;
    use[B_HOST] = strstr(s, "host") != NULL;
    return use[B_SCALAR] || use[B_OPENCL] || use[B_HOST];
}

static int parse_kind(const char *s, relief_synth_kind *k)
{
    for (int i = 0; i < RELIEF_SYNTH_KIND_COUNT; ++i)
        if (strcmp(s, relief_synth_kind_name((relief_synth_kind)i)) == 0) {
            *k = (relief_synth_kind)i;
            return 1;
        }
    return 0;
}

static int usage(void)
{
    fprintf(stderr,
            "usage: bench_complete --case NAME [--kind KIND] [--vertices N] [--colour]\n"
            "       [--spacing S] [--oversample N] [--window W] [--rotations R] [--error E]\n"
            "       [--seed N] [--prune 0|1] [--backends scalar,opencl,host] [--reps N]\n"
            "       [--scalar-reps N] [--smooth-reps N] [--mode full|setup] [--targets K]\n"
            "       [--search exhaustive|coherent|auto] [--search-k K] [--csv FILE]\n");
    return 1;
}

static int parse_args(int argc, char **argv, config *c)
{
    c->name = "case";
    c->csv = NULL;
    c->sp = relief_synth_params_default();
    c->sp.kind = RELIEF_SYNTH_CYLINDER_BARK;
    c->p = relief_params_default();
    c->p.fit = RELIEF_FIT_CYLINDER;
    c->p.search = RELIEF_SEARCH_EXHAUSTIVE;
    c->prune = 1;
    c->reps = 3;
    c->scalar_reps = -1;
    c->smooth_reps = -1;
    c->setup = 0;
    c->targets = 8;
    c->use[B_SCALAR] = c->use[B_OPENCL] = c->use[B_HOST] = 1;
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
            if (!parse_kind(v, &c->sp.kind))
                return usage();
            if (c->sp.kind == RELIEF_SYNTH_PLANE_WAVES || c->sp.kind == RELIEF_SYNTH_PLANE_NOISE)
                c->p.fit = RELIEF_FIT_PLANE;
            else if (c->sp.kind == RELIEF_SYNTH_SPHERE_DIMPLES)
                c->p.fit = RELIEF_FIT_SPHERE;
        } else if (strcmp(a, "--vertices") == 0)
            c->sp.vertices = (size_t)atol(v);
        else if (strcmp(a, "--spacing") == 0)
            c->p.spacing = atof(v);
        else if (strcmp(a, "--oversample") == 0)
            c->p.oversample = atoi(v);
        else if (strcmp(a, "--window") == 0)
            c->p.window = atoi(v);
        else if (strcmp(a, "--rotations") == 0)
            c->p.rotations = atoi(v);
        else if (strcmp(a, "--error") == 0)
            c->p.error = atof(v);
        else if (strcmp(a, "--seed") == 0)
            c->p.seed = (uint32_t)atol(v);
        else if (strcmp(a, "--prune") == 0)
            c->prune = atoi(v) != 0;
        else if (strcmp(a, "--backends") == 0) {
            if (!parse_backends(v, c->use))
                return usage();
        } else if (strcmp(a, "--reps") == 0)
            c->reps = atoi(v);
        else if (strcmp(a, "--scalar-reps") == 0)
            c->scalar_reps = atoi(v);
        else if (strcmp(a, "--smooth-reps") == 0)
            c->smooth_reps = atoi(v);
        else if (strcmp(a, "--mode") == 0) {
            if (strcmp(v, "full") != 0 && strcmp(v, "setup") != 0)
                return usage();
            c->setup = strcmp(v, "setup") == 0;
        } else if (strcmp(a, "--targets") == 0)
            c->targets = atoi(v);
        else if (strcmp(a, "--csv") == 0)
            c->csv = v;
        else if (strcmp(a, "--search") == 0) {
            if (strcmp(v, "exhaustive") == 0)
                c->p.search = RELIEF_SEARCH_EXHAUSTIVE;
            else if (strcmp(v, "coherent") == 0)
                c->p.search = RELIEF_SEARCH_COHERENT;
            else if (strcmp(v, "auto") == 0)
                c->p.search = RELIEF_SEARCH_AUTO;
            else
                return usage();
        } else if (strcmp(a, "--search-k") == 0)
            c->p.search_k = atoi(v);
        else
            return usage();
    }
    if (c->reps < 1 || c->reps > MAX_REPS || c->targets < 1 || c->targets > MAX_TARGETS)
        return usage();
    if (c->scalar_reps < 1 || c->scalar_reps > c->reps)
        c->scalar_reps = c->reps;
    if (c->smooth_reps < 1 || c->smooth_reps > c->reps)
        c->smooth_reps = c->reps;
    return 0;
}

int main(int argc, char **argv)
{
    config c;
    bench_machine mc;
    prepared pp = {NULL, NULL};
    series *se = calloc(NB, sizeof *se);
    relief_mesh *cap = NULL;
    relief_error err = {0};
    FILE *out = NULL;
    int rc = parse_args(argc, argv, &c);
    if (rc != 0 || !se) {
        free(se);
        return rc ? rc : 2;
    }
    bench_read_machine(&mc);
    c.p.rotations = bench_rotations(&c.p, c.sp.kind);
    if (!c.setup) {
        double t0 = relief_seconds();
        if (relief_synth(&c.sp, &cap, NULL, &err) != RELIEF_OK)
            goto fail;
        for (int b = 0; b < NB; ++b)
            se[b].t[S_SYNTH][0] = relief_seconds() - t0, se[b].n[S_SYNTH] = 1;
    }
    for (int r = 0; r < c.reps; ++r)
        for (int b = 0; b < NB; ++b) {
            relief_status st;
            if (!c.use[b] || (b == B_SCALAR && r >= c.scalar_reps))
                continue;
            st = c.setup ? run_setup(&c, b, r, &pp, &se[b], &err)
                         : run_full(&c, cap, b, r, &se[b], &err);
            if (st != RELIEF_OK)
                goto fail;
            fprintf(stderr, "bench_complete %s: %s rep %d/%d: %s %.3f s\n", c.name,
                    backend_name[b], r + 1, b == B_SCALAR ? c.scalar_reps : c.reps,
                    c.setup ? "per target" : "completion",
                    c.setup ? se[b].t[S_PER_TARGET][r] : se[b].t[S_TOTAL][r]);
        }
    if (c.csv) {
        out = bench_csv_append(c.csv,
                               "case,cpu,cores,device,backend,kind,vertices,samples,targets,"
                               "surface_vertices,W,R,prune,colour,stage,unit,reps,median,min,"
                               "max,peak_rss_kib,scored_targets,candidates,pruned,identical,search,"
                               "search_fallbacks\n");
        if (!out)
            goto fail;
    }
    printf("%s: %s %zu vertices, W %d, R %d, %s, search %s; %s (%ld cores); OpenCL device: "
           "%s\n", c.name, relief_synth_kind_name(c.sp.kind), c.sp.vertices, c.p.window,
           c.p.rotations, c.prune ? "pruned" : "exhaustive", relief_search_name(c.p.search),
           mc.cpu, mc.cores, mc.device);
    for (int b = 0; b < NB; ++b) {
        const series *s = &se[b];
        double scored = 0.0;
        const char *same = "n/a";
        if (!c.use[b])
            continue;
        for (int o = 0; o < NB && !c.setup; ++o)
            if (o != b && c.use[o])
                same = strcmp(same, "NO") != 0 && se[o].checksum == s->checksum ? "yes" : "NO";
        if (!c.setup && s->stats.targets)
            scored = (double)s->stats.candidates /
                     ((double)s->samples * (double)c.p.rotations);
        printf("  %s, %zu samples, %zu targets (%zu vertices):\n", s->device, s->samples,
               s->targets, s->nv);
        if (s->list_bytes > 0)
            printf("    closest-vertex lists: %.1f MiB (%.0f bytes per vertex)\n",
                   s->list_bytes / 1048576.0, s->list_bytes / (double)s->nv);
        for (int k = 0; k < NS; ++k) {
            double med, lo, hi;
            char field[256];
            if (s->n[k] == 0)
                continue;
            bench_stats3(s->t[k], s->n[k], &med, &lo, &hi);
            printf("    %-15s median %10.4g s  min %10.4g  max %10.4g  (%d reps)\n",
                   stage_name[k], med, lo, hi, s->n[k]);
            if (out)
                fprintf(out,
                        "%s,%s,%ld,%s,%s,%s,%zu,%zu,%zu,%zu,%d,%d,%d,%d,%s,s,%d,%.6g,%.6g,%.6g,"
                        "%ld,%.0f,%zu,%zu,%s,%s,%zu\n",
                        c.name, mc.cpu, mc.cores,
                        b == B_OPENCL ? mc.device
                                      : bench_csv_field(s->device, field, sizeof field),
                        backend_name[b], relief_synth_kind_name(c.sp.kind),
                        c.sp.vertices, s->samples, s->targets, s->nv, c.p.window,
                        c.p.rotations, c.prune, c.sp.colour, stage_name[k], s->n[k], med, lo,
                        hi, bench_peak_rss_kib(), scored, s->stats.candidates, s->stats.pruned,
                        same, relief_search_name((relief_search_mode)s->stats.search),
                        s->stats.search_misses + s->stats.search_empty);
        }
        if (!c.setup)
            printf("    scored %.0f targets for %zu (%zu candidates, %.1f %% pruned); "
                   "output identical to the other backends: %s\n",
                   scored, s->targets, s->stats.candidates,
                   s->stats.candidates ? 100.0 * (double)s->stats.pruned /
                                             (double)s->stats.candidates
                                       : 0.0,
                   same);
    }
    for (int b = B_OPENCL; b < NB && !c.setup; ++b)
        if (c.use[B_SCALAR] && c.use[b] && se[B_SCALAR].n[S_TOTAL] && se[b].n[S_TOTAL]) {
            double m0, m1, lo, hi, g0, g1;
            bench_stats3(se[B_SCALAR].t[S_GROW], se[B_SCALAR].n[S_GROW], &g0, &lo, &hi);
            bench_stats3(se[b].t[S_GROW], se[b].n[S_GROW], &g1, &lo, &hi);
            bench_stats3(se[B_SCALAR].t[S_TOTAL], se[B_SCALAR].n[S_TOTAL], &m0, &lo, &hi);
            bench_stats3(se[b].t[S_TOTAL], se[b].n[S_TOTAL], &m1, &lo, &hi);
            printf("  scalar / %s median time: growth %.2f, completion %.2f\n", backend_name[b],
                   g0 / g1, m0 / m1);
        }
    printf("  peak resident memory: %.1f MiB\n", (double)bench_peak_rss_kib() / 1024.0);
    if (out)
        fclose(out);
    prepared_clear(&pp);
    relief_mesh_destroy(cap);
    free(se);
    return 0;
fail:
    fprintf(stderr, "bench_complete %s: %s\n", c.name, err.message);
    if (out)
        fclose(out);
    prepared_clear(&pp);
    relief_mesh_destroy(cap);
    free(se);
    return 2;
}
