/* relief cut: a hole cut out of a whole mesh, with its truth (synth/cut.h). */
#include "cli/commands.h"

#include <getopt.h>
#include <stdio.h>
#include <string.h>

#include "relief/relief.h"
#include "cli/options.h"
#include "synth/cut.h"

enum { CUT_TRUTH = OPT_COMMAND, CUT_BALL, CUT_SLAB, CUT_ASCII, CUT_CROP };

static const cli_own own[] = {
    {"ball", CUT_BALL, "X,Y,Z,R", "the vertices within R of the point (X, Y, Z)"},
    {"slab", CUT_SLAB, "X,Y,Z,NX,NY,NZ,H", "the vertices within H of the plane through "
     "(X, Y, Z) with normal (NX, NY, NZ): a band across a cylinder when the normal is its "
     "axis"},
    {"crop", CUT_CROP, NULL, "keep the region and cut away the rest"},
    {"truth", CUT_TRUTH, "T", "the whole mesh, labelled"},
    {"ascii", CUT_ASCII, NULL, "write ascii PLY (default binary)"},
    {NULL, 0, NULL, NULL}};

static const cli_spec spec = {
    "cut", "IN -o OUT (--ball X,Y,Z,R | --slab X,Y,Z,NX,NY,NZ,H) [--crop] [--truth T] "
    "[--ascii]",
    "Cut a hole where the truth is known: OUT is IN without the vertices inside the region "
    "(and the triangles touching them), a capture to complete; T is IN whole with `label` 1 "
    "on the vertices OUT lacks and 0 elsewhere, the truth `relief eval --truth` measures a "
    "completion against. Coordinates are in IN's units. IN is never written. With --crop "
    "OUT keeps only the region: a patch of a larger scan, to cut a hole in next.",
    CLI_OUTPUT, "the capture; required", NULL, NULL, 0, NULL, own, NULL};

typedef struct cut_args {
    relief_cut_region region;
    const char *truth;
    int regions, ascii, crop;
} cut_args;

/* --ball or --slab: n reals into the region. */
static int take_region(cut_args *a, int slab, const char *arg)
{
    double v[7];
    int n;
    if (!cli_parse_reals("cut", slab ? "--slab" : "--ball", arg, v, slab ? 7 : 4, &n))
        return 0;
    if (n != (slab ? 7 : 4)) {
        cli_usage_error("cut", slab ? "--slab: expected X,Y,Z,NX,NY,NZ,H, got '%s'"
                                    : "--ball: expected X,Y,Z,R, got '%s'", arg);
        return 0;
    }
    a->region = slab ? (relief_cut_region){RELIEF_CUT_SLAB, {v[0], v[1], v[2]},
                                           {v[3], v[4], v[5]}, v[6], 0}
                     : (relief_cut_region){RELIEF_CUT_BALL, {v[0], v[1], v[2]}, {0, 0, 0},
                                           v[3], 0};
    ++a->regions;
    return 1;
}

static int take(void *ctx, int id, const char *arg)
{
    cut_args *a = ctx;
    switch (id) {
    case CUT_TRUTH: a->truth = arg; return 1;
    case CUT_ASCII: return a->ascii = 1;
    case CUT_CROP: return a->crop = 1;
    }
    return take_region(a, id == CUT_SLAB, arg);
}

int cli_cmd_cut(int argc, char **argv, int parse_only)
{
    cli_common cm = cli_common_init("cut");
    cut_args a;
    relief_write_options wo = {0};
    relief_error err = {RELIEF_OK, ""};
    relief_mesh *in = NULL, *cap = NULL, *truth = NULL;
    const char *out, *truth_path, *in_path;
    sigset_t held;
    size_t n_cut = 0;
    int rc;

    memset(&a, 0, sizeof a);
    rc = cli_parse(&spec, &cm, NULL, take, &a, argc, argv);
    if (rc)
        return rc < 0 ? 0 : rc;
    out = cm.out;
    truth_path = a.truth;
    wo.ascii = a.ascii;
    a.region.crop = a.crop;
    if (optind >= argc)
        return cli_usage_error("cut", "%smissing input mesh IN", "");
    if (argc - optind > 1)
        return cli_usage_error("cut", "unexpected argument '%s'", argv[optind + 1]);
    in_path = argv[optind];
    if (!out)
        return cli_usage_error("cut", "%smissing -o OUT", "");
    if (a.regions != 1)
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
    if (cli_read_mesh("cut", in_path, 0, &in, NULL, &err) != RELIEF_OK)
        return cli_fail("cut", &err);
    if (relief_mesh_cut(in, &a.region, &cap, &truth, &n_cut, &err) != RELIEF_OK) {
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
