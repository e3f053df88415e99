/* The hole model over a primitive (issue 40): which of the uncovered
 * regions the capture's outline encloses are holes the user wants filled.
 * The capture's boundary loops are found and judged as complete-points
 * judges them (mesh/holes.h: max_hole, a hole ball, outer borders); a
 * lattice region is filled when most of its points lie within the reach of
 * a filled loop, the loop nearest each of them. */
#include "complete/engine.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "mesh/hole_fill.h"
#include "mesh/mesh.h"
#include "smooth/surface.h"

/* A region point belongs to a loop when within this many times its half
 * width of the loop's centre: the lattice lies on the primitive, the loop
 * on the capture, up to the relief's height off it. */
#define REACH 1.5

static int keep_region(void *ctx, const double *pts, size_t n)
{
    const relief_complete_run *r = ctx;
    const relief_hole_info *h = &r->holes;
    double *dist = malloc((n ? n : 1) * sizeof *dist);
    uint32_t *near = malloc((n ? n : 1) * sizeof *near);
    relief_error err = {0};
    size_t inside = 0;
    int keep = 1; /* on failure, as before the hole model: filled */
    if (dist && near && h->n_holes > 0 &&
        relief_rim_distance(r->capture->pos, r->capture->nv, r->rim, pts, n, dist, near,
                            &err) == RELIEF_OK) {
        for (size_t i = 0; i < n; ++i) {
            const relief_rim *m;
            double d2 = 0.0;
            if (near[i] == UINT32_MAX)
                continue;
            m = h->rims + r->rim_index[r->rim[near[i]] - 1];
            for (int c = 0; c < 3; ++c)
                d2 += (pts[3 * i + c] - m->centre[c]) * (pts[3 * i + c] - m->centre[c]);
            inside += sqrt(d2) <= REACH * 0.5 * m->across;
        }
        keep = 2 * inside > n;
    } else if (h->n_holes == 0) {
        keep = 0;
    }
    free(dist);
    free(near);
    return keep;
}

/* A point outside the capture's outline is taken when within half the
 * width of a rim filled in part (a selected notch in a border,
 * mesh/holes.h) of its centre: REACH would take a strip along the rest of
 * the border too, where the lattice's last row stands over a wavy edge. */
static int keep_point(void *ctx, const double *p)
{
    const relief_complete_run *r = ctx;
    for (size_t i = 0; i < r->n_arcs; ++i) {
        const relief_rim_arc *a = r->arcs + i;
        const relief_rim *m = r->holes.rims + r->rim_index[a->label - 1];
        const double *A = r->capture->pos + 3 * (size_t)a->first;
        const double *B = r->capture->pos + 3 * (size_t)a->last;
        double d2 = 0.0, mid[3], c[3], d[3], q[3], cc, t;
        if (!m->part)
            continue;
        for (int e = 0; e < 3; ++e)
            d2 += (p[e] - m->centre[e]) * (p[e] - m->centre[e]);
        if (sqrt(d2) > 0.5 * m->across)
            continue;
        /* and on the notch's side of the chord across its ends (issue 61:
         * the disc alone reached past the scan's border) */
        for (int e = 0; e < 3; ++e)
            mid[e] = 0.5 * (A[e] + B[e]), c[e] = B[e] - A[e], d[e] = a->mean[e] - mid[e];
        cc = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
        t = cc > 0 ? (d[0] * c[0] + d[1] * c[1] + d[2] * c[2]) / cc : 0.0;
        for (int e = 0; e < 3; ++e)
            d[e] -= t * c[e], q[e] = p[e] - mid[e];
        if (q[0] * d[0] + q[1] * d[1] + q[2] * d[2] >= 0.0)
            return 1;
    }
    return 0;
}

