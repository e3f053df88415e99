/* The occluder mask of a scene (occlude.h): the seeds in front of the
 * background, grown by colour inside a window around each (paper 004,
 * section 2.1), then dilated. */
#include "occlude/occlude.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"

/* ------------------------------------------------------------ colour */

static double srgb_linear(double c)
{
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

static double lab_f(double t)
{
    return t > 216.0 / 24389.0 ? cbrt(t) : (24389.0 / 27.0 * t + 16.0) / 116.0;
}

void occ_lab(const uint8_t *rgb, size_t n, float *lab)
{
    for (size_t i = 0; i < n; ++i) {
        double r = srgb_linear(rgb[3 * i] / 255.0), g = srgb_linear(rgb[3 * i + 1] / 255.0);
        double b = srgb_linear(rgb[3 * i + 2] / 255.0);
        double x = (0.4124564 * r + 0.3575761 * g + 0.1804375 * b) / 0.95047;
        double y = 0.2126729 * r + 0.7151522 * g + 0.0721750 * b;
        double z = (0.0193339 * r + 0.1191920 * g + 0.9503041 * b) / 1.08883;
        double fx = lab_f(x), fy = lab_f(y), fz = lab_f(z);
        lab[3 * i] = (float)(116.0 * fy - 16.0);
        lab[3 * i + 1] = (float)(500.0 * (fx - fy));
        lab[3 * i + 2] = (float)(200.0 * (fy - fz));
    }
}

static double delta_e(const float *a, const float *b)
{
    double d0 = a[0] - b[0], d1 = a[1] - b[1], d2 = a[2] - b[2];
    return sqrt(d0 * d0 + d1 * d1 + d2 * d2);
}

/* ------------------------------------------------------------ distances */

/* dist[i] = the chessboard distance from pixel i to the nearest pixel of
 * `set` (capped at cap); two raster passes. */
static void chess_distance(const uint8_t *set, int w, int h, uint16_t cap, uint16_t *dist)
{
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            size_t i = (size_t)y * w + x;
            unsigned d = set[i] ? 0 : cap;
            if (d && y > 0) {
                for (int dx = -1; dx <= 1; ++dx)
                    if (x + dx >= 0 && x + dx < w && dist[i - w + dx] + 1u < d)
                        d = dist[i - w + dx] + 1u;
            }
            if (d && x > 0 && dist[i - 1] + 1u < d)
                d = dist[i - 1] + 1u;
            dist[i] = (uint16_t)d;
        }
    for (int y = h - 1; y >= 0; --y)
        for (int x = w - 1; x >= 0; --x) {
            size_t i = (size_t)y * w + x;
            unsigned d = dist[i];
            if (d && y + 1 < h) {
                for (int dx = -1; dx <= 1; ++dx)
                    if (x + dx >= 0 && x + dx < w && dist[i + w + dx] + 1u < d)
                        d = dist[i + w + dx] + 1u;
            }
            if (d && x + 1 < w && dist[i + 1] + 1u < d)
                d = dist[i + 1] + 1u;
            dist[i] = (uint16_t)d;
        }
}

/* ------------------------------------------------------------ seeds */

/* Keep the 8-connected groups of seed pixels of at least min_area; the
 * others are cleared. queue: scratch of w x h. */
static void drop_small(uint8_t *seed, int w, int h, int min_area, size_t *queue,
                       occ_counts *c)
{
    size_t n = (size_t)w * h;
    for (size_t start = 0; start < n; ++start) {
        size_t head = 0, tail = 0;
        if (seed[start] != 1)
            continue;
        seed[start] = 2;
        queue[tail++] = start;
        while (head < tail) {
            size_t i = queue[head++];
            int x = (int)(i % (size_t)w), y = (int)(i / (size_t)w);
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    size_t j;
                    if (x + dx < 0 || x + dx >= w || y + dy < 0 || y + dy >= h)
                        continue;
                    j = (size_t)(y + dy) * w + (x + dx);
                    if (seed[j] == 1)
                        seed[j] = 2, queue[tail++] = j;
                }
        }
        /* queue[0..tail) is the group: 2 marks it visited. */
        if (tail < (size_t)min_area) {
            for (size_t k = 0; k < tail; ++k)
                seed[queue[k]] = 3;
            c->seeds_dropped += tail;
        } else {
            c->seeds += tail;
            ++c->seed_groups;
        }
    }
    for (size_t i = 0; i < n; ++i)
        seed[i] = seed[i] == 2;
}

