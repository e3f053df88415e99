/* The point-set bench's chores (bench/points.sh), measured by relief's own
 * code:
 *   points_bench_tool measure COMPLETED.ply TRUTH.ply [X,Y,Z,R]
 *       relief_points_measure (host/points/measure.h) printed as JSON, the
 *       added points counted inside the ball only when one is given;
 *   points_bench_tool ply IN OUT.ply
 *       any mesh or point file relief reads, as a PLY (for Open3D);
 *   points_bench_tool pcd2ply IN.pcd OUT.ply
 *       a PCD cloud's finite points (and colour) as a PLY point set;
 *   points_bench_tool sample MESH N SEED OUT.ply
 *       about N points spread evenly on MESH's triangles, as a scanner
 *       samples (blue noise: 6 N drawn uniformly by area with MT19937 and
 *       SEED, kept in draw order when no kept point is within
 *       0.73 sqrt(area / N), which keeps about N), with their triangle's normal: the paper's sizes
 *       (a 22 000 and a 240 000 point bunny) from the scan we have;
 *   points_bench_tool cut-points IN.ply CAPTURE.ply TRUTH.ply X,Y,Z,R
 *       a ball cut from a point set (relief cut needs triangles): CAPTURE
 *       the points outside, TRUTH all of them with `label` 1 inside. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/rng.h"
#include "depth/depth_io.h"
#include "mesh/mesh.h"
#include "points/measure.h"

static relief_mesh *load(const char *path)
{
    relief_mesh *m;
    relief_error err = {0};
    if (relief_mesh_read(path, &m, NULL, &err) != RELIEF_OK) {
        fprintf(stderr, "points_bench_tool: %s\n", err.message);
        exit(1);
    }
    return m;
}

static void save(const relief_mesh *m, const char *path)
{
    relief_error err = {0};
    if (relief_mesh_write(m, path, NULL, &err) != RELIEF_OK) {
        fprintf(stderr, "points_bench_tool: %s\n", err.message);
        exit(1);
    }
}

static void num(const char *key, double v, int last)
{
    if (isfinite(v))
        printf("\"%s\": %.6g%s", key, v, last ? "" : ", ");
    else
        printf("\"%s\": null%s", key, last ? "" : ", ");
}

int main(int argc, char **argv)
{
    relief_error err = {0};
    if ((argc == 4 || argc == 5) && strcmp(argv[1], "measure") == 0) {
        relief_mesh *c = load(argv[2]), *t = load(argv[3]);
        relief_points_measures m;
        double ball[4];
        if (argc == 5 && sscanf(argv[4], "%lf,%lf,%lf,%lf", ball, ball + 1, ball + 2,
                                ball + 3) != 4) {
            fprintf(stderr, "points_bench_tool: measure: the region is X,Y,Z,R\n");
            return 1;
        }
        if (relief_points_measure(c, t, argc == 5 ? ball : NULL, &m, &err) != RELIEF_OK) {
            fprintf(stderr, "points_bench_tool: %s\n", err.message);
            return 1;
        }
        printf("{\"added\": %zu, \"truth_hole\": %zu, ", m.added, m.truth_hole);
        num("acc_rms", m.acc_rms, 0), num("acc_max", m.acc_max, 0);
        num("comp_rms", m.comp_rms, 0), num("comp_max", m.comp_max, 0);
        num("hausdorff", m.hausdorff, 0), num("colour_rms", m.colour_rms, 0);
        num("rough_added", m.rough_added, 0), num("rough_truth_hole", m.rough_truth_hole, 0);
        num("rough_truth_captured", m.rough_truth_captured, 0);
        num("cdetail_added", m.cdetail_added, 0);
        num("cdetail_truth_hole", m.cdetail_truth_hole, 1);
        printf("}\n");
        relief_mesh_destroy(c);
        relief_mesh_destroy(t);
        return 0;
    }
    if (argc == 4 && strcmp(argv[1], "ply") == 0) {
        relief_mesh *m = load(argv[2]);
        save(m, argv[3]);
        relief_mesh_destroy(m);
        return 0;
    }
    if (argc == 4 && strcmp(argv[1], "pcd2ply") == 0) {
        relief_depth_frame f;
        relief_mesh *m;
        if (relief_pcd_read_cloud(argv[2], 0, &f, &err) != RELIEF_OK ||
            relief_depth_frame_points(&f, argv[2], &m, NULL, &err) != RELIEF_OK) {
            fprintf(stderr, "points_bench_tool: %s\n", err.message);
            return 1;
        }
        save(m, argv[3]);
        relief_mesh_destroy(m);
        relief_depth_frame_free(&f);
        return 0;
    }
    if (argc == 6 && strcmp(argv[1], "sample") == 0) {
        relief_mesh *m = load(argv[2]), *o;
        size_t n = strtoull(argv[3], NULL, 10), nt = m->nt;
        double *cum = malloc((nt + 1) * sizeof *cum);
        relief_rng rng;
        if (!nt || !n || !cum || relief_mesh_create(n, 0, RELIEF_MESH_NORMALS, &o, &err) != RELIEF_OK) {
            fprintf(stderr, "points_bench_tool: sample: a mesh with triangles and N >= 1\n");
            return 1;
        }
        cum[0] = 0.0;
        for (size_t t = 0; t < nt; ++t)
            cum[t + 1] = cum[t] + relief_mesh_triangle_area(m, t);
        relief_rng_seed(&rng, (uint32_t)strtoul(argv[4], NULL, 10));
        {
            /* Dart throwing over a hash of cells of side rmin. */
            const double rmin = 0.73 * sqrt(cum[nt] / (double)n);
            const size_t draws = 6 * n, nb = 4 * n + 1;
            double *cand = malloc(draws * 6 * sizeof *cand);
            size_t *head = malloc(nb * sizeof *head), *next = malloc(draws * sizeof *next), kept = 0;
            if (!cand || !head || !next)
                return 1;
            for (size_t b = 0; b < nb; ++b)
                head[b] = SIZE_MAX;
            for (size_t i = 0; i < draws; ++i) {
                double r = relief_rng_uniform(&rng) * cum[nt], u = relief_rng_uniform(&rng),
                       v = relief_rng_uniform(&rng), e1[3], e2[3], nn[3], l, *x = cand + 6 * kept;
                size_t lo = 0, hi = nt;
                const double *a, *b, *c;
                long long ci[3];
                int clash = 0;
                while (hi - lo > 1) {
                    size_t mid = (lo + hi) / 2;
                    if (cum[mid] <= r)
                        lo = mid;
                    else
                        hi = mid;
                }
                if (u + v > 1.0)
                    u = 1.0 - u, v = 1.0 - v;
                a = m->pos + 3 * (size_t)m->tri[3 * lo];
                b = m->pos + 3 * (size_t)m->tri[3 * lo + 1];
                c = m->pos + 3 * (size_t)m->tri[3 * lo + 2];
                for (int k = 0; k < 3; ++k) {
                    e1[k] = b[k] - a[k], e2[k] = c[k] - a[k];
                    x[k] = a[k] + u * e1[k] + v * e2[k];
                    ci[k] = (long long)floor(x[k] / rmin);
                }
                for (int dz = -1; dz <= 1 && !clash; ++dz)
                    for (int dy = -1; dy <= 1 && !clash; ++dy)
                        for (int dx = -1; dx <= 1 && !clash; ++dx) {
                            uint64_t hsh = (uint64_t)(ci[0] + dx) * 73856093u ^
                                           (uint64_t)(ci[1] + dy) * 19349663u ^
                                           (uint64_t)(ci[2] + dz) * 83492791u;
                            for (size_t j = head[hsh % nb]; j != SIZE_MAX && !clash; j = next[j]) {
                                double d2 = 0.0;
                                for (int k = 0; k < 3; ++k)
                                    d2 += (cand[6 * j + k] - x[k]) * (cand[6 * j + k] - x[k]);
                                clash = d2 < rmin * rmin;
                            }
                        }
                if (clash)
                    continue;
                nn[0] = e1[1] * e2[2] - e1[2] * e2[1];
                nn[1] = e1[2] * e2[0] - e1[0] * e2[2];
                nn[2] = e1[0] * e2[1] - e1[1] * e2[0];
                l = sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
                for (int k = 0; k < 3; ++k)
                    x[3 + k] = l > 0.0 ? nn[k] / l : 0.0;
                {
                    uint64_t hsh = (uint64_t)ci[0] * 73856093u ^ (uint64_t)ci[1] * 19349663u ^
                                   (uint64_t)ci[2] * 83492791u;
                    next[kept] = head[hsh % nb];
                    head[hsh % nb] = kept++;
                }
            }
            relief_mesh_destroy(o);
            if (relief_mesh_create(kept, 0, RELIEF_MESH_NORMALS, &o, &err) != RELIEF_OK)
                return 1;
            for (size_t i = 0; i < kept; ++i)
                for (int k = 0; k < 3; ++k)
                    o->pos[3 * i + k] = cand[6 * i + k], o->nrm[3 * i + k] = cand[6 * i + 3 + k];
            free(cand), free(head), free(next);
        }
        save(o, argv[5]);
        free(cum);
        relief_mesh_destroy(o);
        relief_mesh_destroy(m);
        return 0;
    }
    if (argc == 6 && strcmp(argv[1], "cut-points") == 0) {
        relief_mesh *m = load(argv[2]), *t, *c;
        uint8_t *keep;
        double b[4];
        if (sscanf(argv[5], "%lf,%lf,%lf,%lf", b, b + 1, b + 2, b + 3) != 4) {
            fprintf(stderr, "points_bench_tool: cut-points: X,Y,Z,R\n");
            return 1;
        }
        if (relief_mesh_create(m->nv, 0, RELIEF_MESH_LABELS | (m->col ? RELIEF_MESH_COLOURS : 0u),
                               &t, &err) != RELIEF_OK || !(keep = malloc(m->nv)))
            return 1;
        memcpy(t->pos, m->pos, m->nv * 3 * sizeof *t->pos);
        if (m->col)
            memcpy(t->col, m->col, m->nv * 3 * sizeof *t->col);
        for (size_t i = 0; i < m->nv; ++i) {
            double d2 = 0.0;
            for (int c = 0; c < 3; ++c)
                d2 += (m->pos[3 * i + c] - b[c]) * (m->pos[3 * i + c] - b[c]);
            t->label[i] = d2 <= b[3] * b[3];
            keep[i] = !t->label[i];
        }
        if (relief_mesh_subset(m, keep, &c, NULL, &err) != RELIEF_OK) {
            fprintf(stderr, "points_bench_tool: %s\n", err.message);
            return 1;
        }
        save(c, argv[3]);
        save(t, argv[4]);
        free(keep);
        relief_mesh_destroy(c);
        relief_mesh_destroy(t);
        relief_mesh_destroy(m);
        return 0;
    }
    fprintf(stderr, "usage: points_bench_tool measure COMPLETED TRUTH [X,Y,Z,R] | ply IN OUT | pcd2ply IN OUT | "
                    "cut-points IN CAPTURE TRUTH X,Y,Z,R | sample MESH N SEED OUT\n");
    return 1;
}
