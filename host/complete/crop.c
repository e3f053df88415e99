/* A told hole's smoothed base is built on the capture around it (issue
 * 61: a told fill within 3 x CGAL's time): the crop, then the completed
 * crop sewn back into the whole capture. */
#include "complete/engine.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/compare.h"
#include "base/error.h"
#include "base/vec3.h"
#include "mesh/hole_fill.h"
#include "mesh/mesh.h"

/* The crop holds CROP_PER_POOL x the samples a told growth matches against
 * (complete.c's pool: RELIEF_TOLD_POOL_*), then CROP_MARGIN rings more, so
 * the base's smoothing and the pool's windows see what the whole capture
 * would give them there; a crop over half the capture is not made. */
#define CROP_PER_POOL 3
#define CROP_MARGIN 6

/* The targets the filled rims will get, about: a disc's area over its
 * spacing squared, from its rim's vertex count n (n^2 / 4 pi). */
static size_t crop_wanted(const relief_complete_run *r, size_t *n_seeds)
{
    double targets = 0.0, pool;
    *n_seeds = 0;
    for (uint32_t i = 0; i < r->holes.n_rims; ++i) {
        const relief_rim *m = r->holes.rims + i;
        if (m->fate != RELIEF_RIM_FILLED)
            continue;
        targets += (double)m->points * (double)m->points / (4.0 * RELIEF_PI);
        *n_seeds += m->points;
    }
    pool = fmax(RELIEF_TOLD_POOL_MIN, RELIEF_TOLD_POOL_PER_TARGET * targets);
    return (size_t)fmin(CROP_PER_POOL * pool, (double)SIZE_MAX / 2);
}

/* Breadth-first from the filled rims' vertices over the triangles, a ring
 * at a time, until `want` vertices are reached, then CROP_MARGIN rings
 * more; keep[v] marks them. Returns how many. queue: nv. */
static size_t crop_reach(const relief_complete_run *r, const uint32_t *vt_start,
                         const uint32_t *vt, size_t want, uint32_t *queue, uint8_t *keep)
{
    const relief_mesh *c = r->capture;
    size_t head = 0, tail = 0;
    int past = -1;
    for (size_t v = 0; v < c->nv; ++v)
        if (r->rim[v]) {
            queue[tail++] = (uint32_t)v;
            keep[v] = 1;
        }
    while (head < tail && past < CROP_MARGIN) {
        const size_t ring_end = tail;
        for (; head < ring_end; ++head)
            for (uint32_t i = vt_start[queue[head]]; i < vt_start[queue[head] + 1]; ++i)
                for (int k = 0; k < 3; ++k) {
                    const uint32_t w = c->tri[3 * (size_t)vt[i] + (size_t)k];
                    if (!keep[w]) {
                        keep[w] = 1;
                        queue[tail++] = w;
                    }
                }
        if (tail >= want)
            ++past;
    }
    return tail;
}

/* Does the selection lie inside the crop, off its border? Else the crop's
 * border would be told too. */
static int selection_inside(const relief_mesh *c, const uint32_t *vt_start, const uint32_t *vt,
                            const uint8_t *keep, const uint8_t *select)
{
    for (size_t v = 0; select && v < c->nv; ++v) {
        if (!select[v])
            continue;
        if (!keep[v])
            return 0;
        for (uint32_t i = vt_start[v]; i < vt_start[v + 1]; ++i)
            for (int k = 0; k < 3; ++k)
                if (!keep[c->tri[3 * (size_t)vt[i] + (size_t)k]])
                    return 0;
    }
    return 1;
}

