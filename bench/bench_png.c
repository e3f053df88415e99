/* relief's PNG writer (report/png.c: rows filtered and deflated in stripes
 * on every core) against libpng's at its defaults, the writer relief used
 * before, side by side in one process: each PNG of IMAGES_DIR, and the
 * coffee tiled to 8192 x 1024 (the atlas of bench/engines.py), encoded
 * REPEAT times by each in turn; the median wall time of each, their ratio
 * and the file sizes. relief's bytes are decoded by libpng
 * (relief_raster_decode) and checked against the samples they came from.
 *   bench_png IMAGES_DIR [--repeat N] */
#include <png.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_util.h"
#include "base/clock.h"
#include "image/image_io.h"
#include "report/png.h"

typedef struct growing {
    uint8_t *data;
    size_t n, cap;
} growing;

static void on_write(png_structp png, png_bytep data, size_t len)
{
    growing *g = png_get_io_ptr(png);
    if (g->n + len > g->cap) {
        g->cap = (g->n + len) * 2;
        g->data = realloc(g->data, g->cap);
        if (!g->data) {
            fprintf(stderr, "bench_png: out of memory\n");
            exit(2);
        }
    }
    memcpy(g->data + g->n, data, len);
    g->n += len;
}

static void on_flush(png_structp png) { (void)png; }

/* libpng's encoding of 8-bit samples at its defaults; the file's size. */
static size_t libpng_encode(const uint8_t *px, int w, int h, int c)
{
    static const int types[5] = {0, PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA,
                                 PNG_COLOR_TYPE_RGB, PNG_COLOR_TYPE_RGB_ALPHA};
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    growing g = {NULL, 0, 0};
    if (!info) {
        fprintf(stderr, "bench_png: cannot start libpng\n");
        exit(2);
    }
    if (setjmp(png_jmpbuf(png))) {
        fprintf(stderr, "bench_png: libpng failed\n");
        exit(2);
    }
    png_set_write_fn(png, &g, on_write, on_flush);
    png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, 8, types[c], PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = 0; y < h; ++y)
        png_write_row(png, px + (size_t)y * w * c);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    free(g.data);
    return g.n;
}

/* relief's encoding; the file's size, after checking it decodes to px. */
static size_t relief_encode(const uint8_t *px, int w, int h, int c, int check)
{
    relief_error err = {0};
    uint8_t *out = NULL;
    size_t n = 0, vals = (size_t)w * h * c;
    relief_raster r;
    if (relief_png_encode_pixels(px, w, h, c, 8, &out, &n, &err) != RELIEF_OK) {
        fprintf(stderr, "bench_png: %s\n", err.message);
        exit(2);
    }
    if (check) {
        if (relief_raster_decode(out, n, "relief's PNG", NULL, &r, &err) != RELIEF_OK) {
            fprintf(stderr, "bench_png: libpng cannot read relief's PNG: %s\n", err.message);
            exit(2);
        }
        for (size_t i = 0; i < vals; ++i)
            if (r.v[i] != (float)px[i]) {
                fprintf(stderr, "bench_png: relief's PNG decodes to other samples\n");
                exit(2);
            }
        relief_raster_free(&r);
    }
    free(out);
    return n;
}

static void row(const char *name, const uint8_t *px, int w, int h, int c, int repeat)
{
    double tl[64], tr[64];
    size_t nl = 0, nr = 0;
    for (int i = 0; i < repeat; ++i) {
        double t0 = relief_seconds();
        nl = libpng_encode(px, w, h, c);
        tl[i] = relief_seconds() - t0;
        t0 = relief_seconds();
        nr = relief_encode(px, w, h, c, 0);
        tr[i] = relief_seconds() - t0;
    }
    double ml, mr, lo, hi;
    relief_encode(px, w, h, c, 1);
    bench_stats3(tl, repeat, &ml, &lo, &hi);
    bench_stats3(tr, repeat, &mr, &lo, &hi);
    printf("%-22s %5d x %-5d %9.4f %9.4f %6.2f %10zu %10zu %+6.2f %%\n", name, w, h, ml, mr,
           ml / mr, nl, nr, 100.0 * ((double)nr - (double)nl) / (double)nl);
}

/* The file's samples at 8 bits; NULL when it is not an 8-bit image. */
static uint8_t *samples(const char *path, int *w, int *h, int *c)
{
    relief_error err = {0};
    relief_raster r;
    uint8_t *px;
    size_t vals;
    if (relief_raster_read(path, NULL, &r, &err) != RELIEF_OK || r.bit_depth != 8) {
        fprintf(stderr, "bench_png: %s: %s\n", path, err.message[0] ? err.message : "16 bits");
        return NULL;
    }
    vals = (size_t)r.width * r.height * r.channels;
    px = malloc(vals);
    for (size_t i = 0; i < vals && px; ++i)
        px[i] = (uint8_t)r.v[i];
    *w = r.width, *h = r.height, *c = r.channels;
    relief_raster_free(&r);
    return px;
}

int main(int argc, char **argv)
{
    static const char *names[] = {"astronaut.png", "brick.png", "chelsea.png", "coffee.png",
                                  "grass.png", "gravel.png"};
    const char *images = argc > 1 ? argv[1] : "../shared/data/images";
    int repeat = 5, w, h, c;
    char path[1024];
    bench_machine m;
    uint8_t *px;

    for (int i = 2; i < argc; ++i)
        if (strcmp(argv[i], "--repeat") == 0 && i + 1 < argc)
            repeat = atoi(argv[++i]);
    repeat = repeat < 1 ? 1 : repeat > 64 ? 64 : repeat;
    bench_read_machine(&m);
    printf("# %s, %ld cores; libpng %s; medians of %d\n", m.cpu, m.cores, PNG_LIBPNG_VER_STRING,
           repeat);
    printf("%-22s %13s %9s %9s %6s %10s %10s %8s\n", "image", "size", "libpng_s", "relief_s",
           "ratio", "libpng_B", "relief_B", "size");
    for (size_t k = 0; k < sizeof names / sizeof *names; ++k) {
        snprintf(path, sizeof path, "%s/%s", images, names[k]);
        if ((px = samples(path, &w, &h, &c)) != NULL)
            row(names[k], px, w, h, c, repeat);
        if (k == 3 && px) { /* coffee: the atlas, its tiles repeated to 8192 x 1024 */
            int W = 8192, H = 1024;
            uint8_t *atlas = malloc((size_t)W * H * c);
            for (int y = 0; y < H && atlas; ++y)
                for (int x = 0; x < W; ++x)
                    memcpy(atlas + ((size_t)y * W + x) * c, px + ((size_t)(y % h) * w + x % w) * c,
                           (size_t)c);
            if (atlas)
                row("coffee tiled (atlas)", atlas, W, H, c, repeat);
            free(atlas);
        }
        free(px);
    }
    return 0;
}
