/* relief: the command-line tool. One executable, one function per
 * subcommand, getopt_long options, exit codes 0 (success), 1 (bad input or
 * usage), 2 (internal or device failure). Each subcommand sets optind = 0,
 * which makes GNU getopt forget all state from an earlier parse (a pointer
 * into the previous argv among it), so relief_cli_main can run many times in
 * one process (tests/fuzz/fuzz_cli.c). */
#include <errno.h>
#include <getopt.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "relief/relief.h"
#include "base/atomic.h"
#include "base/clock.h"
#include "base/error.h"
#include "base/json.h"
#include "base/memlimit.h"
#include "cli/cli.h"
#include "grow/checkpoint.h"
#include "grow/grow.h"
#include "grow/hierarchy.h"
#include "match/matcher.h"
#include "mesh/mesh.h"
#include "report/measures.h"
#include "report/png.h"
#include "report/render.h"
#include "report/report.h"
#include "report/report_dir.h"
#include "smooth/fit.h"
#include "smooth/oversample.h"
#include "smooth/surface.h"

#define EXIT_USAGE 1
#define EXIT_INTERNAL 2

/* ------------------------------------------------------------ helpers */

static int fail_status(const char *cmd, const relief_error *err)
{
    fprintf(stderr, "relief %s: error: %s\n", cmd,
            err->message[0] ? err->message : relief_strerror(err->status));
    return relief_status_exit_code(err->status);
}

static int usage_error(const char *cmd, const char *fmt, const char *arg)
{
    fprintf(stderr, "relief %s: ", cmd);
    fprintf(stderr, fmt, arg);
    fprintf(stderr, "\nTry 'relief %s --help'.\n", cmd);
    return EXIT_USAGE;
}

static int parse_int(const char *cmd, const char *opt, const char *s, long lo, long hi,
                     long *out)
{
    char *end;
    long v;
    errno = 0;
    v = strtol(s, &end, 10);
    if (end == s || *end != '\0' || errno != 0) {
        fprintf(stderr, "relief %s: %s: '%s' is not an integer\n", cmd, opt, s);
        return 0;
    }
    if (v < lo || v > hi) {
        fprintf(stderr, "relief %s: %s: %ld is out of range: expected %ld..%ld\n", cmd,
                opt, v, lo, hi);
        return 0;
    }
    *out = v;
    return 1;
}

static int parse_real(const char *cmd, const char *opt, const char *s, double *out)
{
    char *end;
    double v;
    errno = 0;
    v = strtod(s, &end);
    if (end == s || *end != '\0' || errno != 0 || !isfinite(v)) {
        fprintf(stderr, "relief %s: %s: '%s' is not a finite number\n", cmd, opt, s);
        return 0;
    }
    *out = v;
    return 1;
}

/* Comma-separated reals: "z0,z1" or "u0,v0,u1,v1". */
static int parse_extent(const char *cmd, const char *s, relief_params *p)
{
    char buf[256], *tok, *save = NULL;
    int n = 0;
    snprintf(buf, sizeof buf, "%s", s);
    for (tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        if (n == 4) {
            fprintf(stderr, "relief %s: --extent: more than 4 values in '%s'\n", cmd, s);
            return 0;
        }
        if (!parse_real(cmd, "--extent", tok, &p->extent[n]))
            return 0;
        ++n;
    }
    if (n != 2 && n != 4) {
        fprintf(stderr,
                "relief %s: --extent: expected z0,z1 (cylinder) or u0,v0,u1,v1 "
                "(plane), got '%s'\n",
                cmd, s);
        return 0;
    }
    p->has_extent = 1;
    p->n_extent = n;
    return 1;
}

/* Is `out` the same file as `in` (by name or by inode)? */
static int same_file(const char *in, const char *out)
{
    struct stat a, b;
    if (strcmp(in, out) == 0)
        return 1;
    if (stat(in, &a) != 0 || stat(out, &b) != 0)
        return 0;
    return a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}

static const char *ext_of(const char *path)
{
    const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
    return dot && (!slash || dot > slash) ? dot : "";
}

static int known_ext(const char *path)
{
    const char *e = ext_of(path);
    return strcasecmp(e, ".ply") == 0 || strcasecmp(e, ".obj") == 0 ||
           strcasecmp(e, ".off") == 0 || strcasecmp(e, ".stl") == 0;
}

/* ------------------------------------------------ complete and smooth */

enum {
    OPT_REPORT = 256, OPT_FIT, OPT_WINDOW, OPT_ROTATIONS, OPT_ERROR, OPT_MU, OPT_SEED,
    OPT_LEVELS, OPT_BACKEND, OPT_DEVICE, OPT_OVERSAMPLE, OPT_SPACING, OPT_EXTENT,
    OPT_QUIET, OPT_ASCII, OPT_TRUTH, OPT_VERTICES, OPT_COLOUR, OPT_NOISE, OPT_JSON,
    OPT_FRAMES, OPT_OVERSAMPLE_SCHEME, OPT_BOOTSTRAP, OPT_NO_PRUNE, OPT_HELP,
    OPT_CHECKPOINT, OPT_RESUME, OPT_CHECKPOINT_EVERY, OPT_MAX_MEMORY,
    OPT_REPORT_DIR, OPT_VIEW, OPT_SIZE, OPT_COLOUR_BY
};

static const char complete_help[] =
    "usage: relief complete IN -o OUT [options]\n"
    "\n"
    "Fit a primitive to the partial capture IN, lay the missing part on it, and\n"
    "grow the capture's relief and colour over it. Writes OUT (PLY with a\n"
    "per-vertex `label`: 0 captured, 1 completed).\n"
    "\n"
    "  -o, --output OUT      completed mesh (.ply, .obj, .off, .stl); required\n"
    "  --report R.json       write a JSON report of the run\n"
    "  --report-dir DIR      write report.json, renders, histograms and index.html\n"
    "                        (open it in a browser) into the folder DIR\n"
    "  --fit MODEL           auto|plane|sphere|cylinder (default auto)\n"
    "  --window W            neighbourhood radius in edge hops, 1..16 (default 3)\n"
    "  --rotations R         rotations tried per sample, 1..64 (default 4)\n"
    "  --error E             acceptance threshold e > 0 (default 0.1)\n"
    "  --mu MU               shape weight 0..1 (default 1 without colour, 0.5 with)\n"
    "  --seed N              random seed (default 1)\n"
    "  --levels M            hierarchy levels 1..8 (default 1: mono-scale)\n"
    "  --backend B           auto|scalar|opencl (default auto)\n"
    "  --device N            OpenCL device index (see 'relief devices')\n"
    "  --oversample N        oversampling passes of the capture, 0..4 (default 1)\n"
    "  --oversample-scheme S butterfly (default: new samples on the smooth\n"
    "                        surface through the capture) or midpoint (the\n"
    "                        papers' coplanar edge midpoints)\n"
    "  --spacing S           target vertex spacing (default: from the capture)\n"
    "  --extent A,B[,C,D]    cylinder z0,z1 or plane u0,v0,u1,v1 to complete\n"
    "  --frames RULE         local frames: paper (000's rule, default) or primitive\n"
    "  --max-memory SIZE     host memory limit, e.g. 512M, 4G (default: 80% of\n"
    "                        physical memory); a larger run is refused up front\n"
    "  --bootstrap           completed targets become matchable too\n"
    "  --no-prune            score every candidate in full (the paper's exhaustive\n"
    "                        search; same result, slower)\n"
    "  --checkpoint FILE     save the growth's state to FILE on SIGINT (Ctrl-C), on a\n"
    "                        device failure and every --checkpoint-every seconds;\n"
    "                        removed when the run completes\n"
    "  --checkpoint-every S  seconds between saves, 0 = only on SIGINT or failure\n"
    "                        (default 300)\n"
    "  --resume FILE         continue a run saved by --checkpoint (same input and\n"
    "                        parameters; any backend): same output as a run never\n"
    "                        interrupted\n"
    "  --ascii               write ascii PLY (default binary)\n"
    "  --quiet               no progress output\n"
    "  -h, --help            this help\n"
    "\n"
    "SIGINT stops the growth between two targets, saves the checkpoint when one\n"
    "is asked for, writes no output and exits 130; a second SIGINT kills at once.\n";

