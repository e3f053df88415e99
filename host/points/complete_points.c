/* The point-set completion pipeline of paper 002 (complete_points.h). */
#include "points/complete_points.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/clock.h"
#include "base/error.h"
#include "base/linalg.h"
#include "base/parallel.h"
#include "base/pool.h"
#include "base/vec3.h"
#include "mesh/hole_fill.h"
#include "mesh/mesh.h"
#include "mesh/untangle.h"
#include "mesh/weld.h"
#include "points/analysis.h"
#include "points/flow.h"
#include "points/patch_mesh.h"
#include "points/surface_mesh.h"

relief_points_params relief_points_params_default(void)
{
    relief_points_params p;
    memset(&p, 0, sizeof p);
    p.what = RELIEF_POINTS_ALL;
    p.k = 16;
    p.smooth_steps = 20;
    p.smooth_dt = 10.0;
    p.max_detail = 1.0;
    p.rim_gap = 1.5707963267948966;
    p.band = 2.0;
    p.seam_band = 3.0;
    p.detail_histogram = 1;
    p.tex = relief_texopt_params_default();
    p.rbf = relief_rbf_params_default();
    return p;
}

void relief_points_report_free(relief_points_report *r)
{
    relief_hole_info_free(&r->holes);
    relief_texopt_result_free(&r->tex);
    free(r->base);
    free(r->base_nrm);
    r->base = r->base_nrm = NULL;
}

/* The host threads every stage runs on: p->threads, or for 0 the CPUs
 * this thread may run on (its affinity). */
static int threads_of(const relief_points_params *p)
{
    return p->threads > 0 ? p->threads : relief_pool_default_threads();
}

static relief_status check_params(const relief_points_params *p, relief_error *err)
{
    if (p->k < 6 || p->k > 64)
        return relief_fail(err, RELIEF_E_RANGE, "k %d out of range: expected 6..64", p->k);
    if (!(p->max_hole >= 0.0 && p->max_hole <= 1e30))
        return relief_fail(err, RELIEF_E_RANGE, "max_hole %g out of range: expected 0..1e30 "
                           "(0: a quarter of the bounding box's diagonal)", p->max_hole);
    if (p->smooth_steps < 0 || p->smooth_steps > 10000)
        return relief_fail(err, RELIEF_E_RANGE, "smooth_steps %d out of range: expected "
                           "0..10000", p->smooth_steps);
    if (!(p->smooth_dt > 0.0 && p->smooth_dt <= 100.0))
        return relief_fail(err, RELIEF_E_RANGE, "smooth_dt %g spacings out of range: expected "
                           "(0, 100]", p->smooth_dt);
    if (!(p->max_detail >= 0.0 && p->max_detail <= 100.0))
        return relief_fail(err, RELIEF_E_RANGE, "max_detail %g spacings out of range: expected "
                           "0..100", p->max_detail);
    if (!(p->rim_gap > 0.0 && p->rim_gap < 6.283185307179586))
        return relief_fail(err, RELIEF_E_RANGE, "rim_gap %g rad out of range: expected "
                           "(0, 2 pi)", p->rim_gap);
    if (p->threads < 0 || p->threads > RELIEF_PARALLEL_MAX_THREADS)
        return relief_fail(err, RELIEF_E_RANGE, "threads %d out of range: expected 0..%d (0: "
                           "the CPUs this thread may run on)", p->threads,
                           RELIEF_PARALLEL_MAX_THREADS);
    if (!(p->band >= 0.0 && p->band <= 1e6) || !(p->seam_band >= 0.0 && p->seam_band <= 1e6))
        return relief_fail(err, RELIEF_E_RANGE, "band %g or seam_band %g spacings out of range: "
                           "expected 0..1e6", p->band, p->seam_band);
    return RELIEF_OK;
}

/* Covariance normals of m's points over g, oriented by m's own normals,
 * else by its triangles' (area-weighted vertex normals), else by a
 * viewpoint or Hoppe's tree (relief_points_normals). nrm: nv x 3. */
static relief_status oriented_normals(const relief_mesh *m, const relief_knn_graph *g,
                                      const double *viewpoint, int threads, double *nrm,
                                      relief_error *err)
{
    double *hint = NULL;
    relief_status st;
    if (m->nrm || m->nt) {
        hint = malloc(m->nv * 3 * sizeof *hint);
        if (!hint)
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the normals of %zu points",
                               m->nv);
        if (m->nrm)
            memcpy(hint, m->nrm, m->nv * 3 * sizeof *hint);
        else
            relief_mesh_vertex_normals(m, hint);
    }
    st = relief_points_normals(m->pos, g, hint, viewpoint, threads, nrm, NULL, err);
    free(hint);
    return st;
}

/* One run: what it was given, what the stages found, and every buffer,
 * freed in one place. */
typedef struct work {
    const relief_mesh *in;
    const relief_points_params *p;
    relief_points_report *rep;
    size_t n, m, N, nc, T;   /* input, new, both, clone, all the texture's points */
    int channels, detail_ch, colour_ch, want_colour, want_geometry;
    double t0, t, spacing, scale;
    relief_knn_graph g;
    double *nrm, *base, *base_nrm, *rim_dist, *tpos, *tnrm, *npos, *nnrm;
    double *cbase, *cnrm; /* the clone's base and normals */
    float *detail, *value, *cdetail;
    double *low;          /* a mesh's patches: the detail's smooth part, N (fill_mesh_holes) */
    uint32_t *rim, *nhole, *near_rim;
    uint8_t *unknown, *exemplar, *rim_term;
    relief_rbf *rbf;
    uint32_t *ptri;       /* a mesh's hole patches (mesh/hole_fill.h): pnt x 3 */
    size_t pnt;
} work;

