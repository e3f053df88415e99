/* Growth of relief and colour over the targets (stage 6 of DESIGN.md;
 * paper 000 section 3 and appendix A). */
#ifndef RELIEF_HOST_GROW_H
#define RELIEF_HOST_GROW_H

#include <stddef.h>

#include "matcher.h"
#include "surface.h"

typedef struct relief_grow_stats {
    size_t targets;           /* to texture */
    size_t passes;            /* boundary lists built */
    size_t candidates;        /* (sample, rotation) pairs scored */
    size_t pruned;            /* of which stopped early by the cutoff */
    size_t invalid;           /* of which mapped onto an unmatchable vertex */
    size_t acceptances;
    size_t rejections;        /* draws at or above e, or no valid candidate */
    size_t no_candidate;      /* of the rejections: no valid candidate at all */
    size_t threshold_raises;  /* passes with no acceptance: e *= 1.1 */
    size_t window_shrinks;
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
} relief_grow_progress;

typedef void (*relief_grow_progress_fn)(void *ctx, const relief_grow_progress *p);

typedef struct relief_grow_options {
    int prune;      /* 1: stop a candidate once it cannot enter the best set */
    int bootstrap;  /* 1: textured targets become matchable */
    relief_grow_progress_fn progress; /* may be NULL; called after each target */
    void *progress_ctx;
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
 * reached or no sample has a neighbourhood that matches at all. */
relief_status relief_grow(relief_surface *s, relief_match_data *d, relief_matcher *m,
                          const relief_params *params, const relief_grow_options *opts,
                          relief_grow_stats *stats, relief_error *err);

/* The shape weight actually used for `params` on a surface with or without
 * colour. */
double relief_grow_mu(const relief_params *params, int has_colour);

#endif
