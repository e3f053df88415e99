/* The image engine's public API (relief/image.h): relief_image, a view of
 * a caller's 8- or 16-bit samples with a row stride, which the readers and
 * writers (image_io.h) take and give as they are, over the float raster
 * that the hole filler works on (fill.h). A fill works on a copy of the
 * image: the caller's buffer and report are written only when the call
 * succeeds. */
#include "relief/relief.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/clock.h"
#include "base/error.h"
#include "base/file.h"
#include "base/json.h"
#include "base/memlimit.h"
#include "base/pool.h"
#include "base/progress.h"
#include "image/fill.h"
#include "image/image_io.h"
#include "image/patch.h"
#include "image/raster.h"
#include "image/vote_fill.h"

_Static_assert(RELIEF_IMAGE_MAX_SIDE == RELIEF_RASTER_MAX_SIDE,
               "the public and the internal image sides agree");

/* ---------------------------------------------------------------- views */

static size_t row_bytes(const relief_image *img)
{
    return (size_t)img->width * (size_t)img->channels * (size_t)(img->bit_depth / 8);
}

static size_t stride_of(const relief_image *img)
{
    return img->stride ? img->stride : row_bytes(img);
}

/* Sample i of row y. 16-bit samples go through memcpy: a caller's stride
 * need not keep its rows aligned. */
static unsigned get_sample(const relief_image *img, int y, size_t i)
{
    const uint8_t *row = (const uint8_t *)img->data + (size_t)y * stride_of(img);
    uint16_t v;
    if (img->bit_depth == 8)
        return row[i];
    memcpy(&v, row + 2 * i, sizeof v);
    return v;
}

static void put_sample(relief_image *img, int y, size_t i, unsigned v)
{
    uint8_t *row = (uint8_t *)img->data + (size_t)y * stride_of(img);
    uint16_t w = (uint16_t)v;
    if (img->bit_depth == 8)
        row[i] = (uint8_t)v;
    else
        memcpy(row + 2 * i, &w, sizeof w);
}

/* The sides and channels of an image, named by `what`. */
static relief_status check_shape(const char *what, int width, int height, int channels,
                                 relief_error *err)
{
    if (width < 1 || width > RELIEF_IMAGE_MAX_SIDE)
        return relief_fail(err, RELIEF_E_RANGE, "%s: width %d out of range: expected 1..%d "
                           "pixels", what, width, RELIEF_IMAGE_MAX_SIDE);
    if (height < 1 || height > RELIEF_IMAGE_MAX_SIDE)
        return relief_fail(err, RELIEF_E_RANGE, "%s: height %d out of range: expected 1..%d "
                           "pixels", what, height, RELIEF_IMAGE_MAX_SIDE);
    if (channels < 1 || channels > 4)
        return relief_fail(err, RELIEF_E_RANGE, "%s: channels %d out of range: expected 1 "
                           "(grey), 2 (grey + alpha), 3 (RGB) or 4 (RGBA)", what, channels);
    return RELIEF_OK;
}

relief_status relief_image_check(const relief_image *img, const char *what, relief_error *err)
{
    relief_status st;
    RELIEF_ENTRY_ERR(err);
    what = what ? what : "image";
    if (!img)
        return relief_fail(err, RELIEF_E_USAGE, "%s: NULL", what);
    if (!img->data)
        return relief_fail(err, RELIEF_E_USAGE, "%s: data is NULL", what);
    st = check_shape(what, img->width, img->height, img->channels, err);
    if (st != RELIEF_OK)
        return st;
    if (img->bit_depth != 8 && img->bit_depth != 16)
        return relief_fail(err, RELIEF_E_RANGE, "%s: bit_depth %d out of range: expected 8 "
                           "or 16", what, img->bit_depth);
    if (img->stride && img->stride < row_bytes(img))
        return relief_fail(err, RELIEF_E_RANGE, "%s: stride %zu out of range: smaller than a "
                           "row (width %d x channels %d x %d bytes = %zu bytes)", what,
                           img->stride, img->width, img->channels, img->bit_depth / 8,
                           row_bytes(img));
    if (img->stride > SIZE_MAX / (size_t)img->height)
        return relief_fail(err, RELIEF_E_RANGE, "%s: stride %zu out of range: %d rows of it "
                           "do not fit in memory", what, img->stride, img->height);
    return RELIEF_OK;
}

