/* Geometry the method cannot handle (surface_check.h). */
#include "smooth/surface_check.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/knn.h"
#include "base/linalg.h"
#include "mesh/mesh.h"

/* ---------------------------------------------------------------- capture */

typedef struct half_edge {
    uint32_t a, b; /* a < b */
    uint32_t t;    /* triangle */
} half_edge;

static int half_edge_cmp(const void *x, const void *y)
{
    const half_edge *p = x, *q = y;
    if (p->a != q->a)
        return p->a < q->a ? -1 : 1;
    if (p->b != q->b)
        return p->b < q->b ? -1 : 1;
    return (p->t > q->t) - (p->t < q->t);
}

/* Edges shared by more than two triangles: a fin, or a second layer
 * joined along an edge. (A vertex where two fans of triangles touch, common
 * in range scans, is harmless: relief re-triangulates the capture's points
 * on the primitive.) */
static relief_status check_manifold(const relief_mesh *m, relief_error *err)
{
    const size_t ne = 3 * m->nt;
    half_edge *e = malloc((ne + 1) * sizeof *e);
    relief_status st = RELIEF_OK;

    if (!e)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the capture's edge list");
    for (size_t t = 0; t < m->nt; ++t)
        for (int i = 0; i < 3; ++i) {
            uint32_t a = m->tri[3 * t + i], b = m->tri[3 * t + (i + 1) % 3];
            e[3 * t + i].a = a < b ? a : b;
            e[3 * t + i].b = a < b ? b : a;
            e[3 * t + i].t = (uint32_t)t;
        }
    qsort(e, ne, sizeof *e, half_edge_cmp);
    for (size_t i = 0, j; i < ne; i = j) {
        for (j = i + 1; j < ne && e[j].a == e[i].a && e[j].b == e[i].b; ++j)
            ;
        if (j - i > 2) {
            const double *p = m->pos + 3 * (size_t)e[i].a, *q = m->pos + 3 * (size_t)e[i].b;
            st = relief_fail(err, RELIEF_E_MESH,
                             "the capture is not manifold: edge %u-%u at (%.6g, %.6g, %.6g) "
                             "is shared by %zu triangles (%u, %u, %u%s); relief needs a "
                             "single-layer surface",
                             e[i].a, e[i].b, 0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]),
                             0.5 * (p[2] + q[2]), j - i, e[i].t, e[i + 1].t, e[i + 2].t,
                             j - i > 3 ? ", ..." : "");
            break;
        }
    }
    free(e);
    return st;
}

/* What the orientation pass finds, areas in the capture's square units. */
typedef struct fold_tally {
    double with, against, total; /* facing the primitive's normal, away from it, all */
    double folded, largest;      /* the folded triangles', the largest one's */
    size_t n_folded, worst;      /* folded triangles, the largest one */
} fold_tally;

/* side (nt): 1 where a triangle faces with the primitive's normal (at the
 * projection of its centroid), -1 against it, 0 when degenerate or too
 * close to edge-on to tell; the areas summed into ft. */
static void fold_sides(const relief_mesh *m, const relief_fit_primitive *pr, signed char *side,
                       fold_tally *ft)
{
    for (size_t t = 0; t < m->nt; ++t) {
        const double *a = m->pos + 3 * (size_t)m->tri[3 * t];
        const double *b = m->pos + 3 * (size_t)m->tri[3 * t + 1];
        const double *c = m->pos + 3 * (size_t)m->tri[3 * t + 2];
        double u[3], w[3], n[3], g[3], q[3], pn[3], len, cosv;
        for (int k = 0; k < 3; ++k) {
            u[k] = b[k] - a[k];
            w[k] = c[k] - a[k];
            g[k] = (a[k] + b[k] + c[k]) / 3.0;
        }
        n[0] = u[1] * w[2] - u[2] * w[1];
        n[1] = u[2] * w[0] - u[0] * w[2];
        n[2] = u[0] * w[1] - u[1] * w[0];
        len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        side[t] = 0;
        if (!(len > 0.0))
            continue;
        relief_fit_project(pr, g, q);
        relief_fit_normal(pr, q, pn);
        cosv = (n[0] * pn[0] + n[1] * pn[1] + n[2] * pn[2]) / len;
        ft->total += 0.5 * len;
        if (cosv > -RELIEF_FOLD_COS)
            side[t] = 1, ft->with += 0.5 * len;
        else if (cosv < RELIEF_FOLD_COS)
            side[t] = -1, ft->against += 0.5 * len;
    }
}

