/* Occluders from depth (relief/occluders.h), inside: the frame's camera and
 * points, its background (planes by RANSAC, or a given mesh) and each
 * pixel's clearance in front of it (background.c); the seeds, the growth
 * by colour and the dilation (mask.c). api.c ties them to the public
 * calls. */
#ifndef RELIEF_HOST_OCCLUDE_OCCLUDE_H
#define RELIEF_HOST_OCCLUDE_OCCLUDE_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"
#include "relief/occluders.h"

/* A frame's geometry: every pixel's point and what lies behind it. */
typedef struct occ_scene {
    int width, height;
    double cam[4];       /* x / z = cam[0] u + cam[1], y / z = cam[2] v + cam[3] */
    double *pts;         /* width x height x 3: the point, NaN where missing */
    size_t captured;     /* pixels with a point */
    double median_z;     /* of the captured points */
    /* the background */
    int n_planes;
    relief_occluder_plane plane[RELIEF_OCCLUDER_MAX_PLANES];
    float *surface;      /* width x height: the background's depth along the
                            pixel's ray; NaN where the ray meets none */
    float *clearance;    /* width x height: how far the point lies in front
                            of the background (negative: behind); NaN where
                            the point is missing or has no background */
    /* The depth noise, a structured-light camera's: sigma(z) = noise x z^2
     * (its disparity quantised: steps of about z^2 / 350 m for a Kinect),
     * measured on the first plane (or the mesh). Each plane has its own,
     * plane[k].noise, and each point is judged against one plane, near[i]
     * (NULL for a mesh: the noise above). */
    double noise;
    uint8_t *near;       /* width x height: the plane of the clearance */
    float *lift;         /* width x height: the clearance less the local level
                            of near[i]'s points (local.c); NaN where missing,
                            NULL for a mesh */
    double margin;       /* a constant margin (depth units), or 0: margin_k x
                            sigma(z) */
    double margin_k;
    /* The colour a capture gives its missing points (a PCD's (192, 0, 0),
     * say), when it has one: no texture, so never grown on nor copied. */
    int has_placeholder;
    uint8_t placeholder[3];
    size_t placeholder_pixels; /* missing-depth pixels of that colour */
    const uint8_t *rgb;  /* the frame's colour (the caller's) */
} occ_scene;

/* Is pixel i a missing point with the placeholder colour (no colour)? */
static inline int occ_no_colour(const occ_scene *s, size_t i)
{
    const uint8_t *c = s->rgb + 3 * i;
    return s->has_placeholder && isnan(s->pts[3 * i + 2]) &&
           c[0] == s->placeholder[0] && c[1] == s->placeholder[1] && c[2] == s->placeholder[2];
}

/* The noise coefficient a of pixel i's point: sigma(z) = a z^2 of the
 * plane it is judged against. */
static inline double occ_noise_at(const occ_scene *s, size_t i)
{
    return s->near ? s->plane[s->near[i]].noise : s->noise;
}

/* The depth noise of pixel i's point: one standard deviation (depth units;
 * NaN where the point is missing). */
static inline double occ_sigma_at(const occ_scene *s, size_t i)
{
    double z = s->pts[3 * i + 2];
    return occ_noise_at(s, i) * z * z;
}

/* The margin pixel i's point must clear to be a seed. */
static inline double occ_margin_at(const occ_scene *s, size_t i)
{
    return s->margin > 0.0 ? s->margin : s->margin_k * occ_sigma_at(s, i);
}

/* The margin at depth z against the first plane (the report's). */
static inline double occ_margin(const occ_scene *s, double z)
{
    return s->margin > 0.0 ? s->margin : s->margin_k * s->noise * z * z;
}

void occ_scene_free(occ_scene *s);

/* Each of planes[0..n_planes)'s region (the captured pixels within 3
 * sigma(z) of it, in its connected support) and the share of it `mask`
 * (width x height, non-zero = occluder) marks: planes[k].region, .marked
 * (NaN when memory runs out). */
void occ_plane_regions(const occ_scene *s, const uint8_t *mask, relief_occluder_plane *planes,
                       int n_planes);

