/* Cameras and poses from files (camera_files.h). Open3D's formats are read
 * as Open3D writes them (open3d/io/IJsonConvertibleIO and
 * PinholeCameraTrajectoryIO's .log), not as general JSON: the keys this
 * needs, found by name. */
#include "cli/camera_files.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/numtext.h"

/* Up to max numbers of s, separated by spaces or commas; how many, with
 * *rest after the last (NULL when something else stops them). */
static int numbers(const char *s, double *out, int max, const char **rest)
{
    int n = 0;
    char *end;
    for (;;) {
        s += strspn(s, " \t\r\n,");
        if (!*s || n == max)
            break;
        out[n] = relief_strtod(s, &end);
        if (end == s || !isfinite(out[n]))
            break;
        ++n, s = end;
    }
    *rest = s;
    return n;
}

int cli_camera_numbers(const char *arg, cli_camera *c)
{
    const char *rest;
    double k[4];
    if (numbers(arg, k, 4, &rest) != 4 || *rest)
        return 0;
    memcpy(c->k, k, sizeof k);
    c->width = c->height = 0;
    return 1;
}

/* The text of a small file (a camera, a pose list): NUL-terminated,
 * owned; NULL with the reason in err. Read in pieces: it may be a pipe. */
static char *slurp(const char *opt, const char *path, relief_error *err)
{
    enum { MOST = 1 << 26 };
    FILE *fp = fopen(path, "rb");
    char *text = NULL, *more;
    size_t len = 0, cap = 0, got;
    if (!fp) {
        relief_fail(err, RELIEF_E_IO, "%s %s: cannot be read", opt, path);
        return NULL;
    }
    do {
        if (len + 4096 + 1 > cap && (cap = 2 * cap + 8192) <= MOST && (more = realloc(text, cap)))
            text = more;
        else if (len + 4096 + 1 > cap) {
            free(text);
            fclose(fp);
            relief_fail(err, RELIEF_E_IO, "%s %s: cannot be held (a camera or pose file is "
                        "under 64 MiB)", opt, path);
            return NULL;
        }
        len += got = fread(text + len, 1, 4096, fp);
    } while (got == 4096);
    if (ferror(fp)) {
        free(text);
        text = NULL;
        relief_fail(err, RELIEF_E_IO, "%s %s: cannot be read", opt, path);
    } else
        text[len] = '\0';
    fclose(fp);
    return text;
}

/* The value after "key": in JSON text: where it starts, or NULL. */
static const char *json_value(const char *text, const char *key)
{
    char quoted[64];
    const char *at;
    snprintf(quoted, sizeof quoted, "\"%s\"", key);
    if (!(at = strstr(text, quoted)))
        return NULL;
    at += strlen(quoted);
    at += strspn(at, " \t\r\n");
    return *at == ':' ? at + 1 + strspn(at + 1, " \t\r\n") : NULL;
}

