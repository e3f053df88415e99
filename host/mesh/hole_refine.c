/* Step 2 of mesh/hole_fill.h: Liepa's refinement. A triangle whose
 * centroid is farther than sigma / 1.7 from each corner (sigma: the
 * corners' wanted edge lengths and their mean at the centroid) is split
 * there, and the patch's inner edges are flipped to Delaunay (opposite
 * angles summing to at most pi), until a pass splits nothing. The patch's
 * edges sit in a hash map from the vertex pair to its two triangles; the
 * rim's edges have one (the mesh holds the other side) and the mesh's
 * edges between rim vertices are in the map as blocked, so that no flip
 * makes one of them twice. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/vec3.h"
#include "mesh/hole_fill_internal.h"

#define KEY_EMPTY UINT64_MAX
#define KEY_GONE (UINT64_MAX - 1)
#define BLOCKED (-2)

typedef struct edge_slot {
    uint64_t key;
    int32_t t[2]; /* the triangles on the edge, -1 none, BLOCKED: a mesh edge */
} edge_slot;

typedef struct edge_map {
    edge_slot *s;
    size_t cap, used; /* used: live and gone slots */
} edge_map;

static uint64_t edge_key(uint32_t a, uint32_t b)
{
    return a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
}

static size_t slot_of(const edge_map *m, uint64_t key)
{
    size_t i = (size_t)((key * 0x9E3779B97F4A7C15ull) >> 20) & (m->cap - 1);
    while (m->s[i].key != KEY_EMPTY && m->s[i].key != key)
        i = (i + 1) & (m->cap - 1);
    return i;
}

static edge_slot *edge_find(edge_map *m, uint32_t a, uint32_t b)
{
    size_t i = slot_of(m, edge_key(a, b));
    return m->s[i].key == KEY_EMPTY ? NULL : &m->s[i];
}

static int map_grow(edge_map *m)
{
    edge_map g = {malloc(m->cap * 2 * sizeof *g.s), m->cap * 2, 0};
    if (!g.s)
        return 0;
    for (size_t i = 0; i < g.cap; ++i)
        g.s[i].key = KEY_EMPTY;
    for (size_t i = 0; i < m->cap; ++i)
        if (m->s[i].key < KEY_GONE) {
            g.s[slot_of(&g, m->s[i].key)] = m->s[i];
            ++g.used;
        }
    free(m->s);
    *m = g;
    return 1;
}

/* The edge's slot, made (no triangles) when absent; NULL: no memory. */
static edge_slot *edge_add(edge_map *m, uint32_t a, uint32_t b)
{
    uint64_t key = edge_key(a, b);
    size_t i;
    if (2 * (m->used + 1) > m->cap && !map_grow(m))
        return NULL;
    i = slot_of(m, key);
    if (m->s[i].key == KEY_EMPTY) {
        m->s[i].key = key, m->s[i].t[0] = m->s[i].t[1] = -1;
        ++m->used;
    }
    return &m->s[i];
}

/* Put triangle t on edge (a, b), or move it there from `from`. */
static int edge_put(edge_map *m, uint32_t a, uint32_t b, int32_t t, int32_t from)
{
    edge_slot *e = edge_add(m, a, b);
    if (!e)
        return 0;
    if (from >= 0 && (e->t[0] == from || e->t[1] == from))
        e->t[e->t[0] == from ? 0 : 1] = t;
    else
        e->t[e->t[0] < 0 && e->t[0] != BLOCKED ? 0 : 1] = t;
    return 1;
}

