/* Measures of a completion (DESIGN.md, "Measures of a completion"): how the
 * completed part of a surface compares with its captured part and, when the
 * true surface is known, with the truth. `relief eval`, the completion
 * report, the tests and the benchmarks all use these numbers.
 *
 * Heights. Each vertex p_i has the displacement D(i) = p_i - q_i from its
 * orthogonal projection q_i on the primitive (relief_fit_project), and the
 * signed height h_i = D(i).n(i), n(i) the primitive's outward unit normal
 * there (relief_fit_normal), so D(i) = h_i n(i) and h_i is
 * relief_fit_distance(p_i). Heights, displacements and distances are in
 * the input's units.
 *
 * Parts. The completed mesh's per-vertex labels split it into the captured
 * part (RELIEF_LABEL_CAPTURED, 0) and the completed part
 * (RELIEF_LABEL_COMPLETED, 1); any other label value is an error.
 *
 * The measures.
 * - MSI, the mean surface integral (paper 001 eq. 2), taken as the
 *   magnitude the DESIGN asks for: msi = (1/n) sum |h_i| over a part.
 *   msi_diff_percent = 100 |msi_completed - msi_captured| / msi_captured;
 *   0 when both are 0, NaN (JSON null) when only msi_captured is 0.
 * - Displacement histogram distance: h over each part binned into
 *   RELIEF_MEASURE_HIST_BINS equal bins over [min h, max h] of both parts
 *   together (bin floor((h - min) / (max - min) * bins), the maximum in the
 *   last bin), each histogram normalised to sum 1; the distance is their
 *   total variation 0.5 * sum_b |p_b - q_b|, in [0, 1] (0: same
 *   distribution at this resolution, 1: disjoint). 0 when every h is equal.
 * - Colour histogram distance (paper 000 figure 13's per-channel RGB
 *   histograms), only when the completed mesh has colour: the same total
 *   variation for each of R, G, B over RELIEF_MEASURE_HIST_BINS bins of
 *   [0, 1] (values outside are clamped), and their mean.
 * - Seam: the mean of |D(a) - D(b)| / |a' - b'| (the jump of the vector
 *   displacement per unit of edge length on the primitive) over the
 *   distinct edges (a, b) of the triangulation that join a captured and a
 *   completed vertex; inside: the same over edges with both ends captured;
 *   seam_ratio = seam / inside (about 1: the seam is no rougher than the
 *   capture itself). Per unit length because the capture is oversampled:
 *   its edges are half as long as the seam's, and a raw jump grows with the
 *   edge. NaN when there is no such edge (a point cloud), or when inside
 *   is 0. Units: dimensionless (input units per input unit).
 * - Dominant spatial frequency of h over a part (relief_dominant_frequency
 *   below), in cycles per input unit, computed in the primitive's parameter
 *   domain (param.h): plane (u, v) in-plane coordinates; cylinder u = arc
 *   length around the axis, v = axial; sphere (longitude * radius, height
 *   along the pole), the equal-area cylindrical map, which stretches
 *   features near the poles: on a sphere the figure compares parts with
 *   each other but is not a physical frequency. Angles are taken relative
 *   to the part's circular mean direction, so a part that straddles the
 *   parameterisation's cut stays contiguous in u.
 * - With a truth mesh (the true whole surface in the same coordinates; its
 *   label 1 marks the part the capture misses):
 *   truth_rms = sqrt(mean over the completed vertices that lie on the truth
 *   of (h_i - h_truth(i))^2) where h_truth(i) is the truth's height at the
 *   same place: the truth
 *   vertices' projections q are indexed in a kd-tree (FLANN, exact), the 3
 *   nearest to q_i are found, and h is interpolated linearly on the
 *   triangle incident to one of them whose projection contains q_i (its
 *   barycentric coordinates, taken in the plane of the projected triangle,
 *   are all >= -1e-9; the one with the largest smallest coordinate wins).
 *   A query that coincides with a truth vertex takes that vertex's h
 *   exactly; one contained in no such triangle (outside the truth, or a
 *   truth without triangles) has no truth under it: it is counted in
 *   n_truth_outside and left out of truth_rms and truth_max_abs, and
 *   truth_rms_outside is the RMS over those vertices against the nearest
 *   truth vertex's h (a guess, reported apart: a completion that spills
 *   past the truth would otherwise fold its spill into the error; NaN when
 *   there is none). truth_rms is NaN when no completed vertex lies on the
 *   truth. freq_truth is the dominant frequency over the truth's
 *   missing part (label 1), heights measured against the same primitive.
 *
 * The primitive is the caller's, or else fitted here (RELIEF_FIT_AUTO) to
 * the captured part: relief_fit_mesh on relief_mesh_subset of the label-0
 * vertices (so a captured vertex that lies in no all-captured triangle is
 * left out of the fit), the same fit the pipeline makes on a capture.
 */