static const char smooth_help[] =
    "usage: relief smooth IN -o OUT [options]\n"
    "\n"
    "Fit a primitive to the partial capture IN and complete it smoothly (no\n"
    "relief yet): the capture's samples and target vertices laid on the\n"
    "primitive over the missing region, in one manifold triangulation. OUT's\n"
    "per-vertex `label` is 0 for samples and 1 for targets.\n"
    "\n"
    "Region: cylinder, the full turn over the capture's axial extent; sphere,\n"
    "the whole sphere; plane, the holes inside the capture's outline.\n"
    "Target spacing: the 10th percentile of the capture's edge lengths (a\n"
    "robust minimum: real scans have slivers), or --spacing.\n"
    "\n"
    "  -o, --output OUT      output mesh; required\n"
    "  --report R.json       write a JSON report (fit, spacing, counts, frame,\n"
    "                        seconds per stage)\n"
    "  --fit MODEL           auto|plane|sphere|cylinder (default auto)\n"
    "  --oversample N        1-to-4 subdivisions of the capture, 0..4 (default 1)\n"
    "  --oversample-scheme S butterfly (default) or midpoint (the papers')\n"
    "  --spacing S           target vertex spacing in the input's units\n"
    "  --extent A,B[,C,D]    cylinder: z0,z1 along the fitted axis from its axis\n"
    "                        point; plane: u0,v0,u1,v1 in the plane's (e1, e2)\n"
    "                        frame from its fitted point (both in the report)\n"
    "  --frames RULE         local frames: paper (000's rule, default) or primitive\n"
    "  --max-memory SIZE     host memory limit, e.g. 512M, 4G (default: 80% of\n"
    "                        physical memory); a larger run is refused up front\n"
    "  --ascii               write ascii PLY (default binary)\n"
    "  --quiet               no progress output\n"
    "  -h, --help            this help\n";

static int parse_fit(const char *cmd, const char *s, relief_fit_model *out)
{
    static const relief_fit_model models[] = {RELIEF_FIT_AUTO, RELIEF_FIT_PLANE,
                                              RELIEF_FIT_SPHERE, RELIEF_FIT_CYLINDER};
    for (size_t i = 0; i < 4; ++i)
        if (strcmp(s, relief_fit_model_name(models[i])) == 0) {
            *out = models[i];
            return 1;
        }
    fprintf(stderr, "relief %s: --fit: '%s' is not one of auto, plane, sphere, cylinder\n",
            cmd, s);
    return 0;
}

typedef struct smooth_report {
    const char *input, *output;
    const relief_params *params;
    const relief_smooth_options *opts;
    const relief_surface *surface;
    double seconds;
} smooth_report;

static void report_params(relief_json *j, const relief_params *p,
                          const relief_smooth_options *o)
{
    rj_begin_object(j, "parameters");
    rj_string(j, "fit", relief_fit_model_name(p->fit));
    rj_int(j, "oversample", p->oversample);
    rj_string(j, "oversample_scheme", relief_oversample_scheme_name(o->oversample_scheme));
    if (p->spacing > 0.0)
        rj_number(j, "spacing", p->spacing);
    else
        rj_null(j, "spacing");
    rj_number(j, "spacing_percentile", o->spacing_percentile);
    rj_string(j, "frames", o->frames == RELIEF_FRAMES_PAPER ? "paper" : "primitive");
    if (p->has_extent) {
        rj_begin_array(j, "extent");
        for (int i = 0; i < p->n_extent; ++i)
            rj_number(j, NULL, p->extent[i]);
        rj_end_array(j);
    }
    rj_end_object(j);
}

static int write_smooth_report(FILE *f, void *ctx)
{
    const smooth_report *r = ctx;
    relief_json j;
    rj_init(&j, f);
    rj_begin_object(&j, NULL);
    rj_string(&j, "relief_version", RELIEF_VERSION_STRING);
    rj_string(&j, "command", "smooth");
    rj_string(&j, "input", r->input);
    rj_string(&j, "output", r->output);
    report_params(&j, r->params, r->opts);
    relief_report_surface_fields(&j, r->surface);
    rj_number(&j, "seconds_total", r->seconds);
    rj_end_object(&j);
    return 0;
}

/* Outputs appear whole or not at all even on Ctrl-C or SIGTERM: both are
 * held back while the files are written (temporary names, then renames)
 * and delivered once every file is in place or removed. The test hook
 * RELIEF_TEST_SIGINT_IN_WRITE raises SIGINT just as the writing starts. */
static void hold_signals(sigset_t *old)
{
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    sigprocmask(SIG_BLOCK, &set, old);
    if (getenv("RELIEF_TEST_SIGINT_IN_WRITE"))
        raise(SIGINT); /* pending until release_signals */
}

static void release_signals(const sigset_t *old)
{
    sigprocmask(SIG_SETMASK, old, NULL);
}

static int run_smooth(const char *in_path, relief_mesh *in, const char *out,
                      const char *report, const relief_params *p,
                      const relief_smooth_options *o, int ascii, int quiet)
{
    relief_error err = {RELIEF_OK, ""};
    relief_write_options wo = {ascii};
    relief_surface *s = NULL;
    double t0 = relief_seconds();
    relief_status st = relief_smooth(in, p, o, &s, &err);
    sigset_t held;
    relief_mesh_destroy(in);
    if (st != RELIEF_OK)
        return fail_status("smooth", &err);
    hold_signals(&held);
    if (report) {
        smooth_report r = {in_path, out, p, o, s, relief_seconds() - t0};
        st = relief_atomic_write_text(report, write_smooth_report, &r, &err);
    }
    if (st == RELIEF_OK) {
        st = relief_mesh_write(s->mesh, out, &wo, &err);
        if (st != RELIEF_OK && report)
            remove(report); /* both outputs or neither */
    }
    release_signals(&held);
    if (st == RELIEF_OK && !quiet) {
        const relief_fit_primitive *pr = &s->fit.prim;
        fprintf(stderr,
                "relief smooth: %s (rms %.3g%s%.4g), spacing %.4g (%s): %zu samples + "
                "%zu targets, %zu triangles -> %s\n",
                relief_fit_model_name(pr->model), s->fit.rms,
                pr->model == RELIEF_FIT_PLANE ? "" : ", radius ",
                pr->model == RELIEF_FIT_PLANE ? 0.0 : pr->radius, s->spacing,
                s->spacing_from_capture ? "from the capture" : "--spacing", s->n_samples,
                s->n_targets, relief_mesh_triangle_count(s->mesh), out);
        if (report)
            fprintf(stderr, "relief smooth: report: %s\n", report);
    }
    relief_surface_destroy(s);
    return st == RELIEF_OK ? 0 : fail_status("smooth", &err);
}

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
} complete_report;

/* Per level of a hierarchical run: sizes, sample pyramids, growth. */
static void report_levels(relief_json *j, const relief_hierarchy_stats *hs)
{
    rj_number(j, "hierarchy_build_seconds", hs->build_seconds);
    rj_begin_array(j, "levels");
    for (int k = 0; k < hs->levels; ++k) {
        const relief_level_stats *l = &hs->level[k];
        rj_begin_object(j, NULL);
        rj_int(j, "level", k + 1);
        rj_int(j, "vertices", (long long)l->vertices);
        rj_int(j, "samples", (long long)l->samples);
        rj_int(j, "targets", (long long)l->targets);
        rj_int(j, "pyramid_boxes", (long long)l->boxes);
        rj_number(j, "pyramid_box_samples_mean", l->box_samples);
        rj_int(j, "restricted_matches", (long long)l->grow.pyramid_hits);
        rj_int(j, "fallbacks_nothing_passed", (long long)l->grow.pyramid_misses);
        rj_int(j, "fallbacks_no_box", (long long)l->grow.pyramid_empty);
        rj_int(j, "candidates_scored", (long long)l->grow.candidates);
        rj_int(j, "acceptances", (long long)l->grow.acceptances);
        rj_int(j, "rejections", (long long)l->grow.rejections);
        rj_int(j, "threshold_raises", (long long)l->grow.threshold_raises);
        rj_number(j, "error_final", l->grow.error_final);
        rj_number(j, "seconds", l->seconds);
        rj_end_object(j);
    }
    rj_end_array(j);
}

