/* Several outputs committed together through a journal, and the recovery
 * of a commit that a kill cut short (output.h). */
#define _GNU_SOURCE /* flock, O_DIRECTORY under -D_POSIX_C_SOURCE */
#include "base/output.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/error.h"
#include "base/output_internal.h"

#define JOURNAL_MAGIC "relief-output-journal 1"

/* One output of a commit. Paths are absolute (a later run, from anywhere,
 * may roll the commit back from its journal), but for `shown`. */
typedef struct entry {
    int folder;        /* 1: a staged folder */
    char *shown;       /* the target as the user named it, for messages */
    char *target;      /* absolute */
    char *staged;      /* the temporary, absolute */
    char *backup;      /* where the previous file is kept, absolute */
    dev_t dev;         /* the staged file's identity: once renamed, the */
    ino_t ino;         /* target is this run's exactly when it has them */
    int lock_fd;       /* holds the staged file's lock; -1 when none */
    int (*replaceable)(const char *path, relief_error *err); /* folders */
} entry;

#define MAX_ENTRIES 16

struct relief_outputs {
    entry e[MAX_ENTRIES];
    size_t n;
    char *journal[MAX_ENTRIES]; /* a copy per folder; [0] is the primary */
    size_t journal_entry[MAX_ENTRIES]; /* the first output in that folder */
    size_t n_journal;
    int journal_fd[MAX_ENTRIES];
    relief_output_hook hook;
    void *hook_ctx;
    unsigned step;
};

/* ------------------------------------------------------------- entries */

static void entry_free(entry *e)
{
    if (e->lock_fd >= 0)
        close(e->lock_fd);
    free(e->shown), free(e->target), free(e->staged), free(e->backup);
    memset(e, 0, sizeof *e);
    e->lock_fd = -1;
}

/* `path`'s absolute form through its folder's realpath (malloc'ed); the
 * folder must exist. */
static char *absolute(const char *path)
{
    const char *name;
    char *dir = relief_output_split(path, &name), *real = dir ? realpath(dir, NULL) : NULL;
    char *out = NULL;
    if (real) {
        size_t n = strlen(real) + strlen(name) + 2;
        if ((out = malloc(n)) != NULL)
            snprintf(out, n, "%s%s%s", real, strcmp(real, "/") ? "/" : "", name);
    }
    free(real);
    free(dir);
    return out;
}

/* The names of an entry from its staged temporary: the backup's is the
 * temporary's with role "old". */
static relief_status entry_names(entry *e, const char *shown, const char *staged,
                                 relief_error *err)
{
    char *last;
    if (!(e->shown = strdup(shown)) || !(e->target = absolute(shown)) ||
        !(e->staged = absolute(staged)) || !(e->backup = strdup(e->staged)))
        return relief_fail_errno(err, errno ? errno : ENOMEM, shown, "cannot name its files");
    last = strrchr(e->backup, '/') + 1; /* ".relief-tmp-..." */
    memcpy(last + strlen(".relief-"), "old", 3);
    return RELIEF_OK;
}

relief_status relief_outputs_begin(relief_outputs **out, relief_error *err)
{
    relief_outputs *o = calloc(1, sizeof *o);
    if (!(*out = o))
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a set of outputs");
    for (size_t i = 0; i < MAX_ENTRIES; ++i)
        o->e[i].lock_fd = o->journal_fd[i] = -1;
    return RELIEF_OK;
}

void relief_outputs_set_hook(relief_outputs *o, relief_output_hook hook, void *ctx)
{
    o->hook = hook, o->hook_ctx = ctx;
}

/* The hook's verdict on the next step: RELIEF_OK or a failure naming it. */
static relief_status step(relief_outputs *o, const char *what, const char *shown,
                          relief_error *err)
{
    ++o->step;
    if (o->hook && o->hook(o->hook_ctx, o->step, what))
        return relief_fail_reason(err, RELIEF_E_SYSTEM, RELIEF_REASON_NONE, "%s: writing the "
                                  "outputs: step %u (%s) failed (test hook)", shown, o->step,
                                  what);
    return RELIEF_OK;
}

