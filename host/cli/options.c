/* Shared option parsing, progress and output guards of the commands
 * (options.h). */
#include "cli/options.h"
#include "cli/cli.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/output.h"
#include "base/clock.h"
#include "base/error.h"
#include "base/json.h"
#include "base/memlimit.h"
#include "base/numtext.h"
#include "complete/engine.h"
#include "report/report_dir.h"

cli_common cli_common_init(const char *cmd)
{
    cli_common c;
    memset(&c, 0, sizeof c);
    c.cmd = cmd;
    return c;
}

int cli_common_option(cli_common *cm, int c, const char *arg)
{
    switch (c) {
    case 'o': cm->out = arg; return 1;
    case OPT_REPORT: cm->report = arg; return 1;
    case OPT_QUIET: cm->quiet = 1; return 1;
    case OPT_MAX_SECONDS: {
        char *end;
        double v = relief_strtod(arg, &end);
        if (end == arg || *end != '\0' || !(v >= 0.0) || !isfinite(v)) {
            fprintf(stderr, "relief %s: --max-seconds: '%s' is not a number of seconds >= 0\n",
                    cm->cmd, arg);
            return -1;
        }
        cm->max_seconds = v;
        return 1;
    }
    case OPT_MASK: cm->mask = arg; return 1;
    case OPT_SEED: {
        long s;
        if (!cli_parse_long(cm->cmd, "--seed", arg, 0, (long)UINT32_MAX, &s))
            return -1;
        cm->seed = (uint32_t)s;
        cm->seed_given = 1;
        return 1;
    }
    }
    return 0;
}

int cli_one_input(cli_common *cm, int argc, char **argv, const char *what,
                  const char **in)
{
    if (optind >= argc) {
        cli_usage_error(cm->cmd, "missing %s", what);
        return 0;
    }
    if (argc - optind > 1) {
        cli_usage_error(cm->cmd, "unexpected argument '%s'", argv[optind + 1]);
        return 0;
    }
    *in = argv[optind];
    if (!cm->out && (cm->shared & CLI_OUTPUT)) {
        cli_usage_error(cm->cmd, "%smissing -o OUT", "");
        return 0;
    }
    return 1;
}

int cli_fail(const char *cmd, const relief_error *err)
{
    fprintf(stderr, "relief %s: error: %s\n", cmd,
            err->message[0] ? err->message : relief_strerror(err->status));
    /* Stopped by a signal: 128 + its number, as a shell reports a process
     * the signal killed (SIGINT's 130 is the status's own). */
    if (err->status == RELIEF_E_CANCELLED && cli_signal())
        return 128 + cli_signal();
    return relief_status_exit_code(err->status);
}

int cli_parse_hole_mask(const char *cmd, const char *arg, int *labels, int *has_ball,
                        double ball[4])
{
    int k = 0;
    *labels = *has_ball = 0;
    if (strcmp(arg, "label") == 0) {
        *labels = 1;
        return 1;
    }
    if (strncmp(arg, "ball:", 5) != 0 ||
        !cli_parse_reals(cmd, "--hole-mask", arg + 5, ball, 4, &k) || k != 4) {
        cli_usage_error(cmd, "--hole-mask: expected 'label' or 'ball:X,Y,Z,R' with R > 0, got "
                        "'%s'", arg);
        return 0;
    }
    *has_ball = 1;
    return 1;
}

int cli_usage_error(const char *cmd, const char *fmt, const char *arg)
{
    fprintf(stderr, "relief %s: ", cmd);
    fprintf(stderr, fmt, arg);
    fprintf(stderr, "\nTry 'relief %s --help'.\n", cmd);
    return EXIT_USAGE;
}

