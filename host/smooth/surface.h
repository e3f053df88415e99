/* The combined surface on which relief grows (stages 3 to 5 of DESIGN.md):
 * the capture's samples and the target vertices laid on the fitted
 * primitive, in one triangulation, with the per-vertex state the growth
 * needs. Built by relief_surface_build (smooth.c). */
#ifndef RELIEF_HOST_SURFACE_H
#define RELIEF_HOST_SURFACE_H

#include "relief/relief.h"
#include "base/params.h"
#include "smooth/fit.h"
#include "smooth/param.h"

/* Which uncovered region of the primitive is completed (targets.h):
 * relief/complete.h's relief_fill_region. */
typedef relief_fill_region relief_fill;

/* A capture covering less than this share of a cylinder's turn (over its
 * axial extent) or of a sphere is a patch of something larger, not a
 * one-sided scan: RELIEF_FILL_AUTO then completes its holes only. A depth
 * camera sees a third to a half of a mug or a trunk, a golf ball's front. */
#define RELIEF_ONE_SIDED_COVER 0.2

/* A capture whose every direction round its cylinder's axis (or from its
 * sphere's centre) lies within this many degrees of a captured vertex goes
 * all round its primitive: it has no hidden side, and RELIEF_FILL_AUTO
 * completes its holes only (a band round a crown, a vase with a cut, a
 * head on a sphere). A one-sided scan (a mug or a globe seen from one
 * side) leaves directions 90 degrees or more from anything captured. */
#define RELIEF_ALL_ROUND_DEGREES 45.0

/* Which of the regions the capture's outline encloses a fill of the holes
 * completes: keep(ctx, pts, n) with a region's lattice points (n x 3, on
 * the primitive) answers non-zero to complete it. keep NULL: every one.
 * The caller's hole model (issue 40) decides here, since the smooth layer
 * does not know which of the capture's boundary loops are the user's. */
typedef struct relief_region_filter {
    int (*keep)(void *ctx, const double *pts, size_t n);
    /* NULL, or: is this lattice point (3, on the primitive) of a region
     * outside the outline to be completed all the same? A notch in the
     * capture's edge is no enclosed hole; a selection that names it (a
     * border's rim filled in part, mesh/holes.h) takes its points. */
    int (*keep_point)(void *ctx, const double *p);
    void *ctx;
    int on_plane;   /* 1: a plane's holes too; 0: a cylinder's or sphere's
                       only (a plane's patch has no opening by design: its
                       holes are filled whatever their size, paper 001) */
} relief_region_filter;

/* How relief_surface_build's refusal begins when the filter left every
 * enclosed region open (the caller says which loops and why). */
#define RELIEF_HOLES_LEFT_OPEN "nothing to complete: the hole model leaves the"

/* Options of the smooth completion beyond relief_params. */
typedef struct relief_smooth_options {
    relief_frames frames;     /* default RELIEF_FRAMES_PAPER */
    double spacing_percentile; /* robust low percentile of the capture's edge
                                  lengths taken as the target spacing when
                                  relief_params.spacing is 0; default 10 */
    int oversample_scheme;     /* RELIEF_OVERSAMPLE_* (oversample.h);
                                  default butterfly */
    int accept_poor_fit;       /* 0 (default): refuse a fit whose rms is
                                  over RELIEF_FIT_POOR of the primitive's
                                  size; 1: go on (the caller warns) */
    double spike_k;            /* a capture vertex whose height lies outside
                                  its neighbours' by more than this many
                                  robust roughness scales is a scanner
                                  spike, left out of the samples
                                  (surface_check.h); default
                                  RELIEF_SPIKE_K, 0: keep them */
    relief_fill fill;          /* region completed; default RELIEF_FILL_AUTO */
    relief_region_filter holes; /* which enclosed regions a fill of the holes
                                  completes; default: all */
    double max_growth;         /* refuse a completion of more than this many
                                  targets per captured vertex, the sign of a
                                  primitive that does not suit the capture
                                  (a nearly flat patch fitted as a huge
                                  cylinder or sphere); default
                                  RELIEF_MAX_GROWTH, 0: no limit */
    const relief_fit_result *fitted; /* the capture's fit with the params'
                                  model, when the caller has made it (complete's
                                  base auto does, to choose the base): taken,
                                  not fitted again; default NULL */
} relief_smooth_options;

/* Default relief_smooth_options.max_growth: targets per captured vertex. A
 * one-sided capture of a cylinder or sphere asks for about 1 to 3. */
#define RELIEF_MAX_GROWTH 100.0

/* Default relief_smooth_options.spike_k (surface_check.h): on the
 * synthetic surfaces no vertex stands out by more than 3.9 scales, on the
 * real scans' relief by 5.5 (a head's range map, a screwdriver); the
 * depth-camera floor of frag_115 has 23 vertices over 8, up to 18. */
#define RELIEF_SPIKE_K 8.0

relief_smooth_options relief_smooth_options_default(void);

/* What the capture check (surface_check.h) found folded and dropped. */
typedef struct relief_fold_stats {
    size_t triangles;         /* triangles facing away from the primitive */
    double area_fraction;     /* their share of the capture's area */
    size_t triangles_dropped; /* they and the triangles around their vertices */
    size_t vertices_dropped;  /* every vertex of a folded triangle, and any
                                 vertex left in no triangle */
} relief_fold_stats;

/* Scanner spikes the capture check (surface_check.h) left out. */
typedef struct relief_spike_stats {
    size_t vertices;          /* vertices taken for spikes, dropped */
    size_t triangles_dropped; /* the triangles around them */
    double scale;             /* robust scale of the local roughness (input units) */
    double threshold;         /* k x scale: a larger excess is a spike */
    double largest;           /* the largest excess in the capture */
} relief_spike_stats;

