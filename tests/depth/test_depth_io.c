/* depth/depth_io.c: the real frames of ../shared/data/depth (their sizes,
 * hole fractions and value ranges as SOURCE.txt states them), small PCDs
 * in each DATA kind and PFMs in each byte order written here with known
 * values, and every truncation and malformed header.
 *   test_depth_io DEPTH_DIR */
#include <lzf.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "check.h"
#include "depth/depth_io.h"

/* A 3 x 2 organised PCD, x y z rgb, in `kind`; pixel (1, 0) missing (NaN). */
static size_t make_pcd(const char *kind, uint8_t *out, size_t cap)
{
    static const float xyz[6][3] = {{0, 0, 1.0f}, {NAN, NAN, NAN}, {2, 0, 1.5f},
                                    {0, 1, 2.0f}, {1, 1, 2.5f}, {2, 1, 3.0f}};
    static const uint32_t rgb[6] = {0xff0000, 0x00ff00, 0x0000ff, 0x102030, 0x405060, 0x708090};
    int n = snprintf((char *)out, cap,
                     "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n"
                     "FIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F %s\nCOUNT 1 1 1 1\n"
                     "WIDTH 3\nHEIGHT 2\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 6\nDATA %s\n",
                     strcmp(kind, "ascii") == 0 ? "U" : "F", kind);
    size_t at = (size_t)n;
    if (strcmp(kind, "ascii") == 0) {
        for (int i = 0; i < 6; ++i)
            at += (size_t)snprintf((char *)out + at, cap - at, "%g %g %g %u\n", xyz[i][0],
                                   xyz[i][1], xyz[i][2], rgb[i]);
        return at;
    }
    if (strcmp(kind, "binary") == 0) {
        for (int i = 0; i < 6; ++i) {
            memcpy(out + at, xyz[i], 12);
            memcpy(out + at + 12, &rgb[i], 4);
            at += 16;
        }
        return at;
    }
    {
        uint8_t plain[96], packed[256];
        uint32_t u = 96, c;
        for (int i = 0; i < 6; ++i)
            for (int k = 0; k < 3; ++k)
                memcpy(plain + (k * 6 + i) * 4, &xyz[i][k], 4);
        for (int i = 0; i < 6; ++i)
            memcpy(plain + (3 * 6 + i) * 4, &rgb[i], 4);
        c = lzf_compress(plain, 96, packed, sizeof packed);
        memcpy(out + at, &c, 4);
        memcpy(out + at + 4, &u, 4);
        memcpy(out + at + 8, packed, c);
        return at + 8 + c;
    }
}

static void check_small(const relief_depth_frame *f, const char *what)
{
    CHECK(f->width == 3 && f->height == 2, "%s: %d x %d", what, f->width, f->height);
    CHECK(f->z[0] == 1.0f && isnan(f->z[1]) && f->z[2] == 1.5f && f->z[5] == 3.0f,
          "%s: z %g %g %g %g", what, f->z[0], f->z[1], f->z[2], f->z[5]);
    CHECK(f->xyz && f->xyz[4 * 3] == 1.0f && f->xyz[4 * 3 + 1] == 1.0f, "%s: xyz", what);
    CHECK(f->rgb && f->rgb[0] == 0xff && f->rgb[1] == 0 && f->rgb[5 * 3 + 2] == 0x90,
          "%s: rgb", what);
}

