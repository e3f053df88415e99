/* A frame's background and every pixel's clearance in front of it
 * (occlude.h): planes found by RANSAC that nothing lies behind, or a given
 * mesh drawn into the frame's camera. */
#include "occlude/occlude.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/compare.h"
#include "base/error.h"
#include "base/linalg.h"
#include "base/rng.h"
#include "depth/frame.h"

/* Points a RANSAC hypothesis is scored on (a random subset of them). */
#define SCORE_POINTS 20000
/* A background plane has at most this share of the captured points
 * behind it by more than the margin (the rest: reflections, a doorway). */
#define MAX_BEHIND 0.02
/* Least-squares refits of a plane on its inliers. */
#define REFITS 3
/* The noise a search starts from, sigma(z) = PRIOR_NOISE x z^2: a
 * Kinect's disparity step (1/8 pixel at f = 580 pixels, a 7.5 cm
 * baseline) is z^2 / 348 m. */
#define PRIOR_NOISE (1.0 / 348.0)
/* The smallest noise measured (noise-free synthetic data): 0.1 mm at 1 m. */
#define MIN_NOISE 1e-4
/* A background plane's inliers are a surface: at least this share of
 * their captured right neighbours are inliers too. */
#define MIN_COHERENCE 0.5
/* ... and passes at least this share of the median depth from the camera. */
#define MIN_OFFSET 0.05
/* RANSAC's consensus band and the default margin, in sigma(z). */
#define BAND_SIGMAS 3.0
#define MARGIN_SIGMAS 4.0
/* A plane's own noise is at least this share of the first plane's: a
 * plane seen nearly edge-on (a floor far off) or a smooth painted wall has
 * residuals under the camera's own step, which a margin must still
 * clear. */
#define NOISE_FLOOR_SHARE 0.5

void occ_scene_free(occ_scene *s)
{
    if (!s)
        return;
    free(s->pts);
    free(s->surface);
    free(s->clearance);
    free(s->near);
    free(s->lift);
    memset(s, 0, sizeof *s);
}

/* The pixel ray (x / z, y / z, 1) of pixel i. */
static void ray_of(const occ_scene *s, size_t i, double r[3])
{
    int u = (int)(i % (size_t)s->width), v = (int)(i / (size_t)s->width);
    r[0] = s->cam[0] * u + s->cam[1];
    r[1] = s->cam[2] * v + s->cam[3];
    r[2] = 1.0;
}

static int camera_of(const relief_depth_image *f, const relief_occluder_params *p, double cam[4])
{
    double fx, fy, cx, cy;
    if (p->has_intrinsics) {
        fx = p->intrinsics[0], fy = p->intrinsics[1];
        cx = p->intrinsics[2], cy = p->intrinsics[3];
    } else if (f->xyz) {
        return relief_depth_fit_camera(f, cam);
    } else {
        fx = fy = 525.0 * f->width / 640.0;
        cx = (f->width - 1) / 2.0, cy = (f->height - 1) / 2.0;
    }
    cam[0] = 1.0 / fx, cam[1] = -cx / fx;
    cam[2] = 1.0 / fy, cam[3] = -cy / fy;
    return 1;
}

/* A placeholder is the colour of over half the missing points (a majority
 * vote, then a count) that at most this share of the captured ones has:
 * a real scene's colours are spread, a writer's fill value is not. */
#define PLACEHOLDER_RARE 0.01

static uint32_t packed_at(const uint8_t *rgb, size_t i)
{
    return (uint32_t)rgb[3 * i] << 16 | (uint32_t)rgb[3 * i + 1] << 8 | rgb[3 * i + 2];
}

