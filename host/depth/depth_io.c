/* PCD and PFM decoders. Every count and offset read from a header is
 * checked against the bytes that are there before it is used, in 64 bits,
 * so that a hostile header can neither overflow a size nor read past the
 * buffer; the fuzz harness (tests/fuzz/fuzz_read_depth.c) holds them to it. */
#include "depth/depth_io.h"

#include <ctype.h>
#include <errno.h>
#include <liblzf/lzf.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/file.h"
#include "base/numtext.h"
#include "mesh/mesh.h"

void relief_depth_frame_free(relief_depth_frame *f)
{
    if (!f)
        return;
    free(f->z);
    free(f->xyz);
    free(f->rgb);
    f->z = f->xyz = NULL;
    f->rgb = NULL;
}

/* An unorganised cloud (HEIGHT 1) may be this long. */
#define PCD_MAX_CLOUD 100000000LL

static relief_status check_sides(const char *name, long long w, long long h,
                                 uint64_t max_pixels, relief_error *err)
{
    if (h == 1 && w > RELIEF_DEPTH_MAX_SIDE && w <= PCD_MAX_CLOUD)
        return max_pixels && (uint64_t)w > max_pixels
                   ? relief_fail(err, RELIEF_E_NOMEM, "%s: a cloud of %lld points is over the "
                                 "limit of %llu points (max_points)", name, w,
                                 (unsigned long long)max_pixels)
                   : RELIEF_OK;
    if (w < 1 || h < 1)
        return relief_fail(err, RELIEF_E_PARSE, "%s: a frame of %lld x %lld pixels: nothing to "
                           "read", name, w, h);
    if (w > RELIEF_DEPTH_MAX_SIDE || h > RELIEF_DEPTH_MAX_SIDE)
        return relief_fail(err, RELIEF_E_RANGE, "%s: a frame of %lld x %lld pixels: each side "
                           "must be at most %d", name, w, h, RELIEF_DEPTH_MAX_SIDE);
    if (max_pixels && (uint64_t)w * (uint64_t)h > max_pixels)
        return relief_fail(err, RELIEF_E_NOMEM, "%s: a frame of %lld x %lld pixels is over the "
                           "limit of %llu pixels (max_pixels)", name, w, h,
                           (unsigned long long)max_pixels);
    return RELIEF_OK;
}

static relief_status alloc_frame(relief_depth_frame *f, int w, int h, int with_xyz,
                                 int with_rgb, const char *name, relief_error *err)
{
    size_t px = (size_t)w * (size_t)h;
    memset(f, 0, sizeof *f);
    f->width = w;
    f->height = h;
    f->z = malloc(px * sizeof(float));
    f->xyz = with_xyz ? malloc(px * 3 * sizeof(float)) : NULL;
    f->rgb = with_rgb ? malloc(px * 3) : NULL;
    if (!f->z || (with_xyz && !f->xyz) || (with_rgb && !f->rgb)) {
        relief_depth_frame_free(f);
        return relief_fail(err, RELIEF_E_NOMEM, "%s: cannot allocate a %d x %d frame", name, w,
                           h);
    }
    return RELIEF_OK;
}

/* ---------------------------------------------------------------- PFM */

/* The next whitespace-separated token of the header at *at (at most
 * cap - 1 characters), skipping '#' comments. */
static int header_token(const uint8_t *d, size_t n, size_t *at, char *tok, size_t cap)
{
    size_t k = 0;
    while (*at < n) {
        if (d[*at] == '#') {
            while (*at < n && d[*at] != '\n')
                ++*at;
        } else if (isspace(d[*at])) {
            ++*at;
        } else {
            break;
        }
    }
    while (*at < n && !isspace(d[*at]) && k + 1 < cap)
        tok[k++] = (char)d[(*at)++];
    tok[k] = '\0';
    return k > 0 && (*at >= n || isspace(d[*at]));
}

