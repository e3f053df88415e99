/* What the engines' parameter tables (relief_param, relief/core.h) share:
 * the entries of run's fields, the names of the backends, and shorthands
 * for the common kinds. */
#ifndef RELIEF_HOST_BASE_PARAM_TABLE_H
#define RELIEF_HOST_BASE_PARAM_TABLE_H

#include <math.h>
#include <stddef.h>

#include "relief/relief.h"

/* NULL-ended names of the backends, in relief_backend's order. */
extern const char *const relief_backend_names[];

/* An entry's fields after name and kind, for the common kinds: offset,
 * value, names, min, max, specials, count offset, count-is-flag, help. */
#define RP_FLAG(type, field, help)                                                      \
    {#field, RELIEF_PARAM_FLAG, offsetof(type, field), NULL, NULL, 0, 1, 0, {0, 0}, 0, 0, help}
#define RP_INT(type, field, value, lo, hi, help)                                        \
    {#field, RELIEF_PARAM_INT, offsetof(type, field), value, NULL, lo, hi, 0, {0, 0}, 0, 0, \
     help}
#define RP_INT1(type, field, value, lo, hi, special, help)                              \
    {#field, RELIEF_PARAM_INT, offsetof(type, field), value, NULL, lo, hi, 1, {special, 0}, \
     0, 0, help}
#define RP_REAL(type, field, value, lo, hi, help)                                       \
    {#field, RELIEF_PARAM_REAL, offsetof(type, field), value, NULL, lo, hi, 0, {0, 0}, 0,  \
     0, help}
#define RP_REAL1(type, field, value, lo, hi, special, help)                             \
    {#field, RELIEF_PARAM_REAL, offsetof(type, field), value, NULL, lo, hi, 1,             \
     {special, 0}, 0, 0, help}
#define RP_SEED(type, field, help)                                                      \
    {#field, RELIEF_PARAM_SEED, offsetof(type, field), "N", NULL, 0, 4294967295.0, 0,      \
     {0, 0}, 0, 0, help}
#define RP_ENUM(type, field, value, names, help)                                        \
    {#field, RELIEF_PARAM_ENUM, offsetof(type, field), value, names, 0, 0, 0, {0, 0}, 0,   \
     0, help}
#define RP_PATH(type, field, value, help)                                               \
    {#field, RELIEF_PARAM_PATH, offsetof(type, field), value, NULL, 0, 0, 0, {0, 0}, 0, 0, \
     help}
#define RP_REALS(type, field, value, lo, hi, count_field, is_flag, help)               \
    {#field, RELIEF_PARAM_REALS, offsetof(type, field), value, NULL, lo, hi, 0, {0, 0},    \
     offsetof(type, count_field), is_flag, help}

/* run's backend (`help` says what this engine's backends do), device,
 * max_memory and threads in an engine's params `type`. */
#define RP_BACKEND(type, help)                                                          \
    {"backend", RELIEF_PARAM_ENUM, offsetof(type, run.backend), "B",                    \
     relief_backend_names, 0, 0, 0, {0, 0}, 0, 0, help}
#define RP_DEVICE(type)                                                                 \
    {"device", RELIEF_PARAM_INT, offsetof(type, run.device), "N", NULL, 0, 255, 1,      \
     {-1, 0}, 0, 0,                                                                     \
     "the OpenCL device, as relief_devices (`relief devices`) numbers them, 0..255; "   \
     "-1 (default): the first GPU or accelerator, else the first device"}
#define RP_MAX_MEMORY(type)                                                             \
    {"max_memory", RELIEF_PARAM_BYTES, offsetof(type, run.max_memory), "SIZE", NULL, 0, \
     HUGE_VAL, 0, {0, 0}, 0, 0,                                                         \
     "host memory the call may plan for, e.g. 512M, 4G: a larger call is refused "      \
     "before it starts; 0 (default): 80 % of physical memory"}

#define RP_THREADS(type)                                                                \
    {"threads", RELIEF_PARAM_INT, offsetof(type, run.threads), "N", NULL, 1,            \
     RELIEF_THREADS_MAX, 1, {0, 0}, 0, 0,                                               \
     "host threads the call may run on at once, 1..64; 0 (default): the CPUs this "     \
     "process may run on (its affinity: taskset, a container's cpuset); scalar runs "    \
     "on one whatever this says; the same output for any count"}

#endif
