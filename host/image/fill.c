#include "image/fill.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/clock.h"
#include "base/error.h"
#include "base/parallel.h"
#include "base/progress.h"
#include "base/rng.h"

relief_fill_params relief_fill_params_default(void)
{
    relief_fill_params p;
    memset(&p, 0, sizeof p);
    p.window = 17;
    p.min_window = 5;
    p.tau = 0.0;
    p.max_hole_fraction = 0.1;
    p.search_radius = 0;
    p.exhaustive = 0;
    p.interp = 1;
    p.interp_diff = -1.0;
    p.interp_sd = -1.0;
    p.interp_span = 4;
    p.pyramid_side = 128;
    p.pyramid_levels = 4;
    p.region_pixels = 4096;
    p.window_pixels = 25;
    p.seed = 1;
    return p;
}

relief_status relief_fill_params_check(const relief_fill_params *p, relief_error *err)
{
    if (p->window < 3 || p->window > 1025 || p->window % 2 == 0)
        return relief_fail_param(err, RELIEF_E_RANGE, "window", "window %d out of range: "
                                 "expected an odd number of pixels in 3..1025", p->window);
    if (p->min_window < 3 || p->min_window > p->window || p->min_window % 2 == 0)
        return relief_fail_param(err, RELIEF_E_RANGE, "min_window", "min_window %d out of "
                                 "range: expected an odd number of pixels in 3..%d (window)",
                                 p->min_window, p->window);
    if (!(p->max_hole_fraction >= 0.0 && p->max_hole_fraction < 1.0))
        return relief_fail_param(err, RELIEF_E_RANGE, "max_hole_fraction", "max_hole_fraction "
                                 "%g out of range: expected 0 <= f < 1", p->max_hole_fraction);
    if (!isfinite(p->tau) || p->tau < 0.0)
        return relief_fail_param(err, RELIEF_E_RANGE, "tau", "tau %g out of range: expected a "
                                 "finite value > 0, or 0 for the default", p->tau);
    if (p->search_radius < 0 || p->search_radius > 1000000)
        return relief_fail_param(err, RELIEF_E_RANGE, "search_radius", "search_radius %d out "
                                 "of range: expected 0..1000000 pixels (0: the whole image)",
                                 p->search_radius);
    if (p->search_radius > 0 && 2 * p->search_radius + 1 < p->window)
        return relief_fail_param(err, RELIEF_E_RANGE, "search_radius", "search_radius %d: the "
                                 "search region must hold a window: expected at least %d "
                                 "(window %d)", p->search_radius, p->window / 2, p->window);
    if (!isfinite(p->interp_diff))
        return relief_fail_param(err, RELIEF_E_RANGE, "interp_diff", "interp_diff %g out of "
                                 "range: expected a finite value (< 0: the default)",
                                 p->interp_diff);
    if (!isfinite(p->interp_sd))
        return relief_fail_param(err, RELIEF_E_RANGE, "interp_sd", "interp_sd %g out of "
                                 "range: expected a finite value (< 0: the default)",
                                 p->interp_sd);
    /* The filler's own (no public field: nothing to name). */
    if (p->interp_span < 1 || p->interp_span > 64)
        return relief_fail(err, RELIEF_E_RANGE, "interp_span %d out of range: expected 1..64",
                           p->interp_span);
    if (p->pyramid_side < 8 || p->pyramid_levels < 0 ||
        p->pyramid_levels > RELIEF_FILL_MAX_LEVELS - 1 || p->region_pixels < 1 ||
        p->window_pixels < 1)
        return relief_fail(err, RELIEF_E_RANGE, "pyramid parameters out of range");
    return RELIEF_OK;
}

relief_status relief_fill_params_validate(const relief_fill_params *p, int width, int height,
                                          relief_error *err)
{
    int side = width < height ? width : height;
    relief_status st = relief_fill_params_check(p, err);
    if (st == RELIEF_OK && side < 3)
        st = relief_fail(err, RELIEF_E_RANGE, "the image (%d x %d pixels) is smaller than the "
                         "smallest window (3 x 3)", width, height);
    else if (st == RELIEF_OK && p->window > side)
        st = relief_fail_param(err, RELIEF_E_RANGE, "window", "window %d is larger than the "
                               "image (%d x %d pixels): expected at most %d", p->window, width,
                               height, side % 2 ? side : side - 1);
    return st;
}

uint64_t relief_fill_estimate(int width, int height, int channels)
{
    uint64_t px = (uint64_t)width * (uint64_t)height;
    /* The raster, the levels' copies (a third more for the coarse ones),
     * their known flags, the hole mask, a rectangle of scores and the
     * boundary list. */
    return px * (uint64_t)channels * 4u + px * (uint64_t)channels * 4u * 4u / 3u +
           px * 2u + px * 8u + px * 4u;
}

/* ---------------------------------------------------------------- 1-D pass */

/* Is the run of `span` known pixels ending at i (going by -step) smooth:
 * its standard deviation under sd in every channel? Fewer than 2 known
 * pixels there: no. */
static int smooth_end(const float *v, const uint8_t *hole, int C, int stride, int i, int step,
                      int limit_lo, int limit_hi, int span, double sd)
{
    for (int c = 0; c < C; ++c) {
        double s = 0.0, s2 = 0.0;
        int m = 0;
        for (int k = 0, j = i; k < span && j >= limit_lo && j <= limit_hi; ++k, j -= step) {
            double x;
            if (hole[j])
                break;
            x = v[(size_t)j * stride + c];
            s += x;
            s2 += x * x;
            ++m;
        }
        if (m < 2)
            return 0;
        if ((s2 - s * s / m) / m > sd * sd)
            return 0;
    }
    return 1;
}

/* The mean |second difference| along the line over the known pixels
 * beyond i (going by -step), at most `reach` of them, i included, in
 * channel c: 0 for a ramp however steep, about 2 sigma for noise of
 * standard deviation sigma. -1 when fewer than 3 pixels are known there. */
static double end_roughness(const float *v, const uint8_t *hole, int stride, int c, int i,
                            int step, int limit_lo, int limit_hi, int reach)
{
    double x[3], sum = 0.0;
    int m = 0;
    for (int k = 0, j = i; k < reach && j >= limit_lo && j <= limit_hi && !hole[j];
         ++k, j -= step) {
        x[k % 3] = v[(size_t)j * stride + c];
        if (++m >= 3)
            sum += fabs(x[k % 3] - 2.0 * x[(k + 2) % 3] + x[(k + 1) % 3]);
    }
    return m >= 3 ? sum / (m - 2) : -1.0;
}

/* The line-level thresholds of one call of the pass. */
typedef struct interp_limits {
    double diff, sd;   /* the paper's: ends agree, ends smooth */
    double rough[4];   /* the largest end roughness a linear run matches, per channel */
    int max_gap, reach; /* the window: the longest gap, and how far each end is looked at */
} interp_limits;

/* May the gap between known pixels ia and ib (b - a - 1 pixels along the
 * line) be filled linearly? Its ends agree and are smooth (the paper's
 * test), it is no longer than the window, and the linear run, whose
 * second differences are 0, matches its ends' local variation: each
 * end's roughness at most the image's own (interp_limits.rough). A gap in
 * texture, however quiet its ends look over 4 pixels, is left to
 * copy-paste, which keeps the texture. */
