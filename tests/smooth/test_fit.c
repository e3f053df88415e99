/* Tests of host/smooth/fit.c: the geometry helpers on known primitives, synthetic
 * noisy primitives with and without gross outliers, degenerate input, and
 * three real scans whose primitive is known (see each SOURCE.txt).
 *
 * Usage: test_fit [DATA_DIR]   DATA_DIR holds the real scans
 * (shared/data/real). Exit 0 on pass, 1 on failure, 77 (skip) when every
 * synthetic check passed but a real scan is missing. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "check.h"
#include "base/error.h"
#include "base/rng.h"
#include "mesh/mesh.h"
#include "smooth/fit.h"

#define PI 3.14159265358979323846

/* ---------------------------------------------------------------- helpers */

static double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void unit(double a[3])
{
    double l = sqrt(dot(a, a));
    for (int k = 0; k < 3; ++k)
        a[k] /= l;
}

static void random_unit(relief_rng *rng, double a[3])
{
    for (int k = 0; k < 3; ++k)
        a[k] = relief_rng_normal(rng);
    unit(a);
}

/* u, v completing unit a to an orthonormal frame. */
static void frame(const double a[3], double u[3], double v[3])
{
    double e[3] = {1, 0, 0};
    if (fabs(a[0]) > 0.9) {
        e[0] = 0;
        e[1] = 1;
    }
    for (int k = 0; k < 3; ++k)
        u[k] = e[k] - dot(e, a) * a[k];
    unit(u);
    v[0] = a[1] * u[2] - a[2] * u[1];
    v[1] = a[2] * u[0] - a[0] * u[2];
    v[2] = a[0] * u[1] - a[1] * u[0];
}

/* Angle in degrees between two lines (directions up to sign). */
static double line_angle_deg(const double a[3], const double b[3])
{
    double c = fabs(dot(a, b)) / sqrt(dot(a, a) * dot(b, b));
    return acos(c > 1.0 ? 1.0 : c) * 180.0 / PI;
}

/* Distance from x to the line through p along unit d. */
static double point_line_distance(const double x[3], const double p[3],
                                  const double d[3])
{
    double w[3], t;
    for (int k = 0; k < 3; ++k)
        w[k] = x[k] - p[k];
    t = dot(w, d);
    for (int k = 0; k < 3; ++k)
        w[k] -= t * d[k];
    return sqrt(dot(w, w));
}

static double dist3(const double a[3], const double b[3])
{
    double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return sqrt(dot(d, d));
}

static void add_noise(relief_rng *rng, double *pts, size_t n, double sigma)
{
    for (size_t i = 0; i < 3 * n; ++i)
        pts[i] += sigma * relief_rng_normal(rng);
}

/* Replace 3% of the points by scanner spikes: moved by 5% to 100% of `size`
 * in a random direction. */
static void add_spikes(relief_rng *rng, double *pts, size_t n, double size)
{
    size_t n_out = (size_t)(0.03 * (double)n + 0.5);
    for (size_t j = 0; j < n_out; ++j) {
        size_t i = j * n / n_out;
        double d[3], len = size * (0.05 + 0.95 * relief_rng_uniform(rng));
        random_unit(rng, d);
        for (int k = 0; k < 3; ++k)
            pts[3 * i + k] += len * d[k];
    }
}

static const char *name_of(relief_fit_model m) { return relief_fit_model_name(m); }

/* ----------------------------------------------------- synthetic shapes */

enum { N_SYNTH = 2000 };

typedef struct truth {
    relief_fit_model model;
    double point[3]; /* plane: a point on it; sphere: centre; cylinder: axis point */
    double dir[3];   /* plane normal or cylinder axis */
    double radius;   /* sphere, cylinder; disc radius for the plane */
} truth;

/* Disc of radius 1 in a random plane. */
static void make_plane(relief_rng *rng, double *pts, truth *t)
{
    double u[3], v[3];
    t->model = RELIEF_FIT_PLANE;
    t->radius = 1.0;
    random_unit(rng, t->dir);
    for (int k = 0; k < 3; ++k)
        t->point[k] = 10.0 * (relief_rng_uniform(rng) - 0.5);
    frame(t->dir, u, v);
    for (size_t i = 0; i < N_SYNTH; ++i) {
        double r = sqrt(relief_rng_uniform(rng)), a = 2 * PI * relief_rng_uniform(rng);
        for (int k = 0; k < 3; ++k)
            pts[3 * i + k] = t->point[k] + r * (cos(a) * u[k] + sin(a) * v[k]);
    }
}

