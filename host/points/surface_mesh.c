/* Local Delaunay umbrellas of a point set, made one surface
 * (surface_mesh.h). */
#include "points/surface_mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/compare.h"
#include "base/error.h"
#include "base/linalg.h"
#include "base/vec3.h"
#include "points/analysis.h"
#include "mesh/io_openmesh.h"
#include "mesh/mesh.h"
#include "points/patch_mesh.h"

#define SURF_CELL_RADIUS 3.0 /* spacings: the 16-gon the Voronoi cell is cut from */
#define SURF_CELL_SIDES 16
#define SURF_MAX_VERTS (SURF_CELL_SIDES + 2 * 64 + 4) /* a cut adds at most one vertex */

/* A convex polygon about the origin of the tangent plane, counter-
 * clockwise; edge e runs from vertex e to vertex e + 1 and was cut by
 * neighbour tag[e] (-1: the outer 16-gon). */
typedef struct cell {
    int m;
    double x[SURF_MAX_VERTS], y[SURF_MAX_VERTS];
    int tag[SURF_MAX_VERTS];
} cell;

/* Keep the part of c nearer the origin than (qx, qy): the half-plane
 * x qx + y qy <= (qx^2 + qy^2) / 2, its new edge tagged t. */
static void cell_cut(cell *c, double qx, double qy, int t)
{
    cell o;
    const double h = 0.5 * (qx * qx + qy * qy);
    o.m = 0;
    for (int e = 0; e < c->m; ++e) {
        const int f = (e + 1) % c->m;
        const double fa = c->x[e] * qx + c->y[e] * qy - h, fb = c->x[f] * qx + c->y[f] * qy - h;
        if (fa <= 0.0)
            o.x[o.m] = c->x[e], o.y[o.m] = c->y[e], o.tag[o.m++] = c->tag[e];
        if ((fa <= 0.0) != (fb <= 0.0) && o.m < SURF_MAX_VERTS) {
            const double s = fa / (fa - fb);
            o.x[o.m] = c->x[e] + s * (c->x[f] - c->x[e]);
            o.y[o.m] = c->y[e] + s * (c->y[f] - c->y[e]);
            o.tag[o.m++] = fa <= 0.0 ? t : c->tag[e]; /* leaving: along the cut */
        }
    }
    *c = o;
}

/* A proposed triangle, its smallest index first (orientation kept). */
typedef struct vote {
    uint32_t v[3];
} vote;

static int vote_cmp(const void *x, const void *y)
{
    const vote *a = x, *b = y;
    for (int q = 0; q < 3; ++q)
        if (a->v[q] != b->v[q])
            return a->v[q] < b->v[q] ? -1 : 1;
    return 0;
}

static vote vote_make(uint32_t a, uint32_t b, uint32_t c)
{
    vote w;
    if (a < b && a < c)
        w.v[0] = a, w.v[1] = b, w.v[2] = c;
    else if (b < c)
        w.v[0] = b, w.v[1] = c, w.v[2] = a;
    else
        w.v[0] = c, w.v[1] = a, w.v[2] = b;
    return w;
}

/* Point i's umbrella: the triangles its Voronoi cell proposes, appended
 * to out (room for k + SURF_CELL_SIDES); returns how many. */
