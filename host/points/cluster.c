/* Surface clustering, direction field and tangent grids (paper 002, 3.2-3.3). */
#include "points/cluster.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/linalg.h"

#define EVEN_NEIGHBOURS 8

static double dist2(const double *a, const double *b)
{
    const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return dx * dx + dy * dy + dz * dz;
}

/* Pauly's split: through the centroid, across the axis of largest
 * variance. Parts are emitted in a fixed (stack) order. */
static size_t bsp(const double *pos, size_t n, size_t max_size, uint32_t *idx, uint32_t *label,
                  size_t *stack)
{
    size_t top = 0, m = 0;
    for (size_t i = 0; i < n; ++i)
        idx[i] = (uint32_t)i;
    stack[top++] = 0, stack[top++] = n;
    while (top) {
        const size_t hi = stack[--top], lo = stack[--top];
        double c[3] = {0, 0, 0}, cov[9] = {0}, eval[3], evec[9], ax[3];
        size_t i, j;
        if (hi - lo <= max_size) {
            for (i = lo; i < hi; ++i)
                label[idx[i]] = (uint32_t)m;
            ++m;
            continue;
        }
        for (i = lo; i < hi; ++i)
            for (int a = 0; a < 3; ++a)
                c[a] += pos[3 * (size_t)idx[i] + a];
        for (int a = 0; a < 3; ++a)
            c[a] /= (double)(hi - lo);
        for (i = lo; i < hi; ++i) {
            const double *p = pos + 3 * (size_t)idx[i];
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b)
                    cov[3 * a + b] += (p[a] - c[a]) * (p[b] - c[b]);
        }
        relief_sym3_eigen(cov, eval, evec);
        for (int a = 0; a < 3; ++a)
            ax[a] = evec[3 * a];
        i = lo, j = hi;
        while (i < j) {
            const double *p = pos + 3 * (size_t)idx[i];
            if ((p[0] - c[0]) * ax[0] + (p[1] - c[1]) * ax[1] + (p[2] - c[2]) * ax[2] < 0) {
                ++i;
            } else {
                const uint32_t t = idx[i];
                idx[i] = idx[--j], idx[j] = t;
            }
        }
        if (i == lo || i == hi) /* all points coincide: halve by index */
            i = lo + (hi - lo) / 2;
        stack[top++] = lo, stack[top++] = i;
        stack[top++] = i, stack[top++] = hi;
    }
    return m;
}

static void centroids(const double *pos, size_t n, const uint32_t *label, size_t m, double *cen,
                      size_t *count)
{
    memset(cen, 0, 3 * m * sizeof *cen);
    memset(count, 0, m * sizeof *count);
    for (size_t i = 0; i < n; ++i) {
        for (int a = 0; a < 3; ++a)
            cen[3 * (size_t)label[i] + a] += pos[3 * i + a];
        ++count[label[i]];
    }
    for (size_t k = 0; k < m; ++k)
        for (int a = 0; a < 3; ++a)
            cen[3 * k + a] /= count[k] ? (double)count[k] : 1.0;
}

/* The paper's evening-out, with its neighbourhood N_i taken as the 8
 * nearest centroids (no radius to tune). */
static void even_out(const double *pos, size_t n, uint32_t *label, size_t m, const double *cen,
                     uint32_t *near)
{
    for (size_t i = 0; i < m; ++i) {
        double best[EVEN_NEIGHBOURS + 1];
        uint32_t *nb = near + i * (EVEN_NEIGHBOURS + 1);
        int got = 0;
        nb[got] = (uint32_t)i, best[got++] = 0;
        for (size_t j = 0; j < m; ++j) {
            double d;
            int k;
            if (j == i)
                continue;
            d = dist2(cen + 3 * i, cen + 3 * j);
            if (got == EVEN_NEIGHBOURS + 1 && d >= best[got - 1])
                continue;
            k = got < EVEN_NEIGHBOURS + 1 ? got++ : got - 1;
            while (k > 1 && best[k - 1] > d) {
                best[k] = best[k - 1], nb[k] = nb[k - 1];
                --k;
            }
            best[k] = d, nb[k] = (uint32_t)j;
        }
        for (int k = got; k < EVEN_NEIGHBOURS + 1; ++k)
            nb[k] = (uint32_t)i;
    }
    for (size_t p = 0; p < n; ++p) {
        const uint32_t *nb = near + (size_t)label[p] * (EVEN_NEIGHBOURS + 1);
        uint32_t b = nb[0];
        double bd = dist2(pos + 3 * p, cen + 3 * (size_t)b);
        for (int k = 1; k < EVEN_NEIGHBOURS + 1; ++k) {
            const double d = dist2(pos + 3 * p, cen + 3 * (size_t)nb[k]);
            if (d < bd || (d == bd && nb[k] < b))
                bd = d, b = nb[k];
        }
        label[p] = b;
    }
}

