/* relief_edge_census, relief_self_intersections and relief_closure_check
 * (mesh/mesh_check.h) on tiny meshes with known answers; the grid's pairs
 * against every pair tested alone; exact predicates where doubles lie;
 * with a data folder (label real), counts measured on the Stanford bunny. */
#include <math.h>
#include <string.h>

#include "check.h"
#include "base/clock.h"
#include "base/predicates.h"
#include "base/rng.h"
#include "mesh/mesh.h"
#include "mesh/mesh_check.h"

static size_t crossings(const double *pos, size_t nv, const uint32_t *tri, size_t nt,
                        const uint8_t *focus, uint8_t *hit)
{
    relief_error err = {0};
    size_t n = 999;
    CHECK(relief_self_intersections(pos, nv, tri, nt, focus, hit, &n, &err) == RELIEF_OK, "%s",
          err.message);
    return n;
}

static relief_edge_census_result census(const uint32_t *tri, size_t nt, size_t nv,
                                        const uint8_t *vfocus)
{
    relief_edge_census_result r;
    relief_error err = {0};
    memset(&r, 0xff, sizeof r);
    CHECK(relief_edge_census(tri, nt, nv, vfocus, &r, &err) == RELIEF_OK, "%s", err.message);
    return r;
}

/* Two triangles through each other; the same apart; sharing an edge. */
static void test_pairs(void)
{
    const double pos[] = {0, 0, 0, 2, 0, 0, 0, 2, 0,          /* flat */
                          0.5, 0.5, -1, 0.5, 0.5, 1, 3, 3, 0, /* through it */
                          2, 2, 0};
    const uint32_t crossing[] = {0, 1, 2, 3, 4, 5}, apart[] = {0, 1, 2, 5, 6, 4},
                   joined[] = {0, 1, 2, 1, 6, 2};
    uint8_t hit[2] = {9, 9};
    CHECK(crossings(pos, 7, crossing, 2, NULL, hit) == 2 && hit[0] == 1 && hit[1] == 1,
          "two crossing triangles: 2 wanted");
    CHECK(crossings(pos, 7, crossing, 2, (const uint8_t[]){0, 1}, hit) == 1 && hit[0] == 0 &&
              hit[1] == 1, "the focus: only triangle 1 reported");
    CHECK(crossings(pos, 7, apart, 2, NULL, NULL) == 0, "apart: 0 wanted");
    CHECK(crossings(pos, 7, joined, 2, NULL, NULL) == 0, "sharing an edge: 0 wanted");
}

/* Touching counts; coplanar overlap counts; coplanar apart does not. */
static void test_touch_and_coplanar(void)
{
    const double pos[] = {0, 0, 0, 2, 0, 0, 0, 2, 0,     /* flat */
                          0.5, 0.5, 0, 3, 3, 1, 3, 4, 2, /* a corner on it */
                          1, 1, 0, 3, 1, 0, 1, 3, 0,     /* on its plane, overlapping */
                          1.5, 1.5, 0, 3, 1.5, 0, 1.5, 3, 0}; /* on it, beyond its edge */
    const uint32_t touch[] = {0, 1, 2, 3, 4, 5}, overlap[] = {0, 1, 2, 6, 7, 8},
                   beyond[] = {0, 1, 2, 9, 10, 11};
    CHECK(crossings(pos, 12, touch, 2, NULL, NULL) == 2, "a corner touching: 2 wanted");
    CHECK(crossings(pos, 12, overlap, 2, NULL, NULL) == 2, "coplanar overlap: 2 wanted");
    CHECK(crossings(pos, 12, beyond, 2, NULL, NULL) == 0, "coplanar apart: 0 wanted");
}

/* One shared vertex: a fan's triangles meeting only there (0); a fan
 * folded through itself (the first and last triangles, 2); two coplanar
 * triangles overlapping from the shared corner (2); an edge shared by a
 * coplanar fold (2), and the same unfolded (0); a duplicate face (2). */
