/* mesh/hole_fill.h on meshes whose fill is known: a flat grid's hole
 * (the patch is flat), a sphere's cap (the faired patch keeps near the
 * sphere, closer than a membrane), a notch in a grid's border (closed as
 * the notch, its chord left open), a hole round a neck (no edge made
 * twice), a band cut all round a cylinder (one strip between its two
 * loops), and the patches' edges: every edge of the filled mesh has two
 * triangles except the border's. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "base/vec3.h"
#include "mesh/hole_fill.h"
#include "mesh/holes.h"

typedef struct tmesh {
    double *pos;
    uint32_t *tri;
    size_t nv, nt;
} tmesh;

/* An S x S grid on z = 0, unit spacing, without the triangles whose
 * centroid lies within r of (cx, cy). */
static tmesh grid_with_hole(int S, double cx, double cy, double r)
{
    tmesh m = {malloc((size_t)S * S * 3 * sizeof(double)),
               malloc((size_t)(S - 1) * (S - 1) * 6 * sizeof(uint32_t)), (size_t)S * S, 0};
    for (int y = 0; y < S; ++y)
        for (int x = 0; x < S; ++x) {
            double *p = m.pos + 3 * (y * S + x);
            p[0] = x, p[1] = y, p[2] = 0.0;
        }
    for (int y = 0; y + 1 < S; ++y)
        for (int x = 0; x + 1 < S; ++x) {
            uint32_t a = (uint32_t)(y * S + x), b = a + 1, c = a + (uint32_t)S, d = c + 1;
            uint32_t q[2][3] = {{a, b, d}, {a, d, c}};
            for (int k = 0; k < 2; ++k) {
                double gx = 0, gy = 0;
                for (int e = 0; e < 3; ++e)
                    gx += m.pos[3 * q[k][e]] / 3, gy += m.pos[3 * q[k][e] + 1] / 3;
                if (hypot(gx - cx, gy - cy) < r)
                    continue;
                memcpy(m.tri + 3 * m.nt++, q[k], sizeof q[k]);
            }
        }
    return m;
}

/* A UV sphere of radius 1, n rings, without the triangles above z = cut. */
static tmesh sphere_cut(int rings, int seg, double cut)
{
    size_t nv = (size_t)(rings - 1) * seg + 2;
    tmesh m = {malloc(nv * 3 * sizeof(double)), malloc((size_t)rings * seg * 6 * sizeof(uint32_t)),
               nv, 0};
    m.pos[0] = 0, m.pos[1] = 0, m.pos[2] = 1;
    for (int i = 1; i < rings; ++i)
        for (int j = 0; j < seg; ++j) {
            double th = RELIEF_PI * i / rings, ph = 2 * RELIEF_PI * j / seg;
            double *p = m.pos + 3 * (1 + (i - 1) * seg + j);
            p[0] = sin(th) * cos(ph), p[1] = sin(th) * sin(ph), p[2] = cos(th);
        }
    m.pos[3 * (nv - 1)] = 0, m.pos[3 * (nv - 1) + 1] = 0, m.pos[3 * (nv - 1) + 2] = -1;
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < seg; ++j) {
            int j1 = (j + 1) % seg;
            uint32_t a = i == 0 ? 0 : (uint32_t)(1 + (i - 1) * seg + j);
            uint32_t b = i == 0 ? 0 : (uint32_t)(1 + (i - 1) * seg + j1);
            uint32_t c = i == rings - 1 ? (uint32_t)(nv - 1) : (uint32_t)(1 + i * seg + j);
            uint32_t d = i == rings - 1 ? (uint32_t)(nv - 1) : (uint32_t)(1 + i * seg + j1);
            uint32_t q[2][3] = {{a, c, d}, {a, d, b}};
            for (int k = 0; k < 2; ++k) {
                double z = 0;
                if (q[k][0] == q[k][1] || q[k][1] == q[k][2] || q[k][0] == q[k][2])
                    continue;
                for (int e = 0; e < 3; ++e)
                    z += m.pos[3 * q[k][e] + 2] / 3;
                if (z > cut)
                    continue;
                memcpy(m.tri + 3 * m.nt++, q[k], sizeof q[k]);
            }
        }
    return m;
}

/* A cylinder of radius 1 about z, z in [0, 2] (rings + 1 rings of seg
 * vertices), open at both ends, without the triangles whose centroid lies
 * within band of z = 1: a band cut all round, two loops bounding one
 * hole. */
