#include "report/measures.h"

#include "base/compare.h"
#include "base/knn.h"
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/rng.h"
#include "base/vec3.h"
#include "mesh/mesh.h"
#include "report/report.h"
#include "smooth/param.h"

/* Barycentric slack for "inside a truth triangle". */
#define BARY_EPS 1e-9
/* Truth vertices whose incident triangles are tried for each query. */
#define TRUTH_K 3

/* ------------------------------------------------------------- helpers */

/* Total variation between the normalised histograms of a (na values) and
 * b (nb values) over RELIEF_MEASURE_HIST_BINS bins of [lo, hi]. */
static double hist_distance(const double *a, size_t na, const double *b, size_t nb,
                            double lo, double hi)
{
    enum { NB = RELIEF_MEASURE_HIST_BINS };
    double ca[NB] = {0}, cb[NB] = {0}, tv = 0.0;
    if (!(hi > lo) || na == 0 || nb == 0)
        return 0.0;
    for (int s = 0; s < 2; ++s) {
        const double *x = s ? b : a;
        double *c = s ? cb : ca;
        size_t n = s ? nb : na;
        for (size_t i = 0; i < n; ++i) {
            double t = floor((x[i] - lo) / (hi - lo) * NB);
            int k = t < 0.0 ? 0 : t >= NB ? NB - 1 : (int)t;
            c[k] += 1.0;
        }
    }
    for (int k = 0; k < NB; ++k)
        tv += fabs(ca[k] / (double)na - cb[k] / (double)nb);
    return 0.5 * tv;
}

/* The distinct edges of m's triangles as sorted keys (lo << 32 | hi). */
static relief_status unique_edges(const relief_mesh *m, uint64_t **edges, size_t *ne,
                                  relief_error *err)
{
    uint64_t *e;
    size_t n = 0;
    *edges = NULL;
    *ne = 0;
    if (m->nt == 0)
        return RELIEF_OK;
    e = malloc(3 * m->nt * sizeof *e);
    if (!e)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the %zu edges of %zu triangles",
                           3 * m->nt, m->nt);
    for (size_t t = 0; t < m->nt; ++t)
        for (int k = 0; k < 3; ++k) {
            uint64_t a = m->tri[3 * t + k], b = m->tri[3 * t + (k + 1) % 3];
            e[3 * t + k] = a < b ? a << 32 | b : b << 32 | a;
        }
    qsort(e, 3 * m->nt, sizeof *e, relief_cmp_u64);
    for (size_t i = 0; i < 3 * m->nt; ++i)
        if (n == 0 || e[i] != e[n - 1])
            e[n++] = e[i];
    *edges = e;
    *ne = n;
    return RELIEF_OK;
}

/* Labels present and 0 or 1; counts of each. */
relief_status relief_measure_check_labels(const relief_mesh *m, const char *what, size_t *n0,
                                          size_t *n1, relief_error *err)
{
    *n0 = *n1 = 0;
    if (!m->label)
        return relief_fail(err, RELIEF_E_MESH,
                           "the %s mesh has no label property (0 captured, 1 completed "
                           "per vertex)",
                           what);
    for (size_t v = 0; v < m->nv; ++v) {
        if (m->label[v] > RELIEF_LABEL_COMPLETED)
            return relief_fail(err, RELIEF_E_MESH,
                               "the %s mesh's vertex %zu has label %u; expected 0 "
                               "(captured) or 1 (completed)",
                               what, v, (unsigned)m->label[v]);
        if (m->label[v] == RELIEF_LABEL_CAPTURED)
            ++*n0;
        else
            ++*n1;
    }
    return RELIEF_OK;
}

relief_status relief_measure_check_parts(const relief_mesh *cm, const relief_mesh *tm,
                                         size_t *n_captured, size_t *n_completed,
                                         size_t *n_truth_missing, relief_error *err)
{
    size_t t0 = 0, t1 = 0;
    relief_status st = relief_mesh_validate(cm, err);
    if (st == RELIEF_OK)
        st = relief_measure_check_labels(cm, "completed", n_captured, n_completed, err);
    if (st != RELIEF_OK)
        return st;
    if (*n_captured == 0 || *n_completed == 0)
        return relief_fail(err, RELIEF_E_MESH,
                           "the completed mesh has no %s vertex (label %d): both parts are "
                           "needed to compare them",
                           *n_captured == 0 ? "captured" : "completed", *n_captured == 0 ? 0 : 1);
    if (tm) {
        st = relief_mesh_validate(tm, err);
        if (st == RELIEF_OK)
            st = relief_measure_check_labels(tm, "truth", &t0, &t1, err);
        if (st != RELIEF_OK)
            return st;
        if (t1 == 0)
            return relief_fail(err, RELIEF_E_MESH,
                               "the truth mesh has no vertex labelled 1: it does not say "
                               "which part the capture misses");
    }
    if (n_truth_missing)
        *n_truth_missing = t1;
    return RELIEF_OK;
}

