/* Welding a split vertex's copies back together where a fill joined them
 * (weld.h). */
#include "mesh/weld.h"

#include <stdlib.h>
#include <string.h>

/* A fan, or the vertices about one, longer than this is not checked, and
 * its copies are not welded: a copy has the degree of a mesh vertex. */
#define WELD_MAX_FAN 64

typedef struct weld_work {
    const uint32_t *tri;
    size_t nt;
    uint32_t *start, *list; /* nv + 1, 3 nt: each vertex's triangles (CSR) */
    uint32_t *rep;          /* nv: the vertex a vertex is welded to (itself: none) */
    uint32_t *next;         /* nv: the vertices welded together, a circular list */
    uint8_t *dead;          /* nt: a triangle dropped */
} weld_work;

static uint32_t find(const weld_work *w, uint32_t v)
{
    while (w->rep[v] != v)
        v = w->rep[v];
    return v;
}

/* The live triangle t's corners as welded, rotated so that c[0] is r; 0
 * when r is not exactly one of them. */
static int corners_at(const weld_work *w, size_t t, uint32_t r, uint32_t c[3])
{
    uint32_t k[3];
    int at = -1, n = 0;
    for (int q = 0; q < 3; ++q) {
        k[q] = find(w, w->tri[3 * t + q]);
        if (k[q] == r)
            at = q, ++n;
    }
    if (n != 1)
        return 0;
    for (int q = 0; q < 3; ++q)
        c[q] = k[(at + q) % 3];
    return 1;
}

/* 1 when the live triangles about r (all its welded vertices') form one
 * fan: each neighbour once before and once after r in the triangles'
 * order, and the edges of the link (a -> b for a triangle r, a, b) one
 * path or one cycle of at least 3. 0 otherwise, or over WELD_MAX_FAN. */
static int one_fan(const weld_work *w, uint32_t r)
{
    uint32_t src[WELD_MAX_FAN], dst[WELD_MAX_FAN], cur;
    size_t k = 0, starts = 0, first = 0, steps = 0;
    uint32_t m = r;
    do {
        for (uint32_t i = w->start[m]; i < w->start[m + 1]; ++i) {
            uint32_t c[3];
            if (w->dead[w->list[i]])
                continue;
            if (!corners_at(w, w->list[i], r, c) || k == WELD_MAX_FAN)
                return 0;
            src[k] = c[1], dst[k++] = c[2];
        }
        m = w->next[m];
    } while (m != r);
    for (size_t i = 0; i < k; ++i) {
        int has_in = 0;
        for (size_t j = 0; j < k; ++j) {
            if (j != i && (src[i] == src[j] || dst[i] == dst[j]))
                return 0;
            has_in |= dst[j] == src[i];
        }
        if (!has_in)
            first = i, ++starts;
    }
    if (k == 0)
        return 1;
    if (starts > 1 || (starts == 0 && k < 3))
        return 0;
    cur = src[first];
    for (;;) { /* follow the link from its start (a path) or any edge (a cycle) */
        size_t j = 0;
        while (j < k && src[j] != cur)
            ++j;
        if (j == k)
            break;
        cur = dst[j], ++steps;
        if (steps > k || (starts == 0 && cur == src[first]))
            break;
    }
    return steps == k;
}

/* The vertices that share a live triangle with r or s (not r or s),
 * into nb; 0 over WELD_MAX_FAN. */
static int neighbours(const weld_work *w, uint32_t r, uint32_t s, uint32_t *nb, size_t *n)
{
    const uint32_t heads[2] = {r, s};
    *n = 0;
    for (int h = 0; h < 2; ++h) {
        uint32_t m = heads[h];
        do {
            for (uint32_t i = w->start[m]; i < w->start[m + 1]; ++i) {
                const size_t t = w->list[i];
                for (int q = 0; !w->dead[t] && q < 3; ++q) {
                    const uint32_t y = find(w, w->tri[3 * t + q]);
                    size_t j = 0;
                    while (j < *n && nb[j] != y)
                        ++j;
                    if (y == r || y == s || j < *n)
                        continue;
                    if (*n == WELD_MAX_FAN)
                        return 0;
                    nb[(*n)++] = y;
                }
            }
            m = w->next[m];
        } while (m != heads[h]);
    }
    return 1;
}

/* Joins (or, again, parts) the welded lists of r and s. */
static void splice(weld_work *w, uint32_t r, uint32_t s)
{
    const uint32_t t = w->next[r];
    w->next[r] = w->next[s];
    w->next[s] = t;
}

