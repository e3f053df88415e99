/* Hole patches triangulated over their mean plane (patch_mesh.h). */
#include "points/patch_mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/compare.h"
#include "base/error.h"
#include "base/linalg.h"
#include "base/union_find.h"
#include "base/vec3.h"
#include "mesh/io_openmesh.h"
#include "mesh/mesh.h"
#include "points/surface_mesh.h"
#include "smooth/delaunay.h"

#define PATCH_MAX_CIRCUMRADIUS 3.0 /* spacings */
/* The longest gap loop closed by ears after the fronts: a patch that met
 * its rim along part of it leaves a thin strip between them, one loop
 * round the hole (97 edges on a 30 mm cut in a vase's wall); no ear's
 * diagonal is longer than 2 x PATCH_MAX_CIRCUMRADIUS spacings, so a wide
 * gap stays open rather than being spanned. */
#define PATCH_MAX_GAP_LOOP 4096

/* A set of directed edges (open addressing on 64-bit keys). */
typedef struct edge_set {
    uint64_t *key;
    size_t cap, n;
} edge_set;

static size_t edge_slot(const edge_set *e, uint64_t k)
{
    size_t i = (size_t)((k * 0x9E3779B97F4A7C15ull) >> 20) & (e->cap - 1);
    while (e->key[i] && e->key[i] != k)
        i = (i + 1) & (e->cap - 1);
    return i;
}

static uint64_t edge_key(uint32_t a, uint32_t b)
{
    return ((uint64_t)a << 32 | b) + 1; /* 0 marks an empty slot */
}

static int edge_has(const edge_set *e, uint32_t a, uint32_t b)
{
    return e->key[edge_slot(e, edge_key(a, b))] != 0;
}

static void edge_add(edge_set *e, uint32_t a, uint32_t b)
{
    size_t i = edge_slot(e, edge_key(a, b));
    if (!e->key[i])
        e->key[i] = edge_key(a, b), ++e->n;
}

static int cand_cmp(const void *x, const void *y)
{
    const relief_cand_tri *a = x, *b = y;
    if (a->rank != b->rank)
        return a->rank < b->rank ? -1 : 1;
    if (a->r != b->r)
        return a->r < b->r ? -1 : 1;
    for (int k = 0; k < 3; ++k)
        if (a->v[k] != b->v[k])
            return a->v[k] < b->v[k] ? -1 : 1;
    return 0;
}

double relief_circumradius(const double *a, const double *b, const double *c)
{
    double ab[3], ac[3], bc[3], x[3], la, lb, lc, area2;
    sub3(b, a, ab), sub3(c, a, ac), sub3(c, b, bc);
    cross3(ab, ac, x);
    area2 = sqrt(dot3(x, x)); /* twice the area */
    la = sqrt(dot3(bc, bc)), lb = sqrt(dot3(ac, ac)), lc = sqrt(dot3(ab, ab));
    return area2 > 0.0 ? la * lb * lc / (2.0 * area2) : INFINITY;
}

/* Does vertex v's fan (its triangles' link edges b -> c, each triangle
 * (v, b, c) in order) form one path or one cycle? Several fans at a vertex
 * make it non-manifold, which the mesh writer refuses. link: the fan's
 * link edges, 2 each, m of them. A join is a pair of edges, one ending
 * where the other starts; the walk from edge 0 follows, at each step, the
 * last edge (by index) that starts where the current one ends. by_start
 * (m pairs, scratch) holds the edges sorted by (start, index), so that
 * both take m log m: a hole patch over a folded rim can put thousands of
 * triangles round one vertex. */
typedef struct link_key {
    uint32_t start, index;
} link_key;

static int link_key_cmp(const void *x, const void *y)
{
    const link_key *a = x, *b = y;
    if (a->start != b->start)
        return a->start < b->start ? -1 : 1;
    return (a->index > b->index) - (a->index < b->index);
}