static void test_shared(void)
{
    const double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.3, 0.3, 1, 0.3, 0.3, -1, /* fold */
                          -1, 0, 0, 0, -1, 0,                                   /* fan apart */
                          0.5, 0.2, 0, 0.2, 0.5, 0};                            /* inside */
    const uint32_t folded[] = {0, 1, 2, 0, 2, 3, 0, 3, 4}, fan[] = {0, 1, 2, 0, 5, 6},
                   inside[] = {0, 1, 2, 0, 7, 8}, fold[] = {0, 1, 2, 1, 0, 7},
                   flat[] = {0, 1, 2, 0, 1, 6}, twice[] = {0, 1, 2, 0, 2, 1};
    uint8_t hit[3];
    CHECK(crossings(pos, 9, folded, 3, NULL, hit) == 2 && hit[0] && !hit[1] && hit[2],
          "a fan folded through itself: triangles 0 and 2 wanted");
    CHECK(crossings(pos, 9, fan, 2, NULL, NULL) == 0, "a fan meeting at its centre: 0 wanted");
    CHECK(crossings(pos, 9, inside, 2, NULL, NULL) == 2, "coplanar from a corner: 2 wanted");
    CHECK(crossings(pos, 9, fold, 2, NULL, NULL) == 2, "a coplanar fold on an edge: 2 wanted");
    CHECK(crossings(pos, 9, flat, 2, NULL, NULL) == 0, "coplanar across an edge: 0 wanted");
    CHECK(crossings(pos, 9, twice, 2, NULL, NULL) == 2, "a duplicate face: 2 wanted");
}

/* A copy of a vertex at its place (a split bow-tie) joins like the vertex:
 * the two fans touch there only; a triangle of no area is skipped. */
static void test_copies_and_slivers(void)
{
    const double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, -1, 0, 0, 0, -1, 1,
                          0.2, 0.2, -1, 0.2, 0.2, 0, 0.2, 0.2, 1};
    const uint32_t bowtie[] = {0, 1, 2, 3, 4, 5}, sliver[] = {0, 1, 2, 6, 7, 8};
    CHECK(crossings(pos, 9, bowtie, 2, NULL, NULL) == 0, "a bow-tie's copies: 0 wanted");
    CHECK(crossings(pos, 9, sliver, 2, NULL, NULL) == 0, "a triangle of no area: skipped");
}

/* The octahedron, closed; with a face removed, one loop of 3 edges; a fin
 * (three triangles on one edge). */
static void test_census(void)
{
    const double pos[] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
    const uint32_t octa[] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4,
                             2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
    const uint32_t fin[] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    const uint8_t near0[6] = {1, 0, 0, 0, 0, 0}, near4[6] = {0, 0, 0, 0, 1, 0};
    relief_edge_census_result r = census(octa, 8, 6, NULL);
    relief_error err = {0};
    CHECK(r.boundary_edges == 0 && r.boundary_loops == 0 && r.nonmanifold_edges == 0,
          "octahedron: %zu %zu %zu", r.boundary_edges, r.boundary_loops, r.nonmanifold_edges);
    CHECK(crossings(pos, 6, octa, 8, NULL, NULL) == 0, "octahedron: no crossing");
    r = census(octa, 7, 6, NULL);
    CHECK(r.boundary_edges == 3 && r.boundary_loops == 1 && r.nonmanifold_edges == 0 &&
              r.focus_boundary_loops == 1 && r.focus_boundary_edges == 3,
          "a face removed: %zu edges, %zu loops, %zu non-manifold", r.boundary_edges,
          r.boundary_loops, r.nonmanifold_edges);
    r = census(octa, 7, 6, near0); /* the removed face is 0 3 5 */
    CHECK(r.focus_boundary_loops == 1 && r.focus_boundary_edges == 2, "focus 0: %zu, %zu",
          r.focus_boundary_loops, r.focus_boundary_edges);
    r = census(octa, 7, 6, near4); /* vertex 4: off the loop */
    CHECK(r.focus_boundary_loops == 0 && r.focus_boundary_edges == 0, "focus 4: %zu, %zu",
          r.focus_boundary_loops, r.focus_boundary_edges);
    r = census(fin, 3, 5, NULL);
    CHECK(r.nonmanifold_edges == 1 && r.boundary_edges == 6 && r.boundary_loops == 1,
          "a fin: %zu non-manifold, %zu boundary edges, %zu loops", r.nonmanifold_edges,
          r.boundary_edges, r.boundary_loops);
    CHECK(relief_edge_census(fin, 3, 4, NULL, &r, &err) == RELIEF_E_MESH &&
              strstr(err.message, "triangle 2"), "an index past the vertices: %s", err.message);
}

