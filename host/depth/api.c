/* Depth-image repair as the public API gives it (relief/depth.h): the
 * parameters, a frame's missing pixels, the memory check, the scorer, the
 * repair (depth_fill.h) on a copy, its measures, an organised cloud's
 * points, and the report; a mesh through its six depth images
 * (mesh_fill.h). The caller's frame or mesh is written only on success. */
#include "relief/relief.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/clock.h"
#include "base/error.h"
#include "base/memlimit.h"
#include "base/progress.h"
#include "depth/depth_fill.h"
#include "depth/fill_report.h"
#include "depth/frame.h"
#include "depth/mesh_fill.h"
#include "depth/mesh_patch.h"
#include "mesh/holes.h"
#include "mesh/mesh.h"
#include "depth/volume.h"
#include "image/patch.h"

relief_depth_fill_params relief_depth_fill_params_default(void)
{
    relief_depth_repair_params r = relief_depth_repair_params_default();
    relief_depth_fill_params p;
    memset(&p, 0, sizeof p);
    p.variant = r.variant;
    p.window = r.synth.window;
    p.sigma = 0.0;
    p.epsilon = r.synth.epsilon;
    p.search_radius = r.synth.search_radius;
    p.exhaustive = 0;
    p.batch = 1;
    p.order = RELIEF_DEPTH_ORDER_BOTH;
    p.tileable = 0;
    p.levels = r.levels;
    p.lambda = 0.0;
    p.membrane = RELIEF_MEMBRANE_AUTO;
    p.seam = 1;
    p.edges = RELIEF_DEPTH_EDGES_AUTO;
    p.edge_step = r.layer.step;
    p.values = RELIEF_DEPTH_VALUES_AUTO;
    p.resolution = relief_mesh_fill_params_default().resolution;
    p.solid = 0;
    p.max_hole = 0.0;
    p.has_hole_ball = p.hole_labels = 0;
    memset(p.hole_ball, 0, sizeof p.hole_ball);
    p.seed = r.synth.seed;
    p.truth = NULL;
    p.run = relief_run_options_default();
    return p;
}

/* A 0/1 switch. */
static relief_status check_flag(const char *name, int v, relief_error *err)
{
    return v == 0 || v == 1 ? RELIEF_OK
                            : relief_fail_param(err, RELIEF_E_RANGE, name, "%s %d out of "
                                                "range: expected 0 or 1", name, v);
}

/* The enumerations and the switches; each refusal names its field
 * (err->param), as do check_values'. */
static relief_status check_choices(const relief_depth_fill_params *p, relief_error *err)
{
    relief_status st = RELIEF_OK;
    if (p->variant < RELIEF_DEPTH_PLAIN || p->variant > RELIEF_DEPTH_DECOMPOSE)
        return relief_fail_param(err, RELIEF_E_RANGE, "variant", "variant %d is not one of "
                                 "plain, haar, decompose", (int)p->variant);
    if (p->order < RELIEF_DEPTH_ORDER_BOTH || p->order > RELIEF_DEPTH_ORDER_VERTICAL)
        return relief_fail_param(err, RELIEF_E_RANGE, "order", "order %d is not one of both, "
                                 "horizontal, vertical", (int)p->order);
    if (p->edges < RELIEF_DEPTH_EDGES_AUTO || p->edges > RELIEF_DEPTH_EDGES_ACROSS)
        return relief_fail_param(err, RELIEF_E_RANGE, "edges", "edges %d is not one of "
                                 "auto, layers, across", (int)p->edges);
    if (p->values < RELIEF_DEPTH_VALUES_AUTO || p->values > RELIEF_DEPTH_VALUES_DISPARITY)
        return relief_fail_param(err, RELIEF_E_RANGE, "values", "values %d is not one of "
                                 "auto, depth, disparity", (int)p->values);
    if (!(p->edge_step >= 1.0 && p->edge_step <= 1000.0))
        return relief_fail_param(err, RELIEF_E_RANGE, "edge_step", "edge_step %g out of "
                                 "range: expected 1..1000 noise units", p->edge_step);
    if (p->membrane < RELIEF_MEMBRANE_AUTO || p->membrane > RELIEF_MEMBRANE_THIN_PLATE)
        return relief_fail_param(err, RELIEF_E_RANGE, "membrane", "membrane %d is not one of "
                                 "auto, harmonic, thin-plate", (int)p->membrane);
    if (p->batch < 1 || p->batch > RELIEF_PIXSYN_MAX_BATCH)
        return relief_fail_param(err, RELIEF_E_RANGE, "batch", "batch %d out of range: "
                                 "expected 1..%d (1: a pixel at a time)", p->batch,
                                 RELIEF_PIXSYN_MAX_BATCH);
    if (p->batch > 1 && p->tileable)
        return relief_fail(err, RELIEF_E_USAGE, "batch %d with tileable: a tileable image is "
                           "filled a pixel at a time; give batch 1", p->batch);
    st = check_flag("exhaustive", p->exhaustive, err);
    if (st == RELIEF_OK)
        st = check_flag("tileable", p->tileable, err);
    if (st == RELIEF_OK)
        st = check_flag("seam", p->seam, err);
    if (st == RELIEF_OK)
        st = check_flag("solid", p->solid, err);
    if (st == RELIEF_OK)
        st = check_flag("skin", p->skin, err);
    return st;
}

