/* Growth of relief and colour over the targets (stage 6 of DESIGN.md;
 * paper 000 section 3 and appendix A). */
#ifndef RELIEF_HOST_GROW_H
#define RELIEF_HOST_GROW_H

#include <signal.h>
#include <stddef.h>
#include <stdint.h>

#include "base/rng.h"
#include "base/params.h"
#include "match/matcher.h"
#include "smooth/surface.h"

typedef struct relief_grow_stats {
    size_t targets;           /* to texture */
    size_t passes;            /* boundary lists built */
    size_t candidates;        /* (sample, rotation) pairs scored */
    size_t pruned;            /* of which stopped early by the cutoff */
    size_t invalid;           /* of which mapped onto an unmatchable vertex */
    size_t acceptances;
    size_t rejections;        /* nothing that passes e, or a draw at or above it */
    size_t no_candidate;      /* of the rejections: every candidate invalid */
    size_t threshold_raises;  /* passes with no acceptance: e *= 1.1 */
    size_t coherent;          /* of the acceptances: coherent candidates */
    size_t window_shrinks;
    size_t pyramid_hits;      /* sample pyramids: targets accepted from their box */
    size_t pyramid_misses;    /* boxes where nothing passed e: all samples scored */
    size_t pyramid_empty;     /* targets with no box or an empty one: all samples */
    size_t search;            /* the search used, a relief_search_mode (auto
                                 resolved); size_t as every count here, so
                                 the checkpoint's copy has no padding */
    size_t search_hits;       /* coherent search: targets accepted from the
                                 continuations */
    size_t search_misses;     /* continuations where nothing passed e: all
                                 samples scored */
    size_t search_empty;      /* targets with no continuation: all samples */
    size_t search_centres;    /* continuations listed, summed over targets */
    double search_seconds;    /* building the search (descriptors, index) */
    double error_final;       /* e at the end */
    double b_shape;           /* the shape bound used (input units) */
    double mu;                /* the shape weight used */
    double seconds;           /* wall time of the growth */
    double match_seconds;     /* of which in the matcher */
} relief_grow_stats;

/* Where a run is, for a progress line. */
typedef struct relief_grow_progress {
    size_t done, total;
    double error;
    double seconds;
    int level, levels; /* the growth is level `level` (0-based) of `levels` */
} relief_grow_progress;

typedef void (*relief_grow_progress_fn)(void *ctx, const relief_grow_progress *p);

/* Everything a growth stopped between two targets needs to continue to the
 * same result (checkpoint.h writes and reads it). Per-vertex arrays cover
 * the targets only: entry i is vertex n_samples + i. Filled by relief_grow
 * for a save callback (valid during the call only), or by
 * relief_checkpoint_read for opts.resume (owned by the checkpoint). */
struct relief_hierarchy_state; /* hierarchy.h */

typedef struct relief_grow_state {
    size_t nv;                /* vertices of the surface */
    size_t n_samples;         /* vertices 0..n_samples-1 are the samples */
    const uint8_t *textured;  /* n_targets: 1 once textured */
    const int *window;        /* n_targets: the target's current window W_t,
                                 edge hops, 1..16 */
    const double *disp;       /* n_targets x 3: displacement D (input units;
                                 0 while untextured) */
    const float *colour;      /* n_targets x 3: colour the matcher reads, in
                                 [0, 1] (grey when the capture has none) */
    const float *mesh_colour; /* n_targets x 3, or NULL when the mesh has no
                                 colour: the colour written out */
    size_t n_list;            /* the current pass's boundary list: */
    const uint32_t *list;     /* n_list vertex ids, in the pass's order */
    size_t next;              /* list[next] is the next target, < n_list */
    size_t pass_accepted;     /* acceptances so far in this pass */
    int pass_any_valid;       /* 1 once a target of this pass had a valid
                                 candidate */
    int pass_all_min_window;  /* 1 while every rejection in this pass left a
                                 window of 1 */
    double error;             /* e now */
    relief_rng rng;           /* the draw's MT19937, mid-sequence */
    relief_grow_stats stats;  /* counts so far (seconds: the growth's wall
                                 time so far) */
    const uint32_t *source;   /* n_targets: the candidate each textured target
                                 copied, sample vertex x R + rotation
                                 (UINT32_MAX while untextured): where its
                                 coherent candidates come from */
    const uint32_t *matched;  /* n_targets: the sample vertex each textured
                                 target copied (UINT32_MAX - 1 while
                                 untextured), when the growth keeps it
                                 (opts.matched, a hierarchy's level); else
                                 NULL */
    /* A hierarchical run's place (hierarchy.h), or NULL for a mono-scale
     * growth: relief_grow leaves it NULL, a hierarchy's levels set it. */
    const struct relief_hierarchy_state *hier;
} relief_grow_state;

