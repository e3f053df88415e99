/* relief_complete_points (relief/points.h): the public parameters checked
 * and mapped onto the pipeline's (complete_points.h), the hole mask and the
 * sample region built from a ball, a box or the input's labels, the memory
 * estimated before anything is allocated, the progress passed on, and the
 * report with the JSON `relief complete-points --report` writes. */
#include "relief/relief.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/json.h"
#include "base/memlimit.h"
#include "base/progress.h"
#include "mesh/mesh.h"
#include "points/complete_points.h"

/* What a run holds at its peak, about: the k-NN graph (12 k bytes a
 * point), a dozen n x 3 double arrays, and the texture's exemplar grids
 * (grid^2 x 4 channels floats over at most 20 000 of them). */
#define BYTES_PER_POINT(k) ((uint64_t)(12 * (k) + 300) * 5)
#define GRID_BYTES(grid) (20000ull * (uint64_t)(grid) * (uint64_t)(grid) * 16)

relief_complete_points_params relief_complete_points_params_default(void)
{
    const relief_points_params d = relief_points_params_default();
    relief_complete_points_params p;
    memset(&p, 0, sizeof p);
    p.what = d.what;
    p.detail_histogram = d.detail_histogram;
    p.k = d.k;
    p.smooth_steps = d.smooth_steps;
    p.max_detail = d.max_detail;
    p.band = d.band;
    p.grid = d.tex.grid_n;
    p.cluster_size = d.tex.cluster_size;
    p.iterations = d.tex.max_iter;
    p.seed = (uint32_t)d.tex.seed;
    p.grid_search = d.tex.brute ? RELIEF_GRID_SEARCH_BRUTE : RELIEF_GRID_SEARCH_KDTREE;
    p.run = relief_run_options_default();
    return p;
}

/* Each check names the field it refuses in err->param too. */
static relief_status check_int(int v, int lo, int hi, const char *name, relief_error *err)
{
    return v >= lo && v <= hi ? RELIEF_OK
                              : relief_fail_param(err, RELIEF_E_RANGE, name, "%s %d out of "
                                                  "range: expected %d..%d", name, v, lo, hi);
}

static relief_status check_real(double v, double lo, double hi, const char *name,
                                relief_error *err)
{
    return v >= lo && v <= hi ? RELIEF_OK
                              : relief_fail_param(err, RELIEF_E_RANGE, name, "%s %g spacings "
                                                  "out of range: expected %.10g..%.10g", name,
                                                  v, lo, hi);
}

static int all_finite(const double *v, int n)
{
    for (int i = 0; i < n; ++i)
        if (!isfinite(v[i]))
            return 0;
    return 1;
}

