/* The point curvature flow and the signed detail (flow.h). */
#include "points/flow.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/parallel.h"
#include "base/vec3.h"

/* Covariance normal and sigma_n of point i over its k neighbours in q,
 * its sign following prev; the neighbourhood's centroid into m. */
static double local_normal(const double *q, const relief_knn_graph *g, size_t i,
                           const double *prev, double n_out[3], double m[3])
{
    double sig = relief_points_covariance(q, g, i, m, n_out);
    if (dot3(n_out, prev) < 0.0)
        for (int a = 0; a < 3; ++a)
            n_out[a] = -n_out[a];
    return sig;
}

/* One Euler step's shares: each point's next position and normal from the
 * current base alone, so the points can be shared out over threads. */
typedef struct flow_step {
    const double *pos, *base;
    const relief_knn_graph *g;
    double dt, max_disp;
    double *next, *base_nrm; /* a point's own row written only */
} flow_step;

/* Point i's next position (eq. 5's step, never past the neighbourhood's
 * own least-squares plane) and its new normal. */
static void step_point(const flow_step *f, size_t i)
{
    const relief_knn_graph *g = f->g;
    const size_t k = (size_t)g->k;
    double nn[3], m[3], dm[3], sig = local_normal(f->base, g, i, f->base_nrm + 3 * i, nn, m);
    double wsum = 0.0, dire = 0.0, h2 = 0.0, kbar, off, step;
    const double *p = f->base + 3 * i;
    double *next = f->next + 3 * i;
    for (size_t r = 0; r < k; ++r)
        h2 += g->d2[i * k + r];
    h2 = h2 / (double)k; /* G's sigma^2: the mean squared neighbour distance */
    for (size_t r = 0; r < k; ++r) {
        const double *u = f->base + 3 * (size_t)g->nbr[i * k + r];
        double d[3], w;
        sub3(p, u, d);
        w = h2 > 0.0 ? exp(-dot3(d, d) / (2.0 * h2)) : 1.0;
        wsum += w;
        dire += w * dot3(nn, d);
    }
    /* sigma_n falls with the square of a point's offset, so the time step
     * must be long to move small offsets at all, and the cap keeps that
     * step from overshooting large ones (explicit Euler's stability). */
    kbar = (wsum > 0.0 && dire / wsum >= 0.0) ? sig : -sig;
    step = f->dt * kbar;
    sub3(p, m, dm);
    off = fabs(dot3(dm, nn)); /* the distance to the plane through m */
    if (step > off)
        step = off;
    else if (step < -off)
        step = -off;
    for (int a = 0; a < 3; ++a)
        next[a] = p[a] - step * nn[a];
    if (f->max_disp > 0.0) { /* shape stays in the base */
        double d[3], len;
        sub3(next, f->pos + 3 * i, d);
        len = sqrt(dot3(d, d));
        if (len > f->max_disp)
            for (int a = 0; a < 3; ++a)
                next[a] = f->pos[3 * i + a] + d[a] * (f->max_disp / len);
    }
    memcpy(f->base_nrm + 3 * i, nn, sizeof nn);
}

static int step_share(void *ctx, size_t lo, size_t hi)
{
    for (size_t i = lo; i < hi; ++i)
        step_point(ctx, i);
    return 0;
}

/* The final base's normals, each following the last step's sign. */
static int normal_share(void *ctx, size_t lo, size_t hi)
{
    const flow_step *f = ctx;
    for (size_t i = lo; i < hi; ++i) {
        double nn[3], m[3];
        local_normal(f->base, f->g, i, f->base_nrm + 3 * i, nn, m);
        memcpy(f->base_nrm + 3 * i, nn, sizeof nn);
    }
    return 0;
}

relief_status relief_curvature_flow(const double *pos, const double *nrm,
                                    const relief_knn_graph *g, int steps, double dt,
                                    double max_disp, int threads, double *base,
                                    double *base_nrm, relief_error *err)
{
    const size_t n = g->n;
    flow_step f;

    if (steps < 0 || steps > 10000)
        return relief_fail(err, RELIEF_E_RANGE, "smoothing steps %d out of range 0..10000",
                           steps);
    if (!(dt > 0.0) || !isfinite(dt))
        return relief_fail(err, RELIEF_E_RANGE, "smoothing step length %g must be positive", dt);
    if (!(max_disp >= 0.0) || !isfinite(max_disp))
        return relief_fail(err, RELIEF_E_RANGE, "the base's largest offset %g must be 0 "
                           "(unbounded) or positive", max_disp);
    f = (flow_step){pos, base, g, dt, max_disp, malloc(n * 3 * sizeof *f.next), base_nrm};
    if (!f.next)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the smoothing of %zu points", n);
    memcpy(base, pos, n * 3 * sizeof *base);
    memcpy(base_nrm, nrm, n * 3 * sizeof *base_nrm);
    for (int s = 0; s < steps; ++s) {
        relief_parallel_ranges(n, threads, step_share, &f);
        memcpy(base, f.next, n * 3 * sizeof *base);
    }
    relief_parallel_ranges(n, threads, normal_share, &f);
    free(f.next);
    return RELIEF_OK;
}

double relief_detail_encode(const double *pos, const double *base, const double *base_nrm,
                            size_t n, float *c)
{
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) {
        double d[3], len, e = 0.0;
        sub3(pos + 3 * i, base + 3 * i, d);
        len = sqrt(dot3(d, d));
        c[i] = (float)(dot3(d, base_nrm + 3 * i) >= 0.0 ? len : -len);
        for (int a = 0; a < 3; ++a) {
            double r = base[3 * i + a] + (double)c[i] * base_nrm[3 * i + a] - pos[3 * i + a];
            e += r * r;
        }
        sum += e;
    }
    return n ? sqrt(sum / (double)n) : 0.0;
}
