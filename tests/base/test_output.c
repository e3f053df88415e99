/* base/output: several outputs committed together across a failure or a
 * kill at every step, rolled back or finished by the next run's tidying;
 * paths a journal must escape; names cut to fit NAME_MAX; what tidying
 * leaves alone. */
#define _GNU_SOURCE
#include <dirent.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "base/output.h"
#include "check.h"

/* The bytes of `path` into buf ("" when it is not there). */
static void slurp(const char *path, char *buf, size_t cap)
{
    FILE *f = fopen(path, "rb");
    size_t n = f ? fread(buf, 1, cap - 1, f) : 0;
    buf[n] = '\0';
    if (f)
        fclose(f);
}

/* dir/name into out (PATH_MAX bytes). */
static void join(char *out, const char *dir, const char *name)
{
    CHECK(snprintf(out, PATH_MAX, "%s/%s", dir, name) < PATH_MAX, "a path too long");
}

static void put(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    CHECK(f && fputs(text, f) >= 0 && fclose(f) == 0, "write %s", path);
}

/* How many entries of `dir` start with ".relief-" (the marker aside). */
static int temporaries(const char *dir)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    int n = 0;
    while (d && (e = readdir(d)) != NULL)
        n += strncmp(e->d_name, ".relief-", 8) == 0;
    if (d)
        closedir(d);
    return n;
}

static relief_status text_sink(relief_sink *s, void *ctx, relief_error *err)
{
    (void)err;
    fputs((const char *)ctx, s->f);
    return RELIEF_OK;
}

typedef struct hook_ctx {
    unsigned at;   /* the step to act on */
    int kill;      /* 1: SIGKILL there, 0: fail it */
    char what[16]; /* what the step was */
} hook_ctx;

static int hook(void *ctx, unsigned step, const char *what)
{
    hook_ctx *h = ctx;
    if (step != h->at)
        return 0;
    snprintf(h->what, sizeof h->what, "%s", what);
    if (h->kill)
        raise(SIGKILL);
    return 1;
}

/* Commit "new A" to a and "new B" to b (b's folder may differ), with the
 * hook at step `at`. Returns the status; *what the step's name. */
static relief_status commit_two(const char *a, const char *b, unsigned at, int kill,
                                char *what)
{
    relief_outputs *o = NULL;
    relief_error err = {0};
    hook_ctx h = {at, kill, ""};
    relief_status st = relief_outputs_begin(&o, &err);
    if (st == RELIEF_OK) {
        relief_outputs_set_hook(o, hook, &h);
        st = relief_outputs_file(o, a, text_sink, "new A", &err);
        if (st == RELIEF_OK)
            st = relief_outputs_file(o, b, text_sink, "new B", &err);
        if (st == RELIEF_OK)
            st = relief_outputs_commit(o, &err);
        else
            relief_outputs_abort(o);
    }
    if (what)
        snprintf(what, 16, "%s", h.what);
    return st;
}

/* Every step killed in a child: after the next run's tidying of both
 * folders, both files old (before the commit's point) or both new (at its
 * cleanup), and no temporary left. */
static void kill_each_step(const char *da, const char *db)
{
    char a[PATH_MAX], b[PATH_MAX], ta[64], tb[64];
    join(a, da, "out one.ply");
    join(b, db, "rep%.json");
    for (unsigned at = 1; at < 20; ++at) {
        int status = 0;
        pid_t pid;
        put(a, "old A");
        put(b, "old B");
        if ((pid = fork()) == 0)
            _exit(commit_two(a, b, at, 1, NULL) == RELIEF_OK ? 0 : 1);
        waitpid(pid, &status, 0);
        relief_output_tidy(da);
        relief_output_tidy(db);
        slurp(a, ta, sizeof ta);
        slurp(b, tb, sizeof tb);
        if (WIFEXITED(status)) { /* past every step */
            CHECK(WEXITSTATUS(status) == 0 && strcmp(ta, "new A") == 0 &&
                  strcmp(tb, "new B") == 0, "a whole commit: %s, %s", ta, tb);
            CHECK(at > 6, "only %u steps", at);
            break;
        }
        CHECK((strcmp(ta, "old A") == 0 && strcmp(tb, "old B") == 0) ||
              (strcmp(ta, "new A") == 0 && strcmp(tb, "new B") == 0),
              "killed at step %u: a mix, '%s' and '%s'", at, ta, tb);
        CHECK(temporaries(da) == 0 && temporaries(db) == 0,
              "killed at step %u: %d and %d temporaries left", at, temporaries(da),
              temporaries(db));
    }
}

