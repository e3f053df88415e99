/* Several inputs to one command (batch.h). */
#include "cli/batch.h"

#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "base/clock.h"
#include "cli/cli.h"
#include "cli/options.h"

static const char *base_name(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

/* OUTDIR/NAME, NAME the input's with `ext` for its extension (NULL: kept).
 * Owned by the caller; NULL when out of memory. */
static char *output_name(const char *dir, const char *in, const char *ext)
{
    const char *name = base_name(in), *dot = strrchr(name, '.');
    const size_t stem = ext && dot && dot != name ? (size_t)(dot - name) : strlen(name);
    const size_t nd = strlen(dir), n = nd + 1 + stem + (ext ? strlen(ext) : 0) + 1;
    char *out = malloc(n);
    if (out)
        snprintf(out, n, "%s%s%.*s%s", dir, nd && dir[nd - 1] == '/' ? "" : "/", (int)stem,
                 name, ext ? ext : "");
    return out;
}

int cli_batch_asked(const cli_common *cm, int argc)
{
    const size_t n_out = cm->out ? strlen(cm->out) : 0;
    return argc - optind > 1 || (argc - optind == 1 && n_out && cm->out[n_out - 1] == '/');
}

/* Refuses, before any run, what a batch cannot do; 1 when it can. The
 * single files are the parsed job's, whatever spelling named them. */
static int batch_checks(const cli_common *cm, const cli_batch *b, char *const *ins, int n,
                        char **outs)
{
    struct stat st;
    if (stat(cm->out, &st) != 0 || !S_ISDIR(st.st_mode)) {
        fprintf(stderr, "relief %s: error: -o '%s': with %d inputs, OUT is a folder that "
                "exists (create it first)\n", cm->cmd, cm->out, n);
        return 0;
    }
    for (int k = 0; k < CLI_BATCH_MAX_ONCE && b->once[k].opt; ++k)
        if (b->once[k].path) {
            fprintf(stderr, "relief %s: error: %s names one file, which %d inputs cannot "
                    "share: run them one by one\n", cm->cmd, b->once[k].opt, n);
            return 0;
        }
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < i; ++j)
            if (strcmp(outs[i], outs[j]) == 0) {
                fprintf(stderr, "relief %s: error: '%s' and '%s' would both be written to "
                        "'%s'\n", cm->cmd, ins[j], ins[i], outs[i]);
                return 0;
            }
    return 1;
}

/* The runs, a line each unless --quiet; the runs' exit statuses in rcs. */
static void run_all(const cli_common *cm, const cli_batch *b, char *const *ins, int n,
                    char **outs, int *rcs, double t0)
{
    for (int i = 0; i < n; ++i) {
        const double t = relief_seconds(), done = (double)(i + 1);
        if (cli_signal()) { /* a signal stops the batch, not only its run */
            fprintf(stderr, "relief %s: stopped by %s: %d of %d inputs not run\n", cm->cmd,
                    cli_signal_name(cli_signal()), n - i, n);
            for (; i < n; ++i)
                rcs[i] = 128 + cli_signal();
            return;
        }
        rcs[i] = b->run(b->job, ins[i], outs[i]);
        if (!cm->quiet)
            fprintf(stderr, "relief %s: [%d/%d] %s: %s in %.1f s (about %.0f s left)\n",
                    cm->cmd, i + 1, n, ins[i], rcs[i] ? "failed" : outs[i],
                    relief_seconds() - t, (relief_seconds() - t0) / done * (n - done));
    }
}

/* The summary (with --quiet, only when a run failed); the highest status. */
static int summary(const cli_common *cm, char *const *ins, int n, const int *rcs, double t0)
{
    int failed = 0, rc = 0;
    for (int i = 0; i < n; ++i) {
        failed += rcs[i] != 0;
        rc = rcs[i] > rc ? rcs[i] : rc;
    }
    if (!failed && cm->quiet)
        return 0;
    fprintf(stderr, "relief %s: %d of %d inputs done in %.1f s", cm->cmd, n - failed, n,
            relief_seconds() - t0);
    for (int i = 0, k = 0; i < n; ++i)
        if (rcs[i])
            fprintf(stderr, "%s%s (exit %d)", k++ ? ", " : "; failed: ", ins[i], rcs[i]);
    fputc('\n', stderr);
    return rc;
}

int cli_batch_run(const cli_common *cm, const cli_batch *b, char *const *ins, int n,
                  int parse_only)
{
    char **outs = calloc((size_t)n + 1, sizeof *outs);
    int *rcs = calloc((size_t)n + 1, sizeof *rcs), rc = 1, ok = outs && rcs;
    const double t0 = relief_seconds();
    if (!cm->out) {
        free(outs), free(rcs);
        return cli_usage_error(cm->cmd, "%smissing -o OUTDIR/ for several inputs", "");
    }
    for (int i = 0; ok && i < n; ++i)
        ok = (outs[i] = output_name(cm->out, ins[i], b->ext)) != NULL;
    if (!ok)
        fprintf(stderr, "relief %s: error: out of memory for %d inputs\n", cm->cmd, n);
    else if (batch_checks(cm, b, ins, n, outs))
        rc = 0;
    if (rc == 0 && !parse_only) {
        run_all(cm, b, ins, n, outs, rcs, t0);
        rc = summary(cm, ins, n, rcs, t0);
    }
    for (int i = 0; outs && i < n; ++i)
        free(outs[i]);
    free(outs), free(rcs);
    return rc;
}
