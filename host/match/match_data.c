/* The float surface the matchers read, and the uniform grid over the
 * projected positions that answers "which vertex is closest to x'?". */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/compare.h"
#include "base/parallel.h"
#include "base/params.h"
#include "base/pool.h"
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
    free(d->sample_of);
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
#define LAYERS 5    /* grid layers a share keeps as planes: a cell's list
                       reads the layers within two of its own */

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

/* Squared distance from p to the box [lo, hi] (0 inside). */
static double box_min2(const double lo[3], const double hi[3], const double p[3])
{
    double s = 0.0;
    for (int k = 0; k < 3; ++k) {
        double e = p[k] < lo[k] ? lo[k] - p[k] : p[k] > hi[k] ? p[k] - hi[k] : 0.0;
        s += e * e;
    }
    return s;
}

/* What building the closest-vertex lists shares: the grid's origin (as
 * the kernel's floats), cell size and rounding margin; the occupied cells
 * as runs of sorted (cell, vertex) pairs, found through a hash set; the
 * active cells; the lists made so far. */
typedef struct list_build {
    relief_match_data *d;
    const uint8_t *near; /* nv, or NULL: lists only about the vertices set */
    double org[3], h, m;
    uint64_t *pair;                /* nv: cell << 32 | vertex, ascending */
    uint32_t *run_start, *run_len; /* nrun: each occupied cell's run in pair */
    uint32_t *run_of;              /* occ's slots: the run of the cell there */
    uint32_t nrun;
    cellset occ, active;
    uint32_t *act;      /* active.n: the active cells, ascending */
    uint32_t *res, nres; /* nres x 3: cell, first item, count of each list */
} list_build;

/* One thread's share of the active cells (build_lists): its scratch
 * candidates and the lists of its cells, in cell order, their first items
 * counted from its own items; its status and error, apart from the other
 * shares'. */
typedef struct list_share {
    const list_build *b;
    uint32_t *cand;     /* ncand_cap: a cell's candidates */
    uint32_t ncand_cap;
    uint32_t *items;    /* n_items of items_cap */
    size_t n_items, items_cap;
    uint32_t *res, nres; /* nres x 3, as list_build's */
    /* The runs of the grid layers l0 .. l0 + LAYERS - 1 as dense planes of
     * ldims[0] x ldims[1] (layer l in plane l % LAYERS, layer_of[] saying
     * which it holds, UINT32_MAX none): the cells go in ascending order, so
     * each layer is laid once, and a look-up there is a load where the
     * hash set's takes a hash and its probes. NULL: the hash set. */
    uint32_t *layer;
    uint32_t layer_of[LAYERS];
    relief_status st;
    relief_error err;
} list_share;

/* The lists' grid over the projected positions: cells of 0.75 x the target
 * spacing, coarser while cell ids would not fit 32 bits or a per-axis
 * count a float. */
static void lists_grid(list_build *b, double spacing)
{
    relief_match_data *d = b->d;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double h, amax = 0.0;
    for (uint32_t v = 0; v < d->nv; ++v)
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
        b->org[k] = d->lgrid[k];
    }
    d->lgrid[3] = (float)h;
    h = d->lgrid[3];
    for (int k = 0; k < 3; ++k)
        d->ldims[k] = (uint32_t)(floor((hi[k] - b->org[k]) / h) + 1.0);
    b->h = h;
    /* Float rounding of the kernel's (x - origin) / h and of its squared
     * distances stays far below this. */
    b->m = 1e-3 * h + 1e-5 * (amax + h);
}

