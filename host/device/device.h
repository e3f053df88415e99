/* Which OpenCL device a backend runs on: the rule every engine's `auto`
 * follows (match/, image/, points/). An OpenCL device on the CPU runs its
 * kernel on the host's own cores, measured no faster than relief's host
 * code (bench/run.sh, bench/image_fill.sh), so auto takes OpenCL only on a
 * GPU or an accelerator, or on the device the caller names. */
#ifndef RELIEF_HOST_DEVICE_DEVICE_H
#define RELIEF_HOST_DEVICE_DEVICE_H

#include <stddef.h>

#include "relief/relief.h"

/* 1 when the device is a GPU or an accelerator. */
int relief_device_is_accelerator(const relief_device_info *info);

/* The index of the first GPU or accelerator among info[0 .. n), or -1. */
int relief_device_first_accelerator(const relief_device_info *info, size_t n);

#endif
