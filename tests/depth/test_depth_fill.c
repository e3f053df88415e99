/* depth/transform.c, depth/depth_fill.c and image/pixel_synth.c: the Haar
 * step and its inverse (exact on a common grid), the membrane on a plane
 * (exact), ROF separating a step from a texture, a periodic depth texture
 * refilled exactly by the plain variant (both searches, rims blended), the
 * Poisson solve (exact on a paraboloid), the rim blend (a misplaced copy
 * of a ramp put back exactly; a rough slope's rim step cut, its texture
 * kept), the capture's
 * inside, the measures on hand-made values, bad parameters, and the real
 * office frame repaired by every variant. With "opencl": the scalar and
 * OpenCL scorers give the same bytes for every variant.
 *   test_depth_fill [opencl] DEPTH_DIR */
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "depth/depth_fill.h"
#include "depth/depth_io.h"
#include "depth/transform.h"
#include "image/patch.h"
#include "image/pixel_synth.h"

static uint32_t lcg(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}

static void test_haar(void)
{
    enum { W = 12, H = 8 };
    float z[W * H], ll[W * H / 4], det[3 * W * H / 4], back[W * H];
    uint32_t s = 7;
    double worst = 0.0;
    /* Integer millimetres as a 16-bit PNG holds them: exact. */
    for (int i = 0; i < W * H; ++i)
        z[i] = (float)(lcg(&s) % 65536u);
    relief_haar_forward(z, W, H, ll, det);
    relief_haar_inverse(ll, det, W, H, back);
    CHECK(memcmp(z, back, sizeof z) == 0, "Haar round trip of integer depths not exact");
    /* A hand-checked block: a b / c d = 1 2 / 3 5. */
    {
        float q[4] = {1, 2, 3, 5}, l, d[3];
        relief_haar_forward(q, 2, 2, &l, d);
        CHECK(l == 2.75f && d[0] == -0.75f && d[1] == -1.25f && d[2] == 0.25f,
              "Haar of 1 2 / 3 5: ll %g lh %g hl %g hh %g", l, d[0], d[1], d[2]);
    }
    /* Metres with full mantissas: within a float's rounding. */
    for (int i = 0; i < W * H; ++i)
        z[i] = 1.0f + (float)(lcg(&s) % 1000000u) * 3.1e-6f;
    relief_haar_forward(z, W, H, ll, det);
    relief_haar_inverse(ll, det, W, H, back);
    for (int i = 0; i < W * H; ++i)
        worst = fmax(worst, fabs((double)back[i] - z[i]) / fabs(z[i]));
    CHECK(worst <= 4.0 * 1.2e-7, "Haar round trip of metres: relative error %g", worst);
}

static void test_membrane(void)
{
    enum { W = 40, H = 30 };
    float z[W * H];
    uint8_t known[W * H];
    relief_error err = {0};
    int it = 0;
    double worst = 0.0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            int i = y * W + x, hole = (x - 20) * (x - 20) + (y - 14) * (y - 14) < 64 ||
                                      (x > 30 && y > 20);
            known[i] = (uint8_t)!hole;
            z[i] = hole ? 0.0f : 2.0f + 0.01f * x - 0.02f * y;
        }
    CHECK(relief_membrane_fill(z, known, W, H, 5000, &it, &err) == RELIEF_OK, "%s", err.message);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            worst = fmax(worst, fabs(z[y * W + x] - (2.0 + 0.01 * x - 0.02 * y)));
    /* The hole in the corner touches the border: Neumann there, and a
     * plane is harmonic but not Neumann, so only the disc is exact. */
    {
        double disc = 0.0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x)
                if ((x - 20) * (x - 20) + (y - 14) * (y - 14) < 64)
                    disc = fmax(disc, fabs(z[y * W + x] - (2.0 + 0.01 * x - 0.02 * y)));
        CHECK(disc < 1e-5, "membrane on a plane: error %g in the disc (%d iterations)", disc,
              it);
    }
    CHECK(worst < 0.2, "membrane: error %g", worst);
    /* A paraboloid (its discrete Laplacian is constant, so L L z = 0): the
     * thin plate fills a disc exactly, the harmonic membrane does not. */
    {
        double thin = 0.0, harm = 0.0;
        float z2[W * H];
        for (int pass = 0; pass < 2; ++pass) {
            float *zz = pass ? z2 : z;
            for (int y = 0; y < H; ++y)
                for (int x = 0; x < W; ++x) {
                    int i = y * W + x;
                    known[i] = (uint8_t)!((x - 20) * (x - 20) + (y - 14) * (y - 14) < 64);
                    zz[i] = known[i] ? (float)(0.001 * ((x - 20) * (x - 20) + (y - 14) * (y - 14)))
                                     : 0.0f;
                }
            if (pass)
                CHECK(relief_membrane_fill(zz, known, W, H, 5000, &it, &err) == RELIEF_OK, "%s",
                      err.message);
            else
                CHECK(relief_membrane_fill_biharmonic(zz, known, NULL, W, H, 5000, &it, &err) ==
                          RELIEF_OK, "%s", err.message);
        }
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                double t = 0.001 * ((x - 20) * (x - 20) + (y - 14) * (y - 14));
                thin = fmax(thin, fabs(z[y * W + x] - t));
                harm = fmax(harm, fabs(z2[y * W + x] - t));
            }
        CHECK(thin < 1e-5 && harm > 0.02, "paraboloid: thin plate error %g (%d iterations), "
              "harmonic %g", thin, it, harm);
    }
    memset(known, 0, sizeof known);
    CHECK(relief_membrane_fill(z, known, W, H, 100, NULL, &err) == RELIEF_E_RANGE,
          "membrane with nothing known accepted");
}

