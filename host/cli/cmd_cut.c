/* relief cut: a hole cut out of a whole mesh, with its truth (synth/cut.h). */
#include "cli/commands.h"

#include <getopt.h>
#include <stdio.h>

#include "relief/relief.h"
#include "cli/options.h"
#include "synth/cut.h"

static const char cut_help[] =
    "usage: relief cut IN -o OUT (--ball X,Y,Z,R | --slab X,Y,Z,NX,NY,NZ,H)\n"
    "                  [--crop] [--truth T] [--ascii]\n"
    "\n"
    "Cut a hole where the truth is known: OUT is IN without the vertices inside\n"
    "the region (and the triangles touching them), a capture to complete; T is\n"
    "IN whole with `label` 1 on the vertices OUT lacks and 0 elsewhere, the\n"
    "truth `relief eval --truth` measures a completion against. Coordinates are\n"
    "in IN's units. IN is never written. With --crop OUT keeps only the region:\n"
    "a patch of a larger scan, to cut a hole in next.\n"
    "\n"
    "  -o, --output OUT      the capture; required\n"
    "  --ball X,Y,Z,R        the vertices within R of the point (X, Y, Z)\n"
    "  --slab X,Y,Z,NX,NY,NZ,H\n"
    "                        the vertices within H of the plane through (X, Y, Z)\n"
    "                        with normal (NX, NY, NZ): a band across a cylinder\n"
    "                        when the normal is its axis\n"
    "  --crop                keep the region and cut away the rest\n"
    "  --truth T             the whole mesh, labelled\n"
    "  --ascii               write ascii PLY (default binary)\n"
    "  -h, --help            this help\n";

int cli_cmd_cut(int argc, char **argv, int parse_only)
{
    enum { OPT_TRUTH = OPT_COMMAND, OPT_BALL, OPT_SLAB, OPT_ASCII, OPT_CROP };
    static const struct option opts[] = {
        {"output", required_argument, 0, 'o'}, {"truth", required_argument, 0, OPT_TRUTH},
        {"ball", required_argument, 0, OPT_BALL}, {"slab", required_argument, 0, OPT_SLAB},
        {"ascii", no_argument, 0, OPT_ASCII},   {"help", no_argument, 0, 'h'},
        {"crop", no_argument, 0, OPT_CROP},
        {0, 0, 0, 0}};
    relief_cut_region region = {RELIEF_CUT_BALL, {0, 0, 0}, {0, 0, 0}, 0, 0};
    relief_write_options wo = {0};
    relief_error err = {RELIEF_OK, ""};
    relief_mesh *in = NULL, *cap = NULL, *truth = NULL;
    const char *out = NULL, *truth_path = NULL, *in_path;
    double v[7];
    sigset_t held;
    size_t n_cut = 0;
    int c, n, rc = 0, regions = 0, crop = 0;

    optind = 0;
    while ((c = getopt_long(argc, argv, "o:h", opts, NULL)) != -1) {
        switch (c) {
        case 'o': out = optarg; break;
        case OPT_TRUTH: truth_path = optarg; break;
        case OPT_BALL:
            if (!cli_parse_reals("cut", "--ball", optarg, v, 4, &n))
                return EXIT_USAGE;
            if (n != 4)
                return cli_usage_error("cut", "--ball: expected X,Y,Z,R, got '%s'", optarg);
            region = (relief_cut_region){RELIEF_CUT_BALL, {v[0], v[1], v[2]}, {0, 0, 0}, v[3], 0};
            ++regions;
            break;
        case OPT_SLAB:
            if (!cli_parse_reals("cut", "--slab", optarg, v, 7, &n))
                return EXIT_USAGE;
            if (n != 7)
                return cli_usage_error("cut", "--slab: expected X,Y,Z,NX,NY,NZ,H, got '%s'",
                                       optarg);
            region = (relief_cut_region){RELIEF_CUT_SLAB, {v[0], v[1], v[2]},
                                         {v[3], v[4], v[5]}, v[6], 0};
            ++regions;
            break;
        case OPT_ASCII: wo.ascii = 1; break;
        case OPT_CROP: crop = 1; break;
        case 'h': fputs(cut_help, stdout); return 0;
        default: fprintf(stderr, "Try 'relief cut --help'.\n"); return EXIT_USAGE;
        }
    }
    if (optind >= argc)
        return cli_usage_error("cut", "%smissing input mesh IN", "");
    if (argc - optind > 1)
        return cli_usage_error("cut", "unexpected argument '%s'", argv[optind + 1]);
    in_path = argv[optind];
    if (!out)
        return cli_usage_error("cut", "%smissing -o OUT", "");
    if (regions != 1)
        return cli_usage_error("cut", "%sgive exactly one region: --ball or --slab", "");
    if (!cli_known_mesh_ext(out))
        return cli_usage_error("cut", "-o: '%s' has no mesh extension (.ply .obj .off .stl)",
                               out);
    if (truth_path && !cli_known_mesh_ext(truth_path))
        return cli_usage_error("cut",
                               "--truth: '%s' has no mesh extension (.ply .obj .off .stl)",
                               truth_path);
    if (cli_same_file(in_path, out))
        return cli_usage_error("cut", "-o: '%s' is the input; relief never overwrites it", out);
    if (truth_path && cli_same_file(in_path, truth_path))
        return cli_usage_error("cut", "--truth: '%s' is the input; relief never overwrites it",
                               truth_path);
    if (truth_path && cli_same_file(out, truth_path))
        return cli_usage_error("cut", "--truth: '%s' is also the -o output", truth_path);
    if (parse_only)
        return 0;
    if (relief_mesh_read(in_path, &in, NULL, &err) != RELIEF_OK)
        return cli_fail("cut", &err);
    region.crop = crop;
    if (relief_mesh_cut(in, &region, &cap, &truth, &n_cut, &err) != RELIEF_OK) {
        relief_mesh_destroy(in);
        return cli_fail("cut", &err);
    }
    cli_hold_signals(&held);
    if (relief_mesh_write(cap, out, &wo, &err) != RELIEF_OK ||
        (truth_path && relief_mesh_write(truth, truth_path, &wo, &err) != RELIEF_OK)) {
        rc = cli_fail("cut", &err);
        remove(out); /* both or neither */
    } else {
        fprintf(stderr,
                "relief cut: %s: %zu of %zu vertices cut, %zu vertices and %zu triangles "
                "captured\n",
                out, n_cut, relief_mesh_vertex_count(in), relief_mesh_vertex_count(cap),
                relief_mesh_triangle_count(cap));
    }
    cli_release_signals(&held);
    relief_mesh_destroy(truth);
    relief_mesh_destroy(cap);
    relief_mesh_destroy(in);
    return rc;
}
