/* The OpenCL matcher against the scalar reference: every (sample, rotation)
 * score of random targets on several surfaces (relative tolerance 1e-5,
 * absolute near zero, identical invalid and pruned flags), and whole
 * completions that must come out byte-identical. Skips (77) only where no
 * OpenCL platform exists. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "base/params.h"
#include "pipeline.h"
#include "base/rng.h"
#include "grow/grow.h"
#include "match/matcher.h"
#include "match/matcher_opencl.h"
#include "match/matcher_scalar.h"
#include "mesh/mesh.h"
#include "smooth/surface.h"

#define RM_REAL float
#define RM_WITH_SCORING
#include "kernels/relief_math.h"

/* The running query again over the samples reordered so that the one with
 * the minimum comes first and the other best-set members last: a launch's
 * later chunks then hold members whose SSD lies above the minimum the
 * first chunk found, which its cutoff must still let through (just over
 * 1.1 x, not the minimum itself). ss and fs hold the scalar loop's
 * results over all samples; returns the samples put last. */
static size_t check_best_last(relief_matcher *ms, relief_matcher *mo,
                              const relief_match_data *d, relief_match_query *qr,
                              const float *ss, const uint8_t *fs, float min_s,
                              relief_synth_kind kind, int trial)
{
    const size_t nc = (size_t)d->ns * 4;
    uint32_t *sub = malloc(d->ns * sizeof *sub), nsub = 0, first = UINT32_MAX;
    uint8_t *best = calloc(d->ns, 1), *f1 = malloc(nc), *f2 = malloc(nc);
    float *s1 = malloc(nc * sizeof *s1), *s2 = malloc(nc * sizeof *s2);
    size_t late = 0, differ = 0, loose = 0;
    float min_o = FLT_MAX;
    relief_error err = {0};
    CHECK(sub && best && f1 && f2 && s1 && s2, "out of memory");
    if (!sub || !best || !f1 || !f2 || !s1 || !s2)
        goto done;
    for (size_t c = 0; c < nc; ++c)
        if (fs[c] == RM_VALID && (double)ss[c] <= 1.1 * min_s) {
            best[c / 4] = 1;
            if (ss[c] == min_s && first == UINT32_MAX)
                first = (uint32_t)(c / 4);
        }
    sub[nsub++] = first;
    for (uint32_t i = 0; i < d->ns; ++i)
        if (!best[i])
            sub[nsub++] = i;
    for (uint32_t i = 0; i < d->ns; ++i)
        if (best[i] && i != first) {
            sub[nsub++] = i;
            late += 1;
        }
    qr->subset = sub;
    qr->n_subset = nsub;
    qr->running = 1;
    CHECK(relief_matcher_score(ms, d, qr, s1, f1, &err) == RELIEF_OK, "%s", err.message);
    CHECK(relief_matcher_score(mo, d, qr, s2, f2, &err) == RELIEF_OK, "%s", err.message);
    for (size_t c = 0; c < (size_t)nsub * 4; ++c)
        if (f2[c] == RM_VALID && s2[c] < min_o)
            min_o = s2[c];
    for (size_t c = 0; c < (size_t)nsub * 4; ++c) {
        const size_t full = (size_t)sub[c / 4] * 4 + c % 4;
        const int member = fs[full] == RM_VALID && (double)ss[full] <= 1.1 * min_s;
        const int in1 = f1[c] == RM_VALID && (double)s1[c] <= 1.1 * min_s;
        const int in2 = f2[c] == RM_VALID && (double)s2[c] <= 1.1 * min_o;
        differ += member != in1 || (member && s1[c] != ss[full]);
        differ += member != in2 || (member && fabsf(s2[c] - ss[full]) > 1e-5f * ss[full]);
        /* Past the first chunk the cutoff is the minimum's, and nothing
         * above it may come out valid. */
        loose += c >= RELIEF_OPENCL_CHUNK_FIRST && f2[c] == RM_VALID &&
                 s2[c] > relief_match_cutoff_after(min_o);
    }
    CHECK(differ == 0, "%s trial %d: best set last: %zu candidates in or out wrongly",
          relief_synth_kind_name(kind), trial, differ);
    if (nc > RELIEF_OPENCL_CHUNK_FIRST) {
        CHECK((nsub - late) * (size_t)4 >= RELIEF_OPENCL_CHUNK_FIRST,
              "%s trial %d: the members put last are not past the first chunk",
              relief_synth_kind_name(kind), trial);
        CHECK(loose == 0, "%s trial %d: %zu candidates past the first chunk are valid above "
              "the cutoff of its minimum", relief_synth_kind_name(kind), trial, loose);
    }
done:
    qr->subset = NULL;
    qr->n_subset = 0;
    qr->running = 0;
    free(s2), free(s1), free(f2), free(f1), free(best), free(sub);
    return late;
}