static int write_complete_report(FILE *f, void *ctx)
{
    const complete_report *r = ctx;
    const relief_grow_stats *g = r->stats;
    relief_json j;
    rj_init(&j, f);
    rj_begin_object(&j, NULL);
    rj_string(&j, "relief_version", RELIEF_VERSION_STRING);
    rj_string(&j, "command", "complete");
    rj_string(&j, "input", r->input);
    rj_string(&j, "output", r->output);
    report_params(&j, r->params, r->opts);
    rj_begin_object(&j, "growth_parameters");
    rj_int(&j, "window", r->params->window);
    rj_int(&j, "rotations", r->params->rotations);
    rj_number(&j, "error", r->params->error);
    rj_number(&j, "mu", g->mu);
    rj_int(&j, "seed", (long long)r->params->seed);
    rj_int(&j, "levels", r->params->levels);
    rj_bool(&j, "prune", r->gopts->prune);
    rj_bool(&j, "bootstrap", r->gopts->bootstrap);
    rj_end_object(&j);
    relief_report_surface_fields(&j, r->surface);
    rj_begin_object(&j, "growth");
    rj_int(&j, "targets", (long long)g->targets);
    rj_int(&j, "passes", (long long)g->passes);
    rj_int(&j, "candidates_scored", (long long)g->candidates);
    rj_int(&j, "pruned", (long long)g->pruned);
    rj_int(&j, "invalid", (long long)g->invalid);
    rj_int(&j, "acceptances", (long long)g->acceptances);
    rj_int(&j, "rejections", (long long)g->rejections);
    rj_int(&j, "no_valid_candidate", (long long)g->no_candidate);
    rj_int(&j, "threshold_raises", (long long)g->threshold_raises);
    rj_int(&j, "window_shrinks", (long long)g->window_shrinks);
    rj_number(&j, "error_final", g->error_final);
    rj_number(&j, "b_shape", g->b_shape);
    rj_number(&j, "seconds", g->seconds);
    rj_number(&j, "match_seconds", g->match_seconds);
    rj_end_object(&j);
    if (r->hier)
        report_levels(&j, r->hier);
    if (r->measures) {
        rj_begin_object(&j, "measures");
        relief_report_measures_fields(&j, r->measures);
        rj_end_object(&j);
    }
    rj_begin_object(&j, "backend");
    rj_string(&j, "name", relief_backend_name(r->backend));
    rj_string(&j, "requested", relief_backend_name(r->params->backend));
    rj_string(&j, "device", r->device);
    rj_number(&j, "kernel_seconds", r->kernel_seconds);
    if (r->fallback && r->fallback[0])
        rj_string(&j, "fallback", r->fallback);
    rj_end_object(&j);
    rj_number(&j, "seconds_total", r->seconds);
    rj_end_object(&j);
    return 0;
}

/* A copy of `m` (all its vertices and triangles). */
static relief_status copy_mesh(const relief_mesh *m, relief_mesh **out, relief_error *err)
{
    uint8_t *keep = malloc(relief_mesh_vertex_count(m) ? relief_mesh_vertex_count(m) : 1);
    relief_status st;
    if (!keep)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot copy a mesh of %zu vertices",
                           relief_mesh_vertex_count(m));
    memset(keep, 1, relief_mesh_vertex_count(m));
    st = relief_mesh_subset(m, keep, out, NULL, err);
    free(keep);
    return st;
}

/* Build the --report-dir folder beside its final place (report_dir.h). */
static relief_status stage_report_dir(const char *dir, complete_report *r,
                                      const relief_mesh *capture, const relief_mesh *smooth,
                                      relief_report_dir **staged, relief_error *err)
{
    relief_report_content c;
    memset(&c, 0, sizeof c);
    c.input = r->input;
    c.output = r->output;
    c.capture = capture;
    c.smooth = smooth;
    c.surface = r->surface;
    c.params = r->params;
    c.stats = r->stats;
    c.measures = r->measures;
    c.backend = relief_backend_name(r->backend);
    c.device = r->device;
    c.seconds_total = r->seconds;
    c.write_json = write_complete_report;
    c.json_ctx = r;
    return relief_report_dir_stage(dir, &c, staged, err);
}

/* "123/456 targets, e 0.1, 52/s, ETA 6 s" on one rewritten stderr line. */
static void print_progress(void *ctx, const relief_grow_progress *p)
{
    double *last = ctx, rate = p->seconds > 0 ? (double)p->done / p->seconds : 0.0;
    if (p->done != p->total && p->seconds - *last < 0.25)
        return;
    *last = p->seconds;
    fprintf(stderr, "\rrelief complete: %zu/%zu targets, e %.3g, %.1f/s, ETA %.0f s   ",
            p->done, p->total, p->error, rate,
            rate > 0 ? (double)(p->total - p->done) / rate : 0.0);
    if (p->done == p->total)
        fputc('\n', stderr);
}

/* SIGINT: set by the handler, read by the growth between two targets. The
 * one piece of global state in relief: a signal handler can reach nothing
 * else (C11 7.14.1.1: a volatile sig_atomic_t static is all it may write). */
static volatile sig_atomic_t interrupted = 0;

static void on_sigint(int sig)
{
    (void)sig;
    interrupted = 1;
}

/* --checkpoint, --resume and the test hook of the CLI test. */
typedef struct run_control {
    const char *checkpoint; /* FILE or NULL */
    double checkpoint_every; /* seconds; 0: only on SIGINT or a failure */
    const char *resume;     /* FILE or NULL */
} run_control;

typedef struct saver {
    const char *path;
    const relief_checkpoint_key *key;
} saver;

static relief_status save_checkpoint(void *ctx, const relief_grow_state *g, relief_error *err)
{
    const saver *sv = ctx;
    return relief_checkpoint_write(sv->path, sv->key, g, err);
}

/* Progress line, and the test hook: RELIEF_TEST_SIGINT_AFTER=N raises SIGINT
 * once N targets have been accepted in this run, so that the CLI test
 * interrupts at a known point. */
typedef struct progress_hook {
    double last;
    int print;
    size_t sigint_after, seen;
} progress_hook;

static void on_progress(void *ctx, const relief_grow_progress *p)
{
    progress_hook *h = ctx;
    if (h->print)
        print_progress(&h->last, p);
    if (h->sigint_after && ++h->seen == h->sigint_after)
        raise(SIGINT);
}

/* Test hook: RELIEF_TEST_DEVICE_FAIL_AFTER=N makes every OpenCL score after
 * the first N fail as an exhausted device would, so that the CLI test sees
 * auto continue on the scalar matcher and an explicit --backend opencl exit
 * 2 with its checkpoint saved. */
typedef struct device_failure {
    size_t after, calls;
} device_failure;

static relief_status inject_device_failure(void *ctx, relief_error *err)
{
    device_failure *f = ctx;
    if (f->calls++ < f->after)
        return RELIEF_OK;
    return relief_fail(err, RELIEF_E_DEVICE, "launching the score kernel: CL_OUT_OF_RESOURCES "
                       "(injected by RELIEF_TEST_DEVICE_FAIL_AFTER=%zu)", f->after);
}

/* Refuse a growth that cannot fit before its match data and state exist. */
static relief_status check_growth_memory(const relief_surface *s, const relief_params *p,
                                         relief_error *err)
{
    const size_t nv = relief_mesh_vertex_count(s->mesh);
    const size_t nt = relief_mesh_triangle_count(s->mesh);
    char what[160];
    snprintf(what, sizeof what, "the growth over %zu vertices (%zu samples x %d rotations)",
             nv, s->n_samples, p->rotations);
    return relief_memory_check(what, relief_estimate_growth(nv, nt, s->n_samples, p->rotations),
                               relief_memory_limit(p),
                               "; raise --spacing or lower --rotations", err);
}

