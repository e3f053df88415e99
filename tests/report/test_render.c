/* The rasteriser and the PNG writer on tiny meshes with known pictures:
 * framing to the pixel, depth order, label and displacement colours, the
 * errors; and every PNG decoded back (zlib inflate and the five PNG
 * filters, CRC of every chunk) and compared byte for byte.
 *
 * `test_render png FILE W H [MIN_COLOURS]` instead checks a PNG written by
 * the CLI: it decodes, has size W x H, and is not blank (foreground
 * fraction in [0.03, 0.97], at least MIN_COLOURS distinct colours, default
 * 16; the figures are printed). Exit 0 when it passes. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "check.h"
#include "png_decode.h"
#include "mesh/mesh.h"
#include "report/png.h"
#include "report/render.h"

/* --------------------------------------------------------- PNG decoder */

/* Decode an 8-bit RGB PNG (what the renderer writes): *rgb (malloc'ed),
 * *w, *h. Returns NULL on success, else what is wrong. */
static const char *png_decode(const uint8_t *png, size_t n, uint8_t **rgb, int *w, int *h)
{
    png_decoded d;
    const char *why = png_decode_all(png, n, &d);
    if (!why && (d.channels != 3 || d.depth != 8))
        why = "not 8-bit RGB";
    if (why) {
        free(d.samples);
        return why;
    }
    *rgb = d.samples;
    *w = d.width;
    *h = d.height;
    return NULL;
}

/* ------------------------------------------------------ pixel statistics */

typedef struct stats {
    double foreground;  /* fraction of pixels that differ from the background */
    size_t colours;     /* distinct colours (capped at 4096 counted) */
    size_t orange, grey; /* foreground pixels of the label hues */
} stats;

static stats pixel_stats(const uint8_t *rgb, int w, int h)
{
    stats s = {0.0, 0, 0, 0};
    uint32_t seen[4096];
    size_t fg = 0, n = (size_t)w * (size_t)h;
    for (size_t i = 0; i < n; ++i) {
        const uint8_t *p = rgb + 3 * i;
        uint32_t c = (uint32_t)p[0] << 16 | (uint32_t)p[1] << 8 | p[2];
        size_t k;
        if (p[0] == RELIEF_RENDER_BACKGROUND_R && p[1] == RELIEF_RENDER_BACKGROUND_G &&
            p[2] == RELIEF_RENDER_BACKGROUND_B)
            continue;
        ++fg;
        if (p[0] > p[1] + 40 && p[1] > p[2] + 20)
            s.orange++;
        else if (abs(p[0] - p[1]) < 6 && abs(p[1] - p[2]) < 6)
            s.grey++;
        for (k = 0; k < s.colours && seen[k] != c; ++k) {
        }
        if (k == s.colours && s.colours < 4096)
            seen[s.colours++] = c;
    }
    s.foreground = (double)fg / (double)n;
    return s;
}

static int is_background(const uint8_t *p)
{
    return p[0] == RELIEF_RENDER_BACKGROUND_R && p[1] == RELIEF_RENDER_BACKGROUND_G &&
           p[2] == RELIEF_RENDER_BACKGROUND_B;
}

/* Encode, decode, compare. */
static void check_png_roundtrip(const relief_rgb_image *img, const char *what)
{
    uint8_t *png = NULL, *back = NULL;
    size_t n = 0;
    int w = 0, h = 0;
    relief_error err;
    const char *why;
    CHECK(relief_png_encode(img->rgb, img->width, img->height, &png, &n, &err) == RELIEF_OK,
          "%s: %s", what, err.message);
    if (!png)
        return;
    why = png_decode(png, n, &back, &w, &h);
    CHECK(why == NULL, "%s: %s", what, why);
    if (!why) {
        CHECK(w == img->width && h == img->height, "%s: decoded %dx%d", what, w, h);
        CHECK(memcmp(back, img->rgb, (size_t)w * (size_t)h * 3) == 0,
              "%s: decoded pixels differ", what);
    }
    free(back);
    free(png);
}

/* ------------------------------------------------------------- meshes */

