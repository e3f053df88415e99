/* Numbers in text whatever the caller's locale (issue 60): in a comma-decimal
 * locale, where the program's own printf writes a half as "0,5" (a GTK host
 * such as GIMP, Python after locale.setlocale), relief still reads and writes
 * "0.5": a PFM's scale and an ascii PCD's points, a REAL and a REALS
 * parameter set from text and formatted back, an ascii PLY with fractional
 * coordinates, the meshes (PLY, OFF, OBJ) and the ascii PCD it writes, an
 * image fill's JSON report, a message quoting a value. Afterwards the caller's
 * locale is as it was; a second thread, which starts in the program's global
 * locale, reads and writes the same.
 *   tests/comma_locale.sh LOCALE_DIR test_api_locale
 * (RELIEF_TEST_LOCALE names the locale; without it the test is skipped.) */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */

#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "api_test.h"

static char tmpdir[256];

/* ------------------------------------------------------------- helpers */

static void path_in(char *buf, size_t n, const char *name)
{
    snprintf(buf, n, "%s/%s", tmpdir, name);
}

/* `n` bytes into the file `name` in tmpdir; its path in `path`. */
static int put_file(const char *name, const void *data, size_t n, char *path, size_t cap)
{
    FILE *f;
    path_in(path, cap, name);
    f = fopen(path, "wb");
    if (!f)
        return 0;
    if (fwrite(data, 1, n, f) != n) {
        fclose(f);
        return 0;
    }
    return fclose(f) == 0;
}

/* The whole of a file as a string (free it); NULL when it cannot be read. */
static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    char *buf = NULL;
    long n;
    if (!f)
        return NULL;
    if (fseek(f, 0, SEEK_END) == 0 && (n = ftell(f)) >= 0 && fseek(f, 0, SEEK_SET) == 0 &&
        (buf = malloc((size_t)n + 1)) != NULL) {
        if (fread(buf, 1, (size_t)n, f) != (size_t)n) {
            free(buf);
            buf = NULL;
        } else {
            buf[n] = '\0';
        }
    }
    fclose(f);
    return buf;
}

/* Is the caller's locale still the comma one? */
static int caller_locale_kept(void)
{
    char half[16];
    snprintf(half, sizeof half, "%.1f", 0.5);
    return strcmp(half, "0,5") == 0;
}

/* ----------------------------------------------------------- parameters */

static void test_params(void)
{
    size_t n_image, n_points;
    const relief_param *image = relief_image_fill_param_table(&n_image);
    const relief_param *points = relief_complete_points_param_table(&n_points);
    const relief_param *frac = relief_param_find(image, n_image, "max_hole_fraction");
    const relief_param *ball = relief_param_find(points, n_points, "hole_ball");
    const relief_param *mem = relief_param_find(image, n_image, "max_memory");
    relief_image_fill_params ip = relief_image_fill_params_default();
    relief_complete_points_params pp = relief_complete_points_params_default();
    relief_error err = {0};
    char text[128];

    CHECK(frac && ball && mem, "the parameters are there");
    if (!frac || !ball || !mem)
        return;
    CHECK_STATUS(relief_param_set(&ip, frac, "0.5", &err), RELIEF_OK, err, NULL);
    CHECK(ip.max_hole_fraction == 0.5, "max_hole_fraction from \"0.5\": %g", ip.max_hole_fraction);
    relief_param_format(&ip, frac, text, sizeof text);
    CHECK(strcmp(text, "0.5") == 0, "max_hole_fraction formatted back: %s", text);
    /* '.' is the only decimal point: "0,5" is no number, in any locale. */
    CHECK_STATUS(relief_param_set(&ip, frac, "0,5", &err), RELIEF_E_USAGE, err,
                 "'0,5' is not a finite number");
    CHECK_STATUS(relief_param_set(&pp, ball, "1.5,-2.25,3,0.5", &err), RELIEF_OK, err, NULL);
    CHECK(pp.has_hole_ball && pp.hole_ball[0] == 1.5 && pp.hole_ball[1] == -2.25 &&
              pp.hole_ball[3] == 0.5, "hole_ball from \"1.5,-2.25,3,0.5\"");
    relief_param_format(&pp, ball, text, sizeof text);
    CHECK(strcmp(text, "1.5,-2.25,3,0.5") == 0, "hole_ball formatted back: %s", text);
    CHECK_STATUS(relief_param_set(&ip, mem, "1.5K", &err), RELIEF_OK, err, NULL);
    CHECK(ip.run.max_memory == 1536, "max_memory from \"1.5K\": %llu",
          (unsigned long long)ip.run.max_memory);
    /* A message quotes the value as it would be set. */
    ip = relief_image_fill_params_default();
    ip.max_hole_fraction = 1.5;
    CHECK_STATUS(relief_image_fill_params_validate(&ip, &err), RELIEF_E_RANGE, err,
                 "max_hole_fraction 1.5 ");
}

/* --------------------------------------------------------------- depths */