/* The camera and the points of `f`: an organised cloud's xyz and the
 * camera fitted to them, or z through p's intrinsics (or the default
 * Kinect's). RELIEF_E_RANGE when fewer than 3 points are captured or no
 * camera can be had; RELIEF_E_NOMEM. */
relief_status occ_scene_points(const relief_depth_image *f, const relief_occluder_params *p,
                               occ_scene *s, relief_error *err);

/* The background of s's points (p->background) and every pixel's surface
 * depth and clearance; s->margin is p->margin or measured. RELIEF_E_RANGE
 * naming why when none is found; RELIEF_E_NOMEM. */
relief_status occ_background(occ_scene *s, const relief_occluder_params *p,
                             relief_error *err);

/* s->lift and each plane's local_noise, from the planes' clearance.
 * RELIEF_E_NOMEM. */
relief_status occ_local_lift(occ_scene *s, relief_error *err);

/* Does pixel i's point stand over k local sigmas above its plane's local
 * level, and over one of the plane's own sigmas in front of it? The
 * second keeps the bumps of a wall that is not quite plane, which its own
 * noise measures, from counting. */
static inline int occ_lifted(const occ_scene *s, size_t i, double k)
{
    double z = s->pts[3 * i + 2];
    return s->lift && s->lift[i] > k * s->plane[s->near[i]].local_noise * z * z &&
           s->clearance[i] > occ_sigma_at(s, i);
}

/* CIELAB (D65) of n sRGB byte triples: lab n x 3. */
void occ_lab(const uint8_t *rgb, size_t n, float *lab);

/* ------------------------------------------------ the neighbouring views */

/* What the views say of a pixel (paper 004, eq. 2.1). */
enum {
    OCC_CUE_UNSEEN = -2,    /* not asked yet */
    OCC_CUE_UNKNOWN = -1,   /* no texture to match, or no view sees it */
    OCC_CUE_BACKGROUND = 0, /* the correspondence error at most parallax */
    OCC_CUE_FOREGROUND = 1  /* over it */
};

/* One view's camera: its size and pinhole (pixel = f y / z + c). */
typedef struct occ_view_camera {
    int width, height;
    double fx, fy, cx, cy;
    const float *lum;       /* width x height: its L* (in occ_views.lum) */
} occ_view_camera;

typedef struct occ_views {
    const occ_scene *s;
    const relief_occluder_params *p;
    const float *lab;       /* the frame's CIELAB, width x height x 3 */
    float *lum;             /* every view's L*, one after the other */
    occ_view_camera cam[RELIEF_OCCLUDER_MAX_VIEWS];
    int8_t *cue;            /* per pixel: OCC_CUE_*, computed when asked */
    size_t fg, bg, unknown; /* the verdicts given */
} occ_views;

/* The views of p (none: v->cue stays NULL and every cue is UNKNOWN) over
 * scene s and the frame's `lab`. RELIEF_E_USAGE for a view through the
 * frame's camera of another size, or without colour; RELIEF_E_NOMEM. */
relief_status occ_views_init(occ_views *v, const occ_scene *s, const float *lab,
                             const relief_occluder_params *p, relief_error *err);
/* Pixel i's verdict, computed on its first asking. */
int occ_views_cue(occ_views *v, size_t i);
void occ_views_free(occ_views *v);

/* What the mask's stages counted (relief_occluder_report's fields). */
typedef struct occ_counts {
    size_t seeds, seed_groups, seeds_dropped, weak_seeds, grown_missing, grown_edge, dilated;
    size_t grown_front;
    size_t total;
    size_t parallax_seeds, view_fg, view_bg, view_unknown;
    size_t front_fg, front_bg, on_bg, on_fg; /* the views against the depth */
} occ_counts;

/* The occluder mask (width x height, 1 = occluder) of scene s with the
 * colour rgb (width x height x 3, sRGB bytes). RELIEF_E_NOMEM. */
relief_status occ_mask(const occ_scene *s, const uint8_t *rgb, const relief_occluder_params *p,
                       uint8_t *mask, occ_counts *counts, relief_error *err);

#endif
