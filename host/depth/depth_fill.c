#include "depth/depth_fill.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/clock.h"
#include "base/error.h"
#include "depth/transform.h"
#include "image/raster.h"

#define MAX_HAAR_LEVELS 6

relief_depth_repair_params relief_depth_repair_params_default(void)
{
    relief_depth_repair_params p;
    memset(&p, 0, sizeof p);
    p.variant = RELIEF_DEPTH_DECOMPOSE;
    p.synth = relief_pixsyn_params_default();
    p.levels = 2;
    p.lambda = 0.0;
    p.rof_iterations = 200;
    p.membrane_iterations = 5000;
    p.thin_plate = 0;
    p.seam = 1;
    p.layer = relief_layer_params_default();
    return p;
}

relief_status relief_depth_repair_params_validate(const relief_depth_repair_params *p, int width,
                                                int height, relief_error *err)
{
    int w = width, h = height;
    /* The engine indexes values with int: 3 channels for the Haar bands. */
    if ((uint64_t)(width + 64) * (uint64_t)(height + 64) * 3u > 0x7fffffffu)
        return relief_fail(err, RELIEF_E_RANGE, "a %d x %d image: at most about 700 million "
                           "pixels are supported", width, height);
    if (p->variant != RELIEF_DEPTH_PLAIN && p->variant != RELIEF_DEPTH_HAAR &&
        p->variant != RELIEF_DEPTH_DECOMPOSE)
        return relief_fail(err, RELIEF_E_RANGE, "variant %d is not one of plain, haar, "
                           "decompose", (int)p->variant);
    if (!isfinite(p->lambda) || p->lambda > 1e12)
        return relief_fail(err, RELIEF_E_RANGE, "lambda %g out of range: expected a finite "
                           "value up to 1e12 (<= 0: automatic)", p->lambda);
    if (p->rof_iterations < 1 || p->rof_iterations > 100000)
        return relief_fail(err, RELIEF_E_RANGE, "rof_iterations %d out of range: expected "
                           "1..100000",
                           p->rof_iterations);
    if (p->membrane_iterations < 1 || p->membrane_iterations > 1000000)
        return relief_fail(err, RELIEF_E_RANGE, "membrane_iterations %d out of range: "
                           "expected 1..1000000",
                           p->membrane_iterations);
    if (p->variant == RELIEF_DEPTH_HAAR) {
        if (p->levels < 1 || p->levels > MAX_HAAR_LEVELS)
            return relief_fail(err, RELIEF_E_RANGE, "levels %d out of range: expected 1..%d",
                               p->levels,
                               MAX_HAAR_LEVELS);
        w = (width + (1 << p->levels) - 1) >> p->levels;
        h = (height + (1 << p->levels) - 1) >> p->levels;
        if (w < p->synth.window || h < p->synth.window)
            return relief_fail(err, RELIEF_E_RANGE, "levels %d leaves %d x %d coefficients "
                               "at the coarsest detail band, smaller than the %d-pixel window: "
                               "give fewer levels or a smaller window", p->levels, w, h,
                               p->synth.window);
        return relief_pixsyn_params_validate(&p->synth, w, h, err);
    }
    return relief_pixsyn_params_validate(&p->synth, width, height, err);
}

uint64_t relief_depth_repair_estimate(int width, int height)
{
    uint64_t n = (uint64_t)(width + 64) * (uint64_t)(height + 64);
    /* Two rasters of values (both orders), the engine's pyramid (4/3 of
     * one, x 3 channels for the Haar details), masks, the source maps, the
     * ROF's dual field and the membrane's solver vectors (doubles), the
     * synthesis queue (up to 9 entries of 12 bytes a pixel, doubled as it
     * grows), the automatic lambda's list of steps and the seam's
     * correction, flux, masks and scratch source map, the thin plate's
     * bridged image and mask. */
    return n * (2u * 4u + 3u * 4u * 4u / 3u + 4u + 2u * 8u + 3u * 8u + 6u * 8u + 216u + 8u +
                4u + 4u + 2u + 8u + 4u + 1u);
}

/* ---------------------------------------------------------------- helpers */

/* The synthesis's pixels as the repair's progress, in its current stage. */
static int synth_progress(void *ctx, size_t done, size_t total)
{
    return relief_progress_count(ctx, done, total);
}

/* Synthesise `img` (channels C) where hole != 0, reporting to `pr` (may
 * be NULL); add the counts. */
static relief_status synthesise(float *v, const uint8_t *hole, const uint8_t *target, int W,
                                int H, int C, const relief_pixsyn_params *sp,
                                relief_progress *pr, relief_patch_scorer *scorer,
                                int64_t *source, relief_depth_repair_report *rep,
                                relief_error *err)
{
    relief_raster r = {W, H, C, 0, v};
    relief_pixsyn_report sr;
    relief_pixsyn_params q = *sp;
    double t0 = relief_seconds();
    relief_status st;
    if (pr) {
        q.progress = synth_progress;
        q.progress_ctx = pr;
    }
    st = relief_pixsyn(&r, hole, target, &q, scorer, source, &sr, err);
    rep->seconds_synthesis += relief_seconds() - t0;
    if (st != RELIEF_OK)
        return st;
    rep->by_synthesis += sr.by_synthesis;
    rep->by_fallback += sr.by_fallback;
    rep->unreached += sr.unreached;
    rep->candidates += sr.candidates;
    rep->seconds_score += sr.seconds_score;
    rep->kept = sr.kept;
    rep->energy[0] = sr.energy[0];
    rep->energy[1] = sr.energy[1];
    return RELIEF_OK;
}

