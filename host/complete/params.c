/* relief_complete_params: defaults, checks, and what the stages take
 * (complete/engine.h). */
#include "complete/engine.h"

#include <math.h>
#include <string.h>

#include "base/error.h"

relief_complete_params relief_complete_params_default(void)
{
    relief_complete_params p;
    const relief_params g = relief_params_default();
    const relief_smooth_options o = relief_smooth_options_default();
    memset(&p, 0, sizeof p);
    p.base = RELIEF_BASE_AUTO;
    p.fit = g.fit;
    p.fill = o.fill;
    p.oversample = g.oversample;
    p.oversample_scheme = (relief_oversample_scheme)o.oversample_scheme;
    p.spacing = g.spacing;
    p.n_extent = 0;
    p.frames = o.frames;
    p.accept_poor_fit = o.accept_poor_fit;
    p.keep_spikes = 0;
    p.max_growth = o.max_growth;
    p.window = g.window;
    p.rotations = g.rotations;
    p.error = g.error;
    p.mu = g.mu;
    p.seed = g.seed;
    p.coherence = g.coherence;
    p.search = g.search;
    p.search_k = g.search_k;
    p.levels = g.levels;
    p.bootstrap = 0;
    p.prune = 1;
    p.checkpoint = NULL;
    p.checkpoint_every = 300.0;
    p.resume = NULL;
    p.report_dir = NULL;
    p.measure = 1;
    p.run = relief_run_options_default();
    return p;
}

/* The enumerations relief_params does not check; each refusal names its
 * field (err->param), as do validate_own's and relief_params_validate's. */
static relief_status validate_choices(const relief_complete_params *p, relief_error *err)
{
    if (p->base < RELIEF_BASE_AUTO || p->base > RELIEF_BASE_SMOOTH)
        return relief_fail_param(err, RELIEF_E_RANGE, "base", "base %d is not one of auto, "
                                 "primitive, smooth", (int)p->base);
    if (p->fill < RELIEF_FILL_AUTO || p->fill > RELIEF_FILL_WHOLE)
        return relief_fail_param(err, RELIEF_E_RANGE, "fill", "fill %d is not one of auto, "
                                 "holes, whole", (int)p->fill);
    if (p->frames < RELIEF_FRAMES_PAPER || p->frames > RELIEF_FRAMES_PRIMITIVE)
        return relief_fail_param(err, RELIEF_E_RANGE, "frames", "frames %d is not one of "
                                 "paper, primitive", (int)p->frames);
    if (p->oversample_scheme < RELIEF_OVERSAMPLE_MIDPOINT ||
        p->oversample_scheme > RELIEF_OVERSAMPLE_BUTTERFLY)
        return relief_fail_param(err, RELIEF_E_RANGE, "oversample_scheme", "oversample_scheme "
                                 "%d is not one of midpoint, butterfly",
                                 (int)p->oversample_scheme);
    return RELIEF_OK;
}

/* The other fields relief_params does not check, and what cannot go
 * together. */
