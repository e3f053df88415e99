/* image/fill.c: the 1-D pass on hand-made rows, a periodic image whose
 * hole copy-paste must fill back exactly, the pyramid against the
 * exhaustive search, the fallback, bad parameters, and (argument
 * "opencl") the OpenCL scorer against the scalar one, byte for byte.
 *   test_fill [opencl] IMAGES_DIR */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "base/rng.h"
#include "image/fill.h"
#include "image/image_io.h"

static relief_raster make(int w, int h, int c)
{
    relief_raster r;
    relief_error err = {0};
    if (relief_raster_create(w, h, c, 8, &r, &err) != RELIEF_OK) {
        fprintf(stderr, "%s\n", err.message);
        exit(2);
    }
    return r;
}

static void test_interp(void)
{
    relief_fill_params p = relief_fill_params_default();
    relief_raster r = make(12, 3, 1);
    uint8_t hole[36] = {0};
    size_t rows, cols;
    /* Row 0: smooth ends 100 and 110 around a 3-pixel gap: filled linearly.
     * Row 1: ends 100 and 160 disagree: left. Row 2: a noisy left end. */
    for (int x = 0; x < 12; ++x) {
        r.v[x] = x < 6 ? 100.0f : 110.0f;
        r.v[12 + x] = x < 6 ? 100.0f : 160.0f;
        r.v[24 + x] = x % 2 ? 80.0f : 120.0f;
    }
    for (int x = 4; x <= 6; ++x)
        hole[x] = hole[12 + x] = hole[24 + x] = 1;
    r.v[24 + 7] = r.v[24 + 8] = r.v[24 + 9] = r.v[24 + 10] = r.v[24 + 11] = 100.0f;
    relief_fill_interp(&r, hole, &p, &rows, &cols, NULL);
    CHECK(rows == 3 && cols == 0, "rows %zu, columns %zu, expected 3 and 0", rows, cols);
    CHECK(r.v[4] == 102.5f && r.v[5] == 105.0f && r.v[6] == 107.5f,
          "row 0 filled %g %g %g, expected 102.5 105 107.5", r.v[4], r.v[5], r.v[6]);
    CHECK(hole[16] && hole[28], "rows 1 and 2 must stay holes");
    relief_raster_free(&r);

    /* Columns: the same gap vertically, found by the column pass only. */
    r = make(3, 12, 1);
    memset(hole, 0, sizeof hole);
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 3; ++x)
            r.v[y * 3 + x] = y < 6 ? 40.0f : 48.0f;
    for (int y = 4; y <= 6; ++y)
        for (int x = 0; x < 3; ++x)
            hole[y * 3 + x] = 1;
    relief_fill_interp(&r, hole, &p, &rows, &cols, NULL);
    CHECK(rows == 0 && cols == 9, "rows %zu, columns %zu, expected 0 and 9", rows, cols);
    CHECK(r.v[5 * 3 + 1] == 44.0f, "column filled %g, expected 44", r.v[5 * 3 + 1]);
    /* A threshold of 0 on the difference refuses it. */
    relief_raster_free(&r);
}

/* Mean 5 x 5 local standard deviation (channel 0) over the pixels of
 * rectangle (x0, y0, w, h) (inside 1) or of the ring r pixels wide round
 * it (inside 0); rough 1: the mean |second difference| along the row and
 * along the column instead (0 on a linear run: streaks). */
static double mean_local_sd(const relief_raster *r, int x0, int y0, int w, int h, int ring,
                            int inside, int rough)
{
    double sum = 0.0;
    int n = 0;
    for (int y = y0 - ring; y < y0 + h + ring; ++y)
        for (int x = x0 - ring; x < x0 + w + ring; ++x) {
            int in = x >= x0 && x < x0 + w && y >= y0 && y < y0 + h;
            double s = 0.0, s2 = 0.0;
            int m = 0;
            if (in != inside || x < 2 || y < 2 || x >= r->width - 2 || y >= r->height - 2)
                continue;
            if (rough) {
                const float *o = r->v + ((size_t)y * r->width + x) * r->channels;
                size_t dy = (size_t)r->width * r->channels;
                sum += fabs(o[-r->channels] - 2.0 * o[0] + o[r->channels]) +
                       fabs(o[-(ptrdiff_t)dy] - 2.0 * o[0] + o[dy]);
                ++n;
                continue;
            }
            for (int dy = -2; dy <= 2; ++dy)
                for (int dx = -2; dx <= 2; ++dx) {
                    double v = r->v[((size_t)(y + dy) * r->width + x + dx) * r->channels];
                    s += v;
                    s2 += v * v;
                    ++m;
                }
            sum += sqrt(fmax(s2 / m - (s / m) * (s / m), 0.0));
            ++n;
        }
    return n ? sum / n : 0.0;
}