/* An nx x ny grid over [x0, x1] x [y0, y1] at height z(x, y), two
 * triangles per cell, counter-clockwise seen from +z; label 1 inside the
 * disc of radius `r` about the centre when labels are asked. */
static relief_mesh *grid(int nx, int ny, double x0, double x1, double y0, double y1,
                         double (*z)(double, double), double z0, unsigned attrs, double r)
{
    relief_mesh *m = NULL;
    relief_error err;
    size_t nv = (size_t)nx * (size_t)ny, nt = 2 * (size_t)(nx - 1) * (size_t)(ny - 1), t = 0;
    if (relief_mesh_create(nv, nt, attrs, &m, &err) != RELIEF_OK) {
        fprintf(stderr, "relief_mesh_create: %s\n", err.message);
        exit(2);
    }
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            size_t v = (size_t)j * (size_t)nx + (size_t)i;
            double x = x0 + (x1 - x0) * i / (nx - 1), y = y0 + (y1 - y0) * j / (ny - 1);
            double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
            m->pos[3 * v] = x;
            m->pos[3 * v + 1] = y;
            m->pos[3 * v + 2] = z0 + (z ? z(x, y) : 0.0);
            if (m->label)
                m->label[v] = (x - cx) * (x - cx) + (y - cy) * (y - cy) < r * r;
            if (m->col) {
                m->col[3 * v] = (float)i / (float)(nx - 1);
                m->col[3 * v + 1] = (float)j / (float)(ny - 1);
                m->col[3 * v + 2] = 0.5f;
            }
        }
    for (int j = 0; j + 1 < ny; ++j)
        for (int i = 0; i + 1 < nx; ++i) {
            uint32_t a = (uint32_t)(j * nx + i), b = a + 1, c = a + (uint32_t)nx, d = c + 1;
            uint32_t f[6] = {a, b, d, a, d, c};
            memcpy(m->tri + 3 * t, f, sizeof f);
            t += 2;
        }
    return m;
}

static double waves(double x, double y)
{
    return 0.05 * sin(12.0 * x) * cos(9.0 * y);
}

static double bump(double x, double y)
{
    double r2 = (x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5);
    return 0.1 * exp(-r2 / 0.01);
}

static relief_status render(const relief_mesh *m, const relief_render_options *o,
                            relief_rgb_image *img, relief_render_info *info, relief_error *err)
{
    img->rgb = NULL;
    return relief_render(m, o, img, info, err);
}

/* -------------------------------------------------------------- tests */

static void test_framing(void)
{
    /* A 2 x 1 rectangle seen from straight above fills the width less the
     * margins: 180 of 200 pixels, and 90 rows. */
    relief_mesh *m = grid(5, 3, 0.0, 2.0, 0.0, 1.0, NULL, 0.0, 0, 0.0);
    relief_render_options o = relief_render_options_default();
    relief_render_info info;
    relief_rgb_image img;
    relief_error err;
    int xmin = 1 << 30, xmax = -1, ymin = 1 << 30, ymax = -1;
    o.width = o.height = 200;
    o.has_view = 1;
    o.elevation = 90.0;
    CHECK(render(m, &o, &img, &info, &err) == RELIEF_OK, "%s", err.message);
    if (img.rgb) {
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x)
                if (!is_background(img.rgb + 3 * ((size_t)y * 200 + (size_t)x))) {
                    xmin = x < xmin ? x : xmin;
                    xmax = x > xmax ? x : xmax;
                    ymin = y < ymin ? y : ymin;
                    ymax = y > ymax ? y : ymax;
                }
        CHECK(abs(xmax - xmin + 1 - 180) <= 2, "rectangle %d pixels wide, expected 180",
              xmax - xmin + 1);
        CHECK(abs(ymax - ymin + 1 - 90) <= 2, "rectangle %d pixels high, expected 90",
              ymax - ymin + 1);
        CHECK(abs(xmin - 10) <= 1 && abs(ymin - 55) <= 1, "rectangle at (%d, %d), expected "
              "(10, 55)", xmin, ymin);
        CHECK(fabs(info.pixel_size - 2.0 / 180.0) < 1e-9, "pixel size %g", info.pixel_size);
        CHECK(info.colour_by == RELIEF_COLOUR_BY_NONE, "auto on a bare mesh gave %s",
              relief_colour_by_name(info.colour_by));
        check_png_roundtrip(&img, "framing");
    }
    relief_rgb_image_free(&img);
    relief_mesh_destroy(m);
}

