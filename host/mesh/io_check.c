#include "mesh/io_check.h"

#include <errno.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "base/error.h"
#include "base/numtext.h"
#include "mesh/io_check_reader.h"

relief_file_format relief_file_format_of(const char *path)
{
    const char *dot = strrchr(path, '.');
    const char *slash = strrchr(path, '/');
    if (!dot || (slash && dot < slash))
        return RELIEF_FILE_UNKNOWN;
    if (strcasecmp(dot, ".ply") == 0)
        return RELIEF_FILE_PLY;
    if (strcasecmp(dot, ".obj") == 0)
        return RELIEF_FILE_OBJ;
    if (strcasecmp(dot, ".off") == 0)
        return RELIEF_FILE_OFF;
    if (strcasecmp(dot, ".stl") == 0)
        return RELIEF_FILE_STL;
    return RELIEF_FILE_UNKNOWN;
}

/* ------------------------------------------------------- line reading */

/* Next line split into whitespace tokens; '#' starts a comment when
 * `comments` is set. Returns 0 at end of file, and at a NUL byte, which
 * ends a token here but not in OpenMesh's readers (a PLY 'end_header\0'
 * would make OpenMesh read on forever); relief_io_check reports it. */
int io_next_line(reader *r, int comments)
{
    ssize_t len = getline(&r->line, &r->cap, r->f);
    char *s;
    if (len < 0)
        return 0;
    ++r->lineno;
    if ((size_t)len != strlen(r->line)) {
        if (!r->nul_line)
            r->nul_line = r->lineno;
        return 0;
    }
    if (comments) {
        char *hash = strchr(r->line, '#');
        if (hash)
            *hash = '\0';
    }
    r->ntok = 0;
    /* Every character isspace() takes, as the C++ streams OpenMesh reads
     * with: "f\v2" is a face for OpenMesh, so it must be one here. */
    for (s = strtok(r->line, " \t\r\n\v\f"); s && r->ntok < MAX_TOKENS;
         s = strtok(NULL, " \t\r\n\v\f"))
        r->tok[r->ntok++] = s;
    return 1;
}

/* Next line with at least one token. */
int io_next_nonblank(reader *r, int comments)
{
    while (io_next_line(r, comments))
        if (r->ntok > 0)
            return 1;
    return 0;
}

int io_parse_double(const char *s, double *out)
{
    char *end;
    errno = 0;
    *out = relief_strtod(s, &end);
    return end != s && *end == '\0';
}

int io_parse_long(const char *s, long long *out)
{
    char *end;
    errno = 0;
    *out = strtoll(s, &end, 10);
    return end != s && *end == '\0' && errno == 0;
}

/* Three finite coordinates in tokens first..first+2 of the line. */
relief_status io_check_coords(reader *r, int first, const char *what,
                                  long long index, relief_error *err)
{
    static const char axis[3] = {'x', 'y', 'z'};
    for (int k = 0; k < 3; ++k) {
        double v;
        if (first + k >= r->ntok)
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s:%ld: %s %lld has %d value(s); expected x y z",
                               r->path, r->lineno, what, index, r->ntok - first);
        if (!io_parse_double(r->tok[first + k], &v))
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s:%ld: %s %lld: %c coordinate '%s' is not a number",
                               r->path, r->lineno, what, index, axis[k],
                               r->tok[first + k]);
        /* OpenMesh reads OFF, OBJ and STL coordinates as floats. */
        if (!isfinite(v) || fabs(v) > FLT_MAX)
            return relief_fail(err, RELIEF_E_MESH,
                               "%s:%ld: %s %lld: %c coordinate '%s' is not finite%s",
                               r->path, r->lineno, what, index, axis[k],
                               r->tok[first + k], isfinite(v) ? " as a float" : "");
    }
    return RELIEF_OK;
}

/* Face corners: `n` indices already resolved to 0-based, checked against the
 * vertex count and for repeats. */
