/* depth-fill on a mesh, the holes only (mesh_patch.h). */
#include "depth/mesh_patch.h"

#include <float.h>
#include <stdint.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "depth/volume.h"
#include "base/linalg.h"
#include "base/union_find.h"
#include "mesh/mesh.h"


/* A vertex of the solid belongs to filled hole h when within REACH times
 * the hole's half width of its rim's centre (the repaired cap bulges, the
 * rim is not round) and farther than GAP voxels from the capture's surface
 * (where the solid's skin follows the capture, it is the capture's). */
#define REACH 1.25
#define GAP 1.5
/* ... and within DEPTH times the hole's width (at least 3 voxels) of the
 * plane through its rim: a cap over a hole in a curved wall bows out of
 * that plane by a tenth of its width or so, while a channel the repair
 * left unrepaired pixels for runs deep into the solid. */
#define DEPTH 0.3

static double dist2(const double *a, const double *b)
{
    double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
}

/* ------------------------------------------------ which solid vertices */

/* The unit normal of the plane through each filled hole's rim (rim labels
 * 1..n_holes over in's vertices): normal + 3 (k - 1). */
static relief_status rim_planes(const relief_mesh *in, const uint32_t *rim, uint32_t n_holes,
                                double *normal, relief_error *err)
{
    uint8_t *mask = malloc(in->nv + 1);
    if (!mask)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the rims' planes");
    double *out = calloc((size_t)n_holes * 3 + 1, sizeof *out);
    if (!out) {
        free(mask);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the rims' planes");
    }
    /* The capture's outward side at each rim: its triangles' area normals
     * (counter-clockwise seen from outside) summed over the rim's. */
    for (size_t t = 0; t < in->nt; ++t) {
        const uint32_t *f = in->tri + 3 * t;
        uint32_t k = rim[f[0]] ? rim[f[0]] : rim[f[1]] ? rim[f[1]] : rim[f[2]];
        double a[3], b[3];
        if (!k)
            continue;
        for (int c = 0; c < 3; ++c)
            a[c] = in->pos[3 * f[1] + c] - in->pos[3 * f[0] + c],
            b[c] = in->pos[3 * f[2] + c] - in->pos[3 * f[0] + c];
        out[3 * (k - 1)] += a[1] * b[2] - a[2] * b[1];
        out[3 * (k - 1) + 1] += a[2] * b[0] - a[0] * b[2];
        out[3 * (k - 1) + 2] += a[0] * b[1] - a[1] * b[0];
    }
    for (uint32_t k = 1; k <= n_holes; ++k) {
        double m[3], eval[3], evec[9], s = 0.0;
        for (size_t v = 0; v < in->nv; ++v)
            mask[v] = rim[v] == k;
        relief_pca3(in->pos, in->nv, mask, m, eval, evec);
        for (int c = 0; c < 3; ++c)
            s += evec[3 * c + 2] * out[3 * (k - 1) + c];
        for (int c = 0; c < 3; ++c)
            normal[3 * (k - 1) + c] = s < 0.0 ? -evec[3 * c + 2] : evec[3 * c + 2];
    }
    free(out);
    free(mask);
    return RELIEF_OK;
}

/* A hole's cap is a height field over its rim's plane: of the solid's
 * skin there, in each cell of a grid of `voxel` over the plane, only what
 * lies within 2 voxels of the outermost point is kept (a channel or the
 * solid's far side below it is dropped). */
static relief_status outermost(const relief_mesh *solid, const relief_hole_info *h,
                               const uint32_t *index_of, const double *normal, double voxel,
                               uint32_t *hole, relief_error *err)
{
    for (uint32_t k = 0; k < h->n_holes; ++k) {
        const relief_rim *r = h->rims + index_of[k];
        const double *n = normal + 3 * k;
        double u[3], w[3], half = REACH * 0.5 * r->across;
        int side = (int)ceil(2.0 * half / voxel) + 1;
        double *top;
        if (side > 4096)
            side = 4096;
        top = malloc((size_t)side * side * sizeof *top);
        if (!top)
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a cap's grid");
        for (size_t c = 0; c < (size_t)side * side; ++c)
            top[c] = -DBL_MAX;
        relief_perp_basis(n, u, w);
        for (int pass = 0; pass < 2; ++pass)
            for (size_t v = 0; v < solid->nv; ++v) {
                const double *p = solid->pos + 3 * v;
                double d[3] = {p[0] - r->centre[0], p[1] - r->centre[1], p[2] - r->centre[2]};
                long i, j;
                double hgt;
                if (hole[v] != k + 1)
                    continue;
                i = (long)floor((d[0] * u[0] + d[1] * u[1] + d[2] * u[2] + half) / voxel);
                j = (long)floor((d[0] * w[0] + d[1] * w[1] + d[2] * w[2] + half) / voxel);
                hgt = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
                if (i < 0 || j < 0 || i >= side || j >= side)
                    continue;
                if (pass == 0)
                    top[j * side + i] = fmax(top[j * side + i], hgt);
                else if (hgt < top[j * side + i] - 2.0 * voxel)
                    hole[v] = 0;
            }
        free(top);
    }
    return RELIEF_OK;
}