/* Issue 40: the 1-D pass must not wipe texture. A low-contrast noise
 * texture (a lunar surface: 120 +- 2.5 on 0..255, correlated over 3 pixels) with a square hole
 * larger than the window and one smaller, and sparse bright points on
 * black (a star field: 2 % of the pixels) with two larger than the window:
 * the fill's local standard deviation over the ring's stays in [0.5, 2].
 * A gap shorter than the window in a star field whose ends see no star
 * within half a window along its line is still filled black: the pass
 * looks along the line only. */
static void test_texture(relief_patch_scorer *s)
{
    typedef struct { int x, y, side; } square;
    static const square all[2][2] = {{{40, 40, 48}, {120, 30, 12}},
                                                         {{40, 40, 48}, {120, 30, 24}}};
    for (int kind = 0; kind < 2; ++kind) {
        const square *holes = all[kind];
        relief_raster r = make(176, 160, 1);
        relief_rng rng;
        relief_fill_params p = relief_fill_params_default();
        relief_fill_report rep;
        relief_error err = {0};
        uint8_t *hole = calloc(176 * 160, 1);
        relief_rng_seed(&rng, 7 + kind);
        for (int i = 0; i < 176 * 160; ++i) /* white noise, sd 7.5, or stars */
            r.v[i] = kind == 0 ? (float)(relief_rng_below(&rng, 13) + relief_rng_below(&rng, 13) +
                                         relief_rng_below(&rng, 13) + relief_rng_below(&rng, 13))
                     : relief_rng_below(&rng, 100) < 2 ? (float)(120 + relief_rng_below(&rng, 136))
                                                        : 0.0f;
        if (kind == 0) { /* a 3 x 3 mean of it: a correlated texture of sd 2.5 */
            relief_raster t = make(176, 160, 1);
            for (int y = 0; y < 160; ++y)
                for (int x = 0; x < 176; ++x) {
                    float sum = 0.0f;
                    for (int dy = -1; dy <= 1; ++dy)
                        for (int dx = -1; dx <= 1; ++dx)
                            sum += r.v[((y + dy + 160) % 160) * 176 + (x + dx + 176) % 176];
                    t.v[y * 176 + x] = roundf(96.0f + sum / 9.0f);
                }
            relief_raster_free(&r);
            r = t;
        }
        for (int h = 0; h < 2; ++h)
            for (int y = holes[h].y; y < holes[h].y + holes[h].side; ++y)
                for (int x = holes[h].x; x < holes[h].x + holes[h].side; ++x) {
                    hole[y * 176 + x] = 1;
                    r.v[y * 176 + x] = 0.0f;
                }
        CHECK(relief_fill(&r, hole, &p, s, &rep, &err) == RELIEF_OK, "%s", err.message);
        for (int h = 0; h < 2; ++h) {
            const char *what = kind ? "star field" : "low-contrast noise";
            double in = mean_local_sd(&r, holes[h].x, holes[h].y, holes[h].side,
                                      holes[h].side, 8, 1, 0),
                   ring = mean_local_sd(&r, holes[h].x, holes[h].y, holes[h].side,
                                        holes[h].side, 8, 0, 0),
                   rough = mean_local_sd(&r, holes[h].x, holes[h].y, holes[h].side,
                                         holes[h].side, 8, 1, 1) /
                           mean_local_sd(&r, holes[h].x, holes[h].y, holes[h].side,
                                         holes[h].side, 8, 0, 1);
            printf("%s, %d x %d hole: local SD %.2f in the fill, %.2f in the ring: ratio "
                   "%.2f; roughness ratio %.2f (%zu of %zu pixels by the 1-D pass)\n", what,
                   holes[h].side, holes[h].side, in, ring, in / ring, rough,
                   rep.by_rows + rep.by_columns, rep.hole_pixels);
            CHECK(in / ring >= 0.5 && in / ring <= 2.0, "%s, %d x %d hole: local SD ratio "
                  "%.2f, expected 0.5..2", what, holes[h].side, holes[h].side, in / ring);
            CHECK(rough >= 0.5 && rough <= 2.0, "%s, %d x %d hole: roughness ratio %.2f, "
                  "expected 0.5..2 (streaks)", what, holes[h].side, holes[h].side, rough);
        }
        free(hole);
        relief_raster_free(&r);
    }
}

