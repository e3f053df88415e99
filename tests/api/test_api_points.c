/* relief_complete_points (relief/points.h) as a user meets it: the
 * defaults; every parameter out of range or NaN, every impossible
 * combination and NULL refused with its status and the field named; a hole
 * cut from a real scan (fertility, read by relief_points_read) completed,
 * and on scalar and host with auto's bytes;
 * the coloured PCD cloud read; a cancel at 50 % leaving the outputs as they
 * were; two threads giving the bytes of two serial calls.
 *   test_api_points DATA_DIR (../shared/data) */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>

#include "api_test.h"

static void test_defaults(void)
{
    relief_complete_points_params p = relief_complete_points_params_default();
    relief_error err = {0};
    CHECK(p.what == RELIEF_POINTS_ALL && !p.smooth_only && p.detail_histogram == 1 && !p.mesh,
          "what, smooth_only, detail_histogram, mesh");
    CHECK(p.k == 16 && p.smooth_steps == 20 && p.max_detail == 1.0 && p.band == 2.0, "base");
    CHECK(p.grid == 23 && p.cluster_size == 300 && p.iterations == 50 && p.seed == 1 &&
              p.grid_search == RELIEF_GRID_SEARCH_KDTREE,
          "texture");
    CHECK(!p.hole_mask && !p.hole_labels && !p.has_hole_ball && !p.sample_mask &&
              !p.sample_labels && !p.has_sample_box && !p.clone && !p.has_viewpoint &&
              p.non_finite_dropped == 0,
          "masks, clone, viewpoint");
    CHECK(p.run.backend == RELIEF_BACKEND_AUTO && p.run.device == -1 && !p.run.progress,
          "run");
    CHECK_STATUS(relief_complete_points_params_validate(&p, &err), RELIEF_OK, err, NULL);
    CHECK(strcmp(relief_grid_search_name(RELIEF_GRID_SEARCH_BRUTE), "brute") == 0, "name");
    CHECK(relief_complete_points_max_points(NULL) > 1000, "max points");
    p.run.max_memory = 1u << 20;
    CHECK(relief_complete_points_max_points(&p) < 1000, "max points within 1 MiB: %llu",
          (unsigned long long)relief_complete_points_max_points(&p));
}

/* p with one change must fail validation with `want`, naming `field`. */
#define BAD(change, want, field)                                                       \
    do {                                                                               \
        relief_complete_points_params p = relief_complete_points_params_default();     \
        relief_error err = {0};                                            \
        change;                                                                        \
        CHECK_STATUS(relief_complete_points_params_validate(&p, &err), want, err, field); \
    } while (0)

