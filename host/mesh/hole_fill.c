/* Exact hole filling (mesh/hole_fill.h): the rims as polygons, step 1
 * (the triangulation) and the driver; hole_refine.c and hole_fair.c hold
 * steps 2 and 3. */
#include "mesh/hole_fill.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/sort.h"
#include "base/vec3.h"
#include "mesh/hole_fill_internal.h"

void relief_hole_fill_options_default(relief_hole_fill_options *o)
{
    memset(o, 0, sizeof *o);
    o->refine = 1;
    o->fair = RELIEF_FAIR_C1;
}

void relief_hole_patches_free(relief_hole_patches *p)
{
    if (!p)
        return;
    free(p->pos), free(p->hole), free(p->tri), free(p->tri_hole);
    memset(p, 0, sizeof *p);
}

int hole_patch_reserve(hole_patch *p, size_t more_x, size_t more_t)
{
    return hole_grow((void **)&p->x, 3 * sizeof *p->x, (void **)&p->sigma, sizeof *p->sigma,
                     &p->cap_x, p->nx + more_x) &&
           hole_grow((void **)&p->t, 3 * sizeof *p->t, NULL, 0, &p->cap_t, p->nt + more_t);
}

/* ------------------------------------------------ step 1: triangulation */

/* The unit normal of triangle a, b, c; zero when degenerate. Returns
 * twice its area. */
static double tri_normal(const double *a, const double *b, const double *c, double *nrm)
{
    double e1[3], e2[3], len;
    sub3(b, a, e1), sub3(c, a, e2);
    cross3(e1, e2, nrm);
    len = sqrt(dot3(nrm, nrm));
    for (int e = 0; e < 3; ++e)
        nrm[e] = len > 0.0 ? nrm[e] / len : 0.0;
    return len;
}

static int is_blocked(const hole_patch *p, uint32_t a, uint32_t b)
{
    if (a > b) {
        uint32_t s = a;
        a = b, b = s;
    }
    for (size_t i = 0; i < p->n_blocked; ++i)
        if (p->blocked[2 * i] == a && p->blocked[2 * i + 1] == b)
            return 1;
    return 0;
}

static int push_tri(hole_patch *p, uint32_t a, uint32_t b, uint32_t c)
{
    if (!hole_patch_reserve(p, 0, 1))
        return 0;
    p->t[3 * p->nt] = a, p->t[3 * p->nt + 1] = b, p->t[3 * p->nt + 2] = c;
    ++p->nt;
    return 1;
}

/* The DP's tables over pairs (i, k), i < k, of an n-gon. */
typedef struct dp_tables {
    size_t n;
    double *angle; /* the largest 1 - cos(dihedral) inside (i, k)'s triangulation */
    double *area;  /* its area */
    double *nrm;   /* 3 per pair: the normal of the triangle on (i, k) */
    int32_t *apex; /* its third vertex, -1: no triangulation */
    uint8_t *forbid; /* 1: (i, k) is an edge of the mesh, not a side */
} dp_tables;

/* 1 - cos of the angle between two unit normals; a missing neighbour (a
 * zero normal: an arc's chord, a degenerate triangle) costs nothing. */
static double bend(const double *a, const double *b)
{
    if (!dot3(b, b) || !dot3(a, a))
        return 0.0;
    return 1.0 - dot3(a, b);
}

/* The best apex m for (i, k): lexicographic in (largest bend, area). */
static void dp_cell(dp_tables *d, const hole_patch *p, const double *opp_nrm, size_t i, size_t k)
{
    size_t n = d->n, ik = i * n + k;
    const double *x = p->x;
    double best_a = INFINITY, best_s = INFINITY;
    d->apex[ik] = -1;
    if (d->forbid[ik])
        return;
    for (size_t m = i + 1; m < k; ++m) {
        size_t im = i * n + m, mk = m * n + k;
        double nt[3], a, s;
        if (d->apex[im] < 0 && m > i + 1)
            continue;
        if (d->apex[mk] < 0 && k > m + 1)
            continue;
        s = 0.5 * tri_normal(x + 3 * i, x + 3 * m, x + 3 * k, nt);
        a = fmax(bend(nt, m == i + 1 ? opp_nrm + 3 * i : d->nrm + 3 * im),
                 bend(nt, k == m + 1 ? opp_nrm + 3 * m : d->nrm + 3 * mk));
        if (m > i + 1)
            a = fmax(a, d->angle[im]), s += d->area[im];
        if (k > m + 1)
            a = fmax(a, d->angle[mk]), s += d->area[mk];
        if (i == 0 && k == n - 1)
            a = fmax(a, bend(nt, opp_nrm + 3 * (n - 1)));
        if (a < best_a - 1e-12 || (a <= best_a + 1e-12 && s < best_s)) {
            best_a = a, best_s = s;
            d->apex[ik] = (int32_t)m;
            memcpy(d->nrm + 3 * ik, nt, sizeof nt);
        }
    }
    d->angle[ik] = best_a, d->area[ik] = best_s;
}