/* The fields one by one. */
static relief_status check_fields(const relief_complete_points_params *p, relief_error *err)
{
    const struct {
        int v;
        const char *name, *param; /* the field, and its entry in the parameter table */
    } flags[] = {{p->smooth_only, "smooth_only", "smooth_only"},
                 {p->detail_histogram, "detail_histogram", "detail_histogram"},
                 {p->mesh, "mesh", "mesh"}, {p->hole_labels, "hole_labels", "hole_labels"},
                 {p->has_hole_ball, "has_hole_ball", "hole_ball"},
                 {p->sample_labels, "sample_labels", "sample_labels"},
                 {p->has_sample_box, "has_sample_box", "sample_box"},
                 {p->has_viewpoint, "has_viewpoint", "viewpoint"}};
    relief_status st = RELIEF_OK;
    if ((int)p->what < RELIEF_POINTS_ALL || (int)p->what > RELIEF_POINTS_GEOMETRY_ONLY)
        return relief_fail_param(err, RELIEF_E_RANGE, "what", "what %d is not one of all, "
                                 "colour, geometry", (int)p->what);
    if ((int)p->grid_search < RELIEF_GRID_SEARCH_KDTREE ||
        (int)p->grid_search > RELIEF_GRID_SEARCH_BRUTE)
        return relief_fail_param(err, RELIEF_E_RANGE, "grid_search", "grid_search %d is not "
                                 "one of kdtree, brute", (int)p->grid_search);
    for (size_t i = 0; st == RELIEF_OK && i < sizeof flags / sizeof flags[0]; ++i)
        if (flags[i].v != 0 && flags[i].v != 1)
            st = relief_fail_param(err, RELIEF_E_RANGE, flags[i].param, "%s %d out of range: "
                                   "expected 0 or 1", flags[i].name, flags[i].v);
    if (st == RELIEF_OK)
        st = check_int(p->k, 6, 64, "k", err);
    if (st == RELIEF_OK)
        st = check_int(p->smooth_steps, 0, 10000, "smooth_steps", err);
    if (st == RELIEF_OK)
        st = check_real(p->max_detail, 0.0, 100.0, "max_detail", err);
    if (st == RELIEF_OK)
        st = check_real(p->band, 0.0, 1e6, "band", err);
    if (st == RELIEF_OK)
        st = check_real(p->max_hole, 0.0, 1e30, "max_hole", err);
    if (st == RELIEF_OK && (p->grid < 3 || p->grid > 33 || p->grid % 2 == 0))
        st = relief_fail_param(err, RELIEF_E_RANGE, "grid", "grid %d out of range: expected "
                               "an odd number in 3..33", p->grid);
    if (st == RELIEF_OK)
        st = check_int(p->cluster_size, 16, 100000, "cluster_size", err);
    if (st == RELIEF_OK)
        st = check_int(p->iterations, 1, 1000, "iterations", err);
    return st;
}

/* The ball, the box and the viewpoint, where given. */
static relief_status check_places(const relief_complete_points_params *p, relief_error *err)
{
    const double *b = p->sample_box;
    if (p->has_hole_ball && !all_finite(p->hole_ball, 3))
        return relief_fail_param(err, RELIEF_E_RANGE, "hole_ball", "hole_ball centre (%g, %g, "
                                 "%g) is not finite", p->hole_ball[0], p->hole_ball[1],
                                 p->hole_ball[2]);
    if (p->has_hole_ball && !(p->hole_ball[3] > 0.0 && isfinite(p->hole_ball[3])))
        return relief_fail_param(err, RELIEF_E_RANGE, "hole_ball", "hole_ball radius R %g out "
                                 "of range: expected a finite R > 0", p->hole_ball[3]);
    if (p->has_sample_box && (!all_finite(b, 6) || !(b[0] < b[3] && b[1] < b[4] && b[2] < b[5])))
        return relief_fail_param(err, RELIEF_E_RANGE, "sample_box", "sample_box "
                                 "%g,%g,%g,%g,%g,%g out of range: expected finite "
                                 "X0,Y0,Z0,X1,Y1,Z1 with X0 < X1, Y0 < Y1, Z0 < Z1", b[0], b[1],
                                 b[2], b[3], b[4], b[5]);
    if (p->has_viewpoint && !all_finite(p->viewpoint, 3))
        return relief_fail_param(err, RELIEF_E_RANGE, "viewpoint", "viewpoint (%g, %g, %g) is "
                                 "not finite", p->viewpoint[0], p->viewpoint[1],
                                 p->viewpoint[2]);
    return RELIEF_OK;
}

