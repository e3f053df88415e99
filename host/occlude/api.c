/* The occluders' public API (relief/occluders.h): the parameters, the
 * finding (background.c, mask.c), the removal through the image and depth
 * engines' public calls, and the reports. Every call works on its own
 * copies: the caller's frame, mask and report are written only on
 * success. */
#include "relief/relief.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/clock.h"
#include "base/error.h"
#include "base/json.h"
#include "base/memlimit.h"
#include "depth/frame.h"
#include "occlude/occlude.h"

/* Bytes per pixel the finding holds at its peak: points, surface and
 * clearance, colour in CIELAB, the distances, origins, queue and RANSAC's
 * scratch, the mask, the views' verdicts (and 4 per view: its L*). */
#define FIND_BYTES_PER_PIXEL 80u

relief_occluder_params relief_occluder_params_default(void)
{
    relief_occluder_params p;
    memset(&p, 0, sizeof p);
    p.background = RELIEF_BACKGROUND_PLANES;
    p.max_planes = 4;
    p.min_support = 0.03;
    p.margin = 0.0;
    p.window = 61;
    p.colour_distance = 12.0;
    p.edge = 3;
    p.min_area = 50;
    p.dilate = 1;
    p.iterations = 500;
    p.parallax = 2.0;
    p.view_radius = 6;
    p.seed = 1;
    p.front_sigmas = 3.0;
    p.run = relief_run_options_default();
    return p;
}

static relief_status check_intrinsics(const relief_occluder_params *p, relief_error *err)
{
    for (int k = 0; k < 4 && p->has_intrinsics; ++k)
        if (!isfinite(p->intrinsics[k]) || (k < 2 && !(p->intrinsics[k] > 0.0)))
            return relief_fail_param(err, RELIEF_E_RANGE, "intrinsics", "intrinsics %g,%g,%g,%g "
                                     "out of range: expected fx,fy > 0 and finite cx,cy (pixels)",
                                     p->intrinsics[0], p->intrinsics[1], p->intrinsics[2],
                                     p->intrinsics[3]);
    return RELIEF_OK;
}

static relief_status check_views(const relief_occluder_params *p, relief_error *err)
{
    if (p->n_views < 0 || p->n_views > RELIEF_OCCLUDER_MAX_VIEWS)
        return relief_fail_param(err, RELIEF_E_RANGE, "n_views", "n_views %d out of range: "
                                 "expected 0..%d", p->n_views, RELIEF_OCCLUDER_MAX_VIEWS);
    if (p->n_views > 0 && !p->views)
        return relief_fail(err, RELIEF_E_USAGE, "views: NULL with n_views %d", p->n_views);
    for (int k = 0; k < p->n_views; ++k) {
        const double *in = p->views[k].intrinsics;
        for (int i = 0; i < 12; ++i)
            if (!isfinite(p->views[k].pose[i]))
                return relief_fail_param(err, RELIEF_E_RANGE, "views", "view %d: pose element %d "
                                         "is not finite", k, i);
        if ((in[0] != 0.0 || in[1] != 0.0 || in[2] != 0.0 || in[3] != 0.0) &&
            !(in[0] > 0.0 && in[1] > 0.0 && isfinite(in[0]) && isfinite(in[1]) &&
              isfinite(in[2]) && isfinite(in[3])))
            return relief_fail_param(err, RELIEF_E_RANGE, "views", "view %d: intrinsics %g,%g,"
                                     "%g,%g out of range: expected fx,fy > 0 and finite cx,cy "
                                     "(pixels), or all 0 for the frame's camera", k, in[0],
                                     in[1], in[2], in[3]);
    }
    if (!(p->parallax >= 0.1 && p->parallax <= 64.0))
        return relief_fail_param(err, RELIEF_E_RANGE, "parallax", "parallax %g out of range: "
                                 "expected 0.1..64 pixels", p->parallax);
    if (p->view_radius < 1 || p->view_radius > 32)
        return relief_fail_param(err, RELIEF_E_RANGE, "view_radius", "view_radius %d out of range: "
                                 "expected 1..32 pixels", p->view_radius);
    return RELIEF_OK;
}

