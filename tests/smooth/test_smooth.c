/* Smooth completion: the combined triangulation is manifold, oriented with
 * the primitive, of the expected topology (closed sphere, cylinder band,
 * plane disc), its targets sit on the primitive at the target spacing, and
 * the per-vertex state (D, normals, frames) is consistent; curved
 * primitives complete a patch's holes and a one-sided scan's hidden side. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "check.h"
#include "base/params.h"
#include "pipeline.h"
#include "mesh/mesh.h"
#include "smooth/fit.h"
#include "smooth/surface.h"
#include "smooth/surface_check.h"

typedef struct edge {
    uint32_t a, b;
} edge;

static int edge_cmp(const void *x, const void *y)
{
    const edge *p = x, *q = y;
    if (p->a != q->a)
        return p->a < q->a ? -1 : 1;
    return (p->b > q->b) - (p->b < q->b);
}

typedef struct topology {
    long euler;
    size_t boundary_edges;
    size_t boundary_targets; /* boundary edges touching a target */
    int oriented;            /* no directed edge twice */
} topology;

static topology topology_of(const relief_surface *s)
{
    const relief_mesh *m = s->mesh;
    topology t = {0, 0, 0, 1};
    edge *e = malloc(3 * m->nt * sizeof *e);
    size_t undirected = 0;
    for (size_t i = 0; i < m->nt; ++i)
        for (int k = 0; k < 3; ++k)
            e[3 * i + k].a = m->tri[3 * i + k], e[3 * i + k].b = m->tri[3 * i + (k + 1) % 3];
    qsort(e, 3 * m->nt, sizeof *e, edge_cmp);
    for (size_t i = 0; i < 3 * m->nt; ++i) {
        edge r = {e[i].b, e[i].a};
        if (i > 0 && edge_cmp(&e[i - 1], &e[i]) == 0)
            t.oriented = 0;
        if (!bsearch(&r, e, 3 * m->nt, sizeof *e, edge_cmp)) {
            ++t.boundary_edges;
            ++undirected;
            if (e[i].a >= s->n_samples || e[i].b >= s->n_samples)
                ++t.boundary_targets;
        } else if (e[i].a < e[i].b) {
            ++undirected;
        }
    }
    t.euler = (long)m->nv - (long)undirected + (long)m->nt;
    free(e);
    return t;
}

/* Triangles facing away from the primitive's normal, and target-target
 * edges outside [0.5, 2] x spacing. */