/* The combinations that cannot be. */
static relief_status check_combinations(const relief_complete_points_params *p,
                                        relief_error *err)
{
    const int holes = (p->hole_mask != NULL) + p->hole_labels + p->has_hole_ball;
    const int samples = (p->sample_mask != NULL) + p->sample_labels + p->has_sample_box;
    if (holes > 1)
        return relief_fail(err, RELIEF_E_USAGE, "hole_mask, hole_labels and has_hole_ball: %d "
                           "hole masks given, expected at most one", holes);
    if (samples > 1)
        return relief_fail(err, RELIEF_E_USAGE, "sample_mask, sample_labels and has_sample_box: "
                           "%d sample regions given, expected at most one", samples);
    if (p->hole_labels && p->sample_labels)
        return relief_fail(err, RELIEF_E_USAGE, "hole_labels and sample_labels would read the "
                           "same labels");
    if (p->what == RELIEF_POINTS_COLOUR_ONLY && !holes)
        return relief_fail(err, RELIEF_E_USAGE, "what colour completes the colour of the hole "
                           "mask's points: give hole_mask, hole_labels or hole_ball");
    if (p->what == RELIEF_POINTS_COLOUR_ONLY && p->smooth_only)
        return relief_fail(err, RELIEF_E_USAGE, "smooth_only fills geometry: not with what "
                           "colour");
    if (p->clone && p->smooth_only)
        return relief_fail(err, RELIEF_E_USAGE, "clone copies detail, which smooth_only leaves "
                           "out");
    if (p->grid_search == RELIEF_GRID_SEARCH_KDTREE &&
        (p->run.backend == RELIEF_BACKEND_OPENCL || p->run.device != -1))
        return relief_fail(err, RELIEF_E_USAGE, "run.backend %s and run.device %d: OpenCL runs "
                           "the brute grid search only; the kd-tree runs on the host (backend "
                           "scalar, host or auto)",
                           relief_backend_name(p->run.backend), p->run.device);
    return RELIEF_OK;
}

relief_status relief_complete_points_params_validate(const relief_complete_points_params *p,
                                                     relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    relief_status st;
    if (!p)
        return relief_fail(err, RELIEF_E_USAGE, "complete-points parameters: NULL");
    st = check_fields(p, err);
    if (st == RELIEF_OK)
        st = check_places(p, err);
    if (st == RELIEF_OK)
        st = relief_run_options_validate(&p->run, err);
    if (st == RELIEF_OK)
        st = check_combinations(p, err);
    return st;
}

static uint64_t memory_limit(const relief_complete_points_params *p)
{
    return p->run.max_memory ? p->run.max_memory : relief_default_memory_limit();
}

uint64_t relief_complete_points_max_points(const relief_complete_points_params *p)
{
    relief_complete_points_params d = relief_complete_points_params_default();
    uint64_t limit;
    int k;
    if (!p)
        p = &d;
    k = p->k < 6 ? 6 : p->k > 64 ? 64 : p->k; /* a k out of range is refused later */
    limit = memory_limit(p);
    return limit ? limit / BYTES_PER_POINT(k) + 1 : 0;
}

static relief_status check_memory(const relief_mesh *in, const relief_complete_points_params *p,
                                  relief_error *err)
{
    const uint64_t n = in->nv, need = n * BYTES_PER_POINT(p->k) + GRID_BYTES(p->grid);
    const uint64_t limit = memory_limit(p);
    if (limit && need > limit)
        return relief_fail(err, RELIEF_E_NOMEM, "%s: about %.1f MiB needed for %zu points, over "
                           "the limit of %.1f MiB (run.max_memory)",
                           p->run.input_name ? p->run.input_name : "the input",
                           need / 1048576.0, in->nv, limit / 1048576.0);
    return RELIEF_OK;
}

/* The hole mask from hole_labels or hole_ball, the sample region from
 * sample_labels or sample_box (n + 1 bytes each, NULL when not asked). */