static size_t umbrella(const double *pos, const double *nrm, const relief_knn_graph *g,
                       size_t i, double radius, vote *out)
{
    const double *p = pos + 3 * i, *n = nrm + 3 * i;
    double u[3], v[3], reach = radius;
    cell c;
    size_t nv = 0;

    relief_perp_basis(n, u, v);
    cross3(n, u, v); /* (u, v, n) right-handed: counter-clockwise about n */
    c.m = SURF_CELL_SIDES;
    for (int s = 0; s < SURF_CELL_SIDES; ++s) {
        const double a = 2.0 * RELIEF_PI * s / SURF_CELL_SIDES;
        c.x[s] = radius * cos(a), c.y[s] = radius * sin(a), c.tag[s] = -1;
    }
    for (int j = 0; j < g->k; ++j) {
        const uint32_t q = g->nbr[i * (size_t)g->k + (size_t)j];
        double d[3], x, y, h, r2;
        sub3(pos + 3 * (size_t)q, p, d);
        x = dot3(d, u), y = dot3(d, v), h = dot3(d, n);
        r2 = x * x + y * y;
        if (dot3(nrm + 3 * (size_t)q, n) <= 0.0 || h * h > r2 || !(r2 > 0.0))
            continue; /* another sheet, or the same place */
        if (0.5 * sqrt(r2) > reach)
            continue; /* its bisector misses the cell */
        cell_cut(&c, x, y, j);
        reach = 0.0;
        for (int e = 0; e < c.m; ++e)
            reach = fmax(reach, sqrt(c.x[e] * c.x[e] + c.y[e] * c.y[e]));
    }
    for (int e = 0; e < c.m; ++e) {
        const int a = c.tag[e], b = c.tag[(e + 1) % c.m];
        if (a >= 0 && b >= 0 && a != b)
            out[nv++] = vote_make((uint32_t)i, g->nbr[i * (size_t)g->k + (size_t)a],
                                  g->nbr[i * (size_t)g->k + (size_t)b]);
    }
    return nv;
}

#define SURF_MAX_LOOP 12 /* edges: longer gaps stay open */

/* A half-edge a -> b of the surface (key a << 32 | b) and the third corner
 * of its triangle. */
typedef struct half_edge {
    uint64_t key;
    uint32_t third;
} half_edge;

static int half_edge_cmp(const void *x, const void *y)
{
    return relief_cmp_u64(&((const half_edge *)x)->key, &((const half_edge *)y)->key);
}

static const half_edge *find_half_edge(const half_edge *he, size_t m, uint32_t a, uint32_t b)
{
    const half_edge k = {(uint64_t)a << 32 | b, 0};
    return bsearch(&k, he, m, sizeof *he, half_edge_cmp);
}

/* Where a gap goes on after it runs b -> a (the surface has a -> b and no
 * b -> a): turn about a from the triangle of a -> b, across the edges with
 * a triangle on both sides, to the first x -> a with none on the other;
 * the gap goes on to x. Two gaps meeting at a vertex (a pinch) are so kept
 * apart. UINT32_MAX when the fan does not end. */
static uint32_t gap_next(const half_edge *he, size_t m, uint32_t a, uint32_t b)
{
    for (size_t turns = 0; turns < m; ++turns) {
        const half_edge *h = find_half_edge(he, m, a, b);
        if (!h)
            return UINT32_MAX;
        if (!find_half_edge(he, m, a, h->third))
            return h->third;
        b = h->third;
    }
    return UINT32_MAX;
}

/* Cut loop (m vertices, in the gap's order) into ears, the shortest
 * diagonal first, none longer than max_diag; the ears go to *fill. 0 when
 * memory runs out. */
/* May an ear use vertex v? Not a captured vertex on no filled rim: that
 * is a border the hole model leaves open (a mouth; the rest of a border
 * whose rim is filled in part), which the gap only touches. */
static int ear_vertex(uint32_t v, size_t first_new, const uint32_t *rim)
{
    return !rim || v >= first_new || rim[v];
}

