/* Half-edge collapses of a free-form level (relief_om_collapse): on a flat
 * 21 x 21 grid of known answer, every requested vertex goes, the result is
 * the even sublattice's 200 triangles, a disc (Euler 1), facing up, its
 * border on the square; nothing goes when every collapse would make an
 * edge over max_edge, or fold against the surface's normals; a
 * non-manifold input is refused. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "mesh/io_openmesh.h"
#include "mesh/mesh.h"

#define N 21 /* grid side, vertices */

static relief_mesh *make_grid(double *nrm, double nz)
{
    relief_mesh *m = NULL;
    relief_error err;
    size_t t = 0;
    if (relief_mesh_create(N * N, 2 * (N - 1) * (N - 1), 0, &m, &err) != RELIEF_OK) {
        fprintf(stderr, "%s\n", err.message);
        exit(2);
    }
    for (size_t j = 0; j < N; ++j)
        for (size_t i = 0; i < N; ++i) {
            size_t v = j * N + i;
            m->pos[3 * v] = (double)i;
            m->pos[3 * v + 1] = (double)j;
            m->pos[3 * v + 2] = 0.0;
            nrm[3 * v] = nrm[3 * v + 1] = 0.0;
            nrm[3 * v + 2] = nz;
        }
    for (size_t j = 0; j + 1 < N; ++j)
        for (size_t i = 0; i + 1 < N; ++i) {
            uint32_t a = (uint32_t)(j * N + i), b = a + 1, c = a + N, d = c + 1;
            uint32_t *f = m->tri + 3 * t;
            /* Diagonals alternate, so no direction is favoured. */
            if ((i + j) % 2) {
                f[0] = a, f[1] = b, f[2] = d, f[3] = a, f[4] = d, f[5] = c;
            } else {
                f[0] = a, f[1] = b, f[2] = c, f[3] = b, f[4] = d, f[5] = c;
            }
            t += 2;
        }
    return m;
}

static int on_square(const double *p)
{
    return p[0] == 0.0 || p[1] == 0.0 || p[0] == N - 1 || p[1] == N - 1;
}

/* Checks the collapsed triangles of the grid: Euler 1, facing +z, border
 * edges on the square, no edge over max_edge. */
static void check_disc(const relief_mesh *m, const uint8_t *removed, const uint32_t *tri,
                       size_t nt, double max_edge)
{
    relief_mesh view = *m;
    relief_adjacency adj;
    relief_error err = {0};
    size_t nv = 0, down = 0, long_edges = 0, off_border = 0, used_removed = 0;
    uint32_t *count;
    for (size_t v = 0; v < m->nv; ++v)
        nv += !removed[v];
    view.tri = (uint32_t *)tri;
    view.nt = nt;
    for (size_t t = 0; t < nt; ++t) {
        const double *a = m->pos + 3 * (size_t)tri[3 * t], *b = m->pos + 3 * (size_t)tri[3 * t + 1],
                     *c = m->pos + 3 * (size_t)tri[3 * t + 2];
        double z = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        down += !(z > 0.0);
        for (int k = 0; k < 3; ++k) {
            const double *p = m->pos + 3 * (size_t)tri[3 * t + k],
                         *q = m->pos + 3 * (size_t)tri[3 * t + (k + 1) % 3];
            long_edges += hypot(p[0] - q[0], p[1] - q[1]) > max_edge;
            used_removed += removed[tri[3 * t + k]];
        }
    }
    CHECK(down == 0, "%zu triangles face down", down);
    CHECK(long_edges == 0, "%zu edges longer than %g", long_edges, max_edge);
    CHECK(used_removed == 0, "%zu corners are removed vertices", used_removed);
    CHECK(relief_mesh_adjacency(&view, &adj, &err) == RELIEF_OK, "%s", err.message);
    if (adj.start) {
        long e = (long)adj.start[m->nv] / 2;
        CHECK((long)nv - e + (long)nt == 1, "Euler characteristic %ld, a disc has 1",
              (long)nv - e + (long)nt);
        relief_adjacency_free(&adj);
    }
    /* A border edge is in one triangle: count each undirected edge. */
    count = calloc(m->nv * m->nv, sizeof *count);
    if (!count)
        exit(2);
    for (size_t t = 0; t < nt; ++t)
        for (int k = 0; k < 3; ++k) {
            uint32_t a = tri[3 * t + k], b = tri[3 * t + (k + 1) % 3];
            ++count[a < b ? a * m->nv + b : b * m->nv + a];
        }
    for (size_t i = 0; i < m->nv * m->nv; ++i)
        if (count[i] == 1)
            off_border += !on_square(m->pos + 3 * (i / m->nv)) ||
                          !on_square(m->pos + 3 * (i % m->nv));
    CHECK(off_border == 0, "%zu border edges leave the square", off_border);
    free(count);
}

int main(void)
{
    double nrm[3 * N * N];
    uint8_t remove[N * N], want[N * N];
    uint32_t *tri = NULL;
    size_t nt = 0, left = 0;
    relief_error err = {0};
    relief_mesh *m = make_grid(nrm, 1.0);

    /* Keep the even sublattice (11 x 11): everything else goes. */
    for (size_t j = 0; j < N; ++j)
        for (size_t i = 0; i < N; ++i)
            want[j * N + i] = (i % 2) || (j % 2);
    memcpy(remove, want, sizeof remove);
    CHECK(relief_om_collapse(m, m->pos, nrm, remove, 3.0, &tri, &nt, &err) == RELIEF_OK, "%s",
          err.message);
    for (size_t v = 0; v < N * N; ++v)
        left += want[v] && !remove[v];
    CHECK(left == 0, "%zu requested vertices stayed", left);
    CHECK(nt == 200, "%zu triangles, the 11 x 11 lattice has 200", nt);
    check_disc(m, remove, tri, nt, 3.0);
    free(tri), tri = NULL;

    /* Every collapse joins a vertex to one two spacings away at best. */
    memcpy(remove, want, sizeof remove);
    CHECK(relief_om_collapse(m, m->pos, nrm, remove, 1.5, &tri, &nt, &err) == RELIEF_OK, "%s",
          err.message);
    left = 0;
    for (size_t v = 0; v < N * N; ++v)
        left += remove[v];
    CHECK(left == 0 && nt == 2 * (N - 1) * (N - 1),
          "max_edge 1.5: %zu removed, %zu triangles (expected none, %d)", left, nt,
          2 * (N - 1) * (N - 1));
    check_disc(m, remove, tri, nt, 1.5);
    free(tri), tri = NULL;

    /* Normals that say the surface faces down: every collapse would fold. */
    relief_mesh_destroy(m);
    m = make_grid(nrm, -1.0);
    memcpy(remove, want, sizeof remove);
    CHECK(relief_om_collapse(m, m->pos, nrm, remove, 3.0, &tri, &nt, &err) == RELIEF_OK, "%s",
          err.message);
    left = 0;
    for (size_t v = 0; v < N * N; ++v)
        left += remove[v];
    CHECK(left == 0, "%zu vertices removed against the surface's normals", left);
    free(tri), tri = NULL;

    /* Two triangles running the same way along an edge: not manifold. */
    m->tri[3] = m->tri[0], m->tri[4] = m->tri[1], m->tri[5] = m->tri[2] + N + 1;
    memcpy(remove, want, sizeof remove);
    CHECK(relief_om_collapse(m, m->pos, nrm, remove, 3.0, &tri, &nt, &err) == RELIEF_E_MESH &&
              strstr(err.message, "not manifold"),
          "a non-manifold input: %s", err.message);
    free(tri);
    relief_mesh_destroy(m);
    return check_result();
}