static relief_status build_masks(const relief_mesh *in, const relief_complete_points_params *p,
                                 uint8_t **hole, uint8_t **sample, relief_error *err)
{
    const size_t n = in->nv;
    const double *v = p->hole_ball, *b = p->sample_box;
    if ((p->hole_labels || p->sample_labels) && !in->label)
        return relief_fail(err, RELIEF_E_USAGE, "%s: the input has no `label` property",
                           p->hole_labels ? "hole_labels" : "sample_labels");
    if ((p->hole_labels || p->has_hole_ball) && !(*hole = calloc(n + 1, 1)))
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the hole mask");
    if ((p->sample_labels || p->has_sample_box) && !(*sample = calloc(n + 1, 1)))
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the sample region");
    for (size_t i = 0; *hole && i < n; ++i) {
        double d2 = 0.0;
        if (p->hole_labels) {
            (*hole)[i] = in->label[i] != 0;
            continue;
        }
        for (int c = 0; c < 3; ++c)
            d2 += (in->pos[3 * i + c] - v[c]) * (in->pos[3 * i + c] - v[c]);
        (*hole)[i] = d2 <= v[3] * v[3];
    }
    for (size_t i = 0; *sample && i < n; ++i) {
        const double *q = in->pos + 3 * i;
        (*sample)[i] = p->sample_labels ? in->label[i] == 1
                                        : q[0] >= b[0] && q[0] <= b[3] && q[1] >= b[1] &&
                                              q[1] <= b[4] && q[2] >= b[2] && q[2] <= b[5];
    }
    return RELIEF_OK;
}

/* The pipeline's parameters: its defaults with the public ones over them. */
static relief_points_params engine_params(const relief_complete_points_params *p,
                                          const uint8_t *hole, const uint8_t *sample,
                                          relief_progress *progress)
{
    relief_points_params e = relief_points_params_default();
    e.what = p->what;
    e.smooth_only = p->smooth_only;
    e.detail_histogram = p->detail_histogram;
    e.mesh = p->mesh;
    e.k = p->k;
    e.smooth_steps = p->smooth_steps;
    e.max_detail = p->max_detail;
    e.band = p->band;
    e.max_hole = p->max_hole;
    e.hole_mask = hole ? hole : p->hole_mask;
    e.sample_mask = sample ? sample : p->sample_mask;
    e.clone = p->clone;
    e.viewpoint = p->has_viewpoint ? p->viewpoint : NULL;
    e.progress = progress;
    e.tex.grid_n = p->grid;
    e.tex.cluster_size = p->cluster_size;
    e.tex.max_iter = p->iterations;
    e.tex.seed = p->seed;
    e.tex.brute = p->grid_search == RELIEF_GRID_SEARCH_BRUTE;
    e.tex.backend = p->run.backend; /* host: grid_nn runs it as scalar */
    /* scalar: every stage on the calling thread, the reference, whatever
     * run.threads says; else every stage on run.threads (0: the CPUs this
     * thread may run on), the same bytes. */
    e.threads = p->run.backend == RELIEF_BACKEND_SCALAR ? 1 : p->run.threads;
    e.tex.device = p->run.device;
    return e;
}

static void json_parameters(relief_json *j, const relief_points_params *e)
{
    rj_begin_object(j, "parameters");
    rj_string(j, "what", relief_points_what_name(e->what));
    rj_bool(j, "smooth_only", e->smooth_only);
    rj_bool(j, "detail_histogram", e->detail_histogram);
    rj_int(j, "k", e->k);
    rj_int(j, "smooth_steps", e->smooth_steps);
    rj_number(j, "smooth_dt_spacings", e->smooth_dt);
    rj_number(j, "max_detail_spacings", e->max_detail);
    rj_number(j, "band_spacings", e->band);
    rj_number(j, "seam_band_spacings", e->seam_band);
    rj_int(j, "grid", e->tex.grid_n);
    rj_int(j, "cluster_size", e->tex.cluster_size);
    rj_number(j, "overlap", e->tex.overlap);
    rj_int(j, "max_iterations", e->tex.max_iter);
    rj_int(j, "seed", (long long)e->tex.seed);
    rj_end_object(j);
}

