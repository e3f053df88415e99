/* relief_io_check for PLY: header, declared element sizes against the
 * file's length, and every ascii or binary value of the body. */
#include "mesh/io_check.h"

#include <errno.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/numtext.h"
#include "mesh/io_check_reader.h"

/* ---------------------------------------------------------------- PLY */

typedef struct ply_prop {
    char name[32];
    int size;       /* bytes of the scalar, or of the list's items */
    int count_size; /* 0 for a scalar; bytes of the list's count otherwise */
    int is_char;
    int kind;       /* of the scalar or the list's items: PLY_UNSIGNED, ... */
    int count_kind; /* of the list's count */
} ply_prop;

enum { PLY_UNSIGNED, PLY_SIGNED, PLY_FLOAT };

typedef struct ply_element {
    char name[32];
    long long count;
    ply_prop prop[32];
    int nprop;
} ply_element;

/* Bytes of a PLY scalar type, 0 if unknown; `kind` gets PLY_UNSIGNED,
 * PLY_SIGNED or PLY_FLOAT. */
static int ply_type_size(const char *t, int *is_char, int *kind)
{
    static const struct {
        const char *name;
        int size, kind;
    } types[] = {{"char", 1, PLY_SIGNED},    {"uchar", 1, PLY_UNSIGNED},
                 {"int8", 1, PLY_SIGNED},    {"uint8", 1, PLY_UNSIGNED},
                 {"short", 2, PLY_SIGNED},   {"ushort", 2, PLY_UNSIGNED},
                 {"int16", 2, PLY_SIGNED},   {"uint16", 2, PLY_UNSIGNED},
                 {"int", 4, PLY_SIGNED},     {"uint", 4, PLY_UNSIGNED},
                 {"int32", 4, PLY_SIGNED},   {"uint32", 4, PLY_UNSIGNED},
                 {"float", 4, PLY_FLOAT},    {"float32", 4, PLY_FLOAT},
                 {"double", 8, PLY_FLOAT},   {"float64", 8, PLY_FLOAT}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; ++i)
        if (strcmp(t, types[i].name) == 0) {
            if (is_char)
                *is_char = types[i].size == 1;
            *kind = types[i].kind;
            return types[i].size;
        }
    return 0;
}

/* Can an ascii value `s` (read as `v`) be read as the property's type:
 * finite and within a float's range, or an integer within the type's? */
static int ply_value_fits(const char *s, double v, const ply_prop *pp)
{
    long long n;
    char *end;
    if (pp->kind == PLY_FLOAT)
        return isfinite(v) && (pp->size == 8 || fabs(v) <= FLT_MAX);
    errno = 0;
    n = strtoll(s, &end, 10);
    if (end == s || *end != '\0' || errno != 0)
        return 0;
    if (pp->kind == PLY_UNSIGNED)
        return n >= 0 && n <= (long long)(pp->size == 4 ? 0xffffffffLL
                                                         : (1LL << (8 * pp->size)) - 1);
    return n >= -(1LL << (8 * pp->size - 1)) && n < (1LL << (8 * pp->size - 1));
}

/* An integer of `size` bytes (1, 2 or 4) from the file; 0 at end of file. */
static int read_ply_int(FILE *f, int size, int kind, int big, long long *out)
{
    unsigned char b[4];
    unsigned long v = 0;
    if (fread(b, 1, (size_t)size, f) != (size_t)size)
        return 0;
    for (int k = 0; k < size; ++k)
        v |= (unsigned long)b[big ? size - 1 - k : k] << (8 * k);
    if (kind == PLY_SIGNED && (v >> (8 * size - 1)) & 1)
        *out = (long long)v - (1LL << (8 * size));
    else
        *out = (long long)v;
    return 1;
}

/* Skips n bytes of the file through its buffer (fseek would drop the buffer
 * at every call); 0 when the file ends first. */
static int skip_bytes(FILE *f, long long n)
{
    char buf[4096];
    while (n > 0) {
        size_t want = n < (long long)sizeof buf ? (size_t)n : sizeof buf;
        if (fread(buf, 1, want, f) != want)
            return 0;
        n -= (long long)want;
    }
    return 1;
}

