/* relief_complete and relief_smooth (relief/complete.h): the mesh pipeline
 * of papers 000 and 001 as stages, each a function: the checks and a saved
 * run to resume, the base (a fitted primitive or the capture's smoothed
 * one), the growth's data and matcher (or the hierarchy's levels), the
 * growth with the caller's progress and cancel, and the report. */
#include "complete/engine.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/clock.h"
#include "base/error.h"
#include "base/memlimit.h"
#include "base/numtext.h"
#include "match/match_data.h"
#include "mesh/mesh.h"
#include "match/search.h"
#include "points/base_surface.h"
#include "report/report_dir.h"
#include "smooth/surface_check.h"

void relief_complete_note(relief_complete_run *r, int warning, const char *fmt, ...)
{
    relief_complete_report *rep = r->rep;
    va_list ap;
    if (!rep || rep->n_notes >= (int)(sizeof rep->notes / sizeof rep->notes[0]))
        return;
    rep->notes[rep->n_notes].warning = warning;
    va_start(ap, fmt);
    relief_vsnprintf_c(rep->notes[rep->n_notes].text, sizeof rep->notes[0].text, fmt, ap);
    va_end(ap);
    ++rep->n_notes;
}

/* ------------------------------------------------------------ the start */

static relief_status check_args(const relief_mesh *capture, const relief_complete_params *p,
                                relief_mesh **out, const relief_complete_report *rep,
                                relief_error *err)
{
    relief_status st;
    if (!capture || !p || !out)
        return relief_fail(err, RELIEF_E_USAGE, "%s is NULL",
                           !capture ? "capture" : !p ? "params" : "out");
    st = relief_complete_params_validate(p, err);
    if (st == RELIEF_OK)
        st = relief_mesh_validate(capture, err);
    if (st == RELIEF_OK && p->report_dir && !rep)
        st = relief_fail(err, RELIEF_E_USAGE, "report_dir: the folder is handed back in the "
                         "report; pass one");
    /* A folder that cannot be written fails now, not after the growth. */
    if (st == RELIEF_OK && p->report_dir)
        st = relief_report_dir_check(p->report_dir, err);
    return st;
}

/* A saved growth to continue (cp->resume), checked against this call's
 * input and parameters. */
static relief_status read_resume(relief_complete_run *r, relief_error *err)
{
    relief_checkpoint_key_make(r->capture, &r->st.params, &r->st.smooth, &r->st.grow, &r->key);
    /* The hole model's choice changes the targets too. */
    relief_snprintf_c(r->key.params + strlen(r->key.params),
                      sizeof r->key.params - strlen(r->key.params),
                      " max_hole=%.17g hole_ball=%s%.17g,%.17g,%.17g,%.17g hole_labels=%d",
                      r->cp->max_hole, r->cp->has_hole_ball ? "" : "none:", r->cp->hole_ball[0],
                      r->cp->hole_ball[1], r->cp->hole_ball[2], r->cp->hole_ball[3],
                      r->cp->hole_labels);
    if (!r->cp->resume)
        return RELIEF_OK;
    return relief_checkpoint_read(r->cp->resume, &r->key, &r->resume, err);
}

/* --------------------------------------------------------------- the base */

/* What the capture check and the fit found, as notes: a poor fit accepted,
 * folded triangles and spikes dropped, a curved primitive's outside left. */
