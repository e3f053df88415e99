/* Scoring one candidate (DESIGN.md "Scoring one candidate"): hand-computed
 * cases on a tiny grid, the point-triangle distance, the exact closest-
 * vertex search, and pruning that never changes the best set. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "base/params.h"
#include "base/rng.h"
#include "match/matcher.h"
#include "mesh/mesh.h"
#include "smooth/surface.h"

#define RM_REAL float
#define RM_WITH_SCORING
#include "kernels/relief_math.h"

/* A 5 x 5 grid of unit spacing on the plane z = 0: vertex j * 5 + i at
 * (i, j, h), diagonals from (i, j) to (i + 1, j + 1); identity frames.
 * Every vertex is a sample but `target`. */
static relief_surface *grid_surface(const double *h, int target, int colour)
{
    relief_surface *s = calloc(1, sizeof *s);
    relief_error err;
    size_t t = 0;
    relief_mesh_create(25, 32, RELIEF_MESH_LABELS | (colour ? RELIEF_MESH_COLOURS : 0u),
                       &s->mesh, &err);
    s->proj = calloc(75, sizeof(double));
    s->disp = calloc(75, sizeof(double));
    s->nrm = calloc(75, sizeof(double));
    s->frame = calloc(225, sizeof(double));
    for (int v = 0; v < 25; ++v) {
        double *p = s->mesh->pos + 3 * v;
        p[0] = v % 5, p[1] = v / 5, p[2] = h ? h[v] : 0.0;
        s->proj[3 * v] = p[0], s->proj[3 * v + 1] = p[1];
        s->disp[3 * v + 2] = p[2];
        s->nrm[3 * v + 2] = 1.0;
        s->frame[9 * v] = 1.0, s->frame[9 * v + 4] = 1.0, s->frame[9 * v + 8] = 1.0;
    }
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
            uint32_t a = (uint32_t)(j * 5 + i);
            uint32_t *f = s->mesh->tri + 3 * t;
            f[0] = a, f[1] = a + 1, f[2] = a + 6, f[3] = a, f[4] = a + 6, f[5] = a + 5;
            t += 2;
        }
    /* Samples first, as relief_surface_build lays them out: move the target last by
     * swapping it with vertex 24 everywhere. */
    if (target != 24) {
        for (int k = 0; k < 3; ++k) {
            double tmp = s->mesh->pos[3 * target + k];
            s->mesh->pos[3 * target + k] = s->mesh->pos[72 + k];
            s->mesh->pos[72 + k] = tmp;
            tmp = s->proj[3 * target + k];
            s->proj[3 * target + k] = s->proj[72 + k];
            s->proj[72 + k] = tmp;
            tmp = s->disp[3 * target + k];
            s->disp[3 * target + k] = s->disp[72 + k];
            s->disp[72 + k] = tmp;
        }
        for (size_t i = 0; i < 3 * t; ++i)
            if (s->mesh->tri[i] == (uint32_t)target)
                s->mesh->tri[i] = 24;
            else if (s->mesh->tri[i] == 24)
                s->mesh->tri[i] = (uint32_t)target;
    }
    s->n_samples = 24;
    s->n_targets = 1;
    s->spacing = 1.0;
    return s;
}

/* Id of the vertex at grid (i, j) after the swap of `target` with 24. */
static uint32_t at(int i, int j, int target)
{
    int v = j * 5 + i;
    return (uint32_t)(v == target ? 24 : v == 24 ? target : v);
}

static int score(const relief_match_data *d, uint32_t s, int r, const float *qp,
                 const float *q, const float *qcol, uint32_t n, float *ssd)
{
    float g[8] = {1, 1, 1, 1, 1, 1, 1, 1};
    return rm_score_candidate(d->proj, d->pos, d->col, d->matchable, d->tri, d->vt_start,
                              d->vt, d->cell_start, d->cell_items, d->grid, d->dims,
                              d->lgrid, d->ldims, d->lmask, d->lslot, d->litems,
                              d->s_proj + 3 * s, d->s_frame + 9 * s, d->cos_r[r],
                              d->sin_r[r], n, qp, q, g, qcol, d->mu, d->inv_b2,
                              1.0f / (float)n, FLT_MAX, ssd);
}

