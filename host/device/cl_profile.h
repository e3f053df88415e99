/* Where an OpenCL engine's time goes, from the device's own clock.
 *
 * With RELIEF_OPENCL_PROFILE=1 in the environment, each OpenCL engine (the
 * mesh matcher, the image and depth scorer, the point grids' search)
 * creates its queue with profiling on, passes every command's event here,
 * and on release writes to stderr, per kind of command (a kernel's name,
 * "write", "read"): how many ran, the bytes moved, and the seconds the
 * device spent on them (CL_PROFILING_COMMAND_START to _END), beside the
 * seconds from the engine's creation to its release on the host's clock
 * and the host work the engine did in the device's place.
 * What the device was not busy with is the host's share: launches,
 * read-backs waiting, ranking, the engine's serial parts. This is the
 * profile Nsight Compute cannot give (it does not see OpenCL kernels).
 * Unset or 0: nothing is recorded and nothing is written. The results are
 * the same bytes either way; only the timing changes (an event per
 * command).
 *
 * Usage (one profile per queue, owned by its engine):
 *   relief_cl_profile *prof;
 *   relief_cl_profile_open("image scorer", info.name, &prof, err);  // NULL: off
 *   queue = clCreateCommandQueue(ctx, dev, relief_cl_profile_queue_flags(prof), &rc);
 *   clEnqueueNDRangeKernel(queue, k, ..., 0, NULL, relief_cl_profile_event(prof, "k", 0));
 *   ...
 *   relief_cl_profile_close(prof, 1);  // before the queue is released
 */
#ifndef RELIEF_HOST_CL_PROFILE_H
#define RELIEF_HOST_CL_PROFILE_H

#ifdef RELIEF_HAVE_OPENCL
#include <CL/cl.h>
#include <stddef.h>

#include "relief/relief.h"

typedef struct relief_cl_profile relief_cl_profile;

/* *out: a profile for the engine called `engine` (a string literal) on
 * the device called `device` (copied), or
 * NULL when RELIEF_OPENCL_PROFILE is unset, empty or 0, or when there is
 * no memory for one (profiling is a diagnostic: it never fails a run).
 * RELIEF_E_RANGE naming the variable when it is set to anything but 0 or
 * 1. */
relief_status relief_cl_profile_open(const char *engine, const char *device,
                                     relief_cl_profile **out, relief_error *err);

/* *on: 1 when RELIEF_OPENCL_PROFILE is 1, 0 when it is unset, empty or 0;
 * RELIEF_E_RANGE naming it otherwise. For an engine that would run
 * elsewhere when its OpenCL start fails: a bad setting is refused, not a
 * reason to run on another backend. */
relief_status relief_cl_profile_env(int *on, relief_error *err);

/* CL_QUEUE_PROFILING_ENABLE with a profile, 0 without (p NULL). */
cl_command_queue_properties relief_cl_profile_queue_flags(const relief_cl_profile *p);

/* The event argument for the next command, of kind `what` (a string
 * literal: the kernel's name, "write" or "read"), moving `bytes` (0 for a
 * kernel): the profile takes the event the enqueue stores there and
 * releases it. NULL (no event) when p is NULL or out of memory. A command
 * that fails to enqueue leaves the slot empty and is not counted. */
cl_event *relief_cl_profile_event(relief_cl_profile *p, const char *what, size_t bytes);

/* The host's clock for relief_cl_profile_host (0 when p is NULL, without
 * reading it). */
double relief_cl_profile_now(const relief_cl_profile *p);

/* Host work of kind `what` (a string literal), begun at `since` (from
 * relief_cl_profile_now) and done now, in place of the device's work (a
 * launch too small to pay, the probes before one): written beside the
 * device's kinds. Nothing when p is NULL. */
void relief_cl_profile_host(relief_cl_profile *p, const char *what, double since);

/* Wait for the recorded commands, write the profile to stderr when
 * `write` (0: an engine whose creation failed), and free p (NULL:
 * nothing). Call it before the queue is released. */
void relief_cl_profile_close(relief_cl_profile *p, int write);
#endif

#endif
