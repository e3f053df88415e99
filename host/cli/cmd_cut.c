/* relief cut: a hole cut out of a whole mesh, with its truth (synth/cut.h). */
#include "cli/commands.h"

#include <getopt.h>
#include <stdio.h>
#include <string.h>

#include "relief/relief.h"
#include "cli/options.h"
#include "mesh/mesh.h"
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

/* What write_one writes: the capture (-o) and the truth. */
typedef struct cut_out {
    relief_mesh *cap, *truth;
    relief_write_options wo;
} cut_out;

static relief_status write_one(void *ctx, size_t i, relief_sink *s, relief_error *err)
{
    const cut_out *o = ctx;
    return relief_mesh_write_to(i == 0 ? o->cap : o->truth, s, &o->wo, err);
}

int cli_cmd_cut(int argc, char **argv, int parse_only)
{
    cli_common cm = cli_common_init("cut");
    cut_args a;
    relief_error err = {0};
    relief_mesh *in = NULL;
    cut_out o = {NULL, NULL, {0}};
    const char *in_path;
    size_t n_cut = 0;
    int rc;

    memset(&a, 0, sizeof a);
    rc = cli_parse(&spec, &cm, NULL, take, &a, argc, argv);
    if (rc)
        return rc < 0 ? 0 : rc;
    o.wo.ascii = a.ascii;
    a.region.crop = a.crop;
    if (!cli_one_input(&cm, argc, argv, "input mesh IN", &in_path))
        return EXIT_USAGE;
    if (a.regions != 1)
        return cli_usage_error("cut", "%sgive exactly one region: --ball or --slab", "");
    if (!cli_known_mesh_ext(cm.out))
        return cli_usage_error("cut", "-o: '%s' has no mesh extension (.ply .obj .off .stl)",
                               cm.out);
    if (a.truth && !cli_known_mesh_ext(a.truth))
        return cli_usage_error("cut",
                               "--truth: '%s' has no mesh extension (.ply .obj .off .stl)",
                               a.truth);
    {
        const cli_output outs[] = {{"-o", cm.out, CLI_OUT_FILE},
                                   {"--truth", a.truth, CLI_OUT_FILE}};
        const int check_rc = cli_check_outputs("cut", &in_path, 1, outs, 2);
        if (check_rc)
            return check_rc;
        if (parse_only)
            return 0;
        if (cli_read_mesh("cut", in_path, 0, &in, NULL, &err) != RELIEF_OK ||
            relief_mesh_cut(in, &a.region, &o.cap, &o.truth, &n_cut, &err) != RELIEF_OK ||
            cli_write_outputs(outs, a.truth ? 2 : 1, write_one, &o, NULL, &err) != RELIEF_OK)
            rc = cli_fail("cut", &err);
        else
            fprintf(stderr, "relief cut: %s: %zu of %zu vertices cut, %zu vertices and %zu "
                    "triangles captured\n", cm.out, n_cut, relief_mesh_vertex_count(in),
                    relief_mesh_vertex_count(o.cap), relief_mesh_triangle_count(o.cap));
    }
    relief_mesh_destroy(o.truth);
    relief_mesh_destroy(o.cap);
    relief_mesh_destroy(in);
    return rc;
}
