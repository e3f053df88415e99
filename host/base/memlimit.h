/* Memory limits: estimate what a completion needs before allocating it,
 * and refuse with the estimate and the limit when it cannot fit, rather
 * than die half-way in the kernel's out-of-memory killer.
 *
 * Host estimates are per vertex and per triangle of the combined surface,
 * measured on synthetic captures (the smooth completion's peak is qhull's
 * triangulation: 1.14 GB for 482 000 vertices, about 2.4 KB per vertex)
 * with a margin. What a device needs is the matcher's to say
 * (match/device_memory.h). */
#ifndef RELIEF_HOST_MEMLIMIT_H
#define RELIEF_HOST_MEMLIMIT_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"
#include "base/params.h"

/* Bytes of host memory, per item, that the estimates use. */
#define RELIEF_MEM_SMOOTH_PER_VERTEX 2500u /* relief_surface_build's peak, qhull included */
#define RELIEF_MEM_SURFACE_PER_VERTEX 240u /* relief_surface after smooth */
#define RELIEF_MEM_SURFACE_PER_TRIANGLE 12u
#define RELIEF_MEM_MATCH_PER_VERTEX 240u   /* match data: float copies, grid, and
                                              the closest-vertex lists (about 170
                                              measured on cylinder-bark) */
#define RELIEF_MEM_MATCH_PER_TRIANGLE 24u
#define RELIEF_MEM_MATCH_PER_SAMPLE 52u
#define RELIEF_MEM_GROW_PER_VERTEX 96u     /* growth: window search, neighbourhood */
#define RELIEF_MEM_GROW_PER_TRIANGLE 72u   /* adjacency, built from the edges */
#define RELIEF_MEM_GROW_PER_CANDIDATE 9u   /* ssd, flag, best set per (sample, rotation) */

/* Physical memory of this machine in bytes (sysconf), 0 when unknown. */
uint64_t relief_physical_memory(void);

/* The host limit when relief_params.max_memory is 0: 80 % of physical
 * memory, or of the address-space limit (RLIMIT_AS) when that is lower;
 * UINT64_MAX when neither is known. */
uint64_t relief_default_memory_limit(void);

/* params->max_memory, or the default when it is 0. */
uint64_t relief_memory_limit(const relief_params *params);

/* Parse a size: a number of bytes with an optional binary suffix K, M, G or
 * T (also KB, KiB, ...; case-insensitive): "512M", "4G", "1.5G", "100000".
 * RELIEF_E_USAGE naming the text when it is not a positive size. */
relief_status relief_parse_size(const char *text, uint64_t *out, relief_error *err);

/* "1.5 GiB", "512 MiB", "900 B" into buf. */
void relief_format_size(uint64_t bytes, char *buf, size_t cap);

/* Host bytes reading a mesh file of `file_bytes` takes at its peak:
 * OpenMesh's own structures and relief's copy, about 6 times a binary
 * PLY's size measured, taken as 16 to cover the other formats. */
#define RELIEF_MEM_READ_PER_FILE_BYTE 16u
uint64_t relief_estimate_read(uint64_t file_bytes);

/* Host bytes relief_surface_build needs at its peak for a surface of `vertices`
 * vertices (samples after oversampling, plus targets). */
uint64_t relief_estimate_smooth(size_t vertices);

/* Host bytes a mono-scale growth needs on a surface of nv vertices, nt
 * triangles and ns samples with R rotations: the surface, the match data
 * and the growth's own state. */
uint64_t relief_estimate_growth(size_t nv, size_t nt, size_t ns, int rotations);

/* RELIEF_E_NOMEM "<what> needs about <need> of memory, over the limit of
 * <limit> (--max-memory ...)<hint>" when need > limit; hint (may be "")
 * says what else makes the run smaller. */
relief_status relief_memory_check(const char *what, uint64_t need, uint64_t limit,
                                  const char *hint, relief_error *err);

#endif