static void check_geometry(const relief_surface *s, const char *what)
{
    const relief_mesh *m = s->mesh;
    size_t flipped = 0, bad_edges = 0, tt_edges = 0;
    double worst_target = 0.0, worst_disp = 0.0;
    for (size_t t = 0; t < m->nt; ++t) {
        const uint32_t *f = m->tri + 3 * t;
        const double *a = s->proj + 3 * f[0], *b = s->proj + 3 * f[1], *c = s->proj + 3 * f[2];
        double e1[3], e2[3], n[3], mid[3], pn[3];
        for (int k = 0; k < 3; ++k)
            e1[k] = b[k] - a[k], e2[k] = c[k] - a[k], mid[k] = (a[k] + b[k] + c[k]) / 3.0;
        n[0] = e1[1] * e2[2] - e1[2] * e2[1];
        n[1] = e1[2] * e2[0] - e1[0] * e2[2];
        n[2] = e1[0] * e2[1] - e1[1] * e2[0];
        relief_fit_normal(&s->fit.prim, mid, pn);
        flipped += n[0] * pn[0] + n[1] * pn[1] + n[2] * pn[2] <= 0.0;
        for (int k = 0; k < 3; ++k) {
            uint32_t p = f[k], q = f[(k + 1) % 3];
            if (p >= s->n_samples && q >= s->n_samples) {
                const double *x = m->pos + 3 * (size_t)p, *y = m->pos + 3 * (size_t)q;
                double l = sqrt((x[0] - y[0]) * (x[0] - y[0]) + (x[1] - y[1]) * (x[1] - y[1]) +
                                (x[2] - y[2]) * (x[2] - y[2]));
                ++tt_edges;
                bad_edges += l < 0.5 * s->spacing || l > 2.0 * s->spacing;
            }
        }
    }
    CHECK(flipped == 0, "%s: %zu of %zu triangles face against the primitive", what,
          flipped, m->nt);
    CHECK(tt_edges > 0 && bad_edges == 0,
          "%s: %zu of %zu target-target edges outside [0.5, 2] x spacing %g", what,
          bad_edges, tt_edges, s->spacing);
    for (size_t v = 0; v < m->nv; ++v) {
        const double *p = m->pos + 3 * v, *q = s->proj + 3 * v, *d = s->disp + 3 * v;
        const double *n = s->nrm + 3 * v, *f = s->frame + 9 * v;
        double dist = relief_fit_distance(&s->fit.prim, p);
        double dn = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
        for (int k = 0; k < 3; ++k)
            worst_disp = fmax(worst_disp, fabs(p[k] - q[k] - d[k]));
        /* D = p - p' is the offset along the normal by the signed distance. */
        worst_disp = fmax(worst_disp, fabs(dn - dist));
        if (v >= s->n_samples)
            worst_target = fmax(worst_target, fabs(dist));
        /* Frames orthonormal, right-handed, third row the normal. */
        {
            double uv = f[0] * f[3] + f[1] * f[4] + f[2] * f[5];
            double cz[3] = {f[1] * f[5] - f[2] * f[4], f[2] * f[3] - f[0] * f[5],
                            f[0] * f[4] - f[1] * f[3]};
            double err = fabs(uv) + fabs(cz[0] - n[0]) + fabs(cz[1] - n[1]) +
                         fabs(cz[2] - n[2]) + fabs(f[6] - n[0]) + fabs(f[7] - n[1]) +
                         fabs(f[8] - n[2]);
            if (err > 1e-9) {
                CHECK(0, "%s: vertex %zu frame is not [u v n] orthonormal (err %g)", what,
                      v, err);
                break;
            }
        }
    }
    CHECK(worst_disp < 1e-9, "%s: D disagrees with p - p' or the signed distance by %g",
          what, worst_disp);
    CHECK(worst_target < 1e-9, "%s: a target is %g off the primitive", what, worst_target);
}

static relief_surface *smooth_synth(relief_synth_kind kind, size_t n, const char *what)
{
    relief_surface *s = NULL;
    relief_error err = {0};
    CHECK(pipeline_smooth(kind, n, 1, &s, &err) == RELIEF_OK, "%s: %s", what, err.message);
    return s;
}

static void test_sphere(void)
{
    relief_surface *s = smooth_synth(RELIEF_SYNTH_SPHERE_DIMPLES, 2000, "sphere");
    topology t;
    if (!s)
        return;
    CHECK(s->fit.prim.model == RELIEF_FIT_SPHERE, "sphere fitted as %s",
          relief_fit_model_name(s->fit.prim.model));
    t = topology_of(s);
    CHECK(t.oriented && t.boundary_edges == 0 && t.euler == 2,
          "sphere: not a closed oriented sphere (euler %ld, %zu boundary edges)", t.euler,
          t.boundary_edges);
    CHECK(s->n_targets > s->n_captured / 2, "sphere: only %zu targets", s->n_targets);
    check_geometry(s, "sphere");
    relief_surface_destroy(s);
}