/* Cap of half-angle 60 degrees (a quarter of the sphere's area) of a sphere
 * of radius 2.5, uniform over the area. */
static void make_sphere(relief_rng *rng, double *pts, truth *t)
{
    double w[3], u[3], v[3], c60 = cos(60.0 * PI / 180.0);
    t->model = RELIEF_FIT_SPHERE;
    t->radius = 2.5;
    for (int k = 0; k < 3; ++k)
        t->point[k] = 10.0 * (relief_rng_uniform(rng) - 0.5);
    random_unit(rng, w);
    frame(w, u, v);
    for (size_t i = 0; i < N_SYNTH; ++i) {
        double ct = c60 + (1.0 - c60) * relief_rng_uniform(rng);
        double st = sqrt(1.0 - ct * ct), a = 2 * PI * relief_rng_uniform(rng);
        for (int k = 0; k < 3; ++k)
            pts[3 * i + k] = t->point[k] + t->radius * (ct * w[k] + st * (cos(a) * u[k] +
                                                                       sin(a) * v[k]));
    }
}

/* 120-degree arc of a cylinder of radius 1.7, axial length 4 radii. */
static void make_cylinder(relief_rng *rng, double *pts, truth *t)
{
    double u[3], v[3];
    t->model = RELIEF_FIT_CYLINDER;
    t->radius = 1.7;
    for (int k = 0; k < 3; ++k)
        t->point[k] = 10.0 * (relief_rng_uniform(rng) - 0.5);
    random_unit(rng, t->dir);
    frame(t->dir, u, v);
    for (size_t i = 0; i < N_SYNTH; ++i) {
        double a = (relief_rng_uniform(rng) - 0.5) * 120.0 * PI / 180.0;
        double z = (relief_rng_uniform(rng) - 0.5) * 4.0 * t->radius;
        for (int k = 0; k < 3; ++k)
            pts[3 * i + k] = t->point[k] + z * t->dir[k] +
                             t->radius * (cos(a) * u[k] + sin(a) * v[k]);
    }
}

/* The projection, normal and distance of every point agree with each other:
 * the projection lies on the primitive and p - projection = d * normal. */
static void check_geometry_consistency(const char *name,
                                       const relief_fit_primitive *prim,
                                       const double *pts, size_t n, double size)
{
    double worst_on = 0.0, worst_d = 0.0, worst_unit = 0.0;
    for (size_t i = 0; i < n; ++i) {
        const double *p = pts + 3 * i;
        double q[3], nrm[3], d = relief_fit_distance(prim, p);
        relief_fit_project(prim, p, q);
        relief_fit_normal(prim, p, nrm);
        worst_on = fmax(worst_on, fabs(relief_fit_distance(prim, q)));
        worst_unit = fmax(worst_unit, fabs(sqrt(dot(nrm, nrm)) - 1.0));
        for (int k = 0; k < 3; ++k)
            worst_d = fmax(worst_d, fabs(p[k] - q[k] - d * nrm[k]));
    }
    CHECK(worst_on <= 1e-12 * size && worst_d <= 1e-12 * size && worst_unit <= 1e-12,
          "%s: projection off the surface by %g, D vs d*n by %g, |n|-1 %g", name,
          worst_on, worst_d, worst_unit);
}

