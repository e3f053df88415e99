#include "io_check.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "error.h"

#define MAX_TOKENS 64

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

typedef struct reader {
    FILE *f;
    const char *path;
    char *line;
    size_t cap;
    long lineno;
    char *tok[MAX_TOKENS];
    int ntok;
} reader;

/* Next line split into whitespace tokens; '#' starts a comment when
 * `comments` is set. Returns 0 at end of file. */
static int next_line(reader *r, int comments)
{
    ssize_t len = getline(&r->line, &r->cap, r->f);
    char *s;
    if (len < 0)
        return 0;
    ++r->lineno;
    if (comments) {
        char *hash = strchr(r->line, '#');
        if (hash)
            *hash = '\0';
    }
    r->ntok = 0;
    for (s = strtok(r->line, " \t\r\n"); s && r->ntok < MAX_TOKENS;
         s = strtok(NULL, " \t\r\n"))
        r->tok[r->ntok++] = s;
    return 1;
}

/* Next line with at least one token. */
static int next_nonblank(reader *r, int comments)
{
    while (next_line(r, comments))
        if (r->ntok > 0)
            return 1;
    return 0;
}

static int parse_double(const char *s, double *out)
{
    char *end;
    errno = 0;
    *out = strtod(s, &end);
    return end != s && *end == '\0';
}

static int parse_long(const char *s, long long *out)
{
    char *end;
    errno = 0;
    *out = strtoll(s, &end, 10);
    return end != s && *end == '\0' && errno == 0;
}

/* Three finite coordinates in tokens first..first+2 of the line. */
static relief_status check_coords(reader *r, int first, const char *what,
                                  long long index, relief_error *err)
{
    static const char axis[3] = {'x', 'y', 'z'};
    for (int k = 0; k < 3; ++k) {
        double v;
        if (first + k >= r->ntok)
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s:%ld: %s %lld has %d value(s); expected x y z",
                               r->path, r->lineno, what, index, r->ntok - first);
        if (!parse_double(r->tok[first + k], &v))
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s:%ld: %s %lld: %c coordinate '%s' is not a number",
                               r->path, r->lineno, what, index, axis[k],
                               r->tok[first + k]);
        if (!isfinite(v))
            return relief_fail(err, RELIEF_E_MESH,
                               "%s:%ld: %s %lld: %c coordinate '%s' is not finite",
                               r->path, r->lineno, what, index, axis[k],
                               r->tok[first + k]);
    }
    return RELIEF_OK;
}

/* Face corners: `n` indices already resolved to 0-based, checked against the
 * vertex count and for repeats. */
