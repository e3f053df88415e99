/* Planar, periodic and spherical Delaunay triangulations on libqhull_r.
 * What each function computes, its shapes and units are in delaunay.h. */
#include "smooth/delaunay.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <libqhull_r/libqhull_r.h>

#include "base/error.h"
#include "base/vec3.h"

/* Coordinates spread less than this fraction of the input's extent off a
 * line (plane for the sphere) count as collinear (coplanar): qhull cannot
 * build an initial simplex from them. */
#define FLAT_REL 1e-12
/* Periodic points closer than this fraction of the band's size (period plus
 * height) in u and in v are taken as one: qhull could keep either of two
 * such points, and must keep the same one in both copies at the seam. */
#define DUP_REL 1e-11
/* First periodic margin, in mean point spacings; it doubles from there. */
#define MARGIN_SPACINGS 4.0
/* Points this close (relative to the radius) to a circumcircle count as on
 * it, so the seam check errs towards a wider margin. */
#define CIRCLE_REL 1e-9
/* Radians by which the triangles around a point may fall short of closing
 * around it (rounding) before the periodic margin is called too narrow. */
#define ANGLE_TOL 1e-9


/* ------------------------------------------------------------ qhull runs */

/* One qhull computation and the memory stream that catches everything qhull
 * writes, so that nothing reaches stderr and failures can quote it. */
typedef struct qhull_run {
    qhT qh;
    coordT *points; /* qhull's copy of the input: it must outlive qh */
    FILE *log;
    char *text;
    size_t len;
} qhull_run;

/* The first non-empty line qhull wrote, without its newline, in buf. */
static const char *qhull_first_line(qhull_run *run, char *buf, size_t cap)
{
    const char *s = run->text ? run->text : "";
    size_t len;
    while (*s == '\n' || *s == ' ')
        ++s;
    len = strcspn(s, "\n");
    if (len >= cap)
        len = cap - 1;
    memcpy(buf, s, len);
    buf[len] = '\0';
    return buf[0] ? buf : "no message";
}

/* Run qhull on a copy of the m points of dimension dim in `xyz` (m x dim)
 * with `options` (after "qhull "). *out receives the run, whose hull is in
 * (*out)->qh on success; qhull_end(*out) must follow in every case, success
 * or not (it accepts NULL). */
static relief_status qhull_begin(const double *xyz, int dim, size_t m,
                                 const char *options, const char *what,
                                 qhull_run **out, relief_error *err)
{
    char cmd[64], line[400];
    int code;
    relief_status st;
    qhull_run *run;

    *out = NULL;
    if (m >= (size_t)INT_MAX)
        return relief_fail(err, RELIEF_E_MESH,
                           "%s: %zu points are more than qhull takes", what, m);
    run = calloc(1, sizeof *run);
    if (!run)
        return relief_fail(err, RELIEF_E_NOMEM, "%s: no memory for qhull", what);
    *out = run;
    run->points = malloc((size_t)dim * m * sizeof *run->points);
    if (!run->points)
        return relief_fail(err, RELIEF_E_NOMEM, "%s: no memory for %zu points",
                           what, m);
    memcpy(run->points, xyz, (size_t)dim * m * sizeof *run->points);
    run->log = open_memstream(&run->text, &run->len);
    if (!run->log)
        return relief_fail(err, RELIEF_E_NOMEM,
                           "%s: cannot open a memory stream for qhull", what);
    qh_zero(&run->qh, run->log);
    snprintf(cmd, sizeof cmd, "qhull %s", options);
    code = qh_new_qhull(&run->qh, dim, (int)m, run->points, False, cmd, NULL,
                        run->log);
    if (code == 0)
        return RELIEF_OK;
    fflush(run->log);
    switch (code) {
    case qh_ERRmem:
        st = RELIEF_E_NOMEM;
        break;
    case qh_ERRsingular:
    case qh_ERRprec:
    case qh_ERRtopology:
    case qh_ERRwide:
        st = RELIEF_E_MESH;
        break;
    default:
        st = RELIEF_E_INTERNAL;
        break;
    }
    return relief_fail(err, st, "%s: qhull '%s' failed on %zu points (exit %d): %s",
                       what, options, m, code,
                       qhull_first_line(run, line, sizeof line));
}

/* Free everything qhull_begin made, however far it got; NULL accepted. */
static void qhull_end(qhull_run *run)
{
    int curlong, totlong;
    if (!run)
        return;
    if (run->log) {
        qh_freeqhull(&run->qh, !qh_ALL);
        qh_memfreeshort(&run->qh, &curlong, &totlong);
        fclose(run->log);
        free(run->text);
    }
    free(run->points);
    free(run);
}