static void note_surface(relief_complete_run *r)
{
    const relief_surface *s = r->s;
    const relief_fold_stats *f = &s->folds;
    const char *model = relief_fit_model_name(s->fit.prim.model);
    if (s->fit.poor_fit)
        relief_complete_note(r, 1, "poor fit accepted: %s", s->fit.reason);
    if (f->triangles > 0)
        relief_complete_note(r, 1, "%zu triangles (%.2f%% of the capture's area) fold back "
                             "over the fitted %s; they, the %zu vertices they touch and %zu "
                             "triangles in all were dropped, and the hole is completed",
                             f->triangles, 100.0 * f->area_fraction, model,
                             f->vertices_dropped, f->triangles_dropped);
    if (s->spikes.vertices > 0)
        relief_complete_note(r, 1, "%zu capture vertices stand out of their neighbours' "
                             "heights by more than %.4g (8 robust scales of %.4g; the largest "
                             "by %.4g): taken for scanner spikes, left out with %zu triangles "
                             "and completed (keep_spikes keeps them)", s->spikes.vertices,
                             s->spikes.threshold, s->spikes.scale, s->spikes.largest,
                             s->spikes.triangles_dropped);
    if (s->fill.region == RELIEF_FILL_HOLES && s->fill.outside_points > 0 &&
        s->fit.prim.model != RELIEF_FIT_PLANE)
        relief_complete_note(r, 0, "the capture covers %.1f%% of the fitted %s: completing "
                             "the %zu hole%s inside its outline (%zu targets); fill whole "
                             "completes the rest of the %s too (%zu more)",
                             100.0 * s->fill.cover, model, s->fill.holes,
                             s->fill.holes == 1 ? "" : "s", s->fill.hole_points, model,
                             s->fill.outside_points);
}

/* How far (in spacings) the smoothed base keeps from the capture when the
 * holes are told: half complete-points' bound (1). The growth copies the
 * samples' displacement over it whole, so what the base smooths away
 * comes back as relief: on the bench's told photogrammetry cuts, over
 * seeds 1 to 3, the knee's detail ratio went from 1.58 to 1.98 down to
 * 1.42 to 1.44, the leg's from 2.18 to 3.41 down to 1.93 to 1.96, the
 * vase's and the head's notch unchanged (issue 61; 0.25 was no better).
 * Not with the default hole model: over the whole statue's 763 targets the
 * tighter displacement range left 113 targets with no continuation under
 * e, each scoring every sample (9.2 s of growth against 4.4 s). */
#define BASE_MAX_DETAIL_TOLD 0.5

/* The capture's own smoothed, hole-filled base (points/base_surface.h),
 * its holes chosen by max_hole or the selection (hole_ball, hole_labels),
 * as complete-points chooses them; the hole model goes to the report.
 * fit: the capture's primitive when already fitted (or NULL). laid: the
 * base is to be laid on that primitive (relief_surface_lay_on), so the
 * curvature flow that smooths it would be thrown away: not run. */
static relief_status smooth_base(relief_complete_run *r, const relief_fit_result *fit,
                                 int laid, relief_error *err)
{
    const relief_complete_params *cp = r->cp;
    relief_points_params pp = relief_points_params_default();
    relief_points_report prep;
    uint8_t *select = NULL, *crop_select = NULL;
    relief_status st = relief_holes_selection(r->capture, cp->hole_labels, cp->has_hole_ball,
                                              cp->hole_ball, &select, err);
    if (st == RELIEF_OK && select)
        st = relief_complete_crop(r, select, &crop_select, err);
    if (st != RELIEF_OK) {
        free(select);
        return st;
    }
    pp.max_hole = cp->max_hole;
    if (cp->has_hole_ball || cp->hole_labels)
        pp.max_detail = BASE_MAX_DETAIL_TOLD;
    pp.hole_select = r->crop ? crop_select : select;
    if (laid)
        pp.smooth_steps = 0;
    /* as complete-points: scalar on one thread, else the threads asked */
    pp.threads = r->st.params.backend == RELIEF_BACKEND_SCALAR ? 1 : r->st.params.threads;
    st = relief_points_base_surface(r->crop ? r->crop : r->capture, &pp, fit, &r->s, &prep,
                                    err);
    free(select);
    free(crop_select);
    r->smooth_base = st == RELIEF_OK;
    if (st == RELIEF_OK) {
        if (!r->crop) { /* else the whole capture's list, already made */
            relief_complete_holes_free(r);
            r->holes = prep.holes; /* taken: the report's list */
            memset(&prep.holes, 0, sizeof prep.holes);
            r->has_holes = 1;
        }
        /* what the base's surface has open at the holes it filled, as
         * counted on it (points/patch_mesh.h) */
        r->closed_checked = 1;
        r->open_loops = prep.open_loops;
        r->open_edges = prep.open_edges;
        relief_points_report_free(&prep);
    }
    return st;
}