static void work_free(work *w)
{
    relief_knn_graph_free(&w->g);
    free(w->nrm), free(w->base), free(w->base_nrm), free(w->rim_dist);
    free(w->tpos), free(w->tnrm), free(w->npos), free(w->nnrm);
    free(w->detail), free(w->value), free(w->low);
    free(w->cbase), free(w->cnrm), free(w->cdetail);
    free(w->rim), free(w->nhole), free(w->near_rim);
    free(w->unknown), free(w->exemplar), free(w->rim_term);
    relief_rbf_free(w->rbf);
    free(w->ptri);
}

static relief_status nomem(const work *w, relief_error *err)
{
    return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the completion of %zu points",
                       w->n);
}

static relief_status cancelled(const relief_progress *pr, relief_error *err)
{
    return relief_fail(err, RELIEF_E_CANCELLED, "cancelled by the progress callback at %.0f %%",
                       100.0 * pr->last);
}

/* The call's progress enters the stage [lo, hi]; RELIEF_E_CANCELLED when
 * the caller asked, now or before. The shares follow the stages' times on
 * the fertility cut at 10 iterations: the texture takes most. */
static relief_status enter_stage(const work *w, double lo, double hi, relief_error *err)
{
    relief_progress *pr = w->p->progress;
    if (!pr)
        return RELIEF_OK;
    relief_progress_stage(pr, lo, hi);
    return relief_progress_step(pr, 0.0) ? cancelled(pr, err) : RELIEF_OK;
}

/* Section 6.1's seam: a new point within d of the rim takes its base normal
 * turned toward the nearest rim point's detail direction, weight (d - s)/d. */
static void place_new_points(const double *pos, const work *w, size_t n, size_t m, double d,
                             double scale, int detail_ch, int channels, double *out)
{
    for (size_t j = 0; j < m; ++j) {
        const double *q = w->npos + 3 * j;
        double nb[3], c = detail_ch >= 0 ? (double)w->value[(n + j) * channels + detail_ch] * scale
                                         : 0.0;
        if (w->low) /* the smooth part, always: the base is the patch less it */
            c += w->low[n + j];
        memcpy(nb, w->nnrm + 3 * j, sizeof nb);
        if (d > 0.0 && w->near_rim[j] != UINT32_MAX && w->rim_dist[n + j] < d) {
            size_t r = w->near_rim[j];
            double delta[3], len, wt = (d - w->rim_dist[n + j]) / d;
            sub3(pos + 3 * r, w->base + 3 * r, delta);
            len = sqrt(dot3(delta, delta));
            if (len > 0.0) {
                /* delta points along the rim's detail; its sign is c's. */
                double sgn = dot3(delta, w->base_nrm + 3 * r) >= 0.0 ? 1.0 : -1.0;
                for (int e = 0; e < 3; ++e)
                    nb[e] += wt * (sgn * delta[e] / len - w->base_nrm[3 * r + e]);
                if (relief_normalize3(nb) == 0.0)
                    memcpy(nb, w->nnrm + 3 * j, sizeof nb);
            }
        }
        for (int e = 0; e < 3; ++e)
            out[3 * j + e] = q[e] + c * nb[e];
    }
}

/* The relief of point i over a quadric height field z = a u^2 + b uv +
 * c v^2 + d u + e v + f fitted by least squares to it and its k
 * neighbours in g, in the frame of its normal nrm: -f, its height over
 * the fit (0 when the fit is singular). */
static double quadric_relief(const double *pos, const double *nrm, const relief_knn_graph *g,
                             size_t i)
{
    double u[3], v[3], A[36] = {0}, B[6] = {0}, x[6];
    const double *p = pos + 3 * i, *nn = nrm + 3 * i;
    relief_perp_basis(nn, u, v);
    for (int j = -1; j < g->k; ++j) {
        const double *q = j < 0 ? p : pos + 3 * (size_t)g->nbr[i * (size_t)g->k + (size_t)j];
        double d[3], a, b, z, row[6];
        sub3(q, p, d);
        a = dot3(d, u), b = dot3(d, v), z = dot3(d, nn);
        row[0] = a * a, row[1] = a * b, row[2] = b * b, row[3] = a, row[4] = b, row[5] = 1.0;
        for (int r = 0; r < 6; ++r) {
            for (int c = 0; c < 6; ++c)
                A[6 * r + c] += row[r] * row[c];
            B[r] += row[r] * z;
        }
    }
    return relief_solve_dense(6, A, B, x) ? -x[5] : 0.0;
}

/* The detail's own relief, high (n): each point's height over a quadric
 * fitted to its neighbourhood (quadric_relief). Not c' less a smoothed
 * c', nor the height over the neighbours' mean: on the statue's knee both
 * were mostly the surface's bend at the neighbourhood's scale and the
 * flow's base's roughness where max_detail cut it back point by point
 * (RMS 0.6 and 0.8 there against the truth's roughness of 0.08), which
 * the synthesis then laid on a smooth patch as noise. */
static void detail_high(const double *pos, const double *nrm, const relief_knn_graph *g,
                        double *high)
{
    for (size_t i = 0; i < g->n; ++i)
        high[i] = quadric_relief(pos, nrm, g, i);
}

