#include "report/pattern.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/vec3.h"
#include "mesh/mesh.h"
#include "report/measures.h"
#include "report/pattern_grid.h"
#include "report/pattern_layout.h"


enum {
    NO = RELIEF_PATTERN_ORIENT_BINS,
    NR = RELIEF_PATTERN_RADIAL_BINS,
    KG = RELIEF_PATTERN_KGRID,
    NF = RELIEF_PATTERN_FIELDS,
    KERN_MAX = 32 /* most taps either side of the tensor's smoothing */
};

/* ------------------------------------------------------------ helpers */

static void part_nan(relief_pattern_part *p)
{
    for (int o = 0; o < NO; ++o) {
        for (int r = 0; r < NR; ++r)
            p->spectrum[o][r] = NAN;
        p->orientation[o] = NAN;
        p->tensor[o] = NAN;
    }
    for (int r = 0; r < NR; ++r)
        p->radial[r] = NAN;
    p->coherence = NAN;
    p->spacing = p->dominant = p->lean_rms = p->lean_across = NAN;
}

/* Total variation between two histograms of n bins; NaN if either is. */
static double tv(const double *p, const double *q, int n)
{
    double s = 0.0;
    for (int b = 0; b < n; ++b)
        s += fabs(p[b] - q[b]);
    return 0.5 * s; /* NaN propagates */
}

static void distances(const relief_pattern_part *a, const relief_pattern_part *b,
                      relief_pattern_distance *d)
{
    d->spectrum = tv(&a->spectrum[0][0], &b->spectrum[0][0], NO * NR);
    d->orientation = tv(a->orientation, b->orientation, NO);
    d->radial = tv(a->radial, b->radial, NR);
    d->tensor = tv(a->tensor, b->tensor, NO);
    d->lean = fabs(a->lean_across - b->lean_across);
}

/* Share weight w between the two orientation bins nearest theta (radians,
 * any value; bin b centred on b pi / NO), circularly. */
static void orient_add(double *bins, double theta, double w)
{
    double x = theta / (RELIEF_PI / NO), b0 = floor(x), fr = x - b0;
    long b = (long)b0 % NO;
    if (b < 0)
        b += NO;
    bins[b] += (1.0 - fr) * w;
    bins[(b + 1) % NO] += fr * w;
}

/* ----------------------------------------------------------- spectrum */

/* Power and its bins, summed over the wave numbers in the band. */
typedef struct spectrum_sum {
    double hist[NO][NR]; /* power by orientation and log |k| scale */
    double total;        /* all the power */
    double sk;           /* power times |k| (cycles per input unit) */
} spectrum_sum;

/* The taper-weighted field with its weighted mean removed: fw[v] for the
 * nx ny nodes (the field's units). */
static void spectrum_field(const part_grid *gr, int f, const double *taper, double *fw)
{
    const size_t nn = gr->nx * gr->ny;
    double sw = 0.0, mean = 0.0;
    for (size_t v = 0; v < nn; ++v) {
        sw += taper[v];
        mean += taper[v] * gr->val[f][v];
    }
    mean /= sw;
    for (size_t v = 0; v < nn; ++v)
        fw[v] = taper[v] * (gr->val[f][v] - mean);
}

/* The transform along u of each of the ny rows of fw (nx x ny) at the
 * 2 KG + 1 wave numbers iu dk, iu = -KG..KG: A, ny x (2 KG + 1) complex
 * values (re, im), row-major. tc, ts: the 2 KG phase table. */
static void spectrum_rows(const double *fw, size_t nx, size_t ny, const double *tc,
                          const double *ts, double *A)
{
    const size_t nku = 2 * KG + 1;
    for (size_t j = 0; j < ny; ++j) {
        const double *row = fw + j * nx;
        for (long iu = -KG; iu <= KG; ++iu) {
            const long stepm = ((iu % (2 * KG)) + 2 * KG) % (2 * KG);
            long m = 0;
            double re = 0.0, im = 0.0;
            for (size_t i = 0; i < nx; ++i) {
                re += row[i] * tc[m];
                im += row[i] * ts[m];
                m += stepm;
                if (m >= 2 * KG)
                    m -= 2 * KG;
            }
            A[2 * (j * nku + (size_t)(iu + KG))] = re;
            A[2 * (j * nku + (size_t)(iu + KG)) + 1] = im;
        }
    }
}