/* The file may wind every triangle the other way: the majority decides
 * which side is "with". side[t] becomes 1 for a folded triangle, else 0;
 * their count, area and the largest of them into ft. */
static void fold_mark(const relief_mesh *m, signed char *side, fold_tally *ft)
{
    for (size_t t = 0; t < m->nt; ++t) {
        double area;
        if (side[t] == 0 || (side[t] > 0) == (ft->with >= ft->against)) {
            side[t] = 0;
            continue;
        }
        side[t] = 1;
        area = relief_mesh_triangle_area(m, t);
        ++ft->n_folded;
        ft->folded += area;
        if (area > ft->largest) {
            ft->largest = area;
            ft->worst = t;
        }
    }
}

/* The refusal of a capture folded over too much of its area, quoting the
 * largest folded triangle. */
static relief_status refuse_folds(const relief_mesh *m, const relief_fit_primitive *pr,
                                  const fold_tally *ft, relief_error *err)
{
    const uint32_t *f = m->tri + 3 * ft->worst;
    const double *p = m->pos + 3 * (size_t)f[0];
    return relief_fail_reason(err, RELIEF_E_MESH, RELIEF_REASON_FOLD_REFUSED,
                       RELIEF_FOLD_REFUSAL " %s: %zu triangles "
                       "(%.1f%% of its area, more than %.0f%%) face away from it, the "
                       "largest triangle %zu (vertices %u, %u, %u) at (%.6g, %.6g, "
                       "%.6g); relief needs a height field over the primitive (or the "
                       "file's triangles are not consistently wound)",
                       relief_fit_model_name(pr->model), ft->n_folded,
                       100.0 * ft->folded / ft->total, 100.0 * RELIEF_FOLD_AREA_MAX, ft->worst,
                       f[0], f[1], f[2], p[0], p[1], p[2]);
}

/* *unfolded: the capture without its n_folded folded triangles (side[t]
 * 1) and every vertex they touch; what went into fs. */
static relief_status drop_folded(const relief_mesh *m, const signed char *side, size_t n_folded,
                                 relief_mesh **unfolded, relief_fold_stats *fs,
                                 relief_error *err)
{
    uint8_t *keep = malloc(m->nv);
    relief_status st;
    if (!keep)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the unfolded capture");
    memset(keep, 1, m->nv);
    for (size_t t = 0; t < m->nt; ++t)
        if (side[t])
            for (int i = 0; i < 3; ++i)
                keep[m->tri[3 * t + i]] = 0;
    st = relief_mesh_subset(m, keep, unfolded, NULL, err);
    if (st == RELIEF_OK && (*unfolded)->nt == 0) {
        relief_mesh_destroy(*unfolded);
        *unfolded = NULL;
        st = relief_fail(err, RELIEF_E_MESH,
                         "the capture has no triangle left once its %zu folded "
                         "triangles and their vertices are dropped", n_folded);
    }
    if (st == RELIEF_OK) {
        fs->vertices_dropped = m->nv - (*unfolded)->nv;
        fs->triangles_dropped = m->nt - (*unfolded)->nt;
    }
    free(keep);
    return st;
}

/* Triangles whose normal turns away from the primitive's: the capture
 * folds back over itself (or its triangles are not consistently wound).
 * Those over RELIEF_FOLD_AREA_MAX of the area are refused; fewer are the
 * fringes a depth camera leaves at depth edges, and go, with every vertex
 * they touch, so that the fold becomes a hole the completion fills. */
