/* The layout of a part's signed lean (pattern_layout.h; pattern.h, 3). */
#include "base/vec3.h"
#include "report/pattern_layout.h"

#include <math.h>


/* The signed lean L = c sin 2 phi at (x, y), in nodes, bilinear between
 * the nodes around it (those of weight 0 need not have a tensor); (c2, s2)
 * = (cos 2 theta0, sin 2 theta0). 0 when a node it needs has no tensor or
 * is off the grid. Interpolating z, not phi, keeps the wrap at +-90
 * degrees out of it. */
static int lean_at(const part_grid *gr, const double *z, double c2, double s2, double x,
                   double y, double *L)
{
    const double fx = floor(x), fy = floor(y), a = x - fx, b = y - fy;
    const long i = (long)fx, j = (long)fy;
    double zc = 0.0, zs = 0.0;
    for (int dj = 0; dj < 2; ++dj)
        for (int di = 0; di < 2; ++di) {
            const double w = (di ? a : 1.0 - a) * (dj ? b : 1.0 - b);
            const long ii = i + di, jj = j + dj;
            size_t n;
            if (w == 0.0)
                continue;
            if (ii < 0 || jj < 0 || ii >= (long)gr->nx || jj >= (long)gr->ny)
                return 0;
            n = (size_t)jj * gr->nx + (size_t)ii;
            if (isnan(z[2 * n]))
                return 0;
            zc += w * z[2 * n];
            zs += w * z[2 * n + 1];
        }
    *L = zs * c2 - zc * s2;
    return 1;
}

void pattern_layout(const part_grid *gr, const double *z, double spacing,
                    relief_pattern_part *out)
{
    const size_t nx = gr->nx, nn = gr->nx * gr->ny;
    const double sd = sin(2.0 * RELIEF_PATTERN_LEAN_FLOOR * RELIEF_PI / 180.0);
    double sc = 0.0, ss = 0.0, sw = 0.0, sp = 0.0, theta0, c2, s2, lag, gam[2];

    out->dominant = out->lean_rms = out->lean_across = NAN;
    for (size_t n = 0; n < nn; ++n)
        if (!isnan(z[2 * n])) {
            sc += z[2 * n];
            ss += z[2 * n + 1];
        }
    if (!(sc * sc + ss * ss > 0.0))
        return; /* no tensor, or orientations that cancel exactly */
    theta0 = 0.5 * atan2(ss, sc);
    c2 = cos(2.0 * theta0);
    s2 = sin(2.0 * theta0);
    out->dominant = fmod(theta0 * 180.0 / RELIEF_PI + 180.0, 180.0);

    for (size_t n = 0; n < nn; ++n) {
        double zr, L, c, phi;
        if (isnan(z[2 * n]))
            continue;
        zr = z[2 * n] * c2 + z[2 * n + 1] * s2;
        L = z[2 * n + 1] * c2 - z[2 * n] * s2;
        c = hypot(zr, L);
        phi = 0.5 * atan2(L, zr);
        sw += c;
        sp += c * phi * phi;
    }
    if (sw > 0.0)
        out->lean_rms = sqrt(sp / sw) * 180.0 / RELIEF_PI;

    if (!(spacing > 0.0) || !isfinite(spacing))
        return;
    lag = spacing / gr->g;
    /* gam[0] across the ridges (along theta0, the dominant gradient),
     * gam[1] along them: the mean squared change of L over one spacing. */
    for (int d = 0; d < 2; ++d) {
        const double ex = d ? -sin(theta0) : cos(theta0), ey = d ? cos(theta0) : sin(theta0);
        double s = 0.0;
        size_t count = 0;
        for (size_t n = 0; n < nn; ++n) {
            const double x = (double)(n % nx), y = (double)(n / nx);
            double La, Lb;
            if (isnan(z[2 * n]) || !lean_at(gr, z, c2, s2, x, y, &La) ||
                !lean_at(gr, z, c2, s2, x + lag * ex, y + lag * ey, &Lb))
                continue;
            s += (Lb - La) * (Lb - La);
            ++count;
        }
        if (count < RELIEF_PATTERN_MIN_NODES)
            return;
        gam[d] = s / (double)count;
    }
    out->lean_across = gam[0] / (gam[0] + gam[1] + 2.0 * sd * sd);
}
