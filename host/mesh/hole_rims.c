/* relief_fill_rims (mesh/hole_fill.h): the mesh's boundary loops walked
 * into the patches' polygons, each closed by the three steps, and the
 * patches gathered in the mesh's indices. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/sort.h"
#include "base/vec3.h"
#include "mesh/hole_fill.h"
#include "mesh/hole_fill_internal.h"

/* The boundary as successors: for the boundary edge a -> b of a triangle
 * (a, b, c) with no b -> a, succ[a] = b and opp[a] = c; pinch[a] = 1 when
 * a starts two. */
typedef struct rim_walk {
    uint32_t *succ, *opp;
    uint8_t *pinch;
} rim_walk;

static relief_status boundary_successors(const uint32_t *tri, size_t nt, size_t nv,
                                         rim_walk *w, relief_error *err)
{
    relief_keyed *e = malloc((3 * nt + 1) * sizeof *e);
    w->succ = malloc((nv + 1) * sizeof *w->succ);
    w->opp = malloc((nv + 1) * sizeof *w->opp);
    w->pinch = calloc(nv + 1, 1);
    if (!e || !w->succ || !w->opp || !w->pinch)
        goto nomem;
    for (size_t t = 0; t < nt; ++t)
        for (int i = 0; i < 3; ++i) {
            uint64_t a = tri[3 * t + i], b = tri[3 * t + (i + 1) % 3];
            e[3 * t + i].key = a << 32 | b;
            e[3 * t + i].index = (uint32_t)(3 * t + i);
        }
    if (relief_sort_keyed(e, 3 * nt) != 0)
        goto nomem;
    for (size_t v = 0; v < nv; ++v)
        w->succ[v] = UINT32_MAX;
    for (size_t i = 0; i < 3 * nt; ++i) {
        uint64_t k = e[i].key, twin = (k & 0xffffffffu) << 32 | k >> 32;
        size_t lo = 0, hi = 3 * nt;
        uint32_t a = (uint32_t)(k >> 32), t = e[i].index / 3, c = e[i].index % 3;
        while (lo < hi) { /* is the twin there? */
            size_t mid = lo + (hi - lo) / 2;
            if (e[mid].key < twin)
                lo = mid + 1;
            else
                hi = mid;
        }
        if (lo < 3 * nt && e[lo].key == twin)
            continue;
        if (w->succ[a] != UINT32_MAX)
            w->pinch[a] = 1;
        w->succ[a] = (uint32_t)(k & 0xffffffffu);
        w->opp[a] = tri[3 * t + (c + 2) % 3];
    }
    free(e);
    return RELIEF_OK;
nomem:
    free(e);
    return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the boundary of %zu triangles", nt);
}

/* The gathered output and what every polygon needs. */
typedef struct fill_job {
    const double *pos;
    size_t nv;
    const uint32_t *tri;
    size_t nt;
    const uint32_t *rim;
    const relief_hole_fill_options *o;
    relief_adjacency adj;
    rim_walk w;
    uint32_t *local;  /* nv: a vertex's index in the polygon being closed, or UINT32_MAX */
    relief_hole_patches *out;
    size_t cap_v, cap_t;
} fill_job;

static int out_reserve(fill_job *j, size_t more_v, size_t more_t)
{
    relief_hole_patches *o = j->out;
    return hole_grow((void **)&o->pos, 3 * sizeof *o->pos, (void **)&o->hole, sizeof *o->hole,
                     &j->cap_v, o->nv_new + more_v) &&
           hole_grow((void **)&o->tri, 3 * sizeof *o->tri, (void **)&o->tri_hole,
                     sizeof *o->tri_hole, &j->cap_t, o->nt_new + more_t);
}

/* The next vertex along the mesh's part of the polygon (p's loops in
 * the patch's order: 0..n_first-1, then n_first..n_mesh-1); an arc's last
 * comes round to 0 across its chord. */
static size_t rim_next(const hole_patch *p, size_t i)
{
    return i < p->n_first ? (i + 1) % p->n_first
                          : p->n_first + (i + 1 - p->n_first) % (p->n_mesh - p->n_first);
}

/* The rim vertices' wanted edge length (their mean edge in the mesh), the
 * mesh's edges between rim vertices apart along the polygon, and the
 * vertices opposite the rim edges (opp[i]: across the edge from i to
 * rim_next(i)). 0: an arc whose chord is a mesh edge (it cannot be closed
 * without a third triangle there); -1: no memory. */
