/* Tests of host/report/pattern.c, pattern_grid.c and pattern_layout.c:
 * stripes on a plane whose completed part runs the same way or turned by
 * hand; the same stripes in colour; the cylinder-bark truth against
 * itself (the floor) and against a completion made by hand from its
 * captured relief turned by 45 and 90 degrees; isotropic noise against
 * itself; the lean's layout: swaying or straight ridges completed as
 * chevrons (flagged) or as zigzags in phase (not); bad input, NaN cases,
 * determinism and the JSON keys.
 *
 * Thresholds were set from measured values (printed by this test; the
 * figures in each comment are the ones measured when it was written):
 * a "small" bound is at least 1.5 times the value measured (most are 2
 * or more), a "large" one at least 0.15 below it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "base/error.h"
#include "base/json.h"
#include "base/rng.h"
#include "mesh/mesh.h"
#include "report/pattern.h"
#include "smooth/fit.h"
#include "smooth/param.h"

#define PI 3.14159265358979323846

static const relief_fit_primitive plane_z = {RELIEF_FIT_PLANE, {0, 0, 0}, {0, 0, 1}, 0.0};

/* Fields over the plane's parameter domain (u, v) (param.h's frame of
 * plane_z, whatever it is: the tests name directions in (u, v)). */
typedef struct field {
    int kind;      /* see field_value */
    double angle;  /* stripes' wave vector, radians from u toward v */
    double angle1; /* the same on the completed part */
    double amp1;   /* the completed part's amplitude factor */
    relief_rng rng;
    int kind1;     /* the completed part's kind; 0: the same as `kind` */
} field;

enum { SAME, STRIPES, NOISE, MEANDER, CHEVRON, ZIGZAG };

/* The lean of the layout kinds' ridges, 25 degrees (the demo's chevrons
 * lean 15 to 30), and the width of their bands of one lean, 1.5
 * wavelengths. */
#define LEAN_DEG 25.0
#define BAND 0.15

/* A triangle wave of slope +-1 and period 2 w: the fold of x into [0, w]. */
static double tri(double x, double w)
{
    double t = fmod(x, 2.0 * w);
    if (t < 0.0)
        t += 2.0 * w;
    return t <= w ? t : 2.0 * w - t;
}

/* Stripes of wavelength 0.1 (10 cycles per unit); white noise; or ridges
 * along v (wavelength 0.1 across them, k along u) laid out three ways,
 * each leaning up to LEAN_DEG from v:
 * - MEANDER: every ridge swaying in phase, x = u - A sin(2 pi v / 0.4),
 *   the lean running smoothly from -LEAN_DEG to +LEAN_DEG along v;
 * - CHEVRON: bands BAND wide across the ridges (along u) leaning +LEAN_DEG
 *   and -LEAN_DEG in turn, each the mirror image of the next, the ridges
 *   meeting in V's at the folds (the demo's defect);
 * - ZIGZAG: the same leans in bands BAND long along the ridges, every
 *   ridge zigzagging in phase with its neighbours (consistent). */
static double field_value(field *f, const double uv[2], int label)
{
    const int kind = label && f->kind1 ? f->kind1 : f->kind;
    const double t = tan(LEAN_DEG * PI / 180.0);
    double x;
    switch (kind) {
    case NOISE: return relief_rng_normal(&f->rng);
    case MEANDER: x = uv[0] - t * 0.4 / (2.0 * PI) * sin(2.0 * PI * uv[1] / 0.4); break;
    case CHEVRON: x = tri(uv[0], BAND) - t * uv[1]; break;
    case ZIGZAG: x = uv[0] - t * tri(uv[1], BAND); break;
    default: {
        double a = label ? f->angle1 : f->angle, amp = label ? f->amp1 : 1.0;
        return amp * sin(2.0 * PI * 10.0 * (uv[0] * cos(a) + uv[1] * sin(a)) + 0.3);
    }
    }
    return sin(2.0 * PI * 10.0 * x + 0.3);
}