relief_status relief_occluder_params_validate(const relief_occluder_params *p, relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    if (!p)
        return relief_fail(err, RELIEF_E_USAGE, "params: NULL");
    if ((unsigned)p->seeding > RELIEF_SEEDING_HYSTERESIS)
        return relief_fail_param(err, RELIEF_E_RANGE, "seeding", "seeding %d out of range: "
                                 "expected hysteresis or margin", (int)p->seeding);
    if ((unsigned)p->noise_model > RELIEF_NOISE_FRAME)
        return relief_fail_param(err, RELIEF_E_RANGE, "noise_model", "noise_model %d out of "
                                 "range: expected plane or frame", (int)p->noise_model);
    if (!(p->front_sigmas >= 0.0 && p->front_sigmas <= 64.0))
        return relief_fail_param(err, RELIEF_E_RANGE, "front_sigmas", "front_sigmas %g out of "
                                 "range: expected 0..64 (sigmas; 0: off)", p->front_sigmas);
    if ((unsigned)p->background > RELIEF_BACKGROUND_MESH)
        return relief_fail_param(err, RELIEF_E_RANGE, "background", "background %d out of range: "
                                 "expected planes, plane or mesh", (int)p->background);
    if (p->background == RELIEF_BACKGROUND_MESH && !p->background_mesh)
        return relief_fail(err, RELIEF_E_USAGE, "background mesh needs background_mesh (the "
                           "surface, in the frame's camera coordinates)");
    if (p->max_planes < 1 || p->max_planes > RELIEF_OCCLUDER_MAX_PLANES)
        return relief_fail_param(err, RELIEF_E_RANGE, "max_planes", "max_planes %d out of range: "
                                 "expected 1..%d", p->max_planes, RELIEF_OCCLUDER_MAX_PLANES);
    if (!(p->min_support >= 1e-6 && p->min_support <= 1.0))
        return relief_fail_param(err, RELIEF_E_RANGE, "min_support", "min_support %g out of range: "
                                 "expected 1e-6..1 (a share of the captured points)",
                                 p->min_support);
    if (isnan(p->margin) || p->margin > 1e9)
        return relief_fail_param(err, RELIEF_E_RANGE, "margin", "margin %g out of range: expected "
                                 "up to 1e9 depth units (<= 0: measured)", p->margin);
    if (p->window < 3 || p->window > 1025 || p->window % 2 == 0)
        return relief_fail_param(err, RELIEF_E_RANGE, "window", "window %d out of range: expected "
                                 "an odd number in 3..1025", p->window);
    if (!(p->colour_distance >= 0.0 && p->colour_distance <= 200.0))
        return relief_fail_param(err, RELIEF_E_RANGE, "colour_distance", "colour_distance %g out "
                                 "of range: expected 0..200 (CIELAB delta E)", p->colour_distance);
    if (p->edge < 0 || p->edge > 64)
        return relief_fail_param(err, RELIEF_E_RANGE, "edge", "edge %d out of range: expected "
                                 "0..64 pixels", p->edge);
    if (p->min_area < 1 || p->min_area > 100000000)
        return relief_fail_param(err, RELIEF_E_RANGE, "min_area", "min_area %d out of range: "
                                 "expected 1..1e8 pixels", p->min_area);
    if (p->dilate < 0 || p->dilate > 64)
        return relief_fail_param(err, RELIEF_E_RANGE, "dilate", "dilate %d out of range: expected "
                                 "0..64 pixels", p->dilate);
    if (p->iterations < 10 || p->iterations > 1000000)
        return relief_fail_param(err, RELIEF_E_RANGE, "iterations", "iterations %d out of range: "
                                 "expected 10..1000000", p->iterations);
    if (check_intrinsics(p, err) != RELIEF_OK)
        return RELIEF_E_RANGE;
    {
        relief_status st = check_views(p, err);
        if (st != RELIEF_OK)
            return st;
    }
    return relief_run_options_validate(&p->run, err);
}

void relief_occluder_report_free(relief_occluder_report *rep)
{
    if (!rep)
        return;
    free(rep->json);
    memset(rep, 0, sizeof *rep);
}

void relief_remove_report_free(relief_remove_report *rep)
{
    if (!rep)
        return;
    relief_occluder_report_free(&rep->find);
    free(rep->mask);
    free(rep->json);
    memset(rep, 0, sizeof *rep);
}

/* ------------------------------------------------------------ the report */