/* hole[v]: 0, or the filled hole (1..n_holes) the solid's vertex v is in. */
static relief_status mark_vertices(const relief_mesh *solid, const relief_mesh *in,
                                   const relief_hole_info *h, const uint32_t *index_of,
                                   const uint32_t *rim, double voxel, uint32_t *hole,
                                   relief_error *err)
{
    relief_triangle_index si;
    double *normal = malloc((h->n_holes + 1) * 3 * sizeof *normal);
    relief_status st = normal ? rim_planes(in, rim, h->n_holes, normal, err)
                              : relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the planes");
    if (st == RELIEF_OK)
        st = relief_triangle_index_build(&si, in->pos, in->tri, in->nt, err);
    else
        memset(&si, 0, sizeof si);
    for (size_t v = 0; st == RELIEF_OK && v < solid->nv; ++v) {
        const double *p = solid->pos + 3 * v;
        double best = DBL_MAX;
        hole[v] = 0;
        for (uint32_t k = 0; k < h->n_holes; ++k) {
            const relief_rim *r = h->rims + index_of[k];
            const double *n = normal + 3 * k;
            double d2 = dist2(p, r->centre), reach = REACH * 0.5 * r->across;
            double off = fabs((p[0] - r->centre[0]) * n[0] + (p[1] - r->centre[1]) * n[1] +
                              (p[2] - r->centre[2]) * n[2]);
            if (d2 <= reach * reach && d2 < best && off <= fmax(DEPTH * r->across, 3.0 * voxel))
                best = d2, hole[v] = k + 1;
        }
        if (hole[v] && relief_triangle_index_d2(&si, p) <= GAP * GAP * voxel * voxel)
            hole[v] = 0;
    }
    if (st == RELIEF_OK)
        st = outermost(solid, h, index_of, normal, voxel, hole, err);
    relief_triangle_index_free(&si);
    free(normal);
    return st;
}

/* -------------------------------------------------------------- loops */

/* Directed boundary edges: from[i] -> to[i] as their one triangle runs it. */
typedef struct edge_list {
    uint32_t *from, *to;
    size_t n;
} edge_list;

static int u64_cmp(const void *x, const void *y)
{
    uint64_t a = *(const uint64_t *)x, b = *(const uint64_t *)y;
    return (a > b) - (a < b);
}

/* The directed boundary edges of the triangles `tri` (nt) over nv vertices
 * for which `take` is non-zero (NULL: all). */
static relief_status boundary_edges(const uint32_t *tri, size_t nt, const uint8_t *take,
                                    edge_list *out, relief_error *err)
{
    uint64_t *key = malloc((3 * nt + 1) * sizeof *key);
    size_t m = 0;
    memset(out, 0, sizeof *out);
    if (!key)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the boundary edges");
    for (size_t t = 0; t < nt; ++t) {
        if (take && !take[t])
            continue;
        for (int c = 0; c < 3; ++c) {
            uint64_t a = tri[3 * t + c], b = tri[3 * t + (c + 1) % 3];
            key[m++] = (a < b ? a << 32 | b : b << 32 | a) << 1 | (a > b);
        }
    }
    qsort(key, m, sizeof *key, u64_cmp);
    out->from = malloc((m + 1) * sizeof *out->from);
    out->to = malloc((m + 1) * sizeof *out->to);
    if (!out->from || !out->to) {
        free(key);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the boundary edges");
    }
    for (size_t i = 0; i < m;) {
        size_t j = i;
        while (j < m && key[j] >> 1 == key[i] >> 1)
            ++j;
        if (j - i == 1) {
            uint64_t e = key[i] >> 1;
            uint32_t lo = (uint32_t)(e >> 32), hi = (uint32_t)e;
            out->from[out->n] = key[i] & 1 ? hi : lo;
            out->to[out->n++] = key[i] & 1 ? lo : hi;
        }
        i = j;
    }
    free(key);
    return RELIEF_OK;
}