static void test_cylinder(void)
{
    relief_surface *s = smooth_synth(RELIEF_SYNTH_CYLINDER_BARK, 2000, "cylinder");
    topology t;
    if (!s)
        return;
    CHECK(s->fit.prim.model == RELIEF_FIT_CYLINDER, "cylinder fitted as %s",
          relief_fit_model_name(s->fit.prim.model));
    t = topology_of(s);
    CHECK(t.oriented && t.euler == 0, "cylinder: not an oriented band (euler %ld)", t.euler);
    /* The only boundary is the two rims: every boundary vertex near an end. */
    {
        double zmin = 1e300, zmax = -1e300;
        size_t off_rim = 0;
        const relief_mesh *m = s->mesh;
        for (size_t v = 0; v < m->nv; ++v) {
            double z = (s->proj[3 * v] - s->fit.prim.point[0]) * s->fit.prim.dir[0] +
                       (s->proj[3 * v + 1] - s->fit.prim.point[1]) * s->fit.prim.dir[1] +
                       (s->proj[3 * v + 2] - s->fit.prim.point[2]) * s->fit.prim.dir[2];
            zmin = fmin(zmin, z);
            zmax = fmax(zmax, z);
        }
        for (size_t i = 0; i < m->nt; ++i)
            for (int k = 0; k < 3; ++k) {
                uint32_t a = m->tri[3 * i + k], b = m->tri[3 * i + (k + 1) % 3];
                int shared = 0;
                for (size_t j = 0; j < m->nt && !shared; ++j)
                    for (int q = 0; q < 3; ++q)
                        if (m->tri[3 * j + q] == b && m->tri[3 * j + (q + 1) % 3] == a)
                            shared = 1;
                if (!shared) {
                    const double *p = s->proj + 3 * (size_t)a;
                    double z = (p[0] - s->fit.prim.point[0]) * s->fit.prim.dir[0] +
                               (p[1] - s->fit.prim.point[1]) * s->fit.prim.dir[1] +
                               (p[2] - s->fit.prim.point[2]) * s->fit.prim.dir[2];
                    off_rim += z > zmin + 1.5 * s->spacing && z < zmax - 1.5 * s->spacing;
                }
            }
        CHECK(off_rim == 0, "cylinder: %zu boundary edges away from the rims (a gap)",
              off_rim);
    }
    /* The targets' lattice has an edge along the axis (rows along it): each
     * target but a row's last has a target one spacing further up the axis,
     * joined to it by a triangle's edge. With rows around the turn the
     * nearest target along the axis was sqrt 3 spacings away and none
     * qualified; axial ridges were then drawn as zigzags (issue 17). */
    {
        const relief_mesh *m = s->mesh;
        const double *dir = s->fit.prim.dir, tol = 1e-6 * s->spacing;
        size_t axial = 0;
        for (size_t a = s->n_samples; a < m->nv; ++a) {
            size_t b;
            for (b = s->n_samples; b < m->nv; ++b) {
                double e2 = 0.0;
                for (int k = 0; k < 3; ++k) {
                    const double e = s->proj[3 * b + k] - s->proj[3 * a + k] - s->spacing * dir[k];
                    e2 += e * e;
                }
                if (e2 <= tol * tol)
                    break;
            }
            if (b == m->nv)
                continue;
            for (size_t i = 0; i < m->nt; ++i) {
                int ha = 0, hb = 0;
                for (int k = 0; k < 3; ++k)
                    ha |= m->tri[3 * i + k] == a, hb |= m->tri[3 * i + k] == b;
                if (ha && hb) {
                    ++axial;
                    break;
                }
            }
        }
        printf("cylinder: %zu of %zu targets have an axial lattice edge\n", axial,
               s->n_targets);
        CHECK(axial >= 9 * s->n_targets / 10, "cylinder: only %zu of %zu targets have an axial "
              "lattice edge (rows along the axis)", axial, s->n_targets);
    }
    check_geometry(s, "cylinder");
    relief_surface_destroy(s);
}

static void test_plane(void)
{
    relief_surface *s = smooth_synth(RELIEF_SYNTH_PLANE_WAVES, 2000, "plane");
    topology t;
    if (!s)
        return;
    CHECK(s->fit.prim.model == RELIEF_FIT_PLANE, "plane fitted as %s",
          relief_fit_model_name(s->fit.prim.model));
    t = topology_of(s);
    CHECK(t.oriented && t.euler == 1, "plane: hole not filled to a disc (euler %ld)", t.euler);
    CHECK(t.boundary_targets == 0, "plane: %zu boundary edges touch a target: targets "
          "escaped the outline", t.boundary_targets);
    /* The hole is a disc of radius 0.25: about pi 0.25^2 / (spacing^2 sqrt3/2) targets. */
    {
        double want = 3.14159265 * 0.0625 / (s->spacing * s->spacing * sqrt(3.0) / 2.0);
        CHECK(s->n_targets > 0.6 * want && s->n_targets < 1.4 * want,
              "plane: %zu targets for a hole that needs about %.0f", s->n_targets, want);
    }
    check_geometry(s, "plane");
    relief_surface_destroy(s);
}

