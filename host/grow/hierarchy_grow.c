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
    o.threads = 0;
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

/* What building one level's pyramids shares: the level k - 1 walk's
 * scratch (npv each), level k's samples indexed by FLANN (ns), and the
 * items so far. */
typedef struct pyramid_build {
    const relief_hierarchy *h;
    int ki, hops;
    const relief_adjacency *adj; /* level k - 1's */
    uint32_t *stamp, *depth, *queue, *seen;
    double *spos, *dist; /* ns x 3: the samples' primitive projections; ns */
    int *idx;            /* ns */
    struct FLANNParameters fp;
    flann_index_t index;
    uint32_t *items;
    size_t n_items, cap;
} pyramid_build;

/* The box (lo, hi) of the level k - 1 samples within `hops` of vertex ms;
 * gen: a stamp new to this walk. */
static void match_box(pyramid_build *b, uint32_t ms, uint32_t gen, double lo[3], double hi[3])
{
    const relief_surface *prev = b->h->level[b->ki - 1];
    const double *pp = b->h->full->proj;
    uint32_t head = 0, tail = 0;
    b->stamp[ms] = gen;
    b->depth[ms] = 0;
    b->queue[tail++] = ms;
    while (head < tail) {
        uint32_t v = b->queue[head++];
        if (v < prev->n_samples)
            for (int k = 0; k < 3; ++k) {
                double x = pp[3 * (size_t)b->h->ids[b->ki - 1][v] + k];
                lo[k] = fmin(lo[k], x);
                hi[k] = fmax(hi[k], x);
            }
        if ((int)b->depth[v] == b->hops)
            continue;
        for (uint32_t i = b->adj->start[v]; i < b->adj->start[v + 1]; ++i) {
            uint32_t u = b->adj->nbr[i];
            if (b->stamp[u] != gen) {
                b->stamp[u] = gen;
                b->depth[u] = b->depth[v] + 1;
                b->queue[tail++] = u;
            }
        }
    }
}

/* Append the level k samples inside the box (lo, hi, widened by eps) to
 * b->items, nearest ms's first. FLANN finds them within the box's sphere. */
static relief_status box_items(pyramid_build *b, uint32_t ms, const double lo[3],
                               const double hi[3], relief_error *err)
{
    const size_t ns = b->h->level[b->ki]->n_samples, first = b->n_items;
    const double *pp = b->h->full->proj;
    double c[3], r2 = 0.0, eps;
    int found;
    for (int k = 0; k < 3; ++k) {
        c[k] = 0.5 * (lo[k] + hi[k]);
        r2 += 0.25 * (hi[k] - lo[k]) * (hi[k] - lo[k]);
    }
    eps = 1e-9 * (sqrt(r2) + b->h->full->spacing);
    found = flann_radius_search_double(b->index, c, b->idx, b->dist, (int)ns,
                                       (float)(r2 * (1.0 + 1e-6) + eps * eps), &b->fp);
    if (found < 0)
        return relief_fail(err, RELIEF_E_INTERNAL, "FLANN radius search failed");
    if (b->n_items + (size_t)found > b->cap) {
        uint32_t *grown;
        b->cap = 2 * (b->n_items + (size_t)found) + 1024;
        grown = realloc(b->items, b->cap * sizeof *b->items);
        if (!grown)
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the sample pyramids");
        b->items = grown;
    }
    for (int i = 0; i < found; ++i) {
        const double *q = b->spos + 3 * (size_t)b->idx[i];
        int in = 1;
        for (int k = 0; k < 3; ++k)
            in &= q[k] >= lo[k] - eps && q[k] <= hi[k] + eps;
        if (in)
            b->items[b->n_items++] = (uint32_t)b->idx[i];
    }
    /* Nearest first to the parent's match (its own vertex at this level,
     * the likeliest good match), ties by id: a running cutoff then drops
     * at once and prunes the rest early. The order, and so the draw, must
     * not depend on the kd-tree's. */
    const double *mp = pp + 3 * (size_t)b->h->ids[b->ki - 1][ms];
    for (size_t i = first + 1; i < b->n_items; ++i)
        for (size_t j = i; j > first && nearer(b->spos, mp, b->items[j], b->items[j - 1]);
             --j) {
            uint32_t x = b->items[j];
            b->items[j] = b->items[j - 1];
            b->items[j - 1] = x;
        }
    return RELIEF_OK;
}

