/* Texture optimisation over overlapping clusters (paper 002, sections 3.3
 * and 4). The energy is measured at the points: for each active cluster i,
 * its matched exemplar grid Z_i is read at each member's tangent
 * coordinates from the exemplar points about that place on Z_i's tangent
 * plane (read_exemplar; the grid's nodes only find the candidates), so that
 *   E = sum_i sum_{p in C_O,i} w_p ||x(p) - Z_i(p)||^2,  w_p = 1 + lambda [p on the rim],
 * which is the header's sum ||G_i - Z_i||^2 + lambda sum_rim (x - x_c)^2
 * taken where the data are (the points) rather than on the nodes: the rim
 * points are known (x = x_c), so the rim term weighs how well a matched
 * neighbourhood agrees with them (Kwatra's controllable synthesis). With
 * that form both steps never raise E: the E-step's mean of the Z_i(p) over
 * the clusters holding an unknown p is its exact minimiser, and the M-step
 * keeps the previous match among its candidates (the 8 nearest exemplar
 * grids to G_i by FLANN's exact kd-tree, or by brute force on the host or
 * an OpenCL device (points/grid_nn.h), G_i being the current values
 * resampled on the grid, then ranked by their E term). */
#include "points/texopt.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/parallel.h"
#include "base/pool.h"
#include "base/rng.h"
#include "points/cluster.h"
#include "points/grid_nn.h"

#define START_PARALLEL_MIN 200000 /* floats a start's scan reads before it is shared out */
#define MAX_EXEMPLARS 20000 /* exemplar grids searched at most (a seeded subset beyond) */
#define CANDIDATES 8        /* nearest grids re-ranked by the energy */
#define MAX_THREADS RELIEF_PARALLEL_MAX_THREADS
_Static_assert(RELIEF_POOL_MAX <= MAX_THREADS, "the default threads fit the shares");

relief_texopt_params relief_texopt_params_default(void)
{
    relief_texopt_params p;
    p.grid_n = 23;
    p.overlap = 0.5;
    /* 300 before the overlap (about 680 after it), where the paper has
     * about 300 after it: measured on frag_115's cut, 133 (the paper's)
     * stopped a tape line at the hole's rim with every seed (colour RMS
     * 0.12), 300 (with grid_n 23, the same node step) carried it across
     * with every seed (0.03); the detail of the bumpy sphere and the bunny
     * came back as rough as at 133. */
    p.cluster_size = 300;
    p.grid_step = 0;
    p.max_iter = 50;
    p.tol = 1e-4;
    p.lambda = 1;
    p.seed = 1;
    p.threads = 0;
    p.brute = 0;
    p.backend = RELIEF_BACKEND_AUTO;
    p.device = -1;
    p.histogram = 0;
    p.progress = NULL;
    return p;
}

void relief_texopt_result_free(relief_texopt_result *r)
{
    if (!r)
        return;
    free(r->energy);
    r->energy = NULL;
}

/* Everything an iteration reads. */
typedef struct opt {
    int gn, ch, nodes, dims;
    size_t A;                  /* active clusters */
    size_t *mstart;            /* A + 1 */
    uint32_t *mpt;             /* members */
    float *mfa, *mfb;          /* their grid coordinates, in [0, gn - 1] */
    size_t *wstart;            /* A x nodes + 1: resampling onto the grid */
    uint32_t *wpt;
    float *ww;
    const uint8_t *rim;
    double lambda;
    float *x;                  /* n x ch current values */
    const float *zvec;         /* exemplar grids, dims each */
    size_t nz;
    relief_grid_nn *nn;        /* the exemplar grids' search */
    float *q;                  /* A x dims: each cluster's current grid G_i */
    uint32_t *cand;            /* A x min(nz, CANDIDATES): its nearest exemplar grids */
    uint32_t *match;           /* A */
    /* Reading an exemplar grid at a cluster's members (read_exemplar): */
    const double *pos, *nrm;   /* n x 3, unit normals */
    const uint8_t *exemplar;   /* n */
    const relief_pbucket *bk;  /* every point, cells of a grid's reach */
    const double *frame;       /* the clusters' frames */
    const uint32_t *label;     /* n: each point's cluster */
    const uint32_t *zq;        /* nz: each exemplar grid's centre point */
    double h;                  /* grid step */
    float *zread;              /* mlen x ch: each member's value in its cluster's match */
} opt;

/* A thread's scratch for read_exemplar. */
typedef struct reader {
    uint32_t *cand;            /* the bucket query's points */
    size_t cand_cap;
    float *ab;                 /* kept points' grid coordinates, 2 each */
    uint32_t *pt;              /* kept points */
    int32_t *next;             /* kept points chained by grid cell */
    size_t kept_cap;
    int32_t *head;             /* gn x gn cells: the first kept point, -1 none */
    float *buf[2];             /* members x ch: a candidate's read, the best's */
    size_t buf_cap;
} reader;

static void reader_free(reader *r)
{
    free(r->cand), free(r->ab), free(r->pt), free(r->next), free(r->head);
    free(r->buf[0]), free(r->buf[1]);
    *r = (reader){0};
}

static void bilerp(const float *z, int gn, int ch, float fa, float fb, float *out)
{
    int a0 = (int)fa, b0 = (int)fb;
    float ta, tb;
    if (a0 > gn - 2)
        a0 = gn - 2;
    if (b0 > gn - 2)
        b0 = gn - 2;
    ta = fa - (float)a0, tb = fb - (float)b0;
    for (int k = 0; k < ch; ++k) {
        const float *r0 = z + ((size_t)b0 * gn + a0) * ch + k, *r1 = r0 + (size_t)gn * ch;
        out[k] = (1 - tb) * ((1 - ta) * r0[0] + ta * r0[ch]) + tb * ((1 - ta) * r1[0] + ta * r1[ch]);
    }
}

/* How much cluster j's grid speaks for a member at grid coordinates
 * (fa, fb): 1 at the centre, falling to 1/16 at the grid's edge (a product
 * of raised cosines floored there), so that where clusters overlap each
 * point takes its value mostly from the grid it is central to; an equal
 * average of overlapping grids that disagree in phase blurs the detail
 * away (Kwatra et al. weigh by a Gaussian falloff for the same reason). */
static float centre_weight(int gn, float fa, float fb)
{
    const float k = 0.5f * (float)(gn - 1);
    const float ua = (fa - k) / k, ub = (fb - k) / k;
    const float wa = 0.5f + 0.5f * cosf(3.14159265f * fminf(fabsf(ua), 1.0f));
    const float wb = 0.5f + 0.5f * cosf(3.14159265f * fminf(fabsf(ub), 1.0f));
    return fmaxf(wa * wb, 1.0f / 16.0f);
}

/* How far read_exemplar (below) looks about a member's place. */
#define READ_RADIUS 1.5f /* grid steps, about 1.3 spacings at the default grid */
#define READ_FAR 2.0f
#define READ_EPS 1e-3     /* grid steps squared: a point on the spot does not take all */

/* Room in rd for nc kept points (ab, pt, next) and for the gn x gn cell
 * heads; -1 when memory runs out. */
static int reader_reserve(reader *rd, size_t nc, int gn)
{
    if (nc > rd->kept_cap) {
        float *ab = realloc(rd->ab, 2 * nc * sizeof *ab);
        uint32_t *pt;
        int32_t *nx;
        if (!ab)
            return -1;
        rd->ab = ab;
        if (!(pt = realloc(rd->pt, nc * sizeof *pt)))
            return -1;
        rd->pt = pt;
        if (!(nx = realloc(rd->next, nc * sizeof *nx)))
            return -1;
        rd->next = nx, rd->kept_cap = nc;
    }
    if (!rd->head && !(rd->head = malloc((size_t)gn * gn * sizeof *rd->head)))
        return -1;
    return 0;
}

