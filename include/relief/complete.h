/* relief/complete.h: a scan's missing part completed with its own relief
 * and colour (Breckon and Fisher, papers 000 and 001): the smooth
 * underlying shape (a fitted plane, sphere or cylinder, or the capture's
 * own smoothed, hole-filled base), then the relief grown over it vertex by
 * vertex, mono-scale or over a hierarchy of levels.
 *
 *   relief_complete_params p = relief_complete_params_default();
 *   relief_complete_report rep;
 *   relief_mesh *done = NULL;
 *   if (relief_complete(capture, &p, &done, &rep, &err) == RELIEF_OK) {
 *       ... done's label 1 marks the vertices completed ...
 *       relief_complete_report_free(&rep);
 *       relief_mesh_destroy(done);
 *   }
 *
 * Lengths are in the input's units; angles in radians. */
#ifndef RELIEF_COMPLETE_H
#define RELIEF_COMPLETE_H

#include "relief/core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* --------------------------------------------------------------- the fit */

/* The primitives a capture is fitted with; auto chooses among them.
 * X(code, name) */
#define RELIEF_FIT_MODEL_LIST(X)                                                \
    X(RELIEF_FIT_AUTO, "auto")                                                  \
    X(RELIEF_FIT_PLANE, "plane")                                                \
    X(RELIEF_FIT_SPHERE, "sphere")                                              \
    X(RELIEF_FIT_CYLINDER, "cylinder")

typedef enum relief_fit_model {
#define RELIEF_X_ENUM(code, name) code,
    RELIEF_FIT_MODEL_LIST(RELIEF_X_ENUM)
#undef RELIEF_X_ENUM
} relief_fit_model;

/* "auto", "plane", "sphere" or "cylinder"; "unknown" out of range. */
RELIEF_API const char *relief_fit_model_name(relief_fit_model model);

/* A fit is poor when rms > RELIEF_FIT_POOR * the primitive's size. */
#define RELIEF_FIT_POOR 0.10
#define RELIEF_FIT_REASON_MAX 320

/* A fitted surface. Signed distances are positive on the side the normal
 * points to: outside a sphere or cylinder, along `dir` for a plane. */
typedef struct relief_fit_primitive {
    relief_fit_model model; /* RELIEF_FIT_PLANE, _SPHERE or _CYLINDER */
    double point[3]; /* plane: its point nearest the input centroid;
                        sphere: the centre;
                        cylinder: the axis point nearest the input centroid */
    double dir[3];   /* plane: unit normal; cylinder: unit axis direction;
                        sphere: (0, 0, 0). Sign: along the mean of the
                        input normals (plane, when normals were given),
                        else its largest-magnitude component is positive. */
    double radius;   /* sphere and cylinder: > 0; plane: 0 */
} relief_fit_primitive;

/* What a fit found. */
typedef struct relief_fit_result {
    relief_fit_primitive prim;
    double rms;             /* RMS orthogonal distance over the inliers of
                               the robust trimming (input units) */
    double rms_all;         /* the same over all n points */
    double inlier_fraction; /* fraction of ALL points with |distance| <=
                               3 * rms, in [0, 1] */
    size_t n_points;        /* points given */
    size_t n_inliers;       /* points the rms is taken over */
    double size;            /* sphere, cylinder: the radius; plane: the
                               inliers' RMS distance from their centroid
                               within the plane (input units) */
    int poor_fit;           /* 1 when rms > RELIEF_FIT_POOR * size */
    double model_rms[4];    /* indexed by relief_fit_model: inlier rms of
                               each model tried (all three under auto, one
                               otherwise); -1 for a model not tried or that
                               could not be fitted. [RELIEF_FIT_AUTO] = -1. */
    char reason[RELIEF_FIT_REASON_MAX]; /* one sentence, e.g. "sphere: rms
                               0.0119 vs plane 0.1335, cylinder 0.0507" */
} relief_fit_result;

