/* Step 3 of mesh/hole_fill.h: fairing. Each row is one vertex's
 * scale-dependent umbrella Laplacian, L(x)_r = sum_u w_u x_u / sum_u w_u
 * - x_r with w_u = 1 / |x_u - x_r| at the refined positions; the rows
 * are the new vertices' (C0) and the rim's (C1: their 1-rings reach the
 * mesh, whose vertices are fixed). The new positions y minimise
 * |A y + c|^2 (A: the rows' weights on the new vertices, c: the fixed
 * vertices' part), by CGLS, conjugate gradients on the normal equations,
 * for each coordinate, started from the refined positions. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/vec3.h"
#include "mesh/hole_fill_internal.h"

typedef struct fair_rows {
    size_t nr, nf;     /* rows, free vertices */
    size_t *start;     /* nr + 1 */
    uint32_t *col;     /* free vertex of each weight */
    double *val;
    double *c;         /* nr x 3: the fixed part */
    size_t cap;
} fair_rows;

static int row_push(fair_rows *r, uint32_t col, double val)
{
    size_t k = r->start[r->nr + 1];
    if (!hole_grow((void **)&r->col, sizeof *r->col, (void **)&r->val, sizeof *r->val, &r->cap,
                   k + 1))
        return 0;
    r->col[k] = col, r->val[k] = val;
    r->start[r->nr + 1] = k + 1;
    return 1;
}

/* One neighbour u of row vertex xr at position xu: free (col) or fixed. */
typedef struct row_acc {
    double wsum, fixed[3];
} row_acc;

static int row_term(fair_rows *r, row_acc *a, const double *xr, const double *xu, long col)
{
    double d[3], w;
    sub3(xu, xr, d);
    w = 1.0 / fmax(sqrt(dot3(d, d)), 1e-300);
    a->wsum += w;
    if (col >= 0)
        return row_push(r, (uint32_t)col, w);
    for (int e = 0; e < 3; ++e)
        a->fixed[e] += w * xu[e];
    return 1;
}

/* Row of local vertex v: its patch neighbours, and for a rim vertex its
 * mesh neighbours not already among them. */
static int make_row(fair_rows *r, const hole_patch *p, size_t v, const relief_adjacency *pa,
                    const double *pos, const relief_adjacency *adj)
{
    row_acc a = {0, {0, 0, 0}};
    size_t first = r->start[r->nr];
    const double *xr = p->x + 3 * v;
    for (uint32_t k = pa->start[v]; k < pa->start[v + 1]; ++k) {
        uint32_t u = pa->nbr[k];
        if (!row_term(r, &a, xr, p->x + 3 * u, u >= p->n_rim ? (long)(u - p->n_rim) : -1))
            return 0;
    }
    if (v < p->n_mesh) {
        uint32_t g = p->gid[v];
        for (uint32_t k = adj->start[g]; k < adj->start[g + 1]; ++k) {
            uint32_t u = adj->nbr[k];
            int dup = 0;
            for (uint32_t i = pa->start[v]; i < pa->start[v + 1] && !dup; ++i)
                dup = pa->nbr[i] < p->n_mesh && p->gid[pa->nbr[i]] == u;
            if (!dup && !row_term(r, &a, xr, pos + 3 * (size_t)u, -1))
                return 0;
        }
    }
    for (size_t k = first; k < r->start[r->nr + 1]; ++k)
        r->val[k] /= a.wsum;
    for (int e = 0; e < 3; ++e)
        r->c[3 * r->nr + e] = a.fixed[e] / a.wsum - (v < p->n_rim ? xr[e] : 0.0);
    if (v >= p->n_rim && !row_push(r, (uint32_t)(v - p->n_rim), -1.0))
        return 0;
    ++r->nr;
    r->start[r->nr + 1] = r->start[r->nr];
    return 1;
}

/* q = A y (nr) and s = A^T q (nf). */
static void mul(const fair_rows *r, const double *y, double *q)
{
    for (size_t i = 0; i < r->nr; ++i) {
        double s = 0.0;
        for (size_t k = r->start[i]; k < r->start[i + 1]; ++k)
            s += r->val[k] * y[r->col[k]];
        q[i] = s;
    }
}