static int compare_surface(relief_synth_kind kind, int colour, size_t vertices)
{
    relief_synth_params sp = relief_synth_params_default();
    relief_params p = relief_params_default();
    relief_mesh *cap = NULL;
    relief_surface *s = NULL;
    relief_match_data *d = NULL;
    relief_matcher *ms = NULL, *mo = NULL;
    relief_error err = {0};
    relief_rng rng;
    relief_query_builder *qb = NULL;
    uint8_t *textured = NULL;
    float *ss = NULL, *so = NULL;
    uint8_t *fs = NULL, *fo = NULL;
    size_t compared = 0, bad_flag = 0, bad_ssd = 0, pruned = 0, invalid = 0;
    size_t running_best = 0, running_late = 0;
    int skip = 0;

    sp.kind = kind;
    sp.vertices = vertices;
    sp.colour = colour;
    CHECK(relief_synth(&sp, &cap, NULL, &err) == RELIEF_OK, "%s", err.message);
    CHECK(relief_surface_build(cap, &p, NULL, &s, &err) == RELIEF_OK, "%s", err.message);
    CHECK(s && relief_match_data_build(s, 4, colour ? 0.5 : 1.0, &d, &err) == RELIEF_OK, "%s",
          err.message);
    if (!d)
        goto done;
    if (relief_matcher_opencl_create(d, -1, 0, &mo, &err) != RELIEF_OK) {
        if (strstr(err.message, "no OpenCL platform")) {
            skip = 1;
            goto done;
        }
        CHECK(0, "OpenCL matcher: %s", err.message);
        goto done;
    }
    relief_matcher_scalar_create(d, &ms, &err);
    CHECK(relief_query_builder_create(s, d, &qb, &err) == RELIEF_OK, "%s", err.message);
    textured = calloc(d->nv, 1);
    if (!qb || !textured)
        goto done;
    for (size_t v = 0; v < s->n_samples; ++v)
        textured[v] = 1; /* the first pass: only the samples are textured */
    {
        size_t nc = (size_t)d->ns * 4;
        ss = malloc(nc * sizeof *ss), so = malloc(nc * sizeof *so);
        fs = malloc(nc), fo = malloc(nc);
        relief_rng_seed(&rng, 11);
        for (int trial = 0; trial < 6; ++trial) {
            relief_match_query qr;
            pipeline_draw_query(qb, s, textured, &rng, 3, &qr);
            CHECK(qr.n > 0, "%s: no target with a textured neighbour",
                  relief_synth_kind_name(kind));
            if (qr.n == 0)
                continue;
            /* Half the trials with no cutoff, half with one that prunes. */
            qr.cutoff = FLT_MAX;
            if (trial % 2) {
                CHECK(relief_matcher_score(ms, d, &qr, ss, fs, &err) == RELIEF_OK, "%s",
                      err.message);
                qr.cutoff = 0.0f;
                for (size_t c = 0; c < nc; ++c)
                    if (fs[c] == RM_VALID)
                        qr.cutoff = fmaxf(qr.cutoff, 0.25f * ss[c]);
            }
            CHECK(relief_matcher_score(ms, d, &qr, ss, fs, &err) == RELIEF_OK, "%s",
                  err.message);
            CHECK(relief_matcher_score(mo, d, &qr, so, fo, &err) == RELIEF_OK, "%s",
                  err.message);
            if (trial % 2 == 0) {
                /* A subset of the samples (the hierarchy's sample pyramids),
                 * out of order: each backend scores exactly those
                 * candidates, and as the full search scored them. */
                uint32_t *sub = malloc(d->ns * sizeof *sub), nsub = 0;
                float *sub_s = malloc(nc * sizeof *sub_s), *sub_o = malloc(nc * sizeof *sub_o);
                uint8_t *sub_fs = malloc(nc), *sub_fo = malloc(nc);
                CHECK(sub && sub_s && sub_o && sub_fs && sub_fo, "out of memory");
                if (sub && sub_s && sub_o && sub_fs && sub_fo) {
                    for (uint32_t i = d->ns; i-- > 0;)
                        if (i % 3 == (uint32_t)trial % 3)
                            sub[nsub++] = i;
                    qr.subset = sub;
                    qr.n_subset = nsub;
                    CHECK(relief_match_query_candidates(d, &qr) == (size_t)nsub * 4,
                          "subset candidates");
                    CHECK(relief_matcher_score(ms, d, &qr, sub_s, sub_fs, &err) == RELIEF_OK,
                          "%s", err.message);
                    CHECK(relief_matcher_score(mo, d, &qr, sub_o, sub_fo, &err) == RELIEF_OK,
                          "%s", err.message);
                    for (size_t c = 0; c < (size_t)nsub * 4; ++c) {
                        size_t full = (size_t)sub[c / 4] * 4 + c % 4;
                        CHECK(sub_fs[c] == fs[full] && sub_fo[c] == fs[full] &&
                                  (fs[full] == RM_INVALID ||
                                   (sub_s[c] == ss[full] &&
                                    fabs(sub_o[c] - ss[full]) <= 1e-5 * fabs(ss[full]))),
                              "subset candidate %zu (sample %u) scores differently",
                              c, (unsigned)sub[c / 4]);
                    }
                    qr.subset = NULL;
                    qr.n_subset = 0;
                }
                free(sub), free(sub_s), free(sub_o), free(sub_fs), free(sub_fo);
            }
            for (size_t c = 0; c < nc; ++c) {
                ++compared;
                pruned += fs[c] == RM_PRUNED;
                invalid += fs[c] == RM_INVALID;
                if (fs[c] != fo[c]) {
                    ++bad_flag;
                } else if (fs[c] != RM_INVALID) {
                    double a = ss[c], b = so[c], tol = 1e-5 * fmax(fabs(a), fabs(b)) + 1e-12;
                    bad_ssd += fabs(a - b) > tol;
                }
            }
            /* The growth's own query, with a running cutoff: whatever
             * each backend cuts short on the way (the OpenCL matcher
             * splits a large launch into chunks, each pruning under the
             * minimum so far), the best set and its scores are the scalar
             * loop's. */
            qr.running = 1;
            qr.cutoff = FLT_MAX; /* as the growth starts it */
            CHECK(relief_matcher_score(ms, d, &qr, ss, fs, &err) == RELIEF_OK, "%s",
                  err.message);
            CHECK(relief_matcher_score(mo, d, &qr, so, fo, &err) == RELIEF_OK, "%s",
                  err.message);
            qr.running = 0;
            {
                float min_s = FLT_MAX, min_o = FLT_MAX;
                size_t in_s = 0, in_o = 0, differ = 0;
                for (size_t c = 0; c < nc; ++c) {
                    if (fs[c] == RM_VALID && ss[c] < min_s)
                        min_s = ss[c];
                    if (fo[c] == RM_VALID && so[c] < min_o)
                        min_o = so[c];
                }
                for (size_t c = 0; c < nc; ++c) {
                    int a = fs[c] == RM_VALID && (double)ss[c] <= 1.1 * min_s;
                    int b = fo[c] == RM_VALID && (double)so[c] <= 1.1 * min_o;
                    in_s += a, in_o += b;
                    differ += a != b || (a && fabs(ss[c] - so[c]) > 1e-5 * ss[c] + 1e-12);
                }
                CHECK(min_s < FLT_MAX && in_s > 0 && differ == 0,
                      "%s trial %d: running query, %zu of %zu (scalar) / %zu (OpenCL) best-set "
                      "members differ", relief_synth_kind_name(kind), trial, differ, in_s, in_o);
                running_best += in_s;
                if (min_s < FLT_MAX)
                    running_late += check_best_last(ms, mo, d, &qr, ss, fs, min_s, kind, trial);
            }
        }
    }
    printf("%s colour %d: %zu candidates compared, %zu pruned, %zu invalid; running "
           "queries: %zu best-set members alike; %zu samples with members scored last\n",
           relief_synth_kind_name(kind), colour, compared, pruned, invalid, running_best,
           running_late);
    if (d && (size_t)d->ns * 4 > RELIEF_OPENCL_CHUNK_FIRST)
        CHECK(running_late > 0, "%s: no best-set member was left to a later chunk",
              relief_synth_kind_name(kind));
    CHECK(compared > 0 && bad_flag == 0, "%s: %zu of %zu flags differ",
          relief_synth_kind_name(kind), bad_flag, compared);
    CHECK(bad_ssd == 0, "%s: %zu of %zu scores differ beyond 1e-5",
          relief_synth_kind_name(kind), bad_ssd, compared);
    CHECK(pruned > 0 && invalid > 0, "%s: the cases should include pruned (%zu) and invalid "
          "(%zu) candidates", relief_synth_kind_name(kind), pruned, invalid);
done:
    free(ss), free(so), free(fs), free(fo);
    free(textured);
    relief_query_builder_destroy(qb);
    relief_matcher_destroy(mo);
    relief_matcher_destroy(ms);
    relief_match_data_destroy(d);
    relief_surface_destroy(s);
    relief_mesh_destroy(cap);
    return skip;
}

