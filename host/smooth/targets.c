/* Targets of the smooth completion: the lattice, what the capture covers,
 * and the regions of the rest (targets.h). A region is found by flooding
 * the lattice's uncovered points through their six neighbours (plane,
 * cylinder: wrapping round the turn) or, on the sphere's Fibonacci
 * lattice, through the uncovered points within 1.5 spacings. */
#include "smooth/targets.h"
#include "base/params.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "base/compare.h"
#include "base/knn.h"
#include "base/vec3.h"

#define RM_REAL double
#include "kernels/relief_math.h"


/* ---------------------------------------------------------- coverage */

/* The capture's triangles projected on the primitive, with a kd-tree over
 * their centroids, to ask "is this point of the primitive covered?". */
typedef struct coverage {
    const relief_mesh *cap;
    double *proj;      /* cap->nv x 3 projected capture vertices */
    double *centroid;  /* cap->nt x 3 */
    flann_index_t index;
    struct FLANNParameters fp;
    int k;
    double lo[3], hi[3]; /* the projected capture's bounding box */
} coverage;

static void coverage_free(coverage *c)
{
    if (c->index)
        flann_free_index_double(c->index, &c->fp);
    free(c->proj);
    free(c->centroid);
}

static relief_status coverage_build(coverage *c, const relief_mesh *cap,
                                    const relief_fit_primitive *prim, relief_error *err)
{
    float speedup;
    memset(c, 0, sizeof *c);
    c->cap = cap;
    c->proj = malloc(cap->nv * 3 * sizeof *c->proj);
    c->centroid = malloc(cap->nt * 3 * sizeof *c->centroid);
    if (!c->proj || !c->centroid)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the coverage index");
    for (int k = 0; k < 3; ++k) {
        c->lo[k] = DBL_MAX;
        c->hi[k] = -DBL_MAX;
    }
    for (size_t v = 0; v < cap->nv; ++v) {
        relief_fit_project(prim, cap->pos + 3 * v, c->proj + 3 * v);
        for (int k = 0; k < 3; ++k) {
            c->lo[k] = fmin(c->lo[k], c->proj[3 * v + k]);
            c->hi[k] = fmax(c->hi[k], c->proj[3 * v + k]);
        }
    }
    for (size_t t = 0; t < cap->nt; ++t)
        for (int k = 0; k < 3; ++k)
            c->centroid[3 * t + k] = (c->proj[3 * cap->tri[3 * t] + k] +
                                      c->proj[3 * cap->tri[3 * t + 1] + k] +
                                      c->proj[3 * cap->tri[3 * t + 2] + k]) / 3.0;
    c->fp = relief_knn_exact_params();
    c->k = cap->nt < 16 ? (int)cap->nt : 16;
    c->index = flann_build_index_double(c->centroid, (int)cap->nt, 3, &speedup, &c->fp);
    if (!c->index)
        return relief_fail(err, RELIEF_E_INTERNAL, "FLANN could not build a kd-tree");
    return RELIEF_OK;
}

/* Is p (on the primitive) within sqrt(r2) of the nearest of the k projected
 * capture triangles whose centroids are nearest p? A point farther than
 * that from the capture's bounding box is not, without a search: most of a
 * sphere's or a cylinder's lattice lies far from a one-sided capture, and
 * there a kd-tree search visits most of the tree (a 2-million-target
 * sphere took minutes). */
static int covered(const coverage *c, const double p[3], double r2)
{
    int idx[16];
    double dist[16], box2 = 0.0;
    for (int k = 0; k < 3; ++k) {
        double d = p[k] < c->lo[k] ? c->lo[k] - p[k] : p[k] > c->hi[k] ? p[k] - c->hi[k] : 0.0;
        box2 += d * d;
    }
    if (box2 > r2)
        return 0;
    if (flann_find_nearest_neighbors_index_double(c->index, (double *)p, 1, idx, dist,
                                                  c->k, (struct FLANNParameters *)&c->fp) != 0)
        return 0;
    for (int i = 0; i < c->k; ++i) {
        const uint32_t *f = c->cap->tri + 3 * (size_t)idx[i];
        if (rm_point_triangle_d2(p, c->proj + 3 * f[0], c->proj + 3 * f[1],
                                 c->proj + 3 * f[2]) <= r2)
            return 1;
    }
    return 0;
}

