/* The repair on reading (host/mesh/repair.c): one hand-made soup per defect,
 * each checked by its counts and by the result being edge- and
 * vertex-manifold, consistently oriented and storable by OpenMesh; a clean
 * mesh comes back untouched; coordinates out of range are refused naming
 * the vertex. With DATA_DIR (../shared/data/real), the three ggg_sfm
 * photogrammetry meshes are read, repaired and cut, and the cut is
 * storable and reads back with nothing to repair.
 *   usage: test_repair [DATA_DIR] */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check.h"
#include "mesh/io_openmesh.h"
#include "mesh/mesh.h"
#include "synth/cut.h"

/* An n x n grid of unit squares in z = 0, two triangles each, all
 * counter-clockwise seen from +z; `extra_v` and `extra_t` zeroed rows after. */
static relief_mesh *grid(int n, size_t extra_v, size_t extra_t)
{
    relief_mesh *m = NULL;
    const size_t nv = (size_t)(n + 1) * (n + 1), nt = 2 * (size_t)n * n;
    relief_error err;
    if (relief_mesh_create(nv + extra_v, nt + extra_t, 0, &m, &err) != RELIEF_OK)
        return NULL;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            double *p = m->pos + 3 * ((size_t)j * (n + 1) + i);
            p[0] = i;
            p[1] = j;
        }
    size_t t = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            uint32_t a = (uint32_t)(j * (n + 1) + i), b = a + 1, c = a + (uint32_t)n + 1,
                     d = c + 1;
            uint32_t f[6] = {a, b, d, a, d, c};
            memcpy(m->tri + 3 * t, f, sizeof f);
            t += 2;
        }
    return m;
}

static void set_tri(relief_mesh *m, size_t t, uint32_t a, uint32_t b, uint32_t c)
{
    m->tri[3 * t] = a;
    m->tri[3 * t + 1] = b;
    m->tri[3 * t + 2] = c;
}

static void set_pos(relief_mesh *m, size_t v, double x, double y, double z)
{
    m->pos[3 * v] = x;
    m->pos[3 * v + 1] = y;
    m->pos[3 * v + 2] = z;
}

static int key_cmp(const void *x, const void *y)
{
    uint64_t a = *(const uint64_t *)x, b = *(const uint64_t *)y;
    return a < b ? -1 : a > b;
}

static uint64_t key(uint32_t a, uint32_t b)
{
    return (uint64_t)a << 32 | b;
}

/* Edge- and vertex-manifold and consistently oriented: every directed edge
 * once (so no undirected edge has three triangles, and neighbours walk
 * their edge opposite ways); around each vertex one fan: following each
 * triangle's edge into the vertex to the triangle with the edge out of it,
 * at most one triangle has no such neighbour (0 inside, 1 on the border);
 * and OpenMesh adds every triangle in order. */
static int is_manifold(const relief_mesh *m, const char *what)
{
    int ok = 1;
    uint64_t *e = malloc((3 * m->nt + 1) * sizeof *e);
    size_t *starts = calloc(m->nv + 1, sizeof *starts);
    for (size_t s = 0; s < 3 * m->nt; ++s)
        e[s] = key(m->tri[s], m->tri[3 * (s / 3) + (s % 3 + 1) % 3]);
    qsort(e, 3 * m->nt, sizeof *e, key_cmp);
    for (size_t s = 1; s < 3 * m->nt; ++s)
        if (e[s] == e[s - 1]) {
            fprintf(stderr, "%s: edge %u-%u twice the same way\n", what,
                    (unsigned)(e[s] >> 32), (unsigned)e[s]);
            ok = 0;
        }
    for (size_t s = 0; s < 3 * m->nt; ++s) {
        const uint32_t v = m->tri[s], in = m->tri[3 * (s / 3) + (s % 3 + 2) % 3];
        const uint64_t out = key(v, in);
        starts[v] += !bsearch(&out, e, 3 * m->nt, sizeof *e, key_cmp);
    }
    for (size_t v = 0; v < m->nv; ++v)
        if (starts[v] > 1) {
            fprintf(stderr, "%s: vertex %zu: %zu fans\n", what, v, starts[v]);
            ok = 0;
        }
    free(e);
    free(starts);
    relief_error err;
    relief_mesh bare = *m;
    uint8_t *accepted = malloc(m->nt + 1);
    bare.nt = 0;
    bare.tri = NULL;
    if (relief_om_storable(&bare, m->tri, m->nt, accepted, &err) != RELIEF_OK)
        ok = 0;
    for (size_t t = 0; ok && t < m->nt; ++t)
        if (!accepted[t]) {
            fprintf(stderr, "%s: OpenMesh refuses triangle %zu\n", what, t);
            ok = 0;
        }
    free(accepted);
    return ok;
}

