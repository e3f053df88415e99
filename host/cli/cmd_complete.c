/* relief complete and relief smooth: the options of relief_complete and
 * relief_smooth (relief/complete.h; smooth takes the smooth completion's
 * only), one call of the engine with progress and SIGINT, then the mesh,
 * the report and the report folder, all or none. */
#include "cli/commands.h"

#include <getopt.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "relief/relief.h"
#include "base/memlimit.h"
#include "cli/options.h"

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

enum {
    OPT_FIT = OPT_COMMAND, OPT_OVERSAMPLE, OPT_OVERSAMPLE_SCHEME, OPT_SPACING, OPT_EXTENT,
    OPT_FILL, OPT_FRAMES, OPT_MAX_GROWTH, OPT_ACCEPT_POOR_FIT, OPT_KEEP_SPIKES, OPT_ASCII,
    /* complete only, from here */
    OPT_WINDOW, OPT_BASE, OPT_ROTATIONS, OPT_ERROR, OPT_COHERENCE, OPT_MU, OPT_LEVELS,
    OPT_SEARCH, OPT_SEARCH_K, OPT_BOOTSTRAP, OPT_NO_PRUNE, OPT_REPORT_DIR, OPT_CHECKPOINT,
    OPT_CHECKPOINT_EVERY, OPT_RESUME
};

static const struct option smooth_own[] = {
    {"fit", required_argument, 0, OPT_FIT},
    {"oversample", required_argument, 0, OPT_OVERSAMPLE},
    {"oversample-scheme", required_argument, 0, OPT_OVERSAMPLE_SCHEME},
    {"spacing", required_argument, 0, OPT_SPACING},
    {"extent", required_argument, 0, OPT_EXTENT},
    {"fill", required_argument, 0, OPT_FILL},
    {"frames", required_argument, 0, OPT_FRAMES},
    {"max-growth", required_argument, 0, OPT_MAX_GROWTH},
    {"accept-poor-fit", no_argument, 0, OPT_ACCEPT_POOR_FIT},
    {"keep-spikes", no_argument, 0, OPT_KEEP_SPIKES},
    {"ascii", no_argument, 0, OPT_ASCII},
    {0, 0, 0, 0}};

static const struct option complete_own[] = {
    {"fit", required_argument, 0, OPT_FIT},
    {"oversample", required_argument, 0, OPT_OVERSAMPLE},
    {"oversample-scheme", required_argument, 0, OPT_OVERSAMPLE_SCHEME},
    {"spacing", required_argument, 0, OPT_SPACING},
    {"extent", required_argument, 0, OPT_EXTENT},
    {"fill", required_argument, 0, OPT_FILL},
    {"frames", required_argument, 0, OPT_FRAMES},
    {"max-growth", required_argument, 0, OPT_MAX_GROWTH},
    {"accept-poor-fit", no_argument, 0, OPT_ACCEPT_POOR_FIT},
    {"keep-spikes", no_argument, 0, OPT_KEEP_SPIKES},
    {"ascii", no_argument, 0, OPT_ASCII},
    {"window", required_argument, 0, OPT_WINDOW},
    {"base", required_argument, 0, OPT_BASE},
    {"rotations", required_argument, 0, OPT_ROTATIONS},
    {"error", required_argument, 0, OPT_ERROR},
    {"coherence", required_argument, 0, OPT_COHERENCE},
    {"mu", required_argument, 0, OPT_MU},
    {"levels", required_argument, 0, OPT_LEVELS},
    {"search", required_argument, 0, OPT_SEARCH},
    {"search-k", required_argument, 0, OPT_SEARCH_K},
    {"bootstrap", no_argument, 0, OPT_BOOTSTRAP},
    {"no-prune", no_argument, 0, OPT_NO_PRUNE},
    {"report-dir", required_argument, 0, OPT_REPORT_DIR},
    {"checkpoint", required_argument, 0, OPT_CHECKPOINT},
    {"checkpoint-every", required_argument, 0, OPT_CHECKPOINT_EVERY},
    {"resume", required_argument, 0, OPT_RESUME},
    {0, 0, 0, 0}};