static void find_placeholder(occ_scene *s)
{
    size_t n = (size_t)s->width * s->height, votes = 0, missing = 0, on_missing = 0, on_cap = 0;
    uint32_t cand = 0;
    for (size_t i = 0; i < n; ++i) {
        if (isfinite(s->pts[3 * i + 2]))
            continue;
        if (votes == 0)
            cand = packed_at(s->rgb, i), votes = 1;
        else
            votes += packed_at(s->rgb, i) == cand ? 1 : (size_t)-1;
    }
    for (size_t i = 0; i < n; ++i) {
        int miss = !isfinite(s->pts[3 * i + 2]), same = packed_at(s->rgb, i) == cand;
        missing += miss, on_missing += miss && same, on_cap += !miss && same;
    }
    if (missing == 0 || 2 * on_missing <= missing ||
        (double)on_cap > PLACEHOLDER_RARE * (double)s->captured)
        return;
    s->has_placeholder = 1;
    s->placeholder[0] = (uint8_t)(cand >> 16), s->placeholder[1] = (uint8_t)(cand >> 8);
    s->placeholder[2] = (uint8_t)cand;
    s->placeholder_pixels = on_missing;
}

relief_status occ_scene_points(const relief_depth_image *f, const relief_occluder_params *p,
                               occ_scene *s, relief_error *err)
{
    size_t n = (size_t)f->width * f->height, m = 0;
    double *zs;
    memset(s, 0, sizeof *s);
    s->width = f->width, s->height = f->height;
    if (!camera_of(f, p, s->cam))
        return relief_fail(err, RELIEF_E_RANGE, "no camera could be fitted to the cloud's "
                           "points: give intrinsics");
    s->pts = malloc(n * 3 * sizeof *s->pts);
    zs = malloc(n * sizeof *zs);
    if (!s->pts || !zs) {
        free(zs);
        occ_scene_free(s);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the frame's points");
    }
    for (size_t i = 0; i < n; ++i) {
        double *q = s->pts + 3 * i, r[3], z = f->z[i];
        const float *x = f->xyz && !p->has_intrinsics ? f->xyz + 3 * i : NULL;
        ray_of(s, i, r);
        if (!(isfinite(z) && z > 0.0)) {
            q[0] = q[1] = q[2] = NAN;
            continue;
        }
        if (x && isfinite(x[0]) && isfinite(x[1]) && isfinite(x[2]))
            q[0] = x[0], q[1] = x[1], q[2] = x[2];
        else
            q[0] = r[0] * z, q[1] = r[1] * z, q[2] = z;
        zs[m++] = z;
    }
    s->captured = m;
    if (m >= 3) {
        qsort(zs, m, sizeof *zs, relief_cmp_double);
        s->median_z = zs[m / 2];
    }
    free(zs);
    s->rgb = f->rgb;
    if (f->rgb)
        find_placeholder(s);
    if (m < 3) {
        occ_scene_free(s);
        return relief_fail(err, RELIEF_E_RANGE, "%zu of %zu pixels have a depth: too few to "
                           "find a background", m, n);
    }
    return RELIEF_OK;
}

/* ------------------------------------------------------------ the planes */

static double signed_dist(const relief_occluder_plane *pl, const double *q)
{
    return pl->normal[0] * q[0] + pl->normal[1] * q[1] + pl->normal[2] * q[2] - pl->offset;
}

/* The plane through three points, facing away from the camera; 0 when
 * they are (nearly) collinear or the plane passes through the camera. */
static int plane_through(const double *a, const double *b, const double *c,
                         relief_occluder_plane *pl)
{
    double e[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double g[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]}, len;
    pl->normal[0] = e[1] * g[2] - e[2] * g[1];
    pl->normal[1] = e[2] * g[0] - e[0] * g[2];
    pl->normal[2] = e[0] * g[1] - e[1] * g[0];
    len = relief_normalize3(pl->normal);
    if (!(len > 1e-12 * (e[0] * e[0] + e[1] * e[1] + e[2] * e[2])))
        return 0;
    pl->offset = pl->normal[0] * a[0] + pl->normal[1] * a[1] + pl->normal[2] * a[2];
    if (pl->offset < 0.0) {
        for (int k = 0; k < 3; ++k)
            pl->normal[k] = -pl->normal[k];
        pl->offset = -pl->offset;
    }
    return pl->offset > 0.0;
}

/* What a search for one plane shares. */
typedef struct plane_search {
    const occ_scene *s;
    const size_t *sub;     /* the scoring subset: pixel indices */
    size_t n_sub;
    const uint8_t *taken;  /* per pixel: on an earlier plane */
    double noise;          /* sigma(z) = noise x z^2 so far */
    double min_offset;     /* planes nearer the camera are edge-on */
} plane_search;