static relief_repair_info repair(relief_mesh *m, const char *what)
{
    relief_repair_info info;
    relief_error err = {0};
    memset(&info, 0, sizeof info);
    CHECK(relief_mesh_repair(m, &info, &err) == RELIEF_OK, "%s: %s", what, err.message);
    CHECK(is_manifold(m, what), "%s: not manifold after the repair", what);
    return info;
}

static void test_clean(void)
{
    relief_mesh *m = grid(3, 0, 0), *c = NULL;
    relief_error err;
    relief_mesh_copy(m, &c, &err);
    relief_repair_info i = repair(m, "clean");
    CHECK(relief_repair_info_describe(&i, NULL, 0) == 0, "clean grid: something repaired");
    CHECK(m->nv == c->nv && m->nt == c->nt &&
              !memcmp(m->tri, c->tri, 3 * m->nt * sizeof *m->tri) &&
              !memcmp(m->pos, c->pos, 3 * m->nv * sizeof *m->pos),
          "a clean mesh came back changed");
    relief_mesh_destroy(m);
    relief_mesh_destroy(c);
}

/* Every triangle on its own three vertices, as STL and some exporters
 * write: 24 vertices weld into the grid's 9. */
static void test_duplicate_vertices(void)
{
    relief_mesh *g = grid(2, 0, 0), *m = NULL;
    relief_error err;
    relief_mesh_create(3 * g->nt, g->nt, 0, &m, &err);
    for (size_t t = 0; t < g->nt; ++t)
        for (int k = 0; k < 3; ++k) {
            memcpy(m->pos + 3 * (3 * t + k), g->pos + 3 * (size_t)g->tri[3 * t + k],
                   3 * sizeof(double));
            m->tri[3 * t + k] = (uint32_t)(3 * t + k);
        }
    relief_repair_info i = repair(m, "soup");
    CHECK(i.vertices_welded == 15, "soup: %zu welded, expected 15", i.vertices_welded);
    CHECK(m->nv == 9 && m->nt == 8, "soup: %zu vertices %zu triangles, expected 9 and 8", m->nv,
          m->nt);
    CHECK(i.nonmanifold_vertices == 0 && i.vertices_added == 0, "soup: %zu split",
          i.nonmanifold_vertices);
    relief_mesh_destroy(g);
    relief_mesh_destroy(m);
}

static void test_duplicate_face(void)
{
    relief_mesh *m = grid(2, 0, 1);
    set_tri(m, 8, m->tri[5], m->tri[4], m->tri[3]); /* triangle 1 again, reversed */
    relief_repair_info i = repair(m, "duplicate face");
    CHECK(i.duplicate_triangles == 1 && m->nt == 8, "duplicate face: %zu dropped, %zu left",
          i.duplicate_triangles, m->nt);
    relief_mesh_destroy(m);
}

static void test_flipped(void)
{
    relief_mesh *m = grid(2, 0, 0), *c = NULL;
    relief_error err;
    uint32_t s = m->tri[3 * 3 + 1];
    m->tri[3 * 3 + 1] = m->tri[3 * 3 + 2];
    m->tri[3 * 3 + 2] = s;
    relief_mesh_copy(m, &c, &err);
    relief_repair_info i = repair(m, "flipped");
    CHECK(i.triangles_flipped == 1, "flipped: %zu flipped, expected 1", i.triangles_flipped);
    /* the majority's way: the other seven stay as they were */
    CHECK(!memcmp(m->tri, c->tri, 9 * sizeof *m->tri) &&
              !memcmp(m->tri + 12, c->tri + 12, 12 * sizeof *m->tri),
          "flipped: another triangle turned");
    relief_mesh_destroy(m);
    relief_mesh_destroy(c);
}

/* A fin standing on the grid's inner edge 4-8 (the diagonal of a square): three
 * triangles on one edge; the fin, the least coplanar, goes. */