static int gap_is_smooth(const float *v, const uint8_t *hole, int C, int stride, int ia,
                         int ib, int gap, int step, int first, int last,
                         const relief_fill_params *p, const interp_limits *lim)
{
    if (gap > lim->max_gap)
        return 0;
    for (int c = 0; c < C; ++c)
        if (fabs((double)v[(size_t)ia * stride + c] - v[(size_t)ib * stride + c]) > lim->diff)
            return 0;
    if (!smooth_end(v, hole, C, stride, ia, step, first, last, p->interp_span, lim->sd) ||
        !smooth_end(v, hole, C, stride, ib, -step, first, last, p->interp_span, lim->sd))
        return 0;
    for (int c = 0; c < C; ++c)
        if (end_roughness(v, hole, stride, c, ia, step, first, last, lim->reach) >
                lim->rough[c] ||
            end_roughness(v, hole, stride, c, ib, -step, first, last, lim->reach) >
                lim->rough[c])
            return 0;
    return 1;
}

/* One line (a row or a column): pixels first, first + step, ... (n of
 * them). Gaps between two known pixels that gap_is_smooth accepts are
 * filled linearly. */
static size_t interp_line(float *v, uint8_t *hole, int C, int stride, int first, int step,
                          int n, const relief_fill_params *p, const interp_limits *lim)
{
    size_t filled = 0;
    int last = first + (n - 1) * step;
    int a = -1; /* index along the line of the last known pixel */
    for (int k = 0; k < n; ++k) {
        int i = first + k * step;
        if (hole[i])
            continue;
        if (a >= 0 && k - a > 1) {
            int ia = first + a * step;
            if (gap_is_smooth(v, hole, C, stride, ia, i, k - a - 1, step, first, last, p,
                              lim)) {
                for (int g = a + 1; g < k; ++g) {
                    int ig = first + g * step;
                    float t = (float)(g - a) / (float)(k - a);
                    for (int c = 0; c < C; ++c) {
                        float va = v[(size_t)ia * stride + c], vb = v[(size_t)i * stride + c];
                        v[(size_t)ig * stride + c] = va + (vb - va) * t;
                    }
                    hole[ig] = 2; /* filled in this pass: not an end for the others */
                    ++filled;
                }
            }
        }
        a = k;
    }
    return filled;
}

/* In place: the median (the (n / 2)-th smallest) of n > 0 values, by
 * Wirth's selection. */
static float median_of(float *x, size_t n)
{
    ptrdiff_t lo = 0, hi = (ptrdiff_t)n - 1, k = (ptrdiff_t)(n / 2);
    while (lo < hi) {
        float pivot = x[k];
        ptrdiff_t i = lo, j = hi;
        do {
            while (x[i] < pivot)
                ++i;
            while (pivot < x[j])
                --j;
            if (i <= j) {
                float t = x[i];
                x[i++] = x[j];
                x[j--] = t;
            }
        } while (i <= j);
        if (j < k)
            lo = i;
        if (k < i)
            hi = j;
    }
    return x[k];
}

/* The image's own roughness per channel: the median |second difference|
 * along rows and columns over the known pixels (every triple, or an even
 * sample of 2^20 of them on a large image). A median, so that the holes'
 * edges and the few strong edges of a photograph do not count: for noise
 * or fine texture of standard deviation sigma it is about 1.65 sigma, for
 * smooth shading near 0. Memory short: 0 (the pass then fills only where
 * both ends are as smooth as a quantised ramp). */
static void image_roughness(const relief_raster *img, const uint8_t *hole, int C,
                            double *rough)
{
    int W = img->width, H = img->height, S = img->channels;
    size_t n = (size_t)W * H, every = 1 + n / ((size_t)1 << 19), m = 0;
    float *d = malloc(sizeof *d * 2 * (n / every + 1));
    for (int c = 0; c < C; ++c)
        rough[c] = 0.0;
    if (!d)
        return;
    for (int c = 0; c < C; ++c) {
        m = 0;
        for (size_t i = 0; i < n; i += every) {
            int x = (int)(i % W), y = (int)(i / W);
            const float *o = img->v + i * S + c;
            if (x > 0 && x < W - 1 && !hole[i - 1] && !hole[i] && !hole[i + 1])
                d[m++] = fabsf(o[-S] - 2.0f * o[0] + o[S]);
            if (y > 0 && y < H - 1 && !hole[i - W] && !hole[i] && !hole[i + W])
                d[m++] = fabsf(o[-(ptrdiff_t)W * S] - 2.0f * o[0] + o[(size_t)W * S]);
        }
        rough[c] = m ? median_of(d, m) : 0.0;
    }
    free(d);
}

void relief_fill_thresholds(const relief_fill_params *p, int bit_depth, double *tau,
                           double *diff, double *sd)
{
    double s = bit_depth == 16 ? 257.0 : 1.0;
    if (tau)
        *tau = p->tau > 0.0 ? p->tau : 36.0 * s;
    if (diff)
        *diff = p->interp_diff >= 0.0 ? p->interp_diff : 16.0 * s;
    if (sd)
        *sd = p->interp_sd >= 0.0 ? p->interp_sd : 3.0 * s;
}

/* The colour channels matched and interpolated: all but alpha. */
static int colour_channels(const relief_raster *r)
{
    return relief_raster_has_alpha(r) ? r->channels - 1 : r->channels;
}

static void make_opaque(relief_raster *img, size_t i)
{
    if (relief_raster_has_alpha(img))
        img->v[i * img->channels + img->channels - 1] = relief_raster_max_value(img) > 0
                                                            ? relief_raster_max_value(img)
                                                            : 1.0f;
}

void relief_fill_interp(relief_raster *img, uint8_t *hole, const relief_fill_params *p,
                        size_t *by_rows, size_t *by_columns, double *roughness)
{
    int W = img->width, H = img->height, C = colour_channels(img);
    size_t rows = 0, cols = 0, n = (size_t)W * H;
    interp_limits lim;
    double image_rough[4];
    relief_fill_thresholds(p, img->bit_depth, NULL, &lim.diff, &lim.sd);
    /* A linear run matches an end no rougher than the image's typical
     * pixel, or than a ramp quantised to the image's levels (|second
     * difference| 0 or 1 on 0..255); the paper's thresholds (16 and 3 on
     * 0..255) alone let quiet-looking ends of a low-contrast texture
     * through and wiped it (issue 40). Half the typical roughness kept
     * texture as well but left the smooth parts of photographs' scratches
     * to copy-paste (bench/image_fill.py, coffee scratch RMS 50.7 against
     * 25.6 with this). */
    image_roughness(img, hole, C, image_rough);
    for (int c = 0; c < C; ++c)
        lim.rough[c] = fmax(1.0 * image_rough[c], img->bit_depth == 16 ? 257.0 : 1.0);
    if (roughness)
        memcpy(roughness, lim.rough, sizeof(double) * (size_t)C);
    lim.max_gap = p->window;
    lim.reach = p->window / 2 + 1;
    for (int y = 0; y < H; ++y)
        rows += interp_line(img->v, hole, C, img->channels, y * W, 1, W, p, &lim);
    for (size_t i = 0; i < n; ++i)
        if (hole[i] == 2) {
            hole[i] = 0; /* the row pass's fills are ends for the column pass */
            make_opaque(img, i);
        }
    for (int x = 0; x < W; ++x)
        cols += interp_line(img->v, hole, C, img->channels, x, W, H, p, &lim);
    for (size_t i = 0; i < n; ++i)
        if (hole[i] == 2) {
            hole[i] = 0;
            make_opaque(img, i);
        }
    if (by_rows)
        *by_rows = rows;
    if (by_columns)
        *by_columns = cols;
}

