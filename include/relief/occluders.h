/* relief/occluders.h: the foreground objects of an RGB-D frame found from
 * its depth, and the surface behind them seen (paper 004, chapter 2: a
 * façade's occluders marked from range data, then its texture filled by
 * chapter 3, relief_image_fill; the depth behind them by paper 003,
 * relief_depth_fill, constrained to the background surface).
 *
 *   relief_depth_image f;                     an organised PCD with colour
 *   relief_depth_read("office.pcd", 0, 0, &f, &err);
 *   relief_occluder_params p = relief_occluder_params_default();
 *   relief_image mask;                        1 channel, 8 bits, 255 = occluder
 *   relief_find_occluders(&f, &p, &mask, NULL, &err);
 *   relief_remove_params r = relief_remove_params_default();
 *   relief_remove_occluders(&f, &mask, &r, NULL, &err);   f: the wall behind
 *
 * The method, step by step (units: the frame's depth units, metres for a
 * PCD or a PNG; pixels):
 * 1. The camera: fitted to an organised cloud's points (relief/depth.h), or
 *    the pinhole `intrinsics` of a depth image; every pixel's ray.
 * 2. The background: planes found by RANSAC among the captured points,
 *    each refined by least squares on its inliers, kept only where nearly
 *    nothing lies behind it (a wall, a floor, a façade; not a desk's top
 *    with the floor under it). Together they bound the free space in front
 *    of the camera: a point's clearance is its smallest distance in front
 *    of any of them.
 * 3. Seeds: the captured points whose clearance exceeds `margin` (the
 *    paper's foreground scan points), in connected groups of at least
 *    `min_area` pixels; with `seeding` hysteresis, also the points over 3/4
 *    of the margin in front connected to them through such points.
 * 4. Growth (the paper's flood fill): from each seed, inside the `window`
 *    square around it, into 4-neighbours whose colour differs from the
 *    pixel they are reached from by at most `colour_distance` (CIELAB
 *    delta E 1976) and whose depth is missing or, within `edge` pixels of
 *    a seed, not behind the background (the misregistered rim of a depth
 *    camera), or which stand over `front_sigmas` above their plane's local
 *    level (thin things on a floor; the window restarts there).
 * 5. The mask, dilated by `dilate` pixels: marking background as
 *    foreground is preferred to the reverse.
 * With registered neighbouring views (the paper's eq. 2.1), each pixel's
 * background point is projected into them and its window's colour
 * searched for around there: the larger displacement found is the
 * correspondence error. The views decide where the depth cannot: a pixel
 * whose depth is missing and which every view matches displaced by over
 * `parallax` pixels towards the camera (the smallest displacement over
 * it: one view seeing behind an occluder's edge does not count) is a
 * seed; one whose error (the larger displacement) is at most `parallax`,
 * on a textured window, is background and growth stops there.
 */
#ifndef RELIEF_OCCLUDERS_H
#define RELIEF_OCCLUDERS_H

#include "relief/core.h"
#include "relief/depth.h"
#include "relief/image.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Most background planes a frame is given. */
#define RELIEF_OCCLUDER_MAX_PLANES 8

/* What the background is: planes (default: up to max_planes, a corner, a
 * floor), plane (the dominant one only) or mesh (background_mesh, in the
 * frame's camera coordinates: z forwards, as the cloud's points).
 * X(code, name) */
#define RELIEF_BACKGROUND_LIST(X)                                               \
    X(RELIEF_BACKGROUND_PLANES, "planes")                                       \
    X(RELIEF_BACKGROUND_PLANE, "plane")                                         \
    X(RELIEF_BACKGROUND_MESH, "mesh")

typedef enum relief_background {
#define RELIEF_X_ENUM(code, name) code,
    RELIEF_BACKGROUND_LIST(RELIEF_X_ENUM)
#undef RELIEF_X_ENUM
} relief_background;

RELIEF_API const char *relief_background_name(relief_background background);

/* Which points are seeds:
 *   margin      (default) paper 004's: those beyond the margin only;
 *   hysteresis  also the points more than 3/4 of the margin in front that
 *               touch them through such points: a chair's legs and base, a
 *               box's lower edge, which stand within the margin of the floor
 *               they rest on. On the shared real frames it also spreads
 *               into walls that are not quite plane (docs/occluders.md), so
 *               it is not the default.
 * X(code, name) */