/* Occupied cells: runs of (cell, vertex) sorted, and each cell's run. */
static relief_status lists_occupied(list_build *b, relief_error *err)
{
    relief_match_data *d = b->d;
    const uint32_t nv = d->nv;
    b->pair = malloc((size_t)nv * sizeof *b->pair);
    b->run_start = malloc(((size_t)nv + 1) * sizeof *b->run_start);
    b->run_len = malloc(((size_t)nv + 1) * sizeof *b->run_len);
    if (!b->pair || !b->run_start || !b->run_len || !set_init(&b->occ, nv) ||
        !set_init(&b->active, 8 * (size_t)nv))
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the closest-vertex lists");
    for (uint32_t v = 0; v < nv; ++v) {
        uint32_t c[3];
        for (int k = 0; k < 3; ++k) {
            double f = floor((d->proj[3 * v + k] - b->org[k]) / b->h);
            c[k] = f < 0 ? 0 : f >= d->ldims[k] ? d->ldims[k] - 1 : (uint32_t)f;
        }
        b->pair[v] = ((uint64_t)((c[2] * d->ldims[1] + c[1]) * d->ldims[0] + c[0]) << 32) | v;
    }
    qsort(b->pair, nv, sizeof *b->pair, relief_cmp_u64);
    for (uint32_t i = 0; i < nv; ++i) {
        if (i == 0 || (b->pair[i] >> 32) != (b->pair[i - 1] >> 32)) {
            b->run_start[b->nrun] = i;
            b->run_len[b->nrun] = 0;
            set_add(&b->occ, (uint32_t)(b->pair[i] >> 32)); /* sized for nv: never grows */
            ++b->nrun;
        }
        ++b->run_len[b->nrun - 1];
    }
    b->run_of = malloc(((size_t)b->occ.mask + 1) * sizeof *b->run_of);
    if (!b->run_of)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the closest-vertex lists");
    for (uint32_t r = 0; r < b->nrun; ++r)
        b->run_of[set_slot(&b->occ, (uint32_t)(b->pair[b->run_start[r]] >> 32))] = r;
    return RELIEF_OK;
}

/* The grid coordinates of a cell id. */
static void cell_coords(const relief_match_data *d, uint32_t cell, int c[3])
{
    c[0] = (int)(cell % d->ldims[0]);
    c[1] = (int)(cell / d->ldims[0] % d->ldims[1]);
    c[2] = (int)(cell / d->ldims[0] / d->ldims[1]);
}

/* The id of the cell at (i, j, l); UINT32_MAX outside the grid. */
static uint32_t cell_at(const relief_match_data *d, int i, int j, int l)
{
    if (i < 0 || j < 0 || l < 0 || i >= (int)d->ldims[0] || j >= (int)d->ldims[1] ||
        l >= (int)d->ldims[2])
        return UINT32_MAX;
    return ((uint32_t)l * d->ldims[1] + (uint32_t)j) * d->ldims[0] + (uint32_t)i;
}

/* Lay grid layer l's runs into plane k of sh->layer: the runs are in cell
 * order, so the layer's are the ones from the first at or past its first
 * cell. */
static void load_layer(list_share *sh, uint32_t l, int k)
{
    const list_build *b = sh->b;
    const size_t plane = (size_t)b->d->ldims[0] * b->d->ldims[1];
    const uint64_t first = (uint64_t)l * plane, end = first + plane;
    uint32_t *dst = sh->layer + (size_t)k * plane, lo = 0, hi = b->nrun;
    memset(dst, 0xff, plane * sizeof *dst);
    while (lo < hi) {
        const uint32_t mid = lo + (hi - lo) / 2;
        if ((b->pair[b->run_start[mid]] >> 32) < first)
            lo = mid + 1;
        else
            hi = mid;
    }
    for (uint32_t r = lo; r < b->nrun && (b->pair[b->run_start[r]] >> 32) < end; ++r)
        dst[(b->pair[b->run_start[r]] >> 32) - first] = r;
    sh->layer_of[k] = l;
}

/* The run of the vertices in the cell at (i, j, l); UINT32_MAX when it is
 * outside the grid or empty. */
static uint32_t run_at(list_share *sh, int i, int j, int l)
{
    const list_build *b = sh->b;
    const uint32_t cell = cell_at(b->d, i, j, l);
    uint32_t slot;
    if (cell == UINT32_MAX)
        return UINT32_MAX;
    if (sh->layer) {
        const size_t plane = (size_t)b->d->ldims[0] * b->d->ldims[1];
        const int k = l % LAYERS;
        if (sh->layer_of[k] != (uint32_t)l)
            load_layer(sh, (uint32_t)l, k);
        return sh->layer[(size_t)k * plane + (cell - (size_t)l * plane)];
    }
    slot = set_slot(&b->occ, cell);
    return b->occ.key[slot] == RM_EMPTY ? UINT32_MAX : b->run_of[slot];
}