/* base auto: the capture's own smoothed, hole-filled base when no
 * primitive fits (issue 21), or, when that cannot be built either, the
 * poor fit's refusal with both reasons. */
static relief_status auto_base(relief_complete_run *r, const relief_fit_result *pre,
                               relief_error *err)
{
    relief_error why = {0};
    relief_status st = smooth_base(r, pre, 0, &why);
    /* The user's selection fills nothing there: that is the answer, not
     * the primitive's poor fit. */
    if (st == RELIEF_E_RANGE && (r->cp->has_hole_ball || r->cp->hole_labels) &&
        why.reason == RELIEF_REASON_NOTHING_TO_FILL) {
        *err = why;
        return st;
    }
    if (st == RELIEF_OK) {
        relief_complete_note(r, 0, "no primitive fits well (%s): growing on the capture's "
                             "smoothed base (base smooth; base primitive with "
                             "accept_poor_fit keeps the %s)", pre->reason,
                             relief_fit_model_name(pre->prim.model));
        return RELIEF_OK;
    }
    st = relief_surface_build(r->capture, &r->st.params, &r->st.smooth, &r->s, err);
    if (st != RELIEF_OK)
        relief_fail_prefix(err, "the smoothed base (base smooth) could not be built either "
                           "(%s); and", why.message);
    return st;
}

/* May base auto take the smoothed base in place of the primitive? Only
 * when the user chose neither the primitive nor its fit or extent. */
static int auto_may_go_smooth(const relief_complete_run *r)
{
    const relief_complete_params *cp = r->cp;
    return cp->base == RELIEF_BASE_AUTO && !cp->accept_poor_fit &&
           cp->fit == RELIEF_FIT_AUTO && !cp->n_extent &&
           relief_mesh_triangle_count(r->capture) > 0;
}

/* base auto, the primitive fitted but the capture folds over it (a fluted
 * pot over its sphere, issue 40): no height field there, so the capture's
 * own smoothed base, which needs none, or the fold's refusal with both
 * reasons. */
static relief_status overlap_base(relief_complete_run *r, relief_error *err)
{
    relief_error why = {0};
    char fold[RELIEF_ERROR_MESSAGE_MAX];
    snprintf(fold, sizeof fold, "%s", err->message);
    if (smooth_base(r, NULL, 0, &why) != RELIEF_OK)
        return relief_fail(err, RELIEF_E_MESH, "%s; and the smoothed base (base smooth) could "
                           "not be built either (%s)", fold, why.message);
    relief_complete_note(r, 0, "the capture is no height field over its primitive (%s): "
                         "growing on the capture's smoothed base (base smooth)", fold);
    return RELIEF_OK;
}

/* Does a selection fill part of a border's loop (a notch, mesh/holes.h)? */
static int told_notch(const relief_complete_run *r)
{
    return r->has_holes && (r->cp->has_hole_ball || r->cp->hole_labels) &&
           relief_holes_in_part(&r->holes);
}

/* Does a selection tell holes closed whole (no notch)? */
static int told_whole(const relief_complete_run *r)
{
    return r->has_holes && (r->cp->has_hole_ball || r->cp->hole_labels) &&
           r->holes.n_holes > 0 && !relief_holes_in_part(&r->holes);
}

