/* The core of the public API as a user meets it: the version, statuses and
 * their names, run options, meshes and their files, synthetic surfaces,
 * devices, and every enumeration's names. */
#include <math.h>
#include <stdlib.h>

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
    CHECK(strcmp(relief_points_what_name(RELIEF_POINTS_COLOUR_ONLY), "colour") == 0, "what");
    CHECK(strcmp(relief_fill_region_name(RELIEF_FILL_WHOLE), "whole") == 0, "fill");
}

static void test_run_options(void)
{
    relief_run_options r = relief_run_options_default();
    relief_error err = {RELIEF_OK, ""};
    CHECK(r.backend == RELIEF_BACKEND_AUTO && r.device == -1 && r.max_memory == 0 &&
              !r.progress && !r.input_name,
          "defaults");
    CHECK_STATUS(relief_run_options_validate(&r, &err), RELIEF_OK, err, NULL);
    r.device = 300;
    CHECK_STATUS(relief_run_options_validate(&r, &err), RELIEF_E_RANGE, err, "device");
    r.device = -1;
    r.backend = (relief_backend)7;
    CHECK_STATUS(relief_run_options_validate(&r, &err), RELIEF_E_RANGE, err, "backend");
    CHECK_STATUS(relief_run_options_validate(NULL, &err), RELIEF_E_USAGE, err, NULL);
}

static void test_mesh(void)
{
    relief_error err = {RELIEF_OK, ""};
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

static void test_devices(void)
{
    relief_error err = {RELIEF_OK, ""};
    size_t n = 99;
    relief_status st = relief_devices(NULL, 0, &n, &err);
    CHECK(st == RELIEF_OK || st == RELIEF_E_NOT_BUILT, "devices: %s", err.message);
    CHECK(st != RELIEF_OK || n < 99, "count set");
}

int main(void)
{
    test_status();
    test_run_options();
    test_mesh();
    test_devices();
    API_TEST_END();
}