/* Sets b up for level k (index ki): its scratch for the walks on level
 * k - 1 (npv each) and for the radius searches (ns + 1 each; spos 3 per
 * sample). Any allocation may fail: the caller checks. */
static void pyramid_init(pyramid_build *b, const relief_hierarchy *h, int ki,
                         const relief_adjacency *prev_adj, int hops)
{
    const size_t ns = h->level[ki]->n_samples, npv = h->level[ki - 1]->mesh->nv;

    memset(b, 0, sizeof *b);
    b->h = h, b->ki = ki, b->hops = hops, b->adj = prev_adj;
    b->stamp = calloc(npv, sizeof *b->stamp);
    b->depth = malloc(npv * sizeof *b->depth);
    b->queue = malloc(npv * sizeof *b->queue);
    b->seen = calloc(npv, sizeof *b->seen);
    b->spos = malloc((ns + 1) * 3 * sizeof *b->spos);
    b->dist = malloc((ns + 1) * sizeof *b->dist);
    b->idx = malloc((ns + 1) * sizeof *b->idx);
    b->fp = relief_knn_exact_params();
}

/* The kd-tree over level k's samples, at their positions on the base. */
static relief_status pyramid_index(pyramid_build *b, relief_error *err)
{
    const relief_hierarchy *h = b->h;
    const size_t ns = h->level[b->ki]->n_samples;
    const double *pp = h->full->proj;
    float speedup;

    for (size_t v = 0; v < ns; ++v)
        memcpy(b->spos + 3 * v, pp + 3 * (size_t)h->ids[b->ki][v], 3 * sizeof(double));
    b->index = flann_build_index_double(b->spos, (int)ns, 3, &speedup, &b->fp);
    if (!b->index)
        return relief_fail(err, RELIEF_E_INTERNAL, "FLANN could not index a level's samples");
    return RELIEF_OK;
}

/* Each target's box of samples, appended to b->items; start (nv + 1,
 * zeroed) gets the CSR offsets and *boxes the targets with a non-empty box. */
static relief_status pyramid_boxes(pyramid_build *b, const uint32_t *prev_match,
                                   uint32_t *start, size_t *boxes, relief_error *err)
{
    const relief_hierarchy *h = b->h;
    const int ki = b->ki, hops = b->hops;
    const relief_adjacency *prev_adj = b->adj;
    const size_t nv = h->level[ki]->mesh->nv, ns = h->level[ki]->n_samples,
                 npv = h->level[ki - 1]->mesh->nv;
    relief_status st;

    for (uint32_t t = 0; t < nv; ++t) {
        double lo[3] = {DBL_MAX, DBL_MAX, DBL_MAX}, hi[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX};
        uint32_t p, ms;
        start[t + 1] = start[t];
        if (t < ns)
            continue;
        p = h->parent[ki][t];
        ms = prev_match[p];
        if (ms >= npv) /* a sample's child, at the hole's rim */
            ms = rim_match(prev_adj, prev_match, npv, p, hops, t + 1, b->seen, b->depth,
                           b->queue);
        if (ms >= npv)
            continue; /* no match to follow: all samples */
        match_box(b, ms, t + 1, lo, hi);
        st = box_items(b, ms, lo, hi, err);
        if (st != RELIEF_OK)
            return st;
        *boxes += b->n_items > start[t + 1];
        start[t + 1] = (uint32_t)b->n_items;
    }
    return RELIEF_OK;
}

/* Frees b's index and scratch; not its items, which become the result. */
static void pyramid_free(pyramid_build *b)
{
    if (b->index)
        flann_free_index_double(b->index, &b->fp);
    free(b->idx);
    free(b->dist);
    free(b->spos);
    free(b->seen);
    free(b->queue);
    free(b->depth);
    free(b->stamp);
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
    const size_t nv = h->level[ki]->mesh->nv;
    uint32_t *start = calloc(nv + 1, sizeof *start);
    pyramid_build b;
    relief_status st;

    pyramid_init(&b, h, ki, prev_adj, hops);
    *boxes = 0;
    if (!start || !b.stamp || !b.depth || !b.queue || !b.seen || !b.spos || !b.dist || !b.idx) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the sample pyramids");
        goto done;
    }
    st = pyramid_index(&b, err);
    if (st == RELIEF_OK)
        st = pyramid_boxes(&b, prev_match, start, boxes, err);
