/* OpenCL event profiles (cl_profile.h). Events wait in `pend` in the order
 * they were enqueued; whenever the array is full, those already complete
 * are read and released, and it grows only when none is. */
#ifdef RELIEF_HAVE_OPENCL
#include "device/cl_profile.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/clock.h"
#include "base/error.h"

#define KINDS 16
#define FIRST_CAP 256

typedef struct kind {
    const char *what;
    int host; /* host work (seconds in host_s), not device commands */
    size_t count;
    double host_s;
    double bytes;
    cl_ulong busy_ns, max_ns;
} kind;

typedef struct pending {
    cl_event ev; /* NULL until the enqueue stores it; stays NULL if it failed */
    int kind;
    size_t bytes;
} pending;

struct relief_cl_profile {
    const char *engine;
    char device[128];
    double opened; /* relief_seconds() at open */
    kind kinds[KINDS];
    int nkinds;
    pending *pend;
    size_t npend, cap;
    size_t lost; /* commands not counted: no memory, or no timestamps */
};

relief_status relief_cl_profile_env(int *on, relief_error *err)
{
    const char *env = getenv("RELIEF_OPENCL_PROFILE");
    *on = 0;
    if (!env || !*env || strcmp(env, "0") == 0)
        return RELIEF_OK;
    if (strcmp(env, "1") != 0)
        return relief_fail(err, RELIEF_E_RANGE,
                           "RELIEF_OPENCL_PROFILE='%.40s': expected 0 or 1 (1: write where "
                           "each OpenCL engine's time goes to stderr)",
                           env);
    *on = 1;
    return RELIEF_OK;
}

relief_status relief_cl_profile_open(const char *engine, const char *device,
                                     relief_cl_profile **out, relief_error *err)
{
    relief_cl_profile *p;
    int on;
    relief_status st = relief_cl_profile_env(&on, err);
    *out = NULL;
    if (st != RELIEF_OK || !on || !(p = calloc(1, sizeof *p)))
        return st;
    p->engine = engine;
    snprintf(p->device, sizeof p->device, "%s", device);
    p->opened = relief_seconds();
    *out = p;
    return RELIEF_OK;
}

cl_command_queue_properties relief_cl_profile_queue_flags(const relief_cl_profile *p)
{
    return p ? CL_QUEUE_PROFILING_ENABLE : 0;
}

/* The index of kind `what` (host work when `host`), added if new; past
 * KINDS - 2 kinds, the last two slots take the rest as "other", device
 * commands and host work apart. */
static int kind_of(relief_cl_profile *p, const char *what, int host)
{
    for (int i = 0; i < p->nkinds; ++i)
        if (p->kinds[i].host == host && strcmp(p->kinds[i].what, what) == 0)
            return i;
    if (p->nkinds >= KINDS - 2) {
        for (int i = 0; i < 2; ++i) {
            p->kinds[KINDS - 2 + i].what = "other";
            p->kinds[KINDS - 2 + i].host = i;
        }
        p->nkinds = KINDS;
        return KINDS - 2 + (host != 0);
    }
    p->kinds[p->nkinds].what = what;
    p->kinds[p->nkinds].host = host;
    return p->nkinds++;
}

/* Count command c, complete, and release its event; 0 when its
 * timestamps cannot be read. */
static int count_one(relief_cl_profile *p, const pending *c)
{
    cl_ulong start = 0, end = 0;
    kind *k = &p->kinds[c->kind];
    int ok = clGetEventProfilingInfo(c->ev, CL_PROFILING_COMMAND_START, sizeof start, &start,
                                     NULL) == CL_SUCCESS &&
             clGetEventProfilingInfo(c->ev, CL_PROFILING_COMMAND_END, sizeof end, &end,
                                     NULL) == CL_SUCCESS &&
             end >= start;
    if (ok) {
        k->count++;
        k->bytes += (double)c->bytes;
        k->busy_ns += end - start;
        if (end - start > k->max_ns)
            k->max_ns = end - start;
    }
    clReleaseEvent(c->ev);
    return ok;
}

/* Count the commands that are complete (all of them, waiting, when
 * `wait`) and keep the rest in order. */
