/* relief/depth.h: depth frames, their files, and depth-image repair (paper
 * 003: constrained texture synthesis of the missing pixels, directly, on
 * Haar bands, or on the texture part of a structure/texture split), for
 * range images and, through six orthographic depth images, for meshes.
 *
 *   relief_depth_image f;
 *   relief_depth_read("frame.pcd", 0, 0, &f, &err);   NaN where missing
 *   relief_depth_fill_params p = relief_depth_fill_params_default();
 *   relief_depth_fill(&f, NULL, &p, NULL, &err);
 *   relief_depth_write(&f, "repaired.pcd", f.format, &err);
 *   relief_depth_image_free(&f);
 */
#ifndef RELIEF_DEPTH_H
#define RELIEF_DEPTH_H

#include "relief/core.h"
#include "relief/image.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Largest side of a depth image (pixels). */
#define RELIEF_DEPTH_MAX_SIDE 65535

/* The file a frame came from, and how a writer encodes one:
 *   pfm             a Portable Float Map of z (Middlebury's disparities);
 *   pcd-ascii, pcd-binary, pcd-compressed
 *                   an organised PCD v0.7 (PCL) with x y z [rgb];
 *   png16           a 16-bit grey PNG, z x png_scale, 0 where missing.
 * X(code, name) */
#define RELIEF_DEPTH_FORMAT_LIST(X)                                             \
    X(RELIEF_DEPTH_PFM, "pfm")                                                  \
    X(RELIEF_DEPTH_PCD_ASCII, "pcd-ascii")                                      \
    X(RELIEF_DEPTH_PCD_BINARY, "pcd-binary")                                    \
    X(RELIEF_DEPTH_PCD_COMPRESSED, "pcd-compressed")                            \
    X(RELIEF_DEPTH_PNG16, "png16")

typedef enum relief_depth_format {
#define RELIEF_X_ENUM(code, name) code,
    RELIEF_DEPTH_FORMAT_LIST(RELIEF_X_ENUM)
#undef RELIEF_X_ENUM
} relief_depth_format;

/* "pfm", ...; "unknown" out of range. */
RELIEF_API const char *relief_depth_format_name(relief_depth_format format);

/* A depth or range image: a view of a caller's arrays, or what
 * relief_depth_read allocated. Rows top to bottom, packed. */
typedef struct relief_depth_image {
    int width, height;  /* pixels, 1..RELIEF_DEPTH_MAX_SIDE */
    float *z;           /* height x width: depth (metres for a PCD or a PNG) or the
                           PFM's value; NaN where missing */
    float *xyz;         /* height x width x 3: an organised cloud's points (NaN
                           where missing), or NULL */
    uint8_t *rgb;       /* height x width x 3: the cloud's colour, or NULL */
    relief_depth_format format; /* what it was read from */
} relief_depth_image;

/* Default PNG scale: values per metre of the TUM and Kinect datasets. */
#define RELIEF_DEPTH_PNG_SCALE 5000.0

/* Read a depth frame: an organised PCD (x y z [rgb]; ascii, binary or
 * binary_compressed), a PFM, a 16-bit grey PNG or a binary PGM, told by
 * the first bytes (a PNG or PGM: z = value / png_scale, 0 missing; png_scale 0:
 * RELIEF_DEPTH_PNG_SCALE, else (0, 1e9] values per metre).
 * max_pixels (0: none) refuses larger frames before they are allocated
 * (RELIEF_E_NOMEM). RELIEF_E_IO naming the path; RELIEF_E_PARSE (the line
 * or byte), RELIEF_E_FORMAT (an unorganised cloud, a PNG of another kind),
 * RELIEF_E_RANGE. Free with relief_depth_image_free. */
RELIEF_API relief_status relief_depth_read(const char *path, double png_scale,
                                           uint64_t max_pixels, relief_depth_image *out,
                                           relief_error *err);