/* The unit square in z = 0 as an n x n grid of spacing 1 / (n - 1),
 * each vertex jittered by up to 0.2 spacings (MT19937 seed 7) so that no
 * grid lines up with another; label 1 inside the disc of radius 0.25 about
 * the centre (the synthetic plane's hole). The field goes into the height
 * (amplitude 0.01) when `height`, and into the grey colour 0.5 + 0.3 x
 * (clamped to [0, 1]) when `colour` (heights are 0 unless `height`). */
static relief_mesh *plane(size_t n, field *f, int height, int colour)
{
    relief_mesh *m = NULL;
    relief_domain pm;
    relief_rng jit;
    const double s = 1.0 / (double)(n - 1);
    relief_domain_init(&pm, &plane_z);
    relief_rng_seed(&jit, 7);
    if (relief_mesh_create(n * n, 0, RELIEF_MESH_LABELS | (colour ? RELIEF_MESH_COLOURS : 0u),
                           &m, NULL) != RELIEF_OK)
        exit(2);
    for (size_t j = 0; j < n; ++j)
        for (size_t i = 0; i < n; ++i) {
            const size_t v = j * n + i;
            double *p = m->pos + 3 * v, uv[2], x;
            p[0] = s * ((double)i + 0.4 * (relief_rng_uniform(&jit) - 0.5));
            p[1] = s * ((double)j + 0.4 * (relief_rng_uniform(&jit) - 0.5));
            p[2] = 0.0;
            m->label[v] = (p[0] - 0.5) * (p[0] - 0.5) + (p[1] - 0.5) * (p[1] - 0.5) < 0.0625;
            relief_domain_coords(&pm, p, uv);
            x = field_value(f, uv, m->label[v]);
            if (height)
                p[2] = 0.01 * x;
            if (colour) {
                double g = 0.5 + 0.3 * x;
                for (int c = 0; c < 3; ++c)
                    m->col[3 * v + c] = (float)(g < 0.0 ? 0.0 : g > 1.0 ? 1.0 : g);
            }
        }
    return m;
}

static int peak(const double *h, int n)
{
    int b = 0;
    for (int i = 1; i < n; ++i)
        if (h[i] > h[b])
            b = i;
    return b;
}

static void show(const char *what, const relief_pattern_distance *d)
{
    printf("%-34s spectrum %.3f orientation %.3f radial %.3f tensor %.3f lean %.3f\n", what,
           d->spectrum, d->orientation, d->radial, d->tensor, d->lean);
}

static int all_nan(const relief_pattern_distance *d)
{
    return isnan(d->spectrum) && isnan(d->orientation) && isnan(d->radial) && isnan(d->tensor) &&
           isnan(d->lean);
}

/* --------------------------------------------------------- plane stripes */

static relief_pattern measure(const relief_mesh *m, const relief_fit_primitive *prim,
                              const relief_mesh *truth, const char *what)
{
    relief_pattern p;
    relief_error err = {0};
    relief_status st = relief_pattern_measure(m, prim, truth, &p, &err);
    CHECK(st == RELIEF_OK, "%s: %s", what, err.message);
    if (st != RELIEF_OK)
        exit(1);
    return p;
}