static void test_rof(void)
{
    enum { W = 64, H = 48 };
    static float f[W * H], u[W * H], v[W * H], tex[W * H];
    static uint8_t known[W * H];
    relief_error err = {0};
    double jump_u, cov = 0, vv = 0, tt = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            int i = y * W + x;
            tex[i] = 0.05f * (float)(((x / 2) + (y / 2)) % 2 ? 1 : -1); /* 2 px checks */
            f[i] = (x >= W / 2 ? 1.0f : 0.0f) + tex[i];
            known[i] = !(x > 5 && x < 12 && y > 5 && y < 12); /* a hole: a free boundary */
        }
    CHECK(relief_rof(f, known, W, H, 0.2, 300, 1, u, v, &err) == RELIEF_OK, "%s", err.message);
    /* On three threads (a share of rows each), the same bits. */
    {
        static float u3[W * H], v3[W * H];
        CHECK(relief_rof(f, known, W, H, 0.2, 300, 3, u3, v3, &err) == RELIEF_OK, "%s",
              err.message);
        CHECK(memcmp(u, u3, sizeof u) == 0 && memcmp(v, v3, sizeof v) == 0,
              "ROF on 3 threads differs from 1 thread");
    }
    /* u keeps the step (rows away from the top and bottom edges). */
    {
        double left = 0, right = 0;
        int m = 0;
        for (int y = 16; y < 32; ++y, ++m) {
            left += u[y * W + W / 2 - 4];
            right += u[y * W + W / 2 + 4];
        }
        jump_u = (right - left) / m;
    }
    for (int i = 0; i < W * H; ++i)
        if (known[i]) {
            cov += (double)v[i] * tex[i];
            vv += (double)v[i] * v[i];
            tt += (double)tex[i] * tex[i];
            CHECK(fabsf(u[i] + v[i] - f[i]) < 1e-6f, "u + v != f at %d", i);
        } else {
            CHECK(u[i] == 0.0f && v[i] == 0.0f, "a missing pixel got u %g v %g", u[i], v[i]);
        }
    CHECK(jump_u > 0.9, "ROF: u's step is %g of 1", jump_u);
    CHECK(cov / sqrt(vv * tt) > 0.9, "ROF: v's correlation with the texture %g",
          cov / sqrt(vv * tt));
}

/* A periodic depth texture (8 x 6 period) with a hole: the plain variant
 * finds the period and refills it exactly, with either search. */
static void test_periodic(relief_patch_scorer *sc)
{
    enum { W = 96, H = 72 };
    static float z[W * H], truth[W * H];
    static uint8_t missing[W * H];
    relief_error err = {0};
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            int i = y * W + x;
            truth[i] = 2.0f + 0.01f * (float)((x % 8) * 3 + (y % 6) * 7 % 11);
            missing[i] = x >= 40 && x < 55 && y >= 30 && y < 42;
            z[i] = missing[i] ? NAN : truth[i];
        }
    for (int exhaustive = 0; exhaustive <= 1; ++exhaustive) {
        relief_depth_repair_params p = relief_depth_repair_params_default();
        relief_depth_repair_report rep;
        relief_depth_measures m;
        float w[W * H];
        memcpy(w, z, sizeof w);
        p.variant = RELIEF_DEPTH_PLAIN;
        p.synth.exhaustive = exhaustive;
        CHECK(relief_depth_repair(w, missing, W, H, &p, sc, NULL, &rep, &err) == RELIEF_OK, "%s",
              err.message);
        relief_depth_measure(w, truth, missing, W, H, &m);
        CHECK(m.compared == 15 * 12 && m.rms == 0.0, "periodic, %s: RMS %g over %zu",
              exhaustive ? "exhaustive" : "pyramid", m.rms, m.compared);
        CHECK(rep.filled == 15 * 12 && rep.outside == 0 && rep.by_fallback == 0,
              "periodic: filled %zu outside %zu fallbacks %zu", rep.filled, rep.outside,
              rep.by_fallback);
    }
}

