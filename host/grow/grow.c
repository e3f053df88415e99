/* Non-parametric growth (paper 000 appendix A, as DESIGN.md reads it):
 *
 *   until every target is textured:
 *     L = untextured targets with a textured 1-ring neighbour, by decreasing
 *         number of textured vertices in their window (ties: vertex id)
 *     for t in L: score every (sample, rotation); best set = SSD within 10 %
 *         of the minimum; draw one uniformly (MT19937); accept it if its SSD
 *         is below e: copy D (re-expressed in t's frame) and colour;
 *         otherwise shrink t's window by one (not below 1)
 *     a pass with no acceptance raises e by 10 %
 *
 * with one addition, coherence (params->coherence = kappa > 0, see
 * coherent_best): before the draw, the candidates that continue the source
 * patches of t's textured neighbours are scored, and the best of them is
 * taken instead of the draw when its SSD is at most kappa x the minimum.
 * The paper's draw alone copies each target from anywhere: a ridge's shape
 * at the capture's edge is then repeated across the whole completion
 * (chevrons, README), and smooth places win over rough ones. Copying
 * patches keeps the capture's own arrangement (Ashikhmin 2001).
 */
#include "grow/grow.h"
#include "base/params.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/clock.h"
#include "base/error.h"
#include "base/rng.h"
#include "base/vec3.h"
#include "match/matcher_scalar.h"
#include "match/search.h"
#include "mesh/mesh.h"
#include "smooth/surface_check.h"

#define RM_REAL float
#define RM_WITH_SCORING
#include "kernels/relief_math.h"

#define MAX_RAISES 400 /* 1.1^400 ~ 4e16: e has stopped meaning anything */

relief_grow_options relief_grow_options_default(void)
{
    relief_grow_options o;
    o.prune = 1;
    o.bootstrap = 0;
    o.progress = NULL;
    o.progress_ctx = NULL;
    o.level = 0;
    o.levels = 1;
    o.pyramid_start = NULL;
    o.pyramid_items = NULL;
    o.matched = NULL;
    o.cancel = NULL;
    o.save = NULL;
    o.save_ctx = NULL;
    o.save_every = 0.0;
    o.resume = NULL;
    o.cancel_after = 0;
    return o;
}

double relief_grow_mu(const relief_params *params, int has_colour)
{
    if (params->mu >= 0.0)
        return has_colour ? params->mu : 1.0;
    return has_colour ? 0.5 : 1.0;
}

/* Breadth-first search state reused across targets. */
typedef struct walker {
    uint32_t *stamp, *depth, *queue;
    uint32_t now;
} walker;

/* Textured vertices within `hops` edges of t (t excluded) into out[],
 * in breadth-first order; returns their count. */
static size_t window(walker *w, const relief_adjacency *adj, const uint8_t *textured, uint32_t t,
                     int hops, uint32_t *out)
{
    size_t head = 0, tail = 0, n = 0;
    ++w->now;
    w->stamp[t] = w->now;
    w->depth[t] = 0;
    w->queue[tail++] = t;
    while (head < tail) {
        uint32_t v = w->queue[head++];
        if (v != t && textured[v])
            out[n++] = v;
        if ((int)w->depth[v] == hops)
            continue;
        for (uint32_t i = adj->start[v]; i < adj->start[v + 1]; ++i) {
            uint32_t u = adj->nbr[i];
            if (w->stamp[u] != w->now) {
                w->stamp[u] = w->now;
                w->depth[u] = w->depth[v] + 1;
                w->queue[tail++] = u;
            }
        }
    }
    return n;
}

typedef struct ranked {
    uint32_t v;
    uint32_t key; /* textured vertices in the window */
} ranked;

static int ranked_cmp(const void *x, const void *y)
{
    const ranked *a = x, *b = y;
    if (a->key != b->key)
        return a->key > b->key ? -1 : 1;
    return (a->v > b->v) - (a->v < b->v);
}

typedef struct neighbour {
    uint32_t v;
    double g;
} neighbour;

static int neighbour_cmp(const void *x, const void *y)
{
    const neighbour *a = x, *b = y;
    if (a->g != b->g)
        return a->g > b->g ? -1 : 1;
    return (a->v > b->v) - (a->v < b->v);
}

/* ------------------------------------------------------- neighbourhoods */

struct relief_query_builder {
    const relief_surface *s;
    const relief_match_data *d;
    relief_adjacency adj;
    walker w;
    uint32_t *nb;   /* nv: a window's textured vertices */
    neighbour *nbs; /* nv: the same with their weights */
    float *qp, *q, *g, *qcol;
};

void relief_query_builder_destroy(relief_query_builder *b)
{
    if (!b)
        return;
    free(b->qcol);
    free(b->g);
    free(b->q);
    free(b->qp);
    free(b->nbs);
    free(b->nb);
    free(b->w.queue);
    free(b->w.depth);
    free(b->w.stamp);
    relief_adjacency_free(&b->adj);
    free(b);
}