/* --------------------------------------------------------------- regions */

/* The uncovered lattice points with the region each belongs to. */
typedef struct regions {
    relief_target_list pts; /* every uncovered point */
    uint32_t *of;           /* pts.n: its region */
    size_t *size;           /* per region: its points */
    uint8_t *outside;       /* per region: 1 when outside the capture's outline */
    size_t n, cap;          /* regions */
    size_t covered;         /* covered lattice points */
} regions;

static void regions_free(regions *r)
{
    free(r->pts.p);
    free(r->of);
    free(r->size);
    free(r->outside);
}

static int push_point(relief_target_list *l, const double p[3])
{
    if (l->n == l->cap) {
        size_t cap = l->cap ? 2 * l->cap : 1024;
        double *q = realloc(l->p, cap * 3 * sizeof *q);
        if (!q)
            return 0;
        l->p = q;
        l->cap = cap;
    }
    memcpy(l->p + 3 * l->n++, p, 3 * sizeof(double));
    return 1;
}

/* A new, empty region; its id, or UINT32_MAX when out of memory. */
static uint32_t new_region(regions *r)
{
    if (r->n == r->cap) {
        size_t cap = r->cap ? 2 * r->cap : 64;
        size_t *size = realloc(r->size, cap * sizeof *size);
        uint8_t *outside;
        if (!size)
            return UINT32_MAX;
        r->size = size;
        outside = realloc(r->outside, cap);
        if (!outside)
            return UINT32_MAX;
        r->outside = outside;
        r->cap = cap;
    }
    r->size[r->n] = 0;
    r->outside[r->n] = 0;
    return (uint32_t)r->n++;
}

/* ------------------------------------------------------------ lattices */

#define COVERED UINT32_MAX
#define UNSEEN (UINT32_MAX - 1)

/* Triangular lattice over [u0, u1] x [v0, v1] (plane) or the full turn
 * times [v0, v1] (cylinder, periodic in u): its uncovered points, flooded
 * into regions. A region touching the border (the first or last row; on a
 * plane the first or last column too) is outside the outline.
 *
 * The lattice's rows run along u on a plane. On a cylinder they run along
 * the axis (v), the rows stacked around the turn (an even number of them,
 * so the half-step offset of odd rows closes up), so that one of the
 * lattice's three edge directions is the axis: ridges along a trunk, a
 * drill's flutes, a bottle's ribs follow lattice edges. With rows around
 * the turn instead, no edge is axial and an axial ridge is drawn as a +-30
 * degree zigzag: the demo's exact truth sampled on that lattice read 15.2
 * degrees of lean against its own 10.4. */
typedef struct lattice {
    int periodic;       /* cylinder: rows along v, stacked around u */
    size_t na, nb;      /* points per row, rows */
    double a0, da;      /* first point of a row and step along it */
    double b0, db;      /* first row and the step between rows */
} lattice;

static void lattice_uv(const lattice *l, size_t i, size_t j, double *u, double *v)
{
    const double a = l->a0 + ((double)i + 0.5 * (double)(j % 2)) * l->da;
    const double b = l->b0 + (double)j * l->db;
    if (l->periodic)
        *u = b, *v = a;
    else
        *u = a, *v = b;
}

/* The lattice's shape: points per row over [a_lo, a_hi] at spacing l->da,
 * rows over [b_lo, b_hi] at l->db (on a cylinder an even number of at
 * least 4 that closes the turn, the step stretched to fit), centred in the
 * non-periodic extent so that both ends get the same margin. */
static void lattice_shape(lattice *l, double a_lo, double a_hi, double b_lo, double b_hi)
{
    const double sp = l->da, row = l->db; /* as laid, before a cylinder's stretch */
    l->na = (size_t)floor((a_hi - a_lo) / sp) + 1;
    if (l->periodic) {
        l->nb = 2 * (size_t)floor((b_hi - b_lo) / (2.0 * row) + 0.5);
        if (l->nb < 4)
            l->nb = 4;
        l->db = (b_hi - b_lo) / (double)l->nb;
    } else {
        l->nb = (size_t)floor((b_hi - b_lo) / row) + 1;
    }
    if (l->periodic)
        l->a0 += 0.5 * ((a_hi - a_lo) - (double)(l->na - 1) * sp);
    else
        l->b0 += 0.5 * ((b_hi - b_lo) - (double)(l->nb - 1) * row);
}