static int clip_ears(const double *pos, uint32_t *loop, size_t m, double max_diag,
                     size_t first_new, const uint32_t *rim, uint32_t **fill, size_t *nf,
                     size_t *cap)
{
    while (m >= 3) {
        size_t best = SIZE_MAX;
        double bl = max_diag;
        for (size_t q = 0; q < m && m > 3; ++q) {
            const uint32_t a = loop[(q + m - 1) % m], b = loop[q], c = loop[(q + 1) % m];
            double d[3];
            if (!ear_vertex(a, first_new, rim) || !ear_vertex(b, first_new, rim) ||
                !ear_vertex(c, first_new, rim))
                continue;
            sub3(pos + 3 * (size_t)c, pos + 3 * (size_t)a, d);
            if (sqrt(dot3(d, d)) <= bl)
                bl = sqrt(dot3(d, d)), best = q;
        }
        if (m == 3 && ear_vertex(loop[0], first_new, rim) &&
            ear_vertex(loop[1], first_new, rim) && ear_vertex(loop[2], first_new, rim))
            best = 1;
        if (best == SIZE_MAX)
            return 1;
        if (*nf == *cap) {
            size_t nc = *cap ? 2 * *cap : 256;
            uint32_t *g = realloc(*fill, nc * 3 * sizeof *g);
            if (!g)
                return 0;
            *fill = g, *cap = nc;
        }
        (*fill)[3 * *nf] = loop[(best + m - 1) % m], (*fill)[3 * *nf + 1] = loop[best];
        (*fill)[3 * *nf + 2] = loop[(best + 1) % m], ++*nf;
        memmove(loop + best, loop + best + 1, (m - best - 1) * sizeof *loop);
        --m;
    }
    return 1;
}

/* The gap loops' walk: the surface's half-edges, which gap edges are
 * walked, the loop being walked, and where each of its vertices is in it. */
typedef struct gap_walk {
    half_edge *he;
    size_t m;
    uint8_t *walked; /* m: the gap along this (twinless) half-edge is walked */
    uint32_t *loop, *at, *ears; /* ears: a loop's copy that clip_ears cuts */
    size_t n_loop;
} gap_walk;

/* Walk the gap along twinless half-edge i into w->loop (the vertices in
 * the gap's order); 0 when it does not close within max_loop edges. */
static int walk_gap(gap_walk *w, size_t i, int max_loop)
{
    uint32_t a = (uint32_t)(w->he[i].key >> 32), b = (uint32_t)w->he[i].key;
    const uint64_t start = w->he[i].key;
    w->n_loop = 0;
    for (;;) { /* the gap runs b -> a */
        const half_edge *h = find_half_edge(w->he, w->m, a, b);
        uint32_t x;
        if (!h || w->walked[h - w->he] || w->n_loop >= (size_t)max_loop)
            return 0;
        w->walked[h - w->he] = 1;
        w->loop[w->n_loop++] = b;
        x = gap_next(w->he, w->m, a, b);
        if (x == UINT32_MAX)
            return 0;
        b = a, a = x;
        if (((uint64_t)a << 32 | b) == start)
            return 1;
    }
}

/* Split a closed walk that passes a vertex twice into simple loops and
 * clip each that may close. */
static int close_walk(gap_walk *w, const double *pos, size_t first_new, const uint32_t *rim,
                      double max_diag, uint32_t **fill, size_t *nf, size_t *cap)
{
    size_t top = 0;
    uint32_t *st = w->loop; /* the stack reuses the loop in place */
    for (size_t k = 0; k <= w->n_loop; ++k) {
        const uint32_t v = k < w->n_loop ? w->loop[k] : w->loop[0];
        if (k < w->n_loop && w->at[v] == UINT32_MAX) {
            w->at[v] = (uint32_t)top;
            st[top++] = v;
            continue;
        }
        { /* v closes the loop st[at[v]] .. st[top - 1] */
            const size_t from = w->at[v];
            int fresh = 0;
            for (size_t q = from; q < top; ++q) {
                fresh |= st[q] >= first_new || (rim && rim[st[q]]);
                if (q > from)
                    w->at[st[q]] = UINT32_MAX;
            }
            if (fresh && top - from >= 3) {
                memcpy(w->ears, st + from, (top - from) * sizeof *w->ears);
                if (!clip_ears(pos, w->ears, top - from, max_diag, first_new, rim, fill, nf,
                               cap))
                    return 0;
            }
            top = from + 1;
        }
    }
    for (size_t q = 0; q < top; ++q)
        w->at[st[q]] = UINT32_MAX;
    return 1;
}

