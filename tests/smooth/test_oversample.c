/* relief_oversample on small grids with known answers: counts, geometry
 * (midpoint: on the surface, area, orientation, shared midpoints; butterfly:
 * interpolation, flatness, cubic reproduction, boundary fallback),
 * attributes, colour transfer, determinism and errors. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "base/vec3.h"
#include "mesh/mesh.h"
#include "smooth/oversample.h"

/* nx x ny grid of spacing h in the xy plane (z = bump * sin cos when bump
 * != 0), two triangles per cell with alternating diagonals, counter-
 * clockwise seen from +z. Labels: 1 for x > half the width, else 0.
 * Normals: +z (only exact for bump = 0, enough for the propagation). */
static relief_mesh *grid(int nx, int ny, double h, double bump, unsigned attrs)
{
    relief_mesh *m = NULL;
    size_t t = 0;
    if (relief_mesh_create((size_t)nx * ny, 2 * (size_t)(nx - 1) * (ny - 1), attrs,
                           &m, NULL) != RELIEF_OK) {
        fprintf(stderr, "cannot create a grid\n");
        exit(2);
    }
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            size_t v = (size_t)j * nx + i;
            double x = i * h, y = j * h;
            m->pos[3 * v] = x;
            m->pos[3 * v + 1] = y;
            m->pos[3 * v + 2] = bump * sin(3.0 * x) * cos(2.0 * y + 0.3);
            if (m->nrm)
                m->nrm[3 * v + 2] = 1.0;
            if (m->label)
                m->label[v] = 2 * i > nx - 1;
            if (m->col) {
                m->col[3 * v] = (float)(x / ((nx - 1) * h));
                m->col[3 * v + 1] = (float)(y / ((ny - 1) * h));
                m->col[3 * v + 2] = 0.5f;
            }
        }
    for (int j = 0; j + 1 < ny; ++j)
        for (int i = 0; i + 1 < nx; ++i) {
            uint32_t v00 = (uint32_t)(j * nx + i), v10 = v00 + 1;
            uint32_t v01 = v00 + (uint32_t)nx, v11 = v01 + 1;
            uint32_t q[6];
            if ((i + j) % 2) {
                uint32_t a[6] = {v00, v10, v11, v00, v11, v01};
                memcpy(q, a, sizeof q);
            } else {
                uint32_t a[6] = {v00, v10, v01, v10, v11, v01};
                memcpy(q, a, sizeof q);
            }
            memcpy(m->tri + 3 * t, q, sizeof q);
            t += 2;
        }
    return m;
}

static size_t grid_edges(size_t nx, size_t ny)
{
    return (nx - 1) * ny + nx * (ny - 1) + (nx - 1) * (ny - 1);
}

/* Unnormalised normal (twice the area vector) of triangle t of m. */
static void tri_normal(const relief_mesh *m, size_t t, double *n)
{
    const double *a = m->pos + 3 * (size_t)m->tri[3 * t];
    const double *b = m->pos + 3 * (size_t)m->tri[3 * t + 1];
    const double *c = m->pos + 3 * (size_t)m->tri[3 * t + 2];
    double ab[3], ac[3];
    sub3(b, a, ab);
    sub3(c, a, ac);
    cross3(ab, ac, n);
}

/* Distance from p to triangle abc (closest point by Voronoi regions,
 * Ericson, Real-Time Collision Detection 5.1.5). */
static double point_triangle_distance(const double *p, const double *a,
                                      const double *b, const double *c)
{
    double ab[3], ac[3], ap[3], bp[3], cp[3], q[3], d[3];
    double d1, d2, d3, d4, d5, d6, va, vb, vc, v, w, den;
    sub3(b, a, ab);
    sub3(c, a, ac);
    sub3(p, a, ap);
    d1 = dot3(ab, ap);
    d2 = dot3(ac, ap);
    if (d1 <= 0 && d2 <= 0) {
        memcpy(q, a, sizeof q);
        goto out;
    }
    sub3(p, b, bp);
    d3 = dot3(ab, bp);
    d4 = dot3(ac, bp);
    if (d3 >= 0 && d4 <= d3) {
        memcpy(q, b, sizeof q);
        goto out;
    }
    vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        v = d1 / (d1 - d3);
        for (int i = 0; i < 3; ++i)
            q[i] = a[i] + v * ab[i];
        goto out;
    }
    sub3(p, c, cp);
    d5 = dot3(ab, cp);
    d6 = dot3(ac, cp);
    if (d6 >= 0 && d5 <= d6) {
        memcpy(q, c, sizeof q);
        goto out;
    }
    vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        w = d2 / (d2 - d6);
        for (int i = 0; i < 3; ++i)
            q[i] = a[i] + w * ac[i];
        goto out;
    }
    va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (int i = 0; i < 3; ++i)
            q[i] = b[i] + w * (c[i] - b[i]);
        goto out;
    }
    den = 1.0 / (va + vb + vc);
    v = vb * den;
    w = vc * den;
    for (int i = 0; i < 3; ++i)
        q[i] = a[i] + ab[i] * v + ac[i] * w;
