/* Mending a triangle soup into a mesh OpenMesh can hold (include/relief/core.h:
 * relief_mesh_repair, relief_repair_info). Each step works on a copy of the
 * triangles and a "dead" flag per triangle; the mesh is replaced only at the
 * end, so a refusal leaves it as it was and a clean mesh is not renumbered. */
#include "mesh/repair.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/sort.h"
#include "base/union_find.h"
#include "base/vec3.h"
#include "mesh/io_openmesh.h"
#include "mesh/mesh.h"

#define NONE UINT32_MAX

/* One side of an undirected edge: triangle t's edge from corner k to k + 1,
 * keyed by its lower and higher vertex. */
typedef struct half {
    uint32_t a, b, t;
    uint8_t k;
} half;

/* The live triangles' edges, sorted so that an edge's sides are one run. */
typedef struct edges {
    half *h;          /* 3 x live triangles */
    size_t nh;
    uint32_t *run;    /* start of each run in h; nrun + 1 entries */
    size_t nrun;
    uint32_t *of;     /* 3 nt: the run of triangle t's edge k, NONE if dead */
} edges;

typedef struct work {
    const relief_mesh *m;
    size_t nv;        /* vertices, split copies included */
    uint32_t *tri;    /* nt x 3, the triangles as repaired so far */
    uint8_t *dead;    /* nt */
    uint32_t *src;    /* nv: the input vertex each vertex copies */
    uint8_t *welded;  /* input nv: 1 for a vertex welded into an earlier one */
    uint32_t *to;     /* input nv: the vertex each was welded into (or itself) */
    uint8_t *flipped; /* nt: 1 once turned over (corners 1 and 2 swapped) */
    uint8_t *taken;   /* input nv: 1 once a fan of the split uses it */
    relief_repair_info *info;
} work;

static int half_cmp(const void *x, const void *y)
{
    const half *p = x, *q = y;
    if (p->a != q->a)
        return p->a < q->a ? -1 : 1;
    if (p->b != q->b)
        return p->b < q->b ? -1 : 1;
    if (p->t != q->t)
        return p->t < q->t ? -1 : 1;
    return (int)p->k - (int)q->k;
}

static void edges_free(edges *e)
{
    free(e->h);
    free(e->run);
    free(e->of);
    memset(e, 0, sizeof *e);
}

/* Sides bucketed by their lower vertex (a counting sort: the mesh's
 * vertices are the keys), then each bucket, a vertex's few edges, in
 * order by insertion (qsort when large): qsort over all of them cost
 * more than the read. */
static int edges_build(const work *w, edges *e)
{
    const size_t nt = w->m->nt;
    size_t *start = calloc(w->nv + 2, sizeof *start);
    memset(e, 0, sizeof *e);
    e->h = malloc((3 * nt + 1) * sizeof *e->h);
    e->run = malloc((3 * nt + 1) * sizeof *e->run);
    e->of = malloc((3 * nt + 1) * sizeof *e->of);
    if (!start || !e->h || !e->run || !e->of) {
        free(start);
        edges_free(e);
        return 0;
    }
    for (size_t t = 0; t < nt; ++t)
        for (int k = 0; k < 3 && !w->dead[t]; ++k) {
            uint32_t p = w->tri[3 * t + k], q = w->tri[3 * t + (k + 1) % 3];
            ++start[(p < q ? p : q) + 2];
        }
    for (size_t v = 0; v < w->nv; ++v)
        start[v + 2] += start[v + 1];
    for (size_t t = 0; t < nt; ++t)
        for (int k = 0; k < 3 && !w->dead[t]; ++k) {
            uint32_t p = w->tri[3 * t + k], q = w->tri[3 * t + (k + 1) % 3];
            half hh = {p < q ? p : q, p < q ? q : p, (uint32_t)t, (uint8_t)k};
            e->h[start[hh.a + 1]++] = hh;
        }
    e->nh = start[w->nv];
    for (size_t v = 0; v < w->nv; ++v)
        if (start[v + 1] - start[v] > 32) /* a cone's apex: no quadratic sort */
            qsort(e->h + start[v], start[v + 1] - start[v], sizeof *e->h, half_cmp);
        else
            for (size_t i = start[v] + 1; i < start[v + 1]; ++i)
                for (size_t j = i; j > start[v] && half_cmp(e->h + j - 1, e->h + j) > 0; --j) {
                half s = e->h[j];
                e->h[j] = e->h[j - 1];
                e->h[j - 1] = s;
            }
    free(start);
    for (size_t i = 0; i < 3 * nt; ++i)
        e->of[i] = NONE;
    for (size_t i = 0; i < e->nh; ++i) {
        if (i == 0 || e->h[i].a != e->h[i - 1].a || e->h[i].b != e->h[i - 1].b)
            e->run[e->nrun++] = (uint32_t)i;
        e->of[3 * (size_t)e->h[i].t + e->h[i].k] = (uint32_t)(e->nrun - 1);
    }
    e->run[e->nrun] = (uint32_t)e->nh;
    return 1;
}