/* lab (na x nb, row after row): COVERED where the capture lies within
 * sqrt(cover2) of the point, else UNSEEN; the covered counted in out. */
static void lattice_cover(const lattice *l, const coverage *cov, const relief_domain *pm,
                          double cover2, uint32_t *lab, regions *out)
{
    for (size_t j = 0; j < l->nb; ++j)
        for (size_t i = 0; i < l->na; ++i) {
            double p[3], u, v;
            lattice_uv(l, i, j, &u, &v);
            relief_domain_point(pm, u, v, p);
            lab[j * l->na + i] = covered(cov, p, cover2) ? COVERED : UNSEEN;
            out->covered += lab[j * l->na + i] == COVERED;
        }
}

/* Region id from the point seed through every UNSEEN point joined to it by
 * lattice edges (six neighbours, wrapping round the turn on a cylinder),
 * with its size and whether it touches the border. stack: scratch for
 * na x nb point indices. */
static void lattice_flood_one(const lattice *l, size_t seed, uint32_t id, uint32_t *lab,
                              uint32_t *stack, regions *out)
{
    uint32_t top = 0;
    lab[seed] = id;
    stack[top++] = (uint32_t)seed;
    while (top > 0) {
        size_t at = stack[--top], i = at % l->na, j = at / l->na;
        /* Six neighbours; odd rows sit half a step further along. */
        long di[6] = {-1, 1, 0, 1, 0, 1}, dj[6] = {0, 0, -1, -1, 1, 1};
        ++out->size[id];
        /* The border: a cylinder's first and last axial positions, a
         * plane's first and last rows and columns. */
        if (i == 0 || i == l->na - 1 || (!l->periodic && (j == 0 || j == l->nb - 1)))
            out->outside[id] = 1;
        if (j % 2 == 0)
            di[2] = -1, di[3] = 0, di[4] = -1, di[5] = 0;
        for (int q = 0; q < 6; ++q) {
            long ii = (long)i + di[q], jj = (long)j + dj[q];
            size_t nb;
            if (l->periodic)
                jj = (jj + (long)l->nb) % (long)l->nb;
            if (ii < 0 || jj < 0 || ii >= (long)l->na || jj >= (long)l->nb)
                continue;
            nb = (size_t)jj * l->na + (size_t)ii;
            if (lab[nb] == UNSEEN) {
                lab[nb] = id;
                stack[top++] = (uint32_t)nb;
            }
        }
    }
}

/* Every UNSEEN point of lab (na x nb) into a region of out, the regions
 * numbered in the order of their first point. */
static relief_status lattice_flood(const lattice *l, uint32_t *lab, uint32_t *stack,
                                   regions *out, relief_error *err)
{
    const size_t n = l->na * l->nb;
    for (size_t seed = 0; seed < n; ++seed) {
        uint32_t id;
        if (lab[seed] != UNSEEN)
            continue;
        if ((id = new_region(out)) == UINT32_MAX)
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the lattice's regions");
        lattice_flood_one(l, seed, id, lab, stack, out);
    }
    return RELIEF_OK;
}

/* The uncovered points (row after row) into out->pts, the region of each
 * into out->of. */
static relief_status lattice_collect(const lattice *l, const relief_domain *pm,
                                     const uint32_t *lab, regions *out, relief_error *err)
{
    out->of = malloc((l->na * l->nb - out->covered + 1) * sizeof *out->of);
    if (!out->of)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the lattice's regions");
    for (size_t j = 0; j < l->nb; ++j)
        for (size_t i = 0; i < l->na; ++i)
            if (lab[j * l->na + i] != COVERED) {
                double p[3], u, v;
                lattice_uv(l, i, j, &u, &v);
                relief_domain_point(pm, u, v, p);
                out->of[out->pts.n] = lab[j * l->na + i];
                if (!push_point(&out->pts, p))
                    return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate targets");
            }
    return RELIEF_OK;
}