/* The Poisson solve: z = x^2 + y^2 has -L z = -4 everywhere, so with
 * the border known and -4 as the source the interior comes back exact. */
static void test_poisson(void)
{
    enum { W = 20, H = 16 };
    static float z[W * H], src[W * H];
    static uint8_t known[W * H];
    relief_error err = {0};
    double worst = 0.0;
    int it = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            int i = y * W + x;
            known[i] = x == 0 || y == 0 || x == W - 1 || y == H - 1;
            z[i] = known[i] ? (float)(x * x + y * y) : 0.0f;
            src[i] = -4.0f;
        }
    CHECK(relief_poisson_fill(z, known, NULL, src, W, H, 5000, &it, &err) == RELIEF_OK, "%s",
          err.message);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            worst = fmax(worst, fabs(z[y * W + x] - (double)(x * x + y * y)));
    CHECK(worst < 1e-3, "Poisson on a paraboloid: error %g (%d iterations)", worst, it);
    /* The same with the last three columns off the domain and NaN there:
     * never read (a NaN would spread through every unknown), never
     * written; column W - 4 is the border now. */
    {
        static uint8_t domain[W * H];
        worst = 0.0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                int i = y * W + x;
                domain[i] = x < W - 3;
                known[i] = x == 0 || y == 0 || x == W - 4 || y == H - 1;
                z[i] = !domain[i] ? NAN : known[i] ? (float)(x * x + y * y) : 0.0f;
            }
        CHECK(relief_poisson_fill(z, known, domain, src, W, H, 5000, &it, &err) == RELIEF_OK,
              "%s", err.message);
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                double e = domain[y * W + x] ? fabs(z[y * W + x] - (double)(x * x + y * y))
                                             : (isnan(z[y * W + x]) ? 0.0 : INFINITY);
                worst = fmax(worst, isnan(e) ? INFINITY : e);
            }
        CHECK(worst < 1e-3, "Poisson on a domain: error %g", worst);
        for (int i = 0; i < W * H; ++i)
            z[i] = !domain[i] ? NAN : known[i] ? z[i] : 0.0f;
        CHECK(relief_membrane_fill_biharmonic(z, known, domain, W, H, 5000, &it, &err) ==
                  RELIEF_OK && isfinite(z[(H / 2) * W + W / 2]) && isnan(z[W - 1]),
              "thin plate on a domain: %s", err.message);
    }
}

/* The rim blend. (1) A ramp whose hole got a copy of the ramp 15 pixels
 * to the right (a step of 0.75 at the rim): every prediction agrees with
 * the ramp, so the blend puts it back exactly. (2) A slope with rough
 * noise, a disc filled by the decompose variant with and without the blend:
 * the rim's slope jump falls, the texture inside stays rough. */
