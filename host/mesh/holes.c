/* Hole rims of meshes and of bare point sets (holes.h). */
#include "mesh/holes.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/json.h"
#include "base/knn.h"
#include "base/numtext.h"
#include "base/union_find.h"
#include "base/vec3.h"
#include "mesh/mesh.h"
#include "mesh/mesh_check.h"


static const char *const fate_names[] = {"", "filled", "too_small", "border", "too_large",
                                         "not_selected"};

const char *relief_rim_fate_name(relief_rim_fate fate)
{
    return fate >= RELIEF_RIM_FILLED && fate <= RELIEF_RIM_NOT_SELECTED ? fate_names[fate]
                                                                          : "unknown";
}

void relief_hole_info_free(relief_hole_info *info)
{
    if (!info)
        return;
    free(info->rims);
    memset(info, 0, sizeof *info);
}

/* The rule of holes.h, in its order: noise, then a selection when there is
 * one, else the border, then the size. */
static relief_rim_fate rim_fate(const relief_hole_rule *rule, int too_small, int selected,
                                int border, double across)
{
    if (too_small)
        return RELIEF_RIM_TOO_SMALL;
    if (rule->select)
        return selected ? RELIEF_RIM_FILLED : RELIEF_RIM_NOT_SELECTED;
    if (border)
        return RELIEF_RIM_BORDER;
    if (rule->max_across > 0.0 && across > rule->max_across)
        return RELIEF_RIM_TOO_LARGE;
    return RELIEF_RIM_FILLED;
}

static void count_fate(relief_hole_info *info, relief_rim_fate fate)
{
    switch (fate) {
    case RELIEF_RIM_FILLED: ++info->n_holes; break;
    case RELIEF_RIM_TOO_SMALL: ++info->n_dropped; break;
    case RELIEF_RIM_BORDER: ++info->n_borders; break;
    case RELIEF_RIM_TOO_LARGE: ++info->n_too_large; break;
    case RELIEF_RIM_NOT_SELECTED: ++info->n_not_selected; break;
    }
}

/* A selected rim the rule would leave open (its fate without the
 * selection: `open`), filled in its selected points alone (holes.h):
 * their count, centroid and width; under min_rim of them it keeps that
 * fate, whole, so that a refusal lists it with the ball that fills it.
 * Returns the points. */
static uint32_t take_part(const double *pos, size_t n, const uint8_t *mark, const uint32_t *comp,
                          uint32_t h, const uint8_t *select, double min_rim,
                          relief_rim_fate open, relief_rim *r)
{
    double c[3] = {0, 0, 0}, far = 0.0, d[3];
    uint32_t k = 0;
    for (size_t i = 0; i < n; ++i)
        if (mark[i] && comp[i] == h && select[i]) {
            for (int e = 0; e < 3; ++e)
                c[e] += pos[3 * i + e];
            ++k;
        }
    if (k < min_rim) {
        r->fate = open;
        return k;
    }
    if (2 * (size_t)k >= r->points) /* most of it: the hole told, whole (the */
        return k;                   /* ball a cap was cut with misses a few) */
    for (int e = 0; e < 3; ++e)
        c[e] /= k;
    for (size_t i = 0; i < n; ++i)
        if (mark[i] && comp[i] == h && select[i]) {
            sub3(pos + 3 * i, c, d);
            far = fmax(far, sqrt(dot3(d, d)));
        }
    r->part = r->points = k;
    r->across = 2.0 * far;
    memcpy(r->centre, c, sizeof c);
    return k;
}

/* Each of the nc rims' centre and radius from its marked points (comp:
 * each point's rim): acc, nc x 5 (zeroed), receives the centroid (3), the
 * point count and the largest distance from the centroid. */
static void rim_shapes(const double *pos, size_t n, const uint8_t *mark, const uint32_t *comp,
                       uint32_t nc, double *acc)
{
    for (size_t i = 0; i < n; ++i)
        if (mark[i]) {
            double *a = acc + 5 * (size_t)comp[i];
            for (int c = 0; c < 3; ++c)
                a[c] += pos[3 * i + c];
            a[3] += 1.0;
        }
    for (uint32_t h = 0; h < nc; ++h)
        for (int c = 0; c < 3; ++c)
            acc[5 * (size_t)h + c] /= acc[5 * (size_t)h + 3];
    for (size_t i = 0; i < n; ++i)
        if (mark[i]) {
            double *a = acc + 5 * (size_t)comp[i], d[3];
            sub3(pos + 3 * i, a, d);
            a[4] = fmax(a[4], sqrt(dot3(d, d)));
        }
}

