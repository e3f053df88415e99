/* The image engine as a user meets it (relief/image.h): the parameters'
 * defaults and every refusal, named; images read, decoded and written; a
 * fill on a real texture that keeps every pixel outside the hole and its
 * buffer's padding; a callback that cancels half-way leaving the buffer
 * as it was; two threads at once giving the bytes of two serial calls.
 *   test_api_image IMAGES_DIR   (brick.png, chelsea.png) */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <unistd.h>

#include "api_test.h"

static char tmp[] = "/tmp/relief-api-image-XXXXXX";
static char brick[1024], chelsea[1024];

static void test_defaults(void)
{
    relief_image_fill_params p = relief_image_fill_params_default();
    relief_error err = {0};
    CHECK(p.window == 17 && p.min_window == 5 && p.tau == 0.0 && p.max_hole_fraction == 0.1 &&
              p.search_radius == 0 && p.exhaustive == 0 && p.interp == 1 &&
              p.interp_diff < 0.0 && p.interp_sd < 0.0 && p.seed == 1,
          "defaults");
    CHECK(p.run.backend == RELIEF_BACKEND_AUTO && p.run.device == -1 && !p.run.progress,
          "run defaults");
    CHECK_STATUS(relief_image_fill_params_validate(&p, &err), RELIEF_OK, err, NULL);
}

/* Each field out of range, NaN included: its status, its name. */
static void test_params(void)
{
    relief_error err = {0};
    relief_image_fill_params p;
#define BAD(field, value, want, needle)                                                    \
    do {                                                                                   \
        p = relief_image_fill_params_default();                                            \
        p.field = value;                                                                   \
        CHECK_STATUS(relief_image_fill_params_validate(&p, &err), want, err, needle);      \
    } while (0)
    BAD(window, 18, RELIEF_E_RANGE, "window 18");
    BAD(window, 1, RELIEF_E_RANGE, "window");
    BAD(window, 1027, RELIEF_E_RANGE, "window");
    BAD(window, -5, RELIEF_E_RANGE, "window");
    BAD(min_window, 4, RELIEF_E_RANGE, "min_window");
    BAD(min_window, 19, RELIEF_E_RANGE, "min_window");
    BAD(tau, NAN, RELIEF_E_RANGE, "tau");
    BAD(tau, -1.0, RELIEF_E_RANGE, "tau");
    BAD(tau, INFINITY, RELIEF_E_RANGE, "tau");
    BAD(max_hole_fraction, NAN, RELIEF_E_RANGE, "max_hole_fraction");
    BAD(max_hole_fraction, 1.0, RELIEF_E_RANGE, "max_hole_fraction");
    BAD(max_hole_fraction, -0.1, RELIEF_E_RANGE, "max_hole_fraction");
    BAD(search_radius, -1, RELIEF_E_RANGE, "search_radius");
    BAD(search_radius, 2000000, RELIEF_E_RANGE, "search_radius");
    BAD(search_radius, 3, RELIEF_E_RANGE, "search_radius");
    BAD(exhaustive, 2, RELIEF_E_RANGE, "exhaustive");
    BAD(interp, -1, RELIEF_E_RANGE, "interp");
    BAD(interp_diff, NAN, RELIEF_E_RANGE, "interp_diff");
    BAD(interp_sd, INFINITY, RELIEF_E_RANGE, "interp_sd");
    BAD(run.device, 300, RELIEF_E_RANGE, "device");
    BAD(run.backend, (relief_backend)9, RELIEF_E_RANGE, "backend");
#undef BAD
    CHECK_STATUS(relief_image_fill_params_validate(NULL, &err), RELIEF_E_USAGE, err, NULL);
    p = relief_image_fill_params_default();
    p.tau = 12.5;
    p.search_radius = 8;
    p.interp_diff = 0.0;
    CHECK_STATUS(relief_image_fill_params_validate(&p, &err), RELIEF_OK, err, NULL);
}