/* What the command line adds to the engine's parameters. */
typedef struct complete_cli {
    cli_common cm;
    relief_complete_params p;
    const char *report_dir, *in;
    int ascii;
} complete_cli;

/* --extent: "z0,z1" (cylinder) or "u0,v0,u1,v1" (plane). */
static int parse_extent(const char *cmd, const char *s, relief_complete_params *p)
{
    int n;
    if (!cli_parse_reals(cmd, "--extent", s, p->extent, 4, &n))
        return 0;
    if (n != 2 && n != 4) {
        fprintf(stderr, "relief %s: --extent: expected z0,z1 (cylinder) or u0,v0,u1,v1 "
                "(plane), got '%s'\n", cmd, s);
        return 0;
    }
    p->n_extent = n;
    return 1;
}

/* The smooth completion's options: 1 taken, 0 not one of them, -1 bad. */
static int smooth_option(complete_cli *c, int opt, const char *arg)
{
    static const char *const fits[] = {"auto", "plane", "sphere", "cylinder"};
    static const char *const schemes[] = CLI_NAMES(RELIEF_OVERSAMPLE_SCHEME_LIST);
    static const char *const fills[] = CLI_NAMES(RELIEF_FILL_REGION_LIST);
    static const char *const frames[] = CLI_NAMES(RELIEF_FRAMES_LIST);
    relief_complete_params *p = &c->p;
    const char *cmd = c->cm.cmd;
    int v, ok = 1;
    switch (opt) {
    case OPT_FIT: ok = CLI_PARSE_ENUM(cmd, "--fit", arg, fits, &v), p->fit = v; break;
    case OPT_OVERSAMPLE: ok = cli_parse_int(cmd, "--oversample", arg, &p->oversample); break;
    case OPT_OVERSAMPLE_SCHEME:
        ok = CLI_PARSE_ENUM(cmd, "--oversample-scheme", arg, schemes, &v);
        p->oversample_scheme = (relief_oversample_scheme)v;
        break;
    case OPT_SPACING: ok = cli_parse_real(cmd, "--spacing", arg, &p->spacing); break;
    case OPT_EXTENT: ok = parse_extent(cmd, arg, p); break;
    case OPT_FILL: ok = CLI_PARSE_ENUM(cmd, "--fill", arg, fills, &v), p->fill = v; break;
    case OPT_FRAMES: ok = CLI_PARSE_ENUM(cmd, "--frames", arg, frames, &v), p->frames = v; break;
    case OPT_MAX_GROWTH: ok = cli_parse_real(cmd, "--max-growth", arg, &p->max_growth); break;
    case OPT_ACCEPT_POOR_FIT: p->accept_poor_fit = 1; break;
    case OPT_KEEP_SPIKES: p->keep_spikes = 1; break;
    case OPT_ASCII: c->ascii = 1; break;
    default: return 0;
    }
    return ok ? 1 : -1;
}

/* The growth's options: 1 taken, 0 not one of them, -1 bad. */
static int growth_option(complete_cli *c, int opt, const char *arg)
{
    static const char *const bases[] = CLI_NAMES(RELIEF_BASE_LIST);
    static const char *const searches[] = CLI_NAMES(RELIEF_SEARCH_LIST);
    relief_complete_params *p = &c->p;
    const char *cmd = c->cm.cmd;
    int v, ok = 1;
    switch (opt) {
    case OPT_WINDOW: ok = cli_parse_int(cmd, "--window", arg, &p->window); break;
    case OPT_BASE: ok = CLI_PARSE_ENUM(cmd, "--base", arg, bases, &v), p->base = v; break;
    case OPT_ROTATIONS: ok = cli_parse_int(cmd, "--rotations", arg, &p->rotations); break;
    case OPT_ERROR: ok = cli_parse_real(cmd, "--error", arg, &p->error); break;
    case OPT_COHERENCE: ok = cli_parse_real(cmd, "--coherence", arg, &p->coherence); break;
    case OPT_MU: ok = cli_parse_real(cmd, "--mu", arg, &p->mu); break;
    case OPT_LEVELS: ok = cli_parse_int(cmd, "--levels", arg, &p->levels); break;
    case OPT_SEARCH: ok = CLI_PARSE_ENUM(cmd, "--search", arg, searches, &v), p->search = v; break;
    case OPT_SEARCH_K: ok = cli_parse_int(cmd, "--search-k", arg, &p->search_k); break;
    case OPT_BOOTSTRAP: p->bootstrap = 1; break;
    case OPT_NO_PRUNE: p->prune = 0; break;
    case OPT_REPORT_DIR: c->report_dir = arg; break;
    case OPT_CHECKPOINT: p->checkpoint = arg; break;
    case OPT_RESUME: p->resume = arg; break;
    case OPT_CHECKPOINT_EVERY:
        ok = cli_parse_real(cmd, "--checkpoint-every", arg, &p->checkpoint_every);
        break;
    default: return 0;
    }
    return ok ? 1 : -1;
}