/* A 3 x 2 PFM, little-endian (scale -1.0), rows bottom to top: the top row
 * holds 0.5 1.5 2.5, the bottom one 3.5 4.5 5.5. */
static void test_pfm(void)
{
    static const char head[] = "Pf\n3 2\n-1.0\n";
    const float rows[6] = {3.5f, 4.5f, 5.5f, 0.5f, 1.5f, 2.5f};
    unsigned char file[sizeof head - 1 + sizeof rows];
    relief_depth_image f;
    relief_error err = {0};
    char path[512];
    memcpy(file, head, sizeof head - 1);
    for (int i = 0; i < 6; ++i) { /* little-endian whatever the host */
        uint32_t u;
        memcpy(&u, &rows[i], 4);
        for (int b = 0; b < 4; ++b)
            file[sizeof head - 1 + 4 * i + b] = (unsigned char)(u >> (8 * b));
    }
    CHECK(put_file("half.pfm", file, sizeof file, path, sizeof path), "write %s", path);
    CHECK_STATUS(relief_depth_read(path, 0, 0, &f, &err), RELIEF_OK, err, NULL);
    if (err.status != RELIEF_OK)
        return;
    CHECK(f.width == 3 && f.height == 2 && f.z[0] == 0.5f && f.z[5] == 5.5f,
          "the PFM's depths: %d x %d, %g ... %g", f.width, f.height, f.z[0], f.z[5]);
    relief_depth_image_free(&f);
}

static const char pcd_ascii[] =
    "# .PCD v0.7 - Point Cloud Data file format\n"
    "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
    "WIDTH 2\nHEIGHT 2\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA ascii\n"
    "0.5 0.25 1.5\n-0.75 0.125 2.5\nnan nan nan\n1.25 -0.5 3.75\n";

/* An ascii PCD read, written back as ascii PCD (its text with '.'), read
 * again: the same points. */
static void test_pcd(void)
{
    relief_depth_image f, g;
    relief_error err = {0};
    char path[512], out[512], *text;
    CHECK(put_file("half.pcd", pcd_ascii, sizeof pcd_ascii - 1, path, sizeof path),
          "write %s", path);
    CHECK_STATUS(relief_depth_read(path, 0, 0, &f, &err), RELIEF_OK, err, NULL);
    if (err.status != RELIEF_OK)
        return;
    CHECK(f.xyz && f.xyz[0] == 0.5f && f.xyz[1] == 0.25f && f.z[0] == 1.5f &&
              f.xyz[3] == -0.75f && f.z[1] == 2.5f && isnan(f.z[2]) && f.z[3] == 3.75f,
          "the PCD's points: z %g %g %g %g", f.z[0], f.z[1], f.z[2], f.z[3]);
    path_in(out, sizeof out, "again.pcd");
    CHECK_STATUS(relief_depth_write(&f, out, RELIEF_DEPTH_PCD_ASCII, 0, &err), RELIEF_OK, err,
                 NULL);
    text = slurp(out);
    CHECK(text && strstr(text, "\n0.5 0.25 1.5\n-0.75 0.125 2.5\n") &&
              strstr(text, "\n1.25 -0.5 3.75\n"), "the ascii PCD written: %s",
          text ? text : "(none)");
    free(text);
    CHECK_STATUS(relief_depth_read(out, 0, 0, &g, &err), RELIEF_OK, err, NULL);
    if (err.status == RELIEF_OK) {
        CHECK(memcmp(f.xyz, g.xyz, 3 * sizeof(float)) == 0 && g.z[3] == 3.75f,
              "the ascii PCD read back");
        relief_depth_image_free(&g);
    }
    relief_depth_image_free(&f);
}

/* --------------------------------------------------------------- meshes */

static const char ply_ascii[] =
    "ply\nformat ascii 1.0\nelement vertex 4\n"
    "property float x\nproperty float y\nproperty float z\n"
    "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n1.5 0 0.25\n1.5 2.5 0.5\n0 2.5 0.75\n3 0 1 2\n3 0 2 3\n";

static const double ply_pos[12] = {0, 0, 0, 1.5, 0, 0.25, 1.5, 2.5, 0.5, 0, 2.5, 0.75};

/* Does `m` hold ply_pos's four vertices? */
static int same_positions(relief_mesh *m)
{
    const double *p = relief_mesh_positions(m);
    if (relief_mesh_vertex_count(m) != 4 || relief_mesh_triangle_count(m) != 2)
        return 0;
    for (int i = 0; i < 12; ++i)
        if (p[i] != ply_pos[i])
            return 0;
    return 1;
}

/* `m` written as `name` (its text must hold "1.5" and no "1,5"), read back. */
static void round_trip(relief_mesh *m, const char *name, int ascii)
{
    relief_write_options o = {ascii};
    relief_error err = {0};
    relief_mesh *back = NULL;
    char path[512], *text;
    path_in(path, sizeof path, name);
    CHECK_STATUS(relief_mesh_write(m, path, &o, &err), RELIEF_OK, err, NULL);
    text = slurp(path);
    CHECK(text && strstr(text, "1.5") && strstr(text, "0.25") && !strstr(text, "1,5") &&
              !strstr(text, "0,25"), "%s written with '.': %s", name, text ? text : "(none)");
    free(text);
    CHECK_STATUS(relief_mesh_read(path, &back, NULL, &err), RELIEF_OK, err, NULL);
    CHECK(back && same_positions(back), "%s read back", name);
    relief_mesh_destroy(back);
}