static relief_status check_corners(const reader *r, const long long *idx, int n,
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

/* ---------------------------------------------------------------- PLY */

typedef struct ply_prop {
    char name[32];
    int size;       /* bytes of the scalar, or of the list's items */
    int count_size; /* 0 for a scalar; bytes of the list's count otherwise */
    int is_char;
} ply_prop;

typedef struct ply_element {
    char name[32];
    long long count;
    ply_prop prop[32];
    int nprop;
} ply_element;

static int ply_type_size(const char *t, int *is_char)
{
    static const struct {
        const char *name;
        int size;
    } types[] = {{"char", 1},   {"uchar", 1},   {"int8", 1},    {"uint8", 1},
                 {"short", 2},  {"ushort", 2},  {"int16", 2},   {"uint16", 2},
                 {"int", 4},    {"uint", 4},    {"int32", 4},   {"uint32", 4},
                 {"float", 4},  {"float32", 4}, {"double", 8},  {"float64", 8}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; ++i)
        if (strcmp(t, types[i].name) == 0) {
            if (is_char)
                *is_char = types[i].size == 1;
            return types[i].size;
        }
    return 0;
}

static relief_status check_ply(reader *r, relief_file_check *out, long long fsize,
                               relief_error *err)
{
    ply_element el[16];
    int nel = 0, fmt = -1; /* 0 ascii, 1 binary */
    ply_element *vert = NULL, *face = NULL;
    int ended = 0;

    if (!next_line(r, 0) || r->ntok != 1 || strcmp(r->tok[0], "ply") != 0)
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s:1: expected the PLY magic line 'ply'", r->path);
    while (next_line(r, 0)) {
        if (r->ntok == 0 || strcmp(r->tok[0], "comment") == 0 ||
            strcmp(r->tok[0], "obj_info") == 0)
            continue;
        if (strcmp(r->tok[0], "end_header") == 0) {
            ended = 1;
            break;
        }
        if (strcmp(r->tok[0], "format") == 0) {
            if (r->ntok < 2)
                goto bad_line;
            if (strcmp(r->tok[1], "ascii") == 0)
                fmt = 0;
            else if (strcmp(r->tok[1], "binary_little_endian") == 0 ||
                     strcmp(r->tok[1], "binary_big_endian") == 0)
                fmt = 1;
            else
                return relief_fail(err, RELIEF_E_PARSE,
                                   "%s:%ld: unknown PLY format '%s'; expected ascii, "
                                   "binary_little_endian or binary_big_endian",
                                   r->path, r->lineno, r->tok[1]);
        } else if (strcmp(r->tok[0], "element") == 0) {
            long long n;
            if (r->ntok != 3 || !parse_long(r->tok[2], &n) || n < 0)
                return relief_fail(err, RELIEF_E_PARSE,
                                   "%s:%ld: expected 'element NAME COUNT' with COUNT >= 0",
                                   r->path, r->lineno);
            if (nel == 16)
                return relief_fail(err, RELIEF_E_PARSE,
                                   "%s:%ld: more than 16 elements", r->path, r->lineno);
            memset(&el[nel], 0, sizeof el[nel]);
            snprintf(el[nel].name, sizeof el[nel].name, "%s", r->tok[1]);
            el[nel].count = n;
            ++nel;
        } else if (strcmp(r->tok[0], "property") == 0) {
            ply_prop *p;
            if (nel == 0)
                return relief_fail(err, RELIEF_E_PARSE,
                                   "%s:%ld: property before any element",
                                   r->path, r->lineno);
            if (el[nel - 1].nprop == 32)
                return relief_fail(err, RELIEF_E_PARSE,
                                   "%s:%ld: more than 32 properties", r->path, r->lineno);
            p = &el[nel - 1].prop[el[nel - 1].nprop];
            if (r->ntok == 3) {
                p->size = ply_type_size(r->tok[1], &p->is_char);
                snprintf(p->name, sizeof p->name, "%s", r->tok[2]);
                if (!p->size)
                    return relief_fail(err, RELIEF_E_PARSE,
                                       "%s:%ld: unknown property type '%s'",
                                       r->path, r->lineno, r->tok[1]);
            } else if (r->ntok == 5 && strcmp(r->tok[1], "list") == 0) {
                p->count_size = ply_type_size(r->tok[2], NULL);
                p->size = ply_type_size(r->tok[3], NULL);
                snprintf(p->name, sizeof p->name, "%s", r->tok[4]);
                if (!p->count_size || !p->size)
                    return relief_fail(err, RELIEF_E_PARSE,
                                       "%s:%ld: unknown list types '%s %s'",
                                       r->path, r->lineno, r->tok[2], r->tok[3]);
            } else {
                goto bad_line;
            }
            ++el[nel - 1].nprop;
        } else {
            goto bad_line;
        }
    }
    if (!ended)
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s: the PLY header has no 'end_header' line (truncated?)",
                           r->path);
    if (fmt < 0)
        return relief_fail(err, RELIEF_E_PARSE, "%s: the PLY header has no 'format' line",
                           r->path);
    for (int e = 0; e < nel; ++e) {
        if (strcmp(el[e].name, "vertex") == 0)
            vert = &el[e];
        else if (strcmp(el[e].name, "face") == 0)
            face = &el[e];
    }
    if (!vert)
        return relief_fail(err, RELIEF_E_PARSE, "%s: the PLY header declares no 'vertex' element",
                           r->path);
    {
        int xyz = 0;
        for (int p = 0; p < vert->nprop; ++p) {
            const char *n = vert->prop[p].name;
            if (!vert->prop[p].count_size &&
                (strcmp(n, "x") == 0 || strcmp(n, "y") == 0 || strcmp(n, "z") == 0))
                ++xyz;
            if (strcmp(n, "label") == 0 && vert->prop[p].is_char && fmt == 0)
                out->ascii_char_label = 1;
        }
        if (xyz != 3)
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s: the PLY 'vertex' element lacks scalar x, y, z properties",
                               r->path);
    }
    out->binary = fmt == 1;
    out->vertices = vert->count;
    out->faces = face ? face->count : 0;

    if (fmt == 1) {
        /* Binary: the body must hold at least every element at its smallest
         * (lists of faces with 3 items, other lists empty). */
        long long need = 0, have = fsize - ftell(r->f);
        for (int e = 0; e < nel; ++e) {
            long long per = 0;
            for (int p = 0; p < el[e].nprop; ++p) {
                const ply_prop *pp = &el[e].prop[p];
                if (!pp->count_size)
                    per += pp->size;
                else
                    per += pp->count_size +
                           (&el[e] == face ? 3LL * pp->size : 0);
            }
            need += per * el[e].count;
        }
        if (have < need)
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s: truncated: the header declares %lld vertices and "
                               "%lld faces, which need at least %lld bytes after the "
                               "header, but only %lld follow",
                               r->path, vert->count, face ? face->count : 0LL, need, have);
        return RELIEF_OK;
    }

    /* Ascii: one line per element item, in header order. */
    for (int e = 0; e < nel; ++e) {
        for (long long i = 0; i < el[e].count; ++i) {
            if (!next_line(r, 0))
                return relief_fail(err, RELIEF_E_PARSE,
                                   "%s:%ld: truncated: the file ends after %lld of the "
                                   "%lld '%s' items the header declares",
                                   r->path, r->lineno, i, el[e].count, el[e].name);
            if (&el[e] == vert) {
                int t = 0;
                for (int p = 0; p < vert->nprop; ++p) {
                    const ply_prop *pp = &vert->prop[p];
                    double v;
                    if (pp->count_size) { /* a list in a vertex: skip it */
                        long long n;
                        if (t >= r->ntok || !parse_long(r->tok[t], &n) || n < 0)
                            goto bad_item;
                        t += 1 + (int)n;
                        continue;
                    }
                    if (t >= r->ntok)
                        return relief_fail(err, RELIEF_E_PARSE,
                                           "%s:%ld: vertex %lld has %d value(s); the "
                                           "header declares %d properties",
                                           r->path, r->lineno, i, r->ntok, vert->nprop);
                    if (!parse_double(r->tok[t], &v))
                        return relief_fail(err, RELIEF_E_PARSE,
                                           "%s:%ld: vertex %lld: property '%s' value "
                                           "'%s' is not a number",
                                           r->path, r->lineno, i, pp->name, r->tok[t]);
                    if (!isfinite(v) && (strcmp(pp->name, "x") == 0 ||
                                         strcmp(pp->name, "y") == 0 ||
                                         strcmp(pp->name, "z") == 0))
                        return relief_fail(err, RELIEF_E_MESH,
                                           "%s:%ld: vertex %lld: %s coordinate '%s' "
                                           "is not finite",
                                           r->path, r->lineno, i, pp->name, r->tok[t]);
                    ++t;
                }
            } else if (&el[e] == face) {
                long long n, idx[MAX_TOKENS];
                relief_status st;
                if (r->ntok < 1 || !parse_long(r->tok[0], &n) || n < 0)
                    goto bad_item;
                if (n >= MAX_TOKENS)
                    return relief_fail(err, RELIEF_E_PARSE,
                                       "%s:%ld: face %lld has %lld corners; at most %d "
                                       "are supported",
                                       r->path, r->lineno, i, n, MAX_TOKENS - 1);
                if (r->ntok < 1 + n)
                    return relief_fail(err, RELIEF_E_PARSE,
                                       "%s:%ld: face %lld declares %lld corners but "
                                       "lists %d",
                                       r->path, r->lineno, i, n, r->ntok - 1);
                for (int k = 0; k < n; ++k)
                    if (!parse_long(r->tok[1 + k], &idx[k]))
                        return relief_fail(err, RELIEF_E_PARSE,
                                           "%s:%ld: face %lld: index '%s' is not an "
                                           "integer",
                                           r->path, r->lineno, i, r->tok[1 + k]);
                st = check_corners(r, idx, (int)n, i, vert->count, err);
                if (st != RELIEF_OK)
                    return st;
            }
            continue;
        bad_item:
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s:%ld: malformed '%s' item %lld", r->path, r->lineno,
                               el[e].name, i);
        }
    }
    return RELIEF_OK;