static void json_texture(relief_json *j, const relief_points_report *r)
{
    rj_begin_object(j, "texture");
    rj_int(j, "channels", r->tex_channels);
    rj_string(j, "grid_search", r->tex.search);
    rj_int(j, "clusters", (long long)r->tex.clusters);
    rj_int(j, "active_clusters", (long long)r->tex.active_clusters);
    rj_int(j, "exemplars", (long long)r->tex.exemplars);
    rj_int(j, "iterations", r->tex.iterations);
    rj_int(j, "grid_used", r->tex.grid_n);
    rj_int(j, "cluster_size_used", r->tex.cluster_size);
    rj_bool(j, "converged", r->tex.converged);
    rj_begin_array(j, "energy");
    for (int i = 0; i < r->tex.iterations; ++i)
        rj_number(j, NULL, r->tex.energy[i]);
    rj_end_array(j);
    rj_end_object(j);
}

/* The report as `relief complete-points --report` has always written it. */
typedef struct json_ctx {
    const relief_complete_points_params *p;
    const relief_points_params *e;
    const relief_points_report *r;
} json_ctx;

static void write_json(relief_json *j, const void *ctx)
{
    const json_ctx *x = ctx;
    const relief_complete_points_params *p = x->p;
    const relief_points_params *e = x->e;
    const relief_points_report *r = x->r;
    rj_begin_object(j, NULL);
    rj_string(j, "command", "complete-points");
    rj_string_or_null(j, "input", p->run.input_name);
    rj_string_or_null(j, "output", p->run.output_name);
    json_parameters(j, e);
    rj_begin_object(j, "points");
    rj_int(j, "input", (long long)r->n_in);
    rj_int(j, "non_finite_dropped", (long long)p->non_finite_dropped);
    rj_int(j, "added", (long long)r->n_added);
    rj_int(j, "masked", (long long)r->n_masked);
    rj_int(j, "clone", (long long)r->n_clone);
    rj_end_object(j);
    relief_holes_json(j, "holes", &r->holes);
    rj_number(j, "spacing", r->spacing);
    rj_int(j, "patch_triangles", (long long)r->patch_triangles);
    rj_int(j, "patch_holes_skipped", (long long)r->patch_skipped);
    if (e->mesh) {
        rj_begin_object(j, "mesh");
        rj_int(j, "triangles", (long long)r->mesh_triangles);
        if (!r->mesh_of_points) {
            rj_int(j, "copies_welded", (long long)r->copies_welded);
            rj_int(j, "untangled", (long long)r->untangled);
            rj_int(j, "crossing_left", (long long)r->crossing_left);
            rj_int(j, "open_loops", (long long)r->open_loops);
            rj_int(j, "open_edges", (long long)r->open_edges);
        }
        if (r->mesh_of_points) {
            rj_int(j, "candidates", (long long)r->mesh_candidates);
            rj_int(j, "boundary_edges", (long long)r->mesh_boundary_edges);
            rj_int(j, "bare_points", (long long)r->mesh_bare_points);
        }
        rj_end_object(j);
    }
    rj_begin_object(j, "base");
    rj_number(j, "detail_rms", r->detail_rms);
    rj_number(j, "reconstruction_rms", r->recon_rms);
    rj_end_object(j);
    json_texture(j, r);
    rj_begin_object(j, "seconds");
    rj_number(j, "analysis", r->t_analysis);
    rj_number(j, "base", r->t_base);
    rj_number(j, "fill", r->t_fill);
    rj_number(j, "texture", r->t_texture);
    rj_number(j, "total", r->t_total);
    rj_end_object(j);
    rj_end_object(j);
}