/* ---------------------------------------------------------------- the filler */

struct relief_filler {
    relief_raster *img;
    relief_fill_params p;
    int C;        /* channels matched */
    double tau;   /* acceptance, values' units */
    int n_levels;
    relief_patch_level lv[RELIEF_FILL_MAX_LEVELS];
    float *v[RELIEF_FILL_MAX_LEVELS];
    uint8_t *known[RELIEF_FILL_MAX_LEVELS];
    relief_patch_scorer *scorer;
    float *ssd, *wsum;
    int *n;
    size_t cap;
    float g[513]; /* the weights of the level being scored (radius <= 512) */
    relief_rng rng;
    relief_fill_report *rep;
    double score_seconds;
    size_t candidates, read_back; /* windows scored, their scores read back */
    int *rects, *pairs, *first, *owner; /* a batch of searches' scratch (batch_rects, */
    size_t rects_cap, pairs_cap, first_cap, owner_cap; /* batch_refine), in ints */
};

/* Room for `count` ints in *buf (cap). 0 when out of memory. */
static int int_room(int **buf, size_t *cap, size_t count)
{
    if (count > *cap) {
        int *b = realloc(*buf, count * sizeof *b);
        if (!b)
            return 0;
        *buf = b, *cap = count;
    }
    return 1;
}

static const float reduce_g[5] = {1.0f, 4.0f, 6.0f, 4.0f, 1.0f};

/* reduce_pixel's sums for C channels where the 5 x 5 fine pixels lie
 * inside level l - 1 and are all known: the same products added in the
 * same order, without a test a tap (the weights, small integers, add up
 * to 256 exactly in any order), so the same bits. 0, and nothing
 * written, when one of them is not known. */
static inline int reduce_inside(relief_filler *f, int l, int X, int Y, int C)
{
    size_t w = (size_t)f->lv[l - 1].width, at = (size_t)(2 * Y - 2) * w + (size_t)(2 * X - 2);
    size_t o = (size_t)Y * f->lv[l].width + X;
    const uint8_t *k = f->known[l - 1] + at;
    const float *v = f->v[l - 1] + at * C;
    float a0 = 0.0f, a1 = 0.0f, a2 = 0.0f, a3 = 0.0f, *out = f->v[l] + o * C;
    for (int dy = 0; dy < 5; ++dy, k += w)
        if (!k[0] || !k[1] || !k[2] || !k[3] || !k[4])
            return 0;
    for (int dy = 0; dy < 5; ++dy, v += w * C)
        for (int dx = 0; dx < 5; ++dx) {
            /* Four accumulators in registers (a loop over C kept them in
             * memory, one store-to-load wait an addition). */
            const float wt = reduce_g[dx] * reduce_g[dy], *p = v + dx * C;
            a0 += wt * p[0];
            if (C > 1)
                a1 += wt * p[1];
            if (C > 2)
                a2 += wt * p[2];
            if (C > 3)
                a3 += wt * p[3];
        }
    out[0] = a0 / 256.0f;
    if (C > 1)
        out[1] = a1 / 256.0f;
    if (C > 2)
        out[2] = a2 / 256.0f;
    if (C > 3)
        out[3] = a3 / 256.0f;
    f->known[l][o] = 1;
    return 1;
}

/* Level l's pixel (X, Y) from level l - 1: the Gaussian [1 4 6 4 1] / 16
 * in each direction over the known pixels around (2X, 2Y), normalised;
 * known when every pixel of its 2 x 2 block is. */
static void reduce_pixel(relief_filler *f, int l, int X, int Y)
{
    const float *g = reduce_g;
    const relief_patch_level *fine = &f->lv[l - 1];
    int C = f->C, w = fine->width, h = fine->height, all = 1;
    float acc[4] = {0.0f, 0.0f, 0.0f, 0.0f}, wsum = 0.0f;
    size_t o = (size_t)Y * f->lv[l].width + X;
    if (X >= 1 && 2 * X + 2 < w && Y >= 1 && 2 * Y + 2 < h) {
        /* One copy of the sums a channel count, each with C a constant. */
        if (C == 3 ? reduce_inside(f, l, X, Y, 3)
                   : C == 1 ? reduce_inside(f, l, X, Y, 1)
                            : C == 4 ? reduce_inside(f, l, X, Y, 4) : reduce_inside(f, l, X, Y, 2))
            return;
    }
    for (int dy = -2; dy <= 2; ++dy) {
        int y = 2 * Y + dy;
        if (y < 0 || y >= h)
            continue;
        for (int dx = -2; dx <= 2; ++dx) {
            int x = 2 * X + dx;
            size_t i;
            float wt;
            if (x < 0 || x >= w)
                continue;
            i = (size_t)y * w + x;
            if (!f->known[l - 1][i]) {
                if (dx >= 0 && dx <= 1 && dy >= 0 && dy <= 1)
                    all = 0;
                continue;
            }
            wt = g[dx + 2] * g[dy + 2];
            wsum += wt;
            for (int c = 0; c < C; ++c)
                acc[c] += wt * f->v[l - 1][i * C + c];
        }
    }
    for (int c = 0; c < C; ++c)
        f->v[l][o * C + c] = wsum > 0.0f ? acc[c] / wsum : 0.0f;
    f->known[l][o] = (uint8_t)(all && wsum > 0.0f);
}

/* Level l's rows [lo, hi), for relief_parallel_ranges. */
typedef struct reduce_level {
    relief_filler *f;
    int l;
} reduce_level;

static int reduce_rows(void *ctx, size_t lo, size_t hi)
{
    reduce_level *r = ctx;
    for (size_t Y = lo; Y < hi; ++Y)
        for (int X = 0; X < r->f->lv[r->l].width; ++X)
            reduce_pixel(r->f, r->l, X, (int)Y);
    return 0;
}

/* Pixels x0..x1, y0..y1 of level 0 changed: bring the coarser levels and
 * the scorer up to date. */
static relief_status changed(relief_filler *f, int x0, int y0, int x1, int y1,
                             relief_error *err)
{
    relief_status st = f->scorer->ops->update(f->scorer->ctx, 0, y0, y1, err);
    for (int l = 1; l < f->n_levels && st == RELIEF_OK; ++l) {
        /* Coarse pixel X reads fine pixels 2X - 2 .. 2X + 2. */
        int X0 = (x0 + 1) / 2 - 1, X1 = (x1 + 2) / 2, Y0 = (y0 + 1) / 2 - 1, Y1 = (y1 + 2) / 2;
        X0 = X0 < 0 ? 0 : X0;
        Y0 = Y0 < 0 ? 0 : Y0;
        X1 = X1 >= f->lv[l].width ? f->lv[l].width - 1 : X1;
        Y1 = Y1 >= f->lv[l].height ? f->lv[l].height - 1 : Y1;
        for (int Y = Y0; Y <= Y1; ++Y)
            for (int X = X0; X <= X1; ++X)
                reduce_pixel(f, l, X, Y);
        st = f->scorer->ops->update(f->scorer->ctx, l, Y0, Y1, err);
        x0 = X0, x1 = X1, y0 = Y0, y1 = Y1;
    }
    return st;
}

