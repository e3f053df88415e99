/* The mesh completion engine behind relief/complete.h: relief_complete and
 * relief_smooth as stages (the base, the growth's data and matcher, the
 * growth, the report), and what the stages share. complete.c orchestrates,
 * params.c converts the public parameters, report.c writes the JSON report
 * and stages the report folder. */
#ifndef RELIEF_HOST_COMPLETE_ENGINE_H
#define RELIEF_HOST_COMPLETE_ENGINE_H

#include <signal.h>

#include "relief/relief.h"
#include "base/output.h"
#include "base/params.h"
#include "base/progress.h"
#include "grow/checkpoint.h"
#include "grow/grow.h"
#include "grow/hierarchy.h"
#include "match/matcher.h"
#include "mesh/holes.h"
#include "report/measures.h"
#include "report/pattern.h"
#include "smooth/surface.h"

/* The public parameters as the stages take them. */
typedef struct relief_complete_stages {
    relief_params params;
    relief_smooth_options smooth;
    relief_grow_options grow;
} relief_complete_stages;

/* Fill `out` from `p` (not checked: relief_complete_params_validate). */
void relief_complete_stages_make(const relief_complete_params *p, relief_complete_stages *out);

/* One relief_complete or relief_smooth call in progress. */
typedef struct relief_complete_run {
    const relief_complete_params *cp;
    const relief_mesh *capture;
    relief_complete_stages st;  /* st.params.rotations resolved once the base is known */
    relief_surface *s;          /* the surface grown on */
    int smooth_base;            /* 1: on the capture's smoothed base */
    relief_hierarchy *hier;     /* levels > 1 */
    relief_hierarchy_stats hstats;
    relief_match_data *d;       /* mono-scale */
    relief_matcher *m;
    relief_grow_stats stats;
    relief_checkpoint_key key;
    relief_checkpoint *resume;  /* cp->resume read */
    int saved;                  /* 1 once this call wrote cp->checkpoint */
    int checkpoint_existed;     /* 1: cp->checkpoint was there before the
                                   call (a relief checkpoint): never removed */
    relief_mesh *before;        /* the surface before growth (report folder) */
    relief_backend backend;     /* what scored */
    char device[256];
    char choice[RELIEF_ERROR_MESSAGE_MAX + 320]; /* why auto chose it */
    relief_reason choice_reason; /* RELIEF_REASON_DEVICE_FELL_BACK: a warning */
    relief_progress progress;
    double *level_share;        /* levels + 1: where each level's growth starts */
    volatile sig_atomic_t cancel; /* set when the progress callback asks */
    size_t fail_after, fail_calls; /* RELIEF_TEST_DEVICE_FAIL_AFTER */
    int measured, patterned;
    relief_measures meas;
    relief_pattern pat;
    double t0;
    relief_complete_report *rep; /* notes go here as the stages find them */
    /* the hole model over a primitive (hole_model.c) */
    int has_holes;              /* 1 once the capture's rims were judged */
    relief_hole_info holes;     /* every boundary loop and its fate */
    uint32_t *rim;              /* capture->nv: 0, or the filled hole's label */
    uint32_t *rim_index;        /* per label - 1: its index in holes.rims */
    struct relief_rim_arc *arcs; /* the notches filled in part (mesh/hole_fill.h) */
    size_t n_arcs;
    relief_mesh *crop;          /* the capture about the told holes, the
                                   smoothed base's (crop.c), or NULL */
    uint32_t *crop_to;          /* crop->nv: each crop vertex's in capture */
    int closed_checked;         /* relief_complete_holes_closed ran: */
    size_t open_loops, open_edges; /* the surface's boundary loops where holes were
                                      filled, their vertices */
} relief_complete_run;

/* Over a primitive (not base smooth), on a capture with triangles: judge
 * the capture's boundary loops by max_hole and hole_ball (mesh/holes.h)
 * and make them the filter of the regions a fill of the holes completes
 * (smooth/surface.h); hole_ball turns fill auto into holes. */
relief_status relief_complete_holes(relief_complete_run *r, relief_error *err);
void relief_complete_holes_free(relief_complete_run *r);

/* Told holes closed whole (no notch) in a capture much larger than they
 * need: r->crop, the capture about them (their rims' vertices and rings
 * of neighbours enough for the smoothing and the pool of samples), on
 * which the smoothed base is built; *crop_select: `select` (capture->nv
 * flags, or NULL) on the crop, the caller's to free. Nothing is cropped
 * (r->crop NULL) for a notch, when the crop would hold 3/4 of the capture
 * or more, or when the selection reaches its border. RELIEF_E_NOMEM. */
relief_status relief_complete_crop(relief_complete_run *r, const uint8_t *select,
                                   uint8_t **crop_select, relief_error *err);
void relief_complete_crop_free(relief_complete_run *r);

/* The whole capture completed: r->capture, verbatim, with the new
 * vertices and faces of the surface completed on the crop (r->crop) or on
 * the capture itself (r->s->mesh) sewn in, and any of its faces the
 * completion replaced gone. RELIEF_E_MESH when the surface's samples are
 * not the capture's vertices in order; RELIEF_E_NOMEM. */
relief_status relief_complete_uncrop(const relief_complete_run *r, relief_mesh **out,
                                     relief_error *err);

/* After the growth: the targets of crossing triangles drawn back toward
 * the base (untangle.c); a remark counts them. RELIEF_E_NOMEM. */
relief_status relief_complete_untangle(relief_complete_run *r, relief_error *err);

/* A note naming the widest rims the hole model left open by its rule (an
 * outer border, an opening wider than max_hole) and what would fill each. */
void relief_complete_note_open_rims(relief_complete_run *r);

/* Once the surface is built over a primitive with only holes filled: the
 * loops of its boundary that no opening the capture keeps by design (a
 * rim not filled: its outer border, a mouth, a notch) explains, most of
 * their vertices over 2 spacings from such a rim, counted (open_loops,
 * open_edges) and said in a warning: a hole relief filled is not closed. */
relief_status relief_complete_holes_closed(relief_complete_run *r, relief_error *err);

/* A note for the report: a warning, or a plain remark. */
void relief_complete_note(relief_complete_run *r, int warning, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* The report's JSON (`relief complete --report`) of a finished run; NULL
 * when out of memory. smooth: relief_smooth's shorter report. */
char *relief_complete_json(const relief_complete_run *r, int smooth);

/* Stage the report folder of a finished run beside cp->report_dir. */
relief_status relief_complete_stage_folder(const relief_complete_run *r,
                                           relief_report_folder **out, relief_error *err);

/* The staged folder of `folder`, for a commit with other outputs
 * (base/output.h); `folder` is freed. */
relief_staged_folder *relief_report_folder_release(relief_report_folder *folder);

#endif
