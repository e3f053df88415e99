/* What every command shares: exit codes, the options common to the
 * engines' commands (-o, --report, --quiet, --seed, --backend, --device,
 * --max-memory, --mask), enumerations parsed through the public headers'
 * name lists, numbers parsed for their syntax only (each engine's
 * _validate checks their ranges and names the parameter), the checks on
 * output paths, progress with SIGINT, and the signal guard around writing
 * outputs. Each parser prints its own message on stderr ("relief CMD:
 * --opt: ...") and returns 0 on a bad value, 1 on a good one. */
#ifndef RELIEF_HOST_CLI_OPTIONS_H
#define RELIEF_HOST_CLI_OPTIONS_H

#include <getopt.h>
#include <signal.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "relief/relief.h"
#include "base/output.h"

#define EXIT_USAGE 1
#define EXIT_INTERNAL 2

/* Long options without a short form: ids above any character. The shared
 * ones first; commands number their own from OPT_COMMAND. */
enum { OPT_REPORT = 256, OPT_QUIET, OPT_SEED, OPT_MASK, OPT_MAX_SECONDS, OPT_COMMAND = 300 };

/* Which shared options a command takes (cli_options). */
enum {
    CLI_OUTPUT = 1u << 0,     /* -o, --output */
    CLI_REPORT = 1u << 1,     /* --report R.json */
    CLI_QUIET = 1u << 2,      /* --quiet */
    CLI_SEED = 1u << 3,       /* --seed N (an engine's seed is its parameter's) */
    CLI_MASK = 1u << 4,       /* --mask MASK */
    CLI_LIMIT = 1u << 5       /* --max-seconds S (an engine run with progress) */
};

/* Entries of an engine's table a command can offer. */
#define CLI_MAX_PARAMS 128

/* What the shared options set. */
typedef struct cli_common {
    const char *cmd;            /* "complete", for messages */
    unsigned shared;            /* the spec's CLI_*: -o is required with CLI_OUTPUT */
    const char *out, *report, *mask;
    int quiet;
    double max_seconds;         /* --max-seconds; 0: no limit */
    int seed_given;             /* 1 when --seed was given: */
    uint32_t seed;
    unsigned char given[CLI_MAX_PARAMS / 8]; /* bit i: the spec's params[i] was given */
} cli_common;

/* Defaults: nothing given. */
cli_common cli_common_init(const char *cmd);

/* One option of a command's own, not an engine parameter: its long name,
 * its getopt id (from OPT_COMMAND), the value it takes (NULL: a flag) and
 * what it does. A list ends with a NULL name. */
typedef struct cli_own {
    const char *name;
    int id;
    const char *arg;
    const char *help;
} cli_own;

/* A command, for its parser and its help: the shared options it takes,
 * the parameters of its engine's table (relief_param: --min-window sets
 * min_window; a flag's --name sets 1 and --no-name 0), and its own. */
typedef struct cli_spec {
    const char *name;           /* "image-fill" */
    const char *usage;          /* after "relief NAME ": "IN -o OUT [options]" */
    const char *about;          /* what it does, paragraphs ("\n\n" between) */
    unsigned shared;            /* CLI_* it takes */
    const char *out_help;       /* -o's help, when CLI_OUTPUT */
    const char *mask_help;      /* --mask's help, when CLI_MASK */
    const relief_param *params; /* the engine's table, or NULL */
    size_t n_params;
    const char *const *skip;    /* table entries it does not offer (NULL last), or NULL */
    const cli_own *own;         /* its own options, or NULL */
    const char *tail;           /* said after the options, or NULL */
} cli_spec;

/* Print the help of `s` (usage, what it does, every option with its value
 * and what it does) to f; `params` (may be NULL) holds the defaults a
 * flag is shown against (--no-name when it is on). */
void cli_help(const cli_spec *s, const void *params, FILE *f);

/* The help in another form, from the same spec: CLI_HELP_MAN, the
 * command's section of relief(1) (troff); CLI_HELP_MARKDOWN, its options
 * as the table of its page in docs/. cli_parse answers --help-man and
 * --help-markdown with them. */
enum { CLI_HELP_TEXT = 1, CLI_HELP_MAN, CLI_HELP_MARKDOWN };
void cli_help_as(const cli_spec *s, const void *params, FILE *f, int format);

/* Parse argv: the shared options into cm, the table's into `params`, the
 * command's own through take(ctx, id, arg) (1 taken, 0 a bad value, said
 * on stderr). Returns 0 to go on, -1 after --help, else the exit status. */
int cli_parse(const cli_spec *s, cli_common *cm, void *params,
              int (*take)(void *ctx, int id, const char *arg), void *ctx, int argc,
              char **argv);

/* Did the command line give the parameter `name` ("window") of s's
 * table, in any spelling (--window, --wind=9, --no-NAME)? After cli_parse. */
int cli_param_given(const cli_common *cm, const cli_spec *s, const char *name);

