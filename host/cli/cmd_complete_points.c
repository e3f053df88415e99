/* relief complete-points: colour and geometric detail completed on a point
 * set with no primitive under it (paper 002), a client of
 * relief_complete_points (relief/points.h): options, the files, the
 * summary. */
#include "cli/commands.h"

#include <getopt.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "relief/relief.h"
#include "cli/batch.h"
#include "cli/options.h"
#include "mesh/mesh.h"

enum {
    CP_COLOUR_ONLY = OPT_COMMAND, CP_GEOMETRY_ONLY, CP_HOLE_MASK, CP_SAMPLE_REGION, CP_MESH,
    CP_CLONE_FROM
};

static const cli_own own[] = {
    {"mesh", CP_MESH, "M.ply", "also write the completed surface: a mesh's triangles and "
     "patches over the filled holes; for a point set, local Delaunay umbrellas through all "
     "the points"},
    {"colour-only", CP_COLOUR_ONLY, NULL, "synthesise the colour of the --hole-mask points "
     "only"},
    {"geometry-only", CP_GEOMETRY_ONLY, NULL, "new points and their detail; colour from the "
     "rim"},
    {"clone-from", CP_CLONE_FROM, "FILE", "copy the detail (and colour, when both have it) "
     "from another scan, sampled about as densely (paper 6.3)"},
    {"hole-mask", CP_HOLE_MASK, "WHAT", "points to synthesise again; the holes whose rims "
     "they touch are the ones filled (a border, or a rim wider than max_hole, only where they "
     "touch it): 'label' (IN's PLY label 1) or 'ball:X,Y,Z,R'"},
    {"sample-region", CP_SAMPLE_REGION, "R", "exemplars only inside the box "
     "X0,Y0,Z0,X1,Y1,Z1 (IN's units), or on the points IN's PLY labels 1 ('label')"},
    {NULL, 0, NULL, NULL}};
static const char *const skip[] = {"what", "mesh", "hole_labels", "hole_ball",
                                   "sample_labels", "sample_box", "viewpoint", NULL};

static cli_spec spec(void)
{
    cli_spec s = {"complete-points", "IN -o OUT.ply [--colour-only | --geometry-only] "
                  "[--report R.json] [options]",
                  "Complete the holes of a point set or mesh that no plane, sphere or "
                  "cylinder fits (paper 002): the detail is peeled off as a signed height "
                  "over a smoothed base, the base's holes are filled by a smooth implicit "
                  "surface (compactly supported RBF), and the height and the colour are "
                  "synthesised on the new points by texture optimisation over overlapping "
                  "clusters. IN: PLY, OBJ, OFF, STL or PCD (organised or not), with or "
                  "without colour; a mesh's holes are its boundary loops, a bare point set's "
                  "are where points see neighbours on one side only; the outer border of an "
                  "open scan is left open. OUT: a PLY point set, the input's points first "
                  "(label 0) then the new ones (label 1), with colour when IN has it and "
                  "normals. IN is never written.",
                  CLI_OUTPUT | CLI_REPORT | CLI_QUIET | CLI_LIMIT, "the completed points; required",
                  NULL, NULL, 0, skip, own, NULL};
    s.params = relief_complete_points_param_table(&s.n_params);
    return s;
}

/* What the command knows that the parameters do not. */
typedef struct points_cli {
    cli_common cm;
    relief_complete_points_params p;
    const char *in, *mesh, *clone;
    cli_output outs[3]; /* -o, --mesh, --report */
} points_cli;

static const char cmd[] = "complete-points";

/* --colour-only or --geometry-only: 1, or 0 when the other was given. */
static int set_what(relief_complete_points_params *p, relief_points_what want)
{
    if (p->what != RELIEF_POINTS_ALL && p->what != want) {
        cli_usage_error(cmd, "%s--colour-only and --geometry-only exclude each other", "");
        return 0;
    }
    p->what = want;
    return 1;
}

/* --sample-region label | X0,Y0,Z0,X1,Y1,Z1 (the order is the parameters'). */
static int parse_sample_region(const char *arg, relief_complete_points_params *p)
{
    int k = 0;
    p->sample_labels = p->has_sample_box = 0;
    if (strcmp(arg, "label") == 0) {
        p->sample_labels = 1;
        return 1;
    }
    if (!cli_parse_reals(cmd, "--sample-region", arg, p->sample_box, 6, &k))
        return 0;
    if (k != 6) {
        cli_usage_error(cmd, "--sample-region: expected X0,Y0,Z0,X1,Y1,Z1 with X0 < X1, "
                        "Y0 < Y1, Z0 < Z1, got '%s'", arg);
        return 0;
    }
    p->has_sample_box = 1;
    return 1;
}