static int dp_emit(hole_patch *p, const dp_tables *d)
{
    size_t n = d->n, top = 0;
    uint32_t *stack = malloc(2 * n * sizeof *stack);
    int ok = stack != NULL;
    if (ok)
        stack[0] = 0, stack[1] = (uint32_t)(n - 1), top = 1;
    while (ok && top) {
        uint32_t i = stack[2 * (top - 1)], k = stack[2 * (top - 1) + 1];
        uint32_t m = (uint32_t)d->apex[i * n + k];
        --top;
        ok = push_tri(p, i, m, k);
        if (m > i + 1)
            stack[2 * top] = i, stack[2 * top + 1] = m, ++top;
        if (k > m + 1)
            stack[2 * top] = m, stack[2 * top + 1] = k, ++top;
    }
    free(stack);
    return ok;
}

/* Barequet-Sharir's search with Liepa's weight. -1: no triangulation
 * avoids the mesh's edges; 0: no memory; 1: done. */
static int triangulate_dp(hole_patch *p, const double *opp_nrm)
{
    size_t n = p->n_rim;
    dp_tables d = {n, malloc(n * n * sizeof *d.angle), malloc(n * n * sizeof *d.area),
                   calloc(n * n * 3, sizeof *d.nrm), malloc(n * n * sizeof *d.apex),
                   calloc(n * n, 1)};
    int r = 0;
    if (!d.angle || !d.area || !d.nrm || !d.apex || !d.forbid)
        goto done;
    for (size_t i = 0; i < p->n_blocked; ++i)
        d.forbid[p->blocked[2 * i] * n + p->blocked[2 * i + 1]] = 1;
    for (size_t len = 2; len < n; ++len)
        for (size_t i = 0; i + len < n; ++i)
            dp_cell(&d, p, opp_nrm, i, i + len);
    r = d.apex[n - 1] < 0 ? -1 : dp_emit(p, &d);
done:
    free(d.angle), free(d.area), free(d.nrm), free(d.apex), free(d.forbid);
    return r;
}

/* Ears over the rim's mean plane (Newell's normal), the smallest interior
 * angle first, an ear holding another rim vertex or closing a mesh edge
 * passed over while another can be cut. */
typedef struct ear_ring {
    uint32_t *prev, *next;
    double *uv; /* n x 2 */
} ear_ring;

static double ear_angle(const ear_ring *r, uint32_t v)
{
    const double *a = r->uv + 2 * r->prev[v], *b = r->uv + 2 * v, *c = r->uv + 2 * r->next[v];
    double e1[2] = {b[0] - a[0], b[1] - a[1]}, e2[2] = {c[0] - b[0], c[1] - b[1]};
    double turn = atan2(e1[0] * e2[1] - e1[1] * e2[0], e1[0] * e2[0] + e1[1] * e2[1]);
    return RELIEF_PI - turn; /* interior angle, > pi where reflex */
}

static int ear_holds_other(const ear_ring *r, uint32_t v)
{
    uint32_t a = r->prev[v], c = r->next[v];
    const double *pa = r->uv + 2 * a, *pb = r->uv + 2 * v, *pc = r->uv + 2 * c;
    for (uint32_t w = r->next[c]; w != a; w = r->next[w]) {
        const double *q = r->uv + 2 * w;
        double d1 = (pb[0] - pa[0]) * (q[1] - pa[1]) - (pb[1] - pa[1]) * (q[0] - pa[0]);
        double d2 = (pc[0] - pb[0]) * (q[1] - pb[1]) - (pc[1] - pb[1]) * (q[0] - pb[0]);
        double d3 = (pa[0] - pc[0]) * (q[1] - pc[1]) - (pa[1] - pc[1]) * (q[0] - pc[0]);
        if (d1 > 0 && d2 > 0 && d3 > 0)
            return 1;
    }
    return 0;
}

