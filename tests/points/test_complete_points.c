/* The point-set completion of paper 002 end to end (host/points/
 * complete_points.c), measured against the truth of cut holes
 * (host/points/measure.c): a bumpy sphere whose bumps must come back (a
 * smooth fill must not pass), coloured stripes on a plane, a real scan
 * (fertility, from ../shared/data/real), determinism and bad input. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "mesh/mesh.h"
#include "points/complete_points.h"
#include "points/measure.h"
#include "synth/cut.h"

#define PI 3.14159265358979323846

/* Fibonacci points on a sphere of radius 1 with bumps of amplitude `bump`
 * and, when colour, stripes across z; label 1 inside the cap z > zcut. */
static relief_mesh *bumpy_sphere(size_t n, double bump, int colour, double zcut)
{
    relief_mesh *m;
    relief_error err;
    if (relief_mesh_create(n, 0, RELIEF_MESH_LABELS | (colour ? RELIEF_MESH_COLOURS : 0u), &m,
                           &err) != RELIEF_OK)
        return NULL;
    for (size_t i = 0; i < n; ++i) {
        double z = 1.0 - 2.0 * (i + 0.5) / (double)n, r = sqrt(1.0 - z * z);
        double a = PI * (3.0 - sqrt(5.0)) * (double)i, x = r * cos(a), y = r * sin(a);
        double s = 1.0 + bump * sin(25.0 * x) * sin(25.0 * y) * sin(25.0 * z);
        m->pos[3 * i] = s * x, m->pos[3 * i + 1] = s * y, m->pos[3 * i + 2] = s * z;
        m->label[i] = z > zcut;
        if (colour) {
            float v = sin(30.0 * x) > 0.0 ? 0.9f : 0.1f;
            m->col[3 * i] = v, m->col[3 * i + 1] = 0.5f, m->col[3 * i + 2] = 1.0f - v;
        }
    }
    return m;
}

/* The points of m with label 0 (the capture). */
static relief_mesh *captured(const relief_mesh *m)
{
    relief_mesh *c;
    relief_error err;
    uint8_t *keep = malloc(m->nv);
    for (size_t i = 0; i < m->nv; ++i)
        keep[i] = m->label[i] == 0;
    if (relief_mesh_subset(m, keep, &c, NULL, &err) != RELIEF_OK)
        c = NULL;
    free(keep);
    if (c) {
        free(c->label);
        c->label = NULL;
        c->attrs &= ~(unsigned)RELIEF_MESH_LABELS;
    }
    return c;
}

/* The defaults, with no size limit on the holes: the caps cut here are
 * wider than a quarter of the sphere's box, which the default takes for an
 * opening by design (issue 40's hole model) and leaves open. */
static relief_points_params wide_holes(void)
{
    relief_points_params p = relief_points_params_default();
    p.max_hole = 1e30;
    return p;
}

static void test_sphere_detail(void)
{
    relief_mesh *truth = bumpy_sphere(12000, 0.03, 0, 0.75), *cap = captured(truth), *out = NULL,
                *smooth = NULL;
    relief_points_params p = wide_holes();
    relief_points_report rep;
    relief_points_measures m, ms;
    relief_error err;
    double h;
    CHECK(relief_points_complete(cap, &p, &out, &rep, &err) == RELIEF_OK, "%s", err.message);
    if (!out)
        goto done;
    h = rep.spacing;
    CHECK(rep.holes.n_holes == 1, "%u holes", rep.holes.n_holes);
    CHECK(rep.tex.iterations >= 2 && rep.tex.energy[rep.tex.iterations - 1] <= rep.tex.energy[0],
          "energy %g -> %g over %d iterations", rep.tex.energy[0],
          rep.tex.energy[rep.tex.iterations - 1], rep.tex.iterations);
    CHECK(relief_points_measure(out, truth, NULL, &m, &err) == RELIEF_OK, "%s", err.message);
    printf("sphere: added %zu for %zu, acc %.4g comp %.4g (spacing %.4g), roughness %.4g vs "
           "truth %.4g\n", m.added, m.truth_hole, m.acc_rms, m.comp_rms, h, m.rough_added,
           m.rough_truth_hole);
    CHECK(m.added > m.truth_hole / 2 && m.added < 2 * m.truth_hole, "%zu added for %zu",
          m.added, m.truth_hole);
    CHECK(m.acc_rms < 1.0 * h && m.comp_rms < 1.0 * h, "accuracy %g, completeness %g, spacing %g",
          m.acc_rms, m.comp_rms, h);
    /* The bumps come back: the detail's roughness is near the truth's. */
    CHECK(m.rough_added > 0.5 * m.rough_truth_hole && m.rough_added < 2.0 * m.rough_truth_hole,
          "roughness %g, truth %g", m.rough_added, m.rough_truth_hole);
    relief_points_report_free(&rep);
    /* The smooth fill alone must fail that: it is the blur the measure catches. */
    p.smooth_only = 1;
    CHECK(relief_points_complete(cap, &p, &smooth, &rep, &err) == RELIEF_OK, "%s", err.message);
    if (smooth && relief_points_measure(smooth, truth, NULL, &ms, &err) == RELIEF_OK) {
        printf("sphere smooth-only: acc %.4g roughness %.4g\n", ms.acc_rms, ms.rough_added);
        CHECK(ms.rough_added < 0.5 * m.rough_added, "smooth fill roughness %g, detail %g",
              ms.rough_added, m.rough_added);
    }
    relief_points_report_free(&rep);
done:
    relief_mesh_destroy(smooth);
    relief_mesh_destroy(out);
    relief_mesh_destroy(cap);
    relief_mesh_destroy(truth);
}

