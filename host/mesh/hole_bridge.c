/* Two loops that bound one hole (mesh/hole_fill.h: a band cut all round a
 * tube): which loops face each other, and step 1 for them, the strip
 * between the two polygons. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "mesh/hole_fill.h"
#include "mesh/hole_fill_internal.h"

void hole_loop_facing(const double *pos, const uint32_t *opp, const uint32_t *loop, size_t n,
                      hole_loop_shape *f)
{
    double len_sum = 0.0, far = 0.0;
    memset(f, 0, sizeof *f);
    f->n = n;
    for (size_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k)
            f->centre[k] += pos[3 * (size_t)loop[i] + k] / (double)n;
    for (size_t i = 0; i < n; ++i) {
        const double *a = pos + 3 * (size_t)loop[i], *b = pos + 3 * (size_t)loop[(i + 1) % n];
        const double *o = pos + 3 * (size_t)opp[loop[(i + 1) % n]];
        double e[3], d[3], r[3], el, dl, along;
        sub3(b, a, e), sub3(a, f->centre, r);
        el = sqrt(dot3(e, e));
        far = fmax(far, dot3(r, r));
        for (int k = 0; k < 3; ++k)
            d[k] = 0.5 * (a[k] + b[k]) - o[k];
        along = el > 0.0 ? dot3(d, e) / (el * el) : 0.0;
        for (int k = 0; k < 3; ++k)
            d[k] -= along * e[k];
        dl = sqrt(dot3(d, d));
        for (int k = 0; dl > 0.0 && k < 3; ++k)
            f->dir[k] += el * d[k] / dl;
        len_sum += el;
    }
    for (int k = 0; len_sum > 0.0 && k < 3; ++k)
        f->dir[k] /= len_sum;
    f->across = 2.0 * sqrt(far);
}

int hole_loops_face(const hole_loop_shape *a, const hole_loop_shape *b)
{
    double c[3], cl, da = sqrt(dot3(a->dir, a->dir)), db = sqrt(dot3(b->dir, b->dir));
    double wide = fmax(a->across, b->across), narrow = fmin(a->across, b->across);
    sub3(b->centre, a->centre, c);
    cl = sqrt(dot3(c, c));
    return a->n >= RELIEF_TUBE_MIN_LOOP && b->n >= RELIEF_TUBE_MIN_LOOP &&
           da > RELIEF_TUBE_FACING && db > RELIEF_TUBE_FACING && narrow >= 0.5 * wide &&
           cl > 0.0 && cl <= 1.5 * wide && dot3(a->dir, c) > 0.8 * da * cl &&
           -dot3(b->dir, c) > 0.8 * db * cl && dot3(a->dir, b->dir) < -0.8 * da * db;
}

/* The strip: A (0..na-1) walked forward and B (na..na+nb-1) backward from
 * the B vertex nearest A's first, each step a triangle on the next rim
 * edge of one loop; the steps chosen by dynamic programming for the least
 * sum of the new edges' lengths (the shortest diagonals of Fuchs, Kedem
 * and Uselton's contour stitching). */
typedef struct strip {
    const double *x;
    size_t na, nb, b0;
} strip;

static uint32_t strip_b(const strip *s, size_t j)
{
    return (uint32_t)(s->na + (s->b0 + s->nb - j % s->nb) % s->nb);
}

static double diag(const strip *s, size_t i, size_t j)
{
    double d[3];
    sub3(s->x + 3 * (i % s->na), s->x + 3 * (size_t)strip_b(s, j), d);
    return sqrt(dot3(d, d));
}

int hole_bridge(hole_patch *p)
{
    strip s = {p->x, p->n_first, p->n_mesh - p->n_first, 0};
    size_t na = s.na, nb = s.nb, w = nb + 1, i, j, b0 = 0;
    double *cost, best = INFINITY;
    uint8_t *from;
    int ok;
    if ((na + 1) * w > RELIEF_TUBE_DP_MAX)
        return -1;
    cost = malloc((na + 1) * w * sizeof *cost), from = malloc((na + 1) * w);
    ok = cost && from && hole_patch_reserve(p, 0, na + nb);
    for (size_t k = 0; ok && k < nb; ++k) {
        double d;
        s.b0 = k, d = diag(&s, 0, 0);
        if (d < best)
            best = d, b0 = k;
    }
    if (!ok)
        goto done;
    s.b0 = b0;
    cost[0] = 0.0;
    for (i = 0; i <= na; ++i)
        for (j = 0; j <= nb; ++j) {
            double ca = i ? cost[(i - 1) * w + j] + diag(&s, i, j) : INFINITY;
            double cb = j ? cost[i * w + j - 1] + diag(&s, i, j) : INFINITY;
            if (!i && !j)
                continue;
            from[i * w + j] = cb < ca; /* 1: the step came along B */
            cost[i * w + j] = fmin(ca, cb);
        }
    for (i = na, j = nb; i || j;) { /* back from the end, pushing each step's triangle */
        uint32_t *t = p->t + 3 * p->nt++;
        if (from[i * w + j]) { /* B's rim edge strip_b(j) -> strip_b(j - 1), apex A's i */
            t[0] = strip_b(&s, j), t[1] = strip_b(&s, j - 1), t[2] = (uint32_t)(i % na);
            --j;
        } else { /* A's rim edge i - 1 -> i, apex B's j */
            t[0] = (uint32_t)(i - 1), t[1] = (uint32_t)(i % na), t[2] = strip_b(&s, j);
            --i;
        }
    }
done:
    free(cost), free(from);
    return ok;
}