/* A patch of the unit cylinder (angles 0..span_deg, z 0..1) or of the unit
 * sphere (longitudes 0..span_deg, latitudes -span_deg/2..span_deg/2) with
 * a gentle relief, on a grid of about 0.02, without the triangles whose
 * centroid lies within `hole` of the patch's middle (0 for none). */
static relief_mesh *patch(relief_fit_model model, double span_deg, double hole)
{
    const double span = span_deg * 3.14159265358979323846 / 180.0;
    const int na = (int)ceil(span / 0.02) + 1;
    const int nb = model == RELIEF_FIT_CYLINDER ? 51 : na;
    const double centre[3] = {cos(span / 2), sin(span / 2), model == RELIEF_FIT_CYLINDER};
    const size_t nv = (size_t)na * (size_t)nb;
    double *pos = malloc(3 * nv * sizeof *pos);
    uint32_t *tri = malloc(6 * nv * sizeof *tri);
    relief_mesh *m = NULL;
    relief_error err = {0};
    size_t nt = 0;

    if (!pos || !tri) {
        free(pos);
        free(tri);
        return NULL;
    }
    for (int i = 0; i < na; ++i)
        for (int j = 0; j < nb; ++j) {
            double *p = pos + 3 * ((size_t)i * (size_t)nb + (size_t)j), a = span * i / (na - 1);
            double b = (double)j / (nb - 1), r = 1.0 + 0.01 * sin(40.0 * a) * sin(40.0 * b);
            if (model == RELIEF_FIT_CYLINDER) {
                p[0] = r * cos(a), p[1] = r * sin(a), p[2] = 2.0 * b;
            } else {
                b = span * (b - 0.5);
                p[0] = r * cos(b) * cos(a), p[1] = r * cos(b) * sin(a), p[2] = r * sin(b);
            }
        }
    /* (angle, z) and (longitude, latitude) counter-clockwise face outward. */
    for (int i = 0; i + 1 < na; ++i)
        for (int j = 0; j + 1 < nb; ++j) {
            const uint32_t q[4] = {(uint32_t)(i * nb + j), (uint32_t)((i + 1) * nb + j),
                                   (uint32_t)((i + 1) * nb + j + 1), (uint32_t)(i * nb + j + 1)};
            for (int t = 0; t < 2; ++t) {
                const uint32_t f[3] = {q[0], q[1 + t], q[2 + t]};
                double c[3] = {0, 0, 0}, d2 = 0;
                for (int k = 0; k < 3; ++k)
                    for (int e = 0; e < 3; ++e)
                        c[e] += pos[3 * f[k] + e] / 3.0;
                for (int e = 0; e < 3; ++e)
                    d2 += (c[e] - centre[e]) * (c[e] - centre[e]);
                if (hole > 0.0 && d2 < hole * hole)
                    continue;
                memcpy(tri + 3 * nt++, f, sizeof f);
            }
        }
    if (relief_mesh_create(nv, nt, 0, &m, &err) == RELIEF_OK) {
        memcpy(relief_mesh_positions(m), pos, 3 * nv * sizeof *pos);
        memcpy(relief_mesh_triangles(m), tri, 3 * nt * sizeof *tri);
    }
    free(pos);
    free(tri);
    return m;
}

/* Curved primitives complete the holes of a patch, the whole of a
 * one-sided scan (targets.h), and --fill overrides either way. */
