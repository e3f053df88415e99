/* Hierarchical completion with sample pyramids (paper 001 section 3).
 *
 * Why a Poisson-disc selection and qhull rather than OpenMesh's decimater:
 * the method wants levels of about k n / M vertices at an even density, so
 * that a window of W hops covers a similar area everywhere on a level, and
 * it wants every level to be a manifold triangulation joined across the
 * cylinder's seam like the smooth completion's. Quadric collapses keep
 * vertices where the relief bends and thin out flat parts, and would need
 * the seam handled again; a nested disc selection on the primitive,
 * re-triangulated by the very code that made the finest level, gives even,
 * nested levels (the discrete levels of a progressive mesh) with known
 * parents, and keeps OpenMesh to the one C++ file.
 *
 * A free-form base (paper 002's, points/base_surface.h) has no parameter
 * domain to re-triangulate in: there the same nested selection is kept by
 * collapsing the base's own triangles onto it (relief_surface_level), the
 * one place the hierarchy uses OpenMesh's collapses. */
#include "grow/hierarchy.h"

#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/knn.h"
#include "base/vec3.h"
#include "mesh/mesh.h"

/* ------------------------------------------------------ disc selection */

static uint64_t mix64(uint64_t x) /* splitmix64's finaliser */
{
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

typedef struct keyed {
    uint64_t key;
    uint32_t v;
} keyed;

static int keyed_cmp(const void *x, const void *y)
{
    const keyed *a = x, *b = y;
    if (a->key != b->key)
        return a->key < b->key ? -1 : 1;
    return (a->v > b->v) - (a->v < b->v);
}

/* A spatial hash of selected points: cells of side `cell`, open addressing
 * on the packed cell coordinates, each cell a linked list through next[]. */
typedef struct disc_grid {
    size_t cap;       /* power of two */
    uint64_t *key;    /* cap; UINT64_MAX empty */
    uint32_t *head;   /* cap */
    uint32_t *next;   /* nv */
    double lo[3], cell;
} disc_grid;

static uint64_t cell_of(const disc_grid *g, const double *p, const int off[3])
{
    uint64_t key = 0;
    for (int k = 0; k < 3; ++k) {
        int64_t c = (int64_t)floor((p[k] - g->lo[k]) / g->cell) + off[k] + 1;
        key = (key << 21) | ((uint64_t)c & 0x1fffff);
    }
    return key;
}

static size_t slot_of(const disc_grid *g, uint64_t key)
{
    size_t i = (size_t)mix64(key) & (g->cap - 1);
    while (g->key[i] != UINT64_MAX && g->key[i] != key)
        i = (i + 1) & (g->cap - 1);
    return i;
}

static void grid_insert(disc_grid *g, const double *pos, uint32_t v)
{
    static const int zero[3] = {0, 0, 0};
    size_t i = slot_of(g, cell_of(g, pos + 3 * (size_t)v, zero));
    if (g->key[i] == UINT64_MAX) {
        g->key[i] = cell_of(g, pos + 3 * (size_t)v, zero);
        g->head[i] = UINT32_MAX;
    }
    g->next[v] = g->head[i];
    g->head[i] = v;
}

static int grid_near(const disc_grid *g, const double *pos, uint32_t v, double r2)
{
    const double *p = pos + 3 * (size_t)v;
    int off[3];
    for (off[0] = -1; off[0] <= 1; ++off[0])
        for (off[1] = -1; off[1] <= 1; ++off[1])
            for (off[2] = -1; off[2] <= 1; ++off[2]) {
                size_t i = slot_of(g, cell_of(g, p, off));
                if (g->key[i] == UINT64_MAX)
                    continue;
                for (uint32_t u = g->head[i]; u != UINT32_MAX; u = g->next[u]) {
                    const double *q = pos + 3 * (size_t)u;
                    double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
                    if (dx * dx + dy * dy + dz * dz < r2)
                        return 1;
                }
            }
    return 0;
}

/* Greedy Poisson-disc selection of radius r over pos (nv x 3), in `order`:
 * every vertex with first[v] <= level - 1 is kept, then each other vertex
 * farther than r from all kept ones is added (mark[v] = 1) until `limit`
 * are kept. Returns the count kept. */
static size_t disc_select(disc_grid *g, const double *pos, size_t nv, const keyed *order,
                          const uint8_t *first, int level, double r, size_t limit,
                          uint8_t *mark)
{
    size_t n = 0;
    g->cell = r;
    for (size_t i = 0; i < g->cap; ++i)
        g->key[i] = UINT64_MAX;
    for (size_t v = 0; v < nv; ++v) {
        mark[v] = 0;
        if (first[v] < level) {
            grid_insert(g, pos, (uint32_t)v);
            ++n;
        }
    }
    for (size_t i = 0; i < nv && n < limit; ++i) {
        uint32_t v = order[i].v;
        if (first[v] < level || grid_near(g, pos, v, r * r))
            continue;
        grid_insert(g, pos, v);
        mark[v] = 1;
        ++n;
    }
    return n;
}

/* first_level[v] for every vertex: levels 1..M-1 hold about k nv / M
 * vertices each, found by bisecting the disc radius; the rest are level M.
 * radius[k - 1] receives each level's radius. */
static relief_status plan_levels(const relief_surface *s, int levels, uint8_t *first,
                                 double *radius, relief_error *err)
{
    const size_t nv = s->mesh->nv;
    const double *pos = s->proj;
    keyed *order = malloc(nv * sizeof *order);
    uint8_t *mark = malloc(nv);
    disc_grid g;
    double hi0[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX}, diag = 0.0;
    relief_status st = RELIEF_OK;

    memset(&g, 0, sizeof g);
    for (g.cap = 16; g.cap < 2 * nv; g.cap *= 2) {
    }
    g.key = malloc(g.cap * sizeof *g.key);
    g.head = malloc(g.cap * sizeof *g.head);
    g.next = malloc(nv * sizeof *g.next);
    if (!order || !mark || !g.key || !g.head || !g.next) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the hierarchy's selection");
        goto done;
    }
    for (int k = 0; k < 3; ++k)
        g.lo[k] = DBL_MAX;
    for (size_t v = 0; v < nv; ++v) {
        order[v].key = mix64(v);
        order[v].v = (uint32_t)v;
        first[v] = (uint8_t)levels;
        for (int k = 0; k < 3; ++k) {
            g.lo[k] = fmin(g.lo[k], pos[3 * v + k]);
            hi0[k] = fmax(hi0[k], pos[3 * v + k]);
        }
    }
    qsort(order, nv, sizeof *order, keyed_cmp);
    for (int k = 0; k < 3; ++k)
        diag += (hi0[k] - g.lo[k]) * (hi0[k] - g.lo[k]);
    diag = sqrt(diag);
    radius[levels - 1] = 0.0;
    for (int level = 1; level < levels; ++level) {
        const size_t want = (size_t)((double)level * (double)nv / levels + 0.5);
        /* The widest radius that still reaches `want` vertices, by
         * bisection (2^20 cells per axis at most: the hash packs 21 bits).
         * On a regular lattice the count jumps at the lattice spacing, so
         * the selection then stops at `want`, leaving the rest of the
         * lattice out in the hash's random order. */
        double lo = diag / 1e6, hi = diag;
        for (int it = 0; it < 40; ++it) {
            double r = sqrt(lo * hi);
            size_t n = disc_select(&g, pos, nv, order, first, level, r, SIZE_MAX, mark);
            if (n >= want)
                lo = r;
            else
                hi = r;
            if (n >= want && n - want <= want / 200)
                break;
        }
        radius[level - 1] = lo;
        disc_select(&g, pos, nv, order, first, level, lo, want, mark);
        for (size_t v = 0; v < nv; ++v)
            if (mark[v])
                first[v] = (uint8_t)level;
    }
done:
    free(g.key);
    free(g.head);
    free(g.next);
    free(mark);
    free(order);
    return st;
}