relief_status cli_read_camera_json(const char *opt, const char *path, cli_camera *c,
                                   relief_error *err)
{
    char *text = slurp(opt, path, err);
    const char *w, *h, *m, *rest;
    double k[9], wh[2] = {0.0, 0.0};
    relief_status st = RELIEF_OK;
    if (!text)
        return RELIEF_E_IO;
    w = json_value(text, "width"), h = json_value(text, "height");
    m = json_value(text, "intrinsic_matrix");
    if (!w || !h || !m || *m != '[')
        st = relief_fail(err, RELIEF_E_PARSE, "%s %s: expected Open3D's camera JSON (\"width\", "
                         "\"height\", \"intrinsic_matrix\": [9 numbers]); %s is missing", opt,
                         path, !w ? "width" : !h ? "height" : "intrinsic_matrix");
    else if (numbers(w, wh, 1, &rest) != 1 || numbers(h, wh + 1, 1, &rest) != 1 ||
             wh[0] < 1 || wh[1] < 1 || wh[0] > 1e6 || wh[1] > 1e6 ||
             wh[0] != floor(wh[0]) || wh[1] != floor(wh[1]))
        st = relief_fail(err, RELIEF_E_PARSE, "%s %s: width and height: expected whole numbers "
                         "of pixels, 1..1e6", opt, path);
    else if (numbers(m + 1, k, 9, &rest) != 9 || *rest != ']')
        st = relief_fail(err, RELIEF_E_PARSE, "%s %s: intrinsic_matrix: expected [9 numbers], "
                         "the 3 x 3 matrix column by column", opt, path);
    else if (!(k[0] > 0.0 && k[4] > 0.0) || k[1] != 0.0 || k[2] != 0.0 || k[3] != 0.0 ||
             k[5] != 0.0 || k[8] != 1.0)
        st = relief_fail(err, RELIEF_E_PARSE, "%s %s: intrinsic_matrix [%g %g %g; %g %g %g; %g "
                         "%g %g] (column by column) is no pinhole camera: expected [fx 0 0; 0 "
                         "fy 0; cx cy 1], fx, fy > 0", opt, path, k[0], k[1], k[2], k[3], k[4],
                         k[5], k[6], k[7], k[8]);
    if (st == RELIEF_OK) {
        c->k[0] = k[0], c->k[1] = k[4], c->k[2] = k[6], c->k[3] = k[7];
        c->width = (int)wh[0], c->height = (int)wh[1];
    }
    free(text);
    return st;
}

/* ------------------------------------------------------------ poses */

/* The next line with something on it ('#' comments dropped), from *at;
 * its number in *no. NULL at the end. The text is cut into lines. */
static char *next_line(char **at, int *no)
{
    while (**at) {
        char *line = *at, *end = line + strcspn(line, "\n");
        *at = *end ? end + 1 : end;
        *end = '\0';
        ++*no;
        line[strcspn(line, "#")] = '\0';
        if (strspn(line, " \t\r,") != strlen(line))
            return line;
    }
    return NULL;
}

/* Is `line` 3 whole numbers (a trajectory log's entry header)? */
static int log_header(const char *line)
{
    const char *rest;
    double id[3];
    return numbers(line, id, 3, &rest) == 3 && !*rest && id[0] == floor(id[0]) &&
           id[1] == floor(id[1]) && id[2] == floor(id[2]);
}

/* Lines of 12 numbers, one per view. */
static relief_status pose_lines(const char *path, char *text, int n_views, double (*pose)[12],
                                relief_error *err)
{
    char *line;
    const char *rest;
    int k = 0, no = 0;
    while ((line = next_line(&text, &no))) {
        if (k == n_views)
            return relief_fail(err, RELIEF_E_PARSE, "--poses %s line %d: more poses than "
                               "--views (%d)", path, no, n_views);
        if (numbers(line, pose[k], 12, &rest) != 12 || strspn(rest, " \t\r,") != strlen(rest))
            return relief_fail(err, RELIEF_E_PARSE, "--poses %s line %d: expected 12 numbers "
                               "(R row by row, then t) or a trajectory log's 3 ids", path, no);
        ++k;
    }
    if (k != n_views)
        return relief_fail(err, RELIEF_E_PARSE, "--poses %s: %d poses for %d views", path, k,
                           n_views);
    return RELIEF_OK;
}

/* A log's entries: *t gets n 4 x 4 row-major matrices (owned). */
static relief_status log_entries(const char *path, char *text, double **t, int *n,
                                 relief_error *err)
{
    char *line;
    const char *rest;
    int no = 0, cap = 0;
    *t = NULL, *n = 0;
    while ((line = next_line(&text, &no))) {
        if (!log_header(line))
            return relief_fail(err, RELIEF_E_PARSE, "--poses %s line %d: expected an entry's 3 "
                               "ids (Open3D's trajectory log)", path, no);
        if (*n == cap) {
            double *more = realloc(*t, (size_t)(cap = cap ? 2 * cap : 16) * 16 * sizeof **t);
            if (!more)
                return relief_fail(err, RELIEF_E_NOMEM, "--poses %s: cannot hold %d entries",
                                   path, cap);
            *t = more;
        }
        for (int r = 0; r < 4; ++r)
            if (!(line = next_line(&text, &no)) ||
                numbers(line, *t + 16 * *n + 4 * r, 4, &rest) != 4 ||
                strspn(rest, " \t\r,") != strlen(rest))
                return relief_fail(err, RELIEF_E_PARSE, "--poses %s line %d: entry %d: expected "
                                   "row %d of its 4 x 4 pose, 4 numbers", path, no, *n, r + 1);
        ++*n;
    }
    return RELIEF_OK;
}

