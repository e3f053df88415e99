/* Files that appear whole or not at all: create a temporary file beside
 * the target (same folder, so rename is atomic), write it, then rename it
 * over the target, or remove it on failure. */
#ifndef RELIEF_HOST_ATOMIC_H
#define RELIEF_HOST_ATOMIC_H

#include <stdio.h>

#include "relief/relief.h"

/* Create an empty temporary file for `path`, named "<path>.tmp-XXXXXX<ext>"
 * with `ext` the target's extension kept last (writers that choose a
 * format by extension need it), with the permissions a plain create would
 * give. `*tmp` receives the malloc'ed name. */
relief_status relief_atomic_create(const char *path, char **tmp, relief_error *err);

/* Rename the finished temporary file over `path` and free the name; on
 * failure remove it. */
relief_status relief_atomic_commit(char *tmp, const char *path, relief_error *err);

/* Remove the temporary file and free its name (NULL accepted). */
void relief_atomic_abort(char *tmp);

/* Write a text file atomically: `write(f, ctx)` fills it and returns 0 on
 * success. */
relief_status relief_atomic_write_text(const char *path, int (*write)(FILE *f, void *ctx),
                                       void *ctx, relief_error *err);

#endif
