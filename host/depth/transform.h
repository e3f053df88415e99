/* The transforms of depth-image repair (paper 003, sections 3.2 and 3.3)
 * on width x height float images, row-major, top row first, with a known
 * mask (1 known, 0 missing) where it matters:
 *  - the membrane: missing pixels by harmonic interpolation of the known
 *    ones (the smooth fill of LL and of the structure u);
 *  - one step of the 2 x 2 Haar transform and its inverse;
 *  - the ROF structure + texture decomposition f = u + v (Chambolle's
 *    projection), on the known pixels only.
 * Values are in the image's own units (metres, disparities). */
#ifndef RELIEF_HOST_DEPTH_TRANSFORM_H
#define RELIEF_HOST_DEPTH_TRANSFORM_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"

/* Fill the pixels where known == 0 with the discrete harmonic function
 * (the 4-neighbour Laplacian zero there) that takes the known values at
 * the known pixels; the image's border is free (Neumann). Solved by
 * conjugate gradients to a relative residual of 1e-8 or `max_iter`
 * iterations; *iterations (may be NULL) gets the number used. Known
 * pixels keep their bits. RELIEF_E_RANGE when no pixel is known. */
relief_status relief_membrane_fill(float *z, const uint8_t *known, int width, int height,
                                   int max_iter, int *iterations, relief_error *err);

/* The same with a source term and a domain: the pixels of the domain
 * where known == 0 solve -L z = source there (source: width x height;
 * NULL: 0, the membrane), L the 4-neighbour Laplacian over the domain's
 * pixels (domain: width x height, non-zero inside; NULL: the whole image;
 * a pixel off it is no neighbour, as one off the image), the known pixels
 * the Dirichlet values. source[p] is the net flux a guidance field sends
 * out of p: for a guidance g (g_pq the wanted z_q - z_p), -sum_q g_pq over
 * p's neighbours, the Poisson equation of gradient-domain editing. Pixels
 * off the domain keep their values. */
relief_status relief_poisson_fill(float *z, const uint8_t *known, const uint8_t *domain,
                                  const float *source, int width, int height, int max_iter,
                                  int *iterations, relief_error *err);

/* The same with the thin plate: the pixels of the domain (NULL: the
 * image) where known == 0 minimise the sum over the domain's pixels of
 * (L z)^2, L the 4-neighbour Laplacian over the domain (free border), so
 * the fill carries the surroundings' slope and curvature into the hole
 * instead of meeting the rim with a kink (the discrete biharmonic).
 * Started from the harmonic fill, then conjugate gradients on the normal
 * equations to a relative residual of 1e-8 or `max_iter` iterations
 * (*iterations: the biharmonic ones). Known pixels and pixels off the
 * domain keep their bits. RELIEF_E_RANGE when no pixel of the domain is
 * known. */
relief_status relief_membrane_fill_biharmonic(float *z, const uint8_t *known,
                                              const uint8_t *domain, int width, int height,
                                              int max_iter, int *iterations, relief_error *err);

/* One Haar step of an image whose sides are even: the 2 x 2 block at
 * (2x, 2y) with a = (2x, 2y), b = (2x + 1, 2y), c = (2x, 2y + 1),
 * d = (2x + 1, 2y + 1) gives, at (x, y) of the half-size bands,
 *   ll = (a + b + c + d) / 4,  lh = (a - b + c - d) / 4,
 *   hl = (a + b - c - d) / 4,  hh = (a - b - c + d) / 4;
 * `detail` holds (lh, hl, hh) per pixel (3 channels). Computed in double:
 * the inverse gives the values back exactly when they lie on a common grid
 * (integer millimetres, 16-bit PNG depths), within a float's rounding
 * otherwise (test_depth_fill). */
void relief_haar_forward(const float *z, int width, int height, float *ll, float *detail);

/* The inverse: z (width x height, even sides) from ll and detail. */
void relief_haar_inverse(const float *ll, const float *detail, int width, int height, float *z);

/* ROF: u minimising TV(u) + 1/(2 lambda) sum (u - f)^2 over the known
 * pixels, the total variation taken over pairs of 4-neighbours both known
 * (a hole is a free boundary, not a jump), by Chambolle's projection
 * (`iterations` steps of 1/4: above the 1/8 his proof covers, the step he
 * reports converging in practice, and it did on every test image here);
 * v = f - u. Missing pixels get u = v = 0.
 * lambda is in the values' units times pixels: a bump of height h and
 * radius r moves to v when lambda >= h r / 2. Its passes run on `threads`
 * host threads (1: this one), each over its own rows: the same bits
 * whatever the count. RELIEF_E_NOMEM. */
relief_status relief_rof(const float *f, const uint8_t *known, int width, int height,
                         double lambda, int iterations, int threads, float *u, float *v,
                         relief_error *err);

#endif
