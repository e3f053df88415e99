/* relief_untangle (mesh/untangle.h). */
#include "mesh/untangle.h"

#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "mesh/mesh.h"
#include "mesh/mesh_check.h"

typedef struct tangle {
    double *pos;
    const double *base;
    size_t nv, first;
    const uint32_t *tri;
    size_t nt;
    uint8_t *mark; /* nv: in a crossing triangle this round */
} tangle;

/* Mark the movable vertices of hit triangles; their count. */
static size_t mark_hit(tangle *t, const uint8_t *hit)
{
    size_t n = 0;
    memset(t->mark, 0, t->nv);
    for (size_t f = 0; f < t->nt; ++f)
        for (int k = 0; hit[f] && k < 3; ++k) {
            uint32_t v = t->tri[3 * f + k];
            if (v >= t->first && !t->mark[v])
                t->mark[v] = 1, ++n;
        }
    return n;
}

static void halve(tangle *t)
{
    for (size_t v = t->first; v < t->nv; ++v)
        for (int e = 0; t->mark[v] && e < 3; ++e)
            t->pos[3 * v + e] = 0.5 * (t->pos[3 * v + e] + t->base[3 * v + e]);
}

/* Each marked vertex to its neighbours' mean (Jacobi: from the positions
 * before the round). */
static relief_status relax(tangle *t, relief_error *err)
{
    relief_mesh m = {.nv = t->nv, .nt = t->nt, .pos = t->pos, .tri = (uint32_t *)t->tri};
    relief_adjacency adj;
    double *was = malloc(t->nv * 3 * sizeof *was + 1);
    relief_status st = was ? relief_mesh_adjacency(&m, &adj, err)
                           : relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the relaxation");
    if (st != RELIEF_OK) {
        free(was);
        return st;
    }
    memcpy(was, t->pos, t->nv * 3 * sizeof *was);
    for (size_t v = t->first; v < t->nv; ++v) {
        uint32_t n = adj.start[v + 1] - adj.start[v];
        if (!t->mark[v] || !n)
            continue;
        for (int e = 0; e < 3; ++e) {
            double c = 0.0;
            for (uint32_t k = adj.start[v]; k < adj.start[v + 1]; ++k)
                c += was[3 * (size_t)adj.nbr[k] + e];
            t->pos[3 * v + e] = c / n;
        }
    }
    relief_adjacency_free(&adj);
    free(was);
    return RELIEF_OK;
}

relief_status relief_untangle(double *pos, const double *base, size_t nv, size_t first,
                              const uint32_t *tri, size_t nt, size_t *moved, size_t *left,
                              relief_error *err)
{
    tangle t = {pos, base, nv, first, tri, nt, malloc(nv + 1)};
    uint8_t *focus = malloc(nt + 1), *hit = malloc(nt + 1), *ever = calloc(nv + 1, 1);
    relief_status st = RELIEF_OK;
    int rounds = base ? 4 * RELIEF_UNTANGLE_ROUNDS : 3 * RELIEF_UNTANGLE_ROUNDS, r = 0;
    *moved = *left = 0;
    if (!t.mark || !focus || !hit || !ever) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the crossing check");
        goto done;
    }
    for (size_t f = 0; f < nt; ++f)
        focus[f] = tri[3 * f] >= first || tri[3 * f + 1] >= first || tri[3 * f + 2] >= first;
    for (;; ++r) {
        st = relief_self_intersections(pos, nv, tri, nt, focus, hit, left, err);
        if (st != RELIEF_OK || !*left || r == rounds || !mark_hit(&t, hit))
            break; /* done, out of rounds, or only fixed triangles cross */
        for (size_t v = first; v < nv; ++v)
            t.mark[v] |= ever[v];
        if (base && r < RELIEF_UNTANGLE_ROUNDS)
            halve(&t);
        else if ((st = relax(&t, err)) != RELIEF_OK)
            break;
        for (size_t v = first; v < nv; ++v)
            ever[v] |= t.mark[v];
    }
    for (size_t v = first; st == RELIEF_OK && v < nv; ++v)
        *moved += ever[v];
done:
    free(t.mark), free(focus), free(hit), free(ever);
    return st;
}