static void test_hand_cases(void)
{
    const int target = 12; /* grid (2, 2) */
    relief_match_data *d = NULL;
    relief_error err;
    float ssd;
    int f;

    /* Flat: any valid candidate scores 0. Neighbour (1, 2) seen from the
     * target (2, 2) is at offset (-1, 0, 0). */
    {
        relief_surface *s = grid_surface(NULL, target, 0);
        const float qp[3] = {-1, 0, 0}, q[3] = {-1, 0, 0};
        CHECK(relief_match_data_build(s, 4, 1.0, &d, &err) == RELIEF_OK, "%s", err.message);
        f = score(d, at(2, 1, target), 0, qp, q, NULL, 1, &ssd);
        CHECK(f == RM_VALID && ssd == 0.0f, "flat: flag %d ssd %g", f, (double)ssd);
        /* From (3, 2) the neighbour lands on (2, 2), the target: invalid. */
        f = score(d, at(3, 2, target), 0, qp, q, NULL, 1, &ssd);
        CHECK(f == RM_INVALID, "landing on a target: flag %d, expected invalid", f);
        /* Rotated by pi (r = 2 of 4) from (1, 2) it lands on (2, 2) too. */
        f = score(d, at(1, 2, target), 2, qp, q, NULL, 1, &ssd);
        CHECK(f == RM_INVALID, "rotated onto a target: flag %d", f);
        /* The flat capture's shape bound falls back to the spacing. */
        CHECK(fabs(d->b_shape - 1.0) < 1e-12, "flat B_shape %g, expected the spacing 1",
              d->b_shape);
        relief_match_data_destroy(d);
        relief_surface_destroy(s);
    }

    /* Rotation by pi/2: one bump of 0.5 at (1, 2); B_shape = 0.5. The
     * neighbour at offset (1, 0) with height 0.5, scored from s = (1, 1):
     * r = 1 turns it to (0, 1), onto the bump: SSD 0; r = 0 puts it over
     * (2, 1), whose triangles are flat at 0: d^2 = 0.25, SSD 0.25/0.5^2 = 1. */
    {
        double h[25] = {0};
        const float qp[3] = {1, 0, 0}, q[3] = {1, 0, 0.5f};
        relief_surface *s;
        h[11] = 0.5; /* grid (1, 2) */
        s = grid_surface(h, target, 0);
        CHECK(relief_match_data_build(s, 4, 1.0, &d, &err) == RELIEF_OK, "%s", err.message);
        CHECK(fabs(d->b_shape - 0.5) < 1e-12, "B_shape %g, expected 0.5", d->b_shape);
        f = score(d, at(1, 1, target), 1, qp, q, NULL, 1, &ssd);
        CHECK(f == RM_VALID && fabsf(ssd) < 1e-6f, "pi/2: flag %d ssd %g, expected 0", f,
              (double)ssd);
        f = score(d, at(1, 1, target), 0, qp, q, NULL, 1, &ssd);
        CHECK(f == RM_VALID && fabsf(ssd - 1.0f) < 1e-6f, "r = 0: flag %d ssd %g, expected 1",
              f, (double)ssd);
        /* Two neighbours average: (r = 0) one at 0.25 away, one exact. */
        {
            const float qp2[6] = {1, 0, 0, -1, 0, 0}, q2[6] = {1, 0, 0.5f, -1, 0, 0};
            f = score(d, at(1, 1, target), 0, qp2, q2, NULL, 2, &ssd);
            CHECK(f == RM_VALID && fabsf(ssd - 0.5f) < 1e-6f, "two neighbours: ssd %g, "
                  "expected 0.5", (double)ssd);
        }
        relief_match_data_destroy(d);
        relief_surface_destroy(s);
    }

    /* Colour: mu = 0.5, neighbour red (1, 0, 0) over a blue (0, 0, 1)
     * vertex: colour term (1 + 0 + 1) / 3; flat shape term 0. */
    {
        relief_surface *s = grid_surface(NULL, target, 1);
        const float qp[3] = {-1, 0, 0}, q[3] = {-1, 0, 0}, red[3] = {1, 0, 0};
        uint32_t v2 = at(1, 1, target);
        CHECK(relief_match_data_build(s, 4, 0.5, &d, &err) == RELIEF_OK, "%s", err.message);
        for (uint32_t v = 0; v < 25; ++v)
            d->col[3 * v] = 0, d->col[3 * v + 1] = 0, d->col[3 * v + 2] = 1;
        f = score(d, at(2, 1, target), 0, qp, q, red, 1, &ssd);
        CHECK(f == RM_VALID && fabsf(ssd - 0.5f * 2.0f / 3.0f) < 1e-6f,
              "colour: ssd %g, expected %g", (double)ssd, 1.0 / 3.0);
        (void)v2;
        relief_match_data_destroy(d);
        relief_surface_destroy(s);
    }
}