/* Binary body, item by item where an element has lists: every list count
 * must fit in what is left of the file, and each face must list 3 to
 * MAX_TOKENS - 1 distinct vertices that exist. OpenMesh trusts these counts
 * (it sizes a face by its count before reading it). */
static relief_status check_ply_body(reader *r, const ply_element *el, int nel,
                                    const ply_element *vert, const ply_element *face,
                                    int big, long long have, relief_error *err)
{
    long long at = 0; /* bytes of the body read so far */
    for (int e = 0; e < nel; ++e) {
        long long per = 0;
        int lists = 0;
        for (int p = 0; p < el[e].nprop; ++p) {
            per += el[e].prop[p].count_size ? 0 : el[e].prop[p].size;
            lists |= el[e].prop[p].count_size != 0;
        }
        if (!lists) { /* fixed size: the pre-check has counted it */
            if (!skip_bytes(r->f, per * el[e].count))
                return relief_fail(err, RELIEF_E_PARSE,
                                   "%s: truncated: the file ends in the '%s' items",
                                   r->path, el[e].name);
            at += per * el[e].count;
            continue;
        }
        for (long long i = 0; i < el[e].count; ++i) {
            for (int p = 0; p < el[e].nprop; ++p) {
                const ply_prop *pp = &el[e].prop[p];
                long long n, idx[MAX_TOKENS];
                int corners = &el[e] == face && (strcmp(pp->name, "vertex_indices") == 0 ||
                                                 strcmp(pp->name, "vertex_index") == 0);
                if (!pp->count_size) {
                    if (!skip_bytes(r->f, pp->size))
                        goto truncated;
                    at += pp->size;
                    continue;
                }
                if (pp->count_kind == PLY_FLOAT)
                    return relief_fail(err, RELIEF_E_PARSE,
                                       "%s: '%s' list '%s' has a floating-point count type",
                                       r->path, el[e].name, pp->name);
                if (!read_ply_int(r->f, pp->count_size, pp->count_kind, big, &n))
                    goto truncated;
                at += pp->count_size;
                if (n < 0 || n * pp->size > have - at)
                    return relief_fail(err, RELIEF_E_PARSE,
                                       "%s: '%s' item %lld: list '%s' declares %lld items "
                                       "(byte %lld of the body), more than the %lld bytes "
                                       "left",
                                       r->path, el[e].name, i, pp->name, n, at, have - at);
                if (!corners) {
                    if (!skip_bytes(r->f, n * pp->size))
                        goto truncated;
                    at += n * pp->size;
                    continue;
                }
                if (n < 3 || n >= MAX_TOKENS)
                    return relief_fail(err, RELIEF_E_PARSE,
                                       "%s: face %lld has %lld corners; expected 3 to %d",
                                       r->path, i, n, MAX_TOKENS - 1);
                if (pp->kind == PLY_FLOAT || pp->size > 4)
                    return relief_fail(err, RELIEF_E_PARSE,
                                       "%s: face vertex indices have a floating-point type",
                                       r->path);
                for (int k = 0; k < n; ++k) {
                    if (!read_ply_int(r->f, pp->size, pp->kind, big, &idx[k]))
                        goto truncated;
                    if (idx[k] < 0 || idx[k] >= vert->count)
                        return relief_fail(err, RELIEF_E_MESH,
                                           "%s: face %lld refers to vertex %lld but the "
                                           "file has %lld vertices",
                                           r->path, i, idx[k], vert->count);
                    for (int j = 0; j < k; ++j)
                        if (idx[j] == idx[k])
                            return relief_fail(err, RELIEF_E_MESH,
                                               "%s: face %lld uses vertex %lld twice",
                                               r->path, i, idx[k]);
                }
                at += n * pp->size;
            }
            continue;
        truncated:
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s: truncated: the file ends in '%s' item %lld of the "
                               "%lld the header declares",
                               r->path, el[e].name, i, el[e].count);
        }
    }
    return RELIEF_OK;
}

/* A PLY version as written in practice ("1.0"): digits with at most one dot,
 * short, and at most 1000. Anything else may not read as a float: OpenMesh's
 * "0.e" fails, and a long run of digits overflows a float (both hang it). */
static int plain_version(const char *s)
{
    int digits = 0, dots = 0;
    if (strlen(s) > 16 || relief_strtod(s, NULL) > 1000.0)
        return 0;
    for (; *s; ++s) {
        if (*s >= '0' && *s <= '9')
            ++digits;
        else if (*s == '.' && dots == 0)
            ++dots;
        else
            return 0;
    }
    return digits > 0;
}