out:
    sub3(p, q, d);
    return sqrt(dot3(d, d));
}

static int pos_cmp(const void *x, const void *y)
{
    const double *a = x, *b = y;
    for (int i = 0; i < 3; ++i)
        if (a[i] != b[i])
            return a[i] < b[i] ? -1 : 1;
    return 0;
}

/* The papers' coplanar midpoints, for the checks that need a new vertex
 * exactly halfway along its edge. */
static const relief_oversample_params MIDPOINT = {RELIEF_OVERSAMPLE_MIDPOINT, 6, 0.0};

static relief_mesh *oversample_or_die(const relief_mesh *in, int passes,
                                      const relief_oversample_params *p)
{
    relief_mesh *out = NULL;
    relief_error err = {0};
    relief_status st = relief_oversample(in, passes, p, &out, &err);
    if (st != RELIEF_OK) {
        fprintf(stderr, "relief_oversample failed: %s: %s\n",
                relief_status_name(st), err.message);
        exit(1);
    }
    return out;
}

static int same_mesh(const relief_mesh *a, const relief_mesh *b)
{
    if (a->nv != b->nv || a->nt != b->nt || a->attrs != b->attrs)
        return 0;
    if (memcmp(a->pos, b->pos, a->nv * 3 * sizeof *a->pos) ||
        memcmp(a->tri, b->tri, a->nt * 3 * sizeof *a->tri))
        return 0;
    if ((!a->col) != (!b->col) || (!a->nrm) != (!b->nrm) ||
        (!a->label) != (!b->label))
        return 0;
    if (a->col && memcmp(a->col, b->col, a->nv * 3 * sizeof *a->col))
        return 0;
    if (a->nrm && memcmp(a->nrm, b->nrm, a->nv * 3 * sizeof *a->nrm))
        return 0;
    if (a->label && memcmp(a->label, b->label, a->nv))
        return 0;
    return 1;
}