/* The clone's base and detail (6.3): the same analysis and flow as the
 * input's, in the clone's own spacing. base, nrm: nc x 3, detail: nc
 * (malloc'ed; freed by the caller also on failure). */
static relief_status clone_detail(const relief_mesh *c, const relief_points_params *p,
                                  int high_pass, double **base, double **nrm, float **detail,
                                  relief_error *err)
{
    relief_knn_graph g;
    double *n0 = NULL, h;
    relief_status st;
    const char *why;
    size_t nc = c->nv;
    *base = *nrm = NULL;
    *detail = NULL;
    if (nc < (size_t)p->k + 1 || !relief_points_spread(c->pos, nc, &why))
        return relief_fail(err, RELIEF_E_RANGE, "clone: %zu points, too few or on a "
                           "line: no detail to copy", nc);
    st = relief_knn_graph_build(c->pos, nc, p->k, threads_of(p), &g, err);
    if (st != RELIEF_OK)
        return st;
    h = relief_knn_spacing(&g);
    n0 = malloc(nc * 3 * sizeof *n0);
    *base = malloc(nc * 3 * sizeof **base);
    *nrm = malloc(nc * 3 * sizeof **nrm);
    *detail = malloc(nc * sizeof **detail);
    if (!n0 || !*base || !*nrm || !*detail) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the clone's %zu points", nc);
        goto done;
    }
    st = oriented_normals(c, &g, NULL, threads_of(p), n0, err);
    if (st == RELIEF_OK && !(h > 0.0))
        st = relief_fail(err, RELIEF_E_RANGE, "clone: most points are duplicates");
    if (st == RELIEF_OK)
        st = relief_curvature_flow(c->pos, n0, &g, p->smooth_steps, p->smooth_dt * h,
                                   p->max_detail * h, threads_of(p), *base, *nrm, err);
    if (st == RELIEF_OK)
        relief_detail_encode(c->pos, *base, *nrm, nc, *detail);
    if (st == RELIEF_OK && high_pass) { /* as the input's (texture_values) */
        double *high = malloc(nc * sizeof *high);
        if (!high) {
            st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the clone's %zu points", nc);
            goto done;
        }
        detail_high(c->pos, n0, &g, high);
        for (size_t i = 0; i < nc; ++i)
            (*detail)[i] = (float)high[i];
        free(high);
    }
done:
    relief_knn_graph_free(&g);
    free(n0);
    return st;
}

/* The parameters and the input, before anything is allocated. */
static relief_status check_input(work *w, relief_error *err)
{
    const relief_mesh *in = w->in;
    const relief_points_params *p = w->p;
    const char *why;
    size_t masked = 0;
    relief_status st = check_params(p, err);
    if (st != RELIEF_OK)
        return st;
    w->want_geometry = p->what != RELIEF_POINTS_COLOUR_ONLY;
    w->want_colour = in->col && p->what != RELIEF_POINTS_GEOMETRY_ONLY && !p->smooth_only;
    if (p->smooth_only && p->what == RELIEF_POINTS_COLOUR_ONLY)
        return relief_fail(err, RELIEF_E_RANGE, "smooth_only fills geometry: not with what "
                           "colour");
    if (p->what == RELIEF_POINTS_COLOUR_ONLY && !in->col)
        return relief_fail(err, RELIEF_E_RANGE, "what colour: the input has no colour");
    if (w->n < (size_t)p->k + 1)
        return relief_fail(err, RELIEF_E_RANGE, "%zu points are too few: the local analysis "
                           "needs more than k = %d", w->n, p->k);
    if (!relief_points_spread(in->pos, w->n, &why))
        return relief_fail(err, RELIEF_E_RANGE, "no base surface can be built: %s", why);
    for (size_t i = 0; p->hole_mask && i < w->n; ++i)
        masked += p->hole_mask[i] != 0;
    w->rep->n_in = w->n;
    w->rep->n_masked = masked;
    return RELIEF_OK;
}

/* 1. Local analysis: the k-NN graph, the spacing, oriented normals, and
 * the holes' rims. */
static relief_status stage_analysis(work *w, relief_error *err)
{
    const relief_mesh *in = w->in;
    const relief_points_params *p = w->p;
    relief_points_report *rep = w->rep;
    size_t n = w->n;
    relief_status st = relief_knn_graph_build(in->pos, n, p->k, threads_of(p), &w->g, err);
    if (st != RELIEF_OK)
        return st;
    w->spacing = relief_knn_spacing(&w->g);
    if (!(w->spacing > 0.0))
        return relief_fail(err, RELIEF_E_RANGE, "the median distance between neighbours is 0: "
                           "more than half of the points are duplicates");
    rep->spacing = w->spacing;
    w->nrm = malloc(n * 3 * sizeof *w->nrm);
    w->rim = calloc(n, sizeof *w->rim);
    if (!w->nrm || !w->rim)
        return nomem(w, err);
    st = oriented_normals(in, &w->g, p->viewpoint, threads_of(p), w->nrm, err);
    if (st != RELIEF_OK)
        return st;
    if (w->want_geometry) {
        relief_hole_rule rule = {relief_hole_size_limit(in->pos, n, p->max_hole),
                                 p->hole_mask ? p->hole_mask : p->hole_select};
        st = in->nt ? relief_holes_mesh(in->pos, n, in->tri, in->nt, &rule, w->rim,
                                        &rep->holes, err)
                    : relief_holes_points(in->pos, w->nrm, &w->g, p->rim_gap, &rule,
                                          threads_of(p), w->rim, &rep->holes, err);
        if (st != RELIEF_OK)
            return st;
    }
    if (p->what == RELIEF_POINTS_COLOUR_ONLY && !rep->n_masked)
        return relief_fail(err, RELIEF_E_RANGE, "nothing to fill: what colour completes the "
                           "colour of the hole mask's points, and none is marked");
    if (!rep->holes.n_holes && !rep->n_masked)
        return relief_holes_none_filled(&rep->holes, err);
    w->t = relief_seconds();
    rep->t_analysis = w->t - w->t0;
    return RELIEF_OK;
}