static void test_stripes_height(void)
{
    field f = {STRIPES, 0.0, 0.0, 1.0, {{0}, 0}, SAME};
    relief_mesh *m = plane(65, &f, 1, 0);
    relief_pattern p = measure(m, &plane_z, NULL, "stripes along v");
    const relief_pattern_distance same = p.d_height;
    relief_pattern_distance turned, half, diag;

    show("height stripes, both along v", &same);
    /* Stripes along v: k along u, orientation bin 0 in both parts. */
    CHECK(peak(p.height[0].orientation, RELIEF_PATTERN_ORIENT_BINS) == 0 &&
              peak(p.height[1].orientation, RELIEF_PATTERN_ORIENT_BINS) == 0,
          "stripes along v peak in orientation bin 0: %d %d",
          peak(p.height[0].orientation, RELIEF_PATTERN_ORIENT_BINS),
          peak(p.height[1].orientation, RELIEF_PATTERN_ORIENT_BINS));
    CHECK(peak(p.height[0].tensor, RELIEF_PATTERN_ORIENT_BINS) == 0 &&
              peak(p.height[1].tensor, RELIEF_PATTERN_ORIENT_BINS) == 0,
          "stripes along v: tensor peak in bin 0");
    CHECK(p.height[0].coherence > 0.9 && p.height[1].coherence > 0.9,
          "stripes are coherent: %.3f %.3f", p.height[0].coherence, p.height[1].coherence);
    CHECK(!p.fitted && !p.has_colour && !p.has_truth, "flags %d %d %d", p.fitted, p.has_colour,
          p.has_truth);
    CHECK(p.n_captured + p.n_completed == 65 * 65 && p.n_completed > 700,
          "parts %zu %zu", p.n_captured, p.n_completed);
    /* Step: the jittered grid's spacing, 1/64 give or take; band from
     * one cycle over the disc (1 / 0.5 = 2) to Nyquist (about 32). */
    CHECK(p.step > 0.8 / 64 && p.step < 1.2 / 64, "step %g", p.step);
    CHECK(p.k_min > 1.8 && p.k_min < 2.3 && p.k_max > 0.5 / (1.2 / 64) &&
              p.k_max < 0.5 / (0.8 / 64),
          "band %g .. %g", p.k_min, p.k_max);
    /* Measured (spectrum / orientation / radial / tensor) 0.071 / 0.067 /
     * 0.017 / 0.000: the disc's narrower window spreads the peak over
     * the neighbouring orientation bins a little more than the square's. */
    CHECK(same.spectrum < 0.2 && same.orientation < 0.2 && same.radial < 0.1 &&
              same.tensor < 0.05,
          "same stripes: small distances");
    relief_mesh_destroy(m);

    /* The bad completion: its stripes turned by 90 degrees (along u). */
    f.angle1 = 0.5 * PI;
    m = plane(65, &f, 1, 0);
    p = measure(m, &plane_z, NULL, "stripes turned 90");
    turned = p.d_height;
    show("height stripes, completed turned 90", &turned);
    CHECK(peak(p.height[1].orientation, RELIEF_PATTERN_ORIENT_BINS) == 6 &&
              peak(p.height[1].tensor, RELIEF_PATTERN_ORIENT_BINS) == 6,
          "stripes along u peak in bin 6 (90 degrees): %d %d",
          peak(p.height[1].orientation, RELIEF_PATTERN_ORIENT_BINS),
          peak(p.height[1].tensor, RELIEF_PATTERN_ORIENT_BINS));
    /* Measured 0.986 / 0.984 / 0.017 / 1.000: the same scales, opposite
     * orientations. */
    CHECK(turned.orientation > 0.8 && turned.tensor > 0.8 && turned.spectrum > 0.8,
          "turned stripes: large distances");
    relief_mesh_destroy(m);

    /* Turned by 45 degrees: still far. Measured 0.966 / 0.965 / 0.018 /
     * 1.000. */
    f.angle1 = 0.25 * PI;
    m = plane(65, &f, 1, 0);
    p = measure(m, &plane_z, NULL, "stripes turned 45");
    diag = p.d_height;
    show("height stripes, completed turned 45", &diag);
    CHECK(diag.orientation > 0.6 && diag.tensor > 0.6 && diag.spectrum > 0.6,
          "stripes turned 45: large distances");
    relief_mesh_destroy(m);

    /* Pattern, not amplitude: the same stripes at half the height. */
    f.angle1 = 0.0;
    f.amp1 = 0.5;
    m = plane(65, &f, 1, 0);
    p = measure(m, &plane_z, NULL, "half amplitude");
    half = p.d_height;
    show("height stripes, completed at half height", &half);
    CHECK(fabs(half.spectrum - same.spectrum) < 1e-9 && fabs(half.tensor - same.tensor) < 1e-9 &&
              fabs(half.lean - same.lean) < 1e-9,
          "amplitude does not change the distances: %g vs %g, %g vs %g, %g vs %g",
          half.spectrum, same.spectrum, half.tensor, same.tensor, half.lean, same.lean);
    relief_mesh_destroy(m);
}