int cli_parse_long(const char *cmd, const char *opt, const char *s, long lo, long hi,
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

int cli_parse_real(const char *cmd, const char *opt, const char *s, double *out)
{
    char *end;
    double v;
    errno = 0;
    v = relief_strtod(s, &end);
    if (end == s || *end != '\0' || errno != 0 || !isfinite(v)) {
        fprintf(stderr, "relief %s: %s: '%s' is not a finite number\n", cmd, opt, s);
        return 0;
    }
    *out = v;
    return 1;
}

/* Comma-separated reals, each checked as cli_parse_real does. */
int cli_parse_reals(const char *cmd, const char *opt, const char *s, double *out, int max,
                    int *n)
{
    char buf[256], *tok, *save = NULL;
    if (strlen(s) >= sizeof buf) {
        fprintf(stderr, "relief %s: %s: '%.40s...' is too long\n", cmd, opt, s);
        return 0;
    }
    snprintf(buf, sizeof buf, "%s", s);
    *n = 0;
    for (tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        if (*n == max) {
            fprintf(stderr, "relief %s: %s: more than %d values in '%s'\n", cmd, opt, max, s);
            return 0;
        }
        if (!cli_parse_real(cmd, opt, tok, &out[*n]))
            return 0;
        ++*n;
    }
    return 1;
}

int cli_parse_enum(const char *cmd, const char *opt, const char *s, const char *const *names,
                   int n, int *out)
{
    for (int i = 0; i < n; ++i)
        if (strcmp(s, names[i]) == 0) {
            *out = i;
            return 1;
        }
    fprintf(stderr, "relief %s: %s: '%s' is not one of", cmd, opt, s);
    for (int i = 0; i < n; ++i)
        fprintf(stderr, "%s %s", i ? "," : "", names[i]);
    fprintf(stderr, "\nTry 'relief %s --help'.\n", cmd);
    return 0;
}

int cli_same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    const char *na, *nb;
    char *da, *db;
    int same, ha, hb;
    if (!a || !b)
        return 0;
    if (strcmp(a, b) == 0)
        return 1;
    ha = stat(a, &sa) == 0, hb = stat(b, &sb) == 0;
    if (ha || hb) /* one is there: the same inode */
        return ha && hb && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    da = relief_output_split(a, &na), db = relief_output_split(b, &nb);
    same = da && db && *na && strcmp(na, nb) == 0 && cli_same_file(da, db);
    free(da);
    free(db);
    return same;
}

/* Print "relief CMD: OPT: 'PATH' <why, with arg>"; EXIT_USAGE. */
static int refuse(const char *cmd, const cli_output *o, const char *why, const char *arg)
{
    fprintf(stderr, "relief %s: %s: '%s' ", cmd, o->opt, o->path);
    fprintf(stderr, why, arg);
    fputc('\n', stderr);
    return EXIT_USAGE;
}

/* One output on its own: a plain file, or none yet, in a writable folder. */
static int check_output(const char *cmd, const cli_output *o)
{
    struct stat sb;
    const char *name;
    char *dir;
    int rc = 0;
    if (o->kind == CLI_OUT_FOLDER) {
        relief_error err = {0};
        if (relief_report_dir_check(o->path, &err) == RELIEF_OK)
            return 0;
        fprintf(stderr, "relief %s: %s: %s\n", cmd, o->opt, err.message);
        return relief_status_exit_code(err.status);
    }
    if (stat(o->path, &sb) == 0 && S_ISDIR(sb.st_mode))
        return refuse(cmd, o, "is a folder; %s names a file", o->opt);
    if (stat(o->path, &sb) == 0 && !S_ISREG(sb.st_mode))
        return refuse(cmd, o, "%sis there and is not a plain file", "");
    if (!(dir = relief_output_split(o->path, &name)))
        return refuse(cmd, o, "%s: cannot allocate a path", "");
    if (!*name)
        rc = refuse(cmd, o, "is a folder's name; %s names a file", o->opt);
    else if (stat(dir, &sb) != 0 || !S_ISDIR(sb.st_mode))
        rc = refuse(cmd, o, "cannot be written: the folder '%s' does not exist", dir);
    else if (access(dir, W_OK | X_OK) != 0) {
        /* The system's reason: a read-only file system is no permission
         * problem, and is a resource failure (exit 2). */
        const int e = errno;
        fprintf(stderr, "relief %s: %s: '%s' cannot be written in '%s': %s\n", cmd, o->opt,
                o->path, dir, strerror(e));
        rc = relief_status_exit_code(relief_errno_status(e));
    }
    free(dir);
    return rc;
}

