/* Exact orientation predicates (Shewchuk 1997, "Adaptive precision
 * floating-point arithmetic and fast robust geometric predicates"): the
 * sign of a determinant of double coordinates, taken from the plain
 * floating-point value when it lies outside that value's rounding-error
 * bound, and otherwise from the determinant evaluated exactly with
 * floating-point expansions. Exact for any finite coordinates whose
 * products neither overflow nor underflow (meshes in any unit between
 * about 1e-70 and 1e70). Points are double[3]. */
#ifndef RELIEF_HOST_PREDICATES_H
#define RELIEF_HOST_PREDICATES_H

/* The sign of det[a - d, b - d, c - d]: +1 when d lies below the plane
 * through a, b and c, which then turn counter-clockwise seen from above;
 * -1 above it; 0 when the four points are coplanar. */
int relief_orient3d(const double *a, const double *b, const double *c, const double *d);

/* The sign of det[a - c, b - c] over coordinates i and j of the points
 * (their projection on that coordinate plane, i, j in 0..2): +1 when a, b
 * and c turn counter-clockwise there, -1 clockwise, 0 collinear. */
int relief_orient2d(const double *a, const double *b, const double *c, int i, int j);

#endif
