/* points/rbf.c: the hierarchical RBF of a unit sphere (f's sign, gradient
 * and zero set, projections onto it), a polar cap cut from the sphere and
 * filled (new points on the sphere, covering the cap and only it, spaced,
 * about as many as the cap holds), a square hole in a plane filled in the
 * plane, and the bad inputs. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "check.h"
#include "points/rbf.h"

/* n Fibonacci points on the unit sphere, their outward normals equal. */
static double *fibonacci(size_t n)
{
    double *p = malloc(n * 3 * sizeof *p), golden = RELIEF_PI * (3.0 - sqrt(5.0));
    for (size_t i = 0; i < n; ++i) {
        double z = 1.0 - (2.0 * (double)i + 1.0) / (double)n, r = sqrt(1.0 - z * z);
        p[3 * i] = r * cos(golden * (double)i);
        p[3 * i + 1] = r * sin(golden * (double)i);
        p[3 * i + 2] = z;
    }
    return p;
}

/* The mean nearest-neighbour distance (brute force: small sets only). */
static double mean_spacing(const double *p, size_t n)
{
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) {
        double best = INFINITY;
        for (size_t j = 0; j < n; ++j) {
            double d[3];
            if (j == i)
                continue;
            sub3(p + 3 * i, p + 3 * j, d);
            best = fmin(best, dot3(d, d));
        }
        sum += sqrt(best);
    }
    return sum / (double)n;
}

/* The smallest distance from x to the points q (n x 3). */
static double nearest(const double *q, size_t n, const double x[3])
{
    double best = INFINITY;
    for (size_t j = 0; j < n; ++j) {
        double d[3];
        sub3(q + 3 * j, x, d);
        best = fmin(best, dot3(d, d));
    }
    return sqrt(best);
}

/* A deterministic uniform number in [0, 1). */
static double uniform(unsigned long long *s)
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*s >> 11) / 9007199254740992.0;
}

static void test_sphere(void)
{
    size_t n = 2000, m = 777, bad_f = 0, bad_grad = 0, bad_proj = 0;
    double *p = fibonacci(n), *fresh = fibonacci(m), s = mean_spacing(p, n);
    double worst_f = 0.0, worst_grad = 1.0, worst_len = 1.0, worst_r = 0.0, x[3], g[3], v;
    relief_rbf_params prm = relief_rbf_params_default();
    relief_rbf *f = NULL;
    relief_error err = {0};
    unsigned long long seed = 7;
    prm.spacing = s;
    CHECK(relief_rbf_fit(p, p, n, &prm, &f, &err) == RELIEF_OK, "%s", err.message);
    if (!f)
        goto out;
    for (size_t i = 0; i < m; ++i) {
        const double *q = fresh + 3 * i;
        double len;
        v = relief_rbf_eval(f, q, g);
        len = sqrt(dot3(g, g));
        worst_f = fmax(worst_f, fabs(v));
        worst_grad = fmin(worst_grad, dot3(g, q) / len);
        if (fabs(len - 1.0) > fabs(worst_len - 1.0))
            worst_len = len;
        bad_f += fabs(v) > 0.01;
        bad_grad += dot3(g, q) / len < 0.99 || len < 0.5 || len > 2.0;
        for (int a = 0; a < 3; ++a)
            x[a] = 0.9 * q[a];
        bad_f += !(relief_rbf_eval(f, x, NULL) < 0.0);
        for (int a = 0; a < 3; ++a)
            x[a] = 1.1 * q[a];
        bad_f += !(relief_rbf_eval(f, x, NULL) > 0.0);
    }
    CHECK(bad_f == 0, "sphere: %zu of %zu fresh points with |f| > 0.01 or the wrong sign "
          "inside or outside (worst |f| %g)", bad_f, m, worst_f);
    CHECK(bad_grad == 0, "sphere: %zu gradients off the normal or not about unit (worst "
          "cosine %g, worst length %g)", bad_grad, worst_grad, worst_len);
    x[0] = x[1] = x[2] = 0.0;
    v = relief_rbf_eval(f, x, NULL);
    CHECK(v < -0.1, "sphere: f(centre) = %g, expected < 0 (a fraction of -1: only the "
          "coarse levels reach it)", v);
    x[0] = 50.0;
    v = relief_rbf_eval(f, x, g);
    CHECK(v == 0.0 && g[0] == 0.0, "sphere: f = %g far outside every support, expected 0", v);
    for (int i = 0; i < 500; ++i) {
        double d[3], r = 0.9 + 0.2 * uniform(&seed), len;
        for (int a = 0; a < 3; ++a)
            d[a] = 2.0 * uniform(&seed) - 1.0;
        len = sqrt(dot3(d, d));
        if (len < 0.1 || len > 1.0) {
            --i;
            continue;
        }
        for (int a = 0; a < 3; ++a)
            x[a] = r * d[a] / len;
        if (!relief_rbf_project(f, x, 10, 1e-6)) {
            ++bad_proj;
            continue;
        }
        worst_r = fmax(worst_r, fabs(sqrt(dot3(x, x)) - 1.0));
    }
    CHECK(bad_proj == 0 && worst_r < 0.01, "sphere: %zu of 500 projections failed, worst "
          "radius error %g (expected < 0.01)", bad_proj, worst_r);
    printf("sphere: spacing %.4f, worst |f| %.2e, worst grad cosine %.6f, worst |grad| %.3f, "
           "projection radius error %.2e\n", s, worst_f, worst_grad, worst_len, worst_r);
out:
    relief_rbf_free(f);
    free(p);
    free(fresh);
}

