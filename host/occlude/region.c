/* Each background plane's region and the share of it the mask marks
 * (occlude.h): the measure of a support surface kept as background (issue
 * 63 asks that no table or floor be over 25 % marked). The region is the
 * plane's connected support, not its whole band: a band 3 sigma thick also
 * cuts the objects that cross it, in specks that are no part of the
 * surface. */
#include "occlude/occlude.h"

#include <math.h>
#include <stdlib.h>

#include "base/union_find.h"

/* A component of the band is the plane's support when it holds at least
 * this share of the band's pixels. */
#define SUPPORT_SHARE 0.05
#define REGION_SIGMAS 3.0

static double plane_distance(const relief_occluder_plane *pl, const double *q)
{
    return pl->normal[0] * q[0] + pl->normal[1] * q[1] + pl->normal[2] * q[2] - pl->offset;
}

/* Plane pl's band (in: within REGION_SIGMAS of its own noise) joined into
 * 4-connected components (parent). */
static size_t band_components(const occ_scene *s, const relief_occluder_plane *pl,
                              uint8_t *in, uint32_t *parent)
{
    size_t n = (size_t)s->width * s->height, m = 0;
    for (size_t i = 0; i < n; ++i) {
        const double *q = s->pts + 3 * i;
        double sigma = pl->noise * q[2] * q[2];
        in[i] = isfinite(q[2]) && fabs(plane_distance(pl, q)) <= REGION_SIGMAS * sigma;
        parent[i] = (uint32_t)i;
        m += in[i];
    }
    for (size_t i = 0; i < n; ++i) {
        size_t x = i % (size_t)s->width;
        if (!in[i])
            continue;
        if (x + 1 < (size_t)s->width && in[i + 1])
            relief_uf_join(parent, (uint32_t)i, (uint32_t)(i + 1));
        if (i + (size_t)s->width < n && in[i + s->width])
            relief_uf_join(parent, (uint32_t)i, (uint32_t)(i + s->width));
    }
    return m;
}

void occ_plane_regions(const occ_scene *s, const uint8_t *mask, relief_occluder_plane *planes,
                       int n_planes)
{
    size_t n = (size_t)s->width * s->height;
    uint8_t *in = malloc(n);
    uint32_t *parent = malloc(n * sizeof *parent), *size = calloc(n, sizeof *size);
    for (int k = 0; k < n_planes; ++k) {
        size_t band, region = 0, marked = 0;
        planes[k].region = 0, planes[k].marked = NAN;
        if (!in || !parent || !size)
            continue; /* out of memory: not measured, said as NaN */
        band = band_components(s, &planes[k], in, parent);
        for (size_t i = 0; i < n; ++i)
            size[i] = 0;
        for (size_t i = 0; i < n; ++i)
            size[relief_uf_find(parent, (uint32_t)i)] += in[i];
        for (size_t i = 0; i < n; ++i) {
            if (!in[i] || size[relief_uf_find(parent, (uint32_t)i)] < SUPPORT_SHARE * band)
                continue;
            ++region;
            marked += mask[i] != 0;
        }
        planes[k].region = region;
        planes[k].marked = region ? (double)marked / region : 0.0;
    }
    free(in);
    free(parent);
    free(size);
}
