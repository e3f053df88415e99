/* image/image_io.c: PNG and JPEG round trips, binary PNM (P5, P6), the real images of
 * ../shared/data/images, and every way a file can be bad.
 *   test_image_io IMAGES_DIR */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "check.h"
#include "image/image_io.h"

/* check_pattern's samples, in the raster's range. */
static void fill_pattern(relief_raster *r)
{
    float max = relief_raster_max_value(r);
    size_t row = (size_t)r->width * r->channels, n = row * r->height;
    for (size_t i = 0; i < n; ++i)
        r->v[i] = (float)(check_pattern(i, row) % (unsigned)(max + 1));
}

static uint8_t *slurp(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    uint8_t *d;
    long len;
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    len = ftell(f);
    fseek(f, 0, SEEK_SET);
    d = malloc((size_t)len + 1);
    *n = fread(d, 1, (size_t)len, f);
    fclose(f);
    return d;
}

static void round_trip(const char *dir, int w, int h, int channels, int depth)
{
    char path[256];
    relief_raster a, b;
    relief_error err = {0};
    relief_status st;
    snprintf(path, sizeof path, "%s/rt_%d_%d_%d.png", dir, w, channels, depth);
    st = relief_raster_create(w, h, channels, depth, &a, &err);
    CHECK(st == RELIEF_OK, "%s", err.message);
    fill_pattern(&a);
    st = relief_raster_write(path, &a, &err);
    CHECK(st == RELIEF_OK, "write %s: %s", path, err.message);
    st = relief_raster_read(path, NULL, &b, &err);
    CHECK(st == RELIEF_OK, "read %s: %s", path, err.message);
    if (st == RELIEF_OK) {
        CHECK(b.width == w && b.height == h && b.channels == channels && b.bit_depth == depth,
              "%s: %d x %d x %d, %d bits", path, b.width, b.height, b.channels, b.bit_depth);
        CHECK(memcmp(a.v, b.v, sizeof(float) * w * h * channels) == 0,
              "%s: values changed", path);
    }
    relief_raster_free(&a);
    relief_raster_free(&b);
}

/* Decoding `n` bytes must fail with `want` (0: any bad-input status). */
static void bad(const uint8_t *d, size_t n, relief_status want, const char *what)
{
    relief_raster r;
    relief_error err = {0};
    relief_status st = relief_raster_decode(d, n, "x", NULL, &r, &err);
    CHECK(st != RELIEF_OK, "%s: decoded", what);
    CHECK(r.v == NULL, "%s: a raster left behind", what);
    CHECK(want ? st == want : relief_status_exit_code(st) == 1,
          "%s: status %s: %s", what, relief_status_name(st), err.message);
    CHECK(strstr(err.message, "x:") == err.message, "%s: message '%s' does not name the input",
          what, err.message);
    if (st == RELIEF_OK)
        relief_raster_free(&r);
}

/* ---- hand-made PNGs: the header fields and palettes libpng's writer
 * would not write. */

static uint32_t crc_of(const uint8_t *b, size_t n, uint32_t c)
{
    c = ~c;
    for (size_t i = 0; i < n; ++i) {
        c ^= b[i];
        for (int k = 0; k < 8; ++k)
            c = c & 1 ? 0xedb88320u ^ (c >> 1) : c >> 1;
    }
    return ~c;
}

static uint8_t *put32(uint8_t *o, uint32_t v)
{
    o[0] = (uint8_t)(v >> 24);
    o[1] = (uint8_t)(v >> 16);
    o[2] = (uint8_t)(v >> 8);
    o[3] = (uint8_t)v;
    return o + 4;
}

/* A chunk at o: length, type, data, CRC; returns its end. */
static uint8_t *chunk(uint8_t *o, const char *type, const uint8_t *data, uint32_t len)
{
    uint8_t *t = put32(o, len);
    memcpy(t, type, 4);
    if (len)
        memcpy(t + 4, data, len);
    return put32(t + 4 + len, crc_of(t, 4 + len, 0));
}

/* A 4 x 4 PNG (IHDR's fields as given: width, height, bit depth, colour
 * type, compression, interlace) with `palette` PLTE entries (0: none)
 * and every pixel byte `fill`, stored uncompressed; its size. */