relief_status relief_query_builder_create(const relief_surface *s, const relief_match_data *d,
                                          relief_query_builder **out, relief_error *err)
{
    const size_t nv = s->mesh->nv;
    relief_query_builder *b = calloc(1, sizeof *b);
    relief_status st;
    if (!b)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a query builder");
    b->s = s;
    b->d = d;
    st = relief_mesh_adjacency(s->mesh, &b->adj, err);
    if (st != RELIEF_OK) {
        relief_query_builder_destroy(b);
        return st;
    }
    b->w.stamp = calloc(nv, sizeof *b->w.stamp);
    b->w.depth = malloc(nv * sizeof *b->w.depth);
    b->w.queue = malloc(nv * sizeof *b->w.queue);
    b->nb = malloc(nv * sizeof *b->nb);
    b->nbs = malloc(nv * sizeof *b->nbs);
    b->qp = malloc(nv * 3 * sizeof *b->qp);
    b->q = malloc(nv * 3 * sizeof *b->q);
    b->g = malloc(nv * sizeof *b->g);
    b->qcol = malloc(nv * 3 * sizeof *b->qcol);
    if (!b->w.stamp || !b->w.depth || !b->w.queue || !b->nb || !b->nbs || !b->qp || !b->q ||
        !b->g || !b->qcol) {
        relief_query_builder_destroy(b);
        return relief_fail(err, RELIEF_E_NOMEM,
                           "cannot allocate neighbourhood state for %zu vertices", nv);
    }
    *out = b;
    return RELIEF_OK;
}

size_t relief_query_count(relief_query_builder *b, const uint8_t *textured, uint32_t t,
                          int hops)
{
    return window(&b->w, &b->adj, textured, t, hops, b->nb);
}

int relief_query_has_textured_neighbour(const relief_query_builder *b,
                                        const uint8_t *textured, uint32_t t)
{
    for (uint32_t i = b->adj.start[t]; i < b->adj.start[t + 1]; ++i)
        if (textured[b->adj.nbr[i]])
            return 1;
    return 0;
}

void relief_query_build(relief_query_builder *b, const uint8_t *textured, uint32_t t, int hops,
                        relief_match_query *query)
{
    const relief_surface *s = b->s;
    const double *tp = s->proj + 3 * (size_t)t, *rt = s->frame + 9 * (size_t)t;
    const double *pos = s->mesh->pos;
    const double reach = hops * s->spacing;
    size_t n = window(&b->w, &b->adj, textured, t, hops, b->nb);
    double wsum = 0.0;

    /* The neighbourhood in t's frame, heaviest first. */
    for (size_t i = 0; i < n; ++i) {
        const double *vp = s->proj + 3 * (size_t)b->nb[i];
        double dp[3] = {vp[0] - tp[0], vp[1] - tp[1], vp[2] - tp[2]};
        double dd = sqrt(dp[0] * dp[0] + dp[1] * dp[1] + dp[2] * dp[2]) / reach;
        b->nbs[i].v = b->nb[i];
        b->nbs[i].g = exp(-0.5 * dd * dd);
    }
    qsort(b->nbs, n, sizeof *b->nbs, neighbour_cmp);
    for (size_t i = 0; i < n; ++i) {
        const uint32_t v = b->nbs[i].v;
        const double *vp = s->proj + 3 * (size_t)v, *vr = pos + 3 * (size_t)v;
        for (int r = 0; r < 3; ++r) {
            const double *axis = rt + 3 * r;
            b->qp[3 * i + r] = (float)(axis[0] * (vp[0] - tp[0]) + axis[1] * (vp[1] - tp[1]) +
                                       axis[2] * (vp[2] - tp[2]));
            b->q[3 * i + r] = (float)(axis[0] * (vr[0] - tp[0]) + axis[1] * (vr[1] - tp[1]) +
                                      axis[2] * (vr[2] - tp[2]));
            b->qcol[3 * i + r] = b->d->col[3 * (size_t)v + r];
        }
        b->g[i] = (float)b->nbs[i].g;
        wsum += (double)b->g[i];
    }
    query->n = (uint32_t)n;
    query->qp = b->qp;
    query->q = b->q;
    query->g = b->g;
    query->qcol = b->qcol;
    query->inv_wsum = (float)(1.0 / wsum);
    query->cutoff = FLT_MAX;
    query->running = 0;
    query->subset = NULL;
    query->n_subset = 0;
}

/* ------------------------------------------------------ a growth's state */

/* What one growth works on, what lasts over its passes, and the pass under
 * way: the stages below share it rather than a dozen arguments each. */
typedef struct grow_run {
    relief_surface *s;
    relief_match_data *d;
    relief_matcher *m;
    const relief_params *params;
    const relief_grow_options *opts;
    relief_grow_stats *stats;
    relief_query_builder *qb;
    relief_search *search; /* NULL unless the search is coherent */
    uint8_t *textured;     /* nv: 1 once a vertex has its displacement */
    int *win;              /* nv: each target's window, in hops */
    uint32_t *src;         /* nv: the candidate a target copied, UINT32_MAX if none */
    ranked *list;          /* n_targets: the pass's boundary list */
    float *ssd;            /* candidates: the last scoring's SSDs */
    uint8_t *flag;         /* candidates: and their RM_* flags */
    uint32_t *best;        /* candidates: those within 10 % of the minimum */
    relief_rng rng;
    size_t remaining, run_acceptances;
    double e, t0, last_save;
    /* The pass under way: its list's length and what it has seen so far. */
    size_t nl, accepted, any_valid, all_min_window;
} grow_run;

