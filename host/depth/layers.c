/* Depth layers of a frame's holes (layers.h). */
#include "depth/layers.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/linalg.h"
#include "base/union_find.h"

#define MIN_PIECE 3     /* rim pixels a piece needs to bound a layer */
#define MAX_PIECES 64   /* the largest pieces of a rim that are ranked */
#define COLOUR_UNIT 12.0 /* an RGB difference that doubles a step's cost */

relief_layer_params relief_layer_params_default(void)
{
    relief_layer_params p;
    memset(&p, 0, sizeof p);
    p.far_sign = 1;
    p.step = 8.0;
    p.near_weight = 8.0;
    return p;
}

void relief_layers_free(relief_layers *l)
{
    if (l) {
        free(l->rank);
        l->rank = NULL;
    }
}

/* ------------------------------------------------------------- the noise */

/* The frame's noise unit (layers.h): the median non-zero |second
 * difference| over known triples along rows and columns, over z^2 for
 * depths. 0 when none is non-zero (a synthetic, noiseless frame). */
static relief_status frame_noise(const float *z, const uint8_t *missing, int W, int H,
                                 int far_sign, double *noise, relief_error *err)
{
    size_t n = 0;
    double *d = malloc(2 * (size_t)W * H * sizeof *d);
    if (!d)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the frame's noise estimate");
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            size_t i = (size_t)y * W + x;
            double scale = far_sign > 0 ? (double)z[i] * z[i] : 1.0;
            if (missing[i] || !(scale > 0.0))
                continue;
            for (int dir = 0; dir < 2; ++dir) {
                size_t s = dir ? (size_t)W : 1;
                int ok = dir ? y > 0 && y + 1 < H : x > 0 && x + 1 < W;
                double d2;
                if (!ok || missing[i - s] || missing[i + s])
                    continue;
                d2 = fabs((double)z[i - s] - 2.0 * z[i] + z[i + s]);
                if (d2 > 0.0 && isfinite(d2))
                    d[n++] = d2 / scale;
            }
        }
    *noise = n ? relief_select_median(d, n) : 0.0;
    free(d);
    return RELIEF_OK;
}

/* ------------------------------------------------------------ the pieces */

/* One hole's working state, reused from hole to hole: its pixels, its
 * rim, the rim's pieces and the paths through it. */
typedef struct lay_run {
    const float *z;
    const uint8_t *missing, *inside;
    int W, H;
    const relief_layer_params *p;
    double noise;
    uint32_t *stamp;    /* W x H: 1 + the last hole that listed the pixel */
    uint32_t *at;       /* W x H: its index in that hole's list or rim */
    uint32_t *hole, *rim, *parent, *piece; /* piece: the rim pixel's piece or UINT32_MAX */
    size_t nhole, nrim;
    float *dist[RELIEF_LAYERS_MAX]; /* per hole pixel */
    uint32_t *heap_i;
    float *heap_k;
    size_t heap_n;
    uint8_t *rank;      /* the output */
} lay_run;

/* The step between two depths: over step noise units at the nearer. */
static int is_step(const lay_run *L, float a, float b)
{
    double zn = L->p->far_sign > 0 ? fmin(a, b) : 1.0;
    double tau = L->p->step * L->noise * (L->p->far_sign > 0 ? zn * zn : 1.0);
    return fabs((double)a - b) > tau;
}

/* Is a in front of b (nearer)? */
static int nearer(const lay_run *L, float a, float b)
{
    return L->p->far_sign > 0 ? a < b : a > b;
}

/* The hole from pixel s (4-connected inside pixels) and its rim (their
 * captured 4-neighbours), tagged with stamp t. */
static void collect(lay_run *L, size_t s, uint32_t t)
{
    static const int dx[4] = {-1, 1, 0, 0}, dy[4] = {0, 0, -1, 1};
    L->nhole = L->nrim = 0;
    L->stamp[s] = t;
    L->at[s] = 0;
    L->hole[L->nhole++] = (uint32_t)s;
    for (size_t k = 0; k < L->nhole; ++k) {
        int x = (int)(L->hole[k] % (uint32_t)L->W), y = (int)(L->hole[k] / (uint32_t)L->W);
        for (int j = 0; j < 4; ++j) {
            int u = x + dx[j], v = y + dy[j];
            size_t q;
            if (u < 0 || u >= L->W || v < 0 || v >= L->H)
                continue;
            q = (size_t)v * L->W + u;
            if (L->stamp[q] == t || (L->missing[q] && !L->inside[q]))
                continue;
            L->stamp[q] = t;
            if (L->inside[q]) {
                L->at[q] = (uint32_t)L->nhole;
                L->hole[L->nhole++] = (uint32_t)q;
            } else {
                L->at[q] = (uint32_t)L->nrim;
                L->rim[L->nrim++] = (uint32_t)q;
            }
        }
    }
}