static int polygon_setup(fill_job *j, hole_patch *p, double *opp)
{
    size_t n = p->n_mesh, nb = 0;
    int ok = 1;
    for (size_t i = 0; i < n; ++i)
        j->local[p->gid[i]] = (uint32_t)i;
    for (size_t i = 0; i < n && ok; ++i) {
        uint32_t g = p->gid[i], s = j->adj.start[g], e = j->adj.start[g + 1];
        size_t next = rim_next(p, i);
        double sum = 0.0;
        for (uint32_t k = s; k < e; ++k) {
            uint32_t u = j->adj.nbr[k], l = j->local[u];
            double d[3];
            sub3(j->pos + 3 * (size_t)u, j->pos + 3 * (size_t)g, d);
            sum += sqrt(dot3(d, d));
            if (l == UINT32_MAX || l <= i || l == next || rim_next(p, l) == i)
                continue;
            if (nb % 16 == 0) {
                uint32_t *b = realloc(p->blocked, (nb + 16) * 2 * sizeof *b);
                if (!b) {
                    ok = -1;
                    break;
                }
                p->blocked = b;
            }
            p->blocked[2 * nb] = (uint32_t)i, p->blocked[2 * nb + 1] = l, ++nb;
        }
        p->sigma[i] = e > s ? sum / (e - s) : 0.0;
        memcpy(p->x + 3 * i, j->pos + 3 * (size_t)g, 3 * sizeof *p->x);
        if (i + 1 < n || p->closed)
            memcpy(opp + 3 * i, j->pos + 3 * (size_t)j->w.opp[p->gid[next]], 3 * sizeof *opp);
        else
            opp[3 * i] = opp[3 * i + 1] = opp[3 * i + 2] = NAN;
    }
    if (!p->closed && ok > 0) { /* the chord: is it a mesh edge? */
        uint32_t g = p->gid[0];
        for (uint32_t k = j->adj.start[g]; k < j->adj.start[g + 1]; ++k)
            if (j->adj.nbr[k] == p->gid[n - 1])
                ok = 0;
    }
    p->n_blocked = nb;
    for (size_t i = 0; i < n; ++i)
        j->local[p->gid[i]] = UINT32_MAX;
    return ok;
}

/* An arc's chord (from its last vertex to its first) cut into pieces
 * about as long as its ends' edges: new polygon vertices n_mesh.. on it,
 * so that the patch's open border keeps the capture's density (one edge
 * across a wide notch leaves a fan of slivers along it that the fairing
 * folds). On the chord's line: a cubic continuing the border outside the
 * arc followed a range scan's jagged border off the truth (lato000's
 * notch: its points 1 h from it, the line's 0.5 h). 0: no memory. */
static int chord_points(hole_patch *p)
{
    const double *a = p->x + 3 * (p->n_mesh - 1), *b = p->x;
    double d[3], s = 0.5 * (p->sigma[p->n_mesh - 1] + p->sigma[0]), len;
    size_t k;
    sub3(b, a, d);
    len = sqrt(dot3(d, d));
    k = s > 0.0 && len > 1.5 * s ? (size_t)floor(len / s + 0.5) - 1 : 0;
    if (!hole_patch_reserve(p, k, 0))
        return 0;
    for (size_t i = 1; i <= k; ++i) {
        double f = (double)i / (double)(k + 1);
        size_t v = p->n_mesh + i - 1;
        for (int e = 0; e < 3; ++e)
            p->x[3 * v + e] = a[e] + f * d[e];
        p->sigma[v] = (1.0 - f) * p->sigma[p->n_mesh - 1] + f * p->sigma[0];
    }
    p->nx = p->n_rim = p->n_mesh + k;
    return 1;
}

/* Add p's new vertices (an arc's chord points first) and triangles to the
 * output under label h. */
static int gather(fill_job *j, const hole_patch *p, uint32_t h)
{
    relief_hole_patches *o = j->out;
    size_t base = j->nv + o->nv_new, nn = p->nx - p->n_mesh;
    if (!out_reserve(j, nn, p->nt))
        return 0;
    if (nn) /* a small hole's patch may add none */
        memcpy(o->pos + 3 * o->nv_new, p->x + 3 * p->n_mesh, nn * 3 * sizeof *o->pos);
    for (size_t i = 0; i < nn; ++i)
        o->hole[o->nv_new + i] = h;
    for (size_t t = 0; t < p->nt; ++t) {
        for (int c = 0; c < 3; ++c) {
            uint32_t l = p->t[3 * t + c];
            o->tri[3 * (o->nt_new + t) + c] =
                l < p->n_mesh ? p->gid[l] : (uint32_t)(base + l - p->n_mesh);
        }
        o->tri_hole[o->nt_new + t] = h;
    }
    o->nv_new += nn, o->nt_new += p->nt;
    return 1;
}

