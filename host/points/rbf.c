#include "points/rbf.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/linalg.h"
#include "base/parallel.h"
#include "base/pool.h"
#include "base/sort.h"
#include "base/vec3.h"

#define MAX_LEVELS 16
#define DEFAULT_MAX_LEVELS 12
/* Cell coordinates are packed 21 bits each into one key; the grids refuse
 * point sets wider than CELL_SPAN cells so that clamping a far query into
 * the key's range never lands it next to a real cell. */
#define CELL_BITS 21
#define CELL_OFFSET (INT64_C(1) << (CELL_BITS - 1))
#define CELL_SPAN 262144.0 /* 2^18 */
#define CELL_EMPTY UINT64_MAX
#define NO_ITEM UINT32_MAX
/* Per centre of a level: position (3), g's quadratic form M (6: xx xy xz
 * yy yz zz), its linear part (3), its constant plus lambda (1). */
#define CW 13
#define CG_MAX_ITER 1000
#define CG_REL_TOL 1e-10 /* on the squared residual: |r| <= 1e-5 |b| */

/* ---- a hash of grid cells, each a chain of items ----------------------
 * One structure serves the levels' centres (built once, read by every
 * evaluation) and the hole fill's points (grown as points are added). */
typedef struct cell_hash {
    double origin[3], inv_h;
    uint64_t *key;  /* n_slots cell keys, CELL_EMPTY where free */
    uint32_t *head; /* n_slots: the last item inserted into the slot's cell */
    uint32_t *next; /* per item: the item inserted before it into its cell */
    size_t n_slots, n_cells, n_items, cap_items;
    int shift; /* 64 - log2(n_slots) */
} cell_hash;

static int64_t cell_coord(double v, double origin, double inv_h)
{
    double c = floor((v - origin) * inv_h);
    c = fmax(c, (double)-CELL_OFFSET);
    c = fmin(c, (double)(CELL_OFFSET - 1));
    return (int64_t)c;
}

static uint64_t cell_key(int64_t i, int64_t j, int64_t k)
{
    return (uint64_t)(i + CELL_OFFSET) << (2 * CELL_BITS) |
           (uint64_t)(j + CELL_OFFSET) << CELL_BITS | (uint64_t)(k + CELL_OFFSET);
}

static size_t hash_slot(const cell_hash *h, uint64_t key)
{
    return (size_t)((key * UINT64_C(0x9E3779B97F4A7C15)) >> h->shift);
}

static int hash_alloc_slots(cell_hash *h, size_t n_slots)
{
    h->key = malloc(n_slots * sizeof *h->key);
    h->head = malloc(n_slots * sizeof *h->head);
    if (!h->key || !h->head)
        return 0;
    for (size_t s = 0; s < n_slots; ++s)
        h->key[s] = CELL_EMPTY, h->head[s] = NO_ITEM;
    h->n_slots = n_slots;
    h->shift = 64;
    while (n_slots > 1)
        n_slots >>= 1, --h->shift;
    return 1;
}

static void hash_free(cell_hash *h)
{
    free(h->key);
    free(h->head);
    free(h->next);
    memset(h, 0, sizeof *h);
}

/* Cells of side `cell` from `origin`, room for about `items` items. */
static int hash_init(cell_hash *h, const double origin[3], double cell, size_t items)
{
    size_t n_slots = 16;
    memset(h, 0, sizeof *h);
    memcpy(h->origin, origin, sizeof h->origin);
    h->inv_h = 1.0 / cell;
    while (n_slots < 2 * items)
        n_slots *= 2;
    h->cap_items = items > 16 ? items : 16;
    h->next = malloc(h->cap_items * sizeof *h->next);
    if (!h->next || !hash_alloc_slots(h, n_slots)) {
        hash_free(h);
        return 0;
    }
    return 1;
}

/* The slot of key's cell, or the free slot where it would go. */
static size_t hash_find(const cell_hash *h, uint64_t key)
{
    size_t s = hash_slot(h, key), mask = h->n_slots - 1;
    while (h->key[s] != key && h->key[s] != CELL_EMPTY)
        s = (s + 1) & mask;
    return s;
}

/* The first item of cell (i, j, k), NO_ITEM when empty. */
static uint32_t hash_head(const cell_hash *h, int64_t i, int64_t j, int64_t k)
{
    size_t s = hash_find(h, cell_key(i, j, k));
    return h->head[s];
}

/* Item number h->n_items at x; 0 when out of memory. */
static int hash_insert(cell_hash *h, const double x[3])
{
    uint64_t key = cell_key(cell_coord(x[0], h->origin[0], h->inv_h),
                            cell_coord(x[1], h->origin[1], h->inv_h),
                            cell_coord(x[2], h->origin[2], h->inv_h));
    size_t s;
    if (h->n_items >= NO_ITEM)
        return 0;
    if (h->n_items == h->cap_items) {
        size_t cap = 2 * h->cap_items;
        uint32_t *next = realloc(h->next, cap * sizeof *next);
        if (!next)
            return 0;
        h->next = next, h->cap_items = cap;
    }
    if (2 * (h->n_cells + 1) > h->n_slots) {
        /* Rehash the cells; their chains stay as they are. */
        uint64_t *old_key = h->key;
        uint32_t *old_head = h->head;
        size_t old_n = h->n_slots;
        if (!hash_alloc_slots(h, 2 * old_n)) {
            free(h->key), free(h->head);
            h->key = old_key, h->head = old_head, h->n_slots = old_n;
            h->shift = 64;
            for (size_t n = old_n; n > 1; n >>= 1)
                --h->shift;
            return 0;
        }
        for (size_t o = 0; o < old_n; ++o)
            if (old_key[o] != CELL_EMPTY) {
                size_t t = hash_find(h, old_key[o]);
                h->key[t] = old_key[o], h->head[t] = old_head[o];
            }
        free(old_key), free(old_head);
    }
    s = hash_find(h, key);
    if (h->key[s] == CELL_EMPTY)
        h->key[s] = key, ++h->n_cells;
    h->next[h->n_items] = h->head[s];
    h->head[s] = (uint32_t)h->n_items++;
    return 1;
}

/* Items whose position (pos, 3 per item) lies within r of x, appended to
 * *out (grown as needed); the count, or (size_t)-1 when out of memory. */
static size_t hash_within(const cell_hash *h, const double *pos, const double x[3], double r,
                          uint32_t **out, size_t *cap)
{
    int64_t lo[3], hi[3];
    size_t n = 0;
    for (int a = 0; a < 3; ++a) {
        lo[a] = cell_coord(x[a] - r, h->origin[a], h->inv_h);
        hi[a] = cell_coord(x[a] + r, h->origin[a], h->inv_h);
    }
    for (int64_t i = lo[0]; i <= hi[0]; ++i)
        for (int64_t j = lo[1]; j <= hi[1]; ++j)
            for (int64_t k = lo[2]; k <= hi[2]; ++k)
                for (uint32_t it = hash_head(h, i, j, k); it != NO_ITEM; it = h->next[it]) {
                    double d[3];
                    sub3(pos + 3 * (size_t)it, x, d);
                    if (dot3(d, d) > r * r)
                        continue;
                    if (n == *cap) {
                        size_t c = *cap ? 2 * *cap : 64;
                        uint32_t *o = realloc(*out, c * sizeof *o);
                        if (!o)
                            return (size_t)-1;
                        *out = o, *cap = c;
                    }
                    (*out)[n++] = it;
                }
    return n;
}

/* ---- the model ------------------------------------------------------- */