relief_status relief_outputs_file(relief_outputs *o, const char *path, relief_sink_fn write,
                                  void *ctx, relief_error *err)
{
    entry *e = &o->e[o->n];
    char *tmp = NULL;
    struct stat sb;
    relief_status st;
    if (o->n == MAX_ENTRIES)
        return relief_fail(err, RELIEF_E_INTERNAL, "more than %d outputs", MAX_ENTRIES);
    if ((st = step(o, "write", path, err)) != RELIEF_OK ||
        (st = relief_output_temp(path, &tmp, &e->lock_fd, err)) != RELIEF_OK)
        return st;
    ++o->n; /* from here the entry is the set's, to abort */
    st = entry_names(e, path, tmp, err);
    if (st == RELIEF_OK && fstat(e->lock_fd, &sb) == 0)
        e->dev = sb.st_dev, e->ino = sb.st_ino;
    if (st == RELIEF_OK)
        st = relief_output_fill(e->lock_fd, path, write, ctx, err);
    if (st != RELIEF_OK && !e->staged)
        unlink(tmp);
    free(tmp);
    return st;
}

relief_status relief_outputs_folder(relief_outputs *o, relief_staged_folder **s,
                                    int (*replaceable)(const char *path, relief_error *err),
                                    relief_error *err)
{
    entry *e = &o->e[o->n];
    char *path, *target;
    struct stat sb;
    relief_status st;
    if (o->n == MAX_ENTRIES)
        return relief_fail(err, RELIEF_E_INTERNAL, "more than %d outputs", MAX_ENTRIES);
    relief_staged_folder_take(*s, &path, &target, &e->lock_fd);
    *s = NULL;
    ++o->n;
    e->folder = 1;
    e->replaceable = replaceable;
    st = entry_names(e, target, path, err);
    if (st == RELIEF_OK && lstat(path, &sb) == 0)
        e->dev = sb.st_dev, e->ino = sb.st_ino;
    if (st != RELIEF_OK && !e->staged)
        relief_output_remove_flat(path);
    free(path);
    free(target);
    return st;
}

/* ------------------------------------------------------------- journal */

/* A path in a journal's line: the bytes that would split or end it as
 * %XX. */
static void put_path(FILE *f, const char *p)
{
    for (; *p; ++p) {
        unsigned char c = (unsigned char)*p;
        if (c <= ' ' || c == '%' || c == 0x7f)
            fprintf(f, "%%%02X", c);
        else
            fputc(c, f);
    }
}

static relief_status journal_text(relief_sink *s, void *ctx, relief_error *err)
{
    const relief_outputs *o = ctx;
    (void)err;
    fprintf(s->f, "%s\n", JOURNAL_MAGIC);
    for (size_t j = 0; j < o->n_journal; ++j) {
        fputs("journal ", s->f);
        put_path(s->f, o->journal[j]);
        fputc('\n', s->f);
    }
    for (size_t i = 0; i < o->n; ++i) {
        const entry *e = &o->e[i];
        fputs(e->folder ? "folder " : "file ", s->f);
        put_path(s->f, e->target);
        fputc(' ', s->f);
        put_path(s->f, e->staged);
        fputc(' ', s->f);
        put_path(s->f, e->backup);
        fprintf(s->f, " %llu %llu\n", (unsigned long long)e->dev, (unsigned long long)e->ino);
    }
    fputs("end\n", s->f);
    return RELIEF_OK;
}

/* Does an entry before i go in `dir`? */
static int seen_folder(const relief_outputs *o, size_t i, const char *dir)
{
    int seen = 0;
    for (size_t k = 0; k < i && !seen; ++k) {
        const char *name;
        char *other = relief_output_split(o->e[k].target, &name);
        seen = other && strcmp(other, dir) == 0;
        free(other);
    }
    return seen;
}

/* One copy of the journal in `dir`, created empty and locked: the first
 * (the primary) with a fresh token, retried on a clash, the others with
 * the first's. 0, or -1 with errno set. */
