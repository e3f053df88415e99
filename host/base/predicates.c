/* Exact orientation predicates (predicates.h). An expansion is a sum of
 * doubles, non-overlapping and in increasing magnitude, that holds a value
 * exactly; its sign is its last component's. The plain determinant settles
 * nearly every call; the exact one runs only where the points are coplanar
 * (collinear) or nearly so, which a mesh's own flat regions make common
 * enough to matter, and is kept simple rather than adaptive. Built without
 * floating-point contraction (CMakeLists.txt): two_sum's error term is only
 * exact when each operation is rounded on its own. */
#include "base/predicates.h"

#include <math.h>

/* Enough for mul's largest product (a cofactor of 16 components times a
 * difference of 2: 64). */
#define EXP_MAX 64

/* 2^-53, the unit roundoff of double. */
#define EPS 1.1102230246251565e-16

/* x + y = a + b exactly, x the rounded sum (Knuth). */
static void two_sum(double a, double b, double *x, double *y)
{
    double s = a + b, bv = s - a, av = s - bv;
    *x = s;
    *y = (a - av) + (b - bv);
}

/* x + y = a * b exactly: the fused multiply-add yields the product's
 * rounding error. */
static void two_prod(double a, double b, double *x, double *y)
{
    *x = a * b;
    *y = fma(a, b, -*x);
}

/* h = e * b (h not e); at most 2n components. */
static int scale(const double *e, int n, double b, double *h)
{
    double q, r, p1, p0, s;
    int k = 0;
    two_prod(e[0], b, &q, &r);
    if (r != 0.0)
        h[k++] = r;
    for (int i = 1; i < n; ++i) {
        two_prod(e[i], b, &p1, &p0);
        two_sum(q, p0, &s, &r);
        if (r != 0.0)
            h[k++] = r;
        two_sum(p1, s, &q, &r);
        if (r != 0.0)
            h[k++] = r;
    }
    if (q != 0.0 || k == 0)
        h[k++] = q;
    return k;
}

/* h = e + f (h neither): their components merged by magnitude and summed
 * in that order (Shewchuk's Fast-Expansion-Sum, zeros dropped); at most
 * n + m components. */
static int sum(const double *e, int n, const double *f, int m, double *h)
{
    int i = 0, j = 0, k = 0;
    double q = (m == 0 || (n > 0 && fabs(e[0]) < fabs(f[0]))) ? e[i++] : f[j++], s, r;
    while (i < n || j < m) {
        const double g = (j >= m || (i < n && fabs(e[i]) < fabs(f[j]))) ? e[i++] : f[j++];
        two_sum(q, g, &s, &r);
        if (r != 0.0)
            h[k++] = r;
        q = s;
    }
    if (q != 0.0 || k == 0)
        h[k++] = q;
    return k;
}

/* h = e * f, f of one or two components (h neither). */
static int mul(const double *e, int n, const double *f, int m, double *h)
{
    double t0[EXP_MAX], t1[EXP_MAX];
    if (m == 1)
        return scale(e, n, f[0], h);
    return sum(t0, scale(e, n, f[0], t0), t1, scale(e, n, f[1], t1), h);
}

static int sign_of(const double *e, int n)
{
    return (e[n - 1] > 0.0) - (e[n - 1] < 0.0);
}

/* A point's coordinates less another's, exactly: per coordinate k an
 * expansion at v + 2 k of n[k] components, 1 where the difference is
 * exact in a double (as it is for nearby points: Sterbenz's lemma), else
 * 2. The short ones keep the exact sums below small. */
typedef struct diff3 {
    double v[6];
    int n[3];
} diff3;

static diff3 diff(const double *a, const double *d)
{
    diff3 r;
    for (int k = 0; k < 3; ++k) {
        double x, y;
        two_sum(a[k], -d[k], &x, &y);
        r.n[k] = y != 0.0 ? 2 : 1;
        r.v[2 * k] = y != 0.0 ? y : x;
        r.v[2 * k + 1] = x;
    }
    return r;
}

/* p_i q_j - p_j q_i, exactly; at most 16 components. */
static int minor2(const diff3 *p, const diff3 *q, int i, int j, double *h)
{
    double l[8], r[8];
    int nl = mul(p->v + 2 * i, p->n[i], q->v + 2 * j, q->n[j], l);
    int nr = mul(p->v + 2 * j, p->n[j], q->v + 2 * i, q->n[i], r);
    for (int k = 0; k < nr; ++k)
        r[k] = -r[k];
    return sum(l, nl, r, nr, h);
}

static int orient3d_exact(const double *a, const double *b, const double *c, const double *d)
{
    const diff3 ad = diff(a, d), bd = diff(b, d), cd = diff(c, d);
    double m[16], t[3][64], ab[128], det[192];
    int nt[3];
    for (int k = 0; k < 3; ++k) { /* along a - d's row: a_k times its cofactor */
        int nm = minor2(&bd, &cd, (k + 1) % 3, (k + 2) % 3, m);
        nt[k] = mul(m, nm, ad.v + 2 * k, ad.n[k], t[k]);
    }
    return sign_of(det, sum(ab, sum(t[0], nt[0], t[1], nt[1], ab), t[2], nt[2], det));
}

int relief_orient3d(const double *a, const double *b, const double *c, const double *d)
{
    const double adx = a[0] - d[0], ady = a[1] - d[1], adz = a[2] - d[2];
    const double bdx = b[0] - d[0], bdy = b[1] - d[1], bdz = b[2] - d[2];
    const double cdx = c[0] - d[0], cdy = c[1] - d[1], cdz = c[2] - d[2];
    const double bc = bdx * cdy, cb = cdx * bdy, ca = cdx * ady, ac = adx * cdy;
    const double ab = adx * bdy, ba = bdx * ady;
    const double det = adz * (bc - cb) + bdz * (ca - ac) + cdz * (ab - ba);
    const double perm = (fabs(bc) + fabs(cb)) * fabs(adz) + (fabs(ca) + fabs(ac)) * fabs(bdz) +
                        (fabs(ab) + fabs(ba)) * fabs(cdz);
    const double bound = (7.0 + 56.0 * EPS) * EPS * perm; /* Shewchuk's o3derrboundA */
    if (det > bound || -det > bound)
        return det > 0.0 ? 1 : -1;
    return orient3d_exact(a, b, c, d);
}

int relief_orient2d(const double *a, const double *b, const double *c, int i, int j)
{
    const double l = (a[i] - c[i]) * (b[j] - c[j]), r = (a[j] - c[j]) * (b[i] - c[i]);
    const double det = l - r, bound = (3.0 + 16.0 * EPS) * EPS * (fabs(l) + fabs(r));
    diff3 ac, bc;
    double m[16];
    if (det > bound || -det > bound)
        return det > 0.0 ? 1 : -1;
    ac = diff(a, c), bc = diff(b, c);
    return sign_of(m, minor2(&ac, &bc, i, j, m));
}
