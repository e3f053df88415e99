/* A part's points and its resampled, tapered grid (pattern_grid.h). */
#include "report/pattern_grid.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/compare.h"
#include "base/error.h"
#include "base/rng.h"
#include "base/vec3.h"
#include "mesh/mesh.h"
#include "report/measures.h"
#include "report/pattern.h"


enum { NF = RELIEF_PATTERN_FIELDS };

/* ------------------------------------------------------------- points */

void pattern_points_free(part_points *pp)
{
    if (pp->index)
        flann_free_index_double(pp->index, &pp->fp);
    free(pp->uv);
    for (int f = 0; f < NF; ++f)
        free(pp->f[f]);
    memset(pp, 0, sizeof *pp);
}

/* Median distance from a point to its nearest other point, over at most
 * RELIEF_MEASURE_FREQ_MAX_POINTS of them drawn without replacement
 * (MT19937 seed 1), each against the whole part. */
static relief_status points_spacing(part_points *pp, relief_error *err)
{
    const size_t n = pp->n;
    size_t m = n > RELIEF_MEASURE_FREQ_MAX_POINTS ? RELIEF_MEASURE_FREQ_MAX_POINTS : n;
    size_t *pick = malloc(n * sizeof *pick);
    double *q = malloc(2 * m * sizeof *q), *d2 = malloc(2 * m * sizeof *d2);
    double *d = malloc(m * sizeof *d);
    int *idx = malloc(2 * m * sizeof *idx);
    relief_status st = RELIEF_OK;

    if (!pick || !q || !d2 || !d || !idx) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the spacing of %zu points", n);
        goto done;
    }
    relief_rng_subset(pick, n, m, 1);
    for (size_t i = 0; i < m; ++i) {
        q[2 * i] = pp->uv[2 * pick[i]];
        q[2 * i + 1] = pp->uv[2 * pick[i] + 1];
    }
    if (flann_find_nearest_neighbors_index_double(pp->index, q, (int)m, idx, d2, 2, &pp->fp) !=
        0) {
        st = relief_fail(err, RELIEF_E_INTERNAL,
                         "FLANN nearest-neighbour search failed on %zu points", m);
        goto done;
    }
    /* The point itself and its neighbour, in either order when they
     * coincide: the larger is the neighbour's distance. */
    for (size_t i = 0; i < m; ++i)
        d[i] = sqrt(d2[2 * i] > d2[2 * i + 1] ? d2[2 * i] : d2[2 * i + 1]);
    qsort(d, m, sizeof *d, relief_cmp_double);
    pp->spacing = m % 2 ? d[m / 2] : 0.5 * (d[m / 2 - 1] + d[m / 2]);
done:
    free(idx);
    free(d);
    free(d2);
    free(q);
    free(pick);
    return st;
}

/* The vertices of m labelled `want`: (u, v), heights, luminance when
 * `colour`; a kd-tree and the spacing when there are enough to measure. */
relief_status pattern_points_load(const relief_domain *pm, const relief_mesh *m, int want,
                                  int colour, part_points *pp, relief_error *err)
{
    size_t n = 0;
    relief_status st;

    memset(pp, 0, sizeof *pp);
    pp->fp = relief_knn_exact_params();
    pp->uv = malloc(2 * m->nv * sizeof *pp->uv);
    pp->f[0] = malloc(m->nv * sizeof *pp->f[0]);
    if (colour)
        pp->f[1] = malloc(m->nv * sizeof *pp->f[1]);
    if (!pp->uv || !pp->f[0] || (colour && !pp->f[1])) {
        pattern_points_free(pp);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the fields of %zu vertices",
                           m->nv);
    }
    pp->n = relief_measure_part_uv(pm, m, want, pp->uv);
    for (size_t v = 0; v < m->nv; ++v)
        if (m->label[v] == want) {
            const float *c = m->col ? m->col + 3 * v : NULL;
            pp->f[0][n] = relief_fit_distance(&pm->prim, m->pos + 3 * v);
            if (colour)
                pp->f[1][n] = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
            ++n;
        }
    if (pp->n < RELIEF_PATTERN_MIN_POINTS)
        return RELIEF_OK;
    if (pp->n > INT_MAX) {
        pattern_points_free(pp);
        return relief_fail(err, RELIEF_E_RANGE,
                           "a part of %zu points: the nearest-neighbour search takes at most %d",
                           n, INT_MAX);
    }
    pp->lo[0] = pp->hi[0] = pp->uv[0];
    pp->lo[1] = pp->hi[1] = pp->uv[1];
    for (size_t i = 0; i < pp->n; ++i)
        for (int c = 0; c < 2; ++c) {
            double x = pp->uv[2 * i + c];
            pp->lo[c] = x < pp->lo[c] ? x : pp->lo[c];
            pp->hi[c] = x > pp->hi[c] ? x : pp->hi[c];
        }
    {
        float speedup = 0.0f;
        pp->index = flann_build_index_double(pp->uv, (int)pp->n, 2, &speedup, &pp->fp);
    }
    if (!pp->index) {
        st = relief_fail(err, RELIEF_E_INTERNAL, "FLANN could not build a kd-tree on %zu points",
                         pp->n);
        pattern_points_free(pp);
        return st;
    }
    st = points_spacing(pp, err);
    if (st != RELIEF_OK)
        pattern_points_free(pp);
    return st;
}