static void test_bad_params(void)
{
    static const uint8_t mask[4] = {1, 0, 0, 0};
    relief_error err = {0};
    CHECK_STATUS(relief_complete_points_params_validate(NULL, &err), RELIEF_E_USAGE, err, NULL);
    BAD(p.what = (relief_points_what)7, RELIEF_E_RANGE, "what");
    BAD(p.smooth_only = 2, RELIEF_E_RANGE, "smooth_only");
    BAD(p.mesh = -1, RELIEF_E_RANGE, "mesh");
    BAD(p.k = 5, RELIEF_E_RANGE, "k 5");
    BAD(p.k = 65, RELIEF_E_RANGE, "6..64");
    BAD(p.smooth_steps = -1, RELIEF_E_RANGE, "smooth_steps");
    BAD(p.max_detail = NAN, RELIEF_E_RANGE, "max_detail");
    BAD(p.max_detail = 101, RELIEF_E_RANGE, "max_detail");
    BAD(p.band = NAN, RELIEF_E_RANGE, "band");
    BAD(p.band = -1, RELIEF_E_RANGE, "band");
    BAD(p.grid = 24, RELIEF_E_RANGE, "grid 24");
    BAD(p.grid = 35, RELIEF_E_RANGE, "odd");
    BAD(p.cluster_size = 0, RELIEF_E_RANGE, "cluster_size");
    BAD(p.iterations = 0, RELIEF_E_RANGE, "iterations");
    BAD(p.grid_search = (relief_grid_search)3, RELIEF_E_RANGE, "grid_search");
    BAD((p.has_hole_ball = 1, p.hole_ball[3] = 0.0), RELIEF_E_RANGE, "hole_ball");
    BAD((p.has_hole_ball = 1, p.hole_ball[3] = -2.0), RELIEF_E_RANGE, "hole_ball");
    BAD((p.has_hole_ball = 1, p.hole_ball[3] = 1.0, p.hole_ball[1] = NAN), RELIEF_E_RANGE,
        "hole_ball");
    BAD((p.has_sample_box = 1, p.sample_box[0] = 1, p.sample_box[3] = 1, p.sample_box[4] = 1,
         p.sample_box[5] = 1),
        RELIEF_E_RANGE, "sample_box");
    BAD((p.has_viewpoint = 1, p.viewpoint[2] = INFINITY), RELIEF_E_RANGE, "viewpoint");
    BAD(p.run.device = 300, RELIEF_E_RANGE, "device");
    BAD(p.what = RELIEF_POINTS_COLOUR_ONLY, RELIEF_E_USAGE, "hole_mask");
    BAD((p.what = RELIEF_POINTS_COLOUR_ONLY, p.hole_mask = mask, p.smooth_only = 1),
        RELIEF_E_USAGE, "smooth_only");
    BAD((p.clone = (const relief_mesh *)mask, p.smooth_only = 1), RELIEF_E_USAGE, "clone");
    BAD(p.run.backend = RELIEF_BACKEND_OPENCL, RELIEF_E_USAGE, "kd-tree");
    BAD(p.run.device = 0, RELIEF_E_USAGE, "run.device");
    BAD((p.hole_labels = 1, p.sample_labels = 1), RELIEF_E_USAGE, "same labels");
    BAD((p.hole_labels = 1, p.hole_mask = mask), RELIEF_E_USAGE, "hole_mask");
    BAD((p.sample_labels = 1, p.has_sample_box = 1, p.sample_box[3] = p.sample_box[4] =
                                                         p.sample_box[5] = 1.0),
        RELIEF_E_USAGE, "sample_labels");
    /* A brute search may take a backend and a device. */
    BAD((p.grid_search = RELIEF_GRID_SEARCH_BRUTE, p.run.backend = RELIEF_BACKEND_SCALAR,
         p.run.device = 0),
        RELIEF_OK, NULL);
}

/* m without its vertices within r of c and their triangles (nor the
 * vertices that leaves in no triangle), made with relief_mesh_create. */
static relief_mesh *cut_ball(relief_mesh *m, const double c[3], double r, size_t *removed)
{
    const size_t n = relief_mesh_vertex_count(m), nt = relief_mesh_triangle_count(m);
    const double *pos = relief_mesh_positions(m);
    const uint32_t *tri = relief_mesh_triangles(m);
    uint32_t *to = malloc(n * sizeof *to);
    uint8_t *used = calloc(n, 1);
    size_t nk = 0, ntk = 0;
    relief_mesh *out = NULL;
    relief_error err = {0};
    for (size_t i = 0; i < n; ++i) {
        double d2 = 0.0;
        for (int a = 0; a < 3; ++a)
            d2 += (pos[3 * i + a] - c[a]) * (pos[3 * i + a] - c[a]);
        to[i] = d2 <= r * r ? UINT32_MAX : 0;
    }
    for (size_t t = 0; t < nt; ++t) {
        const uint32_t *v = tri + 3 * t;
        if (to[v[0]] || to[v[1]] || to[v[2]])
            continue;
        used[v[0]] = used[v[1]] = used[v[2]] = 1;
        ++ntk;
    }
    for (size_t i = 0; i < n; ++i)
        to[i] = used[i] ? (uint32_t)nk++ : UINT32_MAX;
    if (relief_mesh_create(nk, ntk, 0, &out, &err) == RELIEF_OK) {
        double *op = relief_mesh_positions(out);
        uint32_t *ot = relief_mesh_triangles(out);
        for (size_t i = 0; i < n; ++i)
            if (used[i])
                memcpy(op + 3 * (size_t)to[i], pos + 3 * i, 3 * sizeof *op);
        ntk = 0;
        for (size_t t = 0; t < nt; ++t) {
            const uint32_t *v = tri + 3 * t;
            if (to[v[0]] == UINT32_MAX || to[v[1]] == UINT32_MAX || to[v[2]] == UINT32_MAX)
                continue;
            for (int k = 0; k < 3; ++k)
                ot[3 * ntk + k] = to[v[k]];
            ++ntk;
        }
    }
    *removed = n - nk;
    free(to);
    free(used);
    return out;
}

typedef struct seen {
    double last, cancel_at;
    int calls, decreased;
} seen;

static int watch(void *ctx, double fraction)
{
    seen *s = ctx;
    s->decreased |= fraction < s->last;
    s->last = fraction;
    ++s->calls;
    return s->cancel_at > 0.0 && fraction >= s->cancel_at;
}