/* The exemplar points among the query's nc (rd->cand) on the side of the
 * surface of the grid centred at c (frame f: 9, its normal last), at their
 * grid coordinates (rd->ab, in grid steps, half: the centre node's) and
 * chained by the grid cell they fall in (rd->head, rd->next), in query
 * order so that ties break the same way. */
static void chain_exemplar(const opt *o, reader *rd, size_t nc, const double *c, const double *f,
                           double half)
{
    const int gn = o->gn;
    size_t kept = 0;
    for (int i = 0; i < gn * gn; ++i)
        rd->head[i] = -1;
    for (size_t i = nc; i-- > 0;) {
        const uint32_t p = rd->cand[i];
        const double *np = o->nrm + 3 * (size_t)p;
        double s, t, a, b;
        int ia, ib;
        if (!o->exemplar[p] || np[0] * f[6] + np[1] * f[7] + np[2] * f[8] < RELIEF_PGRID_NORMAL_COS)
            continue;
        relief_ptangent(o->pos + 3 * (size_t)p, c, f, &s, &t);
        a = s / o->h + half, b = t / o->h + half;
        if (a < -2.5 || b < -2.5 || a > 2 * half + 2.5 || b > 2 * half + 2.5)
            continue;
        ia = (int)floor(a + 0.5), ib = (int)floor(b + 0.5);
        ia = ia < 0 ? 0 : ia > gn - 1 ? gn - 1 : ia;
        ib = ib < 0 ? 0 : ib > gn - 1 ? gn - 1 : ib;
        rd->ab[2 * kept] = (float)a, rd->ab[2 * kept + 1] = (float)b, rd->pt[kept] = p;
        rd->next[kept] = rd->head[ib * gn + ia];
        rd->head[ib * gn + ia] = (int32_t)kept++;
    }
}

/* One member's read at grid coordinates (fa, fb) into out (ch), from the
 * chained points of the 5 x 5 cells about it (chain_exemplar's): their
 * inverse-square-distance mean within READ_RADIUS, else the nearest within
 * READ_FAR, else the bilinear value of the grid zz (gn x gn x ch). */
static void read_member(const opt *o, const reader *rd, const float *zz, float fa, float fb,
                        float *out)
{
    const int gn = o->gn;
    const int ia = (int)(fa + 0.5f), ib = (int)(fb + 0.5f);
    double acc[4] = {0, 0, 0, 0}, ws = 0.0;
    int32_t best = -1;
    float bd = READ_FAR * READ_FAR;
    for (int b = ib - 2; b <= ib + 2; ++b)
        for (int a = ia - 2; a <= ia + 2; ++a) {
            if (a < 0 || b < 0 || a >= gn || b >= gn)
                continue;
            for (int32_t e = rd->head[b * gn + a]; e >= 0; e = rd->next[e]) {
                const float da = rd->ab[2 * e] - fa, db = rd->ab[2 * e + 1] - fb;
                const float d2 = da * da + db * db;
                if (d2 < bd || (d2 == bd && e < best))
                    bd = d2, best = e;
                if (d2 <= READ_RADIUS * READ_RADIUS) {
                    const double w = 1.0 / ((double)d2 + READ_EPS);
                    for (int k = 0; k < o->ch; ++k)
                        acc[k] += w * o->x[(size_t)rd->pt[e] * o->ch + k];
                    ws += w;
                }
            }
        }
    if (ws > 0.0)
        for (int k = 0; k < o->ch; ++k)
            out[k] = (float)(acc[k] / ws);
    else if (best >= 0)
        memcpy(out, o->x + (size_t)rd->pt[best] * o->ch, (size_t)o->ch * sizeof *out);
    else
        bilerp(zz, gn, o->ch, fa, fb, out);
}

/* Exemplar grid z read at cluster j's members (their grid coordinates
 * mfa, mfb), into out (members x ch), from the exemplar points about z's
 * centre as they lie on its tangent plane (its grid coordinates): the
 * inverse-square-distance mean of those within READ_RADIUS steps of the
 * member's place; else the nearest within READ_FAR; else z's bilinear
 * value. Why not z's nodes: they are Gaussian means of the points about
 * them (sigma h / 2), and a bilinear read blurs them again: stripes 3
 * spacings apart came back at 0.57 of their amplitude (0.65 read so;
 * test_texopt), frag_115's tape with a colour RMS of 0.030 against the
 * truth (0.027). The nearest point alone kept the stripes whole (0.99) but
 * made the bunny's fill speckled: neighbours reading different points,
 * averaged over the clusters, gave a staircase that shading shows
 * (README). Returns -1 when memory runs out. */
static int read_exemplar(const opt *o, reader *rd, uint32_t z, size_t j, float *out)
{
    const float *zz = o->zvec + (size_t)z * o->dims;
    const size_t m0 = o->mstart[j], nm = o->mstart[j + 1] - m0;
    const int gn = o->gn;
    const double half = 0.5 * (gn - 1); /* the centre node's coordinate */
    const uint32_t q = o->zq[z];
    const double *c = o->pos + 3 * (size_t)q, *f = o->frame + 9 * (size_t)o->label[q];
    size_t nc;
    nc = relief_pbucket_query(o->bk, c, relief_pgrid_reach(gn, o->h) + 2 * o->h, &rd->cand,
                              &rd->cand_cap);
    if (nc == SIZE_MAX)
        return -1;
    if (reader_reserve(rd, nc, gn) < 0)
        return -1;
    chain_exemplar(o, rd, nc, c, f, half);
    for (size_t m = 0; m < nm; ++m)
        read_member(o, rd, zz, o->mfa[m0 + m], o->mfb[m0 + m], out + m * o->ch);
    return 0;
}

/* Cluster j's term of E with its members' values read from an exemplar
 * grid (v: members x ch, read_exemplar's). */
static double cluster_energy(const opt *o, size_t j, const float *v)
{
    double e = 0;
    const size_t m0 = o->mstart[j];
    for (size_t m = m0; m < o->mstart[j + 1]; ++m) {
        const uint32_t p = o->mpt[m];
        double s = 0;
        for (int k = 0; k < o->ch; ++k) {
            const double d = (double)o->x[(size_t)p * o->ch + k] - v[(m - m0) * o->ch + k];
            s += d * d;
        }
        e += (o->rim && o->rim[p] ? 1 + o->lambda : 1) * centre_weight(o->gn, o->mfa[m], o->mfb[m]) *
             s;
    }
    return e;
}

/* The M-step's two parallel halves over active clusters lo..hi-1
 * (relief_parallel_ranges), each writing only its own rows, so that the
 * result does not depend on how the clusters are shared out. First each
 * G_i, resampled from the current values: */
static int resample_grids(void *ctx, size_t lo, size_t hi)
{
    const opt *o = ctx;
    for (size_t j = lo; j < hi; ++j) {
        float *q = o->q + j * (size_t)o->dims;
        for (int node = 0; node < o->nodes; ++node) {
            const size_t wn = j * (size_t)o->nodes + (size_t)node;
            for (int k = 0; k < o->ch; ++k) {
                double s = 0;
                for (size_t t = o->wstart[wn]; t < o->wstart[wn + 1]; ++t)
                    s += (double)o->ww[t] * o->x[(size_t)o->wpt[t] * o->ch + k];
                q[node * o->ch + k] = (float)s;
            }
        }
    }
    return 0;
}

/* then, after the search, the candidates ranked by the E term, the
 * previous match kept among them; the winner's read kept in o->zread. */