typedef struct rbf_level {
    double rho, inv_rho;
    double lo[3], hi[3]; /* the centres' box grown by rho: f's support */
    size_t n;
    double *c;      /* n x CW: centre, g and lambda (CW above) */
    double *xyz;    /* n x 3: the centres alone, what a query scans */
    cell_hash grid; /* cells of side rho over the centres */
} rbf_level;

struct relief_rbf {
    int n_levels;
    rbf_level level[MAX_LEVELS];
};

relief_rbf_params relief_rbf_params_default(void)
{
    relief_rbf_params p = {0, 0.0, 0.0, 0};
    return p;
}

void relief_rbf_free(relief_rbf *f)
{
    if (!f)
        return;
    for (int l = 0; l < f->n_levels; ++l) {
        free(f->level[l].c);
        free(f->level[l].xyz);
        hash_free(&f->level[l].grid);
    }
    free(f);
}

/* g_c(c + d) + lambda_c of the centre c (CW doubles) and, when grad is not
 * NULL, its gradient. */
static double quadric(const double *c, const double d[3], double grad[3])
{
    const double *M = c + 3, *b = c + 9;
    double m[3];
    m[0] = M[0] * d[0] + M[1] * d[1] + M[2] * d[2];
    m[1] = M[1] * d[0] + M[3] * d[1] + M[4] * d[2];
    m[2] = M[2] * d[0] + M[4] * d[1] + M[5] * d[2];
    if (grad)
        for (int a = 0; a < 3; ++a)
            grad[a] = 2.0 * m[a] + b[a];
    return dot3(d, m) + dot3(b, d) + c[12];
}

/* Wendland's phi(r) = (1 - r)^4 (4 r + 1) and, since
 * phi'(r) = -20 r (1 - r)^3, grad phi(|d| / rho) = -20 (1 - r)^3 d / rho^2. */
static void level_add(const rbf_level *lv, const double x[3], double *f, double grad[3])
{
    double rho2 = lv->rho * lv->rho, g2 = -20.0 * lv->inv_rho * lv->inv_rho;
    const cell_hash *h = &lv->grid;
    int64_t ci[3];
    for (int a = 0; a < 3; ++a)
        if (x[a] < lv->lo[a] || x[a] > lv->hi[a])
            return;
    for (int a = 0; a < 3; ++a)
        ci[a] = cell_coord(x[a], h->origin[a], h->inv_h);
    /* Cells are rho wide: the ball of radius rho about x lies in the 27
     * around x's, and only about 20 of them meet it (gap[a][o]: how far x
     * is from the cell at offset o - 1 along axis a). The centres of a cell
     * are consecutive (fit_level sorts them), their positions apart from
     * the rest, so that the scan reads few cache lines. */
    double gap[3][3];
    for (int a = 0; a < 3; ++a) {
        double lo_a = h->origin[a] + (double)ci[a] * lv->rho;
        gap[a][0] = (x[a] - lo_a) * (x[a] - lo_a);
        gap[a][1] = 0.0;
        gap[a][2] = (lo_a + lv->rho - x[a]) * (lo_a + lv->rho - x[a]);
    }
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            if (gap[0][i] + gap[1][j] >= rho2)
                continue;
            for (int k = 0; k < 3; ++k) {
                if (gap[0][i] + gap[1][j] + gap[2][k] >= rho2)
                    continue;
                for (uint32_t it = hash_head(h, ci[0] + i - 1, ci[1] + j - 1, ci[2] + k - 1);
                     it != NO_ITEM; it = h->next[it]) {
                    const double *c, *cx = lv->xyz + 3 * (size_t)it;
                    double d[3], r2, r, t, t3, phi, g, gg[3];
                    sub3(x, cx, d);
                    r2 = dot3(d, d);
                    if (r2 >= rho2)
                        continue;
                    c = lv->c + CW * (size_t)it;
                    r = sqrt(r2) * lv->inv_rho;
                    t = 1.0 - r;
                    t3 = t * t * t;
                    phi = t3 * t * (4.0 * r + 1.0);
                    g = quadric(c, d, grad ? gg : NULL);
                    *f += g * phi;
                    if (grad) {
                        double s = g * g2 * t3;
                        for (int a = 0; a < 3; ++a)
                            grad[a] += gg[a] * phi + s * d[a];
                    }
                }
            }
        }
}

/* f of the first n_levels levels. */
static double eval_levels(const relief_rbf *f, int n_levels, const double x[3], double grad[3])
{
    double v = 0.0;
    if (grad)
        grad[0] = grad[1] = grad[2] = 0.0;
    for (int l = 0; l < n_levels; ++l)
        level_add(&f->level[l], x, &v, grad);
    return v;
}

double relief_rbf_eval(const relief_rbf *f, const double x[3], double grad[3])
{
    if (!isfinite(x[0]) || !isfinite(x[1]) || !isfinite(x[2])) {
        if (grad)
            grad[0] = grad[1] = grad[2] = NAN;
        return NAN;
    }
    return eval_levels(f, f->n_levels, x, grad);
}

int relief_rbf_project(const relief_rbf *f, double x[3], int max_iter, double tol)
{
    for (int it = 0;; ++it) {
        double g[3], v = relief_rbf_eval(f, x, g), g2 = dot3(g, g);
        if (fabs(v) <= tol)
            return 1;
        if (it >= max_iter || !(g2 > 0.0) || !isfinite(v) || !isfinite(g2))
            return 0;
        for (int a = 0; a < 3; ++a)
            x[a] -= v * g[a] / g2;
    }
}

/* ---- the fit --------------------------------------------------------- */

/* What cluster's shares read and write. */
typedef struct cluster_job {
    const double *pos, *nrm;
    const double *lo;
    double inv;       /* 1 / the cell's side */
    relief_keyed *k;  /* n: each point's cell, then sorted by it */
    const size_t *seg; /* m + 1: where each cell's run starts in k */
    double *c;        /* m x 6: the centres */
} cluster_job;

static int cluster_keys(void *ctx, size_t lo, size_t hi)
{
    const cluster_job *j = ctx;
    for (size_t i = lo; i < hi; ++i) {
        const double *p = j->pos + 3 * i;
        j->k[i].key = cell_key(cell_coord(p[0], j->lo[0], j->inv),
                               cell_coord(p[1], j->lo[1], j->inv),
                               cell_coord(p[2], j->lo[2], j->inv));
        j->k[i].index = (uint32_t)i;
    }
    return 0;
}

/* Centres [lo, hi): each from its cell's run of points alone. */
static int cluster_centres(void *ctx, size_t lo, size_t hi)
{
    const cluster_job *j = ctx;
    const double *pos = j->pos, *nrm = j->nrm;
    for (size_t g = lo; g < hi; ++g) {
        size_t s = j->seg[g], e = j->seg[g + 1], rep = j->k[s].index;
        double m3[3] = {0, 0, 0}, nm[3] = {0, 0, 0}, best = INFINITY;
        for (size_t t = s; t < e; ++t)
            for (int a = 0; a < 3; ++a) {
                m3[a] += pos[3 * (size_t)j->k[t].index + a];
                nm[a] += nrm[3 * (size_t)j->k[t].index + a];
            }
        for (int a = 0; a < 3; ++a)
            m3[a] /= (double)(e - s);
        for (size_t t = s; t < e; ++t) {
            double d[3], d2;
            sub3(pos + 3 * (size_t)j->k[t].index, m3, d);
            d2 = dot3(d, d);
            if (d2 < best)
                best = d2, rep = j->k[t].index;
        }
        memcpy(j->c + 6 * g, pos + 3 * rep, 3 * sizeof *j->c);
        if (relief_normalize3(nm) < 0.25 * (double)(e - s))
            memcpy(nm, nrm + 3 * rep, sizeof nm);
        memcpy(j->c + 6 * g + 3, nm, sizeof nm);
    }
    return 0;
}