static void test_stripes_colour(void)
{
    field f = {STRIPES, 0.0, 0.0, 1.0, {{0}, 0}, SAME};
    relief_mesh *m = plane(65, &f, 0, 1);
    relief_pattern p = measure(m, &plane_z, NULL, "colour stripes");
    relief_pattern_distance same = p.d_colour, turned;

    show("colour stripes, both along v", &same);
    CHECK(p.has_colour, "has colour");
    /* Flat heights: no height pattern at all. */
    CHECK(all_nan(&p.d_height) && isnan(p.height[0].coherence),
          "flat heights give NaN: %g %g", p.d_height.spectrum, p.d_height.tensor);
    CHECK(peak(p.colour[0].orientation, RELIEF_PATTERN_ORIENT_BINS) == 0 &&
              peak(p.colour[1].tensor, RELIEF_PATTERN_ORIENT_BINS) == 0,
          "colour stripes along v in bin 0");
    /* Measured as for heights, 0.071 / 0.067 / 0.017 / 0.000 (the
     * luminance is the same field). */
    CHECK(same.spectrum < 0.2 && same.orientation < 0.2 && same.radial < 0.1 &&
              same.tensor < 0.05,
          "same colour stripes: small distances");
    relief_mesh_destroy(m);

    f.angle1 = 0.5 * PI;
    m = plane(65, &f, 0, 1);
    p = measure(m, &plane_z, NULL, "colour stripes turned");
    turned = p.d_colour;
    show("colour stripes, completed turned 90", &turned);
    /* Measured 0.986 / 0.984 / 0.017 / 1.000. */
    CHECK(turned.orientation > 0.8 && turned.tensor > 0.8 && turned.spectrum > 0.8,
          "turned colour stripes: large distances");
    relief_mesh_destroy(m);
}

/* ------------------------------------------------------------------ noise */

static void test_noise(void)
{
    field f = {NOISE, 0.0, 0.0, 1.0, {{0}, 0}, SAME};
    relief_mesh *m;
    relief_pattern p;
    relief_rng_seed(&f.rng, 3);
    m = plane(65, &f, 1, 1);
    p = measure(m, &plane_z, NULL, "noise");
    show("white noise, both parts", &p.d_height);
    show("white noise in colour", &p.d_colour);
    printf("white noise coherence %.3f %.3f\n", p.height[0].coherence, p.height[1].coherence);
    /* Isotropic: low coherence, no orientation preferred. Measured
     * distances 0.146 / 0.081 / 0.050 / 0.226 (height), 0.142 / 0.073 /
     * 0.056 / 0.230 (colour), coherence 0.28 in both parts. The tensor
     * histogram of noise is itself noisy: the disc holds some 800 nodes
     * but, smoothed over 2 nodes, only a few dozen independent
     * orientations. */
    CHECK(p.height[0].coherence < 0.5 && p.height[1].coherence < 0.5,
          "noise is incoherent: %.3f %.3f", p.height[0].coherence, p.height[1].coherence);
    CHECK(p.d_height.spectrum < 0.3 && p.d_height.orientation < 0.2 &&
              p.d_height.radial < 0.15 && p.d_height.tensor < 0.45,
          "noise vs noise: small distances");
    CHECK(p.d_colour.spectrum < 0.3 && p.d_colour.orientation < 0.2 &&
              p.d_colour.radial < 0.15 && p.d_colour.tensor < 0.45,
          "colour noise vs noise: small distances");
    relief_mesh_destroy(m);
}

/* ----------------------------------------------------------------- layout */

/* The plane of `plane` (97 x 97 vertices, the disc completed), its
 * captured part laid out as `kind`, its completed part as `kind1`. */
static relief_pattern layout_case(int kind, int kind1, const char *what)
{
    field f = {kind, 0.0, 0.0, 1.0, {{0}, 0}, kind1};
    relief_mesh *m = plane(97, &f, 1, 0);
    relief_pattern p = measure(m, &plane_z, NULL, what);
    printf("%-26s lean_across %.3f -> %.3f, lean distance %.3f; lean rms %.1f -> %.1f deg; "
           "orientation distance %.3f\n",
           what, p.height[0].lean_across, p.height[1].lean_across, p.d_height.lean,
           p.height[0].lean_rms, p.height[1].lean_rms, p.d_height.orientation);
    relief_mesh_destroy(m);
    return p;
}