/* The consensus band at depth z: the given margin, or BAND_SIGMAS. */
static double band(const plane_search *ps, double z)
{
    return ps->s->margin > 0.0 ? ps->s->margin : BAND_SIGMAS * ps->noise * z * z;
}

/* Inliers of `pl` among the subset's free points; -1 when more than
 * MAX_BEHIND of the subset lies behind it. */
static long score(const plane_search *ps, const relief_occluder_plane *pl)
{
    long in = 0, behind = 0, cap = (long)(MAX_BEHIND * (double)ps->n_sub);
    for (size_t k = 0; k < ps->n_sub; ++k) {
        size_t i = ps->sub[k];
        const double *q = ps->s->pts + 3 * i;
        double d = signed_dist(pl, q), b = band(ps, q[2]);
        if (d > b && ++behind > cap)
            return -1;
        if (fabs(d) <= b && !ps->taken[i])
            ++in;
    }
    return in;
}

/* A free captured pixel within `reach` pixels of pixel a, drawn; a
 * itself when a few draws find none. */
static size_t near_pixel(const plane_search *ps, size_t a, int reach, relief_rng *rng)
{
    const occ_scene *s = ps->s;
    int u = (int)(a % (size_t)s->width), v = (int)(a / (size_t)s->width);
    for (int tries = 0; tries < 8; ++tries) {
        int x = u - reach + (int)relief_rng_below(rng, 2u * reach + 1u);
        int y = v - reach + (int)relief_rng_below(rng, 2u * reach + 1u);
        size_t j = (size_t)y * s->width + x;
        if (x >= 0 && y >= 0 && x < s->width && y < s->height && !ps->taken[j] &&
            isfinite(s->pts[3 * j + 2]))
            return j;
    }
    return a;
}

/* The best of `iterations` hypotheses, each through a free subset point
 * and two free points near it in the image: a plane that holds a few per
 * cent of the frame (a floor seen past the furniture) is then drawn as
 * often as a big one, where three points drawn anywhere would rarely all
 * lie on it. */
static int ransac(const plane_search *ps, int iterations, relief_rng *rng,
                  relief_occluder_plane *best)
{
    long best_in = 0;
    int reach = (ps->s->width < ps->s->height ? ps->s->width : ps->s->height) / 8 + 1;
    for (int it = 0; it < iterations; ++it) {
        relief_occluder_plane pl;
        size_t a = ps->sub[relief_rng_below(rng, (uint32_t)ps->n_sub)], b, c;
        long in;
        if (ps->taken[a])
            continue;
        b = near_pixel(ps, a, reach, rng);
        c = near_pixel(ps, a, reach, rng);
        if (b == a || c == a || b == c ||
            !plane_through(ps->s->pts + 3 * a, ps->s->pts + 3 * b, ps->s->pts + 3 * c, &pl) ||
            pl.offset < ps->min_offset)
            continue;
        in = score(ps, &pl);
        if (in > best_in)
            best_in = in, *best = pl;
    }
    return best_in >= 3;
}

/* Mark in sel the free captured points in pl's band; their count. */
static size_t refit_count(const plane_search *ps, const relief_occluder_plane *pl, uint8_t *sel)
{
    const occ_scene *s = ps->s;
    size_t n = (size_t)s->width * s->height, m = 0;
    for (size_t i = 0; i < n; ++i) {
        double d = signed_dist(pl, s->pts + 3 * i);
        sel[i] = !ps->taken[i] && fabs(d) <= band(ps, s->pts[3 * i + 2]); /* NaN: 0 */
        m += sel[i];
    }
    return m;
}

/* Refit `pl` by least squares to all free captured points in its band;
 * sel is per-pixel scratch. Returns the inlier count (0: lost). */
static size_t refit(const plane_search *ps, relief_occluder_plane *pl, uint8_t *sel)
{
    const occ_scene *s = ps->s;
    size_t n = (size_t)s->width * s->height, m = refit_count(ps, pl, sel);
    double c[3], eval[3], evec[9];
    if (m < 3 || relief_pca3(s->pts, n, sel, c, eval, evec) < 3)
        return 0;
    pl->normal[0] = evec[2], pl->normal[1] = evec[5], pl->normal[2] = evec[8];
    pl->offset = pl->normal[0] * c[0] + pl->normal[1] * c[1] + pl->normal[2] * c[2];
    if (pl->offset < 0.0) {
        for (int k = 0; k < 3; ++k)
            pl->normal[k] = -pl->normal[k];
        pl->offset = -pl->offset;
    }
    return pl->offset > 0.0 ? m : 0;
}

