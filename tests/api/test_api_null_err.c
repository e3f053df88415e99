/* Every public entry point that takes a `relief_error *` accepts NULL there
 * (relief/core.h, issue 60 item 4): each is called on failing input (NULL
 * arguments, values out of range, a missing file, a malformed one, nothing
 * to fill, an engine's own refusal) once with an error and once with NULL,
 * and must give the same status, the one expected, without a crash. The
 * call that once crashed: relief_smooth(capture, &p, &out, NULL, NULL) on a
 * capture whose holes the hole model leaves open read err->message.
 *
 * The headers are read too: a RELIEF_API function with a relief_error
 * parameter that no NULL_ERR below calls fails the test, so that a new
 * entry point is held to the promise from its first commit.
 *   test_api_null_err INCLUDE_DIR   (include/relief) */
#include <ctype.h>
#include <dirent.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include "api_test.h"

/* The functions NULL_ERR called, each once. */
#define MAX_NAMES 256
static const char *called[MAX_NAMES];
static size_t n_called;

static void note_called(const char *name)
{
    for (size_t i = 0; i < n_called; ++i)
        if (strcmp(called[i], name) == 0)
            return;
    if (n_called < MAX_NAMES)
        called[n_called++] = name;
}

/* fn args, where args names the error E: first with E an error, then with
 * E NULL. Both must return `want` (RELIEF_OK only where failing input
 * cannot be had), the error must hold that status and a message. */
