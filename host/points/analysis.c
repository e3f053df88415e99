/* k-NN, covariance normals and their orientation (analysis.h). */
#include "points/analysis.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/knn.h"
#include "base/linalg.h"
#include "base/parallel.h"
#include "base/vec3.h"

#define KNN_CHUNK 4096

relief_status relief_knn_graph_build(const double *pos, size_t n, int k, int threads,
                                     relief_knn_graph *g, relief_error *err)
{
    struct FLANNParameters fp = relief_knn_exact_params();
    flann_index_t index = NULL;
    int *idx = NULL;
    double *d2 = NULL;
    float speedup;
    relief_status st = RELIEF_OK;

    memset(g, 0, sizeof *g);
    if (k < 3 || k > 64 || n <= (size_t)k || n > INT32_MAX)
        return relief_fail(err, RELIEF_E_RANGE, "%zu points are too few for %d nearest "
                           "neighbours (k in 3..64, more points than k)", n, k);
    g->nbr = malloc(n * (size_t)k * sizeof *g->nbr);
    g->d2 = malloc(n * (size_t)k * sizeof *g->d2);
    idx = malloc((size_t)KNN_CHUNK * (k + 1) * sizeof *idx);
    d2 = malloc((size_t)KNN_CHUNK * (k + 1) * sizeof *d2);
    if (!g->nbr || !g->d2 || !idx || !d2) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the %d-NN graph of %zu points",
                         k, n);
        goto done;
    }
    index = flann_build_index_double((double *)pos, (int)n, 3, &speedup, &fp);
    /* The queries of a chunk on FLANN's threads: each query's neighbours
     * alone, the same whatever their number. */
    fp.cores = threads < 1 ? 1 : threads;
    if (!index) {
        st = relief_fail(err, RELIEF_E_NOMEM, "FLANN could not index %zu points", n);
        goto done;
    }
    for (size_t s = 0; s < n; s += KNN_CHUNK) {
        int m = (int)(n - s < KNN_CHUNK ? n - s : KNN_CHUNK);
        if (flann_find_nearest_neighbors_index_double(index, (double *)pos + 3 * s, m, idx, d2,
                                                      k + 1, &fp) != 0) {
            st = relief_fail(err, RELIEF_E_INTERNAL, "FLANN's k-NN search failed");
            goto done;
        }
        for (int q = 0; q < m; ++q) {
            size_t i = s + (size_t)q;
            int w = 0;
            /* Drop the point itself (a duplicate may come first instead). */
            for (int r = 0; r <= k && w < k; ++r) {
                size_t j = (size_t)idx[(size_t)q * (k + 1) + r];
                if (j == i)
                    continue;
                g->nbr[i * k + w] = (uint32_t)j;
                g->d2[i * k + w] = d2[(size_t)q * (k + 1) + r];
                ++w;
            }
        }
    }
    g->n = n;
    g->k = k;
done:
    if (index)
        flann_free_index_double(index, &fp);
    free(idx);
    free(d2);
    if (st != RELIEF_OK)
        relief_knn_graph_free(g);
    return st;
}

void relief_knn_graph_free(relief_knn_graph *g)
{
    free(g->nbr);
    free(g->d2);
    memset(g, 0, sizeof *g);
}

double relief_knn_spacing(const relief_knn_graph *g)
{
    double *d = malloc(g->n * sizeof *d), s;
    if (!d || !g->n) {
        free(d);
        return 0.0;
    }
    for (size_t i = 0; i < g->n; ++i)
        d[i] = sqrt(g->d2[i * g->k]);
    s = relief_select_median(d, g->n);
    free(d);
    return s;
}

/* A binary min-heap of (weight, vertex, parent) for Prim's algorithm. */
typedef struct heap_item {
    double w;
    uint32_t v, from;
} heap_item;

typedef struct heap {
    heap_item *a;
    size_t n, cap;
} heap;

static int heap_less(const heap_item *x, const heap_item *y)
{
    /* Ties by vertex then parent, so that the tree does not depend on
     * insertion order beyond the graph's own. */
    if (x->w != y->w)
        return x->w < y->w;
    if (x->v != y->v)
        return x->v < y->v;
    return x->from < y->from;
}

static int heap_push(heap *h, heap_item it)
{
    size_t i;
    if (h->n == h->cap) {
        size_t cap = h->cap ? 2 * h->cap : 1024;
        heap_item *a = realloc(h->a, cap * sizeof *a);
        if (!a)
            return 0;
        h->a = a;
        h->cap = cap;
    }
    i = h->n++;
    while (i > 0 && heap_less(&it, &h->a[(i - 1) / 2])) {
        h->a[i] = h->a[(i - 1) / 2];
        i = (i - 1) / 2;
    }
    h->a[i] = it;
    return 1;
}

