/* Smooth completion: the fitted primitive's "good continuation" of the
 * capture, as one labelled triangulation (stages 2 to 5 of DESIGN.md).
 *
 * Parameter domains. Plane: (u, v) along (e1, e2), e1 x e2 = the normal.
 * Cylinder: u = radius * angle in [0, 2 pi radius) around the axis from e1
 * toward e2 = axis x e1, v = coordinate along the axis; counter-clockwise
 * in (u, v) is outward. Sphere: unit directions from the centre.
 *
 * Targets are laid on a triangular lattice of edge `spacing` (plane,
 * cylinder) or a Fibonacci lattice of the same density (sphere) and kept
 * where the capture does not cover the primitive: a lattice point is
 * covered when it lies within half a spacing of a capture triangle
 * projected on the primitive. Of the uncovered points, the holes the
 * capture's outline encloses or all of them are kept (targets.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/compare.h"
#include "base/params.h"

#include "base/clock.h"
#include "base/error.h"
#include "base/memlimit.h"
#include "base/numtext.h"
#include "base/vec3.h"
#include "mesh/io_openmesh.h"
#include "mesh/mesh.h"
#include "smooth/delaunay.h"
#include "smooth/oversample.h"
#include "smooth/param.h"
#include "smooth/surface.h"
#include "smooth/surface_check.h"
#include "smooth/targets.h"

#define RM_REAL double
#include "kernels/relief_math.h"

relief_smooth_options relief_smooth_options_default(void)
{
    relief_smooth_options o;
    o.frames = RELIEF_FRAMES_PAPER;
    o.spacing_percentile = 10.0;
    o.oversample_scheme = RELIEF_OVERSAMPLE_BUTTERFLY;
    o.accept_poor_fit = 0;
    o.fill = RELIEF_FILL_AUTO;
    o.holes.keep = NULL;
    o.holes.keep_point = NULL;
    o.holes.ctx = NULL;
    o.holes.on_plane = 0;
    o.max_growth = RELIEF_MAX_GROWTH;
    o.spike_k = RELIEF_SPIKE_K;
    o.fitted = NULL;
    return o;
}

void relief_surface_destroy(relief_surface *s)
{
    if (!s)
        return;
    relief_mesh_destroy(s->mesh);
    free(s->proj);
    free(s->disp);
    free(s->nrm);
    free(s->frame);
    free(s);
}

/* The p-th percentile (0..100) of the mesh's edge lengths, each edge counted
 * once per triangle side (interior edges twice, which does not move a
 * percentile of a regular mesh). 0 when the mesh has no triangle. */
static double edge_percentile(const relief_mesh *m, double p)
{
    size_t n = 3 * m->nt, k = 0;
    double *len, r;
    if (n == 0)
        return 0.0;
    len = malloc(n * sizeof *len);
    if (!len)
        return 0.0;
    for (size_t t = 0; t < m->nt; ++t)
        for (int e = 0; e < 3; ++e) {
            const double *a = m->pos + 3 * (size_t)m->tri[3 * t + e];
            const double *b = m->pos + 3 * (size_t)m->tri[3 * t + (e + 1) % 3];
            double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
            double l = sqrt(rm_dot(d, d));
            if (l > 0.0)
                len[k++] = l;
        }
    if (k == 0) {
        free(len);
        return 0.0;
    }
    qsort(len, k, sizeof *len, relief_cmp_double);
    r = len[(size_t)floor(p / 100.0 * (double)(k - 1) + 0.5)];
    free(len);
    return r;
}

static void to_param(const relief_surface *s, const double p[3], double uv[2])
{
    relief_domain_coords(&s->param, p, uv);
}

/* ------------------------------------------------------- triangulation */

/* On the sphere: the convex hull of the vertices' directions from the
 * centre, less the faces wider than alpha (circumradius, input units).
 * *tri gets the hull's triangles (3 ids each), the first *kept of them
 * the ones kept; on a failure after the hull the caller frees *tri. */