done:
    pyramid_free(&b);
    if (st != RELIEF_OK) {
        free(start);
        free(b.items);
        return st;
    }
    if (!b.items)
        b.items = malloc(sizeof *b.items);
    *start_out = start;
    *items_out = b.items;
    return b.items ? RELIEF_OK : relief_fail(err, RELIEF_E_NOMEM, "out of memory");
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

/* What the levels share: the full surface and its primitive projections,
 * the shape bound, one matcher, and the previous level's match data,
 * heights, matches and adjacency (the next level's bases and pyramids read
 * them). */
typedef struct hier_run {
    relief_hierarchy *h;
    relief_surface *s; /* the full surface, level M */
    const relief_params *params;
    const relief_grow_options *go; /* may be NULL */
    const relief_hierarchy_options *ho;
    relief_hierarchy_stats *hs;
    relief_grow_stats *total;
    int M, k0; /* the levels; the first to grow: 0, or a saved run's */
    /* p' on the primitive (nfull x 3), then the samples' captured heights */
    double *prim, *captured;
    double b_shape, mu;
    double *heights_prev;         /* level k - 1's vertices: heights over the primitive */
    uint32_t *match_prev;         /* and the sample each matched */
    relief_matcher *m;            /* every level's, rebound per level */
    relief_match_data *d_prev;    /* the previous level's match data */
    relief_adjacency adj, adj_prev; /* each level's, built once */
    level_saver saver;
    height_field capture; /* the capture's heights, for the samples' low-pass */
    relief_backend *backend;
    char *device, *note;
    size_t device_size, note_size;
} hier_run;

/* One level's own arrays (nv each), freed when it is done unless handed on. */
typedef struct level_work {
    relief_match_data *d;
    uint32_t *pstart, *pitems, *matched;
    double *base, *disp, *heights;
} level_work;

/* One shape bound for every level, the full relief's, so that e means the
 * same at each level as in a mono-scale run; the samples' captured heights
 * go to captured (n_samples). */
static double shape_bound(const relief_surface *s, double *captured)
{
    double hmin = DBL_MAX, hmax = -DBL_MAX;
    for (size_t v = 0; v < s->n_samples; ++v) {
        double hv = captured[v] = dot3(s->disp + 3 * v, s->nrm + 3 * v);
        hmin = fmin(hmin, hv);
        hmax = fmax(hmax, hv);
    }
    return hmax > hmin ? hmax - hmin : s->spacing;
}

/* A saved run: the level to go on with (g->k0), the finished levels'
 * heights, matches and figures back, and the adjacency of the last of them
 * for the pyramids. */
static relief_status hier_resume(hier_run *g, const relief_grow_state *resume,
                                 relief_error *err)
{
    const relief_hierarchy_state *r = resume->hier;
    relief_status st = check_resume(g->h, resume, g->ho, &g->k0, err);
    size_t np;
    if (st != RELIEF_OK || g->k0 == 0)
        return st;
    np = r->prev_nv;
    g->heights_prev = malloc((np + 1) * sizeof *g->heights_prev);
    g->match_prev = malloc((np + 1) * sizeof *g->match_prev);
    if (!g->heights_prev || !g->match_prev)
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the saved levels");
    else {
        memcpy(g->heights_prev, r->heights_prev, np * sizeof *g->heights_prev);
        memcpy(g->match_prev, r->match_prev, np * sizeof *g->match_prev);
        st = relief_mesh_adjacency(g->h->level[g->k0 - 1]->mesh, &g->adj_prev, err);
    }
    for (int ki = 0; ki < g->k0; ++ki) {
        g->hs->level[ki] = r->done[ki];
        add_stats(g->total, &r->done[ki].grow);
    }
    return st;
}