/* 2. Base and detail: the curvature flow's base, the detail over it. */
static relief_status stage_base(work *w, relief_error *err)
{
    const relief_points_params *p = w->p;
    relief_points_report *rep = w->rep;
    size_t n = w->n;
    double s2 = 0.0;
    w->base = malloc(n * 3 * sizeof *w->base);
    w->base_nrm = malloc(n * 3 * sizeof *w->base_nrm);
    w->detail = malloc(n * sizeof *w->detail);
    if (!w->base || !w->base_nrm || !w->detail)
        return nomem(w, err);
    if (w->want_geometry) {
        relief_status st = relief_curvature_flow(w->in->pos, w->nrm, &w->g, p->smooth_steps,
                                                 p->smooth_dt * w->spacing,
                                                 p->max_detail * w->spacing, threads_of(p),
                                                 w->base, w->base_nrm, err);
        if (st != RELIEF_OK)
            return st;
    } else {
        memcpy(w->base, w->in->pos, n * 3 * sizeof *w->base);
        memcpy(w->base_nrm, w->nrm, n * 3 * sizeof *w->base_nrm);
    }
    rep->recon_rms = relief_detail_encode(w->in->pos, w->base, w->base_nrm, n, w->detail);
    for (size_t i = 0; i < n; ++i)
        s2 += (double)w->detail[i] * w->detail[i];
    rep->detail_rms = sqrt(s2 / (double)n);
    rep->t_base = relief_seconds() - w->t;
    w->t = relief_seconds();
    return RELIEF_OK;
}

/* 3. The base's holes filled by the RBF, new base points laid on it. */
/* The detail's smooth part carried over a mesh's patches (hp, in the
 * input's indices) from the rims' (low[0..n)) into low[n..n + nv_new):
 * harmonically, each new vertex the mean of its neighbours', by
 * Gauss-Seidel sweeps in index order until no value moves by more than
 * 1e-4 of the detail's RMS (at most 20 000). */
static relief_status patch_detail(const work *w, const relief_hole_patches *hp, double *low,
                                  relief_error *err)
{
    const size_t n = w->n;
    relief_mesh pm = {0};
    relief_adjacency adj;
    relief_status st;
    double tol = 1e-4 * w->rep->detail_rms;
    pm.nv = n + hp->nv_new, pm.nt = hp->nt_new, pm.tri = hp->tri;
    st = relief_mesh_adjacency(&pm, &adj, err);
    if (st != RELIEF_OK)
        return st;
    for (size_t i = n; i < pm.nv; ++i)
        low[i] = 0.0;
    for (int sweep = 0; sweep < 20000; ++sweep) {
        double moved = 0.0;
        for (size_t i = n; i < pm.nv; ++i) {
            double sum = 0.0, v;
            uint32_t a = adj.start[i], b = adj.start[i + 1];
            for (uint32_t j = a; j < b; ++j)
                sum += low[adj.nbr[j]];
            v = b > a ? sum / (double)(b - a) : 0.0;
            moved = fmax(moved, fabs(v - low[i]));
            low[i] = v;
        }
        if (!(moved > tol))
            break;
    }
    relief_adjacency_free(&adj);
    return RELIEF_OK;
}

/* A mesh's holes closed (mesh/hole_fill.h) on the capture itself, as
 * CGAL's fairing does, so that the patch continues the captured rim's
 * position and tangent plane: faired on the base (smoothed, shrunk into a
 * convex part by up to max_detail), its rim stood a step below the
 * captured one and the fill sank (issue 61: the knee's p95 1.3 h even
 * with no detail). The new points' base is the patch less the detail's
 * smooth part (patch_detail) along its normals, so that base plus the
 * synthesised detail lands on the patch where the detail is the rim's.
 * The patches' vertices are the new points, their triangles kept for the
 * result (5b), closed and edge to edge with the rims, where a patch of
 * the RBF's points triangulated afterwards left cracks. */