/* ---------------------------------------------------------- hierarchy */

void relief_hierarchy_destroy(relief_hierarchy *h)
{
    if (!h)
        return;
    for (int k = 0; k < RELIEF_MAX_LEVELS; ++k) {
        if (k < h->levels - 1)
            relief_surface_destroy(h->level[k]);
        free(h->ids[k]);
        free(h->parent[k]);
    }
    free(h->first_level);
    free(h);
}

/* parent of each vertex of level k (index ki): itself when present at
 * level k - 1, else the nearest level k - 1 vertex on the base. */
static relief_status link_level(relief_hierarchy *h, int ki, relief_error *err)
{
    const relief_surface *fine = h->level[ki], *coarse = h->level[ki - 1];
    const size_t nf = fine->mesh->nv, nc = coarse->mesh->nv, nfull = h->full->mesh->nv;
    const double *pp = h->full->proj;
    uint32_t *loc = malloc(nfull * sizeof *loc);
    double *cpos = malloc((nc + 1) * 3 * sizeof *cpos);
    struct FLANNParameters fp = relief_knn_exact_params();
    flann_index_t index = NULL;
    relief_status st = RELIEF_OK;
    float speedup;

    h->parent[ki] = malloc(nf * sizeof(uint32_t));
    if (!loc || !cpos || !h->parent[ki]) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the hierarchy's links");
        goto done;
    }
    for (size_t v = 0; v < nfull; ++v)
        loc[v] = UINT32_MAX;
    for (size_t v = 0; v < nc; ++v) {
        loc[h->ids[ki - 1][v]] = (uint32_t)v;
        memcpy(cpos + 3 * v, pp + 3 * (size_t)h->ids[ki - 1][v], 3 * sizeof(double));
    }
    index = flann_build_index_double(cpos, (int)nc, 3, &speedup, &fp);
    if (!index) {
        st = relief_fail(err, RELIEF_E_INTERNAL, "FLANN could not index a hierarchy level");
        goto done;
    }
    for (size_t v = 0; v < nf; ++v) {
        const uint32_t f = h->ids[ki][v];
        int idx;
        double dist;
        if (loc[f] != UINT32_MAX) {
            h->parent[ki][v] = loc[f];
            continue;
        }
        if (flann_find_nearest_neighbors_index_double(index, (double *)(pp + 3 * (size_t)f), 1,
                                                      &idx, &dist, 1, &fp) != 0) {
            st = relief_fail(err, RELIEF_E_INTERNAL, "FLANN search failed in the hierarchy");
            goto done;
        }
        h->parent[ki][v] = (uint32_t)idx;
    }
