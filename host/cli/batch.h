/* Several inputs to one command (issue 41): `relief depth-fill f1.png f2.png
 * f3.png -o OUTDIR/` runs the command once per input, each written to OUTDIR under
 * its input's name (the command's extension where it has one: complete and
 * complete-points write .ply), with a line per file on stderr (done or
 * failed, seconds, time left) and a summary (with --quiet, the summary
 * only, and only when a run failed). A failed input does not stop
 * the others, and every good output is kept; the exit status is the
 * highest of the runs' (0 when all succeeded).
 *
 * The command line is parsed once, into the command's job; the batch is a
 * loop that runs that job on each input with that input's output (issue
 * 60): argv is never read again, so every spelling getopt accepts
 * (--out DIR/, --outp=DIR/, -oDIR/) means what it means for one input.
 *
 * Checked before any run (exit 1, nothing written): OUTDIR is a folder
 * that exists; no option of the parsed job names a single file a run would
 * write (--report, --mesh, --points, --report-dir, --checkpoint) or read as
 * a truth (--truth, --resume); no two inputs give one output name. */
#ifndef RELIEF_HOST_CLI_BATCH_H
#define RELIEF_HOST_CLI_BATCH_H

#include "cli/options.h"

/* An option of the job that names one file: its long name ("--report")
 * and its value (NULL: not given). */
typedef struct cli_file_option {
    const char *opt, *path;
} cli_file_option;

#define CLI_BATCH_MAX_ONCE 6

/* A command's parsed job, as the batch runs it. run(job, in, out) is one
 * run on input `in` written to `out`, with the checks a single run makes
 * and without its notes (--quiet), returning its exit status; it works on
 * its own copy of the job, which stays as parsed. */
typedef struct cli_batch {
    const char *ext;  /* the outputs' extension (".ply"), or NULL: each input's */
    int (*run)(const void *job, const char *in, const char *out);
    const void *job;
    cli_file_option once[CLI_BATCH_MAX_ONCE]; /* refused with several inputs */
} cli_batch;

/* Does the command line ask for a batch: several operands (getopt has put
 * them last, from optind), or one with -o ending in '/'? */
int cli_batch_asked(const cli_common *cm, int argc);

/* The batch of ins[0 .. n) with b's job; cm->out is OUTDIR. With
 * parse_only, the checks and no run. Returns the exit status. */
int cli_batch_run(const cli_common *cm, const cli_batch *b, char *const *ins, int n,
                  int parse_only);

#endif
