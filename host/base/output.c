/* Outputs whole or not at all (output.h). */
#define _GNU_SOURCE /* flock, getrandom, O_DIRECTORY under -D_POSIX_C_SOURCE */
#include "base/output.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <time.h>
#include <unistd.h>

#include "base/error.h"
#include "base/output_internal.h"

/* ------------------------------------------------------------ names */

/* The folder `path` goes in (malloc'ed; "." when it names none) and its
 * last name (borrowed from path; "" when path ends in '/'). */
char *relief_output_split(const char *path, const char **name)
{
    const char *slash = strrchr(path, '/');
    size_t n = slash ? (size_t)(slash - path) : 0;
    char *dir = malloc(n + 2);
    if (!dir)
        return NULL;
    if (!slash)
        strcpy(dir, ".");
    else {
        memcpy(dir, path, n ? n : 1); /* "/x" goes in "/" */
        dir[n ? n : 1] = '\0';
    }
    *name = slash ? slash + 1 : path;
    return dir;
}

/* Six random characters of [0-9A-Za-z]. */
void relief_output_token(char out[7])
{
    static const char set[] = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz";
    unsigned char b[6];
    if (getrandom(b, sizeof b, GRND_NONBLOCK) != (ssize_t)sizeof b) {
        /* No entropy yet (early boot): the address of out and the clock. */
        uintptr_t x = (uintptr_t)out ^ (uintptr_t)time(NULL) ^ (uintptr_t)clock();
        for (int i = 0; i < 6; ++i, x = x * 6364136223846793005u + 1442695040888963407u)
            b[i] = (unsigned char)(x >> 33);
    }
    for (int i = 0; i < 6; ++i)
        out[i] = set[b[i] % (sizeof set - 1)];
    out[6] = '\0';
}

/* "DIR/.relief-ROLE-PID-TOKEN[.NAME]" (malloc'ed), NAME cut so that the
 * last component fits NAME_MAX. */
char *relief_output_name(const char *dir, const char *role, long pid, const char *token,
                         const char *name)
{
    char head[64];
    size_t nh = (size_t)snprintf(head, sizeof head, ".relief-%s-%ld-%s", role, pid, token);
    size_t keep = name ? strlen(name) : 0, nd = strlen(dir), n;
    char *out;
    if (keep && nh + 1 + keep > NAME_MAX)
        keep = NAME_MAX - nh - 1;
    n = nd + 1 + nh + 1 + keep + 1;
    if (!(out = malloc(n)))
        return NULL;
    snprintf(out, n, "%s/%s%s%.*s", dir, head, keep ? "." : "", (int)keep, name ? name : "");
    return out;
}

/* ---------------------------------------------------------- sinks */

relief_status relief_sink_bytes(relief_sink *s, void *ctx, relief_error *err)
{
    const relief_bytes *b = ctx;
    (void)err;
    fwrite(b->data, 1, b->n, s->f);
    return RELIEF_OK;
}

/* The stream a writer fills: its bytes go to fd by write(), and the first
 * failure's errno is kept. A writer that sees only "it failed" (OpenMesh's
 * stream, a short fwrite, libpng) or whose errno a later call overwrote
 * cannot lose the system's reason ("No space left on device"): the file's
 * failure is told with it whatever the writer made of it. */
typedef struct sink_fd {
    int fd;
    int err; /* the first failed write's errno; 0 while every byte went */
} sink_fd;

static ssize_t sink_write(void *cookie, const char *buf, size_t n)
{
    sink_fd *c = cookie;
    size_t done = 0;
    while (!c->err && done < n) {
        ssize_t k = write(c->fd, buf + done, n - done);
        if (k < 0 && errno == EINTR)
            continue;
        if (k <= 0)
            c->err = k < 0 ? errno : EIO;
        else
            done += (size_t)k;
    }
    if (c->err)
        errno = c->err;
    return (ssize_t)done; /* fewer than n: stdio marks the stream failed */
}

