/* image/image_io.c: PNG and JPEG round trips, the real images of
 * ../shared/data/images, and every way a file can be bad.
 *   test_image_io IMAGES_DIR */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "check.h"
#include "image/image_io.h"

static void fill_pattern(relief_raster *r)
{
    float max = relief_raster_max_value(r);
    size_t n = (size_t)r->width * r->height * r->channels;
    for (size_t i = 0; i < n; ++i)
        r->v[i] = (float)((i * 2654435761u) % (unsigned)(max + 1));
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

static void round_trip(const char *dir, int channels, int depth)
{
    char path[256];
    relief_raster a, b;
    relief_error err = {RELIEF_OK, ""};
    relief_status st;
    snprintf(path, sizeof path, "%s/rt_%d_%d.png", dir, channels, depth);
    st = relief_raster_create(37, 23, channels, depth, &a, &err);
    CHECK(st == RELIEF_OK, "%s", err.message);
    fill_pattern(&a);
    st = relief_raster_write(path, &a, &err);
    CHECK(st == RELIEF_OK, "write %s: %s", path, err.message);
    st = relief_raster_read(path, NULL, &b, &err);
    CHECK(st == RELIEF_OK, "read %s: %s", path, err.message);
    if (st == RELIEF_OK) {
        CHECK(b.width == 37 && b.height == 23 && b.channels == channels && b.bit_depth == depth,
              "%s: %d x %d x %d, %d bits", path, b.width, b.height, b.channels, b.bit_depth);
        CHECK(memcmp(a.v, b.v, sizeof(float) * 37 * 23 * channels) == 0,
              "%s: values changed", path);
    }
    relief_raster_free(&a);
    relief_raster_free(&b);
}

/* Decoding `n` bytes must fail with `want` (0: any bad-input status). */
static void bad(const uint8_t *d, size_t n, relief_status want, const char *what)
{
    relief_raster r;
    relief_error err = {RELIEF_OK, ""};
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

int main(int argc, char **argv)
{
    const char *images = argc > 1 ? argv[1] : "../shared/data/images";
    const char *dir = check_tmpdir();
    relief_error err = {RELIEF_OK, ""};
    relief_raster r;
    relief_status st;
    char path[512];
    uint8_t *png, *jpg;
    size_t npng = 0, njpg = 0;

    for (int c = 1; c <= 4; ++c) {
        round_trip(dir, c, 8);
        round_trip(dir, c, 16);
    }

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
        snprintf(path, sizeof path, "%s/rt_3_8.png", dir);
        st = relief_raster_read(path, &lim, &r, &err);
        CHECK(st == RELIEF_E_NOMEM && strstr(err.message, "37 x 23"), "limit: %s: %s",
              relief_status_name(st), err.message);
    }

    /* Bad files: empty, not an image, every truncation, corrupt bytes. */
    snprintf(path, sizeof path, "%s/rt_3_8.png", dir);
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
    st = relief_raster_read("/nonexistent/x.png", NULL, &r, &err);
    CHECK(st == RELIEF_E_IO && strstr(err.message, "/nonexistent/x.png"), "missing: %s",
          err.message);
    return check_result();
}
