/* Captures relief refuses, on tiny meshes with known answers: an edge with
 * three triangles, a fold; and those it accepts: a grid wound either way
 * (the majority decides which side is up), two fans touching at a vertex,
 * a little noise facing away at a silhouette. */
#include <string.h>

#include "check.h"
#include "mesh/mesh.h"
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

int main(void)
{
    relief_fit_primitive plane;
    relief_error err = {RELIEF_OK, ""};
    memset(&plane, 0, sizeof plane);
    plane.model = RELIEF_FIT_PLANE;
    plane.dir[2] = 1.0; /* normal +z through the origin */

    for (int flip = 0; flip < 2; ++flip) {
        relief_mesh *m = grid(6, flip, 0);
        CHECK(m && relief_capture_check(m, &plane, &err) == RELIEF_OK,
              "a flat grid wound %s: %s", flip ? "clockwise" : "counter-clockwise",
              err.message);
        relief_mesh_destroy(m);
    }
    { /* A fin on the interior edge 8-15 (vertex 8 is (1, 1), 15 is (1, 2)). */
        relief_mesh *m = grid(6, 0, 1);
        double *p = m->pos + 3 * 49;
        p[0] = 1.5, p[1] = 1.5, p[2] = 1.0;
        m->tri[3 * 72] = 8, m->tri[3 * 72 + 1] = 15, m->tri[3 * 72 + 2] = 49;
        CHECK(relief_capture_check(m, &plane, &err) == RELIEF_E_MESH &&
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
            CHECK(relief_capture_check(m, &plane, &err) == RELIEF_OK, "a bowtie: %s",
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
        CHECK(relief_capture_check(m, &plane, &err) == RELIEF_E_MESH &&
                  strstr(err.message, "overlaps itself over the fitted plane") &&
                  strstr(err.message, "24 triangles (33.3% of its area"),
              "%zu triangles folded: %s", flipped, err.message);
        relief_mesh_destroy(m);
    }
    { /* One small triangle of 72 facing away (1.4 % of the area): over the
       * 1 % allowed; shrink it below and it is noise. */
        relief_mesh *m = grid(6, 0, 0);
        uint32_t x = m->tri[1];
        m->tri[1] = m->tri[2];
        m->tri[2] = x;
        CHECK(relief_capture_check(m, &plane, &err) == RELIEF_E_MESH &&
                  strstr(err.message, "1 triangles (1.4% of its area"),
              "one triangle folded: %s", err.message);
        /* Now make that triangle a sliver: vertex 1 moves from (1, 0) to
         * (0.3, 0); its other triangles stay right side up. */
        m->pos[3 * 1] = 0.3;
        CHECK(relief_capture_check(m, &plane, &err) == RELIEF_OK,
              "a sliver facing away (0.4%% of the area) refused: %s", err.message);
        relief_mesh_destroy(m);
    }
    return check_result();
}
