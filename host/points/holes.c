/* A bare point set's rims (points/holes.h): the points whose neighbours
 * leave a one-sided gap, joined through the k-NN graph, judged by the hole
 * model of mesh/holes.h. */
#include "points/holes.h"

#include <math.h>
#include <stdlib.h>

#include "base/error.h"
#include "base/linalg.h"
#include "base/union_find.h"
#include "base/vec3.h"

#define RELIEF_TWO_PI 6.283185307179586

static int dbl_cmp(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

relief_status relief_holes_points(const double *pos, const double *nrm,
                                  const relief_knn_graph *g, double gap,
                                  const relief_hole_rule *rule, uint32_t *rim,
                                  relief_hole_info *info, relief_error *err)
{
    size_t n = g->n, k = (size_t)g->k;
    uint32_t *parent = malloc(n * sizeof *parent + 1), *piece = malloc(n * sizeof *piece + 1);
    uint8_t *mark = calloc(n + 1, 1);
    double ang[64];
    relief_status st;

    if (!parent || !mark || !piece) {
        free(parent), free(mark), free(piece);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the rim test of %zu points", n);
    }
    if (!(gap > 0.0 && gap < RELIEF_TWO_PI)) {
        free(parent), free(mark), free(piece);
        return relief_fail(err, RELIEF_E_RANGE, "rim angle %g out of range (0, 2 pi)", gap);
    }
    for (size_t i = 0; i < n; ++i) {
        double u[3], v[3], widest;
        size_t m = 0;
        parent[i] = piece[i] = (uint32_t)i;
        relief_perp_basis(nrm + 3 * i, u, v);
        for (size_t r = 0; r < k; ++r) {
            double d[3];
            sub3(pos + 3 * (size_t)g->nbr[i * k + r], pos + 3 * i, d);
            if (dot3(d, u) != 0.0 || dot3(d, v) != 0.0)
                ang[m++] = atan2(dot3(d, v), dot3(d, u));
        }
        if (m < 2) {
            mark[i] = 1;
            continue;
        }
        qsort(ang, m, sizeof *ang, dbl_cmp);
        widest = ang[0] + RELIEF_TWO_PI - ang[m - 1];
        for (size_t r = 1; r < m; ++r)
            widest = fmax(widest, ang[r] - ang[r - 1]);
        mark[i] = widest > gap;
    }
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

