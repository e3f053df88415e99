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

/* Several files that appear together or not at all (a command's outputs).
 * Each finished temporary is moved over its target by relief_atomic_place,
 * which keeps the file that was there under a second name (a hard link, so
 * the target never goes missing; moved aside where links are refused);
 * relief_atomic_settle then drops those once every file is placed, or,
 * after a failure, puts each back: the previous file's own inode returns,
 * its bytes and mtime untouched, and a file that was not there before is
 * removed. Nothing that existed before is ever removed. */
typedef struct relief_atomic_file {
    const char *path; /* the target */
    char *tmp;        /* its temporary (relief_atomic_create); NULL once placed */
    char *old;        /* the previous file, kept until settled, or NULL */
    int placed;       /* 1 once tmp is at path */
} relief_atomic_file;

/* Move f->tmp over f->path, keeping what was there. RELIEF_E_IO naming the
 * path on failure (then relief_atomic_settle(f, 0) puts it back). */
relief_status relief_atomic_place(relief_atomic_file *f, relief_error *err);

/* keep: drop the previous file; else put it back and remove the new one
 * and the temporary. Frees the names. */
void relief_atomic_settle(relief_atomic_file *f, int keep);

#endif