/* One centre per occupied cell of side `cell`: the point nearest the
 * cell's centroid (the lower index on a tie), with the cell's mean normal
 * (the point's own where the cell's normals cancel: a thin sheet). Writes
 * position and normal into c (n x 6, allocated); returns the count, 0 when
 * out of memory. The keys and the centres on `threads` threads, the same
 * whatever their number. */
static size_t cluster(const double *pos, const double *nrm, size_t n, const double lo[3],
                      double cell, int threads, double **c_out)
{
    relief_keyed *k = malloc(n * sizeof *k);
    size_t *seg = malloc((n + 1) * sizeof *seg), m = 0;
    cluster_job j = {pos, nrm, lo, 1.0 / cell, k, seg, malloc(n * 6 * sizeof(double))};
    *c_out = NULL;
    if (!k || !seg || !j.c) {
        free(k), free(seg), free(j.c);
        return 0;
    }
    relief_parallel_ranges(n, threads, cluster_keys, &j);
    if (relief_sort_keyed(k, n)) {
        free(k), free(seg), free(j.c);
        return 0;
    }
    for (size_t i = 0; i < n; ++i)
        if (i == 0 || k[i].key != k[i - 1].key)
            seg[m++] = i;
    seg[m] = n;
    relief_parallel_ranges(m, threads, cluster_centres, &j);
    free(k), free(seg);
    *c_out = j.c;
    return m;
}

/* q = A p over rows lo..hi of a CSR matrix: each row's sum in the
 * row's order, so the same bits on any number of threads. */
typedef struct matvec_job {
    const size_t *start;
    const uint32_t *col;
    const double *val, *p;
    double *q;
} matvec_job;

static int matvec_rows(void *ctx, size_t lo, size_t hi)
{
    const matvec_job *j = ctx;
    for (size_t i = lo; i < hi; ++i) {
        double s = 0.0;
        for (size_t e = j->start[i]; e < j->start[i + 1]; ++e)
            s += j->val[e] * j->p[j->col[e]];
        j->q[i] = s;
    }
    return 0;
}

/* A product of fewer entries runs on the calling thread: starting the
 * others would cost more than it saves. */
#define MATVEC_SHARED_NNZ ((size_t)1 << 16)

/* Conjugate gradients on the symmetric positive definite A (CSR: row
 * start, column, value) from x = 0. Stops at |r| <= 1e-5 |b| or after
 * CG_MAX_ITER steps, keeping the last iterate (the best so far in A's
 * norm): clustered centres can make the system ill-conditioned, and a
 * nearly interpolating f is still the right answer then. The products
 * A p run on `threads`; the dot products and updates, a few operations a
 * row against A's tens, stay on one in a fixed order, so the bits do not
 * depend on the threads. Returns 0 when out of memory. */
static int solve_cg(size_t n, const size_t *start, const uint32_t *col, const double *val,
                    const double *b, double *x, int threads)
{
    double *r = malloc(n * sizeof *r), *p = malloc(n * sizeof *p), *q = malloc(n * sizeof *q);
    double rr = 0.0, bb;
    if (!r || !p || !q) {
        free(r), free(p), free(q);
        return 0;
    }
    for (size_t i = 0; i < n; ++i) {
        x[i] = 0.0, r[i] = p[i] = b[i];
        rr += b[i] * b[i];
    }
    bb = rr;
    if (start[n] < MATVEC_SHARED_NNZ)
        threads = 1;
    for (int it = 0; it < CG_MAX_ITER && rr > CG_REL_TOL * bb && rr > 0.0; ++it) {
        double pq = 0.0, alpha, rr_new = 0.0;
        matvec_job mv = {start, col, val, p, q};
        relief_parallel_ranges(n, threads, matvec_rows, &mv);
        for (size_t i = 0; i < n; ++i)
            pq += p[i] * q[i];
        if (!(pq > 0.0))
            break;
        alpha = rr / pq;
        for (size_t i = 0; i < n; ++i) {
            x[i] += alpha * p[i];
            r[i] -= alpha * q[i];
            rr_new += r[i] * r[i];
        }
        for (size_t i = 0; i < n; ++i)
            p[i] = r[i] + rr_new / rr * p[i];
        rr = rr_new;
    }
    free(r), free(p), free(q);
    return 1;
}

/* The data a level fits to: all points, unit normals, a hash of them. */
typedef struct fit_data {
    double *pos, *nrm; /* n x 3 each */
    size_t n;
    double spacing;
    int n_levels;
    cell_hash grid; /* cells of the fit's radius over pos */
    int threads;    /* the fit's shares run on this many threads */
} fit_data;

/* A thread's list of points near a place (hash_within). */
typedef struct scratch {
    uint32_t *near;
    size_t cap;
} scratch;

static void fit_data_clear(fit_data *fd)
{
    free(fd->pos), free(fd->nrm);
    fd->pos = fd->nrm = NULL;
    hash_free(&fd->grid);
}

/* fd's points for fits of radius R: the points clustered to R / 6, at
 * least half a spacing. */
static relief_status fit_data_make(fit_data *fd, const double *pos, const double *nrm, size_t n,
                                   const double lo[3], double R)
{
    double *c;
    size_t m = cluster(pos, nrm, n, lo, fmax(R / 6.0, 0.5 * fd->spacing), fd->threads, &c);
    fit_data_clear(fd);
    if (!m)
        return RELIEF_E_NOMEM;
    fd->n = m;
    fd->pos = malloc(m * 3 * sizeof *fd->pos);
    fd->nrm = malloc(m * 3 * sizeof *fd->nrm);
    if (!fd->pos || !fd->nrm || !hash_init(&fd->grid, lo, R, m)) {
        free(c);
        return RELIEF_E_NOMEM;
    }
    for (size_t i = 0; i < m; ++i) {
        memcpy(fd->pos + 3 * i, c + 6 * i, 3 * sizeof *c);
        memcpy(fd->nrm + 3 * i, c + 6 * i + 3, 3 * sizeof *c);
        if (!hash_insert(&fd->grid, fd->pos + 3 * i)) {
            free(c);
            return RELIEF_E_NOMEM;
        }
    }
    free(c);
    return RELIEF_OK;
}

/* The local quadratic of centre c (c[0..2], normal c[3..5]) at radius R:
 * in the frame (u, v, n) at c, the height w = h(u, v) = F + D u + E v +
 * A u^2 + B u v + C v^2 fitted by least squares to the points within R
 * whose normals are within 60 degrees of c's, weighted by phi(r / R), and
 *   q(x) = w - h(u, v) = (x - c)^T M (x - c) + b . (x - c) + q0,
 * written to q[0..5] (M: xx xy xz yy yz zz), q[6..8] (b) and q[9] (q0).
 * The tangent plane (q = n . (x - c)) when fewer than 6 points qualify or
 * the fit is singular. 0 when out of memory. */