static int run_complete(const char *in_path, relief_mesh *in, const char *out,
                        const char *report, const char *report_dir, const relief_params *p,
                        const relief_smooth_options *o, relief_grow_options *go, int ascii,
                        int quiet, const run_control *rc)
{
    relief_error err = {RELIEF_OK, ""};
    relief_write_options wo = {ascii};
    relief_surface *s = NULL;
    relief_match_data *d = NULL;
    relief_matcher *m = NULL;
    relief_grow_stats stats;
    double t0 = relief_seconds();
    relief_status st;
    relief_checkpoint_key key;
    relief_checkpoint *ck = NULL;
    relief_mesh *smooth_mesh = NULL; /* before growth, for --report-dir */
    relief_report_dir *staged = NULL;
    relief_hierarchy *hier = NULL;      /* --levels > 1 */
    relief_hierarchy_stats hstats;
    relief_backend used_backend = RELIEF_BACKEND_SCALAR;
    char used_device[256] = "";
    saver sv = {rc->checkpoint, &key};
    progress_hook hook = {-1.0, !quiet && isatty(2), 0, 0};
    const char *hook_env = getenv("RELIEF_TEST_SIGINT_AFTER");
    const char *fail_env = getenv("RELIEF_TEST_DEVICE_FAIL_AFTER");
    device_failure fail_hook = {0, 0};
    struct sigaction sa, old_sa;
    sigset_t held;

    memset(&stats, 0, sizeof stats);
    memset(&hstats, 0, sizeof hstats);
    /* A first SIGINT stops the growth cleanly; SA_RESETHAND lets a second
     * one kill the process as usual. */
    interrupted = 0;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_sigint;
    sa.sa_flags = SA_RESETHAND;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &old_sa);
    go->cancel = &interrupted;
    if (hook_env)
        hook.sigint_after = strtoul(hook_env, NULL, 10);
    relief_checkpoint_key_make(in, p, o, go, &key);
    if (rc->resume) {
        st = relief_checkpoint_read(rc->resume, &key, &ck, &err);
        if (st != RELIEF_OK) {
            relief_mesh_destroy(in);
            sigaction(SIGINT, &old_sa, NULL);
            return fail_status("complete", &err);
        }
        go->resume = relief_checkpoint_state(ck);
    }
    if (rc->checkpoint) {
        go->save = save_checkpoint;
        go->save_ctx = &sv;
        go->save_every = rc->checkpoint_every;
    }
    st = relief_smooth(in, p, o, &s, &err);
    if (st == RELIEF_OK)
        st = check_growth_memory(s, p, &err);
    if (st == RELIEF_OK && p->levels > 1) {
        double th = relief_seconds();
        st = relief_hierarchy_build(s, p->levels, &hier, &err);
        hstats.build_seconds = relief_seconds() - th;
    } else if (st == RELIEF_OK)
        st = relief_match_data_build(s, p->rotations,
                                     relief_grow_mu(p, relief_mesh_colours(in) != NULL), &d,
                                     &err);
    if (!report_dir) { /* else the report renders the capture */
        relief_mesh_destroy(in);
        in = NULL;
    }
    if (st == RELIEF_OK && !hier) {
        char note[RELIEF_ERROR_MESSAGE_MAX + 64];
        st = relief_matcher_create(p->backend, p->device, d, &m, note, sizeof note, &err);
        if (st == RELIEF_OK && note[0])
            fprintf(stderr, "relief complete: backend auto: %s\n", note);
        else if (st == RELIEF_OK && !quiet)
            fprintf(stderr, "relief complete: backend %s: %s\n",
                    relief_backend_name(m->backend), m->device);
        if (st == RELIEF_OK && fail_env && m->backend == RELIEF_BACKEND_OPENCL) {
            fail_hook.after = strtoul(fail_env, NULL, 10);
            m->inject = inject_device_failure;
            m->inject_ctx = &fail_hook;
        }
    }
    if (st == RELIEF_OK && !quiet)
        fprintf(stderr, "relief complete: %s fit, spacing %.4g: %zu samples, %zu targets; "
                "W %d, R %d, e %g, mu %g\n",
                relief_fit_model_name(s->fit.prim.model), s->spacing, s->n_samples,
                s->n_targets, p->window, p->rotations, p->error,
                relief_grow_mu(p, relief_mesh_colours(s->mesh) != NULL));
    if (st == RELIEF_OK && hier && !quiet) {
        fprintf(stderr, "relief complete: %d levels of", p->levels);
        for (int k = 0; k < p->levels; ++k)
            fprintf(stderr, " %zu%s", relief_mesh_vertex_count(hier->level[k]->mesh),
                    k + 1 < p->levels ? "," : "");
        fprintf(stderr, " vertices (%.2f s)\n", hstats.build_seconds);
    }
    /* The report shows the surface before growth, which relief_grow changes
     * in place. */
    if (st == RELIEF_OK && report_dir)
        st = copy_mesh(s->mesh, &smooth_mesh, &err);
    if (st == RELIEF_OK) {
        if (hook.print || hook.sigint_after) {
            go->progress = on_progress;
            go->progress_ctx = &hook;
        }
        if (go->resume && !quiet && go->resume->hier)
            fprintf(stderr, "relief complete: resuming from %s: level %d of %d, %zu of %zu "
                    "targets done\n", rc->resume, go->resume->hier->level,
                    go->resume->hier->levels, go->resume->stats.acceptances,
                    go->resume->stats.targets);
        else if (go->resume && !quiet)
            fprintf(stderr, "relief complete: resuming from %s: %zu of %zu targets done\n",
                    rc->resume, go->resume->stats.acceptances, go->resume->stats.targets);
        if (hier) {
            relief_hierarchy_options ho = relief_hierarchy_options_default();
            relief_hierarchy_stats hs;
            char note[RELIEF_ERROR_MESSAGE_MAX + 64];
            ho.backend = p->backend;
            ho.device = p->device;
            st = relief_hierarchy_grow(hier, s, p, go, &ho, &hs, &stats, &used_backend,
                                       used_device, sizeof used_device, note, sizeof note,
                                       &err);
            hs.build_seconds = hstats.build_seconds;
            hstats = hs;
            if (note[0])
                fprintf(stderr, "relief complete: backend auto: %s\n", note);
            else if (st == RELIEF_OK && !quiet)
                fprintf(stderr, "relief complete: backend %s: %s\n",
                        relief_backend_name(used_backend), used_device);
        } else {
            st = relief_grow(s, d, m, p, go, &stats, &err);
            if (m->fallback_note[0])
                fprintf(stderr, "relief complete: backend auto: %s\n", m->fallback_note);
        }
        if (hook.print && st != RELIEF_OK)
            fputc('\n', stderr); /* end the progress line */
        if (st != RELIEF_OK && rc->checkpoint && stats.acceptances > 0 &&
            (st == RELIEF_E_CANCELLED || st == RELIEF_E_DEVICE))
            fprintf(stderr, "relief complete: state saved to %s; continue with the same "
                    "command and --resume %s\n", rc->checkpoint, rc->checkpoint);
    }
    hold_signals(&held);
    if (st == RELIEF_OK && (report || report_dir)) {
        relief_measures meas;
        relief_error merr = {RELIEF_OK, ""};
        int have = relief_measure(s->mesh, NULL, &s->fit.prim, &meas, &merr) == RELIEF_OK;
        complete_report r = {in_path, out, p, o, go, s, &stats,
                             m ? m->backend : used_backend, m ? m->device : used_device,
                             m ? m->kernel_seconds : stats.match_seconds,
                             hier ? &hstats : NULL, have ? &meas : NULL,
                             relief_seconds() - t0, m ? m->fallback_note : NULL};
        if (!have && !quiet)
            fprintf(stderr, "relief complete: warning: no measures in the report: %s\n",
                    merr.message);
        if (report)
            st = relief_atomic_write_text(report, write_complete_report, &r, &err);
        if (st == RELIEF_OK && report_dir)
            st = stage_report_dir(report_dir, &r, in, smooth_mesh, &staged, &err);
        if (st != RELIEF_OK && report)
            remove(report);
    }
    if (st == RELIEF_OK) {
        st = relief_mesh_write(s->mesh, out, &wo, &err);
        if (st != RELIEF_OK && report)
            remove(report);
    }
    /* The folder goes into place last: all outputs or none. */
    if (st == RELIEF_OK && staged) {
        st = relief_report_dir_commit(staged, &err);
        staged = NULL;
        if (st != RELIEF_OK) {
            remove(out);
            if (report)
                remove(report);
        }
    }
    relief_report_dir_abort(staged);
    release_signals(&held);
    if (st == RELIEF_OK && !quiet) {
        fprintf(stderr, "relief complete: %zu targets textured in %zu passes (%zu rejections, "
                "%zu threshold raises, final e %.3g) in %.2f s -> %s\n",
                stats.acceptances, stats.passes, stats.rejections, stats.threshold_raises,
                stats.error_final, stats.seconds, out);
        if (report)
            fprintf(stderr, "relief complete: report: %s\n", report);
    }
    if (st == RELIEF_OK && report_dir && !quiet)
        fprintf(stderr, "relief complete: report folder: %s/index.html\n", report_dir);
    if (st == RELIEF_OK && rc->checkpoint)
        remove(rc->checkpoint); /* it described an unfinished run */
    relief_hierarchy_destroy(hier);
    relief_matcher_destroy(m);
    relief_match_data_destroy(d);
    relief_surface_destroy(s);
    relief_mesh_destroy(smooth_mesh);
    relief_mesh_destroy(in);
    relief_checkpoint_destroy(ck);
    sigaction(SIGINT, &old_sa, NULL);
    return st == RELIEF_OK ? 0 : fail_status("complete", &err);
}