/* Run write() on a stream over fd, then check the stream, flush and sync.
 * fd stays open (it holds the lock). */
relief_status relief_output_fill(int fd, const char *shown, relief_sink_fn write, void *ctx,
                               relief_error *err)
{
    static const cookie_io_functions_t io = {NULL, sink_write, NULL, NULL};
    sink_fd c = {fd, 0};
    relief_sink s = {NULL, shown};
    relief_status st;
    int during, flushed;
    if (!(s.f = fopencookie(&c, "wb", io)))
        return relief_fail_errno(err, errno, shown, "cannot write");
    setvbuf(s.f, NULL, _IOFBF, 1 << 16);
    st = write(&s, ctx, err);
    during = c.err;
    flushed = fflush(s.f) == 0 && !ferror(s.f);
    fclose(s.f); /* nothing left to flush; fd is not the stream's to close */
    /* A write the system refused explains the writer's failure too; a
     * writer's own reason (a bad mesh, no memory) stands when no write
     * failed before it. */
    if (c.err && (st == RELIEF_OK || during))
        return relief_fail_errno(err, c.err, shown, "cannot write");
    if (st != RELIEF_OK)
        return st;
    if (!flushed)
        return relief_fail_errno(err, EIO, shown, "cannot write");
    if (fsync(fd) != 0)
        return relief_fail_errno(err, errno, shown, "cannot write");
    return RELIEF_OK;
}

int relief_output_create(const char *path)
{
    int fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0 && flock(fd, LOCK_EX | LOCK_NB) != 0) {
        /* A file system without flock: the pid in the name still tells. */
    }
    return fd;
}

relief_status relief_output_plain(const char *path, const char *shown, relief_sink_fn write,
                                  void *ctx, relief_error *err)
{
    int fd = relief_output_create(path);
    relief_status st;
    if (fd < 0)
        return relief_fail_errno(err, errno, shown, "cannot create");
    st = relief_output_fill(fd, shown, write, ctx, err);
    close(fd);
    if (st != RELIEF_OK)
        unlink(path);
    return st;
}

/* A temporary "DIR/.relief-tmp-PID-XXXXXX.NAME" for `path`, created and
 * locked: *tmp (malloc'ed) and *fd. */
relief_status relief_output_temp(const char *path, char **tmp, int *fd, relief_error *err)
{
    const char *name;
    char *dir = relief_output_split(path, &name);
    if (!dir)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a file name");
    relief_output_tidy(dir);
    for (int tries = 0; tries < 100; ++tries) {
        char token[7];
        relief_output_token(token);
        if (!(*tmp = relief_output_name(dir, "tmp", (long)getpid(), token, name))) {
            free(dir);
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a file name");
        }
        if ((*fd = relief_output_create(*tmp)) >= 0 || errno != EEXIST)
            break;
        free(*tmp);
        *tmp = NULL;
    }
    free(dir);
    if (*fd < 0) {
        int e = errno;
        free(*tmp);
        *tmp = NULL;
        return relief_fail_errno(err, e, path, "cannot create a file beside it");
    }
    return RELIEF_OK;
}

/* Sync the folder `path` is in, so that a rename there is on disk. */
void relief_output_sync_dir_of(const char *path)
{
    const char *name;
    char *dir = relief_output_split(path, &name);
    int fd = dir ? open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC) : -1;
    if (fd >= 0) {
        fsync(fd); /* best effort: some file systems refuse a folder's sync */
        close(fd);
    }
    free(dir);
}

