/* Occluders from depth through the public API (relief/occluders.h), on a
 * synthetic RGB-D frame whose truth is known: a textured wall and floor,
 * two boxes and a sphere in front, a depth camera's noise (sigma = 0.0015
 * z^2), 2 % of the depths dropped and the projector's shadow beside each
 * object. The mask's IoU against the truth at least 0.9 (from a cloud's
 * points and from a depth image with intrinsics); the removal's depth
 * within the noise of the true background, its colour's texture like the
 * wall's; the bad inputs' messages.
 *   test_api_occluders                 the checks
 *   test_api_occluders --write DIR     the frame as DIR/scene.pcd,
 *                                      colour.png, depth.png, truth.png; the
 *                                      bad ones: nocolour.pcd (no rgb),
 *                                      flat.pcd (nothing in front),
 *                                      noise.pcd (no background),
 *                                      empty.png (a mask of nothing),
 *                                      half.png (a depth image of another size)
 *   test_api_occluders --iou A.png B.png   print the IoU of two masks */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "api_test.h"

#define W 320
#define H 240
#define FX 262.5
#define CX 159.5
#define CY 119.5
#define NOISE 0.0015 /* sigma(z) = NOISE z^2 */

typedef struct scene {
    float z[W * H], xyz[W * H * 3];
    uint8_t rgb[W * H * 3];
    uint8_t truth[W * H];   /* 1 on the objects */
    float bg_z[W * H];      /* the true background's depth */
} scene;

/* A small deterministic generator (the test's own). */
static uint32_t next(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (uint32_t)(*s >> 33);
}

static double uniform(uint64_t *s)
{
    return (next(s) + 0.5) / 2147483648.0;
}

static double gauss(uint64_t *s)
{
    return sqrt(-2.0 * log(uniform(s))) * cos(6.283185307179586 * uniform(s));
}

static uint8_t clamp8(double v)
{
    return (uint8_t)(v < 0 ? 0 : v > 255 ? 255 : v + 0.5);
}

/* The background's colour at point (x, y, z): bricks on the wall, tiles on
 * the floor, both with a fine grain. */
static void background_colour(double x, double y, double z, int on_floor, uint64_t *g, uint8_t *c)
{
    double grain = 14.0 * (uniform(g) - 0.5);
    if (on_floor) {
        int t = ((int)floor(x / 0.3) + (int)floor(z / 0.3)) & 1;
        double v = (t ? 150 : 110) + grain;
        c[0] = clamp8(v), c[1] = clamp8(v), c[2] = clamp8(v + 10);
        return;
    }
    {
        double row = floor(y / 0.12), off = fmod(row, 2.0) * 0.12;
        double bx = fmod(x + 10.0 + off, 0.24), by = fmod(y + 10.0, 0.12);
        int mortar = bx < 0.02 || by < 0.02;
        double tone = 20.0 * sin(row * 12.9898 + floor((x + off) / 0.24) * 78.233);
        c[0] = clamp8((mortar ? 205 : 170 + tone) + grain);
        c[1] = clamp8((mortar ? 200 : 120 + tone * 0.5) + grain);
        c[2] = clamp8((mortar ? 190 : 90) + grain);
    }
}