/* ------------------------------------------------ checkpoint and resume */

/* Hand the growth's state to opts->save; list[next] is the next target. */
static relief_status save_state(const grow_run *g, size_t next, relief_error *err)
{
    const relief_surface *s = g->s;
    const size_t ns = s->n_samples, nl = g->nl;
    relief_grow_state r;
    relief_status st;
    uint32_t *ids = malloc((nl + 1) * sizeof *ids);
    if (!ids)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a checkpoint's list");
    for (size_t i = 0; i < nl; ++i)
        ids[i] = g->list[i].v;
    r.nv = s->mesh->nv;
    r.n_samples = ns;
    r.textured = g->textured + ns;
    r.window = g->win + ns;
    r.disp = s->disp + 3 * ns;
    r.colour = g->d->col + 3 * ns;
    r.mesh_colour = s->mesh->col ? s->mesh->col + 3 * ns : NULL;
    r.n_list = nl;
    r.list = ids;
    r.next = next;
    r.pass_accepted = g->accepted;
    r.pass_any_valid = g->any_valid != 0;
    r.pass_all_min_window = g->all_min_window != 0;
    r.error = g->e;
    r.rng = g->rng;
    r.stats = *g->stats;
    r.source = g->src + ns;
    r.matched = g->opts->matched ? g->opts->matched + ns : NULL;
    r.hier = NULL;
    st = g->opts->save(g->opts->save_ctx, &r, err);
    free(ids);
    return st;
}

/* The figures a checkpoint (and the caller) sees: the time, the matcher's
 * share of it and the threshold, as of now. */
static void stats_now(const grow_run *g)
{
    g->stats->seconds = relief_seconds() - g->t0;
    g->stats->match_seconds = g->m->kernel_seconds;
    g->stats->error_final = g->e;
}

/* Put a saved growth back on the surface, the match data and the matcher;
 * g->remaining drops by the targets it had textured. */
static relief_status restore_state(const relief_grow_state *r, grow_run *g, relief_error *err)
{
    relief_surface *s = g->s;
    relief_match_data *d = g->d;
    relief_mesh *mesh = s->mesh;
    if (r->nv != mesh->nv || r->n_samples != s->n_samples)
        return relief_fail(err, RELIEF_E_USAGE,
                           "the saved growth is of a surface with %zu vertices (%zu samples); "
                           "this one has %zu (%zu)",
                           r->nv, r->n_samples, mesh->nv, s->n_samples);
    if (!r->mesh_colour != !mesh->col)
        return relief_fail(err, RELIEF_E_USAGE, "the saved growth %s colour; this surface %s",
                           r->mesh_colour ? "has" : "has no", mesh->col ? "has" : "has none");
    for (size_t i = 0; i < s->n_targets; ++i) {
        const size_t t = s->n_samples + i;
        relief_status st;
        g->win[t] = r->window[i];
        g->src[t] = r->source[i];
        if (!r->textured[i])
            continue;
        if (g->src[t] / (uint32_t)d->rotations >= d->ns)
            return relief_fail(err, RELIEF_E_USAGE, "the saved growth's target %zu copied "
                               "candidate %u; this surface has %u samples x %d rotations",
                               t, g->src[t], d->ns, d->rotations);
        for (int k = 0; k < 3; ++k) {
            const double dk = r->disp[3 * i + k], tp = s->proj[3 * t + k];
            s->disp[3 * t + k] = dk;
            mesh->pos[3 * t + k] = tp + dk; /* as the growth computes it */
            d->pos[3 * t + k] = (float)(tp + dk);
            d->col[3 * t + k] = r->colour[3 * i + k];
            if (mesh->col)
                mesh->col[3 * t + k] = r->mesh_colour[3 * i + k];
        }
        g->textured[t] = 1;
        if (g->opts->bootstrap)
            d->matchable[t] = 1;
        st = relief_matcher_update(g->m, d, (uint32_t)t, err);
        if (st != RELIEF_OK)
            return st;
        --g->remaining;
    }
    return RELIEF_OK;
}

/* ------------------------------------------------------------ coherence */

/* The coherent candidates of target t (Ashikhmin 2001): for each textured
 * neighbour n in t's window that copied sample s_n at rotation r_n
 * (src[n] = s_n x R + r_n), the sample lying where t would be if the patch
 * around s_n continued past n, x = s_n' + R_s Rz(theta_n) (R_n^T (t' - n')),
 * at rotation r_n; its closest vertex, when that is a sample. Each distinct
 * candidate is scored in full by the scalar reference
 * (relief_score_host_one), on the host, so every backend takes the same
 * one. The lowest SSD (ties: the
 * lower candidate index) goes to *ssd_out, its sample and rotation to
 * *si_out and *r_out. Returns 0 when no coherent candidate is valid. */