#define NULL_ERR(want, fn, args)                                                        \
    do {                                                                                \
        relief_error err_ = {0};                                                        \
        relief_error *E = &err_;                                                        \
        relief_status with_, without_;                                                  \
        note_called(#fn);                                                               \
        with_ = fn args;                                                                \
        E = NULL;                                                                       \
        without_ = fn args;                                                             \
        CHECK(with_ == (want) && without_ == with_ && err_.status == with_ &&           \
                  (with_ == RELIEF_OK || err_.message[0]),                              \
              "%s%s: %s with an error (%s), %s with NULL; expected %s", #fn, #args,     \
              relief_status_name(with_), err_.message, relief_status_name(without_),    \
              relief_status_name(want));                                                \
    } while (0)

static char tmp[256];

/* tmp/name, in a static buffer of its own per slot (0..3). */
static const char *at(int slot, const char *name)
{
    static char paths[4][512];
    snprintf(paths[slot], sizeof paths[slot], "%s/%s", tmp, name);
    return paths[slot];
}

static void write_file(const char *path, const void *bytes, size_t n)
{
    FILE *f = fopen(path, "wb");
    CHECK(f && fwrite(bytes, 1, n, f) == n && fclose(f) == 0, "cannot write %s", path);
}

/* ------------------------------------------------------------- meshes */

/* A mesh of n vertices at `pos` and t triangles `tri`. */
static relief_mesh *mesh_of(size_t n, const double *pos, size_t t, const uint32_t *tri,
                            unsigned attributes)
{
    relief_error err = {0};
    relief_mesh *m = NULL;
    CHECK_STATUS(relief_mesh_create(n, t, attributes, &m, &err), RELIEF_OK, err, NULL);
    if (!m)
        exit(2);
    memcpy(relief_mesh_positions(m), pos, n * 3 * sizeof *pos);
    if (t)
        memcpy(relief_mesh_triangles(m), tri, t * 3 * sizeof *tri);
    return m;
}

/* A closed tetrahedron: no hole to fill. */
static relief_mesh *tetrahedron(void)
{
    static const double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    static const uint32_t tri[] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    return mesh_of(4, pos, 4, tri, 0);
}

static relief_mesh *synth_capture(relief_synth_kind kind, size_t vertices)
{
    relief_error err = {0};
    relief_synth_params sp = relief_synth_params_default();
    relief_mesh *cap = NULL;
    sp.kind = kind;
    sp.vertices = vertices;
    CHECK_STATUS(relief_synth(&sp, &cap, NULL, &err), RELIEF_OK, err, NULL);
    if (!cap)
        exit(2);
    return cap;
}

/* Parameters by name, run options, synthetic surfaces, devices. */
static void test_core(void)
{
    relief_mesh *m = NULL;
    relief_synth_params sp = relief_synth_params_default();
    relief_run_options run = relief_run_options_default();
    relief_image_fill_params ip = relief_image_fill_params_default();
    relief_synth_kind kind;
    size_t n, count = 0;
    const relief_param *t = relief_image_fill_param_table(&n);
    NULL_ERR(RELIEF_E_USAGE, relief_param_set, (NULL, t, "3", E));
    NULL_ERR(RELIEF_E_USAGE, relief_param_set, (&ip, NULL, "3", E));
    NULL_ERR(RELIEF_E_USAGE, relief_param_set, (&ip, t, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_param_set, (&ip, relief_param_find(t, n, "window"), "x9", E));
    NULL_ERR(RELIEF_E_USAGE, relief_param_set,
             (&ip, relief_param_find(t, n, "max_memory"), "lots", E));
    NULL_ERR(RELIEF_E_USAGE, relief_synth_kind_parse, ("no-such-surface", &kind, E));
    NULL_ERR(RELIEF_E_USAGE, relief_synth_kind_parse, (NULL, &kind, E));
    NULL_ERR(RELIEF_E_USAGE, relief_synth_kind_parse, ("plane-waves", NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_synth_params_validate, (NULL, E));
    sp.vertices = 5;
    NULL_ERR(RELIEF_E_RANGE, relief_synth_params_validate, (&sp, E));
    NULL_ERR(RELIEF_E_RANGE, relief_synth, (&sp, &m, NULL, E));
    sp = relief_synth_params_default();
    sp.noise = NAN;
    NULL_ERR(RELIEF_E_RANGE, relief_synth, (&sp, &m, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_synth, (NULL, &m, NULL, E));
    CHECK(m == NULL, "a surface made on failure");
    NULL_ERR(RELIEF_E_USAGE, relief_run_options_validate, (NULL, E));
    run.threads = RELIEF_THREADS_MAX + 1;
    NULL_ERR(RELIEF_E_RANGE, relief_run_options_validate, (&run, E));
    run = relief_run_options_default();
    run.backend = (relief_backend)17;
    NULL_ERR(RELIEF_E_RANGE, relief_run_options_validate, (&run, E));
    NULL_ERR(RELIEF_E_USAGE, relief_devices, (NULL, 0, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_devices, (NULL, 4, &count, E));
}

/* Meshes made, checked and mended in memory. */
static void test_meshes(void)
{
    relief_mesh *m = NULL, *bad;
    const double nan_pos[] = {0, 0, 0, NAN, 0, 0, 0, 1, 0};
    const double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    const uint32_t far_tri[] = {0, 1, 7};
    NULL_ERR(RELIEF_E_USAGE, relief_mesh_create, (3, 1, 0, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_mesh_create, (3, 1, 1u << 7, &m, E));
    NULL_ERR(RELIEF_E_RANGE, relief_mesh_create, ((size_t)UINT32_MAX + 1, 0, 0, &m, E));
    CHECK(m == NULL, "a mesh made on failure");
    NULL_ERR(RELIEF_E_MESH, relief_mesh_validate, (NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_mesh_repair, (NULL, NULL, E));
    bad = mesh_of(3, nan_pos, 0, NULL, 0);
    NULL_ERR(RELIEF_E_MESH, relief_mesh_validate, (bad, E));
    NULL_ERR(RELIEF_E_MESH, relief_mesh_repair, (bad, NULL, E));
    relief_mesh_destroy(bad);
    bad = mesh_of(4, pos, 1, far_tri, 0);
    NULL_ERR(RELIEF_E_MESH, relief_mesh_validate, (bad, E));
    NULL_ERR(RELIEF_E_MESH, relief_mesh_repair, (bad, NULL, E));
    relief_mesh_destroy(bad);
}

/* ---------------------------------------------------------- mesh files */

static void test_mesh_files(void)
{
    relief_mesh *m = NULL, *tet = tetrahedron(), *nan_mesh;
    relief_read_options raw = {1};
    relief_write_options ascii = {1};
    const char *ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                      "property float y\nproperty float z\nelement face 1\n"
                      "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0\n";
    const char *off = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n";
    const double nan_pos[] = {0, 0, 0, NAN, 0, 0, 0, 1, 0};
    const uint32_t tri[] = {0, 1, 2};
    write_file(at(0, "truncated.ply"), ply, strlen(ply));
    write_file(at(1, "index.off"), off, strlen(off));
    write_file(at(2, "mesh.xyz"), "0 0 0\n", 6);
    NULL_ERR(RELIEF_E_USAGE, relief_mesh_read, (NULL, &m, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_mesh_read, (at(0, "truncated.ply"), NULL, NULL, E));
    NULL_ERR(RELIEF_E_IO, relief_mesh_read, (at(3, "missing.ply"), &m, NULL, E));
    NULL_ERR(RELIEF_E_PARSE, relief_mesh_read, (at(0, "truncated.ply"), &m, NULL, E));
    NULL_ERR(RELIEF_E_MESH, relief_mesh_read, (at(1, "index.off"), &m, NULL, E));
    NULL_ERR(RELIEF_E_FORMAT, relief_mesh_read, (at(2, "mesh.xyz"), &m, NULL, E));
    NULL_ERR(RELIEF_E_FORMAT, relief_mesh_read, (tmp, &m, NULL, E));
    CHECK(mkdir(at(3, "folder.ply"), 0700) == 0, "mkdir %s", at(3, "folder.ply"));
    NULL_ERR(RELIEF_E_IO, relief_mesh_read, (at(3, "folder.ply"), &m, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_mesh_read_with, (NULL, &raw, &m, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_mesh_read_with, (at(0, "truncated.ply"), &raw, NULL, NULL,
                                                     E));
    NULL_ERR(RELIEF_E_IO, relief_mesh_read_with, (at(3, "missing.obj"), &raw, &m, NULL, E));
    NULL_ERR(RELIEF_E_PARSE, relief_mesh_read_with, (at(0, "truncated.ply"), &raw, &m, NULL, E));
    NULL_ERR(RELIEF_E_MESH, relief_mesh_read_with, (at(1, "index.off"), NULL, &m, NULL, E));
    CHECK(m == NULL, "a mesh read on failure");
    NULL_ERR(RELIEF_E_USAGE, relief_mesh_write, (NULL, at(0, "out.ply"), NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_mesh_write, (tet, NULL, NULL, E));
    NULL_ERR(RELIEF_E_FORMAT, relief_mesh_write, (tet, at(0, "out.xyz"), NULL, E));
    NULL_ERR(RELIEF_E_IO, relief_mesh_write, (tet, at(0, "no/such/folder/out.ply"), &ascii, E));
    nan_mesh = mesh_of(3, nan_pos, 1, tri, 0);
    NULL_ERR(RELIEF_E_MESH, relief_mesh_write, (nan_mesh, at(0, "nan.ply"), NULL, E));
    relief_mesh_destroy(nan_mesh);
    relief_mesh_destroy(tet);
}

/* ------------------------------------------------------------ complete */

/* Small and fast: the reference backend, a window of 2. */
static relief_complete_params quick(void)
{
    relief_complete_params p = relief_complete_params_default();
    p.run.backend = RELIEF_BACKEND_SCALAR;
    p.window = 2;
    p.measure = 0;
    return p;
}

static void test_fit(void)
{
    const double line[] = {0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 3, 3};
    const double two[] = {0, 0, 0, 1, 0, 0};
    relief_fit_result fr;
    relief_mesh *few = mesh_of(2, two, 0, NULL, 0);
    NULL_ERR(RELIEF_E_USAGE, relief_fit, (NULL, NULL, 4, RELIEF_FIT_PLANE, &fr, E));
    NULL_ERR(RELIEF_E_USAGE, relief_fit, (line, NULL, 4, (relief_fit_model)9, &fr, E));
    NULL_ERR(RELIEF_E_MESH, relief_fit, (two, NULL, 2, RELIEF_FIT_AUTO, &fr, E));
    NULL_ERR(RELIEF_E_MESH, relief_fit, (line, NULL, 4, RELIEF_FIT_PLANE, &fr, E));
    NULL_ERR(RELIEF_E_MESH, relief_fit, (line, NULL, 4, RELIEF_FIT_SPHERE, &fr, E));
    NULL_ERR(RELIEF_E_USAGE, relief_fit, (line, NULL, 4, RELIEF_FIT_PLANE, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_fit_mesh, (NULL, RELIEF_FIT_AUTO, &fr, E));
    NULL_ERR(RELIEF_E_USAGE, relief_fit_mesh, (few, RELIEF_FIT_AUTO, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_fit_mesh, (few, (relief_fit_model)-1, &fr, E));
    NULL_ERR(RELIEF_E_MESH, relief_fit_mesh, (few, RELIEF_FIT_AUTO, &fr, E));
    relief_mesh_destroy(few);
}

/* The smooth completion's refusals, the crash among them. */
static void test_smooth(relief_mesh *cap, relief_mesh *tet)
{
    relief_complete_params p = quick();
    relief_mesh *out = NULL;
    NULL_ERR(RELIEF_E_USAGE, relief_complete_params_validate, (NULL, E));
    p.window = 17;
    NULL_ERR(RELIEF_E_RANGE, relief_complete_params_validate, (&p, E));
    NULL_ERR(RELIEF_E_RANGE, relief_smooth, (cap, &p, &out, NULL, E));
    p = quick();
    p.base = RELIEF_BASE_SMOOTH;
    p.fit = RELIEF_FIT_PLANE;
    NULL_ERR(RELIEF_E_USAGE, relief_complete_params_validate, (&p, E));
    p.fit = RELIEF_FIT_AUTO;
    NULL_ERR(RELIEF_E_USAGE, relief_smooth, (cap, &p, &out, NULL, E));
    p = quick();
    NULL_ERR(RELIEF_E_USAGE, relief_smooth, (NULL, &p, &out, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_smooth, (cap, NULL, &out, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_smooth, (cap, &p, NULL, NULL, E));
    /* The crash: the hole model leaves the plane's hole open (wider than
     * max_hole) and its border too, so nothing is to complete; relief_smooth
     * then looked into err (strstr on its message) to tell why, and err
     * was the caller's NULL. */
    p.fill = RELIEF_FILL_HOLES;
    p.max_hole = 1e-3;
    NULL_ERR(RELIEF_E_RANGE, relief_smooth, (cap, &p, &out, NULL, E));
    /* A ball that touches no rim: nothing selected. */
    p = quick();
    p.has_hole_ball = 1;
    p.hole_ball[0] = 5.0, p.hole_ball[3] = 0.1;
    NULL_ERR(RELIEF_E_RANGE, relief_smooth, (cap, &p, &out, NULL, E));
    p.hole_labels = 1;
    NULL_ERR(RELIEF_E_USAGE, relief_smooth, (cap, &p, &out, NULL, E));
    /* A closed tetrahedron: its sphere covers nothing to complete. */
    p = quick();
    p.fill = RELIEF_FILL_HOLES;
    NULL_ERR(RELIEF_E_MESH, relief_smooth, (tet, &p, &out, NULL, E));
    CHECK(out == NULL, "an output on failure");
}

static void test_complete(relief_mesh *cap, relief_mesh *tet)
{
    relief_complete_params p = quick();
    relief_complete_report rep;
    relief_mesh *out = NULL;
    const char *notes = at(0, "notes.txt");
    NULL_ERR(RELIEF_E_USAGE, relief_complete, (NULL, &p, &out, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_complete, (cap, NULL, &out, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_complete, (cap, &p, NULL, NULL, E));
    p.levels = 0;
    NULL_ERR(RELIEF_E_RANGE, relief_complete, (cap, &p, &out, NULL, E));
    p = quick();
    p.report_dir = at(1, "no/such/folder/report");
    NULL_ERR(RELIEF_E_USAGE, relief_complete, (cap, &p, &out, NULL, E)); /* rep NULL */
    NULL_ERR(RELIEF_E_IO, relief_complete, (cap, &p, &out, &rep, E));
    p = quick();
    p.resume = at(1, "missing.checkpoint");
    NULL_ERR(RELIEF_E_IO, relief_complete, (cap, &p, &out, NULL, E));
    write_file(notes, "my notes\n", 9);
    p = quick();
    p.resume = notes;
    NULL_ERR(RELIEF_E_PARSE, relief_complete, (cap, &p, &out, NULL, E));
    p = quick();
    p.checkpoint = notes; /* another program's file: never replaced */
    NULL_ERR(RELIEF_E_IO, relief_complete, (cap, &p, &out, NULL, E));
    p = quick();
    p.fill = RELIEF_FILL_HOLES;
    p.max_hole = 1e-3;
    NULL_ERR(RELIEF_E_RANGE, relief_complete, (cap, &p, &out, NULL, E));
    NULL_ERR(RELIEF_E_MESH, relief_complete, (tet, &p, &out, NULL, E));
    p = quick();
    p.run.max_memory = 1024;
    NULL_ERR(RELIEF_E_NOMEM, relief_complete, (cap, &p, &out, NULL, E));
    CHECK(out == NULL, "an output on failure");
}

/* A staged report folder whose place another program's file took since. */
static relief_report_folder *staged_folder(relief_mesh *cap, const char *where)
{
    relief_complete_params p = quick();
    relief_complete_report rep;
    relief_error err = {0};
    relief_mesh *out = NULL;
    relief_report_folder *folder;
    unlink(where);
    p.report_dir = where;
    CHECK_STATUS(relief_complete(cap, &p, &out, &rep, &err), RELIEF_OK, err, NULL);
    relief_mesh_destroy(out);
    if (!rep.json)
        return NULL;
    folder = rep.folder;
    rep.folder = NULL;
    relief_complete_report_free(&rep);
    write_file(where, "not a report\n", 13);
    return folder;
}

static void test_report_folder(relief_mesh *cap)
{
    relief_error err = {0};
    relief_report_folder *with = staged_folder(cap, at(0, "report"));
    relief_status a = relief_report_folder_commit(with, &err), b;
    relief_report_folder *without = staged_folder(cap, at(0, "report"));
    note_called("relief_report_folder_commit");
    b = relief_report_folder_commit(without, NULL);
    CHECK(with && without && a == RELIEF_E_IO && b == a && err.status == a &&
              err.reason == RELIEF_REASON_NOT_RELIEFS,
          "relief_report_folder_commit over another program's file: %s with an error (%s), %s "
          "with NULL", relief_status_name(a), err.message, relief_status_name(b));
    NULL_ERR(RELIEF_OK, relief_report_folder_commit, (NULL, E));
    unlink(at(0, "report"));
}

static void test_eval(relief_mesh *cap, relief_mesh *tet)
{
    relief_eval_result r;
    NULL_ERR(RELIEF_E_USAGE, relief_eval, (NULL, NULL, &r, E));
    NULL_ERR(RELIEF_E_USAGE, relief_eval, (cap, NULL, NULL, E));
    NULL_ERR(RELIEF_E_MESH, relief_eval, (tet, NULL, &r, E));
    NULL_ERR(RELIEF_E_MESH, relief_eval, (cap, NULL, &r, E)); /* no part completed */
}

/* --------------------------------------------------------------- images */

static void test_image_files(void)
{
    uint8_t px[4 * 4 * 3] = {0}, png[4096];
    uint16_t deep[4 * 4] = {0};
    relief_image img = {4, 4, 3, 8, 0, px}, out;
    relief_image grey16 = {4, 4, 1, 16, 0, deep}, odd = img;
    size_t n = 0;
    FILE *f;
    odd.bit_depth = 7;
    NULL_ERR(RELIEF_E_USAGE, relief_image_check, (NULL, "image", E));
    NULL_ERR(RELIEF_E_RANGE, relief_image_check, (&odd, NULL, E));
    odd = img;
    odd.data = NULL;
    NULL_ERR(RELIEF_E_USAGE, relief_image_check, (&odd, "image", E));
    odd = img;
    odd.channels = 5;
    NULL_ERR(RELIEF_E_RANGE, relief_image_check, (&odd, "image", E));
    NULL_ERR(RELIEF_E_USAGE, relief_image_write, (NULL, at(0, "out.png"), E));
    NULL_ERR(RELIEF_E_USAGE, relief_image_write, (&img, NULL, E));
    NULL_ERR(RELIEF_E_FORMAT, relief_image_write, (&img, at(0, "out.gif"), E));
    NULL_ERR(RELIEF_E_FORMAT, relief_image_write, (&grey16, at(0, "out.jpg"), E));
    NULL_ERR(RELIEF_E_IO, relief_image_write, (&img, at(0, "no/such/folder/out.png"), E));
    NULL_ERR(RELIEF_E_RANGE, relief_image_write, (&odd, at(0, "out.png"), E));
    /* A real PNG, then refused by size, and cut short. */
    {
        relief_error err = {0};
        CHECK_STATUS(relief_image_write(&img, at(0, "ok.png"), &err), RELIEF_OK, err, NULL);
    }
    f = fopen(at(0, "ok.png"), "rb");
    n = f ? fread(png, 1, sizeof png, f) : 0;
    if (f)
        fclose(f);
    CHECK(n > 16, "ok.png: %zu bytes", n);
    write_file(at(1, "short.png"), png, n / 2);
    write_file(at(2, "text.png"), "not a picture\n", 14);
    NULL_ERR(RELIEF_E_USAGE, relief_image_read, (NULL, 0, &out, E));
    NULL_ERR(RELIEF_E_USAGE, relief_image_read, (at(0, "ok.png"), 0, NULL, E));
    NULL_ERR(RELIEF_E_IO, relief_image_read, (at(3, "missing.png"), 0, &out, E));
    NULL_ERR(RELIEF_E_FORMAT, relief_image_read, (at(2, "text.png"), 0, &out, E));
    NULL_ERR(RELIEF_E_PARSE, relief_image_read, (at(1, "short.png"), 0, &out, E));
    NULL_ERR(RELIEF_E_NOMEM, relief_image_read, (at(0, "ok.png"), 8, &out, E));
    NULL_ERR(RELIEF_E_USAGE, relief_image_decode, (NULL, 10, "x", 0, &out, E));
    NULL_ERR(RELIEF_E_USAGE, relief_image_decode, (png, n, "x", 0, NULL, E));
    NULL_ERR(RELIEF_E_FORMAT, relief_image_decode, ("GIF89a", 6, NULL, 0, &out, E));
    NULL_ERR(RELIEF_E_PARSE, relief_image_decode, (png, n / 2, "half", 0, &out, E));
    NULL_ERR(RELIEF_E_NOMEM, relief_image_decode, (png, n, "ok", 8, &out, E));
}

static void test_image_fill(void)
{
    uint8_t px[16 * 16 * 3], alpha[16 * 16 * 4], holes[16 * 16], small[8 * 8];
    relief_image img = {16, 16, 3, 8, 0, px}, rgba = {16, 16, 4, 8, 0, alpha};
    relief_image mask = {16, 16, 1, 8, 0, holes}, wrong = {8, 8, 1, 8, 0, small};
    relief_image_fill_params p = relief_image_fill_params_default();
    for (size_t i = 0; i < sizeof px; ++i)
        px[i] = (uint8_t)(i * 7);
    memset(alpha, 0, sizeof alpha); /* every pixel transparent: every one to fill */
    memset(holes, 0, sizeof holes);
    memset(small, 0, sizeof small);
    holes[8 * 16 + 8] = 255;
    NULL_ERR(RELIEF_E_USAGE, relief_image_fill_params_validate, (NULL, E));
    p.min_window = 4;
    NULL_ERR(RELIEF_E_RANGE, relief_image_fill_params_validate, (&p, E));
    NULL_ERR(RELIEF_E_RANGE, relief_image_fill, (&img, &mask, &p, NULL, E));
    p = relief_image_fill_params_default();
    p.run.device = 300;
    NULL_ERR(RELIEF_E_RANGE, relief_image_fill_params_validate, (&p, E));
    p = relief_image_fill_params_default();
    p.run.backend = RELIEF_BACKEND_SCALAR;
    NULL_ERR(RELIEF_E_RANGE, relief_image_fill_check_memory, (0, 16, 3, &p, E));
    NULL_ERR(RELIEF_E_RANGE, relief_image_fill_check_memory, (16, 16, 5, NULL, E));
    p.run.max_memory = 1024;
    NULL_ERR(RELIEF_E_NOMEM, relief_image_fill_check_memory, (4096, 4096, 3, &p, E));
    NULL_ERR(RELIEF_E_NOMEM, relief_image_fill, (&img, &mask, &p, NULL, E));
    p.run.max_memory = 0;
    NULL_ERR(RELIEF_E_USAGE, relief_image_fill, (NULL, &mask, &p, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_image_fill, (&img, &mask, NULL, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_image_fill, (&img, NULL, &p, NULL, E)); /* no alpha */
    NULL_ERR(RELIEF_E_USAGE, relief_image_fill, (&img, &wrong, &p, NULL, E));
    NULL_ERR(RELIEF_E_RANGE, relief_image_fill, (&rgba, NULL, &p, NULL, E));
    p.window = 33; /* larger than the image */
    p.min_window = 3;
    NULL_ERR(RELIEF_E_RANGE, relief_image_fill, (&img, &mask, &p, NULL, E));
}

/* ---------------------------------------------------------------- depth */

/* A w x h frame of z 1 + x / 100 (new arrays; free with free_frame). */
static relief_depth_image frame(int w, int h, int with_rgb)
{
    relief_depth_image f;
    memset(&f, 0, sizeof f);
    f.width = w;
    f.height = h;
    f.format = RELIEF_DEPTH_PFM;
    f.z = malloc((size_t)w * h * sizeof *f.z);
    f.rgb = with_rgb ? calloc((size_t)w * h * 3, 1) : NULL;
    if (!f.z || (with_rgb && !f.rgb))
        exit(2);
    for (int i = 0; i < w * h; ++i)
        f.z[i] = 1.0f + (float)(i % w) / 100.0f;
    return f;
}

static void free_frame(relief_depth_image *f)
{
    free(f->z);
    free(f->rgb);
}

static void test_depth_files(void)
{
    relief_depth_image f = frame(8, 8, 0), out;
    const char *pfm = "Pf\n8 8\n-1.0\n\x01\x02";
    NULL_ERR(RELIEF_E_USAGE, relief_depth_write, (NULL, at(0, "out.pfm"), RELIEF_DEPTH_PFM, 0, E));
    NULL_ERR(RELIEF_E_USAGE, relief_depth_write, (&f, NULL, RELIEF_DEPTH_PFM, 0, E));
    NULL_ERR(RELIEF_E_RANGE, relief_depth_write,
             (&f, at(0, "out.pfm"), (relief_depth_format)42, 0, E));
    NULL_ERR(RELIEF_E_USAGE, relief_depth_write, (&f, at(0, "out.pcd"), RELIEF_DEPTH_PCD_ASCII, 0,
                                                   E)); /* a PCD needs xyz */
    NULL_ERR(RELIEF_E_RANGE, relief_depth_write, (&f, at(0, "out.png"), RELIEF_DEPTH_PNG16, -1, E));
    NULL_ERR(RELIEF_E_IO, relief_depth_write,
             (&f, at(0, "no/such/folder/out.pfm"), RELIEF_DEPTH_PFM, 0, E));
    {
        relief_error err = {0};
        CHECK_STATUS(relief_depth_write(&f, at(0, "ok.pfm"), RELIEF_DEPTH_PFM, 0, &err),
                     RELIEF_OK, err, NULL);
    }
    write_file(at(1, "short.pfm"), pfm, strlen(pfm));
    write_file(at(2, "text.pfm"), "hello\n", 6);
    NULL_ERR(RELIEF_E_USAGE, relief_depth_read, (NULL, 0, 0, &out, E));
    NULL_ERR(RELIEF_E_USAGE, relief_depth_read, (at(0, "ok.pfm"), 0, 0, NULL, E));
    NULL_ERR(RELIEF_E_IO, relief_depth_read, (at(3, "missing.pfm"), 0, 0, &out, E));
    NULL_ERR(RELIEF_E_PARSE, relief_depth_read, (at(1, "short.pfm"), 0, 0, &out, E));
    NULL_ERR(RELIEF_E_FORMAT, relief_depth_read, (at(2, "text.pfm"), 0, 0, &out, E));
    NULL_ERR(RELIEF_E_NOMEM, relief_depth_read, (at(0, "ok.pfm"), 0, 10, &out, E));
    NULL_ERR(RELIEF_E_RANGE, relief_depth_read, (at(0, "ok.pfm"), -1, 0, &out, E));
    NULL_ERR(RELIEF_E_USAGE, relief_depth_read_as,
             (NULL, RELIEF_DEPTH_ENCODING_AUTO, 0, 0, &out, E));
    NULL_ERR(RELIEF_E_RANGE, relief_depth_read_as,
             (at(0, "ok.pfm"), (relief_depth_encoding)9, 0, 0, &out, E));
    NULL_ERR(RELIEF_E_FORMAT, relief_depth_read_as,
             (at(0, "ok.pfm"), RELIEF_DEPTH_ENCODING_NYU, 0, 0, &out, E));
    NULL_ERR(RELIEF_E_USAGE, relief_depth_decode, (NULL, 10, "x", 0, &out, E));
    NULL_ERR(RELIEF_E_USAGE, relief_depth_decode, (pfm, strlen(pfm), "x", 0, NULL, E));
    NULL_ERR(RELIEF_E_PARSE, relief_depth_decode, (pfm, strlen(pfm), NULL, 0, &out, E));
    NULL_ERR(RELIEF_E_FORMAT, relief_depth_decode, ("hello", 5, "x", 0, &out, E));
    free_frame(&f);
}

static void test_depth_fill(relief_mesh *tet)
{
    relief_depth_image f = frame(32, 32, 0), gone = frame(32, 32, 0);
    relief_depth_fill_params p = relief_depth_fill_params_default();
    uint8_t small[4 * 4] = {0};
    relief_image wrong = {4, 4, 1, 8, 0, small};
    relief_mesh *out = NULL, *bare = synth_capture(RELIEF_SYNTH_PLANE_WAVES, 200);
    p.run.backend = RELIEF_BACKEND_SCALAR;
    f.z[16 * 32 + 16] = NAN;
    for (int i = 0; i < 32 * 32; ++i)
        gone.z[i] = NAN;
    NULL_ERR(RELIEF_E_USAGE, relief_depth_fill_params_validate, (NULL, E));
    p.window = 4;
    NULL_ERR(RELIEF_E_RANGE, relief_depth_fill_params_validate, (&p, E));
    NULL_ERR(RELIEF_E_RANGE, relief_depth_fill, (&f, NULL, &p, NULL, E));
    p.window = 9;
    p.batch = 4;
    p.tileable = 1;
    NULL_ERR(RELIEF_E_USAGE, relief_depth_fill_params_validate, (&p, E));
    p = relief_depth_fill_params_default();
    p.run.backend = RELIEF_BACKEND_SCALAR;
    NULL_ERR(RELIEF_E_RANGE, relief_depth_fill_check_memory, (0, 4, &p, E));
    NULL_ERR(RELIEF_E_RANGE, relief_depth_fill_check_memory, (4, RELIEF_DEPTH_MAX_SIDE + 1, NULL,
                                                              E));
    p.run.max_memory = 1024;
    NULL_ERR(RELIEF_E_NOMEM, relief_depth_fill_check_memory, (4096, 4096, &p, E));
    NULL_ERR(RELIEF_E_NOMEM, relief_depth_fill, (&f, NULL, &p, NULL, E));
    NULL_ERR(RELIEF_E_NOMEM, relief_depth_fill_mesh, (tet, &p, NULL, &out, NULL, E));
    p.run.max_memory = 0;
    NULL_ERR(RELIEF_E_USAGE, relief_depth_fill, (NULL, NULL, &p, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_depth_fill, (&f, NULL, NULL, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_depth_fill, (&f, &wrong, &p, NULL, E));
    NULL_ERR(RELIEF_E_RANGE, relief_depth_fill, (&gone, NULL, &p, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_depth_fill_mesh, (NULL, &p, NULL, &out, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_depth_fill_mesh, (tet, &p, NULL, NULL, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_depth_fill_mesh, (tet, NULL, NULL, &out, NULL, E));
    NULL_ERR(RELIEF_E_RANGE, relief_depth_fill_mesh, (tet, &p, NULL, &out, NULL, E));
    p.resolution = 16;
    p.max_hole = 1e-6; /* the plane's hole is an opening: nothing to fill */
    NULL_ERR(RELIEF_E_RANGE, relief_depth_fill_mesh, (bare, &p, NULL, &out, NULL, E));
    p.hole_labels = 1; /* labels all 0: none selected */
    p.max_hole = 0.0;
    NULL_ERR(RELIEF_E_RANGE, relief_depth_fill_mesh, (bare, &p, NULL, &out, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_depth_fill_mesh, (tet, &p, NULL, &out, NULL, E));
    CHECK(out == NULL, "a mesh made on failure");
    relief_mesh_destroy(bare);
    free_frame(&f);
    free_frame(&gone);
}

/* ------------------------------------------------------------ occluders */

static void test_occluders(void)
{
    relief_depth_image f = frame(32, 32, 1), bare = frame(32, 32, 0);
    relief_occluder_params p = relief_occluder_params_default();
    relief_remove_params r = relief_remove_params_default();
    relief_image mask;
    uint8_t small[4 * 4] = {0};
    relief_image wrong = {4, 4, 1, 8, 0, small};
    NULL_ERR(RELIEF_E_USAGE, relief_occluder_params_validate, (NULL, E));
    p.window = 4;
    NULL_ERR(RELIEF_E_RANGE, relief_occluder_params_validate, (&p, E));
    NULL_ERR(RELIEF_E_RANGE, relief_find_occluders, (&f, &p, &mask, NULL, E));
    p = relief_occluder_params_default();
    p.background = RELIEF_BACKGROUND_MESH; /* without its mesh */
    NULL_ERR(RELIEF_E_USAGE, relief_occluder_params_validate, (&p, E));
    p = relief_occluder_params_default();
    NULL_ERR(RELIEF_E_USAGE, relief_find_occluders, (NULL, &p, &mask, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_find_occluders, (&f, &p, NULL, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_find_occluders, (&f, NULL, &mask, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_find_occluders, (&bare, &p, &mask, NULL, E)); /* no rgb */
    /* One plane and nothing in front of it: nothing to mark. */
    NULL_ERR(RELIEF_E_RANGE, relief_find_occluders, (&f, &p, &mask, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_remove_occluders, (NULL, NULL, &r, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_remove_occluders, (&f, NULL, NULL, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_remove_occluders, (&f, &wrong, &r, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_remove_occluders, (&bare, NULL, &r, NULL, E));
    NULL_ERR(RELIEF_E_RANGE, relief_remove_occluders, (&f, NULL, &r, NULL, E));
    r.colour.window = 2;
    NULL_ERR(RELIEF_E_RANGE, relief_remove_occluders, (&f, NULL, &r, NULL, E));
    free_frame(&f);
    free_frame(&bare);
}

/* --------------------------------------------------------------- points */

static void test_points(relief_mesh *cap, relief_mesh *tet)
{
    relief_complete_points_params p = relief_complete_points_params_default();
    relief_mesh *out = NULL;
    const double three[] = {0, 0, 0, 1, 0, 0, 2, 0, 0};
    relief_mesh *line = mesh_of(3, three, 0, NULL, 0);
    const char *pcd = "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n"
                      "COUNT 1 1 1\nWIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\n"
                      "DATA ascii\n0 0 0\n1 0\n";
    const char *good = "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n"
                       "COUNT 1 1 1\nWIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\n"
                       "DATA ascii\n0 0 0\n1 0 0\n0 1 0\n";
    write_file(at(0, "short.pcd"), pcd, strlen(pcd));
    write_file(at(1, "good.pcd"), good, strlen(good));
    write_file(at(2, "cloud.xyz"), "0 0 0\n", 6);
    NULL_ERR(RELIEF_E_USAGE, relief_points_read, (NULL, 0, &out, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_points_read, (at(1, "good.pcd"), 0, NULL, NULL, E));
    NULL_ERR(RELIEF_E_IO, relief_points_read, (at(3, "missing.pcd"), 0, &out, NULL, E));
    NULL_ERR(RELIEF_E_PARSE, relief_points_read, (at(0, "short.pcd"), 0, &out, NULL, E));
    NULL_ERR(RELIEF_E_FORMAT, relief_points_read, (at(2, "cloud.xyz"), 0, &out, NULL, E));
    NULL_ERR(RELIEF_E_NOMEM, relief_points_read, (at(1, "good.pcd"), 2, &out, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_complete_points_params_validate, (NULL, E));
    p.k = 5;
    NULL_ERR(RELIEF_E_RANGE, relief_complete_points_params_validate, (&p, E));
    NULL_ERR(RELIEF_E_RANGE, relief_complete_points, (cap, &p, &out, NULL, E));
    p = relief_complete_points_params_default();
    p.what = RELIEF_POINTS_COLOUR_ONLY; /* without a hole mask */
    NULL_ERR(RELIEF_E_USAGE, relief_complete_points_params_validate, (&p, E));
    p = relief_complete_points_params_default();
    p.run.backend = RELIEF_BACKEND_SCALAR;
    NULL_ERR(RELIEF_E_USAGE, relief_complete_points, (NULL, &p, &out, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_complete_points, (cap, NULL, &out, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_complete_points, (cap, &p, NULL, NULL, E));
    NULL_ERR(RELIEF_E_RANGE, relief_complete_points, (line, &p, &out, NULL, E));
    NULL_ERR(RELIEF_E_RANGE, relief_complete_points, (tet, &p, &out, NULL, E));
    p.hole_labels = 1; /* the capture's labels are all 0: none selected */
    NULL_ERR(RELIEF_E_RANGE, relief_complete_points, (cap, &p, &out, NULL, E));
    NULL_ERR(RELIEF_E_USAGE, relief_complete_points, (tet, &p, &out, NULL, E)); /* none */
    p.hole_labels = 0;
    p.max_hole = 1e-6; /* the plane's hole is an opening: nothing to fill */
    NULL_ERR(RELIEF_E_RANGE, relief_complete_points, (cap, &p, &out, NULL, E));
    p.max_hole = 0.0;
    p.run.max_memory = 1024;
    NULL_ERR(RELIEF_E_NOMEM, relief_complete_points, (cap, &p, &out, NULL, E));
    CHECK(out == NULL, "a cloud made on failure");
    relief_mesh_destroy(line);
}

/* ------------------------------------------------------- the headers */

/* The text of `path` without comments and preprocessor lines (owned). */
static char *declarations(const char *path)
{
    FILE *f = fopen(path, "rb");
    char *text, *out;
    size_t n = 0, k = 0;
    long size;
    if (!f || fseek(f, 0, SEEK_END) != 0 || (size = ftell(f)) < 0 || fseek(f, 0, SEEK_SET))
        return NULL;
    text = malloc((size_t)size + 1);
    out = malloc((size_t)size + 1);
    if (text && out)
        n = fread(text, 1, (size_t)size, f);
    fclose(f);
    if (!text || !out)
        exit(2);
    text[n] = '\0';
    for (size_t i = 0; i < n;) {
        int line_start = i == 0 || text[i - 1] == '\n';
        if (text[i] == '/' && text[i + 1] == '*') {
            char *end = strstr(text + i + 2, "*/");
            i = end ? (size_t)(end - text) + 2 : n;
        } else if (text[i] == '/' && text[i + 1] == '/') {
            while (i < n && text[i] != '\n')
                ++i;
        } else if (line_start && text[i] == '#') {
            while (i < n && !(text[i] == '\n' && text[i - 1] != '\\'))
                ++i;
        } else
            out[k++] = text[i++];
    }
    out[k] = '\0';
    free(text);
    return out;
}

static int was_called(const char *name)
{
    for (size_t i = 0; i < n_called; ++i)
        if (strcmp(called[i], name) == 0)
            return 1;
    return 0;
}

/* Every RELIEF_API function of `path` with a relief_error parameter was
 * called above; returns how many there are. */
static size_t check_header(const char *path)
{
    char *text = declarations(path);
    size_t found = 0;
    CHECK(text != NULL, "cannot read %s", path);
    for (char *s = text; text && (s = strstr(s, "RELIEF_API")) != NULL;) {
        char *end = strchr(s, ';'), *paren = strchr(s, '('), *name;
        char saved;
        if (!end || !paren || paren > end)
            break;
        saved = *end;
        *end = '\0';
        if (strstr(s, "relief_error")) {
            for (name = paren; name > s && (name[-1] == ' ' || name[-1] == '\n');)
                --name;
            *name = '\0';
            while (name > s && (isalnum((unsigned char)name[-1]) || name[-1] == '_'))
                --name;
            ++found;
            CHECK(was_called(name), "%s: %s takes a relief_error but test_api_null_err never "
                  "calls it with err NULL", path, name);
        }
        *end = saved;
        s = end + 1;
    }
    free(text);
    return found;
}

static void test_headers(const char *dir)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    size_t headers = 0, found = 0;
    CHECK(d != NULL, "cannot open %s", dir);
    while (d && (e = readdir(d)) != NULL) {
        size_t len = strlen(e->d_name);
        char path[1024];
        if (len < 3 || strcmp(e->d_name + len - 2, ".h") != 0)
            continue;
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        found += check_header(path);
        ++headers;
    }
    if (d)
        closedir(d);
    CHECK(headers >= 7 && found == n_called,
          "%zu headers declare %zu functions taking a relief_error, %zu were called",
          headers, found, n_called);
    printf("%zu entry points taking a relief_error, in %zu headers\n",
           found, headers);
}

int main(int argc, char **argv)
{
    relief_mesh *cap, *tet;
    if (!api_test_locale())
        return 2;
    if (argc < 2) {
        fprintf(stderr, "usage: test_api_null_err INCLUDE_DIR (include/relief)\n");
        return 2;
    }
    snprintf(tmp, sizeof tmp, "/tmp/relief-null-err-XXXXXX");
    if (!mkdtemp(tmp))
        return 2;
    cap = synth_capture(RELIEF_SYNTH_PLANE_WAVES, 600);
    tet = tetrahedron();
    test_core();
    test_meshes();
    test_mesh_files();
    test_fit();
    test_smooth(cap, tet);
    test_complete(cap, tet);
    test_report_folder(cap);
    test_eval(cap, tet);
    test_image_files();
    test_image_fill();
    test_depth_files();
    test_depth_fill(tet);
    test_occluders();
    test_points(cap, tet);
    test_headers(argv[1]);
    relief_mesh_destroy(cap);
    relief_mesh_destroy(tet);
    {
        char cmd[600];
        snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmp);
        if (system(cmd) != 0)
            fprintf(stderr, "could not remove %s\n", tmp);
    }
    API_TEST_END();
}