#ifndef RELIEF_HOST_MEASURES_H
#define RELIEF_HOST_MEASURES_H

#include <stddef.h>

#include "relief/relief.h"
#include "base/json.h"
#include "smooth/fit.h"
#include "smooth/param.h"

/* Bins of the displacement and colour histograms. */
#define RELIEF_MEASURE_HIST_BINS 32
/* Most points a spectrum is computed on; a larger part is reduced to a
 * deterministic random subset (MT19937, seed 1) of this size. */
#define RELIEF_MEASURE_FREQ_MAX_POINTS 8000
/* A field whose RMS about its mean is at most this fraction of the part's
 * extent L counts as constant (no frequency). */
#define RELIEF_MEASURE_FREQ_FLAT 1e-12
/* Most coarse-grid steps from 0 to the frequency limit along one axis. */
#define RELIEF_MEASURE_FREQ_GRID 96

/* The dominant spatial frequency of a height field over scattered points. */
typedef struct relief_measure_freq {
    double freq;     /* |k| at the spectrum's peak, cycles per input unit;
                        NaN when undefined (fewer than 4 points, a
                        constant field (RELIEF_MEASURE_FREQ_FLAT), points
                        all in one place, or min > limit) */
    double k[2];     /* the peak's wave vector (k_u, k_v), cycles per unit;
                        k and -k are the same peak */
    double limit;    /* largest |k| searched: 1 / (2 s), s the median
                        distance from a point to its nearest neighbour
                        (the Nyquist limit of the point spacing) */
    double min;      /* smallest |k| searched: 1 / L, L the larger side of
                        the points' (u, v) bounding box: at least one
                        cycle over the part */
    size_t n_points; /* points the spectrum was computed on */
} relief_measure_freq;

typedef struct relief_measures {
    size_t n_captured;  /* completed mesh's label-0 vertices */
    size_t n_completed; /* its label-1 vertices */

    relief_fit_primitive prim; /* the primitive the heights are taken from */
    int fitted;                /* 1: fitted here, `fit` is valid; 0: given */
    relief_fit_result fit;

    double msi_captured;     /* mean |h| over the captured part, input units */
    double msi_completed;    /* mean |h| over the completed part */
    double msi_diff_percent; /* see above; NaN when undefined */

    double hist_distance_displacement; /* total variation, [0, 1] */
    int has_colour;                    /* 1 when the completed mesh has colour */
    double hist_distance_rgb[3];       /* per channel, [0, 1]; NaN without colour */
    double hist_distance_colour;       /* their mean; NaN without colour */

    double seam;           /* mean |D(a) - D(b)| / |a' - b'| over captured-
                              completed edges (dimensionless) */
    double inside;         /* the same over captured-captured edges */
    double seam_ratio;     /* seam / inside; NaN when undefined */
    size_t n_seam_edges;   /* edges the seam mean is over */
    size_t n_inside_edges; /* edges the inside mean is over */

    relief_measure_freq freq_captured;  /* h over the captured part */
    relief_measure_freq freq_completed; /* h over the completed part */

    int has_truth;          /* 1 when a truth was given; the rest valid */
    size_t n_truth_missing; /* truth's label-1 vertices */
    double truth_rms;       /* RMS of h - h_truth over completed vertices
                               on the truth; NaN when none is */
    double truth_max_abs;   /* largest |h - h_truth| there */
    size_t n_truth_outside; /* completed vertices with no truth under them
                               (no containing triangle) */
    double truth_rms_outside; /* RMS over those against the nearest truth
                                 vertex's h; NaN when there are none */
    relief_measure_freq freq_truth; /* h over the truth's missing part */
} relief_measures;

/* Measure a completion.
 *
 * completed  the completed surface: positions, triangles (the seam needs
 *            them; a point cloud gets NaN seam figures), labels (required),
 *            colour (optional).
 * truth      the true whole surface in the same coordinates, with labels
 *            (1 = missing from the capture), or NULL.
 * prim       the primitive to measure heights from, or NULL to fit one to
 *            the captured part (RELIEF_FIT_AUTO).
 * out        receives the measures; written only on success.
 *
 * Errors: RELIEF_E_USAGE for NULL completed or out; RELIEF_E_MESH for an
 * invalid mesh (relief_mesh_validate), a mesh without labels ("has no label
 * property"), a label other than 0 or 1 (naming the vertex), an empty
 * captured or completed part, a truth with no label-1 vertex, or a failed
 * fit; RELIEF_E_RANGE for more vertices than FLANN indexes (INT_MAX);
 * RELIEF_E_NOMEM. */
