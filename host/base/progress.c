/* Progress and cancellation of an engine call (base/progress.h). */
#include "base/progress.h"

#include <stddef.h>

void relief_progress_init(relief_progress *p, relief_progress_fn fn, void *ctx)
{
    p->fn = fn;
    p->ctx = ctx;
    p->lo = 0.0;
    p->hi = 1.0;
    p->last = 0.0;
    p->cancelled = 0;
}

void relief_progress_stage(relief_progress *p, double lo, double hi)
{
    p->lo = lo < 0.0 ? 0.0 : lo > 1.0 ? 1.0 : lo;
    p->hi = hi < p->lo ? p->lo : hi > 1.0 ? 1.0 : hi;
}

int relief_progress_step(relief_progress *p, double done)
{
    double f;
    if (!p)
        return 0;
    if (p->cancelled || !p->fn)
        return p->cancelled;
    done = done < 0.0 ? 0.0 : done > 1.0 ? 1.0 : done;
    f = p->lo + done * (p->hi - p->lo);
    if (f < p->last)
        f = p->last;
    p->last = f;
    if (p->fn(p->ctx, f) != 0)
        p->cancelled = 1;
    return p->cancelled;
}

int relief_progress_count(relief_progress *p, size_t done, size_t total)
{
    return relief_progress_step(p, total ? (double)done / (double)total : 1.0);
}
