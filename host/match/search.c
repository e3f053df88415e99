/* The k-coherence search (search.h). */
#include "match/search.h"

#include <flann/flann.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/clock.h"
#include "base/error.h"
#include "base/knn.h"
#include "base/linalg.h"
#include "base/parallel.h"
#include "base/pool.h"
#include "base/vec3.h"

#define RM_REAL float
#define RM_WITH_SCORING
#include "kernels/relief_math.h"

#define POINTS (1 + RELIEF_SEARCH_RINGS * RELIEF_SEARCH_ANGLES)
/* The descriptor's covariance (shape and colour) goes to relief_sym_eigen. */
_Static_assert(2 * POINTS <= RELIEF_SYM_EIGEN_MAX && RELIEF_SEARCH_DIMS <= 2 * POINTS,
               "RELIEF_SEARCH_RINGS x ANGLES too many for the descriptor's eigen-solver");
#define PCA_ROWS 65536 /* descriptors the principal components are taken over */
#define OVERQUERY 8    /* neighbours asked of FLANN per pair wanted: the rest
                          are the pair's own neighbourhood on the surface */
#define CHUNK 4096     /* pairs per FLANN query */

struct relief_search {
    uint32_t ns;
    int rotations, k;
    uint32_t *sim;   /* ns x k: (s, 0)'s similar pairs s' x R + r', UINT32_MAX
                        where fewer were found; (s, r)'s are (s', r' + r) */
    uint32_t *stamp; /* ns: the call that last listed each sample */
    uint32_t now;
    uint32_t *cand;  /* ns: the candidates of the last call */
    double seconds;
};

size_t relief_search_bytes(size_t ns, int rotations, int k)
{
    const size_t pairs = ns * (size_t)rotations;
    const size_t pca = pairs < PCA_ROWS ? pairs : PCA_ROWS;
    /* Reduced descriptors, the similar pairs, FLANN's tree (about one index
     * and a node per point) and its answers for a chunk of pairs, the stamps and
     * the candidates; while they are set up, the principal components' rows. */
    return pca * 2 * POINTS * sizeof(float) +
           pairs * (RELIEF_SEARCH_DIMS * sizeof(float) + 3 * sizeof(uint32_t)) +
           ns * (size_t)k * sizeof(uint32_t) +
           (size_t)CHUNK * (size_t)(OVERQUERY * k + 1) * (sizeof(int) + sizeof(float)) +
           2 * ns * sizeof(uint32_t);
}

/* What every descriptor shares: point p's place (x0, y0) before the
 * rotation and its weights, worked out once rather than per pair (the
 * same floats: each is a function of p, step and mu alone). */
typedef struct ring_points {
    float x0[POINTS], y0[POINTS], wshape[POINTS], wcol[POINTS];
} ring_points;

static void ring_points_init(const relief_match_data *d, float step, ring_points *rp)
{
    for (int p = 0; p < POINTS; ++p) {
        const int ring = p == 0 ? 0 : 1 + (p - 1) / RELIEF_SEARCH_ANGLES;
        const int angle = p == 0 ? 0 : (p - 1) % RELIEF_SEARCH_ANGLES;
        const float rho = (float)ring * step;
        const double phi = 2.0 * RELIEF_PI * angle / RELIEF_SEARCH_ANGLES;
        const float rel = (float)ring / RELIEF_SEARCH_RINGS;
        const float g = expf(-0.5f * rel * rel);
        rp->x0[p] = rho * (float)cos(phi);
        rp->y0[p] = rho * (float)sin(phi);
        rp->wshape[p] = sqrtf(d->mu * g);
        rp->wcol[p] = sqrtf((1.0f - d->mu) * g);
    }
}