/* A float raster holding `img`'s samples (free with relief_raster_free). */
static relief_status raster_of(const relief_image *img, relief_raster *r, relief_error *err)
{
    size_t row = (size_t)img->width * img->channels;
    relief_status st = relief_raster_create(img->width, img->height, img->channels,
                                            img->bit_depth, r, err);
    if (st != RELIEF_OK)
        return st;
    for (int y = 0; y < img->height; ++y)
        for (size_t i = 0; i < row; ++i)
            r->v[(size_t)y * row + i] = (float)get_sample(img, y, i);
    return RELIEF_OK;
}

/* ------------------------------------------------------------------ files */

relief_status relief_image_decode(const void *data, size_t n, const char *name,
                                  uint64_t max_bytes, relief_image *out, relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    name = name ? name : "image";
    if ((!data && n) || !out)
        return relief_fail(err, RELIEF_E_USAGE, "relief_image_decode: %s is NULL",
                           out ? "data" : "out");
    return relief_image_file_decode(data, n, name, max_bytes, out, err);
}

relief_status relief_image_read(const char *path, uint64_t max_bytes, relief_image *out,
                                relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    uint8_t *data;
    size_t n;
    relief_status st;
    if (!path || !out)
        return relief_fail(err, RELIEF_E_USAGE, "relief_image_read: %s is NULL",
                           path ? "out" : "path");
    st = relief_read_file(path, &data, &n, err);
    if (st != RELIEF_OK)
        return st;
    st = relief_image_decode(data, n, path, max_bytes, out, err);
    free(data);
    return st;
}

relief_status relief_image_write(const relief_image *img, const char *path, relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    relief_status st = relief_image_check(img, "image", err);
    if (st == RELIEF_OK && !path)
        st = relief_fail(err, RELIEF_E_USAGE, "relief_image_write: path is NULL");
    return st == RELIEF_OK ? relief_image_file_write(path, img, err) : st;
}

void relief_image_free(relief_image *img)
{
    if (!img)
        return;
    free(img->data);
    memset(img, 0, sizeof *img);
}

/* ------------------------------------------------------------ parameters */

relief_image_fill_params relief_image_fill_params_default(void)
{
    relief_fill_params f = relief_fill_params_default();
    relief_vote_params v = relief_vote_params_default();
    relief_image_fill_params p;
    memset(&p, 0, sizeof p);
    p.method = RELIEF_IMAGE_FILL_WEXLER;
    p.patch = v.patch;
    p.em_steps = v.em_steps;
    p.pm_steps = v.pm_steps;
    p.window = f.window;
    p.min_window = f.min_window;
    p.tau = f.tau;
    p.max_hole_fraction = f.max_hole_fraction;
    p.search_radius = f.search_radius;
    p.exhaustive = f.exhaustive;
    p.interp = f.interp;
    p.interp_diff = f.interp_diff;
    p.interp_sd = f.interp_sd;
    p.seed = f.seed;
    p.run = relief_run_options_default();
    return p;
}

/* The filler's parameters for these; its own (the pyramid's shape, the
 * 1-D pass's span) at their defaults. */
static relief_fill_params engine_params(const relief_image_fill_params *p,
                                        relief_progress *progress)
{
    relief_fill_params f = relief_fill_params_default();
    f.window = p->window;
    f.min_window = p->min_window;
    f.tau = p->tau;
    f.max_hole_fraction = p->max_hole_fraction;
    f.search_radius = p->search_radius;
    f.exhaustive = p->exhaustive;
    f.interp = p->interp;
    f.interp_diff = p->interp_diff;
    f.interp_sd = p->interp_sd;
    f.seed = p->seed;
    f.progress = progress;
    return f;
}

/* The patch voting's parameters for these. */
static relief_vote_params vote_params(const relief_image_fill_params *p,
                                      relief_progress *progress, int threads)
{
    relief_vote_params v = relief_vote_params_default();
    v.patch = p->patch;
    v.em_steps = p->em_steps;
    v.pm_steps = p->pm_steps;
    v.seed = p->seed;
    v.threads = threads;
    v.progress = progress;
    return v;
}

