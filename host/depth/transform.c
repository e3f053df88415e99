#include "depth/transform.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/pool.h"

/* ---------------------------------------------------------------- membrane */

/* Whether pixel i belongs to the domain (NULL: the whole image), and
 * whether it is one of its unknowns. */
static int in_domain(const uint8_t *domain, size_t i)
{
    return !domain || domain[i];
}

static int unknown(const uint8_t *known, const uint8_t *domain, size_t i)
{
    return !known[i] && in_domain(domain, i);
}

/* y = A x over the unknowns: A is the negative 4-neighbour Laplacian
 * restricted to them (known neighbours move to the right-hand side; a
 * neighbour outside the image is no neighbour). idx[i] is the unknown's
 * number of pixel i, or -1. */
static void apply(const int32_t *idx, const int32_t *pix, size_t m, int W, int H,
                  const uint8_t *domain, const double *x, double *y)
{
    for (size_t k = 0; k < m; ++k) {
        int px = pix[k] % W, py = pix[k] / W, deg = 0;
        double s = 0.0;
        int nb[4][2] = {{px - 1, py}, {px + 1, py}, {px, py - 1}, {px, py + 1}};
        for (int j = 0; j < 4; ++j) {
            int u = nb[j][0], v = nb[j][1];
            int32_t o;
            if (u < 0 || u >= W || v < 0 || v >= H || !in_domain(domain, (size_t)v * W + u))
                continue;
            ++deg;
            o = idx[(size_t)v * W + u];
            if (o >= 0)
                s -= x[o];
        }
        y[k] = deg * x[k] + s;
    }
}

/* Conjugate gradients on A x = b over m unknowns, from the x given, to a
 * relative residual of 1e-8 (|r|^2 <= 1e-16 |b|^2, b2 = |b|^2) or max_iter
 * iterations; A(ctx, in, out) applies the symmetric positive definite
 * operator (it may touch entries of in beyond m). r, p and q are scratch of
 * the operator's size. Returns the iterations made. */
static int conjugate_gradients(size_t m, const double *b, double b2, double *x, double *r,
                               double *p, double *q,
                               void (*A)(void *ctx, double *in, double *out), void *ctx,
                               int max_iter)
{
    double rr = 0.0;
    int it = 0;
    A(ctx, x, q);
    for (size_t k = 0; k < m; ++k) {
        r[k] = b[k] - q[k];
        p[k] = r[k];
        rr += r[k] * r[k];
    }
    while (it < max_iter && rr > 1e-16 * (b2 > 0.0 ? b2 : 1.0)) {
        double pq = 0.0, alpha, rr_new = 0.0;
        A(ctx, p, q);
        for (size_t k = 0; k < m; ++k)
            pq += p[k] * q[k];
        if (!(pq > 0.0))
            break;
        alpha = rr / pq;
        for (size_t k = 0; k < m; ++k) {
            x[k] += alpha * p[k];
            r[k] -= alpha * q[k];
            rr_new += r[k] * r[k];
        }
        for (size_t k = 0; k < m; ++k)
            p[k] = r[k] + rr_new / rr * p[k];
        rr = rr_new;
        ++it;
    }
    return it;
}

/* The membrane's operator for conjugate_gradients. */
typedef struct membrane_op {
    const int32_t *idx, *pix;
    size_t m;
    int W, H;
    const uint8_t *domain;
} membrane_op;

static void membrane_apply(void *ctx, double *in, double *out)
{
    const membrane_op *o = ctx;
    apply(o->idx, o->pix, o->m, o->W, o->H, o->domain, in, out);
}

relief_status relief_membrane_fill(float *z, const uint8_t *known, int width, int height,
                                   int max_iter, int *iterations, relief_error *err)
{
    return relief_poisson_fill(z, known, NULL, NULL, width, height, max_iter, iterations,
                               err);
}