static void test_seam(relief_patch_scorer *sc)
{
    enum { W = 64, H = 48 };
    static float z[W * H], truth[W * H], a[W * H], b[W * H];
    static uint8_t missing[W * H], known[W * H];
    static int64_t src[W * H];
    relief_error err = {0};
    double worst = 0.0;
    size_t edges = 0;
    uint32_t seed = 7;
    for (int i = 0; i < W * H; ++i)
        truth[i] = 1.0f + 0.05f * (float)(i % W) + 0.02f * (float)(i / W);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            int i = y * W + x;
            missing[i] = x >= 10 && x < 20 && y >= 8 && y < 14;
            known[i] = !missing[i];
            src[i] = missing[i] ? (int64_t)i + 15 : -1;
            z[i] = missing[i] ? truth[i + 15] : truth[i];
        }
    CHECK(relief_depth_seam(NULL, z, known, missing, src, W, H, 5000, &edges, NULL, &err) ==
              RELIEF_OK, "%s", err.message);
    for (int i = 0; i < W * H; ++i)
        worst = fmax(worst, fabs((double)z[i] - truth[i]));
    CHECK(edges == 2 * 10 + 2 * 6 && worst < 1e-4, "seam on a ramp: %zu rim edges, error %g",
          edges, worst);

    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            int i = y * W + x;
            truth[i] = 2.0f + 0.03f * (float)x + 0.01f * (float)y +
                       0.004f * ((float)(lcg(&seed) % 1000) / 500.0f - 1.0f);
            missing[i] = (x - 30) * (x - 30) + (y - 24) * (y - 24) < 64;
            z[i] = missing[i] ? NAN : truth[i];
        }
    {
        relief_depth_repair_params p = relief_depth_repair_params_default();
        relief_depth_repair_report ra, rb;
        relief_depth_measures ma, mb;
        double rough_a = 0.0, rough_b = 0.0;
        size_t nr = 0;
        p.variant = RELIEF_DEPTH_DECOMPOSE;
        memcpy(a, z, sizeof a);
        memcpy(b, z, sizeof b);
        CHECK(relief_depth_repair(a, missing, W, H, &p, sc, NULL, &ra, &err) == RELIEF_OK, "%s",
              err.message);
        p.seam = 0;
        CHECK(relief_depth_repair(b, missing, W, H, &p, sc, NULL, &rb, &err) == RELIEF_OK, "%s",
              err.message);
        relief_depth_measure(a, truth, missing, W, H, &ma);
        relief_depth_measure(b, truth, missing, W, H, &mb);
        /* Roughness inside: mean |second difference| along rows over
         * triples wholly in the hole. */
        for (int y = 0; y < H; ++y)
            for (int x = 0; x + 2 < W; ++x) {
                int i = y * W + x;
                if (!missing[i] || !missing[i + 1] || !missing[i + 2])
                    continue;
                rough_a += fabs((double)a[i] - 2.0 * a[i + 1] + a[i + 2]);
                rough_b += fabs((double)b[i] - 2.0 * b[i + 1] + b[i + 2]);
                ++nr;
            }
        CHECK(ra.seam_edges > 0 && rb.seam_edges == 0, "seam edges %zu (off: %zu)",
              ra.seam_edges, rb.seam_edges);
        CHECK(ma.rim_jump < 0.8 * mb.rim_jump, "seam: rim jump %g, without %g", ma.rim_jump,
              mb.rim_jump);
        CHECK(nr > 0 && rough_a > 0.7 * rough_b, "seam: roughness inside %g, without %g",
              rough_a / (double)nr, rough_b / (double)nr);
        printf("rough slope: rim jump %.5f with the seam, %.5f without (capture %.5f); "
               "roughness inside %.5f, %.5f\n", ma.rim_jump, mb.rim_jump, ma.capture_jump,
               rough_a / (double)(nr ? nr : 1), rough_b / (double)(nr ? nr : 1));
    }
}

/* The tileable constraint: a periodic texture whose period divides the
 * image, a strip missing down its left border. Without it the strip is outside the
 * capture and stays; with it the torus is refilled exactly, so the result
 * tiles without a seam. */
static void test_tileable(relief_patch_scorer *sc)
{
    enum { W = 96, H = 72 };
    static float z[W * H], truth[W * H], w[W * H];
    static uint8_t missing[W * H];
    relief_error err = {0};
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            int i = y * W + x;
            truth[i] = 2.0f + 0.01f * (float)((x % 8) * 3 + (y % 6) * 7 % 11);
            missing[i] = x < 6; /* a strip down the left border */
            z[i] = missing[i] ? NAN : truth[i];
        }
    for (int tile = 0; tile <= 1; ++tile) {
        relief_depth_repair_params p = relief_depth_repair_params_default();
        relief_depth_repair_report rep;
        relief_depth_measures m;
        memcpy(w, z, sizeof w);
        p.variant = RELIEF_DEPTH_PLAIN;
        p.synth.tileable = tile;
        p.synth.exhaustive = 1;
        p.synth.search_radius = 0;
        if (tile) {
            CHECK(relief_depth_repair(w, missing, W, H, &p, sc, NULL, &rep, &err) == RELIEF_OK,
                  "%s", err.message);
            relief_depth_measure(w, truth, missing, W, H, &m);
            CHECK(rep.filled == 6 * H && m.compared == 6 * H && m.rms == 0.0,
                  "tileable: %zu filled, RMS %g over %zu", rep.filled, m.rms, m.compared);
        } else {
            CHECK(relief_depth_repair(w, missing, W, H, &p, sc, NULL, &rep, &err) ==
                          RELIEF_E_RANGE &&
                      strstr(err.message, "every border"),
                  "a hole at the border without --tileable: %s", err.message);
        }
    }
}