static void filler_free(relief_filler *f)
{
    if (!f)
        return;
    for (int l = 0; l < RELIEF_FILL_MAX_LEVELS; ++l) {
        free(f->v[l]);
        free(f->known[l]);
    }
    free(f->ssd);
    free(f->wsum);
    free(f->n);
    free(f->rects), free(f->pairs), free(f->first), free(f->owner);
    free(f);
}

void relief_filler_destroy(relief_filler *f) { filler_free(f); }

int relief_filler_levels(const relief_filler *f) { return f->n_levels; }

size_t relief_filler_candidates(const relief_filler *f, double *seconds)
{
    if (seconds)
        *seconds = f->score_seconds;
    return f->candidates;
}

size_t relief_filler_scores_read(const relief_filler *f) { return f->read_back; }

relief_status relief_filler_create(relief_raster *img, const uint8_t *hole,
                                   const relief_fill_params *p, relief_patch_scorer *scorer,
                                   relief_filler **out, relief_error *err)
{
    relief_filler *f;
    size_t n = (size_t)img->width * img->height;
    relief_status st = relief_fill_params_validate(p, img->width, img->height, err);
    if (st != RELIEF_OK)
        return st;
    if (n * (size_t)img->channels > 0x7fffffffu)
        return relief_fail(err, RELIEF_E_RANGE, "an image of %d x %d x %d values: at most "
                           "2^31 are supported", img->width, img->height, img->channels);
    f = calloc(1, sizeof *f);
    if (!f)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the filler");
    f->img = img;
    f->p = *p;
    f->C = colour_channels(img);
    f->scorer = scorer;
    relief_fill_thresholds(p, img->bit_depth, &f->tau, NULL, NULL);
    relief_rng_seed(&f->rng, p->seed);
    /* Level 0 is a copy of the colour channels; the pyramid halves while a
     * side is over pyramid_side, at most pyramid_levels times (none when
     * exhaustive). */
    f->n_levels = 1;
    if (!p->exhaustive) {
        int w = img->width, h = img->height;
        while (f->n_levels <= p->pyramid_levels && (w > p->pyramid_side || h > p->pyramid_side) &&
               f->n_levels < RELIEF_FILL_MAX_LEVELS) {
            w = (w + 1) / 2;
            h = (h + 1) / 2;
            ++f->n_levels;
        }
    }
    for (int l = 0; l < f->n_levels; ++l) {
        int w = l ? (f->lv[l - 1].width + 1) / 2 : img->width;
        int h = l ? (f->lv[l - 1].height + 1) / 2 : img->height;
        f->v[l] = malloc((size_t)w * h * f->C * sizeof(float));
        f->known[l] = malloc((size_t)w * h);
        if (!f->v[l] || !f->known[l]) {
            filler_free(f);
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the image pyramid");
        }
        f->lv[l] = (relief_patch_level){f->v[l], f->known[l], w, h, f->C};
        if (l == 0) {
            for (size_t i = 0; i < n; ++i) {
                f->known[0][i] = !hole[i];
                for (int c = 0; c < f->C; ++c)
                    f->v[0][i * f->C + c] = hole[i] ? 0.0f : img->v[i * img->channels + c];
            }
        } else {
            reduce_level rl = {f, l};
            /* Rows on the scorer's threads: each pixel its own, the same
             * values however many. */
            relief_parallel_ranges((size_t)h, scorer->threads, reduce_rows, &rl);
        }
    }
    st = scorer->ops->bind(scorer->ctx, f->lv, f->n_levels, err);
    if (st != RELIEF_OK) {
        filler_free(f);
        return st;
    }
    *out = f;
    return RELIEF_OK;
}

/* How far around a kept match's image (2X, 2Y) the next finer level
 * looks: a coarse window's best position is known to a pixel or two only.
 * On brick.png (test_fill), 1 found the exhaustive best in 13 of 40
 * queries, 2 in 36 of 40. */
#define REFINE 2

/* Valid centres at level l for half-size `half`, inside the search
 * region around (px, py) (full resolution): x0..x1, y0..y1; 0 when none. */
static int region(const relief_filler *f, int l, int px, int py, int half, int *x0, int *y0,
                  int *x1, int *y1)
{
    const relief_patch_level *lv = &f->lv[l];
    int r = f->p.search_radius;
    *x0 = half;
    *y0 = half;
    *x1 = lv->width - 1 - half;
    *y1 = lv->height - 1 - half;
    if (r > 0) {
        int ax = px - r < 0 ? 0 : (px - r) >> l, bx = (px + r) >> l;
        int ay = py - r < 0 ? 0 : (py - r) >> l, by = (py + r) >> l;
        *x0 = ax > *x0 ? ax : *x0;
        *y0 = ay > *y0 ? ay : *y0;
        *x1 = bx < *x1 ? bx : *x1;
        *y1 = by < *y1 ? by : *y1;
    }
    return *x0 <= *x1 && *y0 <= *y1;
}

static int max_holes(const relief_filler *f, int half)
{
    int side = 2 * half + 1;
    return (int)floor(f->p.max_hole_fraction * side * side + 1e-9);
}

/* Keep the `keep` best of the matches offered, in top[0 .. *n) ordered by
 * msd, then by position (row-major): the same order on every backend. */
static int better(const relief_window_match *a, const relief_window_match *b)
{
    if (a->msd != b->msd)
        return a->msd < b->msd;
    if (a->y != b->y)
        return a->y < b->y;
    return a->x < b->x;
}

static void offer(relief_window_match *top, int *n, int keep, relief_window_match m)
{
    int i;
    if (*n == keep && !better(&m, &top[keep - 1]))
        return;
    i = *n < keep ? (*n)++ : keep - 1;
    while (i > 0 && better(&m, &top[i - 1])) {
        top[i] = top[i - 1];
        --i;
    }
    top[i] = m;
}

/* A match's msd: ssd over the weights' sum (paper 003), or over the
 * pixels known in both (unweighted: the same number). */
static relief_window_match make_match(int x, int y, float ssd, int n, float wsum, int weighted)
{
    relief_window_match m = {x, y, ssd, n, (double)ssd / (weighted ? (double)wsum : (double)n)};
    return m;
}

/* The weights of a window of radius `half` at level l for a Gaussian of
 * sigma full-resolution pixels (sigma / 2^l there), in f->g; NULL when
 * unweighted (sigma <= 0). Computed on the host, so that every backend
 * gets the same floats. */
static const float *weights(relief_filler *f, int l, int half, double sigma)
{
    double s = sigma / (double)(1 << l);
    if (sigma <= 0.0)
        return NULL;
    /* Weights under 1e-18 become 0, so that no product of two weights is
     * subnormal (a device that flushes subnormals would disagree). */
    for (int k = 0; k <= half && k < 513; ++k) {
        double g = exp(-(double)k * k / (2.0 * s * s));
        f->g[k] = g < 1e-18 ? 0.0f : (float)g;
    }
    return f->g;
}

relief_status relief_filler_search(relief_filler *f, int px, int py, int w, int exhaustive,
                                   relief_window_match *best, int *found,
                                   relief_window_match *coarse, int *n_coarse,
                                   relief_error *err)
{
    int n_best = 0;
    relief_status st = relief_filler_search_top(f, px, py, w, exhaustive, 0.0, best, 1, &n_best,
                                                coarse, n_coarse, err);
    *found = n_best > 0;
    return st;
}