/* The numbers, each against its range. */
static relief_status check_values(const relief_depth_fill_params *p, relief_error *err)
{
    if (p->window < 3 || p->window > 1025 || p->window % 2 == 0)
        return relief_fail_param(err, RELIEF_E_RANGE, "window", "window %d out of range: "
                                 "expected an odd number in 3..1025 (the window is centred "
                                 "on a pixel)", p->window);
    if (isnan(p->sigma) || p->sigma > 1e6 || (p->sigma > 0.0 && p->sigma < 0.5))
        return relief_fail_param(err, RELIEF_E_RANGE, "sigma", "sigma %g out of range: "
                                 "expected 0.5..1e6 pixels, or <= 0 for window / 6.4",
                                 p->sigma);
    if (!(p->epsilon >= 0.0 && p->epsilon <= 10.0))
        return relief_fail_param(err, RELIEF_E_RANGE, "epsilon", "epsilon %g out of range: "
                                 "expected 0..10", p->epsilon);
    if (p->search_radius < 0 || p->search_radius > 1000000)
        return relief_fail_param(err, RELIEF_E_RANGE, "search_radius", "search_radius %d out "
                                 "of range: expected 0..1000000 pixels (0: the whole image)",
                                 p->search_radius);
    if (p->levels < 1 || p->levels > 6)
        return relief_fail_param(err, RELIEF_E_RANGE, "levels", "levels %d out of range: "
                                 "expected 1..6", p->levels);
    if (isnan(p->lambda) || p->lambda > 1e12)
        return relief_fail_param(err, RELIEF_E_RANGE, "lambda", "lambda %g out of range: "
                                 "expected up to 1e12 (<= 0: 8 x the capture's robust step)",
                                 p->lambda);
    if (!(p->max_hole >= 0.0 && p->max_hole <= 1e30))
        return relief_fail_param(err, RELIEF_E_RANGE, "max_hole", "max_hole %g out of range: "
                                 "expected 0..1e30 (0: a quarter of the bounding box's "
                                 "diagonal)", p->max_hole);
    return RELIEF_OK;
}

relief_status relief_depth_fill_params_validate(const relief_depth_fill_params *p,
                                                relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    relief_status st;
    if (!p)
        return relief_fail(err, RELIEF_E_USAGE, "params: NULL");
    st = check_choices(p, err);
    if (st == RELIEF_OK)
        st = check_values(p, err);
    if (st != RELIEF_OK)
        return st;
    if (p->has_hole_ball && relief_hole_ball_check("hole_ball", p->hole_ball, err) != RELIEF_OK)
        return RELIEF_E_RANGE;
    if (p->has_hole_ball && p->hole_labels)
        return relief_fail(err, RELIEF_E_USAGE, "hole_ball and hole_labels: give one");
    if ((p->has_hole_ball || p->hole_labels || p->max_hole > 0.0) && p->solid)
        return relief_fail(err, RELIEF_E_USAGE, "solid returns the whole solid: a hole "
                           "selection (max_hole, hole_ball, hole_labels) chooses holes of the "
                           "capture, without solid");
    if (p->resolution < 8 || p->resolution > 1024)
        return relief_fail_param(err, RELIEF_E_RANGE, "resolution", "resolution %d out of "
                                 "range: expected 8..1024 voxels", p->resolution);
    return relief_run_options_validate(&p->run, err);
}