/* For each rim of at least min_rim points (acc: rim_shapes), how many
 * points of the connected piece it lies on (rim_piece[h], set here) lie
 * within its ball: inside (nc, zeroed). O(n x rims): rims are few (tens);
 * a scan with thousands of rims is noise the size rule drops first. */
static void rim_insides(const double *pos, size_t n, const uint8_t *mark,
                        const uint32_t *piece, const uint32_t *comp, uint32_t nc,
                        const double *acc, double min_rim, uint32_t *rim_piece, size_t *inside)
{
    for (size_t i = 0; i < n; ++i)
        if (mark[i])
            rim_piece[comp[i]] = piece[i];
    for (uint32_t h = 0; h < nc; ++h) {
        const double *a = acc + 5 * (size_t)h;
        if (a[3] < min_rim)
            continue;
        for (size_t i = 0; i < n; ++i) {
            double d[3];
            if (piece[i] != rim_piece[h])
                continue;
            sub3(pos + 3 * i, a, d);
            inside[h] += dot3(d, d) <= a[4] * a[4];
        }
    }
}

/* Number the components of the marked points (parent: a union-find over
 * all n), keep the holes (the border rule, the size rule of holes.h), and
 * write rim. */
relief_status relief_holes_label(const double *pos, size_t n, const uint8_t *mark,
                                uint32_t *parent, uint32_t *piece, double min_rim,
                                const relief_hole_rule *rule, uint32_t *rim,
                                relief_hole_info *info, relief_error *err)
{
    size_t *piece_size = calloc(n + 1, sizeof *piece_size);
    uint32_t *comp = malloc(n * sizeof *comp), nc = 0;
    double *acc = NULL; /* per component: centroid sum (3), count, radius */
    memset(info, 0, sizeof *info);
    if (!comp || !piece_size) {
        free(comp), free(piece_size);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the hole labels");
    }
    for (size_t i = 0; i < n; ++i) /* piece[i]: its connected piece's root */
        piece[i] = relief_uf_find(piece, (uint32_t)i);
    for (size_t i = 0; i < n; ++i)
        ++piece_size[piece[i]];
    for (size_t i = 0; i < n; ++i)
        comp[i] = UINT32_MAX;
    for (size_t i = 0; i < n; ++i)
        if (mark[i]) {
            uint32_t r = relief_uf_find(parent, (uint32_t)i);
            if (comp[r] == UINT32_MAX)
                comp[r] = nc++;
            comp[i] = comp[r];
        }
    acc = calloc((size_t)nc * 5 + 1, sizeof *acc);
    if (!acc) {
        free(comp), free(piece_size);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the hole labels");
    }
    rim_shapes(pos, n, mark, comp, nc, acc);
    {
        uint32_t *keep = calloc((size_t)nc + 1, sizeof *keep);
        size_t *inside = calloc((size_t)nc + 1, sizeof *inside);
        uint32_t *rim_piece = calloc((size_t)nc + 1, sizeof *rim_piece);
        uint8_t *selected = calloc((size_t)nc + 1, 1);
        info->rims = calloc((size_t)nc + 1, sizeof *info->rims);
        if (!keep || !inside || !rim_piece || !selected || !info->rims) {
            free(keep), free(inside), free(rim_piece), free(selected), free(comp), free(acc),
                free(piece_size);
            relief_hole_info_free(info);
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the hole labels");
        }
        rim_insides(pos, n, mark, piece, comp, nc, acc, min_rim, rim_piece, inside);
        for (size_t i = 0; rule->select && i < n; ++i)
            if (mark[i] && rule->select[i])
                selected[comp[i]] = 1;
        info->max_across = rule->max_across > 0.0 ? rule->max_across : 0.0;
        for (uint32_t h = 0; h < nc; ++h) {
            const double *a = acc + 5 * (size_t)h;
            relief_rim *r = info->rims + h;
            r->points = (uint32_t)a[3];
            r->across = 2.0 * a[4];
            memcpy(r->centre, a, sizeof r->centre);
            r->fate = rim_fate(rule, a[3] < min_rim, selected[h],
                               2 * inside[h] > piece_size[rim_piece[h]], r->across);
            if (r->fate == RELIEF_RIM_FILLED && rule->select) {
                const relief_rim_fate open =
                    rim_fate(&(relief_hole_rule){rule->max_across, NULL}, 0, 0,
                             2 * inside[h] > piece_size[rim_piece[h]], r->across);
                if (open != RELIEF_RIM_FILLED)
                    take_part(pos, n, mark, comp, h, rule->select, min_rim, open, r);
            }
            count_fate(info, r->fate);
            if (r->fate == RELIEF_RIM_FILLED)
                keep[h] = info->n_holes;
        }
        info->n_rims = nc;
        for (size_t i = 0; i < n; ++i)
            rim[i] = mark[i] && (!info->rims[comp[i]].part || rule->select[i]) ? keep[comp[i]]
                                                                               : 0;
        free(keep);
        free(inside);
        free(rim_piece);
        free(selected);
    }
    free(comp);
    free(acc);
    free(piece_size);
    return RELIEF_OK;
}