/* Parse and check the command line: 0 to go on, else the exit status. */
static int parse(complete_cli *c, int argc, char **argv, int smooth)
{
    struct option opts[64];
    relief_error err = {RELIEF_OK, ""};
    int o, taken;
    const unsigned shared = smooth ? CLI_OUTPUT | CLI_REPORT | CLI_QUIET | CLI_MAX_MEMORY
                                   : CLI_ENGINE;
    cli_options(shared, smooth ? smooth_own : complete_own, opts, 64);
    optind = 0;
    while ((o = getopt_long(argc, argv, "o:h", opts, NULL)) != -1) {
        if (o == 'h') {
            fputs(smooth ? smooth_help : complete_help, stdout);
            return -1;
        }
        taken = cli_common_option(&c->cm, o, optarg);
        if (!taken)
            taken = smooth_option(c, o, optarg);
        if (!taken && !smooth)
            taken = growth_option(c, o, optarg);
        if (taken < 0)
            return EXIT_USAGE;
        if (!taken) {
            fprintf(stderr, "Try 'relief %s --help'.\n", c->cm.cmd);
            return EXIT_USAGE;
        }
    }
    if (!cli_one_input(&c->cm, argc, argv, "input mesh IN", &c->in))
        return EXIT_USAGE;
    if (!cli_known_mesh_ext(c->cm.out))
        return cli_usage_error(c->cm.cmd, "-o: '%s' has no known mesh extension (.ply, .obj, "
                               ".off, .stl)", c->cm.out);
    {
        /* --resume and --checkpoint may name one file: the run goes on saving
         * where it was resumed from. */
        const char *ins[] = {c->in};
        const char *outs[] = {c->cm.out, c->cm.report, c->p.checkpoint};
        if (cli_outputs_clash(c->cm.cmd, ins, 1, outs, 3))
            return EXIT_USAGE;
    }
    if (c->cm.seed_given)
        c->p.seed = c->cm.seed;
    c->p.run = c->cm.run;
    c->p.report_dir = c->report_dir;
    if (relief_complete_params_validate(&c->p, &err) != RELIEF_OK)
        return cli_fail(c->cm.cmd, &err);
    return 0;
}

/* IN, refused before it is read when decoding it would not fit the memory
 * limit. */
static relief_status read_input(const complete_cli *c, relief_mesh **in, relief_error *err)
{
    struct stat sb;
    relief_read_info info;
    relief_status st;
    uint64_t limit = c->p.run.max_memory ? c->p.run.max_memory : relief_default_memory_limit();
    char what[RELIEF_ERROR_MESSAGE_MAX / 2];
    snprintf(what, sizeof what, "reading %s", c->in);
    if (stat(c->in, &sb) == 0 && S_ISREG(sb.st_mode)) {
        st = relief_memory_check(what, relief_estimate_read((uint64_t)sb.st_size), limit, "",
                                 err);
        if (st != RELIEF_OK)
            return st;
    }
    st = relief_mesh_read(c->in, in, &info, err);
    if (st == RELIEF_OK && info.nonmanifold_triangles > 0 && !c->cm.quiet)
        fprintf(stderr, "relief %s: warning: %s: %zu non-manifold triangle(s)\n", c->cm.cmd,
                c->in, info.nonmanifold_triangles);
    return st;
}