static relief_status sphere_triangles(const relief_surface *s, double alpha, uint32_t **tri,
                                      size_t *kept, relief_error *err)
{
    const relief_fit_primitive *pr = &s->fit.prim;
    const relief_mesh *m = s->mesh;
    double *dir = malloc(m->nv * 3 * sizeof *dir);
    size_t nt = 0;
    relief_status st;

    if (!dir)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate directions");
    for (size_t v = 0; v < m->nv; ++v) {
        for (int k = 0; k < 3; ++k)
            dir[3 * v + k] = s->proj[3 * v + k] - pr->point[k];
        rm_normalise(dir + 3 * v);
    }
    st = relief_hull_sphere(dir, m->nv, tri, &nt, NULL, err);
    free(dir);
    /* The hull also closes whatever the completion leaves open (the
     * outside of a patch whose holes alone are filled) with faces
     * across the sphere: drop them as the plane drops its long ones. */
    for (size_t t = 0; st == RELIEF_OK && t < nt; ++t) {
        const double *a = s->proj + 3 * (size_t)(*tri)[3 * t];
        const double *b = s->proj + 3 * (size_t)(*tri)[3 * t + 1];
        const double *c = s->proj + 3 * (size_t)(*tri)[3 * t + 2];
        double ab[3], ac[3], bc[3], x[3], r;
        for (int k = 0; k < 3; ++k)
            ab[k] = b[k] - a[k], ac[k] = c[k] - a[k], bc[k] = c[k] - b[k];
        rm_cross(ab, ac, x);
        r = sqrt(rm_dot(ab, ab) * rm_dot(ac, ac) * rm_dot(bc, bc)) /
            (2.0 * sqrt(rm_dot(x, x)));
        if (!(r > alpha)) /* a degenerate triangle (r NaN) stays: not ours to judge */
            memmove(*tri + 3 * (*kept)++, *tri + 3 * t, 3 * sizeof **tri);
    }
    return st;
}

/* On the plane or the cylinder: the Delaunay triangulation of the
 * vertices' parameters (periodic on the cylinder, period 2 pi radius),
 * less the triangles wider than alpha. *tri and *kept as sphere_triangles. */
static relief_status param_triangles(const relief_surface *s, double alpha, uint32_t **tri,
                                     size_t *kept, relief_error *err)
{
    const relief_fit_primitive *pr = &s->fit.prim;
    const relief_mesh *m = s->mesh;
    double *uv = malloc(m->nv * 2 * sizeof *uv);
    size_t nt = 0;
    relief_status st;

    if (!uv)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate parameters");
    for (size_t v = 0; v < m->nv; ++v)
        to_param(s, s->proj + 3 * v, uv + 2 * v);
    if (pr->model == RELIEF_FIT_PLANE)
        st = relief_delaunay_2d(uv, m->nv, tri, &nt, NULL, err);
    else
        st = relief_delaunay_periodic(uv, m->nv, 2.0 * RELIEF_PI * pr->radius, tri, &nt, NULL,
                                      err);
    if (st == RELIEF_OK) {
        const double period = 2.0 * RELIEF_PI * pr->radius;
        for (size_t t = 0; t < nt; ++t) {
            double a[2], b[2], c[2];
            memcpy(a, uv + 2 * (*tri)[3 * t], sizeof a);
            memcpy(b, uv + 2 * (*tri)[3 * t + 1], sizeof b);
            memcpy(c, uv + 2 * (*tri)[3 * t + 2], sizeof c);
            if (pr->model == RELIEF_FIT_CYLINDER) { /* unwrap across the seam */
                if (b[0] - a[0] > period / 2) b[0] -= period;
                if (a[0] - b[0] > period / 2) b[0] += period;
                if (c[0] - a[0] > period / 2) c[0] -= period;
                if (a[0] - c[0] > period / 2) c[0] += period;
            }
            if (relief_circumradius_2d(a, b, c) <= alpha)
                memmove(*tri + 3 * (*kept)++, *tri + 3 * t, 3 * sizeof **tri);
        }
    }
    free(uv);
    return st;
}