static void patch_free(hole_patch *p)
{
    free(p->x), free(p->sigma), free(p->t), free(p->blocked);
    memset(p, 0, sizeof *p);
}

/* The patch of one polygon (gid: n rim vertices in the patch's order)
 * into p, its three steps run; *ears when it was cut by ears. *set 0:
 * an arc whose chord is a mesh edge, no patch. */
static relief_status build_patch(fill_job *j, hole_patch *p, const uint32_t *gid, size_t n,
                                 size_t n_first, int closed, int *set, int *ears,
                                 relief_error *err)
{
    double *opp = NULL;
    relief_status st = RELIEF_OK;
    memset(p, 0, sizeof *p);
    p->n_rim = p->n_mesh = n, p->n_first = n_first, p->gid = gid, p->closed = closed;
    p->max_new = j->o->max_new;
    *set = 0, *ears = 0;
    if (!hole_patch_reserve(p, n, 0))
        goto nomem;
    p->nx = n;
    opp = malloc(3 * n * sizeof *opp);
    if (!opp)
        goto nomem;
    *set = polygon_setup(j, p, opp);
    if (*set < 0)
        goto nomem;
    if (*set == 0)
        goto done;
    if (!closed) {
        double *o2;
        if (!chord_points(p) || !(o2 = realloc(opp, 3 * p->n_rim * sizeof *opp)))
            goto nomem;
        opp = o2;
        for (size_t i = 3 * n; i < 3 * p->n_rim; ++i)
            opp[i] = NAN;
    }
    if (n_first < n) { /* a tube */
        int r = hole_bridge(p);
        if (r == 0)
            goto nomem;
        if (r < 0) {
            *set = 0;
            goto done;
        }
    } else if (!hole_triangulate(p, opp, ears))
        goto nomem;
    if (j->o->refine)
        st = hole_refine(p, err);
    if (st == RELIEF_OK && j->o->fair != RELIEF_FAIR_NONE && p->nx > p->n_rim)
        st = hole_fair(p, (int)j->o->fair, j->pos, &j->adj, err);
    goto done;
nomem:
    st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the patch of a %zu-vertex hole", n);
done:
    free(opp);
    return st;
}

/* A built patch into the output under label h, and counted. */
static relief_status keep_patch(fill_job *j, const hole_patch *p, int ears, uint32_t h,
                                relief_error *err)
{
    if (j->o->max_new && j->out->nv_new + p->nx - p->n_mesh > j->o->max_new)
        return relief_fail(err, RELIEF_E_RANGE, "filling the holes would add more than %zu "
                           "vertices", j->o->max_new);
    if (!gather(j, p, h))
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the patch of a %zu-vertex "
                           "hole", p->n_rim);
    ++j->out->polygons;
    j->out->arcs += !p->closed;
    j->out->by_ears += (size_t)ears;
    return RELIEF_OK;
}

/* Close one polygon (gid: n rim vertices in the patch's order). */
static relief_status close_polygon(fill_job *j, const uint32_t *gid, size_t n, int closed,
                                   uint32_t h, relief_error *err)
{
    hole_patch p;
    int set, ears;
    relief_status st = build_patch(j, &p, gid, n, n, closed, &set, &ears, err);
    if (st == RELIEF_OK && set == 0)
        ++j->out->skipped;
    else if (st == RELIEF_OK)
        st = keep_patch(j, &p, ears, h, err);
    patch_free(&p);
    return st;
}

/* The loop through v, in the patch's order (the boundary reversed) into
 * poly; 0 when it meets a pinch or does not close. */
static size_t walk_loop(fill_job *j, uint32_t v, uint8_t *seen, uint32_t *poly)
{
    size_t n = 0;
    uint32_t u = v;
    int ok = 1;
    do {
        if (j->w.pinch[u] || j->w.succ[u] == UINT32_MAX || seen[u])
            ok = 0;
        seen[u] = 1;
        poly[n++] = u;
        u = j->w.succ[u];
    } while (ok && u != v && u != UINT32_MAX && n < j->nv);
    for (size_t i = 0; i < n / 2; ++i) {
        uint32_t s = poly[i];
        poly[i] = poly[n - 1 - i], poly[n - 1 - i] = s;
    }
    return ok && u == v ? n : 0;
}