/* The start level of a search at (px, py) with half-size `half` (paper
 * 004, 3.2): coarser while the search region holds region_pixels
 * candidates or more and the window window_pixels or more, and the next
 * level still holds the window. */
static int start_level(const relief_filler *f, int px, int py, int half, int exhaustive)
{
    int start = 0, x0, y0, x1, y1;
    if (!exhaustive)
        while (start + 1 < f->n_levels) {
            int h = half >> start, side = 2 * h + 1;
            long cand = region(f, start, px, py, h, &x0, &y0, &x1, &y1)
                            ? (long)(x1 - x0 + 1) * (y1 - y0 + 1)
                            : 0;
            int hn = half >> (start + 1);
            if (cand < f->p.region_pixels || side * side < f->p.window_pixels ||
                2 * hn + 1 > f->lv[start + 1].width || 2 * hn + 1 > f->lv[start + 1].height)
                break;
            ++start;
        }
    return start;
}

int relief_filler_reach(const relief_filler *f, int w)
{
    /* Level l's pixel X reads level 0 within 2^(l+1) - 2 of 2^l X; a search
     * reads level l's pixels within its region (r) and window (w / 2) of
     * its centre's image: level 0 within r + w / 2 + 3 x 2^l of it. */
    if (f->p.search_radius <= 0)
        return INT_MAX / 2; /* the whole image */
    return f->p.search_radius + w / 2 + 4 * (1 << (f->n_levels - 1)) + 2;
}

/* One query of a batch of searches: where it is, how far it has come. */
typedef struct query {
    int px, py, start, keep, n_top, alive;
    relief_window_match top[RELIEF_FILL_MAX_TOP];
} query;

/* Room for `count` scores in f->ssd, f->wsum, f->n. */
static relief_status score_room(relief_filler *f, size_t count, relief_error *err)
{
    if (count > f->cap) {
        float *s = realloc(f->ssd, count * sizeof *s), *ws;
        int *k;
        if (s)
            f->ssd = s;
        ws = realloc(f->wsum, count * sizeof *ws);
        if (ws)
            f->wsum = ws;
        k = realloc(f->n, count * sizeof *k);
        if (k)
            f->n = k;
        if (!s || !ws || !k)
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate %zu window scores", count);
        f->cap = count;
    }
    return RELIEF_OK;
}

/* Query q's `keep` best of its rectangle r's scores, as offer() keeps
 * them: the `len` scores from index `first` of the rectangle's (row-major)
 * on, at f->ssd[at ..] (f->n, f->wsum when weighted); a rectangle's runs
 * come in ascending order. Most of a rectangle cannot enter a full top: a
 * score whose ssd is at least the worst kept msd times its divisor, with a
 * margin far above the rounding's, has an msd at least the worst's, and a
 * later position loses a tie (the scan is row-major), so it is passed over
 * without the division or the call; the rest go through offer(), whose
 * choice this does not change (given, as batch_rects gives it, a list
 * holding nothing from before this rectangle: a tie at msd 0 with an
 * earlier scan's later position would be passed over). On the 2048 x 2048
 * grass (300 M windows) the selection cost as much as the scoring on two
 * threads before. */
static void keep_run(const relief_filler *f, query *q, const int *r, int first, int len,
                     size_t at, int weighted)
{
    int full = q->n_top == q->keep;
    double worst = full ? q->top[q->keep - 1].msd * (1.0 + 1e-9) : 0.0;
    /* Row by row, so that the inner loop is a plain walk along x. */
    for (int k = first, end = first + len; k < end;) {
        int y = k / r[4], x0 = k % r[4], x1 = end - y * r[4] < r[4] ? end - y * r[4] : r[4];
        for (int x = x0; x < x1; ++x, ++at) {
            int n = f->n[at];
            /* Weighted, a window whose common pixels all weigh 0 says
             * nothing: refused. */
            double div = weighted ? (double)f->wsum[at] : (double)n;
            if (n <= 0 || !(div > 0.0) || (full && (double)f->ssd[at] >= worst * div))
                continue;
            offer(q->top, &q->n_top, q->keep,
                  make_match(r[2] + x, r[3] + y, f->ssd[at], n, weighted ? f->wsum[at] : 0.0f,
                             weighted));
            full = q->n_top == q->keep;
            worst = full ? q->top[q->keep - 1].msd * (1.0 + 1e-9) : 0.0;
        }
        k += x1 - x0;
    }
}

/* Rectangles rects[0 .. nr) (query owner[j] each) scored and ranked: in
 * one call where the scorer batches (a single query too: a batch of one),
 * reading back only what may rank where it selects, else one call each. */
static relief_status score_rects(relief_filler *f, query *q, const int *rects, int nr,
                                 size_t total, int l, int h, const float *g, relief_error *err)
{
    const relief_patch_ops *ops = f->scorer->ops;
    const int *owner = f->owner, *keep = f->owner + nr, *runs = NULL;
    size_t n_runs = 0;
    double t0 = relief_seconds();
    relief_status st = RELIEF_OK;
    if (ops->select_rects)
        st = ops->select_rects(f->scorer->ctx, l, h, max_holes(f, h), g, rects, keep, nr, total,
                               f->ssd, g ? f->wsum : NULL, f->n, &runs, &n_runs, err);
    else if (ops->score_rects)
        st = ops->score_rects(f->scorer->ctx, l, h, max_holes(f, h), g, rects, nr, total, f->ssd,
                              g ? f->wsum : NULL, f->n, err);
    else
        for (int k = 0; k < nr && st == RELIEF_OK; ++k) {
            const int *r = rects + 7 * k;
            st = ops->score_rect(f->scorer->ctx, l, r[0], r[1], h, max_holes(f, h), g, r[2],
                                 r[3], r[4], r[5], f->ssd + r[6], g ? f->wsum + r[6] : NULL,
                                 f->n + r[6], err);
        }
    f->score_seconds += relief_seconds() - t0;
    f->candidates += total;
    if (st != RELIEF_OK)
        return st;
    if (!ops->select_rects) {
        for (int j = 0; j < nr; ++j) {
            const int *r = rects + 7 * j;
            keep_run(f, &q[owner[j]], r, 0, r[4] * r[5], (size_t)r[6], g != NULL);
        }
        f->read_back += total;
        return RELIEF_OK;
    }
    for (size_t s = 0; s < n_runs; ++s) {
        const int *run = runs + 4 * s;
        keep_run(f, &q[owner[run[0]]], rects + 7 * run[0], run[1], run[2], (size_t)run[3],
                 g != NULL);
        f->read_back += (size_t)run[2];
    }
    return RELIEF_OK;
}

/* The rectangles of the queries starting at level l, scored (score_rects),
 * each query's `keep` best into its top. */