static int coherent_best(const relief_surface *s, const relief_match_data *d,
                         const relief_query_builder *qb, const relief_match_query *q,
                         const uint32_t *src, uint32_t t, float *ssd_out, uint32_t *si_out,
                         int *r_out)
{
    enum { MAX_SEEN = 64 };
    uint32_t seen[MAX_SEEN];
    size_t nseen = 0;
    int found = 0;
    const double *tp = s->proj + 3 * (size_t)t;
    const uint32_t R = (uint32_t)d->rotations;
    for (uint32_t i = 0; i < q->n; ++i) {
        const uint32_t nv = qb->nbs[i].v, c = src[nv];
        const double *np = s->proj + 3 * (size_t)nv, *nf = s->frame + 9 * (size_t)nv;
        uint32_t r, v2, cand;
        float o[3], ssd;
        size_t k;
        if (c == UINT32_MAX)
            continue;
        r = c % R;
        for (int j = 0; j < 3; ++j)
            o[j] = (float)(nf[3 * j] * (tp[0] - np[0]) + nf[3 * j + 1] * (tp[1] - np[1]) +
                           nf[3 * j + 2] * (tp[2] - np[2]));
        v2 = relief_match_sample_of(d, relief_continue_patch(d, o, c / R, r));
        if (v2 == UINT32_MAX) /* no candidate centre */
            continue;
        cand = v2 * R + r;
        for (k = 0; k < nseen && seen[k] != cand; ++k)
            ;
        if (k < nseen)
            continue;
        if (nseen < MAX_SEEN)
            seen[nseen++] = cand;
        if (relief_score_host_one(d, q, v2, (int)r, FLT_MAX, &ssd) != RM_VALID)
            continue;
        if (!found || ssd < *ssd_out ||
            (ssd == *ssd_out && cand < *si_out * R + (uint32_t)*r_out)) {
            *ssd_out = ssd;
            *si_out = v2;
            *r_out = (int)r;
            found = 1;
        }
    }
    return found;
}

/* ------------------------------------------------------------ the growth */

/* The growth's arrays, every vertex's window at its start, and the samples
 * textured. */
static relief_status grow_alloc(grow_run *g, relief_error *err)
{
    const relief_surface *s = g->s;
    const size_t nv = s->mesh->nv, ncand_max = (size_t)g->d->ns * (size_t)g->d->rotations;
    relief_status st = relief_query_builder_create(s, g->d, &g->qb, err);
    if (st != RELIEF_OK)
        return st;
    g->textured = calloc(nv, 1);
    g->win = malloc(nv * sizeof *g->win);
    g->list = malloc((s->n_targets + 1) * sizeof *g->list);
    g->ssd = malloc((ncand_max + 1) * sizeof *g->ssd);
    g->flag = malloc(ncand_max + 1);
    g->best = malloc((ncand_max + 1) * sizeof *g->best);
    g->src = malloc(nv * sizeof *g->src);
    if (!g->textured || !g->win || !g->list || !g->ssd || !g->flag || !g->best || !g->src)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the growth state for %zu "
                           "vertices and %zu candidates", nv, ncand_max);
    for (size_t v = 0; v < nv; ++v) {
        g->textured[v] = v < s->n_samples;
        g->win[v] = g->params->window;
        g->src[v] = UINT32_MAX;
    }
    return RELIEF_OK;
}

/* Which samples a target scores first: a finer level of a hierarchy has
 * its pyramid boxes; otherwise the parameters choose, and a coherent
 * search builds its index here, before the growth's clock starts. */
static relief_status grow_choose_search(grow_run *g, relief_error *err)
{
    const relief_params *params = g->params;
    relief_status st;
    g->stats->search = g->opts->pyramid_start ? RELIEF_SEARCH_EXHAUSTIVE /* a finer level */
                       : relief_params_search(params, g->d->ns, g->d->rotations,
                                              g->s->n_targets);
    if (g->stats->search != RELIEF_SEARCH_COHERENT)
        return RELIEF_OK;
    st = relief_search_create(g->s, g->d, params->window, params->search_k, params->threads,
                              &g->search, err);
    if (st != RELIEF_OK)
        return st;
    g->stats->search_seconds = relief_search_build_seconds(g->search);
    g->t0 = relief_seconds(); /* the growth's time and rate start after it */
    return RELIEF_OK;
}

/* Take up a saved growth where it stopped: its vertices, its random state,
 * threshold and figures; the time already spent counts. */
static relief_status grow_resume(grow_run *g, relief_error *err)
{
    const relief_grow_state *r = g->opts->resume;
    relief_grow_stats *stats = g->stats;
    relief_status st = restore_state(r, g, err);
    if (st != RELIEF_OK)
        return st;
    if (g->opts->matched && r->matched)
        memcpy(g->opts->matched + g->s->n_samples, r->matched,
               g->s->n_targets * sizeof *g->opts->matched);
    g->rng = r->rng;
    g->e = r->error;
    *stats = r->stats;
    stats->search = g->search ? RELIEF_SEARCH_COHERENT : RELIEF_SEARCH_EXHAUSTIVE;
    stats->search_seconds = relief_search_build_seconds(g->search);
    g->t0 -= r->stats.seconds;
    g->m->kernel_seconds += r->stats.match_seconds;
    return RELIEF_OK;
}