/* Decoding must fail, with a bad-input status naming the input. */
static void bad(relief_status (*decode)(const uint8_t *, size_t, const char *, uint64_t,
                                        relief_depth_frame *, relief_error *),
                const uint8_t *d, size_t n, const char *what)
{
    relief_depth_frame f;
    relief_error err = {0};
    relief_status st = decode(d, n, "x", 0, &f, &err);
    CHECK(st != RELIEF_OK, "%s (%zu bytes): decoded", what, n);
    CHECK(f.z == NULL && f.xyz == NULL && f.rgb == NULL, "%s: a frame left behind", what);
    CHECK(relief_status_exit_code(st) == 1 || st == RELIEF_E_NOMEM, "%s: %s: %s", what,
          relief_status_name(st), err.message);
    CHECK(strncmp(err.message, "x:", 2) == 0, "%s: '%s' does not name the input", what,
          err.message);
    if (st == RELIEF_OK)
        relief_depth_frame_free(&f);
}

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : "../shared/data/depth";
    static const char *kinds[] = {"ascii", "binary", "binary_compressed"};
    relief_error err = {0};
    relief_depth_frame f;
    uint8_t buf[4096];
    char path[1024];
    struct stat sb;

    for (int k = 0; k < 3; ++k) {
        size_t n = make_pcd(kinds[k], buf, sizeof buf);
        relief_status st = relief_pcd_decode(buf, n, "small", 0, &f, &err);
        CHECK(st == RELIEF_OK, "%s: %s", kinds[k], err.message);
        if (st == RELIEF_OK) {
            check_small(&f, kinds[k]);
            relief_depth_frame_free(&f);
        }
        /* Every truncation of the header and the data; ascii data cut
         * inside its last line may still read as numbers, so not there. */
        {
            size_t last = n - 1;
            while (k == 0 && last > 0 && buf[last - 1] != '\n')
                --last;
            for (size_t m = 0; m < (k == 0 ? last : n); ++m)
                bad(relief_pcd_decode, buf, m, kinds[k]);
        }
        /* Too small a pixel limit. */
        CHECK(relief_pcd_decode(buf, n, "small", 5, &f, &err) == RELIEF_E_NOMEM,
              "%s: limit: %s", kinds[k], err.message);
    }
    /* Malformed headers. */
    {
        static const char *headers[] = {
            "VERSION 0.7\nFIELDS x y z\nSIZE 4 4\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nDATA ascii\n1 2 3\n",
            "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F Q\nWIDTH 1\nHEIGHT 1\nDATA ascii\n1 2 3\n",
            "VERSION 0.7\nFIELDS x y w\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nDATA ascii\n1 2 3\n",
            "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 4\nHEIGHT 1\nDATA ascii\n1 2 3\n",
            "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nPOINTS 2\nDATA ascii\n1 2 3\n",
            "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nDATA lzma\n",
            "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nDATA ascii\n1 two 3\n",
            "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 0\nHEIGHT 0\nDATA ascii\n",
            "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 99999\nHEIGHT 2\nDATA binary\n",
            "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE U U U\nWIDTH 1\nHEIGHT 1\nDATA ascii\n1 2 3\n",
            "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nBOGUS 1\nDATA ascii\n1 2 3\n",
        };
        for (size_t i = 0; i < sizeof headers / sizeof headers[0]; ++i)
            bad(relief_pcd_decode, (const uint8_t *)headers[i], strlen(headers[i]), headers[i]);
    }
    /* Issue 40: a garbled key, TYPE or ascii value is quoted escaped
     * (printable ASCII, \xNN for the rest, 32 bytes at most, then "..."),
     * never as raw bytes. Before: the bytes as they were. */
    {
        static const struct { const char *pcd, *want; } garbled[] = {
            {"VERSION 0.7\nFI\x01\x1b[2J\xff\\S x y z\n",
             "unknown key 'FI\\x01\\x1b[2J\\xff\\\\S'"},
            {"VERSION 0.7\nKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKK\x07\n",
             "unknown key 'KKKKKKKKKKKKKKKKKKKKKKKKKKKKKKKK...'"},
            {"VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F \x80\n", "TYPE '\\x80'"},
            {"VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nHEIGHT 1\n"
             "DATA ascii\n1 \x7f\x01 3\n", "'\\x7f\\x01' is not a number"},
        };
        for (size_t i = 0; i < sizeof garbled / sizeof garbled[0]; ++i) {
            const char *g = garbled[i].pcd;
            bad(relief_pcd_decode, (const uint8_t *)g, strlen(g), garbled[i].want);
            relief_pcd_decode((const uint8_t *)g, strlen(g), "x", 0, &f, &err);
            CHECK(strstr(err.message, garbled[i].want) != NULL, "garbled %zu: '%s' lacks '%s'",
                  i, err.message, garbled[i].want);
            for (const char *c = err.message; *c; ++c)
                CHECK(*c >= 0x20 && *c < 0x7f, "garbled %zu: byte 0x%02x in the message", i,
                      (unsigned char)*c);
        }
    }
    /* An unorganised cloud is refused as a range image. */
    {
        const char *u = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 1\n"
                        "DATA ascii\n1 2 3\n4 5 6\n";
        CHECK(relief_pcd_decode((const uint8_t *)u, strlen(u), "u", 0, &f, &err) ==
                  RELIEF_E_FORMAT && strstr(err.message, "unorganised"),
              "unorganised: %s", err.message);
        /* ... and read as a WIDTH x 1 cloud by the point-set entry. */
        CHECK(relief_pcd_decode_cloud((const uint8_t *)u, strlen(u), "u", 0, &f, &err) ==
                  RELIEF_OK, "cloud: %s", err.message);
        if (f.z) {
            CHECK(f.width == 2 && f.height == 1 && f.xyz && f.xyz[3] == 4 && f.z[1] == 6,
                  "cloud: %d x %d", f.width, f.height);
            relief_depth_frame_free(&f);
        }
    }
    /* Clouds past the side limit: POINTS must agree with WIDTH, the data
     * must be there before the points are allocated (ascii too), and the
     * limits hold. */
    {
        static const char *clouds[] = {
            "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 100000\nHEIGHT 1\n"
            "POINTS 5\nDATA ascii\n1 2 3\n",
            "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 100000000\nHEIGHT 1\n"
            "DATA ascii\n1 2 3\n4 5 6\n",
            "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 100000000\nHEIGHT 1\n"
            "DATA binary\n",
            "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 100000001\nHEIGHT 1\n"
            "DATA binary\n",
        };
        for (size_t i = 0; i < sizeof clouds / sizeof clouds[0]; ++i)
            bad(relief_pcd_decode_cloud, (const uint8_t *)clouds[i], strlen(clouds[i]),
                clouds[i]);
        CHECK(relief_pcd_decode_cloud((const uint8_t *)clouds[0], strlen(clouds[0]), "w", 0,
                                      &f, &err) == RELIEF_E_PARSE &&
                  strstr(err.message, "POINTS 5"),
              "POINTS of a wide cloud unchecked: %s", err.message);
        /* Refused by its size, before 1e8 points are allocated. */
        CHECK(relief_pcd_decode_cloud((const uint8_t *)clouds[1], strlen(clouds[1]), "w", 0,
                                      &f, &err) == RELIEF_E_PARSE &&
                  strstr(err.message, "truncated") && strstr(err.message, "at least"),
              "a wide ascii cloud over 12 bytes: %s", err.message);
        CHECK(relief_pcd_decode_cloud((const uint8_t *)clouds[2], strlen(clouds[2]), "w", 1000,
                                      &f, &err) == RELIEF_E_NOMEM,
              "a cloud over max_points: %s", err.message);
    }
    /* PFM: both byte orders, rows bottom to top, +inf missing. */
    for (int little = 0; little <= 1; ++little) {
        float v[6] = {1, 2, 3, 4, INFINITY, 6}; /* rows bottom to top */
        int n = snprintf((char *)buf, sizeof buf, "Pf\n3 2\n%s\n", little ? "-1.0" : "1.0");
        for (int i = 0; i < 6; ++i) {
            uint32_t u;
            memcpy(&u, &v[i], 4);
            for (int b = 0; b < 4; ++b)
                buf[n + i * 4 + b] = (uint8_t)(little ? u >> (8 * b) : u >> (8 * (3 - b)));
        }
        CHECK(relief_pfm_decode(buf, (size_t)n + 24, "p", 0, &f, &err) == RELIEF_OK,
              "pfm: %s", err.message);
        if (f.z) {
            CHECK(f.z[0] == 4 && isnan(f.z[1]) && f.z[2] == 6 && f.z[3] == 1 && f.z[5] == 3,
                  "pfm %s: %g %g %g %g %g", little ? "little" : "big", f.z[0], f.z[1], f.z[2],
                  f.z[3], f.z[5]);
            relief_depth_frame_free(&f);
        }
        for (size_t m = 0; m < (size_t)n + 24; ++m)
            bad(relief_pfm_decode, buf, m, "a truncated PFM");
    }
    /* The writers: each kind written and read back, the same values and
     * colours; a PCD cannot be written from depths alone. */
    {
        size_t n = make_pcd("binary", buf, sizeof buf);
        relief_depth_frame g;
        CHECK(relief_pcd_decode(buf, n, "small", 0, &f, &err) == RELIEF_OK, "%s", err.message);
        for (int k = RELIEF_DEPTH_PFM; k <= RELIEF_DEPTH_PCD_COMPRESSED; ++k) {
            snprintf(path, sizeof path, "%s/w%d.%s", check_tmpdir(), k,
                     k == RELIEF_DEPTH_PFM ? "pfm" : "pcd");
            CHECK(relief_depth_frame_write(path, &f, (relief_depth_kind)k, &err) == RELIEF_OK,
                  "write kind %d: %s", k, err.message);
            if (relief_depth_frame_read(path, 0, &g, &err) != RELIEF_OK) {
                CHECK(0, "read back kind %d: %s", k, err.message);
                continue;
            }
            CHECK(g.format == (relief_depth_kind)k, "kind %d read as %d", k, (int)g.format);
            if (k == RELIEF_DEPTH_PFM) {
                CHECK(g.width == 3 && g.height == 2 && g.z[0] == 1.0f && isnan(g.z[1]) &&
                          g.z[5] == 3.0f,
                      "PFM round trip");
            } else {
                check_small(&g, "written PCD");
            }
            relief_depth_frame_free(&g);
            remove(path);
        }
        free(f.xyz);
        f.xyz = NULL;
        CHECK(relief_depth_frame_write("/tmp/never.pcd", &f, RELIEF_DEPTH_PCD_BINARY, &err) ==
                  RELIEF_E_RANGE, "a PCD without points written");
        CHECK(relief_depth_frame_write("/nonexistent-dir/x.pfm", &f, RELIEF_DEPTH_PFM, &err) ==
                  RELIEF_E_IO, "an unwritable path: %s", err.message);
        relief_depth_frame_free(&f);
    }
    bad(relief_pfm_decode, (const uint8_t *)"Pf\n3 2\n0\n", 9, "scale 0");
    bad(relief_pfm_decode, (const uint8_t *)"P6\n3 2\n255\n", 11, "a PPM");

    /* The real frames. */
    if (stat(dir, &sb) != 0) {
        printf("%s: not found; the real frames are skipped\n", dir);
        return check_result();
    }
    snprintf(path, sizeof path, "%s/office1.pcd", dir);
    if (relief_depth_frame_read(path, 0, &f, &err) == RELIEF_OK) {
        size_t miss = 0;
        float lo = INFINITY, hi = -INFINITY;
        for (size_t i = 0; i < 640 * 480; ++i)
            if (isnan(f.z[i]))
                ++miss;
            else
                lo = fminf(lo, f.z[i]), hi = fmaxf(hi, f.z[i]);
        printf("office1.pcd: %d x %d, %.1f %% missing, z %.3f..%.3f m\n", f.width, f.height,
               100.0 * miss / (640.0 * 480.0), lo, hi);
        CHECK(f.width == 640 && f.height == 480 && f.rgb, "office1: %d x %d", f.width, f.height);
        CHECK(miss > 0.12 * 640 * 480 && miss < 0.22 * 640 * 480, "office1: %zu missing", miss);
        CHECK(lo > 0.3f && hi < 10.0f, "office1: z %g..%g m", lo, hi);
        relief_depth_frame_free(&f);
    } else {
        CHECK(0, "%s", err.message);
    }
    snprintf(path, sizeof path, "%s/motorcycle_disp.pfm", dir);
    if (relief_depth_frame_read(path, 0, &f, &err) == RELIEF_OK) {
        size_t miss = 0;
        float lo = INFINITY, hi = -INFINITY;
        for (size_t i = 0; i < 741 * 500; ++i)
            if (isnan(f.z[i]))
                ++miss;
            else
                lo = fminf(lo, f.z[i]), hi = fmaxf(hi, f.z[i]);
        printf("motorcycle_disp.pfm: %d x %d, %.1f %% missing, %.1f..%.1f px\n", f.width,
               f.height, 100.0 * miss / (741.0 * 500.0), lo, hi);
        CHECK(f.width == 741 && f.height == 500, "motorcycle: %d x %d", f.width, f.height);
        CHECK(fabs(100.0 * miss / (741.0 * 500.0) - 7.3) < 0.1, "motorcycle: %zu missing", miss);
        CHECK(fabsf(lo - 7.2f) < 0.1f && fabsf(hi - 59.9f) < 0.1f, "motorcycle: %g..%g", lo, hi);
        relief_depth_frame_free(&f);
    } else {
        CHECK(0, "%s", err.message);
    }
    return check_result();
}