/* Ridges leaning +-25 degrees, mirrored into chevrons or zigzagging in
 * phase: the same leans, the same orientation histograms; only the
 * layout differs. Measured (lean_across captured -> completed, lean
 * distance): from the meander, chevrons 0.000 -> 0.965 (0.965), zigzag
 * 0.000 -> 0.017 (0.017), the meander itself 0.000 -> 0.001 (0.001);
 * from straight stripes, chevrons 0.002 -> 0.965 (0.963), zigzag
 * 0.002 -> 0.017 (0.015), straight 0.002 -> 0.003 (0.000). The
 * orientation distance cannot tell them apart: 0.467 chevrons, 0.198
 * zigzag (from straight stripes 0.754 and 0.638, both leaning away from
 * the capture's straight ridges). */
static void test_layout(void)
{
    static const struct {
        int kind, kind1, chevrons;
        const char *what;
    } cases[] = {{MEANDER, CHEVRON, 1, "meander -> chevrons"},
                 {MEANDER, ZIGZAG, 0, "meander -> zigzag"},
                 {MEANDER, SAME, 0, "meander -> meander"},
                 {STRIPES, CHEVRON, 1, "straight -> chevrons"},
                 {STRIPES, ZIGZAG, 0, "straight -> zigzag"},
                 {STRIPES, SAME, 0, "straight -> straight"}};
    for (size_t i = 0; i < sizeof cases / sizeof *cases; ++i) {
        relief_pattern p = layout_case(cases[i].kind, cases[i].kind1, cases[i].what);
        const relief_pattern_part *a = &p.height[0], *b = &p.height[1];
        /* Wavelength 0.1 across the ridges (0.09 for the leaning ones,
         * 0.1 cos 25 degrees), dominant gradient along u. */
        CHECK(a->spacing > 0.08 && a->spacing < 0.11 && b->spacing > 0.08 && b->spacing < 0.11,
              "%s: spacing %.4f %.4f", cases[i].what, a->spacing, b->spacing);
        CHECK(fabs(remainder(a->dominant, 180.0)) < 10.0 &&
                  fabs(remainder(b->dominant, 180.0)) < 10.0,
              "%s: dominant %.1f %.1f", cases[i].what, a->dominant, b->dominant);
        /* The consistent layouts: lean changing along the ridges only. */
        CHECK(a->lean_across < 0.05, "%s: captured lean_across %.3f", cases[i].what,
              a->lean_across);
        if (cases[i].chevrons)
            CHECK(b->lean_across > 0.8 && p.d_height.lean > 0.6,
                  "%s: flagged, lean_across %.3f, distance %.3f", cases[i].what, b->lean_across,
                  p.d_height.lean);
        else
            CHECK(b->lean_across < 0.05 && p.d_height.lean < 0.05,
                  "%s: not flagged, lean_across %.3f, distance %.3f", cases[i].what,
                  b->lean_across, p.d_height.lean);
        if (cases[i].kind1 != SAME)
            CHECK(b->lean_rms > 15.0 && b->lean_rms < 30.0, "%s: completed lean rms %.1f deg",
                  cases[i].what, b->lean_rms);
    }
}

/* ------------------------------------------------------------------- bark */

/* The truth's captured relief at (angle, z), by its nearest captured
 * vertex: the radial height sqrt(x^2 + y^2) - 1 (synth's radius 1, axis
 * z). */
static double captured_height(const relief_mesh *t, double a, double z)
{
    double best = INFINITY, h = 0.0;
    for (size_t v = 0; v < t->nv; ++v) {
        const double *p = t->pos + 3 * v;
        double da, d2;
        if (t->label[v] != RELIEF_LABEL_CAPTURED)
            continue;
        da = remainder(atan2(p[1], p[0]) - a, 2.0 * PI);
        d2 = da * da + (p[2] - z) * (p[2] - z);
        if (d2 < best) {
            best = d2;
            h = sqrt(p[0] * p[0] + p[1] * p[1]) - 1.0;
        }
    }
    return h;
}

/* Fold x into [lo, hi] by mirroring at the ends (a continuous tiling). */
static double fold(double x, double lo, double hi)
{
    double w = hi - lo, t = fmod(x - lo, 2.0 * w);
    if (t < 0.0)
        t += 2.0 * w;
    return lo + (t <= w ? t : 2.0 * w - t);
}