/* The scalar completions made so far, by their pipeline: the lane and
 * host_max settings change only the OpenCL side, so each reference is
 * grown once (under ASan a scalar growth is most of a comparison). */
#define REFERENCES 16
typedef struct reference {
    pipeline pl;
    relief_surface *out;
} reference;
static reference references[REFERENCES];
static size_t n_references;

static int same_pipeline(const pipeline *a, const pipeline *b)
{
    return a->kind == b->kind && a->vertices == b->vertices && a->colour == b->colour &&
           a->seed == b->seed && a->window == b->window && a->prune == b->prune &&
           a->bootstrap == b->bootstrap && a->opencl == b->opencl && a->search == b->search;
}

/* The scalar completion of pl (opencl 0), grown on first use; NULL when
 * it failed (a CHECK says why). Freed by free_references. */
static const relief_surface *scalar_reference(const pipeline *pl)
{
    relief_surface *out = NULL;
    relief_grow_stats stats;
    relief_error err = {0};
    for (size_t i = 0; i < n_references; ++i)
        if (same_pipeline(&references[i].pl, pl))
            return references[i].out;
    CHECK(pipeline_run(pl, &out, &stats, &err) == RELIEF_OK, "%s scalar: %s",
          relief_synth_kind_name(pl->kind), err.message);
    CHECK(n_references < REFERENCES, "more than %d scalar references: raise REFERENCES",
          REFERENCES);
    if (out && n_references < REFERENCES)
        references[n_references++] = (reference){*pl, out};
    else
        relief_surface_destroy(out), out = NULL;
    return out;
}