static void plane_json(relief_json *j, const relief_occluder_plane *pl)
{
    rj_begin_object(j, NULL);
    rj_vec3(j, "normal", pl->normal);
    rj_number(j, "offset", pl->offset);
    rj_int(j, "inliers", (long long)pl->inliers);
    rj_number(j, "rms", pl->rms);
    rj_number(j, "noise", pl->noise);
    rj_number(j, "local_noise", pl->local_noise);
    rj_int(j, "region", (long long)pl->region);
    rj_number(j, "marked", pl->marked);
    rj_end_object(j);
}

static void params_json(relief_json *j, const relief_occluder_params *p)
{
    rj_begin_object(j, "parameters");
    rj_string(j, "background", relief_background_name(p->background));
    rj_string(j, "seeding", relief_seeding_name(p->seeding));
    rj_string(j, "noise_model", relief_noise_model_name(p->noise_model));
    rj_int(j, "max_planes", p->max_planes);
    rj_number(j, "min_support", p->min_support);
    rj_number(j, "margin", p->margin);
    rj_number(j, "front_sigmas", p->front_sigmas);
    rj_int(j, "window", p->window);
    rj_number(j, "colour_distance", p->colour_distance);
    rj_int(j, "edge", p->edge);
    rj_int(j, "min_area", p->min_area);
    rj_int(j, "dilate", p->dilate);
    rj_int(j, "iterations", p->iterations);
    rj_int(j, "views", p->n_views);
    rj_number(j, "parallax", p->parallax);
    rj_int(j, "view_radius", p->view_radius);
    rj_int(j, "seed", p->seed);
    rj_end_object(j);
}

typedef struct find_ctx {
    const relief_occluder_params *p;
    const relief_occluder_report *r;
} find_ctx;

/* The finding's members (the "occluders" report, or remove's member). */
static void find_body(relief_json *j, const relief_occluder_params *p,
                      const relief_occluder_report *r)
{
    double cam[4];
    memcpy(cam, r->camera, sizeof cam);
    rj_begin_object(j, "image");
    rj_int(j, "width", r->width);
    rj_int(j, "height", r->height);
    rj_int(j, "captured", (long long)r->captured);
    rj_int(j, "missing", (long long)r->missing);
    if (r->has_placeholder) {
        rj_begin_array(j, "placeholder");
        for (int k = 0; k < 3; ++k)
            rj_int(j, NULL, r->placeholder[k]);
        rj_end_array(j);
    } else {
        rj_null(j, "placeholder");
    }
    rj_int(j, "placeholder_pixels", (long long)r->placeholder_pixels);
    rj_end_object(j);
    params_json(j, p);
    rj_begin_array(j, "camera");
    for (int k = 0; k < 4; ++k)
        rj_number(j, NULL, cam[k]);
    rj_end_array(j);
    rj_begin_object(j, "background");
    rj_string(j, "kind", relief_background_name(p->background));
    rj_begin_array(j, "planes");
    for (int k = 0; k < r->planes; ++k)
        plane_json(j, &r->plane[k]);
    rj_end_array(j);
    rj_number(j, "noise", r->noise);
    rj_number(j, "margin", r->margin);
    rj_int(j, "on_background", (long long)r->on_background);
    rj_int(j, "behind", (long long)r->behind);
    rj_int(j, "no_background", (long long)r->no_background);
    rj_end_object(j);
    rj_begin_object(j, "mask");
    rj_int(j, "seeds", (long long)r->seeds);
    rj_int(j, "seed_groups", (long long)r->seed_groups);
    rj_int(j, "seeds_dropped", (long long)r->seeds_dropped);
    rj_int(j, "weak_seeds", (long long)r->weak_seeds);
    rj_int(j, "grown_missing", (long long)r->grown_missing);
    rj_int(j, "grown_edge", (long long)r->grown_edge);
    rj_int(j, "grown_front", (long long)r->grown_front);
    rj_int(j, "parallax_seeds", (long long)r->parallax_seeds);
    rj_int(j, "dilated", (long long)r->dilated);
    rj_int(j, "occluder_pixels", (long long)r->occluder_pixels);
    rj_number(j, "share", (double)r->occluder_pixels / ((double)r->width * r->height));
    rj_end_object(j);
    rj_begin_object(j, "views");
    rj_int(j, "count", r->views);
    rj_int(j, "foreground", (long long)r->view_foreground);
    rj_int(j, "background", (long long)r->view_background);
    rj_int(j, "unknown", (long long)r->view_unknown);
    rj_begin_object(j, "in_front");
    rj_int(j, "foreground", (long long)r->front_view_foreground);
    rj_int(j, "background", (long long)r->front_view_background);
    rj_end_object(j);
    rj_begin_object(j, "on_background");
    rj_int(j, "background", (long long)r->on_view_background);
    rj_int(j, "foreground", (long long)r->on_view_foreground);
    rj_end_object(j);
    rj_end_object(j);
}