/* Level ki's base (the smoothed level k - 1 surface under each vertex) and,
 * below the finest level, its samples' low-passed heights. */
static relief_status level_base(hier_run *g, int ki, level_work *w, relief_error *err)
{
    const relief_hierarchy *h = g->h;
    const relief_surface *lv = h->level[ki];
    const uint32_t *ids = h->ids[ki];
    const size_t nv = lv->mesh->nv;
    relief_status st = RELIEF_OK;
    if (ki > 0) {
        height_field prev;
        st = field_index(&prev, g->prim, h->ids[ki - 1], g->heights_prev,
                         h->level[ki - 1]->mesh->nv, err);
        if (st == RELIEF_OK)
            st = field_mean(&prev, g->prim, g->s->nrm, ids, nv, h->sigma[ki - 1], w->base,
                            err);
        field_free(&prev);
    } else
        memset(w->base, 0, nv * sizeof *w->base);
    /* Below the finest level the samples' relief is low-passed at the
     * level's own scale first, as an image pyramid filters before it
     * subsamples: a coarse level's vertices are too far apart for the
     * full relief, which would alias into false coarse structure. */
    if (st == RELIEF_OK && ki < g->M - 1)
        st = field_mean(&g->capture, g->prim, g->s->nrm, ids, lv->n_samples,
                        LOWPASS_SIGMA * h->sigma[ki], w->heights, err);
    return st;
}

/* Level ki's vertices on their base: targets flat on it, samples at their
 * low-passed (or, at the finest level, captured) heights. */
static void level_place(const hier_run *g, int ki, level_work *w)
{
    const relief_surface *s = g->s;
    relief_surface *lv = g->h->level[ki];
    relief_mesh *lm = lv->mesh;
    const uint32_t *ids = g->h->ids[ki];
    for (size_t v = 0; v < lm->nv; ++v) {
        const double *p0 = g->prim + 3 * (size_t)ids[v], *n = s->nrm + 3 * (size_t)ids[v];
        double *pv = lm->pos + 3 * v;
        for (int k = 0; k < 3; ++k)
            lv->proj[3 * v + k] = p0[k] + w->base[v] * n[k];
        if (v < lv->n_samples) { /* samples: low-passed, or as captured */
            if (ki < g->M - 1) {
                for (int k = 0; k < 3; ++k)
                    pv[k] = p0[k] + w->heights[v] * n[k];
            } else if (lv != s)
                memcpy(pv, s->mesh->pos + 3 * (size_t)ids[v], 3 * sizeof *pv);
        } else
            memcpy(pv, lv->proj + 3 * v, 3 * sizeof *pv);
        for (int k = 0; k < 3; ++k)
            lv->disp[3 * v + k] = pv[k] - lv->proj[3 * v + k];
        w->matched[v] = v < lv->n_samples ? UINT32_MAX : UINT32_MAX - 1;
    }
}

/* Level ki's match data, under the full relief's shape bound, and the
 * matcher bound to it. */
static relief_status level_matcher(hier_run *g, int ki, level_work *w, relief_error *err)
{
    char lnote[RELIEF_ERROR_MESSAGE_MAX + 320];
    relief_reason why = RELIEF_REASON_NONE;
    relief_status st = relief_match_data_build(g->h->level[ki], g->params->rotations, g->mu,
                                               &w->d, err);
    if (st != RELIEF_OK)
        return st;
    w->d->b_shape = g->b_shape;
    w->d->inv_b2 = (float)(1.0 / (g->b_shape * g->b_shape));
    /* One matcher for every level: OpenCL keeps its context and built
     * program, and only the surface's buffers change. */
    if (g->m)
        return relief_matcher_rebind(g->m, w->d, err);
    st = relief_matcher_create(g->ho->backend, g->ho->device, g->ho->threads, 0.0, w->d, &g->m,
                               lnote, sizeof lnote, &why, err);
    if (st == RELIEF_OK && lnote[0] && g->note && g->note_size && !g->note[0]) {
        snprintf(g->note, g->note_size, "%s", lnote);
        g->hs->backend_reason = why;
    }
    return st;
}

/* Level ki's growth options: its sample pyramids below the coarsest level,
 * where its matches go, the saved run to take up, and a save callback that
 * adds the hierarchy's place. */
