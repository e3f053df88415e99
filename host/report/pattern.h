/* Pattern measures of a completion (issue 17): does the completed part's
 * relief run the same way, at the same scales, as the captured part's?
 * MSI, the histograms, the seam and the dominant frequency (measures.h)
 * cannot see orientation: ridges along a cylinder's axis on the captured
 * side and ridges around it on the completed side pass them all. These
 * compare the parts' power spectra, binned by orientation and scale, and
 * their structure-tensor orientation histograms (1, 2), and the layout of
 * the ridges' lean (3).
 *
 * What the histograms do not see: arrangement. They are blind to phase
 * and position, so a completion made of the capture's own pieces,
 * leaning as the capture's ridges lean but laid out differently, passes
 * them. The demo (cylinder-bark --colour --seed 1, 2054-vertex truth,
 * `relief complete` defaults) grew chevrons on the back while the
 * cylinder's target lattice ran its rows around the turn (before
 * 884af49; 0.026 since), V's and diamonds of ridges leaning 15 to 30
 * degrees either way; but the
 * capture's meandering ridges lean as far (its orientation histogram has
 * 0.19 of its power at 30 degrees), and the completion's distances to it,
 * 0.24 spectrum, 0.09 orientation, 0.13 tensor, are under the truth's own
 * floor, 0.38, 0.25, 0.26 (the truth's back is straighter than its
 * front). What differs is that neighbouring ridges lean opposite ways
 * (mirrored) instead of together: the lean changes across the ridges,
 * where the capture's changes along them as its ridges sway. The layout
 * measure (3) sees that: lean distance 0.170 against the truth's 0.018.
 *
 * What the layout measure does not see. It is one second-order figure of
 * the lean at one lag, so:
 * - it is only as sharp as the truth's own parts agree: on seeds 1 to 4
 *   of the demo the completion's lean distance is 0.170, 0.067, 0.111,
 *   0.217 against floors 0.018, 0.057, 0.012, 0.002; seed 2's truth has
 *   crossing, X-shaped ridges of its own on the back (share 0.33 against
 *   its front's 0.28), and there the chevrons (0.34 against 0.27) are not
 *   told from it. Seeds 7 and 8 (0.144, 0.188 against 0.113, 0.094) are
 *   told apart by less than seeds 1, 3 and 4;
 * - ridges that zigzag in phase (every ridge kinked the same way, as the
 *   demo grows on seeds 5 and 6) are a consistent layout and pass, as
 *   they should; their kinks, sharper than the capture's sway, are not
 *   measured;
 * - without a dominant orientation (noise, pebbles) the lean is the
 *   noise's and the share about 1/2 in every part: equal, and meaningless;
 * - it is a mean over the part: one fold in a wide part weighs only as
 *   much as the nodes within a spacing of it.
 *
 * Fields. Over each part (the completed mesh's label 0, captured, and
 * label 1, completed; a truth's label 0 and label 1, missing) two scalar
 * fields of the primitive's parameter domain (u, v) (param.h; taken as
 * relief_measure_part_uv does, so a part across a cylinder's cut stays
 * whole; on a sphere the equal-area map stretches features near the
 * poles): the height h = relief_fit_distance (input units), and, when the
 * mesh has colour, the luminance Y = 0.2126 R + 0.7152 G + 0.0722 B of its
 * stored [0, 1] RGB (Rec. 709 weights, no linearisation).
 *
 * Why a grid. Each part is resampled onto a regular grid in (u, v), one
 * step g for every part of a measure, and both measures run on the grids:
 * - the parts differ in density (a completion's capture is oversampled to
 *   half the spacing of its targets): a sum over vertices would weight
 *   them differently and per-vertex gradients would be taken at different
 *   scales; on a common grid both see the same scales;
 * - the parts differ in shape (a square minus a disc, and the disc): a
 *   direct DFT over scattered points (as relief_dominant_frequency does,
 *   fine for a peak's position) puts the outline's own spectrum, strong
 *   along the axes of a square's sides, into the orientation bins. On a
 *   grid the field is easily tapered to 0 at the part's outline first.
 * The grid:
 * - step g = the largest of the two parts' point spacings (the median
 *   distance from a point to its nearest neighbour, estimated on at most
 *   RELIEF_MEASURE_FREQ_MAX_POINTS points drawn by MT19937 seed 1), and
 *   at least the longer side of either part's (u, v) bounding box over
 *   RELIEF_PATTERN_GRID_MAX, which bounds the cost on a large mesh (there
 *   frequencies above RELIEF_PATTERN_GRID_MAX / (2 L) are not seen);
 * - nodes at multiples of g over each part's bounding box, centred on it;
 *   a node is inside the part when a point of it lies within
 *   RELIEF_PATTERN_REACH g;
 * - an inside node's value is the weighted least-squares plane through its
 *   RELIEF_PATTERN_KNN nearest points, weights (1 - (d / r)^2)^2 for
 *   d < r, r = max(RELIEF_PATTERN_FIT_RADIUS g, 1.25 d6), d6 the distance
 *   to the 6th nearest (the weighted mean when those points are collinear).
 *
 * 1. Binned power spectrum. On a part's grid, the field's taper-weighted
 *    mean is subtracted and it is multiplied by the taper
 *    w = (1 - cos(pi min(d, T) / T)) / 2, d the distance in nodes from the
 *    node to the nearest node outside the part (or off the grid),
 *    T = RELIEF_PATTERN_TAPER. Its power |F(k)|^2, F the DFT at the node
 *    positions, is evaluated on the half plane of wave vectors
 *    k = (k_u, k_v), k_v >= 0 (P(-k) = P(k)), in steps of
 *    k_max / RELIEF_PATTERN_KGRID, and every k with
 *    k_min <= |k| <= k_max is binned:
 *    - orientation: the angle of k from the u axis toward v, in [0, pi)
 *      (k and -k are one wave), RELIEF_PATTERN_ORIENT_BINS bins, bin b
 *      centred on b pi / ORIENT_BINS (bin 0: k along u, i.e. ridges
 *      along v: a cylinder's ridges along its axis), each k shared
 *      linearly between the two nearest centres, circularly;
 *    - scale: RELIEF_PATTERN_RADIAL_BINS bins equal in log |k| between
 *      k_min and k_max, shared linearly between the two nearest centres
 *      (clamped at the ends);
 *    where k_max = 1 / (2 g), the grid's Nyquist limit, and k_min = 1 / L,
 *    L the shortest side of the two parts' bounding boxes (one cycle
 *    across the narrower part); units cycles per input unit. The
 *    ORIENT x RADIAL histogram is normalised to sum 1 (the fraction of the
 *    part's variance at each orientation and scale); its orientation and
 *    scale marginals are its sums over the other index.
 * 2. Structure-tensor orientation histogram. At each grid node whose 4
 *    neighbours are inside the part, the gradient (central differences)
 *    and its tensor J = grad grad^T; J smoothed by a Gaussian of
 *    RELIEF_PATTERN_TENSOR_SIGMA nodes (cut at 3 sigma), over the
 *    nodes that have a gradient; at each such node the orientation of J's
 *    major eigenvector (the dominant gradient, the same angle convention
 *    as k above: 0 is ridges along v) and the coherence
 *    c = (l1 - l2) / (l1 + l2) in [0, 1]; the histogram of the
 *    orientations over RELIEF_PATTERN_ORIENT_BINS bins (centred and shared
 *    as above), each weighted by its c, normalised to sum 1. Nodes where
 *    l1 + l2 = 0 are left out.
 * 3. Layout of the lean. On the tensor nodes of 2:
 *    - the dominant orientation theta0, half the angle of
 *      sum c (cos 2 theta, sin 2 theta) (degrees in [0, 180) in the
 *      struct and the JSON, `dominant`); e_a = (cos theta0, sin theta0),
 *      across the ridges (the dominant gradient), e_l = (-sin theta0,
 *      cos theta0), along them;
 *    - the signed lean phi = theta - theta0, wrapped into (-90, 90]
 *      degrees, and the field L = c sin 2 phi: the lean weighted by the
 *      coherence (2 c phi for small leans); L is linear in the tensor's
 *      c (cos 2 theta, sin 2 theta), so it is interpolated between nodes
 *      (bilinearly) without a wrap, and incoherent nodes count little;
 *    - the ridge spacing s = 1 / the power-weighted mean |k| of the
 *      part's spectrum over [k_min, k_max] (1), input units;
 *    - gamma_a, gamma_l: the mean of (L(x + s e) - L(x))^2 over the
 *      tensor nodes x whose partner x + s e, for e = e_a or e_l, lies
 *      between four tensor nodes: how much the lean changes over one
 *      spacing across the ridges, and along them;
 *    - lean_across = gamma_a / (gamma_a + gamma_l + 2 sin^2(2 F)),
 *      F = RELIEF_PATTERN_LEAN_FLOOR degrees, in [0, 1): near 0 when the
 *      lean changes only along the ridges (ridges swaying in phase, a
 *      meander, a zigzag; straight ridges), near 1 when only across them
 *      (bands of ridges leaning opposite ways side by side: chevrons,
 *      herringbone, mirrored copies), about 1/2 for a layout without a
 *      direction. The F term keeps straight ridges, whose lean is
 *      resampling noise of a fraction of a degree, near 0 instead of at
 *      a noisy 1/2; it moves the demo's shares by at most 0.02;
 *    - lean_rms = sqrt(sum c phi^2 / sum c), degrees.
 *    Chosen by measurement (cylinder-bark --colour, seeds 1 to 8,
 *    `relief complete` defaults, against the truth's own parts): the
 *    coherence-weighted autocorrelations of L and of phi across and along
 *    at lags of 0.5 to 3 spacings, this share at those lags, the share of
 *    L's power under about 2.7 spacings and the curl of the wave-vector
 *    field (whether the ridges' phase is continuous) all lost seed 2 and
 *    most lost seed 4 too; a tensor smoothing of 3 nodes told seed 2 by
 *    0.04 against 0.02 but flagged seed 5's in-phase zigzags (0.11
 *    against 0.07), and 4 or 5 nodes lost seed 2 again.
 * Distance between two parts: the total variation 0.5 sum_b |p_b - q_b|
 * of their histograms, in [0, 1] (0 the same, 1 disjoint): of the joint
 * spectra (spectrum), of the orientation marginals (orientation), of the
 * scale marginals (radial) and of the tensor histograms (tensor); and
 * |lean_across(a) - lean_across(b)| (lean), in [0, 1).
 *
 * Truth. With a truth mesh (label 1 = the part the capture misses), the
 * same distances between the truth's own label-0 and label-1 parts, with
 * the completion's g, k_min and k_max (so on the same bins): the floor
 * no completion, which can only copy its capture, can be expected to
 * beat, since the truth's own parts differ that much. A truth part whose
 * grid would exceed RELIEF_PATTERN_GRID_MAX nodes along a side takes the
 * step that fits instead (its spectrum then has nothing above its own
 * Nyquist limit).
 *
 * Undefined (NaN, JSON null): every figure of a part with fewer than
 * RELIEF_PATTERN_MIN_POINTS points or fewer than RELIEF_PATTERN_MIN_NODES
 * inside nodes, or whose field is constant (RMS about its mean at most
 * RELIEF_PATTERN_FLAT times its scale: the part's longer box side for h,
 * 1 for Y); the spectrum when the narrower part's box is under
 * RELIEF_PATTERN_MIN_SIDE steps across (k_max / k_min < MIN_SIDE / 2);
 * the tensor histogram, theta0 and lean_rms when no node has a nonzero
 * tensor (or the orientations cancel exactly); the spacing without a
 * spectrum; lean_across without a spacing or with fewer than
 * RELIEF_PATTERN_MIN_NODES pairs across or along; a distance when either
 * of its histograms (shares) is.
 *
 * Deterministic (no global state, the only random draw MT19937 seed 1).
 * Cost: about n log n for a part of n points (a kd-tree) plus a bounded
 * amount per grid node (at most (GRID_MAX + 1)^2 nodes): the 701 459-vertex
 * cylinder-bark truth measured as a completion took 0.9 s, 1.4 s with
 * itself as the truth (4 parts), on one core. The layout adds two
 * bilinear look-ups per tensor node and direction.
 */