/* Whether the rims are blended: p->seam, and not on a torus (the blend
 * neither wraps nor guides edges across the border, which would leave a
 * seam where --tileable promises none; a tileable texture's copies are
 * exact anyway). */
static int blends(const relief_depth_repair_params *p)
{
    return p->seam && !p->synth.tileable;
}

/* Blend the rims of the filled pixels `inside` (relief_depth_seam; u the
 * smooth part or NULL, v the texture or the depths, map the copies'
 * sources); the report gets the edges, the solve's iterations and time. */
static relief_status blend_rims(const float *u, float *v, const uint8_t *missing,
                                const uint8_t *inside, const int64_t *map, int W, int H,
                                const relief_depth_repair_params *p,
                                relief_depth_repair_report *rep, relief_error *err)
{
    size_t n = (size_t)W * H;
    uint8_t *known = malloc(n);
    double t0 = relief_seconds();
    int it = 0;
    relief_status st;
    if (!known)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the seam's mask");
    for (size_t i = 0; i < n; ++i)
        known[i] = !missing[i];
    st = relief_depth_seam(u, v, known, inside, map, W, H, p->membrane_iterations,
                           &rep->seam_edges, &it, err);
    if (it > rep->membrane_iterations)
        rep->membrane_iterations = it;
    rep->seconds_transform += relief_seconds() - t0;
    free(known);
    return st;
}

/* Synthesise v where missing (the pixels `inside` the targets), then,
 * when blends(p), blend the rims (u the smooth part or NULL). The source
 * map is the caller's or a scratch one. */
static relief_status synthesise_blended(const float *u, float *v, const uint8_t *missing,
                                        const uint8_t *inside, int W, int H,
                                        const relief_depth_repair_params *p,
                                        relief_patch_scorer *scorer, int64_t *source,
                                        relief_depth_repair_report *rep, relief_error *err)
{
    size_t n = (size_t)W * H;
    int64_t *map = source;
    relief_status st;
    int blend = blends(p);
    if (blend && !map && !(map = malloc(n * sizeof *map)))
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the source map");
    st = synthesise(v, missing, inside, W, H, 1, &p->synth, p->progress, scorer, map, rep,
                    err);
    if (st == RELIEF_OK && blend)
        st = blend_rims(u, v, missing, inside, map, W, H, p, rep, err);
    if (map != source)
        free(map);
    return st;
}

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* lambda <= 0: from the capture's robust roughness, the median of the
 * non-zero |second differences| along rows and columns over known triples
 * (a quantised capture has many zeros, which would make the median
 * useless). Second differences, not steps: a smooth slope is structure, u's
 * to keep, not texture; on white noise of deviation s the median is
 * 0.6745 sqrt(6) s, and lambda = 8 sqrt(2) s, what the median step gave
 * there. */
static relief_status auto_lambda(const float *z, const uint8_t *known, int W, int H,
                                 double *lambda, relief_error *err)
{
    size_t n = 0, cap = 2 * (size_t)W * H;
    float *d = malloc(cap * sizeof *d);
    if (!d)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the steps' list");
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            size_t i = (size_t)y * W + x;
            if (!known[i])
                continue;
            if (x + 2 < W && known[i + 1] && known[i + 2]) {
                float s = fabsf(z[i] - 2.0f * z[i + 1] + z[i + 2]);
                if (s > 0.0f)
                    d[n++] = s;
            }
            if (y + 2 < H && known[i + W] && known[i + 2 * (size_t)W]) {
                float s = fabsf(z[i] - 2.0f * z[i + W] + z[i + 2 * (size_t)W]);
                if (s > 0.0f)
                    d[n++] = s;
            }
        }
    if (n) {
        qsort(d, n, sizeof *d, cmp_float);
        *lambda = 8.0 * sqrt(2.0) / (0.6745 * sqrt(6.0)) * d[n / 2];
    } else {
        *lambda = 0.0;
    }
    free(d);
    return RELIEF_OK;
}

/* The smooth fill of LL or u over `domain` (the capture and the pixels
 * to fill; the rest, a margin or a z-buffer's background, is no
 * neighbour): the thin plate or the harmonic membrane. */
static relief_status smooth_fill(float *z, const uint8_t *known, const uint8_t *domain, int W,
                                 int H, const relief_depth_repair_params *p, int *iterations,
                                 relief_error *err)
{
    return p->thin_plate ? relief_membrane_fill_biharmonic(z, known, domain, W, H,
                                                           p->membrane_iterations, iterations,
                                                           err)
                         : relief_poisson_fill(z, known, domain, NULL, W, H,
                                               p->membrane_iterations, iterations, err);
}

/* What the seam's helpers read: the smooth part u (NULL: 0) and the detail
 * v of the depth, and which pixels are captured; all width x height. */
typedef struct seam_in {
    const float *u, *v;
    const uint8_t *known;
    int W, H;
} seam_in;