/* Hysteresis: a point over this share of the margin in front of the
 * background joins the seeds it touches (8-connected, through such
 * points). 3 sigma is crossed by few points of a plane with Gaussian
 * noise, too few to connect far (a square lattice percolates at 0.59),
 * while a leg standing 3 sigma above the floor it rests on is reached
 * from the seat above it. Half the margin spread along the shared frames'
 * walls (30 % of the sequence's wall marked, against 9 %). */
#define WEAK_SHARE 0.75

static void weak_seeds(const occ_scene *s, uint8_t *seed, size_t *queue, occ_counts *c)
{
    int w = s->width, h = s->height;
    size_t n = (size_t)w * h, head = 0, tail = 0;
    for (size_t i = 0; i < n; ++i)
        if (seed[i])
            queue[tail++] = i;
    while (head < tail) {
        size_t i = queue[head++];
        int x = (int)(i % (size_t)w), y = (int)(i / (size_t)w);
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                size_t j;
                if (x + dx < 0 || x + dx >= w || y + dy < 0 || y + dy >= h)
                    continue;
                j = (size_t)(y + dy) * w + (x + dx);
                if (seed[j] || !(s->clearance[j] > WEAK_SHARE * occ_margin_at(s, j)))
                    continue; /* NaN: not a point, or no background */
                seed[j] = 1, ++c->weak_seeds;
                queue[tail++] = j;
            }
    }
}

/* Every pixel with a background behind it judged by the views, so that
 * their counts describe the frame and can be set against the depth's:
 * the captured points beyond the margin (in front) and within it (on the
 * background). The verdicts are cached: the mask's stages ask again for
 * free. */
static void judge_frame(const occ_scene *s, occ_views *v, occ_counts *c)
{
    size_t n = (size_t)s->width * s->height;
    if (!v->cue)
        return;
    for (size_t i = 0; i < n; ++i) {
        double cl = s->clearance[i], m;
        int cue;
        if (!isfinite(s->surface[i]))
            continue;
        cue = occ_views_cue(v, i);
        if (!isfinite(cl) || cue == OCC_CUE_UNKNOWN)
            continue;
        m = occ_margin_at(s, i);
        if (cl > m)
            ++*(cue == OCC_CUE_FOREGROUND ? &c->front_fg : &c->front_bg);
        else if (fabs(cl) <= m)
            ++*(cue == OCC_CUE_BACKGROUND ? &c->on_bg : &c->on_fg);
    }
}

/* Seeds where the depth is missing and the views see parallax. */
static void parallax_seeds(const occ_scene *s, occ_views *v, uint8_t *seed, occ_counts *c)
{
    size_t n = (size_t)s->width * s->height;
    if (!v->cue)
        return;
    for (size_t i = 0; i < n; ++i)
        if (!seed[i] && !isfinite(s->pts[3 * i + 2]) &&
            occ_views_cue(v, i) == OCC_CUE_FOREGROUND)
            seed[i] = 1, ++c->parallax_seeds;
}

/* ------------------------------------------------------------ growth */

typedef struct grower {
    const occ_scene *s;
    const float *lab;
    const uint16_t *near_seed; /* chessboard distance to the seeds */
    const relief_occluder_params *p;
    occ_views *views;          /* the second cue (none: every cue unknown) */
    uint8_t *mask;
    uint32_t *origin;          /* the seed each mask pixel was reached from (a
                                  frame has at most 65535^2 < 2^32 pixels) */
    size_t *queue;
} grower;

/* Whether q, a neighbour of p, joins the mask; what it counts as. */
static int joins(const grower *g, size_t p, size_t q, size_t **count, occ_counts *c)
{
    const occ_scene *s = g->s;
    int half = g->p->window / 2, w = s->width, cue;
    size_t o = (size_t)g->origin[p];
    if (g->mask[q] || abs((int)(q % (size_t)w) - (int)(o % (size_t)w)) > half ||
        abs((int)(q / (size_t)w) - (int)(o / (size_t)w)) > half)
        return 0;
    /* A placeholder has no colour to be constant: growth never steps on it. */
    if (occ_no_colour(s, q) || delta_e(g->lab + 3 * p, g->lab + 3 * q) > g->p->colour_distance)
        return 0;
    cue = occ_views_cue(g->views, q);
    if (cue == OCC_CUE_BACKGROUND)
        return 0; /* the views see the background there */
    if (!isfinite(s->pts[3 * q + 2]))
        *count = &c->grown_missing;
    else if (g->near_seed[q] <= g->p->edge &&
             !(s->clearance[q] < -occ_margin_at(s, q)))
        *count = &c->grown_edge; /* the rim, not what lies behind the background */
    else if (g->p->front_sigmas > 0.0 && occ_lifted(s, q, g->p->front_sigmas))
        *count = &c->grown_front; /* standing on the plane, under its margin */
    else
        return 0;
    return 1;
}

