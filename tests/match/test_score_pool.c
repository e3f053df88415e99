/* The host scoring pool (score_pool.h) against the scalar reference's loop:
 * with a fixed cutoff every flag and score is the same whatever the thread
 * count; with a running cutoff the best set (VALID within 1.1 x the
 * minimum), the growth's only use of the scores, is the same candidates
 * with the same scores; the probes that bound a launch's cutoff give the
 * same minimum. Random targets of two surfaces, all the samples, a third
 * of them and a coherent search's hundred, 1, 2, 3, 5 and 16 threads (a
 * hundred centres take 6 of 16), and a thread's blocks both by the
 * scalar loop and in lock-step (score_lanes.h, where the processor has
 * AVX2). The host matcher (matcher_host.h) is the pool behind the matcher
 * table. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "pipeline.h"
#include "base/rng.h"
#include "match/matcher.h"
#include "match/matcher_host.h"
#include "match/matcher_scalar.h"
#include "match/score_pool.h"
#include "mesh/mesh.h"
#include "smooth/surface.h"

#define RM_REAL float
#define RM_WITH_SCORING
#include "kernels/relief_math.h"

/* Is candidate c of (ssd, flag), n of them, in the best set? */
static int in_best(const float *ssd, const uint8_t *flag, size_t n, size_t c)
{
    double minv = INFINITY;
    for (size_t i = 0; i < n; ++i)
        if (flag[i] == RM_VALID && ssd[i] < minv)
            minv = ssd[i];
    return flag[c] == RM_VALID && (double)ssd[c] <= 1.1 * minv;
}

/* Candidates of (sp, fp) that differ from the scalar loop's (sh, fh), n of
 * them: every flag and score with a fixed cutoff; with a running one, the
 * best set and its scores. */
static size_t count_differ(const float *sh, const uint8_t *fh, const float *sp,
                           const uint8_t *fp, size_t n, int running)
{
    size_t bad = 0;
    for (size_t c = 0; c < n; ++c) {
        if (!running) {
            bad += fp[c] != fh[c] || (fh[c] != RM_INVALID && sp[c] != sh[c]);
        } else {
            int bh = in_best(sh, fh, n, c), bp = in_best(sp, fp, n, c);
            bad += bh != bp || (bh && sp[c] != sh[c]);
        }
    }
    return bad;
}