static relief_status build_base(relief_complete_run *r, relief_error *err)
{
    const relief_complete_params *cp = r->cp;
    relief_fit_result pre;
    relief_status st;
    int fitted = 0;
    double t0 = relief_seconds();
    if (cp->base == RELIEF_BASE_SMOOTH) {
        st = smooth_base(r, NULL, 0, err);
    } else if (cp->base == RELIEF_BASE_AUTO && told_notch(r)) {
        st = smooth_base(r, NULL, 0, err);
        if (st == RELIEF_OK)
            relief_complete_note(r, 0, "the hole told reaches the capture's border: its notch "
                                 "is closed by the chord across its ends on the capture's "
                                 "smoothed base (base smooth), where a primitive's lattice "
                                 "would run on past the border (base primitive keeps it)");
    } else if (auto_may_go_smooth(r) &&
               (fitted = relief_fit_mesh_threads(r->capture, RELIEF_FIT_AUTO,
                                                  r->st.params.threads, &pre, NULL) ==
                         RELIEF_OK) &&
               pre.poor_fit) {
        st = auto_base(r, &pre, err);
    } else if (fitted && told_whole(r)) {
        st = smooth_base(r, &pre, 1, err);
        if (st == RELIEF_OK) {
            relief_surface_lay_on(r->s, &pre);
            relief_complete_note(r, 0, "the hole%s told closed from %s rim%s and laid on the "
                                 "fitted %s; the rest of the capture as it is (base "
                                 "primitive completes over the %s's lattice instead)",
                                 r->holes.n_holes == 1 ? "" : "s",
                                 r->holes.n_holes == 1 ? "its" : "their",
                                 r->holes.n_holes == 1 ? "" : "s",
                                 relief_fit_model_name(pre.prim.model),
                                 relief_fit_model_name(pre.prim.model));
        }
    } else {
        relief_error why = {0};
        /* the fit just made, auto's as the params' (auto_may_go_smooth) */
        r->st.smooth.fitted = fitted ? &pre : NULL;
        st = relief_surface_build(r->capture, &r->st.params, &r->st.smooth, &r->s, &why);
        r->st.smooth.fitted = NULL;
        /* surface_check.c's fold refusal, the one a smooth base cures */
        if (st == RELIEF_E_MESH && auto_may_go_smooth(r) &&
            why.reason == RELIEF_REASON_FOLD_REFUSED)
            st = overlap_base(r, &why);
        if (st == RELIEF_E_RANGE && r->has_holes && why.reason == RELIEF_REASON_HOLES_LEFT_OPEN)
            st = relief_holes_none_filled(&r->holes, &why);
        if (st != RELIEF_OK)
            *err = why;
    }
    if (st != RELIEF_OK)
        return st;
    /* From here on the rotations are the base's (0: its default), so the
     * estimate, the growth and the report agree; the checkpoint key keeps
     * them as given. A smooth base turns as a sphere does: 4. */
    r->st.params.rotations = r->smooth_base && cp->rotations == 0
                                 ? 4
                                 : relief_params_rotations(&r->st.params, r->s->fit.prim.model);
    if (!r->smooth_base) /* else the fit is only reported */
        note_surface(r);
    relief_complete_note_open_rims(r);
    st = relief_complete_holes_closed(r, err);
    if (st != RELIEF_OK)
        return st;
    if (r->rep)
        r->rep->seconds_smooth = relief_seconds() - t0;
    return RELIEF_OK;
}

/* ----------------------------------------------------- data and matcher */

/* Host bytes the mono-scale growth needs, the k-coherence search's similar
 * pairs included when it runs. */
static uint64_t growth_bytes(const relief_complete_run *r)
{
    const relief_surface *s = r->s;
    const relief_params *p = &r->st.params;
    uint64_t b = relief_estimate_growth(relief_mesh_vertex_count(s->mesh),
                                        relief_mesh_triangle_count(s->mesh), s->n_samples,
                                        p->rotations);
    if (relief_params_search(p, s->n_samples, p->rotations, s->n_targets) ==
        RELIEF_SEARCH_COHERENT)
        b += relief_search_bytes(s->n_samples, p->rotations, p->search_k);
    return b;
}

/* Refuse a growth that cannot fit before its match data and state exist. */
static relief_status check_growth_memory(const relief_complete_run *r, relief_error *err)
{
    char what[160];
    snprintf(what, sizeof what, "the growth over %zu vertices (%zu samples x %d rotations)",
             relief_mesh_vertex_count(r->s->mesh), r->s->n_samples, r->st.params.rotations);
    return relief_memory_check(what, growth_bytes(r), relief_memory_limit(&r->st.params),
                               "; raise the spacing or lower rotations", err);
}

/* Test hook: RELIEF_TEST_DEVICE_FAIL_AFTER=N makes every OpenCL score after
 * the first N fail as an exhausted device would, so that the CLI test sees
 * auto continue on the host matcher and an explicit OpenCL backend fail
 * with its checkpoint saved. */
