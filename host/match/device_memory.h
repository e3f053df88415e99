/* Device memory: the exact sizes of the buffers the OpenCL matcher uploads
 * for a surface, and whether they fit on a device, checked before anything
 * is uploaded (the host's limits are in base/memlimit.h). */
#ifndef RELIEF_HOST_DEVICE_MEMORY_H
#define RELIEF_HOST_DEVICE_MEMORY_H

#include <stdint.h>

#include "relief/relief.h"
#include "match/match_data.h"

/* Device bytes the OpenCL matcher allocates for `d`, in all and in its
 * largest single buffer (*largest_what names it). */
uint64_t relief_estimate_device(const relief_match_data *d, uint64_t *largest,
                                const char **largest_what);

/* Can `d` go on `dev`? RELIEF_E_NOMEM naming the device, the need and its
 * global memory (or the largest buffer and CL_DEVICE_MAX_MEM_ALLOC_SIZE)
 * when not. A device with 0 for a size is taken as unknown: not checked. */
relief_status relief_device_fits(const relief_device_info *dev, const relief_match_data *d,
                                 relief_error *err);

#endif