/* The repair's own parameters; `mesh`: the mesh route's defaults (the
 * thin plate for membrane auto). */
static relief_depth_repair_params repair_params(const relief_depth_fill_params *p, int mesh)
{
    relief_depth_repair_params r = mesh ? relief_mesh_fill_params_default().depth
                                        : relief_depth_repair_params_default();
    r.variant = p->variant;
    r.synth.window = p->window;
    r.synth.sigma = p->sigma > 0.0 ? p->sigma : 0.0;
    r.synth.epsilon = p->epsilon;
    r.synth.search_radius = p->search_radius;
    r.synth.exhaustive = p->exhaustive;
    r.synth.batch = p->batch;
    r.synth.order = p->order == RELIEF_DEPTH_ORDER_HORIZONTAL ? RELIEF_ORDER_HORIZONTAL
                    : p->order == RELIEF_DEPTH_ORDER_VERTICAL ? RELIEF_ORDER_VERTICAL
                                                              : RELIEF_ORDER_BOTH;
    r.synth.tileable = p->tileable;
    r.synth.seed = p->seed;
    r.levels = p->levels;
    r.lambda = p->lambda > 0.0 ? p->lambda : 0.0;
    if (p->membrane != RELIEF_MEMBRANE_AUTO)
        r.thin_plate = p->membrane == RELIEF_MEMBRANE_THIN_PLATE;
    r.seam = p->seam;
    r.layered = !mesh && p->edges != RELIEF_DEPTH_EDGES_ACROSS; /* auto: the frame's (below) */
    r.layer.step = p->edge_step;
    return r;
}

static relief_depth_order public_order(relief_pixsyn_order o)
{
    return o == RELIEF_ORDER_VERTICAL     ? RELIEF_DEPTH_ORDER_VERTICAL
           : o == RELIEF_ORDER_HORIZONTAL ? RELIEF_DEPTH_ORDER_HORIZONTAL
                                          : RELIEF_DEPTH_ORDER_BOTH;
}

void relief_depth_fill_report_free(relief_depth_fill_report *rep)
{
    if (!rep)
        return;
    free(rep->json);
    memset(rep, 0, sizeof *rep);
}

/* ------------------------------------------------------ what both routes share */

/* The scorer of run->backend. The report gets what it runs on and why. */
static relief_status make_scorer(const relief_run_options *run, relief_patch_scorer **s,
                                 relief_depth_fill_report *rep, relief_error *err)
{
    relief_reason why = RELIEF_REASON_NONE;
    relief_status st = relief_patch_scorer_create(run->backend, run->device, run->threads, s,
                                                  rep->backend_note,
                                                  sizeof rep->backend_note, &why, err);
    if (st != RELIEF_OK)
        return st;
    rep->backend = (*s)->backend;
    snprintf(rep->device, sizeof rep->device, "%s", (*s)->device);
    rep->backend_warning = why == RELIEF_REASON_DEVICE_FELL_BACK;
    return RELIEF_OK;
}

/* The host memory limit of a call. */
static uint64_t memory_limit(const relief_run_options *run)
{
    return run->max_memory ? run->max_memory : relief_default_memory_limit();
}

/* A cancel's message, with how far the call had come. */
static relief_status said(relief_status st, const relief_progress *pr, relief_error *err)
{
    if (st == RELIEF_E_CANCELLED)
        return relief_fail(err, st, "cancelled by the progress callback at %.0f %%",
                           100.0 * pr->last);
    return st;
}

/* ------------------------------------------------------------------ an image */

/* One image's repair, from the arguments to the report. */
typedef struct image_job {
    relief_depth_image *f;
    const relief_depth_fill_params *p;
    relief_depth_repair_params rp;
    size_t n;
    uint8_t *missing;
    int64_t *source;
    float *z; /* the repaired copy of f->z */
    relief_depth_repair_report r;
    relief_depth_measures m;
    relief_depth_fill_report rep;
    relief_progress pr;
    double cam[4];
    double t0;
} image_job;