/* The 1-D pass still fills what it is for (paper 004): a smooth 8-bit
 * gradient with a thin scratch across it and a 10 x 10 hole is filled by
 * it alone, every pixel. */
static void test_interp_gradient(relief_patch_scorer *s)
{
    relief_raster r = make(96, 64, 3);
    relief_fill_params p = relief_fill_params_default();
    relief_fill_report rep;
    relief_error err = {0};
    uint8_t *hole = calloc(96 * 64, 1);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 96; ++x) {
            for (int c = 0; c < 3; ++c)
                r.v[(y * 96 + x) * 3 + c] = roundf(30.0f + 1.3f * x + 0.6f * y + 20.0f * c);
            hole[y * 96 + x] = (y >= 30 && y < 33 && x >= 10 && x < 86) ||
                               (x >= 40 && x < 50 && y >= 8 && y < 18);
        }
    CHECK(relief_fill(&r, hole, &p, s, &rep, &err) == RELIEF_OK, "%s", err.message);
    CHECK(rep.by_rows + rep.by_columns == rep.hole_pixels && rep.hole_pixels == 328,
          "gradient: %zu of %zu hole pixels by the 1-D pass, expected all 328",
          rep.by_rows + rep.by_columns, rep.hole_pixels);
    free(hole);
    relief_raster_free(&r);
}

/* A w x h image repeating a random px x py tile, channels c. */
static relief_raster periodic(int w, int h, int c, int px, int py, uint32_t seed)
{
    relief_raster r = make(w, h, c);
    relief_rng rng;
    float tile[16 * 16 * 4];
    relief_rng_seed(&rng, seed);
    for (int i = 0; i < px * py * c; ++i)
        tile[i] = (float)relief_rng_below(&rng, 256);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int k = 0; k < c; ++k)
                r.v[((size_t)y * w + x) * c + k] = tile[((y % py) * px + x % px) * c + k];
    return r;
}

static void test_periodic(relief_patch_scorer *s, int exhaustive)
{
    relief_raster truth = periodic(160, 144, 3, 7, 5, 3), r = periodic(160, 144, 3, 7, 5, 3);
    relief_fill_params p = relief_fill_params_default();
    relief_fill_report rep;
    relief_error err = {0};
    uint8_t *hole = calloc(160 * 144, 1);
    size_t wrong = 0, holes = 0;
    relief_status st;
    p.exhaustive = exhaustive;
    for (int y = 50; y < 80; ++y)
        for (int x = 60; x < 95; ++x) {
            hole[y * 160 + x] = 1;
            for (int k = 0; k < 3; ++k)
                r.v[(y * 160 + x) * 3 + k] = 0.0f;
        }
    hole[10 * 160 + 150] = 1; /* and a lone pixel */
    st = relief_fill(&r, hole, &p, s, &rep, &err);
    CHECK(st == RELIEF_OK, "%s", err.message);
    for (int i = 0; i < 160 * 144; ++i) {
        holes += hole[i];
        for (int k = 0; k < 3; ++k)
            wrong += hole[i] && r.v[i * 3 + k] != truth.v[i * 3 + k];
    }
    CHECK(rep.hole_pixels == holes, "report: %zu holes of %zu", rep.hole_pixels, holes);
    CHECK(wrong == 0, "%s: %zu of %zu hole values differ from the period", exhaustive ?
          "exhaustive" : "pyramid", wrong, holes * 3);
    CHECK(rep.by_copy == holes && rep.by_fallback == 0 && rep.by_rows + rep.by_columns == 0,
          "filled %zu by copy, %zu fallback, %zu 1-D", rep.by_copy, rep.by_fallback,
          rep.by_rows + rep.by_columns);
    CHECK(exhaustive ? rep.levels == 1 : rep.levels == 2 && rep.start_level == 1,
          "levels %d, start %d", rep.levels, rep.start_level);
    free(hole);
    relief_raster_free(&r);
    relief_raster_free(&truth);
}

/* The pyramid's best against the exhaustive best on a real texture: the
 * best window by the exhaustive search must be the pyramid's, or no
 * better than it, for nearly every query. */