static void test_inside_and_measures(relief_patch_scorer *sc)
{
    enum { W = 10, H = 8 };
    uint8_t missing[W * H], inside[W * H];
    float z[W * H], truth[W * H];
    relief_depth_measures m;
    relief_error err = {0};
    /* A margin two pixels wide (outside) and one pixel in the middle. */
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            missing[y * W + x] = x < 2 || y < 2 || (x == 5 && y == 4);
    CHECK(relief_depth_inside(missing, W, H, inside) == 1 && inside[4 * W + 5] == 1,
          "inside: the margin is outside, the middle pixel inside");
    /* Only a margin: nothing to repair, refused. */
    missing[4 * W + 5] = 0;
    {
        relief_depth_repair_params p = relief_depth_repair_params_default();
        for (int i = 0; i < W * H; ++i)
            z[i] = missing[i] ? NAN : 1.0f;
        p.synth.window = 3;
        p.synth.search_radius = 2;
        CHECK(relief_depth_repair(z, missing, W, H, &p, sc, NULL, NULL, &err) == RELIEF_E_RANGE &&
                  strstr(err.message, "every border"),
              "a margin alone: %s", err.message);
        memset(missing, 1, sizeof missing);
        CHECK(relief_depth_repair(z, missing, W, H, &p, sc, NULL, NULL, &err) == RELIEF_E_RANGE &&
                  strstr(err.message, "every pixel"),
              "all missing: %s", err.message);
        memset(missing, 0, sizeof missing);
        p.synth.window = 4;
        CHECK(relief_depth_repair(z, missing, W, H, &p, sc, NULL, NULL, &err) == RELIEF_E_RANGE,
              "an even window accepted");
        p.synth.window = 11;
        CHECK(relief_depth_repair(z, missing, W, H, &p, sc, NULL, NULL, &err) == RELIEF_E_RANGE,
              "a window larger than the image accepted");
        p = relief_depth_repair_params_default();
        p.variant = RELIEF_DEPTH_HAAR;
        p.levels = 3;
        CHECK(relief_depth_repair(z, missing, W, H, &p, sc, NULL, NULL, &err) == RELIEF_E_RANGE &&
                  strstr(err.message, "levels 3 leaves"),
              "Haar levels leaving bands under the window: %s", err.message);
    }
    /* Measures: a row 1 2 3 [x] with x filled as 5 (truth 4): RMS 1, the
     * rim's second difference |(5 - 3) - (3 - 2)| = 1, the truth's 0. */
    {
        float zz[4] = {1, 2, 3, 5}, tt[4] = {1, 2, 3, 4};
        uint8_t mm[4] = {0, 0, 0, 1};
        relief_depth_measure(zz, tt, mm, 4, 1, &m);
        CHECK(m.compared == 1 && m.rms == 1.0 && m.rim_pairs == 1 && m.rim_jump == 1.0 &&
                  m.truth_jump == 0.0 && m.capture_jump == 0.0,
              "measures: compared %zu rms %g rim %zu jump %g truth %g capture %g", m.compared,
              m.rms, m.rim_pairs, m.rim_jump, m.truth_jump, m.capture_jump);
    }
    (void)truth;
}

/* A box 1.5 m away before a wall at 3 m (z^2 noise, a gentle slope), with
 * the camera's shadow beside the box (a band missing between them) and a
 * hole inside the box: layered, every shadow pixel continues the wall and
 * every box-hole pixel the box, in every variant; across (paper 003), the
 * shadow is a ramp from one to the other. */
enum { LW = 96, LH = 64 };

static void layered_frame(float *z, float *truth, uint8_t *missing)
{
    uint32_t s = 7;
    for (int y = 0; y < LH; ++y)
        for (int x = 0; x < LW; ++x) {
            int i = y * LW + x, box = x >= 24 && x < 52 && y >= 14 && y < 50;
            double base = box ? 1.5 : 3.0 + 0.002 * x;
            double noise = 0.003 * base * base * ((lcg(&s) % 2001) / 1000.0 - 1.0);
            truth[i] = (float)(base + noise);
            /* the shadow: 7 pixels right of the box; a hole in the box */
            missing[i] = (x >= 52 && x < 59 && y >= 14 && y < 50) ||
                         (x >= 32 && x < 40 && y >= 26 && y < 34);
            z[i] = missing[i] ? NAN : truth[i];
        }
}