bad_line:
    return relief_fail(err, RELIEF_E_PARSE, "%s:%ld: malformed PLY header line",
                       r->path, r->lineno);
}

/* ---------------------------------------------------------------- OFF */

static relief_status check_off(reader *r, relief_file_check *out, relief_error *err)
{
    long long n[3];
    int t = 1;
    const char *magic;
    size_t len;

    if (!next_nonblank(r, 1))
        return relief_fail(err, RELIEF_E_PARSE, "%s: the file has no OFF header", r->path);
    magic = r->tok[0];
    len = strlen(magic);
    if (len < 3 || strcmp(magic + len - 3, "OFF") != 0)
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s:%ld: expected an OFF magic word (OFF, COFF, NOFF, ...), "
                           "found '%s'",
                           r->path, r->lineno, magic);
    if (r->ntok > 1 && strcmp(r->tok[1], "BINARY") == 0) {
        out->binary = 1; /* rare; OpenMesh reads it, we check no further */
        return RELIEF_OK;
    }
    for (int k = 0; k < 3; ++k) {
        if (t >= r->ntok) {
            if (!next_nonblank(r, 1))
                return relief_fail(err, RELIEF_E_PARSE,
                                   "%s:%ld: truncated: missing the vertex, face and "
                                   "edge counts",
                                   r->path, r->lineno);
            t = 0;
        }
        if (!parse_long(r->tok[t], &n[k]) || n[k] < 0)
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s:%ld: expected vertex, face and edge counts, found '%s'",
                               r->path, r->lineno, r->tok[t]);
        ++t;
    }
    out->vertices = n[0];
    out->faces = n[1];
    for (long long i = 0; i < n[0]; ++i) {
        relief_status st;
        if (!next_nonblank(r, 1))
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s:%ld: truncated: the file ends after %lld of the %lld "
                               "vertices its header declares",
                               r->path, r->lineno, i, n[0]);
        st = check_coords(r, 0, "vertex", i, err);
        if (st != RELIEF_OK)
            return st;
    }
    for (long long i = 0; i < n[1]; ++i) {
        long long k, idx[MAX_TOKENS];
        relief_status st;
        if (!next_nonblank(r, 1))
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s:%ld: truncated: the file ends after %lld of the %lld "
                               "faces its header declares",
                               r->path, r->lineno, i, n[1]);
        if (!parse_long(r->tok[0], &k) || k < 0 || k >= MAX_TOKENS || r->ntok < 1 + k)
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s:%ld: face %lld: expected a corner count followed by "
                               "that many vertex indices",
                               r->path, r->lineno, i);
        for (int c = 0; c < k; ++c)
            if (!parse_long(r->tok[1 + c], &idx[c]))
                return relief_fail(err, RELIEF_E_PARSE,
                                   "%s:%ld: face %lld: index '%s' is not an integer",
                                   r->path, r->lineno, i, r->tok[1 + c]);
        st = check_corners(r, idx, (int)k, i, n[0], err);
        if (st != RELIEF_OK)
            return st;
    }
    return RELIEF_OK;
}

