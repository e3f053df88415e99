/* Whether a surface is closed where it should be (mesh_check.h): the edge
 * census and the self-intersections. */
#include "mesh/mesh_check.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/predicates.h"
#include "base/union_find.h"
#include "base/vec3.h"

static int u64_cmp(const void *x, const void *y)
{
    uint64_t a = *(const uint64_t *)x, b = *(const uint64_t *)y;
    return (a > b) - (a < b);
}

uint64_t *relief_edge_keys(const uint32_t *tri, size_t nt)
{
    uint64_t *e = malloc(3 * nt * sizeof *e + 1);
    if (!e)
        return NULL;
    for (size_t t = 0; t < nt; ++t)
        for (int c = 0; c < 3; ++c) {
            uint64_t a = tri[3 * t + c], b = tri[3 * t + (c + 1) % 3];
            e[3 * t + c] = a < b ? (a << 32 | b) : (b << 32 | a);
        }
    qsort(e, 3 * nt, sizeof *e, u64_cmp);
    return e;
}

/* Every index below nv, or RELIEF_E_MESH naming the first that is not. */
static relief_status check_indices(const uint32_t *tri, size_t nt, size_t nv, relief_error *err)
{
    for (size_t k = 0; k < 3 * nt; ++k)
        if (tri[k] >= nv)
            return relief_fail(err, RELIEF_E_MESH, "triangle %zu has vertex %u, past the %zu "
                               "vertices", k / 3, tri[k], nv);
    return RELIEF_OK;
}

/* The loops of the boundary whose vertices (mark bit 1) parent joins;
 * bit 2 of a loop's root marks one that meets the focus. */
static void count_loops(uint32_t *parent, uint8_t *mark, size_t nv, const uint8_t *vfocus,
                        relief_edge_census_result *out)
{
    for (size_t v = 0; v < nv; ++v)
        if (mark[v] && (!vfocus || vfocus[v]))
            mark[relief_uf_find(parent, (uint32_t)v)] |= 2;
    for (size_t v = 0; v < nv; ++v)
        if (mark[v] && parent[v] == v) {
            ++out->boundary_loops;
            out->focus_boundary_loops += (mark[v] & 2) != 0;
        }
}

relief_status relief_edge_census(const uint32_t *tri, size_t nt, size_t nv,
                                 const uint8_t *vfocus, relief_edge_census_result *out,
                                 relief_error *err)
{
    relief_edge_census_result r;
    relief_status st = check_indices(tri, nt, nv, err);
    uint64_t *e = st == RELIEF_OK ? relief_edge_keys(tri, nt) : NULL;
    uint32_t *parent = malloc(nv * sizeof *parent + 1);
    uint8_t *mark = calloc(nv + 1, 1);
    if (st == RELIEF_OK && (!e || !parent || !mark))
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the edges of %zu triangles", nt);
    memset(&r, 0, sizeof r);
    for (size_t v = 0; st == RELIEF_OK && v < nv; ++v)
        parent[v] = (uint32_t)v;
    for (size_t i = 0, j; st == RELIEF_OK && i < 3 * nt; i = j) {
        const uint32_t a = (uint32_t)(e[i] >> 32), b = (uint32_t)e[i];
        const int near = !vfocus || vfocus[a] || vfocus[b];
        for (j = i + 1; j < 3 * nt && e[j] == e[i]; ++j)
            ;
        if (j - i == 1) {
            ++r.boundary_edges;
            r.focus_boundary_edges += near;
            mark[a] = mark[b] = 1;
            relief_uf_join(parent, a, b);
        } else if (j - i > 2) {
            ++r.nonmanifold_edges;
            r.focus_nonmanifold_edges += near;
        }
    }
    if (st == RELIEF_OK) {
        count_loops(parent, mark, nv, vfocus, &r);
        *out = r;
    }
    free(e), free(parent), free(mark);
    return st;
}

/* ---- the pair tests ---- */

/* A triangle as the tests see it: its corners' indices and positions, and
 * the coordinate plane (i, j) it projects on with area, the most face-on. */
typedef struct corner_tri {
    uint32_t id[3];
    const double *p[3];
    int i, j;
} corner_tri;

/* Three orientations that disagree: one positive and one negative. */
static int mixed(int a, int b, int c)
{
    return (a > 0 || b > 0 || c > 0) && (a < 0 || b < 0 || c < 0);
}

/* The coordinate dropped to project abc face-on: of those planes where
 * abc keeps an area (exactly), the one where its normal is largest. -1 when
 * abc has no area (its corners are collinear). */
