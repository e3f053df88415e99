/* Tests of host/smooth/delaunay.c: a regular grid (cocircular points), random
 * points against a brute-force empty-circle check, periodic bands (jittered
 * and regular, the seam anywhere), points on a sphere, and bad input.
 * Exit 0 on pass, 1 on failure. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "base/rng.h"
#include "smooth/delaunay.h"

#define PI 3.14159265358979323846

/* ---------------------------------------------------------------- helpers */

/* Edge statistics of a triangle list over nv vertices. */
typedef struct edge_stats {
    size_t edges;      /* distinct undirected edges */
    size_t once;       /* used by one triangle */
    size_t twice;      /* used by two triangles, in opposite directions */
    size_t bad;        /* used more than twice, or twice the same way */
    size_t used_verts; /* vertices in at least one triangle */
    size_t dup_tris;   /* triangles with the same vertex set as another */
    size_t degenerate; /* triangles with a repeated vertex */
} edge_stats;

typedef struct edge_rec {
    uint32_t a, b; /* a < b */
    int dir;       /* +1 when the triangle runs a -> b */
} edge_rec;

static int edge_cmp(const void *pa, const void *pb)
{
    const edge_rec *x = pa, *y = pb;
    if (x->a != y->a)
        return x->a < y->a ? -1 : 1;
    if (x->b != y->b)
        return x->b < y->b ? -1 : 1;
    return x->dir - y->dir;
}

static int tri_cmp(const void *pa, const void *pb)
{
    const uint32_t *x = pa, *y = pb;
    for (int k = 0; k < 3; ++k)
        if (x[k] != y[k])
            return x[k] < y[k] ? -1 : 1;
    return 0;
}

static void sort3(uint32_t *t)
{
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2 - i; ++j)
            if (t[j] > t[j + 1]) {
                uint32_t s = t[j];
                t[j] = t[j + 1];
                t[j + 1] = s;
            }
}

/* Fills s; `once_ok(a, b, ctx)` (may be NULL) is asked about every edge
 * used once and counted in `once_wrong` when it says no. */
static edge_stats edges_of(const uint32_t *tri, size_t nt, size_t nv,
                           int (*once_ok)(uint32_t, uint32_t, const void *),
                           const void *ctx, size_t *once_wrong)
{
    edge_stats s = {0};
    edge_rec *e = malloc(3 * nt * sizeof *e + 1);
    uint32_t *st = malloc(3 * nt * sizeof *st + 1);
    uint8_t *used = calloc(nv + 1, 1);
    if (once_wrong)
        *once_wrong = 0;
    for (size_t t = 0; t < nt; ++t) {
        const uint32_t *v = tri + 3 * t;
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2])
            ++s.degenerate;
        for (int k = 0; k < 3; ++k) {
            uint32_t a = v[k], b = v[(k + 1) % 3];
            edge_rec *r = e + 3 * t + k;
            r->a = a < b ? a : b;
            r->b = a < b ? b : a;
            r->dir = a < b ? 1 : -1;
            used[a] = 1;
            st[3 * t + k] = v[k];
        }
        sort3(st + 3 * t);
    }
    for (size_t i = 0; i < nv; ++i)
        s.used_verts += used[i];
    qsort(e, 3 * nt, sizeof *e, edge_cmp);
    for (size_t i = 0; i < 3 * nt;) {
        size_t j = i;
        while (j < 3 * nt && e[j].a == e[i].a && e[j].b == e[i].b)
            ++j;
        ++s.edges;
        if (j - i == 1) {
            ++s.once;
            if (once_ok && !once_ok(e[i].a, e[i].b, ctx) && once_wrong)
                ++*once_wrong;
        } else if (j - i == 2 && e[i].dir != e[i + 1].dir) {
            ++s.twice;
        } else {
            ++s.bad;
        }
        i = j;
    }
    qsort(st, nt, 3 * sizeof *st, tri_cmp);
    for (size_t t = 1; t < nt; ++t)
        if (tri_cmp(st + 3 * t, st + 3 * (t - 1)) == 0)
            ++s.dup_tris;
    free(e);
    free(st);
    free(used);
    return s;
}

static double area2(const double *a, const double *b, const double *c)
{
    return 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
}