static void cross3(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* v projected on the plane of unit normal nn, normalised; a fixed
 * perpendicular when v is (nearly) along nn. */
static void transport(const double v[3], const double nn[3], double out[3])
{
    const double d = v[0] * nn[0] + v[1] * nn[1] + v[2] * nn[2];
    for (int a = 0; a < 3; ++a)
        out[a] = v[a] - d * nn[a];
    if (relief_normalize3(out) < 1e-6) {
        double w[3];
        relief_perp_basis(nn, out, w);
    }
}

/* Prim's algorithm on the complete graph of the centroids (O(m^2), m the
 * clusters: a few thousand at most for a million points). */
static void direction_field(relief_pclusters *c, const size_t *count, double *key, uint32_t *parent,
                            uint8_t *done)
{
    const size_t m = c->m;
    for (size_t i = 0; i < m; ++i)
        key[i] = INFINITY, parent[i] = UINT32_MAX, done[i] = 0;
    for (size_t added = 0; added < m; ++added) {
        size_t b = SIZE_MAX;
        double *f;
        for (size_t i = 0; i < m; ++i) {
            if (done[i])
                continue;
            if (b == SIZE_MAX || key[i] < key[b] ||
                (key[i] == key[b] && isinf(key[i]) && count[i] > count[b]))
                b = i;
        }
        done[b] = 1;
        f = c->frame + 9 * b;
        if (parent[b] == UINT32_MAX) {
            const double *nn = f + 6;
            double ax[3] = {0, 0, 0};
            int a = 0;
            for (int k = 1; k < 3; ++k)
                if (fabs(nn[k]) < fabs(nn[a]))
                    a = k;
            ax[a] = 1;
            transport(ax, nn, f + 3);
        } else {
            transport(c->frame + 9 * (size_t)parent[b] + 3, f + 6, f + 3);
        }
        cross3(f + 3, f + 6, f);
        relief_normalize3(f);
        for (size_t i = 0; i < m; ++i) {
            double d;
            if (done[i])
                continue;
            d = dist2(c->centre + 3 * b, c->centre + 3 * i);
            if (d < key[i])
                key[i] = d, parent[i] = (uint32_t)b;
        }
    }
}

relief_status relief_pclusters_make(const double *pos, const double *nrm, size_t n,
                                    size_t max_size, relief_pclusters *out, relief_error *err)
{
    relief_status st = RELIEF_E_NOMEM;
    relief_pclusters c = {0};
    uint32_t *idx = malloc(n * sizeof *idx), *near = NULL, *remap = NULL, *parent = NULL;
    /* Pending parts are disjoint and non-empty: at most n pairs. */
    size_t *stack = malloc(2 * (n + 1) * sizeof *stack);
    size_t *count = NULL, m0;
    double *cen0 = NULL, *key = NULL;
    uint8_t *done = NULL;
    c.label = malloc(n * sizeof *c.label);
    if (!idx || !stack || !c.label)
        goto fail;
    if (max_size < 1)
        max_size = 1;
    m0 = bsp(pos, n, max_size, idx, c.label, stack);
    cen0 = malloc(3 * m0 * sizeof *cen0);
    count = malloc(m0 * sizeof *count);
    near = malloc(m0 * (EVEN_NEIGHBOURS + 1) * sizeof *near);
    remap = malloc(m0 * sizeof *remap);
    if (!cen0 || !count || !near || !remap)
        goto fail;
    centroids(pos, n, c.label, m0, cen0, count);
    even_out(pos, n, c.label, m0, cen0, near);
    centroids(pos, n, c.label, m0, cen0, count);
    for (size_t k = 0; k < m0; ++k)
        remap[k] = count[k] ? (uint32_t)c.m++ : UINT32_MAX;
    for (size_t i = 0; i < n; ++i)
        c.label[i] = remap[c.label[i]];
    c.centre = malloc(3 * c.m * sizeof *c.centre);
    c.frame = calloc(9 * c.m, sizeof *c.frame);
    c.radius = calloc(c.m, sizeof *c.radius);
    key = malloc(c.m * sizeof *key);
    parent = malloc(c.m * sizeof *parent);
    done = malloc(c.m);
    if (!c.centre || !c.frame || !c.radius || !key || !parent || !done)
        goto fail;
    centroids(pos, n, c.label, c.m, c.centre, count);
    for (size_t i = 0; i < n; ++i) {
        const size_t k = c.label[i];
        const double d = sqrt(dist2(pos + 3 * i, c.centre + 3 * k));
        for (int a = 0; a < 3; ++a)
            c.frame[9 * k + 6 + a] += nrm[3 * i + a];
        if (d > c.radius[k])
            c.radius[k] = d;
    }
    for (size_t k = 0; k < c.m; ++k) {
        if (relief_normalize3(c.frame + 9 * k + 6) == 0) /* normals cancel: any unit one */
            c.frame[9 * k + 8] = 1;
        c.mean_radius += c.radius[k] / (double)c.m;
    }
    direction_field(&c, count, key, parent, done);
    *out = c;
    c = (relief_pclusters){0};
    st = RELIEF_OK;
fail:
    if (st != RELIEF_OK)
        relief_fail(err, st, "cannot allocate the clusters of %zu points", n);
    relief_pclusters_free(&c);
    free(idx), free(stack), free(near), free(remap), free(parent), free(count), free(cen0);
    free(key), free(done);
    return st;
}

void relief_pclusters_free(relief_pclusters *c)
{
    if (!c)
        return;
    free(c->label), free(c->centre), free(c->frame), free(c->radius);
    *c = (relief_pclusters){0};
}

relief_status relief_pbucket_make(const double *pos, size_t n, double cell, relief_pbucket *b,
                                  relief_error *err)
{
    double hi[3];
    size_t cells;
    *b = (relief_pbucket){0};
    b->pos = pos;
    for (int a = 0; a < 3; ++a)
        b->lo[a] = hi[a] = n ? pos[a] : 0;
    for (size_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) {
            if (pos[3 * i + a] < b->lo[a])
                b->lo[a] = pos[3 * i + a];
            if (pos[3 * i + a] > hi[a])
                hi[a] = pos[3 * i + a];
        }
    for (;;) {
        double total = 1;
        for (int a = 0; a < 3; ++a)
            total *= floor((hi[a] - b->lo[a]) / cell) + 1;
        if (total <= 2.0 * (double)n + 8)
            break;
        cell *= 1.5;
    }
    b->cell = cell;
    cells = 1;
    for (int a = 0; a < 3; ++a) {
        b->dim[a] = (size_t)floor((hi[a] - b->lo[a]) / cell) + 1;
        cells *= b->dim[a];
    }
    b->start = calloc(cells + 1, sizeof *b->start);
    b->item = malloc((n ? n : 1) * sizeof *b->item);
    if (!b->start || !b->item) {
        relief_pbucket_free(b);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a bucket grid of %zu cells",
                           cells);
    }
#define CELL_OF(p)                                                                       \
    ((((size_t)(((p)[2] - b->lo[2]) / b->cell)) * b->dim[1] +                           \
      (size_t)(((p)[1] - b->lo[1]) / b->cell)) * b->dim[0] +                            \
     (size_t)(((p)[0] - b->lo[0]) / b->cell))
    for (size_t i = 0; i < n; ++i)
        ++b->start[CELL_OF(pos + 3 * i) + 1];
    for (size_t k = 0; k < cells; ++k)
        b->start[k + 1] += b->start[k];
    for (size_t i = 0; i < n; ++i)
        b->item[b->start[CELL_OF(pos + 3 * i)]++] = (uint32_t)i;
    for (size_t k = cells; k > 0; --k)
        b->start[k] = b->start[k - 1];
    b->start[0] = 0;
#undef CELL_OF
    return RELIEF_OK;
}