/* Numbers the unknowns of the n pixels in raster order: idx[i] (n entries)
 * is pixel i's unknown number or -1, pix[k] (one per unknown) its pixel.
 * Returns the unknowns' count. */
static size_t poisson_number(const uint8_t *known, const uint8_t *domain, size_t n,
                             int32_t *idx, int32_t *pix)
{
    size_t m = 0;
    for (size_t i = 0; i < n; ++i) {
        idx[i] = unknown(known, domain, i) ? (int32_t)m : -1;
        if (idx[i] >= 0)
            pix[m++] = (int32_t)i;
    }
    return m;
}

/* The right-hand side b (m entries, zeroed by the caller) for the m
 * unknowns pix[]: the known neighbours' depths in z (width x height) plus
 * source at the pixel if given; the starting guess x (m entries): the known
 * neighbours' mean where there are any (faster than 0 on thin holes), else
 * 0. Returns |b|^2. */
static double poisson_rhs(const float *z, const uint8_t *known, const uint8_t *domain,
                          const float *source, int width, int height, const int32_t *pix,
                          size_t m, double *b, double *x)
{
    double b2 = 0.0;
    for (size_t k = 0; k < m; ++k) {
        int px = pix[k] % width, py = pix[k] / width, c = 0;
        int nb[4][2] = {{px - 1, py}, {px + 1, py}, {px, py - 1}, {px, py + 1}};
        for (int j = 0; j < 4; ++j) {
            int u = nb[j][0], v = nb[j][1];
            size_t o;
            if (u < 0 || u >= width || v < 0 || v >= height)
                continue;
            o = (size_t)v * width + u;
            if (known[o] && in_domain(domain, o)) {
                b[k] += z[o];
                ++c;
            }
        }
        x[k] = c ? b[k] / c : 0.0;
        if (source)
            b[k] += source[pix[k]];
        b2 += b[k] * b[k];
    }
    return b2;
}

relief_status relief_poisson_fill(float *z, const uint8_t *known, const uint8_t *domain,
                                  const float *source, int width, int height, int max_iter,
                                  int *iterations, relief_error *err)
{
    size_t n = (size_t)width * height, m = 0, any = 0;
    int32_t *idx = NULL, *pix = NULL;
    double *x = NULL, *b = NULL, *r = NULL, *p = NULL, *q = NULL, b2 = 0.0;
    int it = 0;
    relief_status st = RELIEF_OK;

    if (iterations)
        *iterations = 0;
    for (size_t i = 0; i < n; ++i) {
        any += known[i] != 0 && in_domain(domain, i);
        m += unknown(known, domain, i);
    }
    if (!any)
        return relief_fail(err, RELIEF_E_RANGE, "no pixel is known: nothing to interpolate "
                           "from");
    if (!m)
        return RELIEF_OK;
    idx = malloc(n * sizeof *idx);
    pix = malloc(m * sizeof *pix);
    x = calloc(m, sizeof *x);
    b = calloc(m, sizeof *b);
    r = malloc(m * sizeof *r);
    p = malloc(m * sizeof *p);
    q = malloc(m * sizeof *q);
    if (!idx || !pix || !x || !b || !r || !p || !q) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the membrane's %zu unknowns", m);
        goto done;
    }
    m = poisson_number(known, domain, n, idx, pix);
    b2 = poisson_rhs(z, known, domain, source, width, height, pix, m, b, x);
    /* Conjugate gradients: A is symmetric positive definite when every
     * component of the unknowns touches a known pixel (it does unless
     * none is known, refused above). */
    {
        membrane_op op = {idx, pix, m, width, height, domain};
        it = conjugate_gradients(m, b, b2, x, r, p, q, membrane_apply, &op, max_iter);
    }
    for (size_t k = 0; k < m; ++k)
        z[pix[k]] = (float)x[k];
    if (iterations)
        *iterations = it;
done:
    free(idx);
    free(pix);
    free(x);
    free(b);
    free(r);
    free(p);
    free(q);
    return st;
}