/* Is pixel q on this hole's rim? */
static int on_rim(const lay_run *L, size_t q, uint32_t t)
{
    return L->stamp[q] == t && !L->missing[q];
}

/* The rim cut into pieces: 8-neighbours on the rim joined unless a step
 * apart. Leaves each rim pixel's root in parent. */
static void join_pieces(lay_run *L, uint32_t t)
{
    for (size_t k = 0; k < L->nrim; ++k)
        L->parent[k] = (uint32_t)k;
    for (size_t k = 0; k < L->nrim; ++k) {
        int x = (int)(L->rim[k] % (uint32_t)L->W), y = (int)(L->rim[k] / (uint32_t)L->W);
        for (int v = y - 1; v <= y + 1; ++v)
            for (int u = x - 1; u <= x + 1; ++u) {
                size_t q;
                if (u < 0 || u >= L->W || v < 0 || v >= L->H || (u == x && v == y))
                    continue;
                q = (size_t)v * L->W + u;
                if (on_rim(L, q, t) && !is_step(L, L->z[L->rim[k]], L->z[q]))
                    relief_uf_join(L->parent, (uint32_t)k, L->at[q]);
            }
    }
}

/* Piece statistics: up to MAX_PIECES of at least MIN_PIECE pixels, the
 * largest first (ties: the first on the rim); each rim pixel's piece
 * number in L->piece, UINT32_MAX for the rest. Returns the count. */
typedef struct piece_info {
    uint32_t root, count;
    double sum;
} piece_info;

static int cmp_piece(const void *a, const void *b)
{
    const piece_info *x = a, *y = b;
    if (x->count != y->count)
        return x->count > y->count ? -1 : 1;
    return (x->root > y->root) - (x->root < y->root);
}

static int number_pieces(lay_run *L, piece_info *info, double *mean)
{
    size_t roots = 0;
    int n;
    /* the roots' pixel counts, counted at the roots */
    for (size_t k = 0; k < L->nrim; ++k)
        L->piece[k] = 0;
    for (size_t k = 0; k < L->nrim; ++k)
        ++L->piece[relief_uf_find(L->parent, (uint32_t)k)];
    for (size_t k = 0; k < L->nrim; ++k)
        if (L->parent[k] == k && L->piece[k] >= MIN_PIECE)
            ++roots;
    piece_info *all = malloc((roots + 1) * sizeof *all);
    if (!all)
        return -1;
    roots = 0;
    for (size_t k = 0; k < L->nrim; ++k)
        if (L->parent[k] == k && L->piece[k] >= MIN_PIECE)
            all[roots++] = (piece_info){(uint32_t)k, L->piece[k], 0.0};
    qsort(all, roots, sizeof *all, cmp_piece);
    n = roots < MAX_PIECES ? (int)roots : MAX_PIECES;
    memcpy(info, all, (size_t)n * sizeof *info);
    free(all);
    /* the root's number, through a scratch mark on the roots */
    for (size_t k = 0; k < L->nrim; ++k)
        if (L->parent[k] == k)
            L->piece[k] = UINT32_MAX;
    for (int i = 0; i < n; ++i)
        L->piece[info[i].root] = (uint32_t)i;
    for (size_t k = 0; k < L->nrim; ++k)
        if (L->parent[k] != k)
            L->piece[k] = L->piece[relief_uf_find(L->parent, (uint32_t)k)];
    for (int i = 0; i < n; ++i)
        mean[i] = 0.0;
    for (size_t k = 0; k < L->nrim; ++k)
        if (L->piece[k] != UINT32_MAX)
            mean[L->piece[k]] += L->z[L->rim[k]];
    for (int i = 0; i < n; ++i)
        mean[i] /= info[i].count;
    return n;
}

/* ------------------------------------------------------------- the ranks */

/* front[a * n + b]: piece a meets piece b on the rim across a step, a
 * nearer. */