#define RELIEF_SEEDING_LIST(X)                                                  \
    X(RELIEF_SEEDING_MARGIN, "margin")                                          \
    X(RELIEF_SEEDING_HYSTERESIS, "hysteresis")

typedef enum relief_seeding {
#define RELIEF_X_ENUM(code, name) code,
    RELIEF_SEEDING_LIST(RELIEF_X_ENUM)
#undef RELIEF_X_ENUM
} relief_seeding;

RELIEF_API const char *relief_seeding_name(relief_seeding seeding);

/* Whose noise a point's margin is measured by (when `margin` <= 0):
 *   plane  (default) the plane it is judged against: each background plane's
 *          own sigma_k(z) = a_k z^2, measured on its own inliers (not below
 *          half the first plane's a), and a point is judged against the plane
 *          it is fewest of those sigmas in front of. A floor seen edge-on,
 *          or a wall that is not quite plane, each keeps its own margin.
 *   frame  issue 63's first measure: the first plane's a for every plane.
 * X(code, name) */
#define RELIEF_NOISE_MODEL_LIST(X)                                              \
    X(RELIEF_NOISE_PLANE, "plane")                                              \
    X(RELIEF_NOISE_FRAME, "frame")

typedef enum relief_noise_model {
#define RELIEF_X_ENUM(code, name) code,
    RELIEF_NOISE_MODEL_LIST(RELIEF_X_ENUM)
#undef RELIEF_X_ENUM
} relief_noise_model;

RELIEF_API const char *relief_noise_model_name(relief_noise_model model);

/* Most neighbouring views a call takes. */
#define RELIEF_OCCLUDER_MAX_VIEWS 16

/* A registered neighbouring view of the frame (paper 004: the previous and
 * the next image): its colour, its camera and its pose. A view through the
 * frame's own camera (intrinsics all 0, as a zeroed struct has them) is of
 * the frame's size; one with its own intrinsics may be of any size (another
 * camera, another resolution). A point x in the frame's camera coordinates
 * is y = R x + t in the view's, seen at pixel (fx y0 / y2 + cx,
 * fy y1 / y2 + cy), pixel centres at whole numbers. For a sequence of
 * camera-to-world poses T (Open3D's trajectory log, a SLAM system's output)
 * [R | t] is the top 3 rows of inverse(T_view) T_frame. */
typedef struct relief_occluder_view {
    int width, height;   /* the view's pixels; the frame's when intrinsics
                            are 0 */
    const uint8_t *rgb;  /* height x width x 3, sRGB */
    double pose[12];     /* [R | t], 3 x 4 row-major: a point x in the frame's
                            camera coordinates is R x + t in this view's */
    double intrinsics[4]; /* the view's fx, fy, cx, cy in pixels (fx, fy > 0,
                            cx, cy finite); all 0 (default): the frame's
                            camera (its intrinsics, or the camera fitted to
                            its points) */
} relief_occluder_view;