static int rank_candidates(void *ctx, size_t lo, size_t hi)
{
    const opt *o = ctx;
    const int nn = o->nz < CANDIDATES ? (int)o->nz : CANDIDATES;
    reader rd = {0};
    int fail = 0;
    for (size_t j = lo; j < hi; ++j) {
        const uint32_t *idx = o->cand + j * (size_t)nn;
        const size_t nm = o->mstart[j + 1] - o->mstart[j];
        uint32_t best = o->match[j];
        double be = INFINITY;
        if (nm * o->ch > rd.buf_cap) {
            float *a = realloc(rd.buf[0], nm * o->ch * sizeof *a), *b;
            if (!a) {
                fail = 1;
                break;
            }
            rd.buf[0] = a;
            if (!(b = realloc(rd.buf[1], nm * o->ch * sizeof *b))) {
                fail = 1;
                break;
            }
            rd.buf[1] = b, rd.buf_cap = nm * o->ch;
        }
        if (best != UINT32_MAX) { /* its read, kept from the last step (the same values) */
            memcpy(rd.buf[1], o->zread + o->mstart[j] * o->ch, nm * o->ch * sizeof *rd.buf[1]);
            be = cluster_energy(o, j, rd.buf[1]);
        }
        for (int c = 0; c < nn; ++c) {
            double e;
            if (idx[c] == UINT32_MAX || idx[c] == o->match[j])
                continue;
            if (read_exemplar(o, &rd, idx[c], j, rd.buf[0]) < 0) {
                fail = 1;
                break;
            }
            e = cluster_energy(o, j, rd.buf[0]);
            if (e < be || (e == be && idx[c] < best)) {
                float *t = rd.buf[0];
                rd.buf[0] = rd.buf[1], rd.buf[1] = t;
                be = e, best = idx[c];
            }
        }
        if (fail || best == UINT32_MAX) { /* no grid to match: cannot happen with nz >= 1 */
            fail = 1;
            break;
        }
        o->match[j] = best;
        memcpy(o->zread + o->mstart[j] * o->ch, rd.buf[1], nm * o->ch * sizeof *o->zread);
    }
    reader_free(&rd);
    return fail;
}

/* The M-step: every G_i, their nearest exemplar grids (o->cand, A rows of
 * min(nz, CANDIDATES)), the ranking. */
static relief_status run_mstep(const opt *o, int threads, relief_error *err)
{
    const int nn = o->nz < CANDIDATES ? (int)o->nz : CANDIDATES;
    relief_status st;
    relief_parallel_ranges(o->A, threads, resample_grids, (void *)o);
    st = relief_grid_nn_query(o->nn, o->q, o->A, nn, o->cand, err);
    if (st == RELIEF_OK && relief_parallel_ranges(o->A, threads, rank_candidates, (void *)o))
        return relief_fail(err, RELIEF_E_NOMEM, "texture optimisation: out of memory, or a "
                           "cluster with no candidate grid (ranking)");
    return st;
}

#define START_SHARE 0.15 /* of the texture's progress: the start; the iterations the rest */

static relief_status texopt_cancelled(const relief_progress *pr, relief_error *err)
{
    return relief_fail(err, RELIEF_E_CANCELLED, "cancelled by the progress callback at %.0f %%",
                       100.0 * pr->last);
}

/* The start's search for the exemplar grid nearest q over the nodes that
 * are valid. A grid's distance is summed node by node, each node's
 * channels in order, and a grid stops once its partial sum reaches the
 * best so far; the first grid of the least distance wins. The grids are
 * shared out over threads by ranges; the shares' bests, the earliest of
 * the least, are the serial scan's. (Summing 8 grids side by side, each in
 * its own order, was slower: the scan is bound by reading the grids, and
 * the lanes read past where each would have stopped.) */
typedef struct start_job {
    const opt *o;
    const double *q;     /* dims: q's values as doubles */
    const uint32_t *off; /* nv: the valid nodes' first value's offset */
    size_t nv, parts;
    double e[RELIEF_PARALLEL_MAX_THREADS];
    uint32_t z[RELIEF_PARALLEL_MAX_THREADS];
} start_job;

/* Grid z's distance, stopped at be (any value >= be then). */
static double start_distance(const start_job *j, size_t z, double be)
{
    const int ch = j->o->ch;
    const float *zz = j->o->zvec + z * (size_t)j->o->dims;
    double e = 0.0;
    for (size_t v = 0; v < j->nv && e < be; ++v)
        for (int k = 0; k < ch; ++k) {
            const double d = j->q[j->off[v] + k] - zz[j->off[v] + k];
            e += d * d;
        }
    return e;
}

static int start_parts(void *ctx, size_t lo, size_t hi)
{
    start_job *j = ctx;
    const opt *o = j->o;
    for (size_t part = lo; part < hi; ++part) {
        const size_t z0 = o->nz * part / j->parts, z1 = o->nz * (part + 1) / j->parts;
        double be = INFINITY;
        uint32_t best = (uint32_t)z0;
        for (size_t z = z0; z < z1; ++z) {
            const double d = start_distance(j, z, be);
            if (d < be)
                be = d, best = (uint32_t)z;
        }
        j->e[part] = be, j->z[part] = best;
    }
    return 0;
}

/* q (dims) and its valid nodes (nodes) into the job's scratch qd (dims)
 * and off (nodes); the best grid's index. */
static uint32_t start_match(const opt *o, const float *q, const uint8_t *nvalid, double *qd,
                            uint32_t *off, int threads)
{
    start_job j;
    size_t parts = threads < 1 ? 1 : (size_t)threads, w = 0;
    j.nv = 0;
    for (int node = 0; node < o->nodes; ++node)
        if (nvalid[node])
            off[j.nv++] = (uint32_t)node * (uint32_t)o->ch;
    for (int i = 0; i < o->dims; ++i)
        qd[i] = (double)q[i];
    /* Threads only where a scan is long enough to pay for starting them. */
    if (o->nz * (size_t)o->dims < START_PARALLEL_MIN)
        parts = 1;
    if (parts > o->nz)
        parts = o->nz ? o->nz : 1;
    j.o = o, j.q = qd, j.off = off, j.parts = parts;
    relief_parallel_ranges(parts, (int)parts, start_parts, &j);
    for (size_t part = 1; part < parts; ++part)
        if (j.e[part] < j.e[w])
            w = part;
    return j.z[w];
}

/* sequential_start's state and scratch, freed together on every path. */
typedef struct start_scratch {
    uint8_t *valid;  /* n: known, or set by the start already */
    uint8_t *open;   /* A + 1: clusters that may still have unset members */
    float *q;        /* dims: the chosen cluster's grid over valid points */
    uint8_t *nvalid; /* nodes: which of q's nodes count */
    double *qd;      /* dims: start_match's scratch */
    uint32_t *off;   /* nodes: start_match's scratch */
    reader rd;
} start_scratch;

static void start_scratch_free(start_scratch *s)
{
    free(s->valid), free(s->open), free(s->q), free(s->nvalid), free(s->qd), free(s->off);
    reader_free(&s->rd);
}

/* The next cluster to match: the open one with the largest share of valid
 * members that still has unset ones (the first such on ties); clusters
 * found all valid are closed on the way. SIZE_MAX when none is left. */
static size_t start_pick(const opt *o, const uint8_t *valid, uint8_t *open)
{
    size_t j = SIZE_MAX;
    double best_share = -1.0;
    for (size_t c = 0; c < o->A; ++c) {
        size_t nv = 0, tot = o->mstart[c + 1] - o->mstart[c];
        double share;
        if (!open[c])
            continue;
        for (size_t m = o->mstart[c]; m < o->mstart[c + 1]; ++m)
            nv += valid[o->mpt[m]];
        if (nv == tot) {
            open[c] = 0; /* nothing left to set */
            continue;
        }
        share = (double)nv / (double)tot;
        if (share > best_share)
            best_share = share, j = c;
    }
    return j;
}

