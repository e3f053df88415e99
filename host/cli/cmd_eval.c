/* relief eval: the measures of a completion (report/measures.h). */
#include "cli/commands.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>

#include "relief/relief.h"
#include "base/json.h"
#include "cli/options.h"
#include "report/measures.h"
#include "report/pattern.h"
#include "smooth/fit.h"

static const char eval_help[] =
    "usage: relief eval COMPLETED [--truth T] [--json]\n"
    "\n"
    "Measure a completion, using its per-vertex `label` (0 captured, 1\n"
    "completed) and a primitive fitted to the captured part: the mean surface\n"
    "integral (mean |D.n|) of each part and their % difference, the total-\n"
    "variation distance between the parts' displacement histograms (and RGB\n"
    "histograms when there is colour), the seam measure (mean |D| jump across\n"
    "captured-completed edges over the same inside the capture), and the\n"
    "dominant spatial frequency of each part; and pattern distances (total\n"
    "variation, 0 same to 1 disjoint) between the parts' height power spectra\n"
    "binned by orientation and scale, their orientation and scale marginals,\n"
    "and their structure-tensor orientation histograms; and the layout of\n"
    "the ridges' lean about their dominant orientation: in each part, the\n"
    "share of the lean's change over one ridge spacing that runs across the\n"
    "ridges (high where neighbouring ridges lean opposite ways, as in\n"
    "chevrons), and the parts' difference (the same for luminance when there\n"
    "is colour). With --truth (a mesh whose label 1 marks the missing part,\n"
    "as `relief synth --truth` writes): the RMS relief error against the\n"
    "truth, the truth's dominant frequency, and beside each pattern figure\n"
    "the truth's own, between (or of) its captured and missing parts: the\n"
    "floor a completion cannot be expected to beat.\n"
    "\n"
    "  --truth T             ground-truth mesh in the same coordinates\n"
    "  --json                one JSON object (msi_captured, msi_completed,\n"
    "                        msi_diff_percent, seam_ratio, hist_distance_*,\n"
    "                        pattern_*_distance[_colour][_truth],\n"
    "                        pattern_lean_across_PART[_colour], ...)\n"
    "  -h, --help            this help\n";

static void print_measures_text(const relief_measures *m)
{
    printf("primitive: %s\n", relief_fit_model_name(m->prim.model));
    printf("vertices: %zu captured, %zu completed\n", m->n_captured, m->n_completed);
    printf("msi_captured: %.6g\nmsi_completed: %.6g\nmsi_diff_percent: %.3f\n",
           m->msi_captured, m->msi_completed, m->msi_diff_percent);
    printf("hist_distance_displacement: %.4f\n", m->hist_distance_displacement);
    if (m->has_colour)
        printf("hist_distance_colour: %.4f\n", m->hist_distance_colour);
    printf("seam: %.6g (over %zu edges), inside: %.6g (%zu edges), seam_ratio: %.3f\n",
           m->seam, m->n_seam_edges, m->inside, m->n_inside_edges, m->seam_ratio);
    printf("freq_captured: %.4g\nfreq_completed: %.4g\n", m->freq_captured.freq,
           m->freq_completed.freq);
    if (m->has_truth) {
        printf("truth_rms: %.6g (over %zu completed vertices on the truth)\n", m->truth_rms,
               m->n_completed - m->n_truth_outside);
        printf("truth_outside: %zu", m->n_truth_outside);
        if (m->n_truth_outside)
            printf(" (rms %.6g against the nearest truth vertex)", m->truth_rms_outside);
        printf("\nfreq_truth: %.4g\n", m->freq_truth.freq);
    }
}

/* One line per pattern distance, the truth's own floor beside it; then
 * the parts' lean-across shares, the truth's parts beside them. */
static void print_pattern_text(const char *what, const relief_pattern_distance *d,
                               const relief_pattern_distance *floor,
                               const relief_pattern_part *part,
                               const relief_pattern_part *truth)
{
    static const char *const names[] = {"spectrum", "orientation", "radial", "tensor", "lean"};
    const double v[] = {d->spectrum, d->orientation, d->radial, d->tensor, d->lean};
    const double f[] = {floor ? floor->spectrum : NAN, floor ? floor->orientation : NAN,
                        floor ? floor->radial : NAN, floor ? floor->tensor : NAN,
                        floor ? floor->lean : NAN};
    for (int i = 0; i < 5; ++i) {
        printf("pattern_%s_distance%s: %.4f", names[i], what, v[i]);
        if (floor)
            printf(" (truth's own: %.4f)", f[i]);
        putchar('\n');
    }
    printf("pattern_lean_across%s: captured %.4f, completed %.4f", what, part[0].lean_across,
           part[1].lean_across);
    if (truth)
        printf(" (truth's own: captured %.4f, missing %.4f)", truth[0].lean_across,
               truth[1].lean_across);
    putchar('\n');
}

int cli_cmd_eval(int argc, char **argv, int parse_only)
{
    static const struct option opts[] = {{"truth", required_argument, 0, OPT_TRUTH},
                                         {"json", no_argument, 0, OPT_JSON},
                                         {"help", no_argument, 0, 'h'},
                                         {0, 0, 0, 0}};
    relief_error err = {RELIEF_OK, ""};
    relief_mesh *done = NULL, *truth = NULL;
    const char *truth_path = NULL;
    relief_measures m;
    relief_pattern pat;
    relief_status st;
    int c, json = 0;

    optind = 0;
    while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
        switch (c) {
        case OPT_TRUTH: truth_path = optarg; break;
        case OPT_JSON: json = 1; break;
        case 'h': fputs(eval_help, stdout); return 0;
        default: fprintf(stderr, "Try 'relief eval --help'.\n"); return EXIT_USAGE;
        }
    }
    if (optind >= argc)
        return cli_usage_error("eval", "%smissing mesh COMPLETED", "");
    if (argc - optind > 1)
        return cli_usage_error("eval", "unexpected argument '%s'", argv[optind + 1]);
    if (parse_only)
        return 0;
    st = relief_mesh_read(argv[optind], &done, NULL, &err);
    if (st == RELIEF_OK && truth_path)
        st = relief_mesh_read(truth_path, &truth, NULL, &err);
    if (st == RELIEF_OK)
        st = relief_measure(done, truth, NULL, &m, &err);
    if (st == RELIEF_OK)
        st = relief_pattern_measure(done, &m.prim, truth, &pat, &err);
    relief_mesh_destroy(truth);
    relief_mesh_destroy(done);
    if (st != RELIEF_OK)
        return cli_fail("eval", &err);
    if (json) {
        relief_json j;
        rj_init(&j, stdout);
        rj_begin_object(&j, NULL);
        rj_string(&j, "input", argv[optind]);
        if (truth_path)
            rj_string(&j, "truth", truth_path);
        relief_report_measures_fields(&j, &m);
        relief_pattern_json_fields(&j, &pat);
        rj_end_object(&j);
    } else {
        print_measures_text(&m);
        print_pattern_text("", &pat.d_height, pat.has_truth ? &pat.d_truth_height : NULL,
                           pat.height, pat.has_truth ? pat.truth_height : NULL);
        if (pat.has_colour)
            print_pattern_text("_colour", &pat.d_colour,
                               pat.has_truth_colour ? &pat.d_truth_colour : NULL, pat.colour,
                               pat.has_truth_colour ? pat.truth_colour : NULL);
    }
    return 0;
}