int pattern_points_measurable(const part_points *pp) { return pp->index != NULL; }

double pattern_points_long_side(const part_points *pp)
{
    double a = pp->hi[0] - pp->lo[0], b = pp->hi[1] - pp->lo[1];
    return a > b ? a : b;
}

double pattern_points_short_side(const part_points *pp)
{
    double a = pp->hi[0] - pp->lo[0], b = pp->hi[1] - pp->lo[1];
    return a < b ? a : b;
}

/* Is field f of the part constant (RMS about its mean at most
 * RELIEF_PATTERN_FLAT times `scale`)? */
int pattern_points_flat(const part_points *pp, int f, double scale)
{
    double mean = 0.0, var = 0.0;
    for (size_t i = 0; i < pp->n; ++i)
        mean += pp->f[f][i];
    mean /= (double)pp->n;
    for (size_t i = 0; i < pp->n; ++i)
        var += (pp->f[f][i] - mean) * (pp->f[f][i] - mean);
    return !(sqrt(var / (double)pp->n) > RELIEF_PATTERN_FLAT * scale);
}

/* --------------------------------------------------------------- grid */

void pattern_grid_free(part_grid *gr)
{
    free(gr->inside);
    for (int f = 0; f < NF; ++f)
        free(gr->val[f]);
    memset(gr, 0, sizeof *gr);
}

/* The grid's shape: nx x ny nodes of step g over the part's (u, v)
 * bounding box, org the (u, v) of node (0, 0). */
static void grid_frame(const part_points *pp, double g, part_grid *gr)
{
    gr->g = g;
    gr->nx = (size_t)floor((pp->hi[0] - pp->lo[0]) / g) + 1;
    gr->ny = (size_t)floor((pp->hi[1] - pp->lo[1]) / g) + 1;
    /* Centred on the box, so both edges lose the same. */
    for (int c = 0; c < 2; ++c) {
        size_t nn = c ? gr->ny : gr->nx;
        gr->org[c] = pp->lo[c] + 0.5 * ((pp->hi[c] - pp->lo[c]) - (double)(nn - 1) * g);
    }
}

/* The fields at one node (x, y) from its k nearest points (nb: their
 * indices, dd: their squared distances, FLANN's order): the constant
 * term of a weighted least-squares plane, written to gr->val[f][node]
 * for the nfield fields, and the node marked inside. A node farther
 * than RELIEF_PATTERN_REACH steps from every point stays outside. */
static void node_fit(const part_points *pp, int nfield, int k, double x, double y,
                     const int *nb, const double *dd, size_t node, part_grid *gr)
{
    const double g = gr->g;
    double ds[RELIEF_PATTERN_KNN], r, r2, M[6] = {0}, b[NF][3] = {{0}}, sw = 0.0;
    double det;
    for (int a = 0; a < k; ++a)
        ds[a] = dd[a];
    qsort(ds, (size_t)k, sizeof *ds, relief_cmp_double);
    if (!(sqrt(ds[0]) <= RELIEF_PATTERN_REACH * g))
        return;
    r = sqrt(ds[k < 6 ? k - 1 : 5]) * 1.25;
    if (r < RELIEF_PATTERN_FIT_RADIUS * g)
        r = RELIEF_PATTERN_FIT_RADIUS * g;
    r2 = r * r;
    /* Normal equations of the weighted plane a + b du + c dv, with
     * offsets in steps g so the matrix is well scaled. M holds
     * the symmetric 3 x 3: [0]=11 [1]=1u [2]=1v [3]=uu [4]=uv
     * [5]=vv. */
    for (int a = 0; a < k; ++a) {
        const double *p = pp->uv + 2 * (size_t)nb[a];
        double du = (p[0] - x) / g, dv = (p[1] - y) / g;
        double t = 1.0 - dd[a] / r2, w;
        if (t <= 0.0)
            continue;
        w = t * t;
        sw += w;
        M[0] += w, M[1] += w * du, M[2] += w * dv;
        M[3] += w * du * du, M[4] += w * du * dv, M[5] += w * dv * dv;
        for (int f = 0; f < nfield; ++f) {
            double z = pp->f[f][nb[a]];
            b[f][0] += w * z, b[f][1] += w * du * z, b[f][2] += w * dv * z;
        }
    }
    if (!(sw > 0.0))
        return; /* cannot happen: the nearest is within r */
    {
        /* The first row of M's inverse, by cofactors: only the
         * plane's value at the node (its constant term) is used. */
        double c0 = M[3] * M[5] - M[4] * M[4], c1 = M[2] * M[4] - M[1] * M[5],
               c2 = M[1] * M[4] - M[2] * M[3];
        det = M[0] * c0 + M[1] * c1 + M[2] * c2;
        for (int f = 0; f < nfield; ++f)
            gr->val[f][node] = det > 1e-9 * sw * sw * sw
                                   ? (c0 * b[f][0] + c1 * b[f][1] + c2 * b[f][2]) / det
                                   : b[f][0] / sw;
    }
    gr->inside[node] = 1;
    ++gr->n_inside;
}