static relief_status check_folds(const relief_mesh *m, const relief_fit_primitive *pr,
                                 relief_mesh **unfolded, relief_fold_stats *fs,
                                 relief_error *err)
{
    fold_tally ft = {0.0, 0.0, 0.0, 0.0, 0.0, 0, 0};
    signed char *side = malloc(m->nt + 1);
    relief_status st = RELIEF_OK;

    if (!side)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the capture's orientations");
    fold_sides(m, pr, side, &ft);
    fold_mark(m, side, &ft);
    fs->triangles = ft.n_folded;
    fs->area_fraction = ft.total > 0.0 ? ft.folded / ft.total : 0.0;
    if (ft.total > 0.0 && ft.folded > RELIEF_FOLD_AREA_MAX * ft.total)
        st = refuse_folds(m, pr, &ft, err);
    else if (ft.n_folded > 0)
        st = drop_folded(m, side, ft.n_folded, unfolded, fs, err);
    free(side);
    return st;
}

relief_status relief_capture_check(const relief_mesh *capture,
                                   const relief_fit_primitive *prim, relief_mesh **unfolded,
                                   relief_fold_stats *folds, relief_error *err)
{
    relief_fold_stats dummy;
    relief_status st;
    if (!folds)
        folds = &dummy;
    memset(folds, 0, sizeof *folds);
    *unfolded = NULL;
    st = check_manifold(capture, err);
    if (st == RELIEF_OK)
        st = check_folds(capture, prim, unfolded, folds, err);
    return st;
}

/* ----------------------------------------------------------------- spikes */

/* h (nv): each vertex's distance to the primitive; returns the largest
 * number of neighbours a vertex has. */
static size_t spike_heights(const relief_mesh *m, const relief_fit_primitive *pr,
                            const relief_adjacency *adj, double *h)
{
    size_t ring_max = 0;
    for (size_t v = 0; v < m->nv; ++v) {
        h[v] = relief_fit_distance(pr, m->pos + 3 * v);
        if (adj->start[v + 1] - adj->start[v] > ring_max)
            ring_max = adj->start[v + 1] - adj->start[v];
    }
    return ring_max;
}

/* r (nv): each vertex's excess outside its neighbours' heights (0 for a
 * vertex with fewer than 3 neighbours: no local test); absr (one per
 * vertex tested): |h - the neighbours' median|, whose median gives the
 * scale. ring: scratch for the largest ring. Returns the vertices tested. */
static size_t spike_excess(const relief_mesh *m, const relief_adjacency *adj, const double *h,
                           double *r, double *ring, double *absr)
{
    size_t n_tested = 0;
    for (size_t v = 0; v < m->nv; ++v) {
        size_t n = adj->start[v + 1] - adj->start[v];
        double lo = DBL_MAX, hi = -DBL_MAX;
        r[v] = 0.0;
        if (n < 3)
            continue;
        for (size_t i = 0; i < n; ++i) {
            ring[i] = h[adj->nbr[adj->start[v] + i]];
            lo = fmin(lo, ring[i]);
            hi = fmax(hi, ring[i]);
        }
        absr[n_tested++] = fabs(h[v] - relief_select_median(ring, n));
        r[v] = h[v] > hi ? h[v] - hi : h[v] < lo ? lo - h[v] : 0.0; /* the excess */
    }
    return n_tested;
}

/* The noise scale: 1.4826 times the median of absr (n_tested; reordered),
 * never below the precision of a float file (1e-6 of the capture's size):
 * over a noise-free surface that is exactly flat in places the median is 0
 * and rounding alone would stand out. */
static double spike_scale(const relief_mesh *m, double *absr, size_t n_tested)
{
    double lo[3] = {DBL_MAX, DBL_MAX, DBL_MAX}, hi[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX};
    for (size_t v = 0; v < m->nv; ++v)
        for (int k3 = 0; k3 < 3; ++k3) {
            lo[k3] = fmin(lo[k3], m->pos[3 * v + k3]);
            hi[k3] = fmax(hi[k3], m->pos[3 * v + k3]);
        }
    return fmax(1.4826 * relief_select_median(absr, n_tested),
                1e-6 * sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) +
                            (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                            (hi[2] - lo[2]) * (hi[2] - lo[2])));
}

