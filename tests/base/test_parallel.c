/* The threads relief starts follow the CPUs it may run on (issue 60):
 * relief_cpus_available (base/parallel.h) is the affinity mask's count,
 * and under an affinity of one CPU (as `taskset -c 0`, a container's
 * cpuset or a one-core worker set it) it is 1, the pool's default is 1
 * thread, and a pool started with the default starts no thread at all.
 * An asked count (relief_run_options.threads) is taken as it is, up to
 * RELIEF_POOL_MAX. Skips (77) where the affinity cannot be set. */
#define _GNU_SOURCE /* sched_getaffinity, sched_setaffinity */
#include <dirent.h>
#include <sched.h>
#include <stdio.h>

#include "check.h"
#include "base/parallel.h"
#include "base/pool.h"

/* The threads of this process (/proc/self/task), or -1 without /proc. */
static int process_threads(void)
{
    DIR *d = opendir("/proc/self/task");
    struct dirent *e;
    int n = 0;
    if (!d)
        return -1;
    while ((e = readdir(d)))
        n += e->d_name[0] != '.';
    closedir(d);
    return n;
}

static void count(void *ctx, int k, int n)
{
    (void)k;
    (void)n;
    __atomic_add_fetch((int *)ctx, 1, __ATOMIC_RELAXED);
}

/* Under one CPU: every default is one thread, and none is started. */
static void one_cpu(void)
{
    relief_error err = {0};
    relief_pool *p = NULL;
    int before = process_threads(), parts = 0;
    CHECK(relief_cpus_available() == 1, "%d CPUs under an affinity of one",
          relief_cpus_available());
    CHECK(relief_pool_default_threads() == 1, "default %d threads",
          relief_pool_default_threads());
    CHECK(relief_pool_threads_for(0) == 1, "0 asks %d threads", relief_pool_threads_for(0));
    CHECK(relief_pool_threads_for(3) == 3, "3 asked, %d given", relief_pool_threads_for(3));
    CHECK(relief_pool_create(relief_pool_threads_for(0), &p, &err) == RELIEF_OK, "%s",
          err.message);
    CHECK(relief_pool_threads(p) == 1, "a default pool of %d threads", relief_pool_threads(p));
    CHECK(before < 0 || process_threads() == before, "the pool started %d threads",
          process_threads() - before);
    relief_pool_run(p, 8, count, &parts);
    CHECK(parts == 1, "a job ran in %d parts on a one-thread pool", parts);
    relief_pool_destroy(p);
}

int main(void)
{
    cpu_set_t all, one;
    int first = -1;
    if (sched_getaffinity(0, sizeof all, &all) != 0) {
        printf("skipped: sched_getaffinity failed\n");
        return 77;
    }
    /* With the whole mask: its count, clamped as the pool says. */
    CHECK(relief_cpus_available() == CPU_COUNT(&all), "%d CPUs, the mask has %d",
          relief_cpus_available(), CPU_COUNT(&all));
    CHECK(relief_pool_threads_for(RELIEF_POOL_MAX + 5) == RELIEF_POOL_MAX, "not clamped");
    for (int c = 0; c < CPU_SETSIZE && first < 0; ++c)
        if (CPU_ISSET(c, &all))
            first = c;
    CPU_ZERO(&one);
    CPU_SET(first, &one);
    if (first < 0 || sched_setaffinity(0, sizeof one, &one) != 0) {
        printf("skipped: cannot set the affinity to CPU %d\n", first);
        return 77;
    }
    one_cpu();
    CHECK(sched_setaffinity(0, sizeof all, &all) == 0, "the affinity not restored");
    CHECK(relief_cpus_available() == CPU_COUNT(&all), "%d CPUs after restoring %d",
          relief_cpus_available(), CPU_COUNT(&all));
    return check_result();
}