static void free_references(void)
{
    for (size_t i = 0; i < n_references; ++i)
        relief_surface_destroy(references[i].out);
    n_references = 0;
}

/* A whole completion with each backend: the same seed, the same bytes.
 * host_max sets RELIEF_OPENCL_HOST_MAX for the OpenCL matcher ("0": every
 * query is a launch; NULL: the device's default, which at this size
 * scores most queries on the host). The matcher writes textured targets
 * to the device only before a launch that reads them; with bootstrap
 * those targets are matchable too. */
static void compare_completion(relief_synth_kind kind, int colour, int bootstrap,
                               const char *host_max, relief_search_mode search)
{
    const pipeline ref = {kind, 500, colour, 1, 2, 1, bootstrap, 0, search};
    const pipeline pl = {kind, 500, colour, 1, 2, 1, bootstrap, 1, search};
    const relief_surface *out[2] = {scalar_reference(&ref), NULL};
    relief_surface *ocl = NULL;
    relief_grow_stats stats;
    relief_error err = {0};
    if (host_max)
        setenv("RELIEF_OPENCL_HOST_MAX", host_max, 1);
    else
        unsetenv("RELIEF_OPENCL_HOST_MAX");
    CHECK(pipeline_run(&pl, &ocl, &stats, &err) == RELIEF_OK, "%s OpenCL: %s",
          relief_synth_kind_name(kind), err.message);
    out[1] = ocl;
    if (out[0] && out[1]) {
        const relief_mesh *a = out[0]->mesh, *b = out[1]->mesh;
        CHECK(a->nv == b->nv && memcmp(a->pos, b->pos, 3 * a->nv * sizeof(double)) == 0 &&
                  (!a->col || memcmp(a->col, b->col, 3 * a->nv * sizeof(float)) == 0),
              "%s colour %d bootstrap %d host_max %s search %s: scalar and OpenCL completions "
              "differ", relief_synth_kind_name(kind), colour, bootstrap,
              host_max ? host_max : "default", relief_search_name(search));
    }
    relief_surface_destroy(ocl);
}

