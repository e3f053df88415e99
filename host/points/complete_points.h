/* Completion of colour and geometric detail on a point set with no
 * primitive under it (paper 002; `relief complete-points`, issue 21).
 *
 * The pipeline:
 *   1. local analysis: k-NN, covariance normals consistently oriented,
 *      sigma_n, the spacing (points/analysis.h);
 *   2. the holes: a mesh's boundary loops, or a bare point set's one-sided
 *      points (points/holes.h), and/or a given mask;
 *   3. base and detail: the curvature flow gives the base M', the detail c'
 *      is the signed distance over it (points/flow.h);
 *   4. the base's holes filled by the hierarchical compactly supported RBF
 *      and new base points sampled on it at the spacing (points/rbf.h);
 *   5. c' (and colour) completed on the new points by the texture
 *      optimisation over overlapping clusters (points/texopt.h), from
 *      exemplars outside the holes' band;
 *   6. each new point placed at q' + c' n, n its base normal blended toward
 *      the rim's detail direction within the seam band (section 6.1).
 * Lengths are in the input's unit; "spacings" are multiples of the median
 * nearest-neighbour distance. */
#ifndef RELIEF_HOST_POINTS_COMPLETE_POINTS_H
#define RELIEF_HOST_POINTS_COMPLETE_POINTS_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"
#include "base/progress.h"
#include "points/holes.h"
#include "points/rbf.h"
#include "points/texopt.h"

enum { RELIEF_MESH_PATCH_FAIR = 0, RELIEF_MESH_PATCH_RBF = 1 };

typedef struct relief_points_params {
    relief_points_what what;
    int k;                /* neighbours of the local analysis, 6..64 (default 16) */
    int smooth_steps;     /* curvature-flow steps for the base, 0..10000 (default 20) */
    double smooth_dt;     /* time step in spacings, (0, 100] (default 10; flow.h) */
    double max_detail;    /* the farthest a base point lies from its point, in
                             spacings, 0..100 (default 1; 0: unbounded; flow.h) */
    double rim_gap;       /* one-sided test's angular gap, radians (default pi/2) */
    double band;          /* exemplars keep this far from a rim, spacings >= 0 (default 2) */
    double seam_band;     /* normal blending band d, spacings >= 0 (default 3) */
    double max_hole;      /* rims wider than this (the input's units) are left open;
                             0 (default): a quarter of the bounding box's diagonal
                             (holes.h's rule; a hole mask selects instead) */
    const uint8_t *hole_mask; /* n_in entries or NULL: points whose colour and detail are to
                                 be synthesised again; the holes whose rims it touches
                                 are then the ones filled */
    const uint8_t *hole_select; /* n_in entries or NULL, when hole_mask is NULL: the
                                   holes whose rims it touches are the ones filled,
                                   and no point is synthesised again (complete's
                                   base smooth with a hole_ball or hole_labels) */
    const uint8_t *sample_mask; /* n_in entries or NULL: where exemplars may be centred;
                                   default everywhere outside the band */
    const relief_mesh *clone; /* or NULL: detail (and colour, when both have it) copied from
                                 this other model instead of the input's own (6.3); it
                                 should be sampled about as densely */
    const double *viewpoint;  /* 3 or NULL: a camera the normals face (a PCD's sensor) */
    int smooth_only;      /* the smooth fill alone (paper 002's Fig. 9g, a baseline): new
                             points on the filled base, no detail, colour from the rim */
    int detail_histogram; /* 1 (default): the new points' detail c' ends histogram-
                             matched to the exemplars' about the hole (texopt.h's
                             histogram bit): the averaging of overlapping matches and
                             their leaning to smooth exemplars narrow it; 0: as the
                             optimisation left it (README has both measured); never
                             over a mesh's faired patches (complete_points.c) */
    int mesh;             /* 1: *out also gets triangles: a mesh input's own and the
                             filled holes' patches (points/patch_mesh.h); for a point
                             set, a surface through all the output's points
                             (points/surface_mesh.h) */
    int keep_base;        /* 1: the report keeps the base (rep->base, rep->base_nrm),
                             and the mesh's hole patches join the points on it */
    int no_normals;       /* 1: *out has no normals: its caller sets its own
                             (base_surface.h), so the k-NN graph over every
                             output point that estimates them is not built */
    size_t max_new;       /* refuse more new points than this (default 0: 4 x the input) */
    int mesh_patch;       /* a mesh's holes: RELIEF_MESH_PATCH_FAIR (0, the default)
                             closes each on the base by mesh/hole_fill.h, its
                             vertices the new points; RELIEF_MESH_PATCH_RBF lays
                             paper 002's RBF points and triangulates them after
                             (points/patch_mesh.h), as relief did before issue 61 */
    relief_progress *progress; /* NULL (default), or the caller's: the stages take
                                  consecutive shares of it (analysis, base, fill,
                                  texture, result), and a cancel stops the run at the
                                  next stage or texture iteration (RELIEF_E_CANCELLED) */
    int threads;          /* host threads of every stage, 0..64 (default 0: the CPUs
                             this thread may run on, its affinity; 1: the calling
                             thread alone, the serial
                             reference); each stage shares out work whose items are
                             computed alone, so the bytes do not depend on it */
    relief_texopt_params tex; /* its progress and threads are set from the ones above */
    relief_rbf_params rbf; /* spacing is set from the points when 0; threads from above */
} relief_points_params;