static relief_status inject_device_failure(void *ctx, relief_error *err)
{
    relief_complete_run *r = ctx;
    if (r->fail_calls++ < r->fail_after)
        return RELIEF_OK;
    return relief_fail(err, RELIEF_E_DEVICE, "launching the score kernel: CL_OUT_OF_RESOURCES "
                       "(injected by RELIEF_TEST_DEVICE_FAIL_AFTER=%zu)", r->fail_after);
}

/* The candidate scores a told hole's growth is expected to ask, for auto's
 * choice of a device (matcher.h): every target scores each candidate
 * centre's R rotations under the exhaustive search, and under the coherent
 * search at most the continuations, k + 1 per vertex of its window (about
 * 1 + 3 W (W + 1) on a regular triangulation). 0 (not known: auto asks
 * OpenCL as ever) for an untold completion, whose holes may be large. */
static double told_work(const relief_complete_run *r)
{
    const relief_params *p = &r->st.params;
    const double ns = r->d->ns, targets = (double)r->s->n_targets;
    double centres = ns, cont;
    if (!p->told_holes)
        return 0.0;
    if (relief_params_search(p, r->d->ns, r->d->rotations, r->s->n_targets) ==
        RELIEF_SEARCH_COHERENT) {
        cont = (p->search_k + 1.0) * (1.0 + 3.0 * p->window * (p->window + 1.0));
        centres = cont < ns ? cont : ns;
    }
    return targets * centres * r->d->rotations;
}

/* The matcher of a mono-scale growth over its match data; a told hole's,
 * over the samples around it. */
static relief_status make_matcher(relief_complete_run *r, relief_error *err)
{
    const relief_params *p = &r->st.params;
    const char *fail_env = getenv("RELIEF_TEST_DEVICE_FAIL_AFTER");
    relief_status st = relief_match_data_build_near(
        r->s, p->rotations, relief_grow_mu(p, r->capture->col != NULL),
        p->told_holes ? (size_t)relief_told_pool((double)r->s->n_targets) : SIZE_MAX,
        2 * p->window + 2, p->threads, &r->d, err);
    if (st == RELIEF_OK)
        st = relief_matcher_create(p->backend, p->device, p->threads, told_work(r), r->d, &r->m,
                                   r->choice, sizeof r->choice, &r->choice_reason, err);
    if (st != RELIEF_OK)
        return st;
    r->backend = r->m->backend;
    snprintf(r->device, sizeof r->device, "%s", r->m->device);
    if (fail_env && r->m->backend == RELIEF_BACKEND_OPENCL) {
        r->fail_after = strtoul(fail_env, NULL, 10);
        r->m->inject = inject_device_failure;
        r->m->inject_ctx = r;
    }
    return RELIEF_OK;
}

/* Where each level's growth starts in the call's progress: the levels'
 * shares of all the targets. */
static relief_status level_shares(relief_complete_run *r, relief_error *err)
{
    const int M = r->hier ? r->hier->levels : 1;
    double total = 0.0, at = 0.0;
    r->level_share = malloc((size_t)(M + 1) * sizeof *r->level_share);
    if (!r->level_share)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the progress levels");
    for (int k = 0; k < M; ++k)
        total += (double)(r->hier ? r->hier->level[k]->n_targets : r->s->n_targets);
    for (int k = 0; k < M; ++k) {
        r->level_share[k] = total > 0 ? at / total : (double)k / M;
        at += (double)(r->hier ? r->hier->level[k]->n_targets : r->s->n_targets);
    }
    r->level_share[M] = 1.0;
    return RELIEF_OK;
}

static relief_status prepare_growth(relief_complete_run *r, relief_error *err)
{
    relief_status st = check_growth_memory(r, err);
    if (r->rep)
        r->rep->memory_bytes = growth_bytes(r);
    if (st == RELIEF_OK && r->st.params.levels > 1) {
        double t0 = relief_seconds();
        st = relief_hierarchy_build(r->s, r->st.params.levels, &r->hier, err);
        r->hstats.build_seconds = relief_seconds() - t0;
    } else if (st == RELIEF_OK) {
        st = make_matcher(r, err);
    }
    if (st == RELIEF_OK)
        st = level_shares(r, err);
    /* The report folder shows the surface before growth, which the growth
     * changes in place. */
    if (st == RELIEF_OK && r->cp->report_dir)
        st = relief_mesh_copy(r->s->mesh, &r->before, err);
    return st;
}