static void test_depth_order(void)
{
    /* Two unit squares, grey at z = 0 and orange at z = 1, the same in x
     * and y: from above the orange one hides the grey one, from below the
     * grey one hides the orange one. */
    relief_mesh *lo = grid(2, 2, 0, 1, 0, 1, NULL, 0.0, RELIEF_MESH_LABELS, 0.0);
    relief_mesh *both = NULL;
    relief_error err;
    relief_render_options o = relief_render_options_default();
    relief_rgb_image img;
    CHECK(relief_mesh_create(8, 4, RELIEF_MESH_LABELS, &both, &err) == RELIEF_OK, "%s",
          err.message);
    for (int copy = 0; copy < 2; ++copy) {
        for (size_t v = 0; v < 4; ++v) {
            memcpy(both->pos + 3 * (4 * copy + v), lo->pos + 3 * v, 3 * sizeof(double));
            both->pos[3 * (4 * copy + v) + 2] = copy;
            both->label[4 * copy + v] = (uint8_t)copy;
        }
        for (size_t k = 0; k < 6; ++k)
            both->tri[6 * copy + k] = lo->tri[k] + 4u * (uint32_t)copy;
    }
    o.width = o.height = 64;
    o.has_view = 1;
    o.colour_by = RELIEF_COLOUR_BY_LABEL;
    for (int below = 0; below < 2; ++below) {
        stats s;
        o.elevation = below ? -90.0 : 90.0;
        CHECK(render(both, &o, &img, NULL, &err) == RELIEF_OK, "%s", err.message);
        if (!img.rgb)
            continue;
        s = pixel_stats(img.rgb, img.width, img.height);
        if (below)
            CHECK(s.grey > 0 && s.orange == 0, "from below: %zu grey, %zu orange pixels",
                  s.grey, s.orange);
        else
            CHECK(s.orange > 0 && s.grey == 0, "from above: %zu grey, %zu orange pixels",
                  s.grey, s.orange);
        relief_rgb_image_free(&img);
    }
    relief_mesh_destroy(both);
    relief_mesh_destroy(lo);
}

static void test_labels_and_colour(void)
{
    relief_mesh *m = grid(40, 40, 0, 1, 0, 1, waves, 0.0,
                          RELIEF_MESH_LABELS | RELIEF_MESH_COLOURS, 0.25);
    relief_render_options o = relief_render_options_default();
    relief_render_info info;
    relief_rgb_image img;
    relief_error err;
    stats s;
    o.width = 160;
    o.height = 120;
    CHECK(render(m, &o, &img, &info, &err) == RELIEF_OK, "%s", err.message);
    CHECK(info.colour_by == RELIEF_COLOUR_BY_COLOUR, "auto gave %s",
          relief_colour_by_name(info.colour_by));
    /* The default view faces the grid's side (its normal is +z). */
    CHECK(info.elevation > 30.0 && info.elevation < 89.0, "default elevation %g",
          info.elevation);
    if (img.rgb) {
        s = pixel_stats(img.rgb, img.width, img.height);
        CHECK(img.width == 160 && img.height == 120, "size %dx%d", img.width, img.height);
        CHECK(s.foreground > 0.2 && s.foreground < 0.95, "foreground %.3f", s.foreground);
        CHECK(s.colours > 200, "%zu distinct colours for a colour ramp", s.colours);
        check_png_roundtrip(&img, "colour");
    }
    relief_rgb_image_free(&img);

    o.colour_by = RELIEF_COLOUR_BY_LABEL;
    CHECK(render(m, &o, &img, &info, &err) == RELIEF_OK, "%s", err.message);
    if (img.rgb) {
        s = pixel_stats(img.rgb, img.width, img.height);
        /* the disc is pi / 16 of the square */
        CHECK(s.orange > 0 && s.grey > 0, "labels: %zu grey, %zu orange pixels", s.grey,
              s.orange);
        CHECK(s.orange > s.grey / 8 && s.orange < s.grey / 2,
              "completed disc: %zu orange vs %zu grey pixels", s.orange, s.grey);
        CHECK(s.colours > 10, "%zu distinct colours: no shading", s.colours);
    }
    relief_rgb_image_free(&img);

    m->label[7] = 2;
    CHECK(render(m, &o, &img, NULL, &err) == RELIEF_E_MESH && strstr(err.message, "vertex 7"),
          "label 2: %s", err.message);
    relief_mesh_destroy(m);
}

