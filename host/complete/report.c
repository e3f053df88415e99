/* The reports of relief_complete and relief_smooth: the JSON that `relief
 * complete --report` writes, and the report folder (report/report_dir.h)
 * staged for the caller to commit. */
#include "complete/engine.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/json.h"
#include "report/report.h"
#include "report/report_dir.h"

/* A staged --report-dir folder (relief/complete.h). */
struct relief_report_folder {
    relief_report_dir *staged;
};

static void report_params(relief_json *j, const relief_params *p,
                          const relief_smooth_options *o)
{
    rj_begin_object(j, "parameters");
    rj_string(j, "fit", relief_fit_model_name(p->fit));
    rj_int(j, "oversample", p->oversample);
    rj_string(j, "oversample_scheme",
              relief_oversample_scheme_name((relief_oversample_scheme)o->oversample_scheme));
    if (p->spacing > 0.0)
        rj_number(j, "spacing", p->spacing);
    else
        rj_null(j, "spacing");
    rj_number(j, "spacing_percentile", o->spacing_percentile);
    rj_string(j, "frames", relief_frames_name(o->frames));
    rj_string(j, "fill", relief_fill_region_name(o->fill));
    if (p->has_extent) {
        rj_begin_array(j, "extent");
        for (int i = 0; i < p->n_extent; ++i)
            rj_number(j, NULL, p->extent[i]);
        rj_end_array(j);
    }
    rj_end_object(j);
}

/* What every report starts with: the version, the command, the files. */
static void report_head(relief_json *j, const relief_complete_run *r, const char *command)
{
    rj_string(j, "relief_version", RELIEF_VERSION_STRING);
    rj_string(j, "command", command);
    rj_string_or_null(j, "input", r->cp->run.input_name);
    rj_string_or_null(j, "output", r->cp->run.output_name);
}

static void report_growth_parameters(relief_json *j, const relief_complete_run *r)
{
    const relief_params *p = &r->st.params;
    rj_begin_object(j, "growth_parameters");
    rj_int(j, "window", p->window);
    rj_int(j, "rotations", p->rotations);
    rj_number(j, "error", p->error);
    rj_number(j, "mu", r->stats.mu);
    rj_number(j, "coherence", p->coherence);
    rj_string(j, "search", relief_search_name((relief_search_mode)r->stats.search));
    rj_int(j, "search_k", p->search_k);
    rj_int(j, "seed", (long long)p->seed);
    rj_int(j, "levels", p->levels);
    rj_bool(j, "prune", r->st.grow.prune);
    rj_bool(j, "bootstrap", r->st.grow.bootstrap);
    rj_string(j, "base", r->smooth_base ? "smooth" : "primitive");
    rj_end_object(j);
}

static void report_search(relief_json *j, const relief_grow_stats *g)
{
    rj_begin_object(j, "search");
    rj_int(j, "accepted_from_continuations", (long long)g->search_hits);
    rj_int(j, "fallbacks_nothing_passed", (long long)g->search_misses);
    rj_int(j, "fallbacks_no_continuation", (long long)g->search_empty);
    rj_number(j, "continuations_mean",
              g->acceptances + g->rejections
                  ? (double)g->search_centres / (double)(g->acceptances + g->rejections)
                  : 0.0);
    rj_number(j, "build_seconds", g->search_seconds);
    rj_end_object(j);
}