/* The unit sphere without its cap z > 0.8, filled. */
static void test_cap(void)
{
    size_t n0 = 2000, n = 0, n_new = 0, far = 0, off = 0, outside = 0, close = 0, gaps = 0,
           samples = 0, flipped = 0;
    double *all = fibonacci(n0), *p = malloc(n0 * 3 * sizeof *p), s;
    double *np = NULL, *nn = NULL, worst_r = 0.0, worst_gap = 0.0, expect;
    uint32_t *rim = malloc(n0 * sizeof *rim), *hole = NULL;
    relief_rbf_params prm = relief_rbf_params_default();
    relief_rbf *f = NULL;
    relief_error err = {0};
    s = mean_spacing(all, n0);
    for (size_t i = 0; i < n0; ++i)
        if (all[3 * i + 2] <= 0.8) {
            memcpy(p + 3 * n, all + 3 * i, 3 * sizeof *p);
            rim[n++] = all[3 * i + 2] > 0.7;
        }
    prm.spacing = s;
    CHECK(relief_rbf_fit(p, p, n, &prm, &f, &err) == RELIEF_OK, "%s", err.message);
    if (!f)
        goto out;
    CHECK(relief_rbf_fill_holes(f, p, p, n, rim, 1, s, 10000, &np, &nn, &hole, &n_new,
                                &err) == RELIEF_OK, "%s", err.message);
    for (size_t i = 0; i < n_new; ++i) {
        const double *x = np + 3 * i;
        double r = sqrt(dot3(x, x));
        worst_r = fmax(worst_r, fabs(r - 1.0));
        off += fabs(r - 1.0) > 0.02;
        outside += x[2] < 0.6;
        flipped += dot3(nn + 3 * i, x) < 0.99 * r || hole[i] != 1;
        close += nearest(p, n, x) < 0.7 * s;
        for (size_t j = 0; j < i; ++j) {
            double d[3];
            sub3(np + 3 * j, x, d);
            close += dot3(d, d) < 0.49 * s * s;
        }
    }
    /* The removed cap, sampled 4 times finer than the points. */
    for (double z = 0.8 + 0.25 * s; z < 1.0; z += 0.25 * s) {
        double rr = sqrt(1.0 - z * z);
        int k = (int)ceil(2.0 * RELIEF_PI * rr / (0.25 * s));
        for (int j = 0; j < k; ++j) {
            double x[3] = {rr * cos(2.0 * RELIEF_PI * j / k), rr * sin(2.0 * RELIEF_PI * j / k),
                           z};
            double d = n_new ? nearest(np, n_new, x) : INFINITY;
            worst_gap = fmax(worst_gap, d);
            gaps += d > 1.5 * s;
            ++samples;
        }
    }
    (void)far;
    expect = 2.0 * RELIEF_PI * 0.2 / (s * s);
    CHECK(n_new > 0 && off == 0, "cap: %zu of %zu new points off the sphere by > 2 %% (worst "
          "%g)", off, n_new, worst_r);
    CHECK(outside == 0, "cap: %zu new points below z = 0.6", outside);
    CHECK(flipped == 0, "cap: %zu new normals not outward or not of hole 1", flipped);
    CHECK(close == 0, "cap: %zu new points within 0.7 spacing of another point", close);
    CHECK(gaps == 0, "cap: %zu of %zu cap samples farther than 1.5 spacing from every new "
          "point (worst %g spacings)", gaps, samples, worst_gap / s);
    CHECK(n_new > expect / 2.0 && n_new < expect * 2.0, "cap: %zu new points, the cap "
          "holds about %.0f", n_new, expect);
    printf("cap: %zu given, %zu new (cap area / spacing^2 %.0f), worst radius error %.2e, "
           "worst gap %.2f spacings\n", n, n_new, expect, worst_r, worst_gap / s);

    /* Deterministic: a second fill makes the same points. */
    {
        double *p2 = NULL, *n2 = NULL;
        uint32_t *h2 = NULL;
        size_t m2 = 0;
        relief_rbf_fill_holes(f, p, p, n, rim, 1, s, 10000, &p2, &n2, &h2, &m2, &err);
        CHECK(m2 == n_new && (!m2 || !memcmp(p2, np, m2 * 3 * sizeof *p2)),
              "cap: a second fill made %zu points, the first %zu, or others", m2, n_new);
        free(p2), free(n2), free(h2);
    }

    /* max_new too small: refused, naming the count, nothing returned. */
    free(np), free(nn), free(hole);
    np = nn = NULL, hole = NULL;
    CHECK(relief_rbf_fill_holes(f, p, p, n, rim, 1, s, 10, &np, &nn, &hole, &n_new, &err) ==
          RELIEF_E_NOMEM && strstr(err.message, "10") && !np && !nn && !hole && n_new == 0,
          "max_new 10: status %d, '%s'", (int)err.status, err.message);
out:
    relief_rbf_free(f);
    free(all), free(p), free(rim), free(np), free(nn), free(hole);
}