static int local_quadric(const fit_data *fd, scratch *sc, const double *c, double R,
                         double q[10])
{
    double eu[3], ev[3], ata[36] = {0}, atb[6] = {0}, co[6] = {0}, e[3][3];
    size_t nn = hash_within(&fd->grid, fd->pos, c, R, &sc->near, &sc->cap), used = 0;
    const double *n = c + 3;
    if (nn == (size_t)-1)
        return 0;
    relief_perp_basis(n, eu, ev);
    for (size_t k = 0; k < nn; ++k) {
        const double *p = fd->pos + 3 * (size_t)sc->near[k];
        double d[3], r, w, t, basis[6];
        if (dot3(fd->nrm + 3 * (size_t)sc->near[k], n) < 0.5)
            continue;
        sub3(p, c, d);
        r = sqrt(dot3(d, d)) / R;
        t = 1.0 - r;
        w = t * t * t * t * (4.0 * r + 1.0);
        /* Scaled by R, so that the normal equations are well balanced. */
        basis[0] = 1.0;
        basis[1] = dot3(d, eu) / R;
        basis[2] = dot3(d, ev) / R;
        basis[3] = basis[1] * basis[1];
        basis[4] = basis[1] * basis[2];
        basis[5] = basis[2] * basis[2];
        for (int i = 0; i < 6; ++i) {
            for (int j = 0; j < 6; ++j)
                ata[6 * i + j] += w * basis[i] * basis[j];
            atb[i] += w * basis[i] * dot3(d, n) / R;
        }
        ++used;
    }
    if (used < 6 || !relief_solve_dense(6, ata, atb, co))
        memset(co, 0, sizeof co);
    /* Back to lengths: h = R F + D u + E v + (A u^2 + B u v + C v^2) / R. */
    co[0] *= R;
    co[3] /= R, co[4] /= R, co[5] /= R;
    /* M = -(A eu eu^T + B (eu ev^T + ev eu^T) / 2 + C ev ev^T). */
    memcpy(e[0], eu, sizeof e[0]);
    memcpy(e[1], ev, sizeof e[1]);
    memcpy(e[2], n, sizeof e[2]);
    {
        static const int ij[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
        for (int k = 0; k < 6; ++k) {
            int i = ij[k][0], j = ij[k][1];
            q[k] = -(co[3] * eu[i] * eu[j] + 0.5 * co[4] * (eu[i] * ev[j] + ev[i] * eu[j]) +
                     co[5] * ev[i] * ev[j]);
        }
    }
    for (int a = 0; a < 3; ++a)
        q[6 + a] = n[a] - co[1] * eu[a] - co[2] * ev[a];
    q[9] = -co[0];
    return 1;
}

/* fit_level's per-centre work, shared out over threads: each writes only
 * its own centre's row, so the bytes do not depend on the threads. */
typedef struct level_job {
    relief_rbf *f;
    int l;
    const fit_data *fd;
    const double *c;      /* the centres as given (m x 6) */
    const relief_keyed *order;   /* the level's i-th centre is c's order[i].index-th */
    double R;
    const size_t *start;  /* the level's phi_ij in CSR */
    const uint32_t *col;
    const double *val;
    double *b;            /* in: each row's sum of phi; out: the right-hand side */
} level_job;

/* g_c = q_c / (S_c L) of each centre, and b = -f_{l-1}(c_i). */
static int centre_share(void *ctx, size_t lo, size_t hi)
{
    const level_job *j = ctx;
    rbf_level *lv = &j->f->level[j->l];
    scratch sc = {NULL, 0};
    int failed = 0;
    for (size_t i = lo; i < hi && !failed; ++i) {
        double q[10], *ci = lv->c + CW * i, s = j->b[i];
        j->b[i] = -eval_levels(j->f, j->l, ci, NULL);
        if (!local_quadric(j->fd, &sc, j->c + 6 * (size_t)j->order[i].index, j->R, q))
            failed = 1;
        for (int a = 0; a < 10; ++a)
            ci[3 + a] = q[a] / (s * j->fd->n_levels);
    }
    free(sc.near);
    return failed;
}

/* b_i -= sum_j g_j(c_i) phi_ij. */
static int rhs_share(void *ctx, size_t lo, size_t hi)
{
    const level_job *j = ctx;
    const rbf_level *lv = &j->f->level[j->l];
    for (size_t i = lo; i < hi; ++i)
        for (size_t e = j->start[i]; e < j->start[i + 1]; ++e) {
            const double *cj = lv->c + CW * (size_t)j->col[e];
            double d[3];
            sub3(lv->c + CW * i, cj, d);
            j->b[i] -= quadric(cj, d, NULL) * j->val[e];
        }
    return 0;
}

/* The level's interpolation matrix, a row a centre: phi_ij for the
 * centres j within rho of centre i, in the order of the level's grid. The
 * rows are cut into one run a thread; each run's entries go to a buffer of
 * its own, joined in order after (rows_assemble). */
typedef struct row_run {
    uint32_t *col;
    double *val;
    size_t n, cap; /* entries held, room */
} row_run;

typedef struct row_job {
    const rbf_level *lv;
    const double *lo; /* the grid's origin */
    double rho;
    size_t m, *len;   /* rows; row i's length in len[i + 1] */
    double *b;        /* each row's sum of phi */
    row_run *runs;
    size_t n_runs;
} row_job;

/* Row i's entries appended to run r; 0 when out of memory. */
static int row_entries(const row_job *j, size_t i, row_run *r)
{
    const rbf_level *lv = j->lv;
    const double *ci = lv->c + CW * i;
    size_t first = r->n;
    double s = 0.0;
    int64_t cc[3];
    for (int a = 0; a < 3; ++a)
        cc[a] = cell_coord(ci[a], j->lo[a], lv->grid.inv_h);
    for (int64_t u = cc[0] - 1; u <= cc[0] + 1; ++u)
        for (int64_t v = cc[1] - 1; v <= cc[1] + 1; ++v)
            for (int64_t w = cc[2] - 1; w <= cc[2] + 1; ++w)
                for (uint32_t it = hash_head(&lv->grid, u, v, w); it != NO_ITEM;
                     it = lv->grid.next[it]) {
                    double d[3], rr;
                    sub3(ci, lv->c + CW * (size_t)it, d);
                    rr = sqrt(dot3(d, d)) / j->rho;
                    if (rr >= 1.0)
                        continue;
                    if (r->n == r->cap) {
                        size_t nc = r->cap ? 2 * r->cap : 64;
                        uint32_t *c2 = realloc(r->col, nc * sizeof *c2);
                        double *v2;
                        if (!c2)
                            return 0;
                        r->col = c2;
                        v2 = realloc(r->val, nc * sizeof *v2);
                        if (!v2)
                            return 0;
                        r->val = v2, r->cap = nc;
                    }
                    r->col[r->n] = it;
                    r->val[r->n] = pow(1.0 - rr, 4) * (4.0 * rr + 1.0);
                    s += r->val[r->n++];
                }
    j->len[i + 1] = r->n - first;
    j->b[i] = s; /* the row's sum until centre_share */
    return 1;
}

/* Runs lo..hi: run k holds rows k m / n_runs .. (k + 1) m / n_runs - 1. */
static int row_runs(void *ctx, size_t lo, size_t hi)
{
    const row_job *j = ctx;
    for (size_t k = lo; k < hi; ++k)
        for (size_t i = k * j->m / j->n_runs; i < (k + 1) * j->m / j->n_runs; ++i)
            if (!row_entries(j, i, &j->runs[k]))
                return 1;
    return 0;
}

/* The level's matrix in CSR (*start, m + 1 of them, allocated by the
 * caller; *col, *val allocated here) and b, each row's sum, on `threads`;
 * the same entries in the same order on any number of them. 0 when out of
 * memory. */
static int rows_assemble(const rbf_level *lv, const double lo[3], double rho, size_t m,
                         int threads, size_t *start, uint32_t **col, double **val, double *b)
{
    row_run runs[RELIEF_PARALLEL_MAX_THREADS] = {{NULL, NULL, 0, 0}};
    size_t n_runs = threads < 1 ? 1 : (size_t)threads, at = 0;
    row_job j = {lv, lo, rho, m, start, b, runs, 0};
    int ok;
    n_runs = n_runs > RELIEF_PARALLEL_MAX_THREADS ? RELIEF_PARALLEL_MAX_THREADS : n_runs;
    n_runs = n_runs > m ? (m ? m : 1) : n_runs;
    j.n_runs = n_runs;
    ok = !relief_parallel_ranges(n_runs, (int)n_runs, row_runs, &j);
    start[0] = 0;
    for (size_t i = 0; i < m && ok; ++i)
        start[i + 1] += start[i];
    *col = ok ? malloc((start[m] ? start[m] : 1) * sizeof **col) : NULL;
    *val = *col ? malloc((start[m] ? start[m] : 1) * sizeof **val) : NULL;
    for (size_t k = 0; k < n_runs; ++k) {
        if (*val && runs[k].n) {
            memcpy(*col + at, runs[k].col, runs[k].n * sizeof **col);
            memcpy(*val + at, runs[k].val, runs[k].n * sizeof **val);
        }
        at += runs[k].n;
        free(runs[k].col), free(runs[k].val);
    }
    return *val != NULL;
}

/* Level lv's centres, c's m of them (m x 6: position, normal), in the
 * order of their cells of side lv->rho, so that each cell's lie together.
 * order (m, the caller's) gets each one's index in c; lv->c (m x CW,
 * allocated) and lv->xyz (m x 3, allocated) their positions, lv->grid
 * their cells; lv->lo, lv->hi the centres' box grown by rho (f's
 * support), and lo (3, from INFINITY) the centres' own lower corner, the
 * cells' origin. 0 when out of memory. */
static int level_centres(rbf_level *lv, const double *c, size_t m, double lo[3],
                         relief_keyed *order)
{
    double rho = lv->rho;
    for (int a = 0; a < 3; ++a)
        lv->lo[a] = INFINITY, lv->hi[a] = -INFINITY;
    for (size_t i = 0; i < m; ++i)
        for (int a = 0; a < 3; ++a) {
            lo[a] = fmin(lo[a], c[6 * i + a]);
            lv->lo[a] = fmin(lv->lo[a], c[6 * i + a] - rho);
            lv->hi[a] = fmax(lv->hi[a], c[6 * i + a] + rho);
        }
    for (size_t i = 0; i < m; ++i) {
        const double *x = c + 6 * i;
        order[i].key = cell_key(cell_coord(x[0], lo[0], 1.0 / rho),
                                cell_coord(x[1], lo[1], 1.0 / rho),
                                cell_coord(x[2], lo[2], 1.0 / rho));
        order[i].index = (uint32_t)i;
    }
    if (relief_sort_keyed(order, m))
        return 0;
    if (!hash_init(&lv->grid, lo, rho, m))
        return 0;
    for (size_t i = 0; i < m; ++i) {
        const double *x = c + 6 * (size_t)order[i].index;
        memcpy(lv->c + CW * i, x, 3 * sizeof *x);
        memcpy(lv->xyz + 3 * i, x, 3 * sizeof *x);
        if (!hash_insert(&lv->grid, x))
            return 0;
    }
    return 1;
}

/* Level l of f (levels 0..l-1 done) on the centres c (m x 6: position,
 * normal), as Ohtake et al.:
 *   o_l(x) = sum_c (g_c(x) + lambda_c) phi(|x - c| / rho),
 *   g_c = q_c / (S_c L),  S_c = sum_j phi(|c - c_j| / rho),
 * q_c c's local quadratic (above; quadratic rather than linear so that a
 * hole on a curved surface is spanned by the curvature around it: a blend
 * of tangent planes bulges out of a convex surface, by 0.2 over a 0.6-wide
 * cap of the unit sphere), S_c the overlap of the level's functions at c
 * and L the number of levels: each level's sum of g then approximates the
 * signed distance / L, so that f's gradient is about the normal, of length
 * about 1, near the points. lambda from f_l(c_i) = 0 at every centre:
 *   sum_j lambda_j phi_ij = -f_{l-1}(c_i) - sum_j g_j(c_i) phi_ij. */
static relief_status fit_level(relief_rbf *f, int l, fit_data *fd, const double *c, size_t m,
                               double R, relief_error *err)
{
    rbf_level *lv = &f->level[l];
    double rho = lv->rho, lo[3] = {INFINITY, INFINITY, INFINITY};
    size_t *start = NULL;
    uint32_t *col = NULL;
    double *val = NULL, *b = NULL, *lam = NULL;
    relief_keyed *order = NULL;
    relief_status st = RELIEF_OK;

    lv->n = m;
    lv->c = malloc(m * CW * sizeof *lv->c);
    lv->xyz = malloc(m * 3 * sizeof *lv->xyz);
    order = malloc(m * sizeof *order);
    start = malloc((m + 1) * sizeof *start);
    b = malloc(m * sizeof *b);
    lam = malloc(m * sizeof *lam);
    if (!lv->c || !lv->xyz || !order || !start || !b || !lam)
        goto nomem;
    if (!level_centres(lv, c, m, lo, order))
        goto nomem;

    /* Each centre's neighbours within rho and their phi, and the row's
     * sum, in two passes over the threads (the rows' lengths, then the
     * rows); then, a centre at a time over the threads, g_c from the
     * quadric and b from f so far. */
    if (!rows_assemble(lv, lo, rho, m, fd->threads, start, &col, &val, b))
        goto nomem;
    {
        level_job j = {f, l, fd, c, order, R, start, col, val, b};
        if (relief_parallel_ranges(m, fd->threads, centre_share, &j))
            goto nomem;
        relief_parallel_ranges(m, fd->threads, rhs_share, &j);
    }
    if (!solve_cg(m, start, col, val, b, lam, fd->threads))
        goto nomem;
    for (size_t i = 0; i < m; ++i) {
        if (!isfinite(lam[i])) {
            st = relief_fail(err, RELIEF_E_RANGE, "level %d (support %g, %zu centres): the "
                             "interpolation system has no finite solution", l + 1, rho, m);
            goto done;
        }
        lv->c[CW * i + 12] += lam[i];
    }
    goto done;
nomem:
    st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate level %d (%zu centres, support %g)",
                     l + 1, m, rho);
done:
    free(start), free(col), free(val), free(b), free(lam), free(order);
    return st;
}