static void test_counts(void)
{
    const int nx = 5, ny = 4;
    const unsigned attrs = RELIEF_MESH_NORMALS | RELIEF_MESH_LABELS;
    relief_mesh *in = grid(nx, ny, 0.25, 0.0, attrs);
    const size_t V = in->nv, T = in->nt, E = grid_edges(nx, ny);
    relief_mesh *o1 = oversample_or_die(in, 1, &MIDPOINT);
    relief_mesh *o2 = oversample_or_die(in, 2, &MIDPOINT);
    relief_mesh *o0 = oversample_or_die(in, 0, NULL);
    /* After one pass E' = 2 E + 3 T: each edge splits in two and each
     * triangle adds 3 inner edges. */
    const size_t E1 = 2 * E + 3 * T;

    CHECK(o1->nv == V + E, "1 pass: %zu vertices, expected V + E = %zu", o1->nv, V + E);
    CHECK(o1->nt == 4 * T, "1 pass: %zu triangles, expected %zu", o1->nt, 4 * T);
    CHECK(o2->nv == V + E + E1, "2 passes: %zu vertices, expected %zu", o2->nv,
          V + E + E1);
    CHECK(o2->nt == 16 * T, "2 passes: %zu triangles, expected %zu", o2->nt, 16 * T);
    printf("counts: V %zu E %zu T %zu -> 1 pass V %zu T %zu -> 2 passes V %zu T %zu\n",
           V, E, T, o1->nv, o1->nt, o2->nv, o2->nt);
    CHECK(same_mesh(in, o0), "0 passes is not an exact copy");
    CHECK(o1->attrs == attrs && o2->attrs == attrs, "attributes changed: 0x%x 0x%x",
          o1->attrs, o2->attrs);
    CHECK(!memcmp(o1->pos, in->pos, V * 3 * sizeof(double)) &&
              !memcmp(o2->pos, in->pos, V * 3 * sizeof(double)),
          "original vertices moved or were renumbered");
    CHECK(!memcmp(o1->label, in->label, V) && !memcmp(o1->nrm, in->nrm, V * 3 * sizeof(double)),
          "original labels or normals changed");

    /* Layout: triangle 0 of the grid is (v00, v10, v01) = (0, 1, nx); its
     * edges are the first three, so its children use vertices V, V+1, V+2
     * in the documented order. */
    {
        const uint32_t a = 0, b = 1, c = (uint32_t)nx;
        const uint32_t ab = (uint32_t)V, bc = ab + 1, ca = ab + 2;
        const uint32_t want[12] = {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca};
        CHECK(!memcmp(o1->tri, want, sizeof want), "children of triangle 0 are "
              "(%u %u %u) (%u %u %u) (%u %u %u) (%u %u %u)",
              o1->tri[0], o1->tri[1], o1->tri[2], o1->tri[3], o1->tri[4], o1->tri[5],
              o1->tri[6], o1->tri[7], o1->tri[8], o1->tri[9], o1->tri[10], o1->tri[11]);
    }

    /* Normals: the mean of two +z normals is +z, unit. */
    for (size_t v = V; v < o1->nv; ++v) {
        const double *n = o1->nrm + 3 * v;
        CHECK(fabs(n[0]) < 1e-15 && fabs(n[1]) < 1e-15 && fabs(n[2] - 1.0) < 1e-15,
              "vertex %zu normal (%g %g %g), expected (0 0 1)", v, n[0], n[1], n[2]);
    }
    {
        /* Labels 1 only when both endpoints are 1, positions the exact
         * midpoints, read through the documented child layout. */
        size_t bad = 0;
        for (size_t t = 0; t < in->nt; ++t)
            for (int c = 0; c < 3; ++c) {
                uint32_t a = in->tri[3 * t + c], b = in->tri[3 * t + (c + 1) % 3];
                /* child 3 of t is (ab, bc, ca): corner c is edge c's midpoint */
                uint32_t m = o1->tri[3 * (4 * t + 3) + c];
                uint8_t want = in->label[a] == in->label[b] ? in->label[a] : 0;
                bad += o1->label[m] != want;
                for (int i = 0; i < 3; ++i)
                    bad += o1->pos[3 * (size_t)m + i] !=
                           0.5 * (in->pos[3 * (size_t)a + i] + in->pos[3 * (size_t)b + i]);
            }
        CHECK(bad == 0, "%zu midpoint labels or positions differ from the edge rule", bad);
    }
    relief_mesh_destroy(o0);
    relief_mesh_destroy(o1);
    relief_mesh_destroy(o2);
    relief_mesh_destroy(in);
}