/* A 41 x 41 grid on z = 0, step 0.05, without its square |x|, |y| < 0.3. */
static void test_plane(void)
{
    size_t n = 0, n_new = 0, off = 0, outside = 0, gaps = 0;
    double *p = malloc(41 * 41 * 3 * sizeof *p), *nrm = malloc(41 * 41 * 3 * sizeof *nrm);
    double *np = NULL, *nn = NULL, h = 0.05, worst_z = 0.0, expect = 0.6 * 0.6 / (h * h);
    uint32_t *rim = malloc(41 * 41 * sizeof *rim), *hole = NULL;
    relief_rbf_params prm = relief_rbf_params_default();
    relief_rbf *f = NULL;
    relief_error err = {0};
    for (int i = 0; i < 41; ++i)
        for (int j = 0; j < 41; ++j) {
            double x = -1.0 + h * i, y = -1.0 + h * j, c = fmax(fabs(x), fabs(y));
            if (c < 0.3 - 1e-9)
                continue;
            p[3 * n] = x, p[3 * n + 1] = y, p[3 * n + 2] = 0.0;
            nrm[3 * n] = nrm[3 * n + 1] = 0.0, nrm[3 * n + 2] = 1.0;
            rim[n++] = c < 0.4 - 1e-9;
        }
    prm.spacing = h;
    CHECK(relief_rbf_fit(p, nrm, n, &prm, &f, &err) == RELIEF_OK, "%s", err.message);
    if (!f)
        goto out;
    CHECK(relief_rbf_fill_holes(f, p, nrm, n, rim, 1, h, 10000, &np, &nn, &hole, &n_new,
                                &err) == RELIEF_OK, "%s", err.message);
    for (size_t i = 0; i < n_new; ++i) {
        const double *x = np + 3 * i;
        worst_z = fmax(worst_z, fabs(x[2]));
        off += fabs(x[2]) > 1e-3 * h || nn[3 * i + 2] < 0.999;
        outside += fmax(fabs(x[0]), fabs(x[1])) > 0.3;
    }
    for (double x = -0.3 + 0.25 * h; x < 0.3; x += 0.25 * h)
        for (double y = -0.3 + 0.25 * h; y < 0.3; y += 0.25 * h) {
            double q[3] = {x, y, 0.0};
            gaps += !n_new || nearest(np, n_new, q) > 1.5 * h;
        }
    CHECK(n_new > 0 && off == 0, "plane: %zu of %zu new points off the plane or tilted "
          "(worst |z| %g)", off, n_new, worst_z);
    CHECK(outside == 0, "plane: %zu new points outside the hole", outside);
    CHECK(gaps == 0, "plane: %zu hole samples farther than 1.5 spacing from every new point",
          gaps);
    CHECK(n_new > expect / 2.0 && n_new < expect * 2.0, "plane: %zu new points, the hole "
          "holds about %.0f", n_new, expect);
    printf("plane: %zu given, %zu new (hole area / spacing^2 %.0f), worst |z| %.2e\n", n,
           n_new, expect, worst_z);
out:
    relief_rbf_free(f);
    free(p), free(nrm), free(rim), free(np), free(nn), free(hole);
}