/* Cluster j's grid over valid points into q (dims) and which nodes count
 * into nvalid (nodes): a node counts when at least half its weight is on
 * valid points, its value renormalised over them (0 when it does not). */
static void start_grid(const opt *o, size_t j, const uint8_t *valid, float *q, uint8_t *nvalid)
{
    for (int node = 0; node < o->nodes; ++node) {
        const size_t wn = j * (size_t)o->nodes + (size_t)node;
        double wv = 0.0, wt = 0.0;
        for (size_t t = o->wstart[wn]; t < o->wstart[wn + 1]; ++t) {
            wt += o->ww[t];
            if (valid[o->wpt[t]])
                wv += o->ww[t];
        }
        nvalid[node] = wt > 0.0 && wv >= 0.5 * wt;
        for (int k = 0; k < o->ch; ++k) {
            double acc = 0.0;
            for (size_t t = o->wstart[wn]; nvalid[node] && t < o->wstart[wn + 1]; ++t)
                if (valid[o->wpt[t]])
                    acc += (double)o->ww[t] * o->x[(size_t)o->wpt[t] * o->ch + k];
            q[node * o->ch + k] = nvalid[node] ? (float)(acc / wv) : 0.0f;
        }
    }
}

/* Cluster j's unset members take its match's read (o->zread) and become
 * valid: those in the central half of its grid, or all of them when none
 * is central. */
static void start_take(opt *o, size_t j, uint8_t *valid)
{
    const float half = 0.25f * (float)(o->gn - 1); /* |fa - centre| within it: central */
    const float centre = 0.5f * (float)(o->gn - 1);
    size_t central = 0;
    for (size_t m = o->mstart[j]; m < o->mstart[j + 1]; ++m)
        central += !valid[o->mpt[m]] && fabsf(o->mfa[m] - centre) <= half &&
                   fabsf(o->mfb[m] - centre) <= half;
    for (size_t m = o->mstart[j]; m < o->mstart[j + 1]; ++m) {
        const uint32_t p = o->mpt[m];
        if (valid[p] || (central && (fabsf(o->mfa[m] - centre) > half ||
                                     fabsf(o->mfb[m] - centre) > half)))
            continue;
        memcpy(o->x + (size_t)p * o->ch, o->zread + m * o->ch, (size_t)o->ch * sizeof *o->x);
        valid[p] = 1;
    }
}

/* The unknown values' start, grown inward from the known part as patch-
 * based synthesis grows (Criminisi et al.'s onion order). Repeatedly the
 * active cluster with the largest share of valid members (known, or set
 * before) that still has unset ones is matched against every exemplar grid
 * over its valid nodes only, and its unset members in the central half of
 * its grid take the match's values (all of them when none is central).
 * Why not random values (Kwatra's start): against noise the smoothest
 * exemplar scores best under squared differences, so the optimisation
 * settled in a blur (synthesised detail at a third of the capture's
 * amplitude on a bumpy sphere). Why only the central half: a cluster that
 * set all its members reached across the hole before the clusters on the
 * other side were matched, and a tape line on frag_115 stopped at the rim.
 * Exhaustive over the exemplars: about 2 A x nz x nodes x channels. */
static relief_status sequential_start(opt *o, const uint8_t *unknown, size_t n, int threads,
                                      relief_progress *pr, relief_error *err)
{
    start_scratch s = {0};
    relief_status st = RELIEF_OK;
    s.valid = malloc(n), s.open = malloc(o->A + 1);
    s.q = malloc((size_t)o->dims * sizeof *s.q);
    s.nvalid = malloc((size_t)o->nodes);
    s.qd = malloc((size_t)o->dims * sizeof *s.qd);
    s.off = malloc((size_t)o->nodes * sizeof *s.off);
    if (!s.valid || !s.open || !s.q || !s.nvalid || !s.qd || !s.off) {
        start_scratch_free(&s);
        return relief_fail(err, RELIEF_E_NOMEM, "texture optimisation: out of memory (start)");
    }
    for (size_t i = 0; i < n; ++i)
        s.valid[i] = !unknown[i];
    memset(s.open, 1, o->A);
    for (size_t round = 0;; ++round) {
        const size_t j = start_pick(o, s.valid, s.open);
        uint32_t best;
        if (j == SIZE_MAX)
            break;
        /* About one round a cluster: a share of the start each. */
        if (relief_progress_step(pr, START_SHARE * (round < o->A ? (double)round / o->A : 1.0))) {
            st = texopt_cancelled(pr, err);
            break;
        }
        start_grid(o, j, s.valid, s.q, s.nvalid);
        best = start_match(o, s.q, s.nvalid, s.qd, s.off, threads);
        o->match[j] = best;
        if (read_exemplar(o, &s.rd, best, j, o->zread + o->mstart[j] * o->ch) < 0) {
            st = relief_fail(err, RELIEF_E_NOMEM, "texture optimisation: out of memory (start)");
            break;
        }
        start_take(o, j, s.valid);
    }
    start_scratch_free(&s);
    return st;
}

/* Append to a growing array. */
#define PUSH(arr, len, cap, val)                                            \
    do {                                                                    \
        if ((len) == (cap)) {                                               \
            size_t nc_ = (cap) ? 2 * (cap) : 1024;                          \
            void *np_ = realloc((arr), nc_ * sizeof *(arr));                \
            if (!np_)                                                       \
                goto nomem;                                                 \
            (arr) = np_, (cap) = nc_;                                       \
        }                                                                   \
        (arr)[(len)++] = (val);                                             \
    } while (0)

