#include "image/pixel_synth.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "base/clock.h"
#include "base/error.h"
#include "base/rng.h"
#include "image/fill.h"

/* Matches kept per search for the near-minimum draw. */
#define NEAR_KEEP 8
/* Pixels taken ahead of their copies, and the largest wave (batch). */
#define BATCH RELIEF_PIXSYN_MAX_BATCH

relief_pixsyn_params relief_pixsyn_params_default(void)
{
    relief_pixsyn_params p;
    memset(&p, 0, sizeof p);
    p.window = 9;
    p.sigma = 0.0;
    p.epsilon = 0.1;
    p.search_radius = 32;
    p.exhaustive = 0;
    p.max_hole_fraction = 0.1;
    p.order = RELIEF_ORDER_BOTH;
    p.seed = 1;
    p.batch = 1;
    return p;
}

/* The engine's parameters for these. */
static relief_fill_params engine_params(const relief_pixsyn_params *p)
{
    relief_fill_params f = relief_fill_params_default();
    f.window = p->window;
    f.min_window = p->window;
    f.search_radius = p->search_radius;
    f.exhaustive = p->exhaustive;
    f.max_hole_fraction = p->max_hole_fraction;
    f.interp = 0;
    f.seed = p->seed;
    /* One search per pixel, not per window: the pyramid starts coarser
     * than paper 004's 4096 candidates, once the region holds 1024 (a
     * 33 x 33 region or larger, the default 65 x 65 always). */
    f.region_pixels = 1024;
    return f;
}

relief_status relief_pixsyn_params_validate(const relief_pixsyn_params *p, int width, int height,
                                           relief_error *err)
{
    relief_fill_params f = engine_params(p);
    if (!isfinite(p->sigma) || p->sigma > 1e6 || (p->sigma > 0.0 && p->sigma < 0.5))
        return relief_fail(err, RELIEF_E_RANGE, "sigma %g out of range: expected 0.5..1e6 "
                           "pixels (the nearest neighbours' weights vanish below; <= 0: "
                           "window / 6.4)",
                           p->sigma);
    if (!(p->epsilon >= 0.0 && p->epsilon <= 10.0))
        return relief_fail(err, RELIEF_E_RANGE, "epsilon %g out of range: expected 0..10",
                           p->epsilon);
    if (p->batch < 1 || p->batch > BATCH)
        return relief_fail(err, RELIEF_E_RANGE, "batch %d out of range: expected 1..%d",
                           p->batch, BATCH);
    if (p->batch > 1 && p->tileable)
        return relief_fail(err, RELIEF_E_RANGE, "batch %d with tileable: a tileable image is "
                           "filled a pixel at a time (its copies land across the borders); "
                           "give batch 1", p->batch);
    if (p->order != RELIEF_ORDER_BOTH && p->order != RELIEF_ORDER_HORIZONTAL &&
        p->order != RELIEF_ORDER_VERTICAL)
        return relief_fail(err, RELIEF_E_RANGE, "order %d is not one of both, horizontal, vertical",
                           (int)p->order);
    return relief_fill_params_validate(&f, width, height, err);
}

/* ---------------------------------------------------------------- the queue */

/* A max-heap of missing pixels by known-neighbour count, then by the
 * order's raster key (smaller first). Entries go stale when a pixel's count
 * grows (a fresh one is pushed) or it is filled; stale ones are skipped. */
typedef struct entry {
    int count;
    uint32_t key, pixel;
} entry;

typedef struct heap {
    entry *e;
    size_t n, cap;
} heap;

static int above(const entry *a, const entry *b)
{
    return a->count != b->count ? a->count > b->count : a->key < b->key;
}

static int heap_push(heap *h, entry x)
{
    size_t i;
    if (h->n == h->cap) {
        size_t cap = h->cap ? 2 * h->cap : 1024;
        entry *e = realloc(h->e, cap * sizeof *e);
        if (!e)
            return 0;
        h->e = e;
        h->cap = cap;
    }
    i = h->n++;
    while (i > 0 && above(&x, &h->e[(i - 1) / 2])) {
        h->e[i] = h->e[(i - 1) / 2];
        i = (i - 1) / 2;
    }
    h->e[i] = x;
    return 1;
}

