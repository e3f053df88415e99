#include "base/vec3.h"
#include "smooth/param.h"

#include <math.h>

#define RM_REAL double
#include "kernels/relief_math.h"


void relief_domain_init(relief_domain *pm, const relief_fit_primitive *prim)
{
    static const double z[3] = {0, 0, 1};
    pm->prim = *prim;
    rm_frame_from_normal(prim->model == RELIEF_FIT_SPHERE ? z : prim->dir, pm->e1, pm->e2);
}

void relief_domain_coords(const relief_domain *pm, const double p[3], double uv[2])
{
    const relief_fit_primitive *pr = &pm->prim;
    double d[3] = {p[0] - pr->point[0], p[1] - pr->point[1], p[2] - pr->point[2]};
    if (pr->model == RELIEF_FIT_PLANE) {
        uv[0] = rm_dot(d, pm->e1);
        uv[1] = rm_dot(d, pm->e2);
        return;
    }
    {
        double a = atan2(rm_dot(d, pm->e2), rm_dot(d, pm->e1)), axis[3];
        if (a < 0.0)
            a += 2.0 * RELIEF_PI;
        uv[0] = pr->radius * a;
        if (uv[0] >= 2.0 * RELIEF_PI * pr->radius)
            uv[0] = 0.0;
        if (pr->model == RELIEF_FIT_CYLINDER) {
            uv[1] = rm_dot(d, pr->dir);
        } else {
            rm_cross(pm->e1, pm->e2, axis);
            uv[1] = rm_dot(d, axis);
        }
    }
}

void relief_domain_point(const relief_domain *pm, double u, double v, double p[3])
{
    const relief_fit_primitive *pr = &pm->prim;
    for (int k = 0; k < 3; ++k) {
        if (pr->model == RELIEF_FIT_PLANE) {
            p[k] = pr->point[k] + u * pm->e1[k] + v * pm->e2[k];
        } else {
            double a = u / pr->radius;
            p[k] = pr->point[k] + v * pr->dir[k] +
                   pr->radius * (cos(a) * pm->e1[k] + sin(a) * pm->e2[k]);
        }
    }
}
