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
 * (relief_told_pool), then CROP_MARGIN rings more, so the base's smoothing
 * and the pool's windows see what the whole capture would give them there;
 * a crop of 3/4 of the capture or more is not made. */
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
    pool = relief_told_pool(targets);
    return (size_t)fmin(CROP_PER_POOL * pool, (double)SIZE_MAX / 2);
}

/* The crop's search: done once `want` vertices are reached. */
typedef struct crop_count {
    size_t reached, want;
} crop_count;

static int count_vertex(void *ctx, uint32_t v)
{
    crop_count *c = ctx;
    (void)v;
    return ++c->reached >= c->want;
}

/* Breadth-first from the filled rims' vertices over the triangles, a ring
 * at a time, until `want` vertices are reached, then CROP_MARGIN rings
 * more; keep[v] marks them. Returns how many. queue: nv. */
static size_t crop_reach(const relief_complete_run *r, const uint32_t *vt_start,
                         const uint32_t *vt, size_t want, uint32_t *queue, uint8_t *keep)
{
    const relief_mesh *c = r->capture;
    crop_count n = {0, want};
    for (size_t v = 0; v < c->nv; ++v)
        if (r->rim[v]) {
            queue[n.reached++] = (uint32_t)v;
            keep[v] = 1;
        }
    return relief_mesh_rings(c->tri, vt_start, vt, queue, n.reached, keep, n.reached >= want,
                             CROP_MARGIN, count_vertex, &n);
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

/* A face's vertices, ascending, for finding it again, and its index. */
typedef struct face_key {
    uint32_t v[3];
    size_t face;
} face_key;

/* By the vertices alone: equal keys are the same face. */
static int cmp_face(const void *a, const void *b)
{
    const face_key *x = a, *y = b;
    for (int k = 0; k < 3; ++k)
        if (x->v[k] != y->v[k])
            return x->v[k] < y->v[k] ? -1 : 1;
    return 0;
}

/* t's vertices through map (NULL: as they are), ascending. */
static face_key key_of(const uint32_t *t, const uint32_t *map)
{
    face_key k = {{map ? map[t[0]] : t[0], map ? map[t[1]] : t[1], map ? map[t[2]] : t[2]}, 0};
    qsort(k.v, 3, sizeof *k.v, relief_cmp_u32);
    return k;
}

/* What the sewing knows: the part of the capture the base was built on
 * (the crop, or the capture itself, `to` NULL), the completed surface, and
 * each of its vertices' index in the part (its samples) or past it (its
 * targets: part->nv + j). */
typedef struct sewing {
    const relief_mesh *c, *part, *done;
    const uint32_t *to;  /* part->nv: the capture's vertex, or NULL: itself */
    uint32_t *in_part;   /* done->nv */
    uint8_t *kept;       /* part->nt: the completion kept the face */
    uint8_t *fresh;      /* done->nt: a face the completion made */
} sewing;

/* in_part: the completed surface's samples are the part's vertices in
 * order, those in no triangle left out (points/base_surface.h); matched by
 * their positions, which the base never moves. 0 when they are not. */
static int match_samples(sewing *w, size_t n_samples)
{
    size_t i = 0;
    for (size_t j = 0; j < w->done->nv; ++j) {
        if (j >= n_samples) {
            w->in_part[j] = (uint32_t)(w->part->nv + (j - n_samples));
            continue;
        }
        while (i < w->part->nv &&
               memcmp(w->part->pos + 3 * i, w->done->pos + 3 * j, 3 * sizeof(double)) != 0)
            ++i;
        if (i == w->part->nv)
            return 0;
        w->in_part[j] = (uint32_t)i++;
    }
    return 1;
}

/* Which of the completed surface's faces are new (fresh), and which of
 * the part's own it kept (kept, in the part's face order). */
static relief_status sort_faces(sewing *w, relief_error *err)
{
    const relief_mesh *part = w->part, *done = w->done;
    face_key *keys = malloc(part->nt * sizeof *keys + 1);
    if (!keys)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the capture's faces");
    for (size_t f = 0; f < part->nt; ++f) {
        keys[f] = key_of(part->tri + 3 * f, NULL);
        keys[f].face = f;
    }
    qsort(keys, part->nt, sizeof *keys, cmp_face);
    memset(w->kept, 0, part->nt);
    for (size_t f = 0; f < done->nt; ++f) {
        face_key k = key_of(done->tri + 3 * f, w->in_part);
        const face_key *at = bsearch(&k, keys, part->nt, sizeof *keys, cmp_face), *e;
        w->fresh[f] = at == NULL;
        /* every copy of the face (a capture may repeat one) */
        for (e = at; e && e >= keys && cmp_face(e, at) == 0; --e)
            w->kept[e->face] = 1;
        for (e = at; e && e < keys + part->nt && cmp_face(e, at) == 0; ++e)
            w->kept[e->face] = 1;
    }
    free(keys);
    return RELIEF_OK;
}

/* Vertex v of the output from the completed surface's vertex j
 * (UINT32_MAX: the capture's own v). */
static void copy_vertex(relief_mesh *out, size_t v, const sewing *w, uint32_t j)
{
    const relief_mesh *from = j == UINT32_MAX ? w->c : w->done;
    const size_t at = j == UINT32_MAX ? v : j;
    memcpy(out->pos + 3 * v, from->pos + 3 * at, 3 * sizeof *out->pos);
    if (out->col && from->col)
        memcpy(out->col + 3 * v, from->col + 3 * at, 3 * sizeof *out->col);
    if (out->nrm && from->nrm)
        memcpy(out->nrm + 3 * v, from->nrm + 3 * at, 3 * sizeof *out->nrm);
    if (out->label)
        out->label[v] = j != UINT32_MAX && w->done->label ? w->done->label[j]
                                                         : RELIEF_LABEL_CAPTURED;
}

/* The capture's index of the part's vertex i, or the output's of target
 * i - part->nv. */
static uint32_t out_index(const sewing *w, uint32_t i)
{
    if (i >= w->part->nv)
        return (uint32_t)(w->c->nv + (i - w->part->nv));
    return w->to ? w->to[i] : i;
}

/* The part's faces in the capture's order: drop[t] for those the
 * completion replaced; their count. */
static size_t dropped_faces(const sewing *w, uint8_t *drop)
{
    const relief_mesh *c = w->c;
    uint32_t *of = NULL;
    size_t n = 0, pt = 0;
    if (!w->to) { /* the part is the capture */
        for (size_t t = 0; t < c->nt; ++t)
            n += drop[t] = !w->kept[t];
        return n;
    }
    of = malloc(c->nv * sizeof *of + 1);
    if (!of)
        return SIZE_MAX;
    for (size_t v = 0; v < c->nv; ++v)
        of[v] = UINT32_MAX;
    for (size_t i = 0; i < w->part->nv; ++i)
        of[w->to[i]] = (uint32_t)i;
    for (size_t t = 0; t < c->nt; ++t) { /* relief_mesh_subset kept them in order */
        const uint32_t *v = c->tri + 3 * t;
        if (of[v[0]] == UINT32_MAX || of[v[1]] == UINT32_MAX || of[v[2]] == UINT32_MAX)
            continue;
        n += drop[t] = !w->kept[pt++];
    }
    free(of);
    return n;
}

/* The whole capture with the completed surface's targets and new faces,
 * less the faces the completion replaced. */
static relief_status sew(const sewing *w, relief_mesh **out, relief_error *err)
{
    const relief_mesh *c = w->c, *done = w->done;
    size_t added = 0;
    uint8_t *drop = calloc(c->nt + 1, 1);
    uint32_t *last = malloc((c->nv + 1) * sizeof *last);
    size_t nt = c->nt, f = 0, nd;
    relief_mesh *o;
    relief_status st;
    if (!drop || !last || (nd = dropped_faces(w, drop)) == SIZE_MAX) {
        free(drop), free(last);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the completed capture");
    }
    nt -= nd;
    for (size_t j = 0; j < done->nv; ++j)
        added += w->in_part[j] >= w->part->nv;
    for (size_t t = 0; t < done->nt; ++t)
        nt += w->fresh[t];
    st = relief_mesh_create(c->nv + added, nt, done->attrs | c->attrs, &o, err);
    if (st != RELIEF_OK) {
        free(drop), free(last);
        return st;
    }
    for (size_t v = 0; v < c->nv; ++v)
        last[v] = UINT32_MAX;
    for (size_t j = 0; j < done->nv; ++j) /* the capture's vertices the part holds */
        if (w->in_part[j] < w->part->nv)
            last[out_index(w, w->in_part[j])] = (uint32_t)j;
    for (size_t v = 0; v < c->nv; ++v)
        copy_vertex(o, v, w, last[v]);
    for (size_t j = 0; j < done->nv; ++j)
        if (w->in_part[j] >= w->part->nv)
            copy_vertex(o, out_index(w, w->in_part[j]), w, (uint32_t)j);
    for (size_t t = 0; t < c->nt; ++t)
        if (!drop[t])
            memcpy(o->tri + 3 * f++, c->tri + 3 * t, 3 * sizeof *o->tri);
    for (size_t t = 0; t < done->nt; ++t)
        if (w->fresh[t]) {
            for (int k = 0; k < 3; ++k)
                o->tri[3 * f + (size_t)k] = out_index(w, w->in_part[done->tri[3 * t + (size_t)k]]);
            ++f;
        }
    free(drop), free(last);
    *out = o;
    return RELIEF_OK;
}

relief_status relief_complete_uncrop(const relief_complete_run *r, relief_mesh **out,
                                     relief_error *err)
{
    sewing w = {r->capture, r->crop ? r->crop : r->capture, r->s->mesh, r->crop_to,
                NULL, NULL, NULL};
    relief_status st = RELIEF_OK;
    w.in_part = malloc(w.done->nv * sizeof *w.in_part + 1);
    w.kept = malloc(w.part->nt + 1);
    w.fresh = malloc(w.done->nt + 1);
    if (!w.in_part || !w.kept || !w.fresh)
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the completed capture");
    else if (w.done->nv == 0 || !match_samples(&w, r->s->n_samples))
        st = relief_fail(err, RELIEF_E_MESH, "the completed surface does not hold the "
                         "capture's vertices in order: it cannot be sewn back");
    if (st == RELIEF_OK)
        st = sort_faces(&w, err);
    if (st == RELIEF_OK)
        st = sew(&w, out, err);
    free(w.in_part), free(w.kept), free(w.fresh);
    return st;
}
