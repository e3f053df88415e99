/* relief complete-points: colour and geometric detail completed on a point
 * set with no primitive under it (paper 002; points/complete_points.h). */
#include "cli/commands.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "relief/relief.h"
#include "base/atomic.h"
#include "base/error.h"
#include "base/json.h"
#include "base/memlimit.h"
#include "cli/options.h"
#include "depth/depth_io.h"
#include "mesh/mesh.h"
#include "points/complete_points.h"

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
    "  --band S              exemplars keep S spacings from a rim (default 2)\n"
    "  --seed N              which exemplar grids the texture searches when there\n"
    "                        are over 20 000 to choose from (default 1)\n"
    "  --grid-search S       the texture's nearest exemplar grids: kdtree (FLANN's\n"
    "                        exact kd-tree, default) or brute (every grid; on\n"
    "                        --backend)\n"
    "  --backend B           brute's: auto (OpenCL on a GPU, else scalar), scalar,\n"
    "                        opencl; the same bytes either way\n"
    "  --device N            the OpenCL device (relief devices)\n"
    "  --max-memory SIZE     refuse a run estimated above SIZE (default: a share\n"
    "                        of this machine's memory)\n"
    "  --report R.json       counts, spacing, reconstruction error, energy per\n"
    "                        iteration, times\n"
    "  --quiet               no summary on stderr\n"
    "  -h, --help            this help\n";

enum {
    OPT_COLOUR_ONLY = 512, OPT_GEOMETRY_ONLY, OPT_HOLE_MASK, OPT_SAMPLE_REGION, OPT_K,
    OPT_SMOOTH_STEPS, OPT_GRID, OPT_CLUSTER_SIZE, OPT_ITERATIONS, OPT_BAND, OPT_SMOOTH_ONLY, OPT_MESH, OPT_CLONE_FROM,
    OPT_DETAIL_HISTOGRAM, OPT_NO_DETAIL_HISTOGRAM, OPT_GRID_SEARCH, OPT_MAX_DETAIL
};

/* Read IN: a PCD cloud (its finite points; the sensor at the origin, as
 * PCL's VIEWPOINT default), or a mesh or point file. */
static relief_status read_input(const char *path, uint64_t max_points, relief_mesh **out,
                                int *from_pcd, size_t *dropped, relief_error *err)
{
    relief_depth_frame f;
    relief_status st;
    const char *ext = strrchr(path, '.');

    *from_pcd = 0;
    *dropped = 0;
    if (!ext || strcasecmp(ext, ".pcd") != 0)
        return relief_mesh_read(path, out, NULL, err);
    *from_pcd = 1;
    st = relief_pcd_read_cloud(path, max_points, &f, err);
    if (st != RELIEF_OK)
        return st;
    st = relief_depth_frame_points(&f, path, out, dropped, err);
    relief_depth_frame_free(&f);
    return st;
}

typedef struct report_ctx {
    const char *in, *out, *what;
    const relief_points_params *p;
    const relief_points_report *r;
    size_t dropped;
} report_ctx;