/* The saved pass's list and counts, to go on from where it stopped;
 * returns the index of the next target. */
static size_t grow_resume_pass(grow_run *g)
{
    const relief_grow_state *r = g->opts->resume;
    for (g->nl = 0; g->nl < r->n_list; ++g->nl) {
        g->list[g->nl].v = r->list[g->nl];
        g->list[g->nl].key = 0;
    }
    g->accepted = r->pass_accepted;
    g->any_valid = (size_t)r->pass_any_valid;
    g->all_min_window = (size_t)r->pass_all_min_window;
    return r->next;
}

/* A new pass: the boundary list, ranked by how constrained each target is. */
static relief_status grow_rank_boundary(grow_run *g, relief_error *err)
{
    const relief_surface *s = g->s;
    const size_t nv = s->mesh->nv;
    g->nl = 0;
    g->accepted = 0;
    g->any_valid = 0;
    g->all_min_window = 1;
    for (size_t t = s->n_samples; t < nv; ++t) {
        if (g->textured[t] ||
            !relief_query_has_textured_neighbour(g->qb, g->textured, (uint32_t)t))
            continue;
        g->list[g->nl].v = (uint32_t)t;
        g->list[g->nl].key =
            (uint32_t)relief_query_count(g->qb, g->textured, (uint32_t)t, g->win[t]);
        ++g->nl;
    }
    if (g->nl == 0)
        return relief_fail(err, RELIEF_E_MESH,
                           "%zu target(s) can never be reached: no path joins them to the "
                           "capture in the triangulation",
                           g->remaining);
    qsort(g->list, g->nl, sizeof *g->list, ranked_cmp);
    ++g->stats->passes;
    return RELIEF_OK;
}

/* Between two targets (list[li] is the next): save when due or asked to
 * stop, then stop when asked. */
static relief_status grow_between_targets(grow_run *g, size_t li, relief_error *err)
{
    const relief_grow_options *opts = g->opts;
    const relief_surface *s = g->s;
    const int stop = (opts->cancel && *opts->cancel) ||
                     (opts->cancel_after && g->run_acceptances >= opts->cancel_after);
    if (opts->save && (stop || (opts->save_every > 0.0 &&
                                relief_seconds() - g->last_save >= opts->save_every))) {
        relief_status st;
        stats_now(g);
        st = save_state(g, li, err);
        if (st != RELIEF_OK)
            return st;
        g->last_save = relief_seconds();
    }
    if (stop)
        return relief_fail(err, RELIEF_E_CANCELLED, "interrupted after %zu of %zu targets%s",
                           s->n_targets - g->remaining, s->n_targets,
                           opts->save ? "; state saved" : "");
    return RELIEF_OK;
}

/* A query's first cutoff: just above 1.1 x e when pruning (FLT_MAX
 * without). When the least SSD passes e, every member of the best set
 * (SSD at most 1.1 x that, below 1.1 x e) comes under it; when it does
 * not, the draw is rejected whatever it picks, and score_set takes what it
 * would from the random stream without the set's members. */
static float e_cutoff(const grow_run *g)
{
    if (!g->opts->prune)
        return FLT_MAX;
    return g->e < (double)FLT_MAX / 2 ? relief_match_cutoff_after((float)g->e) : FLT_MAX;
}

/* Target t's neighbourhood, and the samples to score first when the search
 * or a pyramid narrows them (the continuations, or the parent's box). */
static void grow_query(grow_run *g, uint32_t t, relief_match_query *query)
{
    const relief_grow_options *opts = g->opts;
    relief_grow_stats *stats = g->stats;
    relief_query_build(g->qb, g->textured, t, g->win[t], query);
    query->running = opts->prune;
    query->cutoff = e_cutoff(g);
    if (g->search) { /* k-coherence: the continuations first */
        const uint32_t *cs;
        uint32_t nc = relief_search_candidates(g->search, g->s, g->d, g->qb->nb, query->n,
                                               g->src, t, &cs);
        stats->search_centres += nc;
        if (nc > 0 && nc < g->d->ns) {
            query->subset = cs;
            query->n_subset = nc;
        } else {
            ++stats->search_empty;
        }
    } else if (opts->pyramid_start) { /* sample pyramids: the box first */
        query->subset = opts->pyramid_items + opts->pyramid_start[t];
        query->n_subset = opts->pyramid_start[t + 1] - opts->pyramid_start[t];
        if (query->n_subset == 0) {
            query->subset = NULL;
            ++stats->pyramid_empty;
        }
    }
}

/* The matcher failed on list[li]: keep the work done so far (nothing of the
 * target has changed yet) in a checkpoint, and say so if that fails too. */
static relief_status grow_score_failed(grow_run *g, size_t li, relief_status st,
                                       relief_error *err)
{
    relief_error serr = {0};
    stats_now(g);
    if (g->opts->save && save_state(g, li, &serr) != RELIEF_OK && err) {
        char msg[RELIEF_ERROR_MESSAGE_MAX];
        memcpy(msg, err->message, sizeof msg);
        relief_fail(err, st, "%.600s (and %.380s)", msg, serr.message);
    }
    return st;
}