/* Fit the requested model and auto to one synthetic set; print and check. */
static void check_synthetic(const char *name, const truth *t, const double *pts,
                            double noise, double min_inliers)
{
    relief_fit_result fit, fa;
    relief_error err = {0};
    relief_status st;
    double r_err = 0.0, ang = 0.0, off = 0.0;

    st = relief_fit(pts, NULL, N_SYNTH, t->model, &fit, &err);
    CHECK(st == RELIEF_OK, "%s: relief_fit failed: %s", name, err.message);
    if (st != RELIEF_OK)
        return;
    if (t->model == RELIEF_FIT_PLANE) {
        ang = line_angle_deg(fit.prim.dir, t->dir);
        off = fabs(relief_fit_distance(&fit.prim, t->point)) / t->radius;
    } else {
        r_err = fit.prim.radius / t->radius - 1.0;
        if (t->model == RELIEF_FIT_SPHERE) {
            off = dist3(fit.prim.point, t->point) / t->radius;
        } else {
            ang = line_angle_deg(fit.prim.dir, t->dir);
            off = point_line_distance(t->point, fit.prim.point, fit.prim.dir) / t->radius;
        }
    }
    st = relief_fit(pts, NULL, N_SYNTH, RELIEF_FIT_AUTO, &fa, &err);
    CHECK(st == RELIEF_OK, "%s: auto fit failed: %s", name, err.message);
    printf("%-22s radius err %+.4f%%  angle %s%.4f deg  offset %.5f R  rms/noise %.3f  "
           "inliers %.3f  auto=%s\n    explicit: %s\n    auto:     %s\n",
           name, 100.0 * r_err, t->model == RELIEF_FIT_SPHERE ? "(n/a) " : "", ang, off, fit.rms / noise, fit.inlier_fraction,
           st == RELIEF_OK ? name_of(fa.prim.model) : "error", fit.reason,
           st == RELIEF_OK ? fa.reason : err.message);

    CHECK(fit.prim.model == t->model, "%s: model %s", name, name_of(fit.prim.model));
    CHECK(fabs(r_err) <= 0.005, "%s: radius error %.4f%% > 0.5%%", name, 100 * r_err);
    CHECK(ang <= 0.5, "%s: axis/normal off by %.4f deg > 0.5", name, ang);
    CHECK(off <= 0.005, "%s: centre/axis/plane offset %.5f R > 0.005 R", name, off);
    CHECK(fit.rms >= 0.8 * noise && fit.rms <= 1.2 * noise,
          "%s: rms %.5g not within 20%% of the noise %.5g", name, fit.rms, noise);
    CHECK(fit.inlier_fraction >= min_inliers, "%s: inlier fraction %.3f < %.3f", name,
          fit.inlier_fraction, min_inliers);
    CHECK(!fit.poor_fit, "%s: flagged as a poor fit", name);
    CHECK(fit.n_points == N_SYNTH, "%s: n_points %zu", name, fit.n_points);
    CHECK(st == RELIEF_OK && fa.prim.model == t->model, "%s: auto chose %s", name,
          name_of(fa.prim.model));
    check_geometry_consistency(name, &fit.prim, pts, N_SYNTH, t->radius);
}

static void test_synthetic(void)
{
    typedef void (*maker)(relief_rng *, double *, truth *);
    static const maker makers[3] = {make_plane, make_sphere, make_cylinder};
    static const char *names[3] = {"plane", "sphere-cap", "cylinder-120deg"};
    double *pts = malloc(3 * N_SYNTH * sizeof *pts);
    relief_rng rng;
    char name[64];

    if (!pts) {
        CHECK(pts != NULL, "out of memory");
        return;
    }
    relief_rng_seed(&rng, 12345u);
    for (int m = 0; m < 3; ++m) {
        for (int trial = 0; trial < 3; ++trial) {
            truth t;
            double noise;
            makers[m](&rng, pts, &t);
            noise = 0.005 * t.radius;
            add_noise(&rng, pts, N_SYNTH, noise);
            snprintf(name, sizeof name, "%s #%d", names[m], trial);
            check_synthetic(name, &t, pts, noise, 0.97);

            /* The same surface with 3% spikes: outliers must not move it. */
            add_spikes(&rng, pts, N_SYNTH, t.radius);
            snprintf(name, sizeof name, "%s #%d +3%%", names[m], trial);
            check_synthetic(name, &t, pts, noise, 0.94);
        }
    }
    free(pts);
}

/* ------------------------------------------------------- known answers */