static int journal_open(relief_outputs *o, const char *dir, char token[7])
{
    const size_t j = o->n_journal;
    for (int tries = 0; tries < 100; ++tries) {
        if (j == 0)
            relief_output_token(token);
        free(o->journal[j]);
        if (!(o->journal[j] = relief_output_name(dir, "log", (long)getpid(), token, NULL))) {
            errno = ENOMEM;
            return -1;
        }
        if ((o->journal_fd[j] = relief_output_create(o->journal[j])) >= 0) {
            ++o->n_journal;
            return 0;
        }
        if (errno != EEXIST || j > 0)
            return -1;
    }
    return -1;
}

/* A copy of the journal in each folder the outputs go in. */
static relief_status journal_create(relief_outputs *o, relief_error *err)
{
    char token[7];
    for (size_t i = 0; i < o->n; ++i) {
        const char *name;
        char *dir = relief_output_split(o->e[i].target, &name);
        int rc = dir ? 0 : (errno = ENOMEM, -1);
        if (dir && !seen_folder(o, i, dir) && (rc = journal_open(o, dir, token)) == 0)
            o->journal_entry[o->n_journal - 1] = i;
        free(dir);
        if (rc != 0)
            return relief_fail_errno(err, errno, o->e[i].shown, "cannot create a journal "
                                     "beside it");
    }
    return RELIEF_OK;
}

/* The journal written and synced in every folder, the primary last. */
static relief_status journal_write(relief_outputs *o, relief_error *err)
{
    relief_status st = step(o, "journal", o->e[0].shown, err);
    if (st == RELIEF_OK)
        st = journal_create(o, err);
    for (size_t j = o->n_journal; st == RELIEF_OK && j-- > 0;)
        /* A full disk there is told with an output of that folder. */
        st = relief_output_fill(o->journal_fd[j], o->e[o->journal_entry[j]].shown,
                                journal_text, o, err);
    for (size_t j = 0; st == RELIEF_OK && j < o->n_journal; ++j)
        relief_output_sync_dir_of(o->journal[j]);
    return st;
}

/* Remove the journal's copies, the primary first (a copy left alone then
 * says: rolled back or committed, nothing to restore). */
static void journal_remove(relief_outputs *o)
{
    for (size_t j = 0; j < o->n_journal; ++j) {
        unlink(o->journal[j]);
        relief_output_sync_dir_of(o->journal[j]);
    }
}

/* ------------------------------------------------ placing, rolling back */

/* Is `path` there with the identity dev/ino? */
static int is_it(const char *path, unsigned long long dev, unsigned long long ino)
{
    struct stat sb;
    return lstat(path, &sb) == 0 && (unsigned long long)sb.st_dev == dev &&
           (unsigned long long)sb.st_ino == ino;
}

/* Put one output back as it was before its commit, from any point of it:
 * the previous file (or folder) from its backup, or, when there was none,
 * no file where this commit's stands; the temporary gone. Safe to repeat. */
static void roll_back(int folder, const char *target, const char *staged, const char *backup,
                      unsigned long long dev, unsigned long long ino)
{
    struct stat sb;
    const int ours = is_it(target, dev, ino);
    if (lstat(backup, &sb) == 0) {
        if (folder && ours)
            rename(target, staged);
        /* A file's backup may be a second link to the target itself: then
         * rename does nothing and the link goes. */
        if (rename(backup, target) == 0 && !folder)
            unlink(backup);
    } else if (ours) {
        relief_output_remove_flat(target);
    }
    if (lstat(staged, &sb) == 0)
        relief_output_remove_flat(staged);
}

/* Keep what stands at e's target under its backup name, then move the
 * staged output there. */
static relief_status place(relief_outputs *o, const entry *e, relief_error *err)
{
    struct stat sb;
    relief_status st = RELIEF_OK;
    if (lstat(e->target, &sb) == 0) {
        /* A file keeps a second link, so the target never goes missing;
         * a folder (or a file system without links) is moved aside. */
        if ((st = step(o, "link", e->shown, err)) == RELIEF_OK &&
            (e->folder || link(e->target, e->backup) != 0) &&
            rename(e->target, e->backup) != 0)
            st = relief_fail_errno(err, errno, e->shown, "cannot keep the previous file while "
                                   "the new one is moved into place");
    } else if (errno != ENOENT) {
        st = relief_fail_errno(err, errno, e->shown, "cannot inspect");
    }
    if (st == RELIEF_OK && (st = step(o, "rename", e->shown, err)) == RELIEF_OK &&
        rename(e->staged, e->target) != 0)
        st = relief_fail_errno(err, errno, e->shown, "cannot move the finished output into "
                               "place");
    return st;
}

