#include "smooth/oversample.h"

#include "base/knn.h"
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/vec3.h"
#include "mesh/mesh.h"

/* Ties with the k-th nearest squared distance, relative. */
#define TIE_REL 1e-9
/* Bound on the (index, distance) entries one FLANN query batch holds. */
#define QUERY_BATCH_ENTRIES ((size_t)1 << 22)

relief_oversample_params relief_oversample_params_default(void)
{
    relief_oversample_params p;
    p.k = 6;
    p.sigma = 0.0;
    p.scheme = RELIEF_OVERSAMPLE_BUTTERFLY;
    return p;
}

/* One triangle corner ("slot" s = 3 t + c, the edge from corner c to c + 1)
 * filed under its edge's smaller endpoint. */
typedef struct slot_ref {
    uint32_t hi;   /* larger endpoint */
    uint32_t slot; /* 3 t + c */
} slot_ref;

static int slot_ref_cmp(const void *x, const void *y)
{
    const slot_ref *a = x, *b = y;
    if (a->hi != b->hi)
        return a->hi < b->hi ? -1 : 1;
    return (a->slot > b->slot) - (a->slot < b->slot);
}

/* Buckets are mostly a vertex's handful of edges: insertion sort; a hub
 * vertex (a fan's apex) gets qsort so it stays n log n. */
static void sort_bucket(slot_ref *r, size_t n)
{
    if (n > 16) {
        qsort(r, n, sizeof *r, slot_ref_cmp);
        return;
    }
    for (size_t i = 1; i < n; ++i) {
        slot_ref x = r[i];
        size_t j = i;
        while (j > 0 && slot_ref_cmp(&r[j - 1], &x) > 0) {
            r[j] = r[j - 1];
            --j;
        }
        r[j] = x;
    }
}

static uint32_t slot_end(const uint32_t *tri, size_t s)
{
    return tri[s - s % 3 + (s % 3 + 1) % 3];
}

/* Largest valence the butterfly stencils take; a vertex with more keeps
 * its edges' midpoints. */
#define RING_MAX 64

/* The 1-ring of vertex a in rotational order from b (ring[0] = b), walked
 * across a's n triangles `vt`. Returns its length k (the valence), or 0
 * when a is on the boundary, its triangles do not form one closed fan, or
 * k > RING_MAX. Either direction: the stencils are symmetric. */
static int ring_from(const uint32_t *tri, const uint32_t *vt, size_t n, uint32_t a,
                     uint32_t b, uint32_t *ring)
{
    uint32_t cur = b, prev = UINT32_MAX;
    int k = 0;

    if (n < 3 || n > RING_MAX)
        return 0;
    for (;;) {
        uint32_t next = UINT32_MAX, t_next = UINT32_MAX;
        ring[k++] = cur;
        for (size_t i = 0; i < n && t_next == UINT32_MAX; ++i) {
            const uint32_t *f = tri + 3 * (size_t)vt[i];
            int has_a = 0, has_cur = 0;
            if (vt[i] == prev)
                continue;
            for (int c = 0; c < 3; ++c) {
                has_a |= f[c] == a;
                has_cur |= f[c] == cur;
            }
            if (!has_a || !has_cur)
                continue;
            t_next = vt[i];
            for (int c = 0; c < 3; ++c)
                if (f[c] != a && f[c] != cur)
                    next = f[c];
        }
        if (t_next == UINT32_MAX || next == UINT32_MAX)
            return 0; /* a boundary edge (a, cur) */
        if (next == b)
            return (size_t)k == n ? k : 0;
        if ((size_t)k >= n)
            return 0;
        prev = t_next;
        cur = next;
    }
}

/* Adds w times the stencil of an extraordinary vertex a of valence k with
 * ring[0] the edge's other end (Zorin, Schroeder and Sweldens 1996):
 * 3/4 a + sum_j s_j ring[j], s_j = (1/4 + cos(2 pi j / k) + cos(4 pi j / k)
 * / 2) / k for k >= 5, {5/12, -1/12, -1/12} for k = 3 and {3/8, 0, -1/8, 0}
 * for k = 4. */
