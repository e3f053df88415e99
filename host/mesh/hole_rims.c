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

/* The rim vertices' wanted edge length (their mean edge in the mesh), the
 * mesh's edges between rim vertices apart along the polygon, and the
 * vertices opposite the rim edges. 0: an arc whose chord is a mesh edge
 * (it cannot be closed without a third triangle there); -1: no memory. */
static int polygon_setup(fill_job *j, hole_patch *p, double *opp)
{
    size_t n = p->n_rim, nb = 0;
    int ok = 1;
    for (size_t i = 0; i < n; ++i)
        j->local[p->gid[i]] = (uint32_t)i;
    for (size_t i = 0; i < n && ok; ++i) {
        uint32_t g = p->gid[i], s = j->adj.start[g], e = j->adj.start[g + 1];
        double sum = 0.0;
        for (uint32_t k = s; k < e; ++k) {
            uint32_t u = j->adj.nbr[k], l = j->local[u];
            double d[3];
            sub3(j->pos + 3 * (size_t)u, j->pos + 3 * (size_t)g, d);
            sum += sqrt(dot3(d, d));
            if (l == UINT32_MAX || l <= i || l == i + 1 || (i == 0 && l == n - 1))
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
            memcpy(opp + 3 * i, j->pos + 3 * (size_t)j->w.opp[p->gid[(i + 1) % n]],
                   3 * sizeof *opp);
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

/* Add p's new vertices and triangles to the output under label h. */
static int gather(fill_job *j, const hole_patch *p, uint32_t h)
{
    relief_hole_patches *o = j->out;
    size_t base = j->nv + o->nv_new, nn = p->nx - p->n_rim;
    if (!out_reserve(j, nn, p->nt))
        return 0;
    if (nn) /* a small hole's patch may add none */
        memcpy(o->pos + 3 * o->nv_new, p->x + 3 * p->n_rim, nn * 3 * sizeof *o->pos);
    for (size_t i = 0; i < nn; ++i)
        o->hole[o->nv_new + i] = h;
    for (size_t t = 0; t < p->nt; ++t) {
        for (int c = 0; c < 3; ++c) {
            uint32_t l = p->t[3 * t + c];
            o->tri[3 * (o->nt_new + t) + c] =
                l < p->n_rim ? p->gid[l] : (uint32_t)(base + l - p->n_rim);
        }
        o->tri_hole[o->nt_new + t] = h;
    }
    o->nv_new += nn, o->nt_new += p->nt;
    return 1;
}

/* Close one polygon (gid: n rim vertices in the patch's order). */
static relief_status close_polygon(fill_job *j, const uint32_t *gid, size_t n, int closed,
                                   uint32_t h, relief_error *err)
{
    hole_patch p = {0};
    double *opp = malloc(3 * n * sizeof *opp);
    relief_status st = RELIEF_OK;
    int set, ears = 0;
    p.n_rim = n, p.gid = gid, p.closed = closed;
    p.max_new = j->o->max_new;
    if (!opp || !hole_patch_reserve(&p, n, 0))
        goto nomem;
    p.nx = n;
    set = polygon_setup(j, &p, opp);
    if (set < 0)
        goto nomem;
    if (set == 0) {
        ++j->out->skipped;
        goto done;
    }
    if (!hole_triangulate(&p, opp, &ears))
        goto nomem;
    if (j->o->refine)
        st = hole_refine(&p, err);
    if (st == RELIEF_OK && j->o->fair != RELIEF_FAIR_NONE && p.nx > n)
        st = hole_fair(&p, (int)j->o->fair, j->pos, &j->adj, err);
    if (st == RELIEF_OK && j->o->max_new && j->out->nv_new + p.nx - n > j->o->max_new)
        st = relief_fail(err, RELIEF_E_RANGE, "filling the holes would add more than %zu "
                         "vertices", j->o->max_new);
    if (st == RELIEF_OK && !gather(j, &p, h))
        goto nomem;
    if (st == RELIEF_OK) {
        ++j->out->polygons;
        j->out->arcs += !closed;
        j->out->by_ears += (size_t)ears;
    }
    goto done;
nomem:
    st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the patch of a %zu-vertex hole", n);
done:
    free(opp), free(p.x), free(p.sigma), free(p.t), free(p.blocked);
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
    return close_polygon(j, run, m, 0, h, err);
}

relief_status relief_rim_arcs(const double *pos, size_t nv, const uint32_t *tri, size_t nt,
                              const uint32_t *rim, relief_rim_arc **arcs, size_t *n_arcs,
                              relief_error *err)
{
    rim_walk w = {0};
    fill_job j = {pos, nv, rim, NULL, {0}, {0}, NULL, NULL, 0, 0};
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

relief_status relief_fill_rims(const double *pos, size_t nv, const uint32_t *tri, size_t nt,
                               const uint32_t *rim, const relief_hole_fill_options *o,
                               relief_hole_patches *out, relief_error *err)
{
    relief_hole_fill_options def;
    relief_mesh m = {.nv = nv, .nt = nt, .pos = (double *)pos, .tri = (uint32_t *)tri};
    fill_job j = {pos, nv, rim, o, {0}, {0}, NULL, out, 0, 0};
    uint8_t *seen = calloc(nv + 1, 1);
    uint32_t *poly = malloc((nv + 1) * sizeof *poly), *run = malloc((nv + 1) * sizeof *run);
    relief_status st;

    memset(out, 0, sizeof *out);
    if (!o) {
        relief_hole_fill_options_default(&def);
        j.o = &def;
    }
    j.local = malloc((nv + 1) * sizeof *j.local);
    if (!seen || !poly || !run || !j.local) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the rims of %zu vertices", nv);
        goto done;
    }
    for (size_t v = 0; v < nv; ++v)
        j.local[v] = UINT32_MAX;
    st = relief_mesh_adjacency(&m, &j.adj, err);
    if (st == RELIEF_OK)
        st = boundary_successors(tri, nt, nv, &j.w, err);
    for (size_t v = 0; st == RELIEF_OK && v < nv; ++v) {
        size_t n;
        if (!rim[v] || seen[v] || j.w.succ[v] == UINT32_MAX)
            continue;
        n = walk_loop(&j, (uint32_t)v, seen, poly);
        if (!n) {
            ++out->skipped;
            continue;
        }
        st = close_loop(&j, poly, n, run, err);
    }
done:
    if (st != RELIEF_OK)
        relief_hole_patches_free(out);
    relief_adjacency_free(&j.adj);
    free(j.w.succ), free(j.w.opp), free(j.w.pinch);
    free(seen), free(poly), free(run), free(j.local);
    return st;
}
