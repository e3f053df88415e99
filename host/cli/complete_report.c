/* Reports of smooth and complete (complete_report.h). */
#include "cli/complete_report.h"

#include <string.h>

#include "relief/relief.h"
#include "base/params.h"
#include "base/json.h"
#include "report/pattern.h"
#include "report/report.h"
#include "smooth/oversample.h"

static void report_params(relief_json *j, const relief_params *p,
                          const relief_smooth_options *o)
{
    rj_begin_object(j, "parameters");
    rj_string(j, "fit", relief_fit_model_name(p->fit));
    rj_int(j, "oversample", p->oversample);
    rj_string(j, "oversample_scheme", relief_oversample_scheme_name(o->oversample_scheme));
    if (p->spacing > 0.0)
        rj_number(j, "spacing", p->spacing);
    else
        rj_null(j, "spacing");
    rj_number(j, "spacing_percentile", o->spacing_percentile);
    rj_string(j, "frames", o->frames == RELIEF_FRAMES_PAPER ? "paper" : "primitive");
    rj_string(j, "fill", relief_fill_region_name(o->fill));
    if (p->has_extent) {
        rj_begin_array(j, "extent");
        for (int i = 0; i < p->n_extent; ++i)
            rj_number(j, NULL, p->extent[i]);
        rj_end_array(j);
    }
    rj_end_object(j);
}

int cli_write_smooth_report(FILE *f, void *ctx)
{
    const smooth_report *r = ctx;
    relief_json j;
    rj_init(&j, f);
    rj_begin_object(&j, NULL);
    rj_string(&j, "relief_version", RELIEF_VERSION_STRING);
    rj_string(&j, "command", "smooth");
    rj_string(&j, "input", r->input);
    rj_string(&j, "output", r->output);
    report_params(&j, r->params, r->opts);
    relief_report_surface_fields(&j, r->surface);
    rj_number(&j, "seconds_total", r->seconds);
    rj_end_object(&j);
    return 0;
}

/* Per level of a hierarchical run: sizes, sample pyramids, growth. */
static void report_levels(relief_json *j, const relief_hierarchy_stats *hs)
{
    rj_number(j, "hierarchy_build_seconds", hs->build_seconds);
    rj_begin_array(j, "levels");
    for (int k = 0; k < hs->levels; ++k) {
        const relief_level_stats *l = &hs->level[k];
        rj_begin_object(j, NULL);
        rj_int(j, "level", k + 1);
        rj_int(j, "vertices", (long long)l->vertices);
        rj_int(j, "samples", (long long)l->samples);
        rj_int(j, "targets", (long long)l->targets);
        rj_int(j, "pyramid_boxes", (long long)l->boxes);
        rj_number(j, "pyramid_box_samples_mean", l->box_samples);
        rj_int(j, "restricted_matches", (long long)l->grow.pyramid_hits);
        rj_int(j, "fallbacks_nothing_passed", (long long)l->grow.pyramid_misses);
        rj_int(j, "fallbacks_no_box", (long long)l->grow.pyramid_empty);
        rj_string(j, "search", relief_search_name((relief_search_mode)l->grow.search));
        rj_int(j, "candidates_scored", (long long)l->grow.candidates);
        rj_int(j, "acceptances", (long long)l->grow.acceptances);
        rj_int(j, "coherent", (long long)l->grow.coherent);
        rj_int(j, "rejections", (long long)l->grow.rejections);
        rj_int(j, "threshold_raises", (long long)l->grow.threshold_raises);
        rj_number(j, "error_final", l->grow.error_final);
        rj_number(j, "seconds", l->seconds);
        rj_end_object(j);
    }
    rj_end_array(j);
}

