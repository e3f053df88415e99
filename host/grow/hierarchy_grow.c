/* Hierarchical growth (paper 001 section 3): each level grown in turn from
 * coarse to fine, every target's candidates restricted to the sample
 * pyramid under its parent's match, each level grown over the smoothed
 * heights of the one before.
 * The levels themselves are built in hierarchy.c. */
#include "grow/hierarchy.h"
#include "base/params.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/clock.h"
#include "base/error.h"
#include "base/knn.h"
#include "base/vec3.h"
#include "match/matcher.h"
#include "mesh/mesh.h"

relief_hierarchy_options relief_hierarchy_options_default(void)
{
    relief_hierarchy_options o;
    o.backend = RELIEF_BACKEND_AUTO;
    o.device = -1;
    o.pyramids = 1;
    o.heights = NULL;
    return o;
}

/* Is sample a nearer to m than sample b (ties: the lower id)? */
static int nearer(const double *spos, const double *m, uint32_t a, uint32_t b)
{
    double da = 0.0, db = 0.0;
    for (int k = 0; k < 3; ++k) {
        double x = spos[3 * (size_t)a + k] - m[k], y = spos[3 * (size_t)b + k] - m[k];
        da += x * x;
        db += y * y;
    }
    return da < db || (da == db && a < b);
}

/* The match a target whose parent p is a sample (on the hole's rim) follows:
 * that of the level k - 1 target nearest p in hops, within `hops`, the
 * first met breadth first (adjacency ascending); UINT32_MAX when there is
 * none. Without it every such target scored every sample: on a head's cut
 * (lato, 2 levels) 124 rim targets were 97 % of the finest level's work.
 * seen: npv stamps, `gen` new for this call; depth, queue: npv scratch. */
static uint32_t rim_match(const relief_adjacency *adj, const uint32_t *prev_match, size_t npv,
                          uint32_t p, int hops, uint32_t gen, uint32_t *seen, uint32_t *depth,
                          uint32_t *queue)
{
    uint32_t head = 0, tail = 0;
    seen[p] = gen;
    depth[p] = 0;
    queue[tail++] = p;
    while (head < tail) {
        uint32_t v = queue[head++];
        if (prev_match[v] < npv)
            return prev_match[v];
        if ((int)depth[v] == hops)
            continue;
        for (uint32_t i = adj->start[v]; i < adj->start[v + 1]; ++i) {
            uint32_t u = adj->nbr[i];
            if (seen[u] != gen) {
                seen[u] = gen;
                depth[u] = depth[v] + 1;
                queue[tail++] = u;
            }
        }
    }
    return UINT32_MAX;
}

/* The sample pyramids of level k (index ki): for each target, the level k
 * samples inside the box of the samples within `hops` of the sample its
 * parent matched at level k - 1 (prev_match, level k - 1 ids; UINT32_MAX
 * for the samples). CSR over level k's vertices; *boxes counts the
 * targets given a non-empty box. */