static int write_report(FILE *fp, void *ctx)
{
    const report_ctx *c = ctx;
    const relief_points_report *r = c->r;
    relief_json j;
    rj_init(&j, fp);
    rj_begin_object(&j, NULL);
    rj_string(&j, "command", "complete-points");
    rj_string(&j, "input", c->in);
    rj_string(&j, "output", c->out);
    rj_begin_object(&j, "parameters");
    rj_string(&j, "what", c->what);
    rj_bool(&j, "smooth_only", c->p->smooth_only);
    rj_bool(&j, "detail_histogram", c->p->detail_histogram);
    rj_int(&j, "k", c->p->k);
    rj_int(&j, "smooth_steps", c->p->smooth_steps);
    rj_number(&j, "smooth_dt_spacings", c->p->smooth_dt);
    rj_number(&j, "max_detail_spacings", c->p->max_detail);
    rj_number(&j, "band_spacings", c->p->band);
    rj_number(&j, "seam_band_spacings", c->p->seam_band);
    rj_int(&j, "grid", c->p->tex.grid_n);
    rj_int(&j, "cluster_size", c->p->tex.cluster_size);
    rj_number(&j, "overlap", c->p->tex.overlap);
    rj_int(&j, "max_iterations", c->p->tex.max_iter);
    rj_int(&j, "seed", (long long)c->p->tex.seed);
    rj_end_object(&j);
    rj_begin_object(&j, "points");
    rj_int(&j, "input", (long long)r->n_in);
    rj_int(&j, "non_finite_dropped", (long long)c->dropped);
    rj_int(&j, "added", (long long)r->n_added);
    rj_int(&j, "masked", (long long)r->n_masked);
    rj_int(&j, "clone", (long long)r->n_clone);
    rj_end_object(&j);
    rj_begin_object(&j, "holes");
    rj_int(&j, "filled", r->holes.n_holes);
    rj_int(&j, "outer_borders", r->holes.n_borders);
    rj_int(&j, "too_small", r->holes.n_dropped);
    rj_end_object(&j);
    rj_number(&j, "spacing", r->spacing);
    rj_int(&j, "patch_triangles", (long long)r->patch_triangles);
    rj_int(&j, "patch_holes_skipped", (long long)r->patch_skipped);
    if (c->p->mesh) {
        rj_begin_object(&j, "mesh");
        rj_int(&j, "triangles", (long long)r->mesh_triangles);
        if (r->mesh_of_points) {
            rj_int(&j, "candidates", (long long)r->mesh_candidates);
            rj_int(&j, "boundary_edges", (long long)r->mesh_boundary_edges);
            rj_int(&j, "bare_points", (long long)r->mesh_bare_points);
        }
        rj_end_object(&j);
    }
    rj_begin_object(&j, "base");
    rj_number(&j, "detail_rms", r->detail_rms);
    rj_number(&j, "reconstruction_rms", r->recon_rms);
    rj_end_object(&j);
    rj_begin_object(&j, "texture");
    rj_int(&j, "channels", r->tex_channels);
    rj_string(&j, "grid_search", r->tex.search);
    rj_int(&j, "clusters", (long long)r->tex.clusters);
    rj_int(&j, "active_clusters", (long long)r->tex.active_clusters);
    rj_int(&j, "exemplars", (long long)r->tex.exemplars);
    rj_int(&j, "iterations", r->tex.iterations);
    rj_int(&j, "grid_used", r->tex.grid_n);
    rj_int(&j, "cluster_size_used", r->tex.cluster_size);
    rj_bool(&j, "converged", r->tex.converged);
    rj_begin_array(&j, "energy");
    for (int i = 0; i < r->tex.iterations; ++i)
        rj_number(&j, NULL, r->tex.energy[i]);
    rj_end_array(&j);
    rj_end_object(&j);
    rj_begin_object(&j, "seconds");
    rj_number(&j, "analysis", r->t_analysis);
    rj_number(&j, "base", r->t_base);
    rj_number(&j, "fill", r->t_fill);
    rj_number(&j, "texture", r->t_texture);
    rj_number(&j, "total", r->t_total);
    rj_end_object(&j);
    rj_end_object(&j);
    return 0;
}

/* --hole-mask: "label" or "ball:X,Y,Z,R" into a mask of m's points. */
static int build_mask(const char *spec, relief_mesh *m, uint8_t **mask_out)
{
    size_t n = m->nv;
    uint8_t *mask = calloc(n + 1, 1);
    if (!mask) {
        fprintf(stderr, "relief complete-points: error: cannot allocate the mask\n");
        return EXIT_INTERNAL;
    }
    if (strcmp(spec, "label") == 0) {
        if (!m->label) {
            free(mask);
            fprintf(stderr, "relief complete-points: error: --hole-mask label: the input has no "
                            "`label` property\n");
            return EXIT_USAGE;
        }
        for (size_t i = 0; i < n; ++i)
            mask[i] = m->label[i] != 0;
    } else {
        double v[4];
        int k = 0;
        if (strncmp(spec, "ball:", 5) != 0 ||
            !cli_parse_reals("complete-points", "--hole-mask", spec + 5, v, 4, &k) || k != 4 ||
            !(v[3] > 0.0)) {
            free(mask);
            return cli_usage_error("complete-points", "--hole-mask: expected 'label' or "
                                   "'ball:X,Y,Z,R' with R > 0, got '%s'", spec);
        }
        for (size_t i = 0; i < n; ++i) {
            double d2 = 0.0;
            for (int c = 0; c < 3; ++c)
                d2 += (m->pos[3 * i + c] - v[c]) * (m->pos[3 * i + c] - v[c]);
            mask[i] = d2 <= v[3] * v[3];
        }
    }
    *mask_out = mask;
    return 0;
}

