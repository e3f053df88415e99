/* relief/points.h: the holes of a point set or mesh that no primitive fits
 * completed with its own colour and geometric detail (paper 002): the
 * detail peeled off as a signed height over a smoothed base, the base's
 * holes filled by a compactly supported RBF, and the height and colour
 * synthesised on the new points by texture optimisation over overlapping
 * clusters.
 *
 *   relief_complete_points_params p = relief_complete_points_params_default();
 *   relief_mesh *done = NULL;
 *   relief_complete_points(scan, &p, &done, NULL, &err);
 *   ... done: the scan's points (label 0), then the new ones (label 1) ...
 *
 * Lengths are in the input's units; "spacings" are multiples of the median
 * nearest-neighbour distance. relief_points_read reads the input: a mesh
 * or point file (as relief_mesh_read) or a PCD cloud. */
#ifndef RELIEF_POINTS_H
#define RELIEF_POINTS_H

#include "relief/core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What is completed:
 *   all       new points with detail, and colour when the input has it;
 *   colour    the colour of the hole mask's points only (hole_mask,
 *             hole_labels or hole_ball), no new points;
 *   geometry  new points and their detail, colour from the nearest
 *             captured point.
 * X(code, name) */
#define RELIEF_POINTS_WHAT_LIST(X)                                              \
    X(RELIEF_POINTS_ALL, "all")                                                 \
    X(RELIEF_POINTS_COLOUR_ONLY, "colour")                                      \
    X(RELIEF_POINTS_GEOMETRY_ONLY, "geometry")

typedef enum relief_points_what {
#define RELIEF_X_ENUM(code, name) code,
    RELIEF_POINTS_WHAT_LIST(RELIEF_X_ENUM)
#undef RELIEF_X_ENUM
} relief_points_what;

/* The texture optimisation's nearest exemplar grids: FLANN's exact
 * kd-tree on the host, or brute force on run.backend (the same bytes). */
#define RELIEF_GRID_SEARCH_LIST(X)                                              \
    X(RELIEF_GRID_SEARCH_KDTREE, "kdtree")                                      \
    X(RELIEF_GRID_SEARCH_BRUTE, "brute")

typedef enum relief_grid_search {
#define RELIEF_X_ENUM(code, name) code,
    RELIEF_GRID_SEARCH_LIST(RELIEF_X_ENUM)
#undef RELIEF_X_ENUM
} relief_grid_search;

RELIEF_API const char *relief_points_what_name(relief_points_what what);
RELIEF_API const char *relief_grid_search_name(relief_grid_search search);