static void layered_check(relief_patch_scorer *sc, relief_depth_variant v, int layered)
{
    static float z[LW * LH], truth[LW * LH];
    static uint8_t missing[LW * LH];
    relief_depth_repair_params p = relief_depth_repair_params_default();
    relief_depth_repair_report rep;
    relief_error err = {0};
    int shadow_off = 0, box_off = 0, ramp = 0;
    layered_frame(z, truth, missing);
    p.variant = v;
    p.levels = 1;
    p.layered = layered;
    CHECK(relief_depth_repair(z, missing, LW, LH, &p, sc, NULL, &rep, &err) == RELIEF_OK,
          "layered frame, variant %d: %s", (int)v, err.message);
    for (int i = 0; i < LW * LH; ++i) {
        int x = i % LW;
        if (!missing[i])
            continue;
        if (x >= 52) {
            shadow_off += fabs(z[i] - (3.0 + 0.002 * x)) > 0.1;
            ramp += fabs(z[i] - 1.5) > 0.3 && fabs(z[i] - 3.0 - 0.002 * x) > 0.3;
        } else {
            box_off += fabs(z[i] - 1.5) > 0.1;
        }
    }
    if (layered) {
        CHECK(rep.stepped_holes == 1 && rep.layer_passes == 1 && shadow_off == 0 &&
                  box_off == 0,
              "variant %d layered: %zu stepped holes, %d passes; %d shadow pixels off the "
              "wall, %d hole pixels off the box", (int)v, rep.stepped_holes, rep.layer_passes,
              shadow_off, box_off);
        CHECK(rep.layer_noise > 0.0005 && rep.layer_noise < 0.005,
              "the frame's noise measured %g (made 0.003 z^2, uniform)", rep.layer_noise);
    } else {
        CHECK(ramp > 20, "variant %d across: only %d shadow pixels on a ramp", (int)v, ramp);
    }
}

static void test_layers(relief_patch_scorer *sc)
{
    static float z[LW * LH], truth[LW * LH];
    static uint8_t missing[LW * LH], inside[LW * LH];
    relief_layer_params lp = relief_layer_params_default();
    relief_layers lay;
    relief_error err = {0};
    for (int v = RELIEF_DEPTH_PLAIN; v <= RELIEF_DEPTH_DECOMPOSE; ++v) {
        layered_check(sc, (relief_depth_variant)v, 1);
        layered_check(sc, (relief_depth_variant)v, 0);
    }
    /* The shadow's pixels all go to the wall (rank 0), its rim on the box
     * to rank 1; the box's own hole is no step. Disparities: the order
     * reversed (nearer is larger), the same ranks. */
    layered_frame(z, truth, missing);
    relief_depth_inside(missing, LW, LH, inside);
    for (int sign = 1; sign >= -1; sign -= 2) {
        int ok = 1;
        lp.far_sign = sign;
        for (int i = 0; i < LW * LH && sign < 0; ++i)
            z[i] = missing[i] ? NAN : 1.0f / truth[i];
        CHECK(relief_layers_find(z, missing, inside, LW, LH, &lp, &lay, &err) == RELIEF_OK,
              "layers: %s", err.message);
        for (int y = 14; y < 50; ++y) {
            ok = ok && lay.rank[y * LW + 55] == 0 && lay.rank[y * LW + 51] == 1 &&
                 lay.rank[y * LW + 59] == 0 && lay.rank[30 * LW + 35] == RELIEF_LAYER_NONE;
        }
        CHECK(ok && lay.ranks == 2 && lay.stepped_holes == 1 && lay.front_pixels == 0,
              "layers (far_sign %d): ranks %d, %zu stepped, %zu front pixels", sign, lay.ranks,
              lay.stepped_holes, lay.front_pixels);
        relief_layers_free(&lay);
    }
}

/* The office frame, holes cut in its valid parts, every variant: known
 * pixels keep their bits, every inside pixel is filled, the cut holes come
 * back within a few centimetres (RMS), and no fill strays outside the
 * frame's depth range. */