static relief_status fill_mesh_holes(work *w, size_t max_new, relief_error *err)
{
    const relief_mesh *in = w->in;
    relief_hole_fill_options o;
    relief_hole_patches hp;
    relief_mesh bm = {0};
    double *vn = NULL;
    relief_status st;
    relief_hole_fill_options_default(&o);
    o.max_new = max_new;
    st = relief_fill_rims(in->pos, w->n, in->tri, in->nt, w->rim, &o, &hp, err);
    if (st != RELIEF_OK)
        return st;
    w->rep->patch_skipped = hp.skipped;
    bm.nv = w->n + hp.nv_new, bm.nt = in->nt + hp.nt_new;
    bm.pos = malloc(bm.nv * 3 * sizeof *bm.pos + 1);
    bm.tri = malloc(bm.nt * 3 * sizeof *bm.tri + 1);
    vn = malloc(bm.nv * 3 * sizeof *vn + 1);
    w->nnrm = malloc(hp.nv_new * 3 * sizeof *w->nnrm + 1);
    if (!bm.pos || !bm.tri || !vn || !w->nnrm) {
        st = nomem(w, err);
        goto done;
    }
    memcpy(bm.pos, in->pos, w->n * 3 * sizeof *bm.pos);
    if (hp.nv_new) /* NULL when no patch added a vertex */
        memcpy(bm.pos + 3 * w->n, hp.pos, hp.nv_new * 3 * sizeof *bm.pos);
    memcpy(bm.tri, in->tri, in->nt * 3 * sizeof *bm.tri);
    if (hp.nt_new)
        memcpy(bm.tri + 3 * in->nt, hp.tri, hp.nt_new * 3 * sizeof *bm.tri);
    relief_mesh_vertex_normals(&bm, vn);
    for (size_t i = 0; i < hp.nv_new; ++i) {
        const double *v = vn + 3 * (w->n + i);
        double len = sqrt(dot3(v, v));
        for (int e = 0; e < 3; ++e)
            w->nnrm[3 * i + e] = len > 0.0 ? v[e] / len : 0.0;
    }
    w->low = malloc(bm.nv * sizeof *w->low);
    if (!w->low) {
        st = nomem(w, err);
        goto done;
    }
    detail_high(in->pos, w->nrm, &w->g, w->low);
    for (size_t i = 0; i < w->n; ++i) /* the smooth part: c' less the relief */
        w->low[i] = (double)w->detail[i] - w->low[i];
    st = patch_detail(w, &hp, w->low, err);
    if (st != RELIEF_OK)
        goto done;
    for (size_t i = 0; i < hp.nv_new; ++i)
        for (int e = 0; e < 3; ++e)
            hp.pos[3 * i + e] -= w->low[w->n + i] * w->nnrm[3 * i + e];
    w->m = hp.nv_new;
    w->npos = hp.pos, w->nhole = hp.hole, w->ptri = hp.tri, w->pnt = hp.nt_new;
    hp.pos = NULL, hp.hole = NULL, hp.tri = NULL;
done:
    relief_hole_patches_free(&hp);
    free(bm.pos), free(bm.tri), free(vn);
    return st;
}

static relief_status stage_fill(work *w, relief_error *err)
{
    const relief_points_params *p = w->p;
    relief_points_report *rep = w->rep;
    if (w->want_geometry && rep->holes.n_holes && w->in->nt &&
        p->mesh_patch == RELIEF_MESH_PATCH_FAIR) {
        relief_status st = fill_mesh_holes(w, p->max_new ? p->max_new : 4 * w->n, err);
        if (st != RELIEF_OK)
            return st;
    } else if (w->want_geometry && rep->holes.n_holes) {
        relief_rbf_params rp = p->rbf;
        rp.threads = threads_of(p);
        size_t max_new = p->max_new ? p->max_new : 4 * w->n;
        relief_status st;
        if (!(rp.spacing > 0.0))
            rp.spacing = w->spacing;
        st = relief_rbf_fit(w->base, w->base_nrm, w->n, &rp, &w->rbf, err);
        if (st != RELIEF_OK)
            return st;
        st = relief_rbf_fill_holes(w->rbf, w->base, w->base_nrm, w->n, w->rim,
                                   rep->holes.n_holes, w->spacing, max_new, &w->npos, &w->nnrm,
                                   &w->nhole, &w->m, err);
        if (st != RELIEF_OK)
            return st;
    }
    w->N = w->n + w->m;
    rep->n_added = w->m;
    rep->t_fill = relief_seconds() - w->t;
    w->t = relief_seconds();
    return RELIEF_OK;
}

static double detail_rms(const float *c, size_t n)
{
    double s2 = 0.0;
    for (size_t i = 0; i < n; ++i)
        s2 += (double)c[i] * c[i];
    return n ? sqrt(s2 / (double)n) : 0.0;
}

/* 4a. The texture's channels: c' (scaled to colour's range) and colour,
 * on the base's points and the new ones; a clone's (6.3) after them. */