static size_t run_size(const edges *e, uint32_t r)
{
    return e->run[r + 1] - e->run[r];
}

/* 1 when side h goes from its lower vertex to its higher one. */
static int forward(const work *w, const half *h)
{
    return w->tri[3 * (size_t)h->t + h->k] == h->a;
}

/* Unit normal of triangle t, zero when degenerate. */
static void tri_normal(const work *w, uint32_t t, double n[3])
{
    const uint32_t *f = w->tri + 3 * (size_t)t;
    const double *p = w->m->pos;
    double u[3], v[3];
    for (int k = 0; k < 3; ++k) {
        u[k] = p[3 * (size_t)w->src[f[1]] + k] - p[3 * (size_t)w->src[f[0]] + k];
        v[k] = p[3 * (size_t)w->src[f[2]] + k] - p[3 * (size_t)w->src[f[0]] + k];
    }
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; ++k)
        n[k] = len > 0.0 ? n[k] / len : 0.0;
}

typedef struct vkey {
    const double *pos;
    uint32_t v;
} vkey;

static int vkey_cmp(const void *x, const void *y)
{
    const vkey *p = x, *q = y;
    for (int k = 0; k < 3; ++k)
        if (p->pos[3 * (size_t)p->v + k] != p->pos[3 * (size_t)q->v + k])
            return p->pos[3 * (size_t)p->v + k] < p->pos[3 * (size_t)q->v + k] ? -1 : 1;
    return p->v < q->v ? -1 : p->v > q->v;
}

/* Vertices at the very same coordinates become the earliest of them
 * (welded[v] = 1 for the others); triangles are moved onto it. */
static int weld(work *w)
{
    const relief_mesh *m = w->m;
    vkey *key = malloc((m->nv + 1) * sizeof *key);
    uint32_t *to = w->to;
    if (!key)
        return 0;
    for (size_t v = 0; v < m->nv; ++v) {
        key[v].pos = m->pos;
        key[v].v = (uint32_t)v;
        to[v] = (uint32_t)v;
    }
    qsort(key, m->nv, sizeof *key, vkey_cmp);
    for (size_t i = 1; i < m->nv; ++i) {
        const double *p = m->pos + 3 * (size_t)key[i].v;
        const double *q = m->pos + 3 * (size_t)key[i - 1].v;
        if (p[0] == q[0] && p[1] == q[1] && p[2] == q[2]) {
            to[key[i].v] = to[key[i - 1].v];
            w->welded[key[i].v] = 1;
            ++w->info->vertices_welded;
        }
    }
    for (size_t i = 0; i < 3 * m->nt; ++i)
        w->tri[i] = to[w->tri[i]];
    free(key);
    return 1;
}

typedef struct tkey {
    uint32_t s[3];
    uint32_t t;
} tkey;

static int tkey_cmp(const void *x, const void *y)
{
    const tkey *p = x, *q = y;
    for (int k = 0; k < 3; ++k)
        if (p->s[k] != q->s[k])
            return p->s[k] < q->s[k] ? -1 : 1;
    return p->t < q->t ? -1 : p->t > q->t;
}

/* Triangles with a vertex twice or of zero area go, then every triangle on
 * the same three vertices as an earlier one. */