static relief_status batch_rects(relief_filler *f, query *q, int count, int l, int half,
                                 const float *g, relief_error *err)
{
    int h = half >> l, nr = 0, x0, y0, x1, y1;
    size_t total = 0;
    relief_status st;
    int *rects;
    if (!int_room(&f->rects, &f->rects_cap, (size_t)count * 7) ||
        !int_room(&f->owner, &f->owner_cap, (size_t)count * 2))
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate %d searches", count);
    rects = f->rects;
    for (int k = 0; k < count; ++k) {
        if (!q[k].alive || q[k].start != l)
            continue;
        if (!region(f, l, q[k].px, q[k].py, h, &x0, &y0, &x1, &y1)) {
            q[k].alive = 0; /* no candidate: nothing found */
            continue;
        }
        int *r = rects + 7 * nr;
        r[0] = q[k].px >> l, r[1] = q[k].py >> l, r[2] = x0, r[3] = y0;
        r[4] = x1 - x0 + 1, r[5] = y1 - y0 + 1, r[6] = (int)total;
        total += (size_t)r[4] * (size_t)r[5];
        f->owner[nr++] = k;
    }
    if (!nr)
        return RELIEF_OK;
    for (int j = 0; j < nr; ++j) /* the keeps follow the owners */
        f->owner[nr + j] = q[f->owner[j]].keep;
    st = score_room(f, total, err);
    return st == RELIEF_OK ? score_rects(f, q, rects, nr, total, l, h, g, err) : st;
}

/* A query's refinement list at level l: the positions within REFINE pixels
 * of each kept match's image inside the region, each once, appended to
 * pairs (qx, qy, cx, cy); their number, or -1 when the region is empty. */
static int refine_list(const relief_filler *f, const query *q, int l, int h, int *pairs)
{
    int count = 0, kx0, ky0, kx1, ky1;
    if (!region(f, l, q->px, q->py, h, &kx0, &ky0, &kx1, &ky1))
        return -1;
    for (int i = 0; i < q->n_top; ++i)
        for (int dy = -REFINE; dy <= REFINE; ++dy)
            for (int dx = -REFINE; dx <= REFINE; ++dx) {
                int cx = 2 * q->top[i].x + dx, cy = 2 * q->top[i].y + dy, dup = 0;
                if (cx < kx0 || cx > kx1 || cy < ky0 || cy > ky1)
                    continue;
                /* A position two kept matches share is scored once. */
                for (int j = 0; j < i && !dup; ++j)
                    dup = abs(2 * q->top[j].x - cx) <= REFINE &&
                          abs(2 * q->top[j].y - cy) <= REFINE;
                if (dup)
                    continue;
                pairs[4 * count] = q->px >> l, pairs[4 * count + 1] = q->py >> l;
                pairs[4 * count + 2] = cx, pairs[4 * count + 3] = cy;
                ++count;
            }
    return count;
}

#define REFINE_MAX (RELIEF_FILL_MAX_TOP * (2 * REFINE + 1) * (2 * REFINE + 1))
/* The most scores one batched call holds (each 12 bytes, on the host and
 * on the device): a batch past it runs in parts. */
#define BATCH_SCORES ((size_t)1 << 24)

/* The refinement at level l of the queries that started above it, scored
 * in one call where the scorer batches (else one call per query), each
 * keeping its best `keep` (keep_best at level 0). */
static relief_status batch_refine(relief_filler *f, query *q, int count, int l, int half,
                                  const float *g, int keep_best, relief_error *err)
{
    const relief_patch_ops *ops = f->scorer->ops;
    int h = half >> l, np = 0, *pairs, *first;
    relief_status st = RELIEF_OK;
    double t0;
    if (!int_room(&f->pairs, &f->pairs_cap, (size_t)count * REFINE_MAX * 4) ||
        !int_room(&f->first, &f->first_cap, (size_t)count + 1))
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate %d searches", count);
    pairs = f->pairs, first = f->first;
    for (int k = 0; k < count; ++k) {
        int c = q[k].alive && q[k].start > l ? refine_list(f, &q[k], l, h, pairs + 4 * np) : 0;
        first[k] = np;
        if (c < 0)
            q[k].alive = 0, c = 0;
        np += c;
    }
    first[count] = np;
    if (np && (st = score_room(f, (size_t)np, err)) == RELIEF_OK) {
        t0 = relief_seconds();
        if (ops->score_pairs)
            st = ops->score_pairs(f->scorer->ctx, l, h, max_holes(f, h), g, pairs, np, f->ssd,
                                  g ? f->wsum : NULL, f->n, err);
        else
            for (int k = 0; k < count && st == RELIEF_OK; ++k) {
                /* Scored into the stack and copied: scoring straight into
                 * the filler's score arrays ran 15 % slower (astronaut,
                 * scalar), the same instructions (callgrind). */
                int c = first[k + 1] - first[k], xy[2 * REFINE_MAX], ln[REFINE_MAX];
                float ls[REFINE_MAX], lw[REFINE_MAX];
                for (int i = 0; i < c; ++i)
                    xy[2 * i] = pairs[4 * (first[k] + i) + 2],
                    xy[2 * i + 1] = pairs[4 * (first[k] + i) + 3];
                if (!c)
                    continue;
                st = ops->score_list(f->scorer->ctx, l, q[k].px >> l, q[k].py >> l, h,
                                     max_holes(f, h), g, xy, c, ls, g ? lw : NULL, ln, err);
                memcpy(f->ssd + first[k], ls, (size_t)c * sizeof *ls);
                memcpy(f->n + first[k], ln, (size_t)c * sizeof *ln);
                if (g)
                    memcpy(f->wsum + first[k], lw, (size_t)c * sizeof *lw);
            }
        f->score_seconds += relief_seconds() - t0;
        f->candidates += (size_t)np;
        f->read_back += (size_t)np;
    }
    for (int k = 0; k < count && st == RELIEF_OK; ++k) {
        relief_window_match next[RELIEF_FILL_MAX_TOP];
        int n_next = 0;
        if (!q[k].alive || q[k].start <= l)
            continue;
        for (int i = first[k]; i < first[k + 1]; ++i)
            if (f->n[i] > 0 && (!g || f->wsum[i] > 0.0f))
                offer(next, &n_next, l ? q[k].keep : keep_best,
                      make_match(pairs[4 * i + 2], pairs[4 * i + 3], f->ssd[i], f->n[i],
                                 g ? f->wsum[i] : 0.0f, g != NULL));
        memcpy(q[k].top, next, sizeof(relief_window_match) * n_next);
        q[k].n_top = n_next;
    }
    return st;
}

/* The searches of q[0 .. count) (relief_filler_search_batch), level by
 * level from the coarsest start: each level's rectangles and refinements
 * scored in a call or two for all of them. */
static relief_status search_queries(relief_filler *f, query *q, int count, int w,
                                    int exhaustive, double sigma, int keep_best,
                                    relief_window_match *coarse, int *n_coarse,
                                    relief_error *err)
{
    int half = w / 2, top_level = 0;
    relief_status st = RELIEF_OK;
    for (int k = 0; k < count; ++k) {
        q[k].start = start_level(f, q[k].px, q[k].py, half, exhaustive);
        q[k].keep = q[k].start == 0 ? keep_best : 4 * q[k].start;
        if (q[k].keep > RELIEF_FILL_MAX_TOP)
            q[k].keep = RELIEF_FILL_MAX_TOP;
        q[k].n_top = 0, q[k].alive = 1;
        top_level = q[k].start > top_level ? q[k].start : top_level;
    }
    if (count && f->rep && f->rep->start_level < 0) {
        f->rep->start_level = q[0].start;
        f->rep->top_m = q[0].start ? q[0].keep : 1;
    }
    for (int l = top_level; l >= 0 && st == RELIEF_OK; --l) {
        const float *g = weights(f, l, half >> l, sigma);
        st = batch_rects(f, q, count, l, half, g, err);
        if (st == RELIEF_OK && coarse && n_coarse && q[0].start == l && q[0].alive) {
            /* The first query's kept matches at its start level. */
            for (int i = 0; i < q[0].n_top; ++i) {
                coarse[i] = q[0].top[i];
                coarse[i].x <<= l;
                coarse[i].y <<= l;
            }
            *n_coarse = q[0].n_top;
        }
        if (st == RELIEF_OK && l < top_level)
            st = batch_refine(f, q, count, l, half, g, keep_best, err);
    }
    return st;
}

