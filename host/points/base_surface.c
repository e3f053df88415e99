/* A smooth base as the growth's surface (base_surface.h). */
#include "points/base_surface.h"

#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "kernels/relief_math.h"
#include "mesh/mesh.h"

/* Leave out the points of m (N vertices, the first n the capture's) that
 * no triangle reaches from the capture (a crack of the patches, a lone
 * capture vertex, a patch OpenMesh kept apart from the rest: islands the
 * growth cannot reach), with their rows of rep's base and base_nrm, order
 * kept. *m, *n and *N are updated on success. */
static relief_status drop_unreached(relief_mesh **m, relief_points_report *rep, size_t *n,
                                    size_t *N, relief_error *err)
{
    const relief_mesh *in = *m;
    uint8_t *keep = malloc(*N + 1);
    uint32_t *to = malloc((*N + 1) * sizeof *to);
    relief_mesh *used = NULL;
    size_t w = 0, n2 = 0;
    relief_status st;
    if (!keep || !to) {
        free(keep), free(to);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the smooth base's surface");
    }
    /* Reached from the capture through the triangles: samples, and
     * targets joined to them. */
    memset(keep, 0, *N);
    memset(keep, 1, *n);
    for (int grew = 1; grew;) {
        grew = 0;
        for (size_t t = 0; t < in->nt; ++t) {
            const uint32_t *f = in->tri + 3 * t;
            if ((keep[f[0]] || keep[f[1]] || keep[f[2]]) &&
                !(keep[f[0]] && keep[f[1]] && keep[f[2]])) {
                keep[f[0]] = keep[f[1]] = keep[f[2]] = 1;
                grew = 1;
            }
        }
    }
    st = relief_mesh_subset(in, keep, &used, to, err);
    if (st == RELIEF_OK) {
        for (size_t v = 0; v < *N; ++v) {
            if (to[v] == UINT32_MAX)
                continue;
            memmove(rep->base + 3 * w, rep->base + 3 * v, 3 * sizeof(double));
            memmove(rep->base_nrm + 3 * w, rep->base_nrm + 3 * v, 3 * sizeof(double));
            n2 += v < *n;
            ++w;
        }
        relief_mesh_destroy(*m);
        *m = used;
        *n = n2, *N = w;
    }
    free(keep), free(to);
    return st;
}

/* s's frames and displacements over the base (s->proj, s->nrm) for m's N
 * vertices, the first n samples; the targets are moved onto the base and
 * coloured mid grey until textured, as relief_surface_build does, and m's
 * normals dropped (the base's are s->nrm). */
static void set_frames(relief_surface *s, relief_mesh *m, size_t n, size_t N)
{
    if (m->col)
        for (size_t i = 3 * n; i < 3 * N; ++i)
            m->col[i] = 0.5f;
    for (size_t v = 0; v < N; ++v) {
        double *f = s->frame + 9 * v;
        if (v >= n) /* targets sit on the base exactly */
            memcpy(m->pos + 3 * v, s->proj + 3 * v, 3 * sizeof(double));
        for (int k = 0; k < 3; ++k)
            s->disp[3 * v + k] = m->pos[3 * v + k] - s->proj[3 * v + k];
        rm_frame_from_normal(s->nrm + 3 * v, f, f + 3);
        memcpy(f + 6, s->nrm + 3 * v, 3 * sizeof(double));
    }
    free(m->nrm);
    m->nrm = NULL;
    m->attrs &= ~(unsigned)RELIEF_MESH_NORMALS;
}

/* s's counts, spacing and stage times from the base's report. */
static void set_counts(relief_surface *s, const relief_points_report *rep, size_t n, size_t N)
{
    s->spacing = rep->spacing;
    s->alpha = 3.0 * rep->spacing;
    s->spacing_from_capture = 1;
    s->n_captured = rep->n_in;
    s->n_samples = n;
    s->n_dropped = rep->n_in - n;
    s->n_targets = N - n;
    s->fill.region = RELIEF_FILL_HOLES;
    s->fill.holes = rep->holes.n_holes;
    s->fill.hole_points = N - n;
    s->seconds[RELIEF_STAGE_FIT] = rep->t_analysis + rep->t_base;
    s->seconds[RELIEF_STAGE_TARGETS] = rep->t_fill;
}

relief_status relief_points_base_surface(const relief_mesh *capture,
                                         const relief_points_params *pp,
                                         const relief_fit_result *fitted, relief_surface **out,
                                         relief_points_report *rep_out, relief_error *err)
{
    relief_points_params p = *pp;
    relief_points_report rep;
    relief_mesh *m = NULL;
    relief_surface *s = NULL;
    relief_status st;
    size_t n, N;

    *out = NULL;
    if (!capture->nt)
        return relief_fail(err, RELIEF_E_RANGE, "base smooth grows on a mesh: the capture "
                           "has no triangles (relief_complete_points completes a bare point "
                           "set)");
    p.what = RELIEF_POINTS_GEOMETRY_ONLY;
    p.smooth_only = 1, p.mesh = 1, p.keep_base = 1;
    p.no_normals = 1; /* set_frames drops them: the base's are s->nrm */
    p.hole_mask = NULL;
    st = relief_points_complete(capture, &p, &m, &rep, err);
    if (st != RELIEF_OK)
        return st;
    n = rep.n_in, N = m->nv;
    if (!rep.n_added) {
        st = relief_fail(err, RELIEF_E_RANGE, "base smooth: the holes were found but no base "
                         "point could be laid in them");
        goto fail;
    }
    st = drop_unreached(&m, &rep, &n, &N, err);
    if (st != RELIEF_OK)
        goto fail;
    if (N == n) {
        st = relief_fail(err, RELIEF_E_RANGE, "base smooth: none of the %zu base points "
                         "laid in the holes could be joined to the capture's triangles",
                         rep.n_added);
        goto fail;
    }
    s = calloc(1, sizeof *s);
    if (!s)
        goto nomem;
    /* The best primitive, for the report and the measures only. */
    if (fitted) {
        s->fit = *fitted;
    } else if (relief_fit_mesh(capture, RELIEF_FIT_AUTO, &s->fit, NULL) != RELIEF_OK) {
        memset(&s->fit, 0, sizeof s->fit);
        s->fit.prim.model = RELIEF_FIT_PLANE;
        s->fit.prim.dir[2] = 1.0;
    }
    s->free_form = 1;
    s->proj = rep.base, s->nrm = rep.base_nrm;
    rep.base = rep.base_nrm = NULL;
    s->disp = malloc(N * 3 * sizeof *s->disp);
    s->frame = malloc(N * 9 * sizeof *s->frame);
    if (!s->disp || !s->frame)
        goto nomem;
    set_frames(s, m, n, N);
    s->mesh = m;
    set_counts(s, &rep, n, N);
    if (rep_out)
        *rep_out = rep;
    else
        relief_points_report_free(&rep);
    *out = s;
    return RELIEF_OK;
nomem:
    st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the smooth base's surface");
fail:
    if (s) {
        s->mesh = m, m = NULL;
        relief_surface_destroy(s);
    }
    relief_mesh_destroy(m);
    relief_points_report_free(&rep);
    return st;
}