#define U(i) (S->u ? S->u[i] : 0.0f)

/* The wanted step q -> p's neighbour q (one step along d from the filled
 * pixel p) where the step after it, q -> r, is captured: the mean of the
 * capture's own step r - q and the texture's step (u's step plus the
 * source's detail step s -> t), each weighted by the inverse square of its
 * error on the next captured step, r -> a (b: the source's), where both can
 * be checked. Depth units. */
static double seam_two_steps(const seam_in *S, const int d[2], int rx, int ry, int tx, int ty,
                             size_t q, size_t r, size_t t, size_t s)
{
    const float *v = S->v;
    const uint8_t *known = S->known;
    int W = S->W, H = S->H;
    double capture = ((double)U(r) + v[r]) - ((double)U(q) + v[q]);
    double texture = ((double)U(r) - U(q)) + ((double)v[t] - v[s]);
    int ax = rx + d[0], ay = ry + d[1];
    int bx = tx + d[0], by = ty + d[1];
    size_t a, b;
    double g = 0.5 * (capture + texture);
    if (ax >= 0 && ax < W && ay >= 0 && ay < H && known[a = (size_t)ay * W + ax] &&
        bx >= 0 && bx < W && by >= 0 && by < H && known[b = (size_t)by * W + bx]) {
        double next = ((double)U(a) + v[a]) - ((double)U(r) + v[r]);
        double ec = capture - next;
        double et = capture - (((double)U(a) - U(r)) + ((double)v[b] - v[t]));
        if (et == 0.0)
            g = texture;
        else if (ec == 0.0)
            g = capture;
        else
            g = (capture * et * et + texture * ec * ec) / (et * et + ec * ec);
    }
    return g;
}

/* The filled pixel p = (x, y), copied from pixel s: adds to *flux (p's
 * entry of the correction's right-hand side) -sum over p's captured
 * neighbours of the wanted step out of p, with the fill's own steps
 * cancelled. Returns the guided edges (0..4). */
static size_t seam_pixel(const seam_in *S, int x, int y, size_t s, float *flux)
{
    static const int dir[4][2] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}};
    const float *v = S->v;
    const uint8_t *known = S->known;
    int W = S->W, H = S->H;
    size_t p = (size_t)y * W + x, guided = 0;
    int sx = (int)(s % W), sy = (int)(s / W);
    for (int j = 0; j < 4; ++j) {
        int qx = x + dir[j][0], qy = y + dir[j][1];
        int rx = qx + dir[j][0], ry = qy + dir[j][1];
        int tx = sx + dir[j][0], ty = sy + dir[j][1];
        size_t q, r, t;
        double have, g;
        if (qx < 0 || qx >= W || qy < 0 || qy >= H || !known[q = (size_t)qy * W + qx])
            continue;
        if (tx < 0 || tx >= W || ty < 0 || ty >= H || !known[t = (size_t)ty * W + tx] ||
            !known[s])
            continue;
        have = ((double)U(q) + v[q]) - ((double)U(p) + v[p]);
        if (rx >= 0 && rx < W && ry >= 0 && ry < H && known[r = (size_t)ry * W + rx])
            g = seam_two_steps(S, dir[j], rx, ry, tx, ty, q, r, t, s);
        else
            g = ((double)U(q) - U(p)) + ((double)v[t] - v[s]);
        *flux += (float)(have - g);
        ++guided;
    }
    return guided;
}

#undef U

relief_status relief_depth_seam(const float *u, float *v, const uint8_t *known,
                                const uint8_t *filled, const int64_t *source, int width,
                                int height, int max_iter, size_t *edges, int *iterations,
                                relief_error *err)
{
    int W = width, H = height;
    size_t n = (size_t)W * H, guided = 0;
    float *c = calloc(n, sizeof *c), *flux = calloc(n, sizeof *flux);
    uint8_t *fixed = malloc(n), *domain = malloc(n);
    seam_in S = {u, v, known, W, H};
    relief_status st = RELIEF_OK;
    if (edges)
        *edges = 0;
    if (iterations)
        *iterations = 0;
    if (!c || !flux || !fixed || !domain) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the seam's correction");
        goto done;
    }
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            size_t p = (size_t)y * W + x;
            fixed[p] = !filled[p];
            domain[p] = known[p] || filled[p];
            if (!filled[p] || source[p] < 0 || (uint64_t)source[p] >= n)
                continue;
            guided += seam_pixel(&S, x, y, (size_t)source[p], &flux[p]);
        }
    if (guided) {
        st = relief_poisson_fill(c, fixed, domain, flux, W, H, max_iter, iterations, err);
        if (st == RELIEF_OK)
            for (size_t i = 0; i < n; ++i)
                if (filled[i])
                    v[i] += c[i];
    }
    if (edges)
        *edges = guided;
done:
    free(c);
    free(flux);
    free(fixed);
    free(domain);
    return st;
}

/* ---------------------------------------------------------------- variants */