static int face_on(const double *a, const double *b, const double *c)
{
    double u[3], w[3], n[3];
    int best = -1;
    sub3(b, a, u), sub3(c, a, w), cross3(u, w, n);
    for (int k = 0; k < 3; ++k)
        if (relief_orient2d(a, b, c, (k + 1) % 3, (k + 2) % 3) != 0 &&
            (best < 0 || fabs(n[k]) > fabs(n[best])))
            best = k;
    return best;
}

/* x in the closed triangle t, x in t's plane. */
static int in_tri2(const double *x, const corner_tri *t)
{
    return !mixed(relief_orient2d(t->p[0], t->p[1], x, t->i, t->j),
                  relief_orient2d(t->p[1], t->p[2], x, t->i, t->j),
                  relief_orient2d(t->p[2], t->p[0], x, t->i, t->j));
}

/* -1, 0, 1 as x comes before, with or after y along (i, j), which along
 * one line is the order of its points. */
static int lex(const double *x, const double *y, int i, int j)
{
    if (x[i] != y[i])
        return x[i] < y[i] ? -1 : 1;
    return (x[j] > y[j]) - (x[j] < y[j]);
}

/* The closed segments pq and ab, in one plane, meet (projected on i, j). */
static int seg_seg2(const double *p, const double *q, const double *a, const double *b, int i,
                    int j)
{
    const int o1 = relief_orient2d(p, q, a, i, j), o2 = relief_orient2d(p, q, b, i, j);
    const double *plo, *phi, *alo, *ahi;
    if (o1 * o2 > 0 || relief_orient2d(a, b, p, i, j) * relief_orient2d(a, b, q, i, j) > 0)
        return 0;
    if (o1 != 0 || o2 != 0)
        return 1;
    plo = lex(p, q, i, j) < 0 ? p : q, phi = plo == p ? q : p; /* collinear: the spans */
    alo = lex(a, b, i, j) < 0 ? a : b, ahi = alo == a ? b : a;
    return lex(phi, alo, i, j) >= 0 && lex(ahi, plo, i, j) >= 0;
}

/* The sides of t's plane that p and q lie on, as relief_orient3d gives
 * them. */
static int side(const corner_tri *t, const double *p)
{
    return relief_orient3d(t->p[0], t->p[1], t->p[2], p);
}

/* The closed segment pq, its ends on sides sp and sq of t's plane, meets
 * the closed triangle t. Across the plane, where the line pq passes t's
 * edges on no two sides; in it, where an end lies in t or the segment
 * meets an edge. */
static int seg_tri(const double *p, const double *q, int sp, int sq, const corner_tri *t)
{
    if (sp * sq > 0)
        return 0;
    if (sp == 0 && sq == 0)
        return in_tri2(p, t) || in_tri2(q, t) || seg_seg2(p, q, t->p[0], t->p[1], t->i, t->j) ||
               seg_seg2(p, q, t->p[1], t->p[2], t->i, t->j) ||
               seg_seg2(p, q, t->p[2], t->p[0], t->i, t->j);
    return !mixed(relief_orient3d(p, q, t->p[0], t->p[1]), relief_orient3d(p, q, t->p[1], t->p[2]),
                  relief_orient3d(p, q, t->p[2], t->p[0]));
}

/* Two closed triangles meet exactly when an edge of one meets the other:
 * their meeting set's extreme points lie on their boundaries. First
 * (Moeller 1997's), the pairs with one's corners all strictly on one side
 * of the other's plane, most of them, are apart. */
static int tris_meet(const corner_tri *s, const corner_tri *t)
{
    int os[3], ot[3];
    for (int k = 0; k < 3; ++k)
        os[k] = side(t, s->p[k]);
    if ((os[0] > 0 && os[1] > 0 && os[2] > 0) || (os[0] < 0 && os[1] < 0 && os[2] < 0))
        return 0;
    for (int k = 0; k < 3; ++k)
        ot[k] = side(s, t->p[k]);
    if ((ot[0] > 0 && ot[1] > 0 && ot[2] > 0) || (ot[0] < 0 && ot[1] < 0 && ot[2] < 0))
        return 0;
    for (int k = 0; k < 3; ++k) {
        const int l = (k + 1) % 3;
        if (seg_tri(s->p[k], s->p[l], os[k], os[l], t) ||
            seg_tri(t->p[k], t->p[l], ot[k], ot[l], s))
            return 1;
    }
    return 0;
}