static relief_status build_pyramids(const relief_hierarchy *h, int ki,
                                    const relief_adjacency *prev_adj,
                                    const uint32_t *prev_match, int hops, uint32_t **start_out,
                                    uint32_t **items_out, size_t *boxes, relief_error *err)
{
    const relief_surface *lv = h->level[ki], *prev = h->level[ki - 1];
    const size_t nv = lv->mesh->nv, ns = lv->n_samples, npv = prev->mesh->nv;
    const double *pp = h->full->proj;
    const relief_adjacency adj = *prev_adj;
    uint32_t *start = calloc(nv + 1, sizeof *start), *items = NULL;
    uint32_t *stamp = calloc(npv, sizeof *stamp), *depth = malloc(npv * sizeof *depth);
    uint32_t *queue = malloc(npv * sizeof *queue), *seen = calloc(npv, sizeof *seen);
    double *spos = malloc((ns + 1) * 3 * sizeof *spos), *dist = malloc((ns + 1) * sizeof *dist);
    int *idx = malloc((ns + 1) * sizeof *idx);
    size_t n_items = 0, cap = 0;
    struct FLANNParameters fp = relief_knn_exact_params();
    flann_index_t index = NULL;
    relief_status st;
    float speedup;

    *boxes = 0;
    if (!start || !stamp || !depth || !queue || !seen || !spos || !dist || !idx) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the sample pyramids");
        goto done;
    }
    for (size_t v = 0; v < ns; ++v)
        memcpy(spos + 3 * v, pp + 3 * (size_t)h->ids[ki][v], 3 * sizeof(double));
    index = flann_build_index_double(spos, (int)ns, 3, &speedup, &fp);
    if (!index) {
        st = relief_fail(err, RELIEF_E_INTERNAL, "FLANN could not index a level's samples");
        goto done;
    }
    for (uint32_t t = 0; t < nv; ++t) {
        uint32_t p, ms, head = 0, tail = 0;
        double lo[3] = {DBL_MAX, DBL_MAX, DBL_MAX}, hi[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX};
        double c[3], r2 = 0.0, eps;
        int found;
        start[t + 1] = start[t];
        if (t < ns)
            continue;
        p = h->parent[ki][t];
        ms = prev_match[p];
        if (ms >= npv) /* a sample's child, at the hole's rim */
            ms = rim_match(&adj, prev_match, npv, p, hops, t + 1, seen, depth, queue);
        if (ms >= npv)
            continue; /* no match to follow: all samples */
        /* The samples within `hops` of ms at level k - 1, and their box. */
        stamp[ms] = t + 1;
        depth[ms] = 0;
        queue[tail++] = ms;
        while (head < tail) {
            uint32_t v = queue[head++];
            if (v < prev->n_samples)
                for (int k = 0; k < 3; ++k) {
                    double x = pp[3 * (size_t)h->ids[ki - 1][v] + k];
                    lo[k] = fmin(lo[k], x);
                    hi[k] = fmax(hi[k], x);
                }
            if ((int)depth[v] == hops)
                continue;
            for (uint32_t i = adj.start[v]; i < adj.start[v + 1]; ++i) {
                uint32_t u = adj.nbr[i];
                if (stamp[u] != t + 1) {
                    stamp[u] = t + 1;
                    depth[u] = depth[v] + 1;
                    queue[tail++] = u;
                }
            }
        }
        for (int k = 0; k < 3; ++k) {
            c[k] = 0.5 * (lo[k] + hi[k]);
            r2 += 0.25 * (hi[k] - lo[k]) * (hi[k] - lo[k]);
        }
        eps = 1e-9 * (sqrt(r2) + h->full->spacing);
        found = flann_radius_search_double(index, c, idx, dist, (int)ns,
                                           (float)(r2 * (1.0 + 1e-6) + eps * eps), &fp);
        if (found < 0) {
            st = relief_fail(err, RELIEF_E_INTERNAL, "FLANN radius search failed");
            goto done;
        }
        if (n_items + (size_t)found > cap) {
            uint32_t *grown;
            cap = 2 * (n_items + (size_t)found) + 1024;
            grown = realloc(items, cap * sizeof *items);
            if (!grown) {
                st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the sample pyramids");
                goto done;
            }
            items = grown;
        }
        {
            size_t first = n_items;
            for (int i = 0; i < found; ++i) {
                const double *q = spos + 3 * (size_t)idx[i];
                int in = 1;
                for (int k = 0; k < 3; ++k)
                    in &= q[k] >= lo[k] - eps && q[k] <= hi[k] + eps;
                if (in)
                    items[n_items++] = (uint32_t)idx[i];
            }
            /* Nearest first to the parent's match (its own vertex at this
             * level, the likeliest good match), ties by id: a running cutoff
             * then drops at once and prunes the rest early. The order, and
             * so the draw, must not depend on the kd-tree's. */
            const double *mp = pp + 3 * (size_t)h->ids[ki - 1][ms];
            for (size_t i = first + 1; i < n_items; ++i)
                for (size_t j = i; j > first && nearer(spos, mp, items[j], items[j - 1]); --j) {
                    uint32_t x = items[j];
                    items[j] = items[j - 1];
                    items[j - 1] = x;
                }
            *boxes += n_items > first;
        }
        start[t + 1] = (uint32_t)n_items;
    }
    st = RELIEF_OK;
