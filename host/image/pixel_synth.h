/* Constrained texture synthesis (paper 003, section 3.1): Efros and
 * Leung's non-parametric sampling, one missing pixel at a time, run on the
 * image hole filler's engine (fill.h: its pyramid search and its scorer,
 * scalar or OpenCL, the same bits).
 *
 * Each step takes the missing pixel with the most known 8-neighbours (ties
 * in the order's raster: row-major for horizontal, column-major for
 * vertical), compares the w x w window around it with every window of the
 * symmetric search region around it (the pixels known in both, weighted by
 * a Gaussian of sigma pixels: the weighted mean square distance of eq. 1),
 * picks at random among the matches within (1 + epsilon) of the best (of
 * the 8 best at most), and copies that window's centre. A pixel no window
 * matches takes the mean of its known neighbours. Every channel is matched
 * but alpha (2 or 4 channels), as in the image filler.
 *
 * Both orders run when asked (the paper's curved wall: a gradient fills
 * differently along rows than along columns), and the one whose copies
 * matched better is kept: the lower mean weighted distance over its
 * synthesised pixels. Deterministic for a seed whatever the backend. */
#ifndef RELIEF_HOST_IMAGE_PIXEL_SYNTH_H
#define RELIEF_HOST_IMAGE_PIXEL_SYNTH_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"
#include "image/patch.h"
#include "image/raster.h"

typedef enum relief_pixsyn_order {
    RELIEF_ORDER_BOTH = 0,   /* run both, keep the better */
    RELIEF_ORDER_HORIZONTAL, /* ties row-major */
    RELIEF_ORDER_VERTICAL    /* ties column-major */
} relief_pixsyn_order;

/* The largest batch (relief_pixsyn_params.batch). */
#define RELIEF_PIXSYN_MAX_BATCH 256

typedef struct relief_pixsyn_params {
    int window;               /* w, odd, 3..1025; 9 */
    double sigma;             /* the weights' Gaussian, pixels; <= 0: w / 6.4 (Efros-Leung) */
    double epsilon;           /* near-minimum tolerance, >= 0; 0.1 (Efros-Leung) */
    int search_radius;        /* the symmetric search distance, pixels; 32; 0: the whole
                                 image */
    int exhaustive;           /* 1: every window at full resolution, no pyramid */
    double max_hole_fraction; /* a candidate window's missing pixels at most this; 0.1 */
    relief_pixsyn_order order; /* both */
    int tileable;             /* 1: the image is a torus (paper 003's tileable
                                 constraint): windows at a border see across it, the
                                 result repeats without seams */
    uint32_t seed;            /* the near-minimum draw; 1 */
    int batch;                /* 1 (default): Efros and Leung's order, a pixel at a
                                 time. N in 2..256: waves of up to N pixels, taken in
                                 the order's turn, none inside the full-resolution
                                 window of a pixel before it still to be copied, are
                                 searched against the same state and copied in turn:
                                 the search's candidate windows (and a coarse level's
                                 query window, a few pixels wider) do not see the same
                                 wave's copies. One device launch per wave and level;
                                 the same bits on every backend for a given N. Not
                                 with tileable (RELIEF_E_RANGE) */
    /* Called after each pixel: pixels synthesised so far of all (both
     * orders counted when both run). A non-zero answer stops the
     * synthesis: relief_pixsyn returns RELIEF_E_CANCELLED, the image
     * partly synthesised. NULL: none. */
    int (*progress)(void *ctx, size_t done, size_t total);
    void *progress_ctx;
} relief_pixsyn_params;

relief_pixsyn_params relief_pixsyn_params_default(void);

typedef struct relief_pixsyn_report {
    size_t hole_pixels;      /* to synthesise (targets) at the start */
    size_t by_synthesis;     /* copied from a matched window (the order kept) */
    size_t by_fallback;      /* the mean of the known neighbours (the order kept) */
    size_t unreached;        /* targets joined to no known pixel: left as they were */
    relief_pixsyn_order kept; /* horizontal or vertical */
    double energy[2];        /* mean weighted distance of the copies, horizontal and
                                vertical order; -1 where not run */
    size_t candidates;       /* windows scored, both orders */
    int levels;              /* pyramid levels */
    double seconds, seconds_score;
} relief_pixsyn_report;

/* Check `p` against an image of width x height: RELIEF_E_RANGE naming the
 * parameter. */
relief_status relief_pixsyn_params_validate(const relief_pixsyn_params *p, int width, int height,
                                           relief_error *err);

/* Synthesise the pixels of `img` where hole[y * width + x] != 0 and, when
 * `target` is not NULL, target[..] != 0 too (other holes stay unknown: they
 * are never matched and never filled), in place (all channels are matched;
 * real-valued rasters are expected, bit_depth 0, but any works); the
 * others keep their bits. Every target must be joined to a known pixel
 * through targets. `source` (may be NULL):
 * width x height, receives for each synthesised pixel the index y * width
 * + x of the captured pixel its value came from (through earlier copies),
 * -1 for a fallback or a pixel that was known.
 * RELIEF_E_RANGE when every pixel is missing; RELIEF_E_CANCELLED when
 * p->progress asked to stop (img and source then hold a partial result). */
relief_status relief_pixsyn(relief_raster *img, const uint8_t *hole, const uint8_t *target,
                           const relief_pixsyn_params *p, relief_patch_scorer *scorer,
                           int64_t *source, relief_pixsyn_report *rep, relief_error *err);

#endif