/* ------------------------------------------------------------ the growth */

/* Each target grown: the call's fraction over every level, and the
 * caller's answer, a cancel, where the growth reads it. */
static void on_grow_progress(void *ctx, const relief_grow_progress *p)
{
    relief_complete_run *r = ctx;
    const int k = p->level < 0 ? 0 : p->level;
    const double lo = r->level_share[k], hi = r->level_share[k + 1];
    const double done = p->total ? (double)p->done / (double)p->total : 1.0;
    if (relief_progress_step(&r->progress, lo + done * (hi - lo)))
        r->cancel = 1;
}

static relief_status save_checkpoint(void *ctx, const relief_grow_state *g, relief_error *err)
{
    relief_complete_run *r = ctx;
    relief_status st = relief_checkpoint_write(r->cp->checkpoint, &r->key, g, err);
    r->saved |= st == RELIEF_OK;
    return st;
}

/* After a finished run its checkpoint described an unfinished one: it goes
 * when this call made it, never a file that was there before the call
 * (relief removes only what it can prove it wrote). */
static void drop_checkpoint(const relief_complete_run *r)
{
    if (r->cp->checkpoint && r->saved && !r->checkpoint_existed)
        unlink(r->cp->checkpoint);
}

static void note_resume(relief_complete_run *r, const relief_grow_state *g)
{
    if (!r->rep)
        return;
    r->rep->resumed = 1;
    r->rep->resumed_level = g->hier ? g->hier->level : 1;
    r->rep->resumed_done = g->stats.acceptances;
    r->rep->resumed_targets = g->stats.targets;
}

static relief_status grow(relief_complete_run *r, relief_error *err)
{
    relief_grow_options *go = &r->st.grow;
    relief_status st;
    go->progress = on_grow_progress;
    go->progress_ctx = r;
    go->cancel = &r->cancel;
    if (r->resume) {
        go->resume = relief_checkpoint_state(r->resume);
        note_resume(r, go->resume);
    }
    if (r->cp->checkpoint) {
        go->save = save_checkpoint;
        go->save_ctx = r;
        go->save_every = r->cp->checkpoint_every;
    }
    if (relief_progress_step(&r->progress, 0.0))
        return relief_fail(err, RELIEF_E_CANCELLED, "cancelled by the progress callback "
                           "before the growth");
    if (r->hier) {
        relief_hierarchy_options ho = relief_hierarchy_options_default();
        relief_hierarchy_stats hs;
        ho.backend = r->st.params.backend;
        ho.device = r->st.params.device;
        ho.threads = r->st.params.threads;
        st = relief_hierarchy_grow(r->hier, r->s, &r->st.params, go, &ho, &hs, &r->stats,
                                   &r->backend, r->device, sizeof r->device, r->choice,
                                   sizeof r->choice, err);
        hs.build_seconds = r->hstats.build_seconds;
        r->hstats = hs;
        r->choice_reason = hs.backend_reason;
        if (r->hstats.fallback[0])
            relief_complete_note(r, 1, "backend auto: %s", r->hstats.fallback);
    } else {
        st = relief_grow(r->s, r->d, r->m, &r->st.params, go, &r->stats, err);
        r->backend = r->m->backend;
        snprintf(r->device, sizeof r->device, "%s", r->m->device);
        if (r->m->fallback_note[0])
            relief_complete_note(r, 1, "backend auto: %s", r->m->fallback_note);
    }
    return st;
}

/* ------------------------------------------------------------ the report */

static void measure(relief_complete_run *r)
{
    relief_error merr = {0};
    if (!r->cp->measure)
        return;
    r->measured = relief_measure(r->s->mesh, NULL, &r->s->fit.prim, &r->meas, &merr) ==
                  RELIEF_OK;
    r->patterned = r->measured && relief_pattern_measure(r->s->mesh, &r->s->fit.prim, NULL,
                                                         &r->pat, &merr) == RELIEF_OK;
    if (!r->measured || !r->patterned)
        relief_complete_note(r, 1, "no %smeasures in the report: %s",
                             r->measured ? "pattern " : "", merr.message);
}