relief_status relief_measure_fit_captured(const relief_mesh *m, relief_fit_result *fit,
                                          relief_error *err)
{
    relief_mesh *sub = NULL;
    uint8_t *keep = malloc(m->nv);
    relief_status st;
    if (!keep)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate %zu flags", m->nv);
    for (size_t v = 0; v < m->nv; ++v)
        keep[v] = m->label[v] == RELIEF_LABEL_CAPTURED;
    st = relief_mesh_subset(m, keep, &sub, NULL, err);
    if (st == RELIEF_OK) {
        st = relief_fit_mesh(sub, RELIEF_FIT_AUTO, fit, err);
        if (st != RELIEF_OK && err) {
            /* Say which fit failed, keeping the fit's own words. */
            relief_error inner = *err;
            relief_fail(err, st, "fitting a primitive to the captured part: %s",
                        inner.message);
        }
    }
    relief_mesh_destroy(sub);
    free(keep);
    return st;
}

/* (u, v) of the vertices of m with label `want` (all when want < 0),
 * written to uv (count x 2); the angular coordinate of a cylinder or
 * sphere is taken from the points' circular mean direction, in
 * (-pi r, pi r]. Returns the count. */
size_t relief_measure_part_uv(const relief_domain *pm, const relief_mesh *m, int want,
                              double *uv)
{
    const relief_fit_primitive *pr = &pm->prim;
    size_t n = 0;
    for (size_t v = 0; v < m->nv; ++v)
        if (want < 0 || m->label[v] == want) {
            relief_domain_coords(pm, m->pos + 3 * v, uv + 2 * n);
            ++n;
        }
    if (pr->model != RELIEF_FIT_PLANE && n > 0 && pr->radius > 0.0) {
        double sc = 0.0, ss = 0.0, mean;
        for (size_t i = 0; i < n; ++i) {
            double a = uv[2 * i] / pr->radius;
            sc += cos(a);
            ss += sin(a);
        }
        mean = atan2(ss, sc);
        for (size_t i = 0; i < n; ++i)
            uv[2 * i] = pr->radius * remainder(uv[2 * i] / pr->radius - mean, 2.0 * RELIEF_PI);
    }
    return n;
}

/* ----------------------------------------------------------- spectrum */

static double power_at(const double *uv, const double *f, size_t n, double ku, double kv)
{
    double re = 0.0, im = 0.0;
    for (size_t i = 0; i < n; ++i) {
        double ph = 2.0 * RELIEF_PI * (ku * uv[2 * i] + kv * uv[2 * i + 1]);
        re += f[i] * cos(ph);
        im += f[i] * sin(ph);
    }
    return re * re + im * im;
}

/* Median distance from each point to its nearest other point. */
static relief_status median_spacing(const double *uv, size_t n, double *out,
                                    relief_error *err)
{
    struct FLANNParameters fp = relief_knn_exact_params();
    flann_index_t index = NULL;
    int *idx = malloc(2 * n * sizeof *idx);
    double *d2 = malloc(2 * n * sizeof *d2), *d = malloc(n * sizeof *d);
    float speedup = 0.0f;
    relief_status st = RELIEF_OK;

    if (!idx || !d2 || !d) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the neighbours of %zu points", n);
        goto done;
    }
    index = flann_build_index_double((double *)uv, (int)n, 2, &speedup, &fp);
    if (!index) {
        st = relief_fail(err, RELIEF_E_INTERNAL, "FLANN could not build a kd-tree on %zu points",
                         n);
        goto done;
    }
    if (flann_find_nearest_neighbors_index_double(index, (double *)uv, (int)n, idx, d2, 2,
                                                  &fp) != 0) {
        st = relief_fail(err, RELIEF_E_INTERNAL, "FLANN nearest-neighbour search failed on %zu "
                                                 "points", n);
        goto done;
    }
    /* The two nearest are the point itself and its neighbour, in either
     * order when they coincide: the larger is the neighbour's distance. */
    for (size_t i = 0; i < n; ++i)
        d[i] = sqrt(d2[2 * i] > d2[2 * i + 1] ? d2[2 * i] : d2[2 * i + 1]);
    qsort(d, n, sizeof *d, relief_cmp_double);
    *out = n % 2 ? d[n / 2] : 0.5 * (d[n / 2 - 1] + d[n / 2]);
done:
    if (index)
        flann_free_index_double(index, &fp);
    free(d);
    free(d2);
    free(idx);
    return st;
}

/* The spectrum's points into suv (m x 2) and sf (m), f with its mean
 * removed; returns the sum of squares left. A deterministic random subset
 * of m of the n keeps the cost bounded without the aliasing a stride
 * would bring on a regular grid. pick: n scratch. */