static void test_mesh(void)
{
    relief_error err = {0};
    relief_mesh *m = NULL;
    char path[512];
    CHECK(put_file("quad.ply", ply_ascii, sizeof ply_ascii - 1, path, sizeof path),
          "write %s", path);
    CHECK_STATUS(relief_mesh_read(path, &m, NULL, &err), RELIEF_OK, err, NULL);
    if (!m)
        return;
    CHECK(same_positions(m), "the ascii PLY's fractional coordinates");
    round_trip(m, "again.ply", 1);
    round_trip(m, "again.off", 0);
    round_trip(m, "again.obj", 0);
    relief_mesh_destroy(m);
}

/* ---------------------------------------------------------------- image */

/* A 48 x 48 grey image of diagonal stripes with a 5 x 5 hole, filled; its
 * report must say "max_hole_fraction": 0.25, as set from "0.25". */
static void test_image_report(void)
{
    enum { W = 48 };
    static uint8_t pix[W * W], hole[W * W];
    relief_image img = {W, W, 1, 8, 0, pix}, mask = {W, W, 1, 8, 0, hole};
    relief_image_fill_params p = relief_image_fill_params_default();
    relief_image_fill_report rep;
    relief_error err = {0};
    size_t n;
    const relief_param *table = relief_image_fill_param_table(&n);
    for (int y = 0; y < W; ++y)
        for (int x = 0; x < W; ++x) {
            pix[y * W + x] = (uint8_t)((x + y) % 8 < 4 ? 40 : 200);
            hole[y * W + x] = x >= 20 && x < 25 && y >= 20 && y < 25;
        }
    p.run.backend = RELIEF_BACKEND_SCALAR;
    CHECK_STATUS(relief_param_set(&p, relief_param_find(table, n, "max_hole_fraction"), "0.25",
                                  &err), RELIEF_OK, err, NULL);
    CHECK_STATUS(relief_image_fill(&img, &mask, &p, &rep, &err), RELIEF_OK, err, NULL);
    if (err.status != RELIEF_OK)
        return;
    CHECK(rep.json && strstr(rep.json, "\"max_hole_fraction\": 0.25"),
          "the report's number: %s", rep.json ? rep.json : "(none)");
    CHECK(rep.json && api_json_numbers_use_dots(rep.json), "a decimal comma in %s", rep.json);
    relief_image_fill_report_free(&rep);
}

/* -------------------------------------------------------------- threads */

/* On a thread of its own, which starts in the program's global locale (the
 * comma one): a parameter read and written, a PCD read. */
static void *other_thread(void *arg)
{
    int *ok = arg;
    size_t n;
    const relief_param *table = relief_image_fill_param_table(&n);
    const relief_param *frac = relief_param_find(table, n, "max_hole_fraction");
    relief_image_fill_params p = relief_image_fill_params_default();
    relief_depth_image f;
    relief_error err = {0};
    char text[64];
    *ok = relief_param_set(&p, frac, "0.125", &err) == RELIEF_OK &&
          relief_param_format(&p, frac, text, sizeof text) > 0 && strcmp(text, "0.125") == 0 &&
          relief_depth_decode(pcd_ascii, sizeof pcd_ascii - 1, "thread.pcd", 0, &f, &err) ==
              RELIEF_OK;
    if (*ok) {
        *ok = f.z[3] == 3.75f;
        relief_depth_image_free(&f);
    }
    *ok = *ok && caller_locale_kept();
    return NULL;
}

static void test_thread(void)
{
    pthread_t t;
    int ok = 0;
    CHECK(pthread_create(&t, NULL, other_thread, &ok) == 0 && pthread_join(t, NULL) == 0 && ok,
          "a second thread read and wrote 0.125 and kept its locale");
}

int main(void)
{
    const char *name = getenv("RELIEF_TEST_LOCALE");
    if (!name || !name[0]) {
        printf("RELIEF_TEST_LOCALE unset: run me through tests/comma_locale.sh; skipped\n");
        return 77;
    }
    if (!api_test_locale())
        return 2;
    snprintf(tmpdir, sizeof tmpdir, "/tmp/relief-api-locale-XXXXXX");
    if (!mkdtemp(tmpdir)) {
        perror(tmpdir);
        return 2;
    }
    test_params();
    test_pfm();
    test_pcd();
    test_mesh();
    test_image_report();
    test_thread();
    CHECK(caller_locale_kept(), "the caller's locale changed under relief");
    {
        char cmd[300];
        snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
        if (system(cmd) != 0)
            fprintf(stderr, "could not remove %s\n", tmpdir);
    }
    API_TEST_END();
}