static void test_displacement(void)
{
    /* A bump on a plane z = 0, seen from above: red in the middle, the
     * flat part mid grey, heights measured from the given plane. */
    relief_mesh *m = grid(41, 41, 0, 1, 0, 1, bump, 0.0, 0, 0.0);
    relief_fit_primitive plane = {RELIEF_FIT_PLANE, {0, 0, 0}, {0, 0, 1}, 0.0};
    relief_render_options o = relief_render_options_default();
    relief_render_info info;
    relief_rgb_image img;
    relief_error err;
    o.width = o.height = 100;
    o.has_view = 1;
    o.elevation = 90.0;
    o.colour_by = RELIEF_COLOUR_BY_DISPLACEMENT;
    o.prim = &plane;
    o.displacement_range = 0.1;
    CHECK(render(m, &o, &img, &info, &err) == RELIEF_OK, "%s", err.message);
    if (img.rgb) {
        const uint8_t *c = img.rgb + 3 * (50 * 100 + 50), *e = img.rgb + 3 * (12 * 100 + 12);
        CHECK(c[0] > c[2] + 60, "centre (%d, %d, %d) is not red", c[0], c[1], c[2]);
        CHECK(abs(e[0] - e[1]) < 12 && abs(e[1] - e[2]) < 12, "flat corner (%d, %d, %d) is "
              "not grey", e[0], e[1], e[2]);
        CHECK(info.displacement_range == 0.1, "range %g", info.displacement_range);
    }
    relief_rgb_image_free(&img);
    /* Fitted and automatic: the fit is a plane through the grid, the range
     * the 99th percentile of |h|, positive. */
    o.prim = NULL;
    o.displacement_range = 0.0;
    CHECK(render(m, &o, &img, &info, &err) == RELIEF_OK, "%s", err.message);
    CHECK(info.displacement_range > 0.0 && info.displacement_range < 0.1, "auto range %g",
          info.displacement_range);
    relief_rgb_image_free(&img);
    relief_mesh_destroy(m);
}

static void test_point_cloud(void)
{
    relief_mesh *g = grid(30, 30, 0, 1, 0, 1, waves, 0.0, 0, 0.0), *m = NULL;
    relief_render_options o = relief_render_options_default();
    relief_rgb_image img;
    relief_error err;
    CHECK(relief_mesh_create(g->nv, 0, 0, &m, &err) == RELIEF_OK, "%s", err.message);
    memcpy(m->pos, g->pos, g->nv * 3 * sizeof(double));
    o.width = 120;
    o.height = 90;
    CHECK(render(m, &o, &img, NULL, &err) == RELIEF_OK, "%s", err.message);
    if (img.rgb) {
        stats s = pixel_stats(img.rgb, img.width, img.height);
        CHECK(s.foreground > 0.15 && s.foreground < 0.95, "point cloud foreground %.3f",
              s.foreground);
    }
    relief_rgb_image_free(&img);
    relief_mesh_destroy(m);
    relief_mesh_destroy(g);
}