/* Every step failed in the process: both old at once, nothing left. */
static void fail_each_step(const char *da, const char *db)
{
    char a[PATH_MAX], b[PATH_MAX], ta[64], tb[64], what[16];
    join(a, da, "x.ply");
    join(b, db, "y.json");
    for (unsigned at = 1; at < 20; ++at) {
        relief_status st;
        put(a, "old A");
        put(b, "old B");
        st = commit_two(a, b, at, 0, what);
        slurp(a, ta, sizeof ta);
        slurp(b, tb, sizeof tb);
        if (st == RELIEF_OK && !what[0])
            break;
        if (strcmp(what, "cleanup") == 0) /* past the commit's point: it stands */
            CHECK(st == RELIEF_OK && strcmp(ta, "new A") == 0, "failed cleanup: %s", ta);
        else
            CHECK(st == RELIEF_E_SYSTEM && strcmp(ta, "old A") == 0 &&
                  strcmp(tb, "old B") == 0, "failed at step %u (%s): %s, %s, '%s' '%s'",
                  at, what, relief_status_name(st), "", ta, tb);
        CHECK(temporaries(da) == 0 && temporaries(db) == 0, "failed at %u: temporaries",
              at);
    }
}

/* A new file's commit killed: no file where there was none. */
static void kill_new_files(const char *dir)
{
    char a[PATH_MAX], b[PATH_MAX];
    join(a, dir, "new1");
    join(b, dir, "new2");
    for (unsigned at = 1; at < 20; ++at) {
        int status = 0;
        struct stat sb;
        pid_t pid;
        unlink(a), unlink(b);
        if ((pid = fork()) == 0)
            _exit(commit_two(a, b, at, 1, NULL) == RELIEF_OK ? 0 : 1);
        waitpid(pid, &status, 0);
        relief_output_tidy(dir);
        if (WIFEXITED(status))
            break;
        CHECK((stat(a, &sb) != 0 && stat(b, &sb) != 0) ||
              (stat(a, &sb) == 0 && stat(b, &sb) == 0), "step %u: one new file of two", at);
        CHECK(temporaries(dir) == 0, "step %u: temporaries", at);
    }
    unlink(a), unlink(b);
}

/* What tidying must leave: a live process's temporary, names not of the
 * form, the report marker; and what it takes: a dead writer's. */
static void tidy_leaves(const char *dir)
{
    char live[PATH_MAX], dead[PATH_MAX], odd[PATH_MAX], marker[PATH_MAX];
    struct stat sb;
    char name[64];
    snprintf(name, sizeof name, ".relief-tmp-%ld-AbC123.x.ply", (long)getpid());
    join(live, dir, name);
    snprintf(name, sizeof name, ".relief-tmp-%d-AbC123.x.ply", INT_MAX - 7);
    join(dead, dir, name);
    join(odd, dir, ".relief-tmp-notapid.x");
    join(marker, dir, ".relief-report");
    put(live, "live"), put(dead, "dead"), put(odd, "odd"), put(marker, "m");
    relief_output_tidy(dir);
    CHECK(stat(live, &sb) == 0, "a living writer's temporary was removed");
    CHECK(stat(dead, &sb) != 0, "a dead writer's temporary was kept");
    CHECK(stat(odd, &sb) == 0 && stat(marker, &sb) == 0, "a name of another form was removed");
    unlink(live), unlink(odd), unlink(marker);
}

/* A name at NAME_MAX: its temporary's name is cut to fit, the write and
 * the commit work. */
static void long_name(const char *dir)
{
    char path[PATH_MAX], name[NAME_MAX + 1], got[PATH_MAX];
    relief_error err = {0};
    memset(name, 'n', NAME_MAX - 4);
    memcpy(name + NAME_MAX - 4, ".ply", 5);
    join(path, dir, name);
    CHECK(relief_output_file(path, text_sink, "long", &err) == RELIEF_OK, "%s", err.message);
    slurp(path, got, sizeof got);
    CHECK(strcmp(got, "long") == 0 && temporaries(dir) == 0, "a name at NAME_MAX: '%s'", got);
    join(got, dir, "short");
    CHECK(commit_two(path, got, 0, 0, NULL) == RELIEF_OK, "a commit of a name at NAME_MAX");
    CHECK(temporaries(dir) == 0, "a commit of a name at NAME_MAX left temporaries");
    unlink(path);
    unlink(got);
}

int main(void)
{
    char root[] = "/tmp/relief-output-XXXXXX", da[PATH_MAX], db[PATH_MAX];
    CHECK(mkdtemp(root) != NULL, "mkdtemp");
    /* Folder names the journal must escape: a space, '%', a newline. */
    snprintf(da, sizeof da, "%s/a b%%c", root);
    join(db, root, "d\ne");
    CHECK(mkdir(da, 0700) == 0 && mkdir(db, 0700) == 0, "mkdir");
    kill_each_step(da, db);
    kill_each_step(da, da);
    fail_each_step(da, db);
    kill_new_files(da);
    tidy_leaves(da);
    long_name(db);
    if (!check_failures) {
        char cmd[PATH_MAX + 16];
        snprintf(cmd, sizeof cmd, "rm -rf '%s'", root);
        if (system(cmd) != 0) {
        }
    }
    return check_result();
}
