/* Mesh I/O: round trips through every format, and every kind of bad input
 * rejected with the right status and a message naming the problem. */
#include <dirent.h>
#include <math.h>
#include <stdint.h>
#include <string.h>
#include <sys/stat.h>

#include "check.h"
#include "mesh/mesh.h"

/* A 5 x 4 grid, 20 vertices and 24 triangles, with coordinates, colours and
 * labels that survive float32 and 8-bit colour exactly. */
static relief_mesh *make_grid(void)
{
    relief_mesh *m = NULL;
    relief_error err;
    const size_t nu = 5, nv = 4;
    size_t t = 0;
    if (relief_mesh_create(nu * nv, 2 * (nu - 1) * (nv - 1),
                           RELIEF_MESH_COLOURS | RELIEF_MESH_LABELS, &m, &err) != RELIEF_OK) {
        fprintf(stderr, "%s\n", err.message);
        exit(2);
    }
    for (size_t j = 0; j < nv; ++j)
        for (size_t i = 0; i < nu; ++i) {
            size_t v = j * nu + i;
            m->pos[3 * v] = 0.25 * (double)i - 1.5;
            m->pos[3 * v + 1] = 0.125 * (double)j + 2.0;
            m->pos[3 * v + 2] = 0.0625 * (double)((i * j) % 3);
            m->col[3 * v] = (float)(v * 10) / 255.0f;
            m->col[3 * v + 1] = (float)(255 - v * 7) / 255.0f;
            m->col[3 * v + 2] = (float)((v * 37) % 256) / 255.0f;
            m->label[v] = (uint8_t)(v % 3 == 0);
        }
    for (size_t j = 0; j + 1 < nv; ++j)
        for (size_t i = 0; i + 1 < nu; ++i) {
            uint32_t a = (uint32_t)(j * nu + i), b = a + 1, c = a + 1 + (uint32_t)nu,
                     d = a + (uint32_t)nu;
            uint32_t *f = m->tri + 3 * t;
            f[0] = a, f[1] = b, f[2] = c, f[3] = a, f[4] = c, f[5] = d;
            t += 2;
        }
    return m;
}

static double total_area(const relief_mesh *m)
{
    double a = 0.0;
    for (size_t t = 0; t < m->nt; ++t)
        a += relief_mesh_triangle_area(m, t);
    return a;
}

static void round_trip(const char *name, int ascii, int has_colour, int has_label,
                       int same_order)
{
    char path[256];
    relief_mesh *m = make_grid(), *r = NULL;
    relief_write_options wo = {ascii};
    relief_error err = {0};
    relief_read_info info;
    relief_status st;

    snprintf(path, sizeof path, "%s/%s", check_tmpdir(), name);
    st = relief_mesh_write(m, path, &wo, &err);
    CHECK(st == RELIEF_OK, "%s: write: %s", name, err.message);
    st = relief_mesh_read(path, &r, &info, &err);
    CHECK(st == RELIEF_OK, "%s: read back: %s", name, err.message);
    if (st != RELIEF_OK) {
        relief_mesh_destroy(m);
        return;
    }
    CHECK(r->nv == m->nv, "%s: %zu vertices read, %zu written", name, r->nv, m->nv);
    CHECK(r->nt == m->nt, "%s: %zu triangles read, %zu written", name, r->nt, m->nt);
    CHECK(fabs(total_area(r) - total_area(m)) < 1e-9, "%s: area %g vs %g", name,
          total_area(r), total_area(m));
    if (same_order && r->nv == m->nv && r->nt == m->nt) {
        int pos_ok = 1, tri_ok = 1;
        for (size_t i = 0; i < 3 * m->nv; ++i)
            pos_ok &= r->pos[i] == m->pos[i];
        for (size_t i = 0; i < 3 * m->nt; ++i)
            tri_ok &= r->tri[i] == m->tri[i];
        CHECK(pos_ok, "%s: positions differ", name);
        CHECK(tri_ok, "%s: triangles differ", name);
    }
    CHECK(!has_colour == !r->col, "%s: colour %s", name, r->col ? "present" : "absent");
    if (has_colour && r->col && r->nv == m->nv) {
        float worst = 0.0f;
        for (size_t i = 0; i < 3 * m->nv; ++i)
            worst = fmaxf(worst, fabsf(r->col[i] - m->col[i]));
        CHECK(worst < 1e-6f, "%s: colour differs by %g", name, (double)worst);
    }
    CHECK(!has_label == !r->label, "%s: label %s", name, r->label ? "present" : "absent");
    if (has_label && r->label && r->nv == m->nv)
        CHECK(memcmp(r->label, m->label, m->nv) == 0, "%s: labels differ", name);
    relief_mesh_destroy(r);
    relief_mesh_destroy(m);
}