static heap_item heap_pop(heap *h)
{
    heap_item top = h->a[0], last = h->a[--h->n];
    size_t i = 0;
    for (;;) {
        size_t c = 2 * i + 1;
        if (c >= h->n)
            break;
        if (c + 1 < h->n && heap_less(&h->a[c + 1], &h->a[c]))
            ++c;
        if (!heap_less(&h->a[c], &last))
            break;
        h->a[i] = h->a[c];
        i = c;
    }
    if (h->n)
        h->a[i] = last;
    return top;
}

/* Symmetric adjacency of the k-NN graph as CSR (i in j's list when j is in
 * i's or i in j's), so that Prim's tree spans what the graph connects. */
static relief_status sym_adjacency(const relief_knn_graph *g, uint32_t **start_out,
                                   uint32_t **adj_out, relief_error *err)
{
    size_t n = g->n, k = (size_t)g->k;
    uint32_t *deg = calloc(n + 1, sizeof *deg), *adj = NULL, *fill = NULL;
    if (!deg)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the neighbour graph");
    for (size_t i = 0; i < n; ++i)
        for (size_t r = 0; r < k; ++r) {
            ++deg[i + 1];
            ++deg[g->nbr[i * k + r] + 1];
        }
    for (size_t i = 0; i < n; ++i)
        deg[i + 1] += deg[i];
    adj = malloc((size_t)deg[n] * sizeof *adj);
    fill = malloc(n * sizeof *fill);
    if (!adj || !fill) {
        free(deg), free(adj), free(fill);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the neighbour graph");
    }
    memcpy(fill, deg, n * sizeof *fill);
    for (size_t i = 0; i < n; ++i)
        for (size_t r = 0; r < k; ++r) {
            uint32_t j = g->nbr[i * k + r];
            adj[fill[i]++] = j;
            adj[fill[j]++] = (uint32_t)i;
        }
    free(fill);
    *start_out = deg;
    *adj_out = adj;
    return RELIEF_OK;
}

/* Hoppe's propagation: Prim's minimum spanning tree from the point farthest
 * along `view` in each component, flipping each normal to agree with its
 * tree parent's. */
static relief_status orient_mst(const double *pos, const relief_knn_graph *g, const double *hint,
                                double *nrm, relief_error *err)
{
    static const double view[3] = {0.0, 0.0, 1.0};
    size_t n = g->n;
    uint32_t *start = NULL, *adj = NULL;
    uint8_t *done = calloc(n, 1);
    heap h = {0};
    relief_status st;

    if (!done)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the orientation");
    st = sym_adjacency(g, &start, &adj, err);
    if (st != RELIEF_OK) {
        free(done);
        return st;
    }
    /* Points with a hint are fixed already: they seed the tree. */
    for (size_t i = 0; hint && i < n; ++i)
        if (hint[3 * i] != 0.0 || hint[3 * i + 1] != 0.0 || hint[3 * i + 2] != 0.0) {
            done[i] = 1;
            for (uint32_t e = start[i]; e < start[i + 1]; ++e)
                if (!heap_push(&h, (heap_item){1.0 - fabs(dot3(nrm + 3 * i, nrm + 3 * (size_t)adj[e])),
                                               adj[e], (uint32_t)i}))
                    goto nomem;
        }
    for (;;) {
        while (h.n) {
            heap_item it = heap_pop(&h);
            if (done[it.v])
                continue;
            done[it.v] = 1;
            if (dot3(nrm + 3 * (size_t)it.v, nrm + 3 * (size_t)it.from) < 0.0)
                for (int c = 0; c < 3; ++c)
                    nrm[3 * (size_t)it.v + c] = -nrm[3 * (size_t)it.v + c];
            for (uint32_t e = start[it.v]; e < start[it.v + 1]; ++e)
                if (!done[adj[e]] &&
                    !heap_push(&h, (heap_item){1.0 - fabs(dot3(nrm + 3 * (size_t)it.v,
                                                                nrm + 3 * (size_t)adj[e])),
                                               adj[e], it.v}))
                    goto nomem;
        }
        /* A new component: its seed is its point farthest along view. */
        {
            size_t seed = n;
            for (size_t i = 0; i < n; ++i)
                if (!done[i] && (seed == n || dot3(pos + 3 * i, view) > dot3(pos + 3 * seed, view)))
                    seed = i;
            if (seed == n)
                break;
            if (dot3(nrm + 3 * seed, view) < 0.0)
                for (int c = 0; c < 3; ++c)
                    nrm[3 * seed + c] = -nrm[3 * seed + c];
            done[seed] = 1;
            for (uint32_t e = start[seed]; e < start[seed + 1]; ++e)
                if (!heap_push(&h, (heap_item){1.0 - fabs(dot3(nrm + 3 * seed,
                                                               nrm + 3 * (size_t)adj[e])),
                                               adj[e], (uint32_t)seed}))
                    goto nomem;
        }
    }
    free(h.a), free(done), free(start), free(adj);
    return RELIEF_OK;
nomem:
    free(h.a), free(done), free(start), free(adj);
    return relief_fail(err, RELIEF_E_NOMEM, "cannot grow the orientation tree of %zu points", n);
}