/* A PLY header as read: its elements in order, the format, and the vertex
 * and face elements (NULL until found). */
typedef struct ply_header {
    ply_element el[16];
    int nel, fmt, big; /* fmt: -1 none yet, 0 ascii, 1 binary; big: big-endian */
    ply_element *vert, *face;
} ply_header;

static relief_status bad_header_line(const reader *r, relief_error *err)
{
    return relief_fail(err, RELIEF_E_PARSE, "%s:%ld: malformed PLY header line",
                       r->path, r->lineno);
}

/* OpenMesh reads the header as a stream of words, not lines: after
 * obj_info it takes each word as a keyword, and a header keyword there
 * would start an element or property we never checked. */
static relief_status header_obj_info(const reader *r, relief_error *err)
{
    for (int t = 1; t < r->ntok; ++t)
        if (strcmp(r->tok[t], "element") == 0 || strcmp(r->tok[t], "property") == 0 ||
            strcmp(r->tok[t], "end_header") == 0)
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s:%ld: the obj_info line holds the header "
                               "keyword '%s'",
                               r->path, r->lineno, r->tok[t]);
    return RELIEF_OK;
}

/* 'format ascii|binary_little_endian|binary_big_endian VERSION'. */
static relief_status header_format(const reader *r, ply_header *h, relief_error *err)
{
    /* OpenMesh reads the version as a float and loops forever on a header
     * word it cannot read, so only plain versions pass. */
    if (r->ntok != 3 || !plain_version(r->tok[2]))
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s:%ld: expected 'format ascii|binary_little_endian|"
                           "binary_big_endian VERSION' with VERSION such as 1.0",
                           r->path, r->lineno);
    if (strcmp(r->tok[1], "ascii") == 0)
        h->fmt = 0;
    else if (strcmp(r->tok[1], "binary_little_endian") == 0 ||
             strcmp(r->tok[1], "binary_big_endian") == 0) {
        h->fmt = 1;
        h->big = r->tok[1][7] == 'b';
    }
    else
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s:%ld: unknown PLY format '%s'; expected ascii, "
                           "binary_little_endian or binary_big_endian",
                           r->path, r->lineno, r->tok[1]);
    return RELIEF_OK;
}

/* 'element NAME COUNT': a new element, at most 16. */
static relief_status header_element(const reader *r, ply_header *h, relief_error *err)
{
    long long n;
    /* OpenMesh reads COUNT as an unsigned int (and loops forever on one it
     * cannot read). */
    if (r->ntok != 3 || !io_parse_long(r->tok[2], &n) || n < 0 || n > UINT_MAX)
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s:%ld: expected 'element NAME COUNT' with COUNT in "
                           "0..%u",
                           r->path, r->lineno, UINT_MAX);
    if (h->nel == 16)
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s:%ld: more than 16 elements", r->path, r->lineno);
    memset(&h->el[h->nel], 0, sizeof h->el[h->nel]);
    snprintf(h->el[h->nel].name, sizeof h->el[h->nel].name, "%s", r->tok[1]);
    h->el[h->nel].count = n;
    ++h->nel;
    return RELIEF_OK;
}

/* 'property TYPE NAME' or 'property list COUNT_TYPE TYPE NAME' of the last
 * element, at most 32 to an element. */
static relief_status header_property(const reader *r, ply_header *h, relief_error *err)
{
    ply_element *e;
    ply_prop *p;
    if (h->nel == 0)
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s:%ld: property before any element",
                           r->path, r->lineno);
    e = &h->el[h->nel - 1];
    if (e->nprop == 32)
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s:%ld: more than 32 properties", r->path, r->lineno);
    p = &e->prop[e->nprop];
    if (r->ntok == 3) {
        p->size = ply_type_size(r->tok[1], &p->is_char, &p->kind);
        snprintf(p->name, sizeof p->name, "%s", r->tok[2]);
        if (!p->size)
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s:%ld: unknown property type '%s'",
                               r->path, r->lineno, r->tok[1]);
    } else if (r->ntok == 5 && strcmp(r->tok[1], "list") == 0) {
        p->count_size = ply_type_size(r->tok[2], NULL, &p->count_kind);
        p->size = ply_type_size(r->tok[3], NULL, &p->kind);
        snprintf(p->name, sizeof p->name, "%s", r->tok[4]);
        if (!p->count_size || !p->size)
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s:%ld: unknown list types '%s %s'",
                               r->path, r->lineno, r->tok[2], r->tok[3]);
    } else {
        return bad_header_line(r, err);
    }
    ++e->nprop;
    return RELIEF_OK;
}

