/* The JSON report of a depth repair, as `relief depth-fill --report`
 * writes it (the command splices in the files only it knows: the mask,
 * the truth): an image's (its size, the parameters used, the pixels per
 * stage, the synthesis, the measures, the times, the backend) and a
 * mesh's (the grid, the six images, the output mesh, the measures against
 * the truth when given). Each returns a malloc'ed string, or NULL when
 * memory runs out. */
#ifndef RELIEF_HOST_DEPTH_FILL_REPORT_H
#define RELIEF_HOST_DEPTH_FILL_REPORT_H

#include "relief/relief.h"
#include "depth/depth_fill.h"
#include "depth/mesh_fill.h"
#include "depth/mesh_patch.h"

/* rep: the public report, filled but for json (backend, device, note,
 * seconds_total); run: the names of the input and output. */
char *relief_depth_fill_json(const relief_run_options *run, int width, int height,
                             const relief_depth_repair_params *p,
                             const relief_depth_repair_report *r,
                             const relief_depth_measures *m,
                             const relief_depth_fill_report *rep);

/* m: NULL without a truth; holes and patch: NULL for the whole solid. */
char *relief_depth_mesh_json(const relief_run_options *run, const relief_mesh_fill_params *p,
                             const relief_mesh_fill_report *r, const relief_mesh_measures *m,
                             const relief_hole_info *holes,
                             const relief_mesh_patch_report *patch,
                             const relief_depth_fill_report *rep);

#endif
