/* Headless shaded rendering of a mesh into an RGB image: relief's own
 * small rasteriser, so pictures need no display, no GL and no other
 * program.
 *
 * Camera. Orthographic. The view (azimuth, elevation), in degrees in the
 * mesh's own frame, is the direction from the object to the camera:
 *     d = (cos el cos az, cos el sin az, sin el),
 * so azimuth 0, elevation 0 looks along -x at the side facing +x. Screen
 * up is +z projected on the image plane (+y when the view is within 0.1
 * degree of the z axis). The projected vertices (of the mesh, or of a
 * given mesh so that several renders line up) are framed to fill the
 * image less a margin of RELIEF_RENDER_MARGIN of each side, keeping the
 * aspect ratio.
 *
 * Default view (has_view 0): the area-weighted mean normal of the captured
 * part (label 0, or the whole mesh without labels; the mesh's own normals
 * for a point cloud), turned RELIEF_RENDER_TURN_AZ degrees in azimuth and
 * RELIEF_RENDER_TURN_EL degrees in elevation (downwards when the normal is
 * already steeper than 60 degrees) so relief is seen at a slant; azimuth
 * 30, elevation 20 when that mean vanishes (a closed surface).
 *
 * Shading. A z-buffer over RELIEF_RENDER_SUPERSAMPLE^2 samples per pixel
 * (averaged: anti-aliased edges). Normals are the area-weighted vertex
 * normals, interpolated across each triangle (Phong normals, Gouraud
 * colours), flipped towards the camera on back faces, which are also
 * darkened by RELIEF_RENDER_BACK so the inside of an open surface reads
 * as such. One directional light from above-left of the camera: colour *
 * (ambient 0.28 + 0.72 max(0, n.l)) + a weak white highlight. A point
 * cloud (no triangles) is drawn as depth-tested square splats about one
 * point spacing wide, shaded with the file's normals when it has them.
 * Background: RELIEF_RENDER_BACKGROUND, flat, so foreground pixels are the
 * ones that differ from it.
 *
 * Colour (per vertex, interpolated):
 * - colour: the mesh's colour (RELIEF_E_MESH when it has none);
 * - label: RELIEF_LABEL_CAPTURED grey, RELIEF_LABEL_COMPLETED orange
 *   (RELIEF_E_MESH without labels, or for another label value);
 * - displacement: the signed height h = relief_fit_distance(prim, p) on a
 *   blue (-range) - light grey (0) - red (+range) diverging map; the
 *   primitive is the caller's or relief_fit_mesh (RELIEF_FIT_AUTO) on the
 *   label-0 part (the whole mesh without labels), as relief_measure does;
 *   the range is the caller's or the 99th percentile of |h|;
 * - auto: colour when the mesh has it, else label when it has labels,
 *   else a uniform grey;
 * - none: uniform grey.
 */
#ifndef RELIEF_HOST_RENDER_H
#define RELIEF_HOST_RENDER_H

#include <stdint.h>

#include "relief/relief.h"
#include "smooth/fit.h"

#define RELIEF_RENDER_DEFAULT_WIDTH 800
#define RELIEF_RENDER_DEFAULT_HEIGHT 600
#define RELIEF_RENDER_MAX_SIDE 8192
#define RELIEF_RENDER_MARGIN 0.05
#define RELIEF_RENDER_SUPERSAMPLE 2
#define RELIEF_RENDER_TURN_AZ 25.0
#define RELIEF_RENDER_TURN_EL 20.0
#define RELIEF_RENDER_BACK 0.7
/* Background, 8-bit sRGB. */
#define RELIEF_RENDER_BACKGROUND_R 246
#define RELIEF_RENDER_BACKGROUND_G 246
#define RELIEF_RENDER_BACKGROUND_B 248

typedef enum relief_colour_by {
    RELIEF_COLOUR_BY_AUTO = 0,
    RELIEF_COLOUR_BY_LABEL,
    RELIEF_COLOUR_BY_COLOUR,
    RELIEF_COLOUR_BY_DISPLACEMENT,
    RELIEF_COLOUR_BY_NONE
} relief_colour_by;

/* "auto", "label", "colour", "displacement", "none". */
const char *relief_colour_by_name(relief_colour_by c);

/* The two label colours, linear RGB in [0, 1]. */
extern const float relief_render_label_rgb[2][3];

typedef struct relief_render_options {
    int width, height;          /* image size, pixels, 1..RELIEF_RENDER_MAX_SIDE;
                                   default 800 x 600 */
    int has_view;               /* 0: the default view (above) */
    double azimuth, elevation;  /* degrees, elevation in [-90, 90] */
    relief_colour_by colour_by; /* default RELIEF_COLOUR_BY_AUTO */
    const relief_fit_primitive *prim; /* displacement: heights from this
                                         primitive; NULL: fitted (above) */
    double displacement_range;  /* displacement: |h| mapped to the map's
                                   ends (input units); 0: automatic */
    const relief_mesh *frame;   /* frame this mesh's vertices instead of
                                   the rendered mesh's (so renders of
                                   stages of one surface line up); NULL */
} relief_render_options;

relief_render_options relief_render_options_default(void);

/* What a render used, for captions and legends. */
typedef struct relief_render_info {
    double azimuth, elevation;  /* the view, degrees */
    relief_colour_by colour_by; /* resolved: never AUTO */
    double displacement_range;  /* the range used (displacement only) */
    double pixel_size;          /* input units per pixel */
} relief_render_info;

/* An 8-bit RGB image: height rows of width x 3 bytes, top row first. */
typedef struct relief_rgb_image {
    int width, height;
    uint8_t *rgb;
} relief_rgb_image;

void relief_rgb_image_free(relief_rgb_image *img);

/* Render `mesh` (positions; triangles, or none for a point cloud) into
 * *out (allocated here; free with relief_rgb_image_free). `info` may be NULL.
 * Errors: RELIEF_E_USAGE for NULL arguments; RELIEF_E_RANGE for a size or
 * a view out of range or a negative or non-finite displacement_range;
 * RELIEF_E_MESH for an empty or invalid mesh, or one without what the
 * colouring needs (named in the message), or a failed fit; RELIEF_E_NOMEM. */
relief_status relief_render(const relief_mesh *mesh, const relief_render_options *opts,
                            relief_rgb_image *out, relief_render_info *info, relief_error *err);

/* The default view of `mesh` (above), degrees. */
void relief_render_default_view(const relief_mesh *mesh, double *azimuth, double *elevation);

/* The same rule on the part of `mesh` labelled `part` (its triangles whose
 * three vertices carry that label; its vertices for a point cloud), or on
 * the whole mesh for part -1 or a mesh without labels. */
void relief_render_part_view(const relief_mesh *mesh, int part, double *azimuth,
                             double *elevation);

#endif