static void test_colour_and_determinism(void)
{
    relief_mesh *truth = bumpy_sphere(12000, 0.0, 1, 0.8), *cap = captured(truth), *a = NULL,
                *b = NULL;
    relief_points_params p = wide_holes();
    relief_points_report rep;
    relief_points_measures m;
    relief_error err;
    CHECK(relief_points_complete(cap, &p, &a, &rep, &err) == RELIEF_OK, "%s", err.message);
    relief_points_report_free(&rep);
    p.tex.threads = 1;
    CHECK(relief_points_complete(cap, &p, &b, &rep, &err) == RELIEF_OK, "%s", err.message);
    relief_points_report_free(&rep);
    if (!a || !b)
        goto done;
    CHECK(a->nv == b->nv && !memcmp(a->pos, b->pos, a->nv * 3 * sizeof *a->pos) &&
              !memcmp(a->col, b->col, a->nv * 3 * sizeof *a->col),
          "the same seed, 1 thread or many: different points");
    CHECK(relief_points_measure(a, truth, NULL, &m, &err) == RELIEF_OK, "%s", err.message);
    printf("stripes: colour RMS %.3g, colour detail %.3g vs truth %.3g\n", m.colour_rms,
           m.cdetail_added, m.cdetail_truth_hole);
    /* Stripes of 0.1 and 0.9 filled with their mean would score 0.4 RMS
     * on the red and blue channels (0.33 over three) and no detail. */
    CHECK(m.cdetail_added > 0.5 * m.cdetail_truth_hole, "colour detail %g, truth %g",
          m.cdetail_added, m.cdetail_truth_hole);
    CHECK(m.colour_rms < 0.33, "colour RMS %g", m.colour_rms);
    for (size_t i = 0; i < cap->nv; ++i)
        if (a->label[i] != 0 || memcmp(a->pos + 3 * i, cap->pos + 3 * i, 3 * sizeof(double)) ||
            memcmp(a->col + 3 * i, cap->col + 3 * i, 3 * sizeof(float))) {
            CHECK(0, "input point %zu changed", i);
            break;
        }
done:
    relief_mesh_destroy(a);
    relief_mesh_destroy(b);
    relief_mesh_destroy(cap);
    relief_mesh_destroy(truth);
}

static void test_real(const char *dir)
{
    char path[1024];
    relief_mesh *whole = NULL, *cap = NULL, *truth = NULL, *out = NULL;
    relief_cut_region region = {RELIEF_CUT_BALL, {5.47789, 31.1822, 10.7274}, {0, 0, 0}, 8.0, 0};
    relief_points_params p = wide_holes();
    relief_points_report rep;
    relief_points_measures m;
    relief_error err;
    size_t n_cut;
    snprintf(path, sizeof path, "%s/fertility/fertility.off", dir);
    if (relief_mesh_read(path, &whole, NULL, &err) != RELIEF_OK) {
        printf("skipping the real scan: %s\n", err.message);
        return;
    }
    CHECK(relief_mesh_cut(whole, &region, &cap, &truth, &n_cut, &err) == RELIEF_OK, "%s",
          err.message);
    CHECK(relief_points_complete(cap, &p, &out, &rep, &err) == RELIEF_OK, "%s", err.message);
    if (out && relief_points_measure(out, truth, NULL, &m, &err) == RELIEF_OK) {
        printf("fertility: %zu cut, %zu added, acc %.3g comp %.3g hausdorff %.3g (spacing %.3g)\n",
               n_cut, m.added, m.acc_rms, m.comp_rms, m.hausdorff, rep.spacing);
        CHECK(rep.holes.n_holes == 1, "%u holes", rep.holes.n_holes);
        /* Within about a spacing of the surface: the smooth fill alone is
         * at 0.75 spacings, the detail (on a decimated statuette, its
         * facets' noise) adds about 0.35. */
        CHECK(m.acc_rms < 1.25 * rep.spacing && m.comp_rms < 1.5 * rep.spacing,
              "accuracy %g, completeness %g, spacing %g", m.acc_rms, m.comp_rms, rep.spacing);
    }
    relief_points_report_free(&rep);
    relief_mesh_destroy(out);
    relief_mesh_destroy(truth);
    relief_mesh_destroy(cap);
    relief_mesh_destroy(whole);
}

