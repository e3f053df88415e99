/* Window scoring of the image hole filler behind one small table, as the
 * mesh matcher's backends are (match/backend.h): patch_scalar.c, the
 * reference, patch_host.c, the reference's function over a pool of host
 * threads, and patch_opencl.c, the kernel kernels/patch.cl; all score
 * through kernels/patch_math.h's pm_score, so they give the same bits.
 *
 * The filler owns the pyramid's levels; a scorer reads them where they lie
 * (scalar) or keeps a copy on its device that update() brings up to date. */
#ifndef RELIEF_HOST_IMAGE_PATCH_H
#define RELIEF_HOST_IMAGE_PATCH_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"

/* One level of the pyramid: v is height x width x channels (the channels
 * matched, alpha excluded), known height x width (1 known, 0 hole). */
typedef struct relief_patch_level {
    const float *v;
    const uint8_t *known;
    int width, height, channels;
} relief_patch_level;

typedef struct relief_patch_ops {
    /* Take the levels (the pointers stay valid until destroy). */
    relief_status (*bind)(void *ctx, const relief_patch_level *levels, int n_levels,
                          relief_error *err);
    /* Rows y0..y1 of `level` changed, values or known flags. */
    relief_status (*update)(void *ctx, int level, int y0, int y1, relief_error *err);
    /* Score every candidate centre of the rectangle x0 .. x0 + nx - 1,
     * y0 .. y0 + ny - 1 (all wholly inside the level) against the query
     * window at (qx, qy): ssd[j * nx + i], wsum[..] and n[..] as pm_score.
     * `g` (radius + 1 weights) NULL: unweighted; `wsum` may be NULL. */
    relief_status (*score_rect)(void *ctx, int level, int qx, int qy, int radius, int max_holes,
                                const float *g, int x0, int y0, int nx, int ny, float *ssd,
                                float *wsum, int *n, relief_error *err);
    /* Score the `count` candidate centres xy[2 i], xy[2 i + 1] (all wholly
     * inside the level): ssd[i], wsum[i] and n[i] as pm_score. The
     * pyramid's refinement: a few hundred scattered windows. */
    relief_status (*score_list)(void *ctx, int level, int qx, int qy, int radius,
                                int max_holes, const float *g, const int *xy, int count,
                                float *ssd, float *wsum, int *n, relief_error *err);
    void (*destroy)(void *ctx);
    /* Optional batched forms (NULL: the filler calls the ones above once
     * per query; else it calls these alone, a single query as a batch of
     * one), for a device where a call costs more than its work.
     * Many queries' rectangles at one level in one call: rectangle q is
     * rects[7 q ..] = qx, qy, x0, y0, nx, ny, offset, its scores at
     * ssd[offset + j * nx + i] (and wsum, n), `total` scores in all. */
    relief_status (*score_rects)(void *ctx, int level, int radius, int max_holes,
                                 const float *g, const int *rects, int count, size_t total,
                                 float *ssd, float *wsum, int *n, relief_error *err);
    /* Many queries' candidate centres at one level: pair i is
     * pairs[4 i ..] = qx, qy, cx, cy (all wholly inside the level), its
     * scores at ssd[i] (and wsum, n). */
    relief_status (*score_pairs)(void *ctx, int level, int radius, int max_holes,
                                 const float *g, const int *pairs, int count, float *ssd,
                                 float *wsum, int *n, relief_error *err);
    /* Optional (NULL: score_rects alone), for a device whose read-back of
     * every score costs more than the scoring: score_rects' rectangles
     * scored, but only the scores that may hold rectangle q's keep[q] best
     * matches (by msd, as the filler ranks them) read back. They come in
     * runs, run s = (*runs)[4 s ..] = q, first (the index of its first
     * score among rectangle q's, row-major), length, at (where its scores
     * lie in ssd, wsum and n): rectangle by rectangle in batch order,
     * ascending within each, *n_runs of them, in the scorer's memory until
     * its next call; at most `total` scores in all. Every score left out
     * is, by a bound with a margin far above float rounding, worse than
     * keep[q] of those read, so a ranking of the runs alone keeps the same
     * matches. */
    relief_status (*select_rects)(void *ctx, int level, int radius, int max_holes,
                                  const float *g, const int *rects, const int *keep,
                                  int count, size_t total, float *ssd, float *wsum, int *n,
                                  const int **runs, size_t *n_runs, relief_error *err);
} relief_patch_ops;

typedef struct relief_patch_scorer {
    const relief_patch_ops *ops;
    void *ctx;
    relief_backend backend; /* scalar, host or opencl */
    int threads;            /* host threads it scores on (1 but for host) */
    char device[256];       /* what it runs on, for messages and reports */
} relief_patch_scorer;

/* The scalar reference (never fails but for memory). */
relief_status relief_patch_scalar_create(relief_patch_scorer **out, relief_error *err);

/* The host scorer on `threads` threads (<= 0: the CPUs this thread may run
 * on, base/pool.h; at most RELIEF_POOL_MAX); RELIEF_E_NOMEM when its
 * threads cannot start. */
relief_status relief_patch_host_create(int threads, relief_patch_scorer **out,
                                       relief_error *err);

/* The OpenCL scorer on `device` (-1: the first GPU or accelerator, else the
 * first device). RELIEF_E_NOT_BUILT without OpenCL; RELIEF_E_DEVICE with
 * the reason; RELIEF_E_RANGE for a --device there is none of. */
relief_status relief_patch_opencl_create(int device, relief_patch_scorer **out,
                                         relief_error *err);
/* For tests and the bench: the OpenCL scorer's select_rects reads every
 * score back for a batch of fewer than `scores`, else selects; 0 always
 * selects, SIZE_MAX never. Other scorers: no effect. By default
 * RELIEF_PATCH_SELECT_FROM: one read of 768 KiB costs less than the
 * selection's second round trip on a GPU (about 25 GB/s against tens of
 * microseconds a synchronisation). */
#define RELIEF_PATCH_SELECT_FROM ((size_t)1 << 16)
void relief_patch_opencl_select_from(relief_patch_scorer *s, size_t scores);

/* The scorer for `backend`. auto: OpenCL on `device` when one is named
 * (>= 0), else the host scorer on `threads` (0: the default), GPU or not
 * (a launch per window search measured slower than the host's threads);
 * the host scorer too when the named device's OpenCL fails to start.
 * Which and why goes to `note` (may be NULL); *why (may be NULL) is
 * RELIEF_REASON_DEVICE_FELL_BACK when OpenCL failed to start (a
 * warning), else RELIEF_REASON_NONE. */
relief_status relief_patch_scorer_create(relief_backend backend, int device, int threads,
                                         relief_patch_scorer **out, char *note,
                                         size_t note_size, relief_reason *why,
                                         relief_error *err);
void relief_patch_scorer_destroy(relief_patch_scorer *s);

#endif
