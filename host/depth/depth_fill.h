/* Depth-image repair (paper 003): the missing pixels of a depth or range
 * image filled by constrained texture synthesis (image/pixel_synth.h, on
 * the image filler's engine and scorer), in one of three variants:
 *  - plain (3.1): synthesis on the depth values themselves;
 *  - haar (3.2): the 2 x 2 Haar transform to `levels`; the coarsest LL by
 *    the membrane (harmonic interpolation), the LH, HL and HH bands of
 *    every level synthesised together (one 3-channel image per level),
 *    then the inverse transform;
 *  - decompose (3.3): f = u + v by ROF; u by the membrane, v synthesised;
 *    recomposed.
 * Known pixels keep their bits in every variant. Measures against a truth
 * image (RMS over the filled pixels, the slope jump at the hole's rim) are
 * here too, for the command and the bench. */
#ifndef RELIEF_HOST_DEPTH_DEPTH_FILL_H
#define RELIEF_HOST_DEPTH_DEPTH_FILL_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"
#include "base/progress.h"
#include "image/patch.h"
#include "image/pixel_synth.h"
#include "depth/layers.h"

typedef struct relief_depth_repair_params {
    relief_depth_variant variant; /* decompose */
    relief_pixsyn_params synth;   /* the synthesis (window 9, search radius 32, ...) */
    int levels;                   /* haar: transform steps, 1..6; 2 */
    double lambda;                /* decompose: ROF's lambda in the values' units x pixels;
                                     <= 0: automatic, from the capture's roughness (the
                                     median of the non-zero |second differences| along
                                     rows and columns, x 6.98: on white noise of
                                     deviation s, 8 sqrt(2) s) */
    int rof_iterations;           /* decompose: Chambolle iterations; 200 */
    int membrane_iterations;      /* conjugate-gradient iterations at most; 5000 */
    int thin_plate;               /* 1: the smooth fills by the thin plate
                                     (relief_membrane_fill_biharmonic), and decompose
                                     takes ROF of the image bridged by it (u smooth across
                                     the rim); 0 (default for images): harmonic, ROF of
                                     the known pixels. Measured on the bench: the thin
                                     plate halves the motorcycle's rim jumps but
                                     overshoots at depth edges (its disc's RMS 0.79 ->
                                     3.17); meshes default to it (mesh_fill.h) */
    int seam;                     /* 1 (default) blends each hole's rim
                                     in the gradient domain (relief_depth_seam); 0: the
                                     synthesis's copies as they are (paper 003). Not with
                                     synth.tileable (the blend does not wrap) */
    int layered;                  /* 1: a hole across a depth step is filled layer by
                                     layer (layers.h), each from its own rim; 0
                                     (default here; relief_depth_fill's images set it):
                                     every hole from its whole rim (paper 003). Not with
                                     targets (a mesh's z-buffers) nor synth.tileable */
    relief_layer_params layer;    /* the layers' parameters (layers.h) */
    relief_progress *progress;    /* NULL (default): none. The repair reports within
                                     the progress's current stage (the smooth parts
                                     first, then the synthesis, pixel by pixel) and
                                     stops at a cancel: RELIEF_E_CANCELLED, z partly
                                     repaired. synth.progress is its own to set */
} relief_depth_repair_params;

relief_depth_repair_params relief_depth_repair_params_default(void);

typedef struct relief_depth_repair_report {
    size_t missing;              /* pixels missing */
    size_t filled;               /* of them, inside the capture: filled */
    size_t outside;              /* of them, outside: left missing */
    size_t by_synthesis;         /* synthesised (plain: the depths; decompose: v; haar: the
                                    detail coefficients of every level) */
    size_t by_fallback;          /* the synthesis's fallbacks, same units */
    size_t unreached;            /* targets the synthesis could not reach, same units */
    size_t by_membrane;          /* haar: LL coefficients; decompose: u pixels */
    int membrane_iterations;     /* the most any smooth solve took (membrane, thin plate,
                                    the seam's Poisson correction) */
    size_t seam_edges;           /* rim edges the seam blend guided (0: no blend) */
    double lambda;               /* decompose: the lambda used */
    relief_pixsyn_order kept;    /* the order kept (plain, decompose; haar: level 1's) */
    double energy[2];            /* its energies, as relief_pixsyn_report */
    size_t candidates;           /* windows scored */
    int levels;                  /* haar: levels used */
    size_t stepped_holes;        /* layered: holes across a depth step */
    size_t front_pixels;         /* layered: their pixels given a front layer */
    int layer_passes;            /* layered: repairs run, one per rank (1: none stepped) */
    double layer_noise;          /* layered: the frame's noise unit (layers.h) */
    size_t layer_decomposed;     /* layered haar: front pixels filled by decompose, their
                                    layer too thin for the coarsest Haar block */
    double seconds_transform;    /* Haar / ROF / membrane */
    double seconds_synthesis;    /* texture synthesis, every band */
    double seconds_score;        /* of which scoring windows */
} relief_depth_repair_report;