/* The report's notes: warnings always, remarks unless --quiet. */
static void print_notes(const complete_cli *c, const relief_complete_report *rep)
{
    for (int i = 0; i < rep->n_notes; ++i)
        if (rep->notes[i].warning)
            fprintf(stderr, "relief %s: warning: %s\n", c->cm.cmd, rep->notes[i].text);
        else if (!c->cm.quiet)
            fprintf(stderr, "relief %s: %s\n", c->cm.cmd, rep->notes[i].text);
}

/* What ran where, and how the growth went. */
static void print_complete(const complete_cli *c, const relief_complete_report *rep,
                           int colour)
{
    const relief_complete_params *p = &c->p;
    if (rep->backend_note[0] && (!c->cm.quiet || rep->backend_warning))
        fprintf(stderr, "relief complete: backend auto: %s\n", rep->backend_note);
    if (c->cm.quiet)
        return;
    if (!rep->backend_note[0])
        fprintf(stderr, "relief complete: backend %s: %s\n", relief_backend_name(rep->backend),
                rep->device);
    if (rep->resumed && rep->levels > 1)
        fprintf(stderr, "relief complete: resumed from %s: level %d of %d, %zu of %zu targets "
                "done\n", p->resume, rep->resumed_level, rep->levels, rep->resumed_done,
                rep->resumed_targets);
    else if (rep->resumed)
        fprintf(stderr, "relief complete: resumed from %s: %zu of %zu targets done\n",
                p->resume, rep->resumed_done, rep->resumed_targets);
    fprintf(stderr, "relief complete: %s%s, spacing %.4g: %zu samples, %zu targets; W %d, R %d, "
            "e %g, mu %g, %s search; growth memory about %.0f MiB\n",
            rep->smooth_base ? "smooth base" : relief_fit_model_name(rep->fit.prim.model),
            rep->smooth_base ? "" : " fit", rep->spacing, rep->samples, rep->targets,
            p->window, rep->rotations, p->error, p->mu >= 0 ? p->mu : colour ? 0.5 : 1.0,
            relief_search_name(rep->search), (double)rep->memory_bytes / (1024.0 * 1024.0));
    if (rep->levels > 1) {
        fprintf(stderr, "relief complete: %d levels of", rep->levels);
        for (int k = 0; k < rep->levels && k < RELIEF_COMPLETE_MAX_LEVELS; ++k)
            fprintf(stderr, " %zu%s", rep->level_vertices[k], k + 1 < rep->levels ? "," : "");
        fputs(" vertices\n", stderr);
    }
    fprintf(stderr, "relief complete: %zu targets textured in %zu passes (%zu rejections, %zu "
            "threshold raises, final e %.3g) in %.2f s -> %s\n", rep->acceptances, rep->passes,
            rep->rejections, rep->threshold_raises, rep->error_final, rep->seconds_growth,
            c->cm.out);
    if (c->cm.report)
        fprintf(stderr, "relief complete: report: %s\n", c->cm.report);
    if (c->report_dir)
        fprintf(stderr, "relief complete: report folder: %s/index.html\n", c->report_dir);
}

static void print_smooth(const complete_cli *c, const relief_complete_report *rep,
                         size_t triangles)
{
    const relief_fit_primitive *pr = &rep->fit.prim;
    if (c->cm.quiet)
        return;
    fprintf(stderr, "relief smooth: %s (rms %.3g%s%.4g), spacing %.4g (%s): %zu samples + %zu "
            "targets, %zu triangles -> %s\n", relief_fit_model_name(pr->model), rep->fit.rms,
            pr->model == RELIEF_FIT_PLANE ? "" : ", radius ",
            pr->model == RELIEF_FIT_PLANE ? 0.0 : pr->radius, rep->spacing,
            c->p.spacing > 0.0 ? "--spacing" : "from the capture", rep->samples, rep->targets,
            triangles, c->cm.out);
    if (c->cm.report)
        fprintf(stderr, "relief smooth: report: %s\n", c->cm.report);
}