/* A frame's sides, named by `what`. */
static relief_status check_sides(const char *what, int width, int height, relief_error *err)
{
    if (width < 1 || width > RELIEF_DEPTH_MAX_SIDE)
        return relief_fail(err, RELIEF_E_RANGE, "%s width %d out of range: expected 1..%d",
                           what, width, RELIEF_DEPTH_MAX_SIDE);
    if (height < 1 || height > RELIEF_DEPTH_MAX_SIDE)
        return relief_fail(err, RELIEF_E_RANGE, "%s height %d out of range: expected 1..%d",
                           what, height, RELIEF_DEPTH_MAX_SIDE);
    return RELIEF_OK;
}

static relief_status check_frame(const relief_depth_image *f, const char *what,
                                 relief_error *err)
{
    if (!f)
        return relief_fail(err, RELIEF_E_USAGE, "%s: NULL", what);
    if (!f->z)
        return relief_fail(err, RELIEF_E_USAGE, "%s z: NULL", what);
    return check_sides(what, f->width, f->height, err);
}

relief_status relief_depth_fill_check_memory(int width, int height,
                                             const relief_depth_fill_params *p,
                                             relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    relief_depth_fill_params d = relief_depth_fill_params_default();
    uint64_t need, limit = memory_limit(p ? &p->run : &d.run);
    relief_status st = check_sides("frame", width, height, err);
    if (st != RELIEF_OK)
        return st;
    /* The repair's own, and the copy of z, the missing mask and the
     * source map kept here. */
    need = relief_depth_repair_estimate(width, height) +
           (uint64_t)width * (uint64_t)height * 13u;
    if (need > limit)
        return relief_fail(err, RELIEF_E_NOMEM, "repairing a %d x %d image needs about %.0f "
                           "MiB, over the limit of %.0f MiB (max_memory)", width, height,
                           need / 1048576.0, limit / 1048576.0);
    return RELIEF_OK;
}

/* The arguments, then the memory the repair would take against the
 * limit, before anything is allocated. */
static relief_status check_image_args(const relief_depth_image *f, const relief_image *mask,
                                      const relief_depth_fill_params *p, relief_error *err)
{
    relief_status st = check_frame(f, "frame", err);
    if (st == RELIEF_OK)
        st = relief_depth_fill_params_validate(p, err);
    if (st == RELIEF_OK && p->truth) {
        st = check_frame(p->truth, "truth", err);
        if (st == RELIEF_OK && (p->truth->width != f->width || p->truth->height != f->height))
            st = relief_fail(err, RELIEF_E_USAGE, "the truth is %d x %d pixels, the frame %d x "
                             "%d: they must be the same size", p->truth->width,
                             p->truth->height, f->width, f->height);
    }
    if (st == RELIEF_OK && mask)
        st = relief_depth_mask_check(mask, f->width, f->height, err);
    if (st == RELIEF_OK)
        st = relief_depth_fill_check_memory(f->width, f->height, p, err);
    return st;
}

/* The masks and the copy; the refusal of a frame with nothing known. */
static relief_status prepare_image(image_job *job, const relief_image *mask, relief_error *err)
{
    const relief_depth_image *f = job->f;
    const char *name = job->p->run.input_name ? job->p->run.input_name : "the frame";
    job->n = (size_t)f->width * f->height;
    job->missing = malloc(job->n);
    job->source = malloc(job->n * sizeof *job->source);
    job->z = malloc(job->n * sizeof *job->z);
    if (!job->missing || !job->source || !job->z)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the missing mask");
    relief_depth_missing(f, mask, job->missing, &job->rep.missing_in_input,
                         &job->rep.missing_by_mask);
    if (job->rep.missing_in_input + job->rep.missing_by_mask == job->n)
        return relief_fail(err, RELIEF_E_RANGE, "%s: every pixel is missing: there is nothing "
                           "to repair it from", name);
    memcpy(job->z, f->z, job->n * sizeof *job->z);
    return relief_depth_repair_params_validate(&job->rp, f->width, f->height, err);
}

/* The public report and its JSON from the repair's, the measures and the
 * camera fit. */