static tmesh cylinder_band(int rings, int seg, double band)
{
    size_t nv = (size_t)(rings + 1) * seg;
    tmesh m = {malloc(nv * 3 * sizeof(double)), malloc((size_t)rings * seg * 6 * sizeof(uint32_t)),
               nv, 0};
    for (int i = 0; i <= rings; ++i)
        for (int j = 0; j < seg; ++j) {
            double ph = 2 * RELIEF_PI * (j + 0.5 * (i % 2)) / seg, *p = m.pos + 3 * (i * seg + j);
            p[0] = cos(ph), p[1] = sin(ph), p[2] = 2.0 * i / rings;
        }
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < seg; ++j) {
            uint32_t a = (uint32_t)(i * seg + j), b = (uint32_t)(i * seg + (j + 1) % seg);
            uint32_t c = (uint32_t)((i + 1) * seg + j), d = (uint32_t)((i + 1) * seg + (j + 1) % seg);
            uint32_t q[2][3] = {{a, b, c}, {b, d, c}};
            for (int k = 0; k < 2; ++k) {
                double z = (m.pos[3 * q[k][0] + 2] + m.pos[3 * q[k][1] + 2] +
                            m.pos[3 * q[k][2] + 2]) / 3;
                if (fabs(z - 1.0) >= band)
                    memcpy(m.tri + 3 * m.nt++, q[k], sizeof q[k]);
            }
        }
    return m;
}

/* Every boundary vertex labelled 1 (within ball r of c when r > 0). */
static uint32_t *label_rims(const tmesh *m, const double *c, double r)
{
    uint32_t *loop = malloc(m->nv * sizeof *loop), n = 0;
    relief_error err = {0};
    relief_boundary_loops(m->tri, m->nt, m->nv, loop, &n, &err);
    for (size_t v = 0; v < m->nv; ++v) {
        double d[3];
        if (r > 0) {
            sub3(m->pos + 3 * v, c, d);
            if (sqrt(dot3(d, d)) > r)
                loop[v] = 0;
        }
        loop[v] = loop[v] != 0;
    }
    return loop;
}

/* The filled mesh's boundary edges and edges of three or more triangles. */
static void census(const tmesh *m, const relief_hole_patches *p, size_t *open, size_t *over)
{
    size_t nt = m->nt + p->nt_new, nv = m->nv + p->nv_new, ne = 0;
    uint64_t *e = malloc(3 * nt * sizeof *e);
    for (size_t t = 0; t < nt; ++t) {
        const uint32_t *T = t < m->nt ? m->tri + 3 * t : p->tri + 3 * (t - m->nt);
        for (int k = 0; k < 3; ++k) {
            uint64_t a = T[k], b = T[(k + 1) % 3];
            e[ne++] = a < b ? a * nv + b : b * nv + a;
        }
    }
    *open = *over = 0;
    for (size_t i = 0; i < ne; ++i) { /* quadratic: the test meshes are small */
        size_t c = 0;
        for (size_t k = 0; k < ne; ++k)
            c += e[k] == e[i];
        *open += c == 1, *over += c > 2;
    }
    free(e);
}

static void test_flat(void)
{
    tmesh m = grid_with_hole(16, 7.3, 7.6, 4.2);
    uint32_t *rim = label_rims(&m, (double[3]){7.3, 7.6, 0}, 6.0);
    relief_hole_patches p;
    relief_error err = {0};
    size_t open, over;
    double zmax = 0;
    CHECK(relief_fill_rims(m.pos, m.nv, m.tri, m.nt, rim, NULL, &p, &err) == RELIEF_OK, "%s",
          err.message);
    CHECK(p.polygons == 1 && p.arcs == 0 && p.skipped == 0, "%zu polygons", p.polygons);
    printf("flat: %zu new vertices (the grid had about 43 there)\n", p.nv_new);
    CHECK(p.nv_new >= 35 && p.nv_new <= 52, "the refinement keeps the grid's density: %zu "
          "vertices where it had about 43", p.nv_new);
    for (size_t i = 0; i < p.nv_new; ++i)
        zmax = fmax(zmax, fabs(p.pos[3 * i + 2]));
    CHECK(zmax < 1e-9, "a flat hole's patch is flat: |z| up to %g", zmax);
    census(&m, &p, &open, &over);
    CHECK(over == 0, "%zu edges with three triangles", over);
    CHECK(open == 4 * 15, "only the grid's border is open: %zu edges", open);
    relief_hole_patches_free(&p);
    free(rim), free(m.pos), free(m.tri);
}

static double sphere_error(const relief_hole_patches *p, double *worst)
{
    double sum = 0;
    *worst = 0;
    for (size_t i = 0; i < p->nv_new; ++i) {
        double d = fabs(sqrt(dot3(p->pos + 3 * i, p->pos + 3 * i)) - 1.0);
        sum += d, *worst = fmax(*worst, d);
    }
    return p->nv_new ? sum / p->nv_new : INFINITY;
}

