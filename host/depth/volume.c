#include "depth/volume.h"

#include <flann/flann.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/knn.h"
#define RM_REAL double /* the mesh's precision: the kernels' geometry in double */
#include "kernels/relief_math.h"

#define MAX_RESOLUTION 1024

relief_status relief_grid_of_mesh(relief_mesh *m, int resolution, relief_grid *g,
                                  relief_error *err)
{
    size_t nv = relief_mesh_vertex_count(m);
    const double *p = relief_mesh_positions(m);
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double side = 0.0;
    int margin;
    if (resolution < 8 || resolution > MAX_RESOLUTION)
        return relief_fail(err, RELIEF_E_RANGE, "resolution %d out of range: expected 8..%d "
                           "voxels", resolution, MAX_RESOLUTION);
    for (size_t i = 0; i < nv; ++i)
        for (int a = 0; a < 3; ++a) {
            lo[a] = fmin(lo[a], p[3 * i + a]);
            hi[a] = fmax(hi[a], p[3 * i + a]);
        }
    for (int a = 0; a < 3; ++a)
        side = fmax(side, hi[a] - lo[a]);
    if (!(side > 0.0) || !isfinite(side))
        return relief_fail(err, RELIEF_E_RANGE, "the mesh's bounding box is empty or not "
                           "finite: nothing to voxelise");
    g->h = side / resolution;
    /* The margin: room for a repaired surface to rise past the holed
     * mesh's box (a cap over a hole at a pole: Bennu's cut needs 6 voxels
     * at 256, where 2 flattened the cap's top), 1/32 of the side on each
     * face, at least 2 voxels. */
    margin = resolution / 32 > 2 ? resolution / 32 : 2;
    for (int a = 0; a < 3; ++a) {
        double centre = 0.5 * (lo[a] + hi[a]);
        g->n[a] = (int)ceil((hi[a] - lo[a]) / g->h) + 2 * margin;
        if (g->n[a] < 2 * margin + 1)
            g->n[a] = 2 * margin + 1;
        g->origin[a] = centre - 0.5 * g->n[a] * g->h;
    }
    return RELIEF_OK;
}

uint64_t relief_volume_estimate(const relief_grid *g)
{
    uint64_t vox = (uint64_t)g->n[0] * g->n[1] * g->n[2];
    uint64_t pix = (uint64_t)g->n[0] * g->n[1] + (uint64_t)g->n[1] * g->n[2] +
                   (uint64_t)g->n[2] * g->n[0];
    /* Voxel values (float), the surface's edge table and vertices and
     * triangles (a generous 2 per surface voxel, surface ~ vox^(2/3) x 6),
     * the z-buffers (two depths and states, and their repair's 400 bytes a
     * pixel at most). */
    uint64_t surface = 6u * (uint64_t)pow((double)vox, 2.0 / 3.0) + 1024u;
    return vox * 4u + surface * (16u * 2u + 24u + 2u * 12u) + pix * 2u * (4u + 1u + 400u);
}

/* ---------------------------------------------------------------- z-buffers */

void relief_zbuffers_free(relief_zbuffers *z)
{
    for (int a = 0; a < 3; ++a) {
        free(z->front[a]);
        free(z->back[a]);
        free(z->front_state[a]);
        free(z->back_state[a]);
        z->front[a] = z->back[a] = NULL;
        z->front_state[a] = z->back_state[a] = NULL;
    }
}

/* The six images' buffers for grid g: front and back depths (float, in the
 * mesh's units, width[a] x height[a] = n[b] x n[c] pixels along axis a,
 * b = a+1, c = a+2 mod 3) set to +inf and -inf, their states zeroed, and
 * face_near/face_far (int8, same shape) zeroed for the side each kept
 * depth's triangle faces. On failure the caller frees what was made. */
static relief_status zbuffers_alloc(const relief_grid *g, relief_zbuffers *z,
                                    int8_t *face_near[3], int8_t *face_far[3], relief_error *err)
{
    for (int a = 0; a < 3; ++a) {
        int b = (a + 1) % 3, c = (a + 2) % 3;
        size_t n = (size_t)g->n[b] * g->n[c];
        z->width[a] = g->n[b];
        z->height[a] = g->n[c];
        z->front[a] = malloc(n * sizeof(float));
        z->back[a] = malloc(n * sizeof(float));
        z->front_state[a] = calloc(n, 1);
        z->back_state[a] = calloc(n, 1);
        face_near[a] = calloc(n, 1);
        face_far[a] = calloc(n, 1);
        if (!z->front[a] || !z->back[a] || !z->front_state[a] || !z->back_state[a] || !face_near[a] ||
            !face_far[a])
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the z-buffers");
        for (size_t i = 0; i < n; ++i) {
            z->front[a][i] = INFINITY;
            z->back[a][i] = -INFINITY;
        }
    }
    return RELIEF_OK;
}