static int drop_degenerate_and_duplicates(work *w)
{
    const size_t nt = w->m->nt;
    tkey *key = malloc((nt + 1) * sizeof *key);
    size_t n = 0;
    if (!key)
        return 0;
    for (size_t t = 0; t < nt; ++t) {
        uint32_t *f = w->tri + 3 * t;
        double nrm[3];
        tri_normal(w, (uint32_t)t, nrm);
        if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2] ||
            (nrm[0] == 0.0 && nrm[1] == 0.0 && nrm[2] == 0.0)) {
            w->dead[t] = 1;
            ++w->info->degenerate_triangles;
            continue;
        }
        tkey k = {{f[0], f[1], f[2]}, (uint32_t)t};
        for (int i = 0; i < 2; ++i)
            for (int j = 0; j < 2 - i; ++j)
                if (k.s[j] > k.s[j + 1]) {
                    uint32_t s = k.s[j];
                    k.s[j] = k.s[j + 1];
                    k.s[j + 1] = s;
                }
        key[n++] = k;
    }
    qsort(key, n, sizeof *key, tkey_cmp);
    for (size_t i = 1; i < n; ++i)
        if (!memcmp(key[i].s, key[i - 1].s, sizeof key[i].s)) {
            w->dead[key[i].t] = 1;
            ++w->info->duplicate_triangles;
        }
    free(key);
    return 1;
}

/* Of the live sides of run r (more than two), keep the pair that agrees in
 * orientation (the edge walked both ways), then the most nearly coplanar
 * (their normals, turned to agree, closest), then the earliest; drop the
 * rest. */
static void resolve_edge(work *w, const edges *e, uint32_t r)
{
    const half *h = e->h + e->run[r];
    const size_t n = run_size(e, r);
    int best_i = -1, best_j = -1, best_agree = -1;
    double best_flat = -2.0;
    size_t live = 0;
    for (size_t i = 0; i < n; ++i)
        live += !w->dead[h[i].t];
    if (live <= 2)
        return;
    ++w->info->nonmanifold_edges;
    for (size_t i = 0; i < n; ++i) {
        if (w->dead[h[i].t])
            continue;
        double ni[3];
        tri_normal(w, h[i].t, ni);
        for (size_t j = i + 1; j < n; ++j) {
            if (w->dead[h[j].t])
                continue;
            double nj[3];
            tri_normal(w, h[j].t, nj);
            int agree = forward(w, h + i) != forward(w, h + j);
            double flat = (ni[0] * nj[0] + ni[1] * nj[1] + ni[2] * nj[2]) * (agree ? 1 : -1);
            if (agree > best_agree || (agree == best_agree && flat > best_flat)) {
                best_agree = agree;
                best_flat = flat;
                best_i = (int)i;
                best_j = (int)j;
            }
        }
    }
    for (size_t i = 0; i < n; ++i)
        if (!w->dead[h[i].t] && (int)i != best_i && (int)i != best_j) {
            w->dead[h[i].t] = 1;
            ++w->info->nonmanifold_edge_triangles;
        }
}

static int resolve_edges(work *w)
{
    edges e;
    if (!edges_build(w, &e))
        return 0;
    for (uint32_t r = 0; r < e.nrun; ++r)
        if (run_size(&e, r) > 2)
            resolve_edge(w, &e, r);
    edges_free(&e);
    return 1;
}

/* The other side of run r (two sides), and whether they walk it the same way. */
static uint32_t other_side(const work *w, const edges *e, uint32_t r, uint32_t t, int *same)
{
    const half *h = e->h + e->run[r];
    const half *o = h[0].t == t ? h + 1 : h;
    const half *s = h[0].t == t ? h : h + 1;
    *same = forward(w, o) == forward(w, s);
    return o->t;
}

/* Breadth first over the edges with two triangles from each part's earliest
 * triangle: flip[t] so that neighbours walk their edge opposite ways; a part
 * keeps the orientation most of its triangles have. Where a loop cannot
 * agree, the later triangle of the edge goes. */