done:
    if (index)
        flann_free_index_double(index, &fp);
    free(idx);
    free(dist);
    free(spos);
    free(seen);
    free(queue);
    free(depth);
    free(stamp);
    if (st != RELIEF_OK) {
        free(start);
        free(items);
        return st;
    }
    if (!items)
        items = malloc(sizeof *items);
    *start_out = start;
    *items_out = items;
    return items ? RELIEF_OK : relief_fail(err, RELIEF_E_NOMEM, "out of memory");
}

/* Gaussians reach out to this many sigma; a low-pass's sigma is this share
 * of its level's mean edge (a base's is the whole edge). */
#define GAUSS_REACH 3.0
#define LOWPASS_SIGMA 0.5

/* A height field on the base: values at ns vertices of the full surface
 * (sid, ids into it; NULL: 0..ns-1), indexed once by FLANN's exact tree over
 * their primitive projections, so that Gaussian means can be taken at any
 * vertices. Owns pos, the scratch idx/dist and the index. */
typedef struct height_field {
    const uint32_t *sid;
    const double *val;
    size_t ns;
    double *pos, *dist; /* ns x 3, ns */
    int *idx;           /* ns */
    flann_index_t index;
} height_field;

static void field_free(height_field *f)
{
    struct FLANNParameters fp = relief_knn_exact_params();
    if (f->index)
        flann_free_index_double(f->index, &fp);
    free(f->idx);
    free(f->dist);
    free(f->pos);
    memset(f, 0, sizeof *f);
}

/* prim: the full surface's primitive projections (nv x 3). */
static relief_status field_index(height_field *f, const double *prim, const uint32_t *sid,
                                 const double *val, size_t ns, relief_error *err)
{
    struct FLANNParameters fp = relief_knn_exact_params();
    float speedup;
    f->sid = sid, f->val = val, f->ns = ns;
    f->pos = malloc((ns + 1) * 3 * sizeof *f->pos);
    f->dist = malloc((ns + 1) * sizeof *f->dist);
    f->idx = malloc((ns + 1) * sizeof *f->idx);
    f->index = NULL;
    if (!f->pos || !f->dist || !f->idx) {
        field_free(f);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a level's smoothing");
    }
    for (size_t j = 0; j < ns; ++j)
        memcpy(f->pos + 3 * j, prim + 3 * (size_t)(sid ? sid[j] : j), 3 * sizeof *f->pos);
    f->index = flann_build_index_double(f->pos, (int)ns, 3, &speedup, &fp);
    if (!f->index) {
        field_free(f);
        return relief_fail(err, RELIEF_E_INTERNAL, "FLANN could not index a level's heights");
    }
    return RELIEF_OK;
}

/* The Gaussian mean of f (Nadaraya-Watson) at each query vertex qid[i] (ids
 * into the full surface, nq of them): out[i] = sum w_j val[j] / sum w_j
 * over f's vertices within GAUSS_REACH sigma of it, w_j = exp(-d^2 / 2
 * sigma^2) with d the distance between their primitive projections prim,
 * counting only vertices whose normal nrm is within 60 degrees of the
 * query's (so that a free-form base's thin parts do not mix their two
 * sides). With no vertex that near, the nearest one's value. Deterministic:
 * the exact tree, results summed nearest first. */