/* The edges starting at `start`: [*lo, *hi) of by_start. */
static void link_range(const link_key *k, size_t m, uint32_t start, size_t *lo, size_t *hi)
{
    size_t a = 0, b = m;
    while (a < b) {
        size_t c = (a + b) / 2;
        if (k[c].start < start)
            a = c + 1;
        else
            b = c;
    }
    *lo = a;
    for (b = m; a < b;) {
        size_t c = (a + b) / 2;
        if (k[c].start <= start)
            a = c + 1;
        else
            b = c;
    }
    *hi = a;
}

static int one_fan(const uint32_t *link, size_t m, link_key *by_start)
{
    size_t joins = 0, start = 0, walked = 1;
    if (m <= 1)
        return 1;
    for (size_t i = 0; i < m; ++i)
        by_start[i] = (link_key){link[2 * i], (uint32_t)i};
    qsort(by_start, m, sizeof *by_start, link_key_cmp);
    for (size_t i = 0; i < m; ++i) {
        size_t lo, hi;
        link_range(by_start, m, link[2 * i + 1], &lo, &hi);
        joins += hi - lo - (link[2 * i] == link[2 * i + 1]);
    }
    if (joins + 1 == m)
        return 1; /* one open path (directed edges are unique) */
    if (joins != m)
        return 0;
    /* m joins: cycles only; one cycle when a walk from edge 0 meets all.
     * A walk may also fall into a cycle that misses edge 0 (two edges
     * starting at one corner, one fan's end joining another's middle): it
     * stops after m steps, not one fan. */
    for (size_t cur = start; walked <= m;) {
        size_t lo, hi, next;
        link_range(by_start, m, link[2 * cur + 1], &lo, &hi);
        next = lo < hi ? by_start[hi - 1].index : m;
        if (next == start || next == m)
            break;
        cur = next, ++walked;
    }
    return walked == m;
}

/* Drop patch triangles (indices >= first_patch of all) around every vertex
 * whose fan is not one, until none is left. tri: nt x 3, compacted in
 * place; returns the new count. */
static size_t drop_non_manifold(uint32_t *tri, size_t nt, size_t first_patch, size_t nv,
                                int *nomem)
{
    for (;;) {
        uint32_t *start = calloc(nv + 1, sizeof *start), *inc = malloc(3 * nt * sizeof *inc + 1);
        uint32_t *link = NULL;
        link_key *keys = NULL;
        uint8_t *bad = calloc(nv + 1, 1), *drop = calloc(nt + 1, 1);
        size_t link_cap = 0, n_bad = 0, kept = 0;
        if (!start || !inc || !bad || !drop) {
            free(start), free(inc), free(bad), free(drop);
            *nomem = 1;
            return nt;
        }
        {
            relief_mesh view; /* the triangles at each vertex, ascending */
            memset(&view, 0, sizeof view);
            view.nv = nv, view.nt = nt, view.tri = tri;
            relief_mesh_vertex_triangles(&view, start, inc);
        }
        for (size_t v = 0; v < nv; ++v) {
            size_t m = start[v + 1] - start[v];
            int any_patch = 0;
            if (m < 2)
                continue;
            if (m > link_cap) {
                uint32_t *g = realloc(link, 2 * m * sizeof *g);
                link_key *k = g ? realloc(keys, m * sizeof *k) : NULL;
                if (g)
                    link = g;
                if (!k) {
                    *nomem = 1;
                    break;
                }
                keys = k, link_cap = m;
            }
            for (size_t e = 0; e < m; ++e) {
                const uint32_t t = inc[start[v] + e], *x = tri + 3 * (size_t)t;
                int at = x[0] == v ? 0 : x[1] == v ? 1 : 2;
                link[2 * e] = x[(at + 1) % 3], link[2 * e + 1] = x[(at + 2) % 3];
                any_patch |= t >= first_patch;
            }
            if (any_patch && !one_fan(link, m, keys)) {
                bad[v] = 1, ++n_bad;
                for (size_t e = 0; e < m; ++e)
                    if (inc[start[v] + e] >= first_patch)
                        drop[inc[start[v] + e]] = 1;
            }
        }
        for (size_t t = 0; t < nt; ++t)
            if (!drop[t])
                memmove(tri + 3 * kept++, tri + 3 * t, 3 * sizeof *tri);
        free(start), free(inc), free(bad), free(drop), free(link), free(keys);
        if (*nomem || !n_bad || kept == nt)
            return kept;
        nt = kept;
    }
}

