/* Hole filling in images by multi-scale patch voting (issue 62): Wexler,
 * Shechtman and Irani, "Space-time completion of video" (PAMI 2007), with
 * the nearest-neighbour field found by PatchMatch (Barnes et al. 2009), as
 * Newson et al. ("Video inpainting of complex scenes", 2014) run it on
 * images.
 *
 * The image and its hole are halved into a pyramid until the hole is
 * about a patch thick; the coarsest hole is filled from its rim inwards
 * (each ring the mean of its known neighbours). Then, coarsest level
 * first, an expectation-maximisation alternates:
 *   E: every target patch (a P x P patch that holds a hole pixel) finds
 *      its nearest source patch (one inside the image that holds none),
 *      by PatchMatch's propagation and random search over every target at
 *      once (each reads the field of the step before, so the order of the
 *      targets, the threads and the device do not matter);
 *   M: every hole pixel becomes the vote of the patches that cover it,
 *      each the source's pixel at the same place, weighted by
 *      exp(-d / (2 sigma^2)) (d the patch's mean square difference per
 *      sample, sigma^2 its 75th percentile over the level's targets).
 * The field is carried to the next finer level (a source doubled), which
 * votes its first estimate. The last step at full resolution takes each
 * pixel of the hole's thick parts from the best of its covering patches
 * rather than their mean, so texture is copied, not averaged away; a thin
 * part (a scratch a few pixels wide) keeps the mean, smooth across it.
 * Every earlier vote is the mean: a best-patch vote at every step left
 * the fill a mosaic of blocks, each copied whole from another place, with
 * hard seams between them (bench/image_fill.sh's strips).
 *
 * Everything the result depends on is integer arithmetic over the
 * samples (8 or 16 bits): patch distances are exact uint64 sums, weights
 * are quantised on the host before the vote, the votes are integer
 * ratios, and the random choices come from a hash of (seed, level, step,
 * pixel): the same bytes on one thread, many, or a device.
 *
 * The patches match colour and two texture features (Newson et al.: the
 * mean |horizontal| and |vertical| grey differences about each pixel),
 * which the votes carry into the hole like colour, so a textured part of
 * the hole is filled with texture.
 *
 * Units: pixels and sample values (0..255 or 0..65535). Alpha (2 or 4
 * channels) is not matched; a filled pixel becomes opaque. */
#ifndef RELIEF_HOST_IMAGE_VOTE_FILL_H
#define RELIEF_HOST_IMAGE_VOTE_FILL_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"
#include "image/raster.h"
#include "image/vote_cl.h"

typedef struct relief_vote_params {
    int patch;        /* P, odd, 3..15 pixels (default 7) */
    int em_steps;     /* E-M steps at the coarsest level, 1..50 (default 10); finer
                         levels take fewer, at least 4 */
    int pm_steps;     /* PatchMatch iterations per E step, 1..20 (default 3) */
    uint32_t seed;    /* the random initialisation and search (default 1) */
    int threads;      /* host threads (1: the serial reference; the bytes do not
                         depend on it) */
    struct relief_progress *progress; /* NULL or told the share of the levels done */
} relief_vote_params;

relief_vote_params relief_vote_params_default(void);

/* The fields' ranges: RELIEF_E_RANGE naming the field (err->param). */
relief_status relief_vote_params_check(const relief_vote_params *p, relief_error *err);

typedef struct relief_vote_report {
    int levels;          /* pyramid levels used (1: full resolution alone) */
    size_t targets;      /* target patches at full resolution */
    size_t em_steps;     /* E-M steps, every level */
    uint64_t distances;  /* patch distances evaluated, every level */
    double seconds;
} relief_vote_report;

/* Bytes relief_vote_fill needs for a width x height image with `channels`
 * (the raster itself not included), an upper bound. */
uint64_t relief_vote_fill_estimate(int width, int height, int channels);

/* Fill the pixels of `img` (bit_depth 8 or 16) where hole[y * width + x] is
 * non-zero, in place; the others keep their values bit for bit. dev: the
 * OpenCL device the searches and votes run on (vote_cl.h), or NULL for
 * the host's p->threads: the same bytes either way.
 * RELIEF_E_RANGE when no P x P patch of the image lies outside the hole;
 * RELIEF_E_CANCELLED when the progress says so (img then untouched);
 * RELIEF_E_NOMEM. rep may be NULL. */
relief_status relief_vote_fill(relief_raster *img, const uint8_t *hole,
                               const relief_vote_params *p, relief_vote_cl *dev,
                               relief_vote_report *rep, relief_error *err);

#endif