/* A grey 8-bit test card of w x h: a checker with a ramp. */
static uint8_t *card(int w, int h)
{
    uint8_t *v = malloc((size_t)w * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            v[(size_t)y * w + x] = (uint8_t)(((x / 4 + y / 4) % 2 ? 180 : 60) + (x % 4) * 5);
    return v;
}

/* Every bad image and mask: a status and a message naming the field, the
 * image untouched. */
static void test_bad_images(void)
{
    enum { W = 40, H = 30 };
    uint8_t *pix = card(W, H), *keep = malloc(W * H), hole[H][W], small[10][10];
    relief_image_fill_params p = relief_image_fill_params_default();
    relief_error err = {0};
    relief_image img = {W, H, 1, 8, 0, pix}, m = {W, H, 1, 8, 0, hole}, bad;
    relief_image other = {10, 10, 1, 8, 0, small};

    memset(hole, 0, sizeof hole);
    memset(small, 0, sizeof small);
    for (int y = 12; y < 16; ++y)
        for (int x = 18; x < 22; ++x)
            hole[y][x] = 255;
    memcpy(keep, pix, W * H);
    p.window = 9;
    p.run.backend = RELIEF_BACKEND_SCALAR;
#define BAD_IMAGE(field, value, want, needle)                                              \
    do {                                                                                   \
        bad = img;                                                                         \
        bad.field = value;                                                                 \
        CHECK_STATUS(relief_image_check(&bad, "image", &err), want, err, needle);          \
        CHECK_STATUS(relief_image_fill(&bad, &m, &p, NULL, &err), want, err, needle);      \
        bad = m;                                                                           \
        bad.field = value;                                                                 \
        CHECK_STATUS(relief_image_fill(&img, &bad, &p, NULL, &err), want, err, "mask");    \
    } while (0)
    BAD_IMAGE(width, 0, RELIEF_E_RANGE, "width 0");
    BAD_IMAGE(width, -4, RELIEF_E_RANGE, "width -4");
    BAD_IMAGE(width, 70000, RELIEF_E_RANGE, "width 70000");
    BAD_IMAGE(height, 0, RELIEF_E_RANGE, "height 0");
    BAD_IMAGE(height, -1, RELIEF_E_RANGE, "height -1");
    BAD_IMAGE(channels, 0, RELIEF_E_RANGE, "channels 0");
    BAD_IMAGE(channels, 5, RELIEF_E_RANGE, "channels 5");
    BAD_IMAGE(bit_depth, 12, RELIEF_E_RANGE, "bit_depth 12");
    BAD_IMAGE(stride, W - 1, RELIEF_E_RANGE, "stride 39");
    BAD_IMAGE(data, NULL, RELIEF_E_USAGE, "data");
#undef BAD_IMAGE
    CHECK_STATUS(relief_image_check(NULL, "image", &err), RELIEF_E_USAGE, err, "image");
    CHECK_STATUS(relief_image_fill(NULL, &m, &p, NULL, &err), RELIEF_E_USAGE, err, "image");
    CHECK_STATUS(relief_image_fill(&img, &m, NULL, NULL, &err), RELIEF_E_USAGE, err,
                 "parameters");
    CHECK_STATUS(relief_image_fill(&img, &other, &p, NULL, &err), RELIEF_E_USAGE, err,
                 "10 x 10");
    CHECK(strstr(err.message, "40 x 30") != NULL, "both sizes named: %s", err.message);
    CHECK_STATUS(relief_image_fill(&img, NULL, &p, NULL, &err), RELIEF_E_USAGE, err, "alpha");
    p.window = 31;
    CHECK_STATUS(relief_image_fill(&img, &m, &p, NULL, &err), RELIEF_E_RANGE, err,
                 "window 31");
    p.window = 16;
    CHECK_STATUS(relief_image_fill(&img, &m, &p, NULL, &err), RELIEF_E_RANGE, err,
                 "window 16");
    p.window = 9;
    p.tau = NAN;
    CHECK_STATUS(relief_image_fill(&img, &m, &p, NULL, &err), RELIEF_E_RANGE, err, "tau");
    p.tau = 0.0;
    p.run.max_memory = 1000;
    CHECK_STATUS(relief_image_fill(&img, &m, &p, NULL, &err), RELIEF_E_NOMEM, err, "40 x 30");
    {
        /* The same refusal from the size alone, as a caller makes it
         * before it copies the pixels (the Python package). */
        relief_error by_size;
        CHECK_STATUS(relief_image_fill_check_memory(W, H, 1, &p, &by_size), RELIEF_E_NOMEM,
                     by_size, "40 x 30");
        CHECK(strcmp(by_size.message, err.message) == 0, "'%s', the engine said '%s'",
              by_size.message, err.message);
        CHECK_STATUS(relief_image_fill_check_memory(70000, H, 1, &p, &by_size), RELIEF_E_RANGE,
                     by_size, "width 70000");
        CHECK_STATUS(relief_image_fill_check_memory(W, H, 5, &p, &by_size), RELIEF_E_RANGE,
                     by_size, "channels 5");
        CHECK_STATUS(relief_image_fill_check_memory(W, H, 3, NULL, &by_size), RELIEF_OK,
                     by_size, NULL);
    }
    p.run.max_memory = 0;
    CHECK(memcmp(pix, keep, W * H) == 0, "a refused call changed the image");
    /* Nothing to fill: OK, untouched, said. */
    {
        relief_image_fill_report rep;
        memset(hole, 0, sizeof hole);
        CHECK_STATUS(relief_image_fill(&img, &m, &p, &rep, &err), RELIEF_OK, err, NULL);
        CHECK(rep.hole_pixels == 0 && rep.json && strstr(rep.json, "\"hole\": 0"),
              "nothing to fill: %zu", rep.hole_pixels);
        CHECK(memcmp(pix, keep, W * H) == 0, "nothing to fill changed the image");
        relief_image_fill_report_free(&rep);
        CHECK(rep.json == NULL, "report freed");
    }
    free(pix);
    free(keep);
}

static size_t image_bytes(const relief_image *img)
{
    size_t row = (size_t)img->width * img->channels * (img->bit_depth / 8);
    return (img->stride ? img->stride : row) * (size_t)img->height;
}

/* Reading, decoding and writing: a real PNG and a 16-bit RGBA image
 * written and read back sample for sample. */
static void test_files(void)
{
    relief_error err = {0};
    relief_image a, b, c;
    char path[1100];
    FILE *f;

    CHECK_STATUS(relief_image_read(chelsea, 0, &a, &err), RELIEF_OK, err, NULL);
    CHECK(a.width == 451 && a.height == 300 && a.channels == 3 && a.bit_depth == 8 &&
              a.stride == 451 * 3,
          "chelsea: %d x %d x %d, %d bits, stride %zu", a.width, a.height, a.channels,
          a.bit_depth, a.stride);
    snprintf(path, sizeof path, "%s/chelsea.png", tmp);
    CHECK_STATUS(relief_image_write(&a, path, &err), RELIEF_OK, err, NULL);
    CHECK_STATUS(relief_image_read(path, 0, &b, &err), RELIEF_OK, err, NULL);
    CHECK(b.width == a.width && b.height == a.height && b.channels == a.channels &&
              memcmp(a.data, b.data, image_bytes(&a)) == 0,
          "chelsea round trip");
    relief_image_free(&b);
    /* From memory: the same samples. */
    f = fopen(chelsea, "rb");
    if (f) {
        static uint8_t bytes[1 << 20];
        size_t n = fread(bytes, 1, sizeof bytes, f);
        fclose(f);
        CHECK_STATUS(relief_image_decode(bytes, n, "chelsea", 0, &c, &err), RELIEF_OK, err,
                     NULL);
        CHECK(c.data && memcmp(a.data, c.data, image_bytes(&a)) == 0, "decode");
        relief_image_free(&c);
        CHECK_STATUS(relief_image_decode(bytes, 100, "chelsea", 0, &c, &err), RELIEF_E_PARSE,
                     err, "chelsea");
    }
    /* max_bytes bounds the samples: 451 x 300 x 3 bytes fit, a byte less not. */
    CHECK_STATUS(relief_image_read(chelsea, 451 * 300 * 3 - 1, &c, &err), RELIEF_E_NOMEM, err,
                 "451 x 300");
    CHECK_STATUS(relief_image_read(chelsea, 451 * 300 * 3, &c, &err), RELIEF_OK, err, NULL);
    relief_image_free(&c);
    relief_image_free(&a);
    CHECK(a.data == NULL && a.width == 0, "freed");
    CHECK_STATUS(relief_image_read("/nonexistent/x.png", 0, &a, &err), RELIEF_E_IO, err,
                 "/nonexistent/x.png");

    /* 16-bit RGBA with a padded stride: back packed, every sample kept. */
    {
        enum { W = 23, H = 17 };
        static uint16_t px[H][W * 4 + 3];
        relief_image d = {W, H, 4, 16, sizeof px[0], px};
        int same = 1;
        for (int y = 0; y < H; ++y)
            for (int i = 0; i < W * 4; ++i)
                px[y][i] = (uint16_t)(y * 3001 + i * 257 + 11);
        snprintf(path, sizeof path, "%s/deep.png", tmp);
        CHECK_STATUS(relief_image_write(&d, path, &err), RELIEF_OK, err, NULL);
        CHECK_STATUS(relief_image_read(path, 0, &b, &err), RELIEF_OK, err, NULL);
        CHECK(b.bit_depth == 16 && b.channels == 4 && b.stride == W * 8, "16-bit shape");
        for (int y = 0; b.data && y < H; ++y)
            same &= memcmp((uint8_t *)b.data + y * b.stride, px[y], W * 8) == 0;
        CHECK(same, "16-bit samples differ after the round trip");
        relief_image_free(&b);
        CHECK_STATUS(relief_image_read(path, W * H * 8 - 1, &b, &err), RELIEF_E_NOMEM, err,
                     "23 x 17");
        CHECK_STATUS(relief_image_read(path, W * H * 8, &b, &err), RELIEF_OK, err, NULL);
        relief_image_free(&b);
        snprintf(path, sizeof path, "%s/deep.jpg", tmp);
        CHECK_STATUS(relief_image_write(&d, path, &err), RELIEF_E_FORMAT, err, "JPEG");
        CHECK(access(path, F_OK) != 0, "a refused JPEG was left");
        snprintf(path, sizeof path, "%s/deep.bmp", tmp);
        CHECK_STATUS(relief_image_write(&d, path, &err), RELIEF_E_FORMAT, err, "deep.bmp");
        CHECK_STATUS(relief_image_write(&d, NULL, &err), RELIEF_E_USAGE, err, "path");
    }
}

/* brick.png with a square hole of side s at (x0, y0) cut (zeroed), its
 * mask in *mask (caller frees both buffers). */
static int cut_brick(int x0, int y0, int s, relief_image *img, relief_image *mask)
{
    relief_error err = {0};
    uint8_t *m;
    if (relief_image_read(brick, 0, img, &err) != RELIEF_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 0;
    }
    m = calloc((size_t)img->width * img->height, 1);
    for (int y = y0; y < y0 + s; ++y)
        for (int x = x0; x < x0 + s; ++x) {
            m[(size_t)y * img->width + x] = 1;
            for (int c = 0; c < img->channels; ++c)
                ((uint8_t *)img->data)[(size_t)y * img->stride + (size_t)x * img->channels + c] =
                    0;
        }
    *mask = (relief_image){img->width, img->height, 1, 8, 0, m};
    return 1;
}

/* A real fill: outside the hole bit for bit, inside filled with brick
 * texture (varied as the bricks are, of the image's brightness; the cut
 * square had a mean of 109 and a standard deviation of 29), the report's
 * counts and JSON. */
static void test_fill(void)
{
    relief_image img, mask;
    relief_image_fill_params p = relief_image_fill_params_default();
    relief_image_fill_report rep;
    relief_error err = {0};
    uint8_t *before;
    size_t n, changed_out = 0, zero_in = 0;
    double sum_in = 0, sum2_in = 0, sum_all = 0;

    if (!cut_brick(200, 240, 48, &img, &mask))
        return;
    n = image_bytes(&img);
    before = malloc(n);
    memcpy(before, img.data, n);
    p.run.backend = RELIEF_BACKEND_SCALAR;
    p.run.input_name = "brick.png";
    /* Copy-paste alone: the 1-D pass would bridge most of this hole with
     * flat ramps (the ends agree within 16), which says nothing of the
     * texture's synthesis. */
    p.interp = 0;
    CHECK_STATUS(relief_image_fill(&img, &mask, &p, &rep, &err), RELIEF_OK, err, NULL);
    for (size_t i = 0; i < n; ++i) {
        uint8_t v = ((uint8_t *)img.data)[i];
        sum_all += v;
        if (((uint8_t *)mask.data)[i]) {
            zero_in += v == 0;
            sum_in += v;
            sum2_in += (double)v * v;
        } else {
            changed_out += v != before[i];
        }
    }
    CHECK(changed_out == 0, "%zu samples changed outside the hole", changed_out);
    {
        double k = 48.0 * 48.0, mean = sum_in / k, sd = sqrt(sum2_in / k - mean * mean);
        printf("fill of brick.png's 48 x 48 hole: mean %.1f (image %.1f), sd %.1f\n", mean,
               sum_all / n, sd);
        CHECK(zero_in < 48 && sd > 10.0 && fabs(mean - sum_all / n) < 30.0,
              "the fill: %zu black, mean %.1f (image %.1f), sd %.1f", zero_in, mean,
              sum_all / n, sd);
    }
    CHECK(rep.hole_pixels == 48 * 48 &&
              rep.by_rows + rep.by_columns + rep.by_copy + rep.by_fallback == 48 * 48,
          "counts: %zu = %zu + %zu + %zu + %zu", rep.hole_pixels, rep.by_rows, rep.by_columns,
          rep.by_copy, rep.by_fallback);
    CHECK(rep.backend == RELIEF_BACKEND_SCALAR && rep.device[0] && rep.tau == 36.0 &&
              rep.seconds_total > 0.0,
          "report: %s %s %g", relief_backend_name(rep.backend), rep.device, rep.tau);
    CHECK(rep.json && strstr(rep.json, "\"command\": \"image-fill\"") &&
              strstr(rep.json, "\"input\": \"brick.png\"") &&
              strstr(rep.json, "\"output\": null") && strstr(rep.json, "\"hole\": 2304"),
          "json: %s", rep.json ? rep.json : "(none)");
    relief_image_fill_report_free(&rep);
    free(before);
    relief_image_free(&img);
    free(mask.data);
}

/* Method wexler (issue 62): a 64 x 64 hole in brick.png filled by patch
 * voting, the pixels outside it bit for bit, as textured as the cut square
 * (a standard deviation within 0.6..1.4 of its 29) and nearer the truth than
 * a flat fill of the image's mean; one thread (scalar), two (host) and an
 * OpenCL device where one runs give the same bytes, and another seed other
 * bytes. */
static void test_wexler(void)
{
    relief_image truth, img[4], mask;
    size_t n_dev = 0;
    const int runs = relief_devices(NULL, 0, &n_dev, &(relief_error){0}) == RELIEF_OK && n_dev
                         ? 4 : 3;
    relief_error err = {0};
    relief_image_fill_report rep;
    size_t n, changed_out = 0, k = 0;
    double se = 0, se_flat = 0, mean_all = 0, s1 = 0, s2 = 0, t1 = 0, t2 = 0;
    if (relief_image_read(brick, 0, &truth, &err) != RELIEF_OK ||
        !cut_brick(180, 220, 64, &img[0], &mask))
        return;
    n = image_bytes(&truth);
    for (int i = 1; i < runs; ++i) {
        relief_image m2;
        if (!cut_brick(180, 220, 64, &img[i], &m2))
            return;
        free(m2.data);
    }
    for (int i = 0; i < runs; ++i) {
        relief_image_fill_params p = relief_image_fill_params_default();
        p.method = RELIEF_IMAGE_FILL_WEXLER;
        p.interp = 0;
        p.run.backend = i == 1 ? RELIEF_BACKEND_HOST
                        : i == 3 ? RELIEF_BACKEND_OPENCL : RELIEF_BACKEND_SCALAR;
        p.run.threads = i == 1 ? 2 : 0;
        p.seed = i == 2 ? 7 : 1;
        CHECK_STATUS(relief_image_fill(&img[i], &mask, &p, i == 0 ? &rep : NULL, &err),
                     RELIEF_OK, err, NULL);
    }
    for (size_t i = 0; i < n; ++i)
        mean_all += ((uint8_t *)truth.data)[i] / (double)n;
    for (size_t i = 0; i < n; ++i) {
        const double v = ((uint8_t *)img[0].data)[i], t = ((uint8_t *)truth.data)[i];
        if (!((uint8_t *)mask.data)[i]) {
            changed_out += v != t;
            continue;
        }
        ++k, se += (v - t) * (v - t), se_flat += (mean_all - t) * (mean_all - t);
        s1 += v, s2 += v * v, t1 += t, t2 += t * t;
    }
    {
        const double sd = sqrt(s2 / k - (s1 / k) * (s1 / k));
        const double tsd = sqrt(t2 / k - (t1 / k) * (t1 / k));
        printf("wexler fill of brick.png's 64 x 64 hole: rms %.1f (flat %.1f), sd %.1f "
               "(truth %.1f), %d levels, %zu steps\n", sqrt(se / k), sqrt(se_flat / k), sd,
               tsd, rep.pyramid_levels, rep.em_steps);
        CHECK(changed_out == 0, "wexler: %zu samples changed outside the hole", changed_out);
        CHECK(sd > 0.6 * tsd && sd < 1.4 * tsd, "wexler: sd %.1f against the truth's %.1f", sd,
              tsd);
        CHECK(se < se_flat, "wexler: rms %.1f, no nearer the truth than a flat %.1f",
              sqrt(se / k), sqrt(se_flat / k));
    }
    CHECK(memcmp(img[0].data, img[1].data, n) == 0, "wexler: scalar and host (2 threads) differ");
    CHECK(memcmp(img[0].data, img[2].data, n) != 0, "wexler: seeds 1 and 7 gave the same bytes");
    CHECK(runs < 4 || memcmp(img[0].data, img[3].data, n) == 0,
          "wexler: scalar and OpenCL differ");
    if (runs < 4)
        printf("no OpenCL device: wexler's OpenCL bytes are not compared\n");
    CHECK(rep.pyramid_levels > 1 && rep.em_steps > 0 && rep.targets > 64 * 64 &&
              rep.by_copy == 64 * 64 && strstr(rep.json, "\"method\": \"wexler\""),
          "wexler report: %d levels, %zu steps, %zu targets, %zu voted", rep.pyramid_levels,
          rep.em_steps, rep.targets, rep.by_copy);
    relief_image_fill_report_free(&rep);
    for (int i = 0; i < runs; ++i)
        relief_image_free(&img[i]);
    relief_image_free(&truth);
    free(mask.data);
}

/* The mean |Laplacian| of an 8-bit image over the pixels of `mask`, every
 * channel: how rough a fill is, against the truth's. */
static double roughness(const relief_image *img, const uint8_t *mask)
{
    const int W = img->width, H = img->height, C = img->channels;
    const uint8_t *v = img->data;
    double sum = 0.0;
    size_t n = 0;
    for (int y = 1; y < H - 1; ++y)
        for (int x = 1; x < W - 1; ++x) {
            const size_t q = (size_t)y * W + x;
            if (!mask[q])
                continue;
            for (int c = 0; c < C; ++c) {
                const size_t i = q * C + c;
                sum += fabs(4.0 * v[i] - v[i - C] - v[i + C] - v[i - (size_t)W * C] -
                            v[i + (size_t)W * C]);
                ++n;
            }
        }
    return n ? sum / n : 0.0;
}

/* A 5-pixel scratch across chelsea.png (issue 62's thin gaps): wexler
 * continues the fur and the eye smoothly across it, no rougher than the
 * truth and nearer it than paper 004's copy-paste. */
static void test_wexler_scratch(void)
{
    relief_image truth, img[2];
    relief_error err = {0};
    uint8_t *m;
    double se[2] = {0, 0}, rough[2], rough_truth;
    size_t k = 0;
    if (relief_image_read(chelsea, 0, &truth, &err) != RELIEF_OK)
        return;
    m = calloc((size_t)truth.width * truth.height, 1);
    for (int x = 60; x < truth.width - 60; ++x)
        for (int d = -2; d <= 2; ++d) {
            const int y = 60 + (x - 60) * (truth.height - 120) / (truth.width - 120) + d;
            m[(size_t)y * truth.width + x] = 1;
        }
    for (int i = 0; i < 2; ++i) {
        relief_image mask = {truth.width, truth.height, 1, 8, 0, m};
        relief_image_fill_params p = relief_image_fill_params_default();
        CHECK(relief_image_read(chelsea, 0, &img[i], &err) == RELIEF_OK, "chelsea.png again");
        p.method = i ? RELIEF_IMAGE_FILL_JAIN : RELIEF_IMAGE_FILL_WEXLER;
        p.run.backend = RELIEF_BACKEND_HOST;
        CHECK_STATUS(relief_image_fill(&img[i], &mask, &p, NULL, &err), RELIEF_OK, err, NULL);
        rough[i] = roughness(&img[i], m);
    }
    rough_truth = roughness(&truth, m);
    for (size_t q = 0; q < (size_t)truth.width * truth.height; ++q)
        for (int c = 0; m[q] && c < truth.channels; ++c, ++k)
            for (int i = 0; i < 2; ++i) {
                const double e = (double)((uint8_t *)img[i].data)[q * truth.channels + c] -
                                 ((uint8_t *)truth.data)[q * truth.channels + c];
                se[i] += e * e;
            }
    printf("chelsea.png's scratch: rms %.1f wexler, %.1f jain; roughness %.1f, %.1f, truth "
           "%.1f\n", sqrt(se[0] / k), sqrt(se[1] / k), rough[0], rough[1], rough_truth);
    CHECK(se[0] < se[1], "scratch: wexler's rms %.1f not under jain's %.1f", sqrt(se[0] / k),
          sqrt(se[1] / k));
    CHECK(rough[0] <= 1.1 * rough_truth, "scratch: wexler's roughness %.1f over the truth's "
          "%.1f", rough[0], rough_truth);
    for (int i = 0; i < 2; ++i)
        relief_image_free(&img[i]);
    relief_image_free(&truth);
    free(m);
}

typedef struct cancel_ctx {
    double last;
    int calls, decreasing;
    double at;
} cancel_ctx;

static int cancel_half(void *ctx, double fraction)
{
    cancel_ctx *c = ctx;
    c->decreasing |= fraction < c->last;
    c->last = fraction;
    ++c->calls;
    if (fraction >= 0.5) {
        c->at = fraction;
        return 1;
    }
    return 0;
}

/* Cancelled half-way: RELIEF_E_CANCELLED, the buffer and the report as
 * they were. */
static void test_cancel(relief_image_fill_method method)
{
    relief_image img, mask;
    relief_image_fill_params p = relief_image_fill_params_default();
    relief_image_fill_report rep;
    relief_error err = {0};
    cancel_ctx c = {0.0, 0, 0, -1.0};
    uint8_t *before;
    size_t n;

    if (!cut_brick(100, 100, 40, &img, &mask))
        return;
    n = image_bytes(&img);
    before = malloc(n);
    memcpy(before, img.data, n);
    memset(&rep, 0x5a, sizeof rep);
    p.run.backend = RELIEF_BACKEND_SCALAR;
    p.method = method;
    p.interp = 0; /* so that the pastes take the hole from 0 to 1 */
    p.run.progress = cancel_half;
    p.run.progress_ctx = &c;
    CHECK_STATUS(relief_image_fill(&img, &mask, &p, &rep, &err), RELIEF_E_CANCELLED, err,
                 "cancelled");
    CHECK(c.calls > 2 && c.at >= 0.5 && c.at < 1.0 && !c.decreasing,
          "progress: %d calls, cancelled at %g", c.calls, c.at);
    CHECK(memcmp(img.data, before, n) == 0, "a cancelled fill changed the caller's buffer");
    {
        relief_image_fill_report same;
        memset(&same, 0x5a, sizeof same);
        CHECK(memcmp(&rep, &same, sizeof rep) == 0, "a cancelled fill wrote the report");
    }
    free(before);
    relief_image_free(&img);
    free(mask.data);
}

typedef struct job {
    relief_image img, mask;
    relief_backend backend;
    relief_status st;
} job;

static void *fill_job(void *arg)
{
    job *j = arg;
    relief_image_fill_params p = relief_image_fill_params_default();
    relief_error err = {0};
    p.run.backend = j->backend;
    p.window = 11;
    j->st = relief_image_fill(&j->img, &j->mask, &p, NULL, &err);
    if (j->st != RELIEF_OK)
        fprintf(stderr, "fill_job: %s\n", err.message);
    return NULL;
}

/* A hole in chelsea.png (RGB) and in brick.png, each filled by one scalar
 * call and then both at once on `backend`: the same bytes (the backends
 * give the same bits). */
static void test_threads(relief_backend backend)
{
    relief_error err = {0};
    job serial[2], par[2];
    pthread_t t[2];
    uint8_t *cm;

    if (!cut_brick(300, 60, 36, &serial[0].img, &serial[0].mask) ||
        relief_image_read(chelsea, 0, &serial[1].img, &err) != RELIEF_OK)
        return;
    cm = calloc(451 * 300, 1);
    for (int y = 120; y < 150; ++y)
        for (int x = 200; x < 240; ++x)
            cm[y * 451 + x] = 1;
    serial[1].mask = (relief_image){451, 300, 1, 8, 0, cm};
    for (int k = 0; k < 2; ++k) {
        size_t n = image_bytes(&serial[k].img);
        serial[k].backend = RELIEF_BACKEND_SCALAR;
        par[k] = serial[k];
        par[k].backend = backend;
        par[k].img.data = malloc(n);
        memcpy(par[k].img.data, serial[k].img.data, n);
        fill_job(&serial[k]);
    }
    for (int k = 0; k < 2; ++k)
        pthread_create(&t[k], NULL, fill_job, &par[k]);
    for (int k = 0; k < 2; ++k) {
        pthread_join(t[k], NULL);
        CHECK(serial[k].st == RELIEF_OK && par[k].st == RELIEF_OK, "job %d failed", k);
        CHECK(memcmp(serial[k].img.data, par[k].img.data, image_bytes(&par[k].img)) == 0,
              "job %d: two threads at once on %s differ from the serial call", k,
              relief_backend_name(backend));
        relief_image_free(&serial[k].img);
        free(par[k].img.data);
        free(serial[k].mask.data);
    }
}

/* A view of a sub-rectangle of a bigger buffer (stride > row): filled
 * inside the view only, as a packed copy of it is, the rest untouched. */
static void test_view(void)
{
    enum { X0 = 64, Y0 = 80, VW = 160, VH = 120 };
    relief_image big, mask;
    relief_image_fill_params p = relief_image_fill_params_default();
    relief_error err = {0};
    uint8_t *before, *packed, *vm;
    size_t n;
    int outside = 0, differ = 0;

    if (!cut_brick(X0 + 60, Y0 + 50, 24, &big, &mask))
        return;
    free(mask.data);
    n = image_bytes(&big);
    before = malloc(n);
    memcpy(before, big.data, n);
    vm = calloc(VW * VH, 1);
    packed = malloc(VW * VH);
    for (int y = 0; y < VH; ++y) {
        memcpy(packed + y * VW, (uint8_t *)big.data + (size_t)(Y0 + y) * big.stride + X0, VW);
        for (int x = 0; x < VW; ++x)
            vm[y * VW + x] = x >= 60 && x < 84 && y >= 50 && y < 74;
    }
    {
        relief_image view = {VW, VH, 1, 8, big.stride,
                             (uint8_t *)big.data + (size_t)Y0 * big.stride + X0};
        relief_image pk = {VW, VH, 1, 8, 0, packed};
        relief_image m = {VW, VH, 1, 8, 0, vm};
        p.run.backend = RELIEF_BACKEND_SCALAR;
        p.window = 15;
        CHECK_STATUS(relief_image_fill(&view, &m, &p, NULL, &err), RELIEF_OK, err, NULL);
        CHECK_STATUS(relief_image_fill(&pk, &m, &p, NULL, &err), RELIEF_OK, err, NULL);
    }
    for (int y = 0; y < big.height; ++y)
        for (int x = 0; x < big.width; ++x) {
            size_t i = (size_t)y * big.stride + x;
            int in_view = x >= X0 && x < X0 + VW && y >= Y0 && y < Y0 + VH;
            uint8_t v = ((uint8_t *)big.data)[i];
            if (!in_view)
                outside += v != before[i];
            else
                differ += v != packed[(y - Y0) * VW + x - X0];
        }
    CHECK(outside == 0, "%d bytes changed outside the view", outside);
    CHECK(differ == 0, "%d pixels of the view differ from the packed copy's fill", differ);
    free(before);
    free(packed);
    free(vm);
    relief_image_free(&big);
}

/* No mask: the transparent pixels of an RGBA image, filled and opaque;
 * 16 bits a sample. */
static void test_alpha16(void)
{
    enum { W = 64, H = 48 };
    static uint16_t px[H][W][4], keep[H][W][4];
    relief_image img = {W, H, 4, 16, 0, px};
    relief_image_fill_params p = relief_image_fill_params_default();
    relief_image_fill_report rep;
    relief_error err = {0};
    int kept = 1, opaque = 1;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            int hole = x >= 28 && x < 36 && y >= 20 && y < 28;
            for (int c = 0; c < 3; ++c)
                px[y][x][c] = hole ? 0 : (uint16_t)((((x / 4 + y / 4) % 2) ? 50000 : 9000) + 700 * c);
            px[y][x][3] = hole ? 0 : 65535;
        }
    memcpy(keep, px, sizeof px);
    p.window = 9;
    p.run.backend = RELIEF_BACKEND_SCALAR;
    CHECK_STATUS(relief_image_fill(&img, NULL, &p, &rep, &err), RELIEF_OK, err, NULL);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            int hole = x >= 28 && x < 36 && y >= 20 && y < 28;
            if (!hole)
                kept &= memcmp(px[y][x], keep[y][x], sizeof px[y][x]) == 0;
            else
                opaque &= px[y][x][3] == 65535 && (px[y][x][0] == 9000 || px[y][x][0] == 50000);
        }
    CHECK(kept, "16-bit: pixels outside the hole changed");
    CHECK(opaque, "16-bit: a hole pixel is not opaque or not of the checker");
    CHECK(rep.hole_pixels == 64 && rep.tau == 36.0 * 257, "16-bit: %zu holes, tau %g",
          rep.hole_pixels, rep.tau);
    relief_image_fill_report_free(&rep);
}