void relief_pbucket_free(relief_pbucket *b)
{
    if (!b)
        return;
    free(b->start), free(b->item);
    *b = (relief_pbucket){0};
}

size_t relief_pbucket_query(const relief_pbucket *b, const double q[3], double r, uint32_t **buf,
                            size_t *cap)
{
    size_t lo[3], hi[3], got = 0;
    const double r2 = r * r;
    for (int a = 0; a < 3; ++a) {
        const double l = floor((q[a] - r - b->lo[a]) / b->cell);
        const double h = floor((q[a] + r - b->lo[a]) / b->cell);
        if (h < 0 || l >= (double)b->dim[a])
            return 0;
        lo[a] = l < 0 ? 0 : (size_t)l;
        hi[a] = h >= (double)b->dim[a] ? b->dim[a] - 1 : (size_t)h;
    }
    for (size_t z = lo[2]; z <= hi[2]; ++z)
        for (size_t y = lo[1]; y <= hi[1]; ++y)
            for (size_t x = lo[0]; x <= hi[0]; ++x) {
                const size_t k = (z * b->dim[1] + y) * b->dim[0] + x;
                for (size_t j = b->start[k]; j < b->start[k + 1]; ++j) {
                    const uint32_t p = b->item[j];
                    if (dist2(b->pos + 3 * (size_t)p, q) > r2)
                        continue;
                    if (got == *cap) {
                        const size_t nc = *cap ? 2 * *cap : 256;
                        uint32_t *nb = realloc(*buf, nc * sizeof *nb);
                        if (!nb)
                            return SIZE_MAX;
                        *buf = nb, *cap = nc;
                    }
                    (*buf)[got++] = p;
                }
            }
    return got;
}

