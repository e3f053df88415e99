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
#include "cli/batch.h"
#include "cli/options.h"
#include "mesh/mesh.h"

enum { CO_ASCII = OPT_COMMAND, CO_HOLE_MASK };

static const cli_own own[] = {{"ascii", CO_ASCII, NULL, "write ascii PLY (default binary)"},
                              {"hole-mask", CO_HOLE_MASK, "WHAT",
                               "fill exactly the holes whose rims touch WHAT, whatever their "
                               "size (over a primitive, only holes; a border, or a rim wider "
                               "than max_hole, only where WHAT touches it): ball:X,Y,Z,R or "
                               "label (the capture's vertices with a non-zero PLY label)"},
                              {NULL, 0, NULL, NULL}};
static const char *const skip[] = {"measure", NULL};

static cli_spec spec(int smooth)
{
    cli_spec s = {"complete", "IN -o OUT [options]",
                  "Fit a primitive to the partial capture IN (or smooth the capture into a "
                  "base when none fits), lay the missing part on it, and grow the "
                  "capture's relief and colour over it (papers 000 and 001). Writes OUT "
                  "(PLY with a per-vertex `label`: 0 captured, 1 completed).",
                  CLI_OUTPUT | CLI_REPORT | CLI_QUIET | CLI_LIMIT,
                  "the completed mesh (.ply, .obj, .off, .stl); required", NULL, NULL, 0,
                  skip, own,
                  "SIGINT stops the growth between two targets, saves the checkpoint when "
                  "one is asked for, writes no output and exits 130; a second SIGINT kills "
                  "at once."};
    s.params = relief_complete_param_table(&s.n_params);
    if (smooth) {
        s.name = "smooth";
        s.about = "Fit a primitive to the partial capture IN and complete it smoothly (no "
                  "relief yet): the capture's samples and target vertices laid on the "
                  "primitive over the missing region, in one manifold triangulation. OUT's "
                  "per-vertex `label` is 0 for samples and 1 for targets.";
        s.out_help = "the output mesh; required";
        s.params = relief_smooth_param_table(&s.n_params);
        s.tail = NULL;
    }
    return s;
}

/* What the command line adds to the engine's parameters. */
typedef struct complete_cli {
    cli_common cm;
    relief_complete_params p;
    const char *in;
    int smooth, ascii;
    relief_read_info read; /* what reading IN repaired, for the report */
    cli_output outs[4]; /* -o, --report, --checkpoint, --report-dir */
    int had_checkpoint;      /* --checkpoint's file was there before the run, */
    struct stat checkpoint; /* as this */
} complete_cli;

static int take(void *ctx, int id, const char *arg)
{
    complete_cli *c = ctx;
    if (id == CO_ASCII) {
        c->ascii = 1;
        return 1;
    }
    return cli_parse_hole_mask(c->cm.cmd, arg, &c->p.hole_labels, &c->p.has_hole_ball,
                               c->p.hole_ball);
}

/* Parse the options into c: 0 to go on, -1 after --help, else the exit
 * status. */
static int parse(complete_cli *c, int argc, char **argv, int smooth)
{
    const cli_spec s = spec(smooth);
    return cli_parse(&s, &c->cm, &c->p, take, c, argc, argv);
}

/* The files and the parameters of one run (c->in to c->cm.out): 0 when
 * they will do, else the exit status (said). */
static int check(complete_cli *c)
{
    relief_error err = {0};
    /* --resume and --checkpoint may name one file: the run goes on saving
     * where it was resumed from. */
    const cli_output outs[] = {{"-o", c->cm.out, CLI_OUT_FILE},
                               {"--report", c->cm.report, CLI_OUT_FILE},
                               {"--checkpoint", c->p.checkpoint, CLI_OUT_ENGINE},
                               {"--report-dir", c->p.report_dir, CLI_OUT_FOLDER}};
    if (!cli_known_mesh_ext(c->cm.out))
        return cli_usage_error(c->cm.cmd, "-o: '%s' has no known mesh extension (.ply, .obj, "
                               ".off, .stl)", c->cm.out);
    memcpy(c->outs, outs, sizeof outs);
    const int check_rc = cli_check_outputs(c->cm.cmd, &c->in, 1, c->outs, 4);
    if (check_rc)
        return check_rc;
    if (relief_complete_params_validate(&c->p, &err) != RELIEF_OK)
        return cli_fail(c->cm.cmd, &err);
    return 0;
}

/* IN, refused before it is read when decoding it would not fit the memory
 * limit. */