/* ---------------------------------------------------------------- thin plate */

/* (L w)_p for the band pixels, w given on the band (0 off it): the sum
 * over p's 4-neighbours inside the image of w_q - w_p. band[] lists the
 * band's pixels; at[] maps a pixel to its band index or -1. */
static void laplacian(const int32_t *band, size_t nb, const int32_t *at, int W, int H,
                      const uint8_t *domain, const double *w, double *out)
{
    for (size_t k = 0; k < nb; ++k) {
        int px = band[k] % W, py = band[k] / W;
        int nb4[4][2] = {{px - 1, py}, {px + 1, py}, {px, py - 1}, {px, py + 1}};
        double s = 0.0;
        for (int j = 0; j < 4; ++j) {
            int u = nb4[j][0], v = nb4[j][1];
            int32_t o;
            if (u < 0 || u >= W || v < 0 || v >= H || !in_domain(domain, (size_t)v * W + u))
                continue;
            o = at[(size_t)v * W + u];
            s += (o >= 0 ? w[o] : 0.0) - w[k];
        }
        out[k] = s;
    }
}

/* The thin plate's operator for conjugate_gradients: L L on the unknowns,
 * the band's other entries of `in` zeroed first; y is scratch. */
typedef struct plate_op {
    const int32_t *band, *at;
    size_t nb, m;
    int W, H;
    const uint8_t *domain;
    double *y;
} plate_op;

static void plate_apply(void *ctx, double *in, double *out)
{
    const plate_op *o = ctx;
    for (size_t k = o->m; k < o->nb; ++k)
        in[k] = 0.0;
    laplacian(o->band, o->nb, o->at, o->W, o->H, o->domain, in, o->y);
    laplacian(o->band, o->nb, o->at, o->W, o->H, o->domain, o->y, out);
}

/* The thin plate's band in at[] (n = W x H entries, -1 on entry) and
 * band[] (its pixels, room for n): the unknowns first in raster order, then
 * the domain's pixels within two steps of one (the reach of L L). Returns
 * the band's size. */
static size_t plate_band(const uint8_t *known, const uint8_t *domain, int W, int H,
                         int32_t *at, int32_t *band)
{
    size_t n = (size_t)W * H, nb = 0;
    for (size_t i = 0; i < n; ++i)
        if (unknown(known, domain, i)) {
            at[i] = (int32_t)nb;
            band[nb++] = (int32_t)i;
        }
    for (int ring = 0; ring < 2; ++ring) {
        size_t end = nb;
        for (size_t k = 0; k < end; ++k) {
            int px = band[k] % W, py = band[k] / W;
            int nb4[4][2] = {{px - 1, py}, {px + 1, py}, {px, py - 1}, {px, py + 1}};
            for (int j = 0; j < 4; ++j) {
                int u = nb4[j][0], v = nb4[j][1];
                size_t o;
                if (u < 0 || u >= W || v < 0 || v >= H)
                    continue;
                o = (size_t)v * W + u;
                if (at[o] < 0 && in_domain(domain, o)) {
                    at[o] = (int32_t)nb;
                    band[nb++] = (int32_t)o;
                }
            }
        }
    }
    return nb;
}

/* b = -(L L u_known) on the op's m unknowns: c = u_known on the band (0 on
 * the unknowns), y = L c (op->y), b = -(L y) through q; x = the harmonic
 * fill already in z, the start. b, x, c, q: op->nb entries, zeroed by the
 * caller. Returns |b|^2. */
static double plate_rhs(const float *z, const plate_op *op, double *b, double *x, double *c,
                        double *q)
{
    double b2 = 0.0;
    for (size_t k = op->m; k < op->nb; ++k)
        c[k] = z[op->band[k]];
    laplacian(op->band, op->nb, op->at, op->W, op->H, op->domain, c, op->y);
    laplacian(op->band, op->nb, op->at, op->W, op->H, op->domain, op->y, q);
    for (size_t k = 0; k < op->m; ++k) {
        b[k] = -q[k];
        b2 += b[k] * b[k];
        x[k] = z[op->band[k]]; /* the harmonic fill: the start */
    }
    return b2;
}

