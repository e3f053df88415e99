/* Small depth chores for the depth-fill CLI test (test_depth_fill.sh):
 *   depth_tool crop IN X Y W H OUT [KIND]   a crop of IN (PCD or PFM), written as OUT's
 *                                           kind (.pfm, or .pcd: binary, or KIND:
 *                                           pcd-ascii, pcd-binary, pcd-compressed)
 *   depth_tool ring W H OUT.pfm             a tilted plane whose 2-pixel margin is
 *                                           missing (+inf), and nothing else
 *   depth_tool png16 IN SCALE OUT.png       IN's depths x SCALE as a 16-bit PNG (0 missing)
 *   depth_tool same A B [MASK]              exit 0 when every finite depth of A (outside
 *                                           MASK's non-zero pixels) has the same bits in
 *                                           B; prints how many of A's missing pixels B
 *                                           fills and leaves missing */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "depth/depth_io.h"
#include "image/image_io.h"

static relief_depth_frame load(const char *path)
{
    relief_depth_frame f;
    relief_error err = {0};
    size_t len = strlen(path);
    if (len > 4 && strcmp(path + len - 4, ".png") == 0) {
        relief_raster r;
        if (relief_raster_read(path, NULL, &r, &err) != RELIEF_OK) {
            fprintf(stderr, "depth_tool: %s\n", err.message);
            exit(2);
        }
        memset(&f, 0, sizeof f);
        f.width = r.width;
        f.height = r.height;
        f.z = malloc((size_t)r.width * r.height * sizeof *f.z);
        for (size_t i = 0; i < (size_t)r.width * r.height; ++i)
            f.z[i] = r.v[i * r.channels] > 0 ? r.v[i * r.channels] : NAN;
        relief_raster_free(&r);
        return f;
    }
    if (relief_depth_frame_read(path, 0, &f, &err) != RELIEF_OK) {
        fprintf(stderr, "depth_tool: %s\n", err.message);
        exit(2);
    }
    return f;
}

static void save(const char *path, const relief_depth_frame *f, const char *kind)
{
    relief_error err = {0};
    size_t len = strlen(path);
    relief_depth_kind k = len > 4 && strcmp(path + len - 4, ".pcd") == 0
                              ? RELIEF_DEPTH_PCD_BINARY
                              : RELIEF_DEPTH_PFM;
    if (kind && strcmp(kind, "pcd-ascii") == 0)
        k = RELIEF_DEPTH_PCD_ASCII;
    else if (kind && strcmp(kind, "pcd-compressed") == 0)
        k = RELIEF_DEPTH_PCD_COMPRESSED;
    if (relief_depth_frame_write(path, f, k, &err) != RELIEF_OK) {
        fprintf(stderr, "depth_tool: %s\n", err.message);
        exit(2);
    }
}

int main(int argc, char **argv)
{
    if ((argc == 8 || argc == 9) && strcmp(argv[1], "crop") == 0) {
        relief_depth_frame f = load(argv[2]), c;
        int x0 = atoi(argv[3]), y0 = atoi(argv[4]), w = atoi(argv[5]), h = atoi(argv[6]);
        memset(&c, 0, sizeof c);
        c.width = w;
        c.height = h;
        c.z = malloc((size_t)w * h * sizeof *c.z);
        c.xyz = f.xyz ? malloc((size_t)w * h * 3 * sizeof *c.xyz) : NULL;
        c.rgb = f.rgb ? malloc((size_t)w * h * 3) : NULL;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                size_t s = (size_t)(y + y0) * f.width + x + x0, o = (size_t)y * w + x;
                c.z[o] = f.z[s];
                if (c.xyz)
                    memcpy(c.xyz + 3 * o, f.xyz + 3 * s, 3 * sizeof *c.xyz);
                if (c.rgb)
                    memcpy(c.rgb + 3 * o, f.rgb + 3 * s, 3);
            }
        save(argv[7], &c, argc == 9 ? argv[8] : NULL);
        relief_depth_frame_free(&f);
        relief_depth_frame_free(&c);
        return 0;
    }
    if (argc == 5 && strcmp(argv[1], "ring") == 0) {
        relief_depth_frame f;
        int w = atoi(argv[2]), h = atoi(argv[3]);
        memset(&f, 0, sizeof f);
        f.width = w;
        f.height = h;
        f.z = malloc((size_t)w * h * sizeof *f.z);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                f.z[(size_t)y * w + x] = x < 2 || y < 2 || x >= w - 2 || y >= h - 2
                                             ? NAN
                                             : 20.0f + 0.1f * x + 0.05f * y;
        save(argv[4], &f, NULL);
        relief_depth_frame_free(&f);
        return 0;
    }
    if (argc == 5 && strcmp(argv[1], "png16") == 0) {
        relief_depth_frame f = load(argv[2]);
        relief_raster r;
        relief_error err = {0};
        double scale = atof(argv[3]);
        relief_raster_create(f.width, f.height, 1, 16, &r, &err);
        for (size_t i = 0; i < (size_t)f.width * f.height; ++i)
            r.v[i] = isfinite(f.z[i]) ? (float)fmin(65535.0, floor(f.z[i] * scale + 0.5)) : 0.0f;
        if (relief_raster_write(argv[4], &r, &err) != RELIEF_OK) {
            fprintf(stderr, "depth_tool: %s\n", err.message);
            return 2;
        }
        relief_raster_free(&r);
        relief_depth_frame_free(&f);
        return 0;
    }
    if ((argc == 4 || argc == 5) && strcmp(argv[1], "same") == 0) {
        relief_depth_frame a = load(argv[2]), b = load(argv[3]);
        relief_raster m = {0, 0, 0, 0, NULL};
        relief_error err = {0};
        size_t differ = 0, filled = 0, left = 0;
        if (argc == 5 && relief_raster_read(argv[4], NULL, &m, &err) != RELIEF_OK) {
            fprintf(stderr, "depth_tool: %s\n", err.message);
            return 2;
        }
        if (a.width != b.width || a.height != b.height) {
            fprintf(stderr, "depth_tool: sizes differ\n");
            return 1;
        }
        for (size_t i = 0; i < (size_t)a.width * a.height; ++i) {
            if (m.v && m.v[i * m.channels] != 0.0f)
                continue;
            if (isfinite(a.z[i]))
                differ += memcmp(&a.z[i], &b.z[i], sizeof a.z[i]) != 0;
            else if (isfinite(b.z[i]))
                ++filled;
            else
                ++left;
        }
        printf("%zu known differ, %zu filled, %zu left missing\n", differ, filled, left);
        relief_depth_frame_free(&a);
        relief_depth_frame_free(&b);
        relief_raster_free(&m);
        return differ ? 1 : 0;
    }
    fprintf(stderr, "usage: see depth_tool.c\n");
    return 2;
}