/* ------------------------------------------------------------- geometry */

static double orient2d(const double *a, const double *b, const double *c)
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* Circumcentre of (a, b, c) in ctr and its radius; 0 for collinear points
 * (ctr then undefined). */
static int circumcircle(const double *a, const double *b, const double *c,
                        double ctr[2], double *radius)
{
    double bx = b[0] - a[0], by = b[1] - a[1];
    double cx = c[0] - a[0], cy = c[1] - a[1];
    double d = 2.0 * (bx * cy - by * cx);
    double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
    double ux, uy;
    if (d == 0.0)
        return 0;
    ux = (cy * b2 - by * c2) / d;
    uy = (bx * c2 - cx * b2) / d;
    if (!isfinite(ux) || !isfinite(uy))
        return 0;
    ctr[0] = a[0] + ux;
    ctr[1] = a[1] + uy;
    *radius = sqrt(ux * ux + uy * uy);
    return 1;
}

double relief_circumradius_2d(const double a[2], const double b[2],
                              const double c[2])
{
    double ctr[2], r;
    return circumcircle(a, b, c, ctr, &r) ? r : INFINITY;
}

static relief_status check_finite(const double *x, size_t n, int dim,
                                  const char *what, relief_error *err)
{
    for (size_t i = 0; i < n; ++i)
        for (int k = 0; k < dim; ++k)
            if (!isfinite(x[i * dim + k]))
                return relief_fail(err, RELIEF_E_MESH,
                                   "%s: point %zu has a non-finite coordinate "
                                   "(%g)", what, i, x[i * dim + k]);
    return RELIEF_OK;
}

/* RELIEF_E_MESH unless the m points xy (m x 2) span a plane. */
static relief_status check_planar(const double *xy, size_t m,
                                  const char *what, relief_error *err)
{
    size_t far = 0;
    double d2 = 0.0, d[2], area = 0.0;
    for (size_t i = 1; i < m; ++i) {
        double du = xy[2 * i] - xy[0], dv = xy[2 * i + 1] - xy[1];
        if (du * du + dv * dv > d2) {
            d2 = du * du + dv * dv;
            far = i;
        }
    }
    if (d2 == 0.0)
        return relief_fail(err, RELIEF_E_MESH,
                           "%s: all %zu points coincide: nothing to "
                           "triangulate", what, m);
    d[0] = xy[2 * far] - xy[0];
    d[1] = xy[2 * far + 1] - xy[1];
    for (size_t i = 1; i < m; ++i) {
        double a = fabs(d[0] * (xy[2 * i + 1] - xy[1]) -
                        d[1] * (xy[2 * i] - xy[0]));
        if (a > area)
            area = a;
    }
    /* area / |d| is the largest distance from the line, |d| the extent. */
    if (area <= FLAT_REL * d2)
        return relief_fail(err, RELIEF_E_MESH,
                           "%s: all %zu points are collinear (within %g of "
                           "their extent): no triangle has area", what, m,
                           FLAT_REL);
    return RELIEF_OK;
}

/* ------------------------------------------------------ planar Delaunay */

typedef struct ring_vertex {
    double angle; /* about the cell's centroid */
    uint32_t id;
} ring_vertex;

static int ring_cmp(const void *pa, const void *pb)
{
    const ring_vertex *a = pa, *b = pb;
    return (a->angle > b->angle) - (a->angle < b->angle);
}

/* Over the hull's lower (Delaunay) cells of 3 or more vertices: the
 * triangles their fans make (*count) and the most vertices of one cell
 * (*widest). */
static void cells_count(qhT *qh, size_t *count, size_t *widest)
{
    facetT *facet;
    FORALLfacets {
        size_t k = (size_t)qh_setsize(qh, facet->vertices);
        if (facet->upperdelaunay || k < 3)
            continue;
        *count += k - 2;
        if (k > *widest)
            *widest = k;
    }
}

/* The vertices of one Delaunay cell into ring (*k of them) as indices into
 * xy (m x 2), sorted by angle about the cell's centroid: counter-clockwise. */