/* The descriptor of pair (si, r) into out[POINTS x (1 or 2)] (search.h). */
static void describe(const relief_match_data *d, const ring_points *rp, uint32_t si, int r,
                     float *out)
{
    const float *sp = d->s_proj + 3 * (size_t)si, *sf = d->s_frame + 9 * (size_t)si;
    const float cr = d->cos_r[r], sr = d->sin_r[r], inv_b = sqrtf(d->inv_b2);
    const int colour = d->mu < 1.0f;
    for (int p = 0; p < POINTS; ++p) {
        const float a = cr * rp->x0[p] - sr * rp->y0[p], b = sr * rp->x0[p] + cr * rp->y0[p];
        float x[3], h = 0.0f;
        uint32_t v2;
        for (int k = 0; k < 3; ++k)
            x[k] = sp[k] + a * sf[k] + b * sf[3 + k];
        v2 = rm_closest_vertex_listed(x, d->proj, d->cell_start, d->cell_items, d->grid,
                                      d->dims, d->lgrid, d->ldims, d->lmask, d->lslot,
                                      d->litems);
        for (int k = 0; k < 3; ++k)
            h += sf[6 + k] * (d->pos[3 * (size_t)v2 + k] - sp[k]);
        out[p] = rp->wshape[p] * h * inv_b;
        if (colour) {
            const float *c = d->col + 3 * (size_t)v2;
            out[POINTS + p] = rp->wcol[p] * (0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2]);
        }
    }
}

/* Descriptor rows shared over threads (relief_parallel_ranges): each row
 * is written by one thread alone, so the rows are the same bytes however
 * many run. Row i describes pair i x stride into desc; with axes set, row
 * i is pair i projected into red (from desc's row i when desc holds every
 * pair, else described anew). */
typedef struct desc_job {
    const relief_match_data *d;
    const ring_points *rp;
    int dims;
    size_t stride;
    float *desc;
    const double *mean, *axes;
    float *red;
} desc_job;

static int describe_rows(void *ctx, size_t lo, size_t hi)
{
    const desc_job *j = ctx;
    const size_t R = (size_t)j->d->rotations;
    float one[2 * POINTS];
    for (size_t i = lo; i < hi; ++i) {
        const size_t c = i * j->stride;
        describe(j->d, j->rp, (uint32_t)(c / R), (int)(c % R), one);
        memcpy(j->desc + i * (size_t)j->dims, one, (size_t)j->dims * sizeof *one);
    }
    return 0;
}

static int project_rows(void *ctx, size_t lo, size_t hi)
{
    const desc_job *j = ctx;
    const size_t R = (size_t)j->d->rotations;
    const int dims = j->dims;
    float one[2 * POINTS];
    for (size_t c = lo; c < hi; ++c) {
        const float *x = one;
        if (j->stride == 1)
            x = j->desc + c * (size_t)dims;
        else
            describe(j->d, j->rp, (uint32_t)(c / R), (int)(c % R), one);
        for (int a = 0; a < RELIEF_SEARCH_DIMS; ++a) {
            double sum = 0.0;
            for (int i = 0; i < dims; ++i)
                sum += j->axes[dims * a + i] * (x[i] - j->mean[i]);
            j->red[c * RELIEF_SEARCH_DIMS + a] = (float)sum;
        }
    }
    return 0;
}

/* Principal axes of the rows of desc (rows x dims): mean[dims] and
 * axes[RELIEF_SEARCH_DIMS x dims] (row i the i-th axis). */