relief_status relief_complete_holes(relief_complete_run *r, relief_error *err)
{
    const relief_mesh *c = r->capture;
    const relief_complete_params *cp = r->cp;
    const int selected = cp->has_hole_ball || cp->hole_labels;
    relief_status st;
    uint32_t h = 0;
    if (c->nt == 0 || cp->base == RELIEF_BASE_SMOOTH)
        return RELIEF_OK;
    st = relief_holes_of_mesh(c, cp->max_hole, cp->hole_labels, cp->has_hole_ball,
                              cp->hole_ball, &r->rim, &r->holes, err);
    if (st != RELIEF_OK)
        return st;
    r->rim_index = malloc((r->holes.n_holes + 1) * sizeof *r->rim_index);
    if (!r->rim_index)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the capture's rims");
    for (uint32_t i = 0; i < r->holes.n_rims; ++i)
        if (r->holes.rims[i].fate == RELIEF_RIM_FILLED)
            r->rim_index[h++] = i;
    r->has_holes = 1;
    r->st.smooth.holes.keep = keep_region;
    if (relief_holes_in_part(&r->holes)) {
        r->st.smooth.holes.keep_point = keep_point;
        st = relief_rim_arcs(c->pos, c->nv, c->tri, c->nt, r->rim, &r->arcs, &r->n_arcs, err);
        if (st != RELIEF_OK)
            return st;
    }
    r->st.smooth.holes.ctx = r;
    r->st.smooth.holes.on_plane = selected || cp->max_hole > 0.0;
    if (selected && r->st.smooth.fill == RELIEF_FILL_AUTO)
        r->st.smooth.fill = RELIEF_FILL_HOLES;
    return RELIEF_OK;
}

void relief_complete_note_open_rims(relief_complete_run *r)
{
    char line[640];
    if (!r->has_holes)
        return;
    relief_holes_left_line(&r->holes, line, sizeof line);
    if (line[0])
        relief_complete_note(r, 0, "%s", line);
}

/* A selection told which holes to fill: one left open is a failure. */
static relief_status told_hole_open(relief_complete_run *r, relief_error *err)
{
    if (!r->open_loops || !(r->cp->has_hole_ball || r->cp->hole_labels))
        return RELIEF_OK;
    return relief_fail_reason(err, RELIEF_E_RANGE, RELIEF_REASON_HOLES_LEFT_OPEN,
                              "the hole the selection names is not closed: %zu loop(s) of the "
                              "completed surface (%zu boundary vertices) are open where it "
                              "filled", r->open_loops, r->open_edges);
}

relief_status relief_complete_holes_closed(relief_complete_run *r, relief_error *err)
{
    const relief_mesh *m = r->s ? r->s->mesh : NULL;
    relief_open_loops o;
    relief_status st;
    if (r->smooth_base && r->closed_checked) { /* counted on the base (smooth_base) */
        if (r->open_loops)
            relief_complete_note(r, 1, "%zu loop%s of the completed surface (%zu boundary "
                                 "edges) %s open where holes were filled",
                                 r->open_loops, r->open_loops == 1 ? "" : "s", r->open_edges,
                                 r->open_loops == 1 ? "is" : "are");
        return told_hole_open(r, err);
    }
    if (!r->has_holes || r->smooth_base || !m || r->s->fill.region != RELIEF_FILL_HOLES)
        return RELIEF_OK;
    st = relief_holes_not_closed(r->capture, r->rim, m, 2.0 * r->s->spacing, &o, err);
    if (st != RELIEF_OK)
        return st;
    r->closed_checked = 1;
    r->open_loops = o.loops;
    r->open_edges = o.vertices;
    if (o.loops && (r->cp->has_hole_ball || r->cp->hole_labels))
        return told_hole_open(r, err);
    if (o.loops)
        relief_complete_note(r, 1, "%zu loop%s of the completed surface (%zu boundary vertices, "
                             "the largest %zu at (%.4g, %.4g, %.4g)) %s open where no opening of "
                             "the capture is left open: holes relief filled are not closed",
                             o.loops, o.loops == 1 ? "" : "s", o.vertices, o.largest,
                             o.centre[0], o.centre[1], o.centre[2],
                             o.loops == 1 ? "is" : "are");
    return RELIEF_OK;
}

void relief_complete_holes_free(relief_complete_run *r)
{
    relief_hole_info_free(&r->holes);
    free(r->rim);
    free(r->rim_index);
    free(r->arcs);
    r->rim = r->rim_index = NULL;
    r->arcs = NULL, r->n_arcs = 0;
    r->has_holes = 0;
}