static int same_corner(const corner_tri *s, int a, const corner_tri *t, int b)
{
    return s->id[a] == t->id[b] ||
           (s->p[a][0] == t->p[b][0] && s->p[a][1] == t->p[b][1] && s->p[a][2] == t->p[b][2]);
}

/* s and t meet elsewhere than where they are joined (mesh_check.h). One
 * corner c shared: their meeting set is convex and holds c, so it holds
 * more exactly when it reaches the edge opposite c in one of them. An edge
 * shared: only a coplanar fold, both third corners on one side of it. */
static int pair_crosses(const corner_tri *s, const corner_tri *t)
{
    int n = 0, sa[3], ta[3];
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            if (same_corner(s, a, t, b)) {
                sa[n] = a, ta[n++] = b;
                break;
            }
    if (n == 0)
        return tris_meet(s, t);
    if (n == 1) {
        const double *s1 = s->p[(sa[0] + 1) % 3], *s2 = s->p[(sa[0] + 2) % 3];
        const double *t1 = t->p[(ta[0] + 1) % 3], *t2 = t->p[(ta[0] + 2) % 3];
        return seg_tri(s1, s2, side(t, s1), side(t, s2), t) ||
               seg_tri(t1, t2, side(s, t1), side(s, t2), s);
    }
    if (n == 2) {
        const double *e0 = s->p[sa[0]], *e1 = s->p[sa[1]];
        const double *cs = s->p[3 - sa[0] - sa[1]], *ct = t->p[3 - ta[0] - ta[1]];
        return relief_orient3d(e0, e1, cs, ct) == 0 &&
               relief_orient2d(e0, e1, cs, s->i, s->j) * relief_orient2d(e0, e1, ct, s->i, s->j) >
                   0;
    }
    return 1;
}

/* ---- the grid ---- */

/* Cells of side h from lo, a cell's coordinates packed CELL_BITS each;
 * hashed into nb buckets (a power of two) whose entries (a triangle and a
 * cell its box overlaps) lie at start[b] .. start[b + 1]. */
#define CELL_BITS 21
#define CELL_MAX ((1u << CELL_BITS) - 1)

typedef struct tri_grid {
    double lo[3], h;
    size_t nb;
    size_t *start;  /* nb + 1 */
    uint64_t *cell; /* start[nb] entries */
    uint32_t *tri;
} tri_grid;

/* A coordinate's cell along axis k, clamped into the packed range (cells
 * merged at the far end only cost tests; NaN, never met on a triangle
 * with an area, to 0). */
static uint64_t cell_of(const tri_grid *g, double x, int k)
{
    const double c = floor((x - g->lo[k]) / g->h);
    return !(c > 0.0) ? 0 : c >= CELL_MAX ? CELL_MAX : (uint64_t)c;
}

static uint64_t cell_key(const tri_grid *g, const double *x)
{
    return cell_of(g, x[0], 0) << 2 * CELL_BITS | cell_of(g, x[1], 1) << CELL_BITS |
           cell_of(g, x[2], 2);
}

static size_t bucket_of(const tri_grid *g, uint64_t key)
{
    key ^= key >> 30, key *= 0xbf58476d1ce4e5b9u; /* splitmix64's finaliser */
    key ^= key >> 27, key *= 0x94d049bb133111ebu;
    return (size_t)(key ^ key >> 31) & (g->nb - 1);
}

/* Each triangle's box (box: nt x 6, low corner then high) and the
 * coordinate face_on drops (axis, -1 with no area); the count with one. */
static size_t tri_shapes(const double *pos, const uint32_t *tri, size_t nt, double *box,
                         int8_t *axis)
{
    size_t valid = 0;
    for (size_t t = 0; t < nt; ++t) {
        const double *p[3] = {pos + 3 * (size_t)tri[3 * t], pos + 3 * (size_t)tri[3 * t + 1],
                              pos + 3 * (size_t)tri[3 * t + 2]};
        for (int k = 0; k < 3; ++k) {
            box[6 * t + k] = fmin(p[0][k], fmin(p[1][k], p[2][k]));
            box[6 * t + 3 + k] = fmax(p[0][k], fmax(p[1][k], p[2][k]));
        }
        axis[t] = (int8_t)face_on(p[0], p[1], p[2]);
        valid += axis[t] >= 0;
    }
    return valid;
}

/* The entries the boxes make with cells of side h, counted in double (a
 * stray huge triangle could overflow a size_t). */
