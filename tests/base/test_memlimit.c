/* Memory limits: sizes parse and print, the estimates grow with the
 * problem and never wrap, relief_surface_build refuses a capture over the limit
 * before allocating it, and a device too small for the match data (in all,
 * or in its largest buffer) is refused naming both figures. */
#include <stdint.h>
#include <string.h>

#include "check.h"
#include "base/params.h"
#include "base/memlimit.h"
#include "match/device_memory.h"
#include "match/matcher.h"
#include "smooth/surface.h"

int main(void)
{
    static const struct {
        const char *text;
        uint64_t bytes;
    } good[] = {{"100000", 100000},
                {"512M", 512ull << 20},
                {"4G", 4ull << 30},
                {"4g", 4ull << 30},
                {"1.5G", 3ull << 29},
                {"2KiB", 2048},
                {"3MB", 3ull << 20},
                {"1T", 1ull << 40},
                {"7b", 7}};
    static const char *const bad[] = {"", "0", "-1", "x", "12Q", "1.5X", "4GG", "nan",
                                      "inf", "1e30T", "0.1"};
    relief_error err = {0};
    char buf[32];

    for (size_t i = 0; i < sizeof good / sizeof good[0]; ++i) {
        uint64_t v = 0;
        relief_status st = relief_parse_size(good[i].text, &v, &err);
        CHECK(st == RELIEF_OK && v == good[i].bytes, "'%s': %s, %llu (want %llu)",
              good[i].text, err.message, (unsigned long long)v,
              (unsigned long long)good[i].bytes);
    }
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        uint64_t v = 0;
        CHECK(relief_parse_size(bad[i], &v, &err) == RELIEF_E_USAGE &&
                  strstr(err.message, bad[i]),
              "'%s' accepted as %llu", bad[i], (unsigned long long)v);
    }
    relief_format_size(512ull << 20, buf, sizeof buf);
    CHECK(strcmp(buf, "512 MiB") == 0, "512M printed as '%s'", buf);
    relief_format_size(3ull << 29, buf, sizeof buf);
    CHECK(strcmp(buf, "1.50 GiB") == 0, "1.5G printed as '%s'", buf);
    relief_format_size(900, buf, sizeof buf);
    CHECK(strcmp(buf, "900 B") == 0, "900 printed as '%s'", buf);

    CHECK(relief_default_memory_limit() > 0 &&
              (relief_physical_memory() == 0 ||
               relief_default_memory_limit() <= relief_physical_memory()),
          "default limit %llu, physical %llu",
          (unsigned long long)relief_default_memory_limit(),
          (unsigned long long)relief_physical_memory());
    CHECK(relief_estimate_growth(2000, 4000, 1500, 4) > relief_estimate_growth(1000, 2000, 700, 4) &&
              relief_estimate_growth(1000, 2000, 700, 8) > relief_estimate_growth(1000, 2000, 700, 4),
          "the growth estimate does not grow with the problem");
    CHECK(relief_estimate_growth(SIZE_MAX, SIZE_MAX, SIZE_MAX, 64) == UINT64_MAX &&
              relief_estimate_smooth(SIZE_MAX) == UINT64_MAX &&
              relief_estimate_read(UINT64_MAX / 2) == UINT64_MAX &&
              relief_estimate_read(1000) == 16000,
          "the estimates wrap instead of saturating");
    CHECK(relief_memory_check("x", 10, 10, "", &err) == RELIEF_OK, "need == limit refused");
    CHECK(relief_memory_check("the thing", 3ull << 30, 1ull << 30, "; try less", &err) ==
                  RELIEF_E_NOMEM &&
              strstr(err.message, "the thing needs about 3.00 GiB") &&
              strstr(err.message, "physical memory); try less") &&
              strstr(err.message, "limit of 1.00 GiB"),
          "over the limit: %s", err.message);

    /* relief_surface_build, and the device check, on a small capture. */
    {
        relief_synth_params sp = relief_synth_params_default();
        relief_params p = relief_params_default();
        relief_mesh *cap = NULL;
        relief_surface *s = NULL;
        relief_match_data *d = NULL;
        sp.kind = RELIEF_SYNTH_PLANE_WAVES;
        sp.vertices = 500;
        CHECK(relief_synth(&sp, &cap, NULL, &err) == RELIEF_OK, "synth: %s", err.message);
        p.max_memory = 1 << 20;
        CHECK(cap && relief_surface_build(cap, &p, NULL, &s, &err) == RELIEF_E_NOMEM && !s &&
                  strstr(err.message, "over the limit of 1.00 MiB"),
              "smooth under a 1 MiB limit: %s", err.message);
        p.max_memory = 0;
        if (cap && relief_surface_build(cap, &p, NULL, &s, &err) == RELIEF_OK &&
            relief_match_data_build(s, 4, 1.0, &d, &err) == RELIEF_OK) {
            relief_device_info dev;
            uint64_t big = 0;
            const char *what = NULL;
            const uint64_t need = relief_estimate_device(d, &big, &what);
            memset(&dev, 0, sizeof dev);
            strcpy(dev.name, "tiny");
            CHECK(need > (uint64_t)d->nv * 40 && big > 0 && big < need && what && *what,
                  "device estimate %llu for %u vertices, largest %llu",
                  (unsigned long long)need, d->nv, (unsigned long long)big);
            dev.global_mem_bytes = need * 2;
            dev.max_alloc_bytes = need;
            CHECK(relief_device_fits(&dev, d, &err) == RELIEF_OK, "fits: %s", err.message);
            dev.global_mem_bytes = need; /* 90 % of it is usable */
            CHECK(relief_device_fits(&dev, d, &err) == RELIEF_E_NOMEM &&
                      strstr(err.message, "'tiny'") && strstr(err.message, "global memory"),
                  "too little global memory: %s", err.message);
            dev.global_mem_bytes = need * 2;
            dev.max_alloc_bytes = big - 1;
            CHECK(relief_device_fits(&dev, d, &err) == RELIEF_E_NOMEM &&
                      strstr(err.message, "CL_DEVICE_MAX_MEM_ALLOC_SIZE") &&
                      strstr(err.message, what),
                  "a buffer over the largest allocation: %s", err.message);
            dev.global_mem_bytes = 0; /* unknown: not checked */
            dev.max_alloc_bytes = 0;
            CHECK(relief_device_fits(&dev, d, &err) == RELIEF_OK, "unknown sizes refused");
        } else {
            CHECK(0, "smooth or match data: %s", err.message);
        }
        relief_match_data_destroy(d);
        relief_surface_destroy(s);
        relief_mesh_destroy(cap);
    }
    return check_result();
}