/* Fit `model` (or choose one, RELIEF_FIT_AUTO: each extra parameter must
 * cut the residual by 10 %) to n points, in double precision: a
 * least-squares start, Levenberg-Marquardt on the orthogonal distances,
 * outliers beyond 3 robust scales trimmed and the model refitted.
 *
 * pts      n x 3 positions (input units), finite.
 * normals  n x 3 unit normals of the points, or NULL (used to estimate a
 *          cylinder's axis and to orient a plane's normal).
 * n        at least 3 (plane, auto), 4 (sphere), 5 (cylinder).
 * out      written only on success.
 *
 * RELIEF_E_USAGE for NULL arrays or an unknown model; RELIEF_E_MESH for too
 * few points, a non-finite coordinate, coincident or collinear points,
 * coplanar points asked to fit a sphere, or a model whose radius diverges;
 * RELIEF_E_NOMEM. */
RELIEF_API relief_status relief_fit(const double *pts, const double *normals, size_t n,
                                    relief_fit_model model, relief_fit_result *out,
                                    relief_error *err);

/* relief_fit on a mesh's vertices, with the mesh's normals, else its
 * area-weighted triangle normals, else none. */
RELIEF_API relief_status relief_fit_mesh(const relief_mesh *mesh, relief_fit_model model,
                                         relief_fit_result *out, relief_error *err);

/* Signed orthogonal distance (input units) from p to the primitive. */
RELIEF_API double relief_fit_distance(const relief_fit_primitive *prim, const double p[3]);

/* ----------------------------------------------------------- parameters */

/* What the relief is grown over:
 *   auto       smooth when no primitive fits well and neither fit, extent
 *              nor accept_poor_fit is set, else the primitive;
 *   primitive  the fitted plane, sphere or cylinder;
 *   smooth     the capture's smoothed, hole-filled base (paper 002): any
 *              object, a head, a statue.
 * X(code, name) */
#define RELIEF_BASE_LIST(X)                                                     \
    X(RELIEF_BASE_AUTO, "auto")                                                 \
    X(RELIEF_BASE_PRIMITIVE, "primitive")                                       \
    X(RELIEF_BASE_SMOOTH, "smooth")

typedef enum relief_base {
#define RELIEF_X_ENUM(code, name) code,
    RELIEF_BASE_LIST(RELIEF_X_ENUM)
#undef RELIEF_X_ENUM
} relief_base;

/* Which uncovered part of the primitive is completed:
 *   auto   a plane's holes (the whole extent when one is given); a
 *          cylinder's or sphere's whole, as for a one-sided scan's hidden
 *          side, unless the capture has holes and goes all round it
 *          (every direction round the axis, or from the centre, within 45
 *          degrees of a captured vertex: a band, a vase, a head; the
 *          report's round_gap_degrees) or covers less than 20 % of it (a
 *          patch of something larger): then its holes;
 *   holes  the holes inside the capture's outline; over a cylinder or
 *          sphere (a plane too when max_hole or a selection is given) those
 *          the hole model keeps: a rim wider than max_hole stays open, and
 *          a selection (hole_ball, hole_labels) fills exactly what it
 *          touches (the report's hole_model lists every loop and its fate);
 *   whole  every uncovered point of the region. */
#define RELIEF_FILL_REGION_LIST(X)                                              \
    X(RELIEF_FILL_AUTO, "auto")                                                 \
    X(RELIEF_FILL_HOLES, "holes")                                               \
    X(RELIEF_FILL_WHOLE, "whole")

typedef enum relief_fill_region {
#define RELIEF_X_ENUM(code, name) code,
    RELIEF_FILL_REGION_LIST(RELIEF_X_ENUM)
#undef RELIEF_X_ENUM
} relief_fill_region;

/* The local frames the relief is copied in: paper 000's rule on the
 * normal, or along the primitive's parameterisation. */
#define RELIEF_FRAMES_LIST(X)                                                   \
    X(RELIEF_FRAMES_PAPER, "paper")                                             \
    X(RELIEF_FRAMES_PRIMITIVE, "primitive")

typedef enum relief_frames {
#define RELIEF_X_ENUM(code, name) code,
    RELIEF_FRAMES_LIST(RELIEF_X_ENUM)
#undef RELIEF_X_ENUM
} relief_frames;

/* Where oversampling puts a new sample on an edge of the capture: the
 * papers' coplanar midpoint, or the butterfly point on the smooth surface
 * through the capture. */
#define RELIEF_OVERSAMPLE_SCHEME_LIST(X)                                        \
    X(RELIEF_OVERSAMPLE_MIDPOINT, "midpoint")                                   \
    X(RELIEF_OVERSAMPLE_BUTTERFLY, "butterfly")