static void test_pyramid(relief_patch_scorer *s, const char *images)
{
    char path[512];
    relief_raster full, r;
    relief_error err = {0};
    relief_fill_params p = relief_fill_params_default();
    relief_filler *f = NULL;
    uint8_t *hole;
    int same = 0, queries = 0, inside = 0;
    double worst = 1.0;
    snprintf(path, sizeof path, "%s/brick.png", images);
    if (relief_raster_read(path, NULL, &full, &err) != RELIEF_OK) {
        printf("%s: %s; the pyramid test is skipped\n", path, err.message);
        return;
    }
    /* The top-left 256 x 256: 2 levels, the search starting at level 1. */
    r = make(256, 256, 1);
    for (int y = 0; y < 256; ++y)
        memcpy(r.v + y * 256, full.v + y * 512, 256 * sizeof(float));
    hole = calloc(256 * 256, 1);
    for (int y = 100; y < 140; ++y)
        for (int x = 110; x < 150; ++x)
            hole[y * 256 + x] = 1;
    p.pyramid_side = 128;
    CHECK(relief_filler_create(&r, hole, &p, s, &f, &err) == RELIEF_OK, "%s", err.message);
    for (int k = 0; f && k < 40; ++k) {
        int px = 110 + (k * 7) % 40, py = k % 2 ? 99 : 140; /* just outside, on the rim */
        relief_window_match ex, py_best, coarse[RELIEF_FILL_MAX_TOP];
        int fe, fp, nc;
        if (py == 99)
            py = 100, px = 109; /* a hole pixel with known neighbours */
        else
            py = 139, px = 110 + (k * 7) % 40;
        CHECK(relief_filler_search(f, px, py, 17, 1, &ex, &fe, NULL, NULL, &err) == RELIEF_OK,
              "%s", err.message);
        CHECK(relief_filler_search(f, px, py, 17, 0, &py_best, &fp, coarse, &nc, &err) ==
                  RELIEF_OK, "%s", err.message);
        if (!fe || !fp)
            continue;
        ++queries;
        CHECK(nc == 4, "kept %d matches at the start level, expected 4 (4 x level 1)", nc);
        CHECK(py_best.msd >= ex.msd, "the pyramid beat the exhaustive search: %g < %g",
              py_best.msd, ex.msd);
        same += py_best.msd == ex.msd;
        worst = fmax(worst, py_best.msd / fmax(ex.msd, 1e-9));
        /* The exhaustive best lies within reach of a kept coarse match. */
        for (int i = 0; i < nc; ++i)
            if (abs(coarse[i].x - ex.x) <= 2 && abs(coarse[i].y - ex.y) <= 2) {
                ++inside;
                break;
            }
    }
    printf("pyramid: %d of %d queries found the exhaustive best (%d within a kept coarse "
           "match's reach); worst msd ratio %.3f\n", same, queries, inside, worst);
    CHECK(queries >= 20, "only %d queries", queries);
    CHECK(inside >= queries * 8 / 10 && same >= queries * 8 / 10,
          "the pyramid's top M held the exhaustive best in %d and found it in %d of %d",
          inside, same, queries);
    relief_filler_destroy(f);
    free(hole);
    relief_raster_free(&r);
    relief_raster_free(&full);
}

static void test_bad(relief_patch_scorer *s)
{
    relief_raster r = periodic(40, 30, 1, 5, 5, 1);
    relief_fill_params p = relief_fill_params_default();
    relief_error err = {0};
    uint8_t *hole = calloc(40 * 30, 1);
    relief_fill_report rep;
    /* Nothing to fill: fine, nothing changes. */
    CHECK(relief_fill(&r, hole, &p, s, &rep, &err) == RELIEF_OK && rep.hole_pixels == 0,
          "no hole: %s", err.message);
    /* The whole image a hole. */
    memset(hole, 1, 40 * 30);
    CHECK(relief_fill(&r, hole, &p, s, &rep, &err) == RELIEF_E_RANGE &&
              strstr(err.message, "every pixel"), "all holes: %s", err.message);
    /* Every 5 x 5 window over 10 % holes: a hole on every other column. */
    for (int i = 0; i < 40 * 30; ++i)
        hole[i] = (i % 40) % 2 == 0;
    CHECK(relief_fill(&r, hole, &p, s, &rep, &err) == RELIEF_E_RANGE &&
              strstr(err.message, "nothing to copy"), "no window: %s", err.message);
    /* A window larger than the image, even windows. */
    memset(hole, 0, 40 * 30);
    hole[100] = 1;
    p.window = 31;
    CHECK(relief_fill(&r, hole, &p, s, &rep, &err) == RELIEF_E_RANGE &&
              strstr(err.message, "larger than the image"), "window: %s", err.message);
    p.window = 16;
    CHECK(relief_fill(&r, hole, &p, s, &rep, &err) == RELIEF_E_RANGE, "even window");
    p = relief_fill_params_default();
    p.min_window = 19;
    CHECK(relief_fill(&r, hole, &p, s, &rep, &err) == RELIEF_E_RANGE, "min window > window");
    /* A tau so strict that every match fails: the fallback fills it. */
    p = relief_fill_params_default();
    p.tau = 1e-6;
    p.interp = 0;
    {
        relief_rng rng;
        relief_rng_seed(&rng, 5);
        for (int i = 0; i < 40 * 30; ++i) /* break the period */
            r.v[i] += (float)relief_rng_below(&rng, 50);
    }
    CHECK(relief_fill(&r, hole, &p, s, &rep, &err) == RELIEF_OK && rep.by_fallback == 1 &&
              rep.searches == 7, "fallback: %s; %zu fallback, %zu searches", err.message,
          rep.by_fallback, rep.searches);
    free(hole);
    relief_raster_free(&r);
}