/* The boundary of nt triangles over n vertices: mark[v] 1 on a boundary
 * edge (an undirected edge met once), parent joining the ends of each such
 * edge, piece (when not NULL) every triangle's corners. parent and piece
 * are set up here. 0 when out of memory. */
static int boundary_marks(const uint32_t *tri, size_t nt, size_t n, uint8_t *mark,
                          uint32_t *parent, uint32_t *piece, size_t *n_edges)
{
    const size_t m = 3 * nt;
    uint64_t *e = relief_edge_keys(tri, nt);
    if (!e)
        return 0;
    for (size_t i = 0; i < n; ++i) {
        parent[i] = (uint32_t)i;
        if (piece)
            piece[i] = (uint32_t)i;
    }
    for (size_t t = 0; piece && t < m; ++t)
        relief_uf_join(piece, (uint32_t)(e[t] >> 32), (uint32_t)e[t]);
    *n_edges = 0;
    for (size_t i = 0; i < m;) {
        size_t j = i;
        while (j < m && e[j] == e[i])
            ++j;
        if (j - i == 1) {
            uint32_t a = (uint32_t)(e[i] >> 32), b = (uint32_t)e[i];
            mark[a] = mark[b] = 1;
            relief_uf_join(parent, a, b);
            ++*n_edges;
        }
        i = j;
    }
    free(e);
    return 1;
}

relief_status relief_holes_mesh(const double *pos, size_t n, const uint32_t *tri, size_t nt,
                                const relief_hole_rule *rule, uint32_t *rim,
                                relief_hole_info *info, relief_error *err)
{
    uint32_t *parent = malloc(n * sizeof *parent + 1), *piece = malloc(n * sizeof *piece + 1);
    uint8_t *mark = calloc(n + 1, 1);
    relief_status st;
    size_t edges;

    if (!parent || !mark || !piece || !boundary_marks(tri, nt, n, mark, parent, piece, &edges)) {
        free(parent), free(mark), free(piece);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the boundary of %zu triangles",
                           nt);
    }
    st = relief_holes_label(pos, n, mark, parent, piece, 3.0, rule, rim, info, err);
    free(parent), free(mark), free(piece);
    return st;
}

relief_status relief_boundary_loops(const uint32_t *tri, size_t nt, size_t n, uint32_t *loop,
                                    uint32_t *n_loops, relief_error *err)
{
    uint32_t *parent = malloc(n * sizeof *parent + 1), *id = malloc(n * sizeof *id + 1);
    uint8_t *mark = calloc(n + 1, 1);
    size_t edges;
    *n_loops = 0;
    if (!parent || !id || !mark || !boundary_marks(tri, nt, n, mark, parent, NULL, &edges)) {
        free(parent), free(id), free(mark);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the boundary of %zu triangles",
                           nt);
    }
    for (size_t v = 0; v < n; ++v)
        id[v] = 0;
    for (size_t v = 0; v < n; ++v) {
        uint32_t root;
        loop[v] = 0;
        if (!mark[v])
            continue;
        root = relief_uf_find(parent, (uint32_t)v);
        if (!id[root])
            id[root] = ++*n_loops;
        loop[v] = id[root];
    }
    free(parent), free(id), free(mark);
    return RELIEF_OK;
}

