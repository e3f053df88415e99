/* End to end on a synthetic surface: synth -> smooth -> grow (scalar) ->
 * measures against the capture and the ground truth.
 *   usage: test_complete KIND COLOUR(0|1) [VERTICES]
 * Asserts what the issue asks of a plausible completion: every target
 * textured, MSI % difference within 5 % (the papers report 0.3 to 6.7 %),
 * seam measure within 2x that inside the capture, the dominant frequency of
 * periodic reliefs within 10 % of the truth's, and with colour an RGB
 * histogram distance below 0.25 (total variation; identical distributions
 * give 0, disjoint ones 1), and for the coloured bark (the demo) a
 * pattern lean distance within 2.5x the truth's own (report/pattern.h:
 * the ridges' layout). With colour, where an OpenCL device exists, the
 * completion is run again with the OpenCL matcher and must come out
 * byte-identical. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "base/params.h"
#include "pipeline.h"
#include "mesh/mesh.h"
#include "report/measures.h"
#include "report/pattern.h"
#include "smooth/surface.h"

int main(int argc, char **argv)
{
    relief_synth_params sp = relief_synth_params_default();
    relief_params p = relief_params_default();
    relief_grow_options go = relief_grow_options_default();
    relief_mesh *cap = NULL, *truth = NULL;
    relief_surface *s = NULL;
    relief_grow_stats stats;
    relief_measures me;
    relief_error err = {0};
    relief_status st;
    int periodic;

    if (argc < 3 || relief_synth_kind_parse(argv[1], &sp.kind, &err) != RELIEF_OK) {
        fprintf(stderr, "usage: test_complete KIND COLOUR [VERTICES]\n");
        return 2;
    }
    sp.colour = atoi(argv[2]);
    if (argc > 3)
        sp.vertices = (size_t)atol(argv[3]);
    periodic = sp.kind == RELIEF_SYNTH_PLANE_WAVES || sp.kind == RELIEF_SYNTH_CYLINDER_BANDS;

    st = relief_synth(&sp, &cap, &truth, &err);
    if (st == RELIEF_OK)
        st = relief_surface_build(cap, &p, NULL, &s, &err);
    if (st == RELIEF_OK)
        st = pipeline_grow(s, &p, &go, sp.colour, 0, &stats, &err);
    if (st == RELIEF_OK)
        st = relief_measure(s->mesh, truth, &s->fit.prim, &me, &err);
    CHECK(st == RELIEF_OK, "%s: %s", argv[1], err.message);
    if (st == RELIEF_OK) {
        printf("%s colour %d: %zu samples, %zu targets, %.1f s; msi %.5f / %.5f (%.2f %%), "
               "seam ratio %.3f, hist %.3f, colour hist %.3f, freq truth %.3f completed "
               "%.3f\n",
               argv[1], sp.colour, s->n_samples, s->n_targets, stats.seconds,
               me.msi_captured, me.msi_completed, me.msi_diff_percent, me.seam_ratio,
               me.hist_distance_displacement, me.hist_distance_colour, me.freq_truth.freq,
               me.freq_completed.freq);
        CHECK(stats.acceptances == stats.targets, "%zu of %zu targets textured",
              stats.acceptances, stats.targets);
        CHECK(me.msi_diff_percent <= 5.0, "MSI differs by %.2f %% (bound 5 %%)",
              me.msi_diff_percent);
        CHECK(me.seam_ratio <= 2.0, "seam ratio %.3f (bound 2)", me.seam_ratio);
        if (periodic)
            CHECK(fabs(me.freq_completed.freq - me.freq_truth.freq) <=
                      0.1 * me.freq_truth.freq,
                  "dominant frequency %.3f vs the truth's %.3f (bound 10 %%)",
                  me.freq_completed.freq, me.freq_truth.freq);
        if (sp.colour)
            CHECK(me.hist_distance_colour <= 0.25, "colour histogram distance %.3f (bound "
                  "0.25)", me.hist_distance_colour);
    }
    /* The demo's bark (colour, seed 1) keeps its ridges' layout (issue 17),
     * measured as `relief eval --truth` does (the primitive fitted to the
     * captured part), with default options: lean distance 0.038 here, 1.7
     * times the truth's own 0.022. On the cylinder's old target lattice,
     * rows around the turn and no edge along the axis, the same growth made
     * chevrons: 0.17, 9.4 times the truth's own then (0.078 with
     * --coherence 2). The bound fails both. Other seeds of the bark spread
     * widely (README, Completion: 0.025 to 0.18 over seeds 1 to 8, the
     * truth's own 0.002 to 0.06), so it is held on the demo's seed. */
    if (st == RELIEF_OK && sp.kind == RELIEF_SYNTH_CYLINDER_BARK && sp.colour) {
        relief_pattern pat;
        st = relief_pattern_measure(s->mesh, NULL, truth, &pat, &err);
        CHECK(st == RELIEF_OK, "pattern: %s", err.message);
        if (st == RELIEF_OK) {
            printf("pattern: lean distance %.3f (truth's own %.3f), orientation %.3f (%.3f)\n",
                   pat.d_height.lean, pat.d_truth_height.lean, pat.d_height.orientation,
                   pat.d_truth_height.orientation);
            CHECK(pat.d_height.lean <= 2.5 * pat.d_truth_height.lean,
                  "the ridges' lean distance %.3f is over 2.5 x the truth's own %.3f: chevrons",
                  pat.d_height.lean, pat.d_truth_height.lean);
        }
    }
    /* The same completion through OpenCL, from a fresh smooth surface: with
     * colour only. Without, the growth is the same less the colour term,
     * and its bytes across backends are test_score_opencl's (whole
     * completions of the bands and the dimples without colour) and the
     * CLI tests'; the rerun was 45 s of the bark's 105 here. */
    if (st == RELIEF_OK && sp.colour) {
        relief_surface *s2 = NULL;
        relief_match_data *d2 = NULL;
        relief_matcher *m2 = NULL;
        relief_grow_stats stats2;
        st = relief_surface_build(cap, &p, NULL, &s2, &err);
        if (st == RELIEF_OK)
            st = relief_match_data_build(s2, p.rotations, relief_grow_mu(&p, sp.colour), &d2,
                                         &err);
        if (st == RELIEF_OK && relief_matcher_opencl_create(d2, -1, 0, &m2, &err) != RELIEF_OK) {
            printf("OpenCL comparison skipped: %s\n", err.message);
        } else if (st == RELIEF_OK) {
            st = relief_grow(s2, d2, m2, &p, &go, &stats2, &err);
            CHECK(st == RELIEF_OK, "OpenCL: %s", err.message);
            if (st == RELIEF_OK) {
                const relief_mesh *a = s->mesh, *b = s2->mesh;
                printf("OpenCL: %.1f s (scalar %.1f s)\n", stats2.seconds, stats.seconds);
                CHECK(a->nv == b->nv && memcmp(a->pos, b->pos, 3 * a->nv * sizeof(double)) == 0 &&
                          (!a->col || memcmp(a->col, b->col, 3 * a->nv * sizeof(float)) == 0),
                      "the OpenCL completion differs from the scalar one");
            }
        }
        relief_matcher_destroy(m2);
        relief_match_data_destroy(d2);
        relief_surface_destroy(s2);
    }
    relief_surface_destroy(s);
    relief_mesh_destroy(truth);
    relief_mesh_destroy(cap);
    return check_result();
}