static void check_surface(relief_synth_kind kind, int colour)
{
    static const int threads[] = {1, 2, 3, 5, RELIEF_SCORE_POOL_MAX};
    relief_surface *s = NULL;
    relief_match_data *d = NULL;
    relief_query_builder *qb = NULL;
    relief_error err = {0};
    relief_rng rng;
    uint8_t *textured = NULL, *fh = NULL, *fp = NULL;
    float *sh = NULL, *spool = NULL;
    uint32_t *sub = NULL;
    size_t nc, best_seen = 0;

    CHECK(pipeline_smooth(kind, 700, colour, &s, &err) == RELIEF_OK, "%s", err.message);
    CHECK(s && relief_match_data_build(s, 4, colour ? 0.5 : 1.0, &d, &err) == RELIEF_OK, "%s",
          err.message);
    CHECK(d && relief_query_builder_create(s, d, &qb, &err) == RELIEF_OK, "%s", err.message);
    if (!qb)
        goto done;
    nc = (size_t)d->ns * 4;
    textured = calloc(d->nv, 1);
    fh = malloc(nc), fp = malloc(nc);
    sh = malloc(nc * sizeof *sh), spool = malloc(nc * sizeof *spool);
    sub = malloc(d->ns * sizeof *sub);
    if (!textured || !fh || !fp || !sh || !spool || !sub)
        goto done;
    for (size_t v = 0; v < s->n_samples; ++v)
        textured[v] = 1;
    relief_rng_seed(&rng, 5);
    for (int trial = 0; trial < 8; ++trial) {
        relief_match_query q;
        const uint32_t t = pipeline_draw_query(qb, s, textured, &rng, 3, &q);
        if (q.n == 0)
            continue;
        if (trial % 2) { /* every third sample, from the last down */
            uint32_t n = 0;
            for (uint32_t i = d->ns; i-- > 0;)
                if (i % 3 == 1)
                    sub[n++] = i;
            q.subset = sub;
            q.n_subset = trial % 4 == 3 && n > 100 ? 100 : n; /* a coherent search's */
        }
        for (int running = 0; running <= 1; ++running) {
            size_t n;
            q.running = running;
            q.cutoff = FLT_MAX;
            if (!running) { /* a fixed cutoff that prunes */
                relief_score_host(d, &q, sh, fh);
                q.cutoff = 0.0f;
                for (size_t c = 0; c < relief_match_query_candidates(d, &q); ++c)
                    if (fh[c] == RM_VALID && 0.5f * sh[c] > q.cutoff)
                        q.cutoff = 0.5f * sh[c];
            }
            n = relief_match_query_candidates(d, &q);
            relief_score_host(d, &q, sh, fh);
            for (size_t k = 0; k < sizeof threads / sizeof threads[0]; ++k) {
                relief_score_pool *pool = NULL;
                size_t bad = 0;
                CHECK(relief_score_pool_create(threads[k], &pool, &err) == RELIEF_OK, "%s",
                      err.message);
                if (!pool)
                    continue;
                memset(fp, 0xff, n);
                relief_score_pool_run(pool, d, &q, spool, fp);
                bad = count_differ(sh, fh, spool, fp, n, running);
                for (size_t c = 0; running && k == 0 && c < n; ++c)
                    best_seen += in_best(sh, fh, n, c);
                CHECK(bad == 0, "%s colour %d, target %u, %s, %s cutoff, %d threads: %zu of %zu "
                      "candidates differ", relief_synth_kind_name(kind), colour, (unsigned)t,
                      q.subset ? "subset" : "all samples", running ? "running" : "fixed",
                      threads[k], bad, n);
                if (running) { /* the OpenCL matcher's probes: the same minimum */
                    const size_t probes = n < 512 ? n : 512;
                    const float a = relief_score_host_probe(d, &q, probes, 0, 1);
                    const float b = relief_score_pool_probe(pool, d, &q, probes);
                    CHECK(a == b && a < FLT_MAX, "%s, target %u, %d threads: probe minimum %g, "
                          "one thread %g", relief_synth_kind_name(kind), (unsigned)t,
                          threads[k], b, a);
                }
                relief_score_pool_destroy(pool);
            }
            /* Both ways of scoring a thread's blocks, whatever the pool
             * picked on this processor: the scalar loop, and the lanes
             * where the processor has them. */
            for (int lanes = 0; lanes <= relief_host_lanes_supported(); ++lanes) {
                size_t bad = 0;
                memset(fp, 0xff, n);
                for (uint32_t k = 0; k < 3; ++k)
                    relief_score_host_blocks(d, &q, k, 3, lanes, spool, fp);
                bad = count_differ(sh, fh, spool, fp, n, running);
                CHECK(bad == 0, "%s colour %d, target %u, %s cutoff, blocks %s: %zu of %zu "
                      "candidates differ", relief_synth_kind_name(kind), colour, (unsigned)t,
                      running ? "running" : "fixed", lanes ? "in lanes" : "scalar", bad, n);
            }
        }
    }
    CHECK(best_seen > 0, "%s: no best set compared", relief_synth_kind_name(kind));
done:
    free(sub), free(spool), free(sh), free(fp), free(fh), free(textured);
    relief_query_builder_destroy(qb);
    relief_match_data_destroy(d);
    relief_surface_destroy(s);
}

int main(void)
{
    relief_score_pool *pool = NULL;
    relief_error err = {0};
    CHECK(relief_score_pool_create(0, &pool, &err) == RELIEF_E_RANGE && !pool,
          "0 threads accepted");
    CHECK(relief_score_pool_create(RELIEF_SCORE_POOL_MAX + 1, &pool, &err) == RELIEF_E_RANGE,
          "too many threads accepted");
    CHECK(relief_score_pool_default_threads() >= 1, "no default thread count");
    relief_score_pool_destroy(NULL);
    {
        relief_matcher *m = NULL;
        CHECK(relief_matcher_host_create(NULL, 0, &m, &err) == RELIEF_OK && m &&
                  m->backend == RELIEF_BACKEND_HOST && strncmp(m->device, "host (", 6) == 0,
              "host matcher: %s", err.message);
        relief_matcher_destroy(m);
        CHECK(relief_matcher_host_create(NULL, RELIEF_SCORE_POOL_MAX + 1, &m, &err) ==
                  RELIEF_E_RANGE, "host matcher: too many threads accepted");
    }
    printf("lock-step scoring on this processor: %s\n",
           relief_host_lanes_supported() ? "yes (AVX2)" : "no (the scalar loop only)");
    check_surface(RELIEF_SYNTH_PLANE_NOISE, 0);
    check_surface(RELIEF_SYNTH_CYLINDER_BANDS, 1);
    return check_result();
}
