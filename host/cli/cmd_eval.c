/* relief eval: the measures of a completion (relief_eval, relief/eval.h). */
#include "cli/commands.h"

#include <getopt.h>
#include <stdio.h>

#include "relief/relief.h"
#include "cli/options.h"

enum { EVAL_TRUTH = OPT_COMMAND, EVAL_JSON };

static const cli_own own[] = {
    {"truth", EVAL_TRUTH, "T", "ground-truth mesh in the same coordinates"},
    {"json", EVAL_JSON, NULL, "one JSON object (msi_captured, msi_completed, "
     "msi_diff_percent, seam_ratio, hist_distance_*, pattern_*_distance[_colour][_truth], "
     "pattern_lean_across_PART[_colour], ...)"},
    {NULL, 0, NULL, NULL}};

static const cli_spec spec = {
    "eval", "COMPLETED [--truth T] [--json]",
    "Measure a completion, using its per-vertex `label` (0 captured, 1 completed) and a "
    "primitive fitted to the captured part: the mean surface integral (mean |D.n|) of "
    "each part and their % difference, the total-variation distance between the parts' "
    "displacement histograms (and RGB histograms when there is colour), the seam measure "
    "(mean |D| jump across captured-completed edges over the same inside the capture), "
    "and the dominant spatial frequency of each part; and pattern distances (total "
    "variation, 0 same to 1 disjoint) between the parts' height power spectra binned by "
    "orientation and scale, their orientation and scale marginals, and their "
    "structure-tensor orientation histograms; and the layout of the ridges' lean about "
    "their dominant orientation: in each part, the share of the lean's change over one "
    "ridge spacing that runs across the ridges (high where neighbouring ridges lean "
    "opposite ways, as in chevrons), and the parts' difference (the same for luminance "
    "when there is colour). With --truth (a mesh whose label 1 marks the missing part, as "
    "`relief synth --truth` writes): the RMS relief error against the truth, the truth's "
    "dominant frequency, and beside each pattern figure the truth's own, between (or of) "
    "its captured and missing parts: the floor a completion cannot be expected to beat.",
    0, NULL, NULL, NULL, 0, NULL, own, NULL};

typedef struct eval_args {
    const char *truth;
    int json;
} eval_args;

static int take(void *ctx, int id, const char *arg)
{
    eval_args *a = ctx;
    if (id == EVAL_JSON)
        a->json = 1;
    else
        a->truth = arg;
    return 1;
}

int cli_cmd_eval(int argc, char **argv, int parse_only)
{
    cli_common cm = cli_common_init("eval");
    eval_args args = {NULL, 0};
    relief_error err = {0};
    relief_mesh *done = NULL, *truth = NULL;
    relief_eval_result r;
    relief_status st;
    const char *in_path;
    int rc = cli_parse(&spec, &cm, NULL, take, &args, argc, argv);

    if (rc)
        return rc < 0 ? 0 : rc;
    if (!cli_one_input(&cm, argc, argv, "mesh COMPLETED", &in_path))
        return EXIT_USAGE;
    if (parse_only)
        return 0;
    st = cli_read_mesh("eval", in_path, 0, &done, NULL, &err);
    if (st == RELIEF_OK && args.truth)
        st = cli_read_mesh("eval", args.truth, 0, &truth, NULL, &err);
    if (st == RELIEF_OK)
        st = relief_eval(done, truth, &r, &err);
    relief_mesh_destroy(truth);
    relief_mesh_destroy(done);
    if (st != RELIEF_OK)
        return cli_fail("eval", &err);
    if (args.json) {
        const char *keys[] = {"input", "truth"}, *values[] = {in_path, args.truth};
        cli_print_json(stdout, r.json, args.truth ? 2 : 1, keys, values);
    } else {
        fputs(r.text, stdout);
    }
    relief_eval_result_free(&r);
    return 0;
}