/* Add power p at wave vector (iu, iv) dk, |k| = kk, to the histogram:
 * shared between the two nearest scale bins, linear in log |k| between
 * the bin centres (lr = log(k_max / k_min)), and the two nearest
 * orientation bins. */
static void spectrum_bin(spectrum_sum *s, long iu, long iv, double kk, double p, double k_min,
                         double lr)
{
    double x, y;
    int r0;
    s->total += p;
    s->sk += p * kk;
    y = log(kk / k_min) / lr * NR - 0.5;
    x = y <= 0.0 ? 0.0 : y >= NR - 1 ? NR - 1 : y;
    r0 = (int)floor(x);
    if (r0 >= NR - 1)
        r0 = NR - 2;
    {
        double fr = x - r0, ob[NO] = {0};
        orient_add(ob, atan2((double)iv, (double)iu), p);
        for (int o = 0; o < NO; ++o) {
            s->hist[o][r0] += (1.0 - fr) * ob[o];
            s->hist[o][r0 + 1] += fr * ob[o];
        }
    }
}

/* The transform along v of A (spectrum_rows) over the half plane
 * k_v >= 0, each wave number with k_min <= |k| <= k_max (cycles per
 * input unit, dk apart) into s. */
static void spectrum_columns(const double *A, size_t ny, const double *tc, const double *ts,
                             double dk, double k_min, double k_max, spectrum_sum *s)
{
    const size_t nku = 2 * KG + 1;
    const double lr = log(k_max / k_min);
    for (long iv = 0; iv <= KG; ++iv)
        for (long iu = -KG; iu <= KG; ++iu) {
            double re = 0.0, im = 0.0, kk;
            long m = 0;
            if (iv == 0 && iu <= 0)
                continue; /* -k of a k already counted, or k = 0 */
            kk = dk * sqrt((double)(iu * iu + iv * iv));
            if (kk < k_min || kk > k_max)
                continue;
            for (size_t j = 0; j < ny; ++j) {
                const double *a = A + 2 * (j * nku + (size_t)(iu + KG));
                re += a[0] * tc[m] - a[1] * ts[m];
                im += a[0] * ts[m] + a[1] * tc[m];
                m += iv;
                if (m >= 2 * KG)
                    m -= 2 * KG;
            }
            spectrum_bin(s, iu, iv, kk, re * re + im * im, k_min, lr);
        }
}

/* The part's spectrum, orientation and radial histograms (shares of the
 * total power) and spacing (1 / the power-weighted mean |k|, input
 * units) from s; left NaN when there is no power. */
static void spectrum_out(const spectrum_sum *s, relief_pattern_part *out)
{
    if (!(s->total > 0.0))
        return; /* stays NaN */
    for (int o = 0; o < NO; ++o) {
        out->orientation[o] = 0.0;
        for (int r = 0; r < NR; ++r)
            out->spectrum[o][r] = s->hist[o][r] / s->total;
    }
    for (int r = 0; r < NR; ++r)
        out->radial[r] = 0.0;
    out->spacing = s->total / s->sk; /* 1 / the power-weighted mean |k| */
    for (int o = 0; o < NO; ++o)
        for (int r = 0; r < NR; ++r) {
            out->orientation[o] += out->spectrum[o][r];
            out->radial[r] += out->spectrum[o][r];
        }
}

