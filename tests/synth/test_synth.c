/* Synthetic surfaces: determinism, sizes, topology, orientation, labels,
 * and the stochastic kinds' stationarity. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "mesh/mesh.h"
#include "report/measures.h"

typedef struct edge { uint32_t a, b; } edge;

static int edge_cmp(const void *x, const void *y)
{
    const edge *p = x, *q = y;
    if (p->a != q->a)
        return p->a < q->a ? -1 : 1;
    return p->b < q->b ? -1 : p->b > q->b;
}

/* Every edge in one or two triangles, and twice-used edges traversed in
 * opposite directions (consistent orientation). Returns the number of
 * boundary edges, or -1 on a topology error. */
static long check_topology(const relief_mesh *m, const char *what)
{
    edge *e = malloc(3 * m->nt * sizeof *e);
    long boundary = 0;
    int ok = 1;
    for (size_t t = 0; t < m->nt; ++t)
        for (int k = 0; k < 3; ++k) {
            uint32_t a = m->tri[3 * t + k], b = m->tri[3 * t + (k + 1) % 3];
            e[3 * t + k].a = a, e[3 * t + k].b = b;
        }
    /* Directed edges must be unique; undirected ones used at most twice. */
    qsort(e, 3 * m->nt, sizeof *e, edge_cmp);
    for (size_t i = 1; i < 3 * m->nt; ++i)
        if (edge_cmp(&e[i - 1], &e[i]) == 0)
            ok = 0;
    CHECK(ok, "%s: a directed edge is used twice (flipped or overlapping triangles)", what);
    for (size_t i = 0; i < 3 * m->nt; ++i) {
        edge r = {e[i].b, e[i].a};
        if (!bsearch(&r, e, 3 * m->nt, sizeof *e, edge_cmp))
            ++boundary;
    }
    free(e);
    return ok ? boundary : -1;
}

static void check_kind(relief_synth_kind kind)
{
    const char *name = relief_synth_kind_name(kind);
    relief_synth_params p = relief_synth_params_default();
    relief_mesh *c1 = NULL, *t1 = NULL, *c2 = NULL, *t2 = NULL, *c3 = NULL;
    relief_error err = {0};
    size_t ncap = 0;

    p.kind = kind;
    p.colour = 1;
    CHECK(relief_synth(&p, &c1, &t1, &err) == RELIEF_OK, "%s: %s", name, err.message);
    CHECK(relief_synth(&p, &c2, &t2, &err) == RELIEF_OK, "%s: %s", name, err.message);
    if (!c1 || !c2)
        return;
    CHECK(c1->nv == c2->nv && t1->nv == t2->nv &&
              memcmp(c1->pos, c2->pos, 3 * c1->nv * sizeof(double)) == 0 &&
              memcmp(t1->pos, t2->pos, 3 * t1->nv * sizeof(double)) == 0 &&
              memcmp(c1->col, c2->col, 3 * c1->nv * sizeof(float)) == 0 &&
              memcmp(c1->tri, c2->tri, 3 * c1->nt * sizeof(uint32_t)) == 0,
          "%s: two runs with the same seed differ", name);
    CHECK(relief_mesh_validate(t1, &err) == RELIEF_OK, "%s truth: %s", name, err.message);
    CHECK(relief_mesh_validate(c1, &err) == RELIEF_OK, "%s capture: %s", name, err.message);
    CHECK(t1->nv > 1800 && t1->nv < 2200, "%s: %zu truth vertices for --vertices 2000",
          name, t1->nv);
    for (size_t v = 0; v < t1->nv; ++v)
        ncap += t1->label[v] == RELIEF_LABEL_CAPTURED;
    CHECK(ncap == c1->nv, "%s: truth labels %zu captured, capture has %zu", name, ncap,
          c1->nv);
    CHECK(c1->nv > t1->nv / 5 && c1->nv < t1->nv * 9 / 10,
          "%s: capture has %zu of %zu vertices", name, c1->nv, t1->nv);
    for (size_t v = 0; v < c1->nv; ++v)
        if (c1->label[v] != RELIEF_LABEL_CAPTURED) {
            CHECK(0, "%s: capture vertex %zu labelled completed", name, v);
            break;
        }
    {
        long b = check_topology(t1, name);
        if (kind == RELIEF_SYNTH_SPHERE_DIMPLES)
            CHECK(b == 0 && (long)t1->nv - (long)(3 * t1->nt / 2) + (long)t1->nt == 2,
                  "%s: the truth sphere is not closed with Euler characteristic 2 "
                  "(%ld boundary edges)", name, b);
        else
            CHECK(b > 0, "%s: the truth has no boundary", name);
        CHECK(check_topology(c1, name) > 0, "%s: the capture has no boundary", name);
    }
    /* Outward orientation: triangle normals agree with the primitive's. */
    {
        size_t bad = 0;
        for (size_t t = 0; t < t1->nt; ++t) {
            const double *a = t1->pos + 3 * t1->tri[3 * t], *b = t1->pos + 3 * t1->tri[3 * t + 1],
                         *c = t1->pos + 3 * t1->tri[3 * t + 2];
            double e1[3], e2[3], n[3], ref[3];
            for (int k = 0; k < 3; ++k)
                e1[k] = b[k] - a[k], e2[k] = c[k] - a[k];
            n[0] = e1[1] * e2[2] - e1[2] * e2[1];
            n[1] = e1[2] * e2[0] - e1[0] * e2[2];
            n[2] = e1[0] * e2[1] - e1[1] * e2[0];
            if (kind <= RELIEF_SYNTH_PLANE_NOISE)
                ref[0] = 0, ref[1] = 0, ref[2] = 1;
            else if (kind == RELIEF_SYNTH_SPHERE_DIMPLES)
                ref[0] = a[0], ref[1] = a[1], ref[2] = a[2];
            else
                ref[0] = a[0], ref[1] = a[1], ref[2] = 0;
            bad += n[0] * ref[0] + n[1] * ref[1] + n[2] * ref[2] <= 0.0;
        }
        CHECK(bad == 0, "%s: %zu triangles face inward", name, bad);
    }
    /* A different seed changes the stochastic kinds. */
    p.seed = 2;
    CHECK(relief_synth(&p, &c3, NULL, &err) == RELIEF_OK, "%s: %s", name, err.message);
    if (c3 && (kind == RELIEF_SYNTH_PLANE_NOISE || kind == RELIEF_SYNTH_CYLINDER_BARK))
        CHECK(memcmp(c1->pos, c3->pos, 3 * c1->nv * sizeof(double)) != 0,
              "%s: seeds 1 and 2 give the same surface", name);
    relief_mesh_destroy(c1), relief_mesh_destroy(t1), relief_mesh_destroy(c2);
    relief_mesh_destroy(t2), relief_mesh_destroy(c3);
}

