/* The host scorer: kernels/patch_math.h's pm_score, its arithmetic in
 * the same order, over a pool of host threads, with the query window
 * gathered once per call instead of read again for each candidate. A
 * rectangle's rows (a list's entries) are dealt out in turn, thread k of
 * n taking rows k, k + n, ...: the rows of a hole, whose refused centres
 * cost nothing, fall to every thread alike. Each candidate's score is
 * computed by one thread from the same values as the scalar reference's,
 * so it has the same bits however many threads run. */
#include "image/patch.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "base/error.h"
#include "base/pool.h"

/* Pixel comparisons per thread below which a call stays on one thread:
 * a hand-over costs some 10 microseconds, about this many pixels. */
#define MIN_PIXELS_PER_THREAD 8192

/* The query window gathered once per call: per offset (row-major, as
 * pm_score walks them) whether the query pixel counts (inside the level
 * and known), its channels and its weight g[|dy|] * g[|dx|] (1 unweighted).
 * pm_score computes the same from the level per candidate. */
typedef struct query {
    int side, channels;
    uint8_t *ok;
    float *v, *wt;
    size_t cap; /* offsets times channels that v and wt hold (ok: as many bytes) */
} query;

typedef struct host_ctx {
    const relief_patch_level *levels;
    int n_levels;
    relief_pool *pool;
    query q;
} host_ctx;

/* One call's arguments, shared by its parts. */
typedef struct job {
    const relief_patch_level *l;
    const query *q;
    int radius, max_holes, weighted;
    int x0, y0, nx;   /* a rectangle: nx per row, rows y0 .. */
    const int *xy;    /* or a list (NULL for a rectangle) */
    size_t count;     /* rows of the rectangle, entries of the list */
    float *ssd, *wsum;
    int *n;
} job;

static relief_status gather_query(query *q, const relief_patch_level *l, int qx, int qy,
                                  int radius, const float *g, relief_error *err)
{
    int side = 2 * radius + 1, C = l->channels;
    size_t m = (size_t)side * side;
    if (m * (size_t)C > q->cap) {
        uint8_t *ok = realloc(q->ok, m * (size_t)C);
        float *v, *wt;
        if (ok)
            q->ok = ok;
        v = realloc(q->v, m * (size_t)C * sizeof *v);
        if (v)
            q->v = v;
        wt = realloc(q->wt, m * (size_t)C * sizeof *wt);
        if (wt)
            q->wt = wt;
        if (!ok || !v || !wt)
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a %d x %d query window",
                               side, side);
        q->cap = m * (size_t)C;
    }
    q->side = side;
    q->channels = C;
    for (int dy = -radius, o = 0; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx, ++o) {
            int x = qx + dx, y = qy + dy;
            size_t at = (size_t)y * l->width + x;
            q->ok[o] = y >= 0 && y < l->height && x >= 0 && x < l->width && l->known[at];
            for (int c = 0; c < C; ++c)
                q->v[(size_t)o * C + c] = q->ok[o] ? l->v[at * C + c] : 0.0f;
            q->wt[o] = g ? g[dy < 0 ? -dy : dy] * g[dx < 0 ? -dx : dx] : 1.0f;
        }
    return RELIEF_OK;
}

/* pm_score of the candidate at (cx, cy) against the gathered query, with
 * the same operations in the same order (the same bits); it stops as soon
 * as the candidate holds more than max_holes holes, which pm_score would
 * refuse at its end. */
static void score_one(const job *j, int cx, int cy, size_t k)
{
    const relief_patch_level *l = j->l;
    const query *q = j->q;
    const int r = j->radius, W = l->width, C = l->channels;
    const uint8_t *known = l->known;
    float s = 0.0f, ws = 0.0f;
    int both = 0, holes = 0, o = 0;
    j->ssd[k] = 0.0f;
    j->n[k] = -1;
    if (j->wsum)
        j->wsum[k] = 0.0f;
    if (!known[(size_t)cy * W + cx])
        return;
    for (int dy = -r; dy <= r; ++dy) {
        size_t row = (size_t)(cy + dy) * W + (size_t)(cx - r);
        for (int i = 0; i < q->side; ++i, ++o) {
            const float *a, *b;
            if (!known[row + i]) {
                if (++holes > j->max_holes)
                    return;
                continue;
            }
            if (!q->ok[o])
                continue;
            a = q->v + (size_t)o * C;
            b = l->v + (row + i) * C;
            if (j->weighted) {
                float wt = q->wt[o];
                for (int c = 0; c < C; ++c) {
                    float d = a[c] - b[c];
                    s = s + wt * (d * d);
                }
                ws = ws + wt;
            } else {
                for (int c = 0; c < C; ++c) {
                    float d = a[c] - b[c];
                    s = s + d * d;
                }
                ws = ws + 1.0f;
            }
            ++both;
        }
    }
    if (both == 0)
        return;
    j->ssd[k] = s;
    j->n[k] = both;
    if (j->wsum)
        j->wsum[k] = ws;
}

