/* Several inputs to one command (batch.h). */
#include "cli/batch.h"

#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "base/clock.h"

/* Options whose file is one per run. */
static const char *const single_files[] = {"--report", "--mesh", "--points", "--report-dir",
                                           "--checkpoint", "--truth", "--resume", NULL};

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

/* Refuses, before any run, what a batch cannot do; 1 when it can. */
static int batch_checks(const cli_common *cm, int first, int argc, char **argv, char **outs)
{
    struct stat st;
    if (stat(cm->out, &st) != 0 || !S_ISDIR(st.st_mode)) {
        fprintf(stderr, "relief %s: error: -o '%s': with %d inputs, OUT is a folder that "
                "exists (create it first)\n", cm->cmd, cm->out, argc - first);
        return 0;
    }
    for (const char *const *opt = single_files; *opt; ++opt)
        if (cli_given(first, argv, *opt)) {
            fprintf(stderr, "relief %s: error: %s names one file, which %d inputs cannot "
                    "share: run them one by one\n", cm->cmd, *opt, argc - first);
            return 0;
        }
    for (int i = 0; i < argc - first; ++i)
        for (int j = 0; j < i; ++j)
            if (strcmp(outs[i], outs[j]) == 0) {
                fprintf(stderr, "relief %s: error: '%s' and '%s' would both be written to "
                        "'%s'\n", cm->cmd, argv[first + j], argv[first + i], outs[i]);
                return 0;
            }
    return 1;
}

/* argv for one run: the command's name, -o OUT, --quiet, the options
 * given less every -o (as "-o DIR", "-oDIR", "--output DIR" or
 * "--output=DIR"), the input. *n: its count. */
static char **run_argv(int first, char **argv, char *out, char *in, int *n)
{
    char **a = malloc(((size_t)first + 5) * sizeof *a);
    static char o[] = "-o", quiet[] = "--quiet";
    if (!a)
        return NULL;
    *n = 0;
    a[(*n)++] = argv[0], a[(*n)++] = o, a[(*n)++] = out, a[(*n)++] = quiet;
    for (int i = 1; i < first; ++i) {
        const char *t = argv[i];
        if (strcmp(t, "-o") == 0 || strcmp(t, "--output") == 0) {
            ++i; /* and its value */
            continue;
        }
        if ((t[0] == '-' && t[1] == 'o') || strncmp(t, "--output=", 9) == 0)
            continue;
        a[(*n)++] = argv[i];
    }
    a[(*n)++] = in;
    a[*n] = NULL;
    return a;
}

int cli_batch_run(const cli_common *cm, int argc, char **argv)
{
    const int first = optind, n = argc - optind;
    char **outs = calloc((size_t)n + 1, sizeof *outs);
    int *rcs = calloc((size_t)n + 1, sizeof *rcs), rc = 0, failed = 0, ok = outs && rcs;
    const double t0 = relief_seconds();
    if (!cm->out) {
        free(outs), free(rcs);
        return cli_usage_error(cm->cmd, "%smissing -o OUTDIR/ for several inputs", "");
    }
    for (int i = 0; ok && i < n; ++i)
        ok = (outs[i] = output_name(cm->out, argv[first + i], cm->batch.ext)) != NULL;
    if (!ok)
        fprintf(stderr, "relief %s: error: out of memory for %d inputs\n", cm->cmd, n);
    else if (!batch_checks(cm, first, argc, argv, outs))
        ok = 0;
    for (int i = 0; ok && !cm->batch.parse_only && i < n; ++i) {
        int m = 0;
        char **a = run_argv(first, argv, outs[i], argv[first + i], &m);
        const double t = relief_seconds(), done = (double)(i + 1);
        rcs[i] = a ? cm->batch.run(m, a, 0) : 2;
        free(a);
        failed += rcs[i] != 0;
        rc = rcs[i] > rc ? rcs[i] : rc;
        if (!cm->quiet)
            fprintf(stderr, "relief %s: [%d/%d] %s: %s in %.1f s (about %.0f s left)\n",
                    cm->cmd, i + 1, n, argv[first + i], rcs[i] ? "failed" : outs[i],
                    relief_seconds() - t, (relief_seconds() - t0) / done * (n - done));
    }
    if (ok && !cm->batch.parse_only && (failed || !cm->quiet)) { /* --quiet: failures only */
        fprintf(stderr, "relief %s: %d of %d inputs done in %.1f s", cm->cmd, n - failed, n,
                relief_seconds() - t0);
        for (int i = 0, k = 0; i < n; ++i)
            if (rcs[i])
                fprintf(stderr, "%s%s (exit %d)", k++ ? ", " : "; failed: ", argv[first + i],
                        rcs[i]);
        fputc('\n', stderr);
    }
    for (int i = 0; outs && i < n; ++i)
        free(outs[i]);
    free(outs), free(rcs);
    return ok ? rc : 1;
}