static relief_status texture_values(work *w, relief_error *err)
{
    const relief_mesh *in = w->in;
    const relief_points_params *p = w->p;
    size_t n = w->n, m = w->m, N = w->N, T;
    if (p->clone && !p->smooth_only) {
        relief_status st = clone_detail(p->clone, p, w->low != NULL, &w->cbase, &w->cnrm,
                                        &w->cdetail, err);
        if (st != RELIEF_OK)
            return st;
        w->nc = p->clone->nv;
        w->rep->n_clone = w->nc;
        w->want_colour = w->want_colour && p->clone->col; /* else colour from the rim */
    }
    T = w->T = N + w->nc;
    if (w->want_geometry && !p->smooth_only)
        w->detail_ch = w->channels++;
    if (w->want_colour)
        w->colour_ch = w->channels, w->channels += 3;
    w->rep->tex_channels = w->channels;
    w->tpos = malloc(T * 3 * sizeof *w->tpos);
    w->tnrm = malloc(T * 3 * sizeof *w->tnrm);
    w->value = malloc(T * (size_t)w->channels * sizeof *w->value + 1);
    w->unknown = calloc(T, 1);
    w->exemplar = calloc(T, 1);
    w->rim_term = calloc(T, 1);
    w->rim_dist = malloc(N * sizeof *w->rim_dist);
    w->near_rim = malloc((m + 1) * sizeof *w->near_rim);
    if (!w->tpos || !w->tnrm || !w->value || !w->unknown || !w->exemplar || !w->rim_term ||
        !w->rim_dist || !w->near_rim)
        return nomem(w, err);
    memcpy(w->tpos, w->base, n * 3 * sizeof *w->tpos);
    memcpy(w->tnrm, w->base_nrm, n * 3 * sizeof *w->tnrm);
    if (m) {
        memcpy(w->tpos + 3 * n, w->npos, m * 3 * sizeof *w->tpos);
        memcpy(w->tnrm + 3 * n, w->nnrm, m * 3 * sizeof *w->tnrm);
    }
    /* The detail synthesised: c', or over a mesh's patches c' less its
     * smooth part (w->low), in units of 4 x its RMS, so that it weighs in
     * the matching about as a colour channel in [0, 1] does. */
    if (w->low)
        for (size_t i = 0; i < n; ++i)
            w->detail[i] = (float)(w->detail[i] - w->low[i]);
    w->scale = 4.0 * detail_rms(w->detail, n);
    if (!(w->scale > 0.0))
        w->scale = 1.0;
    for (size_t i = 0; i < N; ++i) {
        int is_new = i >= n, ch = w->channels;
        for (int c = 0; c < ch; ++c)
            w->value[i * ch + c] = 0.0f;
        if (!is_new) {
            if (w->detail_ch >= 0)
                w->value[i * ch + w->detail_ch] = (float)(w->detail[i] / w->scale);
            if (w->colour_ch >= 0)
                for (int c = 0; c < 3; ++c)
                    w->value[i * ch + w->colour_ch + c] = in->col[3 * i + c];
        }
        w->unknown[i] = is_new || (p->hole_mask && p->hole_mask[i]);
    }
    return RELIEF_OK;
}

/* 4b. Which points are exemplars and which the rim term holds: the known
 * ones outside the band (and the sample mask), the clone's alone when
 * there is one. */
static relief_status texture_exemplars(work *w, relief_error *err)
{
    const relief_points_params *p = w->p;
    size_t n = w->n, N = w->N, nc = w->nc;
    int ch = w->channels;
    /* The input's points here; the new ones' distances (and nearest rim
     * points) are over the base, below. */
    relief_status st = relief_rim_distance(w->in->pos, n, w->rim, w->tpos, n, w->rim_dist, NULL,
                                           err);
    if (st != RELIEF_OK)
        return st;
    if (w->m) {
        st = relief_rim_distance(w->base, n, w->rim, w->npos, w->m, w->rim_dist + n, w->near_rim,
                                 err);
        if (st != RELIEF_OK)
            return st;
    }
    for (size_t i = 0; i < n; ++i) {
        w->exemplar[i] = !w->unknown[i] && !(w->rim_dist[i] <= p->band * w->spacing) &&
                         (!p->sample_mask || p->sample_mask[i]);
        w->rim_term[i] = !w->unknown[i] && w->rim_dist[i] <= p->band * w->spacing;
    }
    if (nc) {
        /* The clone sits 100 spacings past the input's bounding box in x,
         * so that no cluster holds both. */
        double in_max = -INFINITY, cl_min = INFINITY, shift;
        for (size_t i = 0; i < N; ++i)
            in_max = fmax(in_max, w->tpos[3 * i]);
        for (size_t i = 0; i < nc; ++i)
            cl_min = fmin(cl_min, w->cbase[3 * i]);
        shift = in_max - cl_min + 100.0 * w->spacing;
        for (size_t i = 0; i < n; ++i)
            w->exemplar[i] = 0;
        for (size_t j = 0; j < nc; ++j) {
            size_t i = N + j;
            memcpy(w->tpos + 3 * i, w->cbase + 3 * j, 3 * sizeof *w->tpos);
            w->tpos[3 * i] += shift;
            memcpy(w->tnrm + 3 * i, w->cnrm + 3 * j, 3 * sizeof *w->tnrm);
            if (w->detail_ch >= 0)
                w->value[i * ch + w->detail_ch] = (float)(w->cdetail[j] / w->scale);
            if (w->colour_ch >= 0)
                for (int c = 0; c < 3; ++c)
                    w->value[i * ch + w->colour_ch + c] = p->clone->col[3 * j + c];
            w->exemplar[i] = 1;
        }
    }
    return RELIEF_OK;
}

/* 4c. The texture optimisation over all of it. */
static relief_status texture_run(work *w, relief_error *err)
{
    const relief_points_params *p = w->p;
    relief_texopt_params tex = p->tex;
    tex.threads = threads_of(p);
    size_t n_ex = 0, n_unk = 0, nc = w->nc;
    relief_status st;
    if (!w->channels)
        return RELIEF_OK;
    for (size_t i = 0; i < w->T; ++i)
        n_ex += w->exemplar[i] != 0, n_unk += w->unknown[i] != 0;
    /* A fill larger than what it is to look like would repeat the few
     * exemplars over it, not continue the surface: refused (no exemplar at
     * all: texopt says so). Not over a mesh's patches when the exemplars
     * are the whole capture outside the band: the patches continue the
     * surface themselves, and what is synthesised on them is the relief
     * alone, which may repeat (a band all round a cylinder, the capture
     * about it masked: 5862 points to synthesise from 3014). A sample
     * region or a clone the caller chose is still held to it. */
    if (n_ex > 0 && n_ex < n_unk && !(w->low && !nc && !p->sample_mask))
        return relief_fail(err, RELIEF_E_RANGE, "the holes are larger than the sample region: "
                           "%zu points to synthesise from %zu exemplar points%s; give a "
                           "larger %s", n_unk, n_ex,
                           nc ? " (the clone's)" : p->sample_mask ? " (the sample region)" :
                           " (the capture outside the rims' band)",
                           nc ? "clone" : p->sample_mask ? "sample region" :
                           "capture, or a smaller band");
    /* Over a mesh's patches the relief stays as the optimisation left it:
     * matched to the active clusters' (about 680 points each, most of
     * them farther from a small hole than its own size), it was stretched
     * 4 times on the statue's knee, where the capture about the hole is
     * smoother than the rest of the clusters (issue 61: the fill 3.5
     * times as rough as the truth, 1.4 without). */
    if (p->detail_histogram && w->detail_ch >= 0 && !w->low)
        tex.histogram |= 1u << w->detail_ch;
    tex.progress = p->progress;
    st = relief_texopt_complete(w->tpos, w->tnrm, w->T, w->channels, w->value, w->unknown,
                                w->exemplar, w->rim_term, &tex, &w->rep->tex, err);
    return st;
}

