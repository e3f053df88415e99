#include "mesh/mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/compare.h"
#include "base/error.h"
#include "base/vec3.h"

/* Overflow-checked calloc of n items of size sz. */
static void *alloc_array(size_t n, size_t sz)
{
    if (n == 0)
        return NULL;
    if (n > SIZE_MAX / sz)
        return NULL;
    return calloc(n, sz);
}

relief_status relief_mesh_create(size_t n_vertices, size_t n_triangles,
                                 unsigned attributes, relief_mesh **out,
                                 relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    const unsigned known = RELIEF_MESH_COLOURS | RELIEF_MESH_NORMALS |
                           RELIEF_MESH_LABELS;
    relief_mesh *m;

    if (!out)
        return relief_fail(err, RELIEF_E_USAGE, "relief_mesh_create: out is NULL");
    if (attributes & ~known)
        return relief_fail(err, RELIEF_E_USAGE,
                           "relief_mesh_create: unknown attribute flags 0x%x",
                           attributes & ~known);
    if (n_vertices > UINT32_MAX)
        return relief_fail(err, RELIEF_E_RANGE,
                           "mesh has %zu vertices; at most %u are supported",
                           n_vertices, (unsigned)UINT32_MAX);
    m = calloc(1, sizeof *m);
    if (!m)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a mesh");
    m->nv = n_vertices;
    m->nt = n_triangles;
    m->attrs = attributes;
    m->pos = alloc_array(n_vertices, 3 * sizeof(double));
    m->tri = alloc_array(n_triangles, 3 * sizeof(uint32_t));
    if (attributes & RELIEF_MESH_COLOURS)
        m->col = alloc_array(n_vertices, 3 * sizeof(float));
    if (attributes & RELIEF_MESH_NORMALS)
        m->nrm = alloc_array(n_vertices, 3 * sizeof(double));
    if (attributes & RELIEF_MESH_LABELS)
        m->label = alloc_array(n_vertices, 1);
    if (n_vertices > 0 &&
        (!m->pos || ((attributes & RELIEF_MESH_COLOURS) && !m->col) ||
         ((attributes & RELIEF_MESH_NORMALS) && !m->nrm) ||
         ((attributes & RELIEF_MESH_LABELS) && !m->label))) {
        relief_mesh_destroy(m);
        return relief_fail(err, RELIEF_E_NOMEM,
                           "cannot allocate a mesh of %zu vertices", n_vertices);
    }
    if (n_triangles > 0 && !m->tri) {
        relief_mesh_destroy(m);
        return relief_fail(err, RELIEF_E_NOMEM,
                           "cannot allocate a mesh of %zu triangles", n_triangles);
    }
    *out = m;
    return RELIEF_OK;
}

void relief_mesh_destroy(relief_mesh *m)
{
    if (!m)
        return;
    free(m->label);
    free(m->nrm);
    free(m->col);
    free(m->tri);
    free(m->pos);
    free(m);
}

size_t relief_mesh_vertex_count(const relief_mesh *m) { return m->nv; }
size_t relief_mesh_triangle_count(const relief_mesh *m) { return m->nt; }
unsigned relief_mesh_attributes(const relief_mesh *m) { return m->attrs; }
double *relief_mesh_positions(relief_mesh *m) { return m->pos; }
uint32_t *relief_mesh_triangles(relief_mesh *m) { return m->tri; }
float *relief_mesh_colours(relief_mesh *m) { return m->col; }
double *relief_mesh_normals(relief_mesh *m) { return m->nrm; }
uint8_t *relief_mesh_labels(relief_mesh *m) { return m->label; }