static relief_status principal_axes(const float *desc, size_t rows, int dims, double *mean,
                                    double *axes, relief_error *err)
{
    double *cov = calloc((size_t)dims * (size_t)dims, sizeof *cov);
    double *evec = malloc((size_t)dims * (size_t)dims * sizeof *evec);
    double *work = malloc(2 * (size_t)dims * (size_t)dims * sizeof *work);
    double eval[2 * POINTS];
    if (!cov || !evec || !work) {
        free(cov);
        free(evec);
        free(work);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the search's %d x %d "
                           "covariance over %zu descriptors", dims, dims, rows);
    }
    memset(mean, 0, (size_t)dims * sizeof *mean);
    for (size_t i = 0; i < rows; ++i)
        for (int k = 0; k < dims; ++k)
            mean[k] += desc[i * (size_t)dims + k];
    for (int k = 0; k < dims; ++k)
        mean[k] /= (double)rows;
    for (size_t r = 0; r < rows; ++r) {
        const float *x = desc + r * (size_t)dims;
        for (int i = 0; i < dims; ++i)
            for (int j = i; j < dims; ++j)
                cov[dims * i + j] += (x[i] - mean[i]) * (x[j] - mean[j]);
    }
    for (int i = 0; i < dims; ++i)
        for (int j = 0; j < i; ++j)
            cov[dims * i + j] = cov[dims * j + i];
    relief_sym_eigen(dims, cov, eval, evec, work);
    for (int a = 0; a < RELIEF_SEARCH_DIMS; ++a)
        for (int i = 0; i < dims; ++i)
            axes[dims * a + i] = a < dims ? evec[dims * i + a] : 0.0;
    free(work);
    free(evec);
    free(cov);
    return RELIEF_OK;
}

/* Every sample rotation's descriptor projected on the principal axes of
 * an even stride of them (at most PCA_ROWS): red, pairs x
 * RELIEF_SEARCH_DIMS. When the stride is 1 the strided rows are every
 * pair, described once for the axes and the projection both. */
static relief_status reduce_descriptors(const relief_match_data *d, int dims, float step,
                                        int threads, float *red, relief_error *err)
{
    const size_t pairs = (size_t)d->ns * (size_t)d->rotations;
    const size_t stride = pairs > PCA_ROWS ? (pairs + PCA_ROWS - 1) / PCA_ROWS : 1;
    const size_t rows = (pairs + stride - 1) / stride;
    double mean[2 * POINTS], axes[RELIEF_SEARCH_DIMS * 2 * POINTS];
    ring_points rp;
    desc_job j = {d, &rp, dims, stride, NULL, mean, axes, red};
    relief_status st;
    ring_points_init(d, step, &rp);
    j.desc = malloc(rows * (size_t)dims * sizeof *j.desc);
    if (!j.desc)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the search's %zu x %d "
                           "descriptors", rows, dims);
    relief_parallel_ranges(rows, threads, describe_rows, &j);
    st = principal_axes(j.desc, rows, dims, mean, axes, err);
    if (st == RELIEF_OK)
        relief_parallel_ranges(pairs, threads, project_rows, &j);
    free(j.desc);
    return st;
}

/* Sample si's k similar sample rotations into sim (k of them, UINT32_MAX
 * past the last): the first of the nn found, nearest first, whose sample
 * lies farther than `exclude` from si (not itself, nor its own patch). */
static void keep_similar(const relief_match_data *d, const int *found, int nn, int k,
                         double exclude, size_t si, uint32_t *sim)
{
    const float *sp = d->s_proj + 3 * si;
    int got = 0;
    for (int j = 0; j < nn && got < k; ++j) {
        const float *op;
        float dx, dy, dz;
        if (found[j] < 0)
            continue;
        op = d->s_proj + 3 * ((size_t)found[j] / (size_t)d->rotations);
        dx = op[0] - sp[0], dy = op[1] - sp[1], dz = op[2] - sp[2];
        if ((double)(dx * dx + dy * dy + dz * dz) <= exclude * exclude)
            continue; /* itself, or its own patch of the surface */
        sim[got++] = (uint32_t)found[j];
    }
    while (got < k)
        sim[got++] = UINT32_MAX;
}

/* Every sample's similar rotations (S->sim) from FLANN's index of the
 * reduced descriptors red, CHUNK samples a query; query, idx and dist
 * room for CHUNK queries of nn. Only (s, 0) is asked: when (s, 0) reads
 * as (s', r'), (s, r) reads as (s', r' + r), rotations composing about
 * the normal. */
