/* Small image chores for the image-fill CLI test (test_image_fill.sh):
 *   image_tool mask OUT.png W H X Y RW RH ...  grey mask, 255 in the rectangles
 *   image_tool tile IN OUT.png W H             IN repeated to W x H
 *   image_tool rgba IN OUT.png X Y RW RH       IN with alpha, 0 in the rectangle
 *   image_tool deep IN OUT.png                 IN at 16 bits (x 257)
 *   image_tool outside A B MASK                exit 0 when A and B agree, value for
 *                                              value, wherever MASK is 0 (and print
 *                                              how many hole values differ)
 *   image_tool same A B                        exit 0 when A and B hold the same image
 *                                              (shape, bit depth, every value), whatever
 *                                              their files' bytes
 *   image_tool opaque A                        exit 0 when every alpha is the maximum
 *   image_tool paint IN MASK OUT.png           IN with the hole painted red (white
 *                                              in grey images), for pictures */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image/image_io.h"

static relief_raster load(const char *path)
{
    relief_raster r;
    relief_error err = {0};
    if (relief_raster_read(path, NULL, &r, &err) != RELIEF_OK) {
        fprintf(stderr, "image_tool: %s\n", err.message);
        exit(2);
    }
    return r;
}

static void save(const char *path, const relief_raster *r)
{
    relief_error err = {0};
    if (relief_raster_write(path, r, &err) != RELIEF_OK) {
        fprintf(stderr, "image_tool: %s\n", err.message);
        exit(2);
    }
}

int main(int argc, char **argv)
{
    relief_error err = {0};
    relief_raster a, b, m;
    if (argc >= 9 && (argc - 5) % 4 == 0 && strcmp(argv[1], "mask") == 0) {
        int w = atoi(argv[3]), h = atoi(argv[4]);
        if (relief_raster_create(w, h, 1, 8, &m, &err) != RELIEF_OK)
            return 2;
        for (int k = 5; k + 3 < argc; k += 4) {
            int x0 = atoi(argv[k]), y0 = atoi(argv[k + 1]), rw = atoi(argv[k + 2]),
                rh = atoi(argv[k + 3]);
            for (int y = y0; y < y0 + rh && y < h; ++y)
                for (int x = x0; x < x0 + rw && x < w; ++x)
                    m.v[y * w + x] = 255.0f;
        }
        save(argv[2], &m);
        relief_raster_free(&m);
        return 0;
    }
    if (argc == 6 && strcmp(argv[1], "tile") == 0) {
        int w = atoi(argv[4]), h = atoi(argv[5]);
        a = load(argv[2]);
        if (relief_raster_create(w, h, a.channels, a.bit_depth, &b, &err) != RELIEF_OK)
            return 2;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                memcpy(b.v + ((size_t)y * w + x) * a.channels,
                       a.v + ((size_t)(y % a.height) * a.width + x % a.width) * a.channels,
                       (size_t)a.channels * sizeof *b.v);
        save(argv[3], &b);
        relief_raster_free(&a);
        relief_raster_free(&b);
        return 0;
    }
    if (argc == 8 && strcmp(argv[1], "rgba") == 0) {
        int x0 = atoi(argv[4]), y0 = atoi(argv[5]), rw = atoi(argv[6]), rh = atoi(argv[7]);
        a = load(argv[2]);
        relief_raster_create(a.width, a.height, 4, a.bit_depth, &b, &err);
        for (int y = 0; y < a.height; ++y)
            for (int x = 0; x < a.width; ++x) {
                size_t i = (size_t)y * a.width + x;
                int in = x >= x0 && x < x0 + rw && y >= y0 && y < y0 + rh;
                for (int c = 0; c < 3; ++c)
                    b.v[i * 4 + c] = in ? 0.0f : a.v[i * a.channels + (a.channels >= 3 ? c : 0)];
                b.v[i * 4 + 3] = in ? 0.0f : relief_raster_max_value(&b);
            }
        save(argv[3], &b);
        relief_raster_free(&a);
        relief_raster_free(&b);
        return 0;
    }
    if (argc == 4 && strcmp(argv[1], "deep") == 0) {
        a = load(argv[2]);
        a.bit_depth = 16;
        for (size_t i = 0; i < (size_t)a.width * a.height * a.channels; ++i)
            a.v[i] *= 257.0f;
        save(argv[3], &a);
        relief_raster_free(&a);
        return 0;
    }
    if (argc == 5 && strcmp(argv[1], "outside") == 0) {
        size_t differ = 0, bad = 0;
        a = load(argv[2]);
        b = load(argv[3]);
        m = load(argv[4]);
        if (a.width != b.width || a.height != b.height || a.channels != b.channels ||
            m.width != a.width || m.height != a.height) {
            fprintf(stderr, "image_tool: sizes differ\n");
            relief_raster_free(&a);
            relief_raster_free(&b);
            relief_raster_free(&m);
            return 1;
        }
        for (size_t i = 0; i < (size_t)a.width * a.height; ++i)
            for (int c = 0; c < a.channels; ++c) {
                int same = a.v[i * a.channels + c] == b.v[i * a.channels + c];
                if (m.v[i * m.channels] != 0.0f)
                    differ += !same;
                else
                    bad += !same;
            }
        printf("%zu values differ outside the hole, %zu inside\n", bad, differ);
        relief_raster_free(&a);
        relief_raster_free(&b);
        relief_raster_free(&m);
        return bad ? 1 : 0;
    }
    if (argc == 4 && strcmp(argv[1], "same") == 0) {
        int same;
        a = load(argv[2]);
        b = load(argv[3]);
        same = a.width == b.width && a.height == b.height && a.channels == b.channels &&
               a.bit_depth == b.bit_depth &&
               memcmp(a.v, b.v, sizeof(float) * a.width * a.height * a.channels) == 0;
        relief_raster_free(&a);
        relief_raster_free(&b);
        return same ? 0 : 1;
    }
    if (argc == 3 && strcmp(argv[1], "opaque") == 0) {
        int opaque;
        a = load(argv[2]);
        opaque = a.channels == 2 || a.channels == 4;
        for (size_t i = 0; opaque && i < (size_t)a.width * a.height; ++i)
            opaque = a.v[i * a.channels + a.channels - 1] == relief_raster_max_value(&a);
        relief_raster_free(&a);
        return opaque ? 0 : 1;
    }
    if (argc == 5 && strcmp(argv[1], "paint") == 0) {
        a = load(argv[2]);
        m = load(argv[3]);
        for (size_t i = 0; i < (size_t)a.width * a.height && m.width == a.width; ++i)
            if (m.v[i * m.channels] != 0.0f)
                for (int c = 0; c < a.channels; ++c)
                    a.v[i * a.channels + c] = a.channels >= 3 && c > 0 && c < 3
                                                  ? 0.0f
                                                  : relief_raster_max_value(&a);
        save(argv[4], &a);
        relief_raster_free(&a);
        relief_raster_free(&m);
        return 0;
    }
    fprintf(stderr, "usage: see the comment at the top of tests/image/image_tool.c\n");
    return 2;
}