/* Every folder output's previous self may be replaced (its check). */
static relief_status check_folders(const relief_outputs *o, relief_error *err)
{
    for (size_t i = 0; i < o->n; ++i) {
        const entry *e = &o->e[i];
        struct stat sb;
        if (e->folder && e->replaceable && lstat(e->target, &sb) == 0 &&
            !e->replaceable(e->shown, err))
            return err->status;
    }
    return RELIEF_OK;
}

/* One file alone needs no journal: a rename is whole. */
static relief_status commit_one(relief_outputs *o, relief_error *err)
{
    entry *e = &o->e[0];
    relief_status st = step(o, "rename", e->shown, err);
    if (st == RELIEF_OK && rename(e->staged, e->target) != 0)
        st = relief_fail_errno(err, errno, e->shown, "cannot move the finished file into "
                               "place");
    if (st == RELIEF_OK)
        relief_output_sync_dir_of(e->target);
    return st;
}

/* The journal, every output placed, and the commit's point: the removal
 * of the primary journal. */
static relief_status commit_all(relief_outputs *o, relief_error *err)
{
    relief_status st = check_folders(o, err);
    if (st == RELIEF_OK)
        st = journal_write(o, err);
    for (size_t i = 0; i < o->n && st == RELIEF_OK; ++i)
        st = place(o, &o->e[i], err);
    for (size_t i = 0; i < o->n && st == RELIEF_OK; ++i)
        relief_output_sync_dir_of(o->e[i].target);
    if (st == RELIEF_OK && (st = step(o, "commit", o->e[0].shown, err)) == RELIEF_OK &&
        unlink(o->journal[0]) != 0)
        st = relief_fail_errno(err, errno, o->e[0].shown, "cannot complete the commit");
    if (st == RELIEF_OK)
        relief_output_sync_dir_of(o->journal[0]);
    return st;
}

static void outputs_free(relief_outputs *o)
{
    for (size_t i = 0; i < MAX_ENTRIES; ++i) {
        entry_free(&o->e[i]);
        if (o->journal_fd[i] >= 0)
            close(o->journal_fd[i]);
        free(o->journal[i]);
    }
    free(o);
}

relief_status relief_outputs_commit(relief_outputs *o, relief_error *err)
{
    relief_status st;
    RELIEF_ENTRY_ERR(err);
    if (!o)
        return relief_fail(err, RELIEF_E_USAGE, "relief_outputs_commit: NULL");
    st = o->n == 1 && !o->e[0].folder ? commit_one(o, err) : o->n ? commit_all(o, err)
                                                                 : RELIEF_OK;
    /* Past the commit's point a failure or a kill leaves the new outputs
     * in place and only temporaries, which a later run removes. */
    if (st == RELIEF_OK && o->n_journal)
        (void)step(o, "cleanup", o->e[0].shown, err);
    for (size_t i = o->n; i-- > 0;) {
        const entry *e = &o->e[i];
        if (st != RELIEF_OK)
            roll_back(e->folder, e->target, e->staged, e->backup, e->dev, e->ino);
        else if (o->n_journal)
            relief_output_remove_flat(e->backup);
    }
    journal_remove(o);
    outputs_free(o);
    return st;
}

void relief_outputs_abort(relief_outputs *o)
{
    if (!o)
        return;
    for (size_t i = 0; i < o->n; ++i) {
        if (o->e[i].staged)
            relief_output_remove_flat(o->e[i].staged);
        relief_output_sync_dir_of(o->e[i].staged ? o->e[i].staged : o->e[i].target);
    }
    journal_remove(o);
    outputs_free(o);
}

relief_status relief_staged_folder_commit(relief_staged_folder *s,
                                          int (*replaceable)(const char *path,
                                                             relief_error *err),
                                          relief_error *err)
{
    relief_outputs *o;
    relief_status st;
    RELIEF_ENTRY_ERR(err);
    if ((st = relief_outputs_begin(&o, err)) != RELIEF_OK) {
        relief_staged_folder_abort(s);
        return st;
    }
    if ((st = relief_outputs_folder(o, &s, replaceable, err)) != RELIEF_OK) {
        relief_outputs_abort(o);
        return st;
    }
    return relief_outputs_commit(o, err);
}