static size_t craft_png(uint8_t *o, uint32_t w, uint32_t h, int depth, int ctype, int comp,
                        int interlace, int palette, uint8_t fill)
{
    static const int chans[7] = {1, 1, 3, 1, 2, 1, 4};
    uint8_t ihdr[13], plte[768], z[512], *e = o;
    size_t rb = ((size_t)4 * (depth > 16 ? 16 : depth) * chans[ctype % 7] + 7) / 8,
           raw = 4 * (1 + rb), at = 0;
    uint32_t a = 1, b = 0;
    memcpy(e, "\x89PNG\r\n\x1a\n", 8);
    put32(put32(ihdr, w), h);
    ihdr[8] = (uint8_t)depth;
    ihdr[9] = (uint8_t)ctype;
    ihdr[10] = (uint8_t)comp;
    ihdr[11] = 0;
    ihdr[12] = (uint8_t)interlace;
    e = chunk(e + 8, "IHDR", ihdr, 13);
    for (int i = 0; i < palette * 3; ++i)
        plte[i] = (uint8_t)(40 * i);
    if (palette)
        e = chunk(e, "PLTE", plte, (uint32_t)palette * 3);
    z[at++] = 0x78;
    z[at++] = 0x01;
    z[at++] = 0x01; /* the last block, stored */
    z[at++] = (uint8_t)raw;
    z[at++] = (uint8_t)(raw >> 8);
    z[at++] = (uint8_t)~raw;
    z[at++] = (uint8_t)(~raw >> 8);
    for (size_t i = 0; i < raw; ++i) {
        uint8_t v = i % (1 + rb) == 0 ? 0 : fill; /* each row: filter 0, then its bytes */
        z[at++] = v;
        a = (a + v) % 65521;
        b = (b + a) % 65521;
    }
    put32(z + at, b << 16 | a);
    e = chunk(e, "IDAT", z, (uint32_t)(at + 4));
    e = chunk(e, "IEND", NULL, 0);
    return (size_t)(e - o);
}

/* Issue 40: a pixel past the palette is an error naming its index and
 * the palette's size (before: read as black), and a bad header names the
 * field and its value (before: "Invalid IHDR data"). */
static void test_png_fields(void)
{
    static const struct {
        uint32_t w, h;
        int depth, ctype, comp, interlace, palette, fill;
        relief_status want;
        const char *says;
    } cases[] = {
        {4, 4, 8, 3, 0, 0, 2, 5, RELIEF_E_PARSE, "palette index 5, past the palette of 2 entries"},
        {4, 4, 2, 3, 0, 0, 3, 0xff, RELIEF_E_PARSE, "palette index 3, past the palette of 3"},
        {0, 4, 8, 0, 0, 0, 0, 1, RELIEF_E_PARSE, "IHDR width 0"},
        {4, 70000, 8, 0, 0, 0, 0, 1, RELIEF_E_RANGE, "IHDR height 70000"},
        {4, 4, 3, 2, 0, 0, 0, 1, RELIEF_E_PARSE, "IHDR bit depth 3 for colour type 2 (RGB)"},
        {4, 4, 16, 3, 0, 0, 2, 1, RELIEF_E_PARSE, "IHDR bit depth 16 for colour type 3"},
        {4, 4, 8, 5, 0, 0, 0, 1, RELIEF_E_PARSE, "IHDR colour type 5"},
        {4, 4, 8, 0, 1, 0, 0, 1, RELIEF_E_PARSE, "IHDR compression method 1"},
        {4, 4, 8, 0, 0, 2, 0, 1, RELIEF_E_PARSE, "IHDR interlace method 2"},
    };
    uint8_t buf[2048];
    relief_raster r;
    relief_error err = {0};
    size_t n = craft_png(buf, 4, 4, 8, 3, 0, 0, 2, 1);
    /* The same file with every index in its palette reads. */
    CHECK(relief_raster_decode(buf, n, "x", NULL, &r, &err) == RELIEF_OK && r.channels == 3 &&
              r.v[0] == 120.0f && r.v[2] == 200.0f,
          "a palette PNG: %s", err.message);
    if (r.v)
        relief_raster_free(&r);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        n = craft_png(buf, cases[i].w, cases[i].h, cases[i].depth, cases[i].ctype, cases[i].comp,
                      cases[i].interlace, cases[i].palette, (uint8_t)cases[i].fill);
        bad(buf, n, cases[i].want, cases[i].says);
        relief_raster_decode(buf, n, "x", NULL, &r, &err);
        CHECK(strstr(err.message, cases[i].says) != NULL, "'%s' lacks '%s'", err.message,
              cases[i].says);
    }
}

