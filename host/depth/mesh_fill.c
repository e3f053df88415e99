#include "depth/mesh_fill.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/clock.h"
#include "base/error.h"

relief_mesh_fill_params relief_mesh_fill_params_default(void)
{
    relief_mesh_fill_params p;
    p.resolution = 256;
    p.depth = relief_depth_repair_params_default();
    /* A mesh's z-buffers are smooth surfaces seen without sensor noise:
     * the thin plate carries their curvature over a hole (a holed unit
     * sphere's cap: Hausdorff 0.017 against 0.16 with the membrane). */
    p.depth.thin_plate = 1;
    return p;
}

/* Repair one depth image of the z-buffers: its HOLE pixels. */
static relief_status repair(float *z, const uint8_t *state, int W, int H,
                            const relief_depth_repair_params *dp, relief_patch_scorer *scorer,
                            size_t *holes, size_t *filled, relief_mesh_fill_report *rep,
                            relief_error *err)
{
    size_t n = (size_t)W * H, surface = 0;
    uint8_t *missing = calloc(n, 1), *target = calloc(n, 1);
    relief_depth_repair_report r;
    relief_status st = RELIEF_OK;
    if (!missing || !target) {
        free(missing);
        free(target);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a depth image's masks");
    }
    *holes = 0;
    for (size_t i = 0; i < n; ++i) {
        missing[i] = state[i] != RELIEF_Z_SURFACE;
        surface += !missing[i];
    }
    /* The hole pixels inside the surface's image (a surface pixel on both
     * sides along the row or the column): those at the silhouette, where a
     * ray grazes the hole's rim, have nothing to repair them from on one
     * side; left missing, their axis says nothing there. */
    if (relief_depth_inside(missing, W, H, target) == (size_t)-1) {
        free(missing);
        free(target);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a depth image's masks");
    }
    for (size_t i = 0; i < n; ++i) {
        target[i] = target[i] && state[i] == RELIEF_Z_HOLE;
        *holes += state[i] == RELIEF_Z_HOLE;
    }
    rep->surface_pixels += surface;
    *filled = 0;
    if (*holes && surface) {
        st = relief_depth_repair_targets(z, missing, target, W, H, dp, scorer, NULL, &r, err);
        if (st == RELIEF_OK) {
            for (size_t i = 0; i < n; ++i)
                *filled += target[i] && isfinite(z[i]);
            rep->by_synthesis += r.by_synthesis;
            rep->by_fallback += r.by_fallback;
            rep->by_membrane += r.by_membrane;
            rep->unreached += r.unreached;
        }
    }
    free(missing);
    free(target);
    return st;
}

/* The six images, front and back along each axis, each taking a share of
 * the progress's current stage by its pixels (the z-buffers before them
 * and the surface after take a twentieth each). */
static relief_status repair_images(relief_zbuffers *zb, const relief_mesh_fill_params *p,
                                   relief_patch_scorer *scorer, relief_mesh_fill_report *rep,
                                   relief_error *err)
{
    relief_progress *pr = p->depth.progress;
    double lo = pr ? pr->lo : 0.0, hi = pr ? pr->hi : 1.0, all = 0.0, done = 0.0;
    relief_status st = RELIEF_OK;
    for (int a = 0; a < 3; ++a)
        all += 2.0 * zb->width[a] * (double)zb->height[a];
    for (int k = 0; k < 6 && st == RELIEF_OK; ++k) {
        int a = k / 2, back = k % 2;
        double share = zb->width[a] * (double)zb->height[a] / all;
        if (pr) {
            relief_progress_stage(pr, lo + (0.05 + 0.9 * done) * (hi - lo),
                                  lo + (0.05 + 0.9 * (done + share)) * (hi - lo));
            if (relief_progress_step(pr, 0.0))
                st = relief_fail(err, RELIEF_E_CANCELLED, "cancelled by the progress callback");
        }
        if (st == RELIEF_OK)
            st = repair(back ? zb->back[a] : zb->front[a],
                        back ? zb->back_state[a] : zb->front_state[a], zb->width[a],
                        zb->height[a], &p->depth, scorer, &rep->hole_pixels[k], &rep->filled[k],
                        rep, err);
        done += share;
    }
    if (pr)
        relief_progress_stage(pr, lo, hi);
    if (st == RELIEF_OK)
        relief_progress_step(pr, 0.95);
    return st;
}