/* Solves L L w = 0 on the op's unknowns with the band's other pixels held
 * at z (W x H depths; its unknowns hold the harmonic fill, the start) by
 * conjugate gradients, and writes w into z's unknowns; op->y is set to
 * scratch made here. *iterations (if given) gets the iterations made, on
 * success only. */
static relief_status plate_solve(float *z, plate_op *op, int max_iter, int *iterations,
                                 relief_error *err)
{
    size_t nb = op->nb, m = op->m;
    double *x = NULL, *b = NULL, *r = NULL, *p = NULL, *q = NULL, *y = NULL, *c = NULL;
    double b2 = 0.0;
    int it = 0;
    relief_status st = RELIEF_OK;
    x = calloc(nb, sizeof *x);
    b = calloc(nb, sizeof *b);
    r = calloc(nb, sizeof *r);
    p = calloc(nb, sizeof *p);
    q = calloc(nb, sizeof *q);
    y = calloc(nb, sizeof *y);
    c = calloc(nb, sizeof *c);
    if (!x || !b || !r || !p || !q || !y || !c) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the thin plate's %zu pixels",
                         nb);
        goto done;
    }
    op->y = y;
    b2 = plate_rhs(z, op, b, x, c, q);
    it = conjugate_gradients(m, b, b2, x, r, p, q, plate_apply, op, max_iter);
    for (size_t k = 0; k < m; ++k)
        z[op->band[k]] = (float)x[k];
    if (iterations)
        *iterations = it;
done:
    free(x);
    free(b);
    free(r);
    free(p);
    free(q);
    free(y);
    free(c);
    return st;
}

relief_status relief_membrane_fill_biharmonic(float *z, const uint8_t *known,
                                              const uint8_t *domain, int width, int height,
                                              int max_iter, int *iterations, relief_error *err)
{
    size_t n = (size_t)width * height, nb = 0, m = 0;
    int32_t *at = NULL, *band = NULL;
    int W = width, H = height;
    relief_status st = relief_poisson_fill(z, known, domain, NULL, W, H, max_iter, NULL, err);
    if (iterations)
        *iterations = 0;
    if (st != RELIEF_OK)
        return st;
    /* The band: the unknowns and the pixels within two steps of one (the
     * reach of L L); the unknowns first. */
    at = malloc(n * sizeof *at);
    if (!at)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the thin plate");
    for (size_t i = 0; i < n; ++i)
        at[i] = -1;
    for (size_t i = 0; i < n; ++i)
        m += unknown(known, domain, i);
    if (!m) {
        free(at);
        return RELIEF_OK;
    }
    band = malloc(n * sizeof *band);
    if (!band) {
        free(at);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the thin plate");
    }
    nb = plate_band(known, domain, W, H, at, band);
    {
        plate_op op = {band, at, nb, m, W, H, domain, NULL};
        st = plate_solve(z, &op, max_iter, iterations, err);
    }
    free(at);
    free(band);
    return st;
}

/* ---------------------------------------------------------------- Haar */

void relief_haar_forward(const float *z, int width, int height, float *ll, float *detail)
{
    int w = width / 2, h = height / 2;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double a = z[(size_t)(2 * y) * width + 2 * x], b = z[(size_t)(2 * y) * width + 2 * x + 1];
            double c = z[(size_t)(2 * y + 1) * width + 2 * x];
            double d = z[(size_t)(2 * y + 1) * width + 2 * x + 1];
            size_t o = (size_t)y * w + x;
            ll[o] = (float)((a + b + c + d) / 4.0);
            detail[3 * o] = (float)((a - b + c - d) / 4.0);
            detail[3 * o + 1] = (float)((a + b - c - d) / 4.0);
            detail[3 * o + 2] = (float)((a - b - c + d) / 4.0);
        }
}