#ifndef RELIEF_HOST_PATTERN_H
#define RELIEF_HOST_PATTERN_H

#include <stddef.h>

#include "relief/relief.h"
#include "base/json.h"
#include "smooth/fit.h"

/* Orientation bins over [0, pi), 15 degrees each. */
#define RELIEF_PATTERN_ORIENT_BINS 12
/* Scale bins, equal in log |k|, between k_min and k_max. */
#define RELIEF_PATTERN_RADIAL_BINS 8
/* Most grid nodes along the longer side of a part's bounding box. */
#define RELIEF_PATTERN_GRID_MAX 256
/* Fewest points, and fewest inside grid nodes, a part is measured on. */
#define RELIEF_PATTERN_MIN_POINTS 16
#define RELIEF_PATTERN_MIN_NODES 64
/* Fewest grid steps across the narrower part's box for a spectrum. */
#define RELIEF_PATTERN_MIN_SIDE 8
/* A node is inside a part when a point lies within this many steps g. */
#define RELIEF_PATTERN_REACH 1.0
/* Nearest points a node's local plane is fitted to, and the radius of its
 * weights in steps g (widened to 1.25 times the 6th point's distance). */
#define RELIEF_PATTERN_KNN 16
#define RELIEF_PATTERN_FIT_RADIUS 1.5
/* Width of the taper to 0 at a part's outline, in grid nodes. */
#define RELIEF_PATTERN_TAPER 4
/* Wave-vector grid steps from 0 to k_max along each axis. */
#define RELIEF_PATTERN_KGRID 96
/* Standard deviation of the structure tensor's smoothing, in grid nodes. */
#define RELIEF_PATTERN_TENSOR_SIGMA 2.0
/* Relative RMS at or below which a field counts as constant. */
#define RELIEF_PATTERN_FLAT 1e-12
/* Lean, in degrees, whose changes the lean-across share discounts (3):
 * straight ridges resampled onto the grid lean 0.1 to 0.4 degrees. */
