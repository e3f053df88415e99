/* The core of the public API as a user meets it: the version, statuses and
 * their names, run options, meshes and their files, synthetic surfaces,
 * devices, and every enumeration's names. */
#include <math.h>
#include <stdlib.h>
#include <unistd.h>

#include "api_test.h"

static void test_status(void)
{
    CHECK(strcmp(relief_version(), RELIEF_VERSION_STRING) == 0, "version %s vs header %s",
          relief_version(), RELIEF_VERSION_STRING);
    CHECK(strcmp(relief_status_name(RELIEF_E_CANCELLED), "cancelled") == 0, "name");
    CHECK(relief_status_exit_code(RELIEF_E_CANCELLED) == 130, "exit code");
    CHECK(strcmp(relief_strerror((relief_status)999), "unknown status") == 0, "unknown");
    CHECK(strcmp(relief_backend_name(RELIEF_BACKEND_OPENCL), "opencl") == 0, "backend");
    CHECK(strcmp(relief_backend_name((relief_backend)99), "unknown") == 0, "bad backend");
    CHECK(strcmp(relief_depth_variant_name(RELIEF_DEPTH_DECOMPOSE), "decompose") == 0, "variant");
    CHECK(strcmp(relief_membrane_name(RELIEF_MEMBRANE_THIN_PLATE), "thin-plate") == 0, "membrane");
    CHECK(strcmp(relief_image_fill_method_name(RELIEF_IMAGE_FILL_JAIN), "jain") == 0,
          "image fill method");
    CHECK(strcmp(relief_points_what_name(RELIEF_POINTS_COLOUR_ONLY), "colour") == 0, "what");
    CHECK(strcmp(relief_fill_region_name(RELIEF_FILL_WHOLE), "whole") == 0, "fill");
}

static void test_run_options(void)
{
    relief_run_options r = relief_run_options_default();
    relief_error err = {0};
    CHECK(r.backend == RELIEF_BACKEND_AUTO && r.device == -1 && r.max_memory == 0 &&
              !r.progress && !r.input_name && r.threads == 0,
          "defaults");
    CHECK_STATUS(relief_run_options_validate(&r, &err), RELIEF_OK, err, NULL);
    /* threads: 0 (the affinity's CPUs) or 1..RELIEF_THREADS_MAX, the message
     * naming the field and its range */
    r.threads = RELIEF_THREADS_MAX;
    CHECK_STATUS(relief_run_options_validate(&r, &err), RELIEF_OK, err, NULL);
    r.threads = RELIEF_THREADS_MAX + 1;
    CHECK_STATUS(relief_run_options_validate(&r, &err), RELIEF_E_RANGE, err, "threads 65 out "
                 "of range: expected 1..64");
    r.threads = -1;
    CHECK_STATUS(relief_run_options_validate(&r, &err), RELIEF_E_RANGE, err, "threads");
    r.threads = 0;
    r.device = 300;
    CHECK_STATUS(relief_run_options_validate(&r, &err), RELIEF_E_RANGE, err, "device");
    r.device = -1;
    r.backend = (relief_backend)7;
    CHECK_STATUS(relief_run_options_validate(&r, &err), RELIEF_E_RANGE, err, "backend");
    CHECK_STATUS(relief_run_options_validate(NULL, &err), RELIEF_E_USAGE, err, NULL);
}

static void test_mesh(void)
{
    relief_error err = {0};
    relief_mesh *m = NULL;
    relief_synth_params sp = relief_synth_params_default();
    sp.kind = RELIEF_SYNTH_PLANE_WAVES;
    sp.vertices = 400;
    CHECK_STATUS(relief_synth(&sp, &m, NULL, &err), RELIEF_OK, err, NULL);
    CHECK(m && relief_mesh_vertex_count(m) > 100 && relief_mesh_triangle_count(m) > 100,
          "synth sizes");
    CHECK_STATUS(relief_mesh_validate(m, &err), RELIEF_OK, err, NULL);
    if (m)
        relief_mesh_positions(m)[0] = NAN;
    CHECK_STATUS(relief_mesh_validate(m, &err), RELIEF_E_MESH, err, "vertex 0");
    relief_mesh_destroy(m);
    CHECK_STATUS(relief_mesh_read("/nonexistent/x.ply", &m, NULL, &err), RELIEF_E_IO, err,
                 "/nonexistent/x.ply");
    CHECK_STATUS(relief_mesh_create(2, 1, 0, NULL, &err), RELIEF_E_USAGE, err, NULL);
}

