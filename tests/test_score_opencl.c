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
#include "grow.h"
#include "matcher.h"
#include "mesh.h"
#include "rng.h"
#include "surface.h"

#define RM_REAL float
#define RM_WITH_SCORING
#include "../kernels/relief_math.h"

/* The textured neighbourhood of target t within `reach` of it, in t's
 * frame, as the growth builds it (samples only: nothing is grown yet). */
static uint32_t neighbourhood(const relief_surface *s, size_t t, double reach, float *qp,
                              float *q, float *g, float *qcol, const float *col,
                              float *inv_wsum)
{
    const double *tp = s->proj + 3 * t, *rt = s->frame + 9 * t;
    uint32_t n = 0;
    double wsum = 0.0;
    for (size_t v = 0; v < s->n_samples && n < 64; ++v) {
        const double *vp = s->proj + 3 * v, *vr = s->mesh->pos + 3 * v;
        double d[3] = {vp[0] - tp[0], vp[1] - tp[1], vp[2] - tp[2]};
        double dd = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) / reach;
        if (dd > 1.0)
            continue;
        for (int r = 0; r < 3; ++r) {
            const double *ax = rt + 3 * r;
            qp[3 * n + r] = (float)(ax[0] * d[0] + ax[1] * d[1] + ax[2] * d[2]);
            q[3 * n + r] = (float)(ax[0] * (vr[0] - tp[0]) + ax[1] * (vr[1] - tp[1]) +
                                   ax[2] * (vr[2] - tp[2]));
            qcol[3 * n + r] = col[3 * v + r];
        }
        g[n] = (float)exp(-0.5 * dd * dd);
        wsum += g[n];
        ++n;
    }
    *inv_wsum = (float)(1.0 / wsum);
    return n;
}

static int compare_surface(relief_synth_kind kind, int colour)
{
    relief_synth_params sp = relief_synth_params_default();
    relief_params p = relief_params_default();
    relief_mesh *cap = NULL;
    relief_surface *s = NULL;
    relief_match_data *d = NULL;
    relief_matcher *ms = NULL, *mo = NULL;
    relief_error err = {RELIEF_OK, ""};
    relief_rng rng;
    float qp[192], q[192], g[64], qcol[192];
    float *ss = NULL, *so = NULL;
    uint8_t *fs = NULL, *fo = NULL;
    size_t compared = 0, bad_flag = 0, bad_ssd = 0, pruned = 0, invalid = 0;
    int skip = 0;

    sp.kind = kind;
    sp.vertices = 700;
    sp.colour = colour;
    CHECK(relief_synth(&sp, &cap, NULL, &err) == RELIEF_OK, "%s", err.message);
    CHECK(relief_smooth(cap, &p, NULL, &s, &err) == RELIEF_OK, "%s", err.message);
    CHECK(s && relief_match_data_build(s, 4, colour ? 0.5 : 1.0, &d, &err) == RELIEF_OK, "%s",
          err.message);
    if (!d)
        goto done;
    if (relief_matcher_opencl_create(d, -1, &mo, &err) != RELIEF_OK) {
        if (strstr(err.message, "no OpenCL platform")) {
            skip = 1;
            goto done;
        }
        CHECK(0, "OpenCL matcher: %s", err.message);
        goto done;
    }
    relief_matcher_scalar_create(d, &ms, &err);
    {
        size_t nc = (size_t)d->ns * 4;
        ss = malloc(nc * sizeof *ss), so = malloc(nc * sizeof *so);
        fs = malloc(nc), fo = malloc(nc);
        relief_rng_seed(&rng, 11);
        for (int trial = 0; trial < 6; ++trial) {
            size_t t = s->n_samples + relief_rng_below(&rng, (uint32_t)s->n_targets);
            relief_match_query qr;
            qr.n = neighbourhood(s, t, 3.0 * s->spacing, qp, q, g, qcol, d->col, &qr.inv_wsum);
            if (qr.n == 0)
                continue; /* deep inside the missing part: no neighbour yet */
            qr.qp = qp, qr.q = q, qr.g = g, qr.qcol = qcol, qr.running = 0;
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
        }
    }
    printf("%s colour %d: %zu candidates compared, %zu pruned, %zu invalid\n",
           relief_synth_kind_name(kind), colour, compared, pruned, invalid);
    CHECK(compared > 0 && bad_flag == 0, "%s: %zu of %zu flags differ",
          relief_synth_kind_name(kind), bad_flag, compared);
    CHECK(bad_ssd == 0, "%s: %zu of %zu scores differ beyond 1e-5",
          relief_synth_kind_name(kind), bad_ssd, compared);
    CHECK(pruned > 0 && invalid > 0, "%s: the cases should include pruned (%zu) and invalid "
          "(%zu) candidates", relief_synth_kind_name(kind), pruned, invalid);
done:
    free(ss), free(so), free(fs), free(fo);
    relief_matcher_destroy(mo);
    relief_matcher_destroy(ms);
    relief_match_data_destroy(d);
    relief_surface_destroy(s);
    relief_mesh_destroy(cap);
    return skip;
}