static void report_growth(relief_json *j, const relief_grow_stats *g)
{
    rj_begin_object(j, "growth");
    rj_int(j, "targets", (long long)g->targets);
    rj_int(j, "passes", (long long)g->passes);
    rj_int(j, "candidates_scored", (long long)g->candidates);
    rj_int(j, "pruned", (long long)g->pruned);
    rj_int(j, "invalid", (long long)g->invalid);
    rj_int(j, "acceptances", (long long)g->acceptances);
    rj_int(j, "coherent", (long long)g->coherent);
    rj_int(j, "rejections", (long long)g->rejections);
    rj_int(j, "no_valid_candidate", (long long)g->no_candidate);
    rj_int(j, "threshold_raises", (long long)g->threshold_raises);
    rj_int(j, "window_shrinks", (long long)g->window_shrinks);
    rj_number(j, "error_final", g->error_final);
    rj_number(j, "b_shape", g->b_shape);
    rj_number(j, "seconds", g->seconds);
    rj_number(j, "match_seconds", g->match_seconds);
    if (g->search == RELIEF_SEARCH_COHERENT)
        report_search(j, g);
    rj_end_object(j);
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

static void report_backend(relief_json *j, const relief_complete_run *r)
{
    const relief_complete_report *rep = r->rep;
    rj_begin_object(j, "backend");
    rj_string(j, "name", relief_backend_name(r->backend));
    rj_string(j, "requested", relief_backend_name(r->st.params.backend));
    rj_string(j, "device", r->device);
    if (r->choice[0])
        rj_string(j, "choice", r->choice);
    rj_number(j, "kernel_seconds", rep->seconds_match);
    if (r->hier ? r->hstats.fallback[0] : r->m && r->m->fallback_note[0])
        rj_string(j, "fallback", r->hier ? r->hstats.fallback : r->m->fallback_note);
    rj_end_object(j);
}

static void report_notes(relief_json *j, const relief_complete_report *rep)
{
    rj_begin_array(j, "notes");
    for (int i = 0; i < rep->n_notes; ++i)
        rj_string(j, NULL, rep->notes[i].text);
    rj_end_array(j);
}

/* The surface's loops still open where holes were filled, when that was
 * checked (over a primitive, only holes filled). */
static void report_open(relief_json *j, const relief_complete_run *r)
{
    if (!r->closed_checked)
        return;
    rj_begin_object(j, "holes_not_closed");
    rj_int(j, "loops", (long long)r->open_loops);
    rj_int(j, "boundary_vertices", (long long)r->open_edges);
    rj_end_object(j);
}

static void write_complete(relief_json *j, const relief_complete_run *r)
{
    report_head(j, r, "complete");
    report_params(j, &r->st.params, &r->st.smooth);
    report_growth_parameters(j, r);
    relief_report_surface_fields(j, r->s);
    if (r->has_holes) {
        relief_holes_json(j, "hole_model", &r->holes);
        report_open(j, r);
    }
    report_growth(j, &r->stats);
    if (r->hier)
        report_levels(j, &r->hstats);
    if (r->measured) {
        rj_begin_object(j, "measures");
        relief_report_measures_fields(j, &r->meas);
        if (r->patterned)
            relief_pattern_json_fields(j, &r->pat);
        rj_end_object(j);
    }
    report_backend(j, r);
    report_notes(j, r->rep);
    rj_number(j, "seconds_total", r->rep->seconds_total);
}

static void write_smooth(relief_json *j, const relief_complete_run *r)
{
    report_head(j, r, "smooth");
    report_params(j, &r->st.params, &r->st.smooth);
    relief_report_surface_fields(j, r->s);
    if (r->has_holes) {
        relief_holes_json(j, "hole_model", &r->holes);
        report_open(j, r);
    }
    report_notes(j, r->rep);
    rj_number(j, "seconds_total", r->rep->seconds_total);
}

static void write_complete_doc(relief_json *j, const void *ctx)
{
    rj_begin_object(j, NULL);
    write_complete(j, ctx);
    rj_end_object(j);
}

static void write_smooth_doc(relief_json *j, const void *ctx)
{
    rj_begin_object(j, NULL);
    write_smooth(j, ctx);
    rj_end_object(j);
}

char *relief_complete_json(const relief_complete_run *r, int smooth)
{
    return rj_render(smooth ? write_smooth_doc : write_complete_doc, r, "\n");
}

static int write_json(FILE *f, void *ctx)
{
    return fputs((const char *)ctx, f) < 0;
}

relief_status relief_complete_stage_folder(const relief_complete_run *r,
                                           relief_report_folder **out, relief_error *err)
{
    relief_report_content c;
    relief_report_folder *folder = malloc(sizeof *folder);
    relief_status st;
    if (!folder)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the report folder");
    memset(&c, 0, sizeof c);
    c.input = r->cp->run.input_name ? r->cp->run.input_name : "(the capture)";
    c.output = r->cp->run.output_name ? r->cp->run.output_name : "(the completion)";
    c.capture = r->capture;
    c.smooth = r->before;
    c.surface = r->s;
    c.params = &r->st.params;
    c.stats = &r->stats;
    c.measures = r->measured ? &r->meas : NULL;
    c.backend = relief_backend_name(r->backend);
    c.device = r->device;
    c.seconds_total = r->rep->seconds_total;
    c.write_json = write_json;
    c.json_ctx = r->rep->json;
    st = relief_report_dir_stage(r->cp->report_dir, &c, &folder->staged, err);
    if (st != RELIEF_OK) {
        free(folder);
        return st;
    }
    *out = folder;
    return RELIEF_OK;
}

relief_status relief_report_folder_commit(relief_report_folder *folder, relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    relief_status st;
    if (!folder)
        return RELIEF_OK;
    st = relief_report_dir_commit(folder->staged, err);
    free(folder);
    return st;
}

relief_staged_folder *relief_report_folder_release(relief_report_folder *folder)
{
    relief_staged_folder *s = relief_report_dir_release(folder->staged);
    free(folder);
    return s;
}

void relief_complete_report_free(relief_complete_report *rep)
{
    if (!rep)
        return;
    free(rep->json);
    if (rep->folder) {
        relief_report_dir_abort(rep->folder->staged);
        free(rep->folder);
    }
    memset(rep, 0, sizeof *rep);
}