/* A batch of searches on the OpenCL scorer (one launch per level for all
 * of them: score_rects, score_pairs) finds, query by query, what a single
 * search on the scalar scorer finds: the 8 best, weighted and not. */
static void test_batch(relief_patch_scorer *sc, relief_patch_scorer *cl, const relief_raster *a)
{
    enum { NQ = 24, KEEP = 8 };
    relief_error err = {0};
    relief_fill_params p = relief_fill_params_default();
    uint8_t *hole = calloc((size_t)a->width * a->height, 1);
    relief_filler *fs = NULL, *fc = NULL;
    relief_raster as, ac;
    int pxy[2 * NQ], n_batch[NQ], differ = 0, found = 0;
    relief_window_match batch[NQ * KEEP];
    size_t n = (size_t)a->width * a->height * a->channels;
    relief_raster_create(a->width, a->height, a->channels, 8, &as, &err);
    relief_raster_create(a->width, a->height, a->channels, 8, &ac, &err);
    memcpy(as.v, a->v, n * sizeof(float));
    memcpy(ac.v, a->v, n * sizeof(float));
    for (int y = 100; y < 140; ++y)
        for (int x = 180; x < 220; ++x)
            hole[y * a->width + x] = 1;
    p.search_radius = 48;
    CHECK(relief_filler_create(&as, hole, &p, sc, &fs, &err) == RELIEF_OK, "%s", err.message);
    CHECK(relief_filler_create(&ac, hole, &p, cl, &fc, &err) == RELIEF_OK, "%s", err.message);
    for (int k = 0; k < NQ; ++k) { /* around the hole's rim, and two away from it */
        pxy[2 * k] = k < 22 ? 180 + (k * 7) % 40 : 40 + 300 * (k - 22);
        pxy[2 * k + 1] = k < 22 ? (k % 2 ? 100 : 139) : 60;
    }
    for (int weighted = 0; weighted <= 1 && fs && fc; ++weighted) {
        double sigma = weighted ? 1.6 : 0.0;
        CHECK(relief_filler_search_batch(fc, NQ, pxy, 11, 0, sigma, KEEP, batch, n_batch,
                                         &err) == RELIEF_OK, "batch: %s", err.message);
        for (int k = 0; k < NQ; ++k) {
            relief_window_match one[KEEP];
            int n_one = 0;
            CHECK(relief_filler_search_top(fs, pxy[2 * k], pxy[2 * k + 1], 11, 0, sigma, one,
                                           KEEP, &n_one, NULL, NULL, &err) == RELIEF_OK,
                  "single: %s", err.message);
            found += n_one;
            differ += n_one != n_batch[k] ||
                      memcmp(one, batch + k * KEEP, (size_t)n_one * sizeof *one) != 0;
        }
    }
    CHECK(!differ && found > NQ, "%d of %d batched searches differ from the single ones "
          "(%d matches)", differ, 2 * NQ, found);
    printf("batch: %d searches in batches of %d on OpenCL, each the scalar search's %d "
           "matches\n", 2 * NQ, NQ, KEEP);
    relief_filler_destroy(fs);
    relief_filler_destroy(fc);
    relief_raster_free(&as);
    relief_raster_free(&ac);
    free(hole);
}