static relief_status lattice_regions(const coverage *cov, const relief_domain *pm, double sp,
                                     double u0, double u1, double v0, double v1, int periodic,
                                     regions *out, relief_error *err)
{
    const double row = sp * sqrt(3.0) / 2.0;
    const double cover2 = 0.25 * sp * sp; /* (half a spacing)^2 */
    /* Along the rows, across them: (u, v) on a plane, (v, u) on a cylinder. */
    const double a_lo = periodic ? v0 : u0, a_hi = periodic ? v1 : u1;
    const double b_lo = periodic ? u0 : v0, b_hi = periodic ? u1 : v1;
    lattice l = {periodic, 0, 0, a_lo, sp, b_lo, row};
    size_t n;
    uint32_t *lab = NULL; /* per lattice point: COVERED, UNSEEN or its region */
    uint32_t *stack = NULL;
    relief_status st = RELIEF_OK;

    /* Count in double first: a tiny spacing must not overflow size_t. */
    if (!((floor((a_hi - a_lo) / sp) + 2.0) * (floor((b_hi - b_lo) / row) + 2.0) <= 50000000.0))
        return relief_fail(err, RELIEF_E_RANGE,
                           "the target lattice would have about %.3g points (spacing %g over "
                           "a %g x %g region); raise the spacing",
                           (floor((a_hi - a_lo) / sp) + 1.0) * (floor((b_hi - b_lo) / row) + 1.0),
                           sp, u1 - u0, v1 - v0);
    lattice_shape(&l, a_lo, a_hi, b_lo, b_hi);
    n = l.na * l.nb;
    lab = malloc(n * sizeof *lab);
    stack = malloc(n * sizeof *stack);
    if (!lab || !stack) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a %zu-point lattice", n);
        goto done;
    }
    lattice_cover(&l, cov, pm, cover2, lab, out);
    st = lattice_flood(&l, lab, stack, out, err);
    if (st == RELIEF_OK)
        st = lattice_collect(&l, pm, lab, out, err);
done:
    free(stack);
    free(lab);
    return st;
}

/* The Fibonacci lattice's points (at least 12) on the sphere at the
 * density of a triangular lattice of edge sp: the uncovered ones into
 * out->pts, the covered counted in out->covered. */
static relief_status sphere_lattice(const coverage *cov, const relief_domain *pm, double sp,
                                    regions *out, relief_error *err)
{
    const relief_fit_primitive *pr = &pm->prim;
    const double golden = RELIEF_PI * (3.0 - sqrt(5.0));
    double area = 4.0 * RELIEF_PI * pr->radius * pr->radius;
    double nf = area / (sp * sp * sqrt(3.0) / 2.0), e3[3];
    size_t n;

    if (nf > 50000000.0)
        return relief_fail(err, RELIEF_E_RANGE,
                           "the sphere would need %.0f targets; raise the spacing", nf);
    n = (size_t)nf;
    if (n < 12)
        n = 12;
    rm_cross(pm->e1, pm->e2, e3);
    for (size_t i = 0; i < n; ++i) {
        double z = 1.0 - 2.0 * ((double)i + 0.5) / (double)n, r = sqrt(1.0 - z * z);
        double a = golden * (double)i, p[3];
        for (int c = 0; c < 3; ++c)
            p[c] = pr->point[c] + pr->radius * (r * cos(a) * pm->e1[c] +
                                                r * sin(a) * pm->e2[c] + z * e3[c]);
        if (covered(cov, p, 0.25 * sp * sp))
            ++out->covered;
        else if (!push_point(&out->pts, p))
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate targets");
    }
    return RELIEF_OK;
}

/* Union-find over the m points (parent: m), joining each to those of its
 * k nearest (idx, dist: m x k, squared distances) within sqrt(link2); the
 * smaller id the root, so that regions come out in the order of their
 * first point, whatever order FLANN lists neighbours in. */
