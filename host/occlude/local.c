/* Each point's height above the background near it (occlude.h). A plane
 * fitted to a whole floor or wall misses its gentle bends by more than the
 * camera's noise: the living-room sequence's floor lies 10 mm under its
 * plane by the chair and 20 to 60 mm over it by the wall, so its measured
 * noise (a = 0.00244, a margin of 35 mm at 1.9 m) hides the chair's runners
 * 20 to 30 mm above it. Against the mean of the plane's own points in a
 * square around it, the floor's residual is 0.00124 z^2 and the runners
 * stand 3 to 6 of those sigmas over it. */
#include "occlude/occlude.h"

#include <math.h>
#include <stdlib.h>

#include "base/error.h"
#include "base/linalg.h"

/* The square the local level is the mean over, pixels: wide against a
 * runner (a few pixels), narrow against a floor's bend. */
#define LOCAL_WINDOW 31
/* The points that make the level: within this many of the plane's own
 * sigmas of it, the margin: every point of it that is no seed. With 2, the
 * level lagged under the ramp by which SUN's partition rises to what is
 * marked, and the growth ate 19 % of it (4 % with the margin); a runner
 * raises the level by its share of the square only. */
#define LOCAL_BAND 4.0
/* A level needs this share of the window on the plane; else the plane. */
#define LOCAL_MIN_SHARE 0.05
/* The local noise is at least this share of the first plane's, as
 * background.c's plane noise. */
#define LOCAL_FLOOR_SHARE 0.5

/* Box sums of v over the LOCAL_WINDOW square (zero outside), in place;
 * tmp: w x h scratch. */
static void box_sum(double *v, double *tmp, int w, int h)
{
    int r = LOCAL_WINDOW / 2;
    for (int y = 0; y < h; ++y) {
        const double *row = v + (size_t)y * w;
        double acc = 0.0;
        for (int x = 0; x < r && x < w; ++x)
            acc += row[x];
        for (int x = 0; x < w; ++x) {
            if (x + r < w)
                acc += row[x + r];
            if (x - r - 1 >= 0)
                acc -= row[x - r - 1];
            tmp[(size_t)y * w + x] = acc;
        }
    }
    for (int x = 0; x < w; ++x) {
        double acc = 0.0;
        for (int y = 0; y < r && y < h; ++y)
            acc += tmp[(size_t)y * w + x];
        for (int y = 0; y < h; ++y) {
            if (y + r < h)
                acc += tmp[(size_t)(y + r) * w + x];
            if (y - r - 1 >= 0)
                acc -= tmp[(size_t)(y - r - 1) * w + x];
            v[(size_t)y * w + x] = acc;
        }
    }
}

/* Is pixel i one of plane k's level points? */
static int on_level(const occ_scene *s, size_t i, int k)
{
    double c = s->clearance[i];
    return s->near[i] == k && isfinite(c) && fabs(c) <= LOCAL_BAND * occ_sigma_at(s, i);
}

/* s->lift on plane k's pixels: the clearance less the local level. */
static void plane_level(occ_scene *s, int k, double *sum, double *cnt, double *tmp)
{
    size_t n = (size_t)s->width * s->height;
    double least = LOCAL_MIN_SHARE * LOCAL_WINDOW * LOCAL_WINDOW;
    for (size_t i = 0; i < n; ++i) {
        int in = on_level(s, i, k);
        sum[i] = in ? s->clearance[i] : 0.0;
        cnt[i] = in;
    }
    box_sum(sum, tmp, s->width, s->height);
    box_sum(cnt, tmp, s->width, s->height);
    for (size_t i = 0; i < n; ++i)
        if (s->near[i] == k && isfinite(s->clearance[i]))
            s->lift[i] = (float)(s->clearance[i] - (cnt[i] >= least ? sum[i] / cnt[i] : 0.0));
}

/* Plane k's local noise: the level points' median |lift| / z^2 as a
 * standard deviation's coefficient; d: n scratch. */
static double plane_local_noise(const occ_scene *s, int k, double *d)
{
    size_t n = (size_t)s->width * s->height, m = 0;
    for (size_t i = 0; i < n; ++i)
        if (on_level(s, i, k)) {
            double z = s->pts[3 * i + 2];
            d[m++] = fabs(s->lift[i]) / (z * z);
        }
    return fmax(m ? 1.4826 * relief_select_median(d, m) : s->plane[k].noise,
                LOCAL_FLOOR_SHARE * s->noise);
}

relief_status occ_local_lift(occ_scene *s, relief_error *err)
{
    size_t n = (size_t)s->width * s->height;
    double *sum = malloc(n * sizeof *sum), *cnt = malloc(n * sizeof *cnt);
    double *tmp = malloc(n * sizeof *tmp);
    relief_status st = RELIEF_OK;
    s->lift = malloc(n * sizeof *s->lift);
    if (!sum || !cnt || !tmp || !s->lift) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the local levels' %zu pixels", n);
    } else {
        for (size_t i = 0; i < n; ++i)
            s->lift[i] = NAN;
        for (int k = 0; k < s->n_planes; ++k) {
            plane_level(s, k, sum, cnt, tmp);
            s->plane[k].local_noise = plane_local_noise(s, k, sum);
        }
    }
    free(sum);
    free(cnt);
    free(tmp);
    return st;
}