void relief_haar_inverse(const float *ll, const float *detail, int width, int height, float *z)
{
    int w = width / 2, h = height / 2;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            size_t o = (size_t)y * w + x;
            double s = ll[o], lh = detail[3 * o], hl = detail[3 * o + 1], hh = detail[3 * o + 2];
            z[(size_t)(2 * y) * width + 2 * x] = (float)(s + lh + hl + hh);
            z[(size_t)(2 * y) * width + 2 * x + 1] = (float)(s - lh + hl - hh);
            z[(size_t)(2 * y + 1) * width + 2 * x] = (float)(s + lh - hl - hh);
            z[(size_t)(2 * y + 1) * width + 2 * x + 1] = (float)(s - lh - hl + hh);
        }
}

/* ---------------------------------------------------------------- ROF */

/* One ROF solve's arrays, shared by the threads of its passes. */
typedef struct rof_state {
    const double *fl;      /* f / lambda, 0 where unknown */
    const uint8_t *ex, *ey; /* 1 where the edge to i + 1, i + W is present */
    double *px, *py, *div;
    int W, H;
} rof_state;

/* div at pixel i: the four terms in the order of the definition, each
 * read unconditionally and kept or not by a select (the edges from l =
 * i - 1 and u = i - W where `left` and `up` say they may exist), so that
 * the loops below have no branch to stop their vectorisation. */
static inline double rof_div_at(const uint8_t *restrict ex, const uint8_t *restrict ey,
                                const double *restrict px, const double *restrict py,
                                size_t i, size_t l, size_t u, int left, int up)
{
    const double a = px[i], b = px[l], c = py[i], e = py[u];
    double d = 0.0;
    d = ex[i] ? d + a : d;
    d = (left & (ex[l] != 0)) ? d - b : d;
    d = ey[i] ? d + c : d;
    d = (up & (ey[u] != 0)) ? d - e : d;
    return d;
}

/* div = -grad^T p over rows [lo, hi): reads p, writes div's rows. */
static void rof_div(void *ctx, int k, int parts)
{
    const rof_state *r = ctx;
    const size_t W = (size_t)r->W;
    const uint8_t *restrict ex = r->ex, *restrict ey = r->ey;
    const double *restrict px = r->px, *restrict py = r->py;
    double *restrict div = r->div;
    size_t lo, hi;
    relief_pool_share((size_t)r->H, k, parts, &lo, &hi);
    for (size_t y = lo; y < hi; ++y) {
        const size_t i0 = y * W, u0 = y > 0 ? i0 - W : i0;
        const int up = y > 0;
        div[i0] = rof_div_at(ex, ey, px, py, i0, i0, u0, 0, up);
        for (size_t x = 1; x < W; ++x)
            div[i0 + x] = rof_div_at(ex, ey, px, py, i0 + x, i0 + x - 1, u0 + x, 1, up);
    }
}

/* Chambolle's projected step at pixel i, its edges' far ends `right` and
 * `down` read unconditionally (the last column and row pass i itself,
 * their edges being absent) and the terms kept or not by selects. An
 * unknown pixel has no edge: its gradient is +0, so its p, +0 from the
 * start, stays +0 ((0 + 0) / 1), the value a loop that skips it leaves;
 * every pixel is stored, which lets the loop be vectorised. */
static inline void rof_step_at(const uint8_t *restrict ex, const uint8_t *restrict ey,
                               const double *restrict div,
                               const double *restrict fl, double *restrict px,
                               double *restrict py, size_t i, size_t right, size_t down)
{
    const double tau = 0.25;
    const double here = div[i] - fl[i];
    const double tx = (div[right] - fl[right]) - here;
    const double ty = (div[down] - fl[down]) - here;
    const double gx = ex[i] ? tx : 0.0, gy = ey[i] ? ty : 0.0;
    const double norm = sqrt(gx * gx + gy * gy);
    const double npx = (px[i] + tau * gx) / (1.0 + tau * norm);
    const double npy = (py[i] + tau * gy) / (1.0 + tau * norm);
    px[i] = npx;
    py[i] = npy;
}