/* relief_points_lay_triangles' state: the directed edges laid, the
 * triangles kept (tri, kept), and the laying order (ord, no). */
typedef struct lay_state {
    edge_set es;
    const uint32_t *tri_in;
    size_t nt_in, N;
    uint32_t *tri, *ord;      /* kept x 3, no x 3 */
    size_t kept, no;
    uint8_t *placed;          /* kept: t is in ord */
    uint8_t *has_face;        /* N: a vertex with a triangle laid */
} lay_state;

static void add_edges(edge_set *es, const uint32_t *v)
{
    edge_add(es, v[0], v[1]), edge_add(es, v[1], v[2]), edge_add(es, v[2], v[0]);
}

/* The edge set holds the mesh's own triangles' edges alone. */
static void mesh_edges(lay_state *s)
{
    memset(s->es.key, 0, s->es.cap * sizeof *s->es.key);
    for (size_t t = 0; t < s->nt_in; ++t)
        for (int q = 0; q < 3; ++q)
            edge_add(&s->es, s->tri_in[3 * t + q], s->tri_in[3 * t + (q + 1) % 3]);
}

/* Greedily, in rank then circumradius order, a triangle joins when none of
 * its directed edges is taken yet (by the mesh or an earlier one): every
 * edge then has at most one triangle a side, consistently oriented, which
 * the mesh writer (OpenMesh) needs. */
static void lay_greedy(lay_state *s, const relief_cand_tri *cand, size_t ncand)
{
    mesh_edges(s);
    for (size_t t = 0; t < ncand; ++t) {
        const uint32_t *v = cand[t].v;
        if (edge_has(&s->es, v[0], v[1]) || edge_has(&s->es, v[1], v[2]) ||
            edge_has(&s->es, v[2], v[0]))
            continue;
        add_edges(&s->es, v);
        memcpy(s->tri + 3 * s->kept++, v, 3 * sizeof *s->tri);
    }
}

/* Then no vertex may end with two fans: the input's triangles and the new
 * ones together, new ones dropped where it would. 0 when memory runs out. */
static int lay_manifold(lay_state *s)
{
    uint32_t *all = malloc((s->nt_in + s->kept) * 3 * sizeof *all + 1);
    int nomem = 0;
    size_t total;
    if (!all)
        return 0;
    if (s->nt_in)
        memcpy(all, s->tri_in, s->nt_in * 3 * sizeof *all);
    memcpy(all + 3 * s->nt_in, s->tri, s->kept * 3 * sizeof *all);
    total = drop_non_manifold(all, s->nt_in + s->kept, s->nt_in, s->N, &nomem);
    if (!nomem) {
        s->kept = total - s->nt_in;
        memcpy(s->tri, all + 3 * s->nt_in, s->kept * 3 * sizeof *s->tri);
    }
    free(all);
    return !nomem;
}

/* The passes of a scan in index order, repeated until one lays nothing,
 * without scanning: a triangle's eligibility changes only when a triangle
 * sharing one of its corners is laid, so only those are looked at again,
 * in the order the scan would reach them (the pass's rest from the
 * cursor, the next pass's from the start). Laying order and result are the
 * scan's; the cost is linear in the triangles and their corners' fans, not
 * quadratic (a statue's base patch of 20 000 triangles took over ten
 * minutes in the scan, one pass per front step). */
typedef struct index_heap {
    uint32_t *a;
    size_t n;
} index_heap;

static void heap_push(index_heap *h, uint32_t x)
{
    size_t i = h->n++;
    for (; i > 0 && h->a[(i - 1) / 2] > x; i = (i - 1) / 2)
        h->a[i] = h->a[(i - 1) / 2];
    h->a[i] = x;
}