static entry heap_pop(heap *h)
{
    entry top = h->e[0], last = h->e[--h->n];
    size_t i = 0;
    for (;;) {
        size_t c = 2 * i + 1;
        if (c >= h->n)
            break;
        if (c + 1 < h->n && above(&h->e[c + 1], &h->e[c]))
            ++c;
        if (!above(&h->e[c], &last))
            break;
        h->e[i] = h->e[c];
        i = c;
    }
    if (h->n)
        h->e[i] = last;
    return top;
}

/* ---------------------------------------------------------------- one order */

typedef struct run {
    size_t synthesised, fallbacks, unreached, candidates;
    double energy; /* sum of the copies' weighted distances */
    double seconds_score;
    int levels;
} run;

/* Both orders' progress: when they run side by side only the caller's
 * thread calls p->progress, and a cancel there stops the other order. */
typedef struct progress_state {
    const relief_pixsyn_params *p;
    atomic_size_t done;
    size_t total;
    atomic_int stop;
} progress_state;

/* The mean of the known 8-neighbours of (x, y) into value (C channels). */
static void neighbour_mean(const relief_raster *img, const uint8_t *known, int C, int x, int y,
                           float *value)
{
    int W = img->width, H = img->height, m = 0;
    for (int c = 0; c < C; ++c)
        value[c] = 0.0f;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            int u = x + dx, v = y + dy;
            size_t j;
            if ((!dx && !dy) || u < 0 || u >= W || v < 0 || v >= H)
                continue;
            j = (size_t)v * W + u;
            if (!known[j])
                continue;
            for (int c = 0; c < C; ++c)
                value[c] += img->v[j * img->channels + c];
            ++m;
        }
    for (int c = 0; c < C; ++c)
        value[c] = m ? value[c] / (float)m : 0.0f;
}

/* One more pixel done: the progress told (reporter) or a cancel seen. */
static relief_status step_done(progress_state *prog, int reporter, relief_error *err)
{
    const relief_pixsyn_params *p = prog->p;
    size_t done = atomic_fetch_add(&prog->done, 1) + 1;
    if (reporter && p->progress && p->progress(p->progress_ctx, done, prog->total)) {
        atomic_store(&prog->stop, 1);
        return relief_fail(err, RELIEF_E_CANCELLED, "cancelled by the progress callback "
                           "after %zu of %zu pixels", done, prog->total);
    }
    if (!reporter && atomic_load_explicit(&prog->stop, memory_order_relaxed))
        return relief_fail(err, RELIEF_E_CANCELLED, "cancelled");
    return RELIEF_OK;
}

/* ------------------------------------------------------- one order, batched
 *
 * The order of the pixels depends only on which are filled, never on the
 * values: a pixel's turn is fixed once the pixels before it are taken. So
 * the queue is run ahead of the copies: up to BATCH pixels are taken in
 * their turn (pending), and those that no pending pixel before them can
 * reach (relief_filler_reach: the search region, the window and the
 * pyramid) are searched together, one scorer call per pyramid level for
 * all of them. Then the pending pixels are copied in their turn, each
 * drawing from the generator as the serial loop did, as far as the first
 * one not yet searched. A search is made only once every pixel that can
 * change it is copied, and nothing before its turn within its reach is
 * copied after it, so every pixel gets the serial run's matches and
 * draw: the same bits, with a device launch per batch and level instead
 * of per pixel. */

typedef struct pending {
    uint32_t pixel;
    int searched, n_best;
    relief_window_match best[NEAR_KEEP];
} pending;

typedef struct order_state {
    relief_raster *img;
    const uint8_t *hole, *target;
    const relief_pixsyn_params *p;
    relief_pixsyn_order order;
    int W, H, C, wrap, W0, H0, reach, cap;
    int wave;         /* 0: the order's own; else waves of up to this many (p->batch) */
    int *cover;       /* a wave's pass: the pixels inside an earlier pending pixel's
                         window hold its generation */
    double sigma;
    uint8_t *known;   /* copied (or known from the start): what the copies read */
    uint8_t *ordered; /* taken by the queue (known, pending or copied) */
    uint8_t *count;   /* each pixel's ordered 8-neighbours */
    heap h;
    relief_filler *f;
    relief_rng rng;
    int64_t *source;
    run *out;
    pending *pend;    /* cap, in their turn */
    int np;
    int *stamp, gw, gh, gen; /* the readiness pass's cells (reach wide) */
    int *pxy, *ready;
    relief_window_match *best; /* BATCH x NEAR_KEEP: a batch's matches */
    int *n_best;               /* BATCH */
} order_state;