static void fill_counts(relief_complete_report *rep, const relief_complete_run *r)
{
    const relief_surface *s = r->s;
    rep->smooth_base = r->smooth_base;
    rep->fit = s->fit;
    rep->region = s->fill.region;
    rep->spacing = s->spacing;
    rep->captured = s->n_captured;
    rep->samples = s->n_samples;
    rep->targets = s->n_targets;
    rep->dropped = s->n_dropped;
    rep->folded_triangles = s->folds.triangles;
    rep->spikes = s->spikes.vertices;
    rep->holes = s->fill.holes;
    rep->rotations = r->st.params.rotations;
    rep->search = relief_params_search(&r->st.params, s->n_samples, r->st.params.rotations,
                                       s->n_targets);
}

static void fill_growth(relief_complete_report *rep, const relief_complete_run *r)
{
    const relief_grow_stats *g = &r->stats;
    rep->levels = r->st.params.levels;
    for (int k = 0; k < rep->levels && k < RELIEF_COMPLETE_MAX_LEVELS; ++k)
        rep->level_vertices[k] = r->hier ? relief_mesh_vertex_count(r->hier->level[k]->mesh)
                                         : relief_mesh_vertex_count(r->s->mesh);
    rep->search = (relief_search_mode)g->search;
    rep->acceptances = g->acceptances;
    rep->passes = g->passes;
    rep->rejections = g->rejections;
    rep->threshold_raises = g->threshold_raises;
    rep->candidates = g->candidates;
    rep->error_final = g->error_final;
    rep->seconds_growth = g->seconds + r->hstats.build_seconds;
    rep->seconds_match = r->m ? r->m->kernel_seconds : g->match_seconds;
}

static void fill_backend(relief_complete_report *rep, const relief_complete_run *r)
{
    rep->backend = r->backend;
    snprintf(rep->device, sizeof rep->device, "%s", r->device);
    snprintf(rep->backend_note, sizeof rep->backend_note, "%.1000s", r->choice);
    rep->backend_warning = r->choice_reason == RELIEF_REASON_DEVICE_FELL_BACK;
}

static relief_status finish_report(relief_complete_run *r, int smooth, relief_error *err)
{
    relief_complete_report *rep = r->rep;
    relief_status st = RELIEF_OK;
    if (!smooth)
        measure(r);
    fill_counts(rep, r);
    if (!smooth) {
        fill_growth(rep, r);
        fill_backend(rep, r);
    }
    rep->seconds_total = relief_seconds() - r->t0;
    rep->json = relief_complete_json(r, smooth);
    if (!rep->json)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot write the report");
    if (!smooth && r->cp->report_dir)
        st = relief_complete_stage_folder(r, &rep->folder, err);
    return st;
}

/* ------------------------------------------------------------- the calls */

static void run_free(relief_complete_run *r)
{
    relief_hierarchy_destroy(r->hier);
    relief_matcher_destroy(r->m);
    relief_match_data_destroy(r->d);
    relief_surface_destroy(r->s);
    relief_mesh_destroy(r->before);
    relief_checkpoint_destroy(r->resume);
    relief_complete_holes_free(r);
    relief_complete_crop_free(r);
    free(r->level_share);
}

static void run_init(relief_complete_run *r, const relief_mesh *capture,
                     const relief_complete_params *p, relief_complete_report *rep)
{
    memset(r, 0, sizeof *r);
    r->cp = p;
    r->capture = capture;
    r->rep = rep;
    r->t0 = relief_seconds();
    r->backend = RELIEF_BACKEND_SCALAR;
    relief_complete_stages_make(p, &r->st);
    relief_progress_init(&r->progress, p->run.progress, p->run.progress_ctx);
}

/* The surface's mesh, taken from it: the call's output. Told holes on the
 * smoothed base are sewn into the capture as it was given (crop.c), so it
 * comes back verbatim, even its vertices in no triangle, which the base
 * leaves out. */