/* > 0 when d is inside the circle through the counter-clockwise a, b, c. */
static double incircle(const double *a, const double *b, const double *c,
                       const double *d)
{
    double m[3][3];
    const double *p[3] = {a, b, c};
    for (int i = 0; i < 3; ++i) {
        double x = p[i][0] - d[0], y = p[i][1] - d[1];
        m[i][0] = x;
        m[i][1] = y;
        m[i][2] = x * x + y * y;
    }
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

/* Vertices of the convex hull of n points (monotone chain, strict). */
static size_t hull_count(const double *p, size_t n)
{
    size_t *idx = malloc(n * sizeof *idx), *h = malloc(2 * n * sizeof *h);
    size_t k = 0;
    for (size_t i = 0; i < n; ++i)
        idx[i] = i;
    for (size_t i = 1; i < n; ++i) /* insertion sort: n is small */
        for (size_t j = i; j > 0; --j) {
            const double *a = p + 2 * idx[j - 1], *b = p + 2 * idx[j];
            if (a[0] > b[0] || (a[0] == b[0] && a[1] > b[1])) {
                size_t s = idx[j];
                idx[j] = idx[j - 1];
                idx[j - 1] = s;
            } else {
                break;
            }
        }
    for (size_t i = 0; i < n; ++i) {
        while (k >= 2 && area2(p + 2 * h[k - 2], p + 2 * h[k - 1],
                               p + 2 * idx[i]) <= 0.0)
            --k;
        h[k++] = idx[i];
    }
    for (size_t i = n - 1, lo = k + 1; i-- > 0;) {
        while (k >= lo && area2(p + 2 * h[k - 2], p + 2 * h[k - 1],
                                p + 2 * idx[i]) <= 0.0)
            --k;
        h[k++] = idx[i];
    }
    free(idx);
    free(h);
    return k - 1;
}

/* ------------------------------------------------------------ the plane */

typedef struct square {
    double lo, hi;
    const double *uv;
} square;

static int on_square_side(uint32_t a, uint32_t b, const void *ctx)
{
    const square *q = ctx;
    const double *p = q->uv + 2 * a, *r = q->uv + 2 * b;
    for (int k = 0; k < 2; ++k)
        if ((p[k] == q->lo && r[k] == q->lo) || (p[k] == q->hi && r[k] == q->hi))
            return 1;
    return 0;
}

/* An n x n unit grid at (x0, y0) plus `dups` copies of its first points. */
static void test_grid(int n, double x0, double y0, int dups)
{
    size_t np = (size_t)n * n + dups, nt = 0, unused = 99, wrong;
    double *uv = malloc(2 * np * sizeof *uv), total = 0.0;
    uint32_t *tri = NULL;
    relief_error err = {0};
    int negative = 0;
    relief_status st;
    edge_stats s;
    square q = {0.0, n - 1.0, uv};

    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            uv[2 * (j * n + i)] = x0 + i;
            uv[2 * (j * n + i) + 1] = y0 + j;
        }
    for (int d = 0; d < dups; ++d) {
        uv[2 * ((size_t)n * n + d)] = uv[2 * d];
        uv[2 * ((size_t)n * n + d) + 1] = uv[2 * d + 1];
    }
    st = relief_delaunay_2d(uv, np, &tri, &nt, &unused, &err);
    CHECK(st == RELIEF_OK, "grid %d at (%g, %g): %s", n, x0, y0, err.message);
    if (st != RELIEF_OK) {
        free(uv);
        return;
    }
    CHECK(nt == (size_t)2 * (n - 1) * (n - 1), "grid %d: %zu triangles", n, nt);
    CHECK(unused == (size_t)dups, "grid %d: %zu unused, %d duplicates", n,
          unused, dups);
    for (size_t t = 0; t < nt; ++t) {
        double a = area2(uv + 2 * tri[3 * t], uv + 2 * tri[3 * t + 1],
                         uv + 2 * tri[3 * t + 2]);
        negative += a <= 0.0;
        total += a;
    }
    CHECK(negative == 0, "grid %d: %d triangles not counter-clockwise", n,
          negative);
    CHECK(fabs(total - (n - 1.0) * (n - 1.0)) < 1e-9, "grid %d: area %.12g",
          n, total);
    /* The check works in grid coordinates relative to (x0, y0). */
    for (size_t i = 0; i < np; ++i) {
        uv[2 * i] -= x0;
        uv[2 * i + 1] -= y0;
    }
    s = edges_of(tri, nt, np, on_square_side, &q, &wrong);
    CHECK(s.bad == 0 && s.degenerate == 0 && s.dup_tris == 0,
          "grid %d: %zu bad edges, %zu degenerate, %zu duplicate triangles", n,
          s.bad, s.degenerate, s.dup_tris);
    CHECK(s.once == (size_t)4 * (n - 1) && wrong == 0,
          "grid %d: %zu boundary edges (%zu off the square's sides)", n, s.once,
          wrong);
    CHECK((long)s.used_verts - (long)s.edges + (long)nt == 1,
          "grid %d: V - E + F = %zu - %zu + %zu", n, s.used_verts, s.edges, nt);
    free(tri);
    free(uv);
}