int cli_check_outputs(const char *cmd, const char *const *ins, size_t n_ins,
                      const cli_output *outs, size_t n_outs)
{
    for (size_t o = 0; o < n_outs; ++o) {
        if (!outs[o].path)
            continue;
        for (size_t i = 0; i < n_ins; ++i)
            if (cli_same_file(ins[i], outs[o].path))
                return refuse(cmd, &outs[o], "is an input; relief never overwrites its "
                              "input%s", "");
        for (size_t p = 0; p < o; ++p)
            if (cli_same_file(outs[p].path, outs[o].path))
                return refuse(cmd, &outs[o], "is also named by %s: one file per output",
                              outs[p].opt);
        int rc = check_output(cmd, &outs[o]);
        if (rc)
            return rc;
    }
    return 0;
}

/* The test hooks of writing: RELIEF_TEST_OUTPUT_FAIL=N fails the N-th
 * step (base/output.h: each file written, the journal, each link and
 * rename, the commit), as a full disk or a vanished folder would;
 * RELIEF_TEST_OUTPUT_KILL=N kills the process there (SIGKILL), as a power
 * cut would. */
typedef struct output_hooks {
    unsigned long fail, kill;
} output_hooks;

static int output_hook(void *ctx, unsigned step, const char *what)
{
    const output_hooks *h = ctx;
    if (h->kill == step) {
        fprintf(stderr, "relief: test hook: killed at step %u (%s)\n", step, what);
        raise(SIGKILL);
    }
    return h->fail == step;
}

/* What cli_sink hands the command's writer. */
typedef struct cli_job {
    cli_write_fn write;
    void *ctx;
    size_t i;
} cli_job;

static relief_status cli_sink(relief_sink *s, void *ctx, relief_error *err)
{
    const cli_job *j = ctx;
    return j->write(j->ctx, j->i, s, err);
}

/* Stage every asked file of outs, then *folder. */
static relief_status stage_all(relief_outputs *o, const cli_output *outs, size_t n,
                               cli_write_fn write, void *ctx, relief_report_folder **folder,
                               relief_error *err)
{
    relief_status st = RELIEF_OK;
    for (size_t i = 0; i < n && i < CLI_MAX_OUTPUTS && st == RELIEF_OK; ++i)
        if (outs[i].path && outs[i].kind == CLI_OUT_FILE) {
            cli_job job = {write, ctx, i};
            st = relief_outputs_file(o, outs[i].path, cli_sink, &job, err);
        }
    if (st == RELIEF_OK && folder && *folder) {
        relief_staged_folder *s = relief_report_folder_release(*folder);
        *folder = NULL;
        st = relief_outputs_folder(o, &s, relief_report_dir_replaceable, err);
    }
    return st;
}

relief_status cli_write_outputs(const cli_output *outs, size_t n, cli_write_fn write,
                                void *ctx, relief_report_folder **folder, relief_error *err)
{
    const char *fail = getenv("RELIEF_TEST_OUTPUT_FAIL"), *kill = getenv("RELIEF_TEST_OUTPUT_KILL");
    output_hooks hooks = {fail ? strtoul(fail, NULL, 10) : 0, kill ? strtoul(kill, NULL, 10) : 0};
    relief_outputs *o = NULL;
    relief_status st;
    sigset_t held;
    cli_hold_signals(&held);
    if (cli_signal())
        st = relief_fail(err, RELIEF_E_CANCELLED, "interrupted by %s: nothing written",
                         cli_signal_name(cli_signal()));
    else
        st = relief_outputs_begin(&o, err);
    if (st == RELIEF_OK) {
        relief_outputs_set_hook(o, output_hook, &hooks);
        st = stage_all(o, outs, n, write, ctx, folder, err);
        if (st == RELIEF_OK)
            st = relief_outputs_commit(o, err);
        else
            relief_outputs_abort(o);
    }
    cli_release_signals(&held);
    return st;
}

const char *cli_ext_of(const char *path)
{
    const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
    return dot && (!slash || dot > slash) ? dot : "";
}

int cli_known_mesh_ext(const char *path)
{
    const char *e = cli_ext_of(path);
    return strcasecmp(e, ".ply") == 0 || strcasecmp(e, ".obj") == 0 ||
           strcasecmp(e, ".off") == 0 || strcasecmp(e, ".stl") == 0;
}

/* SIGINT, SIGTERM, SIGHUP or SIGQUIT during a command: the signal's
 * number, set by the handler, read by cli_progress_fn (which cancels the
 * engine's call) and by cli_write_outputs (which then writes nothing).
 * The command line's one piece of global state: a signal handler can
 * reach nothing else (C11 7.14.1.1). The library has none. */