relief_status relief_points_close_gaps(const double *pos, size_t N, size_t first_new,
                                       const uint32_t *rim, double max_diag, int max_loop,
                                       uint32_t **tri, size_t *nt, relief_error *err)
{
    const size_t n = *nt;
    gap_walk w = {malloc((3 * n + 1) * sizeof *w.he), 3 * n, calloc(3 * n + 1, 1),
                  malloc(((size_t)max_loop + 1) * sizeof *w.loop),
                  malloc((N + 1) * sizeof *w.at),
                  malloc(((size_t)max_loop + 1) * sizeof *w.ears), 0};
    uint32_t *fill = NULL, *grown;
    uint8_t *ok = NULL;
    size_t nf = 0, cap = 0, kept = 0;
    relief_status st = RELIEF_OK;
    relief_mesh view;

    if (!w.he || !w.walked || !w.loop || !w.at || !w.ears)
        goto nomem;
    for (size_t t = 0; t < n; ++t)
        for (int q = 0; q < 3; ++q)
            w.he[3 * t + q] = (half_edge){(uint64_t)(*tri)[3 * t + q] << 32 |
                                              (*tri)[3 * t + (q + 1) % 3],
                                          (*tri)[3 * t + (q + 2) % 3]};
    qsort(w.he, w.m, sizeof *w.he, half_edge_cmp);
    memset(w.at, 0xff, (N + 1) * sizeof *w.at);
    /* A half-edge a -> b with no b -> a borders a gap that runs b -> a. */
    for (size_t i = 0; i < w.m; ++i) {
        const uint32_t a = (uint32_t)(w.he[i].key >> 32), b = (uint32_t)w.he[i].key;
        if (w.walked[i] || find_half_edge(w.he, w.m, b, a))
            continue;
        if (walk_gap(&w, i, max_loop) &&
            !close_walk(&w, pos, first_new, rim, max_diag, &fill, &nf, &cap))
            goto nomem;
    }
    if (!nf)
        goto done;
    ok = malloc(nf + 1);
    grown = realloc(*tri, (n + nf) * 3 * sizeof *grown);
    if (!ok || !grown)
        goto nomem;
    *tri = grown;
    memset(&view, 0, sizeof view);
    view.nv = N, view.nt = n, view.pos = (double *)pos, view.tri = *tri;
    st = relief_om_storable(&view, fill, nf, ok, err);
    for (size_t t = 0; st == RELIEF_OK && t < nf; ++t)
        if (ok[t])
            memcpy(*tri + 3 * (n + kept++), fill + 3 * t, 3 * sizeof **tri);
    *nt = n + kept;
    goto done;
nomem:
    st = relief_fail(err, RELIEF_E_NOMEM, "cannot close the gaps of a %zu-triangle surface", n);
done:
    free(w.he), free(w.walked), free(w.loop), free(w.at), free(w.ears), free(fill), free(ok);
    return st;
}

/* The candidate triangles of the N points pos (N x 3, unit normals nrm):
 * every point's umbrella (the triangles its Voronoi cell on the tangent
 * plane proposes, cut from a 16-gon SURF_CELL_RADIUS spacings out) votes,
 * and each distinct triangle is ranked by its votes (0: three or more, 1:
 * two, 2: one) with its circumradius in pos's units. *cand_out (ncand,
 * the caller's to free) on RELIEF_OK; nothing to free otherwise. */