/* The fill of `r` (a copy) on the scalar scorer and on OpenCL, byte for
 * byte; the OpenCL fill's report in *rb. */
static void same_fill(relief_patch_scorer *sc, relief_patch_scorer *cl, const relief_raster *r,
                      const uint8_t *hole, const relief_fill_params *p, const char *what,
                      relief_fill_report *rb)
{
    relief_error err = {0};
    relief_fill_report ra;
    size_t n = (size_t)r->width * r->height * r->channels;
    relief_raster a2, b2;
    relief_raster_create(r->width, r->height, r->channels, 8, &a2, &err);
    relief_raster_create(r->width, r->height, r->channels, 8, &b2, &err);
    memcpy(a2.v, r->v, n * sizeof(float));
    memcpy(b2.v, r->v, n * sizeof(float));
    CHECK(relief_fill(&a2, hole, p, sc, &ra, &err) == RELIEF_OK, "%s: scalar: %s", what,
          err.message);
    CHECK(relief_fill(&b2, hole, p, cl, rb, &err) == RELIEF_OK, "%s: opencl: %s", what,
          err.message);
    CHECK(memcmp(a2.v, b2.v, n * sizeof(float)) == 0, "%s: the backends filled differently",
          what);
    CHECK(ra.by_copy == rb->by_copy && ra.searches == rb->searches &&
              ra.candidates == rb->candidates && ra.scores_read == ra.candidates,
          "%s: reports differ: %zu/%zu copied, %zu/%zu searches", what, ra.by_copy,
          rb->by_copy, ra.searches, rb->searches);
    printf("%s: %zu holes, %zu copied, %zu by the fallback, %zu searches: identical; "
           "%zu of %zu scores read back\n", what, ra.hole_pixels, ra.by_copy, ra.by_fallback,
           ra.searches, rb->scores_read, rb->candidates);
    relief_raster_free(&a2);
    relief_raster_free(&b2);
}

/* The OpenCL scorer's selection on the device (select_rects, here for
 * every batch) keeps the scalar fill's bytes where ties abound: a periodic
 * texture, whose every period ties at 0, and a flat image, whose every
 * window does (then nearly every block is read, and the scorer reads all). */
static void test_select_ties(relief_patch_scorer *sc, relief_patch_scorer *cl)
{
    relief_raster per = periodic(160, 144, 3, 7, 5, 3), flat = periodic(160, 144, 3, 7, 5, 3);
    relief_fill_params p = relief_fill_params_default();
    relief_fill_report rb;
    uint8_t *hole = calloc(160 * 144, 1);
    for (size_t i = 0; i < (size_t)160 * 144 * 3; ++i)
        flat.v[i] = 91.0f;
    for (int y = 50; y < 80; ++y)
        for (int x = 60; x < 95; ++x)
            hole[y * 160 + x] = 1;
    for (int exhaustive = 0; exhaustive <= 1; ++exhaustive) {
        p.exhaustive = exhaustive;
        same_fill(sc, cl, &per, hole, &p, exhaustive ? "periodic, exhaustive, selected"
                                                     : "periodic, pyramid, selected", &rb);
        same_fill(sc, cl, &flat, hole, &p, exhaustive ? "flat, exhaustive, selected"
                                                      : "flat, pyramid, selected", &rb);
    }
    free(hole);
    relief_raster_free(&per);
    relief_raster_free(&flat);
}

/* The OpenCL scorer fills exactly as the scalar one: a real photograph
 * with a disc and a rectangle cut, both searches, reading every score back
 * and selecting them on the device (every batch, whatever its size). */