static void add_ring_stencil(const double *pos, uint32_t a, const uint32_t *ring, int k,
                             double w, double q[3])
{
    for (int i = 0; i < 3; ++i)
        q[i] += w * 0.75 * pos[3 * (size_t)a + i];
    for (int j = 0; j < k; ++j) {
        double sj;
        if (k == 3)
            sj = j == 0 ? 5.0 / 12.0 : -1.0 / 12.0;
        else if (k == 4)
            sj = j == 0 ? 3.0 / 8.0 : j == 2 ? -1.0 / 8.0 : 0.0;
        else
            sj = (0.25 + cos(2.0 * RELIEF_PI * j / k) + 0.5 * cos(4.0 * RELIEF_PI * j / k)) / k;
        for (int i = 0; i < 3; ++i)
            q[i] += w * sj * pos[3 * (size_t)ring[j] + i];
    }
}

/* Each edge's first slot, first[e] (ne of them), and how many slots it
 * has, cnt[e] (ne, zeros; counted up to 3: 2 is an interior manifold
 * edge), from edge (ns slots: each slot's edge id). */
static void count_edge_slots(const uint32_t *edge, size_t ns, uint32_t *first, uint8_t *cnt)
{
    for (size_t s = 0; s < ns; ++s) {
        const uint32_t e = edge[s];
        if (cnt[e] == 0)
            first[e] = (uint32_t)s;
        if (cnt[e] < 3)
            ++cnt[e];
    }
}

/* The modified butterfly point bf (3, the mesh's units) of the interior
 * edge (a, b) of pos (nv x 3): ra (ka of them) is a's 1-ring from b, rb
 * (kb) b's from a, neither end on the boundary. */
static void butterfly_point(const double *pos, uint32_t a, uint32_t b, const uint32_t *ra,
                            int ka, const uint32_t *rb, int kb, double bf[3])
{
    if (ka == 6 && kb == 6) {
        /* Regular: 1/2 (a + b) + 1/8 (c + d) - 1/16 (wings), with c, d
         * = ra[1], ra[5] and the wings ra[2], ra[4], rb[2], rb[4]. */
        for (int i = 0; i < 3; ++i)
            bf[i] = 0.5 * (pos[3 * (size_t)a + i] + pos[3 * (size_t)b + i]) +
                    0.125 * (pos[3 * (size_t)ra[1] + i] + pos[3 * (size_t)ra[5] + i]) -
                    0.0625 * (pos[3 * (size_t)ra[2] + i] + pos[3 * (size_t)ra[4] + i] +
                              pos[3 * (size_t)rb[2] + i] + pos[3 * (size_t)rb[4] + i]);
    } else {
        bf[0] = bf[1] = bf[2] = 0.0;
        if (ka != 6 && kb != 6) {
            add_ring_stencil(pos, a, ra, ka, 0.5, bf);
            add_ring_stencil(pos, b, rb, kb, 0.5, bf);
        } else if (ka != 6) {
            add_ring_stencil(pos, a, ra, ka, 1.0, bf);
        } else {
            add_ring_stencil(pos, b, rb, kb, 1.0, bf);
        }
    }
}

/* q (3), the midpoint of edge (a, b) of pos (nv x 3), moved to bf (3)
 * unless that is over half the edge away. A smooth surface moves it by a
 * small part of the edge; a spike or sliver in the capture can throw it
 * far off, and a sample out there would be copied into the completion. */
static void move_if_near(const double *pos, uint32_t a, uint32_t b, const double bf[3],
                         double q[3])
{
    double move2 = 0.0, len2 = 0.0;
    for (int i = 0; i < 3; ++i) {
        const double dm = bf[i] - q[i];
        const double de = pos[3 * (size_t)a + i] - pos[3 * (size_t)b + i];
        move2 += dm * dm;
        len2 += de * de;
    }
    if (move2 <= 0.25 * len2)
        memcpy(q, bf, 3 * sizeof *bf);
}

/* Moves every new vertex of m (nv + e for edge e of src) from its edge's
 * midpoint to the modified butterfly point (oversample.h). */