/* One scoring of a target's candidates. */
typedef struct scored {
    double minv;     /* the least valid SSD; INFINITY when none came under
                        the cutoff */
    int valid;       /* some candidate is valid (the best set is not empty) */
    uint32_t chosen; /* drawn from the best set when minv < e; else
                        UINT32_MAX (any draw would fail e) */
} scored;

/* Whether any candidate the cutoff pruned is valid, scored in full one at
 * a time (nearly always the first is). */
static int any_pruned_valid(const grow_run *g, const relief_match_query *query, size_t ncand)
{
    const uint32_t R = (uint32_t)g->d->rotations;
    for (size_t c = 0; c < ncand; ++c) {
        float ssd;
        if (g->flag[c] == RM_PRUNED &&
            relief_score_host_one(g->d, query,
                                  relief_match_query_sample(query, (uint32_t)(c / R)),
                                  (int)(c % R), FLT_MAX, &ssd) == RM_VALID)
            return 1;
    }
    return 0;
}

/* The best set's size: the valid candidates within 10 % of minv. */
static size_t best_set(grow_run *g, size_t ncand, double minv)
{
    size_t nbest = 0;
    for (size_t c = 0; c < ncand; ++c)
        if (g->flag[c] == RM_VALID && (double)g->ssd[c] <= 1.1 * minv)
            g->best[nbest++] = (uint32_t)c;
    return nbest;
}

/* Score the query's candidates into g->ssd and g->flag, counting them. */
static relief_status score_into(grow_run *g, size_t li, const relief_match_query *query,
                                size_t *pruned, double *minv, relief_error *err)
{
    const size_t ncand = relief_match_query_candidates(g->d, query);
    relief_status st = relief_matcher_score(g->m, g->d, query, g->ssd, g->flag, err);
    if (st != RELIEF_OK)
        return grow_score_failed(g, li, st, err);
    *pruned = 0;
    *minv = INFINITY;
    g->stats->candidates += ncand;
    for (size_t c = 0; c < ncand; ++c) {
        *pruned += g->flag[c] == RM_PRUNED;
        g->stats->invalid += g->flag[c] == RM_INVALID;
        if (g->flag[c] == RM_VALID && g->ssd[c] < *minv)
            *minv = g->ssd[c];
    }
    g->stats->pruned += *pruned;
    return RELIEF_OK;
}

/* The draw from a best set whose least SSD fails e: rejected whatever it
 * picks, it must still take from the random stream what the draw would,
 * which depends on the set's size only when the first output falls in the
 * top ncand values of 2^32; then the set is scored again without the cutoff
 * to learn its size. */
static relief_status draw_rejected(grow_run *g, size_t li, relief_match_query *query,
                                   size_t ncand, relief_error *err)
{
    const uint32_t x = relief_rng_next(&g->rng);
    size_t pruned;
    double minv;
    relief_status st;
    if (relief_rng_below_one(x, (uint32_t)ncand))
        return RELIEF_OK;
    query->cutoff = FLT_MAX;
    st = score_into(g, li, query, &pruned, &minv, err);
    if (st == RELIEF_OK)
        relief_rng_below_from(&g->rng, x, (uint32_t)best_set(g, ncand, minv));
    return st;
}

/* Score the query's candidates and draw one from the best set (SSD within
 * 10 % of the least). The query's cutoff comes from e (e_cutoff): what it
 * prunes can only belong to a best set that fails e, so the choice, and
 * what the growth takes from the random stream, are as if every candidate
 * were scored in full. */
static relief_status score_set(grow_run *g, size_t li, relief_match_query *query, scored *out,
                               relief_error *err)
{
    const size_t ncand = relief_match_query_candidates(g->d, query);
    size_t pruned;
    relief_status st = score_into(g, li, query, &pruned, &out->minv, err);
    if (st != RELIEF_OK)
        return st;
    out->chosen = UINT32_MAX;
    /* With no valid score under the cutoff, a pruned candidate may still
     * be valid, above it: then a draw was due. */
    out->valid = isfinite(out->minv) || (pruned > 0 && any_pruned_valid(g, query, ncand));
    if (!out->valid)
        return RELIEF_OK;
    g->any_valid = 1;
    if (!(out->minv < g->e)) {
        if (g->opts->prune)
            return draw_rejected(g, li, query, ncand, err);
        /* Every candidate scored in full: DESIGN.md's draw as it reads,
         * the reference that draw_rejected must equal (test_grow). */
        relief_rng_below(&g->rng, (uint32_t)best_set(g, ncand, out->minv));
        return RELIEF_OK;
    }
    const size_t nbest = best_set(g, ncand, out->minv);
    out->chosen = g->best[relief_rng_below(&g->rng, (uint32_t)nbest)];
    return RELIEF_OK;
}

/* Score the query's candidates and draw (score_set). When a narrowed query
 * finds nothing that passes e, every sample is scored (001 section 3.4). */
