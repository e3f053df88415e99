/* Surface clustering, the direction field over the clusters and the
 * tangent-plane grids of the texture optimisation (paper 002, sections 3.2
 * and 3.3). Internal to points/: texopt.c is its user.
 * Units: the points' own; pos and nrm are n x 3 (unit normals). */
#ifndef RELIEF_HOST_POINTS_CLUSTER_H
#define RELIEF_HOST_POINTS_CLUSTER_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"

/* Uniform clusters C_i (before any overlap) with their frames. */
typedef struct relief_pclusters {
    size_t m;            /* clusters */
    uint32_t *label;     /* n: the cluster of each point */
    double *centre;      /* m x 3: centroid y_i */
    double *frame;       /* m x 9: u (right), v (up), n (normal), each a unit 3-vector */
    double *radius;      /* m: distance of the farthest member from y_i */
    double mean_radius;  /* d: the mean of radius */
} relief_pclusters;

/* Cluster n >= 1 points: a binary space partition (Pauly et al. 2002: split
 * through the centroid across the axis of largest variance) until a part
 * holds at most max_size points; then evened out (each point moves to the
 * nearest centroid among its part's own and its 8 nearest parts'); the
 * normal n_i is the mean of the members' normals. Frames: the direction v
 * is carried over the Euclidean minimum spanning tree of the centroids
 * (Prim, from the largest cluster; a new tree from the largest cluster left
 * when a tree cannot grow) by parallel transport: a child's v is its
 * parent's projected onto the child's tangent plane. The root's v is the
 * world axis least aligned with its normal, projected. u = v x n. Chosen
 * over Alexa et al.'s field because it is exact on a plane (every frame the
 * same), turns as little as the surface does along short hops, needs no
 * iteration and is deterministic. RELIEF_E_NOMEM. */
relief_status relief_pclusters_make(const double *pos, const double *nrm, size_t n,
                                    size_t max_size, relief_pclusters *out, relief_error *err);
void relief_pclusters_free(relief_pclusters *c);

/* A uniform bucket grid over points for radius queries. */
typedef struct relief_pbucket {
    const double *pos;   /* the points (not owned) */
    double lo[3];
    double cell;
    size_t dim[3];
    size_t *start;       /* cells + 1 offsets into item */
    uint32_t *item;      /* point indices, by cell, ascending within a cell */
} relief_pbucket;

/* Bucket n points with cells of about `cell` (> 0; enlarged so that there
 * are at most about 2 n cells). RELIEF_E_NOMEM. */
relief_status relief_pbucket_make(const double *pos, size_t n, double cell, relief_pbucket *b,
                                  relief_error *err);
void relief_pbucket_free(relief_pbucket *b);

/* The indices of the points within r of q, cell by cell (a deterministic
 * order), into *buf (grown by realloc; *cap its room). Returns the count, or
 * SIZE_MAX when memory runs out. */
size_t relief_pbucket_query(const relief_pbucket *b, const double q[3], double r, uint32_t **buf,
                            size_t *cap);

/* The cosine below which a point's normal is taken for the other side of
 * a thin shell, not the grid's surface (about 72 degrees). */
#define RELIEF_PGRID_NORMAL_COS 0.3

/* Resampling onto an n x n grid (gn odd) of step h centred at c in the
 * frame f (u, v, n as in relief_pclusters): node (a, b) lies at
 * c + (a - k) h u + (b - k) h v, k = (gn - 1) / 2, node index b gn + a.
 * A node's value is the Gaussian-weighted mean (sigma h / 2) of the
 * candidates whose projection on the tangent plane lies within h of it;
 * candidates are the points within the grid's reach of c whose normals are
 * within 72 degrees of n (a thin shell's other side is left out).
 * For each node: its (point, weight) pairs, weights summing to 1; a node with
 * no point within h takes its nearest candidate (weight 1) and is "empty".
 * Returns, through *empty, the count of empty nodes and, through *foreign,
 * the count of points used that `allowed` (may be NULL) does not flag. */
typedef struct relief_pgrid_weights {
    size_t *start;       /* gn^2 + 1 */
    uint32_t *point;
    float *w;
    size_t cap;          /* room of point */
    double *st;          /* scratch: candidates' tangent coordinates */
    uint32_t *pt;        /* scratch: the candidates kept */
    size_t *fill;        /* scratch: per node */
    size_t w_cap, st_cap, pt_cap, fill_cap;
} relief_pgrid_weights;

/* The reach of a grid: half its diagonal plus h. */
double relief_pgrid_reach(int gn, double h);

/* Fill g (its arrays grown as needed; zero it before the first use) for the
 * grid above from the candidates cand[0..nc-1]. -1 on out of memory, 0 when
 * no candidate at all, else 1. */
int relief_pgrid_weigh(const double *pos, const double *nrm, const uint32_t *cand, size_t nc,
                       const double c[3], const double f[9], int gn, double h,
                       const uint8_t *allowed, relief_pgrid_weights *g, size_t *empty,
                       size_t *foreign);
void relief_pgrid_weights_free(relief_pgrid_weights *g);

/* Tangent coordinates (s along u, t along v) of p about c. */
void relief_ptangent(const double p[3], const double c[3], const double f[9], double *s,
                     double *t);

#endif
