/* The hole model (issues 21 and 40): where a mesh or a point set has
 * holes, the rims of the holes, numbered, and which are filled.
 *
 * A mesh's holes are its boundary loops (edges of one triangle). A bare
 * point set's rim points are those whose neighbourhood is one-sided: the
 * k neighbours projected on the point's tangent plane leave an angular gap
 * wider than `gap` (radians; relief uses pi/2, Bendels et al. 2006's
 * angle criterion); rim points joined through the k-NN graph form one hole
 * (points/holes.h: relief_holes_points).
 *
 * Not every rim is a hole: the outer border of an open scan is one too,
 * and so is an opening the object has by design (a vase's mouth). Under
 * the rule (relief_hole_rule), a rim is filled unless it is too small, an
 * outer border, or wider than max_across; or, given a selection, exactly
 * when it has a selected point.
 *
 * A rim is taken for an outer border, and left open, when the ball about
 * its centroid through its farthest rim point holds more than half of the
 * points of its connected piece (through the triangles, or the k-NN graph;
 * a hole's ball holds few; a border's holds its piece, a stray fragment's
 * included). Rims of fewer than 3 points (a mesh's) or k points (a point set's: an
 * irregular sampling, a laser scan's or a random one, leaves one-sided
 * gaps of a few points everywhere; a hole with fewer than k rim points is
 * under about 2.5 spacings across) are dropped as noise.
 *
 * A selected rim that the rule would leave open (an outer border, or
 * wider than max_across) is filled in part: a cut that reaches a statue's
 * border through the gaps between its folds merges with the border's
 * loop, and the selection says which part is the hole. Only its selected
 * points are labelled, so the fill keeps to them (relief_rim.part); with
 * fewer than 3 (a point set: k) selected it keeps its fate, whole, and is
 * not filled. A selection that takes half or more of such a rim's points
 * (the hole_ball relief_holes_none_filled suggests; the ball a sphere's
 * cap was cut with, which misses a few rim points) fills it whole.
 *
 * Output: rim[i] = 0 off any rim, h in 1..n_holes on hole h's rim. */
#ifndef RELIEF_HOST_MESH_HOLES_H
#define RELIEF_HOST_MESH_HOLES_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"

/* What became of a rim (the hole model of issue 40). */
typedef enum relief_rim_fate {
    RELIEF_RIM_FILLED = 1,   /* a hole, filled */
    RELIEF_RIM_TOO_SMALL,    /* too few rim points: noise, left */
    RELIEF_RIM_BORDER,       /* the capture's outer border, left open */
    RELIEF_RIM_TOO_LARGE,    /* wider than the rule's max_across: an opening
                                the capture has by design (a vessel's mouth or
                                base, a bowl's opening), left open */
    RELIEF_RIM_NOT_SELECTED  /* a selection was given and misses it */
} relief_rim_fate;

/* The name the report uses: "filled", "too_small", "border", "too_large",
 * "not_selected". */
const char *relief_rim_fate_name(relief_rim_fate fate);

typedef struct relief_rim {
    uint32_t points;   /* rim points (a mesh's: its boundary vertices) */
    double across;     /* twice the largest distance of a rim point from the
                          rim's centroid (the diameter, for a round hole), in
                          the input's units */
    double centre[3];  /* the rim points' centroid */
    relief_rim_fate fate;
    uint32_t part;     /* filled in part: the selected points of a rim that
                          would otherwise stay open (a border or wider than
                          max_across: a cut that reaches the border through
                          a gap); points, across and centre are theirs, and
                          only they are labelled; 0: the whole rim */
} relief_rim;

/* Which rims are filled. */
typedef struct relief_hole_rule {
    double max_across;     /* a rim wider than this is left open (too_large);
                              0 or less: no limit */
    const uint8_t *select; /* NULL, or n entries: only the rims with a non-zero
                              point are filled, whatever their size or border
                              (a border or a rim over max_across only in its
                              selected points, above) */
} relief_hole_rule;

typedef struct relief_hole_info {
    uint32_t n_holes;      /* holes kept */
    uint32_t n_borders;    /* rims taken for an outer border and left open */
    uint32_t n_dropped;    /* rims too small */
    uint32_t n_too_large;  /* rims wider than the rule's max_across */
    uint32_t n_not_selected; /* rims the selection misses */
    double max_across;     /* the rule's, as applied */
    relief_rim *rims;      /* n_rims, every rim in label order (a kept rim h
                              is the h-th filled one) (owned) */
    uint32_t n_rims;
} relief_hole_info;

/* 1 when a rim is filled in part (a notch a selection takes of a border
 * or of an opening wider than max_across). */
int relief_holes_in_part(const relief_hole_info *h);

/* Free the rims and zero the info. */
void relief_hole_info_free(relief_hole_info *info);

/* The widest rim filled by default: max_hole when > 0, else a quarter of
 * the diagonal of the n points' bounding box. */
double relief_hole_size_limit(const double *pos, size_t n, double max_hole);

/* The k widest rims the model leaves open by its rule (outer borders,
 * wider than max_across; with `unselected`, those a selection misses too), each as "; FATE rim of N points, W across at
 * (X, Y, Z): [max_hole L or ]hole_ball X,Y,Z,R fills it" into buf (size
 * bytes, always terminated); the length it would take is returned. */
