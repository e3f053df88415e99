/* Delaunay triangulations on qhull's reentrant library (libqhull_r): points
 * in a plane, points on a cylinder unrolled into a periodic band, and unit
 * vectors on a sphere (their convex hull).
 *
 * Output. Each function writes a malloc'ed nt x 3 array of vertex indices
 * (indices into the input rows) to *tri and the triangle count to *nt; the
 * caller frees *tri. Outputs are written only on success. Input points that
 * no triangle uses (exact or near duplicates, which qhull keeps as one
 * vertex; for the sphere also points strictly inside the hull) are counted
 * in *unused when `unused` is not NULL.
 *
 * Cocircular points. Qhull merges the triangles of cocircular points (a
 * square of a regular grid) into one convex cell. The planar and periodic
 * functions split each such cell into a fan from its vertex of least input
 * index, so the result is deterministic and, for the periodic band, the same
 * in every copy of the points across the seam.
 *
 * Errors. RELIEF_E_MESH, saying why, for too few points, all collinear
 * (planar, periodic) or coplanar (sphere) points, a non-finite coordinate,
 * a band with no triangle left (periodic), or a qhull precision failure
 * (qhull's own message is quoted; qhull never writes to stderr);
 * RELIEF_E_USAGE for a NULL uv, dirs, tri or nt; RELIEF_E_RANGE for a bad
 * period; RELIEF_E_NOMEM; RELIEF_E_INTERNAL for a qhull internal error.
 *
 * Units. Coordinates are in the caller's units, any scale; arrays are
 * row-major ("n x 2" means n consecutive (u, v) pairs).
 */
#ifndef RELIEF_HOST_DELAUNAY_H
#define RELIEF_HOST_DELAUNAY_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Delaunay triangulation of n points in the plane.
 *   uv      n x 2 coordinates (u, v), finite; n >= 3, not all collinear,
 *           n < 2^31
 *   tri     receives nt x 3 indices into uv, each triangle counter-clockwise
 *           (positive signed area in the (u, v) plane)
 *   nt      receives the triangle count
 *   unused  receives how many points no triangle uses; may be NULL
 * The triangles cover the convex hull of the points. Qhull options
 * "d Qbb Qz": 'Qbb' scales the lifted coordinate for precision, 'Qz' adds a
 * point at infinity, which keeps qhull stable on cocircular input. */
relief_status relief_delaunay_2d(const double *uv, size_t n, uint32_t **tri,
                                 size_t *nt, size_t *unused,
                                 relief_error *err);

/* Delaunay triangulation of n points on a band periodic in u: a cylinder
 * unrolled, u = radius * angle, v = axial coordinate.
 *   uv      n x 2 coordinates (u, v), finite; u is taken modulo `period`,
 *           so any u is accepted; n >= 3, the v not all equal, n < 2^29
 *   period  the period in u, finite and > 0 (2 * pi * radius), in the
 *           units of u
 *   tri     receives nt x 3 indices into uv, each triangle counter-clockwise
 *           in the unrolled (u, v) plane once its u are unwrapped to lie
 *           within half a period of each other (on a cylinder with
 *           u = r * angle and v = z: facing outwards)
 *   nt, err as for relief_delaunay_2d
 *   unused  as for relief_delaunay_2d, plus points whose every triangle
 *           was dropped (see below); may be NULL. A point within 1e-11 of
 *           the band's size (period + height) of an earlier one, in u
 *           (modulo the period) and in v, is a duplicate and left unused:
 *           qhull must keep the same one of the two on both sides of the
 *           seam.
 * Each periodic triangle appears once; a triangle across the seam joins
 * points from both ends of [0, period). The result is an orientable band:
 * every edge is shared by two triangles except along the band's lower and
 * upper rims (and around the triangles dropped below), and it is the
 * Delaunay triangulation of the points with all their copies
 * u + k * period, less those triangles.
 * Method: the points within a margin of the seam are copied one period
 * over, the copies triangulated, and each triangle kept in its one copy
 * with a vertex at its original u and none shifted down by a period. The
 * margin starts at 4 mean spacings and doubles, up to a whole period, until
 * around every original point the triangles close (2 pi; pi on the rims
 * v = min v and v = max v) and no circumcircle of theirs can hold a point
 * that was not copied. With a whole period copied each side, triangles
 * whose circumcircle could still hold one are dropped.
 * Dropped: triangles with an edge spanning half a period or more in u,
 * whose indices could not say which way round the band they go. They arise
 * where there are few points around (under about 3 per period in some
 * stretch of v), and as long slivers along a rim whose points do not all
 * share one v. */
relief_status relief_delaunay_periodic(const double *uv, size_t n,
                                       double period, uint32_t **tri,
                                       size_t *nt, size_t *unused,
                                       relief_error *err);

/* Spherical Delaunay triangulation of n directions: their convex hull.
 *   dirs    n x 3 vectors (x, y, z), finite, unit length or near it (the
 *           hull of the points as given); n >= 4, not all coplanar,
 *           n < 2^31
 *   tri     receives nt x 3 indices into dirs, counter-clockwise seen from
 *           outside the hull (right-handed normal pointing outwards)
 *   nt, unused, err as for relief_delaunay_2d
 * For directions spread over the whole sphere the result is closed: every
 * edge is shared by two triangles. Qhull options "Qt" (coplanar cells,
 * e.g. four points on one circle of the sphere, are split into triangles). */
relief_status relief_hull_sphere(const double *dirs, size_t n, uint32_t **tri,
                                 size_t *nt, size_t *unused,
                                 relief_error *err);

/* Circumradius of the triangle (a, b, c), points given as (u, v), in their
 * units; INFINITY for collinear or coincident points. For callers that
 * filter out long, thin triangles. */
double relief_circumradius_2d(const double a[2], const double b[2],
                              const double c[2]);

#ifdef __cplusplus
}
#endif

#endif