/* n x k values at a and b the same, or both absent. */
static int same_array(const void *a, const void *b, size_t bytes)
{
    return (!a && !b) || (a && b && memcmp(a, b, bytes) == 0);
}

/* Positions, normals, colours and labels the same, bit for bit. */
static int same_bytes(const relief_mesh *a, const relief_mesh *b)
{
    relief_mesh *x = (relief_mesh *)a, *y = (relief_mesh *)b;
    size_t n;
    if (!a || !b)
        return 0;
    n = relief_mesh_vertex_count(a);
    return n == relief_mesh_vertex_count(b) &&
           same_array(relief_mesh_positions(x), relief_mesh_positions(y), n * 3 * sizeof(double)) &&
           same_array(relief_mesh_normals(x), relief_mesh_normals(y), n * 3 * sizeof(double)) &&
           same_array(relief_mesh_colours(x), relief_mesh_colours(y), n * 3 * sizeof(float)) &&
           same_array(relief_mesh_labels(x), relief_mesh_labels(y), n);
}

/* The same call on one thread (scalar, the reference) and on the host's
 * threads (host): the same bytes as `out`, auto's. The sanitize pass
 * (RELIEF_TEST_PASS=sanitize) runs scalar only: host is auto's run again. */
static void test_backends(const relief_mesh *cut, const relief_complete_points_params *auto_p,
                          const relief_mesh *out)
{
    static const relief_backend backends[2] = {RELIEF_BACKEND_SCALAR, RELIEF_BACKEND_HOST};
    const char *pass = getenv("RELIEF_TEST_PASS");
    int n = pass && strcmp(pass, "sanitize") == 0 ? 1 : 2;
    for (int k = 0; k < n; ++k) {
        relief_complete_points_params p = *auto_p;
        relief_mesh *other = NULL;
        relief_error err = {0};
        p.run.backend = backends[k];
        p.run.progress = NULL;
        CHECK_STATUS(relief_complete_points(cut, &p, &other, NULL, &err), RELIEF_OK, err, NULL);
        CHECK(same_bytes(out, other), "backend %s: other bytes than auto's",
              relief_backend_name(backends[k]));
        relief_mesh_destroy(other);
    }
}

/* A hole cut from fertility, completed with few iterations: every point
 * finite, the input's first (label 0), the new ones (label 1) in the hole. */