static relief_status take_mesh(relief_complete_run *r, relief_mesh **out, relief_error *err)
{
    if (r->crop || (r->smooth_base && (r->cp->has_hole_ball || r->cp->hole_labels)))
        return relief_complete_uncrop(r, out, err);
    *out = r->s->mesh;
    r->s->mesh = NULL;
    return RELIEF_OK;
}

relief_status relief_complete(const relief_mesh *capture, const relief_complete_params *p,
                              relief_mesh **out, relief_complete_report *rep,
                              relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    relief_complete_report own;
    relief_complete_run r;
    relief_status st = check_args(capture, p, out, rep, err);
    int existed = 0;
    /* A file named as the checkpoint is replaced only when relief wrote
     * it: refused now, before the work, when it is anything else. */
    if (st == RELIEF_OK && p->checkpoint)
        st = relief_checkpoint_check_path(p->checkpoint, &existed, err);
    if (st != RELIEF_OK)
        return st;
    memset(&own, 0, sizeof own);
    run_init(&r, capture, p, &own);
    r.checkpoint_existed = existed;
    st = relief_complete_holes(&r, err);
    if (st == RELIEF_OK)
        st = read_resume(&r, err);
    if (st == RELIEF_OK)
        st = build_base(&r, err);
    if (st == RELIEF_OK)
        st = prepare_growth(&r, err);
    if (st == RELIEF_OK)
        st = grow(&r, err);
    if (st == RELIEF_OK)
        st = relief_complete_untangle(&r, err);
    if (st == RELIEF_OK && relief_progress_step(&r.progress, 1.0))
        st = relief_fail(err, RELIEF_E_CANCELLED, "cancelled by the progress callback after "
                         "the growth");
    if (st == RELIEF_OK && rep)
        st = finish_report(&r, 0, err);
    if (st == RELIEF_OK)
        st = take_mesh(&r, out, err);
    if (st == RELIEF_OK)
        drop_checkpoint(&r);
    if (st == RELIEF_OK && rep)
        *rep = own;
    else
        relief_complete_report_free(&own);
    run_free(&r);
    return st;
}

relief_status relief_smooth(const relief_mesh *capture, const relief_complete_params *p,
                            relief_mesh **out, relief_complete_report *rep, relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    relief_complete_report own;
    relief_complete_run r;
    relief_status st = check_args(capture, p, out, rep, err);
    if (st == RELIEF_OK && p->base == RELIEF_BASE_SMOOTH)
        st = relief_fail(err, RELIEF_E_USAGE, "base smooth: relief_smooth lays the targets on "
                         "a primitive (base auto or primitive)");
    if (st != RELIEF_OK)
        return st;
    memset(&own, 0, sizeof own);
    run_init(&r, capture, p, &own);
    st = relief_complete_holes(&r, err);
    if (st == RELIEF_OK && relief_progress_step(&r.progress, 0.0))
        st = relief_fail(err, RELIEF_E_CANCELLED, "cancelled by the progress callback");
    if (st == RELIEF_OK)
        st = relief_surface_build(capture, &r.st.params, &r.st.smooth, &r.s, err);
    if (st == RELIEF_E_RANGE && r.has_holes && err->reason == RELIEF_REASON_HOLES_LEFT_OPEN)
        st = relief_holes_none_filled(&r.holes, err);
    if (st == RELIEF_OK) {
        own.seconds_smooth = relief_seconds() - r.t0;
        note_surface(&r);
        relief_complete_note_open_rims(&r);
        st = relief_complete_holes_closed(&r, err);
    }
    if (st == RELIEF_OK) {
        if (relief_progress_step(&r.progress, 1.0))
            st = relief_fail(err, RELIEF_E_CANCELLED, "cancelled by the progress callback");
    }
    if (st == RELIEF_OK && rep)
        st = finish_report(&r, 1, err);
    if (st == RELIEF_OK)
        st = take_mesh(&r, out, err);
    if (st == RELIEF_OK && rep)
        *rep = own;
    else
        relief_complete_report_free(&own);
    run_free(&r);
    return st;
}