relief_status relief_pfm_decode(const uint8_t *d, size_t n, const char *name,
                                uint64_t max_pixels, relief_depth_frame *out,
                                relief_error *err)
{
    char tok[64], *end;
    size_t at = 0, need;
    long long w, h;
    double scale;
    int channels, little;
    relief_status st;

    memset(out, 0, sizeof *out);
    if (!header_token(d, n, &at, tok, sizeof tok) || (strcmp(tok, "Pf") && strcmp(tok, "PF")))
        return relief_fail(err, RELIEF_E_FORMAT, "%s: not a PFM (it starts with neither Pf "
                           "nor PF)", name);
    channels = tok[1] == 'F' ? 3 : 1;
    if (!header_token(d, n, &at, tok, sizeof tok) || (w = strtoll(tok, &end, 10), *end) ||
        !header_token(d, n, &at, tok, sizeof tok) || (h = strtoll(tok, &end, 10), *end))
        return relief_fail(err, RELIEF_E_PARSE, "%s: PFM header: expected WIDTH HEIGHT after "
                           "the magic", name);
    if (!header_token(d, n, &at, tok, sizeof tok) || (scale = relief_strtod(tok, &end), *end) ||
        !isfinite(scale) || scale == 0.0)
        return relief_fail(err, RELIEF_E_PARSE, "%s: PFM header: expected a non-zero scale "
                           "(its sign is the byte order) after the size", name);
    st = check_sides(name, w, h, max_pixels, err);
    if (st != RELIEF_OK)
        return st;
    ++at; /* the single whitespace character that ends the header */
    little = scale < 0.0;
    need = (size_t)w * (size_t)h * (size_t)channels * 4u;
    if (at > n || n - at < need)
        return relief_fail(err, RELIEF_E_PARSE, "%s: PFM truncated: %lld x %lld x %d floats "
                           "need %zu bytes after the header, the file has %zu", name, w, h,
                           channels, need, at > n ? (size_t)0 : n - at);
    st = alloc_frame(out, (int)w, (int)h, 0, 0, name, err);
    if (st != RELIEF_OK)
        return st;
    for (long long y = 0; y < h; ++y)
        for (long long x = 0; x < w; ++x) {
            /* PFM rows run bottom to top. */
            const uint8_t *p = d + at + ((size_t)(h - 1 - y) * w + x) * channels * 4u;
            uint32_t u = little ? (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 |
                                      (uint32_t)p[3] << 24
                                : (uint32_t)p[3] | (uint32_t)p[2] << 8 | (uint32_t)p[1] << 16 |
                                      (uint32_t)p[0] << 24;
            float v;
            memcpy(&v, &u, sizeof v);
            out->z[(size_t)y * w + x] = isfinite(v) ? v : NAN;
        }
    out->format = RELIEF_DEPTH_PFM;
    return RELIEF_OK;
}

/* ---------------------------------------------------------------- PCD */

#define PCD_MAX_FIELDS 32

typedef struct pcd_field {
    char name[32];
    int size, count; /* bytes per value, values */
    char type;       /* F, U or I */
} pcd_field;

typedef struct pcd_header {
    pcd_field f[PCD_MAX_FIELDS];
    int nf;
    long long width, height, points;
    enum { PCD_ASCII, PCD_BINARY, PCD_COMPRESSED } data;
    size_t body; /* offset of the data */
} pcd_header;

/* Split a header line into at most `max` words. */
static int words(char *line, char **w, int max)
{
    int k = 0;
    char *save = NULL;
    for (char *t = strtok_r(line, " \t\r", &save); t && k < max; t = strtok_r(NULL, " \t\r", &save))
        w[k++] = t;
    return k;
}

/* Which of the per-field keys the header has given so far. */
typedef struct pcd_seen {
    int fields, size, type, count;
} pcd_seen;

/* A FIELDS, SIZE, TYPE or COUNT line (k words w, w[0] the key) into h's
 * fields; once FIELDS has come, each lists one value per field. The key
 * is noted in seen. */
static relief_status parse_field_line(char **w, int k, int line_no, pcd_seen *seen,
                                      pcd_header *h, const char *name, relief_error *err)
{
    char shown[4 * RELIEF_ESCAPE_MAX + 4];
    if (k - 1 > PCD_MAX_FIELDS || k < 2)
        return relief_fail(err, RELIEF_E_PARSE, "%s: PCD header line %d: %s lists %d "
                           "fields; expected 1..%d", name, line_no, w[0], k - 1,
                           PCD_MAX_FIELDS);
    if (seen->fields && k - 1 != h->nf)
        return relief_fail(err, RELIEF_E_PARSE, "%s: PCD header line %d: %s lists %d "
                           "values for %d fields", name, line_no, w[0], k - 1, h->nf);
    h->nf = k - 1;
    for (int i = 0; i < h->nf; ++i) {
        char *end;
        long v;
        if (w[0][0] == 'F') {
            snprintf(h->f[i].name, sizeof h->f[i].name, "%s", w[i + 1]);
        } else if (w[0][0] == 'T') {
            if (strlen(w[i + 1]) != 1 || !strchr("FUI", w[i + 1][0]))
                return relief_fail(err, RELIEF_E_PARSE, "%s: PCD header line %d: "
                                   "TYPE '%s' is not F, U or I", name, line_no,
                                   relief_escape(w[i + 1], RELIEF_ESCAPE_MAX, shown,
                                                 sizeof shown));
            h->f[i].type = w[i + 1][0];
        } else {
            v = strtol(w[i + 1], &end, 10);
            if (*end || v < 1 || v > (w[0][0] == 'S' ? 8 : 1 << 20))
                return relief_fail(err, RELIEF_E_PARSE, "%s: PCD header line %d: %s "
                                   "'%s' is out of range", name, line_no, w[0],
                                   relief_escape(w[i + 1], RELIEF_ESCAPE_MAX, shown,
                                                 sizeof shown));
            if (w[0][0] == 'S')
                h->f[i].size = (int)v;
            else
                h->f[i].count = (int)v;
        }
    }
    seen->fields |= w[0][0] == 'F';
    seen->size |= w[0][0] == 'S';
    seen->type |= w[0][0] == 'T';
    seen->count |= w[0][0] == 'C';
    return RELIEF_OK;
}

/* A WIDTH, HEIGHT or POINTS line (k words w): its one count, >= 0, into h. */
static relief_status parse_count_line(char **w, int k, int line_no, pcd_header *h,
                                      const char *name, relief_error *err)
{
    char *end;
    long long v = k == 2 ? strtoll(w[1], &end, 10) : -1;
    if (k != 2 || *end || v < 0)
        return relief_fail(err, RELIEF_E_PARSE, "%s: PCD header line %d: %s expects "
                           "one count", name, line_no, w[0]);
    if (w[0][0] == 'W')
        h->width = v;
    else if (w[0][0] == 'H')
        h->height = v;
    else
        h->points = v;
    return RELIEF_OK;
}

/* The DATA line (k words w), which ends the header: the data's encoding
 * and where it starts (at, just past the line, in n bytes), then the
 * checks that need the whole header (seen: the keys given). */
static relief_status parse_data_line(char **w, int k, int line_no, size_t at, size_t n,
                                     const pcd_seen *seen, pcd_header *h, const char *name,
                                     relief_error *err)
{
    if (k != 2 || (strcmp(w[1], "ascii") && strcmp(w[1], "binary") &&
                   strcmp(w[1], "binary_compressed")))
        return relief_fail(err, RELIEF_E_PARSE, "%s: PCD header line %d: DATA must be "
                           "ascii, binary or binary_compressed", name, line_no);
    h->data = w[1][0] == 'a' ? PCD_ASCII : strcmp(w[1], "binary") == 0 ? PCD_BINARY
                                                                         : PCD_COMPRESSED;
    h->body = at > n ? n : at;
    if (!seen->fields || !seen->size || !seen->type)
        return relief_fail(err, RELIEF_E_PARSE, "%s: PCD header: FIELDS, SIZE and TYPE "
                           "must come before DATA", name);
    if (!seen->count)
        for (int i = 0; i < h->nf; ++i)
            h->f[i].count = 1;
    if (h->width < 0 || h->height < 0)
        return relief_fail(err, RELIEF_E_PARSE, "%s: PCD header: WIDTH and HEIGHT must "
                           "come before DATA", name);
    /* Sides over the maximum are refused later; their product
     * could overflow here. A cloud (HEIGHT 1) is WIDTH points. */
    if (h->points >= 0 &&
        (h->height == 1 ||
         (h->width <= RELIEF_DEPTH_MAX_SIDE && h->height <= RELIEF_DEPTH_MAX_SIDE)) &&
        h->points != h->width * h->height)
        return relief_fail(err, RELIEF_E_PARSE, "%s: PCD header: POINTS %lld is not "
                           "WIDTH x HEIGHT (%lld x %lld)", name, h->points, h->width,
                           h->height);
    return RELIEF_OK;
}

/* The header of the n bytes at d into h, line by line up to DATA (h->body
 * then the offset of the data). */
static relief_status parse_header(const uint8_t *d, size_t n, const char *name, pcd_header *h,
                                  relief_error *err)
{
    size_t at = 0;
    int line_no = 0;
    pcd_seen seen = {0, 0, 0, 0};
    relief_status st;
    memset(h, 0, sizeof *h);
    h->width = h->height = h->points = -1;
    while (at < n) {
        char line[1024], *w[PCD_MAX_FIELDS + 2], shown[4 * RELIEF_ESCAPE_MAX + 4];
        size_t len = 0;
        int k;
        ++line_no;
        while (at < n && d[at] != '\n' && len + 1 < sizeof line)
            line[len++] = (char)d[at++];
        if (at < n && d[at] != '\n')
            return relief_fail(err, RELIEF_E_PARSE, "%s: PCD header line %d is too long", name,
                               line_no);
        ++at; /* the newline */
        line[len] = '\0';
        if (len == 0 || line[0] == '#')
            continue;
        k = words(line, w, PCD_MAX_FIELDS + 2);
        if (k == 0)
            continue;
        if (strcmp(w[0], "VERSION") == 0 || strcmp(w[0], "VIEWPOINT") == 0)
            continue;
        if (strcmp(w[0], "FIELDS") == 0 || strcmp(w[0], "SIZE") == 0 ||
            strcmp(w[0], "TYPE") == 0 || strcmp(w[0], "COUNT") == 0) {
            st = parse_field_line(w, k, line_no, &seen, h, name, err);
            if (st != RELIEF_OK)
                return st;
            continue;
        }
        if (strcmp(w[0], "WIDTH") == 0 || strcmp(w[0], "HEIGHT") == 0 ||
            strcmp(w[0], "POINTS") == 0) {
            st = parse_count_line(w, k, line_no, h, name, err);
            if (st != RELIEF_OK)
                return st;
            continue;
        }
        if (strcmp(w[0], "DATA") == 0)
            return parse_data_line(w, k, line_no, at, n, &seen, h, name, err);
        return relief_fail(err, RELIEF_E_PARSE, "%s: PCD header line %d: unknown key '%s'", name,
                           line_no, relief_escape(w[0], RELIEF_ESCAPE_MAX, shown, sizeof shown));
    }
    return relief_fail(err, RELIEF_E_PARSE, "%s: PCD header: no DATA line (truncated?)", name);
}

/* Value i (of `count`) of a field at p as a float. */
static float field_value(const uint8_t *p, const pcd_field *f)
{
    if (f->type == 'F' && f->size == 4) {
        float v;
        memcpy(&v, p, 4);
        return v;
    }
    if (f->type == 'F' && f->size == 8) {
        double v;
        memcpy(&v, p, 8);
        return (float)v;
    }
    return NAN;
}

/* The ascii DATA from p to end into out's xyz and rgb (ix, iy, iz, ic the
 * fields' indices, ic -1 without colour). */
static relief_status decode_ascii(const char *p, const char *end, const pcd_header *h, int ix,
                                  int iy, int iz, int ic, size_t px, relief_depth_frame *out,
                                  const char *name, relief_error *err)
{
    for (size_t i = 0; i < px; ++i)
        for (int k = 0; k < h->nf; ++k)
            for (int c = 0; c < h->f[k].count; ++c) {
                char tok[64], shown[4 * RELIEF_ESCAPE_MAX + 4];
                size_t len = 0;
                double v;
                char *e;
                while (p < end && isspace((unsigned char)*p))
                    ++p;
                while (p < end && !isspace((unsigned char)*p) && len + 1 < sizeof tok)
                    tok[len++] = *p++;
                tok[len] = '\0';
                if (len == 0)
                    return relief_fail(err, RELIEF_E_PARSE, "%s: PCD ascii data ends at "
                                       "point %zu of %zu (truncated)", name, i, px);
                v = relief_strtod(tok, &e);
                if (*e && strcmp(tok, "nan") && strcmp(tok, "NaN"))
                    return relief_fail(err, RELIEF_E_PARSE, "%s: PCD ascii point %zu: '%s' "
                                       "is not a number", name, i,
                                       relief_escape(tok, RELIEF_ESCAPE_MAX, shown,
                                                     sizeof shown));
                if (*e)
                    v = NAN;
                if (k == ix || k == iy || k == iz)
                    out->xyz[i * 3 + (k == ix ? 0 : k == iy ? 1 : 2)] = (float)v;
                else if (k == ic) {
                    /* rgb packs 0x00RRGGBB: as an integer (TYPE U or I, and
                     * PCL's ascii for TYPE F too: a whole number >= 1), or
                     * in a float's bits (older writers print that float). */
                    uint32_t u;
                    if (h->f[k].type == 'F' && !(v >= 1.0 && v == floor(v))) {
                        float fv = (float)v;
                        memcpy(&u, &fv, 4);
                    } else {
                        u = v >= 0 && v < 4294967296.0 ? (uint32_t)v : 0;
                    }
                    out->rgb[i * 3] = (uint8_t)(u >> 16);
                    out->rgb[i * 3 + 1] = (uint8_t)(u >> 8);
                    out->rgb[i * 3 + 2] = (uint8_t)u;
                }
            }
    return RELIEF_OK;
}

/* Where each of a header's fields sits in a point: offset[i] bytes into
 * it, point_bytes in all; ix, iy, iz and ic the indices of x, y, z and
 * the colour (rgb or rgba), -1 where there is none. */
typedef struct pcd_layout {
    size_t offset[PCD_MAX_FIELDS], point_bytes;
    int ix, iy, iz, ic;
} pcd_layout;

/* h's fields laid out into L. */
static void layout_fields(const pcd_header *h, pcd_layout *L)
{
    L->ix = L->iy = L->iz = L->ic = -1;
    L->point_bytes = 0;
    for (int i = 0; i < h->nf; ++i) {
        L->offset[i] = L->point_bytes;
        L->point_bytes += (size_t)h->f[i].size * (size_t)h->f[i].count;
        if (strcmp(h->f[i].name, "x") == 0)
            L->ix = i;
        else if (strcmp(h->f[i].name, "y") == 0)
            L->iy = i;
        else if (strcmp(h->f[i].name, "z") == 0)
            L->iz = i;
        else if (strcmp(h->f[i].name, "rgb") == 0 || strcmp(h->f[i].name, "rgba") == 0)
            L->ic = i;
    }
}

/* The fields and the sides, before the data is looked at: x, y and z
 * each F4 or F8 of count 1; a colour not packed in 4 bytes is dropped
 * (L->ic set to -1); organised_only refuses a cloud (HEIGHT 1). */
static relief_status check_fields(const pcd_header *h, pcd_layout *L, int organised_only,
                                  uint64_t max_pixels, const char *name, relief_error *err)
{
    if (L->ix < 0 || L->iy < 0 || L->iz < 0)
        return relief_fail(err, RELIEF_E_FORMAT, "%s: the PCD has no x, y and z fields", name);
    for (int i = 0; i < h->nf; ++i)
        if ((i == L->ix || i == L->iy || i == L->iz) &&
            (h->f[i].type != 'F' || (h->f[i].size != 4 && h->f[i].size != 8) ||
             h->f[i].count != 1))
            return relief_fail(err, RELIEF_E_FORMAT, "%s: PCD field %s is %c%d x %d; expected "
                               "F4 or F8, count 1", name, h->f[i].name, h->f[i].type,
                               h->f[i].size, h->f[i].count);
    if (L->ic >= 0 && (h->f[L->ic].size != 4 || h->f[L->ic].count != 1))
        L->ic = -1; /* a colour packed otherwise is skipped */
    if (organised_only && h->height == 1 && h->width > 1)
        return relief_fail(err, RELIEF_E_FORMAT, "%s: an unorganised point cloud (HEIGHT 1, "
                           "%lld points): a depth image needs an organised one (WIDTH x HEIGHT "
                           "pixels)", name, h->width);
    return check_sides(name, h->width, h->height, max_pixels, err);
}

/* The binary_compressed data of the n bytes at d: its two sizes checked
 * against px points of L->point_bytes and against the file, then the LZF
 * data decompressed into *plain (malloc'd, the caller's to free). */
static relief_status decompress_data(const uint8_t *d, size_t n, const pcd_header *h,
                                     const pcd_layout *L, size_t px, uint8_t **plain,
                                     const char *name, relief_error *err)
{
    uint32_t csize, usize;
    uint8_t *u;
    if (n - h->body < 8)
        return relief_fail(err, RELIEF_E_PARSE, "%s: PCD truncated: no compressed sizes "
                           "after DATA", name);
    memcpy(&csize, d + h->body, 4);
    memcpy(&usize, d + h->body + 4, 4);
    if ((uint64_t)usize != (uint64_t)px * L->point_bytes)
        return relief_fail(err, RELIEF_E_PARSE, "%s: PCD binary_compressed: %u bytes "
                           "uncompressed, expected %zu for %zu points of %zu bytes", name,
                           usize, px * L->point_bytes, px, L->point_bytes);
    if (csize > n - h->body - 8)
        return relief_fail(err, RELIEF_E_PARSE, "%s: PCD truncated: %u compressed bytes "
                           "announced, %zu there", name, csize, n - h->body - 8);
    u = malloc(usize ? usize : 1);
    if (!u)
        return relief_fail(err, RELIEF_E_NOMEM, "%s: cannot allocate %u bytes", name, usize);
    if (lzf_decompress(d + h->body + 8, csize, u, usize) != usize) {
        free(u);
        return relief_fail(err, RELIEF_E_PARSE, "%s: PCD binary_compressed: the LZF data "
                           "is corrupt", name);
    }
    *plain = u;
    return RELIEF_OK;
}

/* Whether the data (from h->body of the n bytes at d) can hold px points,
 * checked before the frame is allocated; binary_compressed data is
 * decompressed into *plain (see decompress_data), which stays NULL
 * otherwise. */
static relief_status check_data(const uint8_t *d, size_t n, const pcd_header *h,
                                const pcd_layout *L, size_t px, uint8_t **plain,
                                const char *name, relief_error *err)
{
    if (h->data == PCD_COMPRESSED) {
        return decompress_data(d, n, h, L, px, plain, name, err);
    } else if (h->data == PCD_BINARY) {
        if ((uint64_t)(n - h->body) < (uint64_t)px * L->point_bytes)
            return relief_fail(err, RELIEF_E_PARSE, "%s: PCD truncated: %zu points of %zu bytes "
                               "need %zu bytes, the file has %zu", name, px, L->point_bytes,
                               px * L->point_bytes, n - h->body);
    } else {
        /* ascii: each value is at least one character, so that a header
         * claiming 1e8 points over a few bytes is refused before the frame
         * is allocated (under 2^32 points x 2^25 values: no overflow). */
        uint64_t values = 0;
        for (int k = 0; k < h->nf; ++k)
            values += (uint64_t)h->f[k].count;
        if ((uint64_t)(n - h->body) < (uint64_t)px * values)
            return relief_fail(err, RELIEF_E_PARSE, "%s: PCD truncated: %zu points of %llu "
                               "ascii values need at least %llu bytes, the file has %zu", name,
                               px, (unsigned long long)values,
                               (unsigned long long)((uint64_t)px * values), n - h->body);
    }
    return RELIEF_OK;
}

/* The binary data (point by point from d + h->body) or the decompressed
 * binary_compressed data (field by field at plain) of px points into
 * out's xyz and rgb. */
static void decode_binary(const uint8_t *d, const pcd_header *h, const pcd_layout *L,
                          const uint8_t *plain, size_t px, relief_depth_frame *out)
{
    for (size_t i = 0; i < px; ++i)
        for (int k = 0; k < h->nf; ++k) {
            const uint8_t *p;
            if (k != L->ix && k != L->iy && k != L->iz && k != L->ic)
                continue;
            /* binary: point by point; compressed: field by field. */
            p = h->data == PCD_BINARY
                    ? d + h->body + i * L->point_bytes + L->offset[k]
                    : plain + L->offset[k] * px + i * (size_t)h->f[k].size * h->f[k].count;
            if (k == L->ic) {
                uint32_t u;
                memcpy(&u, p, 4);
                out->rgb[i * 3] = (uint8_t)(u >> 16);
                out->rgb[i * 3 + 1] = (uint8_t)(u >> 8);
                out->rgb[i * 3 + 2] = (uint8_t)u;
            } else {
                out->xyz[i * 3 + (k == L->ix ? 0 : k == L->iy ? 1 : 2)] =
                    field_value(p, &h->f[k]);
            }
        }
}

/* out's px points: one with a coordinate that is not finite becomes all
 * NaN; z, the depth, is the point's z or NaN. */
static void finish_points(relief_depth_frame *out, size_t px)
{
    for (size_t i = 0; i < px; ++i) {
        float *q = out->xyz + i * 3;
        int ok = isfinite(q[0]) && isfinite(q[1]) && isfinite(q[2]);
        if (!ok)
            q[0] = q[1] = q[2] = NAN;
        out->z[i] = ok ? q[2] : NAN;
    }
}

/* The PCD of n bytes at d into out; organised_only refuses a cloud. */
static relief_status pcd_decode(const uint8_t *d, size_t n, const char *name,
                                uint64_t max_pixels, int organised_only,
                                relief_depth_frame *out, relief_error *err)
{
    pcd_header h;
    pcd_layout L;
    size_t px;
    uint8_t *plain = NULL; /* binary_compressed, decompressed */
    relief_status st;

    memset(out, 0, sizeof *out);
    st = parse_header(d, n, name, &h, err);
    if (st != RELIEF_OK)
        return st;
    layout_fields(&h, &L);
    st = check_fields(&h, &L, organised_only, max_pixels, name, err);
    if (st != RELIEF_OK)
        return st;
    px = (size_t)h.width * (size_t)h.height;
    st = check_data(d, n, &h, &L, px, &plain, name, err);
    if (st != RELIEF_OK)
        return st;
    st = alloc_frame(out, (int)h.width, (int)h.height, 1, L.ic >= 0, name, err);
    if (st != RELIEF_OK) {
        free(plain);
        return st;
    }
    if (h.data == PCD_ASCII) {
        st = decode_ascii((const char *)d + h.body, (const char *)d + n, &h, L.ix, L.iy, L.iz,
                          L.ic, px, out, name, err);
        if (st != RELIEF_OK) {
            relief_depth_frame_free(out);
            return st;
        }
    } else {
        decode_binary(d, &h, &L, plain, px, out);
    }
    free(plain);
    finish_points(out, px);
    out->format = h.data == PCD_ASCII    ? RELIEF_DEPTH_PCD_ASCII
                : h.data == PCD_BINARY ? RELIEF_DEPTH_PCD_BINARY
                                       : RELIEF_DEPTH_PCD_COMPRESSED;
    return RELIEF_OK;
}

relief_status relief_pcd_decode(const uint8_t *d, size_t n, const char *name,
                                uint64_t max_pixels, relief_depth_frame *out,
                                relief_error *err)
{
    return pcd_decode(d, n, name, max_pixels, 1, out, err);
}

relief_status relief_pcd_decode_cloud(const uint8_t *d, size_t n, const char *name,
                                      uint64_t max_points, relief_depth_frame *out,
                                      relief_error *err)
{
    return pcd_decode(d, n, name, max_points, 0, out, err);
}

/* Read `path` whole and decode it with `decode`. */
static relief_status read_with(const char *path, uint64_t max,
                               relief_status (*decode)(const uint8_t *, size_t, const char *,
                                                       uint64_t, relief_depth_frame *,
                                                       relief_error *),
                               relief_depth_frame *out, relief_error *err)
{
    uint8_t *d;
    size_t n;
    relief_status st = relief_read_file(path, &d, &n, err);
    memset(out, 0, sizeof *out);
    if (st != RELIEF_OK)
        return st;
    st = decode(d, n, path, max, out, err);
    free(d);
    return st;
}

relief_status relief_pcd_read_cloud(const char *path, uint64_t max_points,
                                    relief_depth_frame *out, relief_error *err)
{
    return read_with(path, max_points, relief_pcd_decode_cloud, out, err);
}

relief_status relief_depth_frame_decode(const uint8_t *d, size_t n, const char *name,
                                  uint64_t max_pixels, relief_depth_frame *out,
                                  relief_error *err)
{
    memset(out, 0, sizeof *out);
    if (n >= 2 && d[0] == 'P' && (d[1] == 'f' || d[1] == 'F'))
        return relief_pfm_decode(d, n, name, max_pixels, out, err);
    if ((n >= 6 && memcmp(d, "# .PCD", 6) == 0) || (n >= 7 && memcmp(d, "VERSION", 7) == 0))
        return relief_pcd_decode(d, n, name, max_pixels, out, err);
    return relief_fail(err, RELIEF_E_FORMAT, "%s: neither a PCD nor a PFM file (by its first "
                       "bytes)", name);
}

relief_status relief_depth_frame_read(const char *path, uint64_t max_pixels,
                                relief_depth_frame *out, relief_error *err)
{
    return read_with(path, max_pixels, relief_depth_frame_decode, out, err);
}

relief_status relief_depth_frame_points(const relief_depth_frame *f, const char *name,
                                        relief_mesh **out, size_t *dropped, relief_error *err)
{
    size_t px = (size_t)f->width * (size_t)f->height, nf = 0;
    relief_mesh *m = NULL;
    relief_status st;
    *out = NULL;
    if (!f->xyz)
        return relief_fail(err, RELIEF_E_RANGE, "%s: a frame without points (x y z)", name);
    for (size_t i = 0; i < px; ++i)
        nf += isfinite(f->xyz[3 * i]) && isfinite(f->xyz[3 * i + 1]) &&
              isfinite(f->xyz[3 * i + 2]);
    if (!nf)
        return relief_fail(err, RELIEF_E_PARSE, "%s: no finite point among %zu", name, px);
    st = relief_mesh_create(nf, 0, f->rgb ? RELIEF_MESH_COLOURS : 0u, &m, err);
    if (st != RELIEF_OK)
        return st;
    nf = 0;
    for (size_t i = 0; i < px; ++i) {
        if (!(isfinite(f->xyz[3 * i]) && isfinite(f->xyz[3 * i + 1]) &&
              isfinite(f->xyz[3 * i + 2])))
            continue;
        for (int c = 0; c < 3; ++c) {
            m->pos[3 * nf + c] = f->xyz[3 * i + c];
            if (f->rgb)
                m->col[3 * nf + c] = f->rgb[3 * i + c] / 255.0f;
        }
        ++nf;
    }
    if (dropped)
        *dropped = px - nf;
    *out = m;
    return RELIEF_OK;
}

/* ---------------------------------------------------------------- writers */

static int put_u32le(FILE *fp, uint32_t u)
{
    uint8_t b[4] = {(uint8_t)u, (uint8_t)(u >> 8), (uint8_t)(u >> 16), (uint8_t)(u >> 24)};
    return fwrite(b, 1, 4, fp) == 4;
}

static int write_pfm(FILE *fp, const relief_depth_frame *f)
{
    int ok = fprintf(fp, "Pf\n%d %d\n-1.0\n", f->width, f->height) > 0;
    for (int y = f->height - 1; y >= 0 && ok; --y)
        for (int x = 0; x < f->width && ok; ++x) {
            float v = f->z[(size_t)y * f->width + x];
            uint32_t u;
            if (!isfinite(v))
                v = INFINITY;
            memcpy(&u, &v, 4);
            ok = put_u32le(fp, u);
        }
    return ok;
}

static float packed_rgb(const uint8_t *c)
{
    uint32_t u = (uint32_t)c[0] << 16 | (uint32_t)c[1] << 8 | c[2];
    float v;
    memcpy(&v, &u, 4);
    return v;
}

/* The binary_compressed data of f's px points of nf fields: the fields
 * one after another, LZF'd, after the two sizes. 0 on failure, with err
 * set where the file is not the cause. */
static int write_pcd_compressed(FILE *fp, const relief_depth_frame *f, size_t px, int nf,
                                relief_error *err)
{
    size_t usize = px * (size_t)nf * 4u, cap = usize + usize / 16 + 64, csize;
    uint8_t *plain, *packed;
    int ok;
    if (cap > 0xffffffffu) {
        relief_fail(err, RELIEF_E_RANGE, "%zu bytes of points: a binary_compressed PCD "
                    "holds at most 4 GiB", usize);
        return 0;
    }
    plain = malloc(usize);
    packed = malloc(cap);
    if (!plain || !packed) {
        free(plain);
        free(packed);
        relief_fail(err, RELIEF_E_NOMEM, "cannot compress %zu bytes of points", usize);
        return 0;
    }
    for (size_t i = 0; i < px; ++i) {
        for (int k = 0; k < 3; ++k)
            memcpy(plain + ((size_t)k * px + i) * 4u, f->xyz + 3 * i + k, 4);
        if (f->rgb) {
            float c = packed_rgb(f->rgb + 3 * i);
            memcpy(plain + (3 * px + i) * 4u, &c, 4);
        }
    }
    csize = lzf_compress(plain, (unsigned)usize, packed, (unsigned)cap);
    if (csize == 0) /* cannot happen: cap exceeds LZF's worst case */
        relief_fail(err, RELIEF_E_INTERNAL, "LZF could not compress the points");
    ok = csize > 0 && put_u32le(fp, (uint32_t)csize) && put_u32le(fp, (uint32_t)usize) &&
         fwrite(packed, 1, csize, fp) == csize;
    free(plain);
    free(packed);
    return ok;
}

static int write_pcd(FILE *fp, const relief_depth_frame *f, relief_depth_kind kind,
                     relief_error *err)
{
    size_t px = (size_t)f->width * f->height;
    int nf = f->rgb ? 4 : 3, ok;
    ok = fprintf(fp, "# .PCD v0.7 - Point Cloud Data file format (written by relief)\n"
                 "VERSION 0.7\nFIELDS x y z%s\nSIZE 4 4 4%s\nTYPE F F F%s\nCOUNT 1 1 1%s\n"
                 "WIDTH %d\nHEIGHT %d\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS %zu\nDATA %s\n",
                 f->rgb ? " rgb" : "", f->rgb ? " 4" : "", f->rgb ? " F" : "",
                 f->rgb ? " 1" : "", f->width, f->height, px,
                 kind == RELIEF_DEPTH_PCD_ASCII    ? "ascii"
                 : kind == RELIEF_DEPTH_PCD_BINARY ? "binary"
                                                   : "binary_compressed") > 0;
    if (!ok)
        return 0;
    if (kind == RELIEF_DEPTH_PCD_ASCII) {
        for (size_t i = 0; i < px && ok; ++i) {
            const float *q = f->xyz + 3 * i;
            if (isfinite(q[0]) && isfinite(q[1]) && isfinite(q[2]))
                ok = relief_fprintf_c(fp, "%.9g %.9g %.9g", q[0], q[1], q[2]) > 0;
            else
                ok = fputs("nan nan nan", fp) >= 0;
            /* PCL writes a packed rgb in ascii as its integer 0x00RRGGBB. */
            if (ok && f->rgb)
                ok = fprintf(fp, " %u", (unsigned)f->rgb[3 * i] << 16 |
                                            (unsigned)f->rgb[3 * i + 1] << 8 | f->rgb[3 * i + 2]) > 0;
            ok = ok && fputc('\n', fp) != EOF;
        }
        return ok;
    }
    if (kind == RELIEF_DEPTH_PCD_BINARY) {
        for (size_t i = 0; i < px && ok; ++i) {
            float rec[4];
            memcpy(rec, f->xyz + 3 * i, 3 * sizeof(float));
            if (f->rgb)
                rec[3] = packed_rgb(f->rgb + 3 * i);
            ok = fwrite(rec, sizeof(float), (size_t)nf, fp) == (size_t)nf;
        }
        return ok;
    }
    return write_pcd_compressed(fp, f, px, nf, err);
}

relief_status relief_depth_frame_write_to(relief_sink *s, const relief_depth_frame *f,
                                          relief_depth_kind kind, relief_error *err)
{
    relief_error why = {0};
    int ok;
    if (kind != RELIEF_DEPTH_PFM && !f->xyz)
        return relief_fail(err, RELIEF_E_RANGE, "%s: a PCD needs points (x y z), this frame "
                           "has depths only", s->path);
    errno = 0;
    ok = kind == RELIEF_DEPTH_PFM ? write_pfm(s->f, f) : write_pcd(s->f, f, kind, &why);
    if (ok)
        return RELIEF_OK;
    if (why.status != RELIEF_OK)
        return relief_fail(err, why.status, "%s: %s", s->path, why.message);
    return relief_fail_errno(err, errno ? errno : EIO, s->path, "cannot write");
}

/* What frame_sink writes. */
typedef struct frame_job {
    const relief_depth_frame *f;
    relief_depth_kind kind;
} frame_job;

static relief_status frame_sink(relief_sink *s, void *ctx, relief_error *err)
{
    const frame_job *j = ctx;
    return relief_depth_frame_write_to(s, j->f, j->kind, err);
}

relief_status relief_depth_frame_write(const char *path, const relief_depth_frame *f,
                                       relief_depth_kind kind, relief_error *err)
{
    frame_job j = {f, kind};
    return relief_output_file(path, frame_sink, &j, err);
}