void relief_ptangent(const double p[3], const double c[3], const double f[9], double *s,
                     double *t)
{
    const double d[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
    *s = d[0] * f[0] + d[1] * f[1] + d[2] * f[2];
    *t = d[0] * f[3] + d[1] * f[4] + d[2] * f[5];
}

double relief_pgrid_reach(int gn, double h)
{
    return (gn - 1) / 2.0 * h * sqrt(2.0) + h;
}

static int grow(void **p, size_t *cap, size_t need, size_t size)
{
    if (need > *cap) {
        const size_t nc = need > 2 * *cap ? need : 2 * *cap;
        void *q = realloc(*p, nc * size);
        if (!q)
            return -1;
        *p = q, *cap = nc;
    }
    return 0;
}

/* The candidates whose normals face the grid's (frame f: 9, its normal
 * last) kept in g->pt, in candidate order, with their tangent-plane
 * coordinates about c in g->st (2 each, pos's units); returns how many. */
static size_t pgrid_keep(const double *pos, const double *nrm, const uint32_t *cand, size_t nc,
                         const double c[3], const double f[9], relief_pgrid_weights *g)
{
    size_t kept = 0;
    for (size_t j = 0; j < nc; ++j) {
        const double *nn = nrm + 3 * (size_t)cand[j];
        if (nn[0] * f[6] + nn[1] * f[7] + nn[2] * f[8] < RELIEF_PGRID_NORMAL_COS)
            continue;
        relief_ptangent(pos + 3 * (size_t)cand[j], c, f, g->st + 2 * kept, g->st + 2 * kept + 1);
        g->pt[kept++] = cand[j];
    }
    return kept;
}

/* g->start (gn^2 + 1) as the prefix sums of how many kept points reach
 * each node (within h; k: the centre node's index), an empty node given
 * one slot and counted in *empty. */
static void pgrid_count(relief_pgrid_weights *g, size_t kept, int gn, double h, int k,
                        size_t *empty)
{
    const size_t nodes = (size_t)gn * (size_t)gn;
    memset(g->start, 0, (nodes + 1) * sizeof *g->start);
    for (size_t j = 0; j < kept; ++j) {
        const double s = g->st[2 * j] / h + k, t = g->st[2 * j + 1] / h + k;
        const int a0 = (int)fmax(ceil(s - 1), 0), a1 = (int)fmin(floor(s + 1), gn - 1);
        const int b0 = (int)fmax(ceil(t - 1), 0), b1 = (int)fmin(floor(t + 1), gn - 1);
        for (int b = b0; b <= b1; ++b)
            for (int a = a0; a <= a1; ++a)
                if ((s - a) * (s - a) + (t - b) * (t - b) <= 1.0)
                    ++g->start[(size_t)b * (size_t)gn + (size_t)a + 1];
    }
    for (size_t q = 0; q < nodes; ++q) {
        if (!g->start[q + 1])
            g->start[q + 1] = 1, ++*empty;
        g->start[q + 1] += g->start[q];
    }
}

/* Each node's (point, Gaussian weight) pairs, sigma h / 2, in candidate
 * order, into the slots pgrid_count laid out (g->fill: each node's next
 * slot); the uses of points that allowed does not flag are counted in
 * *foreign. The weights are not yet normalised. */
static void pgrid_fill(relief_pgrid_weights *g, size_t kept, int gn, double h, int k,
                       const uint8_t *allowed, size_t *foreign)
{
    for (size_t j = 0; j < kept; ++j) {
        const double s = g->st[2 * j] / h + k, t = g->st[2 * j + 1] / h + k;
        const int a0 = (int)fmax(ceil(s - 1), 0), a1 = (int)fmin(floor(s + 1), gn - 1);
        const int b0 = (int)fmax(ceil(t - 1), 0), b1 = (int)fmin(floor(t + 1), gn - 1);
        for (int b = b0; b <= b1; ++b)
            for (int a = a0; a <= a1; ++a) {
                const double d2 = (s - a) * (s - a) + (t - b) * (t - b);
                const size_t q = (size_t)b * (size_t)gn + (size_t)a;
                if (d2 > 1.0)
                    continue;
                g->point[g->fill[q]] = g->pt[j];
                g->w[g->fill[q]++] = (float)exp(-2.0 * d2); /* sigma = h / 2 */
                if (allowed && !allowed[g->pt[j]])
                    ++*foreign;
            }
    }
}

/* Every node's weights made to sum to 1; an empty node's one slot given
 * its nearest kept point (the first of the nearest) with weight 1, counted
 * in *foreign when allowed does not flag it. */
static void pgrid_normalise(relief_pgrid_weights *g, size_t kept, int gn, double h, int k,
                            const uint8_t *allowed, size_t *foreign)
{
    for (int b = 0; b < gn; ++b)
        for (int a = 0; a < gn; ++a) {
            const size_t q = (size_t)b * (size_t)gn + (size_t)a;
            double sum = 0;
            if (g->fill[q] == g->start[q]) { /* empty: the nearest candidate */
                double best = INFINITY;
                uint32_t nearest = g->pt[0];
                for (size_t j = 0; j < kept; ++j) {
                    const double ds = g->st[2 * j] / h + k - a, dt = g->st[2 * j + 1] / h + k - b;
                    if (ds * ds + dt * dt < best)
                        best = ds * ds + dt * dt, nearest = g->pt[j];
                }
                g->point[g->start[q]] = nearest, g->w[g->start[q]] = 1.0f;
                if (allowed && !allowed[nearest])
                    ++*foreign;
                continue;
            }
            for (size_t j = g->start[q]; j < g->start[q + 1]; ++j)
                sum += g->w[j];
            for (size_t j = g->start[q]; j < g->start[q + 1]; ++j)
                g->w[j] = (float)(g->w[j] / sum);
        }
}

int relief_pgrid_weigh(const double *pos, const double *nrm, const uint32_t *cand, size_t nc,
                       const double c[3], const double f[9], int gn, double h,
                       const uint8_t *allowed, relief_pgrid_weights *g, size_t *empty,
                       size_t *foreign)
{
    const int k = (gn - 1) / 2;
    const size_t nodes = (size_t)gn * (size_t)gn;
    size_t kept;
    *empty = 0, *foreign = 0;
    if (!g->start && !(g->start = malloc((nodes + 1) * sizeof *g->start)))
        return -1;
    if (grow((void **)&g->st, &g->st_cap, 2 * nc + 2, sizeof *g->st) ||
        grow((void **)&g->pt, &g->pt_cap, nc + 1, sizeof *g->pt))
        return -1;
    kept = pgrid_keep(pos, nrm, cand, nc, c, f, g);
    if (!kept)
        return 0;
    /* Each candidate reaches the nodes within h of it, a 3 x 3 block at
     * most: count per node, then fill, so that a node's points stay in
     * candidate order (deterministic). An empty node gets one slot. */
    pgrid_count(g, kept, gn, h, k, empty);
    if (grow((void **)&g->point, &g->cap, g->start[nodes], sizeof *g->point))
        return -1;
    if (grow((void **)&g->w, &g->w_cap, g->start[nodes], sizeof *g->w))
        return -1;
    if (grow((void **)&g->fill, &g->fill_cap, nodes, sizeof *g->fill))
        return -1;
    memcpy(g->fill, g->start, nodes * sizeof *g->fill);
    pgrid_fill(g, kept, gn, h, k, allowed, foreign);
    pgrid_normalise(g, kept, gn, h, k, allowed, foreign);
    return 1;
}

void relief_pgrid_weights_free(relief_pgrid_weights *g)
{
    if (!g)
        return;
    free(g->start), free(g->point), free(g->w), free(g->st), free(g->pt), free(g->fill);
    *g = (relief_pgrid_weights){0};
}