double relief_mesh_triangle_area(const relief_mesh *m, size_t t)
{
    const double *a = m->pos + 3 * (size_t)m->tri[3 * t];
    const double *b = m->pos + 3 * (size_t)m->tri[3 * t + 1];
    const double *c = m->pos + 3 * (size_t)m->tri[3 * t + 2];
    double e1[3], e2[3], n[3];
    for (int k = 0; k < 3; ++k) {
        e1[k] = b[k] - a[k];
        e2[k] = c[k] - a[k];
    }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    return 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

relief_status relief_mesh_validate(const relief_mesh *m, relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    size_t good = 0;

    if (!m || m->nv == 0)
        return relief_fail(err, RELIEF_E_MESH, "the mesh is empty: it has no vertex");
    for (size_t v = 0; v < m->nv; ++v) {
        const double *p = m->pos + 3 * v;
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
            return relief_fail(err, RELIEF_E_MESH,
                               "vertex %zu has a non-finite coordinate "
                               "(%g, %g, %g); expected finite numbers",
                               v, p[0], p[1], p[2]);
    }
    if (m->col) {
        for (size_t i = 0; i < 3 * m->nv; ++i)
            if (!(m->col[i] >= 0.0f && m->col[i] <= 1.0f))
                return relief_fail(err, RELIEF_E_MESH,
                                   "vertex %zu has colour component %g outside [0, 1]",
                                   i / 3, (double)m->col[i]);
    }
    if (m->nrm) {
        for (size_t i = 0; i < 3 * m->nv; ++i)
            if (!isfinite(m->nrm[i]))
                return relief_fail(err, RELIEF_E_MESH,
                                   "vertex %zu has a non-finite normal", i / 3);
    }
    if (m->label) {
        for (size_t v = 0; v < m->nv; ++v)
            if (m->label[v] > RELIEF_LABEL_COMPLETED)
                return relief_fail(err, RELIEF_E_MESH,
                                   "vertex %zu has label %u; expected 0 "
                                   "(captured) or 1 (completed)",
                                   v, (unsigned)m->label[v]);
    }
    for (size_t t = 0; t < m->nt; ++t) {
        const uint32_t *f = m->tri + 3 * t;
        for (int k = 0; k < 3; ++k)
            if (f[k] >= m->nv)
                return relief_fail(err, RELIEF_E_MESH,
                                   "triangle %zu refers to vertex %u but the mesh "
                                   "has %zu vertices (valid indices 0..%zu)",
                                   t, (unsigned)f[k], m->nv, m->nv - 1);
        if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2])
            return relief_fail(err, RELIEF_E_MESH,
                               "triangle %zu repeats a vertex (%u %u %u)", t,
                               (unsigned)f[0], (unsigned)f[1], (unsigned)f[2]);
        if (relief_mesh_triangle_area(m, t) > 0.0)
            ++good;
    }
    if (m->nt > 0 && good == 0)
        return relief_fail(err, RELIEF_E_MESH,
                           "all %zu triangles are degenerate (zero area)", m->nt);
    return RELIEF_OK;
}

relief_status relief_mesh_subset(const relief_mesh *m, const uint8_t *keep,
                                 relief_mesh **out, uint32_t *old_to_new,
                                 relief_error *err)
{
    uint32_t *remap = NULL;
    uint8_t *used = NULL;
    relief_mesh *s = NULL;
    size_t nv = 0, nt = 0;
    relief_status st = RELIEF_OK;

    remap = malloc((m->nv ? m->nv : 1) * sizeof *remap);
    used = calloc(m->nv ? m->nv : 1, 1);
    if (!remap || !used) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a mesh subset");
        goto done;
    }
    for (size_t t = 0; t < m->nt; ++t) {
        const uint32_t *f = m->tri + 3 * t;
        if (keep[f[0]] && keep[f[1]] && keep[f[2]]) {
            used[f[0]] = used[f[1]] = used[f[2]] = 1;
            ++nt;
        }
    }
    for (size_t v = 0; v < m->nv; ++v) {
        if (m->nt == 0)
            used[v] = keep[v] != 0;
        remap[v] = used[v] ? (uint32_t)nv++ : UINT32_MAX;
    }
    st = relief_mesh_create(nv, nt, m->attrs, &s, err);
    if (st != RELIEF_OK)
        goto done;
    for (size_t v = 0; v < m->nv; ++v) {
        size_t w = remap[v];
        if (w == UINT32_MAX)
            continue;
        memcpy(s->pos + 3 * w, m->pos + 3 * v, 3 * sizeof(double));
        if (m->col)
            memcpy(s->col + 3 * w, m->col + 3 * v, 3 * sizeof(float));
        if (m->nrm)
            memcpy(s->nrm + 3 * w, m->nrm + 3 * v, 3 * sizeof(double));
        if (m->label)
            s->label[w] = m->label[v];
    }
    nt = 0;
    for (size_t t = 0; t < m->nt; ++t) {
        const uint32_t *f = m->tri + 3 * t;
        if (keep[f[0]] && keep[f[1]] && keep[f[2]]) {
            for (int k = 0; k < 3; ++k)
                s->tri[3 * nt + k] = remap[f[k]];
            ++nt;
        }
    }
    if (old_to_new)
        memcpy(old_to_new, remap, m->nv * sizeof *remap);
    *out = s;
done:
    free(used);
    free(remap);
    return st;
}

/* Sort a vertex's few neighbours ascending: insertion sort, qsort past
 * a fan's worth. */
static void sort_small(uint32_t *a, size_t n)
{
    if (n > 32) {
        qsort(a, n, sizeof *a, relief_cmp_u32);
        return;
    }
    for (size_t i = 1; i < n; ++i) {
        uint32_t x = a[i];
        size_t j = i;
        for (; j > 0 && a[j - 1] > x; --j)
            a[j] = a[j - 1];
        a[j] = x;
    }
}

/* Each triangle edge in both directions, bucketed by its first vertex
 * (a counting sort), each bucket sorted and its repeats dropped: the
 * (from, to) order of sorting every edge whole, without its n log n. */