/* An n x n grid of unit squares in z = 0, two triangles a square (a
 * diagonal from (i, j) to (i + 1, j + 1)); vertex j n1 + i at (i, j), n1 =
 * n + 1. pos: (n + 1)^2 x 3, tri: 2 n^2 x 3. */
static void grid(size_t n, double *pos, uint32_t *tri)
{
    const size_t n1 = n + 1;
    for (size_t j = 0; j < n1; ++j)
        for (size_t i = 0; i < n1; ++i) {
            pos[3 * (j * n1 + i)] = (double)i;
            pos[3 * (j * n1 + i) + 1] = (double)j;
            pos[3 * (j * n1 + i) + 2] = 0.0;
        }
    for (size_t j = 0; j < n; ++j)
        for (size_t i = 0; i < n; ++i) {
            const uint32_t a = (uint32_t)(j * n1 + i), b = a + 1, c = b + (uint32_t)n1,
                           d = a + (uint32_t)n1;
            uint32_t *q = tri + 6 * (j * n + i);
            q[0] = a, q[1] = b, q[2] = c, q[3] = a, q[4] = c, q[5] = d;
        }
}

/* A square patch standing at y = 2.5 from x = 2.2 to 4.8 and z = -1 to 1,
 * pushed through an 8 x 8 grid: its 2 triangles cross the grid's 6 in
 * squares (2..4, 2) (the line y = 2.5 meets each square's diagonal at
 * x = i + 0.5, inside the patch's span). */
static void test_grid_pierced(void)
{
    double pos[(81 + 4) * 3];
    uint32_t tri[(128 + 2) * 3];
    uint8_t focus[130] = {0}, hit[130];
    const double patch[] = {2.2, 2.5, -1, 4.8, 2.5, -1, 4.8, 2.5, 1, 2.2, 2.5, 1};
    const uint32_t pt[] = {81, 82, 83, 81, 83, 84};
    size_t n, wrong = 0;
    grid(8, pos, tri);
    memcpy(pos + 81 * 3, patch, sizeof patch);
    memcpy(tri + 128 * 3, pt, sizeof pt);
    CHECK(crossings(pos, 85, tri, 128, NULL, NULL) == 0, "the grid alone: 0 wanted");
    n = crossings(pos, 85, tri, 130, NULL, hit);
    for (size_t t = 0; t < 128; ++t) /* squares (2..4, 2): triangles 2 (8 * 2 + i) + 0, 1 */
        wrong += hit[t] != (t >= 36 && t < 42);
    CHECK(n == 8 && !wrong && hit[128] && hit[129], "pierced: %zu crossing (8 wanted), %zu "
          "grid triangles wrong", n, wrong);
    focus[128] = focus[129] = 1;
    n = crossings(pos, 85, tri, 130, focus, hit);
    CHECK(n == 2 && hit[128] && hit[129] && !hit[36], "the patch in focus: %zu (2 wanted)", n);
}

/* The grid's pairs against every pair of triangles tested alone: small
 * triangles scattered in a cube, and long ones over a few shared vertices
 * (many crossings, many shared corners). */
static void test_grid_against_pairs(void)
{
    enum { NT = 240, NP = 60 };
    static double pos[3 * NT * 3];
    static uint32_t tri[3 * NT];
    static uint8_t hit[NT], alone[NT], focus[NT];
    relief_rng rng;
    relief_rng_seed(&rng, 61);
    for (int set = 0; set < 2; ++set) {
        size_t nv = set ? NP : 3 * NT, n, diff = 0, expect = 0;
        for (size_t v = 0; v < nv; ++v) /* set 0: a triangle's first corner, then near it */
            for (int k = 0; k < 3; ++k)
                pos[3 * v + k] = set || v % 3 == 0
                                     ? relief_rng_uniform(&rng)
                                     : pos[3 * (v - v % 3) + k] + 0.2 * relief_rng_uniform(&rng);
        for (size_t t = 0; t < NT; ++t) {
            for (int k = 0; k < 3; ++k)
                tri[3 * t + k] = set ? relief_rng_below(&rng, NP) : (uint32_t)(3 * t + k);
            focus[t] = relief_rng_below(&rng, 3) == 0;
            alone[t] = 0;
        }
        for (size_t s = 0; s < NT; ++s)
            for (size_t t = s + 1; t < NT; ++t) {
                uint32_t two[6];
                uint8_t h2[2];
                memcpy(two, tri + 3 * s, 3 * sizeof *two);
                memcpy(two + 3, tri + 3 * t, 3 * sizeof *two);
                if (crossings(pos, nv, two, 2, NULL, h2) == 2)
                    alone[s] = alone[t] = 1;
            }
        n = crossings(pos, nv, tri, NT, focus, hit);
        for (size_t t = 0; t < NT; ++t) {
            diff += hit[t] != (focus[t] && alone[t]);
            expect += focus[t] && alone[t];
        }
        CHECK(!diff && n == expect, "set %d: %zu triangles differ from the pairs' (%zu of %zu "
              "wanted)", set, diff, expect, n);
        printf("grid against pairs, set %d: %zu of %d focused triangles cross\n", set, n, NT);
    }
}