static relief_status butterfly(const relief_mesh *src, const uint32_t *edge,
                               size_t ne, relief_mesh *m, relief_error *err)
{
    const uint32_t *tri = src->tri;
    const size_t ns = 3 * src->nt, nv = src->nv;
    const double *pos = src->pos;
    uint32_t *first = malloc(ne * sizeof *first);
    uint8_t *cnt = calloc(ne, 1);
    uint32_t *vt_start = malloc((nv + 1) * sizeof *vt_start);
    uint32_t *vt = malloc(ns * sizeof *vt);
    uint32_t ra[RING_MAX], rb[RING_MAX];
    double bf[3];

    if (!first || !cnt || !vt_start || !vt) {
        free(first);
        free(cnt);
        free(vt_start);
        free(vt);
        return relief_fail(err, RELIEF_E_NOMEM,
                           "cannot allocate the butterfly tables of %zu edges", ne);
    }
    relief_mesh_vertex_triangles(src, vt_start, vt);
    count_edge_slots(edge, ns, first, cnt);
    for (size_t e = 0; e < ne; ++e) {
        const uint32_t a = tri[first[e]], b = slot_end(tri, first[e]);
        double *q = m->pos + 3 * (nv + e);
        int ka, kb;

        if (cnt[e] != 2)
            continue; /* a boundary or non-manifold edge */
        ka = ring_from(tri, vt + vt_start[a], vt_start[a + 1] - vt_start[a], a, b, ra);
        kb = ring_from(tri, vt + vt_start[b], vt_start[b + 1] - vt_start[b], b, a, rb);
        if (!ka || !kb)
            continue; /* an end on the boundary */
        butterfly_point(pos, a, b, ra, ka, rb, kb, bf);
        move_if_near(pos, a, b, bf, q);
    }
    free(first);
    free(cnt);
    free(vt_start);
    free(vt);
    return RELIEF_OK;
}

/* The distinct edges of src's 3 nt slots: edge[s] gets the first slot of
 * s's edge, and the count of edges is returned. Counting sort of the slots
 * by smaller endpoint, then each bucket by (larger endpoint, slot): a run of
 * equal pairs is one edge and its first entry is the edge's first
 * appearance. Linear memory, no hashing, and the same order on every
 * platform. off: nv + 1 zeros; ref: 3 nt scratch. */
static size_t find_edges(const relief_mesh *src, uint32_t *off, slot_ref *ref, uint32_t *edge)
{
    const size_t nv = src->nv, ns = 3 * src->nt;
    const uint32_t *tri = src->tri;
    size_t ne = 0;
    for (size_t s = 0; s < ns; ++s) {
        uint32_t a = tri[s], b = slot_end(tri, s);
        ++off[(a < b ? a : b) + 1];
    }
    for (size_t v = 0; v < nv; ++v)
        off[v + 1] += off[v];
    for (size_t s = 0; s < ns; ++s) {
        uint32_t a = tri[s], b = slot_end(tri, s);
        slot_ref r;
        r.hi = a < b ? b : a;
        r.slot = (uint32_t)s;
        ref[off[a < b ? a : b]++] = r;
    }
    memmove(off + 1, off, nv * sizeof *off);
    off[0] = 0;
    for (size_t v = 0; v < nv; ++v) {
        slot_ref *r = ref + off[v];
        size_t n = off[v + 1] - off[v];
        uint32_t first = 0;
        sort_bucket(r, n);
        for (size_t i = 0; i < n; ++i) {
            if (i == 0 || r[i].hi != r[i - 1].hi)
                first = r[i].slot;
            edge[r[i].slot] = first;
        }
    }
    for (size_t s = 0; s < ns; ++s)
        ne += edge[s] == s;
    return ne;
}

/* The new vertex of each edge at its midpoint, in m after src's nv, with
 * its normal and label; len (NULL, or one per edge) gets each edge's
 * length. edge[s] holds the first slot of s's edge, which is <= s, so
 * walking the slots in order meets every edge's first slot before its
 * others and can overwrite edge[] in place with dense edge ids. */