static int orient_parts(work *w, const edges *e, uint8_t *flip)
{
    const size_t nt = w->m->nt;
    uint32_t *queue = malloc((nt + 1) * sizeof *queue);
    uint8_t *seen = calloc(nt + 1, 1);
    if (!queue || !seen) {
        free(queue);
        free(seen);
        return 0;
    }
    for (size_t s = 0; s < nt; ++s) {
        if (w->dead[s] || seen[s])
            continue;
        size_t head = 0, tail = 0, flipped = 0;
        queue[tail++] = (uint32_t)s;
        seen[s] = 1;
        flip[s] = 0;
        while (head < tail) {
            uint32_t t = queue[head++];
            for (int k = 0; k < 3; ++k) {
                uint32_t r = e->of[3 * (size_t)t + k];
                int same;
                if (r == NONE || run_size(e, r) != 2)
                    continue;
                uint32_t u = other_side(w, e, r, t, &same);
                if (!seen[u]) {
                    seen[u] = 1;
                    flip[u] = (uint8_t)(flip[t] ^ same);
                    flipped += flip[u];
                    queue[tail++] = u;
                } else if ((flip[u] ^ flip[t]) != same && !w->dead[u] && !w->dead[t]) {
                    uint32_t later = u > t ? u : t;
                    w->dead[later] = 1;
                    ++w->info->orientation_triangles;
                }
            }
        }
        if (2 * flipped > tail)
            for (size_t i = 0; i < tail; ++i)
                flip[queue[i]] ^= 1;
    }
    free(queue);
    free(seen);
    return 1;
}

static int orient(work *w)
{
    edges e;
    uint8_t *flip = calloc(w->m->nt + 1, 1);
    if (!flip || !edges_build(w, &e)) {
        free(flip);
        return 0;
    }
    int ok = orient_parts(w, &e, flip);
    for (size_t t = 0; ok && t < w->m->nt; ++t)
        if (flip[t] && !w->dead[t]) {
            uint32_t *f = w->tri + 3 * t;
            uint32_t s = f[1];
            f[1] = f[2];
            f[2] = s;
            w->flipped[t] = 1;
            ++w->info->triangles_flipped;
        }
    edges_free(&e);
    free(flip);
    return ok;
}

/* Appends a copy of vertex v; 0 when out of memory. */
static int add_copy(work *w, uint32_t v, size_t *cap)
{
    if (w->nv == *cap) {
        size_t c = 2 * *cap + 16;
        uint32_t *s = realloc(w->src, c * sizeof *s);
        if (!s)
            return 0;
        w->src = s;
        *cap = c;
    }
    w->src[w->nv++] = w->src[v];
    return 1;
}

/* The corner of triangle t at v, and the vertex the input had there. */
static int corner_of(const work *w, uint32_t t, uint32_t v, uint32_t *input)
{
    for (int k = 0; k < 3; ++k)
        if (w->tri[3 * (size_t)t + k] == v) {
            const int in = w->flipped[t] && k ? 3 - k : k; /* where the input had it */
            *input = w->m->tri[3 * (size_t)t + in];
            return k;
        }
    return -1;
}

/* Which vertex the fan of v rooted at ids[i] uses: v when one of its
 * triangles had v in the input; else the input's vertex at its first
 * triangle's corner when it was welded into v (two coincident vertices the
 * file keeps apart on purpose, as a repaired bow-tie written out and read
 * back has, stay apart and count as neither welded nor split); else v if
 * no fan took it; else a new copy. NONE when out of memory. */
static uint32_t fan_vertex(work *w, uint32_t v, const uint32_t *ids, size_t n, size_t i,
                           uint32_t *parent, size_t *cap)
{
    const uint32_t root = ids[i];
    uint32_t o = v, first = v;
    corner_of(w, root, v, &first);
    for (size_t j = i; j < n; ++j)
        if (relief_uf_find(parent, ids[j]) == root && corner_of(w, ids[j], v, &o) >= 0 && o == v)
            break;
    if (o == v && !w->taken[v]) {
        w->taken[v] = 1;
        return v;
    }
    if (first != v && w->welded[first] && w->to[first] == v && !w->taken[first]) {
        w->taken[first] = 1;
        w->welded[first] = 0;
        --w->info->vertices_welded;
        return first;
    }
    if (!w->taken[v]) {
        w->taken[v] = 1;
        return v;
    }
    if (!add_copy(w, v, cap))
        return NONE;
    ++w->info->vertices_added;
    return (uint32_t)(w->nv - 1);
}