relief_status relief_mesh_depth_fill(relief_mesh *in, const relief_mesh_fill_params *p,
                                     relief_patch_scorer *scorer, relief_mesh **out,
                                     relief_mesh_fill_report *rep, relief_error *err)
{
    relief_mesh_fill_report local;
    relief_zbuffers zb;
    float *values = NULL;
    double t0 = relief_seconds();
    relief_status st;
    size_t nvox;

    if (!rep)
        rep = &local;
    memset(rep, 0, sizeof *rep);
    memset(&zb, 0, sizeof zb);
    if (relief_mesh_triangle_count(in) == 0)
        return relief_fail(err, RELIEF_E_RANGE, "the mesh has no triangles: a point set has "
                           "no depth images (a surface is needed)");
    st = relief_grid_of_mesh(in, p->resolution, &rep->grid, err);
    if (st == RELIEF_OK)
        st = relief_zbuffers_make(in, &rep->grid, &zb, err);
    rep->seconds_zbuffers = relief_seconds() - t0;
    if (st != RELIEF_OK)
        return st;
    t0 = relief_seconds();
    st = repair_images(&zb, p, scorer, rep, err);
    rep->seconds_repair = relief_seconds() - t0;
    if (st != RELIEF_OK)
        goto done;
    t0 = relief_seconds();
    nvox = (size_t)rep->grid.n[0] * rep->grid.n[1] * rep->grid.n[2];
    values = malloc(nvox * sizeof *values);
    if (!values) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate %zu voxels", nvox);
        goto done;
    }
    st = relief_zbuffers_voxels(&zb, values, err);
    for (size_t i = 0; i < nvox && st == RELIEF_OK; ++i)
        rep->inside_voxels += values[i] > 0.0f;
    if (st == RELIEF_OK)
        st = relief_isosurface(&rep->grid, values, out, err);
    rep->seconds_surface = relief_seconds() - t0;
done:
    free(values);
    relief_zbuffers_free(&zb);
    return st;
}

static relief_status occupancy(relief_mesh *m, const relief_grid *g, float *values,
                               relief_error *err)
{
    relief_zbuffers zb;
    relief_status st = relief_zbuffers_make(m, g, &zb, err);
    if (st != RELIEF_OK)
        return st;
    st = relief_zbuffers_voxels(&zb, values, err);
    relief_zbuffers_free(&zb);
    return st;
}

relief_status relief_mesh_measure(relief_mesh *repaired, relief_mesh *truth,
                                  const relief_grid *g, relief_mesh_measures *m,
                                  relief_error *err)
{
    size_t nvox = (size_t)g->n[0] * g->n[1] * g->n[2], both = 0, either = 0;
    float *a = malloc(nvox * sizeof *a), *b = malloc(nvox * sizeof *b);
    double mean_ab, max_ab, mean_ba, max_ba;
    relief_status st = RELIEF_OK;
    if (!a || !b) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the measures' voxels");
        goto done;
    }
    st = relief_surface_distance(repaired, truth, &mean_ab, &max_ab, err);
    if (st == RELIEF_OK)
        st = relief_surface_distance(truth, repaired, &mean_ba, &max_ba, err);
    if (st == RELIEF_OK)
        st = occupancy(repaired, g, a, err);
    if (st == RELIEF_OK)
        st = occupancy(truth, g, b, err);
    if (st != RELIEF_OK)
        goto done;
    for (size_t i = 0; i < nvox; ++i) {
        both += a[i] > 0.0f && b[i] > 0.0f;
        either += a[i] > 0.0f || b[i] > 0.0f;
    }
    m->mean = 0.5 * (mean_ab + mean_ba);
    m->hausdorff = fmax(max_ab, max_ba);
    m->iou = either ? (double)both / (double)either : NAN;
done:
    free(a);
    free(b);
    return st;
}