/* A file as real captures come: two squares, one listing a corner twice,
 * one triangle twice, one wound the other way (its neighbours agree). The default read mends it
 * and says so; the raw read keeps the soup; relief_mesh_repair mends that
 * the same way. A vertex far out is refused by both, named. */
static void test_repair(void)
{
    static const char *const soup =
        "ply\nformat ascii 1.0\nelement vertex 7\nproperty float x\nproperty float y\n"
        "property float z\nelement face 5\nproperty list uchar int vertex_indices\n"
        "end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n2 1 0\n1 1 0\n"
        "3 0 1 2\n3 0 2 3\n3 2 1 0\n3 1 4 5\n3 1 6 5\n";
    char dir[] = "/tmp/relief-api-repair-XXXXXX", path[64];
    relief_error err = {0};
    relief_read_info info;
    relief_read_options raw = {1};
    relief_mesh *m = NULL, *r = NULL;
    FILE *f;
    if (!mkdtemp(dir))
        return;
    snprintf(path, sizeof path, "%s/soup.ply", dir);
    f = fopen(path, "w");
    fputs(soup, f);
    fclose(f);
    CHECK_STATUS(relief_mesh_read(path, &m, &info, &err), RELIEF_OK, err, NULL);
    CHECK(m && relief_mesh_vertex_count(m) == 6 && relief_mesh_triangle_count(m) == 4,
          "repaired: %zu vertices, %zu triangles", m ? relief_mesh_vertex_count(m) : 0,
          m ? relief_mesh_triangle_count(m) : 0);
    CHECK(info.repaired && info.repair.vertices_welded == 1 &&
              info.repair.duplicate_triangles == 1 && info.repair.triangles_flipped == 1,
          "counts: welded %zu, duplicates %zu, flipped %zu", info.repair.vertices_welded,
          info.repair.duplicate_triangles, info.repair.triangles_flipped);
    char text[256];
    CHECK(relief_repair_info_describe(&info.repair, text, sizeof text) == 3 &&
              strstr(text, "1 duplicate vertices welded"), "described as '%s'", text);
    CHECK_STATUS(relief_mesh_read_with(path, &raw, &r, &info, &err), RELIEF_OK, err, NULL);
    CHECK(r && relief_mesh_vertex_count(r) == 7 && relief_mesh_triangle_count(r) == 5 &&
              !info.repaired, "raw: the soup as it is");
    relief_repair_info ri;
    CHECK_STATUS(relief_mesh_repair(r, &ri, &err), RELIEF_OK, err, NULL);
    CHECK(r && m && relief_mesh_triangle_count(r) == 4 &&
              !memcmp(relief_mesh_triangles(r), relief_mesh_triangles(m), 12 * sizeof(uint32_t)),
          "relief_mesh_repair mends the raw soup as the reader does");
    relief_mesh_destroy(m);
    relief_mesh_destroy(r);
    m = NULL;
    f = fopen(path, "w");
    fputs("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
          "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
          "end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 1e20\n3 0 1 2\n3 0 2 3\n", f);
    fclose(f);
    CHECK_STATUS(relief_mesh_read_with(path, &raw, &m, NULL, &err), RELIEF_E_MESH, err,
                 "vertex 3: its coordinates (0, 1, 1e+20) are out of range");
    remove(path);
    rmdir(dir);
}

static void test_devices(void)
{
    relief_error err = {0};
    size_t n = 99;
    relief_status st = relief_devices(NULL, 0, &n, &err);
    CHECK(st == RELIEF_OK || st == RELIEF_E_NOT_BUILT, "devices: %s", err.message);
    CHECK(st != RELIEF_OK || n < 99, "count set");
}

int main(void)
{
    if (!api_test_locale())
        return 2;
    test_status();
    test_run_options();
    test_mesh();
    test_repair();
    test_devices();
    API_TEST_END();
}