static uint32_t heap_pop(index_heap *h)
{
    uint32_t top = h->a[0], x = h->a[--h->n];
    size_t i = 0;
    for (;;) {
        size_t c = 2 * i + 1;
        if (c >= h->n)
            break;
        if (c + 1 < h->n && h->a[c + 1] < h->a[c])
            ++c;
        if (h->a[c] >= x)
            break;
        h->a[i] = h->a[c], i = c;
    }
    if (h->n)
        h->a[i] = x;
    return top;
}

typedef struct scan_state {
    uint32_t *vstart, *vtri; /* N + 1, 3 kept: the triangles at each corner
                                (relief_mesh_vertex_triangles) */
    uint8_t *queued;         /* kept: in this or the next pass's heap */
    index_heap pass, next;
    size_t cursor;           /* the index the scan is at; SIZE_MAX: a pass starts */
} scan_state;

static int scan_init(scan_state *q, const lay_state *s)
{
    memset(q, 0, sizeof *q);
    q->vstart = malloc((s->N + 1) * sizeof *q->vstart);
    q->vtri = malloc(3 * s->kept * sizeof *q->vtri + 1);
    q->queued = calloc(s->kept + 1, 1);
    q->pass.a = malloc(s->kept * sizeof *q->pass.a + 1);
    q->next.a = malloc(s->kept * sizeof *q->next.a + 1);
    if (!q->vstart || !q->vtri || !q->queued || !q->pass.a || !q->next.a)
        return 0;
    {
        relief_mesh view;
        memset(&view, 0, sizeof view);
        view.nv = s->N, view.nt = s->kept, view.tri = s->tri;
        relief_mesh_vertex_triangles(&view, q->vstart, q->vtri);
    }
    q->cursor = SIZE_MAX;
    return 1;
}

static void scan_free(scan_state *q)
{
    free(q->vstart), free(q->vtri), free(q->queued), free(q->pass.a), free(q->next.a);
}

/* t is looked at again: in this pass if the scan has not passed it yet. */
static void scan_queue(scan_state *q, const lay_state *s, uint32_t t)
{
    if (s->placed[t] || q->queued[t])
        return;
    q->queued[t] = 1;
    heap_push(q->cursor == SIZE_MAX || t > q->cursor ? &q->pass : &q->next, t);
}

/* Every triangle not laid, for a pass from the start. */
static void scan_all(scan_state *q, const lay_state *s)
{
    q->cursor = SIZE_MAX;
    for (uint32_t t = 0; t < s->kept; ++t)
        scan_queue(q, s, t);
}

/* The next triangle the scan reaches that may have changed, or SIZE_MAX
 * when a whole pass would lay nothing. */
static size_t scan_next(scan_state *q)
{
    if (!q->pass.n) {
        index_heap h = q->pass;
        if (!q->next.n)
            return SIZE_MAX;
        q->pass = q->next, q->next = h;
    }
    q->cursor = heap_pop(&q->pass);
    q->queued[q->cursor] = 0;
    return q->cursor;
}

static void place(lay_state *s, scan_state *q, size_t t)
{
    const uint32_t *v = s->tri + 3 * t;
    add_edges(&s->es, v);
    memcpy(s->ord + 3 * s->no++, v, 3 * sizeof *s->ord);
    s->placed[t] = 1;
    for (int c = 0; c < 3; ++c)
        for (uint32_t k = q->vstart[v[c]]; k < q->vstart[v[c] + 1]; ++k)
            scan_queue(q, s, q->vtri[k]);
}

/* May t join the fronts: it shares an edge with what is laid, each of its
 * corners with faces reached through one of its two edges here, never by
 * a corner alone. */