static double freq_subset(const double *uv, const double *f, size_t n, size_t m, size_t *pick,
                          double *suv, double *sf)
{
    double mean = 0.0, var = 0.0;
    relief_rng_subset(pick, n, m, 1);
    for (size_t i = 0; i < m; ++i) {
        suv[2 * i] = uv[2 * pick[i]];
        suv[2 * i + 1] = uv[2 * pick[i] + 1];
        sf[i] = f[pick[i]];
        mean += sf[i];
    }
    mean /= (double)m;
    for (size_t i = 0; i < m; ++i) {
        sf[i] -= mean;
        var += sf[i] * sf[i];
    }
    return var;
}

/* The highest power over a coarse grid of spacing `step` on the half
 * plane k_v >= 0 (P(-k) = P(k)), among the k with r->min <= |k| <=
 * r->limit: *best (-1 when none), at (*bu, *bv). Along a row each point's
 * phasor advances by a fixed rotation, so a grid point costs one complex
 * multiply-add per point. */
static relief_status freq_coarse_peak(const double *suv, const double *sf, size_t m,
                                      double step, const relief_measure_freq *r, double *best,
                                      double *bu, double *bv, relief_error *err)
{
    const long nu = (long)ceil(r->limit / step), nvk = nu;
    double *acc = malloc((size_t)(2 * nu + 1) * 2 * sizeof *acc);
    if (!acc)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a %ld-wide spectrum row",
                           2 * nu + 1);
    for (long iv = 0; iv <= nvk; ++iv) {
        const double kv = (double)iv * step, ku0 = -(double)nu * step;
        memset(acc, 0, (size_t)(2 * nu + 1) * 2 * sizeof *acc);
        for (size_t i = 0; i < m; ++i) {
            double ph = 2.0 * RELIEF_PI * (ku0 * suv[2 * i] + kv * suv[2 * i + 1]);
            double dph = 2.0 * RELIEF_PI * step * suv[2 * i];
            double zr = sf[i] * cos(ph), zi = sf[i] * sin(ph), wr = cos(dph), wi = sin(dph);
            for (long iu = 0; iu <= 2 * nu; ++iu) {
                double t = zr * wr - zi * wi;
                acc[2 * iu] += zr;
                acc[2 * iu + 1] += zi;
                zi = zr * wi + zi * wr;
                zr = t;
            }
        }
        for (long iu = 0; iu <= 2 * nu; ++iu) {
            double ku = ku0 + (double)iu * step, kk = sqrt(ku * ku + kv * kv);
            double p = acc[2 * iu] * acc[2 * iu] + acc[2 * iu + 1] * acc[2 * iu + 1];
            if (kk >= r->min && kk <= r->limit && p > *best) {
                *best = p;
                *bu = ku;
                *bv = kv;
            }
        }
    }
    free(acc);
    return RELIEF_OK;
}

/* Pattern search from the coarse peak (*bu, *bv), of power best, to the
 * continuous spectrum's local peak, never below |k| = kmin. */
static void freq_refine_peak(const double *suv, const double *sf, size_t m, double step,
                             double kmin, double best, double *bu, double *bv)
{
    double h = 0.5 * step;
    for (int it = 0; it < 200 && h > 1e-4 * step; ++it) {
        double nbu = *bu, nbv = *bv, nbest = best;
        for (int du = -1; du <= 1; ++du)
            for (int dv = -1; dv <= 1; ++dv) {
                double ku = *bu + du * h, kv = *bv + dv * h, p;
                if ((du == 0 && dv == 0) || sqrt(ku * ku + kv * kv) < kmin)
                    continue;
                p = power_at(suv, sf, m, ku, kv);
                if (p > nbest) {
                    nbest = p;
                    nbu = ku;
                    nbv = kv;
                }
            }
        if (nbest > best) {
            best = nbest;
            *bu = nbu;
            *bv = nbv;
        } else {
            h *= 0.5;
        }
    }
}

/* The larger side of the bounding box of the n points uv (n x 2), in uv's
 * units: the longest wavelength the spectrum looks for. */
static double freq_extent(const double *uv, size_t n)
{
    double lo[2], hi[2];
    lo[0] = hi[0] = uv[0];
    lo[1] = hi[1] = uv[1];
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 2; ++c) {
            lo[c] = uv[2 * i + c] < lo[c] ? uv[2 * i + c] : lo[c];
            hi[c] = uv[2 * i + c] > hi[c] ? uv[2 * i + c] : hi[c];
        }
    return hi[0] - lo[0] > hi[1] - lo[1] ? hi[0] - lo[0] : hi[1] - lo[1];
}

/* The spectrum's peak over the subset suv (m x 2), sf (m, mean removed,
 * var its sum of squares) into r->k and r->freq (cycles per uv unit),
 * within r->min..r->limit; left as they are (NaN) when the relief is flat
 * against the extent L or no frequency is in range. */