/* The command's own options: 1 taken, 0 a bad value (said). */
static int take(void *ctx, int c, const char *arg)
{
    points_cli *pc = ctx;
    relief_complete_points_params *p = &pc->p;
    switch (c) {
    case CP_COLOUR_ONLY: return set_what(p, RELIEF_POINTS_COLOUR_ONLY);
    case CP_GEOMETRY_ONLY: return set_what(p, RELIEF_POINTS_GEOMETRY_ONLY);
    case CP_HOLE_MASK:
        return cli_parse_hole_mask(cmd, arg, &p->hole_labels, &p->has_hole_ball, p->hole_ball);
    case CP_SAMPLE_REGION: return parse_sample_region(arg, p);
    case CP_MESH: pc->mesh = arg, p->mesh = 1; return 1;
    case CP_CLONE_FROM: pc->clone = arg; return 1;
    }
    return 0;
}

/* The files of one run (pc->in to pc->cm.out): -o a PLY, --mesh a mesh,
 * none of them an input or another output; the search where it can run.
 * 0 when they will do, else the exit status (said). */
static int check_files(points_cli *pc)
{
    const cli_common *cm = &pc->cm;
    const char *ins[] = {pc->in, pc->clone};
    const cli_output outs[] = {{"-o", cm->out, CLI_OUT_FILE},
                               {"--mesh", pc->mesh, CLI_OUT_FILE},
                               {"--report", cm->report, CLI_OUT_FILE}};
    if (strcasecmp(cli_ext_of(cm->out), ".ply") != 0)
        return cli_usage_error(cmd, "-o: '%s' is not a .ply (the completed points carry "
                               "colour, normals and a label, which only PLY keeps)", cm->out);
    if (pc->mesh && !cli_known_mesh_ext(pc->mesh))
        return cli_usage_error(cmd, "--mesh: '%s' has no mesh extension (.ply .obj .off .stl)",
                               pc->mesh);
    memcpy(pc->outs, outs, sizeof outs);
    const int check_rc = cli_check_outputs(cmd, ins, 2, pc->outs, 3);
    if (check_rc)
        return check_rc;
    /* --device -1 is the default's value: the option given or not, the same run. */
    if ((pc->p.run.backend == RELIEF_BACKEND_OPENCL || pc->p.run.device >= 0) &&
        pc->p.grid_search == RELIEF_GRID_SEARCH_KDTREE)
        return cli_usage_error(cmd, "%s--backend opencl and --device run --grid-search brute "
                               "only; the kd-tree runs on the host (--backend scalar, host or "
                               "auto)", "");
    return 0;
}

/* What write_one writes: the points alone as OUT, the surface as --mesh,
 * the report. */
typedef struct points_out {
    const relief_mesh *done;
    const char *json;
} points_out;

static relief_status write_one(void *ctx, size_t i, relief_sink *s, relief_error *err)
{
    const points_out *o = ctx;
    const relief_write_options wo = {0};
    relief_mesh points = *o->done; /* a view of done without its triangles */
    points.nt = 0, points.tri = NULL;
    return i == 2 ? cli_json_to(s, o->json, 0, NULL, NULL, err)
                  : relief_mesh_write_to(i == 0 ? &points : o->done, s, &wo, err);
}