static int front_fits(const lay_state *s, size_t t)
{
    const uint8_t *hf = s->has_face;
    const uint32_t *v = s->tri + 3 * t;
    int shared[3]; /* shared[q]: edge v[q] -> v[q + 1] has a face */
    if (hf[v[0]] + hf[v[1]] + hf[v[2]] < 2)
        return 0; /* a shared edge has two corners with faces */
    for (int q = 0; q < 3; ++q)
        shared[q] = edge_has(&s->es, v[(q + 1) % 3], v[q]);
    if (!shared[0] && !shared[1] && !shared[2])
        return 0;
    for (int q = 0; q < 3; ++q)
        if (hf[v[q]] && !shared[q] && !shared[(q + 2) % 3])
            return 0;
    return 1;
}

/* Every triangle a front reaches from what is laid, until none is left. */
static void front_pass(lay_state *s, scan_state *q)
{
    for (size_t t; (t = scan_next(q)) != SIZE_MAX;) {
        const uint32_t *v = s->tri + 3 * t;
        if (!front_fits(s, t))
            continue;
        s->has_face[v[0]] = s->has_face[v[1]] = s->has_face[v[2]] = 1;
        place(s, q, t);
    }
    q->cursor = SIZE_MAX; /* the next front_pass starts from the first */
}

/* In the order a front would lay them: each next triangle shares an edge
 * with what is there. OpenMesh adds faces one by one and cannot relink a
 * vertex between two separate fans, which a triangle laid apart from the
 * rest would make for a while. With seed_islands, a front that stops
 * starts again from the first triangle left whose corners have no faces
 * yet (a new component). Then what the fronts left where they met
 * (cracks), after the rest; islands stay out: no front could reach them. */
static void lay_fronts(lay_state *s, scan_state *q, int seed_islands)
{
    mesh_edges(s);
    for (size_t t = 0; t < 3 * s->nt_in; ++t)
        s->has_face[s->tri_in[t]] = 1;
    scan_all(q, s);
    for (size_t seed = 0;;) {
        const uint32_t *v;
        front_pass(s, q);
        if (!seed_islands)
            break;
        while (seed < s->kept && (s->placed[seed] || s->has_face[s->tri[3 * seed]] ||
                                  s->has_face[s->tri[3 * seed + 1]] ||
                                  s->has_face[s->tri[3 * seed + 2]]))
            ++seed;
        if (seed == s->kept)
            break;
        v = s->tri + 3 * seed;
        s->has_face[v[0]] = s->has_face[v[1]] = s->has_face[v[2]] = 1;
        place(s, q, seed);
    }
    scan_all(q, s);
    for (size_t t; (t = scan_next(q)) != SIZE_MAX;) {
        const uint32_t *v = s->tri + 3 * t;
        if (edge_has(&s->es, v[1], v[0]) || edge_has(&s->es, v[2], v[1]) ||
            edge_has(&s->es, v[0], v[2]))
            place(s, q, t);
    }
}

/* Those of ord OpenMesh itself can store in this order (its add_face
 * cannot always relink a vertex whose fans a corner split) into tri; the
 * writer adds them in the same order. */
static relief_status lay_storable(lay_state *s, const double *pos, relief_error *err)
{
    relief_mesh view;
    size_t w = 0;
    uint8_t *ok = malloc(s->no + 1);
    relief_status st;
    if (!ok)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate %zu triangles", s->no);
    memset(&view, 0, sizeof view);
    view.nv = s->N, view.nt = s->nt_in;
    view.pos = (double *)pos, view.tri = (uint32_t *)s->tri_in;
    st = relief_om_storable(&view, s->ord, s->no, ok, err);
    for (size_t t = 0; st == RELIEF_OK && t < s->no; ++t)
        if (ok[t])
            memcpy(s->tri + 3 * w++, s->ord + 3 * t, 3 * sizeof *s->tri);
    s->kept = w;
    free(ok);
    return st;
}