static void find_fronts(const lay_run *L, uint32_t t, int n, uint8_t *front)
{
    memset(front, 0, (size_t)n * n);
    for (size_t k = 0; k < L->nrim; ++k) {
        size_t p = L->rim[k];
        int x = (int)(p % (uint32_t)L->W), y = (int)(p / (uint32_t)L->W);
        uint32_t a = L->piece[k];
        if (a == UINT32_MAX)
            continue;
        for (int v = y - 1; v <= y + 1; ++v)
            for (int u = x - 1; u <= x + 1; ++u) {
                size_t q;
                uint32_t b;
                if (u < 0 || u >= L->W || v < 0 || v >= L->H)
                    continue;
                q = (size_t)v * L->W + u;
                if (!on_rim(L, q, t) || (b = L->piece[L->at[q]]) == UINT32_MAX || b == a)
                    continue;
                if (is_step(L, L->z[p], L->z[q]) && nearer(L, L->z[p], L->z[q]))
                    front[(size_t)a * n + b] = 1;
            }
    }
}

/* Each piece's rank (layers.h) into rank[n]; returns the highest. */
static int rank_pieces(const lay_run *L, int n, const uint8_t *front, const double *mean,
                       int *rank)
{
    int top = 0, changed = 1;
    for (int a = 0; a < n; ++a)
        rank[a] = 0;
    for (int pass = 0; pass < n && changed; ++pass) {
        changed = 0;
        for (int a = 0; a < n; ++a)
            for (int b = 0; b < n; ++b)
                if (front[(size_t)a * n + b] && rank[a] < rank[b] + 1 &&
                    rank[b] + 1 < RELIEF_LAYERS_MAX) {
                    rank[a] = rank[b] + 1;
                    changed = 1;
                }
    }
    /* Islands: in front when nearer than every piece behind by a step. */
    for (int a = 0; a < n; ++a) {
        int alone = 1, any = 0, ahead = 1;
        for (int b = 0; b < n && alone; ++b)
            alone = !front[(size_t)a * n + b] && !front[(size_t)b * n + a];
        if (!alone)
            continue;
        for (int b = 0; b < n; ++b)
            if (b != a && rank[b] == 0) {
                any = 1;
                ahead = ahead && nearer(L, (float)mean[a], (float)mean[b]) &&
                        is_step(L, (float)mean[a], (float)mean[b]);
            }
        if (any && ahead)
            rank[a] = 1;
    }
    for (int a = 0; a < n; ++a)
        top = rank[a] > top ? rank[a] : top;
    return top;
}

/* ------------------------------------------------------------- the paths */

static void heap_push(lay_run *L, float key, uint32_t i)
{
    size_t c = L->heap_n++;
    while (c > 0) {
        size_t up = (c - 1) / 2;
        if (L->heap_k[up] <= key)
            break;
        L->heap_k[c] = L->heap_k[up], L->heap_i[c] = L->heap_i[up];
        c = up;
    }
    L->heap_k[c] = key, L->heap_i[c] = i;
}

static uint32_t heap_pop(lay_run *L, float *key)
{
    uint32_t top = L->heap_i[0];
    float k = L->heap_k[--L->heap_n];
    uint32_t i = L->heap_i[L->heap_n];
    size_t c = 0;
    *key = L->heap_k[0];
    for (;;) {
        size_t l = 2 * c + 1, m = l;
        if (l >= L->heap_n)
            break;
        if (l + 1 < L->heap_n && L->heap_k[l + 1] < L->heap_k[l])
            m = l + 1;
        if (L->heap_k[m] >= k)
            break;
        L->heap_k[c] = L->heap_k[m], L->heap_i[c] = L->heap_i[m];
        c = m;
    }
    L->heap_k[c] = k, L->heap_i[c] = i;
    return top;
}

/* A step's cost from pixel a to its neighbour b: 1, and more where the
 * guide's colour changes. */
static float step_cost(const lay_run *L, size_t a, size_t b)
{
    const uint8_t *g = L->p->rgb;
    double d2 = 0.0;
    if (!g)
        return 1.0f;
    for (int c = 0; c < 3; ++c) {
        double d = (double)g[3 * a + c] - g[3 * b + c];
        d2 += d * d;
    }
    return (float)(1.0 + d2 / (COLOUR_UNIT * COLOUR_UNIT));
}

/* Relax pixel p's 4-neighbours in this hole (stamp t) from `base`: a
 * neighbour's path through p costs base plus the step (Dijkstra's relax,
 * lazy deletion: a pixel is pushed at most once per neighbour, so 4
 * entries a pixel). */