static uint32_t order_key(const order_state *s, int x, int y)
{
    return s->order == RELIEF_ORDER_VERTICAL ? (uint32_t)x * (uint32_t)s->H + (uint32_t)y
                                             : (uint32_t)y * (uint32_t)s->W + (uint32_t)x;
}

/* Pixel (X, Y) taken: its unordered target neighbours count one more. */
static int take_pixel(order_state *s, int X, int Y)
{
    s->ordered[(size_t)Y * s->W + X] = 1;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            int u = X + dx, v = Y + dy;
            size_t j;
            if ((!dx && !dy) || u < 0 || u >= s->W || v < 0 || v >= s->H)
                continue;
            j = (size_t)v * s->W + u;
            if (s->ordered[j] || (s->target && !s->target[j]))
                continue;
            ++s->count[j];
            if (!heap_push(&s->h, (entry){s->count[j], order_key(s, u, v), (uint32_t)j}))
                return 0;
        }
    return 1;
}

/* The queue's initial counts over the known pixels. 0 when out of memory. */
static int queue_start(order_state *s)
{
    for (int y = 0; y < s->H; ++y)
        for (int x = 0; x < s->W; ++x) {
            size_t i = (size_t)y * s->W + x;
            int m = 0;
            if (s->ordered[i] || (s->target && !s->target[i]))
                continue;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    int u = x + dx, v = y + dy;
                    m += (dx || dy) && u >= 0 && u < s->W && v >= 0 && v < s->H &&
                         s->ordered[(size_t)v * s->W + u];
                }
            s->count[i] = (uint8_t)m;
            if (m && !heap_push(&s->h, (entry){m, order_key(s, x, y), (uint32_t)i}))
                return 0;
        }
    return 1;
}

/* Pending filled up to cap from the queue, each pixel (and its copies in a
 * tileable image's padding) taken in its turn. 0 when out of memory. */
static int take_turns(order_state *s)
{
    while (s->np < s->cap && s->h.n) {
        entry e = heap_pop(&s->h);
        int x = (int)(e.pixel % (uint32_t)s->W), y = (int)(e.pixel / (uint32_t)s->W);
        if (s->ordered[e.pixel] || e.count != s->count[e.pixel])
            continue; /* taken already, or a stale count */
        s->pend[s->np++] = (pending){e.pixel, 0, 0, {{0}}};
        for (int ky = s->wrap ? -1 : 0; ky <= (s->wrap ? 1 : 0); ++ky)
            for (int kx = s->wrap ? -1 : 0; kx <= (s->wrap ? 1 : 0); ++kx) {
                int X = x + kx * s->W0, Y = y + ky * s->H0;
                if (X < 0 || X >= s->W || Y < 0 || Y >= s->H || s->ordered[(size_t)Y * s->W + X])
                    continue;
                if (!take_pixel(s, X, Y))
                    return 0;
            }
    }
    return 1;
}

/* The pending pixel i as a query of the batch (ready[nr], pxy). */
static void add_query(order_state *s, int i, int nr)
{
    s->ready[nr] = i;
    s->pxy[2 * nr] = (int)(s->pend[i].pixel % (uint32_t)s->W);
    s->pxy[2 * nr + 1] = (int)(s->pend[i].pixel / (uint32_t)s->W);
}

/* The order's own batch: the pending pixels no pending pixel before them
 * can reach (cells `reach` wide: a pixel in the 3 x 3 cells about an
 * earlier one waits, which is never nearer than reach). */
static int select_reach(order_state *s)
{
    int nr = 0;
    ++s->gen;
    for (int i = 0; i < s->np; ++i) {
        int x = (int)(s->pend[i].pixel % (uint32_t)s->W) / s->reach;
        int y = (int)(s->pend[i].pixel / (uint32_t)s->W) / s->reach, blocked = 0;
        for (int v = y - 1; v <= y + 1 && !blocked; ++v)
            for (int u = x - 1; u <= x + 1 && !blocked; ++u)
                blocked = u >= 0 && u < s->gw && v >= 0 && v < s->gh &&
                          s->stamp[(size_t)v * s->gw + u] == s->gen;
        if (!blocked && !s->pend[i].searched)
            add_query(s, i, nr++);
        s->stamp[(size_t)y * s->gw + x] = s->gen;
    }
    return nr;
}