typedef struct relief_occluder_params {
    relief_background background; /* default planes */
    int max_planes;          /* planes: at most this many; 4, [1, 8] */
    double min_support;      /* a plane holds at least this share of the
                                captured points; 0.03, [1e-6, 1] */
    const relief_mesh *background_mesh; /* mesh: the surface (triangles), the
                                frame's coordinates; read only then */
    double margin;           /* a seed is this far in front of the background,
                                depth units; <= 0 (default): 4 sigma(z) at the
                                point's depth z, the noise measured on the
                                background as sigma(z) = a z^2 (a
                                structured-light camera's quantised
                                disparity); else (0, 1e9] */
    int window;              /* the growth's square around each seed, odd
                                pixels; 61 (the paper's), [3, 1025] */
    double colour_distance;  /* the growth's step, CIELAB delta E; 12, [0, 200] */
    int edge;                /* growth onto background depth within this many
                                pixels of a seed; 3, [0, 64] */
    int min_area;            /* seed groups smaller than this are noise; 50
                                pixels, [1, 1e8] */
    int dilate;              /* the mask grown by this many pixels; 1, [0, 64] */
    int iterations;          /* RANSAC hypotheses per plane; 500, [10, 1e6] */
    int has_intrinsics;      /* 1: intrinsics below; 0 (default): a cloud's
                                fitted camera, or for a frame without xyz
                                fx = fy = 525 x width / 640 and the centre
                                (a Kinect's) */
    double intrinsics[4];    /* fx, fy, cx, cy in pixels (a frame without xyz) */
    const relief_occluder_view *views; /* n_views neighbouring views, or NULL */
    int n_views;             /* 0 (default) .. RELIEF_OCCLUDER_MAX_VIEWS */
    double parallax;         /* views: a correspondence error over this is
                                foreground; 2 pixels, [0.1, 64] */
    int view_radius;         /* views: the colour search's reach behind where
                                the background point projects, and its least
                                reach in front (it goes on to where the ray's
                                point at half the depth projects, at most 64
                                pixels); 6 pixels, [1, 32] */
    uint32_t seed;           /* RANSAC's draws; 1 */
    relief_run_options run;  /* max_memory, progress, names; backend unused */
    relief_seeding seeding;  /* default margin */
    relief_noise_model noise_model; /* default plane */
    double front_sigmas;     /* growth also enters captured points more than
                                this many sigmas over their plane's local
                                level (the mean of its points in a 31-pixel
                                square; sigma: the plane's local_noise z^2):
                                thin things on a floor, a chair's runners;
                                0: never (paper 004's growth); 3, [0, 64] */
} relief_occluder_params;

/* The defaults above. */
RELIEF_API relief_occluder_params relief_occluder_params_default(void);

/* Check the fields; RELIEF_E_RANGE naming the field and its range,
 * RELIEF_E_USAGE for background mesh without background_mesh (its
 * triangles are checked by the call). */
RELIEF_API relief_status relief_occluder_params_validate(const relief_occluder_params *p,
                                                         relief_error *err);

/* relief_occluder_params described field by field (relief_param). */
RELIEF_API const relief_param *relief_occluder_param_table(size_t *count);

/* One background plane: normal . p = offset, the normal facing away from
 * the camera (offset > 0: the camera is in front of it). */
typedef struct relief_occluder_plane {
    double normal[3];
    double offset;           /* depth units */
    size_t inliers;          /* captured points within the margin */
    double rms;              /* their RMS distance to it */
    double noise;            /* its a_k: sigma_k(z) = a_k z^2, the margin's
                                unit against it (noise_model plane; frame:
                                the report's noise) */
    double local_noise;      /* its points' noise about their local level
                                (the mean of its points in a 31-pixel square):
                                front_sigmas' unit */
    size_t region;           /* its region: the captured pixels within 3
                                sigma(z) of it, in its connected support (the
                                4-connected parts of that band holding at
                                least 5 % of it) */
    double marked;           /* the share of the region in the mask (a
                                support surface, a table or a floor, should
                                be near 0); NaN: not measured */
} relief_occluder_plane;

typedef struct relief_occluder_report {
    int width, height;
    size_t captured;         /* pixels with a finite depth */
    size_t missing;          /* pixels without */
    int has_placeholder;     /* 1: the frame gives its missing points one
                                colour (a PCD writer's fill, as (192, 0, 0)):
                                the colour of over half of them, and of under
                                1 % of the captured. Those pixels have no
                                colour: growth never enters them, the removal
                                never copies them (they are holes of its
                                colour fill too, left as they were outside
                                the mask) */
    uint8_t placeholder[3];  /* that colour */
    size_t placeholder_pixels; /* missing pixels of that colour */
    int planes;              /* background planes found (0 for a mesh) */
    relief_occluder_plane plane[RELIEF_OCCLUDER_MAX_PLANES];
    size_t on_background;    /* captured points within the margin of it */
    size_t behind;           /* captured points behind it by more */
    size_t no_background;    /* pixels whose ray meets no background */
    double noise;            /* the background's noise a: sigma(z) = a z^2
                                (from the median absolute residual) */
    double margin;           /* the margin at the median depth */
    size_t seeds;            /* seed pixels kept */
    size_t seed_groups;      /* their connected groups */
    size_t seeds_dropped;    /* seed pixels in groups under min_area */
    size_t weak_seeds;       /* of the seeds, those hysteresis added: within
                                the margin, over 3/4 of it */
    size_t grown_missing;    /* added by growth: depth missing */
    size_t grown_edge;       /* added by growth: background depth at the rim */
    size_t grown_front;      /* added by growth: over front_sigmas in front */
    size_t dilated;          /* added by the dilation */
    int views;               /* neighbouring views used */
    size_t parallax_seeds;   /* seeds where the depth is missing, by the views */
    size_t view_foreground;  /* pixels the views judged: over parallax (every
                                pixel with a background behind it is judged,
                                so these count the frame) */
    size_t view_background;  /* at most parallax, on texture */
    size_t view_unknown;     /* no texture, or seen by no view */
    /* How the views agree with the depth, on the captured points: */
    size_t front_view_foreground; /* in front of the background by over the
                                margin (the depth's foreground), judged
                                foreground by the views */
    size_t front_view_background; /* ... judged background */
    size_t on_view_background; /* within the margin of the background, judged
                                background */
    size_t on_view_foreground; /* ... judged foreground */
    size_t occluder_pixels;  /* the mask's */
    double camera[4];        /* x / z = c0 u + c1, y / z = c2 v + c3 */
    double seconds_total;
    char *json;              /* the report as `relief occluders --report`
                                writes it (owned) */
} relief_occluder_report;