done:
    if (index)
        flann_free_index_double(index, &fp);
    free(cpos);
    free(loc);
    return st;
}

/* The mean length of level k's edges (index ki) on the base. */
static relief_status mean_edge(relief_hierarchy *h, int ki, relief_error *err)
{
    const relief_mesh *m = h->level[ki]->mesh;
    const double *pp = h->full->proj;
    relief_adjacency adj;
    double sum = 0.0;
    size_t n = 0;
    relief_status st = relief_mesh_adjacency(m, &adj, err);
    if (st != RELIEF_OK)
        return st;
    for (size_t v = 0; v < m->nv; ++v)
        for (uint32_t i = adj.start[v]; i < adj.start[v + 1]; ++i) {
            const uint32_t u = adj.nbr[i];
            double d[3];
            if (u < v)
                continue;
            sub3(pp + 3 * (size_t)h->ids[ki][v], pp + 3 * (size_t)h->ids[ki][u], d);
            sum += sqrt(dot3(d, d));
            ++n;
        }
    relief_adjacency_free(&adj);
    h->sigma[ki] = n ? sum / (double)n : h->full->spacing;
    return RELIEF_OK;
}

/* Coarse level k (1 <= k < levels, stored at index k - 1): the vertices
 * whose first level is at most k, retriangulated on the base, with their
 * ids into the full surface (nv + 1 uint32_t). keep is an nv-byte scratch
 * mask. Lowers first_level for the vertices the level could not drop. */