/* The nearest object along ray r (z = 1), its depth and colour; 0: none. */
static int object_hit(const double r[3], uint64_t *g, double *z, uint8_t *c)
{
    double best = INFINITY, t;
    *z = NAN;
    int which = 0;
    /* box A's front, z = 2.0; box B's, z = 2.2, standing on the floor */
    t = 2.0;
    if (fabs(r[0] * t + 0.65) <= 0.30 && fabs(r[1] * t + 0.15) <= 0.40 && t < best)
        best = t, which = 1;
    t = 2.2;
    if (fabs(r[0] * t + 0.05) <= 0.20 && r[1] * t >= 0.35 && r[1] * t <= 0.9 && t < best)
        best = t, which = 2;
    {
        /* the sphere: centre (0.45, -0.05, 2.3), radius 0.35 */
        double cx = 0.45, cy = -0.05, cz = 2.3, rr = 0.35 * 0.35;
        double a = r[0] * r[0] + r[1] * r[1] + 1.0, b = r[0] * cx + r[1] * cy + cz;
        double disc = b * b - a * (cx * cx + cy * cy + cz * cz - rr);
        if (disc >= 0.0 && (t = (b - sqrt(disc)) / a) < best) {
            double nz = (t - cz) / 0.35, nx = (r[0] * t - cx) / 0.35;
            double shade = 0.6 + 0.4 * fmax(0.0, -nz * 0.8 - nx * 0.3);
            best = t, which = 3;
            c[0] = clamp8(40 * shade), c[1] = clamp8(60 * shade), c[2] = clamp8(170 * shade);
        }
    }
    if (!which)
        return 0;
    if (which == 1)
        c[0] = clamp8(180 + 8 * gauss(g)), c[1] = clamp8(40 + 8 * gauss(g)), c[2] = 40;
    if (which == 2)
        c[0] = 50, c[1] = clamp8(150 + 8 * gauss(g)), c[2] = clamp8(60 + 8 * gauss(g));
    *z = best;
    return 1;
}

static void make_scene(scene *s)
{
    uint64_t g = 12345;
    for (int v = 0; v < H; ++v)
        for (int u = 0; u < W; ++u) {
            size_t i = (size_t)v * W + u;
            double r[3] = {(u - CX) / FX, (v - CY) / FX, 1.0};
            double zw = 3.0 / (1.0 - 0.15 * r[0]), zf = r[1] > 0 ? 0.9 / r[1] : INFINITY;
            double zb = fmin(zw, zf), zo, z;
            uint8_t *c = s->rgb + 3 * i;
            s->bg_z[i] = (float)zb;
            s->truth[i] = (uint8_t)object_hit(r, &g, &zo, c);
            if (!s->truth[i])
                background_colour(r[0] * zb, r[1] * zb, zb, zf < zw, &g, c);
            z = s->truth[i] ? zo : zb;
            z += NOISE * z * z * gauss(&g);
            s->z[i] = uniform(&g) < 0.02 ? NAN : (float)z;
        }
    /* The projector's shadow: the background just left of an object. */
    for (int v = 0; v < H; ++v)
        for (int u = 0; u < W; ++u) {
            size_t i = (size_t)v * W + u;
            for (int k = 1; k <= 5 && u + k < W && !s->truth[i]; ++k)
                if (s->truth[i + k])
                    s->z[i] = NAN;
        }
    for (size_t i = 0; i < (size_t)W * H; ++i) {
        int u = (int)(i % W), v = (int)(i / W);
        s->xyz[3 * i] = (float)((u - CX) / FX * s->z[i]);
        s->xyz[3 * i + 1] = (float)((v - CY) / FX * s->z[i]);
        s->xyz[3 * i + 2] = s->z[i];
    }
}

static double iou(const uint8_t *a, const uint8_t *b, size_t n)
{
    size_t both = 0, any = 0;
    for (size_t i = 0; i < n; ++i)
        both += a[i] && b[i], any += a[i] || b[i];
    return any ? (double)both / any : 1.0;
}

static relief_depth_image frame_of(scene *s, int with_xyz)
{
    relief_depth_image f = {W, H, s->z, with_xyz ? s->xyz : NULL, s->rgb,
                            RELIEF_DEPTH_PCD_BINARY};
    return f;
}