static relief_status validate_own(const relief_complete_params *p, relief_error *err)
{
    const int flags[] = {p->accept_poor_fit, p->keep_spikes, p->bootstrap, p->prune,
                         p->measure};
    const char *names[] = {"accept_poor_fit", "keep_spikes", "bootstrap", "prune", "measure"};
    if (p->n_extent != 0 && p->n_extent != 2 && p->n_extent != 4)
        return relief_fail_param(err, RELIEF_E_RANGE, "extent", "n_extent %d out of range: "
                                 "expected 0 (none), 2 (cylinder z0,z1) or 4 (plane "
                                 "u0,v0,u1,v1)", p->n_extent);
    if (!(p->max_growth >= 0.0 && isfinite(p->max_growth)))
        return relief_fail_param(err, RELIEF_E_RANGE, "max_growth", "max_growth %g out of "
                                 "range: expected targets per captured vertex >= 0 (0: no "
                                 "limit)", p->max_growth);
    if (p->has_hole_ball && relief_hole_ball_check("hole_ball", p->hole_ball, err) != RELIEF_OK)
        return RELIEF_E_RANGE;
    if (p->has_hole_ball && p->hole_labels)
        return relief_fail(err, RELIEF_E_USAGE, "hole_ball and hole_labels: give one");
    if ((p->has_hole_ball || p->hole_labels) && p->fill == RELIEF_FILL_WHOLE)
        return relief_fail(err, RELIEF_E_USAGE, "a hole selection (hole_ball, hole_labels) "
                           "fills holes only: not with fill whole");
    if (!(p->max_hole >= 0.0 && p->max_hole <= 1e30))
        return relief_fail_param(err, RELIEF_E_RANGE, "max_hole", "max_hole %g out of range: "
                                 "expected 0..1e30 (0: a quarter of the bounding box's "
                                 "diagonal)", p->max_hole);
    if (!(p->checkpoint_every >= 0.0 && isfinite(p->checkpoint_every)))
        return relief_fail_param(err, RELIEF_E_RANGE, "checkpoint_every", "checkpoint_every "
                                 "%g out of range: expected seconds >= 0 (0: only on cancel "
                                 "or failure)", p->checkpoint_every);
    for (int i = 0; i < 5; ++i)
        if (flags[i] != 0 && flags[i] != 1)
            return relief_fail_param(err, RELIEF_E_RANGE, names[i], "%s %d out of range: "
                                     "expected 0 or 1", names[i], flags[i]);
    if (p->base == RELIEF_BASE_SMOOTH && (p->fit != RELIEF_FIT_AUTO || p->n_extent))
        return relief_fail(err, RELIEF_E_USAGE, "base smooth has no primitive: fit and extent "
                           "do not apply");
    return RELIEF_OK;
}

relief_status relief_complete_params_validate(const relief_complete_params *p,
                                              relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    relief_complete_stages st;
    relief_status s;
    if (!p)
        return relief_fail(err, RELIEF_E_USAGE, "params: NULL");
    s = relief_run_options_validate(&p->run, err);
    if (s == RELIEF_OK)
        s = validate_choices(p, err);
    if (s == RELIEF_OK)
        s = validate_own(p, err);
    if (s != RELIEF_OK)
        return s;
    relief_complete_stages_make(p, &st);
    return relief_params_validate(&st.params, err);
}

void relief_complete_stages_make(const relief_complete_params *p, relief_complete_stages *out)
{
    relief_params *g = &out->params;
    relief_smooth_options *o = &out->smooth;
    relief_grow_options *go = &out->grow;
    *g = relief_params_default();
    g->fit = p->fit;
    g->window = p->window;
    g->rotations = p->rotations;
    g->error = p->error;
    g->mu = p->mu;
    g->seed = p->seed;
    g->coherence = p->coherence;
    g->search = p->search;
    g->told_holes = p->has_hole_ball || p->hole_labels;
    g->search_k = p->search_k;
    g->levels = p->levels;
    g->backend = p->run.backend;
    g->device = p->run.device;
    g->oversample = p->oversample;
    g->spacing = p->spacing;
    g->has_extent = p->n_extent > 0;
    g->n_extent = p->n_extent;
    memcpy(g->extent, p->extent, sizeof g->extent);
    g->max_memory = p->run.max_memory;
    g->threads = p->run.threads;
    *o = relief_smooth_options_default();
    o->frames = p->frames;
    o->oversample_scheme = (int)p->oversample_scheme;
    o->accept_poor_fit = p->accept_poor_fit;
    o->spike_k = p->keep_spikes ? 0.0 : o->spike_k;
    o->fill = p->fill;
    o->max_growth = p->max_growth;
    *go = relief_grow_options_default();
    go->bootstrap = p->bootstrap;
    go->prune = p->prune;
}