static relief_status check(const double *pos, const double *nrm, size_t n, int channels,
                           const float *value, const uint8_t *unknown, const uint8_t *exemplar,
                           const relief_texopt_params *p, size_t *n_unknown, size_t *n_exemplar,
                           relief_error *err)
{
    if (!pos || !nrm || !value || !unknown || !exemplar)
        return relief_fail(err, RELIEF_E_RANGE, "texture optimisation: pos, nrm, value, unknown "
                           "and exemplar must be given");
    if (n < 1 || n >= UINT32_MAX)
        return relief_fail(err, RELIEF_E_RANGE, "texture optimisation: %zu points (1..%u)", n,
                           UINT32_MAX - 1);
    if (channels < 1 || channels > 4)
        return relief_fail(err, RELIEF_E_RANGE, "texture optimisation: channels %d (1..4)",
                           channels);
    if (p->grid_n < 3 || p->grid_n > 33 || p->grid_n % 2 == 0)
        return relief_fail(err, RELIEF_E_RANGE, "texture optimisation: grid_n %d (odd, 3..33)",
                           p->grid_n);
    if (p->cluster_size < 16 || p->cluster_size > 100000)
        return relief_fail(err, RELIEF_E_RANGE,
                           "texture optimisation: cluster_size %d (16..100000)", p->cluster_size);
    if (!(p->overlap >= 0 && p->overlap <= 2))
        return relief_fail(err, RELIEF_E_RANGE, "texture optimisation: overlap %g (0..2)",
                           p->overlap);
    if (!(p->grid_step >= 0 && isfinite(p->grid_step)))
        return relief_fail(err, RELIEF_E_RANGE,
                           "texture optimisation: grid_step %g (>= 0, finite; 0 = automatic)",
                           p->grid_step);
    if (p->max_iter < 1 || p->max_iter > 1000)
        return relief_fail(err, RELIEF_E_RANGE, "texture optimisation: max_iter %d (1..1000)",
                           p->max_iter);
    if (!(p->tol >= 0 && p->tol < 1))
        return relief_fail(err, RELIEF_E_RANGE, "texture optimisation: tol %g ([0, 1))", p->tol);
    if (!(p->lambda >= 0 && isfinite(p->lambda)))
        return relief_fail(err, RELIEF_E_RANGE, "texture optimisation: lambda %g (>= 0, finite)",
                           p->lambda);
    if (p->threads < 0 || p->threads > MAX_THREADS)
        return relief_fail(err, RELIEF_E_RANGE,
                           "texture optimisation: threads %d (0..%d, 0 = online CPUs)",
                           p->threads, MAX_THREADS);
    *n_unknown = *n_exemplar = 0;
    for (size_t i = 0; i < n; ++i) {
        const double *q = pos + 3 * i, *m = nrm + 3 * i;
        if (!isfinite(q[0]) || !isfinite(q[1]) || !isfinite(q[2]))
            return relief_fail(err, RELIEF_E_RANGE,
                               "texture optimisation: point %zu has a non-finite position", i);
        if (!(m[0] * m[0] + m[1] * m[1] + m[2] * m[2] > 1e-24) || !isfinite(m[0] + m[1] + m[2]))
            return relief_fail(err, RELIEF_E_RANGE,
                               "texture optimisation: point %zu has a zero or non-finite normal",
                               i);
        if (unknown[i]) {
            ++*n_unknown;
            if (exemplar[i])
                return relief_fail(err, RELIEF_E_RANGE, "texture optimisation: point %zu is "
                                   "both unknown and an exemplar (exemplars must be known)", i);
            continue;
        }
        for (int k = 0; k < channels; ++k)
            if (!isfinite(value[i * (size_t)channels + k]))
                return relief_fail(err, RELIEF_E_RANGE, "texture optimisation: known point %zu "
                                   "has a non-finite value in channel %d", i, k);
        *n_exemplar += exemplar[i] != 0;
    }
    if (!*n_unknown)
        return relief_fail(err, RELIEF_E_RANGE,
                           "texture optimisation: nothing is unknown (no point to complete)");
    if (!*n_exemplar)
        return relief_fail(err, RELIEF_E_RANGE,
                           "texture optimisation: no point is an exemplar (none to copy from)");
    return RELIEF_OK;
}

typedef struct ranked {
    float v;
    uint32_t i;
} ranked;

static int cmp_ranked(const void *a, const void *b)
{
    const ranked *x = a, *y = b;
    if (x->v != y->v)
        return x->v < y->v ? -1 : 1;
    return (x->i > y->i) - (x->i < y->i);
}

/* Histogram matching of channel c (Heeger and Bergen 1995; Kopf et al.
 * 2007 match histograms within texture optimisation): the unknown values,
 * ranked (ties by index), take the exemplars' values at the same quantile,
 * linearly interpolated. The averaging of overlapping matches narrows the
 * distribution (a blend of two ridges is lower than either); this gives the
 * completed part the capture's spread of values, the layout the
 * optimisation's. */
static relief_status match_histogram(float *value, int ch, int c, size_t n,
                                     const uint8_t *unknown, const uint8_t *exemplar,
                                     relief_error *err)
{
    size_t nk = 0, nu = 0;
    ranked *k, *u;
    for (size_t i = 0; i < n; ++i)
        nk += exemplar[i] != 0, nu += unknown[i] != 0;
    if (nk == 0 || nu == 0)
        return RELIEF_OK;
    k = malloc(nk * sizeof *k);
    u = malloc(nu * sizeof *u);
    if (!k || !u) {
        free(k), free(u);
        return relief_fail(err, RELIEF_E_NOMEM, "texture optimisation: out of memory "
                           "(histograms)");
    }
    nk = nu = 0;
    for (size_t i = 0; i < n; ++i) {
        if (exemplar[i])
            k[nk].v = value[i * (size_t)ch + (size_t)c], k[nk++].i = (uint32_t)i;
        if (unknown[i])
            u[nu].v = value[i * (size_t)ch + (size_t)c], u[nu++].i = (uint32_t)i;
    }
    qsort(k, nk, sizeof *k, cmp_ranked);
    qsort(u, nu, sizeof *u, cmp_ranked);
    for (size_t r = 0; r < nu; ++r) {
        const double q = ((double)r + 0.5) / (double)nu * (double)nk - 0.5;
        const double qc = q < 0.0 ? 0.0 : q > (double)(nk - 1) ? (double)(nk - 1) : q;
        const size_t a = (size_t)qc, b = a + 1 < nk ? a + 1 : a;
        const double f = qc - (double)a;
        value[(size_t)u[r].i * ch + (size_t)c] = (float)((1.0 - f) * k[a].v + f * k[b].v);
    }
    free(k), free(u);
    return RELIEF_OK;
}

/* The exemplars whose distribution histogram matching gives the fill
 * (into ref, n flags): those among the active clusters' members, the
 * capture about the holes (about 680 points a cluster); every exemplar
 * when fewer than HIST_REF_MIN are (a clone scan, which no cluster
 * of the input's holds). The detail's spread differs over an
 * object (fertility's arm is smoother than its body), and a hole should
 * look like what is about it: against the whole capture's distribution the
 * fertility cut's fill came out 1.22 times as rough as the truth, against
 * its surroundings' 1.02 (README). */
#define HIST_REF_MIN 64

static void histogram_reference(const opt *o, size_t mlen, const uint8_t *exemplar, size_t n,
                                uint8_t *ref)
{
    size_t nr = 0;
    memset(ref, 0, n);
    for (size_t m = 0; m < mlen; ++m) {
        const uint32_t p = o->mpt[m];
        if (exemplar[p] && !ref[p])
            ref[p] = 1, ++nr;
    }
    if (nr < HIST_REF_MIN)
        memcpy(ref, exemplar, n);
}

/* One run's state: the parameters it runs at, what its stages build
 * (opt, the clusters, the exemplar grids, the E-step's lists) and free in
 * one place. */
typedef struct texrun {
    opt o;
    relief_texopt_params p;
    const double *pos;         /* n x 3 */
    size_t n;
    int channels, threads;
    relief_pclusters cl;
    relief_pbucket bk;
    relief_pgrid_weights gw;
    double *nrm;               /* n x 3, unit */
    double *energy;            /* max_iter */
    double h, band;            /* grid step, overlap band */
    uint32_t *cand;            /* a bucket query's points */
    size_t ncand_cap;
    uint32_t *elist;           /* the exemplar points, ne */
    size_t ne;
    size_t mlen, mcap, wlen, wcap; /* o.mpt/mfa/mfb, o.wpt/ww: used, allocated */
    uint32_t *acl;             /* the active clusters' indices in cl */
    size_t acap;
    float *zv;                 /* exemplar grids, zlen floats */
    size_t zlen, zcap;
    uint32_t *zq;              /* their centre points */
    size_t nzq, zqcap;
    size_t *pick;              /* the exemplar points' seeded order */
    size_t *pstart;            /* n + 1: per unknown point, its members in pent */
    uint32_t *pent;
    uint8_t *hist_ref;
    int iterations, converged;
    char search_note[336];
    relief_reason search_reason;
} texrun;

static void texrun_free(texrun *r)
{
    opt *o = &r->o;
    relief_grid_nn_destroy(o->nn);
    relief_pclusters_free(&r->cl);
    relief_pbucket_free(&r->bk);
    relief_pgrid_weights_free(&r->gw);
    free(r->nrm), free(r->energy), free(r->cand), free(r->elist), free(r->pick);
    free(r->pstart), free(r->pent), free(r->acl), free(r->zv), free(r->zq), free(r->hist_ref);
    free(o->zread), free(o->mstart), free(o->mpt), free(o->mfa), free(o->mfb), free(o->wstart);
    free(o->wpt), free(o->ww), free(o->x), free(o->match), free(o->q), free(o->cand);
}