static int cmd_complete_or_smooth(int argc, char **argv, int smooth, int parse_only)
{
    const char *cmd = smooth ? "smooth" : "complete";
    static const struct option all_opts[] = {
        {"output", required_argument, 0, 'o'},
        {"report", required_argument, 0, OPT_REPORT},
        {"fit", required_argument, 0, OPT_FIT},
        {"oversample", required_argument, 0, OPT_OVERSAMPLE},
        {"spacing", required_argument, 0, OPT_SPACING},
        {"extent", required_argument, 0, OPT_EXTENT},
        {"ascii", no_argument, 0, OPT_ASCII},
        {"quiet", no_argument, 0, OPT_QUIET},
        {"frames", required_argument, 0, OPT_FRAMES},
        {"oversample-scheme", required_argument, 0, OPT_OVERSAMPLE_SCHEME},
        {"max-memory", required_argument, 0, OPT_MAX_MEMORY},
        {"help", no_argument, 0, 'h'},
        /* complete only, from here ("window" ends smooth's options) */
        {"window", required_argument, 0, OPT_WINDOW},
        {"rotations", required_argument, 0, OPT_ROTATIONS},
        {"error", required_argument, 0, OPT_ERROR},
        {"mu", required_argument, 0, OPT_MU},
        {"seed", required_argument, 0, OPT_SEED},
        {"levels", required_argument, 0, OPT_LEVELS},
        {"backend", required_argument, 0, OPT_BACKEND},
        {"device", required_argument, 0, OPT_DEVICE},
        {"bootstrap", no_argument, 0, OPT_BOOTSTRAP},
        {"no-prune", no_argument, 0, OPT_NO_PRUNE},
        {"report-dir", required_argument, 0, OPT_REPORT_DIR},
        {"checkpoint", required_argument, 0, OPT_CHECKPOINT},
        {"checkpoint-every", required_argument, 0, OPT_CHECKPOINT_EVERY},
        {"resume", required_argument, 0, OPT_RESUME},
        {0, 0, 0, 0}};
    /* smooth takes the options before the complete-only ones. */
    struct option smooth_opts[sizeof all_opts / sizeof all_opts[0]];
    size_t n_smooth = 0;
    relief_params p = relief_params_default();
    relief_smooth_options sopts = relief_smooth_options_default();
    relief_grow_options gopts = relief_grow_options_default();
    run_control control = {NULL, 300.0, NULL};
    relief_error err = {RELIEF_OK, ""};
    relief_mesh *in = NULL;
    relief_read_info info;
    const char *out = NULL, *report = NULL;
    const char *report_dir = NULL;
    int c, ascii = 0, quiet = 0;
    long v;
    double d;

    while (strcmp(all_opts[n_smooth].name, "window") != 0)
        ++n_smooth;
    memcpy(smooth_opts, all_opts, n_smooth * sizeof all_opts[0]);
    memset(&smooth_opts[n_smooth], 0, sizeof smooth_opts[0]);
    optind = 0;
    while ((c = getopt_long(argc, argv, "o:h", smooth ? smooth_opts : all_opts, NULL)) != -1) {
        switch (c) {
        case 'o': out = optarg; break;
        case OPT_REPORT: report = optarg; break;
        case OPT_FIT:
            if (!parse_fit(cmd, optarg, &p.fit))
                return EXIT_USAGE;
            break;
        case OPT_WINDOW:
            if (!parse_int(cmd, "--window", optarg, 1, 16, &v))
                return EXIT_USAGE;
            p.window = (int)v;
            break;
        case OPT_ROTATIONS:
            if (!parse_int(cmd, "--rotations", optarg, 1, 64, &v))
                return EXIT_USAGE;
            p.rotations = (int)v;
            break;
        case OPT_ERROR:
            if (!parse_real(cmd, "--error", optarg, &p.error))
                return EXIT_USAGE;
            break;
        case OPT_MU:
            if (!parse_real(cmd, "--mu", optarg, &p.mu))
                return EXIT_USAGE;
            if (p.mu < 0.0 || p.mu > 1.0) {
                fprintf(stderr, "relief %s: --mu: %s is out of range: expected 0..1\n",
                        cmd, optarg);
                return EXIT_USAGE;
            }
            break;
        case OPT_SEED:
            if (!parse_int(cmd, "--seed", optarg, 0, (long)UINT32_MAX, &v))
                return EXIT_USAGE;
            p.seed = (uint32_t)v;
            break;
        case OPT_LEVELS:
            if (!parse_int(cmd, "--levels", optarg, 1, 8, &v))
                return EXIT_USAGE;
            p.levels = (int)v;
            break;
        case OPT_BACKEND:
            if (strcmp(optarg, "auto") == 0)
                p.backend = RELIEF_BACKEND_AUTO;
            else if (strcmp(optarg, "scalar") == 0)
                p.backend = RELIEF_BACKEND_SCALAR;
            else if (strcmp(optarg, "opencl") == 0)
                p.backend = RELIEF_BACKEND_OPENCL;
            else
                return usage_error(cmd, "--backend: '%s' is not one of auto, scalar, opencl",
                                   optarg);
            break;
        case OPT_DEVICE:
            if (!parse_int(cmd, "--device", optarg, 0, 255, &v))
                return EXIT_USAGE;
            p.device = (int)v;
            break;
        case OPT_OVERSAMPLE:
            if (!parse_int(cmd, "--oversample", optarg, 0, 4, &v))
                return EXIT_USAGE;
            p.oversample = (int)v;
            break;
        case OPT_SPACING:
            if (!parse_real(cmd, "--spacing", optarg, &d))
                return EXIT_USAGE;
            if (d <= 0.0) {
                fprintf(stderr, "relief %s: --spacing: %s is out of range: expected a "
                        "length > 0\n", cmd, optarg);
                return EXIT_USAGE;
            }
            p.spacing = d;
            break;
        case OPT_EXTENT:
            if (!parse_extent(cmd, optarg, &p))
                return EXIT_USAGE;
            break;
        case OPT_ASCII: ascii = 1; break;
        case OPT_QUIET: quiet = 1; break;
        case OPT_BOOTSTRAP: gopts.bootstrap = 1; break;
        case OPT_NO_PRUNE: gopts.prune = 0; break;
        case OPT_REPORT_DIR: report_dir = optarg; break;
        case OPT_CHECKPOINT: control.checkpoint = optarg; break;
        case OPT_RESUME: control.resume = optarg; break;
        case OPT_CHECKPOINT_EVERY:
            if (!parse_real(cmd, "--checkpoint-every", optarg, &control.checkpoint_every))
                return EXIT_USAGE;
            if (control.checkpoint_every < 0.0) {
                fprintf(stderr, "relief %s: --checkpoint-every: %s is out of range: expected "
                        "seconds >= 0\n", cmd, optarg);
                return EXIT_USAGE;
            }
            break;
        case OPT_MAX_MEMORY:
            if (relief_parse_size(optarg, &p.max_memory, &err) != RELIEF_OK) {
                fprintf(stderr, "relief %s: --max-memory: %s\n", cmd, err.message);
                return EXIT_USAGE;
            }
            break;
        case OPT_OVERSAMPLE_SCHEME:
            if (strcmp(optarg, "butterfly") == 0)
                sopts.oversample_scheme = RELIEF_OVERSAMPLE_BUTTERFLY;
            else if (strcmp(optarg, "midpoint") == 0)
                sopts.oversample_scheme = RELIEF_OVERSAMPLE_MIDPOINT;
            else
                return usage_error(cmd, "--oversample-scheme: '%s' is not one of "
                                   "butterfly, midpoint", optarg);
            break;
        case OPT_FRAMES:
            if (strcmp(optarg, "paper") == 0)
                sopts.frames = RELIEF_FRAMES_PAPER;
            else if (strcmp(optarg, "primitive") == 0)
                sopts.frames = RELIEF_FRAMES_PRIMITIVE;
            else
                return usage_error(cmd, "--frames: '%s' is not one of paper, primitive",
                                   optarg);
            break;
        case 'h': fputs(smooth ? smooth_help : complete_help, stdout); return 0;
        default: fprintf(stderr, "Try 'relief %s --help'.\n", cmd); return EXIT_USAGE;
        }
    }
    if (optind >= argc)
        return usage_error(cmd, "%smissing input mesh IN", "");
    if (argc - optind > 1)
        return usage_error(cmd, "unexpected argument '%s'", argv[optind + 1]);
    if (!out)
        return usage_error(cmd, "%smissing -o OUT", "");
    if (!known_ext(out))
        return usage_error(cmd, "-o: '%s' has no known mesh extension (.ply, .obj, .off, "
                           ".stl)", out);
    if (same_file(argv[optind], out))
        return usage_error(cmd, "-o: '%s' is the input; relief never overwrites its input",
                           out);
    if (control.checkpoint && (same_file(argv[optind], control.checkpoint) ||
                               same_file(out, control.checkpoint) ||
                               (report && same_file(report, control.checkpoint))))
        return usage_error(cmd, "--checkpoint: '%s' is the input or an output",
                           control.checkpoint);
    if (relief_params_validate(&p, &err) != RELIEF_OK)
        return fail_status(cmd, &err);
    if (parse_only)
        return 0;
    /* A report folder that cannot be written fails now, not after the growth. */
    if (report_dir && relief_report_dir_check(report_dir, &err) != RELIEF_OK)
        return fail_status(cmd, &err);
    {
        struct stat sb;
        char what[RELIEF_ERROR_MESSAGE_MAX / 2];
        snprintf(what, sizeof what, "reading %s", argv[optind]);
        if (stat(argv[optind], &sb) == 0 && S_ISREG(sb.st_mode) &&
            relief_memory_check(what, relief_estimate_read((uint64_t)sb.st_size),
                                relief_memory_limit(&p), "", &err) != RELIEF_OK)
            return fail_status(cmd, &err);
    }
    if (relief_mesh_read(argv[optind], &in, &info, &err) != RELIEF_OK)
        return fail_status(cmd, &err);
    if (info.nonmanifold_triangles > 0 && !quiet)
        fprintf(stderr, "relief %s: warning: %s: %zu non-manifold triangle(s)\n", cmd,
                argv[optind], info.nonmanifold_triangles);
    if (!smooth)
        return run_complete(argv[optind], in, out, report, report_dir, &p, &sopts, &gopts,
                            ascii, quiet, &control);
    return run_smooth(argv[optind], in, out, report, &p, &sopts, ascii, quiet);
}