static relief_status cell_ring(qhT *qh, const facetT *facet, const double *xy, size_t m,
                               ring_vertex *ring, size_t *k, const char *what,
                               relief_error *err)
{
    vertexT *vertex, **vertexp;
    double c[2] = {0.0, 0.0};
    *k = 0;
    FOREACHvertex_(facet->vertices) {
        int id = qh_pointid(qh, vertex->point);
        if (id < 0 || (size_t)id >= m)
            return relief_fail(err, RELIEF_E_INTERNAL,
                               "%s: qhull cell f%u has vertex p%d, not one "
                               "of the %zu input points", what, facet->id,
                               id, m);
        ring[(*k)++].id = (uint32_t)id;
        c[0] += xy[2 * id];
        c[1] += xy[2 * id + 1];
    }
    c[0] /= (double)*k;
    c[1] /= (double)*k;
    for (size_t i = 0; i < *k; ++i) {
        const double *p = xy + 2 * (size_t)ring[i].id;
        ring[i].angle = atan2(p[1] - c[1], p[0] - c[0]);
    }
    qsort(ring, *k, sizeof *ring, ring_cmp);
    return RELIEF_OK;
}

/* The k - 2 triangles (out: (k - 2) x 3, counter-clockwise) of the fan
 * over the ring's k vertices from the one of least key[] (key NULL: the
 * index). */
static void cell_fan(const double *xy, const uint32_t *key, const ring_vertex *ring, size_t k,
                     uint32_t *out)
{
    size_t first = 0;
    for (size_t i = 1; i < k; ++i) {
        uint32_t ki = key ? key[ring[i].id] : ring[i].id;
        uint32_t kf = key ? key[ring[first].id] : ring[first].id;
        if (ki < kf)
            first = i;
    }
    for (size_t i = 1; i + 1 < k; ++i) {
        uint32_t *o = out + 3 * (i - 1);
        o[0] = ring[first].id;
        o[1] = ring[(first + i) % k].id;
        o[2] = ring[(first + i + 1) % k].id;
        /* The angular order is counter-clockwise; this only catches a
         * nearly flat cell whose angles rounded out of order. */
        if (orient2d(xy + 2 * (size_t)o[0], xy + 2 * (size_t)o[1],
                     xy + 2 * (size_t)o[2]) < 0.0) {
            uint32_t s = o[1];
            o[1] = o[2];
            o[2] = s;
        }
    }
}

/* Delaunay triangulation of the m points xy (m x 2), counter-clockwise, as
 * indices into xy. Qhull gives each Delaunay cell once with all of its
 * cocircular vertices; the cell is split into a fan from the vertex of least
 * key[] (key NULL: the index), so two copies of a cell whose vertices carry
 * the same keys are split alike. */
static relief_status delaunay_cells(const double *xy, size_t m,
                                    const uint32_t *key, uint32_t **tri,
                                    size_t *nt, const char *what,
                                    relief_error *err)
{
    qhull_run *run = NULL;
    uint32_t *out = NULL;
    ring_vertex *ring = NULL;
    size_t count = 0, widest = 0, t = 0;
    facetT *facet;
    qhT *qh;
    relief_status st = check_planar(xy, m, what, err);

    if (st)
        return st;
    /* 'Qbb' scales the lifted coordinate to the others' range; 'Qz' adds a
     * point at infinity, which keeps cocircular input (a regular grid, or
     * all points on one circle: a flat lifted hull) within qhull's
     * precision. No 'Qt': the cells are split here, the same way in every
     * copy (see above). No 'Qc': unused points are counted from the
     * triangles. */
    st = qhull_begin(xy, 2, m, "d Qbb Qz", what, &run, err);
    if (st)
        goto done;
    qh = &run->qh;
    cells_count(qh, &count, &widest);
    out = malloc((count ? count : 1) * 3 * sizeof *out);
    ring = malloc((widest ? widest : 1) * sizeof *ring);
    if (!out || !ring) {
        st = relief_fail(err, RELIEF_E_NOMEM,
                         "%s: no memory for %zu triangles", what, count);
        goto done;
    }
    FORALLfacets {
        size_t k;
        if (facet->upperdelaunay || qh_setsize(qh, facet->vertices) < 3)
            continue;
        st = cell_ring(qh, facet, xy, m, ring, &k, what, err);
        if (st)
            goto done;
        cell_fan(xy, key, ring, k, out + 3 * t);
        t += k - 2;
    }
    *tri = out;
    *nt = t;
    out = NULL;
done:
    free(ring);
    free(out);
    qhull_end(run);
    return st;
}

/* Hand the count triangles t (over n points) to the caller, counting the
 * points they leave unused; frees t on failure. */