/* Refit a hypothesis by least squares while it keeps nothing behind it;
 * its inliers (sel) and their count. */
static size_t polish(const plane_search *ps, relief_occluder_plane *pl, uint8_t *sel)
{
    size_t m;
    for (int r = 0; r < REFITS; ++r) {
        relief_occluder_plane q = *pl;
        if (!refit(ps, &q, sel) || score(ps, &q) < 0 || q.offset < ps->min_offset)
            break;
        *pl = q;
    }
    m = refit_count(ps, pl, sel);
    return m >= 3 ? m : 0;
}

/* The share of sel's pixels whose right neighbour, when captured, is in
 * sel too: near 1 for a surface, near sel's density for scattered
 * depths that a plane happens to cut (which are no background). */
static double coherence(const occ_scene *s, const uint8_t *sel)
{
    size_t pairs = 0, both = 0;
    for (int v = 0; v < s->height; ++v)
        for (int u = 0; u + 1 < s->width; ++u) {
            size_t i = (size_t)v * s->width + u;
            if (!sel[i] || !isfinite(s->pts[3 * (i + 1) + 2]))
                continue;
            ++pairs;
            both += sel[i + 1];
        }
    return pairs ? (double)both / pairs : 0.0;
}

/* The noise of the pixels sel marks: their median |distance| / z^2 as a
 * standard deviation's coefficient (sigma(z) = noise x z^2); -1 when
 * memory runs out. */
static double plane_noise(const occ_scene *s, const relief_occluder_plane *pl, const uint8_t *sel)
{
    size_t n = (size_t)s->width * s->height, m = 0;
    double *d = malloc(n * sizeof *d), med;
    if (!d)
        return -1.0;
    for (size_t i = 0; i < n; ++i)
        if (sel[i])
            d[m++] = fabs(signed_dist(pl, s->pts + 3 * i)) / (s->pts[3 * i + 2] * s->pts[3 * i + 2]);
    med = m ? relief_select_median(d, m) : 0.0;
    free(d);
    return fmax(1.4826 * med, MIN_NOISE);
}

/* Mark the points within plane k's own margin taken; its inliers and RMS. */
static void claim(occ_scene *s, int k, uint8_t *taken)
{
    size_t n = (size_t)s->width * s->height, m = 0;
    double ss = 0.0;
    relief_occluder_plane *pl = &s->plane[k];
    for (size_t i = 0; i < n; ++i) {
        double d = signed_dist(pl, s->pts + 3 * i), z = s->pts[3 * i + 2];
        if (fabs(d) <= (s->margin > 0.0 ? s->margin : s->margin_k * pl->noise * z * z)) {
            taken[i] = 1;
            ss += d * d;
            ++m;
        }
    }
    pl->inliers = m;
    pl->rms = m ? sqrt(ss / m) : 0.0;
}