/* Does run r hold a vertex near the pool (every run when no pool)? */
static int run_near(const list_build *b, uint32_t r)
{
    if (!b->near)
        return 1;
    for (uint32_t e = 0; e < b->run_len[r]; ++e)
        if (b->near[(uint32_t)b->pair[b->run_start[r] + e]])
            return 1;
    return 0;
}

/* Active cells: the occupied ones near the pool and their neighbours,
 * ascending. */
static relief_status lists_active(list_build *b, relief_error *err)
{
    const relief_match_data *d = b->d;
    uint32_t n = 0;
    for (uint32_t r = 0; r < b->nrun; ++r) {
        int c[3];
        if (!run_near(b, r))
            continue;
        cell_coords(d, (uint32_t)(b->pair[b->run_start[r]] >> 32), c);
        for (int dl = -1; dl <= 1; ++dl)
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di) {
                    const uint32_t cell = cell_at(d, c[0] + di, c[1] + dj, c[2] + dl);
                    if (cell != UINT32_MAX && !set_add(&b->active, cell))
                        return relief_fail(err, RELIEF_E_NOMEM,
                                           "cannot allocate the closest-vertex lists");
                }
    }
    b->act = malloc(((size_t)b->active.n + 1) * sizeof *b->act);
    b->res = malloc(((size_t)b->active.n + 1) * 3 * sizeof *b->res);
    if (!b->act || !b->res)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the closest-vertex lists");
    for (size_t i = 0; i <= b->active.mask; ++i)
        if (b->active.key[i] != RM_EMPTY)
            b->act[n++] = b->active.key[i];
    qsort(b->act, n, sizeof *b->act, relief_cmp_u32);
    return RELIEF_OK;
}

/* Room for cap candidates. */
static relief_status cand_grow(list_share *sh, uint32_t cap, relief_error *err)
{
    uint32_t *t = realloc(sh->cand, cap * sizeof *t);
    if (!t)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the closest-vertex lists");
    sh->cand = t;
    sh->ncand_cap = cap;
    return RELIEF_OK;
}

/* Every vertex in the 27 cells around c (one ring) into sh->cand; *n of
 * them. */
static relief_status ring_vertices(list_share *sh, const int c[3], uint32_t *n,
                                   relief_error *err)
{
    const list_build *b = sh->b;
    *n = 0;
    for (int dl = -1; dl <= 1; ++dl)
        for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
                const uint32_t r = run_at(sh, c[0] + di, c[1] + dj, c[2] + dl);
                if (r == UINT32_MAX)
                    continue;
                if (*n + b->run_len[r] > sh->ncand_cap) {
                    relief_status st = cand_grow(sh, 2 * (*n + b->run_len[r]) + 64, err);
                    if (st != RELIEF_OK)
                        return st;
                }
                for (uint32_t e = 0; e < b->run_len[r]; ++e)
                    sh->cand[(*n)++] = (uint32_t)b->pair[b->run_start[r] + e];
            }
    return RELIEF_OK;
}

/* The bound R on the distance from any point of the box [blo, bhi] to its
 * closest vertex, from the n candidates of one ring: the largest, over the
 * box's eight octants, of the smallest farthest-point distance from the
 * octant to a candidate; widened for rounding. */
static double box_reach(const list_share *sh, const double blo[3], const double bhi[3],
                        uint32_t n)
{
    const list_build *b = sh->b;
    double mid[3], best[8], r2 = 0.0;
    for (int k = 0; k < 3; ++k)
        mid[k] = 0.5 * (blo[k] + bhi[k]);
    for (int oct = 0; oct < 8; ++oct)
        best[oct] = INFINITY;
    /* Each octant's squared distance to its farthest point, its terms
     * worked out once per half-axis (octant oct spans [mid, bhi] along k
     * where bit k is set, else [blo, mid]) and summed in k's order. */
    for (uint32_t e = 0; e < n; ++e) {
        const float *pf = b->d->proj + 3 * (size_t)sh->cand[e];
        double t[3][2];
        for (int k = 0; k < 3; ++k) {
            const double p = pf[k];
            double lo = fmax(fabs(p - blo[k]), fabs(p - mid[k]));
            double hi = fmax(fabs(p - mid[k]), fabs(p - bhi[k]));
            t[k][0] = lo * lo, t[k][1] = hi * hi;
        }
        for (int oct = 0; oct < 8; ++oct) {
            double s = 0.0;
            for (int k = 0; k < 3; ++k)
                s += t[k][(oct >> k) & 1];
            best[oct] = fmin(best[oct], s);
        }
    }
    for (int oct = 0; oct < 8; ++oct)
        r2 = fmax(r2, best[oct]);
    return sqrt(r2) * (1.0 + 1e-5) + b->m;
}