/* ------------------------------------------------------------- recovery */

/* The value of a hexadecimal digit, or -1. */
static int hex(char c)
{
    return c >= '0' && c <= '9' ? c - '0' : c >= 'A' && c <= 'F' ? c - 'A' + 10
                                          : c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
}

/* Undo put_path in place; 0 on a malformed escape. */
static int unescape(char *s)
{
    char *w = s;
    for (; *s; ++s, ++w) {
        int hi, lo;
        if (*s != '%') {
            *w = *s;
            continue;
        }
        if ((hi = hex(s[1])) < 0 || (lo = hex(s[2])) < 0 || (hi | lo) == 0)
            return 0;
        *w = (char)(16 * hi + lo);
        s += 2;
    }
    *w = '\0';
    return 1;
}

/* A journal's text, parsed in place: its copies and entries. */
typedef struct journal {
    char *copy[MAX_ENTRIES];
    size_t n_copies;
    struct {
        int folder;
        char *target, *staged, *backup;
        unsigned long long dev, ino;
    } e[MAX_ENTRIES];
    size_t n;
} journal;

/* Is `path` "<the folder of target>/.relief-ROLE-..."? A journal only ever
 * names relief's temporaries beside their targets. */
static int beside(const char *path, const char *target, const char *role)
{
    const char *slash = strrchr(path, '/'), *tslash = strrchr(target, '/');
    char head[16];
    snprintf(head, sizeof head, ".relief-%s-", role);
    return slash && tslash && slash - path == tslash - target &&
           strncmp(path, target, (size_t)(slash - path)) == 0 &&
           strncmp(slash + 1, head, strlen(head)) == 0;
}

/* One line of a journal into j; 0 when malformed. */
static int parse_line(char *line, journal *j)
{
    char *save = NULL, *kind = strtok_r(line, " ", &save), *f[5];
    int n = 0;
    while (n < 5 && (f[n] = strtok_r(NULL, " ", &save)) != NULL)
        ++n;
    if (kind && strcmp(kind, "journal") == 0 && n == 1 && j->n_copies < MAX_ENTRIES)
        return unescape(f[0]) && (j->copy[j->n_copies++] = f[0]) != NULL;
    if (!kind || (strcmp(kind, "file") != 0 && strcmp(kind, "folder") != 0) || n != 5 ||
        j->n == MAX_ENTRIES || !unescape(f[0]) || !unescape(f[1]) || !unescape(f[2]))
        return 0;
    if (!beside(f[1], f[0], "tmp") || !beside(f[2], f[0], "old"))
        return 0;
    j->e[j->n].folder = kind[1] == 'o';
    j->e[j->n].target = f[0], j->e[j->n].staged = f[1], j->e[j->n].backup = f[2];
    j->e[j->n].dev = strtoull(f[3], NULL, 10), j->e[j->n].ino = strtoull(f[4], NULL, 10);
    ++j->n;
    return 1;
}

/* Parse a whole journal (text, NUL-ended); 1 when complete ("end"). */
static int parse_journal(char *text, journal *j)
{
    char *save = NULL, *line = strtok_r(text, "\n", &save);
    memset(j, 0, sizeof *j);
    if (!line || strcmp(line, JOURNAL_MAGIC) != 0)
        return 0;
    while ((line = strtok_r(NULL, "\n", &save)) != NULL) {
        if (strcmp(line, "end") == 0)
            return j->n_copies > 0;
        if (!parse_line(line, j))
            return 0;
    }
    return 0;
}

/* A dead commit's journal at `path`, open on fd (locked): rolled back when
 * its primary still stands, else only its temporaries removed; then its
 * copies go. A journal cut short (a kill while it was written) came
 * before any output moved: it only goes. */