relief_points_params relief_points_params_default(void);

typedef struct relief_points_report {
    size_t n_in, n_added, n_masked, n_clone;
    relief_hole_info holes;
    double spacing;          /* median nearest-neighbour distance */
    double recon_rms;        /* RMS of |p' + c' n' - p| over the input (section 5.2) */
    double detail_rms;       /* RMS of c' over the input */
    size_t patch_triangles;  /* triangles laid over the holes (p->mesh) */
    size_t patch_skipped;    /* holes qhull could not triangulate */
    size_t open_edges, open_loops; /* a mesh's (p->mesh): boundary edges at a filled
                             hole or a new point left open, and the loops they make
                             (relief_points_open_loops) */
    size_t mesh_triangles;   /* all of *out's triangles (p->mesh) */
    size_t untangled;        /* new points drawn back toward the base where their
                                detail crossed the surface (mesh/untangle.h; p->mesh) */
    size_t crossing_left;    /* triangles with a new point still crossing another */
    size_t copies_welded;    /* a split vertex's copies welded again where the patch
                             closed the pinch (p->mesh; mesh/weld.h) */
    int mesh_of_points;      /* 1: they are a point set's surface, counted below */
    size_t mesh_candidates, mesh_boundary_edges, mesh_bare_points; /* a point set's surface
                             (p->mesh): triangles two or three corners proposed, edges with one
                             triangle, points in none */
    double t_analysis, t_base, t_fill, t_texture, t_total; /* seconds */
    relief_texopt_result tex; /* energy per iteration etc. (owned; freed by _free) */
    double *base, *base_nrm;  /* with p->keep_base: (n_in + n_added) x 3, the base point
                                 and unit normal of every output point (owned) */
    int tex_channels;
} relief_points_report;

void relief_points_report_free(relief_points_report *r);

/* Complete `in` (positions; colour, normals, triangles when present) into
 * *out: the input's points first (label 0, the input's colour, oriented
 * normals), then the new ones (label 1); triangles only with p->mesh.
 * RELIEF_E_RANGE when a parameter is out of range, there is nothing to
 * fill (no hole and no mask; naming which), the points are too few or
 * collinear, or fewer exemplar points than points to synthesise (the holes
 * larger than the sample region); RELIEF_E_NOMEM; RELIEF_E_CANCELLED (p->
 * progress). *out only on success; rep is cleared on failure. */
relief_status relief_points_complete(const relief_mesh *in, const relief_points_params *p,
                                     relief_mesh **out, relief_points_report *rep,
                                     relief_error *err);

#endif
