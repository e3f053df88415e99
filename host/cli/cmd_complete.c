/* relief complete and relief smooth: one option parser (smooth takes the
 * options before complete's own), the smooth completion alone, or the whole
 * run with its progress, SIGINT handling, checkpoints and reports. */
#include "cli/commands.h"

#include <getopt.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "relief/relief.h"
#include "base/params.h"
#include "base/atomic.h"
#include "base/clock.h"
#include "base/error.h"
#include "base/memlimit.h"
#include "cli/complete_report.h"
#include "cli/options.h"
#include "points/base_surface.h"
#include "grow/checkpoint.h"
#include "grow/grow.h"
#include "grow/hierarchy.h"
#include "match/matcher.h"
#include "match/search.h"
#include "mesh/mesh.h"
#include "report/measures.h"
#include "report/pattern.h"
#include "report/report_dir.h"
#include "smooth/oversample.h"
#include "smooth/surface.h"

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
    "  --base B              primitive (the fitted one), smooth (paper 002's\n"
    "                        smoothed, hole-filled base under a mesh that no\n"
    "                        primitive fits: a head, a statue; --levels coarsens\n"
    "                        it by collapses) or auto (default: smooth when no\n"
    "                        primitive fits well and neither --fit, --extent nor\n"
    "                        --accept-poor-fit is given)\n"
    "  --window W            neighbourhood radius in edge hops, 1..16 (default 3)\n"
    "  --rotations R         rotations tried per sample, 1..64 (default: 1 on a\n"
    "                        plane, whose frames are all alike, 4 otherwise)\n"
    "  --error E             acceptance threshold e > 0 (default 0.1)\n"
    "  --mu MU               shape weight 0..1 (default 1 without colour, 0.5 with)\n"
    "  --seed N              random seed (default 1)\n"
    "  --coherence K         copy patches: take the best candidate that continues\n"
    "                        a neighbour's source when its score is within K x\n"
    "                        the best; 0 = off, the paper's draw alone (default),\n"
    "                        else 1..100 (measured on the demo: README)\n"
    "  --search S            auto (default), exhaustive or coherent: score every\n"
    "                        sample for each target (paper 000), or only the\n"
    "                        samples that continue its neighbours' patches and\n"
    "                        their K most similar (k-coherence: sub-quadratic);\n"
    "                        auto is coherent above 1e8 samples x R x targets\n"
    "  --search-k K          similar samples per patch for coherent, 1..64\n"
    "                        (default 8)\n"
    "  --levels M            hierarchy levels 1..8 (default 1: mono-scale)\n"
    "  --backend B           who scores the candidates, all with the same output:\n"
    "                        scalar (the reference, one thread), opencl (the\n"
    "                        kernel on --device), host (the reference on every\n"
    "                        core), auto (default: a GPU or accelerator when\n"
    "                        OpenCL has one, or the --device named, else host)\n"
    "  --device N            OpenCL device index (see 'relief devices')\n"
    "  --oversample N        oversampling passes of the capture, 0..4 (default 1)\n"
    "  --oversample-scheme S butterfly (default: new samples on the smooth\n"
    "                        surface through the capture) or midpoint (the\n"
    "                        papers' coplanar edge midpoints)\n"
    "  --spacing S           target vertex spacing (default: from the capture)\n"
    "  --extent A,B[,C,D]    cylinder z0,z1 or plane u0,v0,u1,v1 to complete\n"
    "  --fill REGION         auto (default), holes or whole: what to complete of\n"
    "                        the uncovered primitive (see 'relief smooth --help')\n"
    "  --frames RULE         local frames: paper (000's rule, default) or primitive\n"
    "  --max-memory SIZE     host memory limit, e.g. 512M, 4G (default: 80% of\n"
    "                        physical memory); a larger run is refused up front\n"
    "  --max-growth R        refuse more than R targets per captured vertex, the\n"
    "                        sign of a primitive that does not suit the capture\n"
    "                        (default 100; 0: no limit)\n"
    "  --accept-poor-fit     go on, with a warning, when the fit's rms is over 10%\n"
    "                        of the primitive's size (default: refuse)\n"
    "  --keep-spikes         keep the capture's spikes as relief (default: a vertex\n"
    "                        over 8 robust roughness scales outside its neighbours'\n"
    "                        heights is a scanner spike, left out and completed)\n"
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
    "Region (--fill): the holes inside the capture's outline, or the whole\n"
    "uncovered primitive: the full turn of a cylinder over the capture's axial\n"
    "extent (or --extent), the whole sphere, a plane's --extent. auto: a plane\n"
    "its holes (the whole --extent when given); a cylinder or sphere the whole,\n"
    "as for a one-sided scan's hidden side, unless the capture covers less\n"
    "than 20% of it and has holes: a patch of a larger object, whose holes\n"
    "alone are completed.\n"
    "\n"
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
    "  --fill REGION         auto (default), holes or whole (above)\n"
    "  --frames RULE         local frames: paper (000's rule, default) or primitive\n"
    "  --max-memory SIZE     host memory limit, e.g. 512M, 4G (default: 80% of\n"
    "                        physical memory); a larger run is refused up front\n"
    "  --max-growth R        refuse more than R targets per captured vertex\n"
    "                        (default 100; 0: no limit)\n"
    "  --accept-poor-fit     go on, with a warning, when the fit is poor\n"
    "  --keep-spikes         keep the capture's spikes (default: left out)\n"
    "  --ascii               write ascii PLY (default binary)\n"
    "  --quiet               no progress output\n"
    "  -h, --help            this help\n";

