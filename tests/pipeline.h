/* Test helper: a whole completion of a synthetic capture, synth -> smooth
 * -> match data -> matcher -> grow, with the knobs the tests vary. */
#ifndef RELIEF_TESTS_PIPELINE_H
#define RELIEF_TESTS_PIPELINE_H

#include "base/rng.h"
#include "base/params.h"
#include "grow/grow.h"
#include "match/matcher.h"
#include "match/matcher_opencl.h"
#include "match/matcher_scalar.h"
#include "mesh/mesh.h"
#include "smooth/surface.h"

typedef struct pipeline {
    relief_synth_kind kind;
    size_t vertices;
    int colour;
    uint32_t seed;
    int window;
    int prune;
    int bootstrap;
    int opencl; /* 1: the OpenCL matcher, 0: the scalar reference */
    relief_search_mode search; /* 0 (auto): exhaustive at these sizes */
} pipeline;

/* A synthetic capture's smooth completion with default parameters; *out
 * receives the surface (caller frees) on success. */
static inline relief_status pipeline_smooth(relief_synth_kind kind, size_t vertices, int colour,
                                            relief_surface **out, relief_error *err)
{
    relief_synth_params sp = relief_synth_params_default();
    relief_params p = relief_params_default();
    relief_mesh *cap = NULL;
    relief_status st;
    sp.kind = kind;
    sp.vertices = vertices;
    sp.colour = colour;
    *out = NULL;
    st = relief_synth(&sp, &cap, NULL, err);
    if (st == RELIEF_OK)
        st = relief_surface_build(cap, &p, NULL, out, err);
    relief_mesh_destroy(cap);
    return st;
}

/* Grow s in place: its match data (p's rotations, mu for `colour`), the
 * OpenCL matcher (opencl 1) or the scalar reference, relief_grow; the match
 * data and the matcher are freed after. */
static inline relief_status pipeline_grow(relief_surface *s, const relief_params *p,
                                          const relief_grow_options *go, int colour, int opencl,
                                          relief_grow_stats *stats, relief_error *err)
{
    relief_match_data *d = NULL;
    relief_matcher *m = NULL;
    relief_status st = relief_match_data_build(s, p->rotations, relief_grow_mu(p, colour), &d,
                                               err);
    if (st == RELIEF_OK)
        st = opencl ? relief_matcher_opencl_create(d, -1, 0, &m, err)
                    : relief_matcher_scalar_create(d, &m, err);
    if (st == RELIEF_OK)
        st = relief_grow(s, d, m, p, go, stats, err);
    relief_matcher_destroy(m);
    relief_match_data_destroy(d);
    return st;
}

/* Run it; *out receives the grown surface (caller frees) on success. */
static inline relief_status pipeline_run(const pipeline *pl, relief_surface **out,
                                         relief_grow_stats *stats, relief_error *err)
{
    relief_synth_params sp = relief_synth_params_default();
    relief_params p = relief_params_default();
    relief_grow_options go = relief_grow_options_default();
    relief_mesh *cap = NULL;
    relief_surface *s = NULL;
    relief_status st;

    sp.kind = pl->kind;
    sp.vertices = pl->vertices;
    sp.colour = pl->colour;
    p.seed = pl->seed;
    p.window = pl->window;
    p.search = pl->search;
    go.prune = pl->prune;
    go.bootstrap = pl->bootstrap;
    st = relief_synth(&sp, &cap, NULL, err);
    if (st == RELIEF_OK)
        st = relief_surface_build(cap, &p, NULL, &s, err);
    if (st == RELIEF_OK)
        st = pipeline_grow(s, &p, &go, pl->colour, pl->opencl, stats, err);
    relief_mesh_destroy(cap);
    if (st != RELIEF_OK) {
        relief_surface_destroy(s);
        return st;
    }
    *out = s;
    return RELIEF_OK;
}

/* The growth's own query (window `hops`) for a target drawn with rng until
 * it has a textured neighbour: on the first pass most targets lie deep in
 * the missing part and have none. Returns the target; q->n is 0 when
 * 10000 draws found none. */
static inline uint32_t pipeline_draw_query(relief_query_builder *qb, const relief_surface *s,
                                           const uint8_t *textured, relief_rng *rng, int hops,
                                           relief_match_query *q)
{
    uint32_t t;
    int tries = 0;
    do {
        t = (uint32_t)(s->n_samples + relief_rng_below(rng, (uint32_t)s->n_targets));
        relief_query_build(qb, textured, t, hops, q);
    } while (q->n == 0 && ++tries < 10000);
    return t;
}

#endif