typedef struct relief_complete_points_params {
    relief_points_what what;     /* default all */
    int smooth_only;             /* 1: the smooth fill alone (no detail, colour
                                    from the rim: paper 002's Fig. 9g) */
    int detail_histogram;        /* 1 (default): the new points' detail takes the
                                    distribution of the capture about the hole
                                    (histogram matching); 0: as the optimisation
                                    averaged it */
    int mesh;                    /* 1: *out also gets triangles: a mesh input's own
                                    and patches over the filled holes; for a point
                                    set, a surface through all the points */
    int k;                       /* neighbours of the local analysis; 16, [6, 64] */
    int smooth_steps;            /* curvature-flow steps of the base; 20,
                                    [0, 10000] */
    double max_detail;           /* the base keeps within this many spacings of
                                    every point, so that thin parts stay shape;
                                    1, [0, 100], 0: no bound */
    double band;                 /* exemplars keep this many spacings from a rim;
                                    2, [0, 1e6] */
    double max_hole;             /* a hole whose rim is wider than this (the
                                    input's units: twice the largest distance of a
                                    rim point from the rim's centre) is taken for
                                    an opening the capture has by design (a vase's
                                    mouth or base) and left open; 0 (default): a
                                    quarter of the input's bounding-box diagonal;
                                    [0, 1e30]. A hole mask selects instead. */
    int grid;                    /* texture grid side, odd; 23, [3, 33] */
    int cluster_size;            /* points per cluster before overlap; 300,
                                    [16, 100000] */
    int iterations;              /* texture optimisation iterations; 50, [1, 1000] */
    uint32_t seed;               /* which exemplar grids are searched when there
                                    are over 20 000; 1 */
    relief_grid_search grid_search; /* default kdtree */
    /* Which holes are filled and which points are synthesised again: at
     * most one of hole_mask, hole_labels and has_hole_ball. Given one, the
     * holes whose rims it touches are filled, whatever their size, and no
     * other; a rim the hole model would leave open (a border, or wider
     * than max_hole: a cut that reaches the border) is filled only where
     * the selection touches it, given at least k of its points; its
     * points are synthesised again. */
    const uint8_t *hole_mask;    /* the input's vertex count: non-zero, this
                                    point's colour and detail are synthesised
                                    again; NULL (default): none */
    int hole_labels;             /* 1: the points whose `label` (the PLY property)
                                    is non-zero; the input must have labels */
    int has_hole_ball;           /* 1: the points within hole_ball */
    double hole_ball[4];         /* X, Y, Z, R: centre and radius R > 0 */
    /* Where an exemplar may be centred (default: everywhere outside the
     * band): at most one of sample_mask, sample_labels and has_sample_box;
     * not sample_labels with hole_labels (the same labels). */
    const uint8_t *sample_mask;  /* the input's vertex count: non-zero, here */
    int sample_labels;           /* 1: on the points labelled 1; the input must
                                    have labels */
    int has_sample_box;          /* 1: on the points in sample_box */
    double sample_box[6];        /* X0, Y0, Z0, X1, Y1, Z1 (bounds included),
                                    X0 < X1, Y0 < Y1, Z0 < Z1 */
    const relief_mesh *clone;    /* NULL, or another scan sampled about as densely
                                    whose detail (and colour, when both have it) is
                                    copied instead of the input's own (6.3) */
    int has_viewpoint;           /* 1: the normals face viewpoint (a PCD's sensor,
                                    the origin: relief_points_read_info) */
    double viewpoint[3];
    size_t non_finite_dropped;   /* for the report only: the points the reader
                                    left out (relief_points_read_info); 0 */
    relief_run_options run;      /* backend: scalar runs every stage on the
                                    calling thread (the reference), whatever
                                    threads says; host and auto share each stage
                                    out over run.threads host threads (0: the
                                    CPUs this thread may run on), the same
                                    bytes. The brute grid search runs on OpenCL
                                    for opencl, and for auto on a GPU; opencl
                                    and device are for grid_search brute only.
                                    max_memory bounds the estimate
                                    (relief_complete_points_max_points) */
} relief_complete_points_params;

/* The defaults above. */
RELIEF_API relief_complete_points_params relief_complete_points_params_default(void);

/* Check the fields (the flags 0 or 1, the enumerations in their lists, no
 * NaN); RELIEF_E_RANGE naming the field and its range, RELIEF_E_USAGE for
 * NULL or a combination that cannot be (colour with no hole mask, colour
 * with smooth_only, clone with smooth_only, backend opencl or a device with
 * the kd-tree, two hole masks or two sample regions, hole_labels with
 * sample_labels). */
RELIEF_API relief_status relief_complete_points_params_validate(
    const relief_complete_points_params *p, relief_error *err);

/* relief_complete_points_params described field by field (relief_param,
 * relief/core.h). */
RELIEF_API const relief_param *relief_complete_points_param_table(size_t *count);

/* The most input points a call with p can take within run.max_memory (0:
 * 80 % of physical memory) by the estimate relief_complete_points refuses
 * over: pass it to relief_points_read so that a larger cloud is refused
 * before it is decoded. NULL p: the defaults'. */
RELIEF_API uint64_t relief_complete_points_max_points(const relief_complete_points_params *p);

/* What relief_points_read found besides the points. */
typedef struct relief_points_read_info {
    char format[8];            /* "pcd", or relief_read_info's ("ply", ...) */
    size_t width, height;      /* a PCD's sides (height 1: an unorganised
                                  cloud); 0 for a mesh file */
    size_t non_finite_dropped; /* a PCD's points with a non-finite coordinate
                                  (a depth camera's misses), left out */
    int has_viewpoint;         /* 1 for a PCD: the points were seen from */
    double viewpoint[3];       /* the sensor, at the origin (PCL's default
                                  VIEWPOINT) */
} relief_points_read_info;

/* Read the input of relief_complete_points: PLY, OBJ, OFF or STL by
 * relief_mesh_read, or, by the extension .pcd (case-insensitive), a PCD
 * cloud, organised or not (x y z, rgb when present; ascii, binary or
 * binary_compressed): its finite points in the file's order, with colour
 * when it has rgb, no triangles. max_points (0: no limit) refuses a larger
 * PCD before its points are decoded (RELIEF_E_NOMEM). Errors name the
 * path: RELIEF_E_IO, RELIEF_E_FORMAT, RELIEF_E_PARSE (malformed, truncated,
 * no finite point). info may be NULL. *out only on success. */