static int map_make(edge_map *m, const hole_patch *p)
{
    m->cap = 64, m->used = 0;
    while (m->cap < 8 * (p->nt + p->n_blocked + 8))
        m->cap *= 2;
    m->s = malloc(m->cap * sizeof *m->s);
    if (!m->s)
        return 0;
    for (size_t i = 0; i < m->cap; ++i)
        m->s[i].key = KEY_EMPTY;
    for (size_t i = 0; i < p->n_blocked; ++i) {
        edge_slot *e = edge_add(m, p->blocked[2 * i], p->blocked[2 * i + 1]);
        if (!e)
            return 0;
        e->t[0] = e->t[1] = BLOCKED;
    }
    for (size_t t = 0; t < p->nt; ++t)
        for (int c = 0; c < 3; ++c)
            if (!edge_put(m, p->t[3 * t + c], p->t[3 * t + (c + 1) % 3], (int32_t)t, -1))
                return 0;
    return 1;
}

/* The angle at vertex c of triangle (a, b, c). */
static double corner(const double *x, uint32_t a, uint32_t b, uint32_t c)
{
    double u[3], v[3], w[3];
    sub3(x + 3 * a, x + 3 * c, u), sub3(x + 3 * b, x + 3 * c, v);
    cross3(u, v, w);
    return atan2(sqrt(dot3(w, w)), dot3(u, v));
}

static void tri_cross(const double *x, uint32_t a, uint32_t b, uint32_t c, double *n)
{
    double u[3], v[3];
    sub3(x + 3 * b, x + 3 * a, u), sub3(x + 3 * c, x + 3 * a, v);
    cross3(u, v, n);
}

/* Where in t the directed edge a -> b starts (0..2), or -1. */
static int directed_at(const uint32_t *t, uint32_t a, uint32_t b)
{
    for (int c = 0; c < 3; ++c)
        if (t[c] == a && t[(c + 1) % 3] == b)
            return c;
    return -1;
}

/* Flip edge (a, b) when it is not Delaunay and the flip folds nothing.
 * 1 flipped, 0 not, -1 no memory. */
static int relax(hole_patch *p, edge_map *m, uint32_t a, uint32_t b)
{
    edge_slot *e = edge_find(m, a, b);
    int32_t t0, t1;
    uint32_t c, d, *T0, *T1;
    double n0[3], n1[3], s[3], m0[3], m1[3];
    if (!e || e->t[0] < 0 || e->t[1] < 0)
        return 0;
    t0 = e->t[0], t1 = e->t[1];
    if (directed_at(p->t + 3 * t0, a, b) < 0) {
        int32_t sw = t0;
        t0 = t1, t1 = sw;
    }
    T0 = p->t + 3 * t0, T1 = p->t + 3 * t1;
    c = T0[(directed_at(T0, a, b) + 2) % 3], d = T1[(directed_at(T1, b, a) + 2) % 3];
    if (c == d || edge_find(m, c, d))
        return 0;
    if (corner(p->x, a, b, c) + corner(p->x, b, a, d) <= RELIEF_PI + 1e-9)
        return 0;
    tri_cross(p->x, a, b, c, n0), tri_cross(p->x, b, a, d, n1);
    for (int k = 0; k < 3; ++k)
        s[k] = n0[k] + n1[k];
    tri_cross(p->x, a, d, c, m0), tri_cross(p->x, d, b, c, m1);
    if (dot3(m0, s) <= 0.0 || dot3(m1, s) <= 0.0)
        return 0;
    e->key = KEY_GONE; /* (a, b) goes, (c, d) comes */
    T0[0] = a, T0[1] = d, T0[2] = c;
    T1[0] = d, T1[1] = b, T1[2] = c;
    if (!edge_put(m, a, d, t0, t1) || !edge_put(m, b, c, t1, t0))
        return -1;
    e = edge_add(m, c, d);
    if (!e)
        return -1;
    e->t[0] = t0, e->t[1] = t1;
    return 1;
}

/* Split triangle t at its centroid when Liepa's rule asks. 1 split, 0
 * not, -1 no memory. */