static void find_json(relief_json *j, const void *ctx)
{
    const find_ctx *c = ctx;
    rj_begin_object(j, NULL);
    rj_string(j, "command", "occluders");
    rj_string_or_null(j, "input", c->p->run.input_name);
    rj_string_or_null(j, "output", c->p->run.output_name);
    find_body(j, c->p, c->r);
    rj_begin_object(j, "seconds");
    rj_number(j, "total", c->r->seconds_total);
    rj_end_object(j);
    rj_end_object(j);
}

/* ------------------------------------------------------------ finding */

static relief_status check_frame(const relief_depth_image *f, relief_error *err)
{
    if (!f || !f->z)
        return relief_fail(err, RELIEF_E_USAGE, f ? "frame z: NULL" : "frame: NULL");
    if (f->width < 1 || f->width > RELIEF_DEPTH_MAX_SIDE || f->height < 1 ||
        f->height > RELIEF_DEPTH_MAX_SIDE)
        return relief_fail(err, RELIEF_E_RANGE, "frame size %d x %d out of range: expected "
                           "1..%d pixels a side", f->width, f->height, RELIEF_DEPTH_MAX_SIDE);
    if (!f->rgb)
        return relief_fail(err, RELIEF_E_USAGE, "the frame has no colour (rgb): occluders are "
                           "grown by colour; give an organised PCD with rgb, or a colour image "
                           "with its depth");
    return RELIEF_OK;
}

/* A background mesh's indices and positions, before they are read. */
static relief_status check_mesh(const relief_occluder_params *p, relief_error *err)
{
    if (p->background != RELIEF_BACKGROUND_MESH)
        return RELIEF_OK;
    relief_status st = relief_mesh_validate(p->background_mesh, err);
    if (st != RELIEF_OK) {
        relief_fail_prefix(err, "background_mesh");
        return st;
    }
    if (relief_mesh_triangle_count(p->background_mesh) == 0)
        return relief_fail(err, RELIEF_E_USAGE, "background_mesh: no triangles");
    return RELIEF_OK;
}

static relief_status check_memory(const relief_depth_image *f, const relief_run_options *run,
                                  uint64_t extra, relief_error *err)
{
    uint64_t need = (uint64_t)f->width * f->height * (FIND_BYTES_PER_PIXEL + extra);
    return relief_memory_check("finding the occluders", need,
                               run->max_memory ? run->max_memory : relief_default_memory_limit(),
                               "", err);
}

/* The views' L* (4 bytes a view's pixel) per pixel of the frame, rounded
 * up: views may be of another size than the frame. */
static uint64_t view_bytes(const relief_depth_image *f, const relief_occluder_params *p)
{
    uint64_t all = 0, n = (uint64_t)f->width * f->height;
    for (int k = 0; k < p->n_views && p->views; ++k)
        all += 4u * (uint64_t)(p->views[k].width > 0 ? p->views[k].width : 0) *
               (uint64_t)(p->views[k].height > 0 ? p->views[k].height : 0);
    return n ? (all + n - 1) / n : 0;
}

/* Counts of the background's verdicts on the captured points. */
static void background_counts(const occ_scene *s, relief_occluder_report *r)
{
    size_t n = (size_t)s->width * s->height;
    for (size_t i = 0; i < n; ++i) {
        double c = s->clearance[i], m = occ_margin_at(s, i);
        r->no_background += !isfinite(s->surface[i]);
        r->on_background += isfinite(c) && fabs(c) <= m;
        r->behind += isfinite(c) && c < -m;
    }
}