static relief_status fill_plain(float *z, const uint8_t *missing, const uint8_t *inside, int W,
                                int H,
                                const relief_depth_repair_params *p, relief_patch_scorer *scorer,
                                int64_t *source, relief_depth_repair_report *rep,
                                relief_error *err)
{
    size_t n = (size_t)W * H;
    float *v = malloc(n * sizeof *v);
    relief_status st;
    if (!v)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a copy of the image");
    for (size_t i = 0; i < n; ++i)
        v[i] = missing[i] ? 0.0f : z[i];
    st = synthesise_blended(NULL, v, missing, inside, W, H, p, scorer, source, rep, err);
    if (st == RELIEF_OK)
        for (size_t i = 0; i < n; ++i)
            if (inside[i])
                z[i] = v[i];
    free(v);
    return st;
}

static relief_status fill_decompose(float *z, const uint8_t *missing, const uint8_t *inside,
                                    int W, int H,
                                    const relief_depth_repair_params *p,
                                    relief_patch_scorer *scorer, int64_t *source,
                                    relief_depth_repair_report *rep, relief_error *err)
{
    size_t n = (size_t)W * H;
    float *u = malloc(n * sizeof *u), *v = malloc(n * sizeof *v);
    float *bridge = p->thin_plate ? malloc(n * sizeof *bridge) : NULL;
    uint8_t *known = malloc(n), *domain = malloc(n);
    double lambda = p->lambda, t0 = relief_seconds();
    relief_status st = RELIEF_OK;
    if (!u || !v || !known || !domain || (p->thin_plate && !bridge)) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the decomposition");
        goto done;
    }
    /* The smooth fills' domain: the capture and the pixels to fill; the
     * missing pixels that are not to be filled (a frame's margin, a
     * z-buffer's background) are no neighbours. */
    for (size_t i = 0; i < n; ++i) {
        known[i] = !missing[i];
        domain[i] = known[i] || inside[i];
    }
    if (lambda <= 0.0)
        st = auto_lambda(z, known, W, H, &lambda, err);
    rep->lambda = lambda;
    if (st == RELIEF_OK && p->thin_plate) {
        /* The thin plate carries the rim's slope and curvature into the
         * hole, but ROF over the known pixels alone flattens u towards
         * the hole's free boundary (its natural boundary condition), so
         * there would be none to carry: the holes are bridged by the thin
         * plate first and ROF runs over the domain, which leaves u smooth
         * across the rim and fills it as it goes (u in a hole: ROF of the
         * bridge). */
        for (size_t i = 0; i < n; ++i)
            bridge[i] = known[i] ? z[i] : 0.0f;
        st = smooth_fill(bridge, known, domain, W, H, p, &rep->membrane_iterations, err);
        if (st == RELIEF_OK)
            st = relief_rof(bridge, domain, W, H, lambda, p->rof_iterations,
                            scorer->threads, u, v, err);
    } else if (st == RELIEF_OK) {
        st = relief_rof(z, known, W, H, lambda, p->rof_iterations, scorer->threads, u, v,
                        err);
        if (st == RELIEF_OK)
            st = smooth_fill(u, known, domain, W, H, p, &rep->membrane_iterations, err);
    }
    rep->seconds_transform += relief_seconds() - t0;
    if (st != RELIEF_OK)
        goto done;
    for (size_t i = 0; i < n; ++i)
        rep->by_membrane += inside[i] != 0;
    st = synthesise_blended(u, v, missing, inside, W, H, p, scorer, source, rep, err);
    if (st == RELIEF_OK)
        for (size_t i = 0; i < n; ++i)
            if (inside[i])
                z[i] = u[i] + v[i];
done:
    free(u);
    free(v);
    free(bridge);
    free(known);
    free(domain);
    return st;
}

/* The Haar pyramid of a frame: level 0 the frame padded to Wp x Hp (a
 * multiple of 2^L), level l its LL (ll[l]), its LH, HL and HH bands as one
 * 3-channel image (det[l]), and which coefficients are known and which are
 * targets. */
typedef struct haar_bands {
    int L, Wp, Hp;
    float *ll[MAX_HAAR_LEVELS + 1], *det[MAX_HAAR_LEVELS + 1];
    uint8_t *known[MAX_HAAR_LEVELS + 1], *target[MAX_HAAR_LEVELS + 1];
} haar_bands;

static void haar_free(haar_bands *b)
{
    for (int l = 0; l <= b->L; ++l) {
        free(b->ll[l]);
        free(b->det[l]);
        free(b->known[l]);
        free(b->target[l]);
    }
}

/* Allocate the bands of a W x H frame and take the forward transform:
 * level 0 the frame padded by repeating its last column and row (with
 * their known flags); a coefficient is known when its four pixels are, a
 * target when one of them is. */
