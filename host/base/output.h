/* Outputs that appear whole or not at all, and nothing a user owns lost.
 *
 * Every file relief writes goes through here. A file is written to a
 * temporary beside its target, every write, the flush, fsync and close
 * checked, then renamed over the target; a failure leaves the older file
 * byte for byte and removes the temporary.
 *
 * Temporaries have one form, never nested:
 *
 *     DIR/.relief-ROLE-PID-XXXXXX.NAME
 *
 * hidden, with relief's prefix; ROLE `tmp` (a staged file or folder), `old`
 * (the previous file, kept while a commit of several outputs is under way)
 * or `log` (that commit's journal, no NAME); PID the writing process;
 * NAME the target's name, cut to fit NAME_MAX. While its writer lives a
 * temporary is locked (flock); a later run writing into the same folder
 * removes the ones whose writer died (a SIGKILL, a power cut) and that it
 * can lock, and nothing else.
 *
 * Several outputs (a command's -o, --report, --points, a report folder)
 * are committed together (relief_outputs): every file is staged first,
 * then a journal listing them is written and synced in each folder
 * involved, then each previous file is kept under a second name (a hard
 * link, so the target never goes missing) and the new one renamed over
 * it, and the commit's point is the removal of the first folder's journal.
 * A failure before that point puts every previous file back at once; a
 * kill before it leaves a journal that the next run writing into one of
 * those folders rolls back; a kill after it leaves only temporaries that
 * run removes. So the outputs are all new or all as they were. */
#ifndef RELIEF_HOST_BASE_OUTPUT_H
#define RELIEF_HOST_BASE_OUTPUT_H

#include <stdio.h>

#include "relief/relief.h"

/* Where a writer puts its bytes: an open stream on a staged file, and the
 * target's name as the user gave it (for messages, and for writers that
 * choose a format by extension). A writer need not check each write: the
 * stream's error state, the flush and fsync are checked after it, and a
 * write the system refused (no space, a file size limit, an I/O error) is
 * told with the system's reason whatever the writer returned. */
typedef struct relief_sink {
    FILE *f;
    const char *path;
} relief_sink;

/* Fills a sink; RELIEF_OK or a status with err set (naming s->path). */
typedef relief_status (*relief_sink_fn)(relief_sink *s, void *ctx, relief_error *err);

/* Write `path` whole or not at all with write(sink, ctx). A system
 * failure (no space, an I/O error, a read-only file system) is
 * RELIEF_E_SYSTEM with the system's reason and `path`; a folder that
 * cannot be written in, RELIEF_E_IO. */
relief_status relief_output_file(const char *path, relief_sink_fn write, void *ctx,
                                 relief_error *err);

/* Write a new file `path` inside a folder being staged (no temporary: the
 * folder is the unit that appears whole), synced; messages name `shown`
 * (the file's name once the folder is in place). */
relief_status relief_output_plain(const char *path, const char *shown, relief_sink_fn write,
                                  void *ctx, relief_error *err);

/* Bytes already made (an encoded PNG, a checkpoint's record), for
 * relief_sink_bytes. */
typedef struct relief_bytes {
    const void *data;
    size_t n;
} relief_bytes;

/* A relief_sink_fn writing the relief_bytes ctx points to (a failed write
 * is the sink's to tell, with the system's reason). */
relief_status relief_sink_bytes(relief_sink *s, void *ctx, relief_error *err);

/* The folder `path` goes in (malloc'ed; "." when it names none) and its
 * last name (borrowed from path). NULL when out of memory. */
char *relief_output_split(const char *path, const char **name);

/* ------------------------------------------------ a folder staged alone */

/* A folder built beside its target and moved into place whole: the
 * staging of a report folder, which may outlive the call that made it
 * (relief_complete hands it to its caller). */
typedef struct relief_staged_folder relief_staged_folder;

/* Create the temporary folder for `path` (its parent must exist);
 * relief_staged_folder_path gives where to write in it. */
relief_status relief_staged_folder_create(const char *path, relief_staged_folder **out,
                                          relief_error *err);

/* Where the staged folder is ("DIR/.relief-tmp-PID-XXXXXX.NAME"). */
const char *relief_staged_folder_path(const relief_staged_folder *s);

/* The target ("DIR/NAME" as given). */
const char *relief_staged_folder_target(const relief_staged_folder *s);

/* Remove the staged folder and its files and free `s` (NULL accepted). */
void relief_staged_folder_abort(relief_staged_folder *s);

/* --------------------------------------------- several outputs, together */

typedef struct relief_outputs relief_outputs;

/* A test's hook: called before each step of staging and commit (1, 2,
 * ...), with what the step does ("rename"); a non-zero return fails that
 * step as an I/O error would. A test may also kill the process there. */
typedef int (*relief_output_hook)(void *ctx, unsigned step, const char *what);

/* An empty set of outputs. */
relief_status relief_outputs_begin(relief_outputs **out, relief_error *err);

/* Set the hook (NULL: none). */
void relief_outputs_set_hook(relief_outputs *o, relief_output_hook hook, void *ctx);

/* Stage `path` now: its temporary written by write(sink, ctx), synced and
 * kept locked until the commit. On failure the temporary goes; the set
 * stays usable only for relief_outputs_abort. */
relief_status relief_outputs_file(relief_outputs *o, const char *path, relief_sink_fn write,
                                  void *ctx, relief_error *err);

/* Take a staged folder into the set (`*s` taken, set to NULL). A folder
 * that is there is replaced only when `replaceable(path, ctx)` says so at
 * the commit (1), else the commit fails with its message (0, err set). */
relief_status relief_outputs_folder(relief_outputs *o, relief_staged_folder **s,
                                    int (*replaceable)(const char *path, relief_error *err),
                                    relief_error *err);

/* Move every staged output into place, all or none (see above), and free
 * `o`. On failure every previous file is back and every temporary gone. */
relief_status relief_outputs_commit(relief_outputs *o, relief_error *err);

/* Remove every staged output and free `o` (NULL accepted). */
void relief_outputs_abort(relief_outputs *o);

/* Commit one staged folder on its own (relief_report_folder_commit). */
relief_status relief_staged_folder_commit(relief_staged_folder *s,
                                          int (*replaceable)(const char *path,
                                                             relief_error *err),
                                          relief_error *err);

/* Tidy the folder `dir` before a write into it: roll back (or finish) the
 * commits whose writers died, from their journals (above), then remove
 * the temporaries whose writers died: relief's form, the writer's process
 * gone, not locked, owned by this user. Called by every staging; a
 * failure to tidy is not an error (the write goes on). */
void relief_output_tidy(const char *dir);

#endif