/* The closed loops of the edges whose ends are both tagged `want`, walked
 * from -> to (a vertex with two outgoing edges, a pinch, ends a walk):
 * their vertices one loop after another in *loops (owned), loop i from
 * (*start)[i] to (*start)[i + 1], the longest first; *n of them. */
typedef struct loop_set {
    uint32_t *v;
    size_t *start;
    size_t n;
} loop_set;

static void loops_free(loop_set *l)
{
    free(l->v), free(l->start);
    memset(l, 0, sizeof *l);
}

/* The circuit out->v[used .. used + len) (a loop through pinches visits a
 * vertex twice) split into simple cycles, each kept when of 3 vertices or
 * more, written from `used` on; where (nv, SIZE_MAX between calls) marks
 * the stack's places, stack has room for len. Returns the new end. */
static size_t split_cycles(loop_set *out, size_t used, size_t len, size_t *where,
                           uint32_t *stack, size_t *longest, size_t *at)
{
    const uint32_t *c = stack;
    size_t top = 0, end = used;
    memcpy(stack + len, out->v + used, len * sizeof *stack); /* the circuit, after */
    c = stack + len;
    for (size_t i = 0; i <= len; ++i) {
        const uint32_t v = c[i % len];
        size_t from;
        if (i < len && where[v] == SIZE_MAX) {
            where[v] = top;
            stack[top++] = v;
            continue;
        }
        /* v closes a cycle from its place: stack[from .. top) */
        from = i < len ? where[v] : 0;
        if (top - from >= 3) {
            out->start[out->n++] = end;
            if (top - from > *longest)
                *longest = top - from, *at = out->n - 1;
            memcpy(out->v + end, stack + from, (top - from) * sizeof *stack);
            end += top - from;
        }
        for (size_t k = from + (i < len); k < top; ++k)
            where[stack[k]] = SIZE_MAX;
        if (i == len)
            for (size_t k = 0; k < top && k <= from; ++k)
                where[stack[k]] = SIZE_MAX;
        top = from + (i < len);
    }
    return end;
}

static relief_status find_loops(const edge_list *e, size_t nv, const uint32_t *tag,
                                uint32_t want, loop_set *out, relief_error *err)
{
    /* The edges out of each vertex (CSR); a walk takes any unused one, so
     * a loop through a pinch (a vertex twice on it) is walked whole. */
    size_t *first = calloc(nv + 2, sizeof *first), used = 0, longest = 0, at = 0;
    uint32_t *out_e = malloc((e->n + 1) * sizeof *out_e);
    uint8_t *done = calloc(e->n + 1, 1);
    size_t *where = malloc((nv + 1) * sizeof *where);
    uint32_t *stack = malloc((2 * e->n + 1) * sizeof *stack);
    memset(out, 0, sizeof *out);
    out->v = malloc((e->n + 1) * sizeof *out->v);
    out->start = malloc((e->n + 2) * sizeof *out->start);
    if (!first || !out_e || !done || !where || !stack || !out->v || !out->start) {
        free(first), free(out_e), free(done), free(where), free(stack), loops_free(out);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the loops");
    }
    for (size_t v = 0; v < nv; ++v)
        where[v] = SIZE_MAX;
    for (size_t i = 0; i < e->n; ++i)
        if (tag[e->from[i]] == want && tag[e->to[i]] == want)
            ++first[e->from[i] + 1];
        else
            done[i] = 1;
    for (size_t v = 0; v < nv; ++v)
        first[v + 1] += first[v];
    {
        size_t *fill = malloc((nv + 1) * sizeof *fill);
        if (!fill) {
            free(first), free(out_e), free(done), free(where), free(stack), loops_free(out);
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the loops");
        }
        memcpy(fill, first, nv * sizeof *fill);
        for (size_t i = 0; i < e->n; ++i)
            if (!done[i])
                out_e[fill[e->from[i]]++] = (uint32_t)i;
        free(fill);
    }
    for (size_t i = 0; i < e->n; ++i) {
        size_t len = 0, cur = i;
        if (done[i])
            continue;
        for (;;) {
            uint32_t v = e->to[cur];
            size_t k;
            done[cur] = 1;
            out->v[used + len++] = e->from[cur];
            if (v == e->from[i])
                break;
            for (k = first[v]; k < first[v + 1] && done[out_e[k]]; ++k)
                ;
            if (k == first[v + 1]) {
                len = 0; /* open: not a loop */
                break;
            }
            cur = out_e[k];
        }
        if (len > 0)
            used = split_cycles(out, used, len, where, stack, &longest, &at);
    }
    out->start[out->n] = used;
    if (at > 0) { /* the longest first: move its vertices to the front */
        size_t s0 = out->start[at], len = out->start[at + 1] - s0;
        uint32_t *tmp = malloc(len * sizeof *tmp);
        if (!tmp) {
            free(first), free(out_e), free(done), free(where), free(stack), loops_free(out);
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the loops");
        }
        memcpy(tmp, out->v + s0, len * sizeof *tmp);
        memmove(out->v + len, out->v, s0 * sizeof *tmp);
        memcpy(out->v, tmp, len * sizeof *tmp);
        for (size_t l = at; l > 0; --l) /* loop at moves to 0; 0..at-1 shift */
            out->start[l] = out->start[l - 1] + len;
        out->start[0] = 0;
        free(tmp);
    }
    free(first), free(out_e), free(done), free(where), free(stack);
    return RELIEF_OK;
}

