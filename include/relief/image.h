/* relief/image.h: images, their files, and hole filling in images (paper
 * 004, chapter 3: a 1-D interpolation pass where a gap's ends agree and
 * the image is smooth, then copy-paste synthesis of windows matched over a Gaussian pyramid).
 *
 *   relief_image img;                    (or a view of your own buffer)
 *   relief_image_read("photo.png", &img, &err);
 *   relief_image_fill_params p = relief_image_fill_params_default();
 *   relief_image_fill(&img, &mask, &p, NULL, &err);   mask: non-zero = fill
 *   relief_image_write(&img, "filled.png", &err);
 *   relief_image_free(&img);
 */
#ifndef RELIEF_IMAGE_H
#define RELIEF_IMAGE_H

#include "relief/core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Largest width or height of an image (pixels). */
#define RELIEF_IMAGE_MAX_SIDE 65535

/* An image in memory: a view of a caller's buffer, or what relief_image_read
 * allocated. Samples are unsigned integers in the machine's byte order,
 * interleaved (RGBRGB...), rows top to bottom. */
typedef struct relief_image {
    int width, height;  /* pixels, 1..RELIEF_IMAGE_MAX_SIDE */
    int channels;       /* 1 grey, 2 grey + alpha, 3 RGB, 4 RGBA */
    int bit_depth;      /* 8 (uint8_t samples) or 16 (uint16_t samples) */
    size_t stride;      /* bytes from a row's start to the next's, at least
                           width x channels x bit_depth / 8; 0: exactly that */
    void *data;         /* height rows of stride bytes */
} relief_image;

/* Check an image's fields (sizes, channels, bit depth, stride, data not
 * NULL); RELIEF_E_USAGE or RELIEF_E_RANGE naming `what` and the field. */
RELIEF_API relief_status relief_image_check(const relief_image *img, const char *what,
                                            relief_error *err);

/* Read a PNG (1 to 16 bits; grey, grey + alpha, palette, RGB, RGBA;
 * palettes and transparency expanded) or a JPEG (8-bit grey or colour),
 * told by the file's first bytes, into *out (packed rows, stride set to
 * the row's bytes; free with relief_image_free). RELIEF_E_IO naming the
 * path; RELIEF_E_FORMAT, RELIEF_E_PARSE (with libpng's or libjpeg's words),
 * RELIEF_E_RANGE for a side over the maximum; RELIEF_E_NOMEM. `max_bytes`
 * (0: none) refuses, before decoding, an image whose samples would take
 * more (width x height x channels x bit_depth / 8 bytes). */
RELIEF_API relief_status relief_image_read(const char *path, uint64_t max_bytes,
                                           relief_image *out, relief_error *err);

/* The same from `n` bytes in memory; `name` names them in messages. */
RELIEF_API relief_status relief_image_decode(const void *data, size_t n, const char *name,
                                             uint64_t max_bytes, relief_image *out,
                                             relief_error *err);

/* Write `img` as PNG or JPEG by the path's extension (.png, .jpg, .jpeg),
 * whole or not at all, as relief_mesh_write (RELIEF_E_SYSTEM on a full
 * disk, with the system's reason). PNG keeps channels and bit depth; JPEG
 * (quality 95) takes 8 bits and drops alpha. RELIEF_E_FORMAT for another
 * extension or 16 bits to JPEG; RELIEF_E_IO naming the path. */
RELIEF_API relief_status relief_image_write(const relief_image *img, const char *path,
                                            relief_error *err);

/* Free what relief_image_read or relief_image_decode allocated and zero
 * *img; never call it on a view of your own buffer. NULL accepted. */
RELIEF_API void relief_image_free(relief_image *img);

/* ------------------------------------------------------------ image fill */

/* How the hole is filled:
 *   wexler  (the default) multi-scale patch voting (Wexler, Shechtman and
 *           Irani 2007, with PatchMatch's search, Barnes et al. 2009): every
 *           filled pixel a vote of the P x P patches that cover it, coarse
 *           to fine; patch, em_steps, pm_steps, seed, interp and the backend
 *           apply;
 *   jain    paper 004's copy-paste synthesis, window by window from the
 *           boundary (the bytes of relief before issue 62); window ..
 *           search_radius, exhaustive, seed, interp apply.
 * X(code, name) */
#define RELIEF_IMAGE_FILL_METHOD_LIST(X)                                        \
    X(RELIEF_IMAGE_FILL_WEXLER, "wexler")                                       \
    X(RELIEF_IMAGE_FILL_JAIN, "jain")

typedef enum relief_image_fill_method {
#define RELIEF_X_ENUM(code, name) code,
    RELIEF_IMAGE_FILL_METHOD_LIST(RELIEF_X_ENUM)
#undef RELIEF_X_ENUM
} relief_image_fill_method;

/* "wexler" or "jain" ("unknown" for another value). */
RELIEF_API const char *relief_image_fill_method_name(relief_image_fill_method method);