relief_status io_check_corners(const reader *r, const long long *idx, int n,
                                   long long face, long long nv, relief_error *err)
{
    if (n < 3)
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s:%ld: face %lld has %d corner(s); expected at least 3",
                           r->path, r->lineno, face, n);
    for (int k = 0; k < n; ++k) {
        if (idx[k] < 0 || idx[k] >= nv)
            return relief_fail(err, RELIEF_E_MESH,
                               "%s:%ld: face %lld refers to vertex %lld but the file "
                               "has %lld vertices",
                               r->path, r->lineno, face, idx[k], nv);
        for (int j = 0; j < k; ++j)
            if (idx[j] == idx[k])
                return relief_fail(err, RELIEF_E_MESH,
                                   "%s:%ld: face %lld uses vertex %lld twice",
                                   r->path, r->lineno, face, idx[k]);
    }
    return RELIEF_OK;
}

/* ---------------------------------------------------------------- OFF */

static relief_status check_off(reader *r, relief_file_check *out, relief_error *err)
{
    long long n[3];
    int colour, normals;
    char magic[32];
    const char *p;

    /* OpenMesh takes the whole first line as the magic line and then reads
     * the counts, the coordinates and the faces as a stream of words, with
     * no comments. This check follows the same reading, so that the counts
     * and corner counts OpenMesh will trust are the ones checked here (a
     * count it misreads makes it reserve or loop without bound). */
    if (!io_next_line(r, 0) || r->ntok == 0)
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s:1: expected an OFF magic word (OFF, COFF, NOFF, ...) on "
                           "the first line",
                           r->path);
    snprintf(magic, sizeof magic, "%s", r->tok[0]);
    /* [ST][C][N]OFF, as OpenMesh parses it: ST texture coordinates, C
     * colour, N normals (3 more numbers on each vertex line). */
    p = magic + (strncmp(magic, "ST", 2) == 0 ? 2 : 0);
    colour = *p == 'C';
    p += colour;
    normals = *p == 'N';
    p += normals;
    if (strcmp(p, "OFF") != 0)
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s:%ld: expected an OFF magic word ([ST][C][N]OFF: OFF, COFF, "
                           "NOFF, ...), found '%s'",
                           r->path, r->lineno, magic);
    if (r->ntok > 1 && strcmp(r->tok[1], "BINARY") == 0)
        return relief_fail(err, RELIEF_E_FORMAT,
                           "%s:1: binary OFF is not supported (its records cannot be "
                           "checked before OpenMesh reads them); convert it to binary PLY",
                           r->path);
    if (r->ntok > 1)
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s:1: expected the magic word '%s' alone on the first line, "
                           "found '%s' after it (the counts go on the next line)",
                           r->path, magic, r->tok[1]);
    if (!io_next_nonblank(r, 0))
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s:%ld: truncated: missing the vertex, face and edge counts",
                           r->path, r->lineno);
    for (int k = 0; k < 3; ++k)
        if (r->ntok != 3 || !io_parse_long(r->tok[k], &n[k]) || n[k] < 0 || n[k] > UINT_MAX)
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s:%ld: expected the vertex, face and edge counts (three "
                               "integers in 0..%u, no comment), found '%s'",
                               r->path, r->lineno, UINT_MAX, r->tok[0]);
    out->vertices = n[0];
    out->faces = n[1];
    for (long long i = 0; i < n[0]; ++i) {
        relief_status st;
        if (!io_next_nonblank(r, 0))
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s:%ld: truncated: the file ends after %lld of the %lld "
                               "vertices its header declares",
                               r->path, r->lineno, i, n[0]);
        st = io_check_coords(r, 0, "vertex", i, err);
        if (st == RELIEF_OK && normals)
            st = io_check_coords(r, 3, "vertex normal", i, err);
        if (st != RELIEF_OK)
            return st;
    }
    for (long long i = 0; i < n[1]; ++i) {
        long long k, idx[MAX_TOKENS];
        relief_status st;
        if (!io_next_nonblank(r, 0))
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s:%ld: truncated: the file ends after %lld of the %lld "
                               "faces its header declares",
                               r->path, r->lineno, i, n[1]);
        if (!io_parse_long(r->tok[0], &k) || k < 0 || k >= MAX_TOKENS || r->ntok < 1 + k)
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s:%ld: face %lld: expected a corner count followed by "
                               "that many vertex indices",
                               r->path, r->lineno, i);
        /* Without colour OpenMesh would take an extra word as the next face. */
        if (!colour && r->ntok > 1 + k)
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s:%ld: face %lld: %d value(s) after its %lld vertex "
                               "indices, but a '%s' file has no face colour",
                               r->path, r->lineno, i, r->ntok - 1 - (int)k, k, magic);
        for (int c = 0; c < k; ++c)
            if (!io_parse_long(r->tok[1 + c], &idx[c]))
                return relief_fail(err, RELIEF_E_PARSE,
                                   "%s:%ld: face %lld: index '%s' is not an integer",
                                   r->path, r->lineno, i, r->tok[1 + c]);
        st = io_check_corners(r, idx, (int)k, i, n[0], err);
        if (st != RELIEF_OK)
            return st;
    }
    return RELIEF_OK;
}