static void test_office(relief_patch_scorer *sc, const char *dir)
{
    char path[512];
    relief_depth_frame f;
    relief_error err = {0};
    snprintf(path, sizeof path, "%s/office1.pcd", dir);
    if (relief_depth_frame_read(path, 0, &f, &err) != RELIEF_OK) {
        CHECK(0, "%s", err.message);
        return;
    }
    {
        int W = f.width, H = f.height;
        size_t n = (size_t)W * H;
        uint8_t *missing = malloc(n);
        float *z = malloc(n * sizeof *z), lo = INFINITY, hi = -INFINITY;
        for (size_t i = 0; i < n; ++i) {
            int x = (int)(i % W), y = (int)(i / W);
            int cut = (x - 320) * (x - 320) + (y - 150) * (y - 150) < 400 ||
                      (x >= 430 && x < 470 && y >= 300 && y < 330);
            missing[i] = !isfinite(f.z[i]) || cut;
            if (isfinite(f.z[i])) {
                lo = fminf(lo, f.z[i]);
                hi = fmaxf(hi, f.z[i]);
            }
        }
        for (int variant = 0; variant < 3; ++variant) {
            relief_depth_repair_params p = relief_depth_repair_params_default();
            relief_depth_repair_report rep;
            relief_depth_measures m;
            size_t changed = 0, unfilled = 0, wild = 0;
            p.variant = (relief_depth_variant)variant;
            p.synth.order = RELIEF_ORDER_HORIZONTAL; /* one order: the suite's time */
            for (size_t i = 0; i < n; ++i)
                z[i] = missing[i] ? NAN : f.z[i];
            CHECK(relief_depth_repair(z, missing, W, H, &p, sc, NULL, &rep, &err) == RELIEF_OK,
                  "variant %d: %s", variant, err.message);
            relief_depth_measure(z, f.z, missing, W, H, &m);
            for (size_t i = 0; i < n; ++i) {
                if (!missing[i])
                    changed += memcmp(&z[i], &f.z[i], sizeof z[i]) != 0;
                else if (isnan(z[i]))
                    ++unfilled;
                else if (z[i] < lo - 0.5f || z[i] > hi + 0.5f)
                    ++wild;
            }
            CHECK(changed == 0, "variant %d changed %zu known pixels", variant, changed);
            CHECK(unfilled == rep.outside && rep.filled + rep.outside == rep.missing,
                  "variant %d: %zu left NaN, %zu outside", variant, unfilled, rep.outside);
            CHECK(wild == 0, "variant %d: %zu fills outside %g..%g m", variant, wild, lo, hi);
            CHECK(m.compared > 2000 && m.rms < 0.1, "variant %d: RMS %g m over %zu cut pixels",
                  variant, m.rms, m.compared);
            printf("office1, variant %d: %zu filled, %zu outside; RMS %.4f m over %zu cut "
                   "pixels, slope jump %.2f\n", variant, rep.filled, rep.outside, m.rms,
                   m.compared, m.rim_jump / m.capture_jump);
        }
        free(missing);
        free(z);
    }
    relief_depth_frame_free(&f);
}

/* The crop of the office frame both backend tests repair: its missing
 * pixels and a disc cut at (100, 70), into a and b alike. */
enum { CROP_X0 = 100, CROP_Y0 = 80, CROP_W = 200, CROP_H = 150 };
static void office_crop(const relief_depth_frame *f, float *a, float *b, uint8_t *missing)
{
    for (int y = 0; y < CROP_H; ++y)
        for (int x = 0; x < CROP_W; ++x) {
            float v = f->z[(size_t)(y + CROP_Y0) * f->width + x + CROP_X0];
            int i = y * CROP_W + x;
            missing[i] = !isfinite(v) || (x - 100) * (x - 100) + (y - 70) * (y - 70) < 300;
            a[i] = b[i] = missing[i] ? NAN : v;
        }
}

/* The host scorer (2 and 3 threads: both orders side by side, their
 * scorers sharing the threads; ROF's passes split by rows) against the
 * scalar reference, every variant, on a crop of the office frame. */
static void test_host(relief_patch_scorer *sc, const char *dir)
{
    relief_error err = {0};
    relief_depth_frame f;
    char path[512];
    enum { W = CROP_W, H = CROP_H };
    snprintf(path, sizeof path, "%s/office1.pcd", dir);
    if (relief_depth_frame_read(path, 0, &f, &err) != RELIEF_OK) {
        CHECK(0, "%s", err.message);
        return;
    }
    /* The sanitize pass (RELIEF_TEST_PASS=sanitize) runs 2 threads only. */
    int most = check_sanitize_pass() ? 2 : 3;
    for (int threads = 2; threads <= most; ++threads) {
        relief_patch_scorer *h = NULL;
        CHECK(relief_patch_host_create(threads, &h, &err) == RELIEF_OK, "%s", err.message);
        for (int variant = 0; variant < 3 && h; ++variant) {
            static float a[W * H], b[W * H];
            static uint8_t missing[W * H];
            relief_depth_repair_params p = relief_depth_repair_params_default();
            relief_depth_repair_report ra, rb;
            p.variant = (relief_depth_variant)variant;
            office_crop(&f, a, b, missing);
            CHECK(relief_depth_repair(a, missing, W, H, &p, sc, NULL, &ra, &err) == RELIEF_OK,
                  "scalar: %s", err.message);
            CHECK(relief_depth_repair(b, missing, W, H, &p, h, NULL, &rb, &err) == RELIEF_OK,
                  "host: %s", err.message);
            CHECK(memcmp(a, b, sizeof a) == 0 && ra.by_synthesis == rb.by_synthesis &&
                      ra.candidates == rb.candidates && ra.kept == rb.kept,
                  "variant %d on %d threads: the host scorer differs from the scalar one",
                  variant, threads);
        }
        relief_patch_scorer_destroy(h);
    }
    relief_depth_frame_free(&f);
}