/* Cap a loop of the patch (as its triangles run it) with a fan about a new
 * vertex `c` at its centroid; triangles appended to tri, their count
 * returned. */
static size_t fan(const uint32_t *l, size_t n, uint32_t c, uint32_t *tri)
{
    for (size_t i = 0; i < n; ++i) {
        tri[3 * i] = c;
        tri[3 * i + 1] = l[(i + 1) % n];
        tri[3 * i + 2] = l[i];
    }
    return n;
}

/* ------------------------------------------------------------- zipping */

/* Close the strip between the rim loop r (nr, as the capture's triangles
 * run its edges) and the patch's outer loop p (np, as the patch's run
 * them: the other way round the strip) with triangles that take each edge
 * the other way, the shorter diagonal first. Appends to tri (3 x count,
 * room for nr + np triangles). */
static size_t zip(const double *pos, const uint32_t *r, size_t nr, const uint32_t *p, size_t np,
                  uint32_t *tri)
{
    size_t i = 0, j = 0, j0 = 0, t = 0;
    double best = DBL_MAX;
    for (size_t k = 0; k < np; ++k) /* the patch vertex nearest r[0] */
        if (dist2(pos + 3 * (size_t)r[0], pos + 3 * (size_t)p[k]) < best)
            best = dist2(pos + 3 * (size_t)r[0], pos + 3 * (size_t)p[k]), j0 = k;
    /* q_j walks the patch's loop backwards from j0, with the rim. */
#define Q(j) p[(j0 + np - (j) % np) % np]
    while (i < nr || j < np) {
        const uint32_t ri = r[i % nr], rn = r[(i + 1) % nr], qj = Q(j), qn = Q(j + 1);
        int rim_step = j == np ? 1 : i == nr ? 0 :
            dist2(pos + 3 * (size_t)rn, pos + 3 * (size_t)qj) <=
            dist2(pos + 3 * (size_t)ri, pos + 3 * (size_t)qn);
        if (rim_step) {
            tri[3 * t] = rn, tri[3 * t + 1] = ri, tri[3 * t + 2] = qj;
            ++i;
        } else {
            tri[3 * t] = qj, tri[3 * t + 1] = qn, tri[3 * t + 2] = ri;
            ++j;
        }
        ++t;
    }
#undef Q
    return t;
}

/* ------------------------------------------------------------ the call */

typedef struct patch_work {
    const relief_mesh *in, *solid;
    uint32_t *hole;      /* solid->nv: its filled hole, or 0 */
    uint8_t *take;       /* solid->nt: in a hole's kept patch */
    uint32_t *comp;      /* solid->nv: union-find over the patch triangles */
    uint32_t *new_id;    /* solid->nv: its index in the output, or UINT32_MAX */
    uint32_t *rim_tag;   /* in->nv: its filled hole on a rim, or 0 */
    uint32_t *ptag;      /* solid->nv: its hole when in the kept patch, or 0 */
} patch_work;

static void work_free(patch_work *w)
{
    free(w->hole), free(w->take), free(w->comp), free(w->new_id), free(w->rim_tag),
        free(w->ptag);
}

