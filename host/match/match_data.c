/* The float surface the matchers read, and the uniform grid over the
 * projected positions that answers "which vertex is closest to x'?". */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/compare.h"
#include "base/params.h"
#include "base/error.h"
#include "base/vec3.h"
#include "match/match_data.h"
#include "mesh/mesh.h"

#define RM_REAL float
#define RM_WITH_SCORING
#include "kernels/relief_math.h"


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
    free(d->lslot);
    free(d->litems);
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

/* ------------------------------------------------ closest-vertex lists */

#define LIST_MAX 64 /* a cell whose list would be longer uses the rings */

/* An open-addressing hash set of cell ids (host side, growable). */
typedef struct cellset {
    uint32_t *key, mask, n;
} cellset;

static uint32_t set_slot(const cellset *t, uint32_t cell)
{
    uint32_t h = rm_cell_hash(cell) & t->mask;
    while (t->key[h] != RM_EMPTY && t->key[h] != cell)
        h = (h + 1) & t->mask;
    return h;
}

static int set_init(cellset *t, size_t want)
{
    size_t cap = 16;
    while (cap < 2 * want)
        cap *= 2;
    t->key = malloc(cap * sizeof *t->key);
    if (!t->key)
        return 0;
    memset(t->key, 0xff, cap * sizeof *t->key);
    t->mask = (uint32_t)(cap - 1);
    t->n = 0;
    return 1;
}

/* Insert; 0 when out of memory. */
static int set_add(cellset *t, uint32_t cell)
{
    uint32_t h;
    if (2 * ((size_t)t->n + 1) > (size_t)t->mask + 1) {
        cellset bigger;
        if (!set_init(&bigger, 2 * ((size_t)t->mask + 1)))
            return 0;
        for (size_t i = 0; i <= t->mask; ++i)
            if (t->key[i] != RM_EMPTY)
                bigger.key[set_slot(&bigger, t->key[i])] = t->key[i];
        bigger.n = t->n;
        free(t->key);
        *t = bigger;
    }
    h = set_slot(t, cell);
    if (t->key[h] == RM_EMPTY) {
        t->key[h] = cell;
        ++t->n;
    }
    return 1;
}

/* Squared distance from p to the box [lo, hi] (0 inside), and to the
 * box's farthest point. */
static double box_min2(const double lo[3], const double hi[3], const double p[3])
{
    double s = 0.0;
    for (int k = 0; k < 3; ++k) {
        double e = p[k] < lo[k] ? lo[k] - p[k] : p[k] > hi[k] ? p[k] - hi[k] : 0.0;
        s += e * e;
    }
    return s;
}

static double box_max2(const double lo[3], const double hi[3], const double p[3])
{
    double s = 0.0;
    for (int k = 0; k < 3; ++k) {
        double e = fmax(fabs(p[k] - lo[k]), fabs(p[k] - hi[k]));
        s += e * e;
    }
    return s;
}

/* The lists of rm_closest_vertex_listed. Cells of 0.75 x the target
 * spacing (1.5 x the oversampled samples' spacing: finer cells gave no
 * faster queries and took longer to build); listed: the cells holding a
 * vertex and their 26 neighbours, where the answer lies within two rings.
 * A cell's list is every vertex within R of its box, R bounding the
 * distance from any point of the box to its closest vertex (the largest,
 * over the box's eight octants, of the smallest farthest-point distance
 * from the octant to a vertex nearby). The box is enlarged by a margin
 * that covers the float rounding of the kernel's cell index and distances,
 * so the list always holds the vertex the kernel would pick from all. */