/* Is a captured point left outside the mask? */
static int any_background_left(const occ_scene *s, const uint8_t *mask)
{
    for (size_t i = 0; i < (size_t)s->width * s->height; ++i)
        if (!mask[i] && isfinite(s->pts[3 * i + 2]))
            return 1;
    return 0;
}

/* The scene's fields of the report. */
static void scene_report(const occ_scene *s, relief_occluder_report *r)
{
    r->width = s->width, r->height = s->height;
    r->captured = s->captured, r->missing = (size_t)s->width * s->height - s->captured;
    r->planes = s->n_planes;
    memcpy(r->plane, s->plane, sizeof r->plane);
    memcpy(r->camera, s->cam, sizeof r->camera);
    r->noise = s->noise;
    r->has_placeholder = s->has_placeholder;
    memcpy(r->placeholder, s->placeholder, sizeof r->placeholder);
    r->placeholder_pixels = s->placeholder_pixels;
    r->margin = occ_margin(s, s->median_z);
    background_counts(s, r);
}

/* The scene and its mask (1 = occluder); the report's fields. */
static relief_status find(const relief_depth_image *f, const relief_occluder_params *p,
                          occ_scene *s, uint8_t *mask, relief_occluder_report *r,
                          relief_error *err)
{
    occ_counts c;
    relief_status st = occ_scene_points(f, p, s, err);
    if (st == RELIEF_OK)
        st = occ_background(s, p, err);
    if (st == RELIEF_OK)
        st = occ_mask(s, f->rgb, p, mask, &c, err);
    if (st != RELIEF_OK)
        return st;
    scene_report(s, r);
    r->seeds = c.seeds + c.weak_seeds, r->seed_groups = c.seed_groups;
    r->seeds_dropped = c.seeds_dropped, r->weak_seeds = c.weak_seeds;
    r->grown_missing = c.grown_missing, r->grown_edge = c.grown_edge;
    r->grown_front = c.grown_front;
    r->dilated = c.dilated, r->occluder_pixels = c.total;
    r->views = p->n_views, r->parallax_seeds = c.parallax_seeds;
    r->view_foreground = c.view_fg;
    r->view_background = c.view_bg, r->view_unknown = c.view_unknown;
    r->front_view_foreground = c.front_fg, r->front_view_background = c.front_bg;
    r->on_view_background = c.on_bg, r->on_view_foreground = c.on_fg;
    occ_plane_regions(s, mask, r->plane, r->planes);
    if (c.seeds == 0)
        return relief_fail(err, RELIEF_E_RANGE, "nothing in front of the background: no "
                           "captured point is more than the margin (%.4g at the median depth) "
                           "in front of it in a group of min_area (%d) pixels; no occluder to "
                           "mark", occ_margin(s, s->median_z),
                           p->min_area);
    if (!any_background_left(s, mask))
        return relief_fail(err, RELIEF_E_RANGE, "everything is foreground: the mask covers "
                           "every captured point; give a larger margin or the background");
    return RELIEF_OK;
}

relief_status relief_find_occluders(const relief_depth_image *f, const relief_occluder_params *p,
                                    relief_image *mask, relief_occluder_report *rep,
                                    relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    double t0 = relief_seconds();
    occ_scene s;
    relief_occluder_report r;
    uint8_t *m;
    size_t n;
    relief_status st = check_frame(f, err);
    if (st == RELIEF_OK && !mask)
        st = relief_fail(err, RELIEF_E_USAGE, "mask: NULL");
    if (st == RELIEF_OK)
        st = relief_occluder_params_validate(p, err);
    if (st == RELIEF_OK)
        st = check_mesh(p, err);
    if (st == RELIEF_OK)
        st = check_memory(f, &p->run, view_bytes(f, p), err);
    if (st != RELIEF_OK)
        return st;
    n = (size_t)f->width * f->height;
    memset(&r, 0, sizeof r);
    memset(&s, 0, sizeof s);
    if (!(m = malloc(n)))
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the mask");
    st = find(f, p, &s, m, &r, err);
    occ_scene_free(&s);
    r.seconds_total = relief_seconds() - t0;
    if (st == RELIEF_OK && rep) {
        find_ctx c = {p, &r};
        if (!(r.json = rj_render(find_json, &c, "\n")))
            st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the report");
    }
    if (st != RELIEF_OK) {
        free(m);
        return st;
    }
    for (size_t i = 0; i < n; ++i)
        m[i] = m[i] ? 255 : 0;
    *mask = (relief_image){f->width, f->height, 1, 8, 0, m};
    if (rep)
        *rep = r;
    return RELIEF_OK;
}

