/* A program outside relief's tree, built against an installed relief only
 * (its header and pkg-config, or its CMake package): it completes a mesh,
 * fills an image and repairs a depth image, and checks each did something.
 * Exit 0 when all three work. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <relief/relief.h>

static int fail(const char *what, const relief_error *err)
{
    fprintf(stderr, "consumer: %s: %s\n", what, err->message);
    return 1;
}

static int complete_mesh(void)
{
    relief_error err = {0};
    relief_synth_params sp = relief_synth_params_default();
    relief_complete_params p = relief_complete_params_default();
    relief_complete_report rep;
    relief_mesh *capture = NULL, *done = NULL;
    size_t added = 0;
    sp.kind = RELIEF_SYNTH_PLANE_WAVES;
    sp.vertices = 600;
    if (relief_synth(&sp, &capture, NULL, &err) != RELIEF_OK)
        return fail("synth", &err);
    p.run.backend = RELIEF_BACKEND_SCALAR;
    if (relief_complete(capture, &p, &done, &rep, &err) != RELIEF_OK) {
        relief_mesh_destroy(capture);
        return fail("complete", &err);
    }
    for (size_t v = 0; v < relief_mesh_vertex_count(done); ++v)
        added += relief_mesh_labels(done)[v] == RELIEF_LABEL_COMPLETED;
    printf("consumer: completed %zu vertices (%zu targets, %s)\n", added, rep.targets,
           rep.device);
    relief_complete_report_free(&rep);
    relief_mesh_destroy(done);
    relief_mesh_destroy(capture);
    return added > 0 ? 0 : 1;
}

static int fill_image(void)
{
    enum { W = 64, H = 48 };
    static uint8_t rgb[H][W][3], hole[H][W];
    relief_image img = {W, H, 3, 8, 0, rgb}, mask = {W, H, 1, 8, 0, hole};
    relief_image_fill_params p = relief_image_fill_params_default();
    relief_error err = {0};
    int bad = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            for (int c = 0; c < 3; ++c)
                rgb[y][x][c] = (uint8_t)(((x / 4 + y / 4) % 2) ? 200 : 40 + 20 * c);
            hole[y][x] = x >= 24 && x < 32 && y >= 20 && y < 28;
            if (hole[y][x])
                rgb[y][x][0] = rgb[y][x][1] = rgb[y][x][2] = 0;
        }
    p.window = 9;
    if (relief_image_fill(&img, &mask, &p, NULL, &err) != RELIEF_OK)
        return fail("image fill", &err);
    for (int y = 20; y < 28; ++y)
        for (int x = 24; x < 32; ++x)
            bad += rgb[y][x][0] == 0 && rgb[y][x][1] == 0;
    printf("consumer: image filled, %d hole pixels left black\n", bad);
    return bad == 0 ? 0 : 1;
}

static int repair_depth(void)
{
    enum { W = 40, H = 30 };
    static float z[H * W];
    relief_depth_image f;
    relief_depth_fill_params p = relief_depth_fill_params_default();
    relief_error err = {0};
    int left = 0;
    memset(&f, 0, sizeof f);
    f.width = W;
    f.height = H;
    f.z = z;
    f.format = RELIEF_DEPTH_PFM;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            z[y * W + x] = 1.0f + 0.01f * (float)x + 0.02f * sinf(0.9f * (float)y);
            if (x >= 15 && x < 21 && y >= 10 && y < 16)
                z[y * W + x] = NAN;
        }
    p.window = 5;
    if (relief_depth_fill(&f, NULL, &p, NULL, &err) != RELIEF_OK)
        return fail("depth fill", &err);
    for (int i = 0; i < W * H; ++i)
        left += !isfinite(z[i]);
    printf("consumer: depth repaired, %d pixels still missing\n", left);
    return left == 0 ? 0 : 1;
}

int main(void)
{
    int rc = complete_mesh();
    rc |= fill_image();
    rc |= repair_depth();
    printf("consumer: relief %s: %s\n", relief_version(), rc ? "FAILED" : "ok");
    return rc;
}