static relief_status texrun_nomem(const texrun *r, relief_error *err)
{
    return relief_fail(err, RELIEF_E_NOMEM, "texture optimisation: out of memory (%zu points, "
                       "%d channels)", r->n, r->channels);
}

/* The working values (the unknown ones 0 until sequential_start sets them
 * before anything reads them), unit normals, the exemplar points, the
 * clusters, the grid step and the points' buckets. */
static relief_status run_prepare(texrun *r, const double *nrm_in, const float *value,
                                 const uint8_t *unknown, const uint8_t *exemplar,
                                 size_t n_exemplar, relief_error *err)
{
    opt *o = &r->o;
    const size_t n = r->n;
    const int channels = r->channels;
    relief_status st;
    o->gn = r->p.grid_n, o->ch = channels, o->nodes = r->p.grid_n * r->p.grid_n;
    o->dims = o->nodes * channels, o->lambda = r->p.lambda;
    r->nrm = malloc(3 * n * sizeof *r->nrm);
    o->x = malloc(n * (size_t)channels * sizeof *o->x);
    r->elist = malloc(n_exemplar * sizeof *r->elist);
    r->energy = malloc((size_t)r->p.max_iter * sizeof *r->energy);
    if (!r->nrm || !o->x || !r->elist || !r->energy)
        return texrun_nomem(r, err);
    for (size_t i = 0; i < n; ++i) {
        const double *m = nrm_in + 3 * i;
        const double l = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
        for (int a = 0; a < 3; ++a)
            r->nrm[3 * i + a] = m[a] / l;
        if (exemplar[i])
            r->elist[r->ne++] = (uint32_t)i;
    }
    memcpy(o->x, value, n * (size_t)channels * sizeof *o->x);
    for (size_t i = 0; i < n; ++i)
        if (unknown[i])
            memset(o->x + i * channels, 0, (size_t)channels * sizeof *o->x);
    st = relief_pclusters_make(r->pos, r->nrm, n, (size_t)r->p.cluster_size, &r->cl, err);
    if (st != RELIEF_OK)
        return st;
    r->h = r->p.grid_step > 0 ? r->p.grid_step : 2.0 * r->cl.mean_radius / r->p.grid_n;
    r->band = r->p.overlap * r->cl.mean_radius;
    if (!(r->h > 0))
        return relief_fail(err, RELIEF_E_RANGE, "texture optimisation: the points span no area "
                           "(mean cluster radius 0), so no grid step can be chosen");
    return relief_pbucket_make(r->pos, n, relief_pgrid_reach(o->gn, r->h), &r->bk, err);
}

/* Append member q at grid coordinates (fa, fb). 0, or -1 out of memory. */
static int push_member(texrun *r, uint32_t q, double fa, double fb)
{
    opt *o = &r->o;
    if (r->mlen == r->mcap) {
        const size_t ncap = r->mcap ? 2 * r->mcap : 4096;
        uint32_t *a = realloc(o->mpt, ncap * sizeof *a);
        float *b, *d;
        if (!a)
            return -1;
        o->mpt = a;
        if (!(b = realloc(o->mfa, ncap * sizeof *b)))
            return -1;
        o->mfa = b;
        if (!(d = realloc(o->mfb, ncap * sizeof *d)))
            return -1;
        o->mfb = d, r->mcap = ncap;
    }
    o->mpt[r->mlen] = q, o->mfa[r->mlen] = (float)fa, o->mfb[r->mlen++] = (float)fb;
    return 0;
}

/* Append the resampling weights of the next active cluster's grid (r->gw).
 * 0, or -1 out of memory. */
static int push_weights(texrun *r)
{
    opt *o = &r->o;
    size_t *ms = realloc(o->mstart, (o->A + 2) * sizeof *ms), *ws;
    if (!ms)
        return -1;
    o->mstart = ms;
    ws = realloc(o->wstart, ((o->A + 1) * (size_t)o->nodes + 1) * sizeof *ws);
    if (!ws)
        return -1;
    o->wstart = ws;
    for (int q = 0; q < o->nodes; ++q) {
        for (size_t t = r->gw.start[q]; t < r->gw.start[q + 1]; ++t) {
            if (r->wlen == r->wcap) {
                const size_t ncap = r->wcap ? 2 * r->wcap : 4096;
                uint32_t *a = realloc(o->wpt, ncap * sizeof *a);
                float *b;
                if (!a)
                    return -1;
                o->wpt = a;
                if (!(b = realloc(o->ww, ncap * sizeof *b)))
                    return -1;
                o->ww = b, r->wcap = ncap;
            }
            o->wpt[r->wlen] = r->gw.point[t], o->ww[r->wlen++] = r->gw.w[t];
        }
        o->wstart[o->A * (size_t)o->nodes + (size_t)q + 1] = r->wlen;
    }
    return 0;
}

/* Active clusters: C_O,i is C_i grown by the band; members outside G_i's
 * square are left out (no grid value there), except C_i's own, read at
 * the clamped border so that every point has a cluster. Only the clusters
 * holding an unknown point are kept. */
static relief_status build_active_clusters(texrun *r, const uint8_t *unknown, relief_error *err)
{
    opt *o = &r->o;
    const relief_pclusters *cl = &r->cl;
    const double k = (o->gn - 1) / 2.0, h = r->h;
    o->mstart = malloc(sizeof *o->mstart);
    o->wstart = malloc(sizeof *o->wstart);
    if (!o->mstart || !o->wstart)
        return texrun_nomem(r, err);
    o->mstart[0] = 0, o->wstart[0] = 0;
    for (size_t i = 0; i < cl->m; ++i) {
        const double *c = cl->centre + 3 * i, *f = cl->frame + 9 * i;
        size_t nc = relief_pbucket_query(&r->bk, c, cl->radius[i] + r->band, &r->cand,
                                         &r->ncand_cap);
        const size_t m0 = r->mlen;
        int any = 0;
        size_t empty, foreign;
        if (nc == SIZE_MAX)
            return texrun_nomem(r, err);
        for (size_t j = 0; j < nc; ++j) {
            const uint32_t q = r->cand[j];
            const double *nq = r->nrm + 3 * (size_t)q;
            const int own = cl->label[q] == i;
            double s, t, fa, fb;
            if (!own && nq[0] * f[6] + nq[1] * f[7] + nq[2] * f[8] < 0.3)
                continue;
            relief_ptangent(r->pos + 3 * (size_t)q, c, f, &s, &t);
            fa = s / h + k, fb = t / h + k;
            if (!own && (fa < 0 || fa > 2 * k || fb < 0 || fb > 2 * k))
                continue;
            fa = fa < 0 ? 0 : fa > 2 * k ? 2 * k : fa;
            fb = fb < 0 ? 0 : fb > 2 * k ? 2 * k : fb;
            if (push_member(r, q, fa, fb) < 0)
                return texrun_nomem(r, err);
            any |= unknown[q] != 0;
        }
        if (!any) {
            r->mlen = m0;
            continue;
        }
        nc = relief_pbucket_query(&r->bk, c, relief_pgrid_reach(o->gn, h), &r->cand,
                                  &r->ncand_cap);
        if (nc == SIZE_MAX || relief_pgrid_weigh(r->pos, r->nrm, r->cand, nc, c, f, o->gn, h,
                                                 NULL, &r->gw, &empty, &foreign) < 0 ||
            push_weights(r) < 0)
            return texrun_nomem(r, err);
        o->mstart[o->A + 1] = r->mlen;
        PUSH(r->acl, o->A, r->acap, (uint32_t)i);
    }
    return RELIEF_OK;
nomem:
    return texrun_nomem(r, err);
}

