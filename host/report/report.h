/* JSON reports: what `relief fit --json` prints and what --report writes. */
#ifndef RELIEF_HOST_REPORT_H
#define RELIEF_HOST_REPORT_H

#include "base/json.h"
#include "smooth/fit.h"
#include "smooth/surface.h"

/* The primitive's fields into the current object: model and plane point,
 * normal; sphere center, radius; or cylinder axis_point, axis_dir, radius. */
void relief_report_primitive_fields(relief_json *j, const relief_fit_primitive *p);

/* The fit's fields into the current object: model, rms, rms_all,
 * inlier_fraction, the parameters (plane point, normal; sphere center,
 * radius; cylinder axis_point, axis_dir, radius), n_points, n_inliers,
 * size, poor_fit, poor_fit_limit, model_rms and reason. */
void relief_report_fit_fields(relief_json *j, const relief_fit_result *r);

/* The smooth completion's fields into the current object: fit (object),
 * spacing and where it came from, vertex and triangle counts, the parameter
 * frame, and per-stage seconds. */
void relief_report_surface_fields(relief_json *j, const relief_surface *s);

#endif