relief_status relief_measure(const relief_mesh *completed, const relief_mesh *truth,
                             const relief_fit_primitive *prim, relief_measures *out,
                             relief_error *err);

/* Dominant spatial frequency of the field f over n points uv (n x 2,
 * input units): the peak of the power spectrum
 *     P(k) = |sum_i (f_i - mean f) exp(-2 pi i k.x_i)|^2
 * by a direct DFT over the scattered points (at most
 * RELIEF_MEASURE_FREQ_MAX_POINTS of them, see above), over wave vectors
 * with out->min <= |k| <= out->limit. A coarse grid of step
 * max(1 / (2 L), limit / RELIEF_MEASURE_FREQ_GRID) (half the width of a
 * spectral peak over a part of extent L) over the half plane k_v >= 0
 * finds the peak; a pattern search (8 neighbours, the step halved when
 * none is higher, down to 1e-4 of the coarse step) then refines it, so the
 * result is the continuous spectrum's local maximum, not a grid value.
 * Errors: RELIEF_E_NOMEM, RELIEF_E_RANGE (n > INT_MAX), RELIEF_E_INTERNAL
 * (FLANN failure). Fewer than 4 points, a constant field or too few
 * points for one cycle (min > limit) is not an error: out->freq is NaN. */
relief_status relief_dominant_frequency(const double *uv, const double *f, size_t n,
                                        relief_measure_freq *out, relief_error *err);

/* Write the measures into the current JSON object. Keys (the CLI
 * contract): msi_captured, msi_completed, msi_diff_percent, seam_ratio,
 * hist_distance_displacement, hist_distance_colour (only with colour),
 * and with a truth truth_rms, freq_truth, freq_completed. Also: n_captured,
 * n_completed, primitive {model, parameters as relief_report_fit_fields
 * names them, source}, fit {relief_report_fit_fields} when fitted here,
 * hist_bins, colour (bool), hist_distance_rgb [3], seam, inside,
 * seam_edges, inside_edges, freq_captured, freq_completed (always),
 * spectrum {captured, completed[, truth]: {freq, k, min, limit, points}},
 * and with a truth n_truth_missing, truth_max_abs, truth_outside,
 * truth_rms_outside.
 * Undefined values (NaN) are written as null. */
void relief_report_measures_fields(relief_json *j, const relief_measures *m);

/* ------------------------------------------ helpers shared with pattern.c */
/* relief_measure's own steps, exposed so the other measures of a
 * completion (pattern.h) read labels, fit and parameterise exactly as it
 * does. */

/* Check that m has labels and that each is 0 or 1; count them into *n0
 * (captured) and *n1 (completed). `what` names the mesh in the message
 * ("completed", "truth"). Errors: RELIEF_E_MESH, naming the vertex. */
relief_status relief_measure_check_labels(const relief_mesh *m, const char *what, size_t *n0,
                                          size_t *n1, relief_error *err);

/* What both relief_measure and relief_pattern_measure require of their
 * inputs: a valid completed mesh with labels 0 and 1, both present (counts
 * into *n_captured, *n_completed), and a truth, when tm is not NULL, that
 * is valid, labelled and has a label-1 part (its count into
 * *n_truth_missing, 0 without a truth; the pointer may be NULL). Errors:
 * RELIEF_E_MESH naming the mesh and, for a bad label, the vertex. */
relief_status relief_measure_check_parts(const relief_mesh *cm, const relief_mesh *tm,
                                         size_t *n_captured, size_t *n_completed,
                                         size_t *n_truth_missing, relief_error *err);

/* The primitive relief_measure fits when given none: RELIEF_FIT_AUTO on
 * relief_mesh_subset of m's label-0 vertices. m must have labels. Errors:
 * those of relief_fit_mesh, the message prefixed with what was fitted. */
relief_status relief_measure_fit_captured(const relief_mesh *m, relief_fit_result *fit,
                                          relief_error *err);

/* (u, v) (param.h, input units) of m's vertices labelled `want` (all when
 * want < 0), in vertex order, written to uv (count x 2, room for m->nv x 2
 * is enough); on a cylinder or sphere u is taken relative to the points'
 * circular mean direction, in (-pi r, pi r], so a part that straddles the
 * parameterisation's cut stays contiguous. Returns the count. */
size_t relief_measure_part_uv(const relief_domain *pm, const relief_mesh *m, int want,
                              double *uv);

#endif