static void place_midpoints(const relief_mesh *src, uint32_t *edge, relief_mesh *m, double *len)
{
    const size_t nv = src->nv, ns = 3 * src->nt;
    const uint32_t *tri = src->tri;
    size_t next = 0;
    for (size_t s = 0; s < ns; ++s) {
        uint32_t a, b, lo, hi;
        size_t e, v;
        const double *pa, *pb;
        double *q;

        if (edge[s] != s) {
            edge[s] = edge[edge[s]];
            continue;
        }
        e = next++;
        edge[s] = (uint32_t)e;
        a = tri[s];
        b = slot_end(tri, s);
        lo = a < b ? a : b;
        hi = a < b ? b : a;
        v = nv + e;
        pa = src->pos + 3 * (size_t)lo;
        pb = src->pos + 3 * (size_t)hi;
        q = m->pos + 3 * v;
        for (int c = 0; c < 3; ++c)
            q[c] = 0.5 * (pa[c] + pb[c]);
        if (len) {
            double d0 = pb[0] - pa[0], d1 = pb[1] - pa[1], d2 = pb[2] - pa[2];
            len[e] = sqrt(d0 * d0 + d1 * d1 + d2 * d2);
        }
        if (m->nrm && src->nrm) {
            const double *na = src->nrm + 3 * (size_t)lo;
            const double *nb = src->nrm + 3 * (size_t)hi;
            double *n = m->nrm + 3 * v, l;
            for (int c = 0; c < 3; ++c)
                n[c] = na[c] + nb[c];
            l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            for (int c = 0; c < 3; ++c)
                n[c] = l > 0.0 ? n[c] / l : na[c];
        }
        if (m->label && src->label)
            m->label[v] = src->label[lo] == src->label[hi]
                              ? src->label[lo]
                              : (uint8_t)RELIEF_LABEL_CAPTURED;
    }
}

/* m (nv + ne vertices, 4 nt triangles, created) as src subdivided: src's
 * vertices with their normals and labels where both carry them, each
 * edge's new vertex after them placed by `scheme`, and each triangle's
 * four children on its corners and its edges' vertices. edge (3 nt) holds
 * each slot's first slot on entry and its edge id on return; len (NULL,
 * or ne) gets each edge's length. Fails only as butterfly does. */
static relief_status subdivide(const relief_mesh *src, int scheme, uint32_t *edge, size_t ne,
                               relief_mesh *m, double *len, relief_error *err)
{
    const size_t nv = src->nv, nt = src->nt;
    const uint32_t *tri = src->tri;
    relief_status st;

    memcpy(m->pos, src->pos, nv * 3 * sizeof *m->pos);
    if (m->nrm && src->nrm)
        memcpy(m->nrm, src->nrm, nv * 3 * sizeof *m->nrm);
    if (m->label && src->label)
        memcpy(m->label, src->label, nv);
    place_midpoints(src, edge, m, len);
    if (scheme == RELIEF_OVERSAMPLE_BUTTERFLY) {
        st = butterfly(src, edge, ne, m, err);
        if (st != RELIEF_OK)
            return st;
    }
    /* Each triangle's four children, on its corners and edges' vertices. */
    for (size_t t = 0; t < nt; ++t) {
        const uint32_t a = tri[3 * t], b = tri[3 * t + 1], c = tri[3 * t + 2];
        const uint32_t ab = (uint32_t)(nv + edge[3 * t]);
        const uint32_t bc = (uint32_t)(nv + edge[3 * t + 1]);
        const uint32_t ca = (uint32_t)(nv + edge[3 * t + 2]);
        const uint32_t child[12] = {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca};
        memcpy(m->tri + 12 * t, child, sizeof child);
    }
    return RELIEF_OK;
}

/* One 1-to-4 pass of src into a new mesh carrying `attrs` (src's normals and
 * labels are propagated when both carry them; colour is left zero for the
 * caller), the new vertices placed by `scheme`. When `edge_len` is not NULL
 * it receives the length of each distinct edge of src (malloc'd, *n_edges
 * entries). */
static relief_status split_once(const relief_mesh *src, unsigned attrs, int scheme,
                                relief_mesh **dst, double **edge_len,
                                size_t *n_edges, relief_error *err)
{
    const size_t nv = src->nv, nt = src->nt;
    uint32_t *off = NULL, *edge = NULL;
    slot_ref *ref = NULL;
    double *len = NULL;
    relief_mesh *m = NULL;
    relief_status st = RELIEF_OK;
    size_t ns, ne;

    /* Slots are numbered in uint32; 4 nt children must fit too. */
    if (nt > UINT32_MAX / 4)
        return relief_fail(err, RELIEF_E_RANGE,
                           "cannot oversample %zu triangles: at most %u are "
                           "supported per pass", nt, (unsigned)(UINT32_MAX / 4));
    ns = 3 * nt;
    off = calloc(nv + 1, sizeof *off);
    ref = malloc(ns * sizeof *ref);
    edge = malloc(ns * sizeof *edge);
    if (!off || !ref || !edge) {
        st = relief_fail(err, RELIEF_E_NOMEM,
                         "cannot allocate the edge table of %zu triangles", nt);
        goto done;
    }
    ne = find_edges(src, off, ref, edge);
    if (ne > (size_t)UINT32_MAX - nv) {
        st = relief_fail(err, RELIEF_E_RANGE,
                         "oversampling %zu vertices and %zu edges gives more "
                         "than %u vertices", nv, ne, (unsigned)UINT32_MAX);
        goto done;
    }
    st = relief_mesh_create(nv + ne, 4 * nt, attrs, &m, err);
    if (st != RELIEF_OK)
        goto done;
    if (edge_len) {
        len = malloc(ne * sizeof *len);
        if (!len) {
            st = relief_fail(err, RELIEF_E_NOMEM,
                             "cannot allocate the lengths of %zu edges", ne);
            goto done;
        }
    }
    st = subdivide(src, scheme, edge, ne, m, len, err);
    if (st != RELIEF_OK)
        goto done;

    *dst = m;
    m = NULL;
    if (edge_len) {
        *edge_len = len;
        *n_edges = ne;
        len = NULL;
    }
done:
    free(len);
    relief_mesh_destroy(m);
    free(edge);
    free(ref);
    free(off);
    return st;
}