relief_status relief_image_fill_params_validate(const relief_image_fill_params *p,
                                                relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    relief_fill_params f;
    relief_status st;
    if (!p)
        return relief_fail(err, RELIEF_E_USAGE, "image fill parameters: NULL");
    if (p->exhaustive != 0 && p->exhaustive != 1)
        return relief_fail_param(err, RELIEF_E_RANGE, "exhaustive", "exhaustive %d out of "
                                 "range: expected 0 or 1", p->exhaustive);
    if (p->interp != 0 && p->interp != 1)
        return relief_fail_param(err, RELIEF_E_RANGE, "interp", "interp %d out of range: "
                                 "expected 0 or 1", p->interp);
    if (p->method != RELIEF_IMAGE_FILL_WEXLER && p->method != RELIEF_IMAGE_FILL_JAIN)
        return relief_fail_param(err, RELIEF_E_RANGE, "method", "method %d out of range: "
                                 "expected wexler (%d) or jain (%d)", (int)p->method,
                                 RELIEF_IMAGE_FILL_WEXLER, RELIEF_IMAGE_FILL_JAIN);
    {
        relief_vote_params v = vote_params(p, NULL, 1);
        st = relief_vote_params_check(&v, err);
        if (st != RELIEF_OK)
            return st;
    }
    f = engine_params(p, NULL);
    st = relief_fill_params_check(&f, err);
    if (st == RELIEF_OK)
        st = relief_run_options_validate(&p->run, err);
    return st;
}

void relief_image_fill_report_free(relief_image_fill_report *rep)
{
    if (!rep)
        return;
    free(rep->json);
    memset(rep, 0, sizeof *rep);
}

/* ------------------------------------------------------------------ fill */

/* What one relief_image_fill call holds until it succeeds or fails. */
typedef struct fill_call {
    relief_image *image;
    const relief_image *mask;
    const relief_image_fill_params *p;
    relief_fill_params fp;
    relief_progress progress;
    uint8_t *hole;                /* width x height, 1: to fill */
    size_t holes;
    relief_raster work;           /* the copy being filled */
    relief_patch_scorer *scorer;
    char note[1024];
    relief_reason note_reason; /* RELIEF_REASON_DEVICE_FELL_BACK: a warning */
    relief_fill_report fr;
    relief_vote_report vr;        /* method wexler */
    double t0;
} fill_call;

relief_status relief_image_fill_check_memory(int width, int height, int channels,
                                             const relief_image_fill_params *p,
                                             relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    relief_image_fill_params d = relief_image_fill_params_default();
    const relief_image_fill_params *q = p ? p : &d;
    uint64_t limit = q->run.max_memory ? q->run.max_memory : relief_default_memory_limit();
    uint64_t need;
    char what[128];
    relief_status st = check_shape("image", width, height, channels, err);
    if (st != RELIEF_OK)
        return st;
    need = q->method == RELIEF_IMAGE_FILL_JAIN
               ? relief_fill_estimate(width, height, channels)
               : relief_raster_bytes(width, height, channels) +
                     relief_vote_fill_estimate(width, height, channels) +
                     (uint64_t)width * (uint64_t)height; /* the hole's copy */
    need += (uint64_t)width * (uint64_t)height;
    snprintf(what, sizeof what, "filling an image of %d x %d pixels and %d channel%s", width,
             height, channels, channels == 1 ? "" : "s");
    return relief_memory_check(what, need, limit, "", err);
}

/* The memory a fill plans for, against run.max_memory (0: the default). */
static relief_status check_memory(const fill_call *c, relief_error *err)
{
    const relief_image *img = c->image;
    return relief_image_fill_check_memory(img->width, img->height, img->channels, c->p, err);
}

/* The arguments, each named: the image, the parameters, the memory, the
 * mask (or the image's alpha), and the windows against the image. */