static void test_geometry_known(void)
{
    relief_fit_primitive plane = {RELIEF_FIT_PLANE, {0, 0, 1}, {0, 0, 1}, 0.0};
    relief_fit_primitive sphere = {RELIEF_FIT_SPHERE, {1, 2, 3}, {0, 0, 0}, 2.0};
    relief_fit_primitive cyl = {RELIEF_FIT_CYLINDER, {0, 0, 0}, {0, 0, 1}, 1.0};
    double p[3], q[3], n[3];

    p[0] = 5; p[1] = -3; p[2] = 4;
    CHECK(fabs(relief_fit_distance(&plane, p) - 3.0) < 1e-15, "plane distance");
    relief_fit_project(&plane, p, q);
    CHECK(q[0] == 5 && q[1] == -3 && fabs(q[2] - 1.0) < 1e-15, "plane projection");
    relief_fit_normal(&plane, p, n);
    CHECK(n[0] == 0 && n[1] == 0 && n[2] == 1, "plane normal");

    p[0] = 1; p[1] = 2; p[2] = 6;
    CHECK(fabs(relief_fit_distance(&sphere, p) - 1.0) < 1e-15, "sphere distance");
    relief_fit_project(&sphere, p, q);
    CHECK(fabs(q[0] - 1) + fabs(q[1] - 2) + fabs(q[2] - 5) < 1e-15, "sphere projection");
    relief_fit_normal(&sphere, p, n);
    CHECK(fabs(n[2] - 1.0) < 1e-15, "sphere normal");
    p[2] = 3.5; /* inside: negative distance, normal still outward */
    CHECK(fabs(relief_fit_distance(&sphere, p) + 1.5) < 1e-15, "sphere inside");
    relief_fit_normal(&sphere, p, n);
    CHECK(fabs(n[2] - 1.0) < 1e-15, "sphere inside normal");

    p[0] = 0; p[1] = 3; p[2] = 7;
    CHECK(fabs(relief_fit_distance(&cyl, p) - 2.0) < 1e-15, "cylinder distance");
    relief_fit_project(&cyl, p, q);
    CHECK(fabs(q[0]) + fabs(q[1] - 1) + fabs(q[2] - 7) < 1e-15, "cylinder projection");
    relief_fit_normal(&cyl, p, n);
    CHECK(fabs(n[1] - 1.0) < 1e-15, "cylinder normal");
    p[0] = p[1] = 0; /* on the axis: a unit normal orthogonal to it */
    relief_fit_normal(&cyl, p, n);
    CHECK(fabs(dot(n, n) - 1.0) < 1e-15 && fabs(n[2]) < 1e-15, "cylinder axis normal");

    /* Aliasing allowed: project in place. */
    p[0] = 0; p[1] = 3; p[2] = 7;
    relief_fit_project(&cyl, p, p);
    CHECK(fabs(p[1] - 1.0) < 1e-15, "in-place projection");
}

/* Exact, noise-free data: the fit reproduces it to rounding. */
static void test_exact(void)
{
    double pts[3 * 40];
    relief_fit_result r;
    relief_error err = {0};
    relief_status st;

    for (int i = 0; i < 40; ++i) {
        double a = 2 * PI * i / 40.0, b = PI * (i % 7 + 1) / 9.0;
        pts[3 * i + 0] = 3.0 + 2.0 * sin(b) * cos(a);
        pts[3 * i + 1] = -1.0 + 2.0 * sin(b) * sin(a);
        pts[3 * i + 2] = 0.5 + 2.0 * cos(b);
    }
    st = relief_fit(pts, NULL, 40, RELIEF_FIT_AUTO, &r, &err);
    CHECK(st == RELIEF_OK && r.prim.model == RELIEF_FIT_SPHERE &&
              fabs(r.prim.radius - 2.0) < 1e-9 && r.rms < 1e-9 &&
              r.inlier_fraction == 1.0,
          "exact sphere: %s r %.17g rms %g (%s)", name_of(r.prim.model),
          r.prim.radius, r.rms, err.message);

    /* A flat grid: auto keeps the plane (a sphere is not even determined). */
    for (int i = 0; i < 40; ++i) {
        pts[3 * i + 0] = i % 8;
        pts[3 * i + 1] = i / 8;
        pts[3 * i + 2] = 0.25 * (i % 8) - 0.5 * (i / 8) + 7.0;
    }
    st = relief_fit(pts, NULL, 40, RELIEF_FIT_AUTO, &r, &err);
    CHECK(st == RELIEF_OK && r.prim.model == RELIEF_FIT_PLANE && r.rms < 1e-12,
          "exact plane: %s rms %g (%s)", name_of(r.prim.model), r.rms, err.message);
    printf("exact plane grid   auto: %s\n", r.reason);
}