static int test_opencl(const char *images)
{
    relief_patch_scorer *sc = NULL, *cl = NULL;
    relief_error err = {0};
    char path[512];
    relief_raster a, b;
    relief_status st = relief_patch_opencl_create(-1, &cl, &err);
    if (st != RELIEF_OK) {
        printf("no OpenCL device (%s): skipped\n", err.message);
        return 77;
    }
    relief_patch_scalar_create(&sc, &err);
    snprintf(path, sizeof path, "%s/chelsea.png", images);
    if (relief_raster_read(path, NULL, &a, &err) != RELIEF_OK) {
        printf("%s: %s: skipped\n", path, err.message);
        return 77;
    }
    for (int select = 0; select <= 1; ++select)
        for (int exhaustive = 0; exhaustive <= 1; ++exhaustive) {
            relief_fill_params p = relief_fill_params_default();
            relief_fill_report rb;
            uint8_t *hole = calloc((size_t)a.width * a.height, 1);
            char what[64];
            for (int y = 0; y < a.height; ++y)
                for (int x = 0; x < a.width; ++x)
                    hole[y * a.width + x] =
                        (x - 200) * (x - 200) + (y - 120) * (y - 120) < 15 * 15 ||
                        (x >= 330 && x < 350 && y >= 200 && y < 230);
            p.exhaustive = exhaustive;
            if (exhaustive)
                p.search_radius = 40; /* keeps the reference quick */
            relief_patch_opencl_select_from(cl, select ? 0 : (size_t)-1);
            snprintf(what, sizeof what, "%s, %s", exhaustive ? "exhaustive" : "pyramid",
                     select ? "selected on the device" : "every score read");
            same_fill(sc, cl, &a, hole, &p, what, &rb);
            /* Exhaustive, a search's few best lie in a few blocks of the
             * whole image; the pyramid's small rectangles are mostly read. */
            CHECK(!select ? rb.scores_read == rb.candidates
                          : rb.scores_read < rb.candidates / (exhaustive ? 10 : 2),
                  "%s: %zu of %zu scores read back", what, rb.scores_read, rb.candidates);
            free(hole);
        }
    test_select_ties(sc, cl);
    relief_patch_opencl_select_from(cl, (size_t)-1);
    test_batch(sc, cl, &a); /* every score read */
    relief_patch_opencl_select_from(cl, 0);
    test_batch(sc, cl, &a); /* selected */
    (void)b;
    relief_raster_free(&a);
    relief_patch_scorer_destroy(sc);
    relief_patch_scorer_destroy(cl);
    return check_result();
}

/* A level of `channels` channels with a scatter of holes, for the scorers
 * to read. */
static void random_level(relief_patch_level *l, float *v, uint8_t *known, int w, int h,
                         int channels, uint32_t seed)
{
    for (int i = 0; i < w * h; ++i) {
        seed = seed * 1664525u + 1013904223u;
        known[i] = (seed >> 24) % 7 != 0 && !(i % w > 20 && i % w < 26 && i / w > 12);
        for (int c = 0; c < channels; ++c) {
            seed = seed * 1664525u + 1013904223u;
            v[i * channels + c] = (float)(seed >> 8) / 16777216.0f;
        }
    }
    *l = (relief_patch_level){v, known, w, h, channels};
}

/* The host scorer's windows (lanes of 8 side by side, and the rows' and
 * lists' last few one at a time) have the scalar reference's bits: every
 * channel count, weighted and not, rectangles of every width near 8, lists
 * of every length near 8, on 1, 2 and 3 threads. */