/* The stochastic kinds are stationary at the scale of the missing part:
 * the truth's own two parts differ in MSI by less than the 5 % a
 * completion is held to (test_complete), whatever the seed. */
static void check_stationary(relief_synth_kind kind)
{
    relief_synth_params p = relief_synth_params_default();
    double worst = 0.0;
    p.kind = kind;
    for (uint32_t seed = 1; seed <= 8; ++seed) {
        relief_mesh *t = NULL;
        relief_measures me;
        relief_error err = {0};
        p.seed = seed;
        CHECK(relief_synth(&p, NULL, &t, &err) == RELIEF_OK, "%s", err.message);
        if (t) {
            CHECK(relief_measure(t, NULL, NULL, &me, &err) == RELIEF_OK, "%s", err.message);
            if (me.msi_diff_percent > worst)
                worst = me.msi_diff_percent;
        }
        relief_mesh_destroy(t);
    }
    printf("%s: the truth's parts differ in MSI by at most %.2f %% over seeds 1 to 8\n",
           relief_synth_kind_name(kind), worst);
    CHECK(worst < 5.0, "%s: the truth's own parts differ in MSI by %.2f %%",
          relief_synth_kind_name(kind), worst);
}

static void check_params(void)
{
    relief_synth_params p = relief_synth_params_default();
    relief_mesh *c = NULL, *t = NULL;
    relief_error err = {0};
    relief_synth_kind k;

    p.vertices = 99;
    CHECK(relief_synth(&p, &c, NULL, &err) == RELIEF_E_RANGE && !c, "99 vertices accepted");
    p.vertices = 2000;
    p.noise = 0.5;
    CHECK(relief_synth(&p, &c, NULL, &err) == RELIEF_E_RANGE && !c, "noise 0.5 accepted");
    CHECK(relief_synth_kind_parse("golf", &k, &err) == RELIEF_E_USAGE &&
              strstr(err.message, "sphere-dimples"),
          "unknown kind message: %s", err.message);
    /* Noise moves the capture off the truth by about sigma, nothing else. */
    p.noise = 0.01;
    p.kind = RELIEF_SYNTH_SPHERE_DIMPLES;
    CHECK(relief_synth(&p, &c, &t, &err) == RELIEF_OK, "%s", err.message);
    if (c && t) {
        double s2 = 0.0;
        size_t w = 0;
        for (size_t v = 0; v < t->nv; ++v) {
            if (t->label[v] != RELIEF_LABEL_CAPTURED)
                continue;
            for (int k2 = 0; k2 < 3; ++k2) {
                double d = c->pos[3 * w + k2] - t->pos[3 * v + k2];
                s2 += d * d;
            }
            ++w;
        }
        s2 = sqrt(s2 / (double)c->nv);
        CHECK(s2 > 0.008 && s2 < 0.012, "noise 0.01 gave rms offset %g", s2);
    }
    relief_mesh_destroy(c);
    relief_mesh_destroy(t);
    /* Large sizes stay within reach of --vertices. */
    p.noise = 0.0;
    p.vertices = 200000;
    p.kind = RELIEF_SYNTH_CYLINDER_BARK;
    c = t = NULL;
    CHECK(relief_synth(&p, NULL, &t, &err) == RELIEF_OK, "%s", err.message);
    if (t)
        CHECK(t->nv > 190000 && t->nv < 210000, "200000 requested, %zu made", t->nv);
    relief_mesh_destroy(t);
}

int main(void)
{
    for (int k = 0; k < RELIEF_SYNTH_KIND_COUNT; ++k)
        check_kind((relief_synth_kind)k);
    check_stationary(RELIEF_SYNTH_PLANE_NOISE);
    check_stationary(RELIEF_SYNTH_CYLINDER_BARK);
    check_params();
    return check_result();
}