/* A completion made by hand: the truth with its missing part (the back,
 * angle beyond 80 degrees from +x) replaced by the captured relief turned
 * by `turn` radians in (arc, z) about the middle of each part, mirrored
 * at the captured part's edges to cover the back. */
static relief_mesh *turned_completion(const relief_mesh *t, double turn)
{
    relief_mesh *m = NULL;
    const double half = 80.0 * PI / 180.0;
    if (relief_mesh_create(t->nv, t->nt, t->attrs, &m, NULL) != RELIEF_OK)
        exit(2);
    memcpy(m->pos, t->pos, 3 * t->nv * sizeof *t->pos);
    memcpy(m->tri, t->tri, 3 * t->nt * sizeof *t->tri);
    memcpy(m->label, t->label, t->nv);
    if (t->col)
        memcpy(m->col, t->col, 3 * t->nv * sizeof *t->col);
    for (size_t v = 0; v < t->nv; ++v) {
        double *p = m->pos + 3 * v, a, u, w, cu, cz, h;
        if (t->label[v] != RELIEF_LABEL_COMPLETED)
            continue;
        a = atan2(p[1], p[0]);
        u = remainder(a - PI, 2.0 * PI); /* arc from the back's middle */
        w = p[2] - 1.0;
        cu = fold(cos(turn) * u - sin(turn) * w, -half, half);
        cz = fold(sin(turn) * u + cos(turn) * w + 1.0, 0.0, 2.0);
        h = captured_height(t, cu, cz);
        p[0] = (1.0 + h) * cos(a);
        p[1] = (1.0 + h) * sin(a);
    }
    return m;
}

static void test_bark(void)
{
    relief_synth_params sp = relief_synth_params_default();
    relief_mesh *truth = NULL, *bad;
    relief_error err = {0};
    relief_pattern p;

    sp.kind = RELIEF_SYNTH_CYLINDER_BARK;
    sp.colour = 1;
    sp.seed = 1;
    if (relief_synth(&sp, NULL, &truth, &err) != RELIEF_OK) {
        fprintf(stderr, "synth: %s\n", err.message);
        exit(2);
    }

    /* The truth as its own completion: both figures are the floor. Seed 1
     * measured 0.395 / 0.246 / 0.249 / 0.236: the bark's meander leans
     * the captured side's ridges further than the back's (over seeds 1
     * to 8 the orientation floor ranged 0.08 to 0.26). */
    p = measure(truth, NULL, truth, "bark truth");
    show("bark: truth vs itself (floor)", &p.d_truth_height);
    CHECK(p.fitted && p.prim.model == RELIEF_FIT_CYLINDER, "bark fits a cylinder: %d",
          (int)p.prim.model);
    CHECK(p.has_truth && p.has_truth_colour, "truth flags %d %d", p.has_truth,
          p.has_truth_colour);
    CHECK(p.d_height.spectrum == p.d_truth_height.spectrum &&
              p.d_height.tensor == p.d_truth_height.tensor &&
              p.d_height.lean == p.d_truth_height.lean,
          "truth as completion: the distance is the floor");
    /* The lean's layout: measured lean_across 0.187 captured, 0.200
     * missing, floor 0.013 (the demo's completion: 0.171 -> 0.341,
     * distance 0.170, `relief eval`). */
    printf("bark truth lean_across %.3f %.3f, lean rms %.1f %.1f deg\n",
           p.truth_height[0].lean_across, p.truth_height[1].lean_across,
           p.truth_height[0].lean_rms, p.truth_height[1].lean_rms);
    CHECK(p.d_truth_height.lean < 0.05, "bark lean floor small: %.3f", p.d_truth_height.lean);
    /* Ridges along the axis: orientation peaks within 15 degrees of 0. */
    for (int s = 0; s < 2; ++s) {
        int b = peak(p.height[s].orientation, RELIEF_PATTERN_ORIENT_BINS);
        CHECK(b == 0 || b == 1 || b == 11, "bark part %d: orientation peak in bin %d", s, b);
    }
    CHECK(p.d_truth_height.orientation < 0.5 && p.d_truth_height.tensor < 0.5 &&
              p.d_truth_height.spectrum < 0.6,
          "bark floor small");

    /* Turned by 90 degrees: ridges around the trunk. Measured 0.941 /
     * 0.936 / 0.090 / 0.818, 3.5 to 3.8 times the floor's orientation
     * and tensor distances. */
    bad = turned_completion(truth, 0.5 * PI);
    p = measure(bad, NULL, truth, "bark turned 90");
    show("bark: completion turned 90", &p.d_height);
    show("bark: its floor", &p.d_truth_height);
    CHECK(p.d_height.orientation > 0.75 && p.d_height.tensor > 0.75 &&
              p.d_height.spectrum > 0.75,
          "bark turned 90: large distances");
    CHECK(p.d_height.orientation > 2.0 * p.d_truth_height.orientation &&
              p.d_height.tensor > 2.0 * p.d_truth_height.tensor,
          "bark turned 90: well above the floor");
    relief_mesh_destroy(bad);

    /* Turned by 45 degrees (mirrored at the edges into diamonds of
     * ridges at 45 and 135 degrees, the first overlapping the capture's
     * leaning ridges). Measured 0.698 / 0.642 / 0.093 / 0.789. */
    bad = turned_completion(truth, 0.25 * PI);
    p = measure(bad, NULL, truth, "bark turned 45");
    show("bark: completion turned 45", &p.d_height);
    CHECK(p.d_height.orientation > 0.45 && p.d_height.tensor > 0.45 &&
              p.d_height.spectrum > 0.45,
          "bark turned 45: large distances");
    relief_mesh_destroy(bad);
    relief_mesh_destroy(truth);
}