/* ---------------------------------------------------------------- synth */

static const char synth_help[] =
    "usage: relief synth KIND -o OUT [--truth T] [--seed N] [--vertices N]\n"
    "                    [--colour] [--noise SIGMA] [--ascii]\n"
    "\n"
    "Write a synthetic partial capture with known relief (OUT) and, with\n"
    "--truth, the whole surface it was cut from (T; its `label` is 0 where the\n"
    "capture has the vertex, 1 where a completion must produce it).\n"
    "\n"
    "KIND:\n"
    "%s"
    "\n"
    "  -o, --output OUT      captured part; required\n"
    "  --truth T             whole ground-truth surface\n"
    "  --seed N              random seed (default 1)\n"
    "  --vertices N          approximate vertex count of the truth, 100..4000000\n"
    "                        (default 2000)\n"
    "  --colour              per-vertex colour\n"
    "  --noise SIGMA         scanner noise along the normal on the capture, as a\n"
    "                        fraction of the primitive's size, 0..0.1 (default 0)\n"
    "  --ascii               write ascii PLY (default binary)\n"
    "  -h, --help            this help\n";

static void print_synth_help(void)
{
    char kinds[1024];
    size_t at = 0;
    for (int k = 0; k < RELIEF_SYNTH_KIND_COUNT; ++k)
        at += (size_t)snprintf(kinds + at, sizeof kinds - at, "  %-16s %s\n",
                               relief_synth_kind_name((relief_synth_kind)k),
                               relief_synth_kind_description((relief_synth_kind)k));
    printf(synth_help, kinds);
}

static int cmd_synth(int argc, char **argv, int parse_only)
{
    static const struct option opts[] = {
        {"output", required_argument, 0, 'o'}, {"truth", required_argument, 0, OPT_TRUTH},
        {"seed", required_argument, 0, OPT_SEED},
        {"vertices", required_argument, 0, OPT_VERTICES},
        {"colour", no_argument, 0, OPT_COLOUR}, {"color", no_argument, 0, OPT_COLOUR},
        {"noise", required_argument, 0, OPT_NOISE}, {"ascii", no_argument, 0, OPT_ASCII},
        {"help", no_argument, 0, 'h'}, {0, 0, 0, 0}};
    relief_synth_params sp = relief_synth_params_default();
    relief_write_options wo = {0};
    relief_error err = {RELIEF_OK, ""};
    relief_mesh *cap = NULL, *truth = NULL;
    const char *out = NULL, *truth_path = NULL;
    sigset_t held;
    int c, rc = 0;
    long v;

    optind = 0;
    while ((c = getopt_long(argc, argv, "o:h", opts, NULL)) != -1) {
        switch (c) {
        case 'o': out = optarg; break;
        case OPT_TRUTH: truth_path = optarg; break;
        case OPT_SEED:
            if (!parse_int("synth", "--seed", optarg, 0, (long)UINT32_MAX, &v))
                return EXIT_USAGE;
            sp.seed = (uint32_t)v;
            break;
        case OPT_VERTICES:
            if (!parse_int("synth", "--vertices", optarg, 100, 4000000, &v))
                return EXIT_USAGE;
            sp.vertices = (size_t)v;
            break;
        case OPT_COLOUR: sp.colour = 1; break;
        case OPT_NOISE:
            if (!parse_real("synth", "--noise", optarg, &sp.noise))
                return EXIT_USAGE;
            break;
        case OPT_ASCII: wo.ascii = 1; break;
        case 'h': print_synth_help(); return 0;
        default: fprintf(stderr, "Try 'relief synth --help'.\n"); return EXIT_USAGE;
        }
    }
    if (optind >= argc)
        return usage_error("synth", "%smissing KIND", "");
    if (argc - optind > 1)
        return usage_error("synth", "unexpected argument '%s'", argv[optind + 1]);
    if (!out)
        return usage_error("synth", "%smissing -o OUT", "");
    if (truth_path && same_file(out, truth_path))
        return usage_error("synth", "--truth: '%s' is also the -o output", truth_path);
    if (relief_synth_kind_parse(argv[optind], &sp.kind, &err) != RELIEF_OK)
        return fail_status("synth", &err);
    if (parse_only)
        return 0;
    if (relief_synth(&sp, &cap, truth_path ? &truth : NULL, &err) != RELIEF_OK)
        return fail_status("synth", &err);
    hold_signals(&held);
    if (relief_mesh_write(cap, out, &wo, &err) != RELIEF_OK ||
        (truth && relief_mesh_write(truth, truth_path, &wo, &err) != RELIEF_OK)) {
        rc = fail_status("synth", &err);
        remove(out); /* both or neither: the capture alone is no use */
    } else {
        fprintf(stderr, "relief synth: %s: %zu vertices, %zu triangles (captured)\n", out,
                relief_mesh_vertex_count(cap), relief_mesh_triangle_count(cap));
        if (truth)
            fprintf(stderr, "relief synth: %s: %zu vertices, %zu triangles (truth)\n",
                    truth_path, relief_mesh_vertex_count(truth),
                    relief_mesh_triangle_count(truth));
    }
    release_signals(&held);
    relief_mesh_destroy(truth);
    relief_mesh_destroy(cap);
    return rc;
}

/* ----------------------------------------------------------------- help */

static const char fit_help[] =
    "usage: relief fit IN [--fit auto|plane|sphere|cylinder] [--json]\n"
    "\n"
    "Fit a primitive to the points of IN (least-squares start, then orthogonal-\n"
    "distance refinement with outliers trimmed) and print its parameters in the\n"
    "input's units, the RMS orthogonal residual over the inliers and the\n"
    "fraction of points within 3 RMS. auto picks the model whose residual,\n"
    "penalised 10% per extra parameter, is lowest, and says why. A fit whose\n"
    "RMS exceeds 10% of the primitive's size is reported as poor on stderr.\n"
    "\n"
    "  --fit MODEL           auto|plane|sphere|cylinder (default auto)\n"
    "  --json                one JSON object: model, rms, inlier_fraction and\n"
    "                        point/normal, center/radius or axis_point/axis_dir/radius\n"
    "  -h, --help            this help\n";
static const char eval_help[] =
    "usage: relief eval COMPLETED [--truth T] [--json]\n"
    "\n"
    "Measure a completion, using its per-vertex `label` (0 captured, 1\n"
    "completed) and a primitive fitted to the captured part: the mean surface\n"
    "integral (mean |D.n|) of each part and their % difference, the total-\n"
    "variation distance between the parts' displacement histograms (and RGB\n"
    "histograms when there is colour), the seam measure (mean |D| jump across\n"
    "captured-completed edges over the same inside the capture), and the\n"
    "dominant spatial frequency of each part. With --truth (a mesh whose label\n"
    "1 marks the missing part, as `relief synth --truth` writes): the RMS\n"
    "relief error against the truth and the truth's dominant frequency.\n"
    "\n"
    "  --truth T             ground-truth mesh in the same coordinates\n"
    "  --json                one JSON object (msi_captured, msi_completed,\n"
    "                        msi_diff_percent, seam_ratio, hist_distance_*, ...)\n"
    "  -h, --help            this help\n";
static const char devices_help[] =
    "usage: relief devices\n"
    "\n"
    "List the OpenCL platforms and devices relief can use, with their compute\n"
    "units and memory.\n";

/* ------------------------------------------------------------------ fit */