/* Validate `p` for a width x height image: RELIEF_E_RANGE naming the
 * parameter. */
relief_status relief_depth_repair_params_validate(const relief_depth_repair_params *p, int width,
                                                int height, relief_error *err);

/* Bytes relief_depth_repair needs for a width x height image (for the
 * memory check before the work starts). */
uint64_t relief_depth_repair_estimate(int width, int height);

/* The missing pixels inside the capture: those with a known pixel on
 * both sides along their row, or along their column. A depth camera's
 * invalid margin (office1.pcd: every border pixel) is outside: filling it
 * would be extrapolation, not repair. inside[i] = 1 for them; returns
 * their number. */
size_t relief_depth_inside(const uint8_t *missing, int width, int height, uint8_t *inside);

/* Fill z (width x height, row-major) where missing[i] != 0 and the pixel
 * is inside the capture (relief_depth_inside; with p->synth.tileable,
 * every missing pixel: the image is a torus), in place; the missing
 * pixels outside stay as they are (NaN).
 * `source` (may be NULL; width x height): for each filled pixel the pixel
 * its texture came from (plain, decompose: the synthesis's copy; haar: the
 * finest level's, mapped to full resolution), -1 where none (a fallback,
 * or a known pixel). RELIEF_E_RANGE when every pixel is missing, or when
 * every missing pixel is outside the capture (a hole touching every
 * border and nothing else). */
relief_status relief_depth_repair(float *z, const uint8_t *missing, int width, int height,
                                const relief_depth_repair_params *p, relief_patch_scorer *scorer,
                                int64_t *source, relief_depth_repair_report *rep,
                                relief_error *err);

/* The same with the pixels to fill given: those where missing and
 * target are both non-zero (a mesh's z-buffer: its holes, not the empty
 * background); target NULL: the inside rule above. */
relief_status relief_depth_repair_targets(float *z, const uint8_t *missing, const uint8_t *target,
                                        int width, int height,
                                        const relief_depth_repair_params *p,
                                        relief_patch_scorer *scorer, int64_t *source,
                                        relief_depth_repair_report *rep, relief_error *err);

/* The seam: a hole's rim blended in the gradient domain. The synthesis
 * copies texels next to the capture with no regard to the capture's slope
 * there, so z steps at the rim. Across each rim edge (p filled, q its
 * captured 4-neighbour, r the captured pixel beyond q, s the captured
 * pixel p's texture came from, d = q - p) two predictions of the step
 * z(q) - z(p) are taken:
 *  - the capture's own next step, z(r) - z(q) (its slope continued);
 *  - the smooth part's next step, u(r) - u(q), plus the copied texel's
 *    step in its source, v(s + d) - v(s) (the texture continued).
 * Each is weighted by the inverse square of its error in predicting the
 * next captured step z(r) - z(q) one pixel further out (from z(r + d) -
 * z(r), and from u(r + d) - u(r) + v(s + 2d) - v(s + d)); an exact one
 * wins outright, and without r + d or s + 2d the two count equally. Without
 * r the second alone, with u(q) - u(p) for the smooth part's step. Edges
 * whose source neighbour s + d is not captured, and pixels with no source
 * (fallbacks), keep the fill's own step, as do the edges inside the hole.
 * The least-squares fit of those steps with the captured pixels fixed is a
 * Poisson equation for a correction (relief_poisson_fill over the
 * captured and filled pixels: other missing pixels are no neighbours),
 * added to v over the filled pixels: the texture keeps its detail, the rim
 * loses its step. z = u + v; u may be NULL (0: plain and haar, v the
 * depths). `filled`: the pixels to correct; `known`: the captured ones;
 * `source`: the copies' source pixels (-1: none). *edges (may be NULL)
 * gets the rim edges guided, *iterations (may be NULL) the solve's. */
relief_status relief_depth_seam(const float *u, float *v, const uint8_t *known,
                                const uint8_t *filled, const int64_t *source, int width,
                                int height, int max_iter, size_t *edges, int *iterations,
                                relief_error *err);

/* Measures of a fill against the truth, over the pixels that were missing
 * (mask `missing`; those still NaN are left out); all in the values'
 * units. */
typedef struct relief_depth_measures {
    size_t compared;     /* filled pixels whose truth is finite */
    double rms;          /* RMS of filled - truth over them; NaN when none */
    size_t rim_pairs;    /* (filled p, known q, known q') in a row or column: the rim */
    double rim_jump;     /* mean |(z(p) - z(q)) - (z(q) - z(q'))| over them: the slope
                            step from the capture into the fill */
    double capture_jump; /* the same second difference over known triples: the
                            capture's own roughness */
    double truth_jump;   /* rim_jump with the truth at p (NaN without a truth) */
} relief_depth_measures;

/* `truth` may be NULL (then compared 0, rms and truth_jump NaN); with a
 * truth, only the filled pixels it knows count (the holes cut from a
 * capture, not the capture's own). NaN values of z are left out. */
void relief_depth_measure(const float *z, const float *truth, const uint8_t *missing,
                          int width, int height, relief_depth_measures *m);

#endif