/* A cancel while the two orders run side by side: the progress is told
 * on the caller's thread only, the call stops with RELIEF_E_CANCELLED. */
typedef struct cancel_probe {
    pthread_t caller;
    size_t calls, last, after;
    int elsewhere, backwards;
} cancel_probe;

static int cancel_after(void *ctx, size_t done, size_t total)
{
    cancel_probe *c = ctx;
    (void)total;
    c->elsewhere |= !pthread_equal(pthread_self(), c->caller);
    c->backwards |= done < c->last;
    c->last = done;
    ++c->calls;
    return done >= c->after;
}

static void test_host_cancel(void)
{
    enum { W = 96, H = 80 };
    relief_error err = {0};
    relief_patch_scorer *h = NULL;
    relief_raster img;
    static uint8_t hole[W * H];
    relief_pixsyn_params p = relief_pixsyn_params_default();
    cancel_probe c = {pthread_self(), 0, 0, 150, 0, 0};
    relief_status st;
    CHECK(relief_raster_create(W, H, 1, 0, &img, &err) == RELIEF_OK, "%s", err.message);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            img.v[y * W + x] = (float)((x * 7 + y * 3) % 11) / 11.0f;
            hole[y * W + x] = x > 30 && x < 60 && y > 25 && y < 55;
        }
    p.progress = cancel_after;
    p.progress_ctx = &c;
    CHECK(relief_patch_host_create(2, &h, &err) == RELIEF_OK, "%s", err.message);
    st = relief_pixsyn(&img, hole, NULL, &p, h, NULL, NULL, &err);
    CHECK(st == RELIEF_E_CANCELLED && strstr(err.message, "cancelled") != NULL,
          "cancel with both orders side by side: status %d, %s", (int)st, err.message);
    CHECK(c.calls > 0 && !c.elsewhere && !c.backwards,
          "progress: %zu calls, on another thread %d, backwards %d", c.calls, c.elsewhere,
          c.backwards);
    relief_patch_scorer_destroy(h);
    relief_raster_free(&img);
}

/* Scalar against OpenCL, every variant, on a crop of the office frame. */
static int test_opencl(const char *dir)
{
    relief_patch_scorer *sc = NULL, *cl = NULL;
    relief_error err = {0};
    relief_depth_frame f;
    char path[512];
    enum { W = CROP_W, H = CROP_H };
    if (relief_patch_opencl_create(-1, &cl, &err) != RELIEF_OK) {
        printf("no OpenCL device (%s): skipped\n", err.message);
        return 77;
    }
    relief_patch_scalar_create(&sc, &err);
    snprintf(path, sizeof path, "%s/office1.pcd", dir);
    if (relief_depth_frame_read(path, 0, &f, &err) != RELIEF_OK) {
        CHECK(0, "%s", err.message);
        relief_patch_scorer_destroy(sc);
        relief_patch_scorer_destroy(cl);
        return check_result();
    }
    for (int variant = 0; variant < 3; ++variant) {
        static float a[W * H], b[W * H];
        static uint8_t missing[W * H];
        relief_depth_repair_params p = relief_depth_repair_params_default();
        p.variant = (relief_depth_variant)variant;
        office_crop(&f, a, b, missing);
        CHECK(relief_depth_repair(a, missing, W, H, &p, sc, NULL, NULL, &err) == RELIEF_OK,
              "scalar: %s", err.message);
        CHECK(relief_depth_repair(b, missing, W, H, &p, cl, NULL, NULL, &err) == RELIEF_OK,
              "opencl: %s", err.message);
        CHECK(memcmp(a, b, sizeof a) == 0, "variant %d: the backends differ", variant);
    }
    relief_depth_frame_free(&f);
    relief_patch_scorer_destroy(sc);
    relief_patch_scorer_destroy(cl);
    return check_result();
}

int main(int argc, char **argv)
{
    relief_patch_scorer *sc = NULL;
    relief_error err = {0};
    const char *dir = argc > 1 ? argv[argc - 1] : "../shared/data/depth";
    if (argc > 1 && strcmp(argv[1], "opencl") == 0)
        return test_opencl(argc > 2 ? argv[2] : "../shared/data/depth");
    relief_patch_scalar_create(&sc, &err);
    test_haar();
    test_membrane();
    test_rof();
    test_periodic(sc);
    test_poisson();
    test_seam(sc);
    test_tileable(sc);
    test_inside_and_measures(sc);
    test_layers(sc);
    test_office(sc, dir);
    test_host(sc, dir);
    test_host_cancel();
    relief_patch_scorer_destroy(sc);
    return check_result();
}