/* The fit's arguments checked, in the order the messages are tried: the
 * pointers, n (4..NO_ITEM - 1 points), the spacing, levels, threads and
 * base support of p. RELIEF_OK, or RELIEF_E_RANGE with its message. */
static relief_status fit_check(const double *pos, const double *nrm, size_t n,
                               const relief_rbf_params *p, relief_rbf **out, relief_error *err)
{
    if (!pos || !nrm || !p || !out)
        return relief_fail(err, RELIEF_E_RANGE, "rbf fit: positions, normals, parameters "
                           "and output must not be NULL");
    if (n < 4 || n >= NO_ITEM)
        return relief_fail(err, RELIEF_E_RANGE, "rbf fit: %zu points; expected 4..%u", n,
                           NO_ITEM - 1);
    if (!(p->spacing > 0.0) || !isfinite(p->spacing))
        return relief_fail(err, RELIEF_E_RANGE, "rbf fit: spacing %g; expected a finite "
                           "length > 0", p->spacing);
    if (p->levels < 0 || p->levels > MAX_LEVELS)
        return relief_fail(err, RELIEF_E_RANGE, "rbf fit: levels %d; expected 1..%d (0: "
                           "automatic)", p->levels, MAX_LEVELS);
    if (p->threads < 0 || p->threads > RELIEF_PARALLEL_MAX_THREADS)
        return relief_fail(err, RELIEF_E_RANGE, "rbf fit: threads %d; expected 0..%d (0: the "
                           "online processors)", p->threads, RELIEF_PARALLEL_MAX_THREADS);
    if (!(p->base_support >= 0.0) || !isfinite(p->base_support))
        return relief_fail(err, RELIEF_E_RANGE, "rbf fit: base support %g; expected a finite "
                           "length > 0 (0: 0.75 x the bounding box's diagonal)", p->base_support);
    return RELIEF_OK;
}