static relief_status level_options(hier_run *g, int ki, level_work *w,
                                   relief_grow_options *lo, relief_error *err)
{
    const relief_grow_options *go = g->go;
    relief_level_stats *ls = &g->hs->level[ki];
    const relief_hierarchy *h = g->h;
    if (ki > 0 && g->ho->pyramids) {
        relief_status st = build_pyramids(h, ki, &g->adj_prev, g->match_prev,
                                          g->params->window, &w->pstart, &w->pitems,
                                          &ls->boxes, err);
        if (st != RELIEF_OK)
            return st;
        ls->box_samples =
            ls->boxes ? (double)w->pstart[h->level[ki]->mesh->nv] / (double)ls->boxes : 0.0;
        lo->pyramid_start = w->pstart;
        lo->pyramid_items = w->pitems;
    } else {
        lo->pyramid_start = lo->pyramid_items = NULL;
    }
    lo->matched = w->matched;
    lo->resume = ki == g->k0 && go ? go->resume : NULL;
    lo->level = ki;
    lo->levels = g->M;
    if (go && go->save) {
        g->saver.save = go->save;
        g->saver.ctx = go->save_ctx;
        g->saver.place.levels = g->M;
        g->saver.place.level = ki + 1;
        g->saver.place.prev_nv = ki > 0 ? h->level[ki - 1]->mesh->nv : 0;
        g->saver.place.heights_prev = g->heights_prev;
        g->saver.place.match_prev = g->match_prev;
        g->saver.place.done = g->hs->level;
        lo->save = save_level;
        lo->save_ctx = &g->saver;
    }
    return RELIEF_OK;
}

/* A grown level: the backend that grew it, its heights over the base and
 * over the primitive (for the next level's bases), its matches (for the
 * next level's pyramids); the caller's copy of base and disp if asked. */
static void level_keep(hier_run *g, int ki, level_work *w)
{
    const relief_surface *lv = g->h->level[ki];
    const uint32_t *ids = g->h->ids[ki];
    *g->backend = g->m->backend;
    if (g->device && g->device_size)
        snprintf(g->device, g->device_size, "%s", g->m->device);
    for (size_t v = 0; v < lv->mesh->nv; ++v) {
        w->disp[v] = dot3(lv->disp + 3 * v, g->s->nrm + 3 * (size_t)ids[v]);
        w->heights[v] = w->base[v] + w->disp[v];
    }
    if (g->ho->heights) {
        relief_level_heights *lh = &g->ho->heights[ki];
        lh->base = w->base, lh->disp = w->disp;
        w->base = w->disp = NULL;
    }
    free(g->heights_prev);
    g->heights_prev = w->heights;
    w->heights = NULL;
    free(g->match_prev);
    g->match_prev = w->matched;
    w->matched = NULL;
}

/* Grow level ki: its base, its vertices placed on it, its matcher and
 * options, the growth, then what the next level needs. */
static relief_status level_grow(hier_run *g, int ki, level_work *w, relief_error *err)
{
    relief_surface *lv = g->h->level[ki];
    const size_t nv = lv->mesh->nv;
    relief_level_stats *ls = &g->hs->level[ki];
    relief_grow_options lo = g->go ? *g->go : relief_grow_options_default();
    relief_status st;
    w->matched = malloc((nv + 1) * sizeof *w->matched);
    w->base = malloc((nv + 1) * sizeof *w->base);
    w->disp = malloc((nv + 1) * sizeof *w->disp);
    w->heights = malloc((nv + 1) * sizeof *w->heights);
    if (!w->matched || !w->base || !w->disp || !w->heights)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate hierarchy level %d", ki + 1);
    ls->vertices = nv;
    ls->samples = lv->n_samples;
    ls->targets = lv->n_targets;
    st = relief_mesh_adjacency(lv->mesh, &g->adj, err);
    if (st == RELIEF_OK)
        st = level_base(g, ki, w, err);
    if (st != RELIEF_OK)
        return st;
    level_place(g, ki, w);
    st = level_matcher(g, ki, w, err);
    if (st == RELIEF_OK)
        st = level_options(g, ki, w, &lo, err);
    if (st != RELIEF_OK)
        return st;
    g->m->kernel_seconds = 0.0; /* this level's scoring time only */
    st = relief_grow(lv, w->d, g->m, g->params, &lo, &ls->grow, err);
    add_stats(g->total, &ls->grow);
    if (st != RELIEF_OK) {
        relief_fail_prefix(err, "hierarchy level %d of %d", ki + 1, g->M);
        return st;
    }
    level_keep(g, ki, w);
    return RELIEF_OK;
}