static volatile sig_atomic_t interrupted = 0;

static const int held_signals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT};
#define N_HELD (sizeof held_signals / sizeof held_signals[0])

static void on_signal(int sig)
{
    interrupted = sig;
}

void cli_take_signals(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    /* A first signal stops the command cleanly; SA_RESETHAND lets a second
     * one act as usual (a kill). */
    sa.sa_flags = SA_RESETHAND;
    sigemptyset(&sa.sa_mask);
    interrupted = 0;
    for (size_t i = 0; i < N_HELD; ++i) {
        struct sigaction old;
        /* A signal the caller ignores (nohup's SIGHUP) stays ignored. */
        if (sigaction(held_signals[i], NULL, &old) == 0 && old.sa_handler == SIG_IGN)
            continue;
        sigaction(held_signals[i], &sa, NULL);
    }
}

int cli_signal(void)
{
    return (int)interrupted;
}

const char *cli_signal_name(int sig)
{
    return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : sig == SIGHUP ? "SIGHUP"
           : sig == SIGQUIT ? "SIGQUIT" : "a signal";
}

void cli_progress_start(cli_progress *pr, const cli_common *cm, relief_run_options *run)
{
    const char *cmd = cm->cmd;
    const int quiet = cm->quiet;
    const char *after = getenv("RELIEF_TEST_SIGINT_AFTER");
    const char *scale = getenv("RELIEF_TEST_ESTIMATE_SCALE");
    memset(pr, 0, sizeof *pr);
    pr->cmd = cmd;
    pr->print = !quiet && isatty(2);
    pr->estimate = !quiet;
    pr->estimate_tail = "";
    pr->start = relief_seconds();
    pr->last = -1.0;
    pr->base = -1.0;
    pr->max_seconds = cm->max_seconds;
    pr->estimate_after = 2.0;
    pr->estimate_min = 60.0;
    pr->estimate_settle = 10.0;
    pr->estimate_scale = 1.0;
    if (getenv("RELIEF_TEST_ESTIMATE_NOW"))
        pr->estimate_after = pr->estimate_min = pr->estimate_settle = 0.0;
    if (scale && relief_strtod(scale, NULL) > 0.0)
        pr->estimate_scale = relief_strtod(scale, NULL);
    if (after)
        pr->sigint_after = strtoul(after, NULL, 10);
    if (run)
        run->progress = cli_progress_fn, run->progress_ctx = pr;
}

/* The time left by the recent rate: from a mark that moves up as the call
 * goes on (a growth scores its first targets slower than its last, so the
 * rate since the start overstates what is left), never from before the
 * engine's first report (reading and set-up are not its rate), and only
 * once estimate_after seconds of it have run; -1 when there is none yet. */
static double time_left(cli_progress *pr, double fraction, double t)
{
    double ran, moved;
    if (t - pr->mark[1] >= fmax(2.0, pr->mark[1] - pr->base)) {
        pr->mark[0] = pr->mark[1], pr->mark_fraction[0] = pr->mark_fraction[1];
        pr->mark[1] = t, pr->mark_fraction[1] = fraction;
    }
    ran = t - pr->mark[0];
    moved = fraction - pr->mark_fraction[0];
    if (t - pr->base < pr->estimate_after || !(moved > 0.0) || !(ran > 0.0))
        return -1.0;
    return fraction >= 1.0 ? 0.0 : pr->estimate_scale * ran * (1.0 - fraction) / moved;
}

/* Once, when a call looks long: the time left. */
static void say_estimate(cli_progress *pr, double fraction, double t, double left)
{
    pr->estimate = 0;
    if (left < pr->estimate_min)
        return;
    fprintf(stderr, "%srelief %s: estimated about %.1f min more (%.1f %% done after %.0f s); "
            "SIGINT stops it%s\n", pr->open ? "\r" : "", pr->cmd, left / 60.0,
            100.0 * fraction, t, pr->estimate_tail);
    pr->open = 0;
}

/* --max-seconds (issue 60): the run stops only once its elapsed time has
 * passed the limit. An estimate never stops it: with another process on
 * the core a complete-points run of 15 s was estimated at 6379 s after 12
 * s, and stopped. Once the estimate has had 5 s or 2 % of the call to
 * settle and the whole call looks longer than the limit, one warning says
 * so (with --quiet too: it is about the limit the user set). */
