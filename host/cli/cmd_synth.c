/* relief synth: synthetic partial captures with their truth (synth/). */
#include "cli/commands.h"

#include <getopt.h>
#include <stdint.h>
#include <stdio.h>

#include "relief/relief.h"
#include "cli/options.h"

static const char synth_help[] =
    "usage: relief synth KIND -o OUT [--truth T] [--seed N] [--vertices N]\n"
    "                    [--colour] [--noise SIGMA] [--ascii]\n"
    "\n"
    "Write a synthetic partial capture with known relief (OUT) and, with\n"
    "--truth, the whole surface it was cut from (T; its `label` is 0 where the\n"
    "capture has the vertex, 1 where a completion must produce it).\n"
    "\n"
    "KIND:\n"
    "%s"
    "\n"
    "  -o, --output OUT      captured part; required\n"
    "  --truth T             whole ground-truth surface\n"
    "  --seed N              random seed (default 1)\n"
    "  --vertices N          approximate vertex count of the truth, 100..4000000\n"
    "                        (default 2000)\n"
    "  --colour              per-vertex colour\n"
    "  --noise SIGMA         scanner noise along the normal on the capture, as a\n"
    "                        fraction of the primitive's size, 0..0.1 (default 0)\n"
    "  --ascii               write ascii PLY (default binary)\n"
    "  -h, --help            this help\n";

static void print_synth_help(void)
{
    char kinds[1024];
    size_t at = 0;
    for (int k = 0; k < RELIEF_SYNTH_KIND_COUNT; ++k)
        at += (size_t)snprintf(kinds + at, sizeof kinds - at, "  %-16s %s\n",
                               relief_synth_kind_name((relief_synth_kind)k),
                               relief_synth_kind_description((relief_synth_kind)k));
    printf(synth_help, kinds);
}

int cli_cmd_synth(int argc, char **argv, int parse_only)
{
    enum { OPT_TRUTH = OPT_COMMAND, OPT_VERTICES, OPT_COLOUR, OPT_NOISE, OPT_ASCII };
    static const struct option own[] = {
        {"truth", required_argument, 0, OPT_TRUTH},
        {"vertices", required_argument, 0, OPT_VERTICES},
        {"colour", no_argument, 0, OPT_COLOUR}, {"color", no_argument, 0, OPT_COLOUR},
        {"noise", required_argument, 0, OPT_NOISE}, {"ascii", no_argument, 0, OPT_ASCII},
        {0, 0, 0, 0}};
    struct option opts[16];
    relief_synth_params sp = relief_synth_params_default();
    relief_write_options wo = {0};
    relief_error err = {RELIEF_OK, ""};
    relief_mesh *cap = NULL, *truth = NULL;
    const char *out = NULL, *truth_path = NULL;
    sigset_t held;
    int c, rc = 0;
    long v;

    cli_options(CLI_OUTPUT | CLI_SEED, own, opts, 16);
    optind = 0;
    while ((c = getopt_long(argc, argv, "o:h", opts, NULL)) != -1) {
        switch (c) {
        case 'o': out = optarg; break;
        case OPT_TRUTH: truth_path = optarg; break;
        case OPT_SEED:
            if (!cli_parse_long("synth", "--seed", optarg, 0, (long)UINT32_MAX, &v))
                return EXIT_USAGE;
            sp.seed = (uint32_t)v;
            break;
        case OPT_VERTICES:
            if (!cli_parse_long("synth", "--vertices", optarg, 0, 2000000000L, &v))
                return EXIT_USAGE;
            sp.vertices = (size_t)v;
            break;
        case OPT_COLOUR: sp.colour = 1; break;
        case OPT_NOISE:
            if (!cli_parse_real("synth", "--noise", optarg, &sp.noise))
                return EXIT_USAGE;
            break;
        case OPT_ASCII: wo.ascii = 1; break;
        case 'h': print_synth_help(); return 0;
        default: fprintf(stderr, "Try 'relief synth --help'.\n"); return EXIT_USAGE;
        }
    }
    if (optind >= argc)
        return cli_usage_error("synth", "%smissing KIND", "");
    if (argc - optind > 1)
        return cli_usage_error("synth", "unexpected argument '%s'", argv[optind + 1]);
    if (!out)
        return cli_usage_error("synth", "%smissing -o OUT", "");
    if (truth_path && cli_same_file(out, truth_path))
        return cli_usage_error("synth", "--truth: '%s' is also the -o output", truth_path);
    if (relief_synth_kind_parse(argv[optind], &sp.kind, &err) != RELIEF_OK ||
        relief_synth_params_validate(&sp, &err) != RELIEF_OK)
        return cli_fail("synth", &err);
    if (parse_only)
        return 0;
    if (relief_synth(&sp, &cap, truth_path ? &truth : NULL, &err) != RELIEF_OK)
        return cli_fail("synth", &err);
    cli_hold_signals(&held);
    if (relief_mesh_write(cap, out, &wo, &err) != RELIEF_OK ||
        (truth && relief_mesh_write(truth, truth_path, &wo, &err) != RELIEF_OK)) {
        rc = cli_fail("synth", &err);
        remove(out); /* both or neither: the capture alone is no use */
    } else {
        fprintf(stderr, "relief synth: %s: %zu vertices, %zu triangles (captured)\n", out,
                relief_mesh_vertex_count(cap), relief_mesh_triangle_count(cap));
        if (truth)
            fprintf(stderr, "relief synth: %s: %zu vertices, %zu triangles (truth)\n",
                    truth_path, relief_mesh_vertex_count(truth),
                    relief_mesh_triangle_count(truth));
    }
    cli_release_signals(&held);
    relief_mesh_destroy(truth);
    relief_mesh_destroy(cap);
    return rc;
}