/* Every vertex within reach of the box [blo, bhi], from the cells within
 * `ring` of c, into sh->cand (*n of them); *too_long once there would be
 * more than LIST_MAX. */
static relief_status reach_vertices(list_share *sh, const int c[3], int ring,
                                    const double blo[3], const double bhi[3], double reach,
                                    uint32_t *n, int *too_long, relief_error *err)
{
    const list_build *b = sh->b;
    *n = 0;
    *too_long = 0;
    for (int dl = -ring; dl <= ring; ++dl)
        for (int dj = -ring; dj <= ring; ++dj)
            for (int di = -ring; di <= ring; ++di) {
                const uint32_t r = run_at(sh, c[0] + di, c[1] + dj, c[2] + dl);
                if (r == UINT32_MAX)
                    continue;
                for (uint32_t e = 0; e < b->run_len[r]; ++e) {
                    uint32_t v = (uint32_t)b->pair[b->run_start[r] + e];
                    const float *pf = b->d->proj + 3 * (size_t)v;
                    double p[3] = {pf[0], pf[1], pf[2]};
                    if (box_min2(blo, bhi, p) > reach * reach)
                        continue;
                    if (*n == LIST_MAX) {
                        *too_long = 1;
                        return RELIEF_OK;
                    }
                    if (*n >= sh->ncand_cap) {
                        relief_status st = cand_grow(sh, 2 * *n + 64, err);
                        if (st != RELIEF_OK)
                            return st;
                    }
                    sh->cand[(*n)++] = v;
                }
            }
    return RELIEF_OK;
}

/* The list of one active cell, when it has one: every vertex within R of
 * its box (enlarged by the margin), ascending, appended to the share's
 * items and recorded in its res. A cell far from every vertex, or whose
 * list would be long, has none: the rings answer there. */
static relief_status cell_list(list_share *sh, uint32_t cell, relief_error *err)
{
    const list_build *b = sh->b;
    const double h = b->h, m = b->m;
    double blo[3], bhi[3], reach;
    uint32_t n, ring;
    int c[3], too_long;
    relief_status st;
    cell_coords(b->d, cell, c);
    for (int k = 0; k < 3; ++k) {
        blo[k] = b->org[k] + c[k] * h - m;
        bhi[k] = b->org[k] + (c[k] + 1) * h + m;
    }
    /* The vertices within one ring bound the distance to the closest. */
    st = ring_vertices(sh, c, &n, err);
    if (st != RELIEF_OK || n == 0)
        return st; /* far from every vertex: the rings */
    reach = box_reach(sh, blo, bhi, n);
    ring = (uint32_t)ceil((reach + m) / h);
    if (ring > 2)
        return RELIEF_OK; /* a long list: the rings */
    st = reach_vertices(sh, c, (int)ring, blo, bhi, reach, &n, &too_long, err);
    if (st != RELIEF_OK || too_long || n == 0)
        return st;
    qsort(sh->cand, n, sizeof *sh->cand, relief_cmp_u32);
    if (sh->n_items + n > sh->items_cap) {
        size_t cap = 2 * (sh->n_items + n) + 1024;
        uint32_t *t = realloc(sh->items, cap * sizeof *t);
        if (!t)
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the closest-vertex lists");
        sh->items = t;
        sh->items_cap = cap;
    }
    sh->res[3 * sh->nres] = cell;
    sh->res[3 * sh->nres + 1] = (uint32_t)sh->n_items;
    sh->res[3 * sh->nres + 2] = n;
    ++sh->nres;
    memcpy(sh->items + sh->n_items, sh->cand, n * sizeof *sh->cand);
    sh->n_items += n;
    return RELIEF_OK;
}