static relief_status build_lists(relief_match_data *d, double spacing, relief_error *err)
{
    const uint32_t nv = d->nv;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double h, amax = 0.0, m, org[3];
    uint64_t *pair = NULL;
    uint32_t *run_start = NULL, *run_len = NULL, *run_of = NULL, *act = NULL, *cand = NULL;
    uint32_t *res = NULL, nrun = 0, nres = 0, ncand_cap = 0;
    size_t items_cap = 0;
    cellset occ = {NULL, 0, 0}, active = {NULL, 0, 0};
    relief_status st = RELIEF_OK;

    d->lmask = 0;
    d->lslot = malloc(3 * sizeof *d->lslot);
    if (!d->lslot)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the closest-vertex lists");
    d->lslot[0] = RM_EMPTY, d->lslot[1] = d->lslot[2] = 0;
    d->lgrid[0] = d->lgrid[1] = d->lgrid[2] = 0.0f, d->lgrid[3] = 1.0f;
    d->ldims[0] = d->ldims[1] = d->ldims[2] = 1;
    if (nv == 0 || !(spacing > 0.0))
        return RELIEF_OK; /* no lists: the rings answer every query */
    for (uint32_t v = 0; v < nv; ++v)
        for (int k = 0; k < 3; ++k) {
            lo[k] = fmin(lo[k], d->proj[3 * v + k]);
            hi[k] = fmax(hi[k], d->proj[3 * v + k]);
        }
    for (int k = 0; k < 3; ++k)
        amax = fmax(amax, fmax(fabs(lo[k]), fabs(hi[k])));
    h = 0.75 * spacing;
    for (;;) { /* cell ids must fit 32 bits, per-axis counts a float */
        double cells = 1.0, most = 0.0;
        for (int k = 0; k < 3; ++k) {
            double n = floor((hi[k] - lo[k]) / h) + 1.0;
            cells *= n;
            most = fmax(most, n);
        }
        if (cells < 2147483648.0 && most < 16777216.0)
            break;
        h *= 1.25;
    }
    for (int k = 0; k < 3; ++k) {
        d->lgrid[k] = (float)lo[k];
        org[k] = d->lgrid[k];
    }
    d->lgrid[3] = (float)h;
    h = d->lgrid[3];
    for (int k = 0; k < 3; ++k)
        d->ldims[k] = (uint32_t)(floor((hi[k] - org[k]) / h) + 1.0);
    /* Float rounding of the kernel's (x - origin) / h and of its squared
     * distances stays far below this. */
    m = 1e-3 * h + 1e-5 * (amax + h);

    /* Occupied cells: runs of (cell, vertex) sorted. */
    pair = malloc((size_t)nv * sizeof *pair);
    run_start = malloc(((size_t)nv + 1) * sizeof *run_start);
    run_len = malloc(((size_t)nv + 1) * sizeof *run_len);
    if (!pair || !run_start || !run_len || !set_init(&occ, nv) || !set_init(&active, 8 * (size_t)nv)) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the closest-vertex lists");
        goto done;
    }
    for (uint32_t v = 0; v < nv; ++v) {
        uint32_t c[3];
        for (int k = 0; k < 3; ++k) {
            double f = floor((d->proj[3 * v + k] - org[k]) / h);
            c[k] = f < 0 ? 0 : f >= d->ldims[k] ? d->ldims[k] - 1 : (uint32_t)f;
        }
        pair[v] = ((uint64_t)((c[2] * d->ldims[1] + c[1]) * d->ldims[0] + c[0]) << 32) | v;
    }
    qsort(pair, nv, sizeof *pair, relief_cmp_u64);
    for (uint32_t i = 0; i < nv; ++i) {
        if (i == 0 || (pair[i] >> 32) != (pair[i - 1] >> 32)) {
            run_start[nrun] = i;
            run_len[nrun] = 0;
            set_add(&occ, (uint32_t)(pair[i] >> 32)); /* sized for nv: never grows */
            ++nrun;
        }
        ++run_len[nrun - 1];
    }
    run_of = malloc(((size_t)occ.mask + 1) * sizeof *run_of);
    if (!run_of) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the closest-vertex lists");
        goto done;
    }
    for (uint32_t r = 0; r < nrun; ++r)
        run_of[set_slot(&occ, (uint32_t)(pair[run_start[r]] >> 32))] = r;

    /* Active cells: the occupied ones and their neighbours, ascending. */
    for (uint32_t r = 0; r < nrun; ++r) {
        uint32_t cell = (uint32_t)(pair[run_start[r]] >> 32);
        int c[3] = {(int)(cell % d->ldims[0]), (int)(cell / d->ldims[0] % d->ldims[1]),
                    (int)(cell / d->ldims[0] / d->ldims[1])};
        for (int dl = -1; dl <= 1; ++dl)
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di) {
                    int i = c[0] + di, j = c[1] + dj, l = c[2] + dl;
                    if (i < 0 || j < 0 || l < 0 || i >= (int)d->ldims[0] ||
                        j >= (int)d->ldims[1] || l >= (int)d->ldims[2])
                        continue;
                    if (!set_add(&active, ((uint32_t)l * d->ldims[1] + (uint32_t)j) *
                                                  d->ldims[0] +
                                              (uint32_t)i)) {
                        st = relief_fail(err, RELIEF_E_NOMEM,
                                         "cannot allocate the closest-vertex lists");
                        goto done;
                    }
                }
    }
    act = malloc(((size_t)active.n + 1) * sizeof *act);
    res = malloc(((size_t)active.n + 1) * 3 * sizeof *res);
    if (!act || !res) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the closest-vertex lists");
        goto done;
    }
    {
        uint32_t n = 0;
        for (size_t i = 0; i <= active.mask; ++i)
            if (active.key[i] != RM_EMPTY)
                act[n++] = active.key[i];
        qsort(act, n, sizeof *act, relief_cmp_u32);
    }

    for (uint32_t a = 0; a < active.n; ++a) {
        const uint32_t cell = act[a];
        const int c[3] = {(int)(cell % d->ldims[0]), (int)(cell / d->ldims[0] % d->ldims[1]),
                          (int)(cell / d->ldims[0] / d->ldims[1])};
        double blo[3], bhi[3], r2 = 0.0, reach;
        uint32_t n = 0, ring;
        int too_long = 0;
        for (int k = 0; k < 3; ++k) {
            blo[k] = org[k] + c[k] * h - m;
            bhi[k] = org[k] + (c[k] + 1) * h + m;
        }
        /* The vertices within one ring bound the distance to the closest. */
        for (int dl = -1; dl <= 1; ++dl)
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di) {
                    int i = c[0] + di, j = c[1] + dj, l = c[2] + dl;
                    uint32_t slot, r;
                    if (i < 0 || j < 0 || l < 0 || i >= (int)d->ldims[0] ||
                        j >= (int)d->ldims[1] || l >= (int)d->ldims[2])
                        continue;
                    slot = set_slot(&occ, ((uint32_t)l * d->ldims[1] + (uint32_t)j) *
                                              d->ldims[0] +
                                          (uint32_t)i);
                    if (occ.key[slot] == RM_EMPTY)
                        continue;
                    r = run_of[slot];
                    if (n + run_len[r] > ncand_cap) {
                        uint32_t cap = 2 * (n + run_len[r]) + 64, *t = realloc(cand, cap * sizeof *t);
                        if (!t) {
                            st = relief_fail(err, RELIEF_E_NOMEM,
                                             "cannot allocate the closest-vertex lists");
                            goto done;
                        }
                        cand = t;
                        ncand_cap = cap;
                    }
                    for (uint32_t e = 0; e < run_len[r]; ++e)
                        cand[n++] = (uint32_t)pair[run_start[r] + e];
                }
        if (n == 0)
            continue; /* far from every vertex: the rings */
        for (int oct = 0; oct < 8; ++oct) {
            double olo[3], ohi[3], best = INFINITY;
            for (int k = 0; k < 3; ++k) {
                double mid = 0.5 * (blo[k] + bhi[k]);
                olo[k] = (oct >> k) & 1 ? mid : blo[k];
                ohi[k] = (oct >> k) & 1 ? bhi[k] : mid;
            }
            for (uint32_t e = 0; e < n; ++e) {
                const float *pf = d->proj + 3 * (size_t)cand[e];
                double p[3] = {pf[0], pf[1], pf[2]};
                best = fmin(best, box_max2(olo, ohi, p));
            }
            r2 = fmax(r2, best);
        }
        reach = sqrt(r2) * (1.0 + 1e-5) + m;
        ring = (uint32_t)ceil((reach + m) / h);
        if (ring > 2)
            continue; /* a long list: the rings */
        /* Every vertex within reach of the box, ascending. */
        n = 0;
        for (int dl = -(int)ring; dl <= (int)ring && !too_long; ++dl)
            for (int dj = -(int)ring; dj <= (int)ring && !too_long; ++dj)
                for (int di = -(int)ring; di <= (int)ring && !too_long; ++di) {
                    int i = c[0] + di, j = c[1] + dj, l = c[2] + dl;
                    uint32_t slot, r;
                    if (i < 0 || j < 0 || l < 0 || i >= (int)d->ldims[0] ||
                        j >= (int)d->ldims[1] || l >= (int)d->ldims[2])
                        continue;
                    slot = set_slot(&occ, ((uint32_t)l * d->ldims[1] + (uint32_t)j) *
                                              d->ldims[0] +
                                          (uint32_t)i);
                    if (occ.key[slot] == RM_EMPTY)
                        continue;
                    r = run_of[slot];
                    for (uint32_t e = 0; e < run_len[r]; ++e) {
                        uint32_t v = (uint32_t)pair[run_start[r] + e];
                        const float *pf = d->proj + 3 * (size_t)v;
                        double p[3] = {pf[0], pf[1], pf[2]};
                        if (box_min2(blo, bhi, p) > reach * reach)
                            continue;
                        if (n == LIST_MAX) {
                            too_long = 1;
                            break;
                        }
                        if (n >= ncand_cap) {
                            uint32_t cap = 2 * n + 64, *t = realloc(cand, cap * sizeof *t);
                            if (!t) {
                                st = relief_fail(err, RELIEF_E_NOMEM,
                                                 "cannot allocate the closest-vertex lists");
                                goto done;
                            }
                            cand = t;
                            ncand_cap = cap;
                        }
                        cand[n++] = v;
                    }
                }
        if (too_long || n == 0)
            continue;
        qsort(cand, n, sizeof *cand, relief_cmp_u32);
        if (d->n_litems + n > items_cap) {
            size_t cap = 2 * (d->n_litems + n) + 1024;
            uint32_t *t = realloc(d->litems, cap * sizeof *t);
            if (!t) {
                st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the closest-vertex lists");
                goto done;
            }
            d->litems = t;
            items_cap = cap;
        }
        res[3 * nres] = cell;
        res[3 * nres + 1] = (uint32_t)d->n_litems;
        res[3 * nres + 2] = n;
        ++nres;
        memcpy(d->litems + d->n_litems, cand, n * sizeof *cand);
        d->n_litems += n;
    }
    {
        /* The table the kernel probes: at most half full. */
        cellset tab;
        uint32_t *slots;
        if (!set_init(&tab, nres) ||
            !(slots = malloc(((size_t)tab.mask + 1) * 3 * sizeof *slots))) {
            free(tab.key);
            st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the closest-vertex lists");
            goto done;
        }
        for (size_t i = 0; i <= tab.mask; ++i)
            slots[3 * i] = RM_EMPTY, slots[3 * i + 1] = slots[3 * i + 2] = 0;
        for (uint32_t i = 0; i < nres; ++i) {
            uint32_t sl = set_slot(&tab, res[3 * i]);
            tab.key[sl] = res[3 * i];
            memcpy(slots + 3 * (size_t)sl, res + 3 * (size_t)i, 3 * sizeof *slots);
        }
        free(tab.key);
        free(d->lslot);
        d->lslot = slots;
        d->lmask = tab.mask;
    }
    if (!d->litems) /* at least one item for the device buffer */
        d->litems = calloc(1, sizeof *d->litems);
done:
    free(res);
    free(act);
    free(cand);
    free(run_of);
    free(active.key);
    free(occ.key);
    free(run_len);
    free(run_start);
    free(pair);
    return st;
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
    if (rotations <= 0) {
        relief_params dflt = relief_params_default();
        rotations = relief_params_rotations(&dflt, s->fit.prim.model);
    }
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
    relief_mesh_vertex_triangles(m, d->vt_start, d->vt);
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
        double a = 2.0 * RELIEF_PI * r / rotations;
        d->cos_r[r] = (float)cos(a);
        d->sin_r[r] = (float)sin(a);
    }
    st = build_grid(d, s->spacing, err);
    if (st == RELIEF_OK)
        st = build_lists(d, s->spacing, err);
done:
    if (st != RELIEF_OK) {
        relief_match_data_destroy(d);
        return st;
    }
    *out = d;
    return RELIEF_OK;
}

size_t relief_match_query_candidates(const relief_match_data *d, const relief_match_query *q)
{
    return (size_t)(q->subset ? q->n_subset : d->ns) * (size_t)d->rotations;
}