static void test_random(size_t n, uint32_t seed)
{
    relief_rng rng;
    double *uv = malloc(2 * n * sizeof *uv), total = 0.0;
    uint32_t *tri = NULL;
    size_t nt = 0, h, violations = 0, negative = 0;
    relief_error err = {0};
    relief_status st;
    edge_stats s;

    relief_rng_seed(&rng, seed);
    for (size_t i = 0; i < 2 * n; ++i)
        uv[i] = relief_rng_uniform(&rng);
    st = relief_delaunay_2d(uv, n, &tri, &nt, NULL, &err);
    CHECK(st == RELIEF_OK, "random %zu: %s", n, err.message);
    if (st != RELIEF_OK) {
        free(uv);
        return;
    }
    h = hull_count(uv, n);
    CHECK(nt == 2 * n - h - 2, "random %zu: %zu triangles, hull %zu", n, nt, h);
    for (size_t t = 0; t < nt; ++t) {
        const double *a = uv + 2 * tri[3 * t], *b = uv + 2 * tri[3 * t + 1];
        const double *c = uv + 2 * tri[3 * t + 2];
        double ar = area2(a, b, c);
        negative += ar <= 0.0;
        total += ar;
        for (size_t i = 0; i < n; ++i) {
            if (i == tri[3 * t] || i == tri[3 * t + 1] || i == tri[3 * t + 2])
                continue;
            violations += incircle(a, b, c, uv + 2 * i) > 1e-12;
        }
    }
    CHECK(negative == 0, "random %zu: %zu not counter-clockwise", n, negative);
    CHECK(violations == 0, "random %zu: %zu points inside circumcircles", n,
          violations);
    s = edges_of(tri, nt, n, NULL, NULL, NULL);
    CHECK(s.bad == 0 && s.once == h && s.used_verts == n,
          "random %zu: %zu bad, %zu boundary edges (hull %zu), %zu used", n,
          s.bad, s.once, h, s.used_verts);
    CHECK((long)s.used_verts - (long)s.edges + (long)nt == 1,
          "random %zu: V - E + F = %zu - %zu + %zu", n, s.used_verts, s.edges,
          nt);
    CHECK(total > 0.8 && total < 1.0, "random %zu: area %g", n, total);
    free(tri);
    free(uv);
}

/* ------------------------------------------------------- periodic bands */

typedef struct band {
    const double *uv;
    double z0, z1;
} band;

static int on_band_rim(uint32_t a, uint32_t b, const void *ctx)
{
    const band *q = ctx;
    double za = q->uv[2 * a + 1], zb = q->uv[2 * b + 1];
    return (za == q->z0 && zb == q->z0) || (za == q->z1 && zb == q->z1);
}

/* nu x nv points on u in [0, 2 pi) + offset (any real: the function wraps
 * it), z in [0, 1]; jitter (a fraction of the spacing) moves u everywhere
 * and z off the rims; the last point, when dup, repeats the first one
 * shifted by a period. */