/* 6.3: a smooth sphere's hole takes a bumpy sphere's detail. */
static void test_clone(void)
{
    relief_mesh *truth = bumpy_sphere(12000, 0.0, 0, 0.75), *cap = captured(truth);
    relief_mesh *donor = bumpy_sphere(12000, 0.03, 0, 2.0), *own = NULL, *cloned = NULL;
    relief_points_params p = wide_holes();
    relief_points_report rep;
    relief_points_measures a, b;
    relief_error err;
    CHECK(relief_points_complete(cap, &p, &own, &rep, &err) == RELIEF_OK, "%s", err.message);
    relief_points_report_free(&rep);
    p.clone = donor;
    CHECK(relief_points_complete(cap, &p, &cloned, &rep, &err) == RELIEF_OK && rep.n_clone ==
              donor->nv,
          "%s", err.message);
    relief_points_report_free(&rep);
    if (own && cloned && relief_points_measure(own, truth, NULL, &a, &err) == RELIEF_OK &&
        relief_points_measure(cloned, truth, NULL, &b, &err) == RELIEF_OK) {
        printf("clone: roughness %.4g with the donor's detail, %.4g with its own\n",
               b.rough_added, a.rough_added);
        CHECK(b.rough_added > 3.0 * a.rough_added, "cloned roughness %g, own %g", b.rough_added,
              a.rough_added);
        CHECK(b.acc_rms < 1.0 * rep.spacing + 0.03, "cloned accuracy %g", b.acc_rms);
    }
    relief_mesh_destroy(own);
    relief_mesh_destroy(cloned);
    relief_mesh_destroy(donor);
    relief_mesh_destroy(cap);
    relief_mesh_destroy(truth);
}

static void test_bad_input(void)
{
    relief_mesh *whole = bumpy_sphere(3000, 0.0, 0, 2.0), *cap = captured(whole), *out = NULL,
                *line = NULL;
    relief_points_params p = wide_holes();
    relief_points_report rep;
    relief_error err;
    CHECK(relief_points_complete(cap, &p, &out, &rep, &err) == RELIEF_E_RANGE &&
              strstr(err.message, "nothing to fill") && !out,
          "a closed sphere: %s", err.message);
    p.what = RELIEF_POINTS_COLOUR_ONLY;
    CHECK(relief_points_complete(cap, &p, &out, &rep, &err) == RELIEF_E_RANGE &&
              strstr(err.message, "no colour"),
          "colour only without colour: %s", err.message);
    p = wide_holes();
    p.k = 3;
    CHECK(relief_points_complete(cap, &p, &out, &rep, &err) == RELIEF_E_RANGE &&
              strstr(err.message, "k 3 out of range"),
          "k: %s", err.message);
    p = wide_holes();
    relief_mesh_create(50, 0, 0, &line, &err);
    for (size_t i = 0; i < 50; ++i)
        line->pos[3 * i] = (double)i, line->pos[3 * i + 1] = 2.0 * i, line->pos[3 * i + 2] = 0.0;
    CHECK(relief_points_complete(line, &p, &out, &rep, &err) == RELIEF_E_RANGE &&
              strstr(err.message, "line"),
          "collinear: %s", err.message);
    line->nv = 10;
    CHECK(relief_points_complete(line, &p, &out, &rep, &err) == RELIEF_E_RANGE &&
              strstr(err.message, "too few"),
          "too few: %s", err.message);
    line->nv = 50;
    relief_mesh_destroy(line);
    relief_mesh_destroy(cap);
    relief_mesh_destroy(whole);
}

int main(int argc, char **argv)
{
    test_bad_input();
    test_sphere_detail();
    test_colour_and_determinism();
    test_clone();
    test_real(argc > 1 ? argv[1] : "../shared/data/real");
    return check_result();
}