static void test_find(scene *s)
{
    relief_error err = {RELIEF_OK, ""};
    relief_occluder_params p = relief_occluder_params_default();
    relief_occluder_report r;
    relief_image m, m2;
    relief_depth_image f = frame_of(s, 1);
    double j;
    CHECK_STATUS(relief_find_occluders(&f, &p, &m, &r, &err), RELIEF_OK, err, NULL);
    if (!m.data)
        return;
    j = iou(m.data, s->truth, (size_t)W * H);
    printf("cloud: IoU %.4f, %d planes, noise %.5f, margin %.4f, %zu seeds, %zu grown, %zu "
           "dilated\n", j, r.planes, r.noise, r.margin, r.seeds, r.grown_missing + r.grown_edge,
           r.dilated);
    CHECK(j >= 0.9, "IoU %.4f against the truth, expected at least 0.9", j);
    CHECK(r.planes == 2, "%d background planes, expected the wall and the floor", r.planes);
    CHECK(fabs(r.noise - NOISE) < 0.5 * NOISE, "noise %.5f measured, %.5f made", r.noise, NOISE);
    CHECK(r.json && strstr(r.json, "\"occluders\""), "the report's json");
    /* Deterministic: the same bytes again. */
    CHECK_STATUS(relief_find_occluders(&f, &p, &m2, NULL, &err), RELIEF_OK, err, NULL);
    CHECK(m2.data && !memcmp(m.data, m2.data, (size_t)W * H), "a second run differs");
    relief_image_free(&m2);
    relief_image_free(&m);
    relief_occluder_report_free(&r);
    /* A depth image and its intrinsics. */
    f = frame_of(s, 0);
    p.has_intrinsics = 1;
    p.intrinsics[0] = p.intrinsics[1] = FX, p.intrinsics[2] = CX, p.intrinsics[3] = CY;
    CHECK_STATUS(relief_find_occluders(&f, &p, &m, NULL, &err), RELIEF_OK, err, NULL);
    if (m.data) {
        j = iou(m.data, s->truth, (size_t)W * H);
        printf("depth image: IoU %.4f\n", j);
        CHECK(j >= 0.9, "IoU %.4f from the depth image, expected at least 0.9", j);
    }
    relief_image_free(&m);
}

/* Mean |horizontal and vertical difference| of the colour's luma over the
 * pixels `sel` marks (and their right and lower neighbours). */
static double texture(const uint8_t *rgb, const uint8_t *sel, int want)
{
    double sum = 0.0;
    size_t n = 0;
    for (int v = 0; v + 1 < H; ++v)
        for (int u = 0; u + 1 < W; ++u) {
            size_t i = (size_t)v * W + u, js[2] = {i + 1, i + W};
            for (int k = 0; k < 2; ++k) {
                size_t j = js[k];
                double a, b;
                if ((sel[i] != 0) != want || (sel[j] != 0) != want)
                    continue;
                a = 0.3 * rgb[3 * i] + 0.59 * rgb[3 * i + 1] + 0.11 * rgb[3 * i + 2];
                b = 0.3 * rgb[3 * j] + 0.59 * rgb[3 * j + 1] + 0.11 * rgb[3 * j + 2];
                sum += fabs(a - b), ++n;
            }
        }
    return n ? sum / n : 0.0;
}

static void test_remove(scene *s)
{
    relief_error err = {RELIEF_OK, ""};
    relief_remove_params p = relief_remove_params_default();
    relief_remove_report r;
    scene *out = malloc(sizeof *out);
    relief_depth_image f;
    double ss = 0.0, sn = 0.0, t_fill, t_wall;
    size_t nf = 0, nn = 0;
    if (!out)
        return;
    *out = *s;
    f = frame_of(out, 1);
    CHECK_STATUS(relief_remove_occluders(&f, NULL, &p, &r, &err), RELIEF_OK, err, NULL);
    if (r.mask) {
        for (size_t i = 0; i < (size_t)W * H; ++i) {
            double e = out->z[i] - s->bg_z[i];
            if (s->truth[i] && r.mask[i]) {
                CHECK(isfinite(out->z[i]), "pixel %zu: no depth behind the occluder", i);
                ss += e * e, ++nf;
            }
            if (!s->truth[i] && !r.mask[i] && isfinite(s->z[i]))
                sn += (s->z[i] - s->bg_z[i]) * (s->z[i] - s->bg_z[i]), ++nn;
            if (!r.mask[i])
                CHECK(memcmp(&out->z[i], &s->z[i], sizeof(float)) == 0, "pixel %zu outside "
                      "the mask changed", i);
        }
        t_fill = texture(out->rgb, r.mask, 1);
        t_wall = texture(s->rgb, r.mask, 0);
        printf("removal: depth RMS %.4f about the true background over %zu pixels (the "
               "capture's noise %.4f); texture %.2f against the background's %.2f (ratio "
               "%.2f)\n", sqrt(ss / nf), nf, sqrt(sn / nn), t_fill, t_wall, t_fill / t_wall);
        CHECK(sqrt(ss / nf) <= 1.5 * sqrt(sn / nn), "the filled depth's RMS %.4f is over 1.5 x "
              "the noise %.4f", sqrt(ss / nf), sqrt(sn / nn));
        CHECK(t_fill / t_wall >= 0.7 && t_fill / t_wall <= 1.4, "texture ratio %.2f outside "
              "[0.7, 1.4]", t_fill / t_wall);
    }
    CHECK(r.json && strstr(r.json, "remove-occluders"), "the removal's report");
    relief_remove_report_free(&r);
    free(out);
}