relief_status relief_complete_crop(relief_complete_run *r, const uint8_t *select,
                                   uint8_t **crop_select, relief_error *err)
{
    const relief_mesh *c = r->capture;
    size_t n_seeds, want = crop_wanted(r, &n_seeds), reached;
    uint32_t *vt_start, *vt, *queue, *crop_of;
    uint8_t *keep;
    relief_status st = RELIEF_OK;
    *crop_select = NULL;
    if (!r->has_holes || !r->rim || relief_holes_in_part(&r->holes) || n_seeds == 0 ||
        4 * want >= 3 * c->nv)
        return RELIEF_OK; /* nothing told, a notch, or most of the capture anyway */
    vt_start = calloc(c->nv + 1, sizeof *vt_start);
    vt = malloc(3 * c->nt * sizeof *vt + 1);
    queue = malloc(c->nv * sizeof *queue);
    crop_of = malloc(c->nv * sizeof *crop_of);
    keep = calloc(c->nv, 1);
    if (!vt_start || !vt || !queue || !crop_of || !keep) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the crop about the told holes");
        goto done;
    }
    relief_mesh_vertex_triangles(c, vt_start, vt);
    reached = crop_reach(r, vt_start, vt, want, queue, keep);
    if (4 * reached >= 3 * c->nv || !selection_inside(c, vt_start, vt, keep, select))
        goto done;
    st = relief_mesh_subset(c, keep, &r->crop, crop_of, err);
    if (st != RELIEF_OK)
        goto done;
    /* crop_of: capture -> crop now; turned into crop -> capture */
    r->crop_to = malloc(r->crop->nv * sizeof *r->crop_to + 1);
    *crop_select = select ? malloc(r->crop->nv + 1) : NULL;
    if (!r->crop_to || (select && !*crop_select)) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the crop about the told holes");
        goto done;
    }
    for (size_t v = 0; v < c->nv; ++v)
        if (crop_of[v] != UINT32_MAX) {
            r->crop_to[crop_of[v]] = (uint32_t)v;
            if (select)
                (*crop_select)[crop_of[v]] = select[v];
        }
done:
    if (st != RELIEF_OK) {
        free(*crop_select);
        *crop_select = NULL;
        relief_complete_crop_free(r);
    }
    free(vt_start), free(vt), free(queue), free(crop_of), free(keep);
    return st;
}

void relief_complete_crop_free(relief_complete_run *r)
{
    relief_mesh_destroy(r->crop);
    free(r->crop_to);
    r->crop = NULL;
    r->crop_to = NULL;
}

/* A crop face's vertices, ascending, for finding it again. */
typedef struct face_key {
    uint32_t v[3];
} face_key;

static int cmp_face(const void *a, const void *b)
{
    const face_key *x = a, *y = b;
    for (int k = 0; k < 3; ++k)
        if (x->v[k] != y->v[k])
            return x->v[k] < y->v[k] ? -1 : 1;
    return 0;
}

static face_key key_of(const uint32_t *t)
{
    face_key k = {{t[0], t[1], t[2]}};
    qsort(k.v, 3, sizeof *k.v, relief_cmp_u32);
    return k;
}

/* Which of the completed crop's faces are new (`fresh`), and which of the
 * crop's own it kept (`kept`, by the crop's face order). */
static relief_status sort_faces(const relief_mesh *crop, const relief_mesh *done, uint8_t *kept,
                                uint8_t *fresh, relief_error *err)
{
    face_key *keys = malloc(crop->nt * sizeof *keys + 1);
    uint32_t *order = malloc(crop->nt * sizeof *order + 1);
    if (!keys || !order) {
        free(keys), free(order);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the crop's faces");
    }
    for (size_t f = 0; f < crop->nt; ++f)
        keys[f] = key_of(crop->tri + 3 * f);
    qsort(keys, crop->nt, sizeof *keys, cmp_face);
    memset(kept, 0, crop->nt);
    for (size_t f = 0; f < done->nt; ++f) {
        face_key k = key_of(done->tri + 3 * f);
        const face_key *at = bsearch(&k, keys, crop->nt, sizeof *keys, cmp_face);
        fresh[f] = at == NULL;
        if (at)
            kept[at - keys] = 1;
    }
    /* kept[] is by sorted key: back to the crop's order */
    for (size_t f = 0; f < crop->nt; ++f) {
        face_key k = key_of(crop->tri + 3 * f);
        order[f] = kept[(const face_key *)bsearch(&k, keys, crop->nt, sizeof *keys, cmp_face) -
                        keys];
    }
    for (size_t f = 0; f < crop->nt; ++f)
        kept[f] = (uint8_t)order[f];
    free(keys), free(order);
    return RELIEF_OK;
}

/* Vertex v of the output: the completed crop's vertex i (UINT32_MAX: the
 * capture's own v, untouched by the crop). */
