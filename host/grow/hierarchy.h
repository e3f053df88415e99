/* Hierarchical completion (stage 7 of DESIGN.md; paper 001 section 3).
 *
 * An M-level hierarchy of the combined surface: level M is the surface
 * itself, level k < M about k/M of its vertices, spread evenly (a nested
 * Poisson-disc selection on the primitive, so a vertex of level k is a
 * vertex of every finer level: the discrete levels of a progressive mesh),
 * re-triangulated as the smooth completion triangulates (on a free-form
 * base, paper 002's: the base's own triangles collapsed onto the
 * selection). Each vertex keeps
 * its own label at every level; a vertex new at level k descends from the
 * nearest vertex of level k-1 (its parent).
 *
 * Relief is a height along the primitive's normal (a free-form base's
 * own). Level 1 grows the heights over the primitive (level 0); level k
 * grows them over the completed, smoothed level k-1 surface (001 figure 4):
 * its base, at each vertex the Gaussian mean (sigma level k-1's mean edge,
 * out to 3 sigma) of level k-1's completed heights around it. That is 001's
 * smoothing after levels 1..M-1 (section 3.5, samples and targets alike)
 * and the projection on the smoothed surface in one step, and it treats a
 * vertex the same whether or not it was at level k-1 and whatever the
 * density around it: interpolating over level k-1's triangles instead made
 * the targets' bases weaker than the samples' (most level 2 targets are
 * new, most samples are not, as the capture is denser than the target
 * lattice), and the bark's completed relief 8 % weaker at M = 4. The
 * samples of a level k < M carry their captured height low-passed at that
 * level's scale (the Gaussian mean of the capture's heights, sigma half the
 * level's mean edge), as an image pyramid filters before it subsamples: the
 * full relief on vertices that far apart aliases into false coarse
 * structure, which the finer levels then cannot undo. At level M the
 * samples are where they were captured, so the levels' displacements sum
 * to the capture. Each level runs the mono-scale growth (grow.h) with the
 * same matcher backends. Sample pyramids: at level k >= 2 a
 * target first considers only the samples inside the axis-aligned box of
 * the samples within W hops of the sample its parent matched at level k-1
 * (found with a FLANN kd-tree), and all samples when the box is empty or
 * nothing in it passes e. A target whose parent is a sample (on the hole's
 * rim) follows the match of the level k-1 target nearest its parent, within
 * W hops. */
#ifndef RELIEF_HOST_HIERARCHY_H
#define RELIEF_HOST_HIERARCHY_H

#include <stddef.h>
#include <stdint.h>

#include "grow/grow.h"
#include "base/params.h"
#include "smooth/surface.h"

#define RELIEF_MAX_LEVELS 8

typedef struct relief_hierarchy {
    int levels;               /* M */
    const relief_surface *full; /* the surface it was built from (borrowed) */
    uint8_t *first_level;     /* full nv: the coarsest level (1..M) holding v */
    /* Per level k = 1..M at index k - 1. Level M is `full` itself. */
    relief_surface *level[RELIEF_MAX_LEVELS]; /* owned for k < M */
    uint32_t *ids[RELIEF_MAX_LEVELS];    /* level nv: the vertex's id in full */
    double radius[RELIEF_MAX_LEVELS];    /* the selection's disc radius (input
                                            units; 0 at level M) */
    double sigma[RELIEF_MAX_LEVELS];     /* the level's mean edge length on the
                                            base (input units): its Gaussians'
                                            scale */
    /* For k >= 2, per vertex of level k (level-local ids), the level k-1
     * vertex it descends from: itself when present, else the nearest. */
    uint32_t *parent[RELIEF_MAX_LEVELS];
} relief_hierarchy;

/* Build the M-level hierarchy of s (2 <= levels <= RELIEF_MAX_LEVELS). */
relief_status relief_hierarchy_build(const relief_surface *s, int levels,
                                     relief_hierarchy **out, relief_error *err);
void relief_hierarchy_destroy(relief_hierarchy *h);