static int over_limit(cli_progress *pr, double fraction, double t, double left)
{
    const int settled = left >= 0.0 && (t - pr->base >= 5.0 ||
                                        fraction - pr->base_fraction >= 0.02);
    if (!(pr->max_seconds > 0.0))
        return 0;
    if (t > pr->max_seconds) {
        snprintf(pr->limit, sizeof pr->limit, "stopped after %.2f s, over --max-seconds %g, "
                 "with %.1f %% done", t, pr->max_seconds, 100.0 * fraction);
        return 1;
    }
    if (!pr->limit_warned && settled && t + left > pr->max_seconds) {
        pr->limit_warned = 1;
        fprintf(stderr, "%srelief %s: warning: the run may take about %.0f s in all (%.1f %% "
                "done after %.1f s), over --max-seconds %g; it goes on, and stops only if it "
                "passes %g s\n", pr->open ? "\r" : "", pr->cmd, t + left, 100.0 * fraction, t,
                pr->max_seconds, pr->max_seconds);
        pr->open = 0;
    }
    return 0;
}

int cli_progress_fn(void *ctx, double fraction)
{
    cli_progress *pr = ctx;
    double now = relief_seconds(), t = now - pr->start, left;
    /* The base: the first report, then the first that moved on. An engine
     * may set up for long before its first step (a search index), and one
     * step over that time is no rate. */
    if (pr->base < 0.0 || (!pr->based && fraction > pr->base_fraction)) {
        pr->based = pr->base >= 0.0;
        pr->base = pr->mark[0] = pr->mark[1] = t;
        pr->base_fraction = pr->mark_fraction[0] = pr->mark_fraction[1] = fraction;
    }
    left = time_left(pr, fraction, t);
    /* The one-time estimate waits for the rate to settle a little. */
    if (pr->estimate && left >= 0.0 &&
        (t - pr->base >= pr->estimate_settle || fraction - pr->base_fraction >= 0.05))
        say_estimate(pr, fraction, t, left);
    if (pr->print && (fraction >= 1.0 || pr->last < 0 || now - pr->last >= 0.25)) {
        pr->last = now;
        pr->open = 1;
        fprintf(stderr, "\rrelief %s: %5.1f %%, ETA %.0f s   ", pr->cmd, 100.0 * fraction,
                left > 0.0 ? left : 0.0);
    }
    /* The test hook counts the steps that moved (a growth's acceptances). */
    if (pr->sigint_after && fraction > pr->fraction && ++pr->seen == pr->sigint_after)
        raise(SIGINT);
    pr->fraction = fraction > pr->fraction ? fraction : pr->fraction;
    return interrupted != 0 || pr->limit[0] != '\0' || over_limit(pr, fraction, t, left);
}

int cli_progress_explain(const cli_progress *pr, relief_status st, relief_error *err)
{
    if (st != RELIEF_E_CANCELLED || pr->limit[0] == '\0')
        return 0;
    relief_fail(err, RELIEF_E_RANGE, "%s; raise --max-seconds (0: no limit) or make the run "
                "smaller", pr->limit);
    return 1;
}

void cli_progress_close_line(cli_progress *pr)
{
    if (pr->open)
        fputc('\n', stderr);
    pr->open = 0;
}

void cli_progress_end(cli_progress *pr)
{
    cli_progress_close_line(pr);
}

/* Outputs appear whole or not at all even on Ctrl-C, SIGTERM, SIGHUP or
 * SIGQUIT: they are held back while the files are staged and committed
 * (temporaries, then renames) and delivered once every file is in place
 * or removed. The test hook RELIEF_TEST_SIGINT_IN_WRITE raises SIGINT
 * just as the writing starts. */
void cli_hold_signals(sigset_t *old)
{
    sigset_t set;
    sigemptyset(&set);
    for (size_t i = 0; i < N_HELD; ++i)
        sigaddset(&set, held_signals[i]);
    sigprocmask(SIG_BLOCK, &set, old);
    if (getenv("RELIEF_TEST_SIGINT_IN_WRITE"))
        raise(SIGINT); /* pending until release_signals */
}