/* One triangle P (three xyz vertices, mesh units) into the image along axis
 * a: the pixel centres inside its projection (edges included: a ray through
 * a shared edge meets both triangles at the same depth, which changes
 * nothing), the depth by barycentric interpolation; the nearest and the
 * farthest kept in z->front/back[a] with the side they face (+1 or -1) in
 * face_near/face_far. */
static void zbuffers_rasterise(const double *const P[3], int a, const relief_grid *g,
                               relief_zbuffers *z, int8_t *face_near, int8_t *face_far)
{
    int b = (a + 1) % 3, c = (a + 2) % 3, W = g->n[b], H = g->n[c];
    double u[3], v[3], area;
    int u0, u1, v0, v1;
    for (int k = 0; k < 3; ++k) {
        u[k] = (P[k][b] - g->origin[b]) / g->h - 0.5;
        v[k] = (P[k][c] - g->origin[c]) / g->h - 0.5;
    }
    /* Twice the signed area in (b, c): the sign of the outward
     * normal's a-component. */
    area = (u[1] - u[0]) * (v[2] - v[0]) - (u[2] - u[0]) * (v[1] - v[0]);
    if (area == 0.0)
        return; /* edge-on */
    u0 = (int)ceil(fmin(u[0], fmin(u[1], u[2])));
    u1 = (int)floor(fmax(u[0], fmax(u[1], u[2])));
    v0 = (int)ceil(fmin(v[0], fmin(v[1], v[2])));
    v1 = (int)floor(fmax(v[0], fmax(v[1], v[2])));
    u0 = u0 < 0 ? 0 : u0;
    v0 = v0 < 0 ? 0 : v0;
    u1 = u1 >= W ? W - 1 : u1;
    v1 = v1 >= H ? H - 1 : v1;
    for (int y = v0; y <= v1; ++y)
        for (int x = u0; x <= u1; ++x) {
            double w0 = (u[1] - x) * (v[2] - y) - (u[2] - x) * (v[1] - y);
            double w1 = (u[2] - x) * (v[0] - y) - (u[0] - x) * (v[2] - y);
            double w2 = (u[0] - x) * (v[1] - y) - (u[1] - x) * (v[0] - y);
            double d;
            size_t i = (size_t)y * W + x;
            if (area > 0 ? (w0 < 0 || w1 < 0 || w2 < 0) : (w0 > 0 || w1 > 0 || w2 > 0))
                continue;
            d = (w0 * P[0][a] + w1 * P[1][a] + w2 * P[2][a]) / area;
            if (d < z->front[a][i]) {
                z->front[a][i] = (float)d;
                face_near[i] = area > 0 ? 1 : -1;
            }
            if (d > z->back[a][i]) {
                z->back[a][i] = (float)d;
                face_far[i] = area > 0 ? 1 : -1;
            }
        }
}

/* The states of image a from the sides its kept depths face: the ray along
 * +a enters through a triangle facing -a and leaves through one facing +a;
 * otherwise it went through a hole (its depth NaN). No triangle: EMPTY. */
static void zbuffers_classify(relief_zbuffers *z, int a, const int8_t *face_near,
                              const int8_t *face_far)
{
    size_t n = (size_t)z->width[a] * z->height[a];
    for (size_t i = 0; i < n; ++i) {
        if (!face_near[i]) {
            z->front[a][i] = z->back[a][i] = NAN;
            continue; /* EMPTY */
        }
        z->front_state[a][i] = face_near[i] < 0 ? RELIEF_Z_SURFACE : RELIEF_Z_HOLE;
        z->back_state[a][i] = face_far[i] > 0 ? RELIEF_Z_SURFACE : RELIEF_Z_HOLE;
        if (face_near[i] >= 0)
            z->front[a][i] = NAN;
        if (face_far[i] <= 0)
            z->back[a][i] = NAN;
    }
}