static void plane_uv(const hole_patch *p, double *uv)
{
    size_t n = p->n_rim;
    double nn[3] = {0, 0, 0}, c[3] = {0, 0, 0}, u[3], v[3], len;
    for (size_t i = 0; i < n; ++i) {
        const double *a = p->x + 3 * i, *b = p->x + 3 * ((i + 1) % n);
        nn[0] += (a[1] - b[1]) * (a[2] + b[2]);
        nn[1] += (a[2] - b[2]) * (a[0] + b[0]);
        nn[2] += (a[0] - b[0]) * (a[1] + b[1]);
        for (int e = 0; e < 3; ++e)
            c[e] += a[e] / (double)n;
    }
    len = sqrt(dot3(nn, nn));
    for (int e = 0; e < 3; ++e)
        nn[e] = len > 0 ? nn[e] / len : (e == 2);
    u[0] = fabs(nn[0]) < 0.9 ? 1.0 : 0.0, u[1] = 1.0 - u[0], u[2] = 0.0;
    cross3(nn, u, v);
    len = sqrt(dot3(v, v));
    for (int e = 0; e < 3; ++e)
        v[e] /= len;
    cross3(v, nn, u);
    for (size_t i = 0; i < n; ++i) {
        double d[3];
        sub3(p->x + 3 * i, c, d);
        uv[2 * i] = dot3(d, u), uv[2 * i + 1] = dot3(d, v);
    }
}

static int triangulate_ears(hole_patch *p)
{
    size_t n = p->n_rim, left = n;
    ear_ring r = {malloc(n * sizeof *r.prev), malloc(n * sizeof *r.next),
                  malloc(2 * n * sizeof *r.uv)};
    uint32_t v = 0;
    int ok = r.prev && r.next && r.uv;
    if (!ok)
        goto done;
    plane_uv(p, r.uv);
    for (size_t i = 0; i < n; ++i)
        r.prev[i] = (uint32_t)((i + n - 1) % n), r.next[i] = (uint32_t)((i + 1) % n);
    for (; ok && left > 3; --left) {
        uint32_t best = UINT32_MAX, w = v;
        double best_a = INFINITY;
        for (int pass = 0; pass < 2 && best == UINT32_MAX; ++pass) {
            w = v;
            do {
                double a = ear_angle(&r, w);
                if (a < best_a &&
                    (pass || (a < RELIEF_PI && !ear_holds_other(&r, w) &&
                              !is_blocked(p, r.prev[w], r.next[w]))))
                    best = w, best_a = a;
                w = r.next[w];
            } while (w != v);
        }
        ok = push_tri(p, r.prev[best], best, r.next[best]);
        r.next[r.prev[best]] = r.next[best], r.prev[r.next[best]] = r.prev[best];
        v = r.next[best];
    }
    if (ok)
        ok = push_tri(p, r.prev[v], v, r.next[v]);
done:
    free(r.prev), free(r.next), free(r.uv);
    return ok;
}

int hole_triangulate(hole_patch *p, const double *opp, int *by_ears)
{
    size_t n = p->n_rim;
    double *opp_nrm;
    int r = -1;
    *by_ears = 0;
    if (n == 3)
        return push_tri(p, 0, 1, 2);
    if (n <= RELIEF_HOLE_DP_MAX) {
        opp_nrm = calloc(3 * n, sizeof *opp_nrm);
        if (!opp_nrm)
            return 0;
        /* the mesh's triangle across the patch's rim edge (i, i+1) is
         * (x[i+1], x[i], opp[i]) in the mesh's orientation */
        for (size_t i = 0; i < n; ++i)
            if (!isnan(opp[3 * i]))
                tri_normal(p->x + 3 * ((i + 1) % n), p->x + 3 * i, opp + 3 * i,
                           opp_nrm + 3 * i);
        r = triangulate_dp(p, opp_nrm);
        free(opp_nrm);
        if (r >= 0)
            return r;
    }
    *by_ears = 1;
    return triangulate_ears(p);
}