/* Each kernel on this device: RELIEF_OPENCL_LANES unset (a CPU device
 * runs score_lanes with 16 lanes, another device score), "1" (score), and
 * odd lane counts (score_lanes with a partly idle last register). */
static const char *const lane_settings[] = {NULL, "1", "5", "32"};

static void set_lanes(const char *lanes)
{
    if (lanes)
        setenv("RELIEF_OPENCL_LANES", lanes, 1);
    else
        unsetenv("RELIEF_OPENCL_LANES");
}

int main(void)
{
    /* The sanitize pass: the kernels run inside PoCL, which the sanitizers
     * do not see, and a lane count of 32 drives the host code as 5 does;
     * there the counts up to 5 and one completion sweep show that code to
     * them, and the default pass checks every count. */
    const size_t n_lanes =
        check_sanitize_pass() ? 3 : sizeof lane_settings / sizeof lane_settings[0];
    const size_t n_sweeps = check_sanitize_pass() ? 1 : 2;
    /* Candidate by candidate, the kernel itself: no query on the host
     * (test_score_pool checks the host's split against the scalar loop). */
    setenv("RELIEF_OPENCL_HOST_MAX", "0", 1);
    if (compare_surface(RELIEF_SYNTH_PLANE_WAVES, 0, 700)) {
        printf("no OpenCL platform: skipped\n");
        return 77;
    }
    for (size_t k = 0; k < n_lanes; ++k) {
        set_lanes(lane_settings[k]);
        printf("RELIEF_OPENCL_LANES=%s\n", lane_settings[k] ? lane_settings[k] : "(unset)");
        if (k)
            compare_surface(RELIEF_SYNTH_PLANE_WAVES, 0, 700);
        compare_surface(RELIEF_SYNTH_PLANE_NOISE, 1, 700);
        compare_surface(RELIEF_SYNTH_CYLINDER_BARK, 0, 700);
        compare_surface(RELIEF_SYNTH_SPHERE_DIMPLES, 1, 700);
    }
    set_lanes(NULL);
    /* Large enough that a running query's launch comes in chunks. */
    compare_surface(RELIEF_SYNTH_PLANE_NOISE, 1, 2500);
    {
        /* A lane count out of range is refused, naming the variable. */
        relief_matcher *m = NULL;
        relief_error err = {0};
        static const char *const bad[] = {"0", "65", "x", "8x", "-4"};
        for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
            set_lanes(bad[k]);
            CHECK(relief_matcher_opencl_create(NULL, -1, 0, &m, &err) == RELIEF_E_RANGE && !m &&
                      strstr(err.message, "RELIEF_OPENCL_LANES"),
                  "RELIEF_OPENCL_LANES=%s accepted: %s", bad[k], err.message);
        }
        set_lanes(NULL);
    }
    for (size_t k = 0; k < n_sweeps; ++k) {
        set_lanes(lane_settings[k]);
        compare_completion(RELIEF_SYNTH_PLANE_WAVES, 1, 0, "0", RELIEF_SEARCH_EXHAUSTIVE);
        compare_completion(RELIEF_SYNTH_CYLINDER_BANDS, 0, 0, "0", RELIEF_SEARCH_EXHAUSTIVE);
        compare_completion(RELIEF_SYNTH_SPHERE_DIMPLES, 1, 0, "0", RELIEF_SEARCH_EXHAUSTIVE);
        compare_completion(RELIEF_SYNTH_CYLINDER_BANDS, 1, 1, "0", RELIEF_SEARCH_EXHAUSTIVE);
    }
    set_lanes(NULL);
    compare_completion(RELIEF_SYNTH_SPHERE_DIMPLES, 1, 0, NULL, RELIEF_SEARCH_EXHAUSTIVE);
    compare_completion(RELIEF_SYNTH_CYLINDER_BANDS, 1, 1, NULL, RELIEF_SEARCH_EXHAUSTIVE);
    /* The k-coherence search: small subsets, each a launch ("0") or on the
     * host (default). */
    compare_completion(RELIEF_SYNTH_CYLINDER_BARK, 1, 0, "0", RELIEF_SEARCH_COHERENT);
    compare_completion(RELIEF_SYNTH_SPHERE_DIMPLES, 0, 0, NULL, RELIEF_SEARCH_COHERENT);
    free_references();
    return check_result();
}