static void sphere_link(uint32_t *parent, const int *idx, const double *dist, size_t m,
                        size_t k, double link2)
{
    for (size_t i = 0; i < m; ++i)
        parent[i] = (uint32_t)i;
    for (size_t i = 0; i < m; ++i)
        for (size_t q = 0; q < k; ++q) {
            uint32_t a = (uint32_t)i, b;
            if (idx[i * k + q] < 0 || dist[i * k + q] > link2)
                continue;
            b = (uint32_t)idx[i * k + q];
            while (parent[a] != a)
                a = parent[a] = parent[parent[a]];
            while (parent[b] != b)
                b = parent[b] = parent[parent[b]];
            if (a < b)
                parent[b] = a;
            else if (b < a)
                parent[a] = b;
        }
}

/* A region of out per root of parent (m), numbered in the order of the
 * roots, with each point's region in out->of (m) and the sizes; a region
 * larger than the capture's own cover is outside its outline. */
static relief_status sphere_number(const uint32_t *parent, size_t m, regions *out,
                                   relief_error *err)
{
    for (size_t i = 0; i < m; ++i) {
        uint32_t r = (uint32_t)i;
        while (parent[r] != r)
            r = parent[r];
        if (r == i) {
            uint32_t id = new_region(out);
            if (id == UINT32_MAX)
                return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the sphere's regions");
            out->of[i] = id;
        } else {
            out->of[i] = out->of[r]; /* r < i: already numbered */
        }
        ++out->size[out->of[i]];
    }
    for (size_t id = 0; id < out->n; ++id)
        out->outside[id] = out->size[id] > out->covered;
    return RELIEF_OK;
}

/* Fibonacci lattice on the sphere at the density of a triangular lattice of
 * edge `spacing`: its uncovered points, joined into regions through the
 * pairs within 1.5 spacings (a Fibonacci lattice's nearest neighbours lie
 * 0.9 to 1.1 spacings apart). A region larger than the capture's own cover
 * is outside its outline. */
static relief_status sphere_regions(const coverage *cov, const relief_domain *pm, double sp,
                                    regions *out, relief_error *err)
{
    enum { K = 8 };
    const double link2 = 2.25 * sp * sp;
    uint32_t *parent = NULL;
    int *idx = NULL;
    double *dist = NULL;
    flann_index_t index = NULL;
    struct FLANNParameters fp = relief_knn_exact_params();
    relief_status st = sphere_lattice(cov, pm, sp, out, err);
    size_t m, k;

    if (st != RELIEF_OK)
        return st;
    m = out->pts.n;
    if (m == 0)
        return RELIEF_OK;
    k = m < K ? m : K;
    parent = malloc(m * sizeof *parent);
    out->of = malloc(m * sizeof *out->of);
    idx = malloc(m * k * sizeof *idx);
    dist = malloc(m * k * sizeof *dist);
    if (!parent || !out->of || !idx || !dist) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the sphere's regions");
        goto done;
    }
    {
        float speedup;
        index = flann_build_index_double(out->pts.p, (int)m, 3, &speedup, &fp);
    }
    if (!index || flann_find_nearest_neighbors_index_double(index, out->pts.p, (int)m, idx, dist,
                                                            (int)k, &fp) != 0) {
        st = relief_fail(err, RELIEF_E_INTERNAL, "FLANN could not search the sphere's lattice");
        goto done;
    }
    sphere_link(parent, idx, dist, m, k, link2);
    st = sphere_number(parent, m, out, err);
done:
    if (index)
        flann_free_index_double(index, &fp);
    free(dist);
    free(idx);
    free(parent);
    return st;
}

/* ------------------------------------------------------------- all round */

/* The largest angle (degrees) from a direction round a cylinder's axis to
 * the nearest captured vertex's: half the widest empty arc. */
static double cylinder_gap(const coverage *cov, const relief_domain *pm)
{
    const size_t n = cov->cap->nv;
    double *a = malloc((n ? n : 1) * sizeof *a), widest = 0.0;
    if (!a || n == 0) {
        free(a);
        return 180.0;
    }
    for (size_t v = 0; v < n; ++v) {
        double uv[2];
        relief_domain_coords(pm, cov->proj + 3 * v, uv);
        a[v] = uv[0] / pm->prim.radius;
    }
    qsort(a, n, sizeof *a, relief_cmp_double);
    widest = a[0] + 2.0 * RELIEF_PI - a[n - 1];
    for (size_t v = 1; v < n; ++v)
        widest = fmax(widest, a[v] - a[v - 1]);
    free(a);
    return 0.5 * widest * 180.0 / RELIEF_PI;
}

