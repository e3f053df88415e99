/* Internal layout of relief_mesh. Host code reads and writes the arrays
 * directly; the public API reaches them through accessors. */
#ifndef RELIEF_HOST_MESH_H
#define RELIEF_HOST_MESH_H

#include "relief/relief.h"
#include "base/output.h"

#ifdef __cplusplus
extern "C" {
#endif

struct relief_mesh {
    size_t nv;          /* vertex count */
    size_t nt;          /* triangle count */
    unsigned attrs;     /* RELIEF_MESH_* flags of the arrays present */
    double *pos;        /* nv x 3 */
    uint32_t *tri;      /* nt x 3, NULL when nt == 0 */
    float *col;         /* nv x 3 in [0, 1], or NULL */
    double *nrm;        /* nv x 3, or NULL */
    uint8_t *label;     /* nv, or NULL */
};

/* Area of triangle t of m (input units squared). */
double relief_mesh_triangle_area(const relief_mesh *m, size_t t);

/* Vertex adjacency as CSR: the neighbours of v are
 * nbr[start[v] .. start[v + 1]), ascending, each edge once per direction. */
typedef struct relief_adjacency {
    uint32_t *start; /* nv + 1 */
    uint32_t *nbr;   /* start[nv] */
} relief_adjacency;

relief_status relief_mesh_adjacency(const relief_mesh *m, relief_adjacency *adj,
                                    relief_error *err);
void relief_adjacency_free(relief_adjacency *adj);

/* Vertex-to-triangle lists as CSR: the triangles around v are
 * ids[start[v] .. start[v + 1]), ascending. start: nv + 1 entries, ids:
 * 3 nt entries, both the caller's. */
void relief_mesh_vertex_triangles(const relief_mesh *m, uint32_t *start, uint32_t *ids);

/* Breadth-first over the triangles tri (vertex-to-triangle lists vt_start,
 * vt as relief_mesh_vertex_triangles gives them), a ring at a time, from
 * the n_seeds vertices in queue (marked in seen): each vertex newly reached
 * is marked, queued and passed to visit(ctx, v), which answers 1 once the
 * search has what it wants (done: already so); the search then goes on
 * `margin` rings past the ring where that happened, or until nothing is
 * left. Returns how many vertices are queued. queue: nv entries. */
size_t relief_mesh_rings(const uint32_t *tri, const uint32_t *vt_start, const uint32_t *vt,
                         uint32_t *queue, size_t n_seeds, uint8_t *seen, int done, int margin,
                         int (*visit)(void *ctx, uint32_t v), void *ctx);

/* Area-weighted vertex normals vn (nv x 3, not normalised: the sum of the
 * unnormalised cross products (b - a) x (c - a) of the triangles around
 * each vertex; zero rows for vertices in no triangle). */
void relief_mesh_vertex_normals(const relief_mesh *m, double *vn);

/* Barycentric weights w (of a, b, c) of p projected on the plane of the
 * triangle abc (3-vectors). 0 when the triangle is degenerate (w untouched),
 * else 1. */
int relief_barycentric(const double *p, const double *a, const double *b, const double *c,
                       double w[3]);

/* Build a new mesh from m keeping the vertices with keep[v] != 0 and the
 * triangles whose three vertices are kept; vertices left in no triangle are
 * dropped too when m has triangles. Attributes are copied; vertex order is
 * kept. `old_to_new` (nv entries, may be NULL) receives each old vertex's new
 * index, or UINT32_MAX for a dropped one. */
relief_status relief_mesh_subset(const relief_mesh *m, const uint8_t *keep,
                                 relief_mesh **out, uint32_t *old_to_new,
                                 relief_error *err);

/* A copy of `m` with every array into *out. RELIEF_E_NOMEM. */
relief_status relief_mesh_copy(const relief_mesh *m, relief_mesh **out, relief_error *err);

#ifdef __cplusplus
}
#endif

/* Write `mesh` into the sink in the format of s->path's extension (PLY,
 * OBJ, OFF or STL, as relief_mesh_write), for a caller that stages the
 * file itself (several outputs committed together). */
relief_status relief_mesh_write_to(const relief_mesh *mesh, relief_sink *s,
                                   const relief_write_options *opts, relief_error *err);

#endif