/* Take shared option `c` (a getopt_long id) with `arg`: 1 taken, 0 not a
 * shared option, -1 a bad value (said on stderr: exit EXIT_USAGE). */
int cli_common_option(cli_common *cm, int c, const char *arg);

/* "IN -o OUT": the one operand (`what` when missing), and -o when the
 * command writes one. Returns 0 (and says why) when either is missing or
 * there is an operand too many. (A command that takes several asks
 * cli_batch_asked first, batch.h.) */
int cli_one_input(cli_common *cm, int argc, char **argv, const char *what,
                  const char **in);

/* Print "relief CMD: error: <message>" and return the status's exit code
 * (128 + the signal's number for a call a signal stopped). */
int cli_fail(const char *cmd, const relief_error *err);

/* Print "relief CMD: <fmt with arg>" and the --help hint; EXIT_USAGE. */
int cli_usage_error(const char *cmd, const char *fmt, const char *arg);

/* A decimal integer in lo..hi (for what is the command line's own: sizes
 * of its pictures, counts of its test hooks). */
int cli_parse_long(const char *cmd, const char *opt, const char *s, long lo, long hi,
                   long *out);

/* A finite real. */
int cli_parse_real(const char *cmd, const char *opt, const char *s, double *out);

/* A comma-separated list of at most `max` finite reals into out[0 .. *n). */
int cli_parse_reals(const char *cmd, const char *opt, const char *s, double *out, int max,
                    int *n);

/* One of names[0 .. n) (an enumeration's list, in its order): its index. */
int cli_parse_enum(const char *cmd, const char *opt, const char *s, const char *const *names,
                   int n, int *out);

/* An enumeration's names from its X-macro list: CLI_NAMES(RELIEF_BACKEND_LIST)
 * is { "auto", "scalar", ... }. */
#define CLI_X_NAME(code, name) name,
#define CLI_NAMES(list) {list(CLI_X_NAME)}
#define CLI_PARSE_ENUM(cmd, opt, s, names, out)                                         \
    cli_parse_enum(cmd, opt, s, names, (int)(sizeof names / sizeof names[0]), out)

/* Are a and b one file: the same name, the same inode, or, neither
 * there yet, the same name in the same folder? NULL: no. */
int cli_same_file(const char *a, const char *b);

/* A file or folder a command writes: the option that names it ("-o",
 * "--report"), its path (NULL: not asked for) and who writes it. */
typedef enum cli_out_kind {
    CLI_OUT_FILE,   /* cli_write_outputs, with the others, all or none */
    CLI_OUT_ENGINE, /* a file the engine writes itself (--checkpoint): checked only */
    CLI_OUT_FOLDER  /* a --report-dir the engine stages: cli_write_outputs places it last */
} cli_out_kind;

typedef struct cli_output {
    const char *opt, *path;
    cli_out_kind kind;
} cli_output;

/* Before any work, refuse what would fail after it or destroy data: a
 * folder (or anything but a plain file) where a file is wanted, a folder it
 * goes in that is missing or not writable, a --report-dir that cannot be
 * one (report/report_dir.h), the same file as one of ins[0 .. n_ins) (NULL
 * entries skipped) or as another output. One line naming the option and
 * the path; returns the exit status then (EXIT_USAGE, or 2 for what the
 * system refuses: a read-only file system), else 0. */
int cli_check_outputs(const char *cmd, const char *const *ins, size_t n_ins,
                      const cli_output *outs, size_t n_outs);

/* Write outs[i] (an asked CLI_OUT_FILE) into the sink s (base/output.h:
 * a staged file beside the target; s->path is the target), for
 * cli_write_outputs. */
typedef relief_status (*cli_write_fn)(void *ctx, size_t i, relief_sink *s, relief_error *err);

/* Every asked CLI_OUT_FILE of outs[0 .. n) written by write() to a
 * temporary beside it, and *folder (a staged --report-dir, or NULL; taken,
 * *folder set to NULL), then all moved into place together through a
 * journal (base/output.h): all or none, across a failure or a kill at any
 * step. On any failure the temporaries go and every file that was there
 * is as it was (its inode, bytes and mtime); nothing that existed before
 * is removed. SIGINT, SIGTERM, SIGHUP and SIGQUIT wait until the end
 * (cli_hold_signals); one that came before (cli_signal) writes
 * nothing (RELIEF_E_CANCELLED). At most CLI_MAX_OUTPUTS. */
#define CLI_MAX_OUTPUTS 8
relief_status cli_write_outputs(const cli_output *outs, size_t n, cli_write_fn write,
                                void *ctx, relief_report_folder **folder, relief_error *err);

/* --hole-mask label | ball:X,Y,Z,R, the hole model's selection (issue 40)
 * in every command that fills holes: *labels 1, or *has_ball 1 and ball.
 * 0 after saying what is wrong (R's range is the engine's to check). */
int cli_parse_hole_mask(const char *cmd, const char *arg, int *labels, int *has_ball,
                        double ball[4]);

/* The extension of `path` with its dot ("" when none). */
const char *cli_ext_of(const char *path);