/* The n points' unit normals into unit (n x 3, the caller's) and their
 * bounding box grown into lo, hi (3 each, from +-INFINITY). RELIEF_E_RANGE
 * at the first point with a coordinate or normal that is not finite, or a
 * zero normal (unit and the box then partly written). */
static relief_status fit_normals(const double *pos, const double *nrm, size_t n, double *unit,
                                 double lo[3], double hi[3], relief_error *err)
{
    for (size_t i = 0; i < n; ++i) {
        for (int a = 0; a < 3; ++a) {
            double v = pos[3 * i + a];
            if (!isfinite(v) || !isfinite(nrm[3 * i + a]))
                return relief_fail(err, RELIEF_E_RANGE, "rbf fit: point %zu has a coordinate "
                                   "or normal that is not finite", i);
            lo[a] = fmin(lo[a], v), hi[a] = fmax(hi[a], v);
            unit[3 * i + a] = nrm[3 * i + a];
        }
        if (!(relief_normalize3(unit + 3 * i) > 0.0))
            return relief_fail(err, RELIEF_E_RANGE, "rbf fit: point %zu has a zero normal", i);
    }
    return RELIEF_OK;
}

/* From the n points' box lo, hi (3 each): *rho0, the coarsest level's
 * support (p's, or 0.75 x the box's diagonal), and *levels (p's, or as
 * many as halve rho0 to 2 spacings, at most DEFAULT_MAX_LEVELS), in the
 * points' units. RELIEF_E_RANGE when the points coincide or the finest
 * grid would be over CELL_SPAN cells across. */
static relief_status fit_supports(const relief_rbf_params *p, size_t n, const double lo[3],
                                  const double hi[3], double *rho0_out, int *levels_out,
                                  relief_error *err)
{
    double diag, rho0;
    int levels;

    diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                (hi[2] - lo[2]) * (hi[2] - lo[2]));
    if (!(diag > 0.0))
        return relief_fail(err, RELIEF_E_RANGE, "rbf fit: all %zu points coincide", n);
    rho0 = p->base_support > 0.0 ? p->base_support : 0.75 * diag;
    levels = p->levels;
    if (levels == 0)
        for (levels = 1; levels < DEFAULT_MAX_LEVELS &&
                         ldexp(rho0, -(levels - 1)) > 2.0 * p->spacing;)
            ++levels;
    {
        /* The finest grid: cells of the finest support, and clusters at
         * least half a spacing wide. */
        double fine = ldexp(rho0, -(levels - 1));
        double cell = fmin(fine, 0.5 * p->spacing);
        if ((diag + 2.0 * rho0) / cell > CELL_SPAN)
            return relief_fail(err, RELIEF_E_RANGE, "rbf fit: the finest support %g (spacing %g, "
                               "%d levels) is too small for points spanning %g: at most %g cells "
                               "across", fine, p->spacing, levels, diag, CELL_SPAN);
    }
    *rho0_out = rho0, *levels_out = levels;
    return RELIEF_OK;
}

/* Level l of f, support rho0 / 2^l, fitted to the n points pos (n x 3)
 * with unit normals unit (n x 3) in the box from lo: its centres, fd's
 * data for the fit's radius, then fit_level. f->n_levels counts the level
 * once fd is made, so that relief_rbf_free takes what fit_level leaves
 * on failure. */
static relief_status add_level(relief_rbf *f, int l, fit_data *fd, const double *pos,
                               const double *unit, size_t n, const double lo[3], double rho0,
                               double spacing, relief_error *err)
{
    double *c, rho = ldexp(rho0, -l), R = fmax(rho, 3.0 * spacing);
    /* Centres: clusters half a support wide, so that about 4 pi of the
     * level's functions overlap at each point of a surface (a sparse
     * system that still blends smoothly), no finer than half a spacing,
     * which also merges duplicates. */
    size_t m = cluster(pos, unit, n, lo, fmax(0.5 * rho, 0.5 * spacing), fd->threads, &c);
    relief_status st;
    if (!m)
        return relief_fail(err, RELIEF_E_NOMEM, "rbf fit: cannot cluster level %d", l + 1);
    /* The quadrics' data: the points clustered 6 to the fit's radius
     * (about 100 of them in each fit), so that a coarse level's fit
     * does not visit every point, each of them again. */
    st = fit_data_make(fd, pos, unit, n, lo, R);
    if (st == RELIEF_OK) {
        f->level[l].rho = rho;
        f->level[l].inv_rho = 1.0 / rho;
        f->n_levels = l + 1;
        st = fit_level(f, l, fd, c, m, R, err);
    } else {
        st = relief_fail(err, st, "rbf fit: cannot cluster level %d", l + 1);
    }
    free(c);
    return st;
}

relief_status relief_rbf_fit(const double *pos, const double *nrm, size_t n,
                             const relief_rbf_params *p, relief_rbf **out,
                             relief_error *err)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double rho0 = 0.0, *unit = NULL;
    int levels = 0;
    relief_rbf *f = NULL;
    fit_data fd;
    relief_status st;

    memset(&fd, 0, sizeof fd);
    if (out)
        *out = NULL;
    st = fit_check(pos, nrm, n, p, out, err);
    if (st != RELIEF_OK)
        return st;
    unit = malloc(n * 3 * sizeof *unit);
    if (!unit)
        return relief_fail(err, RELIEF_E_NOMEM, "rbf fit: cannot copy %zu normals", n);
    st = fit_normals(pos, nrm, n, unit, lo, hi, err);
    if (st == RELIEF_OK)
        st = fit_supports(p, n, lo, hi, &rho0, &levels, err);
    if (st != RELIEF_OK)
        goto done;
    fd.spacing = p->spacing, fd.n_levels = levels;
    fd.threads = p->threads > 0 ? p->threads : relief_pool_default_threads();
    f = calloc(1, sizeof *f);
    if (!f) {
        st = relief_fail(err, RELIEF_E_NOMEM, "rbf fit: cannot allocate the model");
        goto done;
    }
    for (int l = 0; l < levels; ++l) {
        st = add_level(f, l, &fd, pos, unit, n, lo, rho0, p->spacing, err);
        if (st != RELIEF_OK)
            goto done;
    }
    *out = f;
    f = NULL;
done:
    relief_rbf_free(f);
    fit_data_clear(&fd);
    free(unit);
    return st;
}

/* ---- the hole fill --------------------------------------------------- */

