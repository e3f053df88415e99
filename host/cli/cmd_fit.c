/* relief fit: fit a primitive and print it. */
#include "cli/commands.h"

#include <getopt.h>
#include <stdio.h>

#include "relief/relief.h"
#include "base/json.h"
#include "cli/options.h"
#include "report/report.h"
#include "smooth/fit.h"

enum { FIT_FIT = OPT_COMMAND, FIT_JSON };

static const cli_own own[] = {
    {"fit", FIT_FIT, "MODEL", "auto (default), plane, sphere or cylinder"},
    {"json", FIT_JSON, NULL, "one JSON object: model, rms, inlier_fraction and point/normal, "
     "center/radius or axis_point/axis_dir/radius"},
    {NULL, 0, NULL, NULL}};

static const cli_spec spec = {
    "fit", "IN [--fit auto|plane|sphere|cylinder] [--json]",
    "Fit a primitive to the points of IN (least-squares start, then orthogonal-distance "
    "refinement with outliers trimmed) and print its parameters in the input's units, the "
    "RMS orthogonal residual over the inliers and the fraction of points within 3 RMS. auto "
    "picks the model whose residual, penalised 10% per extra parameter, is lowest, and says "
    "why. A fit whose RMS exceeds 10% of the primitive's size is reported as poor on stderr.",
    0, NULL, NULL, NULL, 0, NULL, own, NULL};

typedef struct fit_args {
    relief_fit_model model;
    int json;
} fit_args;

static int take(void *ctx, int id, const char *arg)
{
    static const char *const fits[] = CLI_NAMES(RELIEF_FIT_MODEL_LIST);
    fit_args *a = ctx;
    int v;
    if (id == FIT_JSON)
        return a->json = 1;
    if (!CLI_PARSE_ENUM("fit", "--fit", arg, fits, &v))
        return 0;
    a->model = (relief_fit_model)v;
    return 1;
}

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
    cli_common cm = cli_common_init("fit");
    fit_args args = {RELIEF_FIT_AUTO, 0};
    relief_error err = {0};
    relief_fit_result r;
    relief_mesh *in = NULL;
    relief_status st;
    const char *in_path;
    int rc = cli_parse(&spec, &cm, NULL, take, &args, argc, argv);

    if (rc)
        return rc < 0 ? 0 : rc;
    if (!cli_one_input(&cm, argc, argv, "input mesh IN", &in_path))
        return EXIT_USAGE;
    if (parse_only)
        return 0;
    if (cli_read_mesh("fit", in_path, 0, &in, NULL, &err) != RELIEF_OK)
        return cli_fail("fit", &err);
    st = relief_fit_mesh(in, args.model, &r, &err);
    relief_mesh_destroy(in);
    if (st != RELIEF_OK)
        return cli_fail("fit", &err);
    if (args.json) {
        print_fit_json(stdout, in_path, &r);
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