/* At vertex v (its live triangles ids[0..n), ascending), the triangles
 * joined through an edge at v that has two triangles are one fan; each fan
 * gets its own vertex (fan_vertex). */
static int split_vertex(work *w, const edges *e, uint32_t v, const uint32_t *ids, size_t n,
                        uint32_t *parent, size_t *cap)
{
    const size_t added = w->info->vertices_added;
    for (size_t i = 0; i < n; ++i)
        parent[ids[i]] = ids[i];
    for (size_t i = 0; i < n; ++i) {
        const uint32_t t = ids[i];
        for (int k = 0; k < 3; ++k) {
            /* the edges of t at v: the one from v and the one into v */
            if (w->tri[3 * (size_t)t + k] != v && w->tri[3 * (size_t)t + (k + 1) % 3] != v)
                continue;
            uint32_t r = e->of[3 * (size_t)t + k];
            int same;
            if (r != NONE && run_size(e, r) == 2)
                relief_uf_join(parent, t, other_side(w, e, r, t, &same));
        }
    }
    for (size_t i = 0; i < n; ++i) {
        if (relief_uf_find(parent, ids[i]) != ids[i])
            continue; /* not a fan's first triangle */
        const uint32_t to = fan_vertex(w, v, ids, n, i, parent, cap);
        if (to == NONE)
            return 0;
        for (size_t j = i; j < n && to != v; ++j)
            if (relief_uf_find(parent, ids[j]) == ids[i])
                for (int k = 0; k < 3; ++k)
                    if (w->tri[3 * (size_t)ids[j] + k] == v)
                        w->tri[3 * (size_t)ids[j] + k] = to;
    }
    if (w->info->vertices_added > added)
        ++w->info->nonmanifold_vertices;
    return 1;
}

static int split_vertices(work *w)
{
    const size_t nv = w->nv, nt = w->m->nt;
    size_t cap = nv;
    edges e;
    uint32_t *start = calloc(nv + 2, sizeof *start);
    uint32_t *ids = malloc((3 * nt + 1) * sizeof *ids);
    uint32_t *parent = malloc((nt + 1) * sizeof *parent);
    int ok = start && ids && parent && edges_build(w, &e);
    if (!ok) {
        free(start);
        free(ids);
        free(parent);
        return 0;
    }
    for (size_t t = 0; t < nt; ++t)
        for (int k = 0; k < 3 && !w->dead[t]; ++k)
            ++start[w->tri[3 * t + k] + 2];
    for (size_t v = 0; v < nv; ++v)
        start[v + 2] += start[v + 1];
    for (size_t t = 0; t < nt; ++t)
        for (int k = 0; k < 3 && !w->dead[t]; ++k)
            ids[start[w->tri[3 * t + k] + 1]++] = (uint32_t)t;
    for (size_t v = 0; ok && v < nv; ++v)
        if (start[v + 1] > start[v])
            ok = split_vertex(w, &e, (uint32_t)v, ids + start[v], start[v + 1] - start[v],
                              parent, &cap);
    edges_free(&e);
    free(start);
    free(ids);
    free(parent);
    return ok;
}

/* Parts joined through edges with two triangles; those under
 * RELIEF_REPAIR_SMALL_TRIANGLES triangles and 1 % of the live ones go, never
 * the largest (the earliest of equals). */