static void test_band(int nu, int nv, double jitter, double offset, int dup,
                      uint32_t seed)
{
    const double period = 2.0 * PI;
    size_t n = (size_t)nu * nv + (dup != 0), nt = 0, unused = 99, wrong = 0;
    double *uv = malloc(2 * n * sizeof *uv), total = 0.0;
    uint32_t *tri = NULL;
    relief_error err = {0};
    relief_rng rng;
    int negative = 0;
    relief_status st;
    edge_stats s;
    band q = {uv, 0.0, 1.0};

    relief_rng_seed(&rng, seed);
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            double du = jitter * (relief_rng_uniform(&rng) - 0.5);
            double dz = jitter * (relief_rng_uniform(&rng) - 0.5);
            uv[2 * (j * nu + i)] = offset + (i + du) * period / nu;
            uv[2 * (j * nu + i) + 1] =
                (j == 0 || j == nv - 1) ? (double)j / (nv - 1)
                                        : (j + dz) / (nv - 1);
        }
    if (dup) {
        uv[2 * (n - 1)] = uv[0] + period;
        uv[2 * (n - 1) + 1] = uv[1];
    }
    st = relief_delaunay_periodic(uv, n, period, &tri, &nt, &unused, &err);
    CHECK(st == RELIEF_OK, "band %dx%d jitter %g: %s", nu, nv, jitter,
          err.message);
    if (st != RELIEF_OK) {
        free(uv);
        return;
    }
    CHECK(nt == (size_t)2 * nu * (nv - 1), "band %dx%d jitter %g: %zu triangles",
          nu, nv, jitter, nt);
    CHECK(unused == (size_t)(dup != 0), "band %dx%d: %zu unused", nu, nv,
          unused);
    for (size_t t = 0; t < nt; ++t) {
        double p[3][2];
        /* Unwrap u to within half a period of the first vertex. */
        for (int k = 0; k < 3; ++k) {
            const double *v = uv + 2 * tri[3 * t + k];
            p[k][0] = v[0];
            p[k][1] = v[1];
            if (k > 0)
                p[k][0] -= period * round((p[k][0] - p[0][0]) / period);
        }
        double a = area2(p[0], p[1], p[2]);
        negative += a <= 0.0;
        total += a;
    }
    CHECK(negative == 0, "band %dx%d jitter %g: %d not counter-clockwise", nu,
          nv, jitter, negative);
    CHECK(fabs(total - period) < 1e-9, "band %dx%d jitter %g: area %.15g",
          nu, nv, jitter, total);
    s = edges_of(tri, nt, n, on_band_rim, &q, &wrong);
    CHECK(s.bad == 0 && s.degenerate == 0 && s.dup_tris == 0,
          "band %dx%d jitter %g: %zu bad edges, %zu degenerate, %zu duplicate",
          nu, nv, jitter, s.bad, s.degenerate, s.dup_tris);
    CHECK(s.once == (size_t)2 * nu && wrong == 0,
          "band %dx%d jitter %g: %zu edges used once, %zu off the rims", nu, nv,
          jitter, s.once, wrong);
    CHECK((long)s.used_verts - (long)s.edges + (long)nt == 0,
          "band %dx%d jitter %g: V - E + F = %zu - %zu + %zu", nu, nv, jitter,
          s.used_verts, s.edges, nt);
    free(tri);
    free(uv);
}

/* A band as a scan gives it: rims that wander by `jag` of a row's spacing
 * (a hair: their points nearly collinear, so the triangles along them are
 * slivers with circles spanning periods) and a hole of radius hole_r across
 * the seam, wider than the first margin. Every triangle kept is
 * counter-clockwise and has no copy of any point (u + k period, k -1..1)
 * inside its circle, every point is used, and no edge has three
 * triangles. */
static void test_jagged_band(int nu, int nv, double jag, double hole_r, uint32_t seed)
{
    const double period = 2.0 * PI; /* a unit cylinder unrolled, z along it */
    double *uv = malloc(2 * (size_t)nu * nv * sizeof *uv);
    uint32_t *tri = NULL;
    size_t n = 0, nt = 0, unused = 99, inside = 0, negative = 0, wrong = 0;
    relief_error err = {0};
    relief_rng rng;
    relief_status st;
    edge_stats s;

    relief_rng_seed(&rng, seed);
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            double u = (i + 0.4 * (relief_rng_uniform(&rng) - 0.5)) * period / nu;
            double z = j / (nv - 1.0);
            z += ((j == 0 || j == nv - 1) ? jag : 0.4) * (relief_rng_uniform(&rng) - 0.5) /
                 (nv - 1);
            if (hypot(remainder(u, period), z - 0.5) < hole_r)
                continue; /* the hole, centred on the seam */
            uv[2 * n] = u;
            uv[2 * n + 1] = z;
            ++n;
        }
    st = relief_delaunay_periodic(uv, n, period, &tri, &nt, &unused, &err);
    CHECK(st == RELIEF_OK, "jagged band %dx%d: %s", nu, nv, err.message);
    if (st != RELIEF_OK) {
        free(uv);
        return;
    }
    for (size_t t = 0; t < nt; ++t) {
        double p[3][2];
        for (int k = 0; k < 3; ++k) {
            const double *v = uv + 2 * tri[3 * t + k];
            p[k][0] = v[0] - (k ? period * round((v[0] - p[0][0]) / period) : 0.0);
            p[k][1] = v[1];
        }
        negative += area2(p[0], p[1], p[2]) <= 0.0;
        for (size_t i = 0; i < n; ++i)
            for (int k = -1; k <= 1; ++k) {
                double q[2] = {uv[2 * i] + k * period, uv[2 * i + 1]};
                inside += incircle(p[0], p[1], p[2], q) > 1e-9;
            }
    }
    CHECK(negative == 0 && inside == 0, "jagged band %dx%d: %zu of %zu triangles clockwise, "
          "%zu points inside a circle", nu, nv, negative, nt, inside);
    CHECK(unused == 0, "jagged band %dx%d: %zu points unused", nu, nv, unused);
    s = edges_of(tri, nt, n, NULL, NULL, &wrong);
    CHECK(s.bad == 0 && s.degenerate == 0 && s.dup_tris == 0,
          "jagged band %dx%d: %zu bad edges, %zu degenerate, %zu duplicate", nu, nv, s.bad,
          s.degenerate, s.dup_tris);
    free(tri);
    free(uv);
}