/* The shares of the active cells (build_lists): share i of n takes the
 * cells [act * i / n, act * (i + 1) / n). */
typedef struct list_shares {
    list_share *sh;
    size_t n;
} list_shares;

/* Do dense layers (list_share) pay? An active cell makes up to 152
 * look-ups (its ring, then up to two rings about it), each a hash and its
 * probes, where laying a plane's cell is a store: with at most 64 cells of
 * the grid per active cell the layers cost a fraction of what they save
 * (sphere-cap: 5 cells per active cell, its lists 0.13 -> 0.08 s on one
 * busy thread; angel-knee: 32). A share's planes stay within 4 MiB. */
static int layers_pay(const list_build *b)
{
    const uint32_t *n = b->d->ldims;
    const double cells = (double)n[0] * n[1] * n[2];
    return cells <= 64.0 * b->active.n && (double)LAYERS * n[0] * n[1] <= (1 << 20);
}

/* Shares [lo, hi) (one each when there are as many threads as shares),
 * for relief_parallel_ranges: their cells' lists, in cell order. */
static int share_lists(void *ctx, size_t lo, size_t hi)
{
    const list_shares *ls = ctx;
    const size_t plane = (size_t)ls->sh[0].b->d->ldims[0] * ls->sh[0].b->d->ldims[1];
    for (size_t i = lo; i < hi; ++i) {
        list_share *sh = &ls->sh[i];
        const size_t n_act = sh->b->active.n;
        const size_t a0 = n_act * i / ls->n, a1 = n_act * (i + 1) / ls->n;
        sh->res = malloc((a1 - a0 + 1) * 3 * sizeof *sh->res);
        sh->layer = layers_pay(sh->b) ? malloc(LAYERS * plane * sizeof *sh->layer) : NULL;
        memset(sh->layer_of, 0xff, sizeof sh->layer_of);
        sh->st = sh->res ? RELIEF_OK
                         : relief_fail(&sh->err, RELIEF_E_NOMEM,
                                       "cannot allocate the closest-vertex lists");
        for (size_t a = a0; sh->st == RELIEF_OK && a < a1; ++a)
            sh->st = cell_list(sh, sh->b->act[a], &sh->err);
    }
    return 0;
}

/* The shares' lists one after another into d->litems and b->res, each
 * list's first item moved by the items before its share: the lists and
 * items the cells taken in order by one thread would make. */
static relief_status join_lists(list_build *b, const list_shares *ls, relief_error *err)
{
    relief_match_data *d = b->d;
    size_t items = 0;
    for (size_t i = 0; i < ls->n; ++i)
        if (ls->sh[i].st != RELIEF_OK) {
            *err = ls->sh[i].err;
            return ls->sh[i].st;
        } else
            items += ls->sh[i].n_items;
    /* at least one item for the device buffer */
    d->litems = calloc(items ? items : 1, sizeof *d->litems);
    if (!d->litems)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the closest-vertex lists");
    for (size_t i = 0; i < ls->n; ++i) {
        const list_share *sh = &ls->sh[i];
        for (uint32_t l = 0; l < sh->nres; ++l) {
            b->res[3 * b->nres] = sh->res[3 * l];
            b->res[3 * b->nres + 1] = sh->res[3 * l + 1] + (uint32_t)d->n_litems;
            b->res[3 * b->nres + 2] = sh->res[3 * l + 2];
            ++b->nres;
        }
        if (sh->n_items)
            memcpy(d->litems + d->n_litems, sh->items, sh->n_items * sizeof *sh->items);
        d->n_litems += sh->n_items;
    }
    return RELIEF_OK;
}

/* Every active cell's list, the cells shared over `threads`: each cell's
 * list is its own, and the shares are joined in cell order, so the lists
 * and their items are the same bytes for any count. */