relief_status relief_zbuffers_make(relief_mesh *m, const relief_grid *g, relief_zbuffers *z,
                                   relief_error *err)
{
    const double *p = relief_mesh_positions(m);
    const uint32_t *t = relief_mesh_triangles(m);
    size_t nt = relief_mesh_triangle_count(m);
    int8_t *face_near[3] = {NULL}, *face_far[3] = {NULL};
    relief_status st = RELIEF_OK;

    memset(z, 0, sizeof *z);
    z->g = *g;
    st = zbuffers_alloc(g, z, face_near, face_far, err);
    if (st != RELIEF_OK)
        goto done;
    /* Every triangle into every image. */
    for (size_t f = 0; f < nt; ++f) {
        const double *P[3] = {p + 3 * (size_t)t[3 * f], p + 3 * (size_t)t[3 * f + 1],
                              p + 3 * (size_t)t[3 * f + 2]};
        for (int a = 0; a < 3; ++a)
            zbuffers_rasterise(P, a, g, z, face_near[a], face_far[a]);
    }
    for (int a = 0; a < 3; ++a)
        zbuffers_classify(z, a, face_near[a], face_far[a]);
done:
    for (int a = 0; a < 3; ++a) {
        free(face_near[a]);
        free(face_far[a]);
    }
    if (st != RELIEF_OK)
        relief_zbuffers_free(z);
    return st;
}

/* The slope factor of depth image D at pixel (x, y): 1 / sqrt(1 + Db^2 +
 * Dc^2), Db and Dc the depth's derivatives per unit length across the
 * image (central differences where both neighbours have a depth, one-sided
 * where one has): a distance along the axis times it is the distance along
 * the surface's normal. 1 where no neighbour has a depth. */
static double slope_factor(const float *D, int W, int H, int x, int y, double h)
{
    double g[2] = {0.0, 0.0};
    for (int d = 0; d < 2; ++d) {
        int dx = d == 0, dy = d == 1;
        int xm = x - dx, ym = y - dy, xp = x + dx, yp = y + dy;
        int okm = xm >= 0 && ym >= 0 && isfinite(D[(size_t)ym * W + xm]);
        int okp = xp < W && yp < H && isfinite(D[(size_t)yp * W + xp]);
        double c = D[(size_t)y * W + x];
        if (okm && okp)
            g[d] = (D[(size_t)yp * W + xp] - D[(size_t)ym * W + xm]) / (2.0 * h);
        else if (okp)
            g[d] = (D[(size_t)yp * W + xp] - c) / h;
        else if (okm)
            g[d] = (c - D[(size_t)ym * W + xm]) / h;
    }
    return 1.0 / sqrt(1.0 + g[0] * g[0] + g[1] * g[1]);
}

relief_status relief_zbuffers_voxels(const relief_zbuffers *z, float *values,
                                     relief_error *err)
{
    const relief_grid *g = &z->g;
    (void)err;
    for (int k = 0; k < g->n[2]; ++k)
        for (int j = 0; j < g->n[1]; ++j)
            for (int i = 0; i < g->n[0]; ++i) {
                int idx[3] = {i, j, k}, empty = 0, repaired_inside = 0, used = 0;
                double s = INFINITY;
                for (int a = 0; a < 3; ++a) {
                    int b = (a + 1) % 3, c = (a + 2) % 3;
                    size_t pix = (size_t)idx[c] * z->width[a] + idx[b];
                    double t = g->origin[a] + (idx[a] + 0.5) * g->h, d;
                    float F = z->front[a][pix], B = z->back[a][pix];
                    if (z->front_state[a][pix] == RELIEF_Z_EMPTY) {
                        empty = 1;
                        continue;
                    }
                    if (!isfinite(F) || !isfinite(B))
                        continue; /* still missing: this axis says nothing */
                    /* The nearer side's distance, turned towards the
                     * surface's normal by its slope, so that the three
                     * axes agree and the surface is smooth where the
                     * smallest changes axis. */
                    if (t - F <= B - t)
                        d = (t - F) * slope_factor(z->front[a], z->width[a], z->height[a],
                                                   idx[b], idx[c], g->h);
                    else
                        d = (B - t) * slope_factor(z->back[a], z->width[a], z->height[a],
                                                   idx[b], idx[c], g->h);
                    s = fmin(s, d);
                    used = 1;
                    repaired_inside |= d > 0.0 &&
                                       (z->front_state[a][pix] == RELIEF_Z_HOLE ||
                                        z->back_state[a][pix] == RELIEF_Z_HOLE);
                }
                /* A ray that meets nothing puts the voxel outside, unless
                 * a repaired depth puts it inside: the hole that took part
                 * of the surface also took part of the other views'
                 * silhouettes, so their emptiness there is no evidence. */
                if (empty && !repaired_inside)
                    s = -g->h;
                values[((size_t)k * g->n[1] + j) * g->n[0] + i] =
                    used || empty ? (float)s : (float)-g->h;
            }
    return RELIEF_OK;
}