typedef enum relief_oversample_scheme {
#define RELIEF_X_ENUM(code, name) code,
    RELIEF_OVERSAMPLE_SCHEME_LIST(RELIEF_X_ENUM)
#undef RELIEF_X_ENUM
} relief_oversample_scheme;

/* How a target's candidates are found: every (sample, rotation)
 * (exhaustive, paper 000), or the k-coherence search's few hundred
 * (coherent: sub-quadratic); auto: exhaustive while samples x rotations x
 * targets is at most 1e8, else coherent. */
#define RELIEF_SEARCH_LIST(X)                                                   \
    X(RELIEF_SEARCH_AUTO, "auto")                                               \
    X(RELIEF_SEARCH_EXHAUSTIVE, "exhaustive")                                   \
    X(RELIEF_SEARCH_COHERENT, "coherent")

typedef enum relief_search_mode {
#define RELIEF_X_ENUM(code, name) code,
    RELIEF_SEARCH_LIST(RELIEF_X_ENUM)
#undef RELIEF_X_ENUM
} relief_search_mode;

/* Names ("auto", ...); "unknown" out of range. */
RELIEF_API const char *relief_base_name(relief_base base);
RELIEF_API const char *relief_fill_region_name(relief_fill_region region);
RELIEF_API const char *relief_frames_name(relief_frames frames);
RELIEF_API const char *relief_oversample_scheme_name(relief_oversample_scheme scheme);
RELIEF_API const char *relief_search_name(relief_search_mode search);

/* Parameters of relief_complete (all fields) and relief_smooth (the
 * smooth completion's). Ranges are checked by
 * relief_complete_params_validate; every engine call checks them too. */
typedef struct relief_complete_params {
    /* the smooth completion */
    relief_base base;           /* default auto */
    relief_fit_model fit;       /* default auto */
    relief_fill_region fill;    /* default auto */
    int oversample;             /* 1-to-4 subdivision passes of the capture;
                                   1, [0, 4] */
    relief_oversample_scheme oversample_scheme; /* default butterfly */
    double spacing;             /* target spacing; 0 (default): the 10th
                                   percentile of the capture's edge lengths;
                                   else finite > 0 */
    int n_extent;               /* 0 (default): no extent; 2: extent is a
                                   cylinder's z0, z1 along the fitted axis from
                                   its axis point; 4: a plane's u0, v0, u1, v1
                                   in its (e1, e2) frame from its fitted point
                                   (both in the report) */
    double extent[4];
    relief_frames frames;       /* default paper */
    int accept_poor_fit;        /* 1: go on when the fit's rms is over 10 % of
                                   the primitive's size (a warning in the
                                   report); 0 (default): refuse */
    int keep_spikes;            /* 1: keep the capture's spikes as relief; 0
                                   (default): a vertex over 8 robust roughness
                                   scales outside its neighbours' heights is a
                                   scanner spike, left out and completed */
    double max_growth;          /* refuse more than this many targets per
                                   captured vertex (a primitive that does not
                                   suit the capture); 100, >= 0, 0: no limit */
    double max_hole;            /* the hole model (relief/points.h): a hole
                                   whose rim is wider than this (the capture's
                                   units; twice the largest distance of a rim
                                   vertex from the rim's centre) is an opening
                                   by design (a vase's mouth or base) and stays
                                   open, on the smooth base and, when only holes
                                   are filled, over a primitive; 0 (default): a
                                   quarter of the capture's bounding-box
                                   diagonal; [0, 1e30] */
    int has_hole_ball;          /* 1: fill exactly the holes whose rims have a
                                   vertex within hole_ball (X, Y, Z, R > 0),
                                   whatever their size: on the smooth base, and
                                   over a primitive only holes (fill auto
                                   becomes holes). A rim the hole model would
                                   leave open (a border, or wider than
                                   max_hole: a cut that reaches the border)
                                   is filled only where the ball touches it,
                                   given 3 of its vertices (relief/points.h's
                                   rule). 0 (default): none */
    double hole_ball[4];
    int hole_labels;            /* 1: the same with the holes whose rims have a
                                   vertex labelled non-zero (the capture's PLY
                                   `label`; it must have labels); not with
                                   has_hole_ball */
    /* the growth (relief_complete only) */
    int window;                 /* W, neighbourhood radius in edge hops; 3, [1, 16] */
    int rotations;              /* R, rotations tried per sample, [1, 64]; 0
                                   (default): 1 on a plane, 4 otherwise */
    double error;               /* e, acceptance threshold; 0.1, (0, 1e6] */
    double mu;                  /* shape weight, [0, 1]; -1 (default): 1
                                   without colour, 0.5 with */
    uint32_t seed;              /* MT19937 seed; 1 */
    double coherence;           /* kappa: take the best candidate that continues
                                   a neighbour's source when its score is within
                                   kappa x the best; 0 (default, paper 000's
                                   draw alone), or [1, 100] */
    relief_search_mode search;  /* default auto */
    int search_k;               /* similar samples per patch for coherent; 8,
                                   [1, 64] */
    int levels;                 /* M hierarchy levels; 1 (mono-scale), [1, 8] */
    int bootstrap;              /* 1: completed targets become matchable too; 0 */
    int prune;                  /* 1 (default): stop a candidate's score once it
                                   cannot win (same result, faster); 0: score
                                   every candidate in full */
    /* saving and resuming a long growth */
    const char *checkpoint;     /* file the growth's state is saved to when the
                                   call is cancelled or the device fails, and
                                   every checkpoint_every seconds; removed when
                                   the call succeeds, unless it was there
                                   before the call (a relief checkpoint, then
                                   replaced, never removed; any other file is
                                   refused, RELIEF_REASON_NOT_RELIEFS); NULL
                                   (default): none */
    double checkpoint_every;    /* seconds between saves; 300, >= 0; 0: only on
                                   cancel or failure */
    const char *resume;         /* a checkpoint of a call with the same input
                                   and parameters to continue (any backend):
                                   the same result as a call never stopped;
                                   NULL (default) */
    /* the report */
    int measure;                /* 1 (default): the report's JSON and folder carry
                                   the completion's measures (relief_eval's, over
                                   the primitive); 0: leave them out (saves their
                                   time on a large mesh) */
    const char *report_dir;     /* a folder of renders, histograms, report.json
                                   and index.html, staged beside this path and
                                   handed back in the report (relief_complete
                                   only); NULL (default): none */
    relief_run_options run;     /* backend (auto: OpenCL on a GPU, else host),
                                   device, memory, progress, report names */
} relief_complete_params;