/* The report, the mesh, then the folder: all of them or none. */
static relief_status write_outputs(const complete_cli *c, const relief_mesh *done,
                                   relief_complete_report *rep, relief_error *err)
{
    relief_write_options wo = {c->ascii};
    relief_status st = RELIEF_OK;
    sigset_t held;
    cli_hold_signals(&held);
    if (c->cm.report)
        st = cli_write_json(c->cm.report, rep->json, 0, NULL, NULL, err);
    if (st == RELIEF_OK) {
        st = relief_mesh_write(done, c->cm.out, &wo, err);
        if (st != RELIEF_OK && c->cm.report)
            remove(c->cm.report);
    }
    if (st == RELIEF_OK && rep->folder) {
        st = relief_report_folder_commit(rep->folder, err);
        rep->folder = NULL;
        if (st != RELIEF_OK) {
            remove(c->cm.out);
            if (c->cm.report)
                remove(c->cm.report);
        }
    }
    cli_release_signals(&held);
    return st;
}

/* After a cancel or a device failure with --checkpoint, how to go on. */
static void say_resume(const complete_cli *c, relief_status st)
{
    struct stat sb;
    if (c->p.checkpoint && (st == RELIEF_E_CANCELLED || st == RELIEF_E_DEVICE) &&
        stat(c->p.checkpoint, &sb) == 0)
        fprintf(stderr, "relief complete: state saved to %s; continue with the same command "
                "and --resume %s\n", c->p.checkpoint, c->p.checkpoint);
}

static int run(complete_cli *c, int smooth)
{
    relief_error err = {RELIEF_OK, ""};
    relief_complete_report rep;
    relief_mesh *in = NULL, *done = NULL;
    cli_progress pr;
    int ran;
    relief_status st = read_input(c, &in, &err);
    if (st != RELIEF_OK)
        return cli_fail(c->cm.cmd, &err);
    c->p.run.input_name = c->in;
    c->p.run.output_name = c->cm.out;
    c->p.measure = c->cm.report || c->report_dir;
    cli_progress_start(&pr, c->cm.cmd, c->cm.quiet);
    pr.estimate_tail = c->p.checkpoint ? " and saves the checkpoint" : "";
    c->p.run.progress = cli_progress_fn;
    c->p.run.progress_ctx = &pr;
    st = smooth ? relief_smooth(in, &c->p, &done, &rep, &err)
                : relief_complete(in, &c->p, &done, &rep, &err);
    cli_progress_close_line(&pr);
    ran = st == RELIEF_OK;
    if (ran) {
        print_notes(c, &rep);
        st = write_outputs(c, done, &rep, &err);
    }
    /* SIGINT stays ours until the outputs are in place: one during the
     * writing cancels nothing, and kills nothing half-written. */
    cli_progress_end(&pr);
    if (st == RELIEF_OK && smooth)
        print_smooth(c, &rep, relief_mesh_triangle_count(done));
    else if (st == RELIEF_OK)
        print_complete(c, &rep, relief_mesh_colours(in) != NULL);
    else
        say_resume(c, st);
    if (ran) /* an uncommitted folder goes with it */
        relief_complete_report_free(&rep);
    relief_mesh_destroy(done);
    relief_mesh_destroy(in);
    return st == RELIEF_OK ? 0 : cli_fail(c->cm.cmd, &err);
}

static int cmd_complete_or_smooth(int argc, char **argv, int smooth, int parse_only)
{
    complete_cli c;
    int rc;
    memset(&c, 0, sizeof c);
    c.cm = cli_common_init(smooth ? "smooth" : "complete");
    c.p = relief_complete_params_default();
    rc = parse(&c, argc, argv, smooth);
    if (rc)
        return rc < 0 ? 0 : rc;
    return parse_only ? 0 : run(&c, smooth);
}

int cli_cmd_complete(int argc, char **argv, int parse_only)
{
    return cmd_complete_or_smooth(argc, argv, 0, parse_only);
}

int cli_cmd_smooth(int argc, char **argv, int parse_only)
{
    return cmd_complete_or_smooth(argc, argv, 1, parse_only);
}