static relief_status grow_score(grow_run *g, size_t li, relief_match_query *query,
                                scored *out, relief_error *err)
{
    const relief_match_data *d = g->d;
    relief_grow_stats *stats = g->stats;
    for (;;) {
        relief_status st = score_set(g, li, query, out, err);
        if (st != RELIEF_OK)
            return st;
        if (!(query->subset && query->n_subset < d->ns &&
              (out->chosen == UINT32_MAX || !((double)g->ssd[out->chosen] < g->e))))
            return RELIEF_OK;
        /* Nothing in the box (or among the continuations) passes e. */
        if (g->search)
            ++stats->search_misses;
        else
            ++stats->pyramid_misses;
        query->subset = NULL;
        query->n_subset = 0;
        query->cutoff = e_cutoff(g); /* draw_rejected may have lifted it */
    }
}

/* After each target, accepted or not: where the growth is. A rejection
 * moves nothing, but it is where a caller's cancel is seen when a pass
 * accepts nothing for a long while. */
static void report_progress(const grow_run *g)
{
    const relief_grow_options *opts = g->opts;
    if (opts->progress) {
        relief_grow_progress p = {g->s->n_targets - g->remaining, g->s->n_targets, g->e,
                                  relief_seconds() - g->t0, opts->level, opts->levels};
        opts->progress(opts->progress_ctx, &p);
    }
}

/* Texture t from sample si at rotation r: D(t) = R_t Rz(-theta) R_s^T D(s),
 * and the sample's colour; then the matcher, the figures and the progress
 * learn of it. narrowed: the query still had its subset. */
static relief_status grow_accept(grow_run *g, uint32_t t, uint32_t si, int r, int narrowed,
                                 int coherent, relief_error *err)
{
    relief_surface *s = g->s;
    relief_match_data *d = g->d;
    relief_mesh *mesh = s->mesh;
    const relief_grow_options *opts = g->opts;
    relief_grow_stats *stats = g->stats;
    const double *tp = s->proj + 3 * (size_t)t, *rt = s->frame + 9 * (size_t)t;
    const uint32_t sv = d->sample[si];
    const double *rs = s->frame + 9 * (size_t)sv, *ds = s->disp + 3 * (size_t)sv;
    const double th = 2.0 * RELIEF_PI * r / d->rotations, ct = cos(th), sn = sin(th);
    double a[3], b[3];
    relief_status st;
    for (int k = 0; k < 3; ++k)
        a[k] = rs[3 * k] * ds[0] + rs[3 * k + 1] * ds[1] + rs[3 * k + 2] * ds[2];
    b[0] = ct * a[0] + sn * a[1];
    b[1] = -sn * a[0] + ct * a[1];
    b[2] = a[2];
    for (int k = 0; k < 3; ++k) {
        double dk = rt[k] * b[0] + rt[3 + k] * b[1] + rt[6 + k] * b[2];
        s->disp[3 * (size_t)t + k] = dk;
        mesh->pos[3 * (size_t)t + k] = tp[k] + dk;
        d->pos[3 * (size_t)t + k] = (float)(tp[k] + dk);
        d->col[3 * (size_t)t + k] = d->col[3 * (size_t)sv + k];
        if (mesh->col)
            mesh->col[3 * (size_t)t + k] = mesh->col[3 * (size_t)sv + k];
    }
    g->textured[t] = 1;
    g->src[t] = si * (uint32_t)d->rotations + (uint32_t)r;
    if (opts->matched)
        opts->matched[t] = sv;
    if (g->search)
        stats->search_hits += narrowed;
    else
        stats->pyramid_hits += narrowed;
    if (opts->bootstrap)
        d->matchable[t] = 1;
    st = relief_matcher_update(g->m, d, t, err);
    if (st != RELIEF_OK)
        return st;
    ++g->accepted;
    ++stats->acceptances;
    stats->coherent += (size_t)coherent;
    ++g->run_acceptances;
    --g->remaining;
    report_progress(g);
    return RELIEF_OK;
}

/* One target of the pass, list[li]: score, draw (or take the coherent
 * candidate), and accept below e; otherwise shrink its window. */