/* -------------------------------------------------------------- spheres */

static void check_closed(const double *d, size_t n, const uint32_t *tri,
                         size_t nt, const char *name, double area_tol)
{
    double total = 0.0;
    size_t inward = 0;
    edge_stats s;
    for (size_t t = 0; t < nt; ++t) {
        const double *a = d + 3 * tri[3 * t], *b = d + 3 * tri[3 * t + 1];
        const double *c = d + 3 * tri[3 * t + 2];
        double e1[3], e2[3], x[3], m = 0.0;
        for (int k = 0; k < 3; ++k) {
            e1[k] = b[k] - a[k];
            e2[k] = c[k] - a[k];
        }
        x[0] = e1[1] * e2[2] - e1[2] * e2[1];
        x[1] = e1[2] * e2[0] - e1[0] * e2[2];
        x[2] = e1[0] * e2[1] - e1[1] * e2[0];
        for (int k = 0; k < 3; ++k)
            m += x[k] * (a[k] + b[k] + c[k]);
        inward += m <= 0.0;
        total += 0.5 * sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    }
    CHECK(inward == 0, "%s: %zu triangles face inwards", name, inward);
    CHECK(fabs(total - 4.0 * PI) < area_tol * 4.0 * PI,
          "%s: area %g, sphere %g", name, total, 4.0 * PI);
    s = edges_of(tri, nt, n, NULL, NULL, NULL);
    CHECK(s.once == 0 && s.bad == 0 && s.dup_tris == 0 && s.degenerate == 0,
          "%s: %zu edges used once, %zu bad, %zu duplicate triangles", name,
          s.once, s.bad, s.dup_tris);
    CHECK((long)s.used_verts - (long)s.edges + (long)nt == 2,
          "%s: V - E + F = %zu - %zu + %zu", name, s.used_verts, s.edges, nt);
}

static void test_sphere(void)
{
    const size_t n = 500;
    double *d = malloc(3 * n * sizeof *d);
    double cube[8 * 3];
    uint32_t *tri = NULL;
    size_t nt = 0, unused = 99;
    relief_error err = {0};
    relief_status st;

    /* Fibonacci lattice. */
    for (size_t i = 0; i < n; ++i) {
        double z = 1.0 - (2.0 * i + 1.0) / n, r = sqrt(1.0 - z * z);
        double a = PI * (3.0 - sqrt(5.0)) * i;
        d[3 * i] = r * cos(a);
        d[3 * i + 1] = r * sin(a);
        d[3 * i + 2] = z;
    }
    st = relief_hull_sphere(d, n, &tri, &nt, &unused, &err);
    CHECK(st == RELIEF_OK, "fibonacci: %s", err.message);
    if (st == RELIEF_OK) {
        CHECK(nt == 2 * n - 4 && unused == 0, "fibonacci: %zu triangles, %zu "
              "unused", nt, unused);
        check_closed(d, n, tri, nt, "fibonacci", 0.01);
        free(tri);
    }
    free(d);

    /* Cube corners: six square faces of four coplanar points each. */
    for (int i = 0; i < 8; ++i)
        for (int k = 0; k < 3; ++k)
            cube[3 * i + k] = ((i >> k) & 1 ? 1.0 : -1.0) / sqrt(3.0);
    st = relief_hull_sphere(cube, 8, &tri, &nt, &unused, &err);
    CHECK(st == RELIEF_OK, "cube: %s", err.message);
    if (st == RELIEF_OK) {
        CHECK(nt == 12 && unused == 0, "cube: %zu triangles, %zu unused", nt,
              unused);
        /* A cube's area (8) is far from the sphere's: topology only. */
        check_closed(cube, 8, tri, nt, "cube", 1.0);
        free(tri);
    }
}