/* Triangulate all vertices of s->mesh in the parameter domain (on the
 * sphere, their directions' convex hull) and keep the triangles no wider
 * than `alpha` (circumradius, input units), which drops the long triangles
 * Delaunay spans across concave parts of the outline. */
static relief_status triangulate(relief_surface *s, double alpha, relief_error *err)
{
    relief_mesh *m = s->mesh;
    uint32_t *tri = NULL;
    size_t kept = 0;
    relief_status st;

    if (s->fit.prim.model == RELIEF_FIT_SPHERE)
        st = sphere_triangles(s, alpha, &tri, &kept, err);
    else
        st = param_triangles(s, alpha, &tri, &kept, err);
    if (st != RELIEF_OK) {
        free(tri);
        return st;
    }
    free(m->tri);
    m->tri = tri;
    m->nt = kept;
    return RELIEF_OK;
}

/* Drop the vertices no triangle uses: points the triangulation merged with
 * a coincident one (real scans repeat points) or isolated by the width
 * filter. Keeps the order, and so samples before targets. */
static relief_status drop_unused(relief_surface *s, uint32_t *ids, relief_error *err)
{
    relief_mesh *m = s->mesh, *c = NULL;
    uint8_t *used = calloc(m->nv, 1);
    uint32_t *remap = malloc(m->nv * sizeof *remap);
    size_t n = 0, samples = 0;
    relief_status st = RELIEF_OK;
    if (!used || !remap) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a vertex map");
        goto done;
    }
    for (size_t i = 0; i < 3 * m->nt; ++i)
        used[m->tri[i]] = 1;
    for (size_t v = 0; v < m->nv; ++v)
        n += used[v];
    if (n == m->nv)
        goto done;
    st = relief_mesh_subset(m, used, &c, remap, err);
    if (st != RELIEF_OK)
        goto done;
    for (size_t v = 0; v < m->nv; ++v) {
        size_t w = remap[v];
        if (w == UINT32_MAX)
            continue;
        memmove(s->proj + 3 * w, s->proj + 3 * v, 3 * sizeof(double));
        memmove(s->disp + 3 * w, s->disp + 3 * v, 3 * sizeof(double));
        memmove(s->nrm + 3 * w, s->nrm + 3 * v, 3 * sizeof(double));
        memmove(s->frame + 9 * w, s->frame + 9 * v, 9 * sizeof(double));
        if (ids)
            ids[w] = ids[v];
        samples += v < s->n_samples;
    }
    s->n_dropped = m->nv - n;
    s->n_samples = samples;
    s->n_targets = n - samples;
    relief_mesh_destroy(m);
    s->mesh = c;
done:
    free(remap);
    free(used);
    return st;
}

/* Every edge in at most two triangles, opposite ways round. Names the
 * first offence. */
typedef struct dir_edge {
    uint32_t a, b;
} dir_edge;

static int dir_edge_cmp(const void *x, const void *y)
{
    const dir_edge *p = x, *q = y;
    if (p->a != q->a)
        return p->a < q->a ? -1 : 1;
    return (p->b > q->b) - (p->b < q->b);
}

static relief_status check_manifold(const relief_surface *s, relief_error *err)
{
    const relief_mesh *m = s->mesh;
    dir_edge *e = malloc((3 * m->nt + 1) * sizeof *e);
    relief_status st = RELIEF_OK;
    if (!e)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the edge list");
    for (size_t t = 0; t < m->nt; ++t)
        for (int k = 0; k < 3; ++k) {
            e[3 * t + k].a = m->tri[3 * t + k];
            e[3 * t + k].b = m->tri[3 * t + (k + 1) % 3];
        }
    qsort(e, 3 * m->nt, sizeof *e, dir_edge_cmp);
    for (size_t i = 1; i < 3 * m->nt; ++i)
        if (dir_edge_cmp(&e[i - 1], &e[i]) == 0) {
            st = relief_fail(err, RELIEF_E_MESH,
                             "the combined triangulation is not manifold: edge %u-%u is "
                             "used twice in the same direction",
                             (unsigned)e[i].a, (unsigned)e[i].b);
            break;
        }
    free(e);
    return st;
}