/* ------------------------------------------------------------ removal */

relief_remove_params relief_remove_params_default(void)
{
    relief_remove_params p;
    p.find = relief_occluder_params_default();
    p.colour = relief_image_fill_params_default();
    p.depth = relief_depth_fill_params_default();
    return p;
}

typedef struct remove_ctx {
    const relief_remove_params *p;
    const relief_remove_report *r;
    const relief_image_fill_report *colour;
    const relief_depth_fill_report *depth;
    size_t on_surface;
    double t0;          /* when the call started */
} remove_ctx;

static void remove_json(relief_json *j, const void *ctx)
{
    const remove_ctx *c = ctx;
    rj_begin_object(j, NULL);
    rj_string(j, "command", "remove-occluders");
    rj_string_or_null(j, "input", c->p->find.run.input_name);
    rj_string_or_null(j, "output", c->p->find.run.output_name);
    rj_begin_object(j, "occluders");
    find_body(j, &c->p->find, &c->r->find);
    rj_end_object(j);
    rj_begin_object(j, "colour");
    rj_int(j, "hole_pixels", (long long)c->colour->hole_pixels);
    rj_int(j, "by_interpolation", (long long)(c->colour->by_rows + c->colour->by_columns));
    rj_int(j, "by_copy", (long long)c->colour->by_copy);
    rj_int(j, "by_fallback", (long long)c->colour->by_fallback);
    rj_string(j, "device", c->colour->device);
    rj_end_object(j);
    rj_begin_object(j, "depth");
    rj_string(j, "variant", relief_depth_variant_name(c->p->depth.variant));
    rj_int(j, "replaced", (long long)c->r->replaced);
    rj_int(j, "synthesised", (long long)c->depth->filled);
    rj_int(j, "on_surface", (long long)c->on_surface);
    rj_int(j, "left_missing", (long long)c->r->left_missing);
    rj_number(j, "background_rms", c->r->background_rms);
    rj_string(j, "device", c->depth->device);
    rj_end_object(j);
    rj_begin_object(j, "seconds");
    rj_number(j, "find", c->r->find.seconds_total);
    rj_number(j, "colour", c->r->seconds_colour);
    rj_number(j, "depth", c->r->seconds_depth);
    rj_number(j, "total", c->r->seconds_total);
    rj_end_object(j);
    rj_end_object(j);
}

/* The work of one removal: copies of what is written back. */
typedef struct removal {
    size_t n;
    uint8_t *mask;      /* 1 = occluder */
    uint8_t *rgb;       /* the filled colour */
    float *residual;    /* depth about the background; filled */
    float *z, *xyz;     /* the results */
} removal;

static void removal_free(removal *w)
{
    free(w->mask);
    free(w->rgb);
    free(w->residual);
    free(w->z);
    free(w->xyz);
}

static relief_status removal_alloc(removal *w, const relief_depth_image *f, relief_error *err)
{
    w->n = (size_t)f->width * f->height;
    w->mask = malloc(w->n);
    w->rgb = malloc(w->n * 3);
    w->residual = malloc(w->n * sizeof *w->residual);
    w->z = malloc(w->n * sizeof *w->z);
    w->xyz = f->xyz ? malloc(w->n * 3 * sizeof *w->xyz) : NULL;
    if (!w->mask || !w->rgb || !w->residual || !w->z || (f->xyz && !w->xyz))
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the removal's copies");
    return RELIEF_OK;
}

/* The mask from the caller's image (any channel but alpha non-zero). */
static relief_status given_mask(const relief_image *m, const relief_depth_image *f, uint8_t *out,
                                relief_error *err)
{
    relief_status st = relief_depth_mask_check(m, f->width, f->height, err);
    if (st == RELIEF_OK)
        relief_depth_mask_bits(m, out);
    return st;
}