/* ----------------------------------------------------------- bad input */

static void expect_fail(relief_status st, uint32_t *tri, const relief_error *err,
                        const char *name)
{
    CHECK(st != RELIEF_OK, "%s: accepted", name);
    CHECK(tri == (uint32_t *)&expect_fail, "%s: output written on failure", name);
    CHECK(err->message[0] != '\0', "%s: no message", name);
    if (st != RELIEF_OK && getenv("TEST_VERBOSE"))
        printf("  %s: %s\n", name, err->message);
}

static void test_errors(void)
{
    const double two[] = {0, 0, 1, 1};
    const double line[] = {0, 0, 1, 1, 2, 2, 3, 3, 4, 4};
    const double same[] = {1, 2, 1, 2, 1, 2, 1, 2};
    const double nan_pt[] = {0, 0, 1, 0, NAN, 1};
    const double ring[] = {0, 0.5, 1, 0.5, 2, 0.5, 3, 0.5};
    const double circle[] = {1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0,
                             0.6, 0.8, 0};
    const double dup3[] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    /* Two points around: every triangle spans half the period. */
    const double sparse[] = {0, 0, 0, 1, PI, 0, PI, 1};
    /* Sentinel: any write to *tri on failure shows. */
    uint32_t *const sentinel = (uint32_t *)&expect_fail;
    uint32_t *tri;
    size_t nt;
    relief_error err;

#define FAILS(call, name)                                                     \
    do {                                                                      \
        relief_status st_;                                                    \
        tri = sentinel;                                                       \
        memset(&err, 0, sizeof err);                                          \
        st_ = (call);                                                         \
        expect_fail(st_, tri, &err, name);                                    \
    } while (0)
    FAILS(relief_delaunay_2d(two, 2, &tri, &nt, NULL, &err), "2d two points");
    FAILS(relief_delaunay_2d(line, 5, &tri, &nt, NULL, &err), "2d collinear");
    FAILS(relief_delaunay_2d(same, 4, &tri, &nt, NULL, &err), "2d coincident");
    FAILS(relief_delaunay_2d(nan_pt, 3, &tri, &nt, NULL, &err), "2d NaN");
    FAILS(relief_delaunay_periodic(two, 2, 1.0, &tri, &nt, NULL, &err),
          "periodic two points");
    FAILS(relief_delaunay_periodic(ring, 4, 4.0, &tri, &nt, NULL, &err),
          "periodic one ring");
    FAILS(relief_delaunay_periodic(same, 4, 4.0, &tri, &nt, NULL, &err),
          "periodic coincident");
    FAILS(relief_delaunay_periodic(line, 5, 0.0, &tri, &nt, NULL, &err),
          "periodic zero period");
    FAILS(relief_delaunay_periodic(sparse, 4, 2.0 * PI, &tri, &nt, NULL, &err),
          "periodic two points around");
    FAILS(relief_hull_sphere(circle, 3, &tri, &nt, NULL, &err),
          "sphere three points");
    FAILS(relief_hull_sphere(circle, 5, &tri, &nt, NULL, &err),
          "sphere coplanar");
    FAILS(relief_hull_sphere(dup3, 4, &tri, &nt, NULL, &err),
          "sphere coincident");
#undef FAILS
}

int main(void)
{
    test_grid(10, 0.0, 0.0, 0);
    test_grid(10, 1e4, -3e3, 3);   /* far from the origin, with duplicates */
    test_grid(40, 0.0, 0.0, 0);
    test_random(200, 7);
    test_random(200, 8);
    test_band(24, 8, 0.6, 0.0, 0, 3);   /* jittered */
    test_band(24, 8, 0.0, 0.0, 0, 3);   /* regular: cocircular at the seam */
    test_band(24, 8, 0.0, 0.123, 1, 3); /* seam between columns, duplicate */
    test_band(7, 5, 0.5, -2.0, 0, 4);   /* few points around, negative u */
    test_band(300, 30, 0.8, 1.0, 1, 5);
    test_band(200, 4, 0.5, 0.0, 0, 6);  /* wide spacing in u: margin grows */
    test_jagged_band(120, 16, 1e-4, 0.3, 7); /* slivers along the rims */
    test_jagged_band(60, 30, 1e-4, 0.4, 8);
    test_jagged_band(240, 16, 0.0, 0.45, 9);  /* straight rims, a wide hole */
    test_sphere();
    test_errors();
    return check_result();
}