static relief_status field_mean(height_field *f, const double *prim, const double *nrm,
                                const uint32_t *qid, size_t nq, double sigma, double *out,
                                relief_error *err)
{
    const double inv2s2 = 1.0 / (2.0 * sigma * sigma);
    const float reach2 = (float)(GAUSS_REACH * GAUSS_REACH * sigma * sigma);
    struct FLANNParameters fp = relief_knn_exact_params();
    for (size_t i = 0; i < nq; ++i) {
        const double *q = prim + 3 * (size_t)qid[i], *qn = nrm + 3 * (size_t)qid[i];
        double acc = 0.0, wsum = 0.0;
        int found = flann_radius_search_double(f->index, (double *)q, f->idx, f->dist,
                                               (int)f->ns, reach2, &fp);
        if (found < 0)
            return relief_fail(err, RELIEF_E_INTERNAL, "FLANN radius search failed");
        for (int k = 0; k < found; ++k) {
            const uint32_t j = (uint32_t)f->idx[k];
            if (dot3(qn, nrm + 3 * (size_t)(f->sid ? f->sid[j] : j)) < 0.5)
                continue;
            const double w = exp(-f->dist[k] * inv2s2);
            acc += w * f->val[j];
            wsum += w;
        }
        if (wsum == 0.0) {
            if (flann_find_nearest_neighbors_index_double(f->index, (double *)q, 1, f->idx,
                                                          f->dist, 1, &fp) != 0)
                return relief_fail(err, RELIEF_E_INTERNAL, "FLANN search failed");
            acc = f->val[f->idx[0]];
            wsum = 1.0;
        }
        out[i] = acc / wsum;
    }
    return RELIEF_OK;
}

static void add_stats(relief_grow_stats *t, const relief_grow_stats *s)
{
    t->targets += s->targets;
    t->passes += s->passes;
    t->candidates += s->candidates;
    t->pruned += s->pruned;
    t->invalid += s->invalid;
    t->acceptances += s->acceptances;
    t->coherent += s->coherent;
    t->rejections += s->rejections;
    t->no_candidate += s->no_candidate;
    t->threshold_raises += s->threshold_raises;
    t->window_shrinks += s->window_shrinks;
    t->pyramid_hits += s->pyramid_hits;
    t->pyramid_misses += s->pyramid_misses;
    t->pyramid_empty += s->pyramid_empty;
    if (s->search == RELIEF_SEARCH_COHERENT) /* level 1's search is the run's */
        t->search = s->search;
    t->search_hits += s->search_hits;
    t->search_misses += s->search_misses;
    t->search_empty += s->search_empty;
    t->search_centres += s->search_centres;
    t->search_seconds += s->search_seconds;
    t->error_final = s->error_final;
    t->b_shape = s->b_shape;
    t->mu = s->mu;
    t->seconds += s->seconds;
    t->match_seconds += s->match_seconds;
}

/* A level's save callback: the caller's, given the growth's state with the
 * hierarchy's place attached. */
typedef struct level_saver {
    relief_grow_save_fn save;
    void *ctx;
    relief_hierarchy_state place;
} level_saver;

static relief_status save_level(void *ctx, const relief_grow_state *g, relief_error *err)
{
    const level_saver *ls = ctx;
    relief_grow_state with = *g;
    with.hier = &ls->place;
    return ls->save(ls->ctx, &with, err);
}

/* Check a saved hierarchical run against h; the level to continue (0-based). */
static relief_status check_resume(const relief_hierarchy *h, const relief_grow_state *g,
                                  const relief_hierarchy_options *ho, int *k0,
                                  relief_error *err)
{
    const relief_hierarchy_state *r = g->hier;
    size_t want;
    if (!r)
        return relief_fail(err, RELIEF_E_USAGE, "the checkpoint is of a mono-scale run "
                           "(levels 1), not of %d levels", h->levels);
    if (r->levels != h->levels || r->level < 1 || r->level > h->levels)
        return relief_fail(err, RELIEF_E_USAGE, "the checkpoint is at level %d of %d, not of "
                           "a %d-level run", r->level, r->levels, h->levels);
    if (ho->heights)
        return relief_fail(err, RELIEF_E_USAGE, "a resumed hierarchy cannot return the "
                           "finished levels' heights");
    want = r->level > 1 ? h->level[r->level - 2]->mesh->nv : 0;
    if (r->prev_nv != want)
        return relief_fail(err, RELIEF_E_USAGE, "the checkpoint's level %d has %zu vertices; "
                           "this hierarchy's has %zu", r->level - 1, r->prev_nv, want);
    *k0 = r->level - 1;
    return RELIEF_OK;
}