static void test_geometry(void)
{
    relief_mesh *in = grid(7, 6, 0.2, 0.3, 0);
    for (int passes = 1; passes <= 2; ++passes) {
        relief_mesh *o = oversample_or_die(in, passes, &MIDPOINT);
        const size_t fan = (size_t)1 << (2 * passes); /* children per input triangle */
        double lo[3] = {DBL_MAX, DBL_MAX, DBL_MAX}, hi[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX};
        double diag, dmax = 0.0, area_in = 0.0, area_out = 0.0, parent_err = 0.0;
        double cos_min = 1.0;
        size_t dup = 0;
        double *sorted;

        for (size_t v = 0; v < in->nv; ++v)
            for (int i = 0; i < 3; ++i) {
                lo[i] = fmin(lo[i], in->pos[3 * v + i]);
                hi[i] = fmax(hi[i], in->pos[3 * v + i]);
            }
        diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                    (hi[2] - lo[2]) * (hi[2] - lo[2]));

        /* Every output vertex on the original surface. */
        for (size_t v = 0; v < o->nv; ++v) {
            double best = DBL_MAX;
            for (size_t t = 0; t < in->nt; ++t) {
                const uint32_t *f = in->tri + 3 * t;
                double d = point_triangle_distance(o->pos + 3 * v, in->pos + 3 * (size_t)f[0],
                                                   in->pos + 3 * (size_t)f[1],
                                                   in->pos + 3 * (size_t)f[2]);
                if (d < best)
                    best = d;
            }
            if (best > dmax)
                dmax = best;
        }
        CHECK(dmax < 1e-12 * diag, "%d passes: a vertex lies %g off the original "
              "surface (diagonal %g)", passes, dmax, diag);

        /* Area per parent and in total; children coplanar with their
         * parent and wound the same way. */
        for (size_t t = 0; t < in->nt; ++t) {
            double np[3], lp, sum = 0.0;
            tri_normal(in, t, np);
            lp = sqrt(dot3(np, np));
            area_in += 0.5 * lp;
            for (size_t j = fan * t; j < fan * (t + 1); ++j) {
                double nc[3], lc;
                tri_normal(o, j, nc);
                lc = sqrt(dot3(nc, nc));
                sum += 0.5 * lc;
                if (dot3(nc, np) / (lc * lp) < cos_min)
                    cos_min = dot3(nc, np) / (lc * lp);
            }
            area_out += sum;
            if (fabs(sum - 0.5 * lp) / (0.5 * lp) > parent_err)
                parent_err = fabs(sum - 0.5 * lp) / (0.5 * lp);
        }
        CHECK(fabs(area_out - area_in) < 1e-12 * area_in,
              "%d passes: area %.17g, was %.17g", passes, area_out, area_in);
        CHECK(parent_err < 1e-12, "%d passes: children's area differs from the "
              "parent's by %g relative", passes, parent_err);
        CHECK(cos_min > 1.0 - 1e-12, "%d passes: a child's normal is %g rad off "
              "its parent's", passes, acos(fmin(1.0, cos_min)));

        /* Shared midpoints: no two output vertices at the same place. */
        sorted = malloc(o->nv * 3 * sizeof *sorted);
        if (!sorted)
            exit(2);
        memcpy(sorted, o->pos, o->nv * 3 * sizeof *sorted);
        qsort(sorted, o->nv, 3 * sizeof *sorted, pos_cmp);
        for (size_t v = 1; v < o->nv; ++v)
            dup += pos_cmp(sorted + 3 * (v - 1), sorted + 3 * v) == 0;
        CHECK(dup == 0, "%d passes: %zu duplicate vertices", passes, dup);
        free(sorted);

        printf("geometry, %d pass(es): %zu -> %zu vertices; max distance to the "
               "input surface %.3g (diagonal %.3g); area %.17g vs %.17g "
               "(rel %.2g); max per-parent area rel error %.2g; min cos(child, "
               "parent normal) %.17g; duplicates %zu\n",
               passes, in->nv, o->nv, dmax, diag, area_out, area_in,
               fabs(area_out - area_in) / area_in, parent_err, cos_min, dup);
        relief_mesh_destroy(o);
    }
    relief_mesh_destroy(in);
}

/* Largest distance from a vertex to the boundary of the nx x ny grid. */
static double boundary_distance(const double *p, int nx, int ny, double h)
{
    double dx = fmin(p[0], (nx - 1) * h - p[0]);
    double dy = fmin(p[1], (ny - 1) * h - p[1]);
    return fmin(dx, dy);
}

