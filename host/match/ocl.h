/* OpenCL helpers shared by the host code: error names, device lookup.
 * Compiled only with RELIEF_HAVE_OPENCL; the functions in relief.h that
 * need OpenCL answer RELIEF_E_NOT_BUILT otherwise. */
#ifndef RELIEF_HOST_OCL_H
#define RELIEF_HOST_OCL_H

#ifdef RELIEF_HAVE_OPENCL
#include <CL/cl.h>

/* "CL_OUT_OF_RESOURCES" for -5, and so on; "CL_UNKNOWN_ERROR(<n>)" is not
 * returned: unknown codes give "unknown OpenCL error". */
const char *relief_cl_error_name(cl_int code);
#endif

#endif