/* What the target lattice found uncovered and which part was completed. */
typedef struct relief_fill_stats {
    relief_fill region;       /* what was completed: HOLES or WHOLE */
    size_t holes;             /* uncovered regions the capture's outline encloses */
    size_t hole_points;       /* lattice points in them */
    size_t outside_points;    /* uncovered lattice points outside the outline
                                 (targets only when region is WHOLE) */
    double cover;             /* share of the lattice the capture covers, 0..1 */
    double round_gap;         /* cylinder, sphere: the largest angle (degrees)
                                 from a direction round the axis (from the
                                 centre) to the nearest captured vertex's */
    int all_round;            /* 1: round_gap <= RELIEF_ALL_ROUND_DEGREES */
    size_t holes_left;        /* enclosed regions the filter left open */
    size_t holes_left_points; /* lattice points in them */
    size_t outside_taken;     /* lattice points outside the outline that
                                 holes.keep_point took (a selected notch) */
    size_t dropped_holes;     /* enclosed regions where the capture as scanned
                                 had triangles that relief dropped (folded,
                                 spikes): completed whatever the filter says */
} relief_fill_stats;

/* Stages timed by relief_surface_build. */
enum {
    RELIEF_STAGE_FIT,
    RELIEF_STAGE_TARGETS,
    RELIEF_STAGE_OVERSAMPLE,
    RELIEF_STAGE_TRIANGULATE,
    RELIEF_STAGE_COUNT
};

typedef struct relief_surface {
    relief_mesh *mesh;  /* the combined triangulation (owned). Vertices
                           0..n_samples-1 are samples (label 0, the capture
                           after oversampling, at their captured positions),
                           n_samples..nv-1 targets (label 1, on the
                           primitive). Colour when the capture has it; targets
                           get mid grey until textured. */
    relief_fit_result fit;  /* the primitive and how well it fits */
    double spacing;     /* target spacing (input units) */
    double alpha;       /* widest triangle kept (circumradius in the parameter
                           domain, input units; on the sphere in space) */
    int spacing_from_capture; /* 1: derived from the capture, 0: --spacing */
    size_t n_captured;  /* capture vertices before oversampling */
    size_t n_samples;   /* samples, after oversampling */
    size_t n_targets;
    size_t n_dropped;   /* vertices left out: in no triangle (duplicates) */
    relief_fold_stats folds; /* triangles folded over the primitive, dropped
                                with their vertices before the fit's use */
    relief_spike_stats spikes; /* scanner spikes dropped from the capture */
    relief_fill_stats fill; /* the region completed (targets.h) */
    double *proj;       /* nv x 3: projection p' of each vertex on the primitive */
    double *disp;       /* nv x 3: displacement D = p - p' (0 for targets) */
    double *nrm;        /* nv x 3: the primitive's unit outward normal at p' */
    double *frame;      /* nv x 9: the local frame, rows u, v, n (n = nrm) */
    relief_domain param;  /* the primitive's parameter domain (param.h): the
                            frame --extent is given in */
    int free_form;       /* 1: a smoothed base with no parameter domain
                            (points/base_surface.h): proj and nrm are the
                            base's, `fit` and `param` only reported, and
                            coarser levels come from collapsing mesh's own
                            triangles rather than re-triangulating */
    double seconds[RELIEF_STAGE_COUNT]; /* wall time of each stage */
} relief_surface;

/* Fit a primitive to `capture`, oversample it (`params->oversample`
 * passes), lay targets on the primitive over the region to complete at the
 * target spacing, triangulate samples and targets together, and compute the
 * per-vertex state. Region: opts->fill of the uncovered part of the
 * cylinder's full turn over the capture's axial extent (or params->extent
 * z0,z1 along the axis from the fitted axis point), of the sphere, or of
 * the plane around the capture (or params->extent u0,v0,u1,v1 in the
 * plane's (e1, e2) frame from the fitted point): targets.h. RELIEF_E_MESH
 * when the capture fits no primitive well, has nothing to complete, or
 * cannot be joined into a manifold. */
relief_status relief_surface_build(const relief_mesh *capture, const relief_params *params,
                            const relief_smooth_options *opts, relief_surface **out,
                            relief_error *err);

void relief_surface_destroy(relief_surface *s);

/* A smoothed base (free_form, points/base_surface.h) laid on the primitive
 * `fit`: its targets (the patches' inner vertices) moved onto it, and every
 * vertex's base, normal (on the side of the base's own), frame and
 * displacement made the primitive's, as relief_surface_build's over its
 * lattice. complete's told holes over a primitive that fits (issue 61):
 * a sphere's cap is filled on the sphere, from the cap's own rim. */
void relief_surface_lay_on(relief_surface *s, const relief_fit_result *fit);

/* A sub-surface of s for the hierarchy (hierarchy.c): the vertices with
 * keep[v] != 0 (s->mesh->nv entries), in s's order (so samples first),
 * with their per-vertex state, labels and colours, re-triangulated as
 * relief_surface_build triangulates (qhull in the primitive's parameter domain, or
 * on the sphere), keeping triangles of circumradius <= alpha (input units;
 * on the sphere too). Vertices no triangle uses are left out.
 * A free-form s is coarsened instead: its own triangles lose the other
 * vertices by half-edge collapses on the base (relief_om_collapse, no new
 * edge longer than alpha), and a vertex that cannot go without folding
 * the surface stays in the level (so the level may hold a few vertices
 * keep did not ask for).
 * ids (at least as many entries as kept vertices) receives each level
 * vertex's id in s. RELIEF_E_MESH when the result is not manifold. */
relief_status relief_surface_level(const relief_surface *s, const uint8_t *keep, double alpha,
                                   relief_surface **out, uint32_t *ids, relief_error *err);

#endif