typedef struct relief_image_fill_params {
    relief_image_fill_method method; /* RELIEF_IMAGE_FILL_WEXLER (default) or _JAIN */
    int patch;           /* wexler: the patch side P, odd pixels; 7, [3, 15] */
    int em_steps;        /* wexler: vote-and-search steps at the coarsest
                            level (finer levels fewer, at least 4); 10, [1, 50] */
    int pm_steps;        /* wexler: PatchMatch iterations per step; 3, [1, 20] */
    int window;          /* starting window w, odd pixels; 17, [3, 1025]
                            (paper 004: 129 for texture atlases) */
    int min_window;      /* smallest window before the 3 x 3 fallback, odd;
                            5, [3, window] */
    double tau;          /* accept a match when its RMS difference is under
                            tau, in sample units, > 0; 0 (default): 36 on
                            0..255, x 257 at 16 bits */
    double max_hole_fraction; /* a candidate window's hole pixels at most this
                            share; 0.1, [0, 1) */
    int search_radius;   /* search the (2r + 1)^2 window of the same centre,
                            pixels; 0 (default): the whole image; [0, 1e6],
                            and 2r + 1 at least window when not 0 */
    int exhaustive;      /* 1: every window at full resolution (slow; the
                            reference); 0 (default): coarse to fine */
    int interp;          /* 1 (default): the 1-D interpolation pass first,
                            along rows then columns, over the gaps no longer
                            than window whose ends agree (interp_diff), are
                            smooth (interp_sd) and, over half a window
                            along the line, no rougher (mean |second
                            difference|) than the image's median pixel
                            (at least 1 on 0..255, x 257 at 16 bits): a
                            linear run never replaces texture */
    double interp_diff;  /* 1-D pass: a gap's ends differ by at most this in
                            every channel; < 0 (default): 16 on 0..255, scaled */
    double interp_sd;    /* 1-D pass: the 4 pixels beyond each end have a
                            standard deviation of at most this; < 0
                            (default): 3 on 0..255, scaled */
    uint32_t seed;       /* the fallback's random choice; 1 */
    relief_run_options run; /* backend: scalar (one thread, the reference),
                            host (the host's threads), opencl, or auto
                            (default: OpenCL on the device run.device names,
                            else the host's threads); the same bytes on
                            every backend. progress: the share of the hole
                            pixels filled */
} relief_image_fill_params;

/* The defaults above. */
RELIEF_API relief_image_fill_params relief_image_fill_params_default(void);

/* Check the fields that do not depend on an image (exhaustive and interp
 * are 0 or 1; NaN is refused everywhere), and run; RELIEF_E_RANGE naming
 * the field and its range, RELIEF_E_USAGE for p NULL. relief_image_fill
 * also checks the windows fit the image. */
RELIEF_API relief_status relief_image_fill_params_validate(const relief_image_fill_params *p,
                                                           relief_error *err);

/* relief_image_fill_params described field by field (relief_param,
 * relief/core.h). */
RELIEF_API const relief_param *relief_image_fill_param_table(size_t *count);

/* The memory check relief_image_fill makes before it allocates, from the
 * size alone: the host bytes it plans for on a width x height image of
 * `channels` channels (any bit depth) against p->run.max_memory (0: 80 %
 * of physical memory; NULL p: the defaults'). RELIEF_E_NOMEM naming the
 * estimate and the limit, as relief_image_fill refuses; RELIEF_E_RANGE for
 * a side or a channel count out of range; else RELIEF_OK. Needs no pixels,
 * so that a caller who must copy or convert an image first can refuse it
 * before the copy. */
RELIEF_API relief_status relief_image_fill_check_memory(int width, int height, int channels,
                                                        const relief_image_fill_params *p,
                                                        relief_error *err);

/* What a relief_image_fill call did. */
typedef struct relief_image_fill_report {
    size_t hole_pixels;       /* pixels to fill */
    size_t by_rows, by_columns; /* filled by the 1-D pass */
    size_t by_copy;           /* copied from matched windows */
    size_t by_fallback;       /* by the 3 x 3 fallback */
    size_t queries;           /* boundary pixels a search started from */
    size_t windows_tried;     /* window searches, every size */
    size_t windows_accepted;  /* of them, matches under tau */
    size_t candidates;        /* windows scored, all levels (wexler: patch
                                 distances evaluated) */
    int pyramid_levels;       /* 1: full resolution only */
    size_t em_steps;          /* wexler: vote-and-search steps, every level */
    size_t targets;           /* wexler: patches holding a hole pixel at full
                                 resolution */
    int start_level, top_m;   /* where the search starts; matches kept there */
    double tau, interp_diff, interp_sd; /* the thresholds used */
    relief_backend backend;   /* scalar or opencl */
    char device[256];         /* what it ran on */
    char backend_note[1024];  /* why auto chose it; "" when nothing to say */
    int backend_warning;      /* 1: backend_note says OpenCL could not be used */
    double seconds_interp, seconds_copy, seconds_score, seconds_total;
    char *json;               /* the report as `relief image-fill --report`
                                 writes it, less the "mask" member the
                                 command adds (owned) */
} relief_image_fill_report;

/* Free what the report owns and zero it. NULL accepted. */
RELIEF_API void relief_image_fill_report_free(relief_image_fill_report *rep);

/* Fill the pixels of `image` where `mask` is non-zero, in place. mask: an
 * image of the same width and height (any channels and bit depth; a pixel
 * is to fill when any channel but alpha is non-zero), or NULL: the
 * image's transparent pixels (alpha 0; an image without alpha is
 * RELIEF_E_USAGE). The other pixels keep their bits; alpha is not matched
 * and a filled pixel becomes opaque. Deterministic for a seed whatever the
 * backend. A mask with nothing to fill leaves the image as it is
 * (RELIEF_OK, hole_pixels 0). RELIEF_E_USAGE / RELIEF_E_RANGE for a bad
 * argument (named), RELIEF_E_RANGE when every pixel is to fill or no window
 * qualifies, RELIEF_E_NOMEM, RELIEF_E_DEVICE, RELIEF_E_CANCELLED. `image`
 * is written only on success; `rep` (may be NULL) is filled on success and
 * must be freed. */
RELIEF_API relief_status relief_image_fill(relief_image *image, const relief_image *mask,
                                           const relief_image_fill_params *p,
                                           relief_image_fill_report *rep, relief_error *err);

#ifdef __cplusplus
}
#endif

#endif /* RELIEF_IMAGE_H */