static relief_status finish(uint32_t *t, size_t count, size_t n,
                            uint32_t **tri, size_t *nt, size_t *unused,
                            const char *what, relief_error *err)
{
    if (unused) {
        uint8_t *used = calloc(n ? n : 1, 1);
        if (!used) {
            free(t);
            return relief_fail(err, RELIEF_E_NOMEM,
                               "%s: no memory for %zu flags", what, n);
        }
        *unused = n;
        for (size_t i = 0; i < 3 * count; ++i)
            if (!used[t[i]]) {
                used[t[i]] = 1;
                --*unused;
            }
        free(used);
    }
    *tri = t;
    *nt = count;
    return RELIEF_OK;
}

static relief_status check_args(const double *x, size_t n, size_t least,
                                uint32_t **tri, size_t *nt, int dim,
                                const char *what, relief_error *err)
{
    if (!x || !tri || !nt)
        return relief_fail(err, RELIEF_E_USAGE, "%s: %s is NULL", what,
                           !x ? "the point array" : !tri ? "tri" : "nt");
    if (n < least)
        return relief_fail(err, RELIEF_E_MESH,
                           "%s: needs at least %zu points, got %zu", what,
                           least, n);
    return check_finite(x, n, dim, what, err);
}

relief_status relief_delaunay_2d(const double *uv, size_t n, uint32_t **tri,
                                 size_t *nt, size_t *unused,
                                 relief_error *err)
{
    static const char what[] = "relief_delaunay_2d";
    uint32_t *t;
    size_t count;
    relief_status st = check_args(uv, n, 3, tri, nt, 2, what, err);
    if (st)
        return st;
    st = delaunay_cells(uv, n, NULL, &t, &count, what, err);
    if (st)
        return st;
    return finish(t, count, n, tri, nt, unused, what, err);
}

/* ---------------------------------------------------- periodic Delaunay */

typedef struct cell_point {
    int64_t cx, cy; /* cell of side eps */
    uint32_t id;
} cell_point;

static int cell_cmp(const void *pa, const void *pb)
{
    const cell_point *a = pa, *b = pb;
    if (a->cx != b->cx)
        return a->cx < b->cx ? -1 : 1;
    if (a->cy != b->cy)
        return a->cy < b->cy ? -1 : 1;
    return (a->id > b->id) - (a->id < b->id);
}

/* First entry of the sorted c at or after cell (cx, cy). */
static size_t cell_find(const cell_point *c, size_t n, int64_t cx, int64_t cy)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (c[mid].cx < cx || (c[mid].cx == cx && c[mid].cy < cy))
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* Sets dup[i] for each point i within eps in v and in u (modulo the
 * period) of a point j < i that is not itself a duplicate. The points w
 * (n x 2) have u in [0, period), v >= vmin. */
static relief_status mark_duplicates(const double *w, size_t n, double period,
                                     double vmin, double eps, uint8_t *dup,
                                     const char *what, relief_error *err)
{
    cell_point *c = malloc(n * sizeof *c);
    if (!c)
        return relief_fail(err, RELIEF_E_NOMEM,
                           "%s: no memory to find duplicate points", what);
    for (size_t i = 0; i < n; ++i) {
        c[i].cx = (int64_t)floor(w[2 * i] / eps);
        c[i].cy = (int64_t)floor((w[2 * i + 1] - vmin) / eps);
        c[i].id = (uint32_t)i;
    }
    qsort(c, n, sizeof *c, cell_cmp);
    memset(dup, 0, n);
    for (size_t i = 0; i < n; ++i) {
        int64_t cy = (int64_t)floor((w[2 * i + 1] - vmin) / eps);
        for (int k = -1; k <= 1 && !dup[i]; ++k) {
            double u = w[2 * i] + k * period;
            int64_t cx = (int64_t)floor(u / eps);
            if (k != 0 && fabs(u - (k > 0 ? period : 0.0)) > eps)
                continue; /* not near the seam */
            for (int dx = -1; dx <= 1; ++dx)
                for (int dy = -1; dy <= 1; ++dy)
                    for (size_t q = cell_find(c, n, cx + dx, cy + dy);
                         q < n && c[q].cx == cx + dx && c[q].cy == cy + dy;
                         ++q) {
                        size_t j = c[q].id;
                        if (j < i && !dup[j] &&
                            fabs(w[2 * j] - u) <= eps &&
                            fabs(w[2 * j + 1] - w[2 * i + 1]) <= eps)
                            dup[i] = 1;
                    }
        }
    }
    free(c);
    return RELIEF_OK;
}

/* The points within `margin` of the seam copied one period over: the
 * extended set holds every copy u + k * period (k in -1, 0, 1) lying in
 * [-margin, period + margin). */