#define FILL_REJECT 0.75   /* no two points closer, in spacings */
#define FILL_NEIGHBOURS 2.0 /* the front's neighbourhood radius, in spacings */
#define FILL_DRIFT 2.0     /* the most a projection may move a step, in spacings */
#define FILL_ITER 10
#define FILL_TOL 1e-3      /* |f| at a projected point, in spacings */

typedef struct fill_state {
    double *pos, *nrm; /* given then new points, 3 each */
    uint32_t *hole;    /* per point: its hole, 0 for a given point off every rim */
    size_t n, cap;
    cell_hash grid;
    uint32_t *near;
    size_t near_cap;
    /* What the fill was given, and the rims hole by hole: */
    const relief_rbf *f;
    const double *given;     /* n_given x 3 */
    const uint32_t *rim;     /* n_given */
    size_t n_given, max_new, n_rim;
    uint32_t n_holes;
    double spacing;
    double *sphere;          /* per hole 1..n_holes: the rim's centroid (3) and the
                                radius (1) of the ball new points must stay in */
    size_t *rim_start;       /* n_holes + 2: hole k's rim points are */
    size_t *rim_list;        /* rim_list[rim_start[k] .. rim_start[k + 1]) */
} fill_state;

static int fill_grow(fill_state *s)
{
    size_t cap = s->cap * 2;
    double *p = realloc(s->pos, cap * 3 * sizeof *p);
    double *q;
    uint32_t *h;
    if (!p)
        return 0;
    s->pos = p;
    q = realloc(s->nrm, cap * 3 * sizeof *q);
    if (!q)
        return 0;
    s->nrm = q;
    h = realloc(s->hole, cap * sizeof *h);
    if (!h)
        return 0;
    s->hole = h;
    s->cap = cap;
    return 1;
}

/* Is x over the capture rather than over a hole? Then the given point
 * nearest to it (within the front's neighbourhood) is on no rim: in a hole
 * the nearest captured point is always on the hole's rim, while a step that
 * turned back over the capture (between the sparse vertices of a decimated
 * mesh, say) lands nearest an interior point. */
static int over_capture(fill_state *s, size_t n, const uint32_t *rim, const double x[3],
                        double spacing)
{
    size_t nn = hash_within(&s->grid, s->pos, x, FILL_NEIGHBOURS * spacing, &s->near,
                            &s->near_cap), best = SIZE_MAX;
    double best_d2 = INFINITY;
    if (nn == (size_t)-1)
        return 0; /* out of memory: the next search reports it */
    for (size_t e = 0; e < nn; ++e) {
        size_t j = s->near[e];
        double d[3], d2;
        if (j >= n)
            continue;
        sub3(s->pos + 3 * j, x, d);
        d2 = dot3(d, d);
        if (d2 < best_d2 || (d2 == best_d2 && j < best))
            best_d2 = d2, best = j;
    }
    return best != SIZE_MAX && rim[best] == 0;
}

/* The arguments (given), and what the fill needs of them: the points'
 * lowest corner lo and the count of rim points. */
static relief_status fill_check(const double *pos, const double *nrm, size_t n, const uint32_t *rim, uint32_t n_holes,
                                double spacing, double lo[3], size_t *n_rim, relief_error *err)
{
    double span = 0.0;
    if (n < 4 || n >= NO_ITEM)
        return relief_fail(err, RELIEF_E_RANGE, "rbf fill: %zu points; expected 4..%u", n,
                           NO_ITEM - 1);
    if (!(spacing > 0.0) || !isfinite(spacing))
        return relief_fail(err, RELIEF_E_RANGE, "rbf fill: spacing %g; expected a finite "
                           "length > 0", spacing);
    for (size_t i = 0; i < n; ++i) {
        if (rim[i] > n_holes)
            return relief_fail(err, RELIEF_E_RANGE, "rbf fill: rim[%zu] = %u; expected 0 (no "
                               "rim) or a hole 1..%u", i, rim[i], n_holes);
        for (int a = 0; a < 3; ++a) {
            if (!isfinite(pos[3 * i + a]) || !isfinite(nrm[3 * i + a]))
                return relief_fail(err, RELIEF_E_RANGE, "rbf fill: point %zu has a coordinate "
                                   "or normal that is not finite", i);
            lo[a] = fmin(lo[a], pos[3 * i + a]);
        }
        *n_rim += rim[i] != 0;
    }
    for (size_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a)
            span = fmax(span, pos[3 * i + a] - lo[a]);
    if (3.0 * span / (FILL_NEIGHBOURS * spacing) > CELL_SPAN)
        return relief_fail(err, RELIEF_E_RANGE, "rbf fill: spacing %g is too small for points "
                           "spanning %g: at most %g cells of 2 spacings across", spacing, span,
                           CELL_SPAN / 3.0);
    return RELIEF_OK;
}

static relief_status fill_nomem(const fill_state *s, relief_error *err)
{
    return relief_fail(err, RELIEF_E_NOMEM, "rbf fill: cannot allocate the new points (%zu so "
                       "far)", s->n > s->n_given ? s->n - s->n_given : 0);
}

/* The rims, hole by hole in index order, their bounding spheres, and the
 * given points as the fill's first ones. 0 when memory runs out. */
static int fill_setup(fill_state *s, const double *nrm, const double lo[3])
{
    const size_t n = s->n_given;
    const double *pos = s->given;
    const uint32_t *rim = s->rim;
    size_t *at;
    s->sphere = calloc((size_t)s->n_holes + 1, 4 * sizeof *s->sphere);
    s->rim_start = calloc((size_t)s->n_holes + 2, sizeof *s->rim_start);
    s->rim_list = malloc(s->n_rim * sizeof *s->rim_list);
    s->cap = n + 64;
    s->pos = malloc(s->cap * 3 * sizeof *s->pos);
    s->nrm = malloc(s->cap * 3 * sizeof *s->nrm);
    s->hole = malloc(s->cap * sizeof *s->hole);
    if (!s->sphere || !s->rim_start || !s->rim_list || !s->pos || !s->nrm || !s->hole ||
        !hash_init(&s->grid, lo, FILL_NEIGHBOURS * s->spacing, n))
        return 0;
    for (size_t i = 0; i < n; ++i)
        if (rim[i]) {
            ++s->rim_start[rim[i] + 1];
            for (int a = 0; a < 3; ++a)
                s->sphere[4 * rim[i] + a] += pos[3 * i + a];
        }
    for (uint32_t k = 1; k <= s->n_holes; ++k) {
        s->rim_start[k + 1] += s->rim_start[k];
        for (int a = 0; a < 3 && s->rim_start[k + 1] > s->rim_start[k]; ++a)
            s->sphere[4 * k + a] /= (double)(s->rim_start[k + 1] - s->rim_start[k]);
    }
    if (!(at = calloc((size_t)s->n_holes + 1, sizeof *at)))
        return 0;
    for (size_t i = 0; i < n; ++i)
        if (rim[i]) {
            double d[3], *sp = s->sphere + 4 * rim[i];
            s->rim_list[s->rim_start[rim[i]] + at[rim[i]]++] = i;
            sub3(pos + 3 * i, sp, d);
            sp[3] = fmax(sp[3], sqrt(dot3(d, d)));
        }
    free(at);
    for (uint32_t k = 1; k <= s->n_holes; ++k)
        s->sphere[4 * k + 3] += s->spacing;
    memcpy(s->pos, pos, n * 3 * sizeof *s->pos);
    for (size_t i = 0; i < n; ++i) {
        memcpy(s->nrm + 3 * i, nrm + 3 * i, 3 * sizeof *s->nrm);
        relief_normalize3(s->nrm + 3 * i);
        s->hole[i] = rim[i];
        if (!hash_insert(&s->grid, pos + 3 * i))
            return 0;
    }
    s->n = n;
    return 1;
}