/* How a depth image's 16-bit samples are depths, for relief_depth_read_as
 * (colour + depth pairs as the RGB-D datasets store them):
 *   auto  told by the first bytes: a PCD or a PFM as they are, a 16-bit PNG
 *         or PGM as png and pgm say (what relief_depth_read does);
 *   png   a 16-bit grey PNG: value / scale metres, 0 missing;
 *   pgm   a binary PGM (P5, 8 or 16 bits; two bytes big-endian, as Netpbm
 *         says): the same;
 *   nyu   NYU Depth v2's raw Kinect frame: a 16-bit PGM whose samples are
 *         disparities d stored little-endian (against Netpbm's rule);
 *         depth = 351.3 / (1092.5 - d) metres, missing where d >= 2047 or
 *         that is not positive (scale unused);
 *   sun   SUN RGB-D's 16-bit PNG, its bits rotated: d = (v >> 3) | (v << 13)
 *         as 16 bits, then d / scale metres (scale 0: 1000, millimetres).
 * The frame read is RELIEF_DEPTH_PNG16 (what it is written back as).
 * X(code, name) */
#define RELIEF_DEPTH_ENCODING_LIST(X)                                           \
    X(RELIEF_DEPTH_ENCODING_AUTO, "auto")                                       \
    X(RELIEF_DEPTH_ENCODING_PNG, "png")                                         \
    X(RELIEF_DEPTH_ENCODING_PGM, "pgm")                                         \
    X(RELIEF_DEPTH_ENCODING_NYU, "nyu")                                         \
    X(RELIEF_DEPTH_ENCODING_SUN, "sun")

typedef enum relief_depth_encoding {
#define RELIEF_X_ENUM(code, name) code,
    RELIEF_DEPTH_ENCODING_LIST(RELIEF_X_ENUM)
#undef RELIEF_X_ENUM
} relief_depth_encoding;

/* "auto", ...; "unknown" out of range. */
RELIEF_API const char *relief_depth_encoding_name(relief_depth_encoding encoding);

/* relief_depth_read with the samples' encoding named: `scale` is png_scale
 * (png, pgm: 0 is RELIEF_DEPTH_PNG_SCALE; sun: 0 is 1000). RELIEF_E_FORMAT
 * when the file is not what the encoding says (a nyu or pgm that is no
 * 16-bit PGM, a png or sun that is no 16-bit grey PNG), RELIEF_E_RANGE for
 * an encoding out of the list; else relief_depth_read's errors. */
RELIEF_API relief_status relief_depth_read_as(const char *path, relief_depth_encoding encoding,
                                              double scale, uint64_t max_pixels,
                                              relief_depth_image *out, relief_error *err);

/* The same from `n` bytes in memory (PCD or PFM); `name` names them. */
RELIEF_API relief_status relief_depth_decode(const void *data, size_t n, const char *name,
                                             uint64_t max_pixels, relief_depth_image *out,
                                             relief_error *err);

/* Write `f` to `path` as `format`, atomically: a PFM of z (NaN as +inf); an
 * organised PCD (needs xyz; rgb when set); a 16-bit PNG of z x png_scale
 * rounded, 0 where missing (png_scale 0: the default, as relief_depth_read;
 * a filled depth rounds to at least 1, a deep one clamps at 65535).
 * Whole or not at all, as relief_mesh_write (RELIEF_E_SYSTEM on a full
 * disk, with the system's reason), RELIEF_E_IO naming the path,
 * RELIEF_E_USAGE for a PCD without xyz, RELIEF_E_RANGE for a bad size,
 * format or png_scale. */
RELIEF_API relief_status relief_depth_write(const relief_depth_image *f, const char *path,
                                            relief_depth_format format, double png_scale,
                                            relief_error *err);

/* Free what a reader allocated and zero *f. NULL accepted. */
RELIEF_API void relief_depth_image_free(relief_depth_image *f);