static void test_colour(void)
{
    const int nx = 11, ny = 9;
    const double h = 0.1;
    relief_mesh *in = grid(nx, ny, h, 0.0, RELIEF_MESH_COLOURS);

    /* Constant colour stays exactly constant: a normalised sum of one value
     * is that value within a few double ulps, which rounds back to the same
     * float. */
    {
        relief_mesh *o;
        size_t bad = 0;
        for (size_t v = 0; v < in->nv; ++v) {
            in->col[3 * v] = 0.3f;
            in->col[3 * v + 1] = 0.6f;
            in->col[3 * v + 2] = 0.9f;
        }
        o = oversample_or_die(in, 2, NULL);
        for (size_t v = 0; v < o->nv; ++v)
            bad += o->col[3 * v] != 0.3f || o->col[3 * v + 1] != 0.6f ||
                   o->col[3 * v + 2] != 0.9f;
        CHECK(bad == 0, "%zu vertices lost the constant colour", bad);
        relief_mesh_destroy(o);
        relief_mesh_destroy(in);
        in = grid(nx, ny, h, 0.0, RELIEF_MESH_COLOURS);
    }

    /* Linear ramp: red = x / 1, green = y / 0.8. For a linear colour the
     * weighted average is the colour at the weighted centroid of the
     * neighbours, so the error is slope x |centroid - vertex|. Default
     * sigma = h / 2, so a neighbour d away weighs exp(-2 (d^2 - d0^2) / h^2)
     * relative to the nearest (at d0).
     * - One pass, inside (>= 3 h from the border, beyond the <= 1.6 h the
     *   6..12 neighbours reach): every new vertex is an edge midpoint of the
     *   grid, about which the lattice of original vertices is
     *   point-symmetric; ties are included, so the neighbourhood and its
     *   weights are symmetric and the centroid is the vertex itself: exact
     *   up to float rounding (tolerance 1e-6).
     * - One pass, border: the nearest pair (or quad) is still symmetric;
     *   the worst case is a corner edge's midpoint (h/2, 0): (0, h) and
     *   (h, h) weigh e^-2, (2h, 0) e^-4 and (2h, h) e^-6, so the centroid
     *   moves by (2 e^-2 + e^-6) h / (2 + 2 e^-2 + e^-4 + e^-6) = 0.119 h;
     *   tolerance 0.125 h x slope.
     * - Two passes: quarter points, about which the lattice is not
     *   symmetric; the colour is a convex combination of neighbours at most
     *   ~1.8 h away (the k = 6 nearest of a corner's midpoint), so the
     *   tolerance is the plain bound 2 h x slope. */
    for (int passes = 1; passes <= 2; ++passes) {
        relief_mesh *o = oversample_or_die(in, passes, &MIDPOINT);
        double e_in = 0.0, e_all = 0.0;
        size_t n_in = 0;
        const double slope_x = 1.0 / ((nx - 1) * h), slope_y = 1.0 / ((ny - 1) * h);
        const double bound = (passes == 1 ? 0.125 : 2.0) * h * fmax(slope_x, slope_y);
        int range_ok = 1;
        for (size_t v = in->nv; v < o->nv; ++v) {
            const double *p = o->pos + 3 * v;
            const float *c = o->col + 3 * v;
            double er = fabs(c[0] - p[0] * slope_x), eg = fabs(c[1] - p[1] * slope_y);
            double e = fmax(er, eg);
            if (passes == 1 && boundary_distance(p, nx, ny, h) >= 3 * h - 1e-9)
            {
                e_in = fmax(e_in, e);
                ++n_in;
            }
            e_all = fmax(e_all, e);
            range_ok &= c[0] >= 0.0f && c[0] <= 1.0f && c[1] >= 0.0f && c[1] <= 1.0f &&
                        c[2] == 0.5f;
        }
        if (passes == 1)
            CHECK(n_in > 0 && e_in < 1e-6, "1 pass: ramp error %g on %zu vertices "
                  "inside (tolerance 1e-6)", e_in, n_in);
        CHECK(e_all <= bound, "%d passes: ramp error %g, bound %g", passes, e_all, bound);
        CHECK(range_ok, "%d passes: colour outside [0, 1] or blue not constant", passes);
        if (passes == 1)
            printf("colour ramp, 1 pass: max |error| %.3g on the %zu new vertices "
                   ">= 3 h from the border (tolerance 1e-6), %.3g on all %zu "
                   "(tolerance 0.125 h x slope = %.3g)\n",
                   e_in, n_in, e_all, o->nv - in->nv, bound);
        else
            printf("colour ramp, 2 passes: max |error| %.3g on all %zu new "
                   "vertices (tolerance 2 h x slope = %.3g)\n",
                   e_all, o->nv - in->nv, bound);
        relief_mesh_destroy(o);
    }

    /* sigma = 0 means half the median edge length: here h (the axis edges
     * outnumber the diagonals), so sigma = h / 2 given explicitly must give
     * the same colours up to the rounding of the measured median. */
    {
        relief_oversample_params p = relief_oversample_params_default();
        relief_mesh *a, *b;
        double d = 0.0;
        CHECK(p.k == 6 && p.sigma == 0.0, "defaults k %d sigma %g", p.k, p.sigma);
        a = oversample_or_die(in, 1, NULL);
        p.sigma = 0.5 * h;
        b = oversample_or_die(in, 1, &p);
        for (size_t i = 0; i < 3 * a->nv; ++i)
            d = fmax(d, fabs(a->col[i] - b->col[i]));
        CHECK(d < 1e-6, "sigma 0 vs h/2 differ by %g", d);
        /* A much wider sigma changes the border colours (check the
         * parameter is used at all). */
        relief_mesh_destroy(b);
        p.sigma = 10.0 * h;
        b = oversample_or_die(in, 1, &p);
        d = 0.0;
        for (size_t i = 0; i < 3 * a->nv; ++i)
            d = fmax(d, fabs(a->col[i] - b->col[i]));
        CHECK(d > 1e-4, "sigma 10 h gives the same colours as h/2 (%g)", d);
        relief_mesh_destroy(a);
        relief_mesh_destroy(b);
    }
    relief_mesh_destroy(in);

    /* k larger than the vertex count: one triangle, k = 6 and k = 256 use
     * all 3 vertices. */
    {
        relief_mesh *t = grid(2, 2, 1.0, 0.0, RELIEF_MESH_COLOURS), *a, *b;
        relief_oversample_params p = relief_oversample_params_default();
        t->nt = 1;
        a = oversample_or_die(t, 1, &p);
        p.k = RELIEF_OVERSAMPLE_K_MAX;
        b = oversample_or_die(t, 1, &p);
        CHECK(a->nv == 4 + 3 && a->nt == 4, "one triangle gave %zu vertices %zu "
              "triangles", a->nv, a->nt);
        CHECK(same_mesh(a, b), "k = 6 and k = 256 differ on 4 vertices");
        relief_mesh_destroy(a);
        relief_mesh_destroy(b);
        relief_mesh_destroy(t);
    }
}