#define RELIEF_PATTERN_LEAN_FLOOR 2.0

/* The histograms of one field over one part. */
typedef struct relief_pattern_part {
    size_t n_points;        /* the part's vertices */
    size_t n_nodes;         /* grid nodes inside it */
    size_t n_tensor_nodes;  /* nodes with a gradient and a nonzero tensor */
    double spectrum[RELIEF_PATTERN_ORIENT_BINS][RELIEF_PATTERN_RADIAL_BINS];
                            /* [orientation][scale], sums to 1; all NaN
                               when undefined */
    double orientation[RELIEF_PATTERN_ORIENT_BINS]; /* spectrum's marginal */
    double radial[RELIEF_PATTERN_RADIAL_BINS];      /* spectrum's marginal */
    double tensor[RELIEF_PATTERN_ORIENT_BINS]; /* coherence-weighted, sums
                                                  to 1; NaN when undefined */
    double coherence; /* mean c over the tensor nodes, [0, 1]: about 1 for
                         straight stripes, low for isotropic noise */
    double spacing;   /* ridge spacing, 1 / the spectrum's power-weighted
                         mean |k|, input units; NaN without a spectrum */
    double dominant;  /* dominant orientation theta0, degrees in [0, 180),
                         the angle convention of the histograms (3) */
    double lean_rms;  /* coherence-weighted RMS of the lean phi, degrees */
    double lean_across; /* share of the lean's change over one spacing
                           that runs across the ridges, [0, 1) (3) */
} relief_pattern_part;

