/* Completion against truth (measure.h). */
#include "points/measure.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/knn.h"
#include "base/linalg.h"
#include "kernels/relief_math.h"
#include "mesh/mesh.h"

#define ROUGH_K 16

/* Nearest point of `pts` (n) to each query (nq): squared distance and index. */
static relief_status nearest(const double *pts, size_t n, const double *q, size_t nq,
                             double *d2, int *idx, int k, relief_error *err)
{
    struct FLANNParameters fp = relief_knn_exact_params();
    float speedup;
    flann_index_t index = flann_build_index_double((double *)pts, (int)n, 3, &speedup, &fp);
    int rc;
    if (!index)
        return relief_fail(err, RELIEF_E_NOMEM, "FLANN could not index %zu points", n);
    rc = flann_find_nearest_neighbors_index_double(index, (double *)q, (int)nq, idx, d2, k, &fp);
    flann_free_index_double(index, &fp);
    return rc ? relief_fail(err, RELIEF_E_INTERNAL, "FLANN's search failed") : RELIEF_OK;
}

/* Squared distance of each query (nq) to the surface of mesh t: its
 * triangles when it has them (the nearest of the 16 triangles with the
 * nearest centroids), else its points. */
#define NEAR_TRIANGLES 16
static relief_status surface_d2(const relief_mesh *t, const double *q, size_t nq, double *d2,
                                relief_error *err)
{
    size_t nt = t->nt;
    int k = nt < NEAR_TRIANGLES ? (int)nt : NEAR_TRIANGLES;
    double *cent, *cd2;
    int *idx;
    relief_status st;
    if (!nt) {
        int *one = malloc((nq + 1) * sizeof *one);
        if (!one)
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the distances");
        st = nearest(t->pos, t->nv, q, nq, d2, one, 1, err);
        free(one);
        return st;
    }
    cent = malloc(nt * 3 * sizeof *cent);
    cd2 = malloc(nq * (size_t)k * sizeof *cd2 + 1);
    idx = malloc(nq * (size_t)k * sizeof *idx + 1);
    if (!cent || !cd2 || !idx) {
        free(cent), free(cd2), free(idx);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the distances");
    }
    for (size_t f = 0; f < nt; ++f)
        for (int c = 0; c < 3; ++c)
            cent[3 * f + c] = (t->pos[3 * (size_t)t->tri[3 * f] + c] +
                               t->pos[3 * (size_t)t->tri[3 * f + 1] + c] +
                               t->pos[3 * (size_t)t->tri[3 * f + 2] + c]) / 3.0;
    st = nearest(cent, nt, q, nq, cd2, idx, k, err);
    for (size_t j = 0; st == RELIEF_OK && j < nq; ++j) {
        double best = INFINITY;
        for (int r = 0; r < k; ++r) {
            const uint32_t *v = t->tri + 3 * (size_t)idx[j * (size_t)k + r];
            best = fmin(best, rm_point_triangle_d2(q + 3 * j, t->pos + 3 * (size_t)v[0],
                                                   t->pos + 3 * (size_t)v[1],
                                                   t->pos + 3 * (size_t)v[2]));
        }
        d2[j] = best;
    }
    free(cent), free(cd2), free(idx);
    return st;
}

/* Mean over the points of m with label == want of the plane RMS of their
 * neighbourhood among all of m's points (rough), and of the luminance's
 * standard deviation (cdetail, when m has colour). */
static int in_region(const double *region, const double *p)
{
    double d2 = 0.0;
    if (!region)
        return 1;
    for (int k = 0; k < 3; ++k)
        d2 += (p[k] - region[k]) * (p[k] - region[k]);
    return d2 <= region[3] * region[3];
}

/* The points of m labelled `want` inside region (NULL: everywhere): their
 * count, and their positions into q (n x 3) when q is not NULL. */
static size_t gather(const relief_mesh *m, int want, const double *region, double *q)
{
    size_t k = 0;
    for (size_t i = 0; i < m->nv; ++i)
        if (m->label[i] == want && in_region(region, m->pos + 3 * i)) {
            if (q)
                memcpy(q + 3 * k, m->pos + 3 * i, 3 * sizeof *q);
            ++k;
        }
    return k;
}

/* RMS and largest of the square roots of d2 (n >= 1). */
static void rms_max(const double *d2, size_t n, double *rms, double *max)
{
    double s = 0.0, mx = 0.0;
    for (size_t j = 0; j < n; ++j)
        s += d2[j], mx = fmax(mx, d2[j]);
    *rms = sqrt(s / (double)n);
    *max = sqrt(mx);
}