/* ---------------------------------------------------------------- surface */

typedef struct edge_map {
    uint64_t *key; /* 0: empty (keys are id_lo * 2^32 + id_hi + 1) */
    uint32_t *val;
    size_t cap, used;
} edge_map;

static uint64_t mix(uint64_t x)
{
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdULL;
    x ^= x >> 33;
    return x;
}

static int map_grow(edge_map *m)
{
    size_t cap = m->cap ? 2 * m->cap : 1u << 16;
    uint64_t *key = calloc(cap, sizeof *key);
    uint32_t *val = malloc(cap * sizeof *val);
    if (!key || !val) {
        free(key);
        free(val);
        return 0;
    }
    for (size_t i = 0; i < m->cap; ++i)
        if (m->key[i]) {
            size_t h = mix(m->key[i]) & (cap - 1);
            while (key[h])
                h = (h + 1) & (cap - 1);
            key[h] = m->key[i];
            val[h] = m->val[i];
        }
    free(m->key);
    free(m->val);
    m->key = key;
    m->val = val;
    m->cap = cap;
    return 1;
}

typedef struct builder {
    const relief_grid *g;
    const float *s;
    edge_map map;
    double *pos;
    size_t nv, cap_v;
    uint32_t *tri;
    size_t nt, cap_t;
    int oom;
} builder;

static void corner_pos(const relief_grid *g, uint64_t id, double *p)
{
    size_t i = id % (uint64_t)g->n[0], j = (id / (uint64_t)g->n[0]) % (uint64_t)g->n[1],
           k = id / ((uint64_t)g->n[0] * g->n[1]);
    p[0] = g->origin[0] + (i + 0.5) * g->h;
    p[1] = g->origin[1] + (j + 0.5) * g->h;
    p[2] = g->origin[2] + (k + 0.5) * g->h;
}

/* The vertex where the value crosses 0 on the edge between corners a
 * (inside) and b (outside), made once per edge. */
static uint32_t edge_vertex(builder *bd, uint64_t a, uint64_t b)
{
    uint64_t lo = a < b ? a : b, hi = a < b ? b : a, key = (lo << 32 | hi) + 1;
    size_t h;
    if (bd->map.used * 2 >= bd->map.cap && !map_grow(&bd->map)) {
        bd->oom = 1;
        return 0;
    }
    h = mix(key) & (bd->map.cap - 1);
    while (bd->map.key[h] && bd->map.key[h] != key)
        h = (h + 1) & (bd->map.cap - 1);
    if (bd->map.key[h])
        return bd->map.val[h];
    if (bd->nv == bd->cap_v) {
        size_t cap = bd->cap_v ? 2 * bd->cap_v : 4096;
        double *p = realloc(bd->pos, cap * 3 * sizeof *p);
        if (!p) {
            bd->oom = 1;
            return 0;
        }
        bd->pos = p;
        bd->cap_v = cap;
    }
    {
        double pa[3], pb[3], sa = bd->s[a], sb = bd->s[b], w = sa / (sa - sb);
        corner_pos(bd->g, a, pa);
        corner_pos(bd->g, b, pb);
        for (int c = 0; c < 3; ++c)
            bd->pos[3 * bd->nv + c] = pa[c] + w * (pb[c] - pa[c]);
    }
    bd->map.key[h] = key;
    bd->map.val[h] = (uint32_t)bd->nv;
    ++bd->map.used;
    return (uint32_t)bd->nv++;
}

/* A triangle, turned so that its normal points from `in` to `out` (the
 * centroids of the tetrahedron's inside and outside corners). */