static relief_status find_planes(occ_scene *s, const relief_occluder_params *p, uint8_t *taken,
                                 uint8_t *sel, size_t *sub, relief_error *err)
{
    size_t n = (size_t)s->width * s->height, n_cap = 0, need;
    int max = p->background == RELIEF_BACKGROUND_PLANE ? 1 : p->max_planes;
    relief_rng rng;
    /* A plane through (nearly) the camera holds whole rays, whatever their
     * depths: seen edge-on, it is no background. */
    plane_search ps = {s, sub, 0, taken, PRIOR_NOISE, MIN_OFFSET * s->median_z};
    for (size_t i = 0; i < n; ++i)
        if (isfinite(s->pts[3 * i + 2]))
            sub[n_cap++] = i;
    /* The scoring subset: a deterministic draw of the captured pixels. */
    if (n_cap > SCORE_POINTS) {
        size_t *pick = malloc(n_cap * sizeof *pick);
        if (!pick)
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate RANSAC's subset");
        relief_rng_subset(pick, n_cap, SCORE_POINTS, p->seed);
        for (size_t k = 0; k < SCORE_POINTS; ++k)
            pick[k] = sub[pick[k]];
        memcpy(sub, pick, SCORE_POINTS * sizeof *sub);
        free(pick);
        n_cap = SCORE_POINTS;
    }
    ps.n_sub = n_cap;
    need = (size_t)ceil(p->min_support * (double)s->captured);
    relief_rng_seed(&rng, p->seed);
    s->margin = p->margin > 0.0 ? p->margin : 0.0;
    s->margin_k = MARGIN_SIGMAS;
    for (int k = 0; k < max; ++k) {
        relief_occluder_plane pl;
        size_t m;
        int found = ransac(&ps, p->iterations, &rng, &pl);
        m = found ? polish(&ps, &pl, sel) : 0;
        if (!found || m < need || coherence(s, sel) < MIN_COHERENCE)
            break;
        if ((pl.noise = plane_noise(s, &pl, sel)) < 0.0)
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the noise's residuals");
        if (k == 0)
            ps.noise = s->noise = pl.noise;
        if (p->noise_model == RELIEF_NOISE_FRAME)
            pl.noise = s->noise;
        else
            pl.noise = fmax(pl.noise, NOISE_FLOOR_SHARE * s->noise);
        s->plane[k] = pl;
        s->n_planes = k + 1;
        claim(s, k, taken);
    }
    if (s->n_planes == 0)
        return relief_fail(err, RELIEF_E_RANGE, "no background found: no plane holds %.3g %% of "
                           "the %zu captured points (min_support) as one surface facing the "
                           "camera with nothing behind it; give background mesh, or a lower "
                           "min_support",
                           100.0 * p->min_support, s->captured);
    return RELIEF_OK;
}

/* Every pixel's background depth and clearance from the planes: the free
 * space they bound is the intersection of their front sides, so a ray
 * leaves it at its nearest hit and a point's clearance is its distance in
 * front of the plane it is fewest of that plane's sigmas in front of
 * (near[i]); with one noise for all, its smallest distance in front of
 * any. */
static void plane_clearance(occ_scene *s)
{
    size_t n = (size_t)s->width * s->height;
    for (size_t i = 0; i < n; ++i) {
        double r[3], zs = INFINITY, c = NAN, best = INFINITY;
        const double *q = s->pts + 3 * i;
        ray_of(s, i, r);
        s->near[i] = 0;
        for (int k = 0; k < s->n_planes; ++k) {
            const relief_occluder_plane *pl = &s->plane[k];
            double dn = pl->normal[0] * r[0] + pl->normal[1] * r[1] + pl->normal[2] * r[2];
            double ck = -signed_dist(pl, q);
            if (dn > 0.0)
                zs = fmin(zs, pl->offset / dn);
            if (ck / pl->noise < best) /* NaN (no point): never */
                best = ck / pl->noise, c = ck, s->near[i] = (uint8_t)k;
        }
        s->surface[i] = isfinite(zs) ? (float)zs : NAN;
        s->clearance[i] = (float)c;
    }
}

/* ------------------------------------------------------------ the mesh */

/* Draw triangle t's depth into s->surface (nearest kept): its corners
 * projected through the camera, depth interpolated as 1 / z. */