typedef relief_status (*relief_grow_save_fn)(void *ctx, const relief_grow_state *state,
                                             relief_error *err);

typedef struct relief_grow_options {
    int prune;      /* 1: stop a candidate once it cannot enter the best set */
    int bootstrap;  /* 1: textured targets become matchable */
    relief_grow_progress_fn progress; /* may be NULL; called after each target,
                                         accepted or rejected */
    void *progress_ctx;
    int level, levels;  /* where this growth sits in a hierarchy, passed on in
                           its progress: level 0 (default) of 1 */
    /* Sample pyramids (hierarchy.h; may be NULL): target t first scores only
     * the samples pyramid_items[pyramid_start[t] .. pyramid_start[t + 1])
     * (indices into the match data's samples, distinct); when that range is
     * empty or its draw does not pass e, every sample. nv + 1 entries. */
    const uint32_t *pyramid_start, *pyramid_items;
    /* May be NULL; else nv entries: each accepted target's entry is set to
     * the sample vertex it copied from. */
    uint32_t *matched;
    /* Stop between two targets once *cancel is non-zero (may be NULL): the
     * CLI's SIGINT handler sets it. The growth then calls save (when set)
     * and returns RELIEF_E_CANCELLED. */
    volatile sig_atomic_t *cancel;
    /* Called with the state when the growth is cancelled or fails on the
     * device, and every save_every seconds (0: only then). May be NULL. */
    relief_grow_save_fn save;
    void *save_ctx;
    double save_every;
    /* Continue from a saved state instead of from the start (may be NULL).
     * The surface, match data and matcher must be built from the same input
     * and parameters as the saved run's (the checkpoint's fingerprint says
     * so): the result is then byte-identical to an uninterrupted run. */
    const relief_grow_state *resume;
    /* Test hook: behave as if *cancel were set once this many targets have
     * been accepted in this run (0: never). */
    size_t cancel_after;
} relief_grow_options;

relief_grow_options relief_grow_options_default(void);

/* Builds a target's neighbourhood query exactly as the growth does: the
 * textured vertices within `hops` edges of it (itself excluded), in its
 * frame, heaviest Gaussian weight first (ties: vertex id). Tests and the
 * bench use it so that they score what the growth scores. */
typedef struct relief_query_builder relief_query_builder;

relief_status relief_query_builder_create(const relief_surface *s, const relief_match_data *d,
                                          relief_query_builder **out, relief_error *err);
void relief_query_builder_destroy(relief_query_builder *b);

/* 1 when some 1-ring neighbour of t is textured (t is on the boundary). */
int relief_query_has_textured_neighbour(const relief_query_builder *b,
                                        const uint8_t *textured, uint32_t t);

/* Textured vertices within `hops` of t: the boundary list's ranking key. */
size_t relief_query_count(relief_query_builder *b, const uint8_t *textured, uint32_t t,
                          int hops);

/* Fill *query for target t (textured[v] != 0 marks textured vertices; the
 * surface's current positions and the match data's colours are read).
 * The arrays belong to the builder and stay valid until its next call;
 * cutoff is FLT_MAX and running 0. query->n is 0 when t has no textured
 * vertex within reach. */
void relief_query_build(relief_query_builder *b, const uint8_t *textured, uint32_t t, int hops,
                        relief_match_query *query);

/* Grow the targets of `s` in place: positions p = p' + D and colours of the
 * targets change; labels stay (1 completed). `params` gives W, R, e, mu
 * (<0: 1 without colour, 0.5 with) and the seed. The matcher must have been
 * made for `d`, built from `s`. RELIEF_E_MESH when targets can never be
 * reached or no sample has a neighbourhood that matches at all;
 * RELIEF_E_CANCELLED when opts->cancel stopped it (after opts->save). */
relief_status relief_grow(relief_surface *s, relief_match_data *d, relief_matcher *m,
                          const relief_params *params, const relief_grow_options *opts,
                          relief_grow_stats *stats, relief_error *err);

/* The shape weight actually used for `params` on a surface with or without
 * colour. */
double relief_grow_mu(const relief_params *params, int has_colour);

#endif