/* The exemplar grids of one contiguous share of the picked exemplar
 * points, kept in the share's own lists: the shares joined in order are
 * the serial lists, whatever the threads. */
typedef struct grid_share {
    uint32_t *zq, *cand;
    float *zv;
    size_t nzq, zqcap, zlen, zcap, ncand_cap;
    relief_pgrid_weights gw;
    int nomem;
} grid_share;

typedef struct grid_job {
    const texrun *r;
    const float *value;
    const uint8_t *exemplar;
    size_t want, parts;
    grid_share *share; /* parts */
} grid_job;

/* Pick e's grid into g when it is kept: no node reads a point that is not
 * an exemplar and at most a quarter of the nodes have no point within h.
 * 0, or -1 when out of memory. */
static int exemplar_grid(const grid_job *j, grid_share *g, size_t e)
{
    const texrun *r = j->r;
    const opt *o = &r->o;
    const int channels = r->channels;
    const uint32_t q = r->elist[r->pick[e]];
    const size_t nc = relief_pbucket_query(&r->bk, r->pos + 3 * (size_t)q,
                                           relief_pgrid_reach(o->gn, r->h), &g->cand,
                                           &g->ncand_cap);
    size_t empty, foreign;
    int got;
    if (nc == SIZE_MAX)
        return -1;
    got = relief_pgrid_weigh(r->pos, r->nrm, g->cand, nc, r->pos + 3 * (size_t)q,
                             r->cl.frame + 9 * (size_t)r->cl.label[q], o->gn, r->h, j->exemplar,
                             &g->gw, &empty, &foreign);
    if (got < 0)
        return -1;
    /* Up to a quarter of the nodes may have no point within h and take
     * their nearest exemplar point's value: where the grid is finer than
     * the sampling (a decimated scan's sparse parts), no grid would have
     * every node backed otherwise. */
    if (got == 0 || foreign || empty > (size_t)o->nodes / 4)
        return 0;
    if (g->zlen + (size_t)o->dims > g->zcap) {
        const size_t ncap = g->zcap ? 2 * g->zcap : 64 * (size_t)o->dims;
        float *a = realloc(g->zv, ncap * sizeof *a);
        if (!a)
            return -1;
        g->zv = a, g->zcap = ncap;
    }
    PUSH(g->zq, g->nzq, g->zqcap, q);
    for (int node = 0; node < o->nodes; ++node)
        for (int k = 0; k < channels; ++k) {
            double s = 0;
            for (size_t t = g->gw.start[node]; t < g->gw.start[node + 1]; ++t)
                s += (double)g->gw.w[t] * j->value[(size_t)g->gw.point[t] * channels + k];
            g->zv[g->zlen++] = (float)s;
        }
    return 0;
nomem:
    return -1;
}

static int grid_parts(void *ctx, size_t lo, size_t hi)
{
    const grid_job *j = ctx;
    for (size_t part = lo; part < hi; ++part) {
        grid_share *g = &j->share[part];
        const size_t e0 = j->want * part / j->parts, e1 = j->want * (part + 1) / j->parts;
        for (size_t e = e0; e < e1 && !g->nomem; ++e)
            g->nomem = exemplar_grid(j, g, e) < 0;
    }
    return 0;
}

/* The shares' lists joined in order into r's. 0, or -1 when out of memory. */
static int join_grids(texrun *r, const grid_job *j)
{
    size_t nzq = 0, zlen = 0;
    for (size_t part = 0; part < j->parts; ++part) {
        if (j->share[part].nomem)
            return -1;
        nzq += j->share[part].nzq, zlen += j->share[part].zlen;
    }
    r->zq = malloc((nzq ? nzq : 1) * sizeof *r->zq);
    r->zv = malloc((zlen ? zlen : 1) * sizeof *r->zv);
    if (!r->zq || !r->zv)
        return -1;
    r->zqcap = nzq ? nzq : 1, r->zcap = zlen ? zlen : 1;
    for (size_t part = 0; part < j->parts; ++part) {
        const grid_share *g = &j->share[part];
        if (!g->nzq)
            continue; /* a share that kept no grid has no lists */
        memcpy(r->zq + r->nzq, g->zq, g->nzq * sizeof *g->zq);
        memcpy(r->zv + r->zlen, g->zv, g->zlen * sizeof *g->zv);
        r->nzq += g->nzq, r->zlen += g->zlen;
    }
    return 0;
}

/* Exemplar grids: at the exemplar points (a seeded subset of MAX_EXEMPLARS
 * beyond that many), in the frame of the point's cluster, built over the
 * threads (exemplar_grid says which are kept). *no_grid set when none is. */
static relief_status build_exemplar_grids(texrun *r, const float *value,
                                          const uint8_t *exemplar, int *no_grid,
                                          relief_error *err)
{
    opt *o = &r->o;
    const size_t ne = r->ne, want = ne < MAX_EXEMPLARS ? ne : MAX_EXEMPLARS;
    const uint32_t seed32 = (uint32_t)(r->p.seed ^ (r->p.seed >> 32));
    const size_t parts = r->threads < 1 ? 1 : (size_t)r->threads;
    grid_job j = {r, value, exemplar, want, parts, calloc(parts, sizeof(grid_share))};
    int failed;
    r->pick = malloc(ne * sizeof *r->pick);
    if (!r->pick || !j.share) {
        free(j.share);
        return texrun_nomem(r, err);
    }
    relief_rng_subset(r->pick, ne, want, seed32);
    relief_parallel_ranges(parts, r->threads, grid_parts, &j);
    failed = join_grids(r, &j);
    for (size_t part = 0; part < parts; ++part) {
        grid_share *g = &j.share[part];
        free(g->zq), free(g->zv), free(g->cand);
        relief_pgrid_weights_free(&g->gw);
    }
    free(j.share);
    if (failed)
        return texrun_nomem(r, err);
    o->nz = r->zlen / (size_t)o->dims;
    if (!o->nz) {
        *no_grid = 1;
        return relief_fail(err, RELIEF_E_RANGE, "texture optimisation: no exemplar grid can be "
                           "built: none of %zu exemplar points has its %d x %d grid (step %g) "
                           "backed by exemplar points alone, three quarters of its nodes "
                           "within a step of one; mark a larger exemplar region or lower "
                           "grid_n", want, o->gn, o->gn, r->h);
    }
    return RELIEF_OK;
}

/* Per unknown point, the members standing for it (the E-step's lists),
 * the M-step's buffers and the exemplar grids' search. */