/* LANES candidates scored in lock-step: each lane's sums take the same
 * operations in the same order as score_one's (a pixel a lane skips
 * leaves its sums as they were), so each has score_one's bits, while the
 * lanes' independent sums keep the processor's adders busy (one
 * candidate's running sum is a chain of dependent additions). */
#define LANES 8
typedef float lanes_f __attribute__((vector_size(LANES * sizeof(float))));
typedef int32_t lanes_i __attribute__((vector_size(LANES * sizeof(int32_t))));

/* Where mask (-1 or 0 per lane) is set, a; elsewhere b: bits, not
 * arithmetic. */
static inline lanes_f pick(lanes_i mask, lanes_f a, lanes_f b)
{
    return (lanes_f)(((lanes_i)a & mask) | ((lanes_i)b & ~mask));
}

/* Lane t's window has its top-left pixel at at[t] (row: at[0] + t when
 * `row` is set, the lanes side by side on a rectangle's row); its scores
 * go to k + t. C is a constant where the callers below make it one. */
static inline __attribute__((always_inline)) void
score_lanes_c(const job *j, const size_t *at, size_t k, const int C, const int row)
{
    const relief_patch_level *l = j->l;
    const query *q = j->q;
    const int r = j->radius, W = l->width;
    const uint8_t *known = l->known;
    lanes_f s = {0}, ws = {0};
    lanes_i both = {0}, holes = {0};
    int o = 0;
    for (int dy = 0; dy < q->side; ++dy)
        for (int dx = 0; dx < q->side; ++dx, ++o) {
            const size_t off = (size_t)dy * W + (size_t)dx;
            /* Unweighted, wt is 1 and wt * (d * d) is d * d exactly. */
            const float wt = q->wt[o];
            lanes_i in; /* -1 where the candidate's pixel is known */
            for (int t = 0; t < LANES; ++t)
                in[t] = known[(row ? at[0] + (size_t)t : at[t]) + off] ? -1 : 0;
            holes -= in == 0; /* a comparison is -1 where true */
            if (!q->ok[o])
                continue;
            for (int c = 0; c < C; ++c) {
                lanes_f bv, d;
                for (int t = 0; t < LANES; ++t)
                    bv[t] = l->v[((row ? at[0] + (size_t)t : at[t]) + off) * C + c];
                d = q->v[(size_t)o * C + c] - bv;
                s = pick(in, s + wt * (d * d), s);
            }
            ws = pick(in, ws + wt, ws);
            both -= in;
        }
    for (int t = 0; t < LANES; ++t) {
        size_t centre = (row ? at[0] + (size_t)t : at[t]) + (size_t)r * W + (size_t)r;
        int ok = known[centre] && holes[t] <= j->max_holes && both[t] > 0;
        j->ssd[k + t] = ok ? s[t] : 0.0f;
        j->n[k + t] = ok ? both[t] : -1;
        if (j->wsum)
            j->wsum[k + t] = ok ? ws[t] : 0.0f;
    }
}

/* score_lanes_c with the channel count a constant: one channel (depth,
 * grey) and three (colour) have loops of their own. Built twice on x86-64
 * with GCC, for AVX2 (the 8 lanes in one register) and for the baseline,
 * the loader picking one for the processor: the same operations either
 * way (no contraction, no fused multiply-add), so the same bits. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
__attribute__((target_clones("avx2", "default")))
#endif
static void score_lanes(const job *j, const size_t *at, size_t k, int row)
{
    switch (j->l->channels) {
    case 1:
        if (row)
            score_lanes_c(j, at, k, 1, 1);
        else
            score_lanes_c(j, at, k, 1, 0);
        break;
    case 3:
        if (row)
            score_lanes_c(j, at, k, 3, 1);
        else
            score_lanes_c(j, at, k, 3, 0);
        break;
    default:
        score_lanes_c(j, at, k, j->l->channels, 0);
    }
}

/* Lanes of the rectangle's row y from x (its candidates x .. x + LANES - 1). */
static void row_lanes(const job *j, int x, int y, size_t k)
{
    size_t at[LANES];
    at[0] = (size_t)(y - j->radius) * j->l->width + (size_t)(x - j->radius);
    for (int t = 1; t < LANES; ++t)
        at[t] = at[0] + (size_t)t;
    score_lanes(j, at, k, 1);
}

/* Lanes of the list's entries e .. e + LANES - 1. */
static void list_lanes(const job *j, size_t e)
{
    size_t at[LANES];
    for (int t = 0; t < LANES; ++t)
        at[t] = (size_t)(j->xy[2 * (e + t) + 1] - j->radius) * j->l->width +
                (size_t)(j->xy[2 * (e + t)] - j->radius);
    score_lanes(j, at, e, 0);
}

/* Part `part` of `parts`: rectangle rows part, part + parts, ... (each
 * row's last few candidates as the row's last LANES again, the same
 * scores); list blocks of LANES entries alike, the list's last few (fewer
 * than LANES) one by one on the last part. */
