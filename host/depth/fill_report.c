/* The JSON reports of depth repair (fill_report.h). */
#include "depth/fill_report.h"

#include <stdio.h>
#include <stdlib.h>

#include "base/json.h"

typedef struct image_ctx {
    const relief_run_options *run;
    int width, height;
    const relief_depth_repair_params *p;
    const relief_depth_repair_report *r;
    const relief_depth_measures *m;
    const relief_depth_fill_report *rep;
} image_ctx;

typedef struct mesh_ctx {
    const relief_run_options *run;
    const relief_mesh_fill_params *p;
    const relief_mesh_fill_report *r;
    const relief_mesh_measures *m;
    const relief_hole_info *holes;        /* NULL: the whole solid */
    const relief_mesh_patch_report *patch;
    const relief_depth_fill_report *rep;
} mesh_ctx;

static const char *order_name(relief_pixsyn_order o)
{
    return o == RELIEF_ORDER_VERTICAL ? "vertical" : o == RELIEF_ORDER_HORIZONTAL ? "horizontal"
                                                                                  : "both";
}

/* The head and tail every report shares. */
static void head(relief_json *j, const relief_run_options *run)
{
    rj_begin_object(j, NULL);
    rj_string(j, "command", "depth-fill");
    rj_string_or_null(j, "input", run->input_name);
    rj_string_or_null(j, "output", run->output_name);
}

static void tail(relief_json *j, const relief_depth_fill_report *rep)
{
    rj_string(j, "backend", relief_backend_name(rep->backend));
    rj_string(j, "device", rep->device);
    rj_string(j, "backend_note", rep->backend_note);
    rj_end_object(j);
}

static void image_parameters(relief_json *j, const relief_depth_repair_params *p, double lambda)
{
    rj_begin_object(j, "parameters");
    rj_string(j, "variant", relief_depth_variant_name(p->variant));
    rj_int(j, "window", p->synth.window);
    rj_number(j, "sigma", p->synth.sigma > 0 ? p->synth.sigma : p->synth.window / 6.4);
    rj_number(j, "epsilon", p->synth.epsilon);
    rj_int(j, "search_radius", p->synth.search_radius);
    rj_bool(j, "exhaustive", p->synth.exhaustive);
    rj_int(j, "batch", p->synth.batch);
    rj_string(j, "order", order_name(p->synth.order));
    rj_bool(j, "tileable", p->synth.tileable);
    rj_int(j, "levels", p->levels);
    rj_number(j, "lambda", lambda);
    rj_string(j, "membrane", p->thin_plate ? "thin-plate" : "harmonic");
    rj_bool(j, "seam", p->seam);
    rj_string(j, "edges", p->layered ? "layers" : "across");
    if (p->layered) {
        rj_number(j, "edge_step", p->layer.step);
        rj_string(j, "values", p->layer.far_sign < 0 ? "disparity" : "depth");
    }
    rj_int(j, "seed", p->synth.seed);
    rj_end_object(j);
}

static void write_image(relief_json *j, const void *ctx)
{
    const image_ctx *c = ctx;
    const relief_depth_repair_report *r = c->r;
    const relief_depth_measures *m = c->m;
    head(j, c->run);
    rj_begin_object(j, "image");
    rj_int(j, "width", c->width);
    rj_int(j, "height", c->height);
    rj_end_object(j);
    image_parameters(j, c->p, r->lambda);
    rj_begin_object(j, "pixels");
    rj_int(j, "missing", (long long)r->missing);
    rj_int(j, "filled", (long long)r->filled);
    rj_int(j, "outside_left_missing", (long long)r->outside);
    rj_int(j, "missing_in_input", (long long)c->rep->missing_in_input);
    rj_int(j, "missing_by_mask", (long long)c->rep->missing_by_mask);
    rj_int(j, "by_synthesis", (long long)r->by_synthesis);
    rj_int(j, "by_fallback", (long long)r->by_fallback);
    rj_int(j, "by_membrane", (long long)r->by_membrane);
    rj_int(j, "unreached", (long long)r->unreached);
    rj_end_object(j);
    rj_begin_object(j, "synthesis");
    rj_string(j, "order_kept", order_name(r->kept));
    rj_number(j, "energy_horizontal", r->energy[0]);
    rj_number(j, "energy_vertical", r->energy[1]);
    rj_int(j, "candidates_scored", (long long)r->candidates);
    rj_int(j, "membrane_iterations", r->membrane_iterations);
    rj_int(j, "seam_edges", (long long)r->seam_edges);
    rj_end_object(j);
    if (c->p->layered) {
        rj_begin_object(j, "layers");
        rj_number(j, "noise", r->layer_noise);
        rj_int(j, "stepped_holes", (long long)r->stepped_holes);
        rj_int(j, "front_pixels", (long long)r->front_pixels);
        rj_int(j, "passes", r->layer_passes);
        rj_int(j, "haar_pixels_by_decompose", (long long)r->layer_decomposed);
        rj_end_object(j);
    }
    rj_begin_object(j, "measures");
    rj_int(j, "compared", (long long)m->compared);
    rj_number(j, "rms", m->rms);
    rj_int(j, "rim_triples", (long long)m->rim_pairs);
    rj_number(j, "rim_jump", m->rim_jump);
    rj_number(j, "capture_jump", m->capture_jump);
    rj_number(j, "slope_jump", m->rim_jump / m->capture_jump);
    rj_number(j, "truth_rim_jump", m->truth_jump);
    rj_end_object(j);
    rj_begin_object(j, "seconds");
    rj_number(j, "transform", r->seconds_transform);
    rj_number(j, "synthesis", r->seconds_synthesis);
    rj_number(j, "scoring", r->seconds_score);
    rj_number(j, "total", c->rep->seconds_total);
    rj_end_object(j);
    tail(j, c->rep);
}