/* A poor fit the user accepted (--accept-poor-fit) is still said, and so
 * are the folded triangles and the spikes the capture check dropped, and a
 * curved primitive's outside left alone. */
static void warn_poor_fit(const char *cmd, const relief_surface *s)
{
    const relief_fold_stats *f = &s->folds;
    if (s->fit.poor_fit)
        fprintf(stderr, "relief %s: warning: poor fit accepted: %s\n", cmd, s->fit.reason);
    if (f->triangles > 0)
        fprintf(stderr,
                "relief %s: warning: %zu triangles (%.2f%% of the capture's area) fold back "
                "over the fitted %s; they, the %zu vertices they touch and %zu triangles in "
                "all were dropped, and the hole is completed\n",
                cmd, f->triangles, 100.0 * f->area_fraction,
                relief_fit_model_name(s->fit.prim.model), f->vertices_dropped,
                f->triangles_dropped);
    if (s->spikes.vertices > 0)
        fprintf(stderr,
                "relief %s: warning: %zu capture vertices stand out of their neighbours' "
                "heights by more than %.4g (8 robust scales of %.4g; the largest by %.4g): "
                "taken for scanner spikes, left out with %zu triangles and completed "
                "(--keep-spikes keeps them)\n",
                cmd, s->spikes.vertices, s->spikes.threshold, s->spikes.scale,
                s->spikes.largest, s->spikes.triangles_dropped);
    if (s->fill.region == RELIEF_FILL_HOLES && s->fill.outside_points > 0 &&
        s->fit.prim.model != RELIEF_FIT_PLANE)
        fprintf(stderr,
                "relief %s: the capture covers %.1f%% of the fitted %s: completing the %zu "
                "hole%s inside its outline (%zu targets); --fill whole completes the rest of "
                "the %s too (%zu more)\n",
                cmd, 100.0 * s->fill.cover, relief_fit_model_name(s->fit.prim.model),
                s->fill.holes, s->fill.holes == 1 ? "" : "s", s->fill.hole_points,
                relief_fit_model_name(s->fit.prim.model), s->fill.outside_points);
}

