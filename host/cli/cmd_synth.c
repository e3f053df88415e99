/* relief synth: synthetic partial captures with their truth (synth/). */
#include "cli/commands.h"

#include <getopt.h>
#include <stdint.h>
#include <stdio.h>

#include "relief/relief.h"
#include "cli/options.h"
#include "mesh/mesh.h"

enum { SY_TRUTH = OPT_COMMAND, SY_VERTICES, SY_COLOUR, SY_NOISE, SY_ASCII };

static const cli_own own[] = {
    {"truth", SY_TRUTH, "T", "the whole ground-truth surface"},
    {"vertices", SY_VERTICES, "N", "approximate vertex count of the truth, 100..4000000 "
     "(default 2000)"},
    {"colour", SY_COLOUR, NULL, "per-vertex colour"},
    {"color", SY_COLOUR, NULL, "the same"},
    {"noise", SY_NOISE, "SIGMA", "scanner noise along the normal on the capture, as a "
     "fraction of the primitive's size, 0..0.1 (default 0)"},
    {"ascii", SY_ASCII, NULL, "write ascii PLY (default binary)"},
    {NULL, 0, NULL, NULL}};

typedef struct synth_args {
    relief_synth_params sp;
    const char *truth;
    int ascii;
} synth_args;

static int take(void *ctx, int id, const char *arg)
{
    synth_args *a = ctx;
    long v;
    switch (id) {
    case SY_TRUTH: a->truth = arg; return 1;
    case SY_COLOUR: return a->sp.colour = 1;
    case SY_ASCII: return a->ascii = 1;
    case SY_NOISE: return cli_parse_real("synth", "--noise", arg, &a->sp.noise);
    }
    if (!cli_parse_long("synth", "--vertices", arg, 0, 2000000000L, &v))
        return 0;
    a->sp.vertices = (size_t)v;
    return 1;
}

/* The spec, its list of kinds written into kinds[] (the help's tail). */
static cli_spec spec(char *kinds, size_t cap)
{
    cli_spec s = {"synth", "KIND -o OUT [--truth T] [--seed N] [--vertices N] [--colour] "
                  "[--noise SIGMA] [--ascii]",
                  "Write a synthetic partial capture with known relief (OUT) and, with "
                  "--truth, the whole surface it was cut from (T; its `label` is 0 where the "
                  "capture has the vertex, 1 where a completion must produce it).",
                  CLI_OUTPUT | CLI_SEED, "the captured part; required", NULL, NULL, 0, NULL,
                  own, kinds};
    size_t at = (size_t)snprintf(kinds, cap, "KIND:\n");
    for (int k = 0; k < RELIEF_SYNTH_KIND_COUNT && at < cap; ++k)
        at += (size_t)snprintf(kinds + at, cap - at, "%s: %s\n",
                               relief_synth_kind_name((relief_synth_kind)k),
                               relief_synth_kind_description((relief_synth_kind)k));
    return s;
}

/* What write_one writes: the capture (-o) and the truth. */
typedef struct synth_out {
    relief_mesh *cap, *truth;
    relief_write_options wo;
} synth_out;

static relief_status write_one(void *ctx, size_t i, relief_sink *s, relief_error *err)
{
    const synth_out *o = ctx;
    return relief_mesh_write_to(i == 0 ? o->cap : o->truth, s, &o->wo, err);
}

int cli_cmd_synth(int argc, char **argv, int parse_only)
{
    char kinds[1024];
    const cli_spec s = spec(kinds, sizeof kinds);
    cli_common cm = cli_common_init("synth");
    synth_args a = {relief_synth_params_default(), NULL, 0};
    synth_out o = {NULL, NULL, {0}};
    relief_error err = {0};
    const char *kind;
    int rc = cli_parse(&s, &cm, NULL, take, &a, argc, argv);

    if (rc)
        return rc < 0 ? 0 : rc;
    o.wo.ascii = a.ascii;
    if (cm.seed_given)
        a.sp.seed = cm.seed;
    if (!cli_one_input(&cm, argc, argv, "KIND", &kind))
        return EXIT_USAGE;
    {
        const cli_output outs[] = {{"-o", cm.out, CLI_OUT_FILE},
                                   {"--truth", a.truth, CLI_OUT_FILE}};
        const int check_rc = cli_check_outputs("synth", NULL, 0, outs, 2);
        if (check_rc)
            return check_rc;
        if (relief_synth_kind_parse(kind, &a.sp.kind, &err) != RELIEF_OK ||
            relief_synth_params_validate(&a.sp, &err) != RELIEF_OK)
            return cli_fail("synth", &err);
        if (parse_only)
            return 0;
        /* Both or neither: the capture alone is no use. */
        if (relief_synth(&a.sp, &o.cap, a.truth ? &o.truth : NULL, &err) != RELIEF_OK ||
            cli_write_outputs(outs, 2, write_one, &o, NULL, &err) != RELIEF_OK)
            rc = cli_fail("synth", &err);
    }
    if (rc == 0) {
        fprintf(stderr, "relief synth: %s: %zu vertices, %zu triangles (captured)\n", cm.out,
                relief_mesh_vertex_count(o.cap), relief_mesh_triangle_count(o.cap));
        if (o.truth)
            fprintf(stderr, "relief synth: %s: %zu vertices, %zu triangles (truth)\n",
                    a.truth, relief_mesh_vertex_count(o.truth),
                    relief_mesh_triangle_count(o.truth));
    }
    relief_mesh_destroy(o.truth);
    relief_mesh_destroy(o.cap);
    return rc;
}