/* The header, from the magic line to end_header; it must have a format. */
static relief_status ply_read_header(reader *r, ply_header *h, relief_error *err)
{
    int ended = 0;
    if (!io_next_line(r, 0) || r->ntok != 1 || strcmp(r->tok[0], "ply") != 0)
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s:1: expected the PLY magic line 'ply'", r->path);
    while (io_next_line(r, 0)) {
        relief_status st;
        if (r->ntok == 0 || strcmp(r->tok[0], "comment") == 0)
            continue;
        if (strcmp(r->tok[0], "end_header") == 0) {
            ended = 1;
            break;
        }
        if (strcmp(r->tok[0], "obj_info") == 0)
            st = header_obj_info(r, err);
        else if (strcmp(r->tok[0], "format") == 0)
            st = header_format(r, h, err);
        else if (strcmp(r->tok[0], "element") == 0)
            st = header_element(r, h, err);
        else if (strcmp(r->tok[0], "property") == 0)
            st = header_property(r, h, err);
        else
            st = bad_header_line(r, err);
        if (st != RELIEF_OK)
            return st;
    }
    if (!ended)
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s: the PLY header has no 'end_header' line (truncated?)",
                           r->path);
    if (h->fmt < 0)
        return relief_fail(err, RELIEF_E_PARSE, "%s: the PLY header has no 'format' line",
                           r->path);
    return RELIEF_OK;
}

/* The vertex element OpenMesh can read: scalar x, y, z, no list, all of
 * red, green and blue or none; finds h->vert and h->face. */
static relief_status ply_check_vertex_element(const reader *r, ply_header *h,
                                              relief_file_check *out, relief_error *err)
{
    static const char *const rgb[3] = {"red", "green", "blue"};
    const ply_element *vert;
    int xyz = 0, have = 0;
    for (int e = 0; e < h->nel; ++e) {
        if (strcmp(h->el[e].name, "vertex") == 0)
            h->vert = &h->el[e];
        else if (strcmp(h->el[e].name, "face") == 0)
            h->face = &h->el[e];
    }
    if (!h->vert)
        return relief_fail(err, RELIEF_E_PARSE, "%s: the PLY header declares no 'vertex' element",
                           r->path);
    vert = h->vert;
    for (int p = 0; p < vert->nprop; ++p) {
        const char *n = vert->prop[p].name;
        if (!vert->prop[p].count_size &&
            (strcmp(n, "x") == 0 || strcmp(n, "y") == 0 || strcmp(n, "z") == 0))
            ++xyz;
        if (strcmp(n, "label") == 0 && vert->prop[p].is_char && h->fmt == 0)
            out->ascii_char_label = 1;
        /* OpenMesh reads a vertex's list as more scalars (ascii: the
         * coordinates come out shifted; binary: the faces then fail), and
         * with some headers from uninitialised memory. */
        if (vert->prop[p].count_size)
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s: the PLY 'vertex' element has a list property "
                               "'%s'; only scalar vertex properties can be read",
                               r->path, n);
    }
    if (xyz != 3)
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s: the PLY 'vertex' element lacks scalar x, y, z properties",
                           r->path);
    /* OpenMesh reads a colour from red, green and blue together: with only
     * some of them its ascii reader goes out of step, and the next face
     * takes some value as a corner count (found by fuzzing: 'rgd green
     * blue', a 2 GiB face). */
    for (int c = 0; c < 3; ++c)
        for (int p = 0; p < vert->nprop; ++p)
            if (strcmp(vert->prop[p].name, rgb[c]) == 0) {
                have |= 1 << c;
                break;
            }
    if (have != 0 && have != 7)
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s: the PLY 'vertex' element has %s%s%s but not all of "
                           "red, green and blue; a colour needs the three",
                           r->path, have & 1 ? "red " : "", have & 2 ? "green " : "",
                           have & 4 ? "blue" : "");
    return RELIEF_OK;
}