/* Points coplanar (collinear) exactly, with coordinates near 2^40 whose
 * determinant rounds away from 0 in doubles, and moved by one unit in the
 * last place either way: 0, then opposite signs. With b - a = (X, Y, Z1)
 * and c - a = (X + 1, Y, Z2), the normal's z is -Y, and det[a - d, b - d,
 * c - d] = -(d - a) . n = delta Y for d = b + c - a + (0, 0, delta). */
static void test_predicates(void)
{
    const double big = 1099511627776.0, X = 34359738368.0 + 12345, Y = 34359738368.0 - 999;
    const double ulp = 1.0 / 4096.0; /* 2^-12, one unit at 2^40 */
    const double a[3] = {big + 12345, big - 777, big + 31};
    const double b[3] = {a[0] + X, a[1] + Y, a[2] + 17179869184.0 + 7};
    const double c[3] = {a[0] + X + 1, a[1] + Y, a[2] - 8589934592.0 + 5};
    double d[3] = {b[0] + c[0] - a[0], b[1] + c[1] - a[1], b[2] + c[2] - a[2]};
    const double e[3] = {a[0] + 2 * X, a[1] + 2 * Y, 0}, m[3] = {a[0] + X, a[1] + Y, 0};
    double f[3] = {e[0], e[1], 0};
    CHECK(relief_orient3d(a, b, c, d) == 0, "coplanar near 2^40: %d",
          relief_orient3d(a, b, c, d));
    d[2] += ulp;
    CHECK(relief_orient3d(a, b, c, d) == 1, "one unit above: %d", relief_orient3d(a, b, c, d));
    d[2] -= 2 * ulp;
    CHECK(relief_orient3d(a, b, c, d) == -1, "one unit below: %d", relief_orient3d(a, b, c, d));
    CHECK(relief_orient2d(a, m, e, 0, 1) == 0, "collinear near 2^40");
    f[1] += ulp;
    CHECK(relief_orient2d(a, m, f, 0, 1) == -relief_orient2d(a, m, (const double[]){f[0],
                                                                     f[1] - 2 * ulp, 0}, 0, 1) &&
              relief_orient2d(a, m, f, 0, 1) != 0, "one unit off the line");
}

/* An 8 x 8 grid whose vertex 40 (at 4, 4) is completed: closed there
 * (the grid's outer border is not near it). A triangle of its fan
 * removed, a fin on its edge, the vertex moved past its rim within the
 * plane: one defect each. */