static void test_bad(scene *s)
{
    relief_error err = {RELIEF_OK, ""};
    relief_occluder_params p = relief_occluder_params_default();
    relief_image m = {0, 0, 0, 0, 0, NULL};
    relief_depth_image f = frame_of(s, 1);
    scene *t = malloc(sizeof *t);
    uint64_t g = 7;
    f.rgb = NULL;
    CHECK_STATUS(relief_find_occluders(&f, &p, &m, NULL, &err), RELIEF_E_USAGE, err, "colour");
    f = frame_of(s, 1);
    CHECK_STATUS(relief_find_occluders(&f, &p, NULL, NULL, &err), RELIEF_E_USAGE, err, "mask");
    p.window = 60;
    CHECK_STATUS(relief_find_occluders(&f, &p, &m, NULL, &err), RELIEF_E_RANGE, err, "window");
    p = relief_occluder_params_default();
    p.background = RELIEF_BACKGROUND_MESH;
    CHECK_STATUS(relief_find_occluders(&f, &p, &m, NULL, &err), RELIEF_E_USAGE, err,
                 "background_mesh");
    p = relief_occluder_params_default();
    if (!t)
        return;
    /* Nothing in front: the background alone. */
    *t = *s;
    for (size_t i = 0; i < (size_t)W * H; ++i) {
        t->z[i] = t->xyz[3 * i + 2] = t->bg_z[i];
        t->xyz[3 * i] = (float)(((int)(i % W) - CX) / FX * t->z[i]);
        t->xyz[3 * i + 1] = (float)(((int)(i / W) - CY) / FX * t->z[i]);
    }
    f = frame_of(t, 1);
    CHECK_STATUS(relief_find_occluders(&f, &p, &m, NULL, &err), RELIEF_E_RANGE, err,
                 "nothing in front");
    /* No background: depths scattered at random. */
    for (size_t i = 0; i < (size_t)W * H; ++i) {
        t->z[i] = (float)(1.0 + 4.0 * uniform(&g));
        t->xyz[3 * i] = (float)(((int)(i % W) - CX) / FX * t->z[i]);
        t->xyz[3 * i + 1] = (float)(((int)(i / W) - CY) / FX * t->z[i]);
        t->xyz[3 * i + 2] = t->z[i];
    }
    CHECK_STATUS(relief_find_occluders(&f, &p, &m, NULL, &err), RELIEF_E_RANGE, err,
                 "no background");
    /* Nothing captured. */
    for (size_t i = 0; i < (size_t)W * H; ++i)
        t->z[i] = NAN;
    CHECK_STATUS(relief_find_occluders(&f, &p, &m, NULL, &err), RELIEF_E_RANGE, err,
                 "too few");
    CHECK(m.data == NULL, "a mask was written on failure");
    free(t);
}

/* ------------------------------------------------------------ the files */

/* flat.pcd (noise 0: the background alone) or noise.pcd (noise 1: depths
 * scattered at random, no background). 1 when written. */
static int write_bad(const scene *s, const char *dir, int noise, relief_error *err)
{
    char path[4096];
    scene *t = malloc(sizeof *t);
    uint64_t g = 99;
    relief_depth_image f;
    int ok;
    if (!t)
        return 0;
    *t = *s;
    for (size_t i = 0; i < (size_t)W * H; ++i) {
        t->z[i] = noise ? (float)(1.0 + 4.0 * uniform(&g)) : t->bg_z[i];
        t->xyz[3 * i] = (float)(((int)(i % W) - CX) / FX * t->z[i]);
        t->xyz[3 * i + 1] = (float)(((int)(i / W) - CY) / FX * t->z[i]);
        t->xyz[3 * i + 2] = t->z[i];
    }
    f = frame_of(t, 1);
    snprintf(path, sizeof path, "%s/%s.pcd", dir, noise ? "noise" : "flat");
    ok = relief_depth_write(&f, path, RELIEF_DEPTH_PCD_BINARY, 0, err) == RELIEF_OK;
    free(t);
    return ok;
}