static relief_status freq_peak(const double *suv, const double *sf, size_t m, double var,
                               double L, relief_measure_freq *r, relief_error *err)
{
    double step, best = -1.0, bu = 0.0, bv = 0.0;
    relief_status st;
    /* Rounding noise (a part flattened onto a curved primitive keeps
     * |h| ~ 1e-16) is no relief: its peak would be meaningless. */
    if (!(sqrt(var / (double)m) > RELIEF_MEASURE_FREQ_FLAT * L) || r->min > r->limit)
        return RELIEF_OK;
    step = 1.0 / (2.0 * L);
    if (step < r->limit / RELIEF_MEASURE_FREQ_GRID)
        step = r->limit / RELIEF_MEASURE_FREQ_GRID;
    st = freq_coarse_peak(suv, sf, m, step, r, &best, &bu, &bv, err);
    if (st != RELIEF_OK || best < 0.0)
        return st;
    freq_refine_peak(suv, sf, m, step, r->min, best, &bu, &bv);
    r->k[0] = bu;
    r->k[1] = bv;
    r->freq = sqrt(bu * bu + bv * bv);
    return RELIEF_OK;
}

relief_status relief_dominant_frequency(const double *uv, const double *f, size_t n,
                                        relief_measure_freq *out, relief_error *err)
{
    relief_measure_freq r;
    double *suv = NULL, *sf = NULL;
    size_t *pick = NULL, m = n;
    relief_status st = RELIEF_OK;
    double var, L, spacing = 0.0;

    r.freq = NAN;
    r.k[0] = r.k[1] = NAN;
    r.limit = NAN;
    r.min = NAN;
    r.n_points = 0;
    if (n < 4) {
        *out = r;
        return RELIEF_OK;
    }
    if (n > INT_MAX)
        return relief_fail(err, RELIEF_E_RANGE,
                           "spectrum of %zu points: the nearest-neighbour search takes at "
                           "most %d",
                           n, INT_MAX);

    L = freq_extent(uv, n);
    st = median_spacing(uv, n, &spacing, err);
    if (st != RELIEF_OK)
        return st;
    if (!(L > 0.0) || !(spacing > 0.0)) {
        *out = r;
        return RELIEF_OK;
    }
    r.limit = 1.0 / (2.0 * spacing);
    r.min = 1.0 / L;

    if (m > RELIEF_MEASURE_FREQ_MAX_POINTS)
        m = RELIEF_MEASURE_FREQ_MAX_POINTS;
    suv = malloc(2 * m * sizeof *suv);
    sf = malloc(m * sizeof *sf);
    pick = malloc(n * sizeof *pick);
    if (!suv || !sf || !pick) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a spectrum of %zu points", m);
        goto done;
    }
    var = freq_subset(uv, f, n, m, pick, suv, sf);
    r.n_points = m;
    st = freq_peak(suv, sf, m, var, L, &r, err);

done:
    if (st == RELIEF_OK)
        *out = r;
    free(pick);
    free(sf);
    free(suv);
    return st;
}

/* Dominant frequency of h over the vertices of m labelled `want`. */
static relief_status part_frequency(const relief_domain *pm, const relief_mesh *m, int want,
                                    relief_measure_freq *out, relief_error *err)
{
    double *uv = malloc(2 * m->nv * sizeof *uv), *f = malloc(m->nv * sizeof *f);
    relief_status st;
    size_t n = 0;
    if (!uv || !f) {
        free(uv);
        free(f);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a %zu-point spectrum", m->nv);
    }
    relief_measure_part_uv(pm, m, want, uv);
    for (size_t v = 0; v < m->nv; ++v)
        if (m->label[v] == want)
            f[n++] = relief_fit_distance(&pm->prim, m->pos + 3 * v);
    st = relief_dominant_frequency(uv, f, n, out, err);
    free(f);
    free(uv);
    return st;
}

/* -------------------------------------------------------------- truth */

/* The truth as truth_heights reads it: its vertices projected on the
 * primitive (tq, nv x 3), their heights above it (th), and each vertex's
 * triangles (vt_start, vt: relief_mesh_vertex_triangles). */
typedef struct truth_view {
    const relief_mesh *tm;
    const double *tq, *th;
    const uint32_t *vt_start, *vt;
    size_t nv;
} truth_view;

/* The truth's height at the projected place q, interpolated in the
 * projected triangle around q best (its least barycentric weight the
 * largest) among the triangles of q's k nearest truth vertices nb: 1.
 * When q lies in none of them (beyond BARY_EPS), the nearest vertex's
 * height: 0. */