/* A whole completion with each backend: the same seed, the same bytes. */
static void compare_completion(relief_synth_kind kind, int colour)
{
    relief_surface *out[2] = {NULL, NULL};
    for (int b = 0; b < 2; ++b) {
        relief_synth_params sp = relief_synth_params_default();
        relief_params p = relief_params_default();
        relief_grow_options go = relief_grow_options_default();
        relief_grow_stats stats;
        relief_mesh *cap = NULL;
        relief_match_data *d = NULL;
        relief_matcher *m = NULL;
        relief_error err = {RELIEF_OK, ""};
        relief_status st;
        sp.kind = kind;
        sp.vertices = 500;
        sp.colour = colour;
        p.window = 2;
        st = relief_synth(&sp, &cap, NULL, &err);
        if (st == RELIEF_OK)
            st = relief_smooth(cap, &p, NULL, &out[b], &err);
        if (st == RELIEF_OK)
            st = relief_match_data_build(out[b], p.rotations, relief_grow_mu(&p, colour), &d,
                                         &err);
        if (st == RELIEF_OK)
            st = b ? relief_matcher_opencl_create(d, -1, &m, &err)
                   : relief_matcher_scalar_create(d, &m, &err);
        if (st == RELIEF_OK)
            st = relief_grow(out[b], d, m, &p, &go, &stats, &err);
        CHECK(st == RELIEF_OK, "%s backend %d: %s", relief_synth_kind_name(kind), b,
              err.message);
        relief_matcher_destroy(m);
        relief_match_data_destroy(d);
        relief_mesh_destroy(cap);
    }
    if (out[0] && out[1]) {
        const relief_mesh *a = out[0]->mesh, *b = out[1]->mesh;
        CHECK(a->nv == b->nv && memcmp(a->pos, b->pos, 3 * a->nv * sizeof(double)) == 0 &&
                  (!a->col || memcmp(a->col, b->col, 3 * a->nv * sizeof(float)) == 0),
              "%s colour %d: scalar and OpenCL completions differ",
              relief_synth_kind_name(kind), colour);
    }
    relief_surface_destroy(out[0]);
    relief_surface_destroy(out[1]);
}

int main(void)
{
    if (compare_surface(RELIEF_SYNTH_PLANE_WAVES, 0)) {
        printf("no OpenCL platform: skipped\n");
        return 77;
    }
    compare_surface(RELIEF_SYNTH_PLANE_NOISE, 1);
    compare_surface(RELIEF_SYNTH_CYLINDER_BARK, 0);
    compare_surface(RELIEF_SYNTH_SPHERE_DIMPLES, 1);
    compare_completion(RELIEF_SYNTH_PLANE_WAVES, 1);
    compare_completion(RELIEF_SYNTH_CYLINDER_BANDS, 0);
    compare_completion(RELIEF_SYNTH_SPHERE_DIMPLES, 1);
    return check_result();
}