relief_status relief_rim_distance(const double *pos, size_t n, const uint32_t *rim,
                                  const double *query, size_t nq, double *dist,
                                  uint32_t *nearest, relief_error *err)
{
    struct FLANNParameters fp = relief_knn_exact_params();
    size_t m = 0;
    double *rp = NULL, *d2 = NULL;
    uint32_t *which = NULL;
    int *idx = NULL;
    flann_index_t index = NULL;
    float speedup;
    relief_status st = RELIEF_OK;

    if (!query) {
        query = pos;
        nq = n;
    }
    for (size_t i = 0; i < n; ++i)
        m += rim[i] != 0;
    if (!m) {
        for (size_t i = 0; i < nq; ++i) {
            dist[i] = INFINITY;
            if (nearest)
                nearest[i] = UINT32_MAX;
        }
        return RELIEF_OK;
    }
    rp = malloc(m * 3 * sizeof *rp);
    which = malloc(m * sizeof *which);
    idx = malloc((nq + 1) * sizeof *idx);
    d2 = malloc((nq + 1) * sizeof *d2);
    if (!rp || !which || !idx || !d2) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate %zu rim points", m);
        goto done;
    }
    m = 0;
    for (size_t i = 0; i < n; ++i)
        if (rim[i]) {
            memcpy(rp + 3 * m, pos + 3 * i, 3 * sizeof *rp);
            which[m++] = (uint32_t)i;
        }
    index = flann_build_index_double(rp, (int)m, 3, &speedup, &fp);
    if (!index) {
        st = relief_fail(err, RELIEF_E_NOMEM, "FLANN could not index %zu rim points", m);
        goto done;
    }
    if (nq && flann_find_nearest_neighbors_index_double(index, (double *)query, (int)nq, idx, d2,
                                                        1, &fp) != 0) {
        st = relief_fail(err, RELIEF_E_INTERNAL, "FLANN's rim search failed");
        goto done;
    }
    for (size_t i = 0; i < nq; ++i) {
        dist[i] = sqrt(d2[i]);
        if (nearest)
            nearest[i] = which[idx[i]];
    }
done:
    if (index)
        flann_free_index_double(index, &fp);
    free(rp), free(which), free(idx), free(d2);
    return st;
}

/* The widest rim filled: max_hole, or by default a quarter of the
 * diagonal of the points' bounding box. Openings by design are wider (a
 * vase's mouth or base: 0.30 to 0.57 of it on the ggg_sfm captures), the
 * holes a capture misses or a user cuts narrower (at most 0.22 there). */
double relief_hole_size_limit(const double *pos, size_t n, double max_hole)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    if (max_hole > 0.0)
        return max_hole;
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c)
            lo[c] = fmin(lo[c], pos[3 * i + c]), hi[c] = fmax(hi[c], pos[3 * i + c]);
    return n ? 0.25 * sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                           (hi[2] - lo[2]) * (hi[2] - lo[2]))
             : 0.0;
}

size_t relief_holes_open_list(const relief_hole_info *h, int k, int unselected, char *buf,
                              size_t size)
{
    size_t len = 0;
    uint8_t *shown = calloc(h->n_rims + 1, 1);
    if (size)
        buf[0] = '\0';
    for (int i = 0; i < k && shown; ++i) {
        uint32_t best = UINT32_MAX;
        for (uint32_t r = 0; r < h->n_rims; ++r)
            if (!shown[r] && (h->rims[r].fate == RELIEF_RIM_BORDER ||
                              h->rims[r].fate == RELIEF_RIM_TOO_LARGE ||
                              (unselected && h->rims[r].fate == RELIEF_RIM_NOT_SELECTED)) &&
                (best == UINT32_MAX || h->rims[r].across > h->rims[best].across))
                best = r;
        if (best == UINT32_MAX)
            break;
        shown[best] = 1;
        const relief_rim *r = h->rims + best;
        char larger[48] = "";
        if (r->fate == RELIEF_RIM_TOO_LARGE)
            relief_snprintf_c(larger, sizeof larger, "max_hole %.4g or ", 1.01 * r->across);
        len += (size_t)relief_snprintf_c(buf + len, len < size ? size - len : 0,
                                         "; %s rim of %u points, %.4g across at (%.4g, %.4g, "
                                         "%.4g): %shole_ball %.4g,%.4g,%.4g,%.4g fills it%s",
                                         relief_rim_fate_name(r->fate), r->points, r->across,
                                         r->centre[0], r->centre[1], r->centre[2], larger,
                                         r->centre[0], r->centre[1], r->centre[2],
                                         0.6 * r->across,
                                         r->fate == RELIEF_RIM_BORDER ? " (a ball at a notch "
                                         "of it fills the notch)" : "");
    }
    free(shown);
    return len;
}

int relief_holes_in_part(const relief_hole_info *h)
{
    for (uint32_t i = 0; i < h->n_rims; ++i)
        if (h->rims[i].fate == RELIEF_RIM_FILLED && h->rims[i].part)
            return 1;
    return 0;
}