static void test_bad_input(void)
{
    double *p = fibonacci(100), *np = (double *)1, *nn = (double *)1;
    uint32_t rim[100] = {0}, *hole = (uint32_t *)1;
    size_t n_new = 5;
    relief_rbf_params prm = relief_rbf_params_default();
    relief_rbf *f = (relief_rbf *)1;
    relief_error err = {0};
    double zero[12] = {0};

    prm.spacing = 0.3;
    CHECK(relief_rbf_fit(p, p, 3, &prm, &f, &err) == RELIEF_E_RANGE && !f,
          "3 points: %d '%s'", (int)err.status, err.message);
    prm.spacing = 0.0;
    CHECK(relief_rbf_fit(p, p, 100, &prm, &f, &err) == RELIEF_E_RANGE &&
          strstr(err.message, "spacing"), "spacing 0: '%s'", err.message);
    prm.spacing = -1.0;
    CHECK(relief_rbf_fit(p, p, 100, &prm, &f, &err) == RELIEF_E_RANGE, "spacing -1");
    prm.spacing = 0.3;
    prm.levels = 17;
    CHECK(relief_rbf_fit(p, p, 100, &prm, &f, &err) == RELIEF_E_RANGE &&
          strstr(err.message, "1..16"), "17 levels: '%s'", err.message);
    prm.levels = 0;
    prm.base_support = -1.0;
    CHECK(relief_rbf_fit(p, p, 100, &prm, &f, &err) == RELIEF_E_RANGE, "base support -1");
    prm.base_support = 0.0;
    CHECK(relief_rbf_fit(p, zero, 4, &prm, &f, &err) == RELIEF_E_RANGE &&
          strstr(err.message, "normal"), "zero normals: '%s'", err.message);
    prm.spacing = 1e-9;
    CHECK(relief_rbf_fit(p, p, 100, &prm, &f, &err) == RELIEF_E_RANGE, "spacing 1e-9: '%s'",
          err.message);
    prm.spacing = 0.3;
    CHECK(relief_rbf_fit(p, p, 100, &prm, &f, &err) == RELIEF_OK && f, "%s", err.message);

    rim[0] = 1;
    CHECK(relief_rbf_fill_holes(f, p, p, 3, rim, 1, 0.3, 100, &np, &nn, &hole, &n_new, &err) ==
          RELIEF_E_RANGE && !np && !nn && !hole && n_new == 0, "fill, 3 points: '%s'",
          err.message);
    CHECK(relief_rbf_fill_holes(f, p, p, 100, rim, 1, 0.0, 100, &np, &nn, &hole, &n_new,
                                &err) == RELIEF_E_RANGE, "fill, spacing 0: '%s'", err.message);
    CHECK(relief_rbf_fill_holes(f, p, p, 100, rim, 1, -0.3, 100, &np, &nn, &hole, &n_new,
                                &err) == RELIEF_E_RANGE, "fill, spacing -0.3");
    rim[1] = 2;
    CHECK(relief_rbf_fill_holes(f, p, p, 100, rim, 1, 0.3, 100, &np, &nn, &hole, &n_new,
                                &err) == RELIEF_E_RANGE && strstr(err.message, "rim[1]"),
          "fill, rim[1] = 2 of 1 hole: '%s'", err.message);
    rim[0] = rim[1] = 0;
    CHECK(relief_rbf_fill_holes(f, p, p, 100, rim, 1, 0.3, 100, &np, &nn, &hole, &n_new,
                                &err) == RELIEF_OK && !np && !nn && !hole && n_new == 0,
          "fill, no rim: '%s'", err.message);
    relief_rbf_free(f);
    relief_rbf_free(NULL);
    free(p);
}

int main(void)
{
    test_sphere();
    test_cap();
    test_plane();
    test_bad_input();
    return check_result();
}