/* Binned power spectrum of field f on the grid (see the header, 1). */
static relief_status grid_spectrum(const part_grid *gr, int f, const double *taper,
                                   double k_min, double k_max, relief_pattern_part *out,
                                   relief_error *err)
{
    const size_t nx = gr->nx, ny = gr->ny, nku = 2 * KG + 1;
    const double dk = k_max / KG;
    double tc[2 * KG], ts[2 * KG];
    double *fw = malloc(nx * ny * sizeof *fw), *A = malloc(2 * ny * nku * sizeof *A);
    spectrum_sum s = {{{0}}, 0.0, 0.0};

    if (!fw || !A) {
        free(fw);
        free(A);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the spectrum of a %zu x %zu "
                                                "grid", nx, ny);
    }
    /* Node x_i = i g and k = iu dk with dk g = 1 / (2 KG): the phase
     * 2 pi k x is pi (iu i mod 2 KG) / KG, one table for both axes. */
    for (int m = 0; m < 2 * KG; ++m) {
        tc[m] = cos(RELIEF_PI * m / KG);
        ts[m] = -sin(RELIEF_PI * m / KG);
    }
    spectrum_field(gr, f, taper, fw);
    /* Along u, every row at once per wave number; then along v. */
    spectrum_rows(fw, nx, ny, tc, ts, A);
    spectrum_columns(A, ny, tc, ts, dk, k_min, k_max, &s);
    free(A);
    free(fw);
    spectrum_out(&s, out);
    return RELIEF_OK;
}

/* ------------------------------------------------------------- tensor */

/* Separable Gaussian smoothing of n_ch channels of an nx x ny grid, in
 * place (tmp: one channel's worth), zero outside the grid. */
static void smooth(double *const *ch, int n_ch, size_t nx, size_t ny, const double *kern,
                   long R, double *tmp)
{
    for (int c = 0; c < n_ch; ++c) {
        double *x = ch[c];
        for (size_t j = 0; j < ny; ++j)
            for (size_t i = 0; i < nx; ++i) {
                double s = 0.0;
                for (long a = -R; a <= R; ++a) {
                    long ii = (long)i + a;
                    if (ii >= 0 && ii < (long)nx)
                        s += kern[a + R] * x[j * nx + (size_t)ii];
                }
                tmp[j * nx + i] = s;
            }
        for (size_t j = 0; j < ny; ++j)
            for (size_t i = 0; i < nx; ++i) {
                double s = 0.0;
                for (long b = -R; b <= R; ++b) {
                    long jj = (long)j + b;
                    if (jj >= 0 && jj < (long)ny)
                        s += kern[b + R] * tmp[(size_t)jj * nx + i];
                }
                x[j * nx + i] = s;
            }
    }
}

/* The structure tensor's inputs at each node of field v (nx x ny) whose
 * four neighbours are inside: ch[0..2] = Juu, Juv, Jvv of the central
 * differences (the field's units squared), ch[3] = 1 and has = 1 there;
 * elsewhere left as they are (zero). */
static void tensor_gradients(const part_grid *gr, const double *v, double *const *ch,
                             uint8_t *has)
{
    const size_t nx = gr->nx, ny = gr->ny;
    for (size_t j = 1; j + 1 < ny; ++j)
        for (size_t i = 1; i + 1 < nx; ++i) {
            const size_t c = j * nx + i;
            double gu, gv;
            if (!gr->inside[c] || !gr->inside[c - 1] || !gr->inside[c + 1] ||
                !gr->inside[c - nx] || !gr->inside[c + nx])
                continue;
            gu = v[c + 1] - v[c - 1];
            gv = v[c + nx] - v[c - nx];
            ch[0][c] = gu * gu;
            ch[1][c] = gu * gv;
            ch[2][c] = gv * gv;
            ch[3][c] = 1.0;
            has[c] = 1;
        }
}

/* From the smoothed channels (tensor_gradients, nn nodes): z (2 nn, NaN
 * where no tensor), the coherence-weighted orientation histogram hist
 * (NO bins), the coherences' sum *sc and the count of nodes with a
 * tensor. */