static int height_at(const truth_view *tv, const double *q, const int *nb, int k, double *h)
{
    double bscore = -INFINITY, bw[3] = {0, 0, 0};
    size_t bt = 0;
    for (int j = 0; j < k; ++j) {
        if (nb[j] < 0 || (size_t)nb[j] >= tv->nv)
            continue;
        for (uint32_t e = tv->vt_start[nb[j]]; e < tv->vt_start[nb[j] + 1]; ++e) {
            const uint32_t *t = tv->tm->tri + 3 * tv->vt[e];
            const double *a = tv->tq + 3 * t[0], *b = tv->tq + 3 * t[1], *c = tv->tq + 3 * t[2];
            double w[3], wa, wb, wc, s;
            if (!relief_barycentric(q, a, b, c, w))
                continue; /* degenerate once projected */
            wa = w[0], wb = w[1], wc = w[2];
            s = wa < wb ? wa : wb;
            s = s < wc ? s : wc;
            if (s > bscore) {
                bscore = s;
                bt = tv->vt[e];
                bw[0] = wa, bw[1] = wb, bw[2] = wc;
            }
        }
    }
    if (bscore >= -BARY_EPS) {
        const uint32_t *t = tv->tm->tri + 3 * bt;
        double sw = 0.0, sh = 0.0;
        for (int c = 0; c < 3; ++c) {
            double w = bw[c] > 0.0 ? bw[c] : 0.0;
            sw += w;
            sh += w * tv->th[t[c]];
        }
        *h = sh / sw;
        return 1;
    }
    *h = tv->th[nb[0]];
    return 0;
}

/* The k nearest truth vertices of each of the nq completed vertices'
 * projected places qq (nq x 3) among the nv projected truth vertices tq
 * (nv x 3): idx and d2 (nq x k each; squared distances), searched exactly. */
static relief_status truth_knn(double *tq, size_t nv, double *qq, size_t nq, int k, int *idx,
                               double *d2, relief_error *err)
{
    struct FLANNParameters fp = relief_knn_exact_params();
    float speedup = 0.0f;
    relief_status st = RELIEF_OK;
    flann_index_t index = flann_build_index_double(tq, (int)nv, 3, &speedup, &fp);
    if (!index)
        return relief_fail(err, RELIEF_E_INTERNAL,
                           "FLANN could not build a kd-tree on %zu truth vertices", nv);
    if (flann_find_nearest_neighbors_index_double(index, qq, (int)nq, idx, d2, k, &fp) != 0)
        st = relief_fail(err, RELIEF_E_INTERNAL,
                         "FLANN nearest-neighbour search failed on %zu completed vertices", nq);
    flann_free_index_double(index, &fp);
    return st;
}

/* The truth's height at each of the nq projected places qq (nq x 3) into
 * ht_out (nq), from its k nearest truth vertices (idx, d2: truth_knn's):
 * the nearest's height when on the spot, else height_at's; outside (nq)
 * flags, and *n_outside counts, the places no truth triangle covers. */
static relief_status truth_lookup(const truth_view *tv, const double *qq, size_t nq,
                                  const int *idx, const double *d2, int k, double *ht_out,
                                  uint8_t *outside, size_t *n_outside, relief_error *err)
{
    const size_t nv = tv->nv;
    for (size_t i = 0; i < nq; ++i) {
        const double *q = qq + 3 * i;
        const int *nb = idx + (size_t)k * i;
        if (nb[0] < 0 || (size_t)nb[0] >= nv)
            return relief_fail(err, RELIEF_E_INTERNAL,
                               "FLANN returned truth vertex %d, outside 0..%zu", nb[0], nv - 1);
        outside[i] = 0;
        if (d2[(size_t)k * i] == 0.0) {
            ht_out[i] = tv->th[nb[0]];
            continue;
        }
        if (!height_at(tv, q, nb, k, ht_out + i)) {
            outside[i] = 1;
            ++*n_outside;
        }
    }
    return RELIEF_OK;
}