char *relief_depth_fill_json(const relief_run_options *run, int width, int height,
                             const relief_depth_repair_params *p,
                             const relief_depth_repair_report *r,
                             const relief_depth_measures *m,
                             const relief_depth_fill_report *rep)
{
    image_ctx c = {run, width, height, p, r, m, rep};
    return rj_render(write_image, &c, "\n");
}

static void write_mesh(relief_json *j, const void *ctx)
{
    static const char *names[6] = {"x_front", "x_back", "y_front", "y_back", "z_front", "z_back"};
    const mesh_ctx *c = ctx;
    const relief_mesh_fill_report *r = c->r;
    head(j, c->run);
    rj_begin_object(j, "parameters");
    rj_string(j, "variant", relief_depth_variant_name(c->p->depth.variant));
    rj_int(j, "resolution", c->p->resolution);
    rj_int(j, "window", c->p->depth.synth.window);
    rj_int(j, "search_radius", c->p->depth.synth.search_radius);
    rj_int(j, "seed", c->p->depth.synth.seed);
    rj_end_object(j);
    rj_begin_object(j, "grid");
    rj_number(j, "voxel", r->grid.h);
    rj_int(j, "nx", r->grid.n[0]);
    rj_int(j, "ny", r->grid.n[1]);
    rj_int(j, "nz", r->grid.n[2]);
    rj_int(j, "inside_voxels", (long long)r->inside_voxels);
    rj_end_object(j);
    rj_begin_object(j, "images");
    for (int k = 0; k < 6; ++k) {
        rj_begin_object(j, names[k]);
        rj_int(j, "hole_pixels", (long long)r->hole_pixels[k]);
        rj_int(j, "filled", (long long)r->filled[k]);
        rj_end_object(j);
    }
    rj_end_object(j);
    rj_begin_object(j, "pixels");
    rj_int(j, "surface", (long long)r->surface_pixels);
    rj_int(j, "by_synthesis", (long long)r->by_synthesis);
    rj_int(j, "by_fallback", (long long)r->by_fallback);
    rj_int(j, "by_membrane", (long long)r->by_membrane);
    rj_int(j, "unreached", (long long)r->unreached);
    rj_end_object(j);
    rj_string(j, "output", c->holes ? "the capture, its holes filled" : "the solid");
    if (c->holes) {
        relief_holes_json(j, "holes", c->holes);
        rj_begin_object(j, "patches");
        rj_int(j, "holes_patched", (long long)c->patch->holes_patched);
        rj_int(j, "holes_unpatched", (long long)c->patch->holes_unpatched);
        rj_int(j, "inner_loops_capped", (long long)c->patch->inner_loops_capped);
        rj_int(j, "inner_loops_open", (long long)c->patch->inner_loops_open);
        rj_int(j, "vertices_added", (long long)c->patch->vertices_added);
        rj_int(j, "patch_triangles", (long long)c->patch->patch_triangles);
        rj_int(j, "strip_triangles", (long long)c->patch->strip_triangles);
        rj_int(j, "mended_triangles", (long long)c->patch->mended_triangles);
        rj_int(j, "mended_vertices", (long long)c->patch->mended_vertices);
        rj_int(j, "copies_welded", (long long)c->patch->copies_welded);
        rj_int(j, "untangled", (long long)c->patch->untangled);
        rj_int(j, "crossing_left", (long long)c->patch->crossing_left);
        rj_end_object(j);
    }
    rj_begin_object(j, "output_mesh");
    rj_int(j, "vertices", (long long)c->rep->vertices);
    rj_int(j, "triangles", (long long)c->rep->triangles);
    rj_end_object(j);
    if (c->m) {
        rj_begin_object(j, "measures");
        rj_number(j, "mean_distance", c->m->mean);
        rj_number(j, "hausdorff", c->m->hausdorff);
        rj_number(j, "hausdorff_voxels", c->m->hausdorff / r->grid.h);
        rj_number(j, "voxel_iou", c->m->iou);
        rj_end_object(j);
    }
    rj_begin_object(j, "seconds");
    rj_number(j, "zbuffers", r->seconds_zbuffers);
    rj_number(j, "repair", r->seconds_repair);
    rj_number(j, "surface", r->seconds_surface);
    rj_number(j, "total", c->rep->seconds_total);
    rj_end_object(j);
    tail(j, c->rep);
}

char *relief_depth_mesh_json(const relief_run_options *run, const relief_mesh_fill_params *p,
                             const relief_mesh_fill_report *r, const relief_mesh_measures *m,
                             const relief_hole_info *holes,
                             const relief_mesh_patch_report *patch,
                             const relief_depth_fill_report *rep)
{
    mesh_ctx c = {run, p, r, m, holes, patch, rep};
    return rj_render(write_mesh, &c, "\n");
}