/* --------------------------------------------------------------- state */

static void set_frame(const relief_surface *s, relief_frames rule, const double n[3],
                      double f[9])
{
    const relief_fit_primitive *pr = &s->fit.prim;
    double u[3], v[3];
    if (rule == RELIEF_FRAMES_PRIMITIVE && pr->model != RELIEF_FIT_SPHERE) {
        /* Plane: e1; cylinder: the axis, so u runs along bark-like ridges. */
        memcpy(u, pr->model == RELIEF_FIT_PLANE ? s->param.e1 : pr->dir, sizeof u);
        rm_cross(n, u, v);
    } else if (rule == RELIEF_FRAMES_PRIMITIVE) {
        /* Sphere: u points east about e3; the paper's rule near the poles. */
        double e3[3];
        rm_cross(s->param.e1, s->param.e2, e3);
        rm_cross(e3, n, u);
        if (rm_dot(u, u) < 1e-12)
            rm_frame_from_normal(n, u, v);
        else {
            rm_normalise(u);
            rm_cross(n, u, v);
        }
    } else {
        rm_frame_from_normal(n, u, v);
    }
    memcpy(f, u, sizeof u);
    memcpy(f + 3, v, sizeof v);
    memcpy(f + 6, n, 3 * sizeof(double));
}

/* What building a surface shares: the capture as checked (the input, or
 * its unfolded or despiked copy, owned here), the targets, the samples,
 * and the surface being built. */
typedef struct surface_build {
    const relief_params *params;
    const relief_smooth_options *opts;
    const relief_mesh *capture; /* input, unfolded or despiked */
    const relief_mesh *scanned; /* input */
    relief_mesh *unfolded, *despiked, *samples;
    relief_target_list targets;
    relief_surface *s;
} surface_build;

/* The primitive, refused when poor unless accepted; the capture unfolded
 * where it folds over the primitive and despiked when asked. */
static relief_status surface_fit(surface_build *b, relief_error *err)
{
    relief_surface *s = b->s;
    const relief_fit_primitive *pr = &s->fit.prim;
    double t0 = relief_seconds();
    relief_status st = RELIEF_OK;
    if (b->opts->fitted)
        s->fit = *b->opts->fitted;
    else
        st = relief_fit_mesh(b->capture, b->params->fit, &s->fit, err);
    s->seconds[RELIEF_STAGE_FIT] = relief_seconds() - t0;
    if (st != RELIEF_OK)
        return st;
    if (s->fit.poor_fit && !b->opts->accept_poor_fit)
        return relief_fail(err, RELIEF_E_MESH,
                           "the capture fits no primitive well: %s (rms %.4g is more than "
                           "%.0f%% of the %s's size %.4g); base smooth grows on the "
                           "capture's own smoothed surface instead, accept_poor_fit goes on "
                           "anyway",
                           s->fit.reason, s->fit.rms, 100.0 * RELIEF_FIT_POOR,
                           relief_fit_model_name(pr->model), s->fit.size);
    st = relief_capture_check(b->capture, pr, &b->unfolded, &s->folds, err);
    if (st != RELIEF_OK)
        return st;
    if (b->unfolded)
        b->capture = b->unfolded;
    if (b->opts->spike_k > 0.0) {
        st = relief_capture_spikes(b->capture, pr, b->opts->spike_k, &b->despiked, &s->spikes,
                                   err);
        if (st != RELIEF_OK)
            return st;
        if (b->despiked)
            b->capture = b->despiked;
    }
    relief_domain_init(&s->param, pr);
    return RELIEF_OK;
}

