/* Captures relief refuses, on tiny meshes with known answers: an edge with
 * three triangles, a fold over a third of the area; and those it accepts: a
 * grid wound either way (the majority decides which side is up), two fans
 * touching at a vertex, and a triangle facing away (a depth camera's fringe),
 * which is dropped with its vertices. */
#include <string.h>

#include "check.h"
#include "mesh/mesh.h"
#include "smooth/surface.h"
#include "smooth/surface_check.h"

/* An n x n grid of unit cells in z = 0, two triangles per cell, wound
 * counter-clockwise seen from +z (flip: clockwise), with room for `extra`
 * more vertices and triangles. */
static relief_mesh *grid(int n, int flip, int extra)
{
    relief_mesh *m = NULL;
    size_t t = 0;
    if (relief_mesh_create((size_t)((n + 1) * (n + 1) + extra), (size_t)(2 * n * n + extra), 0,
                           &m, NULL) != RELIEF_OK)
        return NULL;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            double *p = m->pos + 3 * (size_t)(j * (n + 1) + i);
            p[0] = i, p[1] = j, p[2] = 0.0;
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            uint32_t a = (uint32_t)(j * (n + 1) + i), b = a + 1, c = a + (uint32_t)n + 2,
                     d = a + (uint32_t)n + 1;
            uint32_t f[6] = {a, b, c, a, c, d};
            if (flip)
                f[1] = c, f[2] = b, f[4] = d, f[5] = c;
            memcpy(m->tri + 3 * t, f, sizeof f);
            t += 2;
        }
    return m;
}

/* relief_capture_check without the unfolded capture. */
static relief_status capture_check(const relief_mesh *m, const relief_fit_primitive *pr,
                                   relief_error *err)
{
    relief_mesh *unfolded = NULL;
    relief_status st = relief_capture_check(m, pr, &unfolded, NULL, err);
    relief_mesh_destroy(unfolded);
    return st;
}