relief_status relief_filler_search_top(relief_filler *f, int px, int py, int w, int exhaustive,
                                       double sigma, relief_window_match *best, int keep_best,
                                       int *n_best, relief_window_match *coarse, int *n_coarse,
                                       relief_error *err)
{
    query q;
    relief_status st;
    *n_best = 0;
    if (n_coarse)
        *n_coarse = 0;
    if (keep_best < 1 || keep_best > RELIEF_FILL_MAX_TOP)
        return relief_fail(err, RELIEF_E_INTERNAL, "a search keeps 1..%d matches, not %d",
                           RELIEF_FILL_MAX_TOP, keep_best);
    q.px = px, q.py = py;
    st = search_queries(f, &q, 1, w, exhaustive, sigma, keep_best, coarse, n_coarse, err);
    if (st == RELIEF_OK && q.alive) {
        memcpy(best, q.top, sizeof(relief_window_match) * q.n_top);
        *n_best = q.n_top;
    }
    return st;
}

/* The scores of a query's rectangle at its start level. */
static size_t query_scores(const relief_filler *f, const query *q, int w, int exhaustive)
{
    int l = start_level(f, q->px, q->py, w / 2, exhaustive), x0, y0, x1, y1;
    if (!region(f, l, q->px, q->py, (w / 2) >> l, &x0, &y0, &x1, &y1))
        return 0;
    return (size_t)(x1 - x0 + 1) * (size_t)(y1 - y0 + 1);
}

relief_status relief_filler_search_batch(relief_filler *f, int count, const int *pxy, int w,
                                         int exhaustive, double sigma, int keep_best,
                                         relief_window_match *best, int *n_best,
                                         relief_error *err)
{
    query one, *q = &one;
    relief_status st;
    if (keep_best < 1 || keep_best > RELIEF_FILL_MAX_TOP)
        return relief_fail(err, RELIEF_E_INTERNAL, "a search keeps 1..%d matches, not %d",
                           RELIEF_FILL_MAX_TOP, keep_best);
    if (count <= 0)
        return RELIEF_OK;
    if (count > 1 && !(q = malloc((size_t)count * sizeof *q)))
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate %d searches", count);
    for (int k = 0; k < count; ++k)
        q[k].px = pxy[2 * k], q[k].py = pxy[2 * k + 1];
    st = RELIEF_OK;
    if (f->scorer->ops->score_rects)
        /* In runs whose rectangles hold BATCH_SCORES scores at most (an
         * exhaustive search over a whole large image is 10^8 a query). */
        for (int k0 = 0, k1; k0 < count && st == RELIEF_OK; k0 = k1) {
            size_t sum = query_scores(f, &q[k0], w, exhaustive);
            for (k1 = k0 + 1; k1 < count; ++k1) {
                size_t more = query_scores(f, &q[k1], w, exhaustive);
                if (sum + more > BATCH_SCORES)
                    break;
                sum += more;
            }
            st = search_queries(f, q + k0, k1 - k0, w, exhaustive, sigma, keep_best, NULL, NULL,
                                err);
        }
    else /* a query at a time: its scores stay in the cache */
        for (int k = 0; k < count && st == RELIEF_OK; ++k)
            st = search_queries(f, q + k, 1, w, exhaustive, sigma, keep_best, NULL, NULL, err);
    for (int k = 0; k < count; ++k) {
        n_best[k] = st == RELIEF_OK && q[k].alive ? q[k].n_top : 0;
        memcpy(best + (size_t)k * keep_best, q[k].top,
               sizeof(relief_window_match) * (size_t)n_best[k]);
    }
    if (q != &one)
        free(q);
    return st;
}

relief_status relief_filler_put(relief_filler *f, int x, int y, const float *value,
                                relief_error *err)
{
    relief_raster *img = f->img;
    size_t q = (size_t)y * img->width + x;
    for (int c = 0; c < f->C; ++c) {
        f->v[0][q * f->C + c] = value[c];
        img->v[q * img->channels + c] = value[c];
    }
    make_opaque(img, q);
    f->known[0][q] = 1;
    return changed(f, x, y, x, y, err);
}

/* Copy the candidate window at (cx, cy) into the holes of the query window
 * at (px, py) where the candidate is known. */
static relief_status paste(relief_filler *f, int px, int py, int cx, int cy, int half,
                           size_t *filled, relief_error *err)
{
    relief_raster *img = f->img;
    int W = img->width, H = img->height, C = f->C;
    int x0 = px - half < 0 ? 0 : px - half, x1 = px + half >= W ? W - 1 : px + half;
    int y0 = py - half < 0 ? 0 : py - half, y1 = py + half >= H ? H - 1 : py + half;
    size_t count = 0;
    for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
            size_t q = (size_t)y * W + x, s = (size_t)(cy + y - py) * W + (cx + x - px);
            if (f->known[0][q] || !f->known[0][s])
                continue;
            for (int c = 0; c < C; ++c) {
                f->v[0][q * C + c] = f->v[0][s * C + c];
                img->v[q * img->channels + c] = f->v[0][s * C + c];
            }
            make_opaque(img, q);
            f->known[0][q] = 1;
            ++count;
        }
    *filled += count;
    return count ? changed(f, x0, y0, x1, y1, err) : RELIEF_OK;
}

/* The last resort for the hole pixel (px, py): the mean of its known 3 x 3
 * neighbours, or a random one of them when they disagree (a channel's
 * range over tau). */
static relief_status fallback(relief_filler *f, int px, int py, relief_error *err)
{
    relief_raster *img = f->img;
    int W = img->width, H = img->height, C = f->C, m = 0, disagree = 0;
    size_t nb[8], q = (size_t)py * W + px;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            int x = px + dx, y = py + dy;
            if ((dx || dy) && x >= 0 && x < W && y >= 0 && y < H && f->known[0][(size_t)y * W + x])
                nb[m++] = (size_t)y * W + x;
        }
    if (m == 0)
        return RELIEF_OK; /* not on the boundary yet */
    for (int c = 0; c < C && !disagree; ++c) {
        float lo = f->v[0][nb[0] * C + c], hi = lo;
        for (int i = 1; i < m; ++i) {
            float v = f->v[0][nb[i] * C + c];
            lo = v < lo ? v : lo;
            hi = v > hi ? v : hi;
        }
        disagree = hi - lo > f->tau;
    }
    if (disagree) {
        size_t s = nb[relief_rng_below(&f->rng, (uint32_t)m)];
        for (int c = 0; c < C; ++c)
            f->v[0][q * C + c] = f->v[0][s * C + c];
    } else {
        for (int c = 0; c < C; ++c) {
            float sum = 0.0f;
            for (int i = 0; i < m; ++i)
                sum += f->v[0][nb[i] * C + c];
            f->v[0][q * C + c] = sum / (float)m;
        }
    }
    for (int c = 0; c < C; ++c)
        img->v[q * img->channels + c] = f->v[0][q * C + c];
    make_opaque(img, q);
    f->known[0][q] = 1;
    if (f->rep)
        ++f->rep->by_fallback;
    return changed(f, px, py, px, py, err);
}

