/* The fit's robust core, shared by the driver (fit.c) and the refinement
 * (fit_robust.c): algebraic starting values, Levenberg-Marquardt on the
 * orthogonal distances, and trimming of outliers. Everything works on
 * points scaled to unit RMS radius about their centroid. Internal to
 * smooth/. */
#ifndef RELIEF_HOST_FIT_ROBUST_H
#define RELIEF_HOST_FIT_ROBUST_H

#include <stddef.h>
#include <stdint.h>

#include "smooth/fit.h"

/* 1 / Phi^-1(3/4): turns the median |residual| of Gaussian noise into its
 * standard deviation. */
#define MAD_TO_SIGMA 1.4826

/* Everything below works on points scaled to unit RMS radius about their
 * centroid, so these are relative tolerances. */
#define FLAT_EIGEN 1e-16      /* eigenvalue ratio taken as exactly zero spread */
#define TRIM_FLOOR 1e-12      /* trimming threshold for exact (noise-free) data */
#define RADIUS_DIVERGED 1e6   /* radius that means "this is really a plane" */
/* Levenberg-Marquardt iteration caps: a fit from an algebraic start, a
 * refit after trimming (warm start: the inliers changed a little), and the
 * quick refinement that ranks the cylinder's start axes. Well-posed fits
 * converge in well under 30 iterations; the caps bound the time spent on a
 * sphere or cylinder crawling towards infinite radius on flat data. */
#define LM_ITERATIONS_COLD 100
#define LM_ITERATIONS_WARM 30
#define LM_ITERATIONS_SCREEN 40
#define LM_LAMBDA_MAX 1e12
/* Points enough to choose a model and rank the cylinder's start axes. */
#define SELECT_POINTS 20000

enum {
    MAX_PARAMS = 5,
    AXES_IN_PLANE = 6 /* cylinder start axes tried in the principal plane */
};

/* Scratch shared by all candidate fits of one relief_fit call. */
typedef struct fit_work {
    size_t n;
    const double *q;     /* n x 3 normalised points */
    double *r;           /* n signed distances to the current primitive */
    double *tmp;         /* n scratch for medians */
    uint8_t *mask;       /* n, 1 = inlier of the current primitive */
    int threads;         /* host threads of fit_each_model (each job its own:
                            the same fits for any count) */
} fit_work;

/* One model's robust fit, in normalised coordinates. */
typedef struct fit_candidate {
    relief_fit_primitive prim;
    double rms;     /* over the inliers */
    double rms_all; /* over all points */
    size_t n_in;    /* inlier count */
    double med_abs; /* median |distance| over all points */
    double size;    /* radius, or the plane inliers' in-plane RMS radius */
} fit_candidate;

/* Fit from `start` on all points, then alternate trimming and refitting on
 * the inliers until the inlier set is stable. Returns 0 when no usable
 * primitive results. */
int fit_robust(fit_work *w, const relief_fit_primitive *start,
               size_t need, fit_candidate *out);

/* Fit one model robustly. The cylinder's start axes (n_axes x 3, unit) are
 * ranked by a short refinement on all points, scored by the median
 * |distance| (which outliers cannot sway); only the best is fitted robustly.
 * Returns 0 when nothing could be fitted. */
int fit_one_model(fit_work *w, relief_fit_model model, size_t need,
                  const double (*axes)[3], int n_axes, fit_candidate *out);

/* fit_one_model of n_models models (distinct, a cylinder last), into
 * out[i] and ok[i]: on w->threads, each of the cylinder's start axes and
 * the plane's and the sphere's fits a job of its own with scratch of its
 * own, the cylinder's fit from its best axis as soon as the axes are
 * screened, beside the others; on this thread one after another where
 * the scratch cannot be had. The same fits either way. */
void fit_each_model(fit_work *w, int n_models, const relief_fit_model *models,
                    const size_t *need, const double (*axes)[3], int n_axes, fit_candidate *out,
                    int *ok);

/* Move a cylinder's axis point to the axis point nearest the origin. The
 * axis point slides freely along the axis; pinning it near the data keeps
 * the rotation update of the direction from swinging the axis about a
 * far-away point. */
void fit_recentre_axis(relief_fit_primitive *c);

#endif