/* The targets, from the capture as scanned (oversampling adds no
 * coverage): refused when there are none, or far more than the capture
 * can supply samples for. */
static relief_status surface_targets(surface_build *b, relief_error *err)
{
    relief_surface *s = b->s;
    const relief_params *params = b->params;
    const relief_mesh *capture = b->capture;
    const relief_fit_primitive *pr = &s->fit.prim;
    const double max_growth = b->opts->max_growth;
    const double t0 = relief_seconds();
    relief_status st = relief_targets_lay(capture, b->scanned, &s->param, s->spacing, params,
                                          b->opts, &b->targets, &s->fill, err);
    if (st != RELIEF_OK)
        return st;
    if (b->targets.n == 0) {
        if (s->fill.holes_left > 0)
            return relief_fail_reason(err, RELIEF_E_RANGE, RELIEF_REASON_HOLES_LEFT_OPEN,
                                      RELIEF_HOLES_LEFT_OPEN " %zu region%s the "
                               "capture's outline encloses open", s->fill.holes_left,
                               s->fill.holes_left == 1 ? "" : "s");
        if (s->fill.region == RELIEF_FILL_HOLES && s->fill.outside_points > 0)
            return relief_fail(err, RELIEF_E_MESH,
                               "nothing to complete: the capture has no hole inside its "
                               "outline%s",
                               pr->model == RELIEF_FIT_PLANE
                                   ? " (give an extent u0,v0,u1,v1 to extend the plane past it)"
                                   : "; fill whole completes the rest of the primitive");
        return relief_fail(err, RELIEF_E_MESH,
                           "nothing to complete: the capture covers the whole region");
    }
    if (max_growth > 0.0 && (double)b->targets.n > max_growth * (double)capture->nv)
        return relief_fail(err, RELIEF_E_MESH,
                           "the %s fit (%s) asks for %zu targets, %.0f per captured vertex "
                           "(%zu): far more than the capture can supply samples for (the "
                           "limit is %g, max_growth). %s; max_growth 0 lifts the limit",
                           relief_fit_model_name(pr->model),
                           params->fit == RELIEF_FIT_AUTO ? "chosen by fit auto" : "requested",
                           b->targets.n, (double)b->targets.n / (double)capture->nv,
                           capture->nv, max_growth,
                           pr->model == RELIEF_FIT_PLANE
                               ? "Bound the region with a smaller extent or raise the spacing"
                               : "If the capture is nearly flat, try fit plane; else bound "
                                 "the region with an extent or raise the spacing");
    s->seconds[RELIEF_STAGE_TARGETS] = relief_seconds() - t0;
    return RELIEF_OK;
}

/* Refuse before the big allocations: each oversampling pass about
 * quadruples the capture's vertices. */
static relief_status surface_memory_check(const surface_build *b, relief_error *err)
{
    const relief_params *params = b->params;
    double nsamp = (double)b->capture->nv * pow(4.0, params->oversample);
    char what[160];
    relief_snprintf_c(what, sizeof what,
                      "the smooth completion of about %.0f samples (%zu captured vertices, "
                      "oversampled %d times) and %zu targets",
                      nsamp, b->capture->nv, params->oversample, b->targets.n);
    return relief_memory_check(what, relief_estimate_smooth((size_t)fmin(nsamp, 1e15) +
                                                            b->targets.n),
                               relief_memory_limit(params),
                               "; lower oversample or raise the spacing", err);
}

/* The surface's vertices: the oversampled capture (the samples, labelled
 * captured), then the targets after them (completed, grey until grown). */