/* Total variation distances between two parts' histograms, [0, 1]. */
typedef struct relief_pattern_distance {
    double spectrum;    /* joint orientation x scale spectra */
    double orientation; /* orientation marginals: sees a turned pattern */
    double radial;      /* scale marginals */
    double tensor;      /* structure-tensor orientation histograms */
    double lean;        /* |difference| of the lean-across shares, [0, 1):
                           sees ridges mirrored into chevrons (3) */
} relief_pattern_distance;

typedef struct relief_pattern {
    relief_fit_primitive prim; /* the primitive the heights are taken from */
    int fitted;                /* 1: fitted here (relief_measure_fit_captured) */
    double step;               /* grid step g, input units */
    double k_min, k_max;       /* the scale bins' range, cycles per unit;
                                  NaN when the spectrum is undefined */
    size_t n_captured, n_completed; /* the completed mesh's parts */

    relief_pattern_part height[2]; /* [0] captured, [1] completed */
    relief_pattern_distance d_height;
    int has_colour;                /* the completed mesh has colour */
    relief_pattern_part colour[2]; /* luminance; valid with has_colour */
    relief_pattern_distance d_colour;

    int has_truth;                        /* a truth was given */
    relief_pattern_part truth_height[2];  /* [0] truth's label 0, [1] label 1 */
    relief_pattern_distance d_truth_height; /* the floor for d_height */
    int has_truth_colour;                 /* truth given and coloured, and
                                             the completed mesh coloured */
    relief_pattern_part truth_colour[2];
    relief_pattern_distance d_truth_colour; /* the floor for d_colour */
} relief_pattern;