static void test_point_triangle(void)
{
    const float a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 1, 0};
    static const struct {
        float p[3];
        float d2;
        const char *region;
    } cases[] = {{{0.25f, 0.25f, 1}, 1, "face"},     {{-1, -1, 0}, 2, "vertex a"},
                 {{2, 0, 0}, 1, "vertex b"},         {{0, 2, 0}, 1, "vertex c"},
                 {{0.5f, -1, 0}, 1, "edge ab"},      {{-1, 0.5f, 0}, 1, "edge ac"},
                 {{1, 1, 0}, 0.5f, "edge bc"},       {{0.2f, 0.3f, 0}, 0, "on the face"},
                 {{0.5f, -1, 2}, 5, "edge ab, above"}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        float d2 = rm_point_triangle_d2(cases[i].p, a, b, c);
        CHECK(fabsf(d2 - cases[i].d2) < 1e-6f, "point-triangle %s: %g, expected %g",
              cases[i].region, (double)d2, (double)cases[i].d2);
    }
}

/* The lock-step code's branch-free distance (rm_point_triangle_d2_flat)
 * against the reference, bit for bit: random points about random, thin,
 * tiny and degenerate triangles (a point, a segment), points on their
 * vertices and edges, so that every region of the test is met. */
static void test_point_triangle_flat(void)
{
    relief_rng rng;
    size_t differ = 0, n = 0;
    relief_rng_seed(&rng, 11);
    for (int i = 0; i < 200000; ++i) {
        float t[9], p[3], ref, flat;
        const int shape = i % 8;
        for (int k = 0; k < 9; ++k)
            t[k] = (float)(relief_rng_uniform(&rng) * 2.0 - 1.0);
        if (shape == 1) /* a point */
            memcpy(t + 3, t, 3 * sizeof(float)), memcpy(t + 6, t, 3 * sizeof(float));
        else if (shape == 2) /* a segment */
            memcpy(t + 6, t + 3, 3 * sizeof(float));
        else if (shape == 3) /* a sliver */
            for (int k = 0; k < 3; ++k)
                t[6 + k] = t[k] + (t[3 + k] - t[k]) * 0.5f + 1e-6f * (float)k;
        else if (shape == 4) /* tiny */
            for (int k = 3; k < 9; ++k)
                t[k] = t[k % 3] + t[k] * 1e-5f;
        for (int k = 0; k < 3; ++k)
            p[k] = (float)(relief_rng_uniform(&rng) * 3.0 - 1.5);
        if (shape == 5) /* on a vertex */
            memcpy(p, t + 3 * (i / 8 % 3), 3 * sizeof(float));
        else if (shape == 6) /* on an edge */
            for (int k = 0; k < 3; ++k)
                p[k] = t[k] + (t[3 + k] - t[k]) * 0.25f;
        ref = rm_point_triangle_d2(p, t, t + 3, t + 6);
        flat = rm_point_triangle_d2_flat(p[0], p[1], p[2], t[0], t[1], t[2], t[3], t[4], t[5],
                                         t[6], t[7], t[8]);
        differ += memcmp(&ref, &flat, sizeof ref) != 0 && !(isnan(ref) && isnan(flat));
        ++n;
    }
    CHECK(differ == 0, "point-triangle, branch-free: %zu of %zu distances differ from the "
          "reference's bits", differ, n);
}