/* The grid search's warning, and what the completion did, on stderr. */
static void summary(const points_cli *pc, const relief_complete_points_params *p,
                    const relief_complete_points_report *r)
{
    if (r->grid_search_warning)
        fprintf(stderr, "relief complete-points: warning: %s\n", r->grid_search);
    else if (!pc->cm.quiet && p->grid_search == RELIEF_GRID_SEARCH_BRUTE)
        fprintf(stderr, "relief complete-points: %s\n", r->grid_search);
    if (r->open_loops)
        fprintf(stderr, "relief complete-points: warning: --mesh: %zu loop(s) of %zu edges "
                        "at the filled holes are still open in the surface (the points fill "
                        "them; their patches did not join everywhere)\n",
                r->open_loops, r->open_edges);
    if (pc->cm.quiet)
        return;
    fprintf(stderr, "relief complete-points: %s: %zu points in, %zu added over %u hole(s), "
                    "%zu masked; spacing %.4g, detail RMS %.4g (reconstruction %.3g); "
                    "texture: %d iterations over %zu clusters; %.1f s\n",
            pc->cm.out, r->points_in, r->added, r->holes, r->masked, r->spacing,
            r->detail_rms, r->reconstruction_rms, r->iterations, r->clusters, r->seconds_total);
    if (r->outer_borders + r->holes_too_large + r->holes_not_selected)
        fprintf(stderr, "relief complete-points: left open: %u outer border(s), %u opening(s) "
                        "wider than max_hole %.4g (--max-hole), %u not selected by the hole "
                        "mask (the report lists each)\n",
                r->outer_borders, r->holes_too_large, r->max_hole, r->holes_not_selected);
    if (r->holes_left[0])
        fprintf(stderr, "relief complete-points: %s\n", r->holes_left);
}

/* Read IN (and the clone), complete, write the outputs. */
static int run(const points_cli *pc, relief_complete_points_params *p)
{
    relief_error err = {0};
    relief_complete_points_report rep;
    relief_points_read_info info;
    relief_mesh *in = NULL, *clone = NULL, *done = NULL;
    /* A PCD's header says how many points it holds: one over the limit is
     * refused before its points are decoded. */
    const uint64_t max_points = relief_complete_points_max_points(p);
    cli_progress pr;
    relief_status st = relief_points_read(pc->in, max_points, &in, &info, &err);

    if (st == RELIEF_OK && pc->clone)
        st = relief_points_read(pc->clone, max_points, &clone, NULL, &err);
    if (st == RELIEF_OK) {
        p->has_viewpoint = info.has_viewpoint;
        memcpy(p->viewpoint, info.viewpoint, sizeof p->viewpoint);
        p->non_finite_dropped = info.non_finite_dropped;
        p->clone = clone;
        p->run.input_name = pc->in;
        p->run.output_name = pc->cm.out;
        cli_progress_start(&pr, &pc->cm, &p->run);
        st = relief_complete_points(in, p, &done, &rep, &err);
        cli_progress_end(&pr);
        cli_progress_explain(&pr, st, &err);
    }
    if (st == RELIEF_OK) {
        points_out o = {done, rep.json};
        st = cli_write_outputs(pc->outs, 3, write_one, &o, NULL, &err);
        if (st == RELIEF_OK)
            summary(pc, p, &rep);
        relief_complete_points_report_free(&rep);
    }
    relief_mesh_destroy(done);
    relief_mesh_destroy(clone);
    relief_mesh_destroy(in);
    return st == RELIEF_OK ? 0 : cli_fail(cmd, &err);
}

/* One input (pc->in to pc->cm.out): the checks, then, unless parse_only,
 * the run. Returns the exit status. */
static int one(points_cli *pc, int parse_only)
{
    relief_error err = {0};
    int rc = check_files(pc);
    if (rc)
        return rc;
    if (relief_complete_points_params_validate(&pc->p, &err) != RELIEF_OK)
        return cli_fail(cmd, &err);
    return parse_only ? 0 : run(pc, &pc->p);
}

/* A batch's run on one input (batch.h): a copy of the job, quiet. */
static int batch_one(const void *job, const char *in, const char *out)
{
    points_cli pc = *(const points_cli *)job;
    pc.in = in, pc.cm.out = out, pc.cm.quiet = 1;
    return one(&pc, 0);
}

int cli_cmd_complete_points(int argc, char **argv, int parse_only)
{
    points_cli pc;
    const cli_spec s = spec();
    int rc;
    memset(&pc, 0, sizeof pc);
    pc.cm = cli_common_init(cmd);
    pc.p = relief_complete_points_params_default();
    rc = cli_parse(&s, &pc.cm, &pc.p, take, &pc, argc, argv);
    if (rc)
        return rc < 0 ? 0 : rc;
    if (cli_batch_asked(&pc.cm, argc)) {
        const cli_batch b = {".ply", batch_one, &pc,
                             {{"--report", pc.cm.report}, {"--mesh", pc.mesh}}};
        return cli_batch_run(&pc.cm, &b, argv + optind, argc - optind, parse_only);
    }
    if (!cli_one_input(&pc.cm, argc, argv, "input IN", &pc.in))
        return EXIT_USAGE;
    return one(&pc, parse_only);
}