static relief_status surface_candidates(const double *pos, const double *nrm, size_t N,
                                        double spacing, int k, relief_cand_tri **cand_out,
                                        size_t *ncand_out, relief_error *err)
{
    relief_knn_graph g;
    vote *votes = NULL;
    relief_cand_tri *cand = NULL;
    size_t nvote = 0, ncand = 0;
    relief_status st = relief_knn_graph_build(pos, N, k, 1, &g, err);

    if (st != RELIEF_OK)
        return st;
    votes = malloc(N * ((size_t)k + SURF_CELL_SIDES) * sizeof *votes);
    if (!votes)
        goto nomem;
    for (size_t i = 0; i < N; ++i)
        nvote += umbrella(pos, nrm, &g, i, SURF_CELL_RADIUS * spacing, votes + nvote);
    relief_knn_graph_free(&g);
    qsort(votes, nvote, sizeof *votes, vote_cmp);
    cand = malloc((nvote + 1) * sizeof *cand);
    if (!cand)
        goto nomem;
    for (size_t a = 0, b; a < nvote; a = b) {
        const uint32_t *v = votes[a].v;
        for (b = a + 1; b < nvote && vote_cmp(votes + a, votes + b) == 0; ++b)
            ;
        cand[ncand].r = relief_circumradius(pos + 3 * (size_t)v[0], pos + 3 * (size_t)v[1],
                                            pos + 3 * (size_t)v[2]);
        cand[ncand].rank = b - a >= 3 ? 0 : b - a == 2 ? 1 : 2;
        memcpy(cand[ncand++].v, v, sizeof cand->v);
    }
    free(votes);
    *cand_out = cand, *ncand_out = ncand;
    return RELIEF_OK;
nomem:
    relief_knn_graph_free(&g);
    free(votes), free(cand);
    return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a surface through %zu points", N);
}

/* info's counts for the nt triangles tri (nt x 3) over N points: the edges
 * that only one triangle has, and the points that no triangle uses, so
 * that a caller sees how open the surface is. 0 when out of memory (info
 * then untouched). */
static int count_open(const uint32_t *tri, size_t nt, size_t N, relief_surface_mesh_info *info)
{
    uint64_t *e = malloc((3 * nt + 1) * sizeof *e);
    uint8_t *used = calloc(N + 1, 1);
    if (!e || !used) {
        free(e), free(used);
        return 0;
    }
    for (size_t t = 0; t < nt; ++t)
        for (int q = 0; q < 3; ++q) {
            uint32_t a = tri[3 * t + q], b = tri[3 * t + (q + 1) % 3];
            e[3 * t + q] = a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
            used[a] = 1;
        }
    qsort(e, 3 * nt, sizeof *e, relief_cmp_u64);
    for (size_t a = 0, b; a < 3 * nt; a = b) {
        for (b = a + 1; b < 3 * nt && e[b] == e[a]; ++b)
            ;
        info->boundary_edges += b - a == 1;
    }
    for (size_t i = 0; i < N; ++i)
        info->bare_points += !used[i];
    free(e), free(used);
    return 1;
}

relief_status relief_points_surface_mesh(const double *pos, const double *nrm, size_t N,
                                         double spacing, int k, uint32_t **tri, size_t *nt,
                                         relief_surface_mesh_info *info, relief_error *err)
{
    relief_cand_tri *cand = NULL;
    size_t ncand = 0;
    relief_status st;
    relief_surface_mesh_info dummy;

    *tri = NULL;
    *nt = 0;
    if (!info)
        info = &dummy;
    memset(info, 0, sizeof *info);
    if (k < 6 || k > 64 || N <= (size_t)k)
        return relief_fail(err, RELIEF_E_RANGE, "a surface through %zu points with k = %d: k "
                           "must be 6..64 and below the point count", N, k);
    if (!(spacing > 0.0))
        return relief_fail(err, RELIEF_E_RANGE, "a surface through points %g apart", spacing);
    st = surface_candidates(pos, nrm, N, spacing, k, &cand, &ncand, err);
    if (st != RELIEF_OK)
        return st;
    info->candidates = ncand;
    st = relief_points_lay_triangles(pos, N, NULL, 0, cand, ncand, 1, tri, nt, err);
    free(cand);
    if (st == RELIEF_OK && *nt)
        st = relief_points_close_gaps(pos, N, 0, NULL, 2.0 * SURF_CELL_RADIUS * spacing,
                                      SURF_MAX_LOOP, tri, nt,
                                      err);
    if (st != RELIEF_OK) {
        free(*tri);
        *tri = NULL, *nt = 0;
        return st;
    }
    info->triangles = *nt;
    if (!count_open(*tri, *nt, N, info)) {
        free(*tri);
        *tri = NULL, *nt = 0;
        return relief_fail(err, RELIEF_E_NOMEM, "cannot count the surface's edges");
    }
    return RELIEF_OK;
}