/* 5a. The result's points: the input's (a masked one at its base point
 * plus the synthesised detail), then the new ones placed at the seam;
 * labels, colours clamped to [0, 1], and normals over the new
 * neighbourhoods. */
static relief_status result_points(work *w, relief_mesh **out_mesh, relief_error *err)
{
    const relief_mesh *in = w->in;
    const relief_points_params *p = w->p;
    size_t n = w->n, m = w->m, N = w->N;
    int ch = w->channels, colour_ch = w->colour_ch, detail_ch = w->detail_ch;
    relief_knn_graph g2;
    relief_mesh *out;
    relief_status st = relief_mesh_create(N, 0, RELIEF_MESH_NORMALS | RELIEF_MESH_LABELS |
                                                    (in->col ? RELIEF_MESH_COLOURS : 0u),
                                          out_mesh, err);
    if (st != RELIEF_OK)
        return st;
    out = *out_mesh;
    memcpy(out->pos, in->pos, n * 3 * sizeof *out->pos);
    for (size_t i = 0; i < n; ++i)
        if (p->hole_mask && p->hole_mask[i] && detail_ch >= 0)
            for (int e = 0; e < 3; ++e)
                out->pos[3 * i + e] = w->base[3 * i + e] +
                                      ((double)w->value[i * ch + detail_ch] * w->scale +
                                       (w->low ? w->low[i] : 0.0)) * w->base_nrm[3 * i + e];
    place_new_points(in->pos, w, n, m, p->seam_band * w->spacing, w->scale, detail_ch, ch,
                     out->pos + 3 * n);
    for (size_t i = 0; i < N; ++i) {
        out->label[i] = i >= n ? RELIEF_LABEL_COMPLETED : RELIEF_LABEL_CAPTURED;
        if (!in->col)
            continue;
        for (int c = 0; c < 3; ++c) {
            float v;
            if (i < n && !(p->hole_mask && p->hole_mask[i] && colour_ch >= 0))
                v = in->col[3 * i + c];
            else if (colour_ch >= 0)
                v = w->value[i * ch + colour_ch + c];
            else /* geometry only: the nearest rim point's colour */
                v = in->col[3 * (size_t)w->near_rim[i - n] + c];
            out->col[3 * i + c] = v < 0.0f ? 0.0f : v > 1.0f ? 1.0f : v;
        }
    }
    if (p->no_normals) {
        free(out->nrm);
        out->nrm = NULL;
        out->attrs &= ~(unsigned)RELIEF_MESH_NORMALS;
        st = RELIEF_OK;
    } else {
        /* Each normal agreeing with the one it had. */
        st = relief_knn_graph_build(out->pos, N, p->k, threads_of(p), &g2, err);
        if (st != RELIEF_OK)
            return st;
        memcpy(w->tnrm, w->nrm, n * 3 * sizeof *w->tnrm);
        st = relief_points_normals(out->pos, &g2, w->tnrm, NULL, threads_of(p), out->nrm,
                                   NULL, err);
        relief_knn_graph_free(&g2);
    }
    if (st == RELIEF_OK && p->keep_base) {
        /* w->tnrm becomes the base's normals, handed to the report. */
        memcpy(w->tnrm, w->base_nrm, n * 3 * sizeof *w->tnrm);
        if (m)
            memcpy(w->tnrm + 3 * n, w->nnrm, m * 3 * sizeof *w->tnrm);
    }
    return st;
}

/* 5a'. A mesh's patches (fill_mesh_holes): the detail synthesised along
 * the base's normals can push a new point next to the rim through the
 * capture (issue 61); such points are drawn back toward the base
 * (mesh/untangle.h), with or without p->mesh, so that the points are the
 * same either way. */
static relief_status untangle(work *w, relief_mesh *out, relief_error *err)
{
    const relief_mesh *in = w->in;
    uint32_t *tri = malloc((in->nt + w->pnt) * 3 * sizeof *tri + 1);
    relief_status st;
    if (!tri)
        return nomem(w, err);
    memcpy(tri, in->tri, in->nt * 3 * sizeof *tri);
    memcpy(tri + 3 * in->nt, w->ptri, w->pnt * 3 * sizeof *tri);
    st = relief_untangle(out->pos, w->tpos, w->N, w->n, tri, in->nt + w->pnt,
                         &w->rep->untangled, &w->rep->crossing_left, err);
    free(tri);
    return st;
}

/* 5b. The result's triangles (p->mesh): a bare point set's surface through
 * all its points, or a mesh's own triangles and patches over its holes. */