/* A given mask's report: the background found, the pixels to remove. */
static relief_status mask_counted(const occ_scene *s, const removal *w,
                                  relief_occluder_report *r, relief_error *err)
{
    scene_report(s, r);
    occ_plane_regions(s, w->mask, r->plane, r->planes);
    for (size_t i = 0; i < w->n; ++i)
        r->occluder_pixels += w->mask[i];
    if (r->occluder_pixels == 0)
        return relief_fail(err, RELIEF_E_RANGE, "the mask marks no pixel: nothing to remove");
    if (r->occluder_pixels == w->n)
        return relief_fail(err, RELIEF_E_RANGE, "the mask marks every pixel: nothing is left "
                           "to fill it from");
    return RELIEF_OK;
}

/* The colour of the occluders, filled by paper 004's chapter 3. The
 * placeholder pixels are holes too, so that their colour is never copied;
 * only the mask's pixels are written back. */
static relief_status fill_colour(const relief_depth_image *f, const occ_scene *s, removal *w,
                                 const relief_remove_params *p, relief_image_fill_report *rep,
                                 relief_error *err)
{
    relief_image img = {f->width, f->height, 3, 8, 0, w->rgb};
    uint8_t *hole = s->has_placeholder ? malloc(w->n) : w->mask;
    relief_image m = {f->width, f->height, 1, 8, 0, hole};
    relief_status st;
    if (!hole)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the colour's holes");
    for (size_t i = 0; hole != w->mask && i < w->n; ++i)
        hole[i] = w->mask[i] || occ_no_colour(s, i);
    memcpy(w->rgb, f->rgb, w->n * 3);
    st = relief_image_fill(&img, &m, &p->colour, rep, err);
    if (hole != w->mask)
        free(hole);
    return st;
}

/* The depth behind them: the residual about the background surface, known
 * on the background's captured points, repaired by paper 003 in the mask
 * (and elsewhere, but only the mask's pixels are kept). */
static relief_status fill_depth(const relief_depth_image *f, const occ_scene *s, removal *w,
                                const relief_remove_params *p, relief_depth_fill_report *rep,
                                relief_error *err)
{
    relief_depth_image res = {f->width, f->height, w->residual, NULL, NULL, RELIEF_DEPTH_PFM};
    relief_image m = {f->width, f->height, 1, 8, 0, w->mask};
    relief_depth_fill_params dp = p->depth;
    relief_status st;
    size_t known = 0;
    for (size_t i = 0; i < w->n; ++i) {
        double c = s->clearance[i];
        int bg = fabs(c) <= occ_margin_at(s, i) && isfinite(s->surface[i]);
        float r = (float)(f->z[i] - s->surface[i]);
        /* depth-fill takes 0 for missing: an exact 0 known is the least float */
        w->residual[i] = bg && !w->mask[i] ? (r == 0.0f ? FLT_MIN : r) : NAN;
        known += bg && !w->mask[i];
    }
    dp.truth = NULL;
    if (known == 0)
        return relief_fail(err, RELIEF_E_RANGE, "no captured point lies on the background "
                           "outside the mask: nothing to repair the depth from");
    st = relief_depth_fill(&res, &m, &dp, rep, err);
    if (st == RELIEF_E_RANGE) {
        /* Every masked pixel is outside the capture along its row and
         * column: they lie on the surface itself (counted as such). */
        for (size_t i = 0; i < w->n; ++i)
            if (w->mask[i])
                w->residual[i] = NAN;
        memset(rep, 0, sizeof *rep);
        relief_error_clear(err);
        st = RELIEF_OK;
    }
    return st;
}

/* Write the removal's z, xyz and colour for the mask's pixels. */
static void compose(const relief_depth_image *f, const occ_scene *s, removal *w,
                    relief_remove_report *r, size_t *on_surface)
{
    double ss = 0.0;
    memcpy(w->z, f->z, w->n * sizeof *w->z);
    if (w->xyz)
        memcpy(w->xyz, f->xyz, w->n * 3 * sizeof *w->xyz);
    *on_surface = 0;
    for (size_t i = 0; i < w->n; ++i) {
        double ray[3], d = w->residual[i];
        int u = (int)(i % (size_t)f->width), v = (int)(i / (size_t)f->width);
        if (!w->mask[i])
            continue;
        if (!isfinite(s->surface[i])) {
            w->z[i] = NAN;
            ++r->left_missing;
        } else {
            if (!isfinite(d))
                d = 0.0, ++*on_surface;
            w->z[i] = (float)(s->surface[i] + d);
            ss += d * d;
            ++r->replaced;
        }
        ray[0] = s->cam[0] * u + s->cam[1], ray[1] = s->cam[2] * v + s->cam[3], ray[2] = 1.0;
        for (int k = 0; k < 3 && w->xyz; ++k)
            w->xyz[3 * i + k] = (float)(ray[k] * w->z[i]);
    }
    r->background_rms = r->replaced ? sqrt(ss / r->replaced) : 0.0;
}

