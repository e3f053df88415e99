/* Several inputs to one command (issue 41): `relief depth-fill f1.png f2.png
 * f3.png -o OUTDIR/` runs the command once per input, each written to OUTDIR under
 * its input's name (the command's extension where it has one: complete and
 * complete-points write .ply), with a line per file on stderr (done or
 * failed, seconds, time left) and a summary (with --quiet, the summary
 * only, and only when a run failed). A failed input does not stop
 * the others, and every good output is kept; the exit status is the
 * highest of the runs' (0 when all succeeded).
 *
 * Checked before any run (exit 1, nothing written): OUTDIR is a folder
 * that exists; no option names a single file a run would write (--report,
 * --mesh, --points, --report-dir, --checkpoint) or read as a truth
 * (--truth, --resume); no two inputs give one output name. */
#ifndef RELIEF_HOST_CLI_BATCH_H
#define RELIEF_HOST_CLI_BATCH_H

#include "cli/options.h"

/* The batch of argv[optind..argc - 1] (getopt has put the operands last)
 * with the options before them; cm->out is OUTDIR. Returns the exit status. */
int cli_batch_run(const cli_common *cm, int argc, char **argv);

#endif