/* Truth heights at the completed vertices' places (see the header). */
static relief_status truth_heights(const relief_fit_primitive *prim, const relief_mesh *cm,
                                   const relief_mesh *tm, double *ht_out, uint8_t *outside,
                                   size_t *n_outside, relief_error *err)
{
    const size_t nv = tm->nv;
    double *tq = NULL, *th = NULL, *qq = NULL, *d2 = NULL;
    int *idx = NULL;
    uint32_t *vt_start = NULL, *vt = NULL;
    size_t nq = 0;
    const int k = nv < TRUTH_K ? (int)nv : TRUTH_K;
    truth_view tv;
    relief_status st = RELIEF_OK;

    *n_outside = 0;
    if (nv > INT_MAX || cm->nv > INT_MAX)
        return relief_fail(err, RELIEF_E_RANGE,
                           "truth lookup on %zu vertices: the nearest-neighbour search "
                           "takes at most %d",
                           nv > cm->nv ? nv : cm->nv, INT_MAX);
    tq = malloc(3 * nv * sizeof *tq);
    th = malloc(nv * sizeof *th);
    qq = malloc(3 * cm->nv * sizeof *qq);
    idx = malloc((size_t)k * cm->nv * sizeof *idx);
    d2 = malloc((size_t)k * cm->nv * sizeof *d2);
    vt_start = malloc((nv + 1) * sizeof *vt_start);
    vt = malloc((3 * tm->nt + 1) * sizeof *vt);
    if (!tq || !th || !qq || !idx || !d2 || !vt_start || !vt) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the truth lookup of %zu vertices",
                         nv);
        goto done;
    }
    for (size_t v = 0; v < nv; ++v) {
        th[v] = relief_fit_distance(prim, tm->pos + 3 * v);
        relief_fit_project(prim, tm->pos + 3 * v, tq + 3 * v);
    }
    relief_mesh_vertex_triangles(tm, vt_start, vt);
    tv = (truth_view){tm, tq, th, vt_start, vt, nv};

    for (size_t v = 0; v < cm->nv; ++v)
        if (cm->label[v] == RELIEF_LABEL_COMPLETED)
            relief_fit_project(prim, cm->pos + 3 * v, qq + 3 * nq++);
    st = truth_knn(tq, nv, qq, nq, k, idx, d2, err);
    if (st == RELIEF_OK)
        st = truth_lookup(&tv, qq, nq, idx, d2, k, ht_out, outside, n_outside, err);

done:
    free(vt);
    free(vt_start);
    free(d2);
    free(idx);
    free(qq);
    free(th);
    free(tq);
    return st;
}

/* ------------------------------------------------------------ measure */

/* Each vertex's height over the primitive (h, nv) and displacement from it
 * (D, nv x 3); the captured heights into ha, the others into hb. */
static void measure_heights(const relief_mesh *cm, const relief_fit_primitive *prim, double *h,
                            double *D, double *ha, size_t *na, double *hb, size_t *nb)
{
    *na = *nb = 0;
    for (size_t v = 0; v < cm->nv; ++v) {
        double n[3];
        h[v] = relief_fit_distance(prim, cm->pos + 3 * v);
        relief_fit_normal(prim, cm->pos + 3 * v, n);
        for (int c = 0; c < 3; ++c)
            D[3 * v + c] = h[v] * n[c];
        if (cm->label[v] == RELIEF_LABEL_CAPTURED)
            ha[(*na)++] = h[v];
        else
            hb[(*nb)++] = h[v];
    }
}

/* MSI: the mean |height| of each part and their difference. */
static void measure_msi(const double *ha, size_t na, const double *hb, size_t nb,
                        relief_measures *r)
{
    double sa = 0.0, sb = 0.0;
    for (size_t i = 0; i < na; ++i)
        sa += fabs(ha[i]);
    for (size_t i = 0; i < nb; ++i)
        sb += fabs(hb[i]);
    r->msi_captured = sa / (double)na;
    r->msi_completed = sb / (double)nb;
    if (r->msi_captured > 0.0)
        r->msi_diff_percent = 100.0 * fabs(r->msi_completed - r->msi_captured) / r->msi_captured;
    else
        r->msi_diff_percent = r->msi_completed == 0.0 ? 0.0 : NAN;
}

/* The histogram distances of the heights (h, nv; split into ha and hb)
 * and, with colour, of each channel (ha and hb then reused for them). */
static void measure_histograms(const relief_mesh *cm, const double *h, double *ha, size_t na,
                               double *hb, size_t nb, relief_measures *r)
{
    double lo = INFINITY, hi = -INFINITY;
    for (size_t v = 0; v < cm->nv; ++v) {
        lo = h[v] < lo ? h[v] : lo;
        hi = h[v] > hi ? h[v] : hi;
    }
    r->hist_distance_displacement = hist_distance(ha, na, hb, nb, lo, hi);
    r->hist_distance_colour = NAN;
    r->hist_distance_rgb[0] = r->hist_distance_rgb[1] = r->hist_distance_rgb[2] = NAN;
    if (!cm->col)
        return;
    r->has_colour = 1;
    r->hist_distance_colour = 0.0;
    for (int c = 0; c < 3; ++c) {
        na = nb = 0;
        for (size_t v = 0; v < cm->nv; ++v) {
            if (cm->label[v] == RELIEF_LABEL_CAPTURED)
                ha[na++] = cm->col[3 * v + c];
            else
                hb[nb++] = cm->col[3 * v + c];
        }
        r->hist_distance_rgb[c] = hist_distance(ha, na, hb, nb, 0.0, 1.0);
        r->hist_distance_colour += r->hist_distance_rgb[c] / 3.0;
    }
}

/* The seam: the mean jump of the displacement D (nv x 3) across the edges
 * joining the parts, against that across the capture's own edges. */