/* A new point at x, on hole k: projected on the surface, near where it
 * was stepped to, inside the hole's ball, clear of every point and off the
 * capture. Its normal g is the surface's, turned to agree with the nearest
 * rim point's. 1 taken, 0 not, -1 out of memory. */
static int fill_take(fill_state *s, uint32_t k, double x[3], double g[3])
{
    const double spacing = s->spacing, *sp = s->sphere + 4 * k, *rn = NULL;
    double x0[3], dv[3], best = INFINITY;
    size_t hit;
    memcpy(x0, x, sizeof x0);
    if (!relief_rbf_project(s->f, x, FILL_ITER, FILL_TOL * spacing))
        return 0;
    sub3(x, x0, dv);
    if (dot3(dv, dv) > FILL_DRIFT * FILL_DRIFT * spacing * spacing)
        return 0;
    sub3(x, sp, dv);
    if (dot3(dv, dv) > sp[3] * sp[3])
        return 0;
    hit = hash_within(&s->grid, s->pos, x, FILL_REJECT * spacing, &s->near, &s->near_cap);
    if (hit == (size_t)-1)
        return -1;
    if (hit > 0 || over_capture(s, s->n_given, s->rim, x, spacing))
        return 0;
    relief_rbf_eval(s->f, x, g);
    if (!(relief_normalize3(g) > 0.0))
        return 0;
    for (size_t e = s->rim_start[k]; e < s->rim_start[k + 1]; ++e) {
        double d2;
        sub3(x, s->given + 3 * s->rim_list[e], dv);
        d2 = dot3(dv, dv);
        if (d2 < best)
            best = d2, rn = s->nrm + 3 * s->rim_list[e];
    }
    if (rn && dot3(g, rn) < 0.0)
        for (int a = 0; a < 3; ++a)
            g[a] = -g[a];
    return 1;
}

/* Front point i's steps: away from its neighbours' centroid and, so that
 * the front also spreads sideways and closes up between its steps, at +-45
 * and +-90 degrees from there in its tangent plane; each step taken is a
 * new point at the end of the front. */
static relief_status fill_steps(fill_state *s, size_t i, relief_error *err)
{
    static const double angle[5] = {0.0, 0.25, -0.25, 0.5, -0.5}; /* x pi */
    const uint32_t k = s->hole[i];
    const double spacing = s->spacing;
    double p[3], nv[3], m[3] = {0, 0, 0}, d[3], t[3], w, cnt = 0;
    size_t nn;
    memcpy(p, s->pos + 3 * i, sizeof p);
    memcpy(nv, s->nrm + 3 * i, sizeof nv);
    nn = hash_within(&s->grid, s->pos, p, FILL_NEIGHBOURS * spacing, &s->near, &s->near_cap);
    if (nn == (size_t)-1)
        return fill_nomem(s, err);
    for (size_t e = 0; e < nn; ++e)
        if (s->near[e] != i) {
            for (int a = 0; a < 3; ++a)
                m[a] += s->pos[3 * (size_t)s->near[e] + a];
            ++cnt;
        }
    if (cnt == 0)
        return RELIEF_OK;
    for (int a = 0; a < 3; ++a)
        d[a] = p[a] - m[a] / cnt;
    w = dot3(d, nv);
    for (int a = 0; a < 3; ++a)
        d[a] -= w * nv[a];
    if (!(relief_normalize3(d) > 1e-6 * spacing))
        return RELIEF_OK;
    cross3(nv, d, t);
    for (int dir = 0; dir < 5; ++dir) {
        double c = cos(angle[dir] * RELIEF_PI), sn = sin(angle[dir] * RELIEF_PI), x[3], g[3];
        int took;
        for (int a = 0; a < 3; ++a)
            x[a] = p[a] + spacing * (c * d[a] + sn * t[a]);
        took = fill_take(s, k, x, g);
        if (took < 0)
            return fill_nomem(s, err);
        if (!took)
            continue;
        if (s->n - s->n_given >= s->max_new)
            return relief_fail(err, RELIEF_E_NOMEM, "rbf fill: more than max_new = %zu new "
                               "points (spacing %g, %u holes)", s->max_new, spacing, s->n_holes);
        if ((s->n == s->cap && !fill_grow(s)) || !hash_insert(&s->grid, x))
            return fill_nomem(s, err);
        memcpy(s->pos + 3 * s->n, x, sizeof x);
        memcpy(s->nrm + 3 * s->n, g, sizeof g);
        s->hole[s->n] = k;
        ++s->n;
    }
    return RELIEF_OK;
}

static void fill_free(fill_state *s)
{
    hash_free(&s->grid);
    free(s->pos), free(s->nrm), free(s->hole), free(s->near);
    free(s->sphere), free(s->rim_start), free(s->rim_list);
}

relief_status relief_rbf_fill_holes(const relief_rbf *f, const double *pos,
                                    const double *nrm, size_t n, const uint32_t *rim,
                                    uint32_t n_holes, double spacing, size_t max_new,
                                    double **out_pos, double **out_nrm,
                                    uint32_t **out_hole, size_t *n_new,
                                    relief_error *err)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY};
    fill_state s;
    relief_status st;

    memset(&s, 0, sizeof s);
    if (out_pos)
        *out_pos = NULL;
    if (out_nrm)
        *out_nrm = NULL;
    if (out_hole)
        *out_hole = NULL;
    if (n_new)
        *n_new = 0;
    if (!f || !pos || !nrm || !rim || !out_pos || !out_nrm || !out_hole || !n_new)
        return relief_fail(err, RELIEF_E_RANGE, "rbf fill: the model, points, normals, rim "
                           "marks and outputs must not be NULL");
    st = fill_check(pos, nrm, n, rim, n_holes, spacing, lo, &s.n_rim, err);
    if (st != RELIEF_OK || n_holes == 0 || s.n_rim == 0)
        return st;
    s.f = f, s.given = pos, s.rim = rim, s.n_given = n, s.max_new = max_new;
    s.n_holes = n_holes, s.spacing = spacing;
    st = fill_setup(&s, nrm, lo) ? RELIEF_OK : fill_nomem(&s, err);
    /* The front: the rim points in index order, then each new point in the
     * order it was made (a FIFO, since new points are appended). */
    for (size_t q = 0, r = 0; st == RELIEF_OK && (r < s.n_rim || q < s.n - n);)
        st = fill_steps(&s, r < s.n_rim ? s.rim_list[r++] : n + q++, err);
    if (st == RELIEF_OK && s.n > n) {
        size_t m = s.n - n;
        *out_pos = malloc(m * 3 * sizeof **out_pos);
        *out_nrm = malloc(m * 3 * sizeof **out_nrm);
        *out_hole = malloc(m * sizeof **out_hole);
        if (!*out_pos || !*out_nrm || !*out_hole) {
            free(*out_pos), free(*out_nrm), free(*out_hole);
            *out_pos = NULL, *out_nrm = NULL, *out_hole = NULL;
            st = fill_nomem(&s, err);
        } else {
            memcpy(*out_pos, s.pos + 3 * n, m * 3 * sizeof **out_pos);
            memcpy(*out_nrm, s.nrm + 3 * n, m * 3 * sizeof **out_nrm);
            memcpy(*out_hole, s.hole + n, m * sizeof **out_hole);
            *n_new = m;
        }
    }
    fill_free(&s);
    return st;
}