static void mul_t(const fair_rows *r, const double *q, double *s)
{
    memset(s, 0, r->nf * sizeof *s);
    for (size_t i = 0; i < r->nr; ++i)
        for (size_t k = r->start[i]; k < r->start[i + 1]; ++k)
            s[r->col[k]] += r->val[k] * q[i];
}

static double dot(const double *a, const double *b, size_t n)
{
    double s = 0.0;
    for (size_t i = 0; i < n; ++i)
        s += a[i] * b[i];
    return s;
}

/* CGLS on |A y - b| for y (nf), from y's content. w: 2 nr + 3 nf scratch. */
static void cgls(const fair_rows *r, const double *b, double *y, double *w)
{
    size_t nr = r->nr, nf = r->nf, max_it = 20000;
    double *res = w, *q = w + nr, *s = q + nr, *pdir = s + nf, *t = pdir + nf, gamma, g0;
    mul(r, y, res);
    for (size_t i = 0; i < nr; ++i)
        res[i] = b[i] - res[i];
    mul_t(r, res, s);
    memcpy(pdir, s, nf * sizeof *s);
    gamma = g0 = dot(s, s, nf);
    for (size_t it = 0; it < max_it && gamma > 1e-24 * g0 && gamma > 0.0; ++it) {
        double qq, alpha, gnew;
        mul(r, pdir, q);
        qq = dot(q, q, nr);
        if (!(qq > 0.0))
            break;
        alpha = gamma / qq;
        for (size_t i = 0; i < nf; ++i)
            y[i] += alpha * pdir[i];
        for (size_t i = 0; i < nr; ++i)
            res[i] -= alpha * q[i];
        mul_t(r, res, t);
        gnew = dot(t, t, nf);
        for (size_t i = 0; i < nf; ++i)
            pdir[i] = t[i] + gnew / gamma * pdir[i];
        memcpy(s, t, nf * sizeof *s);
        gamma = gnew;
    }
}

relief_status hole_fair(hole_patch *p, int continuity, const double *pos,
                        const relief_adjacency *adj, relief_error *err)
{
    size_t nf = p->nx - p->n_rim, nrows = continuity >= 2 ? nf + p->n_mesh : nf;
    /* the patch's own adjacency, in its local indices */
    relief_mesh pm = {.nv = p->nx, .nt = p->nt, .pos = p->x, .tri = p->t};
    relief_adjacency pa = {0};
    fair_rows r = {0, nf, calloc(nrows + 2, sizeof *r.start), NULL, NULL,
                   malloc(3 * nrows * sizeof *r.c), 0};
    double *b = malloc(nrows * sizeof *b), *y = malloc(nf * sizeof *y);
    double *w = malloc((2 * nrows + 3 * nf) * sizeof *w);
    relief_status st = RELIEF_OK;
    if (!r.start || !r.c || !b || !y || !w)
        goto nomem;
    st = relief_mesh_adjacency(&pm, &pa, err);
    if (st != RELIEF_OK)
        goto done;
    /* a chord point has no row: the patch's open border, with no tangent
     * plane to continue (free, the border points fold away) */
    for (size_t v = continuity >= 2 ? 0 : p->n_rim; v < p->nx; ++v)
        if ((v < p->n_mesh || v >= p->n_rim) && !make_row(&r, p, v, &pa, pos, adj))
            goto nomem;
    for (int e = 0; e < 3; ++e) {
        for (size_t i = 0; i < r.nr; ++i)
            b[i] = -r.c[3 * i + e];
        for (size_t i = 0; i < nf; ++i)
            y[i] = p->x[3 * (p->n_rim + i) + e];
        cgls(&r, b, y, w);
        for (size_t i = 0; i < nf; ++i)
            p->x[3 * (p->n_rim + i) + e] = y[i];
    }
    goto done;
nomem:
    st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the fairing of %zu vertices", nf);
done:
    free(r.start), free(r.col), free(r.val), free(r.c), free(b), free(y), free(w);
    relief_adjacency_free(&pa);
    return st;
}