/* Each hole's patch: the solid's triangles with three vertices in it, and
 * of those the largest connected piece. */
static void keep_largest(patch_work *w, uint32_t n_holes)
{
    const relief_mesh *s = w->solid;
    size_t *size = calloc(s->nv + 1, sizeof *size);
    uint32_t *best = calloc(n_holes + 1, sizeof *best);
    size_t *best_size = calloc(n_holes + 1, sizeof *best_size);
    if (!size || !best || !best_size) {
        free(size), free(best), free(best_size);
        memset(w->take, 0, s->nt);
        return;
    }
    for (size_t v = 0; v < s->nv; ++v)
        w->comp[v] = (uint32_t)v;
    for (size_t t = 0; t < s->nt; ++t) {
        const uint32_t *f = s->tri + 3 * t;
        w->take[t] = w->hole[f[0]] && w->hole[f[0]] == w->hole[f[1]] &&
                     w->hole[f[0]] == w->hole[f[2]];
        if (w->take[t]) {
            relief_uf_join(w->comp, f[0], f[1]);
            relief_uf_join(w->comp, f[0], f[2]);
        }
    }
    for (size_t t = 0; t < s->nt; ++t)
        if (w->take[t])
            ++size[relief_uf_find(w->comp, s->tri[3 * t])];
    for (size_t v = 0; v < s->nv; ++v)
        if (size[v] > best_size[w->hole[v]] && w->hole[v])
            best_size[w->hole[v]] = size[v], best[w->hole[v]] = (uint32_t)v;
    for (size_t t = 0; t < s->nt; ++t)
        if (w->take[t]) {
            uint32_t root = relief_uf_find(w->comp, s->tri[3 * t]);
            w->take[t] = root == best[w->hole[s->tri[3 * t]]];
        }
    free(size), free(best), free(best_size);
}

/* Where a patch's boundary pinches (a vertex with two boundary edges out,
 * two loops touching there), a fan or a zip would make the vertex
 * non-manifold: the patch's triangles round such vertices are dropped,
 * until none is left (at most 16 rounds; the loops grow by a ring). */
static relief_status unpinch(patch_work *w, relief_error *err)
{
    const relief_mesh *s = w->solid;
    uint8_t *pinch = malloc(s->nv + 1);
    if (!pinch)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the patches' pinches");
    for (int round = 0; round < 16; ++round) {
        edge_list pe;
        size_t n = 0;
        relief_status st = boundary_edges(s->tri, s->nt, w->take, &pe, err);
        if (st != RELIEF_OK) {
            free(pinch);
            return st;
        }
        memset(pinch, 0, s->nv);
        for (size_t i = 0; i < pe.n; ++i) /* 1: one edge out; 2: more */
            pinch[pe.from[i]] = pinch[pe.from[i]] ? 2 : 1;
        free(pe.from), free(pe.to);
        for (size_t t = 0; t < s->nt; ++t) {
            const uint32_t *f = s->tri + 3 * t;
            if (w->take[t] && (pinch[f[0]] == 2 || pinch[f[1]] == 2 || pinch[f[2]] == 2))
                w->take[t] = 0, ++n;
        }
        if (n == 0)
            break;
    }
    free(pinch);
    return RELIEF_OK;
}

/* Hole k (1..n_holes): the patch's outer loop zipped to the rim's, and
 * each loop the patch leaves inside (where a channel was cut off) capped
 * by a fan about its centroid, a new vertex. */
