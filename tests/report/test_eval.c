/* relief_eval's closure fields (issue 61) on a small labelled PLY written
 * and read back: a relief grid whose middle disc is completed; closed, all
 * four are 0 in the result, the JSON and the text; with a triangle of the
 * patch removed, one open loop of 3 edges; with a completed vertex moved
 * past its rim, crossings. The grid's own outer border is far from the
 * patch and never counted. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "mesh/mesh.h"

#define N 24 /* squares a side */

/* An N x N grid of waves, label 1 within 5 of its middle. */
static relief_mesh *waves(void)
{
    relief_mesh *m = NULL;
    const size_t n1 = N + 1;
    if (relief_mesh_create(n1 * n1, 2 * N * N, RELIEF_MESH_LABELS, &m, NULL) != RELIEF_OK)
        exit(2);
    for (size_t j = 0; j < n1; ++j)
        for (size_t i = 0; i < n1; ++i) {
            double *p = m->pos + 3 * (j * n1 + i);
            p[0] = (double)i, p[1] = (double)j, p[2] = 0.3 * sin(1.3 * (double)i);
            m->label[j * n1 + i] = hypot(p[0] - N / 2, p[1] - N / 2) < 5.0;
        }
    for (size_t j = 0; j < N; ++j)
        for (size_t i = 0; i < N; ++i) {
            const uint32_t a = (uint32_t)(j * n1 + i), b = a + 1, c = b + (uint32_t)n1,
                           d = a + (uint32_t)n1;
            uint32_t *q = m->tri + 6 * (j * N + i);
            q[0] = a, q[1] = b, q[2] = c, q[3] = a, q[4] = c, q[5] = d;
        }
    return m;
}

/* m written as PLY, read back raw (the defects kept) and measured. */
static int eval_file(const relief_mesh *m, const char *name, relief_eval_result *r)
{
    char path[256];
    relief_read_options raw = {1};
    relief_mesh *back = NULL;
    relief_error err = {0};
    int ok;
    snprintf(path, sizeof path, "%s/%s.ply", check_tmpdir(), name);
    ok = relief_mesh_write(m, path, NULL, &err) == RELIEF_OK &&
         relief_mesh_read_with(path, &raw, &back, NULL, &err) == RELIEF_OK &&
         relief_eval(back, NULL, r, &err) == RELIEF_OK;
    CHECK(ok, "%s: %s", name, err.message);
    relief_mesh_destroy(back);
    remove(path);
    return ok;
}

/* The JSON has "key": value, the text "key: value". */
static int says(const relief_eval_result *r, const char *key, size_t value)
{
    char j[96], t[96];
    snprintf(j, sizeof j, "\"%s\": %zu", key, value);
    snprintf(t, sizeof t, "\n%s: %zu\n", key, value);
    return r->json && r->text && strstr(r->json, j) && strstr(r->text, t);
}

int main(void)
{
    relief_mesh *m = waves();
    relief_eval_result r;
    const size_t mid = (N / 2) * (N + 1) + N / 2, n1 = N + 1;
    if (eval_file(m, "closed", &r)) {
        CHECK(r.open_loops_completed == 0 && r.open_edges_completed == 0 &&
                  r.nonmanifold_edges_completed == 0 && r.self_intersections_completed == 0,
              "closed: %zu %zu %zu %zu", r.open_loops_completed, r.open_edges_completed,
              r.nonmanifold_edges_completed, r.self_intersections_completed);
        CHECK(says(&r, "open_loops_completed", 0) && says(&r, "open_edges_completed", 0) &&
                  says(&r, "nonmanifold_edges_completed", 0) &&
                  says(&r, "self_intersections_completed", 0) && strstr(r.json, "\"msi_"),
              "closed: the JSON and the text:\n%s", r.json);
        relief_eval_result_free(&r);
    }
    /* the patch's triangle (mid, mid + 1, mid + 1 + n1) dropped, the last
     * one in its place */
    memcpy(m->tri + 6 * (N / 2 * N + N / 2), m->tri + 3 * (m->nt - 1), 3 * sizeof *m->tri);
    m->nt -= 1;
    if (eval_file(m, "open", &r)) {
        CHECK(r.open_loops_completed == 1 && r.open_edges_completed == 3 &&
                  says(&r, "open_loops_completed", 1) && says(&r, "open_edges_completed", 3),
              "a patch triangle removed: %zu loops, %zu edges", r.open_loops_completed,
              r.open_edges_completed);
        relief_eval_result_free(&r);
    }
    relief_mesh_destroy(m);
    m = waves();
    m->pos[3 * (mid + 2 * n1) + 1] += 3.5; /* two rows up, moved 3.5 further: over its fan */
    if (eval_file(m, "crossing", &r)) {
        CHECK(r.self_intersections_completed > 0 && r.open_loops_completed == 0 &&
                  says(&r, "self_intersections_completed", r.self_intersections_completed),
              "a completed vertex moved past its rim: %zu crossing",
              r.self_intersections_completed);
        relief_eval_result_free(&r);
    }
    relief_mesh_destroy(m);
    rmdir(check_tmpdir());
    return check_result();
}