static size_t tensor_orientations(double *const *ch, const uint8_t *has, size_t nn, double *z,
                                  double *hist, double *sc)
{
    size_t count = 0;
    for (size_t c = 0; c < nn; ++c) {
        double juu, juv, jvv, tr, zc, zs, coh;
        z[2 * c] = z[2 * c + 1] = NAN;
        if (!has[c])
            continue;
        /* Normalised convolution: the mean over the nodes that have a
         * gradient, so the outline does not pull J toward 0. */
        juu = ch[0][c] / ch[3][c];
        juv = ch[1][c] / ch[3][c];
        jvv = ch[2][c] / ch[3][c];
        tr = juu + jvv;
        if (!(tr > 0.0))
            continue;
        /* (zc, zs) = c (cos 2 theta, sin 2 theta), theta the major
         * eigenvector's angle. */
        zc = (juu - jvv) / tr;
        zs = 2.0 * juv / tr;
        coh = sqrt(zc * zc + zs * zs); /* (l1 - l2) / (l1 + l2) */
        coh = coh > 1.0 ? 1.0 : coh;
        z[2 * c] = zc;
        z[2 * c + 1] = zs;
        orient_add(hist, 0.5 * atan2(zs, zc), coh);
        *sc += coh;
        ++count;
    }
    return count;
}

/* Coherence-weighted orientation histogram of field f (header, 2); at
 * each node z = c (cos 2 theta, sin 2 theta), NaN without a tensor (2 per
 * node, for the layout). */
static relief_status grid_tensor(const part_grid *gr, int f, relief_pattern_part *out,
                                 double *z, relief_error *err)
{
    const size_t nx = gr->nx, ny = gr->ny, nn = nx * ny;
    const long R = (long)ceil(3.0 * RELIEF_PATTERN_TENSOR_SIGMA);
    double kern[2 * KERN_MAX + 1], hist[NO] = {0}, sc = 0.0;
    double *buf, *ch[4];
    uint8_t *has;
    size_t count;

    if (R > KERN_MAX)
        return relief_fail(err, RELIEF_E_INTERNAL, "RELIEF_PATTERN_TENSOR_SIGMA %g needs %ld "
                           "taps, more than %d", RELIEF_PATTERN_TENSOR_SIGMA, R, KERN_MAX);
    buf = calloc(5 * nn, sizeof *buf);
    has = calloc(nn, 1);
    if (!buf || !has) {
        free(buf);
        free(has);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the tensor of a %zu x %zu grid",
                           nx, ny);
    }
    for (int c = 0; c < 4; ++c)
        ch[c] = buf + (size_t)c * nn; /* Juu, Juv, Jvv, has-gradient; then tmp */
    for (long a = -R; a <= R; ++a)
        kern[a + R] = exp(-0.5 * (double)(a * a) /
                          (RELIEF_PATTERN_TENSOR_SIGMA * RELIEF_PATTERN_TENSOR_SIGMA));
    tensor_gradients(gr, gr->val[f], ch, has);
    smooth(ch, 4, nx, ny, kern, R, buf + 4 * nn);
    count = tensor_orientations(ch, has, nn, z, hist, &sc);
    free(has);
    free(buf);
    out->n_tensor_nodes = count;
    if (count)
        out->coherence = sc / (double)count;
    if (sc > 0.0)
        for (int o = 0; o < NO; ++o)
            out->tensor[o] = hist[o] / sc;
    return RELIEF_OK;
}

/* ------------------------------------------------------------ measure */