static int drop_small_parts(work *w)
{
    const size_t nt = w->m->nt;
    edges e;
    uint32_t *parent = malloc((nt + 1) * sizeof *parent);
    uint32_t *size = calloc(nt + 1, sizeof *size);
    size_t live = 0;
    uint32_t largest = NONE;
    if (!parent || !size || !edges_build(w, &e)) {
        free(parent);
        free(size);
        return 0;
    }
    for (size_t t = 0; t < nt; ++t)
        parent[t] = (uint32_t)t;
    for (uint32_t r = 0; r < e.nrun; ++r)
        if (run_size(&e, r) == 2)
            relief_uf_join(parent, e.h[e.run[r]].t, e.h[e.run[r] + 1].t);
    for (size_t t = 0; t < nt; ++t)
        if (!w->dead[t]) {
            ++live;
            ++size[relief_uf_find(parent, (uint32_t)t)];
        }
    for (size_t t = 0; t < nt; ++t)
        if (size[t] > 0 && (largest == NONE || size[t] > size[largest]))
            largest = (uint32_t)t;
    for (size_t t = 0; t < nt; ++t) {
        uint32_t root = relief_uf_find(parent, (uint32_t)t);
        if (w->dead[t] || root == largest || size[root] >= RELIEF_REPAIR_SMALL_TRIANGLES ||
            100 * (size_t)size[root] >= live)
            continue;
        if (root == t)
            ++w->info->small_components;
        w->dead[t] = 1;
        ++w->info->small_component_triangles;
    }
    edges_free(&e);
    free(parent);
    free(size);
    return 1;
}

/* The triangles OpenMesh's add_face still refuses, in order, go: the later
 * stages build their half-edge meshes the same way. */
static relief_status drop_unstorable(work *w, relief_error *err)
{
    const relief_mesh *m = w->m;
    relief_mesh probe;
    size_t n = 0;
    uint32_t *live = malloc((3 * m->nt + 1) * sizeof *live);
    uint32_t *id = malloc((m->nt + 1) * sizeof *id);
    uint8_t *ok = malloc(m->nt + 1);
    double *pos = malloc((3 * w->nv + 1) * sizeof *pos);
    relief_status st = RELIEF_E_NOMEM;
    if (live && id && ok && pos) {
        for (size_t t = 0; t < m->nt; ++t)
            if (!w->dead[t]) {
                memcpy(live + 3 * n, w->tri + 3 * t, 3 * sizeof *live);
                id[n++] = (uint32_t)t;
            }
        for (size_t v = 0; v < w->nv; ++v)
            memcpy(pos + 3 * v, m->pos + 3 * (size_t)w->src[v], 3 * sizeof *pos);
        memset(&probe, 0, sizeof probe);
        probe.nv = w->nv;
        probe.pos = pos;
        st = relief_om_storable(&probe, live, n, ok, err);
        for (size_t i = 0; st == RELIEF_OK && i < n; ++i)
            if (!ok[i]) {
                w->dead[id[i]] = 1;
                ++w->info->unstorable_triangles;
            }
    } else {
        relief_fail(err, st, "cannot allocate the repair of a mesh of %zu triangles", m->nt);
    }
    free(live);
    free(id);
    free(ok);
    free(pos);
    return st;
}

/* The repaired arrays into m: kept vertices in order then the copies, live
 * triangles in order. used: the input vertices some input triangle used. */
static relief_status commit(work *w, relief_mesh *m, const uint8_t *welded,
                            const uint8_t *used, relief_error *err)
{
    uint8_t *now = calloc(w->nv + 1, 1);
    uint32_t *to = malloc((w->nv + 1) * sizeof *to);
    relief_mesh *out = NULL;
    size_t nv = 0, nt = 0;
    relief_status st = RELIEF_E_NOMEM;
    if (now && to) {
        for (size_t t = 0; t < m->nt; ++t)
            for (int k = 0; k < 3 && !w->dead[t]; ++k)
                now[w->tri[3 * t + k]] = 1;
        for (size_t v = 0; v < w->nv; ++v) {
            int keep = v < m->nv ? !welded[v] && (now[v] || !used[v]) : now[v];
            to[v] = keep ? (uint32_t)nv++ : NONE;
            w->info->vertices_unused += v < m->nv && !welded[v] && !keep;
        }
        for (size_t t = 0; t < m->nt; ++t)
            nt += !w->dead[t];
        st = relief_mesh_create(nv, nt, m->attrs, &out, err);
    } else {
        relief_fail(err, st, "cannot allocate the repair of a mesh of %zu vertices", m->nv);
    }
    if (st == RELIEF_OK) {
        for (size_t v = 0; v < w->nv; ++v) {
            if (to[v] == NONE)
                continue;
            const size_t d = to[v], s = w->src[v];
            memcpy(out->pos + 3 * d, m->pos + 3 * s, 3 * sizeof *out->pos);
            if (m->col)
                memcpy(out->col + 3 * d, m->col + 3 * s, 3 * sizeof *out->col);
            if (m->nrm)
                memcpy(out->nrm + 3 * d, m->nrm + 3 * s, 3 * sizeof *out->nrm);
            if (m->label)
                out->label[d] = m->label[s];
        }
        nt = 0;
        for (size_t t = 0; t < m->nt; ++t) {
            if (w->dead[t])
                continue;
            for (int k = 0; k < 3; ++k)
                out->tri[3 * nt + k] = to[w->tri[3 * t + k]];
            ++nt;
        }
        /* Swap the arrays so that m keeps its address. */
        relief_mesh tmp = *m;
        *m = *out;
        *out = tmp;
        relief_mesh_destroy(out);
    }
    free(now);
    free(to);
    return st;
}