/* ------------------------------------------------------------- the repair */

/* Paper 003's variants:
 *   plain      synthesis on the depths themselves (3.1);
 *   haar       the coarsest Haar LL interpolated, every level's detail
 *              bands synthesised (3.2);
 *   decompose  ROF's structure u interpolated, the texture v synthesised
 *              (3.3).
 * X(code, name) */
#define RELIEF_DEPTH_VARIANT_LIST(X)                                            \
    X(RELIEF_DEPTH_PLAIN, "plain")                                              \
    X(RELIEF_DEPTH_HAAR, "haar")                                                \
    X(RELIEF_DEPTH_DECOMPOSE, "decompose")

typedef enum relief_depth_variant {
#define RELIEF_X_ENUM(code, name) code,
    RELIEF_DEPTH_VARIANT_LIST(RELIEF_X_ENUM)
#undef RELIEF_X_ENUM
} relief_depth_variant;

/* The synthesis's order: both (run both, keep the better), horizontal
 * (ties row-major) or vertical (ties column-major). */
#define RELIEF_DEPTH_ORDER_LIST(X)                                              \
    X(RELIEF_DEPTH_ORDER_BOTH, "both")                                          \
    X(RELIEF_DEPTH_ORDER_HORIZONTAL, "horizontal")                              \
    X(RELIEF_DEPTH_ORDER_VERTICAL, "vertical")

typedef enum relief_depth_order {
#define RELIEF_X_ENUM(code, name) code,
    RELIEF_DEPTH_ORDER_LIST(RELIEF_X_ENUM)
#undef RELIEF_X_ENUM
} relief_depth_order;

/* The smooth fill of haar's LL and decompose's u: auto (harmonic for
 * images, thin-plate for meshes), harmonic (the membrane), or thin-plate
 * (carries the rim's slope and curvature in; can overshoot at depth
 * edges). */
#define RELIEF_MEMBRANE_LIST(X)                                                 \
    X(RELIEF_MEMBRANE_AUTO, "auto")                                             \
    X(RELIEF_MEMBRANE_HARMONIC, "harmonic")                                     \
    X(RELIEF_MEMBRANE_THIN_PLATE, "thin-plate")

typedef enum relief_membrane {
#define RELIEF_X_ENUM(code, name) code,
    RELIEF_MEMBRANE_LIST(RELIEF_X_ENUM)
#undef RELIEF_X_ENUM
} relief_membrane;

/* A hole across a depth step (a camera's shadow beside an object, a
 * stereo occlusion): layers fills each pixel by the surface it belongs
 * to, from that surface's part of the rim only, so the background
 * continues behind and the foreground's silhouette stays where it was
 * captured (with the frame's colour, where the colour parts them);
 * across fills it from the whole rim (paper 003), a ramp from one
 * surface to the other; auto (default) is layers for depths and across
 * for disparities (values): a step is a difference over edge_step times
 * the noise measured on the frame, and a noise-free disparity map (a
 * stereo benchmark's ground truth) has none to measure, so its slopes
 * would read as steps. */
#define RELIEF_DEPTH_EDGES_LIST(X)                                              \
    X(RELIEF_DEPTH_EDGES_AUTO, "auto")                                          \
    X(RELIEF_DEPTH_EDGES_LAYERS, "layers")                                      \
    X(RELIEF_DEPTH_EDGES_ACROSS, "across")

typedef enum relief_depth_edges {
#define RELIEF_X_ENUM(code, name) code,
    RELIEF_DEPTH_EDGES_LIST(RELIEF_X_ENUM)
#undef RELIEF_X_ENUM
} relief_depth_edges;

/* What a frame's values are, for the layers' order (which surface is in
 * front): auto (a PFM read by relief holds disparities, any other frame
 * depths), depth (larger is farther) or disparity (larger is nearer). */