static relief_status close_hole(patch_work *w, const edge_list *re, const edge_list *pe,
                                uint32_t k, double *pos, size_t *nv, uint32_t *tri, size_t *nt,
                                relief_mesh_patch_report *rep, relief_error *err)
{
    loop_set rl, pl;
    relief_status st = find_loops(re, w->in->nv, w->rim_tag, k, &rl, err);
    if (st != RELIEF_OK)
        return st;
    st = find_loops(pe, w->solid->nv, w->ptag, k, &pl, err);
    if (st != RELIEF_OK) {
        loops_free(&rl);
        return st;
    }
    if (rl.n == 0 || pl.n == 0) {
        ++rep->holes_unpatched;
        loops_free(&rl), loops_free(&pl);
        return RELIEF_OK;
    }
    for (size_t i = 0; i < pl.start[pl.n]; ++i)
        pl.v[i] = w->new_id[pl.v[i]];
    *nt += zip(pos, rl.v, rl.start[1], pl.v, pl.start[1], tri + 3 * *nt);
    for (size_t l = 1; l < pl.n; ++l) {
        const uint32_t *v = pl.v + pl.start[l];
        size_t n = pl.start[l + 1] - pl.start[l], shared = 0;
        double *c = pos + 3 * *nv;
        /* A loop that touches another one at a vertex stays open: a fan
         * there would make that vertex non-manifold. */
        for (size_t i = 0; i < n; ++i)
            for (size_t q = 0; q < pl.start[pl.n] && !shared; ++q)
                shared = pl.v[q] == v[i] && (q < pl.start[l] || q >= pl.start[l + 1]);
        if (shared) {
            ++rep->inner_loops_open;
            continue;
        }
        c[0] = c[1] = c[2] = 0.0;
        for (size_t i = 0; i < n; ++i)
            for (int d = 0; d < 3; ++d)
                c[d] += pos[3 * (size_t)v[i] + d] / (double)n;
        *nt += fan(v, n, (uint32_t)*nv, tri + 3 * *nt);
        ++*nv;
        ++rep->inner_loops_capped;
    }
    ++rep->holes_patched;
    loops_free(&rl), loops_free(&pl);
    return RELIEF_OK;
}

/* A hole whose rim is no closed loop (filled in part: an arc of a border,
 * mesh/holes.h) cannot be zipped: its patch is not taken, so that no
 * piece floats apart from the capture; close_hole counts it unpatched. */
static relief_status drop_open_rims(patch_work *w, uint32_t n_holes, relief_error *err)
{
    const relief_mesh *s = w->solid;
    edge_list re = {0};
    loop_set rl;
    relief_status st = boundary_edges(w->in->tri, w->in->nt, NULL, &re, err);
    for (uint32_t k = 1; st == RELIEF_OK && k <= n_holes; ++k) {
        st = find_loops(&re, w->in->nv, w->rim_tag, k, &rl, err);
        if (st != RELIEF_OK)
            break;
        for (size_t t = 0; rl.n == 0 && t < s->nt; ++t)
            if (w->take[t] && w->hole[s->tri[3 * t]] == k)
                w->take[t] = 0;
        loops_free(&rl);
    }
    free(re.from), free(re.to);
    return st;
}

/* The output: the capture, the patches' vertices and triangles, and the
 * strips; counts in rep. */
static relief_status assemble(patch_work *w, const relief_hole_info *h, relief_mesh **out,
                              relief_mesh_patch_report *rep, relief_error *err)
{
    const relief_mesh *in = w->in, *s = w->solid;
    edge_list re = {0}, pe = {0};
    size_t nv = in->nv, nt = in->nt, cap;
    uint32_t *tri = NULL;
    relief_mesh *m = NULL;
    relief_status st = boundary_edges(in->tri, in->nt, NULL, &re, err);
    if (st == RELIEF_OK)
        st = boundary_edges(s->tri, s->nt, w->take, &pe, err);
    if (st != RELIEF_OK)
        goto done;
    for (size_t v = 0; v < s->nv; ++v)
        w->new_id[v] = UINT32_MAX;
    for (size_t t = 0; t < s->nt; ++t)
        for (int c = 0; w->take[t] && c < 3; ++c) {
            uint32_t v = s->tri[3 * t + c];
            if (w->new_id[v] == UINT32_MAX) {
                w->new_id[v] = (uint32_t)nv++;
                w->ptag[v] = w->hole[v];
            }
        }
    cap = nt + 4 * pe.n + 3 * re.n + 1;
    for (size_t t = 0; t < s->nt; ++t)
        cap += w->take[t];
    tri = malloc(cap * 3 * sizeof *tri);
    if (!tri) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the patches");
        goto done;
    }
    memcpy(tri, in->tri, in->nt * 3 * sizeof *tri);
    for (size_t t = 0; t < s->nt; ++t)
        if (w->take[t]) {
            for (int c = 0; c < 3; ++c)
                tri[3 * nt + c] = w->new_id[s->tri[3 * t + c]];
            ++nt, ++rep->patch_triangles;
        }
    {
        /* Positions of every output vertex, for the zipping, with room for
         * a centre per loop the patches leave inside (pe.n / 3 at most). */
        double *pos = malloc((nv + pe.n / 3 + 1) * 3 * sizeof *pos);
        if (!pos) {
            st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the patches");
            goto done;
        }
        memcpy(pos, in->pos, in->nv * 3 * sizeof *pos);
        for (size_t v = 0; v < s->nv; ++v)
            if (w->new_id[v] != UINT32_MAX)
                memcpy(pos + 3 * (size_t)w->new_id[v], s->pos + 3 * v, 3 * sizeof *pos);
        for (uint32_t k = 1; st == RELIEF_OK && k <= h->n_holes; ++k)
            st = close_hole(w, &re, &pe, k, pos, &nv, tri, &nt, rep, err);
        if (st == RELIEF_OK)
            st = relief_mesh_create(nv, nt, RELIEF_MESH_LABELS | (in->col ? RELIEF_MESH_COLOURS : 0u),
                                    &m, err);
        if (st == RELIEF_OK) {
            memcpy(m->pos, pos, nv * 3 * sizeof *pos);
            memcpy(m->tri, tri, nt * 3 * sizeof *tri);
            for (size_t v = in->nv; v < nv; ++v)
                m->label[v] = RELIEF_LABEL_COMPLETED;
            if (in->col) {
                memcpy(m->col, in->col, in->nv * 3 * sizeof *m->col);
                for (size_t v = in->nv; v < nv; ++v)
                    m->col[3 * v] = m->col[3 * v + 1] = m->col[3 * v + 2] = 0.5f;
            }
        }
        free(pos);
    }
    rep->vertices_added = nv - in->nv;
    rep->strip_triangles = nt - in->nt - rep->patch_triangles;