static relief_status report_image(image_job *job, relief_error *err)
{
    relief_depth_fill_report *rep = &job->rep;
    const relief_depth_repair_report *r = &job->r;
    const relief_depth_measures *m = &job->m;
    rep->missing = r->missing;
    rep->filled = r->filled;
    rep->outside = r->outside;
    rep->by_synthesis = r->by_synthesis;
    rep->by_fallback = r->by_fallback;
    rep->by_membrane = r->by_membrane;
    rep->unreached = r->unreached;
    rep->membrane_iterations = r->membrane_iterations;
    rep->membrane_capped = r->membrane_iterations >= job->rp.membrane_iterations;
    rep->lambda = r->lambda;
    rep->order_kept = public_order(r->kept);
    rep->candidates = r->candidates;
    rep->stepped_holes = r->stepped_holes;
    rep->front_pixels = r->front_pixels;
    rep->noise = job->rp.layered ? r->layer_noise : NAN;
    rep->measured = job->p->truth != NULL;
    rep->compared = m->compared;
    rep->rms = m->rms;
    rep->rim_jump = m->rim_jump;
    rep->capture_jump = m->capture_jump;
    rep->truth_rim_jump = m->truth_jump;
    rep->slope_jump = m->rim_jump / m->capture_jump;
    rep->iou = NAN;
    rep->hausdorff = NAN;
    rep->voxel = NAN;
    rep->seconds_transform = r->seconds_transform;
    rep->seconds_synthesis = r->seconds_synthesis;
    rep->seconds_score = r->seconds_score;
    rep->seconds_total = relief_seconds() - job->t0;
    rep->json = relief_depth_fill_json(&job->p->run, job->f->width, job->f->height, &job->rp, r,
                                       m, rep);
    return rep->json ? RELIEF_OK
                     : relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the report");
}

/* Scorer, repair, measures, camera and report: everything that can fail,
 * on the copy. */
static relief_status run_image(image_job *job, relief_error *err)
{
    relief_patch_scorer *scorer = NULL;
    const relief_depth_image *f = job->f;
    relief_status st = make_scorer(&job->p->run, &scorer, &job->rep, err);
    if (st == RELIEF_OK) {
        job->rp.progress = &job->pr;
        st = relief_depth_repair(job->z, job->missing, f->width, f->height, &job->rp, scorer,
                                 job->source, &job->r, err);
        st = said(st, &job->pr, err);
    }
    relief_patch_scorer_destroy(scorer);
    if (st != RELIEF_OK)
        return st;
    relief_depth_measure(job->z, job->p->truth ? job->p->truth->z : NULL, job->missing,
                         f->width, f->height, &job->m);
    job->rep.camera_fitted = relief_depth_fit_camera(f, job->cam);
    return report_image(job, err);
}

relief_status relief_depth_fill(relief_depth_image *f, const relief_image *mask,
                                const relief_depth_fill_params *p,
                                relief_depth_fill_report *rep, relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    image_job job;
    relief_status st = check_image_args(f, mask, p, err);
    if (st != RELIEF_OK)
        return st;
    memset(&job, 0, sizeof job);
    job.f = f;
    job.p = p;
    job.rp = repair_params(p, 0);
    /* Disparities (a PFM's, unless told) put the larger in front; the
     * frame's colour, a cloud's or a pair's, parts the layers where it can. */
    job.rp.layer.far_sign = p->values == RELIEF_DEPTH_VALUES_DISPARITY ||
                                    (p->values == RELIEF_DEPTH_VALUES_AUTO &&
                                     f->format == RELIEF_DEPTH_PFM)
                                ? -1
                                : 1;
    if (p->edges == RELIEF_DEPTH_EDGES_AUTO && job.rp.layer.far_sign < 0)
        job.rp.layered = 0; /* disparities: across (relief/depth.h) */
    job.rp.layer.rgb = f->rgb;
    if (f->rgb)
        job.rp.layer.near_weight = 1.5;
    job.t0 = relief_seconds();
    relief_progress_init(&job.pr, p->run.progress, p->run.progress_ctx);
    st = prepare_image(&job, mask, err);
    if (st == RELIEF_OK)
        st = run_image(&job, err);
    if (st == RELIEF_OK) {
        /* Nothing fails from here: the caller's frame is written. */
        memcpy(f->z, job.z, job.n * sizeof *f->z);
        if (f->xyz)
            relief_depth_cloud_fill(f, job.missing, job.source,
                                    job.rep.camera_fitted ? job.cam : NULL);
        relief_progress_step(&job.pr, 1.0);
        if (rep) {
            *rep = job.rep;
            job.rep.json = NULL;
        }
    }
    free(job.rep.json);
    free(job.missing);
    free(job.source);
    free(job.z);
    return st;
}

/* ------------------------------------------------------------------- a mesh */

