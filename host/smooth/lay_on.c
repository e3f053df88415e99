/* relief_surface_lay_on (smooth/surface.h): complete's told holes over a
 * primitive that fits (issue 61). */
#include <string.h>

#include "kernels/relief_math.h"
#include "mesh/mesh.h"
#include "smooth/fit.h"
#include "smooth/surface.h"

void relief_surface_lay_on(relief_surface *s, const relief_fit_result *fit)
{
    for (size_t v = 0; v < s->mesh->nv; ++v) {
        double *p = s->proj + 3 * v, *n = s->nrm + 3 * v, *f = s->frame + 9 * v;
        double *x = s->mesh->pos + 3 * v, pn[3];
        /* a sample's relief over the primitive, as the lattice's would be;
         * a target on the primitive, under its patch's place */
        relief_fit_project(&fit->prim, v < s->n_samples ? x : p, p);
        relief_fit_normal(&fit->prim, p, pn);
        /* the base's side: a capture seen from within keeps its normals in */
        if (pn[0] * n[0] + pn[1] * n[1] + pn[2] * n[2] < 0.0)
            pn[0] = -pn[0], pn[1] = -pn[1], pn[2] = -pn[2];
        memcpy(n, pn, sizeof pn);
        if (v >= s->n_samples)
            memcpy(x, p, 3 * sizeof *p);
        for (int k = 0; k < 3; ++k)
            s->disp[3 * v + k] = x[k] - p[k];
        rm_frame_from_normal(n, f, f + 3);
        memcpy(f + 6, n, 3 * sizeof *n);
    }
    s->fit = *fit;
}