/* A decode of `text` (n bytes, the header and samples) must succeed. */
static void good_pnm(const char *text, size_t n, int w, int h, int c, int depth,
                     const float *want, const char *what)
{
    relief_raster r;
    relief_error err = {0};
    relief_status st = relief_raster_decode((const uint8_t *)text, n, "x", NULL, &r, &err);
    CHECK(st == RELIEF_OK, "%s: %s", what, err.message);
    if (st != RELIEF_OK)
        return;
    CHECK(r.width == w && r.height == h && r.channels == c && r.bit_depth == depth,
          "%s: %d x %d x %d, %d bits", what, r.width, r.height, r.channels, r.bit_depth);
    for (int i = 0; i < w * h * c && r.width == w && r.channels == c; ++i)
        CHECK(r.v[i] == want[i], "%s: sample %d is %g, expected %g", what, i, r.v[i], want[i]);
    relief_raster_free(&r);
}

/* ---- binary PNM: 8 and 16 bits, a maxval scaled to the full range,
 * comments in the header; every truncation and bad field refused. */
static void test_pnm(void)
{
    static const float grey[] = {0, 128, 255, 7}, rgb16[] = {1, 258, 65535, 0, 0, 256};
    static const float half[] = {0, 255, 128, 51};
    static const char p6[] = "P6\n2 1\n65535\n\0\1\1\2\xff\xff\0\0\0\0\1\0";
    static const char p5[] = "P5 # grey\n2 2 255\n\0\x80\xff\7";
    char c[64];
    good_pnm(p5, sizeof p5 - 1, 2, 2, 1, 8, grey, "a P5 with a comment");
    good_pnm(p6, sizeof p6 - 1, 2, 1, 3, 16, rgb16, "a 16-bit P6, big-endian");
    good_pnm("P5\n2 2\n10\n\0\12\5\2", 14, 2, 2, 1, 8, half, "a P5 of maxval 10");
    for (size_t n = 0; n + 1 < sizeof p6 - 1; ++n)
        bad((const uint8_t *)p6, n, n ? 0 : RELIEF_E_FORMAT, "a truncated P6");
    bad((const uint8_t *)"P3\n1 1\n255\n1 2 3\n", 17, RELIEF_E_FORMAT, "an ascii P3");
    bad((const uint8_t *)"P5\n2 x\n255\n\0\0", 14, RELIEF_E_PARSE, "a P5 height 'x'");
    bad((const uint8_t *)"P5\n0 2\n255\n", 12, RELIEF_E_FORMAT, "a P5 of width 0");
    bad((const uint8_t *)"P5\n70000 1\n255\n", 16, RELIEF_E_RANGE, "a P5 too wide");
    bad((const uint8_t *)"P5\n1 1\n0\n\0", 11, RELIEF_E_PARSE, "a P5 of maxval 0");
    bad((const uint8_t *)"P5\n1 1\n65536\n\0\0", 16, RELIEF_E_PARSE, "a P5 of maxval 65536");
    bad((const uint8_t *)"P5\n1 1\n9\n\12", 11, RELIEF_E_PARSE, "a P5 sample over maxval");
    snprintf(c, sizeof c, "P5\n1 1\n255");
    bad((const uint8_t *)c, strlen(c), RELIEF_E_PARSE, "a P5 ending in its header");
}