static void test_closure(void)
{
    double pos[81 * 3];
    uint32_t tri[129 * 3];
    uint8_t done[81] = {0};
    relief_closure c;
    relief_error err = {0};
    grid(8, pos, tri);
    done[40] = 1;
    CHECK(relief_closure_check(pos, 81, tri, 128, done, &c, &err) == RELIEF_OK, "%s",
          err.message);
    CHECK(!c.open_loops && !c.open_edges && !c.nonmanifold_edges && !c.self_intersections,
          "closed: %zu %zu %zu %zu", c.open_loops, c.open_edges, c.nonmanifold_edges,
          c.self_intersections);
    memcpy(tri + 3 * 128, tri + 3 * 54, 3 * sizeof *tri); /* triangle 54: 30 31 40 */
    memcpy(tri + 3 * 54, tri + 3 * 127, 3 * sizeof *tri); /* its place: the last one */
    CHECK(relief_closure_check(pos, 81, tri, 127, done, &c, &err) == RELIEF_OK &&
              c.open_loops == 1 && c.open_edges == 3 && !c.self_intersections,
          "a triangle removed: %zu loops, %zu edges", c.open_loops, c.open_edges);
    memcpy(tri + 3 * 54, tri + 3 * 128, 3 * sizeof *tri);
    tri[3 * 128] = 40, tri[3 * 128 + 1] = 41, tri[3 * 128 + 2] = 0; /* a fin on edge 40-41 */
    CHECK(relief_closure_check(pos, 81, tri, 129, done, &c, &err) == RELIEF_OK &&
              c.nonmanifold_edges == 1, "a fin: %zu non-manifold", c.nonmanifold_edges);
    pos[3 * 40 + 1] = 6.5;
    CHECK(relief_closure_check(pos, 81, tri, 128, done, &c, &err) == RELIEF_OK &&
              c.self_intersections > 0 && !c.open_loops, "moved past its rim: %zu crossing",
          c.self_intersections);
    done[40] = 0, done[1] = 1; /* on the outer border */
    pos[3 * 40 + 1] = 4.0;
    CHECK(relief_closure_check(pos, 81, tri, 128, done, &c, &err) == RELIEF_OK &&
              c.open_loops == 1 && c.open_edges == 4, "the border near a completed vertex: %zu "
          "loops, %zu edges", c.open_loops, c.open_edges);
}

/* Real files as they are (raw: no repair) and as relief reads them
 * (repaired). What was measured (this module's first version; the three
 * crossing triangles of blackVase, raw, confirmed by an independent check
 * in exact rationals, Moeller's intervals and polygon clipping, over all
 * 193 777 pairs of touching boxes): the Stanford bunny, 35 947 vertices
 * and 69 451 triangles, has 223 boundary edges in 5 loops (its base), no
 * non-manifold edge and no crossing, raw or repaired; blackVase (ggg_sfm),
 * raw, 4540 boundary edges in 279 loops, 2 non-manifold edges, 3
 * triangles crossing. */
typedef struct real_case {
    const char *file;
    int raw;
    size_t boundary_edges, loops, nonmanifold, crossing;
} real_case;

static void test_real(const char *dir)
{
    static const real_case cases[] = {
        {"stanford_bunny/stanford-bunny.obj", 1, 223, 5, 0, 0},
        {"stanford_bunny/stanford-bunny.obj", 0, 223, 5, 0, 0},
        {"ggg_sfm/blackVase.ply", 1, 4540, 279, 2, 3},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; ++i) {
        const real_case *c = cases + i;
        relief_read_options opts = {c->raw};
        relief_mesh *m = NULL;
        relief_error err = {0};
        relief_edge_census_result r;
        char path[512];
        size_t n;
        double t0, t1, t2;
        snprintf(path, sizeof path, "%s/%s", dir, c->file);
        if (relief_mesh_read_with(path, &opts, &m, NULL, &err) != RELIEF_OK) {
            CHECK(0, "%s: %s", path, err.message);
            continue;
        }
        t0 = relief_seconds();
        r = census(m->tri, m->nt, m->nv, NULL);
        t1 = relief_seconds();
        n = crossings(m->pos, m->nv, m->tri, m->nt, NULL, NULL);
        t2 = relief_seconds();
        printf("%s%s: %zu vertices, %zu triangles: %zu boundary edges in %zu loops, %zu "
               "non-manifold edges (%.3f s); %zu triangles crossing (%.3f s)\n", c->file,
               c->raw ? " (raw)" : "", m->nv, m->nt, r.boundary_edges, r.boundary_loops,
               r.nonmanifold_edges, t1 - t0, n, t2 - t1);
        CHECK(r.boundary_edges == c->boundary_edges && r.boundary_loops == c->loops &&
                  r.nonmanifold_edges == c->nonmanifold && n == c->crossing,
              "%s: %zu %zu %zu %zu, measured %zu %zu %zu %zu", c->file, r.boundary_edges,
              r.boundary_loops, r.nonmanifold_edges, n, c->boundary_edges, c->loops,
              c->nonmanifold, c->crossing);
        relief_mesh_destroy(m);
    }
}

int main(int argc, char **argv)
{
    test_pairs();
    test_touch_and_coplanar();
    test_shared();
    test_copies_and_slivers();
    test_census();
    test_grid_pierced();
    test_grid_against_pairs();
    test_predicates();
    test_closure();
    if (argc > 1)
        test_real(argv[1]);
    return check_result();
}