static int double_cmp(const void *x, const void *y)
{
    const double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

static double median(double *x, size_t n)
{
    qsort(x, n, sizeof *x, double_cmp);
    return n % 2 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]);
}

/* The sizes of the colour queries of nnew vertices among nv0, k asked:
 * *kq = min(k, nv0) neighbours blended, out of *nq = min(2 kq, nv0) that
 * each query fetches (ties with the kq-th come from the rest), *batch
 * queries at a time (QUERY_BATCH_ENTRIES / nq, at most nnew); and a
 * batch's lists, *idx (int) and *d2 (double) of batch x nq each,
 * malloc'd. RELIEF_E_NOMEM when either list cannot be had; the caller
 * frees both lists whatever the result. */
static relief_status query_lists(int k, size_t nv0, size_t nnew, size_t *kq, size_t *nq,
                                 size_t *batch, int **idx, double **d2, relief_error *err)
{
    *kq = (size_t)k < nv0 ? (size_t)k : nv0;
    *nq = 2 * *kq < nv0 ? 2 * *kq : nv0;
    *batch = QUERY_BATCH_ENTRIES / *nq;
    if (*batch > nnew)
        *batch = nnew;
    *idx = malloc(*batch * *nq * sizeof **idx);
    *d2 = malloc(*batch * *nq * sizeof **d2);
    if (!*idx || !*d2)
        return relief_fail(err, RELIEF_E_NOMEM,
                           "cannot allocate the neighbour lists of %zu vertices",
                           *batch);
    return RELIEF_OK;
}

/* The nq neighbours of one query, indices ii and squared distances dd (nq
 * each, as FLANN returned them, by distance), put in the canonical order
 * (distance, index) in place: FLANN's list is sorted by distance already,
 * so this only orders ties and fixes the summation order. */
static void order_neighbours(int *ii, double *dd, size_t nq)
{
    for (size_t j = 1; j < nq; ++j) {
        int xi = ii[j];
        double xd = dd[j];
        size_t l = j;
        while (l > 0 && (dd[l - 1] > xd || (dd[l - 1] == xd && ii[l - 1] > xi))) {
            ii[l] = ii[l - 1];
            dd[l] = dd[l - 1];
            --l;
        }
        ii[l] = xi;
        dd[l] = xd;
    }
}

/* The colour col (3 floats in [0, 1]) of out's vertex `vertex`: the Gaussian
 * blend, weight exp(-d^2 / (2 sigma^2)) with inv2s2 = 1 / (2 sigma^2), of
 * in's colours at the kq nearest of the nq neighbours ii, dd (canonical
 * order, squared distances in the mesh's units) and at those tied with the
 * kq-th. RELIEF_E_INTERNAL, col unwritten, when a neighbour is not one of
 * in's nv0 vertices. */
