/* The closure checks (mesh/mesh_check.h) on meshes as their files have
 * them (no repair): per file, its size, the edge census and the triangles
 * crossing others, each with its median wall time over REPEAT runs (one
 * thread). --subdivide N first splits every triangle into 4 at its edges'
 * midpoints, N times: the same surface with 4^N times the triangles, and
 * coplanar neighbours everywhere (the exact predicates' slow path), to
 * time the grid at half a million triangles and more. --csv appends the
 * rows to PATH.
 *   bench_mesh_check FILE... [--subdivide N] [--repeat N] [--csv PATH] */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_util.h"
#include "base/clock.h"
#include "mesh/mesh.h"
#include "mesh/mesh_check.h"

static int cmp_double(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

/* The distinct edge keys' index of the edge a b (keys: n sorted, unique). */
static size_t edge_at(const uint64_t *keys, size_t n, uint32_t a, uint32_t b)
{
    const uint64_t k = a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = (lo + hi) / 2;
        if (keys[mid] < k)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* m with each triangle split into 4 at its edges' midpoints (a vertex a
 * distinct edge, shared by its triangles); NULL when out of memory. */
static relief_mesh *subdivide(const relief_mesh *m)
{
    uint64_t *keys = relief_edge_keys(m->tri, m->nt);
    relief_mesh *s = NULL;
    size_t ne = 0;
    for (size_t i = 0; keys && i < 3 * m->nt; ++i) /* unique in place */
        if (i == 0 || keys[i] != keys[ne - 1])
            keys[ne++] = keys[i];
    if (!keys || relief_mesh_create(m->nv + ne, 4 * m->nt, 0, &s, NULL) != RELIEF_OK) {
        free(keys);
        return NULL;
    }
    memcpy(s->pos, m->pos, 3 * m->nv * sizeof *s->pos);
    for (size_t e = 0; e < ne; ++e)
        for (int k = 0; k < 3; ++k)
            s->pos[3 * (m->nv + e) + k] = 0.5 * (m->pos[3 * (keys[e] >> 32) + k] +
                                                 m->pos[3 * (keys[e] & 0xffffffffu) + k]);
    for (size_t t = 0; t < m->nt; ++t) {
        const uint32_t *f = m->tri + 3 * t;
        uint32_t mid[3], *q = s->tri + 12 * t;
        for (int k = 0; k < 3; ++k)
            mid[k] = (uint32_t)(m->nv + edge_at(keys, ne, f[k], f[(k + 1) % 3]));
        const uint32_t out[12] = {f[0], mid[0], mid[2], f[1], mid[1], mid[0],
                                  f[2], mid[2], mid[1], mid[0], mid[1], mid[2]};
        memcpy(q, out, sizeof out);
    }
    free(keys);
    return s;
}

/* One file's row: the census and the crossings, median times. */
static void row(const char *path, const relief_mesh *m, int repeat, FILE *csv)
{
    double tc[64], ts[64];
    relief_edge_census_result r;
    relief_error err = {0};
    size_t hits = 0;
    for (int i = 0; i < repeat; ++i) {
        double t0 = relief_seconds(), t1, t2;
        if (relief_edge_census(m->tri, m->nt, m->nv, NULL, &r, &err) != RELIEF_OK)
            break;
        t1 = relief_seconds();
        if (relief_self_intersections(m->pos, m->nv, m->tri, m->nt, NULL, NULL, &hits, &err) !=
            RELIEF_OK)
            break;
        t2 = relief_seconds();
        tc[i] = t1 - t0, ts[i] = t2 - t1;
    }
    if (err.message[0]) {
        fprintf(stderr, "bench_mesh_check: %s: %s\n", path, err.message);
        return;
    }
    qsort(tc, (size_t)repeat, sizeof *tc, cmp_double);
    qsort(ts, (size_t)repeat, sizeof *ts, cmp_double);
    const char *name = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    printf("%-24s %9zu %9zu %8zu %6zu %8zu %9.4f %9zu %9.4f\n", name, m->nv, m->nt,
           r.boundary_edges, r.boundary_loops, r.nonmanifold_edges, tc[repeat / 2], hits,
           ts[repeat / 2]);
    if (csv)
        fprintf(csv, "%s,%zu,%zu,%zu,%zu,%zu,%.6f,%zu,%.6f\n", path, m->nv, m->nt,
                r.boundary_edges, r.boundary_loops, r.nonmanifold_edges, tc[repeat / 2], hits,
                ts[repeat / 2]);
}

int main(int argc, char **argv)
{
    int repeat = 3, subdivisions = 0;
    const char *csv_path = NULL;
    FILE *csv = NULL;
    bench_machine mach;
    for (int i = 1; i + 1 < argc; ++i)
        if (strcmp(argv[i], "--repeat") == 0)
            repeat = atoi(argv[++i]);
        else if (strcmp(argv[i], "--subdivide") == 0)
            subdivisions = atoi(argv[++i]);
        else if (strcmp(argv[i], "--csv") == 0)
            csv_path = argv[++i];
    repeat = repeat < 1 ? 1 : repeat > 64 ? 64 : repeat;
    if (csv_path && !(csv = fopen(csv_path, "a"))) {
        perror(csv_path);
        return 1;
    }
    bench_read_machine(&mach);
    printf("# %s, one thread; medians of %d; %d subdivision(s)\n", mach.cpu, repeat,
           subdivisions);
    printf("%-24s %9s %9s %8s %6s %8s %9s %9s %9s\n", "file", "vertices", "triangles",
           "boundary", "loops", "nonmanif", "census_s", "crossing", "cross_s");
    for (int i = 1; i < argc; ++i) {
        const relief_read_options raw = {1};
        relief_mesh *m = NULL;
        relief_error err = {0};
        if (argv[i][0] == '-' && argv[i][1] == '-') {
            ++i;
            continue;
        }
        if (relief_mesh_read_with(argv[i], &raw, &m, NULL, &err) != RELIEF_OK) {
            fprintf(stderr, "bench_mesh_check: %s\n", err.message);
            continue;
        }
        for (int k = 0; k < subdivisions && m; ++k) {
            relief_mesh *s = subdivide(m);
            relief_mesh_destroy(m);
            m = s;
        }
        if (m)
            row(argv[i], m, repeat, csv);
        relief_mesh_destroy(m);
    }
    if (csv)
        fclose(csv);
    return 0;
}