typedef struct seam_copies {
    size_t m;       /* points in the extended set */
    double *xy;     /* m x 2 */
    uint32_t *src;  /* m original indices */
    int8_t *shift;  /* m: k, the periods added to u */
} seam_copies;

static int copy_present(double u, int k, double period, double margin)
{
    return k == 0 || (k == 1 && u < margin) ||
           (k == -1 && u >= period - margin);
}

/* Copies of the points w (n x 2) but those marked in dup. */
static relief_status seam_copy(const double *w, const uint8_t *dup, size_t n,
                               double period, double margin, seam_copies *s,
                               const char *what, relief_error *err)
{
    size_t m = 0;
    for (size_t i = 0; i < n; ++i)
        for (int k = -1; k <= 1 && !dup[i]; ++k)
            m += (size_t)copy_present(w[2 * i], k, period, margin);
    s->xy = malloc(2 * m * sizeof *s->xy);
    s->src = malloc(m * sizeof *s->src);
    s->shift = malloc(m);
    if (!s->xy || !s->src || !s->shift)
        return relief_fail(err, RELIEF_E_NOMEM,
                           "%s: no memory for %zu seam copies", what, m);
    s->m = 0;
    for (size_t i = 0; i < n; ++i)
        for (int k = -1; k <= 1 && !dup[i]; ++k)
            if (copy_present(w[2 * i], k, period, margin)) {
                s->xy[2 * s->m] = w[2 * i] + k * period;
                s->xy[2 * s->m + 1] = w[2 * i + 1];
                s->src[s->m] = (uint32_t)i;
                s->shift[s->m] = (int8_t)k;
                ++s->m;
            }
    return RELIEF_OK;
}

static void seam_free(seam_copies *s)
{
    free(s->xy);
    free(s->src);
    free(s->shift);
    memset(s, 0, sizeof *s);
}

/* 1 when a copy of some point (not a duplicate) left out of the extended
 * set lies inside or on the circumcircle of (a, b, c): the triangle may
 * then not be Delaunay for the whole periodic set; *reach is then the
 * margin that would hold every copy inside it, how far the circle reaches
 * past [0, period) in u within the band's rows [vmin, vmax], where every
 * point lies (a sliver along the rim has a huge circle, most of it off the
 * band). 2 when that copy is more than a period away, which no margin
 * short of the last resort's whole period settles (a long sliver along a
 * jagged rim, whose circle spans periods). */
static int circle_misses_copy(const double *a, const double *b,
                              const double *c, const double *w,
                              const uint8_t *dup, size_t n, double period,
                              double margin, double vmin, double vmax,
                              double *reach)
{
    double ctr[2], r, d, half;
    if (!circumcircle(a, b, c, ctr, &r))
        return 0; /* a flat fan triangle; its cell's others are checked */
    r *= 1.0 + CIRCLE_REL;
    if (ctr[0] - r > -margin && ctr[0] + r < period + margin)
        return 0;
    d = ctr[1] < vmin ? vmin - ctr[1] : ctr[1] > vmax ? ctr[1] - vmax : 0.0;
    half = d < r ? sqrt(r * r - d * d) : 0.0; /* the circle's half-width on the band */
    *reach = fmax(half - ctr[0], ctr[0] + half - period);
    for (size_t j = 0; j < n; ++j) {
        double dv = w[2 * j + 1] - ctr[1], h2 = r * r - dv * dv, h;
        double kmin, kmax;
        if (h2 < 0.0 || dup[j])
            continue;
        h = sqrt(h2);
        kmin = ceil((ctr[0] - h - w[2 * j]) / period);
        kmax = floor((ctr[0] + h - w[2 * j]) / period);
        if (kmin > kmax)
            continue;
        if (kmin < -1.0 || kmax > 1.0)
            return 2; /* no copy is ever made more than a period away */
        for (int k = (int)kmin; k <= (int)kmax; ++k)
            if (!copy_present(w[2 * j], k, period, margin))
                return 1;
    }
    return 0;
}

/* Angle at p of the triangle (p, q, r), in [0, pi]. */
static double corner_angle(const double *p, const double *q, const double *r)
{
    double ax = q[0] - p[0], ay = q[1] - p[1];
    double bx = r[0] - p[0], by = r[1] - p[1];
    return atan2(fabs(ax * by - ay * bx), ax * bx + ay * by);
}