/* The grid search against brute force, ties to the lowest id included. */
static void test_closest_vertex(void)
{
    relief_synth_params sp = relief_synth_params_default();
    relief_params p = relief_params_default();
    relief_mesh *cap = NULL;
    relief_surface *s = NULL;
    relief_match_data *d = NULL;
    relief_error err;
    relief_rng rng;
    size_t wrong = 0, wrong_listed = 0;

    sp.kind = RELIEF_SYNTH_CYLINDER_BANDS;
    sp.vertices = 600;
    CHECK(relief_synth(&sp, &cap, NULL, &err) == RELIEF_OK, "%s", err.message);
    CHECK(relief_surface_build(cap, &p, NULL, &s, &err) == RELIEF_OK, "%s", err.message);
    CHECK(s && relief_match_data_build(s, 4, 1.0, &d, &err) == RELIEF_OK, "%s", err.message);
    if (!d)
        goto done;
    relief_rng_seed(&rng, 3);
    CHECK(d->n_litems > 0, "no closest-vertex lists were built");
    for (int i = 0; i < 6000; ++i) {
        float x[3];
        uint32_t got, want = 0;
        float best = FLT_MAX;
        /* Around the surface, with some queries exactly on vertices (ties
         * with themselves), many within a spacing of a vertex (where the
         * growth asks: the lists answer), some far outside the grid. */
        if (i % 10 == 0) {
            uint32_t v = relief_rng_below(&rng, d->nv);
            memcpy(x, d->proj + 3 * v, sizeof x);
        } else if (i % 10 >= 4) {
            uint32_t v = relief_rng_below(&rng, d->nv);
            for (int k = 0; k < 3; ++k)
                x[k] = d->proj[3 * v + k] +
                       (float)((relief_rng_uniform(&rng) - 0.5) * 2.0 * s->spacing);
        } else {
            double spread = i % 10 == 1 ? 8.0 : 2.6;
            for (int k = 0; k < 3; ++k)
                x[k] = (float)((relief_rng_uniform(&rng) - 0.5) * spread);
        }
        for (uint32_t v = 0; v < d->nv; ++v) {
            float dx = d->proj[3 * v] - x[0], dy = d->proj[3 * v + 1] - x[1];
            float dz = d->proj[3 * v + 2] - x[2];
            float d2 = dx * dx + dy * dy + dz * dz;
            if (d2 < best) {
                best = d2;
                want = v;
            }
        }
        got = rm_closest_vertex(x, d->proj, d->cell_start, d->cell_items, d->grid, d->dims);
        wrong += got != want;
        got = rm_closest_vertex_listed(x, d->proj, d->cell_start, d->cell_items, d->grid,
                                       d->dims, d->lgrid, d->ldims, d->lmask, d->lslot,
                                       d->litems);
        wrong_listed += got != want;
    }
    CHECK(wrong == 0, "closest vertex: %zu of 6000 queries disagree with brute force", wrong);
    CHECK(wrong_listed == 0,
          "closest vertex from the lists: %zu of 6000 queries disagree with brute force",
          wrong_listed);
done:
    relief_match_data_destroy(d);
    relief_surface_destroy(s);
    relief_mesh_destroy(cap);
}

int main(void)
{
    test_hand_cases();
    test_point_triangle();
    test_point_triangle_flat();
    test_closest_vertex();
    return check_result();
}