/* The step over rows [lo, hi): reads div, writes p's rows. */
static void rof_step(void *ctx, int k, int parts)
{
    const rof_state *r = ctx;
    const size_t W = (size_t)r->W, H = (size_t)r->H;
    const uint8_t *restrict ex = r->ex, *restrict ey = r->ey;
    const double *restrict div = r->div, *restrict fl = r->fl;
    double *restrict px = r->px, *restrict py = r->py;
    size_t lo, hi;
    relief_pool_share(H, k, parts, &lo, &hi);
    for (size_t y = lo; y < hi; ++y) {
        const size_t i0 = y * W, below = y + 1 < H ? W : 0;
        for (size_t x = 0; x + 1 < W; ++x)
            rof_step_at(ex, ey, div, fl, px, py, i0 + x, i0 + x + 1, i0 + x + below);
        rof_step_at(ex, ey, div, fl, px, py, i0 + W - 1, i0 + W - 1, i0 + W - 1 + below);
    }
}

relief_status relief_rof(const float *f, const uint8_t *known, int width, int height,
                         double lambda, int iterations, int threads, float *u, float *v,
                         relief_error *err)
{
    size_t n = (size_t)width * height;
    double *px = calloc(n, sizeof *px), *py = calloc(n, sizeof *py);
    double *div = malloc(n * sizeof *div), *fl = malloc(n * sizeof *fl);
    uint8_t *ex = malloc(n), *ey = malloc(n);
    relief_pool *pool = NULL;
    relief_status st = RELIEF_OK;
    int W = width, H = height;
    if (!px || !py || !div || !fl || !ex || !ey) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the ROF dual field (%zu "
                         "pixels)", n);
        goto done;
    }
    if (!(lambda > 0.0)) {
        for (size_t i = 0; i < n; ++i) {
            u[i] = known[i] ? f[i] : 0.0f;
            v[i] = 0.0f;
        }
        goto done;
    }
    if (threads > H / 16)
        threads = H / 16; /* a share of 16 rows at least */
    threads = threads < 1 ? 1 : threads > RELIEF_POOL_MAX ? RELIEF_POOL_MAX : threads;
    st = relief_pool_create(threads, &pool, err); /* 1: no thread started */
    if (st != RELIEF_OK)
        goto done;
    /* Edges: px[i] joins i and i + 1, py[i] joins i and i + W, present
     * only when both ends are known. div = -grad^T. Each pass writes only
     * its own rows, so the threads' result is one thread's, bit for bit. */
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            size_t i = (size_t)y * W + x;
            ex[i] = x + 1 < W && known[i] && known[i + 1];
            ey[i] = y + 1 < H && known[i] && known[i + W];
            fl[i] = known[i] ? f[i] / lambda : 0.0;
        }
    {
        rof_state r = {fl, ex, ey, px, py, div, W, H};
        for (int it = 0; it <= iterations; ++it) {
            relief_pool_run(pool, threads, rof_div, &r);
            if (it == iterations)
                break;
            relief_pool_run(pool, threads, rof_step, &r);
        }
    }
    for (size_t i = 0; i < n; ++i) {
        if (known[i]) {
            double uu = f[i] - lambda * div[i];
            u[i] = (float)uu;
            v[i] = (float)(f[i] - uu);
        } else {
            u[i] = v[i] = 0.0f;
        }
    }
done:
    relief_pool_destroy(pool);
    free(px);
    free(py);
    free(div);
    free(fl);
    free(ex);
    free(ey);
    return st;
}