static void draw_triangle(occ_scene *s, const double *pos, const uint32_t *t)
{
    double u[3], v[3], iz[3], area;
    int u0, u1, v0, v1;
    for (int k = 0; k < 3; ++k) {
        const double *q = pos + 3 * (size_t)t[k];
        if (!(q[2] > 0.0))
            return;
        u[k] = (q[0] / q[2] - s->cam[1]) / s->cam[0];
        v[k] = (q[1] / q[2] - s->cam[3]) / s->cam[2];
        iz[k] = 1.0 / q[2];
    }
    area = (u[1] - u[0]) * (v[2] - v[0]) - (u[2] - u[0]) * (v[1] - v[0]);
    if (!(fabs(area) > 1e-12))
        return;
    /* Off the image (and no int conversion of a far bound). */
    if (fmax(u[0], fmax(u[1], u[2])) < 0.0 || fmin(u[0], fmin(u[1], u[2])) > s->width - 1.0 ||
        fmax(v[0], fmax(v[1], v[2])) < 0.0 || fmin(v[0], fmin(v[1], v[2])) > s->height - 1.0)
        return;
    u0 = (int)fmax(0.0, ceil(fmin(u[0], fmin(u[1], u[2]))));
    u1 = (int)fmin(s->width - 1.0, floor(fmax(u[0], fmax(u[1], u[2]))));
    v0 = (int)fmax(0.0, ceil(fmin(v[0], fmin(v[1], v[2]))));
    v1 = (int)fmin(s->height - 1.0, floor(fmax(v[0], fmax(v[1], v[2]))));
    for (int y = v0; y <= v1; ++y)
        for (int x = u0; x <= u1; ++x) {
            double b1 = ((x - u[0]) * (v[2] - v[0]) - (u[2] - u[0]) * (y - v[0])) / area;
            double b2 = ((u[1] - u[0]) * (y - v[0]) - (x - u[0]) * (v[1] - v[0])) / area;
            double b0 = 1.0 - b1 - b2, z;
            float *d = s->surface + (size_t)y * s->width + x;
            if (b0 < -1e-9 || b1 < -1e-9 || b2 < -1e-9)
                continue;
            z = 1.0 / (b0 * iz[0] + b1 * iz[1] + b2 * iz[2]);
            if (!(z >= *d))
                *d = (float)z;
        }
}

static relief_status mesh_clearance(occ_scene *s, const relief_occluder_params *p,
                                    relief_error *err)
{
    /* The accessors take a mutable mesh; nothing here writes to it. */
    relief_mesh *m = (relief_mesh *)p->background_mesh;
    const double *pos = relief_mesh_positions(m);
    const uint32_t *tri = relief_mesh_triangles(m);
    size_t nt = relief_mesh_triangle_count(m), n = (size_t)s->width * s->height, k = 0;
    double *d;
    for (size_t i = 0; i < n; ++i)
        s->surface[i] = NAN;
    for (size_t t = 0; t < nt; ++t)
        draw_triangle(s, pos, tri + 3 * t);
    if (!(d = malloc(n * sizeof *d)))
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the background's residuals");
    for (size_t i = 0; i < n; ++i) {
        double z = s->pts[3 * i + 2];
        s->clearance[i] = isfinite(z) && isfinite(s->surface[i]) ? s->surface[i] - (float)z : NAN;
        if (isfinite(s->clearance[i]) && fabs(s->clearance[i]) <= 0.05 * z)
            d[k++] = fabs(s->clearance[i]) / (z * z);
    }
    s->noise = k ? fmax(1.4826 * relief_select_median(d, k), MIN_NOISE) : 0.0;
    free(d);
    if (k < 3)
        return relief_fail(err, RELIEF_E_RANGE, "no background found: the background mesh "
                           "meets %zu of the frame's captured points (within 5 %% of their "
                           "depth)", k);
    s->margin = p->margin > 0.0 ? p->margin : 0.0;
    s->margin_k = MARGIN_SIGMAS;
    return RELIEF_OK;
}

relief_status occ_background(occ_scene *s, const relief_occluder_params *p, relief_error *err)
{
    size_t n = (size_t)s->width * s->height;
    uint8_t *taken = calloc(n, 1), *sel = malloc(n);
    size_t *sub = malloc(n * sizeof *sub);
    relief_status st = RELIEF_OK;
    s->surface = malloc(n * sizeof *s->surface);
    s->clearance = malloc(n * sizeof *s->clearance);
    if (!taken || !sel || !sub || !s->surface || !s->clearance)
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the background's %zu pixels", n);
    if (st == RELIEF_OK && p->background == RELIEF_BACKGROUND_MESH) {
        st = mesh_clearance(s, p, err);
    } else if (st == RELIEF_OK) {
        st = find_planes(s, p, taken, sel, sub, err);
        if (st == RELIEF_OK && !(s->near = malloc(n)))
            st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the planes' %zu pixels", n);
        if (st == RELIEF_OK)
            plane_clearance(s);
        if (st == RELIEF_OK)
            st = occ_local_lift(s, err);
    }
    free(taken);
    free(sel);
    free(sub);
    return st;
}
