#include "report/report.h"

void relief_report_primitive_fields(relief_json *j, const relief_fit_primitive *p)
{
    rj_string(j, "model", relief_fit_model_name(p->model));
    if (p->model == RELIEF_FIT_PLANE) {
        rj_vec3(j, "point", p->point);
        rj_vec3(j, "normal", p->dir);
    } else if (p->model == RELIEF_FIT_SPHERE) {
        rj_vec3(j, "center", p->point);
        rj_number(j, "radius", p->radius);
    } else {
        rj_vec3(j, "axis_point", p->point);
        rj_vec3(j, "axis_dir", p->dir);
        rj_number(j, "radius", p->radius);
    }
}

void relief_report_fit_fields(relief_json *j, const relief_fit_result *r)
{
    relief_report_primitive_fields(j, &r->prim);
    rj_number(j, "rms", r->rms);
    rj_number(j, "rms_all", r->rms_all);
    rj_number(j, "inlier_fraction", r->inlier_fraction);
    rj_int(j, "n_points", (long long)r->n_points);
    rj_int(j, "n_inliers", (long long)r->n_inliers);
    rj_number(j, "size", r->size);
    rj_bool(j, "poor_fit", r->poor_fit);
    rj_number(j, "poor_fit_limit", RELIEF_FIT_POOR);
    rj_begin_object(j, "model_rms");
    for (int m = RELIEF_FIT_PLANE; m <= RELIEF_FIT_CYLINDER; ++m)
        if (r->model_rms[m] >= 0.0)
            rj_number(j, relief_fit_model_name((relief_fit_model)m), r->model_rms[m]);
    rj_end_object(j);
    rj_string(j, "reason", r->reason);
}

void relief_report_surface_fields(relief_json *j, const relief_surface *s)
{
    rj_begin_object(j, "fit");
    relief_report_fit_fields(j, &s->fit);
    rj_end_object(j);
    rj_number(j, "spacing", s->spacing);
    rj_string(j, "spacing_source", s->spacing_from_capture
                                       ? "capture edge-length percentile"
                                       : "given");
    rj_string(j, "region", relief_fill_region_name(s->fill.region));
    rj_number(j, "cover", s->fill.cover);
    if (s->fill.round_gap > 0.0) { /* a cylinder or sphere the targets were laid on */
        rj_number(j, "round_gap_degrees", s->fill.round_gap);
        rj_bool(j, "all_round", s->fill.all_round);
    }
    rj_begin_object(j, "counts");
    rj_int(j, "captured", (long long)s->n_captured);
    rj_int(j, "samples", (long long)s->n_samples);
    rj_int(j, "targets", (long long)s->n_targets);
    rj_int(j, "dropped", (long long)s->n_dropped);
    rj_int(j, "folded_triangles", (long long)s->folds.triangles);
    rj_number(j, "folded_area_fraction", s->folds.area_fraction);
    rj_int(j, "folded_triangles_dropped", (long long)s->folds.triangles_dropped);
    rj_int(j, "folded_vertices_dropped", (long long)s->folds.vertices_dropped);
    rj_int(j, "spikes_dropped", (long long)s->spikes.vertices);
    rj_number(j, "spike_threshold", s->spikes.threshold);
    rj_int(j, "holes", (long long)s->fill.holes);
    rj_int(j, "hole_points", (long long)s->fill.hole_points);
    rj_int(j, "outside_points", (long long)s->fill.outside_points);
    rj_int(j, "holes_left_open", (long long)s->fill.holes_left);
    rj_int(j, "holes_left_open_points", (long long)s->fill.holes_left_points);
    rj_int(j, "dropped_holes", (long long)s->fill.dropped_holes);
    rj_int(j, "outside_points_taken", (long long)s->fill.outside_taken);
    rj_int(j, "vertices", (long long)relief_mesh_vertex_count(s->mesh));
    rj_int(j, "triangles", (long long)relief_mesh_triangle_count(s->mesh));
    rj_end_object(j);
    rj_begin_object(j, "parameter_frame");
    rj_vec3(j, "e1", s->param.e1);
    rj_vec3(j, "e2", s->param.e2);
    rj_end_object(j);
    rj_begin_object(j, "seconds");
    rj_number(j, "fit", s->seconds[RELIEF_STAGE_FIT]);
    rj_number(j, "targets", s->seconds[RELIEF_STAGE_TARGETS]);
    rj_number(j, "oversample", s->seconds[RELIEF_STAGE_OVERSAMPLE]);
    rj_number(j, "triangulate", s->seconds[RELIEF_STAGE_TRIANGULATE]);
    rj_end_object(j);
}
