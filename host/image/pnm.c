/* Binary Netpbm images (pnm.h). The header is parsed strictly: a file
 * that does not say its size and maxval exactly is refused, never guessed
 * at, since a misread header shifts every sample. */
#include "image/pnm.h"

#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "image/raster.h"

int relief_pnm_sniff(const uint8_t *d, size_t n)
{
    return n >= 2 && d[0] == 'P' && d[1] >= '1' && d[1] <= '7';
}

static int is_space(uint8_t c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

/* The next decimal field at *at, after whitespace and '#' comments; -1
 * when there is none, or it has more than 9 digits (no PNM field needs
 * them: a side is at most 65535). */
static long header_number(const uint8_t *d, size_t n, size_t *at)
{
    long v = 0;
    int digits = 0;
    while (*at < n && (is_space(d[*at]) || d[*at] == '#')) {
        if (d[*at] == '#')
            while (*at < n && d[*at] != '\n')
                ++*at;
        else
            ++*at;
    }
    while (*at < n && d[*at] >= '0' && d[*at] <= '9' && digits < 10)
        v = 10 * v + (d[(*at)++] - '0'), ++digits;
    if (digits == 0 || digits > 9 || (*at < n && !is_space(d[*at]) && d[*at] != '#'))
        return -1;
    return v;
}

relief_status relief_pnm_header(const uint8_t *d, size_t n, const char *name, relief_pnm *h,
                                relief_error *err)
{
    static const char *const field[3] = {"width", "height", "maxval"};
    long v[3];
    size_t at = 2;
    if (!relief_pnm_sniff(d, n))
        return relief_fail(err, RELIEF_E_FORMAT, "%s: not a PNM image (no P5 or P6 magic)",
                           name);
    if (d[1] != '5' && d[1] != '6')
        return relief_fail(err, RELIEF_E_FORMAT, "%s: a P%c Netpbm file: only binary grey (P5) "
                           "and colour (P6) are read; convert it (pnmtopnm or convert)", name,
                           d[1]);
    if (n > 2 && !is_space(d[2]) && d[2] != '#')
        return relief_fail(err, RELIEF_E_PARSE, "%s: malformed PNM header: no whitespace after "
                           "the magic P%c", name, d[1]);
    for (int k = 0; k < 3; ++k)
        if ((v[k] = header_number(d, n, &at)) < 0)
            return relief_fail(err, RELIEF_E_PARSE, "%s: malformed PNM header: expected the %s, "
                               "a decimal number, at byte %zu", name, field[k], at);
    for (int k = 0; k < 2; ++k) {
        if (v[k] == 0)
            return relief_fail(err, RELIEF_E_FORMAT, "%s: the image has %ld x %ld pixels: "
                               "nothing to read", name, v[0], v[1]);
        if (v[k] > RELIEF_RASTER_MAX_SIDE)
            return relief_fail(err, RELIEF_E_RANGE, "%s: PNM %s %ld: each side must be at most "
                               "%d pixels", name, field[k], v[k], RELIEF_RASTER_MAX_SIDE);
    }
    if (v[2] < 1 || v[2] > 65535)
        return relief_fail(err, RELIEF_E_PARSE, "%s: PNM maxval %ld out of range: expected "
                           "1..65535", name, v[2]);
    if (at >= n)
        return relief_fail(err, RELIEF_E_PARSE, "%s: truncated PNM: the file ends in its "
                           "header", name);
    /* Exactly one whitespace byte: the samples may start with another. */
    *h = (relief_pnm){(int)v[0], (int)v[1], d[1] == '6' ? 3 : 1, (unsigned)v[2], at + 1};
    return RELIEF_OK;
}

static unsigned sample_at(const uint8_t *p, int wide)
{
    return wide ? (unsigned)p[0] << 8 | p[1] : p[0];
}

relief_status relief_pnm_samples(const uint8_t *d, size_t n, const char *name,
                                 const relief_pnm *h, int full_range, relief_image *out,
                                 relief_error *err)
{
    int wide = h->maxval > 255;
    unsigned top = wide ? 65535u : 255u;
    size_t count = (size_t)h->width * h->height * h->channels, bytes = count * (wide ? 2 : 1);
    void *px;
    if (h->offset > n || n - h->offset < bytes)
        return relief_fail(err, RELIEF_E_PARSE, "%s: truncated PNM: %d x %d x %d samples need "
                           "%zu bytes, the file has %zu after its header", name, h->width,
                           h->height, h->channels, bytes, h->offset > n ? 0 : n - h->offset);
    if (!(px = malloc(count * (wide ? 2 : 1))))
        return relief_fail(err, RELIEF_E_NOMEM, "%s: cannot allocate %d x %d pixels", name,
                           h->width, h->height);
    for (size_t i = 0; i < count; ++i) {
        unsigned s = sample_at(d + h->offset + i * (wide ? 2 : 1), wide);
        if (s > h->maxval) {
            size_t pix = i / (size_t)h->channels;
            free(px);
            return relief_fail(err, RELIEF_E_PARSE, "%s: PNM sample %u at pixel (%zu, %zu) is "
                               "over the maxval %u", name, s, pix % (size_t)h->width,
                               pix / (size_t)h->width, h->maxval);
        }
        if (full_range && h->maxval != top)
            s = (unsigned)(((unsigned long)s * top + h->maxval / 2) / h->maxval);
        if (wide)
            ((uint16_t *)px)[i] = (uint16_t)s;
        else
            ((uint8_t *)px)[i] = (uint8_t)s;
    }
    *out = (relief_image){h->width, h->height, h->channels, wide ? 16 : 8,
                          (size_t)h->width * h->channels * (wide ? 2 : 1), px};
    return RELIEF_OK;
}