static void run_part(void *ctx, int part, int parts)
{
    const job *j = ctx;
    if (j->xy) {
        size_t blocks = j->count / LANES;
        for (size_t b = (size_t)part; b < blocks; b += (size_t)parts)
            list_lanes(j, b * LANES);
        if (part == parts - 1)
            for (size_t e = blocks * LANES; e < j->count; ++e)
                score_one(j, j->xy[2 * e], j->xy[2 * e + 1], e);
        return;
    }
    for (size_t r = (size_t)part; r < j->count; r += (size_t)parts) {
        int y = j->y0 + (int)r, i = 0;
        size_t k = r * (size_t)j->nx;
        for (; i + LANES <= j->nx; i += LANES)
            row_lanes(j, j->x0 + i, y, k + (size_t)i);
        if (i < j->nx && j->nx >= LANES)
            row_lanes(j, j->x0 + j->nx - LANES, y, k + (size_t)(j->nx - LANES));
        else
            for (; i < j->nx; ++i)
                score_one(j, j->x0 + i, y, k + (size_t)i);
    }
}

/* Gather the query, then score on as many threads as the call's size pays
 * for. */
static relief_status run_job(host_ctx *h, job *j, int qx, int qy, const float *g,
                             size_t candidates, relief_error *err)
{
    size_t side = 2 * (size_t)j->radius + 1;
    size_t parts = candidates * side * side / MIN_PIXELS_PER_THREAD;
    relief_status st = gather_query(&h->q, j->l, qx, qy, j->radius, g, err);
    if (st != RELIEF_OK)
        return st;
    if (parts > (j->xy ? j->count / LANES + 1 : j->count))
        parts = j->xy ? j->count / LANES + 1 : j->count;
    relief_pool_run(h->pool, parts > RELIEF_POOL_MAX ? RELIEF_POOL_MAX : (int)parts, run_part,
                    j);
    return RELIEF_OK;
}

static relief_status host_bind(void *ctx, const relief_patch_level *levels, int n_levels,
                               relief_error *err)
{
    host_ctx *h = ctx;
    (void)err;
    h->levels = levels;
    h->n_levels = n_levels;
    return RELIEF_OK;
}

static relief_status host_update(void *ctx, int level, int y0, int y1, relief_error *err)
{
    (void)ctx, (void)level, (void)y0, (void)y1, (void)err;
    return RELIEF_OK; /* it reads the filler's own arrays */
}

static relief_status host_score_rect(void *ctx, int level, int qx, int qy, int radius,
                                     int max_holes, const float *g, int x0, int y0, int nx,
                                     int ny, float *ssd, float *wsum, int *n, relief_error *err)
{
    host_ctx *h = ctx;
    job j = {&h->levels[level], &h->q, radius, max_holes, g != NULL, x0, y0, nx, NULL,
             (size_t)ny, ssd, wsum, n};
    return run_job(h, &j, qx, qy, g, (size_t)nx * (size_t)ny, err);
}

static relief_status host_score_list(void *ctx, int level, int qx, int qy, int radius,
                                     int max_holes, const float *g, const int *xy, int count,
                                     float *ssd, float *wsum, int *n, relief_error *err)
{
    host_ctx *h = ctx;
    job j = {&h->levels[level], &h->q, radius, max_holes, g != NULL, 0, 0, 0, xy,
             count > 0 ? (size_t)count : 0, ssd, wsum, n};
    return run_job(h, &j, qx, qy, g, j.count, err);
}

static void host_destroy(void *ctx)
{
    host_ctx *h = ctx;
    if (h) {
        relief_pool_destroy(h->pool);
        free(h->q.ok);
        free(h->q.v);
        free(h->q.wt);
    }
    free(h);
}

static const relief_patch_ops host_ops = {host_bind, host_update, host_score_rect,
                                          host_score_list, host_destroy, NULL, NULL, NULL};

relief_status relief_patch_host_create(int threads, relief_patch_scorer **out,
                                       relief_error *err)
{
    relief_patch_scorer *s;
    host_ctx *h;
    relief_status st;
    if (threads <= 0)
        threads = relief_pool_default_threads();
    if (threads > RELIEF_POOL_MAX)
        threads = RELIEF_POOL_MAX;
    s = calloc(1, sizeof *s);
    h = calloc(1, sizeof *h);
    if (!s || !h) {
        free(s);
        free(h);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the host scorer");
    }
    st = relief_pool_create(threads, &h->pool, err);
    if (st != RELIEF_OK) {
        free(s);
        free(h);
        return st;
    }
    s->ops = &host_ops;
    s->ctx = h;
    s->backend = RELIEF_BACKEND_HOST;
    s->threads = threads;
    snprintf(s->device, sizeof s->device, "host (%d thread%s)", threads, threads == 1 ? "" : "s");
    *out = s;
    return RELIEF_OK;
}