relief_status relief_points_lay_triangles(const double *pos, size_t N, const uint32_t *tri_in,
                                          size_t nt_in, relief_cand_tri *cand, size_t ncand,
                                          int seed_islands, uint32_t **tri_out, size_t *nt_out,
                                          relief_error *err)
{
    lay_state s;
    scan_state q;
    relief_status st = RELIEF_OK;

    *tri_out = NULL;
    *nt_out = 0;
    if (!ncand)
        return RELIEF_OK;
    memset(&s, 0, sizeof s);
    memset(&q, 0, sizeof q);
    s.tri_in = tri_in, s.nt_in = nt_in, s.N = N;
    qsort(cand, ncand, sizeof *cand, cand_cmp);
    for (s.es.cap = 1024; s.es.cap < 4 * (3 * (nt_in + ncand) + 1); s.es.cap *= 2)
        ;
    s.es.key = calloc(s.es.cap, sizeof *s.es.key);
    s.tri = malloc(ncand * 3 * sizeof *s.tri);
    if (s.es.key && s.tri)
        lay_greedy(&s, cand, ncand);
    if (s.es.key && s.tri && lay_manifold(&s)) {
        s.ord = malloc(s.kept * 3 * sizeof *s.ord + 1);
        s.placed = calloc(s.kept + 1, 1);
        s.has_face = calloc(N + 1, 1);
    }
    if (s.ord && s.placed && s.has_face && scan_init(&q, &s)) {
        lay_fronts(&s, &q, seed_islands);
        st = lay_storable(&s, pos, err);
    } else {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate %zu triangles", ncand);
    }
    scan_free(&q);
    free(s.es.key), free(s.ord), free(s.placed), free(s.has_face);
    if (st != RELIEF_OK || !s.kept) {
        free(s.tri);
        return st;
    }
    *tri_out = s.tri;
    *nt_out = s.kept;
    return RELIEF_OK;
}

/* Candidate triangles, grown as they come. */
typedef struct cand_list {
    relief_cand_tri *v;
    size_t n, cap;
} cand_list;

static int cand_push(cand_list *l, relief_cand_tri c)
{
    if (l->n == l->cap) {
        size_t nc = l->cap ? 2 * l->cap : 1024;
        relief_cand_tri *g = realloc(l->v, nc * sizeof *g);
        if (!g)
            return 0;
        l->v = g, l->cap = nc;
    }
    l->v[l->n++] = c;
    return 1;
}

/* The points of hole k (its rim's capture points and its new points, of
 * the N, the first n_in the capture's), in ids, with their (u, v) in the
 * plane of their mean normal through their centroid, in uv (both room for
 * N). How many there are; 0 when they are fewer than 3, hold no new point
 * or their normals cancel (*skipped counts that one). */
static size_t hole_points(const double *pos, const double *nrm, size_t n_in, size_t N,
                          const uint32_t *rim, const uint32_t *hole, uint32_t k, uint32_t *ids,
                          double *uv, size_t *skipped)
{
    double c[3] = {0, 0, 0}, nm[3] = {0, 0, 0}, u[3], v[3];
    size_t m = 0, fresh = 0;
    for (size_t i = 0; i < N; ++i)
        if (i < n_in ? rim[i] == k : hole[i - n_in] == k) {
            ids[m++] = (uint32_t)i;
            fresh += i >= n_in;
            for (int a = 0; a < 3; ++a)
                c[a] += pos[3 * i + a], nm[a] += nrm[3 * i + a];
        }
    if (m < 3 || !fresh)
        return 0;
    for (int a = 0; a < 3; ++a)
        c[a] /= (double)m;
    if (relief_normalize3(nm) == 0.0) {
        ++*skipped;
        return 0;
    }
    relief_perp_basis(nm, u, v);
    for (size_t j = 0; j < m; ++j) {
        double d[3];
        sub3(pos + 3 * (size_t)ids[j], c, d);
        uv[2 * j] = dot3(d, u), uv[2 * j + 1] = dot3(d, v);
    }
    return m;
}

/* The Delaunay triangles of hole k's points (hole_points) that touch a new
 * point and are no wider than the patch's bound, turned to the points'
 * normals, onto `out`. A triangulation that fails (collinear points) skips
 * the hole (*skipped); only running out of memory fails. */