int main(void)
{
    relief_fit_primitive plane;
    relief_error err = {0};
    memset(&plane, 0, sizeof plane);
    plane.model = RELIEF_FIT_PLANE;
    plane.dir[2] = 1.0; /* normal +z through the origin */

    for (int flip = 0; flip < 2; ++flip) {
        relief_mesh *m = grid(6, flip, 0);
        CHECK(m && capture_check(m, &plane, &err) == RELIEF_OK,
              "a flat grid wound %s: %s", flip ? "clockwise" : "counter-clockwise",
              err.message);
        relief_mesh_destroy(m);
    }
    { /* A fin on the interior edge 8-15 (vertex 8 is (1, 1), 15 is (1, 2)). */
        relief_mesh *m = grid(6, 0, 1);
        double *p = m->pos + 3 * 49;
        p[0] = 1.5, p[1] = 1.5, p[2] = 1.0;
        m->tri[3 * 72] = 8, m->tri[3 * 72 + 1] = 15, m->tri[3 * 72 + 2] = 49;
        CHECK(capture_check(m, &plane, &err) == RELIEF_E_MESH &&
                  strstr(err.message, "edge 8-15 at (1, 1.5, 0) is shared by 3 triangles"),
              "a fin: %s", err.message);
        relief_mesh_destroy(m);
    }
    { /* Two triangles touching at vertex 2 only (a bowtie): accepted. */
        static const double pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 2, 1, 0, 2, 2, 0};
        static const uint32_t tri[] = {0, 1, 2, 2, 3, 4};
        relief_mesh *m = NULL;
        if (relief_mesh_create(5, 2, 0, &m, NULL) == RELIEF_OK) {
            memcpy(m->pos, pos, sizeof pos);
            memcpy(m->tri, tri, sizeof tri);
            CHECK(capture_check(m, &plane, &err) == RELIEF_OK, "a bowtie: %s",
                  err.message);
        }
        relief_mesh_destroy(m);
    }
    { /* The last two columns of cells turned upside down: a fold. */
        relief_mesh *m = grid(6, 0, 0);
        size_t flipped = 0;
        for (size_t t = 0; t < m->nt; ++t) {
            const uint32_t a = m->tri[3 * t];
            if (a % 7 >= 4) { /* cells with i >= 4 */
                uint32_t x = m->tri[3 * t + 1];
                m->tri[3 * t + 1] = m->tri[3 * t + 2];
                m->tri[3 * t + 2] = x;
                ++flipped;
            }
        }
        CHECK(capture_check(m, &plane, &err) == RELIEF_E_MESH &&
                  strstr(err.message, "overlaps itself over the fitted plane") &&
                  strstr(err.message, "24 triangles (33.3% of its area"),
              "%zu triangles folded: %s", flipped, err.message);
        relief_mesh_destroy(m);
    }
    { /* One triangle of 72 facing away (1.4 % of the area, under the 10 %
       * refused): dropped with its three vertices (0, 1 and 8) and the
       * triangles around them, the rest kept as it was. */
        relief_mesh *m = grid(6, 0, 0), *u = NULL;
        relief_fold_stats fs;
        uint32_t x = m->tri[1];
        m->tri[1] = m->tri[2];
        m->tri[2] = x;
        CHECK(relief_capture_check(m, &plane, &u, &fs, &err) == RELIEF_OK && u,
              "one triangle folded: %s", err.message);
        if (u) {
            size_t around = 0; /* triangles touching vertex 0, 1 or 8 */
            for (size_t t = 0; t < m->nt; ++t)
                for (int i = 0; i < 3; ++i)
                    if (m->tri[3 * t + i] == 0 || m->tri[3 * t + i] == 1 ||
                        m->tri[3 * t + i] == 8) {
                        ++around;
                        break;
                    }
            CHECK(fs.triangles == 1 && fs.area_fraction > 0.013 && fs.area_fraction < 0.015,
                  "%zu folded triangles, %.4f of the area (1, 1/72)", fs.triangles,
                  fs.area_fraction);
            CHECK(u->nv == m->nv - 3 && fs.vertices_dropped == 3, "%zu of %zu vertices kept",
                  u->nv, m->nv);
            CHECK(u->nt == m->nt - around && fs.triangles_dropped == around,
                  "%zu of %zu triangles kept (%zu around the fold)", u->nt, m->nt, around);
            CHECK(memcmp(u->pos, m->pos + 3 * 2, 3 * sizeof(double)) == 0,
                  "the first vertex kept is not the grid's vertex 2");
        }
        relief_mesh_destroy(u);
        u = NULL;
        /* Unwound, nothing is dropped. */
        m->tri[2] = m->tri[1];
        m->tri[1] = x;
        CHECK(relief_capture_check(m, &plane, &u, &fs, &err) == RELIEF_OK && !u &&
                  fs.triangles == 0,
              "a flat grid gave an unfolded copy: %s", err.message);
        relief_mesh_destroy(u);
        relief_mesh_destroy(m);
    }
    { /* Spikes: a rough grid (heights 0.01 x a fixed pattern) with one
       * vertex lifted 1 above it: dropped, with its 6 triangles; the rough
       * grid alone, and a step (a band's edge, every vertex inside its
       * neighbours' range), keep everything. */
        relief_mesh *m = grid(8, 0, 0), *u = NULL;
        relief_spike_stats sp;
        for (size_t v = 0; v < m->nv; ++v)
            m->pos[3 * v + 2] = 0.01 * (double)((v * 7) % 5) / 4.0;
        CHECK(relief_capture_spikes(m, &plane, RELIEF_SPIKE_K, &u, &sp, &err) == RELIEF_OK &&
                  !u && sp.vertices == 0 && sp.scale > 0.0,
              "a rough grid has %zu spikes (scale %g, largest %g): %s", sp.vertices, sp.scale,
              sp.largest, err.message);
        relief_mesh_destroy(u);
        u = NULL;
        m->pos[3 * 40 + 2] = 1.0; /* vertex 40: (4, 4), inside */
        CHECK(relief_capture_spikes(m, &plane, RELIEF_SPIKE_K, &u, &sp, &err) == RELIEF_OK &&
                  u && sp.vertices == 1 && sp.triangles_dropped == 6 && u->nv == m->nv - 1 &&
                  sp.largest > 0.98,
              "a spike: %zu dropped (%zu triangles), largest %g: %s", sp.vertices,
              sp.triangles_dropped, sp.largest, err.message);
        relief_mesh_destroy(u);
        u = NULL;
        for (size_t v = 0; v < m->nv; ++v) /* a step of 1 at x = 4 */
            m->pos[3 * v + 2] = m->pos[3 * v] >= 4.0 ? 1.0 : 0.0;
        CHECK(relief_capture_spikes(m, &plane, RELIEF_SPIKE_K, &u, &sp, &err) == RELIEF_OK &&
                  !u && sp.vertices == 0,
              "a step has %zu spikes: %s", sp.vertices, err.message);
        relief_mesh_destroy(u);
        relief_mesh_destroy(m);
    }
    return check_result();
}