static void test_nonmanifold_edge(void)
{
    relief_mesh *m = grid(2, 1, 1);
    set_pos(m, 9, 0.5, 0.5, 2.0);
    set_tri(m, 8, 4, 8, 9);
    relief_repair_info i = repair(m, "fin");
    CHECK(i.nonmanifold_edges == 1 && i.nonmanifold_edge_triangles == 1,
          "fin: %zu edges, %zu triangles dropped", i.nonmanifold_edges,
          i.nonmanifold_edge_triangles);
    CHECK(m->nt == 8 && m->nv == 9, "fin: %zu triangles %zu vertices, expected 8 and 9", m->nt,
          m->nv);
    for (size_t v = 0; v < m->nv; ++v)
        CHECK(m->pos[3 * v + 2] == 0.0, "fin: its apex is still there");
    relief_mesh_destroy(m);
}

/* Two grids touching at one corner (vertex 8 of the first is vertex 0 of the
 * second): the corner is split, one vertex per fan. */
static void test_bow_tie(void)
{
    relief_mesh *a = grid(2, 8, 8);
    for (size_t v = 1; v < 9; ++v)
        set_pos(a, 8 + v, 2.0 + a->pos[3 * v], 2.0 + a->pos[3 * v + 1], 0.0);
    for (size_t t = 0; t < 8; ++t)
        for (int k = 0; k < 3; ++k)
            a->tri[3 * (8 + t) + k] = a->tri[3 * t + k] == 0 ? 8 : a->tri[3 * t + k] + 8;
    relief_repair_info i = repair(a, "bow-tie");
    CHECK(i.nonmanifold_vertices == 1 && i.vertices_added == 1,
          "bow-tie: %zu vertices split, %zu added", i.nonmanifold_vertices, i.vertices_added);
    CHECK(a->nv == 18 && a->nt == 16, "bow-tie: %zu vertices %zu triangles, expected 18 and 16",
          a->nv, a->nt);
    CHECK(a->pos[3 * 17] == 2.0 && a->pos[3 * 17 + 1] == 2.0, "bow-tie: the copy is not "
          "the corner");
    relief_mesh_destroy(a);
}

/* A 1-triangle crumb beside a 200-triangle grid goes; a 2-triangle mesh of
 * two crumbs keeps both (each is half of it). */
static void test_stray(void)
{
    relief_mesh *m = grid(10, 3, 1);
    const size_t nv = m->nv - 3;
    set_pos(m, nv, 20, 0, 0);
    set_pos(m, nv + 1, 21, 0, 0);
    set_pos(m, nv + 2, 20, 1, 0);
    set_tri(m, 200, (uint32_t)nv, (uint32_t)nv + 1, (uint32_t)nv + 2);
    relief_repair_info i = repair(m, "stray");
    CHECK(i.small_components == 1 && i.small_component_triangles == 1 && m->nt == 200,
          "stray: %zu parts, %zu triangles dropped, %zu left", i.small_components,
          i.small_component_triangles, m->nt);
    CHECK(i.vertices_unused == 3 && m->nv == nv, "stray: %zu vertices dropped",
          i.vertices_unused);
    char text[256];
    relief_repair_info_describe(&i, text, sizeof text);
    CHECK(!strcmp(text, "1 triangles of small stray parts dropped, 3 vertices left unused "
                        "dropped"), "stray: described as '%s'", text);
    relief_mesh_destroy(m);
}

static void test_nothing_left(void)
{
    relief_mesh *m = NULL;
    relief_error err;
    relief_repair_info i;
    /* Two copies of one triangle, the second's corners listed again: it
     * welds and goes, one is left. Then the same with only degenerate
     * triangles: refused by the validation with its message. */
    relief_mesh_create(3, 1, 0, &m, &err);
    set_pos(m, 0, 0, 0, 0);
    set_pos(m, 1, 1, 1, 1);
    set_pos(m, 2, 2, 2, 2);
    set_tri(m, 0, 0, 1, 2);
    CHECK(relief_mesh_repair(m, &i, &err) == RELIEF_E_MESH && strstr(err.message, "degenerate"),
          "degenerate-only: '%s'", err.message);
    CHECK(m->nt == 1, "a refused repair changed the mesh");
    relief_mesh_destroy(m);
}