static void relax(lay_run *L, uint32_t t, size_t p, float base, float *d)
{
    static const int dx[4] = {-1, 1, 0, 0}, dy[4] = {0, 0, -1, 1};
    int x = (int)(p % (uint32_t)L->W), y = (int)(p / (uint32_t)L->W);
    for (int j = 0; j < 4; ++j) {
        int u = x + dx[j], v = y + dy[j];
        size_t q;
        float c;
        if (u < 0 || u >= L->W || v < 0 || v >= L->H)
            continue;
        q = (size_t)v * L->W + u;
        if (L->stamp[q] != t || !L->inside[q])
            continue;
        c = base + step_cost(L, p, q);
        if (c < d[L->at[q]]) {
            d[L->at[q]] = c;
            heap_push(L, c, L->at[q]);
        }
    }
}

/* dist[r][k]: hole pixel k's shortest path through the hole from a rim
 * pixel of rank r (INFINITY where none), by Dijkstra from the rank's rim. */
static void paths(lay_run *L, uint32_t t, const int *rank, int r)
{
    float *d = L->dist[r];
    for (size_t k = 0; k < L->nhole; ++k)
        d[k] = INFINITY;
    L->heap_n = 0;
    for (size_t k = 0; k < L->nrim; ++k)
        if (L->piece[k] != UINT32_MAX && rank[L->piece[k]] == r)
            relax(L, t, L->rim[k], 0.0f, d);
    while (L->heap_n > 0) {
        float key;
        uint32_t k = heap_pop(L, &key);
        if (key <= d[k]) /* else a stale entry */
            relax(L, t, L->hole[k], key, d);
    }
}

/* Hole pixel k's same-rank region (4-connected, labelled `label` in
 * L->parent by hole index, L->heap_i its queue): whether it touches a rim
 * pixel of its rank, and in near[r] how often it touches rank r. Returns
 * its size. */
static size_t region(lay_run *L, uint32_t t, size_t k, uint32_t label, int *anchored,
                     size_t *near)
{
    static const int dx[4] = {-1, 1, 0, 0}, dy[4] = {0, 0, -1, 1};
    uint8_t r = L->rank[L->hole[k]];
    size_t head = 0, tail = 0;
    *anchored = 0;
    L->parent[k] = label;
    L->heap_i[tail++] = (uint32_t)k;
    while (head < tail) {
        size_t p = L->hole[L->heap_i[head++]];
        int x = (int)(p % (uint32_t)L->W), y = (int)(p / (uint32_t)L->W);
        for (int j = 0; j < 4; ++j) {
            int u = x + dx[j], v = y + dy[j];
            size_t q;
            uint8_t rq;
            if (u < 0 || u >= L->W || v < 0 || v >= L->H)
                continue;
            q = (size_t)v * L->W + u;
            if (L->stamp[q] != t || (L->missing[q] && !L->inside[q]))
                continue;
            rq = L->rank[q];
            if (rq < RELIEF_LAYERS_MAX && rq != r)
                ++near[rq];
            if (!L->inside[q]) {
                *anchored |= rq == r;
            } else if (rq == r && L->parent[L->at[q]] != label) {
                L->parent[L->at[q]] = label;
                L->heap_i[tail++] = L->at[q];
            }
        }
    }
    return tail;
}

/* A layer's pixels cut off from its rim (their path to it crossed another
 * layer) would be filled with no boundary: each such region joins the
 * layer it borders most, until every region touches its own rim. */
static void anchor(lay_run *L, uint32_t t)
{
    for (int round = 0, moved = 1; moved && round < 2 * RELIEF_LAYERS_MAX; ++round) {
        moved = 0;
        for (size_t k = 0; k < L->nhole; ++k)
            L->parent[k] = UINT32_MAX;
        for (size_t k = 0; k < L->nhole; ++k) {
            size_t near[RELIEF_LAYERS_MAX] = {0}, m;
            int anchored, to = -1;
            if (L->parent[k] != UINT32_MAX)
                continue;
            m = region(L, t, k, (uint32_t)k, &anchored, near);
            for (int r = 0; r < RELIEF_LAYERS_MAX; ++r)
                if (near[r] && (to < 0 || near[r] > near[to]))
                    to = r;
            if (anchored || to < 0)
                continue;
            for (size_t i = 0; i < m; ++i)
                L->rank[L->hole[L->heap_i[i]]] = (uint8_t)to;
            moved = 1;
        }
    }
}

/* Each hole pixel's rank: the nearest rim by path, a front layer's paths
 * weighted, every region anchored to its own rim; and the rim's pieces'
 * ranks. Returns the front pixels. */