static void test_real_scan(const char *data)
{
    static const double c[3] = {5.48, 31.18, 10.73}, r = 8.0;
    char path[1024];
    relief_error err = {0};
    relief_points_read_info info;
    relief_mesh *whole = NULL, *cut = NULL, *out = NULL;
    relief_complete_points_params p = relief_complete_points_params_default();
    relief_complete_points_report rep;
    seen s = {0.0, 0.0, 0, 0};
    size_t removed = 0;
    snprintf(path, sizeof path, "%s/real/fertility/fertility.off", data);
    CHECK_STATUS(relief_points_read(path, 0, &whole, &info, &err), RELIEF_OK, err, NULL);
    if (!whole)
        return;
    CHECK(strcmp(info.format, "off") == 0 && !info.has_viewpoint && info.height == 0,
          "fertility's read info: %s", info.format);
    cut = cut_ball(whole, c, r, &removed);
    CHECK(cut && removed > 10, "the cut removed %zu vertices", removed);
    p.iterations = 3;
    p.run.progress = watch;
    p.run.progress_ctx = &s;
    CHECK_STATUS(relief_complete_points(cut, &p, &out, &rep, &err), RELIEF_OK, err, NULL);
    if (out) {
        const size_t n = relief_mesh_vertex_count(cut), N = relief_mesh_vertex_count(out);
        const double *q = relief_mesh_positions(out);
        const uint8_t *label = relief_mesh_labels(out);
        size_t bad_label = 0, non_finite = 0, far = 0;
        CHECK(N > n && rep.added == N - n && rep.points_in == n && rep.holes >= 1,
              "%zu points in, %zu out, %zu added, %u holes", n, N, rep.added, rep.holes);
        CHECK(rep.added * 4 >= removed && rep.added <= removed * 4,
              "%zu added for %zu removed", rep.added, removed);
        CHECK(relief_mesh_normals(out) && relief_mesh_triangle_count(out) == 0,
              "normals, and no triangles without mesh");
        for (size_t i = 0; i < N; ++i) {
            double d2 = 0.0;
            bad_label += label[i] != (i < n ? RELIEF_LABEL_CAPTURED : RELIEF_LABEL_COMPLETED);
            for (int a = 0; a < 3; ++a) {
                non_finite += !isfinite(q[3 * i + a]);
                d2 += (q[3 * i + a] - c[a]) * (q[3 * i + a] - c[a]);
            }
            far += i >= n && !(sqrt(d2) <= r + 3.0 * rep.spacing);
        }
        CHECK(!bad_label && !non_finite && !far, "%zu wrong labels, %zu non-finite "
              "coordinates, %zu new points away from the hole", bad_label, non_finite, far);
        CHECK(memcmp(q, relief_mesh_positions(cut), n * 3 * sizeof *q) == 0,
              "the input's points moved");
        CHECK(rep.json && strstr(rep.json, "\"command\": \"complete-points\"") &&
                  strstr(rep.json, "\"input\": null") && strstr(rep.json, "\"energy\": [") &&
                  api_json_numbers_use_dots(rep.json),
              "the report's JSON: %.200s", rep.json ? rep.json : "(none)");
        CHECK(rep.iterations >= 1 && rep.iterations <= 3 && rep.exemplars > 0, "texture");
        { /* the hole model: the cut is listed, filled, 2 r to 4 r across (a ball
             * cut on a curved surface leaves no circle) */
            const relief_hole *cut_hole = NULL;
            for (size_t h = 0; h < rep.n_hole_list; ++h)
                if (!strcmp(rep.hole_list[h].fate, "filled") &&
                    (!cut_hole || rep.hole_list[h].rim_points > cut_hole->rim_points))
                    cut_hole = rep.hole_list + h;
            CHECK(cut_hole && cut_hole->across > r && cut_hole->across < 4 * r &&
                      rep.max_hole > 4 * r && strstr(rep.json, "\"fate\": \"filled\""),
                  "the cut's rim in the report: %g across (max_hole %g)",
                  cut_hole ? cut_hole->across : 0.0, rep.max_hole);
        }
        CHECK(s.calls > 3 && !s.decreased && s.last > 0.999999, "progress: %d calls, last %g%s",
              s.calls, s.last, s.decreased ? ", decreased" : "");
        relief_complete_points_report_free(&rep);
        CHECK(!rep.json, "report freed");
        test_backends(cut, &p, out);
    }
    relief_mesh_destroy(out);
    /* A mask read from labels the input does not have; too little memory. */
    p = relief_complete_points_params_default();
    p.hole_labels = 1;
    out = NULL;
    CHECK_STATUS(relief_complete_points(cut, &p, &out, NULL, &err), RELIEF_E_USAGE, err,
                 "hole_labels");
    CHECK(!out, "*out set on failure");
    p = relief_complete_points_params_default();
    p.run.max_memory = 1u << 20;
    CHECK_STATUS(relief_complete_points(cut, &p, &out, NULL, &err), RELIEF_E_NOMEM, err,
                 "max_memory");
    CHECK_STATUS(relief_complete_points(NULL, &p, &out, NULL, &err), RELIEF_E_USAGE, err, "in");
    CHECK_STATUS(relief_complete_points(cut, &p, NULL, NULL, &err), RELIEF_E_USAGE, err, "out");
    CHECK_STATUS(relief_complete_points(cut, NULL, &out, NULL, &err), RELIEF_E_USAGE, err,
                 NULL);
    p = relief_complete_points_params_default();
    CHECK_STATUS(relief_complete_points(whole, &p, &out, NULL, &err), RELIEF_E_RANGE, err,
                 "nothing to fill");
    relief_mesh_destroy(cut);
    relief_mesh_destroy(whole);
}

static void test_read_pcd(const char *data)
{
    char path[1024];
    relief_error err = {0};
    relief_points_read_info info;
    relief_mesh *m = NULL;
    snprintf(path, sizeof path, "%s/points/milk_color.pcd", data);
    CHECK_STATUS(relief_points_read(path, 0, &m, &info, &err), RELIEF_OK, err, NULL);
    if (m) {
        CHECK(relief_mesh_vertex_count(m) == 13704 && relief_mesh_triangle_count(m) == 0 &&
                  relief_mesh_colours(m),
              "milk: %zu points, %zu triangles", relief_mesh_vertex_count(m),
              relief_mesh_triangle_count(m));
        CHECK(strcmp(info.format, "pcd") == 0 && info.width == 13704 && info.height == 1 &&
                  info.non_finite_dropped == 0 && info.has_viewpoint &&
                  info.viewpoint[0] == 0.0 && info.viewpoint[2] == 0.0,
              "milk's read info: %s %zu x %zu", info.format, info.width, info.height);
        CHECK_STATUS(relief_mesh_validate(m, &err), RELIEF_OK, err, NULL);
    }
    relief_mesh_destroy(m);
    m = NULL;
    CHECK_STATUS(relief_points_read(path, 1000, &m, NULL, &err), RELIEF_E_NOMEM, err, "1000");
    CHECK(!m, "*out set over max_points");
    CHECK_STATUS(relief_points_read("/nonexistent/x.pcd", 0, &m, NULL, &err), RELIEF_E_IO, err,
                 "/nonexistent/x.pcd");
    CHECK_STATUS(relief_points_read(NULL, 0, &m, NULL, &err), RELIEF_E_USAGE, err, "path");
}