/* The same from a sphere's centre: over 2 000 Fibonacci directions, the
 * largest angle to the nearest of at most 20 000 captured directions (a
 * stride through the capture's vertices). */
static double sphere_gap(const coverage *cov, const relief_domain *pm)
{
    enum { DIRS = 2000, MAX_V = 20000 };
    const relief_fit_primitive *pr = &pm->prim;
    const size_t nv = cov->cap->nv, stride = nv > MAX_V ? (nv + MAX_V - 1) / MAX_V : 1;
    const double golden = RELIEF_PI * (3.0 - sqrt(5.0));
    double worst = 1.0; /* the smallest best cosine */
    if (nv == 0)
        return 180.0;
    for (int i = 0; i < DIRS; ++i) {
        double z = 1.0 - 2.0 * (i + 0.5) / DIRS, r = sqrt(1.0 - z * z), t = golden * i;
        double d[3] = {r * cos(t), r * sin(t), z}, best = -1.0;
        for (size_t v = 0; v < nv; v += stride) {
            const double *p = cov->proj + 3 * v;
            double q[3] = {p[0] - pr->point[0], p[1] - pr->point[1], p[2] - pr->point[2]};
            double len = sqrt(rm_dot(q, q));
            if (len > 0.0)
                best = fmax(best, rm_dot(q, d) / len);
        }
        worst = fmin(worst, best);
    }
    return acos(fmax(-1.0, fmin(1.0, worst))) * 180.0 / RELIEF_PI;
}

/* ---------------------------------------------------------------- laying */

/* fill auto: a plane's holes (its extent's whole when one is given); a
 * cylinder's or sphere's holes when the capture has some and goes all
 * round it or is a small patch of it, else its whole (a one-sided scan's
 * hidden side, paper 000; and a capture with no enclosed hole, as a cap
 * of a sphere fitted, poorly, as a cylinder round which it wraps). */
static relief_fill auto_fill(const relief_fit_primitive *pr, int extent,
                             const relief_fill_stats *stats)
{
    if (pr->model == RELIEF_FIT_PLANE)
        return extent ? RELIEF_FILL_WHOLE : RELIEF_FILL_HOLES;
    if (extent)
        return RELIEF_FILL_WHOLE;
    if (stats->holes > 0 && (stats->all_round || stats->cover < RELIEF_ONE_SIDED_COVER))
        return RELIEF_FILL_HOLES;
    return RELIEF_FILL_WHOLE;
}

/* Is the region of these n points relief's own hole: covered, most of
 * it, by the capture as scanned (before its folded triangles or spikes
 * were dropped)? */
static int dropped_hole(const coverage *scanned, const double *pts, size_t n, double sp)
{
    size_t in = 0;
    for (size_t i = 0; i < n; ++i)
        in += (size_t)covered(scanned, pts + 3 * i, 0.25 * sp * sp);
    return 2 * in > n;
}

/* Which regions are completed: every one (whole), or those the outline
 * encloses that the filter keeps (holes), and relief's own holes where it
 * dropped what the scan had (scanned, when not NULL). */
static relief_status choose_regions(const regions *rg, relief_fill fill,
                                    const relief_region_filter *f, const coverage *scanned,
                                    double sp, uint8_t *take, relief_fill_stats *stats,
                                    relief_error *err)
{
    size_t *start = NULL, *at = NULL;
    double *pts = NULL;
    relief_status st = RELIEF_OK;
    for (size_t id = 0; id < rg->n; ++id)
        take[id] = fill == RELIEF_FILL_WHOLE || !rg->outside[id];
    if (fill == RELIEF_FILL_WHOLE || !f->keep || rg->n == 0)
        return RELIEF_OK;
    /* The points grouped by region (a counting sort), each group asked. */
    start = calloc(rg->n + 1, sizeof *start);
    at = malloc(rg->n * sizeof *at);
    pts = malloc((rg->pts.n ? rg->pts.n : 1) * 3 * sizeof *pts);
    if (!start || !at || !pts) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the regions' points");
        goto done;
    }
    for (size_t i = 0; i < rg->pts.n; ++i)
        ++start[rg->of[i] + 1];
    for (size_t id = 0; id < rg->n; ++id)
        at[id] = start[id + 1] += start[id];
    for (size_t id = 0; id < rg->n; ++id)
        at[id] = start[id];
    for (size_t i = 0; i < rg->pts.n; ++i)
        memcpy(pts + 3 * at[rg->of[i]]++, rg->pts.p + 3 * i, 3 * sizeof *pts);
    for (size_t id = 0; id < rg->n; ++id) {
        const double *p = pts + 3 * start[id];
        const size_t n = start[id + 1] - start[id];
        if (!take[id])
            continue;
        if (scanned && dropped_hole(scanned, p, n, sp)) {
            ++stats->dropped_holes;
        } else if (!f->keep(f->ctx, p, n)) {
            take[id] = 0;
            ++stats->holes_left;
            stats->holes_left_points += rg->size[id];
        }
    }