/* Is the 4 x 4 matrix a rigid motion (R orthonormal, last row 0 0 0 1)? */
static int rigid(const double *m)
{
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double d = m[i] * m[j] + m[4 + i] * m[4 + j] + m[8 + i] * m[8 + j];
            if (fabs(d - (i == j)) > 1e-4)
                return 0;
        }
    return fabs(m[12]) + fabs(m[13]) + fabs(m[14]) < 1e-9 && fabs(m[15] - 1.0) < 1e-9;
}

/* [R | t] of inverse(v) f: frame camera coordinates to the view's. */
static void relative(const double *v, const double *f, double pose[12])
{
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) {
            /* inverse(v) = [R^T | -R^T t]: row r is column r of v's R */
            double s = c == 3 ? -(v[r] * v[3] + v[4 + r] * v[7] + v[8 + r] * v[11]) : 0.0;
            for (int k = 0; k < 3; ++k)
                s += v[4 * k + r] * f[4 * k + c];
            pose[4 * r + c] = s;
        }
}

/* The picked entries' relative poses. */
static relief_status pick_poses(const char *path, const double *t, int n,
                                const cli_pose_pick *pick, double (*pose)[12], relief_error *err)
{
    int next = 0;
    if (pick->frame < 0 || pick->frame >= n)
        return relief_fail(err, RELIEF_E_USAGE, "--frame-index %d: --poses %s holds entries "
                           "0..%d", pick->frame, path, n - 1);
    for (int k = 0; k < pick->n_views; ++k) {
        int e = pick->view ? pick->view[k] : next + (next >= pick->frame);
        next += !pick->view;
        if (e < 0 || e >= n)
            return relief_fail(err, RELIEF_E_USAGE, "%s %d (view %d): --poses %s holds entries "
                               "0..%d", pick->view ? "--view-index" : "entry", e, k, path, n - 1);
        if (!rigid(t + 16 * e) || !rigid(t + 16 * pick->frame))
            return relief_fail(err, RELIEF_E_PARSE, "--poses %s: entry %d is no rigid motion "
                               "(R orthonormal, last row 0 0 0 1)", path,
                               rigid(t + 16 * e) ? pick->frame : e);
        relative(t + 16 * e, t + 16 * pick->frame, pose[k]);
    }
    return RELIEF_OK;
}

/* Does text start (its first line with something on it) as a trajectory
 * log does? Read on a copy: next_line cuts its text. */
static int starts_as_log(const char *text)
{
    size_t len = strlen(text);
    char *copy = malloc(len + 1), *at = copy, *first;
    int no = 0, is_log;
    if (!copy)
        return 0;
    memcpy(copy, text, len + 1);
    first = next_line(&at, &no);
    is_log = first && log_header(first);
    free(copy);
    return is_log;
}

relief_status cli_read_poses(const char *path, const cli_pose_pick *pick, int given_pick,
                             double (*pose)[12], int *is_log, relief_error *err)
{
    char *text = slurp("--poses", path, err);
    double *t = NULL;
    int n = 0;
    relief_status st;
    if (!text)
        return RELIEF_E_IO;
    *is_log = starts_as_log(text);
    if (!*is_log && given_pick)
        st = relief_fail(err, RELIEF_E_USAGE, "--frame-index and --view-index pick entries of "
                         "a trajectory log; --poses %s is one line of 12 numbers per view",
                         path);
    else if (!*is_log)
        st = pose_lines(path, text, pick->n_views, pose, err);
    else if ((st = log_entries(path, text, &t, &n, err)) == RELIEF_OK)
        st = pick_poses(path, t, n, pick, pose, err);
    free(t);
    free(text);
    return st;
}