static int any_change(const relief_repair_info *i)
{
    return i->vertices_welded || i->degenerate_triangles || i->duplicate_triangles ||
           i->nonmanifold_edge_triangles || i->triangles_flipped ||
           i->orientation_triangles || i->vertices_added || i->small_component_triangles ||
           i->unstorable_triangles || i->vertices_unused;
}

/* Steps in order; 0 when out of memory. */
static int mend(work *w)
{
    return weld(w) && drop_degenerate_and_duplicates(w) && resolve_edges(w) &&
           orient(w) && split_vertices(w) && drop_small_parts(w);
}

relief_status relief_mesh_repair_impl(relief_mesh *m, relief_repair_info *info,
                                      int check_storable, relief_error *err)
{
    relief_repair_info local;
    work w;
    relief_status st = RELIEF_OK;
    if (!m)
        return relief_fail(err, RELIEF_E_USAGE, "relief_mesh_repair: NULL mesh");
    if (!info)
        info = &local;
    memset(info, 0, sizeof *info);
    if (m->nt == 0)
        return RELIEF_OK;
    memset(&w, 0, sizeof w);
    w.m = m;
    w.nv = m->nv;
    w.info = info;
    w.tri = malloc(3 * m->nt * sizeof *w.tri);
    w.dead = calloc(m->nt, 1);
    w.src = malloc((m->nv + 1) * sizeof *w.src);
    uint8_t *welded = calloc(m->nv + 1, 1), *used = calloc(m->nv + 1, 1);
    w.welded = welded;
    w.taken = calloc(m->nv + 1, 1);
    w.to = malloc((m->nv + 1) * sizeof *w.to);
    w.flipped = calloc(m->nt + 1, 1);
    if (!w.tri || !w.dead || !w.src || !welded || !used || !w.taken || !w.to || !w.flipped)
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the repair of a mesh of %zu "
                         "triangles", m->nt);
    if (st == RELIEF_OK) {
        memcpy(w.tri, m->tri, 3 * m->nt * sizeof *w.tri);
        for (size_t v = 0; v < m->nv; ++v)
            w.src[v] = (uint32_t)v;
        for (size_t i = 0; i < 3 * m->nt; ++i)
            used[m->tri[i]] = 1;
        if (!mend(&w))
            st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the repair of a mesh of "
                             "%zu triangles", m->nt);
    }
    if (st == RELIEF_OK && (check_storable || any_change(info)))
        st = drop_unstorable(&w, err);
    size_t live = 0;
    for (size_t t = 0; st == RELIEF_OK && t < m->nt; ++t)
        live += !w.dead[t];
    if (st == RELIEF_OK && live == 0) {
        char what[256];
        relief_repair_info_describe(info, what, sizeof what);
        st = relief_fail(err, RELIEF_E_MESH, "no usable triangle is left after the repair "
                         "(%s)", what);
    }
    if (st == RELIEF_OK && any_change(info))
        st = commit(&w, m, welded, used, err);
    if (st != RELIEF_OK)
        memset(info, 0, sizeof *info);
    free(w.tri);
    free(w.dead);
    free(w.src);
    free(welded);
    free(used);
    free(w.taken);
    free(w.to);
    free(w.flipped);
    return st;
}