int cli_write_complete_report(FILE *f, void *ctx)
{
    const complete_report *r = ctx;
    const relief_grow_stats *g = r->stats;
    relief_json j;
    rj_init(&j, f);
    rj_begin_object(&j, NULL);
    rj_string(&j, "relief_version", RELIEF_VERSION_STRING);
    rj_string(&j, "command", "complete");
    rj_string(&j, "input", r->input);
    rj_string(&j, "output", r->output);
    report_params(&j, r->params, r->opts);
    rj_begin_object(&j, "growth_parameters");
    rj_int(&j, "window", r->params->window);
    rj_int(&j, "rotations", r->params->rotations);
    rj_number(&j, "error", r->params->error);
    rj_number(&j, "mu", g->mu);
    rj_number(&j, "coherence", r->params->coherence);
    rj_string(&j, "search", relief_search_name((relief_search_mode)g->search));
    rj_int(&j, "search_k", r->params->search_k);
    rj_int(&j, "seed", (long long)r->params->seed);
    rj_int(&j, "levels", r->params->levels);
    rj_bool(&j, "prune", r->gopts->prune);
    rj_bool(&j, "bootstrap", r->gopts->bootstrap);
    rj_end_object(&j);
    relief_report_surface_fields(&j, r->surface);
    rj_begin_object(&j, "growth");
    rj_int(&j, "targets", (long long)g->targets);
    rj_int(&j, "passes", (long long)g->passes);
    rj_int(&j, "candidates_scored", (long long)g->candidates);
    rj_int(&j, "pruned", (long long)g->pruned);
    rj_int(&j, "invalid", (long long)g->invalid);
    rj_int(&j, "acceptances", (long long)g->acceptances);
    rj_int(&j, "coherent", (long long)g->coherent);
    rj_int(&j, "rejections", (long long)g->rejections);
    rj_int(&j, "no_valid_candidate", (long long)g->no_candidate);
    rj_int(&j, "threshold_raises", (long long)g->threshold_raises);
    rj_int(&j, "window_shrinks", (long long)g->window_shrinks);
    rj_number(&j, "error_final", g->error_final);
    rj_number(&j, "b_shape", g->b_shape);
    rj_number(&j, "seconds", g->seconds);
    rj_number(&j, "match_seconds", g->match_seconds);
    if (g->search == RELIEF_SEARCH_COHERENT) {
        rj_begin_object(&j, "search");
        rj_int(&j, "accepted_from_continuations", (long long)g->search_hits);
        rj_int(&j, "fallbacks_nothing_passed", (long long)g->search_misses);
        rj_int(&j, "fallbacks_no_continuation", (long long)g->search_empty);
        rj_number(&j, "continuations_mean",
                  g->acceptances + g->rejections
                      ? (double)g->search_centres / (double)(g->acceptances + g->rejections)
                      : 0.0);
        rj_number(&j, "build_seconds", g->search_seconds);
        rj_end_object(&j);
    }
    rj_end_object(&j);
    if (r->hier)
        report_levels(&j, r->hier);
    if (r->measures) {
        rj_begin_object(&j, "measures");
        relief_report_measures_fields(&j, r->measures);
        if (r->pattern)
            relief_pattern_json_fields(&j, r->pattern);
        rj_end_object(&j);
    }
    rj_begin_object(&j, "backend");
    rj_string(&j, "name", relief_backend_name(r->backend));
    rj_string(&j, "requested", relief_backend_name(r->params->backend));
    rj_string(&j, "device", r->device);
    if (r->choice && r->choice[0])
        rj_string(&j, "choice", r->choice);
    rj_number(&j, "kernel_seconds", r->kernel_seconds);
    if (r->fallback && r->fallback[0])
        rj_string(&j, "fallback", r->fallback);
    rj_end_object(&j);
    rj_number(&j, "seconds_total", r->seconds);
    rj_end_object(&j);
    return 0;
}

relief_status cli_stage_report_dir(const char *dir, complete_report *r,
                                   const relief_mesh *capture, const relief_mesh *smooth,
                                   relief_report_dir **staged, relief_error *err)
{
    relief_report_content c;
    memset(&c, 0, sizeof c);
    c.input = r->input;
    c.output = r->output;
    c.capture = capture;
    c.smooth = smooth;
    c.surface = r->surface;
    c.params = r->params;
    c.stats = r->stats;
    c.measures = r->measures;
    c.backend = relief_backend_name(r->backend);
    c.device = r->device;
    c.seconds_total = r->seconds;
    c.write_json = cli_write_complete_report;
    c.json_ctx = r;
    return relief_report_dir_stage(dir, &c, staged, err);
}