static int write_files(scene *s, const char *dir)
{
    char path[4096];
    relief_error err = {RELIEF_OK, ""};
    relief_depth_image f = frame_of(s, 1);
    uint8_t *truth = malloc((size_t)W * H);
    int ok = truth != NULL;
    for (size_t i = 0; ok && i < (size_t)W * H; ++i)
        truth[i] = 0;
    snprintf(path, sizeof path, "%s/empty.png", dir);
    ok = ok && relief_image_write(&(relief_image){W, H, 1, 8, 0, truth}, path, &err) ==
                   RELIEF_OK;
    for (size_t i = 0; ok && i < (size_t)W * H; ++i)
        truth[i] = s->truth[i] ? 255 : 0;
    snprintf(path, sizeof path, "%s/scene.pcd", dir);
    ok = ok && relief_depth_write(&f, path, RELIEF_DEPTH_PCD_BINARY, 0, &err) == RELIEF_OK;
    snprintf(path, sizeof path, "%s/depth.png", dir);
    ok = ok && relief_depth_write(&f, path, RELIEF_DEPTH_PNG16, 0, &err) == RELIEF_OK;
    snprintf(path, sizeof path, "%s/half.png", dir);
    f.width = W / 2, f.height = H / 2;
    ok = ok && relief_depth_write(&f, path, RELIEF_DEPTH_PNG16, 0, &err) == RELIEF_OK;
    f.width = W, f.height = H;
    snprintf(path, sizeof path, "%s/colour.png", dir);
    ok = ok && relief_image_write(&(relief_image){W, H, 3, 8, 0, s->rgb}, path, &err) ==
                   RELIEF_OK;
    snprintf(path, sizeof path, "%s/truth.png", dir);
    ok = ok && relief_image_write(&(relief_image){W, H, 1, 8, 0, truth}, path, &err) ==
                   RELIEF_OK;
    free(truth);
    f.rgb = NULL;
    snprintf(path, sizeof path, "%s/nocolour.pcd", dir);
    ok = ok && relief_depth_write(&f, path, RELIEF_DEPTH_PCD_BINARY, 0, &err) == RELIEF_OK;
    ok = ok && write_bad(s, dir, 0, &err) && write_bad(s, dir, 1, &err);
    if (!ok)
        fprintf(stderr, "test_api_occluders: %s\n", err.message);
    return ok ? 0 : 1;
}

static int print_iou(const char *a, const char *b)
{
    relief_error err = {RELIEF_OK, ""};
    relief_image x, y;
    int ok = relief_image_read(a, 0, &x, &err) == RELIEF_OK;
    ok = ok && relief_image_read(b, 0, &y, &err) == RELIEF_OK;
    if (ok && (x.width != y.width || x.height != y.height || x.channels != 1 ||
               y.channels != 1 || x.bit_depth != 8 || y.bit_depth != 8)) {
        fprintf(stderr, "test_api_occluders: %s and %s: not two grey masks of one size\n", a, b);
        return 1;
    }
    if (!ok) {
        fprintf(stderr, "test_api_occluders: %s\n", err.message);
        return 1;
    }
    printf("%.4f\n", iou(x.data, y.data, (size_t)x.width * x.height));
    relief_image_free(&x);
    relief_image_free(&y);
    return 0;
}

int main(int argc, char **argv)
{
    scene *s;
    int rc;
    if (argc == 4 && !strcmp(argv[1], "--iou"))
        return print_iou(argv[2], argv[3]);
    if (!(s = malloc(sizeof *s)))
        return 1;
    make_scene(s);
    if (argc == 3 && !strcmp(argv[1], "--write")) {
        rc = write_files(s, argv[2]);
        free(s);
        return rc;
    }
    test_find(s);
    test_remove(s);
    test_bad(s);
    free(s);
    API_TEST_END();
}
