/* depth-fill on a mesh, its holes closed by faired patches (mesh_patch.h,
 * relief_mesh_fair_holes). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/knn.h"
#include "base/vec3.h"
#include "depth/mesh_patch.h"
#include "mesh/hole_fill.h"
#include "mesh/mesh.h"
#include "mesh/weld.h"
#include "mesh/untangle.h"

/* The output: `in`, then the patches' vertices (labelled 1, coloured as
 * their rim on average) and triangles. */
static relief_status assemble(const relief_mesh *in, const relief_hole_patches *hp,
                              const uint32_t *rim, relief_mesh **out, relief_error *err)
{
    unsigned attrs = (in->attrs & ~(unsigned)RELIEF_MESH_NORMALS) | RELIEF_MESH_LABELS;
    size_t nv = in->nv, holes = 0;
    double *sum = NULL;
    relief_status st = relief_mesh_create(nv + hp->nv_new, in->nt + hp->nt_new, attrs, out, err);
    if (st != RELIEF_OK)
        return st;
    memcpy((*out)->pos, in->pos, nv * 3 * sizeof *in->pos);
    if (hp->nv_new) /* NULL when no patch added a vertex */
        memcpy((*out)->pos + 3 * nv, hp->pos, hp->nv_new * 3 * sizeof *hp->pos);
    memcpy((*out)->tri, in->tri, in->nt * 3 * sizeof *in->tri);
    if (hp->nt_new)
        memcpy((*out)->tri + 3 * in->nt, hp->tri, hp->nt_new * 3 * sizeof *hp->tri);
    for (size_t v = 0; v < nv; ++v)
        (*out)->label[v] = in->label ? in->label[v] : 0;
    memset((*out)->label + nv, 1, hp->nv_new);
    if (!in->col)
        return RELIEF_OK;
    memcpy((*out)->col, in->col, nv * 3 * sizeof *in->col);
    for (size_t v = 0; v < nv; ++v)
        holes = rim[v] > holes ? rim[v] : holes;
    sum = calloc((holes + 1) * 4, sizeof *sum);
    if (!sum) {
        relief_mesh_destroy(*out);
        *out = NULL;
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the patches' colours");
    }
    for (size_t v = 0; v < nv; ++v)
        if (rim[v]) {
            for (int c = 0; c < 3; ++c)
                sum[4 * rim[v] + c] += in->col[3 * v + c];
            sum[4 * rim[v] + 3] += 1.0;
        }
    for (size_t i = 0; i < hp->nv_new; ++i) {
        const double *s = sum + 4 * hp->hole[i];
        for (int c = 0; c < 3; ++c)
            (*out)->col[3 * (nv + i) + c] = s[3] > 0 ? (float)(s[c] / s[3]) : 0.5f;
    }
    free(sum);
    return RELIEF_OK;
}

/* Each new vertex's rings from the rim (1: a rim vertex's neighbour),
 * capped at `cap`, through the patches' triangles. */
static void rings_from_rim(const relief_hole_patches *hp, size_t nv, uint8_t *ring, uint8_t cap)
{
    memset(ring, cap, hp->nv_new);
    for (uint8_t r = 1; r < cap; ++r)
        for (size_t t = 0; t < hp->nt_new; ++t)
            for (int j = 0; j < 3; ++j)
                for (int k = 0; k < 3; ++k) {
                    uint32_t a = hp->tri[3 * t + j], b = hp->tri[3 * t + k];
                    /* a patch's capture vertices are its rim: ring 0 */
                    if (b >= nv && (a < nv ? 0 : ring[a - nv]) == r - 1 && ring[b - nv] > r)
                        ring[b - nv] = r;
                }
}

/* The offset d (nv_new) along the unit normal u (nv_new x 3) from each
 * new vertex of o to the solid's nearest vertex; 0 where that vertex lies
 * more than `reach` along the normal or half of it off the normal's line
 * (a lid across a vessel's neck, another wall). */
static relief_status solid_offsets(const relief_mesh *o, size_t nv, const relief_mesh *solid,
                                   double reach, double *d, double *u, relief_error *err)
{
    struct FLANNParameters fp = relief_knn_exact_params();
    size_t nn = o->nv - nv;
    double *vn = malloc(o->nv * 3 * sizeof *vn + 1), *d2 = malloc((nn + 1) * sizeof *d2);
    int *idx = malloc((nn + 1) * sizeof *idx);
    flann_index_t index = NULL;
    float speedup;
    relief_status st = RELIEF_OK;
    if (!vn || !d2 || !idx) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the patches' offsets");
        goto done;
    }
    relief_mesh_vertex_normals(o, vn);
    index = flann_build_index_double(solid->pos, (int)solid->nv, 3, &speedup, &fp);
    if (!index || flann_find_nearest_neighbors_index_double(index, o->pos + 3 * nv, (int)nn, idx,
                                                            d2, 1, &fp) != 0) {
        st = relief_fail(err, RELIEF_E_INTERNAL, "FLANN could not search the solid");
        goto done;
    }
    for (size_t i = 0; i < nn; ++i) {
        const double *n = vn + 3 * (nv + i);
        double q[3], len = sqrt(dot3(n, n)), along, off;
        for (int e = 0; e < 3; ++e)
            u[3 * i + e] = len > 0 ? n[e] / len : 0.0;
        sub3(solid->pos + 3 * (size_t)idx[i], o->pos + 3 * (nv + i), q);
        along = dot3(q, u + 3 * i);
        off = sqrt(fmax(dot3(q, q) - along * along, 0.0));
        d[i] = fabs(along) <= reach && off <= 0.5 * reach ? along : 0.0;
    }