done:
    free(start);
    free(at);
    free(pts);
    return st;
}

/* The regions of the primitive's lattice: a sphere's Fibonacci lattice; a
 * cylinder's whole turn over the extent's z0..z1 or the capture's axial
 * span; a plane's extent u0,v0,u1,v1 or the capture's (u, v) box grown by
 * a spacing each side. extent: whether the params' extent applies. */
static relief_status primitive_regions(const coverage *cov, const relief_domain *param,
                                       double spacing, const relief_params *params, int extent,
                                       regions *rg, relief_error *err)
{
    const relief_fit_primitive *pr = &param->prim;
    double lo[2] = {DBL_MAX, DBL_MAX}, hi[2] = {-DBL_MAX, -DBL_MAX};
    if (pr->model == RELIEF_FIT_SPHERE)
        return sphere_regions(cov, param, spacing, rg, err);
    for (size_t v = 0; v < cov->cap->nv; ++v) {
        double uv[2];
        relief_domain_coords(param, cov->proj + 3 * v, uv);
        for (int k = 0; k < 2; ++k) {
            lo[k] = fmin(lo[k], uv[k]);
            hi[k] = fmax(hi[k], uv[k]);
        }
    }
    if (extent && params->n_extent != (pr->model == RELIEF_FIT_CYLINDER ? 2 : 4))
        return pr->model == RELIEF_FIT_CYLINDER
                   ? relief_fail(err, RELIEF_E_USAGE,
                                 "an extent for a cylinder takes 2 values z0,z1")
                   : relief_fail(err, RELIEF_E_USAGE,
                                 "an extent for a plane takes 4 values u0,v0,u1,v1");
    if (pr->model == RELIEF_FIT_CYLINDER)
        return lattice_regions(cov, param, spacing, 0.0, 2.0 * RELIEF_PI * pr->radius,
                               extent ? params->extent[0] : lo[1],
                               extent ? params->extent[1] : hi[1], 1, rg, err);
    if (extent)
        return lattice_regions(cov, param, spacing, params->extent[0], params->extent[2],
                               params->extent[1], params->extent[3], 0, rg, err);
    return lattice_regions(cov, param, spacing, lo[0] - spacing, hi[0] + spacing,
                           lo[1] - spacing, hi[1] + spacing, 0, rg, err);
}

/* The regions' counts into stats: holes and points inside the outline and
 * outside it, the capture's cover of the lattice and, round a cylinder or
 * a sphere, the widest gap (degrees) and whether it goes all round. */
static void region_stats(const regions *rg, const coverage *cov, const relief_domain *param,
                         relief_fill_stats *stats)
{
    const relief_fit_primitive *pr = &param->prim;
    for (size_t id = 0; id < rg->n; ++id) {
        if (rg->outside[id]) {
            stats->outside_points += rg->size[id];
        } else {
            ++stats->holes;
            stats->hole_points += rg->size[id];
        }
    }
    stats->cover = (double)rg->covered / (double)(rg->covered + rg->pts.n);
    if (pr->model != RELIEF_FIT_PLANE) {
        stats->round_gap = pr->model == RELIEF_FIT_SPHERE ? sphere_gap(cov, param)
                                                          : cylinder_gap(cov, param);
        stats->all_round = stats->round_gap <= RELIEF_ALL_ROUND_DEGREES;
    }
}