static size_t assign(lay_run *L, uint32_t t, const int *rank, int top)
{
    size_t front = 0;
    for (int r = 0; r <= top; ++r)
        paths(L, t, rank, r);
    for (size_t k = 0; k < L->nhole; ++k) {
        int best = 0;
        double bd = L->dist[0][k];
        for (int r = 1; r <= top; ++r) {
            double dr = L->dist[r][k] * L->p->near_weight;
            if (dr < bd)
                best = r, bd = dr;
        }
        L->rank[L->hole[k]] = (uint8_t)best;
    }
    for (size_t k = 0; k < L->nrim; ++k)
        L->rank[L->rim[k]] = L->piece[k] == UINT32_MAX ? RELIEF_LAYER_IGNORED
                                                        : (uint8_t)rank[L->piece[k]];
    anchor(L, t);
    for (size_t k = 0; k < L->nhole; ++k)
        front += L->rank[L->hole[k]] > 0;
    return front;
}

/* ------------------------------------------------------------- the holes */

/* One hole, from its pixel s: its rim's pieces ranked and, when stepped,
 * its pixels given ranks. Returns the highest rank (0: not stepped), -1
 * out of memory. */
static int layer_hole(lay_run *L, size_t s, uint32_t t, size_t *front)
{
    piece_info info[MAX_PIECES];
    double mean[MAX_PIECES];
    int rank[MAX_PIECES], n, top;
    uint8_t *fronts;
    collect(L, s, t);
    if (L->nrim < 2 * MIN_PIECE)
        return 0;
    join_pieces(L, t);
    n = number_pieces(L, info, mean);
    if (n < 2)
        return n < 0 ? -1 : 0;
    fronts = malloc((size_t)n * n);
    if (!fronts)
        return -1;
    find_fronts(L, t, n, fronts);
    top = rank_pieces(L, n, fronts, mean, rank);
    free(fronts);
    if (top > 0)
        *front += assign(L, t, rank, top);
    return top;
}

static void run_free(lay_run *L)
{
    free(L->stamp);
    free(L->at);
    free(L->hole);
    free(L->rim);
    free(L->parent);
    free(L->piece);
    for (int r = 0; r < RELIEF_LAYERS_MAX; ++r)
        free(L->dist[r]);
    free(L->heap_i);
    free(L->heap_k);
}

static int run_alloc(lay_run *L, size_t n)
{
    int ok;
    L->stamp = calloc(n, sizeof *L->stamp);
    L->at = malloc(n * sizeof *L->at);
    L->hole = malloc(n * sizeof *L->hole);
    L->rim = malloc(n * sizeof *L->rim);
    L->parent = malloc(n * sizeof *L->parent);
    L->piece = malloc(n * sizeof *L->piece);
    L->heap_i = malloc(4 * n * sizeof *L->heap_i);
    L->heap_k = malloc(4 * n * sizeof *L->heap_k);
    ok = L->stamp && L->at && L->hole && L->rim && L->parent && L->piece && L->heap_i &&
         L->heap_k;
    for (int r = 0; r < RELIEF_LAYERS_MAX; ++r)
        ok = ok && (L->dist[r] = malloc(n * sizeof *L->dist[r])) != NULL;
    return ok;
}

relief_status relief_layers_find(const float *z, const uint8_t *missing, const uint8_t *inside,
                                 int width, int height, const relief_layer_params *p,
                                 relief_layers *out, relief_error *err)
{
    size_t n = (size_t)width * height;
    lay_run L;
    uint32_t t = 0;
    relief_status st;
    memset(out, 0, sizeof *out);
    memset(&L, 0, sizeof L);
    out->ranks = 1;
    L.z = z, L.missing = missing, L.inside = inside, L.W = width, L.H = height, L.p = p;
    st = frame_noise(z, missing, width, height, p->far_sign, &L.noise, err);
    if (st != RELIEF_OK)
        return st;
    out->noise = L.noise;
    out->rank = malloc(n);
    if (!out->rank || !run_alloc(&L, n)) {
        run_free(&L);
        relief_layers_free(out);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the depth layers of a "
                           "%d x %d frame", width, height);
    }
    memset(out->rank, RELIEF_LAYER_NONE, n);
    L.rank = out->rank;
    for (size_t i = 0; i < n; ++i) {
        int top;
        if (!inside[i] || L.stamp[i] != 0)
            continue;
        top = layer_hole(&L, i, ++t, &out->front_pixels);
        if (top < 0) {
            st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a hole's depth layers");
            break;
        }
        out->stepped_holes += top > 0;
        if (top + 1 > out->ranks)
            out->ranks = top + 1;
    }
    run_free(&L);
    if (st != RELIEF_OK)
        relief_layers_free(out);
    return st;
}
