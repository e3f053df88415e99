/* Shared option parsing and output guards of the commands (options.h). */
#include "cli/options.h"

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "base/clock.h"

int cli_fail(const char *cmd, const relief_error *err)
{
    fprintf(stderr, "relief %s: error: %s\n", cmd,
            err->message[0] ? err->message : relief_strerror(err->status));
    return relief_status_exit_code(err->status);
}

int cli_usage_error(const char *cmd, const char *fmt, const char *arg)
{
    fprintf(stderr, "relief %s: ", cmd);
    fprintf(stderr, fmt, arg);
    fprintf(stderr, "\nTry 'relief %s --help'.\n", cmd);
    return EXIT_USAGE;
}

int cli_parse_int(const char *cmd, const char *opt, const char *s, long lo, long hi,
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
    v = strtod(s, &end);
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

/* "z0,z1" or "u0,v0,u1,v1". */
int cli_parse_extent(const char *cmd, const char *s, relief_params *p)
{
    int n;
    if (!cli_parse_reals(cmd, "--extent", s, p->extent, 4, &n))
        return 0;
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
int cli_same_file(const char *in, const char *out)
{
    struct stat a, b;
    if (strcmp(in, out) == 0)
        return 1;
    if (stat(in, &a) != 0 || stat(out, &b) != 0)
        return 0;
    return a.st_dev == b.st_dev && a.st_ino == b.st_ino;
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

int cli_parse_fit(const char *cmd, const char *s, relief_fit_model *out)
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

/* Outputs appear whole or not at all even on Ctrl-C or SIGTERM: both are
 * held back while the files are written (temporary names, then renames)
 * and delivered once every file is in place or removed. The test hook
 * RELIEF_TEST_SIGINT_IN_WRITE raises SIGINT just as the writing starts. */
void cli_hold_signals(sigset_t *old)
{
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    sigprocmask(SIG_BLOCK, &set, old);
    if (getenv("RELIEF_TEST_SIGINT_IN_WRITE"))
        raise(SIGINT); /* pending until release_signals */
}

void cli_release_signals(const sigset_t *old)
{
    sigprocmask(SIG_SETMASK, old, NULL);
}

int cli_parse_backend(const char *cmd, const char *s, int with_host, relief_backend *out)
{
    static const relief_backend all[] = {RELIEF_BACKEND_AUTO, RELIEF_BACKEND_SCALAR,
                                         RELIEF_BACKEND_OPENCL, RELIEF_BACKEND_HOST};
    for (int i = 0; i < (with_host ? 4 : 3); ++i)
        if (strcmp(s, relief_backend_name(all[i])) == 0) {
            *out = all[i];
            return 1;
        }
    fprintf(stderr, "relief %s: --backend: '%s' is not one of auto, scalar, opencl%s\n"
            "Try 'relief %s --help'.\n", cmd, s, with_host ? ", host" : "", cmd);
    return 0;
}

void cli_on_progress(void *ctx, size_t done, size_t total)
{
    cli_progress *pr = ctx;
    double now = relief_seconds(), t = now - pr->start, rate;
    if (!pr->print || (done != total && now - pr->last < 0.25))
        return;
    pr->last = now;
    rate = t > 0 ? (double)done / t : 0.0;
    fprintf(stderr, "\rrelief %s: %s %zu/%zu (%.0f %%), ETA %.0f s   ", pr->cmd, pr->what, done,
            total, total ? 100.0 * (double)done / (double)total : 100.0,
            rate > 0 ? (double)(total - done) / rate : 0.0);
    if (done == total)
        fputc('\n', stderr);
}
