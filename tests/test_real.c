/* End to end on real scans (../shared/data/real, never copied): a hole is
 * cut where the truth is known (synth/cut.h, as `relief cut` does), the
 * capture completed with the scalar matcher, and the completion measured
 * against the truth and against the smooth completion alone.
 *   usage: test_real CASE DATA_DIR     (DATA_DIR: ../shared/data/real)
 *
 * A real capture is not stationary the way the synthetic surfaces are: a
 * drill's shank tapers, Bennu's equator is a ridge, a floor's colour
 * changes from one side of the room to the other. So the measures that
 * compare the completed part with the captured part (MSI, the histograms)
 * are held to the truth's own difference between the same two parts (the
 * floor: relief_measure of the labelled truth), plus the synthetic
 * surfaces' margin (5 MSI points, 0.1 of histogram distance), and never to
 * less than the synthetic bounds (test_complete.c): where the truth's own
 * parts agree, the completion must too. The rest as on the synthetic
 * surfaces: every target textured, seam ratio within 2. Against the truth:
 * a completion copies relief of the right kind, not the lost relief itself,
 * so for a stochastic relief its RMS error is about sqrt(2) times that of
 * the smooth completion (two independent draws of the same texture against
 * one); it must stay within 1.5 times, and where the relief is not
 * stationary (a taper, a ridge) copying from the right place makes it
 * smaller than the smooth completion's, which the cases state. Every case
 * is set so that the smooth completion alone fails a bound.
 *
 * A case that no primitive fits (a face) must be refused with the way out
 * named, not completed: a non-stationary face is not a texture. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "base/params.h"
#include "pipeline.h"
#include "mesh/mesh.h"
#include "report/measures.h"
#include "smooth/surface.h"
#include "synth/cut.h"

typedef struct real_case {
    const char *name;
    const char *file;     /* under DATA_DIR */
    relief_cut_region crop; /* radius > 0: first keep only this patch */
    relief_cut_region cut;
    int accept_poor_fit;  /* the relief is over 10 % of the primitive's size */
    int oversample;       /* -1: the default */
    double spacing;       /* 0: from the capture */
    int primitive_frames; /* frames from the primitive, and R = 1 */
    double rms_vs_smooth; /* bound on truth_rms / the smooth completion's */
    int refused;          /* no primitive fits: relief_surface_build must refuse */
    int shape_only;       /* the relief is the object's shape off the primitive,
                             not a texture: the completed-vs-captured measures
                             are printed, not bounded */
    const char *expect;   /* what the method can and cannot do here */
    double msi_margin;    /* points over the truth's own MSI difference; 0: 5 */
} real_case;

static const real_case cases[] = {
    {"drill-band", "stanford_drill/drill_shaft_vrip.ply",
     {RELIEF_CUT_BALL, {0, 0, 0}, {0, 0, 0}, 0, 1},
     {RELIEF_CUT_SLAB, {0.00061, 0.1225, 0.0146}, {0, 1, 0}, 0.0015, 0}, 1, -1, 0, 0, 0.75, 0, 0,
     "a band 3 mm wide all round the drill's shank (236 of 1961 vertices): stationary "
     "scanner-scale relief on a shaft that tapers by 0.1 mm over its length, which the "
     "cylinder fit leaves in the heights; the samples beside the band carry the right "
     "offset, so the completion is nearer the truth than the smooth one. The band goes all "
     "round, so only it is completed (issue 40; before, 22 targets past the shaft's ends "
     "too): its mean height is 17 to 22 % off the capture's over seeds 1 to 5, the truth's "
     "band 9.65 % (the taper), hence the MSI margin of 15 points; the ends' targets had "
     "pulled it to 2 to 7 %", 15.0},
    {"bennu-disc", "bennu_radar/bennu.obj",
     {RELIEF_CUT_BALL, {0, 0, 0}, {0, 0, 0}, 0, 1},
     {RELIEF_CUT_BALL, {0.2446, 0, 0}, {0, 0, 0}, 0.08, 0}, 0, -1, 0, 0, 0.5, 0, 0,
     "a disc on asteroid Bennu's equatorial ridge (radar shape model, coarse): the ridge "
     "stands above the fitted sphere, as the samples along the rest of the equator do", 0.0},
    {"frag115-disc", "open3d_frag115/frag_115.ply",
     {RELIEF_CUT_BALL, {0, 0, 0}, {0, 0, 0}, 0, 1},
     {RELIEF_CUT_BALL, {1.65835, 1.88511, 1.06949}, {0, 0, 0}, 0.08, 0}, 0, 0, 0.005, 1, 1.5, 0, 0,
     "a 16 cm disc in a depth-camera floor with coloured tape (478 of 64365 vertices): "
     "noise-scale relief and the floor's colour; a tape line crossing the disc is not "
     "continued (the window sees 3 hops, not the line)", 0.0},
    {"planck-crown", "max_planck/decimated-max.obj",
     {RELIEF_CUT_BALL, {45.9, 144.5, 80}, {0, 0, 0}, 70, 1},
     {RELIEF_CUT_BALL, {26.8, 144.5, 100.2}, {0, 0, 0}, 22, 0}, 0, -1, 0, 0, 0.75, 0, 1,
     "a hole in the crown of Max Planck's bald head (17 of a 231-vertex patch cropped "
     "from the decimated bust): a sphere fits the patch, which covers a tenth of it, so "
     "only the hole is completed, not the rest of the sphere. The relief is the head's "
     "own shape off the sphere, not a texture (MSI and histograms are printed, not "
     "bounded); copied from beside the hole it must be nearer the truth than the "
     "smooth sphere, and seamless", 0.0},
    {"max-planck", "max_planck/decimated-max.obj",
     {RELIEF_CUT_BALL, {0, 0, 0}, {0, 0, 0}, 0, 1},
     {RELIEF_CUT_BALL, {0, 0, 0}, {0, 0, 0}, 30, 0}, 0, -1, 0, 0, 0, 1, 0,
     "a bust: no plane, sphere or cylinder fits it (cylinder rms 22 % of its radius), "
     "so completion is refused with accept_poor_fit named", 0.0},
};