/* Write `text` to a file `name` in the test directory and return its path. */
static const char *put(const char *name, const char *text)
{
    static char path[256];
    snprintf(path, sizeof path, "%s/%s", check_tmpdir(), name);
    check_write_file(path, text, strlen(text));
    return path;
}

/* Read `path` and require status `want` with `needle` in the message. */
static void expect_reject(const char *path, relief_status want, const char *needle)
{
    relief_mesh *m = NULL;
    relief_error err = {0};
    relief_status st = relief_mesh_read(path, &m, NULL, &err);
    CHECK(st == want, "%s: status %s, expected %s (%s)", path, relief_status_name(st),
          relief_status_name(want), err.message);
    CHECK(m == NULL, "%s: a mesh was returned on failure", path);
    CHECK(strstr(err.message, needle) != NULL, "%s: message '%s' lacks '%s'", path,
          err.message, needle);
    relief_mesh_destroy(m);
}

static const char ply_head[] = "ply\nformat ascii 1.0\nelement vertex 4\n"
                               "property float x\nproperty float y\nproperty float z\n"
                               "element face 2\nproperty list uchar int vertex_indices\n"
                               "end_header\n";

/* Little-endian binary PLY of a unit square; `idx` overrides the second face's
 * last index, `nan_vertex` >= 0 puts a NaN there, `cut` drops trailing bytes. */