static relief_status hole_candidates(const double *pos, const double *nrm, size_t n_in,
                                     size_t N, const uint32_t *rim, const uint32_t *hole,
                                     uint32_t k, double spacing, uint32_t *ids, double *uv,
                                     cand_list *out, size_t *skipped, relief_error *err)
{
    uint32_t *pt = NULL;
    size_t pnt = 0;
    relief_error qerr;
    size_t m = hole_points(pos, nrm, n_in, N, rim, hole, k, ids, uv, skipped);
    if (!m)
        return RELIEF_OK;
    if (relief_delaunay_2d(uv, m, &pt, &pnt, NULL, &qerr) != RELIEF_OK) {
        if (qerr.status == RELIEF_E_NOMEM)
            return relief_fail(err, RELIEF_E_NOMEM, "cannot triangulate hole %u", k);
        ++*skipped;
        return RELIEF_OK;
    }
    for (size_t t = 0; t < pnt; ++t) {
        uint32_t a = ids[pt[3 * t]], b = ids[pt[3 * t + 1]], d = ids[pt[3 * t + 2]];
        double e1[3], e2[3], x[3], vn[3];
        if (a < n_in && b < n_in && d < n_in)
            continue; /* rim only: over the capture, or a gap along the rim */
        double r = relief_circumradius(pos + 3 * (size_t)a, pos + 3 * (size_t)b, pos + 3 * (size_t)d);
        if (r > PATCH_MAX_CIRCUMRADIUS * spacing)
            continue;
        sub3(pos + 3 * (size_t)b, pos + 3 * (size_t)a, e1);
        sub3(pos + 3 * (size_t)d, pos + 3 * (size_t)a, e2);
        cross3(e1, e2, x);
        for (int q = 0; q < 3; ++q)
            vn[q] = nrm[3 * (size_t)a + q] + nrm[3 * (size_t)b + q] + nrm[3 * (size_t)d + q];
        if (dot3(x, vn) < 0.0) {
            uint32_t s = b;
            b = d, d = s;
        }
        if (!cand_push(out, (relief_cand_tri){r, 0, {a, b, d}})) {
            free(pt);
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the hole patches");
        }
    }
    free(pt);
    return RELIEF_OK;
}

/* The cracks where fronts from two sides met, the strip a patch left along
 * part of its rim, and the filled holes too small for a new point: loops
 * through a new point or a filled hole's rim, closed by ears, with the
 * mesh's own triangles (tri_in) in view (a loop of the capture's that the
 * hole model leaves open stays open). The ears join the patches' *nt
 * triangles *tri (reallocated). */
static relief_status close_patch_gaps(const double *pos, size_t N, size_t n_in,
                                      const uint32_t *rim, double spacing,
                                      const uint32_t *tri_in, size_t nt_in, uint32_t **tri,
                                      size_t *nt, relief_error *err)
{
    uint32_t *all = malloc((nt_in + *nt) * 3 * sizeof *all + 1);
    size_t nall = nt_in + *nt;
    relief_status st;
    if (!all)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the hole patches");
    memcpy(all, tri_in, nt_in * 3 * sizeof *all);
    memcpy(all + 3 * nt_in, *tri, *nt * 3 * sizeof *all);
    st = relief_points_close_gaps(pos, N, n_in, rim, 2.0 * PATCH_MAX_CIRCUMRADIUS * spacing,
                                  PATCH_MAX_GAP_LOOP, &all, &nall, err);
    if (st == RELIEF_OK && nall > nt_in + *nt) {
        uint32_t *g = realloc(*tri, (nall - nt_in) * 3 * sizeof *g);
        if (!g) {
            st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the hole patches");
        } else {
            *tri = g, *nt = nall - nt_in;
            memcpy(*tri, all + 3 * nt_in, *nt * 3 * sizeof **tri);
        }
    }
    free(all);
    return st;
}