int main(int argc, char **argv)
{
    const char *images = argc > 1 ? argv[1] : "../shared/data/images";
    const char *dir = check_tmpdir();
    relief_error err = {0};
    relief_raster r;
    relief_status st;
    char path[512];
    uint8_t *png, *jpg;
    size_t npng = 0, njpg = 0;

    for (int c = 1; c <= 4; ++c) {
        round_trip(dir, 37, 23, c, 8);
        round_trip(dir, 37, 23, c, 16);
    }
    /* Images of the PNG writer's many stripes, each deflated apart into an
     * IDAT of its own, and rows wider than the 32 KiB a stripe is primed
     * with, read back by libpng (test_png checks the stream itself). */
    round_trip(dir, 1500, 700, 4, 16);
    round_trip(dir, 12000, 40, 3, 8);

    /* JPEG: 8 bits, lossy, alpha dropped. */
    st = relief_raster_create(40, 30, 4, 8, &r, &err);
    for (int i = 0; i < 40 * 30; ++i)
        for (int c = 0; c < 4; ++c)
            r.v[i * 4 + c] = (float)(c == 3 ? 255 : 60 + c * 50 + (i % 40));
    snprintf(path, sizeof path, "%s/rt.jpg", dir);
    st = relief_raster_write(path, &r, &err);
    CHECK(st == RELIEF_OK, "write jpeg: %s", err.message);
    relief_raster_free(&r);
    st = relief_raster_read(path, NULL, &r, &err);
    CHECK(st == RELIEF_OK && r.channels == 3 && r.bit_depth == 8 && r.width == 40,
          "read jpeg: %s", err.message);
    if (st == RELIEF_OK) {
        double worst = 0;
        for (int i = 0; i < 40 * 30; ++i)
            for (int c = 0; c < 3; ++c)
                worst = fmax(worst, fabs(r.v[i * 3 + c] - (60 + c * 50 + (i % 40))));
        CHECK(worst < 12, "jpeg round trip off by %g", worst);
        relief_raster_free(&r);
    }

    /* Writing: 16 bits to JPEG, an unknown extension, a folder that is not. */
    relief_raster_create(4, 4, 1, 16, &r, &err);
    snprintf(path, sizeof path, "%s/deep.jpg", dir);
    CHECK(relief_raster_write(path, &r, &err) == RELIEF_E_FORMAT, "16-bit JPEG written");
    snprintf(path, sizeof path, "%s/x.bmp", dir);
    CHECK(relief_raster_write(path, &r, &err) == RELIEF_E_FORMAT, ".bmp written");
    CHECK(relief_raster_write("/nonexistent-dir/x.png", &r, &err) == RELIEF_E_IO,
          "wrote into a missing folder");
    relief_raster_free(&r);

    /* The real images: sizes and kinds as ../shared/data/images/SOURCE.txt. */
    {
        static const struct { const char *name; int w, h, c; } real[] = {
            {"brick.png", 512, 512, 1},   {"grass.png", 512, 512, 1},
            {"gravel.png", 512, 512, 1},  {"coffee.png", 600, 400, 3},
            {"chelsea.png", 451, 300, 3}, {"astronaut.png", 512, 512, 3},
            {"rocket.jpg", 640, 427, 3}};
        struct stat sb;
        if (stat(images, &sb) != 0) {
            printf("%s: not found; the real images are skipped\n", images);
        } else {
            for (size_t i = 0; i < sizeof real / sizeof real[0]; ++i) {
                snprintf(path, sizeof path, "%s/%s", images, real[i].name);
                st = relief_raster_read(path, NULL, &r, &err);
                CHECK(st == RELIEF_OK && r.width == real[i].w && r.height == real[i].h &&
                          r.channels == real[i].c && r.bit_depth == 8,
                      "%s: %s", path, err.message);
                relief_raster_free(&r);
            }
        }
    }

    /* A memory limit refuses before decoding. */
    {
        relief_image_limit lim = {1000, 1.0, "testing"};
        snprintf(path, sizeof path, "%s/rt_37_3_8.png", dir);
        st = relief_raster_read(path, &lim, &r, &err);
        CHECK(st == RELIEF_E_NOMEM && strstr(err.message, "37 x 23"), "limit: %s: %s",
              relief_status_name(st), err.message);
    }

    /* Bad files: empty, not an image, every truncation, corrupt bytes. */
    snprintf(path, sizeof path, "%s/rt_37_3_8.png", dir);
    png = slurp(path, &npng);
    snprintf(path, sizeof path, "%s/rt.jpg", dir);
    jpg = slurp(path, &njpg);
    CHECK(png && jpg, "cannot read back the round-trip files");
    bad((const uint8_t *)"", 0, RELIEF_E_FORMAT, "empty");
    bad((const uint8_t *)"GIF89a......", 12, RELIEF_E_FORMAT, "a GIF");
    for (size_t n = 8; png && n < npng; n += n < 64 ? 1 : 7)
        bad(png, n, 0, "a truncated PNG");
    for (size_t n = 3; jpg && n < njpg; n += n < 64 ? 1 : 11)
        bad(jpg, n, 0, "a truncated JPEG");
    if (png) {
        uint8_t *c = malloc(npng);
        memcpy(c, png, npng);
        c[20] ^= 0x40; /* IHDR's height: its CRC no longer matches */
        bad(c, npng, RELIEF_E_PARSE, "a PNG with a bad CRC");
        memcpy(c, png, npng);
        memset(c + 16, 0, 4); /* width 0 */
        bad(c, npng, 0, "a PNG of width 0");
        memcpy(c, png, npng);
        c[npng / 2] ^= 0xff; /* inside IDAT */
        bad(c, npng, 0, "a PNG with corrupt image data");
        free(c);
    }
    if (jpg) {
        uint8_t *c = malloc(njpg);
        memcpy(c, jpg, njpg);
        for (size_t i = njpg / 2; i < njpg / 2 + 40; ++i)
            c[i] = 0xff;
        bad(c, njpg, 0, "a JPEG with corrupt scan data");
        free(c);
    }
    free(png);
    free(jpg);
    test_png_fields();
    test_pnm();
    st = relief_raster_read("/nonexistent/x.png", NULL, &r, &err);
    CHECK(st == RELIEF_E_IO && strstr(err.message, "/nonexistent/x.png"), "missing: %s",
          err.message);
    return check_result();
}