static relief_status find_similar(flann_index_t index, struct FLANNParameters *fp,
                                  const relief_match_data *d, const float *red, int nn,
                                  double exclude, float *query, int *idx, float *dist,
                                  relief_search *S, relief_error *err)
{
    for (size_t s0 = 0; s0 < d->ns; s0 += CHUNK) {
        const size_t nc = d->ns - s0 < CHUNK ? d->ns - s0 : CHUNK;
        for (size_t i = 0; i < nc; ++i)
            memcpy(query + i * RELIEF_SEARCH_DIMS,
                   red + (s0 + i) * (size_t)d->rotations * RELIEF_SEARCH_DIMS,
                   RELIEF_SEARCH_DIMS * sizeof *query);
        if (flann_find_nearest_neighbors_index_float(index, query, (int)nc, idx, dist, nn,
                                                     fp) != 0)
            return relief_fail(err, RELIEF_E_NOMEM, "FLANN's search of the descriptors failed");
        for (size_t si = s0; si < s0 + nc; ++si)
            keep_similar(d, idx + (si - s0) * (size_t)nn, nn, S->k, exclude, si,
                         S->sim + si * (size_t)S->k);
    }
    return RELIEF_OK;
}

relief_status relief_search_create(const relief_surface *s, const relief_match_data *d,
                                   int window, int k, int threads, relief_search **out,
                                   relief_error *err)
{
    const size_t pairs = (size_t)d->ns * (size_t)d->rotations;
    const int dims = d->mu < 1.0f ? 2 * POINTS : POINTS;
    const float step = (float)(window * s->spacing / RELIEF_SEARCH_RINGS);
    const double exclude = window * s->spacing, t0 = relief_seconds();
    struct FLANNParameters fp = relief_knn_exact_params();
    flann_index_t index = NULL;
    relief_search *S;
    float *red = NULL, *query = NULL, *dist = NULL, speedup;
    int *idx = NULL, nn;
    relief_status st;

    *out = NULL;
    if (k < 1 || k > RELIEF_SEARCH_K_MAX)
        return relief_fail(err, RELIEF_E_RANGE, "search k %d out of range: expected 1..%d", k,
                           RELIEF_SEARCH_K_MAX);
    if (d->ns == 0 || pairs > (size_t)INT32_MAX)
        return relief_fail(err, RELIEF_E_RANGE, "the k-coherence search needs 1..%d sample "
                           "rotations, not %zu", INT32_MAX, pairs);
    /* The queries are independent, so FLANN may spread them over every
     * core (OpenMP): the same neighbours in the same order. */
    fp.cores = 0;
    nn = OVERQUERY * k + 1;
    if ((size_t)nn > pairs)
        nn = (int)pairs;
    S = calloc(1, sizeof *S);
    if (!S)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the k-coherence search");
    S->ns = d->ns;
    S->rotations = d->rotations;
    S->k = k;
    S->sim = malloc((size_t)d->ns * (size_t)k * sizeof *S->sim);
    S->stamp = calloc(d->ns, sizeof *S->stamp);
    S->cand = malloc(d->ns * sizeof *S->cand);
    red = malloc(pairs * RELIEF_SEARCH_DIMS * sizeof *red);
    query = malloc(CHUNK * RELIEF_SEARCH_DIMS * sizeof *query);
    idx = malloc(CHUNK * (size_t)nn * sizeof *idx);
    dist = malloc(CHUNK * (size_t)nn * sizeof *dist);
    if (!S->sim || !S->stamp || !S->cand || !red || !query || !idx || !dist) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the k-coherence search for "
                         "%zu sample rotations (%zu bytes)", pairs,
                         relief_search_bytes(d->ns, d->rotations, k));
        goto done;
    }
    st = reduce_descriptors(d, dims, step, relief_pool_threads_for(threads), red, err);
    if (st != RELIEF_OK)
        goto done;
    index = flann_build_index_float(red, (int)pairs, RELIEF_SEARCH_DIMS, &speedup, &fp);
    if (!index) {
        st = relief_fail(err, RELIEF_E_NOMEM, "FLANN could not index %zu search descriptors",
                         pairs);
        goto done;
    }
    st = find_similar(index, &fp, d, red, nn, exclude, query, idx, dist, S, err);
    if (st != RELIEF_OK)
        goto done;
    S->seconds = relief_seconds() - t0;
    *out = S;
    S = NULL;