static relief_status remove_run(relief_depth_image *f, const relief_image *mask,
                                const relief_remove_params *p, removal *w, occ_scene *s,
                                relief_remove_report *r, remove_ctx *c, relief_error *err)
{
    relief_image_fill_report cr;
    relief_depth_fill_report dr;
    double t;
    relief_status st = removal_alloc(w, f, err);
    memset(&cr, 0, sizeof cr);
    memset(&dr, 0, sizeof dr);
    if (st == RELIEF_OK && mask) {
        st = given_mask(mask, f, w->mask, err);
        if (st == RELIEF_OK)
            st = occ_scene_points(f, &p->find, s, err);
        if (st == RELIEF_OK)
            st = occ_background(s, &p->find, err);
        if (st == RELIEF_OK)
            st = mask_counted(s, w, &r->find, err);
    } else if (st == RELIEF_OK) {
        t = relief_seconds();
        st = find(f, &p->find, s, w->mask, &r->find, err);
        r->find.seconds_total = relief_seconds() - t;
    }
    if (st == RELIEF_OK) {
        t = relief_seconds();
        st = fill_colour(f, s, w, p, &cr, err);
        r->seconds_colour = relief_seconds() - t;
    }
    if (st == RELIEF_OK) {
        t = relief_seconds();
        st = fill_depth(f, s, w, p, &dr, err);
        r->seconds_depth = relief_seconds() - t;
    }
    if (st == RELIEF_OK) {
        compose(f, s, w, r, &c->on_surface);
        c->colour = &cr, c->depth = &dr;
        r->seconds_total = relief_seconds() - c->t0;
        if (!(r->json = rj_render(remove_json, c, "\n")))
            st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the report");
    }
    relief_image_fill_report_free(&cr);
    relief_depth_fill_report_free(&dr);
    return st;
}

relief_status relief_remove_occluders(relief_depth_image *f, const relief_image *mask,
                                      const relief_remove_params *p, relief_remove_report *rep,
                                      relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    double t0 = relief_seconds();
    removal w;
    occ_scene s;
    relief_remove_report r;
    remove_ctx c;
    relief_status st = check_frame(f, err);
    if (st == RELIEF_OK && !p)
        st = relief_fail(err, RELIEF_E_USAGE, "params: NULL");
    if (st == RELIEF_OK)
        st = relief_occluder_params_validate(&p->find, err);
    if (st == RELIEF_OK)
        st = check_mesh(&p->find, err);
    if (st == RELIEF_OK)
        st = relief_image_fill_params_validate(&p->colour, err);
    if (st == RELIEF_OK)
        st = relief_depth_fill_params_validate(&p->depth, err);
    if (st == RELIEF_OK)
        st = check_memory(f, &p->find.run, 32u + view_bytes(f, &p->find), err);
    if (st != RELIEF_OK)
        return st;
    memset(&w, 0, sizeof w);
    memset(&s, 0, sizeof s);
    memset(&r, 0, sizeof r);
    c = (remove_ctx){p, &r, NULL, NULL, 0, t0};
    st = remove_run(f, mask, p, &w, &s, &r, &c, err);
    if (st == RELIEF_OK) {
        memcpy(f->z, w.z, w.n * sizeof *f->z);
        if (f->xyz)
            memcpy(f->xyz, w.xyz, w.n * 3 * sizeof *f->xyz);
        for (size_t i = 0; i < w.n; ++i)
            if (w.mask[i])
                memcpy(f->rgb + 3 * i, w.rgb + 3 * i, 3);
        r.mask = w.mask; /* the report's now */
        w.mask = NULL;
    }
    occ_scene_free(&s);
    removal_free(&w);
    if (st != RELIEF_OK || !rep)
        relief_remove_report_free(&r);
    else
        *rep = r;
    return st;
}