#define RELIEF_DEPTH_VALUES_LIST(X)                                             \
    X(RELIEF_DEPTH_VALUES_AUTO, "auto")                                         \
    X(RELIEF_DEPTH_VALUES_DEPTH, "depth")                                       \
    X(RELIEF_DEPTH_VALUES_DISPARITY, "disparity")

typedef enum relief_depth_values {
#define RELIEF_X_ENUM(code, name) code,
    RELIEF_DEPTH_VALUES_LIST(RELIEF_X_ENUM)
#undef RELIEF_X_ENUM
} relief_depth_values;

RELIEF_API const char *relief_depth_variant_name(relief_depth_variant variant);
RELIEF_API const char *relief_depth_values_name(relief_depth_values values);
RELIEF_API const char *relief_depth_edges_name(relief_depth_edges edges);
RELIEF_API const char *relief_depth_order_name(relief_depth_order order);
RELIEF_API const char *relief_membrane_name(relief_membrane membrane);

typedef struct relief_depth_fill_params {
    relief_depth_variant variant; /* default decompose */
    int window;          /* synthesis window, odd pixels; 9, [3, 1025] */
    double sigma;        /* the window's Gaussian weights, pixels; <= 0
                            (default): window / 6.4; else [0.5, 1e6] */
    double epsilon;      /* near-minimum tolerance of the draw; 0.1, [0, 10] */
    int search_radius;   /* symmetric search distance, pixels; 32; 0: the whole
                            image; [0, 1e6] */
    int exhaustive;      /* 1: every window at full resolution (no pyramid) */
    int batch;           /* 1 (default): Efros and Leung's order, a pixel at a
                            time; [2, 256]: waves of up to that many pixels,
                            none inside the (full-resolution) window of an
                            earlier one still to be filled, searched against
                            the same state (one device launch per wave; their
                            candidate windows do not see the wave's own
                            copies); the same bytes on every backend for a
                            given batch. Not with tileable (RELIEF_E_USAGE) */
    relief_depth_order order; /* default both */
    int tileable;        /* 1: the image is a torus (paper 003's tileable
                            constraint): the result repeats without seams and
                            holes at a border are filled */
    int levels;          /* haar: transform steps; 2, [1, 6] */
    double lambda;       /* decompose: ROF's lambda, depth units x pixels; <= 0
                            (default): 8 x the capture's robust step between
                            neighbours; else (0, 1e12] */
    relief_membrane membrane; /* default auto */
    int seam;            /* 1 (default): each hole's rim blended in the
                            gradient domain, so the fill continues the
                            capture's slope; 0: as synthesised */
    int resolution;      /* meshes: voxels along the box's longest side; 256,
                            [8, 1024] */
    /* meshes: what comes back (issue 40). The six depth images make a
     * closed solid (every opening capped, the inside filled): solid = 1
     * returns it (paper 003, section 2). solid = 0 (default) returns the
     * capture with only its holes filled, chosen by the hole model of
     * relief_complete_points (max_hole, a selection): the solid's skin over
     * each, zipped to its rim; labels 1 on what was added. */
    int solid;
    double max_hole;     /* a hole whose rim is wider than this (mesh units)
                            is an opening by design (a vessel's mouth) and
                            stays open; 0 (default): a quarter of the
                            bounding box's diagonal; [0, 1e30] */
    int has_hole_ball;   /* 1: fill exactly the holes whose rims have a vertex
                            within hole_ball (X, Y, Z, R > 0) */
    double hole_ball[4];
    int hole_labels;     /* 1: ... a vertex labelled non-zero (the mesh must
                            have labels); not with has_hole_ball */
    uint32_t seed;       /* the near-minimum draw; 1 */
    const relief_depth_image *truth; /* NULL, or the complete frame (mesh: use
                            relief_depth_fill_mesh's truth): the report
                            measures the repair against it */
    relief_run_options run; /* backend: scalar (one thread, the reference),
                            host (the host's threads), opencl, or auto
                            (default: OpenCL on the device run.device names,
                            else the host's threads); the same bytes on
                            every backend */
    int skin;            /* meshes, without solid: 1 closes each hole with the
                            solid's skin zipped to its rim (paper 003's
                            surface, relief's route before issue 61); 0
                            (default): with a faired patch made from the
                            rim's own edges (closed, no crossing at the
                            seam), given the solid's relief where the solid
                            lies within 3 voxels of it */
    relief_depth_edges edges; /* images: default auto (layers for depths, across
                            for disparities; issue 63); across is paper 003's */
    double edge_step;    /* images, layers: a step between two surfaces is a
                            difference over this many noise units (the
                            median non-zero |second difference| of the
                            frame, over z^2 for depths, as it is for a PFM's
                            disparities); 8, [1, 1000] */
    relief_depth_values values; /* default auto */
} relief_depth_fill_params;