static relief_status lists_cells(list_build *b, int threads, relief_error *err)
{
    list_share sh[RELIEF_PARALLEL_MAX_THREADS];
    list_shares ls = {sh, 0};
    relief_status st;
    threads = threads < 1 ? 1 : threads > RELIEF_PARALLEL_MAX_THREADS
                                    ? RELIEF_PARALLEL_MAX_THREADS : threads;
    /* A share of fewer than 256 cells costs its thread more to start
     * than it saves. */
    ls.n = b->active.n / 256 + 1;
    if (ls.n > (size_t)threads)
        ls.n = (size_t)threads;
    memset(sh, 0, sizeof sh);
    for (size_t i = 0; i < ls.n; ++i)
        sh[i].b = b;
    relief_parallel_ranges(ls.n, (int)ls.n, share_lists, &ls);
    st = join_lists(b, &ls, err);
    for (size_t i = 0; i < ls.n; ++i) {
        free(sh[i].res);
        free(sh[i].layer);
        free(sh[i].items);
        free(sh[i].cand);
    }
    return st;
}

/* The table the kernel probes, at most half full: (cell, first item,
 * count) per slot, RM_EMPTY cells for the empty ones. */
static relief_status lists_table(list_build *b, relief_error *err)
{
    relief_match_data *d = b->d;
    cellset tab;
    uint32_t *slots;
    if (!set_init(&tab, b->nres) ||
        !(slots = malloc(((size_t)tab.mask + 1) * 3 * sizeof *slots))) {
        free(tab.key);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the closest-vertex lists");
    }
    for (size_t i = 0; i <= tab.mask; ++i)
        slots[3 * i] = RM_EMPTY, slots[3 * i + 1] = slots[3 * i + 2] = 0;
    for (uint32_t i = 0; i < b->nres; ++i) {
        uint32_t sl = set_slot(&tab, b->res[3 * i]);
        tab.key[sl] = b->res[3 * i];
        memcpy(slots + 3 * (size_t)sl, b->res + 3 * (size_t)i, 3 * sizeof *slots);
    }
    free(tab.key);
    free(d->lslot);
    d->lslot = slots;
    d->lmask = tab.mask;
    return RELIEF_OK;
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
static relief_status build_lists(relief_match_data *d, double spacing, const uint8_t *near,
                                 int threads, relief_error *err)
{
    list_build b;
    relief_status st;

    d->lmask = 0;
    d->lslot = malloc(3 * sizeof *d->lslot);
    if (!d->lslot)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the closest-vertex lists");
    d->lslot[0] = RM_EMPTY, d->lslot[1] = d->lslot[2] = 0;
    d->lgrid[0] = d->lgrid[1] = d->lgrid[2] = 0.0f, d->lgrid[3] = 1.0f;
    d->ldims[0] = d->ldims[1] = d->ldims[2] = 1;
    if (d->nv == 0 || !(spacing > 0.0))
        return RELIEF_OK; /* no lists: the rings answer every query */
    memset(&b, 0, sizeof b);
    b.d = d;
    b.near = near;
    lists_grid(&b, spacing);
    st = lists_occupied(&b, err);
    if (st == RELIEF_OK)
        st = lists_active(&b, err);
    if (st == RELIEF_OK)
        st = lists_cells(&b, threads, err);
    if (st == RELIEF_OK)
        st = lists_table(&b, err);
    free(b.res);
    free(b.act);
    free(b.run_of);
    free(b.active.key);
    free(b.occ.key);
    free(b.run_len);
    free(b.run_start);
    free(b.pair);
    return st;
}

relief_status relief_match_data_build(const relief_surface *s, int rotations, double mu,
                                      relief_match_data **out, relief_error *err)
{
    return relief_match_data_build_near(s, rotations, mu, SIZE_MAX, 0, 1, out, err);
}

relief_status relief_match_data_build_near(const relief_surface *s, int rotations, double mu,
                                           size_t n_keep, int margin, int threads,
                                           relief_match_data **out, relief_error *err)
{
    const relief_mesh *m = s->mesh;
    relief_match_data *d = calloc(1, sizeof *d);
    relief_status st = RELIEF_OK;
    double hmin = INFINITY, hmax = -INFINITY;
    uint8_t *near = NULL;

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
    st = relief_match_pool(d, n_keep, margin, &near, err);
    if (st == RELIEF_OK)
        st = build_grid(d, s->spacing, err);
    if (st == RELIEF_OK)
        st = build_lists(d, s->spacing, near, relief_pool_threads_for(threads), err);
done:
    free(near);
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