void relief_holes_left_line(const relief_hole_info *h, char *buf, size_t size)
{
    char list[520];
    if (size)
        buf[0] = '\0';
    if (h->n_borders + h->n_too_large == 0)
        return;
    relief_holes_open_list(h, 2, 0, list, sizeof list);
    relief_snprintf_c(buf, size, "left open: %u outer border(s), %u opening(s) wider than "
                      "max_hole %.4g%s", h->n_borders, h->n_too_large, h->max_across, list);
}

/* No hole is filled: say what was found, the widest rims left open and
 * what would fill each, on one line. */
relief_status relief_holes_none_filled(const relief_hole_info *h, relief_error *err)
{
    char list[600];
    relief_holes_open_list(h, 3, 1, list, sizeof list);
    return relief_fail_reason(err, RELIEF_E_RANGE, RELIEF_REASON_NOTHING_TO_FILL,
                       RELIEF_HOLES_NONE_FILLED " no hole to fill among %u rim(s) "
                       "(%u outer border(s), %u wider than max_hole %.4g, %u not selected, %u "
                       "too small)%s", h->n_rims, h->n_borders, h->n_too_large,
                       h->max_across, h->n_not_selected, h->n_dropped, list);
}

void relief_holes_json(relief_json *j, const char *name, const relief_hole_info *h)
{
    rj_begin_object(j, name);
    rj_int(j, "filled", h->n_holes);
    rj_int(j, "outer_borders", h->n_borders);
    rj_int(j, "too_small", h->n_dropped);
    rj_int(j, "too_large", h->n_too_large);
    rj_int(j, "not_selected", h->n_not_selected);
    rj_number(j, "max_hole", h->max_across);
    rj_begin_array(j, "list");
    for (uint32_t i = 0; i < h->n_rims; ++i) {
        const relief_rim *m = h->rims + i;
        rj_begin_object(j, NULL);
        rj_int(j, "rim_points", m->points);
        rj_number(j, "across", m->across);
        rj_vec3(j, "centre", m->centre);
        rj_string(j, "fate", relief_rim_fate_name(m->fate));
        if (m->part)
            rj_bool(j, "in_part", 1);
        rj_end_object(j);
    }
    rj_end_array(j);
    rj_end_object(j);
}

relief_status relief_hole_ball_check(const char *name, const double ball[4],
                                     relief_error *err)
{
    if (isfinite(ball[0]) && isfinite(ball[1]) && isfinite(ball[2]) && ball[3] > 0.0 &&
        isfinite(ball[3]))
        return RELIEF_OK;
    return relief_fail_param(err, RELIEF_E_RANGE, name, "%s %g,%g,%g,%g out of range: "
                             "expected a finite centre and a radius > 0", name, ball[0],
                             ball[1], ball[2], ball[3]);
}

relief_status relief_holes_selection(const relief_mesh *m, int labels, int has_ball,
                                     const double ball[4], uint8_t **select, relief_error *err)
{
    *select = NULL;
    if (labels && !m->label)
        return relief_fail(err, RELIEF_E_USAGE, "hole_labels: the mesh has no labels (a PLY "
                           "`label` property)");
    if (!labels && !has_ball)
        return RELIEF_OK;
    double *reach = labels ? NULL : calloc(m->nv + 1, sizeof *reach);
    if (!(*select = calloc(m->nv + 1, 1)) || (!labels && !reach)) {
        free(*select), free(reach);
        *select = NULL;
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the hole selection");
    }
    /* A ball selects the vertices whose star it reaches: within R and the
     * vertex's longest edge. The ball a hole was cut with (relief cut
     * --ball) holds none of the hole's rim, which lies just outside it. */
    for (size_t t = 0; reach && t < m->nt; ++t)
        for (int k = 0; k < 3; ++k) {
            uint32_t a = m->tri[3 * t + k], b = m->tri[3 * t + (k + 1) % 3];
            double e[3], len;
            sub3(m->pos + 3 * (size_t)a, m->pos + 3 * (size_t)b, e);
            len = sqrt(dot3(e, e));
            reach[a] = fmax(reach[a], len), reach[b] = fmax(reach[b], len);
        }
    for (size_t v = 0; v < m->nv; ++v) {
        double d[3];
        sub3(m->pos + 3 * v, ball, d);
        (*select)[v] = labels ? m->label[v] != 0 : sqrt(dot3(d, d)) <= ball[3] + reach[v];
    }
    free(reach);
    return RELIEF_OK;
}