/* The defaults above. */
RELIEF_API relief_depth_fill_params relief_depth_fill_params_default(void);

/* Check the fields that do not depend on a frame; RELIEF_E_RANGE naming the
 * field and its range. */
RELIEF_API relief_status relief_depth_fill_params_validate(const relief_depth_fill_params *p,
                                                           relief_error *err);

/* relief_depth_fill_params described field by field (relief_param,
 * relief/core.h). */
RELIEF_API const relief_param *relief_depth_fill_param_table(size_t *count);

/* What a repair did (an image; for a mesh, summed over its six images). */
typedef struct relief_depth_fill_report {
    size_t missing;          /* pixels missing (NaN, 0, inf, or the mask) */
    size_t missing_in_input; /* of them, missing in the frame itself */
    size_t missing_by_mask;  /* of them, known but masked */
    size_t filled;           /* of them, inside the capture: filled */
    size_t outside;          /* of them, outside (no known pixel on both sides
                                along the row or column): left missing */
    size_t by_synthesis, by_fallback, by_membrane, unreached;
    int membrane_iterations; /* the most any smooth solve took */
    int membrane_capped;     /* 1: a solve stopped at its cap before converging */
    double lambda;           /* decompose: the lambda used */
    relief_depth_order order_kept;
    size_t candidates;       /* windows scored */
    size_t stepped_holes;    /* image, edges layers: holes across a depth step */
    size_t front_pixels;     /* of their pixels, those given a nearer surface
                                than the farthest (the rest continue it) */
    double noise;            /* image, edges layers: the noise unit measured
                                (z^2's factor, or a disparity) */
    int camera_fitted;       /* an organised cloud: 1 when a camera was fitted
                                to its points, so the filled pixels have points;
                                0: their points are NaN */
    /* against params.truth (or a mesh's truth), when given; NaN where not
       measured */
    int measured;
    double rms;              /* RMS over the filled pixels (mesh: mean surface
                                distance) */
    size_t compared;         /* image: filled pixels the truth knows */
    double slope_jump;       /* image: rim_jump over capture_jump (1: the rim as
                                rough as the capture; needs no truth) */
    double rim_jump;         /* image: mean |second difference| across the rim,
                                capture into fill (depth units) */
    double capture_jump;     /* image: the same over the capture's own triples */
    double truth_rim_jump;   /* image: rim_jump with the truth in the hole */
    double hausdorff;        /* mesh: symmetric Hausdorff distance (mesh units) */
    double iou;              /* mesh: voxel IoU against the truth */
    /* meshes */
    size_t vertices, triangles; /* of the repaired mesh */
    int grid[3];             /* voxels along x, y and z */
    double voxel;            /* a voxel's side (mesh units) */
    size_t inside_voxels;    /* voxels between the repaired depths */
    relief_backend backend;
    char device[256];
    char backend_note[1024];
    int backend_warning;
    double seconds_transform; /* Haar, ROF, membranes (mesh: z-buffers, surface) */
    double seconds_synthesis; /* the synthesis (mesh: the six repairs) */
    double seconds_score;     /* of which scoring windows (image) */
    double seconds_total;
    char *json;              /* the report as `relief depth-fill --report` writes
                                it (owned) */
    char holes_left[640];    /* mesh: "" or one line naming the widest rims the
                                hole model left open by its rule (an outer
                                border, an opening wider than max_hole), each
                                with its size, centre and the max_hole or
                                hole_ball that fills it */
} relief_depth_fill_report;