static void print_fit_json(FILE *f, const char *path, const relief_fit_result *r)
{
    relief_json j;
    rj_init(&j, f);
    rj_begin_object(&j, NULL);
    rj_string(&j, "input", path);
    relief_report_fit_fields(&j, r);
    rj_end_object(&j);
}

static int cmd_fit(int argc, char **argv, int parse_only)
{
    static const struct option opts[] = {{"fit", required_argument, 0, OPT_FIT},
                                         {"json", no_argument, 0, OPT_JSON},
                                         {"help", no_argument, 0, 'h'},
                                         {0, 0, 0, 0}};
    relief_fit_model model = RELIEF_FIT_AUTO;
    relief_error err = {RELIEF_OK, ""};
    relief_fit_result r;
    relief_mesh *in = NULL;
    relief_status st;
    int c, json = 0;

    optind = 0;
    while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
        switch (c) {
        case OPT_FIT:
            if (!parse_fit("fit", optarg, &model))
                return EXIT_USAGE;
            break;
        case OPT_JSON: json = 1; break;
        case 'h': fputs(fit_help, stdout); return 0;
        default: fprintf(stderr, "Try 'relief fit --help'.\n"); return EXIT_USAGE;
        }
    }
    if (optind >= argc)
        return usage_error("fit", "%smissing input mesh IN", "");
    if (argc - optind > 1)
        return usage_error("fit", "unexpected argument '%s'", argv[optind + 1]);
    if (parse_only)
        return 0;
    if (relief_mesh_read(argv[optind], &in, NULL, &err) != RELIEF_OK)
        return fail_status("fit", &err);
    st = relief_fit_mesh(in, model, &r, &err);
    relief_mesh_destroy(in);
    if (st != RELIEF_OK)
        return fail_status("fit", &err);
    if (json) {
        print_fit_json(stdout, argv[optind], &r);
    } else {
        const relief_fit_primitive *p = &r.prim;
        printf("model: %s\n", relief_fit_model_name(p->model));
        if (p->model == RELIEF_FIT_PLANE)
            printf("point: %.10g %.10g %.10g\nnormal: %.10g %.10g %.10g\n", p->point[0],
                   p->point[1], p->point[2], p->dir[0], p->dir[1], p->dir[2]);
        else if (p->model == RELIEF_FIT_SPHERE)
            printf("center: %.10g %.10g %.10g\nradius: %.10g\n", p->point[0], p->point[1],
                   p->point[2], p->radius);
        else
            printf("axis_point: %.10g %.10g %.10g\naxis_dir: %.10g %.10g %.10g\n"
                   "radius: %.10g\n",
                   p->point[0], p->point[1], p->point[2], p->dir[0], p->dir[1], p->dir[2],
                   p->radius);
        printf("rms: %.6g (over %zu of %zu points)\ninlier_fraction: %.4f (within 3 rms)\n"
               "why: %s\n",
               r.rms, r.n_inliers, r.n_points, r.inlier_fraction, r.reason);
    }
    if (r.poor_fit)
        fprintf(stderr,
                "relief fit: warning: poor fit: rms %.4g is more than %.0f%% of the %s's "
                "size %.4g; the capture may not be a %s\n",
                r.rms, 100.0 * RELIEF_FIT_POOR, relief_fit_model_name(r.prim.model), r.size,
                relief_fit_model_name(r.prim.model));
    return 0;
}

/* ----------------------------------------------------------------- eval */

static void print_measures_text(const relief_measures *m)
{
    printf("primitive: %s\n", relief_fit_model_name(m->prim.model));
    printf("vertices: %zu captured, %zu completed\n", m->n_captured, m->n_completed);
    printf("msi_captured: %.6g\nmsi_completed: %.6g\nmsi_diff_percent: %.3f\n",
           m->msi_captured, m->msi_completed, m->msi_diff_percent);
    printf("hist_distance_displacement: %.4f\n", m->hist_distance_displacement);
    if (m->has_colour)
        printf("hist_distance_colour: %.4f\n", m->hist_distance_colour);
    printf("seam: %.6g (over %zu edges), inside: %.6g (%zu edges), seam_ratio: %.3f\n",
           m->seam, m->n_seam_edges, m->inside, m->n_inside_edges, m->seam_ratio);
    printf("freq_captured: %.4g\nfreq_completed: %.4g\n", m->freq_captured.freq,
           m->freq_completed.freq);
    if (m->has_truth)
        printf("truth_rms: %.6g\nfreq_truth: %.4g\n", m->truth_rms, m->freq_truth.freq);
}

static int cmd_eval(int argc, char **argv, int parse_only)
{
    static const struct option opts[] = {{"truth", required_argument, 0, OPT_TRUTH},
                                         {"json", no_argument, 0, OPT_JSON},
                                         {"help", no_argument, 0, 'h'},
                                         {0, 0, 0, 0}};
    relief_error err = {RELIEF_OK, ""};
    relief_mesh *done = NULL, *truth = NULL;
    const char *truth_path = NULL;
    relief_measures m;
    relief_status st;
    int c, json = 0;

    optind = 0;
    while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
        switch (c) {
        case OPT_TRUTH: truth_path = optarg; break;
        case OPT_JSON: json = 1; break;
        case 'h': fputs(eval_help, stdout); return 0;
        default: fprintf(stderr, "Try 'relief eval --help'.\n"); return EXIT_USAGE;
        }
    }
    if (optind >= argc)
        return usage_error("eval", "%smissing mesh COMPLETED", "");
    if (argc - optind > 1)
        return usage_error("eval", "unexpected argument '%s'", argv[optind + 1]);
    if (parse_only)
        return 0;
    st = relief_mesh_read(argv[optind], &done, NULL, &err);
    if (st == RELIEF_OK && truth_path)
        st = relief_mesh_read(truth_path, &truth, NULL, &err);
    if (st == RELIEF_OK)
        st = relief_measure(done, truth, NULL, &m, &err);
    relief_mesh_destroy(truth);
    relief_mesh_destroy(done);
    if (st != RELIEF_OK)
        return fail_status("eval", &err);
    if (json) {
        relief_json j;
        rj_init(&j, stdout);
        rj_begin_object(&j, NULL);
        rj_string(&j, "input", argv[optind]);
        if (truth_path)
            rj_string(&j, "truth", truth_path);
        relief_report_measures_fields(&j, &m);
        rj_end_object(&j);
    } else {
        print_measures_text(&m);
    }
    return 0;
}

/* --------------------------------------------------------------- render */

static const char render_help[] =
    "usage: relief render MESH -o OUT.png [--view AZ,EL] [--size WxH]\n"
    "                     [--colour-by auto|label|colour|displacement|none]\n"
    "\n"
    "Render MESH shaded (z-buffer, one light, per-vertex colour) into a PNG,\n"
    "headless.\n"
    "\n"
    "  -o, --output OUT.png  the image; required\n"
    "  --view AZ,EL          camera direction from the object, degrees: azimuth\n"
    "                        about +z from +x, elevation -90..90 above the xy\n"
    "                        plane (default: facing the captured part, turned\n"
    "                        25 and 20 degrees so that relief shows)\n"
    "  --size WxH            pixels, 1..8192 each (default 800x600)\n"
    "  --colour-by C         colour: the mesh's colours; label: captured grey,\n"
    "                        completed orange; displacement: height above (red)\n"
    "                        or below (blue) a primitive fitted to the captured\n"
    "                        part; none: grey; auto (default): colour, else label,\n"
    "                        else none\n";

/* "WxH" into two sides. */
static int parse_size(const char *s, int *w, int *h)
{
    char *end;
    const char *second;
    long a, b;
    errno = 0;
    a = strtol(s, &end, 10);
    if (end == s || (*end != 'x' && *end != 'X'))
        goto bad;
    second = end + 1;
    b = strtol(second, &end, 10);
    if (end == second || *end != '\0' || errno != 0)
        goto bad;
    if (a < 1 || b < 1 || a > RELIEF_RENDER_MAX_SIDE || b > RELIEF_RENDER_MAX_SIDE) {
        fprintf(stderr, "relief render: --size: %ldx%ld is out of range: expected 1..%d "
                "pixels per side\n", a, b, RELIEF_RENDER_MAX_SIDE);
        return 0;
    }
    *w = (int)a;
    *h = (int)b;
    return 1;
bad:
    fprintf(stderr, "relief render: --size: '%s' is not WIDTHxHEIGHT in pixels (e.g. "
            "800x600)\nTry 'relief render --help'.\n", s);
    return 0;
}