/* From the triangles et (ent x 3, indices into s), put one copy of each
 * periodic triangle into out as original indices. Returns 1 when the
 * margin was too narrow to trust them: then a wider one is needed, at
 * least *need, the widest reach of a circle that missed a copy (0 when only
 * a star failed to close); 2 when only a whole period can do
 * (circle_misses_copy).
 *
 * Why the checks suffice. If every triangle at an original (unshifted)
 * point has no copy of any point inside its circumcircle, and the angles
 * of those triangles close around the point (2 pi, or pi on the band's
 * lower and upper rim), then the point's star is its star in the periodic
 * triangulation. Every periodic triangle has such a point in the copy this
 * keeps, so none is missing and none is wrong. With a whole period copied
 * each side (the last resort), triangles failing the circle check are
 * dropped instead: only long slivers along a jagged rim do. */
static int seam_pick(const seam_copies *s, const uint32_t *et, size_t ent,
                     const double *w, const uint8_t *dup, size_t n,
                     double period, double margin, double vmin, double vmax,
                     double *fan, uint32_t *out, size_t *kept, double *need)
{
    int last = margin >= period, missed = 0;
    *kept = 0;
    *need = 0.0;
    memset(fan, 0, n * sizeof *fan);
    for (size_t t = 0; t < ent; ++t) {
        const uint32_t *e = et + 3 * t;
        const double *p[3];
        int lo = 1, any0 = 0, long_edge = 0;
        for (int k = 0; k < 3; ++k) {
            int sh = s->shift[e[k]];
            p[k] = s->xy + 2 * (size_t)e[k];
            lo = sh < lo ? sh : lo;
            any0 |= sh == 0;
        }
        if (!any0)
            continue; /* only copies away from [0, period) */
        double reach = 0.0;
        int miss = circle_misses_copy(p[0], p[1], p[2], w, dup, n, period, margin, vmin, vmax,
                                      &reach);
        if (miss == 2 && !last)
            return 2;
        if (miss) {
            /* Every such circle measured: one wider margin settles them all,
             * not a doubling for each (a jagged rim's slivers took 8 qhull
             * runs of a 6000-vertex band). */
            *need = fmax(*need, reach);
            missed = 1;
            continue;
        }
        if (missed && !last)
            continue; /* a wider margin follows: no star or copy to keep */
        for (int k = 0; k < 3; ++k) {
            if (s->shift[e[k]] == 0)
                fan[s->src[e[k]]] +=
                    corner_angle(p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
            long_edge |= fabs(p[k][0] - p[(k + 1) % 3][0]) >= 0.5 * period;
        }
        /* The copy with no vertex shifted by -1 period and one by 0. */
        if (lo != 0 || long_edge)
            continue;
        for (int k = 0; k < 3; ++k)
            out[3 * *kept + k] = s->src[e[k]];
        ++*kept;
    }
    if (last)
        return 0;
    if (missed)
        return 1;
    for (size_t i = 0; i < n; ++i) {
        double v = w[2 * i + 1];
        double full = (v == vmin || v == vmax) ? RELIEF_PI : 2.0 * RELIEF_PI;
        if (!dup[i] && fan[i] < full - ANGLE_TOL)
            return 1;
    }
    return 0;
}

/* The band as the margin search sees it: the points w (n x 2) with u in
 * [0, period) and v in [vmin, vmax], dup marking those taken as another,
 * fan (n) scratch for seam_pick's angle sums. */
typedef struct seam_band {
    const double *w;
    const uint8_t *dup;
    double *fan;
    size_t n;
    double period, vmin, vmax;
} seam_band;

/* w (n x 2): the points uv (n x 2) with u wrapped into [0, period); their
 * range of v into *vmin, *vmax. */
static void wrap_points(const double *uv, size_t n, double period, double *w, double *vmin,
                        double *vmax)
{
    *vmin = *vmax = uv[1];
    for (size_t i = 0; i < n; ++i) {
        double u = fmod(uv[2 * i], period);
        if (u < 0.0)
            u += period;
        if (u >= period) /* -tiny + period rounds up to period */
            u = 0.0;
        w[2 * i] = u;
        w[2 * i + 1] = uv[2 * i + 1];
        *vmin = fmin(*vmin, uv[2 * i + 1]);
        *vmax = fmax(*vmax, uv[2 * i + 1]);
    }
}

/* The band's periodic triangles (*out: *kept x 3, original indices; the
 * caller's on success, NULL otherwise): the Delaunay cells of the points
 * and their copies within a margin of the seam, from `margin` widened
 * until seam_pick trusts them, or until a whole period. */
static relief_status seam_triangulate(const seam_band *b, double margin, uint32_t **out,
                                      size_t *kept, const char *what, relief_error *err)
{
    seam_copies s = {0};
    uint32_t *et = NULL, *picked = NULL;
    size_t ent = 0;
    double need;
    relief_status st;

    *out = NULL;
    for (;;) {
        int wider;
        st = seam_copy(b->w, b->dup, b->n, b->period, margin, &s, what, err);
        if (st)
            goto done;
        st = delaunay_cells(s.xy, s.m, s.src, &et, &ent, what, err);
        /* A few points away from the seam can be collinear on their own. */
        if (st == RELIEF_E_MESH && margin < b->period) {
            margin = fmin(b->period, 2.0 * margin);
            seam_free(&s);
            continue;
        }
        if (st)
            goto done;
        picked = malloc((ent ? ent : 1) * 3 * sizeof *picked);
        if (!picked) {
            st = relief_fail(err, RELIEF_E_NOMEM,
                             "%s: no memory for %zu triangles", what, ent);
            goto done;
        }
        wider = seam_pick(&s, et, ent, b->w, b->dup, b->n, b->period, margin, b->vmin,
                          b->vmax, b->fan, picked, kept, &need);
        free(et);
        et = NULL;
        seam_free(&s);
        if (!wider)
            break;
        free(picked);
        picked = NULL;
        margin = wider == 2 ? b->period : fmin(b->period, fmax(2.0 * margin, need));
    }
    *out = picked;
    picked = NULL;
done:
    free(picked);
    free(et);
    seam_free(&s);
    return st;
}

relief_status relief_delaunay_periodic(const double *uv, size_t n,
                                       double period, uint32_t **tri,
                                       size_t *nt, size_t *unused,
                                       relief_error *err)
{
    static const char what[] = "relief_delaunay_periodic";
    double *w = NULL, *fan = NULL, vmin, vmax, margin;
    uint8_t *dup = NULL;
    uint32_t *out = NULL;
    size_t kept = 0;
    relief_status st = check_args(uv, n, 3, tri, nt, 2, what, err);

    if (st)
        return st;
    if (!isfinite(period) || period <= 0.0)
        return relief_fail(err, RELIEF_E_RANGE,
                           "%s: period %g is not finite and > 0", what, period);
    if (n >= (size_t)INT_MAX / 3)
        return relief_fail(err, RELIEF_E_MESH,
                           "%s: %zu points are more than qhull takes (with "
                           "their seam copies)", what, n);
    w = malloc(2 * n * sizeof *w);
    fan = malloc(n * sizeof *fan);
    dup = malloc(n);
    if (!w || !fan || !dup) {
        st = relief_fail(err, RELIEF_E_NOMEM, "%s: no memory for %zu points",
                         what, n);
        goto done;
    }
    wrap_points(uv, n, period, w, &vmin, &vmax);
    if (!(vmax - vmin > FLAT_REL * (period + fabs(vmax)))) {
        st = relief_fail(err, RELIEF_E_MESH,
                         "%s: all %zu points have v = %g: one ring of points "
                         "bounds no area", what, n, vmin);
        goto done;
    }
    st = mark_duplicates(w, n, period, vmin,
                         DUP_REL * (period + vmax - vmin), dup, what, err);
    if (st)
        goto done;
    margin = fmin(period, MARGIN_SPACINGS *
                              sqrt(period * (vmax - vmin) / (double)n));
    st = seam_triangulate(&(seam_band){w, dup, fan, n, period, vmin, vmax}, margin, &out,
                          &kept, what, err);
    if (st)
        goto done;
    if (kept == 0) {
        st = relief_fail(err, RELIEF_E_MESH,
                         "%s: no triangle: %zu points are too few around the "
                         "band (every triangle would span half a period)",
                         what, n);
        goto done;
    }
    st = finish(out, kept, n, tri, nt, unused, what, err);
    out = NULL;
done:
    free(out);
    free(dup);
    free(fan);
    free(w);
    return st;
}

/* ------------------------------------------------------- spherical hull */

/* RELIEF_E_MESH unless the n points x (n x 3) span a volume. */
static relief_status check_solid(const double *x, size_t n, const char *what,
                                 relief_error *err)
{
    size_t i1 = 0;
    double d2 = 0.0, best = 0.0, a[3], nrm[3] = {0.0, 0.0, 0.0}, nn;
    for (size_t i = 1; i < n; ++i) {
        double e = 0.0;
        for (int k = 0; k < 3; ++k)
            e += (x[3 * i + k] - x[k]) * (x[3 * i + k] - x[k]);
        if (e > d2) {
            d2 = e;
            i1 = i;
        }
    }
    if (d2 == 0.0)
        return relief_fail(err, RELIEF_E_MESH,
                           "%s: all %zu directions coincide", what, n);
    for (int k = 0; k < 3; ++k)
        a[k] = x[3 * i1 + k] - x[k];
    for (size_t i = 1; i < n; ++i) {
        double b[3], c[3], e;
        for (int k = 0; k < 3; ++k)
            b[k] = x[3 * i + k] - x[k];
        c[0] = a[1] * b[2] - a[2] * b[1];
        c[1] = a[2] * b[0] - a[0] * b[2];
        c[2] = a[0] * b[1] - a[1] * b[0];
        e = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
        if (e > best) {
            best = e;
            memcpy(nrm, c, sizeof nrm);
        }
    }
    if (best <= FLAT_REL * FLAT_REL * d2 * d2)
        return relief_fail(err, RELIEF_E_MESH,
                           "%s: all %zu directions are collinear", what, n);
    nn = sqrt(best);
    best = 0.0;
    for (size_t i = 1; i < n; ++i) {
        double e = 0.0;
        for (int k = 0; k < 3; ++k)
            e += (x[3 * i + k] - x[k]) * nrm[k] / nn;
        best = fmax(best, fabs(e));
    }
    if (best <= FLAT_REL * sqrt(d2))
        return relief_fail(err, RELIEF_E_MESH,
                           "%s: all %zu directions lie on one plane (one "
                           "circle of the sphere): their hull has no volume",
                           what, n);
    return RELIEF_OK;
}

relief_status relief_hull_sphere(const double *dirs, size_t n, uint32_t **tri,
                                 size_t *nt, size_t *unused,
                                 relief_error *err)
{
    static const char what[] = "relief_hull_sphere";
    qhull_run *run = NULL;
    uint32_t *out = NULL;
    size_t count = 0, t = 0;
    facetT *facet;
    vertexT *vertex, **vertexp;
    qhT *qh;
    relief_status st = check_args(dirs, n, 4, tri, nt, 3, what, err);

    if (st)
        return st;
    st = check_solid(dirs, n, what, err);
    if (st)
        return st;
    st = qhull_begin(dirs, 3, n, "Qt", what, &run, err);
    if (st)
        goto done;
    qh = &run->qh;
    FORALLfacets
        ++count;
    out = malloc((count ? count : 1) * 3 * sizeof *out);
    if (!out) {
        st = relief_fail(err, RELIEF_E_NOMEM,
                         "%s: no memory for %zu triangles", what, count);
        goto done;
    }
    FORALLfacets {
        uint32_t *o = out + 3 * t;
        const double *p[3];
        double e1[3], e2[3], c[3];
        int k = 0;
        if (qh_setsize(qh, facet->vertices) != 3) {
            st = relief_fail(err, RELIEF_E_INTERNAL,
                             "%s: qhull facet f%u has %d vertices after 'Qt'",
                             what, facet->id, qh_setsize(qh, facet->vertices));
            goto done;
        }
        FOREACHvertex_(facet->vertices) {
            int id = qh_pointid(qh, vertex->point);
            if (id < 0 || (size_t)id >= n) {
                st = relief_fail(err, RELIEF_E_INTERNAL,
                                 "%s: qhull facet f%u has vertex p%d, not one "
                                 "of the %zu input points", what, facet->id,
                                 id, n);
                goto done;
            }
            o[k] = (uint32_t)id;
            p[k++] = dirs + 3 * (size_t)id;
        }
        for (k = 0; k < 3; ++k) {
            e1[k] = p[1][k] - p[0][k];
            e2[k] = p[2][k] - p[0][k];
        }
        c[0] = e1[1] * e2[2] - e1[2] * e2[1];
        c[1] = e1[2] * e2[0] - e1[0] * e2[2];
        c[2] = e1[0] * e2[1] - e1[1] * e2[0];
        /* qhull's normal points out of the hull even where the hull does
         * not hold the origin (directions on one hemisphere). */
        if (c[0] * facet->normal[0] + c[1] * facet->normal[1] +
                c[2] * facet->normal[2] < 0.0) {
            uint32_t s = o[1];
            o[1] = o[2];
            o[2] = s;
        }
        ++t;
    }
    st = finish(out, t, n, tri, nt, unused, what, err);
    out = NULL;
done:
    free(out);
    qhull_end(run);
    return st;
}