relief_status relief_hierarchy_grow(relief_hierarchy *h, relief_surface *s,
                                    const relief_params *params,
                                    const relief_grow_options *go,
                                    const relief_hierarchy_options *ho,
                                    relief_hierarchy_stats *hs, relief_grow_stats *total,
                                    relief_backend *backend, char *device, size_t device_size,
                                    char *note, size_t note_size, relief_error *err)
{
    const size_t nfull = s->mesh->nv;
    const int M = h->levels;
    /* p' on the primitive (nfull x 3), then the samples' captured heights */
    double *prim = malloc((nfull * 3 + s->n_samples) * sizeof *prim), *captured;
    double *heights_prev = NULL, b_shape, hmin = DBL_MAX, hmax = -DBL_MAX;
    uint32_t *match_prev = NULL;
    relief_status st = RELIEF_OK;
    const double mu = relief_grow_mu(params, s->mesh->col != NULL);
    relief_matcher *m = NULL;         /* every level's, rebound per level */
    relief_match_data *d_prev = NULL; /* the previous level's match data */
    /* Each level's adjacency, built once: the next level's pyramids walk
     * it. */
    relief_adjacency adj = {NULL, NULL}, adj_prev = {NULL, NULL};
    const relief_grow_state *resume = go ? go->resume : NULL;
    level_saver saver;
    height_field capture; /* the capture's heights, for the samples' low-pass */
    int k0 = 0; /* the first level to grow: 0, or a saved run's */

    memset(hs, 0, sizeof *hs);
    memset(total, 0, sizeof *total);
    hs->levels = M;
    if (note && note_size)
        note[0] = '\0';
    if (h->full != s) {
        free(prim);
        return relief_fail(err, RELIEF_E_INTERNAL,
                           "the hierarchy was built from another surface");
    }
    if (!prim)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the hierarchy's heights");
    memcpy(prim, s->proj, nfull * 3 * sizeof *prim);
    captured = prim + 3 * nfull;
    /* One shape bound for every level, the full relief's, so that e means
     * the same at each level as in a mono-scale run. */
    for (size_t v = 0; v < s->n_samples; ++v) {
        double hv = captured[v] = dot3(s->disp + 3 * v, s->nrm + 3 * v);
        hmin = fmin(hmin, hv);
        hmax = fmax(hmax, hv);
    }
    b_shape = hmax > hmin ? hmax - hmin : s->spacing;

    /* A saved run: the finished levels' heights, matches and figures back,
     * and the adjacency of the last of them for the pyramids. */
    if (resume) {
        const relief_hierarchy_state *r = resume->hier;
        st = check_resume(h, resume, ho, &k0, err);
        if (st == RELIEF_OK && k0 > 0) {
            const size_t np = r->prev_nv;
            heights_prev = malloc((np + 1) * sizeof *heights_prev);
            match_prev = malloc((np + 1) * sizeof *match_prev);
            if (!heights_prev || !match_prev)
                st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the saved levels");
            else {
                memcpy(heights_prev, r->heights_prev, np * sizeof *heights_prev);
                memcpy(match_prev, r->match_prev, np * sizeof *match_prev);
                st = relief_mesh_adjacency(h->level[k0 - 1]->mesh, &adj_prev, err);
            }
            for (int ki = 0; ki < k0; ++ki) {
                hs->level[ki] = r->done[ki];
                add_stats(total, &r->done[ki].grow);
            }
        }
        if (st != RELIEF_OK) {
            free(heights_prev);
            free(match_prev);
            free(prim);
            relief_adjacency_free(&adj_prev);
            return st;
        }
    }

    memset(&capture, 0, sizeof capture);
    if (k0 < M - 1)
        st = field_index(&capture, prim, NULL, captured, s->n_samples, err);
    for (int ki = k0; ki < M && st == RELIEF_OK; ++ki) {
        relief_surface *lv = h->level[ki];
        relief_mesh *lm = lv->mesh;
        const size_t nv = lm->nv;
        const uint32_t *ids = h->ids[ki];
        relief_level_stats *ls = &hs->level[ki];
        relief_match_data *d = NULL;
        relief_grow_options lo = go ? *go : relief_grow_options_default();
        uint32_t *pstart = NULL, *pitems = NULL, *matched = malloc((nv + 1) * sizeof *matched);
        double *base = malloc((nv + 1) * sizeof *base), *disp = malloc((nv + 1) * sizeof *disp);
        double *heights = malloc((nv + 1) * sizeof *heights);
        double t0 = relief_seconds();
        char lnote[RELIEF_ERROR_MESSAGE_MAX + 320];

        if (!matched || !base || !disp || !heights) {
            st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate hierarchy level %d", ki + 1);
            goto level_done;
        }
        ls->vertices = nv;
        ls->samples = lv->n_samples;
        ls->targets = lv->n_targets;
        st = relief_mesh_adjacency(lm, &adj, err);
        if (st != RELIEF_OK)
            goto level_done;
        /* The smoothed level k - 1 surface under each vertex: its base. */
        if (ki > 0) {
            height_field prev;
            st = field_index(&prev, prim, h->ids[ki - 1], heights_prev,
                             h->level[ki - 1]->mesh->nv, err);
            if (st == RELIEF_OK)
                st = field_mean(&prev, prim, s->nrm, ids, nv, h->sigma[ki - 1], base, err);
            field_free(&prev);
        } else
            memset(base, 0, nv * sizeof *base);
        /* Below the finest level the samples' relief is low-passed at the
         * level's own scale first, as an image pyramid filters before it
         * subsamples: a coarse level's vertices are too far apart for the
         * full relief, which would alias into false coarse structure. */
        if (st == RELIEF_OK && ki < M - 1)
            st = field_mean(&capture, prim, s->nrm, ids, lv->n_samples,
                            LOWPASS_SIGMA * h->sigma[ki], heights, err);
        if (st != RELIEF_OK)
            goto level_done;
        for (size_t v = 0; v < nv; ++v) {
            const double *p0 = prim + 3 * (size_t)ids[v], *n = s->nrm + 3 * (size_t)ids[v];
            double *pv = lm->pos + 3 * v;
            for (int k = 0; k < 3; ++k)
                lv->proj[3 * v + k] = p0[k] + base[v] * n[k];
            if (v < lv->n_samples) { /* samples: low-passed, or as captured */
                if (ki < M - 1) {
                    for (int k = 0; k < 3; ++k)
                        pv[k] = p0[k] + heights[v] * n[k];
                } else if (lv != s)
                    memcpy(pv, s->mesh->pos + 3 * (size_t)ids[v], 3 * sizeof *pv);
            } else
                memcpy(pv, lv->proj + 3 * v, 3 * sizeof *pv);
            for (int k = 0; k < 3; ++k)
                lv->disp[3 * v + k] = pv[k] - lv->proj[3 * v + k];
            matched[v] = v < lv->n_samples ? UINT32_MAX : UINT32_MAX - 1;
        }
        st = relief_match_data_build(lv, params->rotations, mu, &d, err);
        if (st != RELIEF_OK)
            goto level_done;
        d->b_shape = b_shape;
        d->inv_b2 = (float)(1.0 / (b_shape * b_shape));
        /* One matcher for every level: OpenCL keeps its context and built
         * program, and only the surface's buffers change. */
        if (!m) {
            st = relief_matcher_create(ho->backend, ho->device, d, &m, lnote, sizeof lnote,
                                       err);
            if (st == RELIEF_OK && lnote[0] && note && note_size && !note[0])
                snprintf(note, note_size, "%s", lnote);
        } else {
            st = relief_matcher_rebind(m, d, err);
        }
        if (st != RELIEF_OK)
            goto level_done;
        if (ki > 0 && ho->pyramids) {
            st = build_pyramids(h, ki, &adj_prev, match_prev, params->window, &pstart, &pitems,
                                &ls->boxes, err);
            if (st != RELIEF_OK)
                goto level_done;
            ls->box_samples = ls->boxes ? (double)pstart[nv] / (double)ls->boxes : 0.0;
            lo.pyramid_start = pstart;
            lo.pyramid_items = pitems;
        } else {
            lo.pyramid_start = lo.pyramid_items = NULL;
        }
        lo.matched = matched;
        lo.resume = ki == k0 ? resume : NULL;
        lo.level = ki;
        lo.levels = M;
        if (go && go->save) {
            saver.save = go->save;
            saver.ctx = go->save_ctx;
            saver.place.levels = M;
            saver.place.level = ki + 1;
            saver.place.prev_nv = ki > 0 ? h->level[ki - 1]->mesh->nv : 0;
            saver.place.heights_prev = heights_prev;
            saver.place.match_prev = match_prev;
            saver.place.done = hs->level;
            lo.save = save_level;
            lo.save_ctx = &saver;
        }
        m->kernel_seconds = 0.0; /* this level's scoring time only */
        st = relief_grow(lv, d, m, params, &lo, &ls->grow, err);
        if (st != RELIEF_OK) {
            add_stats(total, &ls->grow);
            relief_fail_prefix(err, "hierarchy level %d of %d", ki + 1, M);
            goto level_done;
        }
        add_stats(total, &ls->grow);
        *backend = m->backend;
        if (device && device_size)
            snprintf(device, device_size, "%s", m->device);
        /* Heights over the base, and over the primitive for the next
         * level's bases. */
        for (size_t v = 0; v < nv; ++v) {
            disp[v] = dot3(lv->disp + 3 * v, s->nrm + 3 * (size_t)ids[v]);
            heights[v] = base[v] + disp[v];
        }
        if (ho->heights) {
            relief_level_heights *lh = &ho->heights[ki];
            lh->base = base, lh->disp = disp;
            base = disp = NULL;
        }
        free(heights_prev);
        heights_prev = heights;
        heights = NULL;
        free(match_prev);
        match_prev = matched;
        matched = NULL;
    level_done:
        ls->seconds = relief_seconds() - t0;
        /* The matcher may still read the level's data (queued writes)
         * until the next rebind, which waits for them; d goes after it.
         * On failure the matcher goes first. */
        if (m && m->fallback_note[0])
            snprintf(hs->fallback, sizeof hs->fallback, "%s", m->fallback_note);
        if (st != RELIEF_OK) {
            relief_matcher_destroy(m);
            m = NULL;
        }
        relief_match_data_destroy(d_prev);
        d_prev = d;
        relief_adjacency_free(&adj_prev);
        adj_prev = adj;
        adj.start = NULL;
        adj.nbr = NULL;
        free(pstart);
        free(pitems);
        free(matched);
        free(heights);
        free(disp);
        free(base);
        if (st != RELIEF_OK)
            break;
    }
    field_free(&capture);
    relief_matcher_destroy(m);
    relief_match_data_destroy(d_prev);
    relief_adjacency_free(&adj_prev);
    relief_adjacency_free(&adj);
    /* s is level M: back to displacements from the primitive. */
    memcpy(s->proj, prim, nfull * 3 * sizeof *prim);
    for (size_t v = 0; v < nfull; ++v)
        for (int k = 0; k < 3; ++k)
            s->disp[3 * v + k] = s->mesh->pos[3 * v + k] - s->proj[3 * v + k];
    total->targets = s->n_targets;
    free(match_prev);
    free(heights_prev);
    free(prim);
    return st;
}
