/* Backend choice and the calls every backend goes through. */
#include "match/matcher.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/clock.h"
#include "base/error.h"
#include "device/cl_profile.h"
#include "device/device.h"
#include "match/device_memory.h"
#include "match/matcher_host.h"
#include "match/matcher_opencl.h"
#include "match/matcher_scalar.h"
#include "match/score_pool.h"

/* Refuse a device the surface cannot fit on before uploading anything. */
static relief_status device_fits(int device, const relief_match_data *d, relief_error *err)
{
    relief_device_info info[64];
    size_t n = 0, want = device < 0 ? 0 : (size_t)device;
    /* Enumeration failures are reported by relief_matcher_opencl_create. */
    if (relief_devices(info, 64, &n, NULL) != RELIEF_OK || want >= n || want >= 64)
        return RELIEF_OK;
    return relief_device_fits(&info[want], d, err);
}

/* auto, after a device failure: the host's threads from here on. */
static relief_status fall_back(relief_matcher *m, const relief_match_data *d,
                               const relief_error *why, relief_error *err)
{
    relief_matcher *sc = NULL;
    relief_status st = relief_matcher_host_create(d, relief_score_pool_threads_for(m->threads),
                                                  &sc, err);
    if (st != RELIEF_OK)
        return st;
    snprintf(m->fallback_note, sizeof m->fallback_note,
             "the OpenCL device failed during the run (%s); continued on the host "
             "matcher (%.60s) from there", why ? why->message : "no detail", sc->device);
    m->ops->destroy(m->ctx);
    m->ops = sc->ops;
    m->ctx = sc->ctx;
    m->backend = sc->backend;
    snprintf(m->device, sizeof m->device, "%s", sc->device);
    m->fallback = 0;
    m->inject = NULL; /* the hook stands for the device, which is gone */
    free(sc);
    relief_error_clear(err);
    return RELIEF_OK;
}

/* auto without --device: the index of the first GPU or accelerator among
 * the OpenCL devices, or -1 with the reason in why[] (and *code
 * RELIEF_REASON_DEVICE_FELL_BACK when OpenCL could not be asked). */
static int pick_device(char *why, size_t why_size, relief_reason *code)
{
    relief_device_info info[64];
    relief_error e = {0};
    size_t n = 0;
    int first;
    if (relief_devices(info, 64, &n, &e) != RELIEF_OK) {
        snprintf(why, why_size, RELIEF_MATCHER_UNAVAILABLE " (%s)", e.message);
        if (code)
            *code = RELIEF_REASON_DEVICE_FELL_BACK;
        return -1;
    }
    if (n == 0) {
        snprintf(why, why_size, RELIEF_MATCHER_UNAVAILABLE " (no OpenCL platform or device "
                 "found)");
        if (code)
            *code = RELIEF_REASON_DEVICE_FELL_BACK;
        return -1;
    }
    first = relief_device_first_accelerator(info, n < 64 ? n : 64);
    if (first >= 0)
        return first;
    snprintf(why, why_size, "no GPU or accelerator among the %zu OpenCL device%s (device 0: "
             "%.100s, a %s), whose kernel would run on the host's own cores, no faster "
             "than they score by themselves", n, n == 1 ? "" : "s", info[0].name, info[0].type);
    return -1;
}

/* auto without --device: is the work too small for any device to pay
 * off? The host scores about 3e6 candidates a thread-second (sphere-cap's
 * exhaustive growth, 12 912 576 candidates in 2.04 s on 2 threads), so
 * under RELIEF_MATCHER_DEVICE_MIN_WORK a thread its whole growth takes a
 * third of a second or less, about what a device costs before it scores
 * anything: OpenCL's platforms asked (25 ms for PoCL alone here), a
 * context, the program from its cache and the surface uploaded, then a
 * launch and a read-back per query. Then the device is not asked for, and
 * why[] says so. */
static int too_small(double work, int host_threads, char *why, size_t why_size)
{
    const double bound = RELIEF_MATCHER_DEVICE_MIN_WORK * host_threads;
    if (!(work > 0.0) || work >= bound)
        return 0;
    snprintf(why, why_size, "about %.2g candidates to score, under the %.2g that %d host "
             "thread%s in about a third of a second, too few for a device to pay off its "
             "start; OpenCL not asked", work, bound, host_threads,
             host_threads == 1 ? " scores" : "s score");
    return 1;
}

