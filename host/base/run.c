/* What every engine call shares (relief_run_options, relief/relief.h). */
#include "relief/relief.h"

#include "base/error.h"

const char *relief_version(void)
{
    return RELIEF_VERSION_STRING;
}

relief_run_options relief_run_options_default(void)
{
    relief_run_options r;
    r.backend = RELIEF_BACKEND_AUTO;
    r.device = -1;
    r.max_memory = 0;
    r.progress = NULL;
    r.progress_ctx = NULL;
    r.input_name = NULL;
    r.output_name = NULL;
    r.threads = 0;
    return r;
}

relief_status relief_run_options_validate(const relief_run_options *run, relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    if (!run)
        return relief_fail(err, RELIEF_E_USAGE, "run options: NULL");
    if (run->backend < RELIEF_BACKEND_AUTO || run->backend > RELIEF_BACKEND_HOST)
        return relief_fail_param(err, RELIEF_E_RANGE, "backend", "backend %d is not one of "
                                 "auto, scalar, opencl, host", (int)run->backend);
    if (run->device < -1 || run->device > 255)
        return relief_fail_param(err, RELIEF_E_RANGE, "device", "device %d out of range: "
                                 "expected -1 (the first GPU or accelerator) or 0..255",
                                 run->device);
    if (run->threads < 0 || run->threads > RELIEF_THREADS_MAX)
        return relief_fail_param(err, RELIEF_E_RANGE, "threads", "threads %d out of range: "
                                 "expected 1..%d host threads, or 0 (the CPUs this thread may "
                                 "run on)", run->threads, RELIEF_THREADS_MAX);
    return RELIEF_OK;
}