/* What one level did. */
typedef struct relief_level_stats {
    size_t vertices, samples, targets;
    size_t boxes;         /* targets given a sample-pyramid box */
    double box_samples;   /* mean samples per box */
    relief_grow_stats grow; /* its growth (pyramid_hits: restricted matches;
                               pyramid_misses + pyramid_empty: fallbacks) */
    double seconds;       /* setup, growth and smoothing */
} relief_level_stats;

/* Where a hierarchical run is, for a checkpoint (checkpoint.h): the level
 * in progress and what it takes from the finished ones. Its growth's own
 * state is the relief_grow_state that points here. */
typedef struct relief_hierarchy_state {
    int levels;                     /* M */
    int level;                      /* the level in progress, 1..M */
    size_t prev_nv;                 /* vertices of level - 1 (0 at level 1) */
    const double *heights_prev;     /* prev_nv: level - 1's completed heights
                                       over the primitive (input units) */
    const uint32_t *match_prev;     /* prev_nv: the level - 1 sample each of
                                       its vertices copied (>= UINT32_MAX - 1:
                                       none, a sample) */
    const relief_level_stats *done; /* level - 1 entries: the finished levels */
} relief_hierarchy_state;

typedef struct relief_hierarchy_stats {
    int levels;
    double build_seconds;
    relief_level_stats level[RELIEF_MAX_LEVELS];
    /* Why auto left the OpenCL device during the run (the matcher's
     * fallback_note), else "". */
    char fallback[RELIEF_ERROR_MESSAGE_MAX + 192];
    /* RELIEF_REASON_DEVICE_FELL_BACK when auto's choice (the note) is
     * OpenCL unavailable, a warning; else RELIEF_REASON_NONE. */
    relief_reason backend_reason;
} relief_hierarchy_stats;

/* Heights along the normal (input units) of one level's vertices, kept for
 * inspection and tests: base[v] is the level k-1 surface under v (0 at
 * level 1), disp[v] the displacement grown (targets) or measured (samples)
 * over it; base + disp is what level k+1's bases are smoothed from. */
typedef struct relief_level_heights {
    double *base, *disp;
} relief_level_heights;

/* Options of a hierarchical run. */
typedef struct relief_hierarchy_options {
    relief_backend backend;   /* per level, as relief_matcher_create */
    int device;
    int threads;              /* host threads (0: the default) */
    int pyramids;             /* 1 (default): sample pyramids; 0: every
                                 target scores every sample at every level */
    relief_level_heights *heights; /* NULL, or RELIEF_MAX_LEVELS entries the
                                      run fills (caller frees the arrays) */
} relief_hierarchy_options;

relief_hierarchy_options relief_hierarchy_options_default(void);

/* Complete s's targets through the hierarchy h built from s: on return
 * s's targets hold their final positions and colours (as relief_grow leaves
 * them), s->proj and s->disp are relative to the primitive again, and the
 * samples are where they were. `go` as for relief_grow (progress, pruning,
 * bootstrap, cancel; its pyramid and matched fields are the hierarchy's
 * own). Its save callback receives each level's growth state with `hier`
 * set; go->resume, such a state read back (with the same input and
 * parameters), continues the run at its level to the same result as a run
 * never stopped (RELIEF_E_USAGE for a mono-scale or another hierarchy's
 * state, or with ho->heights). On failure `total` holds the finished
 * levels and the one that stopped.
 * `total` sums the levels' growth; `device` receives the last level's
 * matcher description and `note` (may be NULL) auto's choice of backend
 * and why (relief_matcher_create); hs->fallback why auto left the device
 * during the run. */
relief_status relief_hierarchy_grow(relief_hierarchy *h, relief_surface *s,
                                    const relief_params *params,
                                    const relief_grow_options *go,
                                    const relief_hierarchy_options *ho,
                                    relief_hierarchy_stats *hs, relief_grow_stats *total,
                                    relief_backend *backend, char *device, size_t device_size,
                                    char *note, size_t note_size, relief_error *err);

#endif