relief_status relief_mesh_adjacency(const relief_mesh *m, relief_adjacency *adj,
                                    relief_error *err)
{
    size_t ne = 6 * m->nt, k = 0;
    uint32_t *e = malloc((ne + 1) * sizeof *e);
    size_t *fill = calloc(m->nv + 1, sizeof *fill);
    adj->start = calloc(m->nv + 1, sizeof *adj->start);
    adj->nbr = malloc((ne + 1) * sizeof *adj->nbr);
    if (!e || !fill || !adj->start || !adj->nbr) {
        free(e);
        free(fill);
        relief_adjacency_free(adj);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the vertex adjacency");
    }
    for (size_t i = 0; i < 3 * m->nt; ++i)
        fill[m->tri[i] + 1] += 2; /* each corner starts two directed edges' worth */
    for (size_t v = 0; v < m->nv; ++v)
        fill[v + 1] += fill[v];
    for (size_t t = 0; t < m->nt; ++t)
        for (int i = 0; i < 3; ++i) {
            uint32_t a = m->tri[3 * t + i], b = m->tri[3 * t + (i + 1) % 3];
            e[fill[a]++] = b;
            e[fill[b]++] = a;
        }
    for (size_t v = 0, lo = 0; v < m->nv; lo = fill[v++]) {
        sort_small(e + lo, fill[v] - lo);
        for (size_t i = lo; i < fill[v]; ++i)
            if (i == lo || e[i] != e[i - 1])
                adj->nbr[k++] = e[i];
        adj->start[v + 1] = (uint32_t)k;
    }
    free(fill);
    free(e);
    return RELIEF_OK;
}

void relief_adjacency_free(relief_adjacency *adj)
{
    free(adj->start);
    free(adj->nbr);
    adj->start = adj->nbr = NULL;
}

void relief_mesh_vertex_normals(const relief_mesh *m, double *vn)
{
    memset(vn, 0, m->nv * 3 * sizeof *vn);
    for (size_t t = 0; t < m->nt; ++t) {
        const uint32_t *f = m->tri + 3 * t;
        double e1[3], e2[3], n[3];
        sub3(m->pos + 3 * (size_t)f[1], m->pos + 3 * (size_t)f[0], e1);
        sub3(m->pos + 3 * (size_t)f[2], m->pos + 3 * (size_t)f[0], e2);
        cross3(e1, e2, n);
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k)
                vn[3 * (size_t)f[j] + k] += n[k];
    }
}

void relief_mesh_vertex_triangles(const relief_mesh *m, uint32_t *start, uint32_t *ids)
{
    memset(start, 0, (m->nv + 1) * sizeof *start);
    for (size_t i = 0; i < 3 * m->nt; ++i)
        ++start[m->tri[i] + 1];
    for (size_t v = 0; v < m->nv; ++v)
        start[v + 1] += start[v];
    /* start[v] serves as v's cursor, then everything moves back one. */
    for (size_t t = 0; t < m->nt; ++t)
        for (int k = 0; k < 3; ++k)
            ids[start[m->tri[3 * t + k]]++] = (uint32_t)t;
    for (size_t v = m->nv; v > 0; --v)
        start[v] = start[v - 1];
    start[0] = 0;
}

int relief_barycentric(const double *p, const double *a, const double *b, const double *c,
                       double w[3])
{
    double e0[3], e1[3], e2[3], d00 = 0, d01 = 0, d11 = 0, d20 = 0, d21 = 0, den;
    for (int k = 0; k < 3; ++k) {
        e0[k] = b[k] - a[k];
        e1[k] = c[k] - a[k];
        e2[k] = p[k] - a[k];
        d00 += e0[k] * e0[k];
        d01 += e0[k] * e1[k];
        d11 += e1[k] * e1[k];
        d20 += e2[k] * e0[k];
        d21 += e2[k] * e1[k];
    }
    den = d00 * d11 - d01 * d01;
    if (!(den > 1e-24 * d00 * d11))
        return 0;
    w[1] = (d11 * d20 - d01 * d21) / den;
    w[2] = (d00 * d21 - d01 * d20) / den;
    w[0] = 1.0 - w[1] - w[2];
    return 1;
}

relief_status relief_mesh_copy(const relief_mesh *m, relief_mesh **out, relief_error *err)
{
    uint8_t *keep = malloc(m->nv ? m->nv : 1);
    relief_status st;
    if (!keep)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot copy a mesh of %zu vertices", m->nv);
    memset(keep, 1, m->nv);
    st = relief_mesh_subset(m, keep, out, NULL, err);
    free(keep);
    return st;
}

size_t relief_mesh_rings(const uint32_t *tri, const uint32_t *vt_start, const uint32_t *vt,
                         uint32_t *queue, size_t n_seeds, uint8_t *seen, int done, int margin,
                         int (*visit)(void *ctx, uint32_t v), void *ctx)
{
    size_t head = 0, tail = n_seeds;
    int past = -1; /* rings since the search had what it wanted */
    while (head < tail && past < margin) {
        const size_t ring_end = tail;
        for (; head < ring_end; ++head)
            for (uint32_t i = vt_start[queue[head]]; i < vt_start[queue[head] + 1]; ++i)
                for (int k = 0; k < 3; ++k) {
                    const uint32_t w = tri[3 * (size_t)vt[i] + (size_t)k];
                    if (seen[w])
                        continue;
                    seen[w] = 1;
                    queue[tail++] = w;
                    done |= visit(ctx, w);
                }
        if (done)
            ++past;
    }
    return tail;
}