/* A wave (p->batch): up to `wave` pending pixels, in their turn, none
 * inside the window of a pending pixel before it. */
static int select_wave(order_state *s)
{
    const int half = s->p->window / 2;
    int nr = 0;
    ++s->gen;
    for (int i = 0; i < s->np && nr < s->wave; ++i) {
        int x = (int)(s->pend[i].pixel % (uint32_t)s->W), y = (int)(s->pend[i].pixel / (uint32_t)s->W);
        if (s->cover[s->pend[i].pixel] != s->gen)
            add_query(s, i, nr++);
        for (int v = y - half; v <= y + half; ++v)
            for (int u = x - half; u <= x + half; ++u)
                if (u >= 0 && u < s->W && v >= 0 && v < s->H)
                    s->cover[(size_t)v * s->W + u] = s->gen;
    }
    return nr;
}

/* The batch's searches, together: one scorer call per pyramid level. */
static relief_status search_ready(order_state *s, relief_error *err)
{
    int nr = s->wave ? select_wave(s) : select_reach(s);
    relief_status st = relief_filler_search_batch(s->f, nr, s->pxy, s->p->window,
                                                  s->p->exhaustive, s->sigma, NEAR_KEEP,
                                                  s->best, s->n_best, err);
    for (int k = 0; k < nr && st == RELIEF_OK; ++k) {
        pending *q = &s->pend[s->ready[k]];
        q->searched = 1;
        q->n_best = s->n_best[k];
        memcpy(q->best, s->best + (size_t)k * NEAR_KEEP,
               sizeof(relief_window_match) * (size_t)q->n_best);
    }
    return st;
}

/* Pending pixel q copied in its turn: the near-minimum draw among its
 * matches (else its known neighbours' mean), into the pixel and its
 * copies in the padding. */
static relief_status copy_pixel(order_state *s, const pending *q, relief_error *err)
{
    int x = (int)(q->pixel % (uint32_t)s->W), y = (int)(q->pixel / (uint32_t)s->W);
    float value[4];
    relief_status st = RELIEF_OK;
    if (q->n_best > 0) {
        double limit = q->best[0].msd * (1.0 + s->p->epsilon);
        int near = 1, pick;
        size_t from;
        while (near < q->n_best && q->best[near].msd <= limit)
            ++near;
        pick = near > 1 ? (int)relief_rng_below(&s->rng, (uint32_t)near) : 0;
        from = (size_t)q->best[pick].y * s->W + q->best[pick].x;
        for (int c = 0; c < s->C; ++c)
            value[c] = s->img->v[from * s->C + c];
        s->out->energy += q->best[pick].msd;
        ++s->out->synthesised;
        /* The copy's origin: `from` itself when it was known from the
         * start, else where its own value came from (resolved when it was
         * filled), so the map always ends on a captured pixel. */
        if (s->source)
            s->source[q->pixel] = s->hole[from] ? s->source[from] : (int64_t)from;
    } else {
        neighbour_mean(s->img, s->known, s->C, x, y, value);
        ++s->out->fallbacks;
    }
    for (int ky = s->wrap ? -1 : 0; ky <= (s->wrap ? 1 : 0) && st == RELIEF_OK; ++ky)
        for (int kx = s->wrap ? -1 : 0; kx <= (s->wrap ? 1 : 0) && st == RELIEF_OK; ++kx) {
            int X = x + kx * s->W0, Y = y + ky * s->H0;
            size_t at;
            if (X < 0 || X >= s->W || Y < 0 || Y >= s->H)
                continue;
            at = (size_t)Y * s->W + X;
            if (s->known[at])
                continue;
            st = relief_filler_put(s->f, X, Y, value, err);
            s->known[at] = 1;
        }
    return st;
}

/* The searched pending pixels copied in their turn: those at the front
 * (the order's own batches: a later one waits for its turn), or all of
 * them (a wave); the rest keep their order. */
static relief_status copy_front(order_state *s, progress_state *prog, int reporter,
                                relief_error *err)
{
    int kept = 0, front = 1;
    relief_status st = RELIEF_OK;
    for (int i = 0; i < s->np; ++i) {
        front = front && s->pend[i].searched;
        if (st == RELIEF_OK && s->pend[i].searched && (front || s->wave)) {
            st = copy_pixel(s, &s->pend[i], err);
            st = st == RELIEF_OK ? step_done(prog, reporter, err) : st;
            continue;
        }
        s->pend[kept++] = s->pend[i];
    }
    s->np = kept;
    return st;
}