static relief_status check_mesh_args(const relief_mesh *in, const relief_depth_fill_params *p,
                                     const relief_mesh *truth, relief_mesh **out,
                                     relief_error *err)
{
    relief_status st;
    if (!in || !out)
        return relief_fail(err, RELIEF_E_USAGE, "%s: NULL", in ? "out" : "mesh");
    st = relief_depth_fill_params_validate(p, err);
    if (st == RELIEF_OK && p->truth)
        st = relief_fail(err, RELIEF_E_USAGE, "truth: a mesh's truth is the complete mesh "
                         "(relief_depth_fill_mesh's truth), not a depth image");
    if (st == RELIEF_OK)
        st = relief_mesh_validate(in, err);
    if (st == RELIEF_OK && truth)
        st = relief_mesh_validate(truth, err);
    if (st == RELIEF_OK && relief_mesh_triangle_count(in) == 0)
        st = relief_fail(err, RELIEF_E_RANGE, "%s has no triangles: a point set has no depth "
                         "images (a surface is needed)",
                         p->run.input_name ? p->run.input_name : "the mesh");
    return st;
}

/* The voxel grid against the memory limit (twice over with a truth: its
 * volume is measured on the same grid). */
static relief_status check_grid(const relief_mesh *in, const relief_depth_fill_params *p,
                                int with_truth, relief_error *err)
{
    relief_grid g;
    uint64_t limit = memory_limit(&p->run);
    double need;
    relief_status st = relief_grid_of_mesh((relief_mesh *)in, p->resolution, &g, err);
    if (st != RELIEF_OK)
        return st;
    need = (double)relief_volume_estimate(&g) * (with_truth ? 2.0 : 1.0);
    if (need > (double)limit)
        return relief_fail(err, RELIEF_E_NOMEM, "resolution %d: a %d x %d x %d voxel grid "
                           "needs about %.0f MiB, over the limit of %.0f MiB "
                           "(max_memory); give a lower resolution", p->resolution, g.n[0],
                           g.n[1], g.n[2], need / 1048576.0, limit / 1048576.0);
    return RELIEF_OK;
}

/* The public report of a mesh's repair: the six images summed. */
static void report_mesh(const relief_mesh_fill_report *r, const relief_mesh_measures *m,
                        const relief_mesh *o, relief_depth_fill_report *rep)
{
    for (int k = 0; k < 6; ++k) {
        rep->missing += r->hole_pixels[k];
        rep->filled += r->filled[k];
    }
    rep->missing_in_input = rep->missing;
    rep->outside = rep->missing - rep->filled;
    rep->by_synthesis = r->by_synthesis;
    rep->by_fallback = r->by_fallback;
    rep->by_membrane = r->by_membrane;
    rep->unreached = r->unreached;
    rep->lambda = NAN;
    rep->measured = m != NULL;
    rep->rms = m ? m->mean : NAN;
    rep->hausdorff = m ? m->hausdorff : NAN;
    rep->iou = m ? m->iou : NAN;
    rep->slope_jump = rep->rim_jump = rep->capture_jump = rep->truth_rim_jump = NAN;
    rep->vertices = relief_mesh_vertex_count(o);
    rep->triangles = relief_mesh_triangle_count(o);
    for (int a = 0; a < 3; ++a)
        rep->grid[a] = r->grid.n[a];
    rep->voxel = r->grid.h;
    rep->inside_voxels = r->inside_voxels;
    rep->seconds_transform = r->seconds_zbuffers + r->seconds_surface;
    rep->seconds_synthesis = r->seconds_repair;
}

/* The capture's holes, judged as relief_complete_points judges them; the
 * call is refused, before the work, when none is to be filled. */
static relief_status mesh_holes(const relief_mesh *in, const relief_depth_fill_params *p,
                                relief_hole_info *h, uint32_t **rim, relief_error *err)
{
    relief_status st = relief_holes_of_mesh(in, p->max_hole, p->hole_labels, p->has_hole_ball,
                                            p->hole_ball, rim, h, err);
    if (st == RELIEF_OK && h->n_holes == 0)
        st = relief_holes_none_filled(h, err);
    return st;
}

