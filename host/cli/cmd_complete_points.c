/* relief complete-points: colour and geometric detail completed on a point
 * set with no primitive under it (paper 002), a client of
 * relief_complete_points (relief/points.h): options, the files, the
 * summary. */
#include "cli/commands.h"

#include <getopt.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "relief/relief.h"
#include "cli/options.h"
#include "mesh/mesh.h"

static const char points_help[] =
    "usage: relief complete-points IN -o OUT.ply [--colour-only | --geometry-only]\n"
    "                              [--report R.json] [options]\n"
    "\n"
    "Complete the holes of a point set or mesh that no plane, sphere or cylinder\n"
    "fits (paper 002): the detail is peeled off as a signed height over a\n"
    "smoothed base, the base's holes are filled by a smooth implicit surface\n"
    "(compactly supported RBF), and the height and the colour are synthesised on\n"
    "the new points by texture optimisation over overlapping clusters. IN: PLY,\n"
    "OBJ, OFF, STL or PCD (organised or not), with or without colour; a mesh's\n"
    "holes are its boundary loops, a bare point set's are where points see\n"
    "neighbours on one side only; the outer border of an open scan is left open.\n"
    "OUT: a PLY point set, the input's points first (label 0) then the new ones\n"
    "(label 1), with colour when IN has it and normals. IN is never written.\n"
    "\n"
    "  -o, --output OUT.ply  the completed points; required\n"
    "  --mesh M.ply          also write the completed surface: a mesh's triangles\n"
    "                        and patches over the filled holes; for a point set,\n"
    "                        local Delaunay umbrellas through all the points\n"
    "  --colour-only         synthesise the colour of the --hole-mask points only\n"
    "  --geometry-only       new points and their detail; colour from the rim\n"
    "  --smooth-only         the smooth fill alone (no detail, colour from the\n"
    "                        rim): the baseline of the paper's Fig. 9g\n"
    "  --no-detail-histogram leave the new points' detail as the texture\n"
    "                        optimisation averaged it (by default it takes the\n"
    "                        distribution of the capture about the hole, by\n"
    "                        histogram matching: as rough as the scan's own;\n"
    "                        --detail-histogram, the default)\n"
    "  --clone-from FILE     copy the detail (and colour, when both have it) from\n"
    "                        another scan, sampled about as densely (paper 6.3)\n"
    "  --hole-mask WHAT      points to synthesise again besides the holes: 'label'\n"
    "                        (IN's PLY label 1) or 'ball:X,Y,Z,R'\n"
    "  --sample-region R     exemplars only inside the box X0,Y0,Z0,X1,Y1,Z1 (IN's\n"
    "                        units), or on the points IN's PLY labels 1 ('label')\n"
    "  --k N                 neighbours of the local analysis, 6..64 (default 16)\n"
    "  --smooth-steps N      curvature-flow steps of the base, 0..10000 (default 20)\n"
    "  --max-detail S        the base keeps within S spacings of every point, so\n"
    "                        that thin parts stay shape, not detail, 0..100\n"
    "                        (default 1; 0: no bound)\n"
    "  --grid N              texture grid side, odd, 3..33 (default 23)\n"
    "  --cluster-size N      points per cluster before overlap, 16..100000\n"
    "                        (default 300)\n"
    "  --iterations N        texture optimisation iterations, 1..1000 (default 50)\n"
    "  --band S              exemplars keep S spacings from a rim, 0..1e6 (default 2)\n"
    "  --seed N              which exemplar grids the texture searches when there\n"
    "                        are over 20 000 to choose from (default 1)\n"
    "  --grid-search S       the texture's nearest exemplar grids: kdtree (FLANN's\n"
    "                        exact kd-tree, default) or brute (every grid; on\n"
    "                        --backend)\n"
    "  --backend B           brute's: auto (OpenCL on a GPU, else scalar), scalar,\n"
    "                        opencl (host runs as scalar); the same bytes either way\n"
    "  --device N            the OpenCL device (relief devices)\n"
    "  --max-memory SIZE     refuse a run estimated above SIZE (default: a share\n"
    "                        of this machine's memory)\n"
    "  --report R.json       counts, spacing, reconstruction error, energy per\n"
    "                        iteration, times\n"
    "  --quiet               no summary on stderr\n"
    "  -h, --help            this help\n";