static relief_status haar_forward(haar_bands *b, const float *z, const uint8_t *missing,
                                  const uint8_t *inside, int W, int H, int L, relief_error *err)
{
    int step = 1 << L, Wp = (W + step - 1) / step * step, Hp = (H + step - 1) / step * step;
    memset(b, 0, sizeof *b);
    b->L = L;
    b->Wp = Wp;
    b->Hp = Hp;
    for (int l = 0; l <= L; ++l) {
        size_t m = (size_t)(Wp >> l) * (Hp >> l);
        b->ll[l] = malloc(m * sizeof(float));
        b->known[l] = malloc(m);
        b->target[l] = malloc(m);
        b->det[l] = l ? malloc(3 * m * sizeof(float)) : NULL;
        if (!b->ll[l] || !b->known[l] || !b->target[l] || (l && !b->det[l]))
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the Haar bands");
    }
    for (int y = 0; y < Hp; ++y)
        for (int x = 0; x < Wp; ++x) {
            size_t s = (size_t)(y < H ? y : H - 1) * W + (x < W ? x : W - 1);
            size_t o = (size_t)y * Wp + x;
            b->known[0][o] = !missing[s];
            b->target[0][o] = x < W && y < H && inside[s];
            b->ll[0][o] = missing[s] ? 0.0f : z[s];
        }
    for (int l = 1; l <= L; ++l) {
        int w = Wp >> l, h = Hp >> l, fw = Wp >> (l - 1);
        const uint8_t *k = b->known[l - 1], *t = b->target[l - 1];
        relief_haar_forward(b->ll[l - 1], fw, Hp >> (l - 1), b->ll[l], b->det[l]);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                size_t a = (size_t)(2 * y) * fw + 2 * x;
                b->known[l][(size_t)y * w + x] = k[a] && k[a + 1] && k[a + fw] && k[a + fw + 1];
                b->target[l][(size_t)y * w + x] = t[a] || t[a + 1] || t[a + fw] || t[a + fw + 1];
            }
    }
    return RELIEF_OK;
}

/* The coarsest LL: the membrane, over the known and target coefficients. */
static relief_status haar_coarse(haar_bands *b, const relief_depth_repair_params *p,
                                 relief_depth_repair_report *rep, relief_error *err)
{
    int L = b->L;
    size_t m = (size_t)(b->Wp >> L) * (b->Hp >> L);
    uint8_t *domain = malloc(m);
    relief_status st;
    if (!domain)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the fill's domain");
    for (size_t i = 0; i < m; ++i)
        domain[i] = b->known[L][i] || b->target[L][i];
    st = smooth_fill(b->ll[L], b->known[L], domain, b->Wp >> L, b->Hp >> L, p,
                     &rep->membrane_iterations, err);
    free(domain);
    if (st == RELIEF_E_RANGE)
        return relief_fail(err, RELIEF_E_RANGE, "no Haar coefficient of level %d is known "
                           "(every 2^%d block has a missing pixel): give fewer levels", L, L);
    for (size_t i = 0; i < m && st == RELIEF_OK; ++i)
        rep->by_membrane += b->target[L][i] != 0;
    return st;
}

/* Level l's details synthesised (the three bands as one 3-channel image,
 * so that a copy keeps them together; src, may be NULL, gets the copies'
 * sources), then the inverse into the finer LL (`back`: Wp x Hp scratch),
 * whose known coefficients keep their values. */
static relief_status haar_level(haar_bands *b, int l, const relief_depth_repair_params *p,
                                relief_patch_scorer *scorer, int64_t *src, float *back,
                                relief_depth_repair_report *rep, relief_error *err)
{
    int w = b->Wp >> l, h = b->Hp >> l, fw = b->Wp >> (l - 1), fh = b->Hp >> (l - 1);
    size_t m = (size_t)w * h, any = 0;
    uint8_t *hole = malloc(m);
    relief_pixsyn_params sp = p->synth;
    float *det = b->det[l];
    relief_status st;
    double t0;
    if (!hole)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a band's mask");
    for (size_t i = 0; i < m; ++i) {
        hole[i] = !b->known[l][i];
        any += !hole[i];
        if (hole[i])
            det[3 * i] = det[3 * i + 1] = det[3 * i + 2] = 0.0f;
    }
    if (sp.search_radius > 0) {
        int r = sp.search_radius >> l, least = (sp.window + 1) / 2;
        sp.search_radius = r > least ? r : least;
    }
    st = any ? synthesise(det, hole, b->target[l], w, h, 3, &sp, p->progress, scorer, src, rep,
                          err)
             : relief_fail(err, RELIEF_E_RANGE, "no Haar coefficient of level %d is known: "
                           "give fewer levels", l);
    free(hole);
    if (st != RELIEF_OK)
        return st;
    t0 = relief_seconds();
    relief_haar_inverse(b->ll[l], det, fw, fh, back);
    for (size_t i = 0; i < (size_t)fw * fh; ++i)
        if (!b->known[l - 1][i])
            b->ll[l - 1][i] = back[i];
    rep->seconds_transform += relief_seconds() - t0;
    return RELIEF_OK;
}

/* Level 1's copies (src, at half resolution) mapped to full resolution:
 * each pixel takes the same corner of its block's source block, -1 where
 * that is not a captured pixel. */
static void haar_map_sources(const int64_t *src, const uint8_t *missing, const uint8_t *inside,
                             int W, int H, int Wp, int64_t *map)
{
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            size_t i = (size_t)y * W + x;
            int64_t s = src[(size_t)(y / 2) * (Wp / 2) + x / 2];
            int sx, sy;
            if (!inside[i])
                continue;
            map[i] = -1;
            if (s >= 0) {
                sx = 2 * (int)(s % (Wp / 2)) + (x & 1);
                sy = 2 * (int)(s / (Wp / 2)) + (y & 1);
                if (sx < W && sy < H && !missing[(size_t)sy * W + sx])
                    map[i] = (int64_t)sy * W + sx;
            }
        }
}