/* keep (nv): 0 for each vertex whose excess r (nv) passes sp->threshold,
 * counted in sp with the largest excess. */
static void spike_mark(const relief_mesh *m, const double *r, uint8_t *keep,
                       relief_spike_stats *sp)
{
    memset(keep, 1, m->nv);
    for (size_t v = 0; v < m->nv; ++v) {
        if (fabs(r[v]) > sp->largest)
            sp->largest = fabs(r[v]);
        if (fabs(r[v]) > sp->threshold) {
            keep[v] = 0;
            ++sp->vertices;
        }
    }
}

/* *despiked: the capture with only the vertices keep marks (and the
 * triangles among them); refused when no triangle is left. */
static relief_status drop_spikes(const relief_mesh *m, const uint8_t *keep,
                                 relief_mesh **despiked, relief_spike_stats *sp,
                                 relief_error *err)
{
    relief_status st = relief_mesh_subset(m, keep, despiked, NULL, err);
    if (st == RELIEF_OK && (*despiked)->nt == 0) {
        relief_mesh_destroy(*despiked);
        *despiked = NULL;
        st = relief_fail(err, RELIEF_E_MESH,
                         "the capture has no triangle left once its %zu spikes are dropped; "
                         "keep_spikes keeps them", sp->vertices);
    }
    if (st == RELIEF_OK)
        sp->triangles_dropped = m->nt - (*despiked)->nt;
    return st;
}

relief_status relief_capture_spikes(const relief_mesh *m, const relief_fit_primitive *pr,
                                    double k, relief_mesh **despiked, relief_spike_stats *sp,
                                    relief_error *err)
{
    relief_adjacency adj = {NULL, NULL};
    double *h = malloc((m->nv + 1) * sizeof *h), *r = malloc((m->nv + 1) * sizeof *r);
    double *ring = NULL, *absr = malloc((m->nv + 1) * sizeof *absr);
    uint8_t *keep = NULL;
    size_t n_tested = 0, ring_max = 0;
    relief_status st;

    memset(sp, 0, sizeof *sp);
    *despiked = NULL;
    if (!h || !r || !absr) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the capture's spike test");
        goto done;
    }
    st = relief_mesh_adjacency(m, &adj, err);
    if (st != RELIEF_OK)
        goto done;
    ring_max = spike_heights(m, pr, &adj, h);
    ring = malloc((ring_max + 1) * sizeof *ring);
    keep = malloc(m->nv + 1);
    if (!ring || !keep) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the capture's spike test");
        goto done;
    }
    n_tested = spike_excess(m, &adj, h, r, ring, absr);
    if (n_tested == 0)
        goto done;
    sp->scale = spike_scale(m, absr, n_tested);
    sp->threshold = k * sp->scale;
    spike_mark(m, r, keep, sp);
    if (sp->vertices == 0)
        goto done;
    st = drop_spikes(m, keep, despiked, sp, err);
done:
    relief_adjacency_free(&adj);
    free(keep);
    free(ring);
    free(absr);
    free(r);
    free(h);
    return st;
}

/* ---------------------------------------------------------------- growth */