double relief_points_covariance(const double *pos, const relief_knn_graph *g, size_t i,
                                double centroid[3], double normal[3])
{
    size_t k = (size_t)g->k;
    double m[3] = {0, 0, 0}, c[9] = {0}, ev[3], evec[9], s;
    for (size_t r = 0; r <= k; ++r) {
        const double *q = pos + 3 * (r == k ? i : (size_t)g->nbr[i * k + r]);
        for (int a = 0; a < 3; ++a)
            m[a] += q[a];
    }
    for (int a = 0; a < 3; ++a)
        m[a] /= (double)(k + 1);
    for (size_t r = 0; r <= k; ++r) {
        const double *q = pos + 3 * (r == k ? i : (size_t)g->nbr[i * k + r]);
        double d[3];
        sub3(q, m, d);
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                c[3 * a + b] += d[a] * d[b];
    }
    relief_sym3_eigen(c, ev, evec);
    for (int a = 0; a < 3; ++a)
        normal[a] = evec[3 * a + 2];
    relief_normalize3(normal);
    if (centroid)
        memcpy(centroid, m, sizeof m);
    s = ev[0] + ev[1] + ev[2];
    return s > 0.0 ? fmax(ev[2], 0.0) / s : 0.0;
}

/* The covariance normals' shares (relief_points_normals): each point's
 * row alone, its sign from the viewpoint or its hint; free[i] set where
 * neither decides it. */
typedef struct normal_job {
    const double *pos, *hint, *viewpoint;
    const relief_knn_graph *g;
    double *nrm, *sigma;
    uint8_t *free;
} normal_job;

static int normal_share(void *ctx, size_t lo, size_t hi)
{
    const normal_job *j = ctx;
    for (size_t i = lo; i < hi; ++i) {
        double *n = j->nrm + 3 * i, sv = relief_points_covariance(j->pos, j->g, i, NULL, n);
        const double *h = j->hint ? j->hint + 3 * i : NULL;
        int flip = 0;
        if (j->sigma)
            j->sigma[i] = sv;
        j->free[i] = 0;
        if (j->viewpoint) {
            double d[3];
            sub3(j->viewpoint, j->pos + 3 * i, d);
            flip = dot3(d, n) < 0.0;
        } else if (h && (h[0] != 0.0 || h[1] != 0.0 || h[2] != 0.0)) {
            flip = dot3(h, n) < 0.0;
        } else {
            j->free[i] = 1;
        }
        if (flip)
            for (int a = 0; a < 3; ++a)
                n[a] = -n[a];
    }
    return 0;
}

relief_status relief_points_normals(const double *pos, const relief_knn_graph *g,
                                    const double *hint, const double *viewpoint, int threads,
                                    double *nrm, double *sigma, relief_error *err)
{
    size_t n = g->n;
    int any_free = 0;
    normal_job j = {pos, hint, viewpoint, g, nrm, sigma, malloc(n ? n : 1)};
    if (!j.free)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the normals of %zu points", n);
    relief_parallel_ranges(n, threads, normal_share, &j);
    for (size_t i = 0; i < n && !any_free; ++i)
        any_free = j.free[i];
    free(j.free);
    if (viewpoint || !any_free)
        return RELIEF_OK;
    return orient_mst(pos, g, hint, nrm, err);
}

int relief_points_spread(const double *pos, size_t n, const char **why)
{
    double m[3], ev[3], evec[9];
    relief_pca3(pos, n, NULL, m, ev, evec);
    if (!(ev[0] > 0.0)) {
        *why = "all points are at one place";
        return 0;
    }
    if (ev[1] < 1e-12 * ev[0]) { /* variances: 1e-6 of the extent squared */
        *why = "all points lie on a line (or a few points so far off that the rest look like one)";
        return 0;
    }
    *why = "";
    return 1;
}