static relief_status result_mesh(work *w, relief_mesh *out, relief_error *err)
{
    const relief_mesh *in = w->in;
    const relief_points_params *p = w->p;
    relief_points_report *rep = w->rep;
    uint32_t *pt = NULL;
    size_t pnt = 0;
    const double *mpos = out->pos, *mnrm = out->nrm;
    relief_status st;
    if (!in->nt) {
        relief_surface_mesh_info si;
        st = relief_points_surface_mesh(out->pos, out->nrm, w->N, w->spacing, p->k, &out->tri,
                                        &out->nt, &si, err);
        if (st != RELIEF_OK)
            return st;
        rep->mesh_of_points = 1;
        rep->mesh_candidates = si.candidates;
        rep->mesh_boundary_edges = si.boundary_edges;
        rep->mesh_bare_points = si.bare_points;
        return RELIEF_OK;
    }
    if (w->ptri) { /* the patches closed the holes (fill_mesh_holes) */
        pt = w->ptri, pnt = w->pnt;
        w->ptri = NULL;
    } else if (p->keep_base) {
        /* The caller grows detail on the base (base_surface.h): join the
         * holes where they lie on it. The captured rim stands off the bare
         * base by the detail, which can be wider than the patches reach
         * (fertility: detail RMS 1.7 spacings). */
        mpos = w->tpos, mnrm = w->tnrm;
    }
    if (!pt) {
        st = relief_points_patch_mesh(mpos, mnrm, w->n, w->N, w->rim, w->nhole,
                                      rep->holes.n_holes, w->spacing, in->tri, in->nt, &pt, &pnt,
                                      &rep->patch_skipped, err);
        if (st != RELIEF_OK)
            return st;
    }
    out->tri = malloc((in->nt + pnt) * 3 * sizeof *out->tri + 1);
    if (!out->tri) {
        free(pt);
        return nomem(w, err);
    }
    memcpy(out->tri, in->tri, in->nt * 3 * sizeof *out->tri);
    if (pnt)
        memcpy(out->tri + 3 * in->nt, pt, pnt * 3 * sizeof *out->tri);
    free(pt);
    out->nt = in->nt + pnt;
    /* An ear along a split bow-tie vertex joins its copies with a triangle
     * of no area: the vertex is one again where the patch closed its pinch
     * (the capture has no such triangle: only patch triangles are dropped). */
    st = relief_weld_copies(out->pos, w->N, out->tri, &out->nt, &rep->copies_welded, err);
    if (st != RELIEF_OK)
        return st;
    rep->patch_triangles = out->nt - in->nt;
    return relief_points_open_loops(out->tri, out->nt, w->N, w->n, w->rim, &rep->open_edges,
                                    &rep->open_loops, err);
}

/* The stages in order, each entering its share of the call's progress. */
static relief_status run_stages(work *w, relief_mesh **out, relief_error *err)
{
    relief_status st = check_input(w, err);
    if (st == RELIEF_OK)
        st = enter_stage(w, 0.0, 0.05, err);
    if (st == RELIEF_OK)
        st = stage_analysis(w, err);
    if (st == RELIEF_OK)
        st = enter_stage(w, 0.05, 0.15, err);
    if (st == RELIEF_OK)
        st = stage_base(w, err);
    if (st == RELIEF_OK)
        st = enter_stage(w, 0.15, 0.25, err);
    if (st == RELIEF_OK)
        st = stage_fill(w, err);
    if (st == RELIEF_OK)
        st = enter_stage(w, 0.25, 0.95, err);
    if (st == RELIEF_OK)
        st = texture_values(w, err);
    if (st == RELIEF_OK)
        st = texture_exemplars(w, err);
    if (st == RELIEF_OK)
        st = texture_run(w, err);
    if (st == RELIEF_OK) {
        w->rep->t_texture = relief_seconds() - w->t;
        st = enter_stage(w, 0.95, 1.0, err);
    }
    if (st == RELIEF_OK)
        st = result_points(w, out, err);
    if (st == RELIEF_OK && w->ptri)
        st = untangle(w, *out, err);
    if (st == RELIEF_OK && w->p->mesh)
        st = result_mesh(w, *out, err);
    if (st == RELIEF_OK && relief_progress_step(w->p->progress, 1.0))
        st = cancelled(w->p->progress, err);
    return st;
}

relief_status relief_points_complete(const relief_mesh *in, const relief_points_params *p,
                                     relief_mesh **out_mesh, relief_points_report *rep,
                                     relief_error *err)
{
    work w;
    relief_mesh *out = NULL;
    relief_status st;

    memset(&w, 0, sizeof w);
    memset(rep, 0, sizeof *rep);
    *out_mesh = NULL;
    w.in = in, w.p = p, w.rep = rep;
    w.n = in->nv;
    w.detail_ch = w.colour_ch = -1;
    w.scale = 1.0;
    w.t0 = relief_seconds();
    st = run_stages(&w, &out, err);
    if (st != RELIEF_OK) {
        relief_mesh_destroy(out);
        work_free(&w);
        relief_points_report_free(rep);
        return st;
    }
    rep->mesh_triangles = out->nt;
    if (p->keep_base) {
        rep->base = w.tpos, rep->base_nrm = w.tnrm;
        w.tpos = w.tnrm = NULL;
    }
    rep->t_total = relief_seconds() - w.t0;
    work_free(&w);
    *out_mesh = out;
    return RELIEF_OK;
}
