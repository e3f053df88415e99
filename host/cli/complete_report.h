/* The JSON reports of `relief smooth` and `relief complete` (--report),
 * and the --report-dir folder staged around the latter. */
#ifndef RELIEF_HOST_CLI_COMPLETE_REPORT_H
#define RELIEF_HOST_CLI_COMPLETE_REPORT_H

#include <stdio.h>

#include "relief/relief.h"
#include "base/params.h"
#include "grow/grow.h"
#include "grow/hierarchy.h"
#include "mesh/mesh.h"
#include "report/measures.h"
#include "report/pattern.h"
#include "report/report_dir.h"
#include "smooth/surface.h"

typedef struct smooth_report {
    const char *input, *output;
    const relief_params *params;
    const relief_smooth_options *opts;
    const relief_surface *surface;
    double seconds;
} smooth_report;

typedef struct complete_report {
    const char *input, *output;
    const relief_params *params;
    const relief_smooth_options *opts;
    const relief_grow_options *gopts;
    const relief_surface *surface;
    const relief_grow_stats *stats;
    relief_backend backend;              /* the matcher's (the last level's) */
    const char *device;
    double kernel_seconds;               /* in the matcher, all levels */
    const relief_hierarchy_stats *hier;  /* NULL for a mono-scale run */
    const relief_measures *measures; /* NULL when they could not be taken */
    double seconds;
    const char *fallback; /* why auto left OpenCL during the run, or NULL */
    const relief_pattern *pattern; /* NULL when it could not be taken */
    const char *choice; /* why auto chose the backend it started on, or NULL */
} complete_report;

/* relief_atomic_write_text writers; ctx is a smooth_report or a
 * complete_report. */
int cli_write_smooth_report(FILE *f, void *ctx);
int cli_write_complete_report(FILE *f, void *ctx);

/* Build the --report-dir folder beside its final place (report_dir.h). */
relief_status cli_stage_report_dir(const char *dir, complete_report *r,
                                   const relief_mesh *capture, const relief_mesh *smooth,
                                   relief_report_dir **staged, relief_error *err);

#endif
