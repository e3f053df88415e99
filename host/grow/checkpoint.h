/* Checkpoints of a growth: `relief complete --checkpoint FILE` saves the
 * growth's state (relief_grow_state) when it is interrupted, when it fails
 * on the device, and every few minutes; `--resume FILE` continues it to
 * the same result, byte for byte, as an uninterrupted run.
 *
 * A checkpoint carries a fingerprint of what it was made from: a hash of
 * the input mesh and the parameters that change the result, as text. A
 * resume with another input or other parameters is refused, naming the
 * first parameter that differs. The backend, the device and pruning are
 * not part of it: they never change the result, so a run interrupted on
 * OpenCL may be resumed on the scalar reference.
 *
 * A hierarchical run (--levels M) saves the level in progress, its growth's
 * state and what it takes from the finished levels (relief_hierarchy_state:
 * their heights, matches and figures), so it resumes at that level.
 *
 * File layout (native byte order, little-endian on every platform relief
 * runs on; an order marker rejects the others): magic "RELIEFCK", format
 * version, the fingerprint, the state (with a hierarchy's place, if any),
 * and an FNV-1a 64 checksum of all that precedes it. Written under a
 * temporary name and renamed into place, so the file is always the previous
 * or the new checkpoint, never half. */
#ifndef RELIEF_HOST_CHECKPOINT_H
#define RELIEF_HOST_CHECKPOINT_H

#include <stdint.h>

#include "relief/relief.h"
#include "base/params.h"
#include "grow/grow.h"
#include "smooth/surface.h"

#define RELIEF_CHECKPOINT_PARAMS_MAX 512

/* What a checkpoint must match to be resumed. */
typedef struct relief_checkpoint_key {
    uint64_t input_hash; /* FNV-1a 64 of the input's vertex and triangle counts,
                            positions, triangles, colours and labels */
    char params[RELIEF_CHECKPOINT_PARAMS_MAX]; /* "fit=auto window=3 ..." */
} relief_checkpoint_key;

/* The fingerprint of a completion of `input` with these parameters. */
void relief_checkpoint_key_make(const relief_mesh *input, const relief_params *params,
                                const relief_smooth_options *sopts,
                                const relief_grow_options *gopts, relief_checkpoint_key *key);

/* May `path` be a checkpoint's file: absent (*exists 0), or a relief
 * checkpoint (it starts with the magic; *exists 1)? Anything else is
 * refused (RELIEF_E_IO, reason RELIEF_REASON_NOT_RELIEFS): relief replaces
 * only a checkpoint it wrote. */
relief_status relief_checkpoint_check_path(const char *path, int *exists, relief_error *err);

/* Write `state` with its fingerprint to `path`, whole or not at all.
 * RELIEF_E_IO or RELIEF_E_SYSTEM naming the file and the system's reason
 * when it cannot be written. */
relief_status relief_checkpoint_write(const char *path, const relief_checkpoint_key *key,
                                      const relief_grow_state *state, relief_error *err);

/* A checkpoint read back: its state and the arrays the state points to. */
typedef struct relief_checkpoint relief_checkpoint;

/* Read `path` and check it against `key`: RELIEF_E_IO when it cannot be
 * read, RELIEF_E_PARSE when it is not a checkpoint, is truncated, corrupt
 * (checksum) or inconsistent (naming the field), RELIEF_E_USAGE when it
 * was made from another input, other parameters or another relief version.
 * The state's vertex counts are checked against the surface by
 * relief_grow. */
relief_status relief_checkpoint_read(const char *path, const relief_checkpoint_key *key,
                                     relief_checkpoint **out, relief_error *err);

/* The saved state; valid until relief_checkpoint_destroy. */
const relief_grow_state *relief_checkpoint_state(const relief_checkpoint *c);

/* NULL accepted. */
void relief_checkpoint_destroy(relief_checkpoint *c);

#endif