/* The arc of a loop (poly, n) partly labelled: its label *h, and its m
 * vertices from poly[*first] on, round the other way from the longest
 * stretch without the label (a notch's rim weaves in and out of a ball
 * that selects it: the stretches it leaves inside are bridged). A loop
 * that carries two labels gives the first's. 0: the loop is whole (one
 * label covers it; *h that label, or 0). */
static int arc_of(const uint32_t *rim, const uint32_t *poly, size_t n, uint32_t *h,
                  size_t *first, size_t *m)
{
    size_t all = 1, gap = 0, gap_end = 0;
    *h = 0;
    for (size_t i = 0; i < n; ++i) {
        all &= rim[poly[i]] == rim[poly[0]];
        if (!*h && rim[poly[i]])
            *h = rim[poly[i]];
    }
    if (all)
        return 0;
    for (size_t i = 0, len = 0; i < 2 * n; ++i) { /* twice round, to see it whole */
        len = rim[poly[i % n]] == *h ? 0 : len + 1;
        if (len > gap && len <= n)
            gap = len, gap_end = i % n;
    }
    *first = (gap_end + 1) % n, *m = n - gap;
    return 1;
}

/* 1 when the patch's triangle on the arc's rim edge (a, b) (in the
 * patch's order; the mesh's triangle across it is (b, a, opp[b])) would
 * fold onto the mesh: x, the arc's far end, lies on the mesh's side of
 * the edge. */
static int folds(const fill_job *j, uint32_t a, uint32_t b, uint32_t x)
{
    const double *A = j->pos + 3 * (size_t)a, *B = j->pos + 3 * (size_t)b;
    const double *O = j->pos + 3 * (size_t)j->w.opp[b], *X = j->pos + 3 * (size_t)x;
    double e[3], o[3], q[3], n[3], so[3], sx[3];
    sub3(B, A, e), sub3(O, A, o), sub3(X, A, q);
    cross3(o, e, n); /* the mesh triangle (b, a, O)'s normal, up to length */
    cross3(e, o, so), cross3(e, q, sx);
    return dot3(so, n) * dot3(sx, n) > 0.0;
}

/* Trim an arc's ends (run, *m in the patch's order) while the chord's
 * far end lies on the mesh's side of the end's rim edge: where a border
 * is convex, a ball's selection runs on along it past the notch, and the
 * patch's first triangle there would lie over the capture. */
static void trim_arc(const fill_job *j, uint32_t *run, size_t *m)
{
    for (int trimmed = 1; trimmed && *m > 3;) {
        trimmed = 0;
        if (folds(j, run[0], run[1], run[*m - 1])) {
            memmove(run, run + 1, (*m - 1) * sizeof *run);
            --*m, trimmed = 1;
        }
        if (*m > 3 && folds(j, run[*m - 2], run[*m - 1], run[0]))
            --*m, trimmed = 1;
    }
}

/* An arc's patch that crosses the capture or itself near an end of its
 * chord (the rim runs on along the chord there, a sliver the faired patch
 * folds over: a range scan's border where a ball's selection takes it on
 * past the notch) is made again with that end trimmed, up to
 * RELIEF_NOTCH_TRIMS times; crossings farther in than a quarter of the
 * chord are not the ends' and stop it. */
static relief_status close_arc(fill_job *j, uint32_t *run, size_t m, uint32_t h,
                               relief_error *err)
{
    hole_patch p = {0};
    relief_status st = RELIEF_OK;
    int set = 1, ears = 0;
    for (int tries = 0; st == RELIEF_OK; ++tries) {
        const double *a, *b;
        double where[3], da[3], db[3], dc[3];
        size_t cross = 0;
        patch_free(&p);
        st = build_patch(j, &p, run, m, m, 0, &set, &ears, err);
        if (st != RELIEF_OK || !set || tries == RELIEF_NOTCH_TRIMS || m <= 3)
            break;
        st = hole_patch_crossings(&p, j->pos, j->tri, j->nt, &cross, where, err);
        if (st != RELIEF_OK || !cross)
            break;
        a = j->pos + 3 * (size_t)run[0], b = j->pos + 3 * (size_t)run[m - 1];
        sub3(where, a, da), sub3(where, b, db), sub3(b, a, dc);
        if (16.0 * fmin(dot3(da, da), dot3(db, db)) > dot3(dc, dc))
            break;
        if (dot3(da, da) <= dot3(db, db))
            memmove(run, run + 1, (m - 1) * sizeof *run);
        --m;
    }
    if (st == RELIEF_OK && !set)
        ++j->out->skipped;
    else if (st == RELIEF_OK)
        st = keep_patch(j, &p, ears, h, err);
    patch_free(&p);
    return st;
}