static relief_status fill_haar(float *z, const uint8_t *missing, const uint8_t *inside, int W,
                               int H, const relief_depth_repair_params *p,
                               relief_patch_scorer *scorer, int64_t *source,
                               relief_depth_repair_report *rep, relief_error *err)
{
    int L = p->levels;
    haar_bands b;
    int64_t *src = NULL, *map = source;
    float *back = NULL;
    relief_progress *pr = p->progress;
    double lo = pr ? pr->lo : 0.0, hi = pr ? pr->hi : 1.0, done = 0.0, all = 0.0;
    double t0 = relief_seconds();
    relief_status st = haar_forward(&b, z, missing, inside, W, H, L, err);

    /* The finest level's copies, mapped to full resolution: the caller's
     * source map and the seam's. */
    if (st == RELIEF_OK && blends(p) && !map && !(map = malloc((size_t)W * H * sizeof *map)))
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the Haar bands");
    if (st == RELIEF_OK) {
        src = map ? malloc((size_t)(b.Wp >> 1) * (b.Hp >> 1) * sizeof *src) : NULL;
        back = malloc((size_t)b.Wp * b.Hp * sizeof *back);
        if ((map && !src) || !back)
            st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the Haar bands");
    }
    if (st == RELIEF_OK)
        st = haar_coarse(&b, p, rep, err);
    rep->seconds_transform += relief_seconds() - t0;
    /* Coarse to fine; each level's share of the progress is its share of
     * the coefficients. */
    for (int l = 1; l <= L; ++l)
        all += 1.0 / (double)(1 << (2 * l));
    for (int l = L; l >= 1 && st == RELIEF_OK; --l) {
        double share = 1.0 / (double)(1 << (2 * l)) / all;
        if (pr)
            relief_progress_stage(pr, lo + done * (hi - lo), lo + (done + share) * (hi - lo));
        st = haar_level(&b, l, p, scorer, l == 1 ? src : NULL, back, rep, err);
        done += share;
    }
    if (pr)
        relief_progress_stage(pr, lo, hi);
    if (st != RELIEF_OK)
        goto done;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            if (inside[(size_t)y * W + x])
                z[(size_t)y * W + x] = b.ll[0][(size_t)y * b.Wp + x];
    if (map)
        haar_map_sources(src, missing, inside, W, H, b.Wp, map);
    rep->levels = L;
    /* The rims blended as the plain variant's, each filled pixel's
     * texture taken from its block's source. */
    if (blends(p))
        st = blend_rims(NULL, z, missing, inside, map, W, H, p, rep, err);
done:
    haar_free(&b);
    free(src);
    free(back);
    if (map != source)
        free(map);
    return st;
}

size_t relief_depth_inside(const uint8_t *missing, int width, int height, uint8_t *inside)
{
    int W = width, H = height;
    size_t count = 0;
    int *first_y = malloc((size_t)W * sizeof *first_y), *last_y = malloc((size_t)W * sizeof *last_y);
    if (!first_y || !last_y) {
        free(first_y);
        free(last_y);
        return (size_t)-1;
    }
    /* The first and last known pixel of every column and of every row. */
    for (int x = 0; x < W; ++x) {
        first_y[x] = H;
        last_y[x] = -1;
    }
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            if (!missing[(size_t)y * W + x]) {
                if (first_y[x] == H)
                    first_y[x] = y;
                last_y[x] = y;
            }
    for (int y = 0; y < H; ++y) {
        int first_x = W, last_x = -1;
        for (int x = 0; x < W; ++x)
            if (!missing[(size_t)y * W + x]) {
                if (first_x == W)
                    first_x = x;
                last_x = x;
            }
        for (int x = 0; x < W; ++x) {
            size_t i = (size_t)y * W + x;
            inside[i] = missing[i] && ((x > first_x && x < last_x) ||
                                       (y > first_y[x] && y < last_y[x]));
            count += inside[i];
        }
    }
    free(first_y);
    free(last_y);
    return count;
}

/* The variant, its synthesis taking the progress's current stage but the
 * smooth parts' share (decompose's ROF and membrane are a tenth of a
 * typical run, haar's coarsest membrane much less): nothing reports
 * during them. */
static relief_status run_variant(float *z, const uint8_t *missing, const uint8_t *inside,
                                 int W, int H, const relief_depth_repair_params *p,
                                 relief_patch_scorer *scorer, int64_t *source,
                                 relief_depth_repair_report *rep, relief_error *err)
{
    relief_progress *pr = p->progress;
    double lo = pr ? pr->lo : 0.0, hi = pr ? pr->hi : 1.0, smooth;
    relief_status st;
    if (relief_progress_step(pr, 0.0))
        return relief_fail(err, RELIEF_E_CANCELLED, "cancelled by the progress callback");
    smooth = p->variant == RELIEF_DEPTH_DECOMPOSE ? 0.1 : p->variant == RELIEF_DEPTH_HAAR ? 0.02
                                                                                          : 0.0;
    if (pr)
        relief_progress_stage(pr, lo + smooth * (hi - lo), hi);
    switch (p->variant) {
    case RELIEF_DEPTH_PLAIN:
        st = fill_plain(z, missing, inside, W, H, p, scorer, source, rep, err);
        break;
    case RELIEF_DEPTH_HAAR:
        st = fill_haar(z, missing, inside, W, H, p, scorer, source, rep, err);
        break;
    default:
        st = fill_decompose(z, missing, inside, W, H, p, scorer, source, rep, err);
        break;
    }
    if (pr)
        relief_progress_stage(pr, lo, hi);
    return st;
}

