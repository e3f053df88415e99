/* OpenCL helpers shared by the host code: error names, device lookup.
 * Compiled only with RELIEF_HAVE_OPENCL; the functions in relief.h that
 * need OpenCL answer RELIEF_E_NOT_BUILT otherwise. */
#ifndef RELIEF_HOST_OCL_H
#define RELIEF_HOST_OCL_H

#ifdef RELIEF_HAVE_OPENCL
#include <CL/cl.h>

#include "relief/relief.h"

/* "CL_OUT_OF_RESOURCES" for -5, and so on; "CL_UNKNOWN_ERROR(<n>)" is not
 * returned: unknown codes give "unknown OpenCL error". */
const char *relief_cl_error_name(cl_int code);

/* The device numbered `index` as relief_devices numbers them; index -1:
 * the first GPU or accelerator, else device 0. *info describes it.
 * RELIEF_E_DEVICE when there is no device at all; RELIEF_E_RANGE naming
 * the valid numbers for an index there is none of. */
relief_status relief_cl_device(int index, cl_device_id *dev, relief_device_info *info,
                               relief_error *err);

/* Build a program from `n` sources for `dev` with `options`. On failure
 * RELIEF_E_DEVICE with the error's name, the options and the build log;
 * `origin` (may be "") is added to the message (where the sources came
 * from). */
relief_status relief_cl_build(cl_context ctx, cl_device_id dev, const char **src, cl_uint n,
                              const char *options, const char *origin, cl_program *out,
                              relief_error *err);
#endif

#endif