static const real_case *find_case(const char *name)
{
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i)
        if (strcmp(cases[i].name, name) == 0)
            return &cases[i];
    return NULL;
}

/* The bound on a completed-vs-captured measure: the truth's own value plus
 * the margin, and never less than the synthetic surfaces' bound. */
static double bound(double floor, double margin, double synthetic)
{
    double b = floor + margin;
    return isfinite(b) && b > synthetic ? b : synthetic;
}

int main(int argc, char **argv)
{
    const real_case *c = argc == 3 ? find_case(argv[1]) : NULL;
    relief_params p = relief_params_default();
    relief_smooth_options so = relief_smooth_options_default();
    relief_grow_options go = relief_grow_options_default();
    relief_mesh *in = NULL, *cap = NULL, *truth = NULL;
    relief_surface *s = NULL;
    relief_grow_stats stats;
    relief_measures floor_m, smooth_m, me;
    relief_error err = {0};
    relief_status st;
    size_t n_cut = 0;
    char path[4096];
    int colour;

    if (!c) {
        fprintf(stderr, "usage: test_real CASE DATA_DIR\n");
        return 2;
    }
    printf("%s: %s\n", c->name, c->expect);
    snprintf(path, sizeof path, "%s/%s", argv[2], c->file);
    st = relief_mesh_read(path, &in, NULL, &err);
    if (st == RELIEF_OK && c->crop.radius > 0.0) {
        relief_mesh *patch = NULL, *rest = NULL;
        st = relief_mesh_cut(in, &c->crop, &patch, &rest, NULL, &err);
        relief_mesh_destroy(rest);
        relief_mesh_destroy(in);
        in = patch;
    }
    if (st == RELIEF_OK)
        st = relief_mesh_cut(in, &c->cut, &cap, &truth, &n_cut, &err);
    CHECK(st == RELIEF_OK, "%s: %s", path, err.message);
    if (st != RELIEF_OK)
        goto done;
    colour = cap->col != NULL;
    so.accept_poor_fit = c->accept_poor_fit;
    if (c->oversample >= 0)
        p.oversample = c->oversample;
    p.spacing = c->spacing;
    if (c->primitive_frames) {
        so.frames = RELIEF_FRAMES_PRIMITIVE;
        p.rotations = 1;
    }
    st = relief_surface_build(cap, &p, &so, &s, &err);
    if (c->refused) {
        CHECK(st == RELIEF_E_MESH && strstr(err.message, "accept_poor_fit"),
              "a capture no primitive fits was not refused with accept_poor_fit named "
              "(status %d: %s)", (int)st, err.message);
        if (st != RELIEF_OK)
            printf("refused: %s\n", err.message);
        goto done;
    }
    /* A patch's hole is completed, not the rest of its primitive
     * (smooth/targets.h): about as many targets as vertices were cut. */
    if (st == RELIEF_OK && c->crop.radius > 0.0) {
        printf("region %s: %zu hole(s), %zu targets for %zu vertices cut; %zu points "
               "outside; the patch covers %.1f %%\n",
               relief_fill_region_name(s->fill.region), s->fill.holes, s->n_targets, n_cut,
               s->fill.outside_points, 100.0 * s->fill.cover);
        CHECK(s->fill.region == RELIEF_FILL_HOLES && s->fill.holes == 1 &&
                  s->n_targets < 5 * n_cut && s->fill.outside_points > 20 * s->n_targets,
              "the patch's hole was not completed alone: %s, %zu targets for %zu cut",
              relief_fill_region_name(s->fill.region), s->n_targets, n_cut);
    }
    /* The floor (the truth's own parts) and the smooth completion alone,
     * both against the primitive the pipeline fitted. */
    if (st == RELIEF_OK)
        st = relief_measure(truth, NULL, &s->fit.prim, &floor_m, &err);
    if (st == RELIEF_OK)
        st = relief_measure(s->mesh, truth, &s->fit.prim, &smooth_m, &err);
    if (st == RELIEF_OK)
        st = pipeline_grow(s, &p, &go, colour, 0, &stats, &err);
    if (st == RELIEF_OK)
        st = relief_measure(s->mesh, truth, &s->fit.prim, &me, &err);
    CHECK(st == RELIEF_OK, "%s: %s", c->name, err.message);
    if (st != RELIEF_OK)
        goto done;
    printf("%zu vertices cut; %zu samples, %zu targets, %.1f s\n"
           "msi diff %.2f %% (truth's own %.2f %%), displacement hist %.3f (%.3f), "
           "seam ratio %.3f (%.3f)\n"
           "truth rms %.4g over %zu vertices (smooth completion %.4g: ratio %.3f)\n",
           n_cut, s->n_samples, s->n_targets, stats.seconds, me.msi_diff_percent,
           floor_m.msi_diff_percent, me.hist_distance_displacement,
           floor_m.hist_distance_displacement, me.seam_ratio, floor_m.seam_ratio,
           me.truth_rms, me.n_completed - me.n_truth_outside, smooth_m.truth_rms,
           me.truth_rms / smooth_m.truth_rms);
    if (colour)
        printf("colour hist %.3f (truth's own %.3f)\n", me.hist_distance_colour,
               floor_m.hist_distance_colour);
    CHECK(stats.acceptances == stats.targets, "%zu of %zu targets textured",
          stats.acceptances, stats.targets);
    CHECK(me.seam_ratio <= 2.0, "seam ratio %.3f (bound 2)", me.seam_ratio);
    CHECK(c->shape_only ||
              me.msi_diff_percent <= bound(floor_m.msi_diff_percent,
                                           c->msi_margin > 0.0 ? c->msi_margin : 5.0, 5.0),
          "MSI differs by %.2f %% (the truth's own parts by %.2f %%)", me.msi_diff_percent,
          floor_m.msi_diff_percent);
    CHECK(c->shape_only ||
              me.hist_distance_displacement <= bound(floor_m.hist_distance_displacement, 0.1, 0.25),
          "displacement histogram distance %.3f (the truth's own %.3f)",
          me.hist_distance_displacement, floor_m.hist_distance_displacement);
    if (colour)
        CHECK(me.hist_distance_colour <= bound(floor_m.hist_distance_colour, 0.1, 0.25),
              "colour histogram distance %.3f (the truth's own %.3f)", me.hist_distance_colour,
              floor_m.hist_distance_colour);
    CHECK(me.truth_rms <= c->rms_vs_smooth * smooth_m.truth_rms,
          "RMS against the truth %.4g is over %.2f x the smooth completion's %.4g",
          me.truth_rms, c->rms_vs_smooth, smooth_m.truth_rms);
    /* The bounds can fail: the smooth completion alone (no relief) breaks
     * at least one of them. */
    CHECK(smooth_m.msi_diff_percent > bound(floor_m.msi_diff_percent, 5.0, 5.0) ||
              c->rms_vs_smooth < 1.0,
          "the smooth completion alone (MSI difference %.2f %%) would pass every bound",
          smooth_m.msi_diff_percent);
done:
    relief_surface_destroy(s);
    relief_mesh_destroy(truth);
    relief_mesh_destroy(cap);
    relief_mesh_destroy(in);
    return check_result();
}