/* ---------------------------------------------------------------- OBJ */

/* OpenMesh's OBJ reader skips only lines that begin with '#' (a '#' later
 * in a face line is read as a vertex reference: index -1, whose normal it
 * then writes out of bounds), so comments are taken the same way here. It
 * checks texture and normal references itself. */
static relief_status check_obj(reader *r, relief_file_check *out, relief_error *err)
{
    long long nv = 0, nf = 0, seen_v = 0;

    /* Pass 1 counts vertices, so that faces may refer forward. */
    while (io_next_line(r, 0))
        if (r->ntok > 0 && strcmp(r->tok[0], "v") == 0)
            ++nv;
    rewind(r->f);
    r->lineno = 0;
    while (io_next_line(r, 0)) {
        if (r->ntok == 0 || r->tok[0][0] == '#')
            continue;
        if (strcmp(r->tok[0], "v") == 0) {
            relief_status st = io_check_coords(r, 1, "vertex", seen_v, err);
            if (st != RELIEF_OK)
                return st;
            ++seen_v;
        } else if (strcmp(r->tok[0], "f") == 0) {
            long long idx[MAX_TOKENS];
            int n = r->ntok - 1;
            relief_status st;
            if (r->ntok == MAX_TOKENS) /* next_line kept only MAX_TOKENS words */
                return relief_fail(err, RELIEF_E_PARSE,
                                   "%s:%ld: face %lld has more than %d corners",
                                   r->path, r->lineno, nf, MAX_TOKENS - 2);
            for (int k = 0; k < n; ++k) {
                long long i;
                char *slash = strchr(r->tok[1 + k], '/');
                if (slash)
                    *slash = '\0';
                if (!io_parse_long(r->tok[1 + k], &i) || i == 0)
                    return relief_fail(err, RELIEF_E_PARSE,
                                       "%s:%ld: face %lld: vertex reference '%s' is not "
                                       "a non-zero integer",
                                       r->path, r->lineno, nf, r->tok[1 + k]);
                /* OBJ counts from 1; negative counts back from the last vertex. */
                idx[k] = i > 0 ? i - 1 : seen_v + i;
            }
            st = io_check_corners(r, idx, n, nf, nv, err);
            if (st != RELIEF_OK)
                return st;
            ++nf;
        }
    }
    out->vertices = nv;
    out->faces = nf;
    return RELIEF_OK;
}

/* ---------------------------------------------------------------- STL */