static relief_status blend_neighbours(const relief_mesh *in, const int *ii, const double *dd,
                                      size_t kq, size_t nq, size_t vertex, double inv2s2,
                                      float *col, relief_error *err)
{
    const size_t nv0 = in->nv;
    double sw = 0.0, sc[3] = {0.0, 0.0, 0.0}, lim;
    size_t m = kq;

    lim = dd[kq - 1] * (1.0 + TIE_REL);
    while (m < nq && dd[m] <= lim)
        ++m;
    /* Weights relative to the nearest one (w = 1 there): the
     * normalised sum is the same and cannot underflow to 0/0 when
     * sigma is small against the spacing. */
    for (size_t j = 0; j < m; ++j) {
        const float *c;
        double w;
        if (ii[j] < 0 || (size_t)ii[j] >= nv0)
            return relief_fail(err, RELIEF_E_INTERNAL,
                               "FLANN returned neighbour %d of vertex "
                               "%zu, outside 0..%zu", ii[j],
                               vertex, nv0 - 1);
        c = in->col + 3 * (size_t)ii[j];
        w = exp(-(dd[j] - dd[0]) * inv2s2);
        sw += w;
        for (int ch = 0; ch < 3; ++ch)
            sc[ch] += w * c[ch];
    }
    for (int ch = 0; ch < 3; ++ch) {
        double v = sc[ch] / sw;
        col[ch] = (float)(v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v);
    }
    return RELIEF_OK;
}

/* Colour of out's vertices past in->nv from the k nearest of in's vertices
 * (out's first in->nv vertices are in's, colour copied). */
static relief_status transfer_colour(const relief_mesh *in, relief_mesh *out,
                                     int k, double sigma, relief_error *err)
{
    const size_t nv0 = in->nv, nnew = out->nv - in->nv;
    struct FLANNParameters fp = relief_knn_exact_params();
    flann_index_t index = NULL;
    int *idx = NULL;
    double *d2 = NULL;
    relief_status st = RELIEF_OK;
    size_t kq, nq, batch;
    float speedup = 0.0f;
    const double inv2s2 = 1.0 / (2.0 * sigma * sigma);

    memcpy(out->col, in->col, nv0 * 3 * sizeof *out->col);
    if (nnew == 0)
        return RELIEF_OK;
    if (nv0 > INT_MAX)
        return relief_fail(err, RELIEF_E_RANGE,
                           "colour transfer: %zu original vertices; the "
                           "nearest-neighbour search takes at most %d", nv0,
                           INT_MAX);
    st = query_lists(k, nv0, nnew, &kq, &nq, &batch, &idx, &d2, err);
    if (st != RELIEF_OK)
        goto done;

    /* FLANN's C API takes non-const data; it only reads it (and copies it,
     * as the single kd-tree reorders its points). */
    index = flann_build_index_double((double *)in->pos, (int)nv0, 3, &speedup,
                                     &fp);
    if (!index) {
        st = relief_fail(err, RELIEF_E_INTERNAL,
                         "FLANN could not build a kd-tree on %zu vertices", nv0);
        goto done;
    }

    for (size_t q0 = 0; q0 < nnew; q0 += batch) {
        const size_t nb = nnew - q0 < batch ? nnew - q0 : batch;
        double *qpos = out->pos + 3 * (nv0 + q0);
        if (flann_find_nearest_neighbors_index_double(index, qpos, (int)nb, idx,
                                                      d2, (int)nq, &fp) != 0) {
            st = relief_fail(err, RELIEF_E_INTERNAL,
                             "FLANN nearest-neighbour search failed for "
                             "vertices %zu..%zu", nv0 + q0, nv0 + q0 + nb - 1);
            goto done;
        }
        for (size_t i = 0; i < nb; ++i) {
            int *ii = idx + i * nq;
            double *dd = d2 + i * nq;
            order_neighbours(ii, dd, nq);
            st = blend_neighbours(in, ii, dd, kq, nq, nv0 + q0 + i, inv2s2,
                                  out->col + 3 * (nv0 + q0 + i), err);
            if (st != RELIEF_OK)
                goto done;
        }
    }

done:
    if (index)
        flann_free_index_double(index, &fp);
    free(d2);
    free(idx);
    return st;
}

static relief_status copy_mesh(const relief_mesh *in, relief_mesh **out,
                               relief_error *err)
{
    relief_mesh *m = NULL;
    relief_status st = relief_mesh_create(in->nv, in->nt, in->attrs, &m, err);
    if (st != RELIEF_OK)
        return st;
    memcpy(m->pos, in->pos, in->nv * 3 * sizeof *m->pos);
    if (in->nt)
        memcpy(m->tri, in->tri, in->nt * 3 * sizeof *m->tri);
    if (m->col)
        memcpy(m->col, in->col, in->nv * 3 * sizeof *m->col);
    if (m->nrm)
        memcpy(m->nrm, in->nrm, in->nv * 3 * sizeof *m->nrm);
    if (m->label)
        memcpy(m->label, in->label, in->nv);
    *out = m;
    return RELIEF_OK;
}