/* A colour image's samples as a frame's packed RGB bytes (height x width x
 * 3): grey expanded, alpha dropped, 16 bits to their high byte. */
void cli_image_rgb8(const relief_image *c, uint8_t *rgb);

/* Does `path` end in a mesh extension relief writes (.ply .obj .off .stl)? */
int cli_known_mesh_ext(const char *path);

/* "SIGTERM" for SIGTERM, and the others held. */
const char *cli_signal_name(int sig);

/* Progress of one engine call on stderr, and SIGINT: a line with the
 * fraction done and an ETA at most four times a second on a terminal
 * (print), a one-time estimate when the call looks long (estimate: after
 * 10 s or 5 % of the engine's own progress, when more than a minute is left;
 * RELIEF_TEST_ESTIMATE_NOW=1 says it at once), a first SIGINT cancelling
 * the call (a second kills, as usual), and --max-seconds cancelling it once
 * its elapsed time passes the limit, never on an estimate: an estimate over
 * the limit is one warning line, and the call goes on (issue 60). The rate
 * is taken from the first report whose fraction moved on (base), so reading
 * and set-up, the engine's own before its first step included (a coherent
 * search's index: 18 s before 3367 targets grew in 1.3 s on frag_115), do
 * not make the first estimate absurd. Test hooks: RELIEF_TEST_SIGINT_AFTER=N
 * raises SIGINT at the N-th report of progress past 0;
 * RELIEF_TEST_ESTIMATE_SCALE=F multiplies every estimate of the time left
 * by F (a run that looks F times slower than it is). */
typedef struct cli_progress {
    const char *cmd;
    int print, estimate;
    const char *estimate_tail;  /* said after the estimate ("" or how to resume) */
    int open;                   /* 1 while a progress line waits for its end */
    double start, last, fraction;
    double base, base_fraction; /* seconds after start and fraction of the first report,
                                   then of the first that moved on */
    int based;                      /* base is the first report that moved on */
    double mark[2], mark_fraction[2]; /* the recent rate's marks (time_left) */
    double estimate_after, estimate_min, estimate_settle;
    double max_seconds;         /* 0: no limit */
    double estimate_scale;      /* 1, or RELIEF_TEST_ESTIMATE_SCALE */
    int limit_warned;           /* the estimate over --max-seconds was said */
    char limit[192];            /* why --max-seconds stopped the call; "" */
    unsigned long sigint_after, seen;
} cli_progress;

/* Start reporting (and take SIGINT) for cm's command with its --quiet and
 * --max-seconds, as run's progress callback (run may be NULL). */
void cli_progress_start(cli_progress *pr, const cli_common *cm, relief_run_options *run);

/* The relief_progress_fn: ctx is a cli_progress. Returns 1 once SIGINT
 * came or --max-seconds stopped the call. */
int cli_progress_fn(void *ctx, double fraction);

/* After the call: when st is a cancel by --max-seconds, err says so
 * (RELIEF_E_RANGE, exit 1, as --max-growth refuses) and 1 is returned. */
int cli_progress_explain(const cli_progress *pr, relief_status st, relief_error *err);

/* End the progress line, if one is open (before other messages). */
void cli_progress_close_line(cli_progress *pr);

/* Stop: end the line, give SIGINT back. */
void cli_progress_end(cli_progress *pr);

/* Hold SIGINT and SIGTERM while outputs are written (old: the mask to
 * restore), so that they appear whole or not at all. */
void cli_hold_signals(sigset_t *old);
void cli_release_signals(const sigset_t *old);

/* Print an engine's JSON object to f with the string members keys[i]:
 * values[i] (NULL: null) first. Returns 0 on success. */
int cli_print_json(FILE *f, const char *json, size_t n, const char *const *keys,
                   const char *const *values);

/* Write an engine's JSON report into the sink s, with the string members
 * keys[i]: values[i] (NULL: null) first, for the files the command read
 * that the engine did not (a mask, a truth). n may be 0. */
relief_status cli_json_to(relief_sink *s, const char *json, size_t n,
                          const char *const *keys, const char *const *values,
                          relief_error *err);

/* cli_json_to with `member` (a JSON member's text, "\"key\": value", or
 * NULL) after the string members: what the command's reading repaired. */
relief_status cli_json_with_to(relief_sink *s, const char *json, size_t n,
                               const char *const *keys, const char *const *values,
                               const char *member, relief_error *err);

/* Read the mesh at `path` (relief_mesh_read) for `cmd`; when the reader
 * repaired it and not `quiet`, say so in one warning line naming every
 * repair. `info` may be NULL. */
relief_status cli_read_mesh(const char *cmd, const char *path, int quiet, relief_mesh **out,
                            relief_read_info *info, relief_error *err);

/* The JSON member "input_repair": {...} of a read's repair counts (the
 * fields of relief_repair_info and the file's nonmanifold_triangles) into
 * text (size bytes). */
void cli_repair_json(const relief_read_info *info, char *text, size_t size);

#endif