static int run_smooth(const char *in_path, relief_mesh *in, const char *out,
                      const char *report, const relief_params *p,
                      const relief_smooth_options *o, int ascii, int quiet)
{
    relief_error err = {RELIEF_OK, ""};
    relief_write_options wo = {ascii};
    relief_surface *s = NULL;
    double t0 = relief_seconds();
    relief_status st = relief_surface_build(in, p, o, &s, &err);
    sigset_t held;
    relief_mesh_destroy(in);
    if (st != RELIEF_OK)
        return cli_fail("smooth", &err);
    warn_poor_fit("smooth", s);
    cli_hold_signals(&held);
    if (report) {
        smooth_report r = {in_path, out, p, o, s, relief_seconds() - t0};
        st = relief_atomic_write_text(report, cli_write_smooth_report, &r, &err);
    }
    if (st == RELIEF_OK) {
        st = relief_mesh_write(s->mesh, out, &wo, &err);
        if (st != RELIEF_OK && report)
            remove(report); /* both outputs or neither */
    }
    cli_release_signals(&held);
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
    return st == RELIEF_OK ? 0 : cli_fail("smooth", &err);
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
enum { BASE_AUTO, BASE_PRIMITIVE, BASE_SMOOTH };

typedef struct run_control {
    int base;               /* --base: BASE_AUTO, BASE_PRIMITIVE or BASE_SMOOTH (paper 002's
                               base, points/base_surface.h) */
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
    int print;    /* the progress line (a terminal) */
    int estimate; /* say once how long a long growth will take */
    int checkpoint; /* --checkpoint given */
    double estimate_after, estimate_min; /* seconds */
    size_t sigint_after, seen;
} progress_hook;

/* After `estimate_after` seconds of growth (2), the time left by the rate
 * measured so far, printed once (terminal or not) when it is over
 * `estimate_min` seconds (60): a user who did not expect hours can stop it
 * while it is cheap. The CLI test sets both to 0 with
 * RELIEF_TEST_ESTIMATE_NOW=1. */

static void print_estimate(progress_hook *h, const relief_grow_progress *p)
{
    double rate, left;
    if (p->done == 0 || !(p->seconds > 0))
        return; /* no rate yet */
    h->estimate = 0;
    if (p->done >= p->total)
        return;
    rate = (double)p->done / p->seconds;
    left = (double)(p->total - p->done) / rate;
    if (left < h->estimate_min)
        return;
    fprintf(stderr,
            "%srelief complete: estimated %.1f min more for the %zu targets left "
            "(%.2f targets/s over the first %.0f s); SIGINT stops it%s\n",
            h->print ? "\r" : "", left / 60.0, p->total - p->done, rate, p->seconds,
            h->checkpoint ? " and saves the checkpoint" : "");
}

static void on_progress(void *ctx, const relief_grow_progress *p)
{
    progress_hook *h = ctx;
    if (h->estimate && p->seconds >= h->estimate_after)
        print_estimate(h, p);
    if (h->print)
        print_progress(&h->last, p);
    if (h->sigint_after && ++h->seen == h->sigint_after)
        raise(SIGINT);
}

/* Does auto's note say OpenCL could not be used? A warning, printed under
 * --quiet too; the other notes are a plain choice. */
static int unavailable(const char *note)
{
    return strncmp(note, RELIEF_MATCHER_UNAVAILABLE, strlen(RELIEF_MATCHER_UNAVAILABLE)) == 0;
}

/* Test hook: RELIEF_TEST_DEVICE_FAIL_AFTER=N makes every OpenCL score after
 * the first N fail as an exhausted device would, so that the CLI test sees
 * auto continue on the host matcher and an explicit --backend opencl exit
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

/* Host bytes the mono-scale growth of s needs, the k-coherence search's
 * similar pairs included when it runs. */
static uint64_t growth_bytes(const relief_surface *s, const relief_params *p)
{
    uint64_t b = relief_estimate_growth(relief_mesh_vertex_count(s->mesh),
                                        relief_mesh_triangle_count(s->mesh), s->n_samples,
                                        p->rotations);
    if (relief_params_search(p, s->n_samples, p->rotations, s->n_targets) ==
        RELIEF_SEARCH_COHERENT)
        b += relief_search_bytes(s->n_samples, p->rotations, p->search_k);
    return b;
}

/* Refuse a growth that cannot fit before its match data and state exist. */
static relief_status check_growth_memory(const relief_surface *s, const relief_params *p,
                                         relief_error *err)
{
    const size_t nv = relief_mesh_vertex_count(s->mesh);
    char what[160];
    snprintf(what, sizeof what, "the growth over %zu vertices (%zu samples x %d rotations)",
             nv, s->n_samples, p->rotations);
    return relief_memory_check(what, growth_bytes(s, p),
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
    relief_params resolved;
    relief_checkpoint *ck = NULL;
    relief_mesh *smooth_mesh = NULL; /* before growth, for --report-dir */
    relief_report_dir *staged = NULL;
    relief_hierarchy *hier = NULL;      /* --levels > 1 */
    relief_fit_result pre;              /* --base auto's look at the fit */
    int use_smooth = 0;                 /* growing on a smooth base */
    relief_hierarchy_stats hstats;
    relief_backend used_backend = RELIEF_BACKEND_SCALAR;
    char used_device[256] = "";
    char note[RELIEF_ERROR_MESSAGE_MAX + 320] = ""; /* why auto chose its backend */
    saver sv = {rc->checkpoint, &key};
    progress_hook hook = {-1.0, !quiet && isatty(2), !quiet, rc->checkpoint != NULL, 2.0, 60.0,
                          0, 0};
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
    if (getenv("RELIEF_TEST_ESTIMATE_NOW"))
        hook.estimate_after = hook.estimate_min = 0.0;
    relief_checkpoint_key_make(in, p, o, go, &key);
    if (rc->resume) {
        st = relief_checkpoint_read(rc->resume, &key, &ck, &err);
        if (st != RELIEF_OK) {
            relief_mesh_destroy(in);
            sigaction(SIGINT, &old_sa, NULL);
            return cli_fail("complete", &err);
        }
        go->resume = relief_checkpoint_state(ck);
    }
    if (rc->checkpoint) {
        go->save = save_checkpoint;
        go->save_ctx = &sv;
        go->save_every = rc->checkpoint_every;
    }
    if (rc->base == BASE_SMOOTH) {
        relief_points_params pp = relief_points_params_default();
        st = relief_points_base_surface(in, &pp, &s, NULL, &err);
        use_smooth = 1;
    } else if (rc->base == BASE_AUTO && !o->accept_poor_fit && p->fit == RELIEF_FIT_AUTO &&
               !p->has_extent && relief_mesh_triangle_count(in) > 0 &&
               relief_fit_mesh(in, RELIEF_FIT_AUTO, &pre, NULL) == RELIEF_OK && pre.poor_fit) {
        /* No primitive fits: the capture's own smoothed, hole-filled base
         * (issue 21), or, when that cannot be built either, the poor fit's
         * refusal as before, with both reasons. */
        relief_points_params pp = relief_points_params_default();
        relief_error e2 = {RELIEF_OK, ""};
        st = relief_points_base_surface(in, &pp, &s, NULL, &e2);
        if (st == RELIEF_OK) {
            use_smooth = 1;
            if (!quiet)
                fprintf(stderr, "relief complete: no primitive fits well (%s): growing on the "
                        "capture's smoothed base (--base smooth; --base primitive "
                        "--accept-poor-fit keeps the %s)\n", pre.reason,
                        relief_fit_model_name(pre.prim.model));
        } else {
            st = relief_surface_build(in, p, o, &s, &err);
            if (st != RELIEF_OK)
                fprintf(stderr, "relief complete: the smoothed base (--base smooth) could not "
                        "be built either: %s\n", e2.message);
        }
    } else {
        st = relief_surface_build(in, p, o, &s, &err);
    }
    if (st == RELIEF_OK) {
        /* From here on the rotations are the primitive's (0: its default),
         * so the estimate, the growth and the report agree; the checkpoint
         * key above keeps the options as given. A smooth base turns as a
         * sphere does: 4. */
        resolved = *p;
        resolved.rotations = use_smooth && p->rotations == 0
                                 ? 4
                                 : relief_params_rotations(p, s->fit.prim.model);
        p = &resolved;
        if (!use_smooth) /* else the fit is only reported */
            warn_poor_fit("complete", s);
    }
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
        st = relief_matcher_create(p->backend, p->device, d, &m, note, sizeof note, &err);
        if (st == RELIEF_OK && note[0] && (!quiet || unavailable(note)))
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
        fprintf(stderr, "relief complete: %s%s, spacing %.4g: %zu samples, %zu targets; "
                "W %d, R %d, e %g, mu %g, %s search; growth memory about %.0f MiB\n",
                use_smooth ? "smooth base" : relief_fit_model_name(s->fit.prim.model),
                use_smooth ? "" : " fit", s->spacing, s->n_samples,
                s->n_targets, p->window, p->rotations, p->error,
                relief_grow_mu(p, relief_mesh_colours(s->mesh) != NULL),
                relief_search_name(relief_params_search(p, s->n_samples, p->rotations,
                                                        s->n_targets)),
                (double)growth_bytes(s, p) / (1024.0 * 1024.0));
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
        if (hook.print || hook.estimate || hook.sigint_after) {
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
            ho.backend = p->backend;
            ho.device = p->device;
            st = relief_hierarchy_grow(hier, s, p, go, &ho, &hs, &stats, &used_backend,
                                       used_device, sizeof used_device, note, sizeof note,
                                       &err);
            hs.build_seconds = hstats.build_seconds;
            hstats = hs;
            if (note[0] && (!quiet || unavailable(note)))
                fprintf(stderr, "relief complete: backend auto: %s\n", note);
            else if (st == RELIEF_OK && !quiet)
                fprintf(stderr, "relief complete: backend %s: %s\n",
                        relief_backend_name(used_backend), used_device);
            if (hstats.fallback[0])
                fprintf(stderr, "relief complete: backend auto: %s\n", hstats.fallback);
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
    cli_hold_signals(&held);
    if (st == RELIEF_OK && (report || report_dir)) {
        relief_measures meas;
        relief_pattern pat;
        relief_error merr = {RELIEF_OK, ""};
        int have = relief_measure(s->mesh, NULL, &s->fit.prim, &meas, &merr) == RELIEF_OK;
        int have_pat = have && relief_pattern_measure(s->mesh, &s->fit.prim, NULL, &pat,
                                                      &merr) == RELIEF_OK;
        complete_report r = {in_path, out, p, o, go, s, &stats,
                             m ? m->backend : used_backend, m ? m->device : used_device,
                             m ? m->kernel_seconds : stats.match_seconds,
                             hier ? &hstats : NULL, have ? &meas : NULL,
                             relief_seconds() - t0, m ? m->fallback_note : hstats.fallback,
                             have_pat ? &pat : NULL, note};
        if ((!have || !have_pat) && !quiet)
            fprintf(stderr, "relief complete: warning: no %smeasures in the report: %s\n",
                    have ? "pattern " : "", merr.message);
        if (report)
            st = relief_atomic_write_text(report, cli_write_complete_report, &r, &err);
        if (st == RELIEF_OK && report_dir)
            st = cli_stage_report_dir(report_dir, &r, in, smooth_mesh, &staged, &err);
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
    cli_release_signals(&held);
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
    return st == RELIEF_OK ? 0 : cli_fail("complete", &err);
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
        {"accept-poor-fit", no_argument, 0, OPT_ACCEPT_POOR_FIT},
        {"keep-spikes", no_argument, 0, OPT_KEEP_SPIKES},
        {"fill", required_argument, 0, OPT_FILL},
        {"max-growth", required_argument, 0, OPT_MAX_GROWTH},
        {"help", no_argument, 0, 'h'},
        /* complete only, from here ("window" ends smooth's options) */
        {"window", required_argument, 0, OPT_WINDOW},
        {"base", required_argument, 0, OPT_BASE},
        {"rotations", required_argument, 0, OPT_ROTATIONS},
        {"error", required_argument, 0, OPT_ERROR},
        {"coherence", required_argument, 0, OPT_COHERENCE},
        {"mu", required_argument, 0, OPT_MU},
        {"seed", required_argument, 0, OPT_SEED},
        {"levels", required_argument, 0, OPT_LEVELS},
        {"search", required_argument, 0, OPT_SEARCH},
        {"search-k", required_argument, 0, OPT_SEARCH_K},
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
    run_control control = {0, NULL, 300.0, NULL};
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
            if (!cli_parse_fit(cmd, optarg, &p.fit))
                return EXIT_USAGE;
            break;
        case OPT_BASE:
            if (strcmp(optarg, "smooth") == 0)
                control.base = BASE_SMOOTH;
            else if (strcmp(optarg, "primitive") == 0)
                control.base = BASE_PRIMITIVE;
            else if (strcmp(optarg, "auto") == 0)
                control.base = BASE_AUTO;
            else
                return cli_usage_error(cmd, "--base: '%s' is not one of auto, primitive, smooth",
                                       optarg);
            break;
        case OPT_WINDOW:
            if (!cli_parse_int_range(cmd, "--window", optarg, 1, 16, &v))
                return EXIT_USAGE;
            p.window = (int)v;
            break;
        case OPT_ROTATIONS:
            if (!cli_parse_int_range(cmd, "--rotations", optarg, 1, 64, &v))
                return EXIT_USAGE;
            p.rotations = (int)v;
            break;
        case OPT_ERROR:
            if (!cli_parse_real(cmd, "--error", optarg, &p.error))
                return EXIT_USAGE;
            break;
        case OPT_COHERENCE:
            if (!cli_parse_real(cmd, "--coherence", optarg, &p.coherence))
                return EXIT_USAGE;
            break;
        case OPT_MU:
            if (!cli_parse_real(cmd, "--mu", optarg, &p.mu))
                return EXIT_USAGE;
            if (p.mu < 0.0 || p.mu > 1.0) {
                fprintf(stderr, "relief %s: --mu: %s is out of range: expected 0..1\n",
                        cmd, optarg);
                return EXIT_USAGE;
            }
            break;
        case OPT_SEED:
            if (!cli_parse_int_range(cmd, "--seed", optarg, 0, (long)UINT32_MAX, &v))
                return EXIT_USAGE;
            p.seed = (uint32_t)v;
            break;
        case OPT_LEVELS:
            if (!cli_parse_int_range(cmd, "--levels", optarg, 1, 8, &v))
                return EXIT_USAGE;
            p.levels = (int)v;
            break;
        case OPT_SEARCH:
            if (strcmp(optarg, "auto") == 0)
                p.search = RELIEF_SEARCH_AUTO;
            else if (strcmp(optarg, "exhaustive") == 0)
                p.search = RELIEF_SEARCH_EXHAUSTIVE;
            else if (strcmp(optarg, "coherent") == 0)
                p.search = RELIEF_SEARCH_COHERENT;
            else
                return cli_usage_error(cmd, "--search: '%s' is not one of auto, exhaustive, "
                                       "coherent", optarg);
            break;
        case OPT_SEARCH_K:
            if (!cli_parse_int_range(cmd, "--search-k", optarg, 1, 64, &v))
                return EXIT_USAGE;
            p.search_k = (int)v;
            break;
        case OPT_BACKEND:
            if (!cli_parse_backend(cmd, optarg, 1, &p.backend))
                return EXIT_USAGE;
            break;
        case OPT_DEVICE:
            if (!cli_parse_int_range(cmd, "--device", optarg, 0, 255, &v))
                return EXIT_USAGE;
            p.device = (int)v;
            break;
        case OPT_OVERSAMPLE:
            if (!cli_parse_int_range(cmd, "--oversample", optarg, 0, 4, &v))
                return EXIT_USAGE;
            p.oversample = (int)v;
            break;
        case OPT_SPACING:
            if (!cli_parse_real(cmd, "--spacing", optarg, &d))
                return EXIT_USAGE;
            if (d <= 0.0) {
                fprintf(stderr, "relief %s: --spacing: %s is out of range: expected a "
                        "length > 0\n", cmd, optarg);
                return EXIT_USAGE;
            }
            p.spacing = d;
            break;
        case OPT_EXTENT:
            if (!cli_parse_extent(cmd, optarg, &p))
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
            if (!cli_parse_real(cmd, "--checkpoint-every", optarg, &control.checkpoint_every))
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
        case OPT_ACCEPT_POOR_FIT: sopts.accept_poor_fit = 1; break;
        case OPT_KEEP_SPIKES: sopts.spike_k = 0.0; break;
        case OPT_MAX_GROWTH:
            if (!cli_parse_real(cmd, "--max-growth", optarg, &sopts.max_growth))
                return EXIT_USAGE;
            if (sopts.max_growth < 0.0) {
                fprintf(stderr, "relief %s: --max-growth: %s is out of range: expected "
                        "targets per captured vertex >= 0 (0: no limit)\n", cmd, optarg);
                return EXIT_USAGE;
            }
            break;
        case OPT_OVERSAMPLE_SCHEME:
            if (strcmp(optarg, "butterfly") == 0)
                sopts.oversample_scheme = RELIEF_OVERSAMPLE_BUTTERFLY;
            else if (strcmp(optarg, "midpoint") == 0)
                sopts.oversample_scheme = RELIEF_OVERSAMPLE_MIDPOINT;
            else
                return cli_usage_error(cmd, "--oversample-scheme: '%s' is not one of "
                                   "butterfly, midpoint", optarg);
            break;
        case OPT_FILL:
            if (strcmp(optarg, "auto") == 0)
                sopts.fill = RELIEF_FILL_AUTO;
            else if (strcmp(optarg, "holes") == 0)
                sopts.fill = RELIEF_FILL_HOLES;
            else if (strcmp(optarg, "whole") == 0)
                sopts.fill = RELIEF_FILL_WHOLE;
            else
                return cli_usage_error(cmd, "--fill: '%s' is not one of auto, holes, whole",
                                       optarg);
            break;
        case OPT_FRAMES:
            if (strcmp(optarg, "paper") == 0)
                sopts.frames = RELIEF_FRAMES_PAPER;
            else if (strcmp(optarg, "primitive") == 0)
                sopts.frames = RELIEF_FRAMES_PRIMITIVE;
            else
                return cli_usage_error(cmd, "--frames: '%s' is not one of paper, primitive",
                                   optarg);
            break;
        case 'h': fputs(smooth ? smooth_help : complete_help, stdout); return 0;
        default: fprintf(stderr, "Try 'relief %s --help'.\n", cmd); return EXIT_USAGE;
        }
    }
    if (optind >= argc)
        return cli_usage_error(cmd, "%smissing input mesh IN", "");
    if (argc - optind > 1)
        return cli_usage_error(cmd, "unexpected argument '%s'", argv[optind + 1]);
    if (!out)
        return cli_usage_error(cmd, "%smissing -o OUT", "");
    if (!cli_known_mesh_ext(out))
        return cli_usage_error(cmd, "-o: '%s' has no known mesh extension (.ply, .obj, .off, "
                           ".stl)", out);
    if (cli_same_file(argv[optind], out))
        return cli_usage_error(cmd, "-o: '%s' is the input; relief never overwrites its input",
                           out);
    if (control.checkpoint && (cli_same_file(argv[optind], control.checkpoint) ||
                               cli_same_file(out, control.checkpoint) ||
                               (report && cli_same_file(report, control.checkpoint))))
        return cli_usage_error(cmd, "--checkpoint: '%s' is the input or an output",
                           control.checkpoint);
    if (relief_params_validate(&p, &err) != RELIEF_OK)
        return cli_fail(cmd, &err);
    if (control.base == BASE_SMOOTH && (p.fit != RELIEF_FIT_AUTO || p.has_extent))
        return cli_usage_error(cmd, "%s--base smooth has no primitive: --fit and --extent do "
                               "not apply", "");
    if (parse_only)
        return 0;
    /* A report folder that cannot be written fails now, not after the growth. */
    if (report_dir && relief_report_dir_check(report_dir, &err) != RELIEF_OK)
        return cli_fail(cmd, &err);
    {
        struct stat sb;
        char what[RELIEF_ERROR_MESSAGE_MAX / 2];
        snprintf(what, sizeof what, "reading %s", argv[optind]);
        if (stat(argv[optind], &sb) == 0 && S_ISREG(sb.st_mode) &&
            relief_memory_check(what, relief_estimate_read((uint64_t)sb.st_size),
                                relief_memory_limit(&p), "", &err) != RELIEF_OK)
            return cli_fail(cmd, &err);
    }
    if (relief_mesh_read(argv[optind], &in, &info, &err) != RELIEF_OK)
        return cli_fail(cmd, &err);
    if (info.nonmanifold_triangles > 0 && !quiet)
        fprintf(stderr, "relief %s: warning: %s: %zu non-manifold triangle(s)\n", cmd,
                argv[optind], info.nonmanifold_triangles);
    if (!smooth)
        return run_complete(argv[optind], in, out, report, report_dir, &p, &sopts, &gopts,
                            ascii, quiet, &control);
    return run_smooth(argv[optind], in, out, report, &p, &sopts, ascii, quiet);
}

int cli_cmd_complete(int argc, char **argv, int parse_only)
{
    return cmd_complete_or_smooth(argc, argv, 0, parse_only);
}

int cli_cmd_smooth(int argc, char **argv, int parse_only)
{
    return cmd_complete_or_smooth(argc, argv, 1, parse_only);
}