enum {
    OPT_CP_COLOUR_ONLY = OPT_COMMAND, OPT_CP_GEOMETRY_ONLY, OPT_CP_HOLE_MASK,
    OPT_CP_SAMPLE_REGION, OPT_CP_K, OPT_CP_SMOOTH_STEPS, OPT_CP_GRID, OPT_CP_CLUSTER_SIZE,
    OPT_CP_ITERATIONS, OPT_CP_BAND, OPT_CP_SMOOTH_ONLY, OPT_CP_MESH, OPT_CP_CLONE_FROM,
    OPT_CP_DETAIL_HISTOGRAM, OPT_CP_NO_DETAIL_HISTOGRAM, OPT_CP_GRID_SEARCH, OPT_CP_MAX_DETAIL
};

/* What the command knows that the parameters do not. */
typedef struct points_cli {
    cli_common cm;
    const char *in, *mesh, *clone;
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

/* --hole-mask label | ball:X,Y,Z,R (R's range is the parameters'). */
static int parse_hole_mask(const char *arg, relief_complete_points_params *p)
{
    int k = 0;
    p->hole_labels = p->has_hole_ball = 0;
    if (strcmp(arg, "label") == 0) {
        p->hole_labels = 1;
        return 1;
    }
    if (strncmp(arg, "ball:", 5) != 0 ||
        !cli_parse_reals(cmd, "--hole-mask", arg + 5, p->hole_ball, 4, &k) || k != 4) {
        cli_usage_error(cmd, "--hole-mask: expected 'label' or 'ball:X,Y,Z,R' with R > 0, got "
                        "'%s'", arg);
        return 0;
    }
    p->has_hole_ball = 1;
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

/* One of the command's own options: 1 taken, 0 a bad value (said). */
static int own_option(int c, const char *arg, points_cli *pc, relief_complete_points_params *p)
{
    static const char *const searches[] = CLI_NAMES(RELIEF_GRID_SEARCH_LIST);
    int v;
    switch (c) {
    case OPT_CP_COLOUR_ONLY: return set_what(p, RELIEF_POINTS_COLOUR_ONLY);
    case OPT_CP_GEOMETRY_ONLY: return set_what(p, RELIEF_POINTS_GEOMETRY_ONLY);
    case OPT_CP_HOLE_MASK: return parse_hole_mask(arg, p);
    case OPT_CP_SAMPLE_REGION: return parse_sample_region(arg, p);
    case OPT_CP_SMOOTH_ONLY: p->smooth_only = 1; return 1;
    case OPT_CP_DETAIL_HISTOGRAM: p->detail_histogram = 1; return 1;
    case OPT_CP_NO_DETAIL_HISTOGRAM: p->detail_histogram = 0; return 1;
    case OPT_CP_MESH: pc->mesh = arg, p->mesh = 1; return 1;
    case OPT_CP_CLONE_FROM: pc->clone = arg; return 1;
    case OPT_CP_K: return cli_parse_int(cmd, "--k", arg, &p->k);
    case OPT_CP_SMOOTH_STEPS: return cli_parse_int(cmd, "--smooth-steps", arg, &p->smooth_steps);
    case OPT_CP_MAX_DETAIL: return cli_parse_real(cmd, "--max-detail", arg, &p->max_detail);
    case OPT_CP_GRID: return cli_parse_int(cmd, "--grid", arg, &p->grid);
    case OPT_CP_CLUSTER_SIZE: return cli_parse_int(cmd, "--cluster-size", arg, &p->cluster_size);
    case OPT_CP_ITERATIONS: return cli_parse_int(cmd, "--iterations", arg, &p->iterations);
    case OPT_CP_BAND: return cli_parse_real(cmd, "--band", arg, &p->band);
    case OPT_CP_GRID_SEARCH:
        if (!CLI_PARSE_ENUM(cmd, "--grid-search", arg, searches, &v))
            return 0;
        p->grid_search = (relief_grid_search)v;
        return 1;
    }
    fprintf(stderr, "Try 'relief complete-points --help'.\n");
    return 0;
}

/* The options into pc and p. Returns -1 to go on, else the exit status. */
static int parse(int argc, char **argv, points_cli *pc, relief_complete_points_params *p)
{
    static const struct option own[] = {
        {"colour-only", no_argument, 0, OPT_CP_COLOUR_ONLY},
        {"geometry-only", no_argument, 0, OPT_CP_GEOMETRY_ONLY},
        {"hole-mask", required_argument, 0, OPT_CP_HOLE_MASK},
        {"smooth-only", no_argument, 0, OPT_CP_SMOOTH_ONLY},
        {"detail-histogram", no_argument, 0, OPT_CP_DETAIL_HISTOGRAM}, /* the default */
        {"no-detail-histogram", no_argument, 0, OPT_CP_NO_DETAIL_HISTOGRAM},
        {"mesh", required_argument, 0, OPT_CP_MESH},
        {"clone-from", required_argument, 0, OPT_CP_CLONE_FROM},
        {"sample-region", required_argument, 0, OPT_CP_SAMPLE_REGION},
        {"k", required_argument, 0, OPT_CP_K},
        {"grid-search", required_argument, 0, OPT_CP_GRID_SEARCH},
        {"smooth-steps", required_argument, 0, OPT_CP_SMOOTH_STEPS},
        {"max-detail", required_argument, 0, OPT_CP_MAX_DETAIL},
        {"grid", required_argument, 0, OPT_CP_GRID},
        {"cluster-size", required_argument, 0, OPT_CP_CLUSTER_SIZE},
        {"iterations", required_argument, 0, OPT_CP_ITERATIONS},
        {"band", required_argument, 0, OPT_CP_BAND},
        {0, 0, 0, 0}};
    struct option opts[40];
    int c;

    cli_options(CLI_ENGINE, own, opts, sizeof opts / sizeof opts[0]);
    optind = 0;
    while ((c = getopt_long(argc, argv, "o:h", opts, NULL)) != -1) {
        int taken = cli_common_option(&pc->cm, c, optarg);
        if (taken < 0)
            return EXIT_USAGE;
        if (c == 'h') {
            fputs(points_help, stdout);
            return 0;
        }
        if (!taken && !own_option(c, optarg, pc, p))
            return EXIT_USAGE;
    }
    if (pc->cm.seed_given)
        p->seed = pc->cm.seed;
    p->run.backend = pc->cm.run.backend;
    p->run.device = pc->cm.run.device;
    p->run.max_memory = pc->cm.run.max_memory;
    return -1;
}

/* The operand and the files: -o a PLY, --mesh a mesh, none of them an input
 * or another output. 0 when they will do, else the exit status (said). */
static int check_files(int argc, char **argv, points_cli *pc, relief_grid_search search)
{
    const cli_common *cm = &pc->cm;
    if (!cli_one_input(cm, argc, argv, "input IN", &pc->in))
        return EXIT_USAGE;
    if (strcasecmp(cli_ext_of(cm->out), ".ply") != 0)
        return cli_usage_error(cmd, "-o: '%s' is not a .ply (the completed points carry "
                               "colour, normals and a label, which only PLY keeps)", cm->out);
    if (pc->mesh && !cli_known_mesh_ext(pc->mesh))
        return cli_usage_error(cmd, "--mesh: '%s' has no mesh extension (.ply .obj .off .stl)",
                               pc->mesh);
    {
        const char *ins[] = {pc->in, pc->clone}, *outs[] = {cm->out, cm->report, pc->mesh};
        if (cli_outputs_clash(cmd, ins, 2, outs, 3))
            return EXIT_USAGE;
    }
    if (cm->backend_given && search == RELIEF_GRID_SEARCH_KDTREE)
        return cli_usage_error(cmd, "%s--backend and --device choose where --grid-search brute "
                               "runs; the kd-tree runs on the host", "");
    return 0;
}

/* The points alone as OUT, the surface as --mesh, the report: all or none. */
static relief_status write_outputs(const points_cli *pc, const relief_mesh *done,
                                   const relief_complete_points_report *rep, relief_error *err)
{
    const relief_write_options wo = {0};
    relief_mesh points = *done; /* a view of done without its triangles */
    relief_status st;
    sigset_t held;
    points.nt = 0, points.tri = NULL;
    cli_hold_signals(&held);
    st = relief_mesh_write(&points, pc->cm.out, &wo, err);
    if (st == RELIEF_OK && pc->mesh)
        st = relief_mesh_write(done, pc->mesh, &wo, err);
    if (st == RELIEF_OK && pc->cm.report)
        st = cli_write_json(pc->cm.report, rep->json, 0, NULL, NULL, err);
    if (st != RELIEF_OK) {
        remove(pc->cm.out);
        if (pc->mesh)
            remove(pc->mesh);
    }
    cli_release_signals(&held);
    return st;
}

/* The grid search's warning, and what the completion did, on stderr. */
static void summary(const points_cli *pc, const relief_complete_points_params *p,
                    const relief_complete_points_report *r)
{
    if (r->grid_search_warning)
        fprintf(stderr, "relief complete-points: warning: %s\n", r->grid_search);
    else if (!pc->cm.quiet && p->grid_search == RELIEF_GRID_SEARCH_BRUTE)
        fprintf(stderr, "relief complete-points: %s\n", r->grid_search);
    if (pc->cm.quiet)
        return;
    fprintf(stderr, "relief complete-points: %s: %zu points in, %zu added over %u hole(s)%s, "
                    "%zu masked; spacing %.4g, detail RMS %.4g (reconstruction %.3g); "
                    "texture: %d iterations over %zu clusters; %.1f s\n",
            pc->cm.out, r->points_in, r->added, r->holes,
            r->outer_borders ? " (an outer border left open)" : "", r->masked, r->spacing,
            r->detail_rms, r->reconstruction_rms, r->iterations, r->clusters, r->seconds_total);
}

/* Read IN (and the clone), complete, write the outputs. */
static int run(const points_cli *pc, relief_complete_points_params *p)
{
    relief_error err = {RELIEF_OK, ""};
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
        p->run.progress = cli_progress_fn;
        p->run.progress_ctx = &pr;
        cli_progress_start(&pr, cmd, pc->cm.quiet);
        st = relief_complete_points(in, p, &done, &rep, &err);
        cli_progress_end(&pr);
    }
    if (st == RELIEF_OK) {
        st = write_outputs(pc, done, &rep, &err);
        if (st == RELIEF_OK)
            summary(pc, p, &rep);
        relief_complete_points_report_free(&rep);
    }
    relief_mesh_destroy(done);
    relief_mesh_destroy(clone);
    relief_mesh_destroy(in);
    return st == RELIEF_OK ? 0 : cli_fail(cmd, &err);
}

int cli_cmd_complete_points(int argc, char **argv, int parse_only)
{
    points_cli pc = {cli_common_init(cmd), NULL, NULL, NULL};
    relief_complete_points_params p = relief_complete_points_params_default();
    relief_error err = {RELIEF_OK, ""};
    int rc = parse(argc, argv, &pc, &p);

    if (rc >= 0)
        return rc;
    rc = check_files(argc, argv, &pc, p.grid_search);
    if (rc)
        return rc;
    if (relief_complete_points_params_validate(&p, &err) != RELIEF_OK)
        return cli_fail(cmd, &err);
    if (parse_only)
        return 0;
    return run(&pc, &p);
}