static relief_status build_coarse_level(relief_hierarchy *h, int k, uint8_t *keep,
                                        relief_error *err)
{
    const relief_surface *s = h->full;
    const size_t nv = s->mesh->nv;
    const int levels = h->levels;
    relief_status st;

    for (size_t v = 0; v < nv; ++v)
        keep[v] = h->first_level[v] <= k;
    h->ids[k - 1] = malloc((nv + 1) * sizeof(uint32_t));
    if (!h->ids[k - 1])
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a hierarchy level");
    /* A maximal disc set of radius r leaves no empty circle much wider
     * than r: triangles up to 2 r plus the finest level's own limit. */
    st = relief_surface_level(s, keep, s->alpha + 2.0 * h->radius[k - 1], &h->level[k - 1],
                              h->ids[k - 1], err);
    if (st != RELIEF_OK) {
        relief_fail_prefix(err, "hierarchy level %d of %d", k, levels);
        return st;
    }
    /* A free-form level keeps the vertices it could not collapse
     * away: they belong to it and so to every finer level. */
    for (size_t v = 0; v < h->level[k - 1]->mesh->nv; ++v) {
        uint8_t *f = h->first_level + h->ids[k - 1][v];
        if (*f > k)
            *f = (uint8_t)k;
    }
    if (h->level[k - 1]->n_samples == 0 || h->level[k - 1]->n_targets == 0)
        return relief_fail(err, RELIEF_E_MESH,
                           "hierarchy level %d of %d has %zu samples and %zu targets; "
                           "use fewer levels", k, levels, h->level[k - 1]->n_samples,
                           h->level[k - 1]->n_targets);
    return RELIEF_OK;
}

/* The finest level is the full surface itself (identity ids); then every
 * level's parent links (levels 1..) and mean edge length on the base. */
static relief_status finish_levels(relief_hierarchy *h, relief_error *err)
{
    const size_t nv = h->full->mesh->nv;
    const int levels = h->levels;
    relief_status st;

    h->level[levels - 1] = (relief_surface *)h->full;
    h->ids[levels - 1] = malloc((nv + 1) * sizeof(uint32_t));
    if (!h->ids[levels - 1])
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a hierarchy level");
    for (size_t v = 0; v < nv; ++v)
        h->ids[levels - 1][v] = (uint32_t)v;
    for (int k = 0; k < levels; ++k) {
        st = k ? link_level(h, k, err) : RELIEF_OK;
        if (st == RELIEF_OK)
            st = mean_edge(h, k, err);
        if (st != RELIEF_OK)
            return st;
    }
    return RELIEF_OK;
}

relief_status relief_hierarchy_build(const relief_surface *s, int levels,
                                     relief_hierarchy **out, relief_error *err)
{
    const size_t nv = s->mesh->nv;
    relief_hierarchy *h;
    uint8_t *keep = NULL;
    relief_status st;

    if (levels < 2 || levels > RELIEF_MAX_LEVELS)
        return relief_fail(err, RELIEF_E_RANGE, "levels %d is outside 2..%d", levels,
                           RELIEF_MAX_LEVELS);
    if (nv < (size_t)levels * 16)
        return relief_fail(err, RELIEF_E_MESH,
                           "the surface has %zu vertices: too few for %d levels (at least "
                           "16 per level)", nv, levels);
    h = calloc(1, sizeof *h);
    if (!h)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a hierarchy");
    h->levels = levels;
    h->full = s;
    h->first_level = malloc(nv);
    keep = malloc(nv);
    if (!h->first_level || !keep) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a hierarchy");
        goto fail;
    }
    st = plan_levels(s, levels, h->first_level, h->radius, err);
    if (st != RELIEF_OK)
        goto fail;
    for (int k = 1; k < levels; ++k) {
        st = build_coarse_level(h, k, keep, err);
        if (st != RELIEF_OK)
            goto fail;
    }
    st = finish_levels(h, err);
    if (st != RELIEF_OK)
        goto fail;
    free(keep);
    *out = h;
    return RELIEF_OK;
fail:
    free(keep);
    relief_hierarchy_destroy(h);
    return st;
}