static relief_status surface_vertices(surface_build *b, relief_error *err)
{
    relief_surface *s = b->s;
    relief_oversample_params op = relief_oversample_params_default();
    const relief_mesh *samples;
    relief_mesh *m = NULL;
    double t0 = relief_seconds();
    relief_status st;
    op.scheme = b->opts->oversample_scheme;
    st = relief_oversample(b->capture, b->params->oversample, &op, &b->samples, err);
    if (st != RELIEF_OK)
        return st;
    samples = b->samples;
    s->seconds[RELIEF_STAGE_OVERSAMPLE] = relief_seconds() - t0;
    s->n_captured = b->capture->nv;
    s->n_samples = samples->nv;
    s->n_targets = b->targets.n;
    st = relief_mesh_create(samples->nv + b->targets.n, 0,
                            RELIEF_MESH_LABELS | (samples->col ? RELIEF_MESH_COLOURS : 0u),
                            &m, err);
    if (st != RELIEF_OK)
        return st;
    s->mesh = m;
    memcpy(m->pos, samples->pos, samples->nv * 3 * sizeof(double));
    memcpy(m->pos + 3 * samples->nv, b->targets.p, b->targets.n * 3 * sizeof(double));
    if (m->col) {
        memcpy(m->col, samples->col, samples->nv * 3 * sizeof(float));
        for (size_t i = 3 * samples->nv; i < 3 * m->nv; ++i)
            m->col[i] = 0.5f;
    }
    for (size_t v = 0; v < m->nv; ++v)
        m->label[v] = v < s->n_samples ? RELIEF_LABEL_CAPTURED : RELIEF_LABEL_COMPLETED;
    return RELIEF_OK;
}

/* Each vertex's projection on the primitive, displacement from it, normal
 * and frame; the targets are put on the primitive exactly. */
static relief_status surface_frames(relief_surface *s, relief_frames frames, relief_error *err)
{
    const relief_fit_primitive *pr = &s->fit.prim;
    relief_mesh *m = s->mesh;
    s->proj = malloc(m->nv * 3 * sizeof *s->proj);
    s->disp = malloc(m->nv * 3 * sizeof *s->disp);
    s->nrm = malloc(m->nv * 3 * sizeof *s->nrm);
    s->frame = malloc(m->nv * 9 * sizeof *s->frame);
    if (!s->proj || !s->disp || !s->nrm || !s->frame)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate per-vertex state");
    for (size_t v = 0; v < m->nv; ++v) {
        double *p = m->pos + 3 * v, *q = s->proj + 3 * v;
        relief_fit_project(pr, p, q);
        if (v >= s->n_samples) /* targets sit on the primitive exactly */
            memcpy(p, q, 3 * sizeof *p);
        for (int k = 0; k < 3; ++k)
            s->disp[3 * v + k] = p[k] - q[k];
        relief_fit_normal(pr, q, s->nrm + 3 * v);
        set_frame(s, frames, s->nrm + 3 * v, s->frame + 9 * v);
    }
    return RELIEF_OK;
}

/* Triangulate the samples and targets on the primitive (alpha: twice the
 * larger of the spacing and the capture's 95th-percentile edge), drop the
 * vertices left out, and demand a manifold. */
static relief_status surface_triangulate(const surface_build *b, relief_error *err)
{
    relief_surface *s = b->s;
    const double t0 = relief_seconds();
    relief_status st;
    s->alpha = 2.0 * fmax(s->spacing, edge_percentile(b->capture, 95.0));
    st = triangulate(s, s->alpha, err);
    if (st == RELIEF_OK)
        st = drop_unused(s, NULL, err);
    if (st == RELIEF_OK)
        st = check_manifold(s, err);
    s->seconds[RELIEF_STAGE_TRIANGULATE] = relief_seconds() - t0;
    return st;
}