/* ------------------------------------------------------------ bad input */

static void test_bad_input(void)
{
    field f = {STRIPES, 0.0, 0.0, 1.0, {{0}, 0}, SAME};
    relief_mesh *m = plane(17, &f, 1, 0), *nolabel = NULL;
    relief_pattern p;
    relief_error err = {0};
    relief_status st;

    st = relief_pattern_measure(NULL, &plane_z, NULL, &p, &err);
    CHECK(st == RELIEF_E_USAGE, "NULL mesh: %d", (int)st);
    st = relief_pattern_measure(m, &plane_z, NULL, NULL, &err);
    CHECK(st == RELIEF_E_USAGE, "NULL out: %d", (int)st);

    if (relief_mesh_create(4, 0, 0, &nolabel, NULL) != RELIEF_OK)
        exit(2);
    st = relief_pattern_measure(nolabel, &plane_z, NULL, &p, &err);
    CHECK(st == RELIEF_E_MESH && strstr(err.message, "label"), "no labels: %d %s", (int)st,
          err.message);
    relief_mesh_destroy(nolabel);

    m->label[5] = 2;
    st = relief_pattern_measure(m, &plane_z, NULL, &p, &err);
    CHECK(st == RELIEF_E_MESH && strstr(err.message, "vertex 5"), "label 2: %d %s", (int)st,
          err.message);
    for (size_t v = 0; v < m->nv; ++v)
        m->label[v] = 0;
    st = relief_pattern_measure(m, &plane_z, NULL, &p, &err);
    CHECK(st == RELIEF_E_MESH && strstr(err.message, "no completed"), "no completed: %d %s",
          (int)st, err.message);
    /* A truth that misses nothing. */
    m->label[0] = 1;
    {
        relief_mesh *t = plane(17, &f, 1, 0);
        for (size_t v = 0; v < t->nv; ++v)
            t->label[v] = 0;
        st = relief_pattern_measure(m, &plane_z, t, &p, &err);
        CHECK(st == RELIEF_E_MESH && strstr(err.message, "truth"), "truth without 1: %d %s",
              (int)st, err.message);
        relief_mesh_destroy(t);
    }
    /* One completed vertex is too few: NaN, not an error. */
    st = relief_pattern_measure(m, &plane_z, NULL, &p, &err);
    CHECK(st == RELIEF_OK, "one completed vertex: %s", err.message);
    CHECK(all_nan(&p.d_height) && p.height[1].n_points == 1 && p.height[1].n_nodes == 0,
          "one completed vertex: NaN distances (%g)", p.d_height.spectrum);
    CHECK(!isnan(p.height[0].tensor[0]), "the captured part is still measured");
    relief_mesh_destroy(m);

    /* Only a thin strip completed: too narrow for a spectrum, not for
     * the tensor. */
    m = plane(65, &f, 1, 0);
    for (size_t v = 0; v < m->nv; ++v)
        m->label[v] = m->pos[3 * v + 1] > 0.9;
    st = relief_pattern_measure(m, &plane_z, NULL, &p, &err);
    CHECK(st == RELIEF_OK, "strip: %s", err.message);
    CHECK(isnan(p.k_min) && isnan(p.d_height.spectrum) && isnan(p.height[0].orientation[0]),
          "a strip 6 steps wide has no spectrum: k_min %g", p.k_min);
    CHECK(!isnan(p.d_height.tensor), "a strip still has a tensor distance");
    CHECK(isnan(p.d_height.lean) && isnan(p.height[1].lean_across) &&
              !isnan(p.height[1].lean_rms),
          "no spectrum, no spacing, no lean-across share (its lean rms is still measured)");
    relief_mesh_destroy(m);
}