/* Free what the report owns and zero it. NULL accepted. */
RELIEF_API void relief_depth_fill_report_free(relief_depth_fill_report *rep);

/* The memory check relief_depth_fill makes on an image before it
 * allocates, from the size alone: the host bytes a repair of a width x
 * height frame plans for against p->run.max_memory (0: 80 % of physical
 * memory; NULL p: the defaults'). RELIEF_E_NOMEM naming the estimate and
 * the limit, as relief_depth_fill refuses; RELIEF_E_RANGE for a side out
 * of 1..RELIEF_DEPTH_MAX_SIDE; else RELIEF_OK. Needs no depths, so that a
 * caller who must convert a frame first can refuse it before the copy. */
RELIEF_API relief_status relief_depth_fill_check_memory(int width, int height,
                                                        const relief_depth_fill_params *p,
                                                        relief_error *err);

/* Repair `f` in place: its missing pixels (z NaN, inf or 0, or non-zero in
 * `mask`, an image of the same size: any channel but alpha) inside the
 * capture are filled; those outside (a camera's invalid margin) stay NaN.
 * Known pixels keep their bits. An organised cloud (xyz set) gets a point
 * for each filled pixel through a pinhole camera fitted to its points, and
 * (rgb set) the colour of the pixel its texture came from. Deterministic
 * for a seed whatever the backend. Nothing missing: RELIEF_OK, f untouched.
 * RELIEF_E_RANGE when every pixel is missing or every missing one is
 * outside; RELIEF_E_USAGE for a bad argument (named), a mask or a truth of
 * another size; RELIEF_E_NOMEM (over run.max_memory, before anything is
 * allocated), RELIEF_E_DEVICE, RELIEF_E_CANCELLED (run.progress answered
 * non-zero: between two synthesised pixels). `f` and `rep` (may be NULL;
 * free with relief_depth_fill_report_free) are written only on success. */
RELIEF_API relief_status relief_depth_fill(relief_depth_image *f, const relief_image *mask,
                                           const relief_depth_fill_params *p,
                                           relief_depth_fill_report *rep, relief_error *err);

/* Repair a mesh (triangles counter-clockwise seen from outside) through the
 * six orthographic depth images of its bounding box: the pixels whose ray
 * meets the inside through a hole are repaired, the voxels between the
 * front and back depths kept, and their surface extracted, closed. With
 * p->solid that surface is *out; by default *out is `in` (the vertices in a
 * triangle and the triangles first, in order, as relief_mesh_repair leaves
 * them) with each hole the hole model fills closed, what is added
 * labelled 1 (relief_depth_fill_params.solid and .skin).
 * `truth` (may be NULL): the complete mesh, measured against (p->truth must
 * be NULL). RELIEF_E_RANGE for a mesh without triangles, or when the hole
 * model fills no hole (the message names the loops and what would fill
 * each); RELIEF_E_NOMEM
 * when the voxel grid of p->resolution exceeds run.max_memory; the image
 * route's errors. *out and `rep` are written only on success. */
RELIEF_API relief_status relief_depth_fill_mesh(const relief_mesh *in,
                                                const relief_depth_fill_params *p,
                                                const relief_mesh *truth, relief_mesh **out,
                                                relief_depth_fill_report *rep,
                                                relief_error *err);

#ifdef __cplusplus
}
#endif

#endif /* RELIEF_DEPTH_H */