/* The loop's fill: the whole loop when one label covers it, else its arc. */
static relief_status close_loop(fill_job *j, uint32_t *poly, size_t n, uint32_t *run,
                                relief_error *err)
{
    uint32_t h;
    size_t first, m;
    if (!arc_of(j->rim, poly, n, &h, &first, &m))
        return h ? close_polygon(j, poly, n, 1, h, err) : RELIEF_OK;
    for (size_t i = 0; i < m; ++i)
        run[i] = poly[(first + i) % n];
    trim_arc(j, run, &m);
    if (m < 3) {
        ++j->out->skipped;
        return RELIEF_OK;
    }
    return close_arc(j, run, m, h, err);
}

relief_status relief_rim_arcs(const double *pos, size_t nv, const uint32_t *tri, size_t nt,
                              const uint32_t *rim, relief_rim_arc **arcs, size_t *n_arcs,
                              relief_error *err)
{
    rim_walk w = {0};
    fill_job j = {pos, nv, tri, nt, rim, NULL, {0}, {0}, NULL, NULL, 0, 0};
    uint8_t *seen = calloc(nv + 1, 1);
    uint32_t *poly = malloc((nv + 1) * sizeof *poly);
    relief_status st = seen && poly ? boundary_successors(tri, nt, nv, &w, err)
                                    : relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the "
                                                  "rims of %zu vertices", nv);
    *arcs = NULL, *n_arcs = 0;
    j.w = w;
    for (size_t v = 0; st == RELIEF_OK && v < nv; ++v) {
        size_t n, first, m;
        uint32_t h;
        relief_rim_arc *a;
        if (!rim[v] || seen[v] || w.succ[v] == UINT32_MAX)
            continue;
        n = walk_loop(&j, (uint32_t)v, seen, poly);
        if (!n || !arc_of(rim, poly, n, &h, &first, &m) || m < 3)
            continue;
        a = realloc(*arcs, (*n_arcs + 1) * sizeof *a);
        if (!a) {
            st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the rims' arcs");
            break;
        }
        *arcs = a, a += (*n_arcs)++;
        a->label = h;
        a->first = poly[first], a->last = poly[(first + m - 1) % n];
        a->mean[0] = a->mean[1] = a->mean[2] = 0.0;
        for (size_t i = 0; i < m; ++i)
            for (int e = 0; e < 3; ++e)
                a->mean[e] += pos[3 * (size_t)poly[(first + i) % n] + e] / (double)m;
    }
    if (st != RELIEF_OK)
        free(*arcs), *arcs = NULL, *n_arcs = 0;
    free(w.succ), free(w.opp), free(w.pinch), free(seen), free(poly);
    return st;
}

/* The loops through the rims, walked once: loop k is at
 * v[start[k]..start[k] + len[k]) in the patch's order, len 0 where the
 * walk met a pinch. */
typedef struct loop_set {
    uint32_t *v;
    size_t *start, *len, n;
} loop_set;

static relief_status walk_all(fill_job *j, loop_set *ls, relief_error *err)
{
    uint8_t *seen = calloc(j->nv + 1, 1);
    size_t used = 0;
    ls->v = malloc((2 * j->nv + 1) * sizeof *ls->v);
    ls->start = malloc((j->nv + 1) * sizeof *ls->start);
    ls->len = malloc((j->nv + 1) * sizeof *ls->len);
    ls->n = 0;
    if (!seen || !ls->v || !ls->start || !ls->len) {
        free(seen);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the rims of %zu vertices",
                           j->nv);
    }
    for (size_t v = 0; v < j->nv; ++v) {
        if (!j->rim[v] || seen[v] || j->w.succ[v] == UINT32_MAX)
            continue;
        ls->start[ls->n] = used;
        ls->len[ls->n] = walk_loop(j, (uint32_t)v, seen, ls->v + used);
        used += ls->len[ls->n++]; /* a failed walk's vertices are seen: written once */
    }
    free(seen);
    return RELIEF_OK;
}

/* mate[k]: the loop that bounds one hole with whole loop k (a tube's
 * other end: hole_loops_face), or -1; the first such in the loops' order
 * for each in turn. */