void cli_release_signals(const sigset_t *old)
{
    sigprocmask(SIG_SETMASK, old, NULL);
}

/* The engine's object with the named members and `member` spliced in after
 * its "{\n". */
static int print_json_with(FILE *f, const char *json, size_t n, const char *const *keys,
                           const char *const *values, const char *member)
{
    if ((n || member) && strncmp(json, "{\n", 2) == 0) {
        fputs("{\n", f);
        for (size_t i = 0; i < n; ++i) {
            fprintf(f, "  ");
            rj_put_string(f, keys[i]);
            fputs(": ", f);
            if (values[i])
                rj_put_string(f, values[i]);
            else
                fputs("null", f);
            fputs(",\n", f);
        }
        if (member)
            fprintf(f, "  %s,\n", member);
        json += 2;
    }
    return fputs(json, f) < 0 || ferror(f);
}

int cli_print_json(FILE *f, const char *json, size_t n, const char *const *keys,
                   const char *const *values)
{
    return print_json_with(f, json, n, keys, values, NULL);
}

relief_status cli_json_to(relief_sink *s, const char *json, size_t n,
                          const char *const *keys, const char *const *values,
                          relief_error *err)
{
    return cli_json_with_to(s, json, n, keys, values, NULL, err);
}

relief_status cli_json_with_to(relief_sink *s, const char *json, size_t n,
                               const char *const *keys, const char *const *values,
                               const char *member, relief_error *err)
{
    errno = 0;
    if (print_json_with(s->f, json, n, keys, values, member) != 0)
        return relief_fail_errno(err, errno ? errno : EIO, s->path, "cannot write");
    return RELIEF_OK;
}

relief_status cli_read_mesh(const char *cmd, const char *path, int quiet, relief_mesh **out,
                            relief_read_info *info, relief_error *err)
{
    relief_read_info local;
    char text[RELIEF_ERROR_MESSAGE_MAX];
    if (!info)
        info = &local;
    relief_status st = relief_mesh_read(path, out, info, err);
    if (st == RELIEF_OK && !quiet &&
        relief_repair_info_describe(&info->repair, text, sizeof text) > 0)
        fprintf(stderr, "relief %s: warning: %s: repaired on reading: %s\n", cmd, path, text);
    return st;
}

void cli_repair_json(const relief_read_info *info, char *text, size_t size)
{
    const relief_repair_info *r = &info->repair;
    snprintf(text, size,
             "\"input_repair\": {\"nonmanifold_triangles_in_file\": %zu, "
             "\"vertices_welded\": %zu, \"degenerate_triangles\": %zu, "
             "\"duplicate_triangles\": %zu, \"nonmanifold_edges\": %zu, "
             "\"nonmanifold_edge_triangles\": %zu, \"triangles_flipped\": %zu, "
             "\"orientation_triangles\": %zu, \"nonmanifold_vertices\": %zu, "
             "\"vertices_added\": %zu, \"small_components\": %zu, "
             "\"small_component_triangles\": %zu, \"unstorable_triangles\": %zu, "
             "\"vertices_unused\": %zu}",
             info->nonmanifold_triangles, r->vertices_welded, r->degenerate_triangles,
             r->duplicate_triangles, r->nonmanifold_edges, r->nonmanifold_edge_triangles,
             r->triangles_flipped, r->orientation_triangles, r->nonmanifold_vertices,
             r->vertices_added, r->small_components, r->small_component_triangles,
             r->unstorable_triangles, r->vertices_unused);
}

void cli_image_rgb8(const relief_image *c, uint8_t *rgb)
{
    size_t stride = c->stride ? c->stride : (size_t)c->width * c->channels * c->bit_depth / 8;
    for (int y = 0; y < c->height; ++y)
        for (int x = 0; x < c->width; ++x)
            for (int k = 0; k < 3; ++k) {
                int ch = c->channels >= 3 ? k : 0;
                const uint8_t *row = (const uint8_t *)c->data + (size_t)y * stride;
                size_t i = (size_t)x * c->channels + ch;
                uint16_t v = row[i];
                if (c->bit_depth == 16)
                    memcpy(&v, row + 2 * i, sizeof v), v >>= 8;
                rgb[3 * ((size_t)y * c->width + x) + k] = (uint8_t)v;
            }
}