relief_status relief_holes_of_mesh(const relief_mesh *m, double max_hole, int labels,
                                   int has_ball, const double ball[4], uint32_t **rim,
                                   relief_hole_info *info, relief_error *err)
{
    uint8_t *select = NULL;
    relief_hole_rule rule;
    relief_status st;
    memset(info, 0, sizeof *info);
    *rim = NULL;
    st = relief_holes_selection(m, labels, has_ball, ball, &select, err);
    if (st != RELIEF_OK)
        return st;
    *rim = calloc(m->nv + 1, sizeof **rim);
    if (!*rim) {
        free(select);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the mesh's rims");
    }
    rule.max_across = relief_hole_size_limit(m->pos, m->nv, max_hole);
    rule.select = select;
    st = relief_holes_mesh(m->pos, m->nv, m->tri, m->nt, &rule, *rim, info, err);
    free(select);
    if (st != RELIEF_OK) {
        free(*rim);
        *rim = NULL;
    }
    return st;
}

/* Per loop of `out` (loop: its vertices' numbers), tallied from the nb
 * boundary vertices at[i] and their distances to the capture's openings. */
static relief_status tally_open(const relief_mesh *out, const uint32_t *loop, uint32_t n_loops,
                                const uint32_t *at, const double *dist, size_t nb, double tol,
                                relief_open_loops *o, relief_error *err)
{
    size_t *count = calloc(n_loops + 1, sizeof *count), *far = calloc(n_loops + 1, sizeof *far);
    double *c = calloc(3 * ((size_t)n_loops + 1), sizeof *c);
    if (!count || !far || !c) {
        free(count), free(far), free(c);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the surface's loops");
    }
    for (size_t i = 0; i < nb; ++i) {
        const uint32_t l = loop[at[i]];
        ++count[l];
        far[l] += !(dist[i] <= tol);
        for (int k = 0; k < 3; ++k)
            c[3 * l + k] += out->pos[3 * (size_t)at[i] + k];
    }
    for (uint32_t l = 1; l <= n_loops; ++l) {
        if (2 * far[l] <= count[l])
            continue;
        ++o->loops;
        o->vertices += count[l];
        if (count[l] > o->largest) {
            o->largest = count[l];
            for (int k = 0; k < 3; ++k)
                o->centre[k] = c[3 * l + k] / (double)count[l];
        }
    }
    free(count), free(far), free(c);
    return RELIEF_OK;
}

relief_status relief_holes_not_closed(const relief_mesh *capture, const uint32_t *filled,
                                      const relief_mesh *out, double tol, relief_open_loops *o,
                                      relief_error *err)
{
    const size_t nv = relief_mesh_vertex_count(capture), mv = relief_mesh_vertex_count(out);
    uint32_t *in = malloc((nv + 1) * sizeof *in), *loop = malloc((mv + 1) * sizeof *loop);
    uint32_t *at = NULL, n_in = 0, n_out = 0;
    double *q = NULL, *dist = NULL;
    size_t nb = 0;
    relief_status st = RELIEF_OK;
    memset(o, 0, sizeof *o);
    if (!in || !loop)
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the surface's boundary");
    if (st == RELIEF_OK)
        st = relief_boundary_loops(capture->tri, capture->nt, nv, in, &n_in, err);
    if (st == RELIEF_OK)
        st = relief_boundary_loops(out->tri, out->nt, mv, loop, &n_out, err);
    for (size_t v = 0; st == RELIEF_OK && v < nv; ++v) /* the openings left by choice */
        in[v] = in[v] && !(filled && filled[v]);
    for (size_t v = 0; st == RELIEF_OK && v < mv; ++v)
        nb += loop[v] != 0;
    if (st == RELIEF_OK && nb > 0) {
        q = malloc(3 * nb * sizeof *q);
        dist = malloc(nb * sizeof *dist);
        at = malloc(nb * sizeof *at);
        if (!q || !dist || !at)
            st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the surface's boundary");
    }
    if (st == RELIEF_OK && nb > 0) {
        nb = 0;
        for (size_t v = 0; v < mv; ++v)
            if (loop[v]) {
                at[nb] = (uint32_t)v;
                memcpy(q + 3 * nb++, out->pos + 3 * v, 3 * sizeof *q);
            }
        st = relief_rim_distance(capture->pos, nv, in, q, nb, dist, NULL, err);
    }
    if (st == RELIEF_OK && nb > 0)
        st = tally_open(out, loop, n_out, at, dist, nb, tol, o, err);
    free(in), free(loop), free(at), free(q), free(dist);
    return st;
}
