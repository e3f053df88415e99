/* The float surface the matchers read, and the uniform grid over the
 * projected positions that answers "which vertex is closest to x'?". */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "error.h"
#include "matcher.h"
#include "mesh.h"

#define PI 3.14159265358979323846

void relief_match_data_destroy(relief_match_data *d)
{
    if (!d)
        return;
    free(d->proj);
    free(d->pos);
    free(d->col);
    free(d->matchable);
    free(d->tri);
    free(d->vt_start);
    free(d->vt);
    free(d->cell_start);
    free(d->cell_items);
    free(d->sample);
    free(d->s_proj);
    free(d->s_frame);
    free(d->cos_r);
    free(d->sin_r);
    free(d);
}

/* Grid over the projected positions: cells of about half the target
 * spacing (the oversampled samples' spacing), fewer when that would make
 * more than 4 cells per vertex. */
static relief_status build_grid(relief_match_data *d, double spacing, relief_error *err)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double h = 0.5 * spacing, ext[3];
    size_t ncell;
    uint32_t *cell_of = NULL;

    for (uint32_t v = 0; v < d->nv; ++v)
        for (int k = 0; k < 3; ++k) {
            lo[k] = fmin(lo[k], d->proj[3 * v + k]);
            hi[k] = fmax(hi[k], d->proj[3 * v + k]);
        }
    for (int k = 0; k < 3; ++k)
        ext[k] = hi[k] - lo[k];
    for (;;) {
        double cells = 1.0;
        for (int k = 0; k < 3; ++k)
            cells *= floor(ext[k] / h) + 1.0;
        if (cells <= 4.0 * d->nv + 64.0)
            break;
        h *= 1.25;
    }
    for (int k = 0; k < 3; ++k) {
        d->grid[k] = (float)lo[k];
        d->dims[k] = (uint32_t)(floor(ext[k] / h) + 1.0);
    }
    d->grid[3] = (float)h;
    ncell = (size_t)d->dims[0] * d->dims[1] * d->dims[2];
    d->cell_start = calloc(ncell + 1, sizeof *d->cell_start);
    d->cell_items = malloc(d->nv * sizeof *d->cell_items);
    cell_of = malloc(d->nv * sizeof *cell_of);
    if (!d->cell_start || !d->cell_items || !cell_of) {
        free(cell_of);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a %zu-cell grid", ncell);
    }
    /* Cell of each vertex, computed as the kernel does (float). */
    for (uint32_t v = 0; v < d->nv; ++v) {
        uint32_t c[3];
        for (int k = 0; k < 3; ++k) {
            float f = (d->proj[3 * v + k] - d->grid[k]) / d->grid[3];
            c[k] = f < 0 ? 0 : (f >= (float)d->dims[k] ? d->dims[k] - 1 : (uint32_t)f);
        }
        cell_of[v] = (c[2] * d->dims[1] + c[1]) * d->dims[0] + c[0];
        ++d->cell_start[cell_of[v] + 1];
    }
    for (size_t c = 0; c < ncell; ++c)
        d->cell_start[c + 1] += d->cell_start[c];
    {
        /* Counting sort: vertex ids ascending within each cell. */
        uint32_t *fill = malloc(ncell * sizeof *fill);
        if (!fill) {
            free(cell_of);
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the grid");
        }
        memcpy(fill, d->cell_start, ncell * sizeof *fill);
        for (uint32_t v = 0; v < d->nv; ++v)
            d->cell_items[fill[cell_of[v]]++] = v;
        free(fill);
    }
    free(cell_of);
    return RELIEF_OK;
}

