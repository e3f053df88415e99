/* After the growth (issue 61: no crossing where the patch meets the rim):
 * the targets of triangles that cross another drawn back toward the base
 * (mesh/untangle.h). The base is closed and faired (mesh/hole_fill.h) or
 * the primitive; the relief grown on it, copied from samples whose own
 * neighbours differ from the target's, can push a target next to the rim
 * through the capture's triangles there. It reads only the grown mesh, so
 * every backend gives the same bytes. */
#include "complete/engine.h"
#include "mesh/mesh.h"
#include "mesh/untangle.h"

relief_status relief_complete_untangle(relief_complete_run *r, relief_error *err)
{
    relief_surface *s = r->s;
    relief_mesh *m = s->mesh;
    size_t moved, left;
    relief_status st = relief_untangle(m->pos, s->proj, m->nv, s->n_samples, m->tri, m->nt,
                                       &moved, &left, err);
    if (st != RELIEF_OK || !moved)
        return st;
    for (size_t v = s->n_samples; v < m->nv; ++v)
        for (int e = 0; e < 3; ++e)
            s->disp[3 * v + e] = m->pos[3 * v + e] - s->proj[3 * v + e];
    relief_complete_note(r, 0, "%zu target%s drawn back toward the base, where the relief "
                         "grown on %s crossed the surface; %zu completed triangle%s still "
                         "cross%s another", moved, moved == 1 ? "" : "s",
                         moved == 1 ? "it" : "them", left, left == 1 ? "" : "s",
                         left == 1 ? "es" : "");
    return RELIEF_OK;
}