size_t relief_holes_open_list(const relief_hole_info *h, int k, int unselected, char *buf,
                              size_t size);

/* "" when no rim is left open by the rule, else "left open: B outer
 * border(s), L opening(s) wider than max_hole M" and the two widest as
 * relief_holes_open_list gives them, into buf (size bytes). */
void relief_holes_left_line(const relief_hole_info *h, char *buf, size_t size);

/* How relief_holes_none_filled's message begins. */
#define RELIEF_HOLES_NONE_FILLED "nothing to fill:"

/* No hole is filled: RELIEF_E_RANGE with a one-line message saying what
 * was found, the widest rims left open and the max_hole or hole_ball that
 * would fill each. */
relief_status relief_holes_none_filled(const relief_hole_info *h, relief_error *err);

/* The report's object `name`: the counts by fate, the max_hole applied and
 * every rim (its points, width, centre and fate) in `list`. */
struct relief_json;
void relief_holes_json(struct relief_json *j, const char *name, const relief_hole_info *h);

/* A hole ball's check: a finite centre and a radius > 0 (RELIEF_E_RANGE
 * naming `name`, "hole_ball", in the message and err->param). */
relief_status relief_hole_ball_check(const char *name, const double ball[4],
                                     relief_error *err);

/* A selection of a mesh's vertices (*select: nv bytes, owned, 1 when
 * selected): those with a non-zero label (labels; RELIEF_E_USAGE when the
 * mesh has none) or whose star the ball reaches (has_ball: within its
 * radius and the vertex's longest edge, so that the ball a hole was cut
 * with selects its rim); NULL when neither is asked. */
relief_status relief_holes_selection(const relief_mesh *m, int labels, int has_ball,
                                     const double ball[4], uint8_t **select, relief_error *err);

/* The hole model of a mesh as a user chooses it (complete, depth-fill):
 * max_hole (0: the default limit), and a selection, the vertices with a
 * non-zero label (labels; the mesh must have them) or within ball
 * (has_ball). *rim (owned, m's vertex count) and *info as
 * relief_holes_mesh gives them. */
relief_status relief_holes_of_mesh(const relief_mesh *m, double max_hole, int labels,
                                   int has_ball, const double ball[4], uint32_t **rim,
                                   relief_hole_info *info, relief_error *err);

/* From a mesh's triangles (nt x 3 indices into n vertices). */
relief_status relief_holes_mesh(const double *pos, size_t n, const uint32_t *tri, size_t nt,
                                const relief_hole_rule *rule, uint32_t *rim,
                                relief_hole_info *info, relief_error *err);

/* The rule applied to marked points (mark: n, 1 on a rim) joined into rims
 * by the union-find `parent` and into connected pieces by `piece` (both
 * over n, path-halved by relief_uf_find): rims under min_rim points are
 * too small. What relief_holes_mesh and relief_holes_points share. */
relief_status relief_holes_label(const double *pos, size_t n, const uint8_t *mark,
                                 uint32_t *parent, uint32_t *piece, double min_rim,
                                 const relief_hole_rule *rule, uint32_t *rim,
                                 relief_hole_info *info, relief_error *err);

/* The boundary loops of nt triangles over n vertices: loop[v] (n) 0 off
 * the boundary, else its loop's number, 1..*n_loops, in the order of the
 * loops' smallest vertices (vertices joined through boundary edges: two
 * loops that touch at a vertex are one). RELIEF_E_NOMEM. */
relief_status relief_boundary_loops(const uint32_t *tri, size_t nt, size_t n, uint32_t *loop,
                                    uint32_t *n_loops, relief_error *err);

/* The loops of a completed surface that no opening of its capture
 * explains (issue 40: no hole left where relief says it completed). */
typedef struct relief_open_loops {
    size_t loops;     /* boundary loops of the output left unexplained */
    size_t vertices;  /* their boundary vertices */
    size_t largest;   /* the largest's boundary vertices */
    double centre[3]; /* and its vertices' centroid */
} relief_open_loops;

/* The loops of `out`'s boundary most of whose vertices lie farther than
 * tol from every boundary vertex of `capture` off a filled rim (filled:
 * capture's vertex count, non-zero on the rims of the holes filled; NULL:
 * none). A capture's outer border, a mouth or a notch left open keeps the
 * output's loops along it; a loop elsewhere is a hole the completion
 * should have closed. RELIEF_E_NOMEM. */
relief_status relief_holes_not_closed(const relief_mesh *capture, const uint32_t *filled,
                                      const relief_mesh *out, double tol, relief_open_loops *o,
                                      relief_error *err);

/* For each of nq query points (nq x 3; pos itself when query is NULL, nq
 * then ignored and n used), the distance dist (nq) to the nearest of the n
 * points with rim[i] != 0 and, when `nearest` (nq) is not NULL, that
 * point's index. INFINITY and UINT32_MAX when no point is on a rim. */
relief_status relief_rim_distance(const double *pos, size_t n, const uint32_t *rim,
                                  const double *query, size_t nq, double *dist,
                                  uint32_t *nearest, relief_error *err);

#endif