static relief_status measure_seam(const relief_mesh *cm, const double *D, relief_measures *r,
                                  relief_error *err)
{
    uint64_t *edges = NULL;
    size_t ne = 0;
    double ss = 0.0, si = 0.0;
    relief_status st = unique_edges(cm, &edges, &ne, err);
    if (st != RELIEF_OK)
        return st;
    for (size_t e = 0; e < ne; ++e) {
        size_t a = (size_t)(edges[e] >> 32), b = (size_t)(edges[e] & 0xffffffffu);
        int la = cm->label[a], lb = cm->label[b];
        double dx = D[3 * a] - D[3 * b], dy = D[3 * a + 1] - D[3 * b + 1],
               dz = D[3 * a + 2] - D[3 * b + 2], jump = sqrt(dx * dx + dy * dy + dz * dz);
        /* Per unit of edge length on the primitive: the capture's edges are
         * oversampled to half the length of the seam's, and a jump grows
         * with the edge it spans. */
        double px = (cm->pos[3 * a] - D[3 * a]) - (cm->pos[3 * b] - D[3 * b]);
        double py = (cm->pos[3 * a + 1] - D[3 * a + 1]) - (cm->pos[3 * b + 1] - D[3 * b + 1]);
        double pz = (cm->pos[3 * a + 2] - D[3 * a + 2]) - (cm->pos[3 * b + 2] - D[3 * b + 2]);
        double len = sqrt(px * px + py * py + pz * pz);
        if (!(len > 0.0))
            continue;
        jump /= len;
        if (la != lb) {
            ss += jump;
            ++r->n_seam_edges;
        } else if (la == RELIEF_LABEL_CAPTURED) {
            si += jump;
            ++r->n_inside_edges;
        }
    }
    r->seam = r->n_seam_edges ? ss / (double)r->n_seam_edges : NAN;
    r->inside = r->n_inside_edges ? si / (double)r->n_inside_edges : NAN;
    r->seam_ratio = r->inside > 0.0 ? r->seam / r->inside : NAN;
    free(edges);
    return RELIEF_OK;
}

/* Against the truth tm: the completed heights' errors (h, cm's nv) where
 * the truth is, apart where it is not, and the truth's own spectrum. */
static relief_status measure_truth(const relief_mesh *cm, const relief_mesh *tm,
                                   const relief_domain *pm, const double *h, relief_measures *r,
                                   relief_error *err)
{
    double s2 = 0.0, s2_out = 0.0, mx = 0.0;
    size_t i = 0, n_in;
    double *ht = malloc(r->n_completed * sizeof *ht);
    uint8_t *out_flag = malloc(r->n_completed ? r->n_completed : 1); /* outside the truth */
    relief_status st;
    if (!ht || !out_flag) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate %zu truth heights",
                         r->n_completed);
        goto done;
    }
    st = truth_heights(&r->prim, cm, tm, ht, out_flag, &r->n_truth_outside, err);
    if (st != RELIEF_OK)
        goto done;
    /* Only where the truth is: a completed vertex past the truth's outline
     * has nothing to be compared with, and the nearest truth vertex's
     * height would pass a guess off as an error. */
    for (size_t v = 0; v < cm->nv; ++v)
        if (cm->label[v] == RELIEF_LABEL_COMPLETED) {
            double d = h[v] - ht[i];
            if (out_flag[i++]) {
                s2_out += d * d;
                continue;
            }
            s2 += d * d;
            mx = fabs(d) > mx ? fabs(d) : mx;
        }
    n_in = r->n_completed - r->n_truth_outside;
    if (n_in > 0) {
        r->truth_rms = sqrt(s2 / (double)n_in);
        r->truth_max_abs = mx;
    }
    if (r->n_truth_outside > 0)
        r->truth_rms_outside = sqrt(s2_out / (double)r->n_truth_outside);
    st = part_frequency(pm, tm, RELIEF_LABEL_COMPLETED, &r->freq_truth, err);
done:
    free(ht);
    free(out_flag);
    return st;
}