static double grid_entries(const tri_grid *g, const double *box, const int8_t *axis, size_t nt)
{
    double n = 0.0;
    for (size_t t = 0; t < nt; ++t) {
        double c = 1.0;
        for (int k = 0; axis[t] >= 0 && k < 3; ++k)
            c *= (double)(cell_of(g, box[6 * t + 3 + k], k) - cell_of(g, box[6 * t + k], k) + 1);
        n += axis[t] >= 0 ? c : 0.0;
    }
    return n;
}

/* The origin and the cell side: the triangles' mean box size, doubled
 * while the boxes would make over 16 entries a triangle (a few huge ones
 * beside many small ones), and never under 1 / CELL_MAX of the extent. */
static size_t grid_size(tri_grid *g, const double *box, const int8_t *axis, size_t nt,
                        size_t valid)
{
    double hi[3] = {-INFINITY, -INFINITY, -INFINITY}, sum = 0.0, n;
    g->lo[0] = g->lo[1] = g->lo[2] = INFINITY;
    for (size_t t = 0; t < nt; ++t) {
        double ext = 0.0;
        for (int k = 0; axis[t] >= 0 && k < 3; ++k) {
            g->lo[k] = fmin(g->lo[k], box[6 * t + k]);
            hi[k] = fmax(hi[k], box[6 * t + 3 + k]);
            ext = fmax(ext, box[6 * t + 3 + k] - box[6 * t + k]);
        }
        sum += ext;
    }
    g->h = fmax(sum / (double)valid,
                fmax(hi[0] - g->lo[0], fmax(hi[1] - g->lo[1], hi[2] - g->lo[2])) / CELL_MAX);
    while ((n = grid_entries(g, box, axis, nt)) > 16.0 * (double)valid)
        g->h *= 2.0;
    return (size_t)n;
}

/* Each cell of t's box into its bucket: counted (fill 0), or stored at
 * the bucket's end, which moves back one. */
static void place(tri_grid *g, const double *box, uint32_t t, int fill)
{
    uint64_t lo[3], hi[3];
    for (int k = 0; k < 3; ++k)
        lo[k] = cell_of(g, box[k], k), hi[k] = cell_of(g, box[3 + k], k);
    for (uint64_t x = lo[0]; x <= hi[0]; ++x)
        for (uint64_t y = lo[1]; y <= hi[1]; ++y)
            for (uint64_t z = lo[2]; z <= hi[2]; ++z) {
                const uint64_t key = x << 2 * CELL_BITS | y << CELL_BITS | z;
                const size_t b = bucket_of(g, key);
                if (!fill) {
                    ++g->start[b];
                } else {
                    const size_t at = --g->start[b];
                    g->cell[at] = key, g->tri[at] = t;
                }
            }
}

/* The grid of the triangles with an area, by a counting sort on buckets. */
static relief_status grid_build(tri_grid *g, const double *box, const int8_t *axis, size_t nt,
                                size_t valid, relief_error *err)
{
    const size_t n = valid ? grid_size(g, box, axis, nt, valid) : 0;
    for (g->nb = 1; g->nb < n; g->nb *= 2)
        ;
    g->start = calloc(g->nb + 1, sizeof *g->start);
    g->cell = malloc(n * sizeof *g->cell + 1);
    g->tri = malloc(n * sizeof *g->tri + 1);
    if (!g->start || !g->cell || !g->tri)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a grid of %zu entries over "
                           "%zu triangles", n, nt);
    for (size_t t = 0; t < nt; ++t)
        if (axis[t] >= 0)
            place(g, box + 6 * t, (uint32_t)t, 0);
    for (size_t b = 1; b <= g->nb; ++b) /* each bucket's end */
        g->start[b] += g->start[b - 1];
    for (size_t t = 0; t < nt; ++t)
        if (axis[t] >= 0)
            place(g, box + 6 * t, (uint32_t)t, 1);
    return RELIEF_OK;
}

static void grid_free(tri_grid *g)
{
    free(g->start), free(g->cell), free(g->tri);
}

/* ---- the search ---- */

typedef struct pair_scan {
    const double *pos;
    const uint32_t *tri;
    const double *box;
    const int8_t *axis;
    const uint8_t *focus;
    uint8_t *hit;
} pair_scan;

static corner_tri corners(const pair_scan *c, uint32_t t)
{
    corner_tri r;
    for (int k = 0; k < 3; ++k) {
        r.id[k] = c->tri[3 * (size_t)t + k];
        r.p[k] = c->pos + 3 * (size_t)r.id[k];
    }
    r.i = (c->axis[t] + 1) % 3, r.j = (c->axis[t] + 2) % 3;
    return r;
}