/* relief_oversample's passes and parameters prm checked (RELIEF_E_RANGE),
 * then that in has triangles (RELIEF_E_MESH), in that order. */
static relief_status oversample_check(const relief_mesh *in, int passes,
                                      const relief_oversample_params *prm, relief_error *err)
{
    if (passes < 0 || passes > RELIEF_OVERSAMPLE_PASSES_MAX)
        return relief_fail(err, RELIEF_E_RANGE,
                           "oversampling passes = %d is out of range [0, %d]",
                           passes, RELIEF_OVERSAMPLE_PASSES_MAX);
    if (prm->scheme != RELIEF_OVERSAMPLE_MIDPOINT && prm->scheme != RELIEF_OVERSAMPLE_BUTTERFLY)
        return relief_fail(err, RELIEF_E_RANGE,
                           "oversampling scheme %d is not one of midpoint (%d), "
                           "butterfly (%d)", prm->scheme, RELIEF_OVERSAMPLE_MIDPOINT,
                           RELIEF_OVERSAMPLE_BUTTERFLY);
    if (prm->k < 1 || prm->k > RELIEF_OVERSAMPLE_K_MAX)
        return relief_fail(err, RELIEF_E_RANGE,
                           "oversampling colour neighbours k = %d is out of "
                           "range [1, %d]", prm->k, RELIEF_OVERSAMPLE_K_MAX);
    if (!(isfinite(prm->sigma) && prm->sigma >= 0.0))
        return relief_fail(err, RELIEF_E_RANGE,
                           "oversampling colour sigma = %g is out of range: "
                           "0 (half the median edge length) or a finite "
                           "length > 0", prm->sigma);
    if (in->nt == 0)
        return relief_fail(err, RELIEF_E_MESH,
                           "cannot oversample a point cloud (%zu vertices, no "
                           "triangle): subdivision needs a triangulated "
                           "surface", in->nv);
    return RELIEF_OK;
}

relief_status relief_oversample(const relief_mesh *in, int passes,
                                const relief_oversample_params *p,
                                relief_mesh **out, relief_error *err)
{
    const relief_oversample_params prm =
        p ? *p : relief_oversample_params_default();
    relief_mesh *cur = NULL, *next = NULL; /* owned meshes of the passes */
    double *len = NULL;
    size_t ne = 0;
    double sigma = prm.sigma;
    relief_status st;

    if (!in || !out)
        return relief_fail(err, RELIEF_E_USAGE,
                           "relief_oversample: %s is NULL", in ? "out" : "in");
    st = oversample_check(in, passes, &prm, err);
    if (st != RELIEF_OK)
        return st;
    st = relief_mesh_validate(in, err);
    if (st != RELIEF_OK)
        return st;
    if (passes == 0)
        return copy_mesh(in, out, err);

    for (int pass = 0; pass < passes; ++pass) {
        const int last = pass == passes - 1;
        const unsigned attrs = (in->attrs & ~(unsigned)RELIEF_MESH_COLOURS) |
                               (last ? in->attrs & RELIEF_MESH_COLOURS : 0u);
        const int want_len = pass == 0 && in->col && sigma == 0.0;
        st = split_once(cur ? cur : in, attrs, prm.scheme, &next, want_len ? &len : NULL,
                        &ne, err);
        relief_mesh_destroy(cur);
        cur = next;
        next = NULL;
        if (st != RELIEF_OK)
            goto fail;
    }

    if (in->col) {
        if (sigma == 0.0) {
            sigma = 0.5 * median(len, ne);
            if (!(sigma > 0.0)) {
                st = relief_fail(err, RELIEF_E_MESH,
                                 "cannot derive the colour sigma: the median "
                                 "edge length of the %zu edges is 0; give "
                                 "sigma > 0", ne);
                goto fail;
            }
        }
        st = transfer_colour(in, cur, prm.k, sigma, err);
        if (st != RELIEF_OK)
            goto fail;
    }
    free(len);
    *out = cur;
    return RELIEF_OK;

fail:
    free(len);
    relief_mesh_destroy(cur);
    return st;
}