relief_status relief_match_data_build(const relief_surface *s, int rotations, double mu,
                                      relief_match_data **out, relief_error *err)
{
    const relief_mesh *m = s->mesh;
    relief_match_data *d = calloc(1, sizeof *d);
    relief_status st = RELIEF_OK;
    double hmin = INFINITY, hmax = -INFINITY;

    if (!d)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate match data");
    d->nv = (uint32_t)m->nv;
    d->nt = (uint32_t)m->nt;
    d->ns = (uint32_t)s->n_samples;
    d->rotations = rotations;
    d->proj = malloc(m->nv * 3 * sizeof(float));
    d->pos = malloc(m->nv * 3 * sizeof(float));
    d->col = malloc(m->nv * 3 * sizeof(float));
    d->matchable = calloc(m->nv, 1);
    d->tri = malloc(m->nt * 3 * sizeof(uint32_t));
    d->vt_start = calloc(m->nv + 1, sizeof(uint32_t));
    d->vt = malloc(m->nt * 3 * sizeof(uint32_t));
    d->sample = malloc((s->n_samples + 1) * sizeof(uint32_t));
    d->s_proj = malloc((s->n_samples + 1) * 3 * sizeof(float));
    d->s_frame = malloc((s->n_samples + 1) * 9 * sizeof(float));
    d->cos_r = malloc((size_t)rotations * sizeof(float));
    d->sin_r = malloc((size_t)rotations * sizeof(float));
    if (!d->proj || !d->pos || !d->col || !d->matchable || !d->tri || !d->vt_start || !d->vt ||
        !d->sample || !d->s_proj || !d->s_frame || !d->cos_r || !d->sin_r) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate match data for %zu vertices",
                         m->nv);
        goto done;
    }
    for (size_t i = 0; i < 3 * m->nv; ++i) {
        d->proj[i] = (float)s->proj[i];
        d->pos[i] = (float)m->pos[i];
        d->col[i] = m->col ? m->col[i] : 0.5f;
    }
    for (size_t i = 0; i < 3 * m->nt; ++i)
        d->tri[i] = m->tri[i];
    /* Vertex-to-triangle lists, triangles in ascending order. */
    for (size_t i = 0; i < 3 * m->nt; ++i)
        ++d->vt_start[m->tri[i] + 1];
    for (size_t v = 0; v < m->nv; ++v)
        d->vt_start[v + 1] += d->vt_start[v];
    {
        uint32_t *fill = malloc((m->nv + 1) * sizeof *fill);
        if (!fill) {
            st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate match data");
            goto done;
        }
        memcpy(fill, d->vt_start, (m->nv + 1) * sizeof *fill);
        for (size_t t = 0; t < m->nt; ++t)
            for (int k = 0; k < 3; ++k)
                d->vt[fill[m->tri[3 * t + k]]++] = (uint32_t)t;
        free(fill);
    }
    for (size_t v = 0; v < s->n_samples; ++v) {
        double h = s->disp[3 * v] * s->nrm[3 * v] + s->disp[3 * v + 1] * s->nrm[3 * v + 1] +
                   s->disp[3 * v + 2] * s->nrm[3 * v + 2];
        hmin = fmin(hmin, h);
        hmax = fmax(hmax, h);
        d->matchable[v] = 1;
        d->sample[v] = (uint32_t)v;
        for (int k = 0; k < 3; ++k)
            d->s_proj[3 * v + k] = (float)s->proj[3 * v + k];
        for (int k = 0; k < 9; ++k)
            d->s_frame[9 * v + k] = (float)s->frame[9 * v + k];
    }
    d->b_shape = hmax > hmin ? hmax - hmin : s->spacing;
    d->inv_b2 = (float)(1.0 / (d->b_shape * d->b_shape));
    d->mu = (float)mu;
    for (int r = 0; r < rotations; ++r) {
        double a = 2.0 * PI * r / rotations;
        d->cos_r[r] = (float)cos(a);
        d->sin_r[r] = (float)sin(a);
    }
    st = build_grid(d, s->spacing, err);
done:
    if (st != RELIEF_OK) {
        relief_match_data_destroy(d);
        return st;
    }
    *out = d;
    return RELIEF_OK;
}