/* The defaults above. */
RELIEF_API relief_complete_params relief_complete_params_default(void);

/* Check every field; RELIEF_E_RANGE (or RELIEF_E_USAGE for a combination)
 * naming the first field out of range with its range. */
RELIEF_API relief_status relief_complete_params_validate(const relief_complete_params *p,
                                                         relief_error *err);

/* relief_complete_params described field by field (relief_param,
 * relief/core.h): relief_complete's parameters, and relief_smooth's (the
 * smooth completion's fields, max_memory and threads). */
RELIEF_API const relief_param *relief_complete_param_table(size_t *count);
RELIEF_API const relief_param *relief_smooth_param_table(size_t *count);

/* ---------------------------------------------------------------- report */

/* A --report-dir folder staged by relief_complete, not yet in place. */
typedef struct relief_report_folder relief_report_folder;

/* Move the folder into place and free it; on failure it is removed. A
 * folder there before is replaced only when it is empty or a report relief
 * wrote (its .relief-report marker, nothing else added), else
 * RELIEF_E_IO with reason RELIEF_REASON_NOT_RELIEFS. NULL is accepted
 * (nothing to do). */
RELIEF_API relief_status relief_report_folder_commit(relief_report_folder *folder,
                                                     relief_error *err);

/* Most levels of a hierarchy. */
#define RELIEF_COMPLETE_MAX_LEVELS 8

/* One thing a call wants its caller to know, in a sentence. */
typedef struct relief_note {
    int warning;              /* 1: a warning (a poor fit accepted, part of the
                                 capture dropped, OpenCL left); 0: a remark */
    char text[640];
} relief_note;

/* What a relief_complete or relief_smooth call did. Counts are vertices
 * unless named otherwise; seconds are wall time. */