relief_status relief_surface_build(const relief_mesh *input, const relief_params *params,
                            const relief_smooth_options *opts, relief_surface **out,
                            relief_error *err)
{
    relief_smooth_options dflt = relief_smooth_options_default();
    surface_build b;
    relief_surface *s;
    relief_status st;

    if (!opts)
        opts = &dflt;
    if (input->nt == 0)
        return relief_fail(err, RELIEF_E_MESH,
                           "the capture is a point cloud (no triangles); triangulate it "
                           "first: relief needs the capture's surface to know what it covers");
    s = calloc(1, sizeof *s);
    if (!s)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a surface");
    memset(&b, 0, sizeof b);
    b.params = params;
    b.opts = opts;
    b.capture = b.scanned = input;
    b.s = s;

    st = surface_fit(&b, err);
    if (st == RELIEF_OK) {
        s->spacing_from_capture = params->spacing <= 0.0;
        s->spacing = s->spacing_from_capture ? edge_percentile(b.capture,
                                                               opts->spacing_percentile)
                                             : params->spacing;
        if (!(s->spacing > 0.0))
            st = relief_fail(err, RELIEF_E_MESH,
                             "the capture's edges all have zero length; give a spacing");
    }
    if (st == RELIEF_OK)
        st = surface_targets(&b, err);
    if (st == RELIEF_OK)
        st = surface_memory_check(&b, err);
    if (st == RELIEF_OK)
        st = surface_vertices(&b, err);
    if (st == RELIEF_OK)
        st = surface_frames(s, opts->frames, err);
    if (st == RELIEF_OK)
        st = surface_triangulate(&b, err);

    relief_mesh_destroy(b.samples);
    relief_mesh_destroy(b.despiked);
    relief_mesh_destroy(b.unfolded);
    free(b.targets.p);
    if (st != RELIEF_OK) {
        relief_surface_destroy(s);
        return st;
    }
    *out = s;
    return RELIEF_OK;
}

/* The triangles of a free-form level: s's own, collapsed onto the kept
 * vertices (relief_om_collapse). keep is widened to the vertices that
 * could not go; *tri (*nt x 3) is on s's vertex ids. */
static relief_status collapse_level(const relief_surface *s, uint8_t *keep, double alpha,
                                    uint32_t **tri, size_t *nt, relief_error *err)
{
    const size_t nv = s->mesh->nv;
    relief_status st;
    for (size_t v = 0; v < nv; ++v)
        keep[v] = !keep[v]; /* the vertices to remove */
    st = relief_om_collapse(s->mesh, s->proj, s->nrm, keep, alpha, tri, nt, err);
    for (size_t v = 0; v < nv; ++v)
        keep[v] = !keep[v];
    return st;
}

/* What a level shares with its surface: the fit, the parameter domain,
 * the spacings and the capture's size; alpha is the level's own width. */
static void level_header(relief_surface *l, const relief_surface *s, double alpha)
{
    l->fit = s->fit;
    l->param = s->param;
    l->free_form = s->free_form;
    l->spacing = s->spacing;
    l->spacing_from_capture = s->spacing_from_capture;
    l->alpha = alpha;
    l->n_captured = s->n_captured;
}

/* The level's mesh for n vertices (labels and colours as m's) and its
 * per-vertex arrays (n + 1 rows: proj, disp, nrm 3 each, frame 9); *to
 * gets m->nv + 1 entries for the map from s's ids to the level's. */
static relief_status level_alloc(relief_surface *l, const relief_mesh *m, size_t n,
                                 uint32_t **to, relief_error *err)
{
    relief_status st = relief_mesh_create(n, 0, m->attrs & (RELIEF_MESH_LABELS |
                                                            RELIEF_MESH_COLOURS),
                                          &l->mesh, err);
    if (st != RELIEF_OK)
        return st;
    l->proj = malloc((n + 1) * 3 * sizeof *l->proj);
    l->disp = malloc((n + 1) * 3 * sizeof *l->disp);
    l->nrm = malloc((n + 1) * 3 * sizeof *l->nrm);
    l->frame = malloc((n + 1) * 9 * sizeof *l->frame);
    *to = malloc((m->nv + 1) * sizeof **to);
    if (!l->proj || !l->disp || !l->nrm || !l->frame || !*to)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a level's per-vertex state");
    return RELIEF_OK;
}