relief_status relief_measure(const relief_mesh *cm, const relief_mesh *tm,
                             const relief_fit_primitive *prim, relief_measures *out,
                             relief_error *err)
{
    relief_measures r;
    relief_domain pm;
    relief_status st;
    double *h = NULL, *D = NULL, *ha = NULL, *hb = NULL;
    size_t na, nb;

    if (!cm || !out)
        return relief_fail(err, RELIEF_E_USAGE, "relief_measure: %s is NULL",
                           !cm ? "the completed mesh" : "out");
    memset(&r, 0, sizeof r);
    st = relief_measure_check_parts(cm, tm, &r.n_captured, &r.n_completed, &r.n_truth_missing,
                                    err);
    if (st != RELIEF_OK)
        return st;
    r.has_truth = tm != NULL;

    if (prim) {
        r.prim = *prim;
    } else {
        st = relief_measure_fit_captured(cm, &r.fit, err);
        if (st != RELIEF_OK)
            return st;
        r.prim = r.fit.prim;
        r.fitted = 1;
    }
    relief_domain_init(&pm, &r.prim);

    h = malloc(cm->nv * sizeof *h);
    D = malloc(3 * cm->nv * sizeof *D);
    ha = malloc(r.n_captured * sizeof *ha);
    hb = malloc(r.n_completed * sizeof *hb);
    if (!h || !D || !ha || !hb) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the heights of %zu vertices",
                         cm->nv);
        goto done;
    }
    measure_heights(cm, &r.prim, h, D, ha, &na, hb, &nb);
    measure_msi(ha, na, hb, nb, &r);
    measure_histograms(cm, h, ha, na, hb, nb, &r);
    st = measure_seam(cm, D, &r, err);
    /* Spectra. */
    if (st == RELIEF_OK)
        st = part_frequency(&pm, cm, RELIEF_LABEL_CAPTURED, &r.freq_captured, err);
    if (st == RELIEF_OK)
        st = part_frequency(&pm, cm, RELIEF_LABEL_COMPLETED, &r.freq_completed, err);
    if (st != RELIEF_OK)
        goto done;
    r.truth_rms = r.truth_max_abs = r.truth_rms_outside = NAN;
    r.freq_truth.freq = r.freq_truth.limit = r.freq_truth.min = NAN;
    r.freq_truth.k[0] = r.freq_truth.k[1] = NAN;
    if (tm)
        st = measure_truth(cm, tm, &pm, h, &r, err);

done:
    if (st == RELIEF_OK)
        *out = r;
    free(hb);
    free(ha);
    free(D);
    free(h);
    return st;
}

/* --------------------------------------------------------------- JSON */

static void freq_fields(relief_json *j, const char *key, const relief_measure_freq *f)
{
    rj_begin_object(j, key);
    rj_number(j, "freq", f->freq);
    rj_begin_array(j, "k");
    rj_number(j, NULL, f->k[0]);
    rj_number(j, NULL, f->k[1]);
    rj_end_array(j);
    rj_number(j, "min", f->min);
    rj_number(j, "limit", f->limit);
    rj_int(j, "points", (long long)f->n_points);
    rj_end_object(j);
}

void relief_report_measures_fields(relief_json *j, const relief_measures *m)
{
    const relief_fit_primitive *p = &m->prim;

    rj_int(j, "n_captured", (long long)m->n_captured);
    rj_int(j, "n_completed", (long long)m->n_completed);
    rj_begin_object(j, "primitive");
    relief_report_primitive_fields(j, p);
    rj_string(j, "source", m->fitted ? "fitted to the captured part (auto)" : "given");
    rj_end_object(j);
    if (m->fitted) {
        rj_begin_object(j, "fit");
        relief_report_fit_fields(j, &m->fit);
        rj_end_object(j);
    }

    rj_number(j, "msi_captured", m->msi_captured);
    rj_number(j, "msi_completed", m->msi_completed);
    rj_number(j, "msi_diff_percent", m->msi_diff_percent);
    rj_int(j, "hist_bins", RELIEF_MEASURE_HIST_BINS);
    rj_number(j, "hist_distance_displacement", m->hist_distance_displacement);
    rj_bool(j, "colour", m->has_colour);
    if (m->has_colour) {
        rj_number(j, "hist_distance_colour", m->hist_distance_colour);
        rj_vec3(j, "hist_distance_rgb", m->hist_distance_rgb);
    }
    rj_number(j, "seam", m->seam);
    rj_number(j, "inside", m->inside);
    rj_number(j, "seam_ratio", m->seam_ratio);
    rj_int(j, "seam_edges", (long long)m->n_seam_edges);
    rj_int(j, "inside_edges", (long long)m->n_inside_edges);
    rj_number(j, "freq_captured", m->freq_captured.freq);
    rj_number(j, "freq_completed", m->freq_completed.freq);
    if (m->has_truth) {
        rj_number(j, "truth_rms", m->truth_rms);
        rj_number(j, "truth_max_abs", m->truth_max_abs);
        rj_int(j, "truth_outside", (long long)m->n_truth_outside);
        rj_number(j, "truth_rms_outside", m->truth_rms_outside);
        rj_int(j, "n_truth_missing", (long long)m->n_truth_missing);
        rj_number(j, "freq_truth", m->freq_truth.freq);
    }
    rj_begin_object(j, "spectrum");
    freq_fields(j, "captured", &m->freq_captured);
    freq_fields(j, "completed", &m->freq_completed);
    if (m->has_truth)
        freq_fields(j, "truth", &m->freq_truth);
    rj_end_object(j);
}
