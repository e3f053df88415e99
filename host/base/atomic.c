#include "base/atomic.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/error.h"

int mkstemps(char *template, int suffixlen); /* POSIX.1-2024; glibc has it */

relief_status relief_atomic_create(const char *path, char **tmp, relief_error *err)
{
    const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
    const char *ext = dot && (!slash || dot > slash) ? dot : "";
    size_t len = strlen(path) + strlen(ext) + 16;
    char *name = malloc(len);
    mode_t mask;
    int fd;

    if (!name)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a file name");
    snprintf(name, len, "%s.tmp-XXXXXX%s", path, ext);
    fd = mkstemps(name, (int)strlen(ext));
    if (fd < 0) {
        relief_status st = relief_fail(err, RELIEF_E_IO, "%s: cannot create a file there: %s",
                                       path, strerror(errno));
        free(name);
        return st;
    }
    /* mkstemps makes the file 0600; give it what a plain create would. */
    mask = umask(0);
    umask(mask);
    if (fchmod(fd, 0666 & ~mask) != 0) { /* not fatal: the file stays 0600 */
    }
    close(fd);
    *tmp = name;
    return RELIEF_OK;
}

relief_status relief_atomic_commit(char *tmp, const char *path, relief_error *err)
{
    relief_status st = RELIEF_OK;
    if (rename(tmp, path) != 0) {
        st = relief_fail(err, RELIEF_E_IO, "%s: cannot move the finished file into place: %s",
                         path, strerror(errno));
        unlink(tmp);
    }
    free(tmp);
    return st;
}

void relief_atomic_abort(char *tmp)
{
    if (tmp) {
        unlink(tmp);
        free(tmp);
    }
}

relief_status relief_atomic_write_text(const char *path, int (*write)(FILE *f, void *ctx),
                                       void *ctx, relief_error *err)
{
    char *tmp = NULL;
    FILE *f;
    relief_status st = relief_atomic_create(path, &tmp, err);
    if (st != RELIEF_OK)
        return st;
    f = fopen(tmp, "w");
    if (!f) {
        st = relief_fail(err, RELIEF_E_IO, "%s: cannot write: %s", path, strerror(errno));
        relief_atomic_abort(tmp);
        return st;
    }
    if (write(f, ctx) != 0 || ferror(f)) {
        fclose(f);
        relief_atomic_abort(tmp);
        return relief_fail(err, RELIEF_E_IO, "%s: write failed", path);
    }
    if (fclose(f) != 0) {
        relief_atomic_abort(tmp);
        return relief_fail(err, RELIEF_E_IO, "%s: write failed: %s", path, strerror(errno));
    }
    return relief_atomic_commit(tmp, path, err);
}

relief_status relief_atomic_place(relief_atomic_file *f, relief_error *err)
{
    struct stat sb;
    if (lstat(f->path, &sb) == 0) {
        size_t n = strlen(f->tmp) + 8;
        if (!(f->old = malloc(n)))
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a file name");
        snprintf(f->old, n, "%s.old", f->tmp);
        if (link(f->path, f->old) != 0 && rename(f->path, f->old) != 0) {
            free(f->old);
            f->old = NULL;
            return relief_fail(err, RELIEF_E_IO, "%s: cannot keep the previous file while "
                               "the new one is moved into place: %s", f->path,
                               strerror(errno));
        }
    }
    if (rename(f->tmp, f->path) != 0)
        return relief_fail(err, RELIEF_E_IO, "%s: cannot move the finished file into place: %s",
                           f->path, strerror(errno));
    free(f->tmp);
    f->tmp = NULL;
    f->placed = 1;
    return RELIEF_OK;
}

void relief_atomic_settle(relief_atomic_file *f, int keep)
{
    if (!keep && f->placed && !f->old)
        unlink(f->path); /* this run's file; nothing was there */
    /* Putting it back is a no-op when both names are links to the old
     * file; should it fail, the old file stays under its second name. */
    if (f->old && (keep || rename(f->old, f->path) == 0))
        unlink(f->old);
    relief_atomic_abort(f->tmp);
    free(f->old);
    f->tmp = f->old = NULL;
    f->placed = 0;
}