RELIEF_API void relief_occluder_report_free(relief_occluder_report *rep);

/* Find the occluders of frame `f` (z, and xyz or the params' intrinsics;
 * rgb required). *mask gets a new 1-channel 8-bit image of f's size, 255 on
 * the occluders, 0 elsewhere (free with relief_image_free). RELIEF_E_USAGE
 * for a frame without colour, a bad argument; RELIEF_E_RANGE when no
 * background is found (too few captured points, no plane holding
 * min_support with nothing behind it), or when every captured point is
 * foreground, or none is (nothing to mark: the message says so);
 * RELIEF_E_NOMEM. *mask and `rep` (may be NULL) are written only on
 * success. */
RELIEF_API relief_status relief_find_occluders(const relief_depth_image *f,
                                               const relief_occluder_params *p,
                                               relief_image *mask,
                                               relief_occluder_report *rep,
                                               relief_error *err);

/* What relief_remove_occluders runs: the finding (when no mask is given),
 * the colour's fill (paper 004, chapter 3) and the depth's repair (paper
 * 003) of the residual against the background. */
typedef struct relief_remove_params {
    relief_occluder_params find;
    relief_image_fill_params colour;
    relief_depth_fill_params depth;
} relief_remove_params;

RELIEF_API relief_remove_params relief_remove_params_default(void);

/* What a removal did: the finding's report, then the two fills'. */
typedef struct relief_remove_report {
    relief_occluder_report find; /* its json NULL: the removal's json holds it */
    size_t replaced;          /* occluder pixels given the surface behind */
    size_t left_missing;      /* occluder pixels whose ray meets no background:
                                 depth NaN */
    double background_rms;    /* RMS of the filled depth about the background */
    double seconds_colour, seconds_depth, seconds_total;
    uint8_t *mask;            /* width x height: 1 on the pixels removed (the
                                 found or the given mask; owned) */
    char *json;               /* `relief remove-occluders --report` (owned) */
} relief_remove_report;

RELIEF_API void relief_remove_report_free(relief_remove_report *rep);

/* Remove the occluders of `f` in place: `mask` (f's size, non-zero in any
 * channel but alpha = occluder; NULL: found by relief_find_occluders with
 * p->find) is filled
 * in colour by relief_image_fill (p->colour) and in depth by
 * relief_depth_fill (p->depth) on the depth's residual about the
 * background surface, so that the points behind lie on it with the
 * background's own roughness; xyz (when set) follows through the camera.
 * Pixels outside the mask keep their bits, missing ones stay missing.
 * The errors of the three calls; f and `rep` (may be NULL) are written only
 * on success. */
RELIEF_API relief_status relief_remove_occluders(relief_depth_image *f, const relief_image *mask,
                                                 const relief_remove_params *p,
                                                 relief_remove_report *rep,
                                                 relief_error *err);

#ifdef __cplusplus
}
#endif

#endif /* RELIEF_OCCLUDERS_H */
