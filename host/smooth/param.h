/* The fitted primitive's parameter domain: where targets are laid, the
 * triangulation is made and spatial frequencies are measured.
 *   plane:    (u, v) along (e1, e2) from the fitted point; e1 x e2 = normal.
 *   cylinder: u = radius * angle in [0, 2 pi radius), the angle measured
 *             from e1 toward e2 = axis x e1; v along the axis from the
 *             fitted axis point. Counter-clockwise in (u, v) faces outward.
 *   sphere:   e1, e2 and e3 = e1 x e2 span the sphere's frame (e3 is the
 *             pole); (u, v) = (longitude * radius, z along e3) is offered
 *             for measures, not for triangulation. */
#ifndef RELIEF_HOST_PARAM_H
#define RELIEF_HOST_PARAM_H

#include "smooth/fit.h"

typedef struct relief_domain {
    relief_fit_primitive prim;
    double e1[3], e2[3];
} relief_domain;

/* The deterministic frame of a primitive: e1 from paper 000's frame rule on
 * the plane's normal or the cylinder's axis (the sphere uses the z axis). */
void relief_domain_init(relief_domain *pm, const relief_fit_primitive *prim);

/* (u, v) of a point (on or near the primitive; input units). */
void relief_domain_coords(const relief_domain *pm, const double p[3], double uv[2]);

/* The point of the primitive at (u, v) (plane and cylinder). */
void relief_domain_point(const relief_domain *pm, double u, double v, double p[3]);

#endif
