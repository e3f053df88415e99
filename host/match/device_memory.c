/* What the OpenCL matcher's buffers take on a device (device_memory.h). */
#include "match/device_memory.h"

#include "base/error.h"
#include "base/memlimit.h"

uint64_t relief_estimate_device(const relief_match_data *d, uint64_t *largest,
                                const char **largest_what)
{
    const uint64_t nv = d->nv, nt = d->nt, ns = d->ns, r = (uint64_t)d->rotations;
    const uint64_t cells = (uint64_t)d->dims[0] * d->dims[1] * d->dims[2] + 1;
    const struct {
        const char *what;
        uint64_t bytes;
    } buf[] = {
        {"projected positions", nv * 12}, {"positions", nv * 12},
        {"colours", nv * 12},             {"labels", nv},
        {"triangles", nt * 12},           {"vertex-triangle lists", (nv + 1) * 4},
        {"vertex-triangle lists", (uint64_t)d->vt_start[d->nv] * 4},
        {"the grid", cells * 4},          {"the grid", nv * 4},
        {"the closest-vertex lists", ((uint64_t)d->lmask + 1) * 12},
        {"the closest-vertex lists", (uint64_t)d->n_litems * 4},
        {"sample positions", ns * 12},    {"sample frames", ns * 36},
        {"rotations", r * 8},             {"scores", ns * r * 4},
        {"scores", ns * r},               {"candidate subsets", ns * 4},
        {"the closest-vertex lists", ((uint64_t)d->lmask + 1) * 12},
        {"the closest-vertex lists", (d->n_litems ? (uint64_t)d->n_litems : 1) * 4},
    };
    uint64_t total = 0, big = 0;
    const char *big_what = "";
    for (size_t i = 0; i < sizeof buf / sizeof buf[0]; ++i) {
        total += buf[i].bytes;
        if (buf[i].bytes > big) {
            big = buf[i].bytes;
            big_what = buf[i].what;
        }
    }
    if (largest)
        *largest = big;
    if (largest_what)
        *largest_what = big_what;
    return total;
}

relief_status relief_device_fits(const relief_device_info *dev, const relief_match_data *d,
                                 relief_error *err)
{
    uint64_t big = 0;
    const char *big_what = "";
    const uint64_t need = relief_estimate_device(d, &big, &big_what);
    /* Drivers keep part of global memory for themselves. */
    const uint64_t usable = dev->global_mem_bytes / 10 * 9;
    char a[32], b[32];
    if (dev->global_mem_bytes && need > usable) {
        relief_format_size(need, a, sizeof a);
        relief_format_size(dev->global_mem_bytes, b, sizeof b);
        return relief_fail(err, RELIEF_E_NOMEM,
                           "the surface needs about %s on the OpenCL device '%s', which has "
                           "%s of global memory (relief uses at most 90%%); use "
                           "backend scalar or another device",
                           a, dev->name, b);
    }
    if (dev->max_alloc_bytes && big > dev->max_alloc_bytes) {
        relief_format_size(big, a, sizeof a);
        relief_format_size(dev->max_alloc_bytes, b, sizeof b);
        return relief_fail(err, RELIEF_E_NOMEM,
                           "the buffer of %s needs %s on the OpenCL device '%s', over its "
                           "largest buffer (CL_DEVICE_MAX_MEM_ALLOC_SIZE) of %s; use "
                           "backend scalar or another device",
                           big_what, a, dev->name, b);
    }
    return RELIEF_OK;
}
