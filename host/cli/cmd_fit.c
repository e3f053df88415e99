/* relief fit: fit a primitive and print it. */
#include "cli/commands.h"

#include <getopt.h>
#include <stdio.h>

#include "relief/relief.h"
#include "base/json.h"
#include "cli/options.h"
#include "report/report.h"
#include "smooth/fit.h"

static const char fit_help[] =
    "usage: relief fit IN [--fit auto|plane|sphere|cylinder] [--json]\n"
    "\n"
    "Fit a primitive to the points of IN (least-squares start, then orthogonal-\n"
    "distance refinement with outliers trimmed) and print its parameters in the\n"
    "input's units, the RMS orthogonal residual over the inliers and the\n"
    "fraction of points within 3 RMS. auto picks the model whose residual,\n"
    "penalised 10% per extra parameter, is lowest, and says why. A fit whose\n"
    "RMS exceeds 10% of the primitive's size is reported as poor on stderr.\n"
    "\n"
    "  --fit MODEL           auto|plane|sphere|cylinder (default auto)\n"
    "  --json                one JSON object: model, rms, inlier_fraction and\n"
    "                        point/normal, center/radius or axis_point/axis_dir/radius\n"
    "  -h, --help            this help\n";

static void print_fit_json(FILE *f, const char *path, const relief_fit_result *r)
{
    relief_json j;
    rj_init(&j, f);
    rj_begin_object(&j, NULL);
    rj_string(&j, "input", path);
    relief_report_fit_fields(&j, r);
    rj_end_object(&j);
}

int cli_cmd_fit(int argc, char **argv, int parse_only)
{
    enum { OPT_FIT = OPT_COMMAND, OPT_JSON };
    static const char *const fits[] = CLI_NAMES(RELIEF_FIT_MODEL_LIST);
    static const struct option opts[] = {{"fit", required_argument, 0, OPT_FIT},
                                         {"json", no_argument, 0, OPT_JSON},
                                         {"help", no_argument, 0, 'h'},
                                         {0, 0, 0, 0}};
    relief_fit_model model = RELIEF_FIT_AUTO;
    relief_error err = {RELIEF_OK, ""};
    relief_fit_result r;
    relief_mesh *in = NULL;
    relief_status st;
    int c, v, json = 0;

    optind = 0;
    while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
        switch (c) {
        case OPT_FIT:
            if (!CLI_PARSE_ENUM("fit", "--fit", optarg, fits, &v))
                return EXIT_USAGE;
            model = (relief_fit_model)v;
            break;
        case OPT_JSON: json = 1; break;
        case 'h': fputs(fit_help, stdout); return 0;
        default: fprintf(stderr, "Try 'relief fit --help'.\n"); return EXIT_USAGE;
        }
    }
    if (optind >= argc)
        return cli_usage_error("fit", "%smissing input mesh IN", "");
    if (argc - optind > 1)
        return cli_usage_error("fit", "unexpected argument '%s'", argv[optind + 1]);
    if (parse_only)
        return 0;
    if (relief_mesh_read(argv[optind], &in, NULL, &err) != RELIEF_OK)
        return cli_fail("fit", &err);
    st = relief_fit_mesh(in, model, &r, &err);
    relief_mesh_destroy(in);
    if (st != RELIEF_OK)
        return cli_fail("fit", &err);
    if (json) {
        print_fit_json(stdout, argv[optind], &r);
    } else {
        const relief_fit_primitive *p = &r.prim;
        printf("model: %s\n", relief_fit_model_name(p->model));
        if (p->model == RELIEF_FIT_PLANE)
            printf("point: %.10g %.10g %.10g\nnormal: %.10g %.10g %.10g\n", p->point[0],
                   p->point[1], p->point[2], p->dir[0], p->dir[1], p->dir[2]);
        else if (p->model == RELIEF_FIT_SPHERE)
            printf("center: %.10g %.10g %.10g\nradius: %.10g\n", p->point[0], p->point[1],
                   p->point[2], p->radius);
        else
            printf("axis_point: %.10g %.10g %.10g\naxis_dir: %.10g %.10g %.10g\n"
                   "radius: %.10g\n",
                   p->point[0], p->point[1], p->point[2], p->dir[0], p->dir[1], p->dir[2],
                   p->radius);
        printf("rms: %.6g (over %zu of %zu points)\ninlier_fraction: %.4f (within 3 rms)\n"
               "why: %s\n",
               r.rms, r.n_inliers, r.n_points, r.inlier_fraction, r.reason);
    }
    if (r.poor_fit)
        fprintf(stderr,
                "relief fit: warning: poor fit: rms %.4g is more than %.0f%% of the %s's "
                "size %.4g; the capture may not be a %s\n",
                r.rms, 100.0 * RELIEF_FIT_POOR, relief_fit_model_name(r.prim.model), r.size,
                relief_fit_model_name(r.prim.model));
    return 0;
}