static void emit(builder *bd, uint32_t v0, uint32_t v1, uint32_t v2, const double *in,
                 const double *out)
{
    const double *a = bd->pos + 3 * (size_t)v0, *b = bd->pos + 3 * (size_t)v1,
                 *c = bd->pos + 3 * (size_t)v2;
    double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                   e1[0] * e2[1] - e1[1] * e2[0]};
    double d = n[0] * (out[0] - in[0]) + n[1] * (out[1] - in[1]) + n[2] * (out[2] - in[2]);
    if (v0 == v1 || v1 == v2 || v0 == v2 || bd->oom)
        return; /* a crossing at a corner: no area */
    if (bd->nt == bd->cap_t) {
        size_t cap = bd->cap_t ? 2 * bd->cap_t : 8192;
        uint32_t *t = realloc(bd->tri, cap * 3 * sizeof *t);
        if (!t) {
            bd->oom = 1;
            return;
        }
        bd->tri = t;
        bd->cap_t = cap;
    }
    bd->tri[3 * bd->nt] = v0;
    bd->tri[3 * bd->nt + 1] = d >= 0 ? v1 : v2;
    bd->tri[3 * bd->nt + 2] = d >= 0 ? v2 : v1;
    ++bd->nt;
}

static void tetrahedron(builder *bd, const uint64_t id[4])
{
    int in[4], out[4], ni = 0, no = 0;
    double cin[3] = {0, 0, 0}, cout[3] = {0, 0, 0}, q[3];
    for (int k = 0; k < 4; ++k) {
        if (bd->s[id[k]] > 0.0f)
            in[ni++] = k;
        else
            out[no++] = k;
    }
    if (ni == 0 || no == 0)
        return;
    for (int k = 0; k < ni; ++k) {
        corner_pos(bd->g, id[in[k]], q);
        for (int c = 0; c < 3; ++c)
            cin[c] += q[c] / ni;
    }
    for (int k = 0; k < no; ++k) {
        corner_pos(bd->g, id[out[k]], q);
        for (int c = 0; c < 3; ++c)
            cout[c] += q[c] / no;
    }
    if (ni == 1 || no == 1) {
        int apex = ni == 1 ? in[0] : out[0], *others = ni == 1 ? out : in;
        uint32_t v[3];
        for (int k = 0; k < 3; ++k)
            v[k] = ni == 1 ? edge_vertex(bd, id[apex], id[others[k]])
                           : edge_vertex(bd, id[others[k]], id[apex]);
        emit(bd, v[0], v[1], v[2], cin, cout);
    } else {
        uint32_t a = edge_vertex(bd, id[in[0]], id[out[0]]);
        uint32_t b = edge_vertex(bd, id[in[0]], id[out[1]]);
        uint32_t c = edge_vertex(bd, id[in[1]], id[out[1]]);
        uint32_t d = edge_vertex(bd, id[in[1]], id[out[0]]);
        emit(bd, a, b, c, cin, cout);
        emit(bd, a, c, d, cin, cout);
    }
}

relief_status relief_isosurface(const relief_grid *g, const float *values, relief_mesh **out,
                                relief_error *err)
{
    /* The cube's corners by bits (x 1, y 2, z 4); six tetrahedra around
     * the diagonal 0-7 (Kuhn's split: neighbouring cubes agree on their
     * shared faces' diagonals, so the surface closes). */
    static const int tets[6][4] = {{0, 1, 3, 7}, {0, 3, 2, 7}, {0, 2, 6, 7},
                                   {0, 6, 4, 7}, {0, 4, 5, 7}, {0, 5, 1, 7}};
    builder bd;
    uint64_t nx = (uint64_t)g->n[0], nxy = nx * (uint64_t)g->n[1];
    relief_mesh *m = NULL;
    relief_status st;
    memset(&bd, 0, sizeof bd);
    bd.g = g;
    bd.s = values;
    for (int k = 0; k + 1 < g->n[2] && !bd.oom; ++k)
        for (int j = 0; j + 1 < g->n[1] && !bd.oom; ++j)
            for (int i = 0; i + 1 < g->n[0]; ++i) {
                uint64_t c[8];
                int inside = 0;
                for (int b = 0; b < 8; ++b) {
                    c[b] = (uint64_t)(k + (b >> 2)) * nxy + (uint64_t)(j + ((b >> 1) & 1)) * nx +
                           (uint64_t)(i + (b & 1));
                    inside += values[c[b]] > 0.0f;
                }
                if (inside == 0 || inside == 8)
                    continue;
                for (int t = 0; t < 6; ++t) {
                    uint64_t id[4] = {c[tets[t][0]], c[tets[t][1]], c[tets[t][2]],
                                      c[tets[t][3]]};
                    tetrahedron(&bd, id);
                }
            }
    if (bd.oom) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the surface (%zu vertices so "
                         "far)", bd.nv);
        goto done;
    }
    if (bd.nt == 0) {
        st = relief_fail(err, RELIEF_E_RANGE, "no voxel lies inside the depth images: there "
                         "is no surface to extract");
        goto done;
    }
    st = relief_mesh_create(bd.nv, bd.nt, 0, &m, err);
    if (st == RELIEF_OK) {
        memcpy(relief_mesh_positions(m), bd.pos, bd.nv * 3 * sizeof(double));
        memcpy(relief_mesh_triangles(m), bd.tri, bd.nt * 3 * sizeof(uint32_t));
        *out = m;
    }