int cli_cmd_complete_points(int argc, char **argv, int parse_only)
{
    static const struct option opts[] = {
        {"output", required_argument, 0, 'o'},
        {"report", required_argument, 0, OPT_REPORT},
        {"colour-only", no_argument, 0, OPT_COLOUR_ONLY},
        {"geometry-only", no_argument, 0, OPT_GEOMETRY_ONLY},
        {"hole-mask", required_argument, 0, OPT_HOLE_MASK},
        {"smooth-only", no_argument, 0, OPT_SMOOTH_ONLY},
        {"detail-histogram", no_argument, 0, OPT_DETAIL_HISTOGRAM}, /* the default */
        {"no-detail-histogram", no_argument, 0, OPT_NO_DETAIL_HISTOGRAM},
        {"mesh", required_argument, 0, OPT_MESH},
        {"clone-from", required_argument, 0, OPT_CLONE_FROM},
        {"sample-region", required_argument, 0, OPT_SAMPLE_REGION},
        {"k", required_argument, 0, OPT_K},
        {"grid-search", required_argument, 0, OPT_GRID_SEARCH},
        {"backend", required_argument, 0, OPT_BACKEND},
        {"device", required_argument, 0, OPT_DEVICE},
        {"smooth-steps", required_argument, 0, OPT_SMOOTH_STEPS},
        {"max-detail", required_argument, 0, OPT_MAX_DETAIL},
        {"grid", required_argument, 0, OPT_GRID},
        {"cluster-size", required_argument, 0, OPT_CLUSTER_SIZE},
        {"iterations", required_argument, 0, OPT_ITERATIONS},
        {"band", required_argument, 0, OPT_BAND},
        {"seed", required_argument, 0, OPT_SEED},
        {"max-memory", required_argument, 0, OPT_MAX_MEMORY},
        {"quiet", no_argument, 0, OPT_QUIET},
        {"help", no_argument, 0, 'h'},
        {0, 0, 0, 0}};
    relief_points_params p = relief_points_params_default();
    relief_points_report rep;
    relief_error err = {RELIEF_OK, ""};
    relief_mesh *in = NULL, *out = NULL;
    uint8_t *mask = NULL, *sample = NULL;
    const char *out_path = NULL, *report = NULL, *in_path, *mask_spec = NULL, *mesh_path = NULL;
    const char *clone_path = NULL;
    relief_mesh *clone = NULL;
    const char *what = "all";
    double box[6];
    int c, rc = 0, quiet = 0, have_box = 0, from_pcd, nb = 0, sample_label = -1;
    int backend_given = 0;
    uint64_t max_memory = 0;
    size_t dropped = 0;
    long v;
    sigset_t held;
    static const double origin[3] = {0.0, 0.0, 0.0};

    optind = 0;
    while ((c = getopt_long(argc, argv, "o:h", opts, NULL)) != -1) {
        switch (c) {
        case 'o': out_path = optarg; break;
        case OPT_REPORT: report = optarg; break;
        case OPT_COLOUR_ONLY:
        case OPT_GEOMETRY_ONLY: {
            const relief_points_what want = c == OPT_COLOUR_ONLY ? RELIEF_POINTS_COLOUR_ONLY
                                                                 : RELIEF_POINTS_GEOMETRY_ONLY;
            if (p.what != RELIEF_POINTS_ALL && p.what != want)
                return cli_usage_error("complete-points", "%s--colour-only and --geometry-only "
                                       "exclude each other", "");
            p.what = want, what = c == OPT_COLOUR_ONLY ? "colour" : "geometry";
            break;
        }
        case OPT_HOLE_MASK: mask_spec = optarg; break;
        case OPT_SMOOTH_ONLY: p.smooth_only = 1; break;
        case OPT_DETAIL_HISTOGRAM: p.detail_histogram = 1; break;
        case OPT_NO_DETAIL_HISTOGRAM: p.detail_histogram = 0; break;
        case OPT_MESH: mesh_path = optarg, p.mesh = 1; break;
        case OPT_CLONE_FROM: clone_path = optarg; break;
        case OPT_SAMPLE_REGION:
            if (strcmp(optarg, "label") == 0) {
                sample_label = 1;
                have_box = 0;
                break;
            }
            if (!cli_parse_reals("complete-points", "--sample-region", optarg, box, 6, &nb))
                return EXIT_USAGE;
            if (nb != 6 || !(box[0] < box[3] && box[1] < box[4] && box[2] < box[5]))
                return cli_usage_error("complete-points", "--sample-region: expected "
                                       "X0,Y0,Z0,X1,Y1,Z1 with X0 < X1, Y0 < Y1, Z0 < Z1, got "
                                       "'%s'", optarg);
            have_box = 1, sample_label = -1;
            break;
        case OPT_K:
            if (!cli_parse_int_range("complete-points", "--k", optarg, 6, 64, &v))
                return EXIT_USAGE;
            p.k = (int)v;
            break;
        case OPT_SMOOTH_STEPS:
            if (!cli_parse_int_range("complete-points", "--smooth-steps", optarg, 0, 10000, &v))
                return EXIT_USAGE;
            p.smooth_steps = (int)v;
            break;
        case OPT_MAX_DETAIL:
            if (!cli_parse_real("complete-points", "--max-detail", optarg, &p.max_detail))
                return EXIT_USAGE;
            if (!(p.max_detail >= 0.0 && p.max_detail <= 100.0))
                return cli_usage_error("complete-points", "--max-detail: spacings in 0..100, "
                                       "got '%s'", optarg);
            break;
        case OPT_GRID:
            if (!cli_parse_int_range("complete-points", "--grid", optarg, 3, 33, &v))
                return EXIT_USAGE;
            if (v % 2 == 0)
                return cli_usage_error("complete-points", "--grid: an odd side 3..33, got '%s'",
                                       optarg);
            p.tex.grid_n = (int)v;
            break;
        case OPT_CLUSTER_SIZE:
            if (!cli_parse_int_range("complete-points", "--cluster-size", optarg, 16, 100000, &v))
                return EXIT_USAGE;
            p.tex.cluster_size = (int)v;
            break;
        case OPT_ITERATIONS:
            if (!cli_parse_int_range("complete-points", "--iterations", optarg, 1, 1000, &v))
                return EXIT_USAGE;
            p.tex.max_iter = (int)v;
            break;
        case OPT_BAND:
            if (!cli_parse_real("complete-points", "--band", optarg, &p.band))
                return EXIT_USAGE;
            if (!(p.band >= 0.0 && p.band <= 1e6))
                return cli_usage_error("complete-points", "--band: spacings in 0..1e6, got '%s'",
                                       optarg);
            break;
        case OPT_SEED:
            if (!cli_parse_int_range("complete-points", "--seed", optarg, 0, 4294967295L, &v))
                return EXIT_USAGE;
            p.tex.seed = (uint64_t)v;
            break;
        case OPT_MAX_MEMORY:
            if (relief_parse_size(optarg, &max_memory, &err) != RELIEF_OK)
                return cli_usage_error("complete-points", "--max-memory: %s", err.message);
            break;
        case OPT_GRID_SEARCH:
            if (strcmp(optarg, "kdtree") == 0)
                p.tex.brute = 0;
            else if (strcmp(optarg, "brute") == 0)
                p.tex.brute = 1;
            else
                return cli_usage_error("complete-points", "--grid-search: '%s' is not one of "
                                       "kdtree, brute", optarg);
            break;
        case OPT_BACKEND:
            if (!cli_parse_backend("complete-points", optarg, 0, &p.tex.backend))
                return EXIT_USAGE;
            backend_given = 1;
            break;
        case OPT_DEVICE:
            if (!cli_parse_int_range("complete-points", "--device", optarg, 0, 255, &v))
                return EXIT_USAGE;
            p.tex.device = (int)v;
            backend_given = 1;
            break;
        case OPT_QUIET: quiet = 1; break;
        case 'h': fputs(points_help, stdout); return 0;
        default: fprintf(stderr, "Try 'relief complete-points --help'.\n"); return EXIT_USAGE;
        }
    }
    if (optind >= argc)
        return cli_usage_error("complete-points", "%smissing input IN", "");
    if (argc - optind > 1)
        return cli_usage_error("complete-points", "unexpected argument '%s'", argv[optind + 1]);
    in_path = argv[optind];
    if (!out_path)
        return cli_usage_error("complete-points", "%smissing -o OUT.ply", "");
    if (strcasecmp(cli_ext_of(out_path), ".ply") != 0)
        return cli_usage_error("complete-points", "-o: '%s' is not a .ply (the completed points "
                               "carry colour, normals and a label, which only PLY keeps)",
                               out_path);
    if (cli_same_file(in_path, out_path))
        return cli_usage_error("complete-points", "-o: '%s' is the input; relief never "
                               "overwrites it", out_path);
    if (report && (cli_same_file(in_path, report) || cli_same_file(out_path, report)))
        return cli_usage_error("complete-points", "--report: '%s' is the input or the output",
                               report);
    if (mesh_path && !cli_known_mesh_ext(mesh_path))
        return cli_usage_error("complete-points", "--mesh: '%s' has no mesh extension (.ply .obj "
                               ".off .stl)", mesh_path);
    if (mesh_path && (cli_same_file(in_path, mesh_path) || cli_same_file(out_path, mesh_path) ||
                      (report && cli_same_file(report, mesh_path))))
        return cli_usage_error("complete-points", "--mesh: '%s' is the input or another output",
                               mesh_path);
    if (clone_path && cli_same_file(clone_path, out_path))
        return cli_usage_error("complete-points", "--clone-from: '%s' is the output", clone_path);
    if (clone_path && p.smooth_only)
        return cli_usage_error("complete-points", "%s--clone-from copies detail, which "
                               "--smooth-only leaves out", "");
    if (sample_label >= 0 && mask_spec && strcmp(mask_spec, "label") == 0)
        return cli_usage_error("complete-points", "%s--hole-mask label and --sample-region label "
                               "would read the same labels", "");
    if (p.what == RELIEF_POINTS_COLOUR_ONLY && !mask_spec)
        return cli_usage_error("complete-points", "%s--colour-only completes the colour of the "
                               "--hole-mask points: give --hole-mask", "");
    if (backend_given && !p.tex.brute)
        return cli_usage_error("complete-points", "%s--backend and --device choose where "
                               "--grid-search brute runs; the kd-tree runs on the host", "");
    if (parse_only)
        return 0;

    /* A PCD's header says how many points it holds: one over the limit
     * (by the per-point share of the estimate below) is refused before
     * its points are decoded, as depth-fill does. */
    {
        uint64_t limit = max_memory ? max_memory : relief_default_memory_limit();
        uint64_t max_points = limit ? limit / ((uint64_t)(12 * p.k + 300) * 5) + 1 : 0;
        if (read_input(in_path, max_points, &in, &from_pcd, &dropped, &err) != RELIEF_OK)
            return cli_fail("complete-points", &err);
    }
    if (from_pcd)
        p.viewpoint = origin;
    {
        /* What a run holds at its peak, about: the k-NN graph (12 k bytes a
         * point), a dozen n x 3 double arrays, and the texture's exemplar
         * grids (grid^2 x 4 channels floats over at most 20 000 of them). */
        uint64_t n = in->nv, need = n * (uint64_t)(12 * p.k + 300) * 5 +
                                    20000ull * (uint64_t)p.tex.grid_n * p.tex.grid_n * 16;
        uint64_t limit = max_memory ? max_memory : relief_default_memory_limit();
        if (limit && need > limit) {
            fprintf(stderr, "relief complete-points: error: %s: about %.1f MiB needed for %zu "
                            "points, over the limit of %.1f MiB (--max-memory)\n",
                    in_path, need / 1048576.0, in->nv, limit / 1048576.0);
            relief_mesh_destroy(in);
            return EXIT_INTERNAL;
        }
    }
    if (mask_spec) {
        rc = build_mask(mask_spec, in, &mask);
        if (rc) {
            relief_mesh_destroy(in);
            return rc;
        }
        p.hole_mask = mask;
    }
    if (sample_label >= 0 && !in->label) {
        free(mask);
        relief_mesh_destroy(in);
        fprintf(stderr, "relief complete-points: error: --sample-region label: the input has "
                        "no `label` property\n");
        return EXIT_USAGE;
    }
    if (have_box || sample_label >= 0) {
        sample = calloc(in->nv + 1, 1);
        if (!sample) {
            free(mask);
            relief_mesh_destroy(in);
            fprintf(stderr, "relief complete-points: error: cannot allocate the sample region\n");
            return EXIT_INTERNAL;
        }
        for (size_t i = 0; i < in->nv; ++i) {
            const double *q = in->pos + 3 * i;
            sample[i] = sample_label >= 0
                            ? in->label[i] == sample_label
                            : q[0] >= box[0] && q[0] <= box[3] && q[1] >= box[1] &&
                                  q[1] <= box[4] && q[2] >= box[2] && q[2] <= box[5];
        }
        p.sample_mask = sample;
    }
    if (clone_path) {
        int clone_pcd;
        size_t clone_dropped;
        uint64_t limit = max_memory ? max_memory : relief_default_memory_limit();
        uint64_t max_points = limit ? limit / ((uint64_t)(12 * p.k + 300) * 5) + 1 : 0;
        if (read_input(clone_path, max_points, &clone, &clone_pcd, &clone_dropped, &err) !=
            RELIEF_OK) {
            rc = cli_fail("complete-points", &err);
            goto done;
        }
        p.clone = clone;
    }
    if (relief_points_complete(in, &p, &out, &rep, &err) != RELIEF_OK) {
        rc = cli_fail("complete-points", &err);
        goto done;
    }
    cli_hold_signals(&held);
    {
        relief_write_options wo = {0};
        report_ctx rc_ctx = {in_path, out_path, what, &p, &rep, dropped};
        relief_mesh points = *out; /* the points alone, a view of out */
        relief_status st;
        points.nt = 0, points.tri = NULL;
        st = relief_mesh_write(&points, out_path, &wo, &err);
        if (st == RELIEF_OK && mesh_path)
            st = relief_mesh_write(out, mesh_path, &wo, &err);
        if (st == RELIEF_OK && report)
            st = relief_atomic_write_text(report, write_report, &rc_ctx, &err);
        if (st != RELIEF_OK) {
            rc = cli_fail("complete-points", &err);
            remove(out_path); /* all or none */
            if (mesh_path)
                remove(mesh_path);
        }
    }
    cli_release_signals(&held);
    if (!rc && strncmp(rep.tex.search, "OpenCL unavailable", 18) == 0)
        fprintf(stderr, "relief complete-points: warning: %s\n", rep.tex.search);
    else if (!rc && !quiet && p.tex.brute)
        fprintf(stderr, "relief complete-points: %s\n", rep.tex.search);
    if (!rc && !quiet)
        fprintf(stderr, "relief complete-points: %s: %zu points in, %zu added over %u hole(s)%s, "
                        "%zu masked; spacing %.4g, detail RMS %.4g (reconstruction %.3g); "
                        "texture: %d iterations over %zu clusters; %.1f s\n",
                out_path, rep.n_in, rep.n_added, rep.holes.n_holes,
                rep.holes.n_borders ? " (an outer border left open)" : "", rep.n_masked,
                rep.spacing, rep.detail_rms, rep.recon_rms, rep.tex.iterations, rep.tex.clusters,
                rep.t_total);
    relief_points_report_free(&rep);
done:
    relief_mesh_destroy(clone);
    relief_mesh_destroy(out);
    relief_mesh_destroy(in);
    free(mask);
    free(sample);
    return rc;
}
