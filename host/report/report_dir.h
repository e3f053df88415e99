/* `relief complete --report-dir DIR`: a folder people can open in a
 * browser. DIR/index.html shows
 * - the report's figures (input, fit, counts, growth, timings, backend,
 *   measures), read from the same structures report.json is written from;
 * - renders (render.h, RELIEF_REPORT_DIR_WIDTH x _HEIGHT pixels) from
 *   three views (the capture's default view; the completed part's, or the
 *   first lowered 45 degrees towards grazing when both parts face the same
 *   way, as a hole in a plane does; the first turned 90 degrees in
 *   azimuth) of five stages: the captured input, the smooth completion
 *   (the surface before growth), the final completion, its completed
 *   vertices highlighted (colour by label), and its displacement from the
 *   primitive (one colour range for all three views); every render of a
 *   view is framed on the final surface, so the stages line up;
 * - histograms of the captured and completed parts (paper 000 figure 13):
 *   the displacement h = relief_fit_distance over RELIEF_MEASURE_HIST_BINS
 *   bins of [min h, max h], and with colour R, G and B over the same
 *   number of bins of [0, 1], each normalised to sum 1, as SVG files with
 *   their total-variation distance (the measures' definition);
 * - report.json, written by the caller's writer.
 *
 * - RELIEF_REPORT_DIR_MARKER, relief's mark that it wrote the folder.
 *
 * Whole or not at all, like every relief output (base/output.h): the
 * folder is built beside DIR and moved into place by
 * relief_report_dir_commit (or with other outputs), so a failed run leaves
 * no partial report. An existing DIR is replaced only when it is empty, or
 * carries the marker and holds nothing but files a report writes
 * (index.html, report.json, *.png, *.svg): relief replaces only what it
 * wrote. Otherwise it refuses (RELIEF_REASON_NOT_RELIEFS), naming why. */
#ifndef RELIEF_HOST_REPORT_DIR_H
#define RELIEF_HOST_REPORT_DIR_H

#include <stdio.h>

#include "relief/relief.h"
#include "base/output.h"
#include "base/params.h"
#include "grow/grow.h"
#include "report/measures.h"
#include "smooth/fit.h"
#include "smooth/surface.h"

/* The marker file in every report folder relief writes. */
#define RELIEF_REPORT_DIR_MARKER ".relief-report"

#define RELIEF_REPORT_DIR_WIDTH 640
#define RELIEF_REPORT_DIR_HEIGHT 480

/* What the report shows. Meshes are read only. */
typedef struct relief_report_content {
    const char *input, *output;     /* paths, as given */
    const relief_mesh *capture;     /* the input as read */
    const relief_mesh *smooth;      /* the surface before growth */
    const relief_surface *surface;  /* after growth: the final mesh, fit,
                                       counts and stage timings */
    const relief_params *params;
    const relief_grow_stats *stats;
    const relief_measures *measures; /* NULL when they could not be taken */
    const char *backend, *device;
    double seconds_total;
    int (*write_json)(FILE *f, void *ctx); /* writes report.json; 0 = success */
    void *json_ctx;
} relief_report_content;

typedef struct relief_report_dir relief_report_dir;

/* Can DIR be written (its parent folder exists and DIR is absent, empty or
 * a previous report)? Called before the long work so that a bad path
 * fails at once. RELIEF_E_IO naming what is wrong. */
relief_status relief_report_dir_check(const char *dir, relief_error *err);

/* Build the report in a temporary folder beside `dir`; *out receives it.
 * On failure nothing is left behind. Errors: RELIEF_E_IO, RELIEF_E_NOMEM,
 * and those of relief_render and relief_png_write. */
relief_status relief_report_dir_stage(const char *dir, const relief_report_content *c,
                                      relief_report_dir **out, relief_error *err);

/* Move the staged folder into place (replacing a previous report, see
 * above) and free `r`. On failure the staged folder is removed. */
relief_status relief_report_dir_commit(relief_report_dir *r, relief_error *err);

/* Remove the staged folder and free `r` (NULL accepted). */
void relief_report_dir_abort(relief_report_dir *r);

/* The staged folder, for a commit with other outputs (base/output.h);
 * `r` is freed. */
relief_staged_folder *relief_report_dir_release(relief_report_dir *r);

/* May the report folder at `path`, which is there, be replaced (above)?
 * 1, or 0 with err set: the check a commit makes. */
int relief_report_dir_replaceable(const char *path, relief_error *err);

#endif