done:
    free(re.from), free(re.to), free(pe.from), free(pe.to), free(tri);
    if (st == RELIEF_OK)
        *out = m;
    else
        relief_mesh_destroy(m);
    return st;
}

relief_status relief_mesh_patch_holes(const relief_mesh *in, const relief_mesh *solid,
                                      double voxel, const relief_hole_info *h,
                                      const uint32_t *rim, relief_mesh **out,
                                      relief_mesh_patch_report *rep, relief_error *err)
{
    patch_work w;
    uint32_t *index_of = malloc((h->n_holes + 1) * sizeof *index_of), k = 0;
    relief_status st;
    memset(&w, 0, sizeof w);
    memset(rep, 0, sizeof *rep);
    w.in = in, w.solid = solid;
    w.hole = malloc((solid->nv + 1) * sizeof *w.hole);
    w.take = malloc(solid->nt + 1);
    w.comp = malloc((solid->nv + 1) * sizeof *w.comp);
    w.new_id = malloc((solid->nv + 1) * sizeof *w.new_id);
    w.ptag = calloc(solid->nv + 1, sizeof *w.ptag);
    w.rim_tag = malloc((in->nv + 1) * sizeof *w.rim_tag);
    if (!index_of || !w.hole || !w.take || !w.comp || !w.new_id || !w.ptag || !w.rim_tag) {
        free(index_of);
        work_free(&w);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the hole patches");
    }
    for (uint32_t i = 0; i < h->n_rims; ++i)
        if (h->rims[i].fate == RELIEF_RIM_FILLED)
            index_of[k++] = i;
    memcpy(w.rim_tag, rim, in->nv * sizeof *rim);
    st = mark_vertices(solid, in, h, index_of, rim, voxel, w.hole, err);
    if (st == RELIEF_OK) {
        keep_largest(&w, h->n_holes);
        st = unpinch(&w, err);
        if (st == RELIEF_OK)
            st = drop_open_rims(&w, h->n_holes, err);
        if (st == RELIEF_OK)
            st = assemble(&w, h, out, rep, err);
        /* A strip zipped across a pinch of the rim, or a fan against a
         * strip, can still leave an edge with three triangles or a vertex
         * with two fans: mended as a read mesh is, and counted. */
        if (st == RELIEF_OK) {
            relief_repair_info ri;
            st = relief_mesh_repair(*out, &ri, err);
            rep->mended_triangles = ri.nonmanifold_edge_triangles + ri.orientation_triangles +
                                    ri.degenerate_triangles + ri.duplicate_triangles +
                                    ri.small_component_triangles + ri.unstorable_triangles;
            rep->mended_vertices = ri.nonmanifold_vertices;
            if (st != RELIEF_OK) {
                relief_mesh_destroy(*out);
                *out = NULL;
            }
        }
    }
    free(index_of);
    work_free(&w);
    return st;
}
