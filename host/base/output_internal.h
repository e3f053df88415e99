/* What output.c and output_commit.c share (output.h is the interface). */
#ifndef RELIEF_HOST_BASE_OUTPUT_INTERNAL_H
#define RELIEF_HOST_BASE_OUTPUT_INTERNAL_H

#include "base/output.h"

/* "DIR/.relief-ROLE-PID-TOKEN[.NAME]" (malloc'ed; NAME NULL: none), NAME
 * cut so that the last component fits NAME_MAX. */
char *relief_output_name(const char *dir, const char *role, long pid, const char *token,
                         const char *name);

/* A temporary for `path`, created (0666 less the umask) and locked, after
 * tidying its folder: *tmp (malloc'ed) and *fd (open, holding the lock). */
relief_status relief_output_temp(const char *path, char **tmp, int *fd, relief_error *err);

/* Six random characters of [0-9A-Za-z] and a NUL. */
void relief_output_token(char out[7]);

/* Open a new file `path` for writing (O_EXCL, mode 0666 less the umask)
 * and lock it; -1 with errno set on failure. */
int relief_output_create(const char *path);

/* Run write() on a stream over a duplicate of fd, then check the stream,
 * flush, sync and close it; fd stays open (it holds the lock). Failures
 * name `shown`. */
relief_status relief_output_fill(int fd, const char *shown, relief_sink_fn write, void *ctx,
                                 relief_error *err);

/* Sync the folder `path` is in (best effort). */
void relief_output_sync_dir_of(const char *path);

/* Remove a file, or a folder of plain files and the folder. */
void relief_output_remove_flat(const char *path);

/* Hand a staged folder's names and lock to a commit (*path, *target,
 * *lock_fd taken); s is freed. */
void relief_staged_folder_take(relief_staged_folder *s, char **path, char **target,
                               int *lock_fd);

#endif