static void test_fill(void)
{
    struct {
        relief_fit_model model;
        double span, hole;
        relief_fill fill, want;
        const char *what;
    } cases[] = {
        {RELIEF_FIT_CYLINDER, 60, 0.15, RELIEF_FILL_AUTO, RELIEF_FILL_HOLES, "cylinder patch"},
        {RELIEF_FIT_CYLINDER, 60, 0.15, RELIEF_FILL_WHOLE, RELIEF_FILL_WHOLE,
         "cylinder patch, --fill whole"},
        {RELIEF_FIT_CYLINDER, 180, 0.15, RELIEF_FILL_AUTO, RELIEF_FILL_WHOLE,
         "one-sided cylinder"},
        {RELIEF_FIT_CYLINDER, 180, 0.15, RELIEF_FILL_HOLES, RELIEF_FILL_HOLES,
         "one-sided cylinder, --fill holes"},
        {RELIEF_FIT_SPHERE, 40, 0.15, RELIEF_FILL_AUTO, RELIEF_FILL_HOLES, "sphere patch"},
        {RELIEF_FIT_SPHERE, 40, 0.0, RELIEF_FILL_AUTO, RELIEF_FILL_WHOLE,
         "sphere patch without a hole"},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        relief_mesh *m = patch(cases[c].model, cases[c].span, cases[c].hole);
        relief_params p = relief_params_default();
        relief_smooth_options o = relief_smooth_options_default();
        relief_surface *s = NULL;
        relief_error err = {0};
        relief_status st;
        if (!m) {
            CHECK(0, "%s: cannot build the patch", cases[c].what);
            continue;
        }
        p.fit = cases[c].model;
        o.fill = cases[c].fill;
        st = relief_surface_build(m, &p, &o, &s, &err);
        CHECK(st == RELIEF_OK, "%s: %s", cases[c].what, err.message);
        if (st == RELIEF_OK) {
            const relief_fill_stats *f = &s->fill;
            /* The hole's area over a target's (a lattice cell). */
            double cell = s->spacing * s->spacing * sqrt(3.0) / 2.0;
            double hole = 3.14159265 * cases[c].hole * cases[c].hole / cell;
            printf("%-34s cover %.3f, %zu holes of %zu points, %zu outside: %s, %zu targets "
                   "(hole about %.0f)\n",
                   cases[c].what, f->cover, f->holes, f->hole_points, f->outside_points,
                   f->region == RELIEF_FILL_HOLES ? "holes" : "whole", s->n_targets, hole);
            CHECK(f->region == cases[c].want, "%s: completed the %s", cases[c].what,
                  f->region == RELIEF_FILL_HOLES ? "holes" : "whole");
            CHECK(f->holes == (cases[c].hole > 0.0), "%s: %zu holes", cases[c].what, f->holes);
            CHECK(f->outside_points > 2 * f->hole_points, "%s: %zu points outside",
                  cases[c].what, f->outside_points);
            if (f->region == RELIEF_FILL_HOLES)
                CHECK(s->n_targets == f->hole_points && s->n_targets > 0.6 * hole &&
                          s->n_targets < 1.4 * hole,
                      "%s: %zu targets for a hole of about %.0f", cases[c].what, s->n_targets,
                      hole);
            else
                CHECK(s->n_targets == f->hole_points + f->outside_points, "%s: %zu targets",
                      cases[c].what, s->n_targets);
            check_geometry(s, cases[c].what);
        }
        relief_surface_destroy(s);
        relief_mesh_destroy(m);
    }
}