static void order_free(order_state *s)
{
    relief_filler_destroy(s->f);
    free(s->h.e), free(s->known), free(s->ordered), free(s->count);
    free(s->pend), free(s->stamp), free(s->pxy), free(s->ready), free(s->cover);
    free(s->best), free(s->n_best);
}

/* The state of one order over img; RELIEF_E_NOMEM. */
static relief_status order_init(order_state *s, relief_error *err)
{
    size_t n = (size_t)s->W * s->H;
    s->known = malloc(n), s->ordered = malloc(n), s->count = malloc(n);
    s->pend = malloc(BATCH * sizeof *s->pend);
    s->pxy = malloc(2 * BATCH * sizeof *s->pxy), s->ready = malloc(BATCH * sizeof *s->ready);
    s->best = malloc(BATCH * NEAR_KEEP * sizeof *s->best);
    s->n_best = malloc(BATCH * sizeof *s->n_best);
    if (!s->known || !s->ordered || !s->count || !s->pend || !s->pxy || !s->ready || !s->best ||
        !s->n_best)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the synthesis masks");
    for (size_t i = 0; i < n; ++i) {
        s->known[i] = s->ordered[i] = !s->hole[i];
        if (s->source)
            s->source[i] = -1;
    }
    if (!queue_start(s))
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the synthesis queue");
    return RELIEF_OK;
}

/* The readiness cells, once the filler knows its reach. A scorer that
 * does not batch (the host's: a query's scores stay in its cache), a
 * tileable image (whose copies land across it) or a search over the
 * whole image takes one pixel at a time: the serial loop. */
static relief_status batch_init(order_state *s, int batched, relief_error *err)
{
    s->reach = relief_filler_reach(s->f, s->p->window);
    s->cap = !batched || s->wrap || s->reach >= s->W || s->reach >= s->H ? 1 : BATCH;
    if (s->reach < 1)
        s->reach = 1;
    if (s->p->batch > 1 && !s->wrap) { /* tileable with a batch: refused (validate) */
        s->wave = s->p->batch, s->cap = BATCH;
        s->cover = calloc((size_t)s->W * s->H, sizeof *s->cover);
        if (!s->cover)
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the synthesis waves");
    }
    s->gw = s->W / s->reach + 1, s->gh = s->H / s->reach + 1;
    s->stamp = calloc((size_t)s->gw * s->gh, sizeof *s->stamp);
    if (!s->stamp)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the synthesis queue");
    return RELIEF_OK;
}

/* One order. wrap > 0: img is a tileable image padded by `wrap` pixels
 * on every side with copies of the opposite side (its targets central
 * only); a filled pixel's copies are filled with it. */
static relief_status synth_order(relief_raster *img, const uint8_t *hole,
                                 const uint8_t *target, const relief_pixsyn_params *p,
                                 relief_pixsyn_order order, int wrap,
                                 relief_patch_scorer *scorer, int64_t *source, run *out,
                                 progress_state *prog, int reporter, relief_error *err)
{
    order_state s = {0};
    relief_fill_params fp = engine_params(p);
    relief_status st;

    memset(out, 0, sizeof *out);
    s.img = img, s.hole = hole, s.target = target, s.p = p, s.order = order;
    s.W = img->width, s.H = img->height, s.C = img->channels, s.wrap = wrap;
    s.W0 = s.W - 2 * wrap, s.H0 = s.H - 2 * wrap;
    s.sigma = p->sigma > 0.0 ? p->sigma : p->window / 6.4;
    s.source = source, s.out = out;
    relief_rng_seed(&s.rng, p->seed);
    st = order_init(&s, err);
    if (st == RELIEF_OK)
        st = relief_filler_create(img, hole, &fp, scorer, &s.f, err);
    if (st == RELIEF_OK)
        st = batch_init(&s, scorer->ops->score_rects != NULL, err);
    while (st == RELIEF_OK) {
        if (!take_turns(&s)) {
            st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the synthesis queue");
            break;
        }
        if (!s.np)
            break;
        st = search_ready(&s, err);
        if (st == RELIEF_OK)
            st = copy_front(&s, prog, reporter, err);
    }
    /* Targets the queue never reached: cut off from every known pixel by
     * holes that are not targets. They keep their values, counted. */
    for (size_t i = 0; i < (size_t)s.W * s.H && st == RELIEF_OK; ++i)
        out->unreached += !s.known[i] && (!target || target[i]);
    if (s.f) {
        out->levels = relief_filler_levels(s.f);
        out->candidates = relief_filler_candidates(s.f, &out->seconds_score);
    }
    order_free(&s);
    return st;
}