/* A cubic height field, which the butterfly scheme reproduces exactly on a
 * regular three-direction grid. */
static double cubic(double x, double y)
{
    return 0.3 * x * x * x - 0.2 * x * x * y + 0.1 * y * y + 0.05 * x * y - 0.1 * y;
}

static void test_butterfly(void)
{
    const int nx = 9, ny = 8;
    const double h = 0.125;
    const relief_oversample_params mid = MIDPOINT;
    relief_mesh *flat = grid(nx, ny, h, 0.0, 0), *bump = grid(nx, ny, h, 0.2, 0);
    relief_mesh *reg = grid(nx, ny, h, 0.0, 0), *o = NULL, *om = NULL;
    double zmax = 0.0, moved = 0.0, err_b = 0.0, err_m = 0.0, cub_b = 0.0, cub_m = 0.0;
    double bnd = 0.0;
    size_t n_inner = 0, n_bnd = 0;

    CHECK(relief_oversample_params_default().scheme == RELIEF_OVERSAMPLE_BUTTERFLY,
          "the default scheme is not butterfly");

    /* Interpolating: the original vertices do not move; a plane stays flat
     * (the stencil's weights sum to 1) even with alternating diagonals. */
    o = oversample_or_die(flat, 1, NULL);
    for (size_t v = 0; v < flat->nv; ++v)
        for (int i = 0; i < 3; ++i)
            moved = fmax(moved, fabs(o->pos[3 * v + i] - flat->pos[3 * v + i]));
    for (size_t v = 0; v < o->nv; ++v)
        zmax = fmax(zmax, fabs(o->pos[3 * v + 2]));
    CHECK(moved == 0.0, "an original vertex moved by %g", moved);
    CHECK(zmax < 1e-15, "a flat grid left the plane by %g", zmax);
    relief_mesh_destroy(o);

    /* On a smooth bump the new vertices land much nearer the surface than
     * the chords' midpoints, even on this grid of valences 4 and 8 (the
     * extraordinary stencils); edges on the boundary keep the midpoint. */
    o = oversample_or_die(bump, 1, NULL);
    om = oversample_or_die(bump, 1, &mid);
    for (size_t v = bump->nv; v < o->nv; ++v) {
        const double *p = o->pos + 3 * v, *q = om->pos + 3 * v;
        double zb = 0.2 * sin(3.0 * p[0]) * cos(2.0 * p[1] + 0.3);
        double zm = 0.2 * sin(3.0 * q[0]) * cos(2.0 * q[1] + 0.3);
        if (boundary_distance(q, nx, ny, h) < 1e-12) {
            for (int i = 0; i < 3; ++i)
                bnd = fmax(bnd, fabs(p[i] - q[i]));
            ++n_bnd;
        } else if (boundary_distance(q, nx, ny, h) > 1.5 * h) {
            err_b += fabs(p[2] - zb);
            err_m += fabs(q[2] - zm);
            ++n_inner;
        }
    }
    CHECK(n_bnd == 2 * (size_t)(nx - 1 + ny - 1), "%zu boundary edges", n_bnd);
    CHECK(bnd == 0.0, "a boundary edge's new vertex is %g off its midpoint", bnd);
    err_b /= (double)(n_inner ? n_inner : 1);
    err_m /= (double)(n_inner ? n_inner : 1);
    CHECK(n_inner > 0 && err_b < err_m / 3.0,
          "butterfly mean error %g is not 3x below the midpoints' %g (%zu inner edges)",
          err_b, err_m, n_inner);
    relief_mesh_destroy(o);
    relief_mesh_destroy(om);

    /* Regular three-direction grid (every cell split the same way): the
     * stencil is symmetric, so a new vertex sits above its edge's midpoint,
     * and a cubic height field is reproduced exactly away from the
     * boundary. */
    for (size_t t = 0; t < reg->nt; t += 2) {
        size_t cell = t / 2, i = cell % (size_t)(nx - 1), j = cell / (size_t)(nx - 1);
        uint32_t v00 = (uint32_t)(j * (size_t)nx + i), v10 = v00 + 1;
        uint32_t v01 = v00 + (uint32_t)nx, v11 = v01 + 1;
        uint32_t q[6] = {v00, v10, v11, v00, v11, v01};
        memcpy(reg->tri + 3 * t, q, sizeof q);
    }
    for (size_t v = 0; v < reg->nv; ++v)
        reg->pos[3 * v + 2] = cubic(reg->pos[3 * v], reg->pos[3 * v + 1]);
    o = oversample_or_die(reg, 1, NULL);
    om = oversample_or_die(reg, 1, &mid);
    n_inner = 0;
    for (size_t v = reg->nv; v < o->nv; ++v) {
        const double *p = o->pos + 3 * v, *q = om->pos + 3 * v;
        if (boundary_distance(q, nx, ny, h) <= 1.5 * h)
            continue;
        ++n_inner;
        cub_b = fmax(cub_b, fabs(p[0] - q[0]) + fabs(p[1] - q[1]) +
                                fabs(p[2] - cubic(q[0], q[1])));
        cub_m = fmax(cub_m, fabs(q[2] - cubic(q[0], q[1])));
    }
    CHECK(n_inner > 0 && cub_b < 1e-14, "cubic: butterfly error %g (%zu inner edges)", cub_b,
          n_inner);
    CHECK(cub_m > 1e-4, "cubic: the midpoints' error %g is not visible", cub_m);
    /* A spike (one vertex 20 spacings up) throws the stencils of the edges
     * around it far off; those keep their midpoint, so no new vertex moves
     * more than half its edge's length off the midpoint. A new vertex's
     * edge: children 4t and 4t + 1 of parent t = (a, b, c) are (a, ab, ca)
     * and (ab, b, bc) (oversample.h). */
    {
        relief_mesh *spike = grid(nx, ny, h, 0.0, 0), *os = NULL;
        const size_t apex = (size_t)(ny / 2) * (size_t)nx + (size_t)(nx / 2);
        double worst = 0.0;
        spike->pos[3 * apex + 2] = 20.0 * h;
        os = oversample_or_die(spike, 1, NULL);
        for (size_t t = 0; t < spike->nt; ++t) {
            const uint32_t *f = spike->tri + 3 * t, *c = os->tri + 12 * t;
            const uint32_t nv_edge[3] = {c[1], c[5], c[2]}; /* ab, bc, ca */
            for (int e = 0; e < 3; ++e) {
                const double *pa = spike->pos + 3 * (size_t)f[e];
                const double *pb = spike->pos + 3 * (size_t)f[(e + 1) % 3];
                const double *p = os->pos + 3 * (size_t)nv_edge[e];
                double move2 = 0.0, len2 = 0.0;
                for (int i = 0; i < 3; ++i) {
                    const double dm = p[i] - 0.5 * (pa[i] + pb[i]), de = pa[i] - pb[i];
                    move2 += dm * dm;
                    len2 += de * de;
                }
                worst = fmax(worst, sqrt(move2 / len2));
            }
        }
        CHECK(worst <= 0.5 + 1e-12, "spike: a new vertex moved %.3g of its edge off the "
              "midpoint", worst);
        printf("spike: largest move off a midpoint %.3g of the edge\n", worst);
        relief_mesh_destroy(os);
        relief_mesh_destroy(spike);
    }
    printf("butterfly: originals moved %g, flat grid |z| <= %g, bump mean error %.3g vs "
           "midpoint %.3g (%zu inner edges), %zu boundary edges at their midpoints, "
           "cubic max error %.3g vs midpoint %.3g\n",
           moved, zmax, err_b, err_m, n_inner, n_bnd, cub_b, cub_m);
    relief_mesh_destroy(o);
    relief_mesh_destroy(om);
    relief_mesh_destroy(flat);
    relief_mesh_destroy(bump);
    relief_mesh_destroy(reg);
}