done:
    if (index)
        flann_free_index_double(index, &fp);
    free(vn), free(d2), free(idx);
    return st;
}

/* Smooth d over the patches (rim vertices at 0), `passes` times each
 * vertex halfway to its neighbours' mean: the solid's voxel steps (one
 * voxel, two or three patch vertices wide) go, its larger shape stays. */
static relief_status smooth_offsets(const relief_hole_patches *hp, size_t nv, double *d,
                                    int passes, relief_error *err)
{
    size_t nn = hp->nv_new;
    double *sum = malloc((nn + 1) * 2 * sizeof *sum);
    if (!sum)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the patches' offsets");
    for (int p = 0; p < passes; ++p) {
        memset(sum, 0, nn * 2 * sizeof *sum);
        for (size_t t = 0; t < hp->nt_new; ++t)
            for (int k = 0; k < 3; ++k) {
                uint32_t a = hp->tri[3 * t + k], b = hp->tri[3 * t + (k + 1) % 3];
                double da = a < nv ? 0.0 : d[a - nv], db = b < nv ? 0.0 : d[b - nv];
                if (a >= nv)
                    sum[2 * (a - nv)] += db, sum[2 * (a - nv) + 1] += 1;
                if (b >= nv)
                    sum[2 * (b - nv)] += da, sum[2 * (b - nv) + 1] += 1;
            }
        for (size_t i = 0; i < nn; ++i)
            if (sum[2 * i + 1] > 0)
                d[i] = 0.5 * d[i] + 0.5 * sum[2 * i] / sum[2 * i + 1];
    }
    free(sum);
    return RELIEF_OK;
}

relief_status relief_mesh_fair_holes(const relief_mesh *in, const relief_mesh *solid,
                                     double voxel, const uint32_t *rim, relief_mesh **out,
                                     relief_mesh_patch_report *rep, relief_error *err)
{
    relief_hole_patches hp;
    relief_mesh *o = NULL;
    double *d = NULL, *u = NULL;
    uint8_t *ring = NULL;
    relief_status st;
    memset(rep, 0, sizeof *rep);
    st = relief_fill_rims(in->pos, in->nv, in->tri, in->nt, rim, NULL, &hp, err);
    if (st == RELIEF_OK)
        st = assemble(in, &hp, rim, &o, err);
    /* a rim through a split bow-tie vertex passes it twice, and the patch
     * joins the copies with a triangle of no area: welded where that
     * closed the pinch (mesh/weld.h), as complete-points --mesh does */
    if (st == RELIEF_OK)
        st = relief_weld_copies(o->pos, o->nv, o->tri, &o->nt, &rep->copies_welded, err);
    if (st == RELIEF_OK && solid && hp.nv_new) {
        d = malloc(hp.nv_new * sizeof *d);
        u = malloc(hp.nv_new * 3 * sizeof *u);
        ring = malloc(hp.nv_new);
        if (!d || !u || !ring)
            st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the patches' offsets");
        if (st == RELIEF_OK)
            st = solid_offsets(o, in->nv, solid, 3.0 * voxel, d, u, err);
        if (st == RELIEF_OK)
            st = smooth_offsets(&hp, in->nv, d, 4, err);
        if (st == RELIEF_OK) {
            rings_from_rim(&hp, in->nv, ring, 3);
            for (size_t i = 0; i < hp.nv_new; ++i) /* nothing at the rim, all from ring 3 */
                for (int e = 0; e < 3; ++e)
                    o->pos[3 * (in->nv + i) + e] += d[i] * ring[i] / 3.0 * u[3 * i + e];
        }
    }
    if (st == RELIEF_OK && hp.nv_new) { /* the offsets, or the patch, crossing the capture */
        double *base = malloc(o->nv * 3 * sizeof *base);
        if (!base)
            st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the patches' offsets");
        if (st == RELIEF_OK) {
            memcpy(base, in->pos, in->nv * 3 * sizeof *base);
            memcpy(base + 3 * in->nv, hp.pos, hp.nv_new * 3 * sizeof *base);
            st = relief_untangle(o->pos, base, o->nv, in->nv, o->tri, o->nt, &rep->untangled,
                                 &rep->crossing_left, err);
        }
        free(base);
    }
    if (st == RELIEF_OK) {
        rep->holes_patched = hp.polygons;
        rep->holes_unpatched = hp.skipped;
        rep->vertices_added = hp.nv_new;
        rep->patch_triangles = hp.nt_new;
        *out = o, o = NULL;
    }
    relief_mesh_destroy(o);
    relief_hole_patches_free(&hp);
    free(d), free(u), free(ring);
    return st;
}