/* One order's call, for a thread of its own. */
typedef struct order_job {
    relief_raster *img;
    const uint8_t *hole, *target;
    const relief_pixsyn_params *p;
    relief_pixsyn_order order;
    int wrap;
    relief_patch_scorer *scorer;
    int64_t *source;
    run *out;
    progress_state *prog;
    relief_status st;
    relief_error err;
    atomic_int finished;
} order_job;

static void *order_thread(void *arg)
{
    order_job *j = arg;
    j->st = synth_order(j->img, j->hole, j->target, j->p, j->order, j->wrap, j->scorer,
                        j->source, j->out, j->prog, 0, &j->err);
    atomic_store(&j->finished, 1);
    return NULL;
}

/* The second order's run on its thread, the first's on this one, each on
 * half the host scorer's threads (the orders share nothing but the
 * progress, and each draws from its own generator: the serial run's
 * bits). While the second runs on after the first, its progress is told
 * from here. RELIEF_E_NOMEM when no thread starts (*ran 0: run them one
 * after the other). */
static relief_status orders_side_by_side(order_job *a, order_job *b, int threads, int *ran,
                                         relief_error *err)
{
    relief_patch_scorer *sa = NULL, *sb = NULL;
    const relief_pixsyn_params *p = a->p;
    pthread_t th;
    relief_status st;
    *ran = 0;
    st = relief_patch_host_create(threads - threads / 2, &sa, err);
    if (st == RELIEF_OK)
        st = relief_patch_host_create(threads / 2, &sb, err);
    b->scorer = sb;
    atomic_init(&b->finished, 0);
    if (st != RELIEF_OK || pthread_create(&th, NULL, order_thread, b) != 0) {
        relief_patch_scorer_destroy(sa);
        relief_patch_scorer_destroy(sb);
        return RELIEF_OK;
    }
    *ran = 1;
    st = synth_order(a->img, a->hole, a->target, p, a->order, a->wrap, sa, a->source, a->out,
                     a->prog, 1, err);
    if (st != RELIEF_OK)
        atomic_store(&a->prog->stop, 1);
    while (!atomic_load(&b->finished)) {
        struct timespec pause = {0, 20000000L};
        size_t done = atomic_load(&a->prog->done);
        nanosleep(&pause, NULL);
        if (st == RELIEF_OK && p->progress &&
            p->progress(p->progress_ctx, done, a->prog->total)) {
            atomic_store(&a->prog->stop, 1);
            st = relief_fail(err, RELIEF_E_CANCELLED, "cancelled by the progress callback "
                             "after %zu of %zu pixels", done, a->prog->total);
        }
    }
    pthread_join(th, NULL);
    if (st == RELIEF_OK && b->st != RELIEF_OK) {
        st = b->st;
        *err = b->err;
    }
    relief_patch_scorer_destroy(sa);
    relief_patch_scorer_destroy(sb);
    return st;
}

/* The hole pixels to fill in *targets (those target marks, all when
 * target is NULL; hole, target: one byte a pixel of img); RELIEF_E_RANGE
 * when there are some and no pixel is known to fill them from. */
static relief_status count_targets(const relief_raster *img, const uint8_t *hole,
                                   const uint8_t *target, size_t *targets, relief_error *err)
{
    size_t n = (size_t)img->width * img->height, holes = 0, t = 0;
    for (size_t i = 0; i < n; ++i) {
        holes += hole[i] != 0;
        t += hole[i] && (!target || target[i]);
    }
    *targets = t;
    if (t == 0)
        return RELIEF_OK;
    if (holes == n)
        return relief_fail(err, RELIEF_E_RANGE, "every pixel is missing: there is nothing to "
                           "synthesise from");
    return RELIEF_OK;
}

/* The second order's copy of img in *other, and an uninitialised source
 * map for it (one int64_t a pixel) when with_source; nothing left
 * allocated on failure. */