static relief_status check_call(fill_call *c, relief_error *err)
{
    const relief_image *img = c->image, *mask = c->mask;
    relief_status st = relief_image_check(img, "image", err);
    if (st == RELIEF_OK)
        st = relief_image_fill_params_validate(c->p, err);
    if (st == RELIEF_OK)
        st = check_memory(c, err);
    if (st == RELIEF_OK && mask)
        st = relief_image_check(mask, "mask", err);
    if (st == RELIEF_OK && mask && (mask->width != img->width || mask->height != img->height))
        st = relief_fail(err, RELIEF_E_USAGE, "the mask is %d x %d pixels, the image %d x %d: "
                         "they must be the same size", mask->width, mask->height, img->width,
                         img->height);
    if (st == RELIEF_OK && !mask && img->channels != 2 && img->channels != 4)
        st = relief_fail(err, RELIEF_E_USAGE, "the image has no alpha channel (%d channel%s), "
                         "so no hole: give the hole as a mask", img->channels,
                         img->channels == 1 ? "" : "s");
    if (st == RELIEF_OK)
        st = relief_fill_params_validate(&c->fp, img->width, img->height, err);
    return st;
}

/* The pixels to fill: the mask's non-zero ones (any channel but alpha),
 * or the image's transparent ones. */
static relief_status make_hole(fill_call *c, relief_error *err)
{
    const relief_image *src = c->mask ? c->mask : c->image;
    int C = src->channels, colours = C == 2 || C == 4 ? C - 1 : C;
    c->hole = malloc((size_t)src->width * (size_t)src->height);
    if (!c->hole)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the hole mask");
    c->holes = 0;
    for (int y = 0; y < src->height; ++y)
        for (int x = 0; x < src->width; ++x) {
            size_t i = (size_t)x * C;
            int h = 0;
            if (c->mask)
                for (int k = 0; k < colours; ++k)
                    h |= get_sample(src, y, i + k) != 0;
            else
                h = get_sample(src, y, i + C - 1) == 0;
            c->hole[(size_t)y * src->width + x] = (uint8_t)h;
            c->holes += (size_t)h;
        }
    return RELIEF_OK;
}

/* The window scorer run.backend names. */
static relief_status start_scorer(fill_call *c, relief_error *err)
{
    return relief_patch_scorer_create(c->p->run.backend, c->p->run.device, c->p->run.threads,
                                      &c->scorer, c->note, sizeof c->note, &c->note_reason,
                                      err);
}

/* Method wexler: the 1-D pass (when interp), then the patch voting over
 * what it left: on the scorer's device when it is OpenCL's (vote_cl.h),
 * else on one thread (scalar) or the host's. */
static relief_status run_vote(fill_call *c, relief_error *err)
{
    const relief_patch_scorer *s = c->scorer;
    const int threads = s->backend == RELIEF_BACKEND_SCALAR
                            ? 1
                            : relief_pool_threads_for(c->p->run.threads);
    const size_t n = (size_t)c->work.width * (size_t)c->work.height;
    uint8_t *hole = malloc(n);
    relief_vote_params v;
    relief_vote_cl *dev = NULL;
    relief_status st = RELIEF_OK;
    size_t left;
    double t0 = relief_seconds();
    if (!hole)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the hole mask");
    memcpy(hole, c->hole, n);
    memset(&c->fr, 0, sizeof c->fr);
    relief_fill_thresholds(&c->fp, c->image->bit_depth, &c->fr.tau, &c->fr.interp_diff,
                           &c->fr.interp_sd);
    c->fr.hole_pixels = c->holes;
    c->fr.start_level = -1;
    if (c->p->interp)
        relief_fill_interp(&c->work, hole, &c->fp, &c->fr.by_rows, &c->fr.by_columns,
                           c->fr.interp_roughness);
    c->fr.seconds_interp = relief_seconds() - t0;
    left = c->holes - c->fr.by_rows - c->fr.by_columns;
    v = vote_params(c->p, &c->progress, threads);
    if (left && s->backend == RELIEF_BACKEND_OPENCL)
        st = relief_vote_cl_create(c->p->run.device, &dev, err);
    if (st == RELIEF_OK && left)
        st = relief_vote_fill(&c->work, hole, &v, dev, &c->vr, err);
    relief_vote_cl_destroy(dev);
    c->fr.by_copy = left;
    c->fr.levels = c->vr.levels;
    c->fr.candidates = c->vr.distances;
    c->fr.seconds_copy = c->vr.seconds;
    c->fr.seconds_score = c->vr.seconds;
    free(hole);
    return st;
}