/* Both fields' histograms over one part, on a grid of step g. */
static relief_status analyse_part(const part_points *pp, double g, double k_min, double k_max,
                                  relief_pattern_part out[NF], relief_error *err)
{
    part_grid gr;
    double *taper = NULL, *z = NULL;
    relief_status st;

    for (int f = 0; f < NF; ++f) {
        part_nan(&out[f]);
        out[f].n_points = pp->n;
        out[f].n_nodes = out[f].n_tensor_nodes = 0;
    }
    if (!pattern_points_measurable(pp) || !(g > 0.0))
        return RELIEF_OK;
    st = pattern_grid_resample(pp, g, &gr, err);
    if (st != RELIEF_OK)
        return st;
    for (int f = 0; f < NF; ++f)
        out[f].n_nodes = gr.n_inside;
    if (gr.n_inside < RELIEF_PATTERN_MIN_NODES)
        goto done;
    taper = malloc(gr.nx * gr.ny * sizeof *taper);
    z = malloc(2 * gr.nx * gr.ny * sizeof *z);
    if (!taper || !z) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a %zu x %zu taper and tensor",
                         gr.nx, gr.ny);
        goto done;
    }
    pattern_grid_taper(&gr, taper);
    for (int f = 0; f < NF && st == RELIEF_OK; ++f) {
        if (!pp->f[f] || pattern_points_flat(pp, f, f == 0 ? pattern_points_long_side(pp) : 1.0))
            continue;
        if (k_min > 0.0 && k_min < k_max)
            st = grid_spectrum(&gr, f, taper, k_min, k_max, &out[f], err);
        if (st == RELIEF_OK)
            st = grid_tensor(&gr, f, &out[f], z, err);
        if (st == RELIEF_OK)
            pattern_layout(&gr, z, out[f].spacing, &out[f]);
    }
done:
    free(z);
    free(taper);
    pattern_grid_free(&gr);
    return st;
}

static void pattern_nan(relief_pattern *r)
{
    relief_pattern_distance dn = {NAN, NAN, NAN, NAN, NAN};
    for (int p = 0; p < 2; ++p) {
        part_nan(&r->height[p]);
        part_nan(&r->colour[p]);
        part_nan(&r->truth_height[p]);
        part_nan(&r->truth_colour[p]);
    }
    r->d_height = r->d_colour = r->d_truth_height = r->d_truth_colour = dn;
    r->step = r->k_min = r->k_max = NAN;
}

/* r (NaN measures) with the part counts and the primitive measured from:
 * prim when given, else fitted to cm's captured part. */
static relief_status measure_begin(const relief_mesh *cm, const relief_fit_primitive *prim,
                                   const relief_mesh *tm, relief_pattern *r, relief_error *err)
{
    relief_status st;
    memset(r, 0, sizeof *r);
    pattern_nan(r);
    st = relief_measure_check_parts(cm, tm, &r->n_captured, &r->n_completed, NULL, err);
    if (st != RELIEF_OK)
        return st;
    r->has_truth = tm != NULL;
    if (prim) {
        r->prim = *prim;
    } else {
        relief_fit_result fit;
        st = relief_measure_fit_captured(cm, &fit, err);
        if (st != RELIEF_OK)
            return st;
        r->prim = fit.prim;
        r->fitted = 1;
    }
    return RELIEF_OK;
}

/* One step and one band for every part (see the header): r->step, the
 * grid step (input units), and r->k_min, r->k_max (cycles per unit); the
 * step stays NaN when no part is measurable, the band also when the
 * parts are narrower than RELIEF_PATTERN_MIN_SIDE steps. */
static void measure_band(const part_points pts[2], relief_pattern *r)
{
    double g = 0.0, L = INFINITY;
    for (int p = 0; p < 2; ++p) {
        if (!pattern_points_measurable(&pts[p]))
            continue;
        g = pts[p].spacing > g ? pts[p].spacing : g;
        g = pattern_points_long_side(&pts[p]) / RELIEF_PATTERN_GRID_MAX > g
                ? pattern_points_long_side(&pts[p]) / RELIEF_PATTERN_GRID_MAX
                : g;
        L = pattern_points_short_side(&pts[p]) < L ? pattern_points_short_side(&pts[p]) : L;
    }
    if (g > 0.0 && isfinite(g)) {
        r->step = g;
        if (L >= RELIEF_PATTERN_MIN_SIDE * g) {
            r->k_min = 1.0 / L;
            r->k_max = 1.0 / (2.0 * g);
        }
    }
}