static relief_status check_stl(reader *r, relief_file_check *out, long long fsize,
                               relief_error *err)
{
    unsigned char head[84];
    long long n, nvert = 0;
    int ascii;

    if (fsize >= 84 && fread(head, 1, 84, r->f) == 84) {
        n = (long long)head[80] | (long long)head[81] << 8 |
            (long long)head[82] << 16 | (long long)head[83] << 24;
        if (84 + 50 * n == fsize) {
            out->binary = 1;
            out->faces = n;
            return RELIEF_OK;
        }
    }
    rewind(r->f);
    ascii = io_next_nonblank(r, 0) && strcmp(r->tok[0], "solid") == 0;
    if (!ascii) {
        r->nul_line = 0; /* binary, and not of the size it declares */
        if (fsize < 84)
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s: truncated: a binary STL needs at least 84 bytes, "
                               "the file has %lld",
                               r->path, fsize);
        n = (long long)head[80] | (long long)head[81] << 8 |
            (long long)head[82] << 16 | (long long)head[83] << 24;
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s: binary STL declares %lld triangles (%lld bytes) but the "
                           "file has %lld bytes (truncated or malformed)",
                           r->path, n, 84 + 50 * n, fsize);
    }
    while (io_next_line(r, 0)) {
        if (r->ntok > 0 && strcmp(r->tok[0], "vertex") == 0) {
            relief_status st = io_check_coords(r, 1, "corner", nvert, err);
            if (st != RELIEF_OK)
                return st;
            ++nvert;
        }
    }
    if (nvert % 3 != 0)
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s: ascii STL has %lld 'vertex' lines; expected a multiple "
                           "of 3 (truncated?)",
                           r->path, nvert);
    out->faces = nvert / 3;
    return RELIEF_OK;
}

/* -------------------------------------------------------------- entry */

relief_status relief_io_check(const char *path, relief_file_check *out,
                              relief_error *err)
{
    static const char *const exts[] = {".ply", ".obj", ".off", ".stl"};
    struct stat sb;
    reader r;
    relief_status st;

    memset(out, 0, sizeof *out);
    out->vertices = out->faces = -1;
    out->format = relief_file_format_of(path);
    if (out->format == RELIEF_FILE_UNKNOWN)
        return relief_fail(err, RELIEF_E_FORMAT,
                           "%s: unknown mesh format; expected a file ending in .ply, "
                           ".obj, .off or .stl",
                           path);
    out->ext = exts[out->format];
    if (stat(path, &sb) != 0)
        return relief_fail(err, RELIEF_E_IO, "%s: cannot open: %s", path, strerror(errno));
    if (!S_ISREG(sb.st_mode))
        return relief_fail(err, RELIEF_E_IO, "%s: not a regular file", path);
    if (sb.st_size == 0)
        return relief_fail(err, RELIEF_E_PARSE, "%s: the file is empty", path);

    memset(&r, 0, sizeof r);
    r.path = path;
    r.f = fopen(path, "rb");
    if (!r.f)
        return relief_fail(err, RELIEF_E_IO, "%s: cannot open: %s", path, strerror(errno));
    switch (out->format) {
    case RELIEF_FILE_PLY:
        st = io_check_ply(&r, out, (long long)sb.st_size, err);
        break;
    case RELIEF_FILE_OFF:
        st = check_off(&r, out, err);
        break;
    case RELIEF_FILE_OBJ:
        st = check_obj(&r, out, err);
        break;
    default:
        st = check_stl(&r, out, (long long)sb.st_size, err);
        break;
    }
    if (r.nul_line)
        st = relief_fail(err, RELIEF_E_PARSE,
                         "%s:%ld: a NUL byte in a text line (binary data where text "
                         "was expected)",
                         path, r.nul_line);
    else if (st == RELIEF_OK && ferror(r.f))
        st = relief_fail(err, RELIEF_E_IO, "%s: read error", path);
    free(r.line);
    fclose(r.f);
    return st;
}