static int split(hole_patch *p, edge_map *m, size_t t)
{
    /* Liepa's sqrt 2 leaves a regular grid's hole at 60 % of the grid's
     * vertex density (27 vertices where it had 43: test_hole_fill); 1.7
     * gives it back, one target where the capture would have had a
     * sample, which the growth copies one to one */
    const double alpha = 1.7;
    uint32_t v[3] = {p->t[3 * t], p->t[3 * t + 1], p->t[3 * t + 2]}, c;
    double ctr[3] = {0, 0, 0}, sc = 0.0;
    int32_t u, w;
    for (int k = 0; k < 3; ++k) {
        for (int e = 0; e < 3; ++e)
            ctr[e] += p->x[3 * v[k] + e] / 3.0;
        sc += p->sigma[v[k]] / 3.0;
    }
    if (!(sc > 0.0))
        return 0;
    for (int k = 0; k < 3; ++k) {
        double d[3], len;
        sub3(ctr, p->x + 3 * v[k], d);
        len = alpha * sqrt(dot3(d, d));
        if (len <= sc || len <= p->sigma[v[k]])
            return 0;
    }
    if (!hole_patch_reserve(p, 1, 2))
        return -1;
    c = (uint32_t)p->nx++;
    memcpy(p->x + 3 * c, ctr, sizeof ctr);
    p->sigma[c] = sc;
    u = (int32_t)p->nt, w = (int32_t)p->nt + 1;
    p->nt += 2;
    p->t[3 * t + 2] = c;
    p->t[3 * u] = v[1], p->t[3 * u + 1] = v[2], p->t[3 * u + 2] = c;
    p->t[3 * w] = v[2], p->t[3 * w + 1] = v[0], p->t[3 * w + 2] = c;
    if (!edge_put(m, v[1], v[2], u, (int32_t)t) || !edge_put(m, v[2], v[0], w, (int32_t)t) ||
        !edge_put(m, v[0], c, (int32_t)t, -1) || !edge_put(m, v[0], c, w, -1) ||
        !edge_put(m, v[1], c, (int32_t)t, -1) || !edge_put(m, v[1], c, u, -1) ||
        !edge_put(m, v[2], c, u, -1) || !edge_put(m, v[2], c, w, -1))
        return -1;
    for (int k = 0; k < 3; ++k)
        if (relax(p, m, v[k], v[(k + 1) % 3]) < 0)
            return -1;
    return 1;
}

/* Flip every inner edge until none flips (at most `sweeps` sweeps). */
static int relax_all(hole_patch *p, edge_map *m, int sweeps)
{
    for (int s = 0; s < sweeps; ++s) {
        size_t flips = 0;
        for (size_t t = 0; t < p->nt; ++t)
            for (int k = 0; k < 3; ++k) {
                int r = relax(p, m, p->t[3 * t + k], p->t[3 * t + (k + 1) % 3]);
                if (r < 0)
                    return 0;
                flips += (size_t)r;
            }
        if (!flips)
            break;
    }
    return 1;
}

relief_status hole_refine(hole_patch *p, relief_error *err)
{
    edge_map m = {0};
    relief_status st = RELIEF_OK;
    if (!map_make(&m, p) || !relax_all(p, &m, 50))
        goto nomem;
    for (int pass = 0; pass < 100; ++pass) {
        size_t splits = 0, nt = p->nt;
        for (size_t t = 0; t < nt; ++t) {
            int r = split(p, &m, t);
            if (r < 0)
                goto nomem;
            splits += (size_t)r;
        }
        if (p->max_new && p->nx - p->n_rim > p->max_new) {
            st = relief_fail(err, RELIEF_E_RANGE, "filling a %zu-vertex hole would add more "
                             "than %zu vertices", p->n_rim, p->max_new);
            goto done;
        }
        if (!splits)
            break;
        if (!relax_all(p, &m, 50))
            goto nomem;
    }
    goto done;
nomem:
    st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the refinement of a %zu-vertex hole",
                     p->n_rim);
done:
    free(m.s);
    return st;
}