/* The completion's two parts (pts: loaded here, freed by the caller on
 * failure): the step and band, their measures and distances in r. */
static relief_status measure_completion(const relief_domain *pm, const relief_mesh *cm,
                                        int colour, part_points pts[2], relief_pattern *r,
                                        relief_error *err)
{
    relief_status st = RELIEF_OK;
    for (int p = 0; p < 2 && st == RELIEF_OK; ++p)
        st = pattern_points_load(pm, cm, p, colour, &pts[p], err);
    if (st != RELIEF_OK)
        return st;
    measure_band(pts, r);
    for (int p = 0; p < 2 && st == RELIEF_OK; ++p) {
        relief_pattern_part two[NF];
        st = analyse_part(&pts[p], r->step, r->k_min, r->k_max, two, err);
        r->height[p] = two[0];
        r->colour[p] = two[1];
    }
    if (st != RELIEF_OK)
        return st;
    distances(&r->height[0], &r->height[1], &r->d_height);
    if (colour)
        distances(&r->colour[0], &r->colour[1], &r->d_colour);
    for (int p = 0; p < 2; ++p)
        pattern_points_free(&pts[p]);
    return RELIEF_OK;
}

/* The truth's two parts on the completion's band (tpts: as pts in
 * measure_completion): their measures and distances in r. */
static relief_status measure_truth(const relief_domain *pm, const relief_mesh *tm,
                                   part_points tpts[2], relief_pattern *r, relief_error *err)
{
    relief_status st = RELIEF_OK;
    for (int p = 0; p < 2 && st == RELIEF_OK; ++p) {
        relief_pattern_part two[NF];
        double g = r->step;
        st = pattern_points_load(pm, tm, p, r->has_truth_colour, &tpts[p], err);
        if (st != RELIEF_OK)
            break;
        /* Bounded like the completion's grids; a coarser step leaves
         * the top scale bins empty rather than moving them. */
        if (pattern_points_measurable(&tpts[p]) &&
            pattern_points_long_side(&tpts[p]) / RELIEF_PATTERN_GRID_MAX > g)
            g = pattern_points_long_side(&tpts[p]) / RELIEF_PATTERN_GRID_MAX;
        st = analyse_part(&tpts[p], g, r->k_min, r->k_max, two, err);
        r->truth_height[p] = two[0];
        r->truth_colour[p] = two[1];
        pattern_points_free(&tpts[p]);
    }
    if (st != RELIEF_OK)
        return st;
    distances(&r->truth_height[0], &r->truth_height[1], &r->d_truth_height);
    if (r->has_truth_colour)
        distances(&r->truth_colour[0], &r->truth_colour[1], &r->d_truth_colour);
    return RELIEF_OK;
}

relief_status relief_pattern_measure(const relief_mesh *cm, const relief_fit_primitive *prim,
                                     const relief_mesh *tm, relief_pattern *out,
                                     relief_error *err)
{
    relief_pattern r;
    relief_domain pm;
    relief_status st;
    part_points pts[2], tpts[2];
    const int colour = cm && cm->col != NULL;

    memset(pts, 0, sizeof pts);
    memset(tpts, 0, sizeof tpts);
    if (!cm || !out)
        return relief_fail(err, RELIEF_E_USAGE, "relief_pattern_measure: %s is NULL",
                           !cm ? "the completed mesh" : "out");
    st = measure_begin(cm, prim, tm, &r, err);
    if (st != RELIEF_OK)
        return st;
    relief_domain_init(&pm, &r.prim);
    r.has_colour = colour;
    r.has_truth_colour = tm && colour && tm->col;

    st = measure_completion(&pm, cm, colour, pts, &r, err);
    if (st == RELIEF_OK && tm)
        st = measure_truth(&pm, tm, tpts, &r, err);
    for (int p = 0; p < 2; ++p) {
        pattern_points_free(&pts[p]);
        pattern_points_free(&tpts[p]);
    }
    if (st == RELIEF_OK)
        *out = r;
    return st;
}

