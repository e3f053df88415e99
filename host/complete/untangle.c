/* After the growth (issue 61: no crossing where the patch meets the rim):
 * a target of a triangle that crosses another is drawn back toward its
 * base point, its displacement halved, round after round (at most
 * UNTANGLE_ROUNDS), and then moved to its neighbours' mean, round after
 * round. The base is closed
 * and faired (mesh/hole_fill.h) or the primitive; the relief grown on it,
 * copied from samples whose own neighbours differ from the target's, can
 * push a target next to the rim through the capture's triangles there.
 * Deterministic, and the same for every backend: it reads only the
 * grown mesh. */
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "complete/engine.h"
#include "mesh/mesh.h"
#include "mesh/mesh_check.h"

#define UNTANGLE_ROUNDS 6

/* Mark the targets of hit triangles; their count. */
static size_t mark(const relief_surface *s, const uint8_t *hit, uint8_t *moved)
{
    const relief_mesh *m = s->mesh;
    size_t n = 0;
    memset(moved, 0, m->nv);
    for (size_t t = 0; t < m->nt; ++t)
        for (int k = 0; hit[t] && k < 3; ++k) {
            uint32_t v = m->tri[3 * t + k];
            if (v >= s->n_samples && !moved[v])
                moved[v] = 1, ++n;
        }
    return n;
}

/* Halve the marked targets' displacement. */
static void halve(relief_surface *s, const uint8_t *moved)
{
    for (size_t v = s->n_samples; v < s->mesh->nv; ++v)
        for (int e = 0; moved[v] && e < 3; ++e) {
            double *d = s->disp + 3 * v + e;
            *d *= 0.5;
            s->mesh->pos[3 * v + e] = s->proj[3 * v + e] + *d;
        }
}

/* Where the base itself crosses (a patch faired on the smoothed base
 * meets a rim that stands off it by the capture's relief): each marked
 * target to the mean of its neighbours, the captured rim's among them. */
static relief_status relax(relief_surface *s, const uint8_t *moved, relief_error *err)
{
    relief_mesh *m = s->mesh;
    relief_adjacency adj;
    relief_status st = relief_mesh_adjacency(m, &adj, err);
    if (st != RELIEF_OK)
        return st;
    for (size_t v = s->n_samples; v < m->nv; ++v) {
        double c[3] = {0, 0, 0};
        uint32_t n = adj.start[v + 1] - adj.start[v];
        if (!moved[v] || !n)
            continue;
        for (uint32_t k = adj.start[v]; k < adj.start[v + 1]; ++k)
            for (int e = 0; e < 3; ++e)
                c[e] += m->pos[3 * (size_t)adj.nbr[k] + e] / n;
        for (int e = 0; e < 3; ++e) {
            m->pos[3 * v + e] = c[e];
            s->disp[3 * v + e] = c[e] - s->proj[3 * v + e];
        }
    }
    relief_adjacency_free(&adj);
    return RELIEF_OK;
}

relief_status relief_complete_untangle(relief_complete_run *r, relief_error *err)
{
    relief_surface *s = r->s;
    relief_mesh *m = s->mesh;
    uint8_t *focus = malloc(m->nt + 1), *hit = malloc(m->nt + 1), *moved = malloc(m->nv + 1);
    uint8_t *ever = calloc(m->nv + 1, 1);
    size_t count = 0, drawn = 0;
    int round = 0;
    relief_status st = RELIEF_OK;
    if (!focus || !hit || !moved || !ever) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the crossing check");
        goto done;
    }
    for (size_t t = 0; t < m->nt; ++t) {
        const uint32_t *f = m->tri + 3 * t;
        focus[t] = f[0] >= s->n_samples || f[1] >= s->n_samples || f[2] >= s->n_samples;
    }
    /* halving first, then relaxing */
    for (; round < 2 * UNTANGLE_ROUNDS; ++round) {
        st = relief_self_intersections(m->pos, m->nv, m->tri, m->nt, focus, hit, &count, err);
        if (st != RELIEF_OK || !count || !mark(s, hit, moved))
            break; /* done, or only the capture's own triangles cross there */
        if (round < UNTANGLE_ROUNDS)
            halve(s, moved);
        else
            st = relax(s, moved, err);
        for (size_t v = 0; st == RELIEF_OK && v < m->nv; ++v)
            ever[v] |= moved[v];
        if (st != RELIEF_OK)
            break;
    }
    if (st == RELIEF_OK && round == 2 * UNTANGLE_ROUNDS)
        st = relief_self_intersections(m->pos, m->nv, m->tri, m->nt, focus, hit, &count, err);
    for (size_t v = 0; st == RELIEF_OK && v < m->nv; ++v)
        drawn += ever[v];
    if (st == RELIEF_OK && drawn)
        relief_complete_note(r, 0, "%zu target%s drawn back toward the base, where the relief "
                             "grown on %s crossed the surface; %zu completed triangle%s still "
                             "cross%s another", drawn, drawn == 1 ? "" : "s",
                             drawn == 1 ? "it" : "them", count, count == 1 ? "" : "s",
                             count == 1 ? "es" : "");
done:
    free(focus), free(hit), free(moved), free(ever);
    return st;
}
