/* Hole filling in images (paper 004, chapter 3): a 1-D interpolation pass
 * along rows, then columns, where the gap's ends agree and are smooth,
 * the gap is no longer than the window and each end, over half a window
 * along the line, is no rougher (mean |second difference|) than the
 * image's median pixel (at least 1 on 0..255): texture is left to
 * copy-paste (issue 40). Then copy-paste synthesis: the hole-boundary
 * pixels in raster order, a w x w window centred on each, the best window of the same size in the
 * search region with at most 10 % holes (coarse to fine over a Gaussian
 * pyramid, or exhaustively), accepted when its RMS difference is under
 * tau, the window shrunk by 2 on a failure, and the 3 x 3 fallback last.
 *
 * A module others call (depth images, issue 20, run it on their values):
 * relief_fill works on any relief_raster and a hole mask. Window scoring
 * runs on a relief_patch_scorer (patch.h): scalar or OpenCL, the same bits.
 * Deterministic for a seed whatever the backend. */
#ifndef RELIEF_HOST_IMAGE_FILL_H
#define RELIEF_HOST_IMAGE_FILL_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"
#include "image/patch.h"
#include "image/raster.h"

#define RELIEF_FILL_MAX_LEVELS 8

typedef struct relief_fill_params {
    int window;               /* starting w, odd, 3..1025; 17 (paper: 129 for atlases) */
    int min_window;           /* smallest w tried before the fallback, odd, 3..window; 5 */
    double tau;               /* accept when RMS < tau, in the values' units; <= 0: 36
                                 on 0..255, scaled to the image's range (x 257 at 16 bits) */
    double max_hole_fraction; /* a candidate window's hole pixels at most this; 0.1 */
    int search_radius;        /* search region: the (2 r + 1)^2 window of the same centre,
                                 pixels at full resolution; 0 = the whole image */
    int exhaustive;           /* 1: every window at full resolution, no pyramid */
    int interp;               /* 1: the 1-D pass first (default) */
    double interp_diff;       /* a gap's two ends differ by at most this in every channel;
                                 < 0: 16 on 0..255, scaled */
    double interp_sd;         /* the standard deviation of interp_span pixels beyond each
                                 end at most this in every channel; < 0: 3 on 0..255, scaled */
    int interp_span;          /* 4 */
    int pyramid_side;         /* halve until both sides <= this; 128 */
    int pyramid_levels;       /* or this many halvings were made; 4 */
    int region_pixels;        /* the search starts at the first level whose search region
                                 has fewer candidates than this; 4096 */
    int window_pixels;        /* or whose window has fewer pixels than this; 25 */
    uint32_t seed;            /* the fallback's random choice */
    /* NULL, or told after the 1-D pass and after each paste or fallback
     * the share of the hole pixels filled (base/progress.h); once it says
     * cancelled, relief_fill stops with RELIEF_E_CANCELLED. */
    struct relief_progress *progress;
} relief_fill_params;

relief_fill_params relief_fill_params_default(void);

/* Check the fields alone (ranges, odd windows, finite thresholds):
 * RELIEF_E_RANGE naming the field as spelt here and its range, and in
 * err->param (relief_image_fill_params's fields have the same names). */
relief_status relief_fill_params_check(const relief_fill_params *p, relief_error *err);

/* The thresholds used for values of `bit_depth` bits (0: real-valued):
 * tau, the 1-D pass's end difference and standard deviation, each the
 * parameter when set, else its default on 0..255 scaled (x 257 at 16
 * bits). Any output may be NULL. */
void relief_fill_thresholds(const relief_fill_params *p, int bit_depth, double *tau,
                            double *diff, double *sd);

typedef struct relief_fill_report {
    size_t hole_pixels;                  /* holes at the start */
    size_t by_rows, by_columns;          /* filled by the 1-D pass */
    size_t by_copy, by_fallback;         /* filled by copy-paste, by the 3 x 3 fallback */
    size_t queries;                      /* boundary pixels a search started from */
    size_t searches;                     /* window searches, every size */
    size_t accepted;                     /* of them, matches under tau */
    size_t candidates;                   /* windows scored, all levels */
    size_t scores_read;                  /* of their scores, those the scorer handed back
                                            (fewer where a device ranks them first) */
    int levels;                          /* pyramid levels (1: full resolution only) */
    int start_level;                     /* where the first window size's search starts */
    int top_m;                           /* matches kept there (4 x start level) */
    double tau;                          /* the acceptance threshold used */
    double interp_diff, interp_sd;       /* the 1-D pass's thresholds used */
    double interp_roughness[4];          /* and its roughness limit per colour channel
                                            (0 where the pass did not run) */
    double seconds_interp, seconds_copy; /* the two stages */
    double seconds_score;                /* of which scoring windows */
} relief_fill_report;

/* One window match: the candidate's centre at full resolution and its
 * score: ssd over n pixels known in both (mean square difference
 * msd = ssd / n over the matched channels; rms = sqrt(msd / channels)). */