static void test_sphere_cap(void)
{
    tmesh m = sphere_cut(24, 48, 0.7);
    uint32_t *rim = label_rims(&m, NULL, 0);
    relief_hole_fill_options o;
    relief_hole_patches c1, c0;
    relief_error err = {0};
    size_t open, over;
    double w1, w0, e1, e0;
    relief_hole_fill_options_default(&o);
    CHECK(relief_fill_rims(m.pos, m.nv, m.tri, m.nt, rim, &o, &c1, &err) == RELIEF_OK, "%s",
          err.message);
    o.fair = RELIEF_FAIR_C0;
    CHECK(relief_fill_rims(m.pos, m.nv, m.tri, m.nt, rim, &o, &c0, &err) == RELIEF_OK, "%s",
          err.message);
    e1 = sphere_error(&c1, &w1), e0 = sphere_error(&c0, &w0);
    /* the cap is 0.71 wide, its sagitta 0.3 */
    /* measured: worst 0.049, mean 0.017 (the sphere's edges are 0.13) */
    CHECK(w1 < 0.06 && e1 < 0.025, "the C1 patch keeps near the sphere: worst %g, mean %g", w1,
          e1);
    printf("sphere cap: C1 mean %g worst %g, C0 mean %g worst %g\n", e1, w1, e0, w0);
    CHECK(e1 < e0 / 3, "C1 (mean %g) nearer the sphere than a membrane (%g)", e1, e0);
    census(&m, &c1, &open, &over);
    CHECK(open == 0 && over == 0, "the sphere is closed: %zu open, %zu over", open, over);
    relief_hole_patches_free(&c1), relief_hole_patches_free(&c0);
    free(rim), free(m.pos), free(m.tri);
}

/* A notch: a ball about a border point of the grid takes a bite; only
 * the rim inside a larger ball is labelled, so the bite is closed by its
 * chord and the rest of the border stays. */
static void test_notch(void)
{
    tmesh m = grid_with_hole(16, 7.5, 0.0, 4.0);
    uint32_t *rim = label_rims(&m, (double[3]){7.5, 0.0, 0}, 5.0);
    relief_hole_patches p;
    relief_error err = {0};
    size_t open, over;
    CHECK(relief_fill_rims(m.pos, m.nv, m.tri, m.nt, rim, NULL, &p, &err) == RELIEF_OK, "%s",
          err.message);
    CHECK(p.polygons == 1 && p.arcs == 1, "%zu polygons, %zu arcs", p.polygons, p.arcs);
    census(&m, &p, &open, &over);
    CHECK(over == 0, "%zu edges with three triangles", over);
    CHECK(open < 4 * 15, "the notch is closed, its chord open: %zu open edges", open);
    relief_hole_patches_free(&p);
    free(rim), free(m.pos), free(m.tri);
}

/* A band cut all round a cylinder: its two loops (the ends left open)
 * are one hole, bridged by one patch that keeps near the cylinder, not
 * two caps across it. */
static void test_tube(void)
{
    tmesh m = cylinder_band(20, 48, 0.2);
    uint32_t *rim = label_rims(&m, (double[3]){0, 0, 1}, 1.2);
    relief_hole_patches p;
    relief_error err = {0};
    size_t open, over;
    double worst = 0, zlo = INFINITY, zhi = -INFINITY;
    CHECK(relief_fill_rims(m.pos, m.nv, m.tri, m.nt, rim, NULL, &p, &err) == RELIEF_OK, "%s",
          err.message);
    CHECK(p.polygons == 1 && p.arcs == 0 && p.skipped == 0, "one patch for the two loops: %zu "
          "polygons, %zu skipped", p.polygons, p.skipped);
    for (size_t i = 0; i < p.nv_new; ++i) {
        const double *x = p.pos + 3 * i;
        worst = fmax(worst, fabs(hypot(x[0], x[1]) - 1.0));
        zlo = fmin(zlo, x[2]), zhi = fmax(zhi, x[2]);
    }
    printf("tube: %zu new vertices, radius off by up to %g, z %g..%g\n", p.nv_new, worst, zlo,
           zhi);
    CHECK(p.nv_new > 100 && worst < 0.02, "the strip keeps to the cylinder: %zu vertices, radius "
          "off by up to %g", p.nv_new, worst);
    CHECK(zlo > 0.7 && zhi < 1.3, "the strip stays in the band: z %g..%g", zlo, zhi);
    census(&m, &p, &open, &over);
    CHECK(over == 0 && open == 2 * 48, "only the cylinder's ends are open: %zu open, %zu over",
          open, over);
    relief_hole_patches_free(&p);
    free(rim), free(m.pos), free(m.tri);
}

int main(void)
{
    test_flat();
    test_sphere_cap();
    test_notch();
    test_tube();
    return check_result();
}