static void copy_vertex(relief_mesh *out, size_t v, const relief_mesh *c, const relief_mesh *done,
                        uint32_t i)
{
    const relief_mesh *from = i == UINT32_MAX ? c : done;
    const size_t at = i == UINT32_MAX ? v : i;
    memcpy(out->pos + 3 * v, from->pos + 3 * at, 3 * sizeof *out->pos);
    if (out->col && from->col)
        memcpy(out->col + 3 * v, from->col + 3 * at, 3 * sizeof *out->col);
    if (out->nrm && from->nrm)
        memcpy(out->nrm + 3 * v, from->nrm + 3 * at, 3 * sizeof *out->nrm);
    if (out->label)
        out->label[v] = i == UINT32_MAX ? RELIEF_LABEL_CAPTURED
                        : done->label   ? done->label[i]
                                        : RELIEF_LABEL_CAPTURED;
}

/* The whole capture with the completed crop's new vertices and faces in
 * place of the crop's (the faces the crop's completion dropped, dropped). */
static relief_status sew(const relief_complete_run *r, const uint32_t *to_crop,
                         const uint8_t *kept, const uint8_t *fresh, relief_mesh **out,
                         relief_error *err)
{
    const relief_mesh *c = r->capture, *crop = r->crop, *done = r->s->mesh;
    const size_t added = done->nv - crop->nv;
    size_t nt = c->nt, f = 0;
    uint8_t *drop = calloc(c->nt + 1, 1);
    relief_mesh *o;
    relief_status st;
    if (!drop)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the completed capture");
    for (size_t t = 0, ct = 0; t < c->nt; ++t) { /* the crop's faces in capture order */
        const uint32_t *v = c->tri + 3 * t;
        if (to_crop[v[0]] == UINT32_MAX || to_crop[v[1]] == UINT32_MAX ||
            to_crop[v[2]] == UINT32_MAX)
            continue;
        drop[t] = !kept[ct++];
        nt -= drop[t];
    }
    for (size_t t = 0; t < done->nt; ++t)
        nt += fresh[t];
    st = relief_mesh_create(c->nv + added, nt, done->attrs | c->attrs, &o, err);
    if (st != RELIEF_OK) {
        free(drop);
        return st;
    }
    for (size_t v = 0; v < c->nv; ++v)
        copy_vertex(o, v, c, done, to_crop[v]);
    for (size_t i = 0; i < added; ++i)
        copy_vertex(o, c->nv + i, c, done, (uint32_t)(crop->nv + i));
    for (size_t t = 0; t < c->nt; ++t)
        if (!drop[t])
            memcpy(o->tri + 3 * f++, c->tri + 3 * t, 3 * sizeof *o->tri);
    for (size_t t = 0; t < done->nt; ++t)
        for (int k = 0; fresh[t] && k < 3; ++k) {
            const uint32_t v = done->tri[3 * t + (size_t)k];
            o->tri[3 * f + (size_t)k] =
                v < crop->nv ? r->crop_to[v] : (uint32_t)(c->nv + (v - crop->nv));
            f += k == 2;
        }
    free(drop);
    *out = o;
    return RELIEF_OK;
}

relief_status relief_complete_uncrop(const relief_complete_run *r, relief_mesh **out,
                                     relief_error *err)
{
    const relief_mesh *c = r->capture, *done = r->s->mesh;
    uint32_t *to_crop = malloc(c->nv * sizeof *to_crop + 1);
    uint8_t *kept = malloc(r->crop->nt + 1), *fresh = malloc(done->nt + 1);
    relief_status st;
    if (!to_crop || !kept || !fresh) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the completed capture");
    } else if (done->nv < r->crop->nv) {
        st = relief_fail(err, RELIEF_E_MESH, "the completed crop lost vertices (%zu of %zu)",
                         done->nv, r->crop->nv);
    } else {
        for (size_t v = 0; v < c->nv; ++v)
            to_crop[v] = UINT32_MAX;
        for (size_t i = 0; i < r->crop->nv; ++i)
            to_crop[r->crop_to[i]] = (uint32_t)i;
        st = sort_faces(r->crop, done, kept, fresh, err);
        if (st == RELIEF_OK)
            st = sew(r, to_crop, kept, fresh, out, err);
    }
    free(to_crop), free(kept), free(fresh);
    return st;
}
