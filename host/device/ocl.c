#include "device/ocl.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "device/device.h"

#ifdef RELIEF_HAVE_OPENCL

const char *relief_cl_error_name(cl_int code)
{
    switch (code) {
#define E(x) \
    case x:  \
        return #x;
        E(CL_SUCCESS) E(CL_DEVICE_NOT_FOUND) E(CL_DEVICE_NOT_AVAILABLE)
        E(CL_COMPILER_NOT_AVAILABLE) E(CL_MEM_OBJECT_ALLOCATION_FAILURE)
        E(CL_OUT_OF_RESOURCES) E(CL_OUT_OF_HOST_MEMORY)
        E(CL_PROFILING_INFO_NOT_AVAILABLE) E(CL_MEM_COPY_OVERLAP) E(CL_IMAGE_FORMAT_MISMATCH)
        E(CL_IMAGE_FORMAT_NOT_SUPPORTED) E(CL_BUILD_PROGRAM_FAILURE) E(CL_MAP_FAILURE)
        E(CL_MISALIGNED_SUB_BUFFER_OFFSET) E(CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST)
        E(CL_COMPILE_PROGRAM_FAILURE) E(CL_LINKER_NOT_AVAILABLE) E(CL_LINK_PROGRAM_FAILURE)
        E(CL_DEVICE_PARTITION_FAILED) E(CL_KERNEL_ARG_INFO_NOT_AVAILABLE)
        E(CL_INVALID_VALUE) E(CL_INVALID_DEVICE_TYPE) E(CL_INVALID_PLATFORM)
        E(CL_INVALID_DEVICE) E(CL_INVALID_CONTEXT) E(CL_INVALID_QUEUE_PROPERTIES)
        E(CL_INVALID_COMMAND_QUEUE) E(CL_INVALID_HOST_PTR) E(CL_INVALID_MEM_OBJECT)
        E(CL_INVALID_IMAGE_FORMAT_DESCRIPTOR) E(CL_INVALID_IMAGE_SIZE) E(CL_INVALID_SAMPLER)
        E(CL_INVALID_BINARY) E(CL_INVALID_BUILD_OPTIONS) E(CL_INVALID_PROGRAM)
        E(CL_INVALID_PROGRAM_EXECUTABLE) E(CL_INVALID_KERNEL_NAME)
        E(CL_INVALID_KERNEL_DEFINITION) E(CL_INVALID_KERNEL) E(CL_INVALID_ARG_INDEX)
        E(CL_INVALID_ARG_VALUE) E(CL_INVALID_ARG_SIZE) E(CL_INVALID_KERNEL_ARGS)
        E(CL_INVALID_WORK_DIMENSION) E(CL_INVALID_WORK_GROUP_SIZE)
        E(CL_INVALID_WORK_ITEM_SIZE) E(CL_INVALID_GLOBAL_OFFSET) E(CL_INVALID_EVENT_WAIT_LIST)
        E(CL_INVALID_EVENT) E(CL_INVALID_OPERATION) E(CL_INVALID_GL_OBJECT)
        E(CL_INVALID_BUFFER_SIZE) E(CL_INVALID_MIP_LEVEL) E(CL_INVALID_GLOBAL_WORK_SIZE)
        E(CL_INVALID_PROPERTY) E(CL_INVALID_IMAGE_DESCRIPTOR) E(CL_INVALID_COMPILER_OPTIONS)
        E(CL_INVALID_LINKER_OPTIONS) E(CL_INVALID_DEVICE_PARTITION_COUNT)
#undef E
    case -1001:
        return "CL_PLATFORM_NOT_FOUND_KHR";
    }
    return "unknown OpenCL error";
}

/* A device string, cut to `cap` (drivers' version strings can be long). */
static void device_string(cl_device_id d, cl_device_info what, char *buf, size_t cap)
{
    char full[1024];
    if (clGetDeviceInfo(d, what, sizeof full, full, NULL) != CL_SUCCESS)
        snprintf(full, sizeof full, "?");
    full[sizeof full - 1] = '\0';
    /* Truncation is intended: cut at cap - 1 and terminate. */
    memcpy(buf, full, cap - 1);
    buf[cap - 1] = '\0';
}

