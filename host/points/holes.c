/* A bare point set's rims (points/holes.h): the points whose neighbours
 * leave a one-sided gap, joined through the k-NN graph, judged by the hole
 * model of mesh/holes.h. */
#include "points/holes.h"

#include <math.h>
#include <stdlib.h>

#include "base/error.h"
#include "base/linalg.h"
#include "base/parallel.h"
#include "base/union_find.h"
#include "base/vec3.h"

#define RELIEF_TWO_PI 6.283185307179586

/* a[0..m) ascending: insertion sort, for the few dozen angles of a point
 * (qsort's calls through a comparison were a third of this stage). */
static void sort_small(double *a, size_t m)
{
    for (size_t i = 1; i < m; ++i) {
        double v = a[i];
        size_t j = i;
        for (; j > 0 && a[j - 1] > v; --j)
            a[j] = a[j - 1];
        a[j] = v;
    }
}

typedef struct rim_test {
    const double *pos, *nrm;
    const relief_knn_graph *g;
    double gap;
    uint8_t *mark;
} rim_test;

/* mark[i] for points [lo, hi): is the widest angle between its neighbours,
 * seen along its normal, over the gap? (Fewer than two neighbours off
 * the normal: yes.) For relief_parallel_ranges: each point alone. */
static int rim_share(void *ctx, size_t lo, size_t hi)
{
    const rim_test *t = ctx;
    size_t k = (size_t)t->g->k;
    double ang[64];
    for (size_t i = lo; i < hi; ++i) {
        double u[3], v[3], widest;
        size_t m = 0;
        relief_perp_basis(t->nrm + 3 * i, u, v);
        for (size_t r = 0; r < k; ++r) {
            double d[3];
            sub3(t->pos + 3 * (size_t)t->g->nbr[i * k + r], t->pos + 3 * i, d);
            if (dot3(d, u) != 0.0 || dot3(d, v) != 0.0)
                ang[m++] = atan2(dot3(d, v), dot3(d, u));
        }
        if (m < 2) {
            t->mark[i] = 1;
            continue;
        }
        sort_small(ang, m);
        widest = ang[0] + RELIEF_TWO_PI - ang[m - 1];
        for (size_t r = 1; r < m; ++r)
            widest = fmax(widest, ang[r] - ang[r - 1]);
        t->mark[i] = widest > t->gap;
    }
    return 0;
}

relief_status relief_holes_points(const double *pos, const double *nrm,
                                  const relief_knn_graph *g, double gap,
                                  const relief_hole_rule *rule, int threads, uint32_t *rim,
                                  relief_hole_info *info, relief_error *err)
{
    size_t n = g->n, k = (size_t)g->k;
    uint32_t *parent = malloc(n * sizeof *parent + 1), *piece = malloc(n * sizeof *piece + 1);
    uint8_t *mark = calloc(n + 1, 1);
    rim_test t = {pos, nrm, g, gap, mark};
    relief_status st;

    if (!parent || !mark || !piece) {
        free(parent), free(mark), free(piece);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the rim test of %zu points", n);
    }
    if (!(gap > 0.0 && gap < RELIEF_TWO_PI)) {
        free(parent), free(mark), free(piece);
        return relief_fail(err, RELIEF_E_RANGE, "rim angle %g out of range (0, 2 pi)", gap);
    }
    relief_parallel_ranges(n, threads, rim_share, &t);
    for (size_t i = 0; i < n; ++i)
        parent[i] = piece[i] = (uint32_t)i;
    for (size_t i = 0; i < n; ++i)
        for (size_t r = 0; r < k; ++r) {
            relief_uf_join(piece, (uint32_t)i, g->nbr[i * k + r]);
            if (mark[i] && mark[g->nbr[i * k + r]])
                relief_uf_join(parent, (uint32_t)i, g->nbr[i * k + r]);
        }
    st = relief_holes_label(pos, n, mark, parent, piece, (double)k, rule, rim, info, err);
    free(parent), free(mark), free(piece);
    return st;
}