relief_status relief_points_patch_mesh(const double *pos, const double *nrm, size_t n_in,
                                       size_t N, const uint32_t *rim, const uint32_t *hole,
                                       uint32_t n_holes, double spacing, const uint32_t *tri_in,
                                       size_t nt_in, uint32_t **tri_out, size_t *nt_out,
                                       size_t *skipped, relief_error *err)
{
    uint32_t *ids = malloc((N + 1) * sizeof *ids), *tri = NULL;
    double *uv = malloc((N + 1) * 2 * sizeof *uv);
    cand_list cand = {NULL, 0, 0};
    size_t nt = 0;
    relief_status st = RELIEF_OK;

    *tri_out = NULL;
    *nt_out = 0;
    *skipped = 0;
    if (!ids || !uv) {
        free(ids), free(uv);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the hole patches");
    }
    for (uint32_t k = 1; k <= n_holes && st == RELIEF_OK; ++k)
        st = hole_candidates(pos, nrm, n_in, N, rim, hole, k, spacing, ids, uv, &cand, skipped,
                             err);
    if (st == RELIEF_OK && cand.n)
        st = relief_points_lay_triangles(pos, N, tri_in, nt_in, cand.v, cand.n, 0, &tri, &nt,
                                         err);
    if (st == RELIEF_OK)
        st = close_patch_gaps(pos, N, n_in, rim, spacing, tri_in, nt_in, &tri, &nt, err);
    free(ids), free(uv), free(cand.v);
    if (st != RELIEF_OK) {
        free(tri);
        return st;
    }
    *tri_out = nt ? tri : NULL;
    if (!nt)
        free(tri);
    *nt_out = nt;
    return RELIEF_OK;
}

relief_status relief_points_open_loops(const uint32_t *tri, size_t nt, size_t N, size_t n_in,
                                       const uint32_t *rim, size_t *edges, size_t *loops,
                                       relief_error *err)
{
    uint64_t *e = malloc((3 * nt + 1) * sizeof *e);
    uint32_t *parent = malloc((N + 1) * sizeof *parent);
    uint8_t *on = calloc(N + 1, 1);
    *edges = *loops = 0;
    if (!e || !parent || !on) {
        free(e), free(parent), free(on);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot check the %zu-triangle surface's "
                           "loops", nt);
    }
    for (size_t t = 0; t < nt; ++t)
        for (int q = 0; q < 3; ++q) {
            uint64_t a = tri[3 * t + q], b = tri[3 * t + (q + 1) % 3];
            e[3 * t + q] = a < b ? a << 32 | b : b << 32 | a;
        }
    qsort(e, 3 * nt, sizeof *e, relief_cmp_u64);
    for (size_t v = 0; v < N; ++v)
        parent[v] = (uint32_t)v;
    /* on: 1 on the boundary, 2 on a loop through a vertex of the capture
     * off every filled rim (a border the hole model leaves open, which an
     * arc's chord may join: issue 61) */
    for (size_t i = 0, j; i < 3 * nt; i = j) {
        const uint32_t a = (uint32_t)(e[i] >> 32), b = (uint32_t)e[i];
        for (j = i + 1; j < 3 * nt && e[j] == e[i]; ++j)
            ;
        if (j - i != 1)
            continue;
        on[a] |= 1, on[b] |= 1;
        relief_uf_join(parent, a, b);
    }
    for (size_t v = 0; v < n_in; ++v)
        if (on[v] && !rim[v])
            on[relief_uf_find(parent, (uint32_t)v)] |= 2;
    for (size_t v = 0; v < N; ++v)
        *loops += on[v] == 1 && relief_uf_find(parent, (uint32_t)v) == v;
    for (size_t i = 0, j; i < 3 * nt; i = j) {
        const uint32_t a = (uint32_t)(e[i] >> 32);
        for (j = i + 1; j < 3 * nt && e[j] == e[i]; ++j)
            ;
        *edges += j - i == 1 && !(on[relief_uf_find(parent, a)] & 2);
    }
    free(e), free(parent), free(on);
    return RELIEF_OK;
}
