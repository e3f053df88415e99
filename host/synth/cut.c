#include "synth/cut.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "mesh/mesh.h"

/* Is vertex position p inside the region (normal already unit)? */
static int inside(const relief_cut_region *r, const double *p)
{
    double d[3] = {p[0] - r->point[0], p[1] - r->point[1], p[2] - r->point[2]};
    if (r->shape == RELIEF_CUT_BALL)
        return d[0] * d[0] + d[1] * d[1] + d[2] * d[2] <= r->radius * r->radius;
    return fabs(d[0] * r->normal[0] + d[1] * r->normal[1] + d[2] * r->normal[2]) <=
           r->radius;
}

/* Checks the region r (finite, radius > 0 in the mesh's units) and makes a
 * slab's normal unit length in place. */
static relief_status cut_region_check(relief_cut_region *r, relief_error *err)
{
    double len;
    int finite = isfinite(r->radius);

    for (int k = 0; k < 3; ++k)
        finite = finite && isfinite(r->point[k]) &&
                 (r->shape == RELIEF_CUT_BALL || isfinite(r->normal[k]));
    if (!finite || !(r->radius > 0))
        return relief_fail(err, RELIEF_E_RANGE,
                           "the cut region must be finite with a radius > 0 (radius %g)",
                           r->radius);
    if (r->shape == RELIEF_CUT_SLAB) {
        len = sqrt(r->normal[0] * r->normal[0] + r->normal[1] * r->normal[1] +
                   r->normal[2] * r->normal[2]);
        if (!(len > 0))
            return relief_fail(err, RELIEF_E_RANGE, "the slab's normal is the zero vector");
        for (int k = 0; k < 3; ++k)
            r->normal[k] /= len;
    }
    return RELIEF_OK;
}

/* keep[v] (m->nv entries): whether vertex v stays captured, outside the
 * region (inside it for a crop). Fails when the cut takes no vertex. */
static relief_status cut_keep(const relief_mesh *m, const relief_cut_region *r, uint8_t *keep,
                              relief_error *err)
{
    size_t inside_count = 0;
    for (size_t v = 0; v < m->nv; ++v) {
        keep[v] = !inside(r, m->pos + 3 * v) == !r->crop;
        inside_count += !keep[v];
    }
    if (inside_count == 0)
        return relief_fail(err, RELIEF_E_RANGE,
                           r->crop ? "the crop region holds every one of the mesh's %zu "
                                     "vertices: nothing is cut away"
                                   : "the cut region holds none of the mesh's %zu vertices: "
                                     "nothing to fill",
                           m->nv);
    return RELIEF_OK;
}

/* The ground truth *whole: a copy of m (its positions, triangles, colours
 * and normals) labelled per vertex COMPLETED where the cut took it
 * (remap[v] == UINT32_MAX, m->nv entries) and CAPTURED elsewhere; *missing
 * gets the cut vertices' count. On failure *whole is left for the caller to
 * destroy. */
static relief_status cut_truth(const relief_mesh *m, const uint32_t *remap, relief_mesh **whole,
                               size_t *missing, relief_error *err)
{
    relief_mesh *w;
    relief_status st = relief_mesh_create(m->nv, m->nt, m->attrs | RELIEF_MESH_LABELS, whole,
                                          err);
    if (st != RELIEF_OK)
        return st;
    w = *whole;
    memcpy(w->pos, m->pos, 3 * m->nv * sizeof *m->pos);
    memcpy(w->tri, m->tri, 3 * m->nt * sizeof *m->tri);
    if (m->col)
        memcpy(w->col, m->col, 3 * m->nv * sizeof *m->col);
    if (m->nrm)
        memcpy(w->nrm, m->nrm, 3 * m->nv * sizeof *m->nrm);
    for (size_t v = 0; v < m->nv; ++v) {
        w->label[v] = remap[v] == UINT32_MAX ? RELIEF_LABEL_COMPLETED : RELIEF_LABEL_CAPTURED;
        *missing += remap[v] == UINT32_MAX;
    }
    return RELIEF_OK;
}

relief_status relief_mesh_cut(const relief_mesh *m, const relief_cut_region *region,
                              relief_mesh **captured, relief_mesh **truth, size_t *n_cut,
                              relief_error *err)
{
    relief_cut_region r = *region;
    relief_mesh *cap = NULL, *whole = NULL;
    uint8_t *keep = NULL;
    uint32_t *remap = NULL;
    size_t missing = 0;
    relief_status st = cut_region_check(&r, err);

    if (st != RELIEF_OK)
        return st;
    if (m->nt == 0)
        return relief_fail(err, RELIEF_E_MESH,
                           "the mesh has no triangles: a cut needs a surface whose "
                           "hole has a rim");
    keep = malloc(m->nv);
    remap = malloc(m->nv * sizeof *remap);
    if (!keep || !remap) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a cut of %zu vertices", m->nv);
        goto done;
    }
    st = cut_keep(m, &r, keep, err);
    if (st != RELIEF_OK)
        goto done;
    st = relief_mesh_subset(m, keep, &cap, remap, err);
    if (st != RELIEF_OK)
        goto done;
    if (cap->nt == 0) {
        st = relief_fail(err, RELIEF_E_RANGE,
                         r.crop ? "the crop region holds no triangle of the mesh: nothing "
                                  "is left captured"
                                : "the cut region takes every triangle of the mesh: nothing "
                                  "is left captured");
        goto done;
    }
    free(cap->label);
    cap->label = NULL;
    cap->attrs &= ~(unsigned)RELIEF_MESH_LABELS;
    st = cut_truth(m, remap, &whole, &missing, err);
    if (st != RELIEF_OK)
        goto done;
    if (n_cut)
        *n_cut = missing;
    *captured = cap;
    *truth = whole;
    cap = whole = NULL;
done:
    relief_mesh_destroy(whole);
    relief_mesh_destroy(cap);
    free(remap);
    free(keep);
    return st;
}