int main(int argc, char **argv)
{
    if (!api_test_locale())
        return 2;
    if (argc != 2) {
        fprintf(stderr, "usage: test_api_image IMAGES_DIR\n");
        return 2;
    }
    snprintf(brick, sizeof brick, "%s/brick.png", argv[1]);
    snprintf(chelsea, sizeof chelsea, "%s/chelsea.png", argv[1]);
    if (access(brick, R_OK) != 0 || access(chelsea, R_OK) != 0) {
        printf("%s: no brick.png or chelsea.png: skipped\n", argv[1]);
        return 77;
    }
    if (!mkdtemp(tmp)) {
        perror(tmp);
        return 2;
    }
    test_defaults();
    test_params();
    test_bad_images();
    test_files();
    test_fill();
    test_wexler();
    test_wexler_scratch();
    test_cancel(RELIEF_IMAGE_FILL_JAIN);
    test_cancel(RELIEF_IMAGE_FILL_WEXLER);
    test_threads(RELIEF_BACKEND_SCALAR);
    test_threads(RELIEF_BACKEND_HOST);
    {
        /* OpenCL too where a device runs: its scorers start at once. */
        relief_error err = {0};
        size_t n = 0;
        if (relief_devices(NULL, 0, &n, &err) == RELIEF_OK && n > 0)
            test_threads(RELIEF_BACKEND_OPENCL);
        else
            printf("no OpenCL device: the threads test on OpenCL is skipped\n");
    }
    test_view();
    test_alpha16();
    {
        char cmd[1200];
        snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmp);
        if (system(cmd) != 0)
            fprintf(stderr, "cannot remove %s\n", tmp);
    }
    API_TEST_END();
}