/* Fill the copy. Nothing to fill: no copy, the thresholds reported. */
static relief_status run_fill(fill_call *c, relief_error *err)
{
    relief_status st;
    if (c->holes == 0) {
        memset(&c->fr, 0, sizeof c->fr);
        c->fr.start_level = -1;
        relief_fill_thresholds(&c->fp, c->image->bit_depth, &c->fr.tau, &c->fr.interp_diff,
                               &c->fr.interp_sd);
        return RELIEF_OK;
    }
    if (c->holes == (size_t)c->image->width * (size_t)c->image->height)
        return relief_fail(err, RELIEF_E_RANGE, "every pixel of the image is in the hole: "
                           "there is nothing to fill it from");
    st = raster_of(c->image, &c->work, err);
    if (st == RELIEF_OK && c->p->method == RELIEF_IMAGE_FILL_JAIN)
        st = relief_fill(&c->work, c->hole, &c->fp, c->scorer, &c->fr, err);
    else if (st == RELIEF_OK)
        st = run_vote(c, err);
    return st;
}

/* The filled pixels, every channel, into the caller's buffer; the others
 * and the bytes between rows are not written. */
static void write_back(const fill_call *c)
{
    relief_image *img = c->image;
    const relief_raster *r = &c->work;
    float max = relief_raster_max_value(r);
    int C = img->channels;
    for (int y = 0; y < img->height; ++y)
        for (int x = 0; x < img->width; ++x) {
            size_t q = (size_t)y * img->width + x;
            if (!c->hole[q])
                continue;
            for (int k = 0; k < C; ++k)
                put_sample(img, y, (size_t)x * C + k,
                           relief_raster_quantise(r->v[q * C + k], max));
        }
}

/* The report's JSON, as `relief image-fill --report` writes it less the
 * mask's name (the command splices it in). */
typedef struct json_ctx {
    const fill_call *c;
    const relief_image_fill_report *r;
} json_ctx;

static void write_json(relief_json *j, const void *ctx)
{
    const fill_call *c = ((const json_ctx *)ctx)->c;
    const relief_image_fill_report *r = ((const json_ctx *)ctx)->r;
    const relief_image_fill_params *p = c->p;
    rj_begin_object(j, NULL);
    rj_string(j, "command", "image-fill");
    rj_string_or_null(j, "input", p->run.input_name);
    rj_string_or_null(j, "output", p->run.output_name);
    rj_begin_object(j, "image");
    rj_int(j, "width", c->image->width);
    rj_int(j, "height", c->image->height);
    rj_int(j, "channels", c->image->channels);
    rj_int(j, "bit_depth", c->image->bit_depth);
    rj_end_object(j);
    rj_begin_object(j, "parameters");
    rj_string(j, "method", relief_image_fill_method_name(p->method));
    rj_int(j, "patch", p->patch);
    rj_int(j, "em_steps", p->em_steps);
    rj_int(j, "pm_steps", p->pm_steps);
    rj_int(j, "window", p->window);
    rj_int(j, "min_window", p->min_window);
    rj_number(j, "tau", r->tau);
    rj_number(j, "max_hole_fraction", p->max_hole_fraction);
    rj_int(j, "search_radius", p->search_radius);
    rj_bool(j, "exhaustive", p->exhaustive);
    rj_bool(j, "interp", p->interp);
    rj_number(j, "interp_diff", r->interp_diff);
    rj_number(j, "interp_sd", r->interp_sd);
    /* The 1-D pass's limit on an end's roughness, from the image's own
     * (per colour channel; 0 where the pass did not run). */
    rj_begin_array(j, "interp_roughness");
    for (int k = 0; k < (c->image->channels == 2 || c->image->channels == 4
                             ? c->image->channels - 1 : c->image->channels); ++k)
        rj_number(j, NULL, c->fr.interp_roughness[k]);
    rj_end_array(j);
    rj_int(j, "seed", p->seed);
    rj_end_object(j);
    rj_begin_object(j, "pixels");
    rj_int(j, "hole", (long long)r->hole_pixels);
    rj_int(j, "by_rows", (long long)r->by_rows);
    rj_int(j, "by_columns", (long long)r->by_columns);
    rj_int(j, "by_copy", (long long)r->by_copy);
    rj_int(j, "by_fallback", (long long)r->by_fallback);
    rj_end_object(j);
    rj_begin_object(j, "search");
    rj_int(j, "queries", (long long)r->queries);
    rj_int(j, "windows_tried", (long long)r->windows_tried);
    rj_int(j, "windows_accepted", (long long)r->windows_accepted);
    rj_int(j, "candidates_scored", (long long)r->candidates);
    rj_int(j, "pyramid_levels", r->pyramid_levels);
    rj_int(j, "start_level", r->start_level);
    rj_int(j, "top_m", r->top_m);
    rj_int(j, "em_steps", (long long)r->em_steps);
    rj_int(j, "targets", (long long)r->targets);
    rj_end_object(j);
    rj_begin_object(j, "seconds");
    rj_number(j, "interp", r->seconds_interp);
    rj_number(j, "copy_paste", r->seconds_copy);
    rj_number(j, "scoring", r->seconds_score);
    rj_number(j, "total", r->seconds_total);
    rj_end_object(j);
    rj_string(j, "backend", relief_backend_name(r->backend));
    rj_string(j, "device", r->device);
    rj_string(j, "backend_note", r->backend_note);
    rj_end_object(j);
}