/* After a level, grown or failed: its match data and adjacency become the
 * previous level's, its own arrays go. */
static void level_release(hier_run *g, level_work *w, relief_status st)
{
    /* The matcher may still read the level's data (queued writes) until
     * the next rebind, which waits for them; d goes after it. On failure
     * the matcher goes first. */
    if (g->m && g->m->fallback_note[0])
        snprintf(g->hs->fallback, sizeof g->hs->fallback, "%s", g->m->fallback_note);
    if (st != RELIEF_OK) {
        relief_matcher_destroy(g->m);
        g->m = NULL;
    }
    relief_match_data_destroy(g->d_prev);
    g->d_prev = w->d;
    relief_adjacency_free(&g->adj_prev);
    g->adj_prev = g->adj;
    g->adj.start = NULL;
    g->adj.nbr = NULL;
    free(w->pstart);
    free(w->pitems);
    free(w->matched);
    free(w->heights);
    free(w->disp);
    free(w->base);
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
    const relief_grow_state *resume = go ? go->resume : NULL;
    relief_status st = RELIEF_OK;
    hier_run g;

    memset(&g, 0, sizeof g);
    g.h = h, g.s = s, g.params = params, g.go = go, g.ho = ho, g.hs = hs, g.total = total;
    g.backend = backend, g.device = device, g.device_size = device_size;
    g.note = note, g.note_size = note_size;
    g.M = h->levels;
    g.mu = relief_grow_mu(params, s->mesh->col != NULL);
    g.prim = malloc((nfull * 3 + s->n_samples) * sizeof *g.prim);
    memset(hs, 0, sizeof *hs);
    memset(total, 0, sizeof *total);
    hs->levels = g.M;
    if (note && note_size)
        note[0] = '\0';
    if (h->full != s) {
        free(g.prim);
        return relief_fail(err, RELIEF_E_INTERNAL,
                           "the hierarchy was built from another surface");
    }
    if (!g.prim)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the hierarchy's heights");
    memcpy(g.prim, s->proj, nfull * 3 * sizeof *g.prim);
    g.captured = g.prim + 3 * nfull;
    g.b_shape = shape_bound(s, g.captured);
    if (resume) {
        st = hier_resume(&g, resume, err);
        if (st != RELIEF_OK) {
            free(g.heights_prev);
            free(g.match_prev);
            free(g.prim);
            relief_adjacency_free(&g.adj_prev);
            return st;
        }
    }

    if (g.k0 < g.M - 1)
        st = field_index(&g.capture, g.prim, NULL, g.captured, s->n_samples, err);
    for (int ki = g.k0; ki < g.M && st == RELIEF_OK; ++ki) {
        level_work w;
        const double t0 = relief_seconds();
        memset(&w, 0, sizeof w);
        st = level_grow(&g, ki, &w, err);
        hs->level[ki].seconds = relief_seconds() - t0;
        level_release(&g, &w, st);
    }
    field_free(&g.capture);
    relief_matcher_destroy(g.m);
    relief_match_data_destroy(g.d_prev);
    relief_adjacency_free(&g.adj_prev);
    relief_adjacency_free(&g.adj);
    /* s is level M: back to displacements from the primitive. */
    memcpy(s->proj, g.prim, nfull * 3 * sizeof *g.prim);
    for (size_t v = 0; v < nfull; ++v)
        for (int k = 0; k < 3; ++k)
            s->disp[3 * v + k] = s->mesh->pos[3 * v + k] - s->proj[3 * v + k];
    total->targets = s->n_targets;
    free(g.match_prev);
    free(g.heights_prev);
    free(g.prim);
    return st;
}
