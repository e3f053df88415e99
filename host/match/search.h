/* The k-coherence search (issue 18; Ashikhmin 2001, Tong et al. 2002):
 * a sub-quadratic candidate set for one target, scored by the matchers
 * exactly as the exhaustive search scores every sample.
 *
 * The exhaustive search scores every (sample, rotation) for every target:
 * samples x targets x R x window, the square of the surface. The
 * k-coherence search scores only the samples that continue a neighbour's
 * patch: for each textured neighbour v of target t in its window, with
 * source (s, r) (the candidate v copied; a sample is its own source at
 * rotation 0), and for each of (s, r)'s k most similar (sample, rotation)
 * pairs (s', r'), the sample at t's place relative to v, seen from s' at
 * rotation r' (as grow.c's coherent candidates are found). Each such
 * sample's R rotations are then scored by the backend's rm_score_candidate:
 * the best-set rule, the draw and the acceptance test are the exhaustive
 * search's, only the candidate set is smaller (a few hundred samples
 * against tens of thousands).
 *
 * Similar pairs are precomputed once per surface, over a fixed-length
 * descriptor of each (sample, rotation): the surface read at the centre and
 * on RELIEF_SEARCH_RINGS rings of RELIEF_SEARCH_ANGLES points, at radii
 * j / RINGS x W x spacing in the sample's frame turned by 2 pi r / R, as a
 * target's neighbours are mapped onto it. Each point gives the height of
 * its closest vertex along the sample's normal over B_shape, times
 * sqrt(mu g) (g the window's Gaussian at that radius), and with colour its
 * Rec. 709 luminance times sqrt((1 - mu) g): so that squared descriptor
 * distances weigh shape and colour as the SSD does. The descriptors are
 * reduced to their RELIEF_SEARCH_DIMS principal components (over at most
 * 65 536 of them, evenly strided) and indexed by FLANN's exact kd-tree
 * (base/knn.h), so the pairs are deterministic. Only (s, 0) is looked up:
 * its k neighbours are its nearest pairs (s', r') whose sample lies farther
 * than W x spacing from s (a sample's next-door samples are found anyway by
 * the continuation of t's other neighbours), and (s, r)'s are (s', r' + r),
 * since rotations about the normal compose.
 *
 * Memory: ns x R x RELIEF_SEARCH_DIMS floats and FLANN's tree while it is
 * built, ns x k uint32 kept, and one stamp per sample (relief_search_bytes). */
#ifndef RELIEF_HOST_SEARCH_H
#define RELIEF_HOST_SEARCH_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"
#include "match/match_data.h"
#include "smooth/surface.h"

#define RELIEF_SEARCH_RINGS 3
#define RELIEF_SEARCH_ANGLES 8
#define RELIEF_SEARCH_DIMS 8
#define RELIEF_SEARCH_K_MAX 64

typedef struct relief_search relief_search;

/* Bytes relief_search_create allocates for ns samples, R rotations and k
 * (an estimate within FLANN's tree overhead). */
size_t relief_search_bytes(size_t ns, int rotations, int k);

/* Precompute the k most similar pairs of every sample of d at rotation 0
 * (k 1..RELIEF_SEARCH_K_MAX), reading the surface within `window` hops of
 * spacing s->spacing. d's samples and their colours must be final (the
 * growth never changes them). The descriptors are worked out on `threads`
 * host threads (0: the default, relief_pool_threads_for), the same bytes
 * for any count. */
relief_status relief_search_create(const relief_surface *s, const relief_match_data *d,
                                   int window, int k, int threads, relief_search **out,
                                   relief_error *err);

/* The vertex that continues the patch of sample si at rotation r by the
 * offset o (in the frame of the vertex that copied it): the closest vertex
 * to s' + R_s Rz(2 pi r / R) o. Samples are vertices 0..ns-1. */
uint32_t relief_continue_patch(const relief_match_data *d, const float o[3], uint32_t si,
                               uint32_t r);

/* Candidate centres for target t, whose window holds the n textured
 * vertices nbr[0..n-1] (the query's order); src[v] is the candidate
 * (sample x R + rotation) target v copied, UINT32_MAX while untextured;
 * vertices below s->n_samples are samples and their own source. Writes
 * distinct sample indices to the search's own array, in a deterministic
 * order (every neighbour's own continuation, neighbours in order; then the
 * continuations of its source's similar pairs, likewise), sets
 * *out to it (valid until the next call) and returns their count (0:
 * nothing continues there; score every sample). */
uint32_t relief_search_candidates(relief_search *S, const relief_surface *s,
                                  const relief_match_data *d, const uint32_t *nbr, uint32_t n,
                                  const uint32_t *src, uint32_t t, const uint32_t **out);

/* Wall time the precomputation took, seconds. */
double relief_search_build_seconds(const relief_search *S);

void relief_search_destroy(relief_search *S);

#endif