static relief_status grow_target(grow_run *g, size_t li, relief_error *err)
{
    const relief_match_data *d = g->d;
    relief_grow_stats *stats = g->stats;
    const uint32_t t = g->list[li].v;
    const double kappa = g->params->coherence;
    uint32_t coh_si = 0;
    float coh_ssd = 0.0f;
    int coh_r = 0, use_coh = 0;
    relief_match_query query;
    scored sc;
    relief_status st = grow_between_targets(g, li, err);
    if (st != RELIEF_OK)
        return st;
    grow_query(g, t, &query);
    st = grow_score(g, li, &query, &sc, err);
    if (st != RELIEF_OK)
        return st;
    if (kappa > 0.0) {
        float cssd = 0.0f;
        uint32_t csi = 0;
        int cr = 0;
        /* The draw's best set: none, one that fails e (the continuation
         * then passes or fails e by itself), or the minimum to beat. */
        if (coherent_best(g->s, d, g->qb, &query, g->src, t, &cssd, &csi, &cr) &&
            (sc.chosen == UINT32_MAX || (double)cssd <= kappa * sc.minv)) {
            coh_ssd = cssd;
            coh_si = csi;
            coh_r = cr;
            use_coh = 1;
        }
    }
    if (sc.chosen != UINT32_MAX || use_coh) {
        const uint32_t c = sc.chosen;
        const float score = use_coh ? coh_ssd : g->ssd[c];
        if ((double)score < g->e) {
            const uint32_t si = use_coh ? coh_si :
                relief_match_query_sample(&query, c / (uint32_t)d->rotations);
            const int r = use_coh ? coh_r : (int)(c % (uint32_t)d->rotations);
            return grow_accept(g, t, si, r, query.subset != NULL, use_coh, err);
        }
    } else if (!sc.valid) {
        ++stats->no_candidate;
    }
    ++stats->rejections;
    if (g->win[t] > 1) {
        --g->win[t];
        ++stats->window_shrinks;
    }
    g->all_min_window &= g->win[t] == 1;
    report_progress(g);
    return RELIEF_OK;
}

/* A pass that accepted nothing raises e by 10 %, unless no window can
 * shrink and nothing was ever valid, or e has been raised too often. */
static relief_status grow_end_pass(grow_run *g, relief_error *err)
{
    if (g->accepted > 0)
        return RELIEF_OK;
    if (!g->any_valid && g->all_min_window)
        return relief_fail(err, RELIEF_E_MESH,
                           "no sample has a neighbourhood that matches: every "
                           "candidate maps a neighbour onto a target (is the capture "
                           "smaller than the window?)");
    if (g->stats->threshold_raises == MAX_RAISES)
        return relief_fail(err, RELIEF_E_MESH,
                           "the error threshold was raised %d times without progress",
                           MAX_RAISES);
    g->e *= 1.1;
    ++g->stats->threshold_raises;
    return RELIEF_OK;
}

/* The run's inputs and starting figures: e at the parameters' threshold,
 * the clock started, the stats cleared but for what the data fix. */
static void grow_start(grow_run *g, relief_surface *s, relief_match_data *d,
                       relief_matcher *m, const relief_params *params,
                       const relief_grow_options *opts, relief_grow_stats *stats)
{
    memset(g, 0, sizeof *g);
    g->s = s;
    g->d = d;
    g->m = m;
    g->params = params;
    g->opts = opts;
    g->stats = stats;
    g->remaining = s->n_targets;
    g->e = params->error;
    g->t0 = relief_seconds();
    memset(stats, 0, sizeof *stats);
    stats->targets = s->n_targets;
    stats->b_shape = d->b_shape;
    stats->mu = d->mu;
}

/* Passes until every target is textured; the first one goes on with the
 * saved pass when resume_pass is set. */
static relief_status grow_passes(grow_run *g, int resume_pass, relief_error *err)
{
    relief_status st;

    while (g->remaining > 0) {
        size_t first = 0;
        if (resume_pass) { /* the saved pass, from where it stopped */
            first = grow_resume_pass(g);
            resume_pass = 0;
        } else {
            st = grow_rank_boundary(g, err);
            if (st != RELIEF_OK)
                return st;
        }
        for (size_t li = first; li < g->nl; ++li) {
            st = grow_target(g, li, err);
            if (st != RELIEF_OK)
                return st;
        }
        st = grow_end_pass(g, err);
        if (st != RELIEF_OK)
            return st;
    }
    return RELIEF_OK;
}

/* Frees what grow_alloc and grow_choose_search made (any may be NULL). */
static void grow_free(grow_run *g)
{
    relief_search_destroy(g->search);
    free(g->src);
    free(g->best);
    free(g->flag);
    free(g->ssd);
    free(g->list);
    free(g->win);
    free(g->textured);
    relief_query_builder_destroy(g->qb);
}

relief_status relief_grow(relief_surface *s, relief_match_data *d, relief_matcher *m,
                          const relief_params *params, const relief_grow_options *opts,
                          relief_grow_stats *stats, relief_error *err)
{
    relief_grow_options dflt = relief_grow_options_default();
    grow_run g;
    relief_status st;
    int resume_pass = 0;

    grow_start(&g, s, d, m, params, opts ? opts : &dflt, stats);
    if (d->ns == 0)
        return relief_fail(err, RELIEF_E_MESH, "no sample vertex to grow from");
    st = relief_surface_check_growth(s, params->window, err);
    if (st != RELIEF_OK)
        return st;
    st = grow_alloc(&g, err);
    if (st == RELIEF_OK)
        st = grow_choose_search(&g, err);
    if (st != RELIEF_OK)
        goto done;
    relief_rng_seed(&g.rng, params->seed);
    if (g.opts->resume) {
        st = grow_resume(&g, err);
        if (st != RELIEF_OK)
            goto done;
        resume_pass = g.opts->resume->n_list > 0;
    }
    g.last_save = relief_seconds();
    st = grow_passes(&g, resume_pass, err);
done:
    stats_now(&g);
    grow_free(&g);
    return st;
}