/* Binary: the body must hold at least every element at its smallest (lists
 * of faces with 3 items, other lists empty); then every value is read. */
static relief_status ply_check_binary(reader *r, const ply_header *h, long long fsize,
                                      relief_error *err)
{
    const ply_element *el = h->el, *vert = h->vert, *face = h->face;
    long long need = 0, have = fsize - ftell(r->f);
    for (int e = 0; e < h->nel; ++e) {
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
    return check_ply_body(r, el, h->nel, vert, face, h->big, have, err);
}

/* An ascii vertex, item i: a number for each property, finite coordinates,
 * each value readable as its declared type. */
static relief_status ascii_vertex(const reader *r, const ply_element *vert, long long i,
                                  relief_error *err)
{
    int t = 0;
    for (int p = 0; p < vert->nprop; ++p) {
        const ply_prop *pp = &vert->prop[p];
        double v;
        if (t >= r->ntok)
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s:%ld: vertex %lld has %d value(s); the "
                               "header declares %d properties",
                               r->path, r->lineno, i, r->ntok, vert->nprop);
        if (!io_parse_double(r->tok[t], &v))
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
        /* A value OpenMesh's stream cannot read as the declared type (NaN,
         * beyond a float, negative or too large for the integer) puts the
         * stream out of step: the next face then takes some value as a
         * corner count (found by fuzzing: a 2 GiB face). */
        if (!ply_value_fits(r->tok[t], v, pp))
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s:%ld: vertex %lld: property '%s' value '%s' "
                               "does not fit its %s%d-byte type",
                               r->path, r->lineno, i, pp->name, r->tok[t],
                               pp->kind == PLY_FLOAT      ? "floating-point "
                               : pp->kind == PLY_SIGNED ? "signed "
                                                        : "unsigned ",
                               pp->size);
        ++t;
    }
    return RELIEF_OK;
}

/* An ascii face, item i of element `face`: a corner count and as many
 * integer indices, each a vertex of the file. */
static relief_status ascii_face(const reader *r, const ply_element *face,
                                const ply_element *vert, long long i, relief_error *err)
{
    long long n, idx[MAX_TOKENS];
    if (r->ntok < 1 || !io_parse_long(r->tok[0], &n) || n < 0)
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s:%ld: malformed '%s' item %lld", r->path, r->lineno,
                           face->name, i);
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
        if (!io_parse_long(r->tok[1 + k], &idx[k]))
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s:%ld: face %lld: index '%s' is not an "
                               "integer",
                               r->path, r->lineno, i, r->tok[1 + k]);
    return io_check_corners(r, idx, (int)n, i, vert->count, err);
}

/* Ascii: one line per element item, in header order. */
static relief_status ply_check_ascii(reader *r, const ply_header *h, relief_error *err)
{
    for (int e = 0; e < h->nel; ++e) {
        const ply_element *el = &h->el[e];
        for (long long i = 0; i < el->count; ++i) {
            relief_status st = RELIEF_OK;
            if (!io_next_line(r, 0))
                return relief_fail(err, RELIEF_E_PARSE,
                                   "%s:%ld: truncated: the file ends after %lld of the "
                                   "%lld '%s' items the header declares",
                                   r->path, r->lineno, i, el->count, el->name);
            if (el == h->vert)
                st = ascii_vertex(r, el, i, err);
            else if (el == h->face)
                st = ascii_face(r, el, h->vert, i, err);
            if (st != RELIEF_OK)
                return st;
        }
    }
    return RELIEF_OK;
}

relief_status io_check_ply(reader *r, relief_file_check *out, long long fsize,
                               relief_error *err)
{
    ply_header h;
    relief_status st;
    memset(&h, 0, sizeof h);
    h.fmt = -1;
    st = ply_read_header(r, &h, err);
    if (st == RELIEF_OK)
        st = ply_check_vertex_element(r, &h, out, err);
    if (st != RELIEF_OK)
        return st;
    out->binary = h.fmt == 1;
    out->vertices = h.vert->count;
    out->faces = h.face ? h.face->count : 0;
    if (h.fmt == 1)
        return ply_check_binary(r, &h, fsize, err);
    return ply_check_ascii(r, &h, err);
}