/* Pass r of a layered repair: the pixels of rank r (and, in the first,
 * those of no stepped hole) to fill; every other ranked pixel, a rim's
 * piece of another rank or a hole pixel of another, is missing and no
 * neighbour, so that nothing couples across the step. Returns the pixels
 * to fill. */
static size_t layer_masks(const uint8_t *missing, const uint8_t *inside, const uint8_t *rank,
                          size_t n, int r, uint8_t *miss_r, uint8_t *in_r)
{
    size_t count = 0;
    for (size_t i = 0; i < n; ++i) {
        int own = rank[i] == RELIEF_LAYER_NONE ? r == 0 : rank[i] == r;
        miss_r[i] = missing[i] || !own;
        in_r[i] = inside[i] && own;
        count += in_r[i];
    }
    return count;
}

/* The layered repair (layers.h): one run_variant per rank, each on a copy
 * of z, its share of the progress its share of the pixels; lambda, when
 * automatic, is the first pass's for all. */
static relief_status run_passes(float *z, const uint8_t *missing, const uint8_t *inside,
                                const relief_layers *lay, int W, int H,
                                const relief_depth_repair_params *p,
                                relief_patch_scorer *scorer, int64_t *source,
                                relief_depth_repair_report *rep, relief_error *err)
{
    size_t n = (size_t)W * H, done = 0;
    uint8_t *miss_r = malloc(n), *in_r = malloc(n);
    float *z_r = malloc(n * sizeof *z_r);
    int64_t *src_r = source ? malloc(n * sizeof *src_r) : NULL;
    relief_depth_repair_params q = *p;
    relief_progress *pr = p->progress;
    double lo = pr ? pr->lo : 0.0, hi = pr ? pr->hi : 1.0;
    relief_status st = RELIEF_OK;
    if (!miss_r || !in_r || !z_r || (source && !src_r))
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a layered repair's masks");
    for (int r = 0; r < lay->ranks && st == RELIEF_OK; ++r) {
        size_t m = layer_masks(missing, inside, lay->rank, n, r, miss_r, in_r);
        if (m == 0)
            continue;
        if (pr)
            relief_progress_stage(pr, lo + (hi - lo) * done / rep->filled,
                                  lo + (hi - lo) * (done + m) / rep->filled);
        memcpy(z_r, z, n * sizeof *z);
        for (size_t i = 0; src_r && i < n; ++i)
            src_r[i] = -1;
        st = run_variant(z_r, miss_r, in_r, W, H, &q, scorer, src_r, rep, err);
        if (st == RELIEF_E_RANGE && q.variant == RELIEF_DEPTH_HAAR && r > 0) {
            /* A front layer thinner than the coarsest Haar block (a chair's
             * leg) has no known coefficient there: decompose fills it. */
            relief_depth_repair_params d = q;
            d.variant = RELIEF_DEPTH_DECOMPOSE;
            memset(err, 0, sizeof *err);
            memcpy(z_r, z, n * sizeof *z);
            st = run_variant(z_r, miss_r, in_r, W, H, &d, scorer, src_r, rep, err);
            rep->layer_decomposed += m;
        }
        q.lambda = rep->lambda;
        ++rep->layer_passes;
        for (size_t i = 0; i < n && st == RELIEF_OK; ++i)
            if (in_r[i]) {
                z[i] = z_r[i];
                if (source)
                    source[i] = src_r[i];
            }
        done += m;
    }
    if (pr)
        relief_progress_stage(pr, lo, hi);
    free(miss_r);
    free(in_r);
    free(z_r);
    free(src_r);
    return st;
}

/* The repair, layer by layer where p->layered and a hole crosses a step. */
static relief_status run_repair(float *z, const uint8_t *missing, const uint8_t *inside,
                                int layered, int W, int H, const relief_depth_repair_params *p,
                                relief_patch_scorer *scorer, int64_t *source,
                                relief_depth_repair_report *rep, relief_error *err)
{
    relief_layers lay;
    relief_status st;
    if (!layered)
        return run_variant(z, missing, inside, W, H, p, scorer, source, rep, err);
    st = relief_layers_find(z, missing, inside, W, H, &p->layer, &lay, err);
    if (st != RELIEF_OK)
        return st;
    rep->stepped_holes = lay.stepped_holes;
    rep->front_pixels = lay.front_pixels;
    rep->layer_noise = lay.noise;
    if (lay.ranks > 1) {
        st = run_passes(z, missing, inside, &lay, W, H, p, scorer, source, rep, err);
    } else {
        rep->layer_passes = 1;
        st = run_variant(z, missing, inside, W, H, p, scorer, source, rep, err);
    }
    relief_layers_free(&lay);
    return st;
}

relief_status relief_depth_repair(float *z, const uint8_t *missing, int width, int height,
                                const relief_depth_repair_params *p, relief_patch_scorer *scorer,
                                int64_t *source, relief_depth_repair_report *rep,
                                relief_error *err)
{
    return relief_depth_repair_targets(z, missing, NULL, width, height, p, scorer, source, rep,
                                     err);
}

