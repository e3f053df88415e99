/* What every command shares: exit codes, long-option ids, argument
 * parsing that names the option and its allowed range, the checks on
 * output paths, and the signal guard around writing outputs. Each parser
 * prints its own message on stderr ("relief CMD: --opt: ...") and returns
 * 0 on a bad value, 1 on a good one. */
#ifndef RELIEF_HOST_CLI_OPTIONS_H
#define RELIEF_HOST_CLI_OPTIONS_H

#include <signal.h>
#include <stddef.h>

#include "relief/relief.h"
#include "smooth/fit.h"

#define EXIT_USAGE 1
#define EXIT_INTERNAL 2

/* Long options without a short form: ids above any character. */
enum {
    OPT_REPORT = 256, OPT_FIT, OPT_WINDOW, OPT_ROTATIONS, OPT_ERROR, OPT_MU, OPT_SEED,
    OPT_LEVELS, OPT_BACKEND, OPT_DEVICE, OPT_OVERSAMPLE, OPT_SPACING, OPT_EXTENT,
    OPT_QUIET, OPT_ASCII, OPT_TRUTH, OPT_VERTICES, OPT_COLOUR, OPT_NOISE, OPT_JSON,
    OPT_FRAMES, OPT_OVERSAMPLE_SCHEME, OPT_BOOTSTRAP, OPT_NO_PRUNE, OPT_HELP,
    OPT_CHECKPOINT, OPT_RESUME, OPT_CHECKPOINT_EVERY, OPT_MAX_MEMORY,
    OPT_REPORT_DIR, OPT_VIEW, OPT_SIZE, OPT_COLOUR_BY, OPT_ACCEPT_POOR_FIT, OPT_MAX_GROWTH,
    OPT_COHERENCE, OPT_BALL, OPT_SLAB, OPT_KEEP_SPIKES, OPT_FILL, OPT_CROP, OPT_SEARCH,
    OPT_SEARCH_K, OPT_BASE
};

/* Print "relief CMD: error: <message>" and return the status's exit code. */
int cli_fail(const char *cmd, const relief_error *err);

/* Print "relief CMD: <fmt with arg>" and the --help hint; EXIT_USAGE. */
int cli_usage_error(const char *cmd, const char *fmt, const char *arg);

/* A decimal integer in lo..hi. */
int cli_parse_int(const char *cmd, const char *opt, const char *s, long lo, long hi,
                  long *out);

/* A finite real. */
int cli_parse_real(const char *cmd, const char *opt, const char *s, double *out);

/* A comma-separated list of at most `max` finite reals into out[0 .. *n). */
int cli_parse_reals(const char *cmd, const char *opt, const char *s, double *out, int max,
                    int *n);

/* --extent: "z0,z1" (cylinder) or "u0,v0,u1,v1" (plane) into p->extent. */
int cli_parse_extent(const char *cmd, const char *s, relief_params *p);

/* --backend: auto, scalar, opencl, and host where `with_host`. */
int cli_parse_backend(const char *cmd, const char *s, int with_host, relief_backend *out);

/* --fit: auto, plane, sphere or cylinder. */
int cli_parse_fit(const char *cmd, const char *s, relief_fit_model *out);

/* Is `out` the same file as `in` (by name or by inode)? */
int cli_same_file(const char *in, const char *out);

/* The extension of `path` with its dot ("" when none). */
const char *cli_ext_of(const char *path);

/* Does `path` end in a mesh extension relief writes (.ply .obj .off .stl)? */
int cli_known_mesh_ext(const char *path);

/* A progress line on stderr with an ETA, at most four times a second:
 * "relief CMD: WHAT done/total (p %), ETA s". print 0: silent. */
typedef struct cli_progress {
    const char *cmd, *what;
    int print;
    double start, last;
} cli_progress;

/* A fill's progress callback (ctx: a cli_progress). */
void cli_on_progress(void *ctx, size_t done, size_t total);

/* Hold SIGINT and SIGTERM while outputs are written (old: the mask to
 * restore), so that they appear whole or not at all. */
void cli_hold_signals(sigset_t *old);
void cli_release_signals(const sigset_t *old);

#endif
