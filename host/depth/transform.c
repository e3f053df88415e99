#include "depth/transform.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"

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
    m = 0;
    for (size_t i = 0; i < n; ++i) {
        idx[i] = unknown(known, domain, i) ? (int32_t)m : -1;
        if (idx[i] >= 0)
            pix[m++] = (int32_t)i;
    }
    /* b: the known neighbours' values; the starting guess x: their mean
     * where there are any (faster than 0 on thin holes). */
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

relief_status relief_membrane_fill_biharmonic(float *z, const uint8_t *known,
                                              const uint8_t *domain, int width, int height,
                                              int max_iter, int *iterations, relief_error *err)
{
    size_t n = (size_t)width * height, nb = 0, m = 0;
    int32_t *at = NULL, *band = NULL;
    double *x = NULL, *b = NULL, *r = NULL, *p = NULL, *q = NULL, *y = NULL, *c = NULL;
    double b2 = 0.0;
    int it = 0, W = width, H = height;
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
    /* b = -(L L u_known) on the unknowns: c = u_known on the band (0 on
     * the unknowns), y = L c, b = -(L y). */
    for (size_t k = m; k < nb; ++k)
        c[k] = z[band[k]];
    laplacian(band, nb, at, W, H, domain, c, y);
    laplacian(band, nb, at, W, H, domain, y, q);
    for (size_t k = 0; k < m; ++k) {
        b[k] = -q[k];
        b2 += b[k] * b[k];
        x[k] = z[band[k]]; /* the harmonic fill: the start */
    }
    {
        plate_op op = {band, at, nb, m, W, H, domain, y};
        it = conjugate_gradients(m, b, b2, x, r, p, q, plate_apply, &op, max_iter);
    }
    for (size_t k = 0; k < m; ++k)
        z[band[k]] = (float)x[k];
    if (iterations)
        *iterations = it;
done:
    free(at);
    free(band);
    free(x);
    free(b);
    free(r);
    free(p);
    free(q);
    free(y);
    free(c);
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

relief_status relief_rof(const float *f, const uint8_t *known, int width, int height,
                         double lambda, int iterations, float *u, float *v, relief_error *err)
{
    size_t n = (size_t)width * height;
    double *px = calloc(n, sizeof *px), *py = calloc(n, sizeof *py), *div = malloc(n * sizeof *div);
    const double tau = 0.25;
    int W = width, H = height;
    if (!px || !py || !div) {
        free(px);
        free(py);
        free(div);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the ROF dual field (%zu "
                           "pixels)", n);
    }
    if (!(lambda > 0.0)) {
        for (size_t i = 0; i < n; ++i) {
            u[i] = known[i] ? f[i] : 0.0f;
            v[i] = 0.0f;
        }
        free(px);
        free(py);
        free(div);
        return RELIEF_OK;
    }
    /* Edges: px[i] joins i and i + 1, py[i] joins i and i + W, present
     * only when both ends are known. div = -grad^T. */
#define EX(i, x) ((x) + 1 < W && known[i] && known[(i) + 1])
#define EY(i, y) ((y) + 1 < H && known[i] && known[(i) + W])
    for (int it = 0; it <= iterations; ++it) {
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                size_t i = (size_t)y * W + x;
                double d = 0.0;
                if (EX(i, x))
                    d += px[i];
                if (x > 0 && EX(i - 1, x - 1))
                    d -= px[i - 1];
                if (EY(i, y))
                    d += py[i];
                if (y > 0 && EY(i - W, y - 1))
                    d -= py[i - W];
                div[i] = d;
            }
        if (it == iterations)
            break;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                size_t i = (size_t)y * W + x;
                double gx = 0.0, gy = 0.0, norm;
                if (!known[i])
                    continue;
                if (EX(i, x))
                    gx = (div[i + 1] - f[i + 1] / lambda) - (div[i] - f[i] / lambda);
                if (EY(i, y))
                    gy = (div[i + W] - f[i + W] / lambda) - (div[i] - f[i] / lambda);
                norm = sqrt(gx * gx + gy * gy);
                px[i] = (px[i] + tau * gx) / (1.0 + tau * norm);
                py[i] = (py[i] + tau * gy) / (1.0 + tau * norm);
            }
    }
#undef EX
#undef EY
    for (size_t i = 0; i < n; ++i) {
        if (known[i]) {
            double uu = f[i] - lambda * div[i];
            u[i] = (float)uu;
            v[i] = (float)(f[i] - uu);
        } else {
            u[i] = v[i] = 0.0f;
        }
    }
    free(px);
    free(py);
    free(div);
    return RELIEF_OK;
}