static relief_status order_copy(const relief_raster *img, int with_source, relief_raster *other,
                                int64_t **other_source, relief_error *err)
{
    size_t n = (size_t)img->width * img->height;
    relief_status st = relief_raster_create(img->width, img->height, img->channels,
                                            img->bit_depth, other, err);
    if (st != RELIEF_OK)
        return st;
    memcpy(other->v, img->v, n * img->channels * sizeof *other->v);
    if (with_source && !(*other_source = malloc(n * sizeof **other_source))) {
        relief_raster_free(other);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the source map");
    }
    return RELIEF_OK;
}

/* Run a's order, then b's when n_orders is 2: side by side on a host
 * scorer of two threads or more, else one after the other on a's
 * scorer. */
static relief_status run_orders(order_job *a, order_job *b, int n_orders, relief_error *err)
{
    /* Not b->scorer: orders_side_by_side points it at a scorer of its own,
     * gone when it returns. */
    relief_patch_scorer *scorer = a->scorer;
    int ran = 0;
    relief_status st = RELIEF_OK;
    if (n_orders == 2 && scorer->backend == RELIEF_BACKEND_HOST && scorer->threads >= 2)
        st = orders_side_by_side(a, b, scorer->threads, &ran, err);
    if (!ran) {
        st = synth_order(a->img, a->hole, a->target, a->p, a->order, a->wrap, scorer, a->source,
                         a->out, a->prog, 1, err);
        if (st == RELIEF_OK && n_orders == 2)
            st = synth_order(b->img, b->hole, b->target, b->p, b->order, b->wrap, scorer,
                             b->source, b->out, b->prog, 1, err);
    }
    return st;
}

/* The report from the orders' runs (a: img's; b: the copy's when
 * n_orders is 2); the copy's image and sources replace a's when the
 * vertical order won. */
static void keep_better(const order_job *a, const order_job *b, int n_orders,
                        relief_pixsyn_report *rep)
{
    const order_job *job[2] = {a, b};
    const size_t n = (size_t)a->img->width * a->img->height;
    int keep = 0;
    for (int k = 0; k < n_orders; ++k) {
        const run *r = job[k]->out;
        double e = r->synthesised ? r->energy / (double)r->synthesised : 0.0;
        rep->energy[job[k]->order == RELIEF_ORDER_VERTICAL] = e;
        rep->candidates += r->candidates;
        rep->seconds_score += r->seconds_score;
        rep->levels = r->levels;
    }
    /* The vertical order replaces the horizontal one only when its
     * copies matched strictly better. */
    if (n_orders == 2 && rep->energy[1] < rep->energy[0]) {
        keep = 1;
        memcpy(a->img->v, b->img->v, n * a->img->channels * sizeof *a->img->v);
        if (a->source)
            memcpy(a->source, b->source, n * sizeof *a->source);
    }
    rep->kept = job[keep]->order;
    rep->by_synthesis = job[keep]->out->synthesised;
    rep->by_fallback = job[keep]->out->fallbacks;
    rep->unreached = job[keep]->out->unreached;
}