/* Is some min_window window wholly inside the image at most
 * max_hole_fraction holes? (A summed-area table of the holes.) */
static relief_status check_windows(const relief_raster *img, const uint8_t *hole,
                                   const relief_fill_params *p, relief_error *err)
{
    int W = img->width, H = img->height, s = p->min_window, found = 0;
    int limit = (int)floor(p->max_hole_fraction * s * s + 1e-9);
    uint32_t *sat = calloc((size_t)(W + 1) * (H + 1), sizeof *sat);
    if (!sat)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a hole count table");
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            sat[(size_t)(y + 1) * (W + 1) + x + 1] =
                (hole[(size_t)y * W + x] != 0) + sat[(size_t)y * (W + 1) + x + 1] +
                sat[(size_t)(y + 1) * (W + 1) + x] - sat[(size_t)y * (W + 1) + x];
    for (int y = 0; y + s <= H && !found; ++y)
        for (int x = 0; x + s <= W && !found; ++x) {
            uint32_t c = sat[(size_t)(y + s) * (W + 1) + x + s] - sat[(size_t)y * (W + 1) + x + s] -
                         sat[(size_t)(y + s) * (W + 1) + x] + sat[(size_t)y * (W + 1) + x];
            found = (int)c <= limit && !hole[(size_t)(y + s / 2) * W + x + s / 2];
        }
    free(sat);
    if (!found)
        return relief_fail(err, RELIEF_E_RANGE, "no %d x %d window of the image has at most "
                           "%.0f %% hole pixels: there is nothing to copy from (the hole "
                           "covers too much of the image)", s, s, 100.0 * p->max_hole_fraction);
    return RELIEF_OK;
}

/* The hole pixels with a known 8-neighbour, in raster order, into list;
 * returns their number. */
static size_t boundary(const relief_filler *f, int W, int H, size_t *list)
{
    size_t m = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            int edge = 0;
            if (f->known[0][(size_t)y * W + x])
                continue;
            for (int dy = -1; dy <= 1 && !edge; ++dy)
                for (int dx = -1; dx <= 1 && !edge; ++dx) {
                    int u = x + dx, v = y + dy;
                    edge = u >= 0 && u < W && v >= 0 && v < H && f->known[0][(size_t)v * W + u];
                }
            if (edge)
                list[m++] = (size_t)y * W + x;
        }
    return m;
}

/* The cancelled call's status, at the fraction it was cancelled. */
static relief_status cancelled(const relief_fill_params *p, relief_error *err)
{
    return relief_fail(err, RELIEF_E_CANCELLED, "cancelled by the progress callback at "
                       "%.0f %%", 100.0 * p->progress->last);
}

/* One boundary pixel (px, py): windows from p->window down to min_window
 * until a match under tau is pasted, else the 3 x 3 fallback. *filled
 * counts the pixels filled. */
static relief_status fill_query(relief_filler *f, int px, int py, size_t *filled,
                                relief_error *err)
{
    const relief_fill_params *p = &f->p;
    relief_fill_report *rep = f->rep;
    relief_status st = RELIEF_OK;
    size_t fb = rep->by_fallback;
    ++rep->queries;
    for (int w = p->window; w >= p->min_window && st == RELIEF_OK; w -= 2) {
        relief_window_match best;
        size_t got = 0;
        int found;
        st = relief_filler_search(f, px, py, w, p->exhaustive, &best, &found, NULL, NULL, err);
        ++rep->searches;
        if (st != RELIEF_OK || !found || !(sqrt(best.msd / f->C) < f->tau))
            continue;
        ++rep->accepted;
        st = paste(f, px, py, best.x, best.y, w / 2, &got, err);
        rep->by_copy += got;
        *filled += got;
        return st;
    }
    if (st == RELIEF_OK)
        st = fallback(f, px, py, err);
    *filled += rep->by_fallback - fb;
    return st;
}

/* Copy-paste synthesis until every hole pixel is known: the boundary in
 * raster order, each pixel still a hole queried, the boundary again. */
static relief_status copy_paste(relief_filler *f, size_t holes, size_t filled, size_t *list,
                                relief_error *err)
{
    int W = f->img->width, H = f->img->height;
    relief_status st = RELIEF_OK;
    while (filled < holes && st == RELIEF_OK) {
        size_t m = boundary(f, W, H, list), before = filled;
        for (size_t k = 0; k < m && st == RELIEF_OK; ++k) {
            if (f->known[0][list[k]])
                continue;
            st = fill_query(f, (int)(list[k] % W), (int)(list[k] / W), &filled, err);
            if (st == RELIEF_OK && relief_progress_count(f->p.progress, filled, holes))
                st = cancelled(&f->p, err);
        }
        if (filled == before && st == RELIEF_OK)
            st = relief_fail(err, RELIEF_E_INTERNAL, "the hole filling made no progress with "
                             "%zu pixels left", holes - filled);
    }
    return st;
}

relief_status relief_fill(relief_raster *img, const uint8_t *hole_in, const relief_fill_params *p,
                          relief_patch_scorer *scorer, relief_fill_report *rep,
                          relief_error *err)
{
    size_t n = (size_t)img->width * img->height, holes = 0, *list = NULL;
    uint8_t *hole;
    relief_filler *f = NULL;
    relief_fill_report local;
    relief_status st;
    double t0;

    if (!rep)
        rep = &local;
    memset(rep, 0, sizeof *rep);
    rep->start_level = -1;
    st = relief_fill_params_validate(p, img->width, img->height, err);
    if (st != RELIEF_OK)
        return st;
    for (size_t i = 0; i < n; ++i)
        holes += hole_in[i] != 0;
    rep->hole_pixels = holes;
    relief_fill_thresholds(p, img->bit_depth, &rep->tau, &rep->interp_diff, &rep->interp_sd);
    if (holes == 0)
        return RELIEF_OK;
    if (holes == n)
        return relief_fail(err, RELIEF_E_RANGE, "every pixel of the image is in the hole: "
                           "there is nothing to fill it from");
    st = check_windows(img, hole_in, p, err);
    if (st != RELIEF_OK)
        return st;
    hole = malloc(n);
    list = malloc(n * sizeof *list);
    if (!hole || !list) {
        free(hole);
        free(list);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the hole mask");
    }
    for (size_t i = 0; i < n; ++i)
        hole[i] = hole_in[i] != 0;

    t0 = relief_seconds();
    if (p->interp)
        relief_fill_interp(img, hole, p, &rep->by_rows, &rep->by_columns,
                           rep->interp_roughness);
    rep->seconds_interp = relief_seconds() - t0;
    if (relief_progress_count(p->progress, rep->by_rows + rep->by_columns, holes)) {
        st = cancelled(p, err);
        goto done;
    }

    t0 = relief_seconds();
    st = relief_filler_create(img, hole, p, scorer, &f, err);
    if (st != RELIEF_OK)
        goto done;
    f->rep = rep;
    rep->levels = f->n_levels;
    st = copy_paste(f, holes, rep->by_rows + rep->by_columns, list, err);
    rep->candidates = f->candidates;
    rep->scores_read = f->read_back;
    rep->seconds_score = f->score_seconds;
done:
    rep->seconds_copy = relief_seconds() - t0;
    relief_filler_destroy(f);
    free(hole);
    free(list);
    return st;
}