/* Welds u's and v's vertices when that leaves one fan at the weld and
 * breaks no neighbour's; 1 when welded. */
static int try_weld(weld_work *w, uint32_t u, uint32_t v)
{
    uint32_t r = find(w, u), s = find(w, v), nb[WELD_MAX_FAN], drop[WELD_MAX_FAN], m;
    uint8_t was_one[WELD_MAX_FAN];
    size_t n_nb, n_drop = 0;
    int ok;
    if (r == s)
        return 0;
    if (s < r) {
        const uint32_t x = r;
        r = s, s = x;
    }
    if (!neighbours(w, r, s, nb, &n_nb))
        return 0;
    for (size_t j = 0; j < n_nb; ++j)
        was_one[j] = (uint8_t)one_fan(w, nb[j]);
    w->rep[s] = r;
    splice(w, r, s);
    ok = 1;
    m = r;
    do { /* drop the triangles the weld leaves with two corners at r */
        for (uint32_t i = w->start[m]; ok && i < w->start[m + 1]; ++i) {
            const uint32_t t = w->list[i];
            int at_r = 0;
            for (int q = 0; q < 3; ++q)
                at_r += find(w, w->tri[3 * t + q]) == r;
            if (w->dead[t] || at_r < 2)
                continue;
            if (n_drop == WELD_MAX_FAN)
                ok = 0;
            else
                w->dead[t] = 1, drop[n_drop++] = t;
        }
        m = w->next[m];
    } while (m != r);
    ok = ok && one_fan(w, r);
    for (size_t j = 0; ok && j < n_nb; ++j)
        ok = !was_one[j] || one_fan(w, nb[j]);
    if (!ok) {
        for (size_t j = 0; j < n_drop; ++j)
            w->dead[drop[j]] = 0;
        splice(w, r, s);
        w->rep[s] = s;
    }
    return ok;
}

static int same_place(const double *pos, uint32_t a, uint32_t b)
{
    const double *p = pos + 3 * (size_t)a, *q = pos + 3 * (size_t)b;
    return a != b && p[0] == q[0] && p[1] == q[1] && p[2] == q[2];
}

relief_status relief_weld_copies(const double *pos, size_t nv, uint32_t *tri, size_t *nt,
                                 size_t *welded, relief_error *err)
{
    weld_work w = {tri, *nt, calloc(nv + 2, sizeof *w.start),
                   malloc((3 * *nt + 1) * sizeof *w.list), malloc((nv + 1) * sizeof *w.rep),
                   malloc((nv + 1) * sizeof *w.next), calloc(*nt + 1, 1)};
    size_t kept = 0;
    *welded = 0;
    if (!w.start || !w.list || !w.rep || !w.next || !w.dead) {
        free(w.start), free(w.list), free(w.rep), free(w.next), free(w.dead);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot weld the copies of a %zu-triangle "
                           "mesh's split vertices", *nt);
    }
    for (size_t i = 0; i < 3 * *nt; ++i)
        ++w.start[tri[i] + 1];
    for (size_t v = 0; v < nv; ++v)
        w.start[v + 1] += w.start[v], w.rep[v] = w.next[v] = (uint32_t)v;
    for (size_t i = 0; i < 3 * *nt; ++i) /* start[v] runs ahead, then back */
        w.list[w.start[tri[i]]++] = (uint32_t)(i / 3);
    for (size_t v = nv; v > 0; --v)
        w.start[v] = w.start[v - 1];
    w.start[0] = 0;
    for (size_t t = 0; t < *nt; ++t)
        for (int q = 0; q < 3; ++q) {
            const uint32_t a = tri[3 * t + q], b = tri[3 * t + (q + 1) % 3];
            if (!w.dead[t] && same_place(pos, a, b) && !same_place(pos, a, tri[3 * t + (q + 2) % 3]))
                *welded += (size_t)try_weld(&w, a, b);
        }
    for (size_t t = 0; t < *nt; ++t) {
        uint32_t c[3];
        if (w.dead[t])
            continue;
        for (int q = 0; q < 3; ++q)
            c[q] = find(&w, tri[3 * t + q]);
        memcpy(tri + 3 * kept++, c, sizeof c);
    }
    *nt = kept;
    free(w.start), free(w.list), free(w.rep), free(w.next), free(w.dead);
    return RELIEF_OK;
}