static void test_range(void)
{
    relief_mesh *m = grid(2, 0, 0);
    relief_error err;
    set_pos(m, 4, 0, 0, 1e31);
    CHECK(relief_mesh_repair(m, NULL, &err) == RELIEF_E_MESH &&
              strstr(err.message, "vertex 4") && strstr(err.message, "out of range"),
          "1e31: '%s'", err.message);
    set_pos(m, 4, 1e30, 0, 0);
    CHECK(relief_mesh_repair(m, NULL, &err) == RELIEF_E_MESH &&
              strstr(err.message, "vertex 4") && strstr(err.message, "out of range"),
          "1e30 in a unit grid: '%s'", err.message);
    set_pos(m, 4, 1e14, 0, 0);
    CHECK(relief_mesh_repair(m, NULL, &err) == RELIEF_OK, "1e14 in a unit grid: '%s'",
          err.message);
    /* The whole grid scaled by 1e30: over 1e30 in magnitude. */
    for (size_t i = 0; i < 3 * m->nv; ++i)
        m->pos[i] *= 1e30;
    CHECK(relief_mesh_repair(m, NULL, &err) == RELIEF_E_MESH && strstr(err.message, "1e30"),
          "scaled by 1e30: '%s'", err.message);
    relief_mesh_destroy(m);
}

/* The real captures: repaired, manifold, cut, the cut storable and read
 * back with nothing left to repair. */
static void test_real(const char *data)
{
    static const char *const names[] = {"blackVase", "plasticVase", "Angel"};
    for (size_t n = 0; n < 3; ++n) {
        char path[600], cut_path[600];
        struct stat sb;
        relief_mesh *m = NULL, *cap = NULL, *truth = NULL, *back = NULL;
        relief_read_info info;
        relief_error err = {0};
        size_t n_cut;
        snprintf(path, sizeof path, "%s/ggg_sfm/%s.ply", data, names[n]);
        if (stat(path, &sb) != 0) {
            printf("skip %s: not found\n", path);
            continue;
        }
        CHECK(relief_mesh_read(path, &m, &info, &err) == RELIEF_OK, "%s", err.message);
        if (!m)
            continue;
        char text[512];
        relief_repair_info_describe(&info.repair, text, sizeof text);
        printf("%s: %zu vertices, %zu triangles after: %s\n", names[n], m->nv, m->nt, text);
        CHECK(info.repaired && info.nonmanifold_triangles > 0, "%s: nothing repaired", path);
        CHECK(is_manifold(m, names[n]), "%s: not manifold after the repair", path);
        /* A ball around the middle vertex, 8 % of the box's diagonal. */
        relief_cut_region ball = {RELIEF_CUT_BALL, {0, 0, 0}, {0, 0, 0}, 0, 0};
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (size_t v = 0; v < m->nv; ++v)
            for (int k = 0; k < 3; ++k) {
                lo[k] = fmin(lo[k], m->pos[3 * v + k]);
                hi[k] = fmax(hi[k], m->pos[3 * v + k]);
            }
        memcpy(ball.point, m->pos + 3 * (m->nv / 2), sizeof ball.point);
        ball.radius = 0.08 * sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) +
                                  (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                  (hi[2] - lo[2]) * (hi[2] - lo[2]));
        CHECK(relief_mesh_cut(m, &ball, &cap, &truth, &n_cut, &err) == RELIEF_OK, "%s: %s",
              path, err.message);
        snprintf(cut_path, sizeof cut_path, "%s/%s_cut.ply", check_tmpdir(), names[n]);
        CHECK(cap && relief_mesh_write(cap, cut_path, NULL, &err) == RELIEF_OK, "%s: %s", path,
              err.message);
        CHECK(relief_mesh_read(cut_path, &back, &info, &err) == RELIEF_OK, "%s: %s", cut_path,
              err.message);
        printf("%s cut: %zu vertices cut; read back: %s\n", names[n], n_cut,
               relief_repair_info_describe(&info.repair, text, sizeof text) ? text
                                                                             : "nothing to repair");
        CHECK(back && is_manifold(back, "cut"), "%s: the cut is not manifold", cut_path);
        remove(cut_path);
        relief_mesh_destroy(back);
        relief_mesh_destroy(cap);
        relief_mesh_destroy(truth);
        relief_mesh_destroy(m);
    }
}

int main(int argc, char **argv)
{
    test_clean();
    test_duplicate_vertices();
    test_duplicate_face();
    test_flipped();
    test_nonmanifold_edge();
    test_bow_tie();
    test_stray();
    test_nothing_left();
    test_range();
    if (argc > 1)
        test_real(argv[1]);
    if (argc > 1)
        rmdir(check_tmpdir());
    return check_result();
}