static void recover(const char *path, int fd)
{
    struct stat sb;
    char *text = NULL;
    ssize_t n = -1;
    journal j;
    /* Read whole: one cut short by a short read would pass for one a kill
     * cut short, and go without its roll back. */
    if (fstat(fd, &sb) == 0 && sb.st_size < (off_t)(MAX_ENTRIES * 4 * 3 * PATH_MAX) &&
        (text = malloc((size_t)sb.st_size + 1)) != NULL)
        n = pread(fd, text, (size_t)sb.st_size, 0);
    if (!text || n != (ssize_t)sb.st_size) { /* unreadable now: left for a later run */
        free(text);
        return;
    }
    text[n] = '\0';
    if (n == 0 || !parse_journal(text, &j)) {
        free(text);
        unlink(path);
        return;
    }
    if (lstat(j.copy[0], &sb) == 0) {
        for (size_t i = j.n; i-- > 0;)
            roll_back(j.e[i].folder, j.e[i].target, j.e[i].staged, j.e[i].backup, j.e[i].dev,
                      j.e[i].ino);
    } else {
        for (size_t i = 0; i < j.n; ++i) {
            relief_output_remove_flat(j.e[i].backup);
            relief_output_remove_flat(j.e[i].staged);
        }
    }
    for (size_t c = 0; c < j.n_copies; ++c)
        unlink(j.copy[c]);
    unlink(path); /* in case the folder was named otherwise there */
    free(text);
}

/* ---------------------------------------------------------------- tidy */

/* Parse ".relief-ROLE-PID-TOKEN[.NAME]": *role (its first letter: t, o or
 * l), *pid and where NAME starts ("" when none); 0 when not that form. */
static int temp_form(const char *entry, char *role, long *pid, const char **name)
{
    const char *p = entry;
    char *end;
    if (strncmp(p, ".relief-", 8) != 0)
        return 0;
    p += 8;
    if (strncmp(p, "tmp-", 4) != 0 && strncmp(p, "old-", 4) != 0 && strncmp(p, "log-", 4) != 0)
        return 0;
    *role = p[0];
    *pid = strtol(p + 4, &end, 10);
    if (end == p + 4 || *pid <= 0 || *end != '-' || strlen(end + 1) < 6)
        return 0;
    for (int i = 1; i <= 6; ++i)
        if (!((end[i] >= '0' && end[i] <= '9') || (end[i] >= 'A' && end[i] <= 'Z') ||
              (end[i] >= 'a' && end[i] <= 'z')))
            return 0;
    *name = end[7] == '.' ? end + 8 : end + 7;
    return end[7] == '.' || end[7] == '\0';
}

/* Does the process `pid` live (or belong to someone else)? */
static int alive(long pid)
{
    return pid == (long)getpid() || kill((pid_t)pid, 0) == 0 || errno == EPERM;
}

/* Open `path` (ours, not a link) and take its lock, which a living writer
 * holds: the fd, or -1 when it is not free to take. */
static int take_dead(const char *path)
{
    struct stat sb;
    int fd;
    if (lstat(path, &sb) != 0 || sb.st_uid != geteuid() ||
        !(S_ISREG(sb.st_mode) || S_ISDIR(sb.st_mode)))
        return -1;
    fd = open(path, O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
    if (fd >= 0 && flock(fd, LOCK_EX | LOCK_NB) != 0 && errno == EWOULDBLOCK) {
        close(fd);
        return -1;
    }
    return fd;
}

/* One pass over dir: the journals (`want` 'l') or the other temporaries
 * of dead writers. */
static void tidy_pass(const char *dir, char want)
{
    DIR *d = opendir(dir);
    struct dirent *de;
    while (d && (de = readdir(d)) != NULL) {
        char role, path[PATH_MAX];
        const char *kept;
        long pid;
        int fd;
        if (!temp_form(de->d_name, &role, &pid, &kept) || (role == 'l') != (want == 'l'))
            continue;
        if (alive(pid) ||
            (size_t)snprintf(path, sizeof path, "%s/%s", dir, de->d_name) >= sizeof path ||
            (fd = take_dead(path)) < 0)
            continue;
        if (role == 'l')
            recover(path, fd);
        else
            relief_output_remove_flat(path);
        close(fd);
    }
    if (d)
        closedir(d);
}

void relief_output_tidy(const char *dir)
{
    tidy_pass(dir, 'l');
    tidy_pass(dir, 't');
}