done:
    free(bd.map.key);
    free(bd.map.val);
    free(bd.pos);
    free(bd.tri);
    return st;
}

/* ---------------------------------------------------------------- distance */

#define NEAR_TRIANGLES 16

relief_status relief_triangle_index_build(relief_triangle_index *t, const double *pos,
                                          const uint32_t *tri, size_t nt, relief_error *err)
{
    float speedup;
    memset(t, 0, sizeof *t);
    t->pos = pos, t->tri = tri;
    t->centroid = malloc((nt ? nt : 1) * 3 * sizeof *t->centroid);
    if (!t->centroid)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the distance search");
    for (size_t f = 0; f < nt; ++f)
        for (int c = 0; c < 3; ++c)
            t->centroid[3 * f + c] = (pos[3 * (size_t)tri[3 * f] + c] +
                                      pos[3 * (size_t)tri[3 * f + 1] + c] +
                                      pos[3 * (size_t)tri[3 * f + 2] + c]) / 3.0;
    t->fp = relief_knn_exact_params();
    t->k = nt < NEAR_TRIANGLES ? (int)nt : NEAR_TRIANGLES;
    t->index = flann_build_index_double(t->centroid, (int)nt, 3, &speedup, &t->fp);
    return t->index ? RELIEF_OK
                    : relief_fail(err, RELIEF_E_NOMEM, "FLANN could not index %zu triangles", nt);
}

double relief_triangle_index_d2(const relief_triangle_index *t, const double p[3])
{
    int idx[NEAR_TRIANGLES];
    double d2[NEAR_TRIANGLES], best = INFINITY;
    if (flann_find_nearest_neighbors_index_double(t->index, (double *)p, 1, idx, d2, t->k,
                                                  (struct FLANNParameters *)&t->fp) != 0)
        return NAN;
    for (int r = 0; r < t->k; ++r) {
        const uint32_t *f = t->tri + 3 * (size_t)idx[r];
        best = fmin(best, rm_point_triangle_d2(p, t->pos + 3 * (size_t)f[0],
                                               t->pos + 3 * (size_t)f[1],
                                               t->pos + 3 * (size_t)f[2]));
    }
    return best;
}

void relief_triangle_index_free(relief_triangle_index *t)
{
    if (t->index)
        flann_free_index_double(t->index, &t->fp);
    free(t->centroid);
    memset(t, 0, sizeof *t);
}

relief_status relief_surface_distance(relief_mesh *a, relief_mesh *b, double *mean, double *max,
                                      relief_error *err)
{
    size_t na = relief_mesh_vertex_count(a), nt = relief_mesh_triangle_count(b);
    const double *pa = relief_mesh_positions(a);
    relief_triangle_index ti;
    double sum = 0.0, worst = 0.0;
    relief_status st;
    if (!nt || !na)
        return relief_fail(err, RELIEF_E_RANGE, "a surface without triangles or vertices");
    st = relief_triangle_index_build(&ti, relief_mesh_positions(b), relief_mesh_triangles(b), nt,
                                     err);
    for (size_t v = 0; st == RELIEF_OK && v < na; ++v) {
        double best = sqrt(relief_triangle_index_d2(&ti, pa + 3 * v));
        if (isnan(best)) {
            st = relief_fail(err, RELIEF_E_INTERNAL, "FLANN's search failed");
            break;
        }
        sum += best;
        worst = fmax(worst, best);
    }
    if (st == RELIEF_OK)
        *mean = sum / (double)na, *max = worst;
    relief_triangle_index_free(&ti);
    return st;
}