done:
    if (index)
        flann_free_index_float(index, &fp);
    free(dist);
    free(idx);
    free(query);
    free(red);
    relief_search_destroy(S);
    return st;
}

uint32_t relief_continue_patch(const relief_match_data *d, const float o[3], uint32_t si,
                               uint32_t r)
{
    const float a = d->cos_r[r] * o[0] - d->sin_r[r] * o[1];
    const float b = d->sin_r[r] * o[0] + d->cos_r[r] * o[1];
    float x[3];
    for (int l = 0; l < 3; ++l)
        x[l] = d->s_proj[3 * si + l] + a * d->s_frame[9 * si + l] +
               b * d->s_frame[9 * si + 3 + l] + o[2] * d->s_frame[9 * si + 6 + l];
    return rm_closest_vertex_listed(x, d->proj, d->cell_start, d->cell_items, d->grid, d->dims,
                                    d->lgrid, d->ldims, d->lmask, d->lslot, d->litems);
}

uint32_t relief_search_candidates(relief_search *S, const relief_surface *s,
                                  const relief_match_data *d, const uint32_t *nbr, uint32_t n,
                                  const uint32_t *src, uint32_t t, const uint32_t **out)
{
    const uint32_t R = (uint32_t)S->rotations;
    const double *tp = s->proj + 3 * (size_t)t;
    uint32_t m = 0;
    if (++S->now == 0) { /* the stamps wrapped: start them again */
        memset(S->stamp, 0, S->ns * sizeof *S->stamp);
        S->now = 1;
    }
    /* Two passes: every neighbour's own continuation first, then those of
     * the pairs similar to its source. The first are the likeliest best,
     * so a running cutoff falls early and prunes the rest sooner. */
    for (int pass = 0; pass < 2; ++pass)
        for (uint32_t i = 0; i < n; ++i) {
            const uint32_t v = nbr[i];
            const double *vp = s->proj + 3 * (size_t)v, *vf = s->frame + 9 * (size_t)v;
            const int is_sample = v < s->n_samples;
            const uint32_t vs = relief_match_sample_of(d, v);
            const uint32_t c0 = !is_sample ? src[v] : vs == UINT32_MAX ? UINT32_MAX : vs * R;
            float o[3];
            if (c0 == UINT32_MAX || (pass == 0 && is_sample))
                continue; /* a sample's own continuation is t, not a sample */
            /* t's place seen from v, in v's frame. */
            for (int j = 0; j < 3; ++j)
                o[j] = (float)(vf[3 * j] * (tp[0] - vp[0]) + vf[3 * j + 1] * (tp[1] - vp[1]) +
                               vf[3 * j + 2] * (tp[2] - vp[2]));
            for (int j = pass == 0 ? -1 : 0; j < (pass == 0 ? 0 : S->k); ++j) {
                const uint32_t c =
                    j < 0 ? c0 : S->sim[(size_t)(c0 / R) * (size_t)S->k + (size_t)j];
                uint32_t v2;
                if (c == UINT32_MAX)
                    continue;
                v2 = relief_match_sample_of(
                    d, relief_continue_patch(d, o, c / R, j < 0 ? c % R : (c % R + c0 % R) % R));
                if (v2 == UINT32_MAX || S->stamp[v2] == S->now)
                    continue; /* no candidate centre, or listed */
                S->stamp[v2] = S->now;
                S->cand[m++] = v2;
            }
        }
    *out = S->cand;
    return m;
}

double relief_search_build_seconds(const relief_search *S)
{
    return S ? S->seconds : 0.0;
}

void relief_search_destroy(relief_search *S)
{
    if (!S)
        return;
    free(S->cand);
    free(S->stamp);
    free(S->sim);
    free(S);
}