static void test_determinism(void)
{
    relief_mesh *in = grid(9, 8, 0.125, 0.2,
                           RELIEF_MESH_COLOURS | RELIEF_MESH_NORMALS | RELIEF_MESH_LABELS);
    relief_mesh *a = oversample_or_die(in, 2, NULL);
    relief_mesh *b = oversample_or_die(in, 2, NULL);
    CHECK(same_mesh(a, b), "two runs differ");
    relief_mesh_destroy(a);
    relief_mesh_destroy(b);
    relief_mesh_destroy(in);
}

static void test_errors(void)
{
    relief_mesh *cloud = NULL, *out = NULL, *in = grid(3, 3, 1.0, 0.0, 0);
    relief_error err = {0};
    relief_oversample_params p = relief_oversample_params_default();
    relief_status st;

    if (relief_mesh_create(10, 0, RELIEF_MESH_COLOURS, &cloud, NULL) != RELIEF_OK)
        exit(2);
    st = relief_oversample(cloud, 1, NULL, &out, &err);
    CHECK(st == RELIEF_E_MESH && out == NULL && strstr(err.message, "point cloud"),
          "point cloud: %s (%s)", relief_status_name(st), err.message);
    printf("point cloud: %s: %s\n", relief_status_name(st), err.message);

    st = relief_oversample(in, -1, NULL, &out, &err);
    CHECK(st == RELIEF_E_RANGE && out == NULL, "passes -1: %s", relief_status_name(st));
    st = relief_oversample(in, RELIEF_OVERSAMPLE_PASSES_MAX + 1, NULL, &out, &err);
    CHECK(st == RELIEF_E_RANGE && out == NULL, "passes 9: %s", relief_status_name(st));
    p.scheme = 7;
    st = relief_oversample(in, 1, &p, &out, &err);
    CHECK(st == RELIEF_E_RANGE && out == NULL && strstr(err.message, "scheme"),
          "scheme 7: %s (%s)", relief_status_name(st), err.message);
    p.scheme = RELIEF_OVERSAMPLE_BUTTERFLY;
    p.k = 0;
    st = relief_oversample(in, 1, &p, &out, &err);
    CHECK(st == RELIEF_E_RANGE && out == NULL, "k 0: %s", relief_status_name(st));
    p.k = 6;
    p.sigma = -1.0;
    st = relief_oversample(in, 1, &p, &out, &err);
    CHECK(st == RELIEF_E_RANGE && out == NULL, "sigma -1: %s", relief_status_name(st));
    p.sigma = NAN;
    st = relief_oversample(in, 1, &p, &out, &err);
    CHECK(st == RELIEF_E_RANGE && out == NULL, "sigma NaN: %s", relief_status_name(st));
    st = relief_oversample(NULL, 1, NULL, &out, &err);
    CHECK(st == RELIEF_E_USAGE && out == NULL, "NULL in: %s", relief_status_name(st));
    st = relief_oversample(in, 1, NULL, NULL, NULL);
    CHECK(st == RELIEF_E_USAGE, "NULL out: %s", relief_status_name(st));
    in->tri[0] = 99;
    st = relief_oversample(in, 1, NULL, &out, &err);
    CHECK(st == RELIEF_E_MESH && out == NULL, "index out of range: %s (%s)",
          relief_status_name(st), err.message);
    relief_mesh_destroy(in);
    relief_mesh_destroy(cloud);
}

int main(void)
{
    test_counts();
    test_geometry();
    test_butterfly();
    test_colour();
    test_determinism();
    test_errors();
    return check_result();
}