/* "AZ,EL" in degrees. */
static int parse_view(const char *s, double *az, double *el)
{
    char *end;
    const char *second;
    errno = 0;
    *az = strtod(s, &end);
    if (end == s || *end != ',' || !isfinite(*az))
        goto bad;
    second = end + 1;
    *el = strtod(second, &end);
    if (end == second || *end != '\0' || errno != 0 || !isfinite(*el))
        goto bad;
    if (*el < -90.0 || *el > 90.0) {
        fprintf(stderr, "relief render: --view: elevation %g is out of range: expected "
                "-90..90 degrees\n", *el);
        return 0;
    }
    return 1;
bad:
    fprintf(stderr, "relief render: --view: '%s' is not AZIMUTH,ELEVATION in degrees (e.g. "
            "30,20)\nTry 'relief render --help'.\n", s);
    return 0;
}

static int cmd_render(int argc, char **argv, int parse_only)
{
    static const struct option opts[] = {{"output", required_argument, 0, 'o'},
                                         {"view", required_argument, 0, OPT_VIEW},
                                         {"size", required_argument, 0, OPT_SIZE},
                                         {"colour-by", required_argument, 0, OPT_COLOUR_BY},
                                         {"help", no_argument, 0, 'h'},
                                         {0, 0, 0, 0}};
    static const relief_colour_by bys[] = {RELIEF_COLOUR_BY_AUTO, RELIEF_COLOUR_BY_LABEL,
                                           RELIEF_COLOUR_BY_COLOUR,
                                           RELIEF_COLOUR_BY_DISPLACEMENT, RELIEF_COLOUR_BY_NONE};
    relief_render_options ro = relief_render_options_default();
    relief_render_info info;
    relief_error err = {RELIEF_OK, ""};
    relief_image img = {0, 0, NULL};
    relief_mesh *mesh = NULL;
    const char *out = NULL, *in;
    relief_status st;
    int c, found;

    optind = 0;
    while ((c = getopt_long(argc, argv, "o:h", opts, NULL)) != -1) {
        switch (c) {
        case 'o': out = optarg; break;
        case OPT_VIEW:
            if (!parse_view(optarg, &ro.azimuth, &ro.elevation))
                return EXIT_USAGE;
            ro.has_view = 1;
            break;
        case OPT_SIZE:
            if (!parse_size(optarg, &ro.width, &ro.height))
                return EXIT_USAGE;
            break;
        case OPT_COLOUR_BY:
            found = 0;
            for (size_t i = 0; i < sizeof bys / sizeof bys[0]; ++i)
                if (strcmp(optarg, relief_colour_by_name(bys[i])) == 0) {
                    ro.colour_by = bys[i];
                    found = 1;
                }
            if (!found)
                return usage_error("render", "--colour-by: '%s' is not one of auto, label, "
                                   "colour, displacement, none", optarg);
            break;
        case 'h': fputs(render_help, stdout); return 0;
        default: fprintf(stderr, "Try 'relief render --help'.\n"); return EXIT_USAGE;
        }
    }
    if (optind >= argc)
        return usage_error("render", "%smissing input MESH", "");
    if (argc - optind > 1)
        return usage_error("render", "unexpected argument '%s'", argv[optind + 1]);
    in = argv[optind];
    if (!out)
        return usage_error("render", "%smissing -o OUT.png", "");
    if (strcasecmp(ext_of(out), ".png") != 0)
        return usage_error("render", "-o: '%s' does not end in .png; relief renders PNG "
                           "images", out);
    if (same_file(in, out))
        return usage_error("render", "-o: '%s' is the input; relief never overwrites its input",
                           out);
    if (parse_only)
        return 0;
    st = relief_mesh_read(in, &mesh, NULL, &err);
    if (st == RELIEF_OK) {
        st = relief_render(mesh, &ro, &img, &info, &err);
        if (st == RELIEF_E_MESH) { /* name the file the mesh came from */
            char why[RELIEF_ERROR_MESSAGE_MAX];
            snprintf(why, sizeof why, "%s", err.message);
            relief_fail(&err, st, "%s: %s", in, why);
        }
    }
    if (st == RELIEF_OK)
        st = relief_png_write(out, img.rgb, img.width, img.height, &err);
    if (st == RELIEF_OK)
        fprintf(stderr, "relief render: %s -> %s (%dx%d, view %.1f,%.1f, colour by %s)\n", in,
                out, img.width, img.height, info.azimuth, info.elevation,
                relief_colour_by_name(info.colour_by));
    relief_image_free(&img);
    relief_mesh_destroy(mesh);
    return st == RELIEF_OK ? 0 : fail_status("render", &err);
}

/* -------------------------------------------------------------- devices */

static int cmd_devices(int argc, char **argv, int parse_only)
{
    static const struct option opts[] = {{"help", no_argument, 0, 'h'}, {0, 0, 0, 0}};
    relief_device_info dev[64];
    relief_error err = {RELIEF_OK, ""};
    size_t n = 0;
    int c;

    optind = 0;
    while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
        if (c == 'h') {
            fputs(devices_help, stdout);
            return 0;
        }
        fprintf(stderr, "Try 'relief devices --help'.\n");
        return EXIT_USAGE;
    }
    if (optind < argc)
        return usage_error("devices", "unexpected argument '%s'", argv[optind]);
    if (parse_only)
        return 0;
    if (relief_devices(dev, sizeof dev / sizeof dev[0], &n, &err) != RELIEF_OK)
        return fail_status("devices", &err);
    if (n == 0) {
        printf("no OpenCL platform or device found; relief will use the scalar backend\n");
        return 0;
    }
    for (size_t i = 0; i < n && i < sizeof dev / sizeof dev[0]; ++i)
        printf("device %d: %s [%s] on %s\n"
               "          %s, driver %s, %u compute units, %.1f GiB global memory, "
               "%.1f GiB max buffer\n",
               dev[i].index, dev[i].name, dev[i].type, dev[i].platform, dev[i].version,
               dev[i].driver, dev[i].compute_units,
               (double)dev[i].global_mem_bytes / 1073741824.0,
               (double)dev[i].max_alloc_bytes / 1073741824.0);
    return 0;
}

/* ----------------------------------------------------------------- main */

static const char main_help[] =
    "usage: relief COMMAND [options]\n"
    "\n"
    "Complete the hidden part of a partially captured surface: fit a plane,\n"
    "sphere or cylinder, then grow the capture's relief and colour over the\n"
    "missing part by non-parametric sampling.\n"
    "\n"
    "commands:\n"
    "  complete IN -o OUT    fit, smooth completion and relief/colour growth\n"
    "  smooth IN -o OUT      fit and smooth completion only\n"
    "  fit IN                fit a primitive and print it\n"
    "  synth KIND -o OUT     write a synthetic partial surface with ground truth\n"
    "  eval COMPLETED        measure a completion\n"
    "  render MESH -o P.png  a shaded picture of a mesh\n"
    "  devices               list OpenCL devices\n"
    "\n"
    "  relief COMMAND --help    options of a command\n"
    "  relief --version         version and build options\n"
    "\n"
    "Exit status: 0 success, 1 bad input or usage, 2 internal or device failure.\n";

int relief_cli_main(int argc, char **argv, int parse_only)
{
    const char *cmd;
    if (argc < 2) {
        fputs(main_help, stderr);
        return EXIT_USAGE;
    }
    cmd = argv[1];
    if (strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0 || strcmp(cmd, "help") == 0) {
        fputs(main_help, stdout);
        return 0;
    }
    if (strcmp(cmd, "--version") == 0 || strcmp(cmd, "-V") == 0) {
        printf("relief %s (OpenCL backend: %s)\n", RELIEF_VERSION_STRING,
#ifdef RELIEF_HAVE_OPENCL
               "built"
#else
               "not built"
#endif
        );
        return 0;
    }
    /* Subcommands see argv from their own name on, as getopt expects. */
    if (strcmp(cmd, "complete") == 0)
        return cmd_complete_or_smooth(argc - 1, argv + 1, 0, parse_only);
    if (strcmp(cmd, "smooth") == 0)
        return cmd_complete_or_smooth(argc - 1, argv + 1, 1, parse_only);
    if (strcmp(cmd, "synth") == 0)
        return cmd_synth(argc - 1, argv + 1, parse_only);
    if (strcmp(cmd, "fit") == 0)
        return cmd_fit(argc - 1, argv + 1, parse_only);
    if (strcmp(cmd, "eval") == 0)
        return cmd_eval(argc - 1, argv + 1, parse_only);
    if (strcmp(cmd, "devices") == 0)
        return cmd_devices(argc - 1, argv + 1, parse_only);
    if (strcmp(cmd, "render") == 0)
        return cmd_render(argc - 1, argv + 1, parse_only);
    fprintf(stderr, "relief: unknown command '%s'\n\n%s", cmd, main_help);
    return EXIT_USAGE;
}