static void test_errors(void)
{
    relief_params p = relief_params_default();
    relief_mesh *m = NULL;
    relief_surface *s = NULL;
    relief_error err = {0};

    /* A flat square with no hole: nothing to complete without --extent. */
    relief_mesh_create(4, 2, 0, &m, &err);
    {
        const double pos[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
        const uint32_t tri[6] = {0, 1, 2, 0, 2, 3};
        memcpy(relief_mesh_positions(m), pos, sizeof pos);
        memcpy(relief_mesh_triangles(m), tri, sizeof tri);
    }
    CHECK(relief_surface_build(m, &p, NULL, &s, &err) == RELIEF_E_MESH && !s &&
              strstr(err.message, "nothing to complete"),
          "square without hole: %s", err.message);
    /* With an extent the plane grows past the square. */
    p.has_extent = 1;
    p.n_extent = 4;
    p.extent[0] = -1.0, p.extent[1] = -1.0, p.extent[2] = 2.0, p.extent[3] = 2.0;
    p.spacing = 0.25;
    CHECK(relief_surface_build(m, &p, NULL, &s, &err) == RELIEF_OK, "square with extent: %s",
          err.message);
    if (s) {
        topology t = topology_of(s);
        CHECK(t.euler == 1 && s->n_targets > 100, "extent: euler %ld, %zu targets", t.euler,
              s->n_targets);
        relief_surface_destroy(s);
        s = NULL;
    }
    relief_mesh_destroy(m);

    /* A point cloud cannot tell what it covers. */
    relief_mesh_create(10, 0, 0, &m, &err);
    for (int i = 0; i < 10; ++i)
        relief_mesh_positions(m)[3 * i] = i, relief_mesh_positions(m)[3 * i + 1] = i * i % 7;
    p = relief_params_default();
    CHECK(relief_surface_build(m, &p, NULL, &s, &err) == RELIEF_E_MESH && !s, "point cloud: %s",
          err.message);
    relief_mesh_destroy(m);
}

static void test_real(const char *data)
{
    char path[512];
    struct stat sb;
    relief_mesh *m = NULL;
    relief_surface *s = NULL;
    relief_params p = relief_params_default();
    relief_error err = {0};
    snprintf(path, sizeof path, "%s/bennu_radar/bennu.obj", data);
    if (stat(path, &sb) != 0) {
        printf("skip %s: not found\n", path);
        return;
    }
    /* Bennu is a whole body: as a sphere, there is nothing left to complete. */
    CHECK(relief_mesh_read(path, &m, NULL, &err) == RELIEF_OK, "%s", err.message);
    if (!m)
        return;
    p.fit = RELIEF_FIT_SPHERE;
    {
        relief_status st = relief_surface_build(m, &p, NULL, &s, &err);
        CHECK(st == RELIEF_E_MESH && strstr(err.message, "nothing to complete"),
              "bennu: %s (%s)", relief_status_name(st), err.message);
    }
    relief_surface_destroy(s);
    relief_mesh_destroy(m);
    s = NULL;
    m = NULL;

    /* The drill's zippered range scan folds over its cylinder on 2.6 % of
     * its area (33 triangles at the scan's ragged ends): dropped with the
     * vertices they touch, counted, and the rest completed, not refused. */
    snprintf(path, sizeof path, "%s/stanford_drill/drill_shaft_zip.ply", data);
    CHECK(relief_mesh_read(path, &m, NULL, &err) == RELIEF_OK, "%s", err.message);
    if (!m)
        return;
    {
        relief_smooth_options o = relief_smooth_options_default();
        relief_status st;
        p = relief_params_default();
        o.accept_poor_fit = 1; /* the scan's relief is 34 % of the thin shaft's radius */
        st = relief_surface_build(m, &p, &o, &s, &err);
        CHECK(st == RELIEF_OK, "drill_shaft_zip: %s", err.message);
        if (st == RELIEF_OK) {
            const relief_fold_stats *f = &s->folds;
            printf("drill_shaft_zip: %zu folded triangles (%.2f %% of the area), %zu "
                   "triangles and %zu vertices dropped; %zu captured, %zu targets\n",
                   f->triangles, 100.0 * f->area_fraction, f->triangles_dropped,
                   f->vertices_dropped, s->n_captured, s->n_targets);
            CHECK(f->triangles > 0 && f->area_fraction > 0.01 &&
                      f->area_fraction < RELIEF_FOLD_AREA_MAX,
                  "folds: %zu triangles, %.4f of the area", f->triangles, f->area_fraction);
            CHECK(f->triangles_dropped >= f->triangles && f->vertices_dropped > 0 &&
                      s->n_captured + f->vertices_dropped == relief_mesh_vertex_count(m),
                  "dropped %zu triangles, %zu vertices; %zu captured of %zu",
                  f->triangles_dropped, f->vertices_dropped, s->n_captured,
                  relief_mesh_vertex_count(m));
        }
    }
    relief_surface_destroy(s);
    relief_mesh_destroy(m);
}

int main(int argc, char **argv)
{
    test_sphere();
    test_cylinder();
    test_plane();
    test_fill();
    test_errors();
    if (argc > 1)
        test_real(argv[1]);
    return check_result();
}