/* The public report from the pipeline's, its JSON included. */
static relief_status make_report(const relief_complete_points_params *p,
                                 const relief_points_params *e, const relief_points_report *r,
                                 relief_complete_points_report *out, relief_error *err)
{
    memset(out, 0, sizeof *out);
    out->points_in = r->n_in;
    out->added = r->n_added;
    out->masked = r->n_masked;
    out->clone_points = r->n_clone;
    out->holes = r->holes.n_holes;
    out->outer_borders = r->holes.n_borders;
    out->holes_too_small = r->holes.n_dropped;
    out->holes_too_large = r->holes.n_too_large;
    out->holes_not_selected = r->holes.n_not_selected;
    out->max_hole = r->holes.max_across;
    if (r->holes.n_rims && !(out->hole_list = calloc(r->holes.n_rims, sizeof *out->hole_list)))
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the report's %u holes",
                           r->holes.n_rims);
    for (uint32_t h = 0; h < r->holes.n_rims; ++h) {
        const relief_rim *m = r->holes.rims + h;
        out->hole_list[h] = (relief_hole){m->points, m->across,
                                          {m->centre[0], m->centre[1], m->centre[2]},
                                          relief_rim_fate_name(m->fate)};
    }
    out->n_hole_list = r->holes.n_rims;
    relief_holes_left_line(&r->holes, out->holes_left, sizeof out->holes_left);
    out->spacing = r->spacing;
    out->detail_rms = r->detail_rms;
    out->reconstruction_rms = r->recon_rms;
    out->triangles = r->mesh_triangles;
    out->open_loops = r->open_loops;
    out->open_edges = r->open_edges;
    out->clusters = r->tex.clusters;
    out->active_clusters = r->tex.active_clusters;
    out->exemplars = r->tex.exemplars;
    out->iterations = r->tex.iterations;
    out->converged = r->tex.converged;
    snprintf(out->grid_search, sizeof out->grid_search, "%s", r->tex.search);
    out->grid_search_warning = r->tex.search_reason == RELIEF_REASON_DEVICE_FELL_BACK;
    out->seconds_analysis = r->t_analysis;
    out->seconds_base = r->t_base;
    out->seconds_fill = r->t_fill;
    out->seconds_texture = r->t_texture;
    out->seconds_total = r->t_total;
    {
        const json_ctx x = {p, e, r};
        out->json = rj_render(write_json, &x, "");
    }
    if (!out->json)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot write the report's JSON in memory");
    return RELIEF_OK;
}

void relief_complete_points_report_free(relief_complete_points_report *rep)
{
    if (!rep)
        return;
    free(rep->json);
    free(rep->hole_list);
    memset(rep, 0, sizeof *rep);
}

relief_status relief_complete_points(const relief_mesh *in, const relief_complete_points_params *p,
                                     relief_mesh **out, relief_complete_points_report *rep,
                                     relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    relief_complete_points_report pub;
    relief_points_report r;
    relief_points_params e;
    relief_progress progress;
    relief_mesh *done = NULL;
    uint8_t *hole = NULL, *sample = NULL;
    relief_status st;

    memset(&r, 0, sizeof r);
    memset(&pub, 0, sizeof pub);
    if (!in || !out)
        return relief_fail(err, RELIEF_E_USAGE, "relief_complete_points: %s is NULL",
                           !in ? "in" : "out");
    st = relief_complete_points_params_validate(p, err);
    if (st == RELIEF_OK)
        st = relief_mesh_validate(in, err);
    if (st == RELIEF_OK)
        st = check_memory(in, p, err);
    if (st == RELIEF_OK)
        st = build_masks(in, p, &hole, &sample, err);
    if (st == RELIEF_OK) {
        relief_progress_init(&progress, p->run.progress, p->run.progress_ctx);
        e = engine_params(p, hole, sample, &progress);
        st = relief_points_complete(in, &e, &done, &r, err);
    }
    if (st == RELIEF_OK && rep)
        st = make_report(p, &e, &r, &pub, err);
    if (st == RELIEF_OK) {
        if (rep)
            *rep = pub;
        *out = done;
        done = NULL;
    } else {
        relief_complete_points_report_free(&pub);
    }
    relief_points_report_free(&r);
    relief_mesh_destroy(done);
    free(hole);
    free(sample);
    return st;
}