relief_status relief_output_file(const char *path, relief_sink_fn write, void *ctx,
                                 relief_error *err)
{
    char *tmp = NULL;
    int fd = -1;
    relief_status st = relief_output_temp(path, &tmp, &fd, err);
    if (st != RELIEF_OK)
        return st;
    st = relief_output_fill(fd, path, write, ctx, err);
    if (st == RELIEF_OK && rename(tmp, path) != 0)
        st = relief_fail_errno(err, errno, path, "cannot move the finished file into place");
    if (st != RELIEF_OK)
        unlink(tmp);
    else
        relief_output_sync_dir_of(path);
    close(fd);
    free(tmp);
    return st;
}

/* -------------------------------------------------------- staged folders */

struct relief_staged_folder {
    char *target; /* as given, without trailing slashes */
    char *path;   /* the temporary folder */
    int lock_fd;  /* open on it, locked, while it is ours */
};

void relief_output_remove_flat(const char *path)
{
    DIR *d = opendir(path);
    struct dirent *e;
    if (!d) {
        unlink(path); /* a file, or nothing */
        return;
    }
    while ((e = readdir(d)) != NULL) {
        char full[PATH_MAX];
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
            continue;
        if ((size_t)snprintf(full, sizeof full, "%s/%s", path, e->d_name) < sizeof full)
            unlink(full);
    }
    closedir(d);
    rmdir(path);
}

/* `path` without trailing slashes (malloc'ed), or NULL. */
static char *trimmed(const char *path)
{
    size_t n = strlen(path);
    char *s;
    while (n > 1 && path[n - 1] == '/')
        --n;
    if ((s = malloc(n + 1)) != NULL) {
        memcpy(s, path, n);
        s[n] = '\0';
    }
    return s;
}

/* mkdir a fresh "DIR/.relief-tmp-PID-XXXXXX.NAME" for s->target. */
static relief_status make_folder(relief_staged_folder *s, relief_error *err)
{
    const char *name;
    char *dir = relief_output_split(s->target, &name);
    int e = 0;
    if (!dir)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a path");
    relief_output_tidy(dir);
    for (int tries = 0; tries < 100; ++tries) {
        char token[7];
        relief_output_token(token);
        free(s->path);
        if (!(s->path = relief_output_name(dir, "tmp", (long)getpid(), token, name))) {
            free(dir);
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a path");
        }
        if (mkdir(s->path, 0777) == 0 || (e = errno) != EEXIST)
            break;
    }
    free(dir);
    if (e) {
        free(s->path);
        s->path = NULL;
        return relief_fail_errno(err, e, s->target, "cannot create a folder beside it");
    }
    s->lock_fd = open(s->path, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (s->lock_fd >= 0)
        flock(s->lock_fd, LOCK_EX | LOCK_NB);
    return RELIEF_OK;
}

relief_status relief_staged_folder_create(const char *path, relief_staged_folder **out,
                                          relief_error *err)
{
    relief_staged_folder *s = calloc(1, sizeof *s);
    relief_status st;
    *out = NULL;
    if (!s || !(s->target = trimmed(path))) {
        free(s);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a path");
    }
    s->lock_fd = -1;
    if ((st = make_folder(s, err)) != RELIEF_OK) {
        relief_staged_folder_abort(s);
        return st;
    }
    *out = s;
    return RELIEF_OK;
}

const char *relief_staged_folder_path(const relief_staged_folder *s)
{
    return s->path;
}

const char *relief_staged_folder_target(const relief_staged_folder *s)
{
    return s->target;
}

/* Hand the folder's names and lock to a commit: *path, *target, *lock_fd
 * taken; s freed. */
void relief_staged_folder_take(relief_staged_folder *s, char **path, char **target,
                               int *lock_fd)
{
    *path = s->path, *target = s->target, *lock_fd = s->lock_fd;
    free(s);
}

void relief_staged_folder_abort(relief_staged_folder *s)
{
    if (!s)
        return;
    if (s->path) {
        relief_output_remove_flat(s->path);
        relief_output_sync_dir_of(s->path);
    }
    if (s->lock_fd >= 0)
        close(s->lock_fd);
    free(s->path);
    free(s->target);
    free(s);
}