/* --------------------------------------------------------- bad input */

static void expect_error(const char *what, const double *pts, size_t n,
                         relief_fit_model model, relief_status want)
{
    relief_fit_result r;
    relief_error err = {0};
    relief_status st;

    memset(&r, 0xA5, sizeof r);
    st = relief_fit(pts, NULL, n, model, &r, &err);
    CHECK(st == want, "%s (%s): status %s, expected %s", what, name_of(model),
          relief_status_name(st), relief_status_name(want));
    CHECK(err.status == want && err.message[0] != '\0',
          "%s (%s): no message", what, name_of(model));
    CHECK(r.n_points == (size_t)0xA5A5A5A5A5A5A5A5ull,
          "%s (%s): output written on failure", what, name_of(model));
    printf("%-10s %-8s -> %s: %s\n", what, name_of(model), relief_status_name(st),
           err.message);
}

static void test_degenerate(void)
{
    static const relief_fit_model all[4] = {RELIEF_FIT_AUTO, RELIEF_FIT_PLANE,
                                            RELIEF_FIT_SPHERE, RELIEF_FIT_CYLINDER};
    double two[6] = {0, 0, 0, 1, 1, 1};
    double same[30], line[30], flat[30], bad[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    relief_fit_result r;

    for (int i = 0; i < 10; ++i) {
        same[3 * i] = 1.5;
        same[3 * i + 1] = -2.25;
        same[3 * i + 2] = 1e3 + 0.1;
        line[3 * i] = 1.0 + 0.3 * i;
        line[3 * i + 1] = 2.0 - 0.7 * i;
        line[3 * i + 2] = 0.1 * i * 3;
        flat[3 * i] = cos(0.6 * i);
        flat[3 * i + 1] = sin(0.6 * i) + 0.01 * i * i;
        flat[3 * i + 2] = 5.0;
    }
    for (int m = 0; m < 4; ++m) {
        expect_error("2 points", two, 2, all[m], RELIEF_E_MESH);
        expect_error("identical", same, 10, all[m], RELIEF_E_MESH);
        expect_error("collinear", line, 10, all[m], RELIEF_E_MESH);
    }
    expect_error("3 points", bad, 3, RELIEF_FIT_SPHERE, RELIEF_E_MESH);
    expect_error("4 points", flat, 4, RELIEF_FIT_CYLINDER, RELIEF_E_MESH);
    expect_error("coplanar", flat, 10, RELIEF_FIT_SPHERE, RELIEF_E_MESH);
    expect_error("empty", NULL, 0, RELIEF_FIT_AUTO, RELIEF_E_USAGE);
    bad[4] = NAN;
    expect_error("NaN", bad, 3, RELIEF_FIT_PLANE, RELIEF_E_MESH);
    expect_error("model 7", flat, 10, (relief_fit_model)7, RELIEF_E_USAGE);
    CHECK(relief_fit(flat, NULL, 10, RELIEF_FIT_PLANE, NULL, NULL) == RELIEF_E_USAGE,
          "NULL out accepted");
    CHECK(relief_fit(bad, NULL, 3, RELIEF_FIT_AUTO, &r, NULL) == RELIEF_E_MESH,
          "NaN accepted under auto");
    /* Three points define a plane exactly; auto then has only the plane. */
    bad[4] = 1.0;
    CHECK(relief_fit(bad, NULL, 3, RELIEF_FIT_AUTO, &r, NULL) == RELIEF_OK &&
              r.prim.model == RELIEF_FIT_PLANE && fabs(fabs(r.prim.dir[2]) - 1) < 1e-12,
          "3 points: %s", name_of(r.prim.model));
}

/* ---------------------------------------------------------- real scans */

/* Returns 0 checked, 1 missing file (skip). */
static int check_real(const char *dir, const char *file, relief_fit_model model,
                      relief_fit_model want_auto, double want_radius,
                      double want_rms)
{
    char path[1024];
    relief_mesh *mesh = NULL;
    relief_error err = {0};
    relief_fit_result fit, fa;
    relief_status st;
    FILE *f;
    clock_t t0;

    snprintf(path, sizeof path, "%s/%s", dir, file);
    f = fopen(path, "rb");
    if (!f) {
        printf("SKIP %s: not found\n", path);
        return 1;
    }
    fclose(f);
    st = relief_mesh_read(path, &mesh, NULL, &err);
    CHECK(st == RELIEF_OK, "%s: read failed: %s", path, err.message);
    if (st != RELIEF_OK)
        return 0;
    t0 = clock();
    st = relief_fit_mesh(mesh, model, &fit, &err);
    printf("    (%s fit of %zu points: %.3f s CPU)\n", name_of(model), mesh->nv,
           (double)(clock() - t0) / CLOCKS_PER_SEC);
    CHECK(st == RELIEF_OK, "%s: %s fit failed: %s", file, name_of(model), err.message);
    if (st == RELIEF_OK) {
        printf("%-40s %s: r %.6g rms %.6g (all points %.6g; inlier fraction %.3f, "
               "trimmed set %zu/%zu) poor %d\n    point (%.6g %.6g %.6g) "
               "dir (%.5f %.5f %.5f)\n    %s\n",
               file, name_of(model), fit.prim.radius, fit.rms, fit.rms_all,
               fit.inlier_fraction,
               fit.n_inliers, fit.n_points, fit.poor_fit, fit.prim.point[0],
               fit.prim.point[1], fit.prim.point[2], fit.prim.dir[0], fit.prim.dir[1],
               fit.prim.dir[2], fit.reason);
        if (want_radius > 0.0)
            CHECK(fabs(fit.prim.radius / want_radius - 1.0) <= 0.02,
                  "%s: radius %.6g, expected %.6g within 2%%", file,
                  fit.prim.radius, want_radius);
        /* SOURCE.txt's rms is that of the plain least-squares fit over all
         * points, the minimum of rms_all; the trimmed fit sits a little
         * above it. */
        if (want_rms > 0.0)
            CHECK(fit.rms_all >= 0.999 * want_rms && fit.rms_all <= 1.05 * want_rms,
                  "%s: rms over all points %.6g, expected %.6g to +5%%", file,
                  fit.rms_all, want_rms);
        CHECK(fit.rms <= fit.rms_all && !fit.poor_fit, "%s: rms %.6g over the inliers, "
              "%.6g over all; poor %d", file, fit.rms, fit.rms_all, fit.poor_fit);
    }
    t0 = clock();
    st = relief_fit_mesh(mesh, RELIEF_FIT_AUTO, &fa, &err);
    printf("    (auto fit: %.3f s CPU)\n", (double)(clock() - t0) / CLOCKS_PER_SEC);
    CHECK(st == RELIEF_OK && fa.prim.model == want_auto, "%s: auto chose %s (%s), "
          "expected %s", file, st == RELIEF_OK ? name_of(fa.prim.model) : "error",
          st == RELIEF_OK ? fa.reason : err.message, name_of(want_auto));
    if (st == RELIEF_OK)
        printf("    auto: %s\n", fa.reason);
    relief_mesh_destroy(mesh);
    return 0;
}

int main(int argc, char **argv)
{
    clock_t t0 = clock();
    int missing = 0;

    test_geometry_known();
    test_exact();
    test_degenerate();
    test_synthetic();
    if (argc < 2) {
        printf("SKIP real scans: no data directory given (usage: %s DATA_DIR)\n",
               argv[0]);
        missing = 1;
    } else {
        /* Known values from each SOURCE.txt: drill r 0.8339e-3 (rms 0.103e-3
         * of flute relief), Bennu r 0.2452 (rms 0.0119), frag_115 plane rms
         * 0.003997 over all points. */
        missing += check_real(argv[1], "stanford_drill/drill_shaft_vrip.ply",
                              RELIEF_FIT_CYLINDER, RELIEF_FIT_CYLINDER, 0.834e-3,
                              0.0);
        missing += check_real(argv[1], "bennu_radar/bennu.obj", RELIEF_FIT_SPHERE,
                              RELIEF_FIT_SPHERE, 0.2452, 0.0);
        missing += check_real(argv[1], "open3d_frag115/frag_115.ply", RELIEF_FIT_PLANE,
                              RELIEF_FIT_PLANE, 0.0, 0.003997);
    }
    printf("test_fit: %.2f s CPU\n", (double)(clock() - t0) / CLOCKS_PER_SEC);
    if (check_result() != 0)
        return 1;
    return missing ? 77 : 0;
}