/* The flood fill from every seed at once, in raster order of the seeds
 * and first come first served: deterministic. */
static void grow(grower *g, occ_counts *c)
{
    const occ_scene *s = g->s;
    int w = s->width, h = s->height;
    size_t n = (size_t)w * h, head = 0, tail = 0;
    static const int step[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
    for (size_t i = 0; i < n; ++i)
        if (g->mask[i]) {
            g->origin[i] = (uint32_t)i;
            g->queue[tail++] = i;
        }
    while (head < tail) {
        size_t p = g->queue[head++];
        int x = (int)(p % (size_t)w), y = (int)(p / (size_t)w);
        for (int k = 0; k < 4; ++k) {
            size_t q, *count = NULL;
            if (x + step[k][0] < 0 || x + step[k][0] >= w || y + step[k][1] < 0 ||
                y + step[k][1] >= h)
                continue;
            q = (size_t)(y + step[k][1]) * w + (x + step[k][0]);
            if (!joins(g, p, q, &count, c))
                continue;
            g->mask[q] = 1;
            /* A point lifted off its plane is evidence as a seed is: the
             * window restarts there (a runner is longer than the window). */
            g->origin[q] = count == &c->grown_front ? (uint32_t)q : g->origin[p];
            ++*count;
            g->queue[tail++] = q;
        }
    }
}

/* The seeds, their growth and the dilation into mask; lab, dist, origin
 * and queue are the frame's scratch. */
static relief_status mask_stages(const occ_scene *s, const relief_occluder_params *p,
                                 grower *g, uint16_t *dist, occ_counts *c, relief_error *err)
{
    size_t n = (size_t)s->width * s->height;
    occ_views views;
    relief_status st = occ_views_init(&views, s, g->lab, p, err);
    if (st != RELIEF_OK)
        return st;
    g->views = &views;
    for (size_t i = 0; i < n; ++i)
        g->mask[i] = s->clearance[i] > occ_margin_at(s, i); /* NaN: 0 */
    judge_frame(s, &views, c);
    parallax_seeds(s, &views, g->mask, c);
    drop_small(g->mask, s->width, s->height, p->min_area, g->queue, c);
    if (p->seeding == RELIEF_SEEDING_HYSTERESIS)
        weak_seeds(s, g->mask, g->queue, c);
    chess_distance(g->mask, s->width, s->height, (uint16_t)(p->edge + 1), dist);
    grow(g, c);
    if (p->dilate > 0) {
        chess_distance(g->mask, s->width, s->height, (uint16_t)(p->dilate + 1), dist);
        for (size_t i = 0; i < n; ++i)
            if (!g->mask[i] && dist[i] <= p->dilate)
                g->mask[i] = 1, ++c->dilated;
    }
    for (size_t i = 0; i < n; ++i)
        c->total += g->mask[i];
    c->view_fg = views.fg, c->view_bg = views.bg, c->view_unknown = views.unknown;
    occ_views_free(&views);
    return RELIEF_OK;
}

relief_status occ_mask(const occ_scene *s, const uint8_t *rgb, const relief_occluder_params *p,
                       uint8_t *mask, occ_counts *counts, relief_error *err)
{
    size_t n = (size_t)s->width * s->height;
    float *lab = malloc(n * 3 * sizeof *lab);
    uint16_t *dist = malloc(n * sizeof *dist);
    uint32_t *origin = malloc(n * sizeof *origin);
    size_t *queue = malloc(n * sizeof *queue);
    relief_status st;
    memset(counts, 0, sizeof *counts);
    if (!lab || !dist || !origin || !queue) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the mask's %zu pixels", n);
    } else {
        grower g = {s, lab, dist, p, NULL, mask, origin, queue};
        occ_lab(rgb, n, lab);
        st = mask_stages(s, p, &g, dist, counts, err);
    }
    free(lab);
    free(dist);
    free(origin);
    free(queue);
    return st;
}