/* --------------------------------------------------------------- JSON */

static void numbers(relief_json *j, const char *key, const double *x, int n)
{
    rj_begin_array(j, key);
    for (int i = 0; i < n; ++i)
        rj_number(j, NULL, x[i]);
    rj_end_array(j);
}

static void part_fields(relief_json *j, const char *key, const relief_pattern_part *p)
{
    rj_begin_object(j, key);
    rj_int(j, "points", (long long)p->n_points);
    rj_int(j, "nodes", (long long)p->n_nodes);
    rj_int(j, "tensor_nodes", (long long)p->n_tensor_nodes);
    rj_number(j, "coherence", p->coherence);
    rj_number(j, "spacing", p->spacing);
    rj_number(j, "dominant_orientation", p->dominant);
    rj_number(j, "lean_rms", p->lean_rms);
    rj_number(j, "lean_across", p->lean_across);
    numbers(j, "orientation", p->orientation, NO);
    numbers(j, "radial", p->radial, NR);
    numbers(j, "tensor", p->tensor, NO);
    rj_end_object(j);
}

static void distance_fields(relief_json *j, const char *suffix,
                            const relief_pattern_distance *d)
{
    char key[64];
    snprintf(key, sizeof key, "pattern_spectrum_distance%s", suffix);
    rj_number(j, key, d->spectrum);
    snprintf(key, sizeof key, "pattern_orientation_distance%s", suffix);
    rj_number(j, key, d->orientation);
    snprintf(key, sizeof key, "pattern_radial_distance%s", suffix);
    rj_number(j, key, d->radial);
    snprintf(key, sizeof key, "pattern_tensor_distance%s", suffix);
    rj_number(j, key, d->tensor);
    snprintf(key, sizeof key, "pattern_lean_distance%s", suffix);
    rj_number(j, key, d->lean);
}

/* The parts' lean-across shares as top-level keys. */
static void lean_fields(relief_json *j, const char *suffix, const relief_pattern_part *a,
                        const relief_pattern_part *t)
{
    static const char *const part[] = {"captured", "completed", "truth_captured",
                                       "truth_missing"};
    char key[64];
    for (int i = 0; i < (t ? 4 : 2); ++i) {
        snprintf(key, sizeof key, "pattern_lean_across_%s%s", part[i], suffix);
        rj_number(j, key, i < 2 ? a[i].lean_across : t[i - 2].lean_across);
    }
}

void relief_pattern_json_fields(relief_json *j, const relief_pattern *p)
{
    distance_fields(j, "", &p->d_height);
    if (p->has_colour)
        distance_fields(j, "_colour", &p->d_colour);
    if (p->has_truth)
        distance_fields(j, "_truth", &p->d_truth_height);
    if (p->has_truth_colour)
        distance_fields(j, "_colour_truth", &p->d_truth_colour);
    lean_fields(j, "", p->height, p->has_truth ? p->truth_height : NULL);
    if (p->has_colour)
        lean_fields(j, "_colour", p->colour, p->has_truth_colour ? p->truth_colour : NULL);
    rj_begin_object(j, "pattern");
    rj_number(j, "step", p->step);
    rj_number(j, "k_min", p->k_min);
    rj_number(j, "k_max", p->k_max);
    rj_int(j, "orientation_bins", NO);
    rj_int(j, "radial_bins", NR);
    for (int f = 0; f < 2; ++f) {
        const relief_pattern_part *a = f ? p->colour : p->height;
        const relief_pattern_part *t = f ? p->truth_colour : p->truth_height;
        if (f && !p->has_colour)
            continue;
        rj_begin_object(j, f ? "colour" : "height");
        part_fields(j, "captured", &a[0]);
        part_fields(j, "completed", &a[1]);
        if (f ? p->has_truth_colour : p->has_truth) {
            part_fields(j, "truth_captured", &t[0]);
            part_fields(j, "truth_missing", &t[1]);
        }
        rj_end_object(j);
    }
    rj_end_object(j);
}