relief_status relief_devices(relief_device_info *out, size_t cap, size_t *count,
                             relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    cl_platform_id plats[16];
    cl_uint np = 0;
    cl_int rc;
    size_t n = 0;

    if (!count || (!out && cap))
        return relief_fail(err, RELIEF_E_USAGE, "relief_devices: %s is NULL",
                           count ? "out (with cap > 0)" : "count");
    *count = 0;
    rc = clGetPlatformIDs(16, plats, &np);
    if (rc == -1001 /* CL_PLATFORM_NOT_FOUND_KHR: the ICD loader found none */ ||
        (rc == CL_SUCCESS && np == 0))
        return RELIEF_OK;
    if (rc != CL_SUCCESS)
        return relief_fail(err, RELIEF_E_DEVICE, "clGetPlatformIDs failed: %s",
                           relief_cl_error_name(rc));
    for (cl_uint p = 0; p < np && p < 16; ++p) {
        cl_device_id devs[32];
        cl_uint nd = 0;
        char pname[128];
        if (clGetPlatformInfo(plats[p], CL_PLATFORM_NAME, sizeof pname, pname, NULL) !=
            CL_SUCCESS)
            snprintf(pname, sizeof pname, "?");
        pname[sizeof pname - 1] = '\0';
        rc = clGetDeviceIDs(plats[p], CL_DEVICE_TYPE_ALL, 32, devs, &nd);
        if (rc == CL_DEVICE_NOT_FOUND)
            continue;
        if (rc != CL_SUCCESS)
            return relief_fail(err, RELIEF_E_DEVICE,
                               "clGetDeviceIDs on platform '%s' failed: %s", pname,
                               relief_cl_error_name(rc));
        for (cl_uint d = 0; d < nd && d < 32; ++d, ++n) {
            relief_device_info *i;
            cl_device_type type = 0;
            cl_uint cu = 0;
            cl_ulong mem = 0, alloc = 0;
            if (n >= cap)
                continue;
            i = &out[n];
            memset(i, 0, sizeof *i);
            i->index = (int)n;
            snprintf(i->platform, sizeof i->platform, "%s", pname);
            device_string(devs[d], CL_DEVICE_NAME, i->name, sizeof i->name);
            device_string(devs[d], CL_DEVICE_VERSION, i->version, sizeof i->version);
            device_string(devs[d], CL_DRIVER_VERSION, i->driver, sizeof i->driver);
            clGetDeviceInfo(devs[d], CL_DEVICE_TYPE, sizeof type, &type, NULL);
            clGetDeviceInfo(devs[d], CL_DEVICE_MAX_COMPUTE_UNITS, sizeof cu, &cu, NULL);
            clGetDeviceInfo(devs[d], CL_DEVICE_GLOBAL_MEM_SIZE, sizeof mem, &mem, NULL);
            clGetDeviceInfo(devs[d], CL_DEVICE_MAX_MEM_ALLOC_SIZE, sizeof alloc, &alloc, NULL);
            snprintf(i->type, sizeof i->type, "%s",
                     (type & CL_DEVICE_TYPE_GPU)           ? "gpu"
                     : (type & CL_DEVICE_TYPE_CPU)         ? "cpu"
                     : (type & CL_DEVICE_TYPE_ACCELERATOR) ? "accelerator"
                                                           : "other");
            i->compute_units = cu;
            i->global_mem_bytes = mem;
            i->max_alloc_bytes = alloc;
        }
    }
    *count = n;
    return RELIEF_OK;
}

relief_status relief_cl_device(int index, cl_device_id *dev, relief_device_info *info,
                               relief_error *err)
{
    relief_device_info all[64];
    cl_platform_id plats[16];
    cl_uint np = 0;
    size_t n = 0, want = 0, seen = 0;
    relief_status st = relief_devices(all, 64, &n, err);

    *dev = NULL;
    if (st != RELIEF_OK)
        return st;
    if (n > 64)
        n = 64;
    if (n == 0)
        return relief_fail(err, RELIEF_E_DEVICE, "no OpenCL platform or device found");
    if (index >= 0 && (size_t)index >= n)
        return relief_fail(err, RELIEF_E_RANGE,
                           "device %d: there are %zu OpenCL device(s), 0..%zu (see 'relief "
                           "devices')", index, n, n - 1);
    if (index >= 0)
        want = (size_t)index;
    else if (relief_device_first_accelerator(all, n) >= 0)
        want = (size_t)relief_device_first_accelerator(all, n);
    /* Walk the platforms in relief_devices' order to the wanted device. */
    clGetPlatformIDs(16, plats, &np);
    for (cl_uint p = 0; p < np && p < 16 && !*dev; ++p) {
        cl_device_id devs[32];
        cl_uint nd = 0;
        if (clGetDeviceIDs(plats[p], CL_DEVICE_TYPE_ALL, 32, devs, &nd) != CL_SUCCESS)
            continue;
        for (cl_uint i = 0; i < nd && i < 32 && !*dev; ++i, ++seen)
            if (seen == want)
                *dev = devs[i];
    }
    if (!*dev)
        return relief_fail(err, RELIEF_E_DEVICE, "OpenCL device %zu disappeared", want);
    *info = all[want];
    return RELIEF_OK;
}

relief_status relief_cl_build(cl_context ctx, cl_device_id dev, const char **src, cl_uint n,
                              const char *options, const char *origin, cl_program *out,
                              relief_error *err)
{
    cl_int rc;
    size_t loglen = 0;
    char *log;
    relief_status st;

    *out = clCreateProgramWithSource(ctx, n, src, NULL, &rc);
    if (rc != CL_SUCCESS)
        return relief_fail(err, RELIEF_E_DEVICE, "clCreateProgramWithSource: %s",
                           relief_cl_error_name(rc));
    rc = clBuildProgram(*out, 1, &dev, options, NULL, NULL);
    if (rc == CL_SUCCESS)
        return RELIEF_OK;
    clGetProgramBuildInfo(*out, dev, CL_PROGRAM_BUILD_LOG, 0, NULL, &loglen);
    log = malloc(loglen + 1);
    if (log) {
        clGetProgramBuildInfo(*out, dev, CL_PROGRAM_BUILD_LOG, loglen, log, NULL);
        log[loglen] = '\0';
    }
    st = relief_fail(err, RELIEF_E_DEVICE,
                     "the OpenCL kernel failed to build (%s), options '%s'%s; build log:\n%s",
                     relief_cl_error_name(rc), options, origin, log ? log : "(none)");
    free(log);
    clReleaseProgram(*out);
    *out = NULL;
    return st;
}

#else /* !RELIEF_HAVE_OPENCL */

relief_status relief_devices(relief_device_info *out, size_t cap, size_t *count,
                             relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    if (!count || (!out && cap))
        return relief_fail(err, RELIEF_E_USAGE, "relief_devices: %s is NULL",
                           count ? "out (with cap > 0)" : "count");
    *count = 0;
    return relief_fail(err, RELIEF_E_NOT_BUILT,
                       "relief was built without OpenCL (RELIEF_WITH_OPENCL=OFF)");
}

#endif