relief_status relief_depth_repair_targets(float *z, const uint8_t *missing, const uint8_t *target,
                                        int width, int height,
                                        const relief_depth_repair_params *p,
                                        relief_patch_scorer *scorer, int64_t *source,
                                        relief_depth_repair_report *rep, relief_error *err)
{
    size_t n = (size_t)width * height, holes = 0;
    relief_depth_repair_report local;
    uint8_t *inside;
    relief_status st;
    if (!rep)
        rep = &local;
    memset(rep, 0, sizeof *rep);
    rep->energy[0] = rep->energy[1] = -1.0;
    st = relief_depth_repair_params_validate(p, width, height, err);
    if (st != RELIEF_OK)
        return st;
    for (size_t i = 0; i < n; ++i) {
        holes += missing[i] != 0;
        if (source)
            source[i] = -1;
    }
    rep->missing = holes;
    if (holes == 0)
        return RELIEF_OK;
    if (holes == n)
        return relief_fail(err, RELIEF_E_RANGE, "every pixel of the image is missing: there is "
                           "nothing to repair it from");
    inside = malloc(n);
    if (!inside)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the inside mask");
    if (target) {
        rep->filled = 0;
        for (size_t i = 0; i < n; ++i) {
            inside[i] = missing[i] && target[i];
            rep->filled += inside[i];
        }
        if (rep->filled == 0) {
            free(inside);
            return RELIEF_OK; /* nothing asked */
        }
    } else if (p->synth.tileable) {
        /* On a torus every missing pixel is enclosed. */
        rep->filled = 0;
        for (size_t i = 0; i < n; ++i) {
            inside[i] = missing[i] != 0;
            rep->filled += inside[i];
        }
    } else {
        rep->filled = relief_depth_inside(missing, width, height, inside);
    }
    if (rep->filled == (size_t)-1) {
        free(inside);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the capture's extent");
    }
    rep->outside = holes - rep->filled;
    if (rep->filled == 0) {
        free(inside);
        return relief_fail(err, RELIEF_E_RANGE, "none of the %zu missing pixels lies inside "
                           "the capture (a known pixel on both sides along its row or its "
                           "column): the hole touches every border around the data, and "
                           "filling it would be extrapolation", holes);
    }
    st = run_repair(z, missing, inside, p->layered && !target && !p->synth.tileable, width,
                    height, p, scorer, source, rep, err);
    /* Missing pixels outside the capture are missing in the result too,
     * whatever they held (a masked pixel keeps no stale depth). */
    if (st == RELIEF_OK)
        for (size_t i = 0; i < n; ++i)
            if (missing[i] && !inside[i])
                z[i] = NAN;
    free(inside);
    return st;
}

/* ---------------------------------------------------------------- measures */

void relief_depth_measure(const float *z, const float *truth, const uint8_t *missing,
                          int width, int height, relief_depth_measures *m)
{
    int W = width, H = height;
    double se = 0.0, jump = 0.0, tjump = 0.0, cap = 0.0;
    size_t tpairs = 0, cap_n = 0;
    memset(m, 0, sizeof *m);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            size_t i = (size_t)y * W + x;
            if (missing[i] && truth && isfinite(truth[i]) && isfinite(z[i])) {
                double d = (double)z[i] - truth[i];
                se += d * d;
                ++m->compared;
            }
            /* Triples along +x and +y starting at i: i, i + s, i + 2 s. */
            for (int dir = 0; dir < 2; ++dir) {
                int ok = dir ? y + 2 < H : x + 2 < W;
                size_t s = dir ? (size_t)W : 1, a = i, b = i + s, c = i + 2 * s;
                if (!ok)
                    continue;
                if (!missing[a] && !missing[b] && !missing[c]) {
                    if (isfinite(z[a]) && isfinite(z[b]) && isfinite(z[c])) {
                        cap += fabs((double)z[a] - 2.0 * z[b] + z[c]);
                        ++cap_n;
                    }
                    continue;
                }
                /* A rim triple: one end filled, the other two known. */
                for (int end = 0; end < 2; ++end) {
                    size_t p = end ? c : a, q = b, r = end ? a : c;
                    double step;
                    if (!missing[p] || missing[q] || missing[r] || !isfinite(z[p]) ||
                        !isfinite(z[q]) || !isfinite(z[r]))
                        continue;
                    /* With a truth, the rims of the holes it knows. */
                    if (truth && !isfinite(truth[p]))
                        continue;
                    step = fabs(((double)z[p] - z[q]) - ((double)z[q] - z[r]));
                    jump += step;
                    ++m->rim_pairs;
                    if (truth && isfinite(truth[p])) {
                        tjump += fabs(((double)truth[p] - z[q]) - ((double)z[q] - z[r]));
                        ++tpairs;
                    }
                }
            }
        }
    m->rms = m->compared ? sqrt(se / (double)m->compared) : NAN;
    m->rim_jump = m->rim_pairs ? jump / (double)m->rim_pairs : NAN;
    m->capture_jump = cap_n ? cap / (double)cap_n : NAN;
    m->truth_jump = tpairs ? tjump / (double)tpairs : NAN;
}