typedef struct relief_window_match {
    int x, y;
    float ssd;
    int n;
    double msd;
} relief_window_match;

/* relief_fill_params_check, and the windows against an image of width x
 * height: RELIEF_E_RANGE naming the parameter. */
relief_status relief_fill_params_validate(const relief_fill_params *p, int width, int height,
                                          relief_error *err);

/* Bytes of host memory relief_fill needs for a width x height x channels
 * image, the raster itself included. */
uint64_t relief_fill_estimate(int width, int height, int channels);

/* Fill the pixels of `img` where hole[y * width + x] != 0, in place; the
 * others keep their values bit for bit. Alpha (2 or 4 channels) is not
 * matched; a filled pixel becomes opaque. RELIEF_E_RANGE when every pixel
 * is a hole, or when no min_window window of the image has at most
 * max_hole_fraction holes; RELIEF_E_CANCELLED when p->progress says so
 * (img then half filled: callers fill a copy). `rep` (may be NULL) is
 * filled. */
relief_status relief_fill(relief_raster *img, const uint8_t *hole, const relief_fill_params *p,
                          relief_patch_scorer *scorer, relief_fill_report *rep,
                          relief_error *err);

/* For tests and the bench: the filler's state after the 1-D pass, so that
 * single searches can be compared. */
typedef struct relief_filler relief_filler;
relief_status relief_filler_create(relief_raster *img, const uint8_t *hole,
                                   const relief_fill_params *p, relief_patch_scorer *scorer,
                                   relief_filler **out, relief_error *err);
/* The best window for the query centred at (px, py) with window w:
 * exhaustive (every position at full resolution) or through the pyramid.
 * *found 0 when no candidate qualifies. `coarse` (may be NULL, room for
 * RELIEF_FILL_MAX_TOP) receives the pyramid's kept matches at its start
 * level, mapped to full resolution, and *n_coarse their number. */
#define RELIEF_FILL_MAX_TOP 32
relief_status relief_filler_search(relief_filler *f, int px, int py, int w, int exhaustive,
                                   relief_window_match *best, int *found,
                                   relief_window_match *coarse, int *n_coarse,
                                   relief_error *err);
/* The same, keeping the `keep` (1..RELIEF_FILL_MAX_TOP) best matches at
 * full resolution in best[0 .. *n_best), ordered by msd, then row-major;
 * sigma > 0 weights the windows' pixels by a Gaussian of sigma pixels
 * around the centre (paper 003's weighted mean square distance; sigma / 2^l
 * at level l), sigma <= 0 does not. */
relief_status relief_filler_search_top(relief_filler *f, int px, int py, int w, int exhaustive,
                                       double sigma, relief_window_match *best, int keep,
                                       int *n_best, relief_window_match *coarse, int *n_coarse,
                                       relief_error *err);
/* The searches of `count` queries centred at (pxy[2 k], pxy[2 k + 1]), as
 * relief_filler_search_top gives each (no coarse matches): query k's best
 * in best[k * keep .. k * keep + n_best[k]). Each level's windows are
 * scored in one call for all the queries where the scorer batches
 * (patch.h's score_rects, score_pairs), so a device pays a launch per level
 * rather than per query; the results are each query's own search's, bit
 * for bit. The queries must be independent: none may need a pixel another
 * is about to fill. */
relief_status relief_filler_search_batch(relief_filler *f, int count, const int *pxy, int w,
                                         int exhaustive, double sigma, int keep,
                                         relief_window_match *best, int *n_best,
                                         relief_error *err);
/* The distance (pixels, either axis) within which a filled pixel can
 * change a search at a pixel with window w: the search region, the window
 * and the pyramid's reach. Searches farther apart than this from every
 * pixel filled meanwhile give the same matches. */
int relief_filler_reach(const relief_filler *f, int w);
/* Set the hole pixel (x, y) to value[0 .. channels matched) and make it
 * known, in the image, the pyramid and the scorer. */
relief_status relief_filler_put(relief_filler *f, int x, int y, const float *value,
                                relief_error *err);
/* The pyramid's levels; the windows scored so far and the seconds spent
 * scoring them (*seconds may be NULL). */
int relief_filler_levels(const relief_filler *f);
size_t relief_filler_candidates(const relief_filler *f, double *seconds);
/* Of those windows' scores, how many the scorer read back to the host:
 * all but where its select_rects ranked them on the device first. */
size_t relief_filler_scores_read(const relief_filler *f);
void relief_filler_destroy(relief_filler *f);

/* The 1-D pass alone on `img` (holes filled are cleared in `hole`): for
 * tests. Returns the pixels filled by rows and by columns, and (when
 * roughness is not NULL) the largest end roughness it took in each colour
 * channel, sample units (relief_fill_report.interp_roughness). */
void relief_fill_interp(relief_raster *img, uint8_t *hole, const relief_fill_params *p,
                        size_t *by_rows, size_t *by_columns, double *roughness);

#endif