static relief_status read_input(complete_cli *c, relief_mesh **in, relief_error *err)
{
    struct stat sb;
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
    return cli_read_mesh(c->cm.cmd, c->in, c->cm.quiet, in, &c->read, err);
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
    if (p->report_dir)
        fprintf(stderr, "relief complete: report folder: %s/index.html\n", p->report_dir);
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

/* What write_one writes: the mesh (-o) and the report. */
typedef struct complete_out {
    const complete_cli *c;
    const relief_mesh *done;
    const char *json;
    const char *repair; /* the "input_repair" member (cli_repair_json) */
} complete_out;

static relief_status write_one(void *ctx, size_t i, relief_sink *s, relief_error *err)
{
    const complete_out *o = ctx;
    relief_write_options wo = {o->c->ascii};
    return i == 0 ? relief_mesh_write_to(o->done, s, &wo, err)
                  : cli_json_with_to(s, o->json, 0, NULL, NULL, o->repair, err);
}

/* After a cancel or a device failure with --checkpoint, how to go on: only
 * when this run saved the file (a save renames a new one into place), never
 * on the strength of an older checkpoint that a failed save left there. */
static void say_resume(const complete_cli *c, relief_status st)
{
    struct stat sb;
    if (c->p.checkpoint && (st == RELIEF_E_CANCELLED || st == RELIEF_E_DEVICE) &&
        stat(c->p.checkpoint, &sb) == 0 &&
        (!c->had_checkpoint || sb.st_ino != c->checkpoint.st_ino ||
         sb.st_dev != c->checkpoint.st_dev))
        fprintf(stderr, "relief complete: state saved to %s; continue with the same command "
                "and --resume %s\n", c->p.checkpoint, c->p.checkpoint);
}

static int run(complete_cli *c, int smooth)
{
    relief_error err = {0};
    relief_complete_report rep;
    relief_mesh *in = NULL, *done = NULL;
    cli_progress pr;
    int ran;
    relief_status st = read_input(c, &in, &err);
    if (st != RELIEF_OK)
        return cli_fail(c->cm.cmd, &err);
    c->p.run.input_name = c->in;
    c->p.run.output_name = c->cm.out;
    c->p.measure = c->cm.report || c->p.report_dir;
    c->had_checkpoint = c->p.checkpoint && stat(c->p.checkpoint, &c->checkpoint) == 0;
    cli_progress_start(&pr, &c->cm, &c->p.run);
    pr.estimate_tail = c->p.checkpoint ? " and saves the checkpoint" : "";
    st = smooth ? relief_smooth(in, &c->p, &done, &rep, &err)
                : relief_complete(in, &c->p, &done, &rep, &err);
    cli_progress_close_line(&pr);
    cli_progress_explain(&pr, st, &err);
    ran = st == RELIEF_OK;
    if (ran) {
        char repair[1024];
        complete_out o = {c, done, rep.json, repair};
        cli_repair_json(&c->read, repair, sizeof repair);
        print_notes(c, &rep);
        st = cli_write_outputs(c->outs, 4, write_one, &o, &rep.folder, &err);
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

/* One input (c->in to c->cm.out): the checks, then, unless parse_only,
 * the run. Returns the exit status. */
static int one(complete_cli *c, int parse_only)
{
    int rc = check(c);
    return rc ? rc : parse_only ? 0 : run(c, c->smooth);
}

/* A batch's run on one input (batch.h): a copy of the job, quiet. */
static int batch_one(const void *job, const char *in, const char *out)
{
    complete_cli c = *(const complete_cli *)job;
    c.in = in, c.cm.out = out, c.cm.quiet = 1;
    return one(&c, 0);
}

static int cmd_complete_or_smooth(int argc, char **argv, int smooth, int parse_only)
{
    complete_cli c;
    int rc;
    memset(&c, 0, sizeof c);
    c.cm = cli_common_init(smooth ? "smooth" : "complete");
    c.p = relief_complete_params_default();
    c.smooth = smooth;
    rc = parse(&c, argc, argv, smooth);
    if (rc)
        return rc < 0 ? 0 : rc;
    if (cli_batch_asked(&c.cm, argc)) {
        const cli_batch b = {".ply", batch_one, &c,
                             {{"--report", c.cm.report}, {"--checkpoint", c.p.checkpoint},
                              {"--report-dir", c.p.report_dir}, {"--resume", c.p.resume}}};
        return cli_batch_run(&c.cm, &b, argv + optind, argc - optind, parse_only);
    }
    if (!cli_one_input(&c.cm, argc, argv, "input mesh IN", &c.in))
        return EXIT_USAGE;
    return one(&c, parse_only);
}

int cli_cmd_complete(int argc, char **argv, int parse_only)
{
    return cmd_complete_or_smooth(argc, argv, 0, parse_only);
}

int cli_cmd_smooth(int argc, char **argv, int parse_only)
{
    return cmd_complete_or_smooth(argc, argv, 1, parse_only);
}