static void harvest(relief_cl_profile *p, int wait)
{
    size_t keep = 0;
    for (size_t i = 0; i < p->npend; ++i) {
        pending *c = &p->pend[i];
        cl_int status = CL_COMPLETE;
        if (!c->ev)
            continue;
        if (wait)
            clWaitForEvents(1, &c->ev);
        if (clGetEventInfo(c->ev, CL_EVENT_COMMAND_EXECUTION_STATUS, sizeof status, &status,
                           NULL) != CL_SUCCESS)
            status = -1;
        if (status > CL_COMPLETE) { /* queued, submitted or running */
            p->pend[keep++] = *c;
            continue;
        }
        if (status < 0) {
            clReleaseEvent(c->ev);
            p->lost++;
        } else if (!count_one(p, c)) {
            p->lost++;
        }
    }
    p->npend = keep;
}

cl_event *relief_cl_profile_event(relief_cl_profile *p, const char *what, size_t bytes)
{
    pending *c;
    if (!p)
        return NULL;
    if (p->npend == p->cap)
        harvest(p, 0);
    if (p->npend == p->cap) {
        size_t cap = p->cap ? 2 * p->cap : FIRST_CAP;
        pending *grown = realloc(p->pend, cap * sizeof *grown);
        if (!grown) {
            p->lost++;
            return NULL;
        }
        p->pend = grown;
        p->cap = cap;
    }
    c = &p->pend[p->npend++];
    c->ev = NULL;
    c->kind = kind_of(p, what, 0);
    c->bytes = bytes;
    return &c->ev;
}

double relief_cl_profile_now(const relief_cl_profile *p)
{
    return p ? relief_seconds() : 0;
}

void relief_cl_profile_host(relief_cl_profile *p, const char *what, double since)
{
    kind *k;
    if (!p)
        return;
    k = &p->kinds[kind_of(p, what, 1)];
    k->count++;
    k->host_s += relief_seconds() - since;
}

/* The profile, to stderr. */
static void write_profile(const relief_cl_profile *p)
{
    double open_s = relief_seconds() - p->opened, busy_s = 0;
    for (int i = 0; i < p->nkinds; ++i)
        busy_s += (double)p->kinds[i].busy_ns * 1e-9;
    fprintf(stderr,
            "relief: OpenCL profile of the %s on %s: %.3f s from creation to release, the "
            "device busy %.3f s of it (%.1f %%)\n",
            p->engine, p->device, open_s, busy_s,
            open_s > 0 ? 100 * busy_s / open_s : 0.0);
    for (int i = 0; i < p->nkinds; ++i) {
        const kind *k = &p->kinds[i];
        double s = (double)k->busy_ns * 1e-9;
        if (k->host)
            continue;
        fprintf(stderr, "relief:   %-18s %8zu commands %9.3f s busy, mean %8.3f ms, max %8.3f ms",
                k->what, k->count, s, k->count ? 1e3 * s / (double)k->count : 0.0,
                (double)k->max_ns * 1e-6);
        if (k->bytes >= 1e5)
            fprintf(stderr, ", %.1f MB", k->bytes * 1e-6);
        else if (k->bytes > 0)
            fprintf(stderr, ", %.1f kB", k->bytes * 1e-3);
        fputc('\n', stderr);
    }
    for (int i = 0; i < p->nkinds; ++i)
        if (p->kinds[i].host)
            fprintf(stderr, "relief:   on the host instead: %s, %zu times, %.3f s\n",
                    p->kinds[i].what, p->kinds[i].count, p->kinds[i].host_s);
    if (p->lost)
        fprintf(stderr, "relief:   (%zu commands not counted: no timestamps or no memory)\n",
                p->lost);
}

void relief_cl_profile_close(relief_cl_profile *p, int write)
{
    if (!p)
        return;
    harvest(p, 1);
    for (size_t i = 0; i < p->npend; ++i) { /* left running by a failed wait */
        clReleaseEvent(p->pend[i].ev);
        p->lost++;
    }
    if (write)
        write_profile(p);
    free(p->pend);
    free(p);
}
#endif