static relief_status build_search(texrun *r, const uint8_t *unknown, const uint8_t *exemplar,
                                  relief_error *err)
{
    opt *o = &r->o;
    const size_t n = r->n, mlen = r->mlen;
    size_t *fill;
    if (o->A == 0) /* cannot happen: every unknown point is its own cluster's member */
        return relief_fail(err, RELIEF_E_INTERNAL, "texture optimisation: no active cluster");
    r->pstart = calloc(n + 1, sizeof *r->pstart);
    o->match = malloc(o->A * sizeof *o->match);
    r->pent = malloc((mlen ? mlen : 1) * sizeof *r->pent);
    fill = malloc(n * sizeof *fill);
    if (!r->pstart || !o->match || !r->pent || !fill) {
        free(fill);
        return texrun_nomem(r, err);
    }
    for (size_t m = 0; m < mlen; ++m)
        if (unknown[o->mpt[m]])
            ++r->pstart[o->mpt[m] + 1];
    for (size_t i = 0; i < n; ++i)
        r->pstart[i + 1] += r->pstart[i];
    memcpy(fill, r->pstart, n * sizeof *fill);
    for (size_t m = 0; m < mlen; ++m)
        if (unknown[o->mpt[m]])
            r->pent[fill[o->mpt[m]]++] = (uint32_t)m;
    free(fill);
    o->zvec = r->zv;
    o->pos = r->pos, o->nrm = r->nrm, o->exemplar = exemplar, o->bk = &r->bk;
    o->frame = r->cl.frame, o->label = r->cl.label, o->zq = r->zq, o->h = r->h;
    o->zread = malloc(mlen * (size_t)r->channels * sizeof *o->zread + 1);
    o->q = malloc(o->A * (size_t)o->dims * sizeof *o->q + 1);
    o->cand = malloc(o->A * CANDIDATES * sizeof *o->cand + 1);
    if (!o->zread || !o->q || !o->cand)
        return texrun_nomem(r, err);
    for (size_t j = 0; j < o->A; ++j)
        o->match[j] = UINT32_MAX;
    return relief_grid_nn_create(r->p.brute ? RELIEF_GRID_SEARCH_BRUTE
                                            : RELIEF_GRID_SEARCH_KDTREE,
                                 r->p.backend, r->p.device, r->zv, o->nz, o->dims, r->threads,
                                 &o->nn, r->search_note, sizeof r->search_note,
                                 &r->search_reason, err);
}

/* The E-step: each unknown point the centre-weighted mean of its members'
 * reads in their clusters' matches. */
static void run_estep(texrun *r)
{
    opt *o = &r->o;
    const int channels = r->channels;
    for (size_t i = 0; i < r->n; ++i) {
        float acc[4] = {0, 0, 0, 0}, wsum = 0.0f;
        if (r->pstart[i] == r->pstart[i + 1])
            continue;
        for (size_t t = r->pstart[i]; t < r->pstart[i + 1]; ++t) {
            const size_t m = r->pent[t];
            const float w = centre_weight(o->gn, o->mfa[m], o->mfb[m]);
            for (int k = 0; k < channels; ++k) /* m's value in its cluster's match */
                acc[k] += w * o->zread[m * channels + k];
            wsum += w;
        }
        for (int k = 0; k < channels; ++k)
            o->x[i * channels + k] = acc[k] / wsum;
    }
}

/* M-step, E-step, until E changes by less than tol relatively, is 0, or
 * max_iter; the progress after each iteration. */
static relief_status run_iterations(texrun *r, relief_error *err)
{
    opt *o = &r->o;
    relief_progress *pr = r->p.progress;
    int it = 0;
    while (it < r->p.max_iter) {
        double e = 0;
        relief_status st = run_mstep(o, r->threads, err);
        if (st != RELIEF_OK)
            return st;
        run_estep(r);
        for (size_t j = 0; j < o->A; ++j)
            e += cluster_energy(o, j, o->zread + o->mstart[j] * r->channels);
        r->energy[it++] = e;
        r->iterations = it;
        if (relief_progress_step(pr, START_SHARE + (1.0 - START_SHARE) * it / r->p.max_iter))
            return texopt_cancelled(pr, err);
        if ((it > 1 && fabs(r->energy[it - 2] - e) <= r->p.tol * r->energy[it - 2]) || e == 0) {
            r->converged = 1;
            break;
        }
    }
    return RELIEF_OK;
}

/* The histogram matching on the working values, then the unknown ones
 * into value (so that a failure leaves value unchanged), and res. */
static relief_status run_finish(texrun *r, float *value, const uint8_t *unknown,
                                const uint8_t *exemplar, relief_texopt_result *res,
                                relief_error *err)
{
    opt *o = &r->o;
    const int channels = r->channels;
    if (r->p.histogram) {
        r->hist_ref = malloc(r->n);
        if (!r->hist_ref)
            return texrun_nomem(r, err);
        histogram_reference(o, r->mlen, exemplar, r->n, r->hist_ref);
    }
    for (int c = 0; c < channels; ++c)
        if (r->p.histogram & (1u << c)) {
            relief_status st = match_histogram(o->x, channels, c, r->n, unknown, r->hist_ref,
                                               err);
            if (st != RELIEF_OK)
                return st;
        }
    for (size_t i = 0; i < r->n; ++i)
        if (unknown[i])
            memcpy(value + i * channels, o->x + i * channels, (size_t)channels * sizeof *value);
    if (res) {
        res->clusters = r->cl.m;
        res->active_clusters = o->A;
        res->exemplars = o->nz;
        res->iterations = r->iterations;
        res->energy = r->energy;
        res->converged = r->converged;
        res->grid_n = o->gn;
        res->cluster_size = r->p.cluster_size;
        snprintf(res->search, sizeof res->search, "%s", r->search_note);
        res->search_reason = r->search_reason;
        r->energy = NULL;
    }
    return RELIEF_OK;
}

/* One run at the given parameters; *no_grid set when it failed only
 * because no exemplar grid could be built. */
static relief_status texopt_run(const double *pos, const double *nrm_in, size_t n, int channels,
                                float *value, const uint8_t *unknown, const uint8_t *exemplar,
                                const uint8_t *rim, const relief_texopt_params *pp,
                                relief_texopt_result *res, int *no_grid, relief_error *err)
{
    texrun r;
    size_t n_unknown = 0, n_exemplar = 0;
    relief_status st = check(pos, nrm_in, n, channels, value, unknown, exemplar, pp, &n_unknown,
                             &n_exemplar, err);
    if (st != RELIEF_OK)
        return st;
    memset(&r, 0, sizeof r);
    r.p = *pp, r.pos = pos, r.n = n, r.channels = channels, r.o.rim = rim;
    r.threads = r.p.threads;
    if (r.threads == 0) /* the CPUs this thread may run on */
        r.threads = relief_pool_default_threads();
    st = run_prepare(&r, nrm_in, value, unknown, exemplar, n_exemplar, err);
    if (st == RELIEF_OK)
        st = build_active_clusters(&r, unknown, err);
    if (st == RELIEF_OK)
        st = build_exemplar_grids(&r, value, exemplar, no_grid, err);
    if (st == RELIEF_OK)
        st = build_search(&r, unknown, exemplar, err);
    if (st == RELIEF_OK)
        st = sequential_start(&r.o, unknown, n, r.threads, r.p.progress, err);
    if (st == RELIEF_OK)
        st = run_iterations(&r, err);
    if (st == RELIEF_OK)
        st = run_finish(&r, value, unknown, exemplar, res, err);
    texrun_free(&r);
    return st;
}

relief_status relief_texopt_complete(const double *pos, const double *nrm, size_t n,
                                     int channels, float *value, const uint8_t *unknown,
                                     const uint8_t *exemplar, const uint8_t *rim,
                                     const relief_texopt_params *pp,
                                     relief_texopt_result *res, relief_error *err)
{
    relief_texopt_params p = pp ? *pp : relief_texopt_params_default();
    relief_status st;
    /* A capture too small or too thin for the grids (no exemplar grid with
     * three quarters of its nodes on it) is tried again with clusters of
     * half the points and grids of 1/sqrt 2 the side, the same node step,
     * down to grids of 7: a smaller texture element rather than none. */
    for (;;) {
        int no_grid = 0;
        st = texopt_run(pos, nrm, n, channels, value, unknown, exemplar, rim, &p, res, &no_grid,
                        err);
        if (st == RELIEF_OK || !no_grid || p.grid_n <= 7 || p.cluster_size <= 32 ||
            p.grid_step > 0)
            return st;
        p.cluster_size /= 2;
        p.grid_n = (int)(p.grid_n / 1.41421356) | 1;
        if (p.grid_n < 7)
            p.grid_n = 7;
    }
}