static void test_host_scorer(void)
{
    enum { W = 48, H = 40, MAXC = W * H };
    static float v[W * H * 4], ssd[2][MAXC], ws[2][MAXC];
    static uint8_t known[W * H];
    static int n[2][MAXC], xy[2 * 64];
    relief_error err = {0};
    relief_patch_scorer *sc = NULL, *host[3] = {NULL};
    float g[8] = {1.0f, 0.8f, 0.5f, 0.25f, 0.1f, 0.03f, 0.01f, 0.001f};
    size_t compared = 0, differ = 0;
    CHECK(relief_patch_scalar_create(&sc, &err) == RELIEF_OK, "%s", err.message);
    for (int t = 0; t < 3; ++t)
        CHECK(relief_patch_host_create(t + 1, &host[t], &err) == RELIEF_OK, "%s", err.message);
    for (int channels = 1; channels <= 4; ++channels) {
        relief_patch_level l;
        random_level(&l, v, known, W, H, channels, 7u * channels);
        sc->ops->bind(sc->ctx, &l, 1, &err);
        for (int t = 0; t < 3; ++t)
            host[t]->ops->bind(host[t]->ctx, &l, 1, &err);
        for (int q = 0; q < 6; ++q) {
            int radius = 1 + q % 4, qx = 3 + 7 * q, qy = 2 + 5 * q, holes = q % 3 ? 8 : 100;
            const float *gw = q % 2 ? g : NULL;
            int nx = 5 + 2 * q, ny = 3 + q;
            int count = 3 + 5 * q;
            for (int i = 0; i < count; ++i) {
                xy[2 * i] = radius + (i * 13 + q) % (W - 2 * radius);
                xy[2 * i + 1] = radius + (i * 7 + 3 * q) % (H - 2 * radius);
            }
            sc->ops->score_rect(sc->ctx, 0, qx, qy, radius, holes, gw, radius, radius, nx, ny,
                                ssd[0], ws[0], n[0], &err);
            for (int t = 0; t < 3; ++t) {
                host[t]->ops->score_rect(host[t]->ctx, 0, qx, qy, radius, holes, gw, radius,
                                         radius, nx, ny, ssd[1], ws[1], n[1], &err);
                for (int k = 0; k < nx * ny; ++k, ++compared)
                    differ += memcmp(&ssd[0][k], &ssd[1][k], sizeof(float)) != 0 ||
                              memcmp(&ws[0][k], &ws[1][k], sizeof(float)) != 0 ||
                              n[0][k] != n[1][k];
            }
            sc->ops->score_list(sc->ctx, 0, qx, qy, radius, holes, gw, xy, count, ssd[0],
                                ws[0], n[0], &err);
            for (int t = 0; t < 3; ++t) {
                host[t]->ops->score_list(host[t]->ctx, 0, qx, qy, radius, holes, gw, xy, count,
                                         ssd[1], ws[1], n[1], &err);
                for (int k = 0; k < count; ++k, ++compared)
                    differ += memcmp(&ssd[0][k], &ssd[1][k], sizeof(float)) != 0 ||
                              memcmp(&ws[0][k], &ws[1][k], sizeof(float)) != 0 ||
                              n[0][k] != n[1][k];
            }
        }
    }
    CHECK(compared > 1000 && differ == 0, "host scorer: %zu of %zu windows differ from the "
          "scalar reference", differ, compared);
    printf("host scorer: %zu windows, 1 to 4 channels, 1 to 3 threads: the scalar bits\n",
           compared);
    relief_patch_scorer_destroy(sc);
    for (int t = 0; t < 3; ++t)
        relief_patch_scorer_destroy(host[t]);
}

/* A whole fill on the host's threads is the scalar fill, byte for byte,
 * and says where it ran. */
static void test_host_fill(relief_patch_scorer *sc, const char *images)
{
    relief_patch_scorer *h = NULL;
    relief_error err = {0};
    relief_fill_params p = relief_fill_params_default();
    relief_raster a, b;
    char path[512];
    uint8_t *hole;
    size_t n;
    snprintf(path, sizeof path, "%s/brick.png", images);
    if (relief_raster_read(path, NULL, &a, &err) != RELIEF_OK) {
        printf("%s: %s: skipped\n", path, err.message);
        return;
    }
    n = (size_t)a.width * a.height * a.channels;
    relief_raster_create(a.width, a.height, a.channels, 8, &b, &err);
    memcpy(b.v, a.v, n * sizeof(float));
    hole = calloc((size_t)a.width * a.height, 1);
    for (int y = 200; y < 260; ++y)
        for (int x = 180; x < 250; ++x)
            hole[y * a.width + x] = 1;
    CHECK(relief_patch_host_create(2, &h, &err) == RELIEF_OK, "%s", err.message);
    CHECK(strstr(h->device, "2 threads") != NULL && h->backend == RELIEF_BACKEND_HOST,
          "host scorer: %s", h->device);
    CHECK(relief_fill(&a, hole, &p, sc, NULL, &err) == RELIEF_OK, "scalar: %s", err.message);
    CHECK(relief_fill(&b, hole, &p, h, NULL, &err) == RELIEF_OK, "host: %s", err.message);
    CHECK(memcmp(a.v, b.v, n * sizeof(float)) == 0, "host fill differs from the scalar one");
    relief_patch_scorer_destroy(h);
    relief_raster_free(&a);
    relief_raster_free(&b);
    free(hole);
}

int main(int argc, char **argv)
{
    relief_patch_scorer *s = NULL;
    relief_error err = {0};
    const char *images = "../shared/data/images";
    if (argc > 1 && strcmp(argv[1], "opencl") == 0)
        return test_opencl(argc > 2 ? argv[2] : images);
    if (argc > 1)
        images = argv[1];
    relief_patch_scalar_create(&s, &err);
    test_interp();
    test_texture(s);
    test_interp_gradient(s);
    test_periodic(s, 0);
    test_periodic(s, 1);
    test_pyramid(s, images);
    test_bad(s);
    test_host_scorer();
    test_host_fill(s, images);
    relief_patch_scorer_destroy(s);
    return check_result();
}