/* ---------------------------------------------------------------- OBJ */

static relief_status check_obj(reader *r, relief_file_check *out, relief_error *err)
{
    long long nv = 0, nf = 0, seen_v = 0;

    /* Pass 1 counts vertices, so that faces may refer forward. */
    while (next_line(r, 1))
        if (r->ntok > 0 && strcmp(r->tok[0], "v") == 0)
            ++nv;
    rewind(r->f);
    r->lineno = 0;
    while (next_line(r, 1)) {
        if (r->ntok == 0)
            continue;
        if (strcmp(r->tok[0], "v") == 0) {
            relief_status st = check_coords(r, 1, "vertex", seen_v, err);
            if (st != RELIEF_OK)
                return st;
            ++seen_v;
        } else if (strcmp(r->tok[0], "f") == 0) {
            long long idx[MAX_TOKENS];
            int n = r->ntok - 1;
            relief_status st;
            for (int k = 0; k < n; ++k) {
                long long i;
                char *slash = strchr(r->tok[1 + k], '/');
                if (slash)
                    *slash = '\0';
                if (!parse_long(r->tok[1 + k], &i) || i == 0)
                    return relief_fail(err, RELIEF_E_PARSE,
                                       "%s:%ld: face %lld: vertex reference '%s' is not "
                                       "a non-zero integer",
                                       r->path, r->lineno, nf, r->tok[1 + k]);
                /* OBJ counts from 1; negative counts back from the last vertex. */
                idx[k] = i > 0 ? i - 1 : seen_v + i;
            }
            st = check_corners(r, idx, n, nf, nv, err);
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
    ascii = next_nonblank(r, 0) && strcmp(r->tok[0], "solid") == 0;
    if (!ascii) {
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
    while (next_line(r, 0)) {
        if (r->ntok > 0 && strcmp(r->tok[0], "vertex") == 0) {
            relief_status st = check_coords(r, 1, "corner", nvert, err);
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
        st = check_ply(&r, out, (long long)sb.st_size, err);
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
    if (st == RELIEF_OK && ferror(r.f))
        st = relief_fail(err, RELIEF_E_IO, "%s: read error", path);
    free(r.line);
    fclose(r.f);
    return st;
}