/* Row j of the grid: one k-nearest search for its nx nodes, then each
 * node's fit. q (2 nx), idx and d2 (k nx each): scratch for the search;
 * fp: the part's search parameters (FLANN takes them non-const). */
static relief_status resample_row(const part_points *pp, struct FLANNParameters *fp,
                                  int nfield, int k, size_t j, double *q, int *idx, double *d2,
                                  part_grid *gr, relief_error *err)
{
    const double g = gr->g, y = gr->org[1] + (double)j * g;
    for (size_t i = 0; i < gr->nx; ++i) {
        q[2 * i] = gr->org[0] + (double)i * g;
        q[2 * i + 1] = y;
    }
    if (flann_find_nearest_neighbors_index_double(pp->index, q, (int)gr->nx, idx, d2, k, fp) !=
        0)
        return relief_fail(err, RELIEF_E_INTERNAL,
                           "FLANN nearest-neighbour search failed on %zu grid nodes", gr->nx);
    for (size_t i = 0; i < gr->nx; ++i) {
        const int *nb = idx + (size_t)k * i;
        for (int a = 0; a < k; ++a)
            if (nb[a] < 0 || (size_t)nb[a] >= pp->n)
                return relief_fail(err, RELIEF_E_INTERNAL,
                                   "FLANN returned a neighbour outside 0..%zu", pp->n - 1);
        node_fit(pp, nfield, k, q[2 * i], y, nb, d2 + (size_t)k * i, j * gr->nx + i, gr);
    }
    return RELIEF_OK;
}

/* Resample the part's fields onto nodes of step g over its bounding box
 * (see the header: inside test, local weighted plane). */
relief_status pattern_grid_resample(const part_points *pp, double g, part_grid *gr,
                                    relief_error *err)
{
    const int k = pp->n < RELIEF_PATTERN_KNN ? (int)pp->n : RELIEF_PATTERN_KNN;
    const int nfield = pp->f[1] ? 2 : 1;
    struct FLANNParameters fp = pp->fp;
    double *q = NULL, *d2 = NULL;
    int *idx = NULL;
    relief_status st = RELIEF_OK;

    memset(gr, 0, sizeof *gr);
    grid_frame(pp, g, gr);
    gr->inside = calloc(gr->nx * gr->ny, 1);
    for (int f = 0; f < nfield; ++f)
        gr->val[f] = calloc(gr->nx * gr->ny, sizeof *gr->val[f]);
    q = malloc(2 * gr->nx * sizeof *q);
    d2 = malloc((size_t)k * gr->nx * sizeof *d2);
    idx = malloc((size_t)k * gr->nx * sizeof *idx);
    if (!gr->inside || !gr->val[0] || (nfield > 1 && !gr->val[1]) || !q || !d2 || !idx) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a %zu x %zu grid", gr->nx,
                         gr->ny);
        goto done;
    }
    for (size_t j = 0; j < gr->ny && st == RELIEF_OK; ++j)
        st = resample_row(pp, &fp, nfield, k, j, q, idx, d2, gr, err);
done:
    free(idx);
    free(d2);
    free(q);
    if (st != RELIEF_OK)
        pattern_grid_free(gr);
    return st;
}

/* Taper weights (see the header), 0 outside the part. */
void pattern_grid_taper(const part_grid *gr, double *w)
{
    const long T = RELIEF_PATTERN_TAPER, nx = (long)gr->nx, ny = (long)gr->ny;
    for (long j = 0; j < ny; ++j)
        for (long i = 0; i < nx; ++i) {
            double d = (double)T;
            if (!gr->inside[j * nx + i]) {
                w[j * nx + i] = 0.0;
                continue;
            }
            /* Off the grid counts as outside: the nearest such node. */
            {
                long e = i + 1;
                e = nx - i < e ? nx - i : e;
                e = j + 1 < e ? j + 1 : e;
                e = ny - j < e ? ny - j : e;
                d = (double)e < d ? (double)e : d;
            }
            for (long b = j - T; b <= j + T; ++b)
                for (long a = i - T; a <= i + T; ++a) {
                    double r;
                    if (a < 0 || b < 0 || a >= nx || b >= ny || gr->inside[b * nx + a])
                        continue;
                    r = sqrt((double)((a - i) * (a - i) + (b - j) * (b - j)));
                    d = r < d ? r : d;
                }
            w[j * nx + i] = 0.5 * (1.0 - cos(RELIEF_PI * d / (double)T));
        }
}