relief_status relief_matcher_create(relief_backend backend, int device, int threads,
                                    double work, const relief_match_data *d,
                                    relief_matcher **out, char *note, size_t note_size,
                                    relief_reason *why_code, relief_error *err)
{
    const int host_threads = relief_score_pool_threads_for(threads);
    relief_status st;
    char why[RELIEF_ERROR_MESSAGE_MAX + 64] = "";
    const int named = device >= 0; /* --device given */
    size_t host_max;
    int lanes;
    int set;
    if (note && note_size)
        note[0] = '\0';
    if (why_code)
        *why_code = RELIEF_REASON_NONE;
    if (backend == RELIEF_BACKEND_SCALAR)
        return relief_matcher_scalar_create(d, out, err);
    if (backend == RELIEF_BACKEND_HOST)
        return relief_matcher_host_create(d, host_threads, out, err);
    /* A bad setting is the user's to mend, under auto too, whichever
     * backend auto then picks. */
    st = relief_opencl_host_max_env(&host_max, &set, err);
    if (st == RELIEF_OK)
        st = relief_opencl_lanes_env(&lanes, &set, err);
#ifdef RELIEF_HAVE_OPENCL
    if (st == RELIEF_OK)
        st = relief_cl_profile_env(&set, err);
#endif
    if (st != RELIEF_OK)
        return st;
    if (backend == RELIEF_BACKEND_AUTO && !named &&
        (too_small(work, host_threads, why, sizeof why) ||
         (device = pick_device(why, sizeof why, why_code)) < 0))
        st = RELIEF_E_DEVICE; /* the host, for the reason in why[] */
    else {
        st = device_fits(device, d, err);
        if (st == RELIEF_OK)
            st = relief_matcher_opencl_create(d, device, threads, out, err);
        if (st == RELIEF_OK) {
            (*out)->fallback = backend == RELIEF_BACKEND_AUTO;
            (*out)->threads = threads;
            (*out)->device_index = device;
            if (backend == RELIEF_BACKEND_AUTO && note && note_size)
                snprintf(note, note_size, "%s: %.200s",
                         named ? "the OpenCL device named by its index"
                               : "the first GPU or accelerator OpenCL has",
                         (*out)->device);
        }
        /* A --device there is none of is the user's to mend too. */
        if (st == RELIEF_OK || backend == RELIEF_BACKEND_OPENCL || st == RELIEF_E_RANGE)
            return st;
        snprintf(why, sizeof why, RELIEF_MATCHER_UNAVAILABLE " (%s)",
                 err ? err->message : relief_strerror(st));
        if (why_code)
            *why_code = RELIEF_REASON_DEVICE_FELL_BACK;
    }
    /* auto on the host: say why. */
    relief_error_clear(err);
    st = relief_matcher_host_create(d, host_threads, out, err);
    if (st == RELIEF_OK && note && note_size)
        snprintf(note, note_size, "%s; scoring on the %s", why, (*out)->device);
    return st;
}

relief_status relief_matcher_score(relief_matcher *m, const relief_match_data *d,
                                   const relief_match_query *q, float *ssd, uint8_t *flag,
                                   relief_error *err)
{
    double t0 = relief_seconds();
    relief_status st = m->inject ? m->inject(m->inject_ctx, err) : RELIEF_OK;
    if (st == RELIEF_OK)
        st = m->ops->score(m->ctx, d, q, ssd, flag, err);
    if (st == RELIEF_E_DEVICE && m->fallback) {
        /* Scoring has no side effect: the same query on the reference. */
        st = fall_back(m, d, err, err);
        if (st == RELIEF_OK)
            st = m->ops->score(m->ctx, d, q, ssd, flag, err);
    }
    m->kernel_seconds += relief_seconds() - t0;
    return st;
}

relief_status relief_matcher_update(relief_matcher *m, const relief_match_data *d, uint32_t v,
                                    relief_error *err)
{
    relief_status st = m->ops->update(m->ctx, d, v, err);
    if (st == RELIEF_E_DEVICE && m->fallback)
        st = fall_back(m, d, err, err); /* the reference reads d itself */
    return st;
}

relief_status relief_matcher_rebind(relief_matcher *m, const relief_match_data *d,
                                    relief_error *err)
{
    relief_status st = RELIEF_OK;
    if (m->backend == RELIEF_BACKEND_OPENCL)
        st = device_fits(m->device_index, d, err);
    if (st == RELIEF_OK)
        st = m->ops->rebind(m->ctx, d, err);
    if (st != RELIEF_OK && m->backend == RELIEF_BACKEND_OPENCL && m->fallback &&
        (st == RELIEF_E_DEVICE || st == RELIEF_E_NOMEM))
        st = fall_back(m, d, err, err);
    return st;
}

void relief_matcher_destroy(relief_matcher *m)
{
    if (!m)
        return;
    m->ops->destroy(m->ctx);
    free(m);
}
