/* hole_patch_crossings (mesh/hole_fill_internal.h): a patch against
 * itself and the mesh's triangles near it, by mesh/mesh_check.h's exact
 * test. The mesh's triangles whose boxes meet the patch's box are copied
 * out with their own three vertices each: the test takes two vertices at
 * one position, exactly, for one, so the copies still share the rim's
 * vertices with the patch (x holds the rim's positions exactly). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "mesh/hole_fill_internal.h"
#include "mesh/mesh_check.h"

static int box_meets(const double *lo, const double *hi, const double *a, const double *b,
                     const double *c)
{
    for (int e = 0; e < 3; ++e)
        if (fmax(a[e], fmax(b[e], c[e])) < lo[e] || fmin(a[e], fmin(b[e], c[e])) > hi[e])
            return 0;
    return 1;
}

relief_status hole_patch_crossings(const hole_patch *p, const double *pos, const uint32_t *tri,
                                   size_t nt, size_t *count, double where[3], relief_error *err)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    size_t near = 0, nv, nall;
    double *x = NULL;
    uint32_t *t = NULL;
    uint8_t *focus = NULL, *hit = NULL;
    relief_status st;
    *count = 0, where[0] = where[1] = where[2] = 0.0;
    for (size_t v = 0; v < p->nx; ++v)
        for (int e = 0; e < 3; ++e)
            lo[e] = fmin(lo[e], p->x[3 * v + e]), hi[e] = fmax(hi[e], p->x[3 * v + e]);
    for (size_t f = 0; f < nt; ++f)
        near += (size_t)box_meets(lo, hi, pos + 3 * (size_t)tri[3 * f],
                                  pos + 3 * (size_t)tri[3 * f + 1], pos + 3 * (size_t)tri[3 * f + 2]);
    nv = p->nx + 3 * near, nall = p->nt + near;
    x = malloc(nv * 3 * sizeof *x), t = malloc(nall * 3 * sizeof *t);
    focus = calloc(nall, 1), hit = malloc(nall);
    if (!x || !t || !focus || !hit) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the crossing check of a patch "
                         "of %zu triangles", p->nt);
        goto done;
    }
    memcpy(x, p->x, p->nx * 3 * sizeof *x);
    memcpy(t, p->t, p->nt * 3 * sizeof *t);
    memset(focus, 1, p->nt);
    for (size_t f = 0, k = p->nt; f < nt; ++f) {
        const double *c[3] = {pos + 3 * (size_t)tri[3 * f], pos + 3 * (size_t)tri[3 * f + 1],
                              pos + 3 * (size_t)tri[3 * f + 2]};
        if (!box_meets(lo, hi, c[0], c[1], c[2]))
            continue;
        for (int i = 0; i < 3; ++i) {
            size_t v = p->nx + 3 * (k - p->nt) + (size_t)i;
            memcpy(x + 3 * v, c[i], 3 * sizeof *x);
            t[3 * k + i] = (uint32_t)v;
        }
        ++k;
    }
    st = relief_self_intersections(x, nv, t, nall, focus, hit, count, err);
    for (size_t f = 0; st == RELIEF_OK && f < p->nt; ++f)
        for (int i = 0; hit[f] && i < 3; ++i)
            for (int e = 0; e < 3; ++e)
                where[e] += x[3 * (size_t)t[3 * f + i] + e] / (3.0 * (double)*count);
done:
    free(x), free(t), free(focus), free(hit);
    return st;
}