/* A small coloured plane with a hole (synth plane-waves). */
static relief_mesh *plane(uint32_t seed)
{
    relief_synth_params sp = relief_synth_params_default();
    relief_error err = {0};
    relief_mesh *m = NULL;
    sp.kind = RELIEF_SYNTH_PLANE_WAVES;
    sp.seed = seed;
    sp.vertices = 1200;
    sp.colour = 1;
    CHECK_STATUS(relief_synth(&sp, &m, NULL, &err), RELIEF_OK, err, NULL);
    return m;
}

static relief_complete_points_params small_params(void)
{
    relief_complete_points_params p = relief_complete_points_params_default();
    p.iterations = 4;
    p.grid = 11;
    p.cluster_size = 100;
    p.max_hole = 1e30; /* the plane's hole is wider than a quarter of its box */
    return p;
}

static void test_cancel(void)
{
    relief_mesh *in = plane(3), *out = (relief_mesh *)&out; /* a value to keep */
    relief_complete_points_params p = small_params();
    relief_complete_points_report rep;
    relief_error err = {0};
    seen s = {0.0, 0.5, 0, 0};
    if (!in)
        return;
    memset(&rep, 0, sizeof rep);
    rep.added = 12345;
    p.run.progress = watch;
    p.run.progress_ctx = &s;
    CHECK_STATUS(relief_complete_points(in, &p, &out, &rep, &err), RELIEF_E_CANCELLED, err,
                 "cancelled");
    CHECK(out == (relief_mesh *)&out && rep.added == 12345 && !rep.json,
          "a cancel touched *out or the report");
    CHECK(s.last >= 0.5 && s.last < 1.0 && !s.decreased, "cancelled at %g", s.last);
    relief_mesh_destroy(in);
}

typedef struct job {
    const relief_mesh *in;
    relief_mesh *out;
    relief_status st;
    relief_error err;
} job;

static void *run_job(void *arg)
{
    job *j = arg;
    relief_complete_points_params p = small_params();
    j->out = NULL;
    j->st = relief_complete_points(j->in, &p, &j->out, NULL, &j->err);
    return NULL;
}

static void test_threads(void)
{
    relief_mesh *in[2] = {plane(1), plane(2)};
    job serial[2], both[2];
    pthread_t th[2];
    if (!in[0] || !in[1])
        return;
    for (int i = 0; i < 2; ++i) {
        memset(&serial[i], 0, sizeof serial[i]);
        serial[i].in = in[i];
        run_job(&serial[i]);
        CHECK_STATUS(serial[i].st, RELIEF_OK, serial[i].err, NULL);
        memset(&both[i], 0, sizeof both[i]);
        both[i].in = in[i];
    }
    for (int i = 0; i < 2; ++i)
        CHECK(pthread_create(&th[i], NULL, run_job, &both[i]) == 0, "thread %d", i);
    for (int i = 0; i < 2; ++i) {
        pthread_join(th[i], NULL);
        CHECK_STATUS(both[i].st, RELIEF_OK, both[i].err, NULL);
        CHECK(serial[i].out && relief_mesh_vertex_count(serial[i].out) >
                                   relief_mesh_vertex_count(in[i]),
              "input %d: nothing added", i);
        CHECK(same_bytes(serial[i].out, both[i].out),
              "input %d: two threads at once and serial calls differ", i);
        relief_mesh_destroy(serial[i].out);
        relief_mesh_destroy(both[i].out);
        relief_mesh_destroy(in[i]);
    }
}

int main(int argc, char **argv)
{
    const char *data = argc > 1 ? argv[1] : "../shared/data";
    if (!api_test_locale())
        return 2;
    test_defaults();
    test_bad_params();
    test_real_scan(data);
    test_read_pcd(data);
    test_cancel();
    test_threads();
    API_TEST_END();
}