/* The points of the regions taken (take: per region) into out, and with
 * fill holes those outside the outline that the filter's keep_point asks
 * for. */
static relief_status push_taken(const regions *rg, const uint8_t *take, relief_fill fill,
                                const relief_smooth_options *opts, relief_target_list *out,
                                relief_fill_stats *stats, relief_error *err)
{
    for (size_t i = 0; i < rg->pts.n; ++i) {
        const double *p = rg->pts.p + 3 * i;
        int t = take[rg->of[i]];
        if (!t && fill == RELIEF_FILL_HOLES && rg->outside[rg->of[i]] && opts->holes.keep_point &&
            opts->holes.keep_point(opts->holes.ctx, p)) {
            t = 1;
            ++stats->outside_taken;
        }
        if (t && !push_point(out, p))
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate targets");
    }
    return RELIEF_OK;
}

relief_status relief_targets_lay(const relief_mesh *capture, const relief_mesh *scanned,
                                 const relief_domain *param, double spacing,
                                 const relief_params *params,
                                 const relief_smooth_options *opts,
                                 relief_target_list *out, relief_fill_stats *stats,
                                 relief_error *err)
{
    const relief_fit_primitive *pr = &param->prim;
    relief_fill fill = opts->fill;
    coverage cov, scov;
    regions rg;
    uint8_t *take = NULL;
    relief_status st;
    int extent = params->has_extent && pr->model != RELIEF_FIT_SPHERE;

    memset(&rg, 0, sizeof rg);
    memset(&scov, 0, sizeof scov);
    memset(stats, 0, sizeof *stats);
    st = coverage_build(&cov, capture, pr, err);
    if (st != RELIEF_OK)
        goto done;
    st = primitive_regions(&cov, param, spacing, params, extent, &rg, err);
    if (st != RELIEF_OK)
        goto done;

    region_stats(&rg, &cov, param, stats);
    if (fill == RELIEF_FILL_AUTO && pr->model != RELIEF_FIT_PLANE && !extent &&
        stats->all_round && stats->holes == 0 && rg.pts.n > 0 && stats->cover >= 0.75) {
        /* Issue 61: a band all round a cylinder whose cut merged with its
         * border has no enclosed hole; its whole would be the primitive
         * beyond the capture, not a hidden side. (A capture that covers
         * under 3/4 of its extent, as a sphere's dimples round a cylinder
         * fitted poorly, has a side to complete.) */
        st = relief_fail_param(err, RELIEF_E_RANGE, "fill", "the capture goes all round the "
                               "%s and encloses no hole: fill auto would complete the %s beyond "
                               "it (%zu targets, %.0f%% of the captured extent uncovered); a "
                               "cut that reaches the capture's border is filled with "
                               "hole_ball (--hole-mask ball:X,Y,Z,R), the whole with fill "
                               "whole (--fill whole)",
                               relief_fit_model_name(pr->model),
                               relief_fit_model_name(pr->model), rg.pts.n,
                               100.0 * (1.0 - stats->cover));
        goto done;
    }
    if (fill == RELIEF_FILL_AUTO)
        fill = auto_fill(pr, extent, stats);
    stats->region = fill;
    take = malloc(rg.n ? rg.n : 1);
    if (!take) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the regions");
        goto done;
    }
    if (pr->model != RELIEF_FIT_PLANE || opts->holes.on_plane) {
        const int dropped = scanned && scanned != capture && fill == RELIEF_FILL_HOLES &&
                            opts->holes.keep;
        if (dropped)
            st = coverage_build(&scov, scanned, pr, err);
        if (st == RELIEF_OK)
            st = choose_regions(&rg, fill, &opts->holes, dropped ? &scov : NULL, spacing,
                                take, stats, err);
    } else {
        st = choose_regions(&rg, fill, &(relief_region_filter){NULL, NULL, NULL, 0}, NULL, spacing,
                            take, stats, err);
    }
    if (st == RELIEF_OK)
        st = push_taken(&rg, take, fill, opts, out, stats, err);
done:
    free(take);
    regions_free(&rg);
    coverage_free(&cov);
    coverage_free(&scov);
    return st;
}