/* Copies s's kept vertices, in order, into l; to[v] (s->nv) becomes v's
 * id in l or UINT32_MAX, ids[w] (l's nv) w's id in s. Counts l's samples. */
static void level_copy(relief_surface *l, const relief_surface *s, const uint8_t *keep,
                       uint32_t *to, uint32_t *ids)
{
    const relief_mesh *m = s->mesh;
    size_t w = 0;

    for (size_t v = 0; v < m->nv; ++v) {
        to[v] = UINT32_MAX;
        if (!keep[v])
            continue;
        memcpy(l->mesh->pos + 3 * w, m->pos + 3 * v, 3 * sizeof(double));
        if (m->col && l->mesh->col)
            memcpy(l->mesh->col + 3 * w, m->col + 3 * v, 3 * sizeof(float));
        if (m->label && l->mesh->label)
            l->mesh->label[w] = m->label[v];
        memcpy(l->proj + 3 * w, s->proj + 3 * v, 3 * sizeof(double));
        memcpy(l->disp + 3 * w, s->disp + 3 * v, 3 * sizeof(double));
        memcpy(l->nrm + 3 * w, s->nrm + 3 * v, 3 * sizeof(double));
        memcpy(l->frame + 9 * w, s->frame + 9 * v, 9 * sizeof(double));
        l->n_samples += v < s->n_samples;
        to[v] = (uint32_t)w;
        ids[w++] = (uint32_t)v;
    }
}

/* The level's triangles: a free-form level takes the collapsed ones
 * (*ctri, cnt x 3 on s's ids, renumbered through to; l owns them after),
 * others are triangulated afresh; then the unused vertices go (ids kept
 * in step) and the result must be manifold. */
static relief_status level_triangles(relief_surface *l, int free_form, double alpha,
                                     uint32_t **ctri, size_t cnt, const uint32_t *to,
                                     uint32_t *ids, relief_error *err)
{
    relief_status st = RELIEF_OK;

    if (free_form) {
        for (size_t i = 0; i < 3 * cnt; ++i)
            (*ctri)[i] = to[(*ctri)[i]];
        l->mesh->tri = *ctri, l->mesh->nt = cnt;
        *ctri = NULL;
    } else {
        st = triangulate(l, alpha, err);
    }
    if (st == RELIEF_OK)
        st = drop_unused(l, ids, err);
    if (st == RELIEF_OK)
        st = check_manifold(l, err);
    return st;
}

relief_status relief_surface_level(const relief_surface *s, const uint8_t *keep_in,
                                   double alpha, relief_surface **out, uint32_t *ids,
                                   relief_error *err)
{
    const relief_mesh *m = s->mesh;
    relief_surface *l = calloc(1, sizeof *l);
    uint8_t *keep = malloc(m->nv + 1);
    uint32_t *ctri = NULL, *to = NULL;
    size_t n = 0, cnt = 0;
    relief_status st;

    if (!l || !keep) {
        free(l), free(keep);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a level surface");
    }
    for (size_t v = 0; v < m->nv; ++v)
        keep[v] = keep_in[v] != 0;
    if (s->free_form) {
        st = collapse_level(s, keep, alpha, &ctri, &cnt, err);
        if (st != RELIEF_OK)
            goto fail;
    }
    for (size_t v = 0; v < m->nv; ++v)
        n += keep[v];
    level_header(l, s, alpha);
    st = level_alloc(l, m, n, &to, err);
    if (st != RELIEF_OK)
        goto fail;
    level_copy(l, s, keep, to, ids);
    l->n_targets = n - l->n_samples;
    st = level_triangles(l, s->free_form, alpha, &ctri, cnt, to, ids, err);
    if (st != RELIEF_OK)
        goto fail;
    free(to), free(keep);
    *out = l;
    return RELIEF_OK;
fail:
    free(ctri), free(to), free(keep);
    relief_surface_destroy(l);
    return st;
}