static relief_status find_tubes(const fill_job *j, const loop_set *ls, long *mate,
                                relief_error *err)
{
    hole_loop_shape *f = malloc((ls->n + 1) * sizeof *f);
    if (!f)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the rims' directions");
    for (size_t k = 0; k < ls->n; ++k) {
        const uint32_t *v = ls->v + ls->start[k];
        size_t n = ls->len[k];
        int whole = n >= 3 && j->rim[v[0]];
        for (size_t i = 1; whole && i < n; ++i)
            whole = j->rim[v[i]] == j->rim[v[0]];
        mate[k] = whole ? -2 : -1; /* -2: a whole loop, not paired yet */
        if (whole)
            hole_loop_facing(j->pos, j->w.opp, v, n, f + k);
    }
    for (size_t a = 0; a < ls->n; ++a)
        for (size_t b = a + 1; mate[a] == -2 && b < ls->n; ++b)
            if (mate[b] == -2 && hole_loops_face(f + a, f + b))
                mate[a] = (long)b, mate[b] = (long)a;
    for (size_t k = 0; k < ls->n; ++k)
        mate[k] = mate[k] == -2 ? -1 : mate[k];
    free(f);
    return RELIEF_OK;
}

/* Loops a and b, one hole between them, closed by one patch (the strip,
 * refined and faired) under a's label; each capped alone where the strip
 * is too large to search. */
static relief_status close_tube(fill_job *j, const loop_set *ls, size_t a, size_t b,
                                uint32_t *run, relief_error *err)
{
    size_t na = ls->len[a], nb = ls->len[b];
    hole_patch p;
    int set, ears;
    relief_status st;
    memcpy(run, ls->v + ls->start[a], na * sizeof *run);
    memcpy(run + na, ls->v + ls->start[b], nb * sizeof *run);
    st = build_patch(j, &p, run, na + nb, na, 1, &set, &ears, err);
    if (st == RELIEF_OK && set > 0)
        st = keep_patch(j, &p, 0, j->rim[run[0]], err);
    patch_free(&p);
    if (st == RELIEF_OK && set <= 0) {
        st = close_polygon(j, ls->v + ls->start[a], na, 1, j->rim[run[0]], err);
        if (st == RELIEF_OK)
            st = close_polygon(j, ls->v + ls->start[b], nb, 1, j->rim[run[na]], err);
    }
    return st;
}

relief_status relief_fill_rims(const double *pos, size_t nv, const uint32_t *tri, size_t nt,
                               const uint32_t *rim, const relief_hole_fill_options *o,
                               relief_hole_patches *out, relief_error *err)
{
    relief_hole_fill_options def;
    relief_mesh m = {.nv = nv, .nt = nt, .pos = (double *)pos, .tri = (uint32_t *)tri};
    fill_job j = {pos, nv, tri, nt, rim, o, {0}, {0}, NULL, out, 0, 0};
    loop_set ls = {0};
    long *mate = NULL;
    uint32_t *run = malloc((nv + 1) * sizeof *run);
    relief_status st;

    memset(out, 0, sizeof *out);
    if (!o) {
        relief_hole_fill_options_default(&def);
        j.o = &def;
    }
    j.local = malloc((nv + 1) * sizeof *j.local);
    if (!run || !j.local) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the rims of %zu vertices", nv);
        goto done;
    }
    for (size_t v = 0; v < nv; ++v)
        j.local[v] = UINT32_MAX;
    st = relief_mesh_adjacency(&m, &j.adj, err);
    if (st == RELIEF_OK)
        st = boundary_successors(tri, nt, nv, &j.w, err);
    if (st == RELIEF_OK)
        st = walk_all(&j, &ls, err);
    if (st == RELIEF_OK && !(mate = malloc((ls.n + 1) * sizeof *mate)))
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the rims' pairs");
    if (st == RELIEF_OK)
        st = find_tubes(&j, &ls, mate, err);
    for (size_t k = 0; st == RELIEF_OK && k < ls.n; ++k) {
        if (!ls.len[k])
            ++out->skipped;
        else if (mate[k] < 0)
            st = close_loop(&j, ls.v + ls.start[k], ls.len[k], run, err);
        else if ((size_t)mate[k] > k)
            st = close_tube(&j, &ls, k, (size_t)mate[k], run, err);
    }
done:
    if (st != RELIEF_OK)
        relief_hole_patches_free(out);
    relief_adjacency_free(&j.adj);
    free(j.w.succ), free(j.w.opp), free(j.w.pinch);
    free(ls.v), free(ls.start), free(ls.len), free(mate), free(run), free(j.local);
    return st;
}