static void test_errors(void)
{
    relief_mesh *m = grid(3, 3, 0, 1, 0, 1, NULL, 0.0, 0, 0.0), *empty = NULL;
    relief_render_options o = relief_render_options_default();
    relief_rgb_image img;
    relief_error err;
    uint8_t px[3] = {1, 2, 3};
    char path[256];
    FILE *f;

    o.colour_by = RELIEF_COLOUR_BY_COLOUR;
    CHECK(render(m, &o, &img, NULL, &err) == RELIEF_E_MESH &&
          strstr(err.message, "no per-vertex colour"), "colour: %s", err.message);
    o.colour_by = RELIEF_COLOUR_BY_LABEL;
    CHECK(render(m, &o, &img, NULL, &err) == RELIEF_E_MESH &&
          strstr(err.message, "no label"), "label: %s", err.message);
    o = relief_render_options_default();
    o.width = 0;
    CHECK(render(m, &o, &img, NULL, &err) == RELIEF_E_RANGE && strstr(err.message, "0x600"),
          "width 0: %s", err.message);
    o = relief_render_options_default();
    o.has_view = 1;
    o.elevation = 91.0;
    CHECK(render(m, &o, &img, NULL, &err) == RELIEF_E_RANGE && strstr(err.message, "-90..90"),
          "elevation 91: %s", err.message);
    o = relief_render_options_default();
    CHECK(relief_mesh_create(0, 0, 0, &empty, &err) == RELIEF_OK, "%s", err.message);
    CHECK(render(empty, &o, &img, NULL, &err) == RELIEF_E_MESH, "empty mesh: %s",
          err.message);
    relief_mesh_destroy(empty);
    relief_mesh_destroy(m);

    snprintf(path, sizeof path, "%s/one.png", check_tmpdir());
    CHECK(relief_png_write("/nonexistent-dir/x.png", px, 1, 1, &err) == RELIEF_E_IO &&
          strstr(err.message, "/nonexistent-dir/x.png"), "png into a missing folder: %s",
          err.message);
    CHECK(relief_png_write(path, px, 0, 1, &err) == RELIEF_E_USAGE, "png width 0: %s",
          err.message);
    /* A written file decodes to the same 1 x 1 image. */
    CHECK(relief_png_write(path, px, 1, 1, &err) == RELIEF_OK, "%s", err.message);
    f = fopen(path, "rb");
    CHECK(f != NULL, "%s not written", path);
    if (f) {
        uint8_t buf[256], *back = NULL;
        size_t n = fread(buf, 1, sizeof buf, f);
        int w = 0, h = 0;
        const char *why = png_decode(buf, n, &back, &w, &h);
        fclose(f);
        CHECK(!why && w == 1 && h == 1 && memcmp(back, px, 3) == 0, "one.png: %s",
              why ? why : "wrong pixel");
        free(back);
    }
    remove(path);
    rmdir(check_tmpdir());
}

/* ------------------------------------------------- check a CLI's image */

static int check_file(const char *path, int w_want, int h_want, size_t min_colours)
{
    FILE *f = fopen(path, "rb");
    uint8_t *buf = NULL, *rgb = NULL;
    long n;
    int w = 0, h = 0;
    const char *why;
    stats s;
    if (!f || fseek(f, 0, SEEK_END) != 0 || (n = ftell(f)) <= 0 || fseek(f, 0, SEEK_SET) != 0 ||
        !(buf = malloc((size_t)n)) || fread(buf, 1, (size_t)n, f) != (size_t)n) {
        fprintf(stderr, "%s: cannot read\n", path);
        return 1;
    }
    fclose(f);
    why = png_decode(buf, (size_t)n, &rgb, &w, &h);
    free(buf);
    if (why) {
        fprintf(stderr, "%s: %s\n", path, why);
        return 1;
    }
    s = pixel_stats(rgb, w, h);
    free(rgb);
    printf("%s: %dx%d, foreground %.3f, %zu colours, %zu orange, %zu grey\n", path, w, h,
           s.foreground, s.colours, s.orange, s.grey);
    if (w != w_want || h != h_want) {
        fprintf(stderr, "%s: %dx%d, expected %dx%d\n", path, w, h, w_want, h_want);
        return 1;
    }
    if (s.foreground < 0.03 || s.foreground > 0.97 || s.colours < min_colours) {
        fprintf(stderr, "%s: looks blank: foreground %.3f, %zu colours\n", path, s.foreground,
                s.colours);
        return 1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    if ((argc == 5 || argc == 6) && strcmp(argv[1], "png") == 0)
        return check_file(argv[2], atoi(argv[3]), atoi(argv[4]),
                          argc == 6 ? (size_t)atoi(argv[5]) : 16);
    test_framing();
    test_depth_order();
    test_labels_and_colour();
    test_displacement();
    test_point_cloud();
    test_errors();
    return check_result();
}