/* Triangles s and t, both in the cell `key`: tested there only when that
 * is the cell of their boxes' overlap's low corner (so once a pair), and
 * only while one of them is to be reported and is not yet. */
static void consider(const pair_scan *c, const tri_grid *g, uint32_t s, uint32_t t, uint64_t key)
{
    const double *bs = c->box + 6 * (size_t)s, *bt = c->box + 6 * (size_t)t;
    const int want_s = (!c->focus || c->focus[s]) && !c->hit[s];
    const int want_t = (!c->focus || c->focus[t]) && !c->hit[t];
    double low[3];
    corner_tri a, b;
    if (!want_s && !want_t)
        return;
    for (int k = 0; k < 3; ++k) {
        if (bs[k] > bt[3 + k] || bt[k] > bs[3 + k])
            return;
        low[k] = fmax(bs[k], bt[k]);
    }
    if (cell_key(g, low) != key)
        return;
    a = corners(c, s), b = corners(c, t);
    if (pair_crosses(&a, &b)) {
        c->hit[s] |= want_s;
        c->hit[t] |= want_t;
    }
}

static void scan_bucket(const pair_scan *c, const tri_grid *g, size_t b)
{
    for (size_t x = g->start[b]; x < g->start[b + 1]; ++x)
        for (size_t y = x + 1; y < g->start[b + 1]; ++y)
            if (g->cell[x] == g->cell[y])
                consider(c, g, g->tri[x], g->tri[y], g->cell[x]);
}

relief_status relief_self_intersections(const double *pos, size_t nv, const uint32_t *tri,
                                        size_t nt, const uint8_t *focus, uint8_t *hit,
                                        size_t *count, relief_error *err)
{
    tri_grid g = {{0, 0, 0}, 0, 0, NULL, NULL, NULL};
    double *box = malloc(6 * nt * sizeof *box + 1);
    int8_t *axis = malloc(nt + 1);
    uint8_t *own = hit ? NULL : malloc(nt + 1);
    pair_scan c = {pos, tri, box, axis, focus, hit ? hit : own};
    relief_status st = check_indices(tri, nt, nv, err);
    size_t n = 0;
    if (st == RELIEF_OK && (!box || !axis || !c.hit))
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the boxes of %zu triangles", nt);
    if (st == RELIEF_OK)
        st = grid_build(&g, box, axis, nt, tri_shapes(pos, tri, nt, box, axis), err);
    if (st == RELIEF_OK)
        memset(c.hit, 0, nt);
    for (size_t b = 0; st == RELIEF_OK && b < g.nb; ++b)
        scan_bucket(&c, &g, b);
    for (size_t t = 0; st == RELIEF_OK && t < nt; ++t)
        n += c.hit[t];
    if (st == RELIEF_OK)
        *count = n;
    grid_free(&g);
    free(box), free(axis), free(own);
    return st;
}

relief_status relief_closure_check(const double *pos, size_t nv, const uint32_t *tri, size_t nt,
                                   const uint8_t *completed, relief_closure *c,
                                   relief_error *err)
{
    uint8_t *near = malloc(nv + 1), *touched = calloc(nt + 1, 1);
    relief_edge_census_result ec;
    relief_status st = check_indices(tri, nt, nv, err);
    size_t hits = 0;
    if (st == RELIEF_OK && (!near || !touched))
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the closure of %zu triangles", nt);
    for (size_t v = 0; st == RELIEF_OK && v < nv; ++v)
        near[v] = completed[v] != 0;
    for (size_t t = 0; st == RELIEF_OK && t < nt; ++t) { /* a completed corner: the others near */
        const uint32_t *f = tri + 3 * t;
        touched[t] = completed[f[0]] || completed[f[1]] || completed[f[2]];
        for (int k = 0; touched[t] && k < 3; ++k)
            near[f[k]] = 1;
    }
    if (st == RELIEF_OK)
        st = relief_edge_census(tri, nt, nv, near, &ec, err);
    if (st == RELIEF_OK)
        st = relief_self_intersections(pos, nv, tri, nt, touched, NULL, &hits, err);
    if (st == RELIEF_OK) {
        c->open_loops = ec.focus_boundary_loops;
        c->open_edges = ec.focus_boundary_edges;
        c->nonmanifold_edges = ec.focus_nonmanifold_edges;
        c->self_intersections = hits;
    }
    free(near), free(touched);
    return st;
}