/* Targets no path joins to a sample: breadth-first from every sample. */
static relief_status check_reachable(const relief_surface *s, relief_error *err)
{
    const relief_mesh *m = s->mesh;
    uint32_t *start = calloc(m->nv + 2, sizeof *start);
    uint32_t *nbr = malloc((6 * m->nt + 1) * sizeof *nbr);
    uint32_t *queue = malloc((m->nv + 1) * sizeof *queue);
    uint8_t *seen = calloc(m->nv + 1, 1);
    size_t head = 0, tail = 0, lost = 0, first = 0;
    relief_status st = RELIEF_OK;

    if (!start || !nbr || !queue || !seen) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the reachability search");
        goto done;
    }
    for (size_t i = 0; i < 3 * m->nt; ++i)
        start[m->tri[i] + 2] += 2;
    for (size_t v = 0; v < m->nv; ++v)
        start[v + 2] += start[v + 1];
    for (size_t t = 0; t < m->nt; ++t)
        for (int i = 0; i < 3; ++i) {
            const uint32_t a = m->tri[3 * t + i];
            nbr[start[a + 1]++] = m->tri[3 * t + (i + 1) % 3];
            nbr[start[a + 1]++] = m->tri[3 * t + (i + 2) % 3];
        }
    for (size_t v = 0; v < s->n_samples; ++v) {
        seen[v] = 1;
        queue[tail++] = (uint32_t)v;
    }
    while (head < tail) {
        const uint32_t v = queue[head++];
        for (uint32_t i = start[v]; i < start[v + 1]; ++i)
            if (!seen[nbr[i]]) {
                seen[nbr[i]] = 1;
                queue[tail++] = nbr[i];
            }
    }
    for (size_t v = m->nv; v-- > s->n_samples;)
        if (!seen[v]) {
            ++lost;
            first = v;
        }
    if (lost > 0) {
        const double *p = m->pos + 3 * first;
        st = relief_fail(err, RELIEF_E_MESH,
                         "%zu of %zu targets can never be reached: no path in the "
                         "triangulation joins them to the capture (target %zu at (%.6g, "
                         "%.6g, %.6g) is one); is the extent far from the capture?",
                         lost, s->n_targets, first, p[0], p[1], p[2]);
    }
done:
    free(seen);
    free(queue);
    free(nbr);
    free(start);
    return st;
}

/* A target's window reaches about window x spacing from it; mapped around
 * a sample, its neighbours land on samples only where the nearest target
 * is half a spacing farther still. */
static relief_status check_window(const relief_surface *s, int window, relief_error *err)
{
    const size_t ns = s->n_samples, nt = s->n_targets;
    struct FLANNParameters fp = relief_knn_exact_params();
    flann_index_t index = NULL;
    float speedup;
    double far = 0.0;
    size_t best = 0;
    int fits;

    if (ns == 0 || nt == 0)
        return RELIEF_OK;
    index = flann_build_index_double(s->proj + 3 * ns, (int)nt, 3, &speedup, &fp);
    if (!index)
        return relief_fail(err, RELIEF_E_INTERNAL, "FLANN could not build a kd-tree");
    for (size_t v = 0; v < ns; ++v) {
        int idx;
        double d2;
        if (flann_find_nearest_neighbors_index_double(index, s->proj + 3 * v, 1, &idx, &d2, 1,
                                                      &fp) != 0)
            continue;
        if (d2 > far) {
            far = d2;
            best = v;
        }
    }
    flann_free_index_double(index, &fp);
    far = sqrt(far);
    fits = (int)fmin(floor(far / s->spacing - 0.5), 1e6);
    if (fits < 1)
        return relief_fail(err, RELIEF_E_MESH,
                           "no sample has a complete neighbourhood: every sample lies within "
                           "1.5 target spacings (%.4g) of a target, the farthest %.4g (sample "
                           "%zu); the capture is too small or too thin to grow from",
                           1.5 * s->spacing, far, best);
    if (fits < window)
        return relief_fail(err, RELIEF_E_MESH,
                           "the capture is smaller than the window: a window of %d needs a "
                           "sample %.4g from the missing part, but none is farther than %.4g "
                           "(sample %zu); use a window of %d or less",
                           window, (window + 0.5) * s->spacing, far, best, fits);
    return RELIEF_OK;
}

relief_status relief_surface_check_growth(const relief_surface *s, int window,
                                          relief_error *err)
{
    relief_status st = check_reachable(s, err);
    if (st == RELIEF_OK)
        st = check_window(s, window, err);
    return st;
}
