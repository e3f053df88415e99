/* relief eval: the measures of a completion (relief_eval, relief/eval.h). */
#include "cli/commands.h"

#include <getopt.h>
#include <stdio.h>

#include "relief/relief.h"
#include "cli/options.h"

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

enum { OPT_TRUTH = OPT_COMMAND, OPT_JSON };

int cli_cmd_eval(int argc, char **argv, int parse_only)
{
    static const struct option own[] = {{"truth", required_argument, 0, OPT_TRUTH},
                                         {"json", no_argument, 0, OPT_JSON},
                                         {0, 0, 0, 0}};
    struct option opts[8];
    relief_error err = {RELIEF_OK, ""};
    relief_mesh *done = NULL, *truth = NULL;
    relief_eval_result r;
    const char *truth_path = NULL;
    relief_status st;
    int c, json = 0;
    cli_options(0, own, opts, 8);
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
        st = relief_eval(done, truth, &r, &err);
    relief_mesh_destroy(truth);
    relief_mesh_destroy(done);
    if (st != RELIEF_OK)
        return cli_fail("eval", &err);
    if (json) {
        const char *keys[] = {"input", "truth"}, *values[] = {argv[optind], truth_path};
        cli_print_json(stdout, r.json, truth_path ? 2 : 1, keys, values);
    } else {
        fputs(r.text, stdout);
    }
    relief_eval_result_free(&r);
    return 0;
}