static relief_status roughness(const relief_mesh *m, int want, const double *region,
                               double *rough, double *cdetail, relief_error *err)
{
    size_t nq = 0, n = m->nv;
    double *q, *d2, sr = 0.0, sc = 0.0;
    int *idx;
    relief_status st;
    nq = gather(m, want, region, NULL);
    *rough = *cdetail = NAN;
    if (!nq)
        return RELIEF_OK;
    q = malloc(nq * 3 * sizeof *q);
    d2 = malloc(nq * (ROUGH_K + 1) * sizeof *d2);
    idx = malloc(nq * (ROUGH_K + 1) * sizeof *idx);
    if (!q || !d2 || !idx) {
        free(q), free(d2), free(idx);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the roughness of %zu points",
                           nq);
    }
    gather(m, want, region, q);
    st = nearest(m->pos, n, q, nq, d2, idx, ROUGH_K + 1, err);
    for (size_t j = 0; st == RELIEF_OK && j < nq; ++j) {
        double mean[3], ev[3], evec[9], nb[3 * (ROUGH_K + 1)], lum[ROUGH_K + 1], ml = 0.0,
                                                                              vl = 0.0;
        for (int r = 0; r <= ROUGH_K; ++r) {
            size_t v = (size_t)idx[j * (ROUGH_K + 1) + r];
            memcpy(nb + 3 * r, m->pos + 3 * v, 3 * sizeof *nb);
            if (m->col) {
                lum[r] = 0.299 * m->col[3 * v] + 0.587 * m->col[3 * v + 1] +
                         0.114 * m->col[3 * v + 2];
                ml += lum[r];
            }
        }
        relief_pca3(nb, ROUGH_K + 1, NULL, mean, ev, evec);
        sr += sqrt(fmax(ev[2], 0.0)); /* pca3's eigenvalues are variances */
        if (m->col) {
            ml /= ROUGH_K + 1;
            for (int r = 0; r <= ROUGH_K; ++r)
                vl += (lum[r] - ml) * (lum[r] - ml);
            sc += sqrt(vl / (ROUGH_K + 1));
        }
    }
    if (st == RELIEF_OK) {
        *rough = sr / (double)nq;
        if (m->col)
            *cdetail = sc / (double)nq;
    }
    free(q), free(d2), free(idx);
    return st;
}

relief_status relief_points_measure(const relief_mesh *c, const relief_mesh *t,
                                    const double *region, relief_points_measures *m,
                                    relief_error *err)
{
    double *q = NULL, *d2 = NULL, sc = 0.0, dummy;
    int *idx = NULL;
    size_t nh = 0, na = 0;
    relief_status st;

    memset(m, 0, sizeof *m);
    m->colour_rms = m->cdetail_added = m->cdetail_truth_hole = NAN;
    if (!c->label || !t->label)
        return relief_fail(err, RELIEF_E_RANGE, "the completion and the truth both need a "
                           "`label` property");
    if (c->nv <= ROUGH_K || t->nv <= ROUGH_K)
        return relief_fail(err, RELIEF_E_RANGE, "too few points to measure (%zu, %zu)", c->nv,
                           t->nv);
    na = gather(c, 1, region, NULL);
    nh = gather(t, 1, NULL, NULL);
    if (!na || !nh)
        return relief_fail(err, RELIEF_E_RANGE, "nothing to measure: %zu added points, %zu "
                           "truth-hole points", na, nh);
    m->added = na;
    m->truth_hole = nh;
    q = malloc((na > nh ? na : nh) * 3 * sizeof *q);
    d2 = malloc((na > nh ? na : nh) * sizeof *d2);
    idx = malloc((na > nh ? na : nh) * sizeof *idx);
    if (!q || !d2 || !idx) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the measures");
        goto done;
    }
    /* Accuracy. */
    gather(c, 1, region, q);
    st = surface_d2(t, q, na, d2, err);
    if (st != RELIEF_OK)
        goto done;
    rms_max(d2, na, &m->acc_rms, &m->acc_max);
    /* Completeness and colour: truth-hole points against the completion. */
    gather(t, 1, NULL, q);
    st = nearest(c->pos, c->nv, q, nh, d2, idx, 1, err);
    if (st != RELIEF_OK)
        goto done;
    rms_max(d2, nh, &m->comp_rms, &m->comp_max);
    m->hausdorff = fmax(m->acc_max, m->comp_max);
    if (c->col && t->col) {
        size_t j = 0;
        for (size_t i = 0; i < t->nv; ++i)
            if (t->label[i] == 1) {
                for (int k = 0; k < 3; ++k) {
                    double e = (double)c->col[3 * (size_t)idx[j] + k] - t->col[3 * i + k];
                    sc += e * e;
                }
                ++j;
            }
        m->colour_rms = sqrt(sc / (3.0 * (double)nh));
    }
    st = roughness(c, 1, region, &m->rough_added, &m->cdetail_added, err);
    if (st == RELIEF_OK)
        st = roughness(t, 1, NULL, &m->rough_truth_hole, &m->cdetail_truth_hole, err);
    if (st == RELIEF_OK)
        st = roughness(t, 0, NULL, &m->rough_truth_captured, &dummy, err);
done:
    free(q), free(d2), free(idx);
    return st;
}