RELIEF_API relief_status relief_points_read(const char *path, uint64_t max_points,
                                            relief_mesh **out, relief_points_read_info *info,
                                            relief_error *err);

/* One open boundary of the input (a mesh's boundary loop, a point set's
 * rim) and what became of it. */
typedef struct relief_hole {
    unsigned rim_points;     /* its points (a mesh's: boundary vertices) */
    double across;           /* twice the largest distance of a rim point
                                from the centre: the diameter of a round hole,
                                in the input's units */
    double centre[3];        /* the rim points' centroid */
    const char *fate;        /* "filled"; or left open: "too_small" (noise),
                                "border" (an open scan's outer border),
                                "too_large" (wider than max_hole),
                                "not_selected" (a hole mask misses it) */
} relief_hole;

/* What a relief_complete_points call did. */
typedef struct relief_complete_points_report {
    size_t points_in;        /* input points */
    size_t added;            /* new points */
    size_t masked;           /* hole mask points synthesised again */
    size_t clone_points;     /* points of the clone */
    unsigned holes;          /* holes filled */
    unsigned outer_borders;  /* rims taken for an outer border, left open */
    unsigned holes_too_small; /* rims too small to fill */
    unsigned holes_too_large; /* rims wider than max_hole, left open */
    unsigned holes_not_selected; /* rims the hole mask misses, left open */
    double max_hole;         /* the limit applied (0 with a hole mask) */
    relief_hole *hole_list;  /* every open boundary, n_hole_list (owned) */
    size_t n_hole_list;
    double spacing;          /* median nearest-neighbour distance */
    double detail_rms;       /* RMS of the detail over the input */
    double reconstruction_rms; /* RMS of |base + detail - point| over the input */
    size_t triangles;        /* of *out (params.mesh) */
    size_t open_loops;       /* params.mesh on a mesh: loops of *out still open
                                at a filled hole (its rim or its new points),
                                which the patches did not close */
    size_t open_edges;       /* their boundary edges */
    size_t clusters, active_clusters, exemplars;
    int iterations;          /* texture optimisation iterations run */
    int converged;
    char grid_search[336];   /* the grid search that ran, and any warning */
    int grid_search_warning; /* 1: OpenCL could not be used for it */
    double seconds_analysis, seconds_base, seconds_fill, seconds_texture, seconds_total;
    char *json;              /* the report as `relief complete-points --report`
                                writes it, "input" and "output" from
                                run.input_name and output_name (null when
                                NULL) (owned) */
    char holes_left[640];    /* "" or one line naming the widest rims the hole
                                model left open by its rule (an outer border,
                                an opening wider than max_hole), each with its
                                size, centre and the max_hole or hole_ball that
                                fills it */
} relief_complete_points_report;

/* Free what the report owns and zero it. NULL accepted. */
RELIEF_API void relief_complete_points_report_free(relief_complete_points_report *rep);

/* Complete `in` (positions; colour, normals, triangles when present) into
 * *out: the input's points first (label 0, the input's colour, oriented
 * normals), then the new ones (label 1); triangles only with params.mesh.
 * A mesh's holes are its boundary loops, a bare point set's where points
 * see neighbours on one side only; an open scan's outer border, and an
 * opening wider than max_hole, are left open, and a hole mask selects the
 * holes it touches (each is listed in rep's hole_list with its fate).
 * RELIEF_E_RANGE for a parameter, nothing to fill (the message names the
 * widest rims and the max_hole or hole_ball that would fill each), too few or
 * collinear points, an input with no colour for what = colour, or holes
 * larger than the sample region; RELIEF_E_USAGE for NULL, or hole_labels
 * or sample_labels on an input without labels; RELIEF_E_MESH for an
 * invalid input (relief_mesh_validate); RELIEF_E_NOMEM when the estimate
 * is over run.max_memory; RELIEF_E_CANCELLED when run.progress asks (its
 * stages: analysis, base, fill, texture optimisation per iteration,
 * result). *out and rep only on success (rep may be NULL). */
RELIEF_API relief_status relief_complete_points(const relief_mesh *in,
                                                const relief_complete_points_params *p,
                                                relief_mesh **out,
                                                relief_complete_points_report *rep,
                                                relief_error *err);

#ifdef __cplusplus
}
#endif

#endif /* RELIEF_POINTS_H */