/* The public report of the call, its JSON included. */
static relief_status make_report(const fill_call *c, relief_image_fill_report *r,
                                 relief_error *err)
{
    const relief_fill_report *fr = &c->fr;
    memset(r, 0, sizeof *r);
    r->hole_pixels = c->holes;
    r->by_rows = fr->by_rows;
    r->by_columns = fr->by_columns;
    r->by_copy = fr->by_copy;
    r->by_fallback = fr->by_fallback;
    r->queries = fr->queries;
    r->windows_tried = fr->searches;
    r->windows_accepted = fr->accepted;
    r->candidates = fr->candidates;
    r->pyramid_levels = fr->levels;
    r->em_steps = c->vr.em_steps;
    r->targets = c->vr.targets;
    r->start_level = fr->start_level;
    r->top_m = fr->top_m;
    r->tau = fr->tau;
    r->interp_diff = fr->interp_diff;
    r->interp_sd = fr->interp_sd;
    r->backend = c->scorer->backend;
    snprintf(r->device, sizeof r->device, "%s", c->scorer->device);
    snprintf(r->backend_note, sizeof r->backend_note, "%s", c->note);
    r->backend_warning = c->note_reason == RELIEF_REASON_DEVICE_FELL_BACK;
    r->seconds_interp = fr->seconds_interp;
    r->seconds_copy = fr->seconds_copy;
    r->seconds_score = fr->seconds_score;
    r->seconds_total = relief_seconds() - c->t0;
    {
        const json_ctx x = {c, r};
        r->json = rj_render(write_json, &x, "\n");
    }
    if (!r->json)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot write the report's JSON in memory");
    return RELIEF_OK;
}

relief_status relief_image_fill(relief_image *image, const relief_image *mask,
                                const relief_image_fill_params *p,
                                relief_image_fill_report *rep, relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    fill_call c;
    relief_image_fill_report out;
    relief_status st;

    memset(&c, 0, sizeof c);
    memset(&out, 0, sizeof out);
    c.t0 = relief_seconds();
    c.image = image;
    c.mask = mask;
    c.p = p;
    if (p) {
        relief_progress_init(&c.progress, p->run.progress, p->run.progress_ctx);
        c.fp = engine_params(p, &c.progress);
    }
    st = check_call(&c, err);
    if (st == RELIEF_OK)
        st = make_hole(&c, err);
    if (st == RELIEF_OK)
        st = start_scorer(&c, err);
    if (st == RELIEF_OK)
        st = run_fill(&c, err);
    if (st == RELIEF_OK && rep)
        st = make_report(&c, &out, err);
    if (st == RELIEF_OK) {
        if (c.holes)
            write_back(&c);
        if (rep)
            *rep = out;
    }
    relief_patch_scorer_destroy(c.scorer);
    relief_raster_free(&c.work);
    free(c.hole);
    return st;
}
