/* Oversampling of the captured surface (000 section 4; DESIGN step 4).
 *
 * Each pass replaces every triangle by 4 (1-to-4 subdivision): one new
 * vertex per edge, shared by every triangle of that edge. The original
 * vertices never move, so no detail is added ("no increase in the surface
 * detail"); only the sampling gets denser, which gives the completion
 * intermediate samples against phase shifts between the sample and target
 * vertex sets. Where the new vertex goes (`scheme`):
 * - RELIEF_OVERSAMPLE_MIDPOINT, the papers' rule: the edge's exact midpoint,
 *   so the 4 children are coplanar with their parent. The relief at a
 *   midpoint is then the linear interpolation of its endpoints', which cuts
 *   every crest and fills every trough: on the synthetic surfaces the
 *   midpoints' mean |relief| is 7 to 15 % below the original vertices', and
 *   since 3 of every 4 samples are midpoints, completions copy that loss.
 * - RELIEF_OVERSAMPLE_BUTTERFLY (default): the modified butterfly point
 *   (Zorin, Schroeder and Sweldens 1996). Between two vertices of valence
 *   6, the 8-point butterfly (Dyn, Levin and Gregory 1990): 1/2 (a + b) +
 *   1/8 (c + d) - 1/16 (e1 + e2 + e3 + e4), with c, d the vertices opposite
 *   the edge and e1..e4 those opposite the other edges of its two
 *   triangles; next to a vertex of another valence k, that vertex's
 *   k-point stencil on its 1-ring (the mean of both when both are
 *   irregular). The scheme interpolates (original vertices stay), keeps a
 *   plane flat and reproduces cubic relief exactly on a regular grid, so
 *   the new samples carry the relief the capture implies rather than its
 *   chords. An edge on the boundary, or with an end on it, or next to a
 *   non-manifold or valence > 64 vertex, gets its midpoint, and so does
 *   one whose butterfly point lies farther than half the edge's length
 *   from the midpoint (a spike or a sliver in the capture).
 *
 * Output layout (deterministic for a given input):
 * - vertices: the input's vertices first, with their indices (0..nv-1) and
 *   attributes unchanged; then one vertex per edge of the mesh being split,
 *   in order of the edge's first appearance in the triangle list (triangle
 *   t's edges (a,b), (b,c), (c,a) in that order, t increasing). With several
 *   passes each pass appends after the previous one's vertices.
 * - triangles: parent t = (a, b, c) with edge midpoints ab, bc, ca becomes
 *   children 4t .. 4t+3 = (a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca),
 *   all wound like the parent. After P passes the ancestor of output
 *   triangle j is input triangle j / 4^P.
 * - counts per pass: V' = V + E, T' = 4 T, where E is the number of distinct
 *   edges (unordered vertex pairs) of the mesh being split.
 *
 * Attributes of a new vertex (the input's attribute set is kept):
 * - label: the endpoints' label when they agree, else 0
 *   (RELIEF_LABEL_CAPTURED);
 * - normal: the normalised mean of the endpoints' normals (the normal of the
 *   endpoint with the smaller index when the two cancel out);
 * - colour: a Gaussian weighted sum of the colours of the k nearest ORIGINAL
 *   vertices (those of `in`, whatever the number of passes), weight
 *   w = exp(-d^2 / (2 sigma^2)) with d the Euclidean distance from the new
 *   vertex. Neighbours tied with the k-th nearest distance (relative
 *   difference <= 1e-9) are all included, up to 2k in all, so a regular
 *   grid gives a symmetric neighbourhood whatever the kd-tree's order; a
 *   linear colour ramp is then reproduced exactly at points about which the
 *   original vertices are point-symmetric (the midpoints of a regular grid
 *   after one pass). The search is an exact kd-tree query (FLANN,
 *   FLANN_INDEX_KDTREE_SINGLE, eps 0). A colour is a convex combination of
 *   colours in [0, 1], so it stays in [0, 1] (clamped against rounding); a
 *   constant colour stays exactly constant.
 */
#ifndef RELIEF_HOST_OVERSAMPLE_H
#define RELIEF_HOST_OVERSAMPLE_H

#include <stddef.h>

#include "relief/relief.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RELIEF_OVERSAMPLE_PASSES_MAX 8
#define RELIEF_OVERSAMPLE_K_MAX 256

/* Colour transfer of relief_oversample. */
typedef struct relief_oversample_params {
    int scheme;   /* RELIEF_OVERSAMPLE_*; default BUTTERFLY */
    int k;        /* nearest original vertices per new vertex; default 6,
                     range [1, RELIEF_OVERSAMPLE_K_MAX]; clamped to the
                     input's vertex count */
    double sigma; /* Gaussian width in input units; default 0, which means
                     half the input's median edge length (median over its
                     distinct edges); else finite and > 0 */
} relief_oversample_params;

/* Butterfly, k = 6, sigma = 0 (half the median edge length). */
relief_oversample_params relief_oversample_params_default(void);

/* Oversample `in` by `passes` rounds of 1-to-4 midpoint subdivision (layout
 * and attributes as described above) into a new mesh `*out`, which the
 * caller frees with relief_mesh_destroy. passes = 0 gives a copy.
 * `p` may be NULL (defaults); it only matters when `in` has colour.
 *
 * Errors: RELIEF_E_USAGE for a NULL `in` or `out`; RELIEF_E_RANGE for
 * passes outside [0, RELIEF_OVERSAMPLE_PASSES_MAX], an unknown scheme, k or
 * sigma out of range,
 * or a result over UINT32_MAX vertices; RELIEF_E_MESH for a point cloud
 * (no triangle: it has no surface to subdivide), an input that fails
 * relief_mesh_validate, or a coloured input whose median edge length is 0
 * with sigma = 0; RELIEF_E_NOMEM; RELIEF_E_INTERNAL when FLANN fails. */
relief_status relief_oversample(const relief_mesh *in, int passes,
                                const relief_oversample_params *p,
                                relief_mesh **out, relief_error *err);

#ifdef __cplusplus
}
#endif

#endif