/* No hole could be patched: RELIEF_E_RANGE saying why it may be. */
static relief_status nothing_patched(const relief_hole_info *h, relief_error *err)
{
    int part = relief_holes_in_part(h);
    return relief_fail(err, RELIEF_E_RANGE, "nothing filled: none of the %u hole(s) the hole "
                       "model fills could be patched (%s; complete or complete-points fill "
                       "it; --solid gives the closed volume)", h->n_holes,
                       part ? "a hole filled in part, where a cut reaches the border, has no "
                              "closed rim to join a patch to"
                            : "no skin of the solid lies off the capture within reach of the "
                              "rim, as over a hole under 1.5 voxels across");
}

/* 1 when a hole the model fills has a whole rim, which a patch can join:
 * a hole filled in part never has (mesh_patch.c drops its patch), so a run
 * with no other is refused before the reconstruction, not after it. */
static int any_whole_rim(const relief_hole_info *h)
{
    for (uint32_t i = 0; i < h->n_rims; ++i)
        if (h->rims[i].fate == RELIEF_RIM_FILLED && !h->rims[i].part)
            return 1;
    return 0;
}

relief_status relief_depth_fill_mesh(const relief_mesh *in, const relief_depth_fill_params *p,
                                     const relief_mesh *truth, relief_mesh **out,
                                     relief_depth_fill_report *rep, relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    relief_hole_info holes;
    relief_mesh_patch_report patch;
    uint32_t *rim = NULL;
    relief_mesh_fill_params mp;
    relief_mesh_fill_report r;
    relief_mesh_measures m;
    relief_depth_fill_report local;
    relief_patch_scorer *scorer = NULL;
    relief_progress pr;
    relief_mesh *o = NULL;
    double t0 = relief_seconds();
    relief_status st = check_mesh_args(in, p, truth, out, err);
    if (st == RELIEF_OK)
        st = check_grid(in, p, truth != NULL, err);
    memset(&holes, 0, sizeof holes);
    memset(&patch, 0, sizeof patch);
    if (st == RELIEF_OK && !p->solid)
        st = mesh_holes(in, p, &holes, &rim, err);
    if (st == RELIEF_OK && !p->solid && p->skin && !any_whole_rim(&holes))
        st = nothing_patched(&holes, err);
    if (st != RELIEF_OK) {
        relief_hole_info_free(&holes);
        free(rim);
        return st;
    }
    memset(&local, 0, sizeof local);
    mp = relief_mesh_fill_params_default();
    mp.resolution = p->resolution;
    mp.depth = repair_params(p, 1);
    mp.depth.progress = &pr;
    relief_progress_init(&pr, p->run.progress, p->run.progress_ctx);
    st = make_scorer(&p->run, &scorer, &local, err);
    /* The repair and the measures read the meshes and never write them. */
    if (st == RELIEF_OK)
        st = said(relief_mesh_depth_fill((relief_mesh *)in, &mp, scorer, &o, &r, err), &pr, err);
    if (st == RELIEF_OK && !p->solid) {
        relief_mesh *solid = o;
        o = NULL;
        st = p->skin ? relief_mesh_patch_holes(in, solid, r.grid.h, &holes, rim, &o, &patch,
                                               err)
                     : relief_mesh_fair_holes(in, solid, r.grid.h, rim, &o, &patch, err);
        relief_mesh_destroy(solid);
        if (st == RELIEF_OK && patch.holes_patched == 0)
            st = nothing_patched(&holes, err);
    }
    if (st == RELIEF_OK && truth)
        st = relief_mesh_measure(o, (relief_mesh *)truth, &r.grid, &m, err);
    relief_patch_scorer_destroy(scorer);
    if (st == RELIEF_OK) {
        report_mesh(&r, truth ? &m : NULL, o, &local);
        if (!p->solid)
            relief_holes_left_line(&holes, local.holes_left, sizeof local.holes_left);
        local.seconds_total = relief_seconds() - t0;
        local.json = relief_depth_mesh_json(&p->run, &mp, &r, truth ? &m : NULL,
                                            p->solid ? NULL : &holes,
                                            p->solid ? NULL : &patch, &local);
        if (!local.json)
            st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the report");
    }
    if (st != RELIEF_OK) {
        relief_mesh_destroy(o);
        free(local.json);
        relief_hole_info_free(&holes);
        free(rim);
        return st;
    }
    relief_hole_info_free(&holes);
    free(rim);
    relief_progress_step(&pr, 1.0);
    *out = o;
    if (rep)
        *rep = local;
    else
        free(local.json);
    return RELIEF_OK;
}