static relief_status pixsyn(relief_raster *img, const uint8_t *hole, const uint8_t *target,
                            const relief_pixsyn_params *p, int wrap,
                            relief_patch_scorer *scorer, int64_t *source,
                            relief_pixsyn_report *rep, relief_error *err)
{
    size_t targets;
    relief_pixsyn_report local;
    /* Set below from p->order; initialised only for gcc 12's
     * -Wmaybe-uninitialized, which cannot see that p->order is valid. */
    relief_pixsyn_order orders[2] = {RELIEF_ORDER_HORIZONTAL, RELIEF_ORDER_VERTICAL};
    int n_orders = 0;
    relief_raster other = {0};
    int64_t *other_source = NULL;
    run runs[2];
    progress_state prog;
    relief_status st;
    double t0 = relief_seconds();

    prog.p = p;
    prog.total = 0;
    atomic_init(&prog.done, 0);
    atomic_init(&prog.stop, 0);

    if (!rep)
        rep = &local;
    memset(rep, 0, sizeof *rep);
    rep->energy[0] = rep->energy[1] = -1.0;
    if (img->channels > 4)
        return relief_fail(err, RELIEF_E_RANGE, "%d channels: at most 4", img->channels);
    st = relief_pixsyn_params_validate(p, img->width, img->height, err);
    if (st != RELIEF_OK)
        return st;
    st = count_targets(img, hole, target, &targets, err);
    rep->hole_pixels = targets;
    if (st != RELIEF_OK || targets == 0)
        return st;
    if (p->order == RELIEF_ORDER_BOTH || p->order == RELIEF_ORDER_HORIZONTAL)
        orders[n_orders++] = RELIEF_ORDER_HORIZONTAL;
    if (p->order == RELIEF_ORDER_BOTH || p->order == RELIEF_ORDER_VERTICAL)
        orders[n_orders++] = RELIEF_ORDER_VERTICAL;
    prog.total = targets * (size_t)n_orders;

    /* The second order works on a copy; the better result ends in img. */
    if (n_orders == 2) {
        st = order_copy(img, source != NULL, &other, &other_source, err);
        if (st != RELIEF_OK)
            return st;
    }
    {
        order_job a = {img, hole, target, p, orders[0], wrap, scorer, source, &runs[0], &prog,
                       RELIEF_OK, {0}, 0};
        order_job b = {&other, hole, target, p, orders[1 % n_orders], wrap, scorer,
                       other_source, &runs[1], &prog, RELIEF_OK, {0}, 0};
        st = run_orders(&a, &b, n_orders, err);
        if (st == RELIEF_OK)
            keep_better(&a, &b, n_orders, rep);
    }
    relief_raster_free(&other);
    free(other_source);
    rep->seconds = relief_seconds() - t0;
    return st;
}

relief_status relief_pixsyn(relief_raster *img, const uint8_t *hole, const uint8_t *target,
                           const relief_pixsyn_params *p, relief_patch_scorer *scorer,
                           int64_t *source, relief_pixsyn_report *rep, relief_error *err)
{
    int W = img->width, H = img->height, r = p->window / 2, Wp, Hp;
    size_t np;
    relief_raster pad = {0};
    uint8_t *ph = NULL, *pt = NULL;
    int64_t *ps = NULL;
    relief_status st;
    if (!p->tileable)
        return pixsyn(img, hole, target, p, 0, scorer, source, rep, err);
    /* Tileable (paper 003, 3.1): the image as a torus, padded by the
     * window's radius with copies of the opposite side, so that windows
     * at a border see across it and the result repeats without seams. */
    if (r > W || r > H)
        return relief_fail(err, RELIEF_E_RANGE, "tileable: the window's radius %d exceeds "
                           "the %d x %d image", r, W, H);
    Wp = W + 2 * r;
    Hp = H + 2 * r;
    np = (size_t)Wp * Hp;
    st = relief_raster_create(Wp, Hp, img->channels, img->bit_depth, &pad, err);
    if (st != RELIEF_OK)
        return st;
    ph = malloc(np);
    pt = calloc(np, 1);
    ps = source ? malloc(np * sizeof *ps) : NULL;
    if (!ph || !pt || (source && !ps)) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the tileable image");
        goto done;
    }
    for (int y = 0; y < Hp; ++y)
        for (int x = 0; x < Wp; ++x) {
            int sx = ((x - r) % W + W) % W, sy = ((y - r) % H + H) % H;
            size_t o = (size_t)y * Wp + x, s = (size_t)sy * W + sx;
            memcpy(pad.v + o * img->channels, img->v + s * img->channels,
                   (size_t)img->channels * sizeof *pad.v);
            ph[o] = hole[s] != 0;
            pt[o] = x >= r && x < r + W && y >= r && y < r + H && hole[s] &&
                    (!target || target[s]);
        }
    st = pixsyn(&pad, ph, pt, p, r, scorer, ps, rep, err);
    if (st != RELIEF_OK)
        goto done;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            size_t o = (size_t)(y + r) * Wp + x + r, s = (size_t)y * W + x;
            memcpy(img->v + s * img->channels, pad.v + o * img->channels,
                   (size_t)img->channels * sizeof *img->v);
            if (source) {
                int64_t q = ps[o];
                source[s] = q < 0 ? -1
                                  : (int64_t)((((q / Wp) - r) % H + H) % H) * W +
                                        (((q % Wp) - r) % W + W) % W;
            }
        }
done:
    relief_raster_free(&pad);
    free(ph);
    free(pt);
    free(ps);
    return st;
}