/* Measure the pattern of a completion (see above).
 *
 * completed  positions, labels (required; 0 captured, 1 completed; both
 *            present), colour (optional); triangles are not used, so a
 *            point cloud is fine.
 * prim       the primitive to take heights and (u, v) from (e.g.
 *            relief_measures.prim), or NULL to fit one to the captured
 *            part as relief_measure does.
 * truth      the true whole surface in the same coordinates, labelled
 *            (1 = missing from the capture), or NULL.
 * out        written only on success.
 *
 * Errors: RELIEF_E_USAGE for NULL completed or out; RELIEF_E_MESH for an
 * invalid mesh, missing labels or a label other than 0 or 1 (naming the
 * vertex), an empty captured or completed part, a truth with no label-1
 * vertex, or a failed fit; RELIEF_E_RANGE for a part of more than INT_MAX
 * points (FLANN's limit); RELIEF_E_NOMEM; RELIEF_E_INTERNAL when FLANN
 * fails. Too few points, a constant field and the like are not errors:
 * the figures are NaN (see above). */
relief_status relief_pattern_measure(const relief_mesh *completed,
                                     const relief_fit_primitive *prim,
                                     const relief_mesh *truth, relief_pattern *out,
                                     relief_error *err);

/* Write the pattern measures into the current JSON object. Keys:
 * pattern_spectrum_distance, pattern_orientation_distance,
 * pattern_radial_distance, pattern_tensor_distance, pattern_lean_distance;
 * with colour the same with the suffix _colour; with a truth the floors
 * with the suffix _truth (heights) and, when has_truth_colour,
 * _colour_truth. Then the parts' lean_across: pattern_lean_across_PART,
 * PART captured, completed and with a truth truth_captured,
 * truth_missing; with colour the same with the suffix _colour. Then
 * "pattern": {step, k_min, k_max, orientation_bins, radial_bins, and for
 * height (and colour) {captured, completed[, truth_captured,
 * truth_missing]}: each {points, nodes, tensor_nodes, coherence, spacing,
 * dominant_orientation, lean_rms, lean_across, orientation [ORIENT_BINS],
 * radial [RADIAL_BINS], tensor [ORIENT_BINS]}}. NaN is written as null. */
void relief_pattern_json_fields(relief_json *j, const relief_pattern *p);

#endif