relief_status relief_mesh_repair(relief_mesh *mesh, relief_repair_info *info, relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    if (!mesh)
        return relief_fail(err, RELIEF_E_USAGE, "relief_mesh_repair: NULL mesh");
    relief_status st = relief_mesh_validate(mesh, err);
    if (st == RELIEF_OK)
        st = relief_mesh_check_range(mesh, err);
    if (st == RELIEF_OK)
        st = relief_mesh_repair_impl(mesh, info, 1, err);
    return st;
}

int relief_repair_info_describe(const relief_repair_info *i, char *text, size_t size)
{
    const struct {
        size_t n;
        const char *what;
    } item[] = {
        {i ? i->vertices_welded : 0, "duplicate vertices welded"},
        {i ? i->degenerate_triangles : 0, "degenerate triangles dropped"},
        {i ? i->duplicate_triangles : 0, "duplicate triangles dropped"},
        {i ? i->nonmanifold_edge_triangles : 0, "triangles on non-manifold edges dropped"},
        {i ? i->triangles_flipped : 0, "triangles flipped to orient"},
        {i ? i->orientation_triangles : 0, "triangles dropped that no orientation fits"},
        {i ? i->nonmanifold_vertices : 0, "non-manifold vertices split"},
        {i ? i->small_component_triangles : 0, "triangles of small stray parts dropped"},
        {i ? i->unstorable_triangles : 0, "triangles OpenMesh refused dropped"},
        {i ? i->vertices_unused : 0, "vertices left unused dropped"},
    };
    int n = 0;
    size_t at = 0;
    if (text && size > 0)
        text[0] = '\0';
    for (size_t k = 0; k < sizeof item / sizeof item[0]; ++k) {
        if (item[k].n == 0)
            continue;
        if (text && at < size) {
            int w = snprintf(text + at, size - at, "%s%zu %s", n ? ", " : "", item[k].n,
                             item[k].what);
            at += w > 0 ? (size_t)w : 0;
        }
        ++n;
    }
    return n;
}

static double dist3(const double *p, const double *q)
{
    double r[3];
    sub3(p, q, r);
    return sqrt(dot3(r, r));
}

relief_status relief_mesh_check_range(const relief_mesh *m, relief_error *err)
{
    const size_t nv = m->nv;
    double med[3], gap = INFINITY;
    double *d = malloc((nv + 1) * sizeof *d);
    if (!d)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate %zu distances", nv);
    for (size_t v = 0; v < nv; ++v)
        for (int k = 0; k < 3; ++k)
            if (fabs(m->pos[3 * v + k]) > 1e30) {
                free(d);
                return relief_fail(err, RELIEF_E_MESH, "vertex %zu: its coordinates (%g, %g, "
                                   "%g) are out of range: over 1e30 in magnitude", v,
                                   m->pos[3 * v], m->pos[3 * v + 1], m->pos[3 * v + 2]);
            }
    for (int k = 0; k < 3 && d; ++k) {
        for (size_t v = 0; v < nv; ++v)
            d[v] = m->pos[3 * v + k];
        if (relief_sort_doubles(d, nv))
            free(d), d = NULL;
        else
            med[k] = d[nv / 2];
    }
    for (size_t v = 0; d && v < nv; ++v)
        d[v] = dist3(m->pos + 3 * v, med);
    if (d && relief_sort_doubles(d, nv))
        free(d), d = NULL;
    if (!d)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot sort %zu distances", nv);
    /* The first jump of over 1e15 between neighbouring distances: the
     * vertices beyond it are that much farther than the rest's extent. */
    for (size_t i = 1; i < nv && gap == INFINITY; ++i)
        if (d[i - 1] > 0.0 && d[i] > 1e15 * d[i - 1])
            gap = d[i];
    free(d);
    for (size_t v = 0; gap < INFINITY && v < nv; ++v) {
        const double *p = m->pos + 3 * v;
        if (dist3(p, med) >= gap)
            return relief_fail(err, RELIEF_E_MESH, "vertex %zu: its coordinates (%g, %g, %g) "
                               "are out of range: over 1e15 times farther from the mesh's "
                               "median point than the other vertices", v, p[0], p[1], p[2]);
    }
    return RELIEF_OK;
}