typedef struct relief_complete_report {
    int smooth_base;          /* 1: grown on the capture's smoothed base (no
                                 primitive; `fit` only reported) */
    relief_fit_result fit;    /* the primitive fitted to the capture */
    relief_fill_region region; /* what was completed: holes or whole */
    double spacing;           /* target spacing used */
    size_t captured;          /* capture vertices */
    size_t samples;           /* after oversampling */
    size_t targets;           /* vertices completed */
    size_t dropped;           /* capture vertices in no triangle, left out */
    size_t folded_triangles;  /* capture triangles folded over the primitive,
                                 dropped with their vertices and completed */
    size_t spikes;            /* capture vertices taken for scanner spikes */
    size_t holes;             /* uncovered regions inside the capture's outline */
    /* the growth */
    int levels;               /* levels grown (1: mono-scale) */
    size_t level_vertices[RELIEF_COMPLETE_MAX_LEVELS]; /* each level's, coarsest
                                 first */
    uint64_t memory_bytes;    /* the growth's host memory, estimated before it */
    int resumed;              /* 1: continued from params.resume, at */
    int resumed_level;        /* this level (1 for mono-scale) with */
    size_t resumed_done;      /* this many targets of it textured, of */
    size_t resumed_targets;   /* the level's targets */
    int rotations;            /* R used */
    relief_search_mode search; /* the search used (auto resolved) */
    size_t acceptances;       /* targets textured (all levels) */
    size_t passes;            /* boundary lists built */
    size_t rejections;        /* draws over the threshold */
    size_t threshold_raises;  /* passes with no acceptance (e x 1.1) */
    size_t candidates;        /* (sample, rotation) pairs scored */
    double error_final;       /* e at the end */
    /* where it ran */
    relief_backend backend;   /* the backend that scored (the last level's) */
    char device[256];         /* what it ran on */
    char backend_note[1024];  /* why auto chose it ("" when the backend was
                                 named); leaving OpenCL during the run is a note */
    int backend_warning;      /* 1: backend_note says OpenCL could not be used */
    /* what was refused, dropped, chosen or left, in the order found */
    int n_notes;
    relief_note notes[8];
    /* seconds */
    double seconds_smooth;    /* fit, targets, oversampling, triangulation */
    double seconds_growth;    /* the growth, all levels (hierarchy included) */
    double seconds_match;     /* of which scoring candidates */
    double seconds_total;
    /* the full report, as `relief complete --report` writes it: one JSON
     * object (owned; freed by relief_complete_report_free) */
    char *json;
    /* params.report_dir's folder, staged (owned): commit it with
     * relief_report_folder_commit, or leave it to
     * relief_complete_report_free, which removes it */
    relief_report_folder *folder;
} relief_complete_report;

/* Free what the report owns (json, an uncommitted folder) and zero it.
 * NULL accepted. */
RELIEF_API void relief_complete_report_free(relief_complete_report *rep);

/* ------------------------------------------------------------- the calls */

/* The smooth completion alone (no relief): the capture's samples and the
 * targets laid on the fitted primitive over the missing region, in one
 * manifold triangulation, into *out (label 0 samples, 1 targets; colour
 * when the capture has it). Uses the smooth-completion fields of `p`
 * (base must be auto or primitive). `rep` may be NULL; when given it is
 * filled (its growth fields zero) and must be freed. RELIEF_E_MESH when the
 * capture fits no primitive well (unless accept_poor_fit), has nothing to
 * complete, or cannot be joined into a manifold. */
RELIEF_API relief_status relief_smooth(const relief_mesh *capture,
                                       const relief_complete_params *p, relief_mesh **out,
                                       relief_complete_report *rep, relief_error *err);

/* Complete `capture` (a mesh or a point cloud; colour when it has it) into
 * *out: the capture's samples (label 0) and the completed targets (label
 * 1) carrying relief and colour grown from the capture. Deterministic for a
 * seed whatever the backend. `rep` may be NULL; when given it is filled on
 * success and must be freed with relief_complete_report_free. Errors:
 * RELIEF_E_RANGE for a parameter, RELIEF_E_MESH for a capture that cannot
 * be completed (named why), RELIEF_E_NOMEM when the run's estimate is over
 * run.max_memory, RELIEF_E_DEVICE for an OpenCL failure with an explicit
 * backend, RELIEF_E_CANCELLED when run.progress asked (the checkpoint saved
 * when one is named). *out only on success. */
RELIEF_API relief_status relief_complete(const relief_mesh *capture,
                                         const relief_complete_params *p, relief_mesh **out,
                                         relief_complete_report *rep, relief_error *err);

#ifdef __cplusplus
}
#endif

#endif /* RELIEF_COMPLETE_H */