/* ---------------------------------------------------- determinism, JSON */

static void test_json_and_determinism(void)
{
    field f = {STRIPES, 0.0, 0.5 * PI, 1.0, {{0}, 0}, SAME};
    relief_mesh *m = plane(33, &f, 1, 1);
    relief_pattern a = measure(m, &plane_z, m, "json a"), b = measure(m, &plane_z, m, "json b");
    char *buf = NULL;
    size_t len = 0;
    FILE *fp;
    relief_json j;

    CHECK(memcmp(a.height, b.height, sizeof a.height) == 0 &&
              memcmp(a.colour, b.colour, sizeof a.colour) == 0 &&
              memcmp(&a.d_truth_colour, &b.d_truth_colour, sizeof a.d_truth_colour) == 0,
          "two runs agree bit for bit");

    fp = open_memstream(&buf, &len);
    if (!fp)
        exit(2);
    rj_init(&j, fp);
    rj_begin_object(&j, NULL);
    relief_pattern_json_fields(&j, &a);
    rj_end_object(&j);
    fclose(fp);
    {
        static const char *keys[] = {
            "\"pattern_spectrum_distance\":", "\"pattern_orientation_distance\":",
            "\"pattern_radial_distance\":", "\"pattern_tensor_distance\":",
            "\"pattern_spectrum_distance_colour\":", "\"pattern_tensor_distance_colour\":",
            "\"pattern_orientation_distance_truth\":",
            "\"pattern_orientation_distance_colour_truth\":", "\"pattern\":", "\"step\":",
            "\"truth_missing\":", "\"coherence\":", "\"pattern_lean_distance\":",
            "\"pattern_lean_distance_colour_truth\":", "\"pattern_lean_across_captured\":",
            "\"pattern_lean_across_truth_missing_colour\":", "\"lean_across\":",
            "\"spacing\":", "\"dominant_orientation\":"};
        for (size_t k = 0; k < sizeof keys / sizeof *keys; ++k)
            CHECK(strstr(buf, keys[k]) != NULL, "JSON has %s", keys[k]);
    }
    free(buf);
    relief_mesh_destroy(m);

    /* NaN as null: a mesh with one completed vertex. */
    m = plane(17, &f, 1, 0);
    for (size_t v = 0; v < m->nv; ++v)
        m->label[v] = v == 0;
    a = measure(m, &plane_z, NULL, "json nan");
    buf = NULL;
    fp = open_memstream(&buf, &len);
    if (!fp)
        exit(2);
    rj_init(&j, fp);
    rj_begin_object(&j, NULL);
    relief_pattern_json_fields(&j, &a);
    rj_end_object(&j);
    fclose(fp);
    CHECK(strstr(buf, "\"pattern_spectrum_distance\": null") != NULL &&
              strstr(buf, "colour") == NULL && strstr(buf, "truth") == NULL,
          "NaN written as null, no colour or truth keys: %.200s", buf);
    free(buf);
    relief_mesh_destroy(m);
}

int main(void)
{
    test_stripes_height();
    test_stripes_colour();
    test_noise();
    test_layout();
    test_bark();
    test_bad_input();
    test_json_and_determinism();
    return check_result();
}