static const char *binary_ply(const char *name, int idx, int nan_vertex, size_t cut)
{
    static const char head[] = "ply\nformat binary_little_endian 1.0\nelement vertex 4\n"
                               "property float x\nproperty float y\nproperty float z\n"
                               "element face 2\nproperty list uchar int vertex_indices\n"
                               "end_header\n";
    static char path[256];
    unsigned char buf[512];
    size_t n = strlen(head);
    const float xyz[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const int faces[2][3] = {{0, 1, 2}, {0, 2, 3}};
    memcpy(buf, head, n);
    for (int v = 0; v < 4; ++v)
        for (int k = 0; k < 3; ++k) {
            float f = v == nan_vertex ? NAN : xyz[v][k];
            uint32_t u;
            memcpy(&u, &f, 4);
            for (int b = 0; b < 4; ++b)
                buf[n++] = (unsigned char)(u >> (8 * b));
        }
    for (int f = 0; f < 2; ++f) {
        buf[n++] = 3;
        for (int k = 0; k < 3; ++k) {
            uint32_t u = (uint32_t)(f == 1 && k == 2 ? idx : faces[f][k]);
            for (int b = 0; b < 4; ++b)
                buf[n++] = (unsigned char)(u >> (8 * b));
        }
    }
    snprintf(path, sizeof path, "%s/%s", check_tmpdir(), name);
    check_write_file(path, buf, n - cut);
    return path;
}

static void test_bad_input(void)
{
    char text[1024];
    expect_reject("/nonexistent/relief/mesh.ply", RELIEF_E_IO, "cannot open");
    expect_reject(put("points.xyz", "0 0 0\n"), RELIEF_E_FORMAT, "unknown mesh format");
    expect_reject(put("empty.ply", ""), RELIEF_E_PARSE, "empty");
    expect_reject(check_tmpdir(), RELIEF_E_FORMAT, "unknown mesh format");
    expect_reject(put("magic.ply", "plx\nformat ascii 1.0\n"), RELIEF_E_PARSE, ":1:");
    expect_reject(put("noend.ply", "ply\nformat ascii 1.0\nelement vertex 1\n"),
                  RELIEF_E_PARSE, "end_header");
    expect_reject(put("type.ply", "ply\nformat ascii 1.0\nelement vertex 1\n"
                                  "property quad x\nend_header\n"),
                  RELIEF_E_PARSE, "unknown property type");

    snprintf(text, sizeof text, "%s0 0 0\n1 0 0\n1 1 0\n", ply_head);
    expect_reject(put("trunc.ply", text), RELIEF_E_PARSE, "truncated");
    snprintf(text, sizeof text, "%s0 0 0\n1 0 0\n1 one 0\n0 1 0\n3 0 1 2\n3 0 2 3\n",
             ply_head);
    expect_reject(put("word.ply", text), RELIEF_E_PARSE, ":12: vertex 2");
    snprintf(text, sizeof text, "%s0 0 0\n1 0 0\nnan 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n",
             ply_head);
    expect_reject(put("nan.ply", text), RELIEF_E_MESH, "not finite");
    snprintf(text, sizeof text, "%s0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 7\n",
             ply_head);
    expect_reject(put("range.ply", text), RELIEF_E_MESH, "refers to vertex 7");
    snprintf(text, sizeof text, "%s0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 2\n",
             ply_head);
    expect_reject(put("twice.ply", text), RELIEF_E_MESH, "twice");
    snprintf(text, sizeof text, "%s0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n2 0 2\n",
             ply_head);
    expect_reject(put("corners.ply", text), RELIEF_E_PARSE, "corner");
    snprintf(text, sizeof text, "%s0 0 0\n1 1 1\n2 2 2\n3 3 3\n3 0 1 2\n3 1 2 3\n",
             ply_head);
    expect_reject(put("degenerate.ply", text), RELIEF_E_MESH, "degenerate");
    expect_reject(put("novertex.ply", "ply\nformat ascii 1.0\nelement vertex 0\n"
                                      "property float x\nproperty float y\n"
                                      "property float z\nend_header\n"),
                  RELIEF_E_MESH, "empty");

    expect_reject(binary_ply("bin_trunc.ply", 3, -1, 5), RELIEF_E_PARSE, "truncated");
    expect_reject(binary_ply("bin_range.ply", 9, -1, 0), RELIEF_E_MESH,
                  "face 1 refers to vertex 9 but the file has 4 vertices");
    expect_reject(binary_ply("bin_nan.ply", 3, 2, 0), RELIEF_E_MESH, "vertex 2");

    /* A list on the vertices: OpenMesh reads its items as more scalars
     * (shifted coordinates, then faces that fail), so it is refused. */
    expect_reject(put("vertex_list.ply",
                      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                      "property float y\nproperty float z\nproperty list uchar int foo\n"
                      "end_header\n0 0 0 2 5 6\n1 0 0 1 7\n0 1 0 0\n"),
                  RELIEF_E_PARSE, "list property 'foo'");
    /* Part of a colour: OpenMesh's ascii reader goes out of step (a fuzzed
     * 'rgd green blue' made a 2 GiB face), so it is refused. */
    expect_reject(put("part_colour.ply",
                      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                      "property float y\nproperty float z\nproperty uchar rgd\n"
                      "property uchar green\nproperty uchar blue\nelement face 1\n"
                      "property list uchar int vertex_indices\nend_header\n"
                      "0 0 0 1 2 3\n1 0 0 1 2 3\n0 1 0 1 2 3\n3 0 1 2\n"),
                  RELIEF_E_PARSE, "not all of red, green and blue");
    expect_reject(put("magic.off", "FOO\n3 1 0\n"), RELIEF_E_PARSE, "OFF magic");
    expect_reject(put("trunc.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n"), RELIEF_E_PARSE,
                  "truncated");
    expect_reject(put("range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"),
                  RELIEF_E_MESH, "refers to vertex 3");
    expect_reject(put("inf.off", "OFF\n3 1 0\n0 0 0\n1 inf 0\n0 1 0\n3 0 1 2\n"),
                  RELIEF_E_MESH, ":4: vertex 1");
    /* What OpenMesh would misread (found by fuzzing, tests/fuzz/regressions). */
    expect_reject(put("magicline.off", "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                  RELIEF_E_PARSE, ":1: expected the magic word 'OFF' alone");
    expect_reject(put("extra.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 7\n"),
                  RELIEF_E_PARSE, ":6: face 0: 1 value(s) after its 3 vertex indices");
    expect_reject(put("colour.off", "COFF\n3 1 0\n0 0 0 0.5 0.5 9.5\n1 0 0 0.5 0.5 0.5\n"
                                    "0 1 0 0.5 0.5 0.5\n3 0 1 2\n"),
                  RELIEF_E_MESH, "vertex 0: colour (0.5, 0.5, 9.5) is outside 0..1");
    expect_reject(put("version.ply", "ply\nformat ascii 0.e\nelement vertex 0\nend_header\n"),
                  RELIEF_E_PARSE, ":2: expected 'format");
    expect_reject(put("hash.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 #3\n"), RELIEF_E_PARSE,
                  ":4: face 0: vertex reference '#3'");
    {
        static const char nul[] = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                                  "property float y\nproperty float z\nend_header\0\n0 0 0\n";
        char path[512];
        snprintf(path, sizeof path, "%s/nul.ply", check_tmpdir());
        check_write_file(path, nul, sizeof nul - 1);
        expect_reject(path, RELIEF_E_PARSE, ":7: a NUL byte");
    }

    expect_reject(put("short.obj", "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n"), RELIEF_E_PARSE,
                  ":2: vertex 1");
    expect_reject(put("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"),
                  RELIEF_E_MESH, ":4: face 0 refers to vertex 3");
    expect_reject(put("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"), RELIEF_E_PARSE,
                  "non-zero");

    {
        unsigned char stl[84 + 50] = {0};
        stl[80] = 2; /* two triangles declared, one present */
        char path[256];
        snprintf(path, sizeof path, "%s/trunc.stl", check_tmpdir());
        check_write_file(path, stl, sizeof stl);
        expect_reject(path, RELIEF_E_PARSE, "declares 2 triangles");
    }
    expect_reject(put("odd.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                                 "vertex 1 0 0\nendloop\nendfacet\nendsolid x\n"),
                  RELIEF_E_PARSE, "multiple of 3");
}

/* Files other tools write: OpenMesh's char-label quirk, float colours, point
 * clouds, polygons, negative OBJ indices. */
static void test_variants(void)
{
    relief_mesh *m = NULL;
    relief_error err = {0};
    relief_status st;

    st = relief_mesh_read(put("uchar_label.ply",
                              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                              "property float y\nproperty float z\nproperty uchar label\n"
                              "element face 1\nproperty list uchar int vertex_indices\n"
                              "end_header\n0 0 0 1\n1 0 0 0\n0 1 0 1\n3 0 1 2\n"),
                          &m, NULL, &err);
    CHECK(st == RELIEF_OK, "uchar label: %s", err.message);
    if (st == RELIEF_OK) {
        CHECK(m->label && m->label[0] == 1 && m->label[1] == 0 && m->label[2] == 1,
              "uchar label values wrong");
        relief_mesh_destroy(m);
    }

    st = relief_mesh_read(put("float_colour.ply",
                              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                              "property float y\nproperty float z\nproperty float red\n"
                              "property float green\nproperty float blue\nend_header\n"
                              "0 0 0 1 0 0\n1 0 0 0 1 0\n0 1 0 0 0 1\n"),
                          &m, NULL, &err);
    CHECK(st == RELIEF_OK, "point cloud with float colour: %s", err.message);
    if (st == RELIEF_OK) {
        CHECK(m->nv == 3 && m->nt == 0, "point cloud: %zu vertices %zu triangles", m->nv,
              m->nt);
        CHECK(m->col && fabsf(m->col[0] - 1.0f) < 1e-6f && fabsf(m->col[4] - 1.0f) < 1e-6f,
              "float colours not read");
        relief_mesh_destroy(m);
    }

    st = relief_mesh_read(put("quad.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
                                          "4 0 1 2 3\n"),
                          &m, NULL, &err);
    CHECK(st == RELIEF_OK, "quad OFF: %s", err.message);
    if (st == RELIEF_OK) {
        CHECK(m->nt == 2, "quad split into %zu triangles", m->nt);
        CHECK(fabs(total_area(m) - 1.0) < 1e-12, "quad area %g", total_area(m));
        relief_mesh_destroy(m);
    }

    st = relief_mesh_read(put("negative.obj", "# comment\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                              "f -3/1 -2/2 -1/3\n"),
                          &m, NULL, &err);
    CHECK(st == RELIEF_OK, "negative OBJ indices: %s", err.message);
    if (st == RELIEF_OK) {
        CHECK(m->nt == 1 && m->tri[0] == 0 && m->tri[1] == 1 && m->tri[2] == 2,
              "negative OBJ indices resolved wrongly");
        relief_mesh_destroy(m);
    }
}

static size_t count_entries(const char *dir)
{
    size_t n = 0;
    DIR *d = opendir(dir);
    struct dirent *e;
    if (!d)
        return 0;
    while ((e = readdir(d)))
        n += e->d_name[0] != '.';
    closedir(d);
    return n;
}

/* A failed write leaves the target as it was and no temporary behind. */
static void test_atomic_write(void)
{
    char dir[256], path[300], bad[300];
    relief_mesh *m = make_grid();
    relief_error err = {0};
    struct stat sb;
    const char keep[] = "precious";
    char back[16] = {0};
    FILE *f;

    snprintf(dir, sizeof dir, "%s/atomic", check_tmpdir());
    mkdir(dir, 0700);
    snprintf(path, sizeof path, "%s/out.ply", dir);
    check_write_file(path, keep, sizeof keep);
    m->pos[4] = NAN;
    CHECK(relief_mesh_write(m, path, NULL, &err) == RELIEF_E_MESH,
          "writing a NaN mesh: %s", err.message);
    f = fopen(path, "rb");
    CHECK(f && fread(back, 1, sizeof keep, f) == sizeof keep &&
              memcmp(back, keep, sizeof keep) == 0,
          "the existing file was changed by a failed write");
    if (f)
        fclose(f);
    CHECK(count_entries(dir) == 1, "%zu files in %s after a failed write",
          count_entries(dir), dir);
    m->pos[4] = 0.0;

    snprintf(bad, sizeof bad, "%s/out.xyz", dir);
    CHECK(relief_mesh_write(m, bad, NULL, &err) == RELIEF_E_FORMAT, "unknown extension");
    CHECK(stat(bad, &sb) != 0, "a file was created for an unknown extension");
    snprintf(bad, sizeof bad, "%s/missing/out.ply", dir);
    CHECK(relief_mesh_write(m, bad, NULL, &err) == RELIEF_E_IO,
          "writing into a missing folder: %s", err.message);

    CHECK(relief_mesh_write(m, path, NULL, &err) == RELIEF_OK, "%s", err.message);
    CHECK(count_entries(dir) == 1, "temporary file left behind");
    {
        mode_t mask = umask(0);
        umask(mask);
        CHECK(stat(path, &sb) == 0 && (sb.st_mode & 0777) == (0666 & ~mask),
              "output mode %o, expected %o as a plain create gives",
              (unsigned)(sb.st_mode & 0777), (unsigned)(0666 & ~mask));
    }
    relief_mesh_destroy(m);
}

static void test_real_scans(const char *data)
{
    static const struct {
        const char *file;
        size_t nv, nt;
    } scans[] = {/* as repaired on reading: the drill's file has 1961 and 3855
                    (3 bow-tie vertices, 3 stray triangles), frag_115's 64365
                    and 127229 (17 stray triangles) */
                 {"stanford_drill/drill_shaft_vrip.ply", 1955, 3852},
                 {"bennu_radar/bennu.obj", 1348, 2692},
                 {"fertility/fertility.off", 4494, 9000},
                 {"meshlab_screwdriver/screwdriver.ply", 6789, 13574},
                 {"open3d_frag115/frag_115.ply", 64330, 127212}};
    for (size_t i = 0; i < sizeof scans / sizeof scans[0]; ++i) {
        char path[512];
        relief_mesh *m = NULL;
        relief_error err = {0};
        relief_read_info info;
        struct stat sb;
        snprintf(path, sizeof path, "%s/%s", data, scans[i].file);
        if (stat(path, &sb) != 0) {
            printf("skip %s: not found\n", path);
            continue;
        }
        CHECK(relief_mesh_read(path, &m, &info, &err) == RELIEF_OK, "%s", err.message);
        if (!m)
            continue;
        CHECK(m->nv == scans[i].nv, "%s: %zu vertices, expected %zu", path, m->nv,
              scans[i].nv);
        CHECK(m->nt == scans[i].nt, "%s: %zu triangles, expected %zu", path, m->nt,
              scans[i].nt);
        if (strstr(path, "frag_115"))
            CHECK(m->col && m->nrm, "frag_115 has colour and normals");
        relief_mesh_destroy(m);
    }
}

int main(int argc, char **argv)
{
    round_trip("grid_binary.ply", 0, 1, 1, 1);
    round_trip("grid_ascii.ply", 1, 1, 1, 1);
    round_trip("grid.off", 1, 1, 0, 1);
    round_trip("grid.obj", 1, 0, 0, 1);
    round_trip("grid.stl", 0, 0, 0, 0);
    round_trip("GRID_UPPER.PLY", 0, 1, 1, 1);
    test_bad_input();
    test_variants();
    test_atomic_write();
    if (argc > 1)
        test_real_scans(argv[1]);
    return check_result();
}
